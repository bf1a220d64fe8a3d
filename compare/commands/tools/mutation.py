"""Mutation test of the harness: each typical mistake put into a copy of custom_sim must make `run` exit 1.

    python -m compare tools mutation [NAME ...] [--jobs N] [--out DIR] [--scenes SCENE ...]

Each entry of compare/tools/mutation/catalogue.py is a typical mistake, one text edit of
custom_sim's source. For each one the tool puts it into a copy of custom_sim and runs
`python -m compare run` on that copy; the mistake counts as caught when `run` exits 1 with a
judged check failing (or the run unstable) on at least one scene, and the report names the
check that caught it. Writes DIR/index.md (default reports/mutation) and DIR/mutation.json; exit
status 0 when every mistake was caught, 1 when one was not, 2 for an unknown NAME. Each mistake
costs a numba compile of the copy (its sources differ) and one full `run`. The CI runs it on
every change.
"""
from __future__ import annotations

import os


def add_arguments(parser) -> None:
    parser.add_argument("names", nargs="*", metavar="NAME", help="mistakes to try (default: all)")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="mutants run at once")
    parser.add_argument("--out", default="reports/mutation", metavar="DIR")
    parser.add_argument("--scenes", nargs="*", default=[], metavar="SCENE", help="scenes to run (default: the built-ins)")


def main(args) -> int:
    from ...tools.mutation.mutants import run_all

    return run_all(args.names, args.jobs, args.out, args.scenes)
