"""Measure what separates custom_sim from MuJoCo's native contact: check `contact` and the attribution ladder.

For each scene: check `contact` (MuJoCo's own contact with the penalty mapping, friction off,
the linear damping law, held to the mapping's measured force error and the motion's
sensitivity to it), then the ladder of runs from MuJoCo's native contact with every effect on
to custom_sim, each rung removing one cause (friction law, contact point, mapping, integrator,
damping law), with each cause's measured share. Prints Markdown tables; --json writes every
row. Exit status 1 when a scene fails check `contact`.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

from ..scenarios import builtin_paths, load_all
from ..table import markdown, number


def add_arguments(parser) -> None:
    parser.add_argument("scenes", nargs="*", metavar="SCENE",
                        help="built-in name or path to a .toml (default: every built-in scene)")
    parser.add_argument("--stress", action="store_true", help="add every stress scene (scenarios/stress/)")
    parser.add_argument("--json", metavar="FILE", help="write the rows as JSON")


RUNGS = ("friction law", "contact point", "mapping", "integrator", "damping law")


def contact_table(results: list[tuple]) -> list[str]:
    rows = []
    for scene, check, _ in results:
        verdict = "not judged: " + check.reason.removeprefix("not judged: ") if check.passed is None else (
            "pass" if check.passed else "**FAIL**")
        d = check.details
        err = d.get("mapping_error", {}).get("relative_force_error")
        rows.append([scene.name, f"{number(check.position_error_max)}, {number(check.angle_error_max)}",
                     f"{number(check.tolerance_position)}, {number(check.tolerance_angle)}",
                     f"{number(d.get('judged_until'))} of {number(d.get('duration'))}",
                     number(d.get("motion_position")), number(err), verdict])
    return markdown(["scene", "contact: difference (m, rad)", "tolerance (m, rad)", "judged until (s)", "motion (m)",
                     "mapping error", "verdict"], rows).splitlines()


def ladder_table(results: list[tuple]) -> list[str]:
    rows = []
    for scene, _, ladder in results:
        cells = {r["name"].replace(" and shared cone", ""): r for r in ladder}
        native = cells["native"]
        row = [scene.name, f"{number(native['position_error_max'])}, {number(native['angle_error_max'])}"]
        for name in RUNGS:
            r = cells.get(name)
            if r is None:
                row.append("")
            elif not r["measured"]:
                row.append(r["note"])
            else:
                row.append(f"{number(r['share_position'])} ({number(r['step_position'])} alone)")
        rows.append(row)
    return markdown(["scene", "native (m, rad)", *RUNGS], rows).splitlines()


def main(args) -> int:
    from ..checks.attribution import attribute
    from ..checks.contact_check import check_contact

    specs = list(args.scenes) or [str(p) for p in builtin_paths()]
    if args.stress:
        specs += [str(p) for p in builtin_paths("stress")]
    scenes = load_all(specs)
    results = []
    for scene in scenes:
        print(f"{scene.name} ...", file=sys.stderr, flush=True)
        results.append((scene, check_contact(scene), attribute(scene)))
    print("## Check contact\n")
    print("\n".join(contact_table(results)))
    print("\n## Attribution: each cause's share of the difference (m), and the difference it makes alone\n")
    print("\n".join(ladder_table(results)))
    if args.json:
        Path(args.json).write_text(json.dumps(
            [{"name": s.name, "contact": c.to_json(), "attribution": a} for s, c, a in results], indent=2,
            allow_nan=False) + "\n")
    return 1 if any(c.passed is False for _, c, _ in results) else 0
