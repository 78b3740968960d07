"""rosbag2-compatible MCAP bags: writing, and fast reading of the topic contract into numpy.

Writing follows rosbag2's MCAP storage: profile ``ros2``, schemas named
``pkg/msg/Type`` with encoding ``ros2msg`` (the .msg text followed by every
dependency, each after a line of 80 ``=`` and ``MSG: pkg/Type``), messages in
``cdr``, chunked with message indexes, chunk indexes and statistics.

Reading does not build one Python object per message: records are scanned
linearly (so a truncated file still yields everything before the cut), chunks
are decompressed whole, and for each topic the messages whose CDR layout is
identical (same frame_id, joint names and array sizes: the normal case) are
decoded together as numpy arrays. Messages with other layouts are decoded one
by one with the same code path, so nothing is dropped for being unusual.

Problems that lose data (truncation, a corrupt chunk) are reported in
``BagData.warnings``; problems that make the bag unusable for the request (not
an MCAP file, a missing topic, the wrong type on a topic) raise
:class:`BagError` with the reason.
"""
from __future__ import annotations

import os
import re
import struct
import sys
import zlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

# The topic contract lives in contract.py; re-exported here for the readers and writers of bags.
from .contract import (  # noqa: F401
    BRIDGE_VOLTAGE,
    CONTRACT,
    FLOAT64,
    FRAME_ID,
    JOINT_NAME,
    JOINT_STATE,
    REFERENCE_FORCE,
    SCALAR_FIELD,
    TEMPERATURE,
    TEMPERATURE_MSG,
    WRENCH,
    WRENCH_STAMPED,
)

_MAGIC = b"\x89MCAP0\r\n"
_PRIMITIVES = {
    "bool", "byte", "char", "float32", "float64", "int8", "uint8", "int16", "uint16",
    "int32", "uint32", "int64", "uint64", "string", "wstring",
}


class BagError(ValueError):
    """The bag cannot serve the request; the message says why."""


