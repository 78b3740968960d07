"""The README's main job: driver (sim) -> compensation_node -> haptic side, live over DDS.

Runs the three in one process on one executor, tares the compensation node
while the simulated sensor is still unloaded (as a user would), then compares
the received ``wrench`` and the static-gain reading of ``bridge_voltage``
against ``reference_force``, sample by sample (matched by stamp).
"""
from __future__ import annotations

import os
import time
from typing import Mapping, Optional, TypedDict

import numpy as np
import numpy.typing as npt
import rclpy
from geometry_msgs.msg import WrenchStamped
from rclpy.context import Context
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from sensor_msgs.msg import JointState
from std_srvs.srv import Trigger

from . import contract
from .nodes.common import stamp_to_ns
from .nodes.compensation_node import CompensationNode
from .nodes.driver_node import DriverNode
from .physics.metrics import error_summary
from .sim import profiles

#: Samples collected before the tare (the needle-insertion profile is unloaded for its first second).
TARE_AFTER_SAMPLES = 500


class Recorder(Node):
    """Plays the haptic master: records raw, reference and wrench messages."""

    def __init__(self, context: Context) -> None:
        super().__init__("demo_recorder", namespace=contract.NAMESPACE, context=context)
        qos = QoSProfile(depth=10000, reliability=ReliabilityPolicy.RELIABLE)  # type: ignore[no-untyped-call]
        self.raw: dict[int, float] = {}     # stamp (ns) -> bridge voltage (V)
        self.ref: dict[int, float] = {}     # stamp (ns) -> reference force (N)
        self.wrench: dict[int, float] = {}  # stamp (ns) -> compensated force (N)
        self.create_subscription(JointState, contract.Rel.BRIDGE_VOLTAGE, self._on_raw, qos)
        self.create_subscription(WrenchStamped, contract.Rel.REFERENCE_FORCE, self._on_ref, qos)
        self.create_subscription(WrenchStamped, contract.Rel.WRENCH, self._on_wrench, qos)
        self.tare = self.create_client(Trigger, "compensation_node/tare")

    def _on_raw(self, msg: JointState) -> None:
        self.raw[stamp_to_ns(msg.header.stamp)] = msg.position[0]

    def _on_ref(self, msg: WrenchStamped) -> None:
        self.ref[stamp_to_ns(msg.header.stamp)] = msg.wrench.force.z

    def _on_wrench(self, msg: WrenchStamped) -> None:
        self.wrench[stamp_to_ns(msg.header.stamp)] = msg.wrench.force.z


class DemoResult(TypedDict):
    """:func:`summarize`'s outcome: the matched samples after the tare window, their error summaries, and how
    the run went."""

    stamps_ns: npt.NDArray[np.int64]
    reference_n: npt.NDArray[np.float64]
    static_n: npt.NDArray[np.float64]
    compensated_n: npt.NDArray[np.float64]
    static: dict[str, float]
    compensated: dict[str, float]
    received_wrench: int  # wrenches stamped with a sample of the driver's
    unanswered_wrench: int  # wrenches stamped with no recorded sample: the watchdog's zeros while none came
    expected: int
    tare_ok: bool
    offset_v: float


