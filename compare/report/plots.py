"""The figures of a scenario's page: each a PNG with labelled axes, units, a legend and a title."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.ticker import FuncFormatter, LogLocator, MaxNLocator, NullLocator  # noqa: E402

from custom_sim import Scene, Trajectory  # noqa: E402

from .drawing import outlines  # noqa: E402

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


# Fixed margins (fractions of the figure) that hold the axis labels and titles of these
# figures: matplotlib's tight_layout measured every tick label and took a third of a report.
MARGINS = dict(left=0.14, right=0.97, bottom=0.1, top=0.92, hspace=0.3, wspace=0.25)
# Titles at a fixed height above their axes: placed automatically, each title measures the
# bounding box of every tick label of its axes first, which was 40 % of drawing a figure.
HARNESS_RC = {"axes.titley": 1.0}


def draw_all(figures: dict, warnings: list) -> dict:
    """Each figure drawn under matplotlib's defaults plus HARNESS_RC (whatever a user's module
    set: text.usetex, a style); one that fails is left out, with a warning: a plot never costs
    a verdict. figures: name -> function drawing it (returns the file name or None)."""
    import warnings as python_warnings

    drawn = {}
    for name, draw in figures.items():
        try:
            with python_warnings.catch_warnings(), matplotlib.rc_context():
                python_warnings.simplefilter("ignore")
                matplotlib.rcdefaults()
                matplotlib.rcParams.update(HARNESS_RC)
                drawn[name] = draw()
        except Exception as exc:  # noqa: BLE001 - a figure is not a verdict
            plt.close("all")
            text = str(exc).strip().splitlines()
            warnings.append(f"the {name} figure could not be drawn ({type(exc).__name__}: "
                            f"{text[0] if text else ''}); the checks are unaffected")
            drawn[name] = None
    return drawn


def _power_of_ten(value: float, _position) -> str:
    """A log axis's tick label as plain text, 1e-12: the default typesets each one as TeX."""
    return f"1e{round(np.log10(value)):d}" if value > 0 else ""


def _save(fig, path: Path) -> str:
    fig.subplots_adjust(**MARGINS)
    for ax in fig.axes:
        if ax.get_yscale() == "log":
            # a decade per major tick, unlabelled ticks between them: a log axis over 15
            # decades otherwise builds some hundred tick objects that are never drawn
            ax.yaxis.set_major_locator(LogLocator(numticks=8))
            ax.yaxis.set_minor_locator(NullLocator())
            ax.yaxis.set_major_formatter(FuncFormatter(_power_of_ten))
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path.name


def states(scene: Scene, shown: tuple[Trajectory, ...], path: Path, reference=None) -> str:
    """x, y, theta against time; reference: the converged reference's states (steps + 1, 6)."""
    fig, axes = plt.subplots(3, 1, figsize=(8, 7), sharex=True)
    for j, (ax, name, unit) in enumerate(zip(axes, ("x", "y", "theta"), ("m", "m", "rad"))):
        for tr in shown:
            y = getattr(tr, name)
            k = _envelope(y)
            ax.plot(tr.t[k], y[k], **STYLE[tr.simulator])
        if reference is not None:
            k = _envelope(reference[:, j])
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
        k = _envelope(tr.y)
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
    position, angle = np.maximum(diffs["position"], 1e-12), np.maximum(diffs["angle"], 1e-12)
    k = _envelope(position)
    ax1.semilogy(t[k], position[k], color="tab:red", label="|p_MuJoCo - p_tested|")
    ax1.set_ylabel("position difference (m)")
    ax1.legend(loc="best")
    ax1.grid(alpha=0.3, which="both")
    k = _envelope(angle)
    ax2.semilogy(t[k], angle[k], color="tab:purple", label="|theta_MuJoCo - theta_tested|")
    ax2.set_ylabel("angle difference (rad)")
    ax2.set_xlabel("time (s)")
    ax2.legend(loc="best")
    ax2.grid(alpha=0.3, which="both")
    ax1.set_title(f"{scene.name}: difference to MuJoCo's own contact (penalty mapping)")
    return _save(fig, path)


def energy(scene: Scene, balances: dict, path: Path) -> str:
    """The work-energy balance (compare/energy) of each run: E and E + W above (E + W stays at
    E(0) for the exact motion), the residual R = E - E(0) + W below (the numerics' energy)."""
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    for name, b in balances.items():
        style = dict(_style_of(name), label=name if name in ("custom_sim", "reference") else _style_of(name)["label"])
        kept = E_PLUS_W_STYLE if name != "reference" else {}
        k = _envelope(b.E)
        top.plot(b.t[k], b.E[k], **style)
        if name != "reference":
            k = _envelope(b.E + b.dissipated)
            top.plot(b.t[k], (b.E + b.dissipated)[k], **{**style, **kept, "label": f"{style['label']}: E + W"})
        k = _envelope(b.R)
        bottom.plot(b.t[k], b.R[k], **style)
    top.set_ylabel("energy (J)")
    top.set_title(f"{scene.name}: E = kinetic + m g y + sum k d^2 / 2, and E + W (W: the work dissipated)")
    top.legend(loc="best", fontsize=8)
    bottom.set_ylabel("R = E - E(0) + W (J)")
    bottom.set_xlabel("time (s)")
    bottom.axhline(0.0, color="0.6", lw=0.8)
    for ax in (top, bottom):
        ax.grid(alpha=0.3)
    return _save(fig, path)


def _style_of(name: str) -> dict:
    """A run's line style by the simulator's name (the simulator under test otherwise)."""
    return STYLE.get({"custom_sim": "custom"}.get(name, name), STYLE["user"])


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
        ax.xaxis.set_major_locator(MaxNLocator(3))
    axes[0].set_ylabel("y (m)")
    for tr in (a, b):
        axes[0].plot([], [], **STYLE[tr.simulator])
    axes[0].legend(loc="upper left", fontsize=7)
    fig.suptitle(f"{scene.name}: snapshots ({STYLE[a.simulator]['label']} and dashed MuJoCo)")
    return _save(fig, path)


def step_residuals(scene: Scene, residuals: dict, checks: list, path: Path) -> str | None:
    """Each integrator's one-step residual against time, with its round-off bound.
    residuals: integrator -> per-step position residual (m), shape (steps,); checks: CheckRows."""
    shown = {name: r for name, r in residuals.items() if r is not None and len(r)}
    if not shown:
        return None
    bounds = {c.integrator: c.tolerance_position for c in checks if c.name == "step"}
    fig, ax = plt.subplots(figsize=(8, 4))
    for name, r in shown.items():
        r = np.maximum(np.asarray(r, dtype=float), 1e-20)
        t = scene.dt * np.arange(1, len(r) + 1)
        k = _envelope(r)
        colour = INTEGRATOR_COLOURS.get(name, "tab:gray")
        ax.semilogy(t[k], r[k], color=colour, lw=1, label=name)
        if bounds.get(name):
            ax.axhline(bounds[name], color=colour, ls=":", lw=1)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("one-step position residual (m)")
    ax.set_title(f"{scene.name}: each step against the independent step (dotted: round-off bound)")
    ax.legend(loc="best", fontsize=8)
    ax.grid(alpha=0.3, which="both")
    return _save(fig, path)
