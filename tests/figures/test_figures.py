"""figures/: each figure's numbers on a small case (the lecture's claims), and `python -m figures`
as a user runs it: whole PNGs, one-line errors with exit code 2, Ctrl+C ends in 130."""
import errno
import math
import os
import re
import signal
import subprocess
import sys
import types

import numpy as np
import pytest

import BarrierEnergy
import FrictionEnergy
import figures.page
import simulator
from analysis import wear
from figures import (cli, dissipation, fixed_point, mollifier, relative_velocity, semi_implicit,
                     stick_slip)
from helpers import ROOT, runs
from helpers.fakes import DropsTheHandlersRaise
from scenes import tablecloth
from viewer.output import whole_files

PNG_SIGNATURE, PNG_END = b"\x89PNG\r\n\x1a\n", b"IEND\xaeB`\x82"
plots = figures.page.plots


def is_png(data):
    return data.startswith(PNG_SIGNATURE) and data.endswith(PNG_END)


def caption_fits(page, lines):
    """Every caption line, in the caption's font (figures.page), ends inside the page."""
    font = page.pygame.font.Font(None, 20)
    return all(12 + font.size(line)[0] <= page.surface.get_width() for line in lines)


def page_height(panels, lines):
    """A page's height with `panels` panels and `lines` caption lines (figures.page)."""
    return figures.page.TITLE_HEIGHT + panels * plots.PANEL_HEIGHT \
        + figures.page.LINE_HEIGHT * (lines + 1)


def test_f0_derivative_is_f1():
    r = mollifier.compute(points=201)
    assert r.max_error < 1e-8                     # the difference's error bound: 3e-11 + round-off
    assert r.f1[r.checked >= r.epsv] == pytest.approx(1.0)      # Coulomb's f from eps_v on
    assert np.all(np.diff(r.f1) >= -4 * np.finfo(float).eps)   # rising (to round-off) ...
    assert all(values[0] == 0.0 for values in r.f1s)           # ... from f1(0) = 0 ...
    assert r.f1[0] < 2 * r.checked[0] / r.epsv                 # ... with slope 2 / eps_v there
    page = mollifier.draw(r)
    assert page.surface.get_height() == page_height(4, 3)


def test_friction_power_is_never_above_round_off():
    r = dissipation.compute(mus=(0.11,), duration=0.45)    # the landing (step 30), 15 steps sliding
    run = r.runs[0]
    assert len(run.P) == 45 and len(run.beyond) == 0
    assert np.all(run.P <= run.bound)
    assert run.P.min() < 0.0 and run.bound.max() < 1e-10 * -run.P.min()   # worked; bound: round-off
    page = dissipation.draw(r)
    assert page.surface.get_height() == page_height(2, 3 + len(r.runs)) and is_png(page.png())


def test_fixed_point_reports_a_step_that_does_not_converge():
    r = fixed_point.compute(steps=9)      # step 8 of the hard scene does not converge in 20 updates
    tol, updates = r.scene.tol, r.scene.friction_updates
    i, report, measures = r.failing
    assert report.friction_converged is False
    assert len(measures) == report.friction_updates + 1 == updates + 1 and np.all(measures > tol)
    i, report, measures = r.converging
    assert report.friction_converged is True and measures[-1] <= tol < measures[0]
    assert len(measures) == report.friction_updates + 1 > 1


def test_the_fixed_point_caption_fits_the_page():
    r = fixed_point.compute()
    lines = fixed_point.caption(r)
    page = fixed_point.draw(r)
    assert caption_fits(page, lines)
    assert f"{r.failed} of its first {r.steps} steps did not converge." in lines
    assert page.surface.get_height() == page_height(1, len(lines))


@pytest.fixture(scope="module")
def semi_implicit_short():
    """The semi_implicit figure's numbers, its two scenes over their first 0.4 s."""
    return semi_implicit.compute(duration=0.4)


