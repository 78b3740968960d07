"""The chain elements the discrepancy workflow adds: Prandtl-Ishlinskii hysteresis, thermal lag, polynomial gain
and drift, a zero that jumps. Forward, batch backward and streaming agree; model files carry them; random parameters."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from polyforce_ros.model_file import SensorModel, load_model, save_model
from polyforce_ros.physics.chain import (
    ELEMENT_TYPES, ExponentialDriftElement, ModelError, OffsetElement, PlayHysteresisElement, PolynomialDriftElement,
    PolynomialGainElement, SensorChain, SplineDriftElement, StepDriftElement, ThermalLagElement, ViscoelasticElement,
    play_operator,
)
from polyforce_ros.physics.viscoelastic import PAPER_BURGERS


def _signals(seed, n=6000, dt=5e-3):
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.5, 1.5, n)) * dt  # irregular stamps
    x = np.abs(np.cumsum(rng.normal(0, 0.05, n))) + 0.3 * np.sin(t * rng.uniform(0.5, 3))
    temp = 24 + 3 * np.sin(2 * np.pi * t / rng.uniform(5, 20))
    return t, x, {"temperature_c": temp}


def _random_play(rng, history=False):
    n = int(rng.integers(1, 8))
    radii = np.sort(rng.uniform(0.01, 1.0, n)) + 1e-3 * np.arange(n)
    linear = rng.uniform(0.3, 2.0)
    weights = rng.uniform(0, 1.0, n) * (rng.uniform(size=n) > 0.2)
    if rng.uniform() < 0.5:  # stop type: negative weights, every partial sum with the linear weight above 5 %
        weights = -weights * 0.95 * linear / max(weights.sum(), 1e-12)
    return PlayHysteresisElement(linear, radii, weights, history_max=float(rng.uniform(0, 3)) if history else 0.0)


def _monotone_gain(rng, x_max=10.0):
    """A random polynomial gain, shrunk until it is monotone (invertible) over 0..x_max V."""
    q, c, d = rng.uniform(-0.05, 0.05), rng.uniform(-0.02, 0.02), rng.uniform(-0.005, 0.005)
    x = np.linspace(-1.0, x_max, 200)
    while np.min(1 + 2 * q * x + 3 * c * x ** 2 + 4 * d * x ** 3) < 0.2:
        q, c, d = q / 2, c / 2, d / 2
    return PolynomialGainElement(quadratic_per_v=q, cubic_per_v2=c, quartic_per_v3=d)


@pytest.mark.parametrize("seed", range(6))
def test_play_operator_equals_the_sample_by_sample_definition(seed):
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.normal(size=3000))
    m = int(rng.integers(1, 60))  # the default chunk shrinks with the number of plays: several chunks for many
    radii = np.sort(rng.uniform(0.1, 3.0, m))
    y0 = rng.uniform(-1, 1, m)
    y, expected = y0.copy(), []
    for v in x:
        y = np.minimum(np.maximum(y, v - radii), v + radii)
        expected.append(y.copy())
    np.testing.assert_allclose(play_operator(x, radii, y0, chunk=int(rng.integers(7, 1000))), expected, atol=1e-12)
    np.testing.assert_allclose(play_operator(x, radii, y0), expected, atol=1e-12)
    assert play_operator(x[:0], radii, y0).shape == (0, m)


def _elements(seed):
    rng = np.random.default_rng(seed)
    return [_random_play(rng), _random_play(rng, history=True),
            ThermalLagElement(coefficient_v_per_c=rng.uniform(-0.01, 0.01), reference_c=24.0, tau_s=rng.uniform(1, 60)),
            PolynomialDriftElement(rate_v_per_s=rng.uniform(-1e-3, 1e-3), curvature_v_per_s2=rng.uniform(-1e-6, 1e-6),
                                   cubic_v_per_s3=rng.uniform(-1e-8, 1e-8)),
            _monotone_gain(rng),
            ExponentialDriftElement(amplitude_v=rng.uniform(-0.1, 0.1), tau_s=rng.uniform(10, 100)),
            SplineDriftElement(knots_s=np.sort(rng.uniform(0.5, 1.0, 4)) * np.arange(1, 5) * 3.0,
                               values_v=rng.uniform(-0.05, 0.05, 4)),
            _random_jumps(rng)]


def _random_jumps(rng):
    """A zero that jumps 1-6 times within the first 25 s, half the time with a settling part."""
    n = int(rng.integers(1, 7))
    times = np.sort(rng.uniform(0.5, 25.0, n)) + 1e-3 * np.arange(n)
    settling = rng.uniform() < 0.5
    return StepDriftElement(times, rng.uniform(-0.05, 0.05, n), rng.uniform(0.5, 20.0) if settling else None,
                            rng.uniform(-0.05, 0.05, n) if settling else None)


@pytest.mark.parametrize("seed", range(4))
def test_backward_undoes_forward_and_streaming_equals_batch(seed):
    t, x, aux = _signals(seed)
    for element in _elements(seed):
        y = element.forward(t, x, aux)
        assert np.abs(y - x).max() > 1e-4, element.kind  # the effect is really there
        back = element.backward(t, y, aux)
        np.testing.assert_allclose(back, x, atol=1e-9, err_msg=element.kind)
        noisy = y + np.random.default_rng(seed).normal(0, 1e-3, y.size)
        stream = element.streaming()
        per_sample = [stream.step(ti, yi, {"temperature_c": ci}) for ti, yi, ci in zip(t, noisy, aux["temperature_c"])]
        np.testing.assert_allclose(per_sample, element.backward(t, noisy, aux), atol=1e-9, err_msg=element.kind)
        stream.reset()
        again = [stream.step(ti, yi, {"temperature_c": ci}) for ti, yi, ci in zip(t, noisy, aux["temperature_c"])]
        np.testing.assert_allclose(again, per_sample, atol=1e-12, err_msg=element.kind)


@pytest.mark.parametrize("seed", range(3))
def test_spline_drift_basis_is_the_element_linear_in_its_values(seed):
    # the fitter's design columns and the saved element are one rule: basis @ values == the element's drift
    rng = np.random.default_rng(seed)
    t, x, aux = _signals(seed)
    knots = np.cumsum(rng.uniform(1.0, 10.0, int(rng.integers(2, 9))))
    values = rng.uniform(-0.1, 0.1, knots.size)
    element = SplineDriftElement(knots_s=knots, values_v=values)
    drift = element.forward(t, x, aux) - x
    assert np.abs(drift).max() > 1e-3
    np.testing.assert_allclose(SplineDriftElement.basis(t - t[0], knots) @ values, drift, atol=1e-12)


@pytest.mark.parametrize("seed", range(3))
def test_step_drift_basis_is_the_element_linear_in_its_steps(seed):
    # the fitter's step columns and the saved element are one rule (a jump at a sample's own time included)
    rng = np.random.default_rng(seed)
    t, x, aux = _signals(seed)
    times = np.sort(rng.choice(t[1:] - t[0], int(rng.integers(1, 6)), replace=False))
    steps = rng.uniform(-0.1, 0.1, times.size)
    element = StepDriftElement(times_s=times, steps_v=steps)
    drift = element.forward(t, x, aux) - x
    assert np.abs(drift).max() > 1e-3
    np.testing.assert_allclose(StepDriftElement.basis(t - t[0], times) @ steps, drift, atol=1e-12)


def test_play_hysteresis_is_a_loop_and_history_starts_at_rest():
    e = PlayHysteresisElement(1.0, [0.2, 0.5], [0.3, 0.2], history_max=2.0)
    t = np.linspace(0, 4, 401)
    x = np.concatenate([np.linspace(0, 2, 201), np.linspace(2, 0, 201)[1:]])
    y = e.forward(t, x)
    assert y[0] == pytest.approx(0.0)
    up, down = y[:201], y[200:][::-1]
    assert np.max(down - up) > 0.2  # unloading above loading: a loop
    stop = PlayHysteresisElement(1.5, [0.2, 0.5], [-0.3, -0.2])  # negative weights: loading above unloading
    y = stop.forward(t, x)
    up, down = y[:201], y[200:][::-1]
    assert np.max(up - down) > 0.2 and np.all(np.diff(y[:201]) > 0)
    np.testing.assert_allclose(stop.backward(t, y), x, atol=1e-12)


@pytest.mark.parametrize("seed", range(3))
def test_model_file_round_trip_and_chain_inverse(tmp_path, seed):
    rng = np.random.default_rng(seed)
    elements = _elements(seed)
    chain = SensorChain([elements[0], ViscoelasticElement(PAPER_BURGERS), elements[4], elements[1], elements[2], elements[3],
                         elements[5], elements[7], OffsetElement(0.03)])
    path = save_model(tmp_path / "m.yaml", SensorModel(chain, {"source": "test"}))
    loaded = load_model(path).chain
    assert [e.to_dict() for e in loaded.elements] == [e.to_dict() for e in chain.elements]
    t, f, aux = _signals(seed + 10, n=4000, dt=0.01)
    f = 5 * f / f.max()
    v = loaded.forward(t, f, aux)
    np.testing.assert_allclose(loaded.backward(t, v, aux), f, atol=1e-6)
    assert set(ELEMENT_TYPES) >= {"play_hysteresis", "thermal_lag", "polynomial_drift", "polynomial_gain", "exponential_drift",
                                  "step_drift"}
    del rng


@pytest.mark.parametrize("mapping, message", [
    ({"type": "play_hysteresis", "linear_weight": 1.0, "radii": [0.2, 0.1], "weights": [0.1, 0.1]}, "increasing"),
    ({"type": "play_hysteresis", "linear_weight": 1.0, "radii": [0.1, 0.2], "weights": [-0.1, -0.95]}, "partial sum"),
    ({"type": "play_hysteresis", "linear_weight": 0.0, "radii": [0.1], "weights": [0.1]}, "linear_weight"),
    ({"type": "play_hysteresis", "linear_weight": 1.0, "radii": [0.1, 0.2], "weights": [0.1]}, "same length"),
    ({"type": "play_hysteresis", "linear_weight": 1.0, "radii": "0.1", "weights": [0.1]}, "list"),
    ({"type": "thermal_lag", "coefficient_v_per_c": 0.01, "reference_c": 24.0, "tau_s": -1.0}, "tau_s"),
    ({"type": "polynomial_drift", "rate_v_per_s": 0.0, "curvature_v_per_s2": 1e9, "cubic_v_per_s3": 0.0}, "curvature"),
    ({"type": "step_drift", "times_s": [2.0, 1.0], "steps_v": [0.1, 0.1]}, "increasing"),
    ({"type": "step_drift", "times_s": [0.0], "steps_v": [0.1]}, "> 0"),
    ({"type": "step_drift", "times_s": [1.0], "steps_v": [0.1], "recovery_tau_s": 5.0}, "together"),
    ({"type": "step_drift", "times_s": [1.0], "steps_v": [0.1], "recovery_tau_s": 5.0, "recoveries_v": [0.1, 0.2]},
     "same length"),
    ({"type": "step_drift", "times_s": [1.0], "steps_v": [0.1], "recovery_tau_s": 0.0, "recoveries_v": [0.1]},
     "recovery_tau_s"),
    ({"type": "step_drift", "times_s": [1.0], "steps_v": [1e4]}, "steps_v"),
])
def test_bad_element_mappings_are_model_errors(mapping, message):
    with pytest.raises(ModelError, match=message):
        ELEMENT_TYPES[mapping["type"]].from_dict(mapping)


def test_parsimony_compares_every_smaller_candidate_with_the_overall_best():
    from types import SimpleNamespace

    from polyforce_ros.discrepancy import engine

    def cand(name, size, cv):
        fit = SimpleNamespace(names=["c"] * size, structure=engine.Structure("elastic"), cv_mse=cv)
        return SimpleNamespace(name=name, fit=fit)

    a, b, c = cand("A", 14, 1.0), cand("B", 5, 2.0), cand("C", 3, 3.0)
    beats = {("A", "C")}  # A passes the acceptance test against C only; B is as good as A
    justified = lambda better, than: any(better is x.fit and than is y.fit for x in (a, b, c) for y in (a, b, c)  # noqa: E731
                                         if (x.name, y.name) in beats)
    assert engine._parsimonious([a, b, c], lambda _: True, justified) is b  # not C, which A clearly beats
    assert engine._parsimonious([a, c], lambda _: True, justified) is a
    assert engine._parsimonious([a, b, c], lambda x: x is not b, justified) is a  # only acceptable ones compete


@pytest.mark.parametrize("sigma_n", [0.002, 0.01, 0.05])
def test_the_reference_force_noise_is_measured_under_a_moving_load_and_bounds_the_narrowest_friction(sigma_n):
    from polyforce_ros.discrepancy.effects import EFFECTS
    from polyforce_ros.discrepancy.friction import FRICTION_NOISE_SIGMAS, force_noise_n
    from polyforce_ros.discrepancy.signals import Signals

    rng = np.random.default_rng(int(sigma_n * 1e4))
    t = np.arange(60000) * 0.01
    load = 5.0 + 4.0 * np.sin(2 * np.pi * t / 37.0) + 2.0 * np.sin(2 * np.pi * t / 5.3)  # moving all the time
    force = load + rng.normal(0.0, sigma_n, t.size)
    sig = Signals(t=t, f=force, v=np.zeros_like(t), temp=None, t0=0.0, duration_s=float(t[-1]), temp_ref=0.0,
                  span_f=float(np.ptp(force)))
    assert force_noise_n(sig) == pytest.approx(sigma_n, rel=0.1)
    assert min(EFFECTS["friction"].grid("", sig)) >= FRICTION_NOISE_SIGMAS * 0.9 * sigma_n


@pytest.mark.parametrize("sigma_n", [0.003, 0.03, 0.0005])
def test_a_stiction_band_at_the_narrowest_searched_is_at_its_noise_limit(sigma_n):
    """A friction fitted at the grid's narrowest band (set by the reference force's noise, or by 0.1 % of the span
    when the noise is smaller) wanted a narrower one, where a play acts on the force's smallest wiggles: the
    selection does not judge it. A band above that bound, or another effect, is not limited."""
    from polyforce_ros.discrepancy.effects import EFFECTS
    from polyforce_ros.discrepancy.friction import at_noise_limit
    from polyforce_ros.discrepancy.signals import Signals

    rng = np.random.default_rng(int(sigma_n * 1e4))
    t = np.arange(60000) * 0.01
    force = 5.0 + 4.0 * np.sin(2 * np.pi * t / 37.0) + rng.normal(0.0, sigma_n, t.size)
    sig = Signals(t=t, f=force, v=np.zeros_like(t), temp=None, t0=0.0, duration_s=float(t[-1]), temp_ref=0.0,
                  span_f=float(np.ptp(force)))
    low = min(EFFECTS["friction"].grid("", sig))
    # the noise sets this bound, or the span when the noise is below it
    assert low == pytest.approx(max(0.001 * sig.span_f, 4.0 * sigma_n), rel=0.1)
    assert at_noise_limit("friction", low, sig) and at_noise_limit("friction", 0.5 * low, sig)
    assert not at_noise_limit("friction", 1.5 * low, sig)
    assert not at_noise_limit("hysteresis", low, sig) and not at_noise_limit("friction", None, sig)


@settings(max_examples=200, deadline=None)
@given(q=st.floats(-30.0, 30.0), c=st.floats(-100.0, 100.0), d=st.floats(-100.0, 100.0),
       share=st.floats(0.0, 1.0), beyond=st.floats(0.0, 5.0))
def test_a_polynomial_gain_is_inverted_on_its_rising_branch_and_saturates_beyond_it(q, c, d, share, beyond):
    """Any curve: a reading made on the rising branch through zero comes back exactly (to the input), in batch
    and per sample; a reading beyond the branch (a fitted curve that turns over near the top of its range) comes
    back as the branch's end, never as a point of another branch or a jump."""
    gain = PolynomialGainElement(quadratic_per_v=q, cubic_per_v2=c, quartic_per_v3=d)
    low, high = gain.branch_v
    assert low < 0.0 < high
    x = np.clip(np.linspace(-2.0, 2.0, 101), low, high)
    slope = 1 + 2 * q * x + 3 * c * x ** 2 + 4 * d * x ** 3
    assert np.all(slope >= -1e-9)  # the branch rises
    y = gain.forward(None, x)
    np.testing.assert_allclose(gain.backward(None, y), x, atol=1e-9 * (1 + np.abs(y)).max())
    stream = gain.streaming()
    probe = float(y[int(share * 100)])
    assert stream.step(0.0, probe) == pytest.approx(float(gain.backward(None, np.array([probe]))[0]), abs=1e-12)
    for end in (low, high):
        if abs(end) < 100.0:  # the branch ends where the curve turns down, not where it only flattens
            past = end + np.sign(end) * 1e-6 * max(1.0, abs(end))
            assert 1 + 2 * q * past + 3 * c * past ** 2 + 4 * d * past ** 3 < 0.0
        if abs(end) < 100.0:  # past the turn (within any bridge's reach): the reading of the end, or more, is the end
            past = float(gain.forward(None, np.array([end]))[0]) + np.sign(end) * beyond
            assert gain.backward(None, np.array([past]))[0] == pytest.approx(end, abs=1e-9 * (1 + abs(end)))


