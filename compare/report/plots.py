"""The figures of a scenario's page: each a PNG with labelled axes, units, a legend and a title.

Each figure's data (lines, legends, titles) is drawn here into its frame (compare/report/frames.py:
the axes with their labels, scales, ticks and grid, built ahead where it could be).
"""
from __future__ import annotations

import contextlib
import gc
from pathlib import Path

import numpy as np

from custom_sim import Scene, Trajectory
from scene_types.state import POSE

from .drawing import outlines
from ..checks.step_check import COMPONENTS
from .frames import RESIDUAL_PANELS, frame, harness_rc, save

# A line of more points than this is drawn through the lowest and highest point of each of
# MAX_POINTS / 2 equal runs of samples (its envelope): about three per pixel column of these
# 800-pixel figures, so nothing visible is lost (a spike, a round-off band, a bounce), and a
# round-off residual does not become 10^5 jagged segments that take a second to rasterise.
MAX_POINTS = 2000
STYLE = {"custom": dict(color="tab:blue", lw=1.6, label="custom_sim"),
         "mujoco": dict(color="tab:orange", lw=1.2, ls="--", label="MuJoCo"),
         "user": dict(color="tab:green", lw=1.4, ls="-.", label="your simulator"),
         "reference": dict(color="black", lw=0.8, ls=":", label="converged reference")}
E_PLUS_W_STYLE = dict(lw=0.9, alpha=0.7, ls=":")   # E + W beside each run's E
FOOT = 1e-3   # a residual of exactly 0 is drawn this far below the smallest round-off bound of its panel
INTEGRATOR_COLOURS = {"explicit_euler": "tab:red", "semi_implicit_euler": "tab:blue",
                      "implicit_euler": "tab:purple", "rk4": "tab:green"}


