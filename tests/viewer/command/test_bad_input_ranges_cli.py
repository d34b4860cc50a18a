"""Every scene's numbers in range on the command line (issue 40, item 5): one line naming the flag,
exit code 2, nothing written; or a run with a warning saying what its result cannot be trusted
for. The library's refusals: tests/scenes/test_bad_input_ranges.py."""
import pytest

from helpers.command import messages, refused, run_main, too_wide

pytestmark = pytest.mark.usefixtures("shared_stepping")   # the runs' steps: helpers/runs.py

TABLECLOTH = [
    (["--gravity", "0,-1e308"], "--gravity: gravity = 0, -1e+308: first inertia term inf > 1e+150"),
    (["--mass", "1e300"], "--mass: mass = 1e+300: total mass 1e+300 > 1e+150 (float64)"),
    (["--kappa", "1e-320"], "--kappa: kappa = 9.99989e-321: cannot carry the dish"),
    (["--kappa", "1e300"], "--kappa: kappa = 1e+300: "),
    (["--dhat", "1e300"], "--dhat: dhat = 1e+300: "),
    (["--mu", "1e308"], "--mu: mu = 1e+308: friction's stiffness "),
    (["--h", "1e200"], "--h: h = 1e+200: first inertia term "),
    (["--h", "1e-160"], "--h: h = 1e-160 s: h^2 underflows float64 (h >= 1.5e-154 s)"),
    (["--pull-length", "1e308"], "--pull-length: pull_length must be <= 1e+150"),
    (["--gravity", "0,-1e-320"], "--gravity: gravity = 0, -9.99989e-321: lost in round-off "
                                 "(|gravity| >= 8.9e-11)")]


@pytest.mark.parametrize("flags, said", [
    (["--squeeze", "1e-320"], "--squeeze: squeeze = 9.99989e-321: lost in round-off "
                              "(squeeze >= 1.11e-14)"),       # was 'math domain error'
    (["--kappa", "1e150"], "--kappa: kappa = 1e+150: lost in round-off "
                           "(kappa <= 2.36e+16)")])
def test_the_grasp_refuses_a_squeeze_the_barrier_cannot_resolve(tmp_path, flags, said):
    line = refused(["--scene", "grasp", *flags], tmp_path / "out")
    assert line == f"simulator.py: error: {said}", line
DEFAULT_DURATION = [    # ran for ever: the default duration lasts till the closed-form dish stops
    (["--pull-speed", "1e-300"], "--pull-speed: pull_speed = 1e-300: the dish stops at t = 1e+300"),
    (["--pull-length", "1e100"], "--pull-length: pull_length = 1e+100: the dish stops at t = "),
    (["--h", "1e-12"], "--h: h = 1e-12: the dish stops at t = 0.55 s, more than 1e+08 steps")]


@pytest.mark.parametrize("flags, said", TABLECLOTH, ids=[" ".join(f) for f, _ in TABLECLOTH])
def test_the_tablecloth_refuses_out_of_range_numbers_in_one_line(tmp_path, flags, said):
    """One line, exit 2, nothing written (helpers.command.refused)."""
    line = refused(["--scene", "tablecloth", *flags], tmp_path / "out")
    assert line.startswith(f"simulator.py: error: {said}"), line


@pytest.mark.parametrize("flags, said", DEFAULT_DURATION,
                         ids=[" ".join(f) for f, _ in DEFAULT_DURATION])
def test_a_default_run_too_long_to_end_is_refused_in_one_line(tmp_path, flags, said):
    code, lines = run_main("--scene", "tablecloth", *flags, "--out", str(tmp_path / "out"))
    assert code == 2 and len(lines) == 1 and lines[0].startswith(f"simulator.py: error: {said}")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("flags, said", [
    (["--pull-speed", "1000"], "the pull lasts 0.001 s, under 2 steps of h = 0.005 s: its travel "
                               "cannot be trusted (use U <= 100 m/s)"),
    (["--steps", "30"], "the run ends at 0.15 s, before the dish stops (0.55 s in the closed "
                        "form): its travel is unfinished")])
def test_a_tablecloth_result_that_cannot_be_trusted_is_warned_about(tmp_path, flags, said):
    code, lines = run_main("--scene", "tablecloth", *flags, "--no-frames",
                           "--out", str(tmp_path / "run"))
    assert code == 0 and f"simulator.py: warning: {said}" in messages(lines), lines
    if "unfinished" in said:        # and the closing compares no unfinished travel
        assert ("the dish travelled 0.0103 m by 0.15 s, unfinished: the closed form's stops at "
                "0.55 s") in lines, lines


def test_a_tablecloth_run_to_its_dish_stop_is_not_warned_about(tmp_path):
    code, lines = run_main("--scene", "tablecloth", "--no-frames", "--out", str(tmp_path / "run"))
    assert code == 0 and not [line for line in lines if "warning" in line], lines


def test_a_huge_closed_form_figure_is_said_in_3_digits(tmp_path):
    """--pull-speed 1e-300 for 0.03 s: the closed form's dish stops at 1e+300 s, said so (it was
    written with %.2f, a line of 383 columns); every line fits in 100 columns."""
    code, lines = run_main("--scene", "tablecloth", "--pull-speed", "1e-300", "--duration", "0.03",
                           "--no-frames", "--out", str(tmp_path / "run"))
    assert code == 0 and not too_wide(lines, tmp_path), lines
    assert ("the dish travelled 0.0000 m by 0.03 s, unfinished: the closed form's stops at "
            "1e+300 s") in lines, lines


def test_a_grip_lost_in_round_off_is_refused_before_anything_is_written(tmp_path):
    """--grip 1e-320 ran, then its first frame's drawing ended in an OverflowError traceback,
    exit 1, the folder left claimed: refused in one line, the least grip named."""
    line = refused(["--scene", "chalk", "--grip", "1e-320", "--duration", "0.03"], tmp_path / "o")
    assert line == ("simulator.py: error: --grip: k_hand = 9.99989e-321: lost in round-off "
                    "(k_hand >= 4.21e-13)"), line
