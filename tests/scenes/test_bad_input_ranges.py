"""Every scene's numbers in range (issue 40, item 5): the tablecloth and the chalk refuse what
float64 or the machine cannot hold as the square does, by the shared checks of scenes/ranges.py,
with a ValueError naming the parameter and no RuntimeWarning on the way."""
import warnings

import pytest

import simulator
import utils
from scenes import grasp, ranges

BUILDERS = {"square": simulator.build_scene, "chalk": simulator.build_chalk_scene,
            "tablecloth": simulator.build_tablecloth_scene, "grasp": grasp.build_grasp_scene}

TABLECLOTH = [      # each ended in brentq's "f(a) and f(b) must have different signs" before
    (dict(gravity=(0.0, -1e308)), "gravity"), (dict(mass=1e300), "mass"),
    (dict(kappa=1e-320), "kappa"), (dict(width=1e-300), "width"),
    # each printed a RuntimeWarning, an OverflowError traceback or a MemoryError before
    (dict(kappa=1e300), "kappa"), (dict(dhat=1e300), "dhat"), (dict(mu=1e308), "mu"),
    (dict(h=1e200), "h"), (dict(h=1e-160), "h"), (dict(pull_length=1e308), "pull_length"),
    (dict(pull_speed=1e300), "pull_speed"), (dict(nx=1e4, ny=1e4), "nx"),
    (dict(nx=2, ny=1e9), "ny"), (dict(gravity=(0.0, -1e-320)), "gravity")]
CHALK = [(dict(mu=1e308), "mu"), (dict(kappa=1e300), "kappa"), (dict(dhat=1e300), "dhat"),
         (dict(h=1e200), "h"), (dict(h=1e-160), "h"), (dict(rho=1e300), "rho"),
         (dict(k=1e30), "k"), (dict(nx=1e4, ny=1e4), "nx"),
         (dict(mu_s=1e308), "mu_s"),    # its static friction's stiffness, as mu's
         # an OverflowError traceback as its first frame was drawn (h^2 k_hand / m lost beside 1)
         (dict(k_hand=1e-320), "k_hand"), (dict(k_hand=1e-300), "k_hand"), (dict(h=1e-12), "h")]
GRASP = [(dict(kappa=1e-320), "kappa"), (dict(squeeze=1e300), "squeeze"),
         (dict(mass=1e300), "mass"), (dict(h=1e200), "h"), (dict(gravity=(0.0, -1e308)), "gravity"),
         (dict(nx=1e4, ny=1e4), "nx"),
         # ended in "math domain error" or a gap within round-off of dhat (check_carries)
         (dict(squeeze=1e-320), "squeeze"), (dict(kappa=1e150), "kappa")]


def refused(build, kwargs, monkeypatch):
    """The ParameterError build(**kwargs) raises, on a machine of 1 GiB, warnings as errors."""
    monkeypatch.setattr(ranges, "physical_memory", lambda: 2 ** 30)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(utils.ParameterError) as info:
            build(**kwargs)
    return info.value


@pytest.mark.parametrize("kwargs, name", TABLECLOTH, ids=[str(k) for k, _ in TABLECLOTH])
def test_the_tablecloth_refuses_what_float64_cannot_hold_by_name(kwargs, name, monkeypatch):
    err = refused(simulator.build_tablecloth_scene, kwargs, monkeypatch)
    assert err.parameter == name and str(err).startswith(f"{name} "), str(err)


@pytest.mark.parametrize("kwargs, name", CHALK, ids=[str(k) for k, _ in CHALK])
def test_the_chalk_refuses_what_float64_cannot_hold_by_name(kwargs, name, monkeypatch):
    err = refused(simulator.build_chalk_scene, kwargs, monkeypatch)
    assert err.parameter == name and str(err).startswith(f"{name} "), str(err)


@pytest.mark.parametrize("kwargs, name", GRASP, ids=[str(k) for k, _ in GRASP])
def test_the_grasp_refuses_what_float64_cannot_hold_by_name(kwargs, name, monkeypatch):
    """The grasp's squeeze is carried as the dish's weight is (ranges.check_carries)."""
    err = refused(grasp.build_grasp_scene, kwargs, monkeypatch)
    assert err.parameter == name and str(err).startswith(f"{name} "), str(err)


