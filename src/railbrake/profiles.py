"""Deceleration profiles (schema ``railbrake.profile/1``): the demanded deceleration over speed of a
brake step, with its EN 14531 response times; shipped presets (data/profiles), YAML or CSV files,
or a constant. Read by the train files' brake steps (railbrake.vehicle) and by sizing."""

from __future__ import annotations

import csv
import ctypes
import functools
import io
import numbers
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Union

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

from railbrake import _core, config
from railbrake._args import name_or_path, real, reals, text
from railbrake.config import parse_yaml, read_text
from railbrake.errors import InputError
from railbrake.units import KMH

PROFILE_SCHEMA = "railbrake.profile/1"


class _Response(BaseModel):
    model_config = ConfigDict(extra="forbid")
    # in the C plausibility bound profile.response_time (core/src/bounds.c)
    delay_s: float = Field(ge=config.bound_in("profile.response_time")[0], le=config.bound_in("profile.response_time")[1])
    build_up_s: float = Field(ge=config.bound_in("profile.response_time")[0],
                              le=config.bound_in("profile.response_time")[1])


class _ProfileFile(BaseModel):
    model_config = ConfigDict(extra="forbid")
    schema_: str = Field(alias="schema")
    name: str
    title: str
    source: str
    response: _Response
    speed_kmh: list[float] = Field(min_length=1, max_length=_core.MAX_TABLE)
    deceleration_ms2: list[float] = Field(min_length=1, max_length=_core.MAX_TABLE)

    @model_validator(mode="after")
    def _shape(self):
        _check_profile_points(self.speed_kmh, self.deceleration_ms2)
        return self


def _check_profile_points(speed_kmh, decel):
    if len(speed_kmh) != len(decel):
        raise ValueError(f"speed_kmh ({len(speed_kmh)} points) and deceleration_ms2 ({len(decel)}) "
                         "differ in length")
    if not 1 <= len(speed_kmh) <= _core.MAX_TABLE:
        raise ValueError(f"speed_kmh: {len(speed_kmh)} points: a profile has 1 to {_core.MAX_TABLE}")
    for i, v in enumerate(speed_kmh):
        if not config.within("train.table_speed", v * KMH):
            raise ValueError(f"speed_kmh[{i}] = {v}: {config.range_text('train.table_speed', 'km/h', KMH)}")
        if i and not v > speed_kmh[i - 1]:
            raise ValueError(f"speed_kmh[{i}] = {v}: the profile must be monotonic in speed "
                             f"(strictly above speed_kmh[{i - 1}] = {speed_kmh[i - 1]})")
    for i, a in enumerate(decel):
        if not config.within("profile.deceleration", a):
            raise ValueError(f"deceleration_ms2[{i}] = {a}: {config.range_text('profile.deceleration', 'm/s^2')}")


@dataclass(frozen=True)
class Profile:
    """Demanded deceleration over speed (SI), linear between points, constant beyond the ends."""

    name: str
    title: str
    source: str
    speed: np.ndarray  # m/s
    deceleration: np.ndarray  # m/s^2
    delay: float = 0.0  # s, ta
    build_up: float = 0.0  # s, tb

    @property
    def response_time(self) -> float:
        """EN 14531 equivalent response time te = ta + tb/2."""
        return self.delay + 0.5 * self.build_up

    def table(self) -> _core.SpeedTable:
        return _core.speed_table(self.speed, self.deceleration)

    def at(self, speed):
        table = self.table()
        v = np.asarray(speed, dtype=float)
        return np.array([_core.rb_speed_table_at(ctypes.byref(table), float(x)) for x in v.ravel()]
                        ).reshape(v.shape)


def make_profile(speed_kmh, deceleration_ms2, name="user", title="User profile", source="user input",
                 delay=0.0, build_up=0.0) -> Profile:
    """A profile from points in km/h and m/s^2; checks that the speeds increase strictly."""
    speed_kmh = [float(v) for v in np.atleast_1d(reals("speed_kmh", speed_kmh))]
    decel = [float(a) for a in np.atleast_1d(reals("deceleration_ms2", deceleration_ms2))]
    name, title, source = text("name", name), text("title", title), text("source", source)
    delay, build_up = real("delay", delay, 0.0), real("build_up", build_up, 0.0)
    try:
        _check_profile_points(speed_kmh, decel)
    except ValueError as exc:
        raise InputError(f"profile {name}: {exc}") from None
    return Profile(name, title, source, np.array(speed_kmh) * KMH, np.array(decel), delay, build_up)


def _profile_dir():
    return resources.files("railbrake") / "data" / "profiles"


def profile_names() -> list[str]:
    return sorted(p.name[:-5] for p in _profile_dir().iterdir() if p.name.endswith(".yaml"))


@functools.cache
def _preset_profile(name: str) -> Profile:
    """A shipped profile, read once per process (a study sets up thousands of runs); its arrays
    are read-only, so no caller can change the next one's."""
    profile = _parse_profile((_profile_dir() / f"{name}.yaml").read_text(), f"profile {name}")
    for array in (profile.speed, profile.deceleration):
        array.setflags(write=False)
    return profile


def _parse_profile(text: str, origin: str) -> Profile:
    m = parse_yaml(text, _ProfileFile, origin)
    if m.schema_ != PROFILE_SCHEMA:
        raise InputError(f"{origin}: schema = {m.schema_!r}: expected {PROFILE_SCHEMA!r}")
    return make_profile(m.speed_kmh, m.deceleration_ms2, m.name, m.title, " ".join(m.source.split()),
                        m.response.delay_s, m.response.build_up_s)


def read_profile_csv(path: Path, delay=0.0, build_up=0.0) -> Profile:
    """CSV with columns speed_kmh, deceleration_ms2."""
    path = Path(path)
    with io.StringIO(read_text(path), newline="") as handle:   # a regular file under the size limit
        reader = csv.DictReader(handle)
        needed = {"speed_kmh", "deceleration_ms2"}
        if not reader.fieldnames or not needed <= set(reader.fieldnames):
            raise InputError(f"{path}: columns {reader.fieldnames}: needs {sorted(needed)}")
        rows = []
        for line, row in enumerate(reader, start=2):
            try:
                rows.append((float(row["speed_kmh"]), float(row["deceleration_ms2"])))
            except (TypeError, ValueError):
                raise InputError(f"{path}, line {line}: {row}: not numbers") from None
    return make_profile([r[0] for r in rows], [r[1] for r in rows], path.stem, path.name, str(path),
                        delay, build_up)


ProfileLike = Union[str, Path, Profile, float]


def load_profile(profile: ProfileLike, argument: str = "profile") -> Profile:
    """A preset name (profile_names()), a YAML or CSV file, a Profile, or a constant (m/s^2);
    errors name `argument` (the caller's name for it)."""
    if isinstance(profile, Profile):
        return profile
    if isinstance(profile, numbers.Real) and not isinstance(profile, bool):
        value = real(argument, profile)
        try:
            return make_profile([0.0], [value], "constant", f"constant {value} m/s^2")
        except InputError as exc:
            raise InputError(f"{argument} = {value!r}: {str(exc).split(': ', 1)[-1]}") from None
    name = name_or_path(argument, profile)
    if name in profile_names():
        return _preset_profile(name)
    path = Path(name)
    if path.suffix == ".csv" and path.is_file():
        return read_profile_csv(path)
    if path.suffix in (".yaml", ".yml") and path.is_file():
        return _parse_profile(read_text(path), str(path))
    raise InputError(f"{argument} = {name!r}: not a preset ({', '.join(profile_names())}) nor a file")
