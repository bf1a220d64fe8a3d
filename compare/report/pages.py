"""The report: DIR/index.md and one folder per scenario (metrics.json, CSVs, model.xml, plots).

Every folder is written beside its final place and renamed into it when complete, and
index.md is replaced in one step, so an interrupted run never leaves a half-written report.
"""
from __future__ import annotations

import contextlib
import os
import shutil
from pathlib import Path

from scene_types import csv_text, write_csv
from scene_types.state import POSE, UNIT_OF

from ..files import finite_json, temporary_folder, write_text_atomically

from ..checks import metrics
from ..store import cached
from . import plots
from ..checks.law_difference import judged_law_words, law_lines
from ..checks.status import Status
from ..checks.summary import StepFailure, Summary, read_summary
from ..checks.result import Result, metrics_json, skipped_json
from ..table import DASH, markdown, number


def _num(x, unit: str = "") -> str:
    """A page's number: 4 significant digits, d.dde+XX outside 1e-3..1e4; its unit after it."""
    return DASH if x is None else number(x, 4, sci=(1e-3, 1e4)) + unit


def _write_atomically(path: Path, text: str) -> None:
    """Complete or absent, with the umask's permissions (compare/files.py)."""
    write_text_atomically(path, text)


def run_csv(case, which: str) -> str:
    """The CSV file of custom_sim's run of the case's scene (which "custom") or of MuJoCo's
    native twin with the scene's own mapping ("mujoco"): scene-only work, kept in the cache."""
    run = case.trajectory() if which == "custom" else case.mujoco(case.scene.mujoco.solref)
    return csv_text(run)


@contextlib.contextmanager
def scene_folder(out: Path, name: str):
    """A hidden folder to write DIR/<name>/ into (the umask's permissions, not 0700), moved into
    place whole when the block ends, or removed when it raises."""
    tmp = temporary_folder(out, prefix=f".{name}.")
    try:
        yield tmp
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    final = out / name
    if final.exists():
        shutil.rmtree(final)
    os.replace(tmp, final)


def write_scenario(result: Result, out: Path, mjcf: str) -> dict:
    """Write DIR/<name>/ for a scenario that ran; returns its metrics.json content."""
    scene = result.scene
    with scene_folder(out, scene.name) as tmp:
        data = metrics_json(result)
        for which in ("custom", "mujoco"):
            (tmp / f"trajectory_{which}.csv").write_text(cached(run_csv)(result.case, which), encoding="utf-8")
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
            "residuals": lambda: plots.step_residuals(scene, result.residuals, tmp / "residuals.png"),
        }, result.warnings)   # a figure that fails adds a warning (data["warnings"] is that list)
        # a non-finite number (a user's 1e308 states make errors inf) is written as null and
        # listed under "non_finite": never NaN or Infinity, which is not JSON, and never a crash
        (tmp / "metrics.json").write_text(finite_json(data, indent=2) + "\n")
        (tmp / "index.md").write_text(scenario_page(result, data, figures))
    return data


def write_skipped(result: Result, out: Path) -> dict:
    """Write DIR/<name>/ for a scene the user's code skipped (metrics.json, index.md saying why);
    returns its metrics.json content."""
    scene = result.scene
    data = skipped_json(result)
    with scene_folder(out, scene.name) as tmp:
        (tmp / "metrics.json").write_text(finite_json(data, indent=2) + "\n")
        (tmp / "index.md").write_text("\n".join([
            f"# {scene.name}", "", scene.description, "",
            f"**SKIPPED**: {result.skipped}.", "",
            f"The simulator under test, **{result.simulator}**, does not do this scene (a {scene.body.shape} body): "
            "none of its checks ran, and it fails nothing. A module says which bodies it does with "
            "`SHAPES = (\"box\", ...)`; a step says it does not do a scene by raising `NotImplementedError(\"why\")` "
            "(docs/validate-your-simulator.md).", ""]) + "\n")
    return data


def _image(figures: dict, name: str) -> list[str]:
    """A figure's markdown lines, or a note where it could not be drawn (see the warnings)."""
    return [f"![{name}]({figures[name]})" if figures.get(name) else f"*(the {name} figure could not be drawn)*", ""]


