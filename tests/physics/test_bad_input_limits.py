"""Scenes at the edge of float64 and of the machine: a start within round-off of the slope, values
whose first step would overflow or whose Newton matrix float64 cannot resolve, meshes too large for
memory, and the library's parameter names. Refused at scene build with a ValueError naming the
parameter and its value; on the command line in one line, exit code 2, with nothing written."""
import decimal
import math
import os
import re
import subprocess
import sys

import numpy as np
import pytest

import BarrierEnergy
import MassSpringEnergy
import simulator
import time_integrator
from scenes import ranges, square

from helpers import ROOT

EPS = np.finfo(float).eps


# ---- a start within round-off of the slope (issue 13, part 3) ------------------------------------

@pytest.mark.parametrize("gap, refused",
                         [(0.0, True), (1.2e-16, True), (1e-15, True), (1e-12, False)])
def test_round_off_threshold_on_a_flat_slope(gap, refused):
    """Corner 0 at (-0.5, -0.5) above y = -0.5 - gap: the threshold is ROUNDOFF_ULPS eps
    (max|x| + |o|), 3e-15 m here; a gap of 1e-12 m is a real (if tiny) gap and builds, one ulp of
    0.5 does not."""
    kwargs = dict(slope=(0.0, 1.0), slope_point=(0.0, -0.5 - gap))
    if refused:
        with pytest.raises(ValueError, match="touches the slope"):
            simulator.build_scene(**kwargs)
    else:
        assert "barrier" in simulator.build_scene(**kwargs).terms
    threshold = ranges.ROUNDOFF_ULPS * EPS * (math.hypot(0.5, 0.5) + 0.5 + gap)
    assert (gap <= threshold) == refused


# ---- absurd values (issue 13, part 5) ------------------------------------------------------------

LIBRARY_OVERFLOW = [
    (dict(v0=(1e308, 0.0)), "v0", "kinetic energy"),
    (dict(v0=(1e76, 0.0)), "v0", "kinetic energy"),                # 1/2 1000 kg 1e152 = 5e154 J
    (dict(dhat=1e308), "dhat", "barrier's energy"),
    (dict(h=1e200), "h", "first inertia term"),
    (dict(gravity=(0.0, -1e200)), "gravity", ""),
    (dict(kappa=1e300), "kappa", "barrier's energy"),
    (dict(rho=1e300), "rho", "total mass"),
    (dict(epsv=1e-149), "epsv", "friction's stiffness"),
    (dict(k=1e300, h=1e-70), "k", "springs' stiffness"),
    (dict(side_len=1e200, mass=1.0, slope=None), "side_len", "gravity's term"),
]


@pytest.mark.parametrize("kwargs, culprit, what", LIBRARY_OVERFLOW,
                         ids=[str(k) for k, _, _ in LIBRARY_OVERFLOW])
def test_build_scene_refuses_first_step_overflow(kwargs, culprit, what):
    with pytest.raises(ValueError) as info:
        simulator.build_scene(**kwargs)
    message = str(info.value)
    assert message.startswith(f"{culprit} = ") and what in message, message


def test_scale_limit_leaves_finite_sums():
    """FLOAT64_SCALE_LIMIT: a scale squared and summed over the 1e8 nodes that fit at most (16 KiB
    each in 1.6 TB) stays finite."""
    assert np.isfinite(np.sum(np.full(10, ranges.FLOAT64_SCALE_LIMIT) ** 2) * 1e7)


def test_newton_matrix_bound():
    """h^2 k / m above 0.1/eps is refused naming k (the parameter furthest from the lecture's); at a
    tenth of it, the first step converges and falls g h^2 as free fall does (the translation, which
    only M resolves, comes out right)."""
    m = simulator.DEFAULTS["rho"] / 25                       # n_seg 4: 25 nodes, 40 kg each
    h = simulator.DEFAULTS["h"]
    k_limit = ranges.NEWTON_RATIO_LIMIT * m / h ** 2
    message = r"^k = .*: h\^2 k / m = 9\.0\de\+14 > 0\.1/eps \(m lost in float64\)"
    with pytest.raises(ValueError, match=message):
        simulator.build_scene(k=2 * k_limit)
    scene = simulator.build_scene(k=k_limit / 10, tol=1e-6)
    x, v, report = time_integrator.step(scene, scene.x0.copy(), scene.v0.copy())
    fall = np.average(x - scene.x0, axis=0, weights=scene.m)
    # Newton stops once its step is below tol h: the position is within that of the exact g h^2
    assert fall == pytest.approx([0.0, scene.g[1] * h * h], abs=scene.tol * h)
    with pytest.raises(ValueError, match=r"^h = 1e\+10: h\^2 k / m = "):
        simulator.build_scene(h=1e10, slope=None)
    with pytest.raises(ValueError, match=r"^rho = 1e-20: h\^2 k / m = "):
        simulator.build_scene(rho=1e-20, slope=None)


