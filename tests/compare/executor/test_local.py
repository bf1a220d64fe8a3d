"""The local backends (a fork per task, a pool): a timeout stops only its task and is final,
Ctrl-C stops every task and names each with the step it had reached, the steps are shown."""
from __future__ import annotations

import os
import re
import signal
import time
from pathlib import Path

import pytest

from compare.executor import Interrupted, Task, make_executor, steps
from compare.executor.progress import StepLines



# The slow tasks here sleep this long unless stopped: a run that returns sooner stopped them.
SLOW_TASK = 60.0
# The timeout of test_a_timeout...: TIMEOUT_MARGIN times what two trivial tasks took through the
# same executor just before, under the same load (each started, its steps published, its answer
# seen: what the slow task must do, publish its step, before it is stopped for its row to name
# it), and at least MIN_TIMEOUT s against a reference that happened to be quick.
TIMEOUT_MARGIN = 10
MIN_TIMEOUT = 1.0


@pytest.fixture(params=["processes", "pool"])
def local(request):
    """Two workers, started (a pool's spawned worker imports for a while before its first task)."""
    with make_executor(request.param, workers=2) as executor:
        executor.run(_stepping, [Task(f"warm{i}", (1, 1, 0.0)) for i in range(2)], progress=False)
        yield executor


def _stepping(total: int, reached: int, seconds: float, pid_file: str = "") -> str:
    """Publish `reached` of `total` steps, write this process's id to `pid_file` (if given),
    then sleep `seconds`."""
    steps.started(total)
    steps.reached(reached)
    if pid_file:
        Path(pid_file).write_text(str(os.getpid()))
    time.sleep(seconds)
    return "done"


def gone(pid_file: Path) -> bool:
    """The process whose id `pid_file` holds has ended (and was reaped)."""
    try:
        os.kill(int(pid_file.read_text()), 0)
    except ProcessLookupError:
        return True
    return False


def test_a_timeout_stops_its_task_only_and_is_not_retried(local, tmp_path):
    began = time.monotonic()
    local.run(_stepping, [Task(f"ref{i}", (1, 1, 0.0)) for i in range(2)], progress=False)
    timeout = max(MIN_TIMEOUT, TIMEOUT_MARGIN * (time.monotonic() - began))
    slow = tmp_path / "slow.pid"
    tasks = [Task("slow", (100, 7, SLOW_TASK, str(slow)), meta={"dt": 0.01}), Task("quick", (10, 10, 0.0))]
    began = time.monotonic()
    out = local.run(_stepping, tasks, failed=lambda task, failure: failure, progress=False, timeout=timeout)
    took = time.monotonic() - began
    assert local.retried == 0
    assert out["quick"] == "done"
    failure = out["slow"]
    assert failure.kind == "timeout" and failure.detail == "slow at step 7 of 100 (t = 0.07 s)"
    assert failure.reason == f"stopped after {timeout:g} s, at slow at step 7 of 100 (t = 0.07 s)"
    # stopped at its timeout, not before and not left to sleep: its process is gone
    assert timeout <= took < SLOW_TASK and gone(slow), (took, timeout)


def test_dask_refuses_a_timeout():
    pytest.importorskip("distributed")
    from compare.executor.dask import DaskCluster

    executor = DaskCluster.__new__(DaskCluster)   # no cluster needed to refuse
    with pytest.raises(ValueError, match="no timeout"):
        executor.run(_stepping, [Task("slow", (1, 1, 0.0))], timeout=1.0)


class CtrlCOnceShown(StepLines):
    """The progress display of `run`, pressing Ctrl-C once it has shown a line for each of `keys`
    (as a user would who has seen where the tasks are)."""

    def __init__(self, keys):
        super().__init__("scenes")
        self.keys = set(keys)

    def show(self, running, done: int) -> None:
        super().show(running, done)
        if self.keys <= set(self.last):   # a line printed for each (stderr is not a terminal here)
            signal.raise_signal(signal.SIGINT)


def test_ctrl_c_stops_every_task_naming_each_and_its_step(local, capfd, tmp_path):
    pids = {key: tmp_path / f"{key}.pid" for key in ("first", "second", "waiting")}
    tasks = [Task("first", (100, 7, SLOW_TASK, str(pids["first"])), meta={"dt": 0.01}),
             Task("second", (50, 3, SLOW_TASK, str(pids["second"]))),
             Task("waiting", (1, 1, 0.0, str(pids["waiting"])))]
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    began = time.monotonic()
    try:
        with pytest.raises(Interrupted) as caught:
            local.run(_stepping, tasks, progress=CtrlCOnceShown(["first", "second"]))
    finally:
        signal.signal(signal.SIGINT, previous)
    took = time.monotonic() - began
    assert sorted(caught.value.where) == ["first at step 7 of 100 (t = 0.07 s)", "second at step 3 of 50"]
    # both running tasks stopped (not waited for), the waiting one never started
    assert took < SLOW_TASK and gone(pids["first"]) and gone(pids["second"]), took
    assert not pids["waiting"].exists()
    lines = capfd.readouterr().err.splitlines()
    for shown in ("first: step 7 of 100", "second: step 3 of 50"):
        assert any(re.fullmatch(rf"\[0 of 3 scenes done\] {shown}, [\d,]+ steps/s, about \d+ s to go", line)
                   for line in lines), lines
