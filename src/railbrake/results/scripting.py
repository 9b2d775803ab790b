"""A run's result (Result, built by railbrake.simulation.run) and what a script does with it: a
pandas DataFrame or an Arrow table with the units, the standard figures, and saving it to a run
folder and loading it back unchanged, bit for bit (railbrake.load_result)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from railbrake.errors import InputError
from railbrake.results.record import RunRecord, from_simulation, parse_axles, parse_window

# The standard figures of a run folder (railbrake.plots.simulation), by the name of their file.
PLOT_KINDS = ("wsp_cycle", "braking_curve", "speed_time", "slip", "reservoirs", "cylinders")


class ReadOnlyKpis(dict):
    """A result's KPIs: a dict to read (JSON, ``dict(...)``, ``|``), refusing every change, so what
    ``save()`` writes is what the run computed. ``dict(result.kpis)`` is a copy to change."""

    def _refuse(self, *args, **kwargs):
        raise TypeError("Result.kpis is read-only (the KPIs the run computed, as save() writes them): "
                        "copy it to change it, e.g. kpis = dict(result.kpis)")

    __setitem__ = __delitem__ = __ior__ = update = pop = popitem = clear = setdefault = _refuse

    def __reduce__(self):   # pickle and copy rebuild it whole (not item by item)
        return (ReadOnlyKpis, (dict(self),))


@dataclass
class Result:
    """A run's time series (SI), their units and KPIs (`run --json`'s units). For scripts:
    to_dataframe(), to_arrow(), plot(kind), save(folder) and railbrake.load_result(folder)."""

    scenario: str
    cars: int
    wsp: bool
    time: np.ndarray
    outputs: dict          # channel name -> array (SI)
    units: dict            # channel name -> SI unit
    kpis: dict             # read-only (ReadOnlyKpis)
    atmosphere: float = math.nan   # Pa, the plant's (the train file's)
    meta: dict = field(default_factory=dict)   # what was run, as in run.json (a loaded result)
    resolved: object = field(default=None, repr=False, compare=False)   # the resolve.Resolved run

    def __setattr__(self, name, value):
        if name == "kpis":
            if "kpis" in self.__dict__:
                ReadOnlyKpis._refuse(value)
            value = ReadOnlyKpis(value)
        object.__setattr__(self, name, value)

    def to_dataframe(self):
        """pandas DataFrame, a column per channel (SI) and each pressure also in bar gauge beside it
        (NAME_bar_g); units in .attrs["units"], KPIs in .attrs["kpis"]."""
        return to_dataframe(self)

    def to_arrow(self):
        """pyarrow Table, a column per channel, each field's unit in its metadata."""
        return to_arrow(self)

    def plot(self, kind: str = "braking_curve", path=None, **options):
        """A standard figure (PLOT_KINDS): the Figure, or written to path."""
        return plot(self, kind, path, **options)

    def save(self, folder, overwrite: bool = False):
        """The run folder: timeseries.parquet, kpis.json, run.json (+ config.yaml); load_result reads it.
        An existing folder with files in it is refused unless overwrite=True."""
        return save(self, folder, overwrite)

    def axle_channels(self, quantity: str) -> list[str]:
        return [n for n in self.outputs if n.startswith(quantity + "_c") and "a" in n.split("_c")[-1]]

    def car_channels(self, quantity: str) -> list[str]:
        return [n for n in self.outputs if n.startswith(quantity + "_c") and "a" not in n.split("_c")[-1]]


def record_of(result) -> RunRecord:
    """The RunRecord of a Result: with its scenario's description when the run or the folder it
    was loaded from knows it."""
    if result.resolved is not None:
        return from_simulation(result, result.resolved.scenario)
    meta = dict(result.meta) or {"scenario": result.scenario, "cars": result.cars, "wsp": result.wsp,
                                 "atmosphere_pa": result.atmosphere}
    return RunRecord(result.time, dict(result.outputs), dict(result.units), dict(result.kpis), meta)


GAUGE_SUFFIX = "_bar_g"   # a pressure channel's DataFrame column in bar gauge, as the CLI shows it


def to_dataframe(result):
    """pandas DataFrame, one float64 column per channel (SI: pressures absolute in Pa, as in the
    files), `time` included, and beside each pressure channel NAME its gauge pressure in bar
    (NAME_bar_g: the unit the CLI, the plots and the KPIs use); the units in df.attrs["units"]
    (column -> unit, "bar g" for those), the KPIs in df.attrs["kpis"]."""
    import pandas as pd
    from railbrake.units import pa_to_bar
    columns, units = {}, {}
    atmosphere = record_of(result).atmosphere if not math.isfinite(result.atmosphere) else result.atmosphere
    for name, values in result.outputs.items():
        columns[name], units[name] = values, result.units.get(name, "")
        if units[name] == "Pa":
            columns[name + GAUGE_SUFFIX] = pa_to_bar(np.asarray(values) - atmosphere)
            units[name + GAUGE_SUFFIX] = "bar g"
    frame = pd.DataFrame(columns, copy=True)
    frame.attrs["units"] = units
    frame.attrs["kpis"] = dict(result.kpis)
    frame.attrs["scenario"] = result.scenario
    return frame


