"""Time one step of each scene in both simulators (same run) and print ns per step and the ratio.

Ours runs compiled without recording (custom_sim.Stepper.advance); MuJoCo runs its own C loop
(mj_step with nstep, or rollout: the faster). Each side takes the scene's full duration from
its initial state, warmed up, minimum of repeats of the stepping thread's CPU time (equal to
the wall time on an idle core; the wall figures are printed too). `newton/step` is the
Newton iterations per step (implicit Euler only; the other integrators solve nothing).
--json prints one object per scene per line: name, ns_per_step_custom, ns_per_step_mujoco,
ratio, newton_per_step (and the wall-clock figures and settings). --linearity also times n
and 10 n steps from the scene's end state and prints the cost ratio (10 = linear).
--integrator runs our side with another integrator (e.g. implicit_euler on every scene).
--against REV also times custom_sim as of git revision REV, in the same rounds: before and
after in one run. --cold measures a first `run` on an empty numba cache instead: compile
time and run time apart (with --against REV, that revision's checkout beside today's).
--sim MODULE:FUNCTION also times the user's code, a whole run through the harness per timing
(the integrator it declares, else the scene's), and prints a line per scene: ns per step beside
custom_sim's and MuJoCo's, and the harness's own share per call.
"""
from __future__ import annotations

import dataclasses
import json
import sys

from custom_sim import INTEGRATORS

from scene_types import BadInput
from ..scenarios import load_all
from ..table import text

SPEED_GOAL = 50.0   # issue 5: our step at least 50 times cheaper than MuJoCo's


def add_arguments(parser) -> None:
    parser.add_argument("scenes", nargs="*", metavar="SCENE",
                        help="built-in name or path to a .toml (default: all built-ins)")
    parser.add_argument("--json", action="store_true", help="one JSON object per scene per line")
    parser.add_argument("--linearity", action="store_true",
                        help="also time 10x the steps and print the cost ratio (10 = linear)")
    parser.add_argument("--repeats", type=int, default=None, metavar="N",
                        help="timed repeats after the warm-up (default: 7, fewer for slow scenes)")
    parser.add_argument("--rounds", type=int, default=None, metavar="N",
                        help="times both sides are timed in alternation, minimum kept (default: 3)")
    parser.add_argument("--integrator", choices=sorted(INTEGRATORS), default=None,
                        help="our side's integrator instead of each scene's own")
    parser.add_argument("--against", metavar="REV", default=None,
                        help="also time custom_sim as of this git revision, in the same rounds")
    parser.add_argument("--cold", action="store_true",
                        help="time a first `run` on an empty numba cache: compile and run apart")
    from .sweep import add_simulator_arguments
    add_simulator_arguments(parser)