def test_lagged_and_implicit_friction_end_apart(semi_implicit_short):
    r = semi_implicit_short
    for s in r.scenes:
        assert np.isfinite(s.gap).all() and s.gap[-1] > 0.0
        assert s.gap[0] == 0.0                     # same start
        assert all(far[0] == 0.0 for far in s.from_reference.values())
        steps = len(s.t) - 1                      # the reference and its check: 0.4 s in more steps
        t_ref, t_check = s.runs["reference"].t, s.runs[semi_implicit.CHECK].t
        assert len(t_ref) - 1 == semi_implicit.REFERENCE_DIVISOR * steps
        assert len(t_check) - 1 == semi_implicit.CHECK_DIVISOR * steps
        assert t_ref[-1] == pytest.approx(s.t[-1]) and t_check[-1] == pytest.approx(s.t[-1])
    default, pressed = r.scenes
    assert pressed.gap[-1] > 10 * default.gap[-1]


def test_the_caption_calls_nearer_the_run_the_distances_put_nearer(semi_implicit_short):
    """The verdict comes from the distances at the end: the nearer run, the margin, and "measured"
    only where the margin exceeds the reference's own error (its distance from the check run)."""
    text = "\n".join(semi_implicit.caption(semi_implicit_short))
    for s in semi_implicit_short.scenes:
        lagged, implicit, own = (s.from_reference[name][-1]
                                 for name in ("lagged", "Algorithm 5", semi_implicit.CHECK))
        nearer, margin = ("lagged" if lagged < implicit else "Algorithm 5"), abs(lagged - implicit)
        assert s.verdict == (nearer, margin, margin > own)
        assert (f"{nearer} is nearer by {1e3 * margin:.3g} mm, "
                f"{'more' if margin > own else 'less'} than the reference's own error") in text
        assert f"lagged {1e3 * lagged:.3g} mm, Algorithm 5 {1e3 * implicit:.3g} mm" in text
        most = s.gap.max()
        said = f"lagged and Algorithm 5 coincide to within {1e3 * most:.3g} mm over the run" in text
        assert said == (most <= semi_implicit.COINCIDE * semi_implicit.span(s))
        assert said or f"Algorithm 5 come up to {1e3 * most:.3g} mm apart over the run" in text
    default, pressed = semi_implicit_short.scenes
    assert pressed.verdict[0] == "Algorithm 5" and pressed.verdict[2]   # lagging the push: measured
    assert default.start_load == 0.0 and pressed.start_load > 1.5


def test_both_friction_curves_show_and_the_caption_fits(semi_implicit_short):
    """Lagged (blue) is drawn wider, under Algorithm 5 (orange): in every panel both colours show
    in most columns of the time axis, also where they coincide. The caption ends inside the page."""
    page = semi_implicit.draw(semi_implicit_short)
    assert caption_fits(page, semi_implicit.caption(semi_implicit_short))
    pixels = page.pygame.surfarray.array3d(page.surface)                      # [x, y, rgb]
    for panel in range(2 * len(semi_implicit_short.scenes)):
        top = figures.page.TITLE_HEIGHT + panel * plots.PANEL_HEIGHT
        area = pixels[plots.LEFT + 1:plots.RIGHT, top + 24:top + plots.PANEL_HEIGHT - 30]
        for color in (semi_implicit.run_color(0), semi_implicit.run_color(1)):
            assert np.all(area == color, axis=2).any(axis=1).mean() > 0.9, (panel, color)


