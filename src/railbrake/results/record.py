"""One run's result in the form every output is made from: the time series (SI), their units, the
KPIs and what was run (scenario, train, faults, adhesion zones, demand steps, configuration,
provenance). MIL simulations, HIL runs and saved files all become a RunRecord."""

from __future__ import annotations

import math

import ctypes
import re
from dataclasses import dataclass, field

import numpy as np

from railbrake.errors import InputError
from railbrake.units import cars_text

_AXLE = re.compile(r"^c(\d+)a(\d+)$")
# Result.meta key: how long a healthy brake of the run's train stays short of its demand in its own
# build-up (simulation.response.healthy_shortfall), the reference of the air-shortfall warning
HEALTHY_SHORTFALL = "healthy_cylinder_shortfall_s"


@dataclass
class RunRecord:
    time: np.ndarray
    outputs: dict            # channel name -> samples (SI), "time" included
    units: dict              # channel name -> SI unit
    kpis: dict
    meta: dict = field(default_factory=dict)

    # ---- what was run
    @property
    def atmosphere(self) -> float:
        """Pa, the run's atmospheric pressure (gauge pressures in plots); files without it: the
        standard atmosphere."""
        from railbrake.vehicle import P_ATM
        value = float(self.meta.get("atmosphere_pa") or "nan")
        return value if math.isfinite(value) else P_ATM

    @property
    def kind(self) -> str:
        return self.meta.get("kind", "MIL")

    @property
    def cars(self) -> int:
        return int(self.meta.get("cars") or len(self.car_names()))

    @property
    def wsp(self) -> bool:
        return bool(self.meta.get("wsp", True))

    def title(self) -> str:
        """'fault-vent-valve-stuck (MIL): crh380a-8, 8 cars, WSP on'."""
        m = self.meta
        train = f"{m['train']}, " if m.get("train") else ""
        return (f"{m.get('scenario', 'run')} ({self.kind}): {train}{cars_text(self.cars)}, "
                f"WSP {'on' if self.wsp else 'off'}")

    # ---- channels
    def axle_names(self) -> list[str]:
        """'c1a1', 'c1a2', ... in train order, from the wheel-speed channels."""
        names = [n[len("wheel_speed_"):] for n in self.outputs if n.startswith("wheel_speed_c")]
        return sorted(names, key=axle_key)

    def car_names(self) -> list[str]:
        return sorted({"c" + str(axle_key(a)[0]) for a in self.axle_names()}, key=lambda c: int(c[1:]))

    def channel(self, quantity: str, where: str) -> np.ndarray | None:
        return self.outputs.get(f"{quantity}_{where}")

    def faulty_axles(self) -> list[list[str]]:
        """Per scenario fault, the axles it acts on (a fault on a whole car: each of its axles)."""
        known = self.axle_names()
        groups = []
        for f in self.meta.get("faults", []):
            if f.get("axle") is not None:
                groups.append([a for a in [f"c{f['car']}a{f['axle']}"] if a in known])
            else:
                groups.append([a for a in known if axle_key(a)[0] == f["car"]])
        return [g for g in groups if g]

    def braking_start(self) -> float:
        """s: the first demand step that brakes (0 without demand information)."""
        for d in self.meta.get("demand", []):
            if d.get("emergency") or d.get("service", 0) > 0:
                return float(d["time"])
        return float(self.time[0]) if len(self.time) else 0.0


def axle_key(name: str) -> tuple[int, int]:
    m = _AXLE.match(name)
    return (int(m.group(1)), int(m.group(2))) if m else (0, 0)


def axles_of(n_cars: int) -> list[str]:
    return [f"c{c}a{a}" for c in range(1, n_cars + 1) for a in range(1, 5)]


def parse_axles(text: str | None, record: RunRecord | int, option: str = "--axles") -> list[str]:
    """'c3a2,c1a1' -> ['c3a2', 'c1a1'], each an axle of the record (or of a train of that many cars)."""
    if not text:
        return []
    known = axles_of(record) if isinstance(record, int) else record.axle_names()
    axles = []
    for item in (s.strip().lower() for s in text.split(",")):
        if item not in known:
            raise InputError(f"{option} = {text!r}: {item!r} is not an axle of this run "
                             f"(c1a1 .. {known[-1] if known else 'none'}: car 1..{len(known) // 4}, axle 1..4)")
        axles.append(item)
    return list(dict.fromkeys(axles))


