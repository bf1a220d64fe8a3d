"""The seed's penalty contact law, written again for the dynamics twin (not imported from the
simulator under test), one scalar function per force. Units: m, m/s, N, N m.

For a contact point at depth d = -c_y > 0 (c its world position, the ground the line y = 0)
moving at vc = (vc_x, vc_y):

    normal, "compression"   Fn = k d + c max(0, -vc_y)     (seed Algorithm 1: damps approach only)
    normal, "linear"        Fn = max(0, k d - c vc_y)      (Kelvin-Voigt clamped: never pulls)
    friction                Ft = -mu Fn tanh(alpha vc_x)   (on the contact point's slip)
    rolling resistance      tau = -mu_roll Fn tanh(ROLL_SHARPNESS omega)

The rolling law's sign(omega) is regularised like the sliding law's sign(v): a bare sign makes a
disk that rolling resistance has stopped flip omega every step and creep. ROLL_SHARPNESS is the
scene format's documented regularisation (the simulator under test states the same 100 s/rad);
it is part of the law, not of either implementation.
"""
from __future__ import annotations

import math

from numba import njit

COMPRESSION, LINEAR = 0, 1
DAMPING_LAWS = {"compression": COMPRESSION, "linear": LINEAR}
ROLL_SHARPNESS = 100.0   # s/rad: full rolling resistance above |omega| ~ 0.03 rad/s


@njit(cache=True)
def normal_force(law, k, c, depth, vn):
    """Fn (N) at depth > 0 (m), normal velocity vn (m/s, > 0 leaving the ground)."""
    if law == COMPRESSION:
        return k * depth + c * max(0.0, -vn)
    return max(0.0, k * depth - c * vn)


@njit(cache=True)
def friction_force(mu, alpha, fn, slip):
    """Ft (N) against the slip velocity (m/s) of the contact point."""
    return -mu * fn * math.tanh(alpha * slip)


@njit(cache=True)
def rolling_torque(mu_roll, fn, omega):
    """Rolling-resistance torque (N m, counter-clockwise positive) at angular velocity omega."""
    return -mu_roll * fn * math.tanh(ROLL_SHARPNESS * omega)
