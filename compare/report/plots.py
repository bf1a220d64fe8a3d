"""The figures of a scenario's page: each a PNG with labelled axes, units, a legend and a title."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from custom_sim import Scene, Trajectory  # noqa: E402

from .drawing import outlines  # noqa: E402

MAX_POINTS = 4000  # per line: more is invisible at this size and slows drawing
STYLE = {"custom": dict(color="tab:blue", lw=1.6, label="custom_sim"),
         "mujoco": dict(color="tab:orange", lw=1.2, ls="--", label="MuJoCo")}


def _every(n: int) -> slice:
    return slice(None, None, max(1, n // MAX_POINTS))


def _save(fig, path: Path) -> str:
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path.name


def states(scene: Scene, a: Trajectory, b: Trajectory, path: Path) -> str:
    fig, axes = plt.subplots(3, 1, figsize=(8, 7), sharex=True)
    for ax, name, unit in zip(axes, ("x", "y", "theta"), ("m", "m", "rad")):
        for tr in (a, b):
            k = _every(len(tr.t))
            ax.plot(tr.t[k], getattr(tr, name)[k], **STYLE[tr.simulator])
        ax.set_ylabel(f"{name} ({unit})")
        ax.grid(alpha=0.3)
    axes[0].legend(loc="best")
    axes[-1].set_xlabel("time (s)")
    axes[0].set_title(f"{scene.name}: centre of mass and angle against time")
    return _save(fig, path)


def path_in_plane(scene: Scene, a: Trajectory, b: Trajectory, path: Path) -> str:
    fig, ax = plt.subplots(figsize=(8, 4))
    for tr in (a, b):
        k = _every(len(tr.t))
        ax.plot(tr.x[k], tr.y[k], **STYLE[tr.simulator])
    ax.axhline(0.0, color="0.3", lw=2, label="ground y = 0")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"{scene.name}: path of the centre of mass")
    ax.legend(loc="best")
    ax.grid(alpha=0.3)
    return _save(fig, path)


def error(scene: Scene, diffs: dict, tol, path: Path) -> str:
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    t = diffs["t"]
    k = _every(len(t))
    ax1.semilogy(t[k], np.maximum(diffs["position"][k], 1e-12), color="tab:red", label="|p_MuJoCo - p_custom|")
    if tol.checked and tol.position is not None:
        ax1.axhline(tol.position, color="k", ls=":", label=f"tolerance {tol.position:.2g} m")
    ax1.set_ylabel("position difference (m)")
    ax1.legend(loc="best")
    ax1.grid(alpha=0.3, which="both")
    ax2.semilogy(t[k], np.maximum(diffs["angle"][k], 1e-12), color="tab:purple", label="|theta_MuJoCo - theta_custom|")
    if tol.checked and tol.angle is not None:
        ax2.axhline(tol.angle, color="k", ls=":", label=f"tolerance {tol.angle:.2g} rad")
    ax2.set_ylabel("angle difference (rad)")
    ax2.set_xlabel("time (s)")
    ax2.legend(loc="best")
    ax2.grid(alpha=0.3, which="both")
    ax1.set_title(f"{scene.name}: difference between the simulators")
    return _save(fig, path)


def energy(scene: Scene, a: Trajectory, b: Trajectory, path: Path) -> str:
    fig, ax = plt.subplots(figsize=(8, 4))
    for tr in (a, b):
        k = _every(len(tr.t))
        ax.plot(tr.t[k], tr.energy[k], **STYLE[tr.simulator])
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy (J)")
    ax.set_title(f"{scene.name}: kinetic + gravitational + elastic contact energy")
    ax.legend(loc="best")
    ax.grid(alpha=0.3)
    return _save(fig, path)


def snapshots(scene: Scene, a: Trajectory, b: Trajectory, path: Path, count: int = 6) -> str:
    """The body drawn by both simulators at `count` instants, side by side in a strip."""
    times = np.linspace(0.0, min(a.t[-1], b.t[-1]), count)
    fig, axes = plt.subplots(1, count, figsize=(2.2 * count, 3.2), sharey=True)
    extent = max(0.15, float(np.ptp(np.concatenate([a.y, b.y]))) / 2 + 0.15)
    for ax, t in zip(axes, times):
        for tr in (a, b):
            i = min(int(np.searchsorted(tr.t, t)), len(tr.t) - 1)
            style = STYLE[tr.simulator]
            for poly in outlines(scene, tr.x[i], tr.y[i], tr.theta[i]):
                ax.plot(poly[:, 0], poly[:, 1], color=style["color"], ls=style.get("ls", "-"), lw=1.5)
        i = min(int(np.searchsorted(a.t, t)), len(a.t) - 1)
        ax.axhline(0.0, color="0.3", lw=2)
        ax.set_xlim(a.x[i] - extent, a.x[i] + extent)
        ax.set_ylim(-0.05, 2 * extent - 0.05)
        ax.set_aspect("equal")
        ax.set_title(f"t = {t:.2f} s", fontsize=9)
        ax.set_xlabel("x (m)", fontsize=8)
        ax.tick_params(labelsize=7)
    axes[0].set_ylabel("y (m)")
    axes[0].plot([], [], **{k: v for k, v in STYLE["custom"].items()})
    axes[0].plot([], [], **{k: v for k, v in STYLE["mujoco"].items()})
    axes[0].legend(loc="upper left", fontsize=7)
    fig.suptitle(f"{scene.name}: snapshots (solid custom_sim, dashed MuJoCo)")
    return _save(fig, path)
