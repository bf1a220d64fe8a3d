"""The seed's claims about its integrators, measured: R(end) of custom_sim's run of every built-in
scene with each integrator at the scene's dt (the energy the numerics made or lost).

    python -m compare tools energy-table      prints the markdown table the README shows
"""
from __future__ import annotations

import dataclasses

from custom_sim import INTEGRATORS, SimulationDiverged, simulate

from ..scenarios import builtin_names, load
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
    lines = ["| scene | dt (s) | " + " | ".join(INTEGRATORS) + " |", "|---|---|" + "---|" * len(INTEGRATORS)]
    for name in builtin_names():
        scene = load(name)
        cells = [v if isinstance(v, str) else f"{v[0]:+.2g}" for v in residuals(scene).values()]
        lines.append(f"| {name} | {scene.dt:g} | " + " | ".join(cells) + " |")
    return "\n".join(lines)
