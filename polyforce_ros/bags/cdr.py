"""CDR encoding of the contract message types, owning every byte (pure Python + numpy, no rclpy).

The bytes follow ROS 2's CDR (OMG XCDR1, plain little-endian, as Fast DDS and
rosbag2 use it): a 4-byte encapsulation header ``00 01 00 00`` and then the
payload, in which each primitive is aligned to its own size (at most 8)
relative to the start of the payload. Padding bytes are always zero and a
message ends with its last field (no trailing bytes), so equal content gives
equal bytes: exactly what ``rosbags``' ``serialize_cdr`` produces, and what
every CDR reader (rclpy, rosbags' strict decoder, mcap_ros2) accepts.

Types: ``sensor_msgs/msg/JointState``, ``geometry_msgs/msg/WrenchStamped``,
``sensor_msgs/msg/Temperature`` and ``std_msgs/msg/Float64``.

* :func:`encode` (or ``encode_joint_state`` ... ``encode_float64``): one message
  from plain Python values.
* :func:`series_layout` / :meth:`SeriesLayout.encode`: many messages of one
  fixed layout (same frame_id and joint name) that differ only in header stamp
  and one scalar, encoded in bulk as an ``(n, size)`` uint8 array.
* :func:`encode_message`: a ROS message object of one of these types, read by attribute.

Decoding these bytes back into numbers is :mod:`polyforce_ros.bags.serde`.

Header stamps are given as integer nanoseconds and split like
``builtin_interfaces/Time``: ``sec = floor(ns / 1e9)`` (int32),
``nanosec = ns - sec * 1e9`` (uint32, 0 .. 999 999 999); stamps outside the
int32 second range raise ``ValueError`` rather than wrapping.
"""
from __future__ import annotations

import struct
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from ..contract import FLOAT64, JOINT_STATE, SCALAR_FIELD, TEMPERATURE_MSG, WRENCH_STAMPED

__all__ = [
    "ENCAPSULATION", "STAMP_MIN_NS", "STAMP_MAX_NS", "SeriesLayout", "encode", "encode_float64", "encode_message",
    "encode_joint_state", "encode_series", "encode_temperature", "encode_wrench_stamped", "series_layout", "split_stamp",
    "split_stamps",
]

#: CDR_LE encapsulation (representation id 0x0001, options 0).
ENCAPSULATION = b"\x00\x01\x00\x00"

_NS = 1_000_000_000
#: Smallest and largest stamp (ns) a builtin_interfaces/Time can hold.
STAMP_MIN_NS = -(2**31) * _NS
STAMP_MAX_NS = (2**31 - 1) * _NS + _NS - 1

_I32, _U32, _F64 = struct.Struct("<i"), struct.Struct("<I"), struct.Struct("<d")


class _Writer:
    """Append-only CDR payload builder; alignment is relative to the payload start."""

    def __init__(self) -> None:
        self.buf = bytearray()
        self.marks: dict[str, int] = {}  # name -> payload offset of a field (see SeriesLayout)

    def align(self, n: int) -> None:
        self.buf += b"\x00" * (-len(self.buf) % n)

    def mark(self, name: str | None) -> None:
        if name is not None:
            self.marks[name] = len(self.buf)

    def i32(self, v: int, mark: str | None = None) -> None:
        self.align(4)
        self.mark(mark)
        self.buf += _I32.pack(v)

    def u32(self, v: int, mark: str | None = None) -> None:
        self.align(4)
        self.mark(mark)
        self.buf += _U32.pack(v)

    def f64(self, v: float, mark: str | None = None) -> None:
        self.align(8)
        self.mark(mark)
        self.buf += _F64.pack(v)

    def string(self, s: str | bytes) -> None:
        data = _utf8(s)
        self.u32(len(data) + 1)
        self.buf += data + b"\x00"

    def strings(self, seq: Iterable[str | bytes]) -> None:
        items = list(seq)
        self.u32(len(items))
        for s in items:
            self.string(s)

    def f64s(self, seq: npt.ArrayLike, mark: str | None = None) -> None:
        arr = np.asarray(seq, dtype="<f8").reshape(-1)
        self.u32(arr.size)
        if arr.size:  # an empty sequence is just its count: no alignment for absent elements
            self.align(8)
            self.mark(mark)
            self.buf += arr.tobytes()

    def header(self, stamp_ns: int, frame_id: str | bytes) -> None:
        sec, nanosec = split_stamp(stamp_ns)
        self.i32(sec, "sec")
        self.u32(nanosec, "nanosec")
        self.string(frame_id)

    def message(self) -> bytes:
        return ENCAPSULATION + bytes(self.buf)


def _utf8(s: str | bytes) -> bytes:
    data = s.encode("utf-8") if isinstance(s, str) else bytes(s)
    if b"\x00" in data:
        raise ValueError(f"CDR strings cannot contain NUL characters: {s!r}")
    return data