def test_the_pressed_scene_starts_on_the_slope_and_its_lagged_step_brakes_with_the_push():
    """sliding_start: the square aligned with the slope 8 mm from it, every node moving downhill at
    3 m/s. The lagged first step's friction is mu lambda(x^0), every contact sliding (f1 = 1), the
    springs' forces cancel and the barrier's are normal: the centre of mass's downhill speed after
    one step is v0 + h (g . t - mu sum lambda(x^0) / M), to within Newton's tol."""
    params = semi_implicit.sliding_start(0.008, 3.0, mu=0.3, h=0.05)
    scene = simulator.build_scene(**params)
    t = FrictionEnergy.tangent(scene.n)
    d = BarrierEnergy.distances(scene.x0, scene.n, scene.o)
    assert d[::scene.params["n_seg"] + 1] == pytest.approx(0.008, abs=1e-12)
    assert d.min() == pytest.approx(0.008, abs=1e-12)
    assert scene.v0 @ scene.n == pytest.approx(0.0, abs=1e-12)
    assert scene.v0 @ t == pytest.approx(3.0)
    record = next(simulator.simulate(scene, 1))
    mu_lambda = BarrierEnergy.compute_mu_lambda(scene.x0, scene.n, scene.o, scene.contact_area,
                                               scene.mu, scene.dhat, scene.kappa)
    M = scene.m.sum()
    expected = 3.0 + scene.h * (scene.g @ t - mu_lambda.sum() / M)
    com_v = np.average(record.v, axis=0, weights=scene.m)
    assert com_v @ t == pytest.approx(expected, abs=scene.tol)
    assert mu_lambda.sum() / scene.mu > 1.5 * M * -(scene.g @ scene.n)     # more than its weight


@pytest.fixture(scope="module")
def stick_slip_short(chalk_runs):
    """The stick_slip figure's numbers on a short case: 0.7 s for the marks and the four grips
    (measured: 3 / 4 / 8 / 13 cycles, the loosest grip's period 149 ms), and every tilt over 0.5 s
    (measured: 60 to 67 deg slide 2.39 to 2.98 mm of the hand's 3 mm, 68 to 75 deg at most
    0.023 mm: the figure's bracket, between 67 and 68 deg). Its runs' states are the session's
    (helpers/runs.py, simulate's bit for bit), which tests/scenes/test_chalk.py shares."""
    with pytest.MonkeyPatch.context() as monkeypatch:
        monkeypatch.setattr(stick_slip, "simulator", runs.replaying(chalk_runs))
        return stick_slip.compute(duration=0.7, tilt_duration=0.5)


def test_the_marks_are_the_archard_deposits_of_the_runs(stick_slip_short):
    """Each run's mark is analysis/wear.py's deposit of its steps, over the board its tip slid
    across (the tip, the lowest node, carries the contact); the caption's creep is the tip's
    largest travel over a run of stuck states."""
    r = stick_slip_short
    for tr in (r.pushed, r.dragged):
        lo, hi = tr.mark.span()
        assert tr.tip_lowest and lo <= tr.x.min() and tr.x.max() <= hi
        assert hi - lo < np.ptp(tr.x) + 3 * wear.BIN
        assert tr.mark.values.sum() > 0
    assert 0 < r.push.creep < 0.05 * r.push.length


def test_the_pushed_chalk_leaves_dashes_a_slip_apart_and_the_dragged_a_line(stick_slip_short):
    """Pushed: the slip about catches up with the hand (slip = drive x period), the period is that
    of the speed's peaks, and its mark is a dash per slip (the last, unfinished, not counted), each
    darker where it starts than where it fades by 4.5 times or more (tests/analysis/test_wear.py
    measures why). Dragged: after its start-up no stick, and a mark without a dash."""
    r = stick_slip_short
    push, drive = r.push, r.pushed.scene.params["drive"]
    starts, lengths, peaks = map(np.array, zip(*push.slips))
    assert len(push.slips) >= 3 and push.stuck > 0.5 and (peaks > 2 * drive).all()
    assert push.length == pytest.approx(drive * push.period, rel=0.05)
    u, t = np.abs(r.pushed.u), r.pushed.t
    peak = (u[1:-1] > drive) & (u[1:-1] >= u[:-2]) & (u[1:-1] > u[2:])
    assert np.diff(t[1:-1][peak]).mean() == pytest.approx(push.period, rel=0.02)
    assert len(r.push_mark.dashes) >= len(push.slips) - 1 and r.push_mark.dashes.min() >= 4.5
    drag = r.drag
    assert drag.slips == [] and drag.stuck_after == 0 and 0.2 < drag.start_up < 0.5
    assert len(r.drag_mark.dashes) == 0 and r.drag_mark.p90 / r.drag_mark.p10 < 1.05


