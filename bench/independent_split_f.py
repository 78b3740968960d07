"""Independent split F for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Splits A to E were each run once and are spent. Split F is the untouched held-out set for the next engine: written
before it, run once at its end, never used to choose anything. Every name of the catalogue is hidden in two shapes
that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A to E use:

* a dashpot that flows only above a yield force (Bingham), or one that hardens as it flows;
* creep logarithmic in time (ten Kelvin units, equal weight per decade, 0.2-500 s), or a fast Kelvin unit
  (0.05-0.3 s) beside the core's own;
* a Dahl loop on the voltage path, or a play on the force whose width follows each press's peak (loops that
  scale with their amplitude);
* a zero-order hold (an ADC updating at 15-60 Hz behind the bridge), or a second-order Chebyshev filter (1 dB
  ripple: an underdamped step);
* a soft dead zone (small forces lost), or an asymmetric quadratic gain;
* a thermal zero exponential in the temperature's departure, or one driven by the temperature's rate (a
  thermo-electric transient through a 20-60 s lag);
* a span quadratic in the temperature's departure, or following the square root of it;
* a slow sine of the offset (period 150-400 s), or a logarithmic warm-up;
* a very light mode (damping ratio 0.005-0.015), or a moderately damped high mode (45-80 Hz, 0.08-0.15);
* Coulomb friction that breaks away above its sliding band (Stribeck), or a band that wears to half over the
  record;
* a shift factor that is a sigmoid in temperature (a transition), or quadratic in log.

It also holds six pairs, two effects outside the catalogue (spikes of interference, a pickup of the force's rate
rectified through a 0.5-2 s high-pass) and four clean records. Profiles: sinusoidal dwells around a mean, random
holds reached by fast ramps, and the measured Okamura insertion (``../shared/data``; a train of synthetic punctures
when it is absent) at 0.7-1.3x speed with a partial retraction. Rates 200, 550, 800 and 1000 Hz (a mode at 1000 Hz
with knocks that excite it), 1.5-3 mV noise, stamp jitter, gaps, a temperature that swings slowly over a ramp.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_f.py [--json out.json] [--workers 2] [--stride 1] [--check]
"""
from __future__ import annotations

import numpy as np
from scipy import integrate, signal

from polyforce_ros.physics.viscoelastic import Zener, simulate_deformation
from polyforce_ros.sim.truths import StaticMap
from split_kit import (LinearFilter, Parts, ShapeSplit, ShiftedBurgers, SimOnly, band_play, core_output, dahl, kelvin,
                       ramp_and_hold, repeated_insertions)

SEED0 = 400_000  # never a seed of the registry's splits nor of splits A (90000..) to E (330000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 420.0


# ----------------------------------------------------------------------------- profiles and temperature

def sine_dwells(duration_s, rate_hz, rng):
    """Sines of 0.1-1.5 Hz and 0.5-2.5 N around a mean of 2.5-6 N for 10-40 s (reached and left in 1 s), with
    5-20 s of rest between them."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    now = rng.uniform(3.0, 8.0)
    while now < duration_s:
        length, mean = rng.uniform(10.0, 40.0), rng.uniform(2.5, 6.0)
        amp, freq = min(rng.uniform(0.5, 2.5), mean - 0.3), rng.uniform(0.1, 1.5)
        inside = (t >= now) & (t < now + length)
        s = t[inside] - now
        envelope = np.clip(np.minimum(s, length - s), 0.0, 1.0)
        f[inside] = envelope * (mean + amp * np.sin(2 * np.pi * freq * s))
        now += length + rng.uniform(5.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def random_holds(duration_s, rate_hz, rng):
    """Random levels (a third of them rest) held 2-60 s, reached by ramps of 0.05-0.3 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    knots_t, knots_f, now = [0.0], [0.0], rng.uniform(2.0, 6.0)
    knots_t.append(now)
    knots_f.append(0.0)
    while now < duration_s:
        level = 0.0 if rng.random() < 1 / 3 else rng.uniform(0.5, FORCE_MAX_N)
        now = ramp_and_hold(knots_t, knots_f, now, level, rng.uniform(0.05, 0.3), rng.uniform(2.0, 60.0))
    return t, np.interp(t, knots_t, knots_f)


