"""The exceptions of the bag package.

:class:`BagError` is what a caller sees: the bag cannot serve the request
(not an MCAP file, a missing topic, the wrong type on a topic, bytes no check
foresaw). :class:`Malformed` marks one record or message whose length words
do not fit its bytes; the readers catch it, skip what it names and count it
in their warnings, so it never leaves :mod:`polyforce_ros.bags`.
"""
from __future__ import annotations

__all__ = ["BagError", "Malformed"]


class BagError(ValueError):
    """The bag cannot serve the request; the message says why."""


class Malformed(ValueError):
    """A record or message whose length words do not fit its bytes: skipped and counted, never raised out."""
