"""Check ground (compare/checks/ground_check.py): a body that falls through the ground fails at
the step the energy balance of the free fall says; custom_sim's own runs never do."""
import dataclasses
import math

import numpy as np
import pytest

from compare.checks.ground_check import ground_row
from compare.scenarios import load
from custom_sim import mass_properties, simulate
from custom_sim.runner import ENERGY_FLOOR, ENERGY_GROWTH_LIMIT


def free_fall(scene):
    """The analytic states of the scene's body falling with no contact force at all (a step that
    forgot the ground): y = y0 + vy0 t - g t^2 / 2, the rest carried along."""
    t = np.arange(scene.steps + 1) * scene.dt
    x0, y0 = scene.initial.position
    vx0, vy0 = scene.initial.velocity
    om0 = scene.initial.angular_velocity
    return np.column_stack([x0 + vx0 * t, y0 + vy0 * t - scene.g * t * t / 2, scene.initial.angle + om0 * t,
                            np.full_like(t, vx0), vy0 - scene.g * t, np.full_like(t, om0)])


def test_a_point_that_falls_through_the_ground_fails_where_its_spring_would_hold_too_much():
    """point_drop with no contact force: its contact point sits py below the COM (py < 0), the
    lowest pose the budget counts from is the COM at y_low = -|py|; kinetic + m g (y - y_low)
    stays E0 = m vx0^2 / 2 + m g (y0 - y_low) exactly (free fall from rest vertically), so the
    total with the spring's k d^2 / 2 (d = -(y + py)) passes the budget B = 10 max(E0, 1 J * m)
    where k d^2 / 2 = B - E0: the first step whose depth exceeds that d."""
    scene = dataclasses.replace(load("point_drop"), duration=1.5)
    props = mass_properties(scene.body)
    m, (_, y0), k, py = props.mass, scene.initial.position, scene.contact.k, float(props.points[0][1])
    vx0, vy0 = scene.initial.velocity
    assert vy0 == 0.0 and props.points.shape == (1, 2) and props.points[0][0] == 0.0
    y_low = -abs(py)
    e0 = 0.5 * m * vx0 * vx0 + m * scene.g * (y0 - y_low)             # J
    budget = ENERGY_GROWTH_LIMIT * max(e0, ENERGY_FLOOR * m)
    depth = math.sqrt(2.0 * (budget - e0) / k)                         # m
    fall = math.sqrt(2.0 * (y0 + py + depth) / scene.g)                # s: y0 - g t^2 / 2 = -py - depth
    row = ground_row(scene, free_fall(scene), "semi_implicit_euler")
    assert row.passed is False
    assert row.details["first_step"] == math.floor(fall / scene.dt) + 1
    assert row.details["energy_budget"] == pytest.approx(budget, rel=1e-12)
    assert row.reason.startswith(f"the body sank through the ground: at step {row.details['first_step']} ")


def test_a_box_that_falls_through_fails_and_one_that_stays_on_it_passes():
    """box_drop: custom_sim's run stays within the budget; the same box with no contact force
    does not (its four corners' springs outgrow any energy the drop had)."""
    scene = dataclasses.replace(load("box_drop"), duration=1.0)
    held = ground_row(scene, simulate(scene).states(), scene.integrator)
    fell = ground_row(scene, free_fall(scene), scene.integrator)
    assert held.passed is True and held.details["energy_max"] <= held.details["energy_budget"]
    assert fell.passed is False


@pytest.mark.parametrize("name", ["box_drop", "box_slide", "elastic_bounce", "point_drop", "rolling_circle",
                                  "spinning_box", "t_shape_drop"])
def test_custom_sims_runs_of_every_built_in_pass(name):
    """Every built-in scene with each of custom_sim's integrators that runs it (first 2 s):
    no row fails, so the check changes no built-in's verdict."""
    from custom_sim import INTEGRATORS, SimulationDiverged

    scene = load(name)
    scene = dataclasses.replace(scene, duration=min(scene.duration, 2.0))
    judged = 0
    for integrator in INTEGRATORS:
        try:
            states = simulate(dataclasses.replace(scene, integrator=integrator)).states()
        except SimulationDiverged:
            continue
        row = ground_row(scene, states, integrator)
        assert row.passed is True, row.reason
        judged += 1
    assert judged >= 1


def test_a_scene_without_gravity_or_contact_is_not_judged():
    scene = dataclasses.replace(load("point_drop"), duration=0.1)
    off = dataclasses.replace(scene, effects=tuple(e for e in scene.effects if e != "contact"))
    row = ground_row(off, free_fall(scene), "rk4")
    assert row.passed is None and row.reason == "not judged: the scene has no ground to fall through"
