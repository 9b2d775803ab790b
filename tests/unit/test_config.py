"""The YAML loader names the key, the value and its line for every kind of mistake."""

import re

import pytest
from pydantic import BaseModel, ConfigDict, Field

from railbrake import config
from railbrake.config import load_yaml, parse_yaml
from railbrake.errors import InputError


class Car(BaseModel):
    model_config = ConfigDict(extra="forbid")
    mass_t: float = Field(gt=0)
    motor: bool = False


class Train(BaseModel):
    model_config = ConfigDict(extra="forbid")
    name: str
    cars: list[Car]


GOOD = "name: test\ncars:\n  - mass_t: 50\n  - mass_t: 48\n    motor: true\n"


def test_valid_file_loads():
    train = parse_yaml(GOOD, Train, "t.yaml")
    assert [c.mass_t for c in train.cars] == [50, 48]


@pytest.mark.parametrize("text, message", [
    (GOOD.replace("motor: true", "motr: true"), "t.yaml, line 5: cars.1.motr: unknown key"),
    (GOOD.replace("mass_t: 48", "mass_t: -48"), "t.yaml, line 4: cars.1.mass_t = -48: Input should be greater than 0"),
    (GOOD.replace("mass_t: 50", "mass_t: heavy"), "t.yaml, line 3: cars.0.mass_t = 'heavy'"),
    ("cars:\n  - mass_t: 50\n", "name: missing"),
    ("name: [unclosed\ncars: []\n", "t.yaml, line 2: not valid YAML"),
    ("- just\n- a list\n", "expected a mapping"),
])
def test_errors_name_key_value_and_line(text, message):
    with pytest.raises(InputError) as info:
        parse_yaml(text, Train, "t.yaml")
    assert message in str(info.value)


def test_missing_file_is_named(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        load_yaml(tmp_path / "nope.yaml", Train)


# ------------------------------------------------------------------ plausibility bounds (issue 15)

def test_range_text_is_the_c_bound_in_the_users_unit():
    from railbrake import _core
    low, high = _core.bound("initial_speed")
    assert config.bound_in("initial_speed", 1 / 3.6)[:2] == pytest.approx((low * 3.6, high * 3.6))
    assert config.range_text("initial_speed", "km/h", 1 / 3.6).startswith("must lie in [0, 540] km/h (")
    assert config.range_text("temperature", "degC", 1.0, 273.15).startswith("must lie in [-73.15, 126.85] degC")
    assert config.within("wsp.safety_time", 5.0) and not config.within("wsp.safety_time", 0.0)
    assert not config.within("wsp.safety_time", float("nan"))


def test_a_number_yaml_reads_as_text_is_explained():
    class M(BaseModel):
        tare_t: float
    for text, hint in (("tare_t: 1e29\n", "write 1.0e+29"), ('tare_t: "1_000"\n', "write 1000")):
        with pytest.raises(InputError, match=rf"line 1: tare_t = '.*': text, not a number .*: {re.escape(hint)}"):
            config.parse_yaml(text, M, "f.yaml")


@pytest.mark.parametrize("kind, text, message", [
    ("relay", "supply_bar: 80\n", r"v\.yaml, line 1: supply_bar = 80: must lie in \[1, 10\] bar gauge"),
    ("relay", "control_step_bar: 9.0\n", r"line 1: control_step_bar = 9\.0: must lie in \(0, supply_bar = 8\]"),
    ("relay", "supply_bar: 3.0\n", r"line 1: control_step_bar = 3\.8: must lie in \(0, supply_bar = 3\]"),
    ("epv", "supply_bar: 12\n", r"line 1: supply_bar = 12: must lie in \[1, 10\] bar gauge"),
    ("epv", "supply_bar: true\n", r"line 1: supply_bar = True: must be a number"),
])
def test_valve_pressures_are_bounded(tmp_path, kind, text, message):
    from railbrake import valves
    path = tmp_path / "v.yaml"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        getattr(valves, f"load_{kind}")(path)
    with pytest.raises(InputError, match=r"nope\.yaml: no such file"):
        getattr(valves, f"load_{kind}")(tmp_path / "nope.yaml")


def test_creep_in_percent_is_refused_with_a_hint(tmp_path):
    import numpy as np

    from railbrake.adhesion import identify_polach
    creep = np.linspace(0.0, 30.0, 12)
    with pytest.raises(InputError, match=r"creep\[1\] = 2\.72727: must lie in \[-1, 1\] .* look like percent, divide"):
        identify_polach(creep, 0.3 * np.ones(12), 20.0)
    from typer.testing import CliRunner

    from railbrake.cli import app
    csv = tmp_path / "m.csv"
    csv.write_text("creep,coefficient,speed_kmh\n" + "".join(f"{c},0.3,60\n" for c in range(12)))
    result = CliRunner().invoke(app, ["adhesion", "fit", str(csv)])
    assert result.exit_code == 2 and f"{csv}, line 4: creep = 2: must lie in [-1, 1]" in result.output
    assert "percent" in result.output and "Traceback" not in result.output
    result = CliRunner().invoke(app, ["adhesion", "fit", str(tmp_path / "none.csv")])
    assert result.exit_code == 2 and "none.csv: no such file" in result.output and "Errno" not in result.output
