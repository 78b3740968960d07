"""Independent split H for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Splits A to G were each run once and are spent. Split H is the untouched held-out set for the next engine: written
before it, run once at its end, never used to choose anything. Every name of the catalogue is hidden in two shapes
that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A to G use:

* a dashpot whose rate grows as the hyperbolic sine of the force (Eyring), or one that softens as it flows;
* creep with a power-law spectrum of retardation times (more weight on the long ones), or a Kelvin unit whose
  compliance grows with the force (Schapery);
* a distribution of frictional sliders on the force before the core (Iwan), or a play on the bridge voltage whose
  stuck value creeps toward the input (5-30 s);
* a lag of fractional order (1 / (1 + (s tau)^alpha)), or a Gaussian smoothing window;
* a gain that saturates exponentially, or three straight slopes;
* a thermal zero quadratic in a lagged temperature, or one behind two cascaded lags;
* a span that follows two lags of the temperature at once, or one inversely proportional to (1 + a dT);
* an offset that wanders along a smooth random spline, or settles with two time constants;
* a mode behind a first-order electrical filter, or two close modes that beat;
* a play whose width is drawn anew at every reversal, or one that slips past its stuck force (stick-slip);
* a shift factor quadratic in a lagged temperature, or one that shifts the flow and the delayed elasticity by
  different slopes.

It also holds six pairs, two effects outside the catalogue (noise that grows with the load, bursts of noise) and four
clean records. Profiles: the measured Okamura insertion with a cardiac pulse on the contact, sawtooth ramps released
in 50-200 ms, and square load steps. Rates 240, 640, 850 and 1000 Hz (a mode at 1000 Hz with knocks that excite it),
1-3 mV noise, stamp jitter, gaps, a room temperature that swings slowly and steps when a door opens.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_h.py [--json out.json] [--workers 2] [--stride 1] [--check]
"""
from __future__ import annotations

import numpy as np
from scipy import integrate, interpolate

from polyforce_ros.physics.viscoelastic import Zener, simulate_deformation
from polyforce_ros.sim.truths import StaticMap
from split_kit import (band_play, core_output, ForcePath, kelvin, lagged, LinearFilter, Parts, ramp_and_hold,
                       relaxing_play, repeated_insertions, ShapeSplit, SimOnly, uniform_grid)

SEED0 = 540_000  # never a seed of the registry's splits nor of splits A (90000..) to G (470000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 450.0


# ----------------------------------------------------------------------------- profiles and temperature

def okamura_pulsed(duration_s, rate_hz, rng):
    """The measured insertion with a cardiac pulse (1-1.6 Hz, 5-15 % of the peak) on the force while the needle is
    in contact, repeated with 5-30 s of rest."""
    def pulsed(tp, fp, rng):
        one = np.interp(np.arange(0.0, tp[-1] - tp[0], 1.0 / rate_hz), tp - tp[0], fp)
        s = np.arange(one.size) / rate_hz
        pulse = np.sin(np.pi * rng.uniform(1.0, 1.6) * s + rng.uniform(0, np.pi)) ** 2
        return one + rng.uniform(0.05, 0.15) * one.max() * pulse * (one > 0.1 * one.max())
    return repeated_insertions(duration_s, rate_hz, rng, pulsed, FORCE_MAX_N)


def release_sawtooth(duration_s, rate_hz, rng):
    """Ramps to 2-9 N over 3-15 s released in 50-200 ms, with 2-10 s at rest after each."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    knots_t, knots_f, now = [0.0], [0.0], rng.uniform(3.0, 8.0)
    knots_t.append(now)
    knots_f.append(0.0)
    while now < duration_s:
        now = ramp_and_hold(knots_t, knots_f, now, rng.uniform(2.0, FORCE_MAX_N), rng.uniform(3.0, 15.0), 0.0)
        now = ramp_and_hold(knots_t, knots_f, now, 0.0, rng.uniform(0.05, 0.2), rng.uniform(2.0, 10.0))
    return t, np.interp(t, knots_t, knots_f)


def square_steps(duration_s, rate_hz, rng):
    """Square steps between rest and 2-9 N, edges of 50-300 ms, each level held 3-40 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    knots_t, knots_f, now = [0.0], [0.0], rng.uniform(3.0, 8.0)
    knots_t.append(now)
    knots_f.append(0.0)
    while now < duration_s:
        now = ramp_and_hold(knots_t, knots_f, now, rng.uniform(2.0, FORCE_MAX_N), rng.uniform(0.05, 0.3),
                            rng.uniform(3.0, 40.0))
        now = ramp_and_hold(knots_t, knots_f, now, 0.0, rng.uniform(0.05, 0.3), rng.uniform(3.0, 40.0))
    return t, np.interp(t, knots_t, knots_f)


