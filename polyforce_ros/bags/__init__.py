"""rosbag2-compatible MCAP bags: writing, and fast reading of the topic contract into numpy.

Writing follows rosbag2's MCAP storage: profile ``ros2``, schemas named
``pkg/msg/Type`` with encoding ``ros2msg`` (the .msg text followed by every
dependency, each after a line of 80 ``=`` and ``MSG: pkg/Type``), messages in
``cdr``, chunked with message indexes, chunk indexes and statistics.

Reading does not build one Python object per message: records are scanned
linearly (so a truncated file still yields everything before the cut), chunks
are decompressed whole, and for each topic the messages whose CDR layout is
identical (same frame_id, joint names and array sizes: the normal case) are
decoded together as numpy arrays. Messages with other layouts are decoded one
by one with the same layout rules, so nothing is dropped for being unusual.

Problems that lose data (truncation, a corrupt chunk) are reported in
``BagData.warnings``; problems that make the bag unusable for the request (not
an MCAP file, a missing topic, the wrong type on a topic) raise
:class:`BagError` with the reason.

Damaged or hostile files lose only what they touch, in bounded time and
memory: every length word (records, strings, CDR strings and arrays) is
checked against the bytes that remain before it is used; a chunk is inflated
only up to its declared size and never beyond :data:`MAX_CHUNK_BYTES`
(decompression bombs); a chunk that is over the cap, of an unknown
compression, corrupt or holding an impossible record is skipped (or cut) with
a warning naming its byte offset; a message whose CDR does not fit its bytes
is skipped and counted per topic, also on the bulk paths (each message is
checked to have the layout the vectorised decoding assumes, the odd ones are
decoded one by one). Whatever else malformed bytes could raise becomes a
:class:`BagError`.

Modules, each importing only those listed before it:

* :mod:`.errors`: :class:`BagError`, and the marker of a malformed record or message.
* :mod:`.schema`: message definitions (:func:`schema_text`), RIHS01 type hashes (:func:`type_hash`),
  the value fields read per contract type.
* :mod:`.cdr`: CDR encoding of the contract types, every byte set; bulk encoding of one-scalar series.
* :mod:`.serde`: CDR decoding of the contract types, one message or many of one layout;
  :func:`serialize_template`.
* :mod:`.storage`: MCAP records: :func:`bag_file`, the record walk, chunk inflation within
  :data:`MAX_CHUNK_BYTES`, the summary's schema and channel tables, :func:`copy_messages`.
* :mod:`.reader`: :func:`read_bag` into :class:`BagData` / :class:`TopicData`.
* :mod:`.writer`: :class:`BagWriter` and the QoS it records (:data:`DEFAULT_QOS`).
* :mod:`.messages`: :func:`make_message`, the ROS message objects the replay node publishes.

The topic contract (:mod:`polyforce_ros.contract`: topic names, message types, frame, QoS) is
re-exported here for the readers and writers of bags.
"""
from __future__ import annotations

from ..contract import (
    BRIDGE_VOLTAGE,
    CONTRACT,
    FLOAT64,
    FRAME_ID,
    JOINT_NAME,
    JOINT_STATE,
    QOS_DEPTH,
    QOS_RELIABLE,
    REFERENCE_FORCE,
    SCALAR_FIELD,
    TEMPERATURE,
    TEMPERATURE_MSG,
    WRENCH,
    WRENCH_STAMPED,
)
from .errors import BagError
from .messages import make_message
from .reader import BagData, TopicData, read_bag
from .schema import schema_text, type_hash
from .serde import serialize_template
from .storage import MAX_CHUNK_BYTES, bag_file, copy_messages
from .writer import DEFAULT_QOS, BagWriter

__all__ = [
    # reading
    "BagData", "BagError", "MAX_CHUNK_BYTES", "TopicData", "bag_file", "read_bag",
    # writing
    "BagWriter", "DEFAULT_QOS", "copy_messages", "make_message", "schema_text", "serialize_template", "type_hash",
    # the topic contract
    "BRIDGE_VOLTAGE", "CONTRACT", "FLOAT64", "FRAME_ID", "JOINT_NAME", "JOINT_STATE", "QOS_DEPTH", "QOS_RELIABLE",
    "REFERENCE_FORCE", "SCALAR_FIELD", "TEMPERATURE", "TEMPERATURE_MSG", "WRENCH", "WRENCH_STAMPED",
]
