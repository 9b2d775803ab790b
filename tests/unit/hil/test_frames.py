"""The frame codec seen from Python (the C implementation, docs/hil-interface.md, ICD v3)."""

import math
import re
import struct

import pytest

from railbrake import _core
from railbrake.errors import InputError
from railbrake.hil.frames import (authentic, crc32, decode_plant_frame, encode_bcu_frame, encode_challenge,
                                  frame_header, session_key, siphash24)

KEY = bytes(range(16))


def test_crc32_check_value():
    # CRC-32/ISO-HDLC (IEEE 802.3) catalogue check value of "123456789"; zlib agrees
    assert crc32(b"123456789") == 0xCBF43926


def test_siphash_worked_example_of_the_paper():
    # SipHash-2-4, key 00..0f, message 00..0e: 0xa129ca6149be45e5 (Aumasson and Bernstein, appendix A)
    assert siphash24(KEY, bytes(range(15))) == 0xA129CA6149BE45E5


def test_bcu_frame_layout_matches_the_icd():
    key = session_key(KEY, 0xABCD, 0x1122334455667788, 0x99)
    data = encode_bcu_frame(7, 1234, 2, 2.0, [4.5e5, 4.6e5], hold=[1] * 8, vent=[0, 1] * 4, session=0xABCD,
                            config=0x1234, nonce=0x1122334455667788, plant_nonce=0x99, key=key)
    assert len(data) == 48 + 4 * (1 + 2) + 2 * 8 + 4 + 8 == _core.rb_bcu_frame_size(2, 8)
    fields = struct.unpack_from("<IBBHIIIQBBHQQ", data)
    assert fields == (0x4B524252, 4, 2, 28, 0xABCD, 0x1234, 7, 1234, 2, 8, 0, 0x1122334455667788, 0x99)
    assert struct.unpack_from("<3f", data, 48) == (2.0, 4.5e5, 4.6e5)
    assert list(data[60:68]) == [1] * 8 and list(data[68:76]) == [0, 1] * 4
    assert struct.unpack_from("<IQ", data, 76) == (crc32(data[:76]), siphash24(key, data[:76]))
    assert authentic(data, key) and not authentic(data, session_key(KEY, 0xABCD, 0))
    assert not authentic(data, session_key(KEY, 0xABCD, 0x1122334455667788))   # the plant's nonce keys it too


def test_challenge_is_header_and_trailer_under_the_hello_key():
    hello = session_key(KEY, 9, 0)
    data = encode_challenge(9, 0x77, 100, 0xFEED, 1, hello, plant_nonce=0xBEEF)
    assert len(data) == 60 and authentic(data, hello)
    assert frame_header(data) == {"type": "challenge", "session": 9, "config": 0x77, "sequence": 0, "step": 100,
                                  "nonce": 0xFEED, "plant_nonce": 0xBEEF, "n_cars": 1, "n_axles": 4}


def test_plant_frame_decode_validates():
    header = struct.pack("<IBBHIIIQBBHQQ", 0x4B524252, 4, 1, 4 * (3 + 8 + 1), 77, 0xC0FFEE, 5, 99, 1, 4, 0, 0, 0)
    payload = struct.pack("<3f4f4ff", 80.0, 12.5, 9e5, *[220.0] * 4, *[3e5] * 4, 5.5e5)
    frame = header + payload
    tag = struct.pack("<Q", siphash24(KEY, frame))
    decoded = decode_plant_frame(frame + struct.pack("<I", crc32(frame)) + tag)
    assert decoded["session"] == 77 and decoded["config"] == 0xC0FFEE and decoded["nonce"] == 0
    assert decoded["step"] == 99 and decoded["wheel_speed"] == [220.0] * 4 and decoded["supply_pressure"] == [5.5e5]
    with pytest.raises(InputError, match="crc"):
        decode_plant_frame(frame + struct.pack("<I", crc32(frame) ^ 1) + tag)
    bad = header + struct.pack("<3f", math.nan, 12.5, 9e5) + payload[12:]
    with pytest.raises(InputError, match="train_speed"):
        decode_plant_frame(bad + struct.pack("<I", crc32(bad)) + tag)
    old = bytearray(frame)
    old[4] = 3
    with pytest.raises(InputError, match="version = 3: expected 4"):
        decode_plant_frame(bytes(old) + struct.pack("<I", crc32(bytes(old))) + tag)


def test_only_payload_size_wrong_says_so():
    """Not "size = 76: expected 76": the field that is wrong is named."""
    data = bytearray(encode_bcu_frame(1, 2, 1, 0.5, [2e5], key=KEY))
    data[6] += 1
    body = bytes(data[:-12])
    frame = body + struct.pack("<IQ", crc32(body), siphash24(KEY, body))
    f = _core.BcuFrame()
    err = _core.RbError()
    assert _core.rb_bcu_frame_decode(frame, len(frame), f, err) != 0
    assert err.message.decode().startswith(f"payload_size = {data[6]}: expected {data[6] - 1}")


def test_a_frame_needs_a_key():
    with pytest.raises(InputError, match="key: expected 16 bytes"):
        encode_bcu_frame(1, 2, 1, 0.5, [2e5])


def test_a_bad_bcu_frame_is_refused_when_built_unless_asked_for():
    """The encoder checks what the receiver checks (NaN, out of range, a valve state of 2), naming
    the field; check=False builds it anyway, as a faulty BCU would send it."""
    for args, field in (((1, 2, 1, math.nan, [2e5]), "brake_demand"), ((1, 2, 1, 0.5, [math.inf]), "pressure_demand[0]"),
                        ((1, 2, 1, 0.5, [-1.0]), "pressure_demand[0]"), ((1, 2, 1, 3.0, [2e5]), "brake_demand")):
        with pytest.raises(InputError, match=rf"encode_bcu_frame: {re.escape(field)} = "):
            encode_bcu_frame(*args, key=KEY)
        assert len(encode_bcu_frame(*args, key=KEY, check=False)) > 40
    with pytest.raises(InputError, match=r"hold\[1\] = 2"):
        encode_bcu_frame(1, 2, 1, 0.5, [2e5], hold=[0, 2, 0, 0], vent=[0] * 4, key=KEY)
    with pytest.raises(ValueError, match="n_cars = 0"):
        encode_bcu_frame(1, 2, 0, 0.5, [], key=KEY)
