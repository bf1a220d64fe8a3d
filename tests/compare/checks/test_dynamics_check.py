"""Check `dynamics`: passes a correct simulator to round-off, and fails mistakes put into
custom_sim's own computation (inertia, contact points, mass), while the twin it runs against
stays bit for bit the same (it shares nothing with custom_sim)."""
import dataclasses
import importlib
import json
import warnings

import numpy as np
import pytest

import compare.checks.dynamics_check as dynamics_check
import custom_sim.bodies
from compare.scenarios import builtin_names, load
from compare.checks.dynamics_check import (HORIZON_POSITION, ROUNDOFF_FLOOR_ANGLE, ROUNDOFF_FLOOR_POSITION,
                                            check_dynamics)
from custom_sim import Stepper, simulate
from mujoco_models import simulate_dynamics
from tests.conftest import make_scene
from test_contact_check import rule_breaches

SIMULATE = importlib.import_module("custom_sim.runner")

KEYS = {"name", "isolates", "integrator", "position_error_max", "angle_error_max",
        "tolerance_position", "tolerance_angle", "pass", "reason"}


def short(name, duration=0.4):
    """box_drop's corner lands at 0.25 s: 0.4 s holds the impact and the rock back."""
    return dataclasses.replace(load(name), duration=duration)


def row_for(scene, integrator="semi_implicit_euler"):
    run = dataclasses.replace(scene, integrator=integrator)
    return check_dynamics(run, simulate(run).states(), integrator, run.dt)


def assert_json_row(row):
    assert KEYS <= set(row.to_json())
    json.dumps(row.to_json(), allow_nan=False)


@pytest.mark.parametrize("integrator", ["semi_implicit_euler", "rk4"])
def test_custom_sim_passes_to_round_off(integrator):
    row = row_for(short("t_shape_drop"), integrator)
    assert_json_row(row)
    assert row.passed is True and row.details["bound"] == "round-off", row.reason
    assert row.tolerance_position == ROUNDOFF_FLOOR_POSITION


@pytest.mark.parametrize("integrator", ["explicit_euler", "implicit_euler"])
def test_integrators_mujoco_lacks_are_not_judged(integrator):
    scene = short("box_drop", 0.01)
    row = check_dynamics(scene, np.zeros((scene.steps + 1, 6)), integrator, scene.dt)
    assert_json_row(row)
    assert row.passed is None and "MuJoCo has no" in row.reason and "check step" in row.reason


def test_a_motion_that_amplifies_round_off_is_judged_with_its_measured_sensitivity():
    """At 1e-4 s (its step before it was made stable) the T's semi-implicit friction update is
    unstable during its impact (h lambda = 3.5): custom_sim and the twin part by 5e-9 m, above
    the round-off floor. custom_sim's own loop runs it with the chatter watch off."""
    scene = dataclasses.replace(load("t_shape_drop"), dt=1e-4)
    stepper = Stepper(scene, watch_chatter=False)
    states = np.vstack([stepper.state.copy()] + [stepper.advance(1).copy() for _ in range(scene.steps)])
    row = check_dynamics(scene, states, "semi_implicit_euler", scene.dt)
    assert_json_row(row)
    assert row.details["bound"] == "sensitivity" and row.passed is True, row.reason
    assert ROUNDOFF_FLOOR_POSITION < row.position_error_max <= row.tolerance_position <= HORIZON_POSITION
    assert row.details["friction_step_number_max"] > 2.0 and "unstable" in row.reason


# Mistakes put into custom_sim's own code, one at a time.

def inertia_10_percent_high(monkeypatch):
    real = custom_sim.bodies.box_inertia
    monkeypatch.setattr(custom_sim.bodies, "box_inertia", lambda m, w, h: 1.1 * real(m, w, h))
    custom_sim.bodies.mass_properties.cache_clear()


def corners_with_width_and_height_swapped(monkeypatch):
    real = custom_sim.bodies.box_corners
    monkeypatch.setattr(custom_sim.bodies, "box_corners", lambda w, h, centre=(0.0, 0.0): real(h, w, centre))
    custom_sim.bodies.mass_properties.cache_clear()


def mass_10_percent_high_in_the_compiled_model(monkeypatch):
    real = SIMULATE.build_model

    def heavier(scene, props=None):
        model, points = real(scene, props)
        return model._replace(inv_mass=model.inv_mass / 1.1), points

    monkeypatch.setattr(SIMULATE, "build_model", heavier)


MISTAKES = [(inertia_10_percent_high, "box_drop"), (corners_with_width_and_height_swapped, "box_drop"),
            (mass_10_percent_high_in_the_compiled_model, "point_drop"),
            (inertia_10_percent_high, "t_shape_drop")]


