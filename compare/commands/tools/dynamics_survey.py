"""Check `dynamics` on custom_sim over every built-in and stress scene, with semi-implicit Euler and RK4.

    python -m compare tools dynamics-survey [SCENE ...]

custom_sim against the dynamics twin on each scene (default: every built-in and stress scene),
both of MuJoCo's integrators that custom_sim shares: one Markdown row each, with the difference,
the tolerance, the bound used (round-off or sensitivity), the time judged up to and the friction
step number. Exit status 1 when a row fails. About 4 minutes for every scene.
"""
from __future__ import annotations


def add_arguments(parser) -> None:
    parser.add_argument("scenes", nargs="*", metavar="SCENE", help="default: every built-in and stress scene")


def main(args) -> int:
    from ...checks.dynamics_check import print_survey

    return print_survey(args.scenes)
