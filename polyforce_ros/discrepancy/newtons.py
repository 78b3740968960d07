"""The diagnosis judged where the user feels it: the compensated force at the haptic master.

A model can predict the bridge voltage well and still be a dangerous compensator:
the compensation runs it backward, and an inverse that rises with frequency
turns bridge noise into force. Every diagnosis therefore also runs its models
backward (:meth:`SensorChain.backward`) on the record, its time drifts applied
from the record's first sample (the runtime applies them only with
``apply_time_drifts``; a saved model that holds one is also judged without
them, as the runtime runs it), and judges their noise gain on the chain the
runtime runs (:func:`~polyforce_ros.runtime.compensator.runtime_chain`):

* :func:`force_quality`: the compensated force of the record's left-out blocks
  (each block compensated by the model fitted without it) against the reference,
  as RMSE and largest error in N and in % of full scale and R², with the
  inverse's white-noise gain (:func:`~polyforce_ros.physics.noise_gain.backward_noise_gain`);
* :func:`with_safe_bandwidth`: each sensor-lag element gets an explicit
  bandwidth, its filter time chosen by the compensated force's own error on the
  record (a Wiener-like balance: a longer filter leaves more lag, a shorter one
  passes more noise) among the filters whose noise gain stays within the
  runtime's ``max_noise_gain``.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Optional, Sequence

import numpy as np

from ..physics.chain import FrictionElement, SensorChain, SensorLagElement
from ..physics.noise_gain import NoiseGain, backward_noise_gain, white_noise_gain
from ..runtime import CompensatorConfig
from ..runtime.compensator import runtime_chain

__all__ = ["ForceQuality", "force_quality", "with_safe_bandwidth", "with_filter", "fold_chains", "rate_of", "FILTER_FACTORS",
           "with_friction_deadband", "DEADBAND_SIGMAS", "with_friction_share", "FRICTION_INVERSE_SHARES", "runtime_guard"]

#: Filter times tried for a lag's inverse, as multiples of each stage's own time constant (0: the exact inverse).
#: A saved model's noise gain stays this far inside ``max_noise_gain``: the probe's estimate scatters by a few
#: percent with its noise draw and the record's noise is not exactly white, and the node must not refuse, nor a
#: hand feel, what diagnose saved at the limit.
SAVE_MARGIN = 0.9
FILTER_FACTORS = (0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.25, 1.5, 2.0, 2.5)


@dataclass(frozen=True)
class ForceQuality:
    """Compensated force of a model on a record's left-out blocks, against the reference.

    Attributes
    ----------
    rmse_n, max_error_n : float
        RMS and largest absolute error [N].
    r2 : float
        Coefficient of determination against the reference force.
    full_scale_n : float
        The reference's span [N] (the % figures are of it).
    noise_gain : NoiseGain
        White-noise gain of the model's inverse at the record's rate.
    latency_s : float
        The model's stated latency [s]: the reference was shifted by it before the comparison (a delay cannot
        be undone; it is reported, not scored as error).
    force_n : (n,) ndarray
        The compensated force of each sample [N] (from the model that left its block out).
    """

    rmse_n: float
    max_error_n: float
    r2: float
    full_scale_n: float
    noise_gain: NoiseGain
    latency_s: float = 0.0
    force_n: np.ndarray = field(repr=False, compare=False, default_factory=lambda: np.zeros(0))

    def to_dict(self) -> dict[str, Any]:
        """Plain data (JSON, model-file provenance)."""
        fs = max(self.full_scale_n, 1e-12)
        return {"rmse_n": self.rmse_n, "max_error_n": self.max_error_n, "r2": self.r2,
                "rmse_percent_full_scale": 100.0 * self.rmse_n / fs,
                "max_error_percent_full_scale": 100.0 * self.max_error_n / fs, "full_scale_n": self.full_scale_n,
                "latency_s": self.latency_s,
                "noise_gain_n_per_v": self.noise_gain.gain_n_per_v, "noise_gain": self.noise_gain.to_dict()}


def _aux(temperature_c: Optional[np.ndarray]) -> Optional[dict[str, np.ndarray]]:
    return None if temperature_c is None else {"temperature_c": np.asarray(temperature_c, dtype=float)}


def _errors(force_n: np.ndarray, reference_n: np.ndarray) -> tuple[float, float, float]:
    err = force_n - reference_n
    if not np.all(np.isfinite(err)):
        return float("inf"), float("inf"), float("-inf")
    ss_tot = float(np.sum((reference_n - reference_n.mean()) ** 2))
    r2 = 1.0 - float(np.sum(err ** 2)) / ss_tot if ss_tot > 0 else float("nan")
    return float(np.sqrt(np.mean(err ** 2))), float(np.max(np.abs(err))), r2


def rate_of(t_s: np.ndarray) -> float:
    """The record's sample rate [Hz], from its median stamp spacing."""
    return 1.0 / float(np.median(np.diff(t_s)))


