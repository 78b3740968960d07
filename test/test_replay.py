"""Replay of a shipped bag through the compensation node, end to end; and the live demo."""
import numpy as np
from diagnostic_msgs.msg import DiagnosticStatus
from geometry_msgs.msg import WrenchStamped
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState

from polyforce_ros import bags
from polyforce_ros.demo import TARE_AFTER_SAMPLES, run_live_demo, summarize
from polyforce_ros.nodes.common import stamp_to_ns
from polyforce_ros.nodes.compensation_node import CompensationNode
from polyforce_ros.nodes.replay_node import AnswerTracker, ReplayNode
from polyforce_ros.physics.viscoelastic import PAPER_BURGERS, compensate
from ros_harness import ros
from conftest import REPO


def _replay_through_compensation(n, replay_params, comp_depth=1000, timeout=60.0):
    """Replay ``step_5n`` into a compensation node; return the sink's wrenches and the replay node."""
    path = REPO / "bags" / "step_5n.mcap"
    with ros() as h:
        # no zeroing at start: the offline reference below uses the model's offset
        comp = h.add(CompensationNode(context=h.context, parameter_overrides=[
            Parameter("stale_timeout_s", value=5.0), Parameter("qos_depth", value=comp_depth),
            Parameter("auto_tare", value=False)]))
        sink = h.add(Node("sink", namespace="/polyforce", context=h.context))
        got = []
        sink.create_subscription(WrenchStamped, "wrench", got.append,
                                 QoSProfile(depth=10000, reliability=ReliabilityPolicy.RELIABLE))
        replay = h.add(ReplayNode(context=h.context, parameter_overrides=[
            Parameter("bag_path", value=str(path)), Parameter("start_delay_s", value=0.5), *replay_params]))
        # Waits for the chain, never for the clock: the answers count what went through.
        assert h.spin_until(lambda: replay.answered + replay.unanswered >= n, timeout), (replay.answered, replay.unanswered)
        recorded = set(bags.read_bag(path)[bags.BRIDGE_VOLTAGE].stamp_ns.tolist())
        # the sink also gets the zero wrenches of the stale watchdog before the replay starts
        assert h.spin_until(lambda: sum(stamp_to_ns(w.header.stamp) in recorded for w in got) >= replay.answered, 10.0)
        status = replay._publish_diagnostics()
        del comp
    return got, replay, status


def test_replay_of_shipped_bag_through_compensation_matches_offline():
    recorded = bags.read_bag(REPO / "bags" / "step_5n.mcap")[bags.BRIDGE_VOLTAGE]
    n = 3000  # the first 6 s at 500 Hz, replayed at most 4x faster, paced by the compensation's answers
    got, replay, _ = _replay_through_compensation(n, [
        Parameter("rate_factor", value=4.0), Parameter("lossless", value=True), Parameter("max_in_flight", value=50)])
    assert replay.unanswered == 0
    by_stamp = {stamp_to_ns(w.header.stamp): w.wrench.force.z for w in got}
    stamps = recorded.stamp_ns[:n]
    assert all(s in by_stamp for s in stamps)
    t = (stamps - stamps[0]) * 1e-9
    expected = compensate(PAPER_BURGERS, t, recorded.fields["position"][:n])
    np.testing.assert_allclose([by_stamp[s] for s in stamps], expected, atol=1e-9)


def test_timed_replay_into_a_shallow_queue_reports_the_loss():
    # At x1000 every tick publishes a burst; a compensation node with a queue of 2 must lose most of
    # it, and the replay must say so instead of losing silently.
    n = 2000
    got, replay, status = _replay_through_compensation(n, [
        Parameter("rate_factor", value=1000.0), Parameter("pace_timeout_s", value=0.5)], comp_depth=2)
    assert replay.unanswered > 0
    assert replay.answered + replay.unanswered >= n
    assert status.level == DiagnosticStatus.WARN and "not answered" in status.message


def test_lossless_replay_into_the_same_shallow_queue_loses_nothing():
    recorded = bags.read_bag(REPO / "bags" / "step_5n.mcap")[bags.BRIDGE_VOLTAGE]
    n = 1000
    got, replay, status = _replay_through_compensation(n, [
        Parameter("rate_factor", value=1000.0), Parameter("lossless", value=True), Parameter("max_in_flight", value=1)],
        comp_depth=2)
    assert replay.unanswered == 0 and replay.answered >= n
    stamps = {stamp_to_ns(w.header.stamp) for w in got}
    assert set(recorded.stamp_ns[:n].tolist()) <= stamps
    assert status.level == DiagnosticStatus.OK


