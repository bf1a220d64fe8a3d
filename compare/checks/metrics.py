"""How far two trajectories are apart, on a common time grid (m, rad, m/s, J)."""
from __future__ import annotations

import numpy as np

from custom_sim import Trajectory
from scene_types.state import STATE_COMPONENTS as STATE


def resample(traj: Trajectory, t: np.ndarray) -> dict[str, np.ndarray]:
    """The trajectory's states and energy linearly interpolated at times t (s)."""
    out = {name: np.interp(t, traj.t, getattr(traj, name)) for name in STATE}
    out["energy"] = np.interp(t, traj.t, traj.energy)
    return out


def common_grid(a: Trajectory, b: Trajectory) -> np.ndarray:
    """The coarser of the two step grids, over the time both cover."""
    t = a.t if a.dt >= b.dt else b.t
    return t[t <= min(a.t[-1], b.t[-1]) + 1e-12]


def differences(a: Trajectory, b: Trajectory) -> dict[str, np.ndarray]:
    """Per-time differences b - a on the common grid: position distance, angle, speed."""
    t = common_grid(a, b)
    ra, rb = resample(a, t), resample(b, t)
    return {
        "t": t,
        "position": np.hypot(rb["x"] - ra["x"], rb["y"] - ra["y"]),
        "angle": np.abs(rb["theta"] - ra["theta"]),
        "velocity": np.hypot(rb["vx"] - ra["vx"], rb["vy"] - ra["vy"]),
        "angular_velocity": np.abs(rb["omega"] - ra["omega"]),
    }


def compare(a: Trajectory, b: Trajectory) -> dict[str, float]:
    """Scalar error metrics of b against a (the keys of docs/report-files.md plus velocity errors)."""
    d = differences(a, b)
    pos = d["position"]
    return {
        "position_error_max": float(pos.max()),
        "position_error_rms": float(np.sqrt(np.mean(pos * pos))),
        "position_error_final": float(pos[-1]),
        "angle_error_max": float(d["angle"].max()),
        "velocity_error_max": float(d["velocity"].max()),
        "angular_velocity_error_max": float(d["angular_velocity"].max()),
        "time_of_position_error_max": float(d["t"][np.argmax(pos)]),
    }


def energy_drift(traj: Trajectory) -> float:
    """E(end) - E(0) in J."""
    return float(traj.energy[-1] - traj.energy[0])
