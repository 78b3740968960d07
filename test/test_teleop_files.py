"""The teleop-stack files: launch file, sensor xacro, Foxglove and PlotJuggler layouts. No DDS.

`launch`/`launch_ros` are not on PyPI, so the launch file is checked by its
AST (every executable and parameter file it names exists) and by running its
generate_launch_description() against minimal stand-ins of the launch API.
The xacro is expanded with the real xacro (PyPI) and parsed with urdf-parser-py.
Layouts must reference contract topics and fields that exist in the message types.
"""
import ast
import importlib.util
import json
import re
import sys
import types
import xml.etree.ElementTree as ET

import pytest
import xacro
import yaml
from urdf_parser_py.urdf import URDF

from conftest import REPO
from polyforce_ros import contract
from polyforce_ros.nodes.common import message_class
from polyforce_ros.nodes.haptic_bridge_node import HAPTIC_COMMAND

LAUNCH = REPO / "launch" / "polyforce.launch.py"
XACRO = REPO / "urdf" / "polyforce_sensor.urdf.xacro"
FOXGLOVE = REPO / "config" / "polyforce.foxglove.json"
PLOTJUGGLER = REPO / "config" / "polyforce.plotjuggler.xml"
NODES = {"driver_node", "compensation_node", "haptic_bridge_node", "recorder_node"}


def entry_points():
    setup_text = (REPO / "setup.py").read_text()
    return {m for m in re.findall(r'"(\w+) = polyforce_ros\.', setup_text)}


# ---------------------------------------------------------------------- launch file
def test_launch_file_names_only_existing_executables_and_parameter_files():
    tree = ast.parse(LAUNCH.read_text())
    functions = {n.name for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)}
    assert "generate_launch_description" in functions
    from polyforce_ros.bringup import node_set

    # the launch file starts bringup's node set (one description of it) with a parameter set for each
    executables, packages = set(), set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "Node":
            kw = {k.arg: k.value for k in node.keywords}
            packages.add(kw["package"].id if isinstance(kw["package"], ast.Name) else ast.literal_eval(kw["package"]))
        if isinstance(node, ast.Dict) and all(isinstance(k, ast.Constant) and str(k.value).endswith("_node")
                                              for k in node.keys if k is not None) and node.keys:
            executables |= {k.value for k in node.keys}
    assert executables == set(node_set(with_bridge=True, record=True)) == NODES
    assert executables <= entry_points() and packages == {"PACKAGE"}
    yamls = {n.value for n in ast.walk(tree)
             if isinstance(n, ast.Constant) and isinstance(n.value, str) and n.value.endswith(".yaml")}
    assert yamls == {"driver.yaml", "compensation.yaml", "haptic_bridge.yaml"}
    for name in yamls:
        assert (REPO / "config" / name).is_file(), name
    # installed next to config/: setup.py ships launch/ and urdf/ to share/polyforce_ros
    setup_text = (REPO / "setup.py").read_text()
    assert 'f"share/{PACKAGE}/launch"' in setup_text and 'f"share/{PACKAGE}/urdf"' in setup_text


class _Recorded:
    def __init__(self, *args, **kwargs):
        self.args, self.kwargs = args, kwargs


def fake_launch_modules():
    """Stand-ins for the parts of launch / launch_ros the file uses, with their real signatures' keywords."""

    class LaunchConfiguration:
        def __init__(self, name):
            self.name = name

        def perform(self, context):
            return context.launch_configurations[self.name]

    class DeclareLaunchArgument(_Recorded):
        def __init__(self, name, *, default_value=None, description="", choices=None):
            super().__init__(name, default_value=default_value, description=description, choices=choices)
            self.name, self.default_value, self.choices = name, default_value, choices
            if choices is not None and default_value not in choices:
                raise ValueError(f"default of {name} not in its choices")

    class OpaqueFunction(_Recorded):
        def __init__(self, *, function, args=None, kwargs=None):
            super().__init__(function=function)
            self.function = function

    class LaunchDescription(list):
        pass

    class Node(_Recorded):
        def __init__(self, *, executable, package=None, name=None, namespace=None, parameters=None, remappings=None,
                     arguments=None, output="log", **kwargs):
            super().__init__(executable=executable, package=package, namespace=namespace, parameters=parameters, output=output)

    modules = {
        "launch": types.ModuleType("launch"),
        "launch.actions": types.ModuleType("launch.actions"),
        "launch.substitutions": types.ModuleType("launch.substitutions"),
        "launch_ros": types.ModuleType("launch_ros"),
        "launch_ros.actions": types.ModuleType("launch_ros.actions"),
    }
    modules["launch"].LaunchDescription = LaunchDescription
    modules["launch.actions"].DeclareLaunchArgument = DeclareLaunchArgument
    modules["launch.actions"].OpaqueFunction = OpaqueFunction
    modules["launch.substitutions"].LaunchConfiguration = LaunchConfiguration
    modules["launch_ros.actions"].Node = Node
    return modules