# ----------------------------------------------------------------------------- schemas
def _share_dirs():
    prefixes = [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    prefixes.append(sys.prefix)
    return [Path(p) / "share" for p in prefixes]


def _msg_text(pkg, name):
    for share in _share_dirs():
        path = share / pkg / "msg" / f"{name}.msg"
        if path.is_file():
            return path.read_text()
    raise BagError(f"message definition {pkg}/msg/{name} not found (is AMENT_PREFIX_PATH set?)")


def _dependencies(pkg, text):
    deps = []
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        tokens = line.split()
        if len(tokens) > 1 and "=" in tokens[1]:
            continue  # a constant
        ftype = re.sub(r"(\[.*\]|<=\d+)", "", tokens[0])
        if ftype in _PRIMITIVES:
            continue
        if ftype == "Header":
            deps.append(("std_msgs", "Header"))
        elif "/" in ftype:
            dpkg, dname = ftype.split("/")[0], ftype.split("/")[-1]
            deps.append((dpkg, dname))
        else:
            deps.append((pkg, ftype))
    return deps


def schema_text(type_name: str) -> str:
    """ros2msg schema text of ``pkg/msg/Type`` with all dependencies appended."""
    pkg, _, name = type_name.split("/")
    main = _msg_text(pkg, name)
    parts, seen, todo = [main.rstrip("\n")], {(pkg, name)}, list(_dependencies(pkg, main))
    while todo:
        dep = todo.pop(0)
        if dep in seen:
            continue
        seen.add(dep)
        text = _msg_text(*dep)
        parts.append("=" * 80 + f"\nMSG: {dep[0]}/{dep[1]}\n" + text.rstrip("\n"))
        todo.extend(_dependencies(dep[0], text))
    return "\n".join(parts) + "\n"


# ----------------------------------------------------------------------------- CDR layouts
def _align(pos, n):
    return (pos + n - 1) & ~(n - 1)


def _layout(type_name, payload):
    """Offsets (in the CDR payload after the 4-byte encapsulation header) of one message.

    Returns ``(fields, length_fields)``: ``fields`` maps value names to
    ``(offset, numpy dtype)``; ``length_fields`` lists offsets of the uint32
    length/count words that determine the layout (equal words in equal
    places => identical layout).
    """
    u32 = struct.Struct("<I").unpack_from
    fields, lengths = {}, []
    pos = 0
    if type_name in (JOINT_STATE, WRENCH_STAMPED, TEMPERATURE_MSG):
        fields["sec"], fields["nanosec"] = (0, "<i4"), (4, "<u4")
        lengths.append(8)
        pos = 12 + u32(payload, 8)[0]  # frame_id string incl. NUL
    if type_name == JOINT_STATE:
        pos = _align(pos, 4)
        lengths.append(pos)
        n_names = u32(payload, pos)[0]
        pos += 4
        for _ in range(n_names):
            pos = _align(pos, 4)
            lengths.append(pos)
            pos += 4 + u32(payload, pos)[0]
        for arr in ("position", "velocity", "effort"):
            pos = _align(pos, 4)
            lengths.append(pos)
            count = u32(payload, pos)[0]
            pos += 4
            if count:
                pos = _align(pos, 8)
                if arr == "position":
                    fields["position"] = (pos, "<f8")
                pos += 8 * count
    elif type_name == WRENCH_STAMPED:
        pos = _align(pos, 8)
        for i, name in enumerate(("force_x", "force_y", "force_z", "torque_x", "torque_y", "torque_z")):
            fields[name] = (pos + 8 * i, "<f8")
        pos += 48
    elif type_name == TEMPERATURE_MSG:
        pos = _align(pos, 8)
        fields["temperature"], fields["variance"] = (pos, "<f8"), (pos + 8, "<f8")
        pos += 16
    elif type_name == FLOAT64:
        fields["data"] = (0, "<f8")
        pos = 8
    else:
        raise BagError(f"no decoder for message type {type_name}")
    if pos > len(payload):
        raise BagError(f"{type_name} message shorter than its layout ({len(payload)} < {pos} bytes)")
    return fields, lengths


def _decode_group(type_name, buf, starts, size):
    """Decode messages of one layout: ``buf[starts[i]: starts[i] + size]`` are CDR messages."""
    first = memoryview(buf)[starts[0] + 4 : starts[0] + size]
    fields, lengths = _layout(type_name, first)
    arr = np.frombuffer(buf, dtype=np.uint8)
    steps = np.diff(starts)
    stride = int(steps[0]) if steps.size and steps[0] > 0 and np.all(steps == steps[0]) else None

    def column(off, dtype):
        """Field at byte ``off`` of every message's CDR body (after the 4-byte encapsulation)."""
        if stride is not None or starts.size == 1:  # evenly spaced records: a strided view, no index arrays
            view = np.ndarray((starts.size,), dtype=dtype, buffer=buf, offset=int(starts[0]) + 4 + off,
                              strides=(stride or 1,))
            return view.copy()
        width = np.dtype(dtype).itemsize
        return arr[starts[:, None] + 4 + off + np.arange(width)].view(dtype).ravel()

    # Same layout check: every length word equals the first message's.
    same = np.ones(starts.size, dtype=bool)
    for off in lengths:
        words = column(off, "<u4")
        same &= words == words[0]
    return {name: column(off, dtype) for name, (off, dtype) in fields.items()}, same


@dataclass
class TopicData:
    """One topic's messages as arrays, in log-time order.

    ``stamp_ns``: header stamps (ns, int64; log time for header-less types);
    ``log_time_ns``: when the recorder got each message; ``fields``: decoded
    values (``position`` for JointState, ``force_x`` ... ``torque_z`` for
    WrenchStamped, ``temperature``/``variance``, ``data`` for Float64).
    """

    topic: str
    type_name: str
    log_time_ns: np.ndarray
    stamp_ns: np.ndarray
    fields: dict

    def __len__(self):
        return int(self.log_time_ns.size)

    @property
    def t_s(self) -> np.ndarray:
        """Header stamps in seconds (float64)."""
        return self.stamp_ns.astype(np.float64) * 1e-9


@dataclass
class BagData:
    topics: dict = field(default_factory=dict)
    types: dict = field(default_factory=dict)  # every topic in the bag -> type
    warnings: list = field(default_factory=list)

    def __getitem__(self, topic) -> TopicData:
        return self.topics[topic]


# ----------------------------------------------------------------------------- reading
_REC = struct.Struct("<BQ")


def _decompress(compression, data, size):
    if compression == "":
        return data
    if compression == "zstd":
        import zstandard

        return zstandard.ZstdDecompressor().decompress(data, max_output_size=size)
    if compression == "lz4":
        import lz4.frame

        return lz4.frame.decompress(data)
    raise BagError(f"unsupported chunk compression {compression!r}")


def _string(buf, pos):
    n = struct.unpack_from("<I", buf, pos)[0]
    return bytes(buf[pos + 4 : pos + 4 + n]).decode(), pos + 4 + n


def _read_file(path):
    path = Path(path)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise BagError(f"cannot read bag {path}: {exc.strerror}") from exc
    if not raw.startswith(_MAGIC):
        raise BagError(f"{path} is not an MCAP file (bad magic bytes)")
    return raw


def _scan(raw, on_messages, schemas=None, channels=None):
    """Walk the records of an MCAP file; returns ``(schemas, channels, warnings)``.

    schemas: id -> (name, data); channels: id -> (topic, schema id), filled
    into the given dicts as the walk meets them (schemas and channels precede
    their messages, so ``on_messages`` can look them up). For every
    buffer (the file, then each chunk) ``on_messages(buf, starts, lengths)``
    gets the message records it holds, in bulk. A truncated file stops the
    walk (what came before is kept); a corrupt chunk is skipped. Both are
    reported in ``warnings``.
    """
    schemas = {} if schemas is None else schemas
    channels = {} if channels is None else channels
    warnings = []

    def scan(buf, base, in_chunk):
        pos, n = 0, len(buf)
        runs, singles, single_len = [], [], []  # message records: bulk runs and single ones, in file order
        previous = None
        while pos + 9 <= n:
            op, length = _REC.unpack_from(buf, pos)
            body = pos + 9
            if body + length > n:
                if not in_chunk:
                    warnings.append(f"bag truncated at byte {base + pos}: read what came before it")
                else:
                    warnings.append(f"chunk at byte {base} is cut short: its last messages are lost")
                break
            if op == 5:  # Message
                if previous == length:  # a run of equal messages (one topic written in a series)
                    count = _equal_message_run(buf, pos, length)
                    if singles:
                        runs.append((np.array(singles, dtype=np.int64), np.array(single_len, dtype=np.int64)))
                        singles, single_len = [], []
                    runs.append((body + (9 + length) * np.arange(count, dtype=np.int64), np.full(count, length, dtype=np.int64)))
                    pos += count * (9 + length)
                    continue
                singles.append(body)
                single_len.append(length)
                previous = length
                pos = body + length
                continue
            previous = None
            if op in (3, 4):  # Schema, Channel
                _table_record(op, buf, body, schemas, channels)
            elif op == 6 and not in_chunk:  # Chunk
                read_chunk(buf, body, base + pos)
            elif op == 2:  # Footer
                break
            pos = body + length
        if singles:
            runs.append((np.array(singles, dtype=np.int64), np.array(single_len, dtype=np.int64)))
        if runs:
            on_messages(buf, np.concatenate([r[0] for r in runs]), np.concatenate([r[1] for r in runs]))

    def read_chunk(buf, body, at):
        try:
            _start, _end, size, crc = struct.unpack_from("<QQQI", buf, body)
            compression, p = _string(buf, body + 28)
            rec_len = struct.unpack_from("<Q", buf, p)[0]
            inner = _decompress(compression, bytes(buf[p + 8 : p + 8 + rec_len]), size)
            if len(inner) != size or (crc and zlib.crc32(inner) != crc):
                raise ValueError("size or CRC mismatch")
        except BagError:
            raise
        except Exception as exc:  # noqa: BLE001 - any decoding failure means a corrupt chunk
            warnings.append(f"corrupt chunk at byte {at} ({exc}); its messages are lost, the rest is read")
            return
        scan(inner, at, in_chunk=True)

    scan(memoryview(raw)[8:], 8, in_chunk=False)
    return schemas, channels, warnings


def _equal_message_run(buf, pos, length, max_run=1 << 14):
    """How many message records of body ``length`` follow each other from ``pos`` (at least 1).

    Exactly what the record-by-record walk would find, checked in bulk: candidate k sits
    at ``pos + k (9 + length)`` and counts only if it, and every candidate before it, is a
    complete Message record of that length.
    """
    stride = 9 + length
    count = min(max_run, (len(buf) - pos) // stride)
    if count <= 1:
        return 1
    heads = np.ndarray((count, 9), dtype=np.uint8, buffer=buf, offset=pos, strides=(stride, 1))
    ok = (heads[:, 0] == 5) & (heads[:, 1:].copy().view("<u8")[:, 0] == length)
    return int(count if ok.all() else max(1, np.argmin(ok)))


def read_bag(path, topics=None, expected_types=None, optional=()) -> BagData:
    """Read topics of an MCAP bag into arrays.

    topics: iterable of topic names to decode (default: every topic of a known
    type). A requested topic that is absent raises :class:`BagError` listing
    what the bag holds. optional: topics decoded too when the bag holds them.
    expected_types: ``{topic: type}`` to enforce (default: the bag contract
    for contract topics).
    """
    raw = _read_file(path)
    expected = dict(CONTRACT)
    expected.update(expected_types or {})
    wanted_names = None if topics is None else set(topics) | set(optional)
    decoded = {}  # channel id -> [_Piece] decoded chunk by chunk, so no decompressed chunk is kept
    failed = {}  # channel id -> BagError of a type we cannot decode

    def collect(buf, starts, lens):
        arr = np.frombuffer(buf, dtype=np.uint8)
        cids = arr[starts[:, None] + np.arange(2)].view("<u2").ravel()
        for cid in np.unique(cids).tolist():
            if cid not in channels or cid in failed:
                continue
            topic, sid = channels[cid]
            if wanted_names is not None and topic not in wanted_names:
                continue
            sel = cids == cid
            try:
                decoded.setdefault(cid, []).append(_decode_piece(schemas.get(sid, ("", b""))[0], buf, starts[sel], lens[sel]))
            except BagError as exc:
                failed[cid] = exc

    schemas, channels = {}, {}
    warnings = _scan(raw, collect, schemas, channels)[2]
    types = {topic: schemas.get(sid, ("", b""))[0] for topic, sid in channels.values()}
    result = BagData(types=types, warnings=warnings)
    wanted = list(types) if topics is None else list(topics) + [t for t in optional if t in types]
    for topic in wanted:
        if topic not in types:
            raise BagError(f"{path}: topic {topic} not in bag; it holds {sorted(types) or 'no topics'}")
        if topic in expected and types[topic] != expected[topic]:
            raise BagError(f"{path}: topic {topic} has type {types[topic]}, expected {expected[topic]}")
    for cid, (topic, sid) in channels.items():
        if topic not in wanted:
            continue
        if cid in failed:
            if topics is None:
                continue  # a type we cannot decode, not asked for by name
            raise failed[cid]
        result.topics[topic] = _join_pieces(topic, schemas.get(sid, ("", b""))[0], decoded.get(cid, []))
    return result


def _summary_tables(raw, schemas, channels):
    """Fill schemas and channels from the summary section, when the file is complete.

    A writer repeats every schema and channel there, so messages whose
    definitions sat in a corrupt chunk can still be attributed. Silent when
    there is no readable summary (e.g. a truncated file).
    """
    try:
        if len(raw) < 8 + 29 + 8 or raw[-8:] != _MAGIC:
            return
        op, length = _REC.unpack_from(raw, len(raw) - 8 - 29)
        if op != 2:
            return
        summary_start = struct.unpack_from("<Q", raw, len(raw) - 8 - 20)[0]
        if not summary_start:
            return
        end = len(raw) - 8 - 29
        _scan_records(memoryview(raw)[summary_start:end], schemas, channels)
    except (struct.error, UnicodeDecodeError, ValueError):
        return


def _scan_records(buf, schemas, channels):
    """Schema and channel records of a run of top-level records (no messages, no chunks)."""
    pos, n = 0, len(buf)
    while pos + 9 <= n:
        op, length = _REC.unpack_from(buf, pos)
        body = pos + 9
        if body + length > n:
            return
        if op in (3, 4):
            _table_record(op, buf, body, schemas, channels)
        pos = body + length


def _table_record(op, buf, body, schemas, channels):
    """Register a Schema (op 3: id -> (name, data)) or Channel (op 4: id -> (topic, schema id)) record."""
    if op == 3:
        sid = struct.unpack_from("<H", buf, body)[0]
        name, p = _string(buf, body + 2)
        _encoding, p = _string(buf, p)
        data_len = struct.unpack_from("<I", buf, p)[0]
        schemas[sid] = (name, bytes(buf[p + 4 : p + 4 + data_len]))
    else:
        cid, sid = struct.unpack_from("<HH", buf, body)
        channels[cid] = (_string(buf, body + 4)[0], sid)


def copy_messages(path, writer) -> list:
    """Copy every readable message of ``path`` into ``writer`` (a :class:`BagWriter`), in file order.

    Tolerates truncation and corrupt chunks like :func:`read_bag`; returns its warnings.
    """
    raw = _read_file(path)
    schemas, channels = {}, {}
    _summary_tables(raw, schemas, channels)
    orphans = [0]

    def copy(buf, starts, lens):
        mv = memoryview(buf)
        for start, length in zip(starts.tolist(), lens.tolist()):
            cid = struct.unpack_from("<H", mv, start)[0]
            if cid not in channels or channels[cid][1] not in schemas:
                orphans[0] += 1  # its channel was defined in a lost part of the file
                continue
            log_time = struct.unpack_from("<Q", mv, start + 6)[0]
            topic, sid = channels[cid]
            name, schema_data = schemas[sid]
            writer.write_serialized(topic, name, bytes(mv[start + 22 : start + length]), log_time, schema_data=schema_data)

    warnings = _scan(raw, copy, schemas, channels)[2]
    if orphans[0]:
        warnings.append(f"{orphans[0]} messages skipped: their channel definition was lost with the damaged part")
    return warnings


@dataclass
class _Piece:
    """The messages of one topic in one buffer (a chunk), decoded."""

    log_ns: np.ndarray
    stamp_ns: np.ndarray
    fields: dict


def _decode_piece(type_name, buf, starts, lens) -> _Piece:
    """Decode the message records at ``starts`` (record bodies) of ``buf``, all of ``type_name``."""
    arr = np.frombuffer(buf, dtype=np.uint8)
    log = arr[starts[:, None] + 6 + np.arange(8)].view("<u8").ravel().astype(np.int64)
    data_starts = starts + 22
    sizes = lens - 22
    todo = np.ones(starts.size, dtype=bool)
    logs, stamps, values = [], [], {}
    while todo.any():
        i0 = int(np.flatnonzero(todo)[0])
        group = todo & (sizes == sizes[i0])
        idx = np.flatnonzero(group)
        # the group's first message defines the layout; others must match it
        order = np.concatenate(([i0], idx[idx != i0]))
        columns, same = _decode_group(type_name, buf, data_starts[order], int(sizes[i0]))
        ok = order[same]
        todo[ok] = False
        logs.append(log[ok])
        sec = columns.pop("sec", None)
        if sec is not None:
            stamps.append(sec[same].astype(np.int64) * 1_000_000_000 + columns.pop("nanosec")[same].astype(np.int64))
        else:
            stamps.append(log[ok])
        for name, column in columns.items():
            values.setdefault(name, []).append(column[same])
    return _Piece(np.concatenate(logs), np.concatenate(stamps), {k: np.concatenate(v) for k, v in values.items()})


def _join_pieces(topic, type_name, pieces) -> TopicData:
    """One topic's pieces as one :class:`TopicData`, in log-time order."""
    if not pieces:
        empty = np.zeros(0, dtype=np.int64)
        return TopicData(topic, type_name, empty, empty, {})
    log = np.concatenate([p.log_ns for p in pieces])
    order = np.argsort(log, kind="stable")
    names = set().union(*(p.fields for p in pieces))
    fields = {}
    for name in names:
        parts = [p.fields[name] for p in pieces if name in p.fields]
        if sum(map(len, parts)) == log.size:
            fields[name] = np.concatenate(parts)[order]
    return TopicData(topic, type_name, log[order], np.concatenate([p.stamp_ns for p in pieces])[order], fields)


# ----------------------------------------------------------------------------- writing
class BagWriter:
    """Write a rosbag2-compatible MCAP file.

    ``write(topic, type_name, msg, log_time_ns)`` writes one ROS message;
    ``write_series(...)`` writes a whole array of scalar samples of a contract
    type with bulk CDR encoding. Use as a context manager.
    """

    def __init__(self, path, chunk_size=1 << 20):
        from mcap.writer import CompressionType, Writer

        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._fh = open(self.path, "wb")
        self._writer = Writer(self._fh, chunk_size=chunk_size, compression=CompressionType.ZSTD)
        self._writer.start(profile="ros2", library="polyforce_ros")
        self._schemas, self._channels, self._seq = {}, {}, {}

    def _channel(self, topic, type_name, schema_data=None):
        if topic in self._channels:
            cid, known = self._channels[topic]
            if known != type_name:
                raise BagError(f"topic {topic} already written with type {known}")
            return cid
        if type_name not in self._schemas:
            data = schema_data if schema_data is not None else schema_text(type_name).encode()
            self._schemas[type_name] = self._writer.register_schema(name=type_name, encoding="ros2msg", data=data)
        cid = self._writer.register_channel(
            topic=topic, message_encoding="cdr", schema_id=self._schemas[type_name],
            metadata={"offered_qos_profiles": ""},
        )
        self._channels[topic] = (cid, type_name)
        self._seq[cid] = 0
        return cid

    def write_serialized(self, topic, type_name, data: bytes, log_time_ns: int, schema_data=None):
        """One CDR message; ``schema_data`` supplies the schema text of types not installed here."""
        cid = self._channel(topic, type_name, schema_data)
        self._seq[cid] += 1
        self._writer.add_message(channel_id=cid, log_time=int(log_time_ns), data=data,
                                 publish_time=int(log_time_ns), sequence=self._seq[cid])

    def write(self, topic, type_name, msg, log_time_ns: int):
        from rclpy.serialization import serialize_message

        self.write_serialized(topic, type_name, serialize_message(msg), log_time_ns)

    def write_series(self, topic, type_name, stamp_ns, values, frame_id=FRAME_ID, joint_name=JOINT_NAME,
                     log_time_ns=None):
        """Write one message per sample: JointState position, WrenchStamped force.z,
        Temperature temperature or Float64 data = ``values[i]``, header stamp ``stamp_ns[i]``."""
        stamp_ns = np.asarray(stamp_ns, dtype=np.int64)
        values = np.asarray(values, dtype=np.float64)
        log_time_ns = stamp_ns if log_time_ns is None else np.asarray(log_time_ns, dtype=np.int64)
        if stamp_ns.size == 0:
            self._channel(topic, type_name)
            return
        template = serialize_template(type_name, frame_id, joint_name)
        fields, _ = _layout(type_name, memoryview(template)[4:])
        n, size = stamp_ns.size, len(template)
        block = np.tile(np.frombuffer(template, dtype=np.uint8), (n, 1))
        if "sec" in fields:
            block[:, 4:8] = (stamp_ns // 1_000_000_000).astype("<i4").view(np.uint8).reshape(n, 4)
            block[:, 8:12] = (stamp_ns % 1_000_000_000).astype("<u4").view(np.uint8).reshape(n, 4)
        off = 4 + fields[SCALAR_FIELD[type_name]][0]
        block[:, off : off + 8] = values.astype("<f8").view(np.uint8).reshape(n, 8)
        raw = block.tobytes()
        for i in range(n):
            self.write_serialized(topic, type_name, raw[i * size : (i + 1) * size], log_time_ns[i])

    def close(self):
        if self._fh.closed:
            return
        self._writer.finish()
        self._fh.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def serialize_template(type_name, frame_id=FRAME_ID, joint_name=JOINT_NAME) -> bytes:
    """CDR bytes of one message of a contract type with zero stamp and value."""
    from rclpy.serialization import serialize_message

    return serialize_message(make_message(type_name, 0, 0.0, frame_id, joint_name))


def make_message(type_name, stamp_ns: int, value: float, frame_id=FRAME_ID, joint_name=JOINT_NAME):
    """A contract message carrying one scalar (see :meth:`BagWriter.write_series`)."""
    if type_name == FLOAT64:
        from std_msgs.msg import Float64

        return Float64(data=float(value))
    from builtin_interfaces.msg import Time

    stamp = Time(sec=int(stamp_ns // 1_000_000_000), nanosec=int(stamp_ns % 1_000_000_000))
    if type_name == JOINT_STATE:
        from sensor_msgs.msg import JointState

        msg = JointState(name=[joint_name], position=[float(value)])
    elif type_name == WRENCH_STAMPED:
        from geometry_msgs.msg import WrenchStamped

        msg = WrenchStamped()
        msg.wrench.force.z = float(value)
    elif type_name == TEMPERATURE_MSG:
        from sensor_msgs.msg import Temperature

        msg = Temperature(temperature=float(value))
    else:
        raise BagError(f"no contract message of type {type_name}")
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    return msg
