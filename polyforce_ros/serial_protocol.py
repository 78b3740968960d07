"""Serial frame format between the bridge ADC microcontroller and driver_node.

One frame per ADC sample, 14 bytes, little-endian:

    offset  size  field
    0       2     sync 0xA5 0x5A
    2       2     seq        uint16, +1 per sample (wraps); a jump means lost frames
    4       4     t_us       uint32, device clock at acquisition in microseconds (wraps)
    8       4     counts     int32, ADC reading
    12      2     crc        uint16, CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF) of bytes 2..11

The parser resynchronises on the sync word, so a frame cut by a reconnect or a
corrupted byte costs only that frame; frames failing the CRC are counted and
dropped. Sequence numbers are compared modulo 2**16: a frame ahead of the last
one by ``d`` (1 <= d < 2**15) follows ``d - 1`` lost frames; a frame behind it
is a late (reordered) frame when it fills one of those gaps, a duplicate when
its number was received already, and a sequence jump (a device that restarted
its count) when it lies further back than ``REORDER_WINDOW``. Volts = counts *
volts_per_count + volts_offset (driver parameters).
"""
from __future__ import annotations

import enum
import struct
from collections import deque
from dataclasses import dataclass
from typing import Callable, Final, Literal, Optional, Sequence, Union

from .stamps import REANCHOR_AFTER_S, STAMP_TOLERANCE_S, ConsistentRun

__all__ = ["SYNC", "FRAME_SIZE", "crc16_ccitt", "encode_frame", "Frame", "FrameParser", "DeviceClock", "REORDER_WINDOW"]

SYNC = b"\xa5\x5a"
FRAME_SIZE = 14
#: A frame at most this many sequence numbers behind the newest one is late or a duplicate; further back, a jump.
REORDER_WINDOW = 256
_BODY = struct.Struct("<HIi")


def crc16_ccitt(data: bytes, crc: int = 0xFFFF) -> int:
    """CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection, no final XOR) of ``data``."""
    for byte in data:
        crc ^= byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


def encode_frame(seq: int, t_us: int, counts: int) -> bytes:
    """One 14-byte frame: sync, ``seq`` (u16, wraps), device time ``t_us`` (u32 us, wraps), ADC ``counts`` (i32), CRC."""
    body = _BODY.pack(seq & 0xFFFF, t_us & 0xFFFFFFFF, int(counts))
    return SYNC + body + struct.pack("<H", crc16_ccitt(body))


@dataclass
class Frame:
    """One decoded frame: sequence number, device time (us) and ADC counts."""
    seq: int
    t_us: int
    counts: int


