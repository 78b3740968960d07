"""Effect elements of the sensor chain: inverses, streaming == batch, YAML, block-wise simulation."""
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from polyforce_ros.model_file import SensorModel, load_model, save_model
from polyforce_ros.physics.chain import (
    GainElement, ModelError, NonlinearGainElement, OffsetDriftElement, OffsetElement, SensorChain, SensorLagElement,
    ThermalDriftElement, ThermalLagElement, ThermalSensitivityElement, ViscoelasticElement,
)
from polyforce_ros.physics.viscoelastic import PAPER_BURGERS
from polyforce_ros.sim.sensor import BridgeSimulator


def signals(n=20000, dt=1e-3):
    t = np.arange(n) * dt
    x = 0.8 + 0.5 * np.sin(2 * np.pi * 0.7 * t) + 0.2 * np.sin(2 * np.pi * 0.13 * t)
    temp = 24 + 3 * np.sin(2 * np.pi * t / 7.0)
    return t, x, {"temperature_c": temp}


ELEMENTS = [
    GainElement(gain=0.8),
    NonlinearGainElement(quadratic_per_v=0.08),
    SensorLagElement(tau_s=0.03),
    ThermalDriftElement(coefficient_v_per_c=2e-3, reference_c=22.0),
    OffsetDriftElement(rate_v_per_s=1e-4),
    ThermalLagElement(coefficient_v_per_c=-1.5e-3, reference_c=23.0, tau_s=2.0),
    ThermalDriftElement(coefficient_v_per_c=2e-3, reference_c=22.0, curvature_v_per_c2=-4e-4),
    ThermalLagElement(coefficient_v_per_c=-1.5e-3, reference_c=23.0, tau_s=2.0, curvature_v_per_c2=3e-4),
    ThermalSensitivityElement(span_coefficient_per_c=0.004, reference_c=23.0, thermal_tau_s=1.5),
]


def _element_id(e):
    return e.kind + "".join(f"-{k}" for k in ("curvature_v_per_c2", "thermal_tau_s") if getattr(e, k, 0.0))


@pytest.mark.parametrize("element", ELEMENTS, ids=_element_id)
def test_backward_undoes_forward(element):
    t, x, aux = signals()
    y = element.forward(t, x, aux)
    assert np.abs(y - x).max() > 1e-3  # the effect is really there
    back = element.backward(t, y, aux)
    if element.kind == "sensor_lag":
        # The slope over one step is first-order: error ~ tau * h * |y''| / 2, large only in the
        # start-up transient (the input steps from rest at t0); judged after 10 tau.
        settled = t > 10 * element.tau_s
        max_x2 = 0.5 * (2 * np.pi * 0.7) ** 2 + 0.2 * (2 * np.pi * 0.13) ** 2  # max |x''| of signals()
        bound = element.tau_s * (t[1] - t[0]) * max_x2 / 2
        assert np.abs(back[settled] - x[settled]).max() < 1.05 * bound
    else:
        assert np.abs(back - x).max() < 1e-12


@pytest.mark.parametrize("element", ELEMENTS, ids=_element_id)
def test_streaming_equals_batch(element):
    t, x, aux = signals(3000)
    y = element.forward(t, x, aux) + np.random.default_rng(0).normal(0, 1e-3, t.size)
    batch = element.backward(t, y, aux)
    stream = element.streaming()
    per_sample = [stream.step(ti, yi, {"temperature_c": ci}) for ti, yi, ci in zip(t, y, aux["temperature_c"])]
    np.testing.assert_allclose(per_sample, batch, rtol=1e-12, atol=1e-12)


def test_full_chain_round_trip_and_streaming():
    chain = SensorChain([ViscoelasticElement(PAPER_BURGERS), *ELEMENTS, OffsetElement(0.05)])
    t, _, aux = signals()
    force = 2 + np.sin(2 * np.pi * 0.5 * t)
    volts = chain.forward(t, force, aux)
    est = chain.backward(t, volts, aux)
    settled = t > 0.3  # after the lag's start-up transient (see test_backward_undoes_forward)
    assert np.abs(est[settled] - force[settled]).max() < 1e-3
    stream = chain.streaming()
    per_sample = np.array([stream.step(ti, vi, {"temperature_c": ci}) for ti, vi, ci in zip(t, volts, aux["temperature_c"])])
    np.testing.assert_allclose(per_sample, est, rtol=1e-9, atol=1e-9)


def test_thermal_element_without_temperature_is_identity():
    element = ThermalDriftElement(coefficient_v_per_c=1e-2, reference_c=20.0)
    np.testing.assert_array_equal(element.backward([0, 1], [1.0, 2.0]), [1.0, 2.0])
    assert element.streaming().step(0.0, 1.5, {"temperature_c": None}) == 1.5


def test_block_wise_simulation_equals_whole_record():
    chain = SensorChain([ViscoelasticElement(PAPER_BURGERS), *ELEMENTS, OffsetElement(0.05)])
    t, _, aux = signals()
    force = 2 + np.sin(2 * np.pi * 0.5 * t)
    whole = BridgeSimulator(chain=chain, noise_std_v=0.0, adc_bits=0).simulate(t, force, aux["temperature_c"])
    sim = BridgeSimulator(chain=chain, noise_std_v=0.0, adc_bits=0)
    blocks = [sim.simulate(tb, fb, cb)
              for tb, fb, cb in zip(np.array_split(t, 9), np.array_split(force, 9), np.array_split(aux["temperature_c"], 9))]
    np.testing.assert_allclose(np.concatenate(blocks), whole, rtol=1e-12, atol=1e-12)


def test_yaml_round_trip_and_validation(tmp_path):
    chain = SensorChain([ViscoelasticElement(PAPER_BURGERS), *ELEMENTS, OffsetElement(0.05)])
    path = tmp_path / "m.yaml"
    save_model(path, SensorModel(chain, {"source": "test"}))
    again = load_model(path).chain
    assert [e.to_dict() for e in again.elements] == [e.to_dict() for e in chain.elements]
    with pytest.raises(ModelError, match="tau_s must be > 0"):
        SensorChain.from_dict({"elements": [{"type": "sensor_lag", "tau_s": 0.0}]})
    with pytest.raises(ModelError, match="missing keys"):
        SensorChain.from_dict({"elements": [{"type": "thermal_drift", "coefficient_v_per_c": 1e-3}]})


def test_preisach_element_in_a_chain_yaml_and_streaming(tmp_path):
    from polyforce_ros.evaluation.fsr_preisach import fsr_truth, grip_profile
    from polyforce_ros.physics.chain import PreisachElement

    element = PreisachElement(fsr_truth(seed=2), continuous=True)
    chain = SensorChain([element, OffsetElement(0.0)])
    path = tmp_path / "fsr.yaml"
    save_model(path, SensorModel(chain, {"source": "test"}))
    loaded = load_model(path).chain
    t, force = grip_profile(duration_s=20.0)
    volts = chain.forward(t, force)
    np.testing.assert_allclose(loaded.backward(t, volts)[1:], force[1:], atol=1e-9)  # exact continuous inverse
    stream = loaded.streaming()
    np.testing.assert_allclose([stream.step(ti, vi) for ti, vi in zip(t, volts)][1:], force[1:], atol=1e-9)
    bad = element.to_dict()
    bad["density"] = bad["density"][:5]
    with pytest.raises(ModelError, match="preisach: density needs"):
        SensorChain.from_dict({"elements": [bad]})


def test_sensor_lag_noise_filter_is_the_inverse_followed_by_a_lag_and_bounds_noise():
    """(1 + tau s)/(1 + tau_f s) after the sensor's 1/(1 + tau s): the input seen through a lag of tau_f."""
    t, x, _ = signals()
    sensor = SensorLagElement(tau_s=0.03)
    filtered = SensorLagElement(tau_s=0.03, noise_filter_tau_s=0.003)
    y = sensor.forward(t, x)
    expected = SensorLagElement(tau_s=0.003).forward(t, x)
    # Both runs are exact for piecewise-linear signals, but y is curved: O(h^2 y'') apart, large
    # only while the sensor output rises from rest after the first sample; judged after 10 tau.
    settled = t > 10 * sensor.tau_s
    assert np.abs(filtered.backward(t, y) - expected)[settled].max() < 1e-5
    assert np.abs(filtered.backward(t, y) - x)[t > 0.1].max() < 0.01  # tau_f |x'| at most
    noise = np.random.default_rng(3).normal(0.0, 1e-3, t.size)
    gain_filtered = np.std(filtered.backward(t, noise)) / 1e-3
    gain_slope = np.std(sensor.backward(t, noise)) / 1e-3
    assert gain_filtered <= 0.03 / 0.003
    assert gain_slope > 3 * gain_filtered  # the slope form amplifies noise by ~ sqrt(2) tau / h


