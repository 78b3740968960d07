"""driver_node: raw bridge voltage from the embedded simulator or a serial ADC.

Publishes ``bridge_voltage`` (sensor_msgs/JointState: name = [joint_name],
position = [volts], header.stamp = acquisition time, frame_id = sensor frame).
The ``sim`` backend also publishes the ground-truth applied force on
``reference_force`` (WrenchStamped force.z, N) and ``temperature``
(sensor_msgs/Temperature, degC). Diagnostics on /diagnostics.

Backends
* ``sim`` (default): a sensor with the Burgers truth of ``truth_model_file``
  driven by a force profile, with noise and ADC quantisation. Sample k is
  stamped ``start + k / rate_hz`` and published once that time has passed, so
  the rate is exact however the timer jitters.
* ``serial``: frames of :mod:`polyforce_ros.serial_protocol` from a
  microcontroller; counts are scaled to volts by parameters; stamps map the
  device clock onto host time; the port is reopened after it disappears.
  Diagnostics WARN when the valid frames received stay below RATE_WARN_FRACTION
  of ``expected_rate_hz`` in two consecutive windows of ``rate_window_s`` (a
  device or link too slow for its rate; one window alone may just hold a host
  stall; 0 turns the check off). Reference firmware: ``firmware/``.
  The device's messages (:class:`~polyforce_ros.serial_protocol.MessageDemux`) are
  asked for on every connection: its info (firmware, board, ADC, rate, gain,
  volts_per_count, sensor serial) and status (reset reason, watchdog resets,
  overflows, ADC reconfigurations) appear in diagnostics, which WARN when the
  device's volts_per_count or rate disagree with the parameters, or when it was
  restarted by its watchdog or had to configure its ADC again. Its ADC temperature
  is published on ``temperature`` (sensor_msgs/Temperature, degC, stamped at arrival),
  and its sensor serial on ``sensor_serial`` (std_msgs/String, latched: the latest
  serial reaches late subscribers; published again when a device with another serial
  appears), which compensation_node compares with its model's.
"""
from __future__ import annotations

from collections import deque
from typing import Any, Optional, Union

import numpy as np
import numpy.typing as npt
from diagnostic_msgs.msg import DiagnosticStatus
from geometry_msgs.msg import WrenchStamped
from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from rclpy.node import Node
from rclpy.qos import QoSProfile
from sensor_msgs.msg import JointState, Temperature
from std_msgs.msg import Header, String
from std_srvs.srv import Trigger

from ..model_file import default_model_path, load_model
from ..runtime.sources import (RATE_WARN_FRACTION, DriverConfig, SerialSource, SerialSourceConfig, SimSourceConfig,
                               SimulatedSource)
from ..serial_protocol import REQUEST_INFO, REQUEST_STATUS, DeviceClock, DeviceInfo, FrameParser
from ..sim import profiles
from ..sim.sensor import BridgeSimulator
from .. import contract
from .common import (ERROR, OK, WARN, CreatePublisher, ManagedNode, PolyforceNode, data_qos, declare, declare_qos,
                     declare_settings, latched_qos, ns_to_stamp, read_settings, run)


