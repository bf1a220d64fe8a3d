"""Where a user's simulator departs from the seed's algorithm, and which known mistake explains it.

Two probes, both against the reference's independent step (compare/checks/step_check.py) and
the catalogue of known mistakes (compare/diagnosis/mistakes.py):

    moments      (a step function only) the user's step called from custom_sim's states at
                 chosen moments (flight, touchdown, a sliding corner, rolling, resting): which
                 moments disagree, in which component, and which mistake reproduces the user's
                 step at every moment;
    trajectory   (any input) every step of the user's own trajectory: the first whose one-step
                 residual leaves round-off, its phase and component, and which mistake (or pair)
                 explains every step.

A moment is probed only where the effect it exercises acts (moments.py); the effects no moment
could probe are listed. The first probed moment (or step) off round-off is also given as the
force that makes it, m dv / dt and I domega / dt, at the points touching.

Neither guesses: a catalogued mistake is named only where it reproduces every probed step (every
chosen moment and every step of the trajectory) to round-off; one that explains all but some
steps is kept in the dict (not_named) and never printed: a partial match points the wrong way.
Where none explains the residual to round-off, it says so and shows the residual, in its units
and in newtons (a component within round-off shows none), a torque read as the part of the
contact torque it is (mistakes.read_torque), and a run that gains energy (energy_gain.py).
"""
from __future__ import annotations

import numpy as np

from custom_sim import INTEGRATORS, Scene, SimulationDiverged

from ..checks.case import as_case
from ..checks.step_check import COMPONENTS, UNITS, check_step, first_failure, largest_residual
from ..table import markdown, number
from ..usersim.errors import UserCodeError, UserFault
from ..usersim.scene_dict import scene_dict
from . import mistakes
from .energy_gain import energy_gain
from .laws import law_findings, law_verdict
from .moments import not_probed, pick_moments


def _moments(simulator, scene: Scene, integrator: str, also=(), case=None) -> dict:
    """The user's step from custom_sim's states at the chosen moments, in time order; `also`:
    mistakes whose reproduction of every moment is wanted (the trajectory's explanation);
    case: the scenario's Case, whose custom_sim runs it takes."""
    case = as_case(scene, case)
    run_integrator = integrator if integrator in INTEGRATORS else None
    run_scene = case.variant(run_integrator)
    try:
        ours = case.trajectory(run_integrator).states()
    except SimulationDiverged as exc:
        return {"verdict": f"not diagnosed: custom_sim diverges on this scene ({exc})", "moments": []}
    picked = sorted(pick_moments(run_scene, ours), key=lambda m: m.row)
    gaps = not_probed(run_scene, picked)
    sd = scene_dict(scene)
    numbers = iter([m.row + 1 for m in picked])

    def step(z, _scene_dict, dt):
        return simulator.call(z, sd, dt, next(numbers))
    try:
        out = mistakes.diagnose_step(step, scene, [(m.kind, ours[m.row]) for m in picked],
                                     integrator, scene.dt, sd, also=also)
    except (UserCodeError, UserFault) as exc:
        return {"verdict": f"not diagnosed: the step function failed at a chosen moment: {exc}",
                "moments": [], "details": getattr(exc, "details", ""), "not_probed": gaps}
    for m, entry in zip(picked, out["moments"]):
        entry.update(step=m.row + 1, time=(m.row + 1) * scene.dt, what=m.what)
        if out.get("force") and out["force"]["where"] == m.kind:
            out["force"].update(step=m.row + 1, time=(m.row + 1) * scene.dt)
    out["not_probed"] = gaps
    return out


