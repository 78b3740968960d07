"""Independent split G for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Splits A to F were each run once and are spent. Split G is the untouched held-out set for the next engine: written
before it, run once at its end, never used to choose anything. Every name of the catalogue is hidden in two shapes
that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A to F use:

* a dashpot that hardens with time (Andrade: its rate falls as (1 + t/t_h)^(-2/3)), or one driven by the force
  through a lag of 3-15 s;
* creep with a log-normal spectrum of retardation times (centred at 2-30 s, half a decade wide), or two Kelvin
  units far apart (0.3-1 s and 60-150 s);
* a Bouc-Wen loop on the force before the core, or a Dahl loop on the force before the core;
* a first-order lag behind a dead time (10-150 ms and 3-15 ms), or three real poles (tau, tau/2, tau/3);
* an odd cubic gain, or a local bump of gain around a point of the range;
* a thermal zero that saturates (tanh of the temperature's departure), or one cubic in it;
* a span that saturates in temperature (tanh), or one with a cubic term;
* an offset that rises then falls (two exponentials), or a warm-up as the square root of time;
* a mode with an anti-resonance above it, or a light mode at 35-60 Hz;
* Dahl friction on the force path (a smooth play), or a play whose stuck force creeps after the input (2-10 s);
* a shift factor with a different slope below and above the reference temperature, or one with a cubic term.

It also holds six pairs, two effects outside the catalogue (contact dropouts that scale the bridge signal for
20-200 ms, a motor's 6-14 Hz vibration while the force moves) and four clean records. Profiles: triangular
load-unload cycles at constant rate, long holds modulated like breathing, and the measured Okamura insertion
(``../shared/data``; a train of synthetic punctures when it is absent) advanced in 2-4 steps. Rates 160, 480, 720
and 1000 Hz (a mode at 1000 Hz with knocks that excite it), 1-3.5 mV noise, stamp jitter, gaps, a temperature
cycled by a thermostat on a slow ramp.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_g.py [--json out.json] [--workers 2] [--stride 1] [--check]
"""
from __future__ import annotations

import numpy as np
from scipy import integrate

from polyforce_ros.physics.viscoelastic import Zener, simulate_deformation
from polyforce_ros.sim.truths import StaticMap
from split_kit import (LinearFilter, Parts, ShapeSplit, ShiftedBurgers, SimOnly, core_output, dahl, dead_time,
                       kelvin, ramp_and_hold, relaxing_play, repeated_insertions)

SEED0 = 470_000  # never a seed of the registry's splits nor of splits A (90000..) to F (400000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 450.0


# ----------------------------------------------------------------------------- profiles and temperature

