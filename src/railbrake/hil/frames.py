"""The HIL frames from Python, through the C codec (one layout: core/src/hil_frame.c,
docs/hil-interface.md). For peers written in Python: test peers, or a BCU prototype."""

from __future__ import annotations

import ctypes

from railbrake import _core


def crc32(data: bytes) -> int:
    return int(_core.rb_crc32(data, len(data)))


def encode_bcu_frame(sequence: int, step: int, n_cars: int, brake_demand: float, pressure_demand,
                     hold=(), vent=(), n_axles: int | None = None, session: int = 1, config: int = 0) -> bytes:
    """A BCU frame (pressures in Pa absolute, hold/vent per axle 0/1) in `session` (echo the plant
    frame's) with the configuration digest `config` (the plant's, to be accepted). Values are not
    checked here, so a test peer can send what a faulty BCU would; the receiver validates."""
    f = _core.BcuFrame()
    f.header.session, f.header.config = session & 0xFFFFFFFF, config & 0xFFFFFFFF
    f.header.sequence, f.header.step = sequence & 0xFFFFFFFF, step
    f.header.n_cars = n_cars
    f.header.n_axles = _core.AXLES_PER_CAR * n_cars if n_axles is None else n_axles
    f.brake_demand = brake_demand
    for i, p in enumerate(pressure_demand):
        f.pressure_demand[i] = p
    for i, (h, v) in enumerate(zip(hold, vent)):
        f.hold[i], f.vent[i] = h, v
    buf = ctypes.create_string_buffer(1024)
    size = ctypes.c_size_t()
    _core.call(_core.rb_bcu_frame_encode, ctypes.byref(f), buf, len(buf), ctypes.byref(size))
    return buf.raw[:size.value]


def decode_plant_frame(data: bytes) -> dict:
    """A plant frame as a dict (SI units); InputError names the field that fails validation."""
    f = _core.PlantFrame()
    _core.call(_core.rb_plant_frame_decode, data, len(data), ctypes.byref(f))
    n_cars, n_axles = f.header.n_cars, f.header.n_axles
    return {"session": f.header.session, "config": f.header.config, "sequence": f.header.sequence, "step": f.header.step, "n_cars": n_cars, "n_axles": n_axles,
            "train_speed": f.train_speed, "position": f.position,
            "main_reservoir_pressure": f.main_reservoir_pressure,
            "wheel_speed": list(f.wheel_speed[:n_axles]), "cylinder_pressure": list(f.cylinder_pressure[:n_axles]),
            "supply_pressure": list(f.supply_pressure[:n_cars])}
