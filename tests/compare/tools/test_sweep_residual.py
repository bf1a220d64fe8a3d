"""The sweep's table of the energy residual R(end) (compare/tools/sweep/residual.py): the order it
falls at with dt, and the contact events named where they lower it."""
from __future__ import annotations

import dataclasses

import numpy as np
from markdown_table import rows as table_rows

from compare.oracle.reference import solve_reference
from compare.scenarios import load
from compare.tools.accuracy.workprecision import Run, SceneSweep, custom_residual
from compare.tools.sweep.residual import residual_rows


def test_the_sweep_names_the_contact_events_that_lower_rk4s_order():
    """RK4's R(end) on box_drop falls at about second order (a step across a touchdown integrates
    the force's jump): the sweep's table says so, naming the reference's switches; box_slide's,
    with no touchdown, keeps its fourth order and no note."""
    for name, lowered in (("box_drop", True), ("box_slide", False)):
        scene = dataclasses.replace(load(name), duration=0.5 if name == "box_drop" else 1.0)
        runs = []
        for dt in (4e-4, 2e-4, 1e-4, 5e-5):
            run = Run("custom", "rk4", dt, int(round(scene.duration / dt)))
            run.residual_end, run.residual_max = custom_residual(scene, "rk4", dt)
            runs.append(run)
        switches = solve_reference(scene, np.linspace(0.0, scene.duration, 11)).switches
        sweep = SceneSweep(scene, {"switches": switches, "energy_scale": 1.0}, runs, {})
        row = next(r for r in table_rows("\n".join(residual_rows(sweep))) if r[:2] == ["ours", "rk4"])
        note = row[-1]
        assert ("lowered by the contact events" in note) == lowered, row
        if lowered:
            named = ", ".join(f"{v} {k}" for k, v in switches.items() if v)
            assert switches["touch"] > 0 and f"({named} switches of the reference)" in note, row