def test_lectures_scene_and_stability_extremes_are_far_inside_the_limits():
    """The stability suite's extremes (k 1e9 at h 1 s, kappa 1e9, dhat 1e-4, eps_v 1e-6, 100 m/s,
    n_seg 32) build: the limits refuse only what float64 cannot do."""
    simulator.build_scene(k=1e9, h=1.0, kappa=1e9, dhat=1e-4, epsv=1e-6, mu=10.0, v0=(0.0, -100.0))
    simulator.build_scene(k=1e9, h=1.0, n_seg=32)


# ---- memory --------------------------------------------------------------------------------------

def test_memory_check_refuses_what_does_not_fit(monkeypatch):
    """With 1 GiB of memory, the largest n_seg the message names fits and the next does not."""
    monkeypatch.setattr(ranges, "physical_memory", lambda: 2 ** 30)
    message = r"^n_seg = 300: 9.06e\+4 nodes, 1.38 GiB > 1 GiB \(n_seg <= (\d+)\)"
    with pytest.raises(ValueError, match=message) as info:
        simulator.build_scene(n_seg=300)
    largest = int(str(info.value).split("n_seg <= ")[1].rstrip(")"))
    nodes = lambda n_seg: (n_seg + 1) ** 2      # noqa: E731
    ranges.check_memory("n_seg", largest, nodes)
    with pytest.raises(ValueError):
        ranges.check_memory("n_seg", largest + 1, nodes)


# The peak as VmHWM, not ru_maxrss: a forked child keeps its parent's ru_maxrss across exec, so a
# baseline read the pytest process's own peak once that was larger; VmHWM starts afresh with the
# program. One child: the 1-segment scene's peak first, then that of n_seg 128 and one step.
PEAK = """import simulator, time_integrator
def peak():
    print([line.split()[1] for line in open("/proc/self/status") if line.startswith("VmHWM:")][0])
simulator.build_scene(n_seg=1)
peak()
scene = simulator.build_scene(n_seg=128)
time_integrator.step(scene, scene.x0.copy(), scene.v0.copy())
peak()"""


@pytest.mark.skipif(sys.platform != "linux", reason="reads VmHWM (KiB) from /proc/self/status")
def test_memory_per_node_bounds_the_measured_peak():
    """MEMORY_PER_NODE against the peak resident memory of build_scene and one step at n_seg = 128
    (16641 nodes), less that of a 1-segment scene: at least the measurement, at most 4 times it (so
    the check refuses no scene that would fit by a wide margin)."""
    out = subprocess.run([sys.executable, "-c", PEAK], cwd=ROOT, capture_output=True, text=True,
                         timeout=120, env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})
    one, many = (int(kib) * 1024 for kib in out.stdout.split()[-2:])
    per_node = (many - one) / 129 ** 2
    assert per_node <= ranges.MEMORY_PER_NODE <= 4 * per_node


# ---- the too-large-h warning ---------------------------------------------------------------------

@pytest.mark.parametrize("params", [dict(h=1.0), dict(v0=(1e10, 0.0)), dict(v0=(100.0, 0.0)),
                                    dict(h=0.5, gravity=(0.0, 0.0), v0=(3.0, 0.0)),
                                    dict(h=1.0, gravity=(0.0, -1e6)),
                                    dict(v0=(1e70, 0.0), h=1e-60)], ids=str)
def test_warning_suggests_the_largest_h_that_resolves(params):
    """The warning's 'use h <= H s' is the largest h with |v0| h + |g| h^2 <= side_len, to its 3
    digits: H itself resolves, H plus one unit in its third digit reaches the size (it said 0 s for
    1e10 m/s; 4 eps: the rounding of travel's two products and sum)."""
    scene = simulator.build_scene(**params, slope=None)
    p, (warning,) = scene.params, [w for w in scene.warnings if "use h <=" in w]
    text = warning.split("use h <= ")[1].split(" s)")[0]
    H, unit = float(text), 10.0 ** (math.floor(math.log10(float(text))) - 2)

    def travel(h):
        return math.hypot(*p["v0"]) * h + math.hypot(*p["gravity"]) * h * h
    assert 0.0 < H and travel(H) <= p["side_len"] <= travel(H + unit) * (1 + 4 * EPS)


# ---- library edges (issue 13, part 7) ------------------------------------------------------------