def test_sensor_lag_noise_filter_streams_like_batch_and_round_trips_in_yaml(tmp_path):
    t, x, _ = signals(3000)
    element = SensorLagElement(tau_s=0.03, noise_filter_tau_s=0.005)
    y = SensorLagElement(tau_s=0.03).forward(t, x) + 0.4 + np.random.default_rng(0).normal(0, 1e-3, t.size)
    batch = element.backward(t, y)
    assert batch[0] == pytest.approx(y[0])  # settled at the first sample: no start-up spike
    stream = element.streaming()
    np.testing.assert_allclose([stream.step(ti, yi) for ti, yi in zip(t, y)], batch, rtol=1e-12, atol=1e-12)
    chain = SensorChain([ViscoelasticElement(PAPER_BURGERS), element])
    path = tmp_path / "lag.yaml"
    save_model(path, SensorModel(chain, {"source": "test"}))
    assert load_model(path).chain.elements[-1].to_dict() == element.to_dict()
    assert "noise_filter_tau_s" not in SensorLagElement(tau_s=0.03).to_dict()  # default stays out of files
    with pytest.raises(ModelError, match="noise_filter_tau_s must be >= 0"):
        SensorChain.from_dict({"elements": [{"type": "sensor_lag", "tau_s": 0.03, "noise_filter_tau_s": -1.0}]})
    with pytest.raises(ModelError, match="unknown keys"):
        SensorChain.from_dict({"elements": [{"type": "sensor_lag", "tau_s": 0.03, "filter": 1.0}]})


@pytest.mark.parametrize("bad", ["2.0", True, "abc", None, float("nan")])
def test_play_hysteresis_numbers_are_checked_like_every_other_key(bad):
    from polyforce_ros.physics.chain import PlayHysteresisElement

    with pytest.raises(ModelError, match="linear_weight"):
        PlayHysteresisElement(bad, [0.1], [0.1])
    with pytest.raises(ModelError, match="history_max"):
        PlayHysteresisElement(1.0, [0.1], [0.1], history_max=bad)
    assert PlayHysteresisElement(np.float32(1.0), [0.1], [0.1], history_max=np.int64(3)).history_max == 3.0


def test_a_new_offset_keeps_a_forward_only_chain_forward_only():
    from polyforce_ros.physics.chain import ForwardElement

    class Bump:  # an element that can only simulate (no inverse), as the bench generator's truths hold
        kind = "bump"

        def forward(self, t_s, x, aux=None, state=None):
            return np.asarray(x, dtype=float) + 0.01

        def forward_state(self):
            return None

    assert isinstance(Bump(), ForwardElement)
    truth = SensorChain([ViscoelasticElement(PAPER_BURGERS), Bump()], forward_only=True)
    moved = truth.with_offset(0.2)
    assert moved.forward_only and moved.offset_v == 0.2 and truth.offset_v == 0.0
    t = np.arange(100) * 1e-3
    np.testing.assert_allclose(moved.forward(t, np.ones(100)), truth.forward(t, np.ones(100)) + 0.2)


def test_a_transport_delay_shifts_forward_across_blocks_and_passes_backward_stating_its_latency():
    import numpy as np

    from polyforce_ros.physics.chain import OffsetElement, SensorChain, TransportDelayElement, ViscoelasticElement
    from polyforce_ros.physics.viscoelastic import PAPER_BURGERS

    delay = TransportDelayElement(delay_s=0.0125)
    t = np.arange(2000) * 1e-3
    x = np.sin(7.0 * t) + (t > 0.7)
    whole = delay.forward(t, x)
    state = delay.forward_state()
    blocks = np.concatenate([delay.forward(t[a:b], x[a:b], state=state) for a, b in ((0, 3), (3, 700), (700, 2000))])
    np.testing.assert_array_equal(blocks, whole)
    np.testing.assert_allclose(whole[13:], 0.5 * (x[:-13] + x[1:-12]), atol=1e-12)  # 12.5 samples: mean of two
    assert whole[0] == x[0]  # settled before the record
    np.testing.assert_array_equal(delay.backward(t, x), x)
    assert delay.streaming().step(0.1, 0.25) == 0.25
    chain = SensorChain([ViscoelasticElement(PAPER_BURGERS), delay, OffsetElement(0.02)])
    assert chain.latency_s == 0.0125 and SensorChain.from_dict(chain.to_dict()).latency_s == 0.0125


def test_a_thermal_sensitivity_scales_the_span_and_its_inverse_undoes_it_with_a_bounded_gain():
    import numpy as np

    from polyforce_ros.physics.chain import ThermalSensitivityElement

    e = ThermalSensitivityElement(span_coefficient_per_c=0.004, reference_c=24.0)
    t = np.arange(500) * 0.01
    x = np.linspace(0.0, 2.5, 500)
    temp = 24.0 + 5.0 * np.sin(t)
    y = e.forward(t, x, {"temperature_c": temp})
    np.testing.assert_allclose(y, x * (1 + 0.004 * (temp - 24.0)))
    np.testing.assert_allclose(e.backward(t, y, {"temperature_c": temp}), x, rtol=1e-12)
    stream = e.streaming()
    assert stream.step(0.0, float(y[100]), {"temperature_c": float(temp[100])}) == pytest.approx(x[100], rel=1e-12)
    np.testing.assert_array_equal(e.backward(t, y), y)  # no temperature: not corrected
    # far outside the calibration the inverse divides by at least 0.2: a gain of at most 5
    hot = ThermalSensitivityElement(span_coefficient_per_c=-0.05, reference_c=24.0)
    assert hot.backward(t[:1], np.ones(1), {"temperature_c": 100.0})[0] == pytest.approx(5.0)
    assert type(e).from_dict(e.to_dict()).to_dict() == e.to_dict()


# -- hysteresis at the bridge, beside the core ---------------------------------------------------------------

def _bridge_family(seed):
    """A random core of any type, random plays and history, and a force record with jittered stamps and a gap."""
    from polyforce_ros.physics.chain import BridgeHysteresisElement
    from polyforce_ros.physics.viscoelastic import MODEL_TYPES

    rng = np.random.default_rng(seed)
    kind = sorted(MODEL_TYPES)[seed % len(MODEL_TYPES)]
    n_parameters = len(MODEL_TYPES[kind].parameter_names())
    core = MODEL_TYPES[kind].from_vector(np.exp(rng.uniform(np.log(2.0), np.log(400.0), n_parameters)))
    # plays on the force (seed % 3 == 0), scaled plays whose bands grow with the load (2), or both (1)
    m = int(rng.integers(1, 12)) if seed % 3 < 2 else 0
    radii = np.sort(rng.uniform(0.01, 3.0, m)) + 1e-3 * np.arange(m)
    weights = rng.uniform(0.0, 0.05, m) * rng.choice([0.0, 1.0], m, p=[0.2, 0.8])
    k = int(rng.integers(1, 10)) if seed % 3 > 0 else 0
    scaled = np.sort(rng.uniform(0.003, 1.5, k)) + 1e-3 * np.arange(k)
    scaled_weights = rng.uniform(0.0, 0.05, k) * rng.choice([0.0, 1.0], k, p=[0.2, 0.8])
    element = BridgeHysteresisElement(ViscoelasticElement(core), radii, weights, linear_v_per_n=float(rng.uniform(0, 0.01)),
                                      history_max_n=float(rng.choice([0.0, rng.uniform(0.5, 8.0)])),
                                      scaled_radii=scaled, scaled_weights_v_per_n=scaled_weights,
                                      floor_n=float(rng.uniform(0.01, 1.0)) if k else 0.0)
    dt = np.abs(1e-3 + rng.normal(0.0, 2e-4, 6000))
    dt[3000] = 0.5  # a gap
    t = np.cumsum(dt)
    centre = 5.0 if seed % 2 else 0.0  # a push, or a push and a pull through zero
    force = centre + 4.0 * np.sin(2 * np.pi * t / rng.uniform(0.5, 4.0)) + rng.normal(0.0, 0.05, t.size)
    return element, t, force


@pytest.mark.parametrize("seed", range(18))
def test_bridge_hysteresis_inverts_exactly_streams_like_batch_and_runs_in_blocks(seed):
    element, t, force = _bridge_family(seed)
    chain = SensorChain([element, OffsetElement(0.05)])
    volts = chain.forward(t, force)
    assert np.all(np.isfinite(volts))
    states = chain.forward_states()
    blocks = np.concatenate([chain.forward(t[i:i + 1000], force[i:i + 1000], states=states) for i in range(0, t.size, 1000)])
    np.testing.assert_allclose(blocks, volts, rtol=0, atol=1e-9)
    back = chain.backward(t, volts)
    scale = np.abs(force).max()
    # the core's own round trip is exact at a steady rate and has a discretisation error with jittered stamps and
    # gaps (piecewise-linear force forward, piecewise-linear deformation backward): the plays add none of their own
    core = SensorChain([element.core, OffsetElement(0.05)])
    for stamps, record in ((t, back), (np.arange(t.size) * 1e-3, None)):
        record = chain.backward(stamps, chain.forward(stamps, force)) if record is None else record
        core_error = np.abs(core.backward(stamps, core.forward(stamps, force)) - force).max()
        assert np.abs(record - force).max() <= 1.5 * core_error + 1e-7 * scale
    stream = chain.streaming()
    streamed = np.array([stream.step(ti, vi) for ti, vi in zip(t[:1500], volts[:1500])])
    np.testing.assert_allclose(streamed, back[:1500], rtol=0, atol=1e-9 * scale)
    again = SensorChain.from_dict(chain.to_dict())
    np.testing.assert_array_equal(again.forward(t, force), volts)


