"""Evaluation metrics on cases with known answers."""
import numpy as np
import pytest

from polyforce_ros.physics.chain import SensorLagElement
from polyforce_ros.physics.metrics import (
    bandwidth_3db, hysteresis_percent, r_squared, resolution_changes, sine_component, step_response,
)
from polyforce_ros.sim import profiles


def triangle(n=2001):
    return np.concatenate([np.linspace(0, 1, n // 2 + 1), np.linspace(1, 0, n // 2 + 1)[1:]])


def test_hysteresis_of_a_spring_is_zero_and_of_a_known_loop_is_its_gap():
    u = 7.3 * triangle()
    assert hysteresis_percent(u, 0.31 * u) == pytest.approx(0.0, abs=1e-12)
    peak = np.argmax(u)
    loop = u / 7.3 + np.where(np.arange(u.size) > peak, 0.4 * (u / 7.3) * (1 - u / 7.3), 0.0)  # gap 0.1 at mid-range
    assert hysteresis_percent(u, loop) == pytest.approx(10.0, rel=1e-3)
    with pytest.raises(ValueError):
        hysteresis_percent(np.linspace(0, 1, 50), np.linspace(0, 1, 50))


def test_step_response_of_a_first_order_lag():
    tau = 0.2
    t = np.arange(0, 5, 1e-4)
    y = np.where(t >= 1.0, 1 - np.exp(-(t - 1.0) / tau), 0.0)
    r = step_response(t, 5.0 * y, 1.0, 5.0)
    assert r["rise_time_s"] == pytest.approx(tau * np.log(9), abs=2e-4)
    assert r["settling_time_s"] == pytest.approx(tau * np.log(50), abs=2e-4)
    drifting = 5.0 * (y + 0.01 * np.clip(t - 1.0, 0, None))  # creeps out of the band
    assert step_response(t, drifting, 1.0, 5.0)["settling_time_s"] == float("inf")


def test_sine_component_and_bandwidth_of_a_first_order_lag():
    tau = 0.05
    lag = SensorLagElement(tau_s=tau)
    freqs = np.logspace(-1, 2, 40)
    mags = []
    for f in freqs:
        t = np.arange(0, max(20 / f, 2.0), 1 / (200 * f) if f > 5 else 1e-3)
        y = lag.forward(t, np.sin(2 * np.pi * f * t))
        steady = t > t[-1] / 2
        amp, _ = sine_component(t[steady], y[steady], f)
        mags.append(20 * np.log10(amp))
        expected = 1 / np.sqrt(1 + (2 * np.pi * f * tau) ** 2)
        assert amp == pytest.approx(expected, rel=2e-3)
    assert bandwidth_3db(freqs, mags, reference_db=0.0) == pytest.approx(1 / (2 * np.pi * tau), rel=0.01)
    assert bandwidth_3db(freqs, np.zeros_like(freqs)) == float("inf")  # a spring: flat


def test_resolution_changes_of_a_perfect_sensor():
    t, f = profiles.resolution(rate_hz=100.0)
    changes = resolution_changes(t, f, start_s=10.0, half_period_s=60.0, cycles=4)
    assert changes.size == 4 * 400
    assert changes.mean() == pytest.approx(0.1, abs=1e-9) and changes.std() == pytest.approx(0.0, abs=1e-9)


def test_r_squared_reference():
    ref = np.array([1.0, 2.0, 3.0, 4.0])
    assert r_squared(ref, ref) == 1.0
    assert r_squared(ref, np.full(4, ref.mean())) == 0.0
