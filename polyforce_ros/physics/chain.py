"""A sensor as a chain of elements between applied force and measured voltage.

    force -> [viscoelastic core] -> ... -> [offset] -> voltage

Each element runs forward (simulate), backward in batch (compensate an array)
and backward per sample (``streaming()``, O(1) state), and describes itself as
a plain mapping for the YAML model file. The chain runs its elements forward in
order and backward in reverse order. Elements receive ``aux``, a mapping of
auxiliary signals sampled with the main one (e.g. ``temperature_c``), which
elements that need it (thermal terms) read and others ignore.
"""
from __future__ import annotations

import math
import numbers
from typing import (TYPE_CHECKING, Any, Callable, Collection, Mapping, NoReturn, Optional, Protocol, Self, Sequence,
                    TypedDict, Union, cast, runtime_checkable)

import numpy as np
import numpy.typing as npt

from .expconv import ExpConvState, exp_convolve
from .viscoelastic import (
    MODEL_TYPES,
    CreepCompliance,
    ForwardState,
    RelaxationModulus,
    StreamingCompensator,
    ViscoelasticModel,
    compensate,
    simulate_deformation,
)

if TYPE_CHECKING:  # for annotations only: at run time scipy.interpolate and the Preisach model load when first used
    from scipy.interpolate import CubicSpline

    from .preisach import ContinuousPreisachStream, PreisachModel, PreisachStream

__all__ = ["ModelError", "short_repr", "smoke_records", "ElementStream", "Element", "PARAMETER_BOUNDS",
    "MAX_PREISACH_LEVELS", "ViscoelasticElement",
    "OffsetElement", "GainElement", "NonlinearGainElement", "SensorLagElement", "TransportDelayElement",
    "ThermalDriftElement", "ThermalSensitivityElement",
    "OffsetDriftElement", "PreisachElement", "play_operator", "PlayHysteresisElement", "ThermalLagElement",
    "ExponentialDriftElement", "SplineDriftElement", "PolynomialGainElement", "PolynomialDriftElement", "ELEMENT_TYPES",
    "SensorChain", "ChainStream"]

_FloatArray = npt.NDArray[np.float64]
# A drift term is evaluated on a whole record (array) and, when streaming, on one sample (float).
_FloatOrArray = Union[float, _FloatArray]
# Parameter lists as a model file (list) or a fit (array) gives them; checked by _float_list.
_Numbers = Union[Sequence[float], _FloatArray]


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
                state: Any = None) -> _FloatArray:
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

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> _FloatArray:
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


class _Frozen:
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
    **{f"{k}_n_per_v": _STIFFNESS for k in ("k", "k1", "k2", "k3")},
    **{f"{e}_n_s_per_v": _VISCOSITY for e in ("eta", "eta1", "eta2", "eta3")},
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
    # V per degC: 10 V/degC swings a 10 V range in 1 degC (diagnosis fits +-1 V/degC)
    "coefficient_v_per_c": (-10.0, 10.0, "V/degC", "full scale within 1 degC already"),
    # span change per degC: 5 %/degC halves or doubles the span within 20 degC (diagnosis fits +-2 %/degC)
    "span_coefficient_per_c": (-0.05, 0.05, "1/degC", "the span halves or doubles within 20 degC already"),
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
    # polynomial offset drift: y = x + r t + c2 t**2 + c3 t**3 (t since the first sample)
    # polynomial gain y = x + q x**2 + c x**3 (V in, V out); monotone over the range it was fitted on
    "cubic_per_v2": (-1e3, 1e3, "1/V^2", "100 % nonlinearity at 30 mV already"),
    "quartic_per_v3": (-1e3, 1e3, "1/V^3", "100 % nonlinearity at 0.1 V already"),
    # exponential-approach drift y = x + amplitude_v (1 - exp(-t / tau_s)) (tau_s has its own entry)
    "amplitude_v": (-1e3, 1e3, "V", "beyond any amplifier output"),
    # spline drift: knot times (s after the first sample) and the drift there (V)
    "knots_s": (1e-6, 1e9, "s", "knot times after the first sample, up to 30 years"),
    "values_v": (-1e3, 1e3, "V", "beyond any amplifier output"),
    "curvature_v_per_s2": (-1e3, 1e3, "V/s^2", "over 24 h at most 7.5e12 V: finite"),
    "cubic_v_per_s3": (-1e3, 1e3, "V/s^3", "over 24 h at most 6.5e17 V: finite"),
}
# Parameters where 0 means "off" and is allowed besides the range.
_ZERO_MEANS_OFF = {"noise_filter_tau_s"}
#: Preisach levels: 5x seed 001's 40; n (n + 1) / 2 relays cost O(n**2) per sample.
MAX_PREISACH_LEVELS = 200
# The record a model must carry: 24 h (exp(-r * 86400 s) decays, never grows) and
# the sample steps checked by the smoke runs (10 kHz .. one sample per 10 s).
_DAY_S = 86400.0
_SMOKE_STEPS_S = (1e-4, 1e-3, 1e-2, 1e-1, 1.0, 10.0)
# step_weights squares z = r h: z must stay below ~1e154; 1e150 / 86400 s leaves room.
_MAX_RATE_PER_S = 1e150 / _DAY_S


def short_repr(value: object, limit: int = 60) -> str:
    """``repr(value)`` cut to ``limit`` characters: a hostile value quoted in an error message stays one line."""
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


_short = short_repr


def _range_text(key: str) -> str:
    low, high, unit, why = PARAMETER_BOUNDS[key]
    unit = f" {unit}" if unit else ""
    off = " (or 0 = off)" if key in _ZERO_MEANS_OFF else ""
    return f"[{low:g}, {high:g}]{unit}{off} ({why})"


def _number(kind: str, key: str, value: Any, positive: bool) -> float:
    """``value`` as a finite float within PARAMETER_BOUNDS[key] (when listed), else ModelError."""
    # numbers.Real: numpy's float and integer scalars too; bool is a number to Python, not to a model file
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise ModelError(f"{kind}: {key} must be a number, got {_short(value)}")
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
    return value


def _check_keys(kind: str, mapping: object, expected: Collection[str], optional: Collection[str] = ()) -> None:
    if not isinstance(mapping, dict):
        raise ModelError(f"{kind}: must be a mapping, got {_short(mapping)}")
    bad = [k for k in mapping if not isinstance(k, str)]
    if bad:
        raise ModelError(f"{kind}: keys must be strings, got {_short(bad)}")
    keys = set(mapping) - {"type"}
    allowed = set(expected) | set(optional)
    missing, unknown = sorted(set(expected) - keys), sorted(keys - allowed)
    if missing:
        raise ModelError(f"{kind}: missing keys {missing}")
    if unknown:
        raise ModelError(f"{kind}: unknown keys {_short(unknown, 200)} (expected {sorted(expected)}"
                         + (f", optional {sorted(optional)})" if optional else ")"))


def smoke_records() -> list[tuple[npt.NDArray[np.floating[Any]], _FloatArray, dict[str, _FloatArray], str]]:
    """Short records (t, force N, temperature degC) that every element must carry to finite output:
    uniform at each step of _SMOKE_STEPS_S, and one irregular record spanning 24 h."""
    records: list[tuple[npt.NDArray[np.floating[Any]], _FloatArray, str]] = []
    for h in _SMOKE_STEPS_S:
        t = 1000.0 + h * np.arange(40)
        records.append((t, 5.0 + 4.0 * np.sin(np.linspace(0.0, 6.0, t.size)), f"uniform, step {h:g} s"))
    t = np.unique(np.concatenate([1e-3 * np.arange(20), np.logspace(-1.0, math.log10(_DAY_S), 40)]))
    records.append((t, 5.0 + 4.0 * np.sin(np.linspace(0.0, 9.0, t.size)), "irregular, 24 h"))
    return [(t, f, {"temperature_c": 25.0 + 10.0 * np.sin(np.linspace(0.0, 3.0, t.size))}, label)
            for t, f, label in records]


def _laplace_mismatch(rel: RelaxationModulus, comp: CreepCompliance, s: npt.ArrayLike) -> _FloatArray:
    """|s G(s) * s J(s) - 1| at Laplace variable(s) s > 0: zero for a relaxation that matches its compliance."""
    s = np.asarray(s, dtype=float)
    sg = rel.g_inf_n_per_v + rel.eta_impulse_n_s_per_v * s
    for a, r in zip(rel.a_n_per_v, rel.r_per_s):
        sg = sg + a * s / (s + r)
    sj = comp.j0_v_per_n + comp.fluidity_v_per_n_s / s
    for c, tau in zip(comp.c_v_per_n, comp.tau_s):
        sj = sj + c / (1.0 + tau * s)
    return np.abs(sg * sj - 1.0)


