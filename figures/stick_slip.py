"""Slide "Remarks – Stick-Slip Instability Effect": Rabinowicz's chalk (simulator.CHALK, static
mu_s 0.5 above the kinetic mu 0.35). Pushed, it sticks and slips and leaves a dashed line; dragged,
a smooth one; "the more tightly the chalk is held, the smaller the distance of slip". With one
coefficient it slides below a rigid strut's self-locking angle 90 deg - atan mu and jams above.
The tip is the chalk's lowest node; its cycles are analysis/stick_slip.py's, its mark
analysis/wear.py's. Each run stops before the hand passes over the tip (docs/chalk.md)."""
import math
from itertools import pairwise
from types import SimpleNamespace

import numpy as np

import FrictionEnergy
import simulator
from analysis import stick_slip as counting
from analysis import wear
from figures.page import BLACK, GREY, RED, Page
from viewer.pictures import marks, plots
from viewer.pictures.draw import BLUE, run_color

DURATION = 1.5              # s, the pushed and the dragged chalk and each grip
GRIPS = (1000.0, 2000.0, 4000.0, 8000.0)            # k_hand, N/m, each at the default's press force
TILTS = (60.0, 64.0, 66.0, 67.0, 68.0, 71.0, 75.0)  # degrees, with one coefficient mu_s = mu
TILT_DURATION = 1.0         # s: the hand moves 8 mm
STUCK, SLIPPING = RED, BLUE
MARK_HEIGHT, PROFILE_HEIGHT = 0.3, 0.4      # of a row (1 apart) in the marks' panel: grey, curve


def track(duration, **params):
    """simulator.build_chalk_scene(**params) run for `duration` s, sampled at t = 0 and each step:
    t, the tip's x and velocity u along the board, stuck = |u| < eps_v, the hand's displacement,
    drive_start, whether the tip stayed the lowest node (`tip_lowest`), its mark (wear.Deposit)."""
    scene = simulator.build_chalk_scene(**params)
    records = list(simulator.simulate(scene, round(duration / scene.h)))
    t = np.array([0.0] + [record.t for record in records])
    x = np.stack([scene.x0] + [record.x for record in records])
    v = np.stack([scene.v0] + [record.v for record in records])
    tip, tangent = int(np.argmin(scene.x0[:, 1])), FrictionEnergy.tangent(scene.n)
    mark = wear.Deposit()
    for before, after in pairwise(x):
        mark.step(scene, before, after)
    u = v[:, tip] @ tangent
    return SimpleNamespace(scene=scene, t=t, x=x[:, tip] @ tangent, u=u,
                           stuck=np.abs(u) < scene.epsv,
                           hand=np.array([scene.hand.displacement(s) @ tangent for s in t]),
                           drive_start=counting.drive_start(scene),
                           tip_lowest=bool(np.all(np.argmin(x[:, :, 1], axis=1) == tip)), mark=mark)


def measure(tr):
    """counting.measure of a track with its k_hand and tip_lowest, and `creep`: the tip's largest
    travel over a run of stuck states, from the state before it (m)."""
    p = tr.scene.params
    counted = counting.measure(tr.t, tr.x, tr.u, tr.scene.epsv, p["drive"], tr.drive_start)
    sticks = [tr.x[max(r[0] - 1, 0):r[-1] + 1] for r in counting.runs(tr.stuck) if tr.stuck[r[0]]]
    return SimpleNamespace(**counted._asdict(), creep=max((np.ptp(x) for x in sticks), default=0.0),
                           k_hand=p["k_hand"], tip_lowest=tr.tip_lowest)


def mark_figures(tr):
    """A run's mark: its dashes' contrasts (darkest over faintest bin, wear.dashes), p10 and p90 of
    its bins but the end ones (slid only partly across)."""
    p10, p90 = np.percentile(tr.mark.values[1:-1], (10, 90))
    contrast = [dark / faint for _, dark, faint in wear.dashes(tr.mark.values)]
    return SimpleNamespace(dashes=np.array(contrast), p10=float(p10), p90=float(p90))


def one_coefficient(tilt, duration):
    """The pushed chalk at `tilt` (deg) with mu_s = mu: the tip's and the hand's travel from the
    drive's start (m), and `jams`: the tip stuck through the drive's second half."""
    tr = track(duration, mu_s=simulator.CHALK["mu"], tilt=tilt)
    start = int(np.searchsorted(tr.t, tr.drive_start))
    late = tr.t >= (tr.drive_start + tr.t[-1]) / 2
    return SimpleNamespace(tilt=tilt, travel=float(tr.x[-1] - tr.x[start]),
                           hand_travel=float(tr.hand[-1] - tr.hand[start]),
                           jams=bool(tr.stuck[late].all()), tip_lowest=tr.tip_lowest)


def bracket(tilts):
    """(the largest tilt that slides, the smallest that jams) if every sliding tilt is below every
    jamming one; else None."""
    slides, jams = [r.tilt for r in tilts if not r.jams], [r.tilt for r in tilts if r.jams]
    return (max(slides), min(jams)) if slides and jams and max(slides) < min(jams) else None


