"""Every line a run prints fits in 100 columns (issue 40): progress, warnings, the closing in at
most 3 lines and a refusal in one. Only a path may run longer: the folder the run was given or
its working folder, as the closing's file:// link repeats it."""
import pytest

from helpers.command import closing_lines, run_main, too_wide
from viewer.command import progress

pytestmark = pytest.mark.usefixtures("shared_stepping")   # the runs' steps: helpers/runs.py

WIDTH = 100


# Each run long enough to reach the event its closing words say (measured on each): the lecture's
# square with mu = 0.2 sticks at 2.80 s, so 3.2 s close with its stick and creep in the very words
# and widths of the default run's (stuck at 5.54 s of 6 s), at half the steps; the chalk's first
# slip ends at 0.31 s (3 slips by 0.6 s); the tablecloth's pulls run until the dishes stop.
@pytest.mark.parametrize("args, event", [
    (["--mu", "0.2", "--duration", "3.2"], "the square sticks at "),
    (["--scene", "chalk", "--duration", "0.6"], "stick-slip: 3 slips, "),
    (["--scene", "tablecloth", "--pull-speed", "1,2,4,8", "--frame-stride", "40"],
     "the dish travelled "),
])              # the mu comparison's: test_run_outputs.test_the_lectures_comparison_in_one_command;
# a chalk comparison where one slides and one stick-slips (stick_slip.short_words):
# test_chalk_view.test_a_mixed_chalk_comparison_fits_and_closes_in_3_lines, on the run it shares
def test_every_line_of_a_run_fits_and_it_closes_in_3_lines(args, event, tmp_path, monkeypatch):
    """Each run into its default folder under output/ (the folder's own name counts)."""
    monkeypatch.chdir(tmp_path)
    code, lines = run_main(*args)
    assert code == 0, lines
    assert len(lines) > 3 and not too_wide(lines, tmp_path)
    assert len(closing_lines(lines)) <= 3, lines
    assert closing_lines(lines)[1].startswith(event), lines
    assert WIDTH == progress.WIDTH


def test_a_refusal_is_one_line_that_fits(tmp_path, monkeypatch):
    """A checkout where output/ cannot be made: the folder tried is named, --out is not blamed."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "output").write_text("a file where the runs' folder would be")
    for args in ([], ["--scene", "tablecloth"]):
        code, lines = run_main("--steps", "3", *args)
        assert code == 2 and len(lines) == 1 and not too_wide(lines), lines
        assert lines[0].startswith("simulator.py: error: folder 'output/")
        assert lines[0].endswith(" cannot be created: Not a directory") and "--out" not in lines[0]
    code, lines = run_main("--steps", "3", "--out", "output/mine")
    assert code == 2 and lines == ["simulator.py: error: --out: out folder 'output/mine' cannot be "
                                   f"created: '{tmp_path / 'output'}' is not a folder"]


def test_a_long_warning_is_broken_between_words(tmp_path):
    """The folding mesh's warning (about 150 characters) in lines that fit, the next indented."""
    code, lines = run_main("--n-seg", "8", "--steps", "60", "--no-frames", "--out", str(tmp_path))
    assert code == 0 and not too_wide(lines, tmp_path)
    first = next(i for i, line in enumerate(lines) if "inverted" in line)
    assert lines[first].startswith("simulator.py: warning: at step ")
    assert lines[first + 1].startswith("  ") and "--h" in lines[first + 1]


@pytest.mark.parametrize("name, printed", [("a\nb", "a\\nb"), ("\x1b[31mred", "\\x1b[31mred")])
def test_a_folder_with_control_characters_is_printed_escaped(tmp_path, name, printed):
    """A newline or a terminal's escape in --out: the closing line stays one line, no raw escape
    (files.shown)."""
    code, lines = run_main("--steps", "2", "--no-frames", "--out", str(tmp_path / name))
    assert code == 0 and (tmp_path / name).is_dir()
    assert not [line for line in lines if not line.isprintable()], lines
    assert lines[-1] == f"wrote 3 files in {tmp_path}/{printed}/", lines
