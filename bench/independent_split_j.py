"""Independent split J for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split J is an untouched held-out set: written before the engine it measures, run once at its end, never used to
choose anything. Every name of the catalogue is hidden in two shapes that neither the registry's families
(``polyforce_ros/sim/truths.py``) nor splits A to I use:

* a springpot (a fractional dashpot of order 0.85-0.95) in series with the core, or a dashpot that thins under load
  and thickens again at rest (thixotropy);
* creep through two equal Kelvin lags in cascade (a sigmoidal onset), or a Kelvin unit whose retardation time
  shortens exponentially with the load (stress-activated creep);
* a generalised play on the bridge voltage with a lens-shaped envelope (closed at no load and at the top of the
  range), or a Bouc-Wen loop on the force pinched at its middle (Baber-Noori);
* a Hamming-windowed sinc FIR low-pass (a DAQ's digital anti-alias filter), or a moving average behind a pole;
* an S-shaped cubic integral non-linearity (zero at no load, mid-range and the top of the range), or a smooth random
  one (a spline through random knots);
* a thermal zero that follows the temperature at the middle of a slab (heat diffusion), or a lag that warms and
  cools at different speeds;
* a span that follows the middle of a slab, or one that changes only outside a dead band about the reference (a
  compensation that holds near it);
* an offset that jumps and partly recovers (a disturbed connector), or a random walk smoothed over minutes;
* a mode damped by dry friction at a joint (ringing that decays by a fixed amount per cycle), or a mode whose
  frequency falls as the polymer warms;
* Coulomb friction whose breakaway grows with the time the contact has been stuck (contact ageing), or a guide that
  engages only above a contact force;
* a shift factor on the fictive temperature of a glassy polymer (Tool-Narayanaswamy-Moynihan), or one tabulated at
  five temperatures and interpolated (a measured master curve).

It also holds six pairs, two effects outside the catalogue (a 100 or 120 Hz ripple of the bridge excitation, a
sampling clock that runs fast or slow against the force's) and four clean records. Profiles: blocks of multisine
loading, staircases of advances each followed by a partial retraction, and the measured Okamura insertion with a
2-6 Hz vibration on it (vibration-assisted insertion; ``../shared/data``, a train of synthetic punctures when it is
absent). Rates 220, 520, 780 and 1000 Hz (a mode at 1000 Hz with knocks that excite it), 1-3 mV noise, stamp
jitter, gaps, a temperature swept up and down by a climate chamber.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_j.py [--json out.json] [--workers 2] [--stride 1] [--check]
"""
from __future__ import annotations

import math

import numpy as np
from scipy import integrate, interpolate, signal, special

from polyforce_ros.physics.viscoelastic import Zener, simulate_deformation
from polyforce_ros.sim.truths import StaticMap
from split_kit import (ForcePath, Parts, ShapeSplit, ShiftedBurgers, SimOnly, band_play, core_output, kelvin,
                       ramp_and_hold, repeated_insertions, uniform_grid)

SEED0 = 680_000  # never a seed of the registry's splits nor of splits A (90000..) to I (610000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 450.0


# ----------------------------------------------------------------------------- profiles and temperature

