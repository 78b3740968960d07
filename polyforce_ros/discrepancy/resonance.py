"""Stage 5b of :func:`.engine.diagnose`: a lightly damped mechanical mode, fitted at the record's rate.

The design of the other effects runs on block means at the fit rate (100 Hz), where a 15-60 Hz mode is averaged
away. A mode acts on the voltage the rest of the model predicts: ``V = H(p) + noise`` with
``H(s) = w^2 / (s^2 + 2 zeta w s + w^2)`` (unit gain at rest), ``p`` the out-of-sample prediction at the record's
rate. So when the unexplained test sees structure, or a sensor lag is named (a mode damped at 0.25-0.4 is a
low-pass too, and a lag may hold all of it), (f0, zeta) are fitted by least squares to the transfer from ``p`` to
the measured voltage, started from the residual's strongest band (or from the mode that delays as the lag does)
and from the peak of the empirical transfer (:func:`transfer_peak`), and the mode is named when it passes the
forward step's own test: it lowers the out-of-sample error in ``min_confidence`` of the folds and removes
``min_excess_share`` of the error above the noise floor. A damping at the bound (0.5) is a lag, not a mode. A
sensor lag named at the fit rate may have stood in for the mode's slow part (a moderately damped mode delays the
signal by 2 zeta / w): it is kept only when, beside the mode, it passes the same test (:func:`.engine.diagnose`).

A mode added on top of the model must also show on top of the best low-pass that cannot ring: one to four equal
poles, a named lag's stages replaced by them (:func:`through_equal_poles`); that low-pass refitted on top of the
mode must pass the same test against the low-pass alone. A mode is named for its ringing, and two things a
low-pass corrects also pass the test: the prediction is made from the reference force, whose noise the bridge never
saw (5 mN through a soft core is several mV, white), and a mode low in the band filters it out; and a lag chosen
at the fit rate, where a filter of three or four stages looks like a pole pair, attenuates too much below its
corner, which a mode's gain, rising towards its peak, makes up for.

The fit runs on a uniform grid at the median step (a first-order-hold discretisation, exact for piecewise-linear
input, as the ``resonance`` element's forward run); the fold errors are taken on the record's own stamps, through
the element itself. The low-pass rival is fitted and run on the record's own stamps.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np
import numpy.typing as npt
from scipy import optimize, signal

from ..physics.chain import (ExponentialDriftElement, OffsetDriftElement, OffsetElement, PolynomialDriftElement,
                             ResonanceElement, SensorChain, SensorLagElement, SplineDriftElement, StepDriftElement,
                             ThermalDriftElement, ThermalLagElement, TransportDelayElement)
from ..physics.expconv import lag_cascade
from .effects import LAG_DELAY_RANGE_S
from .residual import excess, passes
from .signals import FloatArray, IntArray

__all__ = ["ModeFit", "fit_mode", "choose_mode", "fold_gain", "through_equal_poles", "transfer_peak", "with_mode",
           "ZETA_BOUNDS", "LOWEST_MODE_HZ", "MAX_EQUAL_POLES", "TRANSFER_SEGMENT_S"]

#: Damping ratios searched: a mode rings below 0.5; at the bound the transfer is a (pole-pair) lag.
ZETA_BOUNDS = (0.005, 0.5)
#: The slowest mode searched [Hz]; the fastest is 0.45 x the record's rate.
LOWEST_MODE_HZ = 2.0

#: Elements that follow a mechanical mode in the chain (the signal conditioning, the slow terms, the offset).
_AFTER_MODE = (SensorLagElement, TransportDelayElement, ThermalDriftElement, ThermalLagElement, PolynomialDriftElement,
               ExponentialDriftElement, SplineDriftElement, StepDriftElement, OffsetDriftElement, OffsetElement)


@dataclass(frozen=True)
class ModeFit:
    """A fitted mode and its test.

    Attributes
    ----------
    frequency_hz, damping_ratio : float
        The mode [Hz] and its damping ratio [-].
    confidence : float
        Share of the folds whose out-of-sample error it lowers.
    excess_share : float
        Share of the error above the noise floor it removes.
    predicted_v : ndarray
        The prediction through the mode at the record's stamps [V].
    """

    frequency_hz: float
    damping_ratio: float
    confidence: float
    excess_share: float
    predicted_v: FloatArray

    def element(self) -> ResonanceElement:
        """The mode as a model-file element."""
        return ResonanceElement(frequency_hz=self.frequency_hz, damping_ratio=self.damping_ratio)


def _through_mode(x: FloatArray, step_s: float, frequency_hz: float, zeta: float) -> FloatArray:
    """``x`` on a uniform grid through the mode, settled at its first value before the record."""
    w = 2.0 * math.pi * frequency_hz
    num, den, _ = signal.cont2discrete(([w * w], [1.0, 2.0 * zeta * w, w * w]), step_s, method="foh")
    out: FloatArray = signal.lfilter(np.ravel(num), den, x - x[0]) + x[0]
    return out


#: The longest Welch segment of :func:`transfer_peak` [s]: a mode damped at 0.005 rings down in 1 / (zeta w), 16 s
#: at 2 Hz, and a segment shorter than its ring-down smears the peak and lowers its coherence.
TRANSFER_SEGMENT_S = 16.0


def transfer_peak(predicted_v: FloatArray, measured_v: FloatArray, step_s: float,
                  highest_hz: float) -> Optional[tuple[float, float]]:
    """The strongest peak of the empirical transfer from a prediction to the measured voltage, the mode it
    suggests as a start for :func:`fit_mode`.

    A lightly damped mode's least-squares surface is a valley a fraction of a hertz wide in frequency: started an
    octave away, the fit settles on a broad, damped compromise.

    Parameters
    ----------
    predicted_v, measured_v : (n,) ndarray of float
        The prediction and the measured voltage on a uniform grid [V].
    step_s : float
        The grid's step [s].
    highest_hz : float
        The fastest mode searched [Hz] (the slowest is :data:`LOWEST_MODE_HZ`).

    Returns
    -------
    (frequency_hz, damping_ratio) or None
        The peak of ``|P_pv / P_pp|`` (Welch: eight or more segments, at most :data:`TRANSFER_SEGMENT_S` long) among
        the frequencies where the coherence is at least a half (the prediction accounts for at least half the
        measured power there; where it holds almost none, above a low-pass, the ratio is noise over nearly
        nothing), and the damping ratio of the mode with that peak gain, ``1 / (2 |H|)``, within
        :data:`ZETA_BOUNDS`. None when the record holds fewer than eight segments of two periods of
        :data:`LOWEST_MODE_HZ`, holds a value that is not finite, or no such frequency has a gain above 1.
    """
    if not (math.isfinite(step_s) and step_s > 0.0 and np.isfinite(predicted_v).all()
            and np.isfinite(measured_v).all()):
        return None
    rate_hz = 1.0 / step_s
    segment = min(int(round(TRANSFER_SEGMENT_S * rate_hz)), predicted_v.size // 8)
    if segment * step_s < 2.0 / LOWEST_MODE_HZ:
        return None
    f, cross = signal.csd(predicted_v, measured_v, fs=rate_hz, nperseg=segment, detrend="linear")
    _, auto = signal.welch(predicted_v, fs=rate_hz, nperseg=segment, detrend="linear")
    _, auto_measured = signal.welch(measured_v, fs=rate_hz, nperseg=segment, detrend="linear")
    with np.errstate(over="ignore", invalid="ignore"):  # a bin out of range is not finite: never a peak
        power = auto * auto_measured
        coherence = np.abs(cross) ** 2 / np.where(power > 0, power, np.inf)
    inside = (f >= LOWEST_MODE_HZ) & (f <= highest_hz) & (auto > 0) & (coherence >= 0.5)
    if not inside.any():
        return None
    gain = np.where(inside, np.abs(cross) / np.where(auto > 0, auto, 1.0), 0.0)
    k = int(np.argmax(gain))
    if not gain[k] > 1.0:
        return None
    return float(f[k]), float(np.clip(0.5 / gain[k], *ZETA_BOUNDS))


def fit_mode(t_s: npt.ArrayLike, measured_v: npt.ArrayLike, predicted_v: npt.ArrayLike, fold: IntArray,
             floor_v: float, band_hz: Optional[Sequence[float]], min_confidence: float,
             min_excess_share: float) -> Optional[ModeFit]:
    """The mode that takes ``predicted_v`` to ``measured_v``, when it passes the test (module docstring); else None.

    Parameters
    ----------
    t_s, measured_v, predicted_v : (n,) array_like of float
        Stamps [s], the bridge voltage and the model's out-of-sample prediction of it [V].
    fold : (n,) ndarray of int
        The cross-validation fold of each sample.
    floor_v : float
        The noise floor [V].
    band_hz : (low, high) or None
        Where the search starts [Hz]: the residual's strongest band, or a band around the mode a named lag
        stands for (:func:`.engine._mode_stage`).
    min_confidence, min_excess_share : float
        The forward step's acceptance thresholds.
    """
    t = np.asarray(t_s, dtype=float)
    v, p = np.asarray(measured_v, dtype=float), np.asarray(predicted_v, dtype=float)
    if t.size < 100:
        return None
    step = float(np.median(np.diff(t)))
    if not (step > 0 and 0.45 / step > 2.0 * LOWEST_MODE_HZ):
        return None
    highest = 0.45 / step
    tu = t[0] + step * np.arange(int((t[-1] - t[0]) / step) + 1)
    pu, vu = np.interp(tu, t, p), np.interp(tu, t, v)

    def residual(theta: FloatArray) -> FloatArray:
        out: FloatArray = _through_mode(pu, step, math.exp(theta[0]), math.exp(theta[1])) - vu
        return out

    lower = np.log([LOWEST_MODE_HZ, ZETA_BOUNDS[0]])
    upper = np.log([highest, ZETA_BOUNDS[1]])
    centres = [math.sqrt(band_hz[0] * band_hz[1]), band_hz[0], band_hz[1]] if band_hz else [0.1 * highest]
    # starts clipped to the same bound are one start
    starts = {(float(np.clip(f0, LOWEST_MODE_HZ, highest)), zeta) for f0 in centres for zeta in (0.03, 0.15)}
    peak = transfer_peak(pu, vu, step, highest)
    if peak is not None:
        starts.add(peak)
    best = None
    for f0, zeta in sorted(starts):
        x0 = np.clip(np.log([f0, zeta]), lower + 1e-9, upper - 1e-9)
        sol = optimize.least_squares(residual, x0, bounds=(lower, upper), x_scale=1.0, max_nfev=40)
        if best is None or sol.cost < best.cost:
            best = sol
    assert best is not None
    frequency_hz, zeta = (float(math.exp(x)) for x in best.x)
    if zeta >= 0.98 * ZETA_BOUNDS[1] or frequency_hz >= 0.98 * highest or frequency_hz <= 1.02 * LOWEST_MODE_HZ:
        return None  # at a bound: a lag or something the mode does not describe
    mode = ResonanceElement(frequency_hz=frequency_hz, damping_ratio=zeta)
    through = np.asarray(mode.forward(t, p - p[0]), dtype=float) + p[0]  # exact on the record's own stamps
    confidence, share = fold_gain(v, through, p, fold, floor_v)
    if not passes(confidence, share, min_confidence, min_excess_share):
        return None
    return ModeFit(frequency_hz, zeta, confidence, share, through)


#: The most equal poles a lag refitted at the record's rate may hold (a fourth-order anti-aliasing filter).
MAX_EQUAL_POLES = 4


def through_equal_poles(t_s: npt.ArrayLike, measured_v: npt.ArrayLike, predicted_v: npt.ArrayLike,
                        lag_stages_s: Sequence[float]) -> FloatArray:
    """``predicted_v`` through the chain of 1 to :data:`MAX_EQUAL_POLES` equal first-order lags (unit gain at rest)
    that takes it closest to ``measured_v`` in least squares, with the named lag's stages (time constants
    ``lag_stages_s`` [s], none when no lag is named) undone first, on the record's own stamps: the rival a mode on
    top of the model is tested against (module docstring). The total delay is searched from one sample to the
    longest a sensor lag may hold (:data:`.effects.LAG_DELAY_RANGE_S`); the prediction itself is kept when no chain
    does better. The stages are undone by the lag's backward run (a slope over each sample interval, which holds
    no bridge noise to amplify here): close to the inverse of the forward run below the stages' corners, not near
    the Nyquist rate, so the rival is a low-pass of the prediction rather than the model refitted, and the test on
    top of it is a mode's own (:func:`choose_mode`)."""
    t = np.asarray(t_s, dtype=float)
    v, p = np.asarray(measured_v, dtype=float), np.asarray(predicted_v, dtype=float)
    step = float(np.median(np.diff(t))) if t.size > 1 else 0.0
    if not 0.0 < step < LAG_DELAY_RANGE_S[1]:
        return p.copy()

    undone = p - p[0]
    for tau_s in lag_stages_s:
        undone = np.asarray(SensorLagElement(tau_s=tau_s).backward(t, undone), dtype=float)

    def through(n_poles: int, log_delay: float) -> FloatArray:
        settled: FloatArray = lag_cascade(t, undone, math.exp(log_delay) / n_poles, n_poles) + p[0]
        return settled

    best, best_sse = p.copy(), float(np.sum((p - v) ** 2))
    for n_poles in range(1, MAX_EQUAL_POLES + 1):
        sol = optimize.minimize_scalar(lambda x, n=n_poles: float(np.sum((through(n, x) - v) ** 2)),
                                       bounds=(math.log(step), math.log(LAG_DELAY_RANGE_S[1])), method="bounded",
                                       options={"xatol": 0.02})
        if float(sol.fun) < best_sse:
            best, best_sse = through(n_poles, float(sol.x)), float(sol.fun)
    return best


