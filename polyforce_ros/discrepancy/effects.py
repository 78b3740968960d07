"""The one effect registry: every effect of the catalogue, defined in one place.

An :class:`Effect` holds everything the project knows about one physical effect:

* how to **simulate** it for the bench generator, as several independent
  *families* with random parameters (:attr:`Effect.families`; a family marked
  ``held_out`` is never used while tuning the engine, see :data:`SPLITS`);
* how to **fit** it: the linear design columns it adds to the sensor model for
  a value of its nonlinear parameter, the grid that parameter is searched on,
  its variants (e.g. hysteresis on the force or on the voltage path), and, for
  the two core effects, the core type it turns the base into;
* its **model-file elements** (how fitted coefficients become chain elements,
  which ``polyforce compensate`` and ``compensation_node`` run backward);
* its **localisation hint**: the segment kinds and signals its residual shows in.

The generator (:mod:`polyforce_ros.sim.bench`), the engine (:mod:`.engine`),
the localiser (:mod:`.localise`), the report and the CLI choices all read
:data:`EFFECTS`; nothing about an effect is spelled anywhere else.

The fitted sensor model is linear in its coefficients once the nonlinear
parameters (retardation times, lag and thermal time constants) are fixed::

    V = Lag_tau( sum_j c_j s_j ) + sum_k d_k a_k + offset

with *sensor* columns ``s_j`` (the core's compliance terms F, int F, K_tau F;
hysteresis play operators; the squared core output) and *additive* columns
``a_k`` (temperature, drift polynomials). Cores are written in compliance
form: j0 F + phi int F + sum_i c_i K_{tau_i}(F), K a unit-gain first-order lag.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Optional

import numpy as np

from ..physics.chain import (
    ExponentialDriftElement, PlayHysteresisElement, PolynomialGainElement, PolynomialDriftElement, PreisachElement,
    SensorLagElement, TransportDelayElement,
    SplineDriftElement, ThermalDriftElement, ThermalLagElement, ThermalSensitivityElement, play_operator,
)
from ..physics.expconv import exp_convolve, exp_convolve_columns
from ..physics.preisach import hysteretic_identity
from ..physics.viscoelastic import Burgers, Burgers2, Maxwell, Zener, Zener2, simulate_deformation_columns

#: Column: (name, samples, lower bound, upper bound, "sensor" | "additive", ridge group or None).
Col = tuple

#: Play-operator half-widths of the hysteresis fit, as fractions of the input span (a regularised
#: non-negative weight distribution over them is fitted). 22 log-spaced, ~27 % apart: with radii up to 2x
#: apart, an operator between two of them leaves 1.5-2x the noise floor at 6 % loops, which a drift or a
#: gain then takes as a second effect.
PLAY_FRACTIONS = np.geomspace(0.003, 0.5, 22)
#: Ridge weight on the play weights, relative to the mean diagonal of the normal matrix.
PLAY_RIDGE = 1e-4


def lag_columns(t, x, tau_s):
    """Unit-gain first-order lag of each column of x (n,) or (n, m), from rest."""
    x = np.asarray(x, dtype=float)
    if x.ndim == 1:  # the design's columns, one by one: no stacking
        return exp_convolve(t, x, [1.0 / tau_s])[:, 0] / tau_s
    return exp_convolve_columns(t, x, 1.0 / tau_s) / tau_s  # one filter over all columns (column-major, contiguous)


# --------------------------------------------------------------------------- simulate-only elements
# Truth elements of the generator's families that the engine never fits in this form
# (forward only; the bench simulator needs nothing else).

class _SimElement:
    kind = "sim"

    def forward_state(self):
        return {}


class BoucWen(_SimElement):
    """Bouc-Wen hysteresis on the voltage path: y = x + z, dz = A dx - beta |dx| |z|^(n-1) z - gamma dx |z|^n."""

    def __init__(self, amplitude, beta, gamma, n=1.0):
        self.a, self.beta, self.gamma, self.n = amplitude, beta, gamma, n

    def forward(self, t, x, aux=None, state=None):
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
    """A damped pole pair (electronics / anti-alias filter): y'' + 2 zeta w y' + w^2 y = w^2 x."""

    def __init__(self, omega, zeta):
        self.w, self.z = omega, zeta

    def forward(self, t, x, aux=None, state=None):
        from scipy import signal

        t, x = np.asarray(t, dtype=float), np.asarray(x, dtype=float)
        sys = signal.lti([self.w ** 2], [1.0, 2 * self.z * self.w, self.w ** 2])
        h = float(np.median(np.diff(t)))
        tu = np.arange(t[0], t[-1] + h, h)
        _, y, _ = signal.lsim(sys, np.interp(tu, t, x), tu - tu[0])
        return np.interp(t, tu, y)


