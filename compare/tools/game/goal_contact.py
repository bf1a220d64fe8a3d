"""Contact of the ball with the goal frame: the ground's penalty spring-damper, against capsules.

For a capsule (segment a-b, radius r, m) and the ball (radius R): depth d = R + r - |p - q|,
q the closest point of a-b; Fn = k d + c max(0, -v . n) (N) along the outward normal n, no
torque, no friction (a strike's ~4 kN would need a tanh friction step near 1e-6 s). The game
adds it to the player's force for the next step. Derivation: docs/physics.md#9-the-goal-frame-in-the-game.
"""
from __future__ import annotations

import math

from .field import Segment


def closest_point(seg: Segment, x: float, y: float) -> tuple[float, float]:
    """The point of segment a-b nearest to (x, y) (m)."""
    ax, ay = seg.a
    ex, ey = seg.b[0] - ax, seg.b[1] - ay
    length2 = ex * ex + ey * ey
    if length2 == 0.0:
        return ax, ay
    t = min(max(((x - ax) * ex + (y - ay) * ey) / length2, 0.0), 1.0)
    return ax + t * ex, ay + t * ey


def capsule_force(seg: Segment, radius: float, x: float, y: float, vx: float, vy: float
                  ) -> tuple[float, float]:
    """(Fx, Fy) in N on a ball of `radius` (m) at (x, y) moving at (vx, vy) from one capsule."""
    qx, qy = closest_point(seg, x, y)
    dx, dy = x - qx, y - qy
    dist = math.hypot(dx, dy)
    depth = radius + seg.radius - dist
    if depth <= 0.0 or dist == 0.0:
        return 0.0, 0.0   # apart (or the centre on the axis, which the stiffness rules out)
    nx, ny = dx / dist, dy / dist
    vn = vx * nx + vy * ny
    fn = seg.k * depth + seg.c * max(0.0, -vn)
    return fn * nx, fn * ny


def goal_force(obstacles: tuple[Segment, ...], radius: float, x: float, y: float,
               vx: float, vy: float) -> tuple[float, float]:
    """Sum of the capsule forces (N) on the ball."""
    fx = fy = 0.0
    for seg in obstacles:
        gx, gy = capsule_force(seg, radius, x, y, vx, vy)
        fx += gx
        fy += gy
    return fx, fy


def clearance(obstacles: tuple[Segment, ...], radius: float, x: float, y: float) -> float:
    """Gap (m) between the ball's surface and the nearest capsule; <= 0 when touching."""
    gap = math.inf
    for seg in obstacles:
        qx, qy = closest_point(seg, x, y)
        gap = min(gap, math.hypot(x - qx, y - qy) - radius - seg.radius)
    return gap