class _DriverLogic(PolyforceNode):
    """Parameters, sources and publishing shared by the plain and the managed (lifecycle) driver."""

    NODE_NAME = "driver_node"
    _active = True
    source: Union[SimulatedSource, SerialSource]  # from the start (configure) on
    port: Optional[Any]  # the serial.Serial of the serial backend while it is open

    def _declare_parameters(self) -> None:
        for config_type in (DriverConfig, SimSourceConfig, SerialSourceConfig):
            declare_settings(self, config_type)
        declare(self, "diagnostics_period_s", 1.0, "Period of /diagnostics (s)", 0.05, 60.0, read_only=True)
        declare_qos(self)
        # read-only parameters: read once, here
        self.config = read_settings(self, DriverConfig)
        self.sim_config = read_settings(self, SimSourceConfig)
        self.serial_config = read_settings(self, SerialSourceConfig)

    def _start(self, create_publisher: CreatePublisher) -> None:
        """Open the source (simulator or serial port) and the topics; raises on bad parameters or files."""
        backend = self.config.backend
        self._make_publisher, self._entities = create_publisher, []
        self._joint, self._frame = self.config.joint_name, self.config.frame_id
        qos = data_qos(self)
        self.pub_raw = create_publisher(JointState, contract.Rel.BRIDGE_VOLTAGE, qos)
        # a (re)start of the simulated profile or a device reset: compensation_node clears its history and zeroes
        # again from this stamp on
        self.pub_reset = create_publisher(Header, contract.Rel.SENSOR_RESET, 10)
        self._open_diagnostics()
        self.published = 0
        self.sensor_resets = 0
        if backend == "sim":
            self._init_sim(qos)
        elif backend == "serial":
            self._init_serial()
        else:
            raise ValueError(f"backend must be 'sim' or 'serial', got {backend!r}")
        self._entities.append(self.create_timer(self.get_parameter("diagnostics_period_s").value, self._publish_diagnostics))

    @property
    def diagnostics_name(self) -> str:
        """Name of the driver's DiagnosticStatus, with its backend."""
        return f"polyforce_ros: driver ({self.config.backend})"

    def _raw_message(self, stamp_ns: int, volts: float) -> JointState:
        msg = JointState(name=[self._joint], position=[float(volts)])
        ns_to_stamp(stamp_ns, msg.header.stamp)
        msg.header.frame_id = self._frame
        return msg

    # ------------------------------------------------------------------ simulator
    def _init_sim(self, qos: QoSProfile) -> None:
        self.pub_ref = self._make_publisher(WrenchStamped, contract.Rel.REFERENCE_FORCE, qos)
        self.pub_temp = self._make_publisher(Temperature, contract.Rel.TEMPERATURE, 10)
        cfg = self.sim_config
        path = cfg.truth_model_file or str(default_model_path())
        chain = load_model(path).chain.with_offset(cfg.offset_v)  # the bridge zero is a property of this sensor
        self.rate_hz = float(cfg.rate_hz)
        self.profile_t, profile_f = profiles.make_profile(cfg.profile, rate_hz=self.rate_hz, seed=cfg.seed)
        self.source = SimulatedSource(
            lambda: BridgeSimulator(chain=chain, noise_std_v=cfg.noise_std_v, adc_bits=cfg.adc_bits, seed=cfg.seed),
            profile_f, self.rate_hz, cfg.temperature_at, loop=cfg.loop)
        self._entities += [self.create_timer(self.config.publish_period_s, self._sim_tick),
                           self.create_service(Trigger, "~/restart_profile", self._on_restart_profile)]
        self.get_logger().info(f"sim backend: profile {cfg.profile} ({self.period_n / self.rate_hz:.1f} s), "
                               f"{self.rate_hz:.0f} Hz, truth {chain.viscoelastic}")

    # the source's state, read by diagnostics, the run loop, the demo and tests; AttributeError before the
    # start and from a source of the other backend
    @property
    def _sim(self) -> SimulatedSource:
        source = self.source
        if not isinstance(source, SimulatedSource):
            raise AttributeError(f"the {self.config.backend} backend has no simulated source")
        return source

    @property
    def _serial(self) -> SerialSource:
        source = self.source
        if not isinstance(source, SerialSource):
            raise AttributeError(f"the {self.config.backend} backend has no serial source")
        return source

    @property
    def profile_f(self) -> npt.NDArray[np.float64]:
        """The simulated force profile, one value per sample (N)."""
        return self._sim.profile_f

    @property
    def period_n(self) -> int:
        """Samples of the simulated force profile."""
        return self._sim.period_n

    @property
    def start_ns(self) -> Optional[int]:
        """Stamp of sample 0 of the simulated profile (ns); None until it starts."""
        return self._sim.start_ns

    @property
    def done(self) -> bool:
        """The simulated profile has ended and does not loop (the run loop then stops); False for serial."""
        source = self.source
        return isinstance(source, SimulatedSource) and source.done

    @property
    def parser(self) -> FrameParser:
        """The serial source's frame parser, with its counters."""
        return self._serial.parser

    @property
    def clock(self) -> DeviceClock:
        """The serial source's mapping of device time onto host time, with its counters."""
        return self._serial.clock

    def _on_restart_profile(self, request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
        """Start the profile again from its first sample, stamped from now, with a relaxed sensor."""
        self._sim.restart()
        self.published = 0
        response.success, response.message = True, "profile restarts at its first sample"
        self.get_logger().info(response.message)
        return response

    def _sim_tick(self) -> None:
        if not self._active:
            return
        source = self._sim
        now = self.get_clock().now().nanoseconds
        if not source.started:
            if self.pub_raw.get_subscription_count() < self.sim_config.wait_for_subscribers:
                return  # matched readers are counted by DDS itself: what is published next reaches them
            source.start(now)
            self._publish_sensor_reset(now)
        block = source.due(now)
        if block is None:
            return
        temp_every = max(1, int(self.rate_hz / 10))
        for i, stamp in enumerate(block.stamp_ns.tolist()):
            self.pub_raw.publish(self._raw_message(stamp, block.voltage_v[i]))
            ref = WrenchStamped()
            ns_to_stamp(stamp, ref.header.stamp)
            ref.header.frame_id = self._frame
            ref.wrench.force.z = float(block.force_n[i])
            self.pub_ref.publish(ref)
            if (block.first + i) % temp_every == 0:
                temp = Temperature(temperature=float(block.temperature_c[i]), variance=0.0)
                ns_to_stamp(stamp, temp.header.stamp)
                temp.header.frame_id = self._frame
                self.pub_temp.publish(temp)
        self.published = source.published

    # ------------------------------------------------------------------ serial
    def _init_serial(self) -> None:
        cfg = self.serial_config
        self.source = SerialSource(cfg.volts_per_count, cfg.volts_offset)
        self.port = None
        self.outages = 0
        self.connected = False
        self._last_error = "not opened yet"
        self._rate_window: Optional[tuple[int, int, int]] = None  # (start ns, parser.frames, outages) being counted
        self._window_rates: deque[float] = deque(maxlen=2)  # frames/s of the last two completed windows
        self.pub_temp = self._make_publisher(Temperature, contract.Rel.TEMPERATURE, 10)  # the ADC's own sensor
        self._known_info: Optional[DeviceInfo] = None  # the device info last logged
        self.pub_serial = self._make_publisher(String, contract.Rel.SENSOR_SERIAL, latched_qos())
        self._published_serial: Optional[str] = None  # the sensor serial last published
        self._open_port()
        self._entities += [self.create_timer(self.config.publish_period_s, self._serial_tick),
                           self.create_timer(cfg.reconnect_period_s, self._reconnect)]

    def _open_port(self) -> bool:
        import serial

        try:
            self.port = serial.Serial(self.serial_config.port, self.serial_config.baud, timeout=0)
        except (serial.SerialException, OSError) as exc:
            self.port = None
            self._last_error = str(exc)
            return False
        self._serial.reset()
        self.connected = True
        self.get_logger().info(f"serial port {self.serial_config.port} open")
        self._request_identity()
        return True

    def _request_identity(self) -> None:
        """Asks the device for its info and status (a device that knows no messages ignores the bytes)."""
        import serial

        assert self.port is not None  # asked on an open port only
        try:
            self.port.write(REQUEST_INFO + REQUEST_STATUS)
        except (serial.SerialException, OSError, TypeError) as exc:
            self.get_logger().warning(f"cannot ask the device who it is: {exc}")

    def _reconnect(self) -> None:
        if not self.connected and self._open_port():
            self.get_logger().info("serial device back: reconnected")

    def _drop_port(self, reason: str) -> None:
        self._close_port()
        if self.connected:
            self.outages += 1
            self.get_logger().error(f"serial device lost ({reason}); retrying every {self.serial_config.reconnect_period_s} s")
        self.connected = False
        self._last_error = reason

    def _publish_sensor_reset(self, stamp_ns: int) -> None:
        reset = Header(frame_id=self._frame)
        ns_to_stamp(stamp_ns, reset.stamp)
        self.pub_reset.publish(reset)
        self.sensor_resets += 1

    def _serial_tick(self) -> None:
        if not self.connected or not self._active:
            return
        import serial

        port = self.port
        assert port is not None  # connected: the port is open
        try:
            waiting = port.in_waiting
            # read(1) on an idle port returns at once; on a vanished device it raises (EIO)
            data = port.read(waiting or 1)
        except (serial.SerialException, OSError, TypeError) as exc:
            self._drop_port(str(exc) or type(exc).__name__)
            return
        if not data:
            return
        reanchored = self.clock.reanchored
        samples = self._serial.feed(data, self.get_clock().now().nanoseconds)
        if self.clock.reanchored != reanchored and samples:  # the device restarted its clock: it was reset
            self._publish_sensor_reset(samples[0][0])
        for stamp, volts in samples:
            self.pub_raw.publish(self._raw_message(stamp, volts))
            self.published += 1
        self._publish_device_messages()

    def _publish_device_messages(self) -> None:
        """Logs a new device identity; publishes the device's temperatures."""
        source = self._serial
        info = source.info
        if info is not None and info != self._known_info:
            previous, self._known_info = self._known_info, info
            self.get_logger().info(
                f"device: firmware {info.firmware} (protocol {info.protocol}) on {info.board}, ADC {info.adc}, "
                f"{info.rate_hz} Hz, gain {info.gain}, volts_per_count {info.volts_per_count!r}, "
                f"sensor serial {info.sensor_serial!r}")
            if previous is not None and previous.sensor_serial != info.sensor_serial:
                self.get_logger().warning(
                    f"sensor serial changed from {previous.sensor_serial!r} to {info.sensor_serial!r}: a model "
                    "calibrated on the former does not describe the latter")
            if info.sensor_serial != self._published_serial:
                self._published_serial = info.sensor_serial
                self.pub_serial.publish(String(data=info.sensor_serial))
        for arrival_ns, reading in source.take_temperatures():
            # variance: the ADS1220 sensor's typical accuracy, +-0.5 degC, taken as one sigma
            msg = Temperature(temperature=reading.celsius, variance=0.25)
            ns_to_stamp(arrival_ns, msg.header.stamp)
            msg.header.frame_id = self._frame
            self.pub_temp.publish(msg)

    # ------------------------------------------------------------------ diagnostics
    def _count_rate_window(self) -> None:
        """Closes the rate window once ``rate_window_s`` of connected time have passed (called per diagnostics)."""
        now = self.get_clock().now().nanoseconds
        window = self._rate_window
        if not self.connected or (window is not None and window[2] != self.outages):
            window = self._rate_window = None  # an outage starts afresh: the rate of a device that is back
            self._window_rates.clear()
        if not self.connected:
            return
        if window is None:
            self._rate_window = (now, self.parser.frames, self.outages)
        elif now - window[0] >= self.serial_config.rate_window_s * 1e9:
            self._window_rates.append((self.parser.frames - window[1]) * 1e9 / (now - window[0]))
            self._rate_window = (now, self.parser.frames, self.outages)

    def _publish_diagnostics(self) -> DiagnosticStatus:
        values: dict[str, Any] = {"published": self.published}
        if self.config.backend == "sim":
            level, message = OK, "simulating"
            values.update(profile=self.sim_config.profile, rate_hz=self.rate_hz)
            if self.done:
                level, message = WARN, "profile finished (loop is false)"
        else:
            self._count_rate_window()
            rates, expected = self._window_rates, self.serial_config.expected_rate_hz
            rate = rates[-1] if rates else None
            values.update(port=self.serial_config.port, connected=self.connected, frames=self.parser.frames,
                          crc_errors=self.parser.crc_errors, lost_frames=self.parser.lost_frames, outages=self.outages,
                          duplicate_frames=self.parser.duplicates, reordered_frames=self.parser.reordered,
                          seq_jumps=self.parser.seq_jumps,
                          implausible_stamp=self.clock.implausible, reanchored=self.clock.reanchored,
                          received_rate_hz="n/a" if rate is None else round(rate, 1), expected_rate_hz=expected)
            problems = []
            if self.parser.crc_errors or self.parser.lost_frames or self.clock.implausible:
                problems.append("corrupt or lost frames or implausible device times seen")
            if self.parser.duplicates or self.parser.reordered or self.parser.seq_jumps:
                problems.append("duplicate or late frames or sequence jumps seen")
            if expected > 0 and len(rates) == 2 and max(rates) < RATE_WARN_FRACTION * expected:
                problems.append(f"receiving {rate:.0f} frames/s, expected {expected:g} (device or link too slow)")
            self._device_diagnostics(values, problems)
            if not self.connected:
                level, message = ERROR, f"serial device unavailable: {self._last_error}"
            elif problems:
                level, message = WARN, "connected; " + "; ".join(problems)
            else:
                level, message = OK, "connected"
        return self.diag.publish(level, message, values)

    def _device_diagnostics(self, values: dict[str, Any], problems: list[str]) -> None:
        """The device's own info and status into ``values``; disagreements and faults into ``problems``."""
        info, status = self._serial.info, self._serial.status
        if info is None:
            values["device_info"] = "not received (asked for at connection; firmware without messages sends none)"
        else:
            values.update(info.values())
            vpc, expected = self.serial_config.volts_per_count, self.serial_config.expected_rate_hz
            if abs(info.volts_per_count - vpc) > 1e-6 * abs(vpc):
                problems.append(f"device reports volts_per_count {info.volts_per_count!r}, parameter is {vpc!r}")
            if expected > 0 and abs(info.rate_hz - expected) > 0.005 * expected:
                problems.append(f"device converts at {info.rate_hz} Hz, expected_rate_hz is {expected:g}")
        if status is not None:
            values.update(status.values())
            if status.reset_reason_name == "watchdog":
                problems.append(f"device restarted by its watchdog ({status.watchdog_resets} watchdog resets)")
            if status.adc_reconfigs:
                problems.append(f"device configured its ADC again {status.adc_reconfigs} times (DRDY fell silent)")

    def _close_port(self) -> None:
        port = getattr(self, "port", None)  # none before the serial backend starts
        if port is not None:
            try:
                port.close()
            except Exception:  # noqa: BLE001 - the device may be gone already; closing may fail too
                pass
        self.port = None

    def destroy_node(self) -> None:
        self._close_port()
        super().destroy_node()


class DriverNode(_DriverLogic, Node):
    """The driver, publishing from construction (``ros2 run polyforce_ros driver_node``)."""


class DriverLifecycleNode(ManagedNode, _DriverLogic, LifecycleNode):
    """The managed driver (``driver_lifecycle_node``): configure opens the source (loads the
    simulator's truth model and profile, or opens the serial port) and the topics; activate
    publishes (the simulated profile starts at its first sample; a serial stream resynchronises);
    deactivate stops publishing; cleanup closes the port and the topics. A source that cannot be
    opened ends configure in ErrorProcessing, with the reason in diagnostics (ERROR)."""

    def _configure(self) -> None:
        super()._configure()
        if self.config.backend == "serial" and not self.connected:
            raise OSError(f"cannot open {self.serial_config.port}: {self._last_error}")

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        if self.config.backend == "sim":
            self._sim.restart()
            self.published = 0
        elif self.port is not None:
            self.port.reset_input_buffer()  # what waited while inactive is not this activation's data
            self._serial.reset()
            self._request_identity()
        self._active = True
        return super().on_activate(state)

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._active = False
        return super().on_deactivate(state)

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._active = False
        return TransitionCallbackReturn.SUCCESS

    def _release(self) -> None:
        self._close_port()


def main(args: Optional[list[str]] = None) -> int:
    return run(DriverNode, args)


def main_lifecycle(args: Optional[list[str]] = None) -> int:
    return run(DriverLifecycleNode, args)


if __name__ == "__main__":
    raise SystemExit(main())
