"""Independent split K for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split K is an untouched held-out set: written before the engine it measures, run once at its end, never used to
choose anything. Every name of the catalogue is hidden in two shapes that neither the registry's families
(``polyforce_ros/sim/truths.py``) nor splits A to J use:

* a dashpot whose viscosity falls from a low-force to a high-force plateau (the Cross model written in the force,
  Meter's form), or one that flows above a yield force as a power 1.4-2.5 of the excess (Herschel-Bulkley);
* creep of a water-swollen polymer draining (Terzaghi consolidation: the square root of time at first, then an
  exponential approach), or a Kelvin unit behind a dead time of 0.5-3 s (a creep that sets in late);
* a Jiles-Atherton loop on the bridge voltage (an irreversible state pinned behind a Langevin curve, locked after
  each reversal until the curve passes it again), or a flag-shaped loop on the force that opens only in a band of
  forces (strain-induced crystallisation that forms on loading and melts lower on unloading);
* a third-order elliptic (Cauer) low-pass, or a digital load cell's exponential average updated at a slower rate
  and linearly interpolated between updates;
* a gain that expands as the inverse of a neo-Hookean rubber's law (the stretch read for the force), or one with
  smooth knees at both ends of the range (bedding-in at the bottom, saturation at the top);
* a thermal zero that is periodic in temperature (an interferometric read-out), or the sawtooth left by a coarse
  compensation table without interpolation;
* a span that follows the temperature's gradient across the body (the temperature less its lag: the gauges and
  the compensating resistor apart), or a span whose temperature coefficient rises along the range;
* an offset that runs away (grows exponentially), or one that settles as a stretched exponential (an adhesive
  relaxing);
* a mode with a hardening cubic stiffness (Duffing), or a mode damped by a drag quadratic in its speed;
* Coulomb friction whose band grows as the load to the power 2/3 (the real contact area of a Hertzian contact),
  or a band that narrows as the force moves faster (velocity weakening along a Stribeck curve);
* a shift factor from two Arrhenius mechanisms in parallel, or an Arrhenius shift whose activation the load lowers
  (Eyring: the clock's temperature slope falls with the force).

It also holds six pairs, two effects outside the catalogue (readings frozen by a stalled bus, a zero that follows
the heat the polymer's own loss dissipates under cyclic load) and four clean records. Profiles: steps of a force
controller with overshoot, cycles whose amplitude grows and shrinks in a diamond, and the measured Okamura
insertion replayed at a speed that wanders (a hand-held needle; ``../shared/data``, a train of synthetic punctures
when it is absent). Rates 270, 580, 860 and 1000 Hz (a mode at 1000 Hz with knocks that excite it), 1-3 mV noise,
stamp jitter, gaps, a sensor that warms under its own excitation and is then cooled by a draught, with gusts.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_k.py [--json out.json] [--workers 2] [--stride 1] [--check]
"""
from __future__ import annotations

import math

import numpy as np
from scipy import integrate, interpolate, optimize, signal

from polyforce_ros.physics.expconv import exp_convolve
from polyforce_ros.physics.viscoelastic import Zener, simulate_deformation
from polyforce_ros.sim.truths import StaticMap
from split_kit import (ForcePath, LinearFilter, Parts, ShapeSplit, ShiftedBurgers, SimOnly, band_play, core_output,
                       dead_time, kelvin, repeated_insertions, uniform_grid)

SEED0 = 750_000  # never a seed of the registry's splits nor of splits A (90000..) to J (680000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 450.0


# ----------------------------------------------------------------------------- profiles and temperature