def run_live_demo(profile: str = "needle_insertion", model_file: str = "", seed: int = 0,
                  progress: bool = True) -> DemoResult:
    """Returns a dict with the matched arrays and the error summaries."""
    context = Context()
    rclpy.init(context=context)
    from rclpy.experimental.events_executor import EventsExecutor

    nodes: list[Node] = []
    try:
        driver = DriverNode(context=context, parameter_overrides=[
            Parameter("profile", value=profile), Parameter("loop", value=False),  # type: ignore[no-untyped-call]
            Parameter("seed", value=seed)])  # type: ignore[no-untyped-call]
        comp = CompensationNode(context=context, parameter_overrides=[
            Parameter("model_file", value=model_file)])  # type: ignore[no-untyped-call]
        rec = Recorder(context)
        nodes = [driver, comp, rec]
        executor = EventsExecutor(context=context)
        for node in nodes:
            executor.add_node(node)
        total = driver.period_n
        bar = None
        if progress:
            from tqdm import tqdm

            bar = tqdm(total=total, unit="sample", desc=f"live demo ({profile}, 1 kHz)", mininterval=0.5)
        tare_future: Optional[Future] = None
        deadline = time.monotonic() + total / driver.rate_hz + 30.0
        while time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.01)
            if bar is not None and len(rec.wrench) > bar.n:
                bar.update(len(rec.wrench) - bar.n)
            if tare_future is None and len(rec.raw) >= TARE_AFTER_SAMPLES:
                tare_future = rec.tare.call_async(Trigger.Request())
            if (driver.done and len(rec.wrench) >= total - 1 and len(rec.ref) >= total
                    and len(rec.wrench.keys() & rec.raw.keys()) >= total - 1):  # the watchdog's zeros answer no sample
                break
        if bar is not None:
            bar.close()
        tare_ok = (tare_future is not None and tare_future.done()  # type: ignore[no-untyped-call]
                   and tare_future.result().success)  # type: ignore[no-untyped-call]
        assert comp.compensator is not None, "the compensation node builds its compensator when it starts"
        tare_offset = comp.compensator.offset_v
    finally:
        for node in nodes:
            node.destroy_node()  # type: ignore[no-untyped-call]
        rclpy.shutdown(context=context)
    return summarize(rec.raw, rec.ref, rec.wrench, tare_offset, comp.model.chain.static_gain_v_per_n(), tare_ok, total)


def summarize(raw: Mapping[int, float], ref: Mapping[int, float], wrench: Mapping[int, float], offset_v: float,
              static_gain_v_per_n: float, tare_ok: bool, expected: int) -> DemoResult:
    """Match samples by stamp and compute the errors after the tare window."""
    answered = set(raw) & set(wrench)
    stamps = np.array(sorted(answered & set(ref)), dtype=np.int64)
    if stamps.size == 0:
        raise RuntimeError("no wrench received: the pipeline did not run")
    stamps = stamps[TARE_AFTER_SAMPLES + 100 :]  # after the tare has taken effect
    reference = np.array([ref[int(s)] for s in stamps])
    volts = np.array([raw[int(s)] for s in stamps])
    compensated = np.array([wrench[int(s)] for s in stamps])
    static = (volts - offset_v) / static_gain_v_per_n
    return {
        "stamps_ns": stamps, "reference_n": reference, "static_n": static, "compensated_n": compensated,
        "static": error_summary(reference, static), "compensated": error_summary(reference, compensated),
        "received_wrench": len(answered), "unanswered_wrench": len(wrench) - len(answered), "expected": expected,
        "tare_ok": tare_ok, "offset_v": offset_v,
    }


def plot(result: DemoResult, path: str | os.PathLike[str], title: str) -> None:
    """The demo's forces (applied, static gain, compensated) and their errors over time, written to ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = (result["stamps_ns"] - result["stamps_ns"][0]) * 1e-9
    fig, (ax, ax_err) = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
    ax.plot(t, result["reference_n"], "r", lw=1.5, label="applied (reference)")
    ax.plot(t, result["static_n"], "k", lw=0.8, label="static gain")
    ax.plot(t, result["compensated_n"], "b", lw=0.8, label="compensated (wrench)")
    ax.set_ylabel("force [N]")
    ax.set_title(title)
    ax.legend()
    ax_err.plot(t, result["static_n"] - result["reference_n"], "k", lw=0.8, label="static gain")
    ax_err.plot(t, result["compensated_n"] - result["reference_n"], "b", lw=0.8, label="compensated")
    ax_err.set_xlabel("time [s]")
    ax_err.set_ylabel("error [N]")
    ax_err.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


__all__ = ["run_live_demo", "summarize", "plot", "profiles"]
