"""Applied-force profiles of the bench experiments in seed 000 (all in N over s).

Every function returns ``(t_s, force_n)`` sampled at ``rate_hz`` and is
deterministic for a given ``seed``. Compression is positive.
"""
from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any, Callable, Optional, Union

import numpy as np
import numpy.typing as npt
from scipy import signal

__all__ = ["PROFILE_NAMES", "creep", "sawtooth", "step", "sine_sweep", "resolution", "needle_insertion",
    "okamura_csv_path", "okamura_insertion", "make_profile"]

PROFILE_NAMES = ("creep", "sawtooth", "step", "sine_sweep", "resolution", "needle_insertion")

FloatArray = npt.NDArray[np.float64]
#: A profile: times [s] and force [N].
Profile = tuple[FloatArray, FloatArray]


def _time(duration_s: float, rate_hz: float) -> FloatArray:
    n = int(round(duration_s * rate_hz)) + 1
    return np.arange(n) / float(rate_hz)


def creep(force_n: float = 5.0, hold_s: float = 120.0, rest_s: float = 60.0, pre_s: float = 2.0, rise_s: float = 0.2,
          rate_hz: float = 1000.0) -> Profile:
    """Creep test (Fig. 8): rest, ramp to ``force_n`` in ``rise_s``, hold, release, recover."""
    t = _time(pre_s + rise_s + hold_s + rise_s + rest_s, rate_hz)
    knots_t = [0, pre_s, pre_s + rise_s, pre_s + rise_s + hold_s, pre_s + 2 * rise_s + hold_s, t[-1]]
    knots_f = [0, 0, force_n, force_n, 0, 0]
    return t, np.interp(t, knots_t, knots_f)


def sawtooth(peak_n: float = 10.0, cycles: int = 4, ramp_rate_n_per_s: float = 1.0, pre_s: float = 2.0,
             post_s: float = 10.0, rate_hz: float = 1000.0) -> Profile:
    """Triangle sawtooth (Fig. 10): ``cycles`` ramps 0 -> peak -> 0 at a constant force rate."""
    ramp_s = peak_n / ramp_rate_n_per_s
    t = _time(pre_s + cycles * 2 * ramp_s + post_s, rate_hz)
    phase = np.clip(t - pre_s, 0.0, cycles * 2 * ramp_s)
    tri = signal.sawtooth(2 * np.pi * phase / (2 * ramp_s), width=0.5)  # -1..1, starts at -1
    return t, np.where(phase > 0, peak_n * 0.5 * (tri + 1.0), 0.0)


def step(force_n: float = 5.0, pre_s: float = 2.0, hold_s: float = 30.0, rise_s: float = 0.0,
         rate_hz: float = 1000.0) -> Profile:
    """Step of ``force_n`` (Fig. 16) at ``pre_s``: within one sample, or a ramp of ``rise_s`` (an actuator's)."""
    t = _time(pre_s + hold_s, rate_hz)
    if rise_s <= 0:
        return t, np.where(t >= pre_s, force_n, 0.0)
    return t, force_n * np.clip((t - pre_s) / rise_s, 0.0, 1.0)


def sine_sweep(f_start_hz: float = 0.01, f_stop_hz: float = 10.0, amplitude_n: float = 1.0, offset_n: float = 3.0,
               duration_s: float = 600.0, rate_hz: float = 1000.0) -> Profile:
    """Logarithmic chirp from ``f_start_hz`` to ``f_stop_hz`` around a preload ``offset_n``, sin(phase) with
    phase = 2 pi f0 T / ln(f1 / f0) ((f1 / f0)^(t / T) - 1).

    Evaluated sample by sample with the C library's ``exp`` and ``sin``: numpy's vectorised ones take other paths
    on other CPUs (AVX-512 or not) and differ in the last bit, and the shipped bags are reproduced byte for byte.
    """
    t = _time(duration_s, rate_hz)
    span_s = float(t[-1]) if t.size > 1 else 1.0
    if f_stop_hz == f_start_hz:
        phase = [2.0 * math.pi * f_start_hz * ti for ti in t.tolist()]
    else:
        k = math.log(f_stop_hz / f_start_hz)
        phase = [2.0 * math.pi * f_start_hz * span_s / k * (math.exp(k * ti / span_s) - 1.0) for ti in t.tolist()]
    wave = np.fromiter((math.sin(x) for x in phase), dtype=float, count=t.size)
    return t, offset_n + amplitude_n * wave


def resolution(preload_n: float = 3.75, step_n: float = 0.1, half_period_s: float = 60.0, cycles: int = 4,
               pre_s: float = 10.0, rate_hz: float = 1000.0) -> Profile:
    """Resolution test (Fig. 13): ``step_n`` square wave on a ``preload_n`` preload."""
    t = _time(pre_s + cycles * 2 * half_period_s, rate_hz)
    square = (np.floor((t - pre_s) / half_period_s) % 2 == 0) & (t >= pre_s)
    ramp_in = np.clip(t / (0.5 * pre_s), 0.0, 1.0)  # preload applied gently, then held
    return t, preload_n * ramp_in + step_n * square


