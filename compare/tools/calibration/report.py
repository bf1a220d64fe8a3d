"""Write a calibration: DIR/index.md, DIR/calibration.json, DIR/model_<scene>.xml and plots.

calibration.json (every length in m, angle in rad):
    parameters       {name: gain or value the calibrated twin carries}: the fit's, or the
                     start (the base mapping's) when the fit was rejected
    fitted_parameters  {name: what the optimiser returned}
    status           the optimiser's termination message, and "; fit rejected: ..." when the
                     fit was worse than the base mapping on a scene it was fitted to;
                     optimiser_status, converged: bool, accepted: bool, verdict (a sentence)
    gave_up[]        each fitted scene the fit made worse: scene, position_error_max and
                     angle_error_max {base mapping, fitted}, residual_rms {...}, why
    scenes[]         name, held_out, position_error_max {seed, physical, penalty, calibrated},
                     angle_error_max {...}, settings (the calibrated pair values), causes;
                     rejected_fit {position_error_max, angle_error_max} when rejected
    fit              start values, bounds, at_bound, iterations, objective per iteration
                     (dimensionless: 0.5 sum over scenes of the mean over steps of (difference /
                     the start's largest)^p, fit.py), p_norm, `scales` {scene: {position: m,
                     angle: rad or null}} (the start's largest differences), ratios {scene:
                     largest ratio at the values returned}, step_back (fraction of the
                     optimiser's step kept), optimiser_values {name: where the optimiser
                     itself ended}, wall_time (s), mujoco_steps, residual_evaluations,
                     readback ok
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from mujoco_models import MAPPINGS  # noqa: E402

from ...files import finite_json, write_text_atomically  # noqa: E402
from ...table import markdown, number  # noqa: E402
from .calibration import Calibration  # noqa: E402
from .causes import causes, short  # noqa: E402
from .fit import P_NORM  # noqa: E402

COLUMNS = (*MAPPINGS[::-1], "calibrated")   # seed, physical, penalty, calibrated


def _m(x) -> str:
    """An error: 3 significant digits, "diverged" where the run has none."""
    return number(x, none="diverged")


def _vec(v) -> str:
    return " ".join(f"{x:.4g}" for x in v)


def payload(cal: Calibration) -> dict:
    r = cal.result
    kept = r.values if cal.values is None else cal.values
    return {
        "parameters": dict(zip(r.parameters, map(float, kept))),
        "fitted_parameters": r.parameters,
        "status": r.status if cal.accepted else f"{r.status}; {cal.verdict}",
        "optimiser_status": r.status,
        "converged": r.converged,
        "accepted": cal.accepted,
        "verdict": cal.verdict,
        "gave_up": cal.gave_up,
        "base_mapping": cal.base,
        "scenes": [{
            "name": s.scene.name, "held_out": s.held_out,
            "position_error_max": {k: s.errors[k]["position_error_max"] for k in COLUMNS},
            "angle_error_max": {k: s.errors[k]["angle_error_max"] for k in COLUMNS},
            "settings": s.settings.as_dict(),
            "model": f"model_{s.scene.name}.xml",
            "causes": [short(c) for c in causes(s.scene)],
            "readback": s.readback,
            **({} if cal.accepted else {"rejected_fit": {
                k: cal.fitted_errors[s.scene.name][k] for k in ("position_error_max", "angle_error_max")}}),
        } for s in cal.scenes],
        "fit": {
            "start": dict(zip(r.parameters, map(float, r.start))),
            "bounds": {p.name: [p.lower, p.upper] for p in cal.params},
            "kinds": {p.name: p.kind for p in cal.params},
            "at_bound": r.at_bound, "iterations": r.iterations, "objective": r.objective,
            "scales": r.scales, "p_norm": P_NORM, "ratios": r.ratios, "step_back": r.step_back,
            "optimiser_values": (None if r.optimiser_values is None
                                 else dict(zip(r.parameters, map(float, r.optimiser_values)))),
            "wall_time": r.wall_time, "mujoco_steps": r.mujoco_steps,
            "residual_evaluations": r.residual_evaluations,
            "jacobian_cost": cal.jacobian,
            "readback_ok": all(row["compiled_equal"] and row["mjcf_equal"]
                               for s in cal.scenes for row in s.readback),
        },
    }


def objective_plot(objective: list[float], path: Path, title: str) -> str:
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.semilogy(range(len(objective)), objective, "o-", color="tab:blue")
    ax.set_xlabel("iteration")
    ax.set_ylabel("objective")
    ax.set_title(title)
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path.name


def error_plot(s, base: str, path: Path) -> str:
    """Position error against time: the base mapping (before) and the calibrated twin (after)."""
    fig, ax = plt.subplots(figsize=(7, 3.5))
    every = slice(None, None, max(1, len(s.t) // 4000))
    curves = [(base, dict(color="tab:orange", label=f"before ({base} mapping)"))]
    if "fitted" in s.paths:   # a rejected fit: the calibrated twin is the base mapping's
        curves.append(("fitted", dict(color="tab:red", label="fitted values (rejected)")))
    else:
        curves.append(("calibrated", dict(color="tab:green", label="after (calibrated)")))
    for key, style in curves:
        d = s.paths[key] - s.reference
        ax.plot(s.t[every], np.hypot(d[:, 0], d[:, 1])[every], lw=1.2, **style)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("|position error| (m)")
    ax.set_title(f"{s.scene.name}{' (held out)' if s.held_out else ' (fitted)'}: residual before and after")
    ax.legend(loc="best")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path.name


def index_page(cal: Calibration, data: dict, figures: dict) -> str:
    r = cal.result
    lines = ["# Calibration of the MuJoCo twin's contact settings", "",
             f"Fitted to custom_sim's trajectories of: {', '.join(s.scene.name for s in cal.scenes if not s.held_out)}; "
             f"held out (never seen by the fit): {', '.join(s.scene.name for s in cal.scenes if s.held_out) or 'none'}. "
             f"Starting point and the settings not fitted: the **{cal.base}** mapping. Optimiser: "
             f"`mujoco.minimize.least_squares` (box bounds, finite differences batched through `mujoco.rollout`).", "",
             f"- status: **{r.status}** ({'converged' if r.converged else 'NOT converged'}) after {r.iterations} iterations",
             f"- cost: {r.wall_time:.1f} s wall time, {r.mujoco_steps:,} MuJoCo steps in {r.residual_evaluations} rollouts",
             f"- objective: {r.objective[0]:.4g} -> {r.objective[-1]:.4g} ((sum over the fitted scenes of the "
             f"mean over steps of (difference / its largest under the {cal.base} mapping)^{P_NORM})^(1/{P_NORM}), "
             f"about the largest of those ratios: a minimax; the largest differences: " + "; ".join(
                 f"{k} {v['position']:.3g} m" + (f", {v['angle']:.3g} rad" if v["angle"] is not None else "")
                 for k, v in r.scales.items()) + ")",
             "- largest difference over the mapping's at the values returned: " + ", ".join(
                 f"{k} {v:.3g}" for k, v in r.ratios.items()) + (
                 "" if r.step_back == 1.0 else f" (after stepping back to {r.step_back:g} of the optimiser's "
                 f"step, where the largest ratio over the scenes is smallest; the optimiser ended at " + ", ".join(
                     f"{p.name} {v:.4g}" for p, v in zip(cal.params, r.optimiser_values)) + ")"),
             f"- **{cal.verdict}**"]
    j = cal.jacobian
    if j:
        lines.append(f"- one Jacobian ({j['columns']} columns, every fitted scene): {j['batched']:.2f} s batched "
                     f"(one mujoco.rollout call per scene, {j['threads']} threads) against {j['one_by_one']:.2f} s "
                     f"one column per call; {'the same numbers' if j['same_numbers'] else 'DIFFERENT numbers'} "
                     f"(load average {j['load_average']:.1f} on {j['cpus']} cores: threads only pay on idle cores)")
    lines.append("")
    if r.at_bound:
        lines += [f"**Stuck on a bound:** {', '.join(r.at_bound)}: the optimum lies outside the box; "
                  f"the setting is compensating for something it cannot model (see below).", ""]
    for g in cal.gave_up:
        pe, ae = g["position_error_max"], g["angle_error_max"]
        lines += [f"**The fit gave up {g['scene']}**, a scene it was fitted to: with the fitted values its "
                  f"largest difference is {_m(pe['fitted'])} m, {_m(ae['fitted'])} rad against "
                  f"{_m(pe[cal.base])} m, {_m(ae[cal.base])} rad with the {cal.base} mapping; {g['why']}. "
                  f"The fit is rejected: the calibrated twin (column *calibrated*, the MJCF files) keeps the "
                  f"{cal.base} mapping's values (column *start*); column *fitted (rejected)* shows what the "
                  f"fit would have given.", ""]
    lines += ["## Fitted settings", ""]
    lines += markdown(["parameter", "kind", "start", f"fitted{'' if cal.accepted else ' (rejected)'}", "bounds",
                       "on a bound"],
                      [[f"`{p.name}`", p.kind, f"{v0:.4g}", f"{v:.4g}", f"[{p.lower:g}, {p.upper:g}]",
                        "**yes**" if any(b.startswith(p.name + " ") for b in r.at_bound) else "no"]
                       for p, v0, v in zip(cal.params, r.start, r.values)]).splitlines()
    lines += ["", "A gain multiplies the base mapping's value of each scene (see docs/calibration.md); the "
              "per-scene values are in calibration.json (`settings`) and in the MJCF files.", "",
              "## Position error max (m) against custom_sim", ""]
    rejected = [] if cal.accepted else ["fitted (rejected)"]
    lines += markdown(["scene", "role", *COLUMNS, *rejected],
                      [[s.scene.name, "held out" if s.held_out else "fitted",
                        *(_m(s.errors[k]["position_error_max"]) for k in COLUMNS),
                        *([] if cal.accepted else [_m(cal.fitted_errors[s.scene.name]["position_error_max"])])]
                       for s in cal.scenes]).splitlines()
    for s in cal.scenes:
        e = {k: s.errors[k]["position_error_max"] for k in COLUMNS}
        best = min((k for k in MAPPINGS if e[k] is not None), key=lambda k: e[k], default=None)
        if cal.accepted and best and (e["calibrated"] is None or e["calibrated"] > e[best]):
            lines.append(f"\n**{s.scene.name}: the calibrated twin is worse than the {best} mapping** "
                         f"({_m(e['calibrated'])} m against {_m(e[best])} m): the fitted settings compensate "
                         f"something a contact setting cannot model in the fitted scenes (see below), and the "
                         f"compensation does not carry over.")
    lines += ["", "Angle error max (rad):", ""]
    lines += markdown(["scene", *COLUMNS], [[s.scene.name, *(_m(s.errors[k]["angle_error_max"]) for k in COLUMNS)]
                                            for s in cal.scenes]).splitlines()
    lines += ["", "## Settings per scene: the three mappings and the calibrated twin", ""]
    settings = []
    for s in cal.scenes:
        rows = dict(cal.mapping_settings.get(s.scene.name, {}))
        rows["calibrated"] = s.settings
        settings += [[s.scene.name, key, _vec(v.solref), _vec(v.solimp), _vec(v.solreffriction),
                      f"{v.friction[0]:.4g}", f"{v.impratio:.4g}"]
                     for key, v in ((k, rows[k]) for k in COLUMNS if k in rows)]
    lines += markdown(["scene", "twin", "solref", "solimp", "solreffriction", "friction (slide)", "impratio"],
                      settings).splitlines()
    lines += ["", "## Objective against iterations", "", f"![objective]({figures['objective']})", "",
              "## Residual before and after", ""]
    for s in cal.scenes:
        lines.append(f"![{s.scene.name}]({figures[s.scene.name]})")
    lines += ["", "## What the fit cannot remove", ""]
    for s in cal.scenes:
        lines.append(f"**{s.scene.name}** (calibrated error {_m(s.errors['calibrated']['position_error_max'])} m):")
        lines += [f"- {c}" for c in causes(s.scene)] + [""]
    lines += ["## Every fitted setting reaches the model", "",
              "Read back from the MjModel compiled from the calibrated spec, and from the MjModel "
              "reloaded from the MJCF written here (6 significant digits).", ""]
    lines += markdown(["scene", "parameter", "field", "fitted", "compiled", "MJCF", "ok"],
                      [[s.scene.name, f"`{row['parameter']}`", row["field"],
                        *(f"{row[k]:.8g}" for k in ("fitted", "compiled", "mjcf")),
                        "yes" if row["compiled_equal"] and row["mjcf_equal"] else "**NO**"]
                       for s in cal.scenes for row in s.readback]).splitlines()
    lines += ["", "## Files", ""] + [f"- [model_{s.scene.name}.xml](model_{s.scene.name}.xml): the calibrated "
                                      f"MJCF of {s.scene.name}" for s in cal.scenes]
    lines += ["- [calibration.json](calibration.json)", "", "Optimiser log:", "", "```", r.log.strip(), "```", ""]
    return "\n".join(lines)


def write_calibration(cal: Calibration, out: Path) -> Path:
    out.mkdir(parents=True, exist_ok=True)
    figures = {"objective": objective_plot(cal.result.objective, out / "objective.png",
                                           "calibration: objective per iteration")}
    for s in cal.scenes:
        figures[s.scene.name] = error_plot(s, cal.base, out / f"residual_{s.scene.name}.png")
        write_text_atomically(out / f"model_{s.scene.name}.xml", s.mjcf)
    data = payload(cal)
    write_text_atomically(out / "calibration.json", finite_json(data, indent=2))
    write_text_atomically(out / "index.md", index_page(cal, data, figures))
    return out / "index.md"


def write_reverse(result, targets, out: Path) -> Path:
    """--reverse: DIR/index.md and DIR/calibration.json with the fitted k, c, mu, alpha."""
    from .reverse import REVERSE_PARAMETERS, UNITS, reverse_errors

    out.mkdir(parents=True, exist_ok=True)
    scenes = []
    for t in targets:
        ct = t.scene.contact
        own = dict(zip(REVERSE_PARAMETERS, (ct.k, ct.c, ct.mu, ct.alpha)))
        before, after = reverse_errors(t, np.ones(4)), reverse_errors(t, result.values)
        scenes.append({"name": t.scene.name, "held_out": False, "mapping": t.mapping,
                       "scene_values": own,
                       "fitted_values": {k: own[k] * g for k, g in zip(REVERSE_PARAMETERS, result.values)},
                       "position_error_max": {"scene": before["position_error_max"],
                                              "calibrated": after["position_error_max"]},
                       "angle_error_max": {"scene": before["angle_error_max"],
                                           "calibrated": after["angle_error_max"]}})
    data = {"parameters": result.parameters, "status": result.status, "converged": result.converged,
            "direction": "reverse", "scenes": scenes,
            "fit": {"at_bound": result.at_bound, "iterations": result.iterations,
                    "objective": result.objective, "wall_time": result.wall_time,
                    "custom_sim_steps": result.extra["custom_steps"],
                    "custom_sim_runs": result.residual_evaluations}}
    fig = objective_plot(result.objective, out / "objective.png", "reverse fit: objective per iteration")
    lines = ["# Reverse calibration: custom_sim's k, c, mu, alpha that follow MuJoCo", "",
             f"- status: **{result.status}** ({'converged' if result.converged else 'NOT converged'}) "
             f"after {result.iterations} iterations",
             f"- cost: {result.wall_time:.2f} s, {result.extra['custom_steps']:,} custom_sim steps in "
             f"{result.residual_evaluations} runs", ""]
    if result.at_bound:
        lines += [f"**Stuck on a bound:** {', '.join(result.at_bound)}", ""]
    lines += markdown(["scene", "MuJoCo mapping", "quantity", "scene file", "fitted (what MuJoCo corresponds to)"],
                      [[s["name"], s["mapping"], k, *(f"{s[v][k]:.5g}" + (f" {UNITS[k]}" if UNITS[k] else "")
                                                      for v in ("scene_values", "fitted_values"))]
                       for s in scenes for k in REVERSE_PARAMETERS]).splitlines()
    lines += [""]
    lines += markdown(["scene", "position error max, scene values (m)", "fitted values (m)"],
                      [[s["name"], _m(s["position_error_max"]["scene"]), _m(s["position_error_max"]["calibrated"])]
                       for s in scenes]).splitlines()
    lines += ["", "As a scene file's `[contact]` table (custom_sim then follows the MuJoCo twin):", ""]
    for s in scenes:
        v = s["fitted_values"]
        lines += [f"{s['name']}:", "", "```toml", "[contact]", f"k = {v['k']:.6g}        # N/m",
                  f"c = {v['c']:.6g}        # N s/m", f"mu = {v['mu']:.6g}",
                  f"alpha = {v['alpha']:.6g}    # s/m", "```", ""]
    lines += ["", f"![objective]({fig})", "", "```", result.log.strip(), "```", ""]
    write_text_atomically(out / "calibration.json", finite_json(data, indent=2))
    write_text_atomically(out / "index.md", "\n".join(lines))
    return out / "index.md"
