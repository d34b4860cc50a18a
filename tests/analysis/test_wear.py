"""The chalk's mark by Archard's law (analysis/wear.py, no pygame here): the deposit of a step, its
bins, its conservation, what the pushed and the dragged chalk leave, and marks.csv.

Archard: the material left per unit length of board is proportional to the normal force times the
length slid there; a bin of 0.1 mm holds sum over steps and contact nodes of lambda_k times the
length of node k's slide within it (N m)."""
import csv
import functools
import os
import subprocess
import sys

import numpy as np
import pytest

import BarrierEnergy
import FrictionEnergy
from analysis import diagnostics, stick_slip, wear

from helpers import ROOT
from helpers.command import run_main

pytestmark = pytest.mark.usefixtures("shared_stepping")   # the runs' steps: helpers/runs.py
W = wear.BIN


def test_a_slide_leaves_lambda_times_its_length_in_each_bin_it_crosses():
    """A node sliding from 0.05 to 0.3 mm under 2 N: 0.05 mm of it in bin 0, 0.1 mm in bins 1 and 2
    (whole), none in bin 3 (it stops at its edge); backwards, the same; one that does not move, or
    is off the board (lambda 0), leaves nothing."""
    j0, d = wear.archard([0.5 * W], [3 * W], [2.0])
    assert j0 == 0 and d[:3] == pytest.approx([2.0 * 0.5 * W, 2.0 * W, 2.0 * W], rel=1e-12)
    assert np.abs(d[3:]).max(initial=0.0) < 1e-18
    back = wear.archard([3 * W], [0.5 * W], [2.0])
    assert back[0] == j0 and back[1] == pytest.approx(d, rel=1e-12, abs=1e-18)
    assert len(wear.archard([W], [W], [2.0])[1]) == 0
    assert len(wear.archard([0.0], [W], [0.0])[1]) == 0


def test_several_nodes_add_up_within_one_call():
    """Three nodes at once, one of them within a single bin and one off the board: each bin holds
    the sum of what each node alone leaves there (no loop over the contacts in archard), and the
    total is sum lambda_k |s1_k - s0_k|, wherever the slides lie (below zero too)."""
    s0, s1 = np.array([-2.5 * W, 1.2 * W, 0.0]), np.array([0.7 * W, 1.7 * W, 5 * W])
    lam = np.array([1.5, 3.0, 0.0])
    j0, d = wear.archard(s0, s1, lam)
    dense = np.zeros(40)
    for k in range(3):
        a, b = wear.archard(s0[k:k + 1], s1[k:k + 1], lam[k:k + 1])
        dense[a + 20:a + 20 + len(b)] += b
    assert j0 == -3 and np.allclose(dense[j0 + 20:j0 + 20 + len(d)], d, rtol=1e-12, atol=1e-18)
    assert d.sum() == pytest.approx((lam * np.abs(s1 - s0)).sum(), rel=1e-12)
    assert d[4] == pytest.approx(3.0 * 0.5 * W, rel=1e-9)      # bin 1: node 1's half bin alone


def test_the_deposit_grows_both_ways_and_keeps_only_the_board_touched():
    """Deposits added left and right of the first, many times: the bins touched hold what a plain
    array would, and only they."""
    mark, dense, rng = wear.Deposit(), np.zeros(4000), np.random.default_rng(5)
    for j0 in np.r_[np.arange(0, 1500, 3), np.arange(0, -1500, -7)]:
        d = rng.random(4)
        mark.add(int(j0), d)
        dense[j0 + 2000:j0 + 2004] += d
    assert mark.first == -1498 and len(mark.values) == 1498 + 1500 + 1
    at = mark.first + 2000
    assert np.array_equal(mark.values, dense[at:at + len(mark.values)])
    assert mark.span() == pytest.approx((-1498 * W, 1501 * W), rel=1e-12)
    assert wear.Deposit().span() is None and wear.Deposit().darkest() == 0.0


@functools.cache
def chalk(chalk_runs, seconds, **params):
    """The chalk stepped for `seconds` (helpers/runs.py): its scene, its mark, the step deposits
    sum_k lambda_k |delta s_k| taken from the barrier's own compute_mu_lambda (mu = 1), and the
    tip's stick-slip (analysis/stick_slip.py)."""
    scene, t, xs, vs = chalk_runs.states(seconds, **params)
    mark, before, tangent = wear.Deposit(), scene.x0, FrictionEnergy.tangent(scene.n)
    tip = int(np.argmin(scene.x0[:, 1]))
    by_hand = []
    for x in xs:
        mark.step(scene, before, x)
        lam = BarrierEnergy.compute_mu_lambda(x, scene.n, scene.o, scene.contact_area, 1.0,
                                              scene.dhat, scene.kappa)
        by_hand.append(float(lam @ np.abs((x - before) @ tangent)))
        before = x
    x_tip, u_tip = np.r_[scene.x0[tip] @ tangent, xs[:, tip] @ tangent], vs[:, tip] @ tangent
    counted = stick_slip.measure(np.r_[0.0, t], x_tip, np.r_[0.0, u_tip], scene.epsv,
                                 scene.params["drive"], stick_slip.drive_start(scene))
    return scene, mark, np.array(by_hand), counted


def test_the_mark_holds_what_the_steps_left_no_more_no_less(chalk_runs):
    """Conservation: over 1.5 s of the pushed chalk the bins sum to the sum over steps and contact
    nodes of lambda_k |delta s_k| (summed in another order: round-off), and no step leaves a
    negative deposit."""
    _, mark, by_hand, _ = chalk(chalk_runs, 1.5)
    assert mark.values.sum() == pytest.approx(by_hand.sum(), rel=1e-12)
    assert (mark.values >= 0).all() and (by_hand >= 0).all() and by_hand.sum() > 0


