"""Check `contact`: MuJoCo's own contact with friction off, held to the mapping's measured error.

The check earns trust three ways: the force error it reads from MuJoCo explains MuJoCo's force
(and its A matches the rigid-body formula it never uses); every built-in scene passes it with a
tolerance below a tenth of its motion (tests/test_against_mujoco.py); and typical mistakes put
into custom_sim fail it.
"""
import dataclasses

import mujoco
import numpy as np
import pytest

import compare.checks.contact_check as contact_check
from compare.scenarios import builtin_names, load
from compare.checks.contact_check import check_contact, contact_scene
from compare.checks.identical_check import check_identical
from compare.checks.impedance import mapping_error, native_run
from custom_sim import mass_properties
from custom_sim.chatter import WATCH_COLUMNS
from custom_sim.integrators import INTEGRATORS, integrate
from custom_sim.model import build_model, initial_state
from custom_sim.runner import blowup_guard
from mujoco_models.run import setup_rollout
from tests.conftest import make_scene

# MuJoCo's force and f* - e agree to round-off of the force sums (1e-16 relative per term)
FORCE_IDENTITY = 1e-9


def short(name: str, duration: float):
    scene = load(name)
    return dataclasses.replace(scene, duration=duration)


def test_force_error_explains_mujocos_force():
    """e = d [(A / A_hat - 1) f + a0 / A_hat] is MuJoCo's force minus our k d - c v, row by row."""
    err = mapping_error(contact_scene(short("box_drop", 0.6)))
    assert err.steps > 100
    assert err.force_check < FORCE_IDENTITY, f"residual {err.force_check:.2e} of the largest force"
    # a box's corner: A = 1/m + r_x^2 / I >= 1/m = 1.5 A_hat, about 5 A_hat far out to the side
    assert err.ratio_min >= 1.5 * (1 - 1e-12) and err.ratio_max > 4.0
    assert 1e-4 < err.relative < 1e-3, err.relative


def test_mujocos_inverse_inertia_is_the_rigid_body_one():
    """A = J M^-1 J^T read from MuJoCo equals 1/m + r_x^2 / I at a tilted box's touching corner:
    the formula the check never uses, computed from the scene alone."""
    scene = contact_scene(load("box_drop"))
    props = mass_properties(scene.body)
    twin, model, data, start, _ = setup_rollout(scene, "penalty")
    theta = 0.4
    corner = props.points[0]
    c, s = np.cos(theta), np.sin(theta)
    rx, ry = c * corner[0] - s * corner[1], s * corner[0] + c * corner[1]
    data.qpos[:] = [0.0, -ry - 1e-4, theta]   # the lowest corner 0.1 mm deep
    data.qvel[:] = 0.0
    mujoco.mj_forward(model, data)
    assert data.nefc == 1
    J = np.array(data.efc_J[:3]).reshape(1, 3)
    x = np.empty((1, 3))
    mujoco.mj_solveM(model, data, x, J)
    A = float((J @ x.T)[0, 0])
    assert A == pytest.approx(1 / props.mass + rx * rx / props.inertia, rel=1e-6)
    assert float(data.efc_diagA[0]) == pytest.approx(2 / (3 * props.mass), rel=1e-9)


def mistaken(scene, mass=1.0, inertia=1.0, points=1.0, law=None):
    """custom_sim's states with a typical mistake: the mass or inertia off by a factor (in the
    contact's acceleration, as a wrong m or I in F / m, tau / I), contact points scaled, or the
    damping law ignored."""
    props = mass_properties(scene.body)
    model, pts = build_model(scene, props)
    model = model._replace(inv_mass=model.inv_mass / mass, inv_inertia=model.inv_inertia / inertia)
    if law is not None:
        model = model._replace(damping_law=law)
    z = initial_state(scene)
    out = np.empty((scene.steps + 1, 6))
    out[0] = z
    integrate(model, np.ascontiguousarray(pts * points), z, scene.dt, scene.steps,
              INTEGRATORS[scene.integrator].code, np.zeros((1, 3)), out[1:], np.zeros(4, dtype=np.int64),
              blowup_guard(scene, props, z, applied_input=False), np.empty((0, WATCH_COLUMNS)))
    return out


