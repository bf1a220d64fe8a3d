"""The identified law as the scene's own types: a Contact for `run --law identified`, and the scene."""
from __future__ import annotations

import dataclasses

from scene_types.schema import Contact, Scene

# How each effect's identified family is written into a Contact: the [contact] field naming the
# family, the parameters it takes, and the neutral value of one it does not take.
_FIELDS = {"normal": ("damping_law", {"c": 0.0, "dissipation": 0.0}),
           "friction": ("friction_law", {"alpha": None}),
           "rolling": ("roll_law", {"roll_sharpness": None})}


class NotIdentified(ValueError):
    """An effect the scene needs has no identified family (law null)."""


def identified_contact(scene: Scene, identification: dict) -> Contact:
    """dataclasses.replace of the scene's Contact with each exercised effect's identified family
    and parameters. "none" (the step applies no friction or rolling resistance) becomes mu = 0
    (mu_roll = 0) under the scene's family: the same forces. An effect not exercised keeps the
    scene's, and so does one the scene's own law reproduces to round-off (a fitted c of 3e-16
    where the scene has 0 is that 0). Raises NotIdentified where an exercised effect's law is None,
    or where the force begins away from the contact points (an onset no [contact] table holds)."""
    changes: dict = {}
    onset = (identification.get("normal") or {}).get("onset")
    if onset is not None:
        raise NotIdentified(f"{identification.get('scene', scene.name)}: normal: the force begins {onset:.6g} m "
                            f"{'above' if onset > 0 else 'below'} the ground, not at the contact points, which no "
                            f"[contact] law can say; no identified law to run")
    for effect, (field, neutral) in _FIELDS.items():
        entry = identification.get(effect) or {}
        if not entry.get("exercised"):
            continue
        law = entry.get("law")
        scene_fits = entry.get("scene_relative")
        if scene_fits is not None and scene_fits <= 1.0:
            continue   # the scene's own family and parameters reproduce the step: keep them exactly
        if law is None:
            closest = (entry.get("closest") or {}).get("law")
            raise NotIdentified(f"{identification.get('scene', scene.name)}: {effect}: no family reproduces the step "
                                f"(closest {closest}); no identified law to run")
        if law == "none":
            changes["mu" if effect == "friction" else "mu_roll"] = 0.0
            continue
        changes[field] = law
        values = dict(neutral)
        for key in ("k", "c", "dissipation") if effect == "normal" else (
                ("mu", "alpha") if effect == "friction" else ("mu_roll", "roll_sharpness")):
            if entry.get(key) is not None:
                values[key] = float(entry[key])
        if effect == "friction" and law == "sign":
            values["alpha"] = None
        if effect == "rolling" and law == "sign":
            values["roll_sharpness"] = None
        changes.update(values)
    return dataclasses.replace(scene.contact, **changes)


def identified_scene(scene: Scene, identification: dict) -> Scene:
    """The scene with its Contact identified and, where the gravity found differs, that g."""
    g = (identification.get("gravity") or {}).get("g")
    return dataclasses.replace(scene, contact=identified_contact(scene, identification),
                               g=scene.g if g is None else float(g))