PROFILES = (okamura_pulsed, release_sawtooth, square_steps)


def temperature(t, rng):
    """A room: a swing of 0.5-1.5 degC with a period of 300-900 s, and a step of 1-2.5 degC either way (a door
    opens) at 30-70 % of the record that settles in 10-40 s."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    swing = rng.uniform(0.5, 1.5) * np.sin(2 * np.pi * s / rng.uniform(300.0, 900.0) + rng.uniform(0, 2 * np.pi))
    at, settle = rng.uniform(0.3, 0.7) * d, rng.uniform(10.0, 40.0)
    step = rng.choice([-1, 1]) * rng.uniform(1.0, 2.5) * (1.0 - np.exp(-np.clip(s - at, 0.0, None) / settle))
    return T_REF_C + rng.uniform(-1, 1) + swing + step


# ----------------------------------------------------------------------------- simulate-only truth elements

class EyringFlowZener(SimOnly):
    """A Zener core plus a dashpot whose rate is phi F0 sinh(F / F0)."""

    def __init__(self, zener, phi_v_per_n_s, f0_n):
        self.zener, self.phi, self.f0 = zener, phi_v_per_n_s, f0_n

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        rate = self.phi * self.f0 * np.sinh(f / self.f0)
        return simulate_deformation(self.zener, t, f) + integrate.cumulative_trapezoid(rate, t, initial=0.0)


class SofteningFlowZener(SimOnly):
    """A Zener core plus a dashpot that softens as it flows: u' = phi F (1 + u / u0), so
    u = u0 (exp(phi / u0 int F) - 1)."""

    def __init__(self, zener, phi_v_per_n_s, u0_v):
        self.zener, self.phi, self.u0 = zener, phi_v_per_n_s, u0_v

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        impulse = integrate.cumulative_trapezoid(f, t, initial=0.0)
        return simulate_deformation(self.zener, t, f) + self.u0 * np.expm1(self.phi * impulse / self.u0)


class FractionalLag(SimOnly):
    """A lag of fractional order, 1 / (1 + (j w tau)^alpha), applied in the frequency domain on a uniform grid at
    the median step (zero-padded, so causal up to the record's length)."""

    def __init__(self, tau_s, alpha):
        self.tau, self.alpha = tau_s, alpha

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        xu = xu - x[0]
        n = 2 * tu.size
        w = 2 * np.pi * np.fft.rfftfreq(n, h)
        gain = 1.0 / (1.0 + (1j * w * self.tau) ** self.alpha)
        y = np.fft.irfft(np.fft.rfft(xu, n) * gain, n)[:tu.size] + x[0]
        return np.interp(t, tu, y)


class GaussianWindow(SimOnly):
    """A causal Gaussian smoothing window of width ``sigma_s``, centred 3 sigma back."""

    def __init__(self, sigma_s):
        self.sigma = sigma_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        k = np.arange(0.0, 6.0 * self.sigma + h, h)
        taps = np.exp(-0.5 * ((k - 3.0 * self.sigma) / self.sigma) ** 2)
        taps /= taps.sum()
        y = np.convolve(np.concatenate([np.full(taps.size - 1, xu[0]), xu]), taps, mode="valid")
        return np.interp(t, tu, y)


class CreepingVoltagePlay(SimOnly):
    """A play of half-width ``r_v`` on the bridge voltage whose stuck value creeps toward the input with
    ``tau_s``."""

    def __init__(self, r_v, tau_s):
        self.r, self.tau = r_v, tau_s

    def forward(self, t_s, x, aux=None, state=None):
        return relaxing_play(np.asarray(t_s, dtype=float), np.asarray(x, dtype=float), self.r, self.tau)


class TwoShiftBurgers(SimOnly):
    """A Burgers core whose flow runs at exp(b_flow dT) and whose delayed elasticity runs at exp(b_kelvin dT)."""

    def __init__(self, c, b_flow, b_kelvin):
        self.c, self.b_flow, self.b_kelvin = c, b_flow, b_kelvin

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        dT = np.broadcast_to(aux["temperature_c"], t.shape) - T_REF_C
        xi = integrate.cumulative_trapezoid(np.exp(self.b_kelvin * dT), t, initial=0.0)
        zener = Zener(self.c.k1_n_per_v, self.c.k2_n_per_v, self.c.eta2_n_s_per_v)
        flow = integrate.cumulative_trapezoid(np.exp(self.b_flow * dT) * f / self.c.eta1_n_s_per_v, t, initial=0.0)
        return simulate_deformation(zener, xi, f) + flow


class LaggedShiftBurgers(SimOnly):
    """A Burgers core whose clock runs at exp(b dTl + q dTl^2), dTl the temperature seen through a lag."""

    def __init__(self, c, b, q, tau_s):
        self.c, self.b, self.q, self.tau = c, b, q, tau_s

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        temp = np.broadcast_to(aux["temperature_c"], t.shape)
        dTl = lagged(t, temp, self.tau) - T_REF_C
        xi = integrate.cumulative_trapezoid(np.exp(self.b * dTl + self.q * dTl ** 2), t, initial=0.0)
        return simulate_deformation(self.c, xi, f)


def random_band(f, r_n, rng):
    """A play whose half-width is drawn anew (60-140 % of ``r_n``) at every reversal of the force."""
    out, p, direction, r = np.empty_like(f), float(f[0]), 0.0, r_n
    previous = float(f[0])
    for i, fi in enumerate(np.asarray(f, dtype=float).tolist()):
        step = np.sign(fi - previous)
        if step != 0 and step != direction:
            direction, r = step, r_n * rng.uniform(0.6, 1.4)
        p = max(fi - r, min(fi + r, p))
        out[i], previous = p, fi
    return out


def slip_overshoot(f, r_n, overshoot):
    """A play of half-width ``r_n`` that, once it slips, jumps past the input to ``(1 - overshoot) r_n`` behind it
    (stick-slip)."""
    out, p = np.empty_like(f), float(f[0])
    for i, fi in enumerate(np.asarray(f, dtype=float).tolist()):
        if fi - p > r_n:
            p = fi - (1.0 - overshoot) * r_n
        elif p - fi > r_n:
            p = fi + (1.0 - overshoot) * r_n
        out[i] = p
    return out


def second_order_mode(f0_hz, zeta):
    w0 = 2 * np.pi * f0_hz
    return np.array([w0 ** 2]), np.array([1.0, 2 * zeta * w0, w0 ** 2])


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    span = FORCE_MAX_N / c.relaxation().g0_n_per_v * 2.0  # ~ the core's output over the force range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([8e4, 4e3]))))
        zener = Zener(c.k1_n_per_v, c.k2_n_per_v, c.eta2_n_s_per_v)
        if shape == "eyring_flow":
            return Parts("zener", EyringFlowZener(zener, phi * 0.6, rng.uniform(2.0, 5.0)), core_changed=True)
        u0 = phi * 5.0 * DURATION_S * rng.uniform(0.6, 1.5)  # ~ the flow over the record under a 5 N mean load
        return Parts("zener", SofteningFlowZener(zener, phi * 0.7, u0), core_changed=True)
    if effect == "delayed_elasticity":
        total = float(np.interp(m, [0, 1], [1 / 60.0, 1 / 6.0]))  # added compliance, V/N
        if shape == "power_law_spectrum":
            taus, n = np.geomspace(0.1, 300.0, 18), rng.uniform(0.2, 0.5)
            w = taus ** n
            w *= total / w.sum()
            p.extra.append(lambda t, f, T, taus=taus, w=w: sum(kelvin(t, f, wi, ti) for wi, ti in zip(w, taus)))
            return p
        tau, a = rng.uniform(2.0, 40.0), rng.uniform(0.5, 1.5)
        p.extra.append(lambda t, f, T, k=total / (1 + a / 2), a=a, tau=tau: kelvin(
            t, f * (1.0 + a * f / FORCE_MAX_N), k, tau))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.02, 0.07]))
        if shape == "iwan_force":
            widths = np.linspace(0.1, 1.0, 8) * frac * FORCE_MAX_N
            p.before.append(ForcePath(lambda t, x, widths=widths: x + np.mean(
                [x - band_play(x, r, r) for r in widths], axis=0)))
            return p
        p.after.append(CreepingVoltagePlay(frac * span / 2, rng.uniform(5.0, 30.0)))
        return p
    if effect == "sensor_lag":
        if shape == "fractional_order":
            tau = float(np.exp(np.interp(m, [0, 1], np.log([0.01, 0.12]))))
            p.after.append(FractionalLag(tau, rng.uniform(0.6, 0.85)))
            return p
        sigma = float(np.exp(np.interp(m, [0, 1], np.log([0.004, 0.03]))))
        p.after.append(GaussianWindow(sigma))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.02, 0.08]))
        if shape == "exp_saturation":
            scale = span / (4.0 * rel)
            if rng.random() < 0.5:
                p.after.append(StaticMap(lambda x, s=scale: -s * np.expm1(-x / s)))
            else:
                p.after.append(StaticMap(lambda x, s=scale: s * np.expm1(x / s)))
            return p
        a1, a2 = rng.uniform(0.2, 0.4) * span / 2, rng.uniform(0.5, 0.8) * span / 2
        s1, s2 = rng.choice([-1, 1]) * 2 * rel, rng.choice([-1, 1]) * 2 * rel
        p.after.append(StaticMap(lambda x, a1=a1, a2=a2, s1=s1, s2=s2: x + s1 * np.clip(np.abs(x) - a1, 0.0, None)
                                 * np.sign(x) + s2 * np.clip(np.abs(x) - a2, 0.0, None) * np.sign(x)))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.02]) * rng.choice([-1, 1]))
        if shape == "lagged_quadratic_zero":
            tau = rng.uniform(20.0, 80.0)
            p.extra.append(lambda t, f, T, k=k, tau=tau: k * (lagged(t, T, tau) - T_REF_C) ** 2 / 2.0)
            return p
        tau = rng.uniform(10.0, 40.0)
        p.extra.append(lambda t, f, T, k=k, tau=tau: k * (lagged(t, lagged(t, T, tau), tau) - T_REF_C))
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.002, 0.01]) * rng.choice([-1, 1]))
        out = core_output(c)
        if shape == "span_two_lags":
            fast, slow = rng.uniform(3.0, 10.0), rng.uniform(60.0, 200.0)
            p.extra.append(lambda t, f, T, a=a, fast=fast, slow=slow, out=out: 1.5 * a * (
                0.5 * lagged(t, T, fast) + 0.5 * lagged(t, T, slow) - T_REF_C) * out(t, f))
            return p
        p.extra.append(lambda t, f, T, a=a, out=out: (1.0 / (1.0 + 1.5 * a * (T - T_REF_C)) - 1.0) * out(t, f))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.08]))
        if shape == "spline_wander":
            knots = np.linspace(0.0, DURATION_S, int(rng.integers(5, 9)))
            values = np.concatenate([[0.0], rng.uniform(-1, 1, knots.size - 1)])
            values *= size / max(np.max(np.abs(values)), 1e-9)
            spline = interpolate.CubicSpline(knots, values)
            p.extra.append(lambda t, f, T, spline=spline: spline(np.clip(t - t[0], 0.0, DURATION_S)))
            return p
        fast, slow, w = rng.uniform(30.0, 60.0), rng.uniform(200.0, 600.0), rng.uniform(0.3, 0.7)
        sign = rng.choice([-1, 1])
        p.extra.append(lambda t, f, T, s=sign * size, a=fast, b=slow, w=w: s * (
            w * (1 - np.exp(-(t - t[0]) / a)) + (1 - w) * (1 - np.exp(-(t - t[0]) / b))))
        return p
    if effect == "resonance":
        if shape == "mode_behind_filter":
            num, den = second_order_mode(rng.uniform(20.0, 45.0), rng.uniform(0.02, 0.06))
            p.after.append(LinearFilter(num, np.polymul(den, [1.0 / (2 * np.pi * rng.uniform(60.0, 150.0)), 1.0])))
            return p
        f1, zeta = rng.uniform(25.0, 50.0), rng.uniform(0.02, 0.05)
        n1, d1 = second_order_mode(f1, zeta)
        n2, d2 = second_order_mode(f1 * rng.uniform(1.05, 1.12), zeta)
        p.after.append(LinearFilter(np.polyadd(0.5 * np.polymul(n1, d2), 0.5 * np.polymul(n2, d1)), np.polymul(d1, d2)))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "random_band":
            seed = int(rng.integers(2**31))
            p.before.append(ForcePath(lambda t, x, r=r * 1.3, seed=seed: random_band(
                x, r, np.random.default_rng(seed))))
            return p
        overshoot = rng.uniform(0.3, 0.7)
        p.before.append(ForcePath(lambda t, x, r=r * 1.3, o=overshoot: slip_overshoot(x, r, o)))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.15, 0.4]))
        if shape == "lagged_quadratic_shift":
            q = rng.uniform(0.01, 0.04) * rng.choice([-1, 1])
            return Parts("burgers", LaggedShiftBurgers(c, b, q, rng.uniform(10.0, 60.0)), core_changed=True)
        ratio = rng.uniform(2.0, 4.0)
        flow, kelvin_b = (b, b * ratio) if rng.random() < 0.5 else (b * ratio, b)
        return Parts("burgers", TwoShiftBurgers(c, flow, kelvin_b), core_changed=True)
    if effect == "load_dependent_noise":
        sigma, seed = float(np.interp(m, [0, 1], [3e-3, 8e-3])), int(rng.integers(2**31))
        p.extra.append(lambda t, f, T, sigma=sigma, seed=seed: np.random.default_rng(seed).normal(
            0.0, 1.0, t.size) * sigma * np.clip(f, 0.0, None) / FORCE_MAX_N)
        return p
    if effect == "noise_bursts":
        sigma, seed = float(np.interp(m, [0, 1], [4e-3, 1e-2])), int(rng.integers(2**31))

        def bursts(t, f, T, sigma=sigma, seed=seed):
            g = np.random.default_rng(seed)
            level = np.zeros_like(t)
            for at in g.uniform(t[0], t[-1], int(g.integers(10, 31))):
                level[(t >= at) & (t < at + g.uniform(0.5, 3.0))] = sigma
            return g.normal(0.0, 1.0, t.size) * level
        p.extra.append(bursts)
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["eyring_flow", "softening_flow"],
    "delayed_elasticity": ["power_law_spectrum", "schapery_kelvin"],
    "hysteresis": ["iwan_force", "creeping_voltage_play"], "sensor_lag": ["fractional_order", "gaussian_window"],
    "nonlinear_gain": ["exp_saturation", "three_slopes"],
    "thermal_drift": ["lagged_quadratic_zero", "two_lag_zero"],
    "thermal_sensitivity": ["span_two_lags", "span_inverse"],
    "offset_drift": ["spline_wander", "two_time_settle"],
    "resonance": ["mode_behind_filter", "beating_modes"], "friction": ["random_band", "slip_overshoot"],
    "thermo_rheological": ["lagged_quadratic_shift", "two_slope_parts"],
}
PAIRS = (("viscous_flow", "thermal_sensitivity"), ("delayed_elasticity", "resonance"),
         ("hysteresis", "nonlinear_gain"), ("sensor_lag", "thermo_rheological"), ("friction", "thermal_drift"),
         ("offset_drift", "delayed_elasticity"))
OUTSIDE = ("load_dependent_noise", "noise_bursts")
RATES = (240.0, 640.0, 850.0, 1000.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split H", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.0e-3, 3.0e-3), jitter=0.3,
                   gap_s=(0.05, 3.0))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
