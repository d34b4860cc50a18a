"""Slide "Remarks – Stick-Slip Instability Effect": Rabinowicz's chalk (Scientific American, 1956). Held at
an obtuse angle to its motion (pushed), it sticks, slips, sticks again and leaves a dashed line; held at
an acute angle (dragged), it draws a smooth one; "the more tightly the chalk is held, the smaller the
distance of slip". The chalk is simulator.build_chalk_scene (simulator.CHALK): a static coefficient mu_s
0.5 above the kinetic mu 0.35, mu lagged from v^n. With one coefficient (mu_s = mu) it does not
stick-slip: pushed below the self-locking angle (a rigid strut's 90 deg - atan mu) it slides with the
hand, above it it jams.

The tip is the chalk's lowest node at the start; at each step it is stuck where its tangential speed is
below eps_v, slipping elsewhere, and its stick-slip cycles are counted as viewer/stick_slip.py defines them
(a run's closing line and the chalk's tests count the same way). Every run stops before the hand passes
over the tip: the chalk stays on the side it started (past vertical, a jammed chalk rests on its other
corner, and with Newton from x^n at tol eps_v / 10 cycles there: issue 28, docs/chalk.md).

Durations: DURATION for the marks and each grip (0.2 s of pressing and holding, then 1.3 s of drive: 9
cycles at the loosest grip, whose period is about 150 ms), TILT_DURATION for each tilt (the hand moves
8 mm: a jammed tip stays stuck, a sliding one follows). The figure's 12 chalk runs take about 27 s on
this project's 2-core machine (`python -m figures stick_slip`, Newton from x_tilde at the chalk's tol
1e-6), under the two minutes issue 28 allows; 3 s runs would double that."""
import math
from types import SimpleNamespace

import numpy as np

import FrictionEnergy
import simulator
from figures.page import BLACK, GREY, RED, Page
from viewer import plots, stick_slip as counting
from viewer.stick_slip import MIN_STICK, runs     # the one definition of a cycle (MIN_STICK: tests read it here)
from viewer.draw import BLUE, run_color

DURATION = 1.5              # s, the pushed and the dragged chalk and each grip
GRIPS = (1000.0, 2000.0, 4000.0, 8000.0)            # k_hand, N/m, each at the default's press force
TILTS = (60.0, 64.0, 66.0, 67.0, 68.0, 71.0, 75.0)  # degrees, with one coefficient mu_s = mu
TILT_DURATION = 1.0         # s
STUCK, SLIPPING = RED, BLUE


def track(duration, **params):
    """The chalk of simulator.build_chalk_scene(**params) stepped for `duration` (s), sampled at t = 0 and
    after each step: t, the tip's x along the board and its tangential speed u (m/s), stuck = |u| < eps_v,
    the hand's displacement along the board, the time the drive starts, and whether the tip stayed the
    lowest node (the one that carries the contact) throughout."""
    scene = simulator.build_chalk_scene(**params)
    tip, tangent = int(np.argmin(scene.x0[:, 1])), FrictionEnergy.tangent(scene.n)
    t, x, u, lowest = [0.0], [scene.x0[tip] @ tangent], [scene.v0[tip] @ tangent], True
    for record in simulator.simulate(scene, round(duration / scene.h)):
        t.append(record.t)
        x.append(record.x[tip] @ tangent)
        u.append(record.v[tip] @ tangent)
        lowest = lowest and int(np.argmin(record.x[:, 1])) == tip
    t, x, u = np.array(t), np.array(x), np.array(u)
    return SimpleNamespace(scene=scene, t=t, x=x, u=u, stuck=np.abs(u) < scene.epsv,
                           hand=np.array([scene.hand.displacement(s) @ tangent for s in t]),
                           drive_start=counting.drive_start(scene), tip_lowest=lowest)


def marks(tr):
    """The marks the tip leaves on the board, one per run of one state: (stuck, the tip's x along it). The
    step from x^n to x^{n+1} = x^n + h v^{n+1} belongs to the state of v^{n+1}, so each run starts at the
    sample before its first: the marks join end to end."""
    return [(bool(tr.stuck[r[0]]), tr.x[max(r[0] - 1, 0):r[-1] + 1]) for r in runs(tr.stuck)]


def measure(tr):
    """What the caption says of a run: viewer.stick_slip's measure of its tip once the hand drives (the cycles,
    their mean period and slip length, the largest peak speed, the fraction stuck, the start-up), and the
    largest creep of a stuck mark (m)."""
    counted = counting.measure(tr.t, tr.x, tr.u, tr.scene.epsv, tr.scene.params["drive"], tr.drive_start)
    return SimpleNamespace(**vars(counted), creep=max((np.ptp(x) for stuck, x in marks(tr) if stuck), default=0.0))


