"""Offset drifts: with temperature (immediate or lagged) and with time (linear, polynomial, exponential,
spline, jumps).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Mapping, Optional, Self, TypedDict

import numpy as np
import numpy.typing as npt

from ..expconv import ExpConvState, exp_convolve
from .base import (
    ElementStream,
    FloatArray,
    FloatOrArray,
    FunctionStream,
    ModelError,
    Numbers,
    SimpleElement,
    abscissae_and_values,
    check_keys,
    check_number,
    temperature_c_of,
)

if TYPE_CHECKING:  # for annotations only: at run time scipy.interpolate loads when first used
    from scipy.interpolate import CubicSpline

__all__ = ["ThermalDriftElement", "OffsetDriftElement", "ThermalLagElement", "ExponentialDriftElement",
           "PolynomialDriftElement", "SplineDriftElement", "StepDriftElement", "TimeDriftElement", "ThermalForwardState",
           "thermal_forward_state",
           "lagged_temperature_c", "LaggedTemperatureStream", "thermal_zero"]


class ThermalForwardState(TypedDict):
    """Block-wise state of a temperature lag."""

    y: FloatArray  # the lag's integral state, degC * s
    t_prev: Optional[float]  # s; None before the first sample
    temp_prev: float  # degC


def thermal_forward_state() -> ThermalForwardState:
    """A fresh temperature-lag state (it settles at the first temperature it sees)."""
    return {"y": np.zeros(1), "t_prev": None, "temp_prev": 0.0}


def lagged_temperature_c(t_s: npt.ArrayLike, temp_c: Optional[FloatArray], tau_s: float,
                         state: Optional[ThermalForwardState] = None) -> Optional[FloatArray]:
    """The temperature through a first-order lag, tau_s T_lag' + T_lag = T [degC], settled at the first temperature
    (or continued from ``state``, which it updates); None without a temperature."""
    t = np.asarray(t_s, dtype=float)
    if temp_c is None or t.size == 0:
        return None
    rate = 1.0 / tau_s
    if state is None or state["t_prev"] is None:  # settled at the first temperature
        y = exp_convolve(t, temp_c, [rate], y0=[temp_c[0] * tau_s])[:, 0]
    else:
        y = exp_convolve(t, temp_c, [rate], y0=state["y"], u_prev=state["temp_prev"], t_prev_s=state["t_prev"])[:, 0]
    if state is not None:
        state["y"], state["t_prev"], state["temp_prev"] = np.array([y[-1]]), float(t[-1]), float(temp_c[-1])
    out: FloatArray = y * rate
    return out


class LaggedTemperatureStream:
    """The per-sample form of :func:`lagged_temperature_c`: ``update(t_s, temp_c)`` returns T_lag [degC], settled at
    the first temperature after a :meth:`reset`; :meth:`peek` gives it without moving the lag."""

    def __init__(self, tau_s: float) -> None:
        self.tau_s = tau_s
        self.lag = ExpConvState([1.0 / tau_s])
        self._peeked: Optional[tuple[float, float, float, float]] = None  # (t_s, temp_c, y, T_lag) of the last peek

    def reset(self) -> None:
        """Forget the history: the next temperature settles the lag."""
        self.lag.reset()
        self._peeked = None

    def peek(self, t_s: float, temp_c: float) -> float:
        """T_lag after a sample at ``t_s``, the lag not moved; an :meth:`update` with the same sample next takes the
        state computed here (one exact step per accepted sample, however often it is peeked)."""
        lag = self.lag
        if lag.t_prev_s is None:
            return float(temp_c)
        y0 = lag.y[0]
        t_prev, u_prev = lag.t_prev_s, lag.u_prev
        state = lag.update(t_s, float(temp_c))
        y = y0 if state is None else state[0]
        lag.y[0], lag.t_prev_s, lag.u_prev = y0, t_prev, u_prev
        out = y / self.tau_s
        self._peeked = None if state is None else (t_s, float(temp_c), y, out)
        return out

    def update(self, t_s: float, temp_c: float) -> float:
        """T_lag after the sample at ``t_s``."""
        lag, peeked = self.lag, self._peeked
        self._peeked = None
        if peeked is not None and peeked[0] == t_s and peeked[1] == temp_c:
            lag.y[0], lag.t_prev_s, lag.u_prev = peeked[2], t_s, float(temp_c)
            return peeked[3]
        if lag.t_prev_s is None:  # settled at the first temperature
            lag.reset([temp_c * self.tau_s])
            lag.update(t_s, float(temp_c))
            return float(temp_c)
        state = lag.update(t_s, float(temp_c))
        return float((lag.y if state is None else state)[0] / self.tau_s)


def thermal_zero(coefficient_v_per_c: float, curvature_v_per_c2: float, departure_c: FloatOrArray) -> FloatOrArray:
    """The zero's shift [V] at a departure from the reference temperature [degC]: linear plus curvature."""
    return (coefficient_v_per_c + curvature_v_per_c2 * departure_c) * departure_c


