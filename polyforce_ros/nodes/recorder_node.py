"""recorder_node: record the topic contract into a rosbag2-compatible MCAP file.

rosbag2 is not available from PyPI; this node records ``bridge_voltage``,
``reference_force``, ``temperature`` and ``wrench`` (whichever are published)
as serialized CDR straight from raw subscriptions (no decoding), with the
receive time as log time, like ``ros2 bag record``. The file is finished
when the node shuts down.
"""
from __future__ import annotations

from rclpy.node import Node

from .. import bags, contract
from .common import DEFAULT_NAMESPACE, OK, Diagnostics, data_qos, declare, declare_qos, message_class, run

#: Topics the recorder can record: relative name -> (message class, type name), from the contract.
TOPICS = {rel: (message_class(type_name), type_name) for rel, type_name in contract.RECORDED.items()}


class RecorderNode(Node):
    def __init__(self, **kwargs):
        kwargs.setdefault("namespace", DEFAULT_NAMESPACE)
        super().__init__("recorder_node", **kwargs)
        path = declare(self, "bag_path", "", "Output mcap file", read_only=True)
        topics = declare(self, "topics", list(TOPICS), "Topics (relative names) to record", read_only=True)
        declare_qos(self)
        if not path:
            raise ValueError("recorder_node needs the bag_path parameter")
        unknown = sorted(set(topics) - set(TOPICS))
        if unknown:
            raise ValueError(f"cannot record {unknown}; known: {sorted(TOPICS)}")
        self.writer = bags.BagWriter(path)
        self.counts = {t: 0 for t in topics}
        qos = data_qos(self)
        for name in topics:
            msg_type, type_name = TOPICS[name]
            full = f"{self.get_namespace().rstrip('/')}/{name}"
            self.create_subscription(msg_type, name, self._make_callback(name, full, type_name), qos, raw=True)
        self.diag = Diagnostics(self, "polyforce_ros: recorder")
        self.create_timer(1.0, lambda: self.diag.publish(OK, f"recording to {path}", self.counts))
        self.get_logger().info(f"recording {topics} to {path}")

    def _make_callback(self, name, full_topic, type_name):
        def callback(data: bytes):
            self.writer.write_serialized(full_topic, type_name, data, self.get_clock().now().nanoseconds)
            self.counts[name] += 1

        return callback

    def destroy_node(self):
        self.writer.close()
        self.get_logger().info(f"bag closed: {self.counts}")
        super().destroy_node()


def main(args=None):
    return run(RecorderNode, args)


if __name__ == "__main__":
    raise SystemExit(main())