def test_the_tighter_grip_slips_less_at_the_same_press_force(stick_slip_short):
    r = stick_slip_short
    assert [g.k_hand for g in r.grips] == list(stick_slip.GRIPS)
    assert all(len(g.slips) >= 2 for g in r.grips)
    lengths = [g.length for g in r.grips]
    assert all(a > b for a, b in zip(lengths, lengths[1:])) and stick_slip.falls(r)
    assert r.grips[1].length == r.push.length                 # the default grip is the pushed run
    assert r.force == pytest.approx(1.0)                      # 2000 N/m x 0.5 mm per held node


def test_one_coefficient_slides_below_and_jams_above_one_tilt_below_the_strut(stick_slip_short):
    """Over the figure's tilts every sliding one is below every jamming one: the bracket, below the
    rigid strut's self-locking angle 90 - atan mu."""
    r = stick_slip_short
    assert [t.tilt for t in r.tilts] == list(stick_slip.TILTS)
    for t in r.tilts:
        assert t.tip_lowest
        assert t.travel < 0.01 * t.hand_travel if t.jams else t.travel > 0.75 * t.hand_travel
    assert r.bracket == (67.0, 68.0)
    assert r.lock == pytest.approx(70.71, abs=0.01) and r.bracket[1] < r.lock


def test_the_stick_slip_caption_says_the_computed_numbers_and_fits_the_page(stick_slip_short):
    r = stick_slip_short
    lines = stick_slip.caption(r)
    text = "\n".join(lines)
    push, m = r.push, r.push_mark
    assert (f"{len(push.slips)} cycles, period {1e3 * push.period:.0f} ms, "
            f"slip {1e3 * push.length:.2f} mm") in text
    assert f"stuck {100 * push.stuck:.0f} % of the drive" in text
    assert f"starts at {r.drag.start_up:.3g} s, then stuck in 0 of its {r.drag.after} steps" in text
    assert f"Its mark: {len(m.dashes)} dashes, each darkest where its slip" in text
    assert f"starts, {m.dashes.min():.1f} to {m.dashes.max():.1f} x its faintest" in text
    assert f"(p90/p10 {m.p90 / m.p10:.2f}): a dashed line." in text and "Its mark: no dash," in text
    assert "slip " + " / ".join(f"{1e3 * g.length:.2f}" for g in r.grips) + " mm" in text
    assert "between 67 and 68 deg, below the rigid strut's 90 - atan mu = 70.7 deg" in text
    assert "did not stay the lowest node" not in text
    page = stick_slip.draw(r)
    assert caption_fits(page, lines) and page.surface.get_height() == page_height(4, len(lines))
    assert is_png(page.png())


@pytest.fixture(scope="module")
def tablecloth_pulls():
    """The relative_velocity figure's numbers on four pulls: the slow and fast ones it draws over
    time (1 and 4 m/s), and one each side of sqrt(mu g L) = 1.40 m/s (1 and 1.6 m/s)."""
    return relative_velocity.compute(speeds=(1.0, 1.6, 4.0, 8.0))


def on_the_closed_form(r):
    """Each pull's travel within 5 % of tablecloth.travel, and the dish at rest at the
    end. 5 %: the closed form leaves out the mollifier's creep below eps_v (at most eps_v for the
    ~1 s the dish rides the cloth: 1e-3 m, 0.1 % of L) and the elastic dish's settling; measured,
    every pull is within 0.012 % (L / U a whole number of steps: relative_velocity.SPEEDS)."""
    epsv = simulator.TABLECLOTH["epsv"]
    for run in r.runs:
        assert run.closed == tablecloth.travel(run.U, r.L, r.mu, r.g)
        assert run.travel == pytest.approx(run.closed, rel=0.05), run.U
        assert abs(run.v_p[-1]) < epsv and run.v_s[-1] == 0.0
    return True


