"""Replay of a shipped bag through the compensation node, end to end; and the live demo."""
import numpy as np
from geometry_msgs.msg import WrenchStamped
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile, ReliabilityPolicy

from polyforce_ros import bags
from polyforce_ros.demo import run_live_demo
from polyforce_ros.nodes.common import stamp_to_ns
from polyforce_ros.nodes.compensation_node import CompensationNode
from polyforce_ros.nodes.replay_node import ReplayNode
from polyforce_ros.physics.viscoelastic import PAPER_BURGERS, compensate
from ros_harness import ros
from conftest import REPO


def test_replay_of_shipped_bag_through_compensation_matches_offline():
    path = REPO / "bags" / "step_5n.mcap"
    recorded = bags.read_bag(path)[bags.BRIDGE_VOLTAGE]
    n = 3000  # the first 6 s at 500 Hz, replayed 4x faster
    with ros() as h:
        comp = h.add(CompensationNode(context=h.context, parameter_overrides=[Parameter("stale_timeout_s", value=5.0)]))
        sink = h.add(Node("sink", namespace="/polyforce", context=h.context))
        got = []
        sink.create_subscription(WrenchStamped, "wrench", got.append, QoSProfile(depth=10000, reliability=ReliabilityPolicy.RELIABLE))
        replay = h.add(ReplayNode(context=h.context, parameter_overrides=[
            Parameter("bag_path", value=str(path)), Parameter("rate_factor", value=4.0), Parameter("start_delay_s", value=0.5)]))
        assert h.spin_until(lambda: replay.index > 2 * n, 20.0)  # raw + reference messages interleaved
        h.spin_for(0.3)
    by_stamp = {stamp_to_ns(w.header.stamp): w.wrench.force.z for w in got}
    stamps = recorded.stamp_ns[:n]
    assert all(s in by_stamp for s in stamps)
    t = (stamps - stamps[0]) * 1e-9
    expected = compensate(PAPER_BURGERS, t, recorded.fields["position"][:n])
    np.testing.assert_allclose([by_stamp[s] for s in stamps], expected, atol=1e-9)


def test_live_demo_compensation_beats_static_gain():
    result = run_live_demo(profile="step", progress=False)
    assert result["tare_ok"]
    assert result["received_wrench"] >= result["expected"] - 1
    assert result["compensated"]["rmse_n"] < result["static"]["rmse_n"] / 10
    assert result["compensated"]["rmse_n"] < 0.02
