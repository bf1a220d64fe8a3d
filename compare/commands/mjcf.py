"""Print (or write with -o) the MJCF of a scene's MuJoCo twin.

The file loads with mujoco.MjModel.from_xml_path and in MuJoCo's viewer (python -m
mujoco.viewer --mjcf FILE); keyframe 'initial' holds the scene's start. SCENE is a built-in
name or a path to a .toml scene file.
"""
from __future__ import annotations

import sys
from pathlib import Path

EXIT_OK, EXIT_BAD_INPUT = 0, 2


def add_arguments(parser) -> None:
    parser.add_argument("scene", metavar="SCENE", help="a built-in scenario name or a path to a .toml scene")
    parser.add_argument("-o", "--output", metavar="FILE", help="write the MJCF to FILE instead of printing it")
    parser.add_argument("--solref", choices=("penalty", "physical", "seed"),
                        help="solref mapping (default: the scene's [mujoco] solref)")


def main(args) -> int:
    from compare.scenarios import load

    scene = load(args.scene)  # a bad scene: compare.cli reports it, exit 2

    from mujoco_models import to_mjcf  # mujoco loads only when there is a model to build

    xml = to_mjcf(scene, args.solref)
    if args.output is None:
        sys.stdout.write(xml)
        return EXIT_OK
    out = Path(args.output)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(xml, encoding="utf-8")
    except OSError as exc:
        print(f"error: {out}: cannot write ({exc.strerror or exc})", file=sys.stderr)
        return EXIT_BAD_INPUT
    print(f"wrote {out}")
    return EXIT_OK
