"""The effect catalogue: every effect the diagnosis can name, defined in one place.

An :class:`Effect` holds everything the fitting side knows about one physical effect:

* how to **fit** it: the linear design columns it adds to the sensor model for
  a value of its nonlinear parameter, the grid that parameter is searched on,
  its variants (e.g. hysteresis on the force or on the voltage path), and, for
  the two core effects, the core type it turns the base into;
* its **model-file elements** (how fitted coefficients become chain elements,
  which ``polyforce compensate`` and ``compensation_node`` run backward);
* its **localisation hint**: the segment kinds and signals its residual shows in.

The engine (:mod:`.engine`), the localiser (:mod:`.localise`), the report and the CLI choices all read
:data:`EFFECTS`; nothing about an effect's fit is spelled anywhere else than in its entry and the functions it
names (here, or in the effect's own module when it outgrows a few functions: :mod:`.friction`; the columns' common
vocabulary is :mod:`.columns`). How each effect is *simulated* for the
bench generator (its truth families and the tune / held-out splits) is the simulation's own business:
:mod:`polyforce_ros.sim.truths` maps every name of :data:`NAMES` to its families.

The fitted sensor model is linear in its coefficients once the nonlinear
parameters (retardation times, lag and thermal time constants) are fixed::

    V = Lag_tau( sum_j c_j s_j ) + sum_k d_k a_k + offset

with *sensor* columns ``s_j`` (the core's compliance terms F, int F, K_tau F, on the reduced time when the
viscosities follow temperature;
hysteresis play operators; a friction's stop; Kelvin units loaded by the force above a knee; the squared core output)
and *additive* columns
``a_k`` (temperature, drift polynomials). Cores are written in compliance
form: j0 F + phi int F + sum_i c_i K_{tau_i}(F), K a unit-gain first-order lag.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Mapping, Optional, Sequence

import numpy as np
import numpy.typing as npt

from ..physics.chain import (
    BridgeHysteresisElement, ExponentialDriftElement, KneeKelvinElement, PlayHysteresisElement,
    PolynomialDriftElement,
    PolynomialGainElement, ViscoelasticElement,
    SensorLagElement, SplineDriftElement, StepDriftElement, ThermalDriftElement, ThermalLagElement, ThermalSensitivityElement,
    MAX_VOLUME_TERMS,
    PARAMETER_BOUNDS,
    PowerFlowElement,
    lowest_volume_fluidity,
    series_fluidity,
    ThermoRheologicalElement,
    TransportDelayElement, lagged_temperature_c, play_operator, scaled_input, scaled_output,
)
from ..physics.viscoelastic import simulate_deformation_columns
from . import friction
from .columns import Col, ColumnsFn, ElementsFn, GridFn, Slot, lag_columns, log_grid, parameter
from .signals import FloatArray, Signals

__all__ = ["SPREAD_RATIO", "Effect", "EFFECTS", "NAMES", "PLAY_FRACTIONS", "PLAY_RIDGE",
           "SPLINE_INTERVALS", "KNEE_FRACTIONS", "KNEE_FLOOR_SHARE", "knees_n", "knee_beside", "volume_beside",
           "lag_stages", "CLOCK_LAGS_S", "clock_of", "clock_sign", "clock_shift_per_c", "clock_lag_variant", "variant_group",
           "hints"]

#: Play-operator half-widths of the hysteresis fit, as fractions of the input span (a regularised
#: non-negative weight distribution over them is fitted). 22 log-spaced, ~27 % apart: with radii up to 2x
#: apart, an operator between two of them leaves 1.5-2x the noise floor at 6 % loops, which a drift or a
#: gain then takes as a second effect.
PLAY_FRACTIONS: FloatArray = np.geomspace(0.003, 0.5, 22)
#: Ridge weight on the play weights, relative to the mean diagonal of the normal matrix.
PLAY_RIDGE = 1e-4
#: Half-widths of the scaled plays (on asinh(F / floor), :class:`~polyforce_ros.physics.chain.BridgeHysteresisElement`):
#: bands of +-0.3 % of the load to e**-1..e**1 times it, log-spaced ~26 % apart like the plays on the force.
SCALED_RADII: FloatArray = np.geomspace(0.003, 1.0, 26)
#: The scaled plays' floor, as a fraction of the force span: below it a band stops shrinking with the load (noise
#: about zero force does not open a loop of its own).
SCALED_FLOOR_FRACTION = 0.02


def _same(variant: str) -> str:
    """A variant that is its own grid variant (its name carries no refined parameter)."""
    return variant


def _single(variant: str, sig: Signals) -> list[Optional[float]]:
    """The grid of a variant without a nonlinear parameter."""
    return [None]


def _no_columns(sig: Signals, variant: str, param: Optional[float]) -> list[Col]:
    """A core effect's columns: none of its own (it changes the core type)."""
    return []


def _no_elements(coef: Mapping[str, float], variant: str, param: Optional[float], sig: Signals) -> list[Slot]:
    """A core effect's elements: none of its own (the core element holds it)."""
    return []


