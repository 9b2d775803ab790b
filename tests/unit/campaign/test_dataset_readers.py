"""A campaign's dataset folder (DIR/runs) reads as one table in the Parquet readers people use,
with no glob trick: it holds the parts alone (the manifests lie in DIR), and every column names its
unit in its field metadata. polars and duckdb come with the test extra (pyproject.toml), not with
railbrake."""

import json

import pyarrow.dataset as ds
import pytest

from railbrake.campaign import dataset
from railbrake.campaign.factors import Factor

FACTORS = [Factor("initial_speed", "quantity", "m/s"), Factor("adhesion_case", "case", "")]
KPIS = ["stopping_distance_m", "wheel_lock_events", "stopped", "worst_axle", "max_slip", "equivalent_response_time_s"]


def _rows(start: int, n: int) -> list[dict]:
    return [{"key": f"k{i:04d}", "run": i, "point": i, "replicate": 0, "seed": 7, "block": "", "sample": -1,
             "factors": {"initial_speed": 50.0 + i, "adhesion_case": "dry"},
             "kpis": {"stopping_distance_m": 100.0 * (i + 1), "wheel_lock_events": 0, "stopped": True,
                      "worst_axle": "c1a1", "max_slip": 0.01, "equivalent_response_time_s": 1.5},
             "status": "ok", "error": None, "wall_time_s": 0.1} for i in range(start, start + n)]


@pytest.fixture
def folder(tmp_path):
    sch = dataset.schema(FACTORS, KPIS, {"name": "t"}, {"worst_axle": "string"})
    for start in (0, 2, 4):
        dataset.write_batch(tmp_path, _rows(start, 2), sch)
    dataset.record_study_keys(tmp_path, [f"k{i:04d}" for i in range(6)])
    return tmp_path


def test_the_runs_folder_holds_the_parts_alone(folder):
    assert {p.suffix for p in (folder / "runs").iterdir()} == {".parquet"}
    assert (folder / dataset.PARTS).is_file() and (folder / dataset.KEYS).is_file()
    assert dataset.read(folder).num_rows == 6


def test_pyarrow_and_pandas_read_the_folder_as_one_table(folder):
    import pandas as pd
    table = ds.dataset(folder / "runs", format="parquet").to_table()
    assert sorted(table.column("key").to_pylist()) == [f"k{i:04d}" for i in range(6)]
    frame = pd.read_parquet(folder / "runs")
    assert len(frame) == 6 and frame["stopping_distance_m"].sum() == pytest.approx(2100.0)


def test_every_column_has_its_unit(folder):
    schema = ds.dataset(folder / "runs", format="parquet").schema
    units = {f.name: (f.metadata or {}).get(b"unit") for f in schema}
    assert None not in units.values(), [n for n, u in units.items() if u is None]
    units = {n: u.decode() for n, u in units.items()}
    assert units["initial_speed"] == "m/s" and units["stopping_distance_m"] == "m" and units["wall_time_s"] == "s"
    assert units["equivalent_response_time_s"] == "s" and units["max_slip"] == "1"
    assert units["wheel_lock_events"] == "1" and units["run"] == "1"         # counts
    assert units["key"] == units["worst_axle"] == units["adhesion_case"] == ""  # text
    assert json.loads(schema.metadata[b"railbrake.units"]) == units


def test_a_dataset_with_its_manifests_in_runs_has_them_moved_out(folder):
    for name in (dataset.PARTS, dataset.KEYS):   # as written before they moved
        (folder / name).rename(folder / "runs" / name)
    assert dataset.read(folder).num_rows == 6
    assert {p.suffix for p in (folder / "runs").iterdir()} == {".parquet"}


def test_polars_scans_the_folder(folder):
    import polars as pl
    assert pl.scan_parquet(folder / "runs").collect().height == 6


def test_duckdb_reads_the_folder(folder):
    import duckdb
    assert duckdb.sql(f"select count(*) from read_parquet('{folder}/runs/**/*.parquet')").fetchall()[0][0] == 6
