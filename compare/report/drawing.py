"""Outlines of a body at a pose, in world coordinates (m), for snapshots."""
from __future__ import annotations

import math

import numpy as np

from custom_sim import Scene, mass_properties
from custom_sim.bodies import box_corners


def outlines(scene: Scene, x: float, y: float, theta: float) -> list[np.ndarray]:
    """Closed polygons (k, 2) outlining the body with its COM at (x, y), turned by theta."""
    body = scene.body
    c, s = math.cos(theta), math.sin(theta)
    rot = np.array([[c, -s], [s, c]])
    if body.shape == "circle":
        a = np.linspace(0, 2 * math.pi, 49)
        ring = body.radius * np.column_stack([np.cos(a), np.sin(a)])
        spoke = np.array([[0.0, 0.0], [body.radius, 0.0]]) @ rot.T  # shows the rotation
        return [ring + (x, y), spoke + (x, y)]
    if body.shape == "point":
        h = body.contact_height
        size = max(h, 0.02)
        return [box_corners(size, size, (0.0, 0.0))[[0, 1, 2, 3, 0]] + (x, y),
                np.array([[x, y], [x, y - h]])]
    if body.shape == "box":
        parts = [(body.size, (0.0, 0.0))]
    else:
        com = np.array(mass_properties(body).com)
        parts = [(p.size, tuple(np.array(p.offset) - com)) for p in body.parts]
    return [box_corners(*size, centre)[[0, 1, 2, 3, 0]] @ rot.T + (x, y) for size, centre in parts]
