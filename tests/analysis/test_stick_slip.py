"""analysis/stick_slip.py: the one count of the chalk's stick-slip cycles, checked on tip histories
built segment by segment, whose cycles are known from how they were built."""
import types

import numpy as np
import pytest

import simulator
from analysis import stick_slip
from figures import stick_slip as figure

H, EPSV, DRIVE, START = 1e-3, 1e-4, 0.01, 0.2
MIN = stick_slip.MIN_STICK


def history(segments, pressing=START):
    """A tip history at every step of H: at rest while the hand presses (to `pressing`, s), then
    `segments`, each (steps, speed) at a constant speed (m/s); x^{n+1} = x^n + h u^{n+1}. Returns
    t, x, u and each segment's first state index."""
    u = [0.0] * (int(round(pressing / H)) + 1)
    firsts = []
    for steps, speed in segments:
        firsts.append(len(u))
        u += [speed] * steps
    u = np.array(u)
    return np.arange(len(u)) * H, np.cumsum(H * u), u, firsts


def cycles(t, x, u, steps=None):
    return stick_slip.measure(t, x, u, EPSV, DRIVE, START, steps).slips


STUCK, FAST, SLOW = 1e-5, 0.1, 0.005      # below eps_v; above the drive; slipping below the drive
SEGMENTS = [(30, STUCK), (5, FAST),            # a cycle
            (30, STUCK), (5, -FAST),           # a cycle, backwards (the speed counts)
            (MIN - 1, STUCK), (5, FAST),       # a stick too short: no cycle
            (30, STUCK), (5, SLOW),            # a slip no faster than the drive: no cycle
            (30, STUCK), (3, 2 * FAST),        # a cycle
            (20, STUCK), (4, FAST)]            # the run ends in this slip: no cycle, no length yet
CYCLES = (1, 3, 9)                             # the slips of SEGMENTS that make a cycle


def test_a_cycle_is_a_long_enough_stick_then_a_slip_faster_than_the_drive_that_ends():
    t, x, u, firsts = history(SEGMENTS)
    expected = []
    for k in CYCLES:
        steps, speed = SEGMENTS[k]
        expected.append((t[firsts[k]], steps * H * speed, abs(speed)))   # start, travel, peak
    assert cycles(t, x, u) == [pytest.approx(e, rel=1e-9, abs=1e-15) for e in expected]
    r = stick_slip.measure(t, x, u, EPSV, DRIVE, START)
    starts = [e[0] for e in expected]
    assert r.period == pytest.approx((starts[-1] - starts[0]) / 2)
    assert r.peak == pytest.approx(2 * FAST)
    assert r.length == pytest.approx(np.mean([e[1] for e in expected]))
    stuck_steps = sum(steps for steps, speed in SEGMENTS if abs(speed) < EPSV)
    assert r.stuck == pytest.approx(stuck_steps / sum(steps for steps, _ in SEGMENTS))
    assert r.start_up == pytest.approx(t[firsts[1]]) and r.after == len(t) - firsts[1]
    assert r.stuck_after == stuck_steps - SEGMENTS[0][0]


def test_a_stick_is_counted_in_the_steps_it_lasted_also_when_the_states_are_thinned():
    """MIN_STICK steps make a stick; a run that kept every 2nd state (recording.History past its
    cap) counts the steps from a stick's first state to its last."""
    for stick, counted in ((MIN, 1), (MIN - 1, 0)):
        t, x, u, _ = history([(stick, STUCK), (6, FAST), (30, STUCK)])
        assert len(cycles(t, x, u)) == counted
    t, x, u, firsts = history([(20, STUCK), (6, FAST), (30, STUCK)])
    last_stuck, steps, outcomes = firsts[1] - 1, np.arange(len(t)), set()
    for first_kept in range(firsts[0], firsts[0] + 14, 2):   # every 2nd state from first_kept on
        kept = np.r_[np.arange(firsts[0]), np.arange(first_kept, len(t), 2)]
        stick = kept[(kept >= firsts[0]) & (kept <= last_stuck)]       # the stick's kept states
        counted = int(stick[-1] - stick[0] + 1 >= MIN)     # the steps from its first to its last
        assert len(cycles(t[kept], x[kept], u[kept], steps[kept])) == counted
        in_states = int(len(stick) >= MIN)                     # without the steps: in states
        assert len(cycles(t[kept], x[kept], u[kept])) == in_states
        outcomes.add(counted)
    assert outcomes == {0, 1}