def parse_window(text: str | None, record: RunRecord | None = None, option: str = "--window"):
    """'40:50' -> (40.0, 50.0) s, inside the recorded time when a record is given."""
    if not text:
        return None
    parts = text.split(":")
    try:
        t0, t1 = (float(p) for p in parts)
    except ValueError:
        raise InputError(f"{option} = {text!r}: expected T0:T1 in s, e.g. 40:50") from None
    if not t1 > t0 or not np.isfinite([t0, t1]).all():
        raise InputError(f"{option} = {text!r}: T1 must be finite and greater than T0")
    if record is not None and len(record.time):
        first, last = float(record.time[0]), float(record.time[-1])
        if t1 <= first or t0 >= last:
            raise InputError(f"{option} = {text!r}: outside the recorded time {first:g} .. {last:g} s")
    return t0, t1


# ------------------------------------------------------------------ from runs

def _scenario_meta(sc) -> dict:
    """What was run, by name: files by their name, not the folders they lie in on this machine."""
    from railbrake.results.config_file import display_name
    spec = sc.spec
    return {"scenario": sc.name, "title": spec.title, "train": display_name(spec.train.preset),
            "condition": display_name(spec.adhesion.condition),
            "zones": [{"start": z.start, "end": z.end, "condition": display_name(z.condition)}
                      for z in spec.adhesion.zones],
            "demand": [{"time": d.time, "emergency": d.emergency, "service": d.service} for d in spec.demand],
            "faults": [{"type": f.type, "car": f.car, "axle": f.axle, "start": f.start,
                        **f.model_dump(include={"noise", "leak_area", "pressure"}, exclude_none=True)}
                       for f in spec.faults]}


def _struct_dict(struct) -> dict:
    return {name: getattr(struct, name) for name, kind in struct._fields_
            if kind in (ctypes.c_double, ctypes.c_int)}


def configuration(sc, cars: int, wsp: bool) -> dict:
    """The configuration a run resolved to: the scenario as validated (SI) and the WSP parameters."""
    from railbrake.simulation.parameters import wsp_params
    return {"scenario": sc.spec.model_dump(mode="json", by_alias=True), "cars": cars, "wsp_enabled": wsp,
            "wsp_parameters": _struct_dict(wsp_params(sc))}


def _check_record_args(result, fields: tuple, kind: str, sc, command_line) -> None:
    """result has what a record reads (its class is a layer above this one: not imported here)."""
    from railbrake import _args
    from railbrake.scenario import Scenario
    missing = [f for f in fields if not hasattr(result, f)]
    if missing:
        raise TypeError(f"result = {_args.show(result)}: must be {kind} (no {', '.join(missing)})")
    _args.instance("sc", sc, Scenario)
    if command_line is not None:
        _args.items("command_line", command_line, str, low=0)


def from_simulation(result, sc, command_line: list[str] | None = None) -> RunRecord:
    """A MIL result (railbrake.simulation.Result) of Scenario sc."""
    from railbrake.results.provenance import provenance
    _check_record_args(result, ("time", "outputs", "units", "kpis", "cars", "wsp"), "a run's Result", sc, command_line)
    meta = _scenario_meta(sc) | {"kind": "MIL", "cars": result.cars, "wsp": result.wsp,
                                 "atmosphere_pa": result.atmosphere,
                                 "configuration": getattr(result, "configuration", None)
                                 or configuration(sc, result.cars, result.wsp),
                                 "provenance": provenance(command_line)}
    if HEALTHY_SHORTFALL in result.meta:   # the reference the run's warnings were judged on
        meta[HEALTHY_SHORTFALL] = result.meta[HEALTHY_SHORTFALL]
    return RunRecord(np.asarray(result.time), dict(result.outputs), dict(result.units), dict(result.kpis), meta)


def from_hil(result, sc, command_line: list[str] | None = None) -> RunRecord:
    """A HIL result (railbrake.hil.HilResult) of Scenario sc: the BCU is external, WSP state unknown
    to the plant (taken as the scenario's)."""
    from railbrake.results.provenance import provenance
    _check_record_args(result, ("time", "outputs", "units", "kpis", "cars", "counters", "timing"),
                       "a HIL run's HilResult", sc, command_line)
    wsp = bool(sc.spec.wsp.enabled)
    meta = _scenario_meta(sc) | {"kind": "HIL", "cars": result.cars, "wsp": wsp,
                                 "atmosphere_pa": result.atmosphere,
                                 "configuration": configuration(sc, result.cars, wsp),
                                 "hil": {"counters": result.counters, "timing": result.timing,
                                         "fault_changes": [c.as_dict() for c in getattr(result, "fault_changes", [])]},
                                 "provenance": provenance(command_line)}
    judged = getattr(result, "meta", None) or {}   # a HilResult has no meta: no healthy reference
    if HEALTHY_SHORTFALL in judged:   # the reference the run's warnings were judged on
        meta[HEALTHY_SHORTFALL] = judged[HEALTHY_SHORTFALL]
    return RunRecord(np.asarray(result.time), dict(result.outputs), dict(result.units), dict(result.kpis), meta)
