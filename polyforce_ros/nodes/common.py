"""What every polyforce node shares: parameters, QoS, diagnostics, stamps and the main loop."""
from __future__ import annotations

import gc
import signal
import sys

import rclpy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.exceptions import ParameterException
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from .. import contract

DEFAULT_NAMESPACE = contract.NAMESPACE
OK, WARN, ERROR = DiagnosticStatus.OK, DiagnosticStatus.WARN, DiagnosticStatus.ERROR


def declare(node, name, default, description, low=None, high=None, read_only=False):
    """Declare a parameter with a description and, for numbers, an inclusive range."""
    desc = ParameterDescriptor(description=description, read_only=read_only)
    if low is not None and isinstance(default, bool) is False:
        if isinstance(default, int):
            desc.integer_range = [IntegerRange(from_value=int(low), to_value=int(high), step=0)]
        elif isinstance(default, float):
            desc.floating_point_range = [FloatingPointRange(from_value=float(low), to_value=float(high), step=0.0)]
    return node.declare_parameter(name, default, desc).value


def data_qos(node) -> QoSProfile:
    """QoS of the data topics from the node's ``qos_reliable`` / ``qos_depth`` parameters.

    Reliable by default so it matches reliable haptic subscribers; a deep
    history absorbs the 10-60 ms scheduler stalls of shared cores.
    """
    reliable = node.get_parameter("qos_reliable").value
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=int(node.get_parameter("qos_depth").value),
        reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.VOLATILE,
    )


def declare_qos(node):
    declare(node, "qos_reliable", contract.QOS_RELIABLE, "Reliable (true) or best-effort (false) data topics", read_only=True)
    declare(node, "qos_depth", contract.QOS_DEPTH, "History depth of data topics (messages)", 1, 100000, read_only=True)


def message_class(type_name: str):
    """The rclpy message class of a contract type name (``pkg/msg/Type``)."""
    from importlib import import_module

    package, _, name = type_name.split("/")
    return getattr(import_module(f"{package}.msg"), name)


def stamp_to_ns(stamp) -> int:
    return int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec)


def ns_to_stamp(ns: int, stamp):
    stamp.sec, stamp.nanosec = divmod(int(ns), 1_000_000_000)
    return stamp


def send_last_zero(node, wait_s=0.5):
    """``node.publish_zero(wait_s)`` on the way out: the haptic master holds the last force it got,
    so the last one must be zero. The context may already be gone at shutdown; then nothing is sent."""
    try:
        node.publish_zero(wait_s=wait_s)
    except Exception:  # noqa: BLE001 - a dead context or publisher: nothing else to do
        pass


class Diagnostics:
    """Publishes one DiagnosticStatus of a node on /diagnostics."""

    def __init__(self, node, name):
        self.node = node
        self.name = name
        self.pub = node.create_publisher(DiagnosticArray, contract.DIAGNOSTICS, 10)

    def publish(self, level, message, values):
        status = DiagnosticStatus(level=level, name=self.name, message=message, hardware_id=self.node.get_name())
        status.values = [KeyValue(key=str(k), value=str(v)) for k, v in values.items()]
        msg = DiagnosticArray(status=[status])
        msg.header.stamp = self.node.get_clock().now().to_msg()
        self.pub.publish(msg)
        return status


def run(node_class, args=None):
    """Main loop of a node executable: EventsExecutor driven by spin_once.

    SIGTERM and SIGINT end the loop so the node can publish its last message
    (e.g. a zero wrench) before the context shuts down.
    """
    rclpy.init(args=args if args is not None else sys.argv)
    from rclpy.experimental import EventsExecutor

    node = None
    stop = {"flag": False}

    def _stop(*_):
        stop["flag"] = True

    try:
        try:
            node = node_class()
        except (ValueError, OSError, ParameterException) as exc:  # bad parameters or files (ModelError, BagError)
            print(f"{node_class.__name__}: error: {exc}", file=sys.stderr)
            return 2
        # Latency: move everything built at start-up out of the cyclic collector's reach and
        # make gen-0 collections rarer; the per-sample path creates no reference cycles, so
        # reference counting frees it, and collector pauses would land in the 1 kHz path.
        gc.collect()
        gc.freeze()
        gc.set_threshold(50_000, 20, 20)
        signal.signal(signal.SIGTERM, _stop)
        signal.signal(signal.SIGINT, _stop)
        # The EventsExecutor cannot hand message info (send times) to a callback; a node that
        # needs it (the recorder) says so and gets the single-threaded executor.
        if getattr(node, "needs_message_info", False):
            from rclpy.executors import SingleThreadedExecutor

            executor = SingleThreadedExecutor()
        else:
            executor = EventsExecutor()
        executor.add_node(node)
        while rclpy.ok() and not stop["flag"] and not getattr(node, "done", False):
            executor.spin_once(timeout_sec=0.1)
    except KeyboardInterrupt:
        pass
    finally:
        if node is not None:
            node.destroy_node()
        if rclpy.ok():
            rclpy.shutdown()
    return getattr(node, "exit_code", 0) if node is not None else 1