def _fit(variant, names, coef_folds, sse_folds):
    from polyforce_ros.discrepancy.design import Fit, Structure, Term

    folds = [np.asarray(c, dtype=float) for c in coef_folds]
    coef = np.mean(folds, axis=0)
    sse = np.asarray(sse_folds, dtype=float)
    return Fit(Structure("burgers", (10.0,), (Term("hysteresis", variant),)), list(names), np.ones(len(names)), coef,
               folds, sse, float(sse.mean()), float(sse.mean()), 1000, 0.0)


@pytest.mark.parametrize("seed", range(6))
def test_scaled_plays_beside_the_bridge_are_kept_by_their_summed_weight_not_each_weight(seed):
    """The scaled plays' weights are one distribution, most of them at zero: a fit that extends the bridge's plays with
    them is kept when their sum lies 3 jackknife standard errors from zero (and it beats the bridge's fit), dropped
    when the sum does not, whatever each weight's own error."""
    from polyforce_ros.discrepancy.selection import SIGNIFICANT_SE, Selection
    from polyforce_ros.physics.fitting import block_jackknife_standard_errors

    rng = np.random.default_rng(seed)
    n_folds = 5
    smaller = _fit("bridge", ["j0", "play0", "offset"], [[0.2, 0.01, 0.02]] * n_folds, np.full(n_folds, 2.0))
    # two weights whose folds trade against each other: each uncertain alone, their sum certain
    trade = rng.uniform(0.5, 1.0) * np.array([1.0, -1.0, 1.0, -1.0, 0.0])
    total = rng.uniform(0.01, 0.02)
    certain = [[0.2, 0.01, 0.02, total / 2 + 0.02 * d, total / 2 - 0.02 * d, 0.0] for d in trade]
    names = ["j0", "play0", "offset", "scaled0", "scaled1", "scaled2"]
    larger = _fit("bridge_scaled", names, certain, np.full(n_folds, 1.0))
    folds = np.array(certain)[:, 3:5]
    assert np.all(np.abs(folds.mean(axis=0)) < SIGNIFICANT_SE * block_jackknife_standard_errors(folds))  # each alone
    noisy = [[0.2, 0.01, 0.02, 0.02 * d, -0.01 * d + 1e-3, 0.0] for d in trade]  # a sum the folds disagree on
    unsure = _fit("bridge_scaled", names, noisy, np.full(n_folds, 1.0))
    zeros = _fit("bridge_scaled", names, [[0.2, 0.01, 0.02, 0.0, 0.0, 0.0]] * n_folds, np.full(n_folds, 1.0))
    selection = Selection(None, smaller, floor_mse=0.5, has_temperature=False, min_confidence=0.8,  # type: ignore[arg-type]
                          min_excess_share=0.3, say=lambda s: None)
    kept = selection._nested([smaller, larger, unsure, zeros], "hysteresis")
    assert [f is larger or f is smaller for f in kept] == [True, True]  # by identity: a Fit's arrays have no truth value
    # without the smaller fit nothing says which columns the larger adds: it is not kept on their sum
    alone = selection._nested([larger, _fit("force", ["j0", "play0", "offset"], [[0.2, 0.01, 0.02]] * n_folds,
                                            np.full(n_folds, 2.0))], "hysteresis")
    assert not any(f is larger for f in alone)


