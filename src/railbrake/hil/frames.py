"""The HIL frames from Python, through the C codec (one layout: core/src/hil_frame.c,
docs/hil-interface.md). For peers written in Python: test peers, or a BCU prototype. Frames carry a
SipHash-2-4 tag under the session key (session_key: from the key file's secret, the plant's session,
the plant's nonce and the BCU's nonce; both 0, the hello key, for hellos, challenges and refusals)."""

from __future__ import annotations

import ctypes

from railbrake import _core
from railbrake._args import whole
from railbrake.errors import InputError

FRAME_TYPES = {1: "plant", 2: "bcu", 3: "challenge"}


def crc32(data: bytes) -> int:
    return int(_core.rb_crc32(data, len(data)))


def siphash24(key: bytes, data: bytes) -> int:
    return int(_core.rb_siphash24(_key(key), data, len(data)))


def _key(key: bytes) -> bytes:
    if not isinstance(key, (bytes, bytearray)) or len(key) != _core.HIL_KEY_SIZE:
        raise InputError(f"key: expected {_core.HIL_KEY_SIZE} bytes")
    return bytes(key)


def session_key(secret: bytes, session: int, nonce: int, plant_nonce: int = 0) -> bytes:
    """The key frames of `session` under the BCU's `nonce` and the plant's `plant_nonce` carry (both
    0: the hello key, of hello, challenge and refusal frames)."""
    out = ctypes.create_string_buffer(_core.HIL_KEY_SIZE)
    _core.rb_hil_session_key(_key(secret), session & 0xFFFFFFFF, plant_nonce & 0xFFFFFFFFFFFFFFFF,
                             nonce & 0xFFFFFFFFFFFFFFFF, out)
    return out.raw


def _header(h, session: int, config: int, sequence: int, step: int, nonce: int, n_cars: int, n_axles: int,
            plant_nonce: int = 0) -> None:
    h.session, h.config = session & 0xFFFFFFFF, config & 0xFFFFFFFF
    h.sequence, h.step, h.nonce = sequence & 0xFFFFFFFF, step, nonce & 0xFFFFFFFFFFFFFFFF
    h.plant_nonce = plant_nonce & 0xFFFFFFFFFFFFFFFF
    h.n_cars, h.n_axles = n_cars, n_axles


def _encode(encoder, frame, key: bytes) -> bytes:
    buf = ctypes.create_string_buffer(1024)
    size = ctypes.c_size_t()
    _core.call(encoder, ctypes.byref(frame), _key(key), buf, len(buf), ctypes.byref(size))
    return buf.raw[:size.value]


def encode_bcu_frame(sequence: int, step: int, n_cars: int, brake_demand: float, pressure_demand,
                     hold=(), vent=(), n_axles: int | None = None, session: int = 1, config: int = 0,
                     nonce: int = 0, key: bytes | None = None, check: bool = True, plant_nonce: int = 0) -> bytes:
    """A BCU frame (pressures in Pa absolute, hold/vent per axle 0/1) in `session` (echo the plant
    frame's) with the configuration digest `config` (the plant's, to be accepted), tagged under key
    (session_key(secret, session, nonce, plant_nonce)). Its values are checked as the receiver checks them (the
    ICD's ranges: InputError naming the field); check=False leaves them as given, so a test peer
    can send what a faulty BCU would."""
    f = _core.BcuFrame()
    n_cars = whole("n_cars", n_cars, 1, _core.PLANT_MAX_CARS)
    pressure_demand, hold, vent = list(pressure_demand), list(hold), list(vent)
    if len(pressure_demand) > n_cars or len(hold) > _core.PLANT_MAX_AXLES or len(vent) > _core.PLANT_MAX_AXLES:
        raise InputError(f"pressure_demand, hold, vent: at most n_cars = {n_cars} pressures and "
                         f"{_core.PLANT_MAX_AXLES} valve states")
    _header(f.header, session, config, sequence, step, nonce, n_cars,
            _core.AXLES_PER_CAR * n_cars if n_axles is None else n_axles, plant_nonce)
    f.brake_demand = brake_demand
    for i, p in enumerate(pressure_demand):
        f.pressure_demand[i] = p
    for i, (h, v) in enumerate(zip(hold, vent)):
        f.hold[i], f.vent[i] = h, v
    data = _encode(_core.rb_bcu_frame_encode, f, key)
    if check:   # the receiver's own checks, on the frame as it will travel (float32 values)
        try:
            _core.call(_core.rb_bcu_frame_decode, data, len(data), ctypes.byref(_core.BcuFrame()))
        except InputError as exc:
            raise InputError(f"encode_bcu_frame: {exc}") from None
    return data


def encode_challenge(session: int, config: int, step: int, nonce: int, n_cars: int, key: bytes,
                     plant_nonce: int = 0) -> bytes:
    """The BCU's challenge: its nonce for the plant of `session`, echoing the plant's hello nonce,
    under the hello key."""
    h = _core.FrameHeader()
    _header(h, session, config, 0, step, nonce, n_cars, _core.AXLES_PER_CAR * n_cars, plant_nonce)
    return _encode(_core.rb_challenge_frame_encode, h, key)


def frame_header(data: bytes) -> dict:
    """The header of any frame whose structure and CRC hold (InputError otherwise), with its type."""
    h = _core.FrameHeader()
    _core.call(_core.rb_frame_check, data, len(data), ctypes.byref(h))
    return {"type": FRAME_TYPES[h.type], "session": h.session, "config": h.config, "sequence": h.sequence,
            "step": h.step, "nonce": h.nonce, "plant_nonce": h.plant_nonce, "n_cars": h.n_cars,
            "n_axles": h.n_axles}


def authentic(data: bytes, key: bytes) -> bool:
    """Whether the frame's tag is that of key."""
    return bool(_core.rb_frame_authentic(data, len(data), _key(key)))


def decode_plant_frame(data: bytes) -> dict:
    """A plant frame as a dict (SI units); InputError names the field that fails validation. The tag
    is not checked: authentic(data, key)."""
    f = _core.PlantFrame()
    _core.call(_core.rb_plant_frame_decode, data, len(data), ctypes.byref(f))
    n_cars, n_axles = f.header.n_cars, f.header.n_axles
    return {"session": f.header.session, "config": f.header.config, "sequence": f.header.sequence,
            "step": f.header.step, "nonce": f.header.nonce, "plant_nonce": f.header.plant_nonce, "n_cars": n_cars,
            "n_axles": n_axles,
            "train_speed": f.train_speed, "position": f.position,
            "main_reservoir_pressure": f.main_reservoir_pressure,
            "wheel_speed": list(f.wheel_speed[:n_axles]), "cylinder_pressure": list(f.cylinder_pressure[:n_axles]),
            "supply_pressure": list(f.supply_pressure[:n_cars])}
