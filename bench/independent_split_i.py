"""Independent split I for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Splits A to H were each run once and are spent. Split I is the untouched held-out set for the next engine: written
before it, run once at its end, never used to choose anything. Every name of the catalogue is hidden in two shapes
that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A to H use:

* a dashpot whose rate is F^2 / (F + F0) (a smooth yield), or one with a second, steeper slope above a knee force;
* creep in a box spectrum (equal compliance per decade over 1-2.5 decades), or a Kelvin unit that creeps with one
  time constant and recovers with another;
* relays on the force before the core with random thresholds (a Preisach cloud), or a play on the force whose width
  grows with the loading rate;
* a triangular FIR window, or two equal poles behind a faster third;
* a gain that clips softly near the top of the range (softplus), or one that bends quadratically above a knee;
* a thermal zero as the tanh of a lagged temperature, or two lags of opposite sign (an overshoot that settles);
* a span as the tanh of a lagged temperature, or one that follows two lags of opposite sign;
* an offset that ramps to a plateau with a rounded corner, or the sum of two slow sines;
* a mode whose frequency rises with the load, or a mode with a pole at its own frequency;
* a friction band that varies with the force level (cogging), or a LuGre bristle model;
* a shift factor that starts above a threshold temperature, or one that is a power of (1 + b dT / p).

It also holds six pairs, two effects outside the catalogue (a coarse quantisation of the bridge, crosstalk from a
second, lateral force) and four clean records. Profiles: bursts of light taps, the measured Okamura insertion
through two layers, and ramps at random rates to random levels. Rates 180, 400, 750 and 1000 Hz (a mode at 1000 Hz
with knocks that excite it), 1-3 mV noise, stamp jitter, gaps, a temperature cycled by an air conditioner.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_i.py [--json out.json] [--workers 2] [--stride 1] [--check]
"""
from __future__ import annotations

import numpy as np
from scipy import integrate

from polyforce_ros.physics.viscoelastic import Zener, simulate_deformation
from polyforce_ros.sim.truths import StaticMap
from split_kit import (band_play, core_output, ForcePath, kelvin, lagged, LinearFilter, Parts, ramp_and_hold,
                       repeated_insertions, ShapeSplit, ShiftedBurgers, SimOnly, uniform_grid)

SEED0 = 610_000  # never a seed of the registry's splits nor of splits A (90000..) to H (540000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 450.0


# ----------------------------------------------------------------------------- profiles and temperature

def tap_bursts(duration_s, rate_hz, rng):
    """Bursts of 5-30 light taps (raised cosines of 0.5-3 N, 80-300 ms long, at 1-4 Hz) on a preload of 0-4 N,
    with 5-25 s of rest between bursts."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    now = rng.uniform(3.0, 8.0)
    while now < duration_s:
        preload, period, n = rng.uniform(0.0, 4.0), 1.0 / rng.uniform(1.0, 4.0), int(rng.integers(5, 31))
        length = n * period + 2.0
        inside = (t >= now) & (t < now + length)
        f[inside] = preload * np.clip(np.minimum(t[inside] - now, now + length - t[inside]), 0.0, 1.0)
        for k in range(n):
            width, size = rng.uniform(0.08, min(0.3, 0.9 * period)), rng.uniform(0.5, 3.0)
            tap = (t >= now + 1.0 + k * period) & (t < now + 1.0 + k * period + width)
            f[tap] += size * 0.5 * (1 - np.cos(2 * np.pi * (t[tap] - now - 1.0 - k * period) / width))
        now += length + rng.uniform(5.0, 25.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def two_layer_okamura(duration_s, rate_hz, rng):
    """The measured insertion, then after 0.5-2 s a second one 1.2-1.8 times as large (a second layer), repeated with
    5-30 s of rest."""
    def two_layers(tp, fp, rng):
        one = np.interp(np.arange(0.0, tp[-1] - tp[0], 1.0 / rate_hz), tp - tp[0], fp)
        pause = np.full(int(rng.uniform(0.5, 2.0) * rate_hz), one[-1])
        return np.concatenate([one, pause, one[-1] + rng.uniform(1.2, 1.8) * one])
    return repeated_insertions(duration_s, rate_hz, rng, two_layers, FORCE_MAX_N)


def random_ramps(duration_s, rate_hz, rng):
    """Ramps at 0.2-5 N/s to random levels of 0-9 N, each held 1-20 s; one level in five is rest."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    knots_t, knots_f, now, level = [0.0], [0.0], rng.uniform(3.0, 8.0), 0.0
    knots_t.append(now)
    knots_f.append(0.0)
    while now < duration_s:
        new = 0.0 if rng.random() < 0.2 else rng.uniform(0.5, FORCE_MAX_N)
        now = ramp_and_hold(knots_t, knots_f, now, new, max(abs(new - level), 0.05) / rng.uniform(0.2, 5.0),
                            rng.uniform(1.0, 20.0))
        level = new
    return t, np.interp(t, knots_t, knots_f)


