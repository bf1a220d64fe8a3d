"""What the harness adds per step to a user's Python step function, measured in one run.

    python -m compare tools overhead [MODULE:FUNCTION] [--sim-process COMMAND] [--scene NAME] [--steps N]

Times, interleaved and the minimum of repeats kept, (1) a bare loop calling a no-op step
`step(state, scene, dt) -> state` n times, (2) the harness's own loop around the same no-op step
(the whole run: scene dict, checks, loop), for a step returning a numpy array and one returning
a list; their difference is the harness's cost per step. Then the given step function (default:
the worked example, examples/seed_sim.py:step) on the scene: ns per step and the whole run's
wall time. Beside it, a step's round trip through a process (--sim-process): a no-op process
in C, then COMMAND (default: examples/process/step.c, built with cc). Exit status 1 when the
harness adds more than 2 us per step, or the no-op process's round trip takes more than 20 us.
"""
from __future__ import annotations


def add_arguments(parser) -> None:
    parser.add_argument("sim", nargs="?", default=None, metavar="MODULE:FUNCTION",
                        help="the step function timed last (default: examples/seed_sim.py:step)")
    parser.add_argument("--sim-process", metavar="COMMAND",
                        help="the process timed last (default: examples/process/step.c, built with cc)")
    parser.add_argument("--scene", default="box_drop")
    parser.add_argument("--steps", type=int, default=20_000)


def main(args) -> int:
    from ...usersim.overhead import print_overhead

    return print_overhead(args.sim, args.scene, args.steps, args.sim_process)
