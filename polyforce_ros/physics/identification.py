"""Identification of viscoelastic sensor models from creep records (seed 000, IV-A/B).

The fit uses the *measured* force history, not an ideal step: the candidate model
is run forward over the whole record (:func:`simulate_deformation`) and its
output compared with the measured bridge voltage on the creep segments. The
bridge offset is eliminated in closed form (variable projection), the
mechanical parameters are fitted in log space (they are all positive and span
decades) with :func:`scipy.optimize.least_squares`.

Model selection uses the Bayesian information criterion, which penalises the
extra dashpot of Burgers unless the data show unbounded creep.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, Optional

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from . import fitting
from .fitting import information_criteria, log_bounds, log_standard_errors, multistart_least_squares, starts_from_compliance
from .viscoelastic import ViscoelasticModel, simulate_deformation

__all__ = ["DEFAULT_FIT_RATE_HZ", "CreepSegment", "find_creep_segments", "block_average", "FitResult", "Selection",
    "fit_creep", "select_model"]

#: Largest rate the fit works at; block averages keep it fast on long records
#: while resolving load steps of ~0.1 s.
DEFAULT_FIT_RATE_HZ = 50.0


@dataclass(frozen=True)
class CreepSegment:
    """One load step, hold and release found in a record (sample indices).

    start: first sample used for fitting (shortly before the step);
    load: first sample at the hold level; release: first sample after the
    hold; stop: end of the recovery (exclusive), before the next step.
    """

    start: int
    load: int
    release: int
    stop: int
    hold_force_n: float
    hold_s: float


def find_creep_segments(t_s: npt.ArrayLike, force_n: npt.ArrayLike, min_hold_s: float = 5.0,
                        hold_tolerance: float = 0.05, min_load_n: Optional[float] = None) -> list[CreepSegment]:
    """Find creep tests (step, hold, release, recovery) in a long force record.

    A hold is a run of samples where the (median-filtered) force stays within
    ``hold_tolerance`` (relative) of its median, at least ``min_hold_s`` long and
    at least ``min_load_n`` above the unloaded baseline (default: 20 % of the
    record's force span). Ramps and cycles do not qualify.

    Returns a list of :class:`CreepSegment`, in time order.
    """
    t = np.asarray(t_s, dtype=float)
    f = np.asarray(force_n, dtype=float)
    if t.size < 3:
        return []
    dt = float(np.median(np.diff(t)))
    if not dt > 0:
        return []
    width = max(3, int(round(0.05 / dt)) | 1)  # ~50 ms median filter against noise
    fs = ndimage.median_filter(f, size=width, mode="nearest")
    baseline = float(np.percentile(fs, 5))
    span = float(np.percentile(fs, 99.5)) - baseline
    threshold = max(0.2 * span, 1e-12) if min_load_n is None else float(min_load_n)
    loaded = fs - baseline > threshold
    segments = []
    for run in _runs(loaded):
        level = float(np.median(fs[run]))
        near = np.abs(fs[run] - level) <= hold_tolerance * abs(level - baseline)
        if not near.any():
            continue
        idx = np.flatnonzero(near) + run.start
        load, release = int(idx[0]), int(idx[-1]) + 1
        hold_s = t[release - 1] - t[load]
        if hold_s < min_hold_s or near.mean() < 0.8:
            continue
        segments.append([run.start, load, release, run.stop, level - baseline, hold_s])
    # A segment runs from shortly before its step to shortly before the force
    # next leaves the baseline (another test of any kind), or to the end.
    pre_n = max(1, int(round(1.0 / dt)))
    off_load = fs - baseline > 0.25 * threshold
    result: list[CreepSegment] = []
    for start, load, release, run_stop, level, hold_s in segments:
        lo = result[-1].stop if result else 0
        rest = np.flatnonzero(~off_load[run_stop:])
        rest_at = run_stop + int(rest[0]) if rest.size else t.size
        later = np.flatnonzero(off_load[rest_at:])
        stop = rest_at + int(later[0]) - pre_n if later.size else t.size
        stop = max(stop, release + 1)
        result.append(CreepSegment(max(start - pre_n, lo), load, release, int(stop), float(level), float(hold_s)))
    return result


def _runs(mask: np.ndarray) -> list[slice]:
    """Slices of consecutive True values."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], mask.astype(np.int8), [0]))))
    return [slice(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2])]


