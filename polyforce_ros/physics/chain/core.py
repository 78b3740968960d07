"""The viscoelastic core: applied force (N) <-> deformation read as bridge volts, with the numerical checks
a core's parameters must pass before it is used.
"""
from __future__ import annotations

import math
from typing import Any, Mapping, Optional, Self, Sequence, TypedDict

import numpy as np
import numpy.typing as npt

from ..expconv import exp_convolve, step_weights_scalar
from ..viscoelastic import (
    MODEL_TYPES,
    CreepCompliance,
    ForwardState,
    RelaxationModulus,
    StreamingCompensator,
    ViscoelasticModel,
    compensate,
    simulate_deformation,
)
from .base import (DAY_S, MAX_RATE_PER_S, FloatArray, FloatOrArray, Frozen, FunctionStream, ModelError, check_keys, check_number,
                   float_list, short_repr, smoke_records, stream_backward, temperature_c_of)
from .drift import LaggedTemperatureStream, ThermalForwardState, lagged_temperature_c, thermal_forward_state

__all__ = ["ViscoelasticElement", "ThermoRheologicalElement", "PowerFlowElement", "MAX_VOLUME_TERMS",
           "volume_fluidity", "lowest_volume_fluidity", "series_fluidity", "KneeKelvinElement", "reduced_time_s",
           "log_shift", "wrapped_core_from_dict", "MAX_LOG_SHIFT"]


def _laplace_mismatch(rel: RelaxationModulus, comp: CreepCompliance, s: npt.ArrayLike) -> FloatArray:
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
            mismatch = _laplace_mismatch(rel, comp, np.logspace(-math.log10(DAY_S), 4.0, 25))
    except (ArithmeticError, ValueError, LookupError, TypeError) as exc:  # LinAlgError is a ValueError
        raise ModelError(f"{kind}: parameters {model.as_dict()} give no relaxation modulus "
                         f"({type(exc).__name__}: {exc}); they are too far apart for float64") from None
    if not all(math.isfinite(v) for v in values + products):
        raise ModelError(f"{kind}: parameters {model.as_dict()} give a non-finite relaxation modulus {rel}")
    if any(r < 0.0 or r * DAY_S >= 1e150 for r in rel.r_per_s):
        raise ModelError(f"{kind}: parameters {model.as_dict()} give relaxation rates {rel.r_per_s} 1/s; "
                         f"each must be within [0, {MAX_RATE_PER_S:.3g}] 1/s")
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


