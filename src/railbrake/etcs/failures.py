"""Failure states of a whole train from its reliability file, counted exactly.

Every failure of the file hits each of its sites (a car, each bogie or each axle of every car, or
the train's air supply) independently with its probability per demand. A car's failures are
therefore a *car configuration*: the set of (failure, site) pairs that failed on it, with the
probability of exactly that set (two failures on one axle only with the product of their
probabilities). A train state gives each car its configuration: the failed sites of every kind
land on distinct units exactly as often as the independent draws put them there.

Symmetry, used only where it holds. On dry rail every axle brakes below its adhesion, so the train's
deceleration depends on the sum of its brake forces, not on where a force is lost: cars of one type
that no common-cause group tells apart are equivalent (a class), and so are the configurations of
one car that differ by a permutation of its axles keeping its bogies (swapping the axles of a
bogie, swapping the bogies). A class outcome says how many of its cars have each (canonical)
configuration: the multinomial law. A common-cause group is an event of its own (it happened or
not); cars in different groups are in different classes, so a state never places an independent
failure on a car a group already names unless the draws do.

States are enumerated depth-first, a branch pruned when no completion can reach the floor; what is
left out counts as no brake at all (railbrake.etcs.mixture.quantile).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from railbrake import _core
from railbrake.errors import InputError
from railbrake.etcs.inputs import CAR_KINDS, TRAIN_KINDS, ReliabilityFile

MAX_STATES = 5000    # states run (each with its scatter sample): a bound before anything is allocated
MAX_CONFIGURATIONS = 5000   # per car class
AXLES = _core.AXLES_PER_CAR
# the axle permutations of a car that keep its bogies (axles 0-1 and 2-3): identity, either
# bogie's axles swapped, both, and the same with the bogies swapped
CAR_SYMMETRY = ((0, 1, 2, 3), (1, 0, 2, 3), (0, 1, 3, 2), (1, 0, 3, 2),
                (2, 3, 0, 1), (3, 2, 0, 1), (2, 3, 1, 0), (3, 2, 1, 0))
assert AXLES == 4, "CAR_SYMMETRY is that of a car of two two-axle bogies"


@dataclass(frozen=True)
class Unit:
    car: int           # 0-based
    axle: int          # 0..3, -1: every axle of the car (or the train's air supply)


@dataclass(frozen=True, order=True)
class Site:
    """One unit a failure of the file can hit within a car: `failure` indexes the file's failures,
    `position` is -1 (the car), a bogie's first axle (0, 2) or an axle (0..3)."""
    failure: int
    position: int


@dataclass(frozen=True)
class CarClass:
    """Cars of one type that the same common-cause groups name (equivalent on dry rail)."""
    name: str
    cars: tuple                  # 0-based, formation order
    options: tuple               # ((counts per configuration), probability), most likely first
    configurations: tuple        # canonical configurations: tuples of Site, () = no failure


@dataclass(frozen=True)
class TrainState:
    probability: float
    outcome: tuple               # per class, its option index; then one 0/1 per common-cause event
    faults: tuple                # (kind, Unit, value) of every fault, at most once each
    label: str


def _sites(reliability: ReliabilityFile) -> tuple[list, list]:
    """(per-car sites, train sites) of the file's failures with a non-zero probability."""
    car, train = [], []
    for i, f in enumerate(reliability.failures):
        if f.probability() == 0.0:
            continue
        if f.unit == "train":
            train.append(Site(i, -1))
        elif f.unit == "car":
            car.append(Site(i, -1))
        else:
            car += [Site(i, a) for a in range(0, AXLES, 2 if f.unit == "bogie" else 1)]
    return car, train


def _image(site: Site, perm: tuple, unit: str) -> Site:
    if site.position < 0:
        return site
    a = perm[site.position]
    return Site(site.failure, a - a % 2 if unit == "bogie" else a)


def canonical(config: tuple, reliability: ReliabilityFile) -> tuple:
    """The least of a configuration's images under the car's symmetry (CAR_SYMMETRY)."""
    units = [f.unit for f in reliability.failures]
    return min(tuple(sorted(_image(s, perm, units[s.failure]) for s in config)) for perm in CAR_SYMMETRY)


def car_configurations(sites: list, reliability: ReliabilityFile, floor: float) -> list[tuple[tuple, float]]:
    """(canonical configuration, probability) of one car, down to `floor`, most likely first: the
    probabilities of a configuration's images summed (each image a distinct set of failed sites)."""
    p = [reliability.failures[s.failure].probability() for s in sites]
    out: dict[tuple, float] = {}

    def walk(i: int, chosen: tuple, prob: float) -> None:
        # prob: that the chosen sites failed and those before i not chosen did not (the rest free)
        if prob < floor:
            return
        if i == len(sites):
            if len(out) >= MAX_CONFIGURATIONS and canonical(chosen, reliability) not in out:
                raise InputError(f"more than {MAX_CONFIGURATIONS} failure configurations of a car above the floor "
                                 f"{floor:g}: raise the floor or check the failure probabilities")
            key = canonical(chosen, reliability)
            out[key] = out.get(key, 0.0) + prob
            return
        if p[i] >= 1.0:
            walk(i + 1, chosen + (sites[i],), prob)
            return
        walk(i + 1, chosen, prob * (1.0 - p[i]))
        walk(i + 1, chosen + (sites[i],), prob * p[i])

    if sites:
        walk(0, (), 1.0)
    else:
        out[()] = 1.0
    return sorted(out.items(), key=lambda kv: -kv[1])


