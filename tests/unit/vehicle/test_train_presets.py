"""Train presets against published figures (CRH380AL: TB/T 1407.2; CRH380A, CRH3C, ICE 3 data)."""

from pathlib import Path

import numpy as np
import pytest
import yaml

from railbrake import vehicle
from railbrake.errors import InputError


@pytest.mark.parametrize("name, cars, motors, mass_t, max_axle_t", [
    ("crh380a-8", 8, 6, 388.4, 15.0),     # README s. 2 [P]: 6M2T, 388.4 t, axle load <= 15 t
    ("crh380al-16", 16, 14, 903.0, None),  # 14M2T, 903 t with rated load [P]
    ("velaro-8", 8, 4, None, 17.0),        # CRH3C 4M4T, axle load 17 t [P]
])
def test_formation_and_masses(name, cars, motors, mass_t, max_axle_t):
    train = vehicle.load_train(name)
    assert len(train.cars) == cars
    assert sum(car.motor for car in train.cars) == motors
    if mass_t:
        assert train.mass == pytest.approx(mass_t * 1e3, rel=1e-9)
    if max_axle_t:
        assert max(car.mass / car.axles for car in train.cars) <= max_axle_t * 1e3
    assert train.mass == pytest.approx(sum(car.mass for car in train.cars))
    assert vehicle.load_train(name, loaded=False).mass < train.mass


def test_rotating_mass_is_sum_over_cars_and_crh380al_factor():
    train = vehicle.load_train("crh380al-16")
    by_hand = sum(car.axles * car.wheelset_inertia / car.wheel_radius**2 for car in train.cars)
    assert train.rotating_mass == pytest.approx(by_hand, rel=1e-12)
    assert train.rotating_mass / train.mass == pytest.approx(0.06, abs=5e-4)  # 6 % [P]


def test_crh380al_running_resistance_is_tbt_1407():
    train = vehicle.load_train("crh380al-16")
    v_kmh = np.array([0.0, 100.0, 200.0, 300.0, 350.0])
    expected = (3.3 + 0.0469 * v_kmh + 0.000921 * v_kmh**2) * 1e3  # kN -> N, TB/T 1407.2 [P]
    assert train.running_resistance(v_kmh / 3.6) == pytest.approx(expected, rel=1e-12)


def test_crh380al_ed_curve_is_tbt_1407():
    train = vehicle.load_train("crh380al-16")
    v = np.array([2.0, 10.0, 30.0, 50.0, 70.0, 97.2])  # m/s, above the 5 km/h fade [T]
    expected = np.minimum.reduce([np.full_like(v, 509.6), 544.34 - 1.787 * v,
                                  42942.9 / v - 121.0, 33033.0 / v]) * 1e3
    assert train.ed_brake_force(v) == pytest.approx(expected, rel=1e-12)
    assert train.ed_brake_force(0.0) == 0.0  # faded out at standstill [T]


def test_c_struct_copy_carries_every_car():
    train = vehicle.load_train("velaro-8")
    c = train.to_c()
    assert c.n_cars == 8
    assert [c.cars[k].motor for k in range(8)] == [int(car.motor) for car in train.cars]
    assert c.cars[1].brake.discs == 3 and c.cars[0].brake.mounting == 1


def _preset_text(name):
    return (Path(vehicle.__file__).parent / "data" / "trains" / f"{name}.yaml").read_text()


def _write(tmp_path, data):
    path = tmp_path / "train.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def test_negative_mass_is_named(tmp_path):
    data = yaml.safe_load(_preset_text("crh380a-8"))
    data["car_types"]["trailer"]["tare_t"] = -40.1
    with pytest.raises(InputError, match=r"car_types\.trailer\.tare_t = -40\.1"):
        vehicle.load_train(_write(tmp_path, data))


def test_lever_ratio_zero_in_file_is_named(tmp_path):
    data = yaml.safe_load(_preset_text("crh380a-8"))
    data["car_types"]["motor"]["caliper"]["lever_ratio"] = 0
    with pytest.raises(InputError, match=r"car_types\.motor\.caliper\.lever_ratio = 0"):
        vehicle.load_train(_write(tmp_path, data))


def test_extra_key_and_unknown_car_type_are_refused(tmp_path):
    data = yaml.safe_load(_preset_text("crh380a-8"))
    data["car_types"]["motor"]["colour"] = "white"
    with pytest.raises(InputError, match=r"car_types\.motor\.colour"):
        vehicle.load_train(_write(tmp_path, data))
    data = yaml.safe_load(_preset_text("crh380a-8"))
    data["formation"][3] = "buffet"
    with pytest.raises(InputError, match=r"formation\[3\] = 'buffet'"):
        vehicle.load_train(_write(tmp_path, data))
    with pytest.raises(InputError, match="not a preset"):
        vehicle.load_train("ice-99")
