"""What a Dask worker does with one batch: resolve and simulate each run, never raise for a run.

A run that raises is returned with status "failed" and its error, so one bad configuration does
not stop a study. Only a lost worker makes the batch fail, and Dask then runs it again elsewhere.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from railbrake.campaign import configuration
from railbrake.campaign.dataset import STATUS_FAILED, STATUS_OK


def equivalent_response_time(result, delay: float, complete: float) -> float | None:
    """EN 14531 te = ta + tb/2 from the train's mean brake-cylinder pressure: ta until it reaches
    `delay` of its peak, tb from there to `complete` of it (fractions from the study file)."""
    names = result.axle_channels("cylinder")
    if not names or result.time.size < 2:
        return None
    p = np.mean([result.outputs[n] for n in names], axis=0)
    rise = p - p[0]
    peak = rise.max()
    if peak <= 0:
        return None
    t_a = float(result.time[np.argmax(rise >= delay * peak)])
    t_c = float(result.time[np.argmax(rise >= complete * peak)])
    return t_a + (t_c - t_a) / 2


def _one(base: str, run: dict, options: dict) -> dict:
    start = time.perf_counter()
    row = {"key": run["key"], "run": run["index"], "point": run["point"], "replicate": run["replicate"],
           "seed": run["seed"], "block": run["block"], "sample": run["sample"], "factors": run["factors"],
           "kpis": {}, "status": STATUS_OK, "error": None}
    try:
        resolved = configuration.resolve(base, run["sets"])
        record = bool(options.get("timeseries") or options.get("build_up"))
        result = configuration.run(resolved, record=record)
        row["kpis"] = dict(result.kpis)
        if options.get("build_up"):
            row["kpis"]["equivalent_response_time_s"] = equivalent_response_time(result, **options["build_up"])
        if options.get("timeseries"):
            from railbrake.simulation.io import write_parquet
            folder = Path(options["out"]) / "timeseries"
            folder.mkdir(parents=True, exist_ok=True)
            write_parquet(result, folder / f"{run['key']}.parquet")
    except Exception as exc:   # noqa: BLE001 - a failed run is data, recorded with its error
        row["status"], row["error"] = STATUS_FAILED, f"{type(exc).__name__}: {exc}"
    row["wall_time_s"] = time.perf_counter() - start
    return row


def execute_batch(base: str, runs: list[dict], options: dict) -> dict:
    start = time.perf_counter()
    rows = [_one(base, run, options) for run in runs]
    return {"rows": rows, "compute_s": time.perf_counter() - start}