@settings(max_examples=200, deadline=None)
@given(steps=st.lists(st.floats(-2.0, 2.0), min_size=1, max_size=200), radius_n=st.floats(0.01, 3.0))
def test_the_last_slide_of_a_friction_is_read_from_its_play(steps, radius_n):
    """Direction and index of each sample's last slide, read from the play's output, are those of a contact
    followed sample by sample (it slides when the force leaves the band around it)."""
    from polyforce_ros.discrepancy.friction import last_slides
    from polyforce_ros.physics.chain import play_operator

    force = np.cumsum(steps)
    contact, sigma_loop, last_loop = 0.0, [], []
    direction, last = 0.0, 0
    for k, x in enumerate(force):
        if x - radius_n > contact:
            contact, direction, last = x - radius_n, 1.0, k
        elif x + radius_n < contact:
            contact, direction, last = x + radius_n, -1.0, k
        sigma_loop.append(direction)
        last_loop.append(last)
    sigma, last_index = last_slides(play_operator(force, [radius_n])[:, 0])
    assert sigma.tolist() == sigma_loop
    assert last_index.tolist() == last_loop


def _friction_signals(temperature_c):
    from polyforce_ros.discrepancy.signals import Signals

    t = np.arange(6000) * 0.1
    force = 5.0 + 4.0 * np.sin(2 * np.pi * t / 37.0) + 1.5 * np.sin(2 * np.pi * t / 5.3)
    temp = None if temperature_c is None else temperature_c(t)
    return Signals(t=t, f=force, v=np.zeros_like(t), temp=temp, t0=0.0, duration_s=float(t[-1]),
                   temp_ref=0.0 if temp is None else float(np.mean(temp)), core_ref=PAPER_BURGERS,
                   span_f=float(np.ptp(force)))


