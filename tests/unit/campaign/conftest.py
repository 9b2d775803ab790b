"""Dask clusters shared by the campaign tests. Starting worker processes (and resolving runs) is
what costs here, so each cluster starts once: a LocalCluster of two single-threaded workers for
the whole session, and a `dask scheduler` with one `dask worker`, started as separate processes
the way a user starts a cluster, for the module that runs a study against it."""

import logging
import socket
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

BIN = Path(sys.executable).parent


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="session")
def two_workers():
    """The address of a running local cluster of two single-threaded worker processes."""
    from dask.distributed import LocalCluster
    warnings.filterwarnings("ignore", message="Port .* is already in use")   # HTTP routes move ports
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.ERROR) as cluster:
        yield cluster.scheduler_address


@pytest.fixture(scope="module")
def dask_cli_cluster():
    """`dask scheduler` and one single-threaded `dask worker`, started here as processes and
    stopped at the end of the module; yields the scheduler's address."""
    address = f"tcp://127.0.0.1:{free_port()}"
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    processes = [subprocess.Popen([str(BIN / "dask"), "scheduler", "--host", "127.0.0.1",
                                   "--port", address.rsplit(":", 1)[1], "--no-dashboard"], **quiet)]
    try:
        processes.append(subprocess.Popen([str(BIN / "dask"), "worker", address, "--nthreads", "1",
                                           "--nworkers", "1", "--no-dashboard"], **quiet))
        yield address
    finally:
        for p in reversed(processes):
            p.terminate()
        for p in reversed(processes):
            p.wait(timeout=30)   # a process that does not stop fails the module's teardown
