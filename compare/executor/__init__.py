"""One interface for running tasks in parallel: `run`, `sweep`, `study` and the tools all use it.

    with make_executor("processes" | "pool" | "dask" | "auto", workers=N) as executor:
        results = executor.run(fn, tasks, ...)      # {task key: result}

    base.py       the interface: Task, the run loop, the one retry rule, timeout, Ctrl-C
    results.py    Store: finished results kept on disk, skipped when a run starts again
    progress.py   what the user sees: a bar of runs done, or each task's steps per second
    processes.py  a process forked for each task (run: isolation, per-scene timeout)
    pool.py       a pool of spawned local processes (sweep without Dask)
    dask.py       a Dask cluster, local or `--scheduler ADDRESS` (study; the `study` extra)
"""
from __future__ import annotations

from .base import Executor, Failure, Interrupted, Task
from .results import Store

STUDY_EXTRA = "pip install -e '.[study]'"   # what installs Dask
KINDS = ("processes", "pool", "dask", "auto")

__all__ = ["Executor", "Failure", "Interrupted", "Task", "Store", "make_executor", "dask_available",
           "require_dask", "STUDY_EXTRA"]


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


def make_executor(kind: str = "auto", scheduler: str | None = None, workers: int | None = None,
                  threads_per_task: int | None = None, dashboard: str | None = None) -> Executor:
    """The executor of `kind` with `workers` processes (default: every core):

      processes  a fresh process forked for each task (isolated; a task can be timed out)
      pool       spawned local processes kept for the executor's life
      dask       the Dask cluster at `scheduler`, else a local one on 127.0.0.1 (needs Dask;
                 dashboard: HOST:PORT to open the local one's dashboard at)
      auto       dask when Dask is installed, else pool; `scheduler` without Dask is bad input
    """
    if kind not in KINDS:
        raise ValueError(f"executor {kind!r}: expected one of {', '.join(KINDS)}")
    if kind == "auto":
        kind = "dask" if dask_available() else "pool"
    if scheduler and kind != "dask":
        require_dask(f"--scheduler {scheduler}")
        raise ValueError(f"--scheduler needs the dask executor, not {kind}")
    if kind == "processes":
        from .processes import Processes
        return Processes(workers, threads_per_task)
    if kind == "pool":
        from .pool import Pool
        return Pool(workers, threads_per_task)
    require_dask(f"--scheduler {scheduler}" if scheduler else "the dask executor")
    from .dask import DaskCluster
    return DaskCluster(scheduler, workers, threads_per_task, dashboard)
