"""Stick-slip, counted on the chalk's tip: the one definition that a chalk run's closing line, its page,
plots.png and summary.png (viewer/command/progress.py, page.py, plots.py, summary.py), the stick-slip figure
(figures/stick_slip.py) and the chalk's tests (tests/scenes/test_chalk.py) all count with.

At each state the tip is stuck where its tangential speed |u| is below eps_v (the static branch of the
mollifier f1), slipping elsewhere. Once the hand drives (t > start), a stick-slip cycle is

- a stick: the tip stuck at every state for at least MIN_STICK steps, then
- a slip: the tip slipping, with a peak speed above the drive's, that ends before the run does (a stick
  follows; a slip the run ends in has no length yet and is not counted).

A cycle's length is the tip's travel from the stick's last state to the slip's last, its time the slip's
first state; the period is the mean time between the slips' starts. A run's states are those it kept:
every step up to recording.MAX_SAMPLES (100 s of the chalk), fewer after; a stick's steps are counted
from its first state to its last (`steps`).
"""
from dataclasses import dataclass

import numpy as np

MIN_STICK = 10          # steps (10 ms at the chalk's h): a shorter stick is not counted as one


@dataclass
class StickSlip:
    """What a run's tip did once the hand drove: its cycles, as (the slip's start time (s), its length (m),
    its peak speed (m/s)); their mean period (s, nan without two), mean length (m) and largest peak (m/s;
    nan without a cycle); the fraction of the driven states stuck (nan without one); the start-up, the
    time of the first slipping state once the hand drives (None if the tip never slips), with the states
    from it on (`after`) and how many of them are stuck (`stuck_after`); the time the drive starts and
    the run's last time."""
    slips: list
    period: float
    length: float
    peak: float
    stuck: float
    start_up: float
    stuck_after: int
    after: int
    start: float
    t_end: float

    @property
    def driven(self):
        """Whether the run went on past the drive's start."""
        return self.t_end > self.start


def runs(stuck):
    """The state indices split into runs of one kind, all stuck or all slipping, in order."""
    return np.split(np.arange(len(stuck)), np.flatnonzero(np.diff(np.asarray(stuck).astype(int))) + 1)


def cycles(t, x, u, epsv, drive, start, steps=None):
    """The stick-slip cycles after `start` (s), as (start time, length, peak speed): states at times t (s)
    with the tip's position x along the board (m) and its velocity or speed u along it (m/s), eps_v and
    the drive's speed (m/s); `steps`, each state's step number (consecutive if not given)."""
    t, x, speed = np.asarray(t, float), np.asarray(x, float), np.abs(np.asarray(u, float))
    steps = np.arange(len(t)) if steps is None else np.asarray(steps)
    driven = t > start
    t, x, speed, steps = t[driven], x[driven], speed[driven], steps[driven]
    stuck = speed < epsv
    parts, slips = runs(stuck), []
    for stick, slip, _ in zip(parts, parts[1:], parts[2:]):         # a third part: the slip has ended
        if stuck[stick[0]] and steps[stick[-1]] - steps[stick[0]] + 1 >= MIN_STICK and speed[slip].max() > drive:
            slips.append((float(t[slip[0]]), float(x[slip[-1]] - x[stick[-1]]), float(speed[slip].max())))
    return slips


def measure(t, x, u, epsv, drive, start, steps=None):
    """A run's StickSlip: its cycles (as `cycles`, the same arguments) and what they add up to."""
    t, speed = np.asarray(t, float), np.abs(np.asarray(u, float))
    slips = cycles(t, x, u, epsv, drive, start, steps)
    starts, lengths, peaks = (np.array(a) for a in zip(*slips)) if slips else ([np.nan],) * 3
    stuck, driven = speed < epsv, t > start
    moving = np.flatnonzero(driven & ~stuck)
    return StickSlip(slips=slips, period=float(np.mean(np.diff(starts))) if len(slips) > 1 else np.nan,
                     length=float(np.mean(lengths)), peak=float(np.max(peaks)),
                     stuck=float(stuck[driven].mean()) if driven.any() else np.nan,
                     start_up=float(t[moving[0]]) if len(moving) else None,
                     stuck_after=int(stuck[moving[0]:].sum()) if len(moving) else None,
                     after=int(len(t) - moving[0]) if len(moving) else 0,
                     start=float(start), t_end=float(t[-1]) if len(t) else 0.0)


def drive_start(scene):
    """When the chalk's hand starts to drive (s): after pressing and holding."""
    return scene.params["t_press"] + scene.params["t_hold"]


def of_track(track):
    """The StickSlip of a chalk run (recording.Track), from the states it kept: the tip's x and speed
    (log.csv's tip_x, tip_speed), its scene's eps_v and drive."""
    s = track.samples.all()
    scene = track.scene
    return measure([a.t for a in s], [a.tip_x for a in s], [a.tip_speed for a in s], scene.epsv,
                   scene.params["drive"], drive_start(scene), [a.step for a in s])


def words(r):
    """A run's StickSlip in words: 'stick-slip: 25 slips, mean slip 1.06 mm, period 107 ms, tip stuck 86 % of
    the drive' (pushed); 'the tip slid without a stick after its start-up at t = 0.29 s' (dragged); 'the tip
    jammed, stuck throughout the drive'; a run of sticks and slips that makes no cycle, or one that ended
    before the drive started."""
    if not r.driven:
        return f"not driven yet at t = {r.t_end:.2f} s (the hand drives from t = {r.start:g} s)"
    if r.slips:
        n = len(r.slips)
        slips = f"{n} slips, mean slip" if n > 1 else "1 slip, slip"
        period = f", period {1e3 * r.period:.0f} ms" if n > 1 else ""
        return f"stick-slip: {slips} {1e3 * r.length:.2f} mm{period}, tip stuck {100 * r.stuck:.0f} % of the drive"
    if r.start_up is None:
        return "the tip jammed, stuck throughout the drive"
    if r.stuck_after == 0:
        return f"the tip slid without a stick after its start-up at t = {r.start_up:.2f} s"
    return (f"no stick-slip cycle: the tip slid from t = {r.start_up:.2f} s, stuck at {r.stuck_after} of its "
            f"{r.after} states since")


def definition(scene):
    """What the words count, with the scene's numbers, in two lines: when the tip is stuck, what a cycle is."""
    return (f"counted once the hand drives, from t = {drive_start(scene):g} s: the tip is stuck below eps_v = "
            f"{scene.epsv:g} m/s;",
            f"a cycle is a stick of at least {MIN_STICK} steps ({1e3 * MIN_STICK * scene.h:.3g} ms), then a slip "
            f"faster than the drive's {scene.params['drive']:g} m/s")