def _verdict(passed) -> str:
    return "not judged" if passed is None else ("pass" if passed else "**FAIL**")


def checks_table(result: Result) -> list[str]:
    """The table a scenario page opens with: one row per check."""
    rows = []
    for c in result.checks:
        diff = (f"{_num(c.position_error_max, ' m')}, {_num(c.angle_error_max, ' rad')}"
                if c.position_error_max is not None else DASH)
        tol = (f"{_num(c.tolerance_position, ' m')}, {_num(c.tolerance_angle, ' rad')}"
               if c.tolerance_position is not None else DASH)
        reason = c.reason.removeprefix("not judged: ") if c.passed is None else c.reason
        note = "" if c.passed else f" ({reason})"
        failure = StepFailure.of(c) if c.passed is False else None
        where = f"; first at step {failure.step} ({failure.phase}): {failure.over()}" if failure is not None else ""
        rows.append([c.label, c.isolates, diff, tol, f"{_verdict(c.passed)}{note}{where}"])
    return markdown(["check", "what it isolates", "largest difference", "tolerance", "verdict"], rows).splitlines()


def stability_words(data: dict, integrator: str) -> str:
    """The theory's stable step for the scene's integrator, or why no step is stable."""
    limit = data["stable_dt_theory"]
    if limit == 0.0:
        return f"no step is stable for {integrator}: {data.get('stable_dt_reason', '')}"
    return f"theory allows dt < {_num(limit, ' s')} for {integrator}"


def energy_table(balances: dict, initial: float) -> list[str]:
    """The work-energy balance of each run: what the physics dissipated (W, by effect) and what
    the numerics made or lost (R = E - E(0) + W; docs/energy-balance.md)."""
    lines = [f"The energy balance (E(0) = {_num(initial, ' J')}): *E(end) - E(0)* is mostly the physics on a "
             "damped scene; *W* the work each dissipative effect did; *R* = E(end) - E(0) + W what the numerics "
             "created (+) or destroyed (-), zero for the exact motion.", ""]
    rows = [[name, *(_num(v, " J") for v in (b["delta_E"], b["dissipated"]["damping"], b["dissipated"]["friction"],
                                             b["dissipated"]["rolling"], b["residual_end"], b["residual_max"]))]
            for name, b in balances.items()]
    lines += markdown(["run", "E(end) - E(0)", "W damping", "W friction", "W rolling", "R(end)", "max abs R"],
                      rows).splitlines()
    lines += [""] + [f"- *{name}*: W by {b['rule']}." for name, b in balances.items()] + [""]
    return lines


