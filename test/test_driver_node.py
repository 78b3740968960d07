"""driver_node: sim backend contract and rate; serial backend over a real pseudo-terminal."""
import os
import time

import numpy as np
import pytest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import WrenchStamped
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState, Temperature

from polyforce_ros.nodes.common import stamp_to_ns
from polyforce_ros.nodes.driver_node import DriverNode
from polyforce_ros.physics.viscoelastic import PAPER_BURGERS
from polyforce_ros.serial_protocol import encode_frame
from polyforce_ros.sim import profiles
from polyforce_ros.sim.sensor import BridgeSimulator
from ros_harness import ros


class Listener(Node):
    def __init__(self, context):
        super().__init__("listener", namespace="/polyforce", context=context)
        qos = QoSProfile(depth=5000, reliability=ReliabilityPolicy.RELIABLE)
        self.raw, self.ref, self.temp, self.diags = [], [], [], []
        self.raw_received_ns = []  # wall-clock time each bridge sample arrived
        self.create_subscription(JointState, "bridge_voltage", self._on_raw, qos)
        self.create_subscription(WrenchStamped, "reference_force", self.ref.append, qos)
        self.create_subscription(Temperature, "temperature", self.temp.append, 10)
        self.create_subscription(DiagnosticArray, "/diagnostics", self.diags.append, 50)

    def _on_raw(self, msg):
        self.raw.append(msg)
        self.raw_received_ns.append(time.time_ns())


def start_driver(h, **params):
    node = h.add(DriverNode(context=h.context, parameter_overrides=[Parameter(k, value=v) for k, v in params.items()]))
    listener = h.add(Listener(h.context))
    return node, listener


def test_sim_backend_contract_values_and_rate():
    with ros() as h:
        node, lis = start_driver(h, profile="step", seed=3, diagnostics_period_s=0.2)
        assert h.spin_until(lambda: len(lis.raw) > 0, 5.0)
        n_start = len(lis.raw)
        # waits for 1.5 s of acquisition to arrive, however long a loaded machine takes to deliver it
        assert h.spin_until(lambda: len(lis.raw) > n_start and span_s_of(lis.raw, n_start) >= 1.5, 30.0)
        raw, ref, received_ns = list(lis.raw), list(lis.ref), list(lis.raw_received_ns)
        assert h.spin_until(lambda: any(d.status[0].level == DiagnosticStatus.OK for d in lis.diags), 5.0)
    # The rate is in the stamps (exactly 1 kHz, below, and none missing). The acquisition never runs ahead of
    # real time: no sample arrives before the time it is stamped with (2 ms for the clocks' rounding); and the
    # last stamp is now (below).
    stamps = np.array([stamp_to_ns(m.header.stamp) for m in raw])
    ahead_ns = stamps - np.array(received_ns[:len(raw)])
    assert ahead_ns.max() <= 2_000_000, f"a sample arrived {ahead_ns.max() * 1e-6:.1f} ms before its stamp"
    assert {tuple(m.name) for m in raw} == {("sarrus_axial",)}
    assert {m.header.frame_id for m in raw} == {"polyforce_sensor"}
    assert set(np.diff(stamps)) <= {999_999, 1_000_000, 1_000_001}  # exactly 1 kHz acquisition stamps
    assert abs(stamps[-1] * 1e-9 - time.time()) < 2.0  # acquisition time is now, not a made-up epoch
    # The samples are exactly the simulator's output for the profile (same seed), in order.
    n = len(raw)
    t, f = profiles.step(rate_hz=1000.0)
    expected = BridgeSimulator(model=PAPER_BURGERS, offset_v=0.05, noise_std_v=1e-3, seed=3).simulate(t[:n], f[:n])
    np.testing.assert_allclose([m.position[0] for m in raw], expected, rtol=0, atol=1e-12)
    ref_by_stamp = {stamp_to_ns(m.header.stamp): m.wrench.force.z for m in ref}
    np.testing.assert_array_equal([ref_by_stamp[s] for s in stamps if s in ref_by_stamp],
                                  f[:n][np.isin(stamps, list(ref_by_stamp))])
    assert len(ref_by_stamp) >= n - 5


def span_s_of(raw, n_start):
    """Seconds of acquisition stamps from sample ``n_start`` to the last of ``raw``."""
    return (stamp_to_ns(raw[-1].header.stamp) - stamp_to_ns(raw[n_start].header.stamp)) * 1e-9


class FakeDevice:
    """A microcontroller on a pseudo-terminal, reachable under a stable symlink (like /dev/serial/by-id)."""

    def __init__(self, link):
        self.link = link
        self.seq = 0
        self.plug()

    def plug(self):
        self.master, slave = os.openpty()
        name = os.ttyname(slave)
        os.close(slave)  # the driver opens it by path
        tmp = f"{self.link}.tmp"
        os.symlink(name, tmp)
        os.replace(tmp, self.link)

    def unplug(self):
        os.close(self.master)

    def send(self, counts, corrupt=False):
        frame = bytearray(encode_frame(self.seq, self.seq * 1000, counts))
        if corrupt:
            frame[10] ^= 0x55
        os.write(self.master, bytes(frame))
        self.seq += 1