def compute(duration=DURATION, grips=GRIPS, tilts=TILTS, tilt_duration=TILT_DURATION):
    """The chalk pushed and dragged; pushed at each grip k_hand at the default's press force
    k_hand * press; with one coefficient at each tilt, and the self-locking angle 90 - atan mu."""
    chalk = simulator.CHALK
    pushed, dragged = track(duration), track(duration, drag=True)
    force = chalk["k_hand"] * chalk["press"]                # N per held node
    grip_runs = [measure(pushed if k == chalk["k_hand"] else
                         track(duration, k_hand=k, press=force / k)) for k in grips]
    tilt_runs = [one_coefficient(tilt, tilt_duration) for tilt in tilts]
    return SimpleNamespace(pushed=pushed, dragged=dragged, push=measure(pushed),
                           drag=measure(dragged), push_mark=mark_figures(pushed),
                           drag_mark=mark_figures(dragged), force=force, grips=grip_runs,
                           tilts=tilt_runs, bracket=bracket(tilt_runs),
                           lock=90.0 - math.degrees(math.atan(chalk["mu"])), duration=duration,
                           tilt_duration=tilt_duration)


def falls(r):
    """Whether the slip length falls at every tighter grip."""
    return all(a.length > b.length for a, b in zip(r.grips, r.grips[1:]))


def mark_words(m):
    """A mark's figures in words, two lines' worth: its dashes, its bins' spread."""
    spread = f"p90/p10 {m.p90 / m.p10:.2f}" if m.p10 > 0 else "bare board among its bins"
    if not len(m.dashes):
        return "Its mark: no dash,", f"{spread}: a continuous line."
    return (f"Its mark: {len(m.dashes)} dashes, each darkest where its slip",
            f"starts, {m.dashes.min():.1f} to {m.dashes.max():.1f} x its faintest 0.1 mm, where "
            f"it fades before the next ({spread}): a dashed line.")


def caption(r):
    """The scene, then what each panel measured."""
    p, push, drag, grips = r.pushed.scene.params, r.push, r.drag, r.grips
    slides = ", ".join(f"{t.tilt:g}" for t in r.tilts if not t.jams) or "none"
    jams = ", ".join(f"{t.tilt:g}" for t in r.tilts if t.jams) or "none"
    catch_up = 1e3 * p["drive"] * push.period

    def each(figure):
        return " / ".join(figure(g) for g in grips)
    lines = [
        f"The chalk: mu_s {p['mu_s']:g} > mu {p['mu']:g} (v_c {p['v_c']:g} m/s), k_hand "
        f"{p['k_hand']:g} N/m, tilt {p['tilt']:g} deg; the hand drives at {p['drive']:g} m/s "
        f"from {r.pushed.drive_start:g} s.",
        f"Stuck: the tip's tangential speed below eps_v = {p['epsv']:g} m/s (it creeps at most "
        f"{1e6 * max(push.creep, drag.creep):.2g} um while stuck).",
        "Its mark, by Archard's law: the normal force times the length slid, per 0.1 mm of board "
        "(N m); grey,",
        "    black at each chalk's darkest 0.1 mm.",
        f"Pushed, {r.duration:g} s: {len(push.slips)} cycles, period {1e3 * push.period:.0f} ms, "
        f"slip {1e3 * push.length:.2f} mm (the hand's travel in a period {catch_up:.2f} mm),",
        f"    peak tip speed {push.peak:.3g} m/s, stuck {100 * push.stuck:.0f} % of the drive. "
        + mark_words(r.push_mark)[0],
        "    " + mark_words(r.push_mark)[1],
        f"Dragged: stuck until it starts at {drag.start_up:.3g} s, then stuck in "
        f"{drag.stuck_after} of its {drag.after} steps." if drag.start_up is not None
        else "Dragged: the tip never starts.",
        "    " + " ".join(mark_words(r.drag_mark)),
        f"Grip, at the same press force {r.force:g} N per held node: k_hand "
        f"{each(lambda g: f'{g.k_hand:g}')} N/m:",
        f"    slip {each(lambda g: f'{1e3 * g.length:.2f}')} mm, "
        f"{each(lambda g: str(len(g.slips)))} cycles in {r.duration:g} s: "
        + ("the tighter the grip, the shorter the slip." if falls(r)
           else "not shorter at every tighter grip."),
        f"One coefficient, mu_s = mu = {p['mu']:g}, {r.tilt_duration:g} s each; it jams where the "
        "tip stays stuck through the drive's second half:"]
    said = f"    slides at {slides} deg, jams at {jams} deg: "
    if r.bracket is None:
        lines.append(said + "no single tilt separates the two.")
    else:
        low, high = r.bracket
        where = "below" if high <= r.lock else "above" if low >= r.lock else "around"
        lines.append(said + f"between {low:g} and {high:g} deg, {where} the rigid strut's "
                     f"90 - atan mu = {r.lock:.1f} deg.")
    runs = [("pushed", push), ("dragged", drag)]
    runs += [(f"k_hand {g.k_hand:g}", g) for g in grips]
    runs += [(f"tilt {t.tilt:g}", t) for t in r.tilts]
    lost = [name for name, run in runs if not run.tip_lowest]
    if lost:
        lines.append(f"The tip did not stay the lowest node in: {', '.join(lost)}.")
    return lines


