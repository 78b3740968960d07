"""Independent split L for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split L is an untouched held-out set: written before the engine it measures, blind to how it works, run once at its
end, never used to choose anything. Every name of the catalogue is hidden in two shapes that neither the registry's
families (``polyforce_ros/sim/truths.py``) nor splits A to K use:

* a fluid-filled cell leaking through an orifice (a flow as the square root of the force, Torricelli), or a flow
  that accelerates as damage accumulates under load (Kachanov-Rabotnov tertiary creep);
* a fractional Kelvin-Voigt unit (a spring beside a springpot of order 0.6-0.85: Mittag-Leffler creep from a Cole-Cole
  spectrum cut at 300 tau or 2000 s), or a Kelvin unit whose dashpot is a power 1.7-2.3 of its force (a fast start, an
  algebraic tail);
* Rayleigh-law loops on the force before the core (parabolic branches from each reversal, Madelung return-point
  memory, less their tip curve), or Berg's rate-independent rubber friction on the bridge voltage (hyperbolic
  approach to its bound after each reversal);
* a causal running median of 20-240 ms (an outlier-rejecting DAQ), or a weighing indicator's motion-adaptive average
  (slow inside a band about its output, eight times faster outside it);
* the compressive non-linearity of a quarter bridge, x / (1 + x / s), or an expansive exponential gain (tunnelling
  conduction in a piezoresistive composite);
* a zero led by the temperature (the thermometer lags the gauges by a first-order lag of 15-60 s: the zero follows the
  reading plus tau times its rate), or a zero behind a thermal lag whose conductance grows with the load (a contact
  that conducts heat better when pressed);
* a span that follows a causal boxcar average of the temperature over 30-120 s, or a span that follows a body whose
  temperature can change at most 0.003-0.01 degC/s (a slew-limited heat flux);
* an offset that approaches its end value hyperbolically (Langmuir sorption, t / (t + tau)), or an amplifier's flicker
  (1/f) noise below 0.03 Hz;
* a mode whose spring is bilinear (1.5-3x stiffer one way: a contact that opens in its swing), or a mode whose damping
  rises with the load (a damping pad squeezed by the force);
* Coulomb friction whose band grows with the force travelled (galling), or a band that wanders in time (particles in
  the guide: a smooth random factor, 10-40 s correlation);
* a core in three layers in series, each on the clock of its own lagged temperature (2-8, 20-60, 100-250 s), or an
  Arrhenius clock 1.5-3x faster once a secondary phase melts (melting and recrystallising with thermal hysteresis).

It also holds six pairs, two effects outside the catalogue (shunt-calibration pulses switched onto the bridge,
electrostatic discharge transients that decay in 0.5-3 s) and four clean records. Profiles: a teleoperator's holds
reached by minimum-jerk moves with a wobble of the hand, stepped-sine frequency-response sweeps up or down on a new mean
each time, and a needle array (2-4 copies of the measured Okamura insertion, each needle 0.3-3 s behind the previous;
``../shared/data``, a train of synthetic punctures when it is absent). Rates 310, 540, 920 and 1000 Hz (a mode at 1000
Hz with knocks that excite it), 1-3 mV noise, stamp jitter, gaps, a sensor taken out of a cold store (3-5 degC below the
room, warming through two time constants) that an operator's hand warms now and then.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_l.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import math

import numpy as np
from scipy import integrate, interpolate, ndimage, optimize

from polyforce_ros.physics.expconv import exp_convolve
from polyforce_ros.physics.viscoelastic import Burgers, Zener, simulate_deformation
from polyforce_ros.sim.truths import StaticMap
from split_kit import (ForcePath, Parts, ShapeSplit, ShiftedBurgers, SimOnly, band_play, core_output, kelvin,
                       repeated_insertions, uniform_grid)

SEED0 = 820_000  # never a seed of the registry's splits nor of splits A (90000..) to K (750000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 480.0


# ----------------------------------------------------------------------------- profiles and temperature

def teleoperator_holds(duration_s, rate_hz, rng):
    """A teleoperator pressing through a haptic master: set points (one in seven a release to zero, else 0.5-7.5 N)
    reached by minimum-jerk moves of 0.4-2.5 s and held 2-30 s, with the hand's wobble on top (a cubic spline through
    normal knots 1-4 s apart, 0.05-0.25 N), faded out near zero force."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    starts, moves, levels, now = [], [], [0.0], rng.uniform(2.0, 6.0)
    while now < duration_s:
        starts.append(now)
        moves.append(rng.uniform(0.4, 2.5))
        levels.append(0.0 if rng.random() < 1.0 / 7.0 else rng.uniform(0.5, 7.5))
        now += moves[-1] + rng.uniform(2.0, 30.0)
    starts, moves, levels = np.asarray(starts), np.asarray(moves), np.asarray(levels)
    k = np.searchsorted(starts, t, side="right") - 1
    inside = k >= 0
    kk = np.maximum(k, 0)
    u = np.clip((t - starts[kk]) / moves[kk], 0.0, 1.0)
    jerk = u ** 3 * (10.0 - 15.0 * u + 6.0 * u * u)
    f = np.where(inside, levels[kk] + (levels[kk + 1] - levels[kk]) * jerk, 0.0)
    step = rng.uniform(1.0, 4.0)
    knots = np.arange(0.0, duration_s + 2.0 * step, step)
    wobble = rng.uniform(0.05, 0.25) * interpolate.CubicSpline(knots, rng.normal(0.0, 1.0, knots.size))(t)
    return t, np.clip(f + wobble * np.clip(f / 0.5, 0.0, 1.0), 0.0, FORCE_MAX_N)


