"""The noise gain of a chain's inverse, and the runtime's guard against a model that shakes the master."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from polyforce_ros.physics.chain import (ModelError, OffsetElement, PlayHysteresisElement, SensorChain,
                                         SensorLagElement, ViscoelasticElement)
from polyforce_ros.physics.noise_gain import backward_noise_gain, white_noise_gain
from polyforce_ros.physics.viscoelastic import PAPER_BURGERS, Elastic
from polyforce_ros.runtime import Compensator, CompensatorConfig
from polyforce_ros.runtime.compensator import check_noise_gain


def _lagged(tau_s, k=5.0, filter_tau_s=0.0):
    return SensorChain([ViscoelasticElement(Elastic(k)), SensorLagElement(tau_s=tau_s, noise_filter_tau_s=filter_tau_s),
                        OffsetElement(0.02)])


@settings(max_examples=25, deadline=None)
@given(tau_s=st.floats(1e-4, 0.3), k=st.floats(0.5, 50.0), rate_hz=st.sampled_from([100.0, 200.0, 1000.0, 2000.0]))
def test_the_gain_of_an_exact_lag_inverse_is_its_difference_equations(tau_s, k, rate_hz):
    # y + tau (y_n - y_{n-1}) / h on white noise: variance (1 + a)^2 + a^2 with a = tau / h, times the stiffness
    a = tau_s * rate_hz
    gain = backward_noise_gain(_lagged(tau_s, k), rate_hz)
    assert gain.gain_n_per_v == pytest.approx(k * math.hypot(1 + a, a), rel=0.05)
    assert white_noise_gain(_lagged(tau_s, k), rate_hz) == gain.gain_n_per_v  # the same probe, the gain alone
    if a > 0.5:
        assert gain.element == "sensor_lag" and gain.element_factor == pytest.approx(math.hypot(1 + a, a), rel=0.05)
    # the response rises towards Nyquist, where the difference of alternate samples is largest
    assert gain.response_n_per_v[-1] > gain.response_n_per_v[0]


def test_a_bandwidth_bounds_the_gain_by_tau_over_its_filter_time():
    exact = backward_noise_gain(_lagged(0.05), 1000.0).gain_n_per_v
    rolled = backward_noise_gain(_lagged(0.05, filter_tau_s=0.025), 1000.0).gain_n_per_v
    assert exact > 300.0 and rolled <= 5.0 * 0.05 / 0.025 * 1.01


def test_a_second_order_roll_off_passes_far_less_noise_for_the_same_filter_time_and_streams_exactly():
    first = SensorLagElement(tau_s=0.05, noise_filter_tau_s=0.01)
    second = SensorLagElement(tau_s=0.05, noise_filter_tau_s=0.01, noise_filter_order=2)
    chain = lambda e: SensorChain([ViscoelasticElement(Elastic(5.0)), e, OffsetElement(0.0)])  # noqa: E731
    g1, g2 = (backward_noise_gain(chain(e), 1000.0) for e in (first, second))
    assert g2.gain_n_per_v < 0.3 * g1.gain_n_per_v  # the inverse falls off above 1 / (2 pi tau_f)
    assert g2.response_n_per_v[-1] < g2.response_n_per_v[len(g2.response_n_per_v) // 2]
    assert second.latency_s == pytest.approx(0.02) and chain(second).latency_s == pytest.approx(0.02)
    t = np.sort(np.random.default_rng(0).uniform(0.0, 5.0, 3000))  # irregular stamps
    x = np.sin(2.0 * t)
    y = SensorLagElement(tau_s=0.05).forward(t, x)
    batch = second.backward(t, y)
    stream = second.streaming()
    np.testing.assert_allclose([stream.step(float(a), float(b)) for a, b in zip(t, y)], batch, atol=1e-12)
    late = np.sin(2.0 * (t - 0.02))  # what is left: 1 / (1 + tau_f s)**2, about 2 tau_f late at low frequency
    assert np.abs(batch - late)[t > 1.0].max() < 2e-3
    with pytest.raises(ModelError):
        SensorLagElement(tau_s=0.05, noise_filter_tau_s=0.01, noise_filter_order=3)


def test_the_shipped_core_and_a_hysteresis_are_judged_by_the_core():
    chain = SensorChain([PlayHysteresisElement(1.0, [0.5, 1.0], [0.1, 0.05]), ViscoelasticElement(PAPER_BURGERS),
                         OffsetElement(0.05)])
    gain = backward_noise_gain(chain, 1000.0)
    g0 = PAPER_BURGERS.relaxation().g0_n_per_v  # instantaneous stiffness: white noise sees the glassy modulus
    assert gain.gain_n_per_v == pytest.approx(g0, rel=0.1) and gain.element == "burgers"
    assert gain.to_dict()["gain_n_per_v"] == gain.gain_n_per_v and len(gain.to_dict()["frequency_hz"]) > 10


def test_the_runtime_refuses_a_model_that_amplifies_noise_and_names_the_element():
    chain = _lagged(0.0117)
    with pytest.raises(ModelError, match=r"sensor_lag element multiplies it by") as info:
        Compensator(chain)
    assert "max_noise_gain 10" in str(info.value)
    comp = Compensator(SensorChain.from_model(PAPER_BURGERS, 0.05))
    kept = comp.chain
    with pytest.raises(ModelError):
        comp.set_chain(chain)
    assert comp.chain is kept  # a refused model never replaces the one in use
    # the same model is accepted with a bandwidth, or at a rate where its inverse stays quiet, or with a wider limit
    assert Compensator(_lagged(0.0117, filter_tau_s=0.01)).noise_gain.gain_n_per_v < 10.0
    assert Compensator(chain, CompensatorConfig(noise_gain_rate_hz=20.0)).noise_gain.gain_n_per_v < 10.0
    assert Compensator(chain, CompensatorConfig(max_noise_gain=1e4)).noise_gain.element == "sensor_lag"


def test_a_degenerate_inverse_is_refused_not_raised_as_a_numerical_error():
    gain = check_noise_gain(SensorChain.from_model(PAPER_BURGERS, 0.0), 1000.0, np.inf)
    assert np.isfinite(gain.gain_n_per_v)
    with pytest.raises(ValueError):
        backward_noise_gain(SensorChain.from_model(PAPER_BURGERS, 0.0), float("nan"))


def test_plays_at_the_bridge_are_judged_against_their_core_alone():
    """The bridge_hysteresis element holds the core: the attribution compares it with its core, never removes the core."""
    from polyforce_ros.physics.chain import BridgeHysteresisElement, ViscoelasticElement
    from polyforce_ros.physics.noise_gain import backward_noise_gain
    from polyforce_ros.physics.viscoelastic import PAPER_BURGERS

    core = ViscoelasticElement(PAPER_BURGERS)
    bridge = BridgeHysteresisElement(core, [0.1, 0.5, 1.0], [0.01, 0.01, 0.01])
    with_plays = backward_noise_gain(SensorChain([bridge, OffsetElement(0.01)]), 1000.0)
    alone = backward_noise_gain(SensorChain([core, OffsetElement(0.01)]), 1000.0)
    assert with_plays.element == alone.element == "burgers"  # the plays (slope >= 1 in the solve) amplify nothing
    assert with_plays.gain_n_per_v <= 1.05 * alone.gain_n_per_v


def test_the_diagnose_printout_says_which_model_is_above_the_guard_at_the_record_rate():
    """A core stiffer than ``max_noise_gain`` passes the bridge noise on at its own gain: its left-out force figures
    are printed with that beside them; a model within the guard is printed plainly."""
    from polyforce_ros.cli import compensated_force_lines
    from polyforce_ros.discrepancy.newtons import force_quality

    t = np.arange(0.0, 20.0, 0.01)
    force = 2.0 + np.sin(t)
    limit = CompensatorConfig.max_noise_gain
    quality = {}
    for label, k in (("base", 5.0 * limit), ("saved", 0.5 * limit)):
        chain = SensorChain([ViscoelasticElement(Elastic(k)), OffsetElement(0.0)])
        volts = chain.forward(t, force) + np.random.default_rng(1).normal(0.0, 2e-3, t.size)
        quality[label] = force_quality([chain], np.zeros(t.size, dtype=int), t, volts, force).to_dict()
    base_line, saved_line = compensated_force_lines(quality, limit)
    assert base_line.startswith("compensated force, left-out blocks, base model") and "above the default" in base_line
    assert saved_line.startswith("compensated force, left-out blocks, saved model") and "above" not in saved_line
    assert f"{quality['base']['noise_gain_n_per_v']:.3g} N/V" in base_line


@pytest.mark.parametrize("tau_s", [0.0, 3e-4])
def test_a_core_refused_for_its_own_gain_is_told_to_raise_the_guard_not_to_add_a_bandwidth(tau_s):
    """A core three times stiffer than the guard, alone or behind a lag whose inverse adds a third to its gain:
    without the lag it is still refused, so the message says to raise the guard and not to bound the lag."""
    limit = CompensatorConfig.max_noise_gain
    chain = _lagged(tau_s, k=3.0 * limit) if tau_s else SensorChain([ViscoelasticElement(Elastic(3.0 * limit)),
                                                                      OffsetElement(0.0)])
    with pytest.raises(ModelError, match=r"raised max_noise_gain") as info:
        Compensator(chain)
    message = str(info.value)
    assert "noise_filter_tau_s" not in message
    assert ("elastic core's own inverse" in message) if not tau_s else ("sensor_lag element multiplies it by" in message
                                                                         and "without it" in message)
