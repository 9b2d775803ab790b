"""Sizing the brake: target cylinder pressure by inverse computation, and stopping distances.

The laws (force balance, blending, the closed-form inverse, the EN 14531 integrator) live in C
(``core/src/vehicle_sizing.c``, ``vehicle_stopping.c``); this module prepares the inputs, reads
the deceleration profiles (railbrake.profiles) and phrases the warnings.

Blending rule (``rb_car_brake_demand``): every car brakes its own translational and rotating mass
at the demanded deceleration, less its mass share of resistance and gradient; on a motor car the
ED brake supplies what it can (ED first), the pneumatic brake the rest. One cylinder pressure per
car type (motor, trailer) makes the type's cars together supply their pneumatic share.
"""

from __future__ import annotations

import csv
import ctypes
import io
from dataclasses import dataclass, field, replace
from typing import Optional

import numpy as np

from railbrake import _core
from railbrake._args import flag, instance, real, reals, text, whole
from railbrake.errors import InputError
# the profiles live in railbrake.profiles (below the train files, which name them); their names here too
from railbrake.profiles import (PROFILE_SCHEMA, Profile, ProfileLike, load_profile, make_profile,  # noqa: F401
                                profile_names, read_profile_csv)
from railbrake.units import KMH, ms_to_kmh
from railbrake.vehicle import Train, load_train, train_discs

MAX_STOP_STEPS = 10**8      # integration steps of one stop (a few s of C time), and
MAX_CURVE_POINTS = 10**6    # points of its curve (24 MB): checked before either is spent
ADHESION_LIMIT = 0.15  # design limit on the adhesion an axle may demand [T]


# ------------------------------------------------------------------ target pressure

@dataclass(frozen=True)
class SizingResult:
    speed: np.ndarray  # m/s
    deceleration: np.ndarray  # m/s^2 demanded
    p_motor: Optional[np.ndarray]  # Pa absolute (None: no motor car)
    p_trailer: Optional[np.ndarray]
    ed_force: np.ndarray  # N, whole train
    adhesion: np.ndarray  # [speed, car]: adhesion each axle of the car demands
    atmospheric_pressure: float
    supply_pressure: float  # Pa absolute
    adhesion_limit: float
    ed_blending: bool = True
    ed_reason: str = ""   # why the ED brake blends or not (the brake step, or as asked)
    warnings: list = field(default_factory=list)

    @property
    def adhesion_demand(self) -> np.ndarray:
        """The largest adhesion any axle demands, per speed."""
        return self.adhesion.max(axis=1)

    def gauge_bar(self, pressure):
        return None if pressure is None else (pressure - self.atmospheric_pressure) / 1e5


def default_speeds(train: Train, profile: Profile, step_kmh: float = 5.0) -> np.ndarray:
    """0 to the train's top speed every step_kmh, with the profile's break points added."""
    grid = np.arange(0.0, ms_to_kmh(train.max_speed) + 1e-9, step_kmh) * KMH
    points = profile.speed[profile.speed <= train.max_speed]
    return np.unique(np.concatenate([grid, points]))


def _ranges(speed, mask) -> str:
    """'120-200 km/h, 300 km/h' for the speeds where mask holds."""
    out, start = [], None
    kmh = ms_to_kmh(np.asarray(speed))
    for i, flag in enumerate(list(mask) + [False]):
        if flag and start is None:
            start = i
        if not flag and start is not None:
            a, b = kmh[start], kmh[i - 1]
            out.append(f"{a:.0f} km/h" if start == i - 1 else f"{a:.0f}-{b:.0f} km/h")
            start = None
    return ", ".join(out)


