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
         "mujoco": dict(color="tab:orange", lw=1.2, ls="--", label="MuJoCo"),
         "user": dict(color="tab:green", lw=1.4, ls="-.", label="your simulator"),
         "reference": dict(color="black", lw=0.8, ls=":", label="converged reference")}
INTEGRATOR_COLOURS = {"explicit_euler": "tab:red", "semi_implicit_euler": "tab:blue",
                      "implicit_euler": "tab:purple", "rk4": "tab:green"}


def _every(n: int) -> slice:
    return slice(None, None, max(1, n // MAX_POINTS))


# Fixed margins (fractions of the figure) that hold the axis labels and titles of these
# figures: matplotlib's tight_layout measured every tick label and took a third of a report.
MARGINS = dict(left=0.14, right=0.97, bottom=0.1, top=0.92, hspace=0.3, wspace=0.25)


def _save(fig, path: Path) -> str:
    fig.subplots_adjust(**MARGINS)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path.name


def states(scene: Scene, shown: tuple[Trajectory, ...], path: Path, reference=None) -> str:
    """x, y, theta against time; reference: the converged reference's states (steps + 1, 6)."""
    fig, axes = plt.subplots(3, 1, figsize=(8, 7), sharex=True)
    for j, (ax, name, unit) in enumerate(zip(axes, ("x", "y", "theta"), ("m", "m", "rad"))):
        for tr in shown:
            k = _every(len(tr.t))
            ax.plot(tr.t[k], getattr(tr, name)[k], **STYLE[tr.simulator])
        if reference is not None:
            k = _every(len(reference))
            ax.plot((scene.dt * np.arange(len(reference)))[k], reference[k, j], **STYLE["reference"])
        ax.set_ylabel(f"{name} ({unit})")
        ax.grid(alpha=0.3)
    axes[0].legend(loc="best")
    axes[-1].set_xlabel("time (s)")
    axes[0].set_title(f"{scene.name}: centre of mass and angle against time")
    return _save(fig, path)


def path_in_plane(scene: Scene, shown: tuple[Trajectory, ...], path: Path) -> str:
    fig, ax = plt.subplots(figsize=(8, 4))
    for tr in shown:
        k = _every(len(tr.t))
        ax.plot(tr.x[k], tr.y[k], **STYLE[tr.simulator])
    ax.axhline(0.0, color="0.3", lw=2, label="ground y = 0")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"{scene.name}: path of the centre of mass")
    ax.legend(loc="best")
    ax.grid(alpha=0.3)
    return _save(fig, path)


def error(scene: Scene, diffs: dict, path: Path) -> str:
    """The difference to MuJoCo's own contact against time (shown; attributed on the page)."""
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    t = diffs["t"]
    k = _every(len(t))
    ax1.semilogy(t[k], np.maximum(diffs["position"][k], 1e-12), color="tab:red", label="|p_MuJoCo - p_tested|")
    ax1.set_ylabel("position difference (m)")
    ax1.legend(loc="best")
    ax1.grid(alpha=0.3, which="both")
    ax2.semilogy(t[k], np.maximum(diffs["angle"][k], 1e-12), color="tab:purple", label="|theta_MuJoCo - theta_tested|")
    ax2.set_ylabel("angle difference (rad)")
    ax2.set_xlabel("time (s)")
    ax2.legend(loc="best")
    ax2.grid(alpha=0.3, which="both")
    ax1.set_title(f"{scene.name}: difference to MuJoCo's own contact (penalty mapping)")
    return _save(fig, path)


def energy(scene: Scene, shown: tuple[Trajectory, ...], path: Path) -> str:
    fig, ax = plt.subplots(figsize=(8, 4))
    for tr in shown:
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
    for tr in (a, b):
        axes[0].plot([], [], **STYLE[tr.simulator])
    axes[0].legend(loc="upper left", fontsize=7)
    fig.suptitle(f"{scene.name}: snapshots ({STYLE[a.simulator]['label']} and dashed MuJoCo)")
    return _save(fig, path)


def step_residuals(scene: Scene, residuals: dict, checks: list[dict], path: Path) -> str | None:
    """Each integrator's one-step residual against time, with its round-off bound.
    residuals: integrator -> per-step position residual (m), shape (steps,)."""
    shown = {name: r for name, r in residuals.items() if r is not None and len(r)}
    if not shown:
        return None
    bounds = {c["integrator"]: c["tolerance_position"] for c in checks if c["name"] == "step"}
    fig, ax = plt.subplots(figsize=(8, 4))
    for name, r in shown.items():
        r = np.asarray(r, dtype=float)
        t = scene.dt * np.arange(1, len(r) + 1)
        k = _every(len(t))
        colour = INTEGRATOR_COLOURS.get(name, "tab:gray")
        ax.semilogy(t[k], np.maximum(r[k], 1e-20), color=colour, lw=1, label=name)
        if bounds.get(name):
            ax.axhline(bounds[name], color=colour, ls=":", lw=1)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("one-step position residual (m)")
    ax.set_title(f"{scene.name}: each step against the independent step (dotted: round-off bound)")
    ax.legend(loc="best", fontsize=8)
    ax.grid(alpha=0.3, which="both")
    return _save(fig, path)
