"""The compiled twin against the scene: inertias, frames, geometry choice, A_hat, the MJCF file."""
import math

import mujoco
import numpy as np
import pytest

from compare.scenarios import load, load_builtins
from custom_sim import mass_properties
from custom_sim.bodies import contact_points_world
from mujoco_models import build_model, build_spec, to_mjcf
from mujoco_models.frames import qpos_qvel
from mujoco_models.geometry import CONTACT_SPHERE_RADIUS
from mujoco_models.solref import a_hat

BUILTINS = load_builtins()
IDS = [s.name for s in BUILTINS]
REL = 1e-12   # derived and compiled values are the same formulas: round-off only
# MuJoCo's XML writer keeps 6 significant digits: a number read back is off by at most
# half a unit in the 6th digit, 5e-6 of itself when that digit is the leading 1 of 1.00000.
MJCF_DIGITS_REL = 5e-6


@pytest.mark.parametrize("scene", BUILTINS, ids=IDS)
def test_compiled_mass_com_and_inertia_are_custom_sims(scene):
    """Two codes, one answer: the twin's inertial (its own rigid_body.py) against custom_sim's."""
    props = mass_properties(scene.body)
    model = build_model(scene)
    b = model.body("body").id
    assert model.body_mass[b] == pytest.approx(props.mass, rel=REL), "mass"
    assert model.body_ipos[b] == pytest.approx([props.com[0], 0.0, props.com[1]], abs=1e-15), "COM"
    assert np.allclose(model.body_iquat[b], [1, 0, 0, 0]), "inertia axes are the body axes"
    ixx, iyy, izz = model.body_inertia[b]
    if props.rotates:
        assert iyy == pytest.approx(props.inertia, rel=REL), "I about the hinge axis y"
    if scene.body.shape == "circle":  # the seed's cylinder, radius R, length 2R along y
        m, R = props.mass, scene.body.radius
        assert (ixx, iyy, izz) == pytest.approx((m * R**2 / 4 + m * (2 * R)**2 / 12, m * R**2 / 2,
                                                 m * R**2 / 4 + m * (2 * R)**2 / 12), rel=REL)


def test_t_shape_off_axis_inertias_by_hand():
    """Boards as deep as their smaller side (t = 0.06 m): Ixx = sum m ((h^2 + t^2)/12 + dz^2)."""
    ixx, iyy, izz = build_model(load("t_shape_drop")).body_inertia[1]
    t2 = 0.06 ** 2
    assert ixx == pytest.approx(0.9 * ((0.0036 + t2) / 12 + 0.048 ** 2) + 0.6 * ((0.0576 + t2) / 12 + 0.072 ** 2), rel=REL)
    assert izz == pytest.approx(0.9 * (0.09 + t2) / 12 + 0.6 * (0.0036 + t2) / 12, rel=REL)
    assert iyy == pytest.approx(7.02e-3 + 2.0736e-3 + 3.06e-3 + 3.1104e-3, rel=1e-9)


@pytest.mark.parametrize("scene", BUILTINS, ids=IDS)
def test_keyframe_puts_the_com_at_the_scene_start(scene):
    model = build_model(scene)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    mujoco.mj_forward(model, data)
    x, y = scene.initial.position
    assert data.xipos[1] == pytest.approx([x, 0.0, y], abs=1e-15), "COM in the world (MuJoCo's z is our y)"
    # the body's rotation about -y by theta: its x axis points to (cos, 0, sin)
    th = scene.initial.angle
    assert data.xmat[1].reshape(3, 3)[:, 0] == pytest.approx([math.cos(th), 0.0, math.sin(th)], abs=1e-15)
    # COM velocity from MuJoCo's own body velocity (mj_objectVelocity at the COM)
    vel = np.zeros(6)
    mujoco.mj_objectVelocity(model, data, mujoco.mjtObj.mjOBJ_XBODY, 1, vel, 0)
    assert vel[1] == pytest.approx(-scene.initial.angular_velocity, abs=1e-12), "omega about -y"


def _touching(scene, state):
    """(our touching contact points (n, 2), MuJoCo's contacts) at the same state."""
    props = mass_properties(scene.body)
    model = build_model(scene)
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = qpos_qvel(props, state)
    mujoco.mj_forward(model, data)
    px, py = contact_points_world(props, state[0], state[1], state[2])
    pts = np.column_stack([px, py])
    return pts[pts[:, 1] < 0.0], data, model


