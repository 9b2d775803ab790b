"""Adhesion presets against their published targets (sources in each preset file, docs/references.md)."""

import sys
import warnings

import numpy as np
import pytest

from railbrake.adhesion import (
    AdhesionRangeWarning,
    car_axles,
    conditions,
    load_condition,
    peak_adhesion,
    preset_names,
)
from railbrake.contact import PolachParams, default_contact, polach_coefficient
from railbrake.errors import InputError
from railbrake.units import kmh_to_ms

conditions_module = sys.modules["railbrake.adhesion.conditions"]  # the module, not the function

PRESETS = ["dry-high", "dry-medium", "wet", "hs-wet", "heavy-rain", "oil-film", "leaves",
           "leaves-full-scale",
           "en15595-low"]


def car_mean_peak(condition, car, v_kmh):
    return np.mean([peak_adhesion(condition, kmh_to_ms(v_kmh), axle=a).coefficient for a in car_axles(car)])


def test_all_presets_exist_and_name_a_source():
    assert sorted(preset_names()) == sorted(PRESETS)
    for condition in conditions():
        assert len(condition.source) > 40
        assert condition.targets, f"{condition.name} documents no target"


def test_default_wheelset_is_documented_one():
    contact = default_contact()
    assert contact.normal_force == pytest.approx(17e3 * 9.80665 / 2)
    assert contact.a > contact.b  # wheel radius 0.46 m > rail head radius 0.3 m


def test_dry_preset_peaks_near_044_at_4_percent_at_30_kmh():
    """Polach (2005) dry set on the default wheelset."""
    peak = peak_adhesion("dry-high", kmh_to_ms(30))
    assert peak.coefficient == pytest.approx(0.44, abs=0.01)
    assert peak.creep == pytest.approx(0.04, abs=0.005)


def test_wet_preset_peaks_near_018_at_300_kmh():
    assert peak_adhesion("wet", kmh_to_ms(300)).coefficient == pytest.approx(0.18, abs=0.01)


@pytest.mark.parametrize("name", PRESETS)
def test_documented_targets_hold(name):
    condition = load_condition(name)
    for target in condition.targets:
        if target["car"]:
            value = car_mean_peak(condition, target["car"], target["speed_kmh"])
        else:
            peak = peak_adhesion(condition, kmh_to_ms(target["speed_kmh"]))
            value = peak.coefficient
            if target["peak_creep"]:
                assert peak.creep == pytest.approx(target["peak_creep"], rel=0.15)
        assert value == pytest.approx(target["peak"], rel=target["rel_tolerance"])


@pytest.mark.parametrize("name", PRESETS)
def test_peaks_fall_with_speed(name):
    peaks = [peak_adhesion(name, kmh_to_ms(v), axle=20).coefficient for v in (10, 50, 100, 200, 300, 350)]
    assert np.all(np.diff(peaks) < 0)


@pytest.mark.parametrize("name", PRESETS)
def test_locked_wheel_brakes_less_than_the_peak(name):
    """What wheel-slide protection relies on: past the peak the creep force falls."""
    contact = default_contact()
    for axle in (0, 12, 60):
        params = load_condition(name).params_at_axle(axle)
        for v_kmh in (100, 200, 300):
            peak = peak_adhesion(name, kmh_to_ms(v_kmh), axle=axle).coefficient
            locked = -polach_coefficient(-1.0, kmh_to_ms(v_kmh), contact.normal_force, contact, params)
            assert locked < 0.9 * peak


def test_heavy_rain_conditioning_along_the_train():
    """Shinkansen heavy rain at 300 km/h: ~0.02 on the front car, ~0.05 on car 4 [P]."""
    assert car_mean_peak("heavy-rain", 1, 300) == pytest.approx(0.02, rel=0.2)
    assert car_mean_peak("heavy-rain", 4, 300) == pytest.approx(0.05, rel=0.2)
    # Parametric in the axle: adhesion recovers with each axle passed, for any train length.
    peaks = [peak_adhesion("heavy-rain", kmh_to_ms(300), axle=a).coefficient for a in range(0, 128, 4)]
    assert np.all(np.diff(peaks) >= 0)
    assert peaks[-1] == pytest.approx(peaks[-2], rel=1e-3)  # saturates far back


@pytest.mark.parametrize("v_kmh", [100, 200, 300])
def test_heavy_rain_train_mean_near_shinkansen_design_curve(v_kmh):
    """8-car mean within 30 % of 13.6/(v+85) [P]; the file states the deviation per speed."""
    train = np.mean([car_mean_peak("heavy-rain", car, v_kmh) for car in range(1, 9)])
    assert train == pytest.approx(13.6 / (v_kmh + 85), rel=0.3)


