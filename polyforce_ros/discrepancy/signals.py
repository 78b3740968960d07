"""The record as the design columns see it: times, force, voltage, temperature and the reference core's output.

:func:`uniform_blocks` averages a record onto a uniform grid at the fit rate; :class:`Signals` holds either that
grid or the record at its own rate, with the caches of the columns made from it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Optional

import numpy as np
import numpy.typing as npt

from ..physics.viscoelastic import ViscoelasticModel

__all__ = ["FloatArray", "BoolArray", "IntArray", "Signals", "uniform_blocks", "noise_std"]

FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]
IntArray = npt.NDArray[np.int64]


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
    span_f, span_x : float
        Force span [N] and span of ``x_ref`` [V] at the fit rate: the play radii scale with them (the same at every
        rate of one reference core).
    cache : dict
        Design columns made from these signals (new with every reference core).
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
    cache: dict[Any, Any] = field(default_factory=dict, init=False, repr=False)
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


def noise_std(x: npt.ArrayLike) -> float:
    """White-noise standard deviation of a sampled signal from its second differences (robust MAD)."""
    d2 = np.diff(np.asarray(x, dtype=float), 2)
    if d2.size < 10:
        return 0.0
    return float(1.4826 * np.median(np.abs(d2 - np.median(d2))) / math.sqrt(6.0))