@dataclass(frozen=True)
class Effect:
    """An effect of the catalogue (see the module docstring).

    Attributes
    ----------
    name : str
        The name the diagnosis reports.
    hint : str
        What its residual looks like, in words (the localisation's evidence).
    segments, signals : tuple of str
        Segment kinds and signals its residual shows in (:mod:`.localise`).
    elements : tuple of str
        Model-file element types that can hold it.
    variants : tuple of str
        Its shapes (path, operator type, start state, number of knots...).
    grid : callable
        ``(variant, sig) ->`` values of its nonlinear parameter searched (``[None]``: none).
    columns : callable
        ``(sig, variant, param) ->`` the design columns it adds (:data:`Col`).
    to_elements : callable
        ``(coef, variant, param, sig) ->`` its chain elements with their slots.
    core_change : dict or None
        Base core kind -> augmented kind (the core effects only).
    needs_temperature : bool
        Testable only on a record with a temperature topic.
    rivals : tuple of str
        Effects it cannot be told apart from in one record: one is named, never both (the swap check chooses).
    record_rate : bool
        Fitted at the record's rate after the selection (:mod:`.resonance`), not by the design at the fit rate.
    extends : dict
        Variant -> the smaller variant it holds (its columns and more): chosen only when the columns it adds are
        significant (:data:`.selection.SIGNIFICANT_SE`).
    also_holds : dict
        Variant -> further smaller variants it holds (with other columns: the lead-lag holds the direct shape with
        its lagged coefficient at zero): it must also pass the acceptance test against each one's best fit.
    core_times : dict
        Variant -> the number of retardation times it adds to the core (a core effect whose parameter is the first
        of them; any further one starts :data:`SPREAD_RATIO` times slower than the one before).
    summed : tuple of str
        Variants of ``extends`` whose added columns are the weights of one distribution (most of them at zero): the
        sum of the added weights must be significant, not each weight.
    grid_variant : callable
        ``variant ->`` the variant of ``variants`` it was refined from (a variant whose name carries a parameter the
        polish refines: friction's band lag); ``extends`` and ``grid`` are keyed by that one.
    """

    name: str
    hint: str
    segments: tuple[str, ...]
    signals: tuple[str, ...]
    elements: tuple[str, ...]
    variants: tuple[str, ...] = ("",)
    grid: GridFn = _single
    columns: ColumnsFn = _no_columns
    to_elements: ElementsFn = _no_elements
    core_change: Optional[Mapping[str, str]] = None
    needs_temperature: bool = False
    rivals: tuple[str, ...] = ()
    record_rate: bool = False
    extends: Mapping[str, str] = field(default_factory=dict)
    also_holds: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    core_times: Mapping[str, int] = field(default_factory=dict)
    summed: tuple[str, ...] = ()
    grid_variant: Callable[[str], str] = _same


# --------------------------------------------------------------------------- columns and elements

def _hyst_start(radii: FloatArray, variant: str) -> FloatArray:
    """Play states before the record: virgin (zero) or after the input came down from the span (r)."""
    return radii if variant.endswith("descending") else np.zeros(radii.size)


def _hyst_path(variant: str) -> str:
    """Where the hysteresis acts: ``force`` (before the core, creeping with it), ``voltage`` (on the core's output)
    or ``bridge`` (on the applied force, added at the bridge beside the core, without creep)."""
    return variant.split("_")[0]


def _hyst_columns(sig: Signals, variant: str, param: Optional[float]) -> list[Col]:
    """Columns of a Prandtl-Ishlinskii hysteresis on the path of ``variant``, each zero at rest at the start.

    Play type: play operators p_r, non-negative weights (the curve steepens after a reversal). Stop type
    (``_stop``, Bouc-Wen-like loops, loading above unloading): stop operators s_r = input - p_r, bounded by
    +-r, non-negative weights. Fitting stops rather than negative plays keeps every column away from the
    input itself, so the core's gain and the weights cannot trade large opposite values."""
    path = _hyst_path(variant)
    on_force = path in ("force", "bridge")
    stop = "_stop" in variant
    key = ("hysteresis columns", path, stop, variant.endswith("descending"))
    if key not in sig.cache:
        span = sig.span_f if on_force else sig.span_x
        radii = PLAY_FRACTIONS * span
        start = _hyst_start(radii, variant)
        # the plays of the play and the stop type are the same: made once per path and start (the force's once per
        # record, the core output's once per reference core)
        plays_key = ("force plays" if on_force else "voltage plays", variant.endswith("descending"))
        store = sig.record_cache if on_force else sig.cache
        u = sig.f_nonlinear if on_force else sig.core_output
        cols = store.get(plays_key)
        if cols is None:
            cols = store[plays_key] = play_operator(u, radii, start) - start
        if stop:
            cols = u[:, None] - cols
        sig.cache[key] = simulate_deformation_columns(sig.reference_core, sig.t, cols) if path == "force" else cols
    cols = sig.cache[key]
    out: list[Col] = [(f"play{i}", cols[:, i], 0.0, np.inf, "sensor", "play") for i in range(cols.shape[1])]
    if variant == "bridge_scaled":  # beside the plays on the force, plays whose bands grow with the load
        scaled = sig.record_cache.get("scaled plays")
        if scaled is None:
            floor = _scaled_floor(sig)
            scaled = sig.record_cache["scaled plays"] = scaled_output(
                play_operator(scaled_input(sig.f_nonlinear, floor), SCALED_RADII), floor)
        out += [(f"scaled{j}", scaled[:, j], 0.0, np.inf, "sensor", "play") for j in range(scaled.shape[1])]
    return out


def _scaled_floor(sig: Signals) -> float:
    """The scaled plays' floor on this record [N]: :data:`SCALED_FLOOR_FRACTION` of the force span, within the model
    file's bounds for ``floor_n``."""
    return float(np.clip(SCALED_FLOOR_FRACTION * sig.span_f, 1e-9, 1e6))


