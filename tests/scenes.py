"""Scene builders shared by the tests: a square clear of a slope of any angle, or resting on it."""
import math

import numpy as np
from scipy.optimize import brentq

import BarrierEnergy
import simulator

SLOPE_POINT = (0.0, -1.0)


def slope_normal(angle_deg):
    """Unit normal of a slope descending to the right at `angle_deg` (0: flat ground)."""
    t = math.radians(angle_deg)
    return np.array([math.sin(t), math.cos(t)])


def downhill(n):
    return np.array([n[1], -n[0]])


def clear_scene(angle_deg=math.degrees(math.atan(0.1)), gap=0.05, v_in=0.0, **kw):
    """The axis-aligned square `gap` metres above a slope of `angle_deg`, moving into it at `v_in` m/s.
    Its half-extent along the normal is side/2 (|n_x| + |n_y|), so its lowest corner is `gap` away."""
    n = slope_normal(angle_deg)
    side = kw.get("side_len", simulator.DEFAULTS["side_len"])
    center = np.array(SLOPE_POINT) + n * (0.5 * side * (abs(n[0]) + abs(n[1])) + gap)
    return simulator.build_scene(slope=tuple(n), slope_point=SLOPE_POINT, center=tuple(center),
                                 v0=tuple(-v_in * n), **kw)


def equilibrium_distance(angle_deg, **kw):
    """Barrier distance d at which the n_seg+1 bottom nodes together carry the weight's normal part,
    M g cos(theta) = (n_seg+1) (-dP/dd)(d), solved by bisection in (0, dhat)."""
    p = {**simulator.DEFAULTS, **kw}
    mass = p["mass"] if p["mass"] is not None else p["rho"] * p["side_len"] ** 2
    load = mass * np.hypot(*p["gravity"]) * math.cos(math.radians(angle_deg)) / (p["n_seg"] + 1)
    w = p["side_len"] / p["n_seg"]
    return brentq(lambda d: -BarrierEnergy.dP_dd(d, w, p["dhat"], p["kappa"]) - load,
                  1e-300, p["dhat"] * (1 - 1e-12), xtol=1e-300, rtol=1e-15)


def resting_scene(angle_deg, **kw):
    """The square at rest, rotated so its bottom edge is parallel to the slope, the bottom row at the
    barrier's equilibrium distance."""
    n = slope_normal(angle_deg)
    side = kw.get("side_len", simulator.DEFAULTS["side_len"])
    center = np.array(SLOPE_POINT) + n * (side / 2 + equilibrium_distance(angle_deg, **kw))
    return simulator.build_scene(slope=tuple(n), slope_point=SLOPE_POINT, angle=-math.radians(angle_deg),
                                 center=tuple(center), **kw)