class StaticMap(_SimElement):
    """y = fn(x) per sample."""

    def __init__(self, fn):
        self.fn = fn

    def forward(self, t, x, aux=None, state=None):
        return self.fn(np.asarray(x, dtype=float))


class Additive(_SimElement):
    """y = x + fn(t - t_first, temperature)."""

    def __init__(self, fn):
        self.fn = fn

    def forward(self, t, x, aux=None, state=None):
        t = np.asarray(t, dtype=float)
        temp = None if not aux or aux.get("temperature_c") is None else np.broadcast_to(aux["temperature_c"], t.shape)
        return np.asarray(x, dtype=float) + self.fn(t - t[0], temp)


@dataclass
class Truth:
    """What a family does to the sensor truth: core replaced, elements before/after the core, at the end."""

    core: object = None
    before: list = field(default_factory=list)  # force path (before the core)
    after: list = field(default_factory=list)   # voltage path (after the core, before the lag)
    late: list = field(default_factory=list)    # after the lag: thermal, drift


@dataclass(frozen=True)
class Family:
    """One way an effect appears in a sensor; ``make(rng, magnitude, ctx) -> Truth``."""

    make: Callable
    held_out: bool = False


@dataclass(frozen=True)
class Effect:
    """An effect of the catalogue (see the module docstring)."""

    name: str
    hint: str
    segments: tuple
    signals: tuple
    elements: tuple
    families: dict
    variants: tuple = ("",)
    grid: Optional[Callable] = None            # (variant, sig) -> nonlinear parameter values (or [None])
    columns: Optional[Callable] = None         # (sig, variant, param) -> list of Col
    to_elements: Optional[Callable] = None     # (coef: name -> value, variant, param, sig) -> [(slot, element)]
    core_change: Optional[dict] = None         # base core kind -> augmented kind (core effects only)
    needs_temperature: bool = False
    needs_base: tuple = ()                     # generator: bases it is hidden against


# --------------------------------------------------------------------------- generator helpers

def _span_v(ctx):
    return ctx["gain_v_per_n"] * ctx["force_range_n"]


def _random_play(rng, span, loop_fraction, n):
    """A Prandtl-Ishlinskii operator with random radii and weights whose loop is ``loop_fraction`` of ``span``."""
    radii = np.sort(rng.uniform(0.01, 0.35, n)) * span
    w = rng.gamma(1.5, 1.0, n)
    # the loop width at full amplitude is about 2 sum w_i r_i (for small weights)
    w *= loop_fraction * span / (2.0 * np.sum(w * radii))
    return PlayHysteresisElement(1.0, np.maximum.accumulate(radii + 1e-9 * np.arange(n)), w)


def _hyst_preisach(rng, m, ctx):
    frac = np.interp(m, [0, 1], [0.01, 0.06])
    return Truth(before=[PreisachElement(hysteretic_identity(0.0, ctx["force_range_n"], frac / 1.0), continuous=True)])


def _random_stop(rng, span, loop_fraction, n):
    """A sum of stop operators on top of the input, x + sum w_i stop_{r_i}(x) (stop = x - play), as a
    Prandtl-Ishlinskii operator: steep after each reversal, saturating; loading above unloading."""
    radii = np.sort(rng.uniform(0.004, 0.06, n)) * span
    w = rng.gamma(1.5, 1.0, n)
    w *= loop_fraction * span / (2.0 * np.sum(w * radii))  # each stop spans +-r: loop width 2 sum w r
    return PlayHysteresisElement(1.0 + float(np.sum(w)), np.maximum.accumulate(radii + 1e-9 * np.arange(n)), -w)


