"""The one fitting stack: parameter transforms and bounds, starting values, multi-start
least squares, standard errors and information criteria.

Calibration (:mod:`.identification`, creep records) and diagnosis
(:mod:`polyforce_ros.discrepancy.engine`, mixed bench records) both fit through
here, so a bound, a criterion or a model type cannot differ between them.

Mechanical parameters are fitted as ``theta = log(value)``: they are all positive
and span decades. Every criterion states its sample count ``n`` (the samples the
residual was computed on) and its parameter count ``p`` (the offset included
when it was fitted).
"""
from __future__ import annotations

import math
from typing import Callable, Iterable, Optional, Sequence, cast

import numpy as np
import numpy.typing as npt
from scipy import optimize

from .viscoelastic import MODEL_TYPES, ViscoelasticModel

__all__ = ["LOG_BOUNDS", "TAU_LOG_BOUNDS", "TAU_GRID_S", "FLUID_KINDS", "model_type", "check_model_types", "log_bounds",
           "multistart_least_squares", "log_standard_errors", "block_jackknife_standard_errors", "information_criteria",
           "starts_from_compliance"]

#: Bounds of log(parameter) for every mechanical parameter (N/V, N s/V): 1e-6 .. 1e12.
LOG_BOUNDS = (math.log(1e-6), math.log(1e12))
#: Log bounds of a time constant fitted on its own (retardation, lag, thermal lag), ln(s).
TAU_LOG_BOUNDS = (math.log(1e-3), math.log(1e4))
#: Starting retardation times of a search over a record (s): 0.3 s to 300 s, 16 log-spaced.
TAU_GRID_S = np.exp(np.linspace(np.log(0.3), np.log(300.0), 16))
#: Core types with a free dashpot (creep without bound).
FLUID_KINDS = frozenset(kind for kind, cls in MODEL_TYPES.items() if cls.shape[2])


def model_type(name_or_type: str | type[ViscoelasticModel]) -> type[ViscoelasticModel]:
    """The model class of a name in :data:`MODEL_TYPES` (or the class itself); ``ValueError`` if unknown."""
    if isinstance(name_or_type, type) and issubclass(name_or_type, ViscoelasticModel):
        return name_or_type
    try:
        return MODEL_TYPES[name_or_type]
    except (KeyError, TypeError):
        raise ValueError(f"unknown model type {name_or_type!r}; known: {sorted(MODEL_TYPES)}") from None


def check_model_types(names: Iterable[object]) -> tuple[str, ...]:
    """The names, validated (``ValueError`` naming the unknown ones); at least one."""
    names = tuple(names)
    unknown = [n for n in names if not isinstance(n, str) or n not in MODEL_TYPES]
    if unknown:
        raise ValueError(f"unknown model types {unknown}; known: {sorted(MODEL_TYPES)}")
    if not names:
        raise ValueError("no model type to fit")
    return cast(tuple[str, ...], names)


