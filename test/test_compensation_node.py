"""compensation_node: topic contract, safety rules, services, runtime reload. In-process, no launch."""
import math
import time

import numpy as np
import pytest
from diagnostic_msgs.msg import DiagnosticStatus
from rclpy.parameter import Parameter
from std_msgs.msg import Float64
from std_srvs.srv import Trigger

from polyforce_ros.model_file import SensorModel, save_model
from polyforce_ros.nodes.common import stamp_to_ns
from polyforce_ros.physics.chain import SensorChain
from polyforce_ros.physics.viscoelastic import PAPER_BURGERS, Zener, compensate
from node_support import T0_NS, Probe, send_all, start  # noqa: F401
from ros_harness import ros

def test_contract_stamps_frame_and_values_match_batch_compensation():
    t = np.arange(1500) * 1e-3
    volts = 0.31 * 5.0 * (t > 0.2) + 0.05 * np.sin(2 * np.pi * 3 * t)
    stamps = T0_NS + (t * 1e9).astype(np.int64)
    with ros() as h:
        node, probe = start(h, stale_timeout_s=5.0)
        send_all(h, probe, stamps, volts, expect=t.size)
        got = probe.sample_wrenches()
    assert [stamp_to_ns(w.header.stamp) for w in got] == list(stamps)
    assert {w.header.frame_id for w in got} == {"sensor_frame"}
    force = np.array([w.wrench.force.z for w in got])
    others = np.array([[w.wrench.force.x, w.wrench.force.y, w.wrench.torque.x, w.wrench.torque.y, w.wrench.torque.z]
                       for w in got])
    np.testing.assert_allclose(force, compensate(PAPER_BURGERS, t, volts), rtol=1e-9, atol=1e-12)
    assert not others.any()


@pytest.mark.parametrize("frame_param", ["", "tool0"])
def test_wrench_header_is_the_input_header_and_never_writes_into_a_received_message(frame_param):
    """Sample path (the input header as it is) and watchdog path (a header of its own) share one message."""
    from sensor_msgs.msg import JointState
    from polyforce_ros.nodes.common import ns_to_stamp
    with ros() as h:
        node, _ = start(h, stale_timeout_s=5.0, frame_id=frame_param)
        sent = []

        class Capture:
            def publish(self, msg):   # publish() serialises at once: keep what was sent then
                sent.append((stamp_to_ns(msg.header.stamp), msg.header.frame_id, msg.wrench.force.z))
        node.pub = Capture()
        inputs = []
        for i in range(5):
            msg = JointState(name=["bridge"], position=[0.1])
            ns_to_stamp(T0_NS + i * 1_000_000, msg.header.stamp)
            msg.header.frame_id = "sensor_frame"
            node._on_joint_state(msg)
            inputs.append(msg)
        node.publish_zero()
    frame = frame_param or "sensor_frame"
    assert [s[:2] for s in sent[:5]] == [(T0_NS + i * 1_000_000, frame) for i in range(5)]
    assert sent[5][2] == 0.0 and sent[5][0] > T0_NS + 10**12 and sent[5][1] == (frame_param or "")
    assert [stamp_to_ns(m.header.stamp) for m in inputs] == [T0_NS + i * 1_000_000 for i in range(5)]
    assert {m.header.frame_id for m in inputs} == {"sensor_frame"}


def test_float64_input_is_compensated_with_arrival_stamps():
    with ros() as h:
        node, probe = start(h, stale_timeout_s=5.0)
        before = time.time_ns()
        for _ in range(50):
            probe.scalar.publish(Float64(data=0.31))
            h.spin_for(0.002)
        assert h.spin_until(lambda: node.counts["published"] >= 50
                            and len([w for w in probe.wrenches if stamp_to_ns(w.header.stamp) >= before]) >= 50)
        got = [w for w in probe.wrenches if stamp_to_ns(w.header.stamp) >= before and w.wrench.force.z != 0.0]
    assert len(got) >= 49
    assert got[0].wrench.force.z == pytest.approx(0.31 * 4.8, rel=1e-6)  # instantaneous stiffness k1


