"""The shipped parameter files name exactly the parameters the nodes declare."""
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
