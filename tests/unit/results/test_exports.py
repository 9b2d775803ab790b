"""Exports: Parquet, CSV and MDF4 of one run hold the same channels and the same samples to the
last bit, with the same units; the metadata carry the provenance."""

import json
import shutil

import numpy as np
import pyarrow.parquet as pq

from railbrake import _core
from railbrake.results import files


def _bits(x):
    return np.asarray(x, dtype=np.float64).view(np.uint64)


def test_csv_and_mdf4_hold_the_parquet_samples_bit_for_bit(saved_run):
    out, _ = saved_run
    parquet = files.load(out / "timeseries.parquet")
    for other in (files.load(out / "timeseries.csv"), files.load(out / "timeseries.mf4")):
        assert list(other.outputs) == list(parquet.outputs)
        for name, samples in parquet.outputs.items():
            assert np.array_equal(_bits(other.outputs[name]), _bits(samples)), name
    mdf = files.load(out / "timeseries.mf4")
    assert {n: mdf.units[n] for n in mdf.units if n != "time"} == \
           {n: u for n, u in parquet.units.items() if n != "time"}
    assert parquet.units["cylinder_c3a2"] == "Pa" and parquet.units["speed"] == "m/s"


def test_the_csv_is_plain_text_with_repr_exact_floats(saved_run):
    out, _ = saved_run
    header, first = (out / "timeseries.csv").read_text().split("\n")[:2]
    table = pq.read_table(out / "timeseries.parquet")
    assert header.split(",") == table.column_names
    assert first.split(",") == [repr(table.column(n)[0].as_py()) for n in table.column_names]


def test_the_csv_has_its_units_beside_it(saved_run):
    """timeseries_units.csv: one `channel,unit` line per column of the CSV, the units of the
    Parquet fields; loading the CSV alone (no run.json) gives them back."""
    out, _ = saved_run
    lines = (out / "timeseries_units.csv").read_text().splitlines()
    table = pq.read_table(out / "timeseries.parquet")
    assert lines[0] == "channel,unit"
    assert [line.split(",")[0] for line in lines[1:]] == (out / "timeseries.csv").read_text().split("\n")[0].split(",")
    assert dict(line.split(",") for line in lines[1:]) == {f.name: f.metadata[b"unit"].decode() for f in table.schema}
    from railbrake.results.files import _read_csv
    assert _read_csv(out / "timeseries.csv")[1]["cylinder_c3a2"] == "Pa"


def test_parquet_and_mdf4_metadata_carry_the_provenance_and_kpis(saved_run):
    out, kpis = saved_run
    meta = pq.read_table(out / "timeseries.parquet").schema.metadata
    run = json.loads(meta[b"railbrake"])
    assert json.loads(meta[b"kpis"]) == kpis
    prov = run["provenance"]
    assert prov["core_build_hash"] == _core.rb_build_hash().decode()
    assert prov["command_line"].startswith("railbrake run ") and "fault-vent-valve-stuck.yaml --cars 3" in prov["command_line"]
    mdf = files.load(out / "timeseries.mf4")
    assert mdf.meta["provenance"] == prov and mdf.kpis == kpis


def test_the_mdf4_and_parquet_files_alone_carry_the_provenance_and_kpis(saved_run, tmp_path):
    """Without run.json and kpis.json beside them (a file sent on its own): read from each file's
    own metadata, the MDF4 header comment as asammdf stores it (XML around the JSON)."""
    out, kpis = saved_run
    run = json.loads((out / "run.json").read_text())["meta"]
    for name in ("timeseries.mf4", "timeseries.parquet"):
        alone = tmp_path / name
        shutil.copy(out / name, alone)
        record = files.load(alone)
        assert record.kpis == kpis, name
        assert record.meta["provenance"] == run["provenance"], name
        assert record.meta["faults"] == run["faults"] and record.kind == "MIL", name
    assert run["faults"] == [{"type": "vent_stuck_open", "car": 3, "axle": 2, "start": 2.0}]