def test_timed_replay_with_nobody_answering_is_not_a_loss():
    """Into a recorder or a plot (no compensation node): nothing publishes the pace topic, so nothing is tracked."""
    path = REPO / "bags" / "step_5n.mcap"
    with ros() as h:
        sink = h.add(Node("raw_sink", namespace="/polyforce", context=h.context))
        raw = []
        sink.create_subscription(JointState, "bridge_voltage", raw.append,
                                 QoSProfile(depth=10000, reliability=ReliabilityPolicy.RELIABLE))
        replay = h.add(ReplayNode(context=h.context, parameter_overrides=[
            Parameter("bag_path", value=str(path)), Parameter("start_delay_s", value=0.2),
            Parameter("rate_factor", value=20.0), Parameter("pace_timeout_s", value=0.05)]))
        assert h.spin_until(lambda: replay.done, 60.0)   # the whole replay, however fast the machine
        status = replay._publish_diagnostics()
        replay.done = False                                 # what it says while replaying
        running = replay._publish_diagnostics()
    assert raw and replay.unanswered == 0 and replay.answered == 0 and not replay._tracking
    assert "not answered" not in status.message   # (behind schedule, on a loaded machine, is not a loss)
    assert running.level == DiagnosticStatus.OK and "not tracked" in running.message


def test_answer_tracker_settles_dropped_and_expired_samples():
    tracker = AnswerTracker(capacity=3)
    for stamp in (10, 20, 30):
        tracker.published(stamp, now_s=0.0)
    tracker.published(20, now_s=0.1)          # a re-send does not count twice
    assert len(tracker) == 3
    assert not tracker.answered(99)           # not ours
    assert tracker.answered(20)               # 10 was dropped downstream
    assert (tracker.answered_count, tracker.unanswered, tracker.foreign, len(tracker)) == (1, 1, 1, 1)
    tracker.published(40, 1.0)
    tracker.published(50, 1.0)
    tracker.published(60, 1.0)                # over capacity: 30 is given up
    assert tracker.unanswered == 2 and len(tracker) == 3
    tracker.expire(now_s=2.5, timeout_s=1.0)
    assert tracker.unanswered == 5 and len(tracker) == 0


def test_the_demo_counts_only_wrenches_that_answer_a_sample_and_the_watchdogs_zeros_apart():
    n = TARE_AFTER_SAMPLES + 300
    stamps = [1_000_000 * (k + 1) for k in range(n)]
    ref = {s: 2.0 + np.sin(k / 50.0) for k, s in enumerate(stamps)}
    raw = {s: 0.31 * f + 0.05 for s, f in ref.items()}
    wrench = {s: ref[s] for s in stamps[:-1]}  # the last sample's wrench lost
    wrench.update({stamps[-1] + 20_000_000 * k: 0.0 for k in range(1, 4)})  # zeros once the input went stale
    result = summarize(raw, ref, wrench, 0.05, 0.31, True, n)
    assert (result["received_wrench"], result["unanswered_wrench"], result["expected"]) == (n - 1, 3, n)
    assert result["stamps_ns"].size == n - 1 - TARE_AFTER_SAMPLES - 100
    assert result["compensated"]["rmse_n"] == 0.0 and result["compensated"]["r2"] == 1.0
    assert result["static"]["rmse_n"] < 1e-12


def test_live_demo_compensation_beats_static_gain():
    result = run_live_demo(profile="step", progress=False)
    assert result["tare_ok"]
    assert result["received_wrench"] >= result["expected"] - 1
    assert result["compensated"]["rmse_n"] < result["static"]["rmse_n"] / 10
    assert result["compensated"]["rmse_n"] < 0.02


def test_timed_replay_starts_tracking_answers_when_an_answerer_appears():
    """Nobody publishes the pace topic at the start; a compensation node that joins later is tracked from then on."""
    path = REPO / "bags" / "step_5n.mcap"
    with ros() as h:
        replay = h.add(ReplayNode(context=h.context, parameter_overrides=[
            Parameter("bag_path", value=str(path)), Parameter("start_delay_s", value=0.2),
            Parameter("rate_factor", value=0.5), Parameter("pace_timeout_s", value=5.0)]))
        assert h.spin_until(lambda: replay.index > 0, 10.0)
        assert not replay._tracking and replay.answered == 0
        h.add(CompensationNode(context=h.context, parameter_overrides=[
            Parameter("stale_timeout_s", value=5.0), Parameter("auto_tare", value=False)]))
        assert h.spin_until(lambda: replay._tracking, 10.0)       # the 1 Hz refresh saw the answerer
        assert h.spin_until(lambda: replay.answered > 50, 20.0)    # and its answers are counted
        assert replay.unanswered == 0 and not replay.done