@pytest.mark.parametrize("variant", ["thermal", "thermal_lag15", "thermal_lag47.5"])  # the last as the polish names it
def test_the_thermal_band_column_is_the_first_order_change_of_the_stop_with_its_band(variant):
    """The band column times the log-slope s is the change of the core's output when the stop's band is
    r exp(s (T - T_ref)), to first order in s: the error left falls faster than s (about as s**1.5, since a
    reversal moves by O(s) in time as well), so it is a small part of the change."""
    from polyforce_ros.discrepancy.effects import EFFECTS
    from polyforce_ros.physics.chain import lagged_temperature_c, play_operator
    from polyforce_ros.physics.viscoelastic import simulate_deformation_columns

    sig = _friction_signals(lambda t: 20.0 + 8.0 * np.sin(2 * np.pi * t / 300.0))
    radius_n = 0.4
    cols = {c[0]: c[1] for c in EFFECTS["friction"].columns(sig, variant, radius_n)}
    lag_s = {"thermal": 0.0, "thermal_lag15": 15.0, "thermal_lag47.5": 47.5}[variant]
    temp = lagged_temperature_c(sig.t, sig.temp, lag_s) if lag_s else sig.temp

    def core_of_stop(slope):
        bands = radius_n * np.exp(slope * (temp - sig.temp_ref))
        stop = sig.f - play_operator(sig.f, bands[:, None])[:, 0]
        return -simulate_deformation_columns(PAPER_BURGERS, sig.t, stop[:, None])[:, 0]

    def rms(x):
        return float(np.sqrt(np.mean(x ** 2)))

    errors = [rms(core_of_stop(s) - cols["friction"] - s * cols["friction_band"]) for s in (0.02, 0.01)]
    assert errors[0] < 0.25 * rms(core_of_stop(0.02) - cols["friction"])
    assert errors[1] < errors[0] / 2.5