def test_bridge_hysteresis_opens_a_loop_the_core_alone_does_not_and_its_inverse_closes_it():
    from polyforce_ros.physics.chain import BridgeHysteresisElement

    radii = np.geomspace(0.1, 4.0, 8)
    weights = np.full(8, 0.004)  # V/N: loop height 2 sum(w r) ~ 0.1 V on a core of 1/4.8 V/N
    element = BridgeHysteresisElement(ViscoelasticElement(PAPER_BURGERS), radii, weights)
    t = np.arange(0.0, 40.0, 1e-3)
    force = 10.0 * np.abs(((t / 10.0) % 2.0) - 1.0)[::-1]  # 0-10 N sawtooth, 20 s period
    with_loop = element.forward(t, force)
    core_only = ViscoelasticElement(PAPER_BURGERS).forward(t, force)
    extra = with_loop - core_only
    up, down = np.gradient(force) > 0, np.gradient(force) < 0
    mid = np.abs(force - 5.0) < 0.1
    assert extra[mid & down].mean() - extra[mid & up].mean() > 0.5 * np.sum(weights * np.minimum(radii, 5.0))
    np.testing.assert_allclose(element.backward(t, with_loop), force, rtol=0, atol=1e-8)


def test_scaled_plays_open_a_loop_that_grows_with_the_load_and_the_inverse_closes_it():
    from polyforce_ros.physics.chain import BridgeHysteresisElement

    scaled = np.geomspace(0.005, 0.05, 6)  # every band crossed 2 N and 8 N away from a reversal
    element = BridgeHysteresisElement(ViscoelasticElement(PAPER_BURGERS), scaled_radii=scaled,
                                      scaled_weights_v_per_n=np.full(6, 0.004), floor_n=0.1)
    t = np.arange(0.0, 40.0, 1e-3)
    force = 10.0 * np.abs(((t / 10.0) % 2.0) - 1.0)[::-1]  # 0-10 N sawtooth, 20 s period
    extra = element.forward(t, force) - ViscoelasticElement(PAPER_BURGERS).forward(t, force)
    up, down = np.gradient(force) > 0, np.gradient(force) < 0
    width = {}
    for level in (2.0, 8.0):
        at = np.abs(force - level) < 0.05
        width[level] = extra[at & down].mean() - extra[at & up].mean()
    # floor (sinh(u + r) - sinh(u - r)) = 2 sqrt(F**2 + floor**2) sinh r: a band of about +-r F, four times as wide
    # at 8 N as at 2 N (a plain play's is the same width at both)
    for level in (2.0, 8.0):
        assert width[level] == pytest.approx(2.0 * np.hypot(level, 0.1) * np.sum(0.004 * np.sinh(scaled)), rel=0.03)
    np.testing.assert_allclose(element.backward(t, element.forward(t, force)), force, rtol=0, atol=1e-8)


@pytest.mark.parametrize("bad, words", [
    ({"core": {"type": "burgers"}, "radii_n": [0.1], "weights_v_per_n": [0.01]}, "missing keys"),
    ({"core": PAPER_BURGERS.as_dict() | {"type": "burgers"}}, "needs radii_n"),
    ({"core": PAPER_BURGERS.as_dict() | {"type": "burgers"}, "scaled_radii": [0.1], "scaled_weights_v_per_n": [0.01]},
     "floor_n > 0"),
    ({"core": PAPER_BURGERS.as_dict() | {"type": "burgers"}, "radii_n": [0.1], "weights_v_per_n": [0.01],
      "floor_n": 0.1}, "floor_n > 0"),
    ({"core": PAPER_BURGERS.as_dict() | {"type": "burgers"}, "scaled_radii": [0.1], "scaled_weights_v_per_n": [0.01],
      "floor_n": 1e-300}, "floor_n"),
    ({"core": PAPER_BURGERS.as_dict() | {"type": "burgers"}, "radii_n": list(np.arange(1.0, 41.0)),
      "weights_v_per_n": [0.01] * 40, "scaled_radii": list(np.linspace(0.01, 1.0, 30)),
      "scaled_weights_v_per_n": [0.01] * 30, "floor_n": 0.1}, "at most 64"),
    ({"core": PAPER_BURGERS.as_dict() | {"type": "burgers"}, "scaled_radii": [0.1], "scaled_weights_v_per_n": [-0.01],
      "floor_n": 0.1}, "scaled_weights_v_per_n"),
    ({"core": PAPER_BURGERS.as_dict() | {"type": "burgers"}, "scaled_radii": [3.0], "scaled_weights_v_per_n": [0.01],
      "floor_n": 0.1}, "scaled_radii"),
    ({"core": PAPER_BURGERS.as_dict() | {"type": "burgers"}, "scaled_radii": [0.1, 0.2], "scaled_weights_v_per_n": [0.01],
      "floor_n": 0.1}, "same length"),
    ({"core": 3.0, "radii_n": [0.1], "weights_v_per_n": [0.01]}, "mapping"),
    ({"core": PAPER_BURGERS.as_dict() | {"type": "burgers"}, "radii_n": [0.1, 0.2], "weights_v_per_n": [0.01, -0.02]},
     r"weights_v_per_n\[0\] \+ \.\.\."),
    ({"core": PAPER_BURGERS.as_dict() | {"type": "burgers"}, "radii_n": [0.2, 0.1], "weights_v_per_n": [0.01, 0.01]},
     "increasing"),
    ({"core": PAPER_BURGERS.as_dict() | {"type": "burgers"}, "radii_n": [0.1], "weights_v_per_n": [float("nan")]},
     "finite"),
    ({"core": PAPER_BURGERS.as_dict() | {"type": "burgers"}, "radii_n": [0.1], "weights_v_per_n": [0.01],
      "history_max_n": -1.0}, "history_max_n"),
])
def test_bridge_hysteresis_refuses_a_bad_mapping_naming_the_key(bad, words):
    from polyforce_ros.physics.chain import ELEMENT_TYPES

    with pytest.raises(ModelError, match=words):
        ELEMENT_TYPES["bridge_hysteresis"].from_dict({"type": "bridge_hysteresis", **bad})


def test_the_core_stream_states_its_next_step_as_an_affine_map_without_advancing():
    from polyforce_ros.physics.viscoelastic import MODEL_TYPES, StreamingCompensator

    rng = np.random.default_rng(3)
    for kind, model_type in MODEL_TYPES.items():
        stream = StreamingCompensator(model_type.from_vector(rng.uniform(1.0, 50.0, len(model_type.parameter_names()))))
        t = 0.0
        for _ in range(200):
            t += float(rng.choice([0.0, 1e-3, 5e-3, 0.3]))
            deformation = float(rng.normal())
            force0, stiffness = stream.affine(t)
            assert stream.affine(t) == (force0, stiffness)  # asking twice changes nothing
            assert stream.step(t, deformation) == pytest.approx(force0 + stiffness * deformation, rel=1e-9, abs=1e-9), kind
        assert stream.affine(t - 1.0) is None


def test_a_stop_type_bridge_hysteresis_whose_weights_sum_to_zero_in_rounding_loads():
    """linear = sum(w), weights = -w: the last partial sum is 0 exactly in arithmetic, +-1e-17 in float64."""
    from polyforce_ros.physics.chain import BridgeHysteresisElement

    rng = np.random.default_rng(5)
    for _ in range(200):
        w = rng.uniform(0.0, 0.05, int(rng.integers(2, 23)))
        radii = np.geomspace(0.01, 5.0, w.size)
        element = BridgeHysteresisElement(ViscoelasticElement(PAPER_BURGERS), radii, -w, linear_v_per_n=float(np.sum(w)))
        assert np.isfinite(element.forward(np.arange(50) * 1e-3, np.linspace(0.0, 9.0, 50))).all()


# -- a lightly damped mechanical mode ------------------------------------------------------------------------

@pytest.mark.parametrize("seed", range(6))
def test_a_resonance_rings_like_its_ode_and_its_inverse_damps_it_without_amplifying_noise(seed):
    from scipy import signal

    from polyforce_ros.physics.chain import ResonanceElement
    from polyforce_ros.physics.noise_gain import backward_noise_gain

    rng = np.random.default_rng(seed)
    f0, zeta = float(rng.uniform(3.0, 60.0)), float(rng.uniform(0.01, 0.3))
    element = ResonanceElement(frequency_hz=f0, damping_ratio=zeta)
    w = 2 * np.pi * f0
    t = np.arange(0.0, 4.0, 1e-3)
    x = np.where(t > 0.5, 1.0, 0.0) + 0.3 * np.sin(2 * np.pi * rng.uniform(0.5, 5.0) * t)
    _, expected, _ = signal.lsim(signal.lti([w * w], [1.0, 2 * zeta * w, w * w]), x, t)
    y = element.forward(t, x)
    np.testing.assert_allclose(y, expected, rtol=0, atol=1e-9)
    halves = SensorChain([element]).forward_states()
    blocks = np.concatenate([SensorChain([element]).forward(t[:1700], x[:1700], states=halves),
                             SensorChain([element]).forward(t[1700:], x[1700:], states=halves)])
    np.testing.assert_allclose(blocks, y, rtol=0, atol=1e-12)
    # the inverse leaves the input through a mode of the same frequency damped at inverse_damping_ratio
    zeta_f = element.inverse_damping_ratio
    _, damped, _ = signal.lsim(signal.lti([w * w], [1.0, 2 * zeta_f * w, w * w]), x, t)
    back = element.backward(t, y)
    assert np.abs(back - damped).max() <= 0.01 * np.abs(x).max() + 1e-3
    step = np.where(t > 0.5, 1.0, 0.0)  # a unit step rings up to exp(-pi zeta / sqrt(1 - zeta^2)) over; inverted, far less
    ringing, damped_ringing = element.forward(t, step).max() - 1.0, element.backward(t, element.forward(t, step)).max() - 1.0
    assert damped_ringing <= np.exp(-np.pi * zeta_f / np.sqrt(1 - zeta_f ** 2)) + 0.01 and damped_ringing < ringing
    stream = element.streaming()
    np.testing.assert_allclose([stream.step(a, b) for a, b in zip(t, y)], back, rtol=0, atol=1e-12)
    core = ViscoelasticElement(PAPER_BURGERS)
    with_mode = backward_noise_gain(SensorChain([core, element, OffsetElement(0.0)]), 1000.0).gain_n_per_v
    assert with_mode <= 1.02 * backward_noise_gain(SensorChain([core, OffsetElement(0.0)]), 1000.0).gain_n_per_v


