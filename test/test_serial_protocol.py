"""The serial frame format: round trip, resync after garbage, CRC, lost frames, clock mapping."""
import random

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from polyforce_ros.serial_protocol import FRAME_SIZE, DeviceClock, FrameParser, crc16_ccitt, encode_frame
from polyforce_ros.serial_protocol import (MSG_INFO, MSG_PAYLOAD_MAX, MSG_STATUS, SYNC, DeviceInfo, DeviceStatus,
                                           DeviceTemperature, MessageDemux, RawMessage, decode_message,
                                           encode_info, encode_message, encode_status, encode_temperature)


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


def _stream(clock, t0_us, arrival0_ns, n, period_us=1000, delay_ns=200_000):
    return [clock.stamp_ns((t0_us + k * period_us) % 2**32, arrival0_ns + k * period_us * 1000 + delay_ns)
            for k in range(n)]


def test_device_clock_drops_a_glitched_device_time_and_keeps_its_mapping():
    clock = DeviceClock()
    host0 = 7_000_000_000_000
    before = _stream(clock, 1_000_000, host0, 100)
    glitch = clock.stamp_ns(1_000_000 + 100_000 + 2**30, host0 + 100_000_000 + 200_000)  # a flipped high bit
    after = _stream(clock, 1_000_000 + 100_000, host0 + 100_000_000, 100)
    assert glitch is None and clock.implausible == 1 and clock.reanchored == 0
    stamps = before + after
    assert all(b - a == 1_000_000 for a, b in zip(stamps, stamps[1:]))  # no jump, no wrap counted


def test_device_clock_follows_a_device_reset_after_reanchor_after_s():
    clock = DeviceClock(reanchor_after_s=0.2)
    host0 = 7_000_000_000_000
    _stream(clock, 50_000_000, host0, 100)                        # device up for 50 s
    restart_arrival = host0 + 100_000_000
    after = _stream(clock, 0, restart_arrival, 500)               # the device restarted its clock at 0
    blind = [k for k, s in enumerate(after) if s is None]
    assert clock.reanchored == 1 and blind == list(range(len(blind))) and len(blind) <= 201
    first = len(blind)
    # stamps follow host time again: within the transport delay of the arrival, and evenly spaced
    assert abs(after[first] - (restart_arrival + first * 1_000_000)) <= 200_000
    assert all(b - a == 1_000_000 for a, b in zip(after[first:], after[first + 1:]))


def test_device_clock_follows_a_fast_device_crystal_through_random_latency():
    # 100 ppm fast device, 30 s at 1 kHz, transport latency 80 us + exponential(400 us), read in chunks
    rng = np.random.default_rng(3)
    clock, host0, ppm = DeviceClock(window_s=10.0), 1_000_000_000_000, 100e-6
    acq_ns = host0 + np.arange(30_000) * 1_000_000
    t_us = (np.arange(30_000) * 1000 * (1 + ppm)).astype(np.int64) % 2**32
    arrival = acq_ns + 80_000 + rng.exponential(400_000, acq_ns.size).astype(np.int64)
    arrival = np.maximum.accumulate(arrival)  # a serial link delivers in order
    err_us = np.array([clock.stamp_ns(int(t), int(a)) - q for t, a, q in zip(t_us, arrival, acq_ns)]) / 1e3
    assert err_us.min() > -10  # never before the conversion
    # a mapping that kept its first offset would be 3 ms late at the end; this one stays within the
    # latency floor plus the drift between two of the many least-delayed frames
    assert err_us[-1000:].max() < 80 + 400 + 100, err_us[-1000:].max()
    assert np.median(err_us[-1000:]) < 300


# ---------------------------------------------------------------------- one read, many frames
MS = 1_000_000


def test_frames_of_one_read_get_their_own_stamps():
    from polyforce_ros.runtime.sources import SerialSource

    got = SerialSource(1.0).feed(b"".join(encode_frame(i, 1000 * i, i) for i in range(5)), 10**18)
    stamps = [s for s, _ in got]
    assert [v for _, v in got] == [0.0, 1.0, 2.0, 3.0, 4.0]
    assert stamps == [10**18 - (4 - i) * MS for i in range(5)]  # the newest, least delayed, at the arrival


