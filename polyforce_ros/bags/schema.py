"""Message definitions of installed ROS 2 types, and the value fields read from the contract types.

* :func:`schema_text`: the ``ros2msg`` schema of ``pkg/msg/Type`` as rosbag2
  stores it in an MCAP Schema record: the ``.msg`` text followed by every
  dependency, each after a line of 80 ``=`` and ``MSG: pkg/Type``.
* :func:`type_hash`: the RIHS01 type description hash of a type (the
  ``topic_type_hash`` of a rosbag2 channel), as the message package installs it.
* :data:`VALUE_FIELDS`: the value fields a reader decodes per contract type.

Definitions are looked up in ``<prefix>/share/<pkg>/msg/`` for every prefix of
``AMENT_PREFIX_PATH``, then in ``sys.prefix``.
"""
from __future__ import annotations

import json
import os
import re
import sys
from pathlib import Path

from ..contract import FLOAT64, JOINT_STATE, TEMPERATURE_MSG, WRENCH_STAMPED
from .errors import BagError

__all__ = ["VALUE_FIELDS", "schema_text", "type_hash"]

_PRIMITIVES = {
    "bool", "byte", "char", "float32", "float64", "int8", "uint8", "int16", "uint16",
    "int32", "uint32", "int64", "uint64", "string", "wstring",
}

#: The value fields decoded per contract type (see :class:`~polyforce_ros.bags.TopicData`), in CDR order:
#: JointState ``position`` (its first element; NaN without positions), WrenchStamped force (N) and torque
#: (N m), Temperature (degC) and its variance (degC^2), Float64 ``data``.
VALUE_FIELDS: dict[str, tuple[str, ...]] = {
    JOINT_STATE: ("position",),
    WRENCH_STAMPED: ("force_x", "force_y", "force_z", "torque_x", "torque_y", "torque_z"),
    TEMPERATURE_MSG: ("temperature", "variance"),
    FLOAT64: ("data",),
}


def _share_dirs() -> list[Path]:
    """``share`` directories searched for message definitions, first match wins."""
    prefixes = [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    prefixes.append(sys.prefix)
    return [Path(p) / "share" for p in prefixes]


def _msg_text(pkg: str, name: str) -> str:
    for share in _share_dirs():
        path = share / pkg / "msg" / f"{name}.msg"
        if path.is_file():
            return path.read_text()
    raise BagError(f"message definition {pkg}/msg/{name} not found (is AMENT_PREFIX_PATH set?)")


def _dependencies(pkg: str, text: str) -> list[tuple[str, str]]:
    """``(package, type)`` of every non-primitive field type of the ``.msg`` ``text`` of package ``pkg``."""
    deps = []
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        tokens = line.split()
        if len(tokens) > 1 and "=" in tokens[1]:
            continue  # a constant
        ftype = re.sub(r"(\[.*\]|<=\d+)", "", tokens[0])
        if ftype in _PRIMITIVES:
            continue
        if ftype == "Header":
            deps.append(("std_msgs", "Header"))
        elif "/" in ftype:
            dpkg, dname = ftype.split("/")[0], ftype.split("/")[-1]
            deps.append((dpkg, dname))
        else:
            deps.append((pkg, ftype))
    return deps


def schema_text(type_name: str) -> str:
    """ros2msg schema text of ``pkg/msg/Type`` with all dependencies appended.

    Raises :class:`~polyforce_ros.bags.BagError` when a definition is not installed.
    """
    pkg, _, name = type_name.split("/")
    main = _msg_text(pkg, name)
    parts, seen, todo = [main.rstrip("\n")], {(pkg, name)}, list(_dependencies(pkg, main))
    while todo:
        dep = todo.pop(0)
        if dep in seen:
            continue
        seen.add(dep)
        text = _msg_text(*dep)
        parts.append("=" * 80 + f"\nMSG: {dep[0]}/{dep[1]}\n" + text.rstrip("\n"))
        todo.extend(_dependencies(dep[0], text))
    return "\n".join(parts) + "\n"


def type_hash(type_name: str) -> str:
    """The RIHS01 type description hash of an installed message type (``pkg/msg/Type``), or "" when unknown.

    Read from the ``.json`` type description the ROS 2 message packages install next to the ``.msg``.
    """
    package, _, name = type_name.partition("/msg/")
    for share in _share_dirs():
        path = share / package / "msg" / f"{name}.json"
        if path.is_file():
            try:
                hashes: list[dict[str, str]] = json.loads(path.read_text())["type_hashes"]
            except (ValueError, KeyError, OSError):
                return ""
            return next((h["hash_string"] for h in hashes if h.get("type_name") == type_name), "")
    return ""
