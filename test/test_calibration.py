"""Calibration from creep bags: CLI contract, never-worse rule, node services, live recording."""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from rclpy.parameter import Parameter
from std_msgs.msg import String
from std_srvs.srv import Trigger

from polyforce_ros.model_file import load_model
from polyforce_ros.nodes.calibration_node import CalibrationNode
from polyforce_ros.nodes.common import latched_qos
from polyforce_ros.nodes.compensation_node import CompensationNode
from polyforce_ros.nodes.driver_node import DriverNode
from polyforce_ros.physics.viscoelastic import PAPER_BURGERS, Zener
from polyforce_ros.sim.recording import simulate_bag
from polyforce_ros.sim.sensor import BridgeSimulator
from ros_harness import ros

ROOT = Path(__file__).resolve().parents[1]


def polyforce(*args):
    return subprocess.run([sys.executable, "-m", "polyforce_ros.cli", *args], cwd=ROOT, capture_output=True, text=True)


@pytest.fixture(scope="module")
def creep_bags(tmp_path_factory):
    d = tmp_path_factory.mktemp("bags")
    zener = Zener(5.5, 12.0, 60.0)
    return {
        "burgers": simulate_bag(d / "burgers.mcap", "creep", rate_hz=200.0, hold_s=90.0, rest_s=40.0),
        "zener": simulate_bag(d / "zener.mcap", "creep", rate_hz=200.0, simulator=BridgeSimulator(model=zener, seed=2),
                              hold_s=90.0, rest_s=40.0),
        "noisy": simulate_bag(d / "noisy.mcap", "creep", rate_hz=200.0, simulator=BridgeSimulator(noise_std_v=0.05, seed=3),
                              hold_s=90.0, rest_s=40.0),
        "sawtooth": simulate_bag(d / "saw.mcap", "sawtooth", rate_hz=100.0),
    }


def test_cli_calibrate_writes_selected_model(creep_bags, tmp_path):
    out = tmp_path / "model.yaml"
    proc = polyforce("calibrate", str(creep_bags["zener"]), "--output", str(out), "--json", str(tmp_path / "r.json"))
    assert proc.returncode == 0, proc.stderr
    model = load_model(out)
    assert model.chain.viscoelastic.kind == "zener"
    for name, value in Zener(5.5, 12.0, 60.0).as_dict().items():
        assert model.chain.viscoelastic.as_dict()[name] == pytest.approx(value, rel=0.02)
    assert model.chain.offset.voltage_v == pytest.approx(0.05, abs=2e-3)
    assert model.provenance["source"] == str(creep_bags["zener"])
    report = json.loads((tmp_path / "r.json").read_text())
    assert report["written"] and report["fits"][0]["model"] == "zener"


def test_worse_or_failed_fit_never_replaces_a_good_model(creep_bags, tmp_path):
    out = tmp_path / "model.yaml"
    assert polyforce("calibrate", str(creep_bags["burgers"]), "--output", str(out)).returncode == 0
    good = out.read_text()
    # A record the existing model already explains better (50 mV of noise): kept.
    proc = polyforce("calibrate", str(creep_bags["noisy"]), "--output", str(out), "--min-r2", "0.0")
    assert proc.returncode == 3 and "as well or better" in proc.stdout
    assert out.read_text() == good
    # No creep segment: a clear error, file kept.
    proc = polyforce("calibrate", str(creep_bags["sawtooth"]), "--output", str(out))
    assert proc.returncode == 2 and "no creep segment" in proc.stderr
    assert out.read_text() == good
    # Not a bag at all.
    junk = tmp_path / "junk.mcap"
    junk.write_bytes(b"not an mcap file")
    proc = polyforce("calibrate", str(junk), "--output", str(out))
    assert proc.returncode == 2 and "not an MCAP" in proc.stderr
    assert out.read_text() == good
    # A sensor that really changed (Zener, other stiffness) is better explained by the new fit: replaced.
    proc = polyforce("calibrate", str(creep_bags["zener"]), "--output", str(out))
    assert proc.returncode == 0, proc.stdout
    assert load_model(out).chain.viscoelastic.kind == "zener"
    assert (tmp_path / "model.yaml.prev").read_text() == good


