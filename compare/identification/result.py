"""The identification as plain data: one dict per effect, and whether each matches the scene."""
from __future__ import annotations

import math

import numpy as np

from .fit import Fit, resolved

# Each effect's parameters in the answer, and the value one its family does not take holds
# (as in the scene's [contact]: c 0 under hunt_crossley, dissipation 0 otherwise, alpha and
# roll_sharpness None under a sign law; mu and mu_roll 0 under "none").
PARAMETERS = {"normal": {"k": None, "c": 0.0, "dissipation": 0.0},
              "friction": {"mu": 0.0, "alpha": None},
              "rolling": {"mu_roll": 0.0, "roll_sharpness": None}}


def _num(x):
    if x is None:
        return None
    x = float(x)
    return x if math.isfinite(x) else None


def _params(effect: str, fit: Fit) -> dict:
    """The family's parameters, rounded to what the probes resolve of them where that is known
    (fit.extra["shown"]: the designed Euler fits, fit.rounded)."""
    out = dict(PARAMETERS[effect])
    shown = fit.extra.get("shown") or fit.params
    out.update({k: _num(v) for k, v in zip(fit.family.params, shown)})
    return out


def not_exercised(why: str) -> dict:
    return {"exercised": False, "law": None, "why": why}


def effect_entry(effect: str, named: Fit | None, also: list[str], closest: Fit | None, fits: list[Fit],
                 scene_fit: Fit | None) -> dict:
    """law and parameters when a family reproduces the step to round-off; else law None and the
    closest family under "closest". residual: the largest (N, or N m for rolling); relative:
    over the round-off bound (<= 1: reproduces). `families`: every family's relative residual."""
    out = {"exercised": True}
    if named is not None:
        out.update(law=named.family.name, **_params(effect, named), residual=named.residual,
                   relative=named.relative)
        if also:
            out["also_fit"] = also
    else:
        out.update(law=None, **{k: None for k in PARAMETERS[effect]}, residual=None, relative=None)
        if closest is not None:
            out["closest"] = {"law": closest.family.name, **_params(effect, closest),
                              "residual": closest.residual, "relative": closest.relative}
    out["families"] = {f.family.name: f.relative for f in fits}
    out["scene_relative"] = None if scene_fit is None else scene_fit.relative
    return out


def unread_entry(effect: str, largest: float, bound: float) -> dict:
    """An effect whose probes saw nothing above round-off: no law, and the largest force seen."""
    unit = "N m" if effect == "rolling" else "N"
    return {"exercised": True, "read": False, "law": None, **{k: None for k in PARAMETERS[effect]},
            "residual": None, "relative": None, "largest_force": largest, "scene_relative": None,
            "why": f"the law could not be read: no probe saw a load above 100 x round-off (largest {effect} force "
                   f"{largest:.2g} {unit}, round-off {bound:.2g} {unit})"}


def gravity_entry(g: float, residual: float, relative: float, scene_relative: float) -> dict:
    """g (m/s^2) when the flight steps are a constant -g to round-off, else None and "closest"."""
    if relative <= 1.0:
        return {"g": g, "residual": residual, "relative": relative, "scene_relative": scene_relative}
    return {"g": None, "residual": None, "relative": None, "scene_relative": scene_relative,
            "closest": {"g": g, "residual": residual, "relative": relative}}


def integrator_entry(name, closest: str, relative: float, tests: dict, why: str, scene) -> dict:
    """name (None: none of the four), residual: the largest of its tests over their round-off
    bounds (for RK4, the contact probes stepped by RK4 under the laws found too); `tests`: each
    integrator's law-free residual."""
    from .integrators import NAMES
    out = {"name": name, "residual": relative, "why": why, "tests": {k: tests.get(k) for k in NAMES if k in tests}}
    if "beta" in tests:   # the measurements the name rests on (designed probes; a run: beta only)
        out["beta"] = tests["beta"]
        out["beta_uncertainty"] = tests.get("beta_uncertainty")
        out["depends_on_dt"] = tests.get("depends_on_dt")
    if "parts" in tests:   # each method's position-update test alone (what `closest` is chosen by)
        out["position_tests"] = {k: v.get("position") for k, v in tests["parts"].items()}
    if name is None:
        out["closest"] = {"name": closest, "residual": relative}
    return out


