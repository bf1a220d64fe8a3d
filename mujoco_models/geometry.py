"""Which geoms stand for each shape, chosen so that MuJoCo's contacts are our contact points.

    contact_geoms(body, props)   a CONTACT_SPHERE_RADIUS sphere at each corner (box, compound);
                                 the point's drawn ball, lowest point at (0, -h); the disk's
                                 sphere of radius R (m, body frame)
    visual_geoms(body)           the drawn shape, in no contact pair

Why spheres (a 3D box or cylinder gives two contacts per 2D point):
docs/mujoco-twins.md#contact-geoms.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .rigid_body import RigidBody
from scene_types.schema import Body

from .inertial import board_depth, point_draw_radius

CONTACT_SPHERE_RADIUS = 1e-9   # m: contact starts 1 nm early, k r = 1e-5 N at k = 1e4 N/m
CONTACT_GROUP = 3              # MuJoCo's viewer hides group 3 by default
VISUAL_GROUP = 1
# A quarter turn about x takes a cylinder's axis (local z) to y.
CYLINDER_ALONG_Y = (math.cos(math.pi / 4), math.sin(math.pi / 4), 0.0, 0.0)


@dataclass(frozen=True)
class GeomPlan:
    """One geom in the body frame (m): kind sphere | box | cylinder | plane, MuJoCo size,
    position, orientation; collides: paired with the ground (a contact geom), else drawn only."""

    name: str
    kind: str
    size: tuple[float, float, float]
    pos: tuple[float, float, float]
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    collides: bool = True


def _to3(x: float, y: float) -> tuple[float, float, float]:
    return (float(x), 0.0, float(y))


def contact_geoms(body: Body, props: RigidBody) -> list[GeomPlan]:
    """The geoms that touch the ground, in the body (geometry) frame."""
    cx, cy = props.com
    if body.shape == "circle":
        return [GeomPlan("contact0", "sphere", (body.radius, 0.0, 0.0), _to3(cx, cy))]
    r = CONTACT_SPHERE_RADIUS
    if body.shape == "point":
        rho = point_draw_radius(body)
        return [GeomPlan("contact0", "sphere", (rho, 0.0, 0.0), _to3(cx, cy - body.contact_height + rho))]
    return [GeomPlan(f"contact{i}", "sphere", (r, 0.0, 0.0), _to3(px + cx, py + cy))
            for i, (px, py) in enumerate(props.points)]


def visual_geoms(body: Body) -> list[GeomPlan]:
    """Geoms that draw the shape and never collide, in the body (geometry) frame."""
    if body.shape == "point":
        r = point_draw_radius(body)
        return [GeomPlan("shape", "sphere", (r, 0.0, 0.0), _to3(0.0, r - body.contact_height), collides=False)]
    if body.shape == "circle":
        R = body.radius
        return [GeomPlan("shape", "cylinder", (R, R, 0.0), (0.0, 0.0, 0.0), CYLINDER_ALONG_Y,
                         collides=False)]
    parts = [(body.size, (0.0, 0.0))] if body.shape == "box" else [(p.size, p.offset) for p in body.parts]
    return [GeomPlan(f"part{j}" if len(parts) > 1 else "shape", "box",
                     (w / 2, board_depth(w, h) / 2, h / 2), _to3(*o), collides=False)
            for j, ((w, h), o) in enumerate(parts)]


def describe(body: Body, props: RigidBody) -> str:
    """One sentence a user reads: what collides and what is drawn."""
    n = len(props.points)
    r = f"{CONTACT_SPHERE_RADIUS:g} m"
    if body.shape == "circle":
        return (f"collision: a sphere of radius R = {body.radius:g} m at the centre (one contact straight "
                f"below it); drawn: the seed's cylinder, radius R, length 2R along y (never collides)")
    if body.shape == "point":
        return (f"collision: a ball of radius {point_draw_radius(body):g} m whose lowest point is our contact "
                f"point (0, -{body.contact_height:g}) m (the point mass never turns); drawn: the same ball")
    what = "box corners" if body.shape == "box" else f"corners of the {len(body.parts)} parts"
    return (f"collision: {n} spheres of radius {r}, one at each of our contact points (the {what}); "
            f"drawn: boxes as deep along y as their smaller side (never collide)")
