"""The physics and simulator import and run without rclpy (ARCHITECTURE: ROS-free core)."""
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_no_rclpy_import_in_core_sources():
    for folder in ("physics", "sim", "runtime"):
        for path in (ROOT / "polyforce_ros" / folder).rglob("*.py"):
            assert not re.search(r"^\s*(import|from)\s+rclpy", path.read_text(), re.M), path


def test_core_imports_and_runs_with_rclpy_blocked():
    code = (
        "import sys; sys.modules['rclpy'] = None\n"
        "import numpy as np\n"
        "from polyforce_ros.physics import viscoelastic, identification, chain, metrics, expconv\n"
        "from polyforce_ros.sim import profiles, sensor\n"
        "from polyforce_ros import contract\n"
        "from polyforce_ros.runtime import Compensator\n"
        "t, f = profiles.step(rate_hz=100.0)\n"
        "v = sensor.BridgeSimulator(noise_std_v=0.0, adc_bits=0, offset_v=0.0).simulate(t, f)\n"
        "assert abs(viscoelastic.compensate(viscoelastic.PAPER_BURGERS, t, v) - f).max() < 1e-6\n"
        "used, force = Compensator(chain.SensorChain.from_model(viscoelastic.PAPER_BURGERS)).run((t * 1e9).astype(np.int64), v)\n"
        "assert used.all() and abs(force - f).max() < 1e-6\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, cwd=ROOT)
