"""Work-precision sweep: error against cost of every integrator in both simulators, stability limits.

For each SCENE (default: every built-in): a reference solution (adaptive DOP853 with contact
switches as events), our four integrators and MuJoCo's four over ladders of step sizes (max
and RMS position error against the reference, wall time as the minimum of repeats, force
evaluations), MuJoCo's own converged solution, and the largest stable step of every
integrator by bisection beside the linear theory. Writes DIR/sweep/index.md (the answer to
"what is the cheapest way to reach 1 mm here?", the stability table, a section per scene),
DIR/sweep/<scene>_workprecision.png, DIR/sweep/results.json and DIR/sweep/cheapest.md (the
README's table of the cheapest way to 1 mm, with the machine it was measured on); reference solutions are
cached (--cache). Uses every core: a local Dask cluster with the study extra, else a process
pool; --scheduler needs Dask (pip install -e '.[study]'). Exit status: 0 done, 2 bad input.
"""
from __future__ import annotations

import math
import os
import sys
import time
from pathlib import Path


from scene_types.integrators import ORDER

from ..cli import output_folder
from ..report.atomic import finite_json, temporary_folder
from ..scenarios import load_all
from ..table import DASH, markdown, number

COLORS = {"explicit_euler": "tab:red", "semi_implicit_euler": "tab:blue", "implicit_euler": "tab:green",
          "rk4": "tab:purple", "Euler": "tab:cyan", "RK4": "tab:pink", "implicit": "tab:olive",
          "implicitfast": "tab:brown"}
LABELS = {"explicit_euler": "explicit Euler", "semi_implicit_euler": "semi-implicit Euler",
          "implicit_euler": "implicit Euler", "rk4": "RK4"}


def add_arguments(parser) -> None:
    parser.add_argument("scenes", nargs="*", metavar="SCENE",
                        help="built-in name or path to a .toml (default: all built-ins)")
    parser.add_argument("--out", default="reports", metavar="DIR",
                        help="output folder (default: reports/); writes DIR/sweep/")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                        help="worker processes: of the local Dask cluster, or of a process pool "
                             "without Dask (default: every core)")
    parser.add_argument("--scheduler", metavar="ADDRESS", default=None,
                        help="run on this Dask cluster, e.g. tcp://127.0.0.1:8786 (default: a local cluster; "
                             "needs the study extra)")
    parser.add_argument("--no-mujoco", action="store_true", help="our simulator only")
    parser.add_argument("--no-stability", action="store_true", help="skip the stability search")
    parser.add_argument("--cache", default=None, metavar="DIR",
                        help="where reference solutions are kept between runs "
                             "(default: compare-sweep-cache in the system's temporary folder)")
    parser.add_argument("--no-cache", action="store_true", help="recompute the reference solutions")


def main(args) -> int:
    if args.scheduler:   # before any work: the one line that says what to install
        from ..executor import require_dask
        require_dask("sweep --scheduler")
    scenes = load_all(args.scenes)
    out = output_folder(args.out)
    folder = out / "sweep"

    from tqdm import tqdm

    from ..tools.accuracy.workprecision import run_sweep

    start = time.perf_counter()
    jobs = max(1, args.jobs)
    import tempfile

    cache = None if args.no_cache else Path(args.cache or Path(tempfile.gettempdir()) / "compare-sweep-cache")
    results = run_sweep(
        scenes, cache_dir=cache, jobs=jobs, scheduler=args.scheduler,
        mujoco=not args.no_mujoco, stability=not args.no_stability,
        progress=lambda total: tqdm(total=total, desc="sweep", unit="task", delay=2, file=sys.stderr))
    runtime = time.perf_counter() - start
    # written beside its place and renamed into it when complete: a reader never sees half a
    # report, and a failure leaves the previous one
    import shutil

    out.mkdir(parents=True, exist_ok=True)
    tmp = temporary_folder(out, ".sweep.")
    try:
        for sweep in results:
            plot_scene(sweep, tmp / f"{sweep.scene.name}_workprecision.png")
        write_json(results, tmp / "results.json", runtime, jobs)
        write_index(results, tmp / "index.md", runtime, jobs)
        (tmp / "cheapest.md").write_text(cheapest_table(results, " ".join(["python -m compare sweep", *args.scenes]))
                                         + "\n")
        if folder.exists():
            shutil.rmtree(folder)
        os.replace(tmp, folder)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    index = folder / "index.md"
    for sweep in results:
        print(f"{sweep.scene.name}: {answer(sweep)}")
    print(f"sweep took {runtime:.0f} s on {jobs} worker(s); report: {index}; "
          f"the cheapest-way table: {folder / 'cheapest.md'}")
    return 0


