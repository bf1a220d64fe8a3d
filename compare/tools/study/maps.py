"""Heatmaps of a study: one panel per integrator (of custom_sim, then of yours with --sim) over
the first two varied fields, the theory's stability limit (custom_sim.stability.stable_step)
drawn over each.

Axes: with dt among the varied fields, dt is the vertical axis and the limit is the curve
h_max(x) = stable_step(scene at x) computed on a fine sample of x (every sample a scene built
through the loader). Without dt, the limit is the contour dt / stable_step = 1 over the grid.
One varied field gives a strip per integrator. More than two: one row of panels per
combination of the others (at most MAX_ROWS).
"""
from __future__ import annotations

import itertools
import math

import numpy as np

MAX_ROWS = 6
THEORY_SAMPLES = 80
STATUS_COLORS = {"ok": "#4a9e5c", "unstable": "#d0453c", "failed": "#9a9a9a", "skipped": "#d9d9d9"}


def _in_panel(row, panel: tuple[str, str]) -> bool:
    """Whether a row belongs to the panel (simulator, integrator)."""
    return (row.get("simulator") or "custom_sim", row["integrator"]) == panel


def panel_title(panel: tuple[str, str]) -> str:
    simulator, integrator = panel
    name = integrator.replace("_", " ")
    return name if simulator == "custom_sim" else f"yours: {name}"


def _is_log(values) -> bool:
    """A log axis for positive values spanning a decade or more."""
    v = np.asarray(values, dtype=float)
    return v.size >= 2 and bool(np.all(v > 0)) and v.max() / v.min() >= 10


def _edges(values, log: bool) -> np.ndarray:
    """Cell edges around sorted numeric values (midpoints, in log where log)."""
    v = np.asarray(values, dtype=float)
    if v.size == 1:
        return np.array([v[0] / 1.5, v[0] * 1.5]) if log else np.array([v[0] - 0.5, v[0] + 0.5])
    t = np.log(v) if log else v
    mid = (t[1:] + t[:-1]) / 2
    e = np.concatenate([[t[0] - (mid[0] - t[0])], mid, [t[-1] + (t[-1] - mid[-1])]])
    return np.exp(e) if log else e


class Axis:
    """A varied field on a plot axis: numeric (maybe log) or categorical (index positions)."""

    def __init__(self, vary):
        self.vary = vary
        self.numeric = vary.numeric
        self.values = sorted(vary.values) if self.numeric else list(vary.values)
        self.log = self.numeric and _is_log(self.values)
        self.edges = _edges(self.values, self.log) if self.numeric else np.arange(len(self.values) + 1) - 0.5

    def position(self, value) -> float:
        return float(value) if self.numeric else float(self.values.index(value))

    def index(self, value) -> int:
        return self.values.index(value)

    def apply(self, set_lim, set_scale, set_ticks) -> None:
        set_lim(self.edges[0], self.edges[-1])
        if self.log:
            set_scale("log")
        if not self.numeric:
            set_ticks(range(len(self.values)), [str(v) for v in self.values])


def layout(study):
    """(x axis, y axis or None, extra varies, their combinations)."""
    varies = list(study.varies)
    names = [v.name for v in varies]
    if "dt" in names and len(varies) > 1:
        y = varies.pop(names.index("dt"))
        x = varies.pop(0)
    else:
        x = varies.pop(0)
        y = varies.pop(0) if varies else None
    combos = list(itertools.product(*(v.values for v in varies)))[:MAX_ROWS] if varies else [()]
    return Axis(x), (Axis(y) if y else None), varies, combos


def _grid(study, xa, ya, extra, combo, panel, value_of):
    """(ny, nx) array of value_of(row) (NaN where absent) for one panel (simulator, integrator)."""
    names = study.names
    grid = np.full((len(ya.values) if ya else 1, len(xa.values)), np.nan)
    for row in study.rows:
        if not _in_panel(row, panel):
            continue
        vals = dict(zip(names, row["values"]))
        if any(vals[v.name] != c for v, c in zip(extra, combo)):
            continue
        j = xa.index(vals[xa.vary.name])
        i = ya.index(vals[ya.vary.name]) if ya else 0
        grid[i, j] = value_of(row)
    return grid