def stepped_sine(duration_s, rate_hz, rng):
    """Frequency-response sweeps: on a mean of 2-5 N (reached and left by 2 s raised-cosine ramps) a sine of 0.4-0.85
    of the room to the range's ends dwells at each of 7-11 log-spaced frequencies from 0.04-0.1 Hz to 2-6 Hz (whole
    cycles, at least two and 5 s), upward or downward at random; 5-20 s of rest between sweeps."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    now = rng.uniform(3.0, 8.0)
    while now < duration_s:
        mean = rng.uniform(2.0, 5.0)
        amp = rng.uniform(0.4, 0.85) * min(mean, 8.5 - mean)
        freqs = np.geomspace(rng.uniform(0.04, 0.1), rng.uniform(2.0, 6.0), int(rng.integers(7, 12)))
        if rng.random() < 0.5:
            freqs = freqs[::-1]
        ramp = (t >= now) & (t < now + 2.0)
        f[ramp] = mean * 0.5 * (1.0 - np.cos(np.pi * (t[ramp] - now) / 2.0))
        now += 2.0
        for hz in freqs:
            dwell = math.ceil(max(2.0 / hz, 5.0) * hz) / hz
            seg = (t >= now) & (t < now + dwell)
            f[seg] = mean + amp * np.sin(2.0 * np.pi * hz * (t[seg] - now))
            now += dwell
        ramp = (t >= now) & (t < now + 2.0)
        f[ramp] = mean * 0.5 * (1.0 + np.cos(np.pi * (t[ramp] - now) / 2.0))
        now += 2.0 + rng.uniform(5.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def needle_array(duration_s, rate_hz, rng):
    """A needle array: 2-4 copies of the measured insertion, each needle entering 0.3-3 s after the one before and
    scaled by 0.5-1 (its own depth), summed; each array insertion scaled to a 2-9 N peak and repeated with 5-30 s of
    rest."""
    def array(tp, fp, rng):
        h = float(tp[1] - tp[0])
        lags = np.concatenate([[0.0], np.cumsum(rng.uniform(0.3, 3.0, int(rng.integers(1, 4))))])
        out = np.zeros(fp.size + int(lags[-1] / h) + 1)
        for lag in lags:
            i0 = int(lag / h)
            out[i0:i0 + fp.size] += rng.uniform(0.5, 1.0) * fp
        return out
    return repeated_insertions(duration_s, rate_hz, rng, array, FORCE_MAX_N)


PROFILES = (teleoperator_holds, stepped_sine, needle_array)


def temperature(t, rng):
    """A sensor taken out of a cold store: from 3-5 degC below a room of 22.5-24 degC it warms through two time
    constants (20-60 s for its housing, 150-400 s for its body, a share of 0.3-0.7 on the first); an operator's hand
    warms it 2-5 times by 0.3-1 degC (rising in 5-20 s, fading in 30-120 s)."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    room, cold, share = T_REF_C + rng.uniform(-0.5, 1.0), rng.uniform(3.0, 5.0), rng.uniform(0.3, 0.7)
    temp = room - cold * (share * np.exp(-s / rng.uniform(20.0, 60.0))
                          + (1.0 - share) * np.exp(-s / rng.uniform(150.0, 400.0)))
    for _ in range(int(rng.integers(2, 6))):
        at, amp = rng.uniform(0.05, 0.9) * d, rng.uniform(0.3, 1.0)
        rise, fade = rng.uniform(5.0, 20.0), rng.uniform(30.0, 120.0)
        u = np.clip(s - at, 0.0, None)
        peak_at = math.log(fade / rise) * rise * fade / (fade - rise)
        temp = temp + amp * (np.exp(-u / fade) - np.exp(-u / rise)) / (math.exp(-peak_at / fade) - math.exp(-peak_at / rise))
    return temp


