"""Writing rosbag2-compatible MCAP bags: :class:`BagWriter`.

The files follow rosbag2's MCAP storage (Jazzy): profile ``ros2``, schemas
named ``pkg/msg/Type`` with encoding ``ros2msg`` (:func:`~polyforce_ros.bags.schema.schema_text`),
messages in ``cdr`` (:mod:`polyforce_ros.bags.cdr` for the contract types),
zstd-compressed chunks with message indexes, chunk indexes and statistics,
channel metadata ``offered_qos_profiles`` (:data:`DEFAULT_QOS`) and
``topic_type_hash``, and a closing ``rosbag2`` metadata record.
"""
from __future__ import annotations

import copy
from pathlib import Path
from typing import TYPE_CHECKING, Any, Self

import numpy as np
import numpy.typing as npt

from ..contract import FRAME_ID, JOINT_NAME, QOS_DEPTH, QOS_RELIABLE
from . import cdr
from .errors import BagError
from .schema import schema_text, type_hash
from .storage import StrPath

if TYPE_CHECKING:
    from mcap.writer import Writer

__all__ = ["DEFAULT_QOS", "BagWriter"]

#: QoS a rosbag2 reader replays the contract topics with (what our nodes offer: reliable, keep-last, volatile).
_INFINITE = {"sec": 9223372036, "nsec": 854775807}
DEFAULT_QOS: list[dict[str, object]] = [
    {"history": "keep_last", "depth": QOS_DEPTH, "reliability": "reliable" if QOS_RELIABLE else "best_effort",
     "durability": "volatile", "deadline": dict(_INFINITE), "lifespan": dict(_INFINITE),
     "liveliness": "automatic", "liveliness_lease_duration": dict(_INFINITE),
     "avoid_ros_namespace_conventions": False}]