def test_bad_samples_are_dropped_counted_and_never_reach_wrench():
    stamps = [T0_NS + i * 1_000_000 for i in range(10)]
    sequence = [
        (stamps[0], 0.1), (stamps[1], float("nan")), (stamps[2], float("inf")), (stamps[3], -float("inf")),
        (stamps[4], 1e12), (stamps[5], 0.1), (stamps[4], 0.1),  # backwards
        (stamps[5], 0.2),  # duplicate stamp
        (stamps[6], 0.1), (stamps[6] + 10_000_000_000, 0.1),  # a 10 s gap
    ]
    with ros() as h:
        # the 10 s gap is sent without waiting 10 s: the stamp plausibility check must allow that much
        node, probe = start(h, stale_timeout_s=30.0, stamp_tolerance_s=30.0)
        for s, v in sequence:
            probe.send(s, v)
            h.spin_for(0.0005)
        assert h.spin_until(lambda: node.counts["samples"] >= len(sequence))
        h.spin_for(0.1)
        got = probe.sample_wrenches()
        status = node._publish_diagnostics()
    c = node.counts
    assert (c["nonfinite"], c["out_of_range"], c["backwards"], c["duplicate"], c["gaps"]) == (3, 1, 1, 1, 1)
    assert len(got) == 4
    assert all(math.isfinite(w.wrench.force.z) for w in got)
    assert status.level == DiagnosticStatus.WARN


def test_force_is_clamped_to_the_limit():
    with ros() as h:
        node, probe = start(h, stale_timeout_s=30.0, force_limit_n=2.0)
        send_all(h, probe, [T0_NS, T0_NS + 1_000_000], [5.0, -5.0], expect=2)
        assert node.set_parameters([Parameter("force_limit_n", value=1.5)])[0].successful  # takes effect at once
        send_all(h, probe, [T0_NS + 2_000_000], [5.0], expect=3)
        got = probe.sample_wrenches()
    assert [w.wrench.force.z for w in got] == [2.0, -2.0, 1.5]
    assert node.counts["clamped"] == 3


def test_tare_and_reset_services():
    with ros() as h:
        node, probe = start(h, stale_timeout_s=30.0, tare_window=100)
        refused = h.call(probe.tare, Trigger.Request())
        assert not refused.success and "no valid samples" in refused.message
        stamps = T0_NS + np.arange(300) * 1_000_000
        send_all(h, probe, stamps[:150], np.full(150, 0.25), expect=150)
        assert probe.sample_wrenches()[-1].wrench.force.z > 0.5  # the unloaded offset reads as force
        tared = h.call(probe.tare, Trigger.Request())
        assert tared.success and "0.250000 V" in tared.message
        send_all(h, probe, stamps[150:], np.full(150, 0.25), expect=300)
        after = [w.wrench.force.z for w in probe.sample_wrenches()[150:]]
        assert max(abs(f) for f in after) < 1e-9
        assert h.call(probe.reset, Trigger.Request()).success
        send_all(h, probe, [stamps[-1] + 1_000_000], [0.25 + 0.31], expect=301)
        assert probe.sample_wrenches()[-1].wrench.force.z == pytest.approx(0.31 * 4.8)


def test_model_reload_by_parameter_and_by_file_change(tmp_path):
    path = tmp_path / "model.yaml"
    save_model(path, SensorModel(SensorChain.from_model(Zener(6.0, 9.0, 50.0))))
    with ros() as h:
        node, probe = start(h, stale_timeout_s=30.0)
        result = node.set_parameters([Parameter("model_file", value=str(path))])[0]
        assert result.successful and node.model.chain.viscoelastic == Zener(6.0, 9.0, 50.0)
        bad = tmp_path / "bad.yaml"
        bad.write_text("format: polyforce_model/1\nelements: [{type: burgers, k1_n_per_v: -1}]\n")
        refused = node.set_parameters([Parameter("model_file", value=str(bad))])[0]
        assert not refused.successful and "missing keys" in refused.reason
        assert node.model.chain.viscoelastic == Zener(6.0, 9.0, 50.0)
        # Rewriting the file in place is picked up without restart; a broken rewrite is refused.
        save_model(path, SensorModel(SensorChain.from_model(PAPER_BURGERS)))
        assert h.spin_until(lambda: node.model.chain.viscoelastic == PAPER_BURGERS, 5.0)
        path.write_text("format: polyforce_model/1\nelements: []\n")
        assert h.spin_until(lambda: node._model_error != "", 5.0)
        assert node.model.chain.viscoelastic == PAPER_BURGERS
        assert node._publish_diagnostics().level == DiagnosticStatus.ERROR  # no input yet: that comes first
        send_all(h, probe, [T0_NS], [0.1], expect=1)
        status = node._publish_diagnostics()
        assert status.level == DiagnosticStatus.WARN and "previous model kept" in status.message
        # a model the compensator refuses (time drifts alone) changes nothing the node says of its model either
        drifts = tmp_path / "drifts.yaml"
        drifts.write_text("format: polyforce_model/1\nelements: [{type: offset_drift, rate_v_per_s: 0.001}]\n")
        refused = node.set_parameters([Parameter("model_file", value=str(drifts))])[0]
        assert not refused.successful and "only time drifts" in refused.reason
        assert node.model.chain.viscoelastic == PAPER_BURGERS and node._model_path == str(path)


