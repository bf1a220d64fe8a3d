"""A pool of local worker processes kept for the executor's life: `sweep` without Dask.

Each worker is started fresh (spawn, as Dask's local cluster does), imports what its first
task needs and then serves one task at a time; its function and arguments are pickled to it.
A worker that dies is replaced by a fresh one for the next task. close() ends them.
"""
from __future__ import annotations

import multiprocessing

from . import steps
from .local import LocalExecutor, Worker, answer, ignore_ctrl_c, one_thread_each


def _serve(conn, shared, slot: int) -> None:
    """A worker's life: tasks (fn, args) from the pipe until None or the pipe closes."""
    ignore_ctrl_c()
    one_thread_each()
    steps.attach(shared, slot)
    while True:
        try:
            job = conn.recv()
        except EOFError:
            return
        except Exception:  # noqa: BLE001 - a task this worker cannot unpickle
            job = (_unreadable, ())
        if job is None:
            return
        answer(conn, *job)


def _unreadable():
    raise RuntimeError("the task could not be unpickled in the worker (is its function importable there?)")


class Pool(LocalExecutor):
    """`workers` spawned processes (default: every core), each running one task at a time."""

    def __init__(self, workers: int | None = None, threads_per_task: int | None = None):
        super().__init__(multiprocessing.get_context("spawn"), workers, threads_per_task)
        self.idle: dict[int, Worker] = {}   # slot -> a live worker waiting for a task

    def _start(self, fn, task, name) -> Worker:
        slot = self._free_slot()
        worker = self.idle.pop(slot, None)
        if worker is not None and not worker.process.is_alive():   # ended while idle
            worker.conn.close()
            worker = None
        if worker is None:
            here, there = self.context.Pipe()
            process = self.context.Process(target=_serve, args=(there, self.shared, slot), daemon=True)
            process.start()
            there.close()
            worker = Worker(process, here, slot)
        worker.conn.send((fn, task.args))
        return worker

    def _done(self, handle: Worker) -> None:
        super()._done(handle)
        self.idle[handle.slot] = handle

    def close(self) -> None:
        for worker in self.idle.values():
            try:
                worker.conn.send(None)
            except OSError:
                pass
        for worker in self.idle.values():
            worker.process.join(timeout=5)
            if worker.process.is_alive():
                worker.process.kill()
                worker.process.join()
            worker.conn.close()
        self.idle.clear()
