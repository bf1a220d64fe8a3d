"""A Dask cluster: `study`, and `sweep` when Dask is installed. Dask is the `study` extra.

The cluster is

  - by default a LocalCluster of `workers` processes (default: every core) of one thread each,
    started once per process and closed at exit (a start takes seconds): numba's and MuJoCo's
    own threads are then the only parallelism inside a process, and `threads_per_task` tells
    each task how many it may use (cores / workers on its host);
  - with `scheduler="tcp://HOST:PORT"` an existing cluster (`dask scheduler`, `dask worker`);
    `tls://HOST:PORT` with Dask's own TLS settings (dask config `distributed.comm.tls.*`, e.g.
    DASK_DISTRIBUTED__COMM__TLS__CA_FILE, ...__CLIENT__CERT, ...__CLIENT__KEY).

Nothing of the local cluster listens beyond the machine: its scheduler, its workers and every
HTTP server (the dashboard included) bind 127.0.0.1. `dashboard="127.0.0.1:0"` opens the
dashboard there (LOOPBACK_DASHBOARD: a free port); its address is `dashboard_link`.

Every task is submitted at once; the scheduler spreads them. A worker that dies loses only the
task it was running: the scheduler reports it (KilledWorker: the local cluster allows no silent
rescheduling, so the executor's rule decides) and the nanny starts a fresh worker. A running
task cannot be stopped, only its result dropped: no `timeout`.
"""
from __future__ import annotations

import logging
import os

from .base import DIED, Executor, Failure, Finished, failure_text
from .local import one_thread_each

CONNECT_TIMEOUT = 10.0   # s to wait for an existing scheduler
LOOPBACK = "127.0.0.1"
LOOPBACK_DASHBOARD = f"{LOOPBACK}:0"   # the dashboard when asked: this machine only, a free port
TLS_SETTINGS = ("the dask config distributed.comm.tls.ca-file, distributed.comm.tls.client.cert and "
                "distributed.comm.tls.client.key (e.g. the environment variables "
                "DASK_DISTRIBUTED__COMM__TLS__CA_FILE, ..._CLIENT__CERT, ..._CLIENT__KEY)")


def _host_and_cores() -> tuple[str, int]:
    import socket
    return socket.gethostname(), os.cpu_count() or 1


_LOCAL: dict[tuple, tuple] = {}   # (workers, dashboard) -> (LocalCluster, Client): one per process, reused


def _local_client(workers: int, dashboard: str | None = None):
    """The process's local cluster of `workers` single-thread worker processes, started once
    and closed when the process exits; everything on 127.0.0.1. dashboard: HOST:PORT of the
    dashboard (None: none; the scheduler's HTTP server, metrics and health, still answers on
    127.0.0.1 at a free port)."""
    import atexit

    import dask
    from distributed import Client, LocalCluster

    cluster, client = _LOCAL.get((workers, dashboard), (None, None))
    if cluster is not None and cluster.status.name == "running" and client.status == "running":
        return cluster, client
    # a task on a worker that dies is not rescheduled behind the executor's back: its rule
    # runs it again (split into single runs) and counts the attempt
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}):
        # every server on the loopback; the scheduler's HTTP server on a free port, not on
        # 8787, which a second cluster (another study, a dashboard of the user's) may hold
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host=LOOPBACK,
                               dashboard_address=None, worker_dashboard_address=f"{LOOPBACK}:0",
                               scheduler_kwargs={"dashboard_address": dashboard or LOOPBACK_DASHBOARD,
                                                 "dashboard": dashboard is not None},
                               silence_logs=logging.ERROR)
    client = Client(cluster)
    if not _LOCAL:
        atexit.register(_close_local)
    _LOCAL[(workers, dashboard)] = (cluster, client)
    return cluster, client


def _connect(scheduler: str):
    """A client of the cluster at `scheduler`; bad input (one line) where none answers, or where
    a tls:// address finds no TLS settings or is refused by them."""
    from distributed import Client

    from scene_types import BadInput

    try:
        return Client(scheduler, timeout=CONNECT_TIMEOUT)
    except TypeError as exc:   # distributed's way of saying a tls:// address has no TLS settings
        if scheduler.startswith("tls://") and "ssl" in str(exc).lower():
            raise BadInput(f"--scheduler {scheduler}: no TLS settings for the client; expected "
                           f"{TLS_SETTINGS}") from None
        raise
    except (OSError, TimeoutError) as exc:
        tls = (f"; a tls:// scheduler takes {TLS_SETTINGS}, the certificate signed by a CA the scheduler trusts"
               if scheduler.startswith("tls://") else "")
        raise BadInput(f"--scheduler {scheduler}: no Dask scheduler answers there ({exc}); "
                       f"expected the address of a running `dask scheduler`, e.g. tcp://127.0.0.1:8786{tls}") from None


def _close_local() -> None:
    for cluster, client in _LOCAL.values():
        client.close()
        cluster.close()
    _LOCAL.clear()


class DaskCluster(Executor):
    """A Dask client on a local or remote cluster (see the module docstring)."""

    capacity = float("inf")
    timeouts = False

    def __init__(self, scheduler: str | None = None, workers: int | None = None,
                 threads_per_task: int | None = None, dashboard: str | None = None):
        """threads_per_task: threads a task may use (default: cores / workers on its host);
        dashboard: HOST:PORT for the local cluster's dashboard (default: none)."""
        self.scheduler = scheduler
        self.cluster = None
        self.dashboard = None if scheduler else dashboard
        self.retried = 0
        if scheduler:
            self.client = _connect(scheduler)
        else:
            self.cluster, self.client = _local_client(workers or os.cpu_count() or 1, dashboard)
        self.client.run(one_thread_each)
        self.threads_per_task = threads_per_task or self._threads_per_task()

    def _threads_per_task(self) -> int:
        """Cores per worker on the busiest host (at least 1): what a task may use inside."""
        info = self.client.run(_host_and_cores)
        per_host: dict[str, list[int]] = {}
        for host, cores in info.values():
            per_host.setdefault(host, []).append(cores)
        return max(1, min(cores[0] // len(cores) for cores in per_host.values())) if per_host else 1

    @property
    def dashboard_link(self) -> str | None:
        """The local cluster's dashboard (http://127.0.0.1:PORT/status), None when not opened."""
        return self.cluster.dashboard_link if self.cluster is not None and self.dashboard else None

    @property
    def workers(self) -> int:
        return len(self.client.scheduler_info(n_workers=-1)["workers"])

    def close(self) -> None:
        """Disconnect from a remote cluster; the local cluster stays for the process's next
        executor and is closed at exit."""
        if self.cluster is None:
            self.client.close()

    def _start(self, fn, task, name):
        return self.client.submit(fn, *task.args, key=name, pure=False)

    def _wait(self, handles: list, seconds: float) -> None:
        from distributed import wait

        try:
            wait(handles, timeout=seconds, return_when="FIRST_COMPLETED")
        except TimeoutError:
            pass

    def _poll(self, future) -> Finished | Failure | None:
        if not future.done():
            return None
        if future.status == "finished":
            return Finished(future.result())
        try:
            exc = future.exception()
        except Exception as err:  # noqa: BLE001 - the scheduler's own error (a lost worker)
            exc = err
        if type(exc).__name__ == "KilledWorker":
            return Failure("died", DIED)
        return Failure("raised", failure_text(exc))

    def _stop(self, future) -> None:
        future.cancel()
