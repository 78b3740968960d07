"""The bad-input matrix (docs/bad-input.md): every case has a defined behaviour and a clear message,
no node crashes, nothing non-finite or out of range reaches `wrench`, a good model file is never lost."""
import math
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
import yaml
from rclpy.parameter import Parameter

from conftest import REPO
from polyforce_ros import bags
from polyforce_ros.model_file import default_model_path, load_model, model_to_mapping
from polyforce_ros.nodes.common import stamp_to_ns
from polyforce_ros.sim.recording import simulate_bag
from ros_harness import ros
from node_support import T0_NS, send_all, start

MS = 1_000_000
# case -> (samples after one good sample at T0, counter that must count it, good samples published)
NODE_CASES = {
    "nan": ([(T0_NS + 1 * MS, float("nan"))], "nonfinite"),
    "+inf": ([(T0_NS + 1 * MS, float("inf"))], "nonfinite"),
    "-inf": ([(T0_NS + 1 * MS, -float("inf"))], "nonfinite"),
    "1e12 V": ([(T0_NS + 1 * MS, 1e12)], "out_of_range"),
    "stamp going backwards": ([(T0_NS - 5 * MS, 0.2)], "backwards"),
    "duplicate stamp": ([(T0_NS, 0.3)], "duplicate"),
    "10 s gap": ([(T0_NS + 10_000 * MS, 0.2)], "gaps"),
}


@pytest.mark.parametrize("case", list(NODE_CASES))
def test_node_input_matrix(case):
    bad, counter = NODE_CASES[case]
    last = max(s for s, _ in bad + [(T0_NS, 0)])
    sequence = [(T0_NS, 0.2)] + bad + [(last + 1 * MS, 0.2)]  # the node must go on after the bad sample
    with ros() as h:
        # the 10 s gap is sent without waiting 10 s: the stamp plausibility check must allow that much
        node, probe = start(h, stale_timeout_s=60.0, stamp_tolerance_s=30.0)
        send_all(h, probe, [s for s, _ in sequence], [v for _, v in sequence], expect=2)
        h.spin_for(0.1)
        got = probe.sample_wrenches()
    assert node.counts[counter] == 1
    forces = [w.wrench.force.z for w in got]
    assert all(math.isfinite(f) and abs(f) <= 12.0 for f in forces)
    expected = 3 if case == "10 s gap" else 2  # a gap sample is used (and counted), the others dropped
    assert len(forces) == expected
    assert stamp_to_ns(got[-1].header.stamp) == last + 1 * MS


def polyforce(*args, timeout=120):
    return subprocess.run([sys.executable, "-m", "polyforce_ros.cli", *args], cwd=REPO, capture_output=True, text=True,
                          timeout=timeout)


@pytest.fixture(scope="module")
def good_bag(tmp_path_factory):
    return simulate_bag(tmp_path_factory.mktemp("bad") / "good.mcap", "creep", rate_hz=200.0, hold_s=40.0, rest_s=20.0)


def make_bag_case(case, good_bag, tmp):
    raw = good_bag.read_bytes()
    path = tmp / f"{case.replace(' ', '_')}.mcap"
    if case == "empty bag":
        with bags.BagWriter(path):
            pass
    elif case == "missing topic":
        with bags.BagWriter(path) as w:
            w.write_series(bags.BRIDGE_VOLTAGE, bags.JOINT_STATE, [1, 2, 3], [0.0, 0.1, 0.2])
    elif case == "wrong message type":
        with bags.BagWriter(path) as w:
            w.write_series(bags.BRIDGE_VOLTAGE, bags.WRENCH_STAMPED, [1, 2, 3], [0.0, 0.1, 0.2])
            w.write_series(bags.REFERENCE_FORCE, bags.WRENCH_STAMPED, [1, 2, 3], [0.0, 0.1, 0.2])
    elif case.startswith("truncated"):
        path.write_bytes(raw[: int(len(raw) * float(case.split()[-1]))])
    elif case == "corrupt chunk":
        from mcap.reader import make_reader

        with open(good_bag, "rb") as fh:
            chunk = make_reader(fh).get_summary().chunk_indexes[1]
        data = bytearray(raw)
        mid = chunk.chunk_start_offset + chunk.chunk_length // 2
        data[mid : mid + 64] = bytes(64)
        path.write_bytes(bytes(data))
    elif case == "not an mcap file":
        path.write_text("hello")
    return path


