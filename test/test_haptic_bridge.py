"""Haptic bridge: every rule in the ROS-free HapticBridge (properties + examples), then the node over DDS."""
import math
import random
import time
from dataclasses import replace

import pytest
import yaml
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import WrenchStamped
from hypothesis import given, settings
from hypothesis import strategies as st
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile, ReliabilityPolicy
from std_msgs.msg import Float64MultiArray

from conftest import REPO
from polyforce_ros import contract
from polyforce_ros.haptics import (HapticBridge, HapticConfig, deadband, device_vector, parse_axis, saturate, scale, shape,
                                   slew, stale_ramp)
from polyforce_ros.nodes.haptic_bridge_node import FD_EFFORT_COMMANDS, HAPTIC_COMMAND, HapticBridgeNode
from polyforce_ros.settings import settings_of
from ros_harness import ros

EPS = 1e-9


# ---------------------------------------------------------------------- strategies
def configs():
    ranges = {f.name: st.floats(meta["low"], meta["high"], allow_nan=False, allow_infinity=False)
              for f, meta in settings_of(HapticConfig)}
    return st.builds(HapticConfig, **ranges)


#: Any force a wire can carry: NaN, +-inf, huge, tiny, and everyday values.
forces = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.floats(-20.0, 20.0),
                   st.sampled_from([0.0, -0.0, math.nan, math.inf, -math.inf, 1e308, -1e308, 5e-324]))
#: Time increments: regular ticks, jitter, long silences, and clock steps backwards.
increments = st.one_of(st.sampled_from([0.0, 0.001, 0.002]), st.floats(0.0, 0.05), st.floats(0.0, 30.0), st.floats(-1.0, 0.0))
events = st.lists(st.tuples(st.sampled_from(["step", "tick"]), increments, forces), max_size=200)


def run(bridge, sequence, t0=100.0):
    """Feed the events; returns [(time, command)] after each (times as fed, possibly going backwards)."""
    t, out = t0, []
    for kind, dt, force in sequence:
        t += dt
        out.append((t, bridge.step(t, force) if kind == "step" else bridge.tick(t)))
    return out


# ---------------------------------------------------------------------- properties
@settings(max_examples=300, deadline=None)
@given(configs(), events)
def test_command_is_always_finite_within_max_and_slew_limited_or_falling(config, sequence):
    bridge = HapticBridge(config)
    t_seen, last_valid_t, previous = None, None, 0.0
    for (kind, _, force), (t, c) in zip(sequence, run(bridge, sequence)):
        assert math.isfinite(c) and abs(c) <= config.max_force_n
        t_eff = t if t_seen is None else max(t, t_seen)  # the bridge treats an earlier time as the last one
        valid = kind == "step" and math.isfinite(force)
        if abs(c) > abs(previous) + EPS or c * previous < 0:  # only a valid sample's slew moves away from zero
            assert valid and last_valid_t is not None, "a tick or a rejected sample moved the command up"
            assert abs(c - previous) <= config.max_slew_n_per_s * (t_eff - last_valid_t) * (1 + 1e-9) + EPS
        if valid:
            last_valid_t = t_eff
        t_seen, previous = t_eff, c


@settings(max_examples=200, deadline=None)
@given(configs(), events, st.lists(st.floats(0.0, 0.3), min_size=1, max_size=50))
def test_stale_input_ramps_to_exactly_zero_within_ramp_s_and_never_holds(config, sequence, gaps):
    bridge = HapticBridge(config)
    run(bridge, sequence)
    t = 1e4  # later than any time of the sequence
    bridge.step(t, 2.0)  # a last valid input, then silence
    onset = t + config.stale_timeout_s
    previous = None
    for gap in gaps:
        t += gap
        c = bridge.tick(t)
        if t >= onset + config.ramp_s:
            assert c == 0.0
        if t > onset:
            assert bridge.stale
            if previous is not None:
                assert abs(c) <= abs(previous)  # never rises, never held above zero past the ramp
            previous = c
    assert bridge.tick(onset + config.ramp_s) == 0.0
    assert bridge.tick(onset + config.ramp_s + 1e3) == 0.0


