"""The seed's claims about its integrators, measured: R(end) of custom_sim's run of every built-in
scene with each integrator at the scene's dt (the energy the numerics made or lost).

    python -m compare tools energy-table      prints the markdown table the README shows
"""
from __future__ import annotations

import dataclasses

from custom_sim import INTEGRATORS, SimulationDiverged, simulate

from ..scenarios import builtin_names, load
from ..table import markdown as markdown_table
from .balance import balance


def residuals(scene) -> dict:
    """{integrator: (R(end), max |R|) J, or the reason it has none}."""
    out = {}
    for name in INTEGRATORS:
        variant = dataclasses.replace(scene, integrator=name)
        try:
            run = simulate(variant)
        except SimulationDiverged as exc:
            out[name] = "unstable" if "chatter" not in str(exc).lower() else "chatters"
            continue
        r = balance(variant, run.t, run.states(), name).R
        out[name] = (float(r[-1]), float(abs(r).max()))
    return out


def markdown() -> str:
    rows = []
    for name in builtin_names():
        scene = load(name)
        cells = [v if isinstance(v, str) else f"{v[0]:+.2g}" for v in residuals(scene).values()]
        rows.append([name, f"{scene.dt:g}", *cells])
    return markdown_table(["scene", "dt (s)", *INTEGRATORS], rows)