def _hyst_elements(coef: Mapping[str, float], variant: str, param: Optional[float], sig: Signals) -> list[Slot]:
    path = _hyst_path(variant)
    span = sig.span_f if path in ("force", "bridge") else sig.span_x
    w = np.clip([max(coef.get(f"play{i}", 0.0), 0.0) for i in range(PLAY_FRACTIONS.size)], 0.0, 1e6)
    keep = w > 1e-12 * max(w.max(), 1e-300)
    # the scaled plays' weights (bridge_scaled's alone), within scaled_weights_v_per_n's bound
    scaled = variant == "bridge_scaled"
    ws = np.clip([max(coef.get(f"scaled{j}", 0.0), 0.0) if scaled else 0.0 for j in range(SCALED_RADII.size)], 0.0, 1e3)
    keep_s = ws > 1e-12 * max(ws.max(), w.max(), 1e-300)
    if not (keep.any() or keep_s.any()):
        return []
    history = 2.0 * span if variant.endswith("descending") else 0.0
    radii = PLAY_FRACTIONS[keep] * span
    if path == "bridge":
        # V = core(F) + sum w op(F); a stop is F - p(F): sum w s(F) = (sum w) F - sum w p(F). The core here is a
        # stand-in: build_chain puts the fitted core in its place.
        if "_stop" in variant:
            w = w * min(1.0, 1e3 / max(float(np.sum(w[keep])), 1e-300))  # linear_v_per_n within its bound
        w = np.minimum(w, 1e3)  # weights_v_per_n within its bound
        linear, weights = (float(np.sum(w[keep])), -w[keep]) if "_stop" in variant else (0.0, w[keep])
        return [("bridge", BridgeHysteresisElement(ViscoelasticElement(sig.reference_core), radii, weights,
                                                   linear_v_per_n=linear, history_max_n=history,
                                                   scaled_radii=SCALED_RADII[keep_s],
                                                   scaled_weights_v_per_n=ws[keep_s],
                                                   floor_n=_scaled_floor(sig) if keep_s.any() else 0.0))]
    # on the force path the operator enters through the core (core(F + sum w op(F))); on the voltage path
    # the core output x stands for itself (x + sum w op(x)); x + sum w (x - p(x)) = (1 + sum w) x - sum w p(x)
    if "_stop" in variant:
        w = w * min(1.0, (1e6 - 1.0) / max(float(np.sum(w[keep])), 1e-300))  # linear_weight within its bound
    linear, weights = (1.0 + float(np.sum(w[keep])), -w[keep]) if "_stop" in variant else (1.0, w[keep])
    return [("before" if path == "force" else "after", PlayHysteresisElement(linear, radii, weights, history_max=history))]


#: Clocks beside the plain one: the core's temperature lags [s] (``lag5``...: where the polish starts, it refines the
#: lag within :data:`.columns.TEMPERATURE_LAG_BOUNDS_S`), a bent shift's WLF C2 [degC] (``wlf25``...).
CLOCK_LAGS_S, CLOCK_C2S_C = (5, 15, 45), (25, 80)


#: The prefix of the variants whose clock slows as it warms (``slowing``, ``slowing_lag15``...): a fill that gels as
#: it warms (a thermogelling poloxamer, methylcellulose). Their parameter is the slope's size; the element's
#: ``shift_per_c`` is its negative.
SLOWING = "slowing"


def clock_sign(variant: str) -> float:
    """The sign of a thermo-rheological variant's shift: +1 for a clock that runs faster when warm, -1 for one that
    slows (:data:`SLOWING`)."""
    return -1.0 if variant.startswith(SLOWING) else 1.0


def clock_shift_per_c(variant: str, param: Optional[float]) -> float:
    """The shift [1/degC] of a thermo-rheological term: its parameter (the slope's size) with its variant's sign."""
    return clock_sign(variant) * parameter(param)


def clock_of(variant: str) -> tuple[float, float]:
    """(core's temperature lag [s], WLF C2 [degC]) of a thermo-rheological variant, of either sign: 0 for none."""
    if variant.startswith(SLOWING):
        variant = variant[len(SLOWING):].lstrip("_")
    return float(variant[3:]) if variant[:3] == "lag" else 0.0, float(variant[3:]) if variant[:3] == "wlf" else 0.0


def clock_lag_variant(lag_s: float, digits: int = 3, slowing: bool = False) -> str:
    """The thermo-rheological variant of a core's temperature lag.

    Parameters
    ----------
    lag_s : float
        The core's temperature lag behind the thermometer's [s].
    digits : int
        Significant digits the name keeps: 3 for an answer (``lag15``, ``lag23.3``), 12 while the polish refines the
        lag through the name (the lag back to 1e-12, far finer than the least squares' steps of about 1e-8, so it
        sees every step it takes).
    slowing : bool
        Whether the clock slows as it warms (:data:`SLOWING`).

    Returns
    -------
    str
        The variant, read back by :func:`clock_of` and :func:`clock_sign`.
    """
    return f"{SLOWING + '_' if slowing else ''}lag{lag_s:.{digits}g}"


def _shift_grid(variant: str, sig: Signals) -> list[Optional[float]]:
    """The size of ln of the viscosities' shift factor per degree searched [1/degC]: 0.005-1 (polymers well below
    their glass transition: 0.02-0.3; WLF's universal constants give 0.78 at it), its sign the variant's."""
    return log_grid(0.005, 1.0, 12)


def _core_clock(sig: Signals, variant: str, param: Optional[float]) -> list[Col]:
    """No columns of its own: the core's columns run on the reduced time (:func:`.design.design_columns`)."""
    return []


def _shift_elements(coef: Mapping[str, float], variant: str, param: Optional[float], sig: Signals) -> list[Slot]:
    # the core here is a stand-in: build_chain puts the fitted core on the reduced time
    return [("core", ThermoRheologicalElement(ViscoelasticElement(sig.reference_core), clock_shift_per_c(variant, param),
                                              float(np.clip(sig.temp_ref, -100.0, 300.0)), *clock_of(variant)))]


def _flow_grid(variant: str, sig: Signals) -> list[Optional[float]]:
    """The nonlinear dashpot's parameter searched: the exponent of a power law (``power``: a flow slower, 0.5, to
    much faster, 4, than in proportion to the load), or the yield force as a share of the force span (``yield``);
    none for the core's linear dashpot."""
    if variant == "power":
        return [0.5, 0.75, 1.5, 2.0, 3.0, 4.0]
    return [0.1, 0.2, 0.3, 0.45] if variant == "yield" else [None]