def test_stale_input_gives_zero_wrench_and_error_then_recovers():
    with ros() as h:
        node, probe = start(h, stale_timeout_s=0.05, diagnostics_period_s=0.05)
        now = time.time_ns()
        send_all(h, probe, [now, now + 1_000_000], [1.0, 1.0], expect=0)
        assert h.spin_until(lambda: any(w.wrench.force.z > 1.0 for w in probe.wrenches), 2.0)
        assert h.spin_until(lambda: node.counts["stale_events"] >= 1, 2.0)
        assert h.spin_until(lambda: probe.wrenches[-1].wrench.force.z == 0.0, 2.0)
        assert h.spin_until(lambda: any(d.status[0].level == DiagnosticStatus.ERROR for d in probe.diags), 2.0)
        probe.diags.clear()
        later = time.time_ns()
        for i in range(20):
            probe.send(later + i * 1_000_000, 1.0)
            h.spin_for(0.002)
        assert not node._stale
        assert h.spin_until(lambda: any(d.status[0].level != DiagnosticStatus.ERROR for d in probe.diags), 2.0)


def test_watchdog_sleeps_until_the_newest_sample_would_go_stale_then_repeats_zeros():
    """No fixed poll while input flows: one wake-up when the newest sample goes stale, then zeros every 20 ms."""
    from sensor_msgs.msg import JointState
    from polyforce_ros.nodes.common import ns_to_stamp
    with ros() as h:
        node, _ = start(h, stale_timeout_s=0.5)
        msg = JointState(name=["bridge"], position=[0.1])
        ns_to_stamp(time.time_ns(), msg.header.stamp)
        node._on_joint_state(msg)
        node._check_stale()
        planned_ns = node._watchdog.timer_period_ns
        assert not node._stale and 0.45e9 < planned_ns <= 0.501e9      # the deadline, plus 1 ms
        node.compensator.last_valid_receive_ns -= 10**9                 # the newest sample is now 1.5 s old
        published = node.node_counts["published"]
        node._check_stale()
        assert node._stale and node.node_counts["stale_events"] == 1
        assert node.node_counts["published"] == published + 1 and node._watchdog.timer_period_ns == 20_000_000
        node.compensator.last_valid_receive_ns = time.time_ns()
        node._check_stale()
        assert node._watchdog.timer_period_ns > 0.45e9
        node.set_parameters([Parameter("stale_timeout_s", value=0.05)])  # a shorter timeout re-plans at once
        assert node._watchdog.timer_period_ns == 1_000_000
        node._check_stale()
        assert node._watchdog.timer_period_ns <= 0.051e9


def test_shutdown_publishes_zero_wrench():
    with ros() as h:
        node, probe = start(h, stale_timeout_s=30.0)
        send_all(h, probe, [T0_NS], [1.0], expect=1)
        n = len(probe.wrenches)
        h.executor.remove_node(node)
        h.nodes.remove(node)
        node.destroy_node()
        assert h.spin_until(lambda: len(probe.wrenches) > n, 2.0)
        assert probe.wrenches[-1].wrench.force.z == 0.0