def _warnings(train: Train, r: SizingResult, coast: np.ndarray) -> list:
    found = []
    over = r.adhesion_demand > r.adhesion_limit
    if over.any():
        found.append(f"adhesion demand up to {r.adhesion_demand.max():.3f} exceeds the design limit "
                     f"{r.adhesion_limit:g} at {_ranges(r.speed, over)}")
    for kind, p in (("motor", r.p_motor), ("trailer", r.p_trailer)):
        if p is not None and (p > r.supply_pressure).any():
            mask = p > r.supply_pressure
            found.append(f"{kind} cylinder pressure up to {r.gauge_bar(p.max()):.2f} bar exceeds the "
                         f"supply {r.gauge_bar(r.supply_pressure):.2f} bar at {_ranges(r.speed, mask)}")
    below = r.deceleration < coast
    if below.any():
        found.append(f"demanded deceleration below the coasting deceleration (resistance alone) "
                     f"at {_ranges(r.speed, below)}: no brake needed there")
    return found


def brake_step(train, kind: str = "emergency") -> tuple:
    """(Profile, ed_blending) of the train's "emergency" or "service" brake step (train file)."""
    train = load_train(train)
    if kind not in ("emergency", "service"):
        raise InputError(f"kind = {kind!r}: must be emergency or service")
    step = train.brake_step(kind)
    try:
        return load_profile(step.profile), step.ed_blending
    except InputError as exc:
        raise InputError(f"train {train.name}: brake_steps.{kind}.profile: {exc}") from None


def _same_profile(a: Profile, b: Profile) -> bool:
    """The same profile however it was named (a preset, or a file the train's brake step names)."""
    return (a.name == b.name and a.speed.shape == b.speed.shape and np.array_equal(a.speed, b.speed)
            and np.array_equal(a.deceleration, b.deceleration))


def _profile_and_ed(train: Train, deceleration, ed, argument: str = "deceleration") -> tuple:
    """(profile, ED blending, why): the profile asked for (default: the train's emergency step) and
    whether the ED brake blends: as given, else as the train's brake step of that profile says,
    else not (pneumatic only: the ED brake is not counted on where no brake step says so)."""
    if ed is not None:
        ed = flag("ed", ed)
    if deceleration is None:
        profile, step_ed = brake_step(train, "emergency")
        if ed is not None:
            return profile, ed, "as asked"
        return profile, step_ed, "as the train's brake_steps.emergency.ed_blending says"
    profile = load_profile(deceleration, argument)
    if ed is not None:
        return profile, ed, "as asked"
    for kind in ("emergency", "service"):
        step = train.brake_step(kind)
        if step.profile == profile.name or _same_profile(brake_step(train, kind)[0], profile):
            return profile, step.ed_blending, f"as the train's brake_steps.{kind}.ed_blending says"
    return profile, False, "the profile is none of the train's brake steps"


def blending_text(result: "SizingResult") -> str:
    """Which brakes a sizing counts, and why: for the size command's title and JSON."""
    brakes = "ED brake blended first on the motor cars, pneumatic the rest" if result.ed_blending \
        else "pneumatic brake only (ED brake not counted)"
    return f"{brakes}: {result.ed_reason}"