def _check_core_numerics(kind: str, model: ViscoelasticModel) -> None:
    """Derived quantities of a viscoelastic core, checked once after it is built.

    * ``relaxation()`` (roots of the relaxation polynomial, residues) must succeed and give
      finite G(0), G(inf), amplitudes, rates and impulse term;
    * every rate r >= 0: a negative one is a growing mode, exp(+|r| t) over a record;
    * r * 86400 s < 1e150 and a * r finite: the recursion squares z = r h in its step weights.
      No lower limit on r is needed: when r h is below float64 resolution exp(-r h) rounds to 1
      and the series/expm1 forms turn the mode into an exact integral, off by at most r * 24 h
      relative, which is then below 1e-7 (r h < 1.1e-16 at h >= 1e-4 s);
    * the relaxation must be the inverse of the creep compliance, s G(s) s J(s) = 1 to 1e-3
      over s = 1/(24 h) .. 1e4 /s (a relaxation whose rates or residues were lost to cancellation
      fails this although every number in it is finite);
    * forward, batch backward and streaming backward runs on short uniform records (10 kHz to
      0.1 Hz) and an irregular 24-hour record must give finite output and raise nothing.
    """
    try:
        with np.errstate(all="ignore"):
            rel = model.relaxation()
            comp = model.compliance()
            values = [rel.g0_n_per_v, rel.g_inf_n_per_v, rel.eta_impulse_n_s_per_v, *rel.a_n_per_v, *rel.r_per_s]
            products = [a * r for a, r in zip(rel.a_n_per_v, rel.r_per_s)]
            mismatch = _laplace_mismatch(rel, comp, np.logspace(-math.log10(_DAY_S), 4.0, 25))
    except (ArithmeticError, ValueError, LookupError, TypeError) as exc:  # LinAlgError is a ValueError
        raise ModelError(f"{kind}: parameters {model.as_dict()} give no relaxation modulus "
                         f"({type(exc).__name__}: {exc}); they are too far apart for float64") from None
    if not all(math.isfinite(v) for v in values + products):
        raise ModelError(f"{kind}: parameters {model.as_dict()} give a non-finite relaxation modulus {rel}")
    if any(r < 0.0 or r * _DAY_S >= 1e150 for r in rel.r_per_s):
        raise ModelError(f"{kind}: parameters {model.as_dict()} give relaxation rates {rel.r_per_s} 1/s; "
                         f"each must be within [0, {_MAX_RATE_PER_S:.3g}] 1/s")
    if not np.all(mismatch <= 1e-3):
        raise ModelError(f"{kind}: parameters {model.as_dict()} are too far apart for float64: the relaxation "
                         f"modulus does not invert the creep compliance (s G s J - 1 up to {np.nanmax(mismatch):.3g})")
    for t, force, _, label in smoke_records():
        stage = "forward"
        try:
            with np.errstate(all="ignore"):
                volts = simulate_deformation(model, t, force)
                ok = bool(np.all(np.isfinite(volts)))
                if ok:
                    stage = "backward"
                    ok = bool(np.all(np.isfinite(compensate(model, t, volts))))
                if ok and label.startswith(("irregular", "uniform, step 0.001 ")):
                    stage = "streaming backward"
                    stream = StreamingCompensator(model)
                    out = [stream.step(float(ti), float(vi)) for ti, vi in zip(t, volts)]
                    ok = all(o is not None and math.isfinite(o) for o in out)
        except (ArithmeticError, ValueError, LookupError, TypeError) as exc:
            raise ModelError(f"{kind}: parameters {model.as_dict()} are too far apart for float64: the {stage} "
                             f"run on a test record ({label}) failed ({type(exc).__name__}: {exc})") from None
        if not ok:
            raise ModelError(f"{kind}: parameters {model.as_dict()} are too far apart for float64: the {stage} "
                             f"run on a test record ({label}) is not finite")


class ViscoelasticElement(_Frozen):
    """The viscoelastic core: force (N) <-> deformation read as volts (seed 000)."""

    model: ViscoelasticModel
    kind: str

    def __init__(self, model: ViscoelasticModel) -> None:
        self._freeze(model=model, kind=model.kind)

    def forward_state(self) -> ForwardState:
        """A fresh forward state of the core (relaxed, unloaded sensor).

        Returns
        -------
        ForwardState
            The :class:`~.viscoelastic.ForwardState` to pass to :meth:`forward`.
        """
        return ForwardState(self.model)

    def forward(self, t_s: npt.ArrayLike, force_n: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[ForwardState] = None) -> _FloatArray:
        """Deformation for a force history, by :func:`~.viscoelastic.simulate_deformation`.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s], non-decreasing.
        force_n : (n,) array_like of float
            Applied force [N].
        aux : mapping, optional
            Not used.
        state : ForwardState, optional
            Carries the core's state across blocks (updated in place); a relaxed, unloaded sensor when omitted.

        Returns
        -------
        (n,) ndarray of float
            Deformation as bridge volts above the offset [V].
        """
        return simulate_deformation(self.model, t_s, force_n, state=state)

    def backward(self, t_s: npt.ArrayLike, deformation_v: npt.ArrayLike,
                 aux: Optional[Mapping[str, Any]] = None) -> _FloatArray:
        """Force for a deformation record from a relaxed sensor, by :func:`~.viscoelastic.compensate`.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s], non-decreasing.
        deformation_v : (n,) array_like of float
            Deformation as bridge volts above the offset [V].
        aux : mapping, optional
            Not used.

        Returns
        -------
        (n,) ndarray of float
            Force [N].
        """
        return compensate(self.model, t_s, deformation_v)

    def streaming(self) -> StreamingCompensator:
        """The per-sample inverse of the core.

        Returns
        -------
        StreamingCompensator
            A fresh :class:`~.viscoelastic.StreamingCompensator`: deformation [V] in, force [N] out.
        """
        return StreamingCompensator(self.model)

    def to_dict(self) -> dict[str, Any]:
        """The core as a model-file mapping.

        Returns
        -------
        dict
            ``type`` (the model kind) and the model's parameters by name [N/V, N*s/V].
        """
        return {"type": self.kind, **self.model.as_dict()}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The core from a model-file mapping whose ``type`` is a viscoelastic model kind.

        Parameters
        ----------
        d : mapping
            ``type`` and the model's parameters by name [N/V, N*s/V].

        Returns
        -------
        ViscoelasticElement
            The core.

        Raises
        ------
        ModelError
            For an unknown type, missing or unknown keys, parameters that are not positive
            numbers within PARAMETER_BOUNDS, or parameters too far apart for float64
            (relaxation, forward and backward runs checked on test records).
        """
        kind = d.get("type") if isinstance(d, dict) else None
        if not isinstance(kind, str) or kind not in MODEL_TYPES:
            raise ModelError(f"viscoelastic core: type must be one of {sorted(MODEL_TYPES)}, got {_short(kind)}")
        model_type = MODEL_TYPES[kind]
        names = model_type.parameter_names()
        _check_keys(kind, d, names)
        values = [_number(kind, n, d[n], positive=True) for n in names]
        try:
            model = model_type(*values)
        except (TypeError, ValueError) as exc:
            raise ModelError(f"{kind}: {exc}") from None
        _check_core_numerics(kind, model)
        return cls(model)


class OffsetElement(_Frozen):
    """Bridge output at zero force: voltage = input + voltage_v."""

    kind = "offset"
    voltage_v: float

    def __init__(self, voltage_v: float = 0.0) -> None:
        self._freeze(voltage_v=float(voltage_v))

    def forward_state(self) -> None:
        """None: the offset has no state."""
        return None

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: object = None) -> _FloatArray:
        """The input plus the offset, ``x + voltage_v``.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s]; not used.
        x : (n,) array_like of float
            Input [V].
        aux : mapping, optional
            Not used.
        state : object, optional
            Not used.

        Returns
        -------
        (n,) ndarray of float
            Output [V].
        """
        return np.asarray(x, dtype=float) + self.voltage_v

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> _FloatArray:
        """The output less the offset, ``y - voltage_v``.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s]; not used.
        y : (n,) array_like of float
            Output [V].
        aux : mapping, optional
            Not used.

        Returns
        -------
        (n,) ndarray of float
            Input [V].
        """
        return np.asarray(y, dtype=float) - self.voltage_v

    def streaming(self) -> ElementStream:
        """The per-sample inverse, ``value - voltage_v``.

        Returns
        -------
        ElementStream
            A stateless stream [V in, V out].
        """
        return _OffsetStream(self)

    def to_dict(self) -> dict[str, Any]:
        """The offset as a model-file mapping.

        Returns
        -------
        dict
            ``{'type': 'offset', 'voltage_v': ...}`` [V].
        """
        return {"type": self.kind, "voltage_v": self.voltage_v}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The offset from a model-file mapping.

        Parameters
        ----------
        d : mapping
            ``{'type': 'offset', 'voltage_v': ...}`` [V].

        Returns
        -------
        OffsetElement
            The offset.

        Raises
        ------
        ModelError
            For other keys or a value that is not a number within PARAMETER_BOUNDS.
        """
        _check_keys(cls.kind, d, ("voltage_v",))
        return cls(_number(cls.kind, "voltage_v", d["voltage_v"], positive=False))


class _OffsetStream:
    def __init__(self, element: OffsetElement) -> None:
        self.voltage_v = element.voltage_v

    def reset(self) -> None:
        """Nothing to forget: the offset has no state."""

    def step(self, t_s: float, value: float, aux: Optional[Mapping[str, Any]] = None) -> float:
        """The offset element's input for its output ``value``.

        Parameters
        ----------
        t_s : float
            Sample time [s]; not used.
        value : float
            Output [V].
        aux : mapping, optional
            Not used.

        Returns
        -------
        float
            ``value - voltage_v`` [V].
        """
        return value - self.voltage_v