def test_a_step_handed_its_lambdas_leaves_what_it_leaves_finding_them(chalk_runs):
    """Track.take hands Deposit.step the lambda_k at x^{n+1} that the tip's normal force sums
    (diagnostics.lambdas): the same bins, bit for bit, as steps that find them; and they are the
    barrier's own lambda_k (compute_mu_lambda, mu = 1) up to round-off in n . n."""
    scene, _, xs, _ = chalk_runs.states(1.5)
    found, handed, before = wear.Deposit(), wear.Deposit(), scene.x0
    for x in xs:
        lam = diagnostics.lambdas(scene, x)
        assert found.step(scene, before, x) == handed.step(scene, before, x, lam)
        assert lam == pytest.approx(BarrierEnergy.compute_mu_lambda(
            x, scene.n, scene.o, scene.contact_area, 1.0, scene.dhat, scene.kappa), rel=1e-12)
        before = x
    assert (found.first, found.values.tobytes()) == (handed.first, handed.values.tobytes())
    assert found.values.sum() > 0


def test_pushed_a_sawtooth_of_dashes_a_slip_apart_each_fading_from_where_its_slip_starts(
        chalk_runs):
    """The pushed chalk, 1.5 s: a dash per slip (RISE: the deposit more than doubles from one bin to
    the next where a slip starts), the dashes a slip length apart (within a bin); each darkest where
    it starts and fading bin by bin to its faintest, where the next begins. The normal force falls
    about 9-fold over a slip (2.27 to 0.24 N, docs/chalk.md), a bin holds lambda times 0.1 mm, and
    the faintest bin holds the slip's end and the stick's creep, wherever in the bin the slip ended:
    so each dash is at least 5 times darker than its faintest bin (measured 5.1 to 7.0, median 6.4);
    the bound, 4.5, leaves room for slips that end elsewhere in their bins. p90 / p10 is 4.68:
    above 4."""
    _, mark, _, counted = chalk(chalk_runs, 1.5)
    v = mark.values
    dashes = wear.dashes(v)
    assert len(dashes) >= len(counted.slips) - 1 >= 9
    starts = np.array([a for a, _, _ in dashes])
    assert np.diff(starts) * W == pytest.approx(counted.length, abs=W)
    contrast = np.array([dark / faint for _, dark, faint in dashes])
    assert contrast.min() >= 4.5 and np.median(contrast) >= 5.5
    for (a, dark, faint), b in zip(dashes, np.r_[starts[1:], len(v)]):
        peak, low = a + int(np.argmax(v[a:b])), a + int(np.argmin(v[a:b]))
        assert peak <= a + 1 and (np.diff(v[peak:low + 1]) < 0).all()    # darkest first, fading
    p10, p90 = np.percentile(v[1:-1], (10, 90))
    assert p90 / p10 > 4.0


def test_dragged_a_uniform_line_without_a_dash(chalk_runs):
    """The dragged chalk slides at the drive's speed under a steady normal force: no dash, and every
    bin inside its mark within 5 % of their median (measured: 2.8 %, the bin after the press's spot,
    where the slide started; the rest within 1e-6)."""
    _, mark, by_hand, counted = chalk(chalk_runs, 1.5, drag=True)
    v = mark.values[1:-1]
    assert wear.dashes(mark.values) == [] and counted.slips == []
    assert np.abs(v / np.median(v) - 1).max() < 0.05
    assert mark.values.sum() == pytest.approx(by_hand.sum(), rel=1e-12)


def simulate(*args):
    """`python simulator.py --scene chalk --no-frames ARGS`, in this process: (exit code, the
    lines it printed)."""
    return run_main("--scene", "chalk", "--no-frames", *args)


def test_a_chalk_run_writes_its_mark_as_marks_csv(tmp_path, chalk_runs):
    """`--scene chalk` writes marks.csv: board position (mm, each bin's middle) and the deposit of
    the bin in N m, as the header says; the rows are the run's mark (the same steps as
    simulator.simulate's), 0.1 mm apart; a comparison writes one per run, named by its tag."""
    out = tmp_path / "rün 1"
    code, lines = simulate("--steps", "300", "--out", str(out))
    assert code == 0, lines
    assert lines[-1] == f"wrote 4 files in {out}/"                        # log, marks, 2 PNGs
    assert sorted(os.listdir(out)) == ["log.csv", "marks.csv", "plots.png", "summary.png"]
    with open(out / "marks.csv", newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["x_mm", "deposit_N_m_per_0.1_mm"]
    x, d = np.array(rows[1:], float).T
    _, mark, _, _ = chalk(chalk_runs, 0.3)
    assert x == pytest.approx(1e3 * mark.centres(), abs=5e-3)
    assert np.diff(x) == pytest.approx(0.1, abs=1e-9)
    assert d == pytest.approx(mark.values, rel=1e-12, abs=0)
    code, lines = simulate("--steps", "30", "--grip", "1000,2000", "--out", str(tmp_path / "two"))
    assert code == 0, lines
    assert {"marks_grip1000.csv", "marks_grip2000.csv"} <= set(os.listdir(tmp_path / "two"))


def test_the_mark_is_computed_without_pygame():
    """The deposit, its dashes and marks.csv need no pygame: importing analysis.wear (and a run's
    recording) loads none, so the analysis runs where pygame is not installed."""
    code = "import sys, analysis.wear, viewer.command.recording; print('pygame' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True,
                          timeout=120, check=False)
    assert done.returncode == 0 and done.stdout.split() == ["False"], done.stderr
