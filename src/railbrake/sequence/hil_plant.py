"""A sequence against the paced HIL loop: the loop runs in a thread of its own (hil.run), the
sequence follows its recorded rows and changes faults through the loop's mailbox (FaultSwitch).
The demand is the external BCU's (the ICD carries none from the plant): a set_demand step is
accepted only where it is what the scenario the BCU runs demands then; the adhesion cannot change."""

from __future__ import annotations

import threading

import numpy as np

from railbrake import hil
from railbrake.errors import InputError
from railbrake.simulation import plant_params

CHUNK_STEPS = 20   # the sequence sees the loop's rows every 20 ms of plant time


class HilPlant:
    def __init__(self, resolved, bcu: tuple[str, int], key):
        self.resolved, self.n_cars = resolved, resolved.cars
        sc = resolved.scenario
        self.names = hil.channels(self.n_cars)
        self.units = dict(self.names)
        self.interval = sc.spec.outputs.record_interval
        self.atmosphere = plant_params(sc, self.n_cars, train=resolved.train).atmosphere
        self.max_time = sc.spec.stop.max_time
        self._chunks, self._rows = [], np.zeros((0, len(self.names)))
        self._changed = threading.Condition()
        self._stop = threading.Event()
        self.switch, self.result, self.error = None, None, None
        self.t, self.rows, self.finished = 0.0, 0, False
        self._thread = threading.Thread(target=self._run, args=(bcu, key), name="railbrake-sequence-hil", daemon=True)
        self._thread.start()
        with self._changed:
            self._changed.wait_for(lambda: self.switch is not None or self.finished, timeout=30)
        if self.error is not None:
            raise self.error

    def _run(self, bcu, key):
        try:
            self.result = hil.run(self.resolved, bcu, key=key, priority=0, on_rows=self._take,
                                  on_faults=self._started, stop=self._stop.is_set, chunk_steps=CHUNK_STEPS)
        except Exception as exc:   # noqa: BLE001 - handed to the sequence's thread
            self.error = exc if isinstance(exc, InputError) else InputError(f"HIL run: {exc}")
        with self._changed:
            self.finished = True
            self._changed.notify_all()

    def _started(self, switch):
        with self._changed:
            self.switch = switch
            self._changed.notify_all()

    def _take(self, rows):
        with self._changed:
            self._chunks.append(rows)
            self._changed.notify_all()

    def _collect(self) -> None:
        if self._chunks:
            self._rows = np.concatenate([self._rows, *self._chunks])
            self._chunks.clear()
        self.rows = len(self._rows)
        if self.rows:
            self.t = float(self._rows[-1, 0])

    def advance(self, t_until: float) -> None:
        with self._changed:
            self._changed.wait_for(lambda: self.finished or (self._chunks and self._chunks[-1][-1, 0] >= t_until - 1e-9)
                                   or (self._rows.size and self._rows[-1, 0] >= t_until - 1e-9))
            self._collect()
        if self.error is not None:
            raise self.error

    def column(self, name: str) -> np.ndarray:
        return self._rows[:, [n for n, _ in self.names].index(name)]

    def signal(self, names: list[str], rows: slice = slice(None)) -> np.ndarray:
        if len(names) == 1:
            return self.column(names[0])[rows]
        return np.abs(np.array([self.column(n)[rows] for n in names])).max(axis=0)

    def set_demand(self, emergency: bool, service: float, where: str) -> str:
        steps = [d for d in self.resolved.scenario.spec.demand if d.time <= self.t + 1e-9]
        now = steps[-1] if steps else None
        if now is None or (bool(now.emergency), float(now.service)) != (bool(emergency), float(service)):
            raise InputError(f"{where}: in HIL the demand is the BCU's (the ICD carries none from the plant): "
                             f"the scenario {self.resolved.scenario.name} the BCU runs demands "
                             f"{'nothing' if now is None else 'emergency' if now.emergency else f'service {now.service:g}'}"
                             f" at t = {self.t:.3f} s")
        return "emergency (the BCU's scenario demand)" if emergency else f"service {service:g} (the BCU's)"

    def set_adhesion(self, condition: str, where: str) -> str:
        raise InputError(f"{where} = {condition!r}: the adhesion cannot change during a HIL run yet")

    def change_fault(self, action: str, fault: dict, where: str) -> str:
        if self.finished:
            raise InputError(f"{where}: the HIL run has ended")
        change = self.switch.change(action, fault, origin="sequence")
        self.advance(change.time_s)
        return f"{change.text} at t = {change.time_s:.3f} s"

    def kpis(self) -> dict:
        if self.result is None:
            raise InputError("KPIs of a HIL run are known once it has ended: wait for the stop first")
        return self.result.kpis

    def close(self) -> None:
        self._stop.set()
        self._thread.join()
