"""The catalogue of known mistakes: each, put into a trajectory, is named by diagnose; a user's
step function with a mistake is named from a few moments; and nothing is guessed."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from compare.oracle.force_law import contact_state
from compare.oracle.reference import Equations
from compare.scenarios import load
from compare.diagnosis.mistakes import (BY_NAME, CATALOGUE, applicable, combine, diagnose,
                                      diagnose_step, pick_moments)
from custom_sim import simulate

import seed_box

# Where each mistake shows: scene and integrator. Every entry of the catalogue is here.
SHOWN_ON = {
    "friction_on_com_velocity": ("box_drop", "semi_implicit_euler"),
    "box_inertia_about_corner": ("box_drop", "implicit_euler"),
    "box_inertia_width_only": ("box_drop", "semi_implicit_euler"),
    "compound_inertia_without_parallel_axis": ("t_shape_drop", "semi_implicit_euler"),
    "compound_points_not_about_com": ("t_shape_drop", "semi_implicit_euler"),
    "disk_inertia_of_a_ring": ("rolling_circle", "semi_implicit_euler"),
    "torque_sign_flipped": ("spinning_box", "rk4"),
    "damping_in_the_air": ("point_drop", "semi_implicit_euler"),
    "linear_damping_for_compression": ("point_drop", "semi_implicit_euler"),
    "compression_damping_for_linear": ("box_drop", "semi_implicit_euler"),
    "explicit_euler_in_disguise": ("point_drop", "semi_implicit_euler"),
    "semi_implicit_for_explicit": ("elastic_bounce", "explicit_euler"),
    "friction_sign_not_tanh": ("point_drop", "semi_implicit_euler"),
    "friction_on_total_normal_force": ("box_slide", "semi_implicit_euler"),
    "gravity_without_mass": ("point_drop", "rk4"),
    "rolling_resistance_bare_sign": ("rolling_circle", "semi_implicit_euler"),
    "rolling_resistance_missing": ("rolling_circle", "semi_implicit_euler"),
    "contact_height_ignored": ("point_drop", "semi_implicit_euler"),
    "corners_not_rotated": ("box_drop", "explicit_euler"),
}
WINDOW = 500          # steps of STEP_UNIT, from BEFORE of them ahead of the first contact
BEFORE = 200
STEP_UNIT = 1e-4      # s: the windows are times, counted in steps of this size


def steps_of(scene, n):
    """n steps of STEP_UNIT in the scene's own steps."""
    return max(1, round(n * STEP_UNIT / scene.dt))


def start_near_contact(scene):
    """custom_sim's state BEFORE steps before the first contact (or the initial state)."""
    sc = dataclasses.replace(scene, duration=min(scene.duration, 1.0))
    states = simulate(sc).states()
    depth, _ = contact_state(Equations.from_scene(scene), states)
    touch = np.flatnonzero((depth > 0).any(axis=1))
    return states[max(0, (touch[0] if touch.size else 0) - steps_of(scene, BEFORE))]


def variant_trajectory(mistake, scene, integrator, steps=WINDOW):
    f = mistake.step_fn(scene, integrator)
    steps = steps_of(scene, steps)
    out = np.empty((steps + 1, 6))
    out[0] = start_near_contact(scene)
    for i in range(steps):
        out[i + 1] = f(out[i], None, scene.dt)
    return out


def test_catalogue_is_documented_and_covered():
    assert len(CATALOGUE) >= 10
    assert set(SHOWN_ON) == set(BY_NAME)
    for m in CATALOGUE:
        assert m.seed_line and m.description and m.name
        scene, integrator = SHOWN_ON[m.name]
        assert m in applicable(dataclasses.replace(load(scene), integrator=integrator), integrator)