def log_bounds(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds of ``n`` log-parameters."""
    return np.full(n, LOG_BOUNDS[0]), np.full(n, LOG_BOUNDS[1])


def multistart_least_squares(residual: Callable[[np.ndarray], np.ndarray], starts: Sequence[npt.ArrayLike], lower: npt.ArrayLike,
                             upper: npt.ArrayLike, max_nfev: Optional[int] = None) -> optimize.OptimizeResult:
    """:func:`scipy.optimize.least_squares` (trf, Jacobian scaling) from every start; the lowest cost wins.

    Starts are clipped just inside the bounds.
    """
    lower, upper = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    best = None
    for x0 in starts:
        x0 = np.clip(np.asarray(x0, dtype=float), lower + 1e-9, upper - 1e-9)
        sol = optimize.least_squares(residual, x0, bounds=(lower, upper), x_scale="jac", method="trf", max_nfev=max_nfev)
        if best is None or sol.cost < best.cost:
            best = sol
    if best is None:
        raise ValueError("no starting point to fit from")
    return best


def log_standard_errors(sol: optimize.OptimizeResult, n: int, p: int) -> np.ndarray:
    """Standard errors of the natural parameters ``exp(sol.x)`` from the Jacobian at the optimum.

    ``n`` residuals, ``p`` free parameters (offset included) for the variance of the noise.
    """
    sigma2 = 2.0 * float(sol.cost) / max(n - p, 1)
    cov_log = sigma2 * np.linalg.pinv(sol.jac.T @ sol.jac)
    return np.asarray(np.exp(sol.x) * np.sqrt(np.clip(np.diag(cov_log), 0.0, None)))


def block_jackknife_standard_errors(left_out_estimates: npt.ArrayLike) -> np.ndarray:
    """Standard errors from the estimates of a blocked cross-validation (the delete-a-block jackknife).

    Each row is the estimate with one contiguous block of the record left out.
    Unlike :func:`log_standard_errors` it does not assume white residuals: a
    slow misfit that the blocks share widens it, as it should. With blocks
    contiguous in time it tends to be conservative (larger than the white-noise
    standard error).

    Parameters
    ----------
    left_out_estimates : (k, p) array_like
        The ``p`` parameters fitted ``k`` times (k >= 2), each without one block,
        in the parameters' own units.

    Returns
    -------
    (p,) ndarray
        Standard error of each parameter, same units; ``sqrt((k-1)/k * sum((x_i - mean)^2))``.
    """
    estimates = np.atleast_2d(np.asarray(left_out_estimates, dtype=float))
    k = estimates.shape[0]
    if k < 2:
        raise ValueError("a jackknife needs at least two left-out estimates")
    spread = estimates - estimates.mean(axis=0)
    return np.asarray(np.sqrt((k - 1) / k * np.sum(spread * spread, axis=0)))


def information_criteria(rss: float, n: int, p: int) -> tuple[float, float]:
    """Gaussian AIC and BIC of a least-squares fit: residual sum of squares ``rss`` over ``n`` samples,
    ``p`` free parameters. Lower is better; compare only criteria over the same samples."""
    if n < 1:
        raise ValueError("information criteria need at least one sample")
    log_var = math.log(max(rss / n, 1e-300))
    return n * log_var + 2 * p, n * log_var + p * math.log(n)


def starts_from_compliance(kind: str, j_inst_v_per_n: float, j_end_v_per_n: float, flow_v_per_n_s: float,
                           taus_s: Sequence[float], hold_s: float = 0.0) -> list[np.ndarray]:
    """Starting log-parameter vectors of any core type from the shape of a creep compliance.

    Parameters
    ----------
    kind : a name in :data:`MODEL_TYPES`.
    j_inst_v_per_n : instantaneous compliance (V/N).
    j_end_v_per_n : compliance at the end of a hold of ``hold_s`` (V/N).
    flow_v_per_n_s : creep rate that does not settle (V/(N s)); the free dashpot's 1/eta.
    taus_s : retardation times to start from (one start each).
    hold_s : length of the hold ``j_end`` was read at (s); the flow part of it is
        not delayed elasticity.
    """
    model_type(kind)
    j_inst = max(j_inst_v_per_n, 1e-12)
    j_end = max(j_end_v_per_n, j_inst * 1.01)
    flow = max(flow_v_per_n_s, 1e-12)
    if kind == "maxwell" and hold_s > 0:  # all of a Maxwell sensor's creep is flow
        flow = max(flow, (j_end - j_inst) / hold_s)
    delayed = max(j_end - j_inst - (flow * hold_s if kind in FLUID_KINDS else 0.0), 0.05 * j_inst)
    starts = []
    for tau in taus_s:
        # two Kelvin elements share the delayed compliance, one faster and one slower than tau
        half, third, fast, slow = 2.0 / delayed, 3.0 / delayed, tau / 2.0, tau * 4.0
        table = {
            "elastic": (1 / j_end,),
            "maxwell": (1 / j_inst, 1 / flow),
            "kelvin": (1 / j_end, tau / j_end),
            "zener": (1 / j_inst, 1 / delayed, tau / delayed),
            "burgers": (1 / j_inst, 1 / delayed, 1 / flow, tau / delayed),
            "zener2": (1 / j_inst, half, half * fast, half, half * slow),
            "burgers2": (1 / j_inst, half, 1 / flow, half * fast, half, half * slow),
            # three Kelvin elements: one faster, one at and one slower than tau
            "zener3": (1 / j_inst, third, third * fast, third, third * tau, third, third * slow),
            "burgers3": (1 / j_inst, third, 1 / flow, third * fast, third, third * tau, third, third * slow),
        }
        starts.append(np.log(table[kind]))
    return starts
