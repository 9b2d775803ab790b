"""Dask clusters shared by the campaign tests: starting worker processes is the slow part."""

import logging
import warnings

import pytest


def _cluster(workers: int):
    from dask.distributed import LocalCluster
    warnings.filterwarnings("ignore", message="Port .* is already in use")   # HTTP routes move ports
    return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                        silence_logs=logging.ERROR)


@pytest.fixture(scope="session")
def one_worker():
    """The address of a running local cluster of one single-threaded worker process."""
    with _cluster(1) as cluster:
        yield cluster.scheduler_address


@pytest.fixture(scope="session")
def two_workers():
    with _cluster(2) as cluster:
        yield cluster.scheduler_address