def _decide(traj: dict, moments: dict | None, scene: Scene, states, integrator: str):
    """(named, not_named): the candidates that reproduce every probed step (every chosen moment
    and every step of the trajectory), and those that explain all but some, with how many."""
    probed = bool(moments and moments.get("moments"))
    judged = traj["step"].passed is not None
    by_traj = list(traj.get("explained_by", []))
    reach = {x["name"]: x for x in (moments or {}).get("mistakes", [])} if probed else {}
    candidates = by_traj + [n for n in ((moments or {}).get("explained_by", []) if probed else [])
                            if n not in by_traj]
    named, not_named = [], []
    for name in candidates:
        # diagnose_step reports every name it was asked about (`also`) and every explanation
        x = reach.get(name, {"reproduces": 0, "of": 0, "not_at": []})
        if probed and x["reproduces"] < x["of"]:
            off = x["of"] - x["reproduces"]
            not_named.append({"name": name, "steps_off": off, "steps": x["of"], "where": "moments",
                              "text": f"{name} explains every step of your trajectory but not your step at "
                                      f"{', '.join(x['not_at'])} ({off} of {x['of']} chosen moments); not named"})
            continue
        if name not in by_traj and judged:
            t = mistakes.explains_trajectory(name, scene, states, integrator, scene.dt)
            if not t["explains"]:
                not_named.append({"name": name, "steps_off": t["steps_off"], "steps": t["steps"],
                                  "where": "trajectory",
                                  "text": f"{name} reproduces your step at every chosen moment but explains all "
                                          f"but {t['steps_off']} of {t['steps']} steps of your trajectory; not named"})
                continue
        named.append(name)
    if not named:
        seen = {n["name"] for n in not_named}
        for route, near in (("trajectory", traj.get("not_named", [])), ("moments", (moments or {}).get("not_named", []))):
            for t in near:
                if t["name"] not in seen:
                    seen.add(t["name"])
                    where = " of your trajectory" if route == "trajectory" else " (chosen moments)"
                    not_named.append({"name": t["name"], "steps_off": t["steps_off"], "steps": t["steps"],
                                      "where": route, "text": mistakes.not_named_text([t], where)})
    return named, ([] if named else not_named)


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


def diagnose(simulator, scene: Scene, trajectory, probe: bool = True, case=None, step_row=None) -> dict:
    """The diagnosis of one run under test (trajectory: a Trajectory, its meta holding a file's
    rounding). probe False: the step is not called from chosen states (it keeps state between
    calls, so an answer out of order would not be the one its run used): the trajectory alone.
    step_row: the step check's row of this trajectory, when the caller has it. The simulator is
    closed afterwards (a process ends): nothing is left running once a scene is judged."""
    try:
        return diagnosis(simulator, scene, trajectory.states(), trajectory.meta.get("rounding"), case, probe,
                         step_row)
    finally:
        simulator.close()


def diagnosis(simulator, scene: Scene, states: np.ndarray, rounding=None, case=None, probe: bool = True,
              step_row=None) -> dict:
    """The diagnosis of the user's run `states` (steps + 1, 6) of `scene` (JSON-safe dict):

    integrator    the one the simulator names
    moments       step functions only: {"moments": [{name, what, step, time, phase, agrees,
                  component, residual {x..omega}, difference (signed), ratio_max, explained_by,
                  force}], "disagree", "steps", "explained_by", "mistakes", "not_named",
                  "not_probed" [{name, effect, why}], "force", "verdict"}; None otherwise
    trajectory    {"step": the step check's row, "explained_by", "mistakes" tried, "not_named",
                  "force", "verdict"}
    named         [{name, seed_line, description}]: every catalogued mistake (pairs split) that
                  reproduces every probed step: every chosen moment and every trajectory step
    not_named     [{name, steps_off, steps, where, text}]: mistakes that explain all but some
    force         the first probed moment (or, without one, trajectory step) off round-off as
                  a force: {where, off, Fx, Fy (N), torque (N m), points [{point, arm, depth}],
                  text}, or None
    laws          where no mistake is named: [{effect, law, text}] for each effect whose law
                  `identify` finds to differ from the scene's (law_diagnosis.py)
    energy_gain   where the run fails: {user, custom, margin, text} (J) if the user's run gains
                  energy where custom_sim's under the same law and integrator loses it, else None
    verdict       one line
    """
    integrator = simulator.integrator_for(scene)
    states = np.asarray(states, dtype=float)
    laws: list[dict] = []
    traj = mistakes.diagnose(scene, states, integrator, scene.dt, input_rtol=rounding or 0.0, step_row=step_row)
    moments = (_moments(simulator, scene, integrator, also=traj.get("explained_by", []), case=case)
               if probe and getattr(simulator, "kind", "") == "step" else None)
    names, not_named = _decide(traj, moments, scene, states, integrator)
    if moments and moments.get("explained_by") and not set(moments["explained_by"]) <= set(names):
        # reproduced at every moment but not over the trajectory: named nowhere, this section included
        moments["verdict"] = (f"disagrees at {moments['where']}; no catalogued mistake explains every probed step "
                              "(these moments and every step of your trajectory) to round-off")
    named = _named(names)
    step_row = traj["step"]
    disagree = bool(moments and moments.get("disagree"))
    force = (moments or {}).get("force") if disagree else traj.get("force")
    gaps = (moments or {}).get("not_probed", [])
    gap_text = ("; could not be probed: " + "; ".join(f"{g['name']} ({g['effect']}: {g['why']})" for g in gaps)
                if gaps else "")
    leads: list = []   # what is known for sure, said before the verdict (each a sentence)
    if step_row.passed is True and not disagree:
        verdict = "every step agrees with the reference step to round-off: nothing to explain" + gap_text
    elif named:
        verdict = "explained by " + "; ".join(f"{n['name']} ({n['seed_line']})" for n in named)
    elif step_row.passed is None and not disagree:
        verdict = traj.get("verdict", "not diagnosed")
    else:
        parts = []
        if force:
            at = (f"at {force['where']} (step {force['step']}, t = {force['time']:.6g} s)"
                  if "step" in force and force["where"] != f"step {force['step']}" else f"at {force['where']}")
            parts.append(f"{at} your step is off by {force['off']}: {mistakes.force_clause(force)}")
        if step_row.passed is False:
            parts.append("your trajectory: " + _trajectory_where(step_row))
        verdict = "no catalogued mistake explains the residual to round-off: " + "; ".join(parts)
        leads += [other_method(scene, states, integrator, scene.integrator, rounding)]
        laws = law_findings(simulator, scene, states, rounding, probe)
        leads += [law_verdict(laws)] if laws else []
        leads += [torque_finding(moments, traj.get("force"))]
    gain = energy_gain(scene, states, integrator, rounding, case) if step_row.passed is False or disagree else None
    said = [*(x for x in leads if x), verdict]
    if gain:   # a symptom: after a mistake named, before what is left unexplained
        said.insert(len(said) - (0 if named else 1), gain["text"])
    verdict = ". ".join([said[0], *map(_capital, said[1:])])
    return {"integrator": integrator, "moments": moments, "trajectory": {**traj, "step": step_row.to_json()},
            "named": named, "not_named": not_named, "force": force, "verdict": verdict, "laws": laws,
            "energy_gain": gain}