def test_a_backlog_after_a_connect_keeps_distinct_increasing_stamps_and_settles_on_the_least_delay():
    from polyforce_ros.runtime.sources import SerialSource

    source, host0 = SerialSource(1.0), 3_000_000_000_000
    for connect in range(2):  # the first connection and a reconnect (the source forgets its mapping)
        source.reset()
        base = connect * 10_000
        acq = [host0 + (base + k) * MS for k in range(400)]

        def frames(ks, base=base):
            return b"".join(encode_frame(base + k, (base + k) * 1000, k) for k in ks)

        # 80 frames waited in the port's buffer; the read came 3 ms after the newest; then 1 kHz reads
        # of one or two frames, 150-250 us after the newest's conversion
        out = source.feed(frames(range(80)), acq[79] + 3 * MS)
        first_read = [s for s, _ in out]
        k = 80
        while k < 400:
            n = min(1 + (k % 3 == 0), 400 - k)
            out += source.feed(frames(range(k, k + n)), acq[k + n - 1] + 150_000 + 100_000 * (k % 2))
            k += n
        stamps = np.array([s for s, _ in out])
        assert [v for _, v in out] == list(range(400))
        assert np.all(np.diff(first_read) == MS)  # the backlog keeps the device's spacing
        assert np.all(np.diff(stamps) >= MS // 2)  # distinct and increasing, also when the offset falls 3 ms
        err = stamps - np.array(acq)
        assert err.min() >= 0  # never before the conversion
        assert err[-100:].max() <= 250_000 and err[-100:].min() == 150_000  # settled on the least delayed reads


def test_a_device_reset_read_in_bursts_re_anchors_with_distinct_stamps():
    clock, host0 = DeviceClock(reanchor_after_s=0.2), 9_000_000_000_000
    _stream(clock, 50_000_000, host0, 100)
    # the device restarted its clock at 0; the host reads 50 frames at a time, every 50 ms
    reads = [clock.stamp_batch([(50 * r + k) * 1000 for k in range(50)], host0 + 200 * MS + (50 * r + 49) * MS)
             for r in range(8)]
    healed = next(r for r, stamps in enumerate(reads) if stamps[0] is not None)
    assert clock.reanchored == 1 and all(s is None for read in reads[:healed] for s in read)
    stamps = [s for read in reads[healed:] for s in read]
    assert None not in stamps and np.all(np.diff(stamps) == MS)
    assert stamps[49] == host0 + 200 * MS + (50 * healed + 49) * MS  # the newest frame of that read at its arrival



# ---------------------------------------------------------------------- sequence numbers
def parse(seqs):
    parser = FrameParser()
    got = parser.feed(b"".join(encode_frame(s, 1000 * i, i) for i, s in enumerate(seqs)))
    return parser, [f.seq for f in got]


def counts(parser):
    return dict(lost=parser.lost_frames, duplicates=parser.duplicates, reordered=parser.reordered,
                jumps=parser.seq_jumps, frames=parser.frames)


@pytest.mark.parametrize("seqs, delivered, expected", [
    ([0, 1, 2, 2, 3], [0, 1, 2, 3], dict(duplicates=1)),                      # the same frame twice
    ([0, 1, 2, 3, 1], [0, 1, 2, 3], dict(duplicates=1)),                      # an old frame again
    ([0, 1, 3, 2, 4], [0, 1, 3, 4], dict(reordered=1)),                       # a swapped pair
    ([65534, 65535, 1, 0, 2], [65534, 65535, 1, 2], dict(reordered=1)),       # swapped across the wrap
    ([0, 1, 5, 6], [0, 1, 5, 6], dict(lost=3)),                               # real losses
    ([0, 4, 2, 2, 5], [0, 4, 5], dict(lost=2, reordered=1, duplicates=1)),    # a loss, one late, then again
    ([65535, 0, 0, 1], [65535, 0, 1], dict(duplicates=1)),                    # a duplicate at the wrap
    ([10_000, 10_001, 0, 1], [10_000, 10_001, 0, 1], dict(jumps=1)),          # a device that restarted its count
])
def test_sequence_arithmetic_tells_duplicates_reorders_losses_and_jumps_apart(seqs, delivered, expected):
    parser, got = parse(seqs)
    assert got == delivered
    assert counts(parser) == dict(dict(lost=0, duplicates=0, reordered=0, jumps=0), frames=len(seqs), **expected)


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 65535), st.lists(st.sampled_from(["next", "skip", "dup", "swap"]), max_size=300))
def test_sequence_counts_add_up_on_any_mix_of_losses_duplicates_and_swaps(seq0, ops):
    seqs, k = [], seq0  # numbers as sent (unwrapped); the wire carries them modulo 2**16
    for op in ops:
        if op == "skip":
            k += 1
        elif op == "dup" and seqs:
            seqs.append(seqs[-1])
            continue
        elif op == "swap" and len(seqs) >= 2 and seqs[-1] == k - 1:  # (a connection starts at its first frame)
            seqs.insert(len(seqs) - 1, k)  # k overtakes its predecessor
            k += 1
            continue
        seqs.append(k)
        k += 1
    parser, got = parse([s % 65536 for s in seqs])
    firsts, late = [], 0  # each number at its first arrival; late: arrived after a newer one
    for s in seqs:
        if s not in firsts:
            late += bool(firsts) and s < max(firsts)
            firsts.append(s)
    delivered = [s for i, s in enumerate(firsts) if s == max(firsts[:i + 1])]
    assert got == [s % 65536 for s in delivered]
    span = max(seqs) - min(seqs) + 1 if seqs else 0
    assert counts(parser) == dict(lost=span - len(firsts), duplicates=len(seqs) - len(firsts), reordered=late,
                                  jumps=0, frames=len(seqs))