def _bounded(value: npt.ArrayLike, key: str) -> npt.NDArray[np.float64]:
    """``value`` clipped to the model file's bounds of ``key``."""
    low, high = PARAMETER_BOUNDS[key][:2]
    out: npt.NDArray[np.float64] = np.clip(np.asarray(value, dtype=float), low, high)
    return out


def _passed_n_s(sig: Signals) -> FloatArray:
    """The load-time integral passed before each sample (the left sum of F dt) [N s]."""
    out: FloatArray = np.concatenate([[0.0], np.cumsum(np.diff(sig.t) * sig.f[:-1])])
    return out


def _volume_scale_n_s(sig: Signals) -> float:
    """The largest load-time integral the record reaches [N s], within the model file's bounds: the scale of a
    fluidity that changes with it. Made once per record."""
    key = "load-time integral scale"
    if key not in sig.record_cache:  # the record's alone, whatever the reference core
        sig.record_cache[key] = float(_bounded(np.max(np.abs(_passed_n_s(sig))), "flow_volume_scale_n_s"))
    out: float = sig.record_cache[key]
    return out


def _flow_law(variant: str, param: Optional[float]) -> tuple[float, float]:
    """(exponent, yield as a share of the force span) of a nonlinear dashpot variant."""
    return (parameter(param), 0.0) if variant == "power" else (1.0, parameter(param))


def _flow_columns(sig: Signals, variant: str, param: Optional[float]) -> list[Col]:
    """A nonlinear dashpot's flow beside the core's linear one: the left sum of ((F - yield) / span)^n dt over the
    forces above the yield, the flow each sample has before its force acts
    (:class:`~polyforce_ros.physics.chain.PowerFlowElement`)."""
    if variant == "volume":  # the left sums of F u^k dt (k = 1..3), u the load-time integral passed over its largest
        key = "flow volume"
        if key not in sig.record_cache:  # the record's alone, whatever the reference core
            passed, scale_n_s = _passed_n_s(sig), _volume_scale_n_s(sig)
            steps, u = np.diff(sig.t) * sig.f[:-1], np.clip(passed[:-1] / scale_n_s, 0.0, 1.0)
            sig.record_cache[key] = [(f"flow_volume{k}", np.concatenate([[0.0], np.cumsum(steps * u ** k)]), -np.inf,
                                      np.inf, "sensor", None) for k in range(1, MAX_VOLUME_TERMS + 1)]
        out: list[Col] = sig.record_cache[key]
        return out
    if variant not in ("power", "yield"):
        return []
    exponent, yield_share = _flow_law(variant, param)
    span = max(sig.span_f, 1e-9)
    rate = (np.maximum(sig.f - yield_share * span, 0.0) / span) ** exponent
    flow = np.concatenate([[0.0], np.cumsum(np.diff(sig.t) * rate[:-1])])
    return [("flow_nonlinear", flow, 0.0, np.inf, "sensor", None)]


def _flow_elements(coef: Mapping[str, float], variant: str, param: Optional[float], sig: Signals) -> list[Slot]:
    if variant == "volume":
        rates = [coef.get(f"flow_volume{k}", 0.0) for k in range(1, MAX_VOLUME_TERMS + 1)]
        # the core here is a stand-in: build_chain puts the fitted core beside the flow
        return [("core", volume_beside(ViscoelasticElement(sig.reference_core), _volume_scale_n_s(sig), rates))]
    if variant not in ("power", "yield"):
        return []
    exponent, yield_share = _flow_law(variant, param)
    span = float(np.clip(sig.span_f, 1e-3, 1e5))
    rate = float(np.clip(coef.get("flow_nonlinear", 0.0), 0.0, 10.0))
    # the core here is a stand-in: build_chain puts the fitted core beside the flow
    return [("core", PowerFlowElement(ViscoelasticElement(sig.reference_core), rate, exponent, span, yield_share * span))]


def _lag_apply(sig: Signals, variant: str, param: Optional[float]) -> list[Col]:
    """The lag has no columns of its own: it filters the sensor columns (:func:`.design.design_columns`)."""
    return []


def _gain_columns(sig: Signals, variant: str, param: Optional[float]) -> list[Col]:
    x = sig.core_output
    return [("quadratic", x ** 2, -np.inf, np.inf, "sensor", None),
            ("cubic", x ** 3, -np.inf, np.inf, "sensor", None),
            ("quartic", x ** 4, -np.inf, np.inf, "sensor", None)]


def _gain_elements(coef: Mapping[str, float], variant: str, param: Optional[float], sig: Signals) -> list[Slot]:
    q = float(np.clip(coef.get("quadratic", 0.0), -1e3, 1e3))
    c = float(np.clip(coef.get("cubic", 0.0), -1e3, 1e3))
    d = float(np.clip(coef.get("quartic", 0.0), -1e3, 1e3))
    return [("after", PolynomialGainElement(quadratic_per_v=q, cubic_per_v2=c, quartic_per_v3=d))]


def _thermal_columns(sig: Signals, variant: str, param: Optional[float]) -> list[Col]:
    """The temperature's departure from the reference (lagged in the ``lag`` variants), its square in the
    ``curved`` ones (a zero whose temperature coefficient itself changes with temperature), and the departure itself
    beside the lagged one in ``lag_lead``: a zero that answers the temperature's rate as well as its level (a
    gradient across the bridge while the gauges catch up with the air; c (T - lag(T)) is c tau times the lagged
    rate of T)."""
    temp = _departure_c(sig, variant, param)
    cols: list[Col] = [("thermal", temp, -np.inf, np.inf, "additive", None)]
    if variant.endswith("curved"):
        cols.append(("thermal_curvature", temp ** 2, -np.inf, np.inf, "additive", None))
    if variant == "lag_lead":
        cols.append(("thermal_direct", _departure_c(sig, "direct", None), -np.inf, np.inf, "additive", None))
    return cols


