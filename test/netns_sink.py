"""Helper process of test_two_namespaces: counts raw and wrench stamps for a while, prints JSON."""
import json
import sys
import time

import rclpy
from geometry_msgs.msg import WrenchStamped
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState

rclpy.init()
node = Node("netns_sink", namespace="/polyforce")
qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
raw, wrench = [], []
stamp = lambda m: m.header.stamp.sec * 1_000_000_000 + m.header.stamp.nanosec  # noqa: E731
node.create_subscription(JointState, "bridge_voltage", lambda m: raw.append(stamp(m)), qos)
node.create_subscription(WrenchStamped, "wrench", lambda m: wrench.append(stamp(m)) if m.wrench.force.z != 0.0 else None, qos)
executor = EventsExecutor()
executor.add_node(node)
end = time.monotonic() + float(sys.argv[1])
while time.monotonic() < end:
    executor.spin_once(timeout_sec=0.05)
executor.remove_node(node)
print(json.dumps({"raw": raw, "wrench": wrench}))
rclpy.shutdown()
