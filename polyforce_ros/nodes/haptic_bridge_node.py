"""haptic_bridge_node: compensated needle force -> force command of the haptic master.

Subscribes ``wrench`` (geometry_msgs/WrenchStamped, force.z = compensated axial
needle force in N, compression positive) and publishes one command per wrench,
from the wrench's own callback (no wait for a timer), on

* ``haptic_command`` (geometry_msgs/WrenchStamped) in the device frame
  ``device_frame_id``, the force on the axis ``device_axis``;
* ``effort_command_topic`` (std_msgs/Float64MultiArray), default
  ``/fd/fd_controller/commands``: the ``~/commands`` input of the
  ``effort_controllers/JointGroupEffortController`` (a forward_command_controller)
  that forcedimension_ros2's fd_bringup spawns as ``fd_controller`` in namespace
  ``fd``, with joints ``[fd_x, fd_y, fd_z]``; ``data`` = ``[fx, fy, fz]`` in N in
  the device base frame. The controller silently ignores messages whose
  ``data`` length differs from its joint count, so ``effort_command_size`` must
  match it (3 for an omega.3/Falcon; 4, 6 or 7 with the orientation and clutch
  joints of its fd_controllers.yaml). Empty topic = not published.

Every rule (validation, deadband, scaling, saturation, slew limit, stale ramp
to zero) is in :class:`polyforce_ros.haptics.HapticBridge`; this node feeds it
each wrench with the host's monotonic receive time (the stale rule's clock) and
the wrench's header stamp (the slew limit's clock; an unstamped wrench, stamp
0, is timed by its arrival), and publishes the command it returns. A timer at
``publish_rate_hz`` (1 kHz, the rate of a Force Dimension ros2_control loop)
serves only the stale ramp: once no valid wrench has come for
``stale_timeout_s`` it publishes the ramp down to zero, the last command of the
ramp being exactly zero, and then stays silent until a wrench comes (at start-up,
before any wrench, it publishes one zero command). A run-time
parameter change that moves the command (a lower ``max_force_n``) is published
at once. The effort controller holds its last command, so on shutdown the node
publishes a zero command and waits for it to be acknowledged. Counters on
/diagnostics.
"""
from __future__ import annotations

import time
from typing import Any, Optional

from diagnostic_msgs.msg import DiagnosticStatus
from geometry_msgs.msg import WrenchStamped
from rcl_interfaces.msg import SetParametersResult
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile
from std_msgs.msg import Float64MultiArray

from .. import contract
from ..haptics import AXES, HapticBridge, HapticConfig, device_vector, parse_axis
from .common import (DEFAULT_NAMESPACE, ERROR, OK, WARN, Diagnostics, RosNode, data_qos, declare, declare_qos,
                     declare_settings, read_settings, run, send_last_zero)

#: Relative name of the WrenchStamped command (in the node's namespace).
HAPTIC_COMMAND = contract.Rel.HAPTIC_COMMAND
#: forcedimension_ros2 (fd_bringup/launch/fd.launch.py): controller "fd_controller" in namespace "fd" -> ~/commands.
FD_EFFORT_COMMANDS = "/fd/fd_controller/commands"
#: Base link of forcedimension_ros2's fd_description (the frame of its effort commands).
FD_BASE_FRAME = "fd_base"
#: Depth of the command topics: a late command is worthless, so a stalled reader gets only the newest ones.
COMMAND_QOS_DEPTH = 10


