"""What every polyforce node shares: parameters, QoS, diagnostics, stamps and the main loop."""
from __future__ import annotations

import gc
import signal
import sys
from types import FrameType
from typing import TYPE_CHECKING, Any, Callable, Optional, Protocol, TypeVar, Union

import rclpy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.exceptions import ParameterException
from rclpy.executors import Executor
from rclpy.lifecycle import LifecycleNode, LifecyclePublisher, LifecycleState, TransitionCallbackReturn
from rclpy.node import Node
from rclpy.publisher import Publisher
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.service import Service
from rclpy.subscription import Subscription
from rclpy.timer import Timer
from rclpy.utilities import ok as rclpy_ok

from .. import contract

DEFAULT_NAMESPACE = contract.NAMESPACE
OK, WARN, ERROR = DiagnosticStatus.OK, DiagnosticStatus.WARN, DiagnosticStatus.ERROR

#: What a managed node closes at cleanup: the subscriptions, services and timers its logic opened.
Entity = Union[Subscription, Service, Timer]
#: ``create_publisher`` or ``create_lifecycle_publisher``: what a logic's ``_start`` opens its topics with.
CreatePublisher = Callable[..., Publisher]
_Config = TypeVar("_Config")


class NodeLogger(Protocol):
    """The logger of a node (rclpy's ``RcutilsLogger``, whose methods rclpy leaves unannotated).

    Each method logs ``message`` at its severity and returns whether it was logged.
    """

    def debug(self, message: str, **kwargs: Any) -> bool: ...
    def info(self, message: str, **kwargs: Any) -> bool: ...
    def warning(self, message: str, **kwargs: Any) -> bool: ...
    def warn(self, message: str, **kwargs: Any) -> bool: ...
    def error(self, message: str, **kwargs: Any) -> bool: ...


if TYPE_CHECKING:
    class RosNode(Node):
        """``rclpy.node.Node`` with the signatures rclpy leaves unannotated (seen by the type checker only)."""

        def get_logger(self) -> NodeLogger: ...
        def destroy_node(self) -> None: ...

    class RosLifecycleNode(LifecycleNode, RosNode):
        """``rclpy.lifecycle.LifecycleNode`` with the signatures rclpy leaves unannotated (type checker only)."""

        def create_lifecycle_publisher(self, *args: Any, **kwargs: Any) -> LifecyclePublisher: ...

    # the node mixins are checked against the node class they are mixed into
    _PolyforceBase = RosNode
    _ManagedBase = RosLifecycleNode
else:
    RosNode = Node
    RosLifecycleNode = LifecycleNode
    _PolyforceBase = _ManagedBase = object


def declare(node: Node, name: str, default: Any, description: str, low: Optional[float] = None,
            high: Optional[float] = None, read_only: bool = False) -> Any:
    """Declare a parameter with a description and, for numbers, the inclusive range ``low`` .. ``high``;
    returns its value."""
    desc = ParameterDescriptor(description=description, read_only=read_only)
    if low is not None and high is not None and isinstance(default, bool) is False:
        if isinstance(default, int):
            desc.integer_range = [IntegerRange(from_value=int(low), to_value=int(high), step=0)]
        elif isinstance(default, float):
            desc.floating_point_range = [FloatingPointRange(from_value=float(low), to_value=float(high), step=0.0)]
    return node.declare_parameter(name, default, desc).value


def declare_settings(node: Node, config_type: type) -> None:
    """Declare a parameter of every field of a configuration dataclass (its default, description and range)."""
    from ..settings import settings_of

    for f, meta in settings_of(config_type):
        default = list(f.default) if isinstance(f.default, tuple) else f.default  # a ROS array parameter is a list
        declare(node, f.name, default, meta["description"], meta["low"], meta["high"], read_only=meta["read_only"])