def _pi_family(operator, path, n_high):
    """Family maker: a random Prandtl-Ishlinskii ``operator`` (:func:`_random_play` or :func:`_random_stop`) with
    2..n_high-1 operators on the force path (before the core) or the voltage path (after it), loop 1-6 % of its span."""

    def make(rng, m, ctx):
        frac = np.interp(m, [0, 1], [0.01, 0.06])
        span = ctx["force_range_n"] if path == "force" else _span_v(ctx)
        element = operator(rng, span, frac, int(rng.integers(2, n_high)))
        return Truth(before=[element]) if path == "force" else Truth(after=[element])

    return make


def _hyst_bouc_wen(rng, m, ctx):
    frac = np.interp(m, [0, 1], [0.01, 0.06])
    span = _span_v(ctx)
    n = 1.0
    # loop height ~ 2 z_max, z_max = A / (beta + gamma) for n = 1
    a = rng.uniform(0.5, 1.0)
    total = a / (frac * span / 2.0)
    beta = total * rng.uniform(0.5, 0.8)
    return Truth(after=[BoucWen(a * rng.uniform(0.8, 1.2), beta, total - beta, n)])


def _lag_first(rng, m, ctx):
    return Truth(after=[SensorLagElement(tau_s=float(np.interp(m, [0, 1], [0.01, 0.15]) * rng.uniform(0.8, 1.2)))])


def _lag_second(rng, m, ctx):
    tau = float(np.interp(m, [0, 1], [0.012, 0.15]) * rng.uniform(0.8, 1.2))
    zeta = rng.uniform(0.5, 1.0)
    return Truth(after=[SecondOrderLag(2 * zeta / tau, zeta)])  # effective delay 2 zeta / omega = tau


def _lag_delay(rng, m, ctx):
    # DAQ buffering or transport: 5-40 ms
    return Truth(after=[TransportDelayElement(delay_s=float(np.interp(m, [0, 1], [0.005, 0.04]) * rng.uniform(0.9, 1.1)))])


def _lag_two_stage(rng, m, ctx):
    tau = float(np.interp(m, [0, 1], [0.012, 0.15]) * rng.uniform(0.8, 1.2))
    share = rng.uniform(0.2, 0.8)  # e.g. an RC anti-alias stage and the sensor's own: delays add up to tau
    return Truth(after=[SensorLagElement(tau_s=share * tau), SensorLagElement(tau_s=(1 - share) * tau)])


def _gain_poly(rng, m, ctx):
    span = _span_v(ctx)
    rel = np.interp(m, [0, 1], [0.015, 0.12]) * rng.choice([-1, 1])  # deviation at full scale
    share = rng.uniform(0.0, 1.0)
    q2, q3 = share * rel / span, (1 - share) * rel / span ** 2
    return Truth(after=[StaticMap(lambda x, q2=q2, q3=q3: x + q2 * x * x + q3 * x ** 3)])


def _gain_tanh(rng, m, ctx):
    span = _span_v(ctx)
    rel = np.interp(m, [0, 1], [0.015, 0.12])  # saturation deficit at full scale
    # s tanh(x / s) = x (1 - (x/s)^2 / 3 ...): deficit rel at x = span -> s = span / sqrt(3 rel)
    s = span / np.sqrt(3 * rel)
    return Truth(after=[StaticMap(lambda x, s=s: s * np.tanh(x / s))])


def _gain_exp(rng, m, ctx):
    span = _span_v(ctx)
    rel = np.interp(m, [0, 1], [0.015, 0.12])
    s = span / (2 * rel)  # s (1 - exp(-x/s)) = x - x^2 / (2 s): deficit rel at full scale
    return Truth(after=[StaticMap(lambda x, s=s: s * (-np.expm1(-x / s)))])


