"""A study's results: a Parquet dataset in DIR/runs/, one file per finished batch, fixed schema.

Columns: key, run, point, replicate, seed, block, sample, one per factor (SI; units in the schema
metadata), one per KPI (float64: booleans and counts as numbers, None as null), status ("ok" or
"failed"), error, wall_time_s. A batch file is written to a temporary name and renamed, so a
study killed at any moment leaves only whole batches: the dataset is always consistent and a
rerun skips the keys it holds. DIR/study.json records the schema and the study's identity.

DIR/runs holds the parts only (and, while one is written, its hidden temporary file), so the folder
reads as one table in any Parquet reader: pyarrow.dataset.dataset(DIR/runs), pandas.read_parquet,
polars.scan_parquet, duckdb's read_parquet('DIR/runs/*.parquet'). Every column names its unit in
its field metadata ("unit": SI or "1" for counts, flags and ratios, "" for text), and the schema
metadata "railbrake.units" maps every column to it.

The dataset vouches for itself: DIR/parts.jsonl lists every part written, one line each
with its SHA-256 and its run keys, appended (and flushed to disk) before the part is renamed into
place; DIR/keys.json holds the run keys of the study as last planned (a dataset written before
they moved out of DIR/runs has them moved on its first read). Resume and report verify
every part against that list before trusting it: a part altered or damaged after it was written
(checksum), copied or brought from another dataset (not listed, or its keys not its own), or
listed but missing is refused by name, and the report counts only the study's keys. A study killed
between the line and the rename is completed on resume (the temporary part matches its line).
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from railbrake.campaign.factors import Factor
from railbrake.errors import InputError

RUNS = "runs"
MANIFEST = "study.json"
STATUS_OK, STATUS_FAILED = "ok", "failed"
_FACTOR_TYPES = {"quantity": pa.float64(), "number": pa.float64(), "integer": pa.int64(), "category": pa.string(),
                 "case": pa.string()}
_FIXED = [("key", pa.string()), ("run", pa.int64()), ("point", pa.int64()), ("replicate", pa.int64()),
          ("seed", pa.int64()), ("block", pa.string()), ("sample", pa.int64())]
_TAIL = [("status", pa.string()), ("error", pa.string()), ("wall_time_s", pa.float64())]


def kpi_kinds(kpis: dict) -> dict:
    """A KPI column is float64 (numbers, booleans, counts, None) or a string (e.g. an axle name).
    A run's None does not tell, so the KPIs of a zeroed C struct are asked as well."""
    probe = {}
    try:
        from railbrake import _core, simulation
        probe = simulation.kpi_dict(_core.Kpis(), 0.0)
    except (AttributeError, TypeError):   # a core without kpi_dict: the run's values alone
        pass
    return {k: "string" if isinstance(v, str) or isinstance(probe.get(k), str) else "float"
            for k, v in kpis.items()}


_SUFFIX_UNITS = (("_kmh", "km/h"), ("_pct", "%"), ("_bar", "bar"), ("_kg", "kg"), ("_kj", "kJ"), ("_mj", "MJ"),
                 ("_c", "°C"), ("_s", "s"), ("_m", "m"))


def column_unit(name: str, kind: pa.DataType) -> str:
    """A column's unit: a KPI's (results.kpis), else its name's suffix (_s, _m, _kg, ...); "1" for a
    number without one (a count, a flag, a ratio), "" for text."""
    from railbrake.results import kpis
    if kind == pa.string():
        return ""
    unit = kpis.unit(name) or next((u for suffix, u in _SUFFIX_UNITS if name.endswith(suffix)), "")
    return unit or "1"


def schema(factors: list[Factor], kpis: list[str], study: dict, kinds: dict | None = None) -> pa.Schema:
    kinds = kinds or {}
    fields = [pa.field(n, t) for n, t in _FIXED]
    fields += [pa.field(f.name, _FACTOR_TYPES[f.kind], metadata={"unit": f.unit}) for f in factors]
    fields += [pa.field(k, pa.string() if kinds.get(k) == "string" else pa.float64()) for k in kpis]
    fields += [pa.field(n, t) for n, t in _TAIL]
    fields = [f if f.metadata else f.with_metadata({"unit": column_unit(f.name, f.type)}) for f in fields]
    meta = {"railbrake.factors": json.dumps({f.name: f.unit for f in factors}),
            "railbrake.kpis": json.dumps(kpis), "railbrake.study": json.dumps(study),
            "railbrake.units": json.dumps({f.name: f.metadata[b"unit"].decode() for f in fields})}
    return pa.schema(fields, metadata=meta)


def _kpi_value(value, kind: pa.DataType):
    if value is None:
        return None
    return str(value) if kind == pa.string() else float(value)