def attribution_section(ladder: list[dict]) -> list[str]:
    """'Why the two differ': the attribution ladder as a table, then each cause in a sentence."""
    lines = ["## Why the two differ", "",
             "A ladder of runs from MuJoCo's native contact (every effect on) to custom_sim, each rung "
             "removing one cause. *difference* is the rung's run against custom_sim; *share* what "
             "removing its cause took off the difference of the rung before; *alone* the distance "
             "between the rung's run and the one before (see docs/differences-from-mujoco.md).", ""]
    rows = []
    for r in ladder:
        if not r["measured"]:
            rows.append([r["name"], r["note"], "", ""])
            continue
        share = DASH if r["share_position"] is None else f"{_num(r['share_position'])}, {_num(r['share_angle'])}"
        alone = DASH if r["step_position"] is None else f"{_num(r['step_position'])}, {_num(r['step_angle'])}"
        rows.append([r["name"], f"{_num(r['position_error_max'])}, {_num(r['angle_error_max'])}", share, alone])
    lines += markdown(["rung: cause removed", "difference (m, rad)", "share (m, rad)", "alone (m, rad)"],
                      rows).splitlines()
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
    lines += verdicts_table(result)
    lines += ["", *folded("What each check isolates, and why it is judged as it is", checks_table(result))]
    lines += ["## The scene", "", *markdown(["", ""], [
        ["body", f"{scene.body.shape}, {_num(scene.body.mass, ' kg')}"],
        ["effects", ", ".join(scene.effects) or "none"],
        ["contact", f"k = {_num(scene.contact.k, ' N/m')}, c = {_num(scene.contact.c, ' N s/m')}, "
                    f"damping law {scene.contact.damping_law}, mu = {scene.contact.mu}, "
                    f"alpha = {scene.contact.alpha} s/m, mu_roll = {scene.contact.mu_roll} m"],
        [result.simulator, f"{tested.integrator}, dt = {scene.dt:g} s, {scene.steps} steps, "
                           + (f"{tested.force_evals} force evaluations, " if tested.force_evals else "")
                           + _num(tested.wall_time, " s")],
        ["MuJoCo", f"{twin.integrator}, dt = {twin.dt:g} s, solref mapping `{scene.mujoco.solref}`, "
                   f"cone {scene.mujoco.cone}, {_num(twin.wall_time, ' s')}"],
        ["stability", stability_words(data, scene.integrator)],
        ["source", f"`{scene.source}`; MuJoCo model: [model.xml](model.xml)"],
    ]).splitlines(), ""]
    if result.diagnosis:
        from ..diagnosis import diagnosis_markdown
        lines += ["## Diagnosis", "", diagnosis_markdown(result.diagnosis), ""]
    lines += ["## Trajectories", ""] + _image(figures, "states") + _image(figures, "path") + _image(figures, "snapshots")
    if figures.get("residuals"):
        lines += ["## One step against the independent step", ""] + _image(figures, "residuals")
    below = [
        "## Difference to MuJoCo's own contact, and energy",
        "",
        *_image(figures, "error"),
        *_image(figures, "energy"),
        *energy_table(data["energy_balance"], data["energy_initial"]),
        "## Events",
        "",
        *markdown(["event", result.simulator, "MuJoCo"], _event_rows(ev_c, ev_m)).splitlines(),
        "",
        "## The three solref mappings",
        "",
        "How MuJoCo's soft contact is set from k and c (docs/physics.md); shown, not judged: with MuJoCo's own "
        "contact the difference is measured and attributed below.",
        "",
    ]
    rows = []
    for mapping, row in result.by_mapping.items():
        if "error" in row:
            rows.append([mapping, f"diverged: {row['error']}", "", "", ""])
            continue
        rows.append([f"{mapping}{' (scene)' if mapping == scene.mujoco.solref else ''}",
                     _num(row["position_error_max"], " m"), _num(row["position_error_rms"], " m"),
                     _num(row["angle_error_max"], " rad"), _num(row["energy_drift_mujoco"], " J")])
    below += markdown(["mapping", "max position difference", "RMS", "max angle difference", "MuJoCo energy drift"],
                      rows).splitlines()
    below += [""] + attribution_section(result.attribution)
    below += ["Every way the twin is built differently:", ""]
    below += [f"- {note}" for note in twin.meta.get("approximations", [])]
    lines += folded("Against MuJoCo's own contact: the difference, the energy, the events, the solref mappings "
                    "and why the two differ", below)
    return "\n".join(lines)


def folded(summary: str, lines: list[str]) -> list[str]:
    """Lines folded under a one-line summary (an HTML details block: markdown renders inside it)."""
    return ["<details>", f"<summary>{summary}</summary>", "", *lines, "", "</details>", ""]


def verdicts_table(result: Result) -> list[str]:
    """The checks in short: each one's largest difference, tolerance and verdict (a failure with
    where it first failed); what each isolates and why, in the folded table below."""
    rows = []
    for c in result.checks:
        diff = (f"{_num(c.position_error_max, ' m')}, {_num(c.angle_error_max, ' rad')}"
                if c.position_error_max is not None else DASH)
        tol = (f"{_num(c.tolerance_position, ' m')}, {_num(c.tolerance_angle, ' rad')}"
               if c.tolerance_position is not None else DASH)
        failure = StepFailure.of(c) if c.passed is False else None
        where = f": {failure.over()} at step {failure.step}" if failure is not None else ""
        rows.append([c.label, diff, tol, _verdict(c.passed) + where])
    return markdown(["check", "largest difference", "tolerance", "verdict"], rows).splitlines()


