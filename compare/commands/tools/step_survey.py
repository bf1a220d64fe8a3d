"""Check `step` on custom_sim over every built-in and stress scene, all four integrators, full length.

    python -m compare tools step-survey [--window STEPS] [SCENE ...]

Prints one row per scene and integrator: steps, the largest residual against its round-off bound,
the check's verdict, and where it first fails. Exit status 1 when any step fails. custom_sim's
implicit Euler lands on the jump's point where its equation has no root (custom_sim/filippov.py),
so a touchdown is no excuse; a failure where custom_sim also counts unconverged Newton solves says
so in its verdict. The CI runs it on every change.
"""
from __future__ import annotations


def add_arguments(parser) -> None:
    parser.add_argument("scenes", nargs="*", help="scene names (default: every built-in and stress scene)")
    parser.add_argument("--window", type=int, default=None, help="check only the first STEPS steps")


def main(args) -> int:
    from ...tools.step_survey import print_survey

    return print_survey(args.scenes, args.window)
