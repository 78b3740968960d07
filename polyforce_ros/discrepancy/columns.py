"""The vocabulary every effect of the catalogue is written in: design columns, chain slots, the callables an
:class:`~.effects.Effect` holds, and the helpers their columns share (a unit-gain lag, a log-spaced grid)."""
from __future__ import annotations

from typing import Callable, Mapping, Optional, Sequence

import numpy as np
import numpy.typing as npt

from ..physics.chain import Element
from ..physics.expconv import exp_convolve, exp_convolve_columns
from .signals import FloatArray, Signals

__all__ = ["Col", "Slot", "GridFn", "ColumnsFn", "ElementsFn", "TEMPERATURE_LAG_BOUNDS_S", "lag_columns", "parameter",
           "log_grid"]

#: Column: (name, samples, lower bound, upper bound, "sensor" | "additive", ridge group or None).
Col = tuple[str, FloatArray, float, float, str, Optional[str]]
#: Where an element goes in the chain: "before" the core (force path), "core" (wraps it), "after" it (voltage path), "lag",
#: "late".
Slot = tuple[str, Element]
#: (variant, signals) -> values of the nonlinear parameter searched ([None]: the variant has none).
GridFn = Callable[[str, Signals], Sequence[Optional[float]]]
#: (signals, variant, parameter) -> the design columns the effect adds.
ColumnsFn = Callable[[Signals, str, Optional[float]], list[Col]]
#: (coefficient by column name, variant, parameter, signals) -> the chain elements of the fitted effect.
ElementsFn = Callable[[Mapping[str, float], str, Optional[float], Signals], list[Slot]]

#: The bounds of a part's temperature lag behind the thermometer's as the polish refines it [s] (a clock's core, a
#: friction band's guide): from a thin part warming with its air to one inside a thick housing.
TEMPERATURE_LAG_BOUNDS_S = (2.0, 120.0)


def lag_columns(t: npt.ArrayLike, x: npt.ArrayLike, tau_s: float) -> FloatArray:
    """Unit-gain first-order lag of each column of x (n,) or (n, m), from rest."""
    x = np.asarray(x, dtype=float)
    if x.ndim == 1:  # the design's columns, one by one: no stacking
        out: FloatArray = exp_convolve(t, x, [1.0 / tau_s])[:, 0] / tau_s
        return out
    return exp_convolve_columns(t, x, 1.0 / tau_s) / tau_s  # one filter over all columns (column-major, contiguous)


def parameter(param: Optional[float]) -> float:
    """The value of a variant's nonlinear parameter; a ValueError for a variant searched without one."""
    if param is None:
        raise ValueError("this variant needs a value of its nonlinear parameter")
    return param


def log_grid(lo: float, hi: float, n: int) -> list[Optional[float]]:
    """``n`` values log-spaced from ``lo`` to ``hi`` (both included): a nonlinear parameter's search grid."""
    return list(np.exp(np.linspace(np.log(lo), np.log(hi), n)))
