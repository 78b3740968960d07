"""ROS message objects of the contract types carrying one scalar (what the replay node publishes).

The one module of the bag package that imports ROS message classes
(``std_msgs``, ``sensor_msgs``, ``geometry_msgs``, ``builtin_interfaces``),
each only when a message of its type is made.
"""
from __future__ import annotations

from typing import Any

from ..contract import FLOAT64, FRAME_ID, JOINT_NAME, JOINT_STATE, TEMPERATURE_MSG, WRENCH_STAMPED
from .errors import BagError

__all__ = ["make_message"]


def make_message(type_name: str, stamp_ns: int, value: float, frame_id: str = FRAME_ID,
                 joint_name: str = JOINT_NAME) -> Any:
    """A contract message carrying one scalar (see :meth:`~polyforce_ros.bags.BagWriter.write_series`).

    ``stamp_ns``: header stamp (ns); ``value``: JointState ``position[0]``,
    WrenchStamped ``force.z``, Temperature ``temperature`` or Float64 ``data``.
    Returns the rclpy message object (``std_msgs.msg.Float64``,
    ``sensor_msgs.msg.JointState``, ``geometry_msgs.msg.WrenchStamped`` or
    ``sensor_msgs.msg.Temperature``); :class:`~polyforce_ros.bags.BagError`
    for another type.
    """
    if type_name == FLOAT64:
        from std_msgs.msg import Float64

        return Float64(data=float(value))
    from builtin_interfaces.msg import Time

    stamp = Time(sec=int(stamp_ns // 1_000_000_000), nanosec=int(stamp_ns % 1_000_000_000))
    if type_name == JOINT_STATE:
        from sensor_msgs.msg import JointState

        msg = JointState(name=[joint_name], position=[float(value)])
    elif type_name == WRENCH_STAMPED:
        from geometry_msgs.msg import WrenchStamped

        msg = WrenchStamped()
        msg.wrench.force.z = float(value)
    elif type_name == TEMPERATURE_MSG:
        from sensor_msgs.msg import Temperature

        msg = Temperature(temperature=float(value))
    else:
        raise BagError(f"no contract message of type {type_name}")
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    return msg
