"""Runs a railbrake.sequence/1 file against the model-in-the-loop plant (the plant closed by the
simulation's own BCU and WSP, the reference BCU's logic): each test on a fresh run of the
sequence's scenario, its steps in order, conditions checked at every recorded sample."""

from __future__ import annotations

import ctypes
import math
import time as wallclock
from dataclasses import dataclass, field

import numpy as np

from railbrake import _core, simulation
from railbrake.simulation.parameters import _condition
from railbrake.errors import InputError
from railbrake.hil.faults import parse_fault
from railbrake.resolve import resolve
from railbrake.results import kpis as kpi_info
from railbrake.units import BAR
from railbrake.sequence.schema import (CHANNEL_DIMENSION, COMPARISONS, Sequence, Threshold, WaitAt, duration,
                                       matching, quantity)


# the KPIs a condition may name: a MIL run's (run --json); a HIL run's also braked_distance_m
KPI_NAMES = tuple(simulation.kpi_dict(_core.Kpis(), 0.0)) + ("braked_distance_m",)


@dataclass
class StepResult:
    index: int                  # 0-based in its test
    action: str
    verdict: str                # pass, fail, error, done
    message: str
    start_s: float              # plant time the step began and ended
    end_s: float
    seconds: float = 0.0        # wall time
    window: tuple | None = None   # expect: (t0, t1, channels, threshold) for the plot
    name: str = ""              # an expectation's name


@dataclass
class TestResult:
    name: str
    steps: list[StepResult] = field(default_factory=list)
    kpis: dict = field(default_factory=dict)      # recorded by kpi steps
    series: dict = field(default_factory=dict)    # channel -> samples of the test's run
    units: dict = field(default_factory=dict)
    seconds: float = 0.0
    atmosphere: float = math.nan                  # Pa, the plant's

    @property
    def verdict(self) -> str:
        verdicts = {s.verdict for s in self.steps}
        return "error" if "error" in verdicts else "fail" if "fail" in verdicts else "pass"


class MilPlant:
    """The plant of a run advanced on demand, its parameters changed between two advances (demand,
    adhesion, faults: read at each step, rb_run_retune for the adhesion)."""

    def __init__(self, resolved):
        self.resolved, self.n_cars = resolved, resolved.cars
        self.plant, self.bcu, self.wsp, self.spec = simulation.structs(resolved)
        self.spec.n_demand = 1   # released until the sequence sets a demand
        self.spec.demand_time[0] = self.spec.demand_service[0] = self.spec.demand_emergency[0] = 0.0
        self.state = ctypes.create_string_buffer(_core.rb_run_state_size())
        _core.call(_core.rb_run_init, ctypes.byref(self.plant), ctypes.byref(self.bcu), ctypes.byref(self.wsp),
                   ctypes.byref(self.spec), self.state)
        self.names = simulation.channels(self.n_cars)
        self.units = dict(self.names)
        self.interval = self.spec.record_interval
        rows = int(math.ceil(self.spec.max_time / self.interval)) + 3
        self.series = np.zeros((rows, len(self.names)))
        self.rows, self.t, self.finished = 1, 0.0, False
        self.max_time = self.spec.max_time
        self.atmosphere = self.plant.atmosphere

    def advance(self, t_until: float) -> None:
        if self.finished or t_until <= self.t:
            return
        done = ctypes.c_int(0)
        _core.call(_core.rb_run_advance, ctypes.byref(self.plant), ctypes.byref(self.bcu), ctypes.byref(self.spec),
                   self.state, t_until, _core.ptr(self.series), len(self.series), ctypes.byref(done))
        self.t, self.finished = min(t_until, self.spec.max_time), bool(done.value)
        times = self.series[1:, 0]
        self.rows = 1 + int(np.count_nonzero(times))

    def column(self, name: str) -> np.ndarray:
        return self.series[:self.rows, [n for n, _ in self.names].index(name)]

    def signal(self, names: list[str], rows: slice = slice(None)) -> np.ndarray:
        """One channel's samples, or the largest absolute value of several at each sample."""
        if len(names) == 1:
            return self.column(names[0])[rows]
        return np.abs(np.array([self.column(n)[rows] for n in names])).max(axis=0)

    def set_demand(self, emergency: bool, service: float, where: str) -> str:
        s, n = self.spec, self.spec.n_demand
        if n >= _core.MAX_DEMAND_STEPS:
            raise InputError(f"{where}: more than {_core.MAX_DEMAND_STEPS} demand changes in one test")
        if s.demand_time[n - 1] >= self.t:   # a change at the same time replaces the last
            n -= 1
        s.demand_time[n], s.demand_service[n], s.demand_emergency[n] = self.t, service, float(emergency)
        s.n_demand = n + 1
        return "emergency" if emergency else f"service {service:g}" if service else "released"

    def set_adhesion(self, condition: str, where: str) -> str:
        try:
            spec = self.resolved.scenario.spec   # cell by cell only where this run has rail cells
            cells = spec.adhesion.rail_conditioning == "cells" and self.plant.rail_cell_length > 0.0
            self.plant.condition[0] = _condition(condition, spec.initial_speed, cells)
        except InputError as exc:
            raise InputError(f"{where} = {condition!r}: {exc}") from None
        _core.call(_core.rb_run_retune, ctypes.byref(self.plant), ctypes.byref(self.wsp), self.state)
        return f"adhesion {condition} outside the track's zones"

    def change_fault(self, action: str, fault: dict, where: str) -> str:
        _, f = parse_fault(fault, action, self.n_cars, where)
        p = self.plant
        same = [i for i in range(p.n_faults) if (p.fault[i].kind, p.fault[i].car, p.fault[i].axle) == (f.kind, f.car, f.axle)]
        name = f"{_core.FAULT_KINDS[f.kind]} on car {f.car + 1}" + ("" if f.axle < 0 else f", axle {f.axle + 1}")
        if action == "inject":
            if same or p.n_faults >= _core.MAX_FAULTS:
                raise InputError(f"{where}: {name}: " + ("already active" if same else
                                                          f"the plant holds at most {_core.MAX_FAULTS} faults"))
            f.start_time = self.t
            p.fault[p.n_faults] = f
            p.n_faults += 1
            return f"{name}: injected"
        if not same:
            raise InputError(f"{where}: {name}: not present, nothing cleared")
        kept = [p.fault[i] for i in range(p.n_faults) if i not in same]
        for i, kept_fault in enumerate(kept):
            p.fault[i] = kept_fault
        p.n_faults = len(kept)
        return f"{name}: cleared"

    def kpis(self) -> dict:
        k = _core.Kpis()
        _core.rb_run_kpis(ctypes.byref(self.plant), self.state, ctypes.byref(k))
        return simulation.kpi_dict(k, self.atmosphere)


