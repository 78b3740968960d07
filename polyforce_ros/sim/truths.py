"""The bench generator's truths: how each effect of the catalogue appears in a simulated sensor.

Every effect of :data:`polyforce_ros.discrepancy.effects.NAMES` appears as several independent *families*
(:data:`FAMILIES`), each a maker of random truth elements of a given magnitude; none is the element the engine fits.
A family marked ``held_out`` is never used while tuning the engine, and neither are the seeds of the held-out
split (:data:`SPLITS`). Elements that can only simulate (:class:`BoucWen`, :class:`SecondOrderLag`,
:class:`StaticMap`, :class:`Additive`) live here too; a forward-only chain admits them.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Optional, TypedDict, Union

import numpy as np
import numpy.typing as npt

from ..physics.chain import (
    ForwardElement, PlayHysteresisElement, PreisachElement, SensorLagElement, ThermalDriftElement, ThermalLagElement,
    ThermalSensitivityElement, TransportDelayElement, play_operator,
)
from ..physics.preisach import hysteretic_identity
from ..physics.viscoelastic import (Burgers, Burgers2, Elastic, ForwardState, Maxwell, ViscoelasticModel, Zener, Zener2,
                                   simulate_deformation)

__all__ = ["FloatArray", "TruthContext", "BoucWen", "PlaysAtBridge", "ShiftedClockCore",
           "SecondOrderLag", "StaticMap", "AdditiveFn", "Additive", "Truth",
           "MakeFn", "Family", "FAMILIES", "HIDDEN_AGAINST", "SPLITS", "families"]

FloatArray = npt.NDArray[np.float64]


class TruthContext(TypedDict):
    """What a family maker knows of the sensor it hides its effect in.

    ``core``: the truth core so far; ``force_range_n``: the load's range [N]; ``duration_s``: the record's
    length [s]; ``gain_v_per_n``: the core's static gain [V/N].
    """

    core: ViscoelasticModel
    force_range_n: float
    duration_s: float
    gain_v_per_n: float


# --------------------------------------------------------------------------- simulate-only elements
# Truth elements of the families that the engine never fits in this form (forward only; the bench simulator
# needs nothing else).

class _SimElement:
    """An element that can only simulate: stateless between blocks unless it says otherwise."""

    kind = "sim"

    def forward_state(self) -> Any:
        """A fresh state for block-wise runs (an empty mapping)."""
        return {}


class BoucWen(_SimElement):
    """Bouc-Wen hysteresis on the voltage path: y = x + z, dz = A dx - beta |dx| |z|^(n-1) z - gamma dx |z|^n."""

    def __init__(self, amplitude: float, beta: float, gamma: float, n: float = 1.0) -> None:
        self.a, self.beta, self.gamma, self.n = amplitude, beta, gamma, n

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Any = None) -> FloatArray:
        """Output for input ``x`` [V]; ``state`` (a dict) carries z and the last input across blocks."""
        x = np.asarray(x, dtype=float)
        st = state if state is not None else {}
        z, xp = st.get("z", 0.0), st.get("x", 0.0)
        out = np.empty_like(x)
        for i, xi in enumerate(x):
            dx = xi - xp
            for _ in range(4):  # four sub-steps per sample: stable for the loop sizes used
                d = dx / 4
                z += self.a * d - self.beta * abs(d) * abs(z) ** (self.n - 1) * z - self.gamma * d * abs(z) ** self.n
            xp = xi
            out[i] = xi + z
        st["z"], st["x"] = z, xp
        return out


class SecondOrderLag(_SimElement):
    """A damped pole pair (electronics / anti-alias filter): y'' + 2 zeta w y' + w^2 y = w^2 x.

    ``omega`` [rad/s], ``zeta`` [-]."""

    def __init__(self, omega: float, zeta: float) -> None:
        self.w, self.z = omega, zeta

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Any = None) -> FloatArray:
        """Output for input ``x``, from rest, on a uniform grid at the median step (each block on its own)."""
        from scipy import signal

        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        sys = signal.lti([self.w ** 2], [1.0, 2 * self.z * self.w, self.w ** 2])
        h = float(np.median(np.diff(t)))
        tu = np.arange(t[0], t[-1] + h, h)
        _, y, _ = signal.lsim(sys, np.interp(tu, t, x), tu - tu[0])
        out: FloatArray = np.interp(t, tu, y)
        return out


class StaticMap(_SimElement):
    """y = fn(x) per sample."""

    def __init__(self, fn: Callable[[FloatArray], FloatArray]) -> None:
        self.fn = fn

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Any = None) -> FloatArray:
        """``fn(x)``."""
        return self.fn(np.asarray(x, dtype=float))


#: An additive term: (time since the first sample [s], temperature [degC] or None) -> volts.
AdditiveFn = Callable[[FloatArray, Optional[FloatArray]], FloatArray]


class Additive(_SimElement):
    """y = x + fn(t - t_first, temperature)."""

    def __init__(self, fn: AdditiveFn) -> None:
        self.fn = fn

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Any = None) -> FloatArray:
        """The input plus the term at the block's times (counted from the block's first)."""
        t = np.asarray(t_s, dtype=float)
        temp = None if not aux or aux.get("temperature_c") is None else np.broadcast_to(aux["temperature_c"], t.shape)
        return np.asarray(x, dtype=float) + self.fn(t - t[0], temp)


class PlaysAtBridge(_SimElement):
    """A core with play operators on the applied force added at the bridge, without creep:
    V = core(F) + sum_i w_i (p_{r_i}(F) - c F), with c = 1 for a bounded term (each play less the force) or 0."""

    def __init__(self, core: ViscoelasticModel, radii_n: FloatArray, weights_v_per_n: FloatArray, bounded: bool) -> None:
        self.core, self.radii_n, self.weights_v_per_n = core, radii_n, weights_v_per_n
        self.linear = 1.0 if bounded else 0.0

    def forward_state(self) -> Any:
        """The core's state and the plays' (relaxed, virgin)."""
        return {"core": ForwardState(self.core), "plays": np.zeros(self.radii_n.size)}

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Any = None) -> FloatArray:
        """Core output plus the plays' term [V] for the force ``x`` [N]."""
        f = np.asarray(x, dtype=float)
        st = state if state is not None else self.forward_state()
        plays = play_operator(f, self.radii_n, st["plays"])
        if f.size:
            st["plays"] = plays[-1].copy()
        term = (plays - self.linear * f[:, None]) @ self.weights_v_per_n
        return np.asarray(simulate_deformation(self.core, t_s, f, state=st["core"]) + term, dtype=float)


