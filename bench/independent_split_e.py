"""Independent split E for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Splits A, B, C and D were each run once and are spent. Split E is the untouched held-out set for the next engine:
written before it, run once at its end, never used to choose anything. Every name of the catalogue is hidden in two
shapes that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A to D use:

* a Kelvin unit far slower than the record (flow within it), or a power-law (Norton) dashpot; creep spread over a
  stretched-exponential spectrum of six Kelvin units, or a second Kelvin unit close to the base's own;
* Preisach relays on the core's output, or relays on the applied force added at the bridge;
* a moving-average (boxcar) filter, or a second-order Butterworth filter;
* a logarithmic (compressive) gain, or a periodic ripple of the gain along the range (an ADC's non-linearity);
* a thermal zero whose slope changes at a temperature (a hinge in T), or one that follows the square root of
  the temperature's departure;
* a span whose temperature coefficient changes at a temperature, or a span exponential in temperature;
* an offset that creeps and is reset every 60-150 s (an auto-zero), or an offset that overshoots (two
  exponentials of opposite sign);
* a mode driven by the force's rate and added at the bridge (an inertial pickup), or a well damped mode
  (damping ratio 0.25-0.4);
* Coulomb friction whose band is not symmetric (it sticks more going up than coming down), or a band that
  follows temperature;
* a time-temperature shift on the flow alone, or a shift linear in temperature.

It also holds six pairs, two effects outside the catalogue (an offset step at each overload above 7 N, a pickup
of an off-axis load at 0.5-3 Hz) and four clean records. Profiles: palpation taps with occasional long presses,
ascending and descending calibration ladders (as ISO 376 loads a force transducer), and the measured Okamura
insertion made 1.5-3x slower (``../shared/data``; a train of synthetic punctures when it is absent). Rates 350,
450, 700 and 900 Hz (a mode at 1000 Hz with knocks that excite it), 1.8-2.8 mV noise, stamp jitter, gaps, a
temperature that warms in two steps.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_e.py [--json out.json] [--workers 2] [--stride 1] [--check]
"""
from __future__ import annotations

import numpy as np
from scipy import integrate, signal

from polyforce_ros.physics.viscoelastic import Zener, Zener2, simulate_deformation
from polyforce_ros.sim.truths import StaticMap
from split_kit import (LinearFilter, Parts, ShapeSplit, ShiftedBurgers, SimOnly, band_play, core_output, kelvin, ramp_and_hold,
                       repeated_insertions, uniform_grid)

SEED0 = 330_000  # never a seed of the registry's splits nor of splits A (90000..), B, C (210000..), D (260000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 480.0


# ----------------------------------------------------------------------------- profiles and temperature

def palpation(duration_s, rate_hz, rng):
    """Taps of 0.3-1 s to 1-8 N every 1-5 s, and now and then (one in six) a press held 10-30 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    knots_t, knots_f, now = [0.0], [0.0], rng.uniform(2.0, 6.0)
    while now < duration_s:
        level, rise = rng.uniform(1.0, 8.0), rng.uniform(0.1, 0.3)
        hold = rng.uniform(10.0, 30.0) if rng.random() < 1 / 6 else rng.uniform(0.1, 0.4)
        knots_t += [now, now + rise, now + rise + hold, now + 2 * rise + hold]
        knots_f += [0.0, level, level, 0.0]
        now += 2 * rise + hold + rng.uniform(1.0, 5.0)
    return t, np.interp(t, knots_t, knots_f)


def calibration_ladders(duration_s, rate_hz, rng):
    """Ascending then descending ladders of 3-6 equal steps to 4-9 N, each step held 4-15 s, reached in 0.5-2 s,
    with 10-40 s of rest between ladders."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    knots_t, knots_f = [0.0, rng.uniform(3.0, 8.0)], [0.0, 0.0]
    now = knots_t[-1]
    while now < duration_s:
        n, top = int(rng.integers(3, 7)), rng.uniform(4.0, FORCE_MAX_N)
        levels = np.concatenate([np.arange(1, n + 1), np.arange(n - 1, -1, -1)]) * top / n
        for level in levels:
            now = ramp_and_hold(knots_t, knots_f, now, level, rng.uniform(0.5, 2.0), rng.uniform(4.0, 15.0))
        now += rng.uniform(10.0, 40.0)
    return t, np.interp(t, knots_t, knots_f)


