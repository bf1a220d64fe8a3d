"""Run every check of each scenario and write the comparison report.

SCENE is a built-in name (see `list`) or a path to a scene file; without SCENE every
built-in scenario runs. Writes DIR/index.md and DIR/<name>/ (metrics.json, trajectory
CSVs, model.xml, plots), into a hidden folder first, then moved into place whole. Exit
status: 0 every scenario judged and every judged check within its tolerance; 1 a check
outside it, or a scenario that could not be judged (nothing judged, unstable, timed out, or an
error: its row says why), or every scenario skipped (a scene the simulator under test says it
does not do: SHAPES, NotImplementedError; skipped scenes fail nothing); 2 bad input (nothing
is written); 130 stopped with Ctrl-C (nothing is written).
"""
from __future__ import annotations

import os
import sys

from scene_types.state import STATE_TEXT, UNITS_TEXT
from scene_types.trajectory import REQUIRED_COLUMNS

from ..cli import EXIT_INTERRUPTED
from ..files import output_folder
from ..scenarios import load_all


def add_arguments(parser) -> None:
    parser.add_argument("scenes", nargs="*", metavar="SCENE", help="built-in name or path to a .toml (default: all built-ins)")
    parser.add_argument("--out", default="reports", metavar="DIR", help="output folder (default: reports/)")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="scenarios run at once (default: every core)")
    user = parser.add_argument_group(
        "the simulator under test (default: custom_sim)",
        "Your own simulator, held to the same checks (docs/validate-your-simulator.md).\n"
        f"state = {STATE_TEXT} of the centre of mass {UNITS_TEXT};\n"
        "scene = the resolved scene as plain dicts and floats, exactly what\n"
        "`python -m compare scene SCENE --json` prints (mass_properties, contact_points, state0).")
    which = user.add_mutually_exclusive_group()
    which.add_argument("--sim", metavar="MODULE:FUNCTION",
                       help="a step function step(state, scene, dt) -> state (6 numbers), called once per step "
                            "from the t = 0 state; MODULE is a dotted module or a path to a .py file. "
                            "A module-level INTEGRATOR = \"rk4\" names the integrator it implements "
                            "(default: the scene's)")
    which.add_argument("--sim-process", metavar="COMMAND",
                       help="a step function in any language: COMMAND reads the scene and `step DT X Y THETA VX VY "
                            "OMEGA` lines on stdin and answers 6 numbers per line (docs/process-protocol.md)")
    user.add_argument("--whole", action="store_true",
                      help="with --sim: FUNCTION is simulate(scene) -> array (steps + 1, 6), row 0 the t = 0 "
                           "state (a 7th column, if any, is the energy in J)")
    which.add_argument("--trajectories", metavar="DIR",
                       help=f"precomputed runs DIR/<scene name>.csv, columns by header name: {','.join(REQUIRED_COLUMNS)} "
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
    """The simulator under test from --sim/--whole/--trajectories/--sim-process (None:
    custom_sim), checked on every scene (preflight), its bad input raised before anything is written."""
    from ..usersim import load_simulator, preflight
    simulator = load_simulator(args.sim, args.whole, args.trajectories, args.sim_process)
    if simulator is not None:
        preflight(simulator, scenes)
    return simulator


def run_config(args):
    """The RunConfig (compare/run/config.py) of run's flags: where the Namespace stops."""
    from ..run.config import RunConfig
    return RunConfig.of(output_folder(args.out).resolve(), args.jobs, args.timeout, getattr(args, "law", None),
                        cache=not getattr(args, "no_cache", False))


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
    from ..api.judge import collect
    from ..executor import Interrupted
    from ..run.lines import cache_line

    config = run_config(args)   # before the user's module imports: its chdir cannot move the report
    if config.timeout is not None and not config.timeout > 0:
        from scene_types import BadInput
        raise BadInput(f"--timeout {config.timeout:g}: expected a positive number of seconds")
    scenes = load_all(args.scenes)
    simulator = None
    loader = getattr(args, "load_simulator", None)
    if loader is not None:
        simulator = loader(args, scenes)  # bad input is raised here, before anything is written
    try:
        judgement = collect(scenes, simulator, config)
    except Interrupted as exc:
        print(f"interrupted: {'; '.join(exc.where) or 'between two scenarios'}; nothing written", file=sys.stderr)
        return EXIT_INTERRUPTED
    # the lines compare.judge returns (compare/api/judgement.py): scenes with a verdict, then the others
    for scene in judgement.scenes:
        if scene.metrics is not None:
            for warning in scene.warnings:
                print(f"warning: {warning}", file=sys.stderr)
            print("\n".join(scene.lines))
    traces = dict(judgement.details)
    for scene in judgement.scenes:
        if scene.metrics is None:   # each once, with its scene, and its traceback below it
            print("\n".join(scene.lines))
            if scene.name in traces:
                sys.stdout.flush()
                print(f"{scene.name}: " + traces.pop(scene.name), file=sys.stderr)
    for name, text in traces.items():   # raised inside a scene that still reached a verdict
        print(f"{name}: {text}", file=sys.stderr)
    print(cache_line([s.metrics for s in judgement.scenes if s.metrics is not None], config.cache), file=sys.stderr)
    print(f"report: {judgement.report}")
    return judgement.exit_status
