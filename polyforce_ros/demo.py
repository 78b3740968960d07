"""The README's main job: driver (sim) -> compensation_node -> haptic side, live over DDS.

Runs the three in one process on one executor, tares the compensation node
while the simulated sensor is still unloaded (as a user would), then compares
the received ``wrench`` and the static-gain reading of ``bridge_voltage``
against ``reference_force``, sample by sample (matched by stamp).
"""
from __future__ import annotations

import time

import numpy as np
import rclpy
from geometry_msgs.msg import WrenchStamped
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile, ReliabilityPolicy
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

    def __init__(self, context):
        super().__init__("demo_recorder", namespace=contract.NAMESPACE, context=context)
        qos = QoSProfile(depth=10000, reliability=ReliabilityPolicy.RELIABLE)
        self.raw, self.ref, self.wrench = {}, {}, {}
        self.create_subscription(JointState, contract.Rel.BRIDGE_VOLTAGE,
                                 lambda m: self.raw.__setitem__(stamp_to_ns(m.header.stamp), m.position[0]), qos)
        self.create_subscription(WrenchStamped, contract.Rel.REFERENCE_FORCE,
                                 lambda m: self.ref.__setitem__(stamp_to_ns(m.header.stamp), m.wrench.force.z), qos)
        self.create_subscription(WrenchStamped, contract.Rel.WRENCH,
                                 lambda m: self.wrench.__setitem__(stamp_to_ns(m.header.stamp), m.wrench.force.z), qos)
        self.tare = self.create_client(Trigger, "compensation_node/tare")


def run_live_demo(profile="needle_insertion", model_file="", seed=0, progress=True):
    """Returns a dict with the matched arrays and the error summaries."""
    context = rclpy.Context()
    rclpy.init(context=context)
    from rclpy.experimental import EventsExecutor

    nodes = []
    try:
        driver = DriverNode(context=context, parameter_overrides=[
            Parameter("profile", value=profile), Parameter("loop", value=False), Parameter("seed", value=seed)])
        comp = CompensationNode(context=context, parameter_overrides=[Parameter("model_file", value=model_file)])
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
        tare_future, deadline = None, time.monotonic() + total / driver.rate_hz + 30.0
        while time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.01)
            if bar is not None and len(rec.wrench) > bar.n:
                bar.update(len(rec.wrench) - bar.n)
            if tare_future is None and len(rec.raw) >= TARE_AFTER_SAMPLES:
                tare_future = rec.tare.call_async(Trigger.Request())
            if driver.done and len(rec.wrench) >= total - 1 and len(rec.ref) >= total:
                break
        if bar is not None:
            bar.close()
        tare_ok = tare_future is not None and tare_future.done() and tare_future.result().success
        tare_offset = comp.compensator.offset_v
    finally:
        for node in nodes:
            node.destroy_node()
        rclpy.shutdown(context=context)
    return summarize(rec.raw, rec.ref, rec.wrench, tare_offset, comp.model.chain.static_gain_v_per_n(), tare_ok, total)


def summarize(raw, ref, wrench, offset_v, static_gain_v_per_n, tare_ok, expected):
    """Match samples by stamp and compute the errors after the tare window."""
    stamps = np.array(sorted(set(raw) & set(ref) & set(wrench)), dtype=np.int64)
    if stamps.size == 0:
        raise RuntimeError("no wrench received: the pipeline did not run")
    stamps = stamps[TARE_AFTER_SAMPLES + 100 :]  # after the tare has taken effect
    reference = np.array([ref[s] for s in stamps])
    volts = np.array([raw[s] for s in stamps])
    compensated = np.array([wrench[s] for s in stamps])
    static = (volts - offset_v) / static_gain_v_per_n
    return {
        "stamps_ns": stamps, "reference_n": reference, "static_n": static, "compensated_n": compensated,
        "static": error_summary(reference, static), "compensated": error_summary(reference, compensated),
        "received_wrench": len(wrench), "expected": expected, "tare_ok": tare_ok, "offset_v": offset_v,
    }


def plot(result, path, title):
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
