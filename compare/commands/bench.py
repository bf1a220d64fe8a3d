"""Time one step of each scene in both simulators (same run) and print ns per step and the ratio.

Ours runs compiled without recording (custom_sim.Stepper.advance); MuJoCo runs its own C loop
(mj_step with nstep, or rollout: the faster). Each side takes the scene's full duration from
its initial state, warmed up, minimum of repeats of the stepping thread's CPU time (equal to
the wall time on an idle core; the wall figures are printed too). --json prints one object
per scene per line: name, ns_per_step_custom, ns_per_step_mujoco, ratio (and the wall-clock
figures and settings). --linearity also times n and 10 n steps from the scene's end state
and prints the cost ratio (10 = linear).
"""
from __future__ import annotations

import json


from ..scenarios import load_all

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


def main(args) -> int:
    scenes = load_all(args.scenes)
    from ..accuracy.benchmark import bench_scene, linearity

    timing = {} if args.repeats is None else {"repeats": max(1, args.repeats)}
    if not args.json:
        print(f"{'scene':<18}{'custom ns/step':>16}{'mujoco ns/step':>16}{'ratio':>9}{'wall ratio':>12}   "
              f"(custom integrator, dt | mujoco integrator, dt, loop)")
    for scene in scenes:
        r = bench_scene(scene, **({} if args.rounds is None else {"rounds": max(1, args.rounds)}), **timing)
        row = r.as_dict()
        lin = linearity(scene, **timing) if args.linearity else None
        if lin is not None:
            row.update(linearity_custom=lin.custom_ratio, linearity_mujoco=lin.mujoco_ratio)
        if args.json:
            print(json.dumps(row), flush=True)
            continue
        goal = "" if r.ratio >= SPEED_GOAL else f"  below the {SPEED_GOAL:g}x goal"
        wall = r.ns_per_step_mujoco_wall / r.ns_per_step_custom_wall
        print(f"{r.name:<18}{r.ns_per_step_custom:>16.1f}{r.ns_per_step_mujoco:>16.1f}{r.ratio:>8.1f}x{wall:>11.1f}x   "
              f"({r.integrator_custom}, {r.dt_custom:g} | {r.integrator_mujoco}, {r.dt_mujoco:g}, "
              f"{r.mujoco_loop}){goal}", flush=True)
        if lin is not None:
            print(f"{'':<18}10x steps cost {lin.custom_ratio:.2f}x (custom), "
                  f"{lin.mujoco_ratio:.2f}x (mujoco)", flush=True)
    return 0