def one_coefficient(tilt, duration):
    """The pushed chalk at `tilt` (degrees) with mu_s = mu: the tip's and the hand's travel from the drive's
    start (m), and whether it jams: the tip stuck at every step of the drive's second half."""
    tr = track(duration, mu_s=simulator.CHALK["mu"], tilt=tilt)
    start = int(np.searchsorted(tr.t, tr.drive_start))
    late = tr.t >= (tr.drive_start + tr.t[-1]) / 2
    return SimpleNamespace(tilt=tilt, travel=float(tr.x[-1] - tr.x[start]),
                           hand_travel=float(tr.hand[-1] - tr.hand[start]), jams=bool(tr.stuck[late].all()),
                           tip_lowest=tr.tip_lowest)


def bracket(tilts):
    """(the largest tilt that slides, the smallest that jams) where every sliding tilt is below every
    jamming one; None otherwise (or if one of the two never happens)."""
    slides, jams = [r.tilt for r in tilts if not r.jams], [r.tilt for r in tilts if r.jams]
    return (max(slides), min(jams)) if slides and jams and max(slides) < min(jams) else None


def compute(duration=DURATION, grips=GRIPS, tilts=TILTS, tilt_duration=TILT_DURATION):
    """The default chalk pushed and dragged; the pushed one at each grip k_hand, its press scaled so the
    press force k_hand * press per held node stays the default's; and with one coefficient at each tilt,
    with the rigid strut's self-locking angle 90 - atan mu and the measured bracket."""
    chalk = simulator.CHALK
    pushed, dragged = track(duration), track(duration, drag=True)
    force = chalk["k_hand"] * chalk["press"]                # N per held node
    grip_runs = []
    for k_hand in grips:
        tr = pushed if k_hand == chalk["k_hand"] else track(duration, k_hand=k_hand, press=force / k_hand)
        grip_runs.append(SimpleNamespace(k_hand=k_hand, tip_lowest=tr.tip_lowest, **vars(measure(tr))))
    tilt_runs = [one_coefficient(tilt, tilt_duration) for tilt in tilts]
    return SimpleNamespace(pushed=pushed, dragged=dragged, push=measure(pushed), drag=measure(dragged), force=force,
                           grips=grip_runs, tilts=tilt_runs, lock=90.0 - math.degrees(math.atan(chalk["mu"])),
                           bracket=bracket(tilt_runs), duration=duration, tilt_duration=tilt_duration)


def falls(r):
    """Whether the slip length falls at every tighter grip (r.grips in the order of k_hand)."""
    return all(a.length > b.length for a, b in zip(r.grips, r.grips[1:]))


def caption(r):
    """The caption's lines: the scene, then what each panel measured."""
    p, push, drag = r.pushed.scene.params, r.push, r.drag
    grips = r.grips
    slides = ", ".join(f"{t.tilt:g}" for t in r.tilts if not t.jams) or "none"
    jams = ", ".join(f"{t.tilt:g}" for t in r.tilts if t.jams) or "none"
    lines = [
        f"The chalk: mu_s {p['mu_s']:g} > mu {p['mu']:g} (v_c {p['v_c']:g} m/s), k_hand {p['k_hand']:g} N/m, tilt "
        f"{p['tilt']:g} deg; the hand drives at {p['drive']:g} m/s from {r.pushed.drive_start:g} s.",
        f"Stuck: the tip's tangential speed below eps_v = {p['epsv']:g} m/s; a stuck mark is a dot (it creeps at "
        f"most {1e6 * max(push.creep, drag.creep):.2g} um).",
        f"Pushed, {r.duration:g} s: {len(push.slips)} cycles, period {1e3 * push.period:.0f} ms, slip "
        f"{1e3 * push.length:.2f} mm (the hand's travel in a period {1e3 * p['drive'] * push.period:.2f} mm),",
        f"    peak tip speed {push.peak:.3g} m/s, stuck {100 * push.stuck:.0f} % of the drive: a dashed line.",
        f"Dragged: stuck until it starts at {drag.start_up:.3g} s, then stuck in {drag.stuck_after} of its "
        f"{drag.after} steps: a continuous line." if drag.start_up is not None
        else "Dragged: the tip never starts.",
        f"Grip, at the same press force {r.force:g} N per held node: k_hand "
        f"{' / '.join(f'{g.k_hand:g}' for g in grips)} N/m:",
        f"    slip {' / '.join(f'{1e3 * g.length:.2f}' for g in grips)} mm, "
        f"{' / '.join(str(len(g.slips)) for g in grips)} cycles in {r.duration:g} s: "
        + ("the tighter the grip, the shorter the slip." if falls(r) else "not shorter at every tighter grip."),
        f"One coefficient, mu_s = mu = {p['mu']:g}, {r.tilt_duration:g} s each; it jams where the tip stays stuck "
        "through the drive's second half:"]
    if r.bracket is not None:
        low, high = r.bracket
        where = "below" if high <= r.lock else "above" if low >= r.lock else "around"
        lines.append(f"    slides at {slides} deg, jams at {jams} deg: between {low:g} and {high:g} deg, {where} "
                     f"the rigid strut's 90 - atan mu = {r.lock:.1f} deg.")
    else:
        lines.append(f"    slides at {slides} deg, jams at {jams} deg: no single tilt separates the two.")
    lost = [name for name, ok in [("pushed", r.pushed.tip_lowest), ("dragged", r.dragged.tip_lowest)]
            + [(f"k_hand {g.k_hand:g}", g.tip_lowest) for g in grips]
            + [(f"tilt {t.tilt:g}", t.tip_lowest) for t in r.tilts] if not ok]
    if lost:
        lines.append(f"The tip did not stay the lowest node in: {', '.join(lost)}.")
    return lines