def class_outcomes(n: int, configs: list[tuple[tuple, float]], floor: float) -> list[tuple[tuple, float]]:
    """(counts per configuration, probability) of n equivalent cars, each with a configuration
    independently: the multinomial law, down to `floor`. A branch is cut when the probability that
    at least its counts occur (bounded by sum over the labelled cars: n! / (prod k! (n - sum k)!)
    prod q^k) is below the floor: no completion can then reach it."""
    q = [p for _, p in configs]
    free = [i for i, (c, _) in enumerate(configs) if c != ()]
    empty = next((i for i, (c, _) in enumerate(configs) if c == ()), None)
    out = []

    def walk(j: int, counts: list, bound: float, used: int) -> None:
        if bound < floor:
            return
        if j == len(free):
            rest = n - used
            if rest and empty is None:
                return   # every car must have some configuration; none left to give the rest
            full = counts[:]
            if empty is not None:
                full[empty] = rest
            logp = math.lgamma(n + 1) + sum(k * math.log(q[i]) - math.lgamma(k + 1)
                                            for i, k in enumerate(full) if k)
            prob = math.exp(logp)
            if prob >= floor:
                out.append((tuple(full), prob))
            return
        i = free[j]
        k, b = 0, bound
        while used + k <= n and b >= floor:
            counts[i] = k
            walk(j + 1, counts, b, used + k)
            b *= (n - used - k) * q[i] / (k + 1)
            k += 1
        counts[i] = 0

    walk(0, [0] * len(configs), 1.0, 0)
    return sorted(out, key=lambda kp: -kp[1])


def car_classes(reliability: ReliabilityFile, train, floor: float) -> list[CarClass]:
    """The train's car classes with their outcomes down to `floor`."""
    sites, _ = _sites(reliability)
    n = len(train.cars)
    named = [set(range(n)) if g.cars == "all" else {c - 1 for c in g.cars} for g in reliability.common_cause]
    groups: dict[tuple, list[int]] = {}
    for car in train.cars:
        key = (car.type_name, tuple(i for i, s in enumerate(named) if car.index in s))
        groups.setdefault(key, []).append(car.index)
    configs_of = {}
    out = []
    for (type_name, cc), cars in groups.items():
        if type_name not in configs_of:
            configs_of[type_name] = car_configurations(sites, reliability, floor)
        configs = configs_of[type_name]
        name = type_name + (" in " + ", ".join(reliability.common_cause[i].name for i in cc) if cc else "")
        out.append(CarClass(name, tuple(cars), tuple(class_outcomes(len(cars), configs, floor)),
                            tuple(c for c, _ in configs)))
    return out


def _unit_faults(config: tuple, car: int, reliability: ReliabilityFile) -> list:
    out = []
    for s in config:
        f = reliability.failures[s.failure]
        axles = [-1] if s.position < 0 else ([s.position, s.position + 1] if f.unit == "bogie" else [s.position])
        out += [(f.kind, Unit(car, a), f.value_si()) for a in axles]
    return out


def common_units(reliability: ReliabilityFile, train) -> list[tuple[str, tuple]]:
    """Each common-cause group's kind and units (a car kind's car, every axle of a car: axle -1)."""
    n = len(train.cars)
    out = []
    for g in reliability.common_cause:
        if g.cars != "all" and max(g.cars) > n:
            raise InputError(f"common_cause {g.name!r}: cars = {g.cars}: the train has {n} cars")
        cars = range(n) if g.cars == "all" else [c - 1 for c in g.cars]
        out.append((g.kind, tuple(Unit(0 if g.kind in TRAIN_KINDS else c, -1) for c in cars)))
    return out


def _describe(config: tuple, reliability: ReliabilityFile) -> str:
    def where(s):
        unit = reliability.failures[s.failure].unit
        return unit if s.position < 0 else f"{unit} {s.position // 2 + 1 if unit == 'bogie' else s.position + 1}"
    return " + ".join(f"{reliability.failures[s.failure].kind} ({where(s)})" for s in config)


