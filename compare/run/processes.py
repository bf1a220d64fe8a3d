"""How `run` spreads its scenarios over processes: the order of submission (expected_cost, in
relative units), the processes with their timeout in s (run_scenes), and the row of a process
that sent nothing back (_no_verdict)."""
from __future__ import annotations

import functools

from .outcome import Outcome


# A scenario's cost in steps of a one-point body, fitted to the seven built-ins' CPU times
# (custom_sim under test, cache off, 2 cores: 2.0 to 7.3 s a scenario). Most of a scenario is
# per step (custom_sim's runs, MuJoCo's, the reference, the step check), a contact point adds
# to each step, and RK4's four force evaluations add less than four times (MuJoCo's and the
# reference's share does not grow with them); the rest is the same for every scenario (the
# twins' set-up, the figures).
POINT_SHARE = 0.43       # a contact point's share of a step, beside the body's own
RK4_SHARE = 1.8          # an RK4 step against an Euler one
FIXED_STEPS = 86_000     # the fixed part, as steps of a one-point body


def expected_cost(scene) -> float:
    """A scenario's relative cost, for the order of submission (see the constants above): the
    costliest go first, so that the last to finish are short ones."""
    from custom_sim import mass_properties
    per_step = 1.0 + POINT_SHARE * len(mass_properties(scene.body).points)
    return scene.steps * per_step * (RK4_SHARE if scene.integrator == "rk4" else 1.0) + FIXED_STEPS


def run_scenes(scenes, work, jobs: int, timeout: float | None = None, cost=None) -> dict:
    """work(scene) -> Outcome for every scene, each in a process forked for it alone
    (compare/executor/processes.py: no state of a user's module passes from one scene to the
    next, and a crash or a hang costs only that scene's row), at most `jobs` at once,
    costliest first by cost(scene); a scene still running after `timeout` s is stopped.
    Ctrl-C stops every process and raises Interrupted, naming each scene and its step."""
    from ..executor import Task, make_executor
    from ..executor.progress import StepLines

    order = sorted(scenes, key=cost, reverse=True) if cost else list(scenes)
    tasks = [Task(s.name, (s,), meta={"dt": s.dt}) for s in order]
    with make_executor("processes", workers=max(1, jobs)) as executor:
        return executor.run(work, tasks, desc="scenarios", progress=StepLines("scenarios"), timeout=timeout,
                            retry=False, failed=functools.partial(_no_verdict, timeout=timeout))


def _no_verdict(task, failure, timeout: float | None) -> Outcome:
    """The row of a scenario whose process gave no Outcome: it raised outside run_one, died
    (a crash outside Python), or ran past --timeout. Not run again: its crash is its verdict."""
    if failure.kind == "timeout":
        return Outcome(failure=("timeout", f"stopped after {timeout:g} s (--timeout), at {failure.detail}"))
    if failure.kind == "died":
        return Outcome(failure=("error", f"the process running it ended without a verdict ({failure.detail}): "
                                         "a crash outside Python, or the machine stopping it"))
    return Outcome(failure=("error", failure.reason.splitlines()[0]))
