"""A Dask worker lost while the local cluster starts (its process dies in a worker preload,
die_once.py) is replaced: the cluster is started again with a warning, and has its workers."""

from pathlib import Path

import dask
import distributed  # noqa: F401 - its configuration defaults, which dask.config.set below extends
import pytest

from railbrake.campaign import execute


@pytest.mark.slow
def test_a_worker_lost_at_start_up_is_replaced(tmp_path, monkeypatch):
    marker = tmp_path / "died"
    monkeypatch.setenv("RAILBRAKE_TEST_DIE_ONCE", str(marker))
    with dask.config.set({"distributed.worker.preload": [str(Path(__file__).with_name("die_once.py"))]}):
        with pytest.warns(RuntimeWarning, match="lost while the local cluster started"):
            client, cluster = execute.connect(None, 2)
    try:
        assert marker.is_file()   # a worker did die
        assert len(client.scheduler_info()["workers"]) == 2
        assert client.submit(sum, [1, 2]).result(timeout=60) == 3
    finally:
        client.close()
        cluster.close()