class ShiftedClockCore(_SimElement):
    """A core whose viscosities follow temperature by the shift factor ``a(T) = exp(log_shift(T))``: it runs on
    ``xi = int dt / a(T)`` (rectangle rule at each sample's own temperature; the forward model's own rule is the
    trapezoid). The whole record in one block."""

    def __init__(self, core: ViscoelasticModel, log_shift: Callable[[FloatArray], FloatArray]) -> None:
        self.core, self.log_shift = core, log_shift

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Any = None) -> FloatArray:
        """Deformation [V] for the force ``x`` [N] at temperatures ``aux['temperature_c']`` [degC]."""
        t = np.asarray(t_s, dtype=float)
        if not aux or aux.get("temperature_c") is None:
            raise ValueError("a thermo-rheological truth needs the temperature")
        temp = np.broadcast_to(np.asarray(aux["temperature_c"], dtype=float), t.shape)
        xi = t[0] + np.concatenate([[0.0], np.cumsum(np.diff(t) * np.exp(-self.log_shift(temp[1:])))])
        return np.asarray(simulate_deformation(self.core, xi, np.asarray(x, dtype=float)), dtype=float)


@dataclass
class Truth:
    """What a family does to the sensor truth: core replaced, elements before/after the core, at the end.

    ``core`` is a viscoelastic model that replaces the base's, or an element that simulates the core itself
    (an out-of-catalogue load-dependent core).
    """

    core: Union[ViscoelasticModel, ForwardElement, None] = None
    before: list[ForwardElement] = field(default_factory=list)  # force path (before the core)
    after: list[ForwardElement] = field(default_factory=list)   # voltage path (after the core, before the lag)
    late: list[ForwardElement] = field(default_factory=list)    # after the lag: thermal, drift


#: A family maker: (random generator, magnitude 0..1, context) -> the truth it hides.
MakeFn = Callable[[np.random.Generator, float, TruthContext], Truth]


@dataclass(frozen=True)
class Family:
    """One way an effect appears in a sensor; ``make(rng, magnitude, ctx) -> Truth``."""

    make: MakeFn
    held_out: bool = False


# --------------------------------------------------------------------------- family makers

def _span_v(ctx: TruthContext) -> float:
    return ctx["gain_v_per_n"] * ctx["force_range_n"]


