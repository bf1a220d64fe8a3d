"""How far each solref mapping's twin lands from the hand-written simulator, per scene.

    python -m compare tools mapping-table [SCENE ...]     (default: every built-in scene)

Prints, for each scene, the maximum distance (m) between the COM of custom_sim's run and of the
native MuJoCo twin's under each of the three solref mappings (penalty, physical, seed); the same
for the penalty twin against custom_sim's run with damping_law = "linear" (MuJoCo's own law:
what is left is the friction law and the mapping); and MuJoCo's CPU time per mj_step (ns, the
fastest of 3 rollouts).
"""
from __future__ import annotations


def add_arguments(parser) -> None:
    parser.add_argument("scenes", nargs="*", metavar="SCENE", help="default: every built-in scene")


def main(args) -> int:
    from ...tools.accuracy.mapping_table import print_table

    return print_table(args.scenes)
