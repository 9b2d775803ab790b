"""One saved run shared by the tests of this folder, in all three formats: the stuck vent valve of
car 3, axle 2 (fault-vent-valve-stuck) with 3 cars and the first 10 s only (fast, also under the
sanitizers; the train has not stopped, so the report warns)."""

import json
from importlib.resources import files

import pytest
import yaml
from typer.testing import CliRunner

from railbrake.cli import app

SECONDS = 10.0


@pytest.fixture(scope="session")
def saved_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fault-run")
    spec = yaml.safe_load((files("railbrake") / "data" / "scenarios" / "fault-vent-valve-stuck.yaml").read_text())
    spec["stop"]["max_time"] = f"{SECONDS} s"
    path = folder / "fault-vent-valve-stuck.yaml"
    path.write_text(yaml.safe_dump(spec))
    out = folder / "out"
    result = CliRunner().invoke(app, ["run", str(path), "--cars", "3", "--out", str(out),
                                      "--format", "parquet,csv", "--format", "mf4", "--json"])
    assert result.exit_code == 0, result.output
    return out, json.loads(result.stdout)
