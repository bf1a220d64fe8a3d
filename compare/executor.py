"""The distributed engine of `study` and `sweep`: tasks on a Dask cluster, retried when a worker dies.

    with Engine(scheduler=None, workers=None) as engine:
        results = engine.run(fn, tasks, desc="study", store=Store(folder), split=..., failed=...)

A task is a batch: fn(*task.args) is a pure function of its arguments (picklable, so any
worker can run it) and its result depends on nothing else. The cluster is

  - by default a LocalCluster of `workers` processes (default: every core) of one thread
    each, started once per process (a start takes seconds) and closed at exit: numba's and MuJoCo's own threads are then the only parallelism inside a process,
    and `threads_per_task` tells each task how many it may use (cores / workers on its host);
  - with `scheduler="tcp://HOST:PORT"` an existing cluster (`dask scheduler`, `dask worker`).

Failures. A worker that dies loses only the task it was running: the scheduler reports it
(KilledWorker; the local cluster allows no silent rescheduling, so the engine decides), the
nanny starts a fresh worker, and the engine submits the task again, split into single runs
when `split` is given, so one bad run cannot take its batch's other runs down with it. A task
that fails a second time becomes `failed(task, reason)` (or raises, without `failed`).

Results already computed are kept in a Store (one JSON file per finished task, written as it
arrives, keyed by the task's key): a run interrupted and started again skips them.

Dask is the `study` extra (`pip install -e '.[study]'`). Without it, `make_engine` gives a
PoolEngine: the same `run` on a local pool of `workers` processes (concurrent.futures), which
is what `sweep` uses in the base install; `study` and `--scheduler` need Dask (`require_dask`).
"""
from __future__ import annotations

import json
import logging
import os
import sys
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Callable

from .report.atomic import finite_json, write_text_atomically

# How long to wait for an existing scheduler before giving up (s).
CONNECT_TIMEOUT = 10.0
STUDY_EXTRA = "pip install -e '.[study]'"   # what installs Dask


def dask_available() -> bool:
    """Dask and distributed are installed (looked up, not imported: an import takes ~1 s)."""
    import importlib.util

    try:
        return all(importlib.util.find_spec(name) is not None for name in ("dask", "distributed"))
    except (ImportError, ValueError):
        return False


def require_dask(what: str) -> None:
    """Bad input, one line, when Dask is missing: '<what> needs Dask: pip install ...'."""
    if not dask_available():
        from scene_types import BadInput
        raise BadInput(f"{what} needs Dask: {STUDY_EXTRA}")


def make_engine(scheduler: str | None = None, workers: int | None = None,
                threads_per_task: int | None = None):
    """An Engine on Dask when it is installed (a local cluster, or the one at `scheduler`), else
    a PoolEngine of local processes; `scheduler` without Dask is bad input."""
    if dask_available():
        return Engine(scheduler=scheduler, workers=workers, threads_per_task=threads_per_task)
    if scheduler:
        require_dask(f"--scheduler {scheduler}")
    return PoolEngine(workers=workers, threads_per_task=threads_per_task)


@dataclass(frozen=True)
class Task:
    """key: unique and stable (a hash of the parameters); args: fn's arguments; runs: how many
    runs it holds (the progress bar's unit); attempt: 1, then 2 when resubmitted."""

    key: str
    args: tuple
    runs: int = 1
    attempt: int = 1
    meta: dict = field(default_factory=dict, compare=False)


class Store:
    """A folder of finished results, one `<key>.json` each, written atomically."""

    def __init__(self, folder: str | Path):
        self.folder = Path(folder)

    def path(self, key: str) -> Path:
        return self.folder / f"{key}.json"

    def load(self, key: str):
        try:
            return json.loads(self.path(key).read_text())
        except (OSError, ValueError):
            return None   # absent, or cut short by an interruption: computed again

    def save(self, key: str, result) -> None:
        self.folder.mkdir(parents=True, exist_ok=True)
        write_text_atomically(self.path(key), finite_json(result))

    def keys(self) -> set[str]:
        return {p.stem for p in self.folder.glob("*.json")} if self.folder.is_dir() else set()


def _worker_setup() -> None:
    """Run in every worker: one thread for each library that would start its own pool."""
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, "1")
    os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")   # see custom_sim/batch.py