# ----------------------------------------------------------------------------- simulate-only truth elements

class FlowCore(SimOnly):
    """A Zener core plus a dashpot whose flow rate is ``rate_of(F)`` (V/s)."""

    def __init__(self, zener, rate_of):
        self.zener, self.rate_of = zener, rate_of

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        return simulate_deformation(self.zener, t, f) + integrate.cumulative_trapezoid(self.rate_of(f), t, initial=0.0)


class DamagedFlow(SimOnly):
    """A Zener core plus a dashpot phi F / (1 - D)^n whose damage D grows as dD/dt = (F / f_ref)^2 / (t_r (1 - D)^2)
    (Kachanov-Rabotnov, integrated in closed form, D held below 0.4): the flow accelerates under load."""

    def __init__(self, zener, phi, t_r_s, f_ref_n, n):
        self.zener, self.phi, self.t_r, self.f_ref, self.n = zener, phi, t_r_s, f_ref_n, n

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        omega = integrate.cumulative_trapezoid((f / self.f_ref) ** 2 / self.t_r, t, initial=0.0)
        intact = np.clip(1.0 - 3.0 * omega, 0.6 ** 3, 1.0) ** (1.0 / 3.0)  # 1 - D
        rate = self.phi * f / intact ** self.n
        return simulate_deformation(self.zener, t, f) + integrate.cumulative_trapezoid(rate, t, initial=0.0)


def cole_cole_creep(t, f, compliance_v_per_n, tau_s, alpha, points=32, longest_s=2000.0):
    """Creep of a fractional Kelvin-Voigt unit, c (1 - E_alpha(-(t / tau)^alpha)): Kelvin units on the Cole-Cole
    spectrum sin(alpha pi) / pi / ((u / tau)^alpha + (u / tau)^-alpha + 2 cos(alpha pi)) over log u, from tau / 1000 to
    min(300 tau, ``longest_s``), weights to a unit sum; from rest."""
    ln_u = np.linspace(math.log(tau_s * 1e-3), math.log(min(tau_s * 10 ** 2.5, longest_s)), points)
    z = alpha * (ln_u - math.log(tau_s))
    weights = math.sin(alpha * math.pi) / math.pi / (np.exp(z) + np.exp(-z) + 2.0 * math.cos(alpha * math.pi))
    weights /= weights.sum()
    rates = np.exp(-ln_u)
    return exp_convolve(t, f, rates) @ (compliance_v_per_n * weights * rates)


