"""The report: DIR/index.md and one folder per scenario (metrics.json, CSVs, model.xml, plots).

Every folder is written beside its final place and renamed into it when complete, and
index.md is replaced in one step, so an interrupted run never leaves a half-written report.
"""
from __future__ import annotations

import os
import shutil
from pathlib import Path

from custom_sim import write_csv

from .atomic import finite_json, temporary_folder, write_text_atomically

from ..checks import metrics
from . import plots
from ..checks.law_difference import law_lines
from ..checks.row import CheckRow
from ..checks.scenario import Result, metrics_json

def _fmt(x, unit: str = "") -> str:
    if x is None:
        return "–"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, float) and (x == 0 or 1e-3 <= abs(x) < 1e4):
        return f"{x:.4g}{unit}"
    return f"{x:.2e}{unit}" if isinstance(x, float) else f"{x}{unit}"


def _write_atomically(path: Path, text: str) -> None:
    """Complete or absent, with the umask's permissions (compare/report/atomic.py)."""
    write_text_atomically(path, text)


def write_scenario(result: Result, out: Path, mjcf: str) -> dict:
    """Write DIR/<name>/ for a scenario that ran; returns its metrics.json content."""
    scene = result.scene
    final = out / scene.name
    tmp = temporary_folder(out, prefix=f".{scene.name}.")   # the umask's permissions, not 0700
    try:
        data = metrics_json(result)
        write_csv(result.custom, tmp / "trajectory_custom.csv")
        write_csv(result.mujoco, tmp / "trajectory_mujoco.csv")
        tested, twin = result.under_test, result.mujoco
        if tested is not result.custom:
            write_csv(tested, tmp / "trajectory_user.csv")
        (tmp / "model.xml").write_text(mjcf)
        diffs = metrics.differences(tested, twin)
        shown = (tested, twin) if tested is result.custom else (tested, result.custom, twin)
        figures = plots.draw_all({
            "states": lambda: plots.states(scene, shown, tmp / "states.png", result.reference),
            "path": lambda: plots.path_in_plane(scene, shown, tmp / "path.png"),
            "error": lambda: plots.error(scene, diffs, tmp / "error.png"),
            "energy": lambda: plots.energy(scene, result.balances, tmp / "energy.png"),
            "snapshots": lambda: plots.snapshots(scene, tested, twin, tmp / "snapshots.png"),
            "residuals": lambda: plots.step_residuals(scene, result.residuals, result.checks, tmp / "residuals.png"),
        }, result.warnings)   # a figure that fails adds a warning (data["warnings"] is that list)
        # a non-finite number (a user's 1e308 states make errors inf) is written as null and
        # listed under "non_finite": never NaN or Infinity, which is not JSON, and never a crash
        (tmp / "metrics.json").write_text(finite_json(data, indent=2) + "\n")
        (tmp / "index.md").write_text(scenario_page(result, data, figures))
        if final.exists():
            shutil.rmtree(final)
        os.replace(tmp, final)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return data


def _image(figures: dict, name: str) -> list[str]:
    """A figure's markdown lines, or a note where it could not be drawn (see the warnings)."""
    return [f"![{name}]({figures[name]})" if figures.get(name) else f"*(the {name} figure could not be drawn)*", ""]


def _verdict(passed) -> str:
    return "not judged" if passed is None else ("pass" if passed else "**FAIL**")


def checks_table(result: Result) -> list[str]:
    """The table a scenario page opens with: one row per check."""
    lines = ["| check | what it isolates | largest difference | tolerance | verdict |", "|---|---|---|---|---|"]
    for c in result.checks:
        diff = (f"{_fmt(c.position_error_max, ' m')}, {_fmt(c.angle_error_max, ' rad')}"
                if c.position_error_max is not None else "–")
        tol = (f"{_fmt(c.tolerance_position, ' m')}, {_fmt(c.tolerance_angle, ' rad')}"
               if c.tolerance_position is not None else "–")
        reason = c.reason.removeprefix("not judged: ") if c.passed is None else c.reason
        note = "" if c.passed else f" ({reason})"
        d = c.details
        where = f"; first at step {d['first_step']} ({d.get('phase', '')}, {d.get('component', '')})" \
            if c.passed is False and d.get("first_step") is not None else ""
        lines.append(f"| {c.label} | {c.isolates} | {diff} | {tol} | {_verdict(c.passed)}{note}{where} |")
    return lines


