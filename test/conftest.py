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


import shutil  # noqa: E402
import subprocess  # noqa: E402

import pytest  # noqa: E402

_SKIP = shutil.ignore_patterns(".venv", ".git", "build", "install", "log", "__pycache__", "*.egg-info", ".pytest_cache", ".hypothesis", "out")


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