def power_dashpot_kelvin(t, f, compliance_v_per_n, tau_s, power, f_ref_n=4.0):
    """A Kelvin unit whose dashpot moves as a power of its force: x' = sign(g) |g|^p / K, g = c F - x, K set so that
    the local time constant is ``tau_s`` at g = c ``f_ref_n``; each step solved exactly for the mean force of the
    step; from rest."""
    k = tau_s * power * (compliance_v_per_n * f_ref_n) ** (power - 1.0)
    one = 1.0 - power
    out, x = np.zeros_like(f), 0.0
    tl, fl = t.tolist(), f.tolist()
    for i in range(1, len(tl)):
        g = compliance_v_per_n * 0.5 * (fl[i] + fl[i - 1]) - x
        if g != 0.0:
            left = (abs(g) ** one + (power - 1.0) * (tl[i] - tl[i - 1]) / k) ** (1.0 / one)
            x += g - math.copysign(left, g)
        out[i] = x
    return out


def rayleigh_loops(x, b):
    """Rayleigh-law hysteresis of ``x`` less its tip curve: from each reversal (x_r, y_r) the branch
    y = y_r + d b / 2 (x - x_r)^2 (d the direction), closed minor loops wiped out (Madelung), the virgin curve from
    x[0]; returns y - b / 2 (x - x0) |x - x0|, zero on the virgin curve, the loops' opening b X^2 / 4 for a cycle of
    amplitude X from its bottom."""
    x0 = float(x[0])
    sx, sy = [x0], [0.0]
    d, prev, y = 0, x0, 0.0
    out = np.empty_like(x)
    for i, xi in enumerate(x.tolist()):
        step = xi - prev
        if step != 0.0:
            nd = 1 if step > 0.0 else -1
            if d and nd != d:
                sx.append(prev)
                sy.append(y)
            d = nd
            while len(sx) >= 3 and d * (xi - sx[-2]) >= 0.0:
                del sx[-2:], sy[-2:]
            y = sy[-1] + d * 0.5 * b * (xi - sx[-1]) ** 2
        prev = xi
        out[i] = y
    return out - 0.5 * b * (x - x0) * np.abs(x - x0)


def berg_friction(x, x2, f_max):
    """Berg's rate-independent friction driven by ``x``: after a reversal at (x_s, F_s) it approaches +-f_max as
    F_s + (x - x_s) / (x2 (1 - d a) + d (x - x_s)) (f_max - d F_s), a = F_s / f_max; from zero."""
    xs, fs, d, prev, fr = float(x[0]), 0.0, 0, float(x[0]), 0.0
    out = np.empty_like(x)
    for i, xi in enumerate(x.tolist()):
        step = xi - prev
        if step != 0.0:
            nd = 1 if step > 0.0 else -1
            if d and nd != d:
                xs, fs = prev, min(max(fr, -0.999 * f_max), 0.999 * f_max)
            d = nd
            u = xi - xs
            fr = fs + u / (x2 * (1.0 - d * fs / f_max) + d * u) * (f_max - d * fs)
        prev = xi
        out[i] = fr
    return out


class BergVoltage(SimOnly):
    """Berg's friction loop added to the bridge voltage: y = x + F_berg(x)."""

    def __init__(self, x2_v, f_max_v):
        self.x2, self.f_max = x2_v, f_max_v

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        return x + berg_friction(x, self.x2, self.f_max)