def test_a_resonance_refuses_an_inverse_that_rings_more_than_the_mode():
    from polyforce_ros.physics.chain import ELEMENT_TYPES

    with pytest.raises(ModelError, match="inverse_damping_ratio"):
        ELEMENT_TYPES["resonance"].from_dict({"type": "resonance", "frequency_hz": 20.0, "damping_ratio": 0.3,
                                              "inverse_damping_ratio": 0.2})
    with pytest.raises(ModelError, match="damping_ratio"):
        ELEMENT_TYPES["resonance"].from_dict({"type": "resonance", "frequency_hz": 20.0, "damping_ratio": 1.5})


def test_bridge_hysteresis_history_settled_start_stop_type_and_static_gain_against_independent_references():
    from polyforce_ros.physics.chain import BridgeHysteresisElement, play_operator

    core = ViscoelasticElement(PAPER_BURGERS)
    radii, w = np.array([0.2, 0.8, 2.0]), np.array([0.01, 0.02, 0.015])
    t = np.arange(0.0, 20.0, 1e-3)
    force = 4.0 + 3.0 * np.sin(2 * np.pi * t / 5.0)
    # the history: the force came down from 6 N to 0 before the record, plays outside the element
    history = play_operator(np.array([0.0, 6.0, 0.0]), radii)[-1]
    expected = core.forward(t, force) + (play_operator(force, radii, history) - history) @ w
    element = BridgeHysteresisElement(core, radii, w, history_max_n=6.0)
    np.testing.assert_allclose(element.forward(t, force), expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(element.backward(t, expected), force, rtol=0, atol=1e-7)
    # a stop-type term (the force less each play) inverts as exactly
    stop = BridgeHysteresisElement(core, radii, -w, linear_v_per_n=float(w.sum()))
    stops = force[:, None] - play_operator(force, radii)
    np.testing.assert_allclose(stop.forward(t, force), core.forward(t, force) + stops @ w, rtol=0, atol=1e-12)
    np.testing.assert_allclose(stop.backward(t, stop.forward(t, force)), force, rtol=0, atol=1e-7)
    chain = SensorChain([element, OffsetElement(0.0)])
    assert chain.static_gain_v_per_n() == pytest.approx(PAPER_BURGERS.static_gain_v_per_n() + w.sum())
    # scaled plays: plays on asinh(F / floor) after the same history, back through floor sinh
    scaled, ws, floor = np.array([0.05, 0.3]), np.array([0.02, 0.01]), 0.3
    u_history = play_operator(np.arcsinh(np.array([0.0, 6.0, 0.0]) / floor), scaled)[-1]
    term = floor * np.sinh(play_operator(np.arcsinh(force / floor), scaled, u_history)) @ ws
    both = BridgeHysteresisElement(core, radii, w, history_max_n=6.0, scaled_radii=scaled, scaled_weights_v_per_n=ws,
                                   floor_n=floor)
    np.testing.assert_allclose(both.forward(t, force),
                               expected + term - floor * np.sinh(u_history) @ ws, rtol=0, atol=1e-12)
    np.testing.assert_allclose(both.backward(t, both.forward(t, force)), force, rtol=0, atol=1e-7)
    assert SensorChain([both]).static_gain_v_per_n() == pytest.approx(
        PAPER_BURGERS.static_gain_v_per_n() + w.sum() + np.cosh(scaled) @ ws)
    with pytest.raises(ValueError, match="non-decreasing"):
        element.backward(t[::-1], expected)


def test_a_resonance_inverse_starts_settled_and_refuses_a_stamp_before_the_previous():
    from polyforce_ros.physics.chain import ResonanceElement

    element = ResonanceElement(frequency_hz=12.0, damping_ratio=0.04)
    t = np.arange(0.0, 1.0, 1e-3)
    np.testing.assert_allclose(element.backward(t, np.full(t.size, 2.5)), 2.5, rtol=0, atol=1e-12)  # no start-up ring
    stream = element.streaming()
    assert stream.step(1.0, 2.5) == pytest.approx(2.5)
    assert stream.step(0.5, 2.5) is None
    with pytest.raises(ValueError, match="non-decreasing"):
        element.forward(t[::-1], t)


# -- friction: Coulomb friction on the force path -------------------------------------------------------------------

@settings(max_examples=60, deadline=None)
@given(radius=st.floats(0.01, 2.0), coupling=st.floats(0.0, 1.0), deadband=st.floats(0.0, 0.2),
       seed=st.integers(0, 2**31 - 1))
def test_friction_forward_is_the_play_its_inverse_is_exact_in_motion_and_never_further_than_its_band(radius, coupling,
                                                                                                        deadband, seed):
    from polyforce_ros.physics.chain import FrictionElement, PlayHysteresisElement

    rng = np.random.default_rng(seed)
    t = np.arange(4000) * 1e-3
    force = np.cumsum(rng.normal(0.0, 0.05, t.size)) + 3.0 * np.sin(t * rng.uniform(0.5, 5.0))
    e = FrictionElement(radius, coupling, deadband)
    core_force = e.forward(t, force)
    if coupling < 1.0:  # F - c stop_r(F) = (1 - c) F + c play_r(F): the Prandtl-Ishlinskii form, independently
        np.testing.assert_allclose(core_force, PlayHysteresisElement(1.0 - coupling, [radius], [coupling]).forward(t, force),
                                   atol=1e-9)
    back = e.backward(t, core_force)
    stream = e.streaming()
    np.testing.assert_allclose([stream.step(0.0, float(y)) for y in core_force], back, atol=1e-12)
    assert np.all(np.abs(back - force) <= 2.0 * coupling * (radius + deadband) + 1e-9)
    # a ramp one way, once the core's force has moved 2 (r + d): exact
    ramp = np.linspace(0.0, 10.0 * (radius + deadband) + 1.0, 500)
    out = e.backward(t[:500], e.forward(t[:500], ramp))
    moved = ramp - ramp[0] > 2.0 * (radius + deadband) / max(1.0 - coupling, 1e-3) + 2.0 * (radius + deadband)
    np.testing.assert_allclose(out[moved], ramp[moved], atol=1e-9)


def test_friction_inverse_passes_noise_inside_its_dead_band_with_gain_one():
    from polyforce_ros.physics.chain import FrictionElement, SensorChain, ViscoelasticElement
    from polyforce_ros.physics.noise_gain import white_noise_gain
    from polyforce_ros.physics.viscoelastic import Burgers

    core = ViscoelasticElement(Burgers(5.0, 10.0, 5000.0, 50.0))
    alone = white_noise_gain(SensorChain([core]), 1000.0)
    # the probe's 1 mV is 5 mN at the core's 5 N/V: a 30 mN dead band holds it, none lets the stop follow it
    assert white_noise_gain(SensorChain([FrictionElement(0.2, 1.0, 0.03), core]), 1000.0) == pytest.approx(alone, rel=0.02)
    assert white_noise_gain(SensorChain([FrictionElement(0.2, 1.0, 0.0), core]), 1000.0) == pytest.approx(2 * alone, rel=0.05)


@settings(max_examples=40, deadline=None)
@given(share=st.floats(0.0, 1.0), coupling=st.floats(0.0, 1.0), seed=st.integers(0, 2**31 - 1))
def test_a_friction_inverse_adds_back_its_share_and_the_core_force_is_never_further_than_the_band(share, coupling, seed):
    """The inverse with ``inverse_share`` s is the core's force plus s times the full inverse's correction; with s 0
    it is the core's force itself, never more than c r from the applied force."""
    from polyforce_ros.physics.chain import FrictionElement

    rng = np.random.default_rng(seed)
    t = np.arange(3000) * 1e-3
    force = np.cumsum(rng.normal(0.0, 0.05, t.size)) + 3.0 * np.sin(t * rng.uniform(0.5, 5.0))
    full = FrictionElement(0.3, coupling, 0.01)
    part = full.with_inverse_share(share)
    core_force = full.forward(t, force)
    np.testing.assert_array_equal(part.forward(t, force), core_force)  # the share is the inverse's alone
    np.testing.assert_allclose(part.backward(t, core_force),
                               core_force + share * (full.backward(t, core_force) - core_force), atol=1e-12)
    stream = part.streaming()
    np.testing.assert_allclose([stream.step(0.0, float(y)) for y in core_force], part.backward(t, core_force), atol=1e-12)
    assert np.all(np.abs(full.with_inverse_share(0.0).backward(t, core_force) - force) <= coupling * 0.3 + 1e-9)
    assert FrictionElement.from_dict(part.to_dict()).to_dict() == part.to_dict()
    assert ("inverse_share" in part.to_dict()) == (share != 1.0)


@pytest.mark.parametrize("bad", [{"radius_n": 0.0, "coupling": 1.0}, {"radius_n": 0.1, "coupling": 1.5},
                                 {"radius_n": 0.1, "coupling": -0.1}, {"radius_n": 0.1, "coupling": 1.0, "deadband_n": -1},
                                 {"radius_n": float("nan"), "coupling": 1.0}, {"radius_n": 0.1},
                                 {"radius_n": 0.1, "coupling": True},
                                 {"radius_n": 0.1, "coupling": 1.0, "inverse_share": 1.5},
                                 {"radius_n": 0.1, "coupling": 1.0, "inverse_share": -0.5}])
def test_a_friction_outside_its_ranges_is_a_model_error(bad):
    from polyforce_ros.physics.chain import FrictionElement, ModelError

    with pytest.raises(ModelError):
        FrictionElement.from_dict({"type": "friction", **bad})
    good = FrictionElement.from_dict({"type": "friction", "radius_n": 0.1, "coupling": 0.9, "deadband_n": 0.01})
    assert FrictionElement.from_dict(good.to_dict()).to_dict() == good.to_dict()


@settings(max_examples=40, deadline=None)
@given(slope=st.floats(-0.5, 0.5), lag_s=st.sampled_from([0.0, 0.5, 20.0]), coupling=st.floats(0.0, 1.0),
       share=st.sampled_from([0.0, 0.5, 1.0]), deadband=st.sampled_from([0.0, 0.02]), seed=st.integers(0, 2**31 - 1))
def test_a_friction_band_that_follows_temperature_streams_as_it_runs_in_batch_and_blocks(slope, lag_s, coupling, share,
                                                                                        deadband, seed):
    """A band r = radius_n exp(slope (T_lag - reference_c)): forward block by block equals forward in one run, the
    per-sample inverse equals the batch one on irregular stamps, and the inverse stays within 2 c (r_max + d) of the
    applied force; without a temperature the band is radius_n."""
    from polyforce_ros.physics.chain import FrictionElement
    from polyforce_ros.physics.chain.hysteresis import BAND_FACTOR_MAX

    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.5e-3, 1.5e-3, 3000))
    force = np.cumsum(rng.normal(0.0, 0.05, t.size)) + 3.0 * np.sin(t * rng.uniform(0.5, 5.0))
    temp = 22.0 + rng.uniform(-8.0, 8.0) * np.sin(t * rng.uniform(0.2, 2.0)) + rng.normal(0.0, 0.05, t.size)
    aux = {"temperature_c": temp}
    e = FrictionElement(0.2, coupling, deadband, share, band_log_slope_per_c=slope, reference_c=22.0,
                        temperature_lag_s=lag_s)
    core_force = e.forward(t, force, aux)
    state = e.forward_state()
    blocks = [e.forward(t[a:b], force[a:b], {"temperature_c": temp[a:b]}, state) for a, b in ((0, 1100), (1100, t.size))]
    np.testing.assert_allclose(np.concatenate(blocks), core_force, atol=1e-12)
    back = e.backward(t, core_force, aux)
    stream = e.streaming()
    np.testing.assert_allclose([stream.step(float(a), float(y), {"temperature_c": float(c)})
                                for a, y, c in zip(t, core_force, temp)], back, atol=1e-9)
    widest = 0.2 * min(float(np.exp(abs(slope) * np.abs(temp - 22.0).max())), BAND_FACTOR_MAX)  # a lag stays inside
    assert np.all(np.abs(back - force) <= 2.0 * coupling * (widest + deadband) + 1e-9)
    np.testing.assert_array_equal(e.forward(t, force), FrictionElement(0.2, coupling).forward(t, force))
    assert FrictionElement.from_dict(e.to_dict()).to_dict() == e.to_dict()
    assert ("band_log_slope_per_c" in e.to_dict()) == (slope != 0.0)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), chunk=st.sampled_from([None, 64, 97]), start=st.floats(-1.0, 1.0))
