"""The validation cases (fast ones) and the runner's handling of bad case folders.

The physics is checked by the cases themselves (validation/<kind>/<id>/): here every
verification case must pass, every case must be well formed and name its source, and a bad
folder must come out as a *broken* case with its reason, never as a pass or a crash.
"""

import json
import re
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from railbrake import _core
from railbrake.cli import app
from railbrake.validation import load_cases, run_cases
from railbrake.validation.report import as_json, to_html, to_markdown

CASES = Path(__file__).resolve().parents[3] / "validation"


@pytest.fixture(scope="module")
def fast_results():
    return run_cases(load_cases(CASES), fast_only=True)


def test_the_cases_cover_every_model_area_with_enough_measurements():
    cases = load_cases(CASES)
    assert len(cases) >= 25
    assert sum(c.kind == "validation" for c in cases) >= 10
    areas = {c.area for c in cases}
    assert {"contact", "adhesion", "pneumatics", "valves", "vehicle", "real-time plant"} <= areas
    for c in cases:
        assert c.source.get("reference"), c.id


def test_every_fast_verification_case_passes_and_none_is_broken(fast_results):
    broken = [(r.id, r.reason) for r in fast_results if r.status == "broken"]
    assert not broken
    failing = [(r.id, r.reason) for r in fast_results if r.kind == "verification" and r.status != "pass"]
    assert not failing


def test_every_failing_case_says_why(fast_results):
    for r in fast_results:
        if r.status == "fail":
            assert "exceeds the tolerance" in r.reason and len(r.reason) > 60, r.id


def test_plant_order_of_convergence_is_first(fast_results):
    order = next(r for r in fast_results if r.id == "plant-order-dt")
    assert order.model[0] == pytest.approx(1.0, abs=0.15)


def _copy_case(tmp_path, kind, case_id, new_id):
    dest = tmp_path / kind / new_id
    shutil.copytree(CASES / kind / case_id, dest)
    return dest


def test_bad_case_folders_are_reported_broken_with_the_reason(tmp_path):
    missing = _copy_case(tmp_path, "verification", "orifice-choked", "missing-reference")
    (missing / "reference.csv").unlink()
    no_unit = _copy_case(tmp_path, "verification", "orifice-choked", "tolerance-without-unit")
    text = (no_unit / "case.yaml").read_text()
    (no_unit / "case.yaml").write_text(re.sub(r"tolerance: \{value: ([^,]+), unit: [^}]+\}", r"tolerance: {value: \1}", text))
    text_cell = _copy_case(tmp_path, "verification", "orifice-choked", "non-numeric-csv")
    csv = (text_cell / "reference.csv").read_text().replace("0.3,", "0.3 bar,")
    (text_cell / "reference.csv").write_text(csv)
    unknown = _copy_case(tmp_path, "verification", "orifice-choked", "unknown-model")
    (unknown / "case.yaml").write_text((unknown / "case.yaml").read_text().replace("function: orifice_flow", "function: nope"))
    (tmp_path / "verification" / "empty-folder-file").mkdir()
    (tmp_path / "verification" / "empty-folder-file" / "notes.txt").write_text("no case.yaml here")

    results = {r.id: r for r in run_cases(load_cases(tmp_path))}
    expected = {"missing-reference": "reference file missing", "tolerance-without-unit": "no unit",
                "non-numeric-csv": "'0.3 bar' is not a number", "unknown-model": "'nope': unknown",
                "empty-folder-file": "case.yaml missing"}
    for case_id, phrase in expected.items():
        assert results[case_id].status == "broken", case_id
        assert phrase in results[case_id].reason, (case_id, results[case_id].reason)
        assert not results[case_id].passed
    report = as_json(list(results.values()))
    assert report["broken"] == len(expected) and report["passed"] == 0


def test_a_model_that_raises_is_broken_not_a_crash(tmp_path):
    case = _copy_case(tmp_path, "validation", "crh380a-stop-300", "no-such-train")
    (case / "case.yaml").write_text((case / "case.yaml").read_text().replace("train: crh380a-8", "train: no-such-train"))
    (result,) = run_cases(load_cases(tmp_path))
    assert result.status == "broken" and "no-such-train" in result.reason


def test_cli_json_lists_the_fields_of_each_case():
    out = CliRunner().invoke(app, ["validate", "--cases", str(CASES), "--case", "orifice-choked", "--json"])
    assert out.exit_code == 0, out.output
    data = json.loads(out.stdout)
    (case,) = data["cases"]
    for key in ("id", "kind", "quantity", "reference", "model", "difference", "tolerance", "passed", "source"):
        assert key in case
    assert data["passed"] == 1 and data["failed"] == 0
    assert re.fullmatch(r"[0-9a-f]{64}", data["build"]["core_build_hash"])


def test_html_report_is_one_file_with_embedded_plots(fast_results, tmp_path):
    html = to_html(fast_results)
    assert html.count("data:image/png;base64,") >= 25
    assert not re.search(r"""(src|href)=['"](https?:|//|file:)""", html)
    assert _core.rb_build_hash().decode() in html
    markdown = to_markdown(fast_results)
    assert "| real-time plant |" in markdown and "## Failing and broken cases" in markdown


def test_unknown_kind_is_a_user_error():
    out = CliRunner().invoke(app, ["validate", "--cases", str(CASES), "--kind", "guesswork"])
    assert out.exit_code == 2 and "must be one of verification, code-to-code, validation" in out.output


def test_a_one_sided_band_bounds_one_side_only(tmp_path):
    """inf in a band's high column (a published 'more than'): any model value above low passes, one
    below fails by its distance to low; inf anywhere else is still refused."""
    case = _copy_case(tmp_path, "validation", "hs-wet-300-scatter", "more-than")
    csv = case / "reference.csv"
    csv.write_text("speed_kmh,front_car,design,car4\n300,0.001,0.0353,inf\n")
    (above,) = run_cases(load_cases(tmp_path))
    assert above.status == "pass" and above.difference == 0.0
    csv.write_text("speed_kmh,front_car,design,car4\n300,0.5,0.5,inf\n")
    (below,) = run_cases(load_cases(tmp_path))
    assert below.status == "fail" and below.difference == pytest.approx(0.5 - below.model[0])   # its tolerance: absolute
    csv.write_text("speed_kmh,front_car,design,car4\n300,0.001,inf,inf\n")
    (refused,) = run_cases(load_cases(tmp_path))
    assert refused.status == "broken" and "only -inf in a band's low column, inf in its high column" in refused.reason
