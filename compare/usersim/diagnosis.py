"""Where a user's simulator departs from the seed's algorithm, and which known mistake explains it.

Two probes, both against the reference's independent step (compare/verdict/step_check.py) and
the catalogue of known mistakes (compare/verdict/mistakes.py):

    moments      (a step function only) the user's step called from custom_sim's states at
                 chosen moments (flight, touchdown, a sliding corner, rolling, resting): which
                 moments disagree, in which component, and which mistake reproduces the user's
                 step at every moment;
    trajectory   (any input) every step of the user's own trajectory: the first whose one-step
                 residual leaves round-off, its phase and component, and which mistake (or pair)
                 explains every step.

Neither guesses: where no catalogued mistake explains the residual to round-off, it says so and
shows the residual.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from custom_sim import INTEGRATORS, Scene, SimulationDiverged, simulate

from ..verdict import mistakes
from .errors import UserCodeError
from .moments import pick_moments
from .scene_dict import scene_dict


def _moments(simulator, scene: Scene, integrator: str) -> dict:
    """The user's step from custom_sim's states at the chosen moments."""
    run_scene = scene if integrator == scene.integrator or integrator not in INTEGRATORS \
        else dataclasses.replace(scene, integrator=integrator)
    try:
        ours = simulate(run_scene).states()
    except SimulationDiverged as exc:
        return {"verdict": f"not diagnosed: custom_sim diverges on this scene ({exc})", "moments": []}
    picked = pick_moments(run_scene, ours)
    sd = scene_dict(scene)

    def step(z, _scene_dict, dt):
        return simulator.call(z, sd, dt)
    try:
        out = mistakes.diagnose_step(step, scene, [(m.kind, ours[m.row]) for m in picked],
                                     integrator, scene.dt, sd)
    except UserCodeError as exc:
        return {"verdict": f"not diagnosed: the step function failed at a chosen moment: {exc}",
                "moments": [], "details": exc.details}
    for m, entry in zip(picked, out["moments"]):
        entry.update(step=m.row + 1, time=(m.row + 1) * scene.dt, what=m.what)
    return out


def _named(*explained: list[str]) -> list[dict]:
    """Each catalogued mistake named (pairs split), once, with the seed's line it concerns."""
    names = []
    for group in explained:
        for name in group:
            for part in name.split(" + "):
                if part not in names:
                    names.append(part)
    return [{"name": n, "seed_line": mistakes.BY_NAME[n].seed_line,
             "description": mistakes.BY_NAME[n].description} for n in names]


def diagnosis(simulator, scene: Scene, states: np.ndarray) -> dict:
    """The diagnosis of the user's run `states` (steps + 1, 6) of `scene` (JSON-safe dict):

    integrator    the one the simulator names
    moments       step functions only: {"moments": [{name, what, step, time, phase, agrees,
                  component, residual {x..omega}, ratio_max, explained_by}], "disagree",
                  "explained_by", "verdict"}; None otherwise
    trajectory    {"step": the step check's row, "explained_by", "mistakes" tried, "verdict"}
    named         [{name, seed_line, description}]: every catalogued mistake that explains
                  what was seen (the trajectory's explanation first; the moments' if it has none)
    verdict       one line
    """
    integrator = simulator.integrator_for(scene)
    states = np.asarray(states, dtype=float)
    traj = mistakes.diagnose(scene, states, integrator, scene.dt)
    moments = _moments(simulator, scene, integrator) if getattr(simulator, "kind", "") == "step" else None
    by_traj = traj.get("explained_by", [])
    by_moments = (moments or {}).get("explained_by", [])
    named = _named(by_traj) if by_traj else _named(by_moments)
    step_row = traj.get("step", {})
    if step_row.get("pass") is True and not (moments and moments.get("disagree")):
        verdict = "every step agrees with the reference step to round-off: nothing to explain"
    elif named:
        verdict = "explained by " + "; ".join(f"{n['name']} ({n['seed_line']})" for n in named)
    elif step_row.get("pass") is None:
        verdict = traj.get("verdict", "not diagnosed")
    else:
        verdict = ("no catalogued mistake explains the residual to round-off: "
                   + traj.get("verdict", ""))
    return {"integrator": integrator, "moments": moments, "trajectory": traj, "named": named,
            "verdict": verdict}


def _fmt(v) -> str:
    return "" if v is None else f"{v:.3g}" if isinstance(v, float) else str(v)


def diagnosis_markdown(diag: dict) -> str:
    """The body of the report's Diagnosis section (markdown, its heading left to the page)."""
    return render_markdown(diag, heading=False)


def render_markdown(diag: dict, heading: bool = True) -> str:
    """The report's "Diagnosis" section (markdown)."""
    lines = (["## Diagnosis", ""] if heading else []) + [f"**{diag['verdict']}**", ""]
    if diag["named"]:
        lines += ["| mistake | seed line | what it does |", "|---|---|---|"]
        lines += [f"| `{n['name']}` | {n['seed_line']} | {n['description']} |" for n in diag["named"]]
        lines.append("")
    m = diag.get("moments")
    if m is not None:
        lines += ["### Your step from chosen moments of custom_sim's run", "", m.get("verdict", ""), ""]
        if m.get("moments"):
            lines += ["| moment | step | what | agrees | component | largest residual / round-off | explained by |",
                      "|---|---|---|---|---|---|---|"]
            for e in m["moments"]:
                lines.append(f"| {e['name']} | {e.get('step', '')} | {e.get('what', e.get('phase', ''))} | "
                             f"{'yes' if e['agrees'] else '**no**'} | {e['component'] or ''} | "
                             f"{_fmt(e['ratio_max'])} | {', '.join(e['explained_by'])} |")
            lines += ["", "Residuals per component (your step minus the reference step, from the same state):", "",
                      "| moment | x (m) | y (m) | theta (rad) | vx (m/s) | vy (m/s) | omega (rad/s) |",
                      "|---|---|---|---|---|---|---|"]
            for e in m["moments"]:
                r = e["residual"]
                lines.append(f"| {e['name']} | " + " | ".join(f"{r[c]:.3g}" for c in
                                                           ("x", "y", "theta", "vx", "vy", "omega")) + " |")
            lines.append("")
    t = diag["trajectory"]
    lines += ["### Every step of your trajectory", "", t.get("verdict", ""), ""]
    row = t.get("step", {})
    if row.get("residual_max"):
        lines += ["| | x (m) | y (m) | theta (rad) | vx (m/s) | vy (m/s) | omega (rad/s) |",
                  "|---|---|---|---|---|---|---|",
                  "| largest one-step residual | " + " | ".join(f"{row['residual_max'][c]:.3g}" for c in
                                                           ("x", "y", "theta", "vx", "vy", "omega")) + " |", ""]
    tried = [x for x in t.get("mistakes", []) if not x.get("screened_out")]
    if tried:
        lines += ["Catalogued mistakes stepped over the whole trajectory:", "",
                  "| mistake | explains | first step off | largest residual / round-off |", "|---|---|---|---|"]
        lines += [f"| `{x['name']}` | {'yes' if x['explains'] else 'no'} | {_fmt(x.get('first_step'))} | "
                  f"{_fmt(x.get('ratio_max'))} |" for x in tried]
        lines.append("")
    return "\n".join(lines)
