"""The reading path: the project functions (in the top-level .py files) that run while
simulator.simulate steps the default scene, 300 lagged steps, then 100 from the start with
friction_updates=3, and their lines without blanks, comments and docstrings: benchmarks/README.md.
`--grasp`: the lines of Python outside tests/ that the grasp adds (issue 41): `grasp_lines`.
"""
import argparse
import ast
import io
import os
import pathlib
import re
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


GRASP_FILES = ("scenes/grasp.py", "FingerEnergy.py", "figures/grasp.py")     # the grasp's own
NOT_SHARED = ("tests", "benchmarks", "figures/stick_slip.py")     # (its "pushed" is the chalk)
GRASP_NAME = re.compile(r"(?i)pushed|grasp|finger|lift")    # a name: scene.pushed, lift_work, ...
GRASP_KEY = re.compile(r"W_lift|grasp")                     # a string that is a key of the grasp's
GRASP_DOC = re.compile(r"(?i)pushed surface|scene\.pushed|grasp|finger")   # a docstring's words


def hook_lines(source):
    """The lines of `source` that exist only for the grasp: each smallest statement (an `if`: its
    test and body; a def: all of it) or list, dict or call element that names it in code
    (GRASP_NAME, or a GRASP_KEY string), and the docstring and comment lines that speak of it
    (GRASP_DOC)."""
    tree, names, lines, parts = ast.parse(source), [], set(), []
    docstrings = {line for node in ast.walk(tree)
                  if isinstance(node, DOCUMENTED) and ast.get_docstring(node) is not None
                  for line in range(node.body[0].lineno, node.body[0].end_lineno + 1)}
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type in (tokenize.STRING, tokenize.COMMENT):
            lines.update(token.start[0] + k for k, text in enumerate(token.string.splitlines())
                         if GRASP_DOC.search(text))
        if token.start[0] not in docstrings and (
                GRASP_NAME.search(token.string) if token.type == tokenize.NAME else
                token.type == tokenize.STRING and GRASP_KEY.search(token.string)):
            names.append(token.start)
    for node in ast.walk(tree):
        if isinstance(node, ast.If):                # not the elif or else after it
            parts.append((node.lineno, node.body[-1].end_lineno, node.test))
        elif isinstance(node, ast.stmt):
            parts.append((node.lineno, node.end_lineno, node))
        elements = [*getattr(node, "elts", []), *getattr(node, "keys", []),
                    *getattr(node, "values", [])]           # a list's, a tuple's, a dict's
        if isinstance(node, ast.Call):
            elements += node.args + node.keywords
        parts += [(e.lineno, e.end_lineno, e) for e in elements if e is not None]
    for start in names:         # the smallest part whose head (an if's test) holds the name
        _, first, last = min((last - first, first, last) for first, last, head in parts
                             if (head.lineno, head.col_offset) <= start
                             < (head.end_lineno, head.end_col_offset))
        lines.update(range(first, last + 1))
    return lines


def grasp_lines(root=tables.ROOT):
    """{file: (lines, code lines)} the grasp adds outside tests/: every line of GRASP_FILES, and
    hook_lines of every other .py file but NOT_SHARED's; code lines as code_lines counts them."""
    counts = {}
    for path in sorted(pathlib.Path(root).rglob("*.py")):
        name = path.relative_to(root).as_posix()
        if name.startswith(NOT_SHARED) or name.startswith("."):
            continue
        source = path.read_text()
        lines = (set(range(1, len(source.splitlines()) + 1)) if name in GRASP_FILES
                 else hook_lines(source))
        if lines:
            counts[name] = (len(lines), len(lines & code_lines(source)))
    return counts


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m benchmarks.reading_path", description=__doc__)
    ap.add_argument("--against", metavar="REV", help="also count this commit (or a folder)")
    ap.add_argument("--functions", action="store_true",
                    help="also list every function that ran with its lines")
    ap.add_argument("--grasp", action="store_true",
                    help="instead, the lines of Python the grasp adds outside tests/, per file")
    args = ap.parse_args(argv)
    if args.grasp:
        counts = grasp_lines()
        total = tuple(map(sum, zip(*counts.values())))
        print(f"  {'file':<28} {'lines':>5} {'code':>5}  (code: no blanks, comments, docstrings)")
        for name, (lines, code) in list(counts.items()) + [("total", total)]:
            whole = "  (the whole file)" if name in GRASP_FILES else ""
            print(f"  {name:<28} {lines:>5} {code:>5}{whole}")
        print(f"the grasp adds {total[0]} lines of Python outside tests/, {total[1]} of them code")
        return 0
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
