"""The traction side of the ED brake in a run: its slide control (in the plant, per motor car), from
data/traction/ed_slide_control.yaml (values and sources)."""

from __future__ import annotations

from functools import cache
from importlib import resources

import yaml

from railbrake import _core


@cache
def slide_control() -> dict:
    """The slide control's parameters (data/traction/ed_slide_control.yaml)."""
    return yaml.safe_load((resources.files("railbrake") / "data" / "traction" / "ed_slide_control.yaml").read_text())


def set_car(car: _core.PlantCar, motor: bool) -> None:
    """A motor car's slide control of its ED brake (a trailer has none)."""
    s = slide_control()
    if motor:
        car.ed_slide_slip, car.ed_slide_release = s["slide_slip"], s["release_slip"]
        car.ed_cut_rate, car.ed_restore_rate = s["cut_rate_per_s"], s["restore_rate_per_s"]

