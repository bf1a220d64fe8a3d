"""Time `identify` per scene for a step function: the designed calls and the fits, best of a few.

    python -m compare tools identify-bench [MODULE:FUNCTION] [SCENE ...] [--repeat N]

Default: examples/seed_sim.py:step (plain numpy) on every built-in scene. Prints, per scene, the
calls made, the fastest and the median wall time of N runs (each from a fresh import), and the
time the step function itself took (the rest is the identification's own work), every call held
to at least --step-us (30 us: a step in plain Python); then the regression route on a 40 000-step
CSV no family fits. Exit status 1 when the slowest scene takes longer than 2 s or the CSV 3 s.
"""
from __future__ import annotations


def add_arguments(parser) -> None:
    parser.add_argument("sim", nargs="?", default="examples/seed_sim.py:step", metavar="MODULE:FUNCTION")
    parser.add_argument("scenes", nargs="*", metavar="SCENE")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--step-us", type=float, default=30.0, metavar="US",
                        help="hold every call of the step to at least US microseconds (default 30: a step in "
                             "plain Python; 0: the step's own time)")


def main(args) -> int:
    from ...identification.benchmark import print_times

    return print_times(args.sim, args.scenes, args.repeat, args.step_us)
