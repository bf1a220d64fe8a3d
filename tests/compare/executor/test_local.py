"""The local backends (a fork per task, a pool): a timeout stops only its task and is final,
Ctrl-C stops every task and names each with the step it had reached, the steps are shown."""
from __future__ import annotations

import os
import signal
import threading
import time

import pytest

from compare.executor import Interrupted, Task, make_executor, steps
from compare.executor.progress import StepLines



@pytest.fixture(params=["processes", "pool"])
def local(request):
    """Two workers, started (a pool's spawned worker imports for a while before its first task)."""
    with make_executor(request.param, workers=2) as executor:
        executor.run(_stepping, [Task(f"warm{i}", (1, 1, 0.0)) for i in range(2)], progress=False)
        yield executor


def _stepping(total: int, reached: int, seconds: float) -> str:
    """Publish `reached` of `total` steps, then sleep `seconds`."""
    steps.started(total)
    steps.reached(reached)
    time.sleep(seconds)
    return "done"


def test_a_timeout_stops_its_task_only_and_is_not_retried(local):
    tasks = [Task("slow", (100, 7, 60.0), meta={"dt": 0.01}), Task("quick", (10, 10, 0.0))]
    start = time.monotonic()
    out = local.run(_stepping, tasks, failed=lambda task, failure: failure, progress=False, timeout=2.0)
    assert local.retried == 0
    assert out["quick"] == "done" and time.monotonic() - start < 20
    failure = out["slow"]
    assert failure.kind == "timeout" and failure.detail == "slow at step 7 of 100 (t = 0.07 s)"
    assert failure.reason == "stopped after 2 s, at slow at step 7 of 100 (t = 0.07 s)"


def test_dask_refuses_a_timeout():
    pytest.importorskip("distributed")
    from compare.executor.dask import DaskCluster

    executor = DaskCluster.__new__(DaskCluster)   # no cluster needed to refuse
    with pytest.raises(ValueError, match="no timeout"):
        executor.run(_stepping, [Task("slow", (1, 1, 0.0))], timeout=1.0)


def test_ctrl_c_stops_every_task_naming_each_and_its_step(local, capfd):
    tasks = [Task("first", (100, 7, 60.0), meta={"dt": 0.01}), Task("second", (50, 3, 60.0)),
             Task("waiting", (1, 1, 0.0))]
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(3.0, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    try:
        timer.start()
        with pytest.raises(Interrupted) as caught:
            local.run(_stepping, tasks, progress=StepLines("scenes"))
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    assert time.monotonic() - start < 20
    assert sorted(caught.value.where) == ["first at step 7 of 100 (t = 0.07 s)", "second at step 3 of 50"]
    err = capfd.readouterr().err
    assert "[0 of 3 scenes done] first: step 7 of 100" in err and "steps/s" in err, err
