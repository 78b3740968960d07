"""Decoding of contract-type CDR messages into numbers, one message or many of one layout at once.

The encoding side is :mod:`polyforce_ros.bags.cdr`; :func:`serialize_template`
gives its zero-stamp, zero-value message of a series.

A message is plain little-endian CDR (encapsulation ``00 01 00 00``, then the
payload, each primitive aligned to its size relative to the payload start).
:func:`message_layout` walks the length words of one message (frame_id, joint
names, array counts), each checked against the bytes that remain, and gives
the byte offsets of its values: ``fields`` maps a value name (``sec``,
``nanosec`` and the :data:`~polyforce_ros.bags.schema.VALUE_FIELDS` of the
type) to ``(offset, dtype)`` in the payload, ``lengths`` lists the payload
offsets of the uint32 words that determine the layout (equal words in equal
places give an identical layout). :func:`decode_group` reads a column per
field from many equal-size messages through strided views and says which of
them really share the first one's layout; :func:`decode_one` decodes one
message with :mod:`struct`. A message whose length words do not fit its bytes
raises :class:`~polyforce_ros.bags.errors.Malformed`.
"""
from __future__ import annotations

import struct
from typing import Any, Literal, TypeAlias

import numpy as np
import numpy.typing as npt

from ..contract import FLOAT64, FRAME_ID, JOINT_NAME, JOINT_STATE, TEMPERATURE_MSG, WRENCH_STAMPED
from . import cdr
from .errors import BagError, Malformed
from .schema import VALUE_FIELDS

__all__ = [
    "CDR_LE", "Buffer", "FieldDtype", "FieldMap", "decode_group", "decode_one", "gather", "message_layout",
    "serialize_template",
]

#: Bytes a message is read from: a whole file, a decompressed chunk or a view of either.
Buffer: TypeAlias = bytes | bytearray | memoryview
#: numpy dtype of a decoded value: header stamp seconds, header stamp nanoseconds, a float64 value.
FieldDtype: TypeAlias = Literal["<i4", "<u4", "<f8"]
#: Value name -> ``(payload offset in bytes, dtype)``.
FieldMap: TypeAlias = dict[str, tuple[int, FieldDtype]]

_U16 = struct.Struct("<H").unpack_from
_U32 = struct.Struct("<I").unpack_from
#: Encapsulation header bytes ``00 01`` (plain CDR, little endian) read as one little-endian uint16.
CDR_LE = 0x0100
_STRUCT_OF: dict[FieldDtype, str] = {"<i4": "<i", "<u4": "<I", "<f8": "<d"}


def _align(pos: int, n: int) -> int:
    return (pos + n - 1) & ~(n - 1)


def _layout(type_name: str, payload: memoryview) -> tuple[FieldMap, list[int]]:
    """Offsets (in the CDR payload after the 4-byte encapsulation header) of one message.

    Returns ``(fields, length_fields)``: ``fields`` maps value names to
    ``(offset, numpy dtype)``; ``length_fields`` lists offsets of the uint32
    length/count words that determine the layout (equal words in equal
    places => identical layout). Every length and count is checked against
    the bytes that remain before it is used, so a message that passes fits
    its payload; one that does not raises :class:`Malformed`.
    """
    n = len(payload)

    def u32(pos: int) -> int:
        if pos + 4 > n:
            raise Malformed(f"{type_name} message of {n} bytes cut short at byte {pos}")
        word: int = _U32(payload, pos)[0]
        return word

    fields: FieldMap = {}
    lengths: list[int] = []
    pos = 0
    if type_name in (JOINT_STATE, WRENCH_STAMPED, TEMPERATURE_MSG):
        fields["sec"] = (0, "<i4")
        fields["nanosec"] = (4, "<u4")
        lengths.append(8)
        size = u32(8)
        if size > n - 12:
            raise Malformed(f"frame_id of {size} bytes runs past the {n}-byte {type_name} message")
        pos = 12 + size  # frame_id string incl. NUL
    if type_name == JOINT_STATE:
        pos = _align(pos, 4)
        lengths.append(pos)
        n_names = u32(pos)
        pos += 4
        if n_names > (n - pos) // 4:  # a name takes at least its 4-byte length word
            raise Malformed(f"{n_names} joint names cannot fit the {n}-byte {type_name} message")
        for _ in range(n_names):
            pos = _align(pos, 4)
            lengths.append(pos)
            size = u32(pos)
            pos += 4
            if size > n - pos:
                raise Malformed(f"joint name of {size} bytes runs past the {n}-byte {type_name} message")
            pos += size
        for arr in ("position", "velocity", "effort"):
            pos = _align(pos, 4)
            lengths.append(pos)
            count = u32(pos)
            pos += 4
            if count:
                pos = _align(pos, 8)
                if count > (n - pos) // 8:
                    raise Malformed(f"{arr} of {count} values runs past the {n}-byte {type_name} message")
                if arr == "position":
                    fields["position"] = (pos, "<f8")
                pos += 8 * count
    elif type_name == WRENCH_STAMPED:
        pos = _align(pos, 8)
        for i, name in enumerate(VALUE_FIELDS[WRENCH_STAMPED]):
            fields[name] = (pos + 8 * i, "<f8")
        pos += 48
    elif type_name == TEMPERATURE_MSG:
        pos = _align(pos, 8)
        fields["temperature"] = (pos, "<f8")
        fields["variance"] = (pos + 8, "<f8")
        pos += 16
    elif type_name == FLOAT64:
        fields["data"] = (0, "<f8")
        pos = 8
    else:
        raise BagError(f"no decoder for message type {type_name}")
    if pos > n:
        raise Malformed(f"{type_name} message shorter than its layout ({n} < {pos} bytes)")
    return fields, lengths