class ViscoelasticElement(Frozen):
    """The viscoelastic core: force (N) <-> deformation read as volts (seed 000)."""

    model: ViscoelasticModel
    kind: str

    def __init__(self, model: ViscoelasticModel) -> None:
        self._freeze(model=model, kind=model.kind)

    def forward_state(self) -> ForwardState:
        """A fresh forward state of the core (relaxed, unloaded sensor)."""
        return ForwardState(self.model)

    def forward(self, t_s: npt.ArrayLike, force_n: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[ForwardState] = None) -> FloatArray:
        """Deformation for a force history, by :func:`~.viscoelastic.simulate_deformation`."""
        return simulate_deformation(self.model, t_s, force_n, state=state)

    def backward(self, t_s: npt.ArrayLike, deformation_v: npt.ArrayLike,
                 aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """Force for a deformation record from a relaxed sensor, by :func:`~.viscoelastic.compensate`."""
        return compensate(self.model, t_s, deformation_v)

    def streaming(self) -> StreamingCompensator:
        """The per-sample inverse of the core."""
        return StreamingCompensator(self.model)

    def to_dict(self) -> dict[str, Any]:
        """The core as a model-file mapping."""
        return {"type": self.kind, **self.model.as_dict()}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The core from a model-file mapping whose ``type`` is a viscoelastic model kind."""
        kind = d.get("type") if isinstance(d, dict) else None
        if not isinstance(kind, str) or kind not in MODEL_TYPES:
            raise ModelError(f"viscoelastic core: type must be one of {sorted(MODEL_TYPES)}, got {short_repr(kind)}")
        model_type = MODEL_TYPES[kind]
        names = model_type.parameter_names()
        check_keys(kind, d, names)
        values = [check_number(kind, n, d[n], positive=True) for n in names]
        try:
            model = model_type(*values)
        except (TypeError, ValueError) as exc:
            raise ModelError(f"{kind}: {exc}") from None
        _check_core_numerics(kind, model)
        return cls(model)


def wrapped_core_from_dict(kind: str, core: object, wrappers: tuple[str, ...] = ()) -> ViscoelasticElement:
    """The core an element of type ``kind`` wraps, from its model-file mapping: a viscoelastic core, or one of the
    core ``wrappers`` (``thermo_rheological``, ``power_flow``) around one; a :class:`ModelError` naming ``kind``
    for anything else."""
    if not isinstance(core, dict):
        raise ModelError(f"{kind}: core must be a mapping (a viscoelastic core), got {short_repr(core)}")
    wrapper = core.get("type")
    if isinstance(wrapper, str) and wrapper in wrappers:
        element: type[ViscoelasticElement] = {"thermo_rheological": ThermoRheologicalElement,
                                              "power_flow": PowerFlowElement}[wrapper]
        return element.from_dict(core)
    return ViscoelasticElement.from_dict(core)


#: Largest |shift_per_c * (T - reference_c)| applied: the core's clock runs at most e^10 faster or slower than real
#: time (a 2e4-fold change of every viscosity), so a wild temperature reading cannot overflow the reduced time.
MAX_LOG_SHIFT = 10.0


def log_shift(departure_c: FloatOrArray, shift_per_c: float, wlf_c2_c: float = 0.0) -> FloatOrArray:
    """ln of the viscosities' shift factor a_T at a departure from the reference temperature [degC]: ``b dT``, or with
    the WLF constant ``C2 = wlf_c2_c`` > 0 ``b dT C2 / (C2 + dT)`` (the same slope b at the reference, bending as
    the Williams-Landel-Ferry and Vogel-Fulcher laws do: ever steeper toward C2 below it, where the clock stops,
    and flatter above it); within +-``MAX_LOG_SHIFT``."""
    if isinstance(departure_c, float):  # one sample of the 1 kHz path: plain floats, no numpy call per sample
        one = shift_per_c * departure_c
        if wlf_c2_c > 0.0:
            one = one * wlf_c2_c / max(wlf_c2_c + departure_c, wlf_c2_c * 1e-9)
        return min(max(one, -MAX_LOG_SHIFT), MAX_LOG_SHIFT)
    raw = shift_per_c * departure_c
    if wlf_c2_c > 0.0:  # at and below -C2 the denominator is held just above 0: the clock's slowest
        raw = raw * wlf_c2_c / np.maximum(wlf_c2_c + departure_c, wlf_c2_c * 1e-9)
    out: FloatOrArray = np.clip(raw, -MAX_LOG_SHIFT, MAX_LOG_SHIFT)
    return out


def reduced_time_s(t_s: npt.ArrayLike, temperature_c: Optional[npt.ArrayLike], shift_per_c: float,
                   reference_c: float, wlf_c2_c: float = 0.0) -> FloatArray:
    """The reduced time of a thermo-rheologically simple material [s]: the clock of its viscosities.

    ``xi_0 = t_0``, ``xi_k = xi_{k-1} + (t_k - t_{k-1}) (e_k + e_{k-1}) / 2`` with ``e = a_T`` of :func:`log_shift`
    (``exp(b (T - T_ref))`` without ``wlf_c2_c``): a viscosity ``eta(T) = eta(T_ref) / a_T`` acts over ``dt`` as
    ``eta(T_ref)`` over ``a_T dt``. Without temperature the reduced time is the time itself.
    """
    t = np.asarray(t_s, dtype=float)
    if temperature_c is None or t.size == 0:
        return t.copy()
    temp = np.broadcast_to(np.asarray(temperature_c, dtype=float), t.shape)
    rate = np.exp(log_shift(temp - reference_c, shift_per_c, wlf_c2_c))
    rate = np.where(np.isfinite(rate), rate, 1.0)
    steps = np.diff(t) * 0.5 * (rate[1:] + rate[:-1])
    out: FloatArray = t[0] + np.concatenate([[0.0], np.cumsum(steps)])
    return out


class _ClockState(TypedDict):
    core: ForwardState
    t: Optional[float]  # the last stamp of the previous block [s]
    xi: float  # its reduced time [s]
    temperature_c: Optional[float]  # its temperature [degC], the core's (behind the thermometer when lagged)
    lag: ThermalForwardState  # the core's temperature behind the thermometer's


class _ReducedTimeStream:
    """The core's per-sample inverse run on the reduced time (:func:`reduced_time_s`, sample by sample), on the
    core's temperature behind the thermometer's when ``temperature_lag_s`` > 0."""

    def __init__(self, inner: StreamingCompensator, shift_per_c: float, reference_c: float,
                 temperature_lag_s: float = 0.0, wlf_c2_c: float = 0.0) -> None:
        self.inner, self.b, self.ref, self.c2 = inner, shift_per_c, reference_c, wlf_c2_c
        self.lag = LaggedTemperatureStream(temperature_lag_s) if temperature_lag_s > 0.0 else None
        self.reset()

    def reset(self) -> None:
        self.inner.reset()
        self.t_prev: Optional[float] = None
        self.xi, self.rate_prev = 0.0, 1.0
        if self.lag is not None:
            self.lag.reset()

    def _core_temperature(self, t_s: float, temp: float) -> float:
        """The core's temperature after the sample at ``t_s``, the lag's state not moved."""
        return temp if self.lag is None else self.lag.peek(t_s, temp)

    def _clock(self, t_s: float, aux: Optional[Mapping[str, Any]]) -> tuple[float, float]:
        """(reduced time, clock rate) at ``t_s``, the state not moved."""
        temp = None if not aux else aux.get("temperature_c")
        rate = 1.0
        if temp is not None:
            core_c = self._core_temperature(t_s, float(temp))
            e = math.exp(log_shift(core_c - self.ref, self.b, self.c2))
            rate = e if math.isfinite(e) else 1.0
        xi = t_s if self.t_prev is None else self.xi + (t_s - self.t_prev) * 0.5 * (rate + self.rate_prev)
        return xi, rate

    def affine(self, t_s: float, aux: Optional[Mapping[str, Any]] = None) -> Optional[tuple[float, float]]:
        """The next :meth:`step` as an affine map of its input (:meth:`StreamingCompensator.affine`)."""
        if self.t_prev is not None and t_s < self.t_prev:
            return None
        return self.inner.affine(self._clock(t_s, aux)[0])

    def step(self, t_s: float, value: float, aux: Optional[Mapping[str, Any]] = None) -> Optional[float]:
        xi, rate = self._clock(t_s, aux)
        force = self.inner.step(xi, value)
        if force is not None:  # a refused sample (a stamp going back) leaves the clock as it was
            self.t_prev, self.xi, self.rate_prev = t_s, xi, rate
            temp = None if not aux else aux.get("temperature_c")
            if self.lag is not None and temp is not None:
                self.lag.update(t_s, float(temp))
        return force


class ThermoRheologicalElement(ViscoelasticElement):
    """A viscoelastic core whose viscosities all follow temperature (time-temperature superposition):
    ``eta(T) = eta(T_ref) exp(-shift_per_c (T - reference_c))``, so creep runs faster when warm (a fill that gels as
    it warms, a thermogelling poloxamer or methylcellulose, has a negative shift: it creeps slower). The core runs on
    the reduced time of :func:`reduced_time_s`; its elastic parts do not change. It reads ``temperature_c``: T is the
    thermometer's, or with ``temperature_lag_s`` the core's own, which follows the thermometer through a first-order
    lag (a core with thermal mass away from its thermometer), settled at the first temperature.

    Parameters (model file keys)
    ----------------------------
    core : mapping
        The core at ``reference_c`` (any viscoelastic model type).
    shift_per_c : float in [-2, 2]
        b [1/degC]: ln of the shift factor per degree (an Arrhenius law linearised near the reference); negative for a
        clock that slows when warm.
    reference_c : float
        T_ref [degC].
    temperature_lag_s : float >= 0, optional
        The time constant [s] of the core's temperature behind the thermometer's; 0 (the default, not written) for
        none.
    wlf_c2_c : float >= 0, optional
        The WLF constant C2 [degC] of :func:`log_shift`: the shift bends, the clock stopping C2 below the reference;
        0 (the default, not written) for the straight law ``b dT`` (the only law of a negative shift).
    """

    KEYS = ("core", "shift_per_c", "reference_c")
    OPTIONAL = {"temperature_lag_s": 0.0, "wlf_c2_c": 0.0}
    shift_per_c: float
    reference_c: float
    temperature_lag_s: float
    wlf_c2_c: float

    def __init__(self, core: ViscoelasticElement, shift_per_c: float, reference_c: float,
                 temperature_lag_s: float = 0.0, wlf_c2_c: float = 0.0) -> None:
        if not isinstance(core, ViscoelasticElement) or isinstance(core, ThermoRheologicalElement):
            raise ModelError("thermo_rheological: core must be a viscoelastic core")
        shift_per_c = check_number("thermo_rheological", "shift_per_c", shift_per_c, positive=False)
        reference_c = check_number("thermo_rheological", "reference_c", reference_c, positive=False)
        lag_s = check_number("thermo_rheological", "temperature_lag_s", temperature_lag_s, positive=False)
        c2 = check_number("thermo_rheological", "wlf_c2_c", wlf_c2_c, positive=False)
        if c2 > 0.0 and shift_per_c < 0.0:  # the WLF bend is a glass transition's: its clock stops in the cold
            raise ModelError("thermo_rheological: a clock that slows when warm (shift_per_c < 0) has no wlf_c2_c")
        self._freeze(model=core.model, kind="thermo_rheological", shift_per_c=shift_per_c, reference_c=reference_c,
                     temperature_lag_s=lag_s, wlf_c2_c=c2)

    def _core_temperature_c(self, t_s: npt.ArrayLike, temp_c: Optional[FloatArray],
                            state: Optional[ThermalForwardState] = None) -> Optional[FloatArray]:
        """The core's temperature: the thermometer's, or behind it through the lag (``state`` continues it)."""
        if temp_c is None or self.temperature_lag_s <= 0.0:
            return temp_c
        return lagged_temperature_c(t_s, np.asarray(temp_c, dtype=float), self.temperature_lag_s, state)

    def _xi(self, t_s: npt.ArrayLike, aux: Optional[Mapping[str, Any]]) -> FloatArray:
        temp = self._core_temperature_c(t_s, temperature_c_of(aux, np.size(t_s)))
        return reduced_time_s(t_s, temp, self.shift_per_c, self.reference_c, self.wlf_c2_c)

    def forward_state(self) -> _ClockState:  # type: ignore[override]
        """A fresh state for block-wise :meth:`forward` runs: the core's, the reduced time's last stamp and the
        core's temperature lag."""
        return {"core": ForwardState(self.model), "t": None, "xi": 0.0, "temperature_c": None,
                "lag": thermal_forward_state()}

    def forward(self, t_s: npt.ArrayLike, force_n: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_ClockState] = None) -> FloatArray:  # type: ignore[override]
        """Deformation for a force history, the core run on the reduced time; ``state`` carries the clock across
        blocks."""
        st = state if state is not None else self.forward_state()
        t = np.asarray(t_s, dtype=float)
        temp = self._core_temperature_c(t, temperature_c_of(aux, t.size), st["lag"])
        if st["t"] is not None and t.size:  # continue the clock from the previous block's last sample
            before = st["temperature_c"] if st["temperature_c"] is not None else self.reference_c
            temps = None if temp is None else np.concatenate([[before], temp])
            xi = reduced_time_s(np.concatenate([[st["t"]], t]), temps, self.shift_per_c, self.reference_c,
                                self.wlf_c2_c)[1:]
            xi = xi - st["t"] + st["xi"]
        else:
            xi = reduced_time_s(t, temp, self.shift_per_c, self.reference_c, self.wlf_c2_c)
        if t.size:
            st["t"], st["xi"] = float(t[-1]), float(xi[-1])
            st["temperature_c"] = None if temp is None else float(temp[-1])
        return simulate_deformation(self.model, xi, force_n, state=st["core"])

    def backward(self, t_s: npt.ArrayLike, deformation_v: npt.ArrayLike,
                 aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """Force for a deformation record from a relaxed sensor, the core's inverse on the reduced time."""
        return compensate(self.model, self._xi(t_s, aux), deformation_v)

    def streaming(self) -> _ReducedTimeStream:  # type: ignore[override]
        """The per-sample inverse on the reduced time, equal to :meth:`backward` sample by sample."""
        return _ReducedTimeStream(StreamingCompensator(self.model), self.shift_per_c, self.reference_c,
                                  self.temperature_lag_s, self.wlf_c2_c)

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping."""
        out = {"type": self.kind, "core": ViscoelasticElement(self.model).to_dict(),
               "shift_per_c": float(self.shift_per_c), "reference_c": float(self.reference_c)}
        for key in self.OPTIONAL:  # 0, the default, is not written: a plain clock writes the file it always did
            if getattr(self, key) > 0.0:
                out[key] = float(getattr(self, key))
        return out

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The element from a model-file mapping."""
        check_keys("thermo_rheological", d, cls.KEYS, cls.OPTIONAL)
        return cls(wrapped_core_from_dict("thermo_rheological", d["core"]), d["shift_per_c"], d["reference_c"],
                   d.get("temperature_lag_s", 0.0), d.get("wlf_c2_c", 0.0))


class _FlowState(TypedDict):
    core: Any  # the wrapped core's forward state
    t: Optional[float]  # the last stamp of the previous block [s]
    force_n: float  # its force [N]
    flow_v: float  # the flow reached at it [V]
    volume_n_s: float  # the load-time integral reached at it [N s]


class PowerFlowElement(ViscoelasticElement):
    """A viscoelastic core beside a dashpot whose rate is a power of the force above a yield force (Norton creep,
    a Bingham flow):

        V = core(F) + flow_rate_v_per_s * integral of (max(F - flow_yield_n, 0) / flow_force_scale_n) ** flow_exponent dt

    A flow that runs faster than in proportion to the load (exponent > 1), slower (< 1), or only above a yield
    force. Optionally a flow whose fluidity changes with the load-time integral already passed (strain hardening,
    a filter that clogs, a leak path that opens or a crack that grows as the core flows):

        + integral of F * sum_k flow_volume_rates_v_per_n_s[k] * u ** (k + 1) dt,   u = clip(X / flow_volume_scale_n_s, 0, 1)

    with X the integral of F dt since the start; beyond the scale (the largest the calibration record reached) and
    below the start the fluidity is held at its value there, never extrapolated. That fluidity with the core's own
    (the dashpot in series; none counted for a thermo-rheological core, which cold can all but stop) is never
    negative in [0, 1]: a negative one would feed the inverse's flow back into its force and grow without bound.
    Both integrals run on the forces before each sample (a left sum), so the inverse is explicit: the flow at a
    sample is known before its force is solved for. ``core`` is a viscoelastic core or a thermo-rheological one.

    Parameters (model file keys)
    ----------------------------
    core : mapping
        The viscoelastic core (any model type, or ``thermo_rheological``).
    flow_rate_v_per_s : float >= 0
        The flow's rate at ``force_scale_n`` [V/s].
    flow_exponent : float
        Its exponent, 0.2-5.
    flow_force_scale_n : float > 0
        The force the rate is given at [N].
    flow_yield_n : float >= 0, optional
        The force below which nothing flows [N] (0: every positive force flows).
    flow_volume_scale_n_s : float > 0, optional
        The load-time integral at which the fluidity stops changing [N s] (with ``flow_volume_rates_v_per_n_s``).
    flow_volume_rates_v_per_n_s : list of 1-3 floats, optional
        The fluidity's change at the scale, linear, quadratic and cubic in u [V/(N s)], either sign, the total with
        the core's never negative in [0, 1] (:func:`lowest_volume_fluidity`, :func:`series_fluidity`).
    """

    KEYS = ("core", "flow_rate_v_per_s", "flow_exponent", "flow_force_scale_n")
    OPTIONAL = {"flow_yield_n": 0.0, "flow_volume_scale_n_s": 0.0, "flow_volume_rates_v_per_n_s": ()}
    core: ViscoelasticElement
    flow_rate_v_per_s: float
    flow_exponent: float
    flow_force_scale_n: float
    flow_yield_n: float
    flow_volume_scale_n_s: float
    flow_volume_rates_v_per_n_s: tuple[float, ...]

    def __init__(self, core: ViscoelasticElement, flow_rate_v_per_s: float, flow_exponent: float,
                 flow_force_scale_n: float, flow_yield_n: float = 0.0, flow_volume_scale_n_s: float = 0.0,
                 flow_volume_rates_v_per_n_s: Any = ()) -> None:
        if not isinstance(core, ViscoelasticElement) or isinstance(core, PowerFlowElement):
            raise ModelError("power_flow: core must be a viscoelastic core (plain or thermo_rheological)")
        rate = check_number("power_flow", "flow_rate_v_per_s", flow_rate_v_per_s, positive=False)
        if rate < 0.0:
            raise ModelError(f"power_flow: flow_rate_v_per_s must be >= 0, got {rate!r}")
        exponent = check_number("power_flow", "flow_exponent", flow_exponent, positive=True)
        scale = check_number("power_flow", "flow_force_scale_n", flow_force_scale_n, positive=True)
        yield_n = check_number("power_flow", "flow_yield_n", flow_yield_n, positive=False)
        if yield_n < 0.0:
            raise ModelError(f"power_flow: flow_yield_n must be >= 0, got {yield_n!r}")
        volume_scale, volume_rates = _volume_law(flow_volume_scale_n_s, flow_volume_rates_v_per_n_s)
        lowest = lowest_volume_fluidity(volume_rates) + series_fluidity(core)
        if lowest < 0.0:
            raise ModelError(f"power_flow: flow_volume_rates_v_per_n_s with the core's own fluidity fall to {lowest:.3g} "
                             "V/(N s) within the scale; a negative fluidity makes the inverse grow without bound")
        self._freeze(model=core.model, kind="power_flow", core=core, flow_rate_v_per_s=rate, flow_exponent=exponent,
                     flow_force_scale_n=scale, flow_yield_n=yield_n, flow_volume_scale_n_s=volume_scale,
                     flow_volume_rates_v_per_n_s=volume_rates)

    def flow_rate(self, force_n: npt.ArrayLike, volume_n_s: npt.ArrayLike = 0.0) -> FloatArray:
        """The flow's rate at each force [V/s], the load-time integral passed before it ``volume_n_s`` [N s]."""
        force = np.asarray(force_n, dtype=float)
        f = np.maximum(force - self.flow_yield_n, 0.0) / self.flow_force_scale_n
        out: FloatArray = self.flow_rate_v_per_s * f ** self.flow_exponent
        if self.flow_volume_rates_v_per_n_s:
            u = np.clip(np.asarray(volume_n_s, dtype=float) / self.flow_volume_scale_n_s, 0.0, 1.0)
            out = out + force * volume_fluidity(self.flow_volume_rates_v_per_n_s, u)
        return out

    def forward_state(self) -> _FlowState:  # type: ignore[override]
        """A fresh state for block-wise :meth:`forward` runs: the core's, and the flow at the last stamp."""
        return {"core": self.core.forward_state(), "t": None, "force_n": 0.0, "flow_v": 0.0, "volume_n_s": 0.0}

    def forward(self, t_s: npt.ArrayLike, force_n: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_FlowState] = None) -> FloatArray:  # type: ignore[override]
        """The core's deformation plus the flow; ``state`` carries both across blocks."""
        st = state if state is not None else self.forward_state()
        t, f = np.asarray(t_s, dtype=float), np.asarray(force_n, dtype=float)
        out = self.core.forward(t, f, aux, state=st["core"])
        if not t.size:
            return out
        before_t = st["t"] if st["t"] is not None else float(t[0])
        dt = np.diff(t, prepend=before_t)
        forces = np.concatenate([[st["force_n"]], f[:-1]])  # the force before each sample
        passed = st["volume_n_s"] + np.cumsum(dt * forces)  # the load-time integral at each sample
        before = np.concatenate([[st["volume_n_s"]], passed[:-1]])
        flow = st["flow_v"] + np.cumsum(dt * self.flow_rate(forces, before))
        st["t"], st["force_n"], st["flow_v"], st["volume_n_s"] = float(t[-1]), float(f[-1]), float(flow[-1]), float(passed[-1])
        result: FloatArray = out + flow
        return result

    def backward(self, t_s: npt.ArrayLike, deformation_v: npt.ArrayLike,
                 aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """Force for a deformation record from a relaxed sensor, sample by sample (:meth:`streaming`)."""
        return stream_backward(self.streaming(), t_s, deformation_v, aux)

    def streaming(self) -> FunctionStream:  # type: ignore[override]
        """The per-sample inverse: the flow so far taken off, then the core's own inverse."""
        inner = self.core.streaming()
        rate, exponent, scale, yield_n = (self.flow_rate_v_per_s, self.flow_exponent, self.flow_force_scale_n,
                                          self.flow_yield_n)
        volume_scale, volume_rates = self.flow_volume_scale_n_s, self.flow_volume_rates_v_per_n_s
        held: dict[str, Any] = {"t": None, "force_n": 0.0, "flow_v": 0.0, "volume_n_s": 0.0}

        def flow_at(t_s: float) -> float:
            flow: float = held["flow_v"]
            if held["t"] is not None:
                force, dt = held["force_n"], t_s - held["t"]
                flow += dt * rate * (max(force - yield_n, 0.0) / scale) ** exponent
                if volume_rates:
                    u = min(max(held["volume_n_s"] / volume_scale, 0.0), 1.0)
                    flow += dt * force * volume_fluidity(volume_rates, u)
            return flow

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> Optional[float]:
            flow = flow_at(t_s)
            force = inner.step(t_s, y - flow, aux)
            if force is not None:  # a refused sample (a stamp going back) leaves the flow as it was
                passed = held["volume_n_s"] + (t_s - held["t"]) * held["force_n"] if held["t"] is not None else 0.0
                held.update(t=t_s, force_n=force, flow_v=flow, volume_n_s=passed)
            return force

        def affine(t_s: float, aux: Optional[Mapping[str, Any]] = None) -> Optional[tuple[float, float]]:
            coefficients = inner.affine(t_s, aux)
            if coefficients is None:
                return None
            force0, stiffness = coefficients
            return force0 - stiffness * flow_at(t_s), stiffness

        def reset() -> None:
            inner.reset()
            held.update(t=None, force_n=0.0, flow_v=0.0, volume_n_s=0.0)

        return FunctionStream(step, reset, affine)

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping."""
        out = {"type": self.kind, "core": self.core.to_dict(), "flow_rate_v_per_s": float(self.flow_rate_v_per_s),
               "flow_exponent": float(self.flow_exponent), "flow_force_scale_n": float(self.flow_force_scale_n)}
        if self.flow_yield_n != 0.0:
            out["flow_yield_n"] = float(self.flow_yield_n)
        if self.flow_volume_rates_v_per_n_s:
            out["flow_volume_scale_n_s"] = float(self.flow_volume_scale_n_s)
            out["flow_volume_rates_v_per_n_s"] = [float(c) for c in self.flow_volume_rates_v_per_n_s]
        return out

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The element from a model-file mapping."""
        check_keys("power_flow", d, cls.KEYS, cls.OPTIONAL)
        inner = wrapped_core_from_dict("power_flow", d["core"], ("thermo_rheological",))
        return cls(inner, d["flow_rate_v_per_s"], d["flow_exponent"], d["flow_force_scale_n"], d.get("flow_yield_n", 0.0),
                   d.get("flow_volume_scale_n_s", 0.0), d.get("flow_volume_rates_v_per_n_s", ()))


#: Most terms of a fluidity that changes with the load-time integral passed (linear to cubic in it): a fluidity
#: that falls or rises several-fold over the record (a filter that clogs to a tenth) needs the third.
MAX_VOLUME_TERMS = 3


def volume_fluidity(rates_v_per_n_s: Sequence[float], u: Any) -> Any:
    """The fluidity's change sum_k rates[k] u^(k+1) at ``u``, the load-time integral passed over its scale (in
    [0, 1]) [V/(N s)]; a float for a float (the per-sample inverse), an array for an array."""
    total: Any = 0.0
    for c in reversed(rates_v_per_n_s):  # Horner, lowest power u^1
        total = (total + c) * u
    return total


def lowest_volume_fluidity(rates_v_per_n_s: Any) -> float:
    """The lowest of :func:`volume_fluidity` over u in [0, 1] [V/(N s)]: at an end or where its slope is zero."""
    rates = [float(c) for c in np.asarray(rates_v_per_n_s, dtype=float).ravel()]
    if not rates:
        return 0.0
    coefficients = np.array([*rates[::-1], 0.0])  # highest power first
    turns = np.roots(np.polyder(coefficients)) if coefficients.size > 2 else np.empty(0)
    inside = [float(r.real) for r in turns if abs(r.imag) < 1e-12 and 0.0 < r.real < 1.0]
    at = np.array([0.0, 1.0, *inside])
    return float(np.min(volume_fluidity(rates, at)))


def series_fluidity(core: ViscoelasticElement) -> float:
    """The fluidity of the dashpot in series in ``core`` that always acts [V/(N s)]: none for a thermo-rheological
    core, whose dashpot cold can all but stop."""
    if isinstance(core, ThermoRheologicalElement):
        return 0.0
    return float(core.model.compliance().fluidity_v_per_n_s)


def _volume_law(scale_n_s: Any, rates: Any) -> tuple[float, tuple[float, ...]]:
    """The checked (scale, rates) of a fluidity that changes with the load-time integral passed: both given, or
    neither (scale 0, no rates)."""
    if isinstance(rates, np.ndarray) and rates.ndim != 1:
        raise ModelError(f"power_flow: flow_volume_rates_v_per_n_s must be a list of numbers, got {short_repr(rates)}")
    given = not (isinstance(rates, (list, tuple, np.ndarray)) and len(rates) == 0)
    scale = check_number("power_flow", "flow_volume_scale_n_s", scale_n_s, positive=False)
    if not given:
        if scale != 0.0:
            raise ModelError("power_flow: flow_volume_scale_n_s needs flow_volume_rates_v_per_n_s")
        return 0.0, ()
    values = float_list("power_flow", "flow_volume_rates_v_per_n_s", rates, positive=False)
    if values.size > MAX_VOLUME_TERMS:
        raise ModelError(f"power_flow: flow_volume_rates_v_per_n_s holds {values.size} values; at most "
                         f"{MAX_VOLUME_TERMS}")
    if scale <= 0.0:
        raise ModelError("power_flow: flow_volume_rates_v_per_n_s needs flow_volume_scale_n_s > 0")
    return scale, tuple(float(v) for v in values)


class _KneeState(TypedDict):
    core: Any  # the wrapped core's forward state
    t: Optional[float]  # the last stamp of the previous block [s]
    loads_n: FloatArray  # each knee unit's load there: the force above its knee [N]
    states_n_s: FloatArray  # their convolution states there [N s] (a deformation is compliance * state / tau)


#: Most knees one element holds.
MAX_KNEES = 8


class KneeKelvinElement(ViscoelasticElement):
    """A viscoelastic core beside Kelvin units of one retardation time that only the force above their knees loads:

        V = core(F) + sum_k knee_compliances_v_per_n[k] * K(max(F - knees_n[k], 0))

    with K the unit-gain first-order lag of time constant ``knee_tau_s`` (on real time, also beside a
    thermo-rheological core): a delayed elasticity whose size changes with the load. A unit that engages above a
    preload (positive compliance: more creep at high loads), or one that bottoms out against a stop (negative: less
    creep above its knee than below it); a few knees make a curved dependence. Above every knee the knee compliances
    up to it sum to more than minus the core's instantaneous compliance: the units, which may settle before the
    core creeps, never make the output fall as the load rises, so the inverse is single-valued and bounded. The
    forward run is the exact recursion of :func:`~polyforce_ros.physics.expconv.exp_convolve`; the inverse solves
    each sample's force exactly for that recursion (the core's step is affine in its deformation, the units' current
    sample piecewise linear in the force), at any spacing and across gaps.

    Parameters (model file keys)
    ----------------------------
    core : mapping
        The viscoelastic core (any model type, ``thermo_rheological`` or ``power_flow``).
    knees_n : list of float, ascending
        The forces above which each unit is loaded [N] (at most :data:`MAX_KNEES`).
    knee_compliances_v_per_n : list of float
        Each unit's settled compliance [V/N], one per knee; each running sum > minus the core's ``j0``.
    knee_tau_s : float > 0
        Their retardation time [s].
    """

    KEYS = ("core", "knees_n", "knee_compliances_v_per_n", "knee_tau_s")
    core: ViscoelasticElement
    knees_n: FloatArray
    knee_compliances_v_per_n: FloatArray
    knee_tau_s: float

    def __init__(self, core: ViscoelasticElement, knees_n: npt.ArrayLike, knee_compliances_v_per_n: npt.ArrayLike,
                 knee_tau_s: float) -> None:
        if not isinstance(core, ViscoelasticElement) or isinstance(core, KneeKelvinElement):
            raise ModelError("knee_kelvin: core must be a viscoelastic core (plain, thermo_rheological or power_flow)")
        knees = float_list("knee_kelvin", "knees_n", knees_n, positive=False)
        compliances = float_list("knee_kelvin", "knee_compliances_v_per_n", knee_compliances_v_per_n, positive=False)
        tau = check_number("knee_kelvin", "knee_tau_s", knee_tau_s, positive=True)
        if knees.size != compliances.size or knees.size > MAX_KNEES:
            raise ModelError(f"knee_kelvin: knees_n and knee_compliances_v_per_n must hold the same number of values, "
                             f"at most {MAX_KNEES}; got {knees.size} and {compliances.size}")
        if np.any(np.diff(knees) <= 0.0):
            raise ModelError(f"knee_kelvin: knees_n must be strictly ascending, got {knees.tolist()}")
        j0_v_per_n = core.model.compliance().j0_v_per_n
        slopes = j0_v_per_n + np.cumsum(compliances)
        if np.any(slopes <= 0.0):
            k = int(np.argmax(slopes <= 0.0))
            raise ModelError(f"knee_kelvin: above the knee at {knees[k]:.6g} N the knee compliances up to it sum to "
                             f"{slopes[k] - j0_v_per_n:.6g} V/N, which must stay above minus the core's instantaneous "
                             f"compliance ({-j0_v_per_n:.6g} V/N): a unit that settles before the core creeps would "
                             f"make the output fall as the load rises, and no inverse follows that")
        self._freeze(model=core.model, kind="knee_kelvin", core=core, knees_n=knees, knee_compliances_v_per_n=compliances,
                     knee_tau_s=tau)

    def loads_n(self, force_n: npt.ArrayLike) -> FloatArray:
        """Each unit's load at each force: the force above its knee, (n, knees) [N]."""
        out: FloatArray = np.maximum(np.asarray(force_n, dtype=float)[:, None] - self.knees_n[None, :], 0.0)
        return out

    def forward_state(self) -> _KneeState:  # type: ignore[override]
        """A fresh state for block-wise :meth:`forward` runs: the core's, and the units' at the last stamp."""
        zeros = np.zeros(self.knees_n.size)
        return {"core": self.core.forward_state(), "t": None, "loads_n": zeros, "states_n_s": zeros.copy()}

    def forward(self, t_s: npt.ArrayLike, force_n: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_KneeState] = None) -> FloatArray:  # type: ignore[override]
        """The core's deformation plus the knee units'; ``state`` carries both across blocks."""
        st = state if state is not None else self.forward_state()
        t, f = np.asarray(t_s, dtype=float), np.asarray(force_n, dtype=float)
        out = self.core.forward(t, f, aux, state=st["core"])
        if not t.size:
            return out
        loads, rate = self.loads_n(f), [1.0 / self.knee_tau_s]
        ys = np.empty_like(loads)
        for k in range(loads.shape[1]):
            ys[:, k] = (exp_convolve(t, loads[:, k], rate)[:, 0] if st["t"] is None else
                        exp_convolve(t, loads[:, k], rate, y0=[st["states_n_s"][k]], u_prev=float(st["loads_n"][k]),
                                     t_prev_s=st["t"])[:, 0])
        st["t"], st["loads_n"], st["states_n_s"] = float(t[-1]), loads[-1].copy(), ys[-1].copy()
        result: FloatArray = out + ys @ self.knee_compliances_v_per_n / self.knee_tau_s
        return result

    def backward(self, t_s: npt.ArrayLike, deformation_v: npt.ArrayLike,
                 aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """Force for a deformation record from a relaxed sensor, sample by sample (:meth:`streaming`)."""
        return stream_backward(self.streaming(), t_s, deformation_v, aux)

    def streaming(self) -> FunctionStream:  # type: ignore[override]
        """The per-sample inverse, exact for the recursion of :meth:`forward`: the core's next step is an affine map
        of its deformation (its stream's ``affine``), and the knee units add to it a term piecewise linear in the
        force (their states known, their current sample weighted by ``h beta / tau``); the force that satisfies both
        is solved for, then the core and the units advance on it."""
        inner = self.core.streaming()
        knees, tau = self.knees_n.tolist(), self.knee_tau_s
        compliances = self.knee_compliances_v_per_n.tolist()
        zeros = [0.0] * len(knees)
        held: dict[str, Any] = {"t": None, "loads_n": zeros, "states_n_s": zeros}

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> Optional[float]:
            if held["t"] is not None and t_s < held["t"]:
                return None  # a stamp going back: nothing moves
            coefficients = inner.affine(t_s, aux)
            if coefficients is None:
                return None
            force0, stiffness = coefficients
            stiffness = max(stiffness, 0.0)
            if held["t"] is None:  # the units start from rest at the first sample
                h, beta = 0.0, 0.0
                bases = zeros
            else:
                h = t_s - held["t"]
                e, alpha, beta = step_weights_scalar(h / tau)
                bases = [e * s + h * alpha * u for s, u in zip(held["states_n_s"], held["loads_n"])]
            settled_v = sum(c * b for c, b in zip(compliances, bases)) / tau
            gains = [c * h * beta / tau for c in compliances]  # V per N above each knee, this sample
            # F + stiffness * sum g_k max(F - knee_k, 0) = force0 + stiffness * (y - settled): rising in F (each
            # running sum of g above -1 / stiffness, by the check on the core's instantaneous compliance)
            target = force0 + stiffness * (y - settled_v)
            slope, below = 1.0, 0.0  # the left side is slope * F + below between the knees passed and the next
            for knee, g in zip(knees, gains):
                if target <= below + slope * knee:
                    break
                slope = max(slope + stiffness * g, 1e-12)
                below -= stiffness * g * knee
            force = (target - below) / slope
            deformation = y - settled_v - sum(g * max(force - k, 0.0) for g, k in zip(gains, knees))
            found = inner.step(t_s, deformation, aux)
            if found is None:
                return None
            loads = [max(found - k, 0.0) for k in knees]
            states = [b + h * beta * u for b, u in zip(bases, loads)]
            held.update(t=t_s, loads_n=loads, states_n_s=states)
            return found

        def reset() -> None:
            inner.reset()
            held.update(t=None, loads_n=zeros, states_n_s=zeros)

        return FunctionStream(step, reset)

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping."""
        return {"type": self.kind, "core": self.core.to_dict(), "knees_n": [float(k) for k in self.knees_n],
                "knee_compliances_v_per_n": [float(c) for c in self.knee_compliances_v_per_n],
                "knee_tau_s": float(self.knee_tau_s)}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The element from a model-file mapping."""
        check_keys("knee_kelvin", d, cls.KEYS)
        inner = wrapped_core_from_dict("knee_kelvin", d["core"], ("thermo_rheological", "power_flow"))
        return cls(inner, d["knees_n"], d["knee_compliances_v_per_n"], d["knee_tau_s"])