def multisine_blocks(duration_s, rate_hz, rng):
    """Blocks of 30-90 s of a multisine (eight equal tones spaced logarithmically from 0.02-0.05 Hz to 1.5-3 Hz, random
    phases) about a mean of 2-6 N with 1-6 N peak to peak, faded in and out over 2 s, between rests of 5-25 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    now = rng.uniform(3.0, 8.0)
    while now < duration_s:
        length = rng.uniform(30.0, 90.0)
        inside = (t >= now) & (t < now + length)
        s = t[inside] - now
        tones, phases = np.geomspace(rng.uniform(0.02, 0.05), rng.uniform(1.5, 3.0), 8), rng.uniform(0, 2 * np.pi, 8)
        x = np.sin(2 * np.pi * np.outer(s, tones) + phases).sum(axis=1)
        x = (x - x.mean()) / max(float(np.ptp(x)), 1e-9) if x.size else x
        mean, pp = rng.uniform(2.0, 6.0), rng.uniform(1.0, 6.0)
        fade = np.clip(s / 2.0, 0.0, 1.0) * np.clip((length - s) / 2.0, 0.0, 1.0)
        f[inside] = fade * np.clip(mean + pp * x, 0.0, FORCE_MAX_N)
        now += length + rng.uniform(5.0, 25.0)
    return t, f


def advance_retract_stairs(duration_s, rate_hz, rng):
    """Staircases of 3-6 advances: each raises the force by 0.8-2.5 N in 0.2-1 s and holds 2-8 s, then backs off by
    30-70 % of that rise in 0.2-0.6 s and holds 1-5 s; the load is released in 0.5-2 s and rests 10-30 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    knots_t, knots_f, now = [0.0], [0.0], rng.uniform(3.0, 8.0)
    knots_t.append(now)
    knots_f.append(0.0)
    while now < duration_s:
        level = 0.0
        for _ in range(int(rng.integers(3, 7))):
            top = min(level + rng.uniform(0.8, 2.5), FORCE_MAX_N)
            now = ramp_and_hold(knots_t, knots_f, now, top, rng.uniform(0.2, 1.0), rng.uniform(2.0, 8.0))
            level = top - rng.uniform(0.3, 0.7) * (top - level)
            now = ramp_and_hold(knots_t, knots_f, now, level, rng.uniform(0.2, 0.6), rng.uniform(1.0, 5.0))
        now = ramp_and_hold(knots_t, knots_f, now, 0.0, rng.uniform(0.5, 2.0), rng.uniform(10.0, 30.0))
    return t, np.interp(t, knots_t, knots_f)


def vibrated_okamura(duration_s, rate_hz, rng):
    """The measured insertion with a 2-6 Hz vibration of 5-15 % of the force on it (vibration-assisted insertion),
    each copy scaled to a 2-9 N peak and repeated with 5-30 s of rest."""
    def vibrated(tp, fp, rng):
        one = np.interp(np.arange(0.0, tp[-1] - tp[0], 1.0 / rate_hz), tp - tp[0], fp)
        depth, hz, phase = rng.uniform(0.05, 0.15), rng.uniform(2.0, 6.0), rng.uniform(0, 2 * np.pi)
        return one * (1.0 + depth * np.sin(2 * np.pi * hz * np.arange(one.size) / rate_hz + phase))
    return repeated_insertions(duration_s, rate_hz, rng, vibrated, FORCE_MAX_N)


PROFILES = (multisine_blocks, advance_retract_stairs, vibrated_okamura)


def temperature(t, rng):
    """A climate chamber sweeping up and down: a triangle wave of 4-7 degC peak to peak with a period of 150-400 s,
    rising over 30-70 % of each period, seen through a lag of 10-40 s, about a level within 1 degC of 23 degC."""
    s = t - t[0]
    period, pp, rise = rng.uniform(150.0, 400.0), rng.uniform(4.0, 7.0), rng.uniform(0.3, 0.7)
    phase = (s / period + rng.uniform(0.0, 1.0)) % 1.0
    wave = pp * (np.where(phase < rise, phase / rise, (1.0 - phase) / (1.0 - rise)) - 0.5)
    smooth = wave[0] + kelvin(t, wave - wave[0], 1.0, rng.uniform(10.0, 40.0))
    return T_REF_C + rng.uniform(-1.0, 1.0) + smooth


# ----------------------------------------------------------------------------- simulate-only truth elements

class SpringpotFlowZener(SimOnly):
    """A Zener core in series with a springpot (a Scott Blair element) of order ``alpha``: its creep per newton is
    phi t0^(1 - alpha) t^alpha / Gamma(1 + alpha), a dashpot of fluidity phi when alpha = 1; by FFT convolution on
    a uniform grid at the median step."""

    def __init__(self, zener, phi, alpha, t0_s):
        self.zener, self.phi, self.alpha, self.t0 = zener, phi, alpha, t0_s

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, fu, h = uniform_grid(t, f)
        creep = self.phi * self.t0 ** (1.0 - self.alpha) * (tu - tu[0]) ** self.alpha / special.gamma(1.0 + self.alpha)
        flow = signal.fftconvolve(np.diff(fu, prepend=0.0), creep)[:tu.size]
        return simulate_deformation(self.zener, t, f) + np.interp(t, tu, flow)


