"""Where a run is judged under another law than its scene's (`run --law`): which effects of
the two laws differ, and by how many newtons, at the moment of the run where they differ most."""
from __future__ import annotations

import dataclasses

import numpy as np

from scene_types import Scene, law_text
from scene_types.laws import LAW_PARAMETERS

# each effect of the law and the [contact] fields that make it
EFFECT_FIELDS = {
    "normal": ("damping_law", "k", "c", "dissipation"),
    "friction": ("friction_law", "mu", "alpha"),
    "rolling": ("roll_law", "mu_roll", "roll_sharpness"),
}
EFFECT_NEEDS = {"normal": "contact", "friction": "friction", "rolling": "rolling_friction"}
# An identified law's parameters are fitted to the round-off of its probes' forces (about 1e-12
# of them); two laws whose forces differ by less than this share of the run's largest force
# are the same law, and no effect is said to differ
SAME_LAW = 1e-9


def differing_effects(scene: Scene) -> list[str]:
    """The effects whose fields differ between the scene file's law and the one judged."""
    asked = scene.scene_contact
    if asked is None:
        return []
    return [effect for effect, fields in EFFECT_FIELDS.items()
            if scene.has(EFFECT_NEEDS[effect])
            and any(getattr(asked, f) != getattr(scene.contact, f) for f in fields)]


def law_differences(scene: Scene, t: np.ndarray, states: np.ndarray) -> list[dict]:
    """For each differing effect: the largest difference of force (N, or N m for the torque)
    between the scene file's law and the judged one, over the run's states, and where it is.
    Only that effect's fields are exchanged, so each row is that effect alone."""
    from ..oracle.force_law import accelerations
    from ..oracle.reference import Equations

    rows = []
    judged = Equations.from_scene(scene)
    scale = np.array([judged.mass, judged.mass, judged.inertia if judged.rotates else 0.0])
    a_judged, _ = accelerations(judged, states)
    loads = a_judged * scale
    largest = max(float(np.max(np.hypot(loads[:, 0], loads[:, 1] + judged.mass * judged.g))),
                  judged.mass * judged.g, np.finfo(float).tiny)
    for effect in differing_effects(scene):
        swapped = dataclasses.replace(scene.contact, **{f: getattr(scene.scene_contact, f)
                                                        for f in EFFECT_FIELDS[effect]})
        asked = Equations.from_scene(dataclasses.replace(scene, contact=swapped))
        a_asked, _ = accelerations(asked, states)
        force = (a_judged - a_asked) * scale
        size = np.hypot(force[:, 0], force[:, 1]) if effect != "rolling" else np.abs(force[:, 2])
        i = int(np.argmax(size))
        if effect != "rolling" and size[i] <= SAME_LAW * largest:
            continue
        rows.append({"effect": effect, "step": i, "t": float(t[i]), "force": [float(v) for v in force[i]],
                     "largest": float(size[i]), "unit": "N m" if effect == "rolling" else "N"})
    return rows


# The parameters' units, for the words
UNITS = {"k": "N/m", "c": "N s/m", "dissipation": "s/m", "alpha": "s/m", "mu": "", "mu_roll": "m",
         "roll_sharpness": "s/rad"}


def _value(name: str, value) -> str:
    unit = UNITS.get(name, "")
    return f"{name} {value:.3g}" + (f" {unit}" if unit else "") if isinstance(value, (int, float)) else f"{name} {value}"


def _side(family: str, shared: str, side: dict, against: dict) -> str:
    """One side's family and its parameters that differ from the other side's as printed: the
    shared one (k, mu, mu_roll) and the family's own, never one the family does not take (c
    under hunt_crossley)."""
    own = LAW_PARAMETERS[family].get(side[family], ())
    shown = [p for p in (shared, *own) if _value(p, side[p]) != _value(p, against[p])]
    return " ".join([side[family], *(_value(p, side[p]) for p in shown)])


def judged_law_words(law: dict) -> str | None:
    """What metrics.json's `law` block says in one clause, for the run line and index.md: None
    where the scene's own law was judged; else 'the identified law: friction smooth_coulomb mu
    0.4, the scene asks tanh mu 0.5' (each effect that differs, its family and every parameter
    that differs), or 'the identified law, the scene's own on every effect'."""
    if not law or law.get("from", "scene") == "scene" or "scene" not in law:
        return None
    source = "the identified law" if law["from"] == "identified" else f"the law of {law['from']}"
    judged, asked = law["judged"], law["scene"]
    words = []
    for d in law.get("differences") or []:
        family, shared = EFFECT_FIELDS[d["effect"]][:2]
        mine, theirs = _side(family, shared, judged, asked), _side(family, shared, asked, judged)
        words.append(f"{d['effect']} {mine}, the scene asks {theirs}")
    return f"{source}: " + "; ".join(words) if words else f"{source}, the scene's own on every effect"


def _component(value: float, scale: float) -> str:
    """A force component of a difference, 0 where it is below SAME_LAW of the difference's size
    (never a number of round-off, never -0)."""
    return "0" if abs(value) <= SAME_LAW * scale else f"{value:+.3g}"


def law_lines(scene: Scene, differences: list[dict]) -> list[str]:
    """The page's opening lines on the law: the one judged beside the scene's, and each effect
    that differs with its difference at a named moment."""
    if scene.scene_contact is None:
        return []
    lines = [f"Judged under the law from **{scene.law_from}**: {law_text(scene.contact)}.", "",
             f"The scene asks: {law_text(scene.scene_contact)}.", ""]
    if not differences:
        lines += ["The two laws agree on every effect this scene has.", ""]
    for d in differences:
        fx, fy, tau = d["force"]
        big = d["largest"]
        what = (f"torque {tau:+.3g} N m" if d["effect"] == "rolling"
                else f"force ({_component(fx, big)}, {_component(fy, big)}) N, torque {_component(tau, big)} N m")
        lines.append(f"- **{d['effect']}** differs: at step {d['step']} (t = {d['t']:.6g} s) the judged law "
                     f"gives {what} more than the scene's ({d['largest']:.3g} {d['unit']}, the largest over the run).")
    lines.append("")
    return lines
