"""Processes of the live benchmark: `source`, `sink` and a bare `relay` node (the baseline).

    python bench/live_parts.py source RATE_HZ SECONDS FLOWING  warms up until FLOWING exists, then publishes
                                                               RATE_HZ * SECONDS samples and prints the count and first stamp
    python bench/live_parts.py sink OUT.npz                    records stamps and receive times until SIGTERM;
                                                               creates OUT.npz.ready once it sees the publisher and
                                                               OUT.npz.flowing at the first wrench received
    python bench/live_parts.py relay                         JointState in -> WrenchStamped out, no computation

For bench/bench_bridge.py (the haptic bridge, matched by value, not by stamp):

    python bench/live_parts.py wrench_source RATE_HZ SECONDS FLOWING OUT.npz STEP_N
                                       like `source`, but `wrench` with force.z = STEP_N * (k + 1), distinct per
                                       message; saves every sent value and its publish time to OUT.npz
    python bench/live_parts.py command_sink OUT.npz     records `haptic_command` force.z, stamps and receive times
                                                          until SIGINT/SIGTERM (.ready and .flowing as `sink`)
    python bench/live_parts.py wrench_relay             `wrench` in -> WrenchStamped copy out on `haptic_command`
                                                          with the bridge's command QoS, no computation
"""
import json
import os
import signal
import sys
import time

import numpy as np
import rclpy
from geometry_msgs.msg import WrenchStamped
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState

from polyforce_ros import contract
from polyforce_ros.nodes.haptic_bridge_node import COMMAND_QOS_DEPTH, HAPTIC_COMMAND

QOS = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
NS = "/polyforce"
#: The haptic bridge's command publisher QoS (reliable, shallow): the relay baseline publishes with the same.
COMMAND_QOS = QoSProfile(depth=COMMAND_QOS_DEPTH, reliability=ReliabilityPolicy.RELIABLE)


def paced(pub, rate_hz, seconds, flowing_path, publish):
    """Call ``publish(k)`` at ``rate_hz``: a warm-up until ``flowing_path`` exists, then the measured run.

    The warm-up proves every reliable match along source -> node -> sink is complete before
    the first measured sample, so a loss in the measured run cannot be a discovery race.
    Returns (``warmup``: samples published before the measured run, ``t0_ns``: wall time from
    which every sample published is measured).
    """
    deadline = time.monotonic() + 10.0
    while pub.get_subscription_count() == 0 and time.monotonic() < deadline:
        time.sleep(0.01)
    period = 1.0 / rate_hz
    n = int(rate_hz * seconds)
    start = time.perf_counter()
    k, warmup, t0_ns = 0, 0, None  # k: samples published, the first ``warmup`` of them not measured
    flowing_deadline = time.monotonic() + 20.0
    while k - warmup < n:
        target = start + k * period
        while True:  # sleep most of the wait, spin the last 200 us for a steady rate
            left = target - time.perf_counter()
            if left <= 0:
                break
            time.sleep(left - 2e-4 if left > 3e-4 else 0)
        if t0_ns is None and warmup % 100 == 0 and (os.path.exists(flowing_path) or time.monotonic() > flowing_deadline):
            t0_ns = time.time_ns()  # every sample stamped from here on is measured
        publish(k)
        k += 1
        if t0_ns is None:
            warmup += 1
    return warmup, t0_ns


def source(rate_hz, seconds, flowing_path):
    """Publish ``bridge_voltage`` at ``rate_hz`` (see :func:`paced`), stamped with the publish time."""
    node = Node("bench_source", namespace=NS)
    pub = node.create_publisher(JointState, "bridge_voltage", QOS)
    msg = JointState(name=["sarrus_axial"], position=[0.0])

    def publish(k):
        now = time.time_ns()
        msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(now, 1_000_000_000)
        msg.position[0] = 0.3 + 0.1 * np.sin(k * 0.01)
        pub.publish(msg)

    warmup, t0_ns = paced(pub, rate_hz, seconds, flowing_path, publish)
    time.sleep(1.0)
    print(json.dumps({"sent": int(rate_hz * seconds), "warmup": warmup, "t0_ns": t0_ns}), flush=True)