def split_stamp(stamp_ns: int | np.integer[Any]) -> tuple[int, int]:
    """``(sec, nanosec)`` of a stamp in integer nanoseconds (``ValueError`` outside the Time range)."""
    ns = _int(stamp_ns)
    if not STAMP_MIN_NS <= ns <= STAMP_MAX_NS:
        raise ValueError(f"stamp {ns} ns is outside the builtin_interfaces/Time range")
    return divmod(ns, _NS)


def _int(v: object) -> int:
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)):
        raise TypeError(f"stamps are integer nanoseconds, got {v!r}")
    return int(v)


def _vector(name: str, v: Iterable[float]) -> tuple[float, ...]:
    components = tuple(float(x) for x in v)
    if len(components) != 3:
        raise ValueError(f"{name} needs 3 components, got {len(components)}")
    return components


# ----------------------------------------------------------------------------- one message
def _joint_state(w: _Writer, stamp_ns: int = 0, frame_id: str = "", name: Iterable[str] = (),
                 position: npt.ArrayLike = (), velocity: npt.ArrayLike = (), effort: npt.ArrayLike = ()) -> None:
    w.header(stamp_ns, frame_id)
    w.strings(name)
    w.f64s(position, "position")
    w.f64s(velocity)
    w.f64s(effort)


def _wrench_stamped(w: _Writer, stamp_ns: int = 0, frame_id: str = "", force: Iterable[float] = (0.0, 0.0, 0.0),
                    torque: Iterable[float] = (0.0, 0.0, 0.0)) -> None:
    w.header(stamp_ns, frame_id)
    for axis, v in zip("xyz", _vector("force", force)):
        w.f64(v, f"force_{axis}")
    for axis, v in zip("xyz", _vector("torque", torque)):
        w.f64(v, f"torque_{axis}")


def _temperature(w: _Writer, stamp_ns: int = 0, frame_id: str = "", temperature: float = 0.0,
                 variance: float = 0.0) -> None:
    w.header(stamp_ns, frame_id)
    w.f64(float(temperature), "temperature")
    w.f64(float(variance), "variance")


def _float64(w: _Writer, data: float = 0.0) -> None:
    w.f64(float(data), "data")


_BUILDERS: dict[str, Callable[..., None]] = {
    JOINT_STATE: _joint_state, WRENCH_STAMPED: _wrench_stamped, TEMPERATURE_MSG: _temperature, FLOAT64: _float64,
}


def _build(type_name: str, fields: Mapping[str, object]) -> _Writer:
    try:
        builder = _BUILDERS[type_name]
    except KeyError:
        raise ValueError(f"no CDR encoder for message type {type_name!r}; known: {sorted(_BUILDERS)}") from None
    w = _Writer()
    builder(w, **fields)
    return w


def encode(type_name: str, **fields: object) -> bytes:
    """CDR bytes (encapsulation header included) of one message of ``type_name``.

    Fields (all optional, zero/empty by default): JointState ``stamp_ns``,
    ``frame_id``, ``name``, ``position``, ``velocity``, ``effort``;
    WrenchStamped ``stamp_ns``, ``frame_id``, ``force`` and ``torque`` (3
    floats each); Temperature ``stamp_ns``, ``frame_id``, ``temperature``,
    ``variance``; Float64 ``data``.
    """
    return _build(type_name, fields).message()


def encode_joint_state(stamp_ns: int = 0, frame_id: str = "", name: Iterable[str] = (), position: npt.ArrayLike = (),
                       velocity: npt.ArrayLike = (), effort: npt.ArrayLike = ()) -> bytes:
    """CDR bytes of a sensor_msgs/JointState (stamp in ns, names, positions, velocities, efforts)."""
    return encode(JOINT_STATE, stamp_ns=stamp_ns, frame_id=frame_id, name=name, position=position,
                  velocity=velocity, effort=effort)


def encode_wrench_stamped(stamp_ns: int = 0, frame_id: str = "", force: Iterable[float] = (0.0, 0.0, 0.0),
                          torque: Iterable[float] = (0.0, 0.0, 0.0)) -> bytes:
    """CDR bytes of a geometry_msgs/WrenchStamped (force in N, torque in N m)."""
    return encode(WRENCH_STAMPED, stamp_ns=stamp_ns, frame_id=frame_id, force=force, torque=torque)


def encode_temperature(stamp_ns: int = 0, frame_id: str = "", temperature: float = 0.0, variance: float = 0.0) -> bytes:
    """CDR bytes of a sensor_msgs/Temperature (degC, variance degC^2)."""
    return encode(TEMPERATURE_MSG, stamp_ns=stamp_ns, frame_id=frame_id, temperature=temperature, variance=variance)


def encode_float64(data: float = 0.0) -> bytes:
    """CDR bytes of a std_msgs/Float64."""
    return encode(FLOAT64, data=data)


