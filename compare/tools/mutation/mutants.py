"""Mutation test of the harness: each typical mistake put into a copy of custom_sim must make
`python -m compare run` exit 1, and the report must name the check that caught it.

    python -m compare tools mutation [NAME ...] [--jobs N] [--out DIR]   (compare/commands/tools/mutation.py)

Writes DIR/index.md (default reports/mutation) and DIR/mutation.json; exit status 0 when every
mistake was caught, 1 when one was not. Each mistake costs a numba compile of the copy (its
sources differ) and one full `run`.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from ...files import finite_json
from ...table import DASH, markdown
from .catalogue import MISTAKES, Mistake

ROOT = Path(__file__).resolve().parents[3]
RUN_TIMEOUT = 1200  # s: a compile and a full run take about a minute on 2 cores


def mutated_copy(mistake: Mistake, folder: Path) -> Path:
    """folder/custom_sim: custom_sim with the mistake put in (every occurrence of the text)."""
    target = folder / "custom_sim"
    shutil.copytree(ROOT / "custom_sim", target, ignore=shutil.ignore_patterns("__pycache__"))
    path = target / mistake.file
    text = path.read_text()
    if mistake.old not in text:
        raise ValueError(f"{mistake.name}: the text to change is not in custom_sim/{mistake.file} any more")
    path.write_text(text.replace(mistake.old, mistake.new))
    return target


def run_mutant(mistake: Mistake, scenes: list[str]) -> dict:
    """Run the default comparison on a mutated custom_sim; which checks failed, per scene."""
    with tempfile.TemporaryDirectory(prefix=f"mutant_{mistake.name}_") as tmp:
        folder = Path(tmp)
        mutated_copy(mistake, folder)
        out = folder / "report"
        # cwd first on sys.path: the mutated custom_sim; compare and mujoco_models from the repository
        env = {**os.environ, "PYTHONPATH": str(ROOT), "NUMBA_CACHE_DIR": str(folder / "numba"),
               "CONTACT_HARNESS_CACHE": "off"}   # every mutant computed: nothing of the original's reused
        start = time.perf_counter()
        proc = subprocess.run([sys.executable, "-m", "compare", "run", *scenes, "--out", str(out), "--jobs", "1"],
                              cwd=folder, env=env, capture_output=True, text=True, timeout=RUN_TIMEOUT)
        caught, errors = {}, {}
        for metrics in sorted(out.glob("*/metrics.json")):
            data = json.loads(metrics.read_text())
            if data["failed_checks"]:
                caught[data["name"]] = data["failed_checks"]
        for line in proc.stdout.splitlines():
            name, _, rest = line.partition(" ")
            status, _, why = rest.strip().partition(": ")
            if status == "unstable":  # the stability check: a divergence or chatter, with its step
                caught[name] = ["unstable"]
            elif status == "error":   # the harness could not judge: not a catch
                errors[name] = why[:160]
        return {"name": mistake.name, "what": mistake.what, "seed_line": mistake.seed_line,
                "exit": proc.returncode, "caught": proc.returncode == 1 and bool(caught),
                "by": caught, "errors": errors, "seconds": round(time.perf_counter() - start, 1),
                "stderr": proc.stderr.strip().splitlines()[-1:] if proc.returncode not in (0, 1) else []}


def checks_named(by: dict) -> list[str]:
    """The checks that caught a mistake, over every scene, without repeats."""
    seen = []
    for names in by.values():
        for n in names:
            key = n.split(":")[0]
            if key not in seen:
                seen.append(key)
    return seen


def index_page(results: list[dict]) -> str:
    caught = sum(r["caught"] for r in results)
    lines = ["# Mutation test: does the verdict catch typical mistakes?", "",
             f"{caught} of {len(results)} mistakes made `python -m compare run` exit 1.", "",
             "A mistake counts as caught when a judged check fails (or the run is unstable) on at least one "
             "scene; a scenario the harness could not judge (an error row) does not count.", "",
             *markdown(["mistake", "where (seed)", "exit", "caught by", "scenes that failed", "errors"],
                       [[f"**{r['name']}**: {r['what']}", r["seed_line"], str(r["exit"]),
                         ", ".join(checks_named(r["by"])) or "**not caught**", ", ".join(r["by"]) or DASH,
                         "; ".join(f"{k}: {v}" for k, v in r["errors"].items()) or DASH]
                        for r in results]).splitlines()]
    return "\n".join(lines) + "\n"


def run_all(names: list[str], jobs: int, out: str, scenes: list[str]) -> int:
    """Try the named mistakes (default: all), `jobs` at once, on the scenes (default: the
    built-ins); writes out/index.md and out/mutation.json. The exit status: 0 every mistake
    caught, 1 one not, 2 an unknown name."""
    known = {m.name: m for m in MISTAKES}
    unknown = [n for n in names if n not in known]
    if unknown:
        print(f"error: unknown mistake {', '.join(unknown)} (expected one of: {', '.join(known)})", file=sys.stderr)
        return 2
    chosen = [known[n] for n in names] or list(MISTAKES)
    from ...executor import Task, make_executor

    with make_executor("processes", workers=max(1, jobs)) as executor:   # each mutant waits on its own `run`
        done = executor.run(run_mutant, [Task(m.name, (m, scenes)) for m in chosen], desc="mutants",
                            progress=False, retry=False)
    results = [done[m.name] for m in chosen]
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "mutation.json").write_text(finite_json(results, indent=2) + "\n")
    (out / "index.md").write_text(index_page(results))
    for r in results:
        verdict = "caught by " + ", ".join(checks_named(r["by"])) if r["caught"] else "NOT CAUGHT"
        print(f"{r['name']:<30} exit {r['exit']}  {verdict}  ({r['seconds']} s)")
    print(f"report: {out / 'index.md'}")
    return 0 if all(r["caught"] for r in results) else 1