def _envelope(y: np.ndarray) -> np.ndarray | slice:
    """Indices of y to draw: all of them up to MAX_POINTS, else the first and last sample and
    each run's lowest and highest, in order."""
    n = len(y)
    if n <= MAX_POINTS:
        return slice(None)
    runs = MAX_POINTS // 2
    width = -(-n // runs)
    padded = np.concatenate([y, np.full(runs * width - n, y[-1])]).reshape(runs, width)
    offset = width * np.arange(runs)
    picked = np.concatenate([[0, n - 1], offset + padded.argmin(axis=1), offset + padded.argmax(axis=1)])
    return np.unique(np.minimum(picked, n - 1))


@contextlib.contextmanager
def _young_objects_only():
    """The garbage collector kept to the objects made inside the block: drawing makes enough of
    them to start full collections, each walking every object of a scenario's process (its
    trajectories, MuJoCo, scipy), which was a fifth of drawing its figures. Objects frozen
    already (by whoever froze them) are left so."""
    if gc.get_freeze_count():
        yield
        return
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()


def draw_all(figures: dict, warnings: list) -> dict:
    """Each figure drawn under matplotlib's defaults plus frames.HARNESS_RC (whatever a user's
    module set: text.usetex, a style); one that fails is left out, with a warning: a plot never
    costs a verdict. figures: name -> function drawing it (returns the file name or None)."""
    import warnings as python_warnings

    drawn = {}
    with _young_objects_only():
        for name, draw in figures.items():
            try:
                with python_warnings.catch_warnings(), harness_rc():
                    python_warnings.simplefilter("ignore")
                    drawn[name] = draw()
            except Exception as exc:  # noqa: BLE001 - a figure is not a verdict
                text = str(exc).strip().splitlines()
                warnings.append(f"the {name} figure could not be drawn ({type(exc).__name__}: "
                                f"{text[0] if text else ''}); the checks are unaffected")
                drawn[name] = None
    return drawn


def states(scene: Scene, shown: tuple[Trajectory, ...], path: Path, reference=None) -> str:
    """x, y, theta against time; reference: the converged reference's states (steps + 1, 6)."""
    fig, axes = frame("states")
    for j, (ax, name) in enumerate(zip(axes, POSE)):
        for tr in shown:
            y = getattr(tr, name)
            k = _envelope(y)
            ax.plot(tr.t[k], y[k], **STYLE[tr.simulator])
        if reference is not None:
            k = _envelope(reference[:, j])
            ax.plot((scene.dt * np.arange(len(reference)))[k], reference[k, j], **STYLE["reference"])
    axes[0].legend(loc="best")
    axes[0].set_title(f"{scene.name}: centre of mass and angle against time")
    return save(fig, path)


def path_in_plane(scene: Scene, shown: tuple[Trajectory, ...], path: Path) -> str:
    fig, (ax,) = frame("path")
    for tr in shown:
        k = _envelope(tr.y)
        ax.plot(tr.x[k], tr.y[k], **STYLE[tr.simulator])
    ax.axhline(0.0, color="0.3", lw=2, label="ground y = 0")
    ax.set_title(f"{scene.name}: path of the centre of mass")
    ax.legend(loc="best")
    return save(fig, path)


def error(scene: Scene, diffs: dict, path: Path) -> str:
    """The difference to MuJoCo's own contact against time (shown; attributed on the page)."""
    fig, (ax1, ax2) = frame("error")
    t = diffs["t"]
    position, angle = np.maximum(diffs["position"], 1e-12), np.maximum(diffs["angle"], 1e-12)
    k = _envelope(position)
    ax1.plot(t[k], position[k], color="tab:red", label="|p_MuJoCo - p_tested|")
    ax1.legend(loc="best")
    k = _envelope(angle)
    ax2.plot(t[k], angle[k], color="tab:purple", label="|theta_MuJoCo - theta_tested|")
    ax2.legend(loc="best")
    ax1.set_title(f"{scene.name}: difference to MuJoCo's own contact (penalty mapping)")
    return save(fig, path)


def energy(scene: Scene, balances: dict, path: Path) -> str:
    """The work-energy balance (compare/energy) of each run: E and E + W above (E + W stays at
    E(0) for the exact motion), the residual R = E - E(0) + W below (the numerics' energy)."""
    fig, (top, bottom) = frame("energy")
    for name, b in balances.items():
        style = dict(_style_of(name), label=name if name in ("custom_sim", "reference") else _style_of(name)["label"])
        kept = E_PLUS_W_STYLE if name != "reference" else {}
        k = _envelope(b.E)
        top.plot(b.t[k], b.E[k], **style)
        if name != "reference":
            e_plus_w = b.E + b.dissipated
            k = _envelope(e_plus_w)
            top.plot(b.t[k], e_plus_w[k], **{**style, **kept, "label": f"{style['label']}: E + W"})
        k = _envelope(b.R)
        bottom.plot(b.t[k], b.R[k], **style)
    top.set_title(f"{scene.name}: E = kinetic + m g y + sum k d^2 / 2, and E + W (W: the work dissipated)")
    top.legend(loc="best", fontsize=8)
    bottom.axhline(0.0, color="0.6", lw=0.8)
    return save(fig, path)


def _style_of(name: str) -> dict:
    """A run's line style by the simulator's name (the simulator under test otherwise)."""
    return STYLE.get({"custom_sim": "custom"}.get(name, name), STYLE["user"])


def snapshots(scene: Scene, a: Trajectory, b: Trajectory, path: Path) -> str:
    """The body drawn by both simulators at frames.SNAPSHOTS instants, side by side in a strip."""
    fig, axes = frame("snapshots")
    times = np.linspace(0.0, min(a.t[-1], b.t[-1]), len(axes))
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
        ax.set_title(f"t = {t:.2f} s", fontsize=9)
    for tr in (a, b):
        axes[0].plot([], [], **STYLE[tr.simulator])
    axes[0].legend(loc="upper left", fontsize=7)
    fig.suptitle(f"{scene.name}: snapshots ({STYLE[a.simulator]['label']} and dashed MuJoCo)")
    return save(fig, path)


def step_residuals(scene: Scene, residuals: dict, path: Path) -> str | None:
    """Each integrator's one-step residual against time, per component in its unit, with its
    round-off bound (dotted) and a cross at each step over it. residuals: integrator ->
    StepTrace (compare/checks/step_check.py: the worst step of each run of steps, so a step over
    its bound always shows, at a cost that does not grow with the run)."""
    shown = {name: r for name, r in residuals.items() if r is not None and len(r.steps)}
    if not shown:
        return None
    fig, axes = frame("residuals")
    for ax, component in zip(axes, RESIDUAL_PANELS):
        k = COMPONENTS.index(component)
        bounds = np.concatenate([tr.bound[:, k] for tr in shown.values()])
        positive = bounds[bounds > 0.0]
        foot = FOOT * positive.min() if positive.size else 1e-20   # where a residual of exactly 0 is drawn
        for name, trace in shown.items():
            colour = INTEGRATOR_COLOURS.get(name, "tab:gray")
            t, r, b = scene.dt * trace.steps[:, k], trace.residual[:, k], trace.bound[:, k]
            ax.plot(t, np.maximum(r, foot), color=colour, lw=1, label=name)
            ax.plot(t, np.maximum(b, foot), color=colour, ls=":", lw=1)
            over = r > b
            if over.any():
                ax.plot(t[over], r[over], "x", color="tab:red", ms=4)
    fig.suptitle(f"{scene.name}: each step against the independent step (dotted: its round-off; x: over it)")
    axes[0].legend(loc="best", fontsize=7)
    return save(fig, path)