def okamura_retraction(duration_s, rate_hz, rng):
    """The measured insertion at 0.7-1.3x speed, with the force dropped to 20-50 % for 1-4 s at 40-80 % of it
    (a partial retraction), then restored; repeated with 5-25 s of rest."""
    def retracted(tp, fp, rng):
        speed = rng.uniform(0.7, 1.3)
        s = np.arange(0.0, (tp[-1] - tp[0]) / speed, 1.0 / rate_hz)
        one = np.interp(s * speed, tp - tp[0], fp)
        at, hold = rng.uniform(0.4, 0.8) * s[-1], rng.uniform(1.0, 4.0)
        shape = 1.0 - (1.0 - rng.uniform(0.2, 0.5)) * np.clip(np.minimum(s - at, at + hold - s) / 0.3, 0.0, 1.0)
        return one * shape
    return repeated_insertions(duration_s, rate_hz, rng, retracted, FORCE_MAX_N)


PROFILES = (sine_dwells, random_holds, okamura_retraction)


def temperature(t, rng):
    """A ramp of 1-3 degC over the record, either sign, under a slow swing of 0.5-2 degC (period 150-400 s)."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    ramp = rng.choice([-1, 1]) * rng.uniform(1.0, 3.0) * s / d
    swing = rng.uniform(0.5, 2.0) * np.sin(2 * np.pi * s / rng.uniform(150.0, 400.0) + rng.uniform(0, 2 * np.pi))
    return T_REF_C + rng.uniform(-1, 1) + ramp + swing


# ----------------------------------------------------------------------------- simulate-only truth elements

class YieldFlowZener(SimOnly):
    """A Zener core plus a dashpot that flows only above a yield force: rate phi (F - F_y) where F > F_y."""

    def __init__(self, zener, phi_v_per_n_s, yield_n):
        self.zener, self.phi, self.yield_n = zener, phi_v_per_n_s, yield_n

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        flow = integrate.cumulative_trapezoid(self.phi * np.maximum(f - self.yield_n, 0.0), t, initial=0.0)
        return simulate_deformation(self.zener, t, f) + flow


class HardeningFlowZener(SimOnly):
    """A Zener core plus a dashpot that hardens as it flows: rate phi F / (1 + u / u0), u the flow so far."""

    def __init__(self, zener, phi_v_per_n_s, u0_v):
        self.zener, self.phi, self.u0 = zener, phi_v_per_n_s, u0_v

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        # du/dt = phi F / (1 + u/u0)  =>  u + u^2 / (2 u0) = phi * integral of F: solved for u >= 0
        w = integrate.cumulative_trapezoid(self.phi * f, t, initial=0.0)
        flow = self.u0 * (np.sqrt(1.0 + 2.0 * np.maximum(w, 0.0) / self.u0) - 1.0)
        return simulate_deformation(self.zener, t, f) + flow


class Dahl(SimOnly):
    """A Dahl loop added to the input: dy/dx = sigma (1 - y / y_max sign(dx)), y from zero."""

    def __init__(self, y_max, sigma):
        self.y_max, self.sigma = y_max, sigma

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        return x + dahl(x, self.y_max, self.sigma)


def amplitude_play(f, share, rest_n=0.2):
    """A play whose half-width is ``share`` of the peak force since the force last rested below ``rest_n``: loops
    that scale with the amplitude of each press."""
    f = np.asarray(f, dtype=float)
    out, p, peak = np.empty_like(f), f[0], 0.0
    for i, fi in enumerate(f.tolist()):
        peak = 0.0 if fi < rest_n else max(peak, fi)
        r = share * peak
        p = max(fi - r, min(fi + r, p))
        out[i] = p
    return out


class ZeroOrderHold(SimOnly):
    """The input held between updates at ``rate_hz`` (an ADC decimating behind the bridge)."""

    def __init__(self, rate_hz):
        self.period = 1.0 / rate_hz

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        held_t = np.floor((t - t[0]) / self.period) * self.period + t[0]
        return np.interp(held_t, t, x)


class StribeckFriction(SimOnly):
    """Friction that sticks until the force moves ``static_n`` from where it stuck, then slides with ``kinetic_n`` <
    ``static_n`` behind the force until the force turns or stops, and sticks again."""

    def __init__(self, static_n, kinetic_n):
        self.static, self.kinetic = static_n, kinetic_n

    def forward(self, t_s, x, aux=None, state=None):
        f = np.asarray(x, dtype=float)
        out, p, sliding = np.empty_like(f), f[0], False
        for i, fi in enumerate(f.tolist()):
            if not sliding and abs(fi - p) > self.static:
                sliding = True  # breaks away, and the band drops to the sliding one at once
            if sliding:
                new = max(fi - self.kinetic, min(fi + self.kinetic, p))
                sliding = new != p
                p = new
            out[i] = p
        return out


class WearingFriction(SimOnly):
    """Coulomb friction whose band wears linearly from ``r0_n`` to half of it over the record."""

    def __init__(self, r0_n):
        self.r0 = r0_n

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        frac = (t - t[0]) / max(t[-1] - t[0], 1e-9)
        r = self.r0 * (1.0 - 0.5 * frac)
        return band_play(f, r, r)


def _rate_of_temperature(t, temp, tau_s):
    """The temperature's rate (degC/s), through a first-order lag of ``tau_s`` from rest."""
    h = float(np.median(np.diff(t)))
    rate = np.gradient(np.asarray(temp, dtype=float), t)
    b, a = signal.bilinear([1.0], [tau_s, 1.0], fs=1.0 / h)
    return signal.lfilter(b, a, rate)


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    span = FORCE_MAX_N / c.relaxation().g0_n_per_v * 2.0  # ~ the core's output over the force range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([8e4, 4e3]))))
        zener = Zener(c.k1_n_per_v, c.k2_n_per_v, c.eta2_n_s_per_v)
        if shape == "yield_flow":
            return Parts("zener", YieldFlowZener(zener, phi * 2.0, rng.uniform(1.0, 3.0)), core_changed=True)
        u0 = rng.uniform(0.2, 0.6) * phi * FORCE_MAX_N * DURATION_S / 4  # hardens to a half-rate within the record
        return Parts("zener", HardeningFlowZener(zener, phi * 1.5, u0), core_changed=True)
    if effect == "delayed_elasticity":
        total = float(np.interp(m, [0, 1], [1 / 60.0, 1 / 6.0]))  # added compliance, V/N
        if shape == "logarithmic_creep":
            taus = np.geomspace(0.2, 500.0, 10)
            p.extra.append(lambda t, f, T, taus=taus, w=total / taus.size: sum(kelvin(t, f, w, ti) for ti in taus))
            return p
        tau = rng.uniform(0.05, 0.3)
        p.extra.append(lambda t, f, T, k=total, tau=tau: kelvin(t, f, k, tau))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.02, 0.07]))
        if shape == "dahl_voltage":
            y_max = frac * span / 2
            p.after.append(Dahl(y_max, rng.uniform(0.5, 2.0)))
            return p
        share = frac * rng.uniform(0.8, 1.2)
        out = core_output(c)
        p.extra.append(lambda t, f, T, s=share, out=out: out(t, amplitude_play(f, s)) - out(t, f))
        return p
    if effect == "sensor_lag":
        if shape == "zero_order_hold":
            p.after.append(ZeroOrderHold(float(np.exp(np.interp(m, [0, 1], np.log([60.0, 15.0]))))))
            return p
        fc = float(np.exp(np.interp(m, [0, 1], np.log([25.0, 2.5]))))
        num, den = signal.cheby1(2, 1.0, 2 * np.pi * fc, analog=True)
        p.after.append(LinearFilter(num, den))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.02, 0.08]))
        if shape == "soft_dead_zone":
            d = rel * span / 2
            p.after.append(StaticMap(lambda x, d=d: x - d * np.tanh(x / d)))
            return p
        sign = rng.choice([-1, 1])
        p.after.append(StaticMap(lambda x, s=span / 2, a=sign * rel: x + a * x * np.abs(x) / s))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.02]) * rng.choice([-1, 1]))
        if shape == "exponential_in_temperature":
            b = rng.uniform(0.15, 0.4) * rng.choice([-1, 1])
            p.extra.append(lambda t, f, T, k=k, b=b: k / b * np.expm1(b * (T - T_REF_C)))
            return p
        tau = rng.uniform(20.0, 60.0)
        p.extra.append(lambda t, f, T, k=k, tau=tau: k * 100.0 * _rate_of_temperature(t, T, tau))
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.002, 0.01]) * rng.choice([-1, 1]))
        out = core_output(c)
        if shape == "span_quadratic":
            p.extra.append(lambda t, f, T, a=a, out=out: 1.5 * a * (T - T_REF_C) ** 2 * out(t, f))
            return p
        p.extra.append(lambda t, f, T, a=a, out=out: 2 * a * np.sign(T - T_REF_C) * np.sqrt(np.abs(T - T_REF_C))
                       * out(t, f))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.08]))
        if shape == "slow_sine":
            period, phase = rng.uniform(150.0, 400.0), rng.uniform(0, 2 * np.pi)
            p.extra.append(lambda t, f, T, s=size, P=period, ph=phase: s / 2 * (
                np.sin(2 * np.pi * (t - t[0]) / P + ph) - np.sin(ph)))
            return p
        tau, sign = rng.uniform(5.0, 60.0), rng.choice([-1, 1])
        p.extra.append(lambda t, f, T, s=size * sign, tau=tau: s * np.log1p((t - t[0]) / tau) / np.log1p(
            DURATION_S / tau))
        return p
    if effect == "resonance":
        if shape == "very_light":
            f0, zeta = rng.uniform(15.0, 40.0), rng.uniform(0.005, 0.015)
        else:
            f0, zeta = rng.uniform(45.0, 80.0), rng.uniform(0.08, 0.15)
        w0 = 2 * np.pi * f0
        p.after.append(LinearFilter([w0 ** 2], [1.0, 2 * zeta * w0, w0 ** 2]))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "stribeck":
            p.before.append(StribeckFriction(r * rng.uniform(1.5, 2.5), r))
            return p
        p.before.append(WearingFriction(r * 1.3))
        return p
    if effect == "thermo_rheological":
        if shape == "sigmoid_shift":
            b, at = float(np.interp(m, [0, 1], [0.6, 1.6])), T_REF_C + rng.uniform(-0.5, 0.5)
            width = rng.uniform(0.5, 1.5)
            return Parts("burgers", ShiftedBurgers(c, lambda T, b=b, at=at, w=width: np.exp(
                b * (np.tanh((T - at) / w) - np.tanh((T_REF_C - at) / w))), flow_only=False), core_changed=True)
        b = float(np.interp(m, [0, 1], [0.08, 0.25]))
        q = rng.uniform(0.02, 0.06) * rng.choice([-1, 1])
        return Parts("burgers", ShiftedBurgers(c, lambda T, b=b, q=q: np.exp(b * (T - T_REF_C) + q * (T - T_REF_C) ** 2),
                                              flow_only=False), core_changed=True)
    if effect == "interference_spikes":
        size = float(np.interp(m, [0, 1], [0.02, 0.06]))
        seed = int(rng.integers(2**31))

        def spikes(t, f, T, size=size, seed=seed):
            g = np.random.default_rng(seed)
            out = np.zeros_like(t)
            at = g.integers(0, t.size, int(g.integers(100, 300)))
            out[at] = size * g.choice([-1, 1], at.size) * g.uniform(0.5, 1.0, at.size)
            return out
        p.extra.append(spikes)
        return p
    if effect == "rectified_rate_pickup":
        g, tau = float(np.interp(m, [0, 1], [0.002, 0.008])), rng.uniform(0.5, 2.0)

        def pickup(t, f, T, g=g, tau=tau):
            h = float(np.median(np.diff(t)))
            rate = np.abs(np.gradient(f, t))
            b, a = signal.bilinear([tau, 0.0], [tau, 1.0], fs=1.0 / h)  # a high-pass of the rectified rate
            return g * signal.lfilter(b, a, rate)
        p.extra.append(pickup)
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["yield_flow", "hardening_flow"],
    "delayed_elasticity": ["logarithmic_creep", "fast_kelvin"],
    "hysteresis": ["dahl_voltage", "amplitude_play"], "sensor_lag": ["zero_order_hold", "chebyshev2"],
    "nonlinear_gain": ["soft_dead_zone", "asymmetric_quadratic"],
    "thermal_drift": ["exponential_in_temperature", "temperature_rate"],
    "thermal_sensitivity": ["span_quadratic", "span_square_root"],
    "offset_drift": ["slow_sine", "logarithmic_warm_up"],
    "resonance": ["very_light", "damped_high_mode"], "friction": ["stribeck", "wearing_band"],
    "thermo_rheological": ["sigmoid_shift", "quadratic_log_shift"],
}
PAIRS = (("viscous_flow", "thermal_drift"), ("delayed_elasticity", "sensor_lag"),
         ("hysteresis", "thermal_sensitivity"), ("nonlinear_gain", "offset_drift"), ("resonance", "friction"),
         ("thermo_rheological", "nonlinear_gain"))
OUTSIDE = ("interference_spikes", "rectified_rate_pickup")
RATES = (200.0, 550.0, 800.0, 1000.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split F", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.35, 0.75),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.5e-3, 3.0e-3), jitter=0.4,
                   gap_s=(0.1, 2.0))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