def test_serial_backend_scales_counts_and_survives_unplug(tmp_path):
    device = FakeDevice(str(tmp_path / "ttyPOLYFORCE"))
    scale, offset = 1e-6, 0.25
    with ros() as h:
        node, lis = start_driver(h, backend="serial", port=device.link, volts_per_count=scale, volts_offset=offset,
                                 reconnect_period_s=0.05, diagnostics_period_s=0.1)
        assert node.connected
        for i in range(100):
            device.send(1000 * i, corrupt=(i == 50))
            h.spin_for(0.001)
        # each wait returns as soon as its condition holds; a loaded machine needs the margin
        assert h.spin_until(lambda: len(lis.raw) >= 99, 30.0)
        values = [m.position[0] for m in lis.raw]
        assert values == pytest.approx([1000 * i * scale + offset for i in range(100) if i != 50])
        stamps = [stamp_to_ns(m.header.stamp) for m in lis.raw]
        assert all(b > a for a, b in zip(stamps, stamps[1:]))
        assert node.parser.crc_errors == 1 and node.parser.lost_frames == 1

        device.unplug()
        assert h.spin_until(lambda: not node.connected, 30.0)
        assert h.spin_until(lambda: any(d.status[0].level == DiagnosticStatus.ERROR for d in lis.diags), 30.0)
        assert node.outages == 1

        device.plug()
        assert h.spin_until(lambda: node.connected, 30.0)
        before = len(lis.raw)
        for _ in range(20):
            device.send(7)
            h.spin_for(0.001)
        assert h.spin_until(lambda: len(lis.raw) >= before + 20, 30.0)
        assert lis.raw[-1].position[0] == pytest.approx(7 * scale + offset)
        device.unplug()


def test_sim_backend_with_extra_effects_and_temperature_swing(tmp_path):
    from polyforce_ros.model_file import SensorModel, save_model
    from polyforce_ros.physics.chain import (
        NonlinearGainElement, OffsetElement, SensorChain, ThermalDriftElement, ViscoelasticElement,
    )

    truth = tmp_path / "truth.yaml"
    chain = SensorChain([ViscoelasticElement(PAPER_BURGERS), NonlinearGainElement(quadratic_per_v=0.1),
                         ThermalDriftElement(coefficient_v_per_c=0.02, reference_c=24.0), OffsetElement(0.0)])
    save_model(truth, SensorModel(chain))
    with ros() as h:
        node, lis = start_driver(h, profile="step", truth_model_file=str(truth), noise_std_v=0.0, adc_bits=0,
                                 temperature_amplitude_c=5.0, temperature_period_s=2.0)
        assert h.spin_until(lambda: len(lis.raw) > 1500 and len(lis.temp) > 10, 10.0)
        raw, temps = list(lis.raw), list(lis.temp)
    n = len(raw)
    t, f = profiles.step(rate_hz=1000.0)
    temp = 24.0 + 5.0 * np.sin(2 * np.pi * t[:n] / 2.0)
    chain = chain.with_offset(0.05)  # the driver's offset_v
    expected = chain.forward(t[:n], f[:n], {"temperature_c": temp})
    np.testing.assert_allclose([m.position[0] for m in raw], expected, atol=1e-12)
    assert np.ptp([m.temperature for m in temps]) > 2.0  # the swing is published


def test_profile_waits_for_its_subscriber_and_restarts_on_request():
    """A late joiner is matched by DDS only after seconds; with wait_for_subscribers the first sample it
    receives is the profile's first, and ~/restart_profile starts the profile again."""
    from std_srvs.srv import Trigger

    with ros() as h:
        driver = h.add(DriverNode(context=h.context, parameter_overrides=[
            Parameter("wait_for_subscribers", value=1), Parameter("profile", value="step")]))
        h.spin_for(0.3)
        assert driver.published == 0 and driver.start_ns is None  # nobody listens yet: nothing is lost
        listener = h.add(Listener(h.context))
        assert h.spin_until(lambda: len(listener.raw) >= 200 and len(listener.ref) >= 200, 20.0)
        first = listener.raw[0]
        assert stamp_to_ns(first.header.stamp) == driver.start_ns  # sample 0 of the profile
        assert listener.ref[0].wrench.force.z == driver.profile_f[0]
        client = listener.create_client(Trigger, "driver_node/restart_profile")
        # counted before the call: the restarted profile's first samples can arrive while the call is spun
        n_before, start_before = len(listener.raw), driver.start_ns
        assert h.call(client, Trigger.Request()).success

        def restarted() -> bool:  # a later start, and a sample of its first 0.1 s (the topic may drop one)
            start = driver.start_ns  # None until the restarted profile's first sample is published
            return start is not None and start > start_before and any(
                0 <= stamp_to_ns(m.header.stamp) - start < 100_000_000 for m in listener.raw[n_before:])

        assert h.spin_until(restarted, 10.0)


def test_sim_source_profiles_are_those_the_simulator_makes():
    """The profiles the sim source's ``profile`` setting names are exactly those ``make_profile`` takes."""
    from polyforce_ros.runtime.sources import SIM_PROFILES

    assert SIM_PROFILES == (*profiles.PROFILE_NAMES, "okamura")
    for name in SIM_PROFILES[:-1]:
        profiles.make_profile(name, rate_hz=100.0)