@pytest.mark.parametrize("name, mistake", [
    ("box_drop", {"inertia": 1.1}),
    ("box_drop", {"mass": 1.1}),
    ("box_drop", {"points": 1.05}),
    ("t_shape_drop", {"inertia": 1.1}),
    ("point_drop", {"mass": 1.1}),
    ("point_drop", {"law": 0}),     # the compression law where the check asks for the linear one
    ("box_slide", {"points": 1.05}),
], ids=lambda v: v if isinstance(v, str) else ",".join(f"{k}={x}" for k, x in v.items()))
def test_a_known_mistake_fails(name, mistake):
    scene = short(name, 0.8)
    row = check_contact(scene, mistaken(contact_scene(scene), **mistake))
    assert row.passed is False, (f"{name} with {mistake}: {row.position_error_max:.3e} m within "
                                 f"{row.tolerance_position:.3e} m")


def test_the_right_states_pass_when_given():
    scene = short("t_shape_drop", 0.8)
    row = check_contact(scene, mistaken(contact_scene(scene)))
    assert row.passed is True, row.reason


def test_without_contact_it_is_not_judged():
    scene = make_scene({"shape": "box", "mass": 1.0, "size": [0.2, 0.1]},
                       {"position": [0.0, 1.0], "angular_velocity": 3.0}, effects=["gravity"], duration=0.2)
    row = check_contact(scene)
    assert row.passed is None and row.reason.startswith("not judged")
    assert row.tolerance_position is None


def test_an_integrator_mujoco_lacks_adds_its_measured_difference():
    """Explicit Euler has no MuJoCo counterpart: the tolerance adds custom_sim's measured
    difference between it and MuJoCo's update, and a wrong inertia still fails."""
    scene = dataclasses.replace(short("t_shape_drop", 0.8), integrator="explicit_euler")
    right = check_contact(scene)
    assert right.passed is True and right.details["integrator_position_max"] > 0.0, right.reason
    assert "explicit_euler" in right.reason
    wrong = check_contact(scene, mistaken(contact_scene(scene), inertia=1.1))
    assert wrong.passed is False, wrong


# The rule every judged tolerance obeys, written here on its own (not read from the checks): a
# check whose cap is lifted (MOTION_SHARE = 10) judges with a tolerance above it, and fails here.
A_TENTH = 0.1


def rule_breaches(row: dict, reference: np.ndarray, dt: float) -> list[str]:
    """The judged tolerances of `row` above a tenth of the motion over its judged window
    [0, judged_until], the motion measured here from `reference` (states every dt): the range of
    the COM path (m) and of the angle (rad)."""
    if row.passed is None:
        return []
    until = row.details.get("judged_until")
    assert until is not None, f"{row.name}: a judged row names its window"
    window = reference[np.arange(len(reference)) * dt <= until + 1e-9 * dt]
    spans = window.max(axis=0) - window.min(axis=0)
    moved, turned = float(np.hypot(spans[0], spans[1])), float(spans[2])
    out = []
    if row.tolerance_position is None or row.tolerance_position > A_TENTH * moved:
        out.append(f"{row.name}: position tolerance {row.tolerance_position} m, motion {moved:.4g} m")
    if row.tolerance_angle is not None and row.tolerance_angle > A_TENTH * turned:
        out.append(f"{row.name}: angle tolerance {row.tolerance_angle:.4g} rad, motion {turned:.4g} rad")
    return out


def contact_breaches(scene) -> list[str]:
    row = check_contact(scene)
    assert row.passed is not None, row.reason
    native, twin, _ = native_run(contact_scene(scene))
    return rule_breaches(row, native, twin.dt)


@pytest.mark.parametrize("name", builtin_names())
def test_every_judged_contact_tolerance_is_within_a_tenth_of_the_motion(name):
    """Position and angle, each against the motion of MuJoCo's run (friction off) over the
    judged window. box_drop's angle: 0.253 rad judged against a tumble of 2.53 rad."""
    assert contact_breaches(load(name)) == []


def test_a_lifted_cap_is_caught(monkeypatch):
    """With the contact check's share of the motion lifted to 10, box_drop is judged over its
    whole run with a tolerance of a fifth of its motion: the rule above sees it."""
    monkeypatch.setattr(contact_check, "MOTION_SHARE", 10.0)
    assert contact_breaches(load("box_drop"))


@pytest.mark.parametrize("name", builtin_names())
def test_every_judged_identical_tolerance_is_within_a_tenth_of_the_motion(name):
    """check identical on custom_sim's own states (what a faithful simulator gives)."""
    from custom_sim import simulate

    scene = load(name)
    states = simulate(scene).states()
    row = check_identical(scene, states, scene.integrator, scene.dt, None)
    assert row.passed is True, row.reason
    assert rule_breaches(row, states, scene.dt) == []


