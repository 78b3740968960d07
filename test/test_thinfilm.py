"""Seed 002: first-order sensor, patch-force model, joint identification, system simulation, inverse."""
from dataclasses import replace

import numpy as np
import pytest

from polyforce_ros.physics.metrics import bandwidth_3db
from polyforce_ros.physics.thinfilm import PatchSensor, PneumaticMuscle, identify_patch_sensor, inversion_bode, linear_summary


def test_first_order_sensor_step_and_bandwidth():
    sensor = PatchSensor()
    t = np.arange(0, 1, 1e-4)
    v = sensor.voltage(t, np.where(t >= 0.1, 100.0, 0.0))
    after = t >= 0.1 + sensor.tau_s
    # one time constant after the step: 63.2 % of kappa * 100 N above the baseline
    assert v[after][0] - sensor.b_v == pytest.approx(0.632 * sensor.kappa_v_per_n * 100, rel=0.01)
    assert sensor.bandwidth_hz() == pytest.approx(1 / (2 * np.pi * 0.03321))


def test_system_simulation_pressure_range_and_valve_cycle():
    muscle = PneumaticMuscle()
    t = np.arange(0, 24, 1e-3)
    p, length = muscle.simulate(t)
    assert p.min() == pytest.approx(121.325e3, rel=1e-3) and p.max() == pytest.approx(600e3, rel=1e-3)
    assert length.min() == pytest.approx(0.75 * 0.120 - 0.006, abs=1e-4) and length.max() < 0.13
    force = PatchSensor().patch_force(t, p, length)
    assert 400 < force.max() < 600  # the paper reports ~450 N peaks
    summary = linear_summary(p, force)
    assert summary["slope_n_per_kpa"] > 0 and summary["r2"] > 0.9


def test_joint_identification_recovers_what_the_data_determine():
    truth = PatchSensor()
    muscle = PneumaticMuscle()
    t = np.arange(0, 40, 1e-2)
    p, length = muscle.simulate(t)
    rng = np.random.default_rng(0)
    v = truth.voltage(t, truth.patch_force(t, p, length)) + rng.normal(0, 0.05, t.size)
    start = replace(truth, c2_per_pa=2e-6, c3_s=-1e-3, k0=-1.0, k1=0.5, tau_s=0.1, b_v=0.0)
    fit, r2, rmse = identify_patch_sensor(t, p, length, v, start)
    for name in ("c2_per_pa", "k0", "k1", "b_v"):
        assert getattr(fit, name) == pytest.approx(getattr(truth, name), rel=0.03), name
    # c3 p' and tau V' are both derivative terms and partly trade off; tau stays close.
    assert fit.tau_s == pytest.approx(truth.tau_s, rel=0.1)
    assert rmse == pytest.approx(0.05, rel=0.1) and r2 > 0.99


def test_inverse_sensor_widens_the_bandwidth():
    sensor = PatchSensor()
    freqs = np.array([0.5, 1, 2, 4, 8, 16, 32])
    raw_db, inv_db = inversion_bode(sensor, freqs, cutoff_hz=50.0)
    assert bandwidth_3db(freqs, raw_db, 0.0) == pytest.approx(sensor.bandwidth_hz(), rel=0.05)  # 1 / (2 pi tau)
    assert bandwidth_3db(freqs, inv_db, 0.0) > 30.0  # limited by the 50 Hz noise filter, not the sensor


def test_thin_film_sensor_as_a_chain_matches_eq_11():
    """gain -> sensor_lag -> offset is eq. 11, so the node can compensate a thin-film sensor by configuration."""
    from polyforce_ros.physics.chain import GainElement, OffsetElement, SensorChain, SensorLagElement

    sensor = PatchSensor()
    chain = SensorChain([GainElement(gain=sensor.kappa_v_per_n), SensorLagElement(tau_s=sensor.tau_s), OffsetElement(sensor.b_v)])
    t = np.arange(0, 5, 1e-3)
    force = 200 * np.clip(t - 1, 0, 1) + 50 * np.sin(2 * np.pi * 1.5 * t)
    force -= force[0]
    np.testing.assert_allclose(chain.forward(t, force), sensor.voltage(t, force), atol=1e-12)
    settled = t > 0.5
    np.testing.assert_allclose(chain.backward(t, chain.forward(t, force))[settled], force[settled], atol=0.5)
