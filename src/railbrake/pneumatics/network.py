"""Pneumatic networks built by name and simulated whole inside the C core.

Elements: reservoirs (fixed p, T), volumes (adiabatic unless heat transfer is given; optional
prescribed volume rate), orifices (area and Cd, or ISO 6358 C and b), pipes (a lumped volume between
two halves of the pipe's resistance), solenoid valves (opening schedule with a response delay),
cylinders (piston, return spring, dead volume, stroke) and, for valve models, bodies with pressure
faces and position-driven flow areas (flapper-nozzle, seat, spool edge).
"""

from __future__ import annotations

import ctypes
import math
import numbers
from dataclasses import dataclass, field

import numpy as np

from railbrake import _core
from railbrake._args import real
from railbrake.errors import InputError
from railbrake.pneumatics.orifice import AMBIENT_PRESSURE, CRITICAL_RATIO_NOZZLE, orifice_c

_LINK_KINDS = {"fixed": 0, "flapper": 1, "seat": 2, "spool": 3}


@dataclass
class ElementResult:
    """Time series of one element; fields not meaningful for its kind are None."""

    p: np.ndarray | None = None      # Pa
    T: np.ndarray | None = None      # K
    m: np.ndarray | None = None      # kg
    mdot: np.ndarray | None = None   # kg/s
    x: np.ndarray | None = None      # m
    v: np.ndarray | None = None      # m/s


@dataclass
class NetworkResult:
    time: np.ndarray
    elements: dict = field(default_factory=dict)
    steps: int = 0
    rejected: int = 0

    def __getitem__(self, name: str) -> ElementResult:
        if name not in self.elements:
            raise KeyError(f"{name!r}: no such element; have {sorted(self.elements)}")
        return self.elements[name]


def _schedule(points, delay: float, what: str) -> _core.Schedule:
    """(time, value) pairs -> C schedule; None means the constant 1."""
    s = _core.Schedule()
    if delay < 0 or not math.isfinite(delay):
        raise InputError(f"{what} delay = {delay}: must be finite and >= 0 (s)")
    s.delay = delay
    if points is None:
        return s
    points = [(float(t), float(v)) for t, v in points]
    if not 1 <= len(points) <= _core.SCHEDULE_MAX:
        raise InputError(f"{what}: {len(points)} schedule points: needs 1 to {_core.SCHEDULE_MAX}")
    for i in range(1, len(points)):
        if points[i][0] < points[i - 1][0]:
            raise InputError(f"{what}: schedule time {points[i][0]} s after {points[i - 1][0]} s: "
                             "times must not decrease")
    s.n = len(points)
    for i, (t, v) in enumerate(points):
        s.t[i], s.value[i] = t, v
    return s


