"""Bring up the polyforce sensor: driver + compensation, optionally the haptic bridge and a recorder.

    ros2 launch polyforce_ros polyforce.launch.py
    ros2 launch polyforce_ros polyforce.launch.py backend:=serial port:=/dev/ttyACM0 model_file:=$HOME/sensor.yaml
    ros2 launch polyforce_ros polyforce.launch.py with_bridge:=true record:=/tmp/run1.mcap namespace:=/left

Parameters come from the shipped files in share/polyforce_ros/config (driver.yaml,
compensation.yaml, haptic_bridge.yaml), or from the files given as *_params
arguments, with the launch arguments applied on top. The files' sections are
passed as parameter dictionaries, so they apply under any namespace.
``polyforce bringup`` does the same without ROS launch (PyPI installs).
"""
from pathlib import Path

import yaml
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, OpaqueFunction
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node

from polyforce_ros import contract
from polyforce_ros.bringup import driver_waits_for, node_set

PACKAGE = "polyforce_ros"
#: share/polyforce_ros/config next to share/polyforce_ros/launch (also true in the source tree).
CONFIG = Path(__file__).resolve().parent.parent / "config"


def _params(path):
    """The ros__parameters of a node's parameter file (its one section, whatever its node name)."""
    data = yaml.safe_load(Path(path).expanduser().read_text()) or {}
    sections = [v["ros__parameters"] for v in data.values() if isinstance(v, dict) and "ros__parameters" in v]
    if len(sections) != 1:
        raise RuntimeError(f"{path}: expected one node section with ros__parameters, found {len(sections)}")
    return sections[0]


def _nodes(context):
    arg = lambda name: LaunchConfiguration(name).perform(context)  # noqa: E731
    namespace = arg("namespace")
    driver = _params(arg("driver_params"))
    if arg("backend") not in ("", "sim", "serial"):
        raise RuntimeError(f"backend must be sim or serial, got {arg('backend')!r}")
    driver = dict(driver, **{name: arg(name) for name in ("backend", "port") if arg(name)})
    compensation = _params(arg("compensation_params"))
    if arg("model_file"):
        compensation = dict(compensation, model_file=str(Path(arg("model_file")).expanduser().resolve()))
    names = node_set(with_bridge=arg("with_bridge").lower() in ("true", "1", "yes"), record=bool(arg("record")))
    params = {
        "recorder_node": {"bag_path": str(Path(arg("record")).expanduser().resolve())} if arg("record") else {},
        "haptic_bridge_node": _params(arg("bridge_params")) if "haptic_bridge_node" in names else {},
        "compensation_node": compensation,
        "driver_node": dict(driver, wait_for_subscribers=driver_waits_for(names)),
    }
    # in bringup's start order (the recorder first, so it records the compensation node's last zero wrench)
    nodes = [Node(package=PACKAGE, executable=name, namespace=namespace, output="screen", parameters=[params[name]])
             for name in names]
    return nodes


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument("backend", default_value="",
                              description="Driver data source: sim (embedded simulator) or serial (ADC); empty = driver_params"),
        DeclareLaunchArgument("port", default_value="",
                              description="Serial device of the ADC (backend serial); empty = driver_params"),
        DeclareLaunchArgument("model_file", default_value="",
                              description="Sensor model YAML for the compensation node; "
                                          "empty = model_file of compensation_params"),
        DeclareLaunchArgument("namespace", default_value=contract.NAMESPACE, description="Namespace of every node"),
        DeclareLaunchArgument("with_bridge", default_value="false", choices=["true", "false"],
                              description="Also start haptic_bridge_node (wrench -> haptic master command)"),
        DeclareLaunchArgument("record", default_value="",
                              description="Record the topic contract to this .mcap file; empty = off"),
        DeclareLaunchArgument("driver_params", default_value=str(CONFIG / "driver.yaml"),
                              description="Parameter file of driver_node"),
        DeclareLaunchArgument("compensation_params", default_value=str(CONFIG / "compensation.yaml"),
                              description="Parameter file of compensation_node"),
        DeclareLaunchArgument("bridge_params", default_value=str(CONFIG / "haptic_bridge.yaml"),
                              description="Parameter file of haptic_bridge_node"),
        OpaqueFunction(function=_nodes),
    ])