def force_quality(chains: Sequence[SensorChain], fold: np.ndarray, t_s: np.ndarray, voltage_v: np.ndarray,
                  reference_n: np.ndarray, temperature_c: Optional[np.ndarray] = None,
                  noise_chain: Optional[SensorChain] = None) -> ForceQuality:
    """Compensate each left-out block with the model fitted without it and score the force against the reference.

    Parameters
    ----------
    chains : sequence of SensorChain
        One model per fold (``chains[b]`` fitted with fold ``b`` left out).
    fold : (n,) ndarray of int
        The fold of each sample.
    t_s, voltage_v, reference_n : (n,) ndarray
        The record: times [s], bridge voltage [V], reference force [N].
    temperature_c : (n,) ndarray, optional
        Temperature [degC] for thermal elements.
    noise_chain : SensorChain, optional
        The model whose noise gain and latency are reported (default ``chains[0]``): the one that is saved.

    Returns
    -------
    ForceQuality
    """
    force = np.empty_like(np.asarray(voltage_v, dtype=float))
    aux = _aux(temperature_c)
    for b, chain in enumerate(chains):
        rows = fold == b
        if rows.any():
            with np.errstate(all="ignore"):
                force[rows] = chain.backward(t_s, voltage_v, aux)[rows]
    reported = noise_chain if noise_chain is not None else chains[0]
    latency_s = reported.latency_s
    reference_n = np.asarray(reference_n, dtype=float)
    if latency_s > 0.0:
        reference_n = np.interp(t_s - latency_s, t_s, reference_n, left=reference_n[0])
    rmse, worst, r2 = _errors(force, reference_n)
    gain = backward_noise_gain(reported, rate_of(t_s))
    return ForceQuality(rmse, worst, r2, float(np.ptp(reference_n)), gain, latency_s, force)


def with_filter(chain: SensorChain, factor: float, order: int = 1) -> SensorChain:
    """``chain`` with every sensor-lag inverse filtered at ``factor`` times the stage's time constant, with a
    roll-off of ``order`` 1 or 2 (factor 0: the exact inverse)."""
    return SensorChain([SensorLagElement(tau_s=e.tau_s, noise_filter_tau_s=factor * e.tau_s,
                                         noise_filter_order=float(order) if factor > 0 else 1.0)
                        if isinstance(e, SensorLagElement) else e for e in chain.elements])


def with_safe_bandwidth(chain: SensorChain, t_s: np.ndarray, voltage_v: np.ndarray, reference_n: np.ndarray,
                        temperature_c: Optional[np.ndarray] = None,
                        max_noise_gain: float = CompensatorConfig.max_noise_gain,
                        rates_hz: Sequence[float] = ()) -> tuple[SensorChain, dict[str, Any]]:
    """Give every sensor-lag element of ``chain`` the inverse bandwidth that compensates the record best in newtons.

    The filter time of each stage is ``factor * tau_s``, one factor of :data:`FILTER_FACTORS` and one roll-off
    order (1 or 2) for all stages: the pair with the lowest force RMSE against the reference (the delay a filter
    adds counts as error, as the hand feels it; only a transport delay, which no inverse undoes, is aligned)
    among those whose noise gain stays within
    :data:`SAVE_MARGIN` of ``max_noise_gain`` at the record's rate and at each of ``rates_hz`` (the runtime's rate);
    when none does,
    the longest filter.

    Returns
    -------
    chain : SensorChain
        The chain with its lag inverses bandwidth-limited (``chain`` itself when it holds no lag).
    choice : dict
        ``filter_factor``, ``filter_order``, ``added_delay_s`` (the delay the compensated force keeps),
        ``noise_gain_n_per_v`` at each rate checked, and ``force_rmse_n`` per (order, factor) tried.
    """
    if not any(isinstance(e, SensorLagElement) for e in chain.elements):
        return chain, {}
    rates = [rate_of(t_s), *rates_hz]
    aux = _aux(temperature_c)
    reference_n = np.asarray(reference_n, dtype=float)
    late = np.interp(t_s - chain.latency_s, t_s, reference_n, left=reference_n[0])  # the transport delay's
    tried: dict[tuple[int, float], float] = {}
    gains: dict[tuple[int, float], list[float]] = {}
    best: Optional[tuple[int, float]] = None
    for key in [(1, 0.0)] + [(order, f) for order in (1, 2) for f in FILTER_FACTORS if f > 0]:
        candidate = with_filter(chain, key[1], key[0])
        gains[key] = [white_noise_gain(runtime_chain(candidate), r) for r in rates]  # as the runtime runs it
        with np.errstate(all="ignore"):
            tried[key] = _errors(candidate.backward(t_s, voltage_v, aux), late)[0]
        if max(gains[key]) <= SAVE_MARGIN * max_noise_gain and (best is None or tried[key] < tried[best]):
            best = key
    order, factor = best if best is not None else (2, FILTER_FACTORS[-1])
    out = with_filter(chain, factor, order)
    return out, {"filter_factor": factor, "filter_order": order, "added_delay_s": out.latency_s,
                 "noise_gain_n_per_v": dict(zip((f"{r:g} Hz" for r in rates), gains[(order, factor)])),
                 "within_max_noise_gain": best is not None, "max_noise_gain": max_noise_gain,
                 "force_rmse_n": {f"order {k[0]} x{k[1]:g}": v for k, v in tried.items()}}


