"""Loaded scenarios, trains and studies are read-only; with_() is the one way to change them, and it
validates as --set does (issue 31, part 2: no silent no-op)."""

import pytest

from railbrake import resolve, scenario, vehicle
from railbrake.campaign import study
from railbrake.errors import InputError, ReadOnlyError


@pytest.mark.parametrize("value", [300 / 3.6, -5])
def test_assigning_to_a_loaded_scenario_raises_and_changes_nothing(value):
    sc = scenario.load("emergency-250-dry")
    with pytest.raises(ReadOnlyError, match=r"initial_speed cannot be assigned.*with_\(initial_speed="):
        sc.initial_speed = value
    with pytest.raises(ReadOnlyError):
        sc.spec.initial_speed = value
    with pytest.raises(ReadOnlyError):
        sc.spec.wsp.enabled = False
    # nothing changed, and a run resolves from the file's 250 km/h
    assert sc.spec.initial_speed == pytest.approx(250 / 3.6)
    assert resolve.resolve(sc).scenario.spec.initial_speed == pytest.approx(250 / 3.6)


def test_scenario_data_is_a_copy():
    sc = scenario.load("emergency-250-dry")
    sc.data["initial_speed"] = "300 km/h"
    assert resolve.resolve(sc).scenario.spec.initial_speed == pytest.approx(250 / 3.6)


def test_with_takes_effect_through_the_same_validation_as_set():
    sc = scenario.load("emergency-250-dry")
    faster = sc.with_(initial_speed="300 km/h")
    assert faster.spec.initial_speed == pytest.approx(300 / 3.6)
    assert sc.spec.initial_speed == pytest.approx(250 / 3.6)
    assert resolve.resolve(faster).digest() == resolve.resolve(sc, sets=["initial_speed=300 km/h"]).digest()
    with pytest.raises(InputError, match=r"initial_speed = '-5 km/h': must lie in \[0, 540\] km/h"):
        sc.with_(initial_speed="-5 km/h")
    with pytest.raises(InputError, match="a unit is required"):
        sc.with_(initial_speed=300 / 3.6)
    with pytest.raises(InputError, match="no such key"):
        sc.with_(initial_sped="300 km/h")
    with pytest.raises(InputError, match="a key of the train file"):
        sc.with_({"train.max_speed_kmh": 100})
    crush = sc.with_({"train.load_case": "crush", "train.cars": 4})
    resolved = resolve.resolve(crush)
    assert (resolved.cars, resolved.train.load_case) == (4, "crush")


def test_train_is_read_only_and_with_validates():
    train = vehicle.load_train("crh380a-8")
    with pytest.raises(ReadOnlyError):
        train.max_speed = 100 / 3.6
    with pytest.raises(ReadOnlyError):
        train.spec.max_speed_kmh = 100
    with pytest.raises(ReadOnlyError):
        train.cars[0].tare = 1.0
    slower = train.with_(max_speed_kmh=300)
    assert (slower.max_speed, train.max_speed) == (pytest.approx(300 / 3.6), pytest.approx(350 / 3.6))
    with pytest.raises(InputError, match=r"max_speed_kmh = 3000: must lie in \[50, 500\] km/h"):
        train.with_(max_speed_kmh=3000)
    crush = train.with_(load_case="crush")
    payload = sum(c.equipment.payload_t.crush for c in train.cars) * 1e3
    assert crush.mass - (train.mass - sum(c.load for c in train.cars)) == pytest.approx(payload)


def test_study_is_read_only_and_with_validates():
    s = study.load("wsp-en15595")
    with pytest.raises(ReadOnlyError):
        s.seeds = 4
    with pytest.raises(ReadOnlyError):
        s.spec.seeds = 4
    assert s.with_(seeds=4).spec.seeds == 4 and s.spec.seeds != 4
    with pytest.raises(InputError, match=r"seeds = 0: a design with no runs"):
        s.with_(seeds=0)
    with pytest.raises(InputError, match="design.kind"):
        s.with_({"design.kind": "spiral"})