def slow_okamura(duration_s, rate_hz, rng):
    """The measured insertion scaled to 2-9 N and made 1.5-3x slower, repeated with 5-30 s of rest."""
    def slowed(tp, fp, rng):
        slow = rng.uniform(1.5, 3.0)
        return np.interp(np.arange(0.0, tp[-1] * slow, 1.0 / rate_hz) / slow, tp - tp[0], fp)
    return repeated_insertions(duration_s, rate_hz, rng, slowed, FORCE_MAX_N)


PROFILES = (palpation, calibration_ladders, slow_okamura)


def temperature(t, rng):
    """Two warmings of 1.5-4 degC each (at 15-35 % and 55-80 % of the record, approached over 10-40 s), either sign."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    out = T_REF_C + rng.uniform(-1, 1) + np.zeros_like(s)
    sign = rng.choice([-1, 1])
    for lo, hi in ((0.15, 0.35), (0.55, 0.8)):
        at, tau = rng.uniform(lo, hi) * d, rng.uniform(10.0, 40.0)
        out += sign * rng.uniform(1.5, 4.0) * -np.expm1(-np.maximum(s - at, 0.0) / tau)
    return out


def _hinge(x, at, below, above):
    """A slope ``below`` up to ``at`` and ``above`` beyond it (continuous)."""
    return np.where(x < at, below * (x - at), above * (x - at)) + below * at


# ----------------------------------------------------------------------------- simulate-only truth elements

class NortonFlowZener(SimOnly):
    """A Zener core plus a power-law (Norton) dashpot in series: the flow's rate is phi F (F / F_max)^(n - 1)."""

    def __init__(self, zener, phi_v_per_n_s, n):
        self.zener, self.phi, self.n = zener, phi_v_per_n_s, n

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        rate = self.phi * f * (np.abs(f) / FORCE_MAX_N) ** (self.n - 1.0)
        flow = integrate.cumulative_trapezoid(rate, t, initial=0.0)
        return simulate_deformation(self.zener, t, f) + flow


class Relays(SimOnly):
    """Preisach relays (hysterons) on the input: each switches up at alpha and down at beta < alpha, adding w when up;
    ``add`` the input itself (on the voltage path) or not (at the bridge, beside the core)."""

    def __init__(self, alphas, betas, weights, add=True):
        self.a, self.b, self.w, self.add = np.asarray(alphas), np.asarray(betas), np.asarray(weights), add

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        up = np.zeros(self.a.size, dtype=bool)
        out = np.empty_like(x)
        for i, xi in enumerate(x):
            up = (up | (xi >= self.a)) & ~(xi <= self.b)
            out[i] = float(self.w @ up)
        return x + out if self.add else out


class Boxcar(SimOnly):
    """A moving average over ``width_s`` (an FIR anti-alias filter), from rest."""

    def __init__(self, width_s):
        self.width = width_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        n = max(1, int(round(self.width / h)))
        y = signal.lfilter(np.ones(n) / n, [1.0], xu - x[0]) + x[0]
        return np.interp(t, tu, y)


class AsymmetricFriction(SimOnly):
    """Coulomb friction that sticks by ``up_n`` while the force rises and by ``down_n`` while it falls."""

    def __init__(self, up_n, down_n):
        self.up, self.down = up_n, down_n

    def forward(self, t_s, x, aux=None, state=None):
        return band_play(x, self.up, self.down)


