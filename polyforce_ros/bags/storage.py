"""MCAP at the record level: finding the file, walking its records, inflating chunks, copying messages.

:func:`scan` walks the records of an MCAP file linearly (so a truncated file
still yields everything before the cut), registers Schema and Channel records
as it meets them and hands the Message records of each buffer (the file, then
each decompressed chunk) on in bulk, as arrays of record offsets and lengths.
:func:`summary_tables` reads the schemas and channels the summary section
repeats, so messages whose definitions sat in a damaged chunk can still be
attributed. :func:`copy_messages` copies every readable message into a writer
without decoding it.

Damaged or hostile files lose only what they touch, in bounded time and
memory: every length word (records, strings) is checked against the bytes
that remain before it is used; a chunk is inflated only up to its declared
size and never beyond :data:`MAX_CHUNK_BYTES` (decompression bombs); a chunk
that is over the cap, of an unknown compression, corrupt or holding an
impossible record is skipped (or cut) with a warning naming its byte offset.
"""
from __future__ import annotations

import os
import struct
import zlib
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Protocol, TypeAlias, TypeVar

import numpy as np
import numpy.typing as npt

from .errors import BagError, Malformed
from .serde import Buffer

__all__ = [
    "GARBAGE_ERRORS", "HEADER_LEN", "MAX_CHUNK_BYTES", "Channels", "MessageSink", "OnMessages", "Schemas",
    "StrPath", "bag_file", "copy_messages", "count_warnings", "mcap_bytes", "scan", "summary_tables",
]

#: A file system path.
StrPath: TypeAlias = str | os.PathLike[str]
#: Schema id -> ``(type name, schema data)``.
Schemas: TypeAlias = dict[int, tuple[str, bytes]]
#: Channel id -> ``(topic, schema id)``.
Channels: TypeAlias = dict[int, tuple[str, int]]
#: ``on_messages(buf, starts, lengths)`` of :func:`scan`: the Message records of ``buf`` whose bodies
#: start at ``starts`` (int64 byte offsets) and are ``lengths`` bytes long.
OnMessages: TypeAlias = Callable[[Buffer, npt.NDArray[np.int64], npt.NDArray[np.int64]], None]

_Runs: TypeAlias = list[tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]]  # record body offsets, lengths
_Entry = TypeVar("_Entry")  # a Schemas or Channels value

_MAGIC = b"\x89MCAP0\r\n"
_U16 = struct.Struct("<H").unpack_from
_U32 = struct.Struct("<I").unpack_from
_U64 = struct.Struct("<Q").unpack_from
_REC = struct.Struct("<BQ")
_CHUNK_HEAD = struct.Struct("<QQQI")  # message start/end time, uncompressed size, uncompressed CRC
#: Bytes of a Message record body before the data: channel id u16, sequence u32, log time u64, publish time u64.
HEADER_LEN = 22
_COMPRESSIONS = ("", "zstd", "lz4")
_BATCH = 1 << 19  # message records per on_messages call at most: a dense chunk goes in parts, its index arrays bounded

#: Largest chunk (decompressed bytes) the reader inflates; a chunk that declares more, or inflates to more
#: than it declares, is skipped with a warning before anything of its size is allocated. BagWriter writes
#: 1 MiB chunks, rosbag2 0.75-4 MiB by default; a chunk also holds whole messages, so one big message (a
#: 64 MiB image or point cloud from another recorder) makes a bigger one. 256 MiB is 4x such a 64 MiB
#: chunk and still bounds reading memory: a 30 KB zstd frame can claim gigabytes (a decompression bomb),
#: and neither its frame header nor lz4 limits the output.
MAX_CHUNK_BYTES = 256 << 20
_LZ4_STEP = 4 << 20  # lz4 output is taken in pieces of this size, into one buffer of the declared size

#: Exceptions that malformed bytes could still raise from numpy/struct if a length check missed a case:
#: the readers turn them into a BagError naming the file rather than a traceback.
GARBAGE_ERRORS = (struct.error, IndexError, KeyError, TypeError, ValueError, OverflowError)


class MessageSink(Protocol):
    """Where :func:`copy_messages` puts messages (a :class:`~polyforce_ros.bags.BagWriter`)."""

    def write_serialized(self, topic: str, type_name: str, data: bytes, log_time_ns: int,
                         schema_data: bytes | None = None) -> None:
        """One CDR message of ``topic``, logged at ``log_time_ns`` (ns); ``schema_data``: its schema text."""


class _ChunkSkipped(Exception):
    """A chunk not inflated on purpose (over the size cap, unknown compression): the reason."""


