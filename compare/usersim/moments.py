"""Moments worth probing a step function at, picked from custom_sim's run of the scene.

Each kind of moment exercises different lines of the seed's algorithm:

    flight       gravity alone (and free spin): the integrator, the mass
    touchdown    the first state with a point below the ground: the normal force, its damper
    sliding      a touching point slipping while the body turns: friction on the slip velocity
                 v + omega x r, the torque r x F, the inertia
    rolling      the circle touching with |slip| <= 1/alpha and spinning: rolling resistance
    resting      touching, the slowest state: the balance of weight and contact force

A moment is a row index into the run's states; the step probed is the one from that row.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from custom_sim import Scene, mass_properties
from custom_sim.bodies import contact_points_world

# A body slower than this (m/s, and rad/s times its size) counts as resting.
RESTING_SPEED = 1e-2


@dataclass(frozen=True)
class Moment:
    kind: str
    row: int
    what: str      # one line: what the body is doing there


def _contact(scene: Scene, states: np.ndarray):
    """depth (T, n) m and slip velocity (T, n) m/s of every contact point."""
    props = mass_properties(scene.body)
    x, y, th, vx, vy, om = states.T
    px, py = contact_points_world(props, x, y, th)
    rx, ry = px - x[:, None], py - y[:, None]
    depth = -py if scene.has("contact") else np.full_like(py, -1.0)
    slip = vx[:, None] - om[:, None] * ry
    return depth, slip, rx, ry, props


def pick_moments(scene: Scene, states: np.ndarray) -> list[Moment]:
    """The moments found in custom_sim's states (steps + 1, 6), at most one of each kind."""
    states = np.asarray(states, dtype=float)
    steps = len(states) - 1
    depth, slip, rx, ry, props = _contact(scene, states[:steps])
    touching = depth > 0.0
    any_touch = touching.any(axis=1)
    om = states[:steps, 5]
    size = float(np.max(np.hypot(props.points[:, 0], props.points[:, 1]))) if len(props.points) else 0.0
    speed = np.hypot(states[:steps, 3], states[:steps, 4]) + np.abs(om) * size
    band = 1.0 / scene.contact.alpha if scene.has("friction") else np.inf
    out = []

    flight = np.flatnonzero(~any_touch)
    if flight.size:
        # the middle of the first flight: well away from the switches
        first = flight[: np.argmax(np.diff(flight) > 1) + 1] if np.any(np.diff(flight) > 1) else flight
        i = int(first[len(first) // 2])
        out.append(Moment("flight", i, f"in flight at t = {i * scene.dt:.4g} s, omega = {om[i]:.3g} rad/s"))

    touch_rows = np.flatnonzero(any_touch)
    if touch_rows.size and flight.size and touch_rows[-1] > flight[0]:
        later = touch_rows[touch_rows > flight[0]]
        i = int(later[0])
        pts = np.flatnonzero(touching[i])
        out.append(Moment("touchdown", i, f"first step in contact after flight, t = {i * scene.dt:.4g} s, "
                                          f"point {', '.join(map(str, pts))}, vy = {states[i, 4]:.3g} m/s"))

    if scene.has("friction") and touch_rows.size:
        fast = touching & (np.abs(slip) > band)
        lever = np.where(fast, np.abs(om[:, None] * ry), 0.0).max(axis=1)
        # a corner sliding while the body turns: where friction's velocity and lever matter most
        score = np.where(fast.any(axis=1), lever + 1e-12 * np.abs(slip).max(axis=1), -1.0)
        score[[m.row for m in out]] = -1.0   # another state than the moments already picked
        i = int(np.argmax(score))
        if score[i] >= 0.0:
            j = int(np.argmax(np.where(fast[i], np.abs(slip[i]), -1.0)))
            turning = f" while turning at {om[i]:.3g} rad/s" if props.rotates else ""
            out.append(Moment("sliding", i, f"point {j} sliding at {slip[i, j]:.3g} m/s{turning}, "
                                            f"t = {i * scene.dt:.4g} s"))

    if scene.body.shape == "circle" and touch_rows.size:
        rolling = any_touch & (np.abs(slip[:, 0]) <= band) & (np.abs(om) * size > band)
        rows = np.flatnonzero(rolling)
        if rows.size:
            i = int(rows[len(rows) // 2])
            out.append(Moment("rolling", i, f"rolling at omega = {om[i]:.3g} rad/s, slip {slip[i, 0]:.2g} m/s, "
                                            f"t = {i * scene.dt:.4g} s"))

    resting = np.flatnonzero(any_touch & (speed < RESTING_SPEED))
    if resting.size:
        i = int(resting[-1])
        out.append(Moment("resting", i, f"resting on point {', '.join(map(str, np.flatnonzero(touching[i])))}, "
                                        f"speed {speed[i]:.2g} m/s, t = {i * scene.dt:.4g} s"))
    return out