# ------------------------------------------------------------------------------------ messages
#: golden messages, byte for byte; firmware/host/fw_test.c ("fw_test golden") must print the same
GOLDEN_INFO = bytes.fromhex(
    "a5c3010138c701010100e8030000404b4c0080001800414453313232300061726475696e6f2d7a65726f000000"
    "0050462d323032342d303030310000000016a0")
GOLDEN_INFO_STUFFED = bytes.fromhex(
    "a5c3010138c701010100a500a5000000a5005aa5005a5aa500a500014142434445464748303132333435363738"
    "39616263646566a5005aa5005aa5005aa5005aa5005aa5005aa5005aa5005a21e6")
GOLDEN_STATUS = bytes.fromhex("a5c3020114eba500005aa500040003005a5a000002000000805101004556")
GOLDEN_TEMPERATURE = bytes.fromhex("a5c3030106f940e20100d3fc8632")
INFO = DeviceInfo(rate_hz=1000, vref_uv=5_000_000, gain=128, adc_bits=24, mains_filter=0, adc="ADS1220",
                  board="arduino-zero", sensor_serial="PF-2024-0001")
INFO_STUFFED = DeviceInfo(rate_hz=0xA5A5, vref_uv=0x5AA55AA5, gain=0xA55A, adc_bits=0xA5, mains_filter=1,
                          adc="ABCDEFGH", board="0123456789abcdef", sensor_serial="\u00a5Z" * 8)
STATUS = DeviceStatus(t_us=0xA55A00A5, reset_reason=4, watchdog_resets=3, overflows=0x5A5A, adc_reconfigs=2,
                      uptime_s=86400)
TEMPERATURE = DeviceTemperature(t_us=123456, temp_q5=-813)


def test_golden_messages():
    assert encode_info(INFO) == GOLDEN_INFO
    assert encode_status(STATUS) == GOLDEN_STATUS
    assert encode_temperature(TEMPERATURE) == GOLDEN_TEMPERATURE
    assert encode_info(INFO_STUFFED) == GOLDEN_INFO_STUFFED  # text fields are Latin-1: one byte per character
    assert INFO.volts_per_count == 5 / 2**30 and INFO.firmware == "1.1.0" and INFO.protocol == 1
    assert TEMPERATURE.celsius == -25.40625 and STATUS.reset_reason_name == "watchdog"
    for golden in (GOLDEN_INFO, GOLDEN_INFO_STUFFED, GOLDEN_STATUS, GOLDEN_TEMPERATURE):
        assert SYNC not in golden and golden[-1] != 0xA5 and golden[2] != 0x5A