def _inflate(compression: str, data: memoryview, size: int, limit: int | None = None) -> Buffer:
    """The records of a chunk: ``data`` decompressed, exactly ``size`` (its declared size) bytes.

    Never produces more than ``min(size, limit) + 1`` bytes, whatever the compressed stream or its frame
    header claims: an unknown compression or a size over ``limit`` raises :class:`_ChunkSkipped` at
    once, output longer or shorter than ``size`` raises :class:`Malformed`.
    """
    limit = MAX_CHUNK_BYTES if limit is None else limit
    if compression not in _COMPRESSIONS:
        raise _ChunkSkipped(f"uses unknown compression {compression[:40]!r}")
    if size > limit:
        raise _ChunkSkipped(f"declares {size} bytes uncompressed, over the {limit >> 20} MiB limit "
                            f"(MAX_CHUNK_BYTES; a decompression bomb?)")
    out: Buffer
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
                raise Malformed(f"it inflates beyond its declared {size} bytes")
    else:
        import lz4.frame

        dec, whole, got = lz4.frame.LZ4FrameDecompressor(), bytearray(size), 0
        piece = dec.decompress(data, max_length=min(size + 1, _LZ4_STEP))
        while True:
            if got + len(piece) > size:
                raise Malformed(f"it inflates beyond its declared {size} bytes")
            whole[got : got + len(piece)] = piece
            got += len(piece)
            if dec.eof or dec.needs_input or not piece:
                break
            piece = dec.decompress(b"", max_length=min(size - got + 1, _LZ4_STEP))
        out = memoryview(whole)[:got]
    if len(out) != size:
        raise Malformed(f"it inflates to {len(out)} bytes, not the declared {size}")
    return out


def _raw_string(buf: memoryview, pos: int) -> tuple[bytes, int]:
    """The bytes of a length-prefixed string at ``pos`` of ``buf`` (one record) and where it ends;
    :class:`Malformed` when the length runs past the record."""
    if pos + 4 > len(buf):
        raise Malformed("string length cut short")
    end: int = pos + 4 + _U32(buf, pos)[0]
    if end > len(buf):
        raise Malformed(f"string of {end - pos - 4} bytes runs past its record")
    return bytes(buf[pos + 4 : end]), end


def _string(buf: memoryview, pos: int) -> tuple[str, int]:
    """A length-prefixed UTF-8 string at ``pos`` of ``buf`` (one record): ``(text, end)``; :class:`Malformed`
    when the length runs past the record or the bytes are not UTF-8."""
    raw, end = _raw_string(buf, pos)
    try:
        return raw.decode("utf-8"), end
    except UnicodeDecodeError as exc:
        raise Malformed("string is not UTF-8") from exc


def bag_file(path: StrPath) -> Path:
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
            files: list[str] = list(info["relative_file_paths"])
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


def mcap_bytes(path: StrPath) -> bytes:
    """The whole MCAP file of the bag at ``path`` (see :func:`bag_file`); ``BagError`` when it cannot be
    read or does not start with the MCAP magic bytes."""
    file = bag_file(path)  # a bag directory reads its one .mcap file
    try:
        raw = file.read_bytes()
    except OSError as exc:
        raise BagError(f"cannot read bag {file}: {exc.strerror}") from exc
    if not raw.startswith(_MAGIC):
        raise BagError(f"{file} is not an MCAP file (bad magic bytes)")
    return raw


def count_warnings(counts: Mapping[str | None, int], what: str) -> list[str]:
    """One warning per topic of ``counts`` (topic or None -> number): ``what`` formatted with ``n`` (the
    number) and ``where`` (``on <topic>``, or ``on an unknown channel`` for None)."""
    out = []
    for topic in sorted(counts, key=str):
        where = f"on {topic}" if topic is not None else "on an unknown channel"
        out.append(what.format(n=counts[topic], where=where))
    return out


def scan(raw: bytes, on_messages: OnMessages, schemas: Schemas | None = None, channels: Channels | None = None,
         malformed: dict[str | None, int] | None = None) -> tuple[Schemas, Channels, list[str]]:
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
    warnings: list[str] = []
    bad_tables = [0]

    def hand_on(buf: memoryview, runs: _Runs) -> None:
        """Give the message records of ``runs`` to on_messages; count those too short for a header."""
        starts, lens = np.concatenate([r[0] for r in runs]), np.concatenate([r[1] for r in runs])
        short = lens < HEADER_LEN
        if short.any():
            for start, length in zip(starts[short].tolist(), lens[short].tolist()):
                topic = channels.get(_U16(buf, start)[0], (None,))[0] if length >= 2 else None
                malformed[topic] = malformed.get(topic, 0) + 1
            starts, lens = starts[~short], lens[~short]
        if starts.size:
            on_messages(buf, starts, lens)

    def walk(data: Buffer, base: int, in_chunk: bool) -> None:
        buf = memoryview(data)
        pos, n = 0, len(buf)
        runs: _Runs = []  # message records: bulk runs and single ones, in file order
        singles: list[int] = []
        single_len: list[int] = []
        pending = 0  # records in runs
        previous: int | None = None
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
                    runs.append((body + (9 + length) * np.arange(count, dtype=np.int64),
                                 np.full(count, length, dtype=np.int64)))
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
                except Malformed:
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

    def read_chunk(rec: memoryview, at: int) -> None:
        try:
            _start, _end, size, crc = _CHUNK_HEAD.unpack_from(rec, 0)
            raw_compression, p = _raw_string(rec, 28)
            compression = raw_compression.decode("utf-8", "replace")  # not UTF-8: an unknown compression
            if p + 8 > len(rec):
                raise Malformed("chunk header cut short")
            data_len = _U64(rec, p)[0]
            if data_len > len(rec) - p - 8:
                raise Malformed(f"its {data_len} compressed bytes run past the chunk")
            inner = _inflate(compression, rec[p + 8 : p + 8 + data_len], size)
            if crc and zlib.crc32(inner) != crc:
                raise Malformed("CRC mismatch")
        except _ChunkSkipped as exc:
            warnings.append(f"chunk at byte {at} {exc}: skipped, its messages are lost, the rest is read")
            return
        except Exception as exc:  # noqa: BLE001 - any decoding failure means a corrupt chunk
            warnings.append(f"corrupt chunk at byte {at} ({exc}); its messages are lost, the rest is read")
            return
        walk(inner, at, in_chunk=True)

    walk(memoryview(raw)[8:], 8, in_chunk=False)
    if bad_tables[0]:
        warnings.append(f"{bad_tables[0]} malformed or contradicting schema/channel records ignored")
    return schemas, channels, warnings


