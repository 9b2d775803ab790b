"""A study's results: a Parquet dataset in DIR/runs/, one file per finished batch, fixed schema.

Columns: key, run, point, replicate, seed, block, sample, one per factor (SI; units in the schema
metadata), one per KPI (float64: booleans and counts as numbers, None as null), status ("ok" or
"failed"), error, wall_time_s. A batch file is written to a temporary name and renamed, so a
study killed at any moment leaves only whole batches: the dataset is always consistent and a
rerun skips the keys it holds. DIR/study.json records the schema and the study's identity.
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


def schema(factors: list[Factor], kpis: list[str], study: dict, kinds: dict | None = None) -> pa.Schema:
    kinds = kinds or {}
    fields = [pa.field(n, t) for n, t in _FIXED]
    fields += [pa.field(f.name, _FACTOR_TYPES[f.kind], metadata={"unit": f.unit}) for f in factors]
    fields += [pa.field(k, pa.string() if kinds.get(k) == "string" else pa.float64()) for k in kpis]
    fields += [pa.field(n, t) for n, t in _TAIL]
    meta = {"railbrake.factors": json.dumps({f.name: f.unit for f in factors}),
            "railbrake.kpis": json.dumps(kpis), "railbrake.study": json.dumps(study)}
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
    final = folder / batch_name([r["key"] for r in rows])
    temporary = folder / f".{final.name}.{os.getpid()}.tmp"
    pq.write_table(table(rows, sch), temporary)
    os.replace(temporary, final)   # atomic: a reader sees the whole batch or none of it
    return final


def _parts(out: Path) -> list[Path]:
    return sorted((out / RUNS).glob("part-*.parquet")) if (out / RUNS).is_dir() else []


def clean(out: Path) -> None:
    """Remove the temporary files a killed study left behind."""
    for path in (out / RUNS).glob(".part-*.tmp") if (out / RUNS).is_dir() else ():
        path.unlink(missing_ok=True)


def existing_keys(out: Path) -> set[str]:
    keys: set[str] = set()
    for part in _parts(out):
        keys.update(pq.read_table(part, columns=["key"]).column("key").to_pylist())
    return keys


def read(out: Path) -> pa.Table:
    """The whole dataset, sorted by key."""
    parts = _parts(Path(out))
    if not parts:
        raise InputError(f"{out}: no campaign dataset here ({RUNS}/part-*.parquet)")
    data = pa.concat_tables([pq.read_table(p) for p in parts])
    return data.sort_by("key")


def read_manifest(out: Path) -> dict | None:
    path = Path(out) / MANIFEST
    return json.loads(path.read_text()) if path.is_file() else None


def write_manifest(out: Path, manifest: dict) -> None:
    out.mkdir(parents=True, exist_ok=True)
    temporary = out / f".{MANIFEST}.tmp"
    temporary.write_text(json.dumps(manifest, indent=2, sort_keys=True))
    os.replace(temporary, out / MANIFEST)
