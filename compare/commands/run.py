"""Run every check of each scenario and write the comparison report.

SCENE is a built-in name (see `list`) or a path to a scene file; without SCENE every
built-in scenario runs. Writes DIR/index.md and DIR/<name>/ (metrics.json, trajectory
CSVs, model.xml, plots), into a hidden folder first, then moved into place whole. Exit
status: 0 every scenario judged and every judged check within its tolerance; 1 a check
outside it, or a scenario that could not be judged (nothing judged, unstable, timed out, or an
error: its row says why); 2 bad input (nothing is written); 130 stopped with Ctrl-C (nothing
is written).
"""
from __future__ import annotations

import functools
import os
import sys
from dataclasses import dataclass
from pathlib import Path

from custom_sim.compile_cache import warm_up_in_parallel

from ..cli import EXIT_INTERRUPTED, output_folder
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
    user.add_argument("--law", metavar="FILE.toml|identified",
                      help="judge every check under another contact law: a [contact] table laid over each "
                           "scene's (docs/scene-format.md), or `identified`: the law `identify` finds in "
                           "--sim's step function (default: the scene's own law)")
    add_timeout(parser)
    parser.add_argument("--no-cache", action="store_true",
                        help="recompute what depends only on the scene (MuJoCo's runs, custom_sim's, the reference) "
                             "instead of taking it from the cache of earlier runs")
    parser.set_defaults(load_simulator=_load_simulator)


def _load_simulator(args, scenes):
    """The simulator under test from --sim/--whole/--trajectories (None: custom_sim), its bad
    input raised before anything is written."""
    from ..usersim import for_run
    return for_run(args, scenes)


@dataclass
class Outcome:
    """What one scenario's process sent back: exactly one field is set."""

    row: dict | None = None            # metrics.json of a scenario that reached a verdict
    failure: tuple | None = None       # (status, why): no verdict (error, unstable, timeout)
    bad_input: tuple | None = None     # (message, details): the user's code broke the protocol
    details: str = ""                  # with a failure: the user's own traceback, where their code raised


def one_line(exc: BaseException) -> str:
    """`Type: first line of the message`: the cause a report row shows."""
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0]}" if text else type(exc).__name__


def run_one(scene, out: str, simulator=None):
    """A scenario's process: run, judge and write it into `out`. Returns an Outcome: the
    metrics.json dict; or (status, cause) when no verdict could be reached; or the bad input
    the user's code gave (the whole run then writes nothing). Never raises."""
    from ..usersim import UserCodeError
    try:
        from mujoco_models import to_mjcf

        from ..report import write_scenario
        from ..checks.scenario import run_scenario

        from ..store import counts

        result = run_scenario(scene, simulator)
        if result.error:
            return Outcome(failure=(result.status, result.error), details=result.error_details)
        row = write_scenario(result, Path(out), to_mjcf(scene))
        return Outcome(row={**row, "cache": counts()})
    except UserCodeError as exc:
        return Outcome(bad_input=(str(exc), exc.details))
    except Exception as exc:  # noqa: BLE001 - becomes the scenario's error row
        return Outcome(failure=("error", one_line(exc)))


def expected_cost(scene) -> float:
    """A scenario's relative cost, for the order of submission: its steps times the force
    evaluations of a step (RK4: 4) times its contact points, plus a constant share for the runs
    of fixed cost (MuJoCo twins, plots)."""
    from custom_sim import INTEGRATORS, mass_properties
    evals = INTEGRATORS[scene.integrator].evals_per_step or 2
    return scene.steps * evals * len(mass_properties(scene.body).points) + 2e5


def run_scenes(scenes, work, jobs: int, timeout: float | None = None, cost=None) -> dict:
    """work(scene) -> Outcome for every scene, each in a process forked for it alone
    (compare/executor/processes.py: no state of a user's module passes from one scene to the
    next, and a crash or a hang costs only that scene's row), at most `jobs` at once,
    costliest first by cost(scene); a scene still running after `timeout` s is stopped.
    Ctrl-C stops every process and raises Interrupted, naming each scene and its step."""
    from ..executor import Task, make_executor
    from ..executor.progress import StepLines

    order = sorted(scenes, key=cost, reverse=True) if cost else list(scenes)
    tasks = [Task(s.name, (s,), meta={"dt": s.dt}) for s in order]
    with make_executor("processes", workers=max(1, jobs)) as executor:
        return executor.run(work, tasks, desc="scenarios", progress=StepLines("scenarios"), timeout=timeout,
                            retry=False, failed=functools.partial(_no_verdict, timeout=timeout))