class BagWriter:
    """Write a rosbag2 MCAP bag, as rosbag2_storage_mcap (Jazzy) does.

    - Messages are written in log-time order across topics (chunks do not overlap), whatever the order of
      the calls: with ``ordered=True`` (default) they are collected and written sorted at :meth:`close`
      (ties keep call order); a live recorder whose log times are arrival times passes ``ordered=False``.
    - Each channel carries ``offered_qos_profiles`` (the YAML list rosbag2 writes) and ``topic_type_hash``
      (RIHS01, where the message package installs it); the file ends with the ``rosbag2`` metadata record
      (``serialized_metadata``: the bag's metadata YAML).
    - ``directory=True`` writes the bag-directory form ``PATH/PATH.name_0.mcap`` + ``PATH/metadata.yaml``.
    - Every byte of a message written by :meth:`write_series` or :meth:`write` (contract types) is set
      (:mod:`polyforce_ros.bags.cdr`), so equal content gives equal files.

    ``chunk_size``: uncompressed bytes per chunk. Use as a context manager.
    """

    def __init__(self, path: StrPath, chunk_size: int = 1 << 20, ordered: bool = True, directory: bool = False) -> None:
        from mcap.writer import CompressionType, Writer

        path = Path(path)
        self.directory: Path | None
        if directory:
            path.mkdir(parents=True, exist_ok=True)
            self.directory, self.path = path, path / f"{path.name}_0.mcap"
        else:
            path.parent.mkdir(parents=True, exist_ok=True)
            self.directory, self.path = None, path
        self._fh = open(self.path, "wb")
        self._writer: Writer = Writer(self._fh, chunk_size=chunk_size, compression=CompressionType.ZSTD)
        self._writer.start(profile="ros2", library="polyforce_ros")
        self._schemas: dict[str, int] = {}  # type name -> schema id
        self._channels: dict[str, tuple[int, str]] = {}  # topic -> (channel id, type name)
        self._seq: dict[int, int] = {}  # channel id -> last sequence number
        self._counts: dict[int, int] = {}  # channel id -> messages written
        self._ordered = ordered
        self._singles: list[tuple[int, int, int, bytes]] = []  # (log ns, publish ns, channel id, bytes), in call order
        # (channel id, encoded (n, size) uint8, log ns (n,)), in call order
        self._series: list[tuple[int, npt.NDArray[np.uint8], npt.NDArray[np.int64]]] = []
        self._t_min: int | None = None
        self._t_max: int | None = None

    def _channel(self, topic: str, type_name: str, schema_data: bytes | None = None) -> int:
        if topic in self._channels:
            cid, known = self._channels[topic]
            if known != type_name:
                raise BagError(f"topic {topic} already written with type {known}")
            return cid
        if type_name not in self._schemas:
            data = schema_data if schema_data is not None else schema_text(type_name).encode()
            self._schemas[type_name] = self._writer.register_schema(name=type_name, encoding="ros2msg", data=data)
        import yaml

        metadata = {"offered_qos_profiles": yaml.safe_dump(DEFAULT_QOS, sort_keys=False).strip()}
        digest = type_hash(type_name)
        if digest:
            metadata["topic_type_hash"] = digest
        cid = self._writer.register_channel(topic=topic, message_encoding="cdr", schema_id=self._schemas[type_name],
                                            metadata=metadata)
        self._channels[topic] = (cid, type_name)
        self._seq[cid], self._counts[cid] = 0, 0
        return cid

    def write_serialized(self, topic: str, type_name: str, data: bytes, log_time_ns: int,
                         schema_data: bytes | None = None, publish_time_ns: int | None = None) -> None:
        """One CDR message; ``publish_time_ns``: when it was sent (default: its log time);
        ``schema_data`` supplies the schema text of types not installed here."""
        cid = self._channel(topic, type_name, schema_data)
        log = int(log_time_ns)
        publish = log if publish_time_ns is None else int(publish_time_ns)
        if self._ordered:
            self._singles.append((log, publish, cid, bytes(data)))
        else:
            self._emit(cid, log, publish, data)

    def write(self, topic: str, type_name: str, msg: Any, log_time_ns: int) -> None:
        """One ROS message object (of any installed type); contract types are encoded by :mod:`.cdr` (every
        byte set), other types by rclpy's serialiser."""
        try:
            data = cdr.encode_message(type_name, msg)
        except ValueError:  # not a contract type: the middleware's serialiser
            from rclpy.serialization import serialize_message

            data = serialize_message(msg)
        self.write_serialized(topic, type_name, data, log_time_ns)

    def write_series(self, topic: str, type_name: str, stamp_ns: npt.ArrayLike, values: npt.ArrayLike,
                     frame_id: str = FRAME_ID, joint_name: str = JOINT_NAME,
                     log_time_ns: npt.ArrayLike | None = None) -> None:
        """Write one message per sample: JointState position, WrenchStamped force.z,
        Temperature temperature or Float64 data = ``values[i]``, header stamp ``stamp_ns[i]`` (ns).

        ``log_time_ns`` (ns, >= 0): when each was logged (default: its stamp). The CDR bytes come from
        :mod:`polyforce_ros.bags.cdr`: every byte is set (zero padding, no trailing bytes), so equal
        input gives equal files and strict CDR readers (rosbags) accept every message. Inputs are checked
        before anything is written (``ValueError``: unequal lengths, a stamp outside the
        builtin_interfaces/Time range, a negative log time; :class:`BagError`: a type without an encoder,
        a NUL in a name).
        """
        stamps = np.asarray(stamp_ns, dtype=np.int64)
        column = np.asarray(values, dtype=np.float64)
        logs = stamps if log_time_ns is None else np.asarray(log_time_ns, dtype=np.int64)
        if not stamps.ndim == column.ndim == logs.ndim == 1 or not stamps.size == column.size == logs.size:
            raise ValueError(f"write_series needs 1-D stamps, values and log times of one length, got shapes "
                             f"{stamps.shape}, {column.shape}, {logs.shape}")
        try:
            layout = cdr.series_layout(type_name, frame_id, joint_name)
        except ValueError as exc:  # a type without an encoder, a NUL in a name
            raise BagError(f"write_series on {topic}: {exc}") from exc
        cdr.split_stamps(stamps)  # the whole series is valid before its first message is written
        if logs.size and logs.min() < 0:
            raise ValueError("write_series: log times must be >= 0 ns")
        cid = self._channel(topic, type_name)
        encoded = layout.encode(stamps, column)
        if self._ordered:
            self._series.append((cid, encoded, logs.copy()))
        else:
            raw = encoded.tobytes()
            size = encoded.shape[1] if encoded.ndim == 2 else layout.size
            for i, t in enumerate(logs.tolist()):
                self._emit(cid, t, t, raw[i * size : (i + 1) * size])

    def _emit(self, cid: int, log: int, publish: int, data: bytes) -> None:
        self._seq[cid] += 1
        self._counts[cid] += 1
        self._writer.add_message(channel_id=cid, log_time=log, data=data, publish_time=publish, sequence=self._seq[cid])
        self._t_min = log if self._t_min is None else min(self._t_min, log)
        self._t_max = log if self._t_max is None else max(self._t_max, log)

    def _flush_sorted(self) -> None:
        """Every collected message, in log-time order (stable: ties keep call order)."""
        parts = [np.array([s[0] for s in self._singles], dtype=np.int64)] + [log for _, _, log in self._series]
        sizes = [len(p) for p in parts]
        if not sum(sizes):
            return
        order = np.argsort(np.concatenate(parts), kind="stable")
        source = np.repeat(np.arange(len(parts)), sizes)[order]
        offset = np.concatenate(([0], np.cumsum(sizes)[:-1]))
        index = order - offset[source]
        series = [(cid, enc.tobytes(), enc.shape[1], log) for cid, enc, log in self._series]
        singles = self._singles
        for src, i in zip(source.tolist(), index.tolist()):
            if src == 0:
                log, publish, cid, data = singles[i]
                self._emit(cid, log, publish, data)
            else:
                cid, raw, size, logs = series[src - 1]
                t = int(logs[i])
                self._emit(cid, t, t, raw[i * size : (i + 1) * size])
        self._singles, self._series = [], []

    def metadata(self) -> dict[str, Any]:
        """The rosbag2 bag metadata (version 9) of what was written: ``{"rosbag2_bagfile_information": ...}``,
        times in ns."""
        start = self._t_min or 0
        duration = (self._t_max - self._t_min) if self._t_max is not None and self._t_min is not None else 0
        count = sum(self._counts.values())
        topics = []
        for topic, (cid, type_name) in self._channels.items():
            topics.append({"topic_metadata": {"name": topic, "type": type_name, "serialization_format": "cdr",
                                              "offered_qos_profiles": copy.deepcopy(DEFAULT_QOS),  # no YAML aliases
                                              "type_description_hash": type_hash(type_name)},
                           "message_count": self._counts[cid]})
        return {"rosbag2_bagfile_information": {
            "version": 9, "storage_identifier": "mcap", "duration": {"nanoseconds": duration},
            "starting_time": {"nanoseconds_since_epoch": start}, "message_count": count,
            "topics_with_message_count": topics, "compression_format": "", "compression_mode": "",
            "relative_file_paths": [self.path.name],
            "files": [{"path": self.path.name, "starting_time": {"nanoseconds_since_epoch": start},
                       "duration": {"nanoseconds": duration}, "message_count": count}],
            "custom_data": None, "ros_distro": "jazzy"}}

    def close(self) -> None:
        """Write the collected messages, the summary and the ``rosbag2`` metadata record and close the file
        (and write ``metadata.yaml`` of a bag directory); a second call does nothing."""
        if self._fh.closed:
            return
        import yaml

        self._flush_sorted()
        info = self.metadata()
        self._writer.add_metadata("rosbag2", {"serialized_metadata": yaml.safe_dump(
            info["rosbag2_bagfile_information"], sort_keys=False)})
        self._writer.finish()  # type: ignore[no-untyped-call]  # mcap: Writer.finish() is unannotated
        self._fh.close()
        if self.directory is not None:
            (self.directory / "metadata.yaml").write_text(yaml.safe_dump(info, sort_keys=False))

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