def enumerate_states(reliability: ReliabilityFile, train, floor: float) -> tuple[list, list, list]:
    """(car classes, common-cause units, states) of the train, its states down to `floor`, most
    likely first."""
    if not 0.0 < floor < 1.0:
        raise InputError(f"state floor = {floor!r}: must lie in (0, 1)")
    classes = car_classes(reliability, train, floor)
    common = common_units(reliability, train)
    _, train_sites = _sites(reliability)
    options = [list(enumerate(p for _, p in c.options)) for c in classes]
    train_p = [reliability.failures[s.failure].probability() for s in train_sites]
    options += [[(0, 1.0 - p), (1, p)] for p in train_p]
    options += [[(0, 1.0 - g.per_demand), (1, g.per_demand)] for g in reliability.common_cause]
    options = [sorted((kp for kp in o if kp[1] > 0.0), key=lambda kp: -kp[1]) for o in options]
    best_rest = [1.0] * (len(options) + 1)
    for i in range(len(options) - 1, -1, -1):
        best_rest[i] = best_rest[i + 1] * (options[i][0][1] if options[i] else 0.0)
    states = []

    def walk(i: int, chosen: tuple, p: float) -> None:
        if p * best_rest[i] < floor:
            return
        if i == len(options):
            if len(states) >= MAX_STATES:
                raise InputError(f"more than {MAX_STATES} failure states above the floor {floor:g}: "
                                 "raise the floor or check the failure probabilities")
            states.append(_state(classes, train_sites, common, reliability, chosen, p))
            return
        for k, pk in options[i]:
            walk(i + 1, chosen + (k,), p * pk)

    walk(0, (), 1.0)
    states.sort(key=lambda s: -s.probability)
    for s in states:
        if len(plant_faults(s)) > _core.MAX_FAULTS:
            raise InputError(f"failure state {s.label}: {len(plant_faults(s))} faults; the plant takes at most "
                             f"{_core.MAX_FAULTS} in one run")
    return classes, common, states


def _state(classes: list, train_sites: list, common: list, reliability: ReliabilityFile, chosen: tuple,
           p: float) -> TrainState:
    faults, parts = [], []
    for c, o in zip(classes, chosen):
        counts = c.options[o][0]
        cars = iter(c.cars)
        for config, k in zip(c.configurations, counts):
            placed = [next(cars) for _ in range(k)]
            if config and k:
                faults += [fault for car in placed for fault in _unit_faults(config, car, reliability)]
                parts.append(f"{k} x [{_describe(config, reliability)}] ({c.name})")
    rest = chosen[len(classes):]
    for s, happened in zip(train_sites, rest):
        if happened:
            f = reliability.failures[s.failure]
            faults.append((f.kind, Unit(0, -1), f.value_si()))
            parts.append(f.kind)
    cc_faults = []
    for (kind, units), g, happened in zip(common, reliability.common_cause, rest[len(train_sites):]):
        if happened:
            cc_faults += [(kind, u, 0.0) for u in units]
            parts.append(g.name)
    return TrainState(p, tuple(chosen), _merge(faults, cc_faults), ", ".join(parts) or "no failure")


def _merge(independent: list, common: list) -> tuple:
    """The faults of a demand, each once: a common-cause group's kind fails every unit of its cars,
    so an independent fault of that kind on one of them adds nothing."""
    covered = {(k, u.car) for k, u, _ in common}
    return tuple(dict.fromkeys([f for f in independent if (f[0], f[1].car) not in covered] + common))


def draw(reliability: ReliabilityFile, train, common: list, rng) -> list:
    """One demand's faults drawn unit by unit (each site of each car, each train site, each
    common-cause event independently): the brute force's draw, without any symmetry."""
    sites, train_sites = _sites(reliability)
    faults = []
    for car in train.cars:
        hit = rng.random(len(sites)) < [reliability.failures[s.failure].probability() for s in sites]
        faults += _unit_faults(tuple(s for s, h in zip(sites, hit) if h), car.index, reliability)
    for s in train_sites:
        if rng.random() < reliability.failures[s.failure].probability():
            f = reliability.failures[s.failure]
            faults.append((f.kind, Unit(0, -1), f.value_si()))
    cc_faults = []
    for (kind, units), g in zip(common, reliability.common_cause):
        if rng.random() < g.per_demand:
            cc_faults += [(kind, u, 0.0) for u in units]
    return list(_merge(faults, cc_faults))


def plant_faults(state_or_faults) -> list:
    """A state's (or a list of (kind, unit, value)) faults as the plant's rb_fault structs, all
    present from the demand on."""
    faults = state_or_faults.faults if isinstance(state_or_faults, TrainState) else state_or_faults
    index = {name: i for i, name in enumerate(_core.FAULT_KINDS)}
    return [_core.Fault(index[kind], u.car, u.axle, 0.0, value) for kind, u, value in faults]


def set_faults(plant, faults: list) -> None:
    """The plant's faults (rb_plant_params.fault) set to `faults` (at most MAX_FAULTS, checked)."""
    if len(faults) > _core.MAX_FAULTS:
        raise InputError(f"{len(faults)} faults; the plant takes at most {_core.MAX_FAULTS} in one run")
    plant.n_faults = len(faults)
    for i, f in enumerate(faults):
        plant.fault[i] = f


__all__ = ["CAR_KINDS", "CarClass", "Site", "TrainState", "Unit", "canonical", "car_classes",
           "car_configurations", "class_outcomes", "common_units", "draw", "enumerate_states", "plant_faults",
           "set_faults"]
