"""Scene -> MuJoCo model, built with mujoco.MjSpec (no XML templates), and its MJCF.

    build_twin(scene, solref, pairs=)   the Twin: the MjSpec and every choice behind it
    build_spec(scene, solref)   the MjSpec (compiled once: A_hat comes from the compiled model)
    build_model(scene, solref)  the compiled MjModel
    to_mjcf(scene, solref)      MjSpec.to_xml(): loads with mujoco.MjModel.from_xml_path

Every contact is an explicit <pair> of the ground with one contact geom. pairs="native": MuJoCo's
own contact, condim from the effects; "normal": condim 1 only; "none": no pair (the dynamics
twin). Sites at the contact points and energy sensors on every twin.
See docs/mujoco-twins.md#how-a-twin-is-built-specpy.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import mujoco

from .quiet import count_warnings_quietly
from .rigid_body import RigidBody, rigid_body
from scene_types.schema import Scene

from .effects import condim_for, friction_for, gravity_vector, pair_friction
from .frames import qpos_qvel
from .geometry import CONTACT_GROUP, VISUAL_GROUP, GeomPlan, contact_geoms, visual_geoms
from .inertial import Inertial, derived_inertial
from .sensors import SensorLayout, add_sensors
from .sites import add_contact_sites
from .solref import ContactParameters, a_hat, contact_parameters

INTEGRATORS = {
    "Euler": mujoco.mjtIntegrator.mjINT_EULER,
    "RK4": mujoco.mjtIntegrator.mjINT_RK4,
    "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
    "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
}
CONES = {"elliptic": mujoco.mjtCone.mjCONE_ELLIPTIC, "pyramidal": mujoco.mjtCone.mjCONE_PYRAMIDAL}
GEOM_TYPES = {"sphere": mujoco.mjtGeom.mjGEOM_SPHERE, "box": mujoco.mjtGeom.mjGEOM_BOX,
              "cylinder": mujoco.mjtGeom.mjGEOM_CYLINDER, "plane": mujoco.mjtGeom.mjGEOM_PLANE}
BODY = "body"      # the moving body (id 1: the world is 0)
GROUND = "ground"
GROUND_SIZE = (0.0, 0.0, 0.05)  # an infinite plane; 0.05 m grid spacing in the viewer
GROUND_RGBA = (0.8, 0.8, 0.8, 1.0)
CONTACT_RGBA = (0.9, 0.2, 0.2, 1.0)
SHAPE_RGBA = (0.3, 0.5, 0.8, 1.0)


@dataclass(frozen=True)
class Twin:
    """A built twin: the spec and every choice that went into it."""

    spec: mujoco.MjSpec
    scene: Scene
    props: RigidBody
    inertial: Inertial
    contact: ContactParameters
    condim: int
    friction: tuple[float, float, float]
    integrator: str
    cone: str
    dt: float
    n_pairs: int
    pairs: str = "native"                  # native | normal | none (docs/mujoco-twins.md)
    sensors: SensorLayout | None = None    # where energy.py finds MuJoCo's energies and depths

    def __getstate__(self):
        """Pickled without its spec (an MjSpec does not pickle): every choice, not the builder."""
        return {**self.__dict__, "spec": None}


def resolve_settings(scene: Scene, integrator: str | None = None, dt: float | None = None):
    """(integrator, dt) with the scene's [mujoco] table as default (dt: mujoco.dt, else scene.dt)."""
    integrator = integrator or scene.mujoco.integrator
    if integrator not in INTEGRATORS:
        raise ValueError(f"unknown MuJoCo integrator {integrator!r} (expected one of: {', '.join(INTEGRATORS)})")
    dt = dt or scene.mujoco.dt or scene.dt
    if not dt > 0.0:
        raise ValueError(f"dt must be > 0 s, got {dt}")
    return integrator, float(dt)


PAIRS = ("native", "normal", "none")


