"""The twin's <inertial>: mass, centre of mass and diagonal inertia from the scene's geometry.

MuJoCo needs a 3D inertia; the body turns only about y (the hinge), so only Iyy acts on the
motion and it is our 2D inertia I exactly. The other two axes come from the 2D shape made
into a slab of depth t along y (the seed's formulas, extended by the slab's thickness):

    box part j (w_j x h_j, centre (dx_j, dz_j) from the COM, depth t_j = min(w_j, h_j)):
        Ixx = sum m_j ((h_j^2 + t_j^2) / 12 + dz_j^2)
        Iyy = sum m_j ((w_j^2 + h_j^2) / 12 + dx_j^2 + dz_j^2)        = I (parallel axes)
        Izz = sum m_j ((w_j^2 + t_j^2) / 12 + dx_j^2)
    circle (the seed's cylinder: radius R, length t = 2R along y):
        Iyy = m R^2 / 2,  Ixx = Izz = m R^2 / 4 + m (2R)^2 / 12
    point: no hinge, so no inertia acts; MuJoCo still wants one > 0, so it gets the drawn
        ball's about its centre, 2 m r^2 / 5 (r = contact_height, or POINT_DRAW_RADIUS when that
        is 0; the COM stays the point's).

The slab's depth makes Ixx + Izz > Iyy strictly (MuJoCo's triangle inequality). The product
Ixz of an asymmetric compound is left out: it couples only to rotations no joint allows.
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
    """The <inertial> of a scene body, by the formulas in this module's docstring."""
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
