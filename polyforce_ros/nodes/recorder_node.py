"""recorder_node: record the topic contract into a rosbag2-compatible MCAP file.

rosbag2 is not available from PyPI; this node records ``bridge_voltage``,
``reference_force``, ``temperature`` and ``wrench`` (whichever are published)
as serialized CDR straight from raw subscriptions (no decoding), with the
receive time as log time, like ``ros2 bag record``. The file is finished
when the node shuts down.
"""
from __future__ import annotations

from typing import Any, Callable, Optional

from .. import bags, contract
from .common import DEFAULT_NAMESPACE, OK, Diagnostics, RosNode, data_qos, declare, declare_qos, message_class, run

#: Topics the recorder can record: relative name -> (message class, type name), from the contract.
TOPICS = {rel: (message_class(type_name), type_name) for rel, type_name in contract.RECORDED.items()}


class RecorderNode(RosNode):
    """The recorder (``ros2 run polyforce_ros recorder_node``); ``kwargs`` as for ``Node``."""

    #: run() gives it an executor that passes message info (the sender's timestamp)
    needs_message_info = True

    def __init__(self, **kwargs: Any) -> None:
        kwargs.setdefault("namespace", DEFAULT_NAMESPACE)
        super().__init__("recorder_node", **kwargs)
        path = declare(self, "bag_path", "", "Output mcap file", read_only=True)
        topics = declare(self, "topics", list(TOPICS), "Topics (relative names) to record", read_only=True)
        bag_format = declare(self, "bag_format", "file",
                             "'file': one .mcap file at bag_path; 'directory': a rosbag2 bag directory "
                             "(bag_path/bag_path_0.mcap + metadata.yaml)", read_only=True)
        if bag_format not in ("file", "directory"):
            raise ValueError(f"bag_format must be 'file' or 'directory', got {bag_format!r}")
        declare_qos(self)
        if not path:
            raise ValueError("recorder_node needs the bag_path parameter")
        unknown = sorted(set(topics) - set(TOPICS))
        if unknown:
            raise ValueError(f"cannot record {unknown}; known: {sorted(TOPICS)}")
        # arrival order is log-time order: write as messages come (nothing held in memory)
        self.writer = bags.BagWriter(path, ordered=False, directory=self.get_parameter("bag_format").value == "directory")
        self.counts = {t: 0 for t in topics}
        qos = data_qos(self)
        for name in topics:
            msg_type, type_name = TOPICS[name]
            full = f"{self.get_namespace().rstrip('/')}/{name}"
            callback = self._make_callback(name, full, type_name)
            # rclpy passes the message info to a callback of two parameters; its annotation knows only one
            self.create_subscription(msg_type, name, callback, qos, raw=True)  # type: ignore[arg-type]
        self.diag = Diagnostics(self, "polyforce_ros: recorder")
        self.create_timer(1.0, lambda: self.diag.publish(OK, f"recording to {path}", self.counts))
        self.get_logger().info(f"recording {topics} to {path}")

    def _make_callback(self, name: str, full_topic: str, type_name: str) -> Callable[[bytes, Any], None]:
        clock = self.get_clock()

        def callback(data: bytes, info: Any) -> None:
            # rosbag2's convention: log time = when the recorder received it, publish time = when it was sent
            log = clock.now().nanoseconds
            sent = info.get("source_timestamp") if isinstance(info, dict) else None  # MessageInfo (a dict here)
            self.writer.write_serialized(full_topic, type_name, data, log, publish_time_ns=sent or log)
            self.counts[name] += 1

        return callback

    def destroy_node(self) -> None:
        self.writer.close()
        self.get_logger().info(f"bag closed: {self.counts}")
        super().destroy_node()


def main(args: Optional[list[str]] = None) -> int:
    return run(RecorderNode, args)


if __name__ == "__main__":
    raise SystemExit(main())