def run_launch(monkeypatch, **arguments):
    for name, module in fake_launch_modules().items():
        monkeypatch.setitem(sys.modules, name, module)
    spec = importlib.util.spec_from_file_location("polyforce_launch", LAUNCH)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    description = module.generate_launch_description()
    declared = {a.name: a for a in description if hasattr(a, "default_value")}
    unknown = set(arguments) - set(declared)
    assert not unknown, unknown
    context = types.SimpleNamespace(launch_configurations={n: arguments.get(n, a.default_value) for n, a in declared.items()})
    (opaque,) = [a for a in description if hasattr(a, "function")]
    return declared, opaque.function(context)


def shipped(name):
    (section,) = yaml.safe_load((REPO / "config" / name).read_text()).values()
    return section["ros__parameters"]


def test_launch_defaults_start_driver_and_compensation_with_the_shipped_parameters(monkeypatch):
    declared, nodes = run_launch(monkeypatch)
    assert {"backend", "model_file", "namespace", "port", "with_bridge", "record"} <= set(declared)
    assert declared["namespace"].default_value == contract.NAMESPACE
    assert [n.kwargs["executable"] for n in nodes] == ["compensation_node", "driver_node"]
    for n in nodes:
        assert n.kwargs["package"] == "polyforce_ros" and n.kwargs["namespace"] == contract.NAMESPACE
    comp, driver = (n.kwargs["parameters"] for n in nodes)
    # the simulated profile waits for the compensation node, the one reader of bridge_voltage
    assert comp == [shipped("compensation.yaml")] and driver == [dict(shipped("driver.yaml"), wait_for_subscribers=1)]


def test_launch_arguments_add_bridge_and_recorder_and_override_parameters(monkeypatch, tmp_path):
    model = tmp_path / "m.yaml"
    _, nodes = run_launch(monkeypatch, backend="serial", port="/dev/ttyUSB3", model_file=str(model), namespace="/left",
                          with_bridge="true", record=str(tmp_path / "run.mcap"))
    by_exe = {n.kwargs["executable"]: n.kwargs for n in nodes}
    assert [n.kwargs["executable"] for n in nodes] == ["recorder_node", "haptic_bridge_node", "compensation_node", "driver_node"]
    assert all(k["namespace"] == "/left" for k in by_exe.values())
    assert by_exe["driver_node"]["parameters"] == [dict(shipped("driver.yaml"), backend="serial", port="/dev/ttyUSB3",
                                                        wait_for_subscribers=2)]  # compensation and recorder
    assert by_exe["compensation_node"]["parameters"] == [dict(shipped("compensation.yaml"), model_file=str(model))]
    assert by_exe["haptic_bridge_node"]["parameters"] == [shipped("haptic_bridge.yaml")]
    assert by_exe["recorder_node"]["parameters"] == [{"bag_path": str(tmp_path / "run.mcap")}]
    with pytest.raises(RuntimeError):
        run_launch(monkeypatch, backend="usb")


# ---------------------------------------------------------------------- xacro / urdf
def expand(tmp_path, prefix=None):
    prefix_attr = f' prefix="{prefix}"' if prefix is not None else ""
    wrapper = tmp_path / "tool.urdf.xacro"
    wrapper.write_text(f"""<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="needle_tool">
  <xacro:include filename="{XACRO}"/>
  <link name="needle_holder"/>
  <xacro:polyforce_sensor parent="needle_holder"{prefix_attr}>
    <origin xyz="0 0 0.05" rpy="0 0 1.5707963267948966"/>
  </xacro:polyforce_sensor>
</robot>
""")
    return URDF.from_xml_string(xacro.process_file(str(wrapper)).toxml())