def controller_steps(duration_s, rate_hz, rng):
    """Steps of a force controller to random set points (one in five rest, else 0.5-7 N) held 3-25 s: its closed
    loop is a second-order response of 0.8-3 Hz with a damping ratio of 0.35-0.7 (an overshoot and a few swings),
    the force clipped at zero where the tool leaves contact and at 9 N."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    edges, levels, now = [0.0], [0.0], rng.uniform(3.0, 8.0)
    while now < duration_s:
        edges.append(now)
        levels.append(0.0 if rng.random() < 0.2 else rng.uniform(0.5, 7.0))
        now += rng.uniform(3.0, 25.0)
    set_point = np.asarray(levels)[np.searchsorted(edges, t, side="right") - 1]
    w, zeta = 2.0 * np.pi * rng.uniform(0.8, 3.0), rng.uniform(0.35, 0.7)
    b, a = signal.bilinear([w * w], [1.0, 2.0 * zeta * w, w * w], fs=rate_hz)
    return t, np.clip(signal.lfilter(b, a, set_point), 0.0, FORCE_MAX_N)


def diamond_sweeps(duration_s, rate_hz, rng):
    """Blocks of 30-80 s of a 0.2-1.2 Hz cycle (1 - cos) on a preload of 0-1 N, its peak growing linearly to 3-8 N
    above the preload at the block's middle and shrinking back (a diamond envelope), 5-20 s of rest between
    blocks."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    now = rng.uniform(3.0, 8.0)
    while now < duration_s:
        length = rng.uniform(30.0, 80.0)
        inside = (t >= now) & (t < now + length)
        s = t[inside] - now
        hz, peak, preload = rng.uniform(0.2, 1.2), rng.uniform(1.5, 4.0), rng.uniform(0.0, 1.0)
        envelope = peak * (1.0 - np.abs(2.0 * s / length - 1.0))
        fade = np.clip(np.minimum(s, length - s), 0.0, 1.0)
        f[inside] = preload * fade + envelope * (1.0 - np.cos(2.0 * np.pi * hz * s))
        now += length + rng.uniform(5.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def wandering_okamura(duration_s, rate_hz, rng):
    """The measured insertion replayed at a speed that wanders smoothly between 0.3 and 3x (a hand-held needle: the
    log of the speed a cubic spline through normal knots of spread 0.4-0.8, 0.3-1.5 s apart), each copy scaled to a
    2-9 N peak and repeated with 5-30 s of rest."""
    def wandering(tp, fp, rng):
        length = tp[-1] - tp[0]
        out_t = np.arange(0.0, 4.0 * length, 1.0 / rate_hz)
        step, spread = rng.uniform(0.3, 1.5), rng.uniform(0.4, 0.8)
        knots = np.arange(0.0, out_t[-1] + 2.0 * step, step)
        log_speed = interpolate.CubicSpline(knots, rng.normal(0.0, spread, knots.size))(out_t)
        source = np.cumsum(np.clip(np.exp(log_speed), 0.3, 3.0)) / rate_hz
        return np.interp(source[source <= length], tp - tp[0], fp)
    return repeated_insertions(duration_s, rate_hz, rng, wandering, FORCE_MAX_N)


PROFILES = (controller_steps, diamond_sweeps, wandering_okamura)


def temperature(t, rng):
    """A sensor warming under its own excitation, then caught in a draught: from 1-3 degC below 23 degC it warms by
    2-4 degC with a time constant of 60-150 s; at 35-65 % of the record a draught of 60-150 s cools it toward 2-4.5
    degC lower with a time constant of 10-30 s, and it recovers with 30-80 s once the draught stops; gusts of 0.1-0.3
    degC (a cubic spline through normal knots 5-20 s apart) ride on top."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    warm = rng.uniform(2.0, 4.0) * -np.expm1(-s / rng.uniform(60.0, 150.0))
    start, length, drop = rng.uniform(0.35, 0.65) * d, rng.uniform(60.0, 150.0), rng.uniform(2.0, 4.5)
    fall, rise = rng.uniform(10.0, 30.0), rng.uniform(30.0, 80.0)
    into = np.clip(s - start, 0.0, length)
    cool = drop * -np.expm1(-into / fall) * np.exp(-np.clip(s - start - length, 0.0, None) / rise)
    step = rng.uniform(5.0, 20.0)
    knots = np.arange(0.0, d + 2.0 * step, step)
    gusts = rng.uniform(0.1, 0.3) * interpolate.CubicSpline(knots, rng.normal(0.0, 1.0, knots.size))(s)
    return T_REF_C + rng.uniform(-3.0, -1.0) + warm - cool + gusts


# ----------------------------------------------------------------------------- simulate-only truth elements

class FlowZener(SimOnly):
    """A Zener core plus a dashpot whose flow rate is ``rate_of(F)`` (V/s)."""

    def __init__(self, zener, rate_of):
        self.zener, self.rate_of = zener, rate_of

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        return simulate_deformation(self.zener, t, f) + integrate.cumulative_trapezoid(self.rate_of(f), t, initial=0.0)


def langevin(s):
    """coth(s) - 1/s, by its series s/3 - s^3/45 near zero."""
    s = np.asarray(s, dtype=float)
    small = np.abs(s) < 1e-3
    safe = np.where(small, 1.0, s)
    return np.where(small, s / 3.0 - s ** 3 / 45.0, 1.0 / np.tanh(safe) - 1.0 / safe)


def jiles_atherton(u, centre, width, pinning):
    """The irreversible state of a Jiles-Atherton model driven by ``u``, less its anhysteretic curve
    L((u - centre) / width): the state moves toward the curve by a share 1 - exp(-|du| / pinning) of the gap while
    the input drives it that way, and stays locked otherwise (after a reversal, until the curve passes it again).
    From the curve at u[0]."""
    u = np.asarray(u, dtype=float)
    target = langevin((u - centre) / width)
    out, z, prev = np.empty_like(u), float(target[0]), float(u[0])
    for i, (ui, ti) in enumerate(zip(u.tolist(), target.tolist())):
        step = ui - prev
        if step * (ti - z) > 0.0:
            z += (ti - z) * -math.expm1(-abs(step) / pinning)
        prev = ui
        out[i] = z - ti
    return out


class JilesAthertonVoltage(SimOnly):
    """A Jiles-Atherton loop on the bridge voltage: y = x + w (z - L), z the irreversible state of
    :func:`jiles_atherton` on x / ``scale_v``; ``w`` opens the loop of a full 0-1-0 cycle of x / scale_v by
    ``opening_v`` at its widest."""

    def __init__(self, scale_v, centre, width, pinning, opening_v):
        self.scale, self.centre, self.width, self.pinning = scale_v, centre, width, pinning
        ref = np.concatenate([np.linspace(0.0, 1.0, 2001), np.linspace(1.0, 0.0, 2001)])
        loop = jiles_atherton(ref, centre, width, pinning)
        self.w = opening_v / max(float(np.max(np.abs(loop[:2001] - loop[2001:][::-1]))), 1e-12)

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        return x + self.w * jiles_atherton(x / self.scale, self.centre, self.width, self.pinning)


def crystallisation_flag(f, on_n, width_n, gap_n):
    """The crystallised share of a strain-crystallising polymer, less the middle of its band: on loading it rises
    to (F - on) / width once F passes ``on_n``; on unloading it melts to (F - on + gap) / width (``gap_n`` lower);
    in between it holds. A loop about the line, open only between on - gap and on + width. From the middle at
    f[0]."""
    low = np.clip((f - on_n) / width_n, 0.0, 1.0)
    high = np.clip((f - on_n + gap_n) / width_n, 0.0, 1.0)
    middle, half = (low + high) / 2.0, (high - low) / 2.0
    return band_play(middle, half, half) - middle


def elliptic_lowpass(delay_s, ripple_db, stop_db):
    """A third-order elliptic (Cauer) low-pass whose group delay at zero frequency is ``delay_s``: (num, den) in s."""
    b, a = signal.ellip(3, ripple_db, stop_db, 1.0, analog=True)
    w = np.array([1e-4, 2e-4])
    phase = np.unwrap(np.angle(signal.freqs(b, a, worN=w)[1]))
    unit_delay = -(phase[1] - phase[0]) / (w[1] - w[0])
    return signal.ellip(3, ripple_db, stop_db, unit_delay / delay_s, analog=True)


class DecimatedAverage(SimOnly):
    """A digital load cell's output: the input sampled every ``period_s`` into an exponential average of time
    constant ``tau_s``, each update shown one period late and linearly interpolated between updates; settled at
    x[0] before the record."""

    def __init__(self, period_s, tau_s):
        self.period, self.tau = period_s, tau_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        updates = np.arange(t[0], t[-1] + self.period, self.period)
        a = -math.expm1(-self.period / self.tau)
        average = signal.lfilter([a], [1.0, a - 1.0], np.interp(updates, t, x) - x[0]) + x[0]
        return np.interp(t, updates + self.period, average, left=x[0])


def neo_hookean_stretch(q):
    """The stretch lambda of a neo-Hookean rubber under the normalised force q: lambda - lambda^-2 = 3 q (Newton's
    method from 1 + q; q held above -0.3)."""
    q = np.maximum(np.asarray(q, dtype=float), -0.3)
    lam = 1.0 + q
    for _ in range(30):
        lam = lam - (lam - lam ** -2 - 3.0 * q) / (1.0 + 2.0 * lam ** -3)
    return lam


def smooth_ramp(u, corner):
    """max(u, 0) with a hyperbolic corner of half-width ``corner``."""
    return 0.5 * (u + np.sqrt(u * u + corner * corner))


class DuffingMode(SimOnly):
    """A light mode on the core's output whose spring hardens with its stretch, w^2 e (1 + (e / e_ref)^2), e the
    mode's lag behind the input (Duffing), integrated per sample (semi-implicit Euler, two sub-steps, on a uniform
    grid at the median step)."""

    def __init__(self, f0_hz, zeta, e_ref_v):
        self.f0, self.zeta, self.e_ref = f0_hz, zeta, e_ref_v

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        w = 2.0 * math.pi * self.f0
        w2, damp, inv_ref2, hs = w * w, 2.0 * self.zeta * w, 1.0 / self.e_ref ** 2, h / 2.0
        y, v, out = float(x[0]), 0.0, np.empty_like(tu)
        for i, xi in enumerate(xu.tolist()):
            for _ in range(2):
                e = xi - y
                v += hs * (w2 * e * (1.0 + e * e * inv_ref2) - damp * v)
                y += hs * v
            out[i] = y
        return np.interp(t, tu, out)


class DragDampedMode(SimOnly):
    """A mode on the core's output damped lightly by a viscous term (damping ratio ``zeta``) and by a drag quadratic
    in its speed that equals the viscous one at the speed w e_ref x ``ratio`` (a tip in a liquid): large ringing dies
    fast, its tail slowly. Semi-implicit Euler with the damping taken implicitly, two sub-steps, on a uniform grid at
    the median step."""

    def __init__(self, f0_hz, zeta, e_ref_v, ratio):
        self.f0, self.zeta, self.e_ref, self.ratio = f0_hz, zeta, e_ref_v, ratio

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        w = 2.0 * math.pi * self.f0
        w2, damp, hs = w * w, 2.0 * self.zeta * w, h / 2.0
        drag = damp / (w * self.e_ref * self.ratio)
        y, v, out = float(x[0]), 0.0, np.empty_like(tu)
        for i, xi in enumerate(xu.tolist()):
            for _ in range(2):
                v = (v + hs * w2 * (xi - y)) / (1.0 + hs * (damp + drag * abs(v)))
                y += hs * v
            out[i] = y
        return np.interp(t, tu, out)


class StressShiftedBurgers(SimOnly):
    """A Burgers core on the reduced time of the shift exp(b dT (1 - c F / F_max)): an Arrhenius clock whose
    activation the load lowers (Eyring), so that its slope in temperature falls as the force rises."""

    def __init__(self, c, b_per_c, c_share):
        self.c, self.b, self.share = c, b_per_c, c_share

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        temp = np.broadcast_to(np.asarray(aux["temperature_c"], dtype=float), t.shape)
        load = np.clip(f / FORCE_MAX_N, 0.0, 1.0)
        rate = np.exp(self.b * (temp - T_REF_C) * (1.0 - self.share * load))
        return simulate_deformation(self.c, integrate.cumulative_trapezoid(rate, t, initial=0.0), f)


class FrozenReadings(SimOnly):
    """A bus that stalls: in each window (start as a share of the record, length in s) the reading stays at the last
    one before it."""

    def __init__(self, windows):
        self.windows = windows

    def forward(self, t_s, x, aux=None, state=None):
        t, y = np.asarray(t_s, dtype=float), np.array(x, dtype=float)
        for share, length in self.windows:
            start = t[0] + share * (t[-1] - t[0])
            inside = np.flatnonzero((t >= start) & (t < start + length))
            if inside.size:
                y[inside] = y[max(inside[0] - 1, 0)]
        return y


def consolidation_creep(t, f, compliance_v_per_n, tau_s, modes=40):
    """Creep of a draining (poroelastic) layer, Terzaghi's average degree of consolidation: Kelvin units of
    4 tau / ((2n + 1)^2 pi^2) weighted 8 / ((2n + 1)^2 pi^2) (to a unit sum) for n = 0 .. modes - 1; from rest."""
    odd = 2.0 * np.arange(modes) + 1.0
    weights = 8.0 / (odd * np.pi) ** 2
    rates = (odd * np.pi) ** 2 / (4.0 * tau_s)
    return exp_convolve(t, f, rates) @ (compliance_v_per_n * weights / weights.sum() * rates)


def velocity_weakening_band(t, f, r_static_n, kinetic_share, speed_n_per_s):
    """A friction band that narrows as the force moves faster, r (k + (1 - k) exp(-(v / v_s)^2)), v the force's rate
    smoothed over 50 ms (a Stribeck curve: the contact enters mixed lubrication)."""
    speed = kelvin(t, np.abs(np.gradient(f, t)), 1.0, 0.05)
    band = r_static_n * (kinetic_share + (1.0 - kinetic_share) * np.exp(-(speed / speed_n_per_s) ** 2))
    return band_play(f, band, band)


def dissipated_heat(t, f, tau_s):
    """The polymer's own warming by its loss under cyclic load: |F dF/dt| (N^2/s) through a lag of ``tau_s``."""
    return kelvin(t, np.abs(f * np.gradient(f, t)), 1.0, tau_s)


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    span = FORCE_MAX_N / c.relaxation().g0_n_per_v * 2.0  # ~ the core's output over the force range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([8e4, 4e3]))))
        zener = Zener(c.k1_n_per_v, c.k2_n_per_v, c.eta2_n_s_per_v)
        if shape == "meter_flow":
            eta0, ratio, f_c, n = 2.0 / phi, rng.uniform(4.0, 10.0), rng.uniform(2.0, 5.0), rng.uniform(2.0, 3.0)
            return Parts("zener", FlowZener(zener, lambda f, e0=eta0, r=ratio, fc=f_c, n=n: f / (
                e0 / r + (e0 - e0 / r) / (1.0 + (np.abs(f) / fc) ** n))), core_changed=True)
        yield_n, power, f0 = rng.uniform(0.3, 1.5), 1.0 / rng.uniform(0.4, 0.7), 4.0
        return Parts("zener", FlowZener(zener, lambda f, phi=3.0 * phi, fy=yield_n, q=power, f0=f0: phi * f0 * (
            np.clip(f - fy, 0.0, None) / f0) ** q), core_changed=True)
    if effect == "delayed_elasticity":
        total = float(np.interp(m, [0, 1], [1 / 60.0, 1 / 6.0]))  # added compliance, V/N
        if shape == "consolidation_creep":
            tau = rng.uniform(5.0, 60.0)
            p.extra.append(lambda t, f, T, k=total, tau=tau: consolidation_creep(t, f, k, tau))
            return p
        delay, tau = rng.uniform(0.5, 3.0), rng.uniform(3.0, 30.0)
        p.extra.append(lambda t, f, T, k=total, d=delay, tau=tau: kelvin(t, dead_time(t, f, d), k, tau))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.02, 0.07]))
        if shape == "jiles_atherton_voltage":
            p.after.append(JilesAthertonVoltage(span / 2, rng.uniform(0.0, 0.4), rng.uniform(0.2, 0.5),
                                                rng.uniform(0.05, 0.15), frac * span))
            return p
        on, width, gap = rng.uniform(2.5, 4.5), rng.uniform(2.0, 3.5), rng.uniform(1.5, 2.5)
        size = 2.0 * frac * FORCE_MAX_N * width / min(gap, width)  # the loop opens by 2 frac F_max at its widest
        p.before.append(ForcePath(lambda t, x, s=size, on=on, w=width, g=gap: x + s * crystallisation_flag(
            x, on, w, g)))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.01, 0.12]))))
        if shape == "elliptic3":
            p.after.append(LinearFilter(*elliptic_lowpass(delay, rng.uniform(0.2, 1.0), rng.uniform(30.0, 45.0))))
            return p
        share = rng.uniform(0.3, 0.6)
        p.after.append(DecimatedAverage(share * delay, (1.0 - share) * delay))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.02, 0.08]))
        top = span / 2 * rng.uniform(1.0, 1.5)
        if shape == "neo_hookean_stretch":
            q_top = optimize.brentq(lambda q, r=rel: (float(neo_hookean_stretch(q)) - 1.0) / q - 1.0 - 2.0 * r,
                                    1e-6, 5.0)  # 1 + 2 rel times the linear output at the top
            p.after.append(StaticMap(lambda x, top=top, q=q_top: top * (neo_hookean_stretch(q * x / top) - 1.0) / q))
            return p
        low, high, corner = rng.uniform(0.1, 0.25) * top, rng.uniform(0.65, 0.85) * top, 0.05 * top
        c_low, c_high = rel * top / low, 1.5 * rel * top / (top - high)
        p.after.append(StaticMap(lambda x, lo=low, hi=high, e=corner, a=c_low, b=c_high: x + a * (
            smooth_ramp(lo - x, e) - smooth_ramp(lo, e)) - b * (smooth_ramp(x - hi, e) - smooth_ramp(-hi, e))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.02]) * rng.choice([-1, 1]))
        if shape == "periodic_zero":
            period, phase = rng.uniform(12.0, 20.0), rng.uniform(-0.8, 0.8)
            p.extra.append(lambda t, f, T, k=1.3 * k, P=period, ph=phase: k * P / (2 * np.pi) * (
                np.sin(2 * np.pi * (T - T_REF_C) / P + ph) - np.sin(ph)))
            return p
        step, rest, node = rng.uniform(0.8, 1.5), rng.uniform(0.4, 0.7), rng.uniform(0.0, 1.0)

        def table_residual(t, f, T, k=k, step=step, rest=rest, node=node):
            v = (T - T_REF_C) / step + node
            return k * (rest * (T - T_REF_C) + step * (v - np.round(v)))
        p.extra.append(table_residual)
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.002, 0.01]) * rng.choice([-1, 1]))
        out = core_output(c)
        if shape == "span_gradient":
            tau = rng.uniform(20.0, 60.0)
            p.extra.append(lambda t, f, T, a=a, tau=tau, out=out: 8.0 * a * (T - T[0] - kelvin(t, T - T[0], 1.0, tau))
                           * out(t, f))
            return p
        p.extra.append(lambda t, f, T, a=a, top=span / 2, out=out: 7.0 * a * (T - T_REF_C) * out(t, f) ** 2 / top)
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.08]))
        sign = rng.choice([-1, 1])
        if shape == "runaway":
            tau = rng.uniform(0.15, 0.35) * DURATION_S
            p.extra.append(lambda t, f, T, s=sign * size, tau=tau: s * np.expm1((t - t[0]) / tau)
                           / np.expm1(DURATION_S / tau))
            return p
        tau, beta = rng.uniform(40.0, 200.0), rng.uniform(0.4, 0.7)
        p.extra.append(lambda t, f, T, s=sign * size, tau=tau, b=beta: s * -np.expm1(-((t - t[0]) / tau) ** b)
                       / -np.expm1(-(DURATION_S / tau) ** b))
        return p
    if effect == "resonance":
        f0 = rng.uniform(18.0, 45.0)
        zeta = float(np.interp(m, [0, 1], [0.06, 0.015])) * rng.uniform(0.8, 1.2)
        e_ref = span / 2 / FORCE_MAX_N * rng.uniform(0.5, 1.5)  # the mode's stretch under 0.5-1.5 N
        if shape == "duffing_mode":
            p.after.append(DuffingMode(f0, zeta, e_ref))
            return p
        p.after.append(DragDampedMode(f0, zeta / 2, e_ref, rng.uniform(1.0, 3.0)))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "hertzian_band":
            floor = rng.uniform(0.1, 0.2)

            def hertzian(t, x, r=r * 1.3, floor=floor):
                band = r * (floor + (1.0 - floor) * (np.clip(x, 0.0, None) / (FORCE_MAX_N / 2)) ** (2.0 / 3.0))
                return band_play(x, band, band)
            p.before.append(ForcePath(hertzian))
            return p
        kinetic, speed = rng.uniform(0.3, 0.6), rng.uniform(0.5, 3.0)
        p.before.append(ForcePath(lambda t, x, r=r * 1.6, k=kinetic, v=speed: velocity_weakening_band(t, x, r, k, v)))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.2, 0.5]))
        if shape == "two_mechanism_shift":
            share = rng.uniform(0.4, 0.8)
            slow = 1.5 * b / (share + 3.0 * (1.0 - share))  # the slope at the reference is 1.5 b
            return Parts("burgers", ShiftedBurgers(c, lambda T, w=share, b1=slow: w * np.exp(b1 * (T - T_REF_C)) + (
                1.0 - w) * np.exp(3.0 * b1 * (T - T_REF_C)), flow_only=False), core_changed=True)
        return Parts("burgers", StressShiftedBurgers(c, 1.5 * b, rng.uniform(0.3, 0.6)), core_changed=True)
    if effect == "frozen_readings":
        n = int(np.interp(m, [0, 1], [6.0, 20.0])) + int(rng.integers(0, 3))
        p.outer.append(FrozenReadings(list(zip(rng.uniform(0.02, 0.98, n).tolist(),
                                               rng.uniform(0.3, 2.5, n).tolist()))))
        return p
    if effect == "dissipative_self_heating":
        k = float(np.interp(m, [0, 1], [3e-3, 1e-2]) * rng.choice([-1, 1]))  # V per N^2/s
        tau = rng.uniform(20.0, 60.0)
        p.extra.append(lambda t, f, T, k=k, tau=tau: k * dissipated_heat(t, f, tau))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["meter_flow", "herschel_bulkley_flow"],
    "delayed_elasticity": ["consolidation_creep", "delayed_onset_kelvin"],
    "hysteresis": ["jiles_atherton_voltage", "crystallisation_flag_force"],
    "sensor_lag": ["elliptic3", "decimated_average"],
    "nonlinear_gain": ["neo_hookean_stretch", "double_knee"],
    "thermal_drift": ["periodic_zero", "table_residual_zero"],
    "thermal_sensitivity": ["span_gradient", "span_rising_tc"],
    "offset_drift": ["runaway", "stretched_exponential_settle"],
    "resonance": ["duffing_mode", "drag_damped_mode"], "friction": ["hertzian_band", "velocity_weakening_band"],
    "thermo_rheological": ["two_mechanism_shift", "stress_lowered_activation"],
}
PAIRS = (("viscous_flow", "sensor_lag"), ("hysteresis", "resonance"), ("friction", "nonlinear_gain"),
         ("thermal_drift", "thermal_sensitivity"), ("offset_drift", "viscous_flow"),
         ("thermo_rheological", "thermal_drift"))
OUTSIDE = ("frozen_readings", "dissipative_self_heating")
RATES = (270.0, 580.0, 860.0, 1000.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split K", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.0e-3, 3.0e-3), jitter=0.3,
                   gap_s=(0.05, 3.0))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