def _event_rows(ev_c: dict, ev_m: dict) -> list[list[str]]:
    """The Events table's rows: each event of the simulator under test and of MuJoCo."""
    def listed(values, spec):
        return ", ".join(format(v, spec) for v in values[:4]) or DASH

    def pose(p):
        return ", ".join(f"{p[c]:.4f} {UNIT_OF[c]}" for c in POSE)
    rows = [["first contact (s)", _num(ev_c["first_contact_time"]), _num(ev_m["first_contact_time"])],
            ["bounce apex heights (m)", listed(ev_c["bounce_apex_heights"], ".4f"),
             listed(ev_m["bounce_apex_heights"], ".4f")],
            ["restitution implied", listed(ev_c["restitution"], ".3f"), listed(ev_m["restitution"], ".3f")],
            ["at rest from (s)", _num(ev_c["rest_time"]), _num(ev_m["rest_time"])]]
    if "rolling_time" in ev_c:
        rows.append(["rolling without slip from (s)", _num(ev_c["rolling_time"]), _num(ev_m["rolling_time"])])
    return rows + [["final pose x, y, theta", pose(ev_c["final_pose"]), pose(ev_m["final_pose"])]]


def _status_cell(summary: Summary) -> str:
    status = summary.status
    if status is Status.FAILED:
        return "**FAIL**: " + ", ".join(summary.failed_checks)
    return "**not judged**" if status is Status.NOT_JUDGED else status.value


INDEX_HEADERS = ["scenario", "simulator", "body", "integrator", "dt (s)", "pos. max (m)", "pos. RMS (m)",
                 "angle max (rad)", "drift R (J)", "dissipated W (J)", "drift R MuJoCo (J)", "time (s)",
                 "time MuJoCo (s)", "result"]


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
    ]
    table = []
    summaries = [read_summary(r) for r in rows]
    for r in summaries:
        own, twin = r.energy_balance[r.simulator], r.energy_balance["mujoco"]
        ran = r.integrator_under_test
        table.append([f"[{r.name}]({r.name}/index.md)", r.simulator, r.shape,
                      ran if ran == r.integrator else f"{ran} (the scene's: {r.integrator})", f"{r.dt:g}",
                      *map(_num, (r.position_error_max, r.position_error_rms, r.angle_error_max,
                                  own["residual_end"], sum(own["dissipated"].values()), twin["residual_end"],
                                  r.wall_time_custom, r.wall_time_mujoco)),
                      _status_cell(r)])
    table += [[f"[{name}]({name}/index.md)" if status == "skipped" else name, *[""] * 12, f"**{status}**: {why}"]
              for name, status, why in failures]
    lines += markdown(INDEX_HEADERS, table).splitlines()
    laws = [(r.name, judged_law_words(r.law)) for r in summaries]
    if any(words for _, words in laws):
        lines += ["", "## The law judged", "",
                  "Where a scenario was judged under another law than its scene's (`run --law`), each effect "
                  "that differs, with the parameters that differ:", ""]
        lines += [f"- [{name}]({name}/index.md): judged under {words}" for name, words in laws if words]
    lines += ["", "## Every judged check", ""]
    checks = [[r.name, c.label, *map(_num, (c.position_error_max, c.tolerance_position, c.angle_error_max,
                                            c.tolerance_angle)), _verdict(c.passed) + _step_failure(c)]
              for r in summaries for c in r.checks if c.passed is not None]
    lines += markdown(["scenario", "check", "largest position difference (m)", "tolerance (m)",
                       "largest angle difference (rad)", "tolerance (rad)", "verdict"], checks).splitlines()
    lines.append("")
    return "\n".join(lines)


def _step_failure(check) -> str:
    """What a failed step row's position and angle columns cannot show: the component over
    round-off (a velocity, when the force is wrong)."""
    failure = StepFailure.of(check) if check.passed is False else None
    return f": {failure.over()} at step {failure.step}" if failure is not None else ""


def write_index(out: Path, rows: list[dict], failures: list[tuple[str, str]]) -> Path:
    path = out / "index.md"
    _write_atomically(path, index_page(rows, failures))
    return path


def summary_table(rows: list[dict]) -> str:
    """The index table alone (for the README)."""
    text = index_page(rows, [])
    return "\n".join(line for line in text.splitlines() if line.startswith("|"))