BAG_CASES = ["empty bag", "missing topic", "wrong message type", "truncated at 0.1", "truncated at 0.5",
             "truncated at 0.9", "corrupt chunk", "not an mcap file"]


@pytest.mark.parametrize("case", BAG_CASES)
def test_bag_matrix_gives_clear_errors_or_warnings(case, good_bag, tmp_path):
    path = make_bag_case(case, good_bag, tmp_path)
    model = tmp_path / "model.yaml"
    model.write_text((REPO / "config" / "paper_burgers.yaml").read_text())
    before = model.read_text()
    for args in (["compensate", str(path), str(tmp_path / "out.mcap")],
                 ["calibrate", str(path), "--output", str(model)],
                 ["diagnose", str(path), "--base", "burgers"]):
        proc = polyforce(*args)
        assert "Traceback" not in proc.stderr, (args, proc.stderr)
        assert proc.returncode in (0, 2, 3), (args, proc.returncode, proc.stderr)
        if proc.returncode == 2:
            assert "error:" in proc.stderr and len(proc.stderr.strip().splitlines()) <= 3, proc.stderr
    if case in ("truncated at 0.5", "truncated at 0.9", "corrupt chunk"):
        # enough is left to read: the damage is reported, what came before is kept
        data = bags.read_bag(path, topics=[bags.BRIDGE_VOLTAGE])
        assert data.warnings and len(data[bags.BRIDGE_VOLTAGE]) > 0
    assert model.read_text() == before or load_model(model).chain.viscoelastic is not None


YAML_CASES = {
    "zero stiffness": (lambda d: d["elements"][0].update(k1_n_per_v=0), "k1_n_per_v must be > 0"),
    "negative stiffness": (lambda d: d["elements"][0].update(k2_n_per_v=-1.0), "k2_n_per_v must be > 0"),
    "missing key": (lambda d: d["elements"][0].pop("eta2_n_s_per_v"), "missing keys"),
    "non-number": (lambda d: d["elements"][0].update(eta1_n_s_per_v="lots"), "must be a number"),
    "unknown key": (lambda d: d["elements"][0].update(colour="blue"), "unknown keys"),
    # valid values, but the exact inverse of an 11.7 ms lag turns 1 mV of noise into ~0.1 N at 1 kHz
    "unbounded lag inverse": (lambda d: d["elements"].insert(1, {"type": "sensor_lag", "tau_s": 0.0117}),
                              "above max_noise_gain"),
}


@pytest.mark.parametrize("case", list(YAML_CASES))
def test_yaml_matrix_is_refused_with_the_reason(case, good_bag, tmp_path):
    mutate, message = YAML_CASES[case]
    data = model_to_mapping(load_model(default_model_path()))
    mutate(data)
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(data))
    proc = polyforce("compensate", str(good_bag), str(tmp_path / "out.mcap"), "--model", str(bad))
    assert proc.returncode == 2 and message in proc.stderr and "Traceback" not in proc.stderr
    with ros() as h:  # a running node refuses it and keeps its model
        node, _ = start(h, stale_timeout_s=60.0)
        result = node.set_parameters([Parameter("model_file", value=str(bad))])[0]
        assert not result.successful and message in result.reason
        assert node.model.chain.viscoelastic is not None


def test_calibration_killed_while_writing_never_loses_the_model(tmp_path):
    """SIGKILL a process that rewrites the model file in a loop: the file always loads, at any instant."""
    path = tmp_path / "model.yaml"
    from polyforce_ros.model_file import save_model

    save_model(path, load_model(default_model_path()))  # the good file that must survive
    writer = (
        "import sys\n"
        "from polyforce_ros.model_file import default_model_path, load_model, save_model\n"
        "m = load_model(default_model_path())\n"
        "m.provenance = {'padding': 'x' * 300_000}\n"  # a large file makes every write take a while
        "while True:\n"
        "    save_model(sys.argv[1], m)\n"
    )
    (tmp_path / "w.py").write_text(writer)
    rng = np.random.default_rng(0)
    for _ in range(8):
        proc = subprocess.Popen([sys.executable, str(tmp_path / "w.py"), str(path)], cwd=REPO)
        time.sleep(0.3 + rng.uniform(0, 0.4))
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
        assert load_model(path).chain.viscoelastic is not None  # complete, valid, never half-written