class _SimpleElement(_Frozen):
    """Base of the effect elements: parameters declared in PARAMS as (name, must_be_positive),
    optional ones in OPTIONAL as name -> default (numbers >= 0; the default leaves them out of files)."""

    kind = ""
    PARAMS: tuple[tuple[str, bool], ...] = ()
    OPTIONAL: dict[str, float] = {}

    def __init__(self, **values: float) -> None:
        for name, positive in self.PARAMS:
            self._freeze(**{name: _number(self.kind, name, values[name], positive)})
        for name, default in self.OPTIONAL.items():
            raw = values.get(name, default)
            if isinstance(raw, (int, float)) and not isinstance(raw, bool) and raw < 0:
                raise ModelError(f"{self.kind}: {name} must be >= 0, got {_short(raw)}")
            self._freeze(**{name: _number(self.kind, name, raw, False)})

    def forward_state(self) -> object:
        """A fresh state for block-wise :meth:`forward` runs.

        Returns
        -------
        object
            None here: the element has no state (elements with one return theirs).
        """
        return None

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping.

        Returns
        -------
        dict
            ``type``, every parameter of PARAMS, and each of OPTIONAL that differs from its default
            (units in the names).
        """
        out = {"type": self.kind, **{name: getattr(self, name) for name, _ in self.PARAMS}}
        out.update({name: getattr(self, name) for name, default in self.OPTIONAL.items() if getattr(self, name) != default})
        return out

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The element from a model-file mapping.

        Parameters
        ----------
        d : mapping
            ``type``, every parameter of PARAMS and any of OPTIONAL (units in the names).

        Returns
        -------
        element
            An instance of the class it is called on.

        Raises
        ------
        ModelError
            For missing or unknown keys, or a value that is not a number within PARAMETER_BOUNDS.
        """
        _check_keys(cls.kind, d, [name for name, _ in cls.PARAMS], cls.OPTIONAL)
        return cls(**{name: d[name] for name in [n for n, _ in cls.PARAMS] + [n for n in cls.OPTIONAL if n in d]})


class _StepFunction(Protocol):
    """The per-sample inverse of a :class:`_FunctionStream`: ``t_s`` (s) and an output sample in, the input out."""

    def __call__(self, t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> Optional[float]: ...


class _FunctionStream:
    """Streaming inverse of an element with a per-sample function ``f(t_s, y, aux) -> x``."""

    def __init__(self, step: _StepFunction, reset: Callable[[], None] = lambda: None) -> None:
        self.step, self.reset = step, reset


class GainElement(_SimpleElement):
    """Linear gain: y = gain * x (e.g. a thin-film sensor's kappa, V/N, seed 002)."""

    kind = "gain"
    PARAMS = (("gain", True),)
    gain: float

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: object = None) -> _FloatArray:
        """The input times the gain, ``gain * x``.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s]; not used.
        x : (n,) array_like of float
            Input [e.g. N, with the gain in V/N].
        aux : mapping, optional
            Not used.
        state : object, optional
            Not used.

        Returns
        -------
        (n,) ndarray of float
            Output [e.g. V].
        """
        return self.gain * np.asarray(x, dtype=float)

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> _FloatArray:
        """The output divided by the gain, ``y / gain``.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s]; not used.
        y : (n,) array_like of float
            Output [e.g. V].
        aux : mapping, optional
            Not used.

        Returns
        -------
        (n,) ndarray of float
            Input [e.g. N, with the gain in V/N].
        """
        return np.asarray(y, dtype=float) / self.gain

    def streaming(self) -> ElementStream:
        """The per-sample inverse, ``value / gain``.

        Returns
        -------
        ElementStream
            A stateless stream [output unit in, input unit out].
        """
        g = self.gain
        return _FunctionStream(lambda t_s, y, aux=None: y / g)


class NonlinearGainElement(_SimpleElement):
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
                state: object = None) -> _FloatArray:
        """The bent curve ``x + quadratic_per_v * x**2``.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s]; not used.
        x : (n,) array_like of float
            Input [V].
        aux : mapping, optional
            Not used.
        state : object, optional
            Not used.

        Returns
        -------
        (n,) ndarray of float
            Output [V].
        """
        x = np.asarray(x, dtype=float)
        return x + self.quadratic_per_v * x * x

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> _FloatArray:
        """The root nearest ``y``, ``2 y / (1 + sqrt(1 + 4 q y))``.

        Where 1 + 4 q y < 0 (no inverse) the square root is taken as 0, so the input is ``2 y`` there.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s]; not used.
        y : (n,) array_like of float
            Output [V].
        aux : mapping, optional
            Not used.

        Returns
        -------
        (n,) ndarray of float
            Input [V].
        """
        y = np.asarray(y, dtype=float)
        disc = np.sqrt(np.clip(1.0 + 4.0 * self.quadratic_per_v * y, 0.0, None))
        return 2.0 * y / (1.0 + disc)

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`.

        Returns
        -------
        ElementStream
            A stateless stream [V in, V out].
        """
        q = self.quadratic_per_v
        return _FunctionStream(lambda t_s, y, aux=None: 2.0 * y / (1.0 + math.sqrt(max(1.0 + 4.0 * q * y, 0.0))))


class _ThermalForwardState(TypedDict):
    y: _FloatArray  # the lag's integral state, degC * s
    t_prev: Optional[float]  # s; None before the first sample
    temp_prev: float  # degC


class _LagForwardState(TypedDict):
    y: _FloatArray  # the lag's integral state, input unit * s
    t_prev: Optional[float]  # s; None before the first sample
    x_prev: float  # input unit


class _LastSample(TypedDict):
    t: Optional[float]  # s; None before the first sample
    y: float  # V


class SensorLagElement(_SimpleElement):
    """First-order sensor/electronics dynamics (seed 002, eq. 10-11 with unit gain): tau y' + y = x.

    Forward: exact for piecewise-linear x (the shared recursion), output zero
    before the first sample.

    Backward, ``noise_filter_tau_s = 0`` (default): x = y + tau dy/dt with the
    slope over the last sample interval; white noise grows by about sqrt(2) tau / h.
    With ``noise_filter_tau_s = tau_f > 0`` the inverse is rolled off into
    (1 + tau s) / (1 + tau_f s) = tau/tau_f + (1 - tau/tau_f) / (1 + tau_f s):
    a weighted sum of y and of y through a lag of tau_f, run with the same
    exact recursion. Noise then grows by at most tau / tau_f, and the
    bandwidth ends near 1 / (2 pi tau_f). With ``noise_filter_order = 2`` the
    roll-off is (1 + tau s) / (1 + tau_f s)**2 = (tau/tau_f) L + (1 - tau/tau_f) L L,
    L a lag of tau_f: the inverse falls off above 1 / (2 pi tau_f) instead of
    staying at tau / tau_f, so white noise passes far less for the same tau_f
    (the compensated force then follows the applied one through 1 / (1 + tau_f s)**2,
    about 2 tau_f late). All assume y constant before its first sample (no
    start-up transient).
    """

    kind = "sensor_lag"
    PARAMS = (("tau_s", True),)
    OPTIONAL = {"noise_filter_tau_s": 0.0, "noise_filter_order": 1.0}
    tau_s: float
    noise_filter_tau_s: float
    noise_filter_order: float

    def __init__(self, **values: float) -> None:
        super().__init__(**values)
        if self.noise_filter_order not in (1.0, 2.0):
            raise ModelError(f"{self.kind}: noise_filter_order must be 1 or 2, got {_short(self.noise_filter_order)}")

    @property
    def latency_s(self) -> float:
        """How late the compensated signal follows: ``noise_filter_order * noise_filter_tau_s`` [s]."""
        return self.noise_filter_order * self.noise_filter_tau_s

    def forward_state(self) -> _LagForwardState:
        """A fresh lag state (output zero, no previous sample) for block-wise :meth:`forward` runs.

        Returns
        -------
        dict
            ``y``: the lag's integral state (1,) [input unit * s]; ``t_prev``: the last sample time [s]
            (None before the first); ``x_prev``: the last input [input unit].
        """
        return {"y": np.zeros(1), "t_prev": None, "x_prev": 0.0}

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_LagForwardState] = None) -> _FloatArray:
        """Output of the lag tau y' + y = x, exact for piecewise-linear ``x``.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s], non-decreasing.
        x : (n,) array_like of float
            Input [any unit, usually V].
        aux : mapping, optional
            Not used.
        state : dict, optional
            From :meth:`forward_state`, carries the lag across blocks (updated in place); a lag at
            zero output when omitted.

        Returns
        -------
        (n,) ndarray of float
            Output [the input's unit].
        """
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        st = state if state is not None else self.forward_state()
        rate = 1.0 / self.tau_s
        if st["t_prev"] is None:
            y = exp_convolve(t, x, [rate], y0=st["y"])[:, 0]
        else:
            y = exp_convolve(t, x, [rate], y0=st["y"], u_prev=st["x_prev"], t_prev_s=st["t_prev"])[:, 0]
        y = y * rate
        if t.size:
            st["y"] = np.array([y[-1] / rate])
            st["t_prev"], st["x_prev"] = float(t[-1]), float(x[-1])
        return y

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> _FloatArray:
        """The input ``y + tau dy/dt`` over the record, or its roll-off when ``noise_filter_tau_s`` > 0.

        The slope is taken over each previous interval (0 at the first sample and over a
        zero-length interval); the roll-off is described in the class docstring.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s].
        y : (n,) array_like of float
            Output [any unit, usually V].
        aux : mapping, optional
            Not used.

        Returns
        -------
        (n,) ndarray of float
            Input [the output's unit].
        """
        t, y = np.asarray(t_s, dtype=float), np.asarray(y, dtype=float)
        tau_f = self.noise_filter_tau_s
        if tau_f > 0.0:
            if y.size == 0:
                return y.copy()
            # the lag starts settled at y[0]: its integral state is y[0] * tau_f
            lagged = exp_convolve(t, y, [1.0 / tau_f], y0=[y[0] * tau_f])[:, 0] / tau_f
            if self.noise_filter_order == 2.0:
                twice = exp_convolve(t, lagged, [1.0 / tau_f], y0=[y[0] * tau_f])[:, 0] / tau_f
                return (self.tau_s / tau_f) * lagged + (1.0 - self.tau_s / tau_f) * twice
            return (self.tau_s / tau_f) * y + (1.0 - self.tau_s / tau_f) * lagged
        slope = np.zeros_like(y)
        if y.size > 1:
            dt = np.diff(t)
            slope[1:] = np.where(dt > 0, np.diff(y) / np.where(dt > 0, dt, 1.0), 0.0)
        return y + self.tau_s * slope

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward` (slope over the last interval, or the rolled-off inverse).

        Returns
        -------
        ElementStream
            A fresh stream [output unit in, input unit out]; its ``reset`` forgets the previous sample.
        """
        tau, tau_f = self.tau_s, self.noise_filter_tau_s
        if tau_f > 0.0 and self.noise_filter_order == 2.0:
            first, second = ExpConvState([1.0 / tau_f]), ExpConvState([1.0 / tau_f])
            w_once, w_twice = tau / tau_f, 1.0 - tau / tau_f

            def filtered2(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
                if first.t_prev_s is None:
                    first.reset([y * tau_f])
                    second.reset([y * tau_f])
                state = first.update(t_s, y)
                once = (state if state is not None else first.y)[0] / tau_f
                state = second.update(t_s, once)
                twice = (state if state is not None else second.y)[0] / tau_f
                return w_once * once + w_twice * twice

            def reset2() -> None:
                first.reset()
                second.reset()

            return _FunctionStream(filtered2, reset2)
        if tau_f > 0.0:
            lag = ExpConvState([1.0 / tau_f])
            w_direct, w_lag = tau / tau_f, 1.0 - tau / tau_f

            def filtered(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
                if lag.t_prev_s is None:
                    lag.reset([y * tau_f])
                state = lag.update(t_s, y)
                if state is None:  # time went backwards: the lag holds, as over a zero-length step
                    state = lag.y
                return w_direct * y + w_lag * state[0] / tau_f

            return _FunctionStream(filtered, lag.reset)

        prev: _LastSample = {"t": None, "y": 0.0}

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
            slope = 0.0
            if prev["t"] is not None and t_s > prev["t"]:
                slope = (y - prev["y"]) / (t_s - prev["t"])
            prev["t"], prev["y"] = t_s, y
            return y + tau * slope

        # a TypedDict's update takes a mapping, not keywords
        return _FunctionStream(step, lambda: prev.update({"t": None, "y": 0.0}))


class _DelayForwardState(TypedDict):
    t: _FloatArray  # s; the input samples of the last delay_s (the interpolation's support)
    x: _FloatArray  # input unit


class TransportDelayElement(_SimpleElement):
    """A pure delay (DAQ buffering, transport): y(t) = x(t - delay_s).

    Forward: the input interpolated linearly at ``t - delay_s``, held at its first sample
    before it (a settled sensor). Backward: a delay cannot be undone without predicting the
    future, so the inverse passes the signal unchanged and the chain states the latency
    (:attr:`SensorChain.latency_s`) instead of boosting noise to fake a prediction.
    """

    kind = "transport_delay"
    PARAMS = (("delay_s", True),)
    delay_s: float

    def forward_state(self) -> _DelayForwardState:
        """A fresh delay state (no input seen) for block-wise :meth:`forward` runs."""
        return {"t": np.zeros(0), "x": np.zeros(0)}

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_DelayForwardState] = None) -> _FloatArray:
        """The input delayed by ``delay_s`` (linear interpolation; the first input before the record); ``state``
        carries the last ``delay_s`` of input across blocks (see :meth:`Element.forward`)."""
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        st = state if state is not None else self.forward_state()
        if t.size == 0:
            return x.copy()
        support_t, support_x = np.concatenate([st["t"], t]), np.concatenate([st["x"], x])
        y = np.interp(t - self.delay_s, support_t, support_x, left=support_x[0])
        keep = support_t >= t[-1] - self.delay_s
        keep[max(int(np.argmax(keep)) - 1, 0)] = True  # one sample before the window: the interpolation's left end
        st["t"], st["x"] = support_t[keep], support_x[keep]
        return y

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> _FloatArray:
        """The output unchanged: the delay stays, stated as latency, never undone by amplifying noise."""
        return np.array(y, dtype=float)

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward` (the sample unchanged)."""
        return _FunctionStream(lambda t_s, y, aux=None: y)


