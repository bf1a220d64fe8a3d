"""Contact sites: one MuJoCo site per contact point, where the twin reads positions and Jacobians.

Sites have no mass and never collide; they only name a point of the body for MuJoCo's
kinematics (site_xpos, mj_jac). In the body (geometry) frame:

    box, compound   each corner of each part: com + p_i (rigid_body.py's points)
    point           (0, -h) below the COM (the point mass never turns)
    circle          the centre. The circle's contact point is straight below the centre,
                    whatever the angle, so it is not a point of the body: whoever reads the
                    site subtracts R along the world's vertical (CONTACT_BELOW_SITE).
"""
from __future__ import annotations

from scene_types.schema import Body

from .rigid_body import RigidBody

SITE_GROUP = 3      # hidden in MuJoCo's viewer by default, as the contact spheres
SITE_SIZE = 0.005   # m, drawn radius only


def contact_below_site(body: Body) -> float:
    """How far (m) below its site, along the world's vertical, a contact point lies: R for the
    circle, 0 for points that are sites themselves."""
    return float(body.radius) if body.shape == "circle" else 0.0


def site_positions(body: Body, rb: RigidBody) -> list[tuple[float, float]]:
    """The sites' 2D positions in the body (geometry) frame (m)."""
    cx, cy = rb.com
    if body.shape == "circle":
        return [(cx, cy)]
    return [(cx + float(px), cy + float(py)) for px, py in rb.points]


def add_contact_sites(mj_body, body: Body, rb: RigidBody) -> list[str]:
    """Add the contact sites to the spec's body; returns their names, in contact-point order."""
    names = []
    for i, (x, y) in enumerate(site_positions(body, rb)):
        name = f"site{i}"
        mj_body.add_site(name=name, pos=[x, 0.0, y], size=[SITE_SIZE, 0.0, 0.0], group=SITE_GROUP)
        names.append(name)
    return names
