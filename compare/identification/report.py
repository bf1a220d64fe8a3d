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


# Significant digits a number is printed to: what float64 carries past a fit's round-off, and
# what float32 resolves (24 bits: 7.2 digits) for a step computing in single precision.
DIGITS = {"float64": 10, "float32": 7}
_DIGITS = {"now": DIGITS["float64"]}


def _g(x, unit: str = "") -> str:
    return "–" if x is None else (f"{x:.{_DIGITS['now']}g} {unit}".rstrip())


def params_text(entry: dict, effect: str) -> str:
    """The parameters of the entry's family only (none for "none", no c for hunt_crossley: the
    JSON's fill-ins for the others are the scene file's, not findings)."""
    from .families import BY_NAME
    fam = BY_NAME.get((effect, entry.get("law")))
    parts = []
    for p in PARAMS[effect] if fam is None else fam.params:
        v = entry.get(p)
        if v is None:
            continue
        parts.append(f"{p} {_g(v, UNITS[p])}")
    return ", ".join(parts)


def residual_text(residual, relative, unit: str, what: str = "residual") -> str:
    """A residual in words: within round-off it is no number of newtons (a 6e-123 N is noise),
    only its share of round-off; beyond, the number and how many times round-off; a
    non-finite one (a force that overflows or is NaN at some probe) as such."""
    if relative is None or residual is None or not (math.isfinite(relative) and math.isfinite(residual)):
        return f"{what} not finite (a non-finite force at some probe)"
    if relative <= 1.0:
        return f"{what} {relative:.2g} of round-off"
    return f"{what} {residual:.3g} {unit} = {relative:.3g} x round-off"


def _num_text(v: float, resolution: float = 0.0) -> str:
    """A coordinate: no -0, nothing below its resolution (m)."""
    return f"{(0.0 if abs(v) <= resolution else v) + 0.0:.6g}"


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
        text += f"; {residual_text(e['residual'], e['relative'], unit)}"
        if e.get("also_fit"):
            text += f"; equally: {', '.join(e['also_fit'])}"
    else:
        c = e.get("closest", {})
        text = (f"no family fits; closest {c.get('law')} ({params_text(c, effect)}), "
                f"{residual_text(c.get('residual'), c.get('relative'), unit)}")
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
    _DIGITS["now"] = DIGITS.get(result.get("precision"), DIGITS["float64"])
    try:
        return _text(result)
    finally:
        _DIGITS["now"] = DIGITS["float64"]


def _text(result: dict) -> str:
    src = {"step": f"{result.get('calls', 0)} designed calls", "whole": f"{result.get('steps', 0)} steps of its run",
           "trajectories": f"{result.get('steps', 0)} steps of its CSV",
           "run": f"{result.get('steps', 0)} steps of its sequential run"}.get(result.get("from"), "")
    single = "; float32 arithmetic: every number it returns is a float32 value, held to single precision's " \
             "round-off" if result.get("precision") == "float32" else ""
    lines = [f"{result['scene']}  ({src}, {result.get('seconds', 0.0):.2f} s{single})"]
    if result.get("keeps_state"):
        lines.append(f"  {'keeps state':<11} {result.get('keeps_state_why', '')}")
    it = result["integrator"]
    if it["name"] is not None:
        lines.append(f"  {'integrator':<11} {it['name']} ({it.get('why', '')}){_match(result, 'integrator')}")
    else:
        c = it.get("closest", {})
        rel = c.get("residual")
        off = (f"{rel:.3g} x round-off" if rel is not None and math.isfinite(rel) else "its test not finite")
        if it.get("why", "").startswith("none:"):   # the measurements: beta, and whether the force depends on dt
            lines.append(f"  {'integrator':<11} {it['why']}; closest in beta {c.get('name')}, its position update "
                         f"{off}{_match(result, 'integrator')}")
        else:
            lines.append(f"  {'integrator':<11} none of the four ({it.get('why', '')}; closest {c.get('name')}, "
                         f"{off}){_match(result, 'integrator')}")
    gr = result["gravity"]
    if gr.get("exercised") is False:
        lines.append(f"  {'gravity':<11} not exercised: {gr.get('why', '')}")
    elif gr["g"] is not None:
        lines.append(f"  {'gravity':<11} g {_g(gr['g'], 'm/s^2')}; {residual_text(gr['residual'], gr['relative'], 'm/s^2')}"
                     f"{_match(result, 'gravity')}")
    else:
        c = gr.get("closest", {})
        lines.append(f"  {'gravity':<11} not a constant g (closest {_g(c.get('g'), 'm/s^2')}, "
                     f"{residual_text(c.get('residual'), c.get('relative'), 'm/s^2')}){_match(result, 'gravity')}")
    for effect in ("normal", "friction", "rolling"):
        lines.append(_effect_line(result, effect))
    b = result["body"]
    pts = b.get("contact_points") or []
    unc = b.get("points_residual") or 0.0
    shown = "; ".join("–" if p is None else f"({_num_text(p[0], unc)}, {_num_text(p[1], unc)})" for p in pts)
    inertia = "–" if b.get("inertia") is None else _g(b["inertia"], "kg m^2")
    res = "" if b.get("residual") is None else f"; {residual_text(b['residual'], b['relative'], 'N m', 'torque residual')}"
    if b.get("rotates") is False:   # a point: what is checked is that the step does not turn it
        inertia = "– (a point mass does not turn)"
        res = "" if b.get("residual") is None else (
            f"; {residual_text(b['residual'], b['relative'], 'rad/s^2', 'angular acceleration')}")
        if b.get("relative") is not None and b["relative"] > 1:
            inertia = "– (the step turns the point mass, which has nothing to turn it)"
    elif b.get("inertia") is None and b.get("closest"):   # the fitted inertia is only the closest
        c = b["closest"]
        near = _g(c.get("inertia"), "kg m^2")
        if c.get("relative") is not None:
            near += f", {residual_text(c['residual'], c['relative'], 'N m', 'torque residual')}"
        inertia = (f"not identified ({b['why'].removeprefix('not identified: ')}); closest {near}" if b.get("why") else
                   f"none reproduces the torque (the forces found times their arms, r x F, for any "
                   f"inertia); closest {near}")
    elif b.get("inertia") is not None and b["inertia"] < 0:
        inertia += " (negative: the torque turns the body the wrong way)"
    why = f" ({b['why']})" if b.get("why") and b.get("inertia") is not None else ""
    lines.append(f"  {'body':<11} mass {b['mass']:g} kg (the scene's: the unit of every force), inertia {inertia}"
                 f"{res}{why}{_match(result, 'body')}")
    where = b.get("contact_points_from") or (f"found where contact begins, to {unc:.2g} m" if pts else "")
    lines.append(f"  {'':<11} contact points {shown} m ({where})")
    if b.get("not_found"):
        lines.append(f"  {'':<11} never found touching: point {', '.join(map(str, b['not_found']))}")
    return "\n".join(lines)
