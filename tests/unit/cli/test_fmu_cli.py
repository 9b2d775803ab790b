"""`railbrake export-fmu` from the command line."""

from fmpy import read_model_description
from fmpy.validation import validate_fmu
from typer.testing import CliRunner

from railbrake.cli import app


def test_export_fmu_writes_a_valid_fmu(tmp_path):
    out = tmp_path / "sub" / "plant.fmu"
    result = CliRunner().invoke(app, ["export-fmu", "service-200-wet", "--fmi", "3", "--cars", "2", "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert "FMI 3.0 co-simulation" in result.output
    assert validate_fmu(str(out)) == []
    names = {v.name for v in read_model_description(str(out)).modelVariables}
    assert {"wheel_speed_c2a4", "cylinder_c2a4", "supply_c2", "pressure_demand_c2", "hold_c2a4"} <= names
    assert "supply_c3" not in names


def test_export_fmu_rejects_bad_options(tmp_path):
    result = CliRunner().invoke(app, ["export-fmu", "--fmi", "1", "-o", str(tmp_path / "x.fmu")])
    assert result.exit_code == 2 and "FMI version '1': must be 2 or 3" in result.output
    result = CliRunner().invoke(app, ["export-fmu", "--cars", "17", "-o", str(tmp_path / "x.fmu")])
    assert result.exit_code == 2 and "cars = 17" in result.output
    assert not (tmp_path / "x.fmu").exists()
    for option, value, words in (("--platforms", "linux64,win32", "'win32' is not a platform"),
                                 ("--platforms", "win64,win64", "named twice"),
                                 ("--model-identifier", "8cars", "must be a C identifier")):
        result = CliRunner().invoke(app, ["export-fmu", option, value, "-o", str(tmp_path / "x.fmu")])
        assert result.exit_code == 2 and words in result.output, result.output
    assert not (tmp_path / "x.fmu").exists()
