"""The diagnosis in laws: where no catalogued mistake explains a run, which effect of the user's
law is another family (or other parameters) than the scene's, found by `identify`."""
from __future__ import annotations

from scene_types import Scene
from scene_types.laws import effect_texts

from ..identify.report import params_text

FIELD = {"normal": "damping_law", "friction": "friction_law", "rolling": "roll_law"}
WORDS = {"normal": "normal force", "friction": "friction", "rolling": "rolling resistance"}


def law_findings(simulator, scene: Scene, states, rounding=None, probe: bool = True) -> list[dict]:
    """[{effect, law, text}] for each effect whose identified law differs from the scene's: from
    designed calls of a step function (probe), else by regression over the run's states. Empty
    when identification itself fails (the user's code raising there is the run's own story)."""
    from ..identify import identify_run, identify_step
    from .errors import UserCodeError, UserFault

    try:
        if probe and getattr(simulator, "kind", "") == "step":
            result = identify_step(simulator, scene)
        else:
            result = identify_run(states, scene, rounding, getattr(simulator, "kind", "whole"))
    except (UserCodeError, UserFault, ValueError, ArithmeticError):
        return []
    declared = simulator.integrator_for(scene)
    if result["integrator"]["name"] != declared or any(result["matches_scene"].get(part) is False
                                                        for part in ("body", "gravity")):
        return []   # the forces are read through the body and the step: a law read through wrong ones says nothing
    asked = effect_texts(scene.contact)
    out = []
    for effect, field in FIELD.items():
        if result["matches_scene"].get(effect) is not False:
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
            text = (f"your {WORDS[effect]} fits no family of the harness (closest {c.get('law')}, "
                    f"{c.get('residual', float('nan')):.3g} off), the scene asks {asked[effect]}")
        out.append({"effect": effect, "law": e.get("law"), "text": text})
    return out


def law_verdict(findings: list[dict]) -> str:
    """One clause for the verdict line: which effects of the law differ, and, where each is a
    family of the harness, how to judge the code under its own law if that law is meant."""
    said = "; ".join(f["text"] for f in findings)
    if all(f["law"] is not None for f in findings):
        return (f"your law differs from the scene's: {said}; if that is the law you mean, `run --law identified` "
                "judges your code under it")
    return f"your law differs from the scene's: {said}"
