"""How much a sensor chain's inverse amplifies white noise on the bridge output.

The compensation runs a chain backward, sample by sample: whatever noise the
bridge voltage carries reaches the haptic master multiplied by the inverse's
gain at the frequencies the noise occupies. White noise covers everything up
to the Nyquist frequency, so an inverse that keeps rising with frequency (the
exact inverse of a lag, of a pole pair, of a very short retardation) turns
millivolts into newtons. :func:`backward_noise_gain` measures that gain the
way the runtime meets it: it runs the chain's own :meth:`SensorChain.backward`
on white noise about the rest point, at the rate the samples arrive, so every
element, linear or not, is judged by what it does rather than by a formula
each element would have to repeat.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np
from scipy import signal

from .chain import (BridgeHysteresisElement, OffsetElement, SensorChain, ThermalDriftElement, ThermalLagElement,
                    ThermalSensitivityElement, ViscoelasticElement)

__all__ = ["NoiseGain", "backward_noise_gain", "white_noise_gain"]

#: Samples of the white-noise probe (a power of two: whole Welch segments).
PROBE_SAMPLES = 8192
#: RMS of the probe [V]: a bridge's noise, small enough that a hysteresis or a gain curve is probed about its rest
#: point, large against float64 rounding.
PROBE_RMS_V = 1e-3
#: Frequencies of the reported response, log-spaced from the lowest Welch bin to Nyquist.
RESPONSE_POINTS = 24


@dataclass(frozen=True)
class NoiseGain:
    """The noise gain of a chain's inverse at one sample rate.

    Attributes
    ----------
    rate_hz : float
        Sample rate of the probe [Hz].
    gain_n_per_v : float
        Output force RMS per input voltage RMS of white noise at ``rate_hz`` [N/V].
    frequency_hz : tuple of float
        Frequencies of ``response_n_per_v`` [Hz], up to Nyquist.
    response_n_per_v : tuple of float
        Magnitude of the inverse's frequency response there [N/V] (cross-spectral estimate).
    element : str
        Kind of the element that amplifies the noise most (the core's kind when no other element adds to it).
    element_factor : float
        The chain's gain over the gain of the chain without that element (1.0 for the core).
    """

    rate_hz: float
    gain_n_per_v: float
    frequency_hz: tuple[float, ...]
    response_n_per_v: tuple[float, ...]
    element: str
    element_factor: float

    def force_noise_n(self, voltage_noise_v: float) -> float:
        """Force noise at the master for white bridge noise of RMS ``voltage_noise_v`` [V], in N RMS."""
        return self.gain_n_per_v * float(voltage_noise_v)

    def to_dict(self) -> dict[str, Any]:
        """Plain data for JSON and model-file provenance."""
        return {"rate_hz": self.rate_hz, "gain_n_per_v": self.gain_n_per_v, "element": self.element,
                "element_factor": self.element_factor,
                "frequency_hz": [round(f, 6) for f in self.frequency_hz],
                "response_n_per_v": [float(f"{r:.6g}") for r in self.response_n_per_v]}


def _reference_temperature(chain: SensorChain) -> Optional[float]:
    for element in chain.elements:
        if isinstance(element, (ThermalDriftElement, ThermalLagElement, ThermalSensitivityElement)):
            return float(element.reference_c)
    return None


def _response(chain: SensorChain, t_s: np.ndarray, noise_v: np.ndarray, aux: Optional[dict[str, np.ndarray]]) -> np.ndarray:
    """The chain's force response to ``noise_v`` about its rest point (the rest run subtracted), N."""
    rest = np.full(t_s.size, chain.offset_v)
    with np.errstate(all="ignore"):  # a degenerate inverse shows as a non-finite gain, reported, not raised
        out = chain.backward(t_s, rest + noise_v, aux) - chain.backward(t_s, rest, aux)
    if not np.all(np.isfinite(out)):
        return np.full(t_s.size, np.inf)
    return np.asarray(signal.detrend(out))  # a slow walk of an integrating element is not noise at the master


def _gain(out: np.ndarray, noise_v: np.ndarray) -> float:
    """Output RMS per input RMS (inf for a non-finite response)."""
    if not np.all(np.isfinite(out)):
        return float("inf")
    return float(np.sqrt(np.mean(out ** 2)) / np.sqrt(np.mean(noise_v ** 2)))


def _probe(chain: SensorChain, rate_hz: float, seed: int) -> tuple[np.ndarray, np.ndarray, Optional[dict[str, np.ndarray]]]:
    """Sample times [s], white noise [V] and the auxiliary signals (the thermal reference) of the probe."""
    if not (np.isfinite(rate_hz) and rate_hz > 0):
        raise ValueError(f"rate_hz must be positive and finite, got {rate_hz!r}")
    t_s = np.arange(PROBE_SAMPLES) / float(rate_hz)
    noise_v = PROBE_RMS_V * np.random.default_rng(seed).standard_normal(PROBE_SAMPLES)
    temp_c = _reference_temperature(chain)
    return t_s, noise_v, None if temp_c is None else {"temperature_c": np.full(PROBE_SAMPLES, temp_c)}


def white_noise_gain(chain: SensorChain, rate_hz: float, seed: int = 0) -> float:
    """The gain of :func:`backward_noise_gain` alone [N/V RMS/RMS]: one backward run, no response or attribution."""
    t_s, noise_v, aux = _probe(chain, rate_hz, seed)
    return _gain(_response(chain, t_s, noise_v, aux), noise_v)


def backward_noise_gain(chain: SensorChain, rate_hz: float, seed: int = 0) -> NoiseGain:
    """Measure how much ``chain``'s inverse amplifies white bridge noise at ``rate_hz``.

    Parameters
    ----------
    chain : SensorChain
        The model the compensation runs backward.
    rate_hz : float
        Sample rate of the bridge voltage [Hz] (the noise spans 0 .. rate_hz / 2).
    seed : int, optional
        Seed of the probe noise (the figure is reproducible for a given chain and rate).

    Returns
    -------
    NoiseGain
        The gain [N/V RMS/RMS], the response's magnitude over frequency, and the element that amplifies most.
    """
    t_s, noise_v, aux = _probe(chain, rate_hz, seed)
    out = _response(chain, t_s, noise_v, aux)
    gain = _gain(out, noise_v)
    if np.isfinite(gain):
        freq, pxy = signal.csd(noise_v, out, fs=rate_hz, nperseg=512)
        _, pxx = signal.welch(noise_v, fs=rate_hz, nperseg=512)
        at = np.geomspace(freq[1], freq[-1], RESPONSE_POINTS)
        response = np.interp(at, freq[1:], np.abs(pxy[1:] / pxx[1:]))
    else:
        at, response = np.geomspace(rate_hz / 512, rate_hz / 2, RESPONSE_POINTS), np.full(RESPONSE_POINTS, np.inf)
    # the element that amplifies most: the chain's gain over the gain without it (a unit-gain element's removal
    # leaves a valid chain; the core and the offset are what the force is made of, never removed)
    core = chain.viscoelastic
    element, factor = (type(core).__name__.lower() if core is not None else "chain"), 1.0
    for i, e in enumerate(chain.elements):
        if isinstance(e, (ViscoelasticElement, OffsetElement)):
            continue
        if isinstance(e, BridgeHysteresisElement):  # the plays beside the core: judged against the core alone
            rest = SensorChain([e.core if j == i else x for j, x in enumerate(chain.elements)])
        else:
            rest = SensorChain([x for j, x in enumerate(chain.elements) if j != i])
        without = _gain(_response(rest, t_s, noise_v, aux), noise_v)
        ratio = gain / without if without > 0 else float("inf")
        if ratio > factor * 1.05:  # 5 %: a probe's own scatter does not name an element
            element, factor = e.kind, ratio
    return NoiseGain(float(rate_hz), gain, tuple(float(f) for f in at), tuple(float(r) for r in response),
                     element, float(factor))
