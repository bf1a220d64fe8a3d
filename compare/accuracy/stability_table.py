"""Theory against measured: the largest stable step of every scene and integrator.

    python -m compare.accuracy.stability_table [SCENE ...] [--jobs N] [--out FILE]

For each built-in and stress scene (or the named ones) and each of custom_sim's integrators:
the limit of each effect by custom_sim/stability.py (`limits`), the smallest of them, and the
largest step the search of stability_search.py measures (stable = no blow-up, no chatter by
custom_sim/chatter.py, no energy growth), with the criterion that fired just above it.
The theory should be within a factor 2 of the measured step and never above it; a row where
it is not says why (NOTES). Prints a Markdown table (and writes it to FILE).
"""
from __future__ import annotations

import argparse
import math
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from custom_sim import INTEGRATORS, Scene
from custom_sim.stability import available_energy, limit_modes, limits

from ..scenarios import builtin_paths, load_all
from .stability_search import custom_limit

BISECTION = {"ratio": 1.005, "scan_points": 10}  # 0.5 %, then 10 steps 2 % apart below
FACTOR = 2.0                                      # theory within this of measured

# Why a row's theory is not within FACTOR of measured (key: scene, integrator or None for all)
NOTES: dict[tuple[str, str | None], str] = {}


def energy_scale(scene: Scene) -> float:
    """J: the energy of the motion without a reference solution: the energy above the lowest
    pose plus the depth of the contact well (m g)^2 / (2 k) that a resting body oscillates in."""
    m, g = scene.body.mass, scene.g if scene.has("gravity") else 0.0
    well = (m * g) ** 2 / (2.0 * scene.contact.k) if scene.has("contact") else 0.0
    return max(available_energy(scene) + well, 1e-9)


def measure(scene: Scene, integrator: str) -> dict:
    """One row: theory by effect and mode, and the measured limit."""
    lim = custom_limit(scene, integrator, energy_scale(scene), **BISECTION)
    by_effect = limits(scene, integrator)
    modes = limit_modes(scene, integrator)
    theory = min(by_effect.values(), default=math.inf)
    binding = min(modes, key=modes.get) if modes else "none"
    return {"scene": scene.name, "integrator": integrator, "dt": scene.dt, "limits": by_effect,
            "modes": modes, "theory": theory, "binding": binding, "measured": lim.h_max,
            "capped": lim.capped, "below": lim.below, "reason": lim.reason, "text": lim.text(),
            "runs": lim.runs}


def verdict(row: dict) -> str:
    """"ok" when theory <= measured <= FACTOR theory (or both unlimited), else what is wrong."""
    th, me = row["theory"], row["measured"]
    if not math.isfinite(th):
        return "ok" if row["capped"] else "theory has no limit"
    if th > me * (1.0 + 1e-9) and not row["capped"]:
        return "OPTIMISTIC"
    if me > FACTOR * th:
        return "ok (lower bound)" if row["capped"] else f"conservative x{me / th:.1f}"
    return "ok"


def _fmt(x: float) -> str:
    return "-" if not math.isfinite(x) else f"{x:.3g}"


def markdown(rows: list[dict]) -> str:
    head = ["| scene | integrator | dt (s) | contact (s) | friction (s) | rolling (s) | theory: binding mode |"
            " measured (s) | unstable just above (criterion) | measured / theory | verdict |",
            "|---|---|---|---|---|---|---|---|---|---|---|"]
    lines = []
    for r in rows:
        lim = r["limits"]
        ratio = r["measured"] / r["theory"] if math.isfinite(r["theory"]) and r["theory"] > 0 else math.nan
        v = verdict(r)
        note = NOTES.get((r["scene"], r["integrator"])) or NOTES.get((r["scene"], None))
        if note and v != "ok":
            v = f"{v}: {note}"
        lines.append(
            f"| {r['scene']} | {r['integrator']} | {r['dt']:g} | {_fmt(lim.get('contact', math.inf))} | "
            f"{_fmt(lim.get('friction', math.inf))} | {_fmt(lim.get('rolling_friction', math.inf))} | "
            f"{_fmt(r['theory'])}: {r['binding']} | {r['text']} | {r['reason'] or '-'} | "
            f"{'-' if math.isnan(ratio) else f'{ratio:.2f}'} | {v} |")
    return "\n".join(head + lines)


def all_scenes(names: list[str]) -> list[Scene]:
    if names:
        return load_all(names)
    return load_all([str(p) for p in list(builtin_paths()) + list(builtin_paths("stress"))])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m compare.accuracy.stability_table", description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="*", metavar="SCENE")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", metavar="FILE", help="also write the table here")
    parser.add_argument("--integrator", action="append", choices=list(INTEGRATORS))
    args = parser.parse_args(argv)
    scenes = all_scenes(args.scenes)
    tasks = [(s, i) for s in scenes for i in (args.integrator or INTEGRATORS)]
    with ProcessPoolExecutor(max(1, args.jobs)) as pool:
        rows = list(pool.map(measure, *zip(*tasks)))
    table = markdown(rows)
    print(table)
    if args.out:
        Path(args.out).write_text(table + "\n")
    bad = [r for r in rows if verdict(r).startswith(("OPTIMISTIC", "theory has"))]
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
