"""Whole-train brake simulation with wheel-slide protection (model in the loop).

Python sets the parameters up (ctypes structs, railbrake.simulation.parameters) and calls the C core,
which runs the BCU and the plant at a fixed 1 ms step into a preallocated array (core/src/plant*.c,
bcu*.c, run.c). The run goes in chunks of simulated time so a caller can show progress. Model:
docs/simulation.md.
"""

from __future__ import annotations

import ctypes
import math
from typing import Callable

import numpy as np

from railbrake import _core
from railbrake._args import flag, function, instance
from railbrake.errors import InputError
from railbrake.resolve import resolve
from railbrake.results.scripting import Result
from railbrake.simulation import changes as run_changes
from railbrake.simulation.parameters import DT, channels, kpi_dict, outside_validity_kpi, structs
from railbrake.vehicle import Train

CHUNK = 2.0                         # s of simulated time per C call with a progress callback
QUIET_CHUNK = 60.0                  # without: fewer calls (each costs some us), Ctrl-C still heard soon

WspCallback = Callable[[_core.WspInputs, _core.WspCommands], None]


def run_batch(configurations: list, kernel: str | None = None) -> list:
    """The KPIs of many runs, made in one call of the C core without recording (a study's batch):
    configurations are resolved (railbrake.resolve.Resolved) or anything `run` takes; per run its
    KPI dict as `run` gives it, or the InputError that stopped it in the core."""
    return run_structs([structs(resolve(c), kernel=kernel) for c in configurations])


def run_structs(prepared: list) -> list:
    """run_batch on configurations already turned into C structs (`structs`)."""
    n = len(prepared)
    if n > _core.MAX_BATCH:
        raise InputError(f"configurations: {n} runs; a batch takes at most {_core.MAX_BATCH}")
    arrays = [(kind * n)() for kind in (_core.PlantParams, _core.BcuParams, _core.WspParams, _core.Scenario)]
    for i, four in enumerate(prepared):
        for array, struct in zip(arrays, four):
            array[i] = struct
    kpis, status, errors = (_core.Kpis * n)(), (ctypes.c_int * n)(), (_core.RbError * n)()
    state = ctypes.create_string_buffer(_core.rb_run_state_size())
    _core.call(_core.rb_run_batch, n, *arrays, state, kpis, status, errors)
    return [kpi_dict(kpis[i], arrays[0][i].atmosphere, arrays[3][i].n_speed_marks) if status[i] == 0
            else InputError(errors[i].message.decode("utf-8", "replace")) for i in range(n)]


def run(scenario="emergency-300-heavy-rain", cars: int | None = None, wsp: bool = True,
        wsp_function: WspCallback | None = None, progress: Callable[[float, float], None] | None = None,
        record: bool = True, dt: float = DT, substeps: int | None = None, kernel: str | None = None,
        train=None, changes=()) -> Result:
    """Run a scenario (preset name, file, Scenario or railbrake.resolve.Resolved) in the C core.

    cars: override the train's number of cars; wsp=False: no WSP (valves never commanded);
    wsp_function(inputs, commands): a Python WSP replacing the default (prototyping; slower);
    progress(t, v): called after each chunk of simulated time with the time and speed (SI);
    dt: the plant's fixed step (s); substeps: sub-steps of air and wheelsets per step (None:
    substeps_for(dt)); kernel: the wheelset kernel, "auto" or "portable" (None: RAILBRAKE_KERNEL);
    train: a vehicle.Train to use instead of the scenario's (e.g. with overrides), lengthened to
    the cars asked for; changes: simulation.Change's (WSP parameters, adhesion, faults changed at a
    time during the run, as the FMU's tunable parameters between doSteps).
    """
    wsp, record = flag("wsp", wsp), flag("record", record)
    function("wsp_function", wsp_function)
    function("progress", progress)
    if train is not None:
        instance("train", train, Train)
    resolved = resolve(scenario, cars)
    sc, n_cars = resolved.scenario, resolved.cars
    configured = resolved if train is None else None   # a train given here is not in the configuration
    plant, bcu, wspp, spec = structs(resolved, wsp, dt, substeps, kernel, train)
    callback = None
    if wsp_function is not None:
        def _adapter(_context, inputs, commands):
            wsp_function(inputs.contents, commands.contents)
        callback = _core.WSP_FUNCTION(_adapter)
        bcu.wsp = callback
    state = ctypes.create_string_buffer(_core.rb_run_state_size())
    _core.call(_core.rb_run_init, ctypes.byref(plant), ctypes.byref(bcu), ctypes.byref(wspp),
               ctypes.byref(spec), state)
    names = channels(n_cars)
    speed_column = [name for name, _ in names].index("speed")
    rows = int(math.ceil(sc.spec.stop.max_time / sc.spec.outputs.record_interval)) + 3 if record else 0
    series = np.zeros((rows, len(names)))
    finished = ctypes.c_int(0)
    pending = run_changes.check(changes, sc.spec.stop.max_time, plant.n_faults, bool(bcu.wsp_per_bogie))
    t, chunk = 0.0, CHUNK if progress is not None else QUIET_CHUNK
    while not finished.value:
        t = min(t + chunk, pending[0].time) if pending else t + chunk
        _core.call(_core.rb_run_advance, ctypes.byref(plant), ctypes.byref(bcu), ctypes.byref(spec), state,
                   t, _core.ptr(series) if record else None, rows, ctypes.byref(finished))
        while pending and pending[0].time <= t and not finished.value:
            run_changes.apply(pending.pop(0), plant, wspp, state)
        if progress is not None:   # the speed of the last row surely written (the one at t may not be)
            row = max(0, min(int(t / sc.spec.outputs.record_interval) - 1, rows - 1))
            progress(min(t, sc.spec.stop.max_time), float(series[row, speed_column]) if record else math.nan)
    kpis = _core.Kpis()
    _core.rb_run_kpis(ctypes.byref(plant), state, ctypes.byref(kpis))
    n_rows = int(np.count_nonzero(series[:, 0])) + 1 if record else 0
    series = series[:n_rows]
    outputs = {name: series[:, i].copy() for i, (name, _) in enumerate(names)}
    k = kpi_dict(kpis, plant.atmosphere)
    return Result(sc.name, n_cars, bool(bcu.wsp_enabled), outputs.get("time", np.zeros(0)), outputs,
                  dict(names), k | outside_validity_kpi(sc, k["max_slip"]), plant.atmosphere, resolved=configured)