def test_user_parameters_accepted_wherever_a_condition_is():
    params = {"mu0": 0.3, "A": 0.4, "B": 0.2, "kA": 0.3, "kS": 0.1}
    from_dict = peak_adhesion(params, 50.0)
    from_params = peak_adhesion(PolachParams(**params), 50.0)
    from_preset = peak_adhesion("wet", 50.0)
    assert from_dict == from_params == from_preset


def test_user_condition_file(tmp_path):
    text = (tmp_path / "c.yaml")
    text.write_text("schema: railbrake.adhesion/1\nname: mine\ntitle: Mine\nsource: measured on site\n"
                    "params: {mu0: 0.2, A: 0.4, B: 0.2, kA: 0.3, kS: 0.1}\n")
    assert load_condition(str(text)).params.mu0 == 0.2
    text.write_text("schema: railbrake.adhesion/1\nname: mine\ntitle: Mine\nsource: x\n"
                    "params: {mu0: 0.2, A: 0.4, B: 0.2, kA: 0.3, kS: 0.1, kZ: 1}\n")
    with pytest.raises(InputError, match="params.kZ"):
        load_condition(str(text))


def test_unknown_condition_and_bad_axle_are_named():
    with pytest.raises(InputError, match="condition = 'sand'"):
        peak_adhesion("sand", 10.0)
    with pytest.raises(InputError, match="axle = -1"):
        peak_adhesion("wet", 10.0, axle=-1)
    with pytest.raises(InputError, match="missing"):
        peak_adhesion({"mu0": 0.3}, 10.0)


def test_every_preset_declares_its_range_of_validity():
    for condition in conditions():
        valid = condition.validity
        assert valid is not None, condition.name
        assert 0 <= valid.speed_min_kmh < valid.speed_max_kmh <= 400
        assert valid.conditions and valid.source


def _peaks_warnings(name, speeds_kmh):
    conditions_module._warned.discard(name)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for v in speeds_kmh:
            peak_adhesion(name, kmh_to_ms(v))
    return [w for w in caught if issubclass(w.category, AdhesionRangeWarning)]


def test_wet_preset_warns_once_above_its_speed_range():
    caught = _peaks_warnings("wet", [300, 250, 300])
    assert len(caught) == 1
    assert "'wet'" in str(caught[0].message) and "300 km/h" in str(caught[0].message)
    assert _peaks_warnings("wet", [60, 100]) == []


def test_user_parameters_without_a_range_never_warn():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        peak_adhesion(PolachParams(0.3, 0.4, 0.2, 0.3, 0.1), kmh_to_ms(350))
    assert not [w for w in caught if issubclass(w.category, AdhesionRangeWarning)]


def test_high_speed_wet_peak_at_300_lies_within_the_shinkansen_scatter():
    """Heavy-rain measurements at 300 km/h: about 0.02 (front car) to 0.05 (car 4); the design
    adhesion 13.6/(v+85) = 0.0353 lies between them."""
    peak = peak_adhesion("hs-wet", kmh_to_ms(300)).coefficient
    assert 0.02 <= peak <= 0.05
    assert peak == pytest.approx(13.6 / (300 + 85), rel=0.05)


def test_a_bad_validity_range_is_refused(tmp_path):
    text = (conditions_module._preset_dir() / "wet.yaml").read_text().replace("speed_kmh: [0, 120]", "speed_kmh: [120, 0]")
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(InputError, match="validity.speed_kmh"):
        load_condition(str(path))


def test_energy_conditioning_matches_the_axle_law_for_equal_axles():
    """Every axle leaving the same energy e: factor(n e) is the axle-count law with N = E_ref / e."""
    from railbrake.adhesion import EnergyConditioning, RailConditioning
    law = EnergyConditioning(leading_factor=0.2, reference_energy=4e4)
    e = law.energy_density(creep_force=-6e3, slip_velocity=1.2, speed=80.0, contact_width=0.011)
    assert e == pytest.approx(6e3 * 1.2 / (0.011 * 80.0))
    axle_law = RailConditioning(leading_factor=0.2, recovery_axles=4e4 / e)
    for n in range(0, 40, 3):
        assert law.factor(n * e) == pytest.approx(axle_law.factor(n), rel=1e-12)
    assert law.factor(0.0) == pytest.approx(0.2) and law.factor(1e12) == pytest.approx(1.0)
    assert law.energy_density(1e4, 1.0, 0.0, 0.01) == 0.0  # standstill: no rail passes


def test_energy_conditioning_refuses_bad_parameters():
    from railbrake.adhesion import EnergyConditioning
    with pytest.raises(InputError, match="leading_factor"):
        EnergyConditioning(leading_factor=0.0, reference_energy=1e4)
    with pytest.raises(InputError, match="reference_energy"):
        EnergyConditioning(leading_factor=0.5, reference_energy=-1.0)