def target_pressure(train, deceleration: Optional[ProfileLike] = None, speeds=None, gradient: float = 0.0,
                    adhesion_limit: float = ADHESION_LIMIT, ed: Optional[bool] = None) -> SizingResult:
    """Cylinder pressure per car type giving the demanded deceleration at each speed (m/s).

    train: a Train or preset name; deceleration: a profile (name, file, Profile or constant m/s^2;
    default: the train's emergency brake step); speeds: m/s (default: 0 to the top speed every
    5 km/h); gradient: rise/run, uphill positive; ed: ED brake first on the motor cars (default:
    as the train's brake step with this profile says, else off: pneumatic only).
    """
    train = load_train(train)
    profile, ed, why = _profile_and_ed(train, deceleration, ed)
    adhesion_limit = real("adhesion_limit", adhesion_limit, 0.0, 1.0, low_open=True)
    gradient = real("gradient", gradient)
    speed = _core.as_double_array(default_speeds(train, profile) if speeds is None
                                  else reals("speeds", speeds, 0.0)).ravel()
    decel = _core.as_double_array(profile.at(speed))
    n, cars = speed.size, len(train.cars)
    p_motor, p_trailer = np.empty(n), np.empty(n)
    adhesion = np.empty(n * cars)
    ed_force = np.empty(n)
    _core.call(_core.rb_size_target_pressure_ed, ctypes.byref(train.c), _core.ptr(speed), _core.ptr(decel),
               n, float(gradient), int(ed), _core.ptr(p_motor), _core.ptr(p_trailer), _core.ptr(ed_force),
               _core.ptr(adhesion))
    types = train.car_types()
    result = SizingResult(speed, decel, p_motor if "motor" in types else None,
                          p_trailer if "trailer" in types else None, ed_force, adhesion.reshape(n, cars),
                          train.atmospheric_pressure, train.supply_pressure, adhesion_limit, ed, why)
    coast = forward_deceleration(train, speed, np.full(n, train.atmospheric_pressure),
                                 np.full(n, train.atmospheric_pressure), ed_mode=_core.ED_OFF,
                                 gradient=gradient)
    result.warnings.extend(_warnings(train, result, coast))
    return result


class SupplyWarning(UserWarning):
    """A brake demand that needs more cylinder pressure than the brake supply gives."""


def supply_warnings(train, steps: dict, v0: float) -> list[str]:
    """Where the brake steps a run demands ({"emergency" or "service": fraction}) need more
    cylinder pressure than the supply gives from 0 to v0 (m/s), as `size` warns: there the
    train decelerates less than the step's profile."""
    train = load_train(train)
    found = []
    speeds = np.linspace(0.0, real("v0", v0, 0.0), _core.MAX_TABLE)
    instance("steps", steps, dict)
    for kind in steps:
        if kind not in ("emergency", "service"):
            raise InputError(f"steps: {kind!r}: not a brake step (emergency, service)")
    for kind, fraction in steps.items():
        profile, ed = brake_step(train, kind)
        if fraction != 1.0:
            profile = replace(profile, deceleration=profile.deceleration * real(f"{kind} fraction", fraction, 0.0, 1.0))
        sized = target_pressure(train, profile, speeds, ed=ed)
        for car_kind, p in (("motor", sized.p_motor), ("trailer", sized.p_trailer)):
            if p is not None and (p > sized.supply_pressure).any():
                found.append(f"{kind} brake{'' if fraction == 1.0 else f' at {fraction:g}'}: {car_kind} cylinder "
                             f"pressure up to {sized.gauge_bar(p.max()):.2f} bar exceeds the supply "
                             f"{sized.gauge_bar(sized.supply_pressure):.2f} bar at "
                             f"{_ranges(speeds, p > sized.supply_pressure)}: the train decelerates less than "
                             f"{profile.name} there")
    return found


@dataclass(frozen=True)
class CarDemand:
    """What the brake control unit needs to brake one car as the sizing does (C law
    rb_size_car_demand): brake force (N, ED plus pneumatic) at full demand over speed (m/s) and
    the pneumatic law solved for the pressure: p = threshold + pressure_per_newton * force."""

    speed: np.ndarray
    force: np.ndarray          # N
    pressure_per_newton: np.ndarray  # Pa/N
    threshold: float           # Pa abs


def demand_speeds(train: Train, profile: Profile) -> np.ndarray:
    """Up to MAX_TABLE speeds from 0 to the top speed: the profile's break points and an even grid."""
    points = profile.speed[profile.speed < train.max_speed]
    room = _core.MAX_TABLE - points.size - 1
    grid = np.linspace(0.0, train.max_speed, max(room, 2))
    speeds = np.unique(np.concatenate([points, grid, [train.max_speed]]))
    return speeds[np.linspace(0, speeds.size - 1, min(speeds.size, _core.MAX_TABLE)).round().astype(int)]


