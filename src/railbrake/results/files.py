"""A run on disk: time series as Parquet, CSV or MDF4 (same channel names and samples, SI units),
kpis.json, and run.json (what was run, units, provenance). Parquet and MDF4 also carry run.json's
content in their own metadata, so each file stands alone; load() reads any of them back."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from railbrake import atomic, jsonio
from railbrake.errors import InputError
from railbrake.results import channel_info
from railbrake.results.record import RunRecord

FORMATS = {"parquet": "timeseries.parquet", "csv": "timeseries.csv", "mf4": "timeseries.mf4"}
_READ_ORDER = ("parquet", "mf4", "csv")


def dumps(data) -> str:
    return jsonio.dumps(data, indent=2)   # NaN and infinities become null


def parse_formats(text: str | None, option: str = "--format") -> list[str]:
    """'parquet,csv' -> ['parquet', 'csv'] (also given as several options)."""
    formats = [f.strip().lower() for f in (text or "parquet").split(",") if f.strip()]
    for f in formats:
        if f not in FORMATS:
            raise InputError(f"{option} = {text!r}: {f!r} is not one of {', '.join(FORMATS)}")
    return list(dict.fromkeys(formats))


# ------------------------------------------------------------------ writing

def arrow_table(record: RunRecord) -> pa.Table:
    """One float64 column per channel, its SI unit in the field's metadata (`unit`); the schema's
    metadata holds run.json's content (`railbrake`), the KPIs, `scenario`, `cars`, `wsp`, `units`."""
    fields = [pa.field(n, pa.float64(), metadata={"unit": record.units.get(n, "")}) for n in record.outputs]
    meta = {"scenario": record.meta.get("scenario", ""), "cars": str(record.cars), "wsp": str(record.wsp),
            "units": json.dumps(record.units), "railbrake": dumps(record.meta), "kpis": dumps(record.kpis)}
    return pa.table({n: np.asarray(v, dtype=np.float64) for n, v in record.outputs.items()},
                    schema=pa.schema(fields, metadata=meta))


def write_parquet(record: RunRecord, path: Path) -> Path:
    with atomic.replacing(path) as temporary:
        pq.write_table(arrow_table(record), temporary)
    return Path(path)


def units_path(path: Path) -> Path:
    """The units sidecar of a CSV time series: timeseries.csv -> timeseries_units.csv."""
    path = Path(path)
    return path.with_name(f"{path.stem}_units.csv")


def write_csv(record: RunRecord, path: Path) -> Path:
    """One header line of channel names, then one line per sample; each value is Python's repr of
    the float64, the shortest text that reads back to the same bits. The SI unit of each channel
    goes into a sidecar, units_path(path) (`channel,unit` lines), so that every CSV reader still
    reads the time series as it is."""
    names = list(record.outputs)
    columns = np.column_stack([np.asarray(record.outputs[n], dtype=np.float64) for n in names])
    with atomic.replacing(units_path(path)) as temporary, open(temporary, "w", newline="") as f:
        f.write("channel,unit\n")
        for name in names:
            f.write(f"{name},{record.units.get(name, '')}\n")
    with atomic.replacing(path) as temporary, open(temporary, "w", newline="") as f:
        f.write(",".join(names) + "\n")
        for row in columns.tolist():
            f.write(",".join(map(repr, row)) + "\n")
    return Path(path)


def _read_units(path: Path) -> dict:
    """Channel -> unit from a CSV's sidecar; {} without one."""
    sidecar = units_path(path)
    if not sidecar.is_file():
        return {}
    lines = sidecar.read_text().splitlines()[1:]
    return dict(line.split(",", 1) for line in lines if "," in line)


def _mdf_signal(name: str, values, time, unit: str):
    """A channel with its comment; a state channel as unsigned integers with its value-to-text conversion."""
    from asammdf import Signal
    conversion = channel_info.conversion(name)
    samples = np.asarray(values, dtype=np.float64)
    if conversion is not None and "lower_0" in conversion:   # ranges among numbers: the samples as they are
        pass
    elif conversion is not None and np.all(np.isin(samples, [float(v) for k, v in conversion.items() if k.startswith("val_")])):
        samples = samples.astype(np.int8 if samples.size and samples.min() < 0 else np.uint8)
    else:
        conversion = None
    return Signal(samples=samples, timestamps=time, name=name, unit=unit, comment=channel_info.comment(name),
                  conversion=conversion)


