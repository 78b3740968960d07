"""Static elements on the voltage side: the bridge offset, linear, quadratic and cubic gains, and a span
that changes with temperature.
"""
from __future__ import annotations

import math
from typing import Any, Mapping, Optional, Self

import numpy as np
import numpy.typing as npt

from .base import (
    ElementStream,
    FloatArray,
    FloatOrArray,
    Frozen,
    FunctionStream,
    SimpleElement,
    check_keys,
    check_number,
    temperature_c_of,
)
from .drift import LaggedTemperatureStream, ThermalForwardState, lagged_temperature_c, thermal_forward_state

__all__ = ["OffsetElement", "GainElement", "NonlinearGainElement", "ThermalSensitivityElement", "PolynomialGainElement"]


class OffsetElement(Frozen):
    """Bridge output at zero force: voltage = input + voltage_v."""

    kind = "offset"
    voltage_v: float

    def __init__(self, voltage_v: float = 0.0) -> None:
        self._freeze(voltage_v=float(voltage_v))

    def forward_state(self) -> None:
        """None: the offset has no state."""
        return None

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: object = None) -> FloatArray:
        """The input plus the offset, ``x + voltage_v``."""
        return np.asarray(x, dtype=float) + self.voltage_v

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The output less the offset, ``y - voltage_v``."""
        return np.asarray(y, dtype=float) - self.voltage_v

    def streaming(self) -> ElementStream:
        """The per-sample inverse, ``value - voltage_v``."""
        return OffsetStream(self)

    def to_dict(self) -> dict[str, Any]:
        """The offset as a model-file mapping."""
        return {"type": self.kind, "voltage_v": self.voltage_v}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The offset from a model-file mapping."""
        check_keys(cls.kind, d, ("voltage_v",))
        return cls(check_number(cls.kind, "voltage_v", d["voltage_v"], positive=False))


class OffsetStream:
    def __init__(self, element: OffsetElement) -> None:
        self.voltage_v = element.voltage_v

    def reset(self) -> None:
        """Nothing to forget: the offset has no state."""

    def step(self, t_s: float, value: float, aux: Optional[Mapping[str, Any]] = None) -> float:
        """The offset element's input for its output ``value``."""
        return value - self.voltage_v




