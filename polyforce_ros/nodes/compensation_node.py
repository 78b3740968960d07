"""compensation_node: raw bridge voltage -> compensated axial force for the haptic master.

Subscribes ``bridge_voltage`` (sensor_msgs/JointState, position[0] in V, stamped
at acquisition), ``bridge_voltage_scalar`` (std_msgs/Float64, stamped on
arrival) and ``temperature`` (for models with a thermal_drift element; the
latest value is used); publishes ``wrench`` (geometry_msgs/WrenchStamped, force.z in N,
compression positive, stamped like the raw sample). Services ``~/tare`` and
``~/reset`` (std_srvs/Trigger). ``sensor_reset`` (std_msgs/Header, stamp = acquisition
time from which the sensor restarted relaxed, sent by the driver when its device or
simulator restarts) clears the history and re-arms the zeroing, like ``~/reset``.
``sensor_serial`` (std_msgs/String, latched, from the driver) is the serial number
the live device reports for its sensor; it is compared with the serial the model's
provenance names (``sensor_serial``, written by calibration). A different serial
is a WARN; with ``require_matching_sensor`` the force is zero (diagnostics ERROR)
until the live serial is known and equals the model's. Diagnostics on /diagnostics.

A thin shell: every rule about samples (bad values, implausible and backwards
stamps and their healing, gaps, tare, drift, clamp, staleness) lives in
:class:`polyforce_ros.runtime.Compensator`, which ``polyforce compensate`` runs
over bags too. The node subscribes, steps it with the host receive time,
publishes, and reports its counters. On shutdown it publishes a final zero wrench.
"""
from __future__ import annotations

import os
import time
from contextlib import suppress
from pathlib import Path
from typing import Any, Optional

from diagnostic_msgs.msg import DiagnosticStatus
from geometry_msgs.msg import WrenchStamped
from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.publisher import Publisher
from rclpy.timer import Timer
from rcl_interfaces.msg import SetParametersResult
from sensor_msgs.msg import JointState, Temperature
from builtin_interfaces.msg import Time
from std_msgs.msg import Float64, Header, String
from std_srvs.srv import Trigger

from ..model_file import SensorModel, default_model_path, load_model
from ..physics.chain import ModelError
from ..runtime import Compensator, CompensatorConfig
from ..runtime.compensator import WARN_COUNTERS, time_drifts
from .. import contract
from .common import (ERROR, OK, WARN, CreatePublisher, ManagedNode, PolyforceNode, RosLifecycleNode, data_qos, declare,
                     declare_qos, declare_settings, latched_qos, ns_to_stamp, run, send_last_zero, stamp_to_ns)

#: What the live sensor serial check found: (state: match, mismatch or unknown; model's serial; live serial; force refused).
SensorCheck = tuple[str, str, Optional[str], bool]


