"""Haptic bridge: every rule in the ROS-free HapticBridge (properties + examples), then the node over DDS."""
import math
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
from polyforce_ros.haptics import (PARAMETERS, HapticBridge, HapticConfig, deadband, device_vector, parse_axis, saturate,
                                   scale, shape, slew, stale_ramp)
from polyforce_ros.nodes.haptic_bridge_node import FD_EFFORT_COMMANDS, HAPTIC_COMMAND, HapticBridgeNode
from ros_harness import ros

EPS = 1e-9


# ---------------------------------------------------------------------- strategies
def configs():
    def rng(name):
        _, low, high, _ = PARAMETERS[name]
        return st.floats(low, high, allow_nan=False, allow_infinity=False)

    return st.builds(HapticConfig, **{name: rng(name) for name in PARAMETERS})


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
    previous_t, previous = None, 0.0
    for t, c in run(bridge, sequence):
        assert math.isfinite(c) and abs(c) <= config.max_force_n
        if previous_t is not None:
            t_eff = max(t, previous_t)  # the bridge treats an earlier time as the last one
            rising_or_crossing = abs(c) > abs(previous) + EPS or c * previous < 0
            if rising_or_crossing:  # only the slew limit may move a command away from zero
                assert abs(c - previous) <= config.max_slew_n_per_s * (t_eff - previous_t) * (1 + 1e-9) + EPS
            previous_t = t_eff
        else:
            previous_t = t
        previous = c


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
    bridge.step(0.0, 3.0)
    assert bridge.command == 0.0  # the new target is reached over the following ticks
    assert bridge.tick(0.01) == pytest.approx(1.0)
    assert bridge.tick(0.02) == pytest.approx(2.0)
    assert bridge.tick(0.05) == 3.0
    assert bridge.counts["slew_limited"] >= 2


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
    # recovery: the command slews up again from zero
    bridge.step(t + 1.0, 1.0)
    assert bridge.command == 0.0 and not bridge.stale and bridge.counts["recoveries"] == 1
    assert bridge.tick(t + 1.005) == pytest.approx(0.5)
    assert bridge.tick(t + 1.02) == 1.0


def test_recovery_mid_ramp_continues_from_the_ramped_value():
    bridge = bridge_with(max_slew_n_per_s=100.0)
    settle(bridge, 2.0)
    last_valid = bridge.last_valid_s
    bridge.step(last_valid + 0.2, 2.0)  # halfway down the ramp: 1.0 N
    assert bridge.command == pytest.approx(1.0)
    assert bridge.tick(last_valid + 0.205) == pytest.approx(1.5)


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
    assert bridge.tick(t + 0.001) == pytest.approx(0.5)
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
        for name, (default, *_rest) in PARAMETERS.items():
            assert params[name] == default, name  # the file documents the defaults of the rules


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

    def send(self, force):
        msg = WrenchStamped()
        msg.header.stamp = self.get_clock().now().to_msg()
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


def test_node_scales_saturates_slews_rejects_nan_and_ramps_to_zero_over_dds():
    params = dict(force_scale=0.5, deadband_n=0.0, max_force_n=2.0, max_slew_n_per_s=50.0, stale_timeout_s=0.1, ramp_s=0.2,
                  device_axis="-y", publish_rate_hz=250.0, diagnostics_period_s=0.2)
    with ros() as h:
        node = h.add(HapticBridgeNode(context=h.context, parameter_overrides=[Parameter(k, value=v) for k, v in params.items()]))
        probe = h.add(Probe(h.context))
        # the chain must flow before anything is measured (DDS discovery takes seconds on busy cores)
        assert h.spin_until(lambda: probe.wrench.get_subscription_count() > 0 and probe.commands and probe.efforts, 15.0)
        deadline = time.monotonic() + 15.0
        while node.bridge.stale and time.monotonic() < deadline:
            feed(h, probe, 0.0, 0.05)
        assert not node.bridge.stale, "wrench never reached the bridge"

        ticks = []  # (monotonic time, command) of every timer tick: the clock the rules run on
        tick = node.bridge.tick
        node.bridge.tick = lambda now: ticks.append((now, tick(now))) or ticks[-1][1]
        start = len(probe.commands)
        feed(h, probe, 3.0, 0.4)  # -> 1.5 N on -y, reached at 50 N/s in 30 ms
        assert h.spin_until(lambda: commanded(probe, -1.5), 2.0)
        rising = probe.commands[start:]
        last = probe.commands[-1]
        assert last.header.frame_id == "fd_base"
        assert (last.wrench.force.x, last.wrench.force.z, last.wrench.torque.y) == (0.0, 0.0, 0.0)

        feed(h, probe, 100.0, 0.3)  # saturates at max_force_n
        assert h.spin_until(lambda: commanded(probe, -2.0), 2.0)

        n_before_stale = len(probe.commands)
        bad_sent = sum(feed(h, probe, bad, 0.05) for bad in (math.nan, math.inf, -math.inf))  # rejected: stale, ramp to zero
        assert h.spin_until(lambda: node.bridge.stale and commanded(probe, 0.0), 3.0)
        assert h.spin_until(lambda: node.bridge.counts["invalid"] == bad_sent, 3.0), (node.bridge.counts, bad_sent)
        falling = [c.wrench.force.y for c in probe.commands[n_before_stale:]]
        assert all(abs(b) <= abs(a) for a, b in zip(falling, falling[1:])), "the stale ramp never rises"
        assert falling[-1] == 0.0

        feed(h, probe, 1.0, 0.2)  # recovery
        assert h.spin_until(lambda: commanded(probe, -0.5), 2.0)
        assert node.bridge.counts["recoveries"] >= 1

        # run-time parameters: a smaller maximum clamps at once; out-of-range values are refused
        assert node.set_parameters([Parameter("max_force_n", value=0.25)])[0].successful
        feed(h, probe, 1.0, 0.05)
        assert h.spin_until(lambda: commanded(probe, -0.25), 2.0)
        assert not node.set_parameters([Parameter("max_force_n", value=1000.0)])[0].successful

        everything = [c.wrench.force.y for c in probe.commands]
        assert all(math.isfinite(f) and abs(f) <= 2.0 for f in everything)
        rising_ys = [c.wrench.force.y for c in rising]
        assert set(rising_ys) <= {-c + 0.0 for _, c in ticks}, "every published command is a tick of the bridge"
        for (t0, a), (t1, b) in zip(ticks, ticks[1:]):
            if abs(b) > abs(a) or a * b < 0:
                assert abs(b - a) <= 50.0 * (t1 - t0) + EPS  # slew limit on the node's monotonic clock
        assert h.spin_until(lambda: any(kv.key == "invalid" and int(kv.value) == bad_sent
                                        for d in probe.diags for s in d.status if s.name.endswith("haptic bridge")
                                        for kv in s.values), 3.0)

        # shutdown: a last zero command (the effort controller would hold the last one)
        assert probe.commands[-1].wrench.force.y != 0.0
        h.executor.remove_node(node)
        h.nodes.remove(node)
        node.destroy_node()
        assert h.spin_until(lambda: commanded(probe, 0.0), 3.0)