class ThixotropicFlowZener(SimOnly):
    """A Zener core plus a dashpot that thins under load and thickens at rest (thixotropy): its fluidity is
    phi (1 + b s), the broken-down share s rising at (1 - s) |F| / (F_max / 2) / tau_break and falling at
    s / tau_rest."""

    def __init__(self, zener, phi, b, tau_break_s, tau_rest_s):
        self.zener, self.phi, self.b, self.tau_break, self.tau_rest = zener, phi, b, tau_break_s, tau_rest_s

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        dt = np.diff(t, prepend=t[0])
        rate, s, f_ref = np.empty_like(f), 0.0, FORCE_MAX_N / 2
        for i, (fi, h) in enumerate(zip(f.tolist(), dt.tolist())):
            s += h * ((1.0 - s) * abs(fi) / f_ref / self.tau_break - s / self.tau_rest)
            s = min(max(s, 0.0), 1.0)
            rate[i] = self.phi * (1.0 + self.b * s) * fi
        return simulate_deformation(self.zener, t, f) + integrate.cumulative_trapezoid(rate, t, initial=0.0)


class LensPlay(SimOnly):
    """A generalised play on the bridge voltage whose envelopes x -+ w(x) close at zero and at ``top_v`` and open to
    ``w_max_v`` halfway, w = w_max sin(pi x / top): a lens-shaped loop, started at x[0]."""

    def __init__(self, w_max_v, top_v):
        self.w, self.top = w_max_v, top_v

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        w = self.w * np.sin(np.pi * np.clip(x / self.top, 0.0, 1.0))
        return band_play(x, w, w)


