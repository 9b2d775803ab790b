import contextlib
import socket
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def pytest_report_header(config):
    from railbrake import _core
    return f"railbrake C core: {_core.lib._name}"


def pytest_collection_modifyitems(config, items):
    """The files that hold a slow test first, the others after, each in collection order. With
    `-n N --dist loadfile --no-loadscope-reorder` (make test) xdist hands files out in this order,
    so a long file (the paced HIL stop, the documentation's command blocks) starts at the beginning
    and the short ones fill the workers around it, instead of a long one starting last and running
    alone at the end (xdist's default order is by number of tests, which puts them last)."""
    slow_files = {item.path for item in items if item.get_closest_marker("slow")}
    items.sort(key=lambda item: item.path not in slow_files)   # stable: collection order within each


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextlib.contextmanager
def _dask_cli_cluster(workers: int):
    """`dask scheduler` and a `dask worker` of `workers` single-threaded processes, started as a
    user starts them and stopped on leaving; yields the scheduler's address."""
    bin_ = Path(sys.executable).parent
    address = f"tcp://127.0.0.1:{_free_port()}"
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    processes = [subprocess.Popen([str(bin_ / "dask"), "scheduler", "--host", "127.0.0.1",
                                   "--port", address.rsplit(":", 1)[1], "--no-dashboard"], **quiet)]
    try:
        processes.append(subprocess.Popen([str(bin_ / "dask"), "worker", address, "--nthreads", "1",
                                           "--nworkers", str(workers), "--no-dashboard"], **quiet))
        yield address
    finally:
        for p in reversed(processes):
            p.terminate()
        for p in reversed(processes):
            p.wait(timeout=30)   # a process that does not stop fails the fixture's teardown


@pytest.fixture(scope="session")
def dask_cli():
    """A function of the number of worker processes giving a context manager that runs an external
    Dask cluster (_dask_cli_cluster) and yields its scheduler's address."""
    return _dask_cli_cluster
