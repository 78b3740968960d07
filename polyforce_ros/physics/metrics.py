"""Error metrics between a reference force and an estimate (both in N, same samples)."""
from __future__ import annotations

from typing import Optional

import numpy as np
import numpy.typing as npt

__all__ = ["rmse", "max_abs_error", "r_squared", "error_summary", "hysteresis_percent", "step_response",
    "sine_component", "bandwidth_3db", "resolution_changes"]


def rmse(reference: npt.ArrayLike, estimate: npt.ArrayLike) -> float:
    """Root-mean-square error, in the unit of the inputs."""
    d = np.asarray(estimate, dtype=float) - np.asarray(reference, dtype=float)
    return float(np.sqrt(np.mean(d * d)))


def max_abs_error(reference: npt.ArrayLike, estimate: npt.ArrayLike) -> float:
    """Largest absolute difference between ``estimate`` and ``reference`` (their unit, e.g. N)."""
    return float(np.max(np.abs(np.asarray(estimate, dtype=float) - np.asarray(reference, dtype=float))))


def r_squared(reference: npt.ArrayLike, estimate: npt.ArrayLike) -> float:
    """Coefficient of determination of ``estimate`` as a prediction of ``reference``.

    1 - SS_res / SS_tot with SS_tot about the reference mean (the definition
    seed 000 uses for Fig. 18: measured vs applied force).
    """
    ref = np.asarray(reference, dtype=float)
    res = np.asarray(estimate, dtype=float) - ref
    tot = ref - ref.mean()
    return float(1.0 - (res @ res) / (tot @ tot))


def error_summary(reference: npt.ArrayLike, estimate: npt.ArrayLike) -> dict[str, float]:
    """RMSE (N), largest error (N) and R^2 of a force estimate against the reference force."""
    return {
        "rmse_n": rmse(reference, estimate),
        "max_abs_n": max_abs_error(reference, estimate),
        "r2": r_squared(reference, estimate),
    }


def hysteresis_percent(input_signal: npt.ArrayLike, output_signal: npt.ArrayLike, grid_points: int = 97) -> float:
    """Hysteresis of one loading/unloading cycle, normalised as in seed 000 (Fig. 11).

    Input and output are divided by their maxima; the cycle is split at the
    input's maximum into loading and unloading branches; the result is the
    largest vertical gap between the branches over 2-98 % of the input range,
    in percent of the normalised output. A pure spring gives 0.
    """
    u = np.asarray(input_signal, dtype=float)
    y = np.asarray(output_signal, dtype=float)
    u, y = u / np.max(np.abs(u)), y / np.max(np.abs(y))
    peak = int(np.argmax(u))
    if peak < 2 or peak > u.size - 3:
        raise ValueError("hysteresis needs a loading and an unloading branch")
    grid = np.linspace(0.02, 0.98, grid_points) * u[peak]

    def branch(us: np.ndarray, ys: np.ndarray) -> np.ndarray:
        order = np.argsort(us, kind="stable")
        return np.asarray(np.interp(grid, us[order], ys[order]), dtype=float)

    return float(100.0 * np.max(np.abs(branch(u[peak:], y[peak:]) - branch(u[: peak + 1], y[: peak + 1]))))


def step_response(t_s: npt.ArrayLike, y: npt.ArrayLike, t_step_s: float, final_value: float,
                  settle_band: float = 0.02) -> dict[str, float]:
    """10-90 % rise time and settling time (s) of a step of size ``final_value`` at ``t_step_s``.

    Settling: time after the step from which |y - final| stays within
    ``settle_band`` * |final| to the end of the record; ``inf`` if it never
    does (a drifting, uncompensated reading). Rise time ``inf`` if 90 % is
    never reached.
    """
    t, y = np.asarray(t_s, dtype=float), np.asarray(y, dtype=float)
    after = t >= t_step_s
    ta, ya = t[after], y[after] / final_value
    hit10, hit90 = np.flatnonzero(ya >= 0.1), np.flatnonzero(ya >= 0.9)
    rise = float(ta[hit90[0]] - ta[hit10[0]]) if hit90.size and hit10.size else float("inf")
    outside = np.flatnonzero(np.abs(ya - 1.0) > settle_band)
    if outside.size == 0:
        settle = 0.0
    elif outside[-1] == ya.size - 1:
        settle = float("inf")
    else:
        settle = float(ta[outside[-1] + 1] - t_step_s)
    return {"rise_time_s": rise, "settling_time_s": settle}


def sine_component(t_s: npt.ArrayLike, y: npt.ArrayLike, freq_hz: float, trend: bool = False) -> tuple[float, float]:
    """Amplitude and phase (rad) of the ``freq_hz`` component by least squares.

    The regression includes a constant and, with ``trend``, a linear drift
    (an uncompensated viscoelastic reading creeps during a sine test).
    """
    t = np.asarray(t_s, dtype=float)
    w = 2 * np.pi * freq_hz * t
    columns = [np.sin(w), np.cos(w), np.ones_like(t)] + ([t - t.mean()] if trend else [])
    coef, *_ = np.linalg.lstsq(np.column_stack(columns), np.asarray(y, dtype=float), rcond=None)
    return float(np.hypot(coef[0], coef[1])), float(np.arctan2(coef[1], coef[0]))


def bandwidth_3db(freqs_hz: npt.ArrayLike, magnitude_db: npt.ArrayLike, reference_db: Optional[float] = None) -> float:
    """Lowest frequency (Hz) where the magnitude falls 3 dB below the reference.

    The reference is the magnitude at the lowest frequency unless given. The
    crossing is interpolated in log-frequency; ``inf`` means the magnitude
    stays within 3 dB over the whole range (bandwidth beyond the last frequency).
    """
    f = np.asarray(freqs_hz, dtype=float)
    m = np.asarray(magnitude_db, dtype=float)
    ref = m[0] if reference_db is None else reference_db
    below = np.flatnonzero(m < ref - 3.0)
    if below.size == 0:
        return float("inf")
    i = below[0]
    if i == 0:
        return float(f[0])
    x0, x1 = np.log10(f[i - 1]), np.log10(f[i])
    frac = (m[i - 1] - (ref - 3.0)) / (m[i - 1] - m[i])
    return float(10 ** (x0 + frac * (x1 - x0)))


def resolution_changes(t_s: npt.ArrayLike, y: npt.ArrayLike, start_s: float, half_period_s: float, cycles: int,
                       window_s: float = 40.0, sample_period_s: float = 0.1) -> np.ndarray:
    """Detected changes of the resolution test (seed 000, Fig. 13-14), as samples.

    Each cycle (low half, then high half of a square wave starting at
    ``start_s``) is referred to its value at the start of the cycle; the
    ``window_s`` seconds in the middle of each high half, sampled every
    ``sample_period_s``, are the detected changes. Returns the array (mean and
    std are the paper's 0.08 +- 0.013 N).
    """
    t, y = np.asarray(t_s, dtype=float), np.asarray(y, dtype=float)
    out = []
    for k in range(cycles):
        c0 = start_s + 2 * k * half_period_s
        base = np.mean(y[(t >= c0 - 0.5) & (t < c0)]) if np.any((t >= c0 - 0.5) & (t < c0)) else y[np.searchsorted(t, c0)]
        # the high half is the first half of each cycle in profiles.resolution
        mid = c0 + 0.5 * half_period_s
        grid = np.arange(mid - window_s / 2, mid + window_s / 2, sample_period_s)
        out.append(np.interp(grid, t, y) - base)
    return np.concatenate(out) if out else np.zeros(0)