def body_entry(law_s, fit: dict | None, found, missing: list[int], scene, turn=None, rotates=True) -> dict:
    """mass (the scene's: the unit every force is read in), inertia, contact points (each found
    where contact begins; None for a point that is never the lowest), their residual (m)."""
    pts = [None] * len(law_s.geometry.points)
    worst_m = worst_rel = 0.0
    match = True
    for f in found or []:
        lx, ly = f.point
        if lx is None and fit is not None and np.isfinite(fit.get("lx", np.nan)):
            lx = fit["lx"]
        if lx is None:
            lx = float(law_s.geometry.points[f.index, 0])
        unc = np.where(np.isfinite(f.uncertainty), f.uncertainty, 0.0)   # digits below it are not the point's
        pts[f.index] = [resolved(float(lx), float(unc[0]) or None), resolved(float(ly), float(unc[1]) or None)]
        worst_m, worst_rel = max(worst_m, f.residual), max(worst_rel, f.relative)
        unc = f.uncertainty
        want = law_s.geometry.points[f.index]
        off = np.abs(np.array([lx, ly]) - want)
        lim = np.where(np.isfinite(unc), unc, 0.0)
        if f.point[0] is None and fit is not None and np.isfinite(fit.get("lx", np.nan)):
            lim[0] = np.inf   # the circle's arm is judged by the torque fit
        match &= bool(np.all(off <= np.maximum(lim, 0.0)))
    out = {"mass": law_s.mass, "inertia": None if fit is None else fit["inertia"], "contact_points": pts,
           "points_rotate": turn, "residual": None if fit is None else fit["residual"],
           "relative": None if fit is None else fit["relative"],
           "points_residual": worst_m, "points_relative": worst_rel, "rotates": bool(rotates)}
    if not rotates and fit is not None:
        out["inertia"] = 0.0
    never = [i for i, p in enumerate(pts) if p is None and i not in missing]
    if never and found:
        out["not_probed"] = never
    if missing:
        out["not_found"] = missing
    out["points_match"] = bool(match and not missing and (turn is None or turn == law_s.geometry.rotate)
                               and found is not None)
    out["scene_relative"] = None if fit is None else fit.get("scene_relative")
    return out


def settle_body(out: dict, rests_on: tuple[str, ...]) -> None:
    """The inertia is a finding only where it reproduces every torque (relative <= 1) and every
    exercised effect whose force enters the torque (rests_on) is identified; otherwise
    body.inertia is None and what was fitted moves under body.closest."""
    b = out["body"]
    if not b.get("rotates", True) or (b.get("inertia") is None and "closest" not in b):
        return
    failed = [e for e in rests_on if out.get(e, {}).get("exercised") and out[e].get("law") is None]
    rel = b.get("relative")
    if "closest" not in b and not failed and rel is not None and rel <= 1.0:
        return
    b.setdefault("closest", {"inertia": b["inertia"], "residual": b.get("residual"), "relative": rel})
    b.update(inertia=None, residual=None, relative=None)
    if failed and not b.get("why"):
        b["why"] = (f"not identified: the {' and the '.join(failed)} fit{'s' if len(failed) == 1 else ''} no family, "
                    "and {} force enters the torque".format("its" if len(failed) == 1 else "their"))


def matches(out: dict, scene) -> dict:
    """Per effect: whether the scene's own law (its family and parameters) reproduces the step to
    round-off; None for an effect not exercised."""
    m = {"integrator": out["integrator"]["name"] == scene.integrator}
    sr = out["gravity"].get("scene_relative")
    m["gravity"] = None if sr is None else bool(sr <= 1.0)
    for effect in ("normal", "friction", "rolling"):
        e = out[effect]
        m[effect] = None if not e["exercised"] else bool(e["scene_relative"] is not None and e["scene_relative"] <= 1.0)
    b = out["body"]
    m["body"] = None if b.get("scene_relative") is None else bool(b["points_match"] and _same_inertia(b, scene))
    return m


# A fitted inertia carries the round-off of the torques it is read from (about 1e-12 of it): two
# inertias this close are the same body; a wrong formula moves it by a factor
INERTIA_RTOL = 1e-9


def _same_inertia(body: dict, scene) -> bool:
    """The scene's own inertia reproduces the torques to round-off (the file's rounding included),
    or the inertia found is the scene's (the oracle's geometry) where the scene's law does not
    reproduce them (another law: the torques then say nothing of the scene's inertia alone) and
    the inertia found does (a body no inertia reproduces is no body's, the scene's included)."""
    from compare.oracle.rigid_body import rigid_body

    if body["scene_relative"] <= 1.0:
        return True
    found = body.get("inertia")
    if found is None or not math.isfinite(found):
        return False
    if body.get("relative") is not None and not body["relative"] <= 1.0:
        return False
    want = rigid_body(scene.body).inertia if rigid_body(scene.body).rotates else 0.0
    return abs(found - want) <= INERTIA_RTOL * max(abs(want), np.finfo(float).tiny)