def test_thermal_drift_model_uses_the_temperature_topic(tmp_path):
    from sensor_msgs.msg import Temperature

    from polyforce_ros.physics.chain import OffsetElement, ThermalDriftElement, ViscoelasticElement

    path = tmp_path / "thermal.yaml"
    chain = SensorChain([ViscoelasticElement(PAPER_BURGERS), ThermalDriftElement(coefficient_v_per_c=0.01, reference_c=20.0),
                         OffsetElement(0.0)])
    save_model(path, SensorModel(chain))
    with ros() as h:
        node, probe = start(h, stale_timeout_s=30.0, model_file=str(path))
        temp_pub = probe.create_publisher(Temperature, "temperature", 10)
        send_all(h, probe, [T0_NS], [0.0], expect=1)
        assert node._publish_diagnostics().level == DiagnosticStatus.WARN  # thermal model, no temperature yet
        temp_pub.publish(Temperature(temperature=30.0))
        assert h.spin_until(lambda: node.compensator.temperature_c == 30.0, 5.0)
        # Unloaded sensor, 10 degC above reference: the bridge reads 0.1 V that is not force.
        send_all(h, probe, [T0_NS + i * 1_000_000 for i in range(1, 50)], [0.1] * 49, expect=50)
        forces = [w.wrench.force.z for w in probe.sample_wrenches()[1:]]
    assert max(abs(f) for f in forces) < 1e-9


def test_hysteresis_model_by_configuration(tmp_path):
    """Any chain runs in the node: here an FSR-like Preisach sensor (seed 001) with its continuous inverse."""
    from polyforce_ros.evaluation.fsr_preisach import fsr_truth
    from polyforce_ros.physics.chain import OffsetElement, PreisachElement

    chain = SensorChain([PreisachElement(fsr_truth(seed=3), continuous=True), OffsetElement(0.0)])
    path = tmp_path / "fsr.yaml"
    save_model(path, SensorModel(chain))
    force = np.concatenate([np.linspace(0.0, 4.0, 200), np.linspace(4.0, 1.0, 150), np.linspace(1.0, 3.0, 100)])
    volts = chain.forward(np.arange(force.size) * 1e-3, force)
    with ros() as h:
        node, probe = start(h, stale_timeout_s=30.0, model_file=str(path), force_limit_n=10.0)
        send_all(h, probe, T0_NS + np.arange(force.size) * 1_000_000, volts, expect=force.size)
        got = np.array([w.wrench.force.z for w in probe.sample_wrenches()])
    np.testing.assert_allclose(got[1:], force[1:], atol=1e-6)


@pytest.mark.parametrize("tracking", [False, True])
def test_drift_tracking_rezeroes_a_drifting_baseline_at_rest(tracking):
    """An unloaded sensor whose bridge drifts by 2 mV/s: without tracking the force creeps away; with it
    the offset follows and the resting force stays inside the band."""
    n = 3000
    stamps = T0_NS + np.arange(n) * 5_000_000  # 200 Hz, 15 s
    volts = 2e-3 * np.arange(n) * 0.005
    with ros() as h:
        node, probe = start(h, stale_timeout_s=30.0, drift_tracking=tracking, drift_band_n=0.05, drift_window_s=1.0)
        send_all(h, probe, stamps, volts, expect=n)
        forces = np.array([w.wrench.force.z for w in probe.sample_wrenches()])
    if tracking:
        assert node.counts["drift_corrections"] >= 10
        assert np.abs(forces).max() < 0.05 + 1e-9
    else:
        assert node.counts["drift_corrections"] == 0
        assert forces[-1] > 0.1  # 30 mV of drift reads as force


