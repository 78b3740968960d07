"""The ROS 2 graph across a network link: driver and compensation node in two network namespaces.

The test makes two namespaces joined by a veth pair (addresses only inside them), runs driver_node
in one and compensation_node plus a counting subscriber in the other, with DDS discovery given the
peer's address on that link (ROS_STATIC_PEERS) and Fast DDS restricted to UDPv4 (shared memory
would bypass the link between namespaces of one host). It checks zero loss at 1 kHz across the
link and that the packets really crossed the veth. Everything is removed afterwards.
"""
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from node_support import stop  # SIGTERM, then SIGKILL: no orphan outlives the test

HERE = Path(__file__).resolve().parent
BIN = Path(sys.executable).parent
TAG = f"{os.getpid() % 10000}"
NS_A, NS_B = f"pfa{TAG}", f"pfb{TAG}"
VETH_A, VETH_B = f"pfva{TAG}", f"pfvb{TAG}"
IP_A, IP_B = "10.231.7.1", "10.231.7.2"


def ip(*args):
    subprocess.run(["ip", *args], check=True, capture_output=True)


@pytest.fixture
def two_namespaces():
    if os.geteuid() != 0 or shutil.which("ip") is None:
        pytest.skip("needs root and iproute2 to create network namespaces")
    try:
        ip("netns", "add", NS_A)
        ip("netns", "add", NS_B)
        ip("link", "add", VETH_A, "type", "veth", "peer", "name", VETH_B)
        ip("link", "set", VETH_A, "netns", NS_A)
        ip("link", "set", VETH_B, "netns", NS_B)
        for ns, dev, addr in ((NS_A, VETH_A, IP_A), (NS_B, VETH_B, IP_B)):
            ip("-n", ns, "addr", "add", f"{addr}/30", "dev", dev)
            ip("-n", ns, "link", "set", dev, "up")
            ip("-n", ns, "link", "set", "lo", "up")
        yield
    finally:
        for ns in (NS_A, NS_B):
            subprocess.run(["ip", "netns", "del", ns], capture_output=True)


def env_for(peer):
    env = dict(os.environ)
    env.update(ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST", ROS_STATIC_PEERS=peer, FASTDDS_BUILTIN_TRANSPORTS="UDPv4",
               ROS_DOMAIN_ID=str(100 + os.getpid() % 100))
    return env


def in_ns(ns, cmd, peer):
    return subprocess.Popen(["ip", "netns", "exec", ns, *cmd], env=env_for(peer), stdout=subprocess.PIPE,
                            stderr=subprocess.DEVNULL, text=True)


def rx_packets(ns, dev):
    out = subprocess.run(["ip", "netns", "exec", ns, "cat", f"/sys/class/net/{dev}/statistics/rx_packets"],
                         capture_output=True, text=True, check=True).stdout
    return int(out)


def test_zero_loss_at_1khz_across_a_veth_link(two_namespaces):
    procs = []
    try:
        procs.append(in_ns(NS_B, [str(BIN / "compensation_node"), "--ros-args", "-p", "stale_timeout_s:=5.0"], IP_A))
        sink = in_ns(NS_B, [sys.executable, str(HERE / "netns_sink.py"), "16"], IP_A)
        procs.append(sink)
        rx_before = rx_packets(NS_B, VETH_B)
        procs.append(in_ns(NS_A, [str(BIN / "driver_node"), "--ros-args", "-p", "profile:=sawtooth"], IP_B))
        out, _ = sink.communicate(timeout=60)
        data = json.loads(out.strip().splitlines()[-1])
        rx_after = rx_packets(NS_B, VETH_B)
    finally:
        for proc in procs:
            stop(proc)
    raw = np.unique(np.array(data["raw"], dtype=np.int64))
    wrench = np.unique(np.array(data["wrench"], dtype=np.int64))
    assert raw.size > 5000, "too little data crossed the link"
    # The driver stamps sample k at start + k ms: any missing stamp between the first and last is a loss.
    expected = int(round((raw[-1] - raw[0]) / 1e6)) + 1
    assert raw.size == expected, f"lost {expected - raw.size} raw samples across the link"
    inside = wrench[(wrench >= raw[0] + 200_000_000) & (wrench <= raw[-1] - 200_000_000)]
    assert set(inside.tolist()) <= set(raw.tolist())
    assert inside.size == int(round((inside[-1] - inside[0]) / 1e6)) + 1, "wrench lost samples"
    assert rx_after - rx_before > raw.size / 10  # the data really went through the veth (UDP packets)
