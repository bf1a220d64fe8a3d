"""Theory against measured: the largest stable step of every scene and integrator.

    python -m compare tools stability-table [SCENE ...] [--jobs N] [--out FILE]   (compare/commands/tools/stability_table.py)

For each built-in and stress scene (or the named ones) and each of custom_sim's integrators:
the limit of each effect by custom_sim/stability.py (`limits`), the smallest of them, and the
largest step the search of stability_search.py measures (stable = no blow-up, no chatter by
custom_sim/chatter.py, no energy growth), with the criterion that fired just above it.
The theory should be within a factor 2 of the measured step and never above it; a row where
it is not says why (NOTES). Prints a Markdown table (and writes it to FILE).
"""
from __future__ import annotations

import json
import math
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from custom_sim import INTEGRATORS, Scene
from custom_sim.stability import available_energy, limit_modes, limits

from ...scenarios import builtin_paths, load_all
from ...table import markdown as markdown_table, number
from .stability_search import custom_limit

BISECTION = {"ratio": 1.005, "scan_points": 10}  # 0.5 %, then 10 steps 2 % apart below
FACTOR = 2.0                                      # theory within this of measured

# Why a row's theory is not within FACTOR of measured (key: scene or None, integrator or None)
IMPACT_BOUND = ("the impact bound puts all the energy that can reach a contact normal into one point at the "
                "smallest normal effective mass (sqrt(2 k E_n)); the real landing is softer, or the point "
                "slides through it (chatter needs the slip near zero while the load is high)")
NOTES: dict[tuple[str | None, str | None], str] = {
    (None, "rk4"): ("RK4's amplification on the negative real axis is positive past h lambda_f = 2.785: the slip "
                    "leaves zero without flipping and settles at a spurious constant slip (a creep: point_drop "
                    "at 8e-3 s slides at 2.4 mm/s for ever), which is no chatter; the search finds the contact's "
                    "or an energy growth far above. The friction limit stays: it is where RK4's rest is lost"),
    (None, "implicit_euler"): ("Newton does not converge where the damper engages at touchdown (the residual "
                               "jumps over zero, see integrators.py): that step is not implicit Euler's, and "
                               "the theory's 'every h' is for the exact implicit step"),
    ("elastic_bounce", None): ("undamped contact has no growing mode; the energy criterion measures the O(h wn) "
                               "energy error of each touchdown inside a step, which passes 10 % after 3 "
                               "bounces: accuracy, not instability"),
    ("box_slide", None): ("the theory takes the smallest tangential effective mass at any lowest point (a corner "
                          "under the COM, 0.125 kg); lying flat the box's is 0.31 kg"),
    ("resting_60s", None): IMPACT_BOUND + " (the box is set down 1.5 mm above its rest, flat on two corners)",
    ("sharp_friction", None): "as box_slide: lying flat the tangential effective mass is 2.5 times the smallest",
    ("rolling_circle", "explicit_euler"): ("the compression law's rest energy balance assumes a small "
                                           "oscillation about rest; the disk rolls at a fixed depth"),
    ("box_drop", None): IMPACT_BOUND + " (box_drop's landing: 215 N measured, 313 N bound)",
    ("impact_chatter", None): IMPACT_BOUND + " (the slap-down: 1290 N measured, 1515 N bound)",
    ("fast_impact", None): IMPACT_BOUND,
    ("t_shape_drop", None): IMPACT_BOUND,
    ("million_steps", None): IMPACT_BOUND,
}


def note(row: dict) -> str | None:
    for key in ((row["scene"], row["integrator"]), (row["scene"], None), (None, row["integrator"])):
        if key in NOTES:
            return NOTES[key]
    return None


def energy_scale(scene: Scene) -> float:
    """J: the energy of the motion without a reference solution: the energy above the lowest
    pose plus the depth of the contact well (m g)^2 / (2 k) that a resting body oscillates in."""
    m, g = scene.body.mass, scene.g if scene.has("gravity") else 0.0
    well = (m * g) ** 2 / (2.0 * scene.contact.k) if scene.has("contact") else 0.0
    return max(available_energy(scene) + well, 1e-9)