def _history(version: str):
    """The file history block naming railbrake as the tool that wrote the file (ASAM MDF4 FHBLOCK)."""
    from asammdf.blocks.v4_blocks import FileHistory
    fh = FileHistory()
    fh.comment = (f"<FHcomment><TX>created</TX><tool_id>railbrake</tool_id><tool_vendor>railbrake</tool_vendor>"
                  f"<tool_version>{version}</tool_version></FHcomment>")
    return fh


def write_mdf(record: RunRecord, path: Path, extra: dict | None = None, events=()) -> Path:
    """MDF 4.10: each channel but time (the master, s) with its SI unit and comment, state channels as
    integers with value-to-text conversions; the header comment holds run.json's content, the KPIs
    and `extra` as JSON; the scenario (as run) and the KPIs attached as JSON files; events: (time s,
    name, comment) as MDF4 event blocks (EVBLOCK, trigger points synchronised on the time master);
    railbrake as the producing tool in the file history."""
    from asammdf import MDF
    from asammdf.blocks import v4_constants
    from asammdf.blocks.v4_blocks import EventBlock
    from railbrake._version import __version__
    mdf = MDF(version="4.10")
    t = np.asarray(record.time, dtype=np.float64)
    mdf.append([_mdf_signal(n, v, t, record.units.get(n, "")) for n, v in record.outputs.items() if n != "time"],
               comment=f"railbrake {record.kind}: {record.title()}")
    header = {"scenario": record.meta.get("scenario"), "cars": record.cars, "kpis": record.kpis,
              **(extra or {}), "railbrake": record.meta}
    mdf.header.comment = dumps(header)
    scenario = {k: record.meta.get(k) for k in ("scenario", "title", "train", "condition", "zones", "demand",
                                                  "faults", "configuration")}
    for name, content, what in (("scenario.json", scenario, "the scenario as run"), ("kpis.json", record.kpis, "KPIs")):
        mdf.attach(dumps(content).encode(), file_name=name, comment=f"railbrake {what}", mime="application/json")
    mdf.file_history[:] = [_history(__version__)]   # the attachments' creator: railbrake
    for time_s, name, comment in events:
        # the event's time is sync_base * sync_factor s: in integer microseconds, exact for 1 ms steps
        event = EventBlock(event_type=v4_constants.EVENT_TYPE_TRIGGER, sync_type=v4_constants.EVENT_SYNC_TYPE_S,
                           cause=v4_constants.EVENT_CAUSE_TOOL, sync_base=int(round(time_s * 1e6)), sync_factor=1e-6)
        event.name, event.comment = name, comment
        mdf.events.append(event)
    path = Path(path).with_suffix(".mf4")   # asammdf saves MDF4 under .mf4
    with atomic.replacing(path) as temporary:
        mdf.save(temporary, overwrite=True, add_history_block=False)
        mdf.close()
    return path


_WRITERS = {"parquet": write_parquet, "csv": write_csv, "mf4": write_mdf}


def write_run(record: RunRecord, folder: Path, formats=("parquet",), complete: bool = True) -> list[Path]:
    """The time series in each format, kpis.json and run.json into folder (each whole or absent);
    complete: then the manifest (write_manifest), which a caller writing more files writes last."""
    folder = begin_folder(folder) if complete else folder
    paths = [_WRITERS[f](record, folder / FORMATS[f]) for f in formats]
    paths += [units_path(folder / FORMATS["csv"])] if "csv" in formats else []
    atomic.write_text(folder / "kpis.json", dumps(record.kpis) + "\n")
    atomic.write_text(folder / "run.json", dumps({"meta": record.meta, "units": record.units}) + "\n")
    paths += [folder / "kpis.json", folder / "run.json"]
    return paths + [write_manifest(folder, record, paths)] if complete else paths


# ------------------------------------------------------------------ completeness

# Written last into a run folder: the sample count and each file's size and SHA-256. A folder
# without it (a run killed while writing) or whose files disagree with it is refused by load().
MANIFEST = "manifest.json"