def _equal_message_run(buf: memoryview, pos: int, length: int, max_run: int = 1 << 14) -> int:
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
    return int(count if ok.all() else max(1, int(np.argmin(ok))))


def summary_tables(raw: bytes, schemas: Schemas, channels: Channels) -> None:
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


def _scan_records(buf: memoryview, schemas: Schemas, channels: Channels) -> None:
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
            except Malformed:
                pass
        pos = body + length


def _table_record(op: int, rec: memoryview, schemas: Schemas, channels: Channels) -> None:
    """Register a Schema (op 3: id -> (name, data)) or Channel (op 4: id -> (topic, schema id)) record
    whose body is ``rec``. Raises :class:`Malformed` for one whose fields run past it, or that
    contradicts an earlier record of the same id (the first one is kept)."""
    if op == 3:
        if len(rec) < 2:
            raise Malformed("schema record cut short")
        sid = _U16(rec, 0)[0]
        name, p = _string(rec, 2)
        _encoding, p = _string(rec, p)
        if p + 4 > len(rec) or _U32(rec, p)[0] > len(rec) - p - 4:
            raise Malformed("schema data runs past its record")
        schema = (name, bytes(rec[p + 4 : p + 4 + _U32(rec, p)[0]]))
        if sid == 0:
            raise Malformed("schema id 0 is reserved")
        _register(schemas, sid, schema)
    else:
        if len(rec) < 4:
            raise Malformed("channel record cut short")
        cid, sid = struct.unpack_from("<HH", rec, 0)
        topic, p = _string(rec, 4)
        _string(rec, p)  # message encoding
        _register(channels, cid, (topic, sid))


def _register(table: dict[int, _Entry], key: int, entry: _Entry) -> None:
    """``table[key] = entry`` unless ``key`` is known; :class:`Malformed` when it is known as something else."""
    known = table.get(key)
    if known is None:
        table[key] = entry
    elif known != entry:
        raise Malformed(f"record contradicts the earlier definition of id {key}")


def copy_messages(path: StrPath, writer: MessageSink) -> list[str]:
    """Copy every readable message of ``path`` into ``writer`` (a :class:`~polyforce_ros.bags.BagWriter`),
    in file order.

    Tolerates truncation, corrupt and oversized chunks like :func:`~polyforce_ros.bags.read_bag`;
    returns its warnings. Messages are copied as they are (their CDR is not
    decoded); records too short to be a message are skipped and counted.
    """
    raw = mcap_bytes(path)
    schemas: Schemas = {}
    channels: Channels = {}
    summary_tables(raw, schemas, channels)
    orphans = [0]
    malformed: dict[str | None, int] = {}

    def copy(buf: Buffer, starts: npt.NDArray[np.int64], lens: npt.NDArray[np.int64]) -> None:
        mv = memoryview(buf)
        for start, length in zip(starts.tolist(), lens.tolist()):
            cid = _U16(mv, start)[0]
            if cid not in channels or channels[cid][1] not in schemas:
                orphans[0] += 1  # its channel was defined in a lost part of the file
                continue
            log_time = _U64(mv, start + 6)[0]
            topic, sid = channels[cid]
            name, schema_data = schemas[sid]
            writer.write_serialized(topic, name, bytes(mv[start + HEADER_LEN : start + length]), log_time,
                                    schema_data=schema_data)

    try:
        warnings = scan(raw, copy, schemas, channels, malformed)[2]
    except BagError:
        raise
    except GARBAGE_ERRORS as exc:
        raise BagError(f"{path}: unreadable bag data ({type(exc).__name__}: {exc})") from exc
    warnings += count_warnings(malformed, "{n} malformed messages {where} skipped")
    if orphans[0]:
        warnings.append(f"{orphans[0]} messages skipped: their channel definition was lost with the damaged part")
    return warnings
