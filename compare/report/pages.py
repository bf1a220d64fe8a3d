"""The report: DIR/index.md and one folder per scenario (metrics.json, CSVs, model.xml, plots).

Every folder is written beside its final place and renamed into it when complete, and
index.md is replaced in one step, so an interrupted run never leaves a half-written report.
"""
from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path

from custom_sim import write_csv

from ..verdict import metrics
from . import plots
from ..verdict.comparison import Result, metrics_json

TERM_CAUSES = {
    "impedance": "MuJoCo's penalty row reproduces k d + c v up to a relative 1e-4 (its impedance d = 1e-4 times "
                 "the gap between the contact's true inverse inertia and the constant A_hat it is scaled by).",
    "switching": "each simulator starts and ends a contact on its own step grid, so a switch can lag by a step.",
    "damping law": "the scene damps only while the body approaches the ground (the seed's compression law); "
                   "MuJoCo damps both ways, clamped at zero, so its body rebounds lower and lands at other times.",
    "friction": "MuJoCo's friction (penalty mapping) is viscous with tanh's slope at rest, capped at mu Fn; ours "
                "is mu Fn tanh(alpha v): both brake at mu g while sliding fast, and part in the slow tail before "
                "the body stops.",
    "impact friction": "when a corner lands, its slip passes through zero; there ours grips within 1/alpha "
                       "of zero slip and MuJoCo's viscous row within mu Fn / c_t, which is wider at impact forces, "
                       "so the body leaves each landing with a slightly different spin and slide.",
    "rolling": "MuJoCo's rolling resistance shares one friction cone with sliding: while the disk slides it is "
               "about zero, ours is mu_roll Fn from the start, so ours rolls away a little slower.",
}


def _fmt(x, unit: str = "") -> str:
    if x is None:
        return "–"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, float) and (x == 0 or 1e-3 <= abs(x) < 1e4):
        return f"{x:.4g}{unit}"
    return f"{x:.2e}{unit}" if isinstance(x, float) else f"{x}{unit}"


def _write_atomically(path: Path, text: str) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)


def write_scenario(result: Result, out: Path, mjcf: str) -> dict:
    """Write DIR/<name>/ for a scenario that ran; returns its metrics.json content."""
    scene = result.scene
    final = out / scene.name
    tmp = Path(tempfile.mkdtemp(dir=out, prefix=f".{scene.name}."))
    try:
        data = metrics_json(result)
        (tmp / "metrics.json").write_text(json.dumps(data, indent=2, allow_nan=False) + "\n")
        write_csv(result.custom, tmp / "trajectory_custom.csv")
        write_csv(result.mujoco, tmp / "trajectory_mujoco.csv")
        (tmp / "model.xml").write_text(mjcf)
        diffs = metrics.differences(result.custom, result.mujoco)
        figures = {
            "states": plots.states(scene, result.custom, result.mujoco, tmp / "states.png"),
            "path": plots.path_in_plane(scene, result.custom, result.mujoco, tmp / "path.png"),
            "error": plots.error(scene, diffs, result.tolerance, tmp / "error.png"),
            "energy": plots.energy(scene, result.custom, result.mujoco, tmp / "energy.png"),
            "snapshots": plots.snapshots(scene, result.custom, result.mujoco, tmp / "snapshots.png"),
        }
        (tmp / "index.md").write_text(scenario_page(result, data, figures))
        if final.exists():
            shutil.rmtree(final)
        os.replace(tmp, final)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return data