def test_cli_calibrate_names_the_sensor_and_a_model_of_another_sensor_is_no_standard(creep_bags, tmp_path):
    out = tmp_path / "model.yaml"
    proc = polyforce("calibrate", str(creep_bags["burgers"]), "--output", str(out), "--sensor-serial", "PF-A",
                     "--json", str(tmp_path / "r.json"))
    assert proc.returncode == 0 and "for sensor PF-A" in proc.stdout, proc.stdout + proc.stderr
    assert load_model(out).provenance["sensor_serial"] == "PF-A"
    assert json.loads((tmp_path / "r.json").read_text())["sensor_serial"] == "PF-A"
    good = out.read_text()
    # the same sensor: the existing model explains the noisy record better and is kept
    proc = polyforce("calibrate", str(creep_bags["noisy"]), "--output", str(out), "--min-r2", "0.0",
                     "--sensor-serial", "PF-A")
    assert proc.returncode == 3 and "as well or better" in proc.stdout and out.read_text() == good
    # another sensor: the model of PF-A says nothing about it, so the fit is written
    proc = polyforce("calibrate", str(creep_bags["noisy"]), "--output", str(out), "--min-r2", "0.0",
                     "--sensor-serial", "PF-B")
    assert proc.returncode == 0 and "in place of the model of sensor PF-A" in proc.stdout, proc.stdout
    assert load_model(out).provenance["sensor_serial"] == "PF-B"
    assert (tmp_path / "model.yaml.prev").read_text() == good


def test_cli_compensate_adds_wrench_stamped_like_raw(creep_bags, tmp_path):
    from polyforce_ros import bags
    from polyforce_ros.physics.viscoelastic import compensate

    out = tmp_path / "out.mcap"
    # compared below with the model's own offset, so without the start-up zeroing
    proc = polyforce("compensate", str(creep_bags["burgers"]), str(out), "--no-auto-tare")
    assert proc.returncode == 0, proc.stderr
    src, dst = bags.read_bag(creep_bags["burgers"]), bags.read_bag(out)
    assert set(dst.types) == set(src.types) | {bags.WRENCH}
    raw, wrench = dst[bags.BRIDGE_VOLTAGE], dst[bags.WRENCH]
    np.testing.assert_array_equal(wrench.stamp_ns, raw.stamp_ns)
    np.testing.assert_array_equal(raw.fields["position"], src[bags.BRIDGE_VOLTAGE].fields["position"])
    t = (raw.stamp_ns - raw.stamp_ns[0]) * 1e-9
    np.testing.assert_allclose(wrench.fields["force_z"], compensate(PAPER_BURGERS, t, raw.fields["position"]), atol=1e-9)
    assert polyforce("compensate", str(out), str(tmp_path / "again.mcap")).returncode == 2  # already has wrench


def test_cli_compensate_leaves_a_models_time_drift_out_with_a_warning_unless_asked(creep_bags, tmp_path):
    from polyforce_ros import bags
    from polyforce_ros.model_file import SensorModel, save_model
    from polyforce_ros.physics.chain import SensorChain, StepDriftElement
    from polyforce_ros.physics.viscoelastic import compensate

    plain = SensorChain.from_model(PAPER_BURGERS, offset_v=0.0)
    model = tmp_path / "drift.yaml"
    save_model(model, SensorModel(SensorChain([*plain.elements, StepDriftElement([1.0], [0.05])])))
    forces = {}
    for flag in ("", "--apply-time-drifts"):
        out = tmp_path / f"out{flag}.mcap"
        proc = polyforce("compensate", str(creep_bags["burgers"]), str(out), "--no-auto-tare", "--model", str(model),
                         *([flag] if flag else []))
        assert proc.returncode == 0, proc.stderr
        assert ("time drifts are left out (step_drift)" in proc.stderr) == (not flag), proc.stderr
        forces[flag] = bags.read_bag(out)[bags.WRENCH].fields["force_z"]
    raw = bags.read_bag(creep_bags["burgers"])[bags.BRIDGE_VOLTAGE]
    t = (raw.stamp_ns - raw.stamp_ns[0]) * 1e-9
    np.testing.assert_allclose(forces[""], compensate(PAPER_BURGERS, t, raw.fields["position"]), atol=1e-9)
    assert np.abs(forces["--apply-time-drifts"] - forces[""])[t > 1.5].min() > 0.1  # N: 50 mV at ~4.8 N/V, and more