def block_average(t_s: npt.ArrayLike, *signals: npt.ArrayLike,
                  rate_hz: float = DEFAULT_FIT_RATE_HZ) -> tuple[np.ndarray, ...]:
    """Average consecutive samples in blocks so the record is at most ``rate_hz``.

    Returns ``(t_s, *signals)`` decimated (unchanged when already slow enough).
    Averaging is linear, so a linear model sees the averaged input as it would
    the original up to dynamics faster than the block (much faster than any
    viscoelastic time constant here).
    """
    t = np.asarray(t_s, dtype=float)
    if t.size < 2:
        return (t, *[np.asarray(s, dtype=float) for s in signals])
    dt = (t[-1] - t[0]) / (t.size - 1)
    block = int(max(1, math.floor((1.0 / rate_hz) / dt))) if dt > 0 else 1
    if block == 1:
        return (t, *[np.asarray(s, dtype=float) for s in signals])
    n = (t.size // block) * block
    out = [t[:n].reshape(-1, block).mean(axis=1)]
    out += [np.asarray(s, dtype=float)[:n].reshape(-1, block).mean(axis=1) for s in signals]
    return tuple(out)


@dataclass
class FitResult:
    """Outcome of fitting one model type to a creep record.

    parameters / stderr: natural units (see the model's field names);
    offset_v: fitted bridge output at zero force; r2, rmse_v: on the segment
    samples at the record's rate; aic / bic: information criteria (lower is
    better) of the fit, on the block-averaged samples it used; n: samples.
    """

    model: ViscoelasticModel
    stderr: dict[str, float]
    offset_v: float
    r2: float
    rmse_v: float
    aic: float
    bic: float
    n: int
    success: bool = True
    message: str = ""

    @property
    def kind(self) -> str:
        """Model type name (a key of ``MODEL_TYPES``)."""
        return self.model.kind

    @property
    def parameters(self) -> dict[str, float]:
        """Fitted parameters by name, in their units (N/V, N s/V)."""
        return self.model.as_dict()

    def summary(self) -> dict[str, Any]:
        """JSON-ready fit report: model, parameters and standard errors, offset [V], R^2, RMSE [V], criteria."""
        return {
            "model": self.kind,
            "parameters": self.parameters,
            "stderr": self.stderr,
            "offset_v": self.offset_v,
            "r2": self.r2,
            "rmse_v": self.rmse_v,
            "aic": self.aic,
            "bic": self.bic,
            "n": self.n,
        }


@dataclass
class Selection:
    """All fits, best (lowest BIC) first."""

    fits: list[FitResult] = field(default_factory=list)
    segments: list[CreepSegment] = field(default_factory=list)

    @property
    def best(self) -> FitResult:
        """The selected fit (the first: fits are ordered best first)."""
        return self.fits[0]


def _initial_guesses(model_type: type[ViscoelasticModel], t: np.ndarray, f: np.ndarray, v: np.ndarray,
                     segments: list[CreepSegment]) -> list[np.ndarray]:
    """A few starting points from the first creep segment's shape (compliances in V/N)."""
    seg = segments[0]
    v0 = float(np.median(v[seg.start : max(seg.start + 1, seg.load - 1)]))
    f_hold = max(seg.hold_force_n, 1e-9)
    hold = slice(seg.load, seg.release)
    th, jh = t[hold] - t[seg.load], (v[hold] - v0) / f_hold
    if th.size < 4 or th[-1] <= 0:
        raise ValueError("creep segment too short to fit")
    hold_s = float(th[-1])
    j_inst = max(float(np.median(jh[: max(2, th.size // 50)])), 1e-9)
    tail = th >= 0.8 * hold_s
    slope = float(np.polyfit(th[tail], jh[tail], 1)[0]) if tail.sum() > 3 else 0.0
    slope = max(slope, 1e-6 * j_inst / hold_s)
    j_end = max(float(np.median(jh[tail])), j_inst * 1.01)
    return starts_from_compliance(model_type.kind, j_inst, j_end, slope, (hold_s / 20, hold_s / 6, hold_s / 2), hold_s)


def fit_creep(model_type: str | type[ViscoelasticModel], t_s: npt.ArrayLike, force_n: npt.ArrayLike,
              voltage_v: npt.ArrayLike, segments: Optional[list[CreepSegment]] = None,
              fit_rate_hz: float = DEFAULT_FIT_RATE_HZ) -> FitResult:
    """Fit one viscoelastic model type to a record with creep segments.

    Parameters
    ----------
    model_type : a class from :data:`MODEL_TYPES` (or its name).
    t_s, force_n, voltage_v : (n,) arrays, s / N / V, the whole record.
    segments : list of :class:`CreepSegment` in the indices of these arrays;
        found automatically when omitted.

    Returns a :class:`FitResult`; raises ``ValueError`` when the record holds
    no usable creep segment or contains non-finite samples.
    """
    model_type = fitting.model_type(model_type)
    t, f, v, segments = _prepare(t_s, force_n, voltage_v, segments)
    mask = np.zeros(t.size, dtype=bool)
    for seg in segments:
        mask[seg.start : seg.stop] = True
    # Decimate once for all candidates; the mask follows the blocks.
    td, fd, vd, md = block_average(t, f, v, mask.astype(float), rate_hz=fit_rate_hz)
    use = md > 0.5
    seg_d = _rescale_segments(segments, t, td)
    n = int(use.sum())
    vu = vd[use]

    def residual(log_params: np.ndarray) -> np.ndarray:
        model = model_type.from_vector(np.exp(log_params))
        gamma = simulate_deformation(model, td, fd)[use]
        r: np.ndarray = vu - gamma
        centred: np.ndarray = r - r.mean()
        return centred

    lower, upper = log_bounds(len(model_type.parameter_names()))
    best = multistart_least_squares(residual, _initial_guesses(model_type, td, fd, vd, seg_d), lower, upper)
    model = model_type.from_vector(np.exp(best.x))
    p = best.x.size + 1  # mechanical parameters plus the offset
    se = log_standard_errors(best, n, p)
    stderr = {name: float(s_) for name, s_ in zip(model_type.parameter_names(), se)}
    # Fit quality at the record's own rate (block averages would hide half the noise).
    gamma = simulate_deformation(model, t, f)[mask]
    vm = v[mask]
    offset = float(np.mean(vm - gamma))
    res = vm - gamma - offset
    rss, tss = float(res @ res), float(((vm - vm.mean()) ** 2).sum())
    aic, bic = information_criteria(2.0 * float(best.cost), n, p)  # on the (decimated) fitted samples
    return FitResult(
        model=model,
        stderr=stderr,
        offset_v=offset,
        r2=1.0 - rss / tss if tss > 0 else float("nan"),
        rmse_v=math.sqrt(rss / vm.size),
        aic=aic,
        bic=bic,
        n=int(vm.size),
        success=bool(best.success),
        message=str(best.message),
    )


def _rescale_segments(segments: Iterable[CreepSegment], t_full: np.ndarray, t_dec: np.ndarray) -> list[CreepSegment]:
    """Map segments from full-rate indices to indices of the decimated record."""
    def idx(i: int) -> int:
        return int(np.clip(np.searchsorted(t_dec, t_full[min(i, t_full.size - 1)]), 0, t_dec.size - 1))

    return [
        CreepSegment(idx(s.start), idx(s.load), max(idx(s.release), idx(s.load) + 1), idx(s.stop - 1) + 1,
                     s.hold_force_n, s.hold_s)
        for s in segments
    ]


def _prepare(t_s: npt.ArrayLike, force_n: npt.ArrayLike, voltage_v: npt.ArrayLike,
             segments: Optional[list[CreepSegment]]) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[CreepSegment]]:
    """Validated float arrays and the creep segments (found when not given)."""
    t, f, v = (np.asarray(a, dtype=float) for a in (t_s, force_n, voltage_v))
    _check_record(t, f, v)
    if segments is None:
        segments = find_creep_segments(t, f)
    if not segments:
        raise ValueError("no creep segment found: need a load step held for several seconds")
    return t, f, v, segments


def _check_record(t: np.ndarray, f: np.ndarray, v: np.ndarray) -> None:
    if not (t.shape == f.shape == v.shape) or t.ndim != 1:
        raise ValueError("time, force and voltage must be 1-D arrays of equal length")
    bad = ~(np.isfinite(t) & np.isfinite(f) & np.isfinite(v))
    if bad.any():
        raise ValueError(f"record holds {int(bad.sum())} non-finite samples; clean them first")
    if np.any(np.diff(t) < 0):
        raise ValueError("record time goes backwards; sort it first")


#: The model types a calibration fits by default (the lowest BIC wins).
DEFAULT_CANDIDATES = ("maxwell", "kelvin", "zener", "burgers")


def select_model(t_s: npt.ArrayLike, force_n: npt.ArrayLike, voltage_v: npt.ArrayLike,
                 candidates: Iterable[str] = DEFAULT_CANDIDATES,
                 segments: Optional[list[CreepSegment]] = None, fit_rate_hz: float = DEFAULT_FIT_RATE_HZ,
                 progress: Optional[Callable[[str], object]] = None) -> Selection:
    """Fit every candidate and rank them by BIC (best first).

    progress: optional callable ``progress(name)`` called before each fit.
    """
    candidates = fitting.check_model_types(candidates)
    t, f, v, segments = _prepare(t_s, force_n, voltage_v, segments)
    fits = []
    for name in candidates:
        if progress is not None:
            progress(name)
        fits.append(fit_creep(name, t, f, v, segments=segments, fit_rate_hz=fit_rate_hz))
    fits.sort(key=lambda r: r.bic)
    return Selection(fits=fits, segments=segments)
