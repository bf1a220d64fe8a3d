"""How far the motion moves when the contact force is off by a known relative error: an
ensemble of custom_sim runs, each perturbed within the penalty mapping's measured error.

A relative force error eps (impedance.py) enters the motion in two ways, and each has its
ensemble members:

    force      k and c scaled by 1 + s eps: every contact force off by the share s eps
    torque     the inverse inertia scaled by 1 + s eps_t: the contact torque off by s eps_t while
               the force is not. Two corners touching at once couple through the body
               (A's off-diagonal terms): MuJoCo's error then shifts load between them, which
               turns the body without changing the total force. (Gravity gives every body the
               same acceleration whatever its inertia, so only the contact is perturbed.)
               eps_t is the torque's own measured error (impedance.py).

with s in FORCE_SHARES (and +-1 for the torque members, bodies that turn only). The spread is,
at each time, the largest distance of a member from the unperturbed run. custom_sim's runs
cost milliseconds, so the ensemble is cheap next to one MuJoCo run.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from custom_sim import Scene, SimulationDiverged, mass_properties
from custom_sim.chatter import WATCH_COLUMNS
from custom_sim.integrators import INTEGRATORS, integrate
from custom_sim.model import build_model, initial_state
from custom_sim.runner import blowup_guard

# Shares of the measured error the force members take: both signs, the full error and half of
# it (the response of a contact switch on a step grid is not monotonic in the force).
FORCE_SHARES = (-1.0, -0.5, 0.5, 1.0)
TORQUE_SHARES = (-1.0, 1.0)


def run_states(scene: Scene, integrator: str, dt: float, force_scale: float = 1.0,
               torque_scale: float = 1.0) -> np.ndarray:
    """custom_sim's states (steps + 1, 6) for the scene at (integrator, dt), with k, c scaled by
    force_scale and the inverse inertia by torque_scale. Raises SimulationDiverged."""
    scene = dataclasses.replace(scene, integrator=integrator, dt=dt)
    if force_scale != 1.0:
        ct = scene.contact
        scene = dataclasses.replace(scene, contact=dataclasses.replace(
            ct, k=ct.k * force_scale, c=ct.c * force_scale))
    props = mass_properties(scene.body)
    model, points = build_model(scene, props)
    model = model._replace(inv_inertia=model.inv_inertia * torque_scale)
    z = initial_state(scene)
    n = scene.steps
    out = np.empty((n + 1, 6))
    out[0] = z
    counters = np.zeros(4, dtype=np.int64)
    guard = blowup_guard(scene, props, z, applied_input=False)
    failed = integrate(model, points, z, dt, n, INTEGRATORS[integrator].code, np.zeros((1, 3)),
                       out[1:], counters, guard, np.empty((0, WATCH_COLUMNS)))  # chatter: not watched
    if failed >= 0:
        raise SimulationDiverged(scene, integrator, dt, int(failed), z.copy())
    return out


def members(scene: Scene, eps: float, eps_torque: float | None = None) -> list[tuple[float, float]]:
    """(force_scale, torque_scale) of each ensemble member for relative errors eps of the force
    and eps_torque of the torque (default eps)."""
    eps_torque = eps if eps_torque is None else eps_torque
    out = [(1.0 + s * eps, 1.0) for s in FORCE_SHARES]
    if mass_properties(scene.body).rotates:
        out += [(1.0, 1.0 + s * eps_torque) for s in TORQUE_SHARES]
    return out


def spread(scene: Scene, eps: float, integrator: str, dt: float, eps_torque: float | None = None,
           centre: np.ndarray | None = None):
    """(centre states, position spread (steps + 1,) m, angle spread rad, members): the
    unperturbed run (centre, if the caller has it) and, at each time, the largest distance of
    a member from it."""
    centre = run_states(scene, integrator, dt) if centre is None else centre
    pos = np.zeros(len(centre))
    ang = np.zeros(len(centre))
    chosen = members(scene, eps, eps_torque)
    for force, torque in chosen:
        other = run_states(scene, integrator, dt, force, torque)
        pos = np.maximum(pos, np.hypot(other[:, 0] - centre[:, 0], other[:, 1] - centre[:, 1]))
        ang = np.maximum(ang, np.abs(other[:, 2] - centre[:, 2]))
    return centre, pos, ang, chosen
