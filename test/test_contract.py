"""One contract: every node, bag and tool uses the names, types and defaults of contract.py."""
import ast

from conftest import REPO
from polyforce_ros import bags, contract
from polyforce_ros.nodes.common import message_class
from polyforce_ros.nodes.recorder_node import TOPICS as RECORDER_TOPICS

# "temperature" is also a field and a signal name, so only the unambiguous relative names are checked
TOPIC_NAMES = ({contract.Rel.BRIDGE_VOLTAGE, contract.Rel.BRIDGE_VOLTAGE_SCALAR, contract.Rel.REFERENCE_FORCE,
                contract.Rel.WRENCH}
               | set(contract.CONTRACT) | {contract.FRAME_ID, contract.JOINT_NAME, contract.NAMESPACE})


def test_every_contract_type_is_a_real_message_with_its_scalar_field():
    for type_name in contract.TOPICS.values():
        cls = message_class(type_name)
        assert f"{cls.__module__.split('.')[0]}/msg/{cls.__name__}" == type_name
    # every data topic carries one scalar; the sensor_reset event carries only its stamp
    assert set(contract.SCALAR_FIELD) == set(contract.TOPICS.values()) - {contract.HEADER}


def test_bags_and_recorder_speak_the_contract():
    assert bags.CONTRACT is contract.CONTRACT and bags.BRIDGE_VOLTAGE == contract.full_name("bridge_voltage")
    assert {rel: t for rel, (_, t) in RECORDER_TOPICS.items()} == contract.RECORDED


def test_no_module_spells_a_contract_name_of_its_own():
    """String literals equal to a topic, frame or namespace appear only in contract.py."""
    offenders = []
    for path in (REPO / "polyforce_ros").rglob("*.py"):
        if path.name == "contract.py":
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value in TOPIC_NAMES:
                offenders.append(f"{path.relative_to(REPO)}:{node.lineno}: {node.value!r}")
    assert not offenders, "\n".join(offenders)


def test_config_and_visualisation_files_speak_the_contract():
    """The YAML defaults and the PlotJuggler/Foxglove layouts name the contract's frame, joint and topics."""
    import json
    import re

    import yaml

    driver = yaml.safe_load((REPO / "config" / "driver.yaml").read_text())
    params = next(iter(driver.values()))["ros__parameters"]
    assert (params["joint_name"], params["frame_id"]) == (contract.JOINT_NAME, contract.FRAME_ID)
    topics = {contract.full_name(rel) for rel in contract.TOPICS}
    named = set(re.findall(r'name="(/[^/"]+/[^/"]+)/', (REPO / "config" / "polyforce.plotjuggler.xml").read_text()))
    named |= {s.split(".")[0] for s in re.findall(r'"(/[a-z_]+/[a-z_]+)[."]', json.dumps(
        json.loads((REPO / "config" / "polyforce.foxglove.json").read_text())))}
    named = {n for n in named if n.startswith(contract.NAMESPACE + "/")}
    assert named and named <= topics, sorted(named - topics)