def stability_words(data: dict, integrator: str) -> str:
    """The theory's stable step for the scene's integrator, or why no step is stable."""
    limit = data["stable_dt_theory"]
    if limit == 0.0:
        return f"no step is stable for {integrator}: {data.get('stable_dt_reason', '')}"
    return f"theory allows dt < {_fmt(limit, ' s')} for {integrator}"


def energy_table(balances: dict, initial: float) -> list[str]:
    """The work-energy balance of each run: what the physics dissipated (W, by effect) and what
    the numerics made or lost (R = E - E(0) + W; docs/energy-balance.md)."""
    lines = [f"The energy balance (E(0) = {_fmt(initial, ' J')}): *E(end) - E(0)* is mostly the physics on a "
             "damped scene; *W* the work each dissipative effect did; *R* = E(end) - E(0) + W what the numerics "
             "created (+) or destroyed (-), zero for the exact motion.", "",
             "| run | E(end) - E(0) | W damping | W friction | W rolling | R(end) | max abs R |",
             "|---|---|---|---|---|---|---|"]
    for name, b in balances.items():
        w = b["dissipated"]
        lines.append(f"| {name} | {_fmt(b['delta_E'], ' J')} | {_fmt(w['damping'], ' J')} | {_fmt(w['friction'], ' J')} "
                     f"| {_fmt(w['rolling'], ' J')} | {_fmt(b['residual_end'], ' J')} | {_fmt(b['residual_max'], ' J')} |")
    lines += [""] + [f"- *{name}*: W by {b['rule']}." for name, b in balances.items()] + [""]
    return lines


def attribution_section(ladder: list[dict]) -> list[str]:
    """'Why the two differ': the attribution ladder as a table, then each cause in a sentence."""
    lines = ["## Why the two differ", "",
             "A ladder of runs from MuJoCo's native contact (every effect on) to custom_sim, each rung "
             "removing one cause. *difference* is the rung's run against custom_sim; *share* what "
             "removing its cause took off the difference of the rung before; *alone* the distance "
             "between the rung's run and the one before (see docs/differences-from-mujoco.md).", "",
             "| rung: cause removed | difference (m, rad) | share (m, rad) | alone (m, rad) |",
             "|---|---|---|---|"]
    for r in ladder:
        if not r["measured"]:
            lines.append(f"| {r['name']} | {r['note']} | | |")
            continue
        share = "–" if r["share_position"] is None else f"{_fmt(r['share_position'])}, {_fmt(r['share_angle'])}"
        alone = "–" if r["step_position"] is None else f"{_fmt(r['step_position'])}, {_fmt(r['step_angle'])}"
        lines.append(f"| {r['name']} | {_fmt(r['position_error_max'])}, {_fmt(r['angle_error_max'])} "
                     f"| {share} | {alone} |")
    lines.append("")
    lines += [f"- **{r['name']}**: {r['cause']}" for r in ladder]
    lines.append("")
    return lines


def scenario_page(result: Result, data: dict, figures: dict) -> str:
    scene = result.scene
    twin, tested = result.mujoco, result.under_test
    ev_c, ev_m = data["events_custom"], data["events_mujoco"]
    judged = result.judged
    skipped = ", ".join(c.label for c in result.not_judged)
    if not judged:
        summary = f"**NOT JUDGED**: no check could be judged ({skipped}; each row says why)."
    else:
        summary = (f"**{'PASS' if result.passed else 'FAIL'}**: {len(judged) - len(result.failed)} of {len(judged)} "
                   f"judged checks within tolerance"
                   + (f"; outside: {', '.join(c.label for c in result.failed)}" if result.failed else "")
                   + (f"; not judged: {skipped} (each row says why)" if skipped else "") + ".")
    lines = [f"# {scene.name}", "", scene.description, "", summary, ""]
    lines += law_lines(scene, result.law_differences)
    lines += [f"> warning: {w}" for w in result.warnings]
    if result.warnings:
        lines.append("")
    lines += ["## Checks", "", f"The simulator under test is **{result.simulator}**.", ""]
    lines += checks_table(result)
    lines += [
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
        f"| {result.simulator} | {scene.integrator}, dt = {scene.dt:g} s, {scene.steps} steps, "
        f"{tested.force_evals} force evaluations, {_fmt(tested.wall_time, ' s')} |",
        f"| MuJoCo | {twin.integrator}, dt = {twin.dt:g} s, solref mapping `{scene.mujoco.solref}`, "
        f"cone {scene.mujoco.cone}, {_fmt(twin.wall_time, ' s')} |",
        f"| stability | {stability_words(data, scene.integrator)} |",
        f"| source | `{scene.source}`; MuJoCo model: [model.xml](model.xml) |",
        "",
    ]
    if result.diagnosis:
        from ..usersim import diagnosis_markdown
        lines += ["## Diagnosis", "", diagnosis_markdown(result.diagnosis), ""]
    lines += ["## Trajectories", ""] + _image(figures, "states") + _image(figures, "path") + _image(figures, "snapshots")
    if figures.get("residuals"):
        lines += ["## One step against the independent step", ""] + _image(figures, "residuals")
    lines += [
        "## Difference to MuJoCo's own contact, and energy",
        "",
        *_image(figures, "error"),
        *_image(figures, "energy"),
        *energy_table(data["energy_balance"], data["energy_initial"]),
        "## Events",
        "",
        f"| event | {result.simulator} | MuJoCo |",
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
        "How MuJoCo's soft contact is set from k and c (docs/physics.md); shown, not judged: with MuJoCo's own "
        "contact the difference is measured and attributed below.",
        "",
        "| mapping | max position difference | RMS | max angle difference | MuJoCo energy drift |",
        "|---|---|---|---|---|",
    ]
    for mapping, row in result.by_mapping.items():
        if "error" in row:
            lines.append(f"| {mapping} | diverged: {row['error']} | | | |")
            continue
        lines.append(f"| {mapping}{' (scene)' if mapping == scene.mujoco.solref else ''} "
                     f"| {_fmt(row['position_error_max'], ' m')} | {_fmt(row['position_error_rms'], ' m')} "
                     f"| {_fmt(row['angle_error_max'], ' rad')} | {_fmt(row['energy_drift_mujoco'], ' J')} |")
    lines += [""] + attribution_section(result.attribution)
    lines += ["Every way the twin is built differently:", ""]
    for note in twin.meta.get("approximations", []):
        lines.append(f"- {note}")
    lines.append("")
    return "\n".join(lines)


