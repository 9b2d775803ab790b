"""Train keys name their unit (`tare_t: 50`), scenario keys take it in their value
(`initial_speed: 300 km/h`). A value with a unit given to a key that names its unit ('60 t') is
refused everywhere (train file, --set, Python sets and with_, study set, factors and points) with
one hint: the key, its unit and the number to write (railbrake.config.named_unit_hint)."""

import pytest
import yaml
from typer.testing import CliRunner

from railbrake import resolve, units, vehicle
from railbrake.campaign import study
from railbrake.cli import app
from railbrake.errors import InputError

TARE = "train.car_types.motor.tare_t"
HINT = r"tare_t = '60 t': the key's name gives the unit \(tare_t: t\): write the number alone, 60"


@pytest.mark.parametrize("name, unit", [("tare_t", "t"), ("max_speed_kmh", "km/h"), ("supply_pressure_bar", "bar"),
                                        ("B_kN_per_kmh", "kN/(km/h)"), ("delivery_kg_s", "kg/s"),
                                        ("drop_out_s", "s"), ("area_mm2", "mm²"), ("load_case", None)])
def test_the_unit_a_key_names(name, unit):
    assert units.unit_in_name(name) == unit


def _train_file(tmp_path, tare):
    data = yaml.safe_load(vehicle._preset_dir().joinpath("crh380a-8.yaml").read_text())
    data["car_types"]["motor"]["tare_t"] = tare
    path = tmp_path / "train.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def test_a_train_file_names_file_line_key_and_the_number_to_write(tmp_path):
    path = _train_file(tmp_path, "60 t")
    with pytest.raises(InputError, match=rf"train.yaml, line \d+: car_types.motor.{HINT}$"):
        vehicle.load_train(str(path))
    motor = next(c for c in vehicle.load_train(str(_train_file(tmp_path, 60))).cars if c.motor)
    assert motor.tare == pytest.approx(60e3)   # written as told


def test_another_unit_is_refused_with_the_key_s_unit(tmp_path):
    with pytest.raises(InputError, match=r"tare_t = '60000 kg': .*\(tare_t: t\): write the number alone, in t \(not kg\)"):
        vehicle.load_train(str(_train_file(tmp_path, "60000 kg")))


def test_a_key_inside_a_key_that_names_the_unit():
    with pytest.raises(InputError, match=r"limit_bar.tare = '3 bar': the key's name gives the unit \(limit_bar: bar\)"):
        resolve.resolve("emergency-250-dry", sets={"train.car_types.motor.emergency_valve.limit_bar.tare": "3 bar"})


def test_set_on_the_command_line():
    done = CliRunner().invoke(app, ["config", "show", "emergency-250-dry", "--set", f"{TARE}=60 t"])
    assert done.exit_code == 2
    assert f"--set {TARE}: car_types.motor.tare_t = '60 t'" in done.output and "write the number alone, 60" in done.output


def test_python_sets_and_with():
    with pytest.raises(InputError, match=rf"sets\['{TARE}'\]: car_types.motor.{HINT}"):
        resolve.resolve("emergency-250-dry", sets={TARE: "60 t"})
    with pytest.raises(InputError, match=rf"--set {TARE}: car_types.motor.{HINT}"):
        resolve.resolve("emergency-250-dry", sets=[f"{TARE}=60 t"])
    with pytest.raises(InputError, match=r"max_speed_kmh = '300 km/h': .*\(max_speed_kmh: km/h\): write the number alone, 300"):
        vehicle.load_train("crh380a-8").with_(max_speed_kmh="300 km/h")
    motor = next(c for c in resolve.resolve("emergency-250-dry", sets={TARE: 60}).train.cars if c.motor)
    assert motor.tare == pytest.approx(60e3)


def test_scenario_keys_take_their_unit_in_the_value():
    with pytest.raises(InputError, match=r"initial_speed = 300: a unit is required .*'300 km/h'"):
        resolve.resolve("emergency-250-dry", sets={"initial_speed": 300})


STUDY = """schema: railbrake.study/1
name: units
base: emergency-250-dry
set: {{train.cars: 2, stop.max_time: "5 s"{set}}}
factors:
  {factor}
design: {{kind: grid}}
"""


@pytest.mark.parametrize("set_, factor, where", [
    (f', {TARE}: "60 t"', 'initial_speed: ["60 km/h", "80 km/h"]', rf"study.yaml, line 4: set.{TARE} = '60 t'"),
    ("", f'{TARE}: {{low: "50 t", high: "60 t", levels: 2}}', rf"study.yaml, line 6: factors.{TARE} = '50 t'"),
    ("", f'{TARE}: [50, "60 t"]', rf"study.yaml, line 6: factors.{TARE} = '60 t'"),
])
def test_a_study_s_set_and_factors(tmp_path, set_, factor, where):
    path = tmp_path / "study.yaml"
    path.write_text(STUDY.format(set=set_, factor=factor))
    with pytest.raises(InputError, match=rf"{where}: the key's name gives the unit \(tare_t: t\)"):
        study.load(str(path))
    path.write_text(STUDY.format(set=set_.replace('"60 t"', "60"), factor=factor.replace('"50 t"', "50")
                                 .replace('"60 t"', "60")))
    assert study.load(str(path)).name == "units"