def theory_columns(scene: Scene, integrator: str) -> dict:
    by_effect = limits(scene, integrator)
    modes = limit_modes(scene, integrator)
    binding = min(modes, key=modes.get) if modes else "none"
    return {"dt": scene.dt, "limits": by_effect, "modes": modes, "binding": binding,
            "theory": min(by_effect.values(), default=math.inf)}


def measure(scene: Scene, integrator: str) -> dict:
    """One row: theory by effect and mode, and the measured limit."""
    lim = custom_limit(scene, integrator, energy_scale(scene), **BISECTION)
    return {"scene": scene.name, "integrator": integrator, "measured": lim.h_max, "capped": lim.capped,
            "below": lim.below, "reason": lim.reason, "text": lim.text(), "runs": lim.runs,
            **theory_columns(scene, integrator)}


def verdict(row: dict) -> str:
    """"ok" when theory <= measured <= FACTOR theory (or both unlimited), else what is wrong."""
    th, me = row["theory"], row["measured"]
    if th == 0.0:
        return "ok (no stable step in theory)" if me < 1e-3 else "conservative: no stable step in theory"
    if not math.isfinite(th):
        return "ok" if row["capped"] else "theory has no limit"
    if th > me * (1.0 + 1e-9) and not row["capped"]:
        return "OPTIMISTIC"
    if me > FACTOR * th:
        return "ok (lower bound)" if row["capped"] else f"conservative x{me / th:.1f}"
    return "ok"


HEADERS = ["scene", "integrator", "dt (s)", "contact (s)", "friction (s)", "rolling (s)", "theory: binding mode",
           "measured (s)", "unstable just above (criterion)", "measured / theory", "verdict"]


def _num(x: float, **options) -> str:
    return number(x, nonfinite="-", **options)


def markdown(rows: list[dict]) -> str:
    cells = []
    for r in rows:
        lim = r["limits"]
        ratio = r["measured"] / r["theory"] if math.isfinite(r["theory"]) and r["theory"] > 0 else math.nan
        v = verdict(r)
        why = note(r)
        if why and not v.startswith("ok"):
            v = f"{v}: {why}"
        cells.append([r["scene"], r["integrator"], f"{r['dt']:g}",
                      *(_num(lim.get(k, math.inf)) for k in ("contact", "friction", "rolling_friction")),
                      f"{_num(r['theory'])}: {r['binding']}", r["text"], r["reason"] or "-",
                      _num(ratio, decimals=2), v])
    return markdown_table(HEADERS, cells)


def all_scenes(names: list[str]) -> list[Scene]:
    if names:
        return load_all(names)
    return load_all([str(p) for p in list(builtin_paths()) + list(builtin_paths("stress"))])


def print_table(names: list[str], jobs: int = 2, out: str | None = None, integrators: list[str] | None = None,
                json_out: str | None = None, measured: str | None = None) -> int:
    """The table of the named scenes (default: every built-in and stress scene), measured on
    `jobs` processes (or the measured columns of an earlier json_out: `measured`); printed, and
    written to `out`, the rows to `json_out`. 1 when a row is unexplained (optimistic), else 0."""
    scenes = all_scenes(names)
    tasks = [(s, i) for s in scenes for i in (integrators or INTEGRATORS)]
    if measured:   # the measured columns of an earlier run, the theory and dt of today
        old = {(r["scene"], r["integrator"]): r for r in json.loads(Path(measured).read_text())}
        rows = [dict(old[(s.name, i)], **theory_columns(s, i)) for s, i in tasks]
    else:
        with ProcessPoolExecutor(max(1, jobs)) as pool:
            rows = list(pool.map(measure, *zip(*tasks)))
    if json_out:
        Path(json_out).write_text(json.dumps(rows, indent=1, default=float))
    table = markdown(rows)
    print(table)
    if out:
        Path(out).write_text(table + "\n")
    bad = [r for r in rows if verdict(r).startswith(("OPTIMISTIC", "theory has")) and not note(r)]
    for r in bad:
        print(f"unexplained: {r['scene']} {r['integrator']}: {verdict(r)}", file=sys.stderr)
    return 1 if bad else 0
