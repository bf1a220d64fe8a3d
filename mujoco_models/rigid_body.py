"""The twin's own rigid body: mass, centre of mass, inertia and contact points from the scene file.

    rigid_body(body) -> RigidBody: mass (kg), inertia about the COM (kg m^2), com in the
        geometry frame (m), contact points relative to the COM at angle 0 (m)

Written here, from the scene's geometry alone, so that nothing the twin integrates comes from
the simulator it checks. The formulas per shape: docs/mujoco-twins.md#the-rigid-body.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from scene_types.schema import Body


@dataclass(frozen=True)
class RigidBody:
    """mass (kg), inertia about the COM for turns in the plane (kg m^2), COM in the geometry
    frame (m), contact points relative to the COM (m, shape (n, 2)), and how they move:

    rotates          the body turns (False for the point mass: it gets no hinge)
    points_rotate    the contact points turn with the body (False for the circle and the point)
    """

    mass: float
    inertia: float
    com: tuple[float, float]
    points: np.ndarray
    rotates: bool
    points_rotate: bool

    @property
    def lowest_com_height(self) -> float:
        """The lowest the COM gets with every contact point on or above the ground (m, <= 0
        means: the COM may reach the ground line when the farthest point is level with it)."""
        return -float(np.max(np.hypot(self.points[:, 0], self.points[:, 1])))


def _corners(w: float, h: float, cx: float, cy: float) -> list[tuple[float, float]]:
    """The four corners of a w x h rectangle centred at (cx, cy), counter-clockwise from
    bottom-left (m)."""
    return [(cx - w / 2, cy - h / 2), (cx + w / 2, cy - h / 2),
            (cx + w / 2, cy + h / 2), (cx - w / 2, cy + h / 2)]


def boxes(body: Body) -> list[tuple[float, tuple[float, float], tuple[float, float]]]:
    """The body as (mass kg, (w, h) m, centre (x, y) m in the geometry frame) rectangles."""
    if body.shape == "box":
        return [(body.mass, tuple(body.size), (0.0, 0.0))]
    if body.shape == "compound":
        return [(p.mass, tuple(p.size), tuple(p.offset)) for p in body.parts]
    raise ValueError(f"a {body.shape} body is not made of boxes")


@lru_cache(maxsize=64)
def rigid_body(body: Body) -> RigidBody:
    """Mass properties and contact points of a scene body (docs/mujoco-twins.md), derived once per
    body (the contact points are read-only: every twin of it shares them)."""
    props = _derive(body)
    props.points.flags.writeable = False
    return props


def _derive(body: Body) -> RigidBody:
    m = float(body.mass)
    if body.shape == "point":
        return RigidBody(m, 0.0, (0.0, 0.0), np.array([[0.0, -float(body.contact_height)]]),
                         rotates=False, points_rotate=False)
    if body.shape == "circle":
        R = float(body.radius)
        return RigidBody(m, 0.5 * m * R * R, (0.0, 0.0), np.array([[0.0, -R]]),
                         rotates=True, points_rotate=False)
    parts = boxes(body)
    total = sum(mj for mj, _, _ in parts)
    cx = sum(mj * o[0] for mj, _, o in parts) / total
    cy = sum(mj * o[1] for mj, _, o in parts) / total
    inertia = 0.0
    points: list[tuple[float, float]] = []
    for mj, (w, h), (ox, oy) in parts:
        dx, dy = ox - cx, oy - cy
        inertia += mj * (w * w + h * h) / 12.0 + mj * (dx * dx + dy * dy)
        points += _corners(w, h, dx, dy)
    return RigidBody(float(total), float(inertia), (float(cx), float(cy)), np.array(points),
                     rotates=True, points_rotate=True)

