"""One saved run shared by the tests of this folder: `railbrake run fault-vent-valve-stuck --cars 3`
in all three formats (the faulty axle c3a2 exists with 3 cars)."""

import json

import pytest
from typer.testing import CliRunner

from railbrake.cli import app


@pytest.fixture(scope="session")
def saved_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("fault-run")
    result = CliRunner().invoke(app, ["run", "fault-vent-valve-stuck", "--cars", "3", "--out", str(out),
                                      "--format", "parquet,csv", "--format", "mf4", "--json"])
    assert result.exit_code == 0, result.output
    return out, json.loads(result.output)
