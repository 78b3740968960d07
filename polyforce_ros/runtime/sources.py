"""The driver's sample sources, ROS-free: what the node publishes, not how.

* :class:`SimulatedSource`: the embedded simulator on the host clock. Given the time
  now, it hands out every sample due since the profile started (stamped on its
  schedule), simulated in blocks with the sensor's state carried across them.
* :class:`SerialSource`: bytes from the ADC link in, stamped volts out (frames parsed
  and checked by :class:`~polyforce_ros.serial_protocol.FrameParser`, device time mapped
  onto host time by :class:`~polyforce_ros.serial_protocol.DeviceClock`, which drops
  implausible device times; every frame of one read gets its own stamp).

``driver_node`` (both variants) owns one of them and only publishes what it returns. Its settings
are declared once, with default, description and range (:func:`~polyforce_ros.settings.setting`), in
:class:`DriverConfig` (every backend), :class:`SimSourceConfig` and :class:`SerialSourceConfig`; the
node declares a parameter of each field and builds its source from them.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional, Protocol

import numpy as np
import numpy.typing as npt

from .. import contract
from ..serial_protocol import DeviceClock, FrameParser
from ..serial_protocol import DeviceInfo, DeviceStatus, DeviceTemperature, MessageDemux
from ..settings import setting

__all__ = ["SimBlock", "SimulatedSource", "SerialSource", "SIM_BLOCK", "MAX_BURST",
           "DriverConfig", "SimSourceConfig", "SerialSourceConfig", "SIM_PROFILES", "RATE_WARN_FRACTION"]

#: Samples simulated ahead per block (1 s at 1 kHz): small enough not to stall a caller.
SIM_BLOCK = 1000
#: At most this many samples are handed out per call (a long stall is caught up gradually).
MAX_BURST = 250
#: Force profiles the simulated source plays: the names ``polyforce_ros.sim.profiles.make_profile`` takes.
SIM_PROFILES = ("creep", "sawtooth", "step", "sine_sweep", "resolution", "needle_insertion", "okamura")
#: Serial backend: WARN when fewer than this fraction of expected_rate_hz frames arrive (covers ADC oscillator tolerance).
RATE_WARN_FRACTION = 0.95


@dataclass(frozen=True)
class DriverConfig:
    """Settings of the driver whatever its backend, each declared once with its description and range
    (:func:`~polyforce_ros.settings.setting`); ``driver_node`` declares a parameter of each."""

    backend: str = setting("sim", "Data source: 'sim' (embedded simulator) or 'serial' (ADC)", read_only=True)
    joint_name: str = setting(contract.JOINT_NAME, "JointState name of the sensor's prismatic joint", read_only=True)
    frame_id: str = setting(contract.FRAME_ID, "Frame of the sensor", read_only=True)
    publish_period_s: float = setting(
        0.002, "Timer period; samples due are published each tick (s)", 0.0005, 0.1, read_only=True)


@dataclass(frozen=True)
class SimSourceConfig:
    """Settings of the simulated source (``backend: sim``): the simulated sensor, its force profile and
    temperature, each declared once with its description and range; ``driver_node`` declares a parameter of
    each, ``polyforce simulate`` and ``polyforce demo`` take their defaults from them."""

    rate_hz: float = setting(1000.0, "Sample rate of the simulator (Hz)", 1.0, 20000.0, read_only=True)
    profile: str = setting("needle_insertion", f"Simulated force profile: {', '.join(SIM_PROFILES)}", read_only=True)
    loop: bool = setting(True, "Restart the profile when it ends (else stop publishing)", read_only=True)
    truth_model_file: str = setting(
        "", "Model YAML of the simulated sensor (may add nonlinear_gain, sensor_lag, thermal_drift, offset_drift "
        "elements); empty = shipped paper model", read_only=True)
    noise_std_v: float = setting(1e-3, "Simulated bridge noise, 1 sigma (V)", 0.0, 1.0, read_only=True)
    adc_bits: int = setting(16, "Simulated ADC resolution (bits, 0 = none)", 0, 32, read_only=True)
    offset_v: float = setting(0.05, "Simulated bridge output at zero force (V)", -5.0, 5.0, read_only=True)
    temperature_c: float = setting(24.0, "Simulated mean temperature (degC)", -40.0, 125.0, read_only=True)
    temperature_amplitude_c: float = setting(
        0.0, "Amplitude of a sinusoidal temperature swing (degC)", 0.0, 50.0, read_only=True)
    temperature_period_s: float = setting(600.0, "Period of the temperature swing (s)", 1.0, 1e6, read_only=True)
    seed: int = setting(0, "Noise and profile seed", 0, 2**31 - 1, read_only=True)
    wait_for_subscribers: int = setting(
        0, "Sim: start the profile once this many subscribers of bridge_voltage are matched (0 = at once), so a "
        "recorder started first records it from its first sample (DDS matches late joiners only after seconds)",
        0, 100, read_only=True)

    def temperature_at(self, t_s: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """Simulated temperature (degC) at the times ``t_s`` (s): the mean plus the optional sinusoidal swing."""
        amplitude = self.temperature_amplitude_c
        swing = amplitude * np.sin(2 * np.pi * np.asarray(t_s) / self.temperature_period_s) if amplitude else 0.0
        return np.broadcast_to(self.temperature_c + swing, np.shape(t_s)).astype(float)


@dataclass(frozen=True)
class SerialSourceConfig:
    """Settings of the serial source (``backend: serial``): the port, the scaling of counts to volts and the
    rate check, each declared once with its description and range; ``driver_node`` declares a parameter of
    each, ``polyforce check-device`` takes its default baud rate from them."""

    port: str = setting("/dev/ttyACM0", "Serial device of the ADC", read_only=True)
    baud: int = setting(921600, "Serial baud rate", 1200, 12000000, read_only=True)
    volts_per_count: float = setting(10.0 / 2**24, "ADC scale (V per count)", 1e-12, 1.0, read_only=True)
    volts_offset: float = setting(0.0, "Volts added after scaling (V)", -100.0, 100.0, read_only=True)
    reconnect_period_s: float = setting(
        0.5, "Delay between attempts to reopen the port (s)", 0.01, 60.0, read_only=True)
    expected_rate_hz: float = setting(
        1000.0, "Serial: frame rate the device should deliver; diagnostics WARN below "
        f"{RATE_WARN_FRACTION:.0%} of it in two consecutive rate windows (Hz, 0 = no check)", 0.0, 100000.0,
        read_only=True)
    rate_window_s: float = setting(
        3.0, "Serial: window over which the received frame rate is measured (s)", 0.1, 600.0, read_only=True)


@dataclass(frozen=True)
class SimBlock:
    """Samples ``first .. first + n - 1`` of the simulated session."""

    first: int
    stamp_ns: np.ndarray        #: acquisition stamps, ns
    voltage_v: np.ndarray       #: bridge output, V
    force_n: np.ndarray         #: applied (reference) force, N
    temperature_c: np.ndarray   #: sensor temperature, degC


class _Simulator(Protocol):
    """What :class:`SimulatedSource` needs of a sensor simulator (:class:`polyforce_ros.sim.sensor.BridgeSimulator`)."""

    def simulate(self, t_s: npt.NDArray[np.float64], force_n: npt.NDArray[np.float64],
                 temperature_c: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """Bridge voltage (V) at the times ``t_s`` (s) for the forces (N) and temperatures (degC), continuing
        from the previous call."""
        ...


#: A temperature (degC) at each of the times given (s).
TemperatureAt = Callable[[npt.NDArray[np.float64]], npt.NDArray[np.float64]]


class SimulatedSource:
    """A simulated bridge sensor driven through a force profile on the host clock.

    Parameters
    ----------
    make_simulator : callable returning a fresh simulator of the sensor (relaxed, unloaded), whose
        ``simulate(t_s, force_n, temperature_c=...)`` continues from its previous call
        (:class:`polyforce_ros.sim.sensor.BridgeSimulator`).
    profile_f : force profile, N, one value per sample at ``rate_hz``.
    rate_hz : sample rate, Hz.
    temperature_at : callable ``t_s -> degC`` (arrays).
    loop : start the profile again when it ends (else the source is ``done``).
    """

    def __init__(self, make_simulator: Callable[[], _Simulator], profile_f: npt.ArrayLike, rate_hz: float,
                 temperature_at: TemperatureAt, loop: bool = True) -> None:
        self._make_simulator = make_simulator
        self.profile_f = np.asarray(profile_f, dtype=float)
        self.period_n = self.profile_f.size
        self.rate_hz = float(rate_hz)
        self.temperature_at = temperature_at
        self.loop = bool(loop)
        self.restart()

    def restart(self) -> None:
        """The profile starts again at its first sample (stamped from the next start), the sensor relaxed."""
        self.sim = self._make_simulator()
        self._buf_f, self._buf_v, self._buf_t, self._buf_first = np.zeros(0), np.zeros(0), np.zeros(0), 0
        self.start_ns: Optional[int] = None
        self.published = 0
        self.done = False

    @property
    def started(self) -> bool:
        """Whether :meth:`start` has stamped sample 0."""
        return self.start_ns is not None

    def start(self, now_ns: int) -> None:
        """Sample 0 is stamped ``now_ns``."""
        self.start_ns = int(now_ns)

    def due(self, now_ns: int) -> Optional[SimBlock]:
        """The samples due by ``now_ns`` not handed out yet (at most :data:`MAX_BURST`), or None."""
        if self.start_ns is None:
            return None
        due = int((now_ns - self.start_ns) * self.rate_hz / 1e9) + 1
        if not self.loop:
            due = min(due, self.period_n)
            if self.published >= self.period_n:
                self.done = True
                return None
        end = min(due, self.published + MAX_BURST)
        if end <= self.published:
            return None
        self._simulate_until(end)
        ks = np.arange(self.published, end)
        i = ks - self._buf_first
        stamps = self.start_ns + np.round(ks * 1e9 / self.rate_hz).astype(np.int64)
        block = SimBlock(self.published, stamps, self._buf_v[i], self._buf_f[i], self._buf_t[i])
        self.published = end
        return block

    def _simulate_until(self, k_end: int) -> None:
        """Make sure samples [.., k_end) are simulated (blocks of SIM_BLOCK, state carried)."""
        while self._buf_first + self._buf_v.size < k_end:
            k0 = self._buf_first + self._buf_v.size
            ks = np.arange(k0, k0 + SIM_BLOCK)
            f = self.profile_f[ks % self.period_n]
            temp = self.temperature_at(ks / self.rate_hz)
            v = self.sim.simulate(ks / self.rate_hz, f, temperature_c=temp)
            drop = max(0, self._buf_v.size - 4 * SIM_BLOCK)  # keep the buffer short
            self._buf_f = np.concatenate((self._buf_f[drop:], f))
            self._buf_v = np.concatenate((self._buf_v[drop:], v))
            self._buf_t = np.concatenate((self._buf_t[drop:], temp))
            self._buf_first += drop


class SerialSource:
    """Bytes of the ADC link in, ``(stamp_ns, voltage_v)`` samples out.

    Volts = counts x ``volts_per_count`` + ``volts_offset``. Corrupt, duplicate and late
    frames (``parser``) and implausible device times (``clock``) are counted there and
    give no sample; lost frames and sequence jumps are counted in ``parser``.

    The device's messages are taken out of the stream first (``demux``): the latest info
    (``info``) and status (``status``) are kept, temperatures wait in ``temperatures`` as
    ``(arrival_ns, DeviceTemperature)`` until :meth:`take_temperatures`.
    """

    def __init__(self, volts_per_count: float, volts_offset: float = 0.0) -> None:
        self.volts_per_count, self.volts_offset = float(volts_per_count), float(volts_offset)
        self.parser = FrameParser()
        self.clock = DeviceClock()
        self.demux = MessageDemux()
        self.info: Optional[DeviceInfo] = None
        self.status: Optional[DeviceStatus] = None
        self.temperatures: list[tuple[int, DeviceTemperature]] = []

    def reset(self) -> None:
        """A new connection: resynchronise on the sync word and re-learn the device clock."""
        self.parser.reset()
        self.clock.reset()
        self.demux.reset()
        self.info = self.status = None  # a new connection may be another device: it says who it is again

    def feed(self, data: bytes, arrival_ns: int) -> list[tuple[int, float]]:
        """Samples of the complete, valid frames in ``data`` (received at ``arrival_ns``).

        The frames of one call are stamped together (:meth:`DeviceClock.stamp_batch`): each keeps its
        own device-time stamp, however many arrive at once (a backlog after a (re)connect or a stall).
        """
        data = self._take_messages(data, arrival_ns)
        frames = self.parser.feed(data)
        stamps = self.clock.stamp_batch([frame.t_us for frame in frames], arrival_ns)
        # an implausible device time (stamp None) gives no sample with a made-up stamp
        return [(stamp, frame.counts * self.volts_per_count + self.volts_offset)
                for frame, stamp in zip(frames, stamps) if stamp is not None]

    def _take_messages(self, data: bytes, arrival_ns: int) -> bytes:
        """Keeps the messages in ``data``; returns the bytes left for the frame parser."""
        data, messages = self.demux.feed(data)
        for message in messages:
            if isinstance(message, DeviceInfo):
                self.info = message
            elif isinstance(message, DeviceStatus):
                self.status = message
            elif isinstance(message, DeviceTemperature):
                self.temperatures.append((arrival_ns, message))
        return data

    def take_temperatures(self) -> list[tuple[int, DeviceTemperature]]:
        """The temperatures received since the last call, as ``(arrival_ns, DeviceTemperature)``."""
        out, self.temperatures = self.temperatures, []
        return out
