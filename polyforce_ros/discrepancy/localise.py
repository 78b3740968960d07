"""Where does the residual (measured - simulated voltage) concentrate, and what does it follow?

Segment kinds are labelled per sample from the reference force and the
temperature; for each, the RMS residual inside is compared with the RMS over
the whole record (a ratio above 1 means the residual concentrates there).
Candidate signals are correlated with the residual; each hints at one effect.
"""
from __future__ import annotations

from typing import Any, Mapping, Optional

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from ..record import Record
from .effects import hints as _registry_hints
from .result import Diagnosis
from .signals import BoolArray, FloatArray

__all__ = ["HINTS", "segment_labels", "localise", "describe"]

#: What a concentration or a correlation suggests: the registry's effects that show there.
HINTS = {key: " / ".join(names) for key, names in _registry_hints().items()}
HINTS.setdefault("force", "gain error of the base")


def segment_labels(t_s: npt.ArrayLike, force_n: npt.ArrayLike, temperature_c: Optional[npt.ArrayLike] = None
                   ) -> tuple[dict[str, BoolArray], FloatArray]:
    """Boolean masks of the segment kinds (dict name -> mask), and the smoothed force rate [N/s]."""
    t, f = np.asarray(t_s), np.asarray(force_n)
    dt = float(np.median(np.diff(t)))
    smooth = ndimage.uniform_filter1d(f, max(1, int(0.1 / dt)))
    rate = np.gradient(smooth, t)
    fmax = max(float(np.percentile(f, 99)), 1e-9)
    labels = {
        "hold_under_load": (f > 0.2 * fmax) & (np.abs(rate) < 0.02 * fmax),
        "high_load": f > 0.7 * fmax,
        "fast_transient": np.abs(rate) > 0.5 * fmax,
    }
    loaded = ndimage.maximum_filter1d((f > 0.2 * fmax).astype(np.uint8), max(1, int(60.0 / dt)), origin=-0) > 0
    labels["rest_after_unloading"] = (f < 0.05 * fmax) & loaded
    moving = np.abs(rate) > 0.02 * fmax
    direction = np.sign(rate) * moving
    change = np.zeros(t.size, dtype=bool)
    idx = np.flatnonzero(direction)
    if idx.size > 1:
        flips = idx[1:][np.diff(direction[idx]) != 0]
        change[flips] = True
    labels["load_reversal"] = ndimage.maximum_filter1d(change.astype(np.uint8), max(1, int(2.0 / dt))) > 0
    if temperature_c is not None:
        trate = np.abs(np.gradient(ndimage.uniform_filter1d(np.asarray(temperature_c), max(1, int(5.0 / dt))), t))
        labels["temperature_change"] = trate > np.percentile(trate, 70)
    labels["late_in_record"] = t > t[0] + 2.0 / 3.0 * (t[-1] - t[0])
    return labels, rate


def localise(rec: Record, residual_v: npt.ArrayLike) -> dict[str, Any]:
    """Concentration of the residual per segment kind and its correlation with candidate signals.

    Returns ``rms_residual_v``, ``concentration`` (segment kind -> ``rms_ratio``, ``fraction``), ``correlation``
    (signal -> correlation coefficient) and ``masks`` (segment kind -> samples)."""
    if rec.force_n is None:
        raise ValueError("record has no reference force")
    labels, rate = segment_labels(rec.t_s, rec.force_n, rec.temperature_c)
    residual = np.asarray(residual_v)
    r = residual - np.mean(residual)
    overall = float(np.sqrt(np.mean(r * r)))
    concentration = {}
    for name, mask in labels.items():
        if mask.sum() > 10:
            concentration[name] = {"rms_ratio": float(np.sqrt(np.mean(r[mask] ** 2)) / max(overall, 1e-300)),
                                   "fraction": float(mask.mean())}
    f = rec.force_n
    direction = np.sign(rate)
    held = np.copy(direction)
    for k in range(1, held.size):  # the direction of the last movement (memory of the loading path)
        if held[k] == 0:
            held[k] = held[k - 1]
    signals = {
        "force": f,
        "force_squared": f * f,
        "force_rate": rate,
        "load_direction": held * (f > 0.05 * f.max()),
        "load_history": np.cumsum(f) * float(np.median(np.diff(rec.t_s))),
        "time": rec.t_s,
    }
    if rec.temperature_c is not None:
        signals["temperature"] = rec.temperature_c
    correlation = {}
    for name, s in signals.items():
        s = np.asarray(s, dtype=float) - np.mean(s)
        denom = np.sqrt((s @ s) * (r @ r))
        correlation[name] = float(s @ r / denom) if denom > 0 else 0.0
    return {"rms_residual_v": overall, "concentration": concentration, "correlation": correlation, "masks": labels}


def describe(loc: Mapping[str, Any], diag: Diagnosis) -> list[str]:
    """Evidence as short sentences with numbers (the JSON ``evidence`` list)."""
    out = [f"noise floor estimated from the data: {diag.noise_floor_v:.3e} V (high-frequency differences of the raw "
           f"voltage and of the reference force through the static gain)",
           f"base model: out-of-sample RMSE {diag.rmse_before:.3e} V ({diag.folds}-fold time-blocked cross-validation, "
           f"{diag.folds * diag.blocks_per_fold} interleaved blocks)"]
    conc = sorted(loc["concentration"].items(), key=lambda kv: -kv[1]["rms_ratio"])
    for name, c in conc[:3]:
        if c["rms_ratio"] > 1.1:
            out.append(f"residual concentrates in {name.replace('_', ' ')}: RMS x{c['rms_ratio']:.2f} of overall "
                       f"({100 * c['fraction']:.0f} % of samples) -> {HINTS.get(name, '?')}")
    corr = sorted(loc["correlation"].items(), key=lambda kv: -abs(kv[1]))
    for name, c in corr[:3]:
        if abs(c) > 0.2:
            out.append(f"residual correlates with {name.replace('_', ' ')}: r = {c:+.2f} -> {HINTS.get(name, '?')}")
    for c in diag.candidates:
        if c.accepted:
            out.append(f"step {c.step}: named {c.effect}{' (' + c.variant + ')' if c.variant else ''}: out-of-sample RMSE "
                       f"-> {c.rmse_v:.3e} V at the fit rate, lower in {100 * c.confidence:.0f} % of the folds, removes "
                       f"{100 * c.excess_share:.0f} % of the error above the noise floor")
    for name, why in diag.skipped.items():
        out.append(f"{name} not tested: {why}")
    if not diag.missing_effects:
        out.append("no catalogue effect is justified: none lowers the out-of-sample error in enough folds")
    else:
        out.append(f"validation RMSE {diag.rmse_before:.3e} -> {diag.rmse_after:.3e} V with {', '.join(diag.missing_effects)}")
    u = diag.unexplained
    if u["present"]:
        out.append(f"unexplained: structured residual {u['rms_v']:.3e} V remains (Ljung-Box p = {u['ljung_box_p']:.1e}) "
                   f"against a noise floor of {u['noise_floor_v']:.3e} V; no catalogue effect describes it")
    return out
