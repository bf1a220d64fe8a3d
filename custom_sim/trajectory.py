"""The trajectory type both simulators return, and its CSV writer (columns of CONTRACT.md)."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

CSV_COLUMNS = ("t", "x", "y", "theta", "vx", "vy", "omega", "energy")


@dataclass(frozen=True)
class Trajectory:
    """States of the centre of mass in the scene's 2D frame, row 0 the initial state (t = 0),
    row i the state after step i. Arrays have shape (steps + 1,).

    Units: t s; x, y m; theta rad (counter-clockwise); vx, vy m/s; omega rad/s; energies J.
    energy = kinetic + gravitational (m g y) + elastic contact (sum of k d^2 / 2).
    """

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    theta: np.ndarray
    vx: np.ndarray
    vy: np.ndarray
    omega: np.ndarray
    energy_kinetic: np.ndarray
    energy_gravity: np.ndarray
    energy_contact: np.ndarray
    simulator: str = "custom"
    integrator: str = ""
    dt: float = 0.0
    force_evals: int = 0          # evaluations of the force law (RK4: 4 per step, ...)
    newton_iterations: int = 0    # implicit Euler only: Newton iterations over the run
    wall_time: float = 0.0        # s, the time-stepping loop alone
    meta: dict = field(default_factory=dict)

    @property
    def energy(self) -> np.ndarray:
        return self.energy_kinetic + self.energy_gravity + self.energy_contact

    @property
    def steps(self) -> int:
        return len(self.t) - 1

    def states(self) -> np.ndarray:
        """(steps + 1, 6) array of x, y, theta, vx, vy, omega."""
        return np.column_stack([self.x, self.y, self.theta, self.vx, self.vy, self.omega])


def write_csv(traj: Trajectory, path: str | Path) -> None:
    """Header row, then one row per step (t = dt, 2 dt, ...): the state after each step."""
    rows = np.column_stack([getattr(traj, c) if c != "energy" else traj.energy for c in CSV_COLUMNS])[1:]
    if not np.all(np.isfinite(rows)):
        raise ValueError(f"refusing to write non-finite values to {path}")
    np.savetxt(path, rows, delimiter=",", header=",".join(CSV_COLUMNS), comments="", fmt="%.10g")


def read_csv(path: str | Path) -> dict[str, np.ndarray]:
    """Columns of a trajectory CSV by name."""
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {c: data[:, i] for i, c in enumerate(CSV_COLUMNS)}
