"""Faults injected and cleared while the HIL plant runs (docs/hil.md, faults at run time).

A change is checked here in the scenario file's terms (the fault kinds, 1-based car and axle, the
noise, leak area or pressure with their units), posted into the running C loop (rb_hil_runner_post_fault: a
mailbox the loop reads once a step, never waiting) and answered by the loop with the plant step it
took effect at, or why it was refused. Every change applied is kept with its time for the run's
report and the recording's events."""

from __future__ import annotations

import ctypes
import threading
import time
from dataclasses import asdict, dataclass

from railbrake import _core, config
from railbrake.errors import InputError
from railbrake.scenario import FaultSpec, fault_problem, fault_value

ACTIONS = {"inject": _core.HIL_FAULT_INJECT, "clear": _core.HIL_FAULT_CLEAR}
ANSWER_TIMEOUT = 10.0   # s of wall time for the loop to answer (it looks every 1 ms step; between two
                        # chunks of steps Python writes the recording)
ANSWER_POLL = 2e-4      # s between looks at the answer


@dataclass(frozen=True)
class FaultChange:
    """A fault change the loop applied: at plant time `time_s` (step `step`), from `origin`."""
    time_s: float
    step: int
    action: str          # inject, clear
    fault: dict          # type, car, axle (1-based; None: every axle / the train), noise, leak_area, pressure (SI)
    text: str            # the loop's words, e.g. "vent_stuck_open on car 3, axle 2: injected"
    origin: str          # control, sequence, dashboard, api

    def as_dict(self) -> dict:
        return asdict(self)


def parse_fault(data, action: str, n_cars: int, where: str) -> tuple[FaultSpec, _core.Fault]:
    """A fault given as a mapping (type, car, axle, noise, leak_area, pressure as in a scenario
    file's faults) -> its spec and C struct. InputError names `where`, the key, the value and what is allowed."""
    if action not in ACTIONS:
        raise InputError(f"{where}: action = {action!r}: must be one of {', '.join(ACTIONS)}")
    if not isinstance(data, dict):
        raise InputError(f"{where}: fault = {data!r}: expected a mapping with type, car, axle")
    if "start" in data:
        raise InputError(f"{where}: fault.start: a fault changed while the plant runs acts at once: remove start")
    spec = config.validate_data(data, FaultSpec, lambda loc: f"{where}: fault.{'.'.join(map(str, loc))}")
    problem = fault_problem(spec, needs_value=action == "inject")
    if problem is not None:
        raise InputError(f"{where}: fault.{problem[0]}{problem[1]}")
    if spec.car is not None and spec.car > n_cars:
        raise InputError(f"{where}: fault.car = {spec.car}: the train has cars 1..{n_cars}")
    value = fault_value(spec) if action == "inject" else 0.0
    fault = _core.Fault(_core.FAULT_KINDS.index(spec.type), 0 if spec.car is None else spec.car - 1,
                        -1 if spec.axle is None else spec.axle - 1, 0.0, value)
    return spec, fault


class FaultSwitch:
    """Changes the faults of a running HIL loop (its C runner state); one change at a time, from
    any thread. Keeps the changes applied (`changes`)."""

    def __init__(self, state, n_cars: int, dt: float):
        self._state, self.n_cars, self._dt = state, n_cars, dt
        self._lock = threading.Lock()       # one change at a time
        self._ended = threading.Event()
        self.changes: list[FaultChange] = []

    def end(self) -> None:
        """The loop has ended (no step runs any more): later changes are refused."""
        self._ended.set()

    def change(self, action: str, fault: dict, origin: str = "api") -> FaultChange:
        """Inject or clear `fault` now; returns the change as the loop applied it. InputError (and
        nothing changed) for a fault that does not fit the train, a refusal by the loop (a fault
        already active, one not present, the table full) or a run that has ended."""
        where = f"{origin} {action}"
        spec, fault_struct = parse_fault(fault, action, self.n_cars, where)
        command = _core.HilFaultCommand(ACTIONS[action], fault_struct)
        with self._lock:
            if self._ended.is_set():
                raise InputError(f"{where}: the run has ended: no fault can change any more")
            status, step, text = self._post(command, where)
            if status != 0:
                raise InputError(f"{where}: refused by the plant: {text}")
            fields = spec.model_dump(exclude={"start"})
            change = FaultChange(step * self._dt, step, action, fields, text, origin)
            self.changes.append(change)
            return change

    def _post(self, command, where: str) -> tuple[int, int, str]:
        if not _core.rb_hil_runner_post_fault(self._state, ctypes.byref(command)):
            raise InputError(f"{where}: the plant's mailbox is busy (an earlier change unanswered): try again")
        step, text = ctypes.c_uint64(0), ctypes.create_string_buffer(_core.ERROR_MESSAGE_SIZE)
        deadline = time.monotonic() + ANSWER_TIMEOUT
        while (status := _core.rb_hil_runner_fault_answer(self._state, ctypes.byref(step), text, len(text))) < 0:
            if self._ended.is_set() or time.monotonic() > deadline:
                # the loop ended (or stalls): its answer may have come meanwhile
                status = _core.rb_hil_runner_fault_answer(self._state, ctypes.byref(step), text, len(text))
                if status >= 0:
                    break
                raise InputError(f"{where}: the run has ended before the plant took the change: nothing changed"
                                 if self._ended.is_set() else
                                 f"{where}: the plant loop did not answer within {ANSWER_TIMEOUT:g} s (it stalls): "
                                 "the change may still apply")
            time.sleep(ANSWER_POLL)
        return status, step.value, text.value.decode("utf-8", "replace")