@pytest.mark.parametrize("name, runs", [("elastic_bounce", 0), ("box_drop", 1)])
def test_a_users_code_runs_again_only_for_a_variant_that_differs_from_the_scene(monkeypatch, name, runs):
    """elastic_bounce is frictionless under the linear law: it is its own contact variant, and
    the check judges the scene's run of the simulator under test, with the row a second run of
    the variant gives. The simulator is an outsider's whose law differs from the scene's, so its
    row fails where custom_sim's run (round-off from the seed example's) would pass. The runs
    end at 0.6 s, after the first landing (0.45 s for elastic_bounce's 1 m fall)."""
    from pathlib import Path

    import compare.usersim as usersim
    from compare.checks.case import Case
    from compare.checks.check import Runs
    from compare.checks.units import contact_row

    scene = dataclasses.replace(load(name), duration=0.6)
    assert (contact_scene(scene) == scene) == (runs == 0)
    outsider = Path(__file__).resolve().parents[2] / "outsiders" / "rk4_smooth_unclamped.py"
    sim = usersim.load_simulator(f"{outsider}:step")
    run, case = usersim.run_user(sim, scene), Case(scene)
    again = check_contact(scene, usersim.run_user(sim, contact_scene(scene)).states(), run.integrator, case=case)
    calls = []
    real = usersim.run_user
    monkeypatch.setattr(usersim, "run_user", lambda sim, s: calls.append(s.name) or real(sim, s))
    row = contact_row(Runs(case, run, {run.integrator: run}, {}, sim))
    assert len(calls) == runs
    # the outsider applies friction whatever the effects say (box_drop's mu 0.5; elastic_bounce's vx
    # stays 0): the row tells so, the rest is check_contact's
    assert ("horizontal_force" in row.details) == (runs == 1)
    assert row.passed is False and dataclasses.replace(row, reason=again.reason, details=again.details) == again


# A seed-style point mass whose step applies friction whatever scene["effects"] says.
FRICTION_ALWAYS = '''
import math

def step(state, scene, dt):
    x, y, th, vx, vy, om = (float(v) for v in state)
    m, ct = scene["mass_properties"]["mass"], scene["contact"]
    fx, fy = 0.0, -m * scene["g"]
    d = -(y - scene["mass_properties"]["contact_points"][0][1])
    if d > 0.0:
        fn = max(0.0, ct["k"] * d - ct["c"] * vy)
        fx, fy = -ct["mu"] * fn * math.tanh(ct["alpha"] * vx), fy + fn
    vx, vy = vx + dt * fx / m, vy + dt * fy / m
    return [x + dt * vx, y + dt * vy, th, vx, vy, om]
'''


def test_a_step_that_applies_friction_with_friction_off_is_told_so(tmp_path):
    """Before: the contact row failed by metres, unexplained. In the friction-off variant no
    horizontal force acts, so vx must stay exactly what it was; this step changes it at the
    first touching step by mu Fn tanh(alpha vx) dt / m."""
    import compare.usersim as usersim
    from compare.checks.case import Case
    from compare.checks.check import Runs
    from compare.checks.units import contact_row
    from compare.run.lines import failure_text

    path = tmp_path / "friction_always.py"
    path.write_text(FRICTION_ALWAYS)
    sim = usersim.load_simulator(f"{path}:step")
    scene = dataclasses.replace(load("point_drop"), duration=0.4)
    run = usersim.run_user(sim, scene)
    row = contact_row(Runs(Case(scene), run, {run.integrator: run}, {}, sim))
    applied = row.details["horizontal_force"]
    states = usersim.run_user(sim, contact_scene(scene)).states()
    first = int(np.flatnonzero(np.diff(states[:, 3]) != 0.0)[0])
    assert applied["step"] == first + 1 and applied["dvx"] == states[first + 1, 3] - states[first, 3]
    assert row.reason.startswith("your step applied a horizontal force in this friction-off variant")
    if row.passed is False:
        assert "horizontal force with friction off" in failure_text(row)


def test_a_step_that_honours_the_effects_is_not_told_anything():
    from compare.checks.contact_check import horizontal_force
    from custom_sim import simulate

    scene = contact_scene(dataclasses.replace(load("box_drop"), duration=0.6))
    assert horizontal_force(scene, simulate(scene).states()) is None
