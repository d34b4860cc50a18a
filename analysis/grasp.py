"""What a grasp showed, in words: held (its creep measured beside u*), dropped (its slip
acceleration measured beside (g + a) - 2 mu N / m), or, where the run ended first, still slipping;
from its slip at every kept state."""
import math

import numpy as np

import closed_forms

SETTLE = 0.05       # s left out of a fit after a phase of the lift begins (the springs take it up)


def phases(scene):
    """The lift's phases: (words, start, end, acceleration a), still, accelerating, steady."""
    f = scene.pushed
    t_a = f.t_lift + f.lift_speed / f.lift_accel
    return [("before the lift", 0.0, f.t_lift, 0.0),
            ("while the lift accelerates", f.t_lift, t_a, f.lift_accel),
            ("in the steady lift", t_a, math.inf, 0.0)]


def phase_at(scene, t):
    """The phase (phases) time t falls in."""
    return next(p for p in phases(scene) if p[1] <= t < p[2])


def fit_window(t, start, end):
    """The times in [start + SETTLE, end], or the last half of [start, end] where that holds fewer
    than 4 states (a short run)."""
    window = (t >= start + SETTLE - 1e-9) & (t <= end + 1e-9)
    return window if window.sum() >= 4 else (t >= (start + end) / 2 - 1e-9) & (t <= end + 1e-9)


def outcome(scene, t, slip):
    """(held, t_drop, phase words, measured, closed form): a block on the pads at the end, its slip
    speed (m/s) in the phase the run ends in beside the creep u* (held where it is below eps_v,
    else still slipping); a dropped one's slip acceleration (m/s^2) in the phase it slid past the
    pads in; t_drop None where not dropped; measured nan where too few states."""
    dropped = np.flatnonzero(slip >= closed_forms.grasp_drop_slip(scene))
    end = float(t[dropped[0]]) if dropped.size else float(t[-1])
    words, start, _, a = phase_at(scene, end - 1e-9 if end > 0 else 0.0)
    window = fit_window(t, start, end)
    order = 2 if dropped.size else 1
    measured = (closed_forms.fitted_rate(t[window], slip[window], start, end, order)
                if window.sum() > order + 1 else math.nan)
    exact = (closed_forms.grasp_slip_acceleration(scene, a) if dropped.size
             else closed_forms.grasp_creep_speed(scene, a))
    return not dropped.size, end if dropped.size else None, words, measured, exact


def words(scene, t, slip, short=False):
    """'held (slid 0.66 mm, Coulomb 0), creeps 0.498 mm/s in the steady lift (u* 0.500)',
    'dropped at 0.62 s, slips 2.462 m/s^2 while the lift accelerates (closed form 2.462)' (the
    closed form (g + a) - 2 mu N / m), or 'slips on the pads at 0.60 s: ...'; `short`, for a
    comparison's closing: 'held, creeps 0.498 mm/s (u* 0.500)', 'dropped at 0.62 s'."""
    on_pads, t_drop, phase, measured, exact = outcome(scene, t, slip)
    if not on_pads:
        return f"dropped at {t_drop:.2f} s" + ("" if short else (
            f", slips {measured:.3f} m/s^2 {phase} (closed form {exact:.3f})"))
    coulomb = closed_forms.grasp_coulomb_slip(scene, float(t[-1]))
    slid = f"slid {1e3 * slip[-1]:.2f} mm, Coulomb {1e3 * coulomb:.3g}"
    if not measured < scene.epsv:
        return f"slips on the pads at {t[-1]:.2f} s" + ("" if short else (
            f": {1e3 * measured:.1f} mm/s {phase} ({slid})"))
    creeps = f"creeps {1e3 * measured:.3f} mm/s"
    if short:
        return f"held, {creeps} (u* {1e3 * exact:.3f})"
    return f"held ({slid}), {creeps} {phase} (u* {1e3 * exact:.3f})"


def of_track(track, short=False):
    """words() of a run's kept states (recording.Track), `short` for a comparison."""
    samples = track.samples.all()
    t, slip = np.array([s.t for s in samples]), np.array([s.slip for s in samples])
    return words(track.scene, t, slip, short)
