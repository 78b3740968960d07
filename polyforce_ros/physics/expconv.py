"""Exponential convolution of a piecewise-linear signal: the one recursion under every model.

Every linear viscoelastic law used here reduces to sums of terms of the form

    y(t) = y(t0) * exp(-r (t - t0)) + integral_{t0}^{t} exp(-r (t - s)) u(s) ds

with a decay rate ``r >= 0`` (1/s). Forward simulation uses it with the creep
compliance (Kelvin elements: ``r = 1/tau``; viscous flow: ``r = 0``, a plain
integral) and compensation uses it with the relaxation modulus (eq. 10-12 of
seed 000).

Between two samples the input ``u`` is taken to vary linearly, for which the
integral has a closed form. The update is therefore *exact* for piecewise-linear
input, for any sample spacing ``h`` (irregular stamps, long gaps), and it only
ever multiplies by ``exp(-r h) <= 1``: unlike the literal recursion of seed 000
(which multiplies by ``exp(+r t_i)`` and overflows float64 after
``709 / r`` seconds, about 68 min at r = 0.173 1/s) it is stable for records of
any length.

For one step of length ``h`` with ``z = r h`` and ``E = exp(-z)``:

    y_i = E y_{i-1} + h (alpha(z) u_{i-1} + beta(z) u_i)
    alpha(z) = (1 - E - z E) / z**2      (-> 1/2 as z -> 0)
    beta(z)  = (z - 1 + E)   / z**2      (-> 1/2 as z -> 0)

so ``r = 0`` is the trapezoidal rule, itself exact for linear input.
"""
from __future__ import annotations

import math
from typing import Iterable, Optional, cast, overload

import numpy as np
import numpy.typing as npt
from scipy import signal

__all__ = ["uniform_step", "uniform_step_after", "step_weights", "step_weights_scalar", "exp_convolve",
    "exp_convolve_columns", "lag_cascade", "ExpConvState"]

# Below this z the closed forms lose digits to cancellation; the Taylor series
# to z**5 is accurate to ~1e-16 relative there.
_SERIES_BELOW = 1e-2
# Batch chunks: the decay accumulated over one chunk stays below this, so
# exp(+Z) cannot overflow (float64 limit ~709), and the chunk length bounds the
# rounding of the running sum.
_MAX_CHUNK_DECAY = 300.0
_MAX_CHUNK_LEN = 1 << 16
# Stamps whose spacings agree to this relative tolerance, or to the float64
# rounding of the times themselves, are uniform; their mean spacing is then
# the best estimate of the step (per-sample differences carry the rounding).
_UNIFORM_RTOL = 1e-12


def uniform_step(t: npt.ArrayLike) -> Optional[float]:
    """The common step of sample times ``t`` if they are uniform up to rounding, else None.

    Parameters
    ----------
    t : (n,) array_like of float
        Sample times [s].

    Returns
    -------
    float or None
        The mean spacing ``(t[-1] - t[0]) / (n - 1)`` [s] when the spacings spread by no more
        than 1e-12 of the first spacing plus the float64 rounding of the stamps; None for
        fewer than two samples, a non-positive span, or irregular spacing.
    """
    t = np.asarray(t, dtype=float)
    if t.size < 2:
        return None
    span = float(t[-1] - t[0])
    if span <= 0:
        return None
    lo, hi = _spacing_range(t)
    if hi - lo <= _UNIFORM_RTOL * float(t[1] - t[0]) + _rounding_s(t[0], t[-1]):
        return span / (t.size - 1)
    return None


