"""The resolved scene as plain dicts, lists and floats: what a user's simulator is given.

Every default is filled in and the derived mass properties are added, so that a simulator
written in any language can read the one JSON object `python -m compare scene SCENE --json`
prints and need nothing else. Units SI; frames as in the scene file (y up, angles
counter-clockwise, ground y = 0).
"""
from __future__ import annotations

from custom_sim import Scene, mass_properties


def _body(scene: Scene) -> dict:
    b = scene.body
    out = {"shape": b.shape, "mass": b.mass}
    if b.shape == "box":
        out["size"] = list(b.of_shape("size"))
    elif b.shape == "circle":
        out["radius"] = b.radius
    elif b.shape == "point":
        out["contact_height"] = b.contact_height
    else:
        out["parts"] = [{"size": list(p.size), "offset": list(p.offset), "mass": p.mass} for p in b.of_shape("parts")]
    return out


def scene_dict(scene: Scene) -> dict:
    """The scene with every default filled in, plus `state0` and `mass_properties`:

    mass_properties.mass            kg
    mass_properties.inertia         kg m^2 about the centre of mass (0 for the point mass)
    mass_properties.com             centre of mass in the body's geometry frame (m)
    mass_properties.contact_points  [[x, y], ...] relative to the centre of mass, body frame (m)
    mass_properties.points_rotate   whether the contact points turn with theta (box, compound);
                                    False: they stay where they are (the circle's point straight
                                    below the centre, the point mass's contact height)
    mass_properties.rotates         whether theta is a degree of freedom (False: point mass)
    contact                         the law (docs/scene-format.md): damping_law, friction_law and
                                    roll_law with their parameters; one a family does not take is
                                    0 (c, dissipation) or None (alpha, roll_sharpness)
    state0                          [x, y, theta, vx, vy, omega] at t = 0
    steps                           duration / dt rounded to the nearest whole step
    """
    props = mass_properties(scene.body)
    ct, ini, mj, tol = scene.contact, scene.initial, scene.mujoco, scene.tolerance
    return {
        "name": scene.name,
        "description": scene.description,
        "source": scene.source,
        "duration": scene.duration,
        "dt": scene.dt,
        "steps": scene.steps,
        "integrator": scene.integrator,
        "effects": list(scene.effects),
        "g": scene.g,
        "body": _body(scene),
        "contact": {"k": ct.k, "c": ct.c, "damping_law": ct.damping_law, "dissipation": ct.dissipation,
                    "mu": ct.mu, "alpha": ct.alpha, "friction_law": ct.friction_law,
                    "mu_roll": ct.mu_roll, "roll_law": ct.roll_law, "roll_sharpness": ct.roll_sharpness},
        "initial": {"position": list(ini.position), "velocity": list(ini.velocity),
                    "angle": ini.angle, "angular_velocity": ini.angular_velocity},
        "state0": [*map(float, ini.position), float(ini.angle), *map(float, ini.velocity),
                   float(ini.angular_velocity)],
        "mass_properties": {
            "mass": float(props.mass),
            "inertia": float(props.inertia),
            "com": [float(props.com[0]), float(props.com[1])],
            "contact_points": [[float(px), float(py)] for px, py in props.points],
            "points_rotate": bool(props.points_rotate),
            "rotates": bool(props.rotates),
        },
        "mujoco": {"solref": mj.solref, "integrator": mj.integrator, "cone": mj.cone,
                   "dt": mj.dt if mj.dt is not None else scene.dt},
        "tolerance": {"position": tol.position, "angle": tol.angle, "reason": tol.reason},
    }