def test_a_kappa_that_cannot_carry_the_dish_names_the_least_that_can():
    """The least kappa the message names carries the dish (the scene builds); half of it not."""
    with pytest.raises(ValueError, match=r"\(kappa >= (\S+)\)") as info:
        simulator.build_tablecloth_scene(kappa=1e-20)
    least = float(str(info.value).split("kappa >= ")[1].rstrip(")"))
    assert simulator.build_tablecloth_scene(kappa=least).x0[:, 1].min() > 0.0
    with pytest.raises(ValueError, match="cannot carry the dish"):
        simulator.build_tablecloth_scene(kappa=least / 2)


@pytest.mark.parametrize("kind", BUILDERS)
def test_every_scene_builder_calls_the_shared_checks(kind, monkeypatch):
    """One shared place: each builder hands its start to scenes.ranges.check_start and its node
    count to check_memory; a new scene does the same."""
    called = []
    for name in ("check_start", "check_memory"):
        real = getattr(ranges, name)
        monkeypatch.setattr(ranges, name, lambda *a, real=real, name=name, **k: (
            called.append(name), real(*a, **k))[1])
    BUILDERS[kind]()
    assert {"check_start", "check_memory"} <= set(called)


@pytest.mark.parametrize("pull_speed, warned", [(4.0, False), (100.0, False), (200.0, True),
                                                (1000.0, True)])
def test_a_pull_under_two_steps_is_warned_about(pull_speed, warned):
    """L/U under 2 steps of h: the travel measured +8 % off the closed form at 200 m/s (1 step),
    +2599 % at 1000 m/s; 100 m/s (2 steps, +1.9 %) is not warned about."""
    said = simulator.build_tablecloth_scene(pull_speed=pull_speed).warnings
    assert bool(said) == warned
    assert all("cannot be trusted (use U <= 100 m/s)" in w for w in said)


@pytest.mark.parametrize("kind", BUILDERS)
@pytest.mark.parametrize("epsv", [1e-300, 1e308])
def test_every_scene_refuses_an_eps_v_whose_square_leaves_float64(kind, epsv, monkeypatch):
    """eps_v in [1e-150, 1e150] (utils.check_epsv): 1e308 overflowed f_hess_term's eps_v^2 in a
    RuntimeWarning, then Newton stalled, in every scene."""
    err = refused(BUILDERS[kind], dict(epsv=epsv), monkeypatch)
    assert err.parameter == "epsv" and "[1e-150, 1e+150]" in str(err), str(err)


def test_a_grasp_of_mu_1e_320_slips_without_a_warning():
    """Its load ratio m (g + a) / (2 mu N) is beyond float64: inf, it slips (no RuntimeWarning
    of a numpy division)."""
    scene = grasp.build_grasp_scene(mu=1e-320)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert grasp.load_ratio(scene) == float("inf") and not grasp.holds(scene)


@pytest.mark.parametrize("name, bound, scale", [("squeeze", 1.11e-14, 1.01),
                                                ("kappa", 2.36e16, 0.99)])
def test_a_squeeze_the_barrier_cannot_resolve_names_the_bound(name, bound, scale, monkeypatch):
    """A load whose gap is within round-off of dhat: refused naming the value that resolves it
    (3 digits); 1 % inside that bound, the grasp is built."""
    err = refused(grasp.build_grasp_scene, {name: 1e-320 if name == "squeeze" else 1e150},
                  monkeypatch)
    op = ">=" if name == "squeeze" else "<="
    assert str(err).endswith(f": lost in round-off ({name} {op} {bound:.3g})")
    assert grasp.build_grasp_scene(**{name: bound * scale}).params[name] == bound * scale


def test_the_least_grip_the_chalk_names_is_taken():
    """h^2 k_hand / m >= 8 eps: the bound the message names (3 digits) builds 1 % above it."""
    with pytest.raises(utils.ParameterError, match=r"k_hand = .*: lost in round-off") as info:
        simulator.build_chalk_scene(k_hand=1e-320)
    least = float(str(info.value).split("k_hand >= ")[1].rstrip(")"))
    assert simulator.build_chalk_scene(k_hand=1.01 * least).hand.k_hand == 1.01 * least
