"""Helpers shared by the node tests: a probe that stands in for the driver and the haptic
master, the compensation node under test, and node executables as processes (stopped by PID)."""
import os
import signal
import subprocess
import sys
from pathlib import Path

from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import WrenchStamped
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64
from std_srvs.srv import Trigger

from polyforce_ros.nodes.common import ns_to_stamp, stamp_to_ns
from polyforce_ros.nodes.compensation_node import CompensationNode

T0_NS = 1_700_000_000_000_000_000


class Probe(Node):
    """Stands in for the driver and the haptic master."""

    def __init__(self, context):
        super().__init__("probe", namespace="/polyforce", context=context)
        qos = QoSProfile(depth=5000, reliability=ReliabilityPolicy.RELIABLE)
        self.raw = self.create_publisher(JointState, "bridge_voltage", qos)
        self.scalar = self.create_publisher(Float64, "bridge_voltage_scalar", qos)
        self.wrenches, self.diags = [], []
        self.create_subscription(WrenchStamped, "wrench", self.wrenches.append, qos)
        self.create_subscription(DiagnosticArray, "/diagnostics", self.diags.append, 50)
        self.tare = self.create_client(Trigger, "compensation_node/tare")
        self.reset = self.create_client(Trigger, "compensation_node/reset")

    def send(self, stamp_ns, volts, frame="sensor_frame"):
        msg = JointState(name=["sarrus_axial"], position=[float(volts)])
        ns_to_stamp(stamp_ns, msg.header.stamp)
        msg.header.frame_id = frame
        self.raw.publish(msg)

    def sample_wrenches(self):
        """Wrenches computed from samples (the watchdog's zeros have now-stamps, far from T0)."""
        return [w for w in self.wrenches if abs(stamp_to_ns(w.header.stamp) - T0_NS) < 10**12]


def start(h, **params):
    params.setdefault("auto_tare", False)  # these tests feed a moving sensor from the first sample
    overrides = [Parameter(k, value=v) for k, v in params.items()]
    node = h.add(CompensationNode(context=h.context, parameter_overrides=overrides))
    probe = h.add(Probe(h.context))
    assert h.spin_until(lambda: probe.raw.get_subscription_count() > 0 and probe.wrenches, 5.0)
    return node, probe


def send_all(h, probe, stamps_ns, volts, expect):
    # Paced at ~2 kHz: an unpaced burst of 1500 messages lost 2 of them in Fast DDS
    # shared memory even with reliable QoS; the sensor contract is 1 kHz.
    for s, v in zip(stamps_ns, volts):
        probe.send(int(s), v)
        h.spin_for(0.0005)
    assert h.spin_until(lambda: len(probe.sample_wrenches()) >= expect, 10.0), len(probe.sample_wrenches())


BIN = Path(sys.executable).parent


def spawn(exe, *ros_args, env=None):
    return subprocess.Popen([str(exe), "--ros-args", *ros_args], env=env or os.environ.copy(),
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def stop(proc, timeout=10.0):
    if proc.poll() is None:
        proc.send_signal(signal.SIGTERM)
        try:
            proc.wait(timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    return proc.returncode
