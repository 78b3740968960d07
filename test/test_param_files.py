"""The shipped parameter files name exactly the parameters the nodes declare."""
from pathlib import Path

import yaml
from rclpy.parameter import Parameter

from conftest import REPO
from polyforce_ros.nodes.calibration_node import CalibrationNode
from polyforce_ros.nodes.compensation_node import CompensationNode
from polyforce_ros.nodes.driver_node import DriverNode
from ros_harness import ros

FILES = {"driver.yaml": DriverNode, "compensation.yaml": CompensationNode, "calibration.yaml": CalibrationNode}


def test_param_files_match_declared_parameters():
    with ros() as h:
        for name, node_class in FILES.items():
            data = yaml.safe_load((REPO / "config" / name).read_text())
            (fqn, section), = data.items()
            params = section["ros__parameters"]
            overrides = [Parameter(k, value=v) for k, v in params.items() if k not in ("output_path",)]
            node = h.add(node_class(context=h.context, parameter_overrides=overrides))
            assert fqn == node.get_fully_qualified_name()
            declared = set(node._parameters) - {"use_sim_time", "start_type_description_service"}
            assert set(params) == declared, name
            for key, value in params.items():
                if key != "output_path":
                    assert node.get_parameter(key).value == value, (name, key)
            for key in declared:
                assert node.describe_parameter(key).description, (name, key)  # every parameter is described


# ---------------------------------------------------------------- docs/parameters.md
#: The nodes of docs/parameters.md, in its order, with the overrides they need to be constructed at all.
DOC_NODES = {
    "driver_node": ("polyforce_ros.nodes.driver_node", "DriverNode", {}),
    "compensation_node": ("polyforce_ros.nodes.compensation_node", "CompensationNode", {}),
    "haptic_bridge_node": ("polyforce_ros.nodes.haptic_bridge_node", "HapticBridgeNode", {}),
    "calibration_node": ("polyforce_ros.nodes.calibration_node", "CalibrationNode", {}),
    "replay_node": ("polyforce_ros.nodes.replay_node", "ReplayNode", {"bag_path": str(REPO / "bags" / "step_5n.mcap")}),
    "recorder_node": ("polyforce_ros.nodes.recorder_node", "RecorderNode", {"bag_path": "{tmp}/parameters.mcap"}),
}
PARAMETERS_DOC = REPO / "docs" / "parameters.md"
_HEADER = """# Node parameters

Every parameter each node declares, with its default, its range and its description, as the nodes
declare them (generated from the nodes: `.venv/bin/python test/test_param_files.py --write`;
`test/test_param_files.py` fails when this page and the nodes disagree). The shipped parameter files
are `config/driver.yaml`, `config/compensation.yaml`, `config/haptic_bridge.yaml` and
`config/calibration.yaml`. Read-only parameters are set at start-up only; the others can be changed
at run time (`ros2 param set`), and out-of-range values are refused.
"""


def _cell(value):
    return str(value).replace("|", "\\|")


def _default(value):
    if isinstance(value, bool):
        return f"`{str(value).lower()}`"
    if isinstance(value, str):  # a home directory as the user writes it, not this machine's
        home = str(Path.home())
        return f'`"{"~" + value[len(home):] if value.startswith(home + "/") else value}"`'
    if isinstance(value, (list, tuple)):
        return f"`[{', '.join(map(str, value))}]`"
    return f"`{value!r}`"


def parameters_markdown():
    """docs/parameters.md as the nodes declare their parameters."""
    import tempfile
    from importlib import import_module

    out = [_HEADER]
    with ros() as h, tempfile.TemporaryDirectory() as tmp:
        for name, (module, cls, needs) in DOC_NODES.items():
            node_class = getattr(import_module(module), cls)
            overrides = [Parameter(k, value=v.format(tmp=tmp)) for k, v in needs.items()]
            node = h.add(node_class(context=h.context, parameter_overrides=overrides))
            out += [f"\n## {name}\n", "| parameter | default | range | run time | description |", "|---|---|---|---|---|"]
            for key in sorted(set(node._parameters) - {"use_sim_time", "start_type_description_service"}):
                d = node.describe_parameter(key)
                value = "(required)" if key in needs else _default(node.get_parameter(key).value)
                span = ""
                if d.floating_point_range:
                    span = f"{d.floating_point_range[0].from_value:g} … {d.floating_point_range[0].to_value:g}"
                elif d.integer_range:
                    span = f"{d.integer_range[0].from_value} … {d.integer_range[0].to_value}"
                out.append(f"| `{key}` | {_cell(value)} | {span} | {'no' if d.read_only else 'yes'} | {_cell(d.description)} |")
    return "\n".join(out) + "\n"


def test_parameters_page_lists_what_the_nodes_declare():
    expected = parameters_markdown()
    assert PARAMETERS_DOC.read_text() == expected, "docs/parameters.md is out of date: python test/test_param_files.py --write"


def test_readme_node_table_names_declared_parameters():
    """Every `parameter` the README's node table names is one the node declares (its default from the page)."""
    import re

    readme = (REPO / "README.md").read_text()
    table = readme[readme.index("| node |"):]
    table = table[:table.index("\n\n")]
    declared = {}
    section = None
    for line in PARAMETERS_DOC.read_text().splitlines():
        if line.startswith("## "):
            section = line[3:].strip()
        elif section and line.startswith("| `"):
            declared.setdefault(section, set()).add(line.split("`")[1])
    rows = [row for row in table.splitlines()[2:] if row.startswith("|")]
    assert {row.split("`")[1] for row in rows} >= set(DOC_NODES), "a node is missing from the README's table"
    for row in rows:
        node = row.split("`")[1]
        params = re.findall(r"`(\w+)`", row.split("|")[-2])
        assert params, row
        unknown = sorted(set(params) - declared.get(node, set()))
        assert not unknown, f"README table: {node} declares no {unknown}"


if __name__ == "__main__":
    import sys

    if sys.argv[1:] == ["--write"]:
        PARAMETERS_DOC.write_text(parameters_markdown())