def _temperature(aux: Optional[Mapping[str, Any]], n: int) -> Optional[_FloatArray]:
    """Temperature samples (degC) from ``aux``: an array of n, a scalar, or None when absent."""
    if not aux or aux.get("temperature_c") is None:
        return None
    return np.broadcast_to(np.asarray(aux["temperature_c"], dtype=float), (n,)) if n else np.zeros(0)


class ThermalDriftElement(_SimpleElement):
    """Output that follows temperature: y = x + coefficient_v_per_c * (T - reference_c).

    T comes from ``aux['temperature_c']``; without it T is taken as the
    reference (no correction), which the node reports.
    """

    kind = "thermal_drift"
    PARAMS = (("coefficient_v_per_c", False), ("reference_c", False))
    coefficient_v_per_c: float
    reference_c: float

    def _term(self, y: _FloatArray, aux: Optional[Mapping[str, Any]]) -> _FloatOrArray:
        temp = _temperature(aux, np.size(y))
        return 0.0 if temp is None else self.coefficient_v_per_c * (temp - self.reference_c)

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: object = None) -> _FloatArray:
        """The input plus the thermal term, ``x + coefficient_v_per_c * (T - reference_c)``.

        Without a temperature ``x`` passes unchanged.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s]; not used.
        x : (n,) array_like of float
            Input [V].
        aux : mapping of str to array_like, optional
            ``temperature_c``: T, (n,) or a scalar [degC].
        state : object, optional
            Not used.

        Returns
        -------
        (n,) ndarray of float
            Output [V].
        """
        x = np.asarray(x, dtype=float)
        return x + self._term(x, aux)

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> _FloatArray:
        """The output less the thermal term, ``y - coefficient_v_per_c * (T - reference_c)``.

        Without a temperature ``y`` passes unchanged.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s]; not used.
        y : (n,) array_like of float
            Output [V].
        aux : mapping of str to array_like, optional
            ``temperature_c``: T, (n,) or a scalar [degC].

        Returns
        -------
        (n,) ndarray of float
            Input [V].
        """
        y = np.asarray(y, dtype=float)
        return y - self._term(y, aux)

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`; a sample without ``aux['temperature_c']`` passes unchanged.

        Returns
        -------
        ElementStream
            A stateless stream [V in, V out].
        """
        c, ref = self.coefficient_v_per_c, self.reference_c

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
            temp = None if not aux else aux.get("temperature_c")
            return y if temp is None else y - c * (temp - ref)

        return _FunctionStream(step)


#: The least span factor 1 + c (T - T_ref) the inverse divides by: a temperature far outside the calibrated range
#: must not turn the division into a huge gain.
_MIN_SPAN_FACTOR = 0.2


class ThermalSensitivityElement(_SimpleElement):
    """A span that changes with temperature: y = x (1 + span_coefficient_per_c (T - reference_c)).

    The load cell datasheets' "temperature effect on sensitivity", beside the zero's
    (:class:`ThermalDriftElement`). T comes from ``aux['temperature_c']``; without it T is
    taken as the reference (no correction). The inverse divides by the span factor, held at
    least ``_MIN_SPAN_FACTOR`` (0.2) so a temperature far outside the calibration never
    multiplies the force by more than 5.
    """

    kind = "thermal_sensitivity"
    PARAMS = (("span_coefficient_per_c", False), ("reference_c", False))
    span_coefficient_per_c: float
    reference_c: float

    def _factor(self, n: int, aux: Optional[Mapping[str, Any]]) -> _FloatOrArray:
        temp = _temperature(aux, n)
        if temp is None:
            return 1.0
        return np.maximum(1.0 + self.span_coefficient_per_c * (temp - self.reference_c), _MIN_SPAN_FACTOR)

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: object = None) -> _FloatArray:
        """The input scaled by the span factor at each sample's temperature (unchanged without one)."""
        x = np.asarray(x, dtype=float)
        return x * self._factor(x.size, aux)

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> _FloatArray:
        """The output divided by the span factor (unchanged without a temperature)."""
        y = np.asarray(y, dtype=float)
        return y / self._factor(y.size, aux)

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`; a sample without ``aux['temperature_c']`` passes unchanged."""
        c, ref = self.span_coefficient_per_c, self.reference_c

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
            temp = None if not aux else aux.get("temperature_c")
            return y if temp is None else y / max(1.0 + c * (temp - ref), _MIN_SPAN_FACTOR)

        return _FunctionStream(step)


class _DriftForwardState(TypedDict):
    t_first: Optional[float]  # s; None before the first sample


class _TimeDriftElement(_SimpleElement):
    """Base of the load-independent drifts: y = x + _term(t - t_first), t_first the first sample of the
    record (forward, batch backward) or after a reset (streaming); subclasses define ``_term(s)`` (V)."""

    def _term(self, s: _FloatOrArray) -> _FloatOrArray:
        """The drift [V] at ``s`` [s] after the first sample: a float for a float, an array for an array."""
        raise NotImplementedError(f"{type(self).__name__} defines no drift term")

    def forward_state(self) -> _DriftForwardState:
        """A fresh state for block-wise :meth:`forward` runs (no first sample yet).

        Returns
        -------
        dict
            ``t_first``: the time of the first sample [s], None until :meth:`forward` has seen one.
        """
        return {"t_first": None}

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_DriftForwardState] = None) -> _FloatArray:
        """The input plus the drift at the time since the first sample.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s].
        x : (n,) array_like of float
            Input [V].
        aux : mapping, optional
            Not used.
        state : dict, optional
            From :meth:`forward_state`: keeps the first sample's time across blocks (set in place
            on the first block); the call's first sample when omitted.

        Returns
        -------
        (n,) ndarray of float
            Output [V].
        """
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        st = state if state is not None else self.forward_state()
        if st["t_first"] is None and t.size:
            st["t_first"] = float(t[0])
        return x + self._term(t - (st["t_first"] or 0.0))

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> _FloatArray:
        """The output less the drift, the time counted from the record's first sample.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s].
        y : (n,) array_like of float
            Output [V].
        aux : mapping, optional
            Not used.

        Returns
        -------
        (n,) ndarray of float
            Input [V].
        """
        t, y = np.asarray(t_s, dtype=float), np.asarray(y, dtype=float)
        return y - self._term(t - t[0]) if t.size else y

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`, the time counted from the first sample after a reset.

        Returns
        -------
        ElementStream
            A fresh stream [V in, V out]; its ``reset`` (a tare) restarts the time.
        """
        first: dict[str, Optional[float]] = {"t": None}

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
            # read once into a local: mypy does not narrow first["t"] after assigning it
            t_first = first["t"]
            if t_first is None:
                t_first = first["t"] = t_s
            return y - float(self._term(t_s - t_first))

        return _FunctionStream(step, lambda: first.update(t=None))