def test_messages_round_trip_through_the_demux():
    passed, found = MessageDemux().feed(GOLDEN_INFO + GOLDEN_STATUS + GOLDEN_TEMPERATURE + GOLDEN_INFO_STUFFED)
    assert passed == b"" and found[:3] == [INFO, STATUS, TEMPERATURE]
    assert found[3] == INFO_STUFFED


def test_a_host_that_knows_only_samples_skips_messages_without_an_error():
    frames = [encode_frame(i, 1000 * i, (-1) ** i * 0xA5C3A5 * i) for i in range(40)]
    messages = [GOLDEN_INFO, GOLDEN_STATUS, GOLDEN_TEMPERATURE, GOLDEN_INFO_STUFFED]
    stream = b"".join(f + (messages[i % 4] if i % 3 == 0 else b"") for i, f in enumerate(frames))
    parser = FrameParser()
    got = parser.feed(stream)
    assert [f.seq for f in got] == list(range(40)) and parser.crc_errors == 0 and parser.lost_frames == 0


def _mixed_stream(rnd, n):
    """Sample frames with messages between them (payloads full of 0xA5, 0xC3 and sync words)."""
    stream, frames, messages = b"", [], []
    for i in range(n):
        counts = rnd.choice([0xA5C3, -0x5AA5C3, rnd.randrange(-(2**31), 2**31), 0x00C3A5])
        t_us = rnd.choice([0xC3A5C3A5, rnd.randrange(2**32)])
        frames.append((i, t_us, counts))
        stream += encode_frame(i, t_us, counts)
        if rnd.random() < 0.3:
            payload = bytes(rnd.choice([0xA5, 0xC3, 0x5A, 0x00, rnd.randrange(256)])
                            for _ in range(rnd.randrange(MSG_PAYLOAD_MAX + 1)))
            msg_type = rnd.choice([MSG_STATUS, 0x7E])  # a status, or a type this host does not know
            messages.append(decode_message(msg_type, 1, payload))
            stream += encode_message(msg_type, payload)
    return stream, frames, messages


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), chunk=st.integers(1, 40))
def test_demux_then_parser_split_anywhere(seed, chunk):
    rnd = random.Random(seed)
    stream, frames, messages = _mixed_stream(rnd, 60)
    demux, parser, got, found = MessageDemux(), FrameParser(), [], []
    for i in range(0, len(stream), chunk):
        passed, new = demux.feed(stream[i : i + chunk])
        got += parser.feed(passed)
        found += new
    assert [(f.seq, f.t_us, f.counts) for f in got] == frames
    assert found == messages and parser.crc_errors == 0 and demux.messages == len(messages)
    assert any(isinstance(m, RawMessage) for m in found) or not any(
        getattr(m, "msg_type", None) == 0x7E for m in messages)


def test_a_corrupt_message_is_no_message_and_costs_no_sample():
    for flip in range(2, len(GOLDEN_STATUS)):
        bad = bytearray(GOLDEN_STATUS)
        bad[flip] ^= 0x10
        stream = encode_frame(1, 10, 5) + bytes(bad) + encode_frame(2, 20, 6) + GOLDEN_TEMPERATURE
        passed, found = MessageDemux().feed(stream)
        assert found == [TEMPERATURE], flip
        parser = FrameParser()
        assert [f.seq for f in parser.feed(passed)] == [1, 2]


def test_a_later_layout_version_is_read_by_its_known_prefix_and_unknown_types_are_kept():
    longer = encode_message(MSG_STATUS, STATUS.payload() + b"\x01\x02\x03", version=2)
    short = encode_message(MSG_INFO, INFO.payload()[:20])
    _, found = MessageDemux().feed(longer + short + encode_message(0x42, b"\xa5"))
    assert found == [STATUS, RawMessage(MSG_INFO, 1, INFO.payload()[:20]), RawMessage(0x42, 1, b"\xa5")]
    with pytest.raises(ValueError):
        encode_message(MSG_STATUS, bytes(MSG_PAYLOAD_MAX + 1))