# ---------------------------------------------------------------------------------------
# The plain answer


def _ms(seconds: float) -> str:
    return f"{seconds:.3g} s" if seconds >= 1.0 else f"{seconds * 1e3:.3g} ms"


def _mm(metres: float) -> str:
    if metres < 1e-4:
        return f"{metres * 1e6:.2g} um"
    return f"{metres * 1e3:.3g} mm"


def _name(run) -> str:
    return LABELS.get(run.integrator, run.integrator) if run.simulator == "custom" else f"MuJoCo {run.integrator}"


def _timing(run) -> str:
    """CPU time with its measured spread: '0.11 ms (+- 0.01 ms)'."""
    spread = run.cpu_time_spread
    return _ms(run.cpu_time) + (f" (+- {_ms(spread)})" if math.isfinite(spread) else "")


def _cost(run) -> str:
    return f"{run.force_evals} force evaluations ({run.steps} steps)"


def _time_verdict(win, others) -> str:
    """What the CPU times say about win against others, only as far as their spread allows."""
    from ..tools.accuracy.workprecision import fastest

    if not others:
        return ""
    quickest, ties = fastest([win, *others])
    if quickest is win:
        return "; also the fastest in CPU time" + (
            f" (within the timing spread of {', '.join(_name(r) for r in ties)})" if ties else ", beyond the timing spread")
    if win in ties:
        return f"; by CPU time {_name(quickest)} ({_timing(quickest)}) cannot be told from it"
    return f"; by CPU time {_name(quickest)} at dt = {quickest.dt:g} s is faster beyond the spread ({_timing(quickest)})"