def _theory(study, ax, xa, ya, extra, combo, panel, grid_rows):
    """Draw the theory's stability limit on one panel; returns whether anything was drawn."""
    from custom_sim import INTEGRATORS, stable_step

    names = study.names
    integrator = panel[1]
    if integrator not in INTEGRATORS:   # yours, an integrator the harness does not know: no theory
        return False
    if ya is not None and ya.vary.name == "dt" and xa.numeric:
        lo, hi = xa.values[0], xa.values[-1]
        xs = np.geomspace(lo, hi, THEORY_SAMPLES) if xa.log else np.linspace(lo, hi, THEORY_SAMPLES)
        hs = []
        for x in xs:
            values = {xa.vary.name: float(x), "dt": ya.values[0], **{v.name: c for v, c in zip(extra, combo)}}
            scene = study.source.varied(study.varies, tuple(values[n] for n in names))
            hs.append(stable_step(scene, integrator))
        hs = np.array(hs, dtype=float)
        hs[hs <= 0.0] = np.nan   # a bare sign law: no stable step, nothing to draw on a log axis
        if not np.any(np.isfinite(hs)):
            return False
        ax.plot(xs, hs, color="black", linewidth=1.6, label="theory: stable_step")
        return True
    if ya is None and xa.vary.name == "dt":
        h = [r["stable_step_theory"] for r in grid_rows if r["stable_step_theory"]]
        if not h:
            return False
        ax.axvline(h[0], color="black", linewidth=1.6, label="theory: stable_step")
        return True
    # the contour dt / stable_step = 1 over the grid
    ratio = _grid(study, xa, ya, extra, combo, panel,
                  lambda r: (r["_dt"] / r["stable_step_theory"]) if r["stable_step_theory"] else 0.0)
    if not np.any(ratio > 0) or ratio.shape[0] < 2 or ratio.shape[1] < 2:
        return False
    xc = [xa.position(v) for v in xa.values]
    yc = [ya.position(v) for v in ya.values]
    with np.errstate(divide="ignore"):
        ax.contour(xc, yc, np.log(np.where(ratio > 0, ratio, 1e-300)), levels=[0.0], colors="black",
                   linewidths=1.6)
    return True


METRICS = {
    "stability": ("stable (green), unstable (red), failed (grey), skipped (light grey)", None),
    "error": ("max position error against the reference (m); x: unstable run", "position_error_max"),
    "twin": ("max position difference to the MuJoCo twin (m); x: unstable run", "twin_position_error_max"),
    "cost": ("wall time of the run (s); x: unstable run", "wall_time"),
}