class WindowedSinc(SimOnly):
    """A causal FIR low-pass: a Hamming-windowed sinc of cut-off ``cutoff_hz`` over ``length_s`` (a DAQ's digital
    anti-alias filter, delayed by half its length), settled at x[0] before the record, on a uniform grid at the
    median step."""

    def __init__(self, length_s, cutoff_hz):
        self.length, self.cutoff = length_s, cutoff_hz

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        n = max(3, int(round(self.length / h)) // 2 * 2 + 1)
        k = np.arange(n) - (n - 1) / 2
        taps = np.sinc(2.0 * min(self.cutoff, 0.45 / h) * h * k) * np.hamming(n)
        y = signal.lfilter(taps / taps.sum(), [1.0], xu - x[0]) + x[0]
        return np.interp(t, tu, y)


class BoxcarPole(SimOnly):
    """A moving average over ``width_s`` behind a first-order pole of ``tau_s`` (an averaging ADC behind an RC
    stage), settled at x[0] before the record, on a uniform grid at the median step."""

    def __init__(self, width_s, tau_s):
        self.width, self.tau = width_s, tau_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        n = max(1, int(round(self.width / h)))
        mean = signal.lfilter(np.ones(n) / n, [1.0], xu - x[0])
        a = math.exp(-h / self.tau)
        return np.interp(t, tu, signal.lfilter([1.0 - a], [1.0, -a], mean) + x[0])


class DryDampedMode(SimOnly):
    """A light mode on the core's output damped by dry friction at a joint as well as viscously (damping ratio
    ``zeta``): the joint holds while the spring pulls less than ``slip_v`` from it, so the ringing decays by about
    4 slip_v a cycle; integrated per sample (semi-implicit Euler, two sub-steps, on a uniform grid at the median
    step)."""

    def __init__(self, f0_hz, zeta, slip_v):
        self.f0, self.zeta, self.slip = f0_hz, zeta, slip_v

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        w = 2.0 * math.pi * self.f0
        w2, damp, held, hs = w * w, 2.0 * self.zeta * w, w * w * self.slip, h / 2.0
        y, v, out = float(xu[0]), 0.0, np.empty_like(xu)
        for i, xi in enumerate(xu.tolist()):
            for _ in range(2):
                a = w2 * (xi - y) - damp * v
                if v == 0.0 and abs(a) <= held:
                    continue  # stuck
                nv = v + hs * (a - math.copysign(held, v if v != 0.0 else a))
                v = 0.0 if v * nv < 0.0 else nv
                y += hs * v
            out[i] = y
        return np.interp(t, tu, out)


class ThermallyTunedMode(SimOnly):
    """A light mode on the core's output whose frequency falls as the polymer warms, f0 (1 - c (T - T_ref)) (its
    modulus softens), integrated per sample (semi-implicit Euler on a uniform grid at the median step)."""

    def __init__(self, f0_hz, zeta, per_c):
        self.f0, self.zeta, self.c = f0_hz, zeta, per_c

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        temp = np.broadcast_to(np.asarray(aux["temperature_c"], dtype=float), t.shape)
        tu, xu, h = uniform_grid(t, x)
        w = 2.0 * np.pi * self.f0 * (1.0 - self.c * (np.interp(tu, t, temp) - T_REF_C))
        y, v, out = float(xu[0]), 0.0, np.empty_like(xu)
        for i, (xi, wi) in enumerate(zip(xu.tolist(), w.tolist())):
            v += h * (wi * wi * (xi - y) - 2.0 * self.zeta * wi * v)
            y += h * v
            out[i] = y
        return np.interp(t, tu, out)


class FictiveShiftBurgers(SimOnly):
    """A Burgers core on the reduced time of the shift factor exp(b (Tf - T_ref)), Tf the polymer's fictive
    temperature (:func:`fictive_temperature`): the creep speeds up as the structure, not the thermometer, warms."""

    def __init__(self, c, b_per_c, tau0_s, c_per_c, x_share):
        self.c, self.b, self.tau0, self.per_c, self.x = c, b_per_c, tau0_s, c_per_c, x_share

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        temp = np.broadcast_to(np.asarray(aux["temperature_c"], dtype=float), t.shape)
        rate = np.exp(self.b * (fictive_temperature(t, temp, self.tau0, self.per_c, self.x) - T_REF_C))
        xi = integrate.cumulative_trapezoid(rate, t, initial=0.0)  # the reduced time
        return simulate_deformation(self.c, xi, np.asarray(x, dtype=float))


class ExcitationRipple(SimOnly):
    """The bridge's excitation rippling at ``hz`` (a rectified mains supply): the whole bridge signal scales by
    1 + g sin(2 pi hz t + phase)."""

    def __init__(self, g, hz, phase):
        self.g, self.hz, self.phase = g, hz, phase

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        return np.asarray(x, dtype=float) * (1.0 + self.g * np.sin(2 * np.pi * self.hz * t + self.phase))


class ClockDrift(SimOnly):
    """The bridge's sampling clock running fast or slow by a fraction ``e`` against the force's: the voltage
    stamped t is the one of t0 + (t - t0) (1 + e)."""

    def __init__(self, e):
        self.e = e

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        return np.interp(t[0] + (t - t[0]) * (1.0 + self.e), t, np.asarray(x, dtype=float))


def activated_kelvin(t, f, compliance_v_per_n, tau0_s, f_a_n):
    """A Kelvin unit whose retardation time shortens with the load, tau0 exp(-|F| / f_a) (stress-activated creep):
    it creeps toward c F quickly under a large load and recovers slowly at rest; from rest."""
    dt = np.diff(t, prepend=t[0])
    out, u = np.empty_like(f), 0.0
    for i, (fi, h) in enumerate(zip(f.tolist(), dt.tolist())):
        u += (compliance_v_per_n * fi - u) * (1.0 - math.exp(-h / (tau0_s * math.exp(-abs(fi) / f_a_n))))
        out[i] = u
    return out


def pinched_bouc_wen(x, z_max, pinch, spread):
    """A Bouc-Wen state driven by ``x`` (A = 1, n = 1, beta = gamma = 1 / (2 z_max): it saturates at +-z_max) whose
    rate collapses where z passes z_max / 10 in the direction of motion, by 1 - pinch exp(-((z sign(dx) - z_max / 10)
    / spread)^2) (Baber-Noori pinching: a loop pinched at its middle); from zero, in sub-steps of at most z_max / 10."""
    x = np.asarray(x, dtype=float)
    k, q = 0.5 / z_max, 0.1 * z_max
    z, out = 0.0, np.empty_like(x)
    for i, step in enumerate(np.diff(x, prepend=x[0]).tolist()):
        if step:
            n = int(abs(step) / q) + 1
            d, s = step / n, math.copysign(1.0, step)
            for _ in range(n):
                z += (1.0 - pinch * math.exp(-((z * s - q) / spread) ** 2)) * (d - k * abs(d) * z - k * d * abs(z))
        out[i] = z
    return out


def s_cubic(u):
    """u (u - 1/2) (u - 1) on [0, 1.1], flat outside: an S-shaped integral non-linearity that is zero at no load, at
    mid-range and at the top of the range (u = 1)."""
    u = np.clip(u, 0.0, 1.1)
    return u * (u - 0.5) * (u - 1.0)


def slab_middle(t, temp, tau_s, modes=40):
    """The temperature at the middle of a slab whose faces follow ``temp`` (heat diffusion): its odd modes n = 0, 1,
    ... as lags of tau / (2n + 1)^2 weighted (-1)^n / (2n + 1) (to a unit sum), settled at temp[0]."""
    n = np.arange(modes)
    weights = (-1.0) ** n / (2 * n + 1)
    weights /= weights.sum()
    d = temp - temp[0]
    return temp[0] + sum(w * kelvin(t, d, 1.0, tau_s / (2 * k + 1) ** 2) for w, k in zip(weights, n.tolist()))


def asymmetric_lag(t, x, tau_up_s, tau_down_s):
    """``x`` through a first-order lag of ``tau_up_s`` while it is above the output and ``tau_down_s`` while below (a
    body that warms and cools at different speeds), settled at x[0]."""
    dt = np.diff(t, prepend=t[0])
    out, u = np.empty_like(x), float(x[0])
    for i, (xi, h) in enumerate(zip(x.tolist(), dt.tolist())):
        u += (xi - u) * (1.0 - math.exp(-h / (tau_up_s if xi > u else tau_down_s)))
        out[i] = u
    return out


def smoothed_walk(t, size_v, seed, tau_s):
    """A random walk of one step a second (from ``seed``) through a lag of ``tau_s``, scaled to a largest excursion
    of ``size_v`` from its start at the record's start."""
    g = np.random.default_rng(seed)
    grid = np.arange(0.0, DURATION_S + 2.0, 1.0)
    walk = np.cumsum(g.normal(0.0, 1.0, grid.size))
    walk = kelvin(grid, walk - walk[0], 1.0, tau_s)
    return size_v * np.interp(t - t[0], grid, walk / max(float(np.abs(walk).max()), 1e-12))


def ageing_stiction(t, f, r_n, growth, theta_s):
    """Coulomb friction whose breakaway grows with the time the contact has been stuck, r (1 + growth ln(1 + t_stuck
    / theta)) (contact ageing); once it breaks away the contact slides r behind the force, and it sticks again where
    the force stops or turns. Stuck at f[0] from the start."""
    out, held, sliding, since = np.empty_like(f), float(f[0]), False, float(t[0])
    for i, (ti, fi) in enumerate(zip(t.tolist(), f.tolist())):
        gap = fi - held
        limit = r_n if sliding else r_n * (1.0 + growth * math.log1p((ti - since) / theta_s))
        if abs(gap) > limit * (1.0 + 1e-9):
            held, sliding = fi - math.copysign(r_n, gap), True
        elif sliding:
            sliding, since = False, ti
        out[i] = held
    return out


def fictive_temperature(t, temp, tau0_s, c_per_c, x_share):
    """The fictive temperature of a glassy polymer (Tool-Narayanaswamy-Moynihan): it relaxes toward the temperature
    with a time constant tau0 exp(-c (x dT + (1 - x) dTf)), dT and dTf the departures of the temperature and of itself
    from the reference (faster when warm, and once the structure has warmed); in equilibrium at temp[0]."""
    dt = np.diff(t, prepend=t[0])
    out, tf = np.empty_like(temp), float(temp[0])
    for i, (ti, h) in enumerate(zip(temp.tolist(), dt.tolist())):
        tau = tau0_s * math.exp(-c_per_c * (x_share * (ti - T_REF_C) + (1.0 - x_share) * (tf - T_REF_C)))
        tf += (ti - tf) * (1.0 - math.exp(-h / tau))
        out[i] = tf
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
        if shape == "springpot_flow":
            return Parts("zener", SpringpotFlowZener(zener, phi, rng.uniform(0.85, 0.95), 100.0), core_changed=True)
        return Parts("zener", ThixotropicFlowZener(zener, phi, rng.uniform(1.0, 3.0), rng.uniform(20.0, 60.0),
                                                   rng.uniform(30.0, 120.0)), core_changed=True)
    if effect == "delayed_elasticity":
        total = float(np.interp(m, [0, 1], [1 / 60.0, 1 / 6.0]))  # added compliance, V/N
        if shape == "cascaded_kelvin":
            tau = rng.uniform(2.0, 30.0)
            p.extra.append(lambda t, f, T, k=total, tau=tau: kelvin(t, kelvin(t, f, 1.0, tau), k, tau))
            return p
        tau0, f_a = rng.uniform(20.0, 80.0), rng.uniform(1.5, 4.0)
        p.extra.append(lambda t, f, T, k=total, tau0=tau0, f_a=f_a: activated_kelvin(t, f, k, tau0, f_a))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.02, 0.07]))
        if shape == "lens_play_voltage":
            p.after.append(LensPlay(frac * span / 3, span * rng.uniform(0.5, 0.8)))
            return p
        z_max, pinch, spread = frac * FORCE_MAX_N * 0.65, rng.uniform(0.6, 0.9), rng.uniform(0.2, 0.4)
        p.before.append(ForcePath(lambda t, x, z=z_max, k=pinch, s=spread: x + pinched_bouc_wen(x, z, k, s * z)))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.01, 0.12]))))
        if shape == "windowed_sinc":
            p.after.append(WindowedSinc(2.0 * delay, 1.5 / delay))
            return p
        share = rng.uniform(0.3, 0.7)
        p.after.append(BoxcarPole(2.0 * share * delay, (1.0 - share) * delay))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.02, 0.08]))
        top = span / 2 * rng.uniform(1.0, 1.5)
        if shape == "s_cubic_inl":
            a = rng.choice([-1, 1]) * rel * top / 0.048  # s_cubic peaks at 0.048
            p.after.append(StaticMap(lambda x, a=a, top=top: x + a * s_cubic(x / top)))
            return p
        spline = interpolate.CubicSpline(np.linspace(0.0, 1.0, 6), np.concatenate([[0.0], rng.normal(0, 1, 4), [0.0]]))
        a = rel * top / float(np.max(np.abs(spline(np.linspace(0.0, 1.0, 501)))))
        p.after.append(StaticMap(lambda x, a=a, top=top, sp=spline: x + a * sp(np.clip(x / top, 0.0, 1.0))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.02]) * rng.choice([-1, 1]))
        if shape == "slab_zero":
            tau = rng.uniform(20.0, 80.0)
            p.extra.append(lambda t, f, T, k=k, tau=tau: k * (slab_middle(t, T, tau) - T_REF_C))
            return p
        fast, slow = rng.uniform(5.0, 20.0), rng.uniform(40.0, 120.0)
        up, down = (fast, slow) if rng.random() < 0.5 else (slow, fast)
        p.extra.append(lambda t, f, T, k=k, up=up, down=down: k * (asymmetric_lag(t, T, up, down) - T_REF_C))
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.002, 0.01]) * rng.choice([-1, 1]))
        out = core_output(c)
        if shape == "span_slab":
            tau = rng.uniform(20.0, 80.0)
            p.extra.append(lambda t, f, T, a=a, tau=tau, out=out: 2.5 * a * (slab_middle(t, T, tau) - T_REF_C)
                           * out(t, f))
            return p
        band = rng.uniform(0.2, 0.8)
        p.extra.append(lambda t, f, T, a=a, b=band, out=out: 5.0 * a * np.sign(T - T_REF_C) * np.clip(
            np.abs(T - T_REF_C) - b, 0.0, None) * out(t, f))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.08]))
        sign = rng.choice([-1, 1])
        if shape == "jump_and_recover":
            at, keep, tau = rng.uniform(0.2, 0.7) * DURATION_S, rng.uniform(0.2, 0.6), rng.uniform(20.0, 80.0)
            p.extra.append(lambda t, f, T, s=sign * size, at=at, keep=keep, tau=tau: s * (t - t[0] >= at) * (
                keep + (1.0 - keep) * np.exp(-np.clip(t - t[0] - at, 0.0, None) / tau)))
            return p
        seed, tau = int(rng.integers(2**31)), rng.uniform(60.0, 180.0)
        p.extra.append(lambda t, f, T, s=size, seed=seed, tau=tau: smoothed_walk(t, s, seed, tau))
        return p
    if effect == "resonance":
        f0 = rng.uniform(18.0, 45.0)
        zeta = float(np.interp(m, [0, 1], [0.06, 0.015])) * rng.uniform(0.8, 1.2)
        if shape == "dry_damped_mode":
            p.after.append(DryDampedMode(f0, zeta / 3, rng.uniform(0.003, 0.01) * span / 2 / FORCE_MAX_N))
            return p
        p.after.append(ThermallyTunedMode(f0, zeta, rng.uniform(0.01, 0.025)))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "ageing_stiction":
            growth, theta = rng.uniform(0.1, 0.3), rng.uniform(1.0, 5.0)
            p.before.append(ForcePath(lambda t, x, r=r * 1.3, g=growth, th=theta: ageing_stiction(t, x, r, g, th)))
            return p
        engage, width = rng.uniform(1.0, 4.0), rng.uniform(0.3, 1.0)

        def engaging_guide(t, x, r=r * 1.6, e=engage, w=width):
            band = r * 0.5 * (1.0 + np.tanh((x - e) / w))
            return band_play(x, band, band)
        p.before.append(ForcePath(engaging_guide))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.2, 0.5]))
        if shape == "fictive_temperature_shift":
            return Parts("burgers", FictiveShiftBurgers(c, b * 1.5, rng.uniform(20.0, 60.0), rng.uniform(0.2, 0.5),
                                                        rng.uniform(0.3, 0.7)), core_changed=True)
        logs = np.concatenate([[0.0], np.cumsum(3.0 * b * rng.uniform(0.5, 2.0, 4))])
        shift = interpolate.PchipInterpolator(T_REF_C + np.array([-6.0, -3.0, 0.0, 3.0, 6.0]), logs - logs[2])
        return Parts("burgers", ShiftedBurgers(c, lambda T, shift=shift: np.exp(shift(T)), flow_only=False),
                     core_changed=True)
    if effect == "excitation_ripple":
        g, hz = float(np.interp(m, [0, 1], [0.006, 0.016])), float(rng.choice([100.0, 120.0]))
        p.outer.append(ExcitationRipple(g, hz, rng.uniform(0, 2 * np.pi)))
        return p
    if effect == "clock_drift":
        p.outer.append(ClockDrift(float(np.interp(m, [0, 1], [1e-4, 5e-4]) * rng.choice([-1, 1]))))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["springpot_flow", "thixotropic_flow"],
    "delayed_elasticity": ["cascaded_kelvin", "activated_kelvin"],
    "hysteresis": ["lens_play_voltage", "pinched_bouc_wen_force"],
    "sensor_lag": ["windowed_sinc", "boxcar_pole"],
    "nonlinear_gain": ["s_cubic_inl", "spline_inl"],
    "thermal_drift": ["slab_zero", "asymmetric_lag_zero"],
    "thermal_sensitivity": ["span_slab", "span_dead_band"],
    "offset_drift": ["jump_and_recover", "smoothed_walk"],
    "resonance": ["dry_damped_mode", "thermally_tuned_mode"], "friction": ["ageing_stiction", "engaging_guide"],
    "thermo_rheological": ["fictive_temperature_shift", "tabulated_shift"],
}
PAIRS = (("viscous_flow", "delayed_elasticity"), ("sensor_lag", "resonance"), ("hysteresis", "friction"),
         ("nonlinear_gain", "thermal_sensitivity"), ("thermal_drift", "offset_drift"),
         ("delayed_elasticity", "thermo_rheological"))
OUTSIDE = ("excitation_ripple", "clock_drift")
RATES = (220.0, 520.0, 780.0, 1000.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split J", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.0e-3, 3.0e-3), jitter=0.3,
                   gap_s=(0.05, 3.0))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
