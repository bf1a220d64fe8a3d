"""What no contact setting can remove: the ways a twin differs from custom_sim by construction.

Each cause is a sentence with the physics behind it; `causes(scene)` lists those that act in a
scene. A fit can trade one cause against another (a stiffer spring to mimic the restitution of
the compression law), but not remove it, and the trade shows on the held-out scenes.
"""
from __future__ import annotations

from custom_sim import Scene

DAMPING_LAW = ("damping law: custom_sim damps only while the point approaches the ground (compression "
               "law); MuJoCo's contact damps both ways and never pulls, so a bounce loses a different "
               "share of its energy at every impact, whatever solref says")
CONTACT_POINT = ("contact point: MuJoCo applies the force and measures the slip at the middle of the "
                 "penetration, d/2 above our corner (d about 1 cm at an impact), so the friction's lever "
                 "arm differs by d/2 while the body turns")
INVERSE_INERTIA = ("constant A_hat: MuJoCo scales every contact row by its diagonal inverse inertia at "
                   "qpos0, where the true one changes with the pose (up to 4 against 2/3 for a box), a "
                   "force error of about d |A / A_hat - 1|")
FRICTION_LAW = ("friction law: ours is mu Fn tanh(alpha v), whose slope follows the load; MuJoCo's row is "
                "viscous (one slope c_t) capped at mu Fn, so it grips too little during an impact and "
                "holds (static friction) where ours creeps")
SHARED_CONE = ("shared cone: all friction rows of a contact sit in one cone with the normal; projecting on "
               "it while sliding raises the normal force (about 2 mu c_t v / impratio) and sliding and "
               "rolling rows share one damping")
TUMBLING = ("tumbling: a body that lands on a corner and rocks amplifies any difference (custom_sim "
            "against itself with k, c scaled by 1 + 1e-4 differs by about 6e-4 m), so the error after "
            "the first impacts measures this sensitivity as much as the settings")


def causes(scene: Scene) -> list[str]:
    """The causes acting in the scene (none without contact)."""
    if not scene.has("contact"):
        return []
    out = []
    if scene.contact.damping_law == "compression":
        out.append(DAMPING_LAW)
    turns = scene.body.shape != "point"
    if turns and scene.has("friction"):
        out.append(CONTACT_POINT)
    if turns:
        out.append(INVERSE_INERTIA)
    if scene.has("friction"):
        out.append(FRICTION_LAW)
        out.append(SHARED_CONE)
    if turns and (scene.initial.angle != 0.0 or scene.initial.angular_velocity != 0.0):
        out.append(TUMBLING)
    return out


def short(cause: str) -> str:
    """The cause's name (the words before the colon)."""
    return cause.split(":", 1)[0]