class OffsetDriftElement(_TimeDriftElement):
    """Load-independent baseline drift: y = x + rate_v_per_s * (t - t_first).

    t_first is the first sample of the record (forward, batch backward) or the
    first sample after a reset (streaming); a tare therefore restarts it.
    """

    kind = "offset_drift"
    PARAMS = (("rate_v_per_s", False),)
    rate_v_per_s: float

    def _term(self, s: _FloatOrArray) -> _FloatOrArray:
        return self.rate_v_per_s * s


class _PreisachForwardState(TypedDict):
    stream: Union[PreisachStream, ContinuousPreisachStream]


class PreisachElement(_Frozen):
    """Rate-independent hysteresis (seed 001): a Preisach operator from input to output (same or any units).

    ``continuous`` selects ramp hysterons and their exact inverse; otherwise the
    discrete relays and the closest-match inverse (quantised to the levels).
    Forward and backward start from all relays down (an unloaded sensor).
    """

    kind = "preisach"
    KEYS = ("u_min", "u_max", "n_levels", "offset", "density", "continuous")
    model: PreisachModel
    continuous: bool

    def __init__(self, model: PreisachModel, continuous: bool = True) -> None:
        self._freeze(model=model, continuous=bool(continuous))

    def forward_state(self) -> _PreisachForwardState:
        """A fresh state for block-wise :meth:`forward` runs (all relays down).

        Returns
        -------
        dict
            ``stream``: a fresh operator stream of the model (continuous or discrete per ``continuous``).
        """
        return {"stream": self.model.stream(self.continuous)}

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_PreisachForwardState] = None) -> _FloatArray:
        """Preisach output for each input sample (discrete or continuous per ``continuous``).

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s]; not used.
        x : (n,) array_like of float
            Input [the model's input unit: N or V].
        aux : mapping, optional
            Not used.
        state : dict, optional
            From :meth:`forward_state`: its stream carries the relays across blocks; all relays down
            when omitted.

        Returns
        -------
        (n,) ndarray of float
            Output [the model's output unit: N or V].
        """
        stream = (state or self.forward_state())["stream"]
        return np.array([stream.forward(float(v)) for v in np.asarray(x, dtype=float)])

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> _FloatArray:
        """The inverse of each output sample, from all relays down (closest-match, or exact when ``continuous``).

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s]; not used.
        y : (n,) array_like of float
            Output [the model's output unit: N or V].
        aux : mapping, optional
            Not used.

        Returns
        -------
        (n,) ndarray of float
            Input [the model's input unit: N or V].
        """
        stream = self.model.stream(self.continuous)
        return np.array([stream.inverse(float(v)) for v in np.asarray(y, dtype=float)])

    def streaming(self) -> ElementStream:
        """The per-sample inverse of the operator.

        Returns
        -------
        ElementStream
            A fresh stream (all relays down) [output unit in, input unit out]; its ``reset`` puts all
            relays down.
        """
        stream = self.model.stream(self.continuous)
        return _FunctionStream(lambda t_s, y, aux=None: stream.inverse(y), stream.reset)

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping.

        Returns
        -------
        dict
            ``type``, the keys of :meth:`PreisachModel.to_dict` and ``continuous``.
        """
        return {"type": self.kind, **self.model.to_dict(), "continuous": self.continuous}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The element from a model-file mapping.

        Parameters
        ----------
        d : mapping
            ``type`` and the keys ``u_min, u_max, n_levels, offset, density, continuous``
            (input and output in N or V).

        Returns
        -------
        PreisachElement
            The element.

        Raises
        ------
        ModelError
            For missing or unknown keys, a density that is not a list of numbers, n_levels
            outside [1, MAX_PREISACH_LEVELS], a non-boolean continuous, or values out of range
            or rejected by :class:`~.preisach.PreisachModel`.
        """
        from .preisach import PreisachModel

        _check_keys(cls.kind, d, cls.KEYS)
        if not isinstance(d["density"], list) or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                                         for v in d["density"]):
            raise ModelError("preisach: density must be a list of numbers")
        n_levels = d["n_levels"]
        if isinstance(n_levels, bool) or not isinstance(n_levels, int) or not 1 <= n_levels <= MAX_PREISACH_LEVELS:
            raise ModelError(f"preisach: n_levels must be an integer in [1, {MAX_PREISACH_LEVELS}] "
                             f"(the operator costs O(n**2) per sample), got {_short(n_levels)}")
        if not isinstance(d["continuous"], bool):
            raise ModelError("preisach: continuous must be true or false")
        for key in ("u_min", "u_max", "offset"):
            _number(cls.kind, key, d[key], positive=False)
        for value in d["density"]:
            _number(cls.kind, "density", value, positive=False)
        try:
            model = PreisachModel.from_dict(d)
        except (ValueError, ArithmeticError) as exc:
            raise ModelError(f"preisach: {exc}") from exc
        return cls(model, d["continuous"])


