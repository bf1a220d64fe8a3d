"""Worker processes on this machine, the common part of the processes and pool backends.

Each worker is a child process with a pipe to this one and a slot of a shared array where the
task it runs publishes its steps (steps.py). The children ignore Ctrl-C: this process takes it
and stops them. A child that ends without an answer has died: its task fails with how it ended
(exit code, signal).
"""
from __future__ import annotations

import os
import signal
from dataclasses import dataclass
from multiprocessing.connection import wait

from . import steps
from .base import DIED, Executor, Failure, Finished, failure_text


@dataclass(eq=False)
class Worker:
    """A child process, this end of its pipe, and its slot of the step counters."""

    process: object
    conn: object
    slot: int


def answer(conn, fn, args) -> None:
    """Send fn(*args) back as ("ok", result), or ("raised", `Type: message`)."""
    try:
        message = ("ok", fn(*args))
    except BaseException as exc:  # noqa: BLE001 - anything the task raises is its failure
        message = ("raised", failure_text(exc))
    try:
        conn.send(message)
    except Exception as exc:  # noqa: BLE001 - a result that cannot be pickled
        conn.send(("raised", f"its result could not be sent back: {failure_text(exc)}"))


def ignore_ctrl_c() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)   # the parent stops us


def one_thread_each() -> None:
    """One thread for each library that would start its own pool (numba's and MuJoCo's own
    threads are then the only parallelism inside a worker)."""
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, "1")
    os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")   # see custom_sim/batch.py


class LocalExecutor(Executor):
    """`workers` slots, each running at most one task at a time in a child process."""

    def __init__(self, context, workers: int | None = None, threads_per_task: int | None = None):
        cores = os.cpu_count() or 1
        self.context = context
        self.workers = self.capacity = max(1, workers or cores)
        self.threads_per_task = threads_per_task or max(1, cores // self.workers)
        self.retried = 0
        self.shared = context.RawArray("d", steps.FIELDS * self.workers)
        self.busy: set[int] = set()

    def _free_slot(self) -> int:
        slot = min(set(range(self.workers)) - self.busy)
        self.busy.add(slot)
        k = slot * steps.FIELDS
        self.shared[k:k + steps.FIELDS] = [0.0] * steps.FIELDS
        return slot

    def _wait(self, handles: list[Worker], seconds: float) -> None:
        wait([h.conn for h in handles] + [h.process.sentinel for h in handles], seconds)

    def _poll(self, handle: Worker) -> Finished | Failure | None:
        if handle.conn.poll():
            try:
                kind, value = handle.conn.recv()
            except (EOFError, OSError):   # closed without an answer
                return self._died(handle)
            self._done(handle)
            return Finished(value) if kind == "ok" else Failure("raised", value)
        if not handle.process.is_alive():
            return self._died(handle)
        return None

    def _died(self, handle: Worker) -> Failure:
        handle.process.join()
        code = handle.process.exitcode
        how = f"killed by signal {-code}" if code is not None and code < 0 else f"exit code {code}"
        self._discard(handle)
        return Failure("died", DIED, how)

    def _stop(self, handle: Worker) -> None:
        handle.process.kill()
        handle.process.join()
        self._discard(handle)

    def _steps(self, handle: Worker) -> tuple[int, int, float]:
        return steps.read(self.shared, handle.slot)

    def _done(self, handle: Worker) -> None:
        """The task answered: its slot is free again."""
        self.busy.discard(handle.slot)

    def _discard(self, handle: Worker) -> None:
        """The worker is gone: close this end of its pipe, free its slot."""
        handle.conn.close()
        self.busy.discard(handle.slot)
