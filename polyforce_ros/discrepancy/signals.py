"""The record as the design columns see it: times, force, voltage, temperature and the reference core's output.

:func:`uniform_blocks` averages a record onto a uniform grid at the fit rate; :class:`Signals` holds either that
grid or the record at its own rate, with the caches of the columns made from it.
"""
from __future__ import annotations

import math
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Any, Optional

import numpy as np
import numpy.typing as npt

from ..physics.viscoelastic import ViscoelasticModel

__all__ = ["FloatArray", "BoolArray", "IntArray", "GapStep", "ZeroJump", "Signals", "ColumnCache", "CACHE_BYTES",
           "uniform_blocks", "record_gaps", "noise_std", "MIN_GAP_S", "MAX_GAPS"]

FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]
IntArray = npt.NDArray[np.int64]


#: The most bytes of arrays one set of signals keeps in its column cache. A polish tries hundreds of retardation times
#: and shift factors, each a set of columns as long as the record: kept without a bound, they take one diagnosis of a
#: thermo-rheological record of 8 minutes at 100 Hz past 15 GB.
CACHE_BYTES = 1 << 30


def _nbytes(value: Any) -> int:
    """The bytes of the arrays in ``value`` (an array, or lists and tuples that hold them)."""
    if isinstance(value, np.ndarray):
        return int(value.nbytes)
    if isinstance(value, (list, tuple)):
        return sum(_nbytes(v) for v in value)
    return 0


class ColumnCache(OrderedDict[Any, Any]):
    """A dict that drops its least recently used entries once their arrays pass ``max_bytes`` (never the newest):
    what it drops is made again when asked for, the same columns."""

    def __init__(self, max_bytes: int = CACHE_BYTES) -> None:
        super().__init__()
        self.max_bytes = max_bytes
        self.held_bytes = 0

    def __getitem__(self, key: Any) -> Any:
        value = super().__getitem__(key)
        self.move_to_end(key)
        return value

    def __setitem__(self, key: Any, value: Any) -> None:
        if key in self:
            self.held_bytes -= _nbytes(super().__getitem__(key))
        super().__setitem__(key, value)
        self.move_to_end(key)
        self.held_bytes += _nbytes(value)
        while self.held_bytes > self.max_bytes and len(self) > 1:
            _, dropped = self.popitem(last=False)
            self.held_bytes -= _nbytes(dropped)


@dataclass(frozen=True)
class GapStep:
    """What the load hidden by a gap can leave in the output after it.

    A flow, or a retardation slower than two cross-validation blocks, carries the difference between the hidden
    load and the interpolated one as a step from the gap on (at most ``step_bound_v``); a faster retardation carries
    it as a departure of its state that decays with its own time tau, at most ``state_bound_v`` x
    (1 - exp(-length_s / tau)).

    Attributes
    ----------
    at_s, length_s : float
        A time inside the gap and the gap's length [s].
    step_bound_v : float
        The largest step [V].
    state_bound_v : float
        The largest departure of a retardation's state [V] that a gap much longer than its time could leave.
    decay_taus_s : tuple of float
        The fast retardation times [s] whose decays every model gets after the gap (the base core's: the same
        nuisance columns for every model compared).
    """

    at_s: float
    length_s: float
    step_bound_v: float
    state_bound_v: float = 0.0
    decay_taus_s: tuple[float, ...] = ()

    def decay_bounds_v(self) -> list[float]:
        """The largest amplitude [V] of the decay of each of :attr:`decay_taus_s` after the gap."""
        return [self.state_bound_v * -math.expm1(-self.length_s / tau) for tau in self.decay_taus_s]


@dataclass(frozen=True)
class ZeroJump:
    """A jump of the zero that a residual shows.

    Attributes
    ----------
    at_s : float
        When [s, the record's clock].
    size_v : float
        How large [V]: the gap between the residual's lines either side, less what the core's bends explain there
        (:func:`.residual.zero_jumps`); a part that settles within the guard is not in it.
    """

    at_s: float
    size_v: float


