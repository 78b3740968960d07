"""Reading the topic contract of an MCAP bag into numpy arrays: :func:`read_bag`.

Reading does not build one Python object per message: :func:`~polyforce_ros.bags.storage.scan`
hands on the Message records of each buffer (the file, then each chunk) in
bulk, and for each topic the messages whose CDR layout is identical (same
frame_id, joint names and array sizes: the normal case) are decoded together
as numpy arrays (:func:`~polyforce_ros.bags.serde.decode_group`). Messages of
other layouts are decoded one by one with the same layout rules, so nothing
is dropped for being unusual; a message whose CDR does not fit its bytes is
skipped and counted per topic, also on the bulk paths (each message is checked
to have the layout the vectorised decoding assumes). Decoded chunks are kept
as columns only, never as bytes.
"""
from __future__ import annotations

from collections.abc import Collection, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from ..contract import CONTRACT, JOINT_STATE, TEMPERATURE_MSG, WRENCH_STAMPED
from .errors import BagError, Malformed
from .schema import VALUE_FIELDS
from .serde import Buffer, decode_group, decode_one, gather, message_layout
from .storage import (
    GARBAGE_ERRORS, HEADER_LEN, Channels, Schemas, StrPath, count_warnings, mcap_bytes, scan,
    summary_tables,
)

__all__ = ["BagData", "TopicData", "read_bag"]


@dataclass
class TopicData:
    """One topic's messages as arrays, in log-time order.

    ``stamp_ns``: header stamps (ns, int64; log time for header-less types);
    ``log_time_ns``: when the recorder got each message (ns, int64); ``fields``:
    decoded values (float64; ``position`` for JointState, ``force_x`` ...
    ``torque_z`` for WrenchStamped, ``temperature``/``variance``, ``data`` for
    Float64).
    """

    topic: str
    type_name: str
    log_time_ns: npt.NDArray[np.int64]
    stamp_ns: npt.NDArray[np.int64]
    fields: dict[str, npt.NDArray[np.float64]]

    def __len__(self) -> int:
        return int(self.log_time_ns.size)

    @property
    def t_s(self) -> npt.NDArray[np.float64]:
        """Header stamps in seconds (float64)."""
        return self.stamp_ns.astype(np.float64) * 1e-9


@dataclass
class BagData:
    """What :func:`read_bag` read: ``topics`` (topic -> :class:`TopicData`), ``types`` (every topic in the
    bag -> its message type) and ``warnings`` (what damage lost, one line per kind and place)."""

    topics: dict[str, TopicData] = field(default_factory=dict)
    types: dict[str, str] = field(default_factory=dict)  # every topic in the bag -> type
    warnings: list[str] = field(default_factory=list)

    def __getitem__(self, topic: str) -> TopicData:
        return self.topics[topic]


def read_bag(path: StrPath, topics: Collection[str] | None = None, expected_types: Mapping[str, str] | None = None,
             optional: Collection[str] = ()) -> BagData:
    """Read topics of an MCAP bag into arrays.

    topics: iterable of topic names to decode (default: every topic of a known
    type). A requested topic that is absent raises :class:`BagError` listing
    what the bag holds. optional: topics decoded too when the bag holds them.
    expected_types: ``{topic: type}`` to enforce (default: the bag contract
    for contract topics).

    Damage loses only what it touches, each kind reported once in ``warnings``:
    a truncated file, a corrupt chunk (bad CRC, undecodable, inflating to other
    than its declared size), a chunk over :data:`~polyforce_ros.bags.MAX_CHUNK_BYTES` or of an
    unknown compression; messages whose CDR does not fit their bytes are
    skipped and counted per topic, as are messages on undefined channels.
    Whatever else malformed bytes could raise becomes a :class:`BagError`.
    """
    raw = mcap_bytes(path)
    try:
        return _read_bag(path, raw, topics, expected_types, optional)
    except BagError:
        raise
    except GARBAGE_ERRORS as exc:
        raise BagError(f"{path}: unreadable bag data ({type(exc).__name__}: {exc})") from exc


def _read_bag(path: StrPath, raw: bytes, topics: Collection[str] | None, expected_types: Mapping[str, str] | None,
              optional: Collection[str]) -> BagData:
    expected = dict(CONTRACT)
    expected.update(expected_types or {})
    wanted_names = None if topics is None else set(topics) | set(optional)
    decoded: dict[int, list[_Piece]] = {}  # channel id -> pieces decoded chunk by chunk, so no decompressed chunk is kept
    failed: dict[int, BagError] = {}  # channel id -> BagError of a type we cannot decode
    malformed: dict[str | None, int] = {}  # topic -> messages skipped
    no_position: dict[str | None, int] = {}  # topic -> messages without a position
    undefined = [0]

    def collect(buf: Buffer, starts: npt.NDArray[np.int64], lens: npt.NDArray[np.int64]) -> None:
        arr = np.frombuffer(buf, dtype=np.uint8)
        cids = gather(arr, starts, "<u2")
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
            if type_name not in VALUE_FIELDS:
                failed[cid] = BagError(f"no decoder for message type {type_name}")
                continue
            sel = cids == cid
            piece, n_bad, n_empty = _decode_piece(type_name, buf, starts[sel], lens[sel])
            decoded.setdefault(cid, []).append(piece)
            if n_bad:
                malformed[topic] = malformed.get(topic, 0) + n_bad
            if n_empty:
                no_position[topic] = no_position.get(topic, 0) + n_empty

    schemas: Schemas = {}
    channels: Channels = {}
    summary_tables(raw, schemas, channels)  # so a lost first chunk does not orphan the rest
    warnings = scan(raw, collect, schemas, channels, malformed)[2]
    warnings += count_warnings(malformed, "{n} malformed messages {where} skipped")
    warnings += count_warnings(no_position, "{n} messages {where} carry no position: read as NaN")
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


