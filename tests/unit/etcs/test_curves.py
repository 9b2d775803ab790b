"""The service-brake train data, the OSRD export and the SUBSET-026 braking curves of every preset
train (1 car from 80 km/h, no scatter: a few whole runs each). The EBD is checked against the
analytic integration of the A_brake_safe step function; the other curves against the order and
the margins the specification gives; the export against OSRD's EtcsBrakeParams rules."""

import json
import math

import pytest
from typer.testing import CliRunner

from railbrake import jsonio
from railbrake.cli import app
from railbrake.etcs import curves, export, model, national, osrd, service
from railbrake.units import KMH
from railbrake.vehicle import preset_names

SPEED = 80.0
RELIABILITY = """schema: railbrake.reliability/1
name: t
source: test
failures:
  - {kind: ep_valve_failed, unit: car, per_demand: 1.0e-4, source: test}
"""
TRAINS = preset_names()


@pytest.fixture(scope="module")
def reliability(tmp_path_factory):
    path = tmp_path_factory.mktemp("etcs") / "rel.yaml"
    path.write_text(RELIABILITY)
    return path


@pytest.fixture(scope="module")
def data(reliability):
    """Per preset train: its braking model's JSON and its service data."""
    out = {}
    for train in TRAINS:
        m = export.to_json(model.braking_model(model.spec(train, reliability, None, 1, SPEED, force_conditions=True)))
        m = json.loads(jsonio.dumps(m))   # as the CLI writes and reads it
        out[train] = (m, service.service_data(m))
    return out


def test_service_data_is_sound(data):
    for train, (m, s) in data.items():
        assert s["V_lower_kmh"] == m["A_brake_emergency"]["V_lower_kmh"]
        # full service brakes less than emergency, normal service less than full service
        for a_e, a_s, a_n in zip(m["A_brake_emergency"]["A_m_s2"], s["A_brake_service"], s["A_brake_normal_service"]):
            assert 0.0 < a_n < a_s <= a_e * 1.001, train
        assert s["T_bs1_s"] == s["T_bs2_s"] == s["T_brake_service_s"] > 0.0
        # Kn = g M / (M + M_rot): below g, M_rot a few per cent of M
        assert s["Kn_plus_m_s2"] == pytest.approx(9.80665 / (1.0 + s["M_rotating_nom_percent"] / 100.0), rel=1e-12)
        assert 1.0 < s["M_rotating_nom_percent"] < 15.0
        assert s["T_traction_cut_off_s"] > 0.0


def test_osrd_export_meets_osrd_rules_for_every_preset(data):
    for train, (m, s) in data.items():
        for layout in osrd.LAYOUTS:
            doc = json.loads(jsonio.dumps(osrd.document(m, s, layout=layout)))
            params = osrd.params_of(doc)
            assert osrd.check(params, SPEED * KMH) == [], train
            assert set(params) == set(osrd.FIELDS) and len(params) == 11
        # k_dry at M_NVEBCL 9 by default (OSRD's national default), boundaries gamma_emergency's
        assert doc["railbrake"]["M_NVEBCL_of_k_dry"] == 9
        assert params["k_dry"]["values"] == [min(k, 1.0) for k in m["Kdry_rst"][9]["coded"]]
        assert params["k_dry"]["boundaries"] == params["gamma_emergency"]["boundaries"] == \
            [v * KMH for v in m["A_brake_emergency"]["V_lower_kmh"][1:]]
        assert params["t_be"] == m["T_brake_emergency_s"]


