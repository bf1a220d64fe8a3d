"""Run every check of each scenario and write the comparison report.

SCENE is a built-in name (see `list`) or a path to a scene file; without SCENE every
built-in scenario runs. Writes DIR/index.md and DIR/<name>/ (metrics.json, trajectory
CSVs, model.xml, plots). Exit status: 0 every check within its tolerance, 1 a check outside
it, or a scenario that could not be judged (unstable, or an error: its row says why), 2 bad
input (nothing is written).
"""
from __future__ import annotations

import os
import sys
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path

from custom_sim.compile_cache import warm_up_in_parallel

from ..cli import output_folder
from ..scenarios import load_all


def add_arguments(parser) -> None:
    parser.add_argument("scenes", nargs="*", metavar="SCENE", help="built-in name or path to a .toml (default: all built-ins)")
    parser.add_argument("--out", default="reports", metavar="DIR", help="output folder (default: reports/)")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="scenarios run at once (default: every core)")
    user = parser.add_argument_group(
        "the simulator under test (default: custom_sim)",
        "Your own simulator, held to the same checks (docs/validate-your-simulator.md).\n"
        "state = [x, y, theta, vx, vy, omega] of the centre of mass (m, m, rad, m/s, m/s, rad/s);\n"
        "scene = the resolved scene as plain dicts and floats, exactly what\n"
        "`python -m compare scene SCENE --json` prints (mass_properties, contact_points, state0).")
    which = user.add_mutually_exclusive_group()
    which.add_argument("--sim", metavar="MODULE:FUNCTION",
                       help="a step function step(state, scene, dt) -> state (6 numbers), called once per step "
                            "from the t = 0 state; MODULE is a dotted module or a path to a .py file. "
                            "A module-level INTEGRATOR = \"rk4\" names the integrator it implements "
                            "(default: the scene's)")
    user.add_argument("--whole", action="store_true",
                      help="with --sim: FUNCTION is simulate(scene) -> array (steps + 1, 6), row 0 the t = 0 "
                           "state (a 7th column, if any, is the energy in J)")
    which.add_argument("--trajectories", metavar="DIR",
                       help="precomputed runs DIR/<scene name>.csv, columns by header name: t,x,y,theta,vx,vy,omega "
                            "required (energy optional), first row t = 0, then one row per step of dt")
    parser.set_defaults(load_simulator=_load_simulator)


def _load_simulator(args, scenes):
    """The simulator under test from --sim/--whole/--trajectories (None: custom_sim), its bad
    input raised before anything is written."""
    from ..usersim import for_run
    return for_run(args, scenes)


def one_line(exc: BaseException) -> str:
    """`Type: first line of the message`: the cause a report row shows."""
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0]}" if text else type(exc).__name__


def run_one(scene, out: str, simulator=None):
    """Worker: run, judge and write one scenario. Returns (metrics.json dict, None), or
    (None, (status, cause)) when no verdict could be reached; never raises for a failure
    inside the scenario, so one scenario cannot stop the others."""
    try:
        from mujoco_models import to_mjcf

        from ..report import write_scenario
        from ..verdict.comparison import run_scenario

        result = run_scenario(scene, simulator)
        if result.error:
            return None, (result.status, result.error)
        return write_scenario(result, Path(out), to_mjcf(scene)), None
    except Exception as exc:  # noqa: BLE001 - becomes the scenario's error row
        from ..cli import BadInput
        if isinstance(exc, BadInput):
            raise
        return None, ("error", one_line(exc))


def expected_cost(scene) -> float:
    """A scenario's relative cost, for the order of submission: its steps times the force
    evaluations of a step (RK4: 4) times its contact points, plus a constant share for the runs
    of fixed cost (MuJoCo twins, plots)."""
    from custom_sim import INTEGRATORS, mass_properties
    evals = INTEGRATORS[scene.integrator].evals_per_step or 2
    return scene.steps * evals * len(mass_properties(scene.body).points) + 2e5


