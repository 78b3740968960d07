"""Element protocols, immutability, parameter bounds and the validation every element's ``from_dict`` uses.

An element runs forward (simulate), backward in batch (compensate an array) and backward per sample
(``streaming()``, O(1) state), and describes itself as a plain mapping for the YAML model file. The
protocols below document those methods once; each element says in one line what its own does.
"""
from __future__ import annotations

import math
import numbers
from typing import Any, Callable, Collection, Mapping, NoReturn, Optional, Protocol, Self, Sequence, Union, runtime_checkable

import numpy as np
import numpy.typing as npt

__all__ = ["ModelError", "ElementStream", "ForwardElement", "Element", "Frozen", "short_repr", "check_number", "check_keys",
           "smoke_records", "SimpleElement", "StepFunction", "AffineFunction",
           "FunctionStream", "stream_backward", "temperature_c_of",
           "float_list",
           "abscissae_and_values", "FloatArray", "FloatOrArray", "Numbers", "PARAMETER_BOUNDS", "MAX_PREISACH_LEVELS", "DAY_S",
           "MAX_RATE_PER_S"]


FloatArray = npt.NDArray[np.float64]
# A drift term is evaluated on a whole record (array) and, when streaming, on one sample (float).
FloatOrArray = Union[float, FloatArray]
# Parameter lists as a model file (list) or a fit (array) gives them; checked by float_list.
Numbers = Union[Sequence[float], FloatArray]

class ModelError(ValueError):
    """A model description that cannot be used (bad type, keys or values)."""


@runtime_checkable
class ElementStream(Protocol):
    """Per-sample inverse of one element: O(1) state, ``step`` maps its output back to its input."""

    def reset(self) -> None:
        """Forget the history: the next sample starts from a relaxed, unloaded element."""
        ...

    def step(self, t_s: float, value: float, aux: Optional[Mapping[str, Any]] = None) -> Optional[float]:
        """The element's input for its output ``value`` at one sample.

        Parameters
        ----------
        t_s : float
            Sample time [s].
        value : float
            The element's output at ``t_s`` [its output unit: N or V].
        aux : mapping of str to float, optional
            Auxiliary samples at ``t_s`` (``temperature_c`` [degC]); elements that do not need them ignore them.

        Returns
        -------
        float or None
            The element's input [its input unit: N or V], or None for a sample it cannot use.
        """
        ...


@runtime_checkable
class ForwardElement(Protocol):
    """What can simulate: every :class:`Element`, and elements that can only simulate (the bench
    generator's truths: Bouc-Wen, a load-dependent core), which only a forward-only chain admits."""

    kind: str

    def forward_state(self) -> Any:
        """A fresh state for block-wise :meth:`forward` runs (relaxed, unloaded).

        Returns
        -------
        object
            The element's state (None for a stateless element), to pass to :meth:`forward`.
        """
        ...

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Any = None) -> FloatArray:
        """Output for input ``x`` at times ``t_s``; ``state`` carries the history across blocks.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s].
        x : (n,) array_like of float
            Input [the element's input unit: N or V].
        aux : mapping of str to array_like, optional
            Auxiliary signals sampled with ``x`` (``temperature_c`` [degC]).
        state : object, optional
            A state from :meth:`forward_state`, updated in place; a relaxed, unloaded element when omitted.

        Returns
        -------
        (n,) ndarray of float
            Output [the element's output unit: N or V].
        """
        ...