class _Check:
    """A condition made ready against a plant: its values at the recorded samples, its threshold."""

    def __init__(self, cond: Condition, plant: MilPlant, where: str):
        given = [c for c in COMPARISONS if getattr(cond, c) is not None]
        if (cond.signal is None) == (cond.kpi is None) or len(given) != 1:
            raise InputError(f"{where}: give one of signal or kpi and one of {', '.join(COMPARISONS)}")
        self.plant, self.kpi = plant, cond.kpi
        if cond.kpi is not None:
            if cond.kpi not in KPI_NAMES:
                raise InputError(f"{where}.kpi = {cond.kpi!r}: not a KPI ({', '.join(KPI_NAMES)})")
            self.channels, dimension, offset = [], CHANNEL_DIMENSION.get(kpi_info.unit(cond.kpi)), 0.0
            self.label = cond.kpi
        else:
            self.channels = matching(cond.signal, plant.units, f"{where}.signal")
            dimension = CHANNEL_DIMENSION.get(plant.units[self.channels[0]])
            offset = plant.atmosphere if dimension == "pressure" else 0.0
            self.label = cond.signal
        written = getattr(cond, given[0])
        self.threshold = Threshold(given[0], quantity(written, dimension, f"{where}.{given[0]}") + offset,
                                   str(written))

    def values(self, first_row: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """(times, values) of the recorded samples from first_row on; a KPI: its value now."""
        if self.kpi is not None:
            value = self.plant.kpis()[self.kpi]
            return np.array([self.plant.t]), np.array([math.nan if value is None else float(value)])
        rows = slice(first_row, self.plant.rows)
        return self.plant.column("time")[rows], self.plant.signal(self.channels, rows)

    def describe(self, t: float, x: float) -> str:
        unit = self.plant.units[self.channels[0]] if self.channels else ""
        if math.isnan(x):
            shown = "no value yet (e.g. no stop)"
        elif CHANNEL_DIMENSION.get(unit) == "pressure":
            shown = f"{(x - self.plant.atmosphere) / BAR:.4g} bar"
        else:
            shown = f"{x:.4g}" + (f" {unit}" if unit not in ("", "1") else "")
        return f"{self.label} = {shown} at t = {t:.3f} s"


def run_test(sequence: Sequence, index: int, resolved, progress=None, plant=None) -> TestResult:
    """Test `index` on `plant` (default: a fresh MIL plant of the resolved scenario)."""
    test = sequence.spec.tests[index]
    plant = MilPlant(resolved) if plant is None else plant
    result = TestResult(test.name)
    started = wallclock.monotonic()
    for j, step in enumerate(test.steps):
        where = sequence.where("tests", index, "steps", j, step.action)
        t0, w0 = plant.t, wallclock.monotonic()
        try:
            verdict, message, window = _execute(step, plant, where, result)
        except InputError as exc:
            verdict, message, window = "error", str(exc), None
        name = step.expect.name or "" if step.expect is not None else ""
        result.steps.append(StepResult(j, step.action, verdict, message, t0, plant.t,
                                       wallclock.monotonic() - w0, window, name))
        if progress is not None:
            progress(test.name, result.steps[-1])
        if verdict == "error":
            break
    result.seconds = wallclock.monotonic() - started
    result.series = {n: plant.column(n).copy() for n, _ in plant.names}
    result.units, result.atmosphere = plant.units, plant.atmosphere
    return result


def _execute(step, plant: MilPlant, where: str, result: TestResult):
    action = step.action
    if action == "set_demand":
        return "done", plant.set_demand(step.set_demand.emergency, step.set_demand.service, where), None
    if action == "set_adhesion":
        return "done", plant.set_adhesion(step.set_adhesion, where), None
    if action in ("inject", "clear"):
        return "done", plant.change_fault(action, getattr(step, action), where), None
    if action == "wait":
        return _wait(step.wait, plant, where)
    if action == "expect":
        return _expect(step.expect, plant, where)
    return _record_kpi(step.kpi, plant, where, result)


def _wait(wait, plant: MilPlant, where: str):
    if isinstance(wait, str):
        seconds = duration(wait, where)
        plant.advance(plant.t + seconds)
        return "done", f"waited to t = {plant.t:.3f} s", None
    if isinstance(wait, WaitAt):
        at = duration(wait.at, f"{where}.at", high=plant.max_time)
        if at < plant.t - 1e-9:
            raise InputError(f"{where}.at = {wait.at!r}: the test is at t = {plant.t:.3f} s already")
        plant.advance(at)
        return "done", f"waited to t = {plant.t:.3f} s", None
    check = _Check(wait.until, plant, f"{where}.until")
    timeout = duration(wait.timeout, f"{where}.timeout")
    hit = _first(check, plant, plant.t, plant.t + timeout, want=True)
    if hit is None:   # a failure of the unit under test, not of the sequence: the test goes on
        return "fail", (f"{where}: {check.label} {check.threshold.comparison.replace('_', ' ')} "
                         f"{check.threshold.written} not reached within {wait.timeout} (to t = {plant.t:.3f} s"
                         f"{', the run ended' if plant.finished else ''})"), None
    return "done", f"{check.describe(*hit)}: {check.threshold.comparison.replace('_', ' ')} {check.threshold.written}", None


def _first(check: _Check, plant: MilPlant, t0: float, t1: float, want: bool):
    """Advances sample by sample up to t1 until the condition is `want` at a sample after t0;
    (t, value) of that sample, or None. Each sample is looked at once."""
    row = 0
    while True:
        times, values = check.values(row)
        if check.kpi is None:
            row = plant.rows
            inside = (times > t0 + 1e-9) & (times <= t1 + 1e-9)
            times, values = times[inside], values[inside]
        found = np.flatnonzero(check.threshold.holds(values) == want)
        if found.size:
            return float(times[found[0]]), float(values[found[0]])
        if plant.t >= t1 - 1e-9 or plant.finished:
            return None
        plant.advance(min(plant.t + plant.interval, t1))


def _expect(expect, plant: MilPlant, where: str):
    verdict, message, window = _judge(expect, plant, where)
    return verdict, (f"{expect.name}: {message}" if expect.name else message), window


def _judge(expect, plant: MilPlant, where: str):
    check = _Check(expect, plant, where)
    if expect.within is not None and expect.during is not None:
        raise InputError(f"{where}: give within or during, not both")
    t0 = plant.t
    rule = f"{check.label} {check.threshold.comparison.replace('_', ' ')} {check.threshold.written}"
    if expect.during is not None:
        t1 = t0 + duration(expect.during, f"{where}.during")
        plant.advance(t1)
        bad = _first(check, plant, t0, t1, want=False)
        window = (t0, t1, check.channels, check.threshold)
        if bad is not None:
            return "fail", f"{rule} during {expect.during} from t = {t0:.3f} s: {check.describe(*bad)}", window
        if plant.t < t1 - 1e-9:
            return "fail", f"{rule} during {expect.during} from t = {t0:.3f} s: the run ended at t = {plant.t:.3f} s", window
        return "pass", f"{rule} held from t = {t0:.3f} to {t1:.3f} s", window
    t1 = t0 + (duration(expect.within, f"{where}.within") if expect.within is not None else 0.0)
    if expect.within is None or check.kpi is not None:
        plant.advance(t1)
        times, values = check.values()
        ok = bool(check.threshold.holds(values[-1]))
        text = f"{rule}: {check.describe(times[-1], values[-1])}"
        return ("pass" if ok else "fail"), text, (t0, t1, check.channels, check.threshold)
    hit = _first(check, plant, t0, t1, want=True)
    window = (t0, t1 if hit is None else hit[0], check.channels, check.threshold)
    if hit is None:
        times, values = check.values()
        last = check.describe(times[-1], values[-1])
        return "fail", f"{rule} within {expect.within} from t = {t0:.3f} s: not reached ({last})", window
    return "pass", f"{rule} within {expect.within}: {check.describe(*hit)}", window


def _record_kpi(step, plant: MilPlant, where: str, result: TestResult):
    if step.kpi is not None:
        value = plant.kpis().get(step.kpi)
    elif step.signal is not None:
        values = plant.signal(matching(step.signal, plant.units, f"{where}.signal"))
        value = float({"max": values.max, "min": values.min, "final": lambda: values[-1]}[step.stat]())
    else:
        raise InputError(f"{where}: give signal or kpi")
    result.kpis[step.name] = value
    return "done", f"{step.name} = {value}", None


def check(sequence: Sequence, resolved) -> None:
    """Every step checked against the plant before anything runs: signals, KPIs, thresholds and
    their units, times, faults, adhesion conditions (InputError: file, line, key)."""
    plant = MilPlant(resolved)
    for i, test in enumerate(sequence.spec.tests):
        for j, step in enumerate(test.steps):
            where = sequence.where("tests", i, "steps", j, step.action)
            action, value = step.action, getattr(step, step.action)
            if action == "expect":
                _Check(value, plant, where)
                if value.within is not None and value.during is not None:
                    raise InputError(f"{where}: give within or during, not both")
                for key in ("within", "during"):
                    if getattr(value, key) is not None:
                        duration(getattr(value, key), f"{where}.{key}")
            elif action == "wait" and isinstance(value, str):
                duration(value, where)
            elif action == "wait" and isinstance(value, WaitAt):
                duration(value.at, f"{where}.at", high=plant.max_time)
            elif action == "wait":
                _Check(value.until, plant, f"{where}.until")
                duration(value.timeout, f"{where}.timeout")
            elif action in ("inject", "clear"):
                parse_fault(value, action, plant.n_cars, where)
            elif action == "set_adhesion":
                plant.set_adhesion(value, where)
            elif action == "kpi" and (value.signal is None) == (value.kpi is None):
                raise InputError(f"{where}: give signal or kpi")
            elif action == "kpi" and value.signal is not None:
                matching(value.signal, plant.units, f"{where}.signal")
            elif action == "kpi" and value.kpi not in KPI_NAMES:
                raise InputError(f"{where}.kpi = {value.kpi!r}: not a KPI ({', '.join(KPI_NAMES)})")


def run(sequence: Sequence, sets=(), progress=None, bcu: tuple[str, int] | None = None, key=None) -> list[TestResult]:
    """Every test of the sequence, each on a fresh run of its scenario (with `sets` overrides, e.g.
    ['wsp.enabled=false']), once every step has been checked: the MIL plant, or with `bcu` (host,
    port) and `key` the paced HIL loop against that BCU."""
    resolved = resolve(sequence.spec.scenario, sequence.spec.cars, sets)
    check(sequence, resolved)
    results = []
    for i in range(len(sequence.spec.tests)):
        if bcu is None:
            results.append(run_test(sequence, i, resolved, progress))
            continue
        from railbrake.sequence.hil_plant import HilPlant
        plant = HilPlant(resolved, bcu, key)
        try:
            results.append(run_test(sequence, i, resolved, progress, plant))
        finally:
            plant.close()
    return results