def message_layout(type_name: str, buf: Buffer, start: int, size: int) -> tuple[FieldMap, list[int]]:
    """The layout of the CDR message ``buf[start: start + size]`` (encapsulation header included).

    Returns ``(fields, lengths)``: ``fields`` maps each value the message
    holds to ``(payload offset, dtype)``; ``lengths`` lists the payload
    offsets of the uint32 length and count words that determine the layout.
    Raises :class:`Malformed` when the encapsulation is not little-endian CDR
    or a length word does not fit the message, and
    :class:`~polyforce_ros.bags.BagError` for a type without a decoder.
    """
    if size < 4 or _U16(buf, start)[0] != CDR_LE:
        raise Malformed(f"{type_name} message is not little-endian CDR")
    return _layout(type_name, memoryview(buf)[start + 4 : start + size])


def gather(arr: npt.NDArray[np.uint8], offsets: npt.NDArray[np.int64], dtype: str) -> npt.NDArray[Any]:
    """Values of ``dtype`` at the (unaligned) byte ``offsets`` of the uint8 array ``arr``.

    One byte column at a time: no ``(n, width)`` index array, so the temporaries stay at
    about 2 int64 per message however many messages a chunk holds.
    """
    width = np.dtype(dtype).itemsize
    out = np.empty((offsets.size, width), dtype=np.uint8)
    for k in range(width):
        np.take(arr, offsets + k if k else offsets, out=out[:, k])
    return out.view(dtype).ravel()


def decode_group(buf: Buffer, starts: npt.NDArray[np.int64], fields: FieldMap,
                 lengths: list[int]) -> tuple[dict[str, npt.NDArray[Any]], npt.NDArray[np.bool_]]:
    """Decode equal-size CDR messages ``buf[starts[i]:]`` assumed to share one layout (``fields``, ``lengths``
    of the first, which must be valid: see :func:`message_layout`).

    Returns ``(columns, same)``: ``columns`` maps each field to its values (dtype of the field), ``same[i]``
    says message i really has that layout (its encapsulation and every length word equal the first's); only
    those entries of the columns are meaningful. Every message in the group has the first one's size, so a
    message of the same layout fits its bytes like the first.
    """
    arr = np.frombuffer(buf, dtype=np.uint8)
    steps = np.diff(starts)
    stride = int(steps[0]) if steps.size and steps[0] > 0 and np.all(steps == steps[0]) else None

    def column(off: int, dtype: str) -> npt.NDArray[Any]:
        """Field at byte ``off`` of every message's CDR body (after the 4-byte encapsulation)."""
        if stride is not None or starts.size == 1:  # evenly spaced records: a strided view, no index arrays
            view: npt.NDArray[Any] = np.ndarray((starts.size,), dtype=dtype, buffer=buf,
                                                offset=int(starts[0]) + 4 + off, strides=(stride or 1,))
            return view.copy()
        return gather(arr, starts + (4 + off), dtype)

    # Same layout check: the encapsulation, and every length word equal to the first message's.
    same: npt.NDArray[np.bool_] = column(-4, "<u2") == CDR_LE
    for off in lengths:
        words = column(off, "<u4")
        same &= words == words[0]
    return {name: column(off, dtype) for name, (off, dtype) in fields.items()}, same


def decode_one(type_name: str, buf: Buffer, start: int, size: int) -> dict[str, float]:
    """Values of the one CDR message ``buf[start: start + size]`` by field name.

    A field the message lacks is absent (a JointState without positions);
    ``sec`` and ``nanosec`` are ints. Raises :class:`Malformed`.
    """
    fields, _ = message_layout(type_name, buf, start, size)
    return {name: struct.unpack_from(_STRUCT_OF[dtype], buf, start + 4 + off)[0]
            for name, (off, dtype) in fields.items()}


def serialize_template(type_name: str, frame_id: str = FRAME_ID, joint_name: str = JOINT_NAME) -> bytes:
    """CDR bytes of one message of a contract type with zero stamp and value (every byte set, see :mod:`.cdr`).

    Raises :class:`~polyforce_ros.bags.BagError` for a type without an encoder or a NUL in a name.
    """
    try:
        return cdr.series_layout(type_name, frame_id, joint_name).template
    except ValueError as exc:
        raise BagError(str(exc)) from exc