def play_operator(x: npt.ArrayLike, radii: npt.ArrayLike, y0: Optional[npt.ArrayLike] = None,
                  chunk: Optional[int] = None) -> _FloatArray:
    """Play (backlash) operators of half-widths ``radii`` on the sequence ``x``.

    ``y_k = min(max(y_{k-1}, x_k - r), x_k + r)``, starting from ``y0`` before
    the first sample. Each step is a clamp, and clamps compose into clamps, so
    the sequence is a prefix composition, computed with log2(chunk) vectorised
    doubling passes per chunk (no Python loop over samples).

    Parameters
    ----------
    x : (n,) array_like of float
        Input sequence [any unit, e.g. N or V].
    radii : (m,) array_like of float
        Half-widths of the plays [the input's unit].
    y0 : (m,) array_like of float, optional
        Each play's state before the first sample [the input's unit]; zeros when omitted.
    chunk : int, optional
        Samples per vectorised chunk. By default about 2**15 values (chunk x m): the passes then run in
        cache, and fewer of them (512-sample chunks of 44 plays run 3x faster than 32768-sample ones).

    Returns
    -------
    (n, m) ndarray of float
        Each play's output at each sample [the input's unit].
    """
    x = np.asarray(x, dtype=float)
    r = np.atleast_1d(np.asarray(radii, dtype=float))
    y = np.zeros(r.size) if y0 is None else np.array(y0, dtype=float)
    out = np.empty((x.size, r.size))
    if x.size == 0:
        return out
    if chunk is None:
        chunk = 1 << max(6, int(math.log2(max(1, (1 << 15) // max(r.size, 1)))))
    width = min(chunk, x.size)
    lo_buf, hi_buf, tmp = (np.empty((width, r.size)) for _ in range(3))
    for start in range(0, x.size, chunk):
        xc = x[start:start + chunk, None]
        n = xc.shape[0]
        lo, hi = lo_buf[:n], hi_buf[:n]
        np.subtract(xc, r, out=lo)
        np.add(xc, r, out=hi)
        shift = 1
        while shift < n:
            # the block ending at k composed after the block ending at k - shift, in place:
            #   hi[k] <- min(max(hi[k - shift], lo[k]), hi[k]);  lo[k] <- min(max(lo[k - shift], lo[k]), hi[k])
            # (the new hi may clamp the new lo: max(lo[k - shift], lo[k]) <= max(hi[k - shift], lo[k]))
            m, a = n - shift, tmp[:n - shift]
            np.maximum(hi[:m], lo[shift:], out=a)
            np.minimum(a, hi[shift:], out=hi[shift:])
            np.maximum(lo[:m], lo[shift:], out=a)
            np.minimum(a, hi[shift:], out=lo[shift:])
            shift *= 2
        block = out[start:start + n]
        np.maximum(y, lo, out=block)
        np.minimum(block, hi, out=block)
        y = block[-1].copy()
    return out


def _float_list(kind: str, key: str, values: object, positive: bool) -> _FloatArray:
    if not isinstance(values, (list, tuple, np.ndarray)) or len(values) == 0:
        raise ModelError(f"{kind}: {key} must be a non-empty list of numbers, got {_short(values)}")
    if len(values) > MAX_PREISACH_LEVELS:
        raise ModelError(f"{kind}: {key} holds {len(values)} values; at most {MAX_PREISACH_LEVELS}")
    return np.array([_number(kind, key, v.item() if isinstance(v, np.generic) else v, positive) for v in list(values)])


def _abscissae_and_values(kind: str, x_key: str, x: object, y_key: str, y: object) -> tuple[_FloatArray, _FloatArray]:
    """Two number lists of one length: ``x`` positive and strictly increasing, ``y`` any finite values."""
    x = _float_list(kind, x_key, x, positive=True)
    y = _float_list(kind, y_key, y, positive=False)
    if x.size != y.size:
        raise ModelError(f"{kind}: {x_key} and {y_key} must have the same length ({x.size} != {y.size})")
    if np.any(np.diff(x) <= 0):
        raise ModelError(f"{kind}: {x_key} must be strictly increasing")
    return x, y


class _PlayForwardState(TypedDict):
    y: _FloatArray  # forward play states, input unit


class PlayHysteresisElement(_Frozen):
    """Rate-independent hysteresis as a Prandtl-Ishlinskii operator: a weighted sum of play operators.

        y = linear_weight * x + sum_i weights[i] * play_{radii[i]}[x]

    Parameters (model file keys)
    ----------------------------
    linear_weight : float > 0
        Weight of the input itself (the reversible part), output unit per input unit.
    radii : list of float > 0, strictly increasing
        Half-widths of the play (backlash) operators, in the input unit (N on the
        force path, V on the voltage path).
    weights : list of float
        Weight of each play operator (same length as ``radii``). Positive weights
        steepen the curve after a reversal (loading below unloading, the play
        type); negative weights flatten it (a stop-type or Bouc-Wen-like loop,
        loading above unloading). Every partial sum ``linear_weight + weights[0]
        + ... + weights[i]`` (the slope once the input has moved ``2 radii[i]``
        from a reversal) must be at least 1e-6: the operator is then strictly
        monotone and invertible.
    history_max : float >= 0, optional
        The input's history before the record: 0 (default) is a virgin sensor
        (every play at zero); a value M means the input came down from M to 0
        before the record (every play of radius r <= M/2 then starts at r).

    Every play operator starts at zero before the first sample (an unloaded
    sensor). With positive partial sums the operator is monotone and its inverse
    is again a Prandtl-Ishlinskii operator (Kuhnen 2003): radii
    ``r'_i = sum_{j<=i} a_j (r_i - r_j)`` (a_0 = linear_weight, r_0 = 0) and weights
    ``b_0 = 1/a_0``, ``b_i = -a_i / (A_i A_{i-1})`` with ``A_i = sum_{j<=i} a_j``,
    exact for the same initial state. ``backward`` (batch) and ``streaming()``
    (O(n) per sample) both run it.
    """

    kind = "play_hysteresis"
    KEYS = ("linear_weight", "radii", "weights")
    OPTIONAL = {"history_max": 0.0}
    linear_weight: float
    radii: _FloatArray
    weights: _FloatArray
    history_max: float

    def __init__(self, linear_weight: float, radii: _Numbers, weights: _Numbers, history_max: float = 0.0) -> None:
        linear_weight = _number(self.kind, "linear_weight", linear_weight, positive=True)
        radii, weights = _abscissae_and_values(self.kind, "radii", radii, "weights", weights)
        slopes = linear_weight + np.cumsum(weights)
        if np.any(slopes < 1e-6):
            raise ModelError(f"{self.kind}: every partial sum linear_weight + weights[0] + ... + weights[i] must be "
                             f">= 1e-6 (a monotone, invertible operator); the smallest is {slopes.min():.6g}")
        history_max = _number(self.kind, "history_max", history_max, positive=False)
        if history_max < 0:
            raise ModelError(f"{self.kind}: history_max must be >= 0")
        self._freeze(linear_weight=linear_weight, radii=radii, weights=weights, history_max=history_max)

    def _history(self) -> _FloatArray:
        """Input samples before the record: 0, then up to history_max and back to 0 (none when 0)."""
        return np.array([0.0, self.history_max, 0.0]) if self.history_max > 0 else np.zeros(0)

    def initial_states(self) -> tuple[_FloatArray, _FloatArray]:
        """The play states after the ``history_max`` history (zeros for a virgin sensor).

        Returns
        -------
        forward : (m,) ndarray of float
            States of the forward plays (half-widths ``radii``) [input unit].
        inverse : (m,) ndarray of float
            States of the inverse plays (radii from :meth:`inverse_parameters`) [output unit].
        """
        h = self._history()
        fwd = play_operator(h, self.radii)[-1] if h.size else np.zeros(self.radii.size)
        b0, r_inv, b = self.inverse_parameters()
        if h.size:
            y_hist = self.linear_weight * h + play_operator(h, self.radii) @ self.weights
            inv = play_operator(y_hist, np.where(r_inv > 0, r_inv, 1e-300))[-1]
        else:
            inv = np.zeros(r_inv.size)
        return fwd, inv

    def inverse_parameters(self) -> tuple[float, _FloatArray, _FloatArray]:
        """The parameters of the inverse Prandtl-Ishlinskii operator (formulas in the class docstring).

        Returns
        -------
        b0 : float
            Weight of the output itself, ``1 / linear_weight`` [input unit per output unit].
        radii : (m,) ndarray of float
            Half-widths ``r'_i`` of the inverse plays [output unit].
        weights : (m,) ndarray of float
            Weights ``b_i`` of the inverse plays [input unit per output unit].
        """
        a = np.concatenate([[self.linear_weight], self.weights])
        r = np.concatenate([[0.0], self.radii])
        cum = np.cumsum(a)
        r_inv = np.array([np.sum(a[: i + 1] * (r[i] - r[: i + 1])) for i in range(1, r.size)])
        b = -a[1:] / (cum[1:] * cum[:-1])
        return 1.0 / a[0], r_inv, b

    def forward_state(self) -> _PlayForwardState:
        """A fresh state for block-wise :meth:`forward` runs.

        Returns
        -------
        dict
            ``y``: the forward play states after the ``history_max`` history (zeros for a virgin
            sensor), (m,) [input unit].
        """
        return {"y": self.initial_states()[0]}

    def _rest_output(self) -> float:
        """Sum of the weighted play states after the history: subtracted so that y = 0 at x = 0 at the start."""
        return float(self.initial_states()[0] @ self.weights)

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_PlayForwardState] = None) -> _FloatArray:
        """Prandtl-Ishlinskii output ``linear_weight * x + sum_i weights[i] * play_i[x]``.

        Shifted so that y = 0 at x = 0 after the history.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s]; not used.
        x : (n,) array_like of float
            Input [N or V].
        aux : mapping, optional
            Not used.
        state : dict, optional
            From :meth:`forward_state`: carries the play states across blocks (updated in place);
            the states after the history when omitted.

        Returns
        -------
        (n,) ndarray of float
            Output [N or V].
        """
        x = np.asarray(x, dtype=float)
        st = state if state is not None else self.forward_state()
        plays = play_operator(x, self.radii, st["y"])
        if x.size:
            st["y"] = plays[-1].copy()
        return self.linear_weight * x + plays @ self.weights - self._rest_output()

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> _FloatArray:
        """The input for output ``y`` over the record, by the inverse Prandtl-Ishlinskii operator.

        The inverse starts from the states after the history (see the class docstring).

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s]; not used.
        y : (n,) array_like of float
            Output [N or V].
        aux : mapping, optional
            Not used.

        Returns
        -------
        (n,) ndarray of float
            Input [N or V].
        """
        y = np.asarray(y, dtype=float) + self._rest_output()
        b0, r_inv, b = self.inverse_parameters()
        keep = r_inv > 0  # r' > 0 for every i >= 1 (radii > 0, linear_weight > 0)
        return b0 * y + play_operator(y, r_inv[keep], self.initial_states()[1][keep]) @ b[keep]

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`, O(m) per sample for m plays.

        Returns
        -------
        ElementStream
            A fresh stream [output unit in, input unit out]; its ``reset`` returns to the states after
            the history.
        """
        b0, r_inv, b = self.inverse_parameters()
        keep = r_inv > 0
        radii, weights = [float(v) for v in r_inv[keep]], [float(v) for v in b[keep]]
        start = [float(v) for v in self.initial_states()[1][keep]]
        state = list(start)
        rest = self._rest_output()

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
            y = y + rest
            total = b0 * y
            for i, (r, w) in enumerate(zip(radii, weights)):
                p = min(max(state[i], y - r), y + r)
                state[i] = p
                total += w * p
            return total

        def reset() -> None:
            state[:] = start

        return _FunctionStream(step, reset)

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping.

        Returns
        -------
        dict
            ``type``, ``linear_weight``, ``radii`` and ``weights`` as floats, and ``history_max`` when not 0.
        """
        out = {"type": self.kind, "linear_weight": float(self.linear_weight), "radii": [float(v) for v in self.radii],
               "weights": [float(v) for v in self.weights]}
        if self.history_max:
            out["history_max"] = float(self.history_max)
        return out

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The element from a model-file mapping.

        Parameters
        ----------
        d : mapping
            ``type``, ``linear_weight``, ``radii``, ``weights`` and optionally ``history_max`` (as :meth:`to_dict`).

        Returns
        -------
        PlayHysteresisElement
            The element.

        Raises
        ------
        ModelError
            For missing or unknown keys, lists that are empty, too long or of different lengths,
            values out of range, radii not strictly increasing, or weights that make the operator
            not monotone.
        """
        _check_keys(cls.kind, d, cls.KEYS, cls.OPTIONAL)
        return cls(d["linear_weight"], d["radii"], d["weights"], d.get("history_max", 0.0))


class ThermalLagElement(_SimpleElement):
    """Output that follows temperature through a first-order thermal lag:
    y = x + coefficient_v_per_c * (T_lag - reference_c), tau_s T_lag' + T_lag = T.

    T comes from ``aux['temperature_c']``; the lag starts settled at the first
    temperature sample (batch, or the first after a reset when streaming).
    Without temperature there is no correction (as :class:`ThermalDriftElement`).
    """

    kind = "thermal_lag"
    PARAMS = (("coefficient_v_per_c", False), ("reference_c", False), ("tau_s", True))
    coefficient_v_per_c: float
    reference_c: float
    tau_s: float

    def _lagged(self, t_s: npt.ArrayLike, temp: Optional[_FloatArray],
                state: Optional[_ThermalForwardState] = None) -> Optional[_FloatArray]:
        t = np.asarray(t_s, dtype=float)
        if temp is None or t.size == 0:
            return None
        rate = 1.0 / self.tau_s
        if state is None or state["t_prev"] is None:  # settled at the first temperature
            y = exp_convolve(t, temp, [rate], y0=[temp[0] * self.tau_s])[:, 0]
        else:
            y = exp_convolve(t, temp, [rate], y0=state["y"], u_prev=state["temp_prev"], t_prev_s=state["t_prev"])[:, 0]
        if state is not None:
            state["y"], state["t_prev"], state["temp_prev"] = np.array([y[-1]]), float(t[-1]), float(temp[-1])
        return y * rate

    def forward_state(self) -> _ThermalForwardState:
        """A fresh lag state for block-wise :meth:`forward` runs (settles at the first temperature it sees).

        Returns
        -------
        dict
            ``y``: the lag's integral state (1,) [degC s]; ``t_prev``: the last sample time [s] (None
            before the first); ``temp_prev``: the last temperature [degC].
        """
        return {"y": np.zeros(1), "t_prev": None, "temp_prev": 0.0}

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_ThermalForwardState] = None) -> _FloatArray:
        """The input plus the lagged thermal term, ``x + coefficient_v_per_c * (T_lag - reference_c)``.

        The lag starts settled at the first temperature (of the call, or of the first block
        when a state is given); ``x`` passes unchanged without ``aux['temperature_c']``.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s], non-decreasing.
        x : (n,) array_like of float
            Input [V].
        aux : mapping of str to array_like, optional
            ``temperature_c``: T, (n,) or a scalar [degC].
        state : dict, optional
            From :meth:`forward_state`, carries the lag across blocks (updated in place); without
            it the lag starts settled at this call's first temperature.

        Returns
        -------
        (n,) ndarray of float
            Output [V].
        """
        x = np.asarray(x, dtype=float)
        lagged = self._lagged(t_s, _temperature(aux, x.size), state)
        return x if lagged is None else x + self.coefficient_v_per_c * (lagged - self.reference_c)

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> _FloatArray:
        """The output less the lagged thermal term, ``y - coefficient_v_per_c * (T_lag - reference_c)``.

        The lag starts settled at the first temperature; ``y`` passes unchanged without
        ``aux['temperature_c']``.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s], non-decreasing.
        y : (n,) array_like of float
            Output [V].
        aux : mapping of str to array_like, optional
            ``temperature_c``: T, (n,) or a scalar [degC].

        Returns
        -------
        (n,) ndarray of float
            Input [V].
        """
        y = np.asarray(y, dtype=float)
        lagged = self._lagged(t_s, _temperature(aux, y.size))
        return y if lagged is None else y - self.coefficient_v_per_c * (lagged - self.reference_c)

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`; the lag starts settled at the first temperature after a reset.

        Returns
        -------
        ElementStream
            A fresh stream [V in, V out]; a sample without ``aux['temperature_c']`` passes unchanged.
        """
        c, ref, tau = self.coefficient_v_per_c, self.reference_c, self.tau_s
        lag = ExpConvState([1.0 / tau])

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
            temp = None if not aux else aux.get("temperature_c")
            if temp is None:
                return y
            if lag.t_prev_s is None:
                lag.reset([temp * tau])
            state = lag.update(t_s, float(temp))
            if state is None:
                state = lag.y
            return y - c * (state[0] / tau - ref)

        return _FunctionStream(step, lag.reset)


class ExponentialDriftElement(_TimeDriftElement):
    """Baseline drift that settles: y = x + amplitude_v * (1 - exp(-(t - t_first) / tau_s)).

    t_first as in :class:`OffsetDriftElement` (first sample, or first after a reset/tare).
    """

    kind = "exponential_drift"
    PARAMS = (("amplitude_v", False), ("tau_s", True))
    amplitude_v: float
    tau_s: float

    def _term(self, s: _FloatOrArray) -> _FloatOrArray:
        return self.amplitude_v * -np.expm1(-np.asarray(s, dtype=float) / self.tau_s)



class PolynomialGainElement(_SimpleElement):
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

    def _poly(self, x: _FloatArray) -> tuple[_FloatArray, _FloatArray]:
        q, c, d = self.quadratic_per_v, self.cubic_per_v2, self.quartic_per_v3
        return x + x * x * (q + x * (c + x * d)), 1.0 + x * (2.0 * q + x * (3.0 * c + 4.0 * d * x))

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: object = None) -> _FloatArray:
        """The curve ``x + q x**2 + c x**3 + d x**4``.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s]; not used.
        x : (n,) array_like of float
            Input [V].
        aux : mapping, optional
            Not used.
        state : object, optional
            Not used.

        Returns
        -------
        (n,) ndarray of float
            Output [V].
        """
        return self._poly(np.asarray(x, dtype=float))[0]

    def _invert(self, y: _FloatArray) -> _FloatArray:
        x = np.array(y, dtype=float, copy=True)
        with np.errstate(all="ignore"):
            for _ in range(16):
                fx, slope = self._poly(x)
                slope = np.where(np.abs(slope) < 0.05, np.copysign(0.05, slope + 0.0), slope)
                x = x - (fx - y) / slope
        return np.where(np.isfinite(x), x, y)

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> _FloatArray:
        """The input for each ``y`` by 16 Newton steps from ``x = y``.

        Where the iteration ends non-finite, ``y`` itself is returned.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s]; not used.
        y : (n,) array_like of float
            Output [V].
        aux : mapping, optional
            Not used.

        Returns
        -------
        (n,) ndarray of float
            Input [V].
        """
        return self._invert(np.asarray(y, dtype=float))

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`.

        Returns
        -------
        ElementStream
            A stateless stream [V in, V out].
        """
        return _FunctionStream(lambda t_s, y, aux=None: float(self._invert(np.array([y]))[0]))


