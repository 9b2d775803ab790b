"""`railbrake etcs braking-model` from the command line: the JSON's SUBSET-026 variables with their
codings, bounds and warnings, the OSRD export, the report; a bad reliability file refused before
any run; an adhesion condition outside its validity refused unless forced."""

import json

import pytest

from typer.testing import CliRunner

from railbrake.cli import app
from railbrake.etcs import confidence

RELIABILITY = """schema: railbrake.reliability/1
name: t
source: test
failures:
  - {kind: ep_valve_failed, unit: car, per_demand: 1.0e-4, source: test}
"""

ARGS = ["etcs", "braking-model", "crh380a-8", "--cars", "2", "--speed", "80", "--samples", "4",
        "--rare-samples", "2", "--workers", "1", "--run-budget", "0"]


def test_json_codings_bounds_osrd_export_and_report(tmp_path):
    rel = tmp_path / "rel.yaml"
    rel.write_text(RELIABILITY)
    out = tmp_path / "out"
    # from 80 km/h the Kwet_rst pair runs the EN 15595 condition below its 120 km/h: forced, recorded
    result = CliRunner().invoke(app, ARGS + ["--reliability", str(rel), "--out", str(out), "--json",
                                             "--force-conditions"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    steps = data["A_brake_emergency"]["V_lower_kmh"]
    assert steps == [0.0, 50.0] and len(data["A_brake_emergency"]["A_m_s2"]) == 2
    assert data["initial_speed_kmh"] == pytest.approx(80.0)
    assert [k["M_NVEBCL"] for k in data["Kdry_rst"]] == list(range(10))
    assert data["Kdry_rst"][8]["EBCL"] == "99.999999 %" and data["Kdry_rst"][9]["EBCL"] == "99.9999999 %"
    assert set(data["codings"]) == {"A_brake_emergency", "T_brake_emergency", "Kdry_rst", "Kwet_rst"}
    assert all("SUBSET-026" in c["clause"] for c in data["codings"].values())
    for level in data["Kdry_rst"]:
        assert len(level["value"]) == len(steps) and "code" not in level
        for value, coded, (low, _) in zip(level["value"], level["coded"], level["bound_95"]):
            assert coded <= max(0.0, value - low) + 1e-12 and 0.0 <= coded <= 1.0
            assert abs(coded / confidence.K_STEP - round(coded / confidence.K_STEP)) < 1e-9
    kwet = data["Kwet_rst"]
    assert 0 < kwet["coded"] <= kwet["value"] <= 1 and kwet["reduced_condition"] == "en15595-low"
    assert any(w.startswith("forced: adhesion condition 'en15595-low'") for w in data["warnings"])
    assert any("ep_valve_failed" in w and "no effect on this brake" in w for w in data["warnings"])
    doc = json.loads((out / "osrd-etcs-brake-params.json").read_text())
    (entry,) = doc["supported_signaling_systems"]   # OSRD's current layout, k_dry at M_NVEBCL 9
    assert entry["type"] == "ETCS_LEVEL2" and doc["railbrake"]["M_NVEBCL_of_k_dry"] == 9
    osrd = entry["brake_params"]
    assert osrd["gamma_emergency"]["boundaries"] == [50 / 3.6]
    assert len(osrd["k_dry"]["values"]) == 2 and osrd["k_dry"]["values"] == data["Kdry_rst"][9]["coded"]
    names = [v["name"] for v in json.loads((out / "etcs-train-data.json").read_text())["variables"]]
    assert {"A_brake_service", "T_bs1", "T_bs2", "Kn+", "Kn-", "T_traction_cut_off"} <= set(names)
    assert osrd["t_be"] == data["T_brake_emergency_s"]
    page = (out / "report.html").read_text()
    assert "<svg" in page and "99.9999999 %" in page and "initial speed 80 km/h" in page
    assert "forced: adhesion condition" in page and "no effect on this brake" in page
    # the braking distance grows with the wet-rail reduction and with the level (None: no brake)
    inf = float("inf")
    wet = [inf if d["M_NVAVADH_0"] is None else d["M_NVAVADH_0"] for d in data["emergency_braking_distance_m"]]
    dry = [inf if d["M_NVAVADH_1"] is None else d["M_NVAVADH_1"] for d in data["emergency_braking_distance_m"]]
    assert all(w >= d for w, d in zip(wet, dry)) and dry == sorted(dry) and wet == sorted(wet)


def test_a_bad_reliability_file_is_refused_before_any_run(tmp_path):
    rel = tmp_path / "rel.yaml"
    rel.write_text(RELIABILITY.replace("1.0e-4", "2.0"))
    out = tmp_path / "out"
    result = CliRunner().invoke(app, ARGS + ["--reliability", str(rel), "--out", str(out)])
    assert result.exit_code != 0
    assert f"{rel}, line 5" in result.output and "per_demand = 2.0" in result.output
    assert not (out / "batches").exists()


def test_a_condition_outside_its_validity_is_refused_unless_forced(tmp_path):
    rel = tmp_path / "rel.yaml"
    rel.write_text(RELIABILITY)
    out = tmp_path / "out"
    result = CliRunner().invoke(app, ARGS + ["--reliability", str(rel), "--out", str(out)])
    assert result.exit_code != 0
    assert "en15595-low" in result.output and "outside 120-400 km/h" in result.output
