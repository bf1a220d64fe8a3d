"""A fresh process forked for each task: what `run` uses, one scenario per process.

No state of a user's module (or of anything else) passes from one task to the next, and a
crash, a hang or a timeout costs only that task. A fork inherits this process's imports and
compiled code and pickles nothing on the way in (the task's function may hold a user's
module); its start costs about 10 ms, against seconds for a Dask local cluster.
"""
from __future__ import annotations

import multiprocessing

from . import steps
from .local import LocalExecutor, Worker, answer, ignore_ctrl_c


def _child(fn, args, conn, shared, slot: int) -> None:
    ignore_ctrl_c()
    steps.attach(shared, slot)
    try:
        answer(conn, fn, args)
    finally:
        conn.close()


class Processes(LocalExecutor):
    """At most `workers` tasks at once (default: every core), each in a process forked for it."""

    def __init__(self, workers: int | None = None, threads_per_task: int | None = None):
        super().__init__(multiprocessing.get_context("fork"), workers, threads_per_task)

    def _start(self, fn, task, name) -> Worker:
        slot = self._free_slot()
        receive, send = self.context.Pipe(duplex=False)
        process = self.context.Process(target=_child, args=(fn, task.args, send, self.shared, slot), daemon=True)
        process.start()
        send.close()
        return Worker(process, receive, slot)

    def _done(self, handle: Worker) -> None:
        handle.process.join()
        self._discard(handle)
