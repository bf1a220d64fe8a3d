"""Mass properties and contact points of the four bodies, derived from their geometry.

Frames: the body frame has its origin at the centre of mass (COM) and turns with the
angle theta (counter-clockwise). Contact points are given relative to the COM.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from scene_types.schema import Body


@dataclass(frozen=True)
class MassProperties:
    """mass (kg), inertia about the COM (kg m^2), COM in the geometry frame (m),
    contact points relative to the COM (m, shape (n, 2)), and how they move:

    rotates          the body turns (False for the point mass: theta stays 0)
    points_rotate    contact points turn with the body (False for the circle, whose contact
                     point is always straight below the centre, and the point mass)
    """

    mass: float
    inertia: float
    com: tuple[float, float]
    points: np.ndarray
    rotates: bool
    points_rotate: bool


def box_inertia(mass: float, w: float, h: float) -> float:
    """Solid rectangle about its centre: m (w^2 + h^2) / 12 (kg m^2)."""
    return mass * (w * w + h * h) / 12.0


def disk_inertia(mass: float, radius: float) -> float:
    """Solid disk about its centre: m R^2 / 2 (kg m^2)."""
    return 0.5 * mass * radius * radius


def box_corners(w: float, h: float, centre=(0.0, 0.0)) -> np.ndarray:
    """Four corners of a w x h box around `centre`, counter-clockwise from bottom-left."""
    cx, cy = centre
    return np.array([[cx - w / 2, cy - h / 2], [cx + w / 2, cy - h / 2],
                     [cx + w / 2, cy + h / 2], [cx - w / 2, cy + h / 2]])


@lru_cache(maxsize=64)
def mass_properties(body: Body) -> MassProperties:
    """Mass, inertia and contact points of a scene body (seed Algorithms 1-4), derived once per
    body (the contact points are read-only: every caller shares them)."""
    props = _derive(body)
    props.points.flags.writeable = False
    return props


def _derive(body: Body) -> MassProperties:
    m = body.mass
    if body.shape == "point":
        # Algorithm 1: touches the ground when y < contact_height, i.e. a point at (0, -h).
        pts = np.array([[0.0, -body.of_shape("contact_height")]])
        return MassProperties(m, 0.0, (0.0, 0.0), pts, rotates=False, points_rotate=False)
    if body.shape == "box":
        w, h = body.of_shape("size")
        return MassProperties(m, box_inertia(m, w, h), (0.0, 0.0), box_corners(w, h),
                              rotates=True, points_rotate=True)
    if body.shape == "circle":
        # Algorithm 4: one contact point r = [0, -R] beneath the centre, whatever theta.
        R = body.of_shape("radius")
        return MassProperties(m, disk_inertia(m, R), (0.0, 0.0), np.array([[0.0, -R]]),
                              rotates=True, points_rotate=False)
    # Algorithm 3: total mass, COM, inertia about the COM by the parallel-axis theorem
    # I = sum_j [ m_j (w_j^2 + h_j^2) / 12 + m_j |o_j - com|^2 ]; every part's corners.
    parts = body.of_shape("parts")
    masses = np.array([p.mass for p in parts])
    offsets = np.array([p.offset for p in parts], dtype=float)
    com = masses @ offsets / masses.sum()
    inertia = 0.0
    corners: list[np.ndarray] = []
    for p, o in zip(parts, offsets):
        rel = o - com
        w, h = p.size
        inertia += box_inertia(p.mass, w, h) + p.mass * float(rel @ rel)
        corners.append(box_corners(w, h, centre=rel))
    return MassProperties(float(masses.sum()), inertia, (float(com[0]), float(com[1])),
                          np.vstack(corners), rotates=True, points_rotate=True)


def contact_points_world(props: MassProperties, x, y, theta):
    """World positions of the contact points for states (x, y, theta) of shape (T,):
    returns px, py of shape (T, n)."""
    x, y, theta = (np.asarray(a, dtype=float)[..., None] for a in (x, y, theta))
    lx, ly = props.points[:, 0], props.points[:, 1]
    if not props.points_rotate:
        return x + lx, y + ly
    c, s = np.cos(theta), np.sin(theta)
    return x + c * lx - s * ly, y + s * lx + c * ly


def min_effective_mass(props: MassProperties) -> float:
    """Smallest effective mass a contact point sees along the ground normal (kg),
    over all points and angles: 1 / m_eff = 1/m + r_x^2 / I with |r_x| <= |r|."""
    if not props.rotates or not props.points_rotate:
        return props.mass
    r2 = float(np.max(np.sum(props.points ** 2, axis=1)))
    return 1.0 / (1.0 / props.mass + r2 / props.inertia)
