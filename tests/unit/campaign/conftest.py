"""Dask clusters shared by the campaign tests. Starting worker processes (and resolving runs) is
what costs here, so each cluster starts once: a LocalCluster of two single-threaded workers for
the whole session, and a `dask scheduler` with one `dask worker`, started as separate processes
the way a user starts a cluster, for the module that runs a study against it."""

import logging
import warnings

import pytest


@pytest.fixture(scope="session")
def two_workers():
    """The address of a running local cluster of two single-threaded worker processes."""
    from dask.distributed import LocalCluster
    warnings.filterwarnings("ignore", message="Port .* is already in use")   # HTTP routes move ports
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.ERROR) as cluster:
        yield cluster.scheduler_address


@pytest.fixture(scope="module")
def dask_cli_cluster(dask_cli):
    """`dask scheduler` and one single-threaded `dask worker`, started here as processes and
    stopped at the end of the module; yields the scheduler's address."""
    with dask_cli(1) as address:
        yield address
