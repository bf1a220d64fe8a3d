"""DIR/sweep/, written whole: each scene's figure, results.json, index.md and cheapest.md go into
a hidden folder beside it, which then replaces the old one; a failure leaves the old one as it
was. `runtime` (s) and `jobs` describe the sweep that measured the results.
"""
from __future__ import annotations

import os
import shutil
from pathlib import Path

from ...files import temporary_folder
from .cheapest import cheapest_table
from .figure import plot_scene
from .page import write_index
from .results_json import write_json


def write_report(results, out: Path, runtime: float, jobs: int, command: str) -> Path:
    """Writes out/sweep/ from results and returns it; `command` is the command line cheapest.md names."""
    folder = out / "sweep"
    out.mkdir(parents=True, exist_ok=True)
    tmp = temporary_folder(out, ".sweep.")
    try:
        for sweep in results:
            plot_scene(sweep, tmp / f"{sweep.scene.name}_workprecision.png")
        write_json(results, tmp / "results.json", runtime, jobs)
        write_index(results, tmp / "index.md", runtime, jobs)
        (tmp / "cheapest.md").write_text(cheapest_table(results, command) + "\n")
        if folder.exists():
            shutil.rmtree(folder)
        os.replace(tmp, folder)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return folder