def test_sensor_serial_of_the_model_against_the_live_device(tmp_path):
    """The driver's latched sensor_serial against the model's provenance: a different sensor is a WARN, or zero
    force and ERROR with require_matching_sensor, which also refuses an unknown serial; the right one is OK."""
    from std_msgs.msg import String

    from polyforce_ros.nodes.common import latched_qos

    path = tmp_path / "pf_a.yaml"
    save_model(path, SensorModel(SensorChain.from_model(PAPER_BURGERS), {"sensor_serial": "PF-A"}))
    unnamed = tmp_path / "unnamed.yaml"
    save_model(unnamed, SensorModel(SensorChain.from_model(PAPER_BURGERS)))
    stamps = iter(T0_NS + np.arange(1000) * 1_000_000)

    def forces(h, probe, n=20):
        start_at = len(probe.sample_wrenches())
        send_all(h, probe, [next(stamps) for _ in range(n)], [0.31] * n, expect=start_at + n)
        return [w.wrench.force.z for w in probe.sample_wrenches()[start_at:]]

    with ros() as h:
        node, probe = start(h, stale_timeout_s=30.0, model_file=str(path))
        serial = probe.create_publisher(String, "sensor_serial", latched_qos())
        assert node.model_serial == "PF-A" and node.live_serial is None
        assert min(forces(h, probe)) > 1.0  # no serial known, nothing required: force flows
        serial.publish(String(data="PF-B"))
        assert h.spin_until(lambda: node.live_serial == "PF-B", 5.0)
        status = node._publish_diagnostics()
        assert status.level == DiagnosticStatus.WARN and "'PF-B' is not the one the model was calibrated on ('PF-A')" \
            in status.message
        assert min(forces(h, probe)) > 1.0  # a warning only
        assert node.set_parameters([Parameter("require_matching_sensor", value=True)])[0].successful
        assert forces(h, probe) == [0.0] * 20
        status = node._publish_diagnostics()
        assert status.level == DiagnosticStatus.ERROR and "zero force (require_matching_sensor)" in status.message
        values = {kv.key: kv.value for kv in status.values}
        assert (values["sensor_serial"], values["model_sensor_serial"], values["sensor_check"]) == ("PF-B", "PF-A",
                                                                                                    "mismatch")
        serial.publish(String(data="PF-A"))  # the right sensor is plugged in
        assert h.spin_until(lambda: node.live_serial == "PF-A", 5.0)
        assert min(forces(h, probe)) > 1.0
        assert node._publish_diagnostics().level == DiagnosticStatus.OK
        # a model that names no sensor cannot be matched: refused while required
        assert node.set_parameters([Parameter("model_file", value=str(unnamed))])[0].successful
        assert forces(h, probe) == [0.0] * 20
        assert "the model names no sensor serial" in node._publish_diagnostics().message
        assert node.set_parameters([Parameter("require_matching_sensor", value=False)])[0].successful
        assert min(forces(h, probe)) > 1.0
        assert node._publish_diagnostics().level == DiagnosticStatus.OK


@pytest.mark.parametrize("apply", [False, True])
def test_a_models_time_drift_is_left_out_unless_apply_time_drifts(tmp_path, apply, monkeypatch):
    """A step drift of 50 mV at 0.1 s: left out by default (a zero that never moves reads as zero force, and the
    log warns that it is left out), the node's own parameter applies it (the step reads as force, and the log says
    so)."""
    from polyforce_ros.physics.chain import OffsetElement, StepDriftElement, ViscoelasticElement

    path = tmp_path / "drift.yaml"
    save_model(path, SensorModel(SensorChain([ViscoelasticElement(PAPER_BURGERS), StepDriftElement([0.1], [0.05]),
                                              OffsetElement(0.0)])))
    from rclpy.impl.rcutils_logger import RcutilsLogger

    logged = []

    def recording(severity):  # the messages as the node logs them, whatever the console's format or stream
        def record(self, message, **kwargs):
            logged.append((severity, str(message)))
            return True
        return record

    for severity in ("warning", "info"):
        monkeypatch.setattr(RcutilsLogger, severity, recording(severity))
    n = 300
    with ros() as h:
        node, probe = start(h, stale_timeout_s=30.0, model_file=str(path), apply_time_drifts=apply)
        send_all(h, probe, T0_NS + np.arange(n) * 1_000_000, np.zeros(n), expect=n)
        forces = np.array([w.wrench.force.z for w in probe.sample_wrenches()])
    assert node.compensator.time_drifts_left_out == (() if apply else ("step_drift",))
    assert any(sev == "warning" and "the model's time drifts are left out (step_drift)" in msg
               for sev, msg in logged) is not apply
    assert any(sev == "info" and "applying the model's time drifts (step_drift)" in msg for sev, msg in logged) is apply
    if apply:
        assert forces[-1] < -0.1  # N: the record's jump, subtracted from a zero that never moved
    else:
        assert np.abs(forces).max() < 1e-9
