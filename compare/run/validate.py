"""Hold a simulator to the checks that need no MuJoCo, and print its diagnosis (writes nothing):
the command `python -m compare validate` (compare/commands/validate.py).

Per scene: the scenario's own pipeline (compare/run/scenario.py: the runs collected once, then
the registry's checks) with the checks that need neither MuJoCo nor the converged reference:
`identical` (against custom_sim, same integrator and dt, to round-off) and `step` (every step
against one independent step) in their columns, the others (`energy`, `ground`) on a line below
where they fail; and the diagnosis. The exit status is `run`'s (compare/checks/status.py
exit_status): 0 when every scene not skipped passed, and there was one; 1 otherwise.
"""
from __future__ import annotations

import sys

from ..checks.status import Status, exit_status, of_rows
from ..checks.summary import StepFailure


def _cell(row) -> str:
    """A CheckRow in a few words."""
    if row.passed is None:
        return "not judged"
    word = "pass" if row.passed else "FAIL"
    failure = StepFailure.of(row)
    if not row.passed and failure is not None:   # step: the component over round-off
        return f"{word} {failure.component} {failure.residual:.2e} / {failure.bound:.2e} {failure.unit}"
    return f"{word} {row.position_error_max:.2e} m / {row.tolerance_position:.2e} m"


def validate(spec: str | None, scenes: list[str], whole: bool = False, trajectories: str | None = None,
             markdown: bool = False, law: str | None = None, process: str | None = None) -> int:
    """Hold spec (MODULE:FUNCTION, or None with trajectories or process) to the checks on the
    scenes, under `law` (a law file, `identified`, or None: each scene's own): one line per scene
    (with markdown, its diagnosis in full); a scene the simulator skips is a line saying why, and
    fails nothing. The exit status."""
    from ..checks.case import Case
    from ..checks.registry import without
    from ..checks.result import Result
    from ..scenarios import load_all
    from ..diagnosis import diagnose, render_markdown
    from ..usersim import load_simulator
    from .scenario import collect_runs, judge

    from ..usersim import SceneSkipped, UserFault, preflight

    sim = load_simulator(spec, whole, trajectories, process)
    if sim is None:
        raise SystemExit("expected MODULE:FUNCTION, --trajectories DIR or --sim-process COMMAND")
    scenes = load_all(scenes)
    preflight(sim, scenes)
    if law:
        from .law import under_law
        scenes = under_law(scenes, law, sim)
    statuses = []
    print(f"{'scene':<16} {'identical':<36} {'step':<36} diagnosis")
    for scene in scenes:
        result = Result(scene)
        try:
            runs = collect_runs(result, Case(scene), sim)
        except SceneSkipped as exc:   # a scene the code does not do: never judged, fails nothing
            print(f"{scene.name:<16} skipped  {exc.reason}")
            statuses.append(Status.SKIPPED)
            continue
        except UserFault as exc:   # this scene's fault: its line, the others still judged
            statuses.append(Status.ERROR)
            print(f"{scene.name:<16} error: {exc}")
            if exc.details:   # its traceback, under its scene's name
                sys.stdout.flush()
                print(f"{scene.name}: {exc.details}", file=sys.stderr)
            continue
        for said in result.warnings:   # float32 states; a step that keeps state (then no probes, as `run`)
            print(f"warning: {scene.name}: {said}", file=sys.stderr)
        rows, _ = judge(runs, without("mujoco", "reference"))
        by_name = {row.name: row for row in rows}
        same, step = by_name["identical"], by_name["step"]
        diag = diagnose(sim, scene, runs.under_test, probe=runs.keeps_state is None, step_row=step)
        statuses.append(of_rows(rows))
        print(f"{scene.name:<16} {_cell(same):<36} {_cell(step):<36} {diag['verdict']}")
        for row in rows:
            if row.name not in ("identical", "step") and row.passed is False:
                print(f"{'':<16} {row.label} FAIL: {row.reason}")
        if markdown:
            print("\n" + render_markdown(diag) + "\n")
    if all(s is Status.SKIPPED for s in statuses):
        print("nothing judged: your simulator skipped every scene (see each line)")
    elif all(s in (Status.SKIPPED, Status.NOT_JUDGED) for s in statuses):
        print("nothing judged: no scene had a check this command can judge (see each line)")
    return exit_status(statuses)
