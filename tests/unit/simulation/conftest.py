"""Comparisons of the real-time plant with the detailed model, shared by the tests of this folder:
each run once per test session, also across pytest-xdist workers (test_compare.py and
test_detailed.py use the same four; the first worker to ask computes one under a file lock, the
others load it)."""

import fcntl
import pickle

import pytest

from railbrake.simulation.compare import compare


@pytest.fixture(scope="session")
def compared(tmp_path_factory, worker_id):
    # the session's base folder is per worker under xdist; its parent is common to all of them
    base = tmp_path_factory.getbasetemp()
    shared = base if worker_id == "master" else base.parent
    cache = {}

    def comparison(scenario: str, cars: int):
        key = (scenario, cars)
        if key not in cache:
            path = shared / f"compare-{scenario}-{cars}.pickle"
            with open(shared / f"compare-{scenario}-{cars}.lock", "w") as lock:
                fcntl.flock(lock, fcntl.LOCK_EX)
                if path.exists():
                    cache[key] = pickle.loads(path.read_bytes())
                else:
                    cache[key] = compare(scenario, cars, steps_ms=())
                    path.write_bytes(pickle.dumps(cache[key]))
        return cache[key]

    return comparison