def _drift_size(rng, m):
    return float(np.interp(m, [0, 1], [0.012, 0.1]) * rng.choice([-1, 1]))  # V over the record


def _drift_linear(rng, m, ctx):
    a, d = _drift_size(rng, m), ctx["duration_s"]
    return Truth(late=[Additive(lambda s, T, a=a, d=d: a * s / d)])


def _drift_power(rng, m, ctx):
    a, d, p = _drift_size(rng, m), ctx["duration_s"], rng.uniform(0.7, 1.5)
    return Truth(late=[Additive(lambda s, T, a=a, d=d, p=p: a * (s / d) ** p)])


def _drift_exp(rng, m, ctx):
    a, d, tau = _drift_size(rng, m), ctx["duration_s"], rng.uniform(0.2, 0.8) * ctx["duration_s"]
    return Truth(late=[Additive(lambda s, T, a=a, tau=tau, d=d: a * -np.expm1(-s / tau) / -np.expm1(-d / tau))])


def _drift_walk(rng, m, ctx):
    a, d = _drift_size(rng, m), ctx["duration_s"]
    # a slow random walk: integrated noise, low-passed to periods longer than the record / 2
    knots = np.concatenate([[0.0], np.cumsum(rng.normal(0, 1, 4))])
    knots = knots / max(np.max(np.abs(knots)), 1e-9)
    grid = np.linspace(0, d, knots.size)
    from scipy.interpolate import CubicSpline

    spline = CubicSpline(grid, knots, bc_type="natural")
    return Truth(late=[Additive(lambda s, T, a=a, sp=spline: a * sp(s))])


def _drift_events(rng, m, ctx):
    a, d = _drift_size(rng, m), ctx["duration_s"]
    # two or three humidity events: smooth steps of random sign, time and width
    k = int(rng.integers(2, 4))
    centre, width = rng.uniform(0.1, 0.9, k) * d, rng.uniform(0.03, 0.15, k) * d
    size = rng.uniform(0.4, 1.0, k) * rng.choice([-1, 1], k)
    size /= np.max(np.abs(np.cumsum(size)))

    def events(s, T, a=a, c=centre, w=width, h=size):
        return a * np.sum(h * (0.5 + 0.5 * np.tanh((np.asarray(s)[:, None] - c) / w)), axis=1)

    return Truth(late=[Additive(lambda s, T, ev=events: ev(s, T) - ev(np.zeros(1), T)[0])])


def _thermal_linear(rng, m, ctx):
    c = float(np.interp(m, [0, 1], [0.0015, 0.01]) * rng.choice([-1, 1]))
    return Truth(late=[ThermalDriftElement(coefficient_v_per_c=c, reference_c=24.0)])


def _thermal_lag(rng, m, ctx):
    c = float(np.interp(m, [0, 1], [0.0015, 0.01]) * rng.choice([-1, 1]))
    return Truth(late=[ThermalLagElement(coefficient_v_per_c=c, reference_c=24.0, tau_s=float(rng.uniform(5.0, 60.0)))])


def _span_thermal(rng, m, ctx):
    # a polymer sensor's span changes by 0.05-0.5 %/degC (a metal-foil cell's by ~0.01 %/degC)
    c = float(np.interp(m, [0, 1], [0.0005, 0.005]) * rng.choice([-1, 1]) * rng.uniform(0.8, 1.2))
    return Truth(after=[ThermalSensitivityElement(span_coefficient_per_c=c, reference_c=24.0)])


def _viscous(rng, m, ctx):
    core = ctx["core"]
    eta1 = float(np.exp(np.interp(m, [0, 1], np.log([40000.0, 1500.0]))) * rng.uniform(0.7, 1.3))
    if core.kind == "elastic":
        return Truth(core=Maxwell(core.k_n_per_v, eta1))
    return Truth(core=Burgers(core.k1_n_per_v, core.k2_n_per_v, eta1, core.eta2_n_s_per_v))