def uniform_step_after(t_prev_s: Optional[float], t: npt.ArrayLike) -> Optional[float]:
    """The common step of a previous sample time ``t_prev_s`` followed by ``t``, else None.

    As :func:`uniform_step` of the joined times (``t`` alone when ``t_prev_s`` is None),
    without copying ``t``.

    Parameters
    ----------
    t_prev_s : float or None
        Time of the sample before ``t`` [s], or None when there is none.
    t : (n,) array_like of float
        Sample times [s].

    Returns
    -------
    float or None
        The common step [s], or None when the joined times are not uniform (or too few:
        an empty ``t``, or a single ``t`` without ``t_prev_s``).
    """
    t = np.asarray(t, dtype=float)
    if t_prev_s is None:
        return uniform_step(t)
    if t.size == 0:
        return None
    gap = float(t[0]) - float(t_prev_s)
    step = uniform_step(t) if t.size > 1 else (gap if gap > 0 else None)
    if step is not None and abs(gap - step) <= _UNIFORM_RTOL * step + _rounding_s(t_prev_s, t[-1]):
        return step
    return None


def _rounding_s(t_first_s: float, t_last_s: float) -> float:
    """Spacing differences within float64 rounding of the stamps themselves."""
    return 8 * np.finfo(float).eps * max(abs(float(t_first_s)), abs(float(t_last_s)))


def _spacing_range(t: np.ndarray, chunk: int = _MAX_CHUNK_LEN) -> tuple[float, float]:
    """(min, max) of ``np.diff(t)``, computed in cache-sized chunks.

    A whole-array diff would write and re-read 8 bytes per sample; on a 10 M
    sample record that check alone cost a quarter of a first-order filter pass.
    """
    buf = np.empty(min(chunk, t.size - 1))
    lo, hi = math.inf, -math.inf
    for start in range(0, t.size - 1, chunk):
        stop = min(start + chunk, t.size - 1)
        d = np.subtract(t[start + 1:stop + 1], t[start:stop], out=buf[: stop - start])
        lo, hi = min(lo, float(d.min())), max(hi, float(d.max()))
    return lo, hi


@overload
def step_weights(z: float) -> tuple[float, float, float]:
    """Scalar ``z``: three floats."""


