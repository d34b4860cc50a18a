"""Stick-slip, counted on the chalk's tip: the one count that the closing line, the page, the
pictures, the figure and the chalk's tests use (docs/output.md says what it counts)."""
from collections import namedtuple

import numpy as np

MIN_STICK = 10          # steps (10 ms at the chalk's h): a shorter stick is not counted as one

# A run's tip once the hand drove: cycles (start time s, length m, peak speed m/s), their mean
# period, length and largest peak (nan without them), the fraction of driven states stuck, the
# tip's mean speed along the board over them (`creep_speed`, m/s: a stuck tip still creeps; nan
# without them), the first slipping time `start_up` (None: never), the states from it (`after`)
# and how many stuck, the drive's start, the run's last time, whether the run went on past the
# start (`driven`).
StickSlip = namedtuple("StickSlip", "slips period length peak stuck creep_speed start_up "
                       "stuck_after after start t_end driven")


def runs(stuck):
    """The state indices split into runs of one kind, all stuck or all slipping, in order."""
    return np.split(np.arange(len(stuck)), np.flatnonzero(np.diff(np.asarray(stuck, int))) + 1)


def measure(t, x, u, epsv, drive, start, steps=None):
    """A run's StickSlip from its tip's states: times t, position x and velocity u along the
    board, eps_v, the drive's speed and start; `steps`, each state's step (default 0, 1, ...). A
    cycle: a stick of MIN_STICK steps or more (|u| < eps_v), then a slip faster than the drive that
    ends before the run; its length, the travel from the stick's last state to the slip's."""
    steps = np.arange(len(t)) if steps is None else np.asarray(steps)
    t, x, speed = np.asarray(t, float), np.asarray(x, float), np.abs(np.asarray(u, float))
    stuck, driven = speed < epsv, t > start
    parts = [np.flatnonzero(driven)[part] for part in runs(stuck[driven])]    # driven states
    slips = []
    for stick, slip, _ in zip(parts, parts[1:], parts[2:]):     # a third part: the slip has ended
        long_enough = steps[stick[-1]] - steps[stick[0]] + 1 >= MIN_STICK
        if stuck[stick[0]] and long_enough and speed[slip].max() > drive:
            slips.append((float(t[slip[0]]), float(x[slip[-1]] - x[stick[-1]]),
                          float(speed[slip].max())))
    starts, lengths, peaks = (np.array(a) for a in zip(*slips)) if slips else ([np.nan],) * 3
    moving, held = np.flatnonzero(driven & ~stuck), stuck & driven
    first = moving[0] if len(moving) else None
    period = float(np.mean(np.diff(starts))) if len(slips) > 1 else np.nan
    t_end = float(t[-1]) if len(t) else 0.0
    return StickSlip(slips=slips, period=period,
                     length=float(np.mean(lengths)), peak=float(np.max(peaks)),
                     stuck=float(stuck[driven].mean()) if driven.any() else np.nan,
                     creep_speed=float(speed[held].mean()) if held.any() else np.nan,
                     start_up=None if first is None else float(t[first]),
                     stuck_after=None if first is None else int(stuck[first:].sum()),
                     after=0 if first is None else int(len(t) - first),
                     start=float(start), t_end=t_end, driven=t_end > start)


def drive_start(scene):
    """When the chalk's hand starts to drive (s): after pressing and holding."""
    return scene.params["t_press"] + scene.params["t_hold"]


def of_track(track):
    """The StickSlip of a chalk run (recording.Track), from the states it kept."""
    s, scene = track.samples.all(), track.scene
    return measure([a.t for a in s], [a.tip_x for a in s], [a.tip_speed for a in s], scene.epsv,
                   scene.params["drive"], drive_start(scene), [a.step for a in s])


def words(r):
    """A StickSlip in words: 'stick-slip: 25 slips, mean slip 1.06 mm, period 107 ms, stuck
    86 % of the drive, creeping 0.067 mm/s', or that the tip slid without a stick, jammed, made no
    cycle, or waits."""
    creeping = f", creeping {1e3 * r.creep_speed:.2g} mm/s"
    if not r.driven:
        return f"not driven yet at t = {r.t_end:.2f} s (the hand drives from t = {r.start:g} s)"
    if r.slips:
        n = len(r.slips)
        slips = f"{n} slips, mean slip" if n > 1 else "1 slip, slip"
        period = f", period {1e3 * r.period:.0f} ms" if n > 1 else ""
        return (f"stick-slip: {slips} {1e3 * r.length:.2f} mm{period}, "
                f"stuck {100 * r.stuck:.0f} % of the drive{creeping}")
    if r.start_up is None:
        return "the tip jammed, stuck throughout the drive" + creeping
    if r.stuck_after == 0:
        return f"the tip slid without a stick after its start-up at t = {r.start_up:.2f} s"
    return (f"no stick-slip cycle: the tip slid from t = {r.start_up:.2f} s, "
            f"stuck at {r.stuck_after} of its {r.after} states since{creeping}")


def short_words(r):
    """words(r) short enough for a comparison's closing: '25 slips of 1.06 mm, creeping 0.067
    mm/s', 'slides, no stick' (after its start-up), 'jammed, creeping ...', 'no cycle, creeping
    ...', 'not driven yet'."""
    creeping = f"creeping {1e3 * r.creep_speed:.2g} mm/s"
    if not r.driven:
        return "not driven yet"
    if r.slips:
        n = len(r.slips)
        return f"{n} slip{'s' * (n > 1)} of {1e3 * r.length:.2f} mm, {creeping}"
    if r.start_up is None:
        return f"jammed, {creeping}"
    if r.stuck_after == 0:
        return "slides, no stick"
    return f"no cycle, {creeping}"


def definition(scene):
    """What the words count, in two lines: when the tip is stuck, its creep, what a cycle is."""
    return (f"counted once the hand drives, from t = {drive_start(scene):g} s: "
            f"the tip is stuck below eps_v = {scene.epsv:g} m/s (creeping: mean speed then);",
            f"a cycle is a stick of at least {MIN_STICK} steps "
            f"({1e3 * MIN_STICK * scene.h:.3g} ms), "
            f"then a slip faster than the drive's {scene.params['drive']:g} m/s")