def answer(sweep) -> str:
    """'What is the cheapest way to reach 1 mm here?' in a few plain sentences: the run with the
    fewest force evaluations (counted, so the same on every rerun), its time beside it, and what
    the times say only where they differ by more than their measured spread."""
    from ..tools.accuracy.workprecision import TARGET_ERROR, best_error, clearly_faster, ranking

    ours = [r for r in sweep.runs if r.simulator == "custom"]
    theirs = [r for r in sweep.runs if r.simulator == "mujoco"]
    parts = []
    ranked = ranking(ours)
    win = ranked[0] if ranked else None
    if win:
        text = (f"ours: {_name(win)} at dt = {win.dt:g} s, {_cost(win)}, {_timing(win)} for the "
                f"{sweep.scene.duration:g} s run, max error {_mm(win.error_max)}")
        if len(ranked) > 1:
            nxt = ranked[1]
            text += f"; next {_name(nxt)} at dt = {nxt.dt:g} s, {nxt.force_evals} force evaluations, {_timing(nxt)}"
        parts.append(text + _time_verdict(win, ranked[1:]) + ".")
    else:
        best = best_error(ours)
        why = ""
        amp = sweep.reference.get("amplification", 1.0)
        if amp > 100:
            why = (f" The motion amplifies a small error about {amp:.0f}-fold (a tumbling landing), "
                   f"so 1 mm at the end needs about {_mm(TARGET_ERROR / amp)} before it.")
        parts.append(f"ours: no step on the ladder reaches 1 mm; the best is {_name(best)} at "
                     f"dt = {best.dt:g} s ({_mm(best.error_max)}, {_timing(best)}).{why}"
                     if best else "ours: no stable run.")
    if theirs:
        own_ranked = ranking(theirs, self_error=True)
        own = own_ranked[0] if own_ranked else None
        if own:
            if win and clearly_faster(win, own):
                versus = f", {own.cpu_time / win.cpu_time:.0f}x the time of our cheapest"
            elif win:
                versus = ", not distinguishable in time from our cheapest"
            else:
                versus = ""
            parts.append(f"MuJoCo: {own.integrator} at dt = {own.dt:g} s, {_cost(own)}, {_timing(own)}, stays "
                         f"within 1 mm of its own converged solution ({_mm(own.error_max_self)}){versus}.")
        else:
            best = best_error(theirs, self_error=True)
            if best:
                parts.append(f"MuJoCo: no step on its ladder reaches 1 mm of its own converged solution "
                             f"(best {best.integrator} at dt = {best.dt:g} s: {_mm(best.error_max_self)}).")
        floor = sweep.mujoco_converged.get("change_at_double_step", 0.0)
        if floor > 0.1 * TARGET_ERROR:
            parts.append(f"(MuJoCo's converged solution itself moves {_mm(floor)} when its step doubles, so "
                         f"its own error is known only to about that.)")
        model = sweep.mujoco_converged.get("error_max", math.nan)
        vs_ref = ranking(theirs)
        if vs_ref:
            parts.append(f"Against our reference MuJoCo reaches 1 mm with {vs_ref[0].integrator} at "
                         f"dt = {vs_ref[0].dt:g} s: {_cost(vs_ref[0])}, {_timing(vs_ref[0])}.")
        elif math.isfinite(model):
            parts.append(f"Against our reference it cannot: its converged solution itself is {_mm(model)} "
                         f"from ours (model difference, not step size).")
    return " ".join(parts)


def machine() -> str:
    """The machine a table was measured on: CPU model, cores, load, versions, date (UTC)."""
    import datetime
    import platform

    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        load = "load average " + " ".join(f"{x:.1f}" for x in os.getloadavg()) + " (1, 5, 15 min)"
    except OSError:
        load = "load unknown"
    versions = []
    for name in ("numba", "mujoco"):
        try:
            versions.append(f"{name} {__import__(name).__version__}")
        except ImportError:
            pass
    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    return (f"{cpu}, {os.cpu_count()} cores, {load}; {platform.system()} {platform.release()}, "
            f"Python {platform.python_version()}, {', '.join(versions)}; {when}")


def cheapest_table(results, command: str = "python -m compare sweep") -> str:
    """The README's table: for each scene, the fewest force evaluations that reach 1 mm in each
    simulator, with the CPU time and its spread beside them, and the machine it was measured on."""
    from ..tools.accuracy.workprecision import ranking

    def cell(run, self_error=False):
        if run is None:
            return "not within 1 mm on the ladder", DASH
        return (f"{_name(run)}, dt {run.dt:g} s: {run.force_evals} force evaluations",
                _timing(run))

    rows = []
    for sweep in results:
        ours = ranking([r for r in sweep.runs if r.simulator == "custom"])
        theirs = ranking([r for r in sweep.runs if r.simulator == "mujoco"], self_error=True)
        a, at = cell(ours[0] if ours else None)
        b, bt = cell(theirs[0] if theirs else None) if any(r.simulator == "mujoco" for r in sweep.runs) else ("not run", DASH)
        rows.append([sweep.scene.name, a, at, b, bt])
    lines = [f"Measured by `{command}` on {machine()}.", "",
             *markdown(["scene", "custom_sim: fewest force evaluations to 1 mm", "CPU time (spread)",
                        "MuJoCo: fewest to 1 mm of its own converged solution", "CPU time (spread)"], rows).splitlines(),
             "", "Ranked by force evaluations (counted, so a rerun gives the same answer), then steps; "
              "the CPU time is the minimum over repeats, and the spread how far the repeats differed. "
              "Force evaluations compare runs of one simulator; between the two, only the times do, and "
              "only where they differ by more than their spread."]
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------
# Plot