def _departure_c(sig: Signals, variant: str, param: Optional[float]) -> FloatArray:
    """The temperature's departure from the reference [degC]; through a first-order lag of time constant ``param``
    in the ``lag`` variants, settled at the first temperature (:func:`~polyforce_ros.physics.chain.lagged_temperature_c`)."""
    if not variant.startswith("lag"):
        return sig.temperature - sig.temp_ref
    lagged = lagged_temperature_c(sig.t, sig.temperature, parameter(param))
    return (sig.temperature if lagged is None else lagged) - sig.temp_ref


def _span_thermal_columns(sig: Signals, variant: str, param: Optional[float]) -> list[Col]:
    """The core output scaled by the temperature's departure, x (1 + c dT) - x = c x dT (lagged in the ``lag``
    variants), by its square in the ``curved`` ones (a span coefficient that itself changes with temperature), and
    by the departure itself beside the lagged one in ``lag_lead``: the zero's thermal paths (:func:`_thermal_columns`)
    for the span, which a gradient across the body reaches as it reaches the zero."""
    temp = _departure_c(sig, variant, param)
    cols: list[Col] = [("span_thermal", sig.core_output * temp, -np.inf, np.inf, "sensor", None)]
    if variant.endswith("curved"):
        cols.append(("span_thermal_curvature", sig.core_output * temp ** 2, -np.inf, np.inf, "sensor", None))
    if variant == "lag_lead":
        cols.append(("span_thermal_direct", sig.core_output * _departure_c(sig, "direct", None), -np.inf, np.inf,
                     "sensor", None))
    return cols


def _span_thermal_elements(coef: Mapping[str, float], variant: str, param: Optional[float], sig: Signals) -> list[Slot]:
    c = float(np.clip(coef.get("span_thermal", 0.0), -0.05, 0.05))
    q = float(np.clip(coef.get("span_thermal_curvature", 0.0), -0.005, 0.005))
    d = float(np.clip(coef.get("span_thermal_direct", 0.0), -0.05, 0.05))
    tau = float(parameter(param)) if variant.startswith("lag") else 0.0
    return [("after", ThermalSensitivityElement(span_coefficient_per_c=c, thermal_tau_s=tau, span_curvature_per_c2=q,
                                                direct_span_coefficient_per_c=d,
                                                reference_c=float(np.clip(sig.temp_ref, -100.0, 300.0))))]


def _thermal_elements(coef: Mapping[str, float], variant: str, param: Optional[float], sig: Signals) -> list[Slot]:
    c = float(np.clip(coef.get("thermal", 0.0), -10.0, 10.0))
    q = float(np.clip(coef.get("thermal_curvature", 0.0), -1.0, 1.0))
    ref = float(np.clip(sig.temp_ref, -100.0, 300.0))
    if variant.startswith("lag"):
        out: list[Slot] = [("late", ThermalLagElement(coefficient_v_per_c=c, reference_c=ref,
                                                      tau_s=float(parameter(param)), curvature_v_per_c2=q))]
        if variant == "lag_lead":
            direct = float(np.clip(coef.get("thermal_direct", 0.0), -10.0, 10.0))
            out.append(("late", ThermalDriftElement(coefficient_v_per_c=direct, reference_c=ref)))
        return out
    return [("late", ThermalDriftElement(coefficient_v_per_c=c, reference_c=ref, curvature_v_per_c2=q))]


#: Knot intervals over the record of the spline variants of offset_drift (a wandering drift). 12 and 16 follow drift
#: events of 3-15 % of the record (with 8 at most, such an event leaves a ringing that a lagged thermal drift or a
#: slow delayed elasticity would take); the cross-validation keeps the finer ones from fitting what the coarse ones
#: need not.
SPLINE_INTERVALS = (4, 6, 8, 12, 16)


def variant_group(variant: str) -> str:
    """The group of variants that differ only in their number of columns (``spline12`` -> ``spline``)."""
    return variant.rstrip("0123456789") if variant.startswith("spline") else variant


def _spline_knots_s(duration_s: float, intervals: int) -> FloatArray:
    """Knot times (s after the first sample) of a spline drift of ``intervals`` equal intervals over the record."""
    return np.linspace(0.0, duration_s, intervals + 1)[1:]


#: Settling times [s] searched for the part of each jump of the zero that settles (the ``jumps`` variant of
#: offset_drift): a charge leaking away, a film drying, a surge decaying; the polish refines within them.
JUMP_SETTLE_S = (2.0, 100.0)
#: The share of each jump (as the residual shows it) that settles, within +-this: one share for every jump (one
#: mechanism), so that a jump whose blocks are left out is predicted from the others, not from its decay's tail.
JUMP_SETTLE_BOUND = 3.0


def _jump_columns(sig: Signals, variant: str, param: Optional[float]) -> list[Col]:
    """A step at each of the record's zero jumps (:attr:`.signals.Signals.zero_jumps`) and, in the ``jumps``
    variant, one column beside them: every jump's size (as the residual shows it) decaying with time ``param``, whose
    coefficient is the share of each jump that settles."""
    key = ("jump steps", sig.zero_jumps)
    if key not in sig.cache:  # the same for every settling time
        # a ridge, as on a spline's knots: with the blocks between two jumps left out only their sum is seen
        steps = StepDriftElement.basis(sig.t - sig.t0, [jump.at_s - sig.t0 for jump in sig.zero_jumps])
        sig.cache[key] = [(f"jump{j}", steps[:, j], -np.inf, np.inf, "additive", "jump")
                          for j in range(steps.shape[1])]
    cols: list[Col] = list(sig.cache[key])
    if variant == "jumps" and sig.zero_jumps:
        settle = np.zeros_like(sig.t)
        for (_, step, *_), jump in zip(cols, sig.zero_jumps):
            settle += step * jump.size_v * np.exp(-np.maximum(sig.t - jump.at_s, 0.0) / parameter(param))
        cols.append(("settle", settle, -JUMP_SETTLE_BOUND, JUMP_SETTLE_BOUND, "additive", None))
    return cols


