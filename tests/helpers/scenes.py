"""A scene builder shared by the tests: the square clear of a slope of any angle (the resting starts
are scenes/square.py's `resting_scene`, shared with the accuracy report)."""
import math

import numpy as np

import simulator
from scenes.square import normal_of_tan

SLOPE_POINT = (0.0, -1.0)


def clear_scene(angle_deg=math.degrees(math.atan(0.1)), gap=0.05, v_in=0.0, **kw):
    """The axis-aligned square `gap` metres above a slope of `angle_deg`, moving into it at `v_in`
    m/s. Its half-extent along the normal is side/2 (|n_x| + |n_y|), so its lowest corner is `gap`
    away."""
    n = np.array(normal_of_tan(math.tan(math.radians(angle_deg))))
    side = kw.get("side_len", simulator.DEFAULTS["side_len"])
    center = np.array(SLOPE_POINT) + n * (0.5 * side * (abs(n[0]) + abs(n[1])) + gap)
    return simulator.build_scene(slope=tuple(n), slope_point=SLOPE_POINT, center=tuple(center),
                                 v0=tuple(-v_in * n), **kw)