# The energy residual R(end) shrinks with dt at the integrator's order (ORDER), away from contact
# events (docs/energy-balance.md)
ORDER_SLACK = 0.3   # a fitted slope this far below the order means something lowers it
ORDER_POINTS = 3    # the finest steps: the asymptotic regime, where the order shows
ROUNDOFF_ULPS = 10  # each step's energy sum rounds by a few eps of the energy: below 10 eps a step, R is round-off
EPS = 2.220446049250313e-16   # numpy.finfo(float).eps, written out: this module imports numpy lazily


def residual_order(runs, floor: float = 0.0) -> float:
    """The slope of log |R(end)| against log dt over the ORDER_POINTS finest stable runs whose
    |R(end)| stands above `floor` (J, the round-off of summing the energy over the run's
    steps); nan with fewer than two."""
    pts = [(r.dt, abs(r.residual_end)) for r in runs
           if r.stable and math.isfinite(r.residual_end) and abs(r.residual_end) > floor * r.steps]
    pts = sorted(pts)[:ORDER_POINTS]
    if len(pts) < 2:
        return math.nan
    import numpy as np
    dts, rs = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    return float(np.polyfit(dts, rs, 1)[0])


def _floor(sweep) -> float:
    """J per step: the round-off of the energy sums, ROUNDOFF_ULPS eps of the run's energy scale."""
    return ROUNDOFF_ULPS * EPS * float(sweep.reference.get("energy_scale", 1.0))


def residual_panel(ax, sweep) -> None:
    """|R(end)| against dt for each integrator: the energy its numerics made or lost."""
    for sim, integ in dict.fromkeys((r.simulator, r.integrator) for r in sweep.runs):
        pts = [(r.dt, abs(r.residual_end)) for r in sweep.of(sim, integ)
               if r.stable and math.isfinite(r.residual_end) and r.residual_end != 0.0]
        if pts:
            xs, ys = zip(*pts)
            label = f"{'ours' if sim == 'custom' else 'MuJoCo'}: {LABELS.get(integ, integ)} " \
                    f"(order {residual_order(sweep.of(sim, integ), _floor(sweep)):.2f})"
            ax.plot(xs, ys, marker="o" if sim == "custom" else "s", linestyle="-" if sim == "custom" else "--",
                    color=COLORS.get(integ), markersize=4, label=label)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("step dt (s)")
    ax.set_ylabel("|R(end)| = |E(end) - E(0) + W| (J)")
    ax.set_title("energy the numerics made or lost (work-energy balance)", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="lower right")


def residual_rows(sweep) -> list[str]:
    """Per integrator: R(end) at each dt, its measured order against the expected one, and
    the contact events when they lower it."""
    switches = ", ".join(f"{v} {k}" for k, v in sweep.reference["switches"].items() if v)
    rows = []
    for sim, integ in dict.fromkeys((r.simulator, r.integrator) for r in sweep.runs):
        runs = sweep.of(sim, integ)
        order, expected = residual_order(runs, _floor(sweep)), ORDER.get(integ)
        values = ", ".join(f"{r.residual_end:.2g} ({r.dt:g} s)" for r in runs
                           if r.stable and math.isfinite(r.residual_end))
        note = ""
        if sim == "mujoco" and integ == "RK4":
            note = ("not measured: the work of MuJoCo's RK4 needs its four stages' constraint forces, which its states "
                    "do not carry (compare.energy.mujoco_side.native_balance steps it row by row)")
        elif math.isfinite(order) and expected and order < expected - ORDER_SLACK:
            note = (f"lowered by the contact events ({switches} switches of the reference): a step across a switch "
                    "integrates the force's jump or kink at first or second order" if switches else
                    "lower than expected without a contact event")
        rows.append(["ours" if sim == "custom" else "MuJoCo", integ, values or DASH, _num(order, decimals=2),
                     expected or DASH, note])
    return markdown(["simulator", "integrator", "R(end) at each dt (J)", "measured order", "expected", "note"],
                    rows).splitlines() + [""]