def test_the_words_say_what_the_tip_did():
    def words(segments, **kw):
        t, x, u, _ = history(segments, **kw)
        return stick_slip.words(stick_slip.measure(t, x, u, EPSV, DRIVE, START))
    t, x, u, _ = history(SEGMENTS)
    r = stick_slip.measure(t, x, u, EPSV, DRIVE, START)
    creeping = f", creeping {1e3 * STUCK:.2g} mm/s"       # every stuck state at STUCK
    assert r.creep_speed == pytest.approx(STUCK)
    assert words(SEGMENTS) == (f"stick-slip: 3 slips, mean slip {1e3 * r.length:.2f} mm, "
                               f"period {1e3 * r.period:.0f} ms, "
                               f"stuck {100 * r.stuck:.0f} % of the drive{creeping}")
    assert words([(30, STUCK), (5, FAST), (30, STUCK)]) == (
        f"stick-slip: 1 slip, slip {5 * H * FAST * 1e3:.2f} mm, "
        f"stuck {100 * 60 / 65:.0f} % of the drive{creeping}")
    start_up = START + 91 * H                  # the first state after the 90 stuck ones
    assert words([(90, STUCK), (500, 0.01)]) == (
        f"the tip slid without a stick after its start-up at t = {start_up:.2f} s")
    assert words([(300, STUCK)]) == "the tip jammed, stuck throughout the drive" + creeping
    assert words([(200, STUCK), (100, -3 * STUCK)]) == (       # stuck both ways: the mean speed
        "the tip jammed, stuck throughout the drive, creeping "
        f"{1e3 * (200 * STUCK + 100 * 3 * STUCK) / 300:.2g} mm/s")
    assert words([(5, STUCK), (5, FAST), (3, STUCK), (50, FAST)]) == (
        f"no stick-slip cycle: the tip slid from t = {START + 6 * H:.2f} s, "
        f"stuck at 3 of its 58 states since{creeping}")
    assert words([], pressing=0.15) == (
        "not driven yet at t = 0.15 s (the hand drives from t = 0.2 s)")


def test_the_short_words_of_a_comparison_say_each_case_within_a_line():
    """stick_slip.short_words: what words says, short enough for a comparison's closing lines."""
    def short(segments, **kw):
        t, x, u, _ = history(segments, **kw)
        return stick_slip.short_words(stick_slip.measure(t, x, u, EPSV, DRIVE, START))
    creeping = f"creeping {1e3 * STUCK:.2g} mm/s"
    r = stick_slip.measure(*history(SEGMENTS)[:3], EPSV, DRIVE, START)
    assert short(SEGMENTS) == f"3 slips of {1e3 * r.length:.2f} mm, {creeping}"
    assert short([(30, STUCK), (5, FAST), (30, STUCK)]) == (
        f"1 slip of {5 * H * FAST * 1e3:.2f} mm, {creeping}")
    assert short([(90, STUCK), (500, 0.01)]) == "slides, no stick"
    assert short([(300, STUCK)]) == f"jammed, {creeping}"
    assert short([(5, STUCK), (5, FAST), (3, STUCK), (50, FAST)]) == f"no cycle, {creeping}"
    assert short([], pressing=0.15) == "not driven yet"


def test_the_definition_has_the_scenes_numbers():
    scene = simulator.build_chalk_scene(h=5e-4, epsv=2e-4)
    first, second = stick_slip.definition(scene)
    p = scene.params
    assert stick_slip.drive_start(scene) == p["t_press"] + p["t_hold"] == 0.2
    assert first == ("counted once the hand drives, from t = 0.2 s: "
                     "the tip is stuck below eps_v = 0.0002 m/s (creeping: mean speed then);")
    assert second == (f"a cycle is a stick of at least {MIN} steps ({MIN * 0.5:g} ms), "
                      "then a slip faster than the drive's 0.01 m/s")


def test_the_figure_counts_with_it():
    """figures/stick_slip.py's measure is this count, with the marks' creep added."""
    t, x, u, _ = history(SEGMENTS)
    scene = types.SimpleNamespace(epsv=EPSV, params={"drive": DRIVE, "k_hand": 2000.0})
    tr = types.SimpleNamespace(scene=scene, t=t, x=x, u=u, stuck=np.abs(u) < EPSV,
                               drive_start=START, tip_lowest=True)
    counted = stick_slip.measure(t, x, u, EPSV, DRIVE, START)._asdict()
    drawn = vars(figure.measure(tr))
    assert {k: drawn[k] for k in counted} == counted and drawn["creep"] > 0
    assert not hasattr(figure, "cycles") and not hasattr(figure, "MIN_STICK")
