"""The reading path: how much code a student reads to follow one run of the default scene.

Counts every project function (a function in one of the repository's top-level .py files) that runs
while `simulator.simulate` steps the default scene, 300 steps with lagged friction, then 100 steps
from the start again with `friction_updates=3` (Algorithm 5, through the impact), and adds up their lines, leaving out blank lines, comment-only
lines and docstrings. A function counts once however often it runs; a generator expression, a lambda
or a nested function belongs to the function whose text holds it (its lines are counted once).

`sys.setprofile` collects the code objects that run; `ast` gives each function's extent (from its
first decorator to its last line) and its docstrings; `tokenize` tells code lines from blank and
comment-only ones.

    python -m benchmarks.reading_path                  # the working tree
    python -m benchmarks.reading_path --against c6bcae2  # and an earlier commit, side by side
    python -m benchmarks.reading_path --functions        # also every function that ran, with its lines

The earlier commit is exported with `git archive` into a temporary folder and run in a subprocess
with that folder first on sys.path; the folder is removed afterwards.
"""
import argparse
import ast
import io
import json
import os
import subprocess
import sys
import tokenize

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

LAGGED_STEPS, IMPLICIT_STEPS, FRICTION_UPDATES = 300, 100, 3


# ------------------------------------------------------------------------------------------------
# Counting lines
# ------------------------------------------------------------------------------------------------

def code_lines(source):
    """The line numbers of `source` that hold code: not blank, not only a comment, not a docstring."""
    lines = set()
    skip = {tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT,
            tokenize.ENDMARKER, tokenize.ENCODING}
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type not in skip:
            lines.update(range(token.start[0], token.end[0] + 1))
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            first = node.body[0] if node.body else None
            if (isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant)
                    and isinstance(first.value.value, str)):
                lines.difference_update(range(first.lineno, first.end_lineno + 1))
    return lines


def function_extents(source):
    """(first line, last line, name) of every function defined in `source`, decorators included, and of
    every lambda outside one (a table's, as time_integrator.TERMS: read as a function of its own)."""
    tree, extents = ast.parse(source), []
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            first = min([node.lineno] + [d.lineno for d in node.decorator_list])
            extents.append((first, node.end_lineno, node.name))
    inside = {id(n) for e in ast.walk(tree) if isinstance(e, (ast.FunctionDef, ast.AsyncFunctionDef))
              for n in ast.walk(e)}
    extents += [(node.lineno, node.end_lineno, "<lambda>") for node in ast.walk(tree)
                if isinstance(node, ast.Lambda) and id(node) not in inside]
    return extents


def enclosing_function(extents, line):
    """The innermost function whose extent holds `line`, or None (module or class level code)."""
    holding = [ext for ext in extents if ext[0] <= line <= ext[1]]
    return max(holding, key=lambda ext: ext[0]) if holding else None


def functions_that_ran(code_objects, tree):
    """{file name: {(first line, function name): its code lines}} for the code objects that ran, over the
    top-level .py files of `tree`: a code object maps to the innermost function holding its first line
    (a generator expression to its function)."""
    per_file = {}
    for path in sorted({c.co_filename for c in code_objects}):
        with open(path) as f:
            source = f.read()
        extents, counted = function_extents(source), code_lines(source)
        functions = {enclosing_function(extents, c.co_firstlineno) for c in code_objects if c.co_filename == path}
        functions.discard(None)
        per_file[os.path.relpath(path, tree)] = {
            (first, name): {line for line in range(first, last + 1) if line in counted}
            for first, last, name in functions}
    return per_file


def reading_path(code_objects, tree):
    """{file name: (functions, lines)}: the functions of functions_that_ran, and their code lines, a
    line that two of them share (a nested function inside another) counted once."""
    return {name: (len(functions), len(set().union(*functions.values())))
            for name, functions in functions_that_ran(code_objects, tree).items()}


def is_project_file(path, tree):
    """True for a top-level .py file of `tree` (not tests/, benchmarks/ or a virtual environment)."""
    path = os.path.abspath(path)
    return os.path.dirname(path) == tree and path.endswith(".py")


# ------------------------------------------------------------------------------------------------
# The run (in the process of one tree)
# ------------------------------------------------------------------------------------------------

