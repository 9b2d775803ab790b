"""ASAM MDF4 recording of a HIL run (asammdf): every recorded channel with its SI unit, the
counters and the timing report in the file comment."""

from __future__ import annotations

import json
from pathlib import Path

from asammdf import MDF, Signal


def write_mdf(result, path: Path) -> Path:
    """Write result's channels (time base: the plant's simulated time, s) to an MDF 4.10 file."""
    mdf = MDF(version="4.10")
    t = result.time
    mdf.append([Signal(samples=values, timestamps=t, name=name, unit=result.units[name])
                for name, values in result.outputs.items() if name != "time"],
               comment=f"railbrake hil: {result.scenario}, {result.cars} cars")
    mdf.header.comment = json.dumps({"scenario": result.scenario, "cars": result.cars,
                                     "counters": result.counters, "timing": result.timing,
                                     "kpis": result.kpis, "interrupted": getattr(result, "interrupted", False)},
                                    default=float)
    saved = mdf.save(path, overwrite=True)   # asammdf may change the suffix: report what it wrote
    mdf.close()
    return Path(saved)
