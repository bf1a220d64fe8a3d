"""Hold a simulator to the checks that need no MuJoCo, and print its diagnosis (writes nothing).

    python -m compare validate examples/seed_sim.py:step [SCENE ...]
    python -m compare validate examples/buggy_sim.py:step box_drop --markdown
    python -m compare validate --trajectories DIR [SCENE ...]
    python -m compare validate examples/seed_sim.py:step box_drop --law identified   (or --law FILE.toml)

Per scene: `identical` (against custom_sim, same integrator and dt, to round-off), `step` (every
step against one independent step) and the diagnosis. Exit status 0 when every judged check
passes and at least one was judged, 1 otherwise, 2 for bad input. `python -m compare run --sim ...` adds the MuJoCo checks
and the report pages.
"""
from __future__ import annotations


def add_arguments(parser) -> None:
    parser.add_argument("sim", nargs="?", metavar="MODULE:FUNCTION",
                        help="the step function under test (with --whole, simulate); MODULE is a dotted "
                             "module or a path to a .py file")
    parser.add_argument("scenes", nargs="*", metavar="SCENE",
                        help="built-in name or path to a .toml (default: every built-in scene)")
    parser.add_argument("--whole", action="store_true",
                        help="FUNCTION is simulate(scene) -> array (steps + 1, 6), called once per scene")
    parser.add_argument("--trajectories", metavar="DIR",
                        help="DIR/<scene>.csv written by a simulator in any language (then SCENE only)")
    parser.add_argument("--sim-process", metavar="COMMAND",
                        help="a step function in any language on stdin/stdout (docs/process-protocol.md; "
                             "then SCENE only)")
    parser.add_argument("--markdown", action="store_true", help="print each scene's diagnosis section in full")
    parser.add_argument("--law", metavar="FILE.toml|identified",
                        help="judge under another contact law: a [contact] table laid over each scene's, or "
                             "`identified`: the law `identify` finds in the simulator (default: the scene's own)")


def main(args) -> int:
    from ..run.validate import validate

    sim, scenes = args.sim, args.scenes
    if (args.trajectories or args.sim_process) and sim:  # then the first positional is a scene
        sim, scenes = None, [sim, *scenes]
    return validate(sim, scenes, args.whole, args.trajectories, args.markdown, args.law, args.sim_process)
