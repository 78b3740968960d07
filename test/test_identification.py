"""Creep identification: segment finding, parameter recovery, model selection."""
import numpy as np
import pytest

from polyforce_ros.physics.identification import find_creep_segments, fit_creep, select_model
from polyforce_ros.physics.viscoelastic import PAPER_BURGERS, Zener
from polyforce_ros.sim import profiles
from polyforce_ros.sim.sensor import BridgeSimulator

#: Realistic bench noise: 1 mV rms on a 16-bit +-5 V ADC (0.15 mV steps).
NOISE_V = 1e-3


def long_record():
    """Rest, three creep tests (2, 5, 8 N) with slow 0.5 s ramps, then a sawtooth (not a creep test)."""
    parts, t0 = [], 0.0
    for force in (2.0, 5.0, 8.0):
        t, f = profiles.creep(force, hold_s=90.0, rest_s=120.0, rise_s=0.5, rate_hz=200.0)
        parts.append((t + t0, f))
        t0 += t[-1] + 1 / 200.0
    t, f = profiles.sawtooth(peak_n=6.0, cycles=3, rate_hz=200.0)
    parts.append((t + t0, f))
    return np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])


def test_segments_found_in_long_record_and_sawtooth_ignored():
    t, f = long_record()
    segs = find_creep_segments(t, f)
    assert [round(s.hold_force_n, 2) for s in segs] == [2.0, 5.0, 8.0]
    for s in segs:
        assert s.hold_s == pytest.approx(90.0, abs=0.5)
        assert s.start < s.load < s.release < s.stop
        assert f[s.start] == pytest.approx(0.0, abs=1e-9)  # starts before the step
    assert segs[-1].stop <= np.searchsorted(t, t[-1] - 0.5) + 1
    assert find_creep_segments(*profiles.sawtooth(rate_hz=200.0)) == []


@pytest.mark.parametrize("truth", [PAPER_BURGERS, Zener(4.8, 10.0, 85.12)], ids=lambda m: m.kind)
def test_fit_recovers_parameters_within_2_percent(truth):
    t, f = long_record()
    v = BridgeSimulator(model=truth, noise_std_v=NOISE_V, offset_v=0.12, seed=7).simulate(t, f)
    fit = fit_creep(type(truth), t, f, v)
    for name, value in truth.as_dict().items():
        assert fit.parameters[name] == pytest.approx(value, rel=0.02), name
        # the standard error is an honest uncertainty: truth within 5 sigma
        assert abs(fit.parameters[name] - value) < 5 * fit.stderr[name] + 1e-9 * value, name
    assert fit.offset_v == pytest.approx(0.12, abs=2e-3)
    assert fit.rmse_v == pytest.approx(NOISE_V, rel=0.3)  # residual is the noise
    assert fit.r2 > 0.99


@pytest.mark.parametrize("truth", [PAPER_BURGERS, Zener(4.8, 10.0, 85.12)], ids=lambda m: m.kind)
def test_selection_picks_the_true_model(truth):
    t, f = profiles.creep(5.0, hold_s=120.0, rest_s=60.0, rate_hz=500.0)
    v = BridgeSimulator(model=truth, noise_std_v=NOISE_V, seed=11).simulate(t, f)
    selection = select_model(t, f, v)
    assert selection.best.kind == truth.kind
    assert [r.bic for r in selection.fits] == sorted(r.bic for r in selection.fits)
    assert {r.kind for r in selection.fits} == {"maxwell", "kelvin", "zener", "burgers"}


def test_fit_rejects_records_without_creep_or_with_bad_samples():
    t, f = profiles.sawtooth(rate_hz=100.0)
    v = BridgeSimulator(seed=1).simulate(t, f)
    with pytest.raises(ValueError, match="no creep segment"):
        fit_creep("burgers", t, f, v)
    t, f = profiles.creep(rate_hz=100.0)
    v = BridgeSimulator(seed=1).simulate(t, f)
    v[100] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        select_model(t, f, v)
