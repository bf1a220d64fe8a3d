"""Every contact-law family of scene_types.laws, written again for the dynamics twin (docs/mujoco-twins.md)."""
from __future__ import annotations

import math

from numba import njit

# each family an integer code, on which the compiled callback (passive.py) branches; a code no
# branch knows gives NaN (the twin's blow-up guard reports it), and passive.law_parameters
# refuses an unknown name before any run
COMPRESSION, LINEAR, UNCLAMPED, HUNT_CROSSLEY = 0, 1, 2, 3
TANH, RAMP, SMOOTH_COULOMB, SIGN = 0, 1, 2, 3
ROLL_TANH, ROLL_SIGN = 0, 1
DAMPING_CODES = {"compression": COMPRESSION, "linear": LINEAR, "unclamped": UNCLAMPED,
                 "hunt_crossley": HUNT_CROSSLEY}
FRICTION_CODES = {"tanh": TANH, "ramp": RAMP, "smooth_coulomb": SMOOTH_COULOMB, "sign": SIGN}
ROLL_CODES = {"tanh": ROLL_TANH, "sign": ROLL_SIGN}


@njit(cache=True)
def _sign(x):
    """sign(x): -1, 0 or 1."""
    if x > 0.0:
        return 1.0
    if x < 0.0:
        return -1.0
    return 0.0


@njit(cache=True)
def normal_force(law, k, c, dissipation, depth, vn):
    """Fn (N) at depth > 0 (m), normal velocity vn (m/s, > 0 leaving); k N/m, c N s/m,
    dissipation s/m. compression k d + c max(0, -vn); linear max(0, k d - c vn); unclamped
    k d - c vn; hunt_crossley max(0, k d (1 - dissipation vn))."""
    if law == COMPRESSION:
        return k * depth + c * max(0.0, -vn)
    if law == LINEAR:
        return max(0.0, k * depth - c * vn)
    if law == UNCLAMPED:
        return k * depth - c * vn
    if law == HUNT_CROSSLEY:
        return max(0.0, k * depth * (1.0 - dissipation * vn))
    return math.nan


@njit(cache=True)
def friction_force(law, mu, alpha, fn, slip):
    """Ft (N) at the friction point's slip velocity (m/s); alpha s/m. -mu Fn times: tanh
    tanh(alpha v); ramp clamp(alpha v, -1, 1); smooth_coulomb v / sqrt(v^2 + 1/alpha^2);
    sign sign(v) (alpha not read)."""
    if law == TANH:
        return -mu * fn * math.tanh(alpha * slip)
    if law == RAMP:
        return -mu * fn * min(1.0, max(-1.0, alpha * slip))
    if law == SMOOTH_COULOMB:
        return -mu * fn * slip / math.sqrt(slip * slip + 1.0 / (alpha * alpha))
    if law == SIGN:
        return -mu * fn * _sign(slip)
    return math.nan


@njit(cache=True)
def rolling_torque(law, mu_roll, sharpness, fn, omega):
    """Rolling-resistance torque (N m, counter-clockwise positive) at omega (rad/s); mu_roll m,
    sharpness s/rad. -mu_roll Fn times: tanh tanh(sharpness omega); sign sign(omega)."""
    if law == ROLL_TANH:
        return -mu_roll * fn * math.tanh(sharpness * omega)
    if law == ROLL_SIGN:
        return -mu_roll * fn * _sign(omega)
    return math.nan