def test_a_sample_frame_ending_in_a5_is_not_held_back_and_a_cut_sync_still_finds_its_message():
    frame = next(f for f in (encode_frame(s, 1000 * s, 7) for s in range(5000)) if f[-1] == 0xA5)
    demux, parser = MessageDemux(), FrameParser()
    passed, found = demux.feed(frame)
    assert [f.counts for f in parser.feed(passed)] == [7] and found == []  # at once, not at the next read
    # a message whose sync is cut between two reads: found, and the parser skips the A5 it was given
    passed, found = demux.feed(GOLDEN_STATUS[:1])
    assert found == [] and parser.feed(passed) == []
    seq = _seq_of(frame) + 1
    passed, found = demux.feed(GOLDEN_STATUS[1:] + encode_frame(seq, 9, 9))
    assert found == [STATUS] and [f.counts for f in parser.feed(passed)] == [9] and parser.crc_errors == 0


def _seq_of(frame):
    return int.from_bytes(frame[2:4], "little")


def _checks(results):
    return {r.name: r.passed for r in results}


def test_device_checklist_judges_a_byte_stream():
    """polyforce check-device's checks on a recorded stream: a frame cut by the opening counts nothing; a CRC error
    later, a railed sample, a wide zero and noise each fail their check, and only theirs."""
    from polyforce_ros.device_check import DeviceReading, evaluate, format_report

    healthy = DeviceStatus(t_us=5, reset_reason=1, watchdog_resets=0, overflows=0, adc_reconfigs=0, uptime_s=3)
    rng = np.random.default_rng(4)
    quiet = (1000 + rng.normal(0, 200, 400)).round().astype(int)  # 200 counts = 0.93 uV rms at 5 V / 2**30

    def stream(counts, extra=b""):
        frames = b"".join(encode_frame(100 + k, 7_000 + 1000 * k, int(c)) for k, c in enumerate(counts))
        cut = SYNC + bytes(5)  # the end of a frame begun before the port was opened: a CRC error, not counted
        return cut + encode_info(INFO) + encode_status(healthy) + frames + extra

    def judged(data, samples=400, **kwargs):
        reading = DeviceReading()
        for i in range(0, len(data), 97):  # in reads of any size
            reading.feed(data[i:i + 97])
        return evaluate(reading, samples, **kwargs)

    good = judged(stream(quiet))
    assert all(r.passed for r in good), format_report(good)
    assert "PASS: all 9 checks" in format_report(good)
    corrupt = bytearray(encode_frame(500, 407_000, 1000))
    corrupt[9] ^= 1
    assert _checks(judged(stream(quiet[:399], bytes(corrupt)))) == {**_checks(good), "link": False}
    railed = quiet.copy()
    railed[17] = 2**23 - 1
    assert [r.name for r in judged(stream(railed)) if not r.passed] == ["not railed", "noise"]
    assert [r.name for r in judged(stream(quiet + 2_500_000)) if not r.passed] == ["zero offset"]
    assert [r.name for r in judged(stream(quiet + 3 * rng.normal(0, 400, 400).round().astype(int)))
            if not r.passed] == ["noise"]
    # the driver's parameters disagreeing with the device; too few frames
    failed = [r.name for r in judged(stream(quiet), volts_per_count=1e-6, expected_rate_hz=2000.0) if not r.passed]
    assert failed == ["volts_per_count", "expected rate"]
    assert [r.name for r in judged(stream(quiet), samples=500) if not r.passed] == ["link"]
    # no messages at all (firmware without them): the noise in volts needs the scale given
    bare = b"".join(encode_frame(k, 1000 * k, int(c)) for k, c in enumerate(quiet))
    failed = [r.name for r in judged(bare) if not r.passed]
    assert failed == ["info", "status", "rate", "noise"]
    assert [r.name for r in judged(bare, volts_per_count=5 / 2**30) if not r.passed] == ["info", "status", "rate"]