def _status_cell(row: dict, failed: str) -> str:
    status = row.get("status", "pass" if row["pass"] else "FAIL")
    if status == "FAIL":
        return "**FAIL**: " + failed
    return "**not judged**" if status == "not judged" else status


def index_page(rows: list[dict], failures: list[tuple[str, str, str]]) -> str:
    lines = [
        "# Comparison report",
        "",
        "One row per scenario. A scenario passes when every judged check passes (the second table). *pos. max* "
        "and *pos. RMS* are the distance between the centres of mass of the simulator under test and of MuJoCo "
        "with its own contact (max and root-mean-square over the run; shown, and attributed on each page), "
        "*angle max* the largest angle difference, *drift* R(end) = E(end) - E(0) + W of each simulator: the "
        "energy its numerics created or destroyed, with the work W the scene's damping, friction and rolling "
        "resistance dissipated beside it (docs/energy-balance.md), *time* the wall time of the stepping alone.",
        "",
        "| scenario | simulator | body | integrator | dt (s) | pos. max (m) | pos. RMS (m) | angle max (rad) "
        "| drift R (J) | dissipated W (J) | drift R MuJoCo (J) | time (s) | time MuJoCo (s) | result |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        own = r["energy_balance"][r.get("simulator", "custom_sim")]
        twin = r["energy_balance"]["mujoco"]
        failed = ", ".join(r.get("failed_checks", []))
        lines.append(
            f"| [{r['name']}]({r['name']}/index.md) | {r.get('simulator', 'custom_sim')} | {r['shape']} "
            f"| {r['integrator']} | {r['dt']:g} "
            f"| {_fmt(r['position_error_max'])} | {_fmt(r['position_error_rms'])} | {_fmt(r['angle_error_max'])} "
            f"| {_fmt(own['residual_end'])} | {_fmt(sum(own['dissipated'].values()))} | {_fmt(twin['residual_end'])} "
            f"| {_fmt(r['wall_time_custom'])} | {_fmt(r['wall_time_mujoco'])} "
            f"| {_status_cell(r, failed)} |")
    for name, status, why in failures:
        lines.append(f"| {name} | | | | | | | | | | | | | **{status}**: {why} |")
    lines += ["", "## Every judged check", "",
              "| scenario | check | largest position difference (m) | tolerance (m) | largest angle difference (rad) "
              "| tolerance (rad) | verdict |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        for c in map(CheckRow.from_json, r["checks"]):
            if c.passed is None:
                continue
            lines.append(f"| {r['name']} | {c.label} | {_fmt(c.position_error_max)} "
                         f"| {_fmt(c.tolerance_position)} | {_fmt(c.angle_error_max)} "
                         f"| {_fmt(c.tolerance_angle)} | {_verdict(c.passed)} |")
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

