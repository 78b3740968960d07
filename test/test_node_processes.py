"""The node executables as a user runs them: separate processes, DDS on loopback, SIGTERM to stop.

Checks `main()` of each node (argument handling, remapping, signals): the
driver feeds the compensation node across processes, and a SIGTERM makes the
compensation node send a last zero wrench and exit 0. Processes that do not
stop are SIGKILLed so no orphan outlives the test.
"""
import os
import sys

import pytest
from geometry_msgs.msg import WrenchStamped
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy

from node_support import BIN, spawn, stop
from ros_harness import ros

def wrench_sink(h, namespace):
    node = h.add(Node("sink", namespace=namespace, context=h.context))
    got = []
    node.create_subscription(WrenchStamped, "wrench", got.append, QoSProfile(depth=10000, reliability=ReliabilityPolicy.RELIABLE))
    return got


def run_pipeline(driver_exe, comp_exe, namespace, env=None):
    procs = []
    try:
        with ros() as h:
            got = wrench_sink(h, namespace)
            procs.append(spawn(comp_exe, "-r", f"__ns:={namespace}", env=env))
            procs.append(spawn(driver_exe, "-r", f"__ns:={namespace}", "-p", "profile:=step", env=env))
            assert h.spin_until(lambda: sum(1 for w in got if w.wrench.force.z > 1.0) > 200, 30.0), (
                "no compensated force across processes", [p.poll() for p in procs])
            assert stop(procs[1]) == 0  # driver
            n = len(got)
            assert stop(procs[0]) == 0  # compensation node: SIGTERM -> zero wrench, exit 0
            assert h.spin_until(lambda: len(got) > n and got[-1].wrench.force.z == 0.0, 5.0)
    finally:
        for p in procs:
            stop(p)
            p.stdout.close()


def test_venv_executables_driver_to_compensation_across_processes():
    run_pipeline(BIN / "driver_node", BIN / "compensation_node", "/pf_venv")


def test_colcon_installed_executables_run(colcon_install):
    prefix = colcon_install / "polyforce_ros"
    site = next(prefix.glob("lib/python3*/site-packages"))
    env = dict(os.environ, AMENT_PREFIX_PATH=f"{prefix}{os.pathsep}{sys.prefix}", PYTHONPATH=str(site))
    lib = prefix / "lib" / "polyforce_ros"
    run_pipeline(lib / "driver_node", lib / "compensation_node", "/pf_colcon", env=env)


def test_bad_parameter_fails_at_start_with_a_clear_message():
    proc = spawn(BIN / "compensation_node", "-p", "model_file:=/nonexistent/model.yaml")
    try:
        out, _ = proc.communicate(timeout=20)
    finally:
        stop(proc)
    assert proc.returncode != 0
    assert "cannot read model file /nonexistent/model.yaml" in out


@pytest.mark.parametrize("args, says", [
    (("-p", "model_file:={bad}"), "outside the allowed range"),
    (("-p", "force_limit_n:=1e9"), "force_limit_n"),
    (("-p", "model_file:={shaky}"), "sensor_lag element multiplies it by"),  # an exact lag inverse: noise x 25
])
def test_a_node_started_with_bad_input_exits_2_with_the_reason(tmp_path, args, says):
    bad, shaky = tmp_path / "bad.yaml", tmp_path / "shaky.yaml"
    bad.write_text("format: polyforce_model/1\nelements:\n- {type: burgers, k1_n_per_v: 1.0e+300, k2_n_per_v: 10.0, "
                   "eta1_n_s_per_v: 4627.94, eta2_n_s_per_v: 85.12}\n")
    shaky.write_text("format: polyforce_model/1\nelements:\n- {type: burgers, k1_n_per_v: 3.23, k2_n_per_v: 10.0, "
                     "eta1_n_s_per_v: 4627.94, eta2_n_s_per_v: 85.12}\n- {type: sensor_lag, tau_s: 0.0117}\n")
    proc = spawn(BIN / "compensation_node", *[a.format(bad=bad, shaky=shaky) for a in args])
    try:
        out, _ = proc.communicate(timeout=60)
    finally:
        stop(proc)
    assert proc.returncode == 2, out
    assert says in out and "Traceback" not in out
