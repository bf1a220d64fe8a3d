"""The twin's own rigid body: by hand, and the explicit <inertial> against MuJoCo's compiler
deriving mass, COM and inertia from geoms of the same shapes and masses."""
import math

import mujoco
import numpy as np
import pytest

from compare.scenarios import load_builtins
from scene_types.schema import Body, Part
from mujoco_models import build_model
from mujoco_models.geometry import visual_geoms
from mujoco_models.inertial import derived_inertial, point_draw_radius
from mujoco_models.rigid_body import rigid_body

BUILTINS = load_builtins()
L_SHAPE = Body(shape="compound", mass=1.3, parts=(
    Part(size=(0.3, 0.05), offset=(0.1, 0.0), mass=0.8),     # a foot to the right
    Part(size=(0.05, 0.25), offset=(-0.03, 0.1), mass=0.5)))  # a post to the left: Ixz != 0
BODIES = [s.body for s in BUILTINS] + [L_SHAPE]
IDS = [s.name for s in BUILTINS] + ["L_shape"]
# MuJoCo's compiler sums the same terms in another order (and diagonalises in double): round-off
REL = 1e-12


def test_box_by_hand():
    rb = rigid_body(Body(shape="box", mass=2.0, size=(0.2, 0.1)))
    assert (rb.mass, rb.inertia, rb.com) == (2.0, pytest.approx(2.0 * (0.04 + 0.01) / 12, rel=1e-15), (0.0, 0.0))
    assert rb.points.tolist() == [[-0.1, -0.05], [0.1, -0.05], [0.1, 0.05], [-0.1, 0.05]]
    assert rb.rotates and rb.points_rotate


def test_t_shape_by_hand():
    """Bar 0.9 kg (0.30 x 0.06 at y = 0.12), stem 0.6 kg (0.06 x 0.24 at 0): COM y = 0.072 m."""
    bar, stem = Part((0.30, 0.06), (0.0, 0.12), 0.9), Part((0.06, 0.24), (0.0, 0.0), 0.6)
    rb = rigid_body(Body(shape="compound", mass=1.5, parts=(bar, stem)))
    assert rb.com == pytest.approx((0.0, 0.072), abs=1e-16)
    i = 0.9 * (0.09 + 0.0036) / 12 + 0.9 * 0.048 ** 2 + 0.6 * (0.0036 + 0.0576) / 12 + 0.6 * 0.072 ** 2
    assert rb.inertia == pytest.approx(i, rel=1e-14)
    assert len(rb.points) == 8 and rb.points[0] == pytest.approx([-0.15, 0.09 - 0.072])


def test_circle_and_point_by_hand():
    c = rigid_body(Body(shape="circle", mass=3.0, radius=0.2))
    assert (c.inertia, c.points.tolist(), c.points_rotate) == (pytest.approx(0.06), [[0.0, -0.2]], False)
    p = rigid_body(Body(shape="point", mass=0.5, contact_height=0.05))
    assert (p.inertia, p.points.tolist(), p.rotates) == (0.0, [[0.0, -0.05]], False)


def _geom_derived(body: Body):
    """(mass, COM (3,), full inertia tensor (3, 3) about the COM) that MuJoCo's compiler derives
    from the twin's drawn shapes given their masses (inertiafromgeom)."""
    spec = mujoco.MjSpec()
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_TRUE
    b = spec.worldbody.add_body(name="body")
    b.add_joint(type=mujoco.mjtJoint.mjJNT_FREE)
    plans = visual_geoms(body)
    masses = [body.mass] if len(plans) == 1 else [p.mass for p in body.parts]
    types = {"box": mujoco.mjtGeom.mjGEOM_BOX, "sphere": mujoco.mjtGeom.mjGEOM_SPHERE,
             "cylinder": mujoco.mjtGeom.mjGEOM_CYLINDER}
    for plan, m in zip(plans, masses):
        b.add_geom(type=types[plan.kind], size=list(plan.size), pos=list(plan.pos), quat=list(plan.quat), mass=m)
    model = spec.compile()
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, model.body_iquat[1])
    rot = rot.reshape(3, 3)
    return model.body_mass[1], model.body_ipos[1], rot @ np.diag(model.body_inertia[1]) @ rot.T


@pytest.mark.parametrize("body", BODIES, ids=IDS)
def test_explicit_inertial_is_mujocos_own_from_geoms(body):
    """Mass, COM and the inertia about the hinge (y) exactly; the x and z diagonal entries of the
    tensor too (the explicit inertial leaves out only Ixz, which no joint feels)."""
    mass, com, tensor = _geom_derived(body)
    inertial = derived_inertial(body)
    ixx, iyy, izz = inertial.diaginertia
    assert mass == pytest.approx(inertial.mass, rel=REL), "mass"
    if body.shape == "point":
        # no hinge: the explicit inertial keeps the COM at the point and gives it the drawn
        # ball's inertia 2/5 m r^2, which MuJoCo derives about the ball's centre
        r = point_draw_radius(body)
        assert com == pytest.approx(visual_geoms(body)[0].pos, abs=1e-15)
        assert tensor == pytest.approx(np.eye(3) * 0.4 * body.mass * r * r, rel=REL)
        assert inertial.diaginertia == pytest.approx((0.4 * body.mass * r * r,) * 3, rel=REL)
        return
    assert com == pytest.approx(inertial.pos, abs=1e-15), "centre of mass"
    assert tensor[1, 1] == pytest.approx(iyy, rel=REL), "I about the hinge axis"
    assert iyy == pytest.approx(rigid_body(body).inertia, rel=REL), "the 2D inertia"
    assert (tensor[0, 0], tensor[2, 2]) == pytest.approx((ixx, izz), rel=REL), "off-hinge diagonal"
    assert tensor[0, 1] == pytest.approx(0.0, abs=1e-15) and tensor[1, 2] == pytest.approx(0.0, abs=1e-15)


def test_the_l_shape_has_a_product_of_inertia_the_hinge_does_not_feel():
    """The case the explicit inertial simplifies: Ixz != 0 couples only turns about x and z."""
    _, _, tensor = _geom_derived(L_SHAPE)
    assert abs(tensor[0, 2]) > 1e-4 * tensor[1, 1]


@pytest.mark.parametrize("scene", BUILTINS, ids=[s.name for s in BUILTINS])
def test_compiled_twin_carries_the_explicit_inertial(scene):
    model = build_model(scene)
    inertial = derived_inertial(scene.body)
    assert model.body_mass[1] == pytest.approx(inertial.mass, rel=REL)
    assert model.body_inertia[1] == pytest.approx(inertial.diaginertia, rel=REL)
    assert model.body_ipos[1] == pytest.approx(inertial.pos, abs=1e-15)
    assert math.isclose(float(model.body_iquat[1][0]), 1.0)
