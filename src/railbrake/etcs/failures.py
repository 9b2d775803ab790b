"""Failure states of a whole train from its reliability file, enumerated with the train's symmetry.

Every fault of the file hits each of its units (cars, bogies or axles of the train) independently
with the same probability. On dry rail the train's deceleration depends on the sum of its brake
forces, not on where along the train a force is lost, so units of one car type are equivalent: a
class is (fault, car type), and a state says how many units of each class failed (k of n: the
binomial law, railbrake.etcs.states), plus which common-cause events happened. A state runs once,
its failed units placed on the first units of their class.

States are enumerated depth-first, a branch pruned when even its most likely completion falls
below the floor; what is left out counts as no brake at all (railbrake.etcs.mixture.quantile).
"""

from __future__ import annotations

from dataclasses import dataclass

from scipy.stats import binom

from railbrake import _core
from railbrake.errors import InputError
from railbrake.etcs.inputs import CAR_KINDS, ReliabilityFile

MAX_STATES = 5000    # states run (each with its scatter sample): a bound before anything is allocated


@dataclass(frozen=True)
class Unit:
    car: int           # 0-based
    axle: int          # 0..3, -1: every axle of the car (or the train's air supply)


@dataclass(frozen=True)
class FaultClass:
    kind: str
    value: float       # SI (leak area, noise), 0 if none
    car_type: str
    units: tuple       # of Unit, in formation order
    probability: float
    span: int = 1      # axles a unit covers from its own on (a bogie: 2)


@dataclass(frozen=True)
class TrainState:
    probability: float
    lost: tuple        # units failed per class
    common: tuple      # 1 per common-cause event that happened
    label: str

    def faults(self, classes: list, common_units: list) -> list[tuple[str, Unit, float]]:
        """(kind, unit, value) of every fault of the state."""
        out = [(c.kind, Unit(u.car, u.axle + a), c.value) for c, k in zip(classes, self.lost)
               for u in c.units[:k] for a in range(c.span)]
        for (kind, units), happened in zip(common_units, self.common):
            if happened:
                out += [(kind, u, 0.0) for u in units]
        return out


def _units(unit: str, car: int) -> list[Unit]:
    """A car's units: the car, its bogies (by their first axle) or its axles."""
    if unit == "car":
        return [Unit(car, -1)]
    step = 2 if unit == "bogie" else 1
    return [Unit(car, a) for a in range(0, _core.AXLES_PER_CAR, step)]


def classes(reliability: ReliabilityFile, train) -> list[FaultClass]:
    """The fault classes of a train (vehicle.Train): each failure of the file per car type."""
    out = []
    for f in reliability.failures:
        p = f.probability()
        if p == 0.0:
            continue
        if f.unit == "train":
            out.append(FaultClass(f.kind, f.value_si(), "train", (Unit(0, -1),), p))
            continue
        for type_name in dict.fromkeys(c.type_name for c in train.cars):
            cars = [c.index for c in train.cars if c.type_name == type_name]
            units = tuple(u for c in cars for u in _units(f.unit, c))
            out.append(FaultClass(f.kind, f.value_si(), type_name, units, p, 2 if f.unit == "bogie" else 1))
    return out


def common_units(reliability: ReliabilityFile, train) -> list[tuple[str, tuple]]:
    n = len(train.cars)
    out = []
    for g in reliability.common_cause:
        cars = range(n) if g.cars == "all" else [c - 1 for c in g.cars]
        if g.cars != "all" and max(g.cars) > n:
            raise InputError(f"common_cause {g.name!r}: cars = {g.cars}: the train has {n} cars")
        axles = [-1] if g.kind in CAR_KINDS or g.kind == "compressor_off" else range(_core.AXLES_PER_CAR)
        out.append((g.kind, tuple(Unit(c, a) for c in cars for a in axles)))
    return out


def enumerate_states(reliability: ReliabilityFile, train, floor: float) -> tuple[list, list, list]:
    """(classes, common-cause units, states) of the train, its states down to `floor`, most
    likely first."""
    if not 0.0 < floor < 1.0:
        raise InputError(f"state floor = {floor!r}: must lie in (0, 1)")
    cls = classes(reliability, train)
    common = common_units(reliability, train)
    q = [g.per_demand for g in reliability.common_cause]
    # per class and event its outcomes with probabilities, most likely first
    options = [[(k, float(binom.pmf(k, len(c.units), c.probability))) for k in range(len(c.units) + 1)] for c in cls]
    options += [[(0, 1.0 - p), (1, p)] for p in q]
    options = [sorted(o, key=lambda kp: -kp[1]) for o in options]
    best_rest = [1.0] * (len(options) + 1)
    for i in range(len(options) - 1, -1, -1):
        best_rest[i] = best_rest[i + 1] * options[i][0][1]
    states = []

    def walk(i: int, chosen: tuple, p: float) -> None:
        if p * best_rest[i] < floor:
            return
        if i == len(options):
            if len(states) >= MAX_STATES:
                raise InputError(f"more than {MAX_STATES} failure states above the floor {floor:g}: "
                                 "raise the floor or check the failure probabilities")
            states.append(_state(cls, reliability, chosen, p))
            return
        for k, pk in options[i]:
            if pk > 0.0:
                walk(i + 1, chosen + (k,), p * pk)

    walk(0, (), 1.0)
    states.sort(key=lambda s: -s.probability)
    for s in states:
        n_faults = len(s.faults(cls, common))
        if n_faults > _core.MAX_FAULTS:
            raise InputError(f"failure state {s.label}: {n_faults} faults; the plant takes at most "
                             f"{_core.MAX_FAULTS} in one run")
    return cls, common, states


def _state(cls: list, reliability: ReliabilityFile, chosen: tuple, p: float) -> TrainState:
    lost, common = chosen[:len(cls)], chosen[len(cls):]
    parts = [f"{k} {c.kind} ({c.car_type})" for c, k in zip(cls, lost) if k]
    parts += [g.name for g, happened in zip(reliability.common_cause, common) if happened]
    return TrainState(p, tuple(lost), tuple(common), ", ".join(parts) or "no failure")


def plant_faults(state: TrainState, cls: list, common: list) -> list:
    """The state's faults as the plant's rb_fault structs, all present from the demand on."""
    index = {name: i for i, name in enumerate(_core.FAULT_KINDS)}
    return [_core.Fault(index[kind], u.car, u.axle, 0.0, value) for kind, u, value in state.faults(cls, common)]



def set_faults(plant, faults: list) -> None:
    """The plant's faults (rb_plant_params.fault) set to `faults` (at most MAX_FAULTS, checked)."""
    if len(faults) > _core.MAX_FAULTS:
        raise InputError(f"{len(faults)} faults; the plant takes at most {_core.MAX_FAULTS} in one run")
    plant.n_faults = len(faults)
    for i, f in enumerate(faults):
        plant.fault[i] = f