@settings(max_examples=300, deadline=None)
@given(configs(), events)
def test_non_finite_input_never_passes_it_acts_like_no_input(config, sequence):
    """A bridge fed NaN/inf behaves exactly like one that got only a tick at that time."""
    fed, reference = HapticBridge(config), HapticBridge(config)
    invalid = sum(1 for kind, _, f in sequence if kind == "step" and not math.isfinite(f))
    cleaned = [(kind if math.isfinite(f) else "tick", dt, f) for kind, dt, f in sequence]
    assert [c for _, c in run(fed, sequence)] == [c for _, c in run(reference, cleaned)]
    assert fed.counts["invalid"] == invalid


@settings(max_examples=200, deadline=None)
@given(configs(), st.floats(-50.0, 50.0))
def test_constant_valid_input_is_reached_and_held(config, force):
    config = replace(config, max_slew_n_per_s=max(config.max_slew_n_per_s, 10.0),
                     stale_timeout_s=max(config.stale_timeout_s, 0.01))
    bridge = HapticBridge(config)
    t = 0.0
    target = shape(force, config)
    for _ in range(3000):  # |target| <= 100 N at >= 10 N/s in steps of >= 5 ms: <= 2000 steps
        bridge.step(t, force)
        t += config.stale_timeout_s / 2
        if bridge.tick(t) == target:
            break
    assert bridge.command == target and not bridge.stale
    assert abs(target) <= config.max_force_n


# ---------------------------------------------------------------------- the rules, by example
def bridge_with(**kw):
    base = dict(force_scale=1.0, deadband_n=0.0, max_force_n=10.0, max_slew_n_per_s=1e6, stale_timeout_s=0.1, ramp_s=0.2)
    return HapticBridge(HapticConfig(**{**base, **kw}))


def settle(bridge, force, t=0.0, dt=0.001, n=50):
    for i in range(n):
        bridge.step(t + i * dt, force)
        bridge.tick(t + i * dt + dt / 2)
    return bridge.command, t + n * dt


def test_scaling():
    assert scale(4.0, 0.5) == 2.0
    assert settle(bridge_with(force_scale=0.5), 4.0)[0] == 2.0
    assert settle(bridge_with(force_scale=0.0), 4.0)[0] == 0.0


def test_deadband_is_continuous_and_applies_to_the_needle_force():
    assert deadband(0.01, 0.02) == 0.0 and deadband(-0.02, 0.02) == 0.0
    assert deadband(0.05, 0.02) == pytest.approx(0.03) and deadband(-0.05, 0.02) == pytest.approx(-0.03)
    bridge = bridge_with(deadband_n=0.02, force_scale=2.0)
    command, t = settle(bridge, 0.015)
    assert command == 0.0 and bridge.counts["deadbanded"] > 0
    assert settle(bridge, 0.05, t)[0] == pytest.approx(0.06)


def test_saturation_at_the_device_maximum():
    assert saturate(math.inf, 3.0) == 3.0 and saturate(-7.0, 3.0) == -3.0
    bridge = bridge_with(max_force_n=3.0)
    command, t = settle(bridge, 100.0)
    assert command == 3.0 and bridge.counts["saturated"] > 0
    assert settle(bridge, -1e308, t)[0] == -3.0
    assert settle(bridge_with(max_force_n=3.0, force_scale=100.0), 1e308)[0] == 3.0  # overflow to inf saturates


def test_slew_rate_limit():
    assert slew(0.0, 3.0, 0.5) == 0.5 and slew(0.0, 3.0, 5.0) == 3.0 and slew(1.0, -1.0, 0.5) == 0.5
    bridge = bridge_with(max_slew_n_per_s=100.0)
    assert bridge.step(0.0, 3.0) == 0.0  # the first sample after a silence moves nothing
    assert bridge.tick(0.009) == 0.0  # a tick never moves the command towards the target
    assert bridge.step(0.01, 3.0) == pytest.approx(1.0)  # 100 N/s x 10 ms since the previous sample
    assert bridge.step(0.02, 3.0) == pytest.approx(2.0)
    assert bridge.step(0.05, 3.0) == 3.0
    assert bridge.counts["slew_limited"] == 2


