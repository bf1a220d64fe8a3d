"""The diagnosis in laws: where no catalogued mistake explains a run, which effect of the user's
law is another family (or other parameters) than the scene's, found by `identify`."""
from __future__ import annotations

from scene_types import Scene
from scene_types.laws import effect_texts

from ..identification.report import params_text

FIELD = {"normal": "damping_law", "friction": "friction_law", "rolling": "roll_law"}
# What each effect's reading rests on (identify reads the normal force and friction from the
# velocity changes at the points where contact acts, through the integrator and gravity; the
# rolling resistance from the angular ones, through the inertia too): a reading is named only
# where none of these failed.
RESTS_ON = {"normal": ("integrator", "gravity", "points"), "friction": ("integrator", "gravity", "points"),
            "rolling": ("integrator", "gravity", "points", "inertia")}
WORDS = {"normal": "normal force", "friction": "friction", "rolling": "rolling resistance"}


def law_findings(simulator, scene: Scene, states, rounding=None, probe: bool = True) -> list[dict]:
    """[{effect, law, text}] for each effect whose identified law differs from the scene's: from
    designed calls of a step function (probe), else by regression over the run's states. Empty
    when identification itself fails (the user's code raising there is the run's own story)."""
    from ..identification import identify_run, identify_step
    from ..usersim.errors import UserCodeError, UserFault

    try:
        if probe and getattr(simulator, "kind", "") == "step":
            result = identify_step(simulator, scene)
        else:
            result = identify_run(states, scene, rounding, getattr(simulator, "kind", "whole"))
    except (UserCodeError, UserFault, ValueError, ArithmeticError):
        return []
    out = findings(result, scene, simulator.integrator_for(scene))
    return out if any(not f.get("unread") for f in out) else []   # nothing read: nothing to say


def _failed(result: dict, declared: str) -> dict:
    """What the readings rest on that identify found wrong: {part: words} of integrator,
    gravity, points (where contact acts) and inertia."""
    failed = {}
    if result["integrator"]["name"] != declared:
        failed["integrator"] = "the integrator, which is not the one declared"
    if result["matches_scene"].get("gravity") is False:
        failed["gravity"] = "gravity, which is not the scene's"
    if result["matches_scene"].get("body") is False:
        body = result.get("body") or {}
        if not body.get("points_match", False):
            failed["points"] = "the contact points, which are not the scene's"
        else:
            failed["inertia"] = "the inertia, which no value matching the scene's reproduces"
    return failed


def findings(result: dict, scene: Scene, declared: str) -> list[dict]:
    """[{effect, law, text}] from identify's result: each effect whose law differs from the
    scene's (its family and parameters, or that it fits no family), named wherever its reading
    does not rest on what failed (RESTS_ON), whatever another effect did; and, where it does,
    that it could not be read (law None, `unread`)."""
    failed = _failed(result, declared)
    asked = effect_texts(scene.contact)
    out = []
    for effect in FIELD:
        if result["matches_scene"].get(effect) is not False:
            continue
        blocked = [failed[p] for p in RESTS_ON[effect] if p in failed]
        if blocked:
            out.append({"effect": effect, "law": None, "unread": True,
                        "text": f"your {WORDS[effect]} is not read: its reading rests on {blocked[0]}"})
            continue
        e = result[effect]
        if e.get("read") is False:   # the probes saw only round-off: nothing to say of the law
            continue
        if e.get("onset") is not None:   # no [contact] law holds an onset: no law to run under
            text = (f"your {WORDS[effect]} begins {abs(e['onset']):.3g} m {'above' if e['onset'] > 0 else 'below'} "
                    f"the ground, the scene's at its contact points")
            out.append({"effect": effect, "law": None, "text": text})
            continue
        if e.get("law") is not None:
            found = f"{e['law']} ({params_text(e, effect)})"
            text = f"your {WORDS[effect]} is {found}, the scene asks {asked[effect]}"
        else:
            c = e.get("closest", {})
            text = (f"your {WORDS[effect]} fits no family of the harness (closest {c.get('law')}"
                    f"{_off(c, effect)}), the scene asks {asked[effect]}")
        out.append({"effect": effect, "law": e.get("law"), "text": text})
    return out


def _off(closest: dict, effect: str) -> str:
    """', 3.2 N off (4.1e+05 x round-off)': the closest family's residual, where it is above round-off."""
    rel, res = closest.get("relative"), closest.get("residual")
    if rel is None or res is None or not (rel > 1.0) or rel == float("inf"):
        return ""
    unit = "N m" if effect == "rolling" else "N"
    return f", {res:.3g} {unit} off ({rel:.2g} x round-off)"


def law_verdict(findings: list[dict]) -> str:
    """One clause for the verdict line: which effects of the law differ, and, where each is a
    family of the harness, how to judge the code under its own law if that law is meant."""
    said = "; ".join(f["text"] for f in findings)
    if all(f["law"] is not None for f in findings):
        return (f"your law differs from the scene's: {said}; if that is the law you mean, `run --law identified` "
                "judges your code under it")
    return f"your law differs from the scene's: {said}"