def test_xacro_expands_to_the_contract_frame_and_sarrus_joint(tmp_path):
    robot = expand(tmp_path)
    links = {link.name for link in robot.links}
    joints = {joint.name: joint for joint in robot.joints}
    assert contract.FRAME_ID in links
    sarrus = joints[contract.JOINT_NAME]
    assert sarrus.type == "prismatic" and sarrus.child == contract.FRAME_ID
    assert list(sarrus.axis) == [0.0, 0.0, 1.0]  # axial axis = +z
    assert sarrus.limit.lower <= 0.0 < sarrus.limit.upper <= 0.01  # small travel, metres (REP-103)
    assert sarrus.limit.effort == pytest.approx(10.0)  # rated force, N
    # mount chain: parent -> (origin) -> mount -> sarrus_axial -> sensor frame
    assert robot.get_chain("needle_holder", contract.FRAME_ID, links=False)[-1] == contract.JOINT_NAME
    mount = joints[robot.get_chain("needle_holder", contract.FRAME_ID, links=False)[0]]
    assert mount.type == "fixed" and mount.parent == "needle_holder"
    assert list(mount.origin.xyz) == [0.0, 0.0, 0.05] and mount.origin.rpy[2] == pytest.approx(1.5707963267948966)
    assert robot.get_root() == "needle_holder"


def test_xacro_prefix_makes_two_sensors_possible(tmp_path):
    robot = expand(tmp_path, prefix="left_")
    assert f"left_{contract.FRAME_ID}" in {link.name for link in robot.links}
    assert f"left_{contract.JOINT_NAME}" in {joint.name for joint in robot.joints}


