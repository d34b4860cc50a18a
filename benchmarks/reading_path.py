"""The reading path: the project functions (in the top-level .py files) that run while
simulator.simulate steps the default scene, 300 lagged steps, then 100 from the start with
friction_updates=3, and their lines without blanks, comments and docstrings (benchmarks/README.md).

    python -m benchmarks.reading_path [--against REV] [--functions]
"""
import argparse
import ast
import io
import json
import os
import sys
import tempfile
import tokenize

import benchmarks

LAGGED_STEPS, IMPLICIT_STEPS, FRICTION_UPDATES = 300, 100, 3
FUNCTIONS = (ast.FunctionDef, ast.AsyncFunctionDef)
DOCUMENTED = (ast.Module, ast.ClassDef) + FUNCTIONS


def code_lines(source):
    """The line numbers of `source` that hold code: not blank, not only a comment, no docstring."""
    lines, skip = set(), {tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT,
                          tokenize.DEDENT, tokenize.ENDMARKER, tokenize.ENCODING}
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type not in skip:
            lines.update(range(token.start[0], token.end[0] + 1))
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, DOCUMENTED) and ast.get_docstring(node) is not None:
            docstring = node.body[0]
            lines.difference_update(range(docstring.lineno, docstring.end_lineno + 1))
    return lines


def function_extents(source):
    """(first line, last line, name) of every function in `source`, decorators included, and of
    every lambda outside one (a table's, as time_integrator.TERMS: a function of its own)."""
    tree, extents = ast.parse(source), []
    for node in ast.walk(tree):
        if isinstance(node, FUNCTIONS):
            first = min([node.lineno] + [d.lineno for d in node.decorator_list])
            extents.append((first, node.end_lineno, node.name))
    inside = {id(n) for f in ast.walk(tree) if isinstance(f, FUNCTIONS) for n in ast.walk(f)}
    return extents + [(node.lineno, node.end_lineno, "<lambda>") for node in ast.walk(tree)
                      if isinstance(node, ast.Lambda) and id(node) not in inside]


def enclosing_function(extents, line):
    """The innermost function whose extent holds `line`, or None (module or class level)."""
    holding = [ext for ext in extents if ext[0] <= line <= ext[1]]
    return max(holding, key=lambda ext: ext[0]) if holding else None


def functions_that_ran(code_objects, tree):
    """{file: {(first line, name): its code lines}} of the functions that hold the code objects
    that ran (each by its first line), over the files of `tree`."""
    per_file = {}
    for path in sorted({c.co_filename for c in code_objects}):
        with open(path) as f:
            source = f.read()
        extents, counted = function_extents(source), code_lines(source)
        functions = {enclosing_function(extents, c.co_firstlineno)
                     for c in code_objects if c.co_filename == path} - {None}
        per_file[os.path.relpath(path, tree)] = {
            (first, name): counted & set(range(first, last + 1))
            for first, last, name in functions}
    return per_file


def reading_path(found):
    """{file: (functions, lines)} of what functions_that_ran found; a line two functions share
    (a nested one) counted once."""
    return {name: (len(functions), len(set().union(*functions.values())))
            for name, functions in found.items()}


def is_project_file(path, tree):
    """True for a top-level .py file of `tree` (not tests/, benchmarks/ or a venv)."""
    path = os.path.abspath(path)
    return os.path.dirname(path) == tree and path.endswith(".py")


def collect(tree):
    """The project code objects that run while simulate steps the default scene, lagged, then
    with Algorithm 5 from the start (the count issue 14 gives for c6bcae2: 444 lines)."""
    import simulator
    runs = ((simulator.build_scene(), LAGGED_STEPS),
            (simulator.build_scene(friction_updates=FRICTION_UPDATES), IMPLICIT_STEPS))
    seen = set()

    def profile(frame, event, arg):
        if event == "call":
            seen.add(frame.f_code)
    sys.setprofile(profile)
    try:
        for scene, steps in runs:
            for _ in simulator.simulate(scene, steps):
                pass
    finally:
        sys.setprofile(None)
    return {c for c in seen if is_project_file(c.co_filename, tree)}


def worker(tree):
    """The reading path of `tree`, counted in this process with `tree` first on sys.path."""
    tree = os.path.abspath(tree)
    sys.path.insert(0, tree)
    found = functions_that_ran(collect(tree), tree)
    functions = [[path, name, first, len(lines)] for path, in_file in found.items()
                 for (first, name), lines in sorted(in_file.items())]
    return {"files": reading_path(found), "functions": functions}


def count(rev):
    """The reading path of a folder or of commit `rev`, in a fresh Python process: ({file:
    (functions, lines)}, [(file, name, first line, lines)])."""
    with tempfile.TemporaryDirectory(prefix="reading_path-") as folder:
        tree = benchmarks.export_tree(rev, folder)
        result = benchmarks.in_fresh_process("benchmarks.reading_path", tree)
    return ({name: tuple(pair) for name, pair in result["files"].items()},
            [tuple(f) for f in result["functions"]])


def totals(per_file):
    """(functions, lines) summed over the files."""
    return sum(f for f, _ in per_file.values()), sum(n for _, n in per_file.values())


def format_table(title, per_file):
    """One line per file (functions, lines), most lines first, then the total."""
    rows = sorted(per_file.items(), key=lambda item: -item[1][1]) + [("total", totals(per_file))]
    return "\n".join([title, f"  {'file':<22} {'functions':>9} {'lines':>6}"] + [
        f"  {name:<22} {functions:>9} {lines:>6}" for name, (functions, lines) in rows])


def format_functions(functions):
    """One line per function that ran: file:first line, name, code lines."""
    return "\n".join(f"  {f'{path}:{first}':<26} {name:<28} {lines:>4}"
                     for path, name, first, lines in functions)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m benchmarks.reading_path",
                                 description=__doc__.split("\n\n")[0])
    ap.add_argument("--against", metavar="REV", help="also count this commit (or a folder)")
    ap.add_argument("--functions", action="store_true",
                    help="also list every function that ran with its lines")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        print(json.dumps(worker(*json.loads(args.worker))))
        return 0
    print(f"functions that run while simulator.simulate steps the default scene ({LAGGED_STEPS} "
          f"lagged steps, then {IMPLICIT_STEPS} from the start with friction_updates="
          f"{FRICTION_UPDATES}); lines without blank lines, comment-only lines and docstrings")
    results = []
    for title, rev in [("working tree", benchmarks.ROOT)] + (
            [(args.against, args.against)] if args.against else []):
        per_file, ran = count(rev)
        print(format_table(title, per_file))
        if args.functions:
            print(format_functions(ran))
        functions, lines = totals(per_file)
        results.append(f"{title} {lines} lines in {functions} functions")
    print("; ".join(results))
    return 0


if __name__ == "__main__":
    sys.exit(main())
