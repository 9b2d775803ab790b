"""The frame codec seen from Python (the C implementation, docs/hil-interface.md)."""

import math
import struct

import pytest

from railbrake import _core
from railbrake.errors import InputError
from railbrake.hil.frames import crc32, decode_plant_frame, encode_bcu_frame


def test_crc32_check_value():
    # CRC-32/ISO-HDLC (IEEE 802.3) catalogue check value of "123456789"; zlib agrees
    assert crc32(b"123456789") == 0xCBF43926


def test_bcu_frame_layout_matches_the_icd():
    data = encode_bcu_frame(7, 1234, 2, 2.0, [4.5e5, 4.6e5], hold=[1] * 8, vent=[0, 1] * 4, session=0xABCD,
                            config=0x1234)
    assert len(data) == 32 + 4 * (1 + 2) + 2 * 8 + 4 == _core.rb_bcu_frame_size(2, 8)
    fields = struct.unpack_from("<IBBHIIIQBB", data)
    assert fields == (0x4B524252, 2, 2, 28, 0xABCD, 0x1234, 7, 1234, 2, 8)
    assert struct.unpack_from("<3f", data, 32) == (2.0, 4.5e5, 4.6e5)
    assert list(data[44:52]) == [1] * 8 and list(data[52:60]) == [0, 1] * 4
    assert struct.unpack_from("<I", data, 60)[0] == crc32(data[:60])


def test_plant_frame_decode_validates():
    header = struct.pack("<IBBHIIIQBBH", 0x4B524252, 2, 1, 4 * (3 + 8 + 1), 77, 0xC0FFEE, 5, 99, 1, 4, 0)
    payload = struct.pack("<3f4f4ff", 80.0, 12.5, 9e5, *[220.0] * 4, *[3e5] * 4, 5.5e5)
    frame = header + payload
    decoded = decode_plant_frame(frame + struct.pack("<I", crc32(frame)))
    assert decoded["session"] == 77 and decoded["config"] == 0xC0FFEE
    assert decoded["step"] == 99 and decoded["wheel_speed"] == [220.0] * 4 and decoded["supply_pressure"] == [5.5e5]
    with pytest.raises(InputError, match="crc"):
        decode_plant_frame(frame + struct.pack("<I", crc32(frame) ^ 1))
    bad = header + struct.pack("<3f", math.nan, 12.5, 9e5) + payload[12:]
    with pytest.raises(InputError, match="train_speed"):
        decode_plant_frame(bad + struct.pack("<I", crc32(bad)))


def test_only_payload_size_wrong_says_so():
    """Not "size = 76: expected 76": the field that is wrong is named."""
    data = bytearray(encode_bcu_frame(1, 2, 1, 0.5, [2e5]))
    data[6] += 1
    body = bytes(data[:-4])
    frame = body + struct.pack("<I", crc32(body))
    f = _core.BcuFrame()
    err = _core.RbError()
    assert _core.rb_bcu_frame_decode(frame, len(frame), f, err) != 0
    assert err.message.decode().startswith(f"payload_size = {data[6]}: expected {data[6] - 1}")
