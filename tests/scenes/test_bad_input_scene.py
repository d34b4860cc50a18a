"""Bad scene parameters: a ValueError from the library naming the parameter and the value (the
command line's one line and exit code 2: tests/viewer/command/test_bad_input_cli.py)."""
import pytest

import simulator


LIBRARY = [
    (dict(side_len=0.0), "side_len must be a finite number > 0, got 0.0"),
    (dict(side_len=-1.0), "side_len must be a finite number > 0, got -1.0"),
    (dict(n_seg=0), "n_seg must be a whole number >= 1, got 0"),
    (dict(n_seg=-3), "n_seg must be a whole number >= 1, got -3"),
    (dict(rho=0.0), "rho must be a finite number > 0, got 0.0"),
    (dict(mass=-5.0), "mass must be a finite number > 0, got -5.0"),
    (dict(k=0.0), "k must be a finite number > 0, got 0.0"),
    (dict(h=-0.01), "h must be a finite number > 0, got -0.01"),
    (dict(dhat=0.0), "dhat must be a finite number > 0, got 0.0"),
    (dict(kappa=-1e5), "kappa must be a finite number > 0, got -100000.0"),
    (dict(epsv=0.0), "epsv must be a finite number > 0, got 0.0"),
    (dict(tol=0.0), "tol must be a finite number > 0, got 0.0"),
    (dict(mu=-0.1), "mu must be >= 0, got -0.1"),
    (dict(slope=(0.0, 0.0)), "slope normal must be non-zero, got [0.0, 0.0]"),
    (dict(slope_point=(0.0, 0.0)), "touches the slope"),
    (dict(slope_point=(0.0, -0.52)), "touches the slope"),  # corner 0
    (dict(friction_updates=-1), "friction_updates must be a whole number >= 0, got -1"),
    (dict(max_newton_iterations=0), "max_newton_iterations must be a whole number >= 1, got 0"),
    (dict(colour="red"), "unknown scene parameter(s): colour"),
    (dict(newton_start="x_tilda"), "newton_start must be one of 'x_n', 'x_tilde', got 'x_tilda'"),
    (dict(newton_start=0), "newton_start must be one of 'x_n', 'x_tilde', got 0"),
] + [(dict([(name, value)]), f"{name} must be") for name in
     ("side_len", "rho", "k", "h", "dhat", "kappa", "epsv", "tol", "mu", "angle", "n_seg", "mass")
     for value in (float("nan"), float("inf"))] + [
    (dict([(name, bad)]), f"{name} must be")
    for name in ("gravity", "slope", "slope_point", "v0", "center")
    for bad in ((float("nan"), 1.0), (0.0, float("inf")), (1.0,))]


@pytest.mark.parametrize("kwargs, message", LIBRARY, ids=[str(k) for k, _ in LIBRARY])
def test_build_scene_refuses(kwargs, message):
    with pytest.raises(ValueError) as info:
        simulator.build_scene(**kwargs)
    assert message in str(info.value)


def test_touching_slope_names_the_node_and_distance():
    message = r"node 0 touches the slope \(-0.05 m\): try --center 0,0.06"
    with pytest.raises(ValueError, match=message):
        simulator.build_scene(slope=(0.0, 1.0), slope_point=(0.0, -0.45))
    scene = simulator.build_scene(slope=(0.0, 1.0), slope_point=(0.0, -0.5 - 1e-9))   # just clear
    assert "barrier" in scene.terms


@pytest.mark.parametrize("steps", [0, -1, 2.5, float("nan"), float("inf")])
def test_simulate_refuses_bad_steps(steps):
    with pytest.raises(ValueError, match=f"steps must be a whole number >= 1, got {steps}"):
        next(simulator.simulate(simulator.build_scene(), steps))
