"""Moments worth probing a step function at, picked from custom_sim's run of the scene.

    pick_moments(scene, states) -> [Moment(kind, row, what)]   at most one of each kind:
        flight, touchdown, rebound, sliding, rolling, resting

A moment is a row index into the run's states (the step probed is the one from that row),
picked only where the effect it probes acts (a force changing the step by ACTIVE_ROUNDOFFS
round-offs at least). `not_probed` says which of the scene's effects no state lets a moment
probe. What each kind exercises: docs/validate-your-simulator.md#reading-the-diagnosis.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compare.oracle.reference import Equations
from .mistakes import (RESTING_LOAD, carries_weight, contact_loads, damper_leaving, least_acting_force,
                                      rebound_score)
from custom_sim import Scene

# A body slower than this (m/s, and rad/s times its size) counts as resting.
RESTING_SPEED = 1e-2

# What each kind of moment probes (the report's words).
EFFECTS = {
    "flight": "gravity and free motion, the integrator",
    "touchdown": "the normal force and its damper on approach",
    "rebound": "the damping law while a point leaves the ground",
    "sliding": "friction on the slip velocity, its torque",
    "rolling": "rolling under a normal load (rolling resistance)",
    "resting": "weight against the contact force",
}


@dataclass(frozen=True)
class Moment:
    kind: str
    row: int
    what: str      # one line: what the body is doing there


def pick_moments(scene: Scene, states: np.ndarray) -> list[Moment]:
    """The moments found in custom_sim's states (steps + 1, 6), at most one of each kind, each
    where the effect it probes acts (see the module)."""
    states = np.asarray(states, dtype=float)
    steps = len(states) - 1
    eq = Equations.from_scene(scene)
    z = states[:steps]
    depth, vcy, slip, fn = contact_loads(eq, z)
    touching = depth > 0.0
    least = least_acting_force(eq, z, scene.dt)           # N, per state
    loaded = touching & (fn > least[:, None])
    any_touch, any_load = touching.any(axis=1), loaded.any(axis=1)
    om = z[:, 5]
    points = np.asarray(eq.points, dtype=float).reshape(-1, 2)
    size = float(np.max(np.hypot(points[:, 0], points[:, 1]))) if len(points) else 0.0
    speed = np.hypot(z[:, 3], z[:, 4]) + np.abs(om) * size
    band = eq.slip_band if scene.has("friction") else np.inf
    out = []

    flight = np.flatnonzero(~any_touch & ((speed > 0.0) | (eq.g > 0.0)))
    if flight.size:
        # the middle of the first flight: well away from the switches
        first = flight[: np.argmax(np.diff(flight) > 1) + 1] if np.any(np.diff(flight) > 1) else flight
        i = int(first[len(first) // 2])
        out.append(Moment("flight", i, f"in flight at t = {i * scene.dt:.4g} s, omega = {om[i]:.3g} rad/s"))

    later = np.flatnonzero(any_load & (np.arange(steps) > flight[0])) if flight.size else flight
    if later.size:
        i = int(later[0])
        pts = np.flatnonzero(loaded[i])
        out.append(Moment("touchdown", i, f"first step in contact after flight, t = {i * scene.dt:.4g} s, "
                                          f"point {', '.join(map(str, pts))}, vy = {z[i, 4]:.3g} m/s, "
                                          f"Fn {fn[i, pts].sum():.3g} N"))

    score = rebound_score(eq, depth, vcy, loaded, least)
    score[[m.row for m in out]] = -1.0   # another state than the moments already picked
    if score.size and score.max() > 0.0:
        i = int(np.argmax(score))
        j = int(np.argmax(np.where(loaded[i] & (vcy[i] > 0.0), vcy[i], -np.inf)))
        out.append(Moment("rebound", i, f"point {j} leaving the ground at {vcy[i, j]:.3g} m/s, "
                                        f"{depth[i, j] * 1e3:.3g} mm deep, Fn {fn[i, j]:.3g} N "
                                        f"(damper {damper_leaving(eq, depth[i, j], vcy[i, j]):.3g} N), "
                                        f"t = {i * scene.dt:.4g} s"))

    if scene.has("friction"):
        # slipping beyond the stiction band under a normal load whose friction acts
        fast = loaded & (np.abs(slip) > band) & (scene.contact.mu * fn * np.tanh(1.0) > least[:, None])
        lever = np.where(fast, np.abs(om[:, None] * (-depth - z[:, 1:2])), 0.0).max(axis=1)
        # a corner sliding while the body turns: where friction's velocity and lever matter most
        score = np.where(fast.any(axis=1), lever + 1e-12 * np.abs(slip).max(axis=1), -1.0)
        score[[m.row for m in out]] = -1.0
        i = int(np.argmax(score)) if score.size else 0
        if score.size and score[i] >= 0.0:
            j = int(np.argmax(np.where(fast[i], np.abs(slip[i]), -1.0)))
            turning = f" while turning at {om[i]:.3g} rad/s" if eq.rotates else ""
            out.append(Moment("sliding", i, f"point {j} sliding at {slip[i, j]:.3g} m/s{turning} "
                                            f"under Fn {fn[i, j]:.3g} N, t = {i * scene.dt:.4g} s"))

    if scene.body.shape == "circle":
        rolling = any_load & (np.abs(slip[:, 0]) <= band) & (np.abs(om) * size > band)
        rows = np.flatnonzero(rolling)
        if rows.size:
            i = int(rows[len(rows) // 2])
            out.append(Moment("rolling", i, f"rolling at omega = {om[i]:.3g} rad/s, slip {slip[i, 0]:.2g} m/s, "
                                            f"Fn {fn[i, 0]:.3g} N, t = {i * scene.dt:.4g} s"))

    resting = np.flatnonzero(any_load & (speed < RESTING_SPEED) & carries_weight(eq, fn))
    if resting.size:
        i = int(resting[-1])
        out.append(Moment("resting", i, f"resting on point {', '.join(map(str, np.flatnonzero(loaded[i])))}, "
                                        f"speed {speed[i]:.2g} m/s, Fn {fn[i].sum():.3g} N, t = {i * scene.dt:.4g} s"))
    return out


def not_probed(scene: Scene, picked: list[Moment]) -> list[dict]:
    """The kinds of moment the scene's effects call for that no state of the run offers with
    the effect acting: [{name, effect, why}] (JSON-safe)."""
    have = {m.kind for m in picked}
    alpha = scene.contact.alpha
    band = f"{1.0 / alpha:.3g} m/s" if scene.has("friction") and alpha else "0 m/s (the sign law)"
    why = {"flight": "the body is never in flight while it moves or feels gravity"}
    if scene.has("contact"):
        why["touchdown"] = "no state in contact after a flight carries a contact force above round-off"
        undamped = scene.contact.c <= 0.0 and scene.contact.dissipation <= 0.0
        why["rebound"] = ("the scene has no damper (c = 0, no dissipation): the damping law does not act"
                          if undamped else
                          "no touching point leaves the ground under a contact force with its damper "
                          "above round-off")
        if scene.has("friction"):
            why["sliding"] = (f"no touching point slips faster than the stiction band 1/alpha = {band} "
                              f"under a normal load")
        if scene.body.shape == "circle":
            why["rolling"] = "the disk never rolls (|omega| R > 1/alpha, |slip| <= 1/alpha) under a normal load"
        why["resting"] = (f"the body never comes to rest (speed < {RESTING_SPEED:g} m/s) with the ground "
                          f"carrying its weight (to {RESTING_LOAD:.0%})")
    return [{"name": k, "effect": EFFECTS[k], "why": w} for k, w in why.items() if k not in have]
