"""Campaign datasets vouch for themselves (issue 32, part 6): parts.jsonl lists each part's SHA-256
and run keys; resume and report verify every part against it and name the file that fails (an
altered KPI, a copied part, a foreign part, a damaged part, a missing one); the report counts only
the study's keys; a study killed between a part's line and its rename is completed on resume.
The datasets here are written by dataset.write_batch itself (no simulation needed)."""

import shutil
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from railbrake.campaign import dataset, execute, study
from railbrake.campaign.factors import Factor
from railbrake.cli import app
from railbrake.errors import InputError

SMALL = Path(__file__).parent / "data" / "small.yaml"
FACTORS = [Factor("initial_speed", "quantity", "m/s")]
KPIS = ["stopping_distance_m"]


def _rows(prefix: str, n: int, start: int = 0) -> list[dict]:
    return [{"key": f"{prefix}{i:04d}", "run": i, "point": i, "replicate": 0, "seed": 7, "block": "", "sample": -1,
             "factors": {"initial_speed": 10.0 + i}, "kpis": {"stopping_distance_m": 100.0 * (i + 1)},
             "status": "ok", "error": None, "wall_time_s": 0.1} for i in range(start, start + n)]


def _dataset(folder: Path, prefix: str = "k") -> list[Path]:
    """Two parts of two runs each, and the study files a report reads."""
    sch = dataset.schema(FACTORS, KPIS, {"name": "t"})
    parts = [dataset.write_batch(folder, _rows(prefix, 2, start), sch) for start in (0, 2)]
    shutil.copy(SMALL, folder / "study.yaml")
    return parts


def _refused(folder: Path, name: str, reason: str) -> None:
    """Resume (existing_keys), the reader and `campaign report` all refuse, naming the file."""
    where = str(folder / "runs" / name)
    for check in (lambda: dataset.existing_keys(folder), lambda: dataset.read(folder)):
        with pytest.raises(InputError) as info:
            check()
        assert str(info.value).startswith(where) and reason in str(info.value)
    out = CliRunner().invoke(app, ["campaign", "report", str(folder)])
    assert out.exit_code == 2 and f"error: {where}" in out.output, out.output


def test_a_whole_dataset_verifies_and_reads_back(tmp_path):
    parts = _dataset(tmp_path)
    assert set(dataset.verify(tmp_path)) == {p.name for p in parts}
    table = dataset.read(tmp_path)
    assert table.column("key").to_pylist() == ["k0000", "k0001", "k0002", "k0003"]
    assert table.column("stopping_distance_m").to_pylist() == [100.0, 200.0, 300.0, 400.0]


def test_an_altered_kpi_in_a_valid_part_is_detected_by_name(tmp_path):
    part = _dataset(tmp_path)[1]
    table = pq.read_table(part)
    altered = table.set_column(table.schema.get_field_index("stopping_distance_m"), "stopping_distance_m",
                               pa.array([1.0, 2.0]))
    pq.write_table(altered, part)   # still a valid Parquet part, of the same keys
    _refused(tmp_path, part.name, "SHA-256 differs")


def test_a_copied_part_is_detected_by_name(tmp_path):
    part = _dataset(tmp_path)[0]
    copy = part.with_name("part-00000000000000000000.parquet")
    shutil.copy(part, copy)
    _refused(tmp_path, copy.name, "not in")


def test_a_foreign_part_is_detected_by_name(tmp_path):
    other = tmp_path / "other"
    foreign = _dataset(other, prefix="z")[0]
    mine = tmp_path / "mine"
    _dataset(mine)
    shutil.copy(foreign, mine / "runs" / foreign.name)   # its own name, another study's keys
    _refused(mine, foreign.name, "another dataset")


def test_a_damaged_part_is_detected_by_name(tmp_path):
    part = _dataset(tmp_path)[0]
    data = part.read_bytes()
    part.write_bytes(data[: len(data) // 2])
    _refused(tmp_path, part.name, "SHA-256 differs")


def test_a_missing_part_is_named(tmp_path):
    part = _dataset(tmp_path)[1]
    part.unlink()
    _refused(tmp_path, part.name, "listed in")


def test_resume_verifies_before_any_run(tmp_path):
    part = _dataset(tmp_path)[0]
    shutil.copy(part, part.with_name("part-11111111111111111111.parquet"))
    with pytest.raises(InputError, match=r"part-11111111111111111111.parquet: not in"):
        execute.run_study(study.load(SMALL), tmp_path, scheduler="tcp://127.0.0.1:9", connect_timeout=0.1)


def test_the_report_counts_only_the_study_keys(tmp_path):
    _dataset(tmp_path)
    dataset.record_study_keys(tmp_path, ["k0001", "k0002", "k0009"])   # the study as planned now
    assert dataset.read(tmp_path).column("key").to_pylist() == ["k0001", "k0002"]


def test_a_study_killed_between_a_parts_line_and_its_rename_is_completed_on_resume(tmp_path, monkeypatch):
    _dataset(tmp_path)
    sch = dataset.schema(FACTORS, KPIS, {"name": "t"})

    def killed(source, target):
        raise KeyboardInterrupt   # the process dies before the rename
    monkeypatch.setattr(dataset.os, "replace", killed)
    with pytest.raises(KeyboardInterrupt):
        dataset.write_batch(tmp_path, _rows("k", 2, 4), sch)
    monkeypatch.undo()
    with pytest.raises(InputError, match="listed in .* but missing"):
        dataset.read(tmp_path)            # the report does not repair
    assert dataset.existing_keys(tmp_path) == {f"k{i:04d}" for i in range(6)}   # resume does
    assert len(dataset.read(tmp_path)) == 6


def test_a_torn_last_line_is_dropped_on_resume_and_refused_by_the_report(tmp_path):
    _dataset(tmp_path)
    manifest = tmp_path / dataset.PARTS
    whole = manifest.read_bytes()
    manifest.write_bytes(whole + b'{"part": "part-1234')   # killed while appending
    with pytest.raises(InputError, match=rf"{manifest}, line 3: damaged"):
        dataset.read(tmp_path)
    assert dataset.existing_keys(tmp_path) == {f"k{i:04d}" for i in range(4)}
    assert manifest.read_bytes() == whole
    manifest.write_bytes(b"garbage\n" + whole)   # damage inside the file: refused even on resume
    with pytest.raises(InputError, match=rf"{manifest}, line 1: damaged"):
        dataset.existing_keys(tmp_path)


def test_a_resume_that_reads_while_a_batch_is_renamed_loses_nothing(tmp_path, monkeypatch):
    """A second process reading the dataset between a part's line and its rename completes the
    rename itself (existing_keys); the writer then finds its part in place and goes on."""
    _dataset(tmp_path)
    sch = dataset.schema(FACTORS, KPIS, {"name": "t"})
    replace = dataset.os.replace

    def reader_first(source, target):
        monkeypatch.setattr(dataset.os, "replace", replace)
        dataset.existing_keys(tmp_path)   # the other process: it renames the part
        replace(source, target)           # now the writer's own rename: its file is gone
    monkeypatch.setattr(dataset.os, "replace", reader_first)
    dataset.write_batch(tmp_path, _rows("k", 2, 4), sch)
    monkeypatch.undo()
    assert dataset.read(tmp_path).column("key").to_pylist() == [f"k{i:04d}" for i in range(6)]