def test_dt_is_an_alias_of_h():
    assert simulator.build_scene(dt=0.005).h == 0.005 == simulator.build_scene(h=0.005).params["h"]
    with pytest.raises(ValueError, match="h is given twice, as h and as its alias dt"):
        simulator.build_scene(dt=0.005, h=0.01)


def test_unknown_parameter_lists_the_valid_names():
    with pytest.raises(ValueError) as info:
        simulator.build_scene(colour="red")
    message = str(info.value)
    assert message.startswith("unknown scene parameter(s): colour; valid: ")
    assert set(message.split("valid: ")[1].split(", ")) == {*simulator.DEFAULTS, "dt"}


@pytest.mark.parametrize("name, value", [("n_seg", "4"), ("h", "0.01"), ("mu", "0.2"),
                                         ("k", b"2e4"), ("angle", "0"), ("mass", "10"),
                                         ("v0", ("1", "2")), ("center", ["0", "0"]),
                                         ("friction_updates", "2"), ("v0", (True, False))])
def test_text_for_numbers_is_refused(name, value):
    with pytest.raises(ValueError, match=f"^{name} must be .*, got {re.escape(repr(value))}"):
        simulator.build_scene(**{name: value})


# ---- numbers that are not float64 numbers (issue 25, item 7) -------------------------------------

SCALARS = [name for name, value in simulator.DEFAULTS.items()
           if isinstance(value, (int, float)) and not isinstance(value, bool)] + ["mass"]
VECTORS = [name for name, value in simulator.DEFAULTS.items() if isinstance(value, tuple)]


@pytest.mark.parametrize("name", SCALARS)
@pytest.mark.parametrize("value", [10 ** 400, -10 ** 400], ids=["10**400", "-10**400"])
def test_an_int_beyond_float64_is_refused_naming_the_parameter(name, value):
    """float(10**400) raises OverflowError: refused as a ValueError naming the parameter, the value
    shown in 3 digits (not its 401)."""
    message = rf"^{name} must be .*, got -?1\.00e\+400, beyond float64's range$"
    with pytest.raises(ValueError, match=message):
        simulator.build_scene(**{name: value})


@pytest.mark.parametrize("name", VECTORS + ["slope"])
@pytest.mark.parametrize("value, shown", [
    ((10 ** 400, 0.0), r"\(1\.00e\+400, 0\.0\), beyond float64's range"),
    ((0.0, -10 ** 400), r"\(0\.0, -1\.00e\+400\), beyond float64's range"),
    ((1j, 0.0), r"\(1j, 0\.0\)"), ((0.0, 2 + 0j), r"\(0\.0, \(2\+0j\)\)"),
    ((True, 0.5), r"\(True, 0\.5\)"), ((None, 0.0), r"\(None, 0\.0\)"),
    (np.array([1.0, 0.0], dtype=complex), r"array\(\[1\.\+0\.j, 0\.\+0\.j\]\)"),
    (np.array(["1", 0.0], dtype=object), r"array\(\['1', 0\.0\], dtype=object\)")],
                         ids=["10**400", "-10**400", "1j", "2+0j", "True", "None", "complex array",
                              "object array of text"])
def test_a_vector_of_no_real_numbers_is_refused_naming_the_parameter(name, value, shown):
    """A complex component (even 2+0j, or a complex array with zero imaginary parts, which numpy
    would convert dropping them), a bool, None, an int beyond float64: a ValueError naming the
    parameter."""
    with pytest.raises(ValueError, match=f"^{name} must be a 2-vector of numbers, got {shown}$"):
        simulator.build_scene(**{name: value})


@pytest.mark.parametrize("name", SCALARS)
@pytest.mark.parametrize("value", [1j, 0.01 + 0j, np.complex128(1.0), np.array(1.0 + 0j),
                                   np.array(True), np.array("4"), np.array([1.0]), [1.0], None],
                         ids=["1j", "0.01+0j", "complex128", "0-d complex", "0-d bool",
                              "0-d text", "1 value", "list", "None"])
def test_a_scalar_of_no_real_number_is_refused_naming_the_parameter(name, value):
    if name == "mass" and value is None:
        return                                  # mass None is the default: rho side_len^2
    with pytest.raises(ValueError, match=f"^{name} must be .*, got {re.escape(repr(value))}$"):
        simulator.build_scene(**{name: value})


def test_real_numbers_of_other_types_are_taken():
    """What is one real number is accepted, whatever its type: numpy scalars and 0-d arrays, a
    Fraction."""
    import fractions
    scene = simulator.build_scene(k=np.float32(2e4), n_seg=np.int64(3), mu=np.array(0.2),
                                  h=fractions.Fraction(1, 100),
                                  center=np.array([0, 1], dtype=np.int8), v0=[np.float16(1.0), 0])
    assert (scene.k[0], scene.params["n_seg"], scene.mu, scene.h) == (2e4, 3, 0.2, 0.01)
    assert scene.params["center"] == (0.0, 1.0) and scene.params["v0"] == (1.0, 0.0)


