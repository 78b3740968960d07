"""replay_node: play an mcap log onto the contract topics with its original timing.

Publishes the recorded ``bridge_voltage``, ``reference_force`` and
``temperature`` messages (whichever the bag holds) with their recorded header
stamps (the acquisition times), spaced as recorded (by log time) divided by
``rate_factor``. A compensation node downstream therefore runs on logged data
exactly as it would live. ``wrench`` is not replayed (it is what the
compensation node produces).
"""
from __future__ import annotations

import time

import numpy as np
from geometry_msgs.msg import WrenchStamped
from rclpy.node import Node
from sensor_msgs.msg import JointState, Temperature

from .. import bags
from .common import DEFAULT_NAMESPACE, OK, WARN, Diagnostics, data_qos, declare, declare_qos, run

_RELATIVE = {bags.BRIDGE_VOLTAGE: "bridge_voltage", bags.REFERENCE_FORCE: "reference_force", bags.TEMPERATURE: "temperature"}
_TYPES = {bags.JOINT_STATE: JointState, bags.WRENCH_STAMPED: WrenchStamped, bags.TEMPERATURE_MSG: Temperature}


class ReplayNode(Node):
    def __init__(self, **kwargs):
        kwargs.setdefault("namespace", DEFAULT_NAMESPACE)
        super().__init__("replay_node", **kwargs)
        path = declare(self, "bag_path", "", "The mcap log to play", read_only=True)
        declare(self, "rate_factor", 1.0, "Playback speed (2.0 = twice as fast)", 0.01, 1000.0, read_only=True)
        declare(self, "loop", False, "Start again at the end", read_only=True)
        declare(self, "start_delay_s", 0.5, "Wait before the first message, for subscribers to connect (s)", 0.0, 60.0, read_only=True)
        declare(self, "joint_name", "sarrus_axial", "JointState name used for replayed samples", read_only=True)
        declare(self, "frame_id", "polyforce_sensor", "Frame of replayed messages", read_only=True)
        declare_qos(self)
        if not path:
            raise ValueError("replay_node needs the bag_path parameter")
        bag = bags.read_bag(path)
        for warning in bag.warnings:
            self.get_logger().warn(f"{path}: {warning}")
        qos = data_qos(self)
        streams = []
        for topic, data in bag.topics.items():
            if topic not in _RELATIVE or len(data) == 0:
                continue
            pub = self.create_publisher(_TYPES[data.type_name], _RELATIVE[topic], qos)
            streams.append((data.log_time_ns, data.stamp_ns, data.fields[bags.SCALAR_FIELD[data.type_name]], data.type_name, pub))
        if not streams:
            raise ValueError(f"{path}: no contract topic to replay")
        # One merged timeline ordered by log time.
        log = np.concatenate([s[0] for s in streams])
        order = np.argsort(log, kind="stable")
        self._log = log[order]
        self._stamp = np.concatenate([s[1] for s in streams])[order]
        self._value = np.concatenate([s[2] for s in streams])[order]
        self._stream = np.concatenate([np.full(len(s[0]), i) for i, s in enumerate(streams)])[order]
        self._kinds = [(s[3], s[4]) for s in streams]
        self._frame, self._joint = self.get_parameter("frame_id").value, self.get_parameter("joint_name").value
        self.diag = Diagnostics(self, "polyforce_ros: replay")
        self.index = 0
        self.loops = 0
        self.done = False
        self._t_start = time.monotonic() + self.get_parameter("start_delay_s").value
        self.create_timer(0.001, self._tick)
        self.create_timer(1.0, self._publish_diagnostics)
        self.get_logger().info(f"replaying {path}: {self._log.size} messages over "
                               f"{(self._log[-1] - self._log[0]) * 1e-9:.1f} s at x{self.get_parameter('rate_factor').value}")

    def _tick(self):
        if self.done:
            return
        elapsed = time.monotonic() - self._t_start
        if elapsed < 0:
            return
        due_log = self._log[0] + int(elapsed * self.get_parameter("rate_factor").value * 1e9)
        end = int(np.searchsorted(self._log, due_log, side="right"))
        for i in range(self.index, end):
            kind, pub = self._kinds[self._stream[i]]
            pub.publish(bags.make_message(kind, int(self._stamp[i]), self._value[i], self._frame, self._joint))
        self.index = max(self.index, end)
        if self.index >= self._log.size:
            if self.get_parameter("loop").value:
                self.index, self.loops = 0, self.loops + 1
                self._t_start = time.monotonic()
            else:
                self.done = True
                self.get_logger().info("replay finished")

    def _publish_diagnostics(self):
        level, message = (WARN, "finished") if self.done else (OK, "replaying")
        return self.diag.publish(level, message, {"published": self.index, "total": int(self._log.size), "loops": self.loops})


def main(args=None):
    return run(ReplayNode, args)


if __name__ == "__main__":
    raise SystemExit(main())
