"""Every way a twin differs from the hand-written simulator, as sentences a user reads.

Brax's io/mjcf refuses what it cannot map; the twin maps everything and says here what it
could only approximate: geometry, the damping law, the friction law, the solref mapping's
known error, the integrator and the step. run.py stores the list in Trajectory.meta.
"""
from __future__ import annotations

from scene_types.schema import Scene

from .geometry import CONTACT_SPHERE_RADIUS

# custom_sim integrators that take the same update as a MuJoCo integrator (contact forces are
# explicit in all of MuJoCo's: "implicit" treats only joint damping and actuators implicitly)
SAME_UPDATE = {"Euler": "semi_implicit_euler", "implicit": "semi_implicit_euler",
               "implicitfast": "semi_implicit_euler", "RK4": "rk4"}


def approximations(twin) -> list[str]:
    """Sentences for a built twin (spec.Twin)."""
    scene = twin.scene
    out = [geometry_note(scene)]
    if scene.has("contact"):
        out += damping_note(scene)
        out += twin.contact.notes
        out += rolling_notes(scene, twin)
        if twin.cone == "pyramidal" and scene.has("friction"):
            out.append("cone: pyramidal, the friction cone cut into 2 (condim - 1) planes; the "
                       "rolling-resistance deceleration is about 4 % off")
    out += stepping_notes(scene, twin.integrator, twin.dt)
    return out


def geometry_note(scene: Scene) -> str:
    shape = scene.body.shape
    if shape == "point":
        return ("geometry: a sphere whose lowest point is our contact point (0, -h): one contact, "
                "at our depth (the point mass never turns)")
    if shape == "circle":
        R = scene.body.radius
        depth = scene.body.mass * scene.g / scene.contact.k if scene.has("gravity") else 0.0
        return (f"geometry: a sphere of radius R = {R:g} m stands in for the seed's cylinder (radius R, "
                f"length 2R), which lying on its side would give two contacts, one at each end of its "
                f"touching line, each with the full depth; the sphere gives one contact straight below "
                f"the centre, as ours. MuJoCo applies it mid-way through the overlap, R - d/2 below the "
                f"centre where ours is at R: at the resting depth d = m g / k = {depth * 1e3:.2g} mm the "
                f"friction's lever arm is {depth / 2 / R * 100:.2g} % shorter")
    what = "box corner" if shape == "box" else "corner of every part"
    return (f"geometry: one sphere of radius {CONTACT_SPHERE_RADIUS:g} m at each {what} (a box geom "
            f"gives two contacts per 2D corner, one at each face in y): one contact per corner as ours, "
            f"touching {CONTACT_SPHERE_RADIUS:g} m before ours. contact point: MuJoCo puts it mid-way "
            f"through the penetration, d/2 above our corner (d reaches about a centimetre at an impact), and "
            f"applies the friction force and measures the slip there: the friction's lever arm about the "
            f"centre of mass differs from ours by d/2, which changes the spin each landing leaves. The "
            f"normal force is the same wherever along the normal it acts")


def damping_note(scene: Scene) -> list[str]:
    if scene.contact.damping_law == "linear":
        return ["damping law: linear, max(0, k d - c v), which is MuJoCo's own"]
    return ["damping law: the scene's 'compression' law (c acts only while the point approaches the "
            "ground) cannot be reproduced: MuJoCo's contact damps both ways and never pulls (our "
            "'linear' law), so its bodies leave the ground slower and bounce lower"]


def rolling_notes(scene: Scene, twin) -> list[str]:
    if not scene.has("rolling_friction"):
        return []
    notes = ["rolling resistance: MuJoCo's rolling rows share one cone with the sliding ones, "
             "(f_t / mu)^2 + (tau / mu_roll)^2 <= Fn^2 (elliptic): while the disk slides, the sliding "
             "force takes the whole cone and the rolling torque is about 0, where ours applies "
             "mu Fn and mu_roll Fn together"]
    if twin.contact.mapping == "penalty" and twin.contact.friction_damping:
        mu, roll = scene.contact.mu, scene.contact.mu_roll
        notes.append(f"rolling resistance (penalty): below its cap mu_roll Fn the rolling torque is "
                     f"viscous, its regularisation being mu^2 / mu_roll^2 = {(mu / roll) ** 2:.3g} times the "
                     f"sliding rows' (mujoco_models/friction.py): it stops a slow disk smoothly where "
                     f"ours keeps mu_roll Fn sign(omega)")
    return notes


def stepping_notes(scene: Scene, integrator: str, dt: float) -> list[str]:
    notes = []
    if SAME_UPDATE[integrator] != scene.integrator:
        notes.append(f"integrator: MuJoCo's {integrator} takes the step of our {SAME_UPDATE[integrator]} "
                     f"(contact forces explicit), the scene runs {scene.integrator}")
    if dt != scene.dt:
        notes.append(f"step: MuJoCo runs dt = {dt:g} s, ours {scene.dt:g} s")
    return notes