def test_a_friction_band_that_follows_temperature_is_searched_only_where_there_is_a_temperature():
    from polyforce_ros.discrepancy.effects import EFFECTS

    without, warm = _friction_signals(None), _friction_signals(lambda t: 20.0 + 0.01 * t)
    assert EFFECTS["friction"].grid("", without) and EFFECTS["friction"].grid("", warm)
    for variant in ("thermal", "thermal_lag15"):
        assert EFFECTS["friction"].grid(variant, without) == []
        assert EFFECTS["friction"].grid(variant, warm) == EFFECTS["friction"].grid("", warm)


def test_a_fitted_thermal_band_is_saved_as_its_friction_element():
    from polyforce_ros.discrepancy.effects import EFFECTS
    from polyforce_ros.physics.chain import FrictionElement

    sig = _friction_signals(lambda t: 20.0 + 0.01 * t)
    (slot, element), = EFFECTS["friction"].to_elements({"friction": 0.8, "friction_band": -0.04}, "thermal_lag15", 0.3, sig)
    assert slot == "before" and isinstance(element, FrictionElement)
    assert (element.radius_n, element.coupling, element.band_log_slope_per_c) == pytest.approx((0.3, 0.8, -0.05))
    assert (element.reference_c, element.temperature_lag_s) == pytest.approx((sig.temp_ref, 15.0))
    (_, plain), = EFFECTS["friction"].to_elements({"friction": 0.8, "friction_band": -0.04}, "", 0.3, sig)
    assert plain.band_log_slope_per_c == 0.0
    assert EFFECTS["friction"].to_elements({"friction": 0.0, "friction_band": -0.04}, "thermal", 0.3, sig) == []