def test_the_dish_travels_as_the_closed_form_says(tablecloth_pulls):
    assert on_the_closed_form(tablecloth_pulls)


def test_the_crossover_is_at_sqrt_mu_g_l_between_riding_and_outrun_pulls(tablecloth_pulls):
    """The closed form's branches L and mu g L^2 / U^2 meet at U = sqrt(0.2 x 9.81 x 1 m) = 1.40
    m/s, and the simulated pulls put it there: 1 m/s rides along (travels L), 1.6 m/s is outrun."""
    r = tablecloth_pulls
    p = simulator.TABLECLOTH
    assert r.crossover == pytest.approx(math.sqrt(p["mu"] * -p["gravity"][1] * p["pull_length"]))
    below, above = (tablecloth.travel(r.crossover * f, r.L, r.mu, r.g)
                    for f in (1 - 1e-9, 1 + 1e-9))
    assert below == r.L and above == pytest.approx(r.L) and above < r.L
    assert r.bracket == (1.0, 1.6)


def test_friction_pulls_the_dish_toward_the_cloth_s_velocity(tablecloth_pulls):
    """Where the dish slides on the cloth (|v_p - v_s| > 10 eps_v after the step) its speed changes
    by mu g h toward v_s: sped up under the pulled cloth, slowed on the still one (measured to
    1e-5; 1 %: the elastic dish); where it rides along, v_p stays within eps_v of v_s."""
    r = tablecloth_pulls
    epsv, h = simulator.TABLECLOTH["epsv"], simulator.TABLECLOTH["h"]
    for run in r.runs:
        relative = run.v_p[1:] - run.v_s[1:]
        slides = np.abs(relative) > 10 * epsv
        acceleration = np.diff(run.v_p) / h
        assert acceleration[slides] == pytest.approx(-r.mu * r.g * np.sign(relative[slides]),
                                                     rel=0.01)
        assert (acceleration[slides] > 0).any() and (acceleration[slides] < 0).any()
    slow = r.runs[0]
    rides = slow.v_s > 0.0
    assert slow.v_p[rides].max() == pytest.approx(slow.U, abs=epsv)


def test_the_relative_velocity_figure_is_written_whole(tablecloth_pulls, tmp_path, monkeypatch):
    """As `python -m figures relative_velocity` writes it (its numbers: the four pulls)."""
    monkeypatch.setattr(relative_velocity, "compute", lambda: tablecloth_pulls)
    assert cli.main(["relative_velocity", "--out", str(tmp_path)]) == 0
    assert os.listdir(tmp_path) == ["relative_velocity.png"]
    assert is_png((tmp_path / "relative_velocity.png").read_bytes())
    lines = relative_velocity.caption(tablecloth_pulls)
    page = relative_velocity.draw(tablecloth_pulls)
    assert caption_fits(page, lines) and page.surface.get_height() == page_height(2, len(lines))


@pytest.mark.slow
def test_every_pull_of_the_relative_velocity_figure_is_on_the_closed_form(tablecloth_pulls,
                                                                          monkeypatch):
    """The figure's pulls; the four tablecloth_pulls made are taken from it, not made again (a
    pull is a function of its speed alone: the same steps, the same numbers)."""
    made, fresh = {run.U: run for run in tablecloth_pulls.runs}, relative_velocity.pull
    monkeypatch.setattr(relative_velocity, "pull", lambda U: made[U] if U in made else fresh(U))
    r = relative_velocity.compute()
    assert {run.U for run in r.runs} >= set(made)
    assert on_the_closed_form(r)
    assert r.bracket[0] < r.crossover < r.bracket[1]
    assert caption_fits(relative_velocity.draw(r), relative_velocity.caption(r))


