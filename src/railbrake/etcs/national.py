"""The national values and the track of the ETCS braking curves (railbrake.etcs.curves): YAML files
or the shipped presets (data/etcs/national-*.yaml, data/etcs/track-*.yaml), validated in full,
an error naming the file, line, key, value and what is allowed."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from railbrake import config
from railbrake.etcs.inputs import _path  # the one lookup of the data/etcs files


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, frozen=True)


class Ura(_Strict):
    at_low_kmh: float = Field(ge=0.0, le=600.0)
    low_kmh: float = Field(ge=0.0, le=50.0)
    at_high_kmh: float = Field(ge=0.0, le=600.0)
    high_kmh: float = Field(ge=0.0, le=50.0)

    @model_validator(mode="after")
    def _ordered(self):
        if not self.at_low_kmh < self.at_high_kmh:
            raise ValueError(f"at_low_kmh = {self.at_low_kmh:g} must lie below at_high_kmh = {self.at_high_kmh:g}")
        return self


class Indication(_Strict):
    bs_factor: float = Field(ge=0.0, le=10.0)
    min_s: float = Field(ge=0.0, le=60.0)


class National(_Strict):
    schema_: Literal["railbrake.etcs-national/1"] = Field(alias="schema")
    name: str
    source: str
    M_NVEBCL: int = Field(ge=0, le=9)
    M_NVAVADH: float = Field(ge=0.0, le=1.0)
    Q_NVSBTSMPERM: bool
    Q_NVSBFBPERM: bool
    Q_NVGUIPERM: bool
    Q_NVINHSMICPERM: bool
    T_warning_s: float = Field(ge=0.0, le=60.0)
    T_driver_s: float = Field(ge=0.0, le=60.0)
    T_indication: Indication
    A_est2_m_s2: float = Field(ge=0.0, le=0.4)
    M_rotating_min_percent: float = Field(ge=0.0, le=100.0)
    M_rotating_max_percent: float = Field(ge=0.0, le=100.0)
    V_ura_kmh: Ura


class Gradient(_Strict):
    from_m: float = Field(ge=0.0, le=1e6)
    permille: float = Field(ge=-100.0, le=100.0)   # uphill positive


class Track(_Strict):
    schema_: Literal["railbrake.etcs-track/1"] = Field(alias="schema")
    name: str
    source: str
    length_m: float = Field(gt=0.0, le=1e6)
    eoa_m: float = Field(gt=0.0, le=1e6)
    svl_m: float = Field(gt=0.0, le=1e6)
    line_speed_kmh: float | None = Field(None, gt=0.0, le=600.0)   # None: the train's maximum speed
    gradients: list[Gradient] = Field(min_length=1, max_length=1000)

    @model_validator(mode="after")
    def _consistent(self):
        if not self.eoa_m <= self.svl_m <= self.length_m:
            raise ValueError(f"eoa_m = {self.eoa_m:g}, svl_m = {self.svl_m:g}, length_m = {self.length_m:g}: "
                             "need eoa_m <= svl_m <= length_m")
        starts = [g.from_m for g in self.gradients]
        if starts[0] != 0.0 or any(a >= b for a, b in zip(starts, starts[1:])):
            raise ValueError(f"gradients: from_m = {starts}: must start at 0 and rise strictly")
        return self


def load_national(name="default") -> National:
    return config.load_yaml(_path("national", name), National)


def load_track(name) -> Track:
    return config.load_yaml(_path("track", name), Track)