def _delayed(rng, m, ctx):
    core = ctx["core"]
    k_new = float(np.interp(m, [0, 1], [60.0, 6.0]) * rng.uniform(0.8, 1.2))
    if core.kind in ("elastic", "maxwell"):
        tau = float(np.exp(rng.uniform(np.log(1.0), np.log(100.0))))  # two decades
        return Truth(core=Zener(core.k_n_per_v, k_new, k_new * tau) if core.kind == "elastic"
                     else Burgers(core.k_n_per_v, k_new, core.eta_n_s_per_v, k_new * tau))
    own = core.eta2_n_s_per_v / core.k2_n_per_v
    # a second Kelvin element a decade or more away from the base's own (two decades overall)
    tau = float(own * np.exp(rng.choice([-1, 1]) * rng.uniform(np.log(5.0), np.log(15.0))))
    if core.kind == "zener":
        return Truth(core=Zener2(core.k1_n_per_v, core.k2_n_per_v, core.eta2_n_s_per_v, k_new, k_new * tau))
    return Truth(core=Burgers2(core.k1_n_per_v, core.k2_n_per_v, core.eta1_n_s_per_v, core.eta2_n_s_per_v, k_new, k_new * tau))


# --------------------------------------------------------------------------- fitting helpers

def _log_grid(lo, hi, n):
    return list(np.exp(np.linspace(np.log(lo), np.log(hi), n)))


def _hyst_start(radii, variant):
    """Play states before the record: virgin (zero) or after the input came down from the span (r)."""
    return radii if variant.endswith("descending") else np.zeros(radii.size)


def _hyst_columns(sig, variant, param):
    """Columns of a Prandtl-Ishlinskii hysteresis on the path of ``variant``, each zero at rest at the start.

    Play type: play operators p_r, non-negative weights (the curve steepens after a reversal). Stop type
    (``_stop``, Bouc-Wen-like loops, loading above unloading): stop operators s_r = input - p_r, bounded by
    +-r, non-negative weights. Fitting stops rather than negative plays keeps every column away from the
    input itself, so the core's gain and the weights cannot trade large opposite values."""
    force = variant.startswith("force")
    stop = "_stop" in variant
    key = ("hysteresis columns", force, stop, variant.endswith("descending"))
    if key not in sig.cache:
        span = sig.span_f if force else sig.span_x
        radii = PLAY_FRACTIONS * span
        start = _hyst_start(radii, variant)
        # the plays of the play and the stop type are the same: made once per path and start (the force's once per
        # record, the core output's once per reference core)
        plays_key = ("force plays" if force else "voltage plays", variant.endswith("descending"))
        store = sig.record_cache if force else sig.cache
        u = sig.f_nonlinear if force else sig.x_ref
        cols = store.get(plays_key)
        if cols is None:
            cols = store[plays_key] = play_operator(u, radii, start) - start
        if stop:
            cols = u[:, None] - cols
        sig.cache[key] = simulate_deformation_columns(sig.core_ref, sig.t, cols) if force else cols
    cols = sig.cache[key]
    return [(f"play{i}", cols[:, i], 0.0, np.inf, "sensor", "play") for i in range(cols.shape[1])]


def _hyst_elements(coef, variant, param, sig):
    span = sig.span_f if variant.startswith("force") else sig.span_x
    w = np.clip([max(coef.get(f"play{i}", 0.0), 0.0) for i in range(PLAY_FRACTIONS.size)], 0.0, 1e6)
    keep = w > 1e-12 * max(w.max(), 1e-300)
    if not keep.any():
        return []
    # on the force path the operator enters through the core (core(F + sum w op(F))); on the voltage path
    # the core output x stands for itself (x + sum w op(x)); x + sum w (x - p(x)) = (1 + sum w) x - sum w p(x)
    if "_stop" in variant:
        w = w * min(1.0, (1e6 - 1.0) / max(float(np.sum(w[keep])), 1e-300))  # linear_weight within its bound
    linear, weights = (1.0 + float(np.sum(w[keep])), -w[keep]) if "_stop" in variant else (1.0, w[keep])
    history = 2.0 * span if variant.endswith("descending") else 0.0
    return [("before" if variant.startswith("force") else "after",
             PlayHysteresisElement(linear, PLAY_FRACTIONS[keep] * span, weights, history_max=history))]