class PolynomialDriftElement(_TimeDriftElement):
    """Load-independent baseline drift of any smooth shape:
    y = x + rate_v_per_s * s + curvature_v_per_s2 * s**2 + cubic_v_per_s3 * s**3, s = t - t_first.

    t_first as in :class:`OffsetDriftElement` (first sample, or first after a reset/tare).
    """

    kind = "polynomial_drift"
    PARAMS = (("rate_v_per_s", False), ("curvature_v_per_s2", False), ("cubic_v_per_s3", False))
    rate_v_per_s: float
    curvature_v_per_s2: float
    cubic_v_per_s3: float

    def _term(self, s: _FloatOrArray) -> _FloatOrArray:
        return s * (self.rate_v_per_s + s * (self.curvature_v_per_s2 + s * self.cubic_v_per_s3))


def _spline_from_zero(knots_s: _FloatArray, values: _FloatArray) -> Any:
    """The natural cubic spline through (0, 0) and (knots_s[i], values[i]) (values may have trailing columns)."""
    from scipy.interpolate import CubicSpline

    values = np.asarray(values, dtype=float)
    return CubicSpline(np.concatenate([[0.0], knots_s]), np.concatenate([np.zeros((1, *values.shape[1:])), values]),
                       bc_type="natural")


class SplineDriftElement(_TimeDriftElement):
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
    knots_s: _FloatArray
    values_v: _FloatArray
    _spline: CubicSpline

    def __init__(self, knots_s: _Numbers, values_v: _Numbers) -> None:
        knots, values = _abscissae_and_values(self.kind, "knots_s", knots_s, "values_v", values_v)
        self._freeze(knots_s=knots, values_v=values, _spline=_spline_from_zero(knots, values))

    def _term(self, s: _FloatOrArray) -> _FloatOrArray:
        s = np.asarray(s, dtype=float)
        return self._spline(np.clip(s, 0.0, self.knots_s[-1]))

    @staticmethod
    def basis(s: _Numbers, knots_s: _Numbers) -> _FloatArray:
        """The drift as a linear map of its knot values: column i is the drift, s (s) after the first sample, of
        unit value at knot i and zero at the others (a fitter's design columns; the drift is ``basis @ values_v``)."""
        knots = np.asarray(knots_s, dtype=float)
        spline = _spline_from_zero(knots, np.eye(knots.size))
        return np.asarray(spline(np.clip(np.asarray(s, dtype=float), 0.0, knots[-1])), dtype=float)

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping.

        Returns
        -------
        dict
            ``{'type': 'spline_drift', 'knots_s': [...], 'values_v': [...]}`` [s, V].
        """
        return {"type": self.kind, "knots_s": [float(v) for v in self.knots_s], "values_v": [float(v) for v in self.values_v]}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The element from a model-file mapping.

        Parameters
        ----------
        d : mapping
            ``type``, ``knots_s`` [s] and ``values_v`` [V].

        Returns
        -------
        SplineDriftElement
            The element.

        Raises
        ------
        ModelError
            For missing or unknown keys, lists that are empty, too long or of different lengths,
            values out of range, or knots not strictly increasing.
        """
        _check_keys(cls.kind, d, cls.KEYS)
        return cls(d["knots_s"], d["values_v"])


class _ElementType(Protocol):
    """An element class as :meth:`SensorChain.from_dict` uses it: every value of ELEMENT_TYPES."""

    def from_dict(self, d: Mapping[str, Any]) -> Element: ...


