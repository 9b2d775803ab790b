"""Reduction of the valve designs to the real-time plant's parameters: the static reduction from the
geometry, the EP fit's agreement with the detailed valve, and the packaged reduced parameters being
what the reduction gives."""

import math

import numpy as np
import pytest
import yaml

from railbrake import valves
from railbrake.units import BAR
from railbrake.valves import epv, reduce as R


@pytest.fixture(scope="module")
def fit():
    return R.fit_epv()


def test_static_reduction_from_the_geometry():
    s, e, r = R.static_reduction(), valves.load_epv(), valves.load_relay()
    assert s["ep_area"] == pytest.approx(math.pi * (e["inlet_seat_diameter_mm"] * 1e-3) ** 2 / 4)
    m = r["membrane"]
    x, v = np.array(m["x_mm"]) * 1e-3, np.array(m["volume_cm3"]) * 1e-6
    a_eff = (v[3] - v[1]) / (x[3] - x[1])   # dV/dx at mid-stroke, central difference
    band = m["spring_rate"] * r["inlet_seat_diameter_mm"] * 1e-3 / 4 / a_eff
    assert s["relay_band"] == pytest.approx(band, rel=0.02)
    assert s["valve_delay"] == r["wsp"]["response_delay_s"]
    # the valves' air: the EP feed orifice, the membrane's lag c / k, its swept volume at the stroke
    # d / 4 (between the table's points at 0 and 1.5 mm: about 7.3 cm^3 per mm) and its stops
    assert s["ep_bleed_area"] == pytest.approx(math.pi * (e["pilot_orifice_diameter_mm"] * 1e-3) ** 2 / 4)
    assert s["relay_tau"] == pytest.approx(m["damping"] / m["spring_rate"])
    stroke = r["inlet_seat_diameter_mm"] * 1e-3 / 4
    assert s["relay_sweep"] == pytest.approx(np.interp(stroke, x, v), rel=0.05)
    assert s["relay_travel"] == pytest.approx(m["travel_mm"] * 1e-3 / stroke)


def test_fitted_ep_model_follows_the_detailed_valve(fit):
    det = np.array(list(fit["steps"]["responses"].values()))
    static = R.reduced_steps(fit["steps"], 0.05, fit["static"]["ep_band"], fit["static"]["ep_area"])
    static_rms = np.sqrt(np.mean((static - det) ** 2)) / BAR
    assert fit["rms_bar"] < 0.1 and fit["rms_bar"] < static_rms
    # each response ends where the detailed valve settled (the demand), within the band's balance
    assert np.max(np.abs(fit["reduced"][:, -1] - det[:, -1])) < 0.05 * BAR
    assert 0.005 < fit["ep_tau"] < 0.5


def test_packaged_reduced_parameters_are_the_reductions(fit):
    packaged = yaml.safe_load((valves.params.DATA / "reduced.yaml").read_text())["plant"]
    derived = {**R.static_reduction(), "ep_tau": fit["ep_tau"], "ep_band": fit["ep_band"], "ep_area": fit["ep_area"]}
    for key, value in packaged.items():
        assert value == pytest.approx(derived[key], rel=0.01), key


def test_fragment_names_the_train_file_keys(fit):
    text = R.fragment({"params": {**R.static_reduction(), "ep_tau": fit["ep_tau"], "ep_band": fit["ep_band"],
                                  "ep_area": fit["ep_area"]}, "fit": fit})
    doc = yaml.safe_load(text)
    assert doc["ep_valve"]["response_s"] == pytest.approx(fit["ep_tau"], rel=1e-3)
    assert doc["wsp_valves"]["hold_area_mm2"] == pytest.approx(15.0, rel=1e-3)


def test_relay_reduction_settles_where_the_detailed_relay_does():
    """The statically reduced relay (isothermal output chamber) settles at the detailed relay's
    output pressure; while filling it lags the adiabatic detailed chamber (the heat of compression
    raises its pressure faster), which the check reports rather than hides."""
    check = R.relay_check()
    assert check["final_bar"] < 0.01
    assert 0.0 < check["rms_bar"] < 0.2 and check["max_bar"] < 1.5
    wide = R.relay_check(params={**R.static_reduction(), "relay_supply_area": 1.35 * R.static_reduction()[
        "relay_supply_area"]})
    assert wide["rms_bar"] < check["rms_bar"]   # a wider effective port makes up for the isothermal fill


@pytest.mark.parametrize("supply_bar", [3.0, 4.0])
def test_supply_margin_is_where_the_detailed_ep_valve_stops_below_its_supply(supply_bar):
    """With the supply below what the rated current asks for, the detailed EP valve (its nozzle
    chamber closed onto the supply) holds its output at the supply less the reduced margin: the
    piston's preload over its area, not fitted."""
    res = epv.epv_step({"supply_bar": supply_bar}, current=1.0, t_end=3.0)
    output = res.elements["control"].p[-1] - res.elements["supply"].p[-1]
    margin = R.static_reduction()["ep_supply_margin"]
    assert 0.2 * BAR < margin < 0.3 * BAR   # 8 N over a 20 mm piston
    assert -output == pytest.approx(margin, abs=0.01 * BAR)


def test_valves_air_over_wsp_cycles_approaches_the_detailed_cars():
    """Over WSP cycles one car of the plant lets out most of the air the detailed car's EP and relay
    valves do (feed-orifice bleed, refilling and exhausting the control chamber the relay membrane
    sweeps), where without those terms it let out almost none; the cylinders vent alike."""
    params = {**yaml.safe_load((valves.params.DATA / "reduced.yaml").read_text())["plant"], **R.static_reduction()}
    bare = {**params, "ep_bleed_area": 0.0, "relay_tau": 0.0, "relay_sweep": 0.0}
    for row in R.air_check(params):
        det, rt = row["detailed_g"], row["plant_g"]
        assert det["bleed"] > 0 and det["ep_exhaust"] > 0 and det["relay_exhaust"] > 0
        assert 0.5 * det["valves"] < rt["valves"] < det["valves"]
        assert rt["cylinder_vents"] == pytest.approx(det["cylinder_vents"], rel=0.03)
        assert R.plant_valve_air(bare, row["cycle_s"])["valves"] < 0.01 * det["valves"]