def car_demands(train, profile: ProfileLike) -> list:
    """Per car of the train, its CarDemand for the profile (load-weighed: the train's masses)."""
    train = load_train(train)
    prof = load_profile(profile)
    speed = _core.as_double_array(demand_speeds(train, prof))
    decel = _core.as_double_array(prof.at(speed))
    out = []
    for k in range(len(train.cars)):
        force, per_n, threshold = np.empty(speed.size), np.empty(speed.size), ctypes.c_double()
        _core.call(_core.rb_size_car_demand, ctypes.byref(train.c), k, _core.ptr(speed), _core.ptr(decel),
                   speed.size, 0.0, _core.ptr(force), _core.ptr(per_n), ctypes.byref(threshold))
        out.append(CarDemand(speed, force, per_n, threshold.value))
    return out


def forward_deceleration(train, speed, p_motor, p_trailer, ed_demand=None, ed_mode=None,
                         gradient: float = 0.0) -> np.ndarray:
    """Train deceleration (m/s^2) at speed (m/s) with absolute cylinder pressures (Pa) per type.

    ED: blended with the demanded deceleration ed_demand (m/s^2) when given, else off; ed_mode
    overrides (_core.ED_OFF, ED_MAX, ED_BLENDED). Pressures beyond the supply are refused.
    """
    train = load_train(train)
    speed = _core.as_double_array(reals("speed", speed, 0.0)).ravel()
    n = speed.size
    arrays = [_core.as_double_array(_broadcast(name, reals(name, x, 0.0), n))
              for name, x in (("p_motor", p_motor), ("p_trailer", p_trailer))]
    if ed_mode is None:
        ed_mode = _core.ED_OFF if ed_demand is None else _core.ED_BLENDED
    ed_mode = whole("ed_mode", ed_mode, min(_core.ED_OFF, _core.ED_MAX, _core.ED_BLENDED),
                    max(_core.ED_OFF, _core.ED_MAX, _core.ED_BLENDED))
    demand = _core.as_double_array(_broadcast("ed_demand", reals("ed_demand", 0.0 if ed_demand is None else ed_demand,
                                                                 0.0), n))
    gradient = real("gradient", gradient)
    out = np.empty(n)
    _core.call(_core.rb_train_deceleration_curve, ctypes.byref(train.c), _core.ptr(speed),
               _core.ptr(arrays[0]), _core.ptr(arrays[1]), int(ed_mode), _core.ptr(demand), n,
               float(gradient), _core.ptr(out))
    return out


def _broadcast(name: str, values: np.ndarray, n: int) -> np.ndarray:
    try:
        return np.broadcast_to(values, (n,))
    except ValueError:
        raise InputError(f"{name}: {values.size} values for {n} speeds (give one, or one per speed)") from None


# ------------------------------------------------------------------ stopping distance

@dataclass(frozen=True)
class StoppingResult:
    distance: float  # m
    time: float  # s
    curve_time: np.ndarray  # s
    curve_speed: np.ndarray  # m/s
    curve_distance: np.ndarray  # m
    warnings: list = field(default_factory=list)
    delay: Optional[float] = None     # s, ta used
    build_up: Optional[float] = None  # s, tb used
    simulated_response: bool = False  # ta, tb measured on the plant (simulation.response)
    max_disc_surface_temperature: Optional[float] = None   # K, hottest friction surface (a train's stop)


