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
pool; --scheduler needs Dask (pip install -e '.[study]'). With --sim the user's code runs beside
them (compare/tools/accuracy/yours.py): its work-precision curve, the order its error falls at,
its largest stable step. Exit status: 0 done, 2 bad input.
"""
from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

from ..files import output_folder
from ..scenarios import load_all


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
    add_simulator_arguments(parser)


def add_simulator_arguments(parser) -> None:
    """--sim, --whole and --law: the user's simulator beside custom_sim and MuJoCo (sweep, bench)."""
    user = parser.add_argument_group(
        "your simulator (docs/accuracy-of-your-code.md)",
        "Your code beside custom_sim and MuJoCo: the same ladder of steps, the same stability search.")
    user.add_argument("--sim", metavar="MODULE:FUNCTION",
                      help="a step function step(state, scene, dt) -> state; run with each integrator custom_sim "
                           "has (as scene[\"integrator\"]), or only the one its module names in INTEGRATOR")
    user.add_argument("--sim-process", metavar="COMMAND",
                      help="a step in any language on stdin/stdout (docs/process-protocol.md), in place of --sim")
    user.add_argument("--whole", action="store_true",
                      help="with --sim: FUNCTION is simulate(scene) -> array (steps + 1, 6); scene[\"dt\"] is "
                           "each rung's step")
    user.add_argument("--law", metavar="FILE.toml|identified",
                      help="every simulator under another contact law: a [contact] table laid over each scene's, "
                           "or `identified`: the law `identify` finds in --sim's step")


PROBE_STEPS = 10   # steps of each scene run here first: a wrong return is bad input before the sweep starts


def user_simulator(args, scenes):
    """(simulator or None, the scenes under --law): bad input raised before anything runs (a
    wrong return shows in the first steps; a fault of the run, e.g. NotImplementedError, is the
    sweep's to report)."""
    import dataclasses

    from ..usersim import UserFault, load_simulator, preflight

    simulator = load_simulator(args.sim, args.whole, process=getattr(args, "sim_process", None))
    if simulator is not None:
        preflight(simulator, scenes)
    if getattr(args, "law", None):
        from ..run.law import under_law
        scenes = under_law(scenes, args.law, simulator)
    if simulator is not None:
        for scene in scenes:
            try:
                simulator.run(dataclasses.replace(scene, duration=min(scene.duration, PROBE_STEPS * scene.dt)))
            except UserFault:
                pass
    return simulator, scenes


def main(args) -> int:
    if args.scheduler:   # before any work: the one line that says what to install
        from ..executor import require_dask
        require_dask("sweep --scheduler")
    scenes = load_all(args.scenes)
    out = output_folder(args.out)
    simulator, scenes = user_simulator(args, scenes)

    from tqdm import tqdm

    from ..tools.accuracy.workprecision import run_sweep
    from ..tools.sweep.answer import answer
    from ..tools.sweep.report import write_report
    from ..tools.sweep.yours import yours_lines

    start = time.perf_counter()
    jobs = max(1, args.jobs)
    cache = None if args.no_cache else Path(args.cache or Path(tempfile.gettempdir()) / "compare-sweep-cache")
    results = run_sweep(
        scenes, cache_dir=cache, jobs=jobs, scheduler=args.scheduler,
        mujoco=not args.no_mujoco, stability=not args.no_stability, simulator=simulator,
        progress=lambda total: tqdm(total=total, desc="sweep", unit="task", delay=2, file=sys.stderr))
    runtime = time.perf_counter() - start
    folder = write_report(results, out, runtime, jobs, " ".join(["python -m compare sweep", *args.scenes]))
    for sweep in results:
        print(f"{sweep.scene.name}: {answer(sweep)}")
        for line in yours_lines(sweep):
            print(f"{sweep.scene.name}: {line}")
    print(f"sweep took {runtime:.0f} s on {jobs} worker(s); report: {folder / 'index.md'}; "
          f"the cheapest-way table: {folder / 'cheapest.md'}")
    return 0