def _drift_columns(sig: Signals, variant: str, param: Optional[float]) -> list[Col]:
    if variant in ("steps", "jumps"):
        return _jump_columns(sig, variant, param)
    s = (sig.t - sig.t0) / sig.duration_s
    if variant.startswith("spline"):  # ridge on the knot values: small where the data say little
        basis = SplineDriftElement.basis(sig.t - sig.t0, _spline_knots_s(sig.duration_s, int(variant[6:])))
        return [(f"knot{j}", basis[:, j], -np.inf, np.inf, "additive", "spline") for j in range(basis.shape[1])]
    if variant == "settling":  # a linear part and an exponential approach of time constant param (s)
        return [("drift1", s, -np.inf, np.inf, "additive", None),
                ("drift_exp", -np.expm1(-(sig.t - sig.t0) / parameter(param)), -np.inf, np.inf, "additive", None)]
    return [(f"drift{p}", s ** p, -np.inf, np.inf, "additive", None) for p in (1, 2, 3)]


def _drift_elements(coef: Mapping[str, float], variant: str, param: Optional[float], sig: Signals) -> list[Slot]:
    d = sig.duration_s
    if variant in ("steps", "jumps"):
        if not sig.zero_jumps:
            return []
        times = [jump.at_s - sig.t0 for jump in sig.zero_jumps]
        steps = [float(np.clip(coef.get(f"jump{j}", 0.0), -1e3, 1e3)) for j in range(len(times))]
        if variant == "steps":
            return [("late", StepDriftElement(times_s=times, steps_v=steps))]
        share = float(np.clip(coef.get("settle", 0.0), -JUMP_SETTLE_BOUND, JUMP_SETTLE_BOUND))
        settles = [float(np.clip(share * jump.size_v, -1e3, 1e3)) for jump in sig.zero_jumps]
        return [("late", StepDriftElement(times_s=times, steps_v=steps, recovery_tau_s=parameter(param),
                                          recoveries_v=settles))]
    if variant.startswith("spline"):
        m = int(variant[6:])
        values = [float(np.clip(coef.get(f"knot{j}", 0.0), -1e3, 1e3)) for j in range(m)]
        return [("late", SplineDriftElement(knots_s=list(_spline_knots_s(d, m)), values_v=values))]
    c = [float(np.clip(coef.get(f"drift{p}", 0.0) / d ** p, -1e3, 1e3)) for p in (1, 2, 3)]
    out: list[Slot] = [("late", PolynomialDriftElement(rate_v_per_s=c[0], curvature_v_per_s2=c[1], cubic_v_per_s3=c[2]))]
    if variant == "settling":
        out.append(("late", ExponentialDriftElement(amplitude_v=float(np.clip(coef.get("drift_exp", 0.0), -1e3, 1e3)),
                                                    tau_s=float(parameter(param)))))
    return out


def lag_stages(variant: str, tau_s: float) -> list[float]:
    """Time constants (s) of the first-order stages of a sensor lag of total delay ``tau_s`` (none for a pure delay)."""
    if variant == "delay":
        return []
    return [tau_s / 2.0, tau_s / 2.0] if variant == "pole_pair" else [tau_s]


def _lag_elements(coef: Mapping[str, float], variant: str, param: Optional[float], sig: Signals) -> list[Slot]:
    if variant == "delay":
        return [("lag", TransportDelayElement(delay_s=float(parameter(param))))]
    return [("lag", SensorLagElement(tau_s=float(tau))) for tau in lag_stages(variant, parameter(param))]


#: The total delay of a sensor lag's poles searched [s]: from electronics (3 ms) to mechanical and
#: signal-conditioning filters (0.8 s).
LAG_DELAY_RANGE_S = (0.003, 0.8)


def _lag_grid(variant: str, sig: Signals) -> list[Optional[float]]:
    """Delays (s) searched: a transport delay of DAQ buffering (2-100 ms), or the total delay of one pole or two
    equal poles (:data:`LAG_DELAY_RANGE_S`)."""
    return log_grid(0.002, 0.1, 10) if variant == "delay" else log_grid(*LAG_DELAY_RANGE_S, 12)


#: How much slower each further Kelvin unit of a spread delayed elasticity starts than the one before: apart enough
#: that their columns are not collinear, close enough that two of them span a decade of a spread spectrum.
SPREAD_RATIO = 10.0


def _delayed_grid(variant: str, sig: Signals) -> list[Optional[float]]:
    """Starting retardation times (s) of a delayed elasticity, up to a quarter of the record; the polish may take
    one up to the record's length (:func:`.refit.polish`), beyond which it is flow within the record. A spread one
    (two units) starts its second unit :data:`SPREAD_RATIO` times slower, so its first starts within the record
    divided by that."""
    grid = log_grid(0.3, max(min(300.0, sig.duration_s / 4.0), 1.0), 12)
    if variant == "spread":
        return [g for g in grid if g is not None and g * SPREAD_RATIO <= sig.duration_s / 2.0]
    return grid