def test_slew_runs_on_the_stamps_of_irregular_samples_not_on_their_arrival():
    bridge = bridge_with(max_slew_n_per_s=100.0)
    stamps = [5.0, 5.001, 5.004, 5.0045, 5.0045, 5.010, 5.011]
    arrivals = [0.0, 0.020, 0.020, 0.021, 0.021, 0.060, 0.061]  # late and in bursts
    got = [bridge.step(a, 3.0, s) for a, s in zip(arrivals, stamps)]
    assert got == pytest.approx([0.0, 0.1, 0.4, 0.45, 0.45, 1.0, 1.1])
    # against zero, the band and the maximum the same way: the slew follows the shaped target
    bridge = bridge_with(max_slew_n_per_s=100.0, deadband_n=0.5, max_force_n=1.0)
    got = [bridge.step(0.001 * k, f, 7.0 + s) for k, (f, s) in enumerate([(0.0, 0.0), (5.0, 0.002), (5.0, 0.02),
                                                                           (0.3, 0.021), (0.3, 0.03)])]
    assert got == pytest.approx([0.0, 0.2, 1.0, 0.9, 0.0])


@settings(max_examples=200, deadline=None)
@given(configs(), st.data())
def test_commands_depend_on_stamps_and_forces_not_on_arrival_times(config, data):
    """Two arrival schedules of the same stamped samples (gaps below stale_timeout_s): the same commands."""
    gap = st.floats(0.0, config.stale_timeout_s * 0.9)
    finite = st.floats(-1e308, 1e308, allow_nan=False)  # (a rejected sample is not fresh: that is the stale rule's)
    samples = data.draw(st.lists(st.tuples(gap, gap, finite), max_size=100))  # (stamp step, arrival gap, force)
    regular, bursty = HapticBridge(config), HapticBridge(config)
    stamp, arrival, a, b = 1e3, 0.0, [], []
    for stamp_step, arrival_gap, force in samples:
        stamp += stamp_step
        arrival += arrival_gap
        a.append(regular.step(stamp, force, stamp))  # arriving on its stamp
        bursty.tick(500.0 + arrival)  # a tick in between changes nothing while the input is fresh
        b.append(bursty.step(500.0 + arrival, force, stamp))
    assert a == b


def test_stamp_steps_no_live_stream_makes_move_nothing_and_are_counted():
    bridge = bridge_with(max_slew_n_per_s=100.0, stale_timeout_s=0.1)
    bridge.step(0.0, 3.0, 10.0)
    assert bridge.step(0.001, 3.0, 10.001) == pytest.approx(0.1)
    assert bridge.step(0.002, 3.0, 9.0) == pytest.approx(0.1)  # backwards: held, re-anchored on this stamp
    assert bridge.step(0.003, 3.0, 9.002) == pytest.approx(0.3)
    assert bridge.step(0.004, 3.0, 9.0 + 3600.0) == pytest.approx(0.3)  # an hour ahead: held
    assert bridge.step(0.005, 3.0, 9.0 + 3600.001) == pytest.approx(0.4)
    assert bridge.counts["stamp_jumps"] == 2
    assert bridge.step(0.006, 3.0, math.nan) == pytest.approx(0.4) and bridge.counts["invalid"] == 1


def test_stale_ramp_reaches_zero_within_ramp_s_and_recovers_without_a_step():
    assert (stale_ramp(2.0, 0.1, 0.2) == pytest.approx(1.0) and stale_ramp(2.0, 0.2, 0.2) == 0.0
            and stale_ramp(2.0, 0.0, 0.0) == 0.0)
    bridge = bridge_with(max_slew_n_per_s=100.0)
    command, t = settle(bridge, 2.0)
    last_valid = bridge.last_valid_s
    assert command == 2.0
    assert bridge.tick(last_valid + 0.099) == 2.0 and not bridge.stale
    assert bridge.tick(last_valid + 0.1) == 2.0 and bridge.stale  # stale at the timeout: the ramp starts here
    assert bridge.tick(last_valid + 0.2) == pytest.approx(1.0) and bridge.stale  # halfway down the 0.2 s ramp
    assert bridge.tick(last_valid + 0.3) == 0.0
    assert bridge.counts["stale_events"] == 1
    # NaN inputs do not count as fresh: a NaN stream goes stale just the same
    bridge2 = bridge_with()
    settle(bridge2, 2.0)
    t2 = bridge2.last_valid_s
    for i in range(1, 400):
        bridge2.step(t2 + i * 0.001, math.nan)
    assert bridge2.command == 0.0 and bridge2.stale and bridge2.counts["invalid"] == 399
    # a single late tick (timer starved) still lands on zero: the ramp is computed from the stale onset
    bridge3 = bridge_with()
    settle(bridge3, 5.0)
    assert bridge3.tick(bridge3.last_valid_s + 5.0) == 0.0
    # recovery: the command slews up again from zero, from the second sample on
    bridge.step(t + 1.0, 1.0)
    assert bridge.command == 0.0 and not bridge.stale and bridge.counts["recoveries"] == 1
    assert bridge.step(t + 1.005, 1.0) == pytest.approx(0.5)
    assert bridge.step(t + 1.02, 1.0) == 1.0


