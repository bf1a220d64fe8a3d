"""Print a scene resolved: every default filled in, and its derived mass properties.

SCENE is a built-in name or a path to a .toml scene file. With --json it prints the one JSON
object a simulator under test is given as `scene` (see `run --sim`), so that a simulator in
another language can read it: mass_properties holds the mass (kg), the inertia about the
centre of mass (kg m^2) and the contact points relative to the centre of mass in the body
frame (m); state0 is [x, y, theta, vx, vy, omega] at t = 0; steps = duration / dt.
"""
from __future__ import annotations

import json


def add_arguments(parser) -> None:
    parser.add_argument("scene", metavar="SCENE", help="a built-in scenario name or a path to a .toml scene")
    parser.add_argument("--json", action="store_true", help="print one JSON object (what --sim's step function gets)")


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
    from ..scenarios import load
    from ..usersim.scene_dict import scene_dict

    d = scene_dict(load(args.scene))  # a bad scene: compare.cli reports it, exit 2
    print(json.dumps(d, indent=2) if args.json else "\n".join(_lines(d)))
    return 0