def collect(tree):
    """The project code objects that run while simulate steps the default scene: 300 lagged steps, then
    100 steps from the start with friction_updates=3. (Run from the start, Algorithm 5 meets the fall
    and the impact; this is the count issue 14 gives for c6bcae2, 444 lines in 67 functions.)"""
    import simulator
    lagged = simulator.build_scene()
    implicit = simulator.build_scene(friction_updates=FRICTION_UPDATES)
    seen = set()

    def profile(frame, event, arg):
        if event == "call":
            seen.add(frame.f_code)

    sys.setprofile(profile)
    try:
        for scene, steps in ((lagged, LAGGED_STEPS), (implicit, IMPLICIT_STEPS)):
            for _ in simulator.simulate(scene, steps):
                pass
    finally:
        sys.setprofile(None)
    return {c for c in seen if is_project_file(c.co_filename, tree)}


def worker(tree):
    """Count the reading path of `tree` in this process, with `tree` first on sys.path: the per-file
    table and, per function, its name, first line and code lines."""
    tree = os.path.abspath(tree)
    sys.path.insert(0, tree)
    code_objects = collect(tree)
    functions = [[path, name, first, len(lines)] for path, found in functions_that_ran(code_objects, tree).items()
                 for (first, name), lines in sorted(found.items())]
    return {"files": reading_path(code_objects, tree), "functions": functions}


def run_tree(tree, functions=False):
    """The reading path of `tree`, counted in a fresh Python process (so its modules are the ones
    imported): {file: (functions, lines)}, and with `functions` also [(file, name, first line, lines)]."""
    done = subprocess.run([sys.executable, "-m", "benchmarks.reading_path", "--worker", tree], cwd=ROOT,
                          capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"counting the reading path of {tree} failed:\n{done.stderr}")
    result = json.loads(done.stdout.strip().splitlines()[-1])
    per_file = {name: tuple(pair) for name, pair in result["files"].items()}
    return (per_file, [tuple(f) for f in result["functions"]]) if functions else per_file


def export_tree(rev, folder):
    """Write the files of commit `rev` into `folder` (git archive; the checkout is not touched)."""
    archive = subprocess.run(["git", "-C", ROOT, "archive", "--format=tar", rev], capture_output=True)
    if archive.returncode != 0:
        raise SystemExit(f"reading_path: error: git archive {rev}: {archive.stderr.decode().strip()}")
    subprocess.run(["tar", "-x", "-C", folder], input=archive.stdout, check=True)


def format_table(title, per_file):
    """One line per file (functions, lines), then the total."""
    lines = [title, f"  {'file':<22} {'functions':>9} {'lines':>6}"]
    for name, (functions, count) in sorted(per_file.items(), key=lambda item: -item[1][1]):
        lines.append(f"  {name:<22} {functions:>9} {count:>6}")
    total_functions = sum(f for f, _ in per_file.values())
    total_lines = sum(n for _, n in per_file.values())
    lines.append(f"  {'total':<22} {total_functions:>9} {total_lines:>6}")
    return "\n".join(lines)


def format_functions(functions):
    """One line per function that ran: file:first line, name, code lines (a nested function's lines
    also count in the function holding it)."""
    return "\n".join(f"  {f'{path}:{first}':<26} {name:<28} {lines:>4}" for path, name, first, lines in functions)


def totals(per_file):
    """(functions, lines) summed over the files."""
    return sum(f for f, _ in per_file.values()), sum(n for _, n in per_file.values())


def count(tree_or_rev, functions):
    """run_tree of a folder, or of commit `tree_or_rev` exported into a temporary folder."""
    import tempfile
    if os.path.isdir(tree_or_rev):
        return run_tree(os.path.abspath(tree_or_rev), functions)
    with tempfile.TemporaryDirectory(prefix="reading_path-") as folder:
        export_tree(tree_or_rev, folder)
        return run_tree(folder, functions)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m benchmarks.reading_path", description=__doc__.split("\n\n")[0])
    ap.add_argument("--against", metavar="REV", help="also count this commit (or an existing folder)")
    ap.add_argument("--functions", action="store_true", help="also list every function that ran with its lines")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        print(json.dumps(worker(args.worker)))
        return 0
    print(f"functions that run while simulator.simulate steps the default scene ({LAGGED_STEPS} lagged steps, "
          f"then {IMPLICIT_STEPS} from the start with friction_updates={FRICTION_UPDATES}); lines without blank "
          "lines, comment-only lines and docstrings")
    trees = [("working tree", ROOT)] + ([(args.against, args.against)] if args.against else [])
    results = []
    for title, tree in trees:
        per_file, functions = count(tree, functions=True)
        print(format_table(title, per_file))
        if args.functions:
            print(format_functions(functions))
        results.append((title, totals(per_file)))
    print("; ".join(f"{title} {lines} lines in {functions} functions" for title, (functions, lines) in results))
    return 0


if __name__ == "__main__":
    sys.exit(main())