def test_a_play_with_a_half_width_per_sample_is_the_clamp_sample_by_sample(seed, chunk, start):
    from polyforce_ros.physics.chain.hysteresis import play_operator

    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.normal(0.0, 0.3, 700))
    radii = np.abs(rng.normal(0.5, 0.3, (700, 2)))
    y, expected = np.array([start, -start]), np.empty((700, 2))
    for k in range(700):
        y = np.minimum(np.maximum(y, x[k] - radii[k]), x[k] + radii[k])
        expected[k] = y
    np.testing.assert_allclose(play_operator(x, radii, [start, -start], chunk=chunk), expected, atol=1e-12)
    np.testing.assert_array_equal(play_operator(x, np.full((700, 1), 0.4), chunk=chunk), play_operator(x, [0.4], chunk=chunk))


def test_a_friction_band_that_widens_in_the_cold_is_undone_exactly_while_the_force_slides():
    """A rising force through a band that widens as the mechanism cools (slope < 0): the core sees F - r(T), and the
    inverse, whose band follows the same temperature, gives F back exactly once the force has left the first band."""
    from polyforce_ros.physics.chain import FrictionElement

    t = np.arange(0.0, 20.0, 1e-3)
    force = 0.5 * t
    temp = 22.0 - 0.3 * t  # 6 degC colder at the end: the band 1.8 times wider
    e = FrictionElement(0.1, 1.0, band_log_slope_per_c=-0.1, reference_c=22.0)
    core_force = e.forward(t, force, {"temperature_c": temp})
    band = 0.1 * np.exp(-0.1 * (temp - 22.0))
    sliding = force > 2.0 * band.max()
    np.testing.assert_allclose(core_force[sliding], (force - band)[sliding], atol=1e-12)
    np.testing.assert_allclose(e.backward(t, core_force, {"temperature_c": temp})[sliding], force[sliding], atol=1e-9)
    # the plain band would leave the widening in the force
    plain = FrictionElement(0.1, 1.0).backward(t, core_force)
    assert np.abs(plain - force)[sliding].max() > 0.05


def test_the_runtime_moves_a_friction_band_with_the_temperature_topic_as_the_batch_inverse_does():
    """The compensator, given a temperature reading before each sample, runs the same inverse as the chain's batch
    backward with that temperature: the band is followed live, not only in the diagnosis."""
    from polyforce_ros.physics.chain import FrictionElement, OffsetElement, SensorChain, ViscoelasticElement
    from polyforce_ros.physics.viscoelastic import Burgers
    from polyforce_ros.runtime import Compensator, CompensatorConfig

    t = np.arange(0.0, 30.0, 1e-3)
    force = 4.0 + 3.0 * np.sin(0.7 * t) * np.sin(0.05 * t)
    temp = 22.0 - 6.0 * np.sin(0.1 * t)
    chain = SensorChain([FrictionElement(0.2, 1.0, 0.0, band_log_slope_per_c=-0.08, reference_c=22.0,
                                         temperature_lag_s=5.0),
                         ViscoelasticElement(Burgers(5.0, 10.0, 5000.0, 50.0)), OffsetElement(0.0)])
    volts = chain.forward(t, force, {"temperature_c": temp})
    _, live = Compensator(chain, CompensatorConfig(auto_tare=False)).run(np.round(t * 1e9).astype(np.int64), volts,
                                                                         temperature_c=temp)
    batch = chain.backward(t, volts, {"temperature_c": temp})
    np.testing.assert_allclose(live, batch, atol=1e-6)
    assert np.abs(live - chain.backward(t, volts)).max() > 0.05  # without the temperature the band stays radius_n


@pytest.mark.parametrize("bad", [{"band_log_slope_per_c": 0.6}, {"band_log_slope_per_c": float("inf")},
                                 {"band_log_slope_per_c": 0.1, "reference_c": 400.0},
                                 {"band_log_slope_per_c": 0.1, "temperature_lag_s": -1.0},
                                 {"band_log_slope_per_c": "0.1"}])
def test_a_friction_band_slope_outside_its_ranges_is_a_model_error(bad):
    from polyforce_ros.physics.chain import FrictionElement, ModelError

    with pytest.raises(ModelError):
        FrictionElement.from_dict({"type": "friction", "radius_n": 0.1, "coupling": 1.0, **bad})


# -- thermo_rheological: a core whose viscosities follow temperature ---------------------------------------------

@settings(max_examples=40, deadline=None)
@given(tau_s=st.floats(0.01, 100.0), seed=st.integers(0, 2**31 - 1))
def test_a_peeked_temperature_lag_is_the_update_it_foretells_and_moves_nothing(tau_s, seed):
    from polyforce_ros.physics.chain.drift import LaggedTemperatureStream

    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(-0.2, 1.0, 200)) * 0.05  # some stamps go back: refused, the lag not moved
    temp = 20.0 + np.cumsum(rng.normal(0.0, 0.3, t.size))
    plain, peeking = LaggedTemperatureStream(tau_s), LaggedTemperatureStream(tau_s)
    for ti, ci in zip(t, temp):
        for _ in range(int(rng.integers(0, 3))):  # peeks at other samples, then at this one, or none at all
            peeking.peek(ti + float(rng.uniform(-0.1, 0.1)), ci + float(rng.normal()))
        foretold = peeking.peek(ti, ci) if rng.uniform() < 0.8 else None
        want = plain.update(ti, ci)
        got = peeking.update(ti, ci)
        assert got == want
        assert foretold is None or foretold == want
        assert peeking.lag.y == plain.lag.y and peeking.lag.t_prev_s == plain.lag.t_prev_s


