"""cheapest.md, the table the README shows: one row per scene, each simulator's cheapest way to
1 mm with its CPU time (s), stamped with the machine (CPU, cores, load, versions, date in UTC).
"""
from __future__ import annotations

import os
from pathlib import Path

from ...table import DASH, markdown
from ..accuracy.workprecision import ranking
from .wording import name, timing


def machine() -> str:
    """The machine a table was measured on: CPU model, cores, load, versions, date (UTC)."""
    import datetime
    import platform

    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        load = "load average " + " ".join(f"{x:.1f}" for x in os.getloadavg()) + " (1, 5, 15 min)"
    except OSError:
        load = "load unknown"
    versions = []
    for module in ("numba", "mujoco"):
        try:
            versions.append(f"{module} {__import__(module).__version__}")
        except ImportError:
            pass
    when = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    return (f"{cpu}, {os.cpu_count()} cores, {load}; {platform.system()} {platform.release()}, "
            f"Python {platform.python_version()}, {', '.join(versions)}; {when}")


def cheapest_table(results, command: str = "python -m compare sweep") -> str:
    """The README's table: for each scene, the fewest force evaluations that reach 1 mm in each
    simulator, with the CPU time and its spread beside them, and the machine it was measured on."""
    def cell(run, self_error=False):
        if run is None:
            return "not within 1 mm on the ladder", DASH
        return (f"{name(run)}, dt {run.dt:g} s: {run.force_evals} force evaluations",
                timing(run))

    rows = []
    for sweep in results:
        ours = ranking([r for r in sweep.runs if r.simulator == "custom"])
        theirs = ranking([r for r in sweep.runs if r.simulator == "mujoco"], self_error=True)
        a, at = cell(ours[0] if ours else None)
        b, bt = cell(theirs[0] if theirs else None) if any(r.simulator == "mujoco" for r in sweep.runs) else ("not run", DASH)
        rows.append([sweep.scene.name, a, at, b, bt])
    lines = [f"Measured by `{command}` on {machine()}.", "",
             *markdown(["scene", "custom_sim: fewest force evaluations to 1 mm", "CPU time (spread)",
                        "MuJoCo: fewest to 1 mm of its own converged solution", "CPU time (spread)"], rows).splitlines(),
             "", "Ranked by force evaluations (counted, so a rerun gives the same answer), then steps; "
              "the CPU time is the minimum over repeats, and the spread how far the repeats differed. "
              "Force evaluations compare runs of one simulator; between the two, only the times do, and "
              "only where they differ by more than their spread."]
    return "\n".join(lines)
