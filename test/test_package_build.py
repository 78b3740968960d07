"""colcon builds the package like a ROS user's workspace would, and `ros2 run` can find it.

ros2cli is not on PyPI, so `ros2 run polyforce_ros X` is checked by what it
relies on: the ament index resolving the package and an executable X under
install/polyforce_ros/lib/polyforce_ros/.
"""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: Every console entry point of setup.py; nodes are added here as they land.
EXECUTABLES = ["polyforce", "driver_node", "compensation_node", "calibration_node", "replay_node", "recorder_node"]


def test_every_entry_point_is_installed_where_ros2_run_looks(colcon_install):
    setup_text = (ROOT / "setup.py").read_text()
    lib = colcon_install / "polyforce_ros" / "lib" / "polyforce_ros"
    for exe in EXECUTABLES:
        assert f'"{exe} = ' in setup_text, exe
        path = lib / exe
        assert path.is_file() and os.access(path, os.X_OK), path
    declared = {line.split("=")[0].strip().strip('"') for line in setup_text.splitlines() if " = polyforce_ros." in line}
    assert declared == set(EXECUTABLES), "keep EXECUTABLES in step with setup.py"


def install_env(colcon_install):
    prefix = colcon_install / "polyforce_ros"
    site = next(prefix.glob("lib/python3*/site-packages"))
    return dict(
        os.environ,
        AMENT_PREFIX_PATH=f"{prefix}{os.pathsep}{sys.prefix}",
        PYTHONPATH=str(site),
    ), prefix


def test_ament_index_resolves_package_and_shares_config(colcon_install):
    env, prefix = install_env(colcon_install)
    code = (
        "from ament_index_python.packages import get_package_share_directory as g\n"
        "import polyforce_ros, pathlib\n"
        "share = pathlib.Path(g('polyforce_ros'))\n"
        "print(share); print(polyforce_ros.__file__)\n"
        "assert (share / 'package.xml').is_file() and (share / 'config' / 'paper_burgers.yaml').is_file()\n"
    )
    out = subprocess.run([sys.executable, "-c", code], env=env, cwd="/", capture_output=True, text=True, check=True).stdout
    share, module = out.split()
    assert Path(share) == prefix / "share" / "polyforce_ros"
    assert Path(module).is_relative_to(prefix)  # the installed copy, not the source tree


def test_installed_executable_runs_and_finds_shipped_model(colcon_install):
    env, prefix = install_env(colcon_install)
    exe = prefix / "lib" / "polyforce_ros" / "polyforce"
    out = subprocess.run([str(exe), "simulate", "--profile", "step"], env=env, cwd="/", capture_output=True, text=True, check=True).stdout
    assert str(prefix / "share" / "polyforce_ros" / "config" / "paper_burgers.yaml") in out