def read_settings(node: Node, config_type: type[_Config]) -> _Config:
    """The configuration dataclass of the node's parameters of its fields (declared by :func:`declare_settings`)."""
    from ..settings import settings_of

    values: dict[str, Any] = {}
    for f, _ in settings_of(config_type):
        value = node.get_parameter(f.name).value
        values[f.name] = tuple(value) if isinstance(f.default, tuple) else value
    return config_type(**values)


def data_qos(node: Node) -> QoSProfile:
    """QoS of the data topics from the node's ``qos_reliable`` / ``qos_depth`` parameters.

    Reliable by default so it matches reliable haptic subscribers; a deep
    history absorbs the 10-60 ms scheduler stalls of shared cores.
    """
    reliable = node.get_parameter("qos_reliable").value
    return QoSProfile(  # type: ignore[no-untyped-call]  # rclpy leaves QoSProfile(**kwargs) unannotated
        history=HistoryPolicy.KEEP_LAST,
        depth=int(node.get_parameter("qos_depth").value),
        reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.VOLATILE,
    )


def latched_qos() -> QoSProfile:
    """QoS of a state topic (``sensor_serial``): the latest value, kept for subscribers that join later."""
    return QoSProfile(  # type: ignore[no-untyped-call]  # rclpy leaves QoSProfile(**kwargs) unannotated
        history=HistoryPolicy.KEEP_LAST, depth=1, reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL)


def declare_qos(node: Node) -> None:
    """Declare ``qos_reliable`` and ``qos_depth``, read by :func:`data_qos`."""
    declare(node, "qos_reliable", contract.QOS_RELIABLE, "Reliable (true) or best-effort (false) data topics", read_only=True)
    declare(node, "qos_depth", contract.QOS_DEPTH, "History depth of data topics (messages)", 1, 100000, read_only=True)


def message_class(type_name: str) -> Any:
    """The rclpy message class of a contract type name (``pkg/msg/Type``)."""
    from importlib import import_module

    package, _, name = type_name.split("/")
    return getattr(import_module(f"{package}.msg"), name)


def stamp_to_ns(stamp: Any) -> int:
    """A ``builtin_interfaces/Time`` as integer nanoseconds."""
    return int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec)


def ns_to_stamp(ns: int, stamp: Any) -> Any:
    """Set a ``builtin_interfaces/Time`` to ``ns`` nanoseconds; returns it."""
    stamp.sec, stamp.nanosec = divmod(int(ns), 1_000_000_000)
    return stamp


class _PublishesZero(Protocol):
    def publish_zero(self, wait_s: float = ...) -> None: ...


def send_last_zero(node: _PublishesZero, wait_s: float = 0.5) -> None:
    """``node.publish_zero(wait_s)`` on the way out: the haptic master holds the last force it got,
    so the last one must be zero. The context may already be gone at shutdown; then nothing is sent."""
    try:
        node.publish_zero(wait_s=wait_s)
    except Exception:  # noqa: BLE001 - a dead context or publisher: nothing else to do
        pass


class Diagnostics:
    """Publishes one DiagnosticStatus of a node on /diagnostics."""

    def __init__(self, node: Node, name: str) -> None:
        self.node = node
        self.name = name
        self.pub = node.create_publisher(DiagnosticArray, contract.DIAGNOSTICS, 10)

    def publish(self, level: bytes, message: str, values: dict[str, Any]) -> DiagnosticStatus:
        """Publish one status (``level`` OK, WARN or ERROR; ``values`` as key/value strings); returns it."""
        status = DiagnosticStatus(level=level, name=self.name, message=message, hardware_id=self.node.get_name())
        status.values = [KeyValue(key=str(k), value=str(v)) for k, v in values.items()]
        msg = DiagnosticArray(status=[status])
        msg.header.stamp = self.node.get_clock().now().to_msg()
        self.pub.publish(msg)
        return status