def scenario_page(result: Result, data: dict, figures: dict) -> str:
    scene, tol = result.scene, result.tolerance
    twin = result.mujoco
    ev_c, ev_m = data["events_custom"], data["events_mujoco"]
    lines = [
        f"# {scene.name}",
        "",
        scene.description,
        "",
        f"**{'PASS' if result.passed else 'FAIL'}**: the largest position difference is "
        f"{_fmt(data['position_error_max'], ' m')} at t = {_fmt(data['time_of_position_error_max'], ' s')} "
        f"(tolerance {_fmt(tol.position, ' m')}), the largest angle difference {_fmt(data['angle_error_max'], ' rad')} "
        f"(tolerance {_fmt(tol.angle, ' rad')}).",
        "",
        "## The scene",
        "",
        "| | |",
        "|---|---|",
        f"| body | {scene.body.shape}, {_fmt(scene.body.mass, ' kg')} |",
        f"| effects | {', '.join(scene.effects) or 'none'} |",
        f"| contact | k = {_fmt(scene.contact.k, ' N/m')}, c = {_fmt(scene.contact.c, ' N s/m')}, "
        f"damping law {scene.contact.damping_law}, mu = {scene.contact.mu}, alpha = {scene.contact.alpha} s/m, "
        f"mu_roll = {scene.contact.mu_roll} m |",
        f"| custom_sim | {scene.integrator}, dt = {scene.dt:g} s, {scene.steps} steps, "
        f"{result.custom.force_evals} force evaluations, {_fmt(result.custom.wall_time, ' s')} |",
        f"| MuJoCo | {twin.integrator}, dt = {twin.dt:g} s, solref mapping `{scene.mujoco.solref}`, "
        f"cone {scene.mujoco.cone}, {_fmt(twin.wall_time, ' s')} |",
        f"| stability | theory allows dt < {_fmt(data['stable_dt_theory'], ' s')} for {scene.integrator} |",
        f"| source | `{scene.source}`; MuJoCo model: [model.xml](model.xml) |",
        "",
        "## Trajectories",
        "",
        f"![states]({figures['states']})",
        "",
        f"![path]({figures['path']})",
        "",
        f"![snapshots]({figures['snapshots']})",
        "",
        "## Difference and energy",
        "",
        f"![error]({figures['error']})",
        "",
        f"![energy]({figures['energy']})",
        "",
        f"Energy drift E(end) - E(0): custom_sim {_fmt(data['energy_drift_custom'], ' J')}, "
        f"MuJoCo {_fmt(data['energy_drift_mujoco'], ' J')} (E(0) = {_fmt(data['energy_initial'], ' J')}).",
        "",
        "## Events",
        "",
        "| event | custom_sim | MuJoCo |",
        "|---|---|---|",
        f"| first contact (s) | {_fmt(ev_c['first_contact_time'])} | {_fmt(ev_m['first_contact_time'])} |",
        f"| bounce apex heights (m) | {', '.join(f'{h:.4f}' for h in ev_c['bounce_apex_heights'][:4]) or '–'} "
        f"| {', '.join(f'{h:.4f}' for h in ev_m['bounce_apex_heights'][:4]) or '–'} |",
        f"| restitution implied | {', '.join(f'{e:.3f}' for e in ev_c['restitution'][:4]) or '–'} "
        f"| {', '.join(f'{e:.3f}' for e in ev_m['restitution'][:4]) or '–'} |",
        f"| at rest from (s) | {_fmt(ev_c['rest_time'])} | {_fmt(ev_m['rest_time'])} |",
    ]
    if "rolling_time" in ev_c:
        lines.append(f"| rolling without slip from (s) | {_fmt(ev_c['rolling_time'])} | {_fmt(ev_m['rolling_time'])} |")
    pc, pm = ev_c["final_pose"], ev_m["final_pose"]
    lines += [
        f"| final pose x, y, theta | {pc['x']:.4f} m, {pc['y']:.4f} m, {pc['theta']:.4f} rad "
        f"| {pm['x']:.4f} m, {pm['y']:.4f} m, {pm['theta']:.4f} rad |",
        "",
        "## The three solref mappings",
        "",
        "How MuJoCo's soft contact is set from k and c (docs/physics.md, \"Three ways to set solref\"). Only the scene's own mapping is judged.",
        "",
        "| mapping | max position difference | RMS | max angle difference | MuJoCo energy drift | verdict |",
        "|---|---|---|---|---|---|",
    ]
    for mapping, row in result.by_mapping.items():
        if "error" in row:
            lines.append(f"| {mapping} | diverged | | | | {row['error']} |")
            continue
        verdict = "not judged" if row["pass"] is None else ("pass" if row["pass"] else "FAIL")
        lines.append(f"| {mapping}{' (scene)' if mapping == scene.mujoco.solref else ''} "
                     f"| {_fmt(row['position_error_max'], ' m')} | {_fmt(row['position_error_rms'], ' m')} "
                     f"| {_fmt(row['angle_error_max'], ' rad')} | {_fmt(row['energy_drift_mujoco'], ' J')} | {verdict} |")
    lines += ["", "## Why the two differ", ""]
    for name, value in tol.terms.items():
        lines.append(f"- **{name}** (up to {_fmt(value, ' m')}): {TERM_CAUSES[name]}")
    for note in twin.meta.get("approximations", []):
        lines.append(f"- {note}")
    lines += ["", f"Tolerance: {tol.reason}.", ""]
    ab = result.ablation
    if ab:
        lines += [
            "### With friction off",
            "",
            f"The same scene run in both simulators with effects {', '.join(ab['effects'])}: the largest position "
            f"difference is {_fmt(ab['position_error_max'], ' m')} (tolerance {_fmt(ab['tolerance_position'], ' m')}), "
            f"the largest angle difference {_fmt(ab['angle_error_max'], ' rad')} "
            f"(tolerance {_fmt(ab['tolerance_angle'], ' rad')}): **{'pass' if ab['pass'] else 'FAIL'}**. "
            "What remains with friction on is the difference between the two friction laws.",
            "",
        ]
    return "\n".join(lines)


def index_page(rows: list[dict], failures: list[tuple[str, str]]) -> str:
    lines = [
        "# Comparison report: custom_sim against MuJoCo",
        "",
        "One row per scenario. *pos. max* and *pos. RMS* are the distance between the two centres of mass "
        "(max and root-mean-square over the run), *angle max* the largest angle difference, *drift* the energy "
        "E(end) - E(0) of each simulator, *time* the wall time of the stepping alone. A scenario passes when "
        "both differences stay within its tolerance, derived from the physics the two models do not share "
        "(see each page's *Why the two differ*).",
        "",
        "| scenario | body | integrator | dt (s) | pos. max (m) | pos. RMS (m) | angle max (rad) | tolerance (m) "
        "| drift custom (J) | drift MuJoCo (J) | time custom (s) | time MuJoCo (s) | result |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| [{r['name']}]({r['name']}/index.md) | {r['shape']} | {r['integrator']} | {r['dt']:g} "
            f"| {_fmt(r['position_error_max'])} | {_fmt(r['position_error_rms'])} | {_fmt(r['angle_error_max'])} "
            f"| {_fmt(r['tolerance']['position'])} | {_fmt(r['energy_drift_custom'])} | {_fmt(r['energy_drift_mujoco'])} "
            f"| {_fmt(r['wall_time_custom'])} | {_fmt(r['wall_time_mujoco'])} | {'pass' if r['pass'] else '**FAIL**'} |")
    for name, why in failures:
        lines.append(f"| {name} | | | | | | | | | | | | **diverged**: {why} |")
    lines.append("")
    return "\n".join(lines)


def write_index(out: Path, rows: list[dict], failures: list[tuple[str, str]]) -> Path:
    path = out / "index.md"
    _write_atomically(path, index_page(rows, failures))
    return path


def summary_table(rows: list[dict]) -> str:
    """The index table alone (for the README)."""
    text = index_page(rows, [])
    return "\n".join(line for line in text.splitlines() if line.startswith("|"))