#: The friction inverse's dead band, in standard deviations of the force noise that the bridge noise makes through
#: the core's instantaneous stiffness: white noise leaves a 3-sigma band in 0.3 % of its samples.
DEADBAND_SIGMAS = 3.0


def runtime_guard(chain: SensorChain, record_rate_hz: float) -> dict[str, Any]:
    """Whether the runtime with its default guard (``max_noise_gain`` judged at ``noise_gain_rate_hz``) accepts
    ``chain``, and its noise gain at that rate and at the record's [N/V]. A stiff sensor (more than
    ``max_noise_gain`` newtons per volt of bridge output) is refused for its core alone: the node then needs a
    raised ``max_noise_gain``, which the diagnosis says rather than saving a model the node silently refuses."""
    limit, runtime_hz = CompensatorConfig.max_noise_gain, CompensatorConfig.noise_gain_rate_hz
    gains = {f"{rate:g}": backward_noise_gain(runtime_chain(chain), rate).gain_n_per_v
             for rate in sorted({float(runtime_hz), float(record_rate_hz)})}
    return {"max_noise_gain": limit, "noise_gain_rate_hz": runtime_hz, "noise_gain_n_per_v": gains,
            "accepted": gains[f"{runtime_hz:g}"] <= limit}


#: Shares of a friction the inverse adds back, tried by the compensated force (:func:`with_friction_share`).
FRICTION_INVERSE_SHARES = (1.0, 0.5, 0.0)


def with_friction_share(chain: SensorChain, share: float) -> SensorChain:
    """``chain`` with every friction element's inverse adding back ``share`` of the friction; ``chain`` itself when
    it holds none."""
    if not any(isinstance(e, FrictionElement) for e in chain.elements):
        return chain
    return SensorChain([e.with_inverse_share(share) if isinstance(e, FrictionElement) else e for e in chain.elements])


def with_friction_deadband(chain: SensorChain, noise_v: float) -> SensorChain:
    """Give every friction element's inverse a dead band that white bridge noise of RMS ``noise_v`` [V] rarely
    crosses (:data:`DEADBAND_SIGMAS` times that noise in newtons, at most the stiction band itself); ``chain`` itself
    when it holds no friction or no core."""
    core = chain.viscoelastic
    if core is None or not any(isinstance(e, FrictionElement) for e in chain.elements):
        return chain
    noise_n = float(noise_v) * core.relaxation().g0_n_per_v
    return SensorChain([e.with_deadband(min(DEADBAND_SIGMAS * noise_n, e.radius_n)) if isinstance(e, FrictionElement)
                        else e for e in chain.elements])


def fold_chains(build: Callable[[dict[str, float]], SensorChain], names: Sequence[str], coef_folds: Sequence[np.ndarray],
                finish: Callable[[SensorChain], SensorChain] = lambda c: c) -> list[SensorChain]:
    """One chain per fold from that fold's coefficients (``build(coef_map)``), each passed through ``finish``."""
    return [finish(build(dict(zip(names, c)))) for c in coef_folds]