class PolyforceNode(_PolyforceBase):
    """Construction shared by the polyforce nodes, plain and managed.

    The base of a node's logic class (``class _XLogic(PolyforceNode)``), placed
    before ``Node`` or ``LifecycleNode`` in the node classes: it names the node,
    puts it in the polyforce namespace unless one is given, declares the
    parameters and, for a plain node, starts it at once.

    Parameters
    ----------
    **kwargs : Any
        Keyword arguments of ``Node`` / ``LifecycleNode`` (``context``,
        ``parameter_overrides``, ``namespace``, ...).

    Attributes
    ----------
    NODE_NAME : str
        The ROS name of the node (class attribute of the logic class).
    diagnostics_name : str
        Name of the node's DiagnosticStatus (attribute or property of the logic class).
    diag : Diagnostics
        The node's /diagnostics publisher, once :meth:`_open_diagnostics` has opened it.

    Notes
    -----
    The logic class supplies ``_declare_parameters()``, ``_start(create_publisher)``,
    which opens the source and the topics and raises ``ValueError`` or ``OSError`` on
    a bad parameter, model file or device, and ``_publish_diagnostics()``. For the type
    checker this mixin is a ``Node`` (:class:`RosNode`); at run time it is placed before
    ``Node`` or ``LifecycleNode``, which provide what it uses of a node.
    """

    NODE_NAME: str
    diag: Diagnostics
    _entities: list[Entity]  # the subscriptions, services and timers ``_start`` opened

    def __init__(self, **kwargs: Any) -> None:
        kwargs.setdefault("namespace", DEFAULT_NAMESPACE)
        super().__init__(self.NODE_NAME, **kwargs)  # Node or LifecycleNode, whichever follows in the MRO
        self._declare_parameters()
        self._ready()

    def _ready(self) -> None:
        """End of construction: a plain node starts at once, with ordinary publishers."""
        self._start(self.create_publisher)

    def _open_diagnostics(self) -> None:
        """Open ``diag`` (:class:`Diagnostics` under :attr:`diagnostics_name`) unless it is open already."""
        if getattr(self, "diag", None) is None:
            self.diag = Diagnostics(self, self.diagnostics_name)

    @property
    def diagnostics_name(self) -> str:
        """Name of the node's DiagnosticStatus (the logic class's)."""
        raise NotImplementedError

    def _declare_parameters(self) -> None:
        """Declare the node's parameters (the logic class's)."""
        raise NotImplementedError

    def _start(self, create_publisher: CreatePublisher) -> None:
        """Open the source and the topics with ``create_publisher`` (the logic class's)."""
        raise NotImplementedError

    def _publish_diagnostics(self) -> DiagnosticStatus:
        """Publish the node's DiagnosticStatus and return it (the logic class's)."""
        raise NotImplementedError


