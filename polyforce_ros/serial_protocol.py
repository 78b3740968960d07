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

import struct
from collections import deque
from dataclasses import dataclass

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

    def __init__(self):
        self.buffer = bytearray()
        self.crc_errors = 0
        self.lost_frames = 0
        self.duplicates = 0
        self.reordered = 0
        self.seq_jumps = 0
        self.frames = 0
        self._last_seq = None
        self._last_abs = 0      # the newest sequence number, unwrapped
        self._missing = deque()  # unwrapped numbers of the frames counted lost within REORDER_WINDOW, ascending

    def reset(self):
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

    def feed(self, data: bytes):
        """Append received bytes; return the complete frames with a valid CRC, in order.

        Bytes before a sync word and frames with a bad CRC are skipped (counted in
        ``crc_errors``); sequence gaps are counted in ``lost_frames``; duplicates and
        late frames are counted and skipped (see the class). A partial frame stays
        buffered for the next call.
        """
        self.buffer += data
        out = []
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

    _REANCHOR = object()

    def __init__(self, window_s: float = 10.0, tolerance_s: float = 1.0, reanchor_after_s: float = 0.2):
        self.window_ns = int(window_s * 1e9)
        self.tolerance_ns = int(tolerance_s * 1e9)
        self.reanchor_after_ns = int(reanchor_after_s * 1e9)
        self.implausible = 0
        self.reanchored = 0
        self.reset()

    def reset(self):
        """Forget the wraps, the offset windows and any re-anchor run: the next frame anchors afresh."""
        self._last_us = None
        self._wraps = 0
        self._window_start = None
        self._min_now = None
        self._min_prev = None
        self._run = None  # [first arrival, last t_us, delay of a raw t_us] of implausible frames
        self._stamped = None  # (device ns, stamp ns) of the last frame stamped under this anchor

    def _offset(self):
        return self._min_now if self._min_prev is None else min(self._min_now, self._min_prev)

    def stamp_ns(self, t_us: int, arrival_ns: int):
        """Host-time stamp (ns) of a frame with device time ``t_us`` read alone, or None when implausible."""
        return self.stamp_batch((t_us,), arrival_ns)[0]

    def stamp_batch(self, t_us_seq, arrival_ns: int) -> list:
        """Host-time stamps (ns) of the frames of one read, received at ``arrival_ns``, in their order.

        Parameters
        ----------
        t_us_seq : sequence of int
            Device times of the frames (us, wrapping at 2**32), in the order the device sent them.
        arrival_ns : int
            Host time of the read, ns.

        Returns
        -------
        list
            One stamp (ns) per frame, None for an implausible one.
        """
        stamps: list = [None] * len(t_us_seq)
        pending: list = []  # (position, device ns) of the frames mapped under the current anchor
        for i, t_us in enumerate(t_us_seq):
            device_ns = self._map(t_us, arrival_ns)
            if device_ns is self._REANCHOR:
                self._stamp(pending, stamps)  # the frames before it belong to the old anchor
                pending = []
                self.reanchored += 1
                self.reset()
                device_ns = self._map(t_us, arrival_ns)
            if device_ns is not None:
                pending.append((i, device_ns))
        self._stamp(pending, stamps)
        return stamps

    def _map(self, t_us, arrival_ns):
        """Device ns of a plausible frame (the offset windows updated), None, or _REANCHOR when a run heals."""
        wraps = self._wraps
        if self._last_us is not None and t_us < self._last_us and self._last_us - t_us > 1 << 31:
            wraps += 1
        device_ns = (wraps * (1 << 32) + t_us) * 1000
        delay = arrival_ns - device_ns
        if self._min_now is not None and abs(delay - self._offset()) > self.tolerance_ns:
            self.implausible += 1
            return self._REANCHOR if self._heals(t_us, arrival_ns) else None
        self._run = None
        self._wraps, self._last_us = wraps, t_us
        if self._window_start is None or arrival_ns - self._window_start > self.window_ns:
            self._min_prev, self._min_now, self._window_start = self._min_now, delay, arrival_ns
        else:
            self._min_now = min(self._min_now, delay)
        return device_ns

    def _stamp(self, pending, stamps):
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
        self._stamped = (pending[-1][1], stamps[pending[-1][0]])

    def _heals(self, t_us, arrival_ns) -> bool:
        raw_delay = arrival_ns - t_us * 1000
        run = self._run
        if run is None or t_us <= run[1] or abs(raw_delay - run[2]) > self.tolerance_ns:
            self._run = [arrival_ns, t_us, raw_delay]
            return False
        run[1], run[2] = t_us, raw_delay
        return arrival_ns - run[0] >= self.reanchor_after_ns