def run_all(scenes, out: Path, jobs: int, simulator=None) -> tuple[dict, dict]:
    """Every scene in worker processes. A worker that dies (a crash in compiled code, the
    machine killing it) breaks the pool; the scenes it took down are run again, one process
    each, so that only the one that kills its process gets an error row."""
    from tqdm import tqdm

    rows, failures = {}, {}
    todo = sorted(scenes, key=expected_cost, reverse=True)  # longest first: the pool's tail is short
    with tqdm(total=len(todo), desc="scenarios", unit="scene", delay=2, file=sys.stderr) as bar:
        for width in (max(1, min(jobs, len(todo))), 1):
            lost = []
            groups = [todo] if width > 1 else [[s] for s in todo]
            for group in groups:
                try:
                    with ProcessPoolExecutor(width) as pool:
                        futures = {pool.submit(run_one, s, str(out), simulator): s for s in group}
                        for future in futures:
                            scene = futures[future]
                            try:
                                row, failure = future.result()
                            except BrokenProcessPool:
                                lost.append(scene)
                                continue
                            bar.update()
                            if row is None:
                                failures[scene.name] = failure
                            else:
                                rows[scene.name] = row
                except BrokenProcessPool:
                    pass
            todo = [s for s in lost if s.name not in rows and s.name not in failures]
            if not todo:
                break
        for scene in todo:  # died even alone
            failures[scene.name] = ("error", "the worker process running it died (a crash outside Python)")
            bar.update()
    return rows, failures


def verdict_line(row: dict) -> str:
    name = row["name"]
    if row["pass"]:
        judged = [c for c in row["checks"] if c["pass"] is not None]
        return f"{name:<20} pass  {len(judged)} checks within tolerance"
    parts = []
    for c in row["checks"]:
        if c["pass"] is False:
            label = f"{c['name']} ({c['integrator']})" if c.get("integrator") else c["name"]
            parts.append(f"{label}: position {c['position_error_max']:.3e} m (tolerance "
                         f"{c['tolerance_position']:.3e} m), angle {c['angle_error_max']:.3e} rad "
                         f"(tolerance {c['tolerance_angle']:.3e} rad)")
    return f"{name:<20} FAIL  " + "; ".join(parts)


def main(args) -> int:
    scenes = load_all(args.scenes)
    simulator = None
    loader = getattr(args, "load_simulator", None)
    if loader is not None:
        simulator = loader(args, scenes)  # bad input is raised here, before anything is written
    out = output_folder(args.out)
    compile_everything()
    out.mkdir(parents=True, exist_ok=True)

    from ..report import write_index

    rows, failures = run_all(scenes, out, args.jobs, simulator)
    ordered = [rows[s.name] for s in scenes if s.name in rows]
    failed = [(s.name, *failures[s.name]) for s in scenes if s.name in failures]
    index = write_index(out, ordered, failed)
    for r in ordered:
        for warning in r.get("warnings", []):
            print(f"warning: {warning}", file=sys.stderr)
        print(verdict_line(r))
    for name, status, why in failed:
        print(f"{name:<20} {status}: {why}")
        print(f"error: {why}", file=sys.stderr)
    print(f"report: {index}")
    return 0 if not failed and all(r["pass"] for r in ordered) else 1


def prepare_workers() -> None:
    """What every worker needs before its first scenario, done once here so that the forked
    workers inherit it: the dynamics twin's compiled passive-force callback, and the modules of
    the checks and the report (matplotlib, scipy, mujoco: a second or more a process)."""
    import compare.report  # noqa: F401
    import compare.verdict.attribution  # noqa: F401
    import compare.verdict.comparison  # noqa: F401
    import compare.verdict.contact_check  # noqa: F401
    import compare.verdict.dynamics_check  # noqa: F401
    import compare.verdict.step_check  # noqa: F401
    import compare.accuracy.reference  # noqa: F401
    from mujoco_models.passive import callback
    callback()


def compile_everything() -> None:
    """Compile once, before the workers start, so that they load numba's cache instead of each
    compiling the same code: custom_sim's two stepping loops at once, in this process and a
    forked one, and here, meanwhile, what prepare_workers does. Prints "compiling the
    simulator (first run only) ..." when it has to."""
    warm_up_in_parallel(meanwhile=prepare_workers)