ELEMENT_TYPES: dict[str, type] = {name: ViscoelasticElement for name in MODEL_TYPES}
ELEMENT_TYPES["offset"] = OffsetElement
for _element in (GainElement, NonlinearGainElement, SensorLagElement, TransportDelayElement, ThermalDriftElement,
                 ThermalSensitivityElement, OffsetDriftElement, PreisachElement, PlayHysteresisElement, ThermalLagElement,
                 PolynomialDriftElement, PolynomialGainElement, ExponentialDriftElement, SplineDriftElement):
    ELEMENT_TYPES[_element.kind] = _element


class SensorChain:
    """Ordered elements from force (first) to voltage (last); an immutable value like its elements.

    ``forward_only=True`` admits elements that can only simulate (:class:`ForwardElement`): such a chain
    runs :meth:`forward` and nothing else (a simulator's truth, never a model file).
    """

    _elements: tuple
    forward_only: bool

    def __init__(self, elements: Sequence[Element], *, forward_only: bool = False) -> None:
        items = tuple(elements)
        object.__setattr__(self, "_elements", items)
        object.__setattr__(self, "forward_only", bool(forward_only))
        if not items:
            raise ModelError("a sensor model needs at least one element")
        required = ForwardElement if forward_only else Element
        odd = [type(e).__name__ for e in items if not isinstance(e, required)]
        if odd:
            raise ModelError(f"not sensor-chain elements: {odd}")
        cores = [e for e in self.elements if isinstance(e, ViscoelasticElement)]
        if len(cores) > 1:
            raise ModelError("a sensor model holds at most one viscoelastic core")

    @property
    def elements(self) -> tuple:
        """The elements, force end first (a tuple: a changed chain is a new chain)."""
        return self._elements

    def __setattr__(self, name: str, value: Any) -> NoReturn:
        raise AttributeError(f"SensorChain is immutable (tried to set {name}); build a new one "
                             "(SensorChain([...]), with_offset)")

    @classmethod
    def from_model(cls, model: ViscoelasticModel, offset_v: float = 0.0) -> Self:
        """The usual chain: a viscoelastic core followed by an offset.

        Parameters
        ----------
        model : ViscoelasticModel
            The core [N/V, N*s/V].
        offset_v : float, optional
            Bridge output at zero force [V].

        Returns
        -------
        SensorChain
            ``[ViscoelasticElement(model), OffsetElement(offset_v)]``.
        """
        return cls([ViscoelasticElement(model), OffsetElement(offset_v)])

    @property
    def viscoelastic(self) -> Optional[ViscoelasticModel]:
        """The viscoelastic model of the core, or None."""
        for e in self.elements:
            if isinstance(e, ViscoelasticElement):
                return e.model
        return None

    @property
    def offset(self) -> OffsetElement:
        """The offset element (a zero offset when the model has none; never added to the chain)."""
        for e in self.elements:
            if isinstance(e, OffsetElement):
                return e
        return OffsetElement(0.0)

    @property
    def needs_temperature(self) -> bool:
        """Whether an element follows temperature (``aux['temperature_c']``, degC): without it, it is not corrected."""
        thermal = (ThermalDriftElement, ThermalLagElement, ThermalSensitivityElement)
        return any(isinstance(e, thermal) for e in self.elements)

    @property
    def offset_v(self) -> float:
        """Bridge output at zero force, V (0 without an offset element)."""
        return self.offset.voltage_v

    def with_offset(self, voltage_v: float) -> "SensorChain":
        """A new chain with another bridge offset; this one is left as it is.

        The offset element is replaced where it stands, or appended at the
        voltage end when the chain has none.

        Parameters
        ----------
        voltage_v : float
            Bridge output at zero force [V].

        Returns
        -------
        SensorChain
            The new chain.
        """
        element = OffsetElement(voltage_v)
        if any(isinstance(e, OffsetElement) for e in self.elements):
            return SensorChain([element if isinstance(e, OffsetElement) else e for e in self.elements],
                               forward_only=self.forward_only)
        return SensorChain([*self.elements, element], forward_only=self.forward_only)

    def forward_states(self) -> list[Any]:
        """Fresh element states for block-wise forward runs (relaxed, unloaded sensor).

        Returns
        -------
        list
            Each element's :meth:`~Element.forward_state`, force end first.
        """
        return [e.forward_state() for e in self.elements]

    def forward(self, t_s: npt.ArrayLike, force_n: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                states: Optional[Sequence[Any]] = None) -> _FloatArray:
        """Voltage for a force history: each element's :meth:`~Element.forward` from the force end.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s], non-decreasing.
        force_n : (n,) array_like of float
            Applied force [N].
        aux : mapping of str to array_like, optional
            Auxiliary signals sampled with the force (``temperature_c`` [degC]).
        states : sequence, optional
            From :meth:`forward_states`, to continue from a previous block (updated in place);
            a relaxed, unloaded sensor when omitted.

        Returns
        -------
        (n,) ndarray of float
            Bridge voltage [V].
        """
        states = states if states is not None else self.forward_states()
        x = np.asarray(force_n, dtype=float)
        for element, state in zip(self.elements, states):
            x = element.forward(t_s, x, aux, state)
        return x

    def backward(self, t_s: npt.ArrayLike, voltage_v: npt.ArrayLike,
                 aux: Optional[Mapping[str, Any]] = None) -> _FloatArray:
        """Force for a voltage record: each element's :meth:`~Element.backward` from the voltage end.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s].
        voltage_v : (n,) array_like of float
            Bridge voltage [V].
        aux : mapping of str to array_like, optional
            Auxiliary signals sampled with the voltage (``temperature_c`` [degC]).

        Returns
        -------
        (n,) ndarray of float
            Force [N].
        """
        x = np.asarray(voltage_v, dtype=float)
        for element in reversed(self.elements):
            x = element.backward(t_s, x, aux)
        return x

    def streaming(self) -> ChainStream:
        """The per-sample inverse of the chain.

        Returns
        -------
        ChainStream
            The elements' fresh per-sample inverses from the voltage end [V in, N out].
        """
        return ChainStream([e.streaming() for e in reversed(self.elements)])

    @property
    def latency_s(self) -> float:
        """How late the compensated force follows the applied force [s]: every transport delay, which the
        inverse cannot undo, plus the filter time of every bandwidth-limited lag inverse."""
        return float(sum(e.delay_s for e in self.elements if isinstance(e, TransportDelayElement))
                     + sum(e.latency_s for e in self.elements if isinstance(e, SensorLagElement)))

    def static_gain_v_per_n(self) -> float:
        """The core's static gain (1.0 without a core); the other elements are not included.

        Returns
        -------
        float
            Static gain [V/N].
        """
        core = self.viscoelastic
        return core.static_gain_v_per_n() if core is not None else 1.0

    def to_dict(self) -> dict[str, Any]:
        """The chain as a model-file mapping.

        Returns
        -------
        dict
            ``{'elements': [...]}``: each element's :meth:`~Element.to_dict`, force end first.
        """
        return {"elements": [e.to_dict() for e in self.elements]}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The chain from a model-file mapping, each element built by its ``type``.

        Parameters
        ----------
        d : mapping
            ``{'elements': [...]}``, force end first.

        Returns
        -------
        SensorChain
            The chain.

        Raises
        ------
        ModelError
            If anything is invalid.
        """
        if not isinstance(d, dict) or not isinstance(d.get("elements"), list):
            raise ModelError("model must be a mapping with a list under 'elements'")
        elements: list[Element] = []
        for i, item in enumerate(d["elements"]):
            if not isinstance(item, dict) or "type" not in item:
                raise ModelError(f"element {i}: must be a mapping with a 'type'")
            kind = item["type"]
            if kind not in ELEMENT_TYPES:
                raise ModelError(f"element {i}: unknown type {kind!r}; known: {sorted(ELEMENT_TYPES)}")
            # ELEMENT_TYPES holds plain types for its readers; every one of them builds from a mapping
            elements.append(cast(_ElementType, ELEMENT_TYPES[kind]).from_dict(item))
        return cls(elements)


class ChainStream:
    """Per-sample inverse of a chain: voltage in, force out (or None if rejected)."""

    def __init__(self, streams: Sequence[ElementStream]) -> None:
        self.streams = streams
        # The usual chain, an offset then the viscoelastic core, runs at 1 kHz: its offset is one
        # subtraction here and its one stateful stream is called directly (the same arithmetic as the loop).
        rest = list(streams)
        self._offset_v = 0.0
        if rest and isinstance(rest[0], _OffsetStream):
            self._offset_v = rest[0].voltage_v
            del rest[0]
        self._only = rest[0] if len(rest) == 1 else None
        self._rest = rest

    def reset(self) -> None:
        """Reset every element's stream (the next sample starts from a relaxed, unloaded sensor)."""
        for s in self.streams:
            s.reset()

    def step(self, t_s: float, voltage_v: float, aux: Optional[Mapping[str, Any]] = None) -> Optional[float]:
        """Force for one voltage sample, or None if an element rejects the sample.

        Parameters
        ----------
        t_s : float
            Sample time [s].
        voltage_v : float
            Bridge voltage [V].
        aux : mapping of str to float, optional
            Auxiliary samples at ``t_s`` (``temperature_c`` [degC]).

        Returns
        -------
        float or None
            Force [N], or None when an element cannot use the sample.
        """
        x: Optional[float]  # declared apart from its value, so that mypy narrows it to float here
        x = voltage_v - self._offset_v
        only = self._only
        if only is not None:
            return only.step(t_s, x, aux)
        for s in self._rest:
            x = s.step(t_s, x, aux)
            if x is None:
                return None
        return x