def run_cli(*args):
    env = {**os.environ, "SDL_VIDEODRIVER": "dummy"}
    return subprocess.run([sys.executable, "-m", "figures", *args], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=120)


def one_error_line(result, code=2):
    lines = result.stderr.splitlines()
    return result.returncode == code and len(lines) == 1 and lines[0].startswith("figures: error: ")


def test_one_figure_is_written_whole(tmp_path):
    result = run_cli("mollifier", "--out", str(tmp_path / "figs"))
    assert result.returncode == 0, result.stderr
    assert sorted(os.listdir(tmp_path / "figs")) == ["mollifier.png"]   # no temporary left
    assert is_png((tmp_path / "figs" / "mollifier.png").read_bytes())


def test_no_name_means_every_figure_into_a_new_folder():
    assert cli.parse([]) == (list(figures.FIGURES), None)
    assert cli.parse(["fixed_point", "mollifier", "mollifier"])[0] == ["mollifier", "fixed_point"]


def test_bad_input_is_one_line_and_exit_code_2(tmp_path, capsys):
    """As `python -m figures` runs it, and in this process for a bad --out."""
    assert one_error_line(run_cli("no_such_figure", "--out", str(tmp_path)))
    (tmp_path / "a_file").write_text("x")
    for out in (tmp_path / "a_file" / "figs", tmp_path / "a_file"):
        assert cli.main(["mollifier", "--out", str(out)]) == 2
        error = capsys.readouterr().err.splitlines()
        assert len(error) == 1 and error[0].startswith("figures: error: ")
    assert os.listdir(tmp_path) == ["a_file"] and (tmp_path / "a_file").read_text() == "x"


def test_a_folder_that_holds_anything_is_refused_and_left_as_it_is(tmp_path, capsys):
    """--out names a new or empty folder: one that holds a file, a link or a folder is refused
    whole, before anything is computed."""
    (tmp_path / "precious.png").write_bytes(b"not ours")
    os.symlink(tmp_path / "precious.png", tmp_path / "mollifier.png")
    before = sorted(os.listdir(tmp_path))
    assert cli.main(["mollifier", "--out", str(tmp_path)]) == 2
    error = capsys.readouterr().err
    assert error.startswith(f"figures: error: out folder {str(tmp_path)!r} is not empty"), error
    assert sorted(os.listdir(tmp_path)) == before
    assert (tmp_path / "precious.png").read_bytes() == b"not ours"


def test_ctrl_c_ends_in_one_line_with_130(tmp_path, capsys, monkeypatch):
    """The line names the folder and what it holds (it said only 'the figures written so far are
    whole', the folder left unnamed)."""
    def interrupted():
        os.kill(os.getpid(), signal.SIGINT)
    monkeypatch.setattr(mollifier, "compute", interrupted)
    assert cli.main(["mollifier", "--out", str(tmp_path)]) == 130
    said = capsys.readouterr().err
    assert said == f"figures: stopped: interrupted; nothing written in {tmp_path}/\n"
    assert os.listdir(tmp_path) == []


def test_a_signal_whose_raise_an_import_dropped_stops_before_the_compute(tmp_path, capsys,
                                                                         monkeypatch):
    """The figure's import drops the handler's raise (DropsTheHandlersRaise's __del__): 130 and
    one line before its compute, not after it (a figure's compute takes up to a minute)."""
    real, imports = cli.importlib.import_module, []

    def import_module(name):
        if not imports:
            DropsTheHandlersRaise(signal.SIGINT)    # made and deleted at once: __del__ runs
        imports.append(name)
        return real(name)
    monkeypatch.setattr(cli.importlib, "import_module", import_module)
    monkeypatch.setattr(mollifier, "compute", lambda: pytest.fail("computed"))
    assert cli.main(["mollifier", "--out", str(tmp_path)]) == 130
    assert capsys.readouterr().err.count("\n") == 1 and os.listdir(tmp_path) == []