@overload
def step_weights(z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Array ``z``: three arrays of its shape."""


def step_weights(z: npt.ArrayLike) -> tuple[float, float, float] | tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Weights ``(E, alpha, beta)`` of one step of the exact exponential recursion.

    Works on scalars and arrays. ``E = exp(-z)``; ``alpha``/``beta`` weight the
    previous/current input sample (see module docstring); multiply them by the
    step length ``h`` in seconds. Below ``z = 0.01`` ``alpha`` and ``beta`` come
    from their Taylor series (the closed forms lose digits to cancellation there).

    Parameters
    ----------
    z : float or array_like of float
        Decay over the step, ``z = r h`` (rate [1/s] times step [s]; dimensionless, >= 0).

    Returns
    -------
    E, alpha, beta : float or ndarray
        Decay factor and input weights (dimensionless): three floats for a scalar (0-d)
        ``z``, else three arrays of the shape of ``z``.
    """
    z = np.asarray(z, dtype=float)
    e = np.exp(-z)
    small = z < _SERIES_BELOW
    zs = np.where(small, z, 0.0)
    # Series of (1 - e^-z (1+z))/z^2 and (z - 1 + e^-z)/z^2.
    alpha_s = 0.5 - zs / 3 + zs**2 / 8 - zs**3 / 30 + zs**4 / 144 - zs**5 / 840
    beta_s = 0.5 - zs / 6 + zs**2 / 24 - zs**3 / 120 + zs**4 / 720 - zs**5 / 5040
    zl = np.where(small, 1.0, z)
    em1 = np.expm1(-zl)  # e^-z - 1, accurate
    alpha_l = (-em1 - zl * np.exp(-zl)) / zl**2
    beta_l = (zl + em1) / zl**2
    alpha = np.where(small, alpha_s, alpha_l)
    beta = np.where(small, beta_s, beta_l)
    if alpha.ndim == 0:
        return float(e), float(alpha), float(beta)
    return e, alpha, beta


def step_weights_scalar(z: float) -> tuple[float, float, float]:
    """Scalar fast path of :func:`step_weights` for per-sample use (no numpy).

    Parameters
    ----------
    z : float
        Decay over the step, ``z = r h`` (dimensionless, >= 0).

    Returns
    -------
    E, alpha, beta : float
        Decay factor ``exp(-z)`` and the weights of the previous and current input
        sample (dimensionless; multiply ``alpha``/``beta`` by ``h`` [s]).
    """
    e = math.exp(-z)
    if z < _SERIES_BELOW:
        z2 = z * z
        alpha = 0.5 - z / 3 + z2 / 8 - z2 * z / 30 + z2 * z2 / 144 - z2 * z2 * z / 840
        beta = 0.5 - z / 6 + z2 / 24 - z2 * z / 120 + z2 * z2 / 720 - z2 * z2 * z / 5040
    else:
        em1 = math.expm1(-z)
        alpha = (-em1 - z * e) / (z * z)
        beta = (z + em1) / (z * z)
    return e, alpha, beta


def exp_convolve(t_s: npt.ArrayLike, u: npt.ArrayLike, rates_per_s: npt.ArrayLike, y0: Optional[npt.ArrayLike] = None,
                 u_prev: Optional[float] = None, t_prev_s: Optional[float] = None) -> np.ndarray:
    """Exponential convolutions of one piecewise-linear signal, vectorised.

    Parameters
    ----------
    t_s : (n,) array of float
        Sample times in seconds, non-decreasing (equal stamps are allowed and
        contribute nothing to the integral). Any spacing.
    u : (n,) array of float
        Input samples (any unit ``U``).
    rates_per_s : (m,) array of float
        Decay rates ``r_k >= 0`` in 1/s.
    y0 : (m,) array, optional
        State ``y_k`` at the previous sample (``t_prev_s``); zeros if omitted.
    u_prev, t_prev_s : float, optional
        Previous sample and its time. When given, the first returned value
        includes the step from ``t_prev_s`` to ``t_s[0]``; when omitted the
        record starts at ``t_s[0]`` with ``y = y0`` there.

    Returns
    -------
    (n, m) array
        ``y_k(t_i)`` in ``U*s``.
    """
    t = np.asarray(t_s, dtype=float)
    u = np.asarray(u, dtype=float)
    rates = np.atleast_1d(np.asarray(rates_per_s, dtype=float))
    if u.shape != t.shape:
        raise ValueError(f"exp_convolve: u must have the shape of t_s, {t.shape}; got {u.shape}")
    n, m = t.size, rates.size
    out = np.empty((n, m))
    if n == 0:
        return out
    y_start = np.zeros(m) if y0 is None else np.asarray(y0, dtype=float).copy()
    if u_prev is not None:
        t_all = np.concatenate(([cast(float, t_prev_s)], t))
        u_all = np.concatenate(([u_prev], u))
    else:
        t_all, u_all = t, u
    h = np.diff(t_all)
    if np.any(h < 0):
        raise ValueError("exp_convolve: sample times must be non-decreasing")
    if u_prev is None:
        out[0] = y_start
        rows = slice(1, None)
    else:
        rows = slice(0, None)
    if h.size == 0:
        return out
    step = uniform_step(t_all)
    for k, r in enumerate(rates):
        if step is not None:
            out[rows, k] = _convolve_uniform(step, u_all, r, y_start[k])
        else:
            out[rows, k] = _convolve_irregular(h, u_all, r, y_start[k])
    return out


def _convolve_uniform(h: float, u_all: np.ndarray, r: float, y_start: npt.ArrayLike) -> np.ndarray:
    """Recursion for constant spacing ``h``: one first-order IIR section (lfilter) along axis 0.

    ``u_all`` may hold one signal (n,) or many as columns (n, m), with
    ``y_start`` a scalar or one value per column.
    """
    e, alpha, beta = step_weights(r * h)
    drive = h * (alpha * u_all[:-1] + beta * u_all[1:])
    zi = e * np.reshape(np.broadcast_to(y_start, u_all.shape[1:]), (1,) + u_all.shape[1:])
    y, _ = signal.lfilter([1.0], [1.0, -e], drive, axis=0, zi=zi)
    return np.asarray(y)


_IrregularWeights = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def _irregular_weights(h: np.ndarray, r: float) -> _IrregularWeights:
    """What :func:`_convolve_irregular` needs of the spacings ``h`` [s] and the rate ``r`` [1/s] alone: the
    accumulated decay and the step weights ``(zc, E, alpha, beta)``, computed once for any number of inputs."""
    z = r * h
    e, alpha, beta = step_weights(z)
    return np.cumsum(z), e, alpha, beta


def _convolve_irregular(h: np.ndarray, u_all: np.ndarray, r: float, y_start: float,
                        weights: Optional[_IrregularWeights] = None) -> np.ndarray:
    """Recursion for arbitrary spacings, in chunks of bounded accumulated decay.

    Within a chunk the solution is ``y_i = exp(-Z_i) (y_in + sum_j exp(Z_j) d_j)``
    with ``Z`` the decay accumulated since the chunk start; bounding ``Z`` keeps
    ``exp(Z)`` finite, and chunk length bounds the rounding of the sum. ``weights``: those of
    :func:`_irregular_weights` for the same ``h`` and ``r``, when already at hand.
    """
    zc, e, alpha, beta = _irregular_weights(h, r) if weights is None else weights
    drive = h * (alpha * u_all[:-1] + beta * u_all[1:])
    y = np.empty_like(drive)
    start, y_in, n = 0, y_start, drive.size
    while start < n:
        base = zc[start - 1] if start else 0.0
        stop = int(np.searchsorted(zc, base + _MAX_CHUNK_DECAY, side="right"))
        stop = min(max(stop, start + 1), start + _MAX_CHUNK_LEN, n)
        big_z = zc[start:stop] - base
        if stop - start == 1:
            y[start] = e[start] * y_in + drive[start]
        else:
            acc = np.cumsum(np.exp(big_z) * drive[start:stop])
            y[start:stop] = np.exp(-big_z) * (y_in + acc)
        y_in = y[stop - 1]
        start = stop
    return np.asarray(y)


def lag_cascade(t_s: npt.ArrayLike, x: npt.ArrayLike, tau_s: float, n_stages: int) -> np.ndarray:
    """``x`` through ``n_stages`` equal first-order lags ``tau y' + y = u`` in series, each from rest.

    Each stage is the exact recursion of :func:`exp_convolve` (piecewise-linear input, any spacing) times the rate,
    its output zero at ``t_s[0]``: the same numbers as running a lag's forward pass ``n_stages`` times, with the
    step weights of irregular stamps computed once instead of once per stage.

    Parameters
    ----------
    t_s : (n,) array_like of float
        Sample times [s], non-decreasing.
    x : (n,) array_like of float
        Input (any unit ``U``); the lags start at rest, so an input that does not start at zero steps at ``t_s[0]``.
    tau_s : float
        Time constant of each stage [s], > 0.
    n_stages : int
        Number of stages, >= 0 (zero returns ``x``).

    Returns
    -------
    (n,) ndarray of float
        The output of the last stage, in ``U``.
    """
    t, y = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
    if y.shape != t.shape:
        raise ValueError(f"lag_cascade: x must have the shape of t_s, {t.shape}; got {y.shape}")
    if not (math.isfinite(tau_s) and tau_s > 0.0):
        raise ValueError(f"lag_cascade: tau_s must be finite and > 0, got {tau_s!r}")
    rate = 1.0 / tau_s
    h = np.diff(t)
    if np.any(h < 0):
        raise ValueError("lag_cascade: sample times must be non-decreasing")
    step = uniform_step(t) if h.size else None
    weights = _irregular_weights(h, rate) if h.size and step is None else None
    for _ in range(n_stages):
        out = np.zeros(t.size)
        if h.size:
            out[1:] = (_convolve_uniform(step, y, rate, 0.0) if step is not None
                       else _convolve_irregular(h, y, rate, 0.0, weights))
        y = out * rate
    return y


def exp_convolve_columns(t_s: npt.ArrayLike, u: npt.ArrayLike, rate_per_s: float) -> np.ndarray:
    """:func:`exp_convolve` of every column of ``u`` with one rate, from rest.

    One ``lfilter`` call along axis 0 when the spacing is uniform (many
    signals through one filter at once); column by column otherwise.

    Parameters
    ----------
    t_s : (n,) array_like of float
        Sample times [s], non-decreasing.
    u : (n, m) array_like of float
        Input signals as columns (any unit ``U``).
    rate_per_s : float
        Decay rate ``r >= 0`` [1/s].

    Returns
    -------
    (n, m) ndarray of float
        ``y(t_i)`` of each column in ``U*s``, zero at the first sample (all zeros for
        fewer than two samples).
    """
    t = np.asarray(t_s, dtype=float)
    u = np.asarray(u, dtype=float)
    out = np.zeros_like(u)
    if t.size < 2:
        return out
    step = uniform_step(t)
    if step is not None:
        out[1:] = _convolve_uniform(step, u, rate_per_s, 0.0)
        return out
    for k in range(u.shape[1]):
        out[:, k] = exp_convolve(t, u[:, k], [rate_per_s])[:, 0]
    return out


class ExpConvState:
    """Streaming form of :func:`exp_convolve`: O(m) work and memory per sample.

    ``update(t_s, u)`` returns the state vector after the new sample (a view of
    internal storage, copy it to keep it). The first sample only initialises
    the previous-sample memory. Returns ``None`` and changes nothing when the
    time goes backwards, so the caller decides what to do with such a sample.

    Parameters
    ----------
    rates_per_s : array_like of float
        Decay rates ``r_k >= 0`` [1/s], one state per rate.
    """

    __slots__ = ("rates_per_s", "y", "t_prev_s", "u_prev", "_h_cached", "_w_cached")

    def __init__(self, rates_per_s: npt.ArrayLike) -> None:
        self.rates_per_s = [float(r) for r in np.atleast_1d(rates_per_s)]
        self.y = [0.0] * len(self.rates_per_s)
        self.t_prev_s: Optional[float] = None
        self.u_prev = 0.0
        self._h_cached: Optional[float] = None
        self._w_cached: list[tuple[float, float, float]] = []  # filled with _h_cached (read only after it)

    def reset(self, y: Optional[Iterable[float]] = None) -> None:
        """Forget the history: no previous sample, and the state set to ``y``.

        Parameters
        ----------
        y : iterable of float, optional
            New state, one value per rate (input unit times s); zeros when omitted.
        """
        self.y = [0.0] * len(self.rates_per_s) if y is None else [float(v) for v in y]
        self.t_prev_s = None
        self.u_prev = 0.0

    def update(self, t_s: float, u: float) -> Optional[list[float]]:
        """Advance the state to a new sample by the exact exponential recursion.

        Parameters
        ----------
        t_s : float
            Sample time [s]. A stamp equal to the previous one is a zero-length step
            (the state does not change; the new value becomes the previous sample).
        u : float
            Input sample (any unit ``U``), taken to vary linearly from the previous one.

        Returns
        -------
        list of float or None
            The state ``y_k`` after the sample (``U*s``, one per rate): the internal list
            itself, updated in place by later calls, so copy it to keep it. The first
            sample after construction or :meth:`reset` only initialises the previous
            sample and returns the state unchanged. None when ``t_s`` is earlier than the
            previous sample; nothing is changed then.
        """
        if self.t_prev_s is None:
            self.t_prev_s, self.u_prev = t_s, u
            return self.y
        h = t_s - self.t_prev_s
        if h < 0.0:
            return None
        # At a steady rate, steps from stamps in seconds differ in their last bits: the cached
        # weights serve a step within 1e-12 (relative) of theirs, an error of ~1e-12 * r * h.
        h_cached = self._h_cached
        if h_cached is None or abs(h - h_cached) > 1e-12 * h_cached:
            self._w_cached = [step_weights_scalar(r * h) for r in self.rates_per_s]
            self._h_cached = h
        u_prev = self.u_prev
        y = self.y
        for k, (e, alpha, beta) in enumerate(self._w_cached):
            y[k] = e * y[k] + h * (alpha * u_prev + beta * u)
        self.t_prev_s, self.u_prev = t_s, u
        return y
