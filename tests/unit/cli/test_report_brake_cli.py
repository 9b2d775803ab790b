"""`railbrake report brake`: JSON, HTML, the refusal of a bad load case."""

import json

from typer.testing import CliRunner

from railbrake.cli import app

runner = CliRunner()


def test_report_brake_json_and_html(tmp_path):
    out = runner.invoke(app, ["report", "brake", "class387-4", "velaro-8", "--load-case", "crush", "--json",
                              "--out", str(tmp_path / "report")])
    assert out.exit_code == 0, out.output
    data = json.loads(out.stdout)
    slow, fast = data["trains"]
    assert [slow["train"], fast["train"]] == ["class387-4", "velaro-8"]
    assert slow["load_case"] == fast["load_case"] == "crush"
    assert slow["uic"]["brake_percentage"] > 0 and slow["tsi"] == [] and slow["passed"] is None
    assert fast["uic"]["brake_percentage"] is None and len(fast["tsi"]) == 4
    assert fast["passed"] == all(r["passed"] for r in fast["tsi"])
    assert set(data["sources"]) == {"uic544", "en14531", "tsi"}
    assert json.loads((tmp_path / "report" / "brake-calculation.json").read_text()) == data
    page = (tmp_path / "report" / "brake-calculation.html").read_text()
    for text in ("class387-4", "velaro-8", "UIC 544-1", "EN 14531-1", "TSI limit (m)", "5360"):
        assert text in page


def test_report_brake_text_and_forced_lambda():
    out = runner.invoke(app, ["report", "brake", "velaro-8", "--force-lambda"])
    assert out.exit_code == 0, out.output
    assert "velaro-8: from 350 km/h" in out.stdout and "TSI 5360 m" in out.stdout
    assert "outside UIC 544-1's validity" in out.stdout


def test_report_brake_refuses_a_bad_load_case_and_train():
    out = runner.invoke(app, ["report", "brake", "velaro-8", "--load-case", "full"])
    assert out.exit_code == 2
    assert "--load-case = 'full': must be one of tare, normal, crush" in out.output
    out = runner.invoke(app, ["report", "brake", "no-such-train"])
    assert out.exit_code == 2 and "no-such-train" in out.output
