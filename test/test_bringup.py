"""`polyforce bringup`: the launch file's bring-up as processes, for PyPI installs.

End to end: bringup starts the nodes, a subscriber here sees wrench and the
haptic command flowing, SIGINT to bringup stops every child (last zero wrench
and zero command seen), exit 0. Plus: the plan (parameter files, overrides,
namespace), a child that dies stops the rest, and SIGKILL after the timeout.
"""
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import WrenchStamped
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy

from conftest import REPO
from polyforce_ros import bringup, contract
from polyforce_ros.nodes.haptic_bridge_node import HAPTIC_COMMAND
from ros_harness import ros

BIN = Path(sys.executable).parent


def gone(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    return False


def test_plan_merges_config_files_with_overrides_in_start_order(tmp_path):
    model = tmp_path / "model.yaml"
    model.write_text((REPO / "config" / "paper_burgers.yaml").read_text())
    specs = bringup.plan(tmp_path, backend="serial", port="/dev/ttyUSB7", model=model, with_bridge=True,
                         record=tmp_path / "run.mcap", config=REPO / "config")
    assert [s.name for s in specs] == ["recorder_node", "haptic_bridge_node", "compensation_node", "driver_node"]
    for spec in specs:
        (fqn, section), = yaml.safe_load(spec.params_file.read_text()).items()
        assert fqn == f"{contract.NAMESPACE}/{spec.name}"
        params = section["ros__parameters"]
        if spec.name in bringup.PARAM_FILES:
            shipped = bringup.load_params(REPO / "config" / bringup.PARAM_FILES[spec.name])
            assert params == dict(shipped, **spec.overrides)
        assert spec.argv[-4:] == ["-r", f"__ns:={contract.NAMESPACE}", "--params-file", str(spec.params_file)]
        assert Path(spec.argv[0]).name in (spec.name, Path(sys.executable).name)
    by_name = {s.name: s for s in specs}
    # the simulated profile waits for both readers of bridge_voltage (compensation and recorder)
    assert by_name["driver_node"].overrides == {"backend": "serial", "port": "/dev/ttyUSB7", "wait_for_subscribers": 2}
    assert by_name["compensation_node"].overrides == {"model_file": str(model.resolve())}
    assert by_name["recorder_node"].overrides == {"bag_path": str(tmp_path / "run.mcap")}
    # another namespace: the same parameters under the node's name there
    (tmp_path / "left").mkdir()
    other = bringup.plan(tmp_path / "left", namespace="left/")
    assert [s.name for s in other] == ["compensation_node", "driver_node"]
    assert set(yaml.safe_load(other[0].params_file.read_text())) == {"/left/compensation_node"}
    with pytest.raises(ValueError):
        bringup.plan(tmp_path, backend="usb")
    with pytest.raises(FileNotFoundError):
        bringup.plan(tmp_path, model=tmp_path / "missing.yaml")


def test_cli_dry_run_prints_the_plan():
    out = subprocess.run([str(BIN / "polyforce"), "bringup", "--dry-run", "--with-bridge", "--backend", "sim"],
                         capture_output=True, text=True, timeout=60, check=True).stdout
    for name in ("haptic_bridge_node", "compensation_node", "driver_node"):
        assert f"{name}: " in out
    assert "backend=sim" in out and "recorder_node" not in out


def started_pids(log_path):
    return {m[1]: int(m[2]) for m in re.finditer(r"started (\w+) \(pid (\d+)\)", log_path.read_text())}


def test_bringup_runs_the_pipeline_and_sigint_stops_every_child(tmp_path):
    bag = tmp_path / "run.mcap"
    log = tmp_path / "bringup.log"
    with ros() as h, open(log, "w") as log_file:
        sink = h.add(Node("bringup_sink", namespace=contract.NAMESPACE, context=h.context))
        qos = QoSProfile(depth=10000, reliability=ReliabilityPolicy.RELIABLE)
        wrenches, commands = [], []
        sink.create_subscription(WrenchStamped, contract.Rel.WRENCH, wrenches.append, qos)
        sink.create_subscription(WrenchStamped, HAPTIC_COMMAND, commands.append, qos)
        recorded = {}  # the recorder's message counts per topic, from its diagnostics

        def on_diagnostics(msg):
            for status in msg.status:
                if status.name == "polyforce_ros: recorder":
                    recorded.update({kv.key: int(kv.value) for kv in status.values if kv.value.isdigit()})

        sink.create_subscription(DiagnosticArray, contract.DIAGNOSTICS, on_diagnostics, 10)
        proc = subprocess.Popen([str(BIN / "polyforce"), "bringup", "--with-bridge", "--record", str(bag)],
                                stdout=log_file, stderr=subprocess.STDOUT)
        pids = {}
        try:
            # the whole chain must flow first: driver -> compensation -> bridge, and the recorder writing
            # (DDS discovery takes seconds, and each node discovers the others on its own)
            flowing = h.spin_until(lambda: len(wrenches) > 500 and len(commands) > 500 and sum(recorded.values()) > 500,
                                   60.0)
            pids = started_pids(log)
            assert flowing, (len(wrenches), len(commands), recorded, proc.poll(), log.read_text()[-3000:])
            assert set(pids) == {"recorder_node", "haptic_bridge_node", "compensation_node", "driver_node"}
            assert all(not gone(pid) for pid in pids.values())
            proc.send_signal(signal.SIGINT)
            deadline = time.monotonic() + 60.0
            while proc.poll() is None and time.monotonic() < deadline:
                h.spin_for(0.05)  # keep receiving: the last zero wrench and zero command arrive while stopping
            assert proc.returncode == 0, log.read_text()[-3000:]
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
            for pid in pids.values():  # never leave an orphan behind, whatever failed
                if not gone(pid):
                    os.kill(pid, signal.SIGKILL)
        h.spin_for(0.5)
    assert all(gone(pid) for pid in pids.values()), pids
    assert wrenches[-1].wrench.force.z == 0.0, "the compensation node's last zero wrench"
    assert commands[-1].wrench.force.x == 0.0, "the haptic bridge's last zero command"
    assert bag.is_file() and bag.stat().st_size > 10_000
    text = log.read_text()
    assert "all nodes stopped" in text and "killed" not in text


def test_a_child_that_dies_stops_the_others(tmp_path):
    bad = tmp_path / "bad_model.yaml"
    bad.write_text("format: not_a_model\n")
    log = tmp_path / "bringup.log"
    with open(log, "w") as log_file:
        proc = subprocess.run([str(BIN / "polyforce"), "bringup", "--model", str(bad)], stdout=log_file,
                              stderr=subprocess.STDOUT, timeout=120)
    pids = started_pids(log)
    try:
        assert proc.returncode == 1, log.read_text()
        assert "compensation_node exited with code" in log.read_text()
        assert set(pids) == {"compensation_node", "driver_node"}
    finally:
        for pid in pids.values():
            if not gone(pid):
                os.kill(pid, signal.SIGKILL)
    assert all(gone(pid) for pid in pids.values())


def test_a_child_that_ignores_sigint_is_killed_after_the_timeout(tmp_path):
    ready, polite_ready = tmp_path / "ready", tmp_path / "polite_ready"
    stubborn = [sys.executable, "-c", "import pathlib, signal, sys, time; signal.signal(signal.SIGINT, signal.SIG_IGN); "
                "pathlib.Path(sys.argv[1]).touch(); time.sleep(60)", str(ready)]
    # each child says when its handler is in place: on a loaded machine a Python child (re-executed by the ROS
    # wheels' bootstrapper) took longer than a fixed wait to start, and the SIGINT it had not yet met killed it
    polite = [sys.executable, "-c", "import pathlib, sys, time\ntry:\n    pathlib.Path(sys.argv[1]).touch()\n"
              "    time.sleep(60)\nexcept KeyboardInterrupt:\n    pass", str(polite_ready)]
    runner = bringup.Bringup([bringup.ChildSpec("stubborn", stubborn, None), bringup.ChildSpec("polite", polite, None)],
                             stop_timeout_s=3.0, log=lambda text: None)  # room for a loaded machine's exit
    # started where SIGINT is ignored (a background job of a script): the children must not inherit the ignoring
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        runner.start()
    finally:
        signal.signal(signal.SIGINT, previous)
    try:
        deadline = time.monotonic() + 60.0
        while not (ready.exists() and polite_ready.exists()) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert ready.exists() and polite_ready.exists(), "the children did not start within 60 s"
        start = time.monotonic()
        codes = runner.stop()
    finally:
        for _, p in runner.procs:
            if p.poll() is None:
                p.kill()
                p.wait()
    assert codes == {"stubborn": -signal.SIGKILL, "polite": 0}
    assert runner.killed == ["stubborn"]
    assert 3.0 <= time.monotonic() - start < 10.0
