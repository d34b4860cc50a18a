"""benchmarks/frame_parts.py: each part of a frame timed within the default run."""
import pytest

from benchmarks import frame_parts, tables
from helpers.checkout import ROOT, checkout_state


def test_each_part_is_timed_and_the_frame_holds_its_parts(tmp_path):
    """One default run in a fresh process (the timers replace module functions): every part was
    called and took time, and the whole frame, which calls the drawing, the PNG (the palette
    indices within it) and the OBJ text, took at least their sum (process time never runs
    backwards)."""
    before = checkout_state()
    ms = tables.in_fresh_process("benchmarks.frame_parts", "frame_parts", ROOT, str(tmp_path))
    assert set(ms) == set(frame_parts.PARTS) and all(ms[part] > 0 for part in ms)
    inside = ("drawing", "PNG in bands", "OBJ text")
    assert ms["whole frame"] >= sum(ms[part] for part in inside)
    assert ms["PNG in bands"] >= ms["palette indices"]
    assert checkout_state() == before


def test_rounds_below_one_are_refused_in_one_line(capsys):
    assert frame_parts.main(["--rounds", "0"]) == 2
    said = capsys.readouterr().err
    assert said.count("\n") == 1 and "--rounds" in said and "0" in said


def test_help_is_the_docstrings_first_paragraph(capsys):
    with pytest.raises(SystemExit) as ended:
        frame_parts.main(["--help"])
    assert ended.value.code == 0
    said = capsys.readouterr().out
    assert said.startswith("usage: python -m benchmarks.frame_parts ")
    description = " ".join(said.split("\n\n")[1].split())
    assert description == " ".join(frame_parts.__doc__.split("\n\n")[0].split())