@settings(max_examples=200, deadline=None)
@given(departure=st.one_of(st.floats(-1e3, 1e3), st.sampled_from([float("nan"), float("inf"), -float("inf")])),
       shift=st.floats(-2.0, 2.0), c2=st.one_of(st.just(0.0), st.floats(1.0, 1e4)))
def test_the_shift_law_of_one_sample_is_the_shift_law_of_an_array(departure, shift, c2):
    from polyforce_ros.physics.chain import log_shift

    one = log_shift(departure, shift, c2)
    with np.errstate(invalid="ignore"):
        many = log_shift(np.array([departure]), shift, c2)
    assert type(one) is float
    np.testing.assert_array_equal([one], many)


@settings(max_examples=30, deadline=None)
@given(shift=st.floats(-0.3, 0.3), swing=st.floats(0.0, 8.0), seed=st.integers(0, 2**31 - 1),
       lag_s=st.one_of(st.just(0.0), st.floats(0.5, 60.0)), c2=st.one_of(st.just(0.0), st.floats(1.0, 200.0)))
def test_a_thermo_rheological_core_runs_on_the_reduced_time_forward_backward_streaming_and_in_blocks(shift, swing, seed,
                                                                                                   lag_s, c2):
    """A clock that runs faster when warm (shift > 0, straight or bent) or slower (shift < 0, straight)."""
    from polyforce_ros.physics.chain import ThermoRheologicalElement, ViscoelasticElement, reduced_time_s

    c2 = c2 if shift >= 0.0 else 0.0
    rng = np.random.default_rng(seed)
    core = ViscoelasticElement(PAPER_BURGERS)
    e = ThermoRheologicalElement(core, shift, 24.0, temperature_lag_s=lag_s, wlf_c2_c=c2)
    t = np.cumsum(rng.uniform(0.5, 1.5, 3000)) * 0.02
    force = np.abs(np.cumsum(rng.normal(0.0, 0.1, t.size)))
    temp = 24.0 + swing * np.sin(t / rng.uniform(5.0, 30.0))
    aux = {"temperature_c": temp}
    volts = e.forward(t, force, aux)
    # the same core on the reduced time, which scipy's trapezoid gives independently; the core's temperature behind
    # the thermometer's by an independent integration of tau T' + T = T_thermometer (settled at the start)
    from scipy.integrate import cumulative_trapezoid, solve_ivp

    core_c = temp
    if lag_s > 0.0:
        core_c = solve_ivp(lambda x, y: (np.interp(x, t, temp) - y) / lag_s, (t[0], t[-1]), [temp[0]], t_eval=t,
                           rtol=1e-10, atol=1e-10, max_step=float(np.min(np.diff(t)))).y[0]
    # the WLF law as Williams, Landel and Ferry write it, log10 a_T = -C1 dT / (C2 + dT), with C1 from the slope at
    # the reference (b = C1 ln 10 / C2), the clock stopped (a_T = e**-10) at and below -C2
    d = core_c - 24.0
    if c2 > 0.0 and shift > 0.0:  # a shift of zero is no shift, bent or not
        c1 = shift * c2 / np.log(10.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            ln_a = np.where(d > -c2, np.log(10.0) * c1 * d / (c2 + d), -np.inf)
    else:
        ln_a = shift * d
    xi = t[0] + cumulative_trapezoid(np.exp(np.clip(ln_a, -10.0, 10.0)), t, initial=0.0)
    np.testing.assert_allclose(e._xi(t, aux), xi, rtol=1e-6, atol=1e-6)
    if lag_s == 0.0:
        np.testing.assert_allclose(reduced_time_s(t, temp, shift, 24.0, c2), xi, rtol=1e-12, atol=1e-9)
    xi = e._xi(t, aux)
    np.testing.assert_allclose(volts, core.forward(xi, force), atol=1e-12)
    back = e.backward(t, volts, aux)
    np.testing.assert_allclose(back, force, rtol=1e-6, atol=1e-5)  # the core's own round trip on a fast reduced time
    stream = e.streaming()
    np.testing.assert_allclose([stream.step(ti, vi, {"temperature_c": ci}) for ti, vi, ci in zip(t, volts, temp)], back,
                               atol=1e-9)
    state = e.forward_state()
    blocks = [e.forward(t[i:i + 701], force[i:i + 701], {"temperature_c": temp[i:i + 701]}, state)
              for i in range(0, t.size, 701)]
    np.testing.assert_allclose(np.concatenate(blocks), volts, atol=1e-9)
    # at the reference temperature, or without one, it is the core itself
    np.testing.assert_allclose(e.forward(t, force), core.forward(t, force), atol=1e-12)


@pytest.mark.parametrize("bad", [{"shift_per_c": -5.0}, {"shift_per_c": 5.0}, {"shift_per_c": float("nan")},
                                 {"shift_per_c": -0.1, "wlf_c2_c": 50.0},
                                 {"reference_c": 1e4}, {"core": [1.0]}, {"core": {"type": "gain", "gain": 1.0}},
                                 {"temperature_lag_s": -1.0}, {"temperature_lag_s": 1e-5}, {"temperature_lag_s": 1e7},
                                 {"temperature_lag_s": "10"}, {"temperature_lag_s": float("inf")}, {"lag_s": 10.0},
                                 {"wlf_c2_c": -50.0}, {"wlf_c2_c": 0.5}, {"wlf_c2_c": 1e5}, {"wlf_c2_c": float("nan")},
                                 {"wlf_c2_c": [50.0]}, {"c2": 50.0}])
def test_a_thermo_rheological_element_outside_its_ranges_is_a_model_error(bad):
    from polyforce_ros.physics.chain import ModelError, ThermoRheologicalElement, ViscoelasticElement

    good = ThermoRheologicalElement(ViscoelasticElement(PAPER_BURGERS), 0.05, 22.0).to_dict()
    # a core on its thermometer's temperature, on a straight law, writes the file it always did
    assert "temperature_lag_s" not in good and "wlf_c2_c" not in good
    assert ThermoRheologicalElement.from_dict(good).to_dict() == good
    for more in ({"temperature_lag_s": 30.0}, {"wlf_c2_c": 45.0}, {"temperature_lag_s": 3.0, "wlf_c2_c": 120.0},
                 {"shift_per_c": -0.3}, {"shift_per_c": -0.3, "temperature_lag_s": 10.0}):
        assert ThermoRheologicalElement.from_dict({**good, **more}).to_dict() == {**good, **more}
    with pytest.raises(ModelError):
        ThermoRheologicalElement.from_dict({**good, **bad})


# -- temperature: a curved zero, a lagged span --------------------------------------------------------------

@settings(max_examples=40, deadline=None)
@given(c=st.floats(-0.05, 0.05), q=st.floats(-0.01, 0.01), tau=st.one_of(st.just(0.0), st.floats(0.5, 200.0)),
       ref=st.floats(15.0, 35.0), seed=st.integers(0, 2 ** 16), direct=st.floats(-0.05, 0.05))
def test_a_curved_zero_and_a_lagged_span_follow_their_formulas_in_blocks_and_round_trip(c, q, tau, ref, seed, direct):
    from scipy.signal import lfilter

    rng = np.random.default_rng(seed)
    t = np.arange(4000) * 0.05
    temp = ref + rng.uniform(-8, 8) * np.tanh((t - rng.uniform(20, 180)) / rng.uniform(5, 40))
    x = rng.uniform(0, 2, t.size)
    aux = {"temperature_c": temp}
    zero = (ThermalLagElement(coefficient_v_per_c=c, reference_c=ref, tau_s=tau, curvature_v_per_c2=q) if tau
            else ThermalDriftElement(coefficient_v_per_c=c, reference_c=ref, curvature_v_per_c2=q))
    span = ThermalSensitivityElement(span_coefficient_per_c=c / 10, reference_c=ref, thermal_tau_s=tau,
                                     span_curvature_per_c2=q / 10, direct_span_coefficient_per_c=direct / 10)
    # the lag by its own recursion: exact for a temperature linear between samples (a first-order hold)
    if tau:
        a = np.exp(-0.05 / tau)
        b1 = 1 - tau / 0.05 * (1 - a)
        lagged = lfilter([b1, (1 - a) - b1], [1, -a], temp - temp[0]) + temp[0]
    else:
        lagged = temp
    d = lagged - ref
    np.testing.assert_allclose(zero.forward(t, x, aux), x + c * d + q * d ** 2, atol=1e-9)
    factor = np.maximum(1 + c / 10 * d + q / 10 * d ** 2 + direct / 10 * (temp - ref), 0.2)
    np.testing.assert_allclose(span.forward(t, x, aux), x * factor, atol=1e-9)
    np.testing.assert_allclose(span.backward(t, span.forward(t, x, aux), aux), x, atol=1e-9)
    stream = span.streaming()  # the runtime's per-sample inverse
    y = span.forward(t, x, aux)
    np.testing.assert_allclose([stream.step(ti, yi, {"temperature_c": ci}) for ti, yi, ci in zip(t[:300], y[:300], temp[:300])],
                               x[:300], atol=1e-9)
    for e in (zero, span):
        state = e.forward_state()
        blocks = np.concatenate([e.forward(t[i:j], x[i:j], {"temperature_c": temp[i:j]}, state)
                                 for i, j in ((0, 1), (1, 1700), (1700, 4000))])
        np.testing.assert_allclose(blocks, e.forward(t, x, aux), atol=1e-12)
        assert type(e).from_dict(e.to_dict()).to_dict() == e.to_dict()


def test_a_zero_curvature_and_no_span_lag_stay_out_of_the_model_file_and_bad_values_are_refused():
    assert "curvature_v_per_c2" not in ThermalDriftElement(coefficient_v_per_c=1e-3, reference_c=20.0).to_dict()
    assert not {"thermal_tau_s", "span_curvature_per_c2", "direct_span_coefficient_per_c"} & set(
        ThermalSensitivityElement(span_coefficient_per_c=1e-3, reference_c=20.0).to_dict())
    for name in ("span_curvature_per_c2", "direct_span_coefficient_per_c"):
        for bad in (float("nan"), "x", 1e9):
            with pytest.raises(ModelError, match=name):
                ThermalSensitivityElement.from_dict({"type": "thermal_sensitivity", "span_coefficient_per_c": 1e-3,
                                                     "reference_c": 20.0, name: bad})
    for bad in ({"curvature_v_per_c2": 5.0}, {"curvature_v_per_c2": float("nan")}, {"curvature_v_per_c2": "x"}):
        with pytest.raises(ModelError, match="curvature_v_per_c2"):
            ThermalDriftElement.from_dict({"type": "thermal_drift", "coefficient_v_per_c": 1e-3, "reference_c": 20.0, **bad})
    for bad in (-1.0, 1e9, float("inf")):
        with pytest.raises(ModelError, match="thermal_tau_s"):
            ThermalSensitivityElement.from_dict({"type": "thermal_sensitivity", "span_coefficient_per_c": 1e-3,
                                                 "reference_c": 20.0, "thermal_tau_s": bad})


@settings(max_examples=25, deadline=None)
@given(rate=st.floats(1e-4, 0.05), exponent=st.floats(0.3, 4.5), scale=st.floats(1.0, 20.0), shift=st.floats(0.0, 0.2),
       yield_n=st.one_of(st.just(0.0), st.floats(0.1, 6.0)),
       volume_rates=st.lists(st.floats(-0.02, 0.02), max_size=3), volume_scale=st.floats(0.5, 50.0),
       seed=st.integers(0, 2 ** 16))
def test_a_power_flow_adds_its_left_sum_to_the_core_runs_in_blocks_and_its_inverse_undoes_it(
        rate, exponent, scale, shift, yield_n, volume_rates, volume_scale, seed):
    """V = core(F) + rate sum over the samples before of ((F - yield) / scale)^n dt above the yield, and with
    volume rates c_k the left sum of F sum_k c_k u^k dt, u the load-time integral passed (a left sum too) over
    its scale held within [0, 1]; block by block as in one run; the inverse (plain or thermo-rheological core)
    returns the force; the model file round-trips."""
    from polyforce_ros.physics.chain import PowerFlowElement, ThermoRheologicalElement
    from polyforce_ros.physics.viscoelastic import Zener

    from polyforce_ros.physics.chain import lowest_volume_fluidity

    assume(lowest_volume_fluidity(volume_rates) >= 0.0)  # a zener core has no fluidity of its own to spare
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.5e-3, 1.5e-3, 6000))
    f = np.clip(4 + 3 * np.sin(2 * np.pi * rng.uniform(0.1, 2.0) * t) + rng.normal(0, 0.05, t.size), -0.5, None)
    aux = {"temperature_c": 23 + 3 * np.sin(t / rng.uniform(0.5, 5.0))}
    plain = ViscoelasticElement(Zener(rng.uniform(1, 10), rng.uniform(5, 50), rng.uniform(10, 500)))
    core = ThermoRheologicalElement(plain, shift, 23.0) if shift > 0.1 else plain
    e = PowerFlowElement(core, rate, exponent, scale, yield_n, volume_scale if volume_rates else 0.0, volume_rates)
    u = np.clip(np.concatenate([[0.0], np.cumsum(np.diff(t) * f[:-1])]) / volume_scale, 0.0, 1.0)
    fluid = rate * (np.maximum(f - yield_n, 0) / scale) ** exponent + f * sum(
        (c * u ** (k + 1) for k, c in enumerate(volume_rates)), np.zeros_like(f))
    left = np.concatenate([[0.0], np.cumsum(np.diff(t) * fluid[:-1])])
    v = e.forward(t, f, aux)
    np.testing.assert_allclose(v, core.forward(t, f, aux) + left, atol=1e-12)
    state = e.forward_state()
    blocks = np.concatenate([e.forward(t[i:j], f[i:j], {"temperature_c": aux["temperature_c"][i:j]}, state)
                             for i, j in ((0, 1), (1, 2500), (2500, 6000))])
    np.testing.assert_allclose(blocks, v, atol=1e-12)
    np.testing.assert_allclose(e.backward(t, v, aux), f, atol=1e-6)
    assert PowerFlowElement.from_dict(e.to_dict()).to_dict() == e.to_dict()


