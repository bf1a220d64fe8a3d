"""<scene>_workprecision.png: max COM error (m) against the CPU time (s) of the run, against
MuJoCo's own converged solution and against our reference, and |R(end)| (J) against dt (s); with
--sim the user's code beside them (dotted, triangles).
"""
from __future__ import annotations

import math
from pathlib import Path

from ..accuracy.workprecision import TARGET_ERROR
from .residual import residual_order, roundoff_floor
from .wording import LABELS, SIMULATOR

# each simulator's curves: ours solid with circles, MuJoCo dashed with squares, the user's dotted with triangles
STYLE = {"custom": {"marker": "o", "linestyle": "-"}, "mujoco": {"marker": "s", "linestyle": "--"},
         "yours": {"marker": "^", "linestyle": ":", "linewidth": 2.0}}

COLORS = {"explicit_euler": "tab:red", "semi_implicit_euler": "tab:blue", "implicit_euler": "tab:green",
          "rk4": "tab:purple", "Euler": "tab:cyan", "RK4": "tab:pink", "implicit": "tab:olive",
          "implicitfast": "tab:brown"}


def residual_panel(ax, sweep) -> None:
    """|R(end)| against dt for each integrator: the energy its numerics made or lost."""
    for sim, integ in dict.fromkeys((r.simulator, r.integrator) for r in sweep.runs):
        pts = [(r.dt, abs(r.residual_end)) for r in sweep.of(sim, integ)
               if r.stable and math.isfinite(r.residual_end) and r.residual_end != 0.0]
        if pts:
            xs, ys = zip(*pts)
            label = f"{SIMULATOR[sim]}: {LABELS.get(integ, integ)} " \
                    f"(order {residual_order(sweep.of(sim, integ), roundoff_floor(sweep)):.2f})"
            ax.plot(xs, ys, color=COLORS.get(integ), markersize=4, label=label, **STYLE[sim])
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("step dt (s)")
    ax.set_ylabel("|R(end)| = |E(end) - E(0) + W| (J)")
    ax.set_title("energy the numerics made or lost (work-energy balance)", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="lower right")


def plot_scene(sweep, path: Path) -> None:
    """The scene's three panels, written as a PNG to path."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(19, 5.2))
    first = fig.add_subplot(1, 3, 1)
    axes = [first, fig.add_subplot(1, 3, 2, sharey=first)]
    residual_panel(fig.add_subplot(1, 3, 3), sweep)
    panels = (("numerical error: ours vs reference, MuJoCo vs its own converged solution", True),
              ("against our reference (MuJoCo: numerical error + model difference)", False))
    integrators = []
    for r in sweep.runs:
        if (r.simulator, r.integrator) not in integrators:
            integrators.append((r.simulator, r.integrator))
    for ax, (title, own) in zip(axes, panels):
        for sim, integ in integrators:
            runs = [r for r in sweep.of(sim, integ) if r.stable]
            err = [r.error_max_self if (own and sim == "mujoco") else r.error_max for r in runs]
            pts = [(r.cpu_time, e, r.dt) for r, e in zip(runs, err) if math.isfinite(e) and e > 0]
            if not pts:
                continue
            xs, ys, dts = zip(*pts)
            style = dict(color=COLORS.get(integ), markersize=4, **STYLE[sim])
            label = f"{SIMULATOR[sim]}: {LABELS.get(integ, integ) if sim != 'mujoco' else integ}"
            ax.plot(xs, ys, label=label, **style)
            for x, y, dt in ((xs[0], ys[0], dts[0]), (xs[-1], ys[-1], dts[-1])):
                ax.annotate(f"{dt:.0e}", (x, y), fontsize=6, xytext=(2, 2), textcoords="offset points",
                            color=COLORS.get(integ))
        ax.axhline(TARGET_ERROR, color="grey", linewidth=0.8, linestyle=":")
        ax.text(0.99, TARGET_ERROR, "1 mm", va="bottom", ha="right", fontsize=8, color="grey",
                transform=ax.get_yaxis_transform())
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("time of the run (s): CPU time of the stepping, min of repeats")
        ax.set_title(title, fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("max COM position error over the run (m)")
    axes[0].legend(fontsize=7, loc="lower left")
    ref = sweep.reference
    fig.suptitle(f"{sweep.scene.name}: work-precision ({sweep.scene.duration:g} s simulated; labels: step size in s; "
                 f"reference converged to {ref['change_at_tighter_tolerance']:.1e} m)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
