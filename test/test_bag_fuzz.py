"""Fuzz-proof bag reading: mutated real bags never give anything but data (+ warnings) or a BagError.

Every mutation starts from a bag in bags/. Damage inside a chunk is made "valid" (recompressed, CRC
recomputed) so it reaches the record and CDR parsers instead of being caught as a corrupt chunk.
Each read must finish within seconds and bounded memory (decompression bombs included), and lose
nothing silently: fewer messages than the original means a warning.

Examples per property: 20 by default (the file runs in well under a minute);
POLYFORCE_FUZZ_EXAMPLES=500 for a long campaign. The runs are derandomised (repeatable).
"""
import io
import json
import os
import struct
import subprocess
import sys
import time
import tracemalloc
import zlib
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import lz4.frame
import numpy as np
import pytest
import zstandard
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from mcap.reader import make_reader

from polyforce_ros import bags

REPO = Path(__file__).resolve().parents[1]
SOURCE = REPO / "bags" / "step_5n.mcap"  # 4 chunks, the smallest sample bag
TOPICS = [bags.BRIDGE_VOLTAGE, bags.REFERENCE_FORCE]
OPTIONAL = [bags.TEMPERATURE]
EXAMPLES = int(os.environ.get("POLYFORCE_FUZZ_EXAMPLES", "20"))
FUZZ = settings(derandomize=True, database=None, deadline=None, max_examples=EXAMPLES,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
MAX_SECONDS = 5.0  # per read of a mutated bag (a clean one takes ~10 ms)
MAX_BYTES = 600 << 20
GIB = 1 << 30
HUGE = [0x7FFFFFFF, 0xFFFFFFFF, 0x80000000, 0x10000]  # a CDR string or array length
PAST_ANY_CHUNK = [0x7FFFFFFF, 0xFFFFFFFF, 2**64 - 1]  # a record length
REC = struct.Struct("<BQ")
FIELDS = {bags.JOINT_STATE: {"position"}, bags.TEMPERATURE_MSG: {"temperature", "variance"},
          bags.WRENCH_STAMPED: {"force_x", "force_y", "force_z", "torque_x", "torque_y", "torque_z"}}


# ----------------------------------------------------------------------------- MCAP surgery
def records(buf, pos=0):
    """``(opcode, record offset, body offset, body length)`` of consecutive records from ``pos``."""
    while pos + 9 <= len(buf):
        op, length = REC.unpack_from(buf, pos)
        yield op, pos, pos + 9, length
        if op == 2:  # footer
            return
        pos += 9 + length


@dataclass
class Chunk:
    offset: int  # of the chunk record in the file
    end: int
    start_time: int
    end_time: int
    records: bytes  # decompressed


@dataclass
class Source:
    raw: bytes
    chunks: list
    types: dict  # channel id -> (topic, type name)


def load_source(path=SOURCE) -> Source:
    raw = path.read_bytes()
    chunks = []
    for op, pos, body, length in records(raw, 8):
        if op != 6:
            continue
        start, end, size, _crc = struct.unpack_from("<QQQI", raw, body)
        n = struct.unpack_from("<I", raw, body + 28)[0]
        assert raw[body + 32 : body + 32 + n] == b"zstd"
        p = body + 32 + n
        data = raw[p + 8 : p + 8 + struct.unpack_from("<Q", raw, p)[0]]
        recs = zstandard.ZstdDecompressor().decompress(data, max_output_size=size)  # trusted: our own bag
        chunks.append(Chunk(pos, body + length, start, end, recs))
    with open(path, "rb") as fh:
        summary = make_reader(fh).get_summary()
    types = {cid: (ch.topic, summary.schemas[ch.schema_id].name) for cid, ch in summary.channels.items()}
    return Source(raw, chunks, types)


def chunk_record(recs, *, compression="zstd", compressed=None, declared=None, crc=None, start=0, end=0):
    """A Chunk record holding ``recs`` (or the given ``compressed`` bytes), size and CRC true unless given."""
    if compressed is None:
        compressed = {"zstd": lambda: zstandard.ZstdCompressor().compress(recs),
                      "lz4": lambda: lz4.frame.compress(recs), "": lambda: recs}[compression]()
    name = compression.encode() if isinstance(compression, str) else compression
    body = (struct.pack("<QQQI", start, end, len(recs) if declared is None else declared,
                        zlib.crc32(recs) if crc is None else crc)
            + struct.pack("<I", len(name)) + name + struct.pack("<Q", len(compressed)) + compressed)
    return REC.pack(6, len(body)) + body


def replace_chunk(src: Source, index, new_record) -> bytes:
    """The bag with chunk ``index`` replaced; the footer's summary offsets follow the size change."""
    c = src.chunks[index]
    out = bytearray(src.raw[: c.offset] + new_record + src.raw[c.end :])
    delta = len(new_record) - (c.end - c.offset)
    footer = len(out) - 8 - 29
    if out[footer] == 2:
        for at in (footer + 9, footer + 17):  # summary start, summary offset start
            value = struct.unpack_from("<Q", out, at)[0]
            if value > c.offset:
                struct.pack_into("<Q", out, at, value + delta)
    return bytes(out)


def with_records(src: Source, index, recs) -> bytes:
    """The bag with chunk ``index`` holding ``recs`` instead, recompressed with a true size and CRC."""
    c = src.chunks[index]
    return replace_chunk(src, index, chunk_record(recs, start=c.start_time, end=c.end_time))


def messages(recs):
    """``(record offset, body offset, body length)`` of the Message records of a chunk."""
    return [(pos, body, length) for op, pos, body, length in records(recs) if op == 5]


def cdr_length_words(type_name, cdr):
    """Offsets (in the CDR after its 4-byte encapsulation) of the string/array length words of a message."""
    u32 = lambda p: struct.unpack_from("<I", cdr, p)[0]  # noqa: E731
    align = lambda p, n: (p + n - 1) // n * n  # noqa: E731
    words, pos = [8], 12 + u32(8)
    if type_name == bags.JOINT_STATE:
        pos = align(pos, 4)
        words.append(pos)
        n_names, pos = u32(pos), pos + 4
        for _ in range(n_names):
            pos = align(pos, 4)
            words.append(pos)
            pos += 4 + u32(pos)
        for _ in range(3):
            pos = align(pos, 4)
            words.append(pos)
            count, pos = u32(pos), pos + 4
            if count:
                pos = align(pos, 8) + 8 * count
    return words


# ----------------------------------------------------------------------------- reading, checked
class NullWriter:
    def __init__(self):
        self.count = 0

    def write_serialized(self, topic, type_name, data, log_time_ns, schema_data=None):
        self.count += 1


def bounded(fn, trace=True):
    """``fn()`` timed (and memory-traced): returns its result or BagError, asserting the bounds.

    tracemalloc sees Python and numpy allocations; the decompressors' own are measured by the bomb
    tests in a fresh process (ru_maxrss).
    """
    if trace:
        tracemalloc.start()
        tracemalloc.reset_peak()
    t0 = time.perf_counter()
    try:
        result = fn()
    except bags.BagError as exc:
        result = exc
    finally:
        elapsed = time.perf_counter() - t0
        peak = tracemalloc.get_traced_memory()[1] if trace else 0
        if trace:
            tracemalloc.stop()
    assert elapsed < MAX_SECONDS, f"took {elapsed:.1f} s"
    assert peak < MAX_BYTES, f"peak {peak >> 20} MiB traced"
    if isinstance(result, bags.BagError):
        # each kind of damage has its own handling; the catch-all for stray numpy/struct errors is a last resort
        assert "unreadable bag data" not in str(result), result
    return result


def read(path):
    """read_bag of the contract topics (+ copy_messages), within bounds; BagData or the BagError."""
    bag = bounded(lambda: bags.read_bag(path, topics=TOPICS, optional=OPTIONAL))
    copied = bounded(lambda: bags.copy_messages(path, NullWriter()), trace=False)  # same walk as read_bag
    assert isinstance(copied, (list, bags.BagError))
    if isinstance(bag, bags.BagData):
        for _topic, data in bag.topics.items():
            n = len(data)
            assert data.log_time_ns.dtype == np.int64 and data.stamp_ns.dtype == np.int64 and data.stamp_ns.size == n
            assert set(data.fields) == FIELDS[data.type_name], data.fields.keys()
            assert all(v.shape == (n,) and v.dtype == np.float64 for v in data.fields.values())
    return bag


def total(bag):
    return sum(len(d) for d in bag.topics.values())


class Ctx:
    """The source bag parsed, its clean read, and a work folder (with a short repr for hypothesis reports)."""

    def __init__(self, work):
        self.src, self.work = load_source(), work
        self.original = bags.read_bag(SOURCE, topics=TOPICS, optional=OPTIONAL)
        assert self.original.warnings == [] and total(self.original) > 30_000
        for data in self.original.topics.values():
            assert np.all(np.diff(data.log_time_ns) > 0)  # unique: assert_values_kept relies on it

    def __repr__(self):
        return f"Ctx({SOURCE.name})"


@pytest.fixture(scope="module")
def ctx(tmp_path_factory):
    return Ctx(tmp_path_factory.mktemp("fuzz"))


def write(work, name, data):
    path = work / name
    path.write_bytes(data)
    return path


def chunk_log_times(src, index):
    """topic -> Counter of log times of chunk ``index``'s messages."""
    out = {}
    for _pos, body, _length in messages(src.chunks[index].records):
        recs = src.chunks[index].records
        cid, log = struct.unpack_from("<H", recs, body)[0], struct.unpack_from("<Q", recs, body + 6)[0]
        out.setdefault(src.types[cid][0], Counter())[log] += 1
    return out


def assert_only_lost(bag, original, lost):
    """``bag`` holds exactly ``original`` minus ``lost`` (topic -> Counter of log times)."""
    for topic, ref in original.topics.items():
        got = bag.topics[topic].log_time_ns if topic in bag.topics else np.zeros(0, dtype=np.int64)
        gone = np.array(sorted(lost.get(topic, Counter())), dtype=np.int64)
        np.testing.assert_array_equal(np.sort(got), np.setdiff1d(ref.log_time_ns, gone), err_msg=topic)


def assert_values_kept(bag, original):
    """Every message read carries the original's log time, stamp and value (none altered, only some
    missing). Log times are unique per topic in the source bag."""
    for topic, data in bag.topics.items():
        ref, name = original[topic], bags.SCALAR_FIELD[data.type_name]
        at = np.clip(np.searchsorted(ref.log_time_ns, data.log_time_ns), 0, len(ref) - 1)
        np.testing.assert_array_equal(ref.log_time_ns[at], data.log_time_ns, err_msg=topic)
        np.testing.assert_array_equal(ref.stamp_ns[at], data.stamp_ns, err_msg=topic)
        np.testing.assert_array_equal(ref.fields[name][at], data.fields[name], err_msg=topic)


# ----------------------------------------------------------------------------- properties
chunk_index = st.integers(0, 3)
fraction = st.floats(0, 1, exclude_max=True)


@FUZZ
@given(index=chunk_index, flips=st.lists(st.tuples(fraction, st.integers(1, 255)), min_size=1, max_size=8))
def test_byte_flips_in_a_valid_chunk(ctx, index, flips):
    """Flipped bytes anywhere in a chunk's records (CRC recomputed): data or BagError, nothing lost silently."""
    src, original, work = ctx.src, ctx.original, ctx.work
    recs = bytearray(src.chunks[index].records)
    for where, xor in flips:
        recs[int(where * len(recs))] ^= xor
    bag = read(write(work, "flip.mcap", with_records(src, index, bytes(recs))))
    if isinstance(bag, bags.BagData) and total(bag) != total(original):
        assert bag.warnings


@FUZZ
@given(index=chunk_index, where=fraction, junk=st.binary(min_size=1, max_size=2048))
def test_random_bytes_spliced_into_a_valid_chunk(ctx, index, where, junk):
    src, original, work = ctx.src, ctx.original, ctx.work
    recs = src.chunks[index].records
    at = int(where * len(recs))
    bag = read(write(work, "splice.mcap", with_records(src, index, recs[:at] + junk + recs[at + len(junk) :])))
    if isinstance(bag, bags.BagData) and total(bag) != total(original):
        assert bag.warnings


@FUZZ
@given(index=chunk_index, which=fraction, word=st.integers(0, 10), value=st.sampled_from(HUGE))
def test_huge_cdr_length_skips_exactly_that_message(ctx, index, which, word, value):
    """A string/array length of 0x7fffffff etc. in one message: that message is skipped and counted, the
    rest is read unchanged (bulk paths included: the message may be first, inside or last of its run)."""
    src, original, work = ctx.src, ctx.original, ctx.work
    recs = bytearray(src.chunks[index].records)
    msgs = messages(recs)
    _pos, body, length = msgs[int(which * len(msgs))]
    topic, type_name = src.types[struct.unpack_from("<H", recs, body)[0]]
    cdr = body + 22 + 4
    words = cdr_length_words(type_name, recs[cdr : body + length])
    struct.pack_into("<I", recs, cdr + words[word % len(words)], value)
    bag = read(write(work, "cdr.mcap", with_records(src, index, bytes(recs))))
    assert isinstance(bag, bags.BagData), bag
    assert f"1 malformed messages on {topic} skipped" in bag.warnings, bag.warnings
    lost = {topic: Counter([struct.unpack_from("<Q", recs, body + 6)[0]])}
    assert_only_lost(bag, original, lost)
    assert_values_kept(bag, original)


@FUZZ
@given(index=chunk_index, which=fraction, keep=fraction)
def test_truncated_message_skips_exactly_that_message(ctx, index, which, keep):
    """A message cut short (its record length adjusted, so the chunk's framing holds): skipped and
    counted, unless the cut only took the padding after its last field (rclpy's JointState carries
    8 such bytes): then it reads unchanged."""
    src, original, work = ctx.src, ctx.original, ctx.work
    recs = src.chunks[index].records
    msgs = messages(recs)
    pos, body, length = msgs[int(which * len(msgs))]
    topic, log = src.types[struct.unpack_from("<H", recs, body)[0]][0], struct.unpack_from("<Q", recs, body + 6)[0]
    new_len = int(keep * length)  # 0 .. length - 1
    mutated = recs[:pos] + REC.pack(5, new_len) + recs[body : body + new_len] + recs[body + length :]
    bag = read(write(work, "cut.mcap", with_records(src, index, mutated)))
    assert isinstance(bag, bags.BagData), bag
    assert_values_kept(bag, original)
    if log in bag[topic].log_time_ns:
        assert new_len >= length - 8 and bag.warnings == []
        assert_only_lost(bag, original, {})
        return
    where = topic if new_len >= 2 else "an unknown channel"
    assert bag.warnings == [f"1 malformed messages on {where} skipped"], bag.warnings
    assert_only_lost(bag, original, {topic: Counter([log])})


@FUZZ
@given(index=chunk_index, which=fraction, value=st.sampled_from(PAST_ANY_CHUNK + [0x10000, 0, 1, 21, 22]))
def test_message_record_length_field(ctx, index, which, value):
    """A Message record's length set to 0x7fffffff, 0xffffffff, 2^64-1 or too small: the chunk's framing
    is lost from there; what came before is kept, the loss is reported."""
    src, original, work = ctx.src, ctx.original, ctx.work
    recs = bytearray(src.chunks[index].records)
    msgs = messages(recs)
    pos, _body, _length = msgs[int(which * len(msgs))]
    struct.pack_into("<Q", recs, pos + 1, value)
    bag = read(write(work, "reclen.mcap", with_records(src, index, bytes(recs))))
    assert isinstance(bag, bags.BagData), bag
    assert bag.warnings
    if value in PAST_ANY_CHUNK:  # runs past the chunk: a clean cut
        assert any("cut short" in w for w in bag.warnings), bag.warnings
        assert_values_kept(bag, original)


@pytest.mark.parametrize("name", ["zstx", "", "lz4", "ZSTD", "brotli", "\u00e9", b"\xff\xfe", "z" * 5000])
@pytest.mark.parametrize("index", [0, 2])
def test_unknown_or_wrong_compression_skips_only_that_chunk(ctx, name, index):
    src, original, work = ctx.src, ctx.original, ctx.work
    c = src.chunks[index]
    compressed = zstandard.ZstdCompressor().compress(c.records)
    mutated = replace_chunk(src, index, chunk_record(c.records, compression=name, compressed=compressed,
                                                     start=c.start_time, end=c.end_time))
    bag = read(write(work, "comp.mcap", mutated))
    assert isinstance(bag, bags.BagData), bag
    assert any(f"chunk at byte {c.offset}" in w for w in bag.warnings), bag.warnings
    if name not in ("", "lz4"):
        assert any("unknown compression" in w for w in bag.warnings), bag.warnings
    assert_only_lost(bag, original, chunk_log_times(src, index))  # the first chunk's channels come from the summary
    assert_values_kept(bag, original)


@FUZZ
@given(flips=st.lists(st.tuples(fraction, st.integers(1, 255)), min_size=1, max_size=16))
def test_byte_flips_anywhere_in_the_file(ctx, flips):
    """No CRC repair: chunk headers, lengths, the summary and footer are hit too."""
    src, work = ctx.src, ctx.work
    raw = bytearray(src.raw)
    for where, xor in flips:
        raw[8 + int(where * (len(raw) - 8))] ^= xor
    read(write(work, "raw.mcap", bytes(raw)))


def test_joint_state_without_position_reads_as_nan_with_a_warning(ctx):
    """Valid CDR without the value (an empty position array) no longer drops the topic's position column."""
    path = ctx.work / "empty_position.mcap"
    with bags.BagWriter(path) as w:
        for i in range(40):
            msg = bags.make_message(bags.JOINT_STATE, 1_000_000 * (i + 1), float(i))
            if i in (0, 17):
                msg.position = []
            w.write(bags.BRIDGE_VOLTAGE, bags.JOINT_STATE, msg, 1_000_000 * (i + 1))
    bag = bags.read_bag(path, topics=[bags.BRIDGE_VOLTAGE])
    position = bag[bags.BRIDGE_VOLTAGE].fields["position"]
    assert np.isnan(position[[0, 17]]).all()
    np.testing.assert_array_equal(np.delete(position, [0, 17]), np.delete(np.arange(40.0), [0, 17]))
    assert bag.warnings == [f"2 messages on {bags.BRIDGE_VOLTAGE} carry no position: read as NaN"]


# ----------------------------------------------------------------------------- decompression bombs
def zstd_bomb(total, content_size=True):
    """``total`` zero bytes as one zstd frame, compressed streaming (never ``total`` bytes in memory)."""
    out = io.BytesIO()
    writer = zstandard.ZstdCompressor(level=3).stream_writer(out, size=total if content_size else -1, closefd=False)
    block = bytes(1 << 20)
    for _ in range(total >> 20):
        writer.write(block)
    writer.flush(zstandard.FLUSH_FRAME)
    return out.getvalue()


def lz4_bomb(total):
    comp = lz4.frame.LZ4FrameCompressor()
    parts, block = [comp.begin(source_size=total)], bytes(1 << 20)
    parts += [comp.compress(block) for _ in range(total >> 20)]
    return b"".join(parts + [comp.flush()])


def zeros_crc(total):
    crc, block = 0, bytes(1 << 20)
    for _ in range(total >> 20):
        crc = zlib.crc32(block, crc)
    return crc


# (compression, inflated size, declared size, frame header holds the size)
BOMBS = {
    "zstd 1 GiB declared true": ("zstd", GIB, GIB, True),
    "zstd 1 GiB declared 1 MiB": ("zstd", GIB, 1 << 20, True),
    "zstd 1 GiB no frame size, declared 1 MiB": ("zstd", GIB, 1 << 20, False),
    "zstd 3 GiB declared 1 MiB": ("zstd", 3 * GIB, 1 << 20, True),
    "zstd 200 MiB of zeros, inside the cap": ("zstd", 200 << 20, 200 << 20, True),
    "lz4 512 MiB declared true": ("lz4", 512 << 20, 512 << 20, True),
    "lz4 512 MiB declared 1 MiB": ("lz4", 512 << 20, 1 << 20, True),
    "lz4 200 MiB of zeros, inside the cap": ("lz4", 200 << 20, 200 << 20, True),
}

# A fresh interpreter, so that ru_maxrss (C allocations of the decompressors included) measures this read only.
_MEASURE = """
import json, resource, sys, time
from polyforce_ros import bags
rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
t0 = time.perf_counter()
try:
    bag = bags.read_bag(sys.argv[1], topics=[bags.BRIDGE_VOLTAGE, bags.REFERENCE_FORCE])
    out = {"warnings": bag.warnings, "counts": {t: len(d) for t, d in bag.topics.items()}}
except bags.BagError as exc:
    out = {"error": str(exc)}
out["seconds"] = time.perf_counter() - t0
out["rss_mib"] = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - rss0) / 1024
print(json.dumps(out))
"""


@pytest.mark.parametrize("case", list(BOMBS))
def test_decompression_bomb_chunk_is_skipped_fast_in_bounded_memory(ctx, case):
    src, original, work = ctx.src, ctx.original, ctx.work
    compression, inflated, declared, frame_size = BOMBS[case]
    bomb = zstd_bomb(inflated, frame_size) if compression == "zstd" else lz4_bomb(inflated)
    assert len(bomb) < 5 << 20  # the file stays small
    index = 1
    c = src.chunks[index]
    crc = zeros_crc(inflated) if declared == inflated else 0
    path = write(work, "bomb.mcap", replace_chunk(src, index, chunk_record(
        b"", compression=compression, compressed=bomb, declared=declared, crc=crc, start=c.start_time, end=c.end_time)))
    proc = subprocess.run([sys.executable, "-c", _MEASURE, str(path)], cwd=REPO, capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr
    out = json.loads(proc.stdout)
    assert "error" not in out, out
    assert out["seconds"] < MAX_SECONDS, out
    assert out["rss_mib"] < MAX_BYTES >> 20, out
    assert any(f"chunk at byte {c.offset}" in w for w in out["warnings"]), out
    if declared > bags.MAX_CHUNK_BYTES:
        assert any(f"over the {bags.MAX_CHUNK_BYTES >> 20} MiB limit" in w for w in out["warnings"]), out
    lost = chunk_log_times(src, index)
    for topic in TOPICS:
        assert out["counts"][topic] == len(original[topic]) - sum(lost.get(topic, Counter()).values())


def test_dense_valid_chunk_inside_the_cap_is_read_in_bounded_memory(ctx):
    """The legitimate worst case under the cap: a 30 KB chunk that inflates to 128 MiB of valid messages
    (a million of them) is read whole, in bounded time and memory."""
    src, original, work = ctx.src, ctx.original, ctx.work
    recs = src.chunks[1].records
    pos, body, length = messages(recs)[10]
    topic = src.types[struct.unpack_from("<H", recs, body)[0]][0]
    block = recs[pos : body + length] * ((1 << 20) // (body + length - pos))
    copies = 128
    out = io.BytesIO()
    writer = zstandard.ZstdCompressor(level=3).stream_writer(out, size=copies * len(block), closefd=False)
    crc = 0
    for _ in range(copies):
        writer.write(block)
        crc = zlib.crc32(block, crc)
    writer.flush(zstandard.FLUSH_FRAME)
    path = write(work, "dense.mcap", replace_chunk(src, 1, chunk_record(b"", compressed=out.getvalue(),
                                                                           declared=copies * len(block), crc=crc)))
    proc = subprocess.run([sys.executable, "-c", _MEASURE, str(path)], cwd=REPO, capture_output=True, text=True,
                          timeout=120)
    out = json.loads(proc.stdout)
    assert out["seconds"] < 2 * MAX_SECONDS and out["rss_mib"] < MAX_BYTES >> 20 and out["warnings"] == [], out
    lost = chunk_log_times(src, 1)
    added = copies * len(block) // (body + length - pos)
    assert out["counts"][topic] == len(original[topic]) - sum(lost.get(topic, Counter()).values()) + added


# ----------------------------------------------------------------------------- the CLIs
def polyforce(*args):
    exe = Path(sys.executable).with_name("polyforce")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "polyforce_ros.cli"]
    return subprocess.run(cmd + list(args), cwd=REPO, capture_output=True, text=True, timeout=180)


def cli_cases(src):
    recs = bytearray(src.chunks[1].records)
    _pos, body, _length = messages(recs)[5]
    struct.pack_into("<I", recs, body + 22 + 4 + 8, 0xFFFFFFFF)  # frame_id length of one message
    c = src.chunks[2]
    return {
        "huge string length": with_records(src, 1, bytes(recs)),
        "zstd bomb, small declared size": replace_chunk(src, 2, chunk_record(
            b"", compressed=zstd_bomb(GIB), declared=len(c.records), crc=0, start=c.start_time, end=c.end_time)),
        "unknown compression": replace_chunk(src, 3, chunk_record(
            src.chunks[3].records, compression="zst\x00",
            compressed=zstandard.ZstdCompressor().compress(src.chunks[3].records))),
    }


def test_cli_compensate_and_calibrate_on_mutated_bags(ctx):
    """Exit 0 with the damage reported, or 2 with a one-line error; never a traceback. (calibrate may also
    exit 3: a valid run that keeps the previous model.)"""
    src, work = ctx.src, ctx.work
    for case, data in cli_cases(src).items():
        path = write(work, f"cli_{case.split()[0]}.mcap", data)
        out = work / f"cli_{case.split()[0]}_out.mcap"
        proc = polyforce("compensate", str(path), str(out))
        assert "Traceback" not in proc.stderr and proc.returncode in (0, 2), (case, proc.returncode, proc.stderr)
        if proc.returncode == 0:
            assert bags.read_bag(out, topics=[bags.WRENCH]).topics[bags.WRENCH].log_time_ns.size > 0
        model = work / f"model_{case.split()[0]}.yaml"
        proc = polyforce("calibrate", str(path), "--output", str(model))
        assert "Traceback" not in proc.stderr and proc.returncode in (0, 2, 3), (case, proc.returncode, proc.stderr)