@pytest.mark.parametrize("mistake,name", MISTAKES, ids=[f"{m.__name__}-{n}" for m, n in MISTAKES])
def test_a_mistake_in_custom_sim_fails_the_check_and_leaves_the_twin_alone(monkeypatch, mistake, name):
    scene = short(name, 0.6 if name == "t_shape_drop" else 0.4)
    twin_before = simulate_dynamics(scene).states()
    correct = simulate(scene).states()
    mistake(monkeypatch)   # mass properties are derived once per body: the mistake clears them
    try:
        wrong = simulate(scene).states()
    finally:
        custom_sim.bodies.mass_properties.cache_clear()   # the mistake's must not outlive the test
    assert not np.array_equal(wrong, correct), "the mistake changes custom_sim's run"
    row = check_dynamics(scene, wrong, "semi_implicit_euler", scene.dt)
    assert_json_row(row)
    assert row.passed is False, (f"{mistake.__name__} on {name} passed: {row.position_error_max:.3g} m, "
                                 f"{row.angle_error_max:.3g} rad against {row.tolerance_position:.3g} m")
    assert row.position_error_max > 1e3 * row.tolerance_position, (
        f"{mistake.__name__} on {name}: {row.position_error_max:.3g} m is close to the tolerance "
        f"{row.tolerance_position:.3g} m")
    assert np.array_equal(simulate_dynamics(scene).states(), twin_before), \
        "the twin moved with a mistake made in custom_sim"


# No judged tolerance above a tenth of the motion it judges (rule_breaches states the rule on
# its own, against the twin's motion over the judged window).

def twin_breaches(scene, integrator="semi_implicit_euler"):
    run = dataclasses.replace(scene, integrator=integrator)
    row = check_dynamics(run, simulate(run).states(), integrator, run.dt)
    twin = simulate_dynamics(run, dynamics_check.MUJOCO_TWIN[integrator], run.dt).states()
    return row, rule_breaches(row, twin, run.dt)


@pytest.mark.parametrize("integrator", ["semi_implicit_euler", "rk4"])
@pytest.mark.parametrize("name", builtin_names())
def test_every_judged_dynamics_tolerance_is_within_a_tenth_of_the_motion(name, integrator):
    """A point mass and a ball bouncing straight never turn: their angle is shown, not judged
    (a round-off tolerance of 1e-9 rad on an angle that stays 0 would exceed a tenth of it)."""
    row, breaches = twin_breaches(load(name), integrator)
    assert row.passed is True, row.reason
    assert breaches == []


def barely_turning():
    """A box in flight turning at 1e-9 rad/s: 2e-10 rad in 0.2 s, below ten times the angle's
    round-off tolerance (1e-9 rad); its position falls by 0.2 m."""
    return make_scene({"shape": "box", "mass": 1.0, "size": [0.2, 0.1]},
                      {"position": [0.0, 1.0], "angular_velocity": 1e-9}, effects=["gravity"], duration=0.2)


def test_an_angle_that_barely_turns_is_shown_not_judged():
    row, breaches = twin_breaches(barely_turning())
    assert breaches == [] and row.passed is True
    assert row.tolerance_angle is None and row.details["tolerance_angle_shown"] == ROUNDOFF_FLOOR_ANGLE
    assert row.details["motion_angle"] == pytest.approx(2e-10, rel=1e-3)
    assert "the angle is shown, not judged" in row.reason


def test_a_lifted_cap_is_caught(monkeypatch):
    monkeypatch.setattr(dynamics_check, "MOTION_SHARE", 10.0)
    row, breaches = twin_breaches(barely_turning())
    assert row.tolerance_angle == ROUNDOFF_FLOOR_ANGLE and breaches


def test_friction_step_number_under_the_bare_sign_is_its_slope_where_a_point_is_loaded():
    """The friction update's h mu Fn shape'(v) / m_t under the bare sign: its slope is 0 off zero
    slip and infinite at it, and a point in the air (Fn = 0) has no friction at all. A box at
    rest in the air (every slip exactly 0) gives 0, with no warning (0 x inf is no rate); the
    same box resting on the ground gives inf (no explicit step is stable); sliding, 0."""
    scene = dataclasses.replace(load("box_drop"), contact=dataclasses.replace(
        load("box_drop").contact, friction_law="sign", alpha=None))
    rest = scene.body.mass * scene.g / (2 * scene.contact.k)   # the flat box's sag on its two corners, m
    air = np.array([[0.0, 0.3, 0.0, 0.0, 0.0, 0.0]])
    resting = np.array([[0.0, 0.05 - rest, 0.0, 0.0, 0.0, 0.0]])
    sliding = np.array([[0.0, 0.05 - rest, 0.0, 0.5, 0.0, 0.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert dynamics_check.friction_step_number(scene, air) == 0.0
        assert dynamics_check.friction_step_number(scene, resting) == np.inf
        assert dynamics_check.friction_step_number(scene, sliding) == 0.0