def plot(study, metric: str, path) -> None:
    """One PNG: panels per integrator (columns) and per combination of the other fields (rows)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import BoundaryNorm, ListedColormap, LogNorm

    title, column = METRICS[metric]
    xa, ya, extra, combos = layout(study)
    for row in study.rows:
        row["_dt"] = dict(zip(study.names, row["values"])).get("dt", study.source.scene.dt)
    panels = study.panels
    ncol, nrow = len(panels), len(combos)
    fig, axes = plt.subplots(nrow, ncol, figsize=(max(7.0, 3.6 * ncol + 1.2), (3.0 if ya else 1.6) * nrow + 1.0),
                             squeeze=False, sharex=True, sharey=True)
    codes = {"ok": 0, "unstable": 1, "failed": 2, "skipped": 3}
    if column is None:
        cmap = ListedColormap([STATUS_COLORS[s] for s in codes])
        norm = BoundaryNorm([-0.5, 0.5, 1.5, 2.5, 3.5], 4)
        value_of = lambda r: codes[r["status"]]  # noqa: E731
    else:
        finite = [r[column] for r in study.rows if r.get(column) is not None and r[column] > 0]
        lo, hi = (min(finite), max(finite)) if finite else (1e-9, 1.0)
        cmap = plt.get_cmap("viridis").with_extremes(bad="#e6e6e6")
        norm = LogNorm(lo, max(hi, lo * 10))
        value_of = lambda r: r[column] if r.get(column) is not None and r[column] > 0 else np.nan  # noqa: E731
    mesh = None
    for i, combo in enumerate(combos):
        for j, integ in enumerate(panels):
            ax = axes[i, j]
            grid = _grid(study, xa, ya, extra, combo, integ, value_of)
            yedges = ya.edges if ya else np.array([0.0, 1.0])
            xe = xa.edges if xa.numeric else np.arange(len(xa.values) + 1) - 0.5
            mesh = ax.pcolormesh(xe, yedges, np.ma.masked_invalid(grid), cmap=cmap, norm=norm, shading="flat")
            if column is not None:   # the value of an unstable run is shown, crossed out
                bad = _grid(study, xa, ya, extra, combo, integ, lambda r: float(r["status"] != "ok"))
                yi, xi = np.nonzero(bad == 1.0)
                if yi.size:
                    ax.scatter([xa.position(xa.values[k]) for k in xi],
                               [ya.position(ya.values[k]) for k in yi] if ya else [0.5] * yi.size,
                               marker="x", s=18, color="#d0453c", linewidths=1.0,
                               label="unstable (or failed)")
            rows = [r for r in study.rows if _in_panel(r, integ)]
            drawn = _theory(study, ax, xa, ya, extra, combo, integ, rows)
            xa.apply(ax.set_xlim, ax.set_xscale, ax.set_xticks)
            if ya:
                ya.apply(ax.set_ylim, ax.set_yscale, ax.set_yticks)
            else:
                ax.set_yticks([])
            head = panel_title(integ)
            if extra:
                head += "\n" + ", ".join(f"{v.name}={c:g}" if isinstance(c, float) else f"{v.name}={c}"
                                         for v, c in zip(extra, combo))
            if not drawn:
                head += "\n(theory: no limit)"
            ax.set_title(head, fontsize=9)
            if i == nrow - 1:
                ax.set_xlabel(xa.vary.name)
            if j == 0 and ya:
                ax.set_ylabel(ya.vary.name + (" (s)" if ya.vary.name == "dt" else ""))
    handles = [h for h in axes[0, 0].get_legend_handles_labels()[0]]
    if handles:
        axes[0, 0].legend(fontsize=7, loc="lower left")
    fig.suptitle(f"{study.source.scene.name}: {title}", fontsize=10)
    fig.tight_layout(rect=(0, 0, 0.88 if column else 1.0, 0.95))
    if column and mesh is not None:
        cax = fig.add_axes([0.895, 0.12, 0.015, 0.75])
        fig.colorbar(mesh, cax=cax)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    for row in study.rows:
        row.pop("_dt", None)


def measured_limits(study) -> list[dict]:
    """With dt varied: per integrator and value of the other fields, the largest dt whose run
    and every smaller dt's run were stable, beside the theory's limit there."""
    names = study.names
    if "dt" not in names:
        return []
    others = [n for n in names if n != "dt"]
    table: dict = {}
    for row in study.rows:
        vals = dict(zip(names, row["values"]))
        key = ((row.get("simulator") or "custom_sim", row["integrator"]), tuple(vals[n] for n in others))
        table.setdefault(key, []).append((vals["dt"], row["status"], row["stable_step_theory"]))
    out = []
    for (integ, combo), entries in table.items():
        entries.sort()
        largest = None
        for dt, status, _ in entries:
            if status != "ok":
                break
            largest = dt
        theory = entries[0][2]
        first_bad = next((dt for dt, s, _ in entries if s == "unstable"), None)
        out.append({"integrator": integ[1], "simulator": integ[0], "values": dict(zip(others, combo)),
                    "stable_up_to": largest,
                    "first_unstable": first_bad, "theory": theory,
                    "ratio": (largest / theory) if (largest and theory) else math.nan})
    order = {panel: i for i, panel in enumerate(study.panels)}
    out.sort(key=lambda lim: (order[(lim["simulator"], lim["integrator"])], tuple(lim["values"].values())))
    return out