def triangle_cycles(duration_s, rate_hz, rng):
    """Blocks of 2-8 triangular load-unload cycles at a constant 0.5-4 N/s to a 3-9 N peak, 10-30 s of rest
    between blocks."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    knots_t, knots_f, now = [0.0], [0.0], rng.uniform(3.0, 8.0)
    knots_t.append(now)
    knots_f.append(0.0)
    while now < duration_s:
        peak, slope = rng.uniform(3.0, FORCE_MAX_N), rng.uniform(0.5, 4.0)
        for _ in range(int(rng.integers(2, 9))):
            now = ramp_and_hold(knots_t, knots_f, now, peak, peak / slope, 0.0)
            now = ramp_and_hold(knots_t, knots_f, now, 0.0, peak / slope, 0.0)
        now = ramp_and_hold(knots_t, knots_f, now, 0.0, 0.0, rng.uniform(10.0, 30.0))
    return t, np.interp(t, knots_t, knots_f)


def breathing_holds(duration_s, rate_hz, rng):
    """Holds of 40-120 s at 3-8 N reached in 1-3 s, modulated by 0.3-1 N at 0.15-0.35 Hz (breathing), with
    10-50 s of rest between them."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    now = rng.uniform(3.0, 10.0)
    while now < duration_s:
        length, level, edge = rng.uniform(40.0, 120.0), rng.uniform(3.0, 8.0), rng.uniform(1.0, 3.0)
        amp, freq = rng.uniform(0.3, 1.0), rng.uniform(0.15, 0.35)
        inside = (t >= now) & (t < now + length)
        s = t[inside] - now
        envelope = np.clip(np.minimum(s, length - s) / edge, 0.0, 1.0)
        f[inside] = envelope * (level + amp * np.sin(2 * np.pi * freq * s + rng.uniform(0, 2 * np.pi)))
        now += length + rng.uniform(10.0, 50.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def stepped_okamura(duration_s, rate_hz, rng):
    """The measured insertion cut into 2-4 advances, each followed by a pause of 1-3 s where the force relaxes to
    60-90 % of where it stopped (a needle advanced in steps), repeated with 5-30 s of rest."""
    def stepped(tp, fp, rng):
        one = np.interp(np.arange(0.0, tp[-1] - tp[0], 1.0 / rate_hz), tp - tp[0], fp)
        cuts = np.sort(rng.uniform(0.2, 0.9, int(rng.integers(1, 4)))) * one.size
        pieces, start = [], 0
        for cut in [*cuts.astype(int), one.size]:
            pieces.append(one[start:cut])
            if cut < one.size and cut > start:
                n = int(rng.uniform(1.0, 3.0) * rate_hz)
                keep = rng.uniform(0.6, 0.9)
                last = one[cut - 1]
                pieces.append(last * (keep + (1.0 - keep) * np.exp(-np.arange(n) / (0.3 * rate_hz))))
            start = cut
        return np.concatenate(pieces)
    return repeated_insertions(duration_s, rate_hz, rng, stepped, FORCE_MAX_N)


PROFILES = (triangle_cycles, breathing_holds, stepped_okamura)


def temperature(t, rng):
    """A thermostat: a triangle of 1-2.5 degC peak to peak with a period of 60-200 s, on a ramp of 1-3 degC either
    way."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    period, swing = rng.uniform(60.0, 200.0), rng.uniform(1.0, 2.5)
    phase = (s / period + rng.uniform(0, 1)) % 1.0
    tri = swing * (2.0 * np.abs(2.0 * phase - 1.0) - 1.0) / 2.0
    return T_REF_C + rng.uniform(-1, 1) + rng.choice([-1, 1]) * rng.uniform(1.0, 3.0) * s / d + tri


# ----------------------------------------------------------------------------- simulate-only truth elements

class AndradeFlowZener(SimOnly):
    """A Zener core plus a dashpot that hardens with time: rate phi F (1 + t / t_h)^(-2/3)."""

    def __init__(self, zener, phi_v_per_n_s, t_h_s):
        self.zener, self.phi, self.t_h = zener, phi_v_per_n_s, t_h_s

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        rate = self.phi * f * (1.0 + (t - t[0]) / self.t_h) ** (-2.0 / 3.0)
        return simulate_deformation(self.zener, t, f) + integrate.cumulative_trapezoid(rate, t, initial=0.0)


class LaggedFlowZener(SimOnly):
    """A Zener core plus a dashpot driven by the force through a first-order lag of ``tau_s``."""

    def __init__(self, zener, phi_v_per_n_s, tau_s):
        self.zener, self.phi, self.tau = zener, phi_v_per_n_s, tau_s

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        lagged = kelvin(t, f, 1.0, self.tau)
        return simulate_deformation(self.zener, t, f) + integrate.cumulative_trapezoid(self.phi * lagged, t,
                                                                                         initial=0.0)


def bouc_wen(x, amplitude, a=1.0, beta=0.6, gamma=0.4, n=1.0):
    """A Bouc-Wen state driven by ``x``, scaled so its loop saturates at about ``amplitude``."""
    x = np.asarray(x, dtype=float)
    z_max = (a / (beta + gamma)) ** (1.0 / n)
    scale = amplitude / z_max
    dx = np.diff(x, prepend=x[0]) / scale
    z, out = 0.0, np.empty_like(x)
    for i, step in enumerate(dx.tolist()):
        z += a * step - beta * abs(step) * abs(z) ** (n - 1) * z - gamma * step * abs(z) ** n
        out[i] = z
    return out * scale


class ForceLoop(SimOnly):
    """A loop on the force before the core: ``F + loop(F)`` (hysteresis of the force path)."""

    def __init__(self, loop):
        self.loop = loop

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        return x + self.loop(x)


class DahlFriction(SimOnly):
    """Friction in the mechanism as a Dahl model: the force passed on is ``F - z``, z a Dahl state of half-width
    ``r_n`` (a play with rounded corners)."""

    def __init__(self, r_n, sigma):
        self.r, self.sigma = r_n, sigma

    def forward(self, t_s, x, aux=None, state=None):
        f = np.asarray(x, dtype=float)
        return f - dahl(f, self.r, self.sigma)


class RelaxingFriction(SimOnly):
    """A play of half-width ``r_n`` whose stuck force creeps toward the input with ``tau_s``."""

    def __init__(self, r_n, tau_s):
        self.r, self.tau = r_n, tau_s

    def forward(self, t_s, x, aux=None, state=None):
        return relaxing_play(np.asarray(t_s, dtype=float), np.asarray(x, dtype=float), self.r, self.tau)


class DeadTimeLag(SimOnly):
    """A first-order lag of ``tau_s`` behind a dead time of ``delay_s``."""

    def __init__(self, tau_s, delay_s):
        self.lag, self.delay = LinearFilter([1.0], [tau_s, 1.0]), delay_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        return self.lag.forward(t, dead_time(t, np.asarray(x, dtype=float), self.delay))


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    span = FORCE_MAX_N / c.relaxation().g0_n_per_v * 2.0  # ~ the core's output over the force range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([8e4, 4e3]))))
        zener = Zener(c.k1_n_per_v, c.k2_n_per_v, c.eta2_n_s_per_v)
        if shape == "andrade_flow":
            return Parts("zener", AndradeFlowZener(zener, phi * 3.0, rng.uniform(20.0, 100.0)), core_changed=True)
        return Parts("zener", LaggedFlowZener(zener, phi, rng.uniform(3.0, 15.0)), core_changed=True)
    if effect == "delayed_elasticity":
        total = float(np.interp(m, [0, 1], [1 / 60.0, 1 / 6.0]))  # added compliance, V/N
        if shape == "lognormal_spectrum":
            centre, taus = rng.uniform(np.log10(2.0), np.log10(30.0)), np.geomspace(0.05, 2000.0, 19)
            w = np.exp(-0.5 * ((np.log10(taus) - centre) / 0.5) ** 2)
            w *= total / w.sum()
            p.extra.append(lambda t, f, T, taus=taus, w=w: sum(kelvin(t, f, wi, ti) for wi, ti in zip(w, taus)))
            return p
        fast, slow = rng.uniform(0.3, 1.0), rng.uniform(60.0, 150.0)
        p.extra.append(lambda t, f, T, k=total / 2, a=fast, b=slow: kelvin(t, f, k, a) + kelvin(t, f, k, b))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.02, 0.07]))
        if shape == "bouc_wen_force":
            p.before.append(ForceLoop(lambda x, amp=frac * FORCE_MAX_N / 2: bouc_wen(x, amp)))
            return p
        sigma = rng.uniform(0.5, 2.0)
        p.before.append(ForceLoop(lambda x, amp=frac * FORCE_MAX_N / 2, s=sigma: dahl(x, amp, s)))
        return p
    if effect == "sensor_lag":
        if shape == "dead_time_lag":
            tau = float(np.exp(np.interp(m, [0, 1], np.log([0.01, 0.15]))))
            p.after.append(DeadTimeLag(tau, rng.uniform(0.003, 0.015)))
            return p
        tau = float(np.exp(np.interp(m, [0, 1], np.log([0.01, 0.15]))))
        den = np.polymul(np.polymul([tau, 1.0], [tau / 2, 1.0]), [tau / 3, 1.0])
        p.after.append(LinearFilter([1.0], den))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.02, 0.08]))
        if shape == "odd_cubic":
            sign = rng.choice([-1, 1])
            p.after.append(StaticMap(lambda x, s=span / 2, a=sign * rel: x + a * x ** 3 / s ** 2))
            return p
        at, width, sign = rng.uniform(0.3, 0.7) * span / 2, rng.uniform(0.1, 0.25) * span / 2, rng.choice([-1, 1])
        p.after.append(StaticMap(lambda x, a=sign * rel * span / 2, at=at, w=width: x + a * np.exp(
            -0.5 * ((np.abs(x) - at) / w) ** 2)))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.02]) * rng.choice([-1, 1]))
        if shape == "saturating_zero":
            w = rng.uniform(1.0, 3.0)
            p.extra.append(lambda t, f, T, k=k, w=w: k * w * np.tanh((T - T_REF_C) / w))
            return p
        p.extra.append(lambda t, f, T, k=k: k * (T - T_REF_C) ** 3 / 2.0)
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.002, 0.01]) * rng.choice([-1, 1]))
        out = core_output(c)
        if shape == "span_saturating":
            w = rng.uniform(0.5, 1.5)
            p.extra.append(lambda t, f, T, a=a, w=w, out=out: 2.5 * a * w * np.tanh((T - T_REF_C) / w) * out(t, f))
            return p
        p.extra.append(lambda t, f, T, a=a, out=out: a * ((T - T_REF_C) + 0.3 * (T - T_REF_C) ** 3) * out(t, f))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.08]))
        sign = rng.choice([-1, 1])
        if shape == "rise_and_fall":
            rise, fall = rng.uniform(20.0, 60.0), rng.uniform(150.0, 400.0)
            s = np.linspace(0.0, DURATION_S, 2001)
            peak = float(np.max(np.exp(-s / fall) - np.exp(-s / rise)))
            p.extra.append(lambda t, f, T, s=sign * size / peak, a=rise, b=fall: s * (
                np.exp(-(t - t[0]) / b) - np.exp(-(t - t[0]) / a)))
            return p
        p.extra.append(lambda t, f, T, s=sign * size: s * np.sqrt(np.clip(t - t[0], 0.0, None) / DURATION_S))
        return p
    if effect == "resonance":
        if shape == "anti_resonance":
            fp, zp = rng.uniform(20.0, 50.0), rng.uniform(0.02, 0.06)
            fz = fp * rng.uniform(1.3, 1.8)
            wp, wz = 2 * np.pi * fp, 2 * np.pi * fz
            num = np.array([1.0, 2 * 0.05 * wz, wz ** 2]) * wp ** 2 / wz ** 2
            p.after.append(LinearFilter(num, [1.0, 2 * zp * wp, wp ** 2]))
            return p
        f0, zeta = rng.uniform(35.0, 60.0), rng.uniform(0.02, 0.06)
        w0 = 2 * np.pi * f0
        p.after.append(LinearFilter([w0 ** 2], [1.0, 2 * zeta * w0, w0 ** 2]))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "dahl_friction":
            p.before.append(DahlFriction(r * 1.3, rng.uniform(1.0, 3.0)))
            return p
        p.before.append(RelaxingFriction(r * 1.3, rng.uniform(2.0, 10.0)))
        return p
    if effect == "thermo_rheological":
        if shape == "two_slope_shift":
            b = float(np.interp(m, [0, 1], [0.15, 0.4]))
            above, below = (b * rng.uniform(2.0, 4.0), b) if rng.random() < 0.5 else (b, b * rng.uniform(2.0, 4.0))
            return Parts("burgers", ShiftedBurgers(c, lambda T, a=above, u=below: np.exp(np.where(
                T > T_REF_C, a, u) * (T - T_REF_C)), flow_only=False), core_changed=True)
        b = float(np.interp(m, [0, 1], [0.15, 0.4]))
        q = rng.uniform(0.01, 0.03) * rng.choice([-1, 1])
        return Parts("burgers", ShiftedBurgers(c, lambda T, b=b, q=q: np.exp(b * (T - T_REF_C) + q * (T - T_REF_C) ** 3),
                                              flow_only=False), core_changed=True)
    if effect == "contact_dropouts":
        share = float(np.interp(m, [0, 1], [0.3, 0.7]))
        out, seed = core_output(c), int(rng.integers(2**31))

        def dropouts(t, f, T, share=share, out=out, seed=seed):
            g = np.random.default_rng(seed)
            loss = np.zeros_like(t)
            for at in g.uniform(t[0], t[-1], int(g.integers(15, 40))):
                loss[(t >= at) & (t < at + g.uniform(0.02, 0.2))] = share
            return -loss * out(t, f)
        p.extra.append(dropouts)
        return p
    if effect == "motor_vibration":
        size, freq = float(np.interp(m, [0, 1], [0.01, 0.03])), rng.uniform(6.0, 14.0)

        def vibration(t, f, T, size=size, freq=freq):
            moving = np.abs(np.gradient(f, t))
            envelope = kelvin(t, np.minimum(moving / 2.0, 1.0), 1.0, 0.2)
            return size * envelope * np.sin(2 * np.pi * freq * (t - t[0]))
        p.extra.append(vibration)
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["andrade_flow", "lagged_flow"],
    "delayed_elasticity": ["lognormal_spectrum", "wide_pair"],
    "hysteresis": ["bouc_wen_force", "dahl_force"], "sensor_lag": ["dead_time_lag", "three_real_poles"],
    "nonlinear_gain": ["odd_cubic", "gain_bump"],
    "thermal_drift": ["saturating_zero", "cubic_zero"],
    "thermal_sensitivity": ["span_saturating", "span_cubic"],
    "offset_drift": ["rise_and_fall", "square_root_warm_up"],
    "resonance": ["anti_resonance", "mid_mode"], "friction": ["dahl_friction", "relaxing_band"],
    "thermo_rheological": ["two_slope_shift", "cubic_shift"],
}
PAIRS = (("viscous_flow", "nonlinear_gain"), ("delayed_elasticity", "thermal_drift"), ("hysteresis", "sensor_lag"),
         ("thermal_sensitivity", "offset_drift"), ("friction", "delayed_elasticity"),
         ("resonance", "thermo_rheological"))
OUTSIDE = ("contact_dropouts", "motor_vibration")
RATES = (160.0, 480.0, 720.0, 1000.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split G", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.35, 0.75),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.0e-3, 3.5e-3), jitter=0.3,
                   gap_s=(0.05, 3.0))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