def fold_gain(measured_v: FloatArray, better_v: FloatArray, than_v: FloatArray, fold: IntArray,
              floor_v: float) -> tuple[float, float]:
    """How much the prediction ``better_v`` improves on ``than_v``: the share of folds whose squared error it lowers,
    and the share of ``than_v``'s error above the noise floor it removes."""
    folds = np.unique(fold)
    before = np.array([np.sum((measured_v - than_v)[fold == k] ** 2) for k in folds])
    after = np.array([np.sum((measured_v - better_v)[fold == k] ** 2) for k in folds])
    share = float((before.sum() - after.sum()) / excess(float(before.sum()), measured_v.size * floor_v ** 2))
    return float(np.mean(after < before)), share


def _beyond_low_pass(t_s: npt.ArrayLike, measured_v: FloatArray, predicted_v: FloatArray, mode: ModeFit,
                     fold: IntArray, floor_v: float, min_confidence: float, min_excess_share: float,
                     lag_stages_s: Sequence[float]) -> Optional[ModeFit]:
    """``mode`` with the lower of its own test and the test of the low-pass with the mode against the low-pass
    alone (:func:`through_equal_poles`, on ``predicted_v`` and on the mode's prediction), None when that second test
    fails. The poles are refitted on top of the mode: poles fitted alone take part of a mode's ringing as
    attenuation, so a mode fitted on top of them afterwards would be judged only on what they left."""
    low_pass = through_equal_poles(t_s, measured_v, predicted_v, lag_stages_s)
    with_mode = through_equal_poles(t_s, measured_v, mode.predicted_v, lag_stages_s)
    confidence, share = fold_gain(measured_v, with_mode, low_pass, fold, floor_v)
    if not passes(confidence, share, min_confidence, min_excess_share):
        return None
    return ModeFit(mode.frequency_hz, mode.damping_ratio, min(mode.confidence, confidence),
                   min(mode.excess_share, share), mode.predicted_v)


