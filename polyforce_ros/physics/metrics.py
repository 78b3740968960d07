"""Error metrics between a reference force and an estimate (both in N, same samples)."""
from __future__ import annotations

import numpy as np


def rmse(reference, estimate) -> float:
    """Root-mean-square error, in the unit of the inputs."""
    d = np.asarray(estimate, dtype=float) - np.asarray(reference, dtype=float)
    return float(np.sqrt(np.mean(d * d)))


def max_abs_error(reference, estimate) -> float:
    return float(np.max(np.abs(np.asarray(estimate, dtype=float) - np.asarray(reference, dtype=float))))


def r_squared(reference, estimate) -> float:
    """Coefficient of determination of ``estimate`` as a prediction of ``reference``.

    1 - SS_res / SS_tot with SS_tot about the reference mean (the definition
    seed 000 uses for Fig. 18: measured vs applied force).
    """
    ref = np.asarray(reference, dtype=float)
    res = np.asarray(estimate, dtype=float) - ref
    tot = ref - ref.mean()
    return float(1.0 - (res @ res) / (tot @ tot))


def error_summary(reference, estimate) -> dict:
    return {
        "rmse_n": rmse(reference, estimate),
        "max_abs_n": max_abs_error(reference, estimate),
        "r2": r_squared(reference, estimate),
    }
