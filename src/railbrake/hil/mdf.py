"""ASAM MDF4 recording of a HIL run (asammdf): every recorded channel with its SI unit; the
counters, the timing report, the KPIs and the run's provenance in the file comment
(railbrake.results.files.write_mdf, the same writer as `run --format mf4`)."""

from __future__ import annotations

from pathlib import Path


def write_mdf(result, path: Path, scenario=None) -> Path:
    """Write result's channels (time base: the plant's simulated time, s) to an MDF 4.10 file."""
    from railbrake import scenario as scenarios
    from railbrake.results import files, record
    sc = scenario if scenario is not None else scenarios.load(result.scenario)
    return files.write_mdf(record.from_hil(result, sc), path,
                           {"counters": result.counters, "timing": result.timing,
                            "interrupted": getattr(result, "interrupted", False)})