def other_method(scene: Scene, states: np.ndarray, stepped: str, asked: str, rounding=None) -> str | None:
    """Where the run fails the step check under `stepped` (the integrator the simulator declares,
    else the scene's) and passes it at every step under another of the four: a sentence naming
    that method and how to declare it. None where no other method explains every step."""
    for other in INTEGRATORS:
        if other == stepped:
            continue
        if check_step(scene, states, other, scene.dt, input_rtol=rounding or 0.0).passed:
            said = (f"you declare {stepped}" if stepped != asked else
                    f"the scene asks {asked} and your code declares none")
            return (f"your step is {other}: every step agrees with {other}'s to round-off ({said}); declare "
                    f"it (INTEGRATOR = \"{other}\" in a Python module, `ready {other}` on the step protocol) "
                    f"or step with {asked}")
    return None


def _capital(text: str) -> str:
    return text[:1].upper() + text[1:]


def torque_finding(moments: dict | None, traj_force: dict | None) -> str | None:
    """Where every disagreeing moment (else the trajectory's first failing step) is a torque
    with no force beside it and reads as the same part of the contact torque (mistakes.read_torque)
    the same way: that, in one clause ("the friction torque (r x Ft) has the opposite sign at
    every moment your step disagrees: touchdown, sliding"); else None."""
    entries = [e for e in (moments or {}).get("moments", []) if not e["agrees"]]
    if entries:
        readings = [(e.get("force") or {}).get("torque_reading") for e in entries]
        where = f"at every moment your step disagrees ({', '.join(e['name'] for e in entries)})"
    elif traj_force:
        readings, where = [traj_force.get("torque_reading")], f"at the first step off round-off ({traj_force['where']})"
    else:
        return None
    if not readings or any(r is None for r in readings):
        return None
    first = readings[0]
    if any((r["part"], r["factor"]) != (first["part"], first["factor"]) for r in readings):
        return None
    return f"{mistakes.PART_WORDS[first['part']]} {first['how']} {where}"


def _trajectory_where(row) -> str:
    """The step check's (a CheckRow's) first failing step and largest residual, in one clause."""
    return f"{first_failure(row)}; {largest_residual(row)}"


