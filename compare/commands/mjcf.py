"""Print (or write with -o) the MJCF of a scene's MuJoCo twin.

The file loads with mujoco.MjModel.from_xml_path and in MuJoCo's viewer (python -m
mujoco.viewer --mjcf FILE); keyframe 'initial' holds the scene's start. SCENE is a built-in
name or a path to a .toml scene file. With --law FILE.toml (or `identified` with --sim) the
twin of the scene under that law, as `run --law` builds it: the law's nearest MuJoCo mapping,
with a comment per effect naming what MuJoCo cannot express of it.
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
    from .scene import add_law_arguments
    add_law_arguments(parser)


def main(args) -> int:
    from .scene import load_under_law

    scene = load_under_law(args)  # a bad scene or law: compare.cli reports it, exit 2

    from mujoco_models import to_mjcf  # mujoco loads only when there is a model to build

    xml = to_mjcf(scene, args.solref)
    if args.law is not None:
        xml = with_law_comments(xml, scene, args.solref or scene.mujoco.solref)
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


OWN, LAWS = "the scene's '", "the law's '"   # the notes name a scene's own law; here it is --law's


def with_law_comments(xml: str, scene, mapping: str) -> str:
    """The MJCF with comments after its opening one: the law it was built under (where from,
    each effect's family and parameters) and, per effect, what MuJoCo cannot express of it
    (mujoco_models.approximations: the same sentences as a report's twin)."""
    from mujoco_models.approximations import damping_note, friction_law_notes, roll_law_notes
    from scene_types.laws import law_text

    where = ("the law identify found in the simulator" if scene.law_from == "identified"
             else f"the law of {scene.law_from}, laid over the scene's [contact]")
    notes = [f"contact law: {where}: {law_text(scene.contact)}"]
    if scene.has("contact"):
        notes += damping_note(scene, mapping) + friction_law_notes(scene) + roll_law_notes(scene)
    else:
        notes.append("the scene lists no contact: no law is used")
    comments = "".join(f"  <!-- {_comment_text(n.replace(OWN, LAWS))} -->\n" for n in notes)
    head, sep, rest = xml.partition("-->\n")   # after the opening comment (spec.py's header)
    return head + sep + comments + rest if sep else comments + xml


def _comment_text(text: str) -> str:
    """Text an XML comment may hold (no "--")."""
    while "--" in text:
        text = text.replace("--", "- -")
    return text