def _random_play(rng: np.random.Generator, span: float, loop_fraction: float, n: int) -> PlayHysteresisElement:
    """A Prandtl-Ishlinskii operator with random radii and weights whose loop is ``loop_fraction`` of ``span``."""
    radii = np.sort(rng.uniform(0.01, 0.35, n)) * span
    w = rng.gamma(1.5, 1.0, n)
    # the loop width at full amplitude is about 2 sum w_i r_i (for small weights)
    w *= loop_fraction * span / (2.0 * np.sum(w * radii))
    return PlayHysteresisElement(1.0, np.maximum.accumulate(radii + 1e-9 * np.arange(n)), w)


def _hyst_preisach(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    frac = np.interp(m, [0, 1], [0.01, 0.06])
    return Truth(before=[PreisachElement(hysteretic_identity(0.0, ctx["force_range_n"], frac / 1.0), continuous=True)])


def _random_stop(rng: np.random.Generator, span: float, loop_fraction: float, n: int) -> PlayHysteresisElement:
    """A sum of stop operators on top of the input, x + sum w_i stop_{r_i}(x) (stop = x - play), as a
    Prandtl-Ishlinskii operator: steep after each reversal, saturating; loading above unloading."""
    radii = np.sort(rng.uniform(0.004, 0.06, n)) * span
    w = rng.gamma(1.5, 1.0, n)
    w *= loop_fraction * span / (2.0 * np.sum(w * radii))  # each stop spans +-r: loop width 2 sum w r
    return PlayHysteresisElement(1.0 + float(np.sum(w)), np.maximum.accumulate(radii + 1e-9 * np.arange(n)), -w)


def _pi_family(operator: Callable[[np.random.Generator, float, float, int], PlayHysteresisElement], path: str,
               n_high: int) -> MakeFn:
    """Family maker: a random Prandtl-Ishlinskii ``operator`` (:func:`_random_play` or :func:`_random_stop`) with
    2..n_high-1 operators on the force path (before the core) or the voltage path (after it), loop 1-6 % of its span."""

    def make(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
        frac = np.interp(m, [0, 1], [0.01, 0.06])
        span = ctx["force_range_n"] if path == "force" else _span_v(ctx)
        element = operator(rng, span, frac, int(rng.integers(2, n_high)))
        return Truth(before=[element]) if path == "force" else Truth(after=[element])

    return make


def _bridge_family(bounded: bool) -> MakeFn:
    """Family maker: 2..7 plays of random radii (1-35 % of the force range) on the applied force added at the
    bridge beside the truth core, loop 1-6 % of the voltage span; ``bounded``: each play less the force."""

    def make(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
        frac = np.interp(m, [0, 1], [0.01, 0.06])
        n = int(rng.integers(2, 8))
        radii = np.sort(rng.uniform(0.01, 0.35, n)) * ctx["force_range_n"] + 1e-9 * np.arange(n)
        w = rng.gamma(1.5, 1.0, n)
        w *= frac * _span_v(ctx) / (2.0 * np.sum(w * radii))
        return Truth(core=PlaysAtBridge(ctx["core"], np.maximum.accumulate(radii), w, bounded))

    return make


def _hyst_bouc_wen(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    frac = np.interp(m, [0, 1], [0.01, 0.06])
    span = _span_v(ctx)
    n = 1.0
    # loop height ~ 2 z_max, z_max = A / (beta + gamma) for n = 1
    a = rng.uniform(0.5, 1.0)
    total = a / (frac * span / 2.0)
    beta = total * rng.uniform(0.5, 0.8)
    return Truth(after=[BoucWen(a * rng.uniform(0.8, 1.2), beta, total - beta, n)])


def _friction_family(rigid: bool) -> MakeFn:
    """Family maker: Coulomb friction in the mechanism, a stiction band of half-width 0.5-3 % of the force range on
    the force the core sees; ``rigid``: the whole force sticks (a play with no linear part), else 60-95 % of it."""

    def make(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * ctx["force_range_n"] * rng.uniform(0.8, 1.2))
        coupling = 1.0 - 1e-6 if rigid else float(rng.uniform(0.6, 0.95))
        return Truth(before=[PlayHysteresisElement(1.0 - coupling, [r], [coupling])])

    return make


def _lag_first(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    return Truth(after=[SensorLagElement(tau_s=float(np.interp(m, [0, 1], [0.01, 0.15]) * rng.uniform(0.8, 1.2)))])


def _lag_second(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    tau = float(np.interp(m, [0, 1], [0.012, 0.15]) * rng.uniform(0.8, 1.2))
    zeta = rng.uniform(0.5, 1.0)
    return Truth(after=[SecondOrderLag(2 * zeta / tau, zeta)])  # effective delay 2 zeta / omega = tau


def _lag_delay(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    # DAQ buffering or transport: 5-40 ms
    return Truth(after=[TransportDelayElement(delay_s=float(np.interp(m, [0, 1], [0.005, 0.04]) * rng.uniform(0.9, 1.1)))])


def _lag_two_stage(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    tau = float(np.interp(m, [0, 1], [0.012, 0.15]) * rng.uniform(0.8, 1.2))
    share = rng.uniform(0.2, 0.8)  # e.g. an RC anti-alias stage and the sensor's own: delays add up to tau
    return Truth(after=[SensorLagElement(tau_s=share * tau), SensorLagElement(tau_s=(1 - share) * tau)])


def _mode_family(light: bool) -> MakeFn:
    """Family maker: a mechanical mode on the voltage path, 12-35 Hz, lightly damped (zeta 0.25 at magnitude 0 down
    to 0.02 at 1) or moderately (0.4 down to 0.1)."""

    def make(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
        zeta = float(np.exp(np.interp(m, [0, 1], np.log([0.25, 0.02] if light else [0.4, 0.1]))) * rng.uniform(0.8, 1.2))
        return Truth(after=[SecondOrderLag(2 * np.pi * float(rng.uniform(12.0, 35.0)), zeta)])

    return make


def _gain_poly(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    span = _span_v(ctx)
    rel = np.interp(m, [0, 1], [0.015, 0.12]) * rng.choice([-1, 1])  # deviation at full scale
    share = rng.uniform(0.0, 1.0)
    q2, q3 = share * rel / span, (1 - share) * rel / span ** 2

    def gain(x: FloatArray) -> FloatArray:
        out: FloatArray = x + q2 * x * x + q3 * x ** 3
        return out

    return Truth(after=[StaticMap(gain)])


def _gain_tanh(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    span = _span_v(ctx)
    rel = np.interp(m, [0, 1], [0.015, 0.12])  # saturation deficit at full scale
    # s tanh(x / s) = x (1 - (x/s)^2 / 3 ...): deficit rel at x = span -> s = span / sqrt(3 rel)
    s = span / np.sqrt(3 * rel)

    def gain(x: FloatArray) -> FloatArray:
        out: FloatArray = s * np.tanh(x / s)
        return out

    return Truth(after=[StaticMap(gain)])


def _gain_exp(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    span = _span_v(ctx)
    rel = np.interp(m, [0, 1], [0.015, 0.12])
    s = span / (2 * rel)  # s (1 - exp(-x/s)) = x - x^2 / (2 s): deficit rel at full scale

    def gain(x: FloatArray) -> FloatArray:
        out: FloatArray = s * (-np.expm1(-x / s))
        return out

    return Truth(after=[StaticMap(gain)])


def _drift_size(rng: np.random.Generator, m: float) -> float:
    return float(np.interp(m, [0, 1], [0.012, 0.1]) * rng.choice([-1, 1]))  # V over the record


def _drift_linear(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    a, d = _drift_size(rng, m), ctx["duration_s"]

    def drift(s: FloatArray, T: Optional[FloatArray]) -> FloatArray:
        return a * s / d

    return Truth(late=[Additive(drift)])


def _drift_power(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    a, d, p = _drift_size(rng, m), ctx["duration_s"], rng.uniform(0.7, 1.5)

    def drift(s: FloatArray, T: Optional[FloatArray]) -> FloatArray:
        out: FloatArray = a * (s / d) ** p
        return out

    return Truth(late=[Additive(drift)])


def _drift_exp(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    a, d, tau = _drift_size(rng, m), ctx["duration_s"], rng.uniform(0.2, 0.8) * ctx["duration_s"]

    def drift(s: FloatArray, T: Optional[FloatArray]) -> FloatArray:
        out: FloatArray = a * -np.expm1(-s / tau) / -np.expm1(-d / tau)
        return out

    return Truth(late=[Additive(drift)])


def _drift_walk(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    a, d = _drift_size(rng, m), ctx["duration_s"]
    # a slow random walk: integrated noise, low-passed to periods longer than the record / 2
    knots = np.concatenate([[0.0], np.cumsum(rng.normal(0, 1, 4))])
    knots = knots / max(np.max(np.abs(knots)), 1e-9)
    grid = np.linspace(0, d, knots.size)
    from scipy.interpolate import CubicSpline

    spline = CubicSpline(grid, knots, bc_type="natural")

    def drift(s: FloatArray, T: Optional[FloatArray]) -> FloatArray:
        out: FloatArray = a * spline(s)
        return out

    return Truth(late=[Additive(drift)])


def _drift_events(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    a, d = _drift_size(rng, m), ctx["duration_s"]
    # two or three humidity events: smooth steps of random sign, time and width
    k = int(rng.integers(2, 4))
    centre, width = rng.uniform(0.1, 0.9, k) * d, rng.uniform(0.03, 0.15, k) * d
    size = rng.uniform(0.4, 1.0, k) * rng.choice([-1, 1], k)
    size /= np.max(np.abs(np.cumsum(size)))

    def events(s: npt.ArrayLike) -> FloatArray:
        out: FloatArray = a * np.sum(size * (0.5 + 0.5 * np.tanh((np.asarray(s)[:, None] - centre) / width)), axis=1)
        return out

    def drift(s: FloatArray, T: Optional[FloatArray]) -> FloatArray:
        out: FloatArray = events(s) - events(np.zeros(1))[0]
        return out

    return Truth(late=[Additive(drift)])


def _thermal_linear(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    c = float(np.interp(m, [0, 1], [0.0015, 0.01]) * rng.choice([-1, 1]))
    return Truth(late=[ThermalDriftElement(coefficient_v_per_c=c, reference_c=24.0)])


def _thermal_lag(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    c = float(np.interp(m, [0, 1], [0.0015, 0.01]) * rng.choice([-1, 1]))
    return Truth(late=[ThermalLagElement(coefficient_v_per_c=c, reference_c=24.0, tau_s=float(rng.uniform(5.0, 60.0)))])


def _span_thermal(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    # a polymer sensor's span changes by 0.05-0.5 %/degC (a metal-foil cell's by ~0.01 %/degC)
    c = float(np.interp(m, [0, 1], [0.0005, 0.005]) * rng.choice([-1, 1]) * rng.uniform(0.8, 1.2))
    return Truth(after=[ThermalSensitivityElement(span_coefficient_per_c=c, reference_c=24.0)])


def _shift_family(law: str) -> MakeFn:
    """Family maker: the truth core's viscosities follow temperature, by an Arrhenius law in absolute temperature
    (``ln a = E/R (1/T - 1/T_ref)``) or the WLF law (``log10 a = -C1 dT / (C2 + dT)``), 0.02-0.12 per degree about
    24 degC."""

    def make(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
        b = float(np.interp(m, [0, 1], [0.02, 0.12]) * rng.uniform(0.8, 1.2))  # -d ln a / dT at the reference
        if law == "arrhenius":
            t_ref_k = 24.0 + 273.15
            e_over_r = b * t_ref_k ** 2

            def log_shift(temp: FloatArray) -> FloatArray:
                out: FloatArray = e_over_r * (1.0 / (temp + 273.15) - 1.0 / t_ref_k)
                return out
        else:
            c2 = float(rng.uniform(50.0, 120.0))
            c1 = b * c2 / np.log(10.0)

            def log_shift(temp: FloatArray) -> FloatArray:
                out: FloatArray = -np.log(10.0) * c1 * (temp - 24.0) / (c2 + temp - 24.0)
                return out

        return Truth(core=ShiftedClockCore(ctx["core"], log_shift))

    return make


def _viscous(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    core = ctx["core"]
    eta1 = float(np.exp(np.interp(m, [0, 1], np.log([40000.0, 1500.0]))) * rng.uniform(0.7, 1.3))
    if isinstance(core, Elastic):
        return Truth(core=Maxwell(core.k_n_per_v, eta1))
    if not isinstance(core, Zener):
        raise ValueError(f"a viscous flow is hidden against an elastic or a zener core, not a {core.kind}")
    return Truth(core=Burgers(core.k1_n_per_v, core.k2_n_per_v, eta1, core.eta2_n_s_per_v))


def _delayed(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    core = ctx["core"]
    k_new = float(np.interp(m, [0, 1], [60.0, 6.0]) * rng.uniform(0.8, 1.2))
    if isinstance(core, (Elastic, Maxwell)):
        tau = float(np.exp(rng.uniform(np.log(1.0), np.log(100.0))))  # two decades
        return Truth(core=Zener(core.k_n_per_v, k_new, k_new * tau) if isinstance(core, Elastic)
                     else Burgers(core.k_n_per_v, k_new, core.eta_n_s_per_v, k_new * tau))
    if not isinstance(core, (Zener, Burgers)):
        raise ValueError(f"a delayed elasticity is hidden against an elastic, maxwell, zener or burgers core, "
                         f"not a {core.kind}")
    own = core.eta2_n_s_per_v / core.k2_n_per_v
    # a second Kelvin element a decade or more away from the base's own (two decades overall)
    tau = float(own * np.exp(rng.choice([-1, 1]) * rng.uniform(np.log(5.0), np.log(15.0))))
    if isinstance(core, Zener):
        return Truth(core=Zener2(core.k1_n_per_v, core.k2_n_per_v, core.eta2_n_s_per_v, k_new, k_new * tau))
    return Truth(core=Burgers2(core.k1_n_per_v, core.k2_n_per_v, core.eta1_n_s_per_v, core.eta2_n_s_per_v, k_new, k_new * tau))


_FAM = Family
#: Every effect of the catalogue -> its families by name (a family marked held_out is never used while tuning).
FAMILIES: dict[str, dict[str, Family]] = {
    "viscous_flow": {"eta_two_decades": _FAM(_viscous)},
    "delayed_elasticity": {"tau_two_decades": _FAM(_delayed)},
    "hysteresis": {"preisach_force": _FAM(_hyst_preisach), "play_voltage": _FAM(_pi_family(_random_play, "voltage", 6)),
                   "stop_force": _FAM(_pi_family(_random_stop, "force", 5)),
                   "stop_voltage": _FAM(_pi_family(_random_stop, "voltage", 5)),
                   "play_force": _FAM(_pi_family(_random_play, "force", 6), held_out=True),
                   "bouc_wen_voltage": _FAM(_hyst_bouc_wen, held_out=True),
                   "play_bridge": _FAM(_bridge_family(bounded=False)),
                   "bounded_bridge": _FAM(_bridge_family(bounded=True), held_out=True)},
    "friction": {"rigid_contact": _FAM(_friction_family(rigid=True)),
                 "partial_contact": _FAM(_friction_family(rigid=False), held_out=True)},
    "sensor_lag": {"first_order": _FAM(_lag_first), "two_stage": _FAM(_lag_two_stage), "transport_delay": _FAM(_lag_delay),
                   "pole_pair": _FAM(_lag_second, held_out=True)},
    "resonance": {"light_mode": _FAM(_mode_family(light=True)), "moderate_mode": _FAM(_mode_family(light=False),
                                                                                      held_out=True)},
    "nonlinear_gain": {"polynomial": _FAM(_gain_poly), "exp_approach": _FAM(_gain_exp),
                       "tanh": _FAM(_gain_tanh, held_out=True)},
    "thermal_drift": {"linear": _FAM(_thermal_linear), "thermal_lag": _FAM(_thermal_lag, held_out=True)},
    "thermal_sensitivity": {"linear_span": _FAM(_span_thermal)},
    "thermo_rheological": {"arrhenius": _FAM(_shift_family("arrhenius")),
                           "wlf": _FAM(_shift_family("wlf"), held_out=True)},
    "offset_drift": {"linear": _FAM(_drift_linear), "exp_approach": _FAM(_drift_exp), "events": _FAM(_drift_events),
                     "power_law": _FAM(_drift_power, held_out=True), "random_walk": _FAM(_drift_walk, held_out=True)},
}

#: The base cores a core effect is hidden against (a core that does not hold it already); other effects: any base.
HIDDEN_AGAINST: dict[str, tuple[str, ...]] = {
    "viscous_flow": ("elastic", "zener"),
    "delayed_elasticity": ("elastic", "maxwell", "zener", "burgers"),
}

#: First seed of the split the engine was tuned on, and of the held-out split (never used while tuning). The
#: matrix gives its i-th case the seed ``first + 97 i`` (+1 for a second seed): tune seeds are 0 or 1 modulo 97,
#: held-out seeds 53 or 54, so the two splits never share a record (their ranges overlap beyond 5000).
SPLITS = {"tune": 0, "held_out": 5000}


def families(effect: str, split: str) -> list[str]:
    """Family names of ``effect`` usable in ``split`` ("tune": those not held out; "held_out": all)."""
    fams: Mapping[str, Family] = FAMILIES[effect]
    return [n for n, f in fams.items() if split == "held_out" or not f.held_out]
