"""Processes of the live benchmark: `source`, `sink` and a bare `relay` node (the baseline).

    python bench/live_parts.py source RATE_HZ SECONDS        publishes JointState stamped now, then prints the count
    python bench/live_parts.py sink OUT.json                 records stamp->receive latency until SIGTERM
    python bench/live_parts.py relay                         JointState in -> WrenchStamped out, no computation
"""
import json
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


def source(rate_hz, seconds):
    node = Node("bench_source", namespace=NS)
    pub = node.create_publisher(JointState, "bridge_voltage", QOS)
    deadline = time.monotonic() + 10.0
    while pub.get_subscription_count() == 0 and time.monotonic() < deadline:
        time.sleep(0.01)
    time.sleep(1.0)  # let the whole chain finish discovery
    msg = JointState(name=["sarrus_axial"], position=[0.0])
    period = 1.0 / rate_hz
    n = int(rate_hz * seconds)
    start = time.perf_counter()
    for k in range(n):
        target = start + k * period
        while True:  # sleep most of the wait, spin the last 200 us for a steady rate
            left = target - time.perf_counter()
            if left <= 0:
                break
            time.sleep(left - 2e-4 if left > 3e-4 else 0)
        now = time.time_ns()
        msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(now, 1_000_000_000)
        msg.position[0] = 0.3 + 0.1 * np.sin(k * 0.01)
        pub.publish(msg)
    time.sleep(1.0)
    print(json.dumps({"sent": n}), flush=True)


def sink(out_path):
    node = Node("bench_sink", namespace=NS)
    lat, stamps = [], []

    def on_wrench(msg):
        stamp = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
        if msg.wrench.force.z != 0.0:  # the source never sends exactly 0; the watchdog does
            lat.append(time.time_ns() - stamp)
            stamps.append(stamp)

    node.create_subscription(WrenchStamped, "wrench", on_wrench, QOS)
    run(node, ready_file=out_path + ".ready", ready=lambda: node.count_publishers(f"{NS}/wrench") > 0)
    lat_us = np.array(lat, dtype=float) / 1e3
    unique = len(set(stamps))
    st = np.unique(np.array(stamps, dtype=np.int64))
    gaps = np.diff(st) if st.size > 1 else np.zeros(1, dtype=np.int64)
    worst = int(np.argmax(gaps)) if st.size > 1 else 0
    with open(out_path, "w") as fh:
        json.dump({"largest_gap_ms": float(gaps.max() / 1e6) if st.size > 1 else None,
                   "largest_gap_at_s": float((st[worst] - st[0]) / 1e9) if st.size > 1 else None,
                   "received": unique, "p50_us": float(np.percentile(lat_us, 50)) if lat else None,
                   "p99_us": float(np.percentile(lat_us, 99)) if lat else None, "max_us": float(lat_us.max()) if lat else None}, fh)


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
            source(float(sys.argv[2]), float(sys.argv[3]))
        elif role == "sink":
            sink(sys.argv[2])
        elif role == "relay":
            relay()
    finally:
        if rclpy.ok():
            rclpy.shutdown()
