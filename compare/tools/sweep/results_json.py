"""results.json: the sweep as numbers, per scene its reference, MuJoCo's converged solution, every
run (m, rad, s, J), every stability limit (s) and each integrator's fitted order, with the answer in
words beside them (and, with --sim, what it says of the user's code: "yours")."""
from __future__ import annotations

import dataclasses
from pathlib import Path

from ...files import finite_json
from ..accuracy.orders import orders
from .answer import answer
from .yours import yours_lines


def write_json(results, path: Path, runtime: float, jobs: int) -> None:
    """Every scene of results, the sweep's runtime (s) and worker count; states are left out."""
    doc = {"runtime_s": runtime, "jobs": jobs, "scenes": []}
    for sweep in results:
        ref = {k: v for k, v in sweep.reference.items() if k != "states"}
        conv = {k: v for k, v in sweep.mujoco_converged.items() if k != "states"}
        doc["scenes"].append({
            "name": sweep.scene.name, "reference": ref, "mujoco_converged": conv,
            "cheapest_to_1mm": answer(sweep),
            "runs": [r.as_dict() for r in sweep.runs],
            "stability": [dataclasses.asdict(lim) for lim in sweep.stability],
            "orders": orders(sweep),
            **({"yours": {**sweep.yours, "lines": yours_lines(sweep)}} if sweep.yours else {}),
        })
    path.write_text(finite_json(doc, indent=1))