class FrameParser:
    """Incremental parser: ``feed(bytes)`` returns the complete, valid frames found, in sequence order.

    Attributes
    ----------
    crc_errors : int
        Frames (or sync words) failing the CRC.
    frames : int
        Frames with a valid CRC, every kind below included.
    lost_frames : int
        Sequence numbers skipped and not received late (net of ``reordered``).
    duplicates : int
        Frames whose sequence number was received already (dropped).
    reordered : int
        Late frames, received after a newer one (dropped: their stamps would go backwards).
    seq_jumps : int
        Frames further behind the newest one than ``REORDER_WINDOW``, or exactly 2**15 away
        (a device that restarted its count): the sequence restarts at them, nothing is counted lost.
    """

    def __init__(self) -> None:
        self.buffer = bytearray()
        self.crc_errors = 0
        self.lost_frames = 0
        self.duplicates = 0
        self.reordered = 0
        self.seq_jumps = 0
        self.frames = 0
        self._last_seq: Optional[int] = None
        self._last_abs = 0      # the newest sequence number, unwrapped
        self._missing: deque[int] = deque()  # unwrapped numbers of the frames counted lost within REORDER_WINDOW, ascending

    def reset(self) -> None:
        """Forget partial data and the sequence (after a reconnect)."""
        self.buffer.clear()
        self._last_seq = None
        self._missing.clear()

    def _accept(self, seq: int) -> bool:
        """Count ``seq`` against the sequence so far; True if the frame is new and in order."""
        if self._last_seq is None:
            self._last_seq, self._last_abs = seq, 0
            return True
        ahead = (seq - self._last_seq) & 0xFFFF
        if 0 < ahead < 0x8000:
            self.lost_frames += ahead - 1
            first_missing = self._last_abs + 1
            self._last_seq, self._last_abs = seq, self._last_abs + ahead
            missing = self._missing
            missing.extend(range(max(first_missing, self._last_abs - REORDER_WINDOW), self._last_abs))
            while missing and missing[0] < self._last_abs - REORDER_WINDOW:
                missing.popleft()
            return True
        behind = (0x10000 - ahead) & 0xFFFF
        if behind == 0:
            self.duplicates += 1
            return False
        if behind <= REORDER_WINDOW:
            number = self._last_abs - behind
            if number in self._missing:
                self._missing.remove(number)
                self.lost_frames -= 1
                self.reordered += 1
            else:
                self.duplicates += 1
            return False
        self.seq_jumps += 1
        self._last_seq = seq
        self._missing.clear()
        return True

    def feed(self, data: bytes) -> list[Frame]:
        """Append received bytes; return the complete frames with a valid CRC, in order.

        Bytes before a sync word and frames with a bad CRC are skipped (counted in
        ``crc_errors``); sequence gaps are counted in ``lost_frames``; duplicates and
        late frames are counted and skipped (see the class). A partial frame stays
        buffered for the next call.
        """
        self.buffer += data
        out: list[Frame] = []
        buf = self.buffer
        while True:
            start = buf.find(SYNC)
            if start < 0:
                del buf[: max(0, len(buf) - 1)]  # keep a possible first sync byte
                break
            if len(buf) - start < FRAME_SIZE:
                del buf[:start]
                break
            frame = bytes(buf[start : start + FRAME_SIZE])
            body = frame[2:12]
            if struct.unpack("<H", frame[12:])[0] != crc16_ccitt(body):
                self.crc_errors += 1
                del buf[: start + 1]  # resync past this sync word
                continue
            seq, t_us, counts = _BODY.unpack(body)
            self.frames += 1
            if self._accept(seq):
                out.append(Frame(seq, t_us, counts))
            del buf[: start + FRAME_SIZE]
        return out


class _Anchor(enum.Enum):
    """What :meth:`DeviceClock._map` returns when a run of implausible frames heals: anchor afresh."""

    REANCHOR = enum.auto()


