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


ROOT = Path(__file__).resolve().parents[1]
#: Every console entry point of setup.py; nodes are added here as they land.
EXECUTABLES = ["polyforce", "driver_node", "compensation_node", "compensation_lifecycle_node", "driver_lifecycle_node",
               "calibration_node", "replay_node", "recorder_node", "haptic_bridge_node"]


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
    out = subprocess.run([str(exe), "simulate", "--profile", "step"], env=env, cwd="/", capture_output=True, text=True,
                         check=True).stdout
    assert str(prefix / "share" / "polyforce_ros" / "config" / "paper_burgers.yaml") in out


def test_launch_file_urdf_and_layouts_are_installed_with_everything_they_name(colcon_install, tmp_path):
    """`ros2 launch polyforce_ros polyforce.launch.py` needs the file in share/.../launch and what it names."""
    import ast

    env, prefix = install_env(colcon_install)
    share = prefix / "share" / "polyforce_ros"
    launch_file = share / "launch" / "polyforce.launch.py"
    assert launch_file.is_file()
    tree = ast.parse(launch_file.read_text())
    # the launch file starts bringup's node set, with a parameter set keyed by each executable
    executables = {k.value for n in ast.walk(tree) if isinstance(n, ast.Dict) and n.keys
                   for k in n.keys if isinstance(k, ast.Constant) and str(k.value).endswith("_node")}
    assert executables == {"driver_node", "compensation_node", "haptic_bridge_node", "recorder_node"}
    for exe in executables:
        path = prefix / "lib" / "polyforce_ros" / exe
        assert path.is_file() and os.access(path, os.X_OK), path
    yamls = {n.value for n in ast.walk(tree)
             if isinstance(n, ast.Constant) and isinstance(n.value, str) and n.value.endswith(".yaml")}
    assert yamls and all((share / "config" / name).is_file() for name in yamls), yamls
    for layout in ("polyforce.foxglove.json", "polyforce.plotjuggler.xml"):
        assert (share / "config" / layout).is_file(), layout
    # the installed xacro, found the way a user's robot description finds it: $(find polyforce_ros)
    wrapper = tmp_path / "tool.urdf.xacro"
    wrapper.write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="tool">'
        '<xacro:include filename="$(find polyforce_ros)/urdf/polyforce_sensor.urdf.xacro"/>'
        '<link name="holder"/><xacro:polyforce_sensor parent="holder"><origin xyz="0 0 0" rpy="0 0 0"/></xacro:polyforce_sensor>'
        "</robot>")
    urdf = subprocess.run([str(Path(sys.executable).parent / "xacro"), str(wrapper)], env=env, cwd="/",
                          capture_output=True, text=True, check=True).stdout
    from urdf_parser_py.urdf import URDF

    from polyforce_ros import contract

    robot = URDF.from_xml_string(urdf)
    assert contract.FRAME_ID in {link.name for link in robot.links}
    assert contract.JOINT_NAME in {joint.name for joint in robot.joints}


def test_readme_colcon_build_packages_select_command(tmp_path):
    """The README's command, verbatim, in a fresh workspace (needs colcon-package-selection)."""
    from conftest import _SKIP

    shutil.copytree(ROOT, tmp_path / "src" / "polyforce_ros", ignore=_SKIP)
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    proc = subprocess.run("colcon build --packages-select polyforce_ros", shell=True, cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "Finished <<< polyforce_ros" in proc.stdout, proc.stdout
    lib = tmp_path / "install" / "polyforce_ros" / "lib" / "polyforce_ros"
    assert all((lib / exe).is_file() for exe in EXECUTABLES)
    assert (tmp_path / "install" / "polyforce_ros" / "share" / "polyforce_ros" / "launch" / "polyforce.launch.py").is_file()