@given(st.floats(1.0, 200.0))
@settings(max_examples=200, deadline=None)
def test_a_clock_lag_variant_names_the_lag_it_is_made_from(lag_s):
    """The polish refines a clock's lag through its variant's name: at twelve digits the name gives the lag back and
    a step of the least squares' size (1e-8) changes it (so the polish sees every step it takes), at three digits
    within half a per cent (what the diagnosis reports)."""
    from polyforce_ros.discrepancy.effects import EFFECTS, clock_lag_variant, clock_of

    assert clock_of(clock_lag_variant(lag_s, 12)) == (pytest.approx(lag_s, rel=1e-11), 0.0)
    stepped = clock_of(clock_lag_variant(lag_s * (1.0 + 1e-8), 12))[0]
    assert stepped > clock_of(clock_lag_variant(lag_s, 12))[0]
    assert clock_of(clock_lag_variant(lag_s))[0] == pytest.approx(lag_s, rel=5e-3)
    assert {"lag5", "lag15", "lag45"} <= set(EFFECTS["thermo_rheological"].variants)
    # a clock that slows as it warms: the same lag, the other sign
    from polyforce_ros.discrepancy.effects import clock_sign

    slowing = clock_lag_variant(lag_s, 12, slowing=True)
    assert clock_of(slowing) == clock_of(clock_lag_variant(lag_s, 12)) and clock_sign(slowing) == -1.0
    assert clock_sign(clock_lag_variant(lag_s)) == 1.0 and clock_sign("wlf25") == 1.0 and clock_sign("slowing") == -1.0
    assert {"slowing", "slowing_lag15"} <= set(EFFECTS["thermo_rheological"].variants)


