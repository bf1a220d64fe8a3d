"""Run scenarios in both simulators and write the comparison report.

SCENE is a built-in name (see `list`) or a path to a scene file; without SCENE every
built-in scenario runs. Writes DIR/index.md and DIR/<name>/ (metrics.json, trajectory
CSVs, model.xml, plots). Exit status: 0 all within tolerance, 1 one outside it (or
diverged: no report is written for that scenario), 2 bad input (nothing is written).
"""
from __future__ import annotations

import os
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from custom_sim import warm_up

from ..cli import output_folder
from ..scenarios import load_all


def add_arguments(parser) -> None:
    parser.add_argument("scenes", nargs="*", metavar="SCENE", help="built-in name or path to a .toml (default: all built-ins)")
    parser.add_argument("--out", default="reports", metavar="DIR", help="output folder (default: reports/)")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="scenarios run at once (default: every core)")


def run_one(scene, out: str):
    """Worker: run, compare and write one scenario; returns (row or None, divergence message)."""
    from ..verdict.comparison import run_scenario
    from ..report import write_scenario

    result = run_scenario(scene)
    if result.error:
        return None, result.error
    from mujoco_models import to_mjcf

    return write_scenario(result, Path(out), to_mjcf(scene)), None


def main(args) -> int:
    scenes = load_all(args.scenes)
    warm_up()  # compile once here, before the workers start (they inherit it or load the cache)
    out = output_folder(args.out)
    out.mkdir(parents=True, exist_ok=True)

    from tqdm import tqdm

    from ..report import write_index

    rows, failures = {}, []
    jobs = max(1, min(args.jobs, len(scenes)))
    with ProcessPoolExecutor(jobs) as pool:
        futures = {pool.submit(run_one, s, str(out)): s.name for s in scenes}
        for future in tqdm(futures, desc="scenarios", unit="scene", delay=2, file=sys.stderr):
            name = futures[future]
            row, error = future.result()
            if row is None:
                failures.append((name, error))
                print(f"error: {error}", file=sys.stderr)
            else:
                rows[name] = row
    ordered = [rows[s.name] for s in scenes if s.name in rows]
    index = write_index(out, ordered, failures)
    for r in ordered:
        verdict = "pass" if r["pass"] else "FAIL"
        print(f"{r['name']:<20} {verdict:<5} position {r['position_error_max']:.3e} m "
              f"(tolerance {r['tolerance']['position']:.3e} m), angle {r['angle_error_max']:.3e} rad")
    for name, _ in failures:
        print(f"{name:<20} diverged: no report written")
    print(f"report: {index}")
    return 0 if not failures and all(r["pass"] for r in ordered) else 1
