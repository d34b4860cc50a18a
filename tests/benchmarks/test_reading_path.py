"""benchmarks/reading_path.py: the line counter, on a source whose counts are read off its text,
and on this tree."""
import os

from helpers.checkout import ROOT, checkout_state


# the reading path's counter, on a source whose counts are read off its text
SOURCE = '''"""Module docstring: not counted."""
import math


def f(xs):
    """A docstring
    over two lines."""
    # a comment line
    total = sum(x * x for x in xs)

    return math.sqrt(total)  # a trailing comment: the line counts


def g():
    text = """a string that is not a docstring
    counts on both its lines"""
    return text


class C:
    """Class docstring."""

    def method(self):
        return 1
'''


def test_code_lines_leave_out_blanks_comments_and_docstrings():
    from benchmarks import reading_path
    assert reading_path.code_lines(SOURCE) == {2, 5, 9, 11, 14, 15, 16, 17, 20, 23, 24}


def test_reading_path_counts_the_functions_that_ran_once_with_their_generators(tmp_path):
    """f ran (its generator expression is part of f), method ran twice, g never ran: 2 functions,
    3 + 2 lines in mod.py; a file outside the tree's top level is not a project file."""
    from benchmarks import reading_path
    path = tmp_path / "mod.py"
    path.write_text(SOURCE)
    module = compile(SOURCE, str(path), "exec")
    codes = {}

    def walk(code):
        codes[code.co_name] = code
        for const in code.co_consts:
            if hasattr(const, "co_name"):
                walk(const)
    walk(module)
    ran = {codes["f"], codes["<genexpr>"], codes["method"]}
    outside = compile(SOURCE, str(tmp_path / "tests" / "mod.py"), "exec")   # not at the top level
    ran |= {const for const in outside.co_consts if hasattr(const, "co_name")}
    found = reading_path.functions_that_ran(ran, str(tmp_path))
    assert found == [("mod.py", "f", 5, [5, 9, 11]), ("mod.py", "method", 23, [23, 24])]
    assert reading_path.per_file(found) == {"mod.py": (2, 5)}
    listed = reading_path.format_functions(found)
    assert [line.split() for line in listed.splitlines()] == [
        ["mod.py:5", "f", "3"], ["mod.py:23", "method", "2"]]


def test_reading_path_of_this_tree_against_itself(capsys):
    """python -m benchmarks.reading_path --against <this tree>: the same table twice, counting the
    integrator and the simulator, each file within its code lines, the totals in the last line."""
    from benchmarks import reading_path
    before = checkout_state()
    assert reading_path.main(["--against", ROOT]) == 0
    assert checkout_state() == before                               # it writes no file
    out = capsys.readouterr().out.splitlines()
    tables = [out[out.index(title) + 2:] for title in ("working tree", ROOT)]
    tables = [table[:[line.split()[0] for line in table].index("total")] for table in tables]
    assert tables[0] == tables[1]
    per_file = {name: (int(functions), int(lines))
                for name, functions, lines in map(str.split, tables[0])}
    assert {"time_integrator.py", "simulator.py", "utils.py"} <= set(per_file)
    for name, (functions, lines) in per_file.items():
        assert 0 < functions <= lines
        with open(os.path.join(ROOT, name)) as f:
            assert lines <= len(reading_path.code_lines(f.read()))
    functions, lines = map(sum, zip(*per_file.values()))
    counted = f"{lines} lines in {functions} functions"
    assert out[-1] == f"working tree {counted}; {ROOT} {counted}"


# the grasp's line counter (issue 41), on a source whose hook lines are read off its text
HOOKED = '''"""A module: its pushed surfaces' hook."""


def f(scene, x):
    """Its other lines are the body's."""
    if scene.pushed is not None:
        x = scene.pushed.body(x)
        return x
    elif scene.n is None:
        return None
    y = [1, 2,
         scene.pushed]
    return {"a": 1,
            "W_lift": 2}, y       # the grasp's pads


def pushed_report(report):
    return report
'''


def test_hook_lines_count_what_names_the_grasp():
    """The docstring line that speaks of it (1), the if's test and body (not its elif: 6-8), the
    list's element (12), the dict's key (14) with its comment, the def named for it (17-18)."""
    from benchmarks import reading_path
    assert reading_path.hook_lines(HOOKED) == {1, 6, 7, 8, 12, 14, 17, 18}