def test_recovery_mid_ramp_continues_from_the_ramped_value():
    bridge = bridge_with(max_slew_n_per_s=100.0)
    settle(bridge, 2.0)
    last_valid = bridge.last_valid_s
    bridge.step(last_valid + 0.2, 2.0)  # halfway down the ramp: 1.0 N
    assert bridge.command == pytest.approx(1.0)
    assert bridge.step(last_valid + 0.205, 2.0) == pytest.approx(1.5)


def test_no_force_before_the_first_input_and_reset():
    bridge = bridge_with()
    assert bridge.stale and bridge.tick(0.0) == 0.0 and bridge.tick(10.0) == 0.0
    settle(bridge, 1.0)
    bridge.reset()
    assert bridge.command == 0.0 and bridge.stale


def test_run_time_reconfiguration_clamps_at_once_and_rejects_bad_values():
    bridge = bridge_with()
    command, t = settle(bridge, 5.0)
    assert command == 5.0
    bridge.configure(max_force_n=2.0)
    assert bridge.command == 2.0 and bridge.target == 2.0
    bridge.configure(force_scale=0.1)
    assert bridge.step(t + 0.001, 5.0) == pytest.approx(0.5)
    for bad in (dict(max_force_n=math.nan), dict(ramp_s=-1.0), dict(max_slew_n_per_s=0.0), dict(force_scale=math.inf)):
        with pytest.raises(ValueError):
            bridge.configure(**bad)
    # a shortened timeout makes an input stale at once, never a backwards slew
    bridge.configure(stale_timeout_s=0.001, ramp_s=0.0)
    assert bridge.tick(t + 0.01) == 0.0


def test_device_axis_mapping_and_effort_layout():
    assert parse_axis("x") == (0, 1.0) and parse_axis("-Y") == (1, -1.0)
    assert device_vector(2.0, "x") == [2.0, 0.0, 0.0]
    assert device_vector(2.0, "-z", 7) == [0.0, 0.0, -2.0, 0.0, 0.0, 0.0, 0.0]
    assert math.copysign(1.0, device_vector(0.0, "-x")[0]) == 1.0  # no -0.0
    with pytest.raises(ValueError):
        parse_axis("w")
    with pytest.raises(ValueError):
        device_vector(1.0, "z", 2)


# ---------------------------------------------------------------------- the node over DDS
def test_param_file_matches_declared_parameters():
    data = yaml.safe_load((REPO / "config" / "haptic_bridge.yaml").read_text())
    (fqn, section), = data.items()
    params = section["ros__parameters"]
    with ros() as h:
        node = h.add(HapticBridgeNode(context=h.context, parameter_overrides=[Parameter(k, value=v) for k, v in params.items()]))
        assert fqn == node.get_fully_qualified_name()
        declared = set(node._parameters) - {"use_sim_time", "start_type_description_service"}
        assert set(params) == declared
        for key, value in params.items():
            assert node.get_parameter(key).value == value, key
            assert node.describe_parameter(key).description, key
        for f, _ in settings_of(HapticConfig):
            assert params[f.name] == f.default, f.name  # the file documents the defaults of the rules


class Probe(Node):
    """Plays the compensation node (publishes wrench) and the haptic device (subscribes its commands)."""

    def __init__(self, context):
        super().__init__("haptic_probe", namespace=contract.NAMESPACE, context=context)
        qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
        self.wrench = self.create_publisher(WrenchStamped, contract.Rel.WRENCH, qos)
        self.commands, self.efforts, self.diags = [], [], []
        self.create_subscription(WrenchStamped, HAPTIC_COMMAND, self.commands.append, qos)
        # forward_command_controller subscribes with SystemDefaultsQoS: reliable, keep last
        self.create_subscription(Float64MultiArray, FD_EFFORT_COMMANDS, self.efforts.append, 10)
        self.create_subscription(DiagnosticArray, contract.DIAGNOSTICS, self.diags.append, 50)

    def send(self, force, stamp_ns=None):
        msg = WrenchStamped()
        if stamp_ns is None:
            msg.header.stamp = self.get_clock().now().to_msg()
        else:
            msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(stamp_ns, 1_000_000_000)
        msg.header.frame_id = contract.FRAME_ID
        msg.wrench.force.z = float(force)
        self.wrench.publish(msg)