class HapticBridgeNode(RosNode):
    """The haptic bridge (``ros2 run polyforce_ros haptic_bridge_node``); ``kwargs`` as for ``Node``."""

    def __init__(self, **kwargs: Any) -> None:
        kwargs.setdefault("namespace", DEFAULT_NAMESPACE)
        super().__init__("haptic_bridge_node", **kwargs)
        declare_settings(self, HapticConfig)
        declare(self, "device_frame_id", FD_BASE_FRAME, "Frame of haptic_command (the haptic device's base)", read_only=True)
        declare(self, "device_axis", "x",
                f"Device axis that renders the needle force, one of {sorted(AXES)}; compression pushes the handle "
                "towards +axis (omega.x: +x points at the operator, so insertion resistance pushes the hand back)",
                read_only=True)
        declare(self, "effort_command_topic", FD_EFFORT_COMMANDS,
                "Float64MultiArray effort command of the device's forward/effort controller; empty = not published",
                read_only=True)
        declare(self, "effort_command_size", 3,
                "Entries of the effort command (the controller's joint count: 3 = fd_x, fd_y, fd_z)", 1, 7, read_only=True)
        declare(self, "publish_rate_hz", 1000.0,
                "Rate of the stale ramp's commands (Hz); while wrenches arrive, one command per wrench",
                1.0, 10000.0, read_only=True)
        declare(self, "diagnostics_period_s", 1.0, "Period of /diagnostics (s)", 0.05, 60.0, read_only=True)
        declare_qos(self)
        p = {name: param.value for name, param in self._parameters.items()}
        self.axis = p["device_axis"]
        self.size = int(p["effort_command_size"])
        device_vector(0.0, self.axis, self.size)  # raises on a bad axis / size at start-up
        self.axis_index, self.axis_sign = parse_axis(self.axis)
        self.bridge = HapticBridge(read_settings(self, HapticConfig))
        self.node_counts = dict(published=0)
        self._published_n: Optional[float] = None  # the last command published, N
        # the first header stamp seen: stamps are passed on relative to it (float precision)
        self._stamp0_ns: Optional[int] = None
        self._reported = dict(self.bridge.counts)

        qos = data_qos(self)
        command_qos = QoSProfile(  # type: ignore[no-untyped-call]  # rclpy leaves QoSProfile(**kwargs) unannotated
            history=HistoryPolicy.KEEP_LAST, depth=COMMAND_QOS_DEPTH, reliability=qos.reliability,
            durability=DurabilityPolicy.VOLATILE)
        self.pub = self.create_publisher(WrenchStamped, HAPTIC_COMMAND, command_qos)
        self.effort_pub = None
        if p["effort_command_topic"]:
            self.effort_pub = self.create_publisher(Float64MultiArray, p["effort_command_topic"], command_qos)
        self._out = WrenchStamped()
        self._out.header.frame_id = p["device_frame_id"]
        self._effort = Float64MultiArray()
        self.create_subscription(WrenchStamped, contract.Rel.WRENCH, self._on_wrench, qos)
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.create_timer(1.0 / p["publish_rate_hz"], self._on_timer)
        self.diag = Diagnostics(self, "polyforce_ros: haptic bridge")
        self.create_timer(p["diagnostics_period_s"], self._publish_diagnostics)
        self.get_logger().info(
            f"needle force x{p['force_scale']} (deadband {p['deadband_n']} N, max {p['max_force_n']} N, "
            f"slew {p['max_slew_n_per_s']} N/s) -> {self.axis} of {p['device_frame_id']} on "
            f"{self.pub.topic_name}" + (f" and {self.effort_pub.topic_name}" if self.effort_pub else ""))

    def _on_set_parameters(self, params: list[Parameter]) -> SetParametersResult:
        changes = {p.name: p.value for p in params if p.name in HapticConfig.names()}
        if changes:
            try:
                self.bridge.configure(**changes)
            except (TypeError, ValueError) as exc:
                return SetParametersResult(successful=False, reason=str(exc))
            if self._published_n is not None and self.bridge.command != self._published_n:
                self._publish(self.bridge.command)  # a lower maximum clamps the command now, not at the next wrench
        return SetParametersResult(successful=True)

    def _on_wrench(self, msg: WrenchStamped) -> None:
        now = time.monotonic()
        stamp = msg.header.stamp
        stamp_ns = stamp.sec * 1_000_000_000 + stamp.nanosec
        if stamp_ns == 0:
            stamp_s = None
        else:
            if self._stamp0_ns is None:
                self._stamp0_ns = stamp_ns
            stamp_s = (stamp_ns - self._stamp0_ns) * 1e-9
        self._publish(self.bridge.step(now, msg.wrench.force.z, stamp_s))

    def _on_timer(self) -> None:
        command = self.bridge.tick(time.monotonic())
        if self.bridge.stale and command != self._published_n:  # the stale ramp, down to its last zero
            self._publish(command)

    def _publish(self, force_n: float) -> None:
        msg = self._out
        msg.header.stamp = self.get_clock().now().to_msg()
        force = self.axis_sign * force_n + 0.0
        msg.wrench.force.x = force if self.axis_index == 0 else 0.0
        msg.wrench.force.y = force if self.axis_index == 1 else 0.0
        msg.wrench.force.z = force if self.axis_index == 2 else 0.0
        self.pub.publish(msg)
        if self.effort_pub is not None:
            self._effort.data = device_vector(force_n, self.axis, self.size)
            self.effort_pub.publish(self._effort)
        self.node_counts["published"] += 1
        self._published_n = force_n

    def _publish_diagnostics(self) -> DiagnosticStatus:
        counts = self.bridge.counts
        new = {k: counts[k] - self._reported[k] for k in counts}
        self._reported = dict(counts)
        if self.bridge.stale:
            level, message = ERROR, "no valid wrench: command ramped to zero"
        elif new["invalid"]:
            level, message = WARN, "non-finite wrench samples rejected"
        elif new["saturated"]:
            level, message = WARN, "command saturated at max_force_n"
        else:
            level, message = OK, "running"
        values = dict(self.bridge.summary(), **self.node_counts, device_axis=self.axis)
        return self.diag.publish(level, message, values)

    def publish_zero(self, wait_s: float = 0.0) -> None:
        """A zero command now; on shutdown, wait up to ``wait_s`` for subscribers to acknowledge it."""
        self._publish(0.0)
        if wait_s > 0:
            from rclpy.duration import Duration

            for pub in (self.pub, self.effort_pub):
                if pub is not None:
                    pub.wait_for_all_acked(Duration(nanoseconds=int(wait_s * 1e9)))

    def destroy_node(self) -> None:
        send_last_zero(self)
        super().destroy_node()


def main(args: Optional[list[str]] = None) -> int:
    return run(HapticBridgeNode, args)


if __name__ == "__main__":
    raise SystemExit(main())