def test_osrd_rules_catch_what_osrd_refuses(data):
    m, s = data[TRAINS[0]]
    good = osrd.brake_params(m, s)[0]

    def broken(**change):
        p = json.loads(json.dumps(good))
        p.update(change)
        return osrd.check(p)

    assert any("unknown field" in e for e in broken(k_extra=1.0))
    p = dict(good)
    del p["t_bs1"]
    assert osrd.check(p) == ["missing field t_bs1"]
    assert broken(k_dry={"boundaries": [], "values": [0.7]})           # not gamma_emergency's boundaries
    assert broken(k_wet={**good["k_wet"], "values": [1.2] * len(good["k_wet"]["values"])})
    assert broken(k_n_pos={**good["k_n_pos"], "values": [11.0] * len(good["k_n_pos"]["values"])})
    assert broken(gamma_service={"boundaries": [5.0, 4.0], "values": [1.0, 1.0, 1.0]})
    assert broken(t_be=-1.0)


def _analytic_ebd(m: dict, v: float, level: int, avadh: float) -> float:
    """Distance (m) from v (m/s) to standstill at A_brake_safe of each speed step, summed step by step."""
    lower = [x * KMH for x in m["A_brake_emergency"]["V_lower_kmh"]]
    upper = lower[1:] + [math.inf]
    kwet = m["Kwet_rst"]["coded"]
    total = 0.0
    for lo, hi, a, k in zip(lower, upper, m["A_brake_emergency"]["A_m_s2"], m["Kdry_rst"][level]["coded"]):
        if v > lo:
            total += (min(v, hi) ** 2 - lo ** 2) / (2.0 * a * k * (kwet + avadh * (1.0 - kwet)))
    return total


def test_ebd_is_the_integral_of_the_safe_deceleration_on_flat_10km(data):
    track, nv = national.load_track("flat-10km"), national.load_national()
    assert nv.M_NVEBCL == 9 and nv.M_NVAVADH == 0.0
    for train, (m, s) in data.items():
        r = curves.compute(m, s, track, nv)
        assert r["svl_m"] == 10000.0 and r["eoa_m"] == 10000.0
        for x, v_kmh in r["curves"]["EBD"]:
            if v_kmh > 1.0:
                expected = _analytic_ebd(m, v_kmh * KMH, 9, 0.0)
                assert r["svl_m"] - x == pytest.approx(expected, rel=0.005), (train, v_kmh)


def test_curves_lie_in_the_specifications_order(data):
    nv = national.load_national()
    for track_name in ("flat-10km", "descent-10km"):
        track = national.load_track(track_name)
        for train, (m, s) in data.items():
            r = curves.compute(m, s, track, nv)
            c = {n: dict((round(v, 9), x) for x, v in pts) for n, pts in r["curves"].items()}
            assert set(curves.NAMES) <= set(c)
            t_be = m["T_brake_emergency_s"]
            for v_kmh, ebd in c["EBD"].items():
                if v_kmh <= 0.0:
                    continue
                v = v_kmh * KMH
                sbi = min(c["SBI1"][v_kmh], c["SBI2"][v_kmh])
                assert ebd - c["EBI"][v_kmh] >= v * t_be - 1e-9, (train, track_name, v_kmh)
                assert c["I"][v_kmh] < c["P"][v_kmh] < c["W"][v_kmh] < sbi <= c["SBI2"][v_kmh] < c["EBI"][v_kmh], \
                    (train, track_name, v_kmh)
                assert c["SBI1"][v_kmh] < c["SBD"][v_kmh] <= track.eoa_m


def test_cli_curves_from_a_braking_model_folder(data, tmp_path):
    m, s = data[TRAINS[0]]
    folder = tmp_path / "model"
    folder.mkdir()
    (folder / "braking-model.json").write_text(jsonio.dumps(m))
    (folder / "service-brake.json").write_text(jsonio.dumps(s))
    out = tmp_path / "curves"
    result = CliRunner().invoke(app, ["etcs", "curves", str(folder), "--track", "flat-10km", "--json", "--out", str(out)])
    assert result.exit_code == 0, result.output
    r = json.loads(result.stdout)
    assert set(curves.NAMES) <= set(r["curves"]) and r["eoa_m"] == r["svl_m"] == 10000.0
    assert r["national_values"]["M_NVEBCL"] == 9 and r["national_values"]["source"]
    assert all(len(p) == 2 for p in r["curves"]["EBD"])
    assert (out / "curves.html").read_text().startswith("<!doctype html>") and (out / "curves.png").stat().st_size > 0