class ThermalDriftElement(SimpleElement):
    """Output that follows temperature: y = x + c (T - T_ref) + q (T - T_ref)^2, with c = ``coefficient_v_per_c``,
    q = ``curvature_v_per_c2`` (optional, 0) and T_ref = ``reference_c``.

    T comes from ``aux['temperature_c']``; without it T is taken as the
    reference (no correction), which the node reports.
    """

    kind = "thermal_drift"
    PARAMS = (("coefficient_v_per_c", False), ("reference_c", False))
    OPTIONAL = {"curvature_v_per_c2": 0.0}
    SIGNED = frozenset({"curvature_v_per_c2"})
    coefficient_v_per_c: float
    reference_c: float
    curvature_v_per_c2: float

    def _term(self, y: FloatArray, aux: Optional[Mapping[str, Any]]) -> FloatOrArray:
        temp = temperature_c_of(aux, np.size(y))
        return 0.0 if temp is None else thermal_zero(self.coefficient_v_per_c, self.curvature_v_per_c2,
                                                     temp - self.reference_c)

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: object = None) -> FloatArray:
        """The input plus the thermal term."""
        x = np.asarray(x, dtype=float)
        return x + self._term(x, aux)

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The output less the thermal term."""
        y = np.asarray(y, dtype=float)
        return y - self._term(y, aux)

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`; a sample without ``aux['temperature_c']`` passes unchanged."""
        c, q, ref = self.coefficient_v_per_c, self.curvature_v_per_c2, self.reference_c

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
            temp = None if not aux else aux.get("temperature_c")
            return y if temp is None else y - float(thermal_zero(c, q, temp - ref))

        return FunctionStream(step)



class _DriftForwardState(TypedDict):
    t_first: Optional[float]  # s; None before the first sample


