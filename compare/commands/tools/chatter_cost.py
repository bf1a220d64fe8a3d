"""What watching for chatter costs: ns per step with and without the tracker, in one run.

    python -m compare tools chatter-cost [SCENE ...]     (default: the built-in scenes)

Each scene runs its full duration with its integrator and dt in custom_sim's compiled loop,
recording nothing, twice per round: with the chatter tracker (custom_sim's default) and without
it. The rounds (5, after a warm-up) alternate the two, and each keeps its minimum CPU time of
the stepping thread, so load from other processes falls on neither side alone.
"""
from __future__ import annotations


def add_arguments(parser) -> None:
    parser.add_argument("scenes", nargs="*", metavar="SCENE", help="default: the built-in scenes")


def main(args) -> int:
    from ...tools.accuracy.chatter_cost import print_table

    return print_table(args.scenes)