class GainElement(SimpleElement):
    """Linear gain: y = gain * x (e.g. a thin-film sensor's kappa, V/N, seed 002)."""

    kind = "gain"
    PARAMS = (("gain", True),)
    gain: float

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: object = None) -> FloatArray:
        """The input times the gain, ``gain * x``."""
        return self.gain * np.asarray(x, dtype=float)

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The output divided by the gain, ``y / gain``."""
        return np.asarray(y, dtype=float) / self.gain

    def streaming(self) -> ElementStream:
        """The per-sample inverse, ``value / gain``."""
        g = self.gain
        return FunctionStream(lambda t_s, y, aux=None: y / g)


class NonlinearGainElement(SimpleElement):
    """Static nonlinearity of the bridge gain: y = x + quadratic_per_v * x**2 (volts in, volts out).

    Inverted with the root nearest x, written as 2y / (1 + sqrt(1 + 4 q y))
    (no cancellation when q is small); where 1 + 4 q y < 0 the model has no
    inverse and the square root is taken as 0: the inverse goes on past the
    vertex with slope 2, continuous and monotone rather than saturating.
    """

    kind = "nonlinear_gain"
    PARAMS = (("quadratic_per_v", False),)
    quadratic_per_v: float

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: object = None) -> FloatArray:
        """The bent curve ``x + quadratic_per_v * x**2``."""
        x = np.asarray(x, dtype=float)
        y: FloatArray = x + self.quadratic_per_v * x * x
        return y

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The root nearest ``y``, ``2 y / (1 + sqrt(1 + 4 q y))``."""
        y = np.asarray(y, dtype=float)
        disc = np.sqrt(np.clip(1.0 + 4.0 * self.quadratic_per_v * y, 0.0, None))
        return 2.0 * y / (1.0 + disc)

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`."""
        q = self.quadratic_per_v
        return FunctionStream(lambda t_s, y, aux=None: 2.0 * y / (1.0 + math.sqrt(max(1.0 + 4.0 * q * y, 0.0))))



#: The least span factor 1 + c (T - T_ref) the inverse divides by: a temperature far outside the calibrated range
#: must not turn the division into a huge gain.
_MIN_SPAN_FACTOR = 0.2


def span_factor(coefficient_per_c: float, curvature_per_c2: float, departure_c: FloatOrArray) -> FloatOrArray:
    """The span factor 1 + c dT + q dT^2 at a temperature departure ``departure_c`` [degC]."""
    return 1.0 + departure_c * (coefficient_per_c + curvature_per_c2 * departure_c)


class ThermalSensitivityElement(SimpleElement):
    """A span that changes with temperature: y = x (1 + c dT + q dT^2), dT = T - reference_c, c =
    ``span_coefficient_per_c`` and q = ``span_curvature_per_c2`` (optional, 0: a span coefficient that itself changes
    with temperature).

    The load cell datasheets' "temperature effect on sensitivity", beside the zero's
    (:class:`ThermalDriftElement`). T comes from ``aux['temperature_c']``; without it T is
    taken as the reference (no correction). With ``thermal_tau_s`` > 0 the span follows the
    temperature through a first-order lag of that time constant (the gauges warm after the
    thermometer), settled at the first temperature. The inverse divides by the span factor, held at
    least ``_MIN_SPAN_FACTOR`` (0.2) so a temperature far outside the calibration never
    multiplies the force by more than 5.
    """

    kind = "thermal_sensitivity"
    PARAMS = (("span_coefficient_per_c", False), ("reference_c", False))
    OPTIONAL = {"thermal_tau_s": 0.0, "span_curvature_per_c2": 0.0}
    SIGNED = frozenset({"span_curvature_per_c2"})
    span_coefficient_per_c: float
    reference_c: float
    thermal_tau_s: float
    span_curvature_per_c2: float

    def _factor(self, t_s: npt.ArrayLike, n: int, aux: Optional[Mapping[str, Any]],
                state: Optional[ThermalForwardState] = None) -> FloatOrArray:
        temp = temperature_c_of(aux, n)
        if temp is not None and self.thermal_tau_s > 0.0:
            temp = lagged_temperature_c(t_s, temp, self.thermal_tau_s, state)
        if temp is None:
            return 1.0
        return np.maximum(span_factor(self.span_coefficient_per_c, self.span_curvature_per_c2, temp - self.reference_c),
                          _MIN_SPAN_FACTOR)

    def forward_state(self) -> Optional[ThermalForwardState]:
        """A fresh lag state for block-wise :meth:`forward` runs (None without a lag)."""
        return thermal_forward_state() if self.thermal_tau_s > 0.0 else None

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[ThermalForwardState] = None) -> FloatArray:
        """The input scaled by the span factor at each sample's (lagged) temperature (unchanged without one)."""
        x = np.asarray(x, dtype=float)
        return x * self._factor(t_s, x.size, aux, state)

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The output divided by the span factor (unchanged without a temperature)."""
        y = np.asarray(y, dtype=float)
        return y / self._factor(t_s, y.size, aux)

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`; a sample without ``aux['temperature_c']`` passes unchanged."""
        c, q, ref = self.span_coefficient_per_c, self.span_curvature_per_c2, self.reference_c
        lag = LaggedTemperatureStream(self.thermal_tau_s) if self.thermal_tau_s > 0.0 else None

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
            temp = None if not aux else aux.get("temperature_c")
            if temp is None:
                return y
            if lag is not None:
                temp = lag.update(t_s, temp)
            return float(y / max(float(span_factor(c, q, temp - ref)), _MIN_SPAN_FACTOR))

        return FunctionStream(step, lag.reset if lag is not None else lambda: None)


class PolynomialGainElement(SimpleElement):
    """Static nonlinearity of the bridge gain up to the fourth power (V in, V out):
    y = x + quadratic_per_v x**2 + cubic_per_v2 x**3 + quartic_per_v3 x**4.

    Describes polynomial and saturating (tanh, exponential-approach) gain curves
    over a sensor's range. Inverted per sample by Newton's method from x = y
    (16 iterations, the slope kept away from zero); where the curve is not
    monotone the last iterate is returned.
    """

    kind = "polynomial_gain"
    PARAMS = (("quadratic_per_v", False), ("cubic_per_v2", False), ("quartic_per_v3", False))
    quadratic_per_v: float
    cubic_per_v2: float
    quartic_per_v3: float

    def _poly(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        q, c, d = self.quadratic_per_v, self.cubic_per_v2, self.quartic_per_v3
        return x + x * x * (q + x * (c + x * d)), 1.0 + x * (2.0 * q + x * (3.0 * c + 4.0 * d * x))

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: object = None) -> FloatArray:
        """The curve ``x + q x**2 + c x**3 + d x**4``."""
        return self._poly(np.asarray(x, dtype=float))[0]

    def _invert(self, y: FloatArray) -> FloatArray:
        x = np.array(y, dtype=float, copy=True)
        with np.errstate(all="ignore"):
            for _ in range(16):
                fx, slope = self._poly(x)
                slope = np.where(np.abs(slope) < 0.05, np.copysign(0.05, slope + 0.0), slope)
                x = x - (fx - y) / slope
        return np.where(np.isfinite(x), x, y)

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The input for each ``y`` by 16 Newton steps from ``x = y``."""
        return self._invert(np.asarray(y, dtype=float))

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`."""
        return FunctionStream(lambda t_s, y, aux=None: float(self._invert(np.array([y]))[0]))