def _lag_apply(sig, variant, param):  # the lag has no columns of its own: it filters the sensor columns
    return []


def _gain_columns(sig, variant, param):
    return [("quadratic", sig.x_ref ** 2, -np.inf, np.inf, "sensor", None),
            ("cubic", sig.x_ref ** 3, -np.inf, np.inf, "sensor", None),
            ("quartic", sig.x_ref ** 4, -np.inf, np.inf, "sensor", None)]


def _gain_elements(coef, variant, param, sig):
    q = float(np.clip(coef.get("quadratic", 0.0), -1e3, 1e3))
    c = float(np.clip(coef.get("cubic", 0.0), -1e3, 1e3))
    d = float(np.clip(coef.get("quartic", 0.0), -1e3, 1e3))
    return [("after", PolynomialGainElement(quadratic_per_v=q, cubic_per_v2=c, quartic_per_v3=d))]


def _thermal_columns(sig, variant, param):
    temp = sig.temp - sig.temp_ref
    if variant == "lag":  # the lag starts settled at the first temperature, as ThermalLagElement
        temp = exp_convolve(sig.t, sig.temp, [1.0 / param], y0=[sig.temp[0] * param])[:, 0] / param - sig.temp_ref
    return [("thermal", temp, -np.inf, np.inf, "additive", None)]


def _span_thermal_columns(sig, variant, param):
    # the core output scaled by the temperature's departure: x (1 + c dT) - x = c x dT
    return [("span_thermal", sig.x_ref * (sig.temp - sig.temp_ref), -np.inf, np.inf, "sensor", None)]


def _span_thermal_elements(coef, variant, param, sig):
    c = float(np.clip(coef.get("span_thermal", 0.0), -0.05, 0.05))
    return [("after", ThermalSensitivityElement(span_coefficient_per_c=c,
                                                reference_c=float(np.clip(sig.temp_ref, -100.0, 300.0))))]


def _thermal_elements(coef, variant, param, sig):
    c = float(np.clip(coef.get("thermal", 0.0), -10.0, 10.0))
    ref = float(np.clip(sig.temp_ref, -100.0, 300.0))
    if variant == "lag":
        return [("late", ThermalLagElement(coefficient_v_per_c=c, reference_c=ref, tau_s=float(param)))]
    return [("late", ThermalDriftElement(coefficient_v_per_c=c, reference_c=ref))]


#: Knot intervals over the record of the spline variants of offset_drift (a wandering drift). 12 and 16 follow drift
#: events of 3-15 % of the record (with 8 at most, such an event leaves a ringing that a lagged thermal drift or a
#: slow delayed elasticity would take); the cross-validation keeps the finer ones from fitting what the coarse ones
#: need not.
SPLINE_INTERVALS = (4, 6, 8, 12, 16)


def variant_group(variant: str) -> str:
    """The group of variants that differ only in their number of columns (``spline12`` -> ``spline``)."""
    return variant.rstrip("0123456789") if variant.startswith("spline") else variant


def _spline_knots_s(duration_s, intervals):
    """Knot times (s after the first sample) of a spline drift of ``intervals`` equal intervals over the record."""
    return np.linspace(0.0, duration_s, intervals + 1)[1:]


def _drift_columns(sig, variant, param):
    s = (sig.t - sig.t0) / sig.duration_s
    if variant.startswith("spline"):  # ridge on the knot values: small where the data say little
        basis = SplineDriftElement.basis(sig.t - sig.t0, _spline_knots_s(sig.duration_s, int(variant[6:])))
        return [(f"knot{j}", basis[:, j], -np.inf, np.inf, "additive", "spline") for j in range(basis.shape[1])]
    if variant == "settling":  # a linear part and an exponential approach of time constant param (s)
        return [("drift1", s, -np.inf, np.inf, "additive", None),
                ("drift_exp", -np.expm1(-(sig.t - sig.t0) / param), -np.inf, np.inf, "additive", None)]
    return [(f"drift{p}", s ** p, -np.inf, np.inf, "additive", None) for p in (1, 2, 3)]


