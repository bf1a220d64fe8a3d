"""What `study` writes: DIR/study.csv (and .parquet), DIR/<metric>.png, DIR/index.md."""
from __future__ import annotations

from pathlib import Path

from ...table import markdown, number
from . import maps, table


def _num(x, **options) -> str:
    """3 significant digits, "-" for a value that is missing or not finite."""
    return number(x, none="-", nonfinite="-", **options)


def _value(v) -> str:
    return f"{v:g}" if isinstance(v, float) else str(v)


def write_report(study, out: Path, command: str | None = None) -> Path:
    out.mkdir(parents=True, exist_ok=True)
    table.write_csv(out / "study.csv", study.names, study.rows)
    parquet = table.write_parquet(out / "study.parquet", study.names, study.rows)
    figures = []
    for metric in maps.METRICS:
        if metric == "twin" and not study.twin:
            continue
        path = out / f"{metric}.png"
        maps.plot(study, metric, path)
        figures.append((metric, path.name))
    index = out / "index.md"
    index.write_text("\n".join(_index_lines(study, figures, parquet, command)) + "\n")
    return index


def _index_lines(study, figures, parquet: bool, command: str | None) -> list[str]:
    scene = study.source.scene
    counts = {s: sum(r["status"] == s for r in study.rows) for s in ("ok", "unstable", "failed", "skipped")}
    where = (f"the cluster at {study.scheduler}" if study.scheduler else
             f"a local Dask cluster of {study.workers} worker process(es), one thread each")
    lines = [f"# Study of {scene.name}", "", scene.description, ""]
    if command:
        lines += ["```", command, "```", ""]
    summary = (f"{len(study.rows)} runs: {counts['ok']} ok, {counts['unstable']} unstable, "
               f"{counts['failed']} failed" + (f", {counts['skipped']} skipped." if counts["skipped"] else "."))
    if study.workers:
        summary += (f" {len(study.rows) - study.reused} computed in {study.wall_time:.1f} s on {where}, "
                    f"{study.threads_per_task} thread(s) per task")
        summary += f"; {study.reused} taken from batches/ (an earlier run)." if study.reused else "."
    else:
        summary += " All were taken from batches/ (computed by an earlier run of this study)."
    lines += [
        summary,
        "",
        "Varied:", ""]
    for v in study.varies:
        lines.append(f"- `{v.name}`: {', '.join(_value(x) for x in v.values)}")
    lines += [f"- integrators: {', '.join(study.integrators)}"]
    if study.yours:
        lines.append(f"- yours: `{study.yours.bundle.spec}`{' (--whole)' if study.yours.bundle.whole else ''}, "
                     f"{', '.join(study.yours.integrators)}; shipped to the workers as "
                     f"{len(study.yours.bundle.files)} file(s): {', '.join(r for r, _ in study.yours.bundle.files)}")
    if study.source.law_from:
        lines.append(f"- the law: `{study.source.law_from}` laid over the scene's [contact]")
    judged = ("Every other field is the scene file's. Per run: `stable` (custom_sim did not stop the run "
              "as diverged, and the energy read outside hard contact did not rise by more than 10 % of the "
              "motion's largest kinetic energy), `position_error_max` (m, the largest distance of the centre of "
              "mass from the converged reference, read every 2 ms), `twin_position_error_max` (m, the same "
              "against the MuJoCo twin of the same scene), `wall_time` (s, the compiled stepping alone), "
              f"`force_evals`, `status`. Table: [study.csv](study.csv){' and study.parquet' if parquet else ''}; "
              "an empty cell has its reason in `note`.")
    if study.yours:
        judged += (" Yours (`simulator` = yours): unstable where it left custom_sim's healthy range, returned a "
                   "non-finite state or gained energy as above; `wall_time` is its loop; skipped where it raised "
                   "NotImplementedError, failed where it raised anything else.")
    lines += ["", judged, ""]
    for metric, name in figures:
        lines += [f"## {maps.METRICS[metric][0]}", "", f"![{metric}]({name})", ""]
    limits = maps.measured_limits(study)
    if limits:
        lines += ["## Largest stable step: measured against theory", "",
                  "Measured: the largest dt of the grid whose run, and every smaller dt's, was stable "
                  "(so the true limit lies between it and the next dt of the grid). Theory: "
                  "custom_sim.stability.stable_step for the same scene.", ""]
        rows = [[maps.panel_title((lim["simulator"], lim["integrator"])),
                 ", ".join(f"{k}={_value(v)}" for k, v in lim["values"].items()) or "-",
                 *map(_num, (lim["stable_up_to"], lim["first_unstable"], lim["theory"])),
                 _num(lim["ratio"], decimals=2)] for lim in limits]
        lines += markdown(["integrator", "other fields", "stable up to (s)", "first unstable (s)", "theory (s)",
                           "measured / theory"], rows).splitlines()
        lines.append("")
    failed = [r for r in study.rows if r["status"] == "failed"]
    if failed:
        lines += ["## Failed runs", ""]
        lines += [f"- {', '.join(f'{n}={_value(v)}' for n, v in zip(study.names, r['values']))}, "
                  f"{maps.panel_title((r.get('simulator') or 'custom_sim', r['integrator']))}: {r['note']}"
                  for r in failed]
        lines.append("")
    return lines