def _options(v0, v_end, gradient, delay, build_up, equivalent, dt, dt_out, t_max, gradients=()):
    """The C stop options; each argument a finite number (its range: rb_stop_options_check)."""
    o = _core.StopOptions(real("v0", v0), real("v_end", v_end), real("gradient", gradient), real("delay", delay),
                          real("build_up", build_up), int(flag("equivalent_response", equivalent)),
                          real("dt", dt, 0.0, low_open=True), real("dt_out", dt_out, 0.0, low_open=True),
                          real("t_max", t_max, 0.0, low_open=True))
    if isinstance(gradients, (str, bytes)) or not hasattr(gradients, "__len__"):
        raise TypeError(f"gradients = {gradients!r}: must be a list of (start m, rise/run) pairs")
    if o.t_max / o.dt > MAX_STOP_STEPS or o.t_max / o.dt_out > MAX_CURVE_POINTS:   # before the loop and the arrays
        raise InputError(f"t_max = {o.t_max:g} s: at dt = {o.dt:g} s and dt_out = {o.dt_out:g} s more than "
                         f"{MAX_STOP_STEPS:.0e} steps or {MAX_CURVE_POINTS:.0e} curve points: shorten t_max or "
                         "lengthen dt, dt_out")
    if len(gradients) > _core.MAX_STOP_GRADIENTS:
        raise InputError(f"gradients: {len(gradients)} pieces, at most {_core.MAX_STOP_GRADIENTS}")
    o.n_gradients = len(gradients)
    for i, (start, value) in enumerate(gradients):
        o.gradient_start[i], o.gradient_value[i] = float(start), float(value)
    return o


def train_length(train: Train) -> float:
    """m over couplers: the sum of the cars' lengths (train file)."""
    return float(sum(car.equipment.length_m for car in train.cars))


def _run(function, first, options, t_max, dt_out, last=()) -> tuple:
    capacity = int(t_max / dt_out) + 4
    t, v, s = np.empty(capacity), np.empty(capacity), np.empty(capacity)
    n, dist, time = ctypes.c_size_t(), ctypes.c_double(), ctypes.c_double()
    _core.call(function, *first, ctypes.byref(options), _core.ptr(t), _core.ptr(v), _core.ptr(s),
               capacity, ctypes.byref(n), ctypes.byref(dist), ctypes.byref(time), *last)
    k = n.value
    return dist.value, time.value, t[:k].copy(), v[:k].copy(), s[:k].copy()


def _pressure_command(train: Train, profile: Profile, v0: float, ed: bool):
    """Target pressures over 0..v0 as tables, limited to the supply (with a warning). Sized on
    level track, as the BCU does (it does not know the gradient)."""
    speeds = np.linspace(0.0, v0, _core.MAX_TABLE)
    sized = target_pressure(train, profile, speeds, ed=ed)
    warnings = list(sized.warnings)
    cmd = _core.BrakeCommand()
    for kind, p in (("motor", sized.p_motor), ("trailer", sized.p_trailer)):
        if p is None:
            continue
        if (p > sized.supply_pressure).any():
            warnings.append(f"{kind} target pressure limited to the supply "
                            f"{sized.gauge_bar(sized.supply_pressure):.2f} bar: the train decelerates "
                            "less than the profile there")
        setattr(cmd, f"p_{kind}", _core.speed_table(speeds, np.minimum(p, sized.supply_pressure)))
    cmd.ed_mode = _core.ED_BLENDED if ed else _core.ED_OFF
    cmd.ed_demand = profile.table()
    return cmd, warnings