def _drift_elements(coef, variant, param, sig):
    d = sig.duration_s
    if variant.startswith("spline"):
        m = int(variant[6:])
        values = [float(np.clip(coef.get(f"knot{j}", 0.0), -1e3, 1e3)) for j in range(m)]
        return [("late", SplineDriftElement(knots_s=list(_spline_knots_s(d, m)), values_v=values))]
    c = [float(np.clip(coef.get(f"drift{p}", 0.0) / d ** p, -1e3, 1e3)) for p in (1, 2, 3)]
    out = [("late", PolynomialDriftElement(rate_v_per_s=c[0], curvature_v_per_s2=c[1], cubic_v_per_s3=c[2]))]
    if variant == "settling":
        out.append(("late", ExponentialDriftElement(amplitude_v=float(np.clip(coef.get("drift_exp", 0.0), -1e3, 1e3)),
                                                    tau_s=float(param))))
    return out


def lag_stages(variant, tau_s):
    """Time constants (s) of the first-order stages of a sensor lag of total delay ``tau_s`` (none for a pure delay)."""
    if variant == "delay":
        return []
    return [tau_s / 2.0, tau_s / 2.0] if variant == "pole_pair" else [tau_s]


def _lag_elements(coef, variant, param, sig):
    if variant == "delay":
        return [("lag", TransportDelayElement(delay_s=float(param)))]
    return [("lag", SensorLagElement(tau_s=float(tau))) for tau in lag_stages(variant, param)]


def _lag_grid(variant, sig):
    """Delays (s) searched: a transport delay of DAQ buffering (2-100 ms), or the total delay of one pole or two
    equal poles, from electronics (3 ms) to mechanical and signal-conditioning filters (0.8 s)."""
    return _log_grid(0.002, 0.1, 10) if variant == "delay" else _log_grid(0.003, 0.8, 12)


