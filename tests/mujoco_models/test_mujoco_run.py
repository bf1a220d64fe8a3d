"""simulate_mujoco's contract: the Trajectory it returns, how it counts, and that rollout's
output is read right (against a plain mj_step loop on the same model)."""
import dataclasses
import math

import mujoco
import numpy as np
import pytest

from compare.scenarios import load, load_builtins
from custom_sim import parse_scene
from mujoco_models import MujocoDiverged, build_model, simulate_mujoco
from mujoco_models.frames import states_from_q
from mujoco_models.geometry import CONTACT_SPHERE_RADIUS
from mujoco_models.rigid_body import rigid_body

STAGES = {"Euler": 1, "implicit": 1, "implicitfast": 1, "RK4": 4}
META_KEYS = {"solref_mapping", "solref", "solimp", "condim", "approximations", "geometry"}


def short(scene, duration=0.05):
    return dataclasses.replace(scene, duration=duration)


@pytest.mark.parametrize("integrator", list(STAGES))
def test_trajectory_fields_and_force_evaluations(integrator):
    scene = short(load("box_drop"))
    tr = simulate_mujoco(scene, integrator=integrator)
    assert tr.simulator == "mujoco" and tr.integrator == integrator
    assert tr.dt == scene.dt and tr.steps == scene.steps == round(0.05 / scene.dt)
    assert tr.t == pytest.approx(np.arange(scene.steps + 1) * scene.dt)
    assert tr.force_evals == scene.steps * STAGES[integrator]
    assert tr.wall_time > 0.0
    assert META_KEYS <= set(tr.meta)
    assert tr.meta["solref_mapping"] == "penalty" and len(tr.meta["solref"]) == 2 and len(tr.meta["solimp"]) == 5
    assert tr.meta["approximations"] and all(isinstance(s, str) for s in tr.meta["approximations"])


@pytest.mark.parametrize("scene", load_builtins(), ids=lambda s: s.name)
def test_every_builtin_runs_with_every_mapping(scene):
    for mapping in ("penalty", "physical", "seed"):
        tr = simulate_mujoco(short(scene, 0.2), solref=mapping)
        assert np.all(np.isfinite(tr.states())), mapping
        assert tr.meta["solref_mapping"] == mapping


def test_defaults_come_from_the_mujoco_table():
    scene = parse_scene({
        "duration": 0.01, "dt": 1e-4, "body": {"shape": "point", "mass": 1.0}, "initial": {"position": [0, 1]},
        "mujoco": {"solref": "physical", "integrator": "RK4", "dt": 5e-4, "cone": "pyramidal"}}, file="<test>")
    tr = simulate_mujoco(scene)
    assert ((tr.integrator, tr.dt, tr.steps, tr.meta["solref_mapping"], tr.meta["cone"])
            == ("RK4", 5e-4, 20, "physical", "pyramidal"))
    assert any("step: MuJoCo runs dt = 0.0005 s" in s for s in tr.meta["approximations"])
    tr = simulate_mujoco(scene, solref="seed", integrator="Euler", dt=1e-3)
    assert (tr.integrator, tr.dt, tr.steps, tr.meta["solref_mapping"]) == ("Euler", 1e-3, 10, "seed")


def test_rollout_rows_are_the_states_of_a_plain_step_loop():
    """The T-shape (COM offset from its geometry frame) bouncing on a corner."""
    scene = short(load("t_shape_drop"), 0.4)
    tr = simulate_mujoco(scene)
    model = build_model(scene)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    qpos, qvel = [data.qpos.copy()], [data.qvel.copy()]
    for _ in range(scene.steps):
        mujoco.mj_step(model, data)
        qpos.append(data.qpos.copy())
        qvel.append(data.qvel.copy())
    loop = states_from_q(rigid_body(scene.body), np.array(qpos), np.array(qvel))
    assert np.min(tr.y) < 0.2, "it touched the ground"
    assert np.allclose(tr.states(), loop, rtol=0, atol=1e-12)
    # and the COM is MuJoCo's own xipos (mj_step leaves the kinematics of the step's start)
    mujoco.mj_kinematics(model, data)
    assert data.xipos[1][[0, 2]] == pytest.approx(tr.states()[-1, :2], abs=1e-12)


def test_same_input_same_trajectory_bit_for_bit():
    scene = short(load("t_shape_drop"), 0.5)
    a, b = simulate_mujoco(scene), simulate_mujoco(scene)
    assert np.array_equal(a.states(), b.states())


def test_energy_is_contract_formula_on_mujoco_state():
    """kinetic + m g y + sum of k d^2 / 2 over the corners, computed here by hand; MuJoCo's
    contact distance is the corner's depth plus the contact sphere's radius."""
    scene = short(load("box_drop"), 0.35)          # the corner lands near 0.25 s
    tr = simulate_mujoco(scene)
    m, k, (w, h) = scene.body.mass, scene.contact.k, scene.body.size
    inertia = m * (w * w + h * h) / 12
    touched = 0
    for i in range(0, tr.steps + 1, 97):
        x, y, th, vx, vy, om = tr.states()[i]
        depth = [max(0.0, CONTACT_SPHERE_RADIUS - (y + math.sin(th) * cx + math.cos(th) * cy))
                 for cx, cy in ((-w / 2, -h / 2), (w / 2, -h / 2), (w / 2, h / 2), (-w / 2, h / 2))]
        touched += any(depth)
        expected = 0.5 * m * (vx * vx + vy * vy) + 0.5 * inertia * om * om + m * 9.81 * y + sum(0.5 * k * d * d for d in depth)
        assert tr.energy[i] == pytest.approx(expected, rel=1e-12, abs=1e-12)
    assert touched


def test_a_run_that_blows_up_raises():
    """k = 1e8 N/m on 1 kg at dt = 1e-3 s: h wn = 10, far beyond semi-implicit Euler's 2."""
    scene = parse_scene({
        "duration": 0.5, "dt": 1e-3, "effects": ["gravity", "contact"], "body": {"shape": "point", "mass": 1.0},
        "contact": {"k": 1e8, "c": 0.0, "damping_law": "linear"}, "initial": {"position": [0, 0.1]}}, file="<test>")
    with pytest.raises(MujocoDiverged, match="blew up"):
        simulate_mujoco(scene)


def test_mapping_table_rows():
    from compare.tools.accuracy.mapping_table import mapping_errors, max_position_difference

    errors = mapping_errors(short(load("elastic_bounce"), 0.5))
    assert set(errors) == {"penalty", "physical", "seed", "penalty_vs_linear_law", "ns_per_step"}
    assert errors["penalty"] < 1e-5 < errors["seed"], "the penalty twin follows the bounce, the seed one does not"
    a = simulate_mujoco(short(load("point_drop"), 0.01))
    with pytest.raises(ValueError, match="step counts"):
        max_position_difference(a, simulate_mujoco(short(load("point_drop"), 0.02)))
