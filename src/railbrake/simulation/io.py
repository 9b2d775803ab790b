"""Writing a simulation result: time series as Parquet (SI units in the metadata), KPIs as JSON."""

from __future__ import annotations

import json
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from railbrake import jsonio


def write_parquet(result, path: Path) -> None:
    fields = [pa.field(name, pa.float64(), metadata={"unit": result.units[name]}) for name in result.outputs]
    table = pa.table({name: result.outputs[name] for name in result.outputs},
                     schema=pa.schema(fields, metadata={
                         "scenario": result.scenario, "cars": str(result.cars), "wsp": str(result.wsp),
                         "units": json.dumps(result.units)}))
    pq.write_table(table, path)


def write_kpis(result, path: Path) -> None:
    path.write_text(jsonio.dumps(result.kpis, indent=2) + "\n")   # NaN -> null: kpis.json stays JSON