def test_a_power_flow_refuses_a_falling_rate_a_wild_exponent_and_a_core_that_is_not_viscoelastic():
    from polyforce_ros.physics.chain import PowerFlowElement
    from polyforce_ros.physics.viscoelastic import Zener

    core = ViscoelasticElement(Zener(3.0, 20.0, 200.0))
    good = PowerFlowElement(core, 0.01, 2.0, 9.0).to_dict()
    for key, bad in (("flow_rate_v_per_s", -1e-3), ("flow_rate_v_per_s", float("nan")), ("flow_exponent", 0.0),
                     ("flow_exponent", 50.0), ("flow_force_scale_n", 0.0), ("flow_yield_n", -1.0),
                     ("core", {"type": "offset", "offset_v": 0.0})):
        with pytest.raises(ModelError, match="power_flow|core|type"):
            PowerFlowElement.from_dict({**good, key: bad})
    with pytest.raises(ModelError, match="power_flow"):
        PowerFlowElement(PowerFlowElement(core, 0.01, 2.0, 9.0), 0.01, 2.0, 9.0)


def test_a_fluidity_that_changes_as_the_core_flows_needs_a_scale_and_at_most_three_bounded_terms():
    from polyforce_ros.physics.chain import PowerFlowElement
    from polyforce_ros.physics.viscoelastic import Zener

    core = ViscoelasticElement(Zener(3.0, 20.0, 200.0))
    good = PowerFlowElement(core, 0.0, 1.0, 9.0, 0.0, 100.0, [1e-3, -5e-4]).to_dict()
    assert good["flow_volume_rates_v_per_n_s"] == [1e-3, -5e-4]
    for key, bad in (("flow_volume_scale_n_s", 0.0), ("flow_volume_scale_n_s", -1.0), ("flow_volume_scale_n_s", 1e12),
                     ("flow_volume_scale_n_s", float("nan")), ("flow_volume_rates_v_per_n_s", [1e-3] * 4),
                     ("flow_volume_rates_v_per_n_s", [5.0]), ("flow_volume_rates_v_per_n_s", [float("inf")]),
                     ("flow_volume_rates_v_per_n_s", "1e-3"), ("flow_volume_rates_v_per_n_s", [True])):
        with pytest.raises(ModelError, match="power_flow"):
            PowerFlowElement.from_dict({**good, key: bad})
    alone = {k: v for k, v in good.items() if k != "flow_volume_rates_v_per_n_s"}
    with pytest.raises(ModelError, match="flow_volume_rates_v_per_n_s"):  # a scale without its rates
        PowerFlowElement.from_dict(alone)
    off = {k: v for k, v in good.items() if k != "flow_volume_scale_n_s"}
    with pytest.raises(ModelError, match="flow_volume_scale_n_s"):  # rates without a scale
        PowerFlowElement.from_dict(off)
    plain = PowerFlowElement(core, 0.01, 2.0, 9.0)
    assert "flow_volume_scale_n_s" not in plain.to_dict() and plain.flow_volume_rates_v_per_n_s == ()


def test_a_fluidity_that_changes_as_the_core_flows_is_refused_where_it_would_turn_negative():
    """The volume terms with the core's own fluidity never negative in [0, 1], between the ends too (a dip at u =
    0.25 of p = u (2 u - 1) 1e-3); a thermo-rheological core lends none of its own, which cold can stop."""
    from polyforce_ros.physics.chain import PowerFlowElement, ThermoRheologicalElement, lowest_volume_fluidity
    from polyforce_ros.physics.viscoelastic import Burgers, Zener

    assert lowest_volume_fluidity([-1e-3, 2e-3]) == pytest.approx(-1.25e-4)
    assert lowest_volume_fluidity([1e-3, -3e-3, 2.5e-3]) == pytest.approx(min(0.0, 1e-3 - 3e-3 + 2.5e-3))
    zener = ViscoelasticElement(Zener(3.0, 20.0, 200.0))
    burgers = ViscoelasticElement(Burgers(3.0, 20.0, 1000.0, 200.0))  # its own fluidity 1e-3 V/(N s)
    for core, rates, ok in ((zener, [-1e-3, 2e-3], False), (zener, [1e-3, -5e-4], True),
                            (burgers, [-5e-4], True), (burgers, [-2e-3], False), (burgers, [-4e-3, 4e-3], True),
                            (ThermoRheologicalElement(burgers, 0.1, 23.0), [-5e-4], False)):
        if ok:
            PowerFlowElement(core, 0.0, 1.0, 9.0, 0.0, 100.0, rates)
        else:
            with pytest.raises(ModelError, match="negative fluidity"):
                PowerFlowElement(core, 0.0, 1.0, 9.0, 0.0, 100.0, rates)