def build_twin(scene: Scene, solref: str | None = None, *, integrator: str | None = None,
               dt: float | None = None, pairs: str = "native") -> Twin:
    """Build the scene's twin; solref: penalty | physical | seed (default scene.mujoco.solref);
    pairs: native | normal | none (module docstring)."""
    if pairs not in PAIRS:
        raise ValueError(f"unknown contact pairs {pairs!r} (expected one of: {', '.join(PAIRS)})")
    count_warnings_quietly()
    mapping = solref or scene.mujoco.solref
    integrator, dt = resolve_settings(scene, integrator, dt)
    props = rigid_body(scene.body)
    inertial = derived_inertial(scene.body, props)

    spec = mujoco.MjSpec()
    spec.modelname = scene.name
    spec.comment = _header(scene, mapping)
    spec.option.timestep = dt
    spec.option.integrator = INTEGRATORS[integrator]
    spec.option.cone = CONES[scene.mujoco.cone]
    spec.option.gravity = list(gravity_vector(scene))

    _add_geom(spec.worldbody, GeomPlan(GROUND, "plane", GROUND_SIZE, (0.0, 0.0, 0.0)), 0, GROUND_RGBA)
    body = spec.worldbody.add_body(name=BODY)
    body.explicitinertial = True
    body.mass = inertial.mass
    body.ipos = list(inertial.pos)
    body.inertia = list(inertial.diaginertia)
    body.add_joint(name="x", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[1.0, 0.0, 0.0])
    body.add_joint(name="y", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0.0, 0.0, 1.0])
    if props.rotates:
        body.add_joint(name="theta", type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0.0, -1.0, 0.0],
                       pos=list(inertial.pos))
    contacts = contact_geoms(scene.body, props)
    for plan in contacts:
        _add_geom(body, plan, CONTACT_GROUP, CONTACT_RGBA)
    for plan in visual_geoms(scene.body):
        _add_geom(body, plan, VISUAL_GROUP, SHAPE_RGBA)
    sites = add_contact_sites(body, scene.body, props)

    # a twin whose pairs carry the normal only gets the parameters of the frictionless scene
    # (no friction rows, no pyramid scaling of the normal's solref)
    paired_scene = scene if pairs == "native" else dataclasses.replace(
        scene, effects=tuple(e for e in scene.effects if "friction" not in e))
    params = contact_parameters(paired_scene, mapping, body_a_hat(scene.body, spec), dt, props)
    spec.option.impratio = params.impratio
    condim = condim_for(scene) if pairs == "native" else 1
    paired = []
    if scene.has("contact") and pairs != "none":
        for plan in contacts:
            spec.add_pair(name=f"ground_{plan.name}", geomname1=GROUND, geomname2=plan.name,
                          condim=condim, friction=list(pair_friction(scene)),
                          solref=list(params.solref), solimp=list(params.solimp),
                          solreffriction=list(params.solreffriction))
            paired.append(plan.name)
    if not paired:   # no geom can collide: skipping the collision stage gives the same states, sooner
        spec.option.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    sensors = add_sensors(spec, GROUND, paired, sites if scene.has("contact") and not paired else [])

    qpos, qvel = qpos_qvel(props, _initial_state(scene))
    spec.add_key(name="initial", qpos=list(qpos), qvel=list(qvel))
    return Twin(spec, scene, props, inertial, params, condim, friction_for(scene),
                integrator, scene.mujoco.cone, dt, len(paired), pairs, sensors)


_A_HAT: dict = {}


def body_a_hat(body, spec: mujoco.MjSpec) -> float:
    """MuJoCo's A_hat (1/kg) of the body's contact with the world. The mass matrix alone sets it
    (the body's inertia and joints: not the pairs, the step or the integrator), so it is read
    once per body, from a compile of the first twin's spec before its contact pairs are
    written, and every later twin of that body takes it without compiling."""
    if body not in _A_HAT:
        model = spec.compile()
        _A_HAT[body] = a_hat(model, model.body(BODY).id)
    return _A_HAT[body]


def build_spec(scene: Scene, solref: str | None = None, **settings) -> mujoco.MjSpec:
    """The twin's MjSpec; settings: integrator=, dt= (default: the scene's [mujoco] table)."""
    return build_twin(scene, solref, **settings).spec


def build_model(scene: Scene, solref: str | None = None, **settings) -> mujoco.MjModel:
    """The twin's compiled MjModel (qpos0 = 0; keyframe 0 "initial" holds the scene's start)."""
    return build_spec(scene, solref, **settings).compile()


_COMPILED: dict = {}
COMPILED_KEPT = 32   # twins kept compiled (a scenario needs about ten; each is a few hundred kB)


def compiled_twin(scene: Scene, solref: str | None = None, *, integrator: str | None = None,
                  dt: float | None = None, pairs: str = "native") -> tuple[Twin, mujoco.MjModel]:
    """The twin and its compiled MjModel, compiled once per distinct twin (the scene, its
    mapping, integrator, step and pairs) and shared: a caller makes its own MjData and never
    changes the model (build_model gives a model of one's own to change)."""
    key = (scene, solref or scene.mujoco.solref, *resolve_settings(scene, integrator, dt), pairs)
    if key not in _COMPILED:
        if len(_COMPILED) >= COMPILED_KEPT:
            _COMPILED.pop(next(iter(_COMPILED)))
        twin = build_twin(scene, solref, integrator=integrator, dt=dt, pairs=pairs)
        _COMPILED[key] = (twin, twin.spec.compile())
    return _COMPILED[key]


def to_mjcf(scene: Scene, solref: str | None = None, **settings) -> str:
    """The twin as MJCF text (MjSpec.to_xml of the compiled spec)."""
    return compiled_twin(scene, solref, **settings)[0].spec.to_xml()


def _initial_state(scene: Scene):
    i = scene.initial
    return (*i.position, i.angle, *i.velocity, i.angular_velocity)


def _add_geom(body, plan: GeomPlan, group: int, rgba):
    """A geom that never collides by itself (contacts are explicit pairs)."""
    return body.add_geom(name=plan.name, type=GEOM_TYPES[plan.kind],
                         size=list(plan.size), pos=list(plan.pos), quat=list(plan.quat),
                         group=group, rgba=list(rgba), contype=0, conaffinity=0)


def _header(scene: Scene, mapping: str) -> str:
    """The MJCF's opening comment (an XML comment may not hold "--")."""
    text = (f" MuJoCo twin of scene '{scene.name}' ({scene.source}), generated by mujoco_models. "
            f"The body moves in the x-z plane: slide joints x and y (MuJoCo's z is the scene's y) and "
            f"hinge theta (axis 0 -1 0 through the centre of mass: the counter-clockwise angle). The "
            f"COM is at (qpos_x, qpos_y) + the inertial pos. Contacts are the explicit pairs of the "
            f"ground with the spheres of group {CONTACT_GROUP}; group {VISUAL_GROUP} only draws the "
            f"shape. solref mapping: {mapping}. Keyframe 'initial' holds the scene's initial state. ")
    while "--" in text:
        text = text.replace("--", "- -")
    return text