def choose_mode(t_s: npt.ArrayLike, measured_v: npt.ArrayLike, predicted_v: npt.ArrayLike, fold: IntArray,
                floor_v: float, band_hz: Optional[Sequence[float]], min_confidence: float, min_excess_share: float,
                predicted_without_lag_v: Optional[FloatArray] = None, structure_seen: bool = True,
                lag_stages_s: Sequence[float] = ()) -> tuple[Optional[ModeFit], bool]:
    """The mode to name, if any, and whether the sensor lag named at the fit rate goes (module docstring).

    A mode on top of ``predicted_v`` is named when it passes the test against it and the best low-pass that
    cannot ring (:func:`through_equal_poles`, the named lag's stages ``lag_stages_s`` [s] replaced) with a mode
    passes the test against that low-pass alone (:func:`_beyond_low_pass`); its confidence and share are the lower
    of the two. With a lag named (``predicted_without_lag_v``: the prediction of the model without it), three models
    compete: the lag (``predicted_v``), the lag and a mode, the mode alone. A mode on top of the lag is named when
    it passes the test against the lag; the lag then stays only when it passes the test against the mode alone. A
    mode that does not pass on top of the lag may still replace it: when the mode alone passes the test against the
    lag. When the model leaves no structure the unexplained test sees (``structure_seen`` False), no mode is added
    on top of it: the gain would be a misfit of the lag's shape that the record does not show; the mode may still
    replace the lag.

    Returns
    -------
    mode : ModeFit or None
        The mode named (its ``predicted_v`` is the final prediction).
    drop_lag : bool
        Whether the lag is dropped (the mode holds it).
    """
    v = np.asarray(measured_v, dtype=float)
    on_top = (fit_mode(t_s, v, predicted_v, fold, floor_v, band_hz, min_confidence, min_excess_share)
              if structure_seen else None)
    if on_top is not None:  # the ringing must show on top of the best low-pass that cannot ring, too
        on_top = _beyond_low_pass(t_s, v, np.asarray(predicted_v, dtype=float), on_top, fold, floor_v,
                                  min_confidence, min_excess_share, lag_stages_s)
    if predicted_without_lag_v is None:
        return on_top, False
    alone = fit_mode(t_s, v, predicted_without_lag_v, fold, floor_v, band_hz, 0.0, -math.inf)
    if alone is None:
        return on_top, False
    if on_top is not None:
        confidence, share = fold_gain(v, on_top.predicted_v, alone.predicted_v, fold, floor_v)
        lag_needed = passes(confidence, share, min_confidence, min_excess_share)
        return (on_top, False) if lag_needed else (alone, True)
    confidence, share = fold_gain(v, alone.predicted_v, np.asarray(predicted_v, dtype=float), fold, floor_v)
    if passes(confidence, share, min_confidence, min_excess_share):
        return ModeFit(alone.frequency_hz, alone.damping_ratio, confidence, share, alone.predicted_v), True
    return None, False


def with_mode(chain: SensorChain, mode: ModeFit) -> SensorChain:
    """``chain`` with the mode on the voltage path, after the core and before the signal conditioning and the
    slow terms."""
    elements = list(chain.elements)
    at = next((i for i, e in enumerate(elements) if isinstance(e, _AFTER_MODE)), len(elements))
    return SensorChain([*elements[:at], mode.element(), *elements[at:]])