# ---------------------------------------------------------------------- layouts
TOPIC_TYPES = dict(contract.CONTRACT)
TOPIC_TYPES[contract.full_name(HAPTIC_COMMAND)] = contract.WRENCH_STAMPED
TOPIC_TYPES[contract.DIAGNOSTICS] = "diagnostic_msgs/msg/DiagnosticArray"
NUMERIC = {"double", "float", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64", "octet", "boolean"}


def field_type(type_name, path):
    """Resolve a field path ([(name, indexed), ...]) in a message type; returns the final ROS field type."""
    cls = message_class(type_name)
    current = None
    for name, indexed in path:
        assert cls is not None, f"{type_name}: {name} follows a non-message field"
        fields = cls.get_fields_and_field_types()
        assert name in fields, f"{type_name} has no field {name!r} (has {sorted(fields)})"
        current = fields[name]
        if indexed:
            match = re.fullmatch(r"sequence<(.+?)(, \d+)?>|(.+)\[\d*\]", current)
            assert match, f"{type_name}.{name} is not an array ({current})"
            current = match.group(1) or match.group(3)
        cls = message_class(current.replace("/", "/msg/", 1)) if "/" in current else None
    return current


def diagnostic_names():
    """(hardware_id, status name) of every node's Diagnostics, from the node sources."""
    names = set()
    for path in (REPO / "polyforce_ros" / "nodes").glob("*_node.py"):
        tree = ast.parse(path.read_text())
        node_name = status = None
        for call in ast.walk(tree):
            if not isinstance(call, ast.Call):
                continue
            names_given = [a.value for a in call.args if isinstance(a, ast.Constant) and isinstance(a.value, str)]
            if isinstance(call.func, ast.Attribute) and call.func.attr == "__init__" and names_given:
                node_name = names_given[0]  # super().__init__("name", ...) or Base.__init__(self, "name", ...)
            if getattr(call.func, "id", None) == "Diagnostics":
                status = call.args[1]
        for node in ast.walk(tree):  # nodes on nodes/common.py's PolyforceNode: NODE_NAME and diagnostics_name
            if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
                if node.targets[0].id == "NODE_NAME":
                    node_name = ast.literal_eval(node.value)
                elif node.targets[0].id == "diagnostics_name":
                    status = node.value
            elif isinstance(node, ast.FunctionDef) and node.name == "diagnostics_name":
                status = next(n.value for n in ast.walk(node) if isinstance(n, ast.Return))
        if status is None:
            continue
        if isinstance(status, ast.JoinedStr):  # the driver: f"polyforce_ros: driver ({backend})"
            for backend in ("sim", "serial"):
                names.add((node_name, "".join(v.value if isinstance(v, ast.Constant) else backend for v in status.values)))
        else:
            names.add((node_name, ast.literal_eval(status)))
    return names


def test_foxglove_layout_plots_contract_topics_and_existing_fields():
    layout = json.loads(FOXGLOVE.read_text())
    panels = layout["configById"]

    def leaves(tree):
        return [tree] if isinstance(tree, str) else leaves(tree["first"]) + leaves(tree["second"])

    assert sorted(leaves(layout["layout"])) == sorted(panels)
    statuses = {name for _, name in diagnostic_names()}
    plotted = {}
    for panel_id, config in panels.items():
        for entry in config.get("paths", []):
            topic, _, rest = entry["value"].partition(".")
            assert topic in TOPIC_TYPES, topic
            filtered = re.fullmatch(r'status\[:\]\{name=="([^"]+)"\}\.level', rest)
            if filtered:  # diagnostics level of one named status
                assert topic == contract.DIAGNOSTICS and filtered[1] in statuses, filtered[1]
                assert field_type(TOPIC_TYPES[topic], [("status", True), ("level", False)]) in NUMERIC
                continue
            path = [(m[1], bool(m[2])) for m in re.finditer(r"(\w+)(\[\d+\])?", rest)]
            assert field_type(TOPIC_TYPES[topic], path) in NUMERIC, entry["value"]
            plotted[entry["value"]] = panel_id
        if "topicToRender" in config:
            assert config["topicToRender"] == contract.DIAGNOSTICS
    voltage = f"{contract.BRIDGE_VOLTAGE}.position[0]"
    force = f"{contract.WRENCH}.wrench.force.z"
    reference = f"{contract.REFERENCE_FORCE}.wrench.force.z"
    assert {voltage, force, reference} <= set(plotted)
    assert plotted[force] == plotted[reference]  # compensated and reference force in one plot
    assert any(p.startswith("DiagnosticSummary!") for p in panels)


def test_plotjuggler_layout_plots_contract_topics_and_existing_fields():
    root = ET.parse(PLOTJUGGLER).getroot()
    assert root.tag == "root"
    (main,) = [tw for tw in root.iter("tabbed_widget") if tw.get("parent") == "main_window"]
    for splitter in main.iter("DockSplitter"):
        children = [c for c in splitter if c.tag in ("DockArea", "DockSplitter")]
        assert int(splitter.get("count")) == len(children) == len(splitter.get("sizes").split(";"))
        assert splitter.get("orientation") in ("-", "|")
    curves = [c.get("name") for c in main.iter("curve")]
    statuses = diagnostic_names()
    for name in curves:
        topic = max((t for t in TOPIC_TYPES if name.startswith(t + "/")), key=len)
        rest = name[len(topic) + 1:]
        type_name = TOPIC_TYPES[topic]
        if type_name == contract.JOINT_STATE:  # PlotJuggler: /topic/<joint name>/position
            joint, field = rest.split("/")
            assert joint == contract.JOINT_NAME and field in ("position", "velocity", "effort")
        elif topic == contract.DIAGNOSTICS:  # PlotJuggler: /diagnostics/<hardware_id>/<status name>/level
            hardware_id, status, value = rest.split("/")
            assert (hardware_id, status) in statuses and value == "level"
        else:
            assert field_type(type_name, [(part, False) for part in rest.split("/")]) in NUMERIC, name
    assert f"{contract.WRENCH}/wrench/force/z" in curves
    assert f"{contract.REFERENCE_FORCE}/wrench/force/z" in curves
    assert f"{contract.BRIDGE_VOLTAGE}/{contract.JOINT_NAME}/position" in curves
    (subscriber,) = [p for p in root.iter("plugin") if p.get("ID") == "ROS2 Topic Subscriber"]
    topics = subscriber.find("selected_topics").get("value").split(";")
    assert set(topics) <= set(TOPIC_TYPES)
    assert {curve_topic for curve_topic in TOPIC_TYPES if any(c.startswith(curve_topic + "/") for c in curves)} <= set(topics)