PROFILES = (tap_bursts, two_layer_okamura, random_ramps)


def temperature(t, rng):
    """An air conditioner: a square wave of 1-2 degC with a period of 120-360 s seen through a lag of 20-60 s, on a
    drift of 1-3 degC either way."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    period, swing = rng.uniform(120.0, 360.0), rng.uniform(1.0, 2.0)
    square = swing * np.sign(np.sin(2 * np.pi * s / period + rng.uniform(0, 2 * np.pi)))
    smooth = square[0] + kelvin(t, square - square[0], 1.0, rng.uniform(20.0, 60.0))
    return T_REF_C + rng.uniform(-1, 1) + rng.choice([-1, 1]) * rng.uniform(1.0, 3.0) * s / d + smooth


# ----------------------------------------------------------------------------- simulate-only truth elements

class RateFlowZener(SimOnly):
    """A Zener core plus a dashpot whose rate is ``rate_of(F)`` (V/s)."""

    def __init__(self, zener, rate_of):
        self.zener, self.rate_of = zener, rate_of

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        return simulate_deformation(self.zener, t, f) + integrate.cumulative_trapezoid(self.rate_of(f), t, initial=0.0)


class TriangularWindow(SimOnly):
    """A causal triangular FIR window of total length ``width_s``."""

    def __init__(self, width_s):
        self.width = width_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        n = max(3, int(round(self.width / h)))
        taps = 1.0 - np.abs(np.linspace(-1.0, 1.0, n))
        taps /= taps.sum()
        y = np.convolve(np.concatenate([np.full(n - 1, xu[0]), xu]), taps, mode="valid")
        return np.interp(t, tu, y)


class LoadTunedMode(SimOnly):
    """A light mode on the core's output whose frequency rises with the deflection (f0 (1 + s |x| / x_max): a
    structure that stiffens under load), integrated per sample (semi-implicit Euler on a uniform grid at the
    median step)."""

    def __init__(self, f0_hz, zeta, stiffening, x_max_v):
        self.f0, self.zeta, self.s, self.x_max = f0_hz, zeta, stiffening, x_max_v

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        w = 2 * np.pi * self.f0 * (1.0 + self.s * np.minimum(np.abs(xu - xu[0]) / self.x_max, 1.0))
        y, v, out = xu[0], 0.0, np.empty_like(xu)
        for i, (xi, wi) in enumerate(zip(xu.tolist(), w.tolist())):
            v += h * (wi * wi * (xi - y) - 2.0 * self.zeta * wi * v)
            y += h * v
            out[i] = y
        return np.interp(t, tu, out)


def relays(f, low_n, high_n, weights_n):
    """Relays switched up at ``high_n`` and down at ``low_n`` (each < its high), weighted: a Preisach cloud, from
    all down."""
    f = np.asarray(f, dtype=float)
    up, out = np.zeros(low_n.size, dtype=bool), np.empty_like(f)
    for i, fi in enumerate(f.tolist()):
        up = (up | (fi >= high_n)) & ~(fi <= low_n)
        out[i] = float(weights_n @ up)
    return out


def rate_play(t, f, r0_n, per_n_per_s):
    """A play on the force whose half-width is ``r0_n + per_n_per_s |dF/dt|`` (smoothed over 0.1 s)."""
    rate = np.abs(np.gradient(f, t))
    width = r0_n + per_n_per_s * kelvin(t, rate, 1.0, 0.1)
    return band_play(f, width, width)


def asymmetric_kelvin(t, f, compliance_v_per_n, tau_up_s, tau_down_s):
    """A Kelvin unit that creeps toward c F with ``tau_up_s`` while below it and recovers with ``tau_down_s``."""
    dt = np.diff(t, prepend=t[0])
    out, u = np.empty_like(f), 0.0
    for i, (fi, h) in enumerate(zip(f.tolist(), dt.tolist())):
        target = compliance_v_per_n * fi
        tau = tau_up_s if target > u else tau_down_s
        u += (target - u) * (1.0 - np.exp(-h / tau))
        out[i] = u
    return out


def lugre(t, f, r_n, sigma0_per_n, viscous_n_s):
    """The force a LuGre contact passes on: F - z - viscous dz/dt-like drag, z a bristle state that saturates at
    ``r_n``: dz/dt = v - sigma0 |v| z / r, v the force's rate seen as the slip rate."""
    dt = np.diff(t, prepend=t[0])
    v_all = np.gradient(f, t)
    out, z = np.empty_like(f), 0.0
    for i, (v, h) in enumerate(zip(v_all.tolist(), dt.tolist())):
        z += h * (v - sigma0_per_n * abs(v) * z / r_n)
        z = min(max(z, -r_n), r_n)
        out[i] = f[i] - z - viscous_n_s * v
    return out


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    span = FORCE_MAX_N / c.relaxation().g0_n_per_v * 2.0  # ~ the core's output over the force range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([8e4, 4e3]))))
        zener = Zener(c.k1_n_per_v, c.k2_n_per_v, c.eta2_n_s_per_v)
        if shape == "smooth_yield_flow":
            f0 = rng.uniform(1.0, 4.0)
            return Parts("zener", RateFlowZener(zener, lambda f, phi=phi * 1.5, f0=f0: phi * np.clip(f, 0.0, None) ** 2
                                                / (np.clip(f, 0.0, None) + f0)), core_changed=True)
        knee, steeper = rng.uniform(3.0, 6.0), rng.uniform(2.0, 5.0)
        return Parts("zener", RateFlowZener(zener, lambda f, phi=phi, k=knee, s=steeper: phi * (
            f + (s - 1.0) * np.clip(f - k, 0.0, None))), core_changed=True)
    if effect == "delayed_elasticity":
        total = float(np.interp(m, [0, 1], [1 / 60.0, 1 / 6.0]))  # added compliance, V/N
        if shape == "box_spectrum":
            low = rng.uniform(np.log10(0.5), np.log10(5.0))
            taus = np.logspace(low, low + rng.uniform(1.0, 2.5), 12)
            p.extra.append(lambda t, f, T, taus=taus, k=total / taus.size: sum(kelvin(t, f, k, ti) for ti in taus))
            return p
        up, down = rng.uniform(2.0, 30.0), rng.uniform(2.0, 30.0)
        p.extra.append(lambda t, f, T, k=total, up=up, down=down: asymmetric_kelvin(t, f, k, up, down))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.02, 0.07]))
        if shape == "relays_force":
            n = 40
            centre, half = rng.uniform(0.0, FORCE_MAX_N, n), rng.uniform(0.05, 1.0, n) * frac * FORCE_MAX_N
            weights = rng.uniform(0.0, 1.0, n)
            weights *= frac * FORCE_MAX_N / weights.sum()
            low = np.maximum(centre - half, 0.0)
            p.before.append(ForcePath(lambda t, x, lo=low, hi=centre + half, w=weights: x + relays(x, lo, hi, w)))
            return p
        r0 = frac * FORCE_MAX_N / 4
        p.before.append(ForcePath(lambda t, x, r0=r0: rate_play(t, x, r0, r0 / 2.0)))
        return p
    if effect == "sensor_lag":
        tau = float(np.exp(np.interp(m, [0, 1], np.log([0.01, 0.12]))))
        if shape == "triangular_window":
            p.after.append(TriangularWindow(2.0 * tau))
            return p
        p.after.append(LinearFilter([1.0], np.polymul(np.polymul([tau, 1.0], [tau, 1.0]), [tau / 4, 1.0])))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.02, 0.08]))
        if shape == "softplus_clip":
            top, soft = span / 2 * rng.uniform(0.9, 1.2), span / 2 * 4.0 * rel
            p.after.append(StaticMap(lambda x, top=top, s=soft: x - s * np.logaddexp(0.0, (x - top) / s)))
            return p
        knee, sign = rng.uniform(0.2, 0.6) * span / 2, rng.choice([-1, 1])
        p.after.append(StaticMap(lambda x, k=knee, a=sign * rel * 6 / (span / 2): x + a * np.clip(
            np.abs(x) - k, 0.0, None) ** 2 * np.sign(x)))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.02]) * rng.choice([-1, 1]))
        if shape == "lagged_tanh_zero":
            w, tau = rng.uniform(1.0, 3.0), rng.uniform(10.0, 60.0)
            p.extra.append(lambda t, f, T, k=k, w=w, tau=tau: k * w * np.tanh((lagged(t, T, tau) - T_REF_C) / w))
            return p
        fast, slow, back = rng.uniform(5.0, 20.0), rng.uniform(60.0, 200.0), rng.uniform(0.3, 0.7)
        p.extra.append(lambda t, f, T, k=k, a=fast, b=slow, r=back: k * (
            (lagged(t, T, a) - T_REF_C) - r * (lagged(t, T, b) - T_REF_C)) / (1.0 - r))
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.002, 0.01]) * rng.choice([-1, 1]))
        out = core_output(c)
        if shape == "span_lagged_tanh":
            w, tau = rng.uniform(0.5, 2.0), rng.uniform(10.0, 60.0)
            p.extra.append(lambda t, f, T, a=a, w=w, tau=tau, out=out: 5.0 * a * w * np.tanh(
                (lagged(t, T, tau) - T_REF_C) / w) * out(t, f))
            return p
        fast, slow, back = rng.uniform(5.0, 20.0), rng.uniform(60.0, 200.0), rng.uniform(0.3, 0.7)
        p.extra.append(lambda t, f, T, a=a, f_=fast, s=slow, r=back, out=out: 1.5 * a * (
            (lagged(t, T, f_) - T_REF_C) - r * (lagged(t, T, s) - T_REF_C)) / (1.0 - r) * out(t, f))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.08]))
        sign = rng.choice([-1, 1])
        if shape == "ramp_to_plateau":
            corner, rounding = rng.uniform(0.3, 0.7) * DURATION_S, rng.uniform(10.0, 40.0)
            p.extra.append(lambda t, f, T, s=sign * size, c_=corner, r=rounding: s * (
                c_ - r * np.logaddexp(0.0, (c_ - (t - t[0])) / r)) / c_)
            return p
        p1, p2 = rng.uniform(150.0, 300.0), rng.uniform(300.0, 600.0)
        ph1, ph2 = rng.uniform(0, 2 * np.pi), rng.uniform(0, 2 * np.pi)
        p.extra.append(lambda t, f, T, s=sign * size / 2, a=p1, b=p2, u=ph1, v=ph2: s * (
            np.sin(2 * np.pi * (t - t[0]) / a + u) - np.sin(u) + np.sin(2 * np.pi * (t - t[0]) / b + v) - np.sin(v)))
        return p
    if effect == "resonance":
        f0, zeta = rng.uniform(20.0, 45.0), rng.uniform(0.02, 0.06)
        if shape == "load_tuned_mode":
            p.after.append(LoadTunedMode(f0, zeta, rng.uniform(0.2, 0.6), span / 2))
            return p
        w0 = 2 * np.pi * f0
        p.after.append(LinearFilter([w0 ** 3], np.polymul([1.0, 2 * zeta * w0, w0 ** 2], [1.0, w0])))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "cogging_band":
            pitch, depth = rng.uniform(1.5, 4.0), rng.uniform(0.3, 0.7)
            p.before.append(ForcePath(lambda t, x, r=r * 1.3, pitch=pitch, d=depth: band_play(
                x, r * (1 + d * np.sin(2 * np.pi * x / pitch)), r * (1 + d * np.sin(2 * np.pi * x / pitch)))))
            return p
        sigma0, visc = rng.uniform(2.0, 8.0), rng.uniform(0.0005, 0.002)
        p.before.append(ForcePath(lambda t, x, r=r * 1.3, s=sigma0, v=visc: lugre(t, x, r, s, v)))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.15, 0.4]))
        if shape == "threshold_shift":
            t0 = T_REF_C + rng.uniform(-2.0, 0.0)
            return Parts("burgers", ShiftedBurgers(c, lambda T, b=b * 1.5, t0=t0: np.exp(
                b * np.clip(T - t0, 0.0, None)), flow_only=False), core_changed=True)
        power = rng.uniform(2.0, 6.0)
        return Parts("burgers", ShiftedBurgers(c, lambda T, b=b * 1.5, q=power: np.clip(
            1.0 + b * (T - T_REF_C) / q, 1e-3, None) ** q, flow_only=False), core_changed=True)
    if effect == "coarse_quantisation":
        step = float(np.interp(m, [0, 1], [4e-3, 1e-2]))
        p.outer.append(StaticMap(lambda x, q=step: np.round(x / q) * q))
        return p
    if effect == "lateral_crosstalk":
        share, seed = float(np.interp(m, [0, 1], [0.03, 0.08])), int(rng.integers(2**31))

        def crosstalk(t, f, T, share=share, seed=seed, span=span):
            g = np.random.default_rng(seed)
            knots = np.arange(t[0], t[-1] + 5.0, g.uniform(1.0, 4.0))
            lateral = np.interp(t, knots, g.uniform(-1.0, 1.0, knots.size))
            return share * span / 2 * lateral
        p.extra.append(crosstalk)
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["smooth_yield_flow", "two_slope_flow"],
    "delayed_elasticity": ["box_spectrum", "asymmetric_kelvin"],
    "hysteresis": ["relays_force", "rate_play"], "sensor_lag": ["triangular_window", "three_poles_two_equal"],
    "nonlinear_gain": ["softplus_clip", "knee_quadratic"],
    "thermal_drift": ["lagged_tanh_zero", "opposite_lags_zero"],
    "thermal_sensitivity": ["span_lagged_tanh", "span_opposite_lags"],
    "offset_drift": ["ramp_to_plateau", "two_slow_sines"],
    "resonance": ["load_tuned_mode", "mode_with_pole"], "friction": ["cogging_band", "lugre"],
    "thermo_rheological": ["threshold_shift", "power_shift"],
}
PAIRS = (("viscous_flow", "resonance"), ("delayed_elasticity", "thermal_sensitivity"),
         ("hysteresis", "offset_drift"), ("sensor_lag", "nonlinear_gain"), ("friction", "thermo_rheological"),
         ("thermal_drift", "viscous_flow"))
OUTSIDE = ("coarse_quantisation", "lateral_crosstalk")
RATES = (180.0, 400.0, 750.0, 1000.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split I", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.0e-3, 3.0e-3), jitter=0.3,
                   gap_s=(0.05, 3.0))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
