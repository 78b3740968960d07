"""The topic contract: the one home of names, message types, frames and QoS defaults.

Nodes, bags, the recorder, the replay and the CLI import these; nothing else
spells a topic, a type or a default frame. ROS-free (type names are strings;
``nodes/common.py`` maps them to rclpy message classes).
"""
from __future__ import annotations

__all__ = [
    "NAMESPACE", "Rel", "RECORDED", "JOINT_STATE", "WRENCH_STAMPED", "TEMPERATURE_MSG", "FLOAT64", "HEADER", "STRING",
    "TOPICS", "full_name",
    "BRIDGE_VOLTAGE", "BRIDGE_VOLTAGE_SCALAR", "REFERENCE_FORCE", "WRENCH", "TEMPERATURE", "CONTRACT",
    "SCALAR_FIELD", "FRAME_ID", "JOINT_NAME", "QOS_RELIABLE", "QOS_DEPTH", "DIAGNOSTICS",
]

#: Default namespace of every node (all names below are relative to it and remappable).
NAMESPACE = "/polyforce"

JOINT_STATE = "sensor_msgs/msg/JointState"
WRENCH_STAMPED = "geometry_msgs/msg/WrenchStamped"
TEMPERATURE_MSG = "sensor_msgs/msg/Temperature"
FLOAT64 = "std_msgs/msg/Float64"
HEADER = "std_msgs/msg/Header"
STRING = "std_msgs/msg/String"


class Rel:
    """Relative topic names (resolved in the node's namespace, remappable)."""

    BRIDGE_VOLTAGE = "bridge_voltage"                 # position[0] = bridge output, V; stamp = acquisition time
    BRIDGE_VOLTAGE_SCALAR = "bridge_voltage_scalar"   # plain numbers from DAQ nodes, stamped on arrival
    REFERENCE_FORCE = "reference_force"               # force.z of a bench load cell, N
    WRENCH = "wrench"                                 # force.z = compensated axial force, N; stamp of the raw sample
    TEMPERATURE = "temperature"                       # degC
    HAPTIC_COMMAND = "haptic_command"                 # haptic_bridge_node: force for the haptic master, device frame
    SENSOR_RESET = "sensor_reset"                     # the sensor restarted relaxed at header.stamp (driver -> compensation)
    SENSOR_SERIAL = "sensor_serial"                   # serial number the device reports for its sensor (latched, driver)


#: Relative topic name -> message type.
TOPICS = {
    Rel.BRIDGE_VOLTAGE: JOINT_STATE,
    Rel.BRIDGE_VOLTAGE_SCALAR: FLOAT64,
    Rel.REFERENCE_FORCE: WRENCH_STAMPED,
    Rel.WRENCH: WRENCH_STAMPED,
    Rel.TEMPERATURE: TEMPERATURE_MSG,
    Rel.HAPTIC_COMMAND: WRENCH_STAMPED,
    Rel.SENSOR_RESET: HEADER,
    Rel.SENSOR_SERIAL: STRING,
}


def full_name(relative: str, namespace: str = NAMESPACE) -> str:
    """``/namespace/relative`` (the name a bag records)."""
    return f"{namespace.rstrip('/')}/{relative}"


BRIDGE_VOLTAGE = full_name(Rel.BRIDGE_VOLTAGE)
BRIDGE_VOLTAGE_SCALAR = full_name(Rel.BRIDGE_VOLTAGE_SCALAR)
REFERENCE_FORCE = full_name(Rel.REFERENCE_FORCE)
WRENCH = full_name(Rel.WRENCH)
TEMPERATURE = full_name(Rel.TEMPERATURE)

#: Topics a bag records (the scalar input is not one of them): relative name -> message type.
RECORDED = {rel: TOPICS[rel] for rel in (Rel.BRIDGE_VOLTAGE, Rel.REFERENCE_FORCE, Rel.WRENCH, Rel.TEMPERATURE)}
#: The bag contract: recorded topic (full name) -> message type.
CONTRACT = {full_name(rel): type_name for rel, type_name in RECORDED.items()}

#: The field that carries a contract message's one scalar.
SCALAR_FIELD = {JOINT_STATE: "position", WRENCH_STAMPED: "force_z", TEMPERATURE_MSG: "temperature", FLOAT64: "data",
                STRING: "data"}

#: Sensor frame (urdf) and the JointState name of the sensor's passive prismatic joint.
FRAME_ID = "polyforce_sensor"
JOINT_NAME = "sarrus_axial"

#: Data topics: reliable (haptic subscribers are reliable), deep enough for 10-60 ms scheduler stalls.
QOS_RELIABLE = True
QOS_DEPTH = 1000

DIAGNOSTICS = "/diagnostics"