def commanded(probe, force_y):
    """Both command topics' latest message carry ``force_y`` on -y (the two subscriptions are taken independently)."""
    return (bool(probe.commands) and probe.commands[-1].wrench.force.y == force_y
            and bool(probe.efforts) and probe.efforts[-1].data.tolist() == [0.0, force_y, 0.0])


def feed(h, probe, force, seconds, period=0.002):
    """Publish ``force`` every ``period`` for ``seconds``; returns the number of messages sent."""
    end, sent = time.monotonic() + seconds, 0
    while time.monotonic() < end:
        probe.send(force)
        sent += 1
        h.spin_for(period)
    return sent


def start_flowing(h, node, probe):
    """Feed zero wrenches until the bridge takes them and both command topics reach the probe."""
    deadline = time.monotonic() + 15.0  # DDS discovery takes seconds on busy cores
    while (node.bridge.stale or not probe.commands or not probe.efforts) and time.monotonic() < deadline:
        feed(h, probe, 0.0, 0.05)
    assert not node.bridge.stale and probe.commands and probe.efforts, "the chain never flowed"


def test_node_scales_saturates_slews_rejects_nan_and_ramps_to_zero_over_dds():
    # stale_timeout_s is well above any stall of a busy test machine between two fed wrenches: while wrenches
    # flow the bridge must never go stale, or its timer's ramp would be published among the samples' commands
    params = dict(force_scale=0.5, deadband_n=0.0, max_force_n=2.0, max_slew_n_per_s=50.0, stale_timeout_s=1.0, ramp_s=0.2,
                  device_axis="-y", publish_rate_hz=250.0, diagnostics_period_s=0.2)
    with ros() as h:
        node = h.add(HapticBridgeNode(context=h.context, parameter_overrides=[Parameter(k, value=v) for k, v in params.items()]))
        probe = h.add(Probe(h.context))
        start_flowing(h, node, probe)

        steps = []  # (stamp s, command) of every valid sample: the clock the slew limit runs on
        step = node.bridge.step
        node.bridge.step = lambda now, force, stamp=None: steps.append((stamp, step(now, force, stamp))) or steps[-1][1]
        start, stale_events = len(probe.commands), node.bridge.counts["stale_events"]
        feed(h, probe, 3.0, 0.4)  # -> 1.5 N on -y, reached at 50 N/s in 30 ms
        assert h.spin_until(lambda: commanded(probe, -1.5), 2.0)
        rising = probe.commands[start:]
        assert node.bridge.counts["stale_events"] == stale_events, "wrenches flowed without a gap of stale_timeout_s"
        last = probe.commands[-1]
        assert last.header.frame_id == "fd_base"
        assert (last.wrench.force.x, last.wrench.force.z, last.wrench.torque.y) == (0.0, 0.0, 0.0)

        feed(h, probe, 100.0, 0.3)  # saturates at max_force_n
        assert h.spin_until(lambda: commanded(probe, -2.0), 2.0)

        n_before_stale = len(probe.commands)
        # rejected: for longer than stale_timeout_s they do not keep the bridge fresh, so it is stale while they
        # still flow, and ramps to zero
        bad_sent = sum(feed(h, probe, bad, 0.5) for bad in (math.nan, math.inf, -math.inf))
        assert node.bridge.stale, "invalid wrenches kept the bridge fresh"
        assert h.spin_until(lambda: commanded(probe, 0.0), 5.0)
        assert h.spin_until(lambda: node.bridge.counts["invalid"] == bad_sent, 3.0), (node.bridge.counts, bad_sent)
        falling = [c.wrench.force.y for c in probe.commands[n_before_stale:]]
        assert all(abs(b) <= abs(a) for a, b in zip(falling, falling[1:])), "the stale ramp never rises"
        assert falling[-1] == 0.0

        feed(h, probe, 1.0, 0.2)  # recovery
        assert h.spin_until(lambda: commanded(probe, -0.5), 2.0)
        assert node.bridge.counts["recoveries"] >= 1

        # run-time parameters: a smaller maximum clamps at once (published without waiting for a wrench);
        # out-of-range values are refused
        assert node.set_parameters([Parameter("max_force_n", value=0.25)])[0].successful
        assert h.spin_until(lambda: commanded(probe, -0.25), 2.0)
        assert not node.set_parameters([Parameter("max_force_n", value=1000.0)])[0].successful

        everything = [c.wrench.force.y for c in probe.commands]
        assert all(math.isfinite(f) and abs(f) <= 2.0 for f in everything)
        rising_ys = [c.wrench.force.y for c in rising]
        assert set(rising_ys) <= {-c + 0.0 for _, c in steps}, "every command while wrenches flow is a sample's"
        for (t0, a), (t1, b) in zip(steps, steps[1:]):
            if abs(b) > abs(a) or a * b < 0:
                assert abs(b - a) <= 50.0 * (t1 - t0) + EPS  # slew limit over the wrenches' stamps
        assert h.spin_until(lambda: any(kv.key == "invalid" and int(kv.value) == bad_sent
                                        for d in probe.diags for s in d.status if s.name.endswith("haptic bridge")
                                        for kv in s.values), 3.0)

        # shutdown: a last zero command (the effort controller would hold the last one)
        assert probe.commands[-1].wrench.force.y != 0.0
        h.executor.remove_node(node)
        h.nodes.remove(node)
        node.destroy_node()
        assert h.spin_until(lambda: commanded(probe, 0.0), 3.0)


