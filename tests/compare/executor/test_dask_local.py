"""The local Dask cluster of `study`: it starts beside whatever holds Dask's usual port."""
import socket
import warnings

import pytest

pytest.importorskip("distributed")

from compare.executor.dask import _close_local, _local_client  # noqa: E402

DASK_HTTP_PORT = 8787   # Dask's default for the scheduler's HTTP server


def test_a_local_cluster_starts_without_a_warning_while_another_holds_port_8787():
    """A second cluster (another study, or a test's) used to take 8787 and warn 'Port 8787 is
    already in use' onto the user's terminal."""
    holder = socket.socket()
    try:
        holder.bind(("", DASK_HTTP_PORT))
    except OSError:
        pass   # held already: the situation this test is about
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            cluster, client = _local_client(1)
            assert client.submit(sum, [1, 2]).result() == 3
    finally:
        _close_local()
        holder.close()


def _listening(pid: int) -> set[str]:
    """The addresses a process and its children listen on (IPs only)."""
    import psutil

    me = psutil.Process(pid)
    found = set()
    for proc in [me, *me.children(recursive=True)]:
        try:
            found |= {c.laddr.ip for c in proc.net_connections(kind="inet") if c.status == psutil.CONN_LISTEN}
        except psutil.Error:
            pass
    return found


@pytest.mark.parametrize("dashboard", [None, "127.0.0.1:0"])
def test_the_local_cluster_listens_on_the_loopback_only(dashboard):
    """It used to open the scheduler's HTTP server (the dashboard) on 0.0.0.0, reachable from
    the network, for every study."""
    import os
    from urllib.parse import urlparse

    from compare.executor.dask import DaskCluster

    _close_local()   # a cluster of this size another test left must not answer for this one
    try:
        engine = DaskCluster(workers=1, **({} if dashboard is None else {"dashboard": dashboard}))
        cluster = engine.cluster
        assert urlparse(cluster.scheduler_address).hostname == "127.0.0.1", cluster.scheduler_address
        http = {s.getsockname()[0] for s in cluster.scheduler.http_server._sockets.values()}
        assert http == {"127.0.0.1"}, f"the scheduler's HTTP server listens on {http}"
        listening = _listening(os.getpid())
        assert listening and listening <= {"127.0.0.1"}, f"the cluster listens on {listening}"
        if dashboard is None:
            assert engine.dashboard_link is None
        else:
            assert urlparse(engine.dashboard_link).hostname == "127.0.0.1", engine.dashboard_link
    finally:
        _close_local()
