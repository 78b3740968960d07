"""One source per setting: a configuration dataclass field carries its default, description and range.

A runtime part's configuration (e.g. :class:`~polyforce_ros.runtime.CompensatorConfig`) declares each
setting once with :func:`setting`; the node declares a ROS parameter of each field from it
(``nodes.common.declare_settings``), the CLI takes its defaults from it, and the tests tie
``config/*.yaml`` and ``docs/parameters.md`` to the parameters the nodes declare. ROS-free.
"""
from __future__ import annotations

from dataclasses import Field, field, fields
from typing import Any, Iterator, Optional

__all__ = ["setting", "settings_of"]


def setting(default: Any, description: str, low: Optional[float] = None, high: Optional[float] = None,
            read_only: bool = False) -> Any:
    """A dataclass field with its default, its description (units in brackets) and, for numbers, its inclusive range."""
    return field(default=default, metadata={"description": description, "low": low, "high": high,
                                            "read_only": read_only})


def settings_of(config_type: type) -> Iterator[tuple[Field[Any], dict[str, Any]]]:
    """Each field of a configuration dataclass declared with :func:`setting`, with its metadata."""
    for f in fields(config_type):
        if "description" in f.metadata:
            yield f, dict(f.metadata)