class TimeDriftElement(SimpleElement):
    """Base of the load-independent drifts: y = x + _term(t - t_first), t_first the first sample of the
    record (forward, batch backward) or after a reset (streaming); subclasses define ``_term(s)`` (V).

    A time drift describes the record it was fitted on: the runtime leaves it out unless asked
    (``apply_time_drifts``)."""

    def _term(self, s: FloatOrArray) -> FloatOrArray:
        """The drift [V] at ``s`` [s] after the first sample: a float for a float, an array for an array."""
        raise NotImplementedError(f"{type(self).__name__} defines no drift term")

    def forward_state(self) -> _DriftForwardState:
        """A fresh state for block-wise :meth:`forward` runs (no first sample yet)."""
        return {"t_first": None}

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_DriftForwardState] = None) -> FloatArray:
        """The input plus the drift at the time since the first sample."""
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        st = state if state is not None else self.forward_state()
        if st["t_first"] is None and t.size:
            st["t_first"] = float(t[0])
        return x + self._term(t - (st["t_first"] or 0.0))

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The output less the drift, the time counted from the record's first sample."""
        t, y = np.asarray(t_s, dtype=float), np.asarray(y, dtype=float)
        return y - self._term(t - t[0]) if t.size else y

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`, the time counted from the first sample after a reset."""
        first: dict[str, Optional[float]] = {"t": None}

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
            # read once into a local: mypy does not narrow first["t"] after assigning it
            t_first = first["t"]
            if t_first is None:
                t_first = first["t"] = t_s
            return y - float(self._term(t_s - t_first))

        return FunctionStream(step, lambda: first.update(t=None))


class OffsetDriftElement(TimeDriftElement):
    """Load-independent baseline drift: y = x + rate_v_per_s * (t - t_first).

    t_first is the first sample of the record (forward, batch backward) or the
    first sample after a reset (streaming); a tare therefore restarts it.
    """

    kind = "offset_drift"
    PARAMS = (("rate_v_per_s", False),)
    rate_v_per_s: float

    def _term(self, s: FloatOrArray) -> FloatOrArray:
        return self.rate_v_per_s * s



class ThermalLagElement(SimpleElement):
    """Output that follows temperature through a first-order thermal lag:
    y = x + c (T_lag - T_ref) + q (T_lag - T_ref)^2, tau_s T_lag' + T_lag = T (c, q, T_ref as
    :class:`ThermalDriftElement`).

    T comes from ``aux['temperature_c']``; the lag starts settled at the first
    temperature sample (batch, or the first after a reset when streaming).
    Without temperature there is no correction (as :class:`ThermalDriftElement`).
    """

    kind = "thermal_lag"
    PARAMS = (("coefficient_v_per_c", False), ("reference_c", False), ("tau_s", True))
    OPTIONAL = {"curvature_v_per_c2": 0.0}
    SIGNED = frozenset({"curvature_v_per_c2"})
    coefficient_v_per_c: float
    reference_c: float
    tau_s: float
    curvature_v_per_c2: float

    def _lagged(self, t_s: npt.ArrayLike, temp: Optional[FloatArray],
                state: Optional[ThermalForwardState] = None) -> Optional[FloatArray]:
        return lagged_temperature_c(t_s, temp, self.tau_s, state)

    def forward_state(self) -> ThermalForwardState:
        """A fresh lag state for block-wise :meth:`forward` runs (settles at the first temperature it sees)."""
        return thermal_forward_state()

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[ThermalForwardState] = None) -> FloatArray:
        """The input plus the lagged thermal term."""
        x = np.asarray(x, dtype=float)
        lagged = self._lagged(t_s, temperature_c_of(aux, x.size), state)
        return x if lagged is None else x + thermal_zero(self.coefficient_v_per_c, self.curvature_v_per_c2,
                                                         lagged - self.reference_c)

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The output less the lagged thermal term."""
        y = np.asarray(y, dtype=float)
        lagged = self._lagged(t_s, temperature_c_of(aux, y.size))
        return y if lagged is None else y - thermal_zero(self.coefficient_v_per_c, self.curvature_v_per_c2,
                                                         lagged - self.reference_c)

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`; the lag starts settled at the first temperature after a reset."""
        c, q, ref = self.coefficient_v_per_c, self.curvature_v_per_c2, self.reference_c
        lag = LaggedTemperatureStream(self.tau_s)

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
            temp = None if not aux else aux.get("temperature_c")
            return y if temp is None else y - float(thermal_zero(c, q, lag.update(t_s, temp) - ref))

        return FunctionStream(step, lag.reset)


class ExponentialDriftElement(TimeDriftElement):
    """Baseline drift that settles: y = x + amplitude_v * (1 - exp(-(t - t_first) / tau_s)).

    t_first as in :class:`OffsetDriftElement` (first sample, or first after a reset/tare).
    """

    kind = "exponential_drift"
    PARAMS = (("amplitude_v", False), ("tau_s", True))
    amplitude_v: float
    tau_s: float

    def _term(self, s: FloatOrArray) -> FloatOrArray:
        return self.amplitude_v * -np.expm1(-np.asarray(s, dtype=float) / self.tau_s)




class PolynomialDriftElement(TimeDriftElement):
    """Load-independent baseline drift of any smooth shape:
    y = x + rate_v_per_s * s + curvature_v_per_s2 * s**2 + cubic_v_per_s3 * s**3, s = t - t_first.

    t_first as in :class:`OffsetDriftElement` (first sample, or first after a reset/tare).
    """

    kind = "polynomial_drift"
    PARAMS = (("rate_v_per_s", False), ("curvature_v_per_s2", False), ("cubic_v_per_s3", False))
    rate_v_per_s: float
    curvature_v_per_s2: float
    cubic_v_per_s3: float

    def _term(self, s: FloatOrArray) -> FloatOrArray:
        return s * (self.rate_v_per_s + s * (self.curvature_v_per_s2 + s * self.cubic_v_per_s3))


class StepDriftElement(TimeDriftElement):
    """Load-independent zero that jumps (a zero shift: a charge, a splash, a slipping clamp, a switched ground
    loop), each jump settling part of the way back:
    y = x + sum_i H(s - times_s[i]) (steps_v[i] + recoveries_v[i] exp(-(s - times_s[i]) / recovery_tau_s)).

    Parameters (model file keys)
    ----------------------------
    times_s : list of float > 0, strictly increasing
        Times of the jumps after the first sample, s.
    steps_v : list of float
        What each jump leaves for good, V (same length).
    recovery_tau_s : float > 0, optional
        Time constant of the part of each jump that settles, s (with ``recoveries_v``).
    recoveries_v : list of float, optional
        The part of each jump that settles, V (same length as ``times_s``; none: every jump stays whole).

    t_first as in :class:`OffsetDriftElement` (first sample, or first after a reset/tare), like the other time
    drifts. A record's jumps say nothing about the next record's: a diagnosis saves them so that its model describes
    the record it came from, and the runtime leaves them out unless ``apply_time_drifts``.
    """

    kind = "step_drift"
    KEYS = ("times_s", "steps_v")
    OPTIONAL_KEYS = ("recovery_tau_s", "recoveries_v")
    times_s: FloatArray
    steps_v: FloatArray
    recovery_tau_s: Optional[float]
    recoveries_v: Optional[FloatArray]
    _left_v: FloatArray      # what the jumps up to each leave for good (0 before the first) [V]
    _settling_v: FloatArray  # what still settles just after each jump [V]

    def __init__(self, times_s: Numbers, steps_v: Numbers, recovery_tau_s: Optional[float] = None,
                 recoveries_v: Optional[Numbers] = None) -> None:
        times, steps = abscissae_and_values(self.kind, "times_s", times_s, "steps_v", steps_v)
        if (recovery_tau_s is None) != (recoveries_v is None):
            raise ModelError(f"{self.kind}: recovery_tau_s and recoveries_v come together")
        tau: Optional[float] = None
        recoveries: Optional[FloatArray] = None
        if recovery_tau_s is not None:
            tau = check_number(self.kind, "recovery_tau_s", recovery_tau_s, positive=True)
            _, recoveries = abscissae_and_values(self.kind, "times_s", times_s, "recoveries_v", recoveries_v)
        # what the jumps leave for good up to each, and what still settles just after each (the parts settle with
        # one time, so their sum decays as one: A_j = A_j-1 exp(-(t_j - t_j-1) / tau) + r_j)
        settling = np.zeros(times.size)
        if tau is not None and recoveries is not None:
            decay = np.exp(-np.diff(times, prepend=times[0]) / tau)
            for j in range(times.size):
                settling[j] = (settling[j - 1] * decay[j] if j else 0.0) + recoveries[j]
        self._freeze(times_s=times, steps_v=steps, recovery_tau_s=tau, recoveries_v=recoveries,
                     _left_v=np.concatenate([[0.0], np.cumsum(steps)]), _settling_v=settling)

    def _term(self, s: FloatOrArray) -> FloatOrArray:
        s_arr = np.asarray(s, dtype=float)
        last = np.searchsorted(self.times_s, s_arr, side="right") - 1  # the last jump at or before s; -1: none yet
        drift_v: FloatArray = self._left_v[last + 1]
        if self.recovery_tau_s is not None:
            j = np.maximum(last, 0)
            age = np.maximum(s_arr - self.times_s[j], 0.0)
            drift_v = drift_v + np.where(last >= 0, self._settling_v[j] * np.exp(-age / self.recovery_tau_s), 0.0)
        return drift_v if np.ndim(drift_v) else float(drift_v)

    @staticmethod
    def basis(s: Numbers, times_s: Numbers) -> FloatArray:
        """The jumps' steps as columns: column i is 1 from ``times_s[i]`` on, s (s) after the first sample, and 0
        before (a fitter's design columns; the drift without recoveries is ``basis @ steps_v``)."""
        return (np.asarray(s, dtype=float)[:, None] >= np.asarray(times_s, dtype=float)[None, :]).astype(float)

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping."""
        out: dict[str, Any] = {"type": self.kind, "times_s": [float(v) for v in self.times_s],
                               "steps_v": [float(v) for v in self.steps_v]}
        if self.recovery_tau_s is not None and self.recoveries_v is not None:
            out["recovery_tau_s"] = float(self.recovery_tau_s)
            out["recoveries_v"] = [float(v) for v in self.recoveries_v]
        return out

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The element from a model-file mapping."""
        check_keys(cls.kind, d, cls.KEYS, cls.OPTIONAL_KEYS)
        return cls(d["times_s"], d["steps_v"], d.get("recovery_tau_s"), d.get("recoveries_v"))


def _spline_from_zero(knots_s: FloatArray, values: FloatArray) -> Any:
    """The natural cubic spline through (0, 0) and (knots_s[i], values[i]) (values may have trailing columns)."""
    from scipy.interpolate import CubicSpline

    values = np.asarray(values, dtype=float)
    return CubicSpline(np.concatenate([[0.0], knots_s]), np.concatenate([np.zeros((1, *values.shape[1:])), values]),
                       bc_type="natural")


class SplineDriftElement(TimeDriftElement):
    """Load-independent baseline drift of a wandering shape (a slow random walk, humidity events):
    y = x + S(t - t_first), S the natural cubic spline through (knots_s[i], values_v[i]), S = 0 at s = 0.

    Parameters (model file keys)
    ----------------------------
    knots_s : list of float > 0, strictly increasing
        Knot times after the first sample, s.
    values_v : list of float
        The drift at each knot, V (same length). Between 0 and the first knot the
        spline starts from 0; after the last knot the drift holds its last value
        (a fitted drift says nothing beyond its record, and holding is bounded).

    t_first as in :class:`OffsetDriftElement` (first sample, or first after a reset/tare).
    """

    kind = "spline_drift"
    KEYS = ("knots_s", "values_v")
    knots_s: FloatArray
    values_v: FloatArray
    _spline: CubicSpline

    def __init__(self, knots_s: Numbers, values_v: Numbers) -> None:
        knots, values = abscissae_and_values(self.kind, "knots_s", knots_s, "values_v", values_v)
        self._freeze(knots_s=knots, values_v=values, _spline=_spline_from_zero(knots, values))

    def _term(self, s: FloatOrArray) -> FloatOrArray:
        s = np.asarray(s, dtype=float)
        drift_v: FloatArray = self._spline(np.clip(s, 0.0, self.knots_s[-1]))
        return drift_v

    @staticmethod
    def basis(s: Numbers, knots_s: Numbers) -> FloatArray:
        """The drift as a linear map of its knot values: column i is the drift, s (s) after the first sample, of
        unit value at knot i and zero at the others (a fitter's design columns; the drift is ``basis @ values_v``)."""
        knots = np.asarray(knots_s, dtype=float)
        spline = _spline_from_zero(knots, np.eye(knots.size))
        return np.asarray(spline(np.clip(np.asarray(s, dtype=float), 0.0, knots[-1])), dtype=float)

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping."""
        return {"type": self.kind, "knots_s": [float(v) for v in self.knots_s], "values_v": [float(v) for v in self.values_v]}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The element from a model-file mapping."""
        check_keys(cls.kind, d, cls.KEYS)
        return cls(d["knots_s"], d["values_v"])