class ThermalBandFriction(SimOnly):
    """Coulomb friction whose band follows temperature, r = r0 (1 + 0.1 (T - T_ref)), never below r0 / 4."""

    def __init__(self, r0_n):
        self.r0 = r0_n

    def forward(self, t_s, x, aux=None, state=None):
        f = np.asarray(x, dtype=float)
        temp = np.broadcast_to(aux["temperature_c"], f.shape)
        r = np.maximum(self.r0 * (1 + 0.1 * (temp - T_REF_C)), self.r0 / 4)
        return band_play(f, r, r)


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    span = FORCE_MAX_N / c.relaxation().g0_n_per_v * 2.0  # ~ the core's output over the force range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        if shape == "kelvin_beyond_record":  # within the record a Kelvin unit of tau >> record is a flow
            tau = rng.uniform(5.0, 20.0) * DURATION_S
            eta_equiv = float(np.exp(np.interp(m, [0, 1], np.log([1e5, 4e3]))))
            k3 = eta_equiv / tau
            return Parts("zener", Zener2(c.k1_n_per_v, c.k2_n_per_v, c.eta2_n_s_per_v, k3, k3 * tau), core_changed=True)
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([1e5, 4e3]))))
        zener = Zener(c.k1_n_per_v, c.k2_n_per_v, c.eta2_n_s_per_v)
        return Parts("zener", NortonFlowZener(zener, phi, rng.uniform(1.3, 2.0)), core_changed=True)
    if effect == "delayed_elasticity":
        total = float(np.interp(m, [0, 1], [1 / 60.0, 1 / 6.0]))  # added compliance, V/N
        if shape == "stretched_spectrum":
            taus = np.geomspace(1.0, 100.0, 6)
            weights = (taus / taus.mean()) ** rng.uniform(-0.5, 0.5)
            weights *= total / weights.sum()
            p.extra.append(lambda t, f, T, taus=taus, w=weights: sum(kelvin(t, f, wi, ti) for wi, ti in zip(w, taus)))
            return p
        tau2 = c.eta2_n_s_per_v / c.k2_n_per_v
        tau3 = tau2 * rng.choice([1 / 3, 3.0]) * rng.uniform(0.8, 1.2)
        p.extra.append(lambda t, f, T, k=total, tau=tau3: kelvin(t, f, k, tau))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.02, 0.07]))
        n = int(rng.integers(4, 9))
        if shape == "relays_voltage":
            alphas = rng.uniform(0.1, 0.9, n) * span / 2
            betas = alphas - rng.uniform(0.05, 0.4, n) * span / 2
            weights = rng.uniform(0.5, 1.0, n)
            p.after.append(Relays(alphas, betas, weights * frac * span / 2 / weights.sum()))
            return p
        alphas = rng.uniform(0.1, 0.9, n) * FORCE_MAX_N
        betas = alphas - rng.uniform(0.05, 0.4, n) * FORCE_MAX_N
        weights = rng.uniform(0.5, 1.0, n)
        relays = Relays(alphas, betas, weights * frac * span / 2 / weights.sum(), add=False)
        p.extra.append(lambda t, f, T, relays=relays: relays.forward(t, f))
        return p
    if effect == "sensor_lag":
        if shape == "boxcar":
            p.after.append(Boxcar(float(np.exp(np.interp(m, [0, 1], np.log([0.03, 0.15]))))))
            return p
        fc = float(np.exp(np.interp(m, [0, 1], np.log([30.0, 2.0]))))
        num, den = signal.butter(2, 2 * np.pi * fc, analog=True)
        p.after.append(LinearFilter(num, den))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.02, 0.08]))
        if shape == "logarithmic":
            s0 = span / (2 * rel) / 2  # x0 log(1 + x / x0) bends by ~rel over the range
            p.after.append(StaticMap(lambda x, s0=s0: np.sign(x) * s0 * np.log1p(np.abs(x) / s0)))
            return p
        cycles = rng.uniform(2.0, 5.0)
        p.after.append(StaticMap(lambda x, s=span, r=rel, k=cycles: x + r * s / 2 * np.sin(2 * np.pi * k * x / s)))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.003, 0.01]) * rng.choice([-1, 1]))
        if shape == "hinge_in_temperature":
            at, ratio = T_REF_C + rng.uniform(-0.5, 1.5), rng.uniform(0.2, 3.0) * rng.choice([-1, 1])
            p.extra.append(lambda t, f, T, k=k, at=at, ratio=ratio: _hinge(T, at, k, k * ratio) - _hinge(
                np.array([T_REF_C]), at, k, k * ratio)[0])
            return p
        p.extra.append(lambda t, f, T, k=k: 2.0 * k * np.sign(T - T_REF_C) * np.sqrt(np.abs(T - T_REF_C)))
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.002, 0.01]) * rng.choice([-1, 1]))
        out = core_output(c)
        if shape == "span_hinge":
            at, ratio = T_REF_C + rng.uniform(-0.5, 1.5), rng.uniform(0.2, 3.0) * rng.choice([-1, 1])
            p.extra.append(lambda t, f, T, a=a, at=at, ratio=ratio, out=out: (
                _hinge(T, at, a, a * ratio) - _hinge(np.array([T_REF_C]), at, a, a * ratio)[0]) * out(t, f))
            return p
        p.extra.append(lambda t, f, T, a=a, out=out: np.expm1(a * (T - T_REF_C)) * out(t, f))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.08]))
        if shape == "autozero_sawtooth":
            period = rng.uniform(60.0, 150.0)
            phase = rng.uniform(0.0, 1.0)
            p.extra.append(lambda t, f, T, s=size, P=period, ph=phase: s * (((t - t[0]) / P + ph) % 1.0))
            return p
        tau1, tau2 = rng.uniform(10.0, 40.0), rng.uniform(100.0, 300.0)
        over, sign = rng.uniform(0.4, 0.8), rng.choice([-1, 1])
        p.extra.append(lambda t, f, T, s=size * sign, a=tau1, b=tau2, o=over: s * (
            -np.expm1(-(t - t[0]) / a) * (1 + o) + np.expm1(-(t - t[0]) / b) * o))
        return p
    if effect == "resonance":
        if shape == "inertial_pickup":
            f0, zeta = rng.uniform(15.0, 45.0), rng.uniform(0.02, 0.08)
            w0 = 2 * np.pi * f0
            gain = float(np.interp(m, [0, 1], [0.015, 0.05])) * span / w0  # V per N/s at the mode
            pickup = LinearFilter([gain * w0 ** 2, 0.0], [1.0, 2 * zeta * w0, w0 ** 2])  # the rate, through the mode
            p.extra.append(lambda t, f, T, pickup=pickup: pickup.forward(t, f - f[0]))
            return p
        f0 = rng.uniform(20.0, 50.0)
        w0, zeta = 2 * np.pi * f0, rng.uniform(0.25, 0.4)
        p.after.append(LinearFilter([w0 ** 2], [1.0, 2 * zeta * w0, w0 ** 2]))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "asymmetric_band":
            share = rng.uniform(0.2, 0.45)
            p.before.append(AsymmetricFriction(2 * r * (1 - share), 2 * r * share))
            return p
        p.before.append(ThermalBandFriction(r))
        return p
    if effect == "thermo_rheological":
        if shape == "flow_only":
            b = float(np.interp(m, [0, 1], [0.15, 0.35])) * rng.uniform(0.8, 1.2)
            return Parts("burgers", ShiftedBurgers(c, lambda T, b=b: np.exp(b * (T - T_REF_C)), flow_only=True),
                         core_changed=True)
        b = float(np.interp(m, [0, 1], [0.04, 0.12]))
        return Parts("burgers", ShiftedBurgers(c, lambda T, b=b: np.maximum(1 + b * (T - T_REF_C), 0.2),
                                               flow_only=False), core_changed=True)
    if effect == "overload_set":
        k = float(np.interp(m, [0, 1], [0.01, 0.04]))  # V per overload above 7 N
        p.extra.append(lambda t, f, T, k=k: k * np.cumsum(np.diff((f > 7.0).astype(int), prepend=0) > 0))
        return p
    if effect == "off_axis_pickup":
        g = float(np.interp(m, [0, 1], [0.004, 0.012]))
        lo, hi = 0.5, rng.uniform(1.5, 3.0)
        seed = int(rng.integers(2**31))

        def pickup(t, f, T, g=g, lo=lo, hi=hi, seed=seed):
            h = float(np.median(np.diff(t)))
            sos = signal.butter(2, [lo, hi], btype="band", fs=1.0 / h, output="sos")
            x = signal.sosfilt(sos, np.random.default_rng(seed).normal(0.0, 1.0, t.size))
            return g * x / max(float(np.std(x)), 1e-12)
        p.extra.append(pickup)
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["kelvin_beyond_record", "norton_dashpot"],
    "delayed_elasticity": ["stretched_spectrum", "close_second_kelvin"],
    "hysteresis": ["relays_voltage", "relays_bridge"], "sensor_lag": ["boxcar", "butterworth2"],
    "nonlinear_gain": ["logarithmic", "ripple"], "thermal_drift": ["hinge_in_temperature", "square_root"],
    "thermal_sensitivity": ["span_hinge", "span_exponential"],
    "offset_drift": ["autozero_sawtooth", "overshoot"],
    "resonance": ["inertial_pickup", "damped_mode"], "friction": ["asymmetric_band", "thermal_band"],
    "thermo_rheological": ["flow_only", "linear_shift"],
}
PAIRS = (("viscous_flow", "hysteresis"), ("sensor_lag", "thermal_drift"), ("friction", "offset_drift"),
         ("resonance", "thermal_sensitivity"), ("delayed_elasticity", "nonlinear_gain"), ("thermo_rheological", "friction"))
OUTSIDE = ("overload_set", "off_axis_pickup")
RATES = (350.0, 700.0, 900.0, 450.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split E", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.4, 0.8), pair_shapes=(0, -1),
                   rates=RATES, profiles=PROFILES, temperature=temperature, make_parts=make_parts,
                   duration_s=DURATION_S, noise_v=(1.8e-3, 2.8e-3), jitter=0.3, gap_s=(0.1, 1.5))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
