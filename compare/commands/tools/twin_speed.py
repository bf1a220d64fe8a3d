"""What the dynamics twin's contact law costs: ns per mj_step, measured in one run.

    python -m compare tools twin-speed [SCENE ...]     (default: every built-in scene)

For each scene and MuJoCo integrator (Euler, RK4), the CPU time per step of whole-run rollouts
(the fastest of 3, after a warm-up) of

    native     the native twin: MuJoCo's own contact pairs and solver
    dynamics   the dynamics twin: no pairs, the seed's law in the compiled passive callback
    bare       the dynamics twin's model with no callback installed (MuJoCo's step alone: the
               difference to `dynamics` is what the callback costs)
"""
from __future__ import annotations


def add_arguments(parser) -> None:
    parser.add_argument("scenes", nargs="*", metavar="SCENE", help="default: every built-in scene")


def main(args) -> int:
    from ...tools.accuracy.twin_speed import print_table

    return print_table(args.scenes)