def begin_folder(folder: Path) -> Path:
    """A run folder about to be (re)written: created, its manifest removed first (until the new one
    is written the folder reads as incomplete), a killed writer's temporaries swept."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    (folder / MANIFEST).unlink(missing_ok=True)
    atomic.sweep(folder)
    return folder


def _digest(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def write_manifest(folder: Path, record: RunRecord, paths) -> Path:
    """The manifest of a complete run folder: `samples` and, per file written (paths), its bytes and
    sha256. Written last, whole or absent."""
    folder = Path(folder)
    entries = {}
    for path in paths:
        path = Path(path)
        if path.parent.resolve() == folder.resolve() and path.name != MANIFEST and path.is_file():
            entries[path.name] = {"bytes": path.stat().st_size, "sha256": _digest(path)}
    manifest = {"samples": len(record.time), "files": dict(sorted(entries.items()))}
    return atomic.write_text(folder / MANIFEST, json.dumps(manifest, indent=1) + "\n")


def refresh_manifest(folder: Path, paths) -> None:
    """A complete run folder's manifest after files of it were written anew (its figures redrawn by
    `railbrake plot`): their entries take the new bytes and digests; nothing else changes. A folder
    without a manifest, or files elsewhere, are left as they are."""
    folder = Path(folder)
    if not (folder / MANIFEST).is_file():
        return
    manifest = json.loads((folder / MANIFEST).read_text())
    for path in map(Path, paths):
        if path.parent.resolve() == folder.resolve() and path.name != MANIFEST and path.is_file():
            manifest["files"][path.name] = {"bytes": path.stat().st_size, "sha256": _digest(path)}
    manifest["files"] = dict(sorted(manifest["files"].items()))
    atomic.write_text(folder / MANIFEST, json.dumps(manifest, indent=1) + "\n")


def check_complete(folder: Path) -> dict:
    """The manifest of a complete run folder; InputError naming what is missing or damaged otherwise."""
    folder = Path(folder)
    manifest_path = folder / MANIFEST
    if not manifest_path.is_file():
        raise InputError(f"{folder}: incomplete run folder: {MANIFEST} is missing (it is written last; the "
                         "run that wrote this folder was interrupted, or it predates manifests: write it again)")
    try:
        manifest = json.loads(manifest_path.read_text())
        files, samples = manifest["files"], int(manifest["samples"])
    except (ValueError, KeyError, TypeError) as exc:
        raise InputError(f"{manifest_path}: damaged manifest ({exc})") from None
    missing = [name for name in files if not (folder / name).is_file()]
    if missing:
        raise InputError(f"{folder}: incomplete run folder: missing {', '.join(missing)} (listed in {MANIFEST})")
    for name, entry in files.items():
        size = (folder / name).stat().st_size
        if size != entry.get("bytes") or _digest(folder / name) != entry.get("sha256"):
            raise InputError(f"{folder / name}: {size} bytes whose SHA-256 differs from {MANIFEST}'s "
                             f"({entry.get('bytes')} bytes): changed or partly written after the run")
    return {"samples": samples, "files": files}


# ------------------------------------------------------------------ reading

def _read_parquet(path: Path):
    table = pq.read_table(path)
    meta = {k.decode(): v.decode() for k, v in (table.schema.metadata or {}).items()}
    outputs = {n: table.column(n).to_numpy() for n in table.column_names}
    units = {f.name: (f.metadata or {}).get(b"unit", b"").decode() for f in table.schema}
    run = json.loads(meta["railbrake"]) if "railbrake" in meta else {
        "scenario": meta.get("scenario", path.stem), "cars": int(meta.get("cars", 0) or 0),
        "wsp": meta.get("wsp", "True") == "True"}
    kpis = json.loads(meta["kpis"]) if "kpis" in meta else None
    return outputs, units, run, kpis


def _mdf_header(comment: str | None) -> dict:
    """The JSON written into the MDF4 header comment. asammdf saves a plain comment as the XML
    <HDcomment><TX>...</TX></HDcomment> (escaped) and reads that XML back: take the TX text."""
    text = (comment or "").strip()
    if text.startswith("<"):
        import xml.etree.ElementTree as ET
        try:
            text = ET.fromstring(text).findtext("TX") or ""
        except ET.ParseError:
            return {}
    try:
        header = json.loads(text or "{}")
    except json.JSONDecodeError:
        return {}
    return header if isinstance(header, dict) else {}


def _read_mdf(path: Path):
    from asammdf import MDF
    with MDF(path) as mdf:
        header = _mdf_header(mdf.header.comment)
        outputs, units = {}, {}
        for name in mdf.channels_db:
            if name in ("t", "time") or name.startswith("$"):
                continue
            signal = mdf.get(name, raw=True)   # state channels: their integers, not the texts
            if "time" not in outputs:
                outputs["time"], units["time"] = np.asarray(signal.timestamps, dtype=np.float64), "s"
            outputs[name], units[name] = np.asarray(signal.samples, dtype=np.float64), signal.unit
    run = header.get("railbrake") or {"scenario": header.get("scenario", path.stem), "cars": header.get("cars"),
                                      "kind": "HIL"}
    if "counters" in header:
        run.setdefault("hil", {"counters": header["counters"], "timing": header.get("timing")})
    return outputs, units, run, header.get("kpis")


def _csv_number(text: str) -> float:
    """A CSV value: a float, or FMPy's True/False for a Boolean variable."""
    text = text.strip()
    return {"True": 1.0, "False": 0.0}.get(text) if text in ("True", "False") else float(text)