def test_cli_compensate_judges_the_noise_gain_of_the_chain_it_runs(creep_bags, tmp_path):
    # a drift moves a nonlinear gain's working point: with it the inverse passes noise at ~24 N/V, without it (as
    # compensate runs by default) at 4.8 N/V; a limit of 10 refuses the model only when the drift is applied
    from polyforce_ros.model_file import SensorModel, save_model
    from polyforce_ros.physics.chain import (OffsetElement, PolynomialGainElement, SensorChain, StepDriftElement,
                                             ViscoelasticElement)

    model = tmp_path / "drift.yaml"
    save_model(model, SensorModel(SensorChain([
        ViscoelasticElement(PAPER_BURGERS), PolynomialGainElement(quadratic_per_v=0.3, cubic_per_v2=0.0, quartic_per_v3=0.0),
        OffsetElement(0.0), StepDriftElement([0.001], [0.8])])))
    for flag, code in (("", 0), ("--apply-time-drifts", 2)):
        proc = polyforce("compensate", str(creep_bags["burgers"]), str(tmp_path / f"out{flag}.mcap"), "--model",
                         str(model), *([flag] if flag else []))
        assert proc.returncode == code, proc.stderr
        assert ("above max_noise_gain" in proc.stderr) == bool(code), proc.stderr


def test_calibration_node_service_then_compensation_node_loads_it(creep_bags, tmp_path):
    out = tmp_path / "node_model.yaml"
    with ros() as h:
        node = h.add(CalibrationNode(context=h.context, parameter_overrides=[
            Parameter("bag_path", value=str(creep_bags["zener"])), Parameter("output_path", value=str(out))]))
        client = node.create_client(Trigger, "calibration_node/calibrate")
        results = []
        node.create_subscription(String, "calibration_node/result", results.append, 1)
        response = h.call(client, Trigger.Request(), timeout=30.0)
        assert response.success and "zener written" in response.message
        assert h.spin_until(lambda: results, 5.0)
        assert json.loads(results[-1].data)["fits"][0]["model"] == "zener"
        comp = h.add(CompensationNode(context=h.context, parameter_overrides=[Parameter("model_file", value=str(out))]))
        assert comp.model.chain.viscoelastic.kind == "zener"
        # A failing request is answered, not crashed on.
        node.set_parameters([Parameter("bag_path", value=str(tmp_path / "missing.mcap"))])
        failed = h.call(client, Trigger.Request())
        assert not failed.success and "cannot read bag" in failed.message


def test_live_recording_of_a_creep_experiment(tmp_path):
    out = tmp_path / "live.yaml"
    with ros() as h:
        cal = h.add(CalibrationNode(context=h.context, parameter_overrides=[Parameter("output_path", value=str(out))]))
        # the serial a serial-backend driver announces (latched): the recorded sensor's, named in the model
        serial = cal.create_publisher(String, "sensor_serial", latched_qos())
        serial.publish(String(data="PF-LIVE-9"))
        assert h.spin_until(lambda: cal.live_serial == "PF-LIVE-9", 5.0)
        start = cal.create_client(Trigger, "calibration_node/start_recording")
        stop = cal.create_client(Trigger, "calibration_node/stop_and_fit")
        assert h.call(start, Trigger.Request()).success
        h.add(DriverNode(context=h.context, parameter_overrides=[
            Parameter("profile", value="step"), Parameter("noise_std_v", value=2e-4)]))
        h.spin_for(8.5)  # 2 s unloaded, then the 5 N step held for 6.5 s
        response = h.call(stop, Trigger.Request(), timeout=30.0)
    assert response.success, response.message
    assert load_model(out).chain.viscoelastic.kind in ("burgers", "zener")
    assert load_model(out).chain.viscoelastic.as_dict()["k1_n_per_v"] == pytest.approx(4.8, rel=0.02)
    assert load_model(out).provenance["sensor_serial"] == "PF-LIVE-9"