@given(st.floats(1.0, 200.0))
@settings(max_examples=200, deadline=None)
def test_a_friction_band_lag_variant_names_its_lag_and_is_tested_as_the_grid_variant_it_started_from(lag_s):
    """A friction band's lag is refined through its variant's name like a clock's; whatever lag it gets, the variant
    is the grid's lagged band for the significance test of its band column (``extends``), and its element follows the
    refined lag (its column: the band column's test)."""
    from polyforce_ros.discrepancy.effects import EFFECTS
    from polyforce_ros.discrepancy.friction import BAND_LAGS_S, band_lag_s, band_lag_variant, is_band

    friction = EFFECTS["friction"]
    assert band_lag_s(band_lag_variant(lag_s, 12)) == pytest.approx(lag_s, rel=1e-11)
    assert band_lag_s(band_lag_variant(lag_s * (1.0 + 1e-8), 12)) > band_lag_s(band_lag_variant(lag_s, 12))
    assert band_lag_s(band_lag_variant(lag_s)) == pytest.approx(lag_s, rel=5e-3)
    refined = band_lag_variant(lag_s)
    assert is_band(refined) and friction.grid_variant(refined) in friction.extends
    assert friction.grid_variant(refined) in BAND_LAGS_S and BAND_LAGS_S[friction.grid_variant(refined)] > 0.0
    assert [friction.grid_variant(v) for v in friction.variants] == list(friction.variants)
    coef = {"friction": 1.0, "friction_band": 0.05}
    element = friction.to_elements(coef, refined, 0.2, _friction_signals(lambda t: 20.0 + 0.0 * t))[0][1]
    assert element.temperature_lag_s == pytest.approx(band_lag_s(refined))
