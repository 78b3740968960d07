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
by one with the same layout rules, so nothing is dropped for being unusual.

Problems that lose data (truncation, a corrupt chunk) are reported in
``BagData.warnings``; problems that make the bag unusable for the request (not
an MCAP file, a missing topic, the wrong type on a topic) raise
:class:`BagError` with the reason.

Damaged or hostile files lose only what they touch, in bounded time and
memory: every length word (records, strings, CDR strings and arrays) is
checked against the bytes that remain before it is used; a chunk is inflated
only up to its declared size and never beyond :data:`MAX_CHUNK_BYTES`
(decompression bombs); a chunk that is over the cap, of an unknown
compression, corrupt or holding an impossible record is skipped (or cut) with
a warning naming its byte offset; a message whose CDR does not fit its bytes
is skipped and counted per topic, also on the bulk paths (each message is
checked to have the layout the vectorised decoding assumes, the odd ones are
decoded one by one). Whatever else malformed bytes could raise becomes a
:class:`BagError`.
"""
from __future__ import annotations

import copy
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
    QOS_DEPTH,
    QOS_RELIABLE,
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
_U16 = struct.Struct("<H").unpack_from
_U32 = struct.Struct("<I").unpack_from
_U64 = struct.Struct("<Q").unpack_from
_CDR_LE = 0x0100  # encapsulation header bytes 00 01 (plain CDR, little endian), read as "<u2"
_STRUCT_OF = {"<i4": "<i", "<u4": "<I", "<f8": "<d"}

#: The value fields decoded per type (see :class:`TopicData`); a JointState without positions gives NaN.
_FIELDS = {
    JOINT_STATE: ("position",),
    WRENCH_STAMPED: ("force_x", "force_y", "force_z", "torque_x", "torque_y", "torque_z"),
    TEMPERATURE_MSG: ("temperature", "variance"),
    FLOAT64: ("data",),
}


class _Malformed(ValueError):
    """A record or message whose length words do not fit its bytes: skipped and counted, never raised out."""


def _align(pos, n):
    return (pos + n - 1) & ~(n - 1)


def _layout(type_name, payload):
    """Offsets (in the CDR payload after the 4-byte encapsulation header) of one message.

    Returns ``(fields, length_fields)``: ``fields`` maps value names to
    ``(offset, numpy dtype)``; ``length_fields`` lists offsets of the uint32
    length/count words that determine the layout (equal words in equal
    places => identical layout). Every length and count is checked against
    the bytes that remain before it is used, so a message that passes fits
    its payload; one that does not raises :class:`_Malformed`.
    """
    n = len(payload)

    def u32(pos):
        if pos + 4 > n:
            raise _Malformed(f"{type_name} message of {n} bytes cut short at byte {pos}")
        return _U32(payload, pos)[0]

    fields, lengths = {}, []
    pos = 0
    if type_name in (JOINT_STATE, WRENCH_STAMPED, TEMPERATURE_MSG):
        fields["sec"], fields["nanosec"] = (0, "<i4"), (4, "<u4")
        lengths.append(8)
        size = u32(8)
        if size > n - 12:
            raise _Malformed(f"frame_id of {size} bytes runs past the {n}-byte {type_name} message")
        pos = 12 + size  # frame_id string incl. NUL
    if type_name == JOINT_STATE:
        pos = _align(pos, 4)
        lengths.append(pos)
        n_names = u32(pos)
        pos += 4
        if n_names > (n - pos) // 4:  # a name takes at least its 4-byte length word
            raise _Malformed(f"{n_names} joint names cannot fit the {n}-byte {type_name} message")
        for _ in range(n_names):
            pos = _align(pos, 4)
            lengths.append(pos)
            size = u32(pos)
            pos += 4
            if size > n - pos:
                raise _Malformed(f"joint name of {size} bytes runs past the {n}-byte {type_name} message")
            pos += size
        for arr in ("position", "velocity", "effort"):
            pos = _align(pos, 4)
            lengths.append(pos)
            count = u32(pos)
            pos += 4
            if count:
                pos = _align(pos, 8)
                if count > (n - pos) // 8:
                    raise _Malformed(f"{arr} of {count} values runs past the {n}-byte {type_name} message")
                if arr == "position":
                    fields["position"] = (pos, "<f8")
                pos += 8 * count
    elif type_name == WRENCH_STAMPED:
        pos = _align(pos, 8)
        for i, name in enumerate(_FIELDS[WRENCH_STAMPED]):
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
    if pos > n:
        raise _Malformed(f"{type_name} message shorter than its layout ({n} < {pos} bytes)")
    return fields, lengths


def _message_layout(type_name, buf, start, size):
    """:func:`_layout` of the CDR message ``buf[start: start + size]``, its encapsulation checked too."""
    if size < 4 or _U16(buf, start)[0] != _CDR_LE:
        raise _Malformed(f"{type_name} message is not little-endian CDR")
    return _layout(type_name, memoryview(buf)[start + 4 : start + size])


def _gather(arr, offsets, dtype):
    """Values of ``dtype`` at the (unaligned) byte ``offsets`` of the uint8 array ``arr``.

    One byte column at a time: no ``(n, width)`` index array, so the temporaries stay at
    about 2 int64 per message however many messages a chunk holds.
    """
    width = np.dtype(dtype).itemsize
    out = np.empty((offsets.size, width), dtype=np.uint8)
    for k in range(width):
        np.take(arr, offsets + k if k else offsets, out=out[:, k])
    return out.view(dtype).ravel()


def _decode_group(buf, starts, fields, lengths):
    """Decode equal-size CDR messages ``buf[starts[i]:]`` assumed to share one layout (``fields``, ``lengths``
    of the first, which must be valid: see :func:`_message_layout`).

    Returns ``(columns, same)``: ``same[i]`` says message i really has that layout (its encapsulation and
    every length word equal the first's); only those entries of the columns are meaningful. Every message
    in the group has the first one's size, so a message of the same layout fits its bytes like the first.
    """
    arr = np.frombuffer(buf, dtype=np.uint8)
    steps = np.diff(starts)
    stride = int(steps[0]) if steps.size and steps[0] > 0 and np.all(steps == steps[0]) else None

    def column(off, dtype):
        """Field at byte ``off`` of every message's CDR body (after the 4-byte encapsulation)."""
        if stride is not None or starts.size == 1:  # evenly spaced records: a strided view, no index arrays
            view = np.ndarray((starts.size,), dtype=dtype, buffer=buf, offset=int(starts[0]) + 4 + off,
                              strides=(stride or 1,))
            return view.copy()
        return _gather(arr, starts + (4 + off), dtype)

    # Same layout check: the encapsulation, and every length word equal to the first message's.
    same = column(-4, "<u2") == _CDR_LE
    for off in lengths:
        words = column(off, "<u4")
        same &= words == words[0]
    return {name: column(off, dtype) for name, (off, dtype) in fields.items()}, same


def _decode_one(type_name, buf, start, size):
    """Values of the one CDR message ``buf[start: start + size]`` by field name (a field it lacks is
    absent: a JointState without positions); raises :class:`_Malformed`."""
    fields, _ = _message_layout(type_name, buf, start, size)
    return {name: struct.unpack_from(_STRUCT_OF[dtype], buf, start + 4 + off)[0]
            for name, (off, dtype) in fields.items()}


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
_CHUNK_HEAD = struct.Struct("<QQQI")  # message start/end time, uncompressed size, uncompressed CRC
_HEADER_LEN = 22  # Message record: channel id u16, sequence u32, log time u64, publish time u64, then the data
_COMPRESSIONS = ("", "zstd", "lz4")
_BATCH = 1 << 19  # message records per on_messages call at most: a dense chunk goes in parts, its index arrays bounded

#: Largest chunk (decompressed bytes) the reader inflates; a chunk that declares more, or inflates to more
#: than it declares, is skipped with a warning before anything of its size is allocated. This project
#: writes 1 MiB chunks (:class:`BagWriter`), rosbag2 0.75-4 MiB by default; a chunk also holds whole
#: messages, so one big message (a 64 MiB image or point cloud from another recorder) makes a bigger
#: one. 256 MiB is 4x such a 64 MiB chunk and still bounds reading memory: a 30 KB zstd frame can
#: claim gigabytes (a decompression bomb), and neither its frame header nor lz4 limits the output.
MAX_CHUNK_BYTES = 256 << 20
_LZ4_STEP = 4 << 20  # lz4 output is taken in pieces of this size, into one buffer of the declared size


class _ChunkSkipped(Exception):
    """A chunk not inflated on purpose (over the size cap, unknown compression): the reason."""


def _inflate(compression, data, size, limit=None):
    """The records of a chunk: ``data`` decompressed, exactly ``size`` (its declared size) bytes.

    Never produces more than ``min(size, limit) + 1`` bytes, whatever the compressed stream or its frame
    header claims: an unknown compression or a size over ``limit`` raises :class:`_ChunkSkipped` at
    once, output longer or shorter than ``size`` raises :class:`_Malformed`.
    """
    limit = MAX_CHUNK_BYTES if limit is None else limit
    if compression not in _COMPRESSIONS:
        raise _ChunkSkipped(f"uses unknown compression {compression[:40]!r}")
    if size > limit:
        raise _ChunkSkipped(f"declares {size} bytes uncompressed, over the {limit >> 20} MiB limit "
                            f"(MAX_CHUNK_BYTES; a decompression bomb?)")
    if compression == "":
        out = data
    elif compression == "zstd":
        import zstandard

        # A streaming read bounded by the declared size; one-shot decompress() would allocate whatever
        # the frame header claims, max_output_size notwithstanding.
        reader = zstandard.ZstdDecompressor().stream_reader(data, read_across_frames=True)
        out = reader.read(size)
        if len(out) == size:
            try:
                more = reader.read(1)
            except zstandard.ZstdError:
                more = b""  # junk after the declared content: the CRC judges what we keep
            if more:
                raise _Malformed(f"it inflates beyond its declared {size} bytes")
    else:
        import lz4.frame

        dec, out, got = lz4.frame.LZ4FrameDecompressor(), bytearray(size), 0
        piece = dec.decompress(data, max_length=min(size + 1, _LZ4_STEP))
        while True:
            if got + len(piece) > size:
                raise _Malformed(f"it inflates beyond its declared {size} bytes")
            out[got : got + len(piece)] = piece
            got += len(piece)
            if dec.eof or dec.needs_input or not piece:
                break
            piece = dec.decompress(b"", max_length=min(size - got + 1, _LZ4_STEP))
        out = memoryview(out)[:got]
    if len(out) != size:
        raise _Malformed(f"it inflates to {len(out)} bytes, not the declared {size}")
    return out


def _raw_string(buf, pos):
    """The bytes of a length-prefixed string at ``pos`` of ``buf`` (one record) and where it ends;
    :class:`_Malformed` when the length runs past the record."""
    if pos + 4 > len(buf):
        raise _Malformed("string length cut short")
    end = pos + 4 + _U32(buf, pos)[0]
    if end > len(buf):
        raise _Malformed(f"string of {end - pos - 4} bytes runs past its record")
    return bytes(buf[pos + 4 : end]), end


def _string(buf, pos):
    """A length-prefixed UTF-8 string at ``pos`` of ``buf`` (one record): ``(text, end)``; :class:`_Malformed`
    when the length runs past the record or the bytes are not UTF-8."""
    raw, end = _raw_string(buf, pos)
    try:
        return raw.decode("utf-8"), end
    except UnicodeDecodeError as exc:
        raise _Malformed("string is not UTF-8") from exc


def _read_file(path):
    path = bag_file(path)  # a bag directory reads its one .mcap file
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise BagError(f"cannot read bag {path}: {exc.strerror}") from exc
    if not raw.startswith(_MAGIC):
        raise BagError(f"{path} is not an MCAP file (bad magic bytes)")
    return raw


def _count_warnings(counts, what):
    """One warning per topic of ``counts`` (topic or None -> number): ``N <what> on <topic> ...``."""
    out = []
    for topic in sorted(counts, key=str):
        where = f"on {topic}" if topic is not None else "on an unknown channel"
        out.append(what.format(n=counts[topic], where=where))
    return out


def _scan(raw, on_messages, schemas=None, channels=None, malformed=None):
    """Walk the records of an MCAP file; returns ``(schemas, channels, warnings)``.

    schemas: id -> (name, data); channels: id -> (topic, schema id), filled
    into the given dicts as the walk meets them (schemas and channels precede
    their messages, so ``on_messages`` can look them up). For every
    buffer (the file, then each chunk) ``on_messages(buf, starts, lengths)``
    gets the message records it holds, in bulk; each is at least a message
    header long and lies inside ``buf``. A truncated file stops the walk (what
    came before is kept); a corrupt chunk, one over :data:`MAX_CHUNK_BYTES` or
    of an unknown compression is skipped; a record inside a chunk that cannot
    be one (bad opcode, length past the chunk's end) ends that chunk. Message
    records too short for their header are counted per topic in ``malformed``
    (topic or None -> count); schema and channel records that are malformed or
    contradict an earlier definition are ignored. All is reported in ``warnings``.
    """
    schemas = {} if schemas is None else schemas
    channels = {} if channels is None else channels
    malformed = {} if malformed is None else malformed
    warnings = []
    bad_tables = [0]

    def hand_on(buf, runs):
        """Give the message records of ``runs`` to on_messages; count those too short for a header."""
        starts, lens = np.concatenate([r[0] for r in runs]), np.concatenate([r[1] for r in runs])
        short = lens < _HEADER_LEN
        if short.any():
            for start, length in zip(starts[short].tolist(), lens[short].tolist()):
                topic = channels.get(_U16(buf, start)[0], (None,))[0] if length >= 2 else None
                malformed[topic] = malformed.get(topic, 0) + 1
            starts, lens = starts[~short], lens[~short]
        if starts.size:
            on_messages(buf, starts, lens)

    def scan(buf, base, in_chunk):
        buf = memoryview(buf)
        pos, n = 0, len(buf)
        runs, singles, single_len = [], [], []  # message records: bulk runs and single ones, in file order
        pending = 0  # records in runs
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
                        pending += len(singles)
                        singles, single_len = [], []
                    runs.append((body + (9 + length) * np.arange(count, dtype=np.int64), np.full(count, length, dtype=np.int64)))
                    pending += count
                    pos += count * (9 + length)
                    if pending >= _BATCH:  # a dense chunk is handed on in parts: bounded index arrays
                        hand_on(buf, runs)
                        runs, pending = [], 0
                    continue
                singles.append(body)
                single_len.append(length)
                previous = length
                pos = body + length
                if len(singles) >= _BATCH:
                    hand_on(buf, runs + [(np.array(singles, dtype=np.int64), np.array(single_len, dtype=np.int64))])
                    runs, singles, single_len, pending = [], [], [], 0
                continue
            previous = None
            if op in (3, 4):  # Schema, Channel
                try:
                    _table_record(op, buf[body : body + length], schemas, channels)
                except _Malformed:
                    bad_tables[0] += 1
            elif in_chunk:  # a chunk holds schemas, channels and messages only: the framing is lost
                warnings.append(f"chunk at byte {base} holds an invalid record (opcode {op:#04x}) at offset {pos}: "
                                "its remaining messages are lost")
                break
            elif op == 6:  # Chunk
                read_chunk(buf[body : body + length], base + pos)
            elif op == 2:  # Footer
                break
            elif op == 0:  # no writer makes it: zeroed or overwritten bytes
                warnings.append(f"bag damaged at byte {base + pos} (record opcode 0x00): read what came before it")
                break
            pos = body + length
        if singles:
            runs.append((np.array(singles, dtype=np.int64), np.array(single_len, dtype=np.int64)))
        if runs:
            hand_on(buf, runs)

    def read_chunk(rec, at):
        try:
            _start, _end, size, crc = _CHUNK_HEAD.unpack_from(rec, 0)
            compression, p = _raw_string(rec, 28)
            compression = compression.decode("utf-8", "replace")  # not UTF-8: an unknown compression
            if p + 8 > len(rec):
                raise _Malformed("chunk header cut short")
            data_len = _U64(rec, p)[0]
            if data_len > len(rec) - p - 8:
                raise _Malformed(f"its {data_len} compressed bytes run past the chunk")
            inner = _inflate(compression, rec[p + 8 : p + 8 + data_len], size)
            if crc and zlib.crc32(inner) != crc:
                raise _Malformed("CRC mismatch")
        except _ChunkSkipped as exc:
            warnings.append(f"chunk at byte {at} {exc}: skipped, its messages are lost, the rest is read")
            return
        except Exception as exc:  # noqa: BLE001 - any decoding failure means a corrupt chunk
            warnings.append(f"corrupt chunk at byte {at} ({exc}); its messages are lost, the rest is read")
            return
        scan(inner, at, in_chunk=True)

    scan(memoryview(raw)[8:], 8, in_chunk=False)
    if bad_tables[0]:
        warnings.append(f"{bad_tables[0]} malformed or contradicting schema/channel records ignored")
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


# Exceptions that malformed bytes could still raise from numpy/struct if a check above missed a case:
# read_bag and copy_messages turn them into a BagError naming the file rather than a traceback.
_GARBAGE_ERRORS = (struct.error, IndexError, KeyError, TypeError, ValueError, OverflowError)


def read_bag(path, topics=None, expected_types=None, optional=()) -> BagData:
    """Read topics of an MCAP bag into arrays.

    topics: iterable of topic names to decode (default: every topic of a known
    type). A requested topic that is absent raises :class:`BagError` listing
    what the bag holds. optional: topics decoded too when the bag holds them.
    expected_types: ``{topic: type}`` to enforce (default: the bag contract
    for contract topics).

    Damage loses only what it touches, each kind reported once in ``warnings``:
    a truncated file, a corrupt chunk (bad CRC, undecodable, inflating to other
    than its declared size), a chunk over :data:`MAX_CHUNK_BYTES` or of an
    unknown compression; messages whose CDR does not fit their bytes are
    skipped and counted per topic, as are messages on undefined channels.
    """
    raw = _read_file(path)
    try:
        return _read_bag(path, raw, topics, expected_types, optional)
    except BagError:
        raise
    except _GARBAGE_ERRORS as exc:
        raise BagError(f"{path}: unreadable bag data ({type(exc).__name__}: {exc})") from exc


def _read_bag(path, raw, topics, expected_types, optional):
    expected = dict(CONTRACT)
    expected.update(expected_types or {})
    wanted_names = None if topics is None else set(topics) | set(optional)
    decoded = {}  # channel id -> [_Piece] decoded chunk by chunk, so no decompressed chunk is kept
    failed = {}  # channel id -> BagError of a type we cannot decode
    malformed, no_position, undefined = {}, {}, [0]  # topic -> messages skipped / without a position

    def collect(buf, starts, lens):
        arr = np.frombuffer(buf, dtype=np.uint8)
        cids = _gather(arr, starts, "<u2")
        for cid in np.unique(cids).tolist():
            if cid not in channels:
                undefined[0] += int(np.count_nonzero(cids == cid))
                continue
            if cid in failed:
                continue
            topic, sid = channels[cid]
            if wanted_names is not None and topic not in wanted_names:
                continue
            type_name = schemas.get(sid, ("", b""))[0]
            if type_name not in _FIELDS:
                failed[cid] = BagError(f"no decoder for message type {type_name}")
                continue
            sel = cids == cid
            piece, n_bad, n_empty = _decode_piece(type_name, buf, starts[sel], lens[sel])
            decoded.setdefault(cid, []).append(piece)
            if n_bad:
                malformed[topic] = malformed.get(topic, 0) + n_bad
            if n_empty:
                no_position[topic] = no_position.get(topic, 0) + n_empty

    schemas, channels = {}, {}
    _summary_tables(raw, schemas, channels)  # so a lost first chunk does not orphan the rest
    warnings = _scan(raw, collect, schemas, channels, malformed)[2]
    warnings += _count_warnings(malformed, "{n} malformed messages {where} skipped")
    warnings += _count_warnings(no_position, "{n} messages {where} carry no position: read as NaN")
    if undefined[0]:
        warnings.append(f"{undefined[0]} messages on undefined channels skipped")
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
            try:
                _table_record(op, buf[body : body + length], schemas, channels)
            except _Malformed:
                pass
        pos = body + length


def _table_record(op, rec, schemas, channels):
    """Register a Schema (op 3: id -> (name, data)) or Channel (op 4: id -> (topic, schema id)) record
    whose body is ``rec``. Raises :class:`_Malformed` for one whose fields run past it, or that
    contradicts an earlier record of the same id (the first one is kept)."""
    if op == 3:
        if len(rec) < 2:
            raise _Malformed("schema record cut short")
        sid = _U16(rec, 0)[0]
        name, p = _string(rec, 2)
        _encoding, p = _string(rec, p)
        if p + 4 > len(rec) or _U32(rec, p)[0] > len(rec) - p - 4:
            raise _Malformed("schema data runs past its record")
        key, table, entry = sid, schemas, (name, bytes(rec[p + 4 : p + 4 + _U32(rec, p)[0]]))
        if sid == 0:
            raise _Malformed("schema id 0 is reserved")
    else:
        if len(rec) < 4:
            raise _Malformed("channel record cut short")
        cid, sid = struct.unpack_from("<HH", rec, 0)
        topic, p = _string(rec, 4)
        _string(rec, p)  # message encoding
        key, table, entry = cid, channels, (topic, sid)
    known = table.get(key)
    if known is None:
        table[key] = entry
    elif known != entry:
        raise _Malformed(f"record contradicts the earlier definition of id {key}")


def copy_messages(path, writer) -> list:
    """Copy every readable message of ``path`` into ``writer`` (a :class:`BagWriter`), in file order.

    Tolerates truncation, corrupt and oversized chunks like :func:`read_bag`;
    returns its warnings. Messages are copied as they are (their CDR is not
    decoded); records too short to be a message are skipped and counted.
    """
    raw = _read_file(path)
    schemas, channels = {}, {}
    _summary_tables(raw, schemas, channels)
    orphans = [0]
    malformed = {}

    def copy(buf, starts, lens):
        mv = memoryview(buf)
        for start, length in zip(starts.tolist(), lens.tolist()):
            cid = _U16(mv, start)[0]
            if cid not in channels or channels[cid][1] not in schemas:
                orphans[0] += 1  # its channel was defined in a lost part of the file
                continue
            log_time = _U64(mv, start + 6)[0]
            topic, sid = channels[cid]
            name, schema_data = schemas[sid]
            writer.write_serialized(topic, name, bytes(mv[start + _HEADER_LEN : start + length]), log_time,
                                    schema_data=schema_data)

    try:
        warnings = _scan(raw, copy, schemas, channels, malformed)[2]
    except BagError:
        raise
    except _GARBAGE_ERRORS as exc:
        raise BagError(f"{path}: unreadable bag data ({type(exc).__name__}: {exc})") from exc
    warnings += _count_warnings(malformed, "{n} malformed messages {where} skipped")
    if orphans[0]:
        warnings.append(f"{orphans[0]} messages skipped: their channel definition was lost with the damaged part")
    return warnings


@dataclass
class _Piece:
    """The messages of one topic in one buffer (a chunk), decoded."""

    log_ns: np.ndarray
    stamp_ns: np.ndarray
    fields: dict


#: A group of equal-size messages smaller than this is decoded message by message (bulk set-up costs more).
_BULK_MIN = 16
#: Bulk layouts tried per group of equal-size messages; what is left then goes message by message, so
#: garbage of many layouts costs linear time, not one vectorised pass per layout.
_BULK_ROUNDS = 8


def _decode_piece(type_name, buf, starts, lens):
    """Decode the message records at ``starts`` (record bodies, lengths ``lens``) of ``buf``, all of ``type_name``.

    Returns ``(piece, malformed, without_position)``. Messages of equal size are decoded in bulk with
    the layout of the first well-formed one; each is checked to really have it (:func:`_decode_group`),
    and those that do not are decoded one by one, their lengths validated (:func:`_layout`): a message
    whose CDR does not fit its bytes is left out and counted in ``malformed``. A JointState without
    positions reads as NaN (counted in ``without_position``).
    """
    arr = np.frombuffer(buf, dtype=np.uint8)
    log = _gather(arr, starts + 6, "<u8").astype(np.int64)
    data_starts = starts + _HEADER_LEN
    sizes = lens - _HEADER_LEN
    names = _FIELDS[type_name]
    kept, secs, nsecs, values = [], [], [], {name: [] for name in names}
    odd = []  # index arrays of messages to decode one by one
    n_empty = 0
    if sizes[0] == sizes.min() == sizes.max():  # the normal case: one layout per topic
        groups = [np.arange(sizes.size)]
    else:
        order = np.argsort(sizes, kind="stable")
        groups = np.split(order, np.flatnonzero(np.diff(sizes[order])) + 1)
    for idx in groups:
        for _ in range(_BULK_ROUNDS):
            if idx.size < _BULK_MIN:
                break
            i0 = int(idx[0])
            try:
                fields, lengths = _message_layout(type_name, buf, int(data_starts[i0]), int(sizes[i0]))
            except _Malformed:  # the first is malformed (counted by the one-by-one pass): the next leads
                odd.append(idx[:1])
                idx = idx[1:]
                continue
            columns, same = _decode_group(buf, data_starts[idx], fields, lengths)
            if not same[0]:
                break
            kept.append(idx[same])
            if "sec" in columns:
                secs.append(columns["sec"][same])
                nsecs.append(columns["nanosec"][same])
            for name in names:
                if name in columns:
                    values[name].append(columns[name][same])
                else:  # a JointState with an empty position array
                    values[name].append(np.full(int(np.count_nonzero(same)), np.nan))
                    n_empty += int(np.count_nonzero(same))
            idx = idx[~same]
        if idx.size:
            odd.append(idx)
    n_bad = 0
    if odd:
        one_idx, one_sec, one_nsec, one_vals = [], [], [], {name: [] for name in names}
        for i in np.concatenate(odd).tolist():
            try:
                got = _decode_one(type_name, buf, int(data_starts[i]), int(sizes[i]))
            except _Malformed:
                n_bad += 1
                continue
            one_idx.append(i)
            if "sec" in got:
                one_sec.append(got["sec"])
                one_nsec.append(got["nanosec"])
            for name in names:
                one_vals[name].append(got.get(name, np.nan))
            n_empty += any(name not in got for name in names)
        kept.append(np.array(one_idx, dtype=np.int64))
        secs.append(np.array(one_sec, dtype=np.int64))
        nsecs.append(np.array(one_nsec, dtype=np.int64))
        for name in names:
            values[name].append(np.array(one_vals[name], dtype=np.float64))
    ok = np.concatenate(kept) if kept else np.zeros(0, dtype=np.int64)
    if type_name in (JOINT_STATE, WRENCH_STAMPED, TEMPERATURE_MSG):
        stamps = (np.concatenate(secs).astype(np.int64) * 1_000_000_000 + np.concatenate(nsecs).astype(np.int64)
                  if secs else np.zeros(0, dtype=np.int64))
    else:
        stamps = log[ok]
    fields = {name: np.concatenate(v) if v else np.zeros(0) for name, v in values.items()}
    return _Piece(log[ok], stamps, fields), n_bad, n_empty


def _join_pieces(topic, type_name, pieces) -> TopicData:
    """One topic's pieces as one :class:`TopicData`, in log-time order."""
    if not pieces:  # none read (all lost or malformed): empty columns, every field present
        empty = np.zeros(0, dtype=np.int64)
        return TopicData(topic, type_name, empty, empty, {name: np.zeros(0) for name in _FIELDS.get(type_name, ())})
    log = np.concatenate([p.log_ns for p in pieces])
    order = np.argsort(log, kind="stable")
    fields = {name: np.concatenate([p.fields[name] for p in pieces])[order] for name in pieces[0].fields}
    return TopicData(topic, type_name, log[order], np.concatenate([p.stamp_ns for p in pieces])[order], fields)


# ----------------------------------------------------------------------------- writing
#: QoS a rosbag2 reader replays the contract topics with (what our nodes offer: reliable, keep-last, volatile).
_INFINITE = {"sec": 9223372036, "nsec": 854775807}
DEFAULT_QOS = [{"history": "keep_last", "depth": QOS_DEPTH, "reliability": "reliable" if QOS_RELIABLE else "best_effort",
                "durability": "volatile", "deadline": dict(_INFINITE), "lifespan": dict(_INFINITE),
                "liveliness": "automatic", "liveliness_lease_duration": dict(_INFINITE),
                "avoid_ros_namespace_conventions": False}]


def type_hash(type_name: str) -> str:
    """The RIHS01 type description hash of an installed message type (``pkg/msg/Type``), or "" when unknown.

    Read from the ``.json`` type description the ROS 2 message packages install next to the ``.msg``.
    """
    import json

    package, _, name = type_name.partition("/msg/")
    for prefix in _share_prefixes():
        path = Path(prefix) / "share" / package / "msg" / f"{name}.json"
        if path.is_file():
            try:
                hashes = json.loads(path.read_text())["type_hashes"]
            except (ValueError, KeyError, OSError):
                return ""
            return next((h["hash_string"] for h in hashes if h.get("type_name") == type_name), "")
    return ""


def _share_prefixes():
    return [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p] + [sys.prefix]


def bag_file(path) -> Path:
    """The MCAP file of a bag given as a file or as a rosbag2 bag directory (``metadata.yaml``).

    ``BagError`` for a directory that is not a one-file MCAP bag.
    """
    path = Path(path)
    if not path.is_dir():
        return path
    meta = path / "metadata.yaml"
    if meta.is_file():
        import yaml

        try:
            info = yaml.safe_load(meta.read_text())["rosbag2_bagfile_information"]
            files = list(info["relative_file_paths"])
            storage = info.get("storage_identifier", "mcap")
        except (yaml.YAMLError, KeyError, TypeError, OSError) as exc:
            raise BagError(f"{meta}: not a rosbag2 metadata file ({exc})") from exc
        if storage != "mcap":
            raise BagError(f"{path}: storage {storage!r}; only mcap bags can be read")
        if len(files) != 1:
            raise BagError(f"{path}: {len(files)} bag files; split bags are not supported")
        return path / files[0]
    found = sorted(path.glob("*.mcap"))
    if len(found) != 1:
        raise BagError(f"{path}: a bag directory needs metadata.yaml or exactly one .mcap file, found {len(found)}")
    return found[0]


class BagWriter:
    """Write a rosbag2 MCAP bag, as rosbag2_storage_mcap (Jazzy) does.

    - Messages are written in log-time order across topics (chunks do not overlap), whatever the order of
      the calls: with ``ordered=True`` (default) they are collected and written sorted at :meth:`close`
      (ties keep call order); a live recorder whose log times are arrival times passes ``ordered=False``.
    - Each channel carries ``offered_qos_profiles`` (the YAML list rosbag2 writes) and ``topic_type_hash``
      (RIHS01, where the message package installs it); the file ends with the ``rosbag2`` metadata record
      (``serialized_metadata``: the bag's metadata YAML).
    - ``directory=True`` writes the bag-directory form ``PATH/PATH.name_0.mcap`` + ``PATH/metadata.yaml``.
    - Every byte of a message written by :meth:`write_series` or :meth:`write` (contract types) is set
      (:mod:`polyforce_ros.cdr`), so equal content gives equal files.

    Use as a context manager.
    """

    def __init__(self, path, chunk_size=1 << 20, ordered=True, directory=False):
        from mcap.writer import CompressionType, Writer

        path = Path(path)
        if directory:
            path.mkdir(parents=True, exist_ok=True)
            self.directory, self.path = path, path / f"{path.name}_0.mcap"
        else:
            path.parent.mkdir(parents=True, exist_ok=True)
            self.directory, self.path = None, path
        self._fh = open(self.path, "wb")
        self._writer = Writer(self._fh, chunk_size=chunk_size, compression=CompressionType.ZSTD)
        self._writer.start(profile="ros2", library="polyforce_ros")
        self._schemas, self._channels, self._seq, self._counts = {}, {}, {}, {}
        self._ordered = ordered
        self._singles: list = []   # (log ns, publish ns, channel id, bytes), in call order
        self._series: list = []    # (channel id, encoded (n, size) uint8, log ns (n,)), in call order
        self._t_min, self._t_max = None, None

    def _channel(self, topic, type_name, schema_data=None):
        if topic in self._channels:
            cid, known = self._channels[topic]
            if known != type_name:
                raise BagError(f"topic {topic} already written with type {known}")
            return cid
        if type_name not in self._schemas:
            data = schema_data if schema_data is not None else schema_text(type_name).encode()
            self._schemas[type_name] = self._writer.register_schema(name=type_name, encoding="ros2msg", data=data)
        import yaml

        metadata = {"offered_qos_profiles": yaml.safe_dump(DEFAULT_QOS, sort_keys=False).strip()}
        digest = type_hash(type_name)
        if digest:
            metadata["topic_type_hash"] = digest
        cid = self._writer.register_channel(topic=topic, message_encoding="cdr", schema_id=self._schemas[type_name],
                                            metadata=metadata)
        self._channels[topic] = (cid, type_name)
        self._seq[cid], self._counts[cid] = 0, 0
        return cid

    def write_serialized(self, topic, type_name, data: bytes, log_time_ns: int, schema_data=None,
                         publish_time_ns=None):
        """One CDR message; ``publish_time_ns``: when it was sent (default: its log time);
        ``schema_data`` supplies the schema text of types not installed here."""
        cid = self._channel(topic, type_name, schema_data)
        log = int(log_time_ns)
        publish = log if publish_time_ns is None else int(publish_time_ns)
        if self._ordered:
            self._singles.append((log, publish, cid, bytes(data)))
        else:
            self._emit(cid, log, publish, data)

    def write(self, topic, type_name, msg, log_time_ns: int):
        """One ROS message object; contract types are encoded by :mod:`.cdr` (every byte set)."""
        from . import cdr

        try:
            data = cdr.encode_message(type_name, msg)
        except ValueError:  # not a contract type: the middleware's serialiser
            from rclpy.serialization import serialize_message

            data = serialize_message(msg)
        self.write_serialized(topic, type_name, data, log_time_ns)

    def write_series(self, topic, type_name, stamp_ns, values, frame_id=FRAME_ID, joint_name=JOINT_NAME,
                     log_time_ns=None):
        """Write one message per sample: JointState position, WrenchStamped force.z,
        Temperature temperature or Float64 data = ``values[i]``, header stamp ``stamp_ns[i]``.

        The CDR bytes come from :mod:`polyforce_ros.cdr`: every byte is set
        (zero padding, no trailing bytes), so equal input gives equal files and
        strict CDR readers (rosbags) accept every message. Inputs are checked
        before anything is written (``ValueError``: unequal lengths, a stamp
        outside the builtin_interfaces/Time range, a negative log time).
        """
        from . import cdr

        stamp_ns = np.asarray(stamp_ns, dtype=np.int64)
        values = np.asarray(values, dtype=np.float64)
        log_time_ns = stamp_ns if log_time_ns is None else np.asarray(log_time_ns, dtype=np.int64)
        if not stamp_ns.ndim == values.ndim == log_time_ns.ndim == 1 or not stamp_ns.size == values.size == log_time_ns.size:
            raise ValueError(f"write_series needs 1-D stamps, values and log times of one length, got shapes "
                             f"{stamp_ns.shape}, {values.shape}, {log_time_ns.shape}")
        try:
            layout = cdr.series_layout(type_name, frame_id, joint_name)
        except ValueError as exc:  # a type without an encoder, a NUL in a name
            raise BagError(f"write_series on {topic}: {exc}") from exc
        cdr.split_stamps(stamp_ns)  # the whole series is valid before its first message is written
        if log_time_ns.size and log_time_ns.min() < 0:
            raise ValueError("write_series: log times must be >= 0 ns")
        cid = self._channel(topic, type_name)
        encoded = layout.encode(stamp_ns, values)
        if self._ordered:
            self._series.append((cid, encoded, log_time_ns.copy()))
        else:
            raw = encoded.tobytes()
            size = encoded.shape[1] if encoded.ndim == 2 else layout.size
            for i, t in enumerate(log_time_ns.tolist()):
                self._emit(cid, t, t, raw[i * size : (i + 1) * size])

    def _emit(self, cid, log, publish, data):
        self._seq[cid] += 1
        self._counts[cid] += 1
        self._writer.add_message(channel_id=cid, log_time=log, data=data, publish_time=publish, sequence=self._seq[cid])
        self._t_min = log if self._t_min is None else min(self._t_min, log)
        self._t_max = log if self._t_max is None else max(self._t_max, log)

    def _flush_sorted(self):
        """Every collected message, in log-time order (stable: ties keep call order)."""
        parts = [np.array([s[0] for s in self._singles], dtype=np.int64)] + [log for _, _, log in self._series]
        sizes = [len(p) for p in parts]
        if not sum(sizes):
            return
        order = np.argsort(np.concatenate(parts), kind="stable")
        source = np.repeat(np.arange(len(parts)), sizes)[order]
        offset = np.concatenate(([0], np.cumsum(sizes)[:-1]))
        index = order - offset[source]
        series = [(cid, enc.tobytes(), enc.shape[1], log) for cid, enc, log in self._series]
        singles = self._singles
        for src, i in zip(source.tolist(), index.tolist()):
            if src == 0:
                log, publish, cid, data = singles[i]
                self._emit(cid, log, publish, data)
            else:
                cid, raw, size, logs = series[src - 1]
                t = int(logs[i])
                self._emit(cid, t, t, raw[i * size : (i + 1) * size])
        self._singles, self._series = [], []

    def metadata(self) -> dict:
        """The rosbag2 bag metadata (version 9) of what was written."""
        start = self._t_min or 0
        duration = (self._t_max - self._t_min) if self._t_min is not None else 0
        count = sum(self._counts.values())
        topics = []
        for topic, (cid, type_name) in self._channels.items():
            topics.append({"topic_metadata": {"name": topic, "type": type_name, "serialization_format": "cdr",
                                              "offered_qos_profiles": copy.deepcopy(DEFAULT_QOS),  # no YAML aliases
                                              "type_description_hash": type_hash(type_name)},
                           "message_count": self._counts[cid]})
        return {"rosbag2_bagfile_information": {
            "version": 9, "storage_identifier": "mcap", "duration": {"nanoseconds": duration},
            "starting_time": {"nanoseconds_since_epoch": start}, "message_count": count,
            "topics_with_message_count": topics, "compression_format": "", "compression_mode": "",
            "relative_file_paths": [self.path.name],
            "files": [{"path": self.path.name, "starting_time": {"nanoseconds_since_epoch": start},
                       "duration": {"nanoseconds": duration}, "message_count": count}],
            "custom_data": None, "ros_distro": "jazzy"}}

    def close(self):
        if self._fh.closed:
            return
        import yaml

        self._flush_sorted()
        info = self.metadata()
        self._writer.add_metadata("rosbag2", {"serialized_metadata": yaml.safe_dump(
            info["rosbag2_bagfile_information"], sort_keys=False)})
        self._writer.finish()
        self._fh.close()
        if self.directory is not None:
            (self.directory / "metadata.yaml").write_text(yaml.safe_dump(info, sort_keys=False))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def serialize_template(type_name, frame_id=FRAME_ID, joint_name=JOINT_NAME) -> bytes:
    """CDR bytes of one message of a contract type with zero stamp and value (every byte set, see :mod:`.cdr`)."""
    from . import cdr

    try:
        return cdr.series_layout(type_name, frame_id, joint_name).template
    except ValueError as exc:
        raise BagError(str(exc)) from exc


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