@dataclass
class _Piece:
    """The messages of one topic in one buffer (a chunk), decoded."""

    log_ns: npt.NDArray[np.int64]
    stamp_ns: npt.NDArray[np.int64]
    fields: dict[str, npt.NDArray[np.float64]]


#: A group of equal-size messages smaller than this is decoded message by message (bulk set-up costs more).
_BULK_MIN = 16
#: Bulk layouts tried per group of equal-size messages; what is left then goes message by message, so
#: garbage of many layouts costs linear time, not one vectorised pass per layout.
_BULK_ROUNDS = 8


def _decode_piece(type_name: str, buf: Buffer, starts: npt.NDArray[np.int64],
                  lens: npt.NDArray[np.int64]) -> tuple[_Piece, int, int]:
    """Decode the message records at ``starts`` (record bodies, lengths ``lens``) of ``buf``, all of ``type_name``.

    Returns ``(piece, malformed, without_position)``. Messages of equal size are decoded in bulk with
    the layout of the first well-formed one; each is checked to really have it (:func:`decode_group`),
    and those that do not are decoded one by one, their lengths validated (:func:`message_layout`): a
    message whose CDR does not fit its bytes is left out and counted in ``malformed``. A JointState
    without positions reads as NaN (counted in ``without_position``).
    """
    arr = np.frombuffer(buf, dtype=np.uint8)
    log = gather(arr, starts + 6, "<u8").astype(np.int64)
    data_starts = starts + HEADER_LEN
    sizes = lens - HEADER_LEN
    names = VALUE_FIELDS[type_name]
    kept: list[npt.NDArray[np.int64]] = []
    secs: list[npt.NDArray[np.signedinteger[Any]]] = []  # int32 from the bulk path, int64 message by message
    nsecs: list[npt.NDArray[np.integer[Any]]] = []  # uint32 from the bulk path, int64 message by message
    values: dict[str, list[npt.NDArray[np.float64]]] = {name: [] for name in names}
    odd: list[npt.NDArray[np.int64]] = []  # index arrays of messages to decode one by one
    n_empty = 0
    groups: list[npt.NDArray[np.int64]]
    if sizes[0] == sizes.min() == sizes.max():  # the normal case: one layout per topic
        groups = [np.arange(sizes.size, dtype=np.int64)]
    else:
        order = np.argsort(sizes, kind="stable")
        groups = np.split(order, np.flatnonzero(np.diff(sizes[order])) + 1)
    for idx in groups:
        for _ in range(_BULK_ROUNDS):
            if idx.size < _BULK_MIN:
                break
            i0 = int(idx[0])
            try:
                fields, lengths = message_layout(type_name, buf, int(data_starts[i0]), int(sizes[i0]))
            except Malformed:  # the first is malformed (counted by the one-by-one pass): the next leads
                odd.append(idx[:1])
                idx = idx[1:]
                continue
            columns, same = decode_group(buf, data_starts[idx], fields, lengths)
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
        one_idx: list[int] = []
        one_sec: list[float] = []
        one_nsec: list[float] = []
        one_vals: dict[str, list[float]] = {name: [] for name in names}
        for i in np.concatenate(odd).tolist():
            try:
                got = decode_one(type_name, buf, int(data_starts[i]), int(sizes[i]))
            except Malformed:
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
    stamps: npt.NDArray[np.int64]
    if type_name in (JOINT_STATE, WRENCH_STAMPED, TEMPERATURE_MSG):
        stamps = (np.concatenate(secs).astype(np.int64) * 1_000_000_000 + np.concatenate(nsecs).astype(np.int64)
                  if secs else np.zeros(0, dtype=np.int64))
    else:
        stamps = log[ok]
    fields_out = {name: np.concatenate(v) if v else np.zeros(0) for name, v in values.items()}
    return _Piece(log[ok], stamps, fields_out), n_bad, n_empty


def _join_pieces(topic: str, type_name: str, pieces: list[_Piece]) -> TopicData:
    """One topic's pieces as one :class:`TopicData`, in log-time order."""
    if not pieces:  # none read (all lost or malformed): empty columns, every field present
        empty = np.zeros(0, dtype=np.int64)
        return TopicData(topic, type_name, empty, empty,
                         {name: np.zeros(0) for name in VALUE_FIELDS.get(type_name, ())})
    log = np.concatenate([p.log_ns for p in pieces])
    order = np.argsort(log, kind="stable")
    fields = {name: np.concatenate([p.fields[name] for p in pieces])[order] for name in pieces[0].fields}
    return TopicData(topic, type_name, log[order], np.concatenate([p.stamp_ns for p in pieces])[order], fields)
