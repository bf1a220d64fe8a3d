"""The executor interface: tasks in, results by task key out, one rule for failures.

    with make_executor("pool", workers=4) as executor:
        results = executor.run(fn, tasks, desc="sweep", store=Store(folder), split=..., failed=...)

A task is fn(*task.args); its result depends on nothing else. A backend (processes.py, pool.py,
dask.py) only starts, watches and stops tasks; everything else is here, the same for all:

  - results already in `store` are not computed again; each new one is saved as it arrives;
  - a task that raised or whose worker died is run once more, split into single runs when
    `split` is given (one bad run cannot take its batch's other runs down with it); a second
    failure becomes failed(task, failure) (without `failed`: RuntimeError). With retry=False
    the first failure is final;
  - a task still running after `timeout` s is stopped and never run again;
  - progress: a bar of runs done (progress.Bar), or any object with the same four methods;
  - Ctrl-C stops every running task and raises Interrupted, naming each and the step it had
    reached.
"""
from __future__ import annotations

import time
from collections import deque
from dataclasses import dataclass, field, replace
from typing import Any
from collections.abc import Callable

from .progress import Bar, where
from .results import Store

POLL = 0.2   # s between two looks at the running tasks (Ctrl-C and timeouts are seen within it)


@dataclass(frozen=True)
class Task:
    """key: unique and stable (a scene's name, a hash of the parameters); args: fn's arguments;
    runs: how many runs it holds (the progress bar's unit); attempt: 1, then 2 when run again;
    meta: what the progress display may use ("dt": s per step, to tell a step's time)."""

    key: str
    args: tuple
    runs: int = 1
    attempt: int = 1
    meta: dict = field(default_factory=dict, compare=False)


@dataclass(frozen=True)
class Failure:
    """Why a task gave no result. kind: "raised" (fn raised), "died" (its worker process ended),
    "timeout"; reason: one line for a report; detail: how a worker died ("exit code 70",
    "killed by signal 9"), or where a timed-out task was stopped."""

    kind: str
    reason: str
    detail: str = ""

    def __str__(self) -> str:
        return self.reason


@dataclass(frozen=True)
class Finished:
    value: Any


class Interrupted(KeyboardInterrupt):
    """Ctrl-C: `where` names each task that was running and the step it had reached."""

    def __init__(self, where: list[str]):
        super().__init__("; ".join(where) or "between two tasks")
        self.where = where


def failure_text(exc: BaseException) -> str:
    """`Type: message` (`Type` alone without a message)."""
    text = str(exc).strip()
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


DIED = "the worker running it died"


class Executor:
    """The interface; a backend implements the five methods below `run`."""

    capacity: int = 1            # tasks running at once
    workers: int = 1             # worker processes
    threads_per_task: int = 1    # threads a task may use inside its worker
    scheduler: str | None = None
    timeouts = True              # can stop a running task (`timeout`)
    retried = 0                  # tasks run again after a failure, over the executor's life

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def run(self, fn: Callable, tasks: list[Task], desc: str = "tasks", store: Store | None = None,
            split: Callable[[Task], list[Task]] | None = None,
            failed: Callable[[Task, Failure], Any] | None = None, progress=True,
            timeout: float | None = None, retry: bool = True) -> dict[str, Any]:
        """Results of fn(*task.args) by task key, the tasks started in the order given.
        split(task) -> tasks of one run each (run after a first failure); failed(task, failure)
        -> the result of a task that failed for good; progress: True/False (a bar of runs) or a
        display (progress.Bar's methods); timeout: s a task may run."""
        if timeout is not None and not self.timeouts:
            raise ValueError(f"{type(self).__name__} cannot stop a running task: no timeout")
        results, todo = _from_store(tasks, store)
        shown = progress if hasattr(progress, "show") else Bar(desc, enabled=bool(progress))
        shown.start(tasks, todo)
        queue = deque(todo)
        running: dict = {}   # handle -> (task, time.monotonic() at its start)
        try:
            while queue or running:
                while queue and len(running) < self.capacity:
                    task = queue.popleft()
                    running[self._start(fn, task, f"{desc}-{task.key}-{task.attempt}")] = (task, time.monotonic())
                self._wait(list(running), POLL)
                for handle, (task, began) in list(running.items()):
                    end = self._poll(handle)
                    if end is None and timeout is not None and time.monotonic() - began > timeout:
                        at = where(task, self._steps(handle))
                        self._stop(handle)
                        end = Failure("timeout", f"stopped after {timeout:g} s, at {at}", at)
                    if end is None:
                        continue
                    del running[handle]
                    if isinstance(end, Finished):
                        _keep(results, store, task.key, end.value)
                        shown.finished(task)
                        continue
                    if retry and task.attempt < 2 and end.kind != "timeout":
                        self.retried += 1
                        again = split(task) if (split and task.runs > 1) else [task]
                        queue.extend(replace(t, attempt=2) for t in again)
                        continue
                    if failed is None:
                        twice = " twice" if task.attempt > 1 else ""
                        raise RuntimeError(f"{desc}: task {task.key} failed{twice}: {end}")
                    _keep(results, store, task.key, failed(task, end))
                    shown.finished(task)
                shown.show([(t, self._steps(h)) for h, (t, _) in running.items()], len(results))
        except KeyboardInterrupt:
            at = [where(t, self._steps(h)) for h, (t, _) in running.items()]
            raise Interrupted(at) from None
        finally:
            for handle in running:
                self._stop(handle)
            shown.close()
        return results

    # --- what a backend implements ------------------------------------------------------

    def _start(self, fn: Callable, task: Task, name: str):
        """Start fn(*task.args) (name: unique among the tasks started); returns its handle."""
        raise NotImplementedError

    def _wait(self, handles: list, seconds: float) -> None:
        """Return when a task may have ended, or after `seconds`."""
        raise NotImplementedError

    def _poll(self, handle) -> Finished | Failure | None:
        """The task's end, or None while it runs."""
        raise NotImplementedError

    def _stop(self, handle) -> None:
        """Stop the task at once (its worker killed, or its result dropped)."""
        raise NotImplementedError

    def _steps(self, handle) -> tuple[int, int, float]:
        """(steps reached, steps in the run, time.time() stepping began; 0 before, or unknown)."""
        return 0, 0, 0.0

    def close(self) -> None:
        """Let go of the workers."""


def _from_store(tasks: list[Task], store: Store | None) -> tuple[dict[str, Any], list[Task]]:
    """(the results `store` already holds, by task key; the tasks still to run)."""
    results, todo = {}, []
    for task in tasks:
        done = store.load(task.key) if store else None
        if done is not None:
            results[task.key] = done
        else:
            todo.append(task)
    return results, todo


def _keep(results: dict, store: Store | None, key: str, result) -> None:
    results[key] = result
    if store is not None:
        store.save(key, result)
