"""Contact force at the same state: MuJoCo under the penalty mapping against our force law.

Ours: custom_sim.forces.accelerations (the hand-written law) times the mass and inertia.
MuJoCo: qfrc_constraint and mj_contactForce after mj_forward. Gravity is off unless a case
needs it, so MuJoCo's unconstrained acceleration a0 is 0 and its normal force is (solref.py)

    f = F / (1 + d (A / A_hat - 1)),   F = max(0, k depth - c v)  (our linear law)

with d the impedance, A the contact's true inverse inertia and A_hat MuJoCo's approximation.
"""
import mujoco
import numpy as np
import pytest

from custom_sim import mass_properties, parse_scene
from custom_sim.bodies import contact_points_world
from custom_sim.forces import accelerations
from custom_sim.model import build_model as build_ours
from mujoco_models import build_spec
from mujoco_models.frames import qpos_qvel
from mujoco_models.rigid_body import rigid_body
from mujoco_models.friction import FRICTION_IMPRATIO
from mujoco_models.geometry import CONTACT_SPHERE_RADIUS
from mujoco_models.solref import PENALTY_IMPEDANCE, a_hat

K, C, MU = 1e4, 20.0, 0.5
ROUNDOFF = 1e-10   # relative: the solver's answer for one contact is a closed formula


def scene(shape, effects=("contact",), cone="elliptic", **body):
    b = {"point": {"shape": "point", "mass": 1.0, "contact_height": 0.0},
         "box": {"shape": "box", "mass": 1.0, "size": [0.2, 0.1]}}[shape]
    b.update(body)
    return parse_scene({"duration": 0.1, "dt": 1e-4, "effects": list(effects), "body": b,
                        "contact": {"k": K, "c": C, "mu": MU, "damping_law": "linear"},
                        "initial": {"position": [0.0, 1.0]}, "mujoco": {"cone": cone}}, file="<test>")


def forward(sc, state, spec=None):
    spec = spec or build_spec(sc, "penalty")
    model = spec.compile()
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = qpos_qvel(rigid_body(sc.body), state)
    mujoco.mj_forward(model, data)
    return model, data


def ours(sc, state):
    """(Fx N, Fy N, tau N m) of our force law at the state."""
    props = mass_properties(sc.body)
    model, points = build_ours(sc, props)
    ax, ay, aw = accelerations(model, points, np.asarray(state, float), 0.0, 0.0, 0.0)
    return np.array([ax * props.mass, ay * props.mass, aw * props.inertia])


def contact_frame_force(model, data, i=0):
    f = np.zeros(6)
    mujoco.mj_contactForce(model, data, i, f)
    return f[0], f[1:3]    # normal, tangential (2)


@pytest.mark.parametrize("vy", [-0.3, 0.2, 1.5])   # approaching, receding, receding too fast: 0
def test_point_normal_force_is_ours_exactly(vy):
    """A point mass has A = A_hat = 1/m (MuJoCo's shortcut for a body without rotation)."""
    sc = scene("point")
    state = [0.0, -2e-3, 0.0, 0.0, vy, 0.0]
    model, data = forward(sc, state)
    expected = ours(sc, state)
    assert expected[1] == pytest.approx(max(0.0, K * 2e-3 - C * vy), rel=1e-12)
    assert data.qfrc_constraint[1] == pytest.approx(expected[1], rel=ROUNDOFF, abs=1e-12), "Fn"


def test_tilted_box_corner_force_and_torque_within_the_impedance_bound():
    sc = scene("box")
    props = mass_properties(sc.body)
    theta, depth = 0.4, 2e-3
    px, py = contact_points_world(props, 0.0, 0.0, theta)
    low = int(np.argmin(py))
    state = [0.0, -py[low] - depth, theta, 0.1, -0.3, 2.0]
    model, data = forward(sc, state)
    assert data.ncon == 1
    expected = ours(sc, state)
    # bound: relative d |A/A_hat - 1| from the impedance, plus the sphere's radius in the depth
    rx = px[low]
    inv_mass = 1.0 / props.mass + rx * rx / props.inertia
    fn = expected[1]
    rel = PENALTY_IMPEDANCE * abs(inv_mass / a_hat(model) - 1.0) + K * CONTACT_SPHERE_RADIUS / fn + ROUNDOFF
    got = data.qfrc_constraint
    assert got[0] == pytest.approx(0.0, abs=1e-9), "no friction listed: no tangential force"
    assert got[1] == pytest.approx(fn, rel=rel), "normal force"
    assert got[2] == pytest.approx(expected[2], rel=rel), "torque r x F about the COM"
    assert abs(got[1] / fn - 1.0) > 0.1 * PENALTY_IMPEDANCE, "the bound is not vacuous: A != A_hat"