def _host_and_cores() -> tuple[str, int]:
    import socket
    return socket.gethostname(), os.cpu_count() or 1


_LOCAL: dict[int, tuple] = {}   # workers -> (LocalCluster, Client): one per process, reused


def _local_client(workers: int):
    """The process's local cluster of `workers` single-thread worker processes, started once
    (a start takes seconds) and closed when the process exits."""
    import atexit

    import dask
    from distributed import Client, LocalCluster

    cluster, client = _LOCAL.get(workers, (None, None))
    if cluster is not None and cluster.status.name == "running" and client.status == "running":
        return cluster, client
    # a task on a worker that dies is not rescheduled behind the engine's back: the engine
    # resubmits it (split into single runs) and counts the attempt
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}):
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=None, worker_dashboard_address=None,
                               silence_logs=logging.ERROR)
    client = Client(cluster)
    if not _LOCAL:
        atexit.register(_close_local)
    _LOCAL[workers] = (cluster, client)
    return cluster, client


def _close_local() -> None:
    for cluster, client in _LOCAL.values():
        client.close()
        cluster.close()
    _LOCAL.clear()


class _Closing:
    """`with engine:` closes it at the end (each engine has its own close)."""

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


class Engine(_Closing):
    """A Dask client on a local or remote cluster (see the module docstring)."""

    def __init__(self, scheduler: str | None = None, workers: int | None = None,
                 threads_per_task: int | None = None):
        """threads_per_task: threads a task may use (default: cores / workers on its host)."""
        from distributed import Client

        self.scheduler = scheduler
        self.cluster = None
        if scheduler:
            from scene_types import BadInput
            try:
                self.client = Client(scheduler, timeout=CONNECT_TIMEOUT)
            except (OSError, TimeoutError) as exc:
                raise BadInput(f"--scheduler {scheduler}: no Dask scheduler answers there ({exc}); "
                               "expected the address of a running `dask scheduler`, e.g. tcp://127.0.0.1:8786") from None
        else:
            self.cluster, self.client = _local_client(workers or os.cpu_count() or 1)
        self.client.run(_worker_setup)
        self.retried = 0   # tasks submitted again after a failure, over this engine's life
        self.threads_per_task = threads_per_task or self._threads_per_task()

    def _threads_per_task(self) -> int:
        """Cores per worker on the busiest host (at least 1): what a task may use inside."""
        info = self.client.run(_host_and_cores)
        per_host: dict[str, list[int]] = {}
        for host, cores in info.values():
            per_host.setdefault(host, []).append(cores)
        return max(1, min(cores[0] // len(cores) for cores in per_host.values())) if per_host else 1

    @property
    def workers(self) -> int:
        return len(self.client.scheduler_info(n_workers=-1)["workers"])

    def close(self) -> None:
        """Disconnect from a remote cluster; the local cluster stays for the process's next
        engine and is closed at exit."""
        if self.cluster is None:
            self.client.close()

    def run(self, fn: Callable, tasks: list[Task], desc: str = "tasks", store: Store | None = None,
            split: Callable[[Task], list[Task]] | None = None,
            failed: Callable[[Task, str], Any] | None = None, progress: bool = True) -> dict[str, Any]:
        """Results of fn(*task.args) by task key; tasks already in `store` are not run again.
        split(task) -> tasks of one run each (resubmitted after a first failure); failed(task,
        reason) -> the result of a task that failed twice (default: raise RuntimeError)."""
        from distributed import as_completed

        results, todo = _from_store(tasks, store)
        bar = _bar(tasks, todo, desc, progress)
        pending = {}

        def submit(task: Task):
            future = self.client.submit(fn, *task.args, key=f"{desc}-{task.key}-{task.attempt}", pure=False)
            pending[future] = task
            return future

        stream = as_completed([submit(t) for t in todo])
        for future in stream:
            task = pending.pop(future)
            if future.status == "finished":
                result = future.result()
                self._keep(results, store, task.key, result)
                bar.update(task.runs)
                continue
            retry = _after_failure(task, _reason(future), desc, results, store, split, failed, bar)
            self.retried += bool(retry)
            for t in retry:
                stream.add(submit(t))
        bar.close()
        return results

    @staticmethod
    def _keep(results: dict, store: Store | None, key: str, result) -> None:
        results[key] = result
        if store is not None:
            store.save(key, result)


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


def _bar(tasks: list[Task], todo: list[Task], desc: str, progress: bool):
    from tqdm import tqdm

    total = sum(t.runs for t in tasks)
    return tqdm(total=total, initial=total - sum(t.runs for t in todo), desc=desc, unit="run",
                file=sys.stderr, delay=1, disable=not progress)


def _after_failure(task: Task, reason: str, desc: str, results: dict, store: Store | None,
                   split, failed, bar) -> list[Task]:
    """The tasks to submit again after `task` failed: on a first failure, the task split into its
    runs (or once more); on a second, none: its result is failed(task, reason) (without
    `failed`, RuntimeError)."""
    if task.attempt < 2:
        return split(task) if (split and task.runs > 1) else [replace(task, attempt=2)]
    if failed is None:
        bar.close()
        raise RuntimeError(f"{desc}: task {task.key} failed twice: {reason}")
    Engine._keep(results, store, task.key, failed(task, reason))
    bar.update(task.runs)
    return []


def _reason(future) -> str:
    try:
        exc = future.exception()
    except Exception as err:  # noqa: BLE001 - the scheduler's own error (a lost worker)
        exc = err
    name = type(exc).__name__
    if name == "KilledWorker":
        return "the worker running it died"
    return f"{name}: {exc}"


class PoolEngine(_Closing):
    """Engine.run without Dask: tasks on `workers` local processes (default: every core), each a
    pool of its own holding one task at a time, started fresh (spawn, as Dask's local cluster
    does) and closed by close(). As on Dask, a worker that dies loses only the task it was
    running, and is started again; a task that raised or lost its worker is resubmitted once
    (split into single runs when `split` is given), then becomes `failed(task, reason)`."""

    scheduler = None

    def __init__(self, workers: int | None = None, threads_per_task: int | None = None):
        cores = os.cpu_count() or 1
        self._lanes: list = [None] * max(1, workers or cores)
        self.threads_per_task = threads_per_task or max(1, cores // len(self._lanes))
        self.retried = 0

    @property
    def workers(self) -> int:
        return len(self._lanes)

    def _lane(self, i: int):
        if self._lanes[i] is None:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            self._lanes[i] = ProcessPoolExecutor(max_workers=1, initializer=_worker_setup,
                                                 mp_context=multiprocessing.get_context("spawn"))
        return self._lanes[i]

    def _drop(self, i: int) -> None:
        lane, self._lanes[i] = self._lanes[i], None
        if lane is not None:
            lane.shutdown(wait=True, cancel_futures=True)

    def close(self) -> None:
        for i in range(len(self._lanes)):
            self._drop(i)

    def run(self, fn: Callable, tasks: list[Task], desc: str = "tasks", store: Store | None = None,
            split: Callable[[Task], list[Task]] | None = None,
            failed: Callable[[Task, str], Any] | None = None, progress: bool = True) -> dict[str, Any]:
        """As Engine.run."""
        from collections import deque
        from concurrent.futures import FIRST_COMPLETED, wait
        from concurrent.futures.process import BrokenProcessPool

        results, waiting = _from_store(tasks, store)
        todo: deque[Task] = deque(waiting)
        bar = _bar(tasks, waiting, desc, progress)
        running: dict = {}   # future -> (task, lane)
        try:
            while todo or running:
                busy = {lane for _, lane in running.values()}
                for i in range(len(self._lanes)):
                    if todo and i not in busy:
                        task = todo.popleft()
                        running[self._lane(i).submit(fn, *task.args)] = (task, i)
                finished, _ = wait(list(running), return_when=FIRST_COMPLETED)
                for future in finished:
                    task, lane = running.pop(future)
                    exc = future.exception()
                    if exc is None:
                        Engine._keep(results, store, task.key, future.result())
                        bar.update(task.runs)
                        continue
                    if isinstance(exc, BrokenProcessPool):   # its process died: a fresh one next
                        self._drop(lane)
                        reason = "the worker running it died"
                    else:
                        reason = f"{type(exc).__name__}: {exc}"
                    retry = _after_failure(task, reason, desc, results, store, split, failed, bar)
                    self.retried += bool(retry)
                    todo.extend(retry)
        finally:
            bar.close()
        return results
