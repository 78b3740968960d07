"""The noise floor a diagnosis measures against, and the test for structure left in its residual.

* :func:`noise_floor` (stage 1 of :func:`.engine.diagnose`): the white noise of the bridge voltage and of the
  reference force, from second differences of the raw samples, the reference's through the base fit's
  instantaneous compliance.
* :func:`zero_jumps` (stage 3): where the base's residual jumps while its core's output does not (where the
  ``steps`` and ``jumps`` variants of an offset drift put theirs).
* :func:`drift_follows_load` (stage 4): whether a fitted offset drift moves the residual at rest as it does under
  load, as a drift in time does.
* :func:`unexplained_test` (stage 5): the out-of-sample residual at the record's rate (:func:`out_of_sample`)
  averaged to ~1 s and tested for whiteness (Ljung-Box), and split into octave bands (:func:`band_structure`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import numpy as np
import numpy.typing as npt
from scipy import ndimage, stats

from ..physics.chain import lagged_temperature_c
from ..physics.identification import block_average
from .design import Fit, Fitter, design
from .columns import Col, lag_columns
from .signals import MIN_GAP_S, FloatArray, IntArray, Signals, ZeroJump, noise_std

__all__ = ["noise_std", "NoiseFloor", "noise_floor", "excess", "ljung_box", "band_structure", "Unexplained",
           "unexplained_test", "out_of_sample", "where", "drift_follows_load", "slow_response_columns", "zero_jumps", "near"]


# ----------------------------------------------------------------------------- the noise floor

@dataclass(frozen=True)
class NoiseFloor:
    """The white noise a model cannot predict.

    Attributes
    ----------
    floor_v : float
        RMS at the record's rate [V]: the voltage's and the reference's through the instantaneous compliance.
    fit_mse : float
        Its mean square after block averaging to the fit rate [V^2]: what the cross-validation errors are
        compared with.
    """

    floor_v: float
    fit_mse: float


def noise_floor(voltage_v: npt.ArrayLike, force_n: npt.ArrayLike, j0_v_per_n: float,
                samples_per_bin: float) -> NoiseFloor:
    """The noise floor from the data: the voltage's white noise, and the reference's through the instantaneous
    compliance ``j0_v_per_n`` of the base fit (the creep terms low-pass it away; the static gain, 1.5-2x larger for
    a burgers, would overestimate the floor, and validation RMSEs would come out at 0.73-0.93x of it).

    ``samples_per_bin``: raw samples per fit-rate bin (white noise averages down by it).
    """
    sigma_v, sigma_f = noise_std(voltage_v), noise_std(force_n)
    gain = abs(float(j0_v_per_n))
    floor = math.sqrt(sigma_v ** 2 + (gain * sigma_f) ** 2)
    return NoiseFloor(floor, floor ** 2 / samples_per_bin)


def excess(mse: float, floor_mse: float) -> float:
    """A mean square error's excess over the noise floor's, counted as at least a quarter of the floor's own: the
    denominator of every share of the excess (acceptance, candidates' report, explained share), which a model at or
    below the floor would otherwise make a ratio over ~0."""
    return max(mse - floor_mse, 0.25 * floor_mse)


def something_left(structure_seen: bool, rmse_v: float, floor_v: float, ratio: float) -> bool:
    """Whether a model leaves something of the record unexplained: structure that :func:`unexplained_test` sees, or
    an error whose own excess over the noise floor, ``sqrt(rmse_v**2 - floor_v**2)``, is at least ``ratio`` times
    the floor (chatter in bursts of a few milliseconds has no band or 1 s average of its own) [V]."""
    return structure_seen or math.sqrt(max(rmse_v ** 2 - floor_v ** 2, 0.0)) >= ratio * floor_v


def passes(confidence: float, excess_share: float, min_confidence: float, min_excess_share: float) -> bool:
    """The acceptance test on a model's gain over another: it lowers the out-of-sample error in ``min_confidence``
    of the folds and removes ``min_excess_share`` of the other's error above the floor (:func:`excess`). The one
    home of the test for every candidate: the effects of the catalogue and a mechanical mode alike."""
    return confidence >= min_confidence and excess_share >= min_excess_share


# ----------------------------------------------------------------------------- the unexplained residual

def ljung_box(x: npt.ArrayLike, lags: int = 20) -> tuple[float, float]:
    """Ljung-Box statistic and p-value of the first ``lags`` autocorrelations of x (white -> large p)."""
    samples = np.asarray(x, dtype=float)
    d = samples - np.mean(samples)
    n = d.size
    lags = min(lags, n // 4)
    denom = float(d @ d)
    if lags < 1 or denom <= 0:
        return 0.0, 1.0
    rho = np.array([float(d[:-k] @ d[k:]) / denom for k in range(1, lags + 1)])
    q = n * (n + 2) * float(np.sum(rho ** 2 / (n - np.arange(1, lags + 1))))
    return q, float(stats.chi2.sf(q, lags))


def band_structure(resid_v: npt.ArrayLike, t_s: npt.ArrayLike, floor_v: float,
                   lowest_hz: float = 0.5) -> list[dict[str, float]]:
    """Structured RMS of a residual in octave bands from ``lowest_hz`` to Nyquist, over a white floor.

    The residual's one-sided power spectrum (Welch, segments of ~8 s) is integrated over each octave and the
    power white noise of RMS ``floor_v`` would put there is subtracted: what remains is structure at that time
    scale (a resonance rings in its band, an unmodelled lag in the fast ones) that 1 s averages do not see.

    Returns
    -------
    list of dict
        ``low_hz``, ``high_hz``, ``rms_v`` (the structured RMS in the band, 0 when below the floor).
    """
    from scipy import signal

    resid_v = np.asarray(resid_v, dtype=float)
    rate_hz = 1.0 / float(np.median(np.diff(t_s)))
    nperseg = int(min(resid_v.size, 2 ** round(math.log2(max(8.0 * rate_hz, 16.0)))))
    freq, psd = signal.welch(resid_v - resid_v.mean(), fs=rate_hz, nperseg=nperseg)
    white = 2.0 * floor_v ** 2 / rate_hz
    df = freq[1] - freq[0]
    out, low = [], lowest_hz
    while low < rate_hz / 2.0:
        high = min(2.0 * low, rate_hz / 2.0)
        band = (freq >= low) & (freq < high)
        structured = float(np.sum(psd[band] - white) * df) if band.any() else 0.0
        out.append({"low_hz": low, "high_hz": high, "rms_v": math.sqrt(max(structured, 0.0))})
        low = high
    return out


@dataclass(frozen=True)
class Unexplained:
    """Whether an out-of-sample residual holds structure (:func:`unexplained_test`).

    Attributes
    ----------
    present : bool
        Structure of at least the ratio asked of the noise floor, in the 1 s averages or in a band.
    rms_v : float
        The larger structured RMS of the two views [V].
    ljung_box_q, ljung_box_p : float
        Whiteness of the 1 s averages.
    bands : list of dict
        The octave bands (:func:`band_structure`).
    """

    present: bool
    rms_v: float
    ljung_box_q: float
    ljung_box_p: float
    bands: list[dict[str, float]] = field(default_factory=list)


def unexplained_test(t_s: FloatArray, resid_v: FloatArray, floor_v: float, ratio: float) -> Unexplained:
    """Whether an out-of-sample residual holds structure.

    Two views, each against the white noise floor: the residual averaged to ~1 s, tested for whiteness
    (Ljung-Box) with a structured RMS of at least ``ratio`` of the floor; and the residual at the record's rate
    in octave bands (:func:`band_structure`), any band holding at least ``ratio`` of the floor (a resonance or
    a fast dynamic leaves nothing in 1 s averages). ``rms_v`` is the larger structured RMS of the two views.
    """
    slow = block_average(t_s, resid_v, rate_hz=1.0)[1]
    q, p_value = ljung_box(slow, lags=20)
    m_slow = t_s.size / max(slow.size, 1)
    structured = math.sqrt(max(float(np.var(slow)) - floor_v ** 2 / m_slow, 0.0))
    bands = band_structure(resid_v, t_s, floor_v)
    in_bands = max((b["rms_v"] for b in bands), default=0.0)
    present = bool((p_value < 1e-3 and structured >= ratio * floor_v) or in_bands >= ratio * floor_v)
    return Unexplained(present, max(structured, in_bands), q, p_value, bands)


def shown_share(t_s: FloatArray, part_v: FloatArray, floor_v: float, ratio: float) -> float:
    """How much of a noise-free signal the unexplained test would see, as a share of ``floor_v``: its larger RMS
    in 1 s averages or in an octave band (:func:`unexplained_test` over a zero floor, which subtracts nothing; the
    test proper subtracts the floor's own power in each band, which a noise-free part does not hold). The 1 s
    averages count without the test's whiteness gate: a part is counted as shown when in doubt.

    What the record can show at its own rate is ``ratio`` of the floor (step 5's test): an effect that adds less
    to a prediction, or a model that differs from another by less, describes nothing the record tells apart."""
    seen = unexplained_test(t_s, part_v - float(np.mean(part_v)), 0.0, ratio)
    return seen.rms_v / floor_v if floor_v > 0.0 else float("inf")


def out_of_sample(sig_full: Signals, fit: Fit, fitter: Fitter, bin_of_sample: IntArray
                  ) -> tuple[float, FloatArray, FloatArray]:
    """Out-of-sample prediction at the record's rate: each sample predicted by the fit that left its fold out.

    A sample's fold is that of the fit-rate bin it was averaged into (a fold of its own, from its own time,
    would put the few samples of a bin that straddles a block boundary in a fold whose fit used them).

    Returns
    -------
    rmse_v : float
        RMS of the residual [V].
    resid_v, predicted_v : (n,) ndarray
        Measured minus predicted voltage, and the prediction [V].
    """
    names, a, lo, hi, ridge = design(sig_full, fit.structure)
    block = fitter.fold[bin_of_sample]
    pred = np.empty_like(sig_full.v)
    for b in range(fitter.k):
        rows = block == b
        pred[rows] = a[rows] @ fit.coef_folds[b]
    resid = sig_full.v - pred
    return float(np.sqrt(np.mean(resid ** 2))), resid, pred


def where(loc: Mapping[str, Any]) -> dict[str, dict[str, float]]:
    """The two segment kinds the residual concentrates in most and the two signals it follows most."""
    conc = loc.get("concentration", {})
    top = sorted(conc.items(), key=lambda kv: -kv[1]["rms_ratio"])[:2]
    corr = sorted(loc.get("correlation", {}).items(), key=lambda kv: -abs(kv[1]))[:2]
    return {"segments": {k: round(v["rms_ratio"], 3) for k, v in top},
            "follows": {k: round(v, 3) for k, v in corr}}


# ----------------------------------------------------------------------------- a drift in time, or in load

#: Rest: the reference force below this share of its span [-], for at least MIN_REST_S [s]; a rest's level at each
#: end is the mean over REST_EDGE_S [s] there.
REST_SHARE_OF_SPAN = 0.05
MIN_REST_S = 1.0
REST_EDGE_S = 0.3


def _slope(y: FloatArray, x: FloatArray) -> tuple[float, float]:
    """Least-squares slope of ``y`` on ``x`` through zero, and its standard error."""
    sxx = float(x @ x)
    if sxx <= 0.0 or y.size < 2:
        return math.nan, math.inf
    b = float(x @ y) / sxx
    res = y - b * x
    return b, math.sqrt(float(res @ res) / (y.size - 1) / sxx)


def drift_follows_load(sig: Signals, model_without_drift_v: FloatArray, drift_v: FloatArray, min_runs: int = 4
                       ) -> bool:
    """Whether a fitted drift follows the load rather than time.

    A drift in time moves the voltage at rest as it moves it under load. Over each rest (the reference force below
    ``REST_SHARE_OF_SPAN`` of its span for ``MIN_REST_S``) and over each loaded stretch between two rests, the
    change of the residual left without the drift (``sig.v - model_without_drift_v``) is compared with the drift's own
    change there: the slope of one on the other is about 1 in both kinds of stretch for a drift. The drift follows
    the load when the residual at rest moves less than half as much as the drift says and significantly less than
    under load (three standard errors): what it describes happens while loaded (a core, a contact, a loop that the
    model's shapes miss) and leaves the rests alone or runs against them.

    A fit bin left empty (``sig.valid`` False, as stamp jitter leaves some at the fit rate) takes the state of its
    valid neighbours, so it does not cut a rest, and the levels are means over valid bins only.

    Parameters
    ----------
    sig : Signals
        The record at the fit rate.
    model_without_drift_v, drift_v : (n,) ndarray
        The fitted model's prediction without the drift, and the drift's part of it [V].
    min_runs : int
        Rests needed for a verdict.

    Returns
    -------
    bool
        True when the drift follows the load; False when it holds at rest as a drift in time does, or when the
        record has fewer than ``min_runs`` rests.
    """
    h = float(np.median(np.diff(sig.t))) if sig.t.size > 1 else 0.0
    if not h > 0.0:
        return False
    valid = np.ones(sig.t.size, dtype=bool) if sig.valid is None else np.asarray(sig.valid, dtype=bool)
    if not valid.any():
        return False
    at_rest = sig.f < REST_SHARE_OF_SPAN * max(sig.span_f, 1e-12)
    # an empty bin is at rest when the valid bins on both sides are
    kept = np.flatnonzero(valid)
    before = kept[np.clip(np.searchsorted(kept, np.arange(valid.size), side="right") - 1, 0, kept.size - 1)]
    after = kept[np.clip(np.searchsorted(kept, np.arange(valid.size)), 0, kept.size - 1)]
    rest = np.where(valid, at_rest, at_rest[before] & at_rest[after])
    edges = np.flatnonzero(np.diff(rest.astype(np.int8))) + 1
    starts, stops = np.r_[0, edges], np.r_[edges, rest.size]
    w = max(1, int(round(REST_EDGE_S / h)))
    runs = [(int(a), int(b)) for a, b in zip(starts, stops)
            if rest[a] and (b - a) * h >= MIN_REST_S and valid[a:a + w].any() and valid[b - w:b].any()]
    if len(runs) < min_runs:
        return False
    resid = np.asarray(sig.v - model_without_drift_v, dtype=float)
    drift = np.asarray(drift_v, dtype=float)

    def level(x: FloatArray, lo: int, hi: int) -> float:
        return float(x[lo:hi][valid[lo:hi]].mean())

    def changes(x: FloatArray) -> tuple[FloatArray, FloatArray]:
        rests = np.array([level(x, b - w, b) - level(x, a, a + w) for a, b in runs])
        loaded = np.array([level(x, a1, a1 + w) - level(x, b0 - w, b0) for (_, b0), (a1, _) in zip(runs[:-1], runs[1:])])
        return rests, loaded

    (r_rest, r_load), (d_rest, d_load) = changes(resid), changes(drift)
    b_rest, se_rest = _slope(r_rest, d_rest)
    b_load, se_load = _slope(r_load, d_load)
    if not (math.isfinite(b_rest) and math.isfinite(b_load)):
        return False
    return bool(b_rest < 0.5 and b_load - b_rest > 3.0 * math.hypot(se_rest, se_load))


#: Retardation times of the generic slow response to the load that an offset drift must beat [s]: half-decades from
#: 1 s to the record's length (a slower unit is flow within it).
SLOW_LOAD_TAU_S = (1.0, 1.0)
#: Thermal lags of the generic slow response to the temperature [s]: half-decades from 3 s to half the record.
SLOW_THERMAL_TAU_S = (3.0, 0.5)


def _half_decades(lo_s: float, hi_s: float) -> FloatArray:
    """Times from ``lo_s`` up to ``hi_s`` (inclusive where it falls on the grid), 10^0.5 apart [s]."""
    n = int(math.floor(2.0 * math.log10(max(hi_s / lo_s, 1.0)) + 1e-9)) + 1
    return np.asarray(lo_s * 10.0 ** (0.5 * np.arange(n)), dtype=float)


def slow_response_columns(sig: Signals) -> list[Col]:
    """Additive design columns of a generic slow response to what drives the sensor, free in sign: the load through
    unit-gain first-order lags (:data:`SLOW_LOAD_TAU_S`); with a temperature, its departure direct and through lags
    (:data:`SLOW_THERMAL_TAU_S`), alone and times the load (a zero and a span that follow the temperature in any slow
    way).

    An offset drift is a function of time alone. What a model misses in the shape of a slow effect it holds (creep
    spread over time scales, a zero behind two thermal lags, a contact that slips) is a function of the load or the
    temperature history, which a spline in time also follows: these columns are the rival that tells the two apart
    (:meth:`.selection.Selection.why_not_judged`)."""
    key = "slow response"
    if key not in sig.record_cache:
        t, f = sig.t, sig.f
        cols: list[Col] = [(f"slow_load_{tau:.3g}", lag_columns(t, f, float(tau)), -np.inf, np.inf, "additive", None)
                           for tau in _half_decades(SLOW_LOAD_TAU_S[0], SLOW_LOAD_TAU_S[1] * sig.duration_s)]
        if sig.temp is not None:
            temps = [("direct", sig.temp)] + [
                (f"{tau:.3g}", lagged_temperature_c(t, sig.temp, float(tau)))
                for tau in _half_decades(SLOW_THERMAL_TAU_S[0], SLOW_THERMAL_TAU_S[1] * sig.duration_s)]
            for name, temp in temps:
                departure = np.asarray(temp, dtype=float) - sig.temp_ref
                cols.append((f"slow_zero_{name}", departure, -np.inf, np.inf, "additive", None))
                cols.append((f"slow_span_{name}", departure * f, -np.inf, np.inf, "additive", None))
        sig.record_cache[key] = [(c[0], np.ascontiguousarray(c[1], dtype=float), *c[2:]) for c in cols]
    out: list[Col] = sig.record_cache[key]
    return out


# ----------------------------------------------------------------------------- jumps of the zero

#: A jump of the zero is sought as the gap between two straight lines, each fitted over JUMP_SIDE_S [s] on one side
#: and carried JUMP_GUARD_S [s] across to the instant between them: a smooth residual (creep, a drift, a kink at a
#: load reversal) carries both lines to the same level there, a step does not, and whatever settles within the guard
#: (a slip of 20-100 ms, a wetting of 0.5 s, a lag's transient) does not move either line.
JUMP_SIDE_S = 3.0
JUMP_GUARD_S = 0.5
#: Standard deviations of the gap, under the white noise at the fit rate, a jump must exceed: the gaps of a record
#: are nearly independent a window apart (~170 per 10 minutes), and 6 keeps a false jump near 1e-7 per such gap.
JUMP_SIGMAS = 6.0
#: Most jumps kept (the largest): each is one column, two with its settling.
MAX_JUMPS = 24


def _line_end_weights(n: int, beyond: int) -> FloatArray:
    """Weights that give a least-squares line through ``n`` equally spaced samples at ``beyond`` samples after the
    last (a linear map of the samples: the line's value there)."""
    x = np.arange(n, dtype=float)
    xm = x.mean()
    return np.asarray(1.0 / n + (x - xm) * (n - 1 + beyond - xm) / float(np.sum((x - xm) ** 2)), dtype=float)


def _line_gaps(y: FloatArray, n: int, g: int) -> FloatArray:
    """At each sample k, the line through y[k+g : k+g+n] minus the line through y[k-g-n+1 : k-g+1], both carried to
    k; NaN where either window leaves the record."""
    w = _line_end_weights(n, g)
    windows = np.lib.stride_tricks.sliding_window_view(y, n)
    from_left, from_right = windows @ w, windows @ w[::-1]
    out = np.full(y.size, np.nan)
    k = np.arange(n - 1 + g, y.size - g - n + 1)
    out[k] = from_right[k + g] - from_left[k - g - n + 1]
    return out


def near(mask: npt.ArrayLike, reach: int) -> npt.NDArray[np.bool_]:
    """Samples within ``reach`` samples of a true one of ``mask`` (a binary dilation; outside the array is false)."""
    mask = np.asarray(mask, dtype=bool)
    if reach <= 0 or mask.size == 0:
        return mask.copy()
    out: npt.NDArray[np.bool_] = ndimage.binary_dilation(mask, structure=np.ones(2 * int(reach) + 1, dtype=bool))
    return out


def zero_jumps(t_s: FloatArray, resid_v: FloatArray, core_v: FloatArray, valid: npt.ArrayLike, sigma_v: float,
               stepped_gaps_s: Sequence[tuple[float, float]] = ()) -> tuple[ZeroJump, ...]:
    """Where, and by how much, the residual ``resid_v`` of a model jumps while its core's output ``core_v`` does
    not (in time order).

    The gap between the lines either side (:data:`JUMP_SIDE_S`, :data:`JUMP_GUARD_S`), once what the gaps of the
    core's output and of its square explain is taken out, must exceed :data:`JUMP_SIGMAS` of its scale (what white
    noise of ``sigma_v`` gives it, or its robust spread over the record if larger). The largest first, its size
    taken out of the residual, none other within a window and a guard of it (its side lobes), at most
    :data:`MAX_JUMPS`; each placed where one step splits the residual (less that gain and curvature) best within a
    guard of the peak. A step
    at a gap that every model gives a step of its own (``stepped_gaps_s``) is sought like the others but not kept;
    near a stretch without samples (0.1 s or five bins at least) only a step at it is kept: across the stretch the
    record is interpolated, and the residual bends at its ends.

    Parameters
    ----------
    t_s : (n,) ndarray
        Uniform times [s] (the fit rate's grid).
    resid_v, core_v : (n,) ndarray
        The model's residual and its core's output [V], finite.
    valid : (n,) array of bool
        Bins that hold samples (the others hold the record interpolated).
    sigma_v : float
        The residual's white noise at this rate [V].
    stepped_gaps_s : sequence of (float, float)
        (start, end) [s] of each gap the models give a step of their own.
    """
    t, r, x = (np.asarray(a, dtype=float) for a in (t_s, resid_v, core_v))
    ok = np.asarray(valid, dtype=bool)
    if t.size < 8 or not (math.isfinite(sigma_v) and sigma_v >= 0.0):
        return ()
    dt = float(np.median(np.diff(t)))
    if not dt > 0.0:
        return ()
    n, g = max(int(round(JUMP_SIDE_S / dt)), 4), max(int(round(JUMP_GUARD_S / dt)), 1)
    if t.size < 2 * (n + g) + 1:
        return ()
    raw_gaps = _line_gaps(r, n, g)
    usable = np.isfinite(raw_gaps)
    # where the load moves sharply the core's output bends too, and a gain the base lacks (a few per cent, or a
    # curvature) moves the residual's lines with it: what the gaps of the core's output and of its square explain
    # is not a jump of the zero
    scale = max(float(np.ptp(x)), 1e-12)
    gaps_x = np.column_stack([_line_gaps(x / scale, n, g), _line_gaps((x / scale) ** 2, n, g)])[usable]
    # the gap's scale under white noise, or its robust scale over the record when the residual is not white (a
    # misfit's slow structure moves the lines apart too): a jump stands out of both
    white = sigma_v * math.sqrt(2.0 * float(np.sum(_line_end_weights(n, g) ** 2)))
    raw, inlier = raw_gaps[usable], np.ones(int(usable.sum()), dtype=bool)
    height = 0.0
    for _ in range(3):  # the gain fitted on the gaps that are not jumps (jumps would lend the core's bends a share)
        beta = np.linalg.lstsq(gaps_x[inlier], raw[inlier], rcond=None)[0]
        rest = raw - gaps_x @ beta
        spread = 1.4826 * float(np.median(np.abs(rest - np.median(rest))))
        height = JUMP_SIGMAS * max(white, spread)
        inlier = np.abs(rest) <= height
    if not height > 0.0:
        return ()
    gap = np.zeros(t.size)
    gap[usable] = rest
    bends = np.zeros(t.size)
    bends[usable] = gaps_x @ beta
    misfit = np.column_stack([x / scale, (x / scale) ** 2]) @ beta  # the same, on the residual itself (gaps are linear)

    stepped = np.zeros(t.size, dtype=bool)
    for start, end in stepped_gaps_s:
        stepped |= (t >= start) & (t <= end)
    stepped = near(stepped, g)
    empty = ndimage.binary_opening(~ok, structure=np.ones(max(int(math.ceil(MIN_GAP_S / dt)), 5), dtype=bool))
    at_empty, near_empty = near(empty, g), near(empty, n + g)
    # a step inside one window tilts that line, so the gap has side lobes of the other sign within a window of the
    # jump, and what settles after it bends the lines there: the largest jump first, taken out of the residual
    # (the gap there recomputed) before the next is sought, and none other within a window and a guard of it
    jumps: list[ZeroJump] = []
    r = r.copy()  # the jumps found are taken out of it as the search goes
    free = usable.copy()
    reach = n + 2 * g
    for _ in range(4 * MAX_JUMPS):  # steps at gaps cost a pass each but are not kept: bounded all the same
        if len(jumps) == MAX_JUMPS or not free.any():
            break
        k = int(np.argmax(np.where(free, np.abs(gap), 0.0)))
        if abs(gap[k]) <= height:
            break
        # the step splits the residual, less the gain and curvature the gaps showed, best within a guard of the peak
        # (the residual itself would take the load's own edges nearby)
        size = float(gap[k])
        lo, hi = max(k - 2 * g, 0), min(k + 2 * g + 1, t.size)
        seg = r[lo:hi] - misfit[lo:hi]
        m = np.arange(max(k - g - lo, 1), min(k + g - lo, seg.size - 1) + 1)  # split before seg[m]
        c = np.cumsum(seg)
        left, right = c[m - 1] / m, (c[-1] - c[m - 1]) / (seg.size - m)
        at = lo + int(m[np.argmax(np.abs(right - left) * np.sqrt(m * (seg.size - m)))])
        if not (stepped[k] or stepped[at]) and (at_empty[at] or not near_empty[k]):
            jumps.append(ZeroJump(0.5 * float(t[at - 1] + t[at]), size))
        r[at:] -= size  # the gap is the jump's size (means would take the load's moves)
        # the statistic changes only where a window holds the step
        a, b = max(at - 2 * (n + g), 0), min(at + 2 * (n + g) + 1, t.size)
        local = _line_gaps(r[a:b], n, g)
        part = np.isfinite(local) & usable[a:b]
        gap[a:b][part] = local[part] - bends[a:b][part]
        free[max(k - reach, 0):k + reach + 1] = False
    return tuple(sorted(jumps, key=lambda j: j.at_s))
