"""The one retry rule, on every backend: a task whose worker died, or that raised, runs once
more (a batch split into single runs); a second failure becomes failed(task, failure); results
kept in a Store are not computed again.

The Dask backend's local cluster (two workers) is the one test_study uses: same xdist worker.
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest

from compare.executor import Store, Task, make_executor

pytestmark = pytest.mark.xdist_group("dask_cluster")

BACKENDS = ["processes", "pool", "dask"]


def _task(a: float, b: float, dies: str = "") -> float:
    """a / b; first ends its worker process when `dies` is "always", or "once:<marker file>"
    while that file does not exist yet (it is created)."""
    if dies == "always":
        os._exit(3)
    if dies.startswith("once:"):
        marker = Path(dies[len("once:"):])
        if not marker.exists():
            marker.write_text("died once\n")
            os._exit(3)
    return a / b


def _marked(task, failure) -> str:
    return f"failed ({failure.kind}): {failure}"


@pytest.fixture(scope="module", params=BACKENDS)
def executor(request):
    with make_executor(request.param, workers=2) as ex:
        yield ex
        if request.param == "dask":   # the nanny restarts a dead worker: whole again for test_study
            ex.client.wait_for_workers(2, timeout=120)


def test_a_task_whose_worker_dies_once_is_run_again(executor, tmp_path):
    tasks = [Task(f"ok{i}", (float(i), 2.0)) for i in range(4)]
    tasks.insert(1, Task("once", (1.0, 4.0, f"once:{tmp_path / 'marker'}")))
    before = executor.retried
    out = executor.run(_task, tasks, desc="once", failed=_marked, progress=False)
    assert out == {"once": 0.25, **{f"ok{i}": i / 2.0 for i in range(4)}}
    assert executor.retried - before >= 1


def test_a_task_whose_worker_dies_twice_is_marked_failed(executor):
    out = executor.run(_task, [Task("dies", (1.0, 1.0, "always"))], desc="twice", failed=_marked, progress=False)
    assert out == {"dies": "failed (died): the worker running it died"}


def test_a_raising_batch_is_split_and_a_run_that_fails_twice_is_marked(executor, tmp_path):
    """(1, 0) raises every time, (1, 2) never; "kept" is in the store already and not run."""
    def split(task):
        return [Task("good", (1.0, 2.0)), Task("bad", (1.0, 0.0))]

    store = Store(tmp_path)
    store.save("kept", 42)
    tasks = [Task("batch", (1.0, 0.0), runs=2), Task("alone", (3.0, 0.0)), Task("fine", (3.0, 4.0)),
             Task("kept", (1.0, 0.0))]
    before = executor.retried
    out = executor.run(_task, tasks, desc="raising", store=store, split=split, failed=_marked, progress=False)
    assert out["fine"] == 0.75 and out["good"] == 0.5 and out["kept"] == 42 and "batch" not in out
    assert out["bad"] == out["alone"] == "failed (raised): ZeroDivisionError: float division by zero"
    assert executor.retried - before == 2
    assert store.load("fine") == 0.75 and store.load("bad") == out["bad"]


def test_without_failed_a_second_failure_raises(executor):
    with pytest.raises(RuntimeError, match=r"raising: task alone failed twice: ZeroDivisionError"):
        executor.run(_task, [Task("alone", (3.0, 0.0))], desc="raising", progress=False)