def wrench_source(rate_hz, seconds, flowing_path, out_path, step_n):
    """Publish ``wrench`` at ``rate_hz`` (see :func:`paced`) with force.z = ``step_n * (k + 1)``: one value per message.

    Saves ``value_n`` and ``sent_ns`` (wall time just before each publish) of every message, warm-up included.
    """
    node = Node("bench_wrench_source", namespace=NS)
    pub = node.create_publisher(WrenchStamped, contract.Rel.WRENCH, QOS)
    msg = WrenchStamped()
    msg.header.frame_id = contract.FRAME_ID
    values, sent = [], []

    def publish(k):
        value = step_n * (k + 1)
        msg.wrench.force.z = value
        now = time.time_ns()
        msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(now, 1_000_000_000)
        pub.publish(msg)
        values.append(value)
        sent.append(now)

    warmup, t0_ns = paced(pub, rate_hz, seconds, flowing_path, publish)
    time.sleep(1.0)
    np.savez(out_path, value_n=np.array(values), sent_ns=np.array(sent, dtype=np.int64))
    print(json.dumps({"sent": int(rate_hz * seconds), "warmup": warmup, "t0_ns": t0_ns}), flush=True)


def sink(out_path):
    node = Node("bench_sink", namespace=NS)
    stamps, received = [], []
    flowing = {"path": out_path + ".flowing"}

    def on_wrench(msg):
        if msg.wrench.force.z != 0.0:  # the source never sends exactly 0; the watchdog does
            received.append(time.time_ns())
            stamps.append(msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec)
            if flowing["path"]:
                open(flowing["path"], "w").close()
                flowing["path"] = None

    node.create_subscription(WrenchStamped, "wrench", on_wrench, QOS)
    run(node, ready_file=out_path + ".ready", ready=lambda: node.count_publishers(f"{NS}/wrench") > 0)
    np.savez(out_path, stamp_ns=np.array(stamps, dtype=np.int64), received_ns=np.array(received, dtype=np.int64))


def relay():
    node = Node("relay", namespace=NS)
    pub = node.create_publisher(WrenchStamped, "wrench", QOS)
    out = WrenchStamped()

    def on_raw(msg):
        out.header = msg.header
        out.wrench.force.z = msg.position[0]
        pub.publish(out)

    node.create_subscription(JointState, "bridge_voltage", on_raw, QOS)
    run(node)


def command_sink(out_path):
    """Record every ``haptic_command``: force.z, header stamp and receive time (for value matching)."""
    node = Node("bench_command_sink", namespace=NS)
    values, stamps, received = [], [], []
    flowing = {"path": out_path + ".flowing"}

    def on_command(msg):
        received.append(time.time_ns())
        values.append(msg.wrench.force.z)
        stamps.append(msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec)
        if flowing["path"] and msg.wrench.force.z != 0.0:  # the source never sends 0; an idle bridge does
            open(flowing["path"], "w").close()
            flowing["path"] = None

    node.create_subscription(WrenchStamped, HAPTIC_COMMAND, on_command, QOS)
    run(node, ready_file=out_path + ".ready", ready=lambda: node.count_publishers(f"{NS}/{HAPTIC_COMMAND}") > 0)
    np.savez(out_path, value_n=np.array(values), stamp_ns=np.array(stamps, dtype=np.int64),
             received_ns=np.array(received, dtype=np.int64))


def wrench_relay():
    """The bridge's baseline: ``wrench`` in -> a WrenchStamped copy out on ``haptic_command``, no computation."""
    node = Node("wrench_relay", namespace=NS)
    pub = node.create_publisher(WrenchStamped, HAPTIC_COMMAND, COMMAND_QOS)
    node.create_subscription(WrenchStamped, contract.Rel.WRENCH, pub.publish, QOS)
    run(node)


def run(node, ready_file=None, ready=None):
    """Spin until SIGTERM or SIGINT; once ``ready()`` holds, create ``ready_file`` (the orchestrator waits for it)."""
    stop = {"flag": False}
    signal.signal(signal.SIGTERM, lambda *_: stop.update(flag=True))
    signal.signal(signal.SIGINT, lambda *_: stop.update(flag=True))
    executor = EventsExecutor()
    executor.add_node(node)
    while not stop["flag"]:
        executor.spin_once(timeout_sec=0.05)
        if ready_file and ready():
            open(ready_file, "w").close()
            ready_file = None
    executor.remove_node(node)


if __name__ == "__main__":
    rclpy.init()
    try:
        role = sys.argv[1]
        if role == "source":
            source(float(sys.argv[2]), float(sys.argv[3]), sys.argv[4])
        elif role == "sink":
            sink(sys.argv[2])
        elif role == "relay":
            relay()
        elif role == "wrench_source":
            wrench_source(float(sys.argv[2]), float(sys.argv[3]), sys.argv[4], sys.argv[5], float(sys.argv[6]))
        elif role == "command_sink":
            command_sink(sys.argv[2])
        elif role == "wrench_relay":
            wrench_relay()
        else:
            raise SystemExit(f"unknown role {role!r}")
    finally:
        if rclpy.ok():
            rclpy.shutdown()
