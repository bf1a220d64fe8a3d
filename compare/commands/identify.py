"""Tell which contact law a simulator implements: each effect's family and parameters, or none.

    python -m compare identify MODULE:FUNCTION [SCENE ...] [--json]
    python -m compare identify MODULE:FUNCTION [SCENE ...] --whole
    python -m compare identify --trajectories DIR [SCENE ...]

A step function step(state, scene, dt) -> state is called from states identify designs (flight,
where contact begins, depths, normal velocities, slips, spins); each effect's force is recovered
from the step's velocity change through the integrator found, in newtons, and every family of
scene_types.laws is fitted to it. A family is named only where it reproduces the step to
round-off; otherwise the law is null and the closest family is given. With --whole
(simulate(scene) -> array (steps + 1, 6)) or --trajectories (DIR/<scene>.csv), the same by
regression over the steps the run visited, to the rounding the file allows, saying which
effects the run never exercised. SCENE: built-in names or .toml paths (default: every built-in).
A scene the simulator does not do (its module's SHAPES, a step raising NotImplementedError) is
a line `SCENE  skipped  REASON` ({"scene", "skipped"} with --json). Exit status: 0 every
exercised effect is the scene's own law; 1 one is not, or every scene was skipped; 2 bad input
(a module or function that does not load, a step that raises or returns no state: that scene's
one line, with its name, and the other scenes identified). See docs/identify.md.
"""
from __future__ import annotations

import sys

from scene_types.trajectory import REQUIRED_COLUMNS


def add_arguments(parser) -> None:
    parser.add_argument("targets", nargs="*", metavar="MODULE:FUNCTION [SCENE ...]",
                        help="the function under test (a step function; with --whole, simulate), then scenes "
                             "(built-in names or .toml paths; default: every built-in). With --trajectories, "
                             "scenes only")
    parser.add_argument("--json", action="store_true", help="print one JSON object per scene (one per line)")
    which = parser.add_mutually_exclusive_group()
    which.add_argument("--whole", action="store_true",
                       help="FUNCTION is simulate(scene) -> array (steps + 1, 6): regression over its run")
    which.add_argument("--trajectories", metavar="DIR",
                       help=f"DIR/<scene>.csv ({','.join(REQUIRED_COLUMNS)}): regression over each file's steps")
    which.add_argument("--sim-process", metavar="COMMAND",
                       help="a step function in any language on stdin/stdout (docs/process-protocol.md): "
                            "designed probes as for a Python step; then scenes only")


def _one_line(exc, scene: str = "") -> None:
    """Bad input without the user's traceback: identify answers in one line (naming the scene,
    and the MODULE:FUNCTION it was given, which `run` calls --sim)."""
    from scene_types import BadInput
    raise BadInput((f"{scene}: " if scene else "") + str(exc).removeprefix("--sim ")) from None


def main(args) -> int:
    from scene_types import BadInput

    from ..identification import identify
    from ..identification.report import as_json, text
    from ..scenarios import load_all
    from ..usersim import SceneSkipped, UserCodeError, UserFault, load_simulator

    targets = list(args.targets)
    if args.trajectories is None and args.sim_process is None:
        if not targets:
            raise BadInput("identify: expected MODULE:FUNCTION (a step function, or with --whole a simulate "
                           "function) or --trajectories DIR")
        spec, scenes = targets[0], targets[1:]
    else:
        spec, scenes = None, targets
    try:
        simulator = load_simulator(spec, args.whole, args.trajectories, args.sim_process)
    except UserCodeError as exc:
        _one_line(exc)
    scene_list = load_all(scenes)
    status, skipped, failed = 0, 0, False
    for scene in scene_list:
        try:
            result = identify(simulator, scene)
        except SceneSkipped as exc:   # a scene the code does not do: said, and nothing fails
            skipped += 1
            print(as_json({"scene": scene.name, "skipped": exc.reason}) if args.json
                  else f"{scene.name}  skipped  {exc.reason}\n", flush=True)
            continue
        except (UserCodeError, UserFault) as exc:   # this scene's: said once, with its scene; the others go on
            failed = True
            message = str(exc).removeprefix("--sim ")
            if args.json:
                print(as_json({"scene": scene.name, "error": message}), flush=True)
            else:
                print(f"error: {scene.name}: {message}", file=sys.stderr, flush=True)
            continue
        if any(v is False for v in result["matches_scene"].values()):
            status = 1
        print(as_json(result) if args.json else text(result) + "\n", flush=True)
    if failed:
        return 2
    return 1 if skipped == len(scene_list) else status


if __name__ == "__main__":   # not an entry point of its own: `python -m compare identify` is
    sys.exit(2)