def test_a_track_whose_svl_is_before_its_eoa_is_refused(tmp_path):
    path = tmp_path / "t.yaml"
    path.write_text("schema: railbrake.etcs-track/1\nname: t\nsource: test\nlength_m: 1000.0\neoa_m: 900.0\n"
                    "svl_m: 800.0\ngradients: [{from_m: 0.0, permille: 0.0}]\n")
    with pytest.raises(Exception, match="eoa_m <= svl_m"):
        national.load_track(path)


def test_supervision_limits_are_the_specifications_time_shifts(data):
    """W, P, I from the most restrictive SBI by V T_warning, V T_driver, V T_indication; SBI1 and
    SBI2 from SBD and EBI by V T_bs1, V T_bs2 (SUBSET-026 3.13.9.3.3-6, A.3.1 fixed values)."""
    nv = national.load_national()
    m, s = data[TRAINS[0]]
    r = curves.compute(m, s, national.load_track("descent-10km"), nv)
    t = r["times_s"]
    assert t["T_indication"] == pytest.approx(max(0.8 * s["T_bs_s"], 5.0) + 4.0)
    c = {n: {v: x for x, v in pts} for n, pts in r["curves"].items()}
    for v_kmh, ebi in c["EBI"].items():
        v = v_kmh * KMH
        sbi = min(c["SBI1"][v_kmh], c["SBI2"][v_kmh])
        assert c["SBI2"][v_kmh] == pytest.approx(ebi - v * t["T_bs2"], abs=1e-9)
        assert c["SBI1"][v_kmh] == pytest.approx(c["SBD"][v_kmh] - v * t["T_bs1"], abs=1e-9)
        assert c["W"][v_kmh] == pytest.approx(sbi - v * 2.0, abs=1e-9)
        assert c["P"][v_kmh] == pytest.approx(sbi - v * 4.0, abs=1e-9)
        assert c["I"][v_kmh] == pytest.approx(c["P"][v_kmh] - v * t["T_indication"], abs=1e-9)


def test_guidance_caps_the_permitted_speed_when_the_nation_permits_it(data, tmp_path):
    text = national._path("national", "default").read_text().replace("Q_NVGUIPERM: false", "Q_NVGUIPERM: true")
    path = tmp_path / "nv.yaml"
    path.write_text(text)
    m, s = data[TRAINS[0]]
    track = national.load_track("flat-10km")
    plain = curves.compute(m, s, track, national.load_national())
    guided = curves.compute(m, s, track, national.load_national(path))
    assert "GUI" in guided["curves"] and "GUI" not in plain["curves"]
    for (xp, v), (xg, _), (xgui, _) in zip(plain["curves"]["P"], guided["curves"]["P"], guided["curves"]["GUI"]):
        assert xg == pytest.approx(min(xp, xgui), abs=1e-9)


def test_a_bad_national_value_is_refused_with_its_file_and_key(tmp_path):
    text = national._path("national", "default").read_text().replace("M_NVEBCL: 9", "M_NVEBCL: 12")
    path = tmp_path / "nv.yaml"
    path.write_text(text)
    with pytest.raises(Exception, match=r"M_NVEBCL") as info:
        national.load_national(path)
    assert str(path) in str(info.value)


@pytest.mark.parametrize("doc", [{}, {"etcs_brake_params": None},
                                 {"supported_signaling_systems": [{"type": "ETCS_LEVEL2"}]},
                                 {"supported_signaling_systems": [{"type": "BAL", "brake_params": {}}]}])
def test_an_osrd_file_without_brake_params_is_refused_with_its_name(doc):
    from railbrake.errors import InputError
    with pytest.raises(InputError, match=r"stock\.json: no etcs_brake_params .* ETCS_LEVEL2 with a brake_params"):
        osrd.params_of(doc, "stock.json")