class CausalMedian(SimOnly):
    """A running median over the last ``window_s`` (an odd number of samples of a uniform grid at the median step)."""

    def __init__(self, window_s):
        self.window = window_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        n = max(3, int(round(self.window / h)) | 1)
        return np.interp(t, tu, ndimage.median_filter(xu, size=n, origin=n // 2, mode="nearest"))


class MotionAdaptiveAverage(SimOnly):
    """A weighing indicator's filter: an exponential average of time constant ``tau_s`` while the input stays within
    ``band_v`` of the output, ``tau_s`` / 8 outside it; on a uniform grid at the median step, settled at x[0]."""

    def __init__(self, tau_s, band_v):
        self.tau, self.band = tau_s, band_v

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        slow, fast = -math.expm1(-h / self.tau), -math.expm1(-8.0 * h / self.tau)
        y, out = float(xu[0]), np.empty_like(xu)
        for i, xi in enumerate(xu.tolist()):
            e = xi - y
            y += e * (slow if abs(e) < self.band else fast)
            out[i] = y
        return np.interp(t, tu, out)


def load_lagged_temperature(t, f, temp, tau_s, gain):
    """The temperature behind a lag whose time constant is ``tau_s`` / (1 + gain F / F_max) (a contact that conducts
    heat better when pressed); exact per step for the step's own constant; from temp[0]."""
    tl, fl, tp = t.tolist(), np.clip(np.asarray(f) / FORCE_MAX_N, 0.0, 1.0).tolist(), np.asarray(temp).tolist()
    y, out = tp[0], np.empty(len(tl))
    out[0] = y
    for i in range(1, len(tl)):
        y += (tp[i] - y) * -math.expm1(-(tl[i] - tl[i - 1]) * (1.0 + gain * fl[i]) / tau_s)
        out[i] = y
    return out


def boxcar_temperature(t, temp, window_s):
    """The mean of the temperature over the last ``window_s`` (over what there is at the start)."""
    area = integrate.cumulative_trapezoid(temp, t, initial=0.0)
    start = np.maximum(t - window_s, t[0])
    width = t - start
    mean = (area - np.interp(start, t, area)) / np.where(width > 0, width, 1.0)
    return np.where(width > 0, mean, temp[0])


def slew_limited(t, temp, rate_c_per_s):
    """A temperature that follows ``temp`` at most at ``rate_c_per_s``; from temp[0]."""
    tl, tp = t.tolist(), np.asarray(temp).tolist()
    y, out = tp[0], np.empty(len(tl))
    out[0] = y
    for i in range(1, len(tl)):
        limit = rate_c_per_s * (tl[i] - tl[i - 1])
        y += min(max(tp[i] - y, -limit), limit)
        out[i] = y
    return out


def flicker(rng, size_v, corner_hz=0.03, step_s=1.0):
    """A 1/f (flicker) noise below ``corner_hz`` on a grid of ``step_s`` over the record, of RMS ``size_v`` / 2.5,
    from zero; returns a function of the time since the first sample."""
    grid = np.arange(0.0, DURATION_S + 60.0, step_s)
    hz = np.fft.rfftfreq(grid.size, step_s)
    shape = np.where((hz > 0) & (hz <= corner_hz), 1.0 / np.sqrt(np.maximum(hz, 1e-12)), 0.0)
    noise = np.fft.irfft(shape * (rng.normal(size=hz.size) + 1j * rng.normal(size=hz.size)), grid.size)
    noise = size_v / 2.5 * (noise - noise[0]) / noise.std()
    return lambda s: np.interp(s, grid, noise)


def smooth_random(rng, correlation_s):
    """A smooth random function of time (a cubic spline through unit normal knots ``correlation_s`` apart)."""
    knots = np.arange(0.0, DURATION_S + 2.0 * correlation_s + 60.0, correlation_s)
    return interpolate.CubicSpline(knots, rng.normal(0.0, 1.0, knots.size))


class BilinearMode(SimOnly):
    """A light mode on the core's output whose spring is ``ratio`` times stiffer while its lag behind the input is
    negative (a contact that opens in its swing); semi-implicit Euler, two sub-steps, on a uniform grid at the median
    step."""

    def __init__(self, f0_hz, zeta, ratio):
        self.f0, self.zeta, self.ratio = f0_hz, zeta, ratio

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        w = 2.0 * math.pi * self.f0
        soft, stiff, damp, hs = w * w, w * w * self.ratio, 2.0 * self.zeta * w, h / 2.0
        y, v, out = float(xu[0]), 0.0, np.empty_like(xu)
        for i, xi in enumerate(xu.tolist()):
            for _ in range(2):
                e = xi - y
                v = (v + hs * (soft if e >= 0.0 else stiff) * e) / (1.0 + hs * damp)
                y += hs * v
            out[i] = y
        return np.interp(t, tu, out)


class LoadDampedMode(SimOnly):
    """A light mode on the core's output whose damping ratio grows as zeta (1 + gain clip(x / top, 0, 1)) (a damping
    pad squeezed by the load); semi-implicit Euler with the damping implicit, two sub-steps, on a uniform grid."""

    def __init__(self, f0_hz, zeta, gain, top_v):
        self.f0, self.zeta, self.gain, self.top = f0_hz, zeta, gain, top_v

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        w = 2.0 * math.pi * self.f0
        w2, hs = w * w, h / 2.0
        damp = 2.0 * self.zeta * w * (1.0 + self.gain * np.clip(xu / self.top, 0.0, 1.0))
        y, v, out = float(xu[0]), 0.0, np.empty_like(xu)
        for i, (xi, di) in enumerate(zip(xu.tolist(), damp.tolist())):
            for _ in range(2):
                v = (v + hs * w2 * (xi - y)) / (1.0 + hs * di)
                y += hs * v
            out[i] = y
        return np.interp(t, tu, out)


class LayeredShiftCore(SimOnly):
    """A Burgers core in three equal layers in series, each on the reduced time of exp(b (T_i - T_ref)), T_i the
    temperature behind the layer's own lag (the body warms from its skin to its middle)."""

    def __init__(self, c, b_per_c, lags_s):
        self.layer = Burgers(3.0 * c.k1_n_per_v, 3.0 * c.k2_n_per_v, 3.0 * c.eta1_n_s_per_v, 3.0 * c.eta2_n_s_per_v)
        self.b, self.lags = b_per_c, lags_s

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        temp = np.broadcast_to(np.asarray(aux["temperature_c"], dtype=float), t.shape)
        out = np.zeros_like(t)
        for lag in self.lags:
            inner = temp[0] + kelvin(t, temp - temp[0], 1.0, lag)
            xi = integrate.cumulative_trapezoid(np.exp(self.b * (inner - T_REF_C)), t, initial=0.0)
            out += simulate_deformation(self.layer, xi, f)
        return out


def melting_clock(b_per_c, onset_c, width_c, half_gap_c, boost):
    """The rate exp(b dT) (1 + boost phi), phi the molten share of a secondary phase: clip((p - onset) / width, 0, 1)
    with p the temperature through a play of ``half_gap_c`` (it melts warmer than it recrystallises)."""
    def rate(temp):
        temp = np.asarray(temp, dtype=float)
        molten = np.clip((band_play(temp, half_gap_c, half_gap_c) - onset_c) / width_c, 0.0, 1.0)
        return np.exp(b_per_c * (temp - T_REF_C)) * (1.0 + boost * molten)
    return rate


def pulses(s, starts, widths, edge_s=0.005):
    """Unit rectangular pulses with linear edges of ``edge_s``."""
    out = np.zeros_like(s)
    for a, w in zip(starts, widths):
        out += np.clip((s - a) / edge_s, 0.0, 1.0) - np.clip((s - a - w) / edge_s, 0.0, 1.0)
    return out


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    span = FORCE_MAX_N / c.relaxation().g0_n_per_v * 2.0  # ~ the core's output over the force range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([8e4, 4e3]))))  # V / (N s) at 1 N
        zener = Zener(c.k1_n_per_v, c.k2_n_per_v, c.eta2_n_s_per_v)
        if shape == "orifice_leak":
            f0 = 4.0
            return Parts("zener", FlowCore(zener, lambda f, phi=1.5 * phi, f0=f0: phi * f0 * np.sign(f) * np.sqrt(
                np.abs(f) / f0)), core_changed=True)
        return Parts("zener", DamagedFlow(zener, 1.3 * phi, rng.uniform(1000.0, 2500.0), 4.0, rng.uniform(1.5, 2.5)),
                     core_changed=True)
    if effect == "delayed_elasticity":
        total = float(np.interp(m, [0, 1], [1 / 60.0, 1 / 6.0]))  # added compliance, V/N
        if shape == "fractional_kelvin":
            tau, alpha = rng.uniform(3.0, 30.0), rng.uniform(0.6, 0.85)
            p.extra.append(lambda t, f, T, k=total, tau=tau, a=alpha: cole_cole_creep(t, f, k, tau, a))
            return p
        tau, power = rng.uniform(3.0, 20.0), rng.uniform(1.7, 2.3)
        p.extra.append(lambda t, f, T, k=total, tau=tau, q=power: power_dashpot_kelvin(t, f, k, tau, q))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.02, 0.07]))
        if shape == "rayleigh_force":
            b = 4.0 * frac * FORCE_MAX_N / 6.0 ** 2  # opens by frac F_max for a 0-6-0 N cycle
            p.before.append(ForcePath(lambda t, x, b=b: x + rayleigh_loops(x, b)))
            return p
        p.after.append(BergVoltage(rng.uniform(0.04, 0.12) * span / 2, frac * span / 2))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.01, 0.12]))))
        if shape == "running_median":
            p.after.append(CausalMedian(2.0 * delay))
            return p
        p.after.append(MotionAdaptiveAverage(2.0 * delay, rng.uniform(0.04, 0.08) * span))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.02, 0.08]))
        top = span / 2 * rng.uniform(1.0, 1.5)
        if shape == "quarter_bridge":
            s = top * (1.0 - 2.0 * rel) / (2.0 * rel)  # 1 - 2 rel times the linear output at the top
            p.after.append(StaticMap(lambda x, s=s: x / (1.0 + np.maximum(x, -0.9 * s) / s)))
            return p
        s = optimize.brentq(lambda s, r=rel: s / top * math.expm1(top / s) - 1.0 - 2.0 * r, 0.05 * top, 1e4 * top)
        p.after.append(StaticMap(lambda x, s=s: s * np.expm1(np.minimum(x, 5.0 * s) / s)))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.02]) * rng.choice([-1, 1]))
        if shape == "thermometer_lags":
            tau = rng.uniform(15.0, 60.0)
            p.extra.append(lambda t, f, T, k=k, tau=tau: k * (T + tau * np.gradient(T, t) - T_REF_C))
            return p
        tau, gain = rng.uniform(60.0, 200.0), rng.uniform(1.5, 3.0)
        p.extra.append(lambda t, f, T, k=k, tau=tau, g=gain: k * (load_lagged_temperature(t, f, T, tau, g) - T_REF_C))
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.002, 0.01]) * rng.choice([-1, 1]))
        out = core_output(c)
        if shape == "boxcar_span":
            window = rng.uniform(30.0, 120.0)
            p.extra.append(lambda t, f, T, a=2.0 * a, w=window, out=out: a * (boxcar_temperature(t, T, w) - T_REF_C)
                           * out(t, f))
            return p
        rate = rng.uniform(0.003, 0.01)
        p.extra.append(lambda t, f, T, a=2.0 * a, r=rate, out=out: a * (slew_limited(t, T, r) - T_REF_C) * out(t, f))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.08]) * rng.choice([-1, 1]))
        if shape == "hyperbolic_approach":
            tau = rng.uniform(0.05, 0.4) * DURATION_S
            p.extra.append(lambda t, f, T, s=size, tau=tau: s * (t - t[0]) / (t - t[0] + tau)
                           * (DURATION_S + tau) / DURATION_S)
            return p
        noise = flicker(rng, abs(size))
        p.extra.append(lambda t, f, T, n=noise: n(t - t[0]))
        return p
    if effect == "resonance":
        f0 = rng.uniform(18.0, 45.0)
        zeta = float(np.interp(m, [0, 1], [0.06, 0.015])) * rng.uniform(0.8, 1.2)
        if shape == "bilinear_mode":
            p.after.append(BilinearMode(f0, zeta, rng.uniform(1.5, 3.0)))
            return p
        p.after.append(LoadDampedMode(f0, zeta / 3.0, rng.uniform(2.0, 5.0), span / 2))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "galling_band":
            grow, travel = rng.uniform(1.5, 2.5), rng.uniform(100.0, 400.0)

            def galling(t, x, r=r, g=grow, L=travel):
                used = np.cumsum(np.abs(np.diff(x, prepend=x[0])))
                band = r * (1.0 + (g - 1.0) * -np.expm1(-used / L))
                return band_play(x, band, band)
            p.before.append(ForcePath(galling))
            return p
        wander, sigma = smooth_random(rng, rng.uniform(10.0, 40.0)), rng.uniform(0.3, 0.5)

        def wandering(t, x, r=1.2 * r, w=wander, sg=sigma):
            band = r * np.exp(sg * w(t - t[0]))
            return band_play(x, band, band)
        p.before.append(ForcePath(wandering))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.15, 0.4]))
        if shape == "layered_core":
            lags = [rng.uniform(2.0, 8.0), rng.uniform(20.0, 60.0), rng.uniform(100.0, 250.0)]
            return Parts("burgers", LayeredShiftCore(c, 1.5 * b, lags), core_changed=True)
        boost = float(np.interp(m, [0, 1], [0.6, 1.8])) * rng.uniform(0.8, 1.2)
        rate_of = melting_clock(b, rng.uniform(19.5, 21.5), rng.uniform(1.0, 2.5), rng.uniform(0.3, 0.7), boost)
        return Parts("burgers", ShiftedBurgers(c, rate_of, flow_only=False), core_changed=True)
    if effect == "shunt_calibration":
        size = float(np.interp(m, [0, 1], [0.04, 0.12]))
        starts = np.cumsum(rng.uniform(25.0, 70.0, 24)) - rng.uniform(0.0, 20.0)
        widths = rng.uniform(0.3, 1.0, starts.size)
        p.extra.append(lambda t, f, T, s=size, a=starts, w=widths: s * pulses(t - t[0], a, w))
        return p
    if effect == "discharge_transients":
        n = int(rng.integers(4, 11))
        at, taus = rng.uniform(0.03, 0.97, n) * DURATION_S, rng.uniform(0.5, 3.0, n)
        sizes = float(np.interp(m, [0, 1], [0.04, 0.1])) * rng.uniform(0.6, 1.4, n) * rng.choice([-1, 1], n)

        def discharges(t, f, T, at=at, taus=taus, sizes=sizes):
            s, out = t - t[0], np.zeros_like(t)
            for a, tau, size in zip(at, taus, sizes):
                out += size * np.exp(-np.clip(s - a, 0.0, None) / tau) * (s >= a)
            return out
        p.extra.append(discharges)
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["orifice_leak", "damage_accelerated_flow"],
    "delayed_elasticity": ["fractional_kelvin", "power_dashpot_kelvin"],
    "hysteresis": ["rayleigh_force", "berg_voltage"],
    "sensor_lag": ["running_median", "motion_adaptive_average"],
    "nonlinear_gain": ["quarter_bridge", "tunnelling_exponential"],
    "thermal_drift": ["thermometer_lags", "load_dependent_lag"],
    "thermal_sensitivity": ["boxcar_span", "slew_limited_span"],
    "offset_drift": ["hyperbolic_approach", "flicker_noise"],
    "resonance": ["bilinear_mode", "load_damped_mode"], "friction": ["galling_band", "wandering_band"],
    "thermo_rheological": ["layered_core", "melting_clock"],
}
PAIRS = (("viscous_flow", "resonance"), ("delayed_elasticity", "thermal_sensitivity"), ("hysteresis", "offset_drift"),
         ("sensor_lag", "friction"), ("nonlinear_gain", "thermal_drift"), ("thermo_rheological", "hysteresis"))
OUTSIDE = ("shunt_calibration", "discharge_transients")
RATES = (310.0, 540.0, 920.0, 1000.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split L", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.0e-3, 3.0e-3), jitter=0.45,
                   gap_s=(0.1, 2.5))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
