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
