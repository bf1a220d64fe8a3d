"""The identification printed: a readable table per scene, or one JSON object per scene."""
from __future__ import annotations

import json
import math

UNITS = {"k": "N/m", "c": "N s/m", "dissipation": "s/m", "mu": "", "alpha": "s/m", "mu_roll": "m",
         "roll_sharpness": "s/rad"}
PARAMS = {"normal": ("k", "c", "dissipation"), "friction": ("mu", "alpha"), "rolling": ("mu_roll", "roll_sharpness")}
RESIDUAL_UNIT = {"normal": "N", "friction": "N", "rolling": "N m"}


def json_safe(value):
    """Plain JSON: numpy numbers as floats, non-finite numbers as null."""
    if isinstance(value, dict):
        return {str(k): json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    if hasattr(value, "item") and not isinstance(value, (str, bytes)):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def as_json(result: dict) -> str:
    return json.dumps(json_safe(result))


def _g(x, unit: str = "") -> str:
    return "–" if x is None else (f"{x:.10g} {unit}".rstrip())


def params_text(entry: dict, effect: str) -> str:
    parts = []
    for p in PARAMS[effect]:
        v = entry.get(p)
        if v is None or (p in ("c", "dissipation") and v == 0.0 and entry.get("law") is not None
                         and (p == "c") == (entry.get("law") == "hunt_crossley")):
            continue
        parts.append(f"{p} {_g(v, UNITS[p])}")
    return ", ".join(parts)


def _match(result: dict, key: str) -> str:
    m = result.get("matches_scene", {}).get(key)
    return "" if m is None else ("  = scene" if m else "  ≠ scene")


def _effect_line(result: dict, effect: str) -> str:
    e = result[effect]
    if not e.get("exercised", True) and e.get("law") is None:
        return f"  {effect:<11} not exercised: {e.get('why', '')}"
    unit = RESIDUAL_UNIT[effect]
    if e.get("read") is False:
        return f"  {effect:<11} {e['why']}{_match(result, effect)}"
    if e["law"] is not None:
        text = (f"{e['law']} ({params_text(e, effect)})" if params_text(e, effect) else e["law"])
        text += f"; residual {e['residual']:.2g} {unit} = {e['relative']:.2g} of round-off"
        if e.get("also_fit"):
            text += f"; equally: {', '.join(e['also_fit'])}"
    else:
        c = e.get("closest", {})
        text = (f"no family fits; closest {c.get('law')} ({params_text(c, effect)}), residual "
                f"{c.get('residual', float('nan')):.3g} {unit} = {c.get('relative', float('nan')):.3g} x round-off")
    if e.get("onset") is not None and e.get("law") is None and e.get("onset_seen") is not None:
        text += f"; a force acts up to {e['onset_seen']:.6g} m above the ground (the highest step of the run with one)"
    elif e.get("onset") is not None:
        text += (f"; the force begins {abs(e['onset']):.6g} m {'above' if e['onset'] > 0 else 'below'} the ground "
                 f"at each contact point (depths measured from there)")
    if not e.get("exercised", True):
        text += f" (not exercised: {e.get('why', '')})"
    elif e.get("why"):
        text += f" ({e['why']})"
    return f"  {effect:<11} {text}{_match(result, effect)}"


def text(result: dict) -> str:
    """A few lines per scene: each effect's family and parameters, or what came closest."""
    src = {"step": f"{result.get('calls', 0)} designed calls", "whole": f"{result.get('steps', 0)} steps of its run",
           "trajectories": f"{result.get('steps', 0)} steps of its CSV"}.get(result.get("from"), "")
    lines = [f"{result['scene']}  ({src}, {result.get('seconds', 0.0):.2f} s)"]
    it = result["integrator"]
    if it["name"] is not None:
        lines.append(f"  {'integrator':<11} {it['name']} ({it.get('why', '')}){_match(result, 'integrator')}")
    else:
        c = it.get("closest", {})
        closest = f"closest {c.get('name')}, {c.get('residual', float('nan')):.3g} x round-off"
        if it.get("why", "").startswith("none:"):   # the measurements: beta, and whether the force depends on dt
            closest = (f"closest in beta {c.get('name')}, its position update {c.get('residual', float('nan')):.3g} x "
                       f"round-off")
            lines.append(f"  {'integrator':<11} {it['why']}; {closest}{_match(result, 'integrator')}")
        else:
            lines.append(f"  {'integrator':<11} none of the four ({it.get('why', '')}; {closest})"
                         f"{_match(result, 'integrator')}")
    gr = result["gravity"]
    if gr.get("exercised") is False:
        lines.append(f"  {'gravity':<11} not exercised: {gr.get('why', '')}")
    elif gr["g"] is not None:
        lines.append(f"  {'gravity':<11} g {gr['g']:.10g} m/s^2; residual {gr['residual']:.2g} m/s^2 = "
                     f"{gr['relative']:.2g} of round-off{_match(result, 'gravity')}")
    else:
        c = gr.get("closest", {})
        lines.append(f"  {'gravity':<11} not a constant g (closest {_g(c.get('g'), 'm/s^2')}, "
                     f"{c.get('relative', float('nan')):.3g} x round-off){_match(result, 'gravity')}")
    for effect in ("normal", "friction", "rolling"):
        lines.append(_effect_line(result, effect))
    b = result["body"]
    pts = b.get("contact_points") or []
    shown = "; ".join("–" if p is None else f"({p[0]:.6g}, {p[1]:.6g})" for p in pts)
    inertia = "–" if b.get("inertia") is None else f"{b['inertia']:.10g} kg m^2"
    res = "" if b.get("residual") is None else (f"; torque residual {b['residual']:.2g} N m = "
                                                f"{b['relative']:.2g} of round-off")
    if b.get("rotates") is False:   # a point: what is checked is that the step does not turn it
        inertia = "– (a point mass does not turn)"
        res = "" if b.get("residual") is None else (f"; angular acceleration {b['residual']:.2g} rad/s^2 = "
                                                    f"{b['relative']:.2g} of round-off")
        if b.get("relative") is not None and b["relative"] > 1:
            inertia = "– (the step turns the point mass, which has nothing to turn it)"
    elif b.get("relative") is not None and b["relative"] > 1:   # the fitted inertia is only the closest
        inertia = (f"none reproduces the torque (the forces found times their arms, r x F, for any "
                   f"inertia); closest {inertia}")
    elif b.get("inertia") is not None and b["inertia"] < 0:
        inertia += " (negative: the torque turns the body the wrong way)"
    why = f" ({b['why']})" if b.get("why") else ""
    lines.append(f"  {'body':<11} mass {b['mass']:g} kg (the scene's: the unit of every force), inertia {inertia}"
                 f"{res}{why}{_match(result, 'body')}")
    where = b.get("contact_points_from") or (f"found where contact begins, to {b.get('points_residual', 0):.2g} m"
                                             if pts else "")
    lines.append(f"  {'':<11} contact points {shown} m ({where})")
    if b.get("not_found"):
        lines.append(f"  {'':<11} never found touching: point {', '.join(map(str, b['not_found']))}")
    return "\n".join(lines)
