"""The events a user looks for in a trajectory: contact, bounces, rest, rolling.

A point touches the ground when its depth is positive, which is exactly when the elastic
contact energy (sum of k d^2 / 2) is positive; both simulators report it by the same formula.
"""
from __future__ import annotations

import math

import numpy as np

from custom_sim import Scene, Trajectory
from scene_types.state import POSE

REST_SPEED = 1e-2          # m/s: slower than this (and REST_SPIN) until the end counts as at rest
REST_SPIN = 0.1            # rad/s
ROLLING_SLIP = 1e-2        # m/s: |vx + omega R| below this until the end counts as rolling
MIN_BOUNCE_HEIGHT = 1e-3   # m: apexes lower than this above the touch-down height are not bounces


def touching(traj: Trajectory) -> np.ndarray:
    return traj.energy_contact > 0.0


def first_contact_time(traj: Trajectory) -> float | None:
    hit = np.nonzero(touching(traj))[0]
    return float(traj.t[hit[0]]) if hit.size else None


def bounce_apexes(traj: Trajectory) -> list[tuple[float, float]]:
    """(t, y) of the highest point of each flight after the first contact."""
    touch = touching(traj)
    if not touch.any():
        return []
    first = int(np.argmax(touch))
    apexes = []
    i = first
    n = len(touch)
    while i < n:
        while i < n and touch[i]:
            i += 1
        start = i
        while i < n and not touch[i]:
            i += 1
        if i < n and i > start:  # a complete flight: left the ground and came back
            j = start + int(np.argmax(traj.y[start:i]))
            apexes.append((float(traj.t[j]), float(traj.y[j])))
    return apexes


def restitutions(traj: Trajectory) -> list[float]:
    """e_i = sqrt(h_{i+1} / h_i), h = apex height above the height of the first touch-down
    (free flight: apex height is v^2 / 2g, so the ratio of heights is e^2)."""
    touch = touching(traj)
    if not touch.any():
        return []
    y_touch = float(traj.y[int(np.argmax(touch))])
    first_h = float(traj.y[0]) - y_touch
    heights = [first_h] + [y - y_touch for _, y in bounce_apexes(traj)]
    heights = [h for h in heights if h > MIN_BOUNCE_HEIGHT]
    return [math.sqrt(b / a) for a, b in zip(heights, heights[1:])]


def _settles(mask: np.ndarray, t: np.ndarray) -> float | None:
    """First time from which mask holds until the end."""
    if not mask[-1]:
        return None
    bad = np.nonzero(~mask)[0]
    return float(t[bad[-1] + 1]) if bad.size else float(t[0])


def rest_time(traj: Trajectory) -> float | None:
    speed = np.hypot(traj.vx, traj.vy)
    return _settles((speed < REST_SPEED) & (np.abs(traj.omega) < REST_SPIN), traj.t)


def rolling_time(traj: Trajectory, radius: float) -> float | None:
    """From when the disk rolls without slipping (slip vx + omega R small) until the end."""
    slip = np.abs(traj.vx + traj.omega * radius)
    moving = np.abs(traj.vx) > REST_SPEED
    return _settles((slip < ROLLING_SLIP) & moving, traj.t)


def events(scene: Scene, traj: Trajectory) -> dict:
    apexes = bounce_apexes(traj)
    out = {
        "first_contact_time": first_contact_time(traj),
        "bounce_apex_heights": [y for _, y in apexes[:10]],
        "restitution": restitutions(traj)[:10],
        "rest_time": rest_time(traj),
        "final_pose": {c: float(getattr(traj, c)[-1]) for c in POSE},
    }
    if scene.body.shape == "circle":
        out["rolling_time"] = rolling_time(traj, scene.body.of_shape("radius"))
    return out