class _CompensationLogic(PolyforceNode):
    """Parameters, runtime and callbacks shared by the plain and the managed (lifecycle) node."""

    NODE_NAME = "compensation_node"
    diagnostics_name = "polyforce_ros: compensation"
    _active = True
    compensator: Optional[Compensator]  # from the start (configure) on
    model: SensorModel
    pub: Publisher
    _model_path: str
    _model_mtime: Optional[int]
    _tare_logged: str
    _watchdog: Timer

    def _declare_parameters(self) -> None:
        declare(self, "model_file", "", "Sensor model YAML; empty = the shipped paper model (seed 000 eq. 5)")
        declare_settings(self, CompensatorConfig)  # the runtime's policy: one declaration per field
        declare(self, "require_matching_sensor", False,
                "Publish force only while the live device's sensor serial (sensor_serial, from the driver) equals the "
                "one the model's provenance names; otherwise zero force and diagnostics ERROR. False: a different "
                "serial is a WARN and force is published")
        declare(self, "joint_name", "", "Joint to read from JointState; empty = position[0]")
        declare(self, "frame_id", "", "Frame of the wrench; empty = the frame of the input")
        declare(self, "diagnostics_period_s", 1.0, "Period of /diagnostics (s)", 0.05, 60.0, read_only=True)
        declare(self, "model_check_period_s", 1.0,
                "How often the model file is checked for changes (s)", 0.1, 60.0, read_only=True)
        declare_qos(self)

    def _start(self, create_publisher: CreatePublisher) -> None:
        """Load the model, build the runtime and open every topic, service and timer (raises on a bad model)."""
        # Parameter values read on every sample, kept in a dict refreshed by the set-parameters
        # callback (a get_parameter call per value and sample costs latency at 1 kHz).
        self.p: dict[str, Any] = {name: param.value for name, param in self._parameters.items()}
        self._open_diagnostics()
        self.node_counts = dict(published=0, stale_events=0, bad_joint=0, model_reloads=0)
        self.compensator = None
        self._stale = True
        self._model_error = ""
        self.live_serial: Optional[str] = None  # the sensor serial the driver announced (None until one arrives)
        self._sensor_state: Optional[SensorCheck] = None  # set by _check_sensor when the model is loaded
        self._refuse_force = False
        self._load_model(self.get_parameter("model_file").value)  # raises on a bad file at start-up
        qos = data_qos(self)
        self.pub = create_publisher(WrenchStamped, contract.Rel.WRENCH, qos)
        self._out = WrenchStamped()
        self._watchdog = self.create_timer(min(0.02, self.p["stale_timeout_s"] / 4), self._check_stale)
        self._entities = [
            self.create_subscription(JointState, contract.Rel.BRIDGE_VOLTAGE, self._on_joint_state, qos),
            self.create_subscription(Float64, contract.Rel.BRIDGE_VOLTAGE_SCALAR, self._on_scalar, qos),
            self.create_subscription(Temperature, contract.Rel.TEMPERATURE, self._on_temperature, 10),
            self.create_subscription(Header, contract.Rel.SENSOR_RESET, self._on_sensor_reset, 10),
            self.create_subscription(String, contract.Rel.SENSOR_SERIAL, self._on_sensor_serial, latched_qos()),
            self.create_service(Trigger, "~/tare", self._on_tare),
            self.create_service(Trigger, "~/reset", self._on_reset),
            self._watchdog,
            self.create_timer(self.get_parameter("diagnostics_period_s").value, self._publish_diagnostics),
            self.create_timer(self.get_parameter("model_check_period_s").value, self._check_model_file),
        ]
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.get_logger().info(f"compensating with {self._model_path} ({self.model.chain.viscoelastic})")
        self._log_tare_decision()

    # ------------------------------------------------------------------ model
    def _load_model(self, path_param: str) -> None:
        path = str(Path(path_param).expanduser()) if path_param else str(default_model_path())
        model = load_model(path)
        comp = self.compensator
        # the compensator first: a model it refuses changes nothing here either
        if comp is None:
            config = CompensatorConfig(**{name: self.p[name] for name in CompensatorConfig.names()})
            comp = self.compensator = Compensator(model.chain, config)
        else:
            comp.set_chain(model.chain)  # a tare is kept; the history belongs to the old model
        self.model, self._model_path = model, path
        self._model_mtime = _mtime(path)
        self._needs_temperature = model.chain.needs_temperature
        self._check_sensor()
        gain = comp.noise_gain
        self.get_logger().info(f"model noise gain {gain.gain_n_per_v:.3g} N/V rms at {gain.rate_hz:g} Hz "
                               f"(max_noise_gain {comp.config.max_noise_gain:g}; most from {gain.element})")
        applied = time_drifts(model.chain) if comp.config.apply_time_drifts else ()
        if comp.time_drifts_note:
            self.get_logger().warning(comp.time_drifts_note)
        elif applied:
            self.get_logger().info(f"applying the model's time drifts ({', '.join(applied)}) from each start, reset "
                                   "or tare (apply_time_drifts)")

    @property
    def _comp(self) -> Compensator:
        """The compensator; it exists from the start (configure) on, before any callback that uses it runs."""
        comp = self.compensator
        assert comp is not None, "the compensator exists once the node is started"
        return comp

    @property
    def counts(self) -> dict[str, int]:
        """The runtime's counters and the node's own (published, stale events, ...)."""
        return {**self._comp.counts, **self.node_counts}

    def _check_model_file(self) -> None:
        mtime = _mtime(self._model_path)
        if mtime is None or mtime == self._model_mtime:
            return
        try:
            self._load_model(self.get_parameter("model_file").value)
            self.node_counts["model_reloads"] += 1
            self._model_error = ""
            self.get_logger().info(f"model file changed, reloaded {self._model_path}")
        except ModelError as exc:
            self._model_mtime = mtime  # report once per change
            self._model_error = str(exc)
            self.get_logger().error(f"model file changed but is invalid, keeping the previous model: {exc}")

    def _on_set_parameters(self, params: list[Parameter]) -> SetParametersResult:
        for p in params:
            if p.name == "model_file":
                try:
                    self._load_model(p.value)
                except ModelError as exc:
                    return SetParametersResult(successful=False, reason=str(exc))
                self.node_counts["model_reloads"] += 1
                self._model_error = ""
                self.get_logger().info(f"model set to {self._model_path}")
        for p in params:
            self.p[p.name] = p.value
        if any(p.name == "require_matching_sensor" for p in params):
            self._check_sensor()
        changes = {p.name: p.value for p in params if p.name in CompensatorConfig.names()}
        if changes:
            self._comp.configure(**changes)
        if "stale_timeout_s" in changes:  # the watchdog may sleep until the old deadline: wake it to re-plan
            self._watchdog.timer_period_ns = 1_000_000
            self._watchdog.reset()  # type: ignore[no-untyped-call]  # rclpy leaves Timer.reset unannotated
        return SetParametersResult(successful=True)

    # ------------------------------------------------------------------ input
    def _on_joint_state(self, msg: JointState) -> None:
        joint = self.p["joint_name"]
        if joint:
            try:
                index = msg.name.index(joint)
            except ValueError:
                self.node_counts["bad_joint"] += 1
                return
        else:
            index = 0
        position = msg.position
        if len(position) <= index:
            self.node_counts["bad_joint"] += 1
            return
        self._process(stamp_to_ns(msg.header.stamp), position[index], msg.header)

    def _on_temperature(self, msg: Temperature) -> None:
        self._comp.temperature(msg.temperature)  # a non-finite reading is ignored there

    def _on_scalar(self, msg: Float64) -> None:
        self._process(time.time_ns(), msg.data, None)

    def _process(self, stamp_ns: int, voltage_v: float, header: Optional[Header]) -> None:
        if not self._active:  # a managed node that is configured but not active uses no sample
            return
        comp = self.compensator
        assert comp is not None  # subscribed once the compensator exists
        # The receive clock is the system clock, as the driver's stamps are (ROS time without sim time).
        force = comp.step(stamp_ns, voltage_v, time.time_ns())
        if comp.auto_tare_status is not self._tare_logged:
            self._log_tare_decision()
        if force is None:
            return
        if self._refuse_force:
            force = 0.0  # not the sensor the model describes (require_matching_sensor)
        self._stale = False
        if header is None or self.p["frame_id"]:
            self._publish(stamp_ns, force, header.frame_id if header is not None else "")
            return
        # Stamped like its raw sample and in its frame: the input header as it is, one setter
        # instead of three (the cache-cold cost of this callback is the node's latency over a relay).
        out = self._out
        out.header = header
        out.wrench.force.z = force
        self.pub.publish(out)
        self.node_counts["published"] += 1

    def _publish(self, stamp_ns: int, force_n: float, frame_id: str = "") -> None:
        # One message object, reused: publish() serialises at once, so refilling it is cheaper than
        # building a WrenchStamped per sample. Its header is a new one: the one it holds may be a
        # received message's (_process), which is not ours to write.
        msg = self._out
        msg.header = Header(stamp=ns_to_stamp(stamp_ns, Time()), frame_id=self.p["frame_id"] or frame_id)
        msg.wrench.force.z = float(force_n)
        self.pub.publish(msg)
        self.node_counts["published"] += 1

    def _log_tare_decision(self) -> None:
        """Log each change of the zeroing: INFO when zeroed or waiting, WARN when it fell back to the model's offset."""
        comp = self._comp
        self._tare_logged = status = comp.auto_tare_status
        if comp.auto_tare_failed:
            self.get_logger().warn(f"{status}; call ~/tare with the sensor unloaded")
        elif status == "pending":
            self.get_logger().info("zero force until the sensor rests for the start-up zeroing")
        elif status != "off":
            self.get_logger().info(status)

    def _on_sensor_reset(self, msg: Header) -> None:
        """The sensor restarted relaxed at ``msg.stamp``: forget the history, zero again before force."""
        self._comp.reset(from_stamp_ns=stamp_to_ns(msg.stamp))
        self.get_logger().info("sensor restarted: history cleared, zeroing again")
        self._log_tare_decision()

    # ------------------------------------------------------------------ sensor identity
    @property
    def model_serial(self) -> str:
        """The sensor serial the model's provenance names ("" for none)."""
        return str(self.model.provenance.get("sensor_serial") or "").strip()

    def _on_sensor_serial(self, msg: String) -> None:
        self.live_serial = msg.data.strip()
        self._check_sensor()

    def _check_sensor(self) -> None:
        """Compares the live sensor serial with the model's: decides whether force is refused, logs each change."""
        model, live = self.model_serial, self.live_serial
        if not model or live is None:
            state = "unknown"
        else:
            state = "match" if live == model else "mismatch"
        self._refuse_force = bool(self.p["require_matching_sensor"]) and state != "match"
        key: SensorCheck = (state, model, live, self._refuse_force)
        if key == self._sensor_state:
            return
        self._sensor_state = key
        # one call site per severity: rclpy refuses a call site whose severity changes
        if self._refuse_force:
            self.get_logger().error(self._sensor_message())
        elif state == "mismatch":
            self.get_logger().warning(self._sensor_message())
        elif state == "match":
            self.get_logger().info(self._sensor_message())

    @property
    def _sensor_check(self) -> SensorCheck:
        """What the last comparison of the live and the model's sensor serial found (made since the model is loaded)."""
        check = self._sensor_state
        assert check is not None, "the sensor is checked whenever a model is loaded"
        return check

    def _sensor_message(self) -> str:
        """What the comparison of the live and the model's sensor serial found ("" when there is nothing to say)."""
        state, model, live, refuse = self._sensor_check
        refused = ": zero force (require_matching_sensor)" if refuse else ""
        if state == "match":
            return f"sensor {live!r} is the one the model was calibrated on"
        if state == "mismatch":
            return f"live sensor {live!r} is not the one the model was calibrated on ({model!r}){refused}"
        if not refuse:
            return ""
        if not model:
            return f"the model names no sensor serial{refused}"
        return f"no sensor serial from the driver yet{refused}"

    # ------------------------------------------------------------------ safety
    def _check_stale(self) -> None:
        """The watchdog: a zero wrench once no valid input came for ``stale_timeout_s``, then every zero period.

        While input flows it wakes once, when the newest sample would go stale, not on a fixed
        50 Hz poll: each executor wake-up delays the sample that arrives meanwhile, which shows in
        the tail of the 1 kHz latency (docs/benchmarks.md, benchmark 1). A stop is also caught on
        time (not up to one poll period late).
        """
        comp = self._comp
        timeout_s = comp.config.stale_timeout_s
        zero_period_ns = int(min(0.02, timeout_s / 4) * 1e9)
        now_ns = time.time_ns()
        last_ns = comp.last_valid_receive_ns
        if not self._active:
            next_ns = zero_period_ns
        elif comp.stale(now_ns):
            if not self._stale:
                self.node_counts["stale_events"] += 1
                self.get_logger().error(f"no valid input for {timeout_s:.3f} s: publishing zero force")
            self._stale = True
            self._publish(self.get_clock().now().nanoseconds, 0.0)
            next_ns = zero_period_ns
        else:  # just after the newest sample goes stale (stale() is a strict comparison)
            assert last_ns is not None  # not stale: a valid sample has come
            next_ns = max(last_ns + int(timeout_s * 1e9) - now_ns, 0) + 1_000_000
        self._watchdog.timer_period_ns = next_ns
        self._watchdog.reset()  # type: ignore[no-untyped-call]  # rclpy leaves Timer.reset unannotated

    def publish_zero(self, wait_s: float = 0.0) -> None:
        """A zero wrench now; on shutdown, wait up to ``wait_s`` for subscribers to acknowledge it."""
        self._publish(self.get_clock().now().nanoseconds, 0.0)
        if wait_s > 0:
            from rclpy.duration import Duration

            self.pub.wait_for_all_acked(Duration(nanoseconds=int(wait_s * 1e9)))

    # ------------------------------------------------------------------ services
    def _on_tare(self, request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
        response.success, response.message = self._comp.tare()
        if response.success:
            self.get_logger().info(response.message)
        else:
            self.get_logger().warn(response.message)
        return response

    def _on_reset(self, request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
        self._comp.reset()
        response.success, response.message = True, "compensator history cleared"
        self.get_logger().info(response.message)
        return response

    # ------------------------------------------------------------------ diagnostics
    def _publish_diagnostics(self) -> DiagnosticStatus:
        c = self.counts
        comp, sensor_check = self._comp, self._sensor_check[0]
        if self._stale:
            level, message = ERROR, "no valid input: publishing zero force"
        elif self._refuse_force:
            level, message = ERROR, self._sensor_message()
        elif self._needs_temperature and comp.temperature_c is None:
            level, message = WARN, "model follows temperature but no temperature received: not corrected"
        elif comp.auto_tare_failed:
            level, message = ERROR, f"{comp.auto_tare_status}: call ~/tare with the sensor unloaded"
        elif comp.auto_tare_pending:
            level, message = WARN, "publishing zero force until the sensor rests (start-up zeroing pending)"
        elif sensor_check == "mismatch":
            level, message = WARN, self._sensor_message()
        elif self._model_error:
            level, message = WARN, f"model file invalid, previous model kept: {self._model_error}"
        elif any(c[k] for k in WARN_COUNTERS):
            level, message = WARN, "running; bad or clamped samples seen (see counters)"
        else:
            level, message = OK, "running"
        values = dict(c, active=self._active, model_file=self._model_path, model=self.model.chain.viscoelastic,
                      offset_v=comp.offset_v, tared=comp.tare_offset_v is not None,
                      auto_tare=comp.auto_tare_status,
                      noise_gain_n_per_v=comp.noise_gain.gain_n_per_v,
                      time_drifts_left_out=", ".join(comp.time_drifts_left_out) or "none",
                      sensor_serial=self.live_serial if self.live_serial is not None else "unknown",
                      model_sensor_serial=self.model_serial or "none", sensor_check=sensor_check)
        return self.diag.publish(level, message, values)

    def destroy_node(self) -> None:
        send_last_zero(self)
        super().destroy_node()


class CompensationNode(_CompensationLogic, Node):
    """The compensation node, running from construction (``ros2 run polyforce_ros compensation_node``)."""


class CompensationLifecycleNode(ManagedNode, _CompensationLogic, LifecycleNode):
    """The managed compensation node (``compensation_lifecycle_node``).

    configure loads and validates the model and opens the topics; activate starts
    compensating and publishing; deactivate publishes a final zero wrench; cleanup
    closes everything. A model that cannot be loaded makes configure end in
    ErrorProcessing (diagnostics ERROR with the reason) and back to unconfigured.
    """

    compensator = None  # until configure

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._active = True
        self._comp.reset()  # what came before activation is not this activation's history
        return super().on_activate(state)

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.publish_zero(wait_s=0.5)
        self._active = False
        return super().on_deactivate(state)

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        if self._active:
            self.publish_zero(wait_s=0.5)
        self._active = False
        return TransitionCallbackReturn.SUCCESS

    def _release(self) -> None:
        with suppress(ValueError):  # not added yet when configure failed before the end of _start
            self.remove_on_set_parameters_callback(self._on_set_parameters)
        self.compensator = None

    def destroy_node(self) -> None:
        if self._active:
            send_last_zero(self)
        self._active = False
        RosLifecycleNode.destroy_node(self)  # LifecycleNode's: the last zero is sent only by an active node


def _mtime(path: str) -> Optional[int]:
    try:
        return os.stat(path).st_mtime_ns
    except OSError:
        return None


def main(args: Optional[list[str]] = None) -> int:
    return run(CompensationNode, args)


def main_lifecycle(args: Optional[list[str]] = None) -> int:
    return run(CompensationLifecycleNode, args)


if __name__ == "__main__":
    raise SystemExit(main())
