"""The shared recursion: exact for piecewise-linear input, stable, batch == streaming."""
import math

import numpy as np
import pytest

from polyforce_ros.physics.chain import SensorLagElement
from polyforce_ros.physics.expconv import ExpConvState, exp_convolve, lag_cascade, step_weights, step_weights_scalar


def exact_linear(t, a, b, r):
    """int_0^t exp(-r (t-s)) (a + b s) ds, closed form."""
    if r == 0:
        return a * t + 0.5 * b * t * t
    rt = r * t
    # Written with expm1 in combined form: the textbook t/r - (1 - e^-rt)/r^2 cancels badly.
    return -a * np.expm1(-rt) / r + b * (rt + np.expm1(-rt)) / r**2


@pytest.mark.parametrize("r", [0.0, 7e-4, 0.173, 5.0, 300.0])
def test_exact_for_linear_input_on_irregular_grid(r):
    rng = np.random.default_rng(1)
    t = np.concatenate(([0.0], np.cumsum(rng.exponential(0.01, 2000))))
    u = 0.3 + 2.0 * t
    y = exp_convolve(t, u, [r])[:, 0]
    np.testing.assert_allclose(y, exact_linear(t, 0.3, 2.0, r), rtol=1e-11, atol=1e-13)


def test_weights_continuous_across_series_threshold():
    z = np.array([1e-2 * (1 - 1e-9), 1e-2 * (1 + 1e-9)])
    e, a, b = step_weights(z)
    assert abs(a[0] - a[1]) < 1e-10 and abs(b[0] - b[1]) < 1e-10
    for zi in (0.0, 1e-8, 5e-3, 0.02, 3.0, 800.0):
        np.testing.assert_allclose(step_weights_scalar(zi), step_weights(zi), rtol=1e-14, atol=1e-300)
    # Trapezoid limit and the sum rule alpha + beta = (1 - e^-z)/z.
    assert step_weights(0.0)[1:] == (0.5, 0.5)
    e, a, b = step_weights(0.37)
    assert math.isclose(a + b, (1 - math.exp(-0.37)) / 0.37, rel_tol=1e-14)


def test_uniform_and_irregular_paths_agree():
    t = np.arange(0, 50, 1e-3)
    u = np.sin(t) + 0.1 * np.cos(17 * t)
    uniform = exp_convolve(t, u, [0.0, 0.173, 2.0])
    jitter = t + np.concatenate(([0.0], np.full(t.size - 1, 1e-15)))  # breaks exact uniformity
    jitter[1::2] += 1e-9
    irregular = exp_convolve(jitter, u, [0.0, 0.173, 2.0])
    np.testing.assert_allclose(irregular, uniform, rtol=0, atol=1e-8)


def test_streaming_matches_batch_with_gap_and_duplicates():
    rng = np.random.default_rng(2)
    t = np.cumsum(rng.uniform(0.0005, 0.0015, 5000))
    t[2000:] += 10.0  # a 10 s gap
    t[3000] = t[2999]  # a duplicate stamp
    u = rng.normal(size=t.size)
    rates = [7e-4, 0.173, 40.0]
    batch = exp_convolve(t, u, rates)
    state = ExpConvState(rates)
    stream = np.array([list(state.update(ti, ui)) for ti, ui in zip(t, u)])
    np.testing.assert_allclose(stream, batch, rtol=1e-10, atol=1e-12)


def test_state_rejects_time_going_backwards_and_keeps_state():
    state = ExpConvState([0.5])
    state.update(0.0, 1.0)
    before = list(state.update(1.0, 1.0))
    assert state.update(0.5, 100.0) is None
    assert state.y == before and state.t_prev_s == 1.0
    with pytest.raises(ValueError, match="non-decreasing"):
        exp_convolve([0.0, 1.0, 0.5], [1.0, 1.0, 1.0], [0.5])


def test_no_overflow_far_beyond_paper_recursion_limit():
    # The literal recursion of eq. 12 needs exp(r t) and overflows past 709 / r seconds.
    r = 0.173
    t_start = 10 * 709 / r  # ~11 h
    with pytest.raises(OverflowError):
        math.exp(r * t_start)
    elapsed = np.arange(100_000) * 1e-3
    t = t_start + elapsed  # stamps near 4e4 s carry ~7e-12 s of float rounding each
    y = exp_convolve(t, np.ones_like(t), [r])[:, 0]
    assert np.all(np.isfinite(y))
    # Uniform stamps are integrated with their common step, i.e. at the intended elapsed times.
    np.testing.assert_allclose(y, -np.expm1(-r * elapsed) / r, rtol=1e-10)


def test_uniform_step_after_a_previous_sample():
    from polyforce_ros.physics.expconv import uniform_step_after

    t = 1e5 + np.arange(1, 1001) * 1e-3  # stamps far from zero: rounding of the times themselves
    assert uniform_step_after(1e5, t) == pytest.approx(1e-3)
    assert uniform_step_after(None, t) == pytest.approx(1e-3)
    assert uniform_step_after(1e5 - 1e-3, t) is None  # the gap to the block is two steps
    assert uniform_step_after(1e5, t[:1]) == pytest.approx(1e-3)  # one sample: the gap is the step
    assert uniform_step_after(t[0], t[:1]) is None  # a duplicate stamp is no step


@pytest.mark.parametrize("stamps", ["jittered", "uniform", "gap"])
@pytest.mark.parametrize("n_stages", [0, 1, 3])
def test_lag_cascade_is_the_lag_run_again_and_again(stamps, n_stages):
    """The cascade gives the very numbers of a lag's forward pass repeated: it only computes the weights once."""
    rng = np.random.default_rng(n_stages)
    t = np.arange(3000) / 1000.0
    if stamps == "jittered":
        t = t + rng.uniform(-0.3e-3, 0.3e-3, t.size)
    elif stamps == "gap":
        t = np.concatenate((t[:1000], t[1800:]))
    x = np.cumsum(rng.normal(0.0, 1.0, t.size))
    tau_s = 0.0137
    expected = x
    for _ in range(n_stages):
        expected = np.asarray(SensorLagElement(tau_s=tau_s).forward(t, expected), dtype=float)
    assert np.array_equal(lag_cascade(t, x, tau_s, n_stages), expected)


@pytest.mark.parametrize("bad", [dict(tau_s=0.0), dict(tau_s=float("nan")), dict(tau_s=-1.0),
                                 dict(t=[0.0, 0.2, 0.1]), dict(x=[1.0, 1.0]), dict(x=np.ones((3, 2)))])
def test_lag_cascade_refuses_what_has_no_meaning(bad):
    t = np.asarray(bad.get("t", [0.0, 0.1, 0.2]))
    with pytest.raises(ValueError):
        lag_cascade(t, bad.get("x", np.ones(t.size)), bad.get("tau_s", 0.01), 2)


@pytest.mark.parametrize("u", [[1.0, 2.0], [1.0, 2.0, 3.0, 4.0], np.ones((3, 1))])
def test_exp_convolve_refuses_an_input_that_is_not_one_value_per_stamp(u):
    """A length mismatch would otherwise be filtered silently over the shorter of the two (or broadcast)."""
    with pytest.raises(ValueError, match="shape of t_s"):
        exp_convolve([0.0, 0.1, 0.2], u, [1.0])