@runtime_checkable
class Element(ForwardElement, Protocol):
    """What every element of a :class:`SensorChain` is: an immutable value that runs forward
    (simulate), backward in batch and per sample, and describes itself for the model file.

    ``t_s`` in s; ``x``/``y`` in the element's input/output units (N or V); ``aux`` holds
    auxiliary signals sampled with the main one (``temperature_c``).
    """

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """Input that gave output ``y`` at times ``t_s``: the inverse of :meth:`forward` over a record.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s].
        y : (n,) array_like of float
            Output [the element's output unit: N or V].
        aux : mapping of str to array_like, optional
            Auxiliary signals sampled with ``y`` (``temperature_c`` [degC]).

        Returns
        -------
        (n,) ndarray of float
            Input [the element's input unit: N or V].
        """
        ...

    def streaming(self) -> ElementStream:
        """The per-sample inverse (O(1) state), equal to :meth:`backward` sample by sample.

        Returns
        -------
        ElementStream
            A fresh stream (relaxed, unloaded element).
        """
        ...

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping.

        Returns
        -------
        dict
            ``type`` and the element's parameters, with units in their names.
        """
        ...


class Frozen:
    """Attributes are set once, in ``__init__`` (through ``_freeze``); a changed element is a new element."""

    def _freeze(self, **values: Any) -> None:
        for name, value in values.items():
            if isinstance(value, np.ndarray):  # arrays too: a read-only copy, so no one writes into a model
                value = value.copy()
                value.flags.writeable = False
            object.__setattr__(self, name, value)

    def __setattr__(self, name: str, value: Any) -> NoReturn:
        raise AttributeError(f"{type(self).__name__} is immutable (tried to set {name}); build a new element "
                             "(SensorChain.with_offset for the bridge offset)")

    def __delattr__(self, name: str) -> NoReturn:
        raise AttributeError(f"{type(self).__name__} is immutable (tried to delete {name})")



# Bounds of every parameter a model file may set: name -> (low, high, unit, why).
# Values outside are a ModelError naming the element, the key and the range.
# They are wide physical limits, not a plausibility check: each range holds
# the identification search boxes (physics/identification.py and
# discrepancy/engine.py fit the core parameters in log space over 1e-6..1e12,
# the effects of a diagnosis over the ranges noted below) with a margin, and
# each keeps every derived quantity (1/k, k/eta, k**2/eta, r * h, the products
# of the chain) many orders of magnitude inside float64, so a model within
# them cannot turn a finite record into inf or NaN through its parameters
# alone. Combinations that are still numerically degenerate are caught after
# the element is built (_check_core_numerics) and for the whole chain on load
# (model_file.validate_chain_numerics).
_STIFFNESS = (1e-7, 1e13, "N/V", "a decade around the fitted 1e-6..1e12; 1/k and k**2 stay far from float64 limits")
_VISCOSITY = (1e-7, 1e13, "N*s/V", "a decade around the fitted 1e-6..1e12; time constants eta/k 1e-20..1e20 s")
PARAMETER_BOUNDS = {
    **{f"{k}_n_per_v": _STIFFNESS for k in ("k", "k1", "k2", "k3", "k4")},
    **{f"{e}_n_s_per_v": _VISCOSITY for e in ("eta", "eta1", "eta2", "eta3", "eta4")},
    # a bridge/ADC reads a few volts; 1 kV is far beyond any amplifier output
    "voltage_v": (-1e3, 1e3, "V", "an offset beyond any amplifier output is not a sensor"),
    # a drift faster than 1 kV/s crosses any ADC range within milliseconds (diagnosis fits +-1 V/s)
    "rate_v_per_s": (-1e3, 1e3, "V/s", "faster than any drift; over 24 h at most 8.6e7 V"),
    # V/N or V/V: 1 nV..1 GV per unit; the inverse divides by it
    "gain": (1e-9, 1e9, "", "the inverse divides by the gain"),
    # y = x + q x**2: |q| = 1e3 /V already bends the curve by 100 % at 1 mV (diagnosis fits +-1 /V)
    "quadratic_per_v": (-1e3, 1e3, "1/V", "100 % nonlinearity at 1 mV already"),
    # electronics (0.1 us) to a slow thermal lag (11.6 days); diagnosis fits 1e-4..10 s
    "tau_s": (1e-7, 1e6, "s", "from 0.1 us electronics to 11.6 days; the forward run scales by 1/tau"),
    "noise_filter_tau_s": (1e-7, 1e6, "s", "a lag like tau_s"),
    "noise_filter_order": (1.0, 2.0, "", "first- or second-order roll-off of the inverse"),
    # DAQ buffering and transport: microseconds to a few seconds (diagnosis fits 2..100 ms)
    "delay_s": (1e-7, 10.0, "s", "a force felt seconds late is no force feedback"),
    # a mechanical mode: from a slow suspension (1 mHz) to a stiff structure (100 kHz); damped below critical
    "frequency_hz": (1e-3, 1e5, "Hz", "beyond any mechanical mode a force sensor shows"),
    "damping_ratio": (1e-3, 0.95, "", "a mode at or above critical damping is a lag (sensor_lag)"),
    "inverse_damping_ratio": (1e-3, 0.95, "", "the inverse's damping, above the mode's"),
    # V per degC: 10 V/degC swings a 10 V range in 1 degC (diagnosis fits +-1 V/degC)
    "coefficient_v_per_c": (-10.0, 10.0, "V/degC", "full scale within 1 degC already"),
    # the zero's curvature: 1 V/degC^2 swings a 10 V range within about 3 degC (diagnosis fits within it)
    "curvature_v_per_c2": (-1.0, 1.0, "V/degC^2", "full scale within 3 degC already"),
    # span change per degC: 5 %/degC halves or doubles the span within 20 degC (diagnosis fits +-2 %/degC)
    "span_coefficient_per_c": (-0.05, 0.05, "1/degC", "the span halves or doubles within 20 degC already"),
    # the span coefficient's own change per degC: 5e-3/degC^2 halves or doubles the span within 10 degC
    "span_curvature_per_c2": (-0.005, 0.005, "1/degC^2", "the span halves or doubles within 10 degC already"),
    "direct_span_coefficient_per_c": (-0.05, 0.05, "1/degC", "as span_coefficient_per_c"),
    # a power-law dashpot: 10 V/s fills any range within a second; exponents beyond 5 are a step, below 0.2 a constant
    "flow_rate_v_per_s": (0.0, 10.0, "V/s", "a range filled within a second already"),
    "flow_exponent": (0.2, 5.0, "", "a flow rate steeper than F^5 is a yield step, flatter than F^0.2 a constant"),
    "flow_force_scale_n": (1e-3, 1e5, "N", "1 mN to 100 kN: beyond any force sensor range"),
    "flow_yield_n": (0.0, 1e5, "N", "100 kN: beyond any force sensor range"),
    # a fluidity that changes with the load-time integral passed: the integral at which it stops changing, and the
    # change there (0.1 V per newton-second: a 10 N push flows 1 V per second, a range within seconds)
    "flow_volume_scale_n_s": (1e-6, 1e9, "N s", "a billion newton-seconds: 30 years at 1 N"),
    "flow_volume_rates_v_per_n_s": (-0.1, 0.1, "V/(N s)", "a 10 N push would flow a range within seconds"),
    # Kelvin units loaded by the force above knees: a compliance may be negative (a unit that bottoms out above its
    # knee) as long as each running sum stays above minus the core's instantaneous compliance (checked against it)
    "knees_n": (-1e5, 1e5, "N", "100 kN: beyond any force sensor range"),
    "knee_compliances_v_per_n": (-1e3, 1e3, "V/N", "1 kV per newton: beyond any bridge"),
    "knee_tau_s": (1e-3, 1e6, "s", "a retardation faster than 1 ms is a lag (sensor_lag); up to 11.6 days"),
    # the span's thermal lag behind the thermometer (0 = none): up to a day
    "thermal_tau_s": (1e-3, 1e5, "s", "a span a day behind its temperature follows the weather, not the sensor"),
    # a polymer sensor below -100 degC is glass, above 300 degC it decomposes
    "reference_c": (-100.0, 300.0, "degC", "the range a polymer sensor survives"),
    # Preisach input/output range and weights, in N or V (either side of the core)
    "u_min": (-1e6, 1e6, "", "1 MN or 1 MV: beyond any sensor range"),
    "u_max": (-1e6, 1e6, "", "1 MN or 1 MV: beyond any sensor range"),
    "offset": (-1e6, 1e6, "", "1 MN or 1 MV: beyond any sensor range"),
    "density": (0.0, 1e6, "", "non-negative relay weights, each within the output range"),
    # Prandtl-Ishlinskii (play-operator) hysteresis, input/output in N or V (either side of the core)
    "linear_weight": (1e-6, 1e6, "", "the inverse divides by it (and by every partial sum of weights)"),
    "radii": (1e-9, 1e6, "", "play half-widths > 0, in the input unit; 1 MN or 1 MV is beyond any sensor"),
    "weights": (-1e6, 1e6, "", "play weights; with linear_weight every partial sum stays > 0 (monotone, invertible)"),
    "history_max": (0.0, 1e6, "", "the input's maximum before the record, in the input unit"),
    # play operators at the bridge beside the core (bridge_hysteresis): force in, volts out
    "radii_n": (1e-9, 1e6, "N", "play half-widths > 0; 1 MN is beyond any sensor"),
    "weights_v_per_n": (-1e3, 1e3, "V/N", "a loop of 1 kV per newton is beyond any bridge"),
    "linear_v_per_n": (0.0, 1e3, "V/N", "a loop of 1 kV per newton is beyond any bridge"),
    "history_max_n": (0.0, 1e6, "N", "the force's maximum before the record"),
    # plays on asinh(F / floor_n), whose bands grow with the load: a half-width of 2 is a band of e**+-2 (7x) the load
    "scaled_radii": (1e-6, 2.0, "", "a band from a seventh to seven times the load is no longer a loop"),
    "scaled_weights_v_per_n": (0.0, 1e3, "V/N", "a loop of 1 kV per newton is beyond any bridge"),
    "floor_n": (1e-9, 1e6, "N", "the force below which a scaled band stops shrinking; 1 MN is beyond any sensor"),
    # Coulomb friction on the force path: the stiction band's half-width and the share of it the contact takes
    "radius_n": (1e-9, 1e6, "N", "a friction force of 1 MN is beyond any mechanism"),
    "coupling": (0.0, 1.0, "", "a share of the friction force"),
    "inverse_share": (0.0, 1.0, "", "a share of the friction the inverse adds back"),
    "band_log_slope_per_c": (-0.5, 0.5, "1/degC", "a band e times wider per 2 degC is beyond any grease or fit"),
    # time-temperature superposition: ln of the viscosities' shift factor per degree (polymers: 0.02-0.3 /degC)
    "shift_per_c": (-2.0, 2.0, "1/degC", "a viscosity 7x smaller per degree is beyond any polymer"),
    "temperature_lag_s": (1e-3, 1e5, "s", "a core a day behind its thermometer follows the weather, not the sensor"),
    # the WLF constant C2 relative to the reference: ln a_T = b dT C2 / (C2 + dT), the clock stopping C2 below it
    "wlf_c2_c": (1.0, 1e4, "degC", "a clock that stops within a degree of the reference is a glass; beyond 10 000 degC "
                 "the law is straight (0)"),
    "deadband_n": (0.0, 1e6, "N", "the inverse's dead band on the core's force, a few times its noise"),
    # polynomial offset drift: y = x + r t + c2 t**2 + c3 t**3 (t since the first sample)
    # polynomial gain y = x + q x**2 + c x**3 (V in, V out); monotone over the range it was fitted on
    "cubic_per_v2": (-1e3, 1e3, "1/V^2", "100 % nonlinearity at 30 mV already"),
    "quartic_per_v3": (-1e3, 1e3, "1/V^3", "100 % nonlinearity at 0.1 V already"),
    # exponential-approach drift y = x + amplitude_v (1 - exp(-t / tau_s)) (tau_s has its own entry)
    "amplitude_v": (-1e3, 1e3, "V", "beyond any amplifier output"),
    # spline drift: knot times (s after the first sample) and the drift there (V)
    "knots_s": (1e-6, 1e9, "s", "knot times after the first sample, up to 30 years"),
    "values_v": (-1e3, 1e3, "V", "beyond any amplifier output"),
    # a zero that jumps: the jumps' times (s after the first sample), what each leaves (V) and the part that settles
    "times_s": (1e-6, 1e9, "s", "jump times after the first sample, up to 30 years"),
    "steps_v": (-1e3, 1e3, "V", "beyond any amplifier output"),
    "recoveries_v": (-1e3, 1e3, "V", "beyond any amplifier output"),
    "recovery_tau_s": (1e-3, 1e6, "s", "a settling faster than 1 ms is part of the jump; up to 11.6 days"),
    "curvature_v_per_s2": (-1e3, 1e3, "V/s^2", "over 24 h at most 7.5e12 V: finite"),
    "cubic_v_per_s3": (-1e3, 1e3, "V/s^3", "over 24 h at most 6.5e17 V: finite"),
}
# Parameters where 0 means "off" and is allowed besides the range.
_ZERO_MEANS_OFF = {"noise_filter_tau_s", "thermal_tau_s", "floor_n", "flow_volume_scale_n_s", "temperature_lag_s",
                   "wlf_c2_c"}
#: Preisach levels: 5x seed 001's 40; n (n + 1) / 2 relays cost O(n**2) per sample.
MAX_PREISACH_LEVELS = 200
# The record a model must carry: 24 h (exp(-r * 86400 s) decays, never grows) and
# the sample steps checked by the smoke runs (10 kHz .. one sample per 10 s).
DAY_S = 86400.0
_SMOKE_STEPS_S = (1e-4, 1e-3, 1e-2, 1e-1, 1.0, 10.0)
# step_weights squares z = r h: z must stay below ~1e154; 1e150 / 86400 s leaves room.
MAX_RATE_PER_S = 1e150 / DAY_S



def short_repr(value: object, limit: int = 60) -> str:
    """``repr(value)`` cut to ``limit`` characters: a hostile value quoted in an error message stays one line."""
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."



def _range_text(key: str) -> str:
    low, high, unit, why = PARAMETER_BOUNDS[key]
    unit = f" {unit}" if unit else ""
    off = " (or 0 = off)" if key in _ZERO_MEANS_OFF else ""
    return f"[{low:g}, {high:g}]{unit}{off} ({why})"


def check_number(kind: str, key: str, value: Any, positive: bool) -> float:
    """``value`` as a finite float within PARAMETER_BOUNDS[key] (when listed), else ModelError."""
    # numbers.Real: numpy's float and integer scalars too; bool is a number to Python, not to a model file
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise ModelError(f"{kind}: {key} must be a number, got {short_repr(value)}")
    try:
        value = float(value)
    except OverflowError:
        raise ModelError(f"{kind}: {key} must be a number that fits a float (|x| < 1.8e308), "
                         f"got an integer of about {int(value.bit_length() * math.log10(2)) + 1} digits") from None
    if not math.isfinite(value):
        raise ModelError(f"{kind}: {key} must be finite, got {value!r}")
    if positive and value <= 0.0:
        raise ModelError(f"{kind}: {key} must be > 0, got {value!r}")
    bounds = PARAMETER_BOUNDS.get(key)
    if bounds is not None and not (bounds[0] <= value <= bounds[1]):
        if not (value == 0.0 and key in _ZERO_MEANS_OFF):
            raise ModelError(f"{kind}: {key} = {value!r} is outside the allowed range {_range_text(key)}")
    return float(value)


def check_keys(kind: str, mapping: object, expected: Collection[str], optional: Collection[str] = ()) -> None:
    """``mapping`` is a dict with string keys, all of ``expected`` and nothing beyond ``optional`` (and ``type``),
    else a :class:`ModelError` naming ``kind`` and the keys."""
    if not isinstance(mapping, dict):
        raise ModelError(f"{kind}: must be a mapping, got {short_repr(mapping)}")
    bad = [k for k in mapping if not isinstance(k, str)]
    if bad:
        raise ModelError(f"{kind}: keys must be strings, got {short_repr(bad)}")
    keys = set(mapping) - {"type"}
    allowed = set(expected) | set(optional)
    missing, unknown = sorted(set(expected) - keys), sorted(keys - allowed)
    if missing:
        raise ModelError(f"{kind}: missing keys {missing}")
    if unknown:
        raise ModelError(f"{kind}: unknown keys {short_repr(unknown, 200)} (expected {sorted(expected)}"
                         + (f", optional {sorted(optional)})" if optional else ")"))


def smoke_records() -> list[tuple[npt.NDArray[np.floating[Any]], FloatArray, dict[str, FloatArray], str]]:
    """Short records (t, force N, temperature degC) that every element must carry to finite output:
    uniform at each step of _SMOKE_STEPS_S, and one irregular record spanning 24 h."""
    records: list[tuple[npt.NDArray[np.floating[Any]], FloatArray, str]] = []
    for h in _SMOKE_STEPS_S:
        t = 1000.0 + h * np.arange(40)
        records.append((t, 5.0 + 4.0 * np.sin(np.linspace(0.0, 6.0, t.size)), f"uniform, step {h:g} s"))
    t = np.unique(np.concatenate([1e-3 * np.arange(20), np.logspace(-1.0, math.log10(DAY_S), 40)]))
    records.append((t, 5.0 + 4.0 * np.sin(np.linspace(0.0, 9.0, t.size)), "irregular, 24 h"))
    return [(t, f, {"temperature_c": 25.0 + 10.0 * np.sin(np.linspace(0.0, 3.0, t.size))}, label)
            for t, f, label in records]



class SimpleElement(Frozen):
    """Base of the effect elements: parameters declared in PARAMS as (name, must_be_positive),
    optional ones in OPTIONAL as name -> default (numbers >= 0 unless named in SIGNED; the default leaves them
    out of files)."""

    kind = ""
    PARAMS: tuple[tuple[str, bool], ...] = ()
    OPTIONAL: dict[str, float] = {}
    SIGNED: frozenset[str] = frozenset()

    def __init__(self, **values: float) -> None:
        for name, positive in self.PARAMS:
            self._freeze(**{name: check_number(self.kind, name, values[name], positive)})
        for name, default in self.OPTIONAL.items():
            raw = values.get(name, default)
            if isinstance(raw, (int, float)) and not isinstance(raw, bool) and raw < 0 and name not in self.SIGNED:
                raise ModelError(f"{self.kind}: {name} must be >= 0, got {short_repr(raw)}")
            self._freeze(**{name: check_number(self.kind, name, raw, False)})

    def forward_state(self) -> object:
        """A fresh state for block-wise :meth:`forward` runs."""
        return None

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping."""
        out = {"type": self.kind, **{name: getattr(self, name) for name, _ in self.PARAMS}}
        out.update({name: getattr(self, name) for name, default in self.OPTIONAL.items() if getattr(self, name) != default})
        return out

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The element from a model-file mapping."""
        check_keys(cls.kind, d, [name for name, _ in cls.PARAMS], cls.OPTIONAL)
        return cls(**{name: d[name] for name in [n for n, _ in cls.PARAMS] + [n for n in cls.OPTIONAL if n in d]})


class StepFunction(Protocol):
    """The per-sample inverse of a :class:`FunctionStream`: ``t_s`` (s) and an output sample in, the input out."""

    def __call__(self, t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> Optional[float]: ...


def stream_backward(stream: ElementStream, t_s: npt.ArrayLike, y: npt.ArrayLike,
                    aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
    """An element's inverse over a record, run sample by sample through its ``stream`` (an implicit or recursive
    inverse): each sample's input, the last one for a sample the stream refuses; the temperature of ``aux`` (a
    scalar or one value per sample) passed on with each sample."""
    t, v = np.asarray(t_s, dtype=float), np.asarray(y, dtype=float)
    if t.size > 1 and np.any(np.diff(t) < 0):
        raise ValueError("t_s must be non-decreasing")
    temp = temperature_c_of(aux, t.size)
    out = np.empty(v.size)
    last = 0.0
    for i, (ti, vi) in enumerate(zip(t.tolist(), v.tolist())):
        x = stream.step(ti, vi, None if temp is None else {"temperature_c": float(temp[i])})
        last = x if x is not None else last
        out[i] = last
    return out


#: The next step of a core's per-sample inverse as an affine map of its output, without advancing it:
#: ``(t_s, aux) -> (force0_n, stiffness_n_per_v)``, None for a stamp before the previous one.
AffineFunction = Callable[[float, Optional[Mapping[str, Any]]], Optional[tuple[float, float]]]


class FunctionStream:
    """Streaming inverse of an element with a per-sample function ``f(t_s, y, aux) -> x``; a core's stream also has
    ``affine`` (:data:`AffineFunction`), which an element beside the core solves its own force with."""

    def __init__(self, step: StepFunction, reset: Callable[[], None] = lambda: None,
                 affine: Optional[AffineFunction] = None) -> None:
        self.step, self.reset, self.affine = step, reset, affine



def temperature_c_of(aux: Optional[Mapping[str, Any]], n: int) -> Optional[FloatArray]:
    """Temperature samples (degC) from ``aux``: an array of n, a scalar, or None when absent."""
    if not aux or aux.get("temperature_c") is None:
        return None
    return np.broadcast_to(np.asarray(aux["temperature_c"], dtype=float), (n,)) if n else np.zeros(0)



def float_list(kind: str, key: str, values: object, positive: bool) -> FloatArray:
    """``values`` as a float array: a non-empty list of at most MAX_PREISACH_LEVELS numbers, each checked by
    :func:`check_number` (finite, within PARAMETER_BOUNDS[key], > 0 if ``positive``), else ModelError."""
    if not isinstance(values, (list, tuple, np.ndarray)) or len(values) == 0:
        raise ModelError(f"{kind}: {key} must be a non-empty list of numbers, got {short_repr(values)}")
    if len(values) > MAX_PREISACH_LEVELS:
        raise ModelError(f"{kind}: {key} holds {len(values)} values; at most {MAX_PREISACH_LEVELS}")
    return np.array([check_number(kind, key, v.item() if isinstance(v, np.generic) else v, positive) for v in list(values)])


def abscissae_and_values(kind: str, x_key: str, x: object, y_key: str, y: object) -> tuple[FloatArray, FloatArray]:
    """Two number lists of one length: ``x`` positive and strictly increasing, ``y`` any finite values."""
    x = float_list(kind, x_key, x, positive=True)
    y = float_list(kind, y_key, y, positive=False)
    if x.size != y.size:
        raise ModelError(f"{kind}: {x_key} and {y_key} must have the same length ({x.size} != {y.size})")
    if np.any(np.diff(x) <= 0):
        raise ModelError(f"{kind}: {x_key} must be strictly increasing")
    return x, y