@dataclass
class Signals:
    """The record at one rate, with what design columns need.

    Attributes
    ----------
    t, f, v : (n,) ndarray
        Times [s], reference force [N], bridge voltage [V].
    temp : (n,) ndarray or None
        Temperature [degC]; None when the record has no temperature topic.
    t0, duration_s : float
        First time and length of the record [s].
    temp_ref : float
        Reference temperature of the thermal columns (the record's mean) [degC].
    x_ref : (n,) ndarray or None
        Output of the reference core (the current model's) [V]; None until a core is set.
    valid : (n,) ndarray of bool or None
        Samples that are fitted and scored (None: all).
    core_ref : ViscoelasticModel or None
        The reference core behind ``x_ref``.
    f_smooth : (n,) ndarray or None
        The force behind ``x_ref`` and the force plays [N]; None: ``f`` itself.
    gap_steps : tuple of GapStep
        Each gap long enough to hide load history (:func:`record_gaps`), with the largest step [V] the hidden load
        can leave and the largest departure of a fast retardation's state; the design gives the record after each
        its own offset step and a decay of each fast retardation of the base core, so bounded.
    span_f, span_x : float
        Force span [N] and span of ``x_ref`` [V] at the fit rate: the play radii scale with them (the same at every
        rate of one reference core).
    zero_jumps : tuple of ZeroJump
        Where the base model's residual jumps while its core's output does not (:func:`.residual.zero_jumps`): where
        the ``steps`` and ``jumps`` variants of an offset drift put theirs.
    cache : ColumnCache
        Design columns made from these signals (new with every reference core), at most :data:`CACHE_BYTES`.
    record_cache : dict
        What depends on the record alone (force, time), not on the reference core: kept by every refresh.
    """

    t: FloatArray
    f: FloatArray
    v: FloatArray
    temp: Optional[FloatArray]
    t0: float
    duration_s: float
    temp_ref: float
    x_ref: Optional[FloatArray] = None
    valid: Optional[BoolArray] = None
    core_ref: Optional[ViscoelasticModel] = None
    f_smooth: Optional[FloatArray] = None
    span_f: float = 1.0
    span_x: float = 1.0
    gap_steps: tuple[GapStep, ...] = ()
    zero_jumps: tuple[ZeroJump, ...] = ()
    cache: ColumnCache = field(default_factory=ColumnCache, init=False, repr=False)
    record_cache: dict[Any, Any] = field(default_factory=dict, repr=False)

    @property
    def f_nonlinear(self) -> FloatArray:
        """The force that drives the nonlinear columns (x_ref, the force plays), N."""
        return self.f if self.f_smooth is None else self.f_smooth

    @property
    def core_output(self) -> FloatArray:
        """``x_ref``, the reference core's output [V]; a ValueError before a reference core is set."""
        if self.x_ref is None:
            raise ValueError("the signals have no reference core output yet")
        return self.x_ref

    @property
    def reference_core(self) -> ViscoelasticModel:
        """``core_ref``, the reference core; a ValueError before one is set."""
        if self.core_ref is None:
            raise ValueError("the signals have no reference core yet")
        return self.core_ref

    @property
    def temperature(self) -> FloatArray:
        """``temp`` [degC]; a ValueError for a record without temperature."""
        if self.temp is None:
            raise ValueError("the record has no temperature")
        return self.temp


def uniform_blocks(t_s: npt.ArrayLike, force_n: npt.ArrayLike, voltage_v: npt.ArrayLike, temperature_c: npt.ArrayLike,
                   rate_hz: float) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, BoolArray, IntArray]:
    """Block means on a uniform time grid of step 1/rate_hz (the record's own step when slower).

    Returns ``(t, force, voltage, temperature, valid, bin_of_sample)``: bins without samples (dropped blocks)
    get force and temperature interpolated (the model needs its input everywhere) and are
    marked invalid (never fitted, never scored). A uniform grid keeps every exponential
    convolution on its fast path whatever the stamp jitter. ``bin_of_sample``: the bin each sample
    was averaged into (its cross-validation fold is the bin's).
    """
    t = np.asarray(t_s, dtype=float)
    step = max(1.0 / rate_hz, float(np.median(np.diff(t))))
    k = np.floor((t - t[0]) / step).astype(np.int64)
    n = int(k[-1]) + 1
    counts = np.bincount(k, minlength=n).astype(float)
    valid = counts > 0
    grid = t[0] + (np.arange(n) + 0.5) * step

    def mean(x: npt.ArrayLike) -> FloatArray:
        m = np.bincount(k, weights=np.asarray(x, dtype=float), minlength=n)[valid] / counts[valid]
        out: FloatArray = np.interp(grid, grid[valid], m)
        return out

    return grid, mean(force_n), mean(voltage_v), mean(temperature_c), valid, k


#: Shortest gap [s] whose hidden load history gets an offset step of its own: within 0.1 s a hand-held needle's
#: force moves little, and interpolating across it loses less than the noise.
MIN_GAP_S = 0.1
#: Most gaps given a step (the longest): each is one more column of every model.
MAX_GAPS = 8


def record_gaps(t_s: npt.ArrayLike, margin_s: float, min_gap_s: float = MIN_GAP_S,
                most: int = MAX_GAPS) -> tuple[tuple[float, float], ...]:
    """(middle [s], length [s]) of each of the record's ``most`` longest gaps of at least ``min_gap_s`` with at least
    ``margin_s`` of record before and after it (the middle: at any rate, every sample and every fitted bin lies on
    one side), in time order.

    Across a gap the force is interpolated, but a sensor with memory integrated the load it really had: a flow, or a
    retardation slower than the record, carries the difference as a step in the output from the gap on. Each such
    step is a nuisance of the record (it is not saved with the model); without one, a time drift is fitted to it
    and named. A step is fitted out of sample only with record on both sides of it in every fold's training blocks:
    two cross-validation blocks' length each side (blocks are dealt to the folds in turn). Nearer an end, the step
    and the offset trade freely when a fold is left out.
    """
    t = np.asarray(t_s, dtype=float)
    if t.size < 3:
        return ()
    dt = np.diff(t)
    step = float(np.median(dt))
    long_gaps = np.flatnonzero(dt >= max(min_gap_s, 5.0 * step))
    long_gaps = long_gaps[(t[long_gaps] >= t[0] + margin_s) & (t[long_gaps + 1] <= t[-1] - margin_s)]
    chosen = np.sort(long_gaps[np.argsort(dt[long_gaps])[::-1][:most]])
    return tuple((float(0.5 * (t[k] + t[k + 1])), float(dt[k])) for k in chosen)


def noise_std(x: npt.ArrayLike) -> float:
    """White-noise standard deviation of a sampled signal from its second differences (robust MAD)."""
    d2 = np.diff(np.asarray(x, dtype=float), 2)
    if d2.size < 10:
        return 0.0
    return float(1.4826 * np.median(np.abs(d2 - np.median(d2))) / math.sqrt(6.0))
