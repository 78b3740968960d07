"""compensation_lifecycle_node: managed transitions over the standard lifecycle services."""
import math

from lifecycle_msgs.msg import State, Transition
from lifecycle_msgs.srv import ChangeState, GetState
from rclpy.parameter import Parameter

from node_support import T0_NS, Probe
from polyforce_ros.nodes.compensation_node import CompensationLifecycleNode
from ros_harness import ros

MS = 1_000_000


def _change(h, client, transition_id):
    return h.call(client, ChangeState.Request(transition=Transition(id=transition_id))).success


def _state(h, client):
    return h.call(client, GetState.Request()).current_state.id


def _send(h, probe, first, n, volts=0.2):
    for i in range(n):
        probe.send(T0_NS + (first + i) * MS, volts)
        h.spin_for(0.0005)
    h.spin_for(0.2)


def test_configure_activate_deactivate_cleanup():
    with ros() as h:
        node = h.add(CompensationLifecycleNode(context=h.context, parameter_overrides=[
            Parameter("stale_timeout_s", value=30.0), Parameter("auto_tare", value=False)]))
        probe = h.add(Probe(h.context))
        change = probe.create_client(ChangeState, "compensation_node/change_state")
        get = probe.create_client(GetState, "compensation_node/get_state")
        assert _state(h, get) == State.PRIMARY_STATE_UNCONFIGURED
        assert _change(h, change, Transition.TRANSITION_CONFIGURE)
        assert _state(h, get) == State.PRIMARY_STATE_INACTIVE
        assert h.spin_until(lambda: probe.raw.get_subscription_count() > 0, 5.0)
        _send(h, probe, 0, 20)
        assert probe.sample_wrenches() == [] and node.counts["samples"] == 0  # inactive: nothing used, nothing out
        assert _change(h, change, Transition.TRANSITION_ACTIVATE)
        assert h.spin_until(lambda: probe.raw.get_subscription_count() > 0 and probe.wrenches is not None, 5.0)
        _send(h, probe, 100, 50)
        assert h.spin_until(lambda: len(probe.sample_wrenches()) >= 45, 10.0)
        assert all(math.isfinite(w.wrench.force.z) for w in probe.sample_wrenches())
        before = len(probe.wrenches)
        assert _change(h, change, Transition.TRANSITION_DEACTIVATE)
        assert h.spin_until(lambda: len(probe.wrenches) > before, 5.0)
        assert probe.wrenches[-1].wrench.force.z == 0.0  # the final zero wrench
        assert _change(h, change, Transition.TRANSITION_CLEANUP)
        assert _state(h, get) == State.PRIMARY_STATE_UNCONFIGURED and node.compensator is None
        assert _change(h, change, Transition.TRANSITION_CONFIGURE)  # and again
        assert _state(h, get) == State.PRIMARY_STATE_INACTIVE


def test_a_bad_model_ends_configure_in_error_processing_with_the_reason(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("format: polyforce_model/1\nelements:\n- {type: zener, k1_n_per_v: -1.0, k2_n_per_v: 1.0, "
                   "eta2_n_s_per_v: 1.0}\n")
    with ros() as h:
        node = h.add(CompensationLifecycleNode(context=h.context, parameter_overrides=[
            Parameter("model_file", value=str(bad))]))
        probe = h.add(Probe(h.context))
        change = probe.create_client(ChangeState, "compensation_node/change_state")
        get = probe.create_client(GetState, "compensation_node/get_state")
        assert not _change(h, change, Transition.TRANSITION_CONFIGURE)
        assert _state(h, get) == State.PRIMARY_STATE_UNCONFIGURED  # via ErrorProcessing
        status = node._publish_diagnostics()
    assert status.level == status.ERROR and "k1_n_per_v" in status.message


def test_driver_lifecycle_publishes_only_while_active():
    from rclpy.node import Node
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from sensor_msgs.msg import JointState

    from polyforce_ros.nodes.driver_node import DriverLifecycleNode

    with ros() as h:
        driver = h.add(DriverLifecycleNode(context=h.context, parameter_overrides=[Parameter("profile", value="step")]))
        sink = h.add(Node("sink", namespace="/polyforce", context=h.context))
        got = []
        sink.create_subscription(JointState, "bridge_voltage", got.append,
                                 QoSProfile(depth=5000, reliability=ReliabilityPolicy.RELIABLE))
        change = sink.create_client(ChangeState, "driver_node/change_state")
        get = sink.create_client(GetState, "driver_node/get_state")
        assert _change(h, change, Transition.TRANSITION_CONFIGURE)
        h.spin_for(0.3)
        assert got == [] and driver.published == 0  # configured, not active: silent
        assert _change(h, change, Transition.TRANSITION_ACTIVATE)
        assert h.spin_until(lambda: len(got) >= 200, 10.0)
        assert _change(h, change, Transition.TRANSITION_DEACTIVATE)
        h.spin_for(0.1)
        n = len(got)
        h.spin_for(0.3)
        assert len(got) == n  # nothing after deactivation
        assert _change(h, change, Transition.TRANSITION_CLEANUP)
        assert _state(h, get) == State.PRIMARY_STATE_UNCONFIGURED


def test_driver_lifecycle_without_its_serial_port_ends_configure_in_error(tmp_path):
    from polyforce_ros.nodes.driver_node import DriverLifecycleNode

    with ros() as h:
        driver = h.add(DriverLifecycleNode(context=h.context, parameter_overrides=[
            Parameter("backend", value="serial"), Parameter("port", value=str(tmp_path / "no_such_tty"))]))
        probe = h.add(Probe(h.context))
        change = probe.create_client(ChangeState, "driver_node/change_state")
        get = probe.create_client(GetState, "driver_node/get_state")
        assert not _change(h, change, Transition.TRANSITION_CONFIGURE)
        assert _state(h, get) == State.PRIMARY_STATE_UNCONFIGURED
        status = driver._publish_diagnostics()
    assert status.level == status.ERROR and "no_such_tty" in status.message