@pytest.mark.parametrize("slip", [0.05, 0.2, 3.0])
def test_penalty_friction_is_viscous_c_t_capped_at_mu_fn(slip):
    """No gravity: c_t = c; the point's A_t = 1/m is the A_ref the damping was set for, so
    f_t = -min(c v, mu Fn), and the normal force stays k depth up to the cone projection's
    mu c v (A_t + R_t) / R_n (friction.py), which is 2 mu c v / impratio here."""
    sc = scene("point", effects=("contact", "friction"))
    depth = 1e-3
    model, data = forward(sc, [0.0, -depth, 0.0, slip, 0.0, 0.0])
    fn, ft = contact_frame_force(model, data)
    fn_spring = K * depth
    inflation = 2 * MU * C * slip / FRICTION_IMPRATIO
    assert fn == pytest.approx(fn_spring, abs=inflation + 1e-9), "normal force"
    assert np.linalg.norm(ft) == pytest.approx(min(C * slip, MU * fn), rel=1e-6), "|friction|"
    assert data.qfrc_constraint[0] < 0.0, "friction opposes the slip"


def test_penalty_friction_slope_is_the_tanh_slope_at_rest():
    """With gravity, c_t = mu alpha m g (one resting contact): our tanh law's slope at zero slip."""
    sc = scene("point", effects=("gravity", "contact", "friction"))
    depth, slip = 9.81 / K, 1e-3
    model, data = forward(sc, [0.0, -depth, 0.0, slip, 0.0, 0.0])
    fn, ft = contact_frame_force(model, data)
    ours_ft = ours(sc, [0.0, -depth, 0.0, slip, 0.0, 0.0])[0]
    # ours: mu Fn tanh(alpha v) = mu Fn alpha v (1 - (alpha v)^2 / 3 + ...): 3e-3 relative at alpha v = 0.1
    assert np.linalg.norm(ft) == pytest.approx(-ours_ft, rel=(100 * slip) ** 2 / 3 + 1e-3)


def test_default_impratio_would_raise_the_normal_force_while_sliding():
    """Why friction.py sets impratio: at MuJoCo's default 1 the elliptic cone's projection gives
    Fn = (k d + mu c v) / (1 + mu^2) once c v > mu k d."""
    sc = scene("point", effects=("contact", "friction"))
    spec = build_spec(sc, "penalty")
    spec.option.impratio = 1.0
    for p in spec.pairs:
        p.solreffriction = [0.0, 0.0]
    depth, slip = 1e-3, 3.0
    model, data = forward(sc, [0.0, -depth, 0.0, slip, 0.0, 0.0], spec)
    fn, _ = contact_frame_force(model, data)
    assert fn == pytest.approx((K * depth + MU * C * slip) / (1 + MU * MU), rel=1e-3)


def test_pyramidal_cone_normal_force_is_scaled_back_to_ours():
    """The 2 (n - 1) pyramid rows share R_py = 2 mu^2 (1 + mu^2) (1 - d) / d A_hat and feel each
    other through A (each about 1 + mu^2 here): relative error 2 (n - 1) (1 + mu^2) A / R_py."""
    sc = scene("point", effects=("contact", "friction"), cone="pyramidal")
    model, data = forward(sc, [0.0, -1e-3, 0.0, 0.0, 0.0, 0.0])
    d, n = PENALTY_IMPEDANCE, 3
    r_py = 2 * MU**2 * (1 + MU**2) * (1 - d) / d * a_hat(model)
    rel = 2 * (n - 1) * (1 + MU**2) * (1.0 / sc.body.mass) / r_py
    assert data.qfrc_constraint[1] == pytest.approx(K * 1e-3, rel=rel)