def needle_insertion(peak_n: float = 4.0, punctures: int = 3, duration_s: float = 30.0, seed: int = 0,
                     rate_hz: float = 1000.0) -> Profile:
    """Synthetic needle insertion: layered loading, puncture drops, hold, retraction.

    Force rises as the needle deforms each tissue layer, drops by 30-60 % when
    the layer ruptures (within ~30 ms), builds again by friction and the next
    layer, then relaxes during a hold and returns to zero on retraction. The
    result is low-pass filtered at 3 Hz (the band of insertion forces reported
    in seed 000) except for the puncture drops, which stay sharp.
    """
    rng = np.random.default_rng(seed)
    t = _time(duration_s, rate_hz)
    insert_end = 0.6 * duration_s
    times = np.sort(rng.uniform(0.15, 0.95, punctures)) * insert_end
    levels = np.sort(rng.uniform(0.35, 1.0, punctures)) * peak_n
    levels[-1] = peak_n
    knots_t, knots_f = [0.0, 1.0], [0.0, 0.0]
    for tp, fp in zip(times, levels):
        knots_t += [1.0 + tp, 1.0 + tp + 0.03]
        knots_f += [fp, fp * rng.uniform(0.4, 0.7)]
    hold_end = 1.0 + insert_end + 0.2 * duration_s
    knots_t += [1.0 + insert_end, hold_end, hold_end + 2.0, t[-1]]
    knots_f += [0.8 * knots_f[-1] + 0.2 * peak_n, 0.7 * knots_f[-1], 0.0, 0.0]
    f = np.interp(t, knots_t, knots_f)
    # Smooth the loading phases (tissue is soft) but keep the drops sharp: filter
    # the signal and restore the original within 40 ms after each puncture.
    sos = signal.butter(2, 3.0, fs=rate_hz, output="sos")
    smooth = signal.sosfiltfilt(sos, f)
    for tp in times:
        near = (t >= 1.0 + tp - 0.02) & (t <= 1.0 + tp + 0.06)
        smooth[near] = f[near]
    return t, np.clip(smooth, 0.0, None)


def okamura_csv_path() -> Optional[Path]:
    """Path of the measured insertion profile in ``shared/data`` if present, else None.

    Looked up in ``$POLYFORCE_DATA_DIR``, then in ``../shared/data`` beside the
    repository (the project's layout).
    """
    candidates = []
    if os.environ.get("POLYFORCE_DATA_DIR"):
        candidates.append(Path(os.environ["POLYFORCE_DATA_DIR"]))
    candidates.append(Path(__file__).resolve().parents[3] / "shared" / "data")
    for base in candidates:
        path = base / "needle_insertion_okamura" / "time_force.csv"
        if path.is_file():
            return path
    return None


def okamura_insertion(path: Union[str, os.PathLike[str], None] = None, peak_n: float = 4.0, rate_hz: float = 1000.0,
                      pre_s: float = 1.0, post_s: float = 5.0) -> Profile:
    """Measured needle-insertion force (Okamura et al. 2004, bovine liver), resampled.

    The digitised record has irregular, repeated time values: samples are
    sorted, duplicates merged by their mean, and the curve linearly resampled
    at ``rate_hz``, scaled so its maximum is ``peak_n``, and padded with zero
    force before and after. Raises ``FileNotFoundError`` when absent.
    """
    path = Path(path) if path else okamura_csv_path()
    if path is None or not Path(path).is_file():
        raise FileNotFoundError("Okamura needle-insertion data not found (set POLYFORCE_DATA_DIR)")
    raw = np.loadtxt(path, delimiter=",", ndmin=2)
    order = np.argsort(raw[:, 0], kind="stable")
    tr, fr = raw[order, 0], raw[order, 1]
    uniq, inverse = np.unique(tr, return_inverse=True)
    fm = np.bincount(inverse, weights=fr) / np.bincount(inverse)
    t_data = np.arange(0.0, uniq[-1], 1.0 / rate_hz)
    f_data = np.interp(t_data, uniq, fm) * (peak_n / fm.max())
    t = _time(pre_s + t_data[-1] + post_s, rate_hz)
    f = np.interp(t - pre_s, t_data, f_data, left=0.0, right=0.0)
    # Taper the start and end so the padded record has no jump at the ends.
    f[t < pre_s] = 0.0
    return t, f


def make_profile(name: str, rate_hz: float = 1000.0, seed: int = 0, **kwargs: Any) -> Profile:
    """Profile by name (one of :data:`PROFILE_NAMES`, or ``okamura``)."""
    table: dict[str, Callable[..., Profile]] = {
        "creep": creep,
        "sawtooth": sawtooth,
        "step": step,
        "sine_sweep": sine_sweep,
        "resolution": resolution,
        "needle_insertion": lambda **kw: needle_insertion(seed=seed, **kw),
        "okamura": okamura_insertion,
    }
    if name not in table:
        raise ValueError(f"unknown profile {name!r}; choose from {sorted(table)}")
    return table[name](rate_hz=rate_hz, **kwargs)