#: Knees of a load-dependent delayed elasticity (its ``knee`` variants), as fractions of the force span above the
#: smallest force: a Kelvin unit that a preload keeps out of play at low loads, or that a stop holds at high ones; all
#: three together (``knees``) make a curved dependence (a spring that stiffens, a stop that engages gradually).
KNEE_FRACTIONS = {"knee15": (0.15,), "knee30": (0.3,), "knee50": (0.5,), "knees": (0.15, 0.3, 0.5)}


def knees_n(sig: Signals, variant: str) -> FloatArray:
    """The knees of a ``knee`` variant of delayed elasticity [N], within the range the force covers."""
    f = sig.f_nonlinear
    return float(np.min(f)) + np.asarray(KNEE_FRACTIONS[variant]) * max(float(np.ptp(f)), 1e-9)


def _knee_columns(sig: Signals, variant: str, param: Optional[float]) -> list[Col]:
    """The ``knee`` variants' columns beside the Kelvin unit they add to the core: units of the same time loaded by
    the force above each knee, their compliances of either sign (more creep above a knee, or less)."""
    if variant not in KNEE_FRACTIONS:
        return []
    loads = np.maximum(sig.f_nonlinear[:, None] - knees_n(sig, variant)[None, :], 0.0)
    cols = lag_columns(sig.t, loads, parameter(param))
    return [(f"knee{k}", cols[:, k], -np.inf, np.inf, "sensor", None) for k in range(cols.shape[1])]


def _knee_elements(coef: Mapping[str, float], variant: str, param: Optional[float], sig: Signals) -> list[Slot]:
    if variant not in KNEE_FRACTIONS:
        return []
    knees = knees_n(sig, variant)
    compliances = [coef.get(f"knee{k}", 0.0) for k in range(knees.size)]
    if not any(compliances):
        return []
    # the core here is a stand-in: build_chain puts the fitted core inside (:func:`knee_beside`)
    return [("core", knee_beside(ViscoelasticElement(sig.reference_core), knees, compliances, float(parameter(param))))]


#: The most the knee units may take off above a knee, as a share of the core's instantaneous compliance (the model
#: file's bound is all of it): the output still rises with the load at a tenth of the core's instant slope, so the
#: inverse stays single-valued and bounded.
KNEE_FLOOR_SHARE = 0.9


def volume_beside(core: ViscoelasticElement, scale_n_s: float, rates_v_per_n_s: Sequence[float]) -> PowerFlowElement:
    """``core`` beside a flow whose fluidity changes with the load-time integral passed, each rate within the model
    file's bounds and all shrunk together, when they must, so that with the core's own fluidity the total is never
    negative (:func:`~polyforce_ros.physics.chain.lowest_volume_fluidity`): the fitted shape, as much of it as a
    flow that only dissipates can hold."""
    rates = _bounded(rates_v_per_n_s, "flow_volume_rates_v_per_n_s")
    lowest, own = lowest_volume_fluidity(rates), series_fluidity(core)
    if lowest + own < 0.0:
        rates = rates * (own / -lowest) * (1.0 - 1e-9)
    return PowerFlowElement(core, 0.0, 1.0, 1.0, 0.0, float(_bounded(scale_n_s, "flow_volume_scale_n_s")),
                            [float(r) for r in rates])


def knee_beside(core: ViscoelasticElement, knees: npt.ArrayLike, compliances_v_per_n: Sequence[float],
                tau_s: float) -> KneeKelvinElement:
    """``core`` beside knee units, each compliance within the model file's bounds and their running sum above
    :data:`KNEE_FLOOR_SHARE` times minus the core's instantaneous compliance."""
    floor = -KNEE_FLOOR_SHARE * core.model.compliance().j0_v_per_n
    low, high = PARAMETER_BOUNDS["knee_compliances_v_per_n"][:2]
    kept, total = [], 0.0
    for c in compliances_v_per_n:
        c = float(np.clip(c, max(floor - total, low), high))
        kept.append(c)
        total += c
    return KneeKelvinElement(core, _bounded(knees, "knees_n"), kept, float(_bounded(tau_s, "knee_tau_s")))


def _thermal_grid(variant: str, sig: Signals) -> list[Optional[float]]:
    """Time constants (s) of the thermal lag; none for the direct variants."""
    return log_grid(3.0, 120.0, 6) if variant.startswith("lag") else [None]


def _drift_grid(variant: str, sig: Signals) -> list[Optional[float]]:
    """Time constants (s) of a settling drift, 5 % to the whole record, or of the part of a jump that settles
    (:data:`JUMP_SETTLE_S`); none for the other variants. A record without zero jumps has no ``steps`` or ``jumps``."""
    if variant in ("steps", "jumps") and not sig.zero_jumps:
        return []
    if variant == "jumps":
        return log_grid(*JUMP_SETTLE_S, 5)
    return [sig.duration_s * f for f in (0.05, 0.1, 0.2, 0.35, 0.6, 1.0)] if variant == "settling" else [None]