HEADS = [f"{c} ({u})" for c, u in zip(COMPONENTS, UNITS)]   # the tables' column heads


def _ratio(v) -> str:
    """A residual over its round-off; a round-off of 0 (a component that cannot round) in words."""
    return "any (round-off 0)" if v is not None and v >= 1e300 else _num(v)


def _num(v) -> str:
    """3 significant digits, an empty cell for a value that is missing."""
    return number(v, none="")


def _table(headers, rows) -> list[str]:
    return markdown(headers, rows).splitlines() + [""]


def diagnosis_markdown(diag: dict) -> str:
    """The body of the report's Diagnosis section (markdown, its heading left to the page)."""
    return render_markdown(diag, heading=False)


def _force_rows(diag: dict) -> list[tuple[str, dict]]:
    """(where, force) of every disagreeing moment, then the trajectory's first failing step."""
    rows = [(f"{e['name']} (step {e.get('step', '')})", {**e["force"], "off": mistakes.off_text(e)})
            for e in (diag.get("moments") or {}).get("moments", []) if e.get("force")]
    t = diag["trajectory"].get("force")
    if t:
        rows.append((f"{t['where']} of your trajectory", t))
    return rows


def _acting_at(f: dict) -> str:
    pts = [str(p["point"]) for p in f["points"]]
    if not pts:
        return "no point touching"
    return f"point {pts[0]}" if len(pts) == 1 else f"points {', '.join(pts)} (shared)"


def render_markdown(diag: dict, heading: bool = True) -> str:
    """The report's "Diagnosis" section (markdown)."""
    lines = (["## Diagnosis", ""] if heading else []) + [f"**{diag['verdict']}**", ""]
    if diag["named"]:
        lines += _table(["mistake", "seed line", "what it does"],
                        [[f"`{n['name']}`", n["seed_line"], n["description"]] for n in diag["named"]])
    forces = _force_rows(diag)
    if forces:
        lines += ["Your step minus the reference step, as the force that makes it (m dv / dt, I domega / dt; "
                  f"dt = {_num(forces[0][1]['dt'])} s, m = {_num(forces[0][1]['mass'])} kg; empty: that velocity "
                  "agrees to round-off):", ""]
        lines += _table(["where", "off by", "Fx (N)", "Fy (N)", "torque (N m)", "acting at"],
                        [[where, f.get("off", ""), _num(f["Fx"]), _num(f["Fy"]), _num(f["torque"]),
                          _acting_at(f)] for where, f in forces])
    m = diag.get("moments")
    if m is not None:
        lines += ["### Your step from chosen moments of custom_sim's run", "", m.get("verdict", ""), ""]
        if m.get("not_probed"):
            lines += ["Effects that could not be probed (no state of custom_sim's run has them acting):", ""]
            lines += [f"- {g['name']}: {g['effect']}; {g['why']}" for g in m["not_probed"]]
            lines.append("")
        if m.get("moments"):
            lines += markdown(["moment", "step", "what", "agrees", "component", "largest residual / round-off"],
                              [[e["name"], str(e.get("step", "")), e.get("what", e.get("phase", "")),
                                "yes" if e["agrees"] else "**no**", e["component"] or "", _ratio(e["ratio_max"])]
                               for e in m["moments"]]).splitlines()
            lines += ["", "Residuals per component (your step minus the reference step, from the same state):", ""]
            lines += _table(["moment", *HEADS],
                            [[e["name"], *(f"{e['residual'][c]:.3g}" for c in COMPONENTS)] for e in m["moments"]])
    t = diag["trajectory"]
    lines += ["### Every step of your trajectory", "", t.get("verdict", ""), ""]
    row = t.get("step", {})
    if row.get("residual_max"):
        lines += _table(["", *HEADS],
                        [["largest one-step residual", *(f"{row['residual_max'][c]:.3g}" for c in COMPONENTS)]])
    tried = [x for x in t.get("mistakes", []) if not x.get("screened_out")]
    if tried:
        lines += ["Catalogued mistakes stepped over the whole trajectory:", ""]
        lines += _table(["mistake", "explains", "first step off", "largest residual / round-off"],
                        [[f"`{x['name']}`", "yes" if x["explains"] else "no", _num(x.get("first_step")),
                          _ratio(x.get("ratio_max"))] for x in tried])
    return "\n".join(lines)
