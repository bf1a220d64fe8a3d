"""Check `step` on custom_sim over every built-in and stress scene, all four integrators, full length.

    python -m compare tools step-survey [--window STEPS] [SCENE ...]   (compare/commands/tools/step_survey.py)

Prints one row per scene and integrator: steps, the largest residual against its round-off bound,
the check's verdict, and where it first fails. Exit status 1 when any step fails. custom_sim's
implicit Euler lands on the jump's point where its equation has no root (custom_sim/filippov.py),
so a touchdown is no excuse; a failure where custom_sim also counts unconverged Newton solves says
so in its verdict.
"""
from __future__ import annotations

import dataclasses
import time

from custom_sim import SimulationDiverged, simulate

from compare.scenarios import load, load_builtins

from ..oracle.one_step import METHODS
from ..checks.step_check import check_step
from ..table import stream


def survey(scenes, window: int | None = None):
    rows = []
    for scene in scenes:
        for method in METHODS:
            sc = dataclasses.replace(scene, integrator=method)
            if window:
                sc = dataclasses.replace(sc, duration=min(sc.duration, window * sc.dt))
            try:
                traj = simulate(sc)
            except SimulationDiverged as exc:
                rows.append({"scene": scene.name, "integrator": method, "diverged": exc.step})
                continue
            start = time.perf_counter()
            row = check_step(sc, traj.states(), method, sc.dt)
            rows.append({"scene": scene.name, "integrator": method, "steps": traj.steps,
                         "seconds": time.perf_counter() - start, "row": row,
                         "unconverged": traj.meta.get("newton_unconverged_steps", 0)})
    return rows


def print_survey(names: list[str], window: int | None = None) -> int:
    """The survey of the named scenes (default: every built-in and stress scene) as a Markdown
    table; 1 when a step fails, else 0."""
    scenes = [load(s) for s in names] or load_builtins() + load_builtins("stress")
    bad = 0

    def rows():
        nonlocal bad
        for r in survey(scenes, window):
            if "diverged" in r:
                yield [r["scene"], r["integrator"], "", "", "", f"diverged at step {r['diverged']}", ""]
                continue
            row = r["row"]
            where = ""
            if not row.passed:
                d = row.details
                where = f"{d['first_step']} ({d['component']}; {d['phase']})"
                bad += 1
                verdict = "FAIL"
                if r["unconverged"]:
                    verdict += f" (custom_sim's Newton unconverged on {r['unconverged']} step(s))"
            else:
                verdict = "pass"
            yield [r["scene"], r["integrator"], str(r["steps"]), f"{r['seconds']:.2f}",
                   f"{row.details['bound_ratio_max']:.3g}", verdict, where]
    stream(["scene", "integrator", "steps", "check s", "largest residual / bound", "verdict", "first failing step"],
           rows())
    return 1 if bad else 0