EFFECTS: dict[str, Effect] = {
    "viscous_flow": Effect(
        "viscous_flow", "creep during holds that never settles (viscous_flow)", ("hold_under_load", "late_in_record"),
        ("load_history",), ("maxwell", "burgers", "burgers2", "burgers3", "power_flow"),
        # the core's linear dashpot, or beside it one whose rate is a power of the force or flows above a yield, or
        # one whose fluidity changes with the load-time integral passed (strain hardening, clogging, a growing leak)
        variants=("", "power", "yield", "volume"), grid=_flow_grid, columns=_flow_columns, to_elements=_flow_elements,
        extends={"power": "", "yield": "", "volume": ""},
        core_change={"elastic": "maxwell", "zener": "burgers", "zener2": "burgers2", "zener3": "burgers3"}),
    "delayed_elasticity": Effect(
        "delayed_elasticity", "creep and recovery that settle (delayed_elasticity)", ("hold_under_load", "rest_after_unloading"),
        ("load_history",), ("zener", "burgers", "zener2", "burgers2", "zener3", "burgers3", "knee_kelvin"),
        grid=_delayed_grid,
        # one Kelvin unit, two a decade apart (a retardation spectrum spread over time scales), or one beside units of
        # the same time that only the force above a knee loads (one knee, or three: a curved dependence on the load)
        variants=("", "spread", *KNEE_FRACTIONS), extends={"spread": "", **{k: "" for k in KNEE_FRACTIONS}},
        also_holds={"knees": tuple(k for k in KNEE_FRACTIONS if k != "knees")},
        core_times={"": 1, "spread": 2, **{k: 1 for k in KNEE_FRACTIONS}}, columns=_knee_columns,
        to_elements=_knee_elements,
        core_change={"elastic": "zener", "maxwell": "burgers", "zener": "zener2", "burgers": "burgers2",
                     "zener2": "zener3", "burgers2": "burgers3"}),
    "hysteresis": Effect(
        "hysteresis", "path dependence at load reversals (hysteresis)", ("load_reversal",), ("load_direction",),
        ("play_hysteresis", "bridge_hysteresis"),
        variants=("force", "voltage", "bridge", "force_descending", "voltage_descending", "bridge_descending",
                  "force_stop", "voltage_stop", "bridge_stop", "force_stop_descending", "voltage_stop_descending",
                  "bridge_stop_descending", "bridge_scaled"),
        # plays at the bridge and beside them plays whose bands grow with the load (a friction whose normal force
        # the load makes): chosen only when the scaled plays add what the bridge's plays miss
        extends={"bridge_scaled": "bridge"}, summed=("bridge_scaled",),
        columns=_hyst_columns, to_elements=_hyst_elements, rivals=("friction",)),
    "friction": Effect(
        "friction", "a dead band at load reversals, the same width at every load (friction)", ("load_reversal",),
        ("load_direction",), ("friction",), grid=friction.grid, columns=friction.columns, to_elements=friction.elements,
        # a band of one width, or one that follows the mechanism's temperature (chosen only when its band column is
        # significant)
        variants=friction.VARIANTS, extends={v: "" for v in friction.BAND_LAGS_S}, grid_variant=friction.grid_variant,
        # a partial friction is a single force play (F - c stop = (1 - c) F + c play), and a few plays are a spread
        # friction: with both named, each takes the other's misfit between their radii
        rivals=("hysteresis",)),
    "sensor_lag": Effect(
        "sensor_lag", "dynamics faster than the model (sensor_lag)", ("fast_transient",), ("force_rate",), ("sensor_lag",),
        # one pole, two equal poles (a critically damped pair) of the same total delay param, or a pure delay
        variants=("", "pole_pair", "delay"), grid=_lag_grid, columns=_lag_apply, to_elements=_lag_elements),
    "resonance": Effect(
        "resonance", "ringing after fast load changes (resonance)", ("fast_transient",), ("force_rate",), ("resonance",),
        record_rate=True),
    "nonlinear_gain": Effect(
        "nonlinear_gain", "gain changing with load (nonlinear_gain)", ("high_load",), ("force_squared",), ("polynomial_gain",),
        columns=_gain_columns, to_elements=_gain_elements),
    "thermal_drift": Effect(
        "thermal_drift", "output following temperature (thermal_drift)", ("temperature_change",), ("temperature",),
        ("thermal_drift", "thermal_lag"),
        variants=("direct", "lag", "direct_curved", "lag_curved", "lag_lead"), grid=_thermal_grid,
        extends={"direct_curved": "direct", "lag_curved": "lag", "lag_lead": "lag"}, also_holds={"lag_lead": ("direct",)},
        columns=_thermal_columns, to_elements=_thermal_elements, needs_temperature=True),
    "thermal_sensitivity": Effect(
        "thermal_sensitivity", "a span that follows temperature (thermal_sensitivity)", ("temperature_change", "high_load"),
        ("temperature",), ("thermal_sensitivity",), variants=("direct", "lag", "direct_curved", "lag_curved", "lag_lead"),
        grid=_thermal_grid, extends={"direct_curved": "direct", "lag_curved": "lag", "lag_lead": "lag"},
        also_holds={"lag_lead": ("direct",)}, columns=_span_thermal_columns,
        to_elements=_span_thermal_elements, needs_temperature=True),
    "thermo_rheological": Effect(
        "thermo_rheological", "creep whose speed follows temperature (thermo_rheological)",
        ("temperature_change", "hold_under_load"),
        ("temperature", "load_history"), ("thermo_rheological",), grid=_shift_grid, columns=_core_clock,
        variants=("", *(clock_lag_variant(s) for s in CLOCK_LAGS_S), *(f"wlf{c}" for c in CLOCK_C2S_C),
                  SLOWING, *(clock_lag_variant(s, slowing=True) for s in CLOCK_LAGS_S)),
        to_elements=_shift_elements, needs_temperature=True),
    "offset_drift": Effect(
        "offset_drift", "a slow drift over time (offset_drift)", ("late_in_record",), ("time",),
        ("polynomial_drift", "exponential_drift", "spline_drift", "step_drift"),
        variants=("polynomial", "settling", *(f"spline{m}" for m in SPLINE_INTERVALS), "steps", "jumps"), grid=_drift_grid,
        extends={"jumps": "steps"},
        columns=_drift_columns, to_elements=_drift_elements),
}

#: The catalogue's names, in a fixed order (CLI choices, report tables, the matrix).
NAMES = tuple(EFFECTS)


def hints() -> dict[str, list[str]]:
    """Localisation hints: segment kind / signal -> the effects whose residual shows there."""
    out: dict[str, list[str]] = {}
    for e in EFFECTS.values():
        for key in e.segments + e.signals:
            out.setdefault(key, []).append(e.name)
    return out