# ---- a slope normal of any float64 components (issue 33, item 7) ---------------------------------

@pytest.mark.parametrize("slope", [(1e-320, 1e-319), (1e-310, 1e-310), (-3e-322, 5e-323),
                                   (1e308, 1e308)], ids=str)
def test_a_slope_normal_of_any_size_is_normalized_exactly(slope):
    """Scaled by its largest component first, a subnormal slope (1e-320 is 2024 of float64's
    smallest step) normalizes as the same direction in whole numbers of that step does, bit for bit
    (one code path: each division by a power of two is exact); 1e308 components (|slope| beyond
    float64) too."""
    unit = 5e-324 if max(map(abs, slope)) < 1e-300 else 2.0 ** 1000      # exact powers of two
    whole = tuple(c / unit for c in slope)
    assert all(float(c).is_integer() for c in whole) or unit > 1.0
    n = square.slope_normal(slope)
    assert n.tobytes() == square.slope_normal(whole).tobytes()
    assert abs(np.hypot(*n) - 1.0) <= EPS
    assert np.sign(n).tolist() == np.sign(slope).tolist()


@pytest.mark.parametrize("scale", [1.0, 1e-300, 1e-306, 1e300, 1e307])
def test_a_slope_normal_of_normal_float64_components_builds_a_unit_normal(scale):
    """At any scale the normal comes out of unit length within 1 eps, in the slope's direction."""
    rng = np.random.default_rng(25)
    for slope in rng.uniform(0.1, 1.0, (50, 2)) * scale * np.array([[1.0, 3.0]]):
        n = square.slope_normal(tuple(slope))
        assert abs(np.hypot(*n) - 1.0) <= EPS
        assert n[0] * slope[1] == pytest.approx(n[1] * slope[0], rel=1e-15)
    scene = simulator.build_scene(slope=(0.1 * scale, scale), center=(0.0, 0.0))
    assert scene.n == pytest.approx(simulator.build_scene().n, rel=1e-15)


def test_the_lectures_slope_is_normalized_as_the_lecture_does():
    """(0.1, 1) / |(0.1, 1)|: its largest component is 1, so scaling first changes no bit."""
    slope = np.array(simulator.DEFAULTS["slope"])
    assert simulator.build_scene().n.tobytes() == (slope / np.hypot(*slope)).tobytes()


def test_an_object_array_of_numbers_converts_as_float_does():
    """An object array of decimal.Decimal (or Fraction) converts item by item as float() does,
    wherever a float64 array is taken: a scene's vectors, an energy's positions, a per-node array;
    one that holds text, a bool or a complex number is refused as any other array of no real
    numbers."""
    D = decimal.Decimal
    objects = np.array([D("0.1"), D("0.25")], dtype=object)
    assert simulator.build_scene(center=objects).params["center"] == (0.1, 0.25)
    x = np.array([[D(0), D(0)], [D("0.5"), D(0)]], dtype=object)
    e, l2 = np.array([[0, 1]]), np.array([0.16])
    assert MassSpringEnergy.val(x, e, l2, 1e3) == MassSpringEnergy.val(x.astype(float), e, l2, 1e3)
    up, origin, area = np.array([0.0, 1.0]), np.zeros(2), np.array([D(1), D(1)], dtype=object)
    w = BarrierEnergy.compute_mu_lambda(x + [0, D("0.003")], up, origin, area, 0.2)
    assert w.dtype == np.float64 and w[0] > 0.0
    for bad in (np.array([[D(0), "0"], [D(1), D(0)]], dtype=object),
                np.array([[D(0), True], [D(1), D(0)]], dtype=object),
                np.array([[D(0), 1j], [D(1), D(0)]], dtype=object)):
        with pytest.raises(ValueError, match="^x must hold real numbers, got an object array"):
            MassSpringEnergy.val(bad, e, l2, 1e3)


@pytest.mark.parametrize("step_index", ["a", None, 1.5, -1, float("nan")])
def test_a_step_index_that_is_no_whole_number_is_refused_by_name(step_index):
    """step(..., step_index=n): n numbers the step and sets its time, a whole number >= 0."""
    scene = simulator.build_scene()
    with pytest.raises(ValueError, match=r"^step_index must be a whole number >= 0, got "):
        time_integrator.step(scene, scene.x0, scene.v0, step_index=step_index)
