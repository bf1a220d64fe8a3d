"""Print a scene resolved: every default filled in, and its derived mass properties.

SCENE is a built-in name or a path to a .toml scene file. With --json it prints the one JSON
object a simulator under test is given as `scene` (see `run --sim`), so that a simulator in
another language can read it: mass_properties holds the mass (kg), the inertia about the
centre of mass (kg m^2) and the contact points relative to the centre of mass in the body
frame (m); state0 is [x, y, theta, vx, vy, omega] at t = 0; steps = duration / dt. With
--law FILE.toml (or `identified` with --sim), the scene under that law: what the step receives
in `run --law`.
"""
from __future__ import annotations

import json


def add_arguments(parser) -> None:
    parser.add_argument("scene", metavar="SCENE", help="a built-in scenario name or a path to a .toml scene")
    parser.add_argument("--json", action="store_true", help="print one JSON object (what --sim's step function gets)")
    add_law_arguments(parser)


def add_law_arguments(parser) -> None:
    """--law, and the simulator `--law identified` finds it in (scene, mjcf)."""
    parser.add_argument("--law", metavar="FILE.toml|identified",
                        help="the scene under another contact law, as `run --law` judges it: a [contact] table "
                             "laid over the scene's, or `identified`: the law `identify` finds in --sim")
    parser.add_argument("--sim", metavar="MODULE:FUNCTION",
                        help="with --law identified: the step function whose law is used (with --whole, simulate)")
    parser.add_argument("--whole", action="store_true", help="with --sim: FUNCTION is simulate(scene)")


def load_under_law(args):
    """The scene SCENE names, under --law when given (bad input: a law file's error, --sim
    without --law identified, a simulator that skips the scene or whose law is not found)."""
    from scene_types import BadInput

    from ..scenarios import load

    scene = load(args.scene)  # a bad scene: compare.cli reports it, exit 2
    if args.law is None:
        if args.sim or args.whole:
            raise BadInput("--sim: expected it with --law identified (the law identify finds in it)")
        return scene
    if args.law != "identified" and (args.sim or args.whole):
        raise BadInput(f"--sim with --law {args.law}: expected --law identified (a law file needs no simulator)")
    from ..run.law import under_law
    from ..usersim import load_simulator

    simulator = load_simulator(args.sim, args.whole) if args.sim else None
    skipped: dict = {}
    (out,) = under_law([scene], args.law, simulator, skipped)
    if scene.name in skipped:
        raise BadInput(f"--law identified: {args.sim} skips {scene.name} ({skipped[scene.name]}): "
                       "no law to identify")
    return out


def _lines(value, indent: str = "") -> list[str]:
    """Readable nested key: value lines."""
    out = []
    for key, v in value.items():
        if isinstance(v, dict):
            out.append(f"{indent}{key}:")
            out += _lines(v, indent + "  ")
        elif isinstance(v, list) and v and isinstance(v[0], (dict, list)):
            out.append(f"{indent}{key}:")
            out += [f"{indent}  - {json.dumps(item)}" for item in v]
        else:
            out.append(f"{indent}{key}: {json.dumps(v)}")
    return out


def main(args) -> int:
    from ..usersim.scene_dict import scene_dict

    d = scene_dict(load_under_law(args))
    print(json.dumps(d, indent=2) if args.json else "\n".join(_lines(d)))
    return 0