def _no_verdict(task, failure, timeout: float | None) -> Outcome:
    """The row of a scenario whose process gave no Outcome: it raised outside run_one, died
    (a crash outside Python), or ran past --timeout. Not run again: its crash is its verdict."""
    if failure.kind == "timeout":
        return Outcome(failure=("timeout", f"stopped after {timeout:g} s (--timeout), at {failure.detail}"))
    if failure.kind == "died":
        return Outcome(failure=("error", f"the process running it ended without a verdict ({failure.detail}): "
                                         "a crash outside Python, or the machine stopping it"))
    return Outcome(failure=("error", failure.reason.splitlines()[0]))


def _number(value, unit: str) -> str:
    return "–" if value is None else f"{value:.3e} {unit}"


def failure_text(check) -> str:
    """What a failed check (a CheckRow) measured: the component and value that left the tolerance."""
    label, d = check.label, check.details
    if d.get("first_residual") is not None:   # step: per component, per step
        return (f"{label}: {d['component']} off by {d['first_residual']:.3e} at step {d['first_step']} "
                f"(t = {d['first_time']:.6g} s, {d['phase']}), round-off bound {d['first_bound']:.3e}")
    parts = []
    pos, tol_p = check.position_error_max, check.tolerance_position
    ang, tol_a = check.angle_error_max, check.tolerance_angle
    if pos is not None and tol_p is not None and pos > tol_p:
        parts.append(f"position {pos:.3e} m (tolerance {tol_p:.3e} m)")
    if ang is not None and tol_a is not None and ang > tol_a:
        parts.append(f"angle {ang:.3e} rad (tolerance {tol_a:.3e} rad)")
    if d.get("component_first_over") and d.get("first_step_over") is not None:
        parts.append(f"first at step {d['first_step_over']}, in {d['component_first_over']}")
    if not parts:   # failed on something else (a non-finite state, ...): its reason says what
        parts.append(check.reason or f"position {_number(pos, 'm')}, angle {_number(ang, 'rad')}")
    return f"{label}: " + ", ".join(parts)


def verdict_line(row: dict) -> str:
    """The line `run` prints for a scenario that ran (its metrics.json): pass (with what was not
    judged), FAIL (each failed check's component and value), or not judged."""
    from ..checks.row import CheckRow
    from ..checks.scenario import SHOWN

    name = row["name"]
    checks = [CheckRow.from_json(c) for c in row["checks"]]
    judged = [c for c in checks if c.passed is not None]
    skipped = [c.label for c in checks if c.passed is None and c.name not in SHOWN]
    note = f"; not judged: {', '.join(skipped)} (see the page)" if skipped else ""
    if not judged:
        return f"{name:<20} not judged: no check could be judged ({', '.join(skipped) or 'none'}; see the page)"
    if row["pass"]:
        return f"{name:<20} pass  {len(judged)} checks within tolerance{note}"
    return f"{name:<20} FAIL  " + "; ".join(failure_text(c) for c in checks if c.passed is False)


def add_timeout(parser) -> None:
    parser.add_argument("--timeout", type=float, metavar="SECONDS",
                        help="stop a scenario that runs longer than this (its row says where it was)")


def main(args) -> int:
    import signal

    from ..usersim.guard import mark_interrupted

    previous = signal.signal(signal.SIGINT, mark_interrupted)
    try:
        return _run(args)
    finally:
        signal.signal(signal.SIGINT, previous)


