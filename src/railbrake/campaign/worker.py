"""What a Dask worker does with one batch: resolve and simulate each run, never raise for a run.

A run that raises is returned with status "failed" and its error, so one bad configuration does
not stop a study. Only a lost worker makes the batch fail, and Dask then runs it again elsewhere.
A run records no time series unless the study asks for them (or it is an assessment's reference,
whose build-up time is measured on its total brake force): those runs are set up one by one and run
together in one call of the C core (simulation.run_structs), their KPIs only. The warnings a run
raises travel back with its row.
"""

from __future__ import annotations

import os
import socket
import time
import warnings
from pathlib import Path

import numpy as np

from railbrake.campaign import configuration
from railbrake.campaign.dataset import STATUS_FAILED, STATUS_OK


def equivalent_response_time(result, train) -> float | None:
    """EN 14531-1 te = ta + tb/2 on the train's total brake force (simulation.response, with the
    fractions and window of data/response/en14531.yaml, as `run`, `stopping-distance` and the ETCS
    model measure it), from the first step with a brake demand. Not on the deceleration: a
    speed-stepped emergency demand and the pads' friction make it rise over the whole stop."""
    from railbrake.simulation import response
    demand = result.outputs.get("demand_deceleration")
    if demand is None or not np.any(demand > 0):
        return None
    return response.measure(result, train, float(result.time[np.argmax(demand > 0)])).response


def _needs_build_up(run: dict, options: dict) -> bool:
    """The build-up time is measured on the assessment's reference runs (the others use their
    reference's, campaign.assess): only they record a time series for it."""
    reference = options.get("build_up_reference")
    return bool(options.get("build_up")) and (reference is None or
                                              all(run["factors"].get(k) == v for k, v in reference.items()))


def _row(run: dict) -> dict:
    return {"key": run["key"], "run": run["index"], "point": run["point"], "replicate": run["replicate"],
            "seed": run["seed"], "block": run["block"], "sample": run["sample"], "factors": run["factors"],
            "kpis": {}, "status": STATUS_OK, "error": None, "warnings": []}


def _failed(row: dict, exc: Exception) -> None:
    row["status"], row["error"] = STATUS_FAILED, f"{type(exc).__name__}: {exc}"


def _recorded(base: str, run: dict, options: dict, row: dict) -> None:
    """A run that keeps its time series (asked for, or its build-up time measured on it)."""
    try:
        with warnings.catch_warnings(record=True) as caught:   # they go back to the client with the row
            warnings.simplefilter("always")
            resolved = configuration.resolve(base, run["sets"])
            result = configuration.run(resolved, record=True)
        row["warnings"] = [f"{w.category.__name__}: {w.message}" for w in caught]
        # a forced run outside a condition's validity says so in its warnings (simulation.structs):
        # every row keeps the same KPI columns
        row["kpis"] = {k: v for k, v in result.kpis.items() if k != "adhesion_outside_validity"}
        if options.get("build_up"):
            build_up = _needs_build_up(run, options)
            row["kpis"]["equivalent_response_time_s"] = (equivalent_response_time(result, resolved.train)
                                                         if build_up else None)
        if options.get("timeseries"):
            from railbrake.simulation.io import write_parquet
            folder = Path(options["out"]) / "timeseries"
            folder.mkdir(parents=True, exist_ok=True)
            write_parquet(result, folder / f"{run['key']}.parquet")
    except Exception as exc:   # noqa: BLE001 - a failed run is data, recorded with its error
        _failed(row, exc)


def _kpis_only(base: str, runs: list[dict], rows: list[dict], options: dict) -> None:
    """Runs without time series: each resolved and set up here, then all run in one C call."""
    from railbrake import _core, simulation
    prepared, ready, scenarios = [], [], []
    for run, row in zip(runs, rows):
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                resolved = configuration.resolve(base, run["sets"])
                prepared.append(simulation.structs(resolved))
            row["warnings"] = [f"{w.category.__name__}: {w.message}" for w in caught]
            ready.append(row)
            scenarios.append(resolved.scenario)
        except Exception as exc:   # noqa: BLE001
            _failed(row, exc)
    outcomes = [o for i in range(0, len(prepared), _core.MAX_BATCH)
                for o in simulation.run_structs(prepared[i:i + _core.MAX_BATCH])]
    for row, outcome, sc in zip(ready, outcomes, scenarios):
        if isinstance(outcome, Exception):
            _failed(row, outcome)
            continue
        try:   # a condition's creep range, known once run (its speed range: refused before)
            flag = simulation.outside_validity_kpi(sc, outcome["max_slip"]).get("adhesion_outside_validity", "")
        except Exception as exc:   # noqa: BLE001
            _failed(row, exc)
            continue
        if "validity.creep" in flag:
            row["warnings"].append(f"AdhesionRangeWarning: forced outside validity: {flag}")
        row["kpis"] = dict(outcome)
        if options.get("build_up"):
            row["kpis"]["equivalent_response_time_s"] = None


def execute_batch(base: str, runs: list[dict], options: dict) -> dict:
    """The rows, and when and where the batch ran (wall clock) and the CPU time it took, for the
    scheduling and cost figures. Each row's wall_time_s: its share of the batch."""
    began, start, cpu = time.time(), time.perf_counter(), time.process_time()
    rows = [_row(run) for run in runs]
    recorded = [options.get("timeseries") or _needs_build_up(run, options) for run in runs]
    for run, row, keep in zip(runs, rows, recorded):
        if keep:
            _recorded(base, run, options, row)
    _kpis_only(base, [r for r, k in zip(runs, recorded) if not k], [r for r, k in zip(rows, recorded) if not k],
               options)
    compute = time.perf_counter() - start
    for row in rows:
        row["wall_time_s"] = compute / len(rows)
    return {"rows": rows, "compute_s": compute, "cpu_s": time.process_time() - cpu,
            "began": began, "ended": time.time(), "worker": f"{socket.gethostname()}:{os.getpid()}"}
