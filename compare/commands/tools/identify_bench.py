"""Time `identify` per scene for a step function: the designed calls and the fits, best of a few.

    python -m compare tools identify-bench [MODULE:FUNCTION] [SCENE ...] [--repeat N]

Default: examples/seed_sim.py:step (plain numpy) on every built-in scene. Prints, per scene, the
calls made, the fastest and the median wall time of N runs (each from a fresh import), and the
time the step function itself took (the rest is the identification's own work). Exit status 1
when the slowest scene takes longer than its budget (5 s).
"""
from __future__ import annotations


def add_arguments(parser) -> None:
    parser.add_argument("sim", nargs="?", default="examples/seed_sim.py:step", metavar="MODULE:FUNCTION")
    parser.add_argument("scenes", nargs="*", metavar="SCENE")
    parser.add_argument("--repeat", type=int, default=3)


def main(args) -> int:
    from ...identify.benchmark import print_times

    return print_times(args.sim, args.scenes, args.repeat)
