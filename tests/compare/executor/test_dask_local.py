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