def test_node_publishes_one_command_per_wrench_slewed_over_the_stamps_over_dds():
    """Wrenches sent in irregular bursts with irregular stamps: exactly one command each, at once, and each
    command is the previous one slewed towards the target by the rate times the stamp step."""
    rate = 40.0
    params = dict(force_scale=1.0, deadband_n=0.0, max_force_n=5.0, max_slew_n_per_s=rate, stale_timeout_s=5.0,
                  ramp_s=0.2, device_axis="z", publish_rate_hz=1000.0)
    with ros() as h:
        node = h.add(HapticBridgeNode(context=h.context, parameter_overrides=[Parameter(k, value=v) for k, v in params.items()]))
        probe = h.add(Probe(h.context))
        start_flowing(h, node, probe)
        assert h.spin_until(lambda: probe.commands[-1].wrench.force.z == 0.0, 2.0)
        h.spin_for(0.1)
        n0, published0, inputs0 = len(probe.commands), node.node_counts["published"], node.bridge.counts["inputs"]

        # stamps 0.1-9 ms apart, sent in bursts of 1-5 with 0-20 ms pauses: arrival order is stamp order,
        # arrival times have nothing to do with the stamps; the force changes every 1-40 wrenches
        rng = random.Random(5)
        stamp_ns, force = time.time_ns(), 0.0
        sent = []  # (stamp ns, force)
        while len(sent) < 300:
            for _ in range(rng.randint(1, 5)):
                stamp_ns += rng.randint(100_000, 9_000_000)
                if rng.random() < 0.1:
                    force = rng.choice([0.0, 0.05, 0.5, 2.0, -1.0, 3.0, 10.0])
                probe.send(force, stamp_ns)
                sent.append((stamp_ns, force))
            h.spin_for(rng.uniform(0.0, 0.02))
        assert h.spin_until(lambda: len(probe.commands) >= n0 + len(sent), 10.0)
        h.spin_for(0.2)  # nothing more comes: the timer publishes only a stale ramp
        assert len(probe.commands) == n0 + len(sent)
        assert node.node_counts["published"] - published0 == len(sent) == node.bridge.counts["inputs"] - inputs0
        assert not node.bridge.stale

        got = [c.wrench.force.z for c in probe.commands[n0:]]
        stamps_s = [(ns - node._stamp0_ns) * 1e-9 for ns, _ in sent]  # as the node passes them: from its first
        kinds = set()
        for k in range(1, len(sent)):
            step = rate * (stamps_s[k] - stamps_s[k - 1])
            target = shape(sent[k][1], node.bridge.config)
            assert got[k] == pytest.approx(slew(got[k - 1], target, step), abs=1e-9), (k, got[k - 1], target, step)
            kinds.add("limited" if got[k] != pytest.approx(target, abs=1e-9) else "reached")
        assert kinds == {"limited", "reached"}  # both cases of the slew were checked