@pytest.mark.parametrize("name", list(SHOWN_ON))
def test_diagnose_names_the_mistake(name):
    scene_name, integrator = SHOWN_ON[name]
    scene = dataclasses.replace(load(scene_name), integrator=integrator)
    # implicit Euler and RK4 steps one row at a time cost more: a shorter window, still 100
    # steps past the first contact
    states = variant_trajectory(BY_NAME[name], scene, integrator,
                                WINDOW if integrator in ("explicit_euler", "semi_implicit_euler") else BEFORE + 100)
    out = diagnose(scene, states, integrator, scene.dt)
    assert out["step"].passed is False
    assert out["explained_by"] == [name], out["verdict"]
    assert BY_NAME[name].seed_line in out["verdict"]


def test_two_mistakes_are_named_as_a_pair():
    """Issue 11's buggy copy: friction on the COM velocity and inertia m (w^2 + h^2) / 3."""
    pair = combine(BY_NAME["friction_on_com_velocity"], BY_NAME["box_inertia_about_corner"])
    scene = load("box_drop")
    states = variant_trajectory(pair, scene, scene.integrator)
    out = diagnose(scene, states, scene.integrator, scene.dt)
    assert out["explained_by"] == [pair.name], out["verdict"]


def test_a_mistake_outside_the_catalogue_is_not_guessed():
    """A stiffness 1 % off is no catalogued mistake: the diagnosis says so and gives the residual."""
    scene = load("point_drop")
    stiffer = dataclasses.replace(scene, contact=dataclasses.replace(scene.contact, k=1.01 * scene.contact.k))
    states = simulate(dataclasses.replace(stiffer, duration=0.4)).states()
    out = diagnose(scene, states, scene.integrator, scene.dt)
    assert out["step"].passed is False and out["explained_by"] == []
    # a stiffer ground changes Fn, seen first in vy or through the friction it bounds in vx
    assert "no catalogued mistake" in out["verdict"] and out["step"].details["component"] in ("vx", "vy")
    assert "contact at point 0" in out["step"].details["phase"]


def test_a_correct_trajectory_has_nothing_to_explain():
    scene = load("box_slide")
    out = diagnose(scene, simulate(dataclasses.replace(scene, duration=0.2)).states(),
                   scene.integrator, scene.dt)
    assert out["step"].passed is True and out["explained_by"] == []


def test_diagnose_step_from_moments_names_the_mistake():
    """A user's step with the torque sign flipped (the tests' own seed box, not a variant):
    it agrees in flight and disagrees in omega wherever a corner touches."""
    scene = load("box_drop")
    moments = pick_moments(scene, simulate(scene).states())
    names = [n for n, _ in moments]
    assert {"in flight", "touchdown", "rebound", "sliding contact", "resting"} <= set(names), names
    # every contact moment is a state with a point touching (the touchdown too: the step from
    # the last state in flight feels no contact force and would prove nothing)
    depth, _ = contact_state(Equations.from_scene(scene), np.array([z for _, z in moments]))
    assert all((d > 0).any() == (n != "in flight") for n, d in zip(names, depth)), names

    def user_step(state, scene_dict, dt):
        return seed_box.box_step(state, scene, dt, torque_sign=-1.0)
    out = diagnose_step(user_step, scene, moments)
    by_name = {e["name"]: e for e in out["moments"]}
    assert by_name["in flight"]["agrees"]
    assert not by_name["sliding contact"]["agrees"] and by_name["sliding contact"]["component"] == "omega"
    assert out["explained_by"] == ["torque_sign_flipped"], out["verdict"]


def test_diagnose_step_rolling_moment_of_a_disk():
    scene = load("rolling_circle")
    moments = pick_moments(scene, simulate(scene).states())
    assert "rolling" in [n for n, _ in moments]
    ring = BY_NAME["disk_inertia_of_a_ring"].step_fn(scene, scene.integrator)
    out = diagnose_step(ring, scene, moments)
    assert out["explained_by"] == ["disk_inertia_of_a_ring"], out["verdict"]
    correct = diagnose_step(lambda z, s, dt: simulate_one(scene, z), scene, moments)
    assert correct["disagree"] == [], correct["verdict"]


def simulate_one(scene, z):
    """custom_sim's own step from z (a faithful simulator)."""
    from custom_sim import Stepper
    st = Stepper(scene)
    st.reset(z)
    return st.advance(1).copy()