def _run(args) -> int:
    from ..report.publish import report_aside
    from ..executor import Interrupted
    from ..usersim import UserCodeError

    out = output_folder(args.out).resolve()   # before the user's module imports: its chdir cannot move it
    if getattr(args, "no_cache", False):
        from ..store import CACHE_ENV
        os.environ[CACHE_ENV] = "off"
    if args.timeout is not None and not args.timeout > 0:
        from scene_types import BadInput
        raise BadInput(f"--timeout {args.timeout:g}: expected a positive number of seconds")
    scenes = load_all(args.scenes)
    simulator = None
    loader = getattr(args, "load_simulator", None)
    if loader is not None:
        simulator = loader(args, scenes)  # bad input is raised here, before anything is written
    if getattr(args, "law", None):
        scenes = under_law(scenes, args.law, simulator)
    compile_everything()

    from ..report import write_index

    try:
        with report_aside(out) as work:
            outcomes = run_scenes(scenes, functools.partial(run_one, out=str(work), simulator=simulator),
                                  args.jobs, args.timeout, expected_cost)
            bad = [o.bad_input for o in outcomes.values() if o.bad_input]
            if bad:
                raise UserCodeError(*bad[0])
            rows = [outcomes[s.name].row for s in scenes if outcomes[s.name].row is not None]
            failed = [(s.name, *outcomes[s.name].failure) for s in scenes if outcomes[s.name].failure]
            details = [outcomes[s.name].details for s in scenes if outcomes[s.name].details]
            index = write_index(work, rows, failed)
    except Interrupted as exc:
        print(f"interrupted: {'; '.join(exc.where) or 'between two scenarios'}; nothing written", file=sys.stderr)
        return EXIT_INTERRUPTED
    index = out / index.name
    for r in rows:
        for warning in r.get("warnings", []):
            named = warning if warning.startswith(f"{r['name']}:") else f"{r['name']}: {warning}"
            print(f"warning: {named}", file=sys.stderr)
        print(verdict_line(r))
        for law in (r.get("diagnosis") or {}).get("laws") or []:
            print(f"{'':<20} law   {law['text']}")
    for text in details:
        print(text, file=sys.stderr)
    for name, status, why in failed:
        print(f"{name:<20} {status}: {why}")
        print(f"error: {why}", file=sys.stderr)
    print(cache_line(rows), file=sys.stderr)
    if failed or any(r.get("cache", {}).get("misses") for r in rows):   # the cache may have grown
        from ..store import trim
        trim()
    print(f"report: {index}")
    judged = all(any(c["pass"] is not None for c in r["checks"]) for r in rows)
    return 0 if not failed and judged and all(r["pass"] for r in rows) else 1


def cache_line(rows: list[dict]) -> str:
    """What came from the cache of scene-only work (compare/store.py), in one line."""
    from ..store import folder

    where = folder()
    if where is None:
        return "cache: off (scene-only work computed)"
    hits = sum(r["cache"]["hits"] for r in rows if "cache" in r)
    misses = sum(r["cache"]["misses"] for r in rows if "cache" in r)
    whole = sum(1 for r in rows if r.get("cache", {}).get("hits") and not r["cache"]["misses"])
    return (f"cache: {hits} of {hits + misses} scene-only runs from {where} ({whole} of {len(rows)} scenarios "
            f"wholly; --no-cache recomputes)")


def under_law(scenes, law: str, simulator):
    """The scenes under `--law`: a law file's [contact] laid over each scene's, or the law
    `identify` finds in the simulator under test (its bad input raised before anything runs)."""
    from scene_types import BadInput
    from scene_types.law_file import load_law, with_law

    if law != "identified":
        table = load_law(law)
        return [with_law(s, table, law) for s in scenes]
    if simulator is None:
        raise BadInput("--law identified: expected --sim MODULE:FUNCTION (a step function, or with --whole "
                       "a whole run) or --trajectories DIR, whose law `identify` can find")
    from ..identify import NotIdentified, identified_contact, identify
    from ..usersim import UserCodeError, UserFault
    out = []
    for scene in scenes:
        try:
            out.append(with_law(scene, identified_contact(scene, identify(simulator, scene)), "identified"))
        except NotIdentified as exc:
            raise BadInput(f"--law identified: {exc} (`python -m compare identify` shows each effect)") from None
        except UserFault as exc:
            raise UserCodeError(f"--law identified: {exc}", getattr(exc, "details", "")) from None
    return out


def prepare_workers() -> None:
    """What every worker needs before its first scenario, done once here so that the forked
    workers inherit it: the dynamics twin's compiled passive-force callback, and the modules of
    the checks and the report (matplotlib, scipy, mujoco: a second or more a process)."""
    import compare.report  # noqa: F401
    from ..store import prepare
    prepare()   # joblib and the code's digest, once
    compare.report.prebuild_figures()   # each figure's axes and ticks, built once for every worker
    import compare.checks.attribution  # noqa: F401
    import compare.checks.scenario  # noqa: F401
    import compare.checks.contact_check  # noqa: F401
    import compare.checks.dynamics_check  # noqa: F401
    import compare.checks.step_check  # noqa: F401
    import compare.oracle.reference  # noqa: F401
    from mujoco_models.passive import callback
    callback()


def compile_everything() -> None:
    """Compile once, before the workers start, so that they load numba's cache instead of each
    compiling the same code: custom_sim's two stepping loops at once, in this process and a
    forked one, and here, meanwhile, what prepare_workers does. Prints "compiling the
    simulator (first run only) ..." when it has to."""
    warm_up_in_parallel(meanwhile=prepare_workers)
