"""What the OS grants for real time is reported, and refusals come with a clear note."""

import pytest

from railbrake.errors import InputError
from railbrake.hil import RealTime, request_real_time


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