class Network:
    """A pneumatic circuit built by name; see the module docstring and docs/pneumatics.md."""

    def __init__(self, ambient_pressure: float = AMBIENT_PRESSURE):
        self.ambient_pressure = real("ambient_pressure", ambient_pressure, 0.0, low_open=True)
        self._nodes: list[tuple[str, _core.NetNode]] = []
        self._links: list[tuple[str, _core.NetLink]] = []
        self._bodies: list[tuple[str, _core.NetBody]] = []
        self._tables: list[_core.ForceTable] = []
        self._membranes: list[_core.Membrane] = []
        self._names: dict[str, tuple[str, int]] = {}   # name -> (kind, index)
        self._aliases: dict[str, tuple[str, int]] = {}  # cylinder name -> its body

    # ------------------------------------------------------------ building
    def _claim(self, name: str, kind: str, index: int) -> None:
        if not isinstance(name, str) or not name:
            raise InputError(f"name = {name!r}: must be a non-empty string")
        if name in self._names:
            raise InputError(f"name {name!r} is used twice (already a {self._names[name][0]})")
        self._names[name] = (kind, index)

    def _node(self, name: str, role: str) -> int:
        kind, index = self._names.get(name, (None, None))
        if kind != "node":
            raise InputError(f"{role} = {name!r}: no reservoir, volume, pipe or cylinder of that name")
        return index

    @staticmethod
    def _check(name, what, value, low=0.0, strict=True, unit=""):
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise TypeError(f"{name}: {what} = {value!r}: must be a number, not {type(value).__name__}")
        value = float(value)
        bad = not math.isfinite(value) or (value <= low if strict else value < low)
        if bad:
            relation = ">" if strict else ">="
            raise InputError(f"{name}: {what} = {value:g}{unit}: must be finite and {relation} {low:g}")
        return value

    def add_reservoir(self, name: str, pressure: float, temperature: float = 293.15) -> None:
        """A node of fixed pressure (Pa) and temperature (K)."""
        node = _core.NetNode(0, self._check(name, "pressure", pressure, unit=" Pa"),
                             self._check(name, "temperature", temperature, unit=" K"), 0.0, 0.0, 0.0, 0.0)
        self._claim(name, "node", len(self._nodes))
        self._nodes.append((name, node))

    def add_volume(self, name: str, volume: float, pressure: float, temperature: float = 293.15,
                   heat_transfer: float = 0.0, wall_temperature: float | None = None,
                   volume_rate: float = 0.0) -> None:
        """A lumped ideal-gas volume (m^3) with initial p (Pa) and T (K).

        heat_transfer: h*A (W/K) to a wall at wall_temperature (default: the initial temperature);
        0 is adiabatic. volume_rate: a prescribed dV/dt (m^3/s), e.g. a driven piston."""
        wall = temperature if wall_temperature is None else wall_temperature
        node = _core.NetNode(1, self._check(name, "pressure", pressure, unit=" Pa"),
                             self._check(name, "temperature", temperature, unit=" K"),
                             self._check(name, "volume", volume, unit=" m^3"), float(volume_rate),
                             self._check(name, "heat_transfer", heat_transfer, strict=False, unit=" W/K"),
                             self._check(name, "wall_temperature", wall, unit=" K"))
        self._claim(name, "node", len(self._nodes))
        self._nodes.append((name, node))

    def _add_link(self, name, a, b, orifice, kind="fixed", body=-1, diameter=0.0, offset=0.0,
                  direction=1.0, shape=0.0, opening=None, delay=0.0):
        link = _core.NetLink(_LINK_KINDS[kind], self._node(a, f"{name}: from"), self._node(b, f"{name}: to"),
                             orifice, body, diameter, offset, direction, shape,
                             _schedule(opening, delay, name))
        if link.from_ == link.to:
            raise InputError(f"{name}: from = to = {a!r}: an orifice joins two different nodes")
        status = _core.RbError()
        if _core.lib.rb_orifice_check(ctypes.byref(orifice), ctypes.byref(status)):
            raise InputError(f"{name}: {status.message.decode()}")
        self._claim(name, "link", len(self._links))
        self._links.append((name, link))

    def add_orifice(self, name: str, a: str, b: str, area: float | None = None,
                    discharge_coefficient: float = 1.0, critical_ratio: float = CRITICAL_RATIO_NOZZLE,
                    sonic_conductance: float | None = None) -> None:
        """A fixed orifice from node a to node b (positive flow a -> b): area (m^2) and Cd, or the
        ISO 6358 sonic conductance C (m^3/(s Pa)) and critical ratio b."""
        if area is not None:
            self._check(name, "area", area, strict=False, unit=" m^2")
        self._add_link(name, a, b, orifice_c(area, discharge_coefficient, critical_ratio, sonic_conductance))

    def add_pipe(self, name: str, a: str, b: str, length: float, diameter: float,
                 friction_factor: float = 0.02, pressure: float | None = None,
                 temperature: float = 293.15) -> None:
        """A pipe as a lumped volume (named `name`) between two halves of its resistance.

        Loss coefficient K = 1 + f L / d (exit loss plus Darcy friction, f = 0.02 for a smooth
        turbulent pipe [T]); each half is an orifice of the pipe's bore with Cd = min(1, sqrt(2/K)).
        The initial pressure defaults to that of node a."""
        length = self._check(name, "length", length, unit=" m")
        diameter = self._check(name, "diameter", diameter, unit=" m")
        self._check(name, "friction_factor", friction_factor, strict=False)
        area = math.pi * diameter ** 2 / 4
        if pressure is None:
            pressure = self._nodes[self._node(a, f"{name}: from")][1].pressure
        self.add_volume(name, area * length, pressure, temperature)
        cd = min(1.0, math.sqrt(2.0 / (1.0 + friction_factor * length / diameter)))
        self._add_link(f"{name}.in", a, name, orifice_c(area, cd))
        self._add_link(f"{name}.out", name, b, orifice_c(area, cd))

    def add_valve(self, name: str, a: str, b: str, area: float, discharge_coefficient: float = 0.8,
                  critical_ratio: float = CRITICAL_RATIO_NOZZLE, opening=None, delay: float = 0.0) -> None:
        """A solenoid valve: an orifice whose area is `area` times the opening (0..1), given as
        (time s, opening) points linear in between, applied `delay` seconds late (response time)."""
        self._check(name, "area", area, strict=False, unit=" m^2")
        self._add_link(name, a, b, orifice_c(area, discharge_coefficient, critical_ratio),
                       opening=opening, delay=delay)

    def add_driven_orifice(self, name: str, a: str, b: str, body: str, kind: str, diameter: float,
                           offset: float = 0.0, direction: float = 1.0, shape: float = math.pi / 2,
                           discharge_coefficient: float = 0.8,
                           critical_ratio: float = CRITICAL_RATIO_NOZZLE) -> None:
        """A flow area driven by a body position: kind 'flapper' (pi D gap), 'seat' (pi D lift
        sin(shape)) or 'spool' (shape = radial clearance); opening = direction * (x - offset)."""
        if kind not in ("flapper", "seat", "spool"):
            raise InputError(f"{name}: kind = {kind!r}: must be 'flapper', 'seat' or 'spool'")
        if body not in self._names or self._names[body][0] != "body":
            raise InputError(f"{name}: body = {body!r}: no body of that name")
        self._check(name, "diameter", diameter, unit=" m")
        if direction not in (1, -1, 1.0, -1.0):
            raise InputError(f"{name}: direction = {direction}: must be +1 or -1")
        self._add_link(name, a, b, orifice_c(1.0, discharge_coefficient, critical_ratio), kind,
                       self._names[body][1], diameter, offset, direction, shape)

    def add_body(self, name: str, mass: float, faces=(), spring_rate: float = 0.0,
                 spring_preload: float = 0.0, damping: float = 0.0, friction: float = 0.0,
                 friction_velocity: float = 1e-3, x_min: float = -math.inf, x_max: float = math.inf,
                 stop_stiffness: float = 1e7, stop_damping: float | None = None, x_initial: float = 0.0,
                 force: float = 0.0, solenoid=None) -> None:
        """A moving body (x positive along its axis). faces: (node, area m^2 or (x, V) table,
        direction +-1) tuples: the node's gauge pressure pushes along direction*x and its volume
        grows by direction*V(x). Spring force -(preload + rate x); sealing friction
        -friction tanh(v/friction_velocity). End stops: a penalty spring stop_stiffness with
        stop_damping (default: critical for the body's mass, so it does not bounce).
        solenoid: (gap table, current table, force grid, airgap at x = 0, [(t, current)] schedule)
        with airgap = airgap0 - x."""
        mass = self._check(name, "mass", mass, unit=" kg")
        if stop_damping is None:
            stop_damping = 2 * math.sqrt(stop_stiffness * mass)
        body = _core.NetBody(
            mass=mass, spring_rate=float(spring_rate),
            spring_preload=float(spring_preload), damping=float(damping),
            friction=self._check(name, "friction", friction, strict=False, unit=" N"),
            friction_velocity=self._check(name, "friction_velocity", friction_velocity, unit=" m/s"),
            x_min=float(x_min), x_max=float(x_max), stop_stiffness=float(stop_stiffness),
            stop_damping=float(stop_damping), x_initial=float(x_initial), force=float(force),
            ambient_pressure=self.ambient_pressure, force_table=-1)
        if not x_min < x_max:
            raise InputError(f"{name}: x_min = {x_min}, x_max = {x_max}: need x_min < x_max")
        faces = list(faces)
        if len(faces) > _core.BODY_FACES:
            raise InputError(f"{name}: {len(faces)} faces: at most {_core.BODY_FACES}")
        body.n_faces = len(faces)
        for i, (node, area, direction) in enumerate(faces):
            index = self._node(node, f"{name}: face node")
            if self._nodes[index][1].kind != 1:
                raise InputError(f"{name}: face node {node!r} is a reservoir; a face needs a volume")
            body.face_node[i], body.face_direction[i], body.face_membrane[i] = index, float(direction), -1
            if np.ndim(area) == 0:
                body.face_area[i] = self._check(name, "face area", area, strict=False, unit=" m^2")
            else:
                body.face_membrane[i] = self._membrane(name, area)
        if solenoid is not None:
            gap, current, forces, airgap0, schedule = solenoid
            body.force_table = self._force_table(name, gap, current, forces)
            body.airgap_initial = float(airgap0)
            body.current = _schedule(schedule, 0.0, f"{name} current")
        self._claim(name, "body", len(self._bodies))
        self._bodies.append((name, body))

    def _membrane(self, name, table) -> int:
        x, volume = (_core.as_double_array(c) for c in table)
        membrane = _core.Membrane()
        _core.call(_core.rb_membrane_init, ctypes.byref(membrane), _core.ptr(x), _core.ptr(volume),
                   len(x) if len(x) == len(volume) else -1)
        self._membranes.append(membrane)
        return len(self._membranes) - 1

    def _force_table(self, name, gap, current, forces) -> int:
        gap, current = np.asarray(gap, float), np.asarray(current, float)
        forces = np.asarray(forces, float)
        if forces.shape != (gap.size, current.size):
            raise InputError(f"{name}: force table shape {forces.shape}: needs (airgaps, currents) = "
                             f"({gap.size}, {current.size})")
        if max(gap.size, current.size) > _core.FORCE_TABLE_MAX:
            raise InputError(f"{name}: force table {gap.size} x {current.size}: at most "
                             f"{_core.FORCE_TABLE_MAX} airgaps and currents")
        table = _core.ForceTable(n_gap=gap.size, n_current=current.size)
        table.gap[:gap.size] = gap.tolist()
        table.current[:current.size] = current.tolist()
        table.force[:forces.size] = forces.ravel().tolist()
        _core.call(_core.rb_force_table_check, ctypes.byref(table))
        self._tables.append(table)
        return len(self._tables) - 1

    def add_cylinder(self, name: str, piston_area: float, stroke: float, dead_volume: float,
                     pressure: float = AMBIENT_PRESSURE, temperature: float = 293.15,
                     spring_rate: float = 0.0, spring_preload: float = 0.0, piston_mass: float = 1.0,
                     damping: float = 200.0, friction: float = 0.0) -> None:
        """A single-acting cylinder: a volume `name` (dead volume + piston_area * x) whose gauge
        pressure drives the piston against its return spring, 0 <= x <= stroke."""
        self.add_volume(name, dead_volume, pressure, temperature)
        self._check(name, "stroke", stroke, unit=" m")
        self.add_body(f"{name}.piston", piston_mass, [(name, piston_area, 1.0)], spring_rate,
                      spring_preload, damping, friction, x_min=0.0, x_max=stroke)
        self._aliases[name] = self._names[f"{name}.piston"]

    # ------------------------------------------------------------ simulation
    def _check_connected(self) -> None:
        used = set()
        for _, link in self._links:
            used.update((link.from_, link.to))
        for _, body in self._bodies:
            used.update(body.face_node[i] for i in range(body.n_faces))
        for index, (name, node) in enumerate(self._nodes):
            if index not in used:
                raise InputError(f"{name!r} is left unconnected: join it with an orifice, pipe or valve")

    def _compiled(self):
        def array(ctype, items):
            return (ctype * max(1, len(items)))(*items)

        nodes = array(_core.NetNode, [n for _, n in self._nodes])
        links = array(_core.NetLink, [lk for _, lk in self._links])
        bodies = array(_core.NetBody, [b for _, b in self._bodies])
        tables = array(_core.ForceTable, self._tables)
        membranes = array(_core.Membrane, self._membranes)
        net = _core.Network(nodes, len(self._nodes), links, len(self._links), bodies, len(self._bodies),
                            tables, len(self._tables), membranes, len(self._membranes))
        return net, (nodes, links, bodies, tables, membranes)

    def simulate(self, t_end: float, n_points: int = 501, times=None, rtol: float = 1e-6,
                 atol: float = 1e-8, max_step: float = 0.0, max_steps: int = 2_000_000) -> NetworkResult:
        """Simulate from 0 to t_end (s) inside C; results at n_points equally spaced times (or at
        `times`). atol is relative to each state's scale (mass at 1 bar, 300 K, body stroke)."""
        if not self._nodes:
            raise InputError("network is empty: add reservoirs, volumes and orifices first")
        self._check_connected()
        t_end = self._check("simulate", "t_end", t_end, unit=" s")
        t = np.linspace(0.0, t_end, int(n_points)) if times is None else _core.as_double_array(times)
        net, keep = self._compiled()
        n_out, nn, nl, nb = t.size, len(self._nodes), len(self._links), len(self._bodies)
        n_int = ctypes.c_size_t()
        n_work = _core.rb_network_workspace_size(ctypes.byref(net), n_out, ctypes.byref(n_int))
        work = np.zeros(n_work)
        iwork = np.zeros(max(1, n_int.value), dtype=np.intc)
        out = {k: np.zeros((n_out, max(1, n))) for k, n in
               (("p", nn), ("T", nn), ("m", nn), ("mdot", nl), ("x", nb), ("v", nb))}
        options = _core.OdeOptions(float(rtol), float(atol), None, 0.0, float(max_step), int(max_steps))
        stats = _core.OdeStats()
        _core.call(_core.rb_network_simulate, ctypes.byref(net), _core.ptr(t), n_out, ctypes.byref(options),
                   _core.ptr(work), n_work, iwork.ctypes.data_as(ctypes.POINTER(ctypes.c_int)),
                   *(_core.ptr(out[k]) for k in ("p", "T", "m", "mdot", "x", "v")), ctypes.byref(stats))
        del keep
        result = NetworkResult(t, steps=stats.steps, rejected=stats.rejected)
        for i, (name, _) in enumerate(self._nodes):
            result.elements[name] = ElementResult(p=out["p"][:, i], T=out["T"][:, i], m=out["m"][:, i])
        for j, (name, _) in enumerate(self._links):
            result.elements[name] = ElementResult(mdot=out["mdot"][:, j])
        for k, (name, _) in enumerate(self._bodies):
            result.elements[name] = ElementResult(x=out["x"][:, k], v=out["v"][:, k])
        for name, (_, k) in self._aliases.items():
            result.elements[name].x, result.elements[name].v = out["x"][:, k], out["v"][:, k]
        return result
