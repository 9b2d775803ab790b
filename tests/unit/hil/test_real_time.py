"""What the OS grants for real time is reported, and refusals come with a clear note."""

import os
import threading

import pytest

from railbrake.errors import InputError
from railbrake.hil import RealTime, request_real_time
from conftest import SECRET


def test_refusals_are_explained():
    notes = RealTime(True, memory_locked=False, fifo_priority=False, priority=80).notes()
    assert any("SCHED_FIFO priority 80 refused" in n and "CAP_SYS_NICE" in n for n in notes)
    assert any("mlockall refused" in n and "CAP_IPC_LOCK" in n for n in notes)
    assert RealTime(True, memory_locked=True, fifo_priority=True, priority=80).notes() == []


def test_priority_zero_asks_nothing_and_out_of_range_is_an_error():
    assert request_real_time(0) == RealTime(False)
    assert "not requested" in RealTime(False).notes()[0]
    with pytest.raises(InputError, match="priority = 100: must lie in \\[0, 99\\]"):
        request_real_time(100)


def _a_short_run(**options):
    from railbrake import hil
    return hil.run("emergency-300-heavy-rain", ("127.0.0.1", 9), cars=1, duration=0.05, paced=False,
                   priority=0, key=SECRET, **options)


@pytest.mark.skipif(len(os.sched_getaffinity(0)) < 2, reason="needs two CPUs")
def test_the_loop_has_its_cpu_to_itself_and_the_masks_come_back():
    """--cpu: during the run the loop's thread runs only on its CPU, another thread of the process
    (a dashboard server's) never on it; both masks as they were afterwards."""
    cpus = sorted(os.sched_getaffinity(0))
    loop_cpu = cpus[-1]
    seen, stop = {}, threading.Event()
    other = threading.Thread(target=lambda: (seen.setdefault("tid", threading.get_native_id()), stop.wait(30)))
    other.start()
    try:
        before = (os.sched_getaffinity(0), os.sched_getaffinity(seen["tid"]))

        def look(rows):
            seen["loop"] = os.sched_getaffinity(0)
            seen["other"] = os.sched_getaffinity(seen["tid"])

        _a_short_run(cpu=loop_cpu, on_rows=look)
        assert seen["loop"] == {loop_cpu}
        assert loop_cpu not in seen["other"] and seen["other"]
        assert (os.sched_getaffinity(0), os.sched_getaffinity(seen["tid"])) == before
    finally:
        stop.set()
        other.join()


def test_a_cpu_the_process_cannot_use_is_refused():
    with pytest.raises(InputError, match="cpu = 4096: must be one of this process's CPUs"):
        _a_short_run(cpu=4096)
