"""The reading path: the project functions (in the top-level .py files) that run while
simulator.simulate steps the default scene, 300 lagged steps, then 100 from the start with
friction_updates=3, and their lines without blanks, comments and docstrings: benchmarks/README.md.
"""
import argparse
import ast
import io
import os
import sys
import tempfile
import tokenize

from benchmarks import tables

LAGGED_STEPS, IMPLICIT_STEPS, FRICTION_UPDATES = 300, 100, 3
FUNCTIONS = (ast.FunctionDef, ast.AsyncFunctionDef)
DOCUMENTED = (ast.Module, ast.ClassDef) + FUNCTIONS
NOT_CODE = {tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT,
            tokenize.ENDMARKER, tokenize.ENCODING}


def code_lines(source):
    """The line numbers of `source` that hold code: not blank, not only a comment, no docstring."""
    lines = set()
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type not in NOT_CODE:
            lines.update(range(token.start[0], token.end[0] + 1))
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, DOCUMENTED) and ast.get_docstring(node) is not None:
            lines.difference_update(range(node.body[0].lineno, node.body[0].end_lineno + 1))
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


def functions_that_ran(code_objects, tree):
    """[(file, name, first line, its code lines)], sorted, of the functions in `tree`'s top-level
    .py files that hold the code objects that ran (the innermost one holding a code object)."""
    firsts, ran = {}, []
    for c in code_objects:
        firsts.setdefault(os.path.abspath(c.co_filename), []).append(c.co_firstlineno)
    for path in sorted(p for p in firsts if os.path.dirname(p) == tree and p.endswith(".py")):
        with open(path) as f:
            source = f.read()
        extents, counted = function_extents(source), code_lines(source)
        holding = ([ext for ext in extents if ext[0] <= line <= ext[1]] for line in firsts[path])
        ran += [(os.path.relpath(path, tree), name, first,
                 sorted(counted.intersection(range(first, last + 1))))
                for first, last, name in sorted({max(h) for h in holding if h})]
    return ran


def per_file(functions):
    """{file: (functions, lines)} of functions_that_ran; lines nested functions share count once."""
    held = {}
    for path, _, _, lines in functions:
        held.setdefault(path, []).append(lines)
    return {path: (len(lines), len(set().union(*lines))) for path, lines in held.items()}


def worker(tree):
    """functions_that_ran in `tree` (first on sys.path) while simulate steps the default scene,
    lagged, then with Algorithm 5 from the start (issue 14 gives 444 lines for c6bcae2)."""
    sys.path.insert(0, tree)
    import simulator
    runs = ((simulator.build_scene(), LAGGED_STEPS),
            (simulator.build_scene(friction_updates=FRICTION_UPDATES), IMPLICIT_STEPS))
    seen = set()

    def profile(frame, event, arg):
        if event == "call":
            seen.add(frame.f_code)
    sys.setprofile(profile)
    for scene, steps in runs:
        for _ in simulator.simulate(scene, steps):
            pass
    sys.setprofile(None)
    return functions_that_ran(seen, tree)


def count(rev):
    """worker of a folder or of commit `rev`, in a fresh Python process."""
    with tempfile.TemporaryDirectory(prefix="reading_path-") as folder:
        tree = tables.export_tree(rev, folder)
        return tables.in_fresh_process("benchmarks.reading_path", "worker", tree)


def format_functions(functions):
    """One line per function that ran: file:first line, name, code lines."""
    return "\n".join(f"  {f'{path}:{first}':<26} {name:<28} {len(lines):>4}"
                     for path, name, first, lines in functions)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m benchmarks.reading_path", description=__doc__)
    ap.add_argument("--against", metavar="REV", help="also count this commit (or a folder)")
    ap.add_argument("--functions", action="store_true",
                    help="also list every function that ran with its lines")
    args = ap.parse_args(argv)
    print(f"functions that run while simulator.simulate steps the default scene ({LAGGED_STEPS} "
          f"lagged steps, then {IMPLICIT_STEPS} from the start with friction_updates="
          f"{FRICTION_UPDATES}); lines without blank lines, comment-only lines and docstrings")
    results = []
    for title, rev in [("working tree", tables.ROOT)] + (
            [(args.against, args.against)] if args.against else []):
        ran = count(rev)
        files = per_file(ran)
        total = tuple(map(sum, zip(*files.values())))
        print(title, f"  {'file':<22} {'functions':>9} {'lines':>6}", sep="\n")
        rows = sorted(files.items(), key=lambda item: -item[1][1])      # most lines first
        for name, (functions, lines) in rows + [("total", total)]:
            print(f"  {name:<22} {functions:>9} {lines:>6}")
        if args.functions:
            print(format_functions(ran))
        results.append(f"{title} {total[1]} lines in {total[0]} functions")
    print("; ".join(results))
    return 0


if __name__ == "__main__":
    sys.exit(main())
