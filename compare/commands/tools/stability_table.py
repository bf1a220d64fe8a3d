"""Theory against measured: the largest stable step of every scene and integrator.

    python -m compare tools stability-table [SCENE ...] [--jobs N] [--integrator NAME]
                                            [--out FILE] [--json FILE] [--measured FILE]

For each built-in and stress scene (or the named ones) and each of custom_sim's integrators:
the limit of each effect by custom_sim/stability.py (`limits`), the smallest of them, and the
largest step the search of compare/tools/accuracy/stability_search.py measures (stable = no
blow-up, no chatter by custom_sim/chatter.py, no energy growth), with the criterion that fired
just above it. The theory should be within a factor 2 of the measured step and never above it;
a row where it is not says why. Prints a Markdown table (and writes it to FILE). Exit status 1
when a row is optimistic and unexplained.
"""
from __future__ import annotations


def add_arguments(parser) -> None:
    from custom_sim import INTEGRATORS

    parser.add_argument("scenes", nargs="*", metavar="SCENE")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", metavar="FILE", help="also write the table here")
    parser.add_argument("--integrator", action="append", choices=list(INTEGRATORS))
    parser.add_argument("--json", metavar="FILE", help="also write the rows as JSON")
    parser.add_argument("--measured", metavar="FILE", help="take the measured limits from an earlier --json "
                        "(they do not depend on the scene's dt) and recompute only the theory")


def main(args) -> int:
    from ...tools.accuracy.stability_table import print_table

    return print_table(args.scenes, args.jobs, args.out, args.integrator, args.json, args.measured)