@pytest.mark.parametrize("name,state", [
    ("box_drop", [0.3, 0.02, 0.4, 0, 0, 0]),          # tilted: one corner down
    ("box_drop", [0.0, 0.0499, 0.0, 0, 0, 0]),        # flat: two corners down
    ("t_shape_drop", [0.1, 0.10, 0.9, 0, 0, 0]),      # on its side
    ("t_shape_drop", [0.0, 0.19, 0.0, 0, 0, 0]),      # on its foot: the stem's two corners
    ("rolling_circle", [0.5, 0.099, 2.0, 0, 0, 0]),   # any angle: one point below the centre
    ("point_drop", [0.2, 0.049, 0.0, 0, 0, 0]),
])
def test_mujoco_contacts_are_our_contact_points(name, state):
    """The geometry choice: one MuJoCo contact per touching point of ours, at that point, with
    our depth (+ the contact sphere's radius for the corners that turn)."""
    ours, data, _ = _touching(load(name), np.array(state, dtype=float))
    assert data.ncon == len(ours) > 0
    pos = np.array([data.contact[i].pos for i in range(data.ncon)])
    depth = -np.array([data.contact[i].dist for i in range(data.ncon)])
    order = np.argsort(pos[:, 0])
    ours = ours[np.argsort(ours[:, 0])]
    assert pos[order, 0] == pytest.approx(ours[:, 0], abs=1e-12), "x of each contact"
    extra = 0.0 if name in ("rolling_circle", "point_drop") else CONTACT_SPHERE_RADIUS
    assert depth[order] == pytest.approx(-ours[:, 1] + extra, abs=1e-12), "depth"


def test_a_box_geom_would_give_two_contacts_per_corner():
    """Why spheres: MuJoCo's 3D box against the plane touches with both of its y faces."""
    spec = build_spec(load("box_drop"))
    for g in spec.geoms:
        if g.name == "shape":
            g.contype = g.conaffinity = 1
    spec.geom("ground").contype = spec.geom("ground").conaffinity = 1
    model = spec.compile()
    data = mujoco.MjData(model)
    data.qpos[:] = [0.3, 0.02, 0.4]
    mujoco.mj_forward(model, data)
    box = model.geom("shape").id
    assert sum(1 for i in range(data.ncon) if box in data.contact[i].geom) == 2


@pytest.mark.parametrize("name", ["box_drop", "t_shape_drop", "point_drop", "rolling_circle"])
def test_a_hat_is_one_number_for_every_contact_and_pose(name):
    """efc_diagA of every normal row equals the model's A_hat: 2/(3m) with a hinge, 1/m without."""
    scene = load(name)
    props = mass_properties(scene.body)
    model = build_model(scene)
    expected = (2.0 / 3.0 if props.rotates else 1.0) / props.mass
    assert a_hat(model) == pytest.approx(expected, rel=REL)
    data = mujoco.MjData(model)
    seen = 0
    for theta in (0.0, 0.3, 1.1, 2.5):
        state = np.array([0.0, 0.0, theta if props.rotates else 0.0, 0, 0, 0])
        lowest = contact_points_world(props, *state[:3])[1].min()
        state[1] = -lowest - 2e-3    # lowest point 2 mm deep
        data.qpos[:], data.qvel[:] = qpos_qvel(props, state)
        mujoco.mj_forward(model, data)
        for i in range(data.ncon):
            row = data.contact[i].efc_address
            assert data.efc_diagA[row] == pytest.approx(expected, rel=REL), f"theta {theta}, contact {i}"
            seen += 1
    assert seen >= 4


@pytest.mark.parametrize("scene", BUILTINS, ids=IDS)
def test_mjcf_file_loads_and_is_the_built_model(scene, tmp_path):
    path = tmp_path / "model.xml"
    path.write_text(to_mjcf(scene))
    loaded = mujoco.MjModel.from_xml_path(str(path))
    built = build_model(scene)
    for field in ("body_mass", "body_ipos", "body_inertia", "geom_size", "geom_pos", "pair_solref",
                  "pair_solimp", "pair_solreffriction", "pair_friction", "key_qpos", "key_qvel"):
        assert np.allclose(getattr(loaded, field), getattr(built, field), rtol=MJCF_DIGITS_REL, atol=0), field
    assert (loaded.opt.timestep, loaded.opt.cone, loaded.opt.integrator, loaded.opt.impratio) == \
           (built.opt.timestep, built.opt.cone, built.opt.integrator, built.opt.impratio)
    assert np.array_equal(loaded.opt.gravity, built.opt.gravity)