def encode_message(type_name: str, msg: Any) -> bytes:
    """CDR bytes of a ROS message object of a contract type (read by attribute; no rclpy needed).

    ``ValueError`` for a type without an encoder here.
    """
    if type_name not in _BUILDERS:
        raise ValueError(f"no CDR encoder for message type {type_name!r}; known: {sorted(_BUILDERS)}")
    if type_name == FLOAT64:
        return encode_float64(msg.data)
    stamp_ns = int(msg.header.stamp.sec) * 1_000_000_000 + int(msg.header.stamp.nanosec)
    frame_id = msg.header.frame_id
    if type_name == JOINT_STATE:
        return encode_joint_state(stamp_ns, frame_id, list(msg.name), list(msg.position), list(msg.velocity),
                                  list(msg.effort))
    if type_name == WRENCH_STAMPED:
        f, q = msg.wrench.force, msg.wrench.torque
        return encode_wrench_stamped(stamp_ns, frame_id, (f.x, f.y, f.z), (q.x, q.y, q.z))
    return encode_temperature(stamp_ns, frame_id, msg.temperature, msg.variance)


# ----------------------------------------------------------------------------- series
def _scalar_message(type_name: str, frame_id: str, joint_name: str) -> dict[str, object]:
    if type_name == JOINT_STATE:
        return {"frame_id": frame_id, "name": [joint_name], "position": [0.0]}
    if type_name in (WRENCH_STAMPED, TEMPERATURE_MSG):
        return {"frame_id": frame_id}
    return {}


@dataclass(frozen=True)
class SeriesLayout:
    """The fixed layout of one-scalar messages that differ only in stamp and value.

    ``template``: the whole message (header included) with zero stamp and value;
    ``stamp_offset``: byte offset of ``header.stamp.sec`` in it (``nanosec``
    follows at +4), None for Float64; ``value_offset``: byte offset of the
    scalar (float64).
    """

    type_name: str
    template: bytes
    stamp_offset: int | None
    value_offset: int

    @property
    def size(self) -> int:
        """Bytes of one encoded message (the encapsulation header included)."""
        return len(self.template)

    def encode(self, stamp_ns: npt.ArrayLike, values: npt.ArrayLike) -> npt.NDArray[np.uint8]:
        """An ``(n, size)`` uint8 array whose row i is the CDR message of ``stamp_ns[i]``, ``values[i]``.

        Every byte is set: a zeroed array gets the template's constant bytes
        (lengths, strings; zero padding), then the stamp and value columns are
        written through strided views. ``tobytes()`` gives the n messages back to back.
        """
        column = np.asarray(values, dtype="<f8")
        if column.ndim != 1:
            raise ValueError(f"values must be 1-D, got shape {column.shape}")
        n, size = column.size, self.size
        block = np.zeros((n, size), dtype=np.uint8)
        block[:] = np.frombuffer(self.template, dtype=np.uint8)
        if self.stamp_offset is not None:
            sec, nanosec = split_stamps(stamp_ns)
            if sec.size != n:
                raise ValueError(f"{sec.size} stamps for {n} values")
            self._column(block, self.stamp_offset, "<i4")[:] = sec
            self._column(block, self.stamp_offset + 4, "<u4")[:] = nanosec
        self._column(block, self.value_offset, "<f8")[:] = column  # same dtype: NaN payloads kept bit for bit
        return block

    @staticmethod
    def _column(block: npt.NDArray[np.uint8], offset: int, dtype: str) -> npt.NDArray[Any]:
        n, size = block.shape
        return np.ndarray((n,), dtype=dtype, buffer=block, offset=offset, strides=(size,))


def series_layout(type_name: str, frame_id: str = "", joint_name: str = "") -> SeriesLayout:
    """The :class:`SeriesLayout` of ``type_name`` messages with this frame_id (and joint name, for JointState)."""
    w = _build(type_name, _scalar_message(type_name, frame_id, joint_name))
    head = len(ENCAPSULATION)
    stamp = w.marks.get("sec")
    return SeriesLayout(type_name, w.message(), None if stamp is None else head + stamp,
                        head + w.marks[SCALAR_FIELD[type_name]])


def encode_series(type_name: str, stamp_ns: npt.ArrayLike, values: npt.ArrayLike, frame_id: str = "",
                  joint_name: str = "") -> npt.NDArray[np.uint8]:
    """``series_layout(type_name, frame_id, joint_name).encode(stamp_ns, values)``."""
    return series_layout(type_name, frame_id, joint_name).encode(stamp_ns, values)


def split_stamps(stamp_ns: npt.ArrayLike) -> tuple[npt.NDArray[np.int32], npt.NDArray[np.uint32]]:
    """Vectorised :func:`split_stamp`: ``(sec int32, nanosec uint32)`` arrays of an int64 ns array."""
    stamps = np.asarray(stamp_ns)
    if stamps.ndim != 1:
        raise ValueError(f"stamps must be 1-D, got shape {stamps.shape}")
    if stamps.size and not np.issubdtype(stamps.dtype, np.integer):
        raise TypeError(f"stamps are integer nanoseconds, got dtype {stamps.dtype}")
    if stamps.size and (int(stamps.min()) < STAMP_MIN_NS or int(stamps.max()) > STAMP_MAX_NS):
        raise ValueError("stamps outside the builtin_interfaces/Time range "
                         f"[{STAMP_MIN_NS}, {STAMP_MAX_NS}] ns")
    sec, nanosec = np.divmod(stamps.astype(np.int64), _NS)
    return sec.astype(np.int32), nanosec.astype(np.uint32)