class DeviceClock:
    """Maps the device's wrapping microsecond clock onto host time (ns).

    The offset host - device is the minimum of (arrival - device time) over a
    sliding pair of windows: the least-delayed frames bound the true offset,
    and the window lets it follow the drift between the two crystals.

    The frames of one read (:meth:`stamp_batch`) all arrive at the same instant:
    every one of them updates the offset first (the last, least delayed, bounds
    it best), then all are stamped with that offset, so they keep their
    device-time spacing. When a newer, less delayed read lowers the offset, the
    offset in use follows at once unless that would put a stamp less than half
    its device-time step after the previous stamp: then it follows at that
    rate. Stamps of one anchor thus increase as the device times do, and never
    come before the frame's acquisition (the offset in use is never below the
    estimate).

    The stamp rules of the compensation runtime apply here too: a frame whose
    delay (arrival - device time) departs from the current offset by more than
    ``tolerance_s`` is implausible (a corrupt clock field, a device reset) and
    gets no stamp (None, counted in ``implausible``); it never moves the wrap
    count or the offset. Implausible frames that agree among themselves
    (increasing device time, steady delay) for ``reanchor_after_s`` of arrival
    time re-anchor the mapping (counted in ``reanchored``): a device that
    really restarted its clock is followed.
    """

    _REANCHOR: Final = _Anchor.REANCHOR

    def __init__(self, window_s: float = 10.0, tolerance_s: float = STAMP_TOLERANCE_S,
                 reanchor_after_s: float = REANCHOR_AFTER_S) -> None:
        self.window_ns = int(window_s * 1e9)
        self.tolerance_ns = int(tolerance_s * 1e9)
        self.reanchor_after_ns = int(reanchor_after_s * 1e9)
        self._run = ConsistentRun(self.tolerance_ns, self.reanchor_after_ns)  # implausible frames that agree
        self.implausible = 0
        self.reanchored = 0
        self.reset()

    def reset(self) -> None:
        """Forget the wraps, the offset windows and any re-anchor run: the next frame anchors afresh."""
        self._last_us: Optional[int] = None
        self._wraps = 0
        self._window_start: Optional[int] = None
        self._min_now: Optional[int] = None
        self._min_prev: Optional[int] = None
        self._run.reset()
        self._stamped: Optional[tuple[int, int]] = None  # (device ns, stamp ns) of the last frame stamped under this anchor

    def _offset(self) -> int:
        """The offset host - device in use (ns); set once a frame has been mapped under this anchor."""
        assert self._min_now is not None, "no frame mapped under this anchor yet"
        return self._min_now if self._min_prev is None else min(self._min_now, self._min_prev)

    def stamp_ns(self, t_us: int, arrival_ns: int) -> Optional[int]:
        """Host-time stamp (ns) of a frame with device time ``t_us`` read alone, or None when implausible."""
        return self.stamp_batch((t_us,), arrival_ns)[0]

    def stamp_batch(self, t_us_seq: Sequence[int], arrival_ns: int) -> list[Optional[int]]:
        """Host-time stamps (ns) of the frames of one read, received at ``arrival_ns``, in their order.

        Parameters
        ----------
        t_us_seq : sequence of int
            Device times of the frames (us, wrapping at 2**32), in the order the device sent them.
        arrival_ns : int
            Host time of the read, ns.

        Returns
        -------
        list of int or None
            One stamp (ns) per frame, None for an implausible one.
        """
        stamps: list[Optional[int]] = [None] * len(t_us_seq)
        pending: list[tuple[int, int]] = []  # (position, device ns) of the frames mapped under the current anchor
        for i, t_us in enumerate(t_us_seq):
            device_ns = self._map(t_us, arrival_ns)
            if device_ns is self._REANCHOR:
                self._stamp(pending, stamps)  # the frames before it belong to the old anchor
                pending = []
                self.reanchored += 1
                self.reset()
                device_ns = self._map(t_us, arrival_ns)  # anchors afresh: never _REANCHOR
            if device_ns is not None and device_ns is not self._REANCHOR:
                pending.append((i, device_ns))
        self._stamp(pending, stamps)
        return stamps

    def _map(self, t_us: int, arrival_ns: int) -> Union[int, None, _Anchor]:
        """Device ns of a plausible frame (the offset windows updated), None, or _REANCHOR when a run heals."""
        wraps = self._wraps
        if self._last_us is not None and t_us < self._last_us and self._last_us - t_us > 1 << 31:
            wraps += 1
        device_ns = (wraps * (1 << 32) + t_us) * 1000
        delay = arrival_ns - device_ns
        if self._min_now is not None and abs(delay - self._offset()) > self.tolerance_ns:
            self.implausible += 1
            return self._REANCHOR if self._heals(t_us, arrival_ns) else None
        self._run.reset()
        self._wraps, self._last_us = wraps, t_us
        if self._window_start is None or arrival_ns - self._window_start > self.window_ns:
            self._min_prev, self._min_now, self._window_start = self._min_now, delay, arrival_ns
        else:
            self._min_now = delay if self._min_now is None else min(self._min_now, delay)
        return device_ns

    def _stamp(self, pending: Sequence[tuple[int, int]], stamps: list[Optional[int]]) -> None:
        """Stamp the ``pending`` frames with the current offset, held so stamps advance at least half as fast."""
        if not pending:
            return
        offset = self._offset()
        if self._stamped is not None:
            last_device, last_stamp = self._stamped
            step = pending[0][1] - last_device
            offset = max(offset, last_stamp - last_device - step // 2)
        for i, device_ns in pending:
            stamps[i] = device_ns + offset
        self._stamped = (pending[-1][1], pending[-1][1] + offset)

    def _heals(self, t_us: int, arrival_ns: int) -> bool:
        return self._run.add(t_us, arrival_ns - t_us * 1000, arrival_ns)


# ------------------------------------------------------------------------------------ messages
# The device's identity, health and ADC temperature share the link with the sample frames
# (firmware/polyforce_fw.h, "messages"):
#
#     sync 0xA5 0xC3, then the body stuffed (every 0xA5 byte is followed by 0x00):
#     type u8, version u8, len u8, len ^ 0xFF u8, payload (len bytes, little-endian fields),
#     crc u16 = CRC-16/CCITT-FALSE of type .. payload
#
# A message never contains the sample sync 0xA5 0x5A, never starts with 0x5A and never ends
# with 0xA5, so FrameParser alone skips messages as line noise without counting a CRC error.
# MessageDemux takes them out of the byte stream before FrameParser sees it.

MSG_SYNC = b"\xa5\xc3"
MSG_PAYLOAD_MAX = 64
MSG_INFO, MSG_STATUS, MSG_TEMPERATURE = 0x01, 0x02, 0x03
#: One ASCII byte from the host asks the device for an info / a status message.
REQUEST_INFO, REQUEST_STATUS = b"I", b"S"
#: Reset reasons of the status message, by code.
RESET_REASONS = {0: "unknown", 1: "power_on", 2: "external", 3: "brown_out", 4: "watchdog", 5: "software"}
#: mains_filter of the info message: the ADS1220's 50/60 Hz FIR setting, by code.
MAINS_FILTERS = {0: "off", 1: "50+60 Hz", 2: "50 Hz", 3: "60 Hz"}
_MSG_MAX_STUFFED = 2 * (4 + MSG_PAYLOAD_MAX + 2)
_INFO = struct.Struct("<BBBBIIHBB8s16s16s")
_STATUS = struct.Struct("<IBxHIII")
_TEMPERATURE = struct.Struct("<Ih")


def encode_message(msg_type: int, payload: bytes, version: int = 1) -> bytes:
    """One message: sync 0xA5 0xC3, then type, version, length, its complement, ``payload`` and the CRC, stuffed."""
    payload = bytes(payload)
    if len(payload) > MSG_PAYLOAD_MAX:
        raise ValueError(f"payload of {len(payload)} bytes, at most {MSG_PAYLOAD_MAX}")
    body = bytes((msg_type & 0xFF, version & 0xFF, len(payload), len(payload) ^ 0xFF)) + payload
    body += struct.pack("<H", crc16_ccitt(body))
    return MSG_SYNC + body.replace(b"\xa5", b"\xa5\x00")


def _text(raw: bytes) -> str:
    """A NUL-padded field as text (Latin-1: one character per byte, both ways)."""
    return raw.split(b"\0", 1)[0].decode("latin-1")


@dataclass(frozen=True)
class DeviceInfo:
    """Who the device is (info message, version 1): sent at start and on request (``REQUEST_INFO``)."""
    rate_hz: int          #: conversions per second
    vref_uv: int          #: ADC reference (the bridge excitation when ratiometric), uV
    gain: int             #: PGA gain
    adc_bits: int         #: ADC resolution (two's complement)
    mains_filter: int     #: code of MAINS_FILTERS
    adc: str
    board: str
    sensor_serial: str    #: serial number of the sensor on this device
    protocol: int = 1     #: link protocol version
    firmware: str = "1.1.0"  #: firmware version, major.minor.patch

    @property
    def volts_per_count(self) -> float:
        """vref / (gain * 2**(adc_bits - 1)): the driver's ``volts_per_count`` for this device."""
        return self.vref_uv * 1e-6 / (self.gain * 2.0 ** (self.adc_bits - 1))

    def payload(self) -> bytes:
        major, minor, patch = (int(x) for x in self.firmware.split("."))
        return _INFO.pack(self.protocol, major, minor, patch, self.rate_hz, self.vref_uv, self.gain, self.adc_bits,
                          self.mains_filter, self.adc.encode("latin-1"), self.board.encode("latin-1"),
                          self.sensor_serial.encode("latin-1"))

    @classmethod
    def from_payload(cls, payload: bytes) -> "DeviceInfo":
        (protocol, major, minor, patch, rate, vref, gain, bits, mains, adc, board,
         serial) = _INFO.unpack_from(payload)  # a later version only appends fields
        return cls(rate, vref, gain, bits, mains, _text(adc), _text(board), _text(serial), protocol,
                   f"{major}.{minor}.{patch}")

    def values(self) -> dict[str, Union[int, float, str]]:
        """Key/values for diagnostics."""
        return {"device_protocol": self.protocol, "device_firmware": self.firmware, "device_board": self.board,
                "device_adc": self.adc, "device_rate_hz": self.rate_hz, "device_gain": self.gain,
                "device_vref_v": self.vref_uv * 1e-6, "device_volts_per_count": repr(self.volts_per_count),
                "device_mains_filter": MAINS_FILTERS.get(self.mains_filter, str(self.mains_filter)),
                "sensor_serial": self.sensor_serial}


@dataclass(frozen=True)
class DeviceStatus:
    """The device's health (status message, version 1): sent periodically and on request (``REQUEST_STATUS``)."""
    t_us: int             #: device time when sent
    reset_reason: int     #: code of RESET_REASONS: why the device last started
    watchdog_resets: int  #: watchdog resets since power-on
    overflows: int        #: conversions refused by the device's full ring since start
    adc_reconfigs: int    #: times the ADC was configured again because its DRDY fell silent
    uptime_s: int         #: seconds since start

    @property
    def reset_reason_name(self) -> str:
        return RESET_REASONS.get(self.reset_reason, f"code {self.reset_reason}")

    def payload(self) -> bytes:
        return _STATUS.pack(self.t_us, self.reset_reason, self.watchdog_resets, self.overflows, self.adc_reconfigs,
                            self.uptime_s)

    @classmethod
    def from_payload(cls, payload: bytes) -> "DeviceStatus":
        return cls(*_STATUS.unpack_from(payload))

    def values(self) -> dict[str, Union[int, str]]:
        """Key/values for diagnostics."""
        return {"device_reset_reason": self.reset_reason_name, "device_watchdog_resets": self.watchdog_resets,
                "device_overflows": self.overflows, "device_adc_reconfigs": self.adc_reconfigs,
                "device_uptime_s": self.uptime_s}


@dataclass(frozen=True)
class DeviceTemperature:
    """The ADC's own temperature sensor (temperature message, version 1), in 1/32 degC steps."""
    t_us: int      #: device time of the reading
    temp_q5: int   #: temperature in 1/32 degC

    @property
    def celsius(self) -> float:
        return self.temp_q5 / 32.0

    def payload(self) -> bytes:
        return _TEMPERATURE.pack(self.t_us, self.temp_q5)

    @classmethod
    def from_payload(cls, payload: bytes) -> "DeviceTemperature":
        return cls(*_TEMPERATURE.unpack_from(payload))


@dataclass(frozen=True)
class RawMessage:
    """A message of a type (or a payload too short for the layout) this host does not know: kept, not decoded."""
    msg_type: int
    version: int
    payload: bytes


#: A decoded message: the dataclass of a known type, else the raw message.
Message = Union[DeviceInfo, DeviceStatus, DeviceTemperature, RawMessage]

# message type -> (decoder of its payload, the payload's least size in bytes)
_DECODERS: dict[int, tuple[Callable[[bytes], Message], int]] = {
    MSG_INFO: (DeviceInfo.from_payload, _INFO.size), MSG_STATUS: (DeviceStatus.from_payload, _STATUS.size),
    MSG_TEMPERATURE: (DeviceTemperature.from_payload, _TEMPERATURE.size)}


def encode_info(info: DeviceInfo) -> bytes:
    """The info message of ``info``."""
    return encode_message(MSG_INFO, info.payload())


def encode_status(status: DeviceStatus) -> bytes:
    """The status message of ``status``."""
    return encode_message(MSG_STATUS, status.payload())


def encode_temperature(temperature: DeviceTemperature) -> bytes:
    """The temperature message of ``temperature``."""
    return encode_message(MSG_TEMPERATURE, temperature.payload())


def decode_message(msg_type: int, version: int, payload: bytes) -> Message:
    """The dataclass of a known type (a longer payload of a later version is read by its known prefix), else RawMessage."""
    decoder = _DECODERS.get(msg_type)
    if decoder is None or version < 1 or len(payload) < decoder[1]:
        return RawMessage(msg_type, version, bytes(payload))
    return decoder[0](payload)


class MessageDemux:
    """Takes the messages out of the link's byte stream; the rest goes on to :class:`FrameParser`.

    ``feed(data)`` returns ``(sample_bytes, messages)``: the bytes that are not part of a valid
    message, in order, and the decoded messages. A candidate (sync 0xA5 0xC3 at any position, also
    inside a sample frame) becomes a message only with correct stuffing, a consistent length and
    its CRC; anything else passes through unchanged, so no sample frame is ever taken. Bytes from a
    candidate on are held back until it is complete or refuted (at most one message's length).
    A 0xA5 that ends the data passes on at once (a sample frame may end with it) and is kept
    for a sync cut between two reads; when it does start a message, the frame parser is left
    with that single stray byte, which it skips without counting an error.
    """

    def __init__(self) -> None:
        self.buffer = bytearray()
        self.messages = 0  #: valid messages taken out
        self._passed = 0   # bytes at the start of the buffer that were passed on already (0 or 1)

    def reset(self) -> None:
        """Forget partial data (after a reconnect)."""
        self.buffer.clear()
        self._passed = 0

    def _parse(self, start: int) -> Union[tuple[int, Message], None, Literal["more"]]:
        """At a candidate: (end, message) when valid, None when refuted, "more" when incomplete."""
        buf, i, body, need = self.buffer, start + 2, bytearray(), 4
        while len(body) < need:
            if i >= len(buf):
                return "more"
            byte = buf[i]
            i += 1
            if byte == 0xA5:
                if i >= len(buf):
                    return "more"
                if buf[i] != 0x00:
                    return None  # unstuffed 0xA5: not a message
                i += 1
            body.append(byte)
            if len(body) == 4:
                if body[2] ^ body[3] != 0xFF or body[2] > MSG_PAYLOAD_MAX:
                    return None
                need = 4 + body[2] + 2
        if struct.unpack_from("<H", body, len(body) - 2)[0] != crc16_ccitt(bytes(body[:-2])):
            return None
        return i, decode_message(body[0], body[1], bytes(body[4:-2]))

    def feed(self, data: bytes) -> tuple[bytes, list[Message]]:
        """Append received bytes; return ``(bytes for FrameParser, messages found)``."""
        self.buffer += data
        buf, passed = self.buffer, bytearray()
        found: list[Message] = []
        pos, search = self._passed, 0  # bytes before pos are passed on; candidates are sought from search
        while True:
            start = buf.find(MSG_SYNC, search)
            if start < 0:
                passed += buf[pos:]
                cut = buf.endswith(b"\xa5")  # a sync may be cut in two: keep its first byte, passed on
                del buf[: len(buf) - 1 if cut else len(buf)]
                self._passed = 1 if cut else 0
                break
            result = self._parse(start)
            if isinstance(result, str):  # "more"
                passed += buf[pos:start]
                del buf[:start]
                self._passed = max(0, pos - start)
                break
            if result is None:
                passed += buf[pos:start + 1]  # not a message: its first byte belongs to the samples
                pos = search = max(pos, start + 1)
                continue
            end, message = result
            passed += buf[pos:start]
            found.append(message)
            self.messages += 1
            pos = search = end
        return bytes(passed), found


__all__ += ["MSG_SYNC", "MSG_PAYLOAD_MAX", "MSG_INFO", "MSG_STATUS", "MSG_TEMPERATURE", "REQUEST_INFO",
            "REQUEST_STATUS", "RESET_REASONS", "MAINS_FILTERS", "encode_message", "encode_info", "encode_status",
            "encode_temperature", "decode_message", "DeviceInfo", "DeviceStatus", "DeviceTemperature", "RawMessage",
            "Message", "MessageDemux"]
