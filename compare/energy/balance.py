"""The work-energy balance of a run: E(t) - E(0) + W(t) = R(t), R the energy the numerics made or lost."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scene_types import Scene
from scene_types.trajectory import CSV_RELATIVE_ROUNDING

from .law import EFFECTS, body_of
from .terms import energy
from .work import StepWork, step_work


@dataclass(frozen=True)
class Balance:
    """One trajectory's balance, arrays over its T states: t (s); E (J), the mechanical energy
    (kinetic + m g y + sum k d^2 / 2); W (T, 3) J, the work done so far against damping,
    friction and rolling resistance (EFFECTS); R = E - E(0) + W (J), zero for the exact
    motion. rule: how W was accumulated (work.RULES); step_mismatch (6,): the recorded steps
    against the named integrator's steps (nan under the trapezoid rule); jump_steps: implicit
    Euler's touchdown jumps; selected_steps: its steps where a bare sign law applied a value of
    its set; quadrature_bound (J): the trapezoid rule's error bound on W summed
    over the effects (0 when the integrator's own rule was used)."""

    t: np.ndarray
    E: np.ndarray
    W: np.ndarray
    R: np.ndarray
    rule: str
    integrator: str | None
    step_mismatch: np.ndarray
    jump_steps: int = 0
    quadrature_bound: float = 0.0
    selected_steps: int = 0

    @property
    def dissipated(self) -> np.ndarray:
        """Work against every effect together (T,) J."""
        return self.W.sum(axis=1)


def step_sizes(t, dt: float) -> np.ndarray:
    """The steps h (T - 1,) s of the times t (T,): dt itself when every step is dt to within
    the rounding of t (a written time carries a relative CSV_RELATIVE_ROUNDING, and a
    difference of two the sum of both), so that no round-off of t enters a step; else the
    common step of evenly spaced times, else the differences themselves."""
    t = np.asarray(t, dtype=float)
    diffs = np.diff(t)
    if len(diffs) == 0:
        return diffs
    rounding = 2.0 * (CSV_RELATIVE_ROUNDING + np.finfo(float).eps) * float(np.max(np.abs(t)))
    even = (t[-1] - t[0]) / len(diffs)
    if np.max(np.abs(diffs - even)) > rounding:
        return diffs
    return np.full(len(diffs), dt if abs(dt - even) <= rounding / len(diffs) else even)


def from_parts(t, E, increments: StepWork, integrator: str | None) -> Balance:
    """A Balance from the energy (T,) and each step's work."""
    W = np.vstack([np.zeros((1, 3)), np.cumsum(increments.work, axis=0)])
    return Balance(np.asarray(t, dtype=float), E, W, E - E[0] + W.sum(axis=1), increments.rule, integrator,
                   increments.step_mismatch, increments.jump_steps, increments.quadrature_bound,
                   increments.selected_steps)


def balance(scene: Scene, t, states, integrator: str | None = None) -> Balance:
    """The balance of the states (T, 6) = [x, y, theta, vx, vy, omega] at times t (T,) s of a
    run of the scene. integrator: the one that took the steps (explicit_euler,
    semi_implicit_euler, implicit_euler, rk4), whose own rule then gives W; None (a
    trajectory of unknown origin, a user's CSV): the trapezoid rule on the dissipated power."""
    Z = np.atleast_2d(np.asarray(states, dtype=float))
    rb = body_of(scene)
    h = step_sizes(t, scene.dt)
    return from_parts(t, energy(scene, rb, Z), step_work(scene, rb, h, Z, integrator), integrator)


def metrics_block(b: Balance) -> dict:
    """The metrics.json block of one trajectory (J): delta_E = E(end) - E(0), the work
    dissipated per effect, R at the end and its largest magnitude."""
    measured = bool(np.all(np.isfinite(b.R)))   # None where the balance could not be measured (b.rule says why)
    return {
        "delta_E": float(b.E[-1] - b.E[0]),
        "dissipated": {name: float(b.W[-1, i]) + 0.0 for i, name in enumerate(EFFECTS)},  # + 0.0: no -0.0
        "residual_end": float(b.R[-1]) if measured else None,
        "residual_max": float(np.max(np.abs(b.R))) if measured else None,
    }
