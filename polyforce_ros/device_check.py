"""Bring-up checklist of a serial ADC device (``polyforce check-device``), ROS-free.

With the sensor unloaded, :func:`read_device` asks the device for its info and status
messages and reads ``samples`` sample frames from the first valid one on;
:func:`evaluate` judges what it read, one :class:`CheckResult` per check:

========================  =====================================================================
check                     passes when
========================  =====================================================================
info                      an info message arrived, of the link protocol this host reads (1)
sensor serial             the info names the sensor (not empty, not ``unset``)
status                    a status message arrived; no watchdog reset since power-on and no ADC
                          reconfiguration (DRDY fell silent)
link                      the frames arrived with no CRC error, no lost, duplicate or late frame
                          and no sequence jump
rate                      the conversion rate measured on the device clock is within
                          ``rate_tolerance`` (5 %) of the rate the info announces
counts in range           every sample lies inside the ADC's code range, -2^(bits-1) .. 2^(bits-1)-1
not railed                no sample sits on either end code (a saturated or open input)
zero offset               the mean at zero load is within ``max_offset_fraction`` (25 %) of full
                          scale (a 2 mV/V bridge spans 26 % at full load; a larger zero points at
                          a miswired or damaged bridge and leaves too little range for the load)
noise                     the rms about the samples' straight-line trend, input-referred, is at
                          most ``max_noise_uv`` (5 uV; the ADS1220's own noise at 1000 SPS and gain
                          128 is of the order of 1-2 uV rms, so more is pickup: shielding, grounding,
                          mains)
========================  =====================================================================

Given expectations (the driver's parameters) add two checks: ``volts_per_count`` equals the
device's (relative 1e-6) and ``expected rate`` is within ``rate_tolerance`` of the announced rate.
The noise needs the scale in volts: the info's ``volts_per_count``, else the one given.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .serial_protocol import (REQUEST_INFO, REQUEST_STATUS, DeviceInfo, DeviceStatus, Frame, FrameParser,
                              MessageDemux)

__all__ = ["Limits", "CheckResult", "DeviceReading", "read_device", "evaluate", "format_report", "DeviceOpenError"]

#: The link protocol versions this host reads.
SUPPORTED_PROTOCOLS = (1,)
#: Sensor serials that say the serial was not set when flashing.
UNSET_SERIALS = ("", "unset")


@dataclass(frozen=True)
class Limits:
    """The limits the checks judge by (defaults: the documented bring-up limits)."""

    max_noise_uv: float = 5.0          #: input-referred rms noise about the trend, uV
    max_offset_fraction: float = 0.25  #: |mean counts| at zero load, as a fraction of full scale
    rate_tolerance: float = 0.05       #: measured against announced rate, relative (the ADC oscillator's tolerance)


@dataclass(frozen=True)
class CheckResult:
    """One check: its name, whether it passed, and what was measured."""

    name: str
    passed: bool
    detail: str


class DeviceOpenError(OSError):
    """The port could not be opened (no such device, no permission)."""


@dataclass
class DeviceReading:
    """What was read from the device: its latest info and status, and the sample frames.

    Bytes go in through :meth:`feed`; the frames are kept from the first valid one on, and the
    link counters (CRC errors, lost, duplicate and late frames, sequence jumps) are counted
    from there, so a frame cut by opening the port mid-stream counts nothing.
    """

    info: Optional[DeviceInfo] = None
    status: Optional[DeviceStatus] = None
    frames: list[Frame] = field(default_factory=list)
    parser: FrameParser = field(default_factory=FrameParser)
    demux: MessageDemux = field(default_factory=MessageDemux)
    _baseline: Optional[dict[str, int]] = None

    def feed(self, data: bytes) -> None:
        """Takes the messages out of ``data`` and parses the rest into frames."""
        rest, messages = self.demux.feed(data)
        for message in messages:
            if isinstance(message, DeviceInfo):
                self.info = message
            elif isinstance(message, DeviceStatus):
                self.status = message
        if self._baseline is None:  # byte by byte up to the first valid frame: the counters start after it
            for i in range(len(rest)):
                first = self.parser.feed(rest[i:i + 1])
                if first:
                    self._baseline = self._counters()
                    self.frames += first
                    rest = rest[i + 1:]
                    break
            else:
                return
        self.frames += self.parser.feed(rest)

    def _counters(self) -> dict[str, int]:
        p = self.parser
        return {"crc_errors": p.crc_errors, "lost_frames": p.lost_frames, "duplicates": p.duplicates,
                "reordered": p.reordered, "seq_jumps": p.seq_jumps}

    def link_errors(self) -> dict[str, int]:
        """The link counters since the first valid frame."""
        base = self._baseline or self._counters()
        return {k: v - base[k] for k, v in self._counters().items()}


def read_device(port: str, samples: int, baud: int = 921600, timeout_s: float = 10.0) -> DeviceReading:
    """Opens ``port``, asks for info and status, and reads until ``samples`` frames, the info and a status
    have arrived or ``timeout_s`` has passed. Raises :class:`DeviceOpenError` when the port cannot be opened."""
    import serial

    try:
        link = serial.Serial(port, baud, timeout=0.05)
    except (serial.SerialException, OSError, ValueError) as exc:
        raise DeviceOpenError(f"cannot open {port}: {exc}") from exc
    reading = DeviceReading()
    try:
        link.reset_input_buffer()  # what waited in the host's buffer is not this check's
        deadline = time.monotonic() + timeout_s
        asked = None
        while time.monotonic() < deadline:
            if (reading.info is None or reading.status is None) and (asked is None or time.monotonic() - asked > 1.0):
                link.write(REQUEST_INFO + REQUEST_STATUS)  # asked again each second until both arrived
                asked = time.monotonic()
            reading.feed(link.read(max(1, link.in_waiting)))
            if len(reading.frames) >= samples and reading.info is not None and reading.status is not None:
                break
    finally:
        link.close()
    del reading.frames[samples:]
    return reading


def _check(name: str, passed: bool, detail: str) -> CheckResult:
    return CheckResult(name, bool(passed), detail)


def evaluate(reading: DeviceReading, samples: int, limits: Optional[Limits] = None,
             volts_per_count: Optional[float] = None, expected_rate_hz: Optional[float] = None) -> list[CheckResult]:
    """The checklist (module docstring) for ``reading``, judged by ``limits`` (default: :class:`Limits`);
    ``volts_per_count`` and ``expected_rate_hz``, the driver's parameters, add a check each when given."""
    limits = limits if limits is not None else Limits()
    info, status, frames = reading.info, reading.status, reading.frames
    out = []
    if info is None:
        out.append(_check("info", False, "no info message (firmware without messages, or not a polyforce device)"))
    else:
        out.append(_check(
            "info", info.protocol in SUPPORTED_PROTOCOLS and 8 <= info.adc_bits <= 32 and info.rate_hz > 0
            and info.gain > 0 and info.vref_uv > 0,
            f"protocol {info.protocol}, firmware {info.firmware}, board {info.board}, ADC {info.adc} "
            f"({info.adc_bits} bits), {info.rate_hz} Hz, gain {info.gain}, vref {info.vref_uv * 1e-6:g} V, "
            f"volts_per_count {info.volts_per_count!r}"))
        out.append(_check("sensor serial", info.sensor_serial.strip().lower() not in UNSET_SERIALS,
                          f"{info.sensor_serial!r}" + (" (set it when flashing)" if info.sensor_serial.strip().lower()
                                                       in UNSET_SERIALS else "")))
    if status is None:
        out.append(_check("status", False, "no status message"))
    else:
        out.append(_check("status", status.watchdog_resets == 0 and status.adc_reconfigs == 0,
                          f"reset reason {status.reset_reason_name}, {status.watchdog_resets} watchdog resets, "
                          f"{status.adc_reconfigs} ADC reconfigurations, {status.overflows} overflows, "
                          f"up {status.uptime_s} s"))
    errors = reading.link_errors()
    out.append(_check("link", len(frames) >= samples and not any(errors.values()),
                      f"{len(frames)} of {samples} frames; " + ", ".join(f"{v} {k.replace('_', ' ')}"
                                                                          for k, v in errors.items())))
    vpc = info.volts_per_count if info is not None else volts_per_count
    if volts_per_count is not None and info is not None:
        out.append(_check("volts_per_count", abs(info.volts_per_count - volts_per_count) <= 1e-6 * abs(volts_per_count),
                          f"device {info.volts_per_count!r}, expected {volts_per_count!r}"))
    if expected_rate_hz is not None and info is not None:
        out.append(_check("expected rate", abs(info.rate_hz - expected_rate_hz) <= limits.rate_tolerance * expected_rate_hz,
                          f"device announces {info.rate_hz} Hz, expected {expected_rate_hz:g} Hz"))
    if len(frames) < 2:
        for name in ("rate", "counts in range", "not railed", "zero offset", "noise"):
            out.append(_check(name, False, f"{len(frames)} frames: nothing to judge"))
        return out
    out.append(_rate_check(frames, info, limits))
    counts = np.array([f.counts for f in frames], dtype=np.int64)
    bits = info.adc_bits if info is not None else 24
    low, high = -(2 ** (bits - 1)), 2 ** (bits - 1) - 1
    span = f"{counts.min()} .. {counts.max()} counts"
    out.append(_check("counts in range", counts.min() >= low and counts.max() <= high,
                      f"{span}, ADC range {low} .. {high}"))
    railed = int(np.count_nonzero((counts <= low) | (counts >= high)))
    out.append(_check("not railed", railed == 0, f"{railed} samples on an end code"))
    mean = float(counts.mean())
    fraction = abs(mean) / 2 ** (bits - 1)
    volts = f" ({mean * vpc * 1e3:.4g} mV)" if vpc else ""
    out.append(_check("zero offset", fraction <= limits.max_offset_fraction,
                      f"mean {mean:.1f} counts{volts}, {100 * fraction:.2f} % of full scale "
                      f"(limit {100 * limits.max_offset_fraction:g} %)"))
    index = np.arange(counts.size, dtype=float)
    residual = counts - np.polyval(np.polyfit(index, counts.astype(float), 1), index)
    rms_counts = float(np.sqrt(np.mean(residual ** 2)))
    if not vpc:
        out.append(_check("noise", False, f"{rms_counts:.2f} counts rms; no volts_per_count (no info message): "
                                          "give --volts-per-count"))
    else:
        rms_uv, pp_uv = rms_counts * vpc * 1e6, float(np.ptp(residual)) * vpc * 1e6
        out.append(_check("noise", rms_uv <= limits.max_noise_uv,
                          f"{rms_uv:.3g} uV rms ({rms_counts:.2f} counts), {pp_uv:.3g} uV peak to peak, "
                          f"over {counts.size} samples (limit {limits.max_noise_uv:g} uV rms)"))
    return out


