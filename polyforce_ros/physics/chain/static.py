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
    thermometer), settled at the first temperature; ``direct_span_coefficient_per_c`` (optional, 0) then adds
    d (T - reference_c) with the temperature as measured, beside the lagged terms: a span that answers the
    temperature's rate as well as its level (c dT_lag + d dT, with d = -c, is c times the gradient T - lag(T)
    between the thermometer and the gauges). The inverse divides by the span factor, held at
    least ``_MIN_SPAN_FACTOR`` (0.2) so a temperature far outside the calibration never
    multiplies the force by more than 5.
    """

    kind = "thermal_sensitivity"
    PARAMS = (("span_coefficient_per_c", False), ("reference_c", False))
    OPTIONAL = {"thermal_tau_s": 0.0, "span_curvature_per_c2": 0.0, "direct_span_coefficient_per_c": 0.0}
    SIGNED = frozenset({"span_curvature_per_c2", "direct_span_coefficient_per_c"})
    span_coefficient_per_c: float
    reference_c: float
    thermal_tau_s: float
    span_curvature_per_c2: float
    direct_span_coefficient_per_c: float

    def _span(self, lagged_c: FloatOrArray, direct_c: FloatOrArray) -> FloatOrArray:
        """The span factor at a (lagged) temperature and the temperature as measured [degC], held at least
        ``_MIN_SPAN_FACTOR``."""
        factor = span_factor(self.span_coefficient_per_c, self.span_curvature_per_c2, lagged_c - self.reference_c)
        return np.maximum(factor + self.direct_span_coefficient_per_c * (direct_c - self.reference_c), _MIN_SPAN_FACTOR)

    def _factor(self, t_s: npt.ArrayLike, n: int, aux: Optional[Mapping[str, Any]],
                state: Optional[ThermalForwardState] = None) -> FloatOrArray:
        direct = temperature_c_of(aux, n)
        if direct is None:
            return 1.0
        lagged = lagged_temperature_c(t_s, direct, self.thermal_tau_s, state) if self.thermal_tau_s > 0.0 else None
        return self._span(direct if lagged is None else lagged, direct)

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
        lag = LaggedTemperatureStream(self.thermal_tau_s) if self.thermal_tau_s > 0.0 else None

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
            temp = None if not aux else aux.get("temperature_c")
            if temp is None:
                return y
            lagged = lag.update(t_s, temp) if lag is not None else temp
            return float(y / float(self._span(lagged, temp)))

        return FunctionStream(step, lag.reset if lag is not None else lambda: None)


#: The farthest input [V] the polynomial gain's inverse looks for on a branch without an end (far beyond any bridge
#: output), and its most iterations (Newton's converge in a few; a bisection of the whole reach in 64).
_REACH_V = 1e3
_INVERSE_STEPS = 64


class PolynomialGainElement(SimpleElement):
    """Static nonlinearity of the bridge gain up to the fourth power (V in, V out):
    y = x + quadratic_per_v x**2 + cubic_per_v2 x**3 + quartic_per_v3 x**4.

    Describes polynomial and saturating (tanh, exponential-approach) gain curves
    over a sensor's range. Inverted per sample on the curve's rising branch
    through zero, between the stationary points nearest zero on either side
    (``branch_v``): Newton's method from x = y, safeguarded by bisection so that
    each iterate stays on the branch and brackets the root. A reading beyond the branch
    is inverted to the branch's end: a fitted curve that turns over near the top
    of its range saturates the force there instead of jumping to another branch.
    """

    kind = "polynomial_gain"
    PARAMS = (("quadratic_per_v", False), ("cubic_per_v2", False), ("quartic_per_v3", False))
    quadratic_per_v: float
    cubic_per_v2: float
    quartic_per_v3: float
    branch_v: tuple[float, float]
    _bracket_v: tuple[float, float, float, float]

    def __init__(self, **values: float) -> None:
        super().__init__(**values)
        self._freeze(branch_v=self._rising_branch())
        # the inverse's search bracket (the branch within +-_REACH_V) and the readings at its ends, made once: the
        # inverse runs per sample
        low, high = max(self.branch_v[0], -_REACH_V), min(self.branch_v[1], _REACH_V)
        y_low, y_high = self._poly(np.array([low, high]))[0]
        self._freeze(_bracket_v=(low, high, float(y_low), float(y_high)))

    def _rising_branch(self) -> tuple[float, float]:
        """The input range [V] around zero on which the curve rises: between the real roots of its slope
        1 + 2 q x + 3 c x**2 + 4 d x**3 nearest zero where the slope turns negative (the slope is 1 at zero; at a
        root where it only touches zero the curve rises on)."""
        q, c, d = self.quadratic_per_v, self.cubic_per_v2, self.quartic_per_v3
        slope = np.array([4.0 * d, 3.0 * c, 2.0 * q, 1.0])
        # a leading power that stays negligible within the inverse's reach only puts far roots (and rounding) there
        size = np.abs(slope) * _REACH_V ** np.arange(3, -1, -1)
        while slope.size > 1 and size[0] < 1e-12 * size.max():
            slope, size = slope[1:], size[1:]
        roots = np.roots(slope)
        real = np.sort(roots.real[np.abs(roots.imag) <= 1e-6 * np.maximum(1.0, np.abs(roots.real))])
        ends = []
        for side in (real[real < 0.0][::-1], real[real > 0.0]):  # outward from zero
            end = math.inf
            for i, root in enumerate(side):
                beyond = 0.5 * (root + side[i + 1]) if i + 1 < side.size else root + math.copysign(max(1.0, abs(root)), root)
                if np.polyval(slope, beyond) < 0.0:
                    end = abs(float(root))
                    break
            ends.append(end)
        return -ends[0], ends[1]

    def _poly(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        q, c, d = self.quadratic_per_v, self.cubic_per_v2, self.quartic_per_v3
        return x + x * x * (q + x * (c + x * d)), 1.0 + x * (2.0 * q + x * (3.0 * c + 4.0 * d * x))

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: object = None) -> FloatArray:
        """The curve ``x + q x**2 + c x**3 + d x**4``."""
        return self._poly(np.asarray(x, dtype=float))[0]

    def _invert(self, y: FloatArray) -> FloatArray:
        # Newton's method safeguarded by bisection on a bracket of the root (the branch's ends, or +-_REACH_V where
        # it has none): a step that leaves the bracket, or a slope that is not rising, bisects instead. A reading
        # beyond the branch is its end; an infinite one on a side without an end stays infinite.
        shape, y = np.shape(y), np.atleast_1d(y)
        low, high, y_low, y_high = self._bracket_v
        x = np.where(y >= y_high, high, np.where(y <= y_low, low, y))
        x[np.isposinf(y) & math.isinf(self.branch_v[1])] = np.inf
        x[np.isneginf(y) & math.isinf(self.branch_v[0])] = -np.inf
        inside = (y > y_low) & (y < y_high)
        if inside.any():
            x[inside] = self._on_branch(y[inside], low, high)
        return np.where(np.isnan(y), y, x).reshape(shape)  # no reading, no input

    def _on_branch(self, y: FloatArray, low: float, high: float) -> FloatArray:
        a, b = np.full(y.shape, low), np.full(y.shape, high)
        x = np.clip(y, low, high)
        last_step = b - a
        with np.errstate(all="ignore"):
            for _ in range(_INVERSE_STEPS):
                fx, slope = self._poly(x)
                a, b = np.where(fx < y, x, a), np.where(fx > y, x, b)
                newton = x - (fx - y) / np.where(slope > 0.0, slope, np.nan)
                # Newton's step is taken inside the bracket and when it at least halves the one before (else it
                # may cycle about an inflection); otherwise the bracket is halved
                take = (newton > a) & (newton < b) & (np.abs(newton - x) <= 0.5 * np.abs(last_step))
                stepped = np.where(take, newton, 0.5 * (a + b))
                last_step = stepped - x
                x = stepped
                if bool(np.all(np.abs(last_step) <= 1e-12 * (1.0 + np.abs(x)))):
                    break
        return x

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The input for each ``y`` on the rising branch through zero (its end for a ``y`` beyond it)."""
        return self._invert(np.asarray(y, dtype=float))

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`."""
        return FunctionStream(lambda t_s, y, aux=None: float(self._invert(np.array([y]))[0]))
