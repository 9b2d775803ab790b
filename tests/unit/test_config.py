"""The YAML loader names the key, the value and its line for every kind of mistake."""

import pytest
from pydantic import BaseModel, ConfigDict, Field

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