class ManagedNode(PolyforceNode, _ManagedBase):
    """Lifecycle plumbing of a managed node: construction, configure, error processing, cleanup.

    Mixed in first (``class XLifecycleNode(ManagedNode, _XLogic, LifecycleNode)``),
    it owns the rules the managed nodes share, so each lives once:

    * construction opens only the diagnostics; configure opens the rest;
    * configure runs :meth:`_configure`; a bad parameter, model file or device
      (``ValueError``, which ``ModelError`` is, or ``OSError``) ends it in
      ErrorProcessing, with the reason logged and kept in :attr:`error`;
    * error processing publishes that reason on /diagnostics (ERROR) and
      closes what configure opened; cleanup closes it too;
    * closing destroys every publisher configure created and every
      subscription, service and timer the logic kept in ``_entities``, then
      calls :meth:`_release` for what else the node holds;
    * diagnostics of an unconfigured node say so: ERROR with the reason after a
      failed configure, else OK ``unconfigured``.

    Parameters
    ----------
    **kwargs : Any
        Keyword arguments of ``LifecycleNode``, as for :class:`PolyforceNode`.

    Attributes
    ----------
    error : str
        Why the last configure failed; empty after a successful one.

    Notes
    -----
    Besides what :class:`PolyforceNode` needs, the logic class keeps the
    subscriptions, services and timers ``_start`` creates in ``_entities`` and
    supplies ``_publish_diagnostics()``. The node class may extend
    :meth:`_configure` (a check after ``_start``) and :meth:`_release`.
    The transition callbacks take the ``LifecycleState`` the transition starts
    from and return a ``TransitionCallbackReturn``.
    """

    _active = False
    _configured = False
    error: str = ""
    _opened_publishers: list[LifecyclePublisher]

    def _ready(self) -> None:
        """End of construction: only the diagnostics are open until configure."""
        self._entities, self._opened_publishers = [], []
        self._open_diagnostics()

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        """SUCCESS once :meth:`_configure` has opened everything; ERROR, with the reason, on bad input."""
        try:
            self._configure()
        except (ValueError, OSError) as exc:  # ModelError is a ValueError
            self.error = f"configure failed: {exc}"
            self.get_logger().error(self.error)
            return TransitionCallbackReturn.ERROR
        self.error, self._configured = "", True
        return TransitionCallbackReturn.SUCCESS

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Close everything configure opened."""
        self._close()
        return TransitionCallbackReturn.SUCCESS

    def on_error(self, state: LifecycleState) -> TransitionCallbackReturn:
        """ErrorProcessing: the reason on /diagnostics (ERROR), what was opened closed, back to unconfigured."""
        self.diag.publish(ERROR, self.error or "error", {"state": "error processing"})
        self._close()
        return TransitionCallbackReturn.SUCCESS

    def _configure(self) -> None:
        """Open the source and the topics, with lifecycle publishers; raises ValueError or OSError on bad input."""
        self._opened_publishers = []
        self._start(self._create_publisher)

    def _create_publisher(self, *args: Any, **kwargs: Any) -> LifecyclePublisher:
        """``create_lifecycle_publisher``, remembered so that :meth:`_close` destroys it."""
        pub = self.create_lifecycle_publisher(*args, **kwargs)
        self._opened_publishers.append(pub)
        return pub

    def _close(self) -> None:
        """Inactive, every entity configure opened destroyed, then :meth:`_release`; safe to call again."""
        self._active = self._configured = False
        for entity in self._entities:
            if isinstance(entity, Subscription):
                self.destroy_subscription(entity)
            elif isinstance(entity, Service):
                self.destroy_service(entity)
            elif isinstance(entity, Timer):
                self.destroy_timer(entity)
            else:
                raise TypeError(f"cannot close a {type(entity).__name__}")
        for pub in self._opened_publishers:
            self.destroy_lifecycle_publisher(pub)
        self._entities, self._opened_publishers = [], []
        self._release()

    def _release(self) -> None:
        """What the node holds besides ROS entities (a model, a port); nothing by default."""

    def _publish_diagnostics(self) -> DiagnosticStatus:
        """The logic's diagnostics once configured; before, the configure error (ERROR) or OK ``unconfigured``."""
        if not self._configured:
            return self.diag.publish(ERROR if self.error else OK, self.error or "unconfigured", {"active": False})
        return super()._publish_diagnostics()


def run(node_class: Callable[[], RosNode], args: Optional[list[str]] = None) -> int:
    """Main loop of a node executable: EventsExecutor driven by spin_once.

    SIGTERM and SIGINT end the loop so the node can publish its last message
    (e.g. a zero wrench) before the context shuts down.
    """
    rclpy.init(args=args if args is not None else sys.argv)
    from rclpy.experimental.events_executor import EventsExecutor

    node: Optional[RosNode] = None
    stop = {"flag": False}

    def _stop(signum: int, frame: Optional[FrameType]) -> None:
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

            executor: Executor = SingleThreadedExecutor()
        else:
            executor = EventsExecutor()
        executor.add_node(node)
        while rclpy_ok() and not stop["flag"] and not getattr(node, "done", False):
            executor.spin_once(timeout_sec=0.1)
    except KeyboardInterrupt:
        pass
    finally:
        if node is not None:
            node.destroy_node()
        if rclpy_ok():
            rclpy.shutdown()
    exit_code: int = getattr(node, "exit_code", 0) if node is not None else 1
    return exit_code
