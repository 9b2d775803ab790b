"""Sanders of a train file (core/src/rail_conditioning.c) in runs: on heavy rain with the rail cells,
a WSP-triggered sander in front of the leading axle shortens the stop and books its sand; without
the rail cells the run says the sanders act on nothing."""

from importlib import resources

import numpy as np
import pytest

from railbrake import simulation
from railbrake.scenario import load

VARIABLE = """
sanders:
  units:
    - {car: 1, axle: 1, rate_kg_min: RATE, trigger: wsp}
  sand_reference_kg_m: 0.002
  sand_entrained: 0.2
  sand_retention: 0.5
  source: test values
"""


def _train_with(tmp_path, sanders: str, name: str = "sanded") -> str:
    text = (resources.files("railbrake") / "data" / "trains" / "crh380al-16.yaml").read_text()
    path = tmp_path / f"{name}.yaml"
    path.write_text(text + sanders)
    return str(path)


@pytest.fixture(scope="module")
def sanded_train(tmp_path_factory):
    return _train_with(tmp_path_factory.mktemp("train"), VARIABLE.replace("RATE", "1.5"))


def _run(train=None, **changes):
    sc = load("emergency-300-heavy-rain").with_({"train.cars": 4, **({"train.preset": train} if train else {}),
                                                 **changes})
    return simulation.run(sc)


def test_sand_shortens_the_stop_on_heavy_rain(sanded_train):
    cells = {"adhesion.rail_conditioning": "cells"}
    plain, sanded = _run(**cells), _run(sanded_train, **cells)
    assert sanded.kpis["stopping_distance_m"] < 0.97 * plain.kpis["stopping_distance_m"]


def test_sanders_without_rail_cells_are_said_to_act_on_nothing(sanded_train):
    with pytest.warns(UserWarning, match="sanders act on the rail cells"):
        _run(sanded_train)


def test_a_variable_rate_reaches_the_core_as_a_table_over_speed(tmp_path):
    """rate_kg_min as {speed_kmh, value}: the plant gets kg/s over m/s; a table constant at the
    fixed rate runs bit for bit as that fixed rate; more sand at speed stops sooner."""
    table = _train_with(tmp_path, VARIABLE.replace("RATE", "{speed_kmh: [0, 300], value: [0.0, 6.0]}"), "table")
    sc = load("emergency-300-heavy-rain").with_({"train.cars": 4, "train.preset": table,
                                                 "adhesion.rail_conditioning": "cells"})
    rate = simulation.plant_params(sc, 4).sander_rate[0]
    assert (rate.n, list(rate.speed[:2]), list(rate.value[:2])) == (2, [0.0, pytest.approx(300 / 3.6)],
                                                                    [0.0, pytest.approx(0.1)])
    flat = _train_with(tmp_path, VARIABLE.replace("RATE", "{speed_kmh: [0, 300], value: [1.5, 1.5]}"), "flat")
    fixed = _train_with(tmp_path, VARIABLE.replace("RATE", "1.5"), "fixed")
    cells = {"adhesion.rail_conditioning": "cells"}
    assert _run(flat, **cells).kpis == _run(fixed, **cells).kpis
    assert _run(table, **cells).kpis["stopping_distance_m"] < _run(fixed, **cells).kpis["stopping_distance_m"]


@pytest.mark.parametrize("rate, message", [
    ("{speed_kmh: [0, 300], value: [0.0, 0.0]}", "every rate is 0 kg/min"),
    ("{speed_kmh: [0, 300], value: [0.0, 61.0]}", r"value\[1\] = 61"),
    ("{speed_kmh: [100, 50], value: [1.0, 2.0]}", "speeds must increase"),
])
def test_a_variable_rate_table_is_checked(tmp_path, rate, message):
    from railbrake import vehicle
    from railbrake.errors import InputError
    with pytest.raises(InputError, match=message):
        vehicle.load_train(_train_with(tmp_path, VARIABLE.replace("RATE", rate)))


def test_the_t1107_rail_as_laid_has_its_published_friction():
    """The sander validation cases' rail (validation/validation/sanders-t1107-class387): as laid it
    peaks at the published untreated 0.02 at the trial's 55 mph (its file's target)."""
    from pathlib import Path

    from railbrake.adhesion import load_condition, peak_adhesion
    path = Path(__file__).resolve().parents[3] / "validation" / "validation" / "sanders-t1107-class387" / \
        "t1107-low-adhesion.yaml"
    condition = load_condition(str(path))
    (target,) = condition.targets
    assert peak_adhesion(condition, target["speed_kmh"] / 3.6, axle=0).coefficient == \
        pytest.approx(target["peak"], rel=target["rel_tolerance"])
    assert target["peak"] == 0.02


def _t1107_run(retention: float):
    """The T1107 Class 387 stop (validation case sanders-t1107-class387) with one sander on car 1
    axle 3 laying the same sand on every metre (rate in proportion to speed, 0.5 g/m: below what
    saturates the law), so that the axles behind it meet rail sanded alike."""
    from pathlib import Path

    import yaml

    from railbrake.resolve import resolve
    from railbrake.validation.models import _sanders
    folder = Path(__file__).resolve().parents[3] / "validation" / "validation" / "sanders-t1107-class387"
    calibration = dict(yaml.safe_load((folder / "calibration.yaml").read_text()), sand_retention=retention)
    units = [{"car": 1, "axle": 3, "rate_kg_min": {"speed_kmh": [0, 180], "value": [0.0, 1.5]},
              "trigger": "driver", "start_s": 0.0}]
    return simulation.run(resolve(str(folder / "scenario.yaml"), sets={"train.sanders": _sanders(units, calibration)}))


def _axle_peaks(result, above_kmh: float = 20.0) -> np.ndarray:
    running = result.outputs["speed"] > above_kmh / 3.6
    return np.array([np.max(np.abs(result.outputs[n][running])) for n in result.axle_channels("adhesion")])


def test_behind_a_sander_the_axles_find_more_adhesion_along_the_train():
    """Each axle that passes crushes part of the loose sand into the rail and leaves part for the
    next: the adhesion the axles behind the sander (axle 3 on) find never falls along the train and
    ends well above the sander's own axle's; with no sand left loose (retention 0) the sander's axle
    takes it all and every axle behind finds the same."""
    peaks = _axle_peaks(_t1107_run(0.4))[2:]
    assert np.all(np.diff(peaks) >= -0.01 * peaks[:-1])   # the recording's 20 ms samples of the slip cycles
    assert peaks[-1] > 1.15 * peaks[0]
    flat = _axle_peaks(_t1107_run(0.0))[2:]
    assert np.ptp(flat) < 0.02 * flat.mean()
