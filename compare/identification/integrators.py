"""The four integrators as observations: where each evaluates the force, and RK4's step, vectorised."""
from __future__ import annotations

import numpy as np

from .model import Kinematics, Law, accelerations

NAMES = ("explicit_euler", "semi_implicit_euler", "implicit_euler", "rk4")
# In q1 = q0 + h v0 + beta h (v1 - v0): the share of the new velocity each takes, exact under a
# constant force (free flight); RK4 integrates a constant force exactly, which is beta = 1/2.
POSITION_SHARE = {"explicit_euler": 0.0, "semi_implicit_euler": 1.0, "implicit_euler": 1.0, "rk4": 0.5}
# How far below its start the state a step evaluates the force at falls in free fall from rest
# under gravity, in units of g h^2 (the onset of contact is seen there): z0 itself for the
# explicit steps, RK4's last stage z0 - g h^2 / 2. Implicit Euler is started moving up at the
# speed its own free fall takes off in one step (onset.py), so that it reads the force at rest
# at its start height: 0. (Read moving down, a damper engages with c |v_n| the moment the point
# touches, and the step's equation has no root for depths below h c |v_n| / k.)
FALL_SHARE = {"explicit_euler": 0.0, "semi_implicit_euler": 0.0, "implicit_euler": 0.0, "rk4": 0.5}
# The integrators that read the force at the end of the step, at the velocity they end with.
READS_AT_END = ("implicit_euler",)


def evaluated_at(integrator: str, Z0: np.ndarray, Z1: np.ndarray) -> np.ndarray | None:
    """The states the Euler steps evaluate the force at (None for RK4: four states)."""
    if integrator in ("explicit_euler", "semi_implicit_euler"):
        return Z0
    if integrator == "implicit_euler":
        return Z1
    return None


def rk4_step(law: Law, Z0: np.ndarray, H: np.ndarray) -> np.ndarray:
    """One classical RK4 step of the law from every row of Z0 with its own step H (s)."""
    H = np.asarray(H, dtype=float)[:, None]

    def f(Z):
        return np.hstack([Z[:, 3:], accelerations(law, Z)])
    k1 = f(Z0)
    k2 = f(Z0 + 0.5 * H * k1)
    k3 = f(Z0 + 0.5 * H * k2)
    k4 = f(Z0 + H * k3)
    return Z0 + H / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


def predicted_rate(law: Law, integrator: str, Z0: np.ndarray, Z1: np.ndarray, H: np.ndarray,
                   kin: Kinematics | None = None) -> np.ndarray:
    """The velocity change over h (n, 3) the law gives under the integrator: a at the state the
    Euler steps evaluate it, RK4's own combination of four (kin: the kinematics of the state
    an Euler step evaluates, when already computed)."""
    Ze = evaluated_at(integrator, Z0, Z1)
    if Ze is not None:
        return accelerations(law, Ze, kin)
    return (rk4_step(law, Z0, H)[:, 3:] - Z0[:, 3:]) / np.asarray(H, dtype=float)[:, None]


def position_residual(Z0: np.ndarray, Z1: np.ndarray, H: np.ndarray, share: float) -> np.ndarray:
    """q1 - (q0 + h ((1 - share) v0 + share v1)) (n, 3), m and rad: zero for the integrator whose
    POSITION_SHARE it is (for RK4 only under a constant force)."""
    H = np.asarray(H, dtype=float)[:, None]
    return Z1[:, :3] - (Z0[:, :3] + H * ((1.0 - share) * Z0[:, 3:] + share * Z1[:, 3:]))
