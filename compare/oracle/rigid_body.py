"""Mass properties and contact points of a scene's body, computed here from the scene file alone.

    rigid_body(body) -> RigidBody: mass (kg), inertia about the COM (kg m^2), COM (m), contact
        points relative to the COM (m)

The checks must not share the quantity they check, so the oracle does not take custom_sim's
mass properties: box and compound parts are polygons whose area moments come from Green's
theorem, one polar moment about a common origin shifted to the COM once (custom_sim sums
parallel axes per part). Formulas: docs/step-check.md#the-geometry-by-greens-theorem.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from scene_types import Scene
from scene_types import Body


@dataclass(frozen=True)
class RigidBody:
    """mass (kg), inertia about the COM (kg m^2, 0 for the point), COM in the scene's body
    frame (m), contact points relative to the COM in the body frame (m, tuple of (x, y)),
    turning: the points turn with theta; rotates: theta is a degree of freedom."""

    mass: float
    inertia: float
    com: tuple[float, float]
    points: tuple[tuple[float, float], ...]
    turning: bool
    rotates: bool


def rectangle(size, centre=(0.0, 0.0)) -> np.ndarray:
    """Vertices (4, 2) of a w x h rectangle around centre, counter-clockwise from bottom-left."""
    w, h = size
    cx, cy = centre
    return np.array([[cx - w / 2, cy - h / 2], [cx + w / 2, cy - h / 2],
                     [cx + w / 2, cy + h / 2], [cx - w / 2, cy + h / 2]], dtype=float)


def area_moments(vertices: np.ndarray) -> tuple[float, float, float, float]:
    """(A m^2, int x m^3, int y m^3, int (x^2 + y^2) m^4) of a simple polygon (n, 2),
    counter-clockwise, about the origin: Green's theorem over its edges."""
    x, y = vertices[:, 0], vertices[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = cross.sum() / 2.0
    sx = (cross * (x + xn)).sum() / 6.0
    sy = (cross * (y + yn)).sum() / 6.0
    polar = (cross * (x * x + x * xn + xn * xn + y * y + y * yn + yn * yn)).sum() / 12.0
    return float(area), float(sx), float(sy), float(polar)


def polygons_body(polygons, masses) -> RigidBody:
    """A body of uniform-density polygons (each (n, 2), ccw) with the given masses (kg)."""
    total, first, polar = 0.0, np.zeros(2), 0.0
    for verts, m in zip(polygons, masses):
        area, sx, sy, jz = area_moments(verts)
        rho = m / area
        total += m
        first += rho * np.array([sx, sy])
        polar += rho * jz
    com = first / total
    inertia = polar - total * float(com @ com)
    pts = np.vstack(polygons) - com
    return RigidBody(total, float(inertia), (float(com[0]), float(com[1])),
                     tuple((float(px), float(py)) for px, py in pts), turning=True, rotates=True)


@lru_cache(maxsize=64)
def rigid_body(body: Body) -> RigidBody:
    """The body's mass properties and contact points from the scene's geometry (derived once
    per body; the RigidBody holds tuples, so every caller may share it)."""
    if body.shape == "point":
        return RigidBody(body.mass, 0.0, (0.0, 0.0), ((0.0, -float(body.contact_height)),),
                         turning=False, rotates=False)
    if body.shape == "circle":
        R = float(body.radius)
        return RigidBody(body.mass, body.mass * R * R / 2.0, (0.0, 0.0), ((0.0, -R),),
                         turning=False, rotates=True)
    if body.shape == "box":
        return polygons_body([rectangle(body.size)], [body.mass])
    return polygons_body([rectangle(p.size, p.offset) for p in body.parts],
                         [p.mass for p in body.parts])


def of_scene(scene: Scene) -> RigidBody:
    return rigid_body(scene.body)