def table(rows: list[dict], sch: pa.Schema) -> pa.Table:
    kpis = json.loads(sch.metadata[b"railbrake.kpis"])
    columns = {name: [] for name in sch.names}
    for row in rows:
        unknown = set(row["kpis"]) - set(kpis)
        if unknown:
            raise RuntimeError(f"KPIs {sorted(unknown)} are not in the dataset's schema; use a new --out")
        for name in sch.names:
            if name in kpis:
                columns[name].append(_kpi_value(row["kpis"].get(name), sch.field(name).type))
            elif name in row["factors"]:
                columns[name].append(row["factors"][name])
            else:
                columns[name].append(row.get(name))
    return pa.table({n: pa.array(columns[n], type=sch.field(n).type) for n in sch.names}, schema=sch)


def batch_name(keys: list[str]) -> str:
    return "part-" + hashlib.sha256("".join(keys).encode()).hexdigest()[:20] + ".parquet"


def write_batch(out: Path, rows: list[dict], sch: pa.Schema) -> Path:
    folder = out / RUNS
    folder.mkdir(parents=True, exist_ok=True)
    keys = [r["key"] for r in rows]
    final = folder / batch_name(keys)
    temporary = folder / f".{final.name}.{os.getpid()}.tmp"
    pq.write_table(table(rows, sch), temporary)
    sha = _sha256(temporary)
    _append_part(out, final.name, sha, keys)   # listed first: a part never unlisted
    try:
        os.replace(temporary, final)   # atomic: a reader sees the whole batch or none of it
    except FileNotFoundError:   # a resume reading the dataset meanwhile completed the rename (_recover)
        if not (final.is_file() and _sha256(final) == sha):
            raise
    return final


# ------------------------------------------------------------------ the parts' manifest

PARTS = "parts.jsonl"    # in DIR: one line per part, {"part", "sha256", "keys"}
KEYS = "keys.json"       # in DIR: {"keys": the study's run keys}


def _moved_out(out: Path, name: str) -> Path:
    """DIR/name; a dataset written when it lay in DIR/runs has it moved up first (DIR/runs holds
    the parts alone, for every Parquet reader)."""
    path, old = Path(out) / name, Path(out) / RUNS / name
    if old.is_file() and not path.exists():
        os.replace(old, path)
    return path


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _append_part(out: Path, name: str, sha: str, keys: list[str]) -> None:
    line = json.dumps({"part": name, "sha256": sha, "keys": keys}, separators=(",", ":")) + "\n"
    with _moved_out(out, PARTS).open("a") as handle:
        handle.write(line)
        handle.flush()
        os.fsync(handle.fileno())


def _where(out: Path, name: str) -> str:
    return str(Path(out) / name) if name in (PARTS, KEYS) else str(Path(out) / RUNS / name)


def _listed(out: Path, repair: bool) -> dict[str, dict]:
    """part name -> its line of parts.jsonl; a torn last line (a study killed while appending it:
    its part was never renamed into place) is dropped when repairing, refused otherwise."""
    path = _moved_out(out, PARTS)
    if not path.is_file():
        return {}
    raw = path.read_bytes()
    lines = raw.split(b"\n")
    listed = {}
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        try:
            entry = json.loads(line)
            if not (isinstance(entry, dict) and isinstance(entry.get("part"), str)
                    and isinstance(entry.get("sha256"), str) and isinstance(entry.get("keys"), list)):
                raise ValueError
        except ValueError:
            last = number == len(lines) and not raw.endswith(b"\n")
            if last and repair:
                with path.open("r+b") as handle:   # the line being written when the study was killed
                    handle.truncate(len(raw) - len(line))
                break
            raise InputError(f"{path}, line {number}: damaged (not a part's record): the dataset cannot be "
                             "verified; run the study into a new folder") from None
        listed[entry["part"]] = entry
    return listed


def _recover(out: Path, name: str, entry: dict) -> bool:
    """A listed part killed before its rename: rename its temporary file if it matches its line."""
    for temporary in (out / RUNS).glob(f".{name}.*.tmp"):
        if _sha256(temporary) == entry["sha256"]:
            os.replace(temporary, out / RUNS / name)
            return True
    return False


def verify(out: Path, repair: bool = False) -> dict[str, dict]:
    """Every part of DIR/runs checked against parts.jsonl (name -> its line): InputError naming the
    first part that is not listed (copied, foreign), whose checksum differs (altered, damaged),
    whose name is not that of its keys, or that is listed but missing. repair (resume): complete a
    study killed between a part's line and its rename."""
    out = Path(out)
    listed = _listed(out, repair)
    present = {p.name for p in _parts(out)}
    if present and not _moved_out(out, PARTS).is_file():
        raise InputError(f"{_where(out, PARTS)}: missing, so the parts cannot be verified (a dataset of a railbrake "
                         "before dataset manifests, or the file removed): run the study into a new folder")
    for name in sorted(present - set(listed)):
        raise InputError(f"{_where(out, name)}: not in {_where(out, PARTS)}: a copy, or a part of another "
                         "dataset: remove it (this dataset's parts are listed there when written)")
    for name, entry in listed.items():
        if name not in present and not (repair and _recover(out, name, entry)):
            raise InputError(f"{_where(out, name)}: listed in {_where(out, PARTS)} but missing: restore it, or run "
                             "the study into a new folder")
        if batch_name(entry["keys"]) != name:
            raise InputError(f"{_where(out, name)}: its name is not that of its runs' keys in {_where(out, PARTS)}")
        if _sha256(out / RUNS / name) != entry["sha256"]:
            raise InputError(f"{_where(out, name)}: its SHA-256 differs from {_where(out, PARTS)}: altered or "
                             "damaged after it was written; remove it (and its line) to run its runs again, "
                             "or run the study into a new folder")
    return listed


