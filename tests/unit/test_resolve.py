"""The resolved configuration: overrides reach the validated scenario and train, errors say where."""

import json
import shutil
from importlib import resources

import pytest

from railbrake.errors import InputError
from railbrake.resolve import resolve, valid_keys
from railbrake.units import KMH


def test_overrides_reach_scenario_and_train():
    base = resolve("emergency-250-dry")
    r = resolve("emergency-250-dry", cars=2, sets=["initial_speed=200 km/h",
                                                   "train.car_types.motor.wheelset_inertia_kgm2=140"])
    assert r.cars == 2 and r.scenario.spec.train.cars == 2
    assert r.scenario.spec.initial_speed == pytest.approx(200 * KMH)
    motors = [c for c in r.train.cars if c.motor]
    assert motors and all(c.wheelset_inertia == 140.0 for c in motors)
    assert all(c.wheelset_inertia != 140.0 for c in base.train.cars if c.motor)
    assert r.tree()["train"]["car_types"]["motor"]["wheelset_inertia_kgm2"] == 140
    assert r.digest() != base.digest()


def test_mapping_overrides_and_train_preset():
    r = resolve("emergency-250-dry", sets={"train.preset": "velaro-8", "adhesion.condition": "hs-wet"})
    assert r.train.name == "velaro-8" and r.scenario.spec.adhesion.condition == "hs-wet"
    assert r.cars == len(r.train.cars)


def test_digest_is_stable_and_canonical_is_json():
    a, b = resolve("service-200-wet"), resolve("service-200-wet")
    assert a.digest() == b.digest() and len(a.digest()) == 64
    body = json.loads(a.canonical())
    assert body["cars"] == a.cars and "formation" in body["train"]


def test_unknown_key_names_the_closest_ones():
    with pytest.raises(InputError, match=r"--set initial_sped: no such key; closest valid keys: initial_speed"):
        resolve("emergency-250-dry", sets=["initial_sped=100 km/h"])


@pytest.mark.parametrize("setting, message", [
    ("initial_speed=300", r"--set initial_speed: initial_speed = 300: .*unit is required"),
    ("train.car_types.motor.tare_t=heavy", r"--set train.car_types.motor.tare_t: car_types.motor.tare_t = 'heavy'"),
    ("no-equals-sign", r"expected KEY=VALUE"),
    ("demand.5.time=1 s", r"no such key"),
    # a section set to a value (a train file is given as train.preset, not as train)
    ("train=my-train.yaml", r"--set train = 'my-train.yaml': train is a section \(preset.*set one of its keys"),
])
def test_bad_overrides_name_the_override(setting, message):
    with pytest.raises(InputError, match=message):
        resolve("emergency-250-dry", sets=[setting])


def test_cars_apply_before_the_fault_check():
    # the preset's fault sits on car 3: with 2 cars it must be refused, naming the file's line
    with pytest.raises(InputError, match=r"preset fault-vent-valve-stuck, line \d+: faults.0.car = 3: .*cars 1..2"):
        resolve("fault-vent-valve-stuck", cars=2)
    assert resolve("fault-vent-valve-stuck", cars=3).cars == 3


def test_relative_files_resolve_against_the_scenario_folder(tmp_path, monkeypatch):
    data = resources.files("railbrake") / "data"
    folder = tmp_path / "study"
    folder.mkdir()
    shutil.copy(data / "trains" / "crh380a-8.yaml", folder / "my-train.yaml")
    shutil.copy(data / "adhesion" / "hs-wet.yaml", folder / "my-rail.yaml")   # valid at 250 km/h
    text = (data / "scenarios" / "emergency-250-dry.yaml").read_text()
    text = text.replace("preset: crh380a-8", "preset: my-train.yaml").replace("dry-medium", "my-rail.yaml")
    assert "my-train.yaml" in text and "my-rail.yaml" in text
    (folder / "scenario.yaml").write_text(text)
    monkeypatch.chdir(tmp_path)   # elsewhere than the scenario's folder
    r = resolve(folder / "scenario.yaml")
    assert r.train.name == "crh380a-8"
    assert r.tree()["adhesion"]["condition"] == str(folder / "my-rail.yaml")


def test_valid_keys_cover_schema_defaults_and_file_keys():
    keys = valid_keys(resolve("emergency-250-dry").tree())
    for key in ("initial_speed", "wsp.speed_threshold", "train.cars", "train.preset",
                "train.car_types.motor.cylinder.area_m2", "demand.0.time"):
        assert key in keys


def test_overrides_stack_on_a_resolved_configuration():
    first = resolve("emergency-250-dry", sets={"train.preset": "velaro-8"})
    second = resolve(first, cars=2, sets=["initial_speed=120 km/h"])
    assert second.train.name == "velaro-8" and second.cars == 2
    assert second.scenario.spec.initial_speed == pytest.approx(120 * KMH)
    assert resolve(first) is first


def test_python_sets_read_their_string_values_as_set_does():
    """sets={"k": "VALUE"} reads VALUE as `--set k=VALUE` does (a list, a number, a quantity)."""
    from railbrake.resolve import resolve as resolve_
    by_cli = resolve_("emergency-250-dry", sets=["stop.max_time=150 s", "initial_speed=180 km/h",
                                                  "adhesion.zones=[{start: 400 m, end: 700 m, condition: leaves}]"])
    by_api = resolve_("emergency-250-dry", sets={"stop.max_time": "150 s", "initial_speed": "180 km/h",
                                                 "adhesion.zones": "[{start: 400 m, end: 700 m, condition: leaves}]"})
    assert by_api.canonical() == by_cli.canonical()
    assert by_api.scenario.spec.stop.max_time == 150.0 and len(by_api.scenario.spec.adhesion.zones) == 1


SCENARIO_TEXT = (resources.files("railbrake") / "data" / "scenarios" / "emergency-250-dry.yaml").read_text()


@pytest.mark.parametrize("train, words", [
    ("train: crh380a-8", ["line 4", "train = 'crh380a-8'", "must be a mapping"]),   # a scalar: one error
    ("train: {preset: " + "x" * 10_000 + "}", ["line 4", "train.preset", "too long"]),
    ("train: {preset: " + "x" * 300 + ".yaml}", ["line 4", "train.preset", "too long"]),
])
def test_a_bad_train_gives_one_error_with_file_line_and_key(tmp_path, train, words):
    lines = SCENARIO_TEXT.splitlines()
    assert lines[3].startswith("train:")
    path = tmp_path / "scenario.yaml"
    path.write_text("\n".join(lines[:3] + [train] + lines[4:]) + "\n")
    with pytest.raises(InputError) as caught:
        resolve(str(path))
    message = str(caught.value)
    assert message.startswith(str(path)) and all(w in message for w in words), message
    assert len(message) < 400 and "File name too long" not in message   # the 10 kB name is not echoed
