"""When a twin's run is void: its own blow-up test, on MuJoCo's state and MuJoCo's energy.

A row has blown up when it is not finite, lies beyond POSITION_LIMIT or moves faster than
SPEED_LIMIT, or, without applied input, holds more mechanical energy above the lowest pose than
ENERGY_GROWTH_LIMIT times what the run started with: every effect of a scene conserves or
dissipates energy, so only an unstable step grows it tenfold (explicit Euler gains a few per cent
a bounce). The thresholds are the harness's definition of "diverged"; the energy here is
MuJoCo's (energy.py) above the COM's lowest height (rigid_body.py), not the simulator under test's.
"""
from __future__ import annotations

import numpy as np

from .rigid_body import RigidBody

POSITION_LIMIT = 1e6       # m: far beyond any scene
SPEED_LIMIT = 1e5          # m/s and rad/s: the fastest stress scene hits at 30 m/s, spins at 100 rad/s
ENERGY_GROWTH_LIMIT = 10.0
ENERGY_FLOOR = 1.0         # J/kg: the budget of a body that starts at rest on its lowest pose


def first_blowup(states: np.ndarray, kinetic: np.ndarray, potential: np.ndarray,
                 rb: RigidBody, g: float) -> int:
    """Index of the first row of states (T, 6) that has blown up (module docstring), or -1.
    kinetic, potential: MuJoCo's energies of the rows (J); g: the gravity the twin runs (m/s^2)."""
    finite = np.all(np.isfinite(states), axis=1) & np.isfinite(kinetic) & np.isfinite(potential)
    with np.errstate(invalid="ignore"):
        far = np.any(np.abs(states[:, :2]) > POSITION_LIMIT, axis=1)
        fast = np.any(np.abs(states[:, 3:]) > SPEED_LIMIT, axis=1)
        above_lowest = kinetic + potential - rb.mass * g * rb.lowest_com_height
        budget = ENERGY_GROWTH_LIMIT * max(float(above_lowest[0]), ENERGY_FLOOR * rb.mass)
        rich = above_lowest > budget
    bad = ~finite | far | fast | rich
    return int(np.argmax(bad)) if bad.any() else -1