_FAM = Family
EFFECTS = {
    "viscous_flow": Effect(
        "viscous_flow", "creep during holds that never settles (viscous_flow)", ("hold_under_load", "late_in_record"),
        ("load_history",), ("maxwell", "burgers", "burgers2"),
        {"eta_two_decades": _FAM(_viscous)},
        core_change={"elastic": "maxwell", "zener": "burgers", "zener2": "burgers2"}, needs_base=("elastic", "zener")),
    "delayed_elasticity": Effect(
        "delayed_elasticity", "creep and recovery that settle (delayed_elasticity)", ("hold_under_load", "rest_after_unloading"),
        ("load_history",), ("zener", "burgers", "zener2", "burgers2"),
        {"tau_two_decades": _FAM(_delayed)},
        # starting retardation times up to a quarter of the record; the polish may take one up to the record's
        # length (engine._polish), beyond which it is flow within the record
        grid=lambda variant, sig: _log_grid(0.3, max(min(300.0, sig.duration_s / 4.0), 1.0), 12),
        core_change={"elastic": "zener", "maxwell": "burgers", "zener": "zener2", "burgers": "burgers2"},
        needs_base=("elastic", "maxwell", "zener", "burgers")),
    "hysteresis": Effect(
        "hysteresis", "path dependence at load reversals (hysteresis)", ("load_reversal",), ("load_direction",),
        ("play_hysteresis",),
        {"preisach_force": _FAM(_hyst_preisach), "play_voltage": _FAM(_pi_family(_random_play, "voltage", 6)),
         "stop_force": _FAM(_pi_family(_random_stop, "force", 5)),
         "stop_voltage": _FAM(_pi_family(_random_stop, "voltage", 5)),
         "play_force": _FAM(_pi_family(_random_play, "force", 6), held_out=True),
         "bouc_wen_voltage": _FAM(_hyst_bouc_wen, held_out=True)},
        variants=("force", "voltage", "force_descending", "voltage_descending",
                  "force_stop", "voltage_stop", "force_stop_descending", "voltage_stop_descending"),
        grid=lambda variant, sig: [None],
        columns=_hyst_columns, to_elements=_hyst_elements),
    "sensor_lag": Effect(
        "sensor_lag", "dynamics faster than the model (sensor_lag)", ("fast_transient",), ("force_rate",), ("sensor_lag",),
        {"first_order": _FAM(_lag_first), "two_stage": _FAM(_lag_two_stage), "transport_delay": _FAM(_lag_delay),
         "pole_pair": _FAM(_lag_second, held_out=True)},
        # one pole, two equal poles (a critically damped pair) of the same total delay param, or a pure delay
        variants=("", "pole_pair", "delay"), grid=_lag_grid, columns=_lag_apply,
        to_elements=_lag_elements),
    "nonlinear_gain": Effect(
        "nonlinear_gain", "gain changing with load (nonlinear_gain)", ("high_load",), ("force_squared",), ("polynomial_gain",),
        {"polynomial": _FAM(_gain_poly), "exp_approach": _FAM(_gain_exp), "tanh": _FAM(_gain_tanh, held_out=True)},
        grid=lambda variant, sig: [None], columns=_gain_columns, to_elements=_gain_elements),
    "thermal_drift": Effect(
        "thermal_drift", "output following temperature (thermal_drift)", ("temperature_change",), ("temperature",),
        ("thermal_drift", "thermal_lag"),
        {"linear": _FAM(_thermal_linear), "thermal_lag": _FAM(_thermal_lag, held_out=True)},
        variants=("direct", "lag"), grid=lambda variant, sig: [None] if variant == "direct" else _log_grid(3.0, 120.0, 6),
        columns=_thermal_columns, to_elements=_thermal_elements, needs_temperature=True),
    "thermal_sensitivity": Effect(
        "thermal_sensitivity", "a span that follows temperature (thermal_sensitivity)", ("temperature_change", "high_load"),
        ("temperature",), ("thermal_sensitivity",),
        {"linear_span": _FAM(_span_thermal)},
        grid=lambda variant, sig: [None], columns=_span_thermal_columns, to_elements=_span_thermal_elements,
        needs_temperature=True),
    "offset_drift": Effect(
        "offset_drift", "a slow drift over time (offset_drift)", ("late_in_record",), ("time",),
        ("polynomial_drift", "exponential_drift", "spline_drift"),
        {"linear": _FAM(_drift_linear), "exp_approach": _FAM(_drift_exp), "events": _FAM(_drift_events),
         "power_law": _FAM(_drift_power, held_out=True), "random_walk": _FAM(_drift_walk, held_out=True)},
        variants=("polynomial", "settling", *(f"spline{m}" for m in SPLINE_INTERVALS)),
        grid=lambda variant, sig: ([sig.duration_s * f for f in (0.05, 0.1, 0.2, 0.35, 0.6, 1.0)] if variant == "settling"
                                   else [None]),
        columns=_drift_columns, to_elements=_drift_elements),
}

#: The catalogue's names, in a fixed order (CLI choices, report tables, the matrix).
NAMES = tuple(EFFECTS)

#: First seed of the split the engine was tuned on, and of the held-out split (never used while tuning). The
#: matrix gives its i-th case the seed ``first + 97 i`` (+1 for a second seed): tune seeds are 0 or 1 modulo 97,
#: held-out seeds 53 or 54, so the two splits never share a record (their ranges overlap beyond 5000).
SPLITS = {"tune": 0, "held_out": 5000}


def families(effect, split):
    """Family names of ``effect`` usable in ``split`` ("tune": those not held out; "held_out": all)."""
    fams = EFFECTS[effect].families
    return [n for n, f in fams.items() if split == "held_out" or not f.held_out]


def hints():
    """Localisation hints: segment kind / signal -> the effects whose residual shows there."""
    out = {}
    for e in EFFECTS.values():
        for key in e.segments + e.signals:
            out.setdefault(key, []).append(e.name)
    return out