def to_arrow(result):
    """pyarrow Table, one float64 column per channel, each field's unit in its metadata (b"unit"),
    the run's description and KPIs in the schema's metadata (as in timeseries.parquet)."""
    from railbrake.results import files
    return files.arrow_table(record_of(result))


def plot(result, kind: str = "braking_curve", path: Path | str | None = None, axle: str | None = None,
         axles: str | None = None, window: str | None = None):
    """One standard figure: path None returns the matplotlib Figure, else writes it (format from the
    suffix) and returns the path. axle: wsp_cycle's axle (default the worst); axles: slip's
    coloured axles besides the worst ('c3a2,c1a1'); window: 'T0:T1' in s for wsp_cycle."""
    from railbrake import _args
    from railbrake.plots import simulation as plots
    from railbrake.results import episodes
    if kind not in PLOT_KINDS:
        raise InputError(f"plot kind = {_args.show(kind)}: must be one of {', '.join(PLOT_KINDS)}")
    record = record_of(result)
    path = None if path is None else _args.path("path", path)
    if path is not None and not path.parent.is_dir():
        raise InputError(f"path = {_args.show(str(path))}: no folder {path.parent} to write it into")
    if kind == "wsp_cycle":
        chosen = parse_axles(axle, record, "axle") or [episodes.plotted_axles(record, None)[0]]
        return plots.plot_wsp_cycle(record, chosen[0], path, parse_window(window, record, "window"))
    if kind == "slip":
        return plots.plot_slip(record, episodes.plotted_axles(record, parse_axles(axles, record, "axles")), path)
    if kind == "cylinders":
        return plots.plot_cylinders(record, path, {a for group in record.faulty_axles() for a in group})
    return {"braking_curve": plots.plot_braking_curve, "speed_time": plots.plot_speed_time,
            "reservoirs": plots.plot_reservoirs}[kind](record, path)


def save(result, folder: Path | str, overwrite: bool = False) -> Path:
    """timeseries.parquet, kpis.json and run.json into folder (and config.yaml, the resolved
    configuration, when the result knows it), then manifest.json; load_result reads it back bit
    for bit, and refuses a folder whose writing was cut short. A folder that exists with anything
    in it is refused unless overwrite=True (its files are then replaced)."""
    from railbrake.results import files
    from railbrake.results.config_file import write_config
    from railbrake import _args
    folder = _args.path("folder", folder)
    overwrite = _args.flag("overwrite", overwrite)
    if folder.exists() and not folder.is_dir():
        raise InputError(f"folder = {_args.show(str(folder))}: is a file; give a folder")
    if folder.exists() and any(folder.iterdir()) and not overwrite:
        raise InputError(f"{folder}: exists and is not empty: save(folder, overwrite=True) replaces its run "
                         "files, or choose a new folder")
    folder = files.begin_folder(folder)
    record = record_of(result)
    paths = files.write_run(record, folder, ["parquet"], complete=False)
    if result.resolved is not None:
        paths += write_config(result.resolved, folder / "config.yaml")   # and the files it names
    files.write_manifest(folder, record, paths)   # last: a folder without it is an interrupted save
    return folder


def compare(*runs) -> dict:
    """Runs side by side as `railbrake compare` gives them (its --json): each a Result or a saved
    run (folder or time-series file); KPIs with their differences from the first run, the largest
    channel differences per unit."""
    from railbrake import _args
    from railbrake.results import files
    from railbrake.results.compare import compare_runs
    if len(runs) < 2:
        raise InputError(f"compare: {len(runs)} run given: needs at least two")
    records, names = [], []
    for i, run in enumerate(runs):
        if isinstance(run, (str, Path)):
            path = _args.path(f"runs[{i}]", run)
            if not path.exists():
                raise InputError(f"runs[{i}] = {_args.show(str(path))}: no such run folder or file")
            records.append(files.load(path))
            names.append(str(run))
        elif hasattr(run, "outputs") and hasattr(run, "kpis"):
            records.append(record_of(run))
            names.append(getattr(run, "scenario", f"run {i + 1}"))
        else:
            raise TypeError(f"runs[{i}] = {_args.show(run)}: must be a Result or a saved run's folder")
    return compare_runs(records, names)


def load_result(folder: Path | str):
    """The Result saved in a run folder (Result.save, `railbrake run --out`, `hil --out`) or one of its
    time-series files."""
    from railbrake import _args
    from railbrake.results import files
    folder = _args.path("folder", folder)
    if not folder.exists():
        raise InputError(f"folder = {_args.show(str(folder))}: no such run folder or file")
    record = files.load(folder)
    meta = {k: v for k, v in record.meta.items() if k != "source"}
    return Result(meta.get("scenario", Path(folder).name), record.cars, record.wsp, record.time, record.outputs,
                  record.units, record.kpis, record.atmosphere, meta=meta)
