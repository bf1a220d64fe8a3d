"""The twin's <inertial>: mass, centre of mass and diagonal inertia from the scene's geometry.

    derived_inertial(body) -> Inertial: mass (kg), COM (m), (Ixx, Iyy, Izz) (kg m^2)

Iyy (the hinge's axis) is our 2D inertia exactly; Ixx and Izz are those of the 2D shape made a
slab of depth board_depth along y (the disk: the seed's cylinder of length 2R), so that
Ixx + Izz > Iyy. The formulas: docs/mujoco-twins.md#the-explicit-inertial.
"""
from __future__ import annotations

from dataclasses import dataclass

from .rigid_body import RigidBody, rigid_body
from scene_types.schema import Body

POINT_DRAW_RADIUS = 0.02  # m: the ball drawn for a point mass with contact_height 0


@dataclass(frozen=True)
class Inertial:
    """mass (kg), COM in the body (geometry) frame in 2D (x, y) m, and the diagonal inertia
    (Ixx, Iyy, Izz) kg m^2 about the COM along MuJoCo's axes (y is the hinge axis)."""

    mass: float
    com: tuple[float, float]
    diaginertia: tuple[float, float, float]
    slab_depth: float | None  # m, depth along y of the slab the off-axis inertias assume

    @property
    def pos(self) -> tuple[float, float, float]:
        """The COM in MuJoCo's body frame: 2D y is MuJoCo's z."""
        return (self.com[0], 0.0, self.com[1])


def point_draw_radius(body: Body) -> float:
    """Radius (m) of the ball drawn for a point mass: its contact height, or a default."""
    return body.contact_height if body.contact_height > 0.0 else POINT_DRAW_RADIUS


def board_depth(w: float, h: float) -> float:
    """Depth along y (m) of a box part: its smaller side (a board seen edge-on)."""
    return min(w, h)


def derived_inertial(body: Body, props: RigidBody | None = None) -> Inertial:
    """The <inertial> of a scene body (formulas: docs/mujoco-twins.md#the-explicit-inertial)."""
    props = props or rigid_body(body)
    m = props.mass
    if body.shape == "point":
        r = point_draw_radius(body)
        i = 0.4 * m * r * r
        return Inertial(m, props.com, (i, i, i), None)
    if body.shape == "circle":
        R = body.radius
        t = 2.0 * R
        side = m * R * R / 4.0 + m * t * t / 12.0
        return Inertial(m, props.com, (side, props.inertia, side), t)
    if body.shape == "box":
        parts = [(m, body.size, (0.0, 0.0))]
    else:
        parts = [(p.mass, p.size, p.offset) for p in body.parts]
    cx, cz = props.com
    ixx = izz = 0.0
    for mj, (w, h), (ox, oz) in parts:
        t = board_depth(w, h)
        dx, dz = ox - cx, oz - cz
        ixx += mj * ((h * h + t * t) / 12.0 + dz * dz)
        izz += mj * ((w * w + t * t) / 12.0 + dx * dx)
    depth = max(board_depth(w, h) for _, (w, h), _ in parts)
    return Inertial(m, props.com, (ixx, props.inertia, izz), depth)