def _read_csv(path: Path):
    """Our CSV or FMPy's (quoted names; 'time' first)."""
    with open(path) as f:
        names = [n.strip().strip('"') for n in f.readline().strip().split(",")]
        rows = [line.split(",") for line in f if line.strip()]
    columns = zip(*rows) if rows else [[] for _ in names]
    outputs = {n: np.array([_csv_number(x) for x in col], dtype=np.float64) for n, col in zip(names, columns)}
    return outputs, _read_units(path), {"scenario": path.stem, "kind": "FMU"}, None


_READERS = {"parquet": _read_parquet, "mf4": _read_mdf, "csv": _read_csv}


def _data_file(path: Path) -> Path:
    if path.is_file():
        return path
    if not path.is_dir():
        raise InputError(f"{path}: no such run folder or file")
    for fmt in _READ_ORDER:
        candidates = [path / FORMATS[fmt]] + sorted(path.glob(f"*.{fmt}"))
        for c in candidates:
            if c.is_file() and not atomic.is_temporary(c):
                return c
    raise InputError(f"{path}: no timeseries.parquet, .mf4 or .csv in this folder")


def load(path: Path | str, prefer: str | None = None) -> RunRecord:
    """A saved run: a folder written by `run --out` / `hil --out`, or one Parquet, MDF4 or CSV file
    (an FMU result from FMPy as CSV too). prefer: the format to read in a folder with several."""
    path = Path(path)
    folder = path if path.is_dir() else path.parent
    manifest = check_complete(folder) if path.is_dir() or (folder / MANIFEST).is_file() else None
    data = path / FORMATS[prefer] if prefer and path.is_dir() else _data_file(path)
    if manifest is not None and data.name not in manifest["files"]:
        raise InputError(f"{data}: not among the files of {folder / MANIFEST} (written by another run?)")
    fmt = data.suffix.lstrip(".").lower()
    if fmt not in _READERS:
        raise InputError(f"{data}: unknown format {data.suffix!r} (parquet, mf4 or csv)")
    outputs, units, meta, kpis = _READERS[fmt](data)
    if "time" not in outputs or "speed" not in outputs:
        raise InputError(f"{data}: no 'time' and 'speed' channels: not a railbrake run")
    if manifest is not None and len(outputs["time"]) != manifest["samples"]:
        raise InputError(f"{data}: {len(outputs['time'])} samples, {manifest['samples']} in {folder / MANIFEST}")
    folder = data.parent
    if (folder / "run.json").is_file():
        saved = json.loads((folder / "run.json").read_text())
        meta = saved.get("meta", meta) if fmt == "csv" or not meta.get("provenance") else meta
        units = units or saved.get("units", {})
    if (folder / "kpis.json").is_file():
        kpis = json.loads((folder / "kpis.json").read_text())
    meta.setdefault("source", str(data))
    units = {n: units.get(n, "") for n in outputs}
    return RunRecord(outputs["time"], outputs, units, kpis if kpis is not None else {}, meta)