def main(args) -> int:
    scenes = load_all(args.scenes)
    if args.cold:
        return cold(args)
    from .sweep import user_simulator
    yours, scenes = user_simulator(args, scenes)
    from ..tools.accuracy.benchmark import bench_scene, custom_sim_at, linearity

    try:
        before = custom_sim_at(args.against) if args.against else None
    except ValueError as err:
        raise BadInput(str(err)) from None
    timing = {} if args.repeats is None else {"repeats": max(1, args.repeats)}
    rows, mine = [], []
    for scene in scenes:
        if args.integrator:
            scene = dataclasses.replace(scene, integrator=args.integrator)
        if not args.json:
            print(f"{scene.name} ...", file=sys.stderr, flush=True)
        r = bench_scene(scene, before=before, yours=yours,
                        **({} if args.rounds is None else {"rounds": max(1, args.rounds)}), **timing)
        row = r.as_dict()
        lin = linearity(scene, **timing) if args.linearity else None
        if lin is not None:
            row.update(linearity_custom=lin.custom_ratio, linearity_mujoco=lin.mujoco_ratio)
        if args.json:
            print(json.dumps(row), flush=True)
            continue
        floor = "–" if r.ns_per_step_minimal is None else \
            f"{r.ns_per_step_minimal:.1f} ({r.ns_per_step_custom / r.ns_per_step_minimal:.1f}x)"
        rows.append([r.name, f"{r.ns_per_step_custom:.1f}", floor, f"{r.ns_per_step_mujoco:.1f}", f"{r.ratio:.1f}x",
                     f"{r.ns_per_step_mujoco_wall / r.ns_per_step_custom_wall:.1f}x", f"{r.newton_per_step:.2f}",
                     *([f"{r.ns_per_step_before:.1f}", f"{r.ns_per_step_custom / r.ns_per_step_before:.2f}x"]
                       if before else []),
                     f"{r.integrator_custom}, {r.dt_custom:g}", f"{r.integrator_mujoco}, {r.dt_mujoco:g}, {r.mujoco_loop}",
                     *([f"{lin.custom_ratio:.2f}x (custom), {lin.mujoco_ratio:.2f}x (mujoco)"] if lin else []),
                     "" if r.ratio >= SPEED_GOAL else f"below the {SPEED_GOAL:g}x goal"])
        if yours is not None:
            mine.append(yours_line(r))
    if not args.json:
        figures = ["custom ns/step", "minimal loop", "mujoco ns/step", "ratio", "wall ratio", "newton/step",
                   *(["before ns/step", "after/before"] if before else [])]
        words = ["custom integrator, dt", "mujoco integrator, dt, loop",
                 *(["10x steps cost"] if args.linearity else []), "note"]
        print(text(["scene", *figures, *words], rows,
                   align=["left", *["right"] * len(figures), *["left"] * len(words)]))
        for line in mine:
            print(line)
    return 0


def yours_line(r) -> str:
    """The user's step on one scene: ns per step beside custom_sim's and MuJoCo's, the harness's share."""
    line = (f"{r.name}: yours ({r.yours}, {r.integrator_yours}, dt {r.dt_custom:g}): "
            f"{r.ns_per_step_yours:.0f} ns/step, {r.ns_per_step_yours / r.ns_per_step_custom:.0f}x custom_sim's "
            f"{r.ns_per_step_custom:.1f}, {r.ns_per_step_yours / r.ns_per_step_mujoco:.1f}x MuJoCo's "
            f"{r.ns_per_step_mujoco:.0f}")
    if r.ns_per_call_harness is not None:
        line += (f"; the harness's own share {r.ns_per_call_harness:.0f} ns per call "
                 f"({r.ns_per_call_harness / r.ns_per_step_yours:.1%})")
    else:
        line += "; one call per run (the harness's share is the scene dict and the checks of the array)"
    return line


def cold(args) -> int:
    """--cold: the first run's compile time and run time, apart (see accuracy/cold_start.py)."""
    import tempfile
    from pathlib import Path

    from ..tools.accuracy import cold_start

    names = list(args.scenes)
    with tempfile.TemporaryDirectory() as work:
        trees = [("today", cold_start.ROOT)]
        if args.against:
            try:
                trees.append((args.against, cold_start.checkout(args.against, Path(work))))
            except ValueError as err:
                raise BadInput(str(err)) from None
        load = cold_start.load_average()
        try:
            results = cold_start.measure([tree for _, tree in trees], names, rounds=args.rounds or 1)
        except RuntimeError as err:   # a command that failed in a checkout: said, not a traceback
            print(f"error: bench --cold: {err}", file=sys.stderr)
            return 1
        labelled = [(label, r) for (label, _), r in zip(trees, results)]
        if args.json:
            for label, r in labelled:
                print(json.dumps({"tree": label, **{k: dataclasses.asdict(getattr(r, k)) for k in
                                                   ("compile", "run_warm", "first_run", "second_run", "user_run", "after_edit",
                                                    "user_code")}}))
        else:
            print("`" + " ".join(["python -m compare run", *names]) + "` on an empty numba cache:")
            print(cold_start.table(labelled))
        print(f"load average (1, 5, 15 min) before: {load}; after: {cold_start.load_average()}")
    return 0
