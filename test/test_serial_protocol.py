"""The serial frame format: round trip, resync after garbage, CRC, lost frames, clock mapping."""
from polyforce_ros.serial_protocol import FRAME_SIZE, DeviceClock, FrameParser, crc16_ccitt, encode_frame


def test_crc_reference_value():
    assert crc16_ccitt(b"123456789") == 0x29B1  # CRC-16/CCITT-FALSE check value


def test_round_trip_split_anywhere_and_resync():
    frames = [encode_frame(i, 1000 * i, -5000 + 37 * i) for i in range(50)]
    stream = b"\x00garbage\xa5" + b"".join(frames[:10]) + frames[10][:5] + b"".join(frames[11:])
    parser, got = FrameParser(), []
    for i in range(0, len(stream), 7):  # arbitrary read sizes
        got += parser.feed(stream[i : i + 7])
    assert [f.seq for f in got] == [i for i in range(50) if i != 10]
    assert got[5].counts == -5000 + 37 * 5 and got[5].t_us == 5000
    assert parser.lost_frames == 1 and parser.crc_errors == 1  # the cut frame fails its CRC


def test_corrupt_frame_is_dropped_and_counted():
    frame = bytearray(encode_frame(1, 10, 123))
    frame[9] ^= 0xFF
    parser = FrameParser()
    got = parser.feed(bytes(frame) + encode_frame(2, 20, 5))
    assert [f.seq for f in got] == [2] and parser.crc_errors == 1
    assert len(frame) == FRAME_SIZE


def test_device_clock_unwraps_and_uses_least_delayed_frame():
    clock = DeviceClock(window_s=10.0)
    host0 = 5_000_000_000
    stamps = []
    for k, delay_us in enumerate([900, 300, 700, 300, 500]):
        t_us = (2**32 - 2000 + 1000 * k) % 2**32  # wraps after the second sample
        arrival = host0 + 1000 * k * 1000 + delay_us * 1000
        stamps.append(clock.stamp_ns(t_us, arrival))
    steps = [b - a for a, b in zip(stamps[2:], stamps[3:])]
    assert steps == [1_000_000, 1_000_000]  # once the 300 us frame is seen, spacing is exact
