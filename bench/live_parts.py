"""Processes of the live benchmark: `source`, `sink` and a bare `relay` node (the baseline).

    python bench/live_parts.py source RATE_HZ SECONDS FLOWING  warms up until FLOWING exists, then publishes
                                                               RATE_HZ * SECONDS samples and prints the count and first stamp
    python bench/live_parts.py sink OUT.npz                    records stamps and receive times until SIGTERM;
                                                               creates OUT.npz.ready once it sees the publisher and
                                                               OUT.npz.flowing at the first wrench received
    python bench/live_parts.py relay                         JointState in -> WrenchStamped out, no computation
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

QOS = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
NS = "/polyforce"


def source(rate_hz, seconds, flowing_path):
    """Publish at ``rate_hz``: a warm-up until the sink reports the first wrench, then the measured run.

    The warm-up proves every reliable match along source -> node -> sink is complete before
    the first measured sample, so a loss in the measured run cannot be a discovery race.
    """
    node = Node("bench_source", namespace=NS)
    pub = node.create_publisher(JointState, "bridge_voltage", QOS)
    deadline = time.monotonic() + 10.0
    while pub.get_subscription_count() == 0 and time.monotonic() < deadline:
        time.sleep(0.01)
    msg = JointState(name=["sarrus_axial"], position=[0.0])
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
        now = time.time_ns()
        msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(now, 1_000_000_000)
        msg.position[0] = 0.3 + 0.1 * np.sin(k * 0.01)
        pub.publish(msg)
        k += 1
        if t0_ns is None:
            warmup += 1
    time.sleep(1.0)
    print(json.dumps({"sent": n, "warmup": warmup, "t0_ns": t0_ns}), flush=True)


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


def run(node, ready_file=None, ready=None):
    """Spin until SIGTERM; once ``ready()`` holds, create ``ready_file`` (the orchestrator waits for it)."""
    stop = {"flag": False}
    signal.signal(signal.SIGTERM, lambda *_: stop.update(flag=True))
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
    finally:
        if rclpy.ok():
            rclpy.shutdown()