def plot_scene(sweep, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..tools.accuracy.workprecision import TARGET_ERROR

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
            style = dict(color=COLORS.get(integ), marker="o" if sim == "custom" else "s",
                         linestyle="-" if sim == "custom" else "--", markersize=4)
            label = f"ours: {LABELS.get(integ, integ)}" if sim == "custom" else f"MuJoCo: {integ}"
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


# ---------------------------------------------------------------------------------------
# Markdown and JSON


def _num(x, **options) -> str:
    """The sweep's number: 3 significant digits, "-" for a value that is missing or not finite."""
    return number(x, none="-", nonfinite="-", **options)


def stability_rows(sweep) -> list[list[str]]:
    from ..tools.accuracy.stability_search import theory

    rows = []
    for lim in sweep.stability:
        if lim.simulator == "custom":
            th = theory(sweep.scene, lim.integrator)
        else:  # MuJoCo's Euler is semi-implicit; implicit(fast) integrate contact explicitly too
            th = theory(sweep.scene, "rk4" if lim.integrator == "RK4" else "semi_implicit_euler")
        spring = th["spring"]
        ratio = lim.h_max / spring if math.isfinite(spring) and spring > 0 else math.nan
        name = LABELS.get(lim.integrator, lim.integrator) if lim.simulator == "custom" else f"MuJoCo {lim.integrator}"
        why = lim.reason or ("stable up to the largest step tried" if lim.capped else "")
        rows.append([sweep.scene.name, name, lim.text(), *map(_num, (lim.first_threshold, spring, th["spring_point"],
                                                                    th["friction"], th["combined"])),
                     _num(ratio, decimals=2), why])
    return rows


STABILITY_HEADERS = [
    "scene", "integrator", "measured h_max (s)", "first threshold, before the scans (s)",
    "theory: contact spring, effective mass (s)", "theory: contact spring, point mass (s)",
    "theory: tanh friction (s)", "stable_step (the smaller) (s)", "measured / spring theory",
    "what failed just above h_max",
]


def write_index(results, path: Path, runtime: float, jobs: int) -> Path:
    from ..oracle.reference import REFERENCE_RTOL
    from ..tools.accuracy.stability_search import ENERGY_GROWTH_LIMIT, QUIET_CONTACT_SHARE
    from ..tools.accuracy.workprecision import GRID, LADDER, MUJOCO_CONVERGED_N, MUJOCO_LADDER, RUN_BUDGET

    lines = [
        "# What accuracy costs: work-precision and stability",
        "",
        f"Sweep of {len(results)} scene(s) in {runtime:.0f} s on {jobs} worker process(es) "
        f"(`python -m compare sweep`).",
        "",
        "How it is measured (docs/physics.md, \"Accuracy against cost\"):",
        "",
        f"- **Reference**: the same equations as custom_sim solved by scipy's DOP853 at rtol = atol = "
        f"{REFERENCE_RTOL:g}, each contact switch (a point touching or leaving, the kink of the damping law; "
        f"the sign of omega under a sign(omega) rolling law) located as an event and the integration "
        f"restarted there "
        f"(compare/oracle/reference.py). *Converged* = the change when the tolerance is tightened 100-fold.",
        f"- **Error**: distance between centres of mass, simulator against reference, every {GRID * 1e3:g} ms; "
        f"max and RMS (L2) over the run. MuJoCo's error is given twice: against its own converged solution "
        f"(RK4 at dt = {GRID / MUJOCO_CONVERGED_N:g} s: numerical error only) and against our reference "
        "(numerical error plus model difference).",
        "- **Cost**: time of the stepping alone (ours: one compiled call, MuJoCo: `mj_step` with nstep, "
        "both recording nothing), the minimum over repeats after a warm-up, as the CPU time of the stepping "
        "thread (the wall time on an idle core; on this shared 2-core machine it does not charge a run for "
        "time given to other processes; results.json has the wall times too), and force evaluations.",
        f"- **Ladders**: dt = {GRID:g} s / n, n in {list(LADDER)} for ours and {list(MUJOCO_LADDER)} for MuJoCo; "
        f"a rung predicted to take over {RUN_BUDGET:g} s is skipped; unstable rungs are left out of the diagrams.",
        f"- **Stable** = no divergence (for MuJoCo: no reset on a bad acceleration), for ours no chatter (a contact "
        f"point's slip or normal velocity flipping sign every step, custom_sim/chatter.py; docs/stability.md), "
        f"and the energy, read where "
        f"the contact energy is under {QUIET_CONTACT_SHARE:.0%} of the motion's energy, never more than "
        f"{ENERGY_GROWTH_LIMIT:.0%} of the motion's largest kinetic energy above its start. The exact motion "
        f"only loses energy (damping, friction and rolling resistance all dissipate), so growth is numerical.",
        "",
        "## What is the cheapest way to reach 1 mm here?",
        "",
        "The step size with the fewest force evaluations whose max COM position error over the whole run is "
        "within 1 mm, and stays within it at every finer step on the ladder (a fixed step's error jumps about "
        "as the contact switches fall at different places inside a step; one lucky step size is not an "
        "answer). Force evaluations are counted, so the answer does not move with the machine's load; the "
        "CPU time stands beside them with the spread of its repeats, and a time is called faster only when "
        "it differs by more than that spread.",
        "",
        cheapest_table(results),
        "",
    ]
    for sweep in results:
        lines.append(f"- **{sweep.scene.name}**: {answer(sweep)}")
    lines += ["", "## Stability limits", "",
              "Largest stable step found by bisection (to 1 %) and checked by a scan of 20 steps 2 % apart "
              "below it (stable and unstable steps interleave near the limit when a bouncing body spends only "
              "a few steps in each contact), beside the linear theory of "
              "custom_sim/stability.py split by what sets it: the contact spring-damper with the smallest "
              "effective mass at a contact point (a box corner: 1/m_eff = 1/m + r^2/I), the same with the "
              "whole mass at the point, and the tanh friction's stiff rate; `stable_step` is the smaller. "
              "`>=`: stable up to the largest step tried. MuJoCo rows use the semi-implicit theory (MuJoCo's "
              "Euler is semi-implicit, and all its integrators treat contact forces explicitly) or RK4's.", ""]
    lines += markdown(STABILITY_HEADERS, [row for sweep in results for row in stability_rows(sweep)]).splitlines()
    lines += ["", STABILITY_NOTES, ""]
    for sweep in results:
        lines += scene_section(sweep)
    path.write_text("\n".join(lines) + "\n")
    return path


STABILITY_NOTES = """Reading the table:

- The theory is for a linear oscillator: a resting contact. Most scenes use the compression law,
  which damps only while a point moves into the ground, and explicit Euler's stability rests on
  damping alone; undamped (elastic_bounce) it has no stable step at all, and the figure is the
  step at which a 3 s run has gained 10 % (3 contacts, each multiplying the energy by about
  exp(pi h wn)).
- Where custom_sim's `stable_step` is set by the tanh friction (h lambda_f < 2, lambda_f =
  mu alpha Fn / m_t at the largest load Fn a point carries, an impact's peak), going past it makes
  the slip velocity flip sign every step around zero; tanh saturates, so this chatter stays
  bounded and gains no energy, but custom_sim's run stops on it (SimulationChattered) and the
  search counts it as unstable. docs/stability.md tables theory against measured.
- A bouncing body spends only a few steps in each contact near the limit, and what a bounce
  does to the energy then depends on where the touchdown falls inside a step: stable and
  unstable steps interleave, and the scan below the first threshold can move h_max far down
  (elastic_bounce: a symplectic Euler bounce changes the energy by O(h wn), so at a few ms one
  bounce already gains 10 %; the resting-contact theory does not apply).
- Implicit Euler has no linear limit, but its Newton solve meets the contact switch and the
  max() kink inside a step: at large steps on the tumbling bodies it can fail and diverge.
- MuJoCo's implicit and implicitfast equal its Euler here: they differ only in how joint damping
  and actuators are treated, and these twins have neither."""


def scene_section(sweep) -> list[str]:
    ref = sweep.reference
    s = sweep.scene
    conv = sweep.mujoco_converged
    lines = [f"## {s.name}", "", f"{s.description}", "",
             f"![work-precision diagram of {s.name}]({s.name}_workprecision.png)", "",
             f"- Reference: {ref['method']} at rtol = atol = {ref['rtol']:g}, {ref['segments']} smooth pieces "
             f"({', '.join(f'{v} {k}' for k, v in ref['switches'].items() if v)} switches), "
             f"{ref['nfev']} evaluations, {ref['solve_time']:.2f} s. Converged: a 100-fold tighter tolerance "
             f"moves it by {ref['change_at_tighter_tolerance']:.2g} m at most.",
             f"- Error amplification: raising the start by 1e-7 m moves the motion by up to "
             f"{ref['amplification']:.3g} x 1e-7 m (largest at t = {ref['amplification_time']:.3g} s)."]
    if conv:
        lines.append(f"- MuJoCo's converged solution ({conv['integrator']} at dt = {conv['dt']:g} s) moves by "
                     f"{conv['change_at_double_step']:.2g} m when the step doubles, and lies "
                     f"{conv['error_max']:.3g} m (max; RMS {conv['error_l2']:.3g} m) from our reference: "
                     f"the model difference.")
    lines += ["", "**Energy the numerics made or lost** (R(end) = E(end) - E(0) + W, docs/energy-balance.md):", "",
              *residual_rows(sweep)]
    lines += ["", f"**Cheapest way to 1 mm:** {answer(sweep)}", ""]
    rows = [[r.simulator, r.integrator, f"{r.dt:g}", *map(_num, (r.error_max, r.error_l2, r.angle_error_max,
                                                                  r.error_max_self, r.residual_end, r.cpu_time,
                                                                  r.wall_time)),
             str(r.force_evals), "" if r.stable else "unstable: " + r.note] for r in sweep.runs]
    lines += markdown(["simulator", "integrator", "dt (s)", "max error (m)", "RMS error (m)", "max angle error (rad)",
                       "MuJoCo vs own converged, max (m)", "R(end) (J)", "CPU time (s)", "wall time (s)",
                       "force evaluations", "note"], rows).splitlines()
    lines.append("")
    return lines


def write_json(results, path: Path, runtime: float, jobs: int) -> None:
    import dataclasses

    doc = {"runtime_s": runtime, "jobs": jobs, "scenes": []}
    for sweep in results:
        ref = {k: v for k, v in sweep.reference.items() if k != "states"}
        conv = {k: v for k, v in sweep.mujoco_converged.items() if k != "states"}
        doc["scenes"].append({
            "name": sweep.scene.name, "reference": ref, "mujoco_converged": conv,
            "cheapest_to_1mm": answer(sweep),
            "runs": [r.as_dict() for r in sweep.runs],
            "stability": [dataclasses.asdict(lim) for lim in sweep.stability],
        })
    path.write_text(finite_json(doc, indent=1))