def _rate_check(frames: list[Frame], info: Optional[DeviceInfo], limits: Limits) -> CheckResult:
    """Conversions per second of device time (sequence steps over the device clock, both modulo their wrap)."""
    steps = sum((b.seq - a.seq) & 0xFFFF for a, b in zip(frames, frames[1:]))
    elapsed_us = sum((b.t_us - a.t_us) & 0xFFFFFFFF for a, b in zip(frames, frames[1:]))
    if elapsed_us == 0:
        return _check("rate", False, "the device clock did not advance")
    rate = steps * 1e6 / elapsed_us
    if info is None:
        return _check("rate", False, f"{rate:.1f} Hz measured on the device clock; no announced rate (no info)")
    return _check("rate", abs(rate - info.rate_hz) <= limits.rate_tolerance * info.rate_hz,
                  f"{rate:.1f} Hz measured on the device clock, {info.rate_hz} Hz announced "
                  f"(tolerance {100 * limits.rate_tolerance:g} %)")


def format_report(results: list[CheckResult]) -> str:
    """One line per check (PASS or FAIL, name, what was measured) and a verdict."""
    width = max(len(r.name) for r in results)
    lines = [f"{'PASS' if r.passed else 'FAIL'}  {r.name:<{width}}  {r.detail}" for r in results]
    failed = [r.name for r in results if not r.passed]
    lines.append(f"FAIL: {len(failed)} of {len(results)} checks failed ({', '.join(failed)})" if failed
                 else f"PASS: all {len(results)} checks")
    return "\n".join(lines)
