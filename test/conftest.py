"""Test-session environment: DDS stays on loopback in an isolated domain.

Set before any test imports rclpy. The domain id is derived from the process
id so that concurrent runs on one machine do not see each other.
"""
import os
import sys
from pathlib import Path

os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
os.environ["ROS_DOMAIN_ID"] = str(100 + os.getpid() % 100)  # 100..199, away from the default 0
# The ROS wheels do not set AMENT_PREFIX_PATH; message packages live in the venv prefix.
os.environ["AMENT_PREFIX_PATH"] = os.pathsep.join(
    p for p in (sys.prefix, os.environ.get("AMENT_PREFIX_PATH", "")) if p
)

REPO = Path(__file__).resolve().parents[1]

# POLYFORCE_UNIT_GUARD=1 (test_static runs the unit layer so): rclpy cannot be imported and no process can
# be started, so a unit test that needs either fails instead of quietly making the layer ROS-bound.
if os.environ.get("POLYFORCE_UNIT_GUARD"):
    import subprocess as _subprocess

    sys.modules["rclpy"] = None  # type: ignore[assignment]

    def _no_process(*args, **kwargs):
        raise RuntimeError("a unit test may not start a process (mark it @pytest.mark.process)")

    _subprocess.Popen.__init__ = _no_process  # type: ignore[method-assign]


import shutil  # noqa: E402

# Every test file belongs to exactly one layer (pytest -m <layer>); "slow" is added on top.
LAYERS = {
    "unit": ["test_bags.py", "test_bench_bridge.py", "test_bench_stats.py", "test_chain_elements.py", "test_expconv.py",
             "test_identification.py", "test_metrics.py", "test_model_file.py", "test_fitting.py", "test_record.py",
             "test_preisach.py", "test_properties.py", "test_runtime.py", "test_serial_protocol.py", "test_thinfilm.py",
             "test_viscoelastic.py", "test_model_fuzz.py", "test_noise_gain.py", "test_offline_gate.py", "test_probe_startup.py"],
    "ros": ["test_teleop_files.py", "test_compensation_node.py", "test_contract.py", "test_driver_node.py",
            "test_live_attacks.py", "test_param_files.py", "test_replay.py", "test_haptic_bridge.py", "test_lifecycle.py"],
    "process": ["test_bad_input.py", "test_calibration.py", "test_cli_demo.py", "test_discrepancy.py",
                "test_discrepancy_elements.py", "test_discrepancy_pipeline.py",
                "test_discrepancy_newtons.py", "test_evaluate.py", "test_node_processes.py",
                "test_package_build.py", "test_ros_free_physics.py", "test_bag_fuzz.py", "test_bringup.py", "test_firmware.py",
                "test_static.py", "test_cdr.py", "test_bag_conventions.py", "test_layers.py",
                "test_bench_chain.py"],
    "netns": ["test_two_namespaces.py"],
}
SLOW = {"test_discrepancy.py", "test_discrepancy_pipeline.py", "test_discrepancy_newtons.py",
        "test_evaluate.py", "test_package_build.py",
        "test_two_namespaces.py", "test_cli_demo.py", "test_bringup.py", "test_firmware.py", "test_bench_chain.py"}
_LAYER_OF = {name: layer for layer, names in LAYERS.items() for name in names}
import subprocess  # noqa: E402

import pytest  # noqa: E402
from hypothesis import settings as _hypothesis_settings  # noqa: E402

# Property and fuzz tests: derandomised in CI (a red run must mean a regression, not a new draw);
# POLYFORCE_FUZZ=1 explores new random examples, 20x as many, for a longer campaign by hand.
_hypothesis_settings.register_profile("ci", derandomize=True, database=None)
_hypothesis_settings.register_profile("fuzz", derandomize=False, max_examples=2000)
_hypothesis_settings.load_profile("fuzz" if os.environ.get("POLYFORCE_FUZZ") else "ci")

_SKIP = shutil.ignore_patterns(".venv", ".git", "build", "install", "log", "__pycache__", "*.egg-info", ".pytest_cache",
                               ".hypothesis", "out")


@pytest.fixture(scope="session")
def colcon_install(tmp_path_factory):
    ws = tmp_path_factory.mktemp("ws")
    shutil.copytree(REPO, ws / "src" / "polyforce_ros", ignore=_SKIP)
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    colcon = Path(sys.executable).parent / "colcon"
    proc = subprocess.run(
        [str(colcon), "--log-base", "log", "build", "--base-paths", "src"],
        cwd=ws, env=env, capture_output=True, text=True, timeout=300,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return ws / "install"




def pytest_collection_modifyitems(config, items):
    unknown = set()
    for item in items:
        name = item.path.name
        layer = _LAYER_OF.get(name)
        if layer is None:
            unknown.add(name)
            continue
        # a test may name its own layer (a CLI subprocess among unit tests of the same concern)
        own = [m.name for m in item.iter_markers() if m.name in LAYERS]
        if not own:
            item.add_marker(getattr(pytest.mark, layer))
        if name in SLOW:
            item.add_marker(pytest.mark.slow)
    if unknown:
        raise pytest.UsageError(f"test files without a layer in test/conftest.py LAYERS: {sorted(unknown)}")