def record_study_keys(out: Path, keys: list[str]) -> None:
    """The study's run keys (as planned now), for the report to count only them."""
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    (folder / RUNS / KEYS).unlink(missing_ok=True)   # of a dataset written when it lay there
    temporary = folder / f".{KEYS}.tmp"
    temporary.write_text(json.dumps({"keys": sorted(keys)}))
    os.replace(temporary, folder / KEYS)


def study_keys(out: Path) -> set[str] | None:
    path = _moved_out(out, KEYS)
    if not path.is_file():
        return None
    try:
        keys = json.loads(path.read_text())["keys"]
    except (ValueError, KeyError, TypeError):
        raise InputError(f"{path}: damaged (not the study's run keys); run the study again to rewrite it") from None
    return set(keys)


def _parts(out: Path) -> list[Path]:
    return sorted((out / RUNS).glob("part-*.parquet")) if (out / RUNS).is_dir() else []


def clean(out: Path) -> None:
    """Remove the temporary files a killed study left behind."""
    for path in (out / RUNS).glob(".part-*.tmp") if (out / RUNS).is_dir() else ():
        path.unlink(missing_ok=True)


def existing_keys(out: Path, study_keys: list[str] | None = None) -> set[str]:
    """The keys the dataset holds, from its verified parts (a resume completes a part killed before
    its rename); study_keys, when given, are recorded as the study's (record_study_keys) in a
    dataset already there (a new one records them when its folder is made)."""
    out = Path(out)
    keys: set[str] = set()
    for entry in verify(out, repair=True).values():
        keys.update(entry["keys"])
    if study_keys is not None and (out / RUNS).is_dir():
        record_study_keys(out, study_keys)
    return keys


def _read_part(out: Path, name: str, keys: list[str]) -> pa.Table:
    try:
        part = pq.read_table(out / RUNS / name)
    except (OSError, pa.ArrowException) as exc:
        raise InputError(f"{_where(out, name)}: not a readable Parquet part ({exc})") from None
    if sorted(part.column("key").to_pylist()) != sorted(keys):
        raise InputError(f"{_where(out, name)}: holds other runs than {_where(out, PARTS)} lists for it")
    return part


def read(out: Path) -> pa.Table:
    """The whole dataset, verified (verify), of the study's keys only, each once, sorted by key."""
    out = Path(out)
    listed = verify(out)
    if not listed:
        raise InputError(f"{out}: no campaign dataset here ({RUNS}/part-*.parquet)")
    data = pa.concat_tables([_read_part(out, name, entry["keys"]) for name, entry in listed.items()])
    wanted = study_keys(out)
    keep, seen = [], set()
    for key in data.column("key").to_pylist():   # each of the study's keys once
        keep.append(key not in seen and (wanted is None or key in wanted))
        seen.add(key)
    return data.filter(pa.array(keep, type=pa.bool_())).sort_by("key")


def read_manifest(out: Path) -> dict | None:
    """DIR/study.json, None without one; InputError naming it when it is damaged."""
    path = Path(out) / MANIFEST
    if not path.is_file():
        return None
    try:
        manifest = json.loads(path.read_bytes())
    except (ValueError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: damaged ({exc}): not the study's record; restore it, or run the study "
                         "into a new folder") from None
    if not isinstance(manifest, dict):
        raise InputError(f"{path}: damaged (a JSON {type(manifest).__name__}, not the study's record); restore "
                         "it, or run the study into a new folder")
    for key, kinds in _MANIFEST_TYPES.items():
        if manifest.get(key) is not None and not isinstance(manifest[key], kinds):
            raise InputError(f"{path}: damaged: {key} = {manifest[key]!r} is not a "
                             f"{' or '.join(k.__name__ for k in kinds)}; restore it, or run the study into a new folder")
    return manifest


# the shape of study.json's entries (execute._manifest writes them)
_MANIFEST_TYPES = {"schema": (str,), "study": (str,), "base": (str,), "factors": (dict,), "factor_order": (list,),
                   "kinds": (dict,), "kpis": (list,), "kpi_kinds": (dict,), "runs": (int,), "design": (str,),
                   "samples": (int,)}


def write_manifest(out: Path, manifest: dict) -> None:
    out.mkdir(parents=True, exist_ok=True)
    temporary = out / f".{MANIFEST}.tmp"
    temporary.write_text(json.dumps(manifest, indent=2, sort_keys=True))
    os.replace(temporary, out / MANIFEST)