def stopping_distance(v0: float, train=None, profile: Optional[ProfileLike] = None,
                      deceleration: Optional[float] = None, response_time: Optional[float] = None,
                      delay: Optional[float] = None, build_up: Optional[float] = None,
                      equivalent_response: bool = True, gradient: float = 0.0, v_end: float = 0.0,
                      dt: float = 0.01, dt_out: float = 0.5, t_max: float = 3600.0,
                      ed: Optional[bool] = None, gradients=()) -> StoppingResult:
    """Stopping distance and time from v0 (m/s), integrated in C in the EN 14531 manner.

    With a train: the target pressures of `profile` (default: the train's emergency brake step;
    limited to the supply) and, where the step blends it (ed), the ED brake act on the whole train
    with resistance, gradient and rotary inertia. Without a train:
    the profile's (or the constant `deceleration`'s) deceleration itself, no resistance.
    Response: delay ta and build-up tb (default: the profile's); response_time sets te directly.
    railbrake.simulation.stopping_distance gives a train its own build-up, measured on the plant,
    as `railbrake stopping-distance` does.
    equivalent_response=True steps the brake on at te = ta + tb/2, False ramps it over tb.
    gradients: a piecewise gradient instead of `gradient`, (start m, rise/run) pairs along the
    track from the train's front at the brake's start (as a scenario's track.gradients), applied
    at the middle of the train (so each start moves back by half the train's length).
    """
    v0 = real("v0", v0, 0.0)
    if response_time is not None:
        response_time = real("response_time", response_time, 0.0, real("t_max", t_max, 0.0, low_open=True))
    trained = None if train is None else load_train(train)
    if deceleration is not None:
        prof, ed = load_profile(real("deceleration", deceleration), "deceleration"), bool(ed)
    elif trained is not None:
        prof, ed, _ = _profile_and_ed(trained, profile, ed, "profile")
    else:
        prof = load_profile("emergency" if profile is None else profile)
    ta = prof.delay if delay is None else delay
    tb = prof.build_up if build_up is None else build_up
    if response_time is not None:
        ta, tb = response_time, 0.0
    half = 0.5 * train_length(trained) if trained is not None else 0.0
    pieces = [(real(f"gradients[{i}] start", piece[0]) + half, real(f"gradients[{i}] gradient", piece[1]))
              for i, piece in enumerate(_pairs("gradients", gradients))]
    options = _options(v0, v_end, gradient, ta, tb, equivalent_response, dt, dt_out, t_max, pieces)
    if train is None:
        table = prof.table()
        result = _run(_core.rb_stop_profile, (ctypes.byref(table),), options, t_max, dt_out)
        return StoppingResult(*result, delay=ta, build_up=tb)
    cmd, warnings = _pressure_command(trained, prof, v0, ed)
    # the pads fade with their discs' heat as in the plant (rb_stop_train_heated)
    discs, hottest = train_discs(trained), ctypes.c_double()
    result = _run(_core.rb_stop_train_heated, (ctypes.byref(trained.c), ctypes.byref(cmd), ctypes.byref(discs)),
                  options, t_max, dt_out, (ctypes.byref(hottest),))
    return StoppingResult(*result, warnings=warnings, delay=ta, build_up=tb,
                          max_disc_surface_temperature=hottest.value)


def _pairs(name: str, pairs) -> list:
    if isinstance(pairs, (str, bytes)) or not hasattr(pairs, "__iter__"):
        raise TypeError(f"{name} = {pairs!r}: must be a list of (start m, rise/run) pairs")
    pairs = list(pairs)
    for i, pair in enumerate(pairs):
        if isinstance(pair, (str, bytes)) or not hasattr(pair, "__len__") or len(pair) != 2:
            raise TypeError(f"{name}[{i}] = {pair!r}: must be a (start m, rise/run) pair")
    return pairs


def coast_down(train, v0: float, v_end: float, gradient: float = 0.0, dt: float = 0.05,
               dt_out: float = 5.0, t_max: float = 2e4) -> StoppingResult:
    """Resistance-only run-down from v0 to v_end (m/s): no brake at all."""
    train = load_train(train)
    options = _options(v0, v_end, gradient, 0.0, 0.0, True, dt, dt_out, t_max)
    cmd = _core.BrakeCommand()
    return StoppingResult(*_run(_core.rb_stop_train, (ctypes.byref(train.c), ctypes.byref(cmd)),
                                options, t_max, dt_out))


def stopping_distance_constant(v0: float, deceleration: float, response_time: float) -> tuple:
    """Hand check (C): v0 te + v0^2 / (2 a) and te + v0 / a."""
    s, t = ctypes.c_double(), ctypes.c_double()
    _core.call(_core.rb_stop_constant, real("v0", v0), real("deceleration", deceleration),
               real("response_time", response_time),
               ctypes.byref(s), ctypes.byref(t))
    return s.value, t.value
