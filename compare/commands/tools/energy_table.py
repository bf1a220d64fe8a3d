"""The seed's claims about its integrators, measured: R(end) of every built-in scene with each integrator.

    python -m compare tools energy-table

Prints the Markdown table the README shows: R(end) in J, the energy the numerics made or lost,
of custom_sim's run of every built-in scene with each integrator at the scene's dt ("unstable"
or "chatters" where the run stops). docs/energy-balance.md defines R.
"""
from __future__ import annotations


def add_arguments(parser) -> None:
    pass


def main(args) -> int:
    from ...energy.table import markdown

    print(markdown())
    return 0
