"""scenes/grasp.py: a grasp's outcome from its slip, on slips of known speed and acceleration."""
import numpy as np
import pytest

from scenes import grasp


def test_a_creeping_slip_is_held_and_its_speed_is_measured_in_the_phase_it_ends_in():
    scene = grasp.build_grasp_scene()
    t = np.arange(0, 301) * scene.h
    slip = 4.97e-4 * t                                  # 0.497 mm/s throughout
    held, t_drop, phase, measured, exact, since = grasp.outcome(scene, t, slip)
    assert held and t_drop is None and phase == "in the steady lift" and since == 0.55
    assert measured == pytest.approx(4.97e-4, rel=1e-9)
    assert exact == grasp.creep_speed(scene)
    words = grasp.words(scene, t, slip)
    assert words == ("held (slid 0.75 mm, Coulomb 0); creeps 0.497 mm/s in the steady lift from "
                     "0.55 s (u* 0.500)")
    assert grasp.words(scene, t, slip, short=True) == (
        "held, creeps 0.497 mm/s from 0.55 s (u* 0.500)")


def test_a_slip_past_the_pads_is_dropped_at_that_time_with_its_acceleration():
    """A slip of 2.462 (t - 0.1)^2 / 2 from t = 0.1 s reaches the pads' 0.05 m at 0.1 + 0.2015 s,
    in the lift's acceleration (to 0.5 s); the Coulomb block, slipping from t = 0 (this start is
    not settled), at 0.218 s (test_grasp.py)."""
    scene = grasp.build_grasp_scene(squeeze=1.5696)
    t = np.arange(0, 121) * scene.h
    slip = 2.462 * np.maximum(t - 0.1, 0.0) ** 2 / 2
    held, t_drop, phase, measured, _, since = grasp.outcome(scene, t, slip)
    assert not held and t_drop == pytest.approx(0.305) and phase == "while the lift accelerates"
    assert since == pytest.approx(0.15)
    assert measured == pytest.approx(2.462, rel=1e-9)
    assert grasp.words(scene, t, slip) == (
        "dropped at 0.30 s (Coulomb 0.22); it slips 2.462 m/s^2 while the lift accelerates from "
        "0.15 s (closed form 2.462)")
    assert grasp.words(scene, t, slip, short=True) == "dropped at 0.30 s (Coulomb 0.22)"


def test_a_run_that_ends_while_the_block_still_slides_says_so():
    """Slipping at 50 mm/s, far above eps_v, when the run ends, 3 cm down, not yet past the pads:
    neither held nor dropped."""
    scene = grasp.build_grasp_scene(squeeze=2.0)
    t = np.arange(0, 121) * scene.h
    assert grasp.words(scene, t, 0.05 * t).startswith(
        "slips on the pads at 0.60 s (slid 30.00 mm, Coulomb ")
    assert grasp.words(scene, t, 0.05 * t).endswith("; at 50.0 mm/s in the steady lift from 0.55 s")
    assert grasp.words(scene, t, 0.05 * t, short=True) == "slips on the pads at 0.60 s"


def test_a_slip_that_slows_past_the_pads_says_so_without_a_minus_sign():
    """2 mu N / m = 10 > g: in the steady lift a slipping block slows at g - 10 = -0.19 m/s^2; a
    slip 0.03 m + 0.1 tau - 0.095 tau^2 (tau = t - 0.5 s) reaches the pads' 0.05 m at tau 0.2685;
    the Coulomb block at tau 0.2518 (test_grasp.py)."""
    scene = grasp.build_grasp_scene(squeeze=2.0)
    t = np.arange(0, 161) * scene.h
    tau = np.maximum(t - 0.5, 0.0)
    slip = np.where(t < 0.5, 0.03 * (t / 0.5) ** 2, 0.03 + 0.1 * tau - 0.095 * tau ** 2)
    assert grasp.words(scene, t, slip) == ("dropped at 0.77 s (Coulomb 0.75); its slip slows at "
                                           "0.190 m/s^2 in the steady lift from 0.55 s (closed "
                                           "form 0.190)")


@pytest.mark.parametrize("steps", [1, 3, 21, 101])
def test_a_run_too_short_to_fit_a_rate_says_so_and_claims_no_slip(steps):
    """1 to 3 kept states before the lift, 2 at 0.105 s into its acceleration, 2 into the steady
    lift: fewer than the 4 a fit needs (fitted_rate's nan), so neither held nor slipping."""
    scene = grasp.build_grasp_scene()
    t = np.arange(0, steps + 1) * scene.h
    slip = 5e-4 * t
    assert np.isnan(grasp.outcome(scene, t, slip)[3])
    said = grasp.words(scene, t, slip)
    assert said.startswith(f"is on the pads at {t[-1]:.2f} s (slid ") and "slips" not in said
    assert said.endswith("; too short a run to fit its speed (fewer than 4 states in its window)")
    assert grasp.words(scene, t, slip, short=True) == (
        f"on the pads at {t[-1]:.2f} s, too short to fit its speed")


def test_a_drop_too_soon_to_fit_its_acceleration_says_so():
    """A slip reaching the pads' 0.05 m at 0.105 s, 1 state into the lift's acceleration: no fit."""
    scene = grasp.build_grasp_scene(squeeze=0.1)
    t = np.arange(0, 22) * scene.h
    slip = 0.05 * (t / t[-1]) ** 4
    assert grasp.outcome(scene, t, slip)[1] == t[-1]
    said = grasp.words(scene, t, slip)
    assert said.startswith("dropped at 0.10 s (Coulomb ") and "nan" not in said
    assert said.endswith("; too short a run to fit its acceleration (fewer than 4 states in its "
                         "window)")


def test_a_short_phase_s_fit_says_its_first_state_s_time():
    """0.03 s: the fit from the phase's middle, 0.015 s, its first state (formatted as '%.2f' it
    read 'from 0.01 s', a time no state fitted has)."""
    scene = grasp.build_grasp_scene()
    t = np.arange(0, 7) * scene.h
    assert grasp.words(scene, t, 5e-4 * t, short=True) == (
        "held, creeps 0.500 mm/s from 0.015 s (u* 0.500)")