@settings(max_examples=20, deadline=None)
@given(rates=st.lists(st.floats(-0.1, 0.1), min_size=1, max_size=3), scale=st.floats(1e-3, 1e4),
       volts=st.sampled_from([-1.0, -0.2, 0.3, 1.0]), seed=st.integers(0, 2 ** 16))
def test_a_fluidity_that_changes_as_the_core_flows_never_grows_the_force_over_hours_of_a_held_voltage(
        rates, scale, volts, seed):
    """Three hours of one bridge voltage at 10 Hz through the inverse of a flow whose fluidity changes as it flows
    (any legal rates beside a burgers core, shrunk as the engine shrinks them): the force relaxes, it never grows past
    its first value and never turns NaN, at either sign of the load."""
    from polyforce_ros.discrepancy.effects import volume_beside
    from polyforce_ros.physics.viscoelastic import Burgers

    rng = np.random.default_rng(seed)
    core = ViscoelasticElement(Burgers(rng.uniform(1, 10), rng.uniform(5, 50), rng.uniform(10, 500),
                                       rng.uniform(1e3, 1e5)))
    e = volume_beside(core, scale, rates)
    t = np.arange(0.0, 3 * 3600.0, 0.1)
    force = e.backward(t, np.full(t.size, volts))
    assert np.all(np.isfinite(force))
    assert np.max(np.abs(force)) <= abs(force[0]) * (1 + 1e-9)


@settings(max_examples=40, deadline=None)
@given(knees=st.lists(st.floats(-1.0, 8.0), min_size=1, max_size=3, unique=True),
       shares=st.lists(st.floats(-0.3, 3.0), min_size=3, max_size=3), tau_s=st.floats(1e-3, 30.0),
       rate_hz=st.sampled_from([50.0, 100.0, 1000.0]), gap_s=st.sampled_from([0.0, 0.5, 3.0]),
       wrap=st.sampled_from(["plain", "thermo_rheological", "lagged_clock", "power_flow"]), seed=st.integers(0, 2 ** 16))
def test_knee_units_add_kelvin_units_loaded_above_their_knees_run_in_blocks_and_their_inverse_undoes_them(
        knees, shares, tau_s, rate_hz, gap_s, wrap, seed):
    """V = core(F) + sum c_k K_tau(max(F - knee_k, 0)) (the exact recursion), block by block as in one run; the
    inverse returns the force exactly, at any rate, for a unit faster than a sample, across a gap of seconds and
    with units that take up to 0.9 of the core's instantaneous compliance away above their knees; the model file
    round-trips."""
    from polyforce_ros.physics.chain import KneeKelvinElement, PowerFlowElement, ThermoRheologicalElement
    from polyforce_ros.physics.expconv import exp_convolve
    from polyforce_ros.physics.viscoelastic import Zener

    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.5, 1.5, 3000) / rate_hz)
    t[1500:] += gap_s
    f = np.clip(4 + 3 * np.sin(2 * np.pi * rng.uniform(0.1, 2.0) * t) + rng.normal(0, 0.05, t.size), -0.5, None)
    f[1500:] += 2.0 * (gap_s > 0)  # the load moved while nothing was recorded
    aux = {"temperature_c": 23 + 3 * np.sin(t / rng.uniform(0.5, 5.0))}
    plain = ViscoelasticElement(Zener(rng.uniform(1, 10), rng.uniform(5, 50), rng.uniform(10, 500)))
    core = {"plain": plain, "thermo_rheological": ThermoRheologicalElement(plain, 0.1, 23.0),
            "lagged_clock": ThermoRheologicalElement(plain, 0.1, 23.0, temperature_lag_s=2.0),
            "power_flow": PowerFlowElement(plain, 0.01, 2.0, 9.0)}[wrap]
    j0 = plain.model.compliance().j0_v_per_n
    knees = sorted(knees)
    compliances = [share * j0 for share in shares[:len(knees)]]  # running sums above -0.9 of the core's j0
    e = KneeKelvinElement(core, knees, compliances, tau_s)
    units = sum(c * exp_convolve(t, np.maximum(f - k, 0.0), [1.0 / tau_s])[:, 0] / tau_s
                for k, c in zip(knees, compliances))
    v = e.forward(t, f, aux)
    np.testing.assert_allclose(v, core.forward(t, f, aux) + units, atol=1e-12)
    state = e.forward_state()
    blocks = np.concatenate([e.forward(t[i:j], f[i:j], {"temperature_c": aux["temperature_c"][i:j]}, state)
                             for i, j in ((0, 1), (1, 1400), (1400, 3000))])
    np.testing.assert_allclose(blocks, v, atol=1e-12)
    own_n = float(np.max(np.abs(core.backward(t, core.forward(t, f, aux), aux) - f)))  # the core's own rounding
    np.testing.assert_allclose(e.backward(t, v, aux), f, atol=1e-6 + 10.0 * own_n)
    assert KneeKelvinElement.from_dict(e.to_dict()).to_dict() == e.to_dict()


def test_knee_units_refuse_a_falling_output_bad_lists_and_a_core_that_is_not_viscoelastic():
    """Above a knee the units may take away less than the core's instantaneous compliance, never all of it: a
    unit that settles before the core creeps would otherwise make the output fall as the load rises."""
    from polyforce_ros.physics.chain import BridgeHysteresisElement, KneeKelvinElement
    from polyforce_ros.physics.viscoelastic import Zener

    core = ViscoelasticElement(Zener(3.0, 20.0, 200.0))  # instantaneous compliance 1/3 V/N
    good = KneeKelvinElement(core, [2.0, 5.0], [0.1, -0.4], 8.0).to_dict()
    for key, bad in (("knee_compliances_v_per_n", [0.1, -0.5]), ("knee_compliances_v_per_n", [-0.4]),
                     ("knee_compliances_v_per_n", [float("nan"), 0.1]), ("knee_compliances_v_per_n", []),
                     ("knees_n", [5.0, 2.0]), ("knees_n", [2.0, 2.0]), ("knees_n", "x"), ("knees_n", [1.0] * 9),
                     ("knee_tau_s", 0.0), ("knee_tau_s", 1e-5),
                     ("core", {"type": "offset", "offset_v": 0.0}), ("core", [1.0])):
        with pytest.raises(ModelError, match="knee_kelvin|core|type"):
            KneeKelvinElement.from_dict({**good, key: bad})
    with pytest.raises(ModelError, match="knee_kelvin"):
        KneeKelvinElement(KneeKelvinElement(core, [2.0], [0.1], 8.0), [2.0], [0.1], 8.0)
    with pytest.raises(ModelError, match="knee_kelvin"):  # the plays at the bridge solve with an affine core step
        BridgeHysteresisElement(KneeKelvinElement(core, [2.0], [0.1], 8.0), [0.1], [0.01])


def test_bridge_hysteresis_inverts_stop_plays_whose_breakpoints_tie_and_stays_exact_beside_a_stiff_core():
    """Stop-type plays (a negative weight) start with tied breakpoints after a jump from rest; and a stiff core (1e9
    N/V) beside heavy scaled plays with a wide floor turns any rounding of the plays' sums into newtons."""
    from polyforce_ros.physics.chain import BridgeHysteresisElement
    from polyforce_ros.physics.viscoelastic import Burgers

    t = np.arange(0.0, 3.0, 1e-3)
    force = 5.0 + 4.0 * np.sin(2 * np.pi * t / 1.5)
    stop = BridgeHysteresisElement(ViscoelasticElement(PAPER_BURGERS), [0.05, 0.5, 5.0], [1.0, 1.0, -1.0])
    np.testing.assert_allclose(stop.backward(t, stop.forward(t, force)), force, rtol=0, atol=1e-8)
    for k1, floor in ((1e9, 1e5), (1e6, 1e5)):
        core = ViscoelasticElement(Burgers(k1_n_per_v=k1, k2_n_per_v=2 * k1, eta1_n_s_per_v=min(1e3 * k1, 1e13),
                                           eta2_n_s_per_v=min(10 * k1, 1e13)))
        element = BridgeHysteresisElement(core, [0.1], [1e3], scaled_radii=[0.01, 2.0],
                                          scaled_weights_v_per_n=[1e3, 1e3], floor_n=floor)
        volts = element.forward(t, force)
        # the model's own limit: a volt's last bit through the stiffest slope
        limit = 8.0 * np.finfo(float).eps * np.abs(volts).max() * k1
        assert np.abs(element.backward(t, volts) - force).max() <= max(limit, 1e-8)