def test_ctrl_c_as_a_full_disk_is_said_waits(tmp_path, capsys, monkeypatch):
    """The error's line and exit code 1 (the Stopped the handler raised in that line's making
    escaped main, a traceback)."""
    class Full(OSError):
        def __str__(self):
            os.kill(os.getpid(), signal.SIGINT)
            return "No space left on device"

    def full(result):
        raise Full()
    monkeypatch.setattr(mollifier, "compute", lambda: None)
    monkeypatch.setattr(mollifier, "draw", full)
    assert cli.main(["mollifier", "--out", str(tmp_path)]) == 1
    assert capsys.readouterr().err == (f"figures: error: cannot write {tmp_path}: No space left "
                                       f"on device\n")


def test_a_full_disk_is_said_as_simulator_says_it(tmp_path, capsys, monkeypatch):
    """errno 28 on the PNG: 'cannot write <file>: No space left on device', one line, exit 1,
    in simulator.py's words (files.cannot_write), not the raw '[Errno 28] ...'."""
    def full(path, data):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), path)
    monkeypatch.setattr(mollifier, "compute", lambda: None)
    monkeypatch.setattr(mollifier, "draw", lambda _: types.SimpleNamespace(png=lambda: b"png"))
    monkeypatch.setattr(whole_files, "write_temporary", full)
    assert cli.main(["mollifier", "--out", str(tmp_path)]) == 1
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith(f"figures: error: cannot write {tmp_path}/"), err
    assert err[0].endswith(": No space left on device") and "Errno" not in err[0], err


def test_ctrl_c_while_writing_lands_after_the_file_is_whole(tmp_path, capsys, monkeypatch):
    """A real SIGINT sent while the PNG is being written is held until the rename: the file is
    whole, no temporary file is left, and the run then ends with 130."""
    real = whole_files.write_temporary

    def write_interrupted(path, data):
        if path.endswith("-mollifier.png"):
            os.kill(os.getpid(), signal.SIGINT)
        return real(path, data)
    monkeypatch.setattr(whole_files, "write_temporary", write_interrupted)
    assert cli.main(["mollifier", "--out", str(tmp_path)]) == 130
    said = capsys.readouterr().err
    assert said == f"figures: stopped: interrupted; 1 figure kept in {tmp_path}/\n"
    assert sorted(os.listdir(tmp_path)) == ["mollifier.png"]
    assert is_png((tmp_path / "mollifier.png").read_bytes())


def test_each_run_writes_a_new_folder_of_its_own(tmp_path, monkeypatch, capsys):
    """Without --out, each run makes output/figures-<date>-<time>/ (a suffix where that is
    taken): two runs, two folders, and a file the user left in output/ untouched. fixed_point's
    numbers are stubbed here: only the files are under test."""
    class Stub:
        def png(self):
            return b"a stub page"
    monkeypatch.setattr(fixed_point, "compute", lambda: None)
    monkeypatch.setattr(fixed_point, "draw", lambda result: Stub())
    monkeypatch.chdir(tmp_path)
    (tmp_path / "output").mkdir()
    (tmp_path / "output" / "notes.txt").write_text("mine")
    assert cli.main(["fixed_point"]) == 0 and cli.main(["fixed_point"]) == 0
    runs = sorted(p for p in (tmp_path / "output").iterdir() if p.is_dir())
    assert len(runs) == 2 and all(re.fullmatch(r"figures-\d{8}-\d{6}(-\d+)?", p.name) for p in runs)
    assert all(os.listdir(p) == ["fixed_point.png"] for p in runs)
    assert (tmp_path / "output" / "notes.txt").read_text() == "mine"
    out = capsys.readouterr().out.splitlines()
    said = [line for line in out if line.startswith("figures: wrote")]
    assert [line.split()[2] for line in said] == [str(p.relative_to(tmp_path) / "fixed_point.png")
                                                  for p in runs]