def draw(r):
    """The marks of the pushed and the dragged chalk, the tip's speed against time, the slip length
    against the grip, and the tip's travel against the tilt with one coefficient."""
    page = Page("Stick-slip: Rabinowicz's chalk pushed and dragged, its grip, and one coefficient", 4, caption(r))
    chalks = (("pushed", r.pushed, 1.0, run_color(1)), ("dragged", r.dragged, 0.0, run_color(2)))
    x = np.concatenate([r.pushed.x, r.dragged.x])
    ax = page.axes(0, 1e3 * x.max(), -0.6, 1.6, "the marks the tip leaves on the board, along it (mm)", "x (mm)",
                   "chalk", x_lo=min(0.0, 1e3 * x.min()), yticks=[(y, name) for name, _, y, _ in chalks])
    for _, tr, y, _ in chalks:
        for stuck, xs in marks(tr):
            if not stuck:
                ax.line(1e3 * xs, np.full(len(xs), y), SLIPPING, 4)
        for stuck, xs in marks(tr):
            if stuck:
                page.markers(ax, 1e3 * np.array([xs.min(), xs.max()]), [y, y], STUCK, 5)
    ax.legend(STUCK, "stuck: |u| < eps_v")
    ax.legend(SLIPPING, "slipping")

    speeds = np.abs(np.concatenate([r.pushed.u, r.dragged.u]))
    epsv, drive = r.pushed.scene.epsv, r.pushed.scene.params["drive"]
    ax = page.axes(1, r.duration, *plots.speed_range(speeds, epsv),
                   "the tip's tangential speed |u| (m/s, log) against time (s)", "t (s)", "|u| (m/s)", log=True)
    for name, tr, _, color in chalks:
        ax.line(tr.t, np.abs(tr.u), color, 1)
        ax.legend(color, name)
    ax.hline(epsv, STUCK, f"eps_v {epsv:g}: stuck below")
    ax.hline(drive, BLACK, f"the drive, {drive:g} m/s")
    ax.vline(r.pushed.drive_start, GREY, "the hand starts")

    k = np.array([g.k_hand for g in r.grips])
    lengths = 1e3 * np.array([g.length for g in r.grips])
    catch_up = 1e3 * drive * np.array([g.period for g in r.grips])
    title = "slip length (mm) against the grip k_hand (N/m)" + (": the tighter, the shorter" if falls(r) else "")
    ax = page.axes(2, 1.1 * k.max(), 0.0, 1.1 * np.nanmax(np.concatenate([lengths, catch_up])), title,
                   "k_hand (N/m)", "slip (mm)")
    ax.line(k, lengths, SLIPPING)
    page.markers(ax, k, catch_up, run_color(1), 8)          # a ring around the slip length where they agree
    page.markers(ax, k, lengths, SLIPPING, 4)
    ax.legend(SLIPPING, "slip length (mean)")
    ax.legend(run_color(1), "drive x period")

    tilt = np.array([t.tilt for t in r.tilts])
    travel = 1e3 * np.array([t.travel for t in r.tilts])
    jams = np.array([t.jams for t in r.tilts])
    hand = 1e3 * max(t.hand_travel for t in r.tilts)
    ax = page.axes(3, max(tilt.max(), r.lock) + 1.0, min(0.0, travel.min()), max(hand, travel.max()),
                   f"one coefficient (mu_s = mu): the tip's travel (mm) while the hand moves {hand:.2g} mm, "
                   "against the tilt (deg)",
                   "tilt (deg)", "travel (mm)", x_lo=min(tilt.min(), r.lock) - 1.0)
    ax.hline(hand, BLACK, "the hand's travel")
    ax.vline(r.lock, GREY, f"90 - atan mu = {r.lock:.1f}")
    page.markers(ax, tilt[~jams], travel[~jams], SLIPPING, 5)
    page.markers(ax, tilt[jams], travel[jams], STUCK, 5)
    ax.legend(SLIPPING, "slides")
    ax.legend(STUCK, "jams")
    return page