def draw_mark(page, ax, mark, y):
    """A mark as grey, MARK_HEIGHT tall about the row y of `ax`: each pixel column the deposit of
    the board under it (wear.Deposit.shade), black at the mark's darkest."""
    mm = (ax.t_max - ax.t_lo) / (plots.RIGHT - plots.LEFT)      # of board per pixel column
    top, bottom = (round(float(ax.px(0.0, y + d)[1])) for d in (MARK_HEIGHT / 2, -MARK_HEIGHT / 2))
    marks.paint_mark(page.pygame, page.surface, mark, lambda s: ax.px(1e3 * s, y)[0],
                     lambda c: 1e-3 * (ax.t_lo + (np.asarray(c, float) - plots.LEFT) * mm), top,
                     bottom - top)


def draw(r):
    """The two chalks' marks, the tip's speed against time, the slip length against the grip, and
    the tip's travel against the tilt with one coefficient."""
    page = Page("Stick-slip: Rabinowicz's chalk pushed and dragged, its grip, and one coefficient",
                4, caption(r))
    chalks = (("pushed", r.pushed, 1.0, run_color(1)), ("dragged", r.dragged, 0.0, run_color(2)))
    spans = np.array([tr.mark.span() for _, tr, _, _ in chalks])
    ax = page.axes(0, 1e3 * spans.max(), -0.3, 1.65, "the mark each chalk leaves (Archard: normal "
                   "force x length slid), along the board (mm)", "x (mm)", "chalk",
                   x_lo=min(0.0, 1e3 * spans.min()), yticks=[(y, name) for name, _, y, _ in chalks])
    ax.legend(BLACK, "grey: the mark")
    ax.note("black: its darkest")
    for name, tr, y, color in chalks:
        draw_mark(page, ax, tr.mark, y)
        profile = y + 0.2 + PROFILE_HEIGHT * tr.mark.values / tr.mark.darkest()
        ax.line(1e3 * tr.mark.centres(), profile, color, 1)
        ax.legend(color, f"{name}, per 0.1 mm")
        ax.note(f"  0 to {tr.mark.darkest():.3g} N m")

    speeds = np.abs(np.concatenate([r.pushed.u, r.dragged.u]))
    epsv, drive = r.pushed.scene.epsv, r.pushed.scene.params["drive"]
    ax = page.axes(1, r.duration, *plots.speed_range(speeds, epsv),
                   "the tip's tangential speed |u| (m/s, log) against time (s)", "t (s)",
                   "|u| (m/s)", log=True)
    for name, tr, _, color in chalks:
        ax.line(tr.t, np.abs(tr.u), color, 3 if name == "dragged" else 1)   # dragged: at the drive
        ax.legend(color, name)
    ax.hline(epsv, STUCK, f"eps_v {epsv:g}: stuck below")
    ax.hline(drive, BLACK, f"the drive, {drive:g} m/s")     # 1 px through the dragged tip's 3
    ax.vline(r.pushed.drive_start, GREY, "the hand starts")

    k = np.array([g.k_hand for g in r.grips])
    lengths = 1e3 * np.array([g.length for g in r.grips])
    catch_up = 1e3 * drive * np.array([g.period for g in r.grips])
    title = "slip length (mm) against the grip k_hand (N/m)"
    ax = page.axes(2, 1.1 * k.max(), 0.0, 1.1 * np.nanmax(np.concatenate([lengths, catch_up])),
                   title + (": the tighter, the shorter" if falls(r) else ""), "k_hand (N/m)",
                   "slip (mm)")
    ax.line(k, lengths, SLIPPING)
    ax.markers(k, catch_up, run_color(1), 8)        # a ring around the slip length where they agree
    ax.markers(k, lengths, SLIPPING, 4)
    ax.legend(SLIPPING, "slip length (mean)")
    ax.legend(run_color(1), "drive x period")

    tilt = np.array([t.tilt for t in r.tilts])
    travel = 1e3 * np.array([t.travel for t in r.tilts])
    jams = np.array([t.jams for t in r.tilts])
    hand = 1e3 * max(t.hand_travel for t in r.tilts)
    ax = page.axes(3, max(tilt.max(), r.lock) + 1.0, min(0.0, travel.min()),
                   max(hand, travel.max()),
                   f"one coefficient (mu_s = mu): the tip's travel (mm) while the hand moves "
                   f"{hand:.2g} mm, against the tilt (deg)", "tilt (deg)", "travel (mm)",
                   x_lo=min(tilt.min(), r.lock) - 1.0)
    ax.hline(hand, BLACK, "the hand's travel")
    ax.vline(r.lock, GREY, f"90 - atan mu = {r.lock:.1f}")
    ax.markers(tilt[~jams], travel[~jams], SLIPPING, 5)
    ax.markers(tilt[jams], travel[jams], STUCK, 5)
    ax.legend(SLIPPING, "slides")
    ax.legend(STUCK, "jams")
    return page
