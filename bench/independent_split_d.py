"""Independent split D for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Splits A, B and C were each run once and are spent; split D was written before the engine it measured and run
once at commit ``0f78c4b`` (the result is in docs/discrepancy.md), so it is spent too. Every name of the catalogue
is hidden in two shapes that neither the registry's families
(``polyforce_ros/sim/truths.py``) nor splits A, B and C use:

* a flow added to a two-Kelvin core, or a fast flow (300-3000 N s/V); a second Kelvin unit on a Zener sensor, or a
  Kelvin unit of 0.5-3 s on a Maxwell sensor;
* plays on the force whose width grows with the load; a sensitivity that differs between loading and unloading;
* a fourth-order Bessel anti-alias filter; a lead-lag network (only part of the signal lags);
* a power-law gain; a gain that stiffens as a squared tanh;
* a thermal zero with thermal hysteresis (the zero follows temperature through a play); a zero following the
  temperature's rate of change (a thermal gradient);
* a span with thermal hysteresis; a span quadratic in a lagged temperature;
* a staircase of offset steps; a wander of random slopes;
* two modes; a low mode (5-12 Hz);
* a friction band that grows with the load; Coulomb plus viscous friction;
* a core temperature that lags the thermometer; a strong Arrhenius shift.

It also holds six pairs, two effects outside the catalogue (a span ripple at 0.5-2 Hz, a permanent set that
follows the largest load so far) and four clean records. Profiles: staircases with hand tremor (8-12 Hz) on the
holds, repeated ramp-hold-release creep tests, and the measured Okamura insertion with its punctures sharpened
(``../shared/data``; a train of synthetic punctures when it is absent). Rates 250, 400 and 1000 Hz (a mode at
1000 Hz with knocks that excite it), 2-2.5 mV noise, stamp jitter, gaps, a temperature that heats and cools.

Scored like the other splits (``bench/independent_split.py``). It is run once per engine and never used to choose
anything. ``--check`` prints each case's effect size against its noise without diagnosing.

    .venv/bin/python bench/independent_split_d.py [--json out.json] [--workers 2] [--stride 1] [--check]
"""
from __future__ import annotations

import numpy as np
from scipy import signal

from polyforce_ros.physics.chain import play_operator
from polyforce_ros.physics.expconv import exp_convolve
from polyforce_ros.physics.viscoelastic import Burgers, Burgers2, Zener2, simulate_deformation
from polyforce_ros.sim.truths import SecondOrderLag, StaticMap
from split_kit import (LinearFilter, Parts, ShapeSplit, SimOnly, band_play, core_output, ramp_and_hold,
                       repeated_insertions)

SEED0 = 260_000  # never a seed of the registry's splits nor of splits A (90000..), B (140000..), C (210000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 500.0


# ----------------------------------------------------------------------------- profiles and temperature

def tremor_staircase(duration_s, rate_hz, rng):
    """Levels held 5-40 s, reached in 0.1-1 s, with a hand tremor of 8-12 Hz and 20-80 mN on every hold."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    knots_t, knots_f = [0.0, rng.uniform(2.0, 6.0)], [0.0, 0.0]
    now = knots_t[-1]
    while now < duration_s:
        level = rng.uniform(0.5, FORCE_MAX_N) * (rng.random() > 0.2)
        now = ramp_and_hold(knots_t, knots_f, now, level, rng.uniform(0.1, 1.0), rng.uniform(5.0, 40.0))
    f = np.interp(t, knots_t, knots_f)
    tremor = rng.uniform(0.02, 0.08) * np.sin(2 * np.pi * rng.uniform(8.0, 12.0) * t + rng.uniform(0, 6.3))
    return t, np.clip(f + tremor * (f > 0.2), 0.0, None)


def creep_tests(duration_s, rate_hz, rng):
    """Repeated creep tests: a ramp of 0.2-2 s to 2-9 N, a hold of 20-60 s, a release, a rest of 20-60 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    knots_t, knots_f, now = [0.0], [0.0], rng.uniform(3.0, 8.0)
    while now < duration_s:
        level, ramp = rng.uniform(2.0, FORCE_MAX_N), rng.uniform(0.2, 2.0)
        hold, rest = rng.uniform(20.0, 60.0), rng.uniform(20.0, 60.0)
        knots_t += [now, now + ramp, now + ramp + hold, now + 2 * ramp + hold]
        knots_f += [0.0, level, level, 0.0]
        now += 2 * ramp + hold + rest
    return t, np.interp(t, knots_t, knots_f)


def sharpened_okamura(duration_s, rate_hz, rng):
    """The measured insertion scaled to 2-9 N, its force drops (punctures) made 2-5x faster: time runs faster
    wherever the force falls."""
    def sharpened(tp, fp, rng):
        falling = np.diff(fp, prepend=fp[0]) < 0
        warped = np.cumsum(np.where(falling, 1.0 / rng.uniform(2.0, 5.0), 1.0)) / rate_hz
        return np.interp(np.arange(0.0, warped[-1], 1.0 / rate_hz), warped, fp)
    return repeated_insertions(duration_s, rate_hz, rng, sharpened, FORCE_MAX_N)


PROFILES = (tremor_staircase, creep_tests, sharpened_okamura)


def temperature(t, rng):
    """Heating then cooling: up by 3-7 degC over 20-40 % of the record, back down over the rest, plus a 0.5 degC
    wobble of a few minutes."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    top, peak = rng.uniform(0.2, 0.4) * d, rng.uniform(3.0, 7.0) * rng.choice([-1, 1])
    shape = np.where(s < top, s / top, np.clip(1 - (s - top) / (d - top) * rng.uniform(0.6, 1.0), 0.0, 1.0))
    return T_REF_C + rng.uniform(-1, 1) + peak * shape + 0.5 * np.sin(2 * np.pi * s / rng.uniform(120, 300))


def _play(x, r):
    return play_operator(np.asarray(x, dtype=float), [r], [float(np.asarray(x)[0])])[:, 0]


# ----------------------------------------------------------------------------- simulate-only truth elements

class LoadWidthPlays(SimOnly):
    """Plays on the force whose half-width grows with the load, r (0.5 + F / F_max): the core sees
    F + sum w_i (p_i(F) - F)."""

    def __init__(self, radii_n, weights):
        self.r, self.w = np.asarray(radii_n), np.asarray(weights)

    def forward(self, t_s, x, aux=None, state=None):
        f = np.asarray(x, dtype=float)
        out, p = np.empty_like(f), np.full(self.w.size, f[0])
        for i, fi in enumerate(f):
            r = self.r * (0.5 + max(fi, 0.0) / FORCE_MAX_N)
            p = np.maximum(fi - r, np.minimum(fi + r, p))
            out[i] = fi + float(self.w @ (p - fi))
        return out


class DirectionalGain(SimOnly):
    """A sensitivity that differs between loading and unloading: y = x (1 + c z), z the direction of motion
    smoothed over an x-distance w (dz = |dx| (sign(dx) - z) / w)."""

    def __init__(self, c, width_v):
        self.c, self.w = c, width_v

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        out, z, xp = np.empty_like(x), 0.0, x[0]
        for i, xi in enumerate(x):
            dx = xi - xp
            if dx:
                z += min(abs(dx) / self.w, 1.0) * (np.sign(dx) - z)
            xp = xi
            out[i] = xi * (1 + self.c * z)
        return out


class LoadBandFriction(SimOnly):
    """Coulomb friction whose band grows with the load (a seal pressed harder): r = r0 (1 + F / F_max)."""

    def __init__(self, r0_n):
        self.r0 = r0_n

    def forward(self, t_s, x, aux=None, state=None):
        f = np.asarray(x, dtype=float)
        r = self.r0 * (1 + np.maximum(f, 0.0) / FORCE_MAX_N)
        return band_play(f, r, r)


class ViscousCoulomb(SimOnly):
    """Coulomb friction (a play of half-width r) plus a viscous part proportional to the force's rate."""

    def __init__(self, r_n, c_s):
        self.r, self.c = r_n, c_s

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        rate = np.gradient(f, t)
        return _play(f, self.r) - self.c * rate


class LaggedShiftBurgers(SimOnly):
    """A Burgers core on the reduced time of an Arrhenius shift b (ln a = -b dT), the core's temperature lagging
    the thermometer by a first-order lag of ``tau_s``."""

    def __init__(self, c, b, tau_s):
        self.core, self.b, self.tau = c, b, tau_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        temp = np.broadcast_to(aux["temperature_c"], t.shape)
        lagged = exp_convolve(t, temp, [1.0 / self.tau], y0=[temp[0] * self.tau])[:, 0] / self.tau
        rate = np.exp(self.b * (lagged - T_REF_C))
        xi = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(t))])
        return simulate_deformation(self.core, xi, np.asarray(x, dtype=float))


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    span = FORCE_MAX_N / c.relaxation().g0_n_per_v * 2.0  # ~ the core's output over the force range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        if shape == "flow_on_two_kelvins":
            k3 = c.k2_n_per_v * rng.uniform(1.0, 3.0)
            eta1 = float(np.exp(np.interp(m, [0, 1], np.log([2e5, 5e3]))))
            return Parts("zener2", Burgers2(c.k1_n_per_v, c.k2_n_per_v, eta1, c.eta2_n_s_per_v, k3,
                                            k3 * rng.uniform(100.0, 300.0)), core_changed=True)
        eta1 = float(np.exp(np.interp(m, [0, 1], np.log([3e3, 300.0]))))
        return Parts("zener", Burgers(c.k1_n_per_v, c.k2_n_per_v, eta1, c.eta2_n_s_per_v), core_changed=True)
    if effect == "delayed_elasticity":
        if shape == "zener_to_zener2":
            k3 = float(np.interp(m, [0, 1], [50.0, 6.0]))
            tau2 = c.eta2_n_s_per_v / c.k2_n_per_v
            tau3 = tau2 * rng.choice([0.1, 10.0]) * rng.uniform(0.7, 1.4)
            return Parts("zener", Zener2(c.k1_n_per_v, c.k2_n_per_v, c.eta2_n_s_per_v, k3, k3 * tau3),
                         core_changed=True)
        k2 = float(np.interp(m, [0, 1], [60.0, 6.0]))
        return Parts("maxwell", Burgers(c.k1_n_per_v, k2, c.eta1_n_s_per_v, k2 * rng.uniform(0.5, 3.0)),
                     core_changed=True)
    if effect == "hysteresis":
        frac = np.interp(m, [0, 1], [0.02, 0.08])
        if shape == "load_width_plays":
            n = int(rng.integers(2, 6))
            radii = np.sort(rng.uniform(0.01, 0.2, n)) * FORCE_MAX_N
            w = rng.uniform(0.3, 1.0, n)
            w *= frac * FORCE_MAX_N / (2 * np.sum(w * radii))
            p.before.append(LoadWidthPlays(radii, w))
            return p
        p.after.append(DirectionalGain(frac * rng.choice([-1, 1]), rng.uniform(0.02, 0.2) * span))
        return p
    if effect == "sensor_lag":
        if shape == "bessel4":
            fc = float(np.exp(np.interp(m, [0, 1], np.log([40.0, 4.0]))))
            num, den = signal.bessel(4, 2 * np.pi * fc, analog=True, norm="delay")
            p.after.append(LinearFilter(num, den))
            return p
        tau = float(np.exp(np.interp(m, [0, 1], np.log([0.02, 0.5]))))
        a = rng.uniform(0.3, 0.7)  # (1 + a tau s) / (1 + tau s): a share a of the signal passes at once
        p.after.append(LinearFilter([a * tau, 1.0], [tau, 1.0]))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.02, 0.1]))
        if shape == "power_law":
            q = rel * rng.choice([-1, 1])
            p.after.append(StaticMap(lambda x, s=span, q=q: np.sign(x) * s * (np.abs(x) / s) ** (1 + q)))
            return p
        p.after.append(StaticMap(lambda x, s=span, r=rel: x * (1 + 2 * r * np.tanh(x / s) ** 2)))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.003, 0.01]) * rng.choice([-1, 1]))
        if shape == "thermal_hysteresis":
            band = rng.uniform(0.5, 1.5)
            p.extra.append(lambda t, f, T, k=k, b=band: k * (_play(T, b) - T_REF_C))
            return p
        tau = rng.uniform(20.0, 80.0)  # the gradient across the body: T minus its lag, times k * 3

        def gradient(t, f, T, k=k, tau=tau):
            lagged = exp_convolve(t, T, [1.0 / tau], y0=[T[0] * tau])[:, 0] / tau
            return 3.0 * k * (T - lagged)
        p.extra.append(gradient)
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.002, 0.01]) * rng.choice([-1, 1]))
        out = core_output(c)
        if shape == "span_thermal_hysteresis":
            band = rng.uniform(0.5, 1.5)
            p.extra.append(lambda t, f, T, a=a, b=band, out=out: a * (_play(T, b) - T_REF_C) * out(t, f))
            return p
        tau = rng.uniform(10.0, 60.0)

        def quadratic_lagged(t, f, T, a=a, tau=tau, out=out):
            d = exp_convolve(t, T, [1.0 / tau], y0=[T[0] * tau])[:, 0] / tau - T_REF_C
            return (a * d + 0.2 * abs(a) * d ** 2) * out(t, f)
        p.extra.append(quadratic_lagged)
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.08]))
        if shape == "staircase":
            n = int(rng.integers(3, 6))
            at, width = np.sort(rng.uniform(0.1, 0.9, n)) * DURATION_S, rng.uniform(2.0, 10.0, n)
            steps = rng.normal(0.0, 1.0, n)
            steps *= size / max(np.abs(np.cumsum(steps)).max(), 1e-9)
            p.extra.append(lambda t, f, T, at=at, w=width, s=steps: sum(
                si * 0.5 * (1 + np.tanh((t - t[0] - ai) / wi)) for ai, wi, si in zip(at, w, s)))
            return p
        knots = np.linspace(0.0, DURATION_S, int(rng.integers(4, 8)))
        values = np.cumsum(np.concatenate([[0.0], rng.normal(0.0, 1.0, knots.size - 1)]))
        values *= size / max(np.abs(values).max(), 1e-9)
        p.extra.append(lambda t, f, T, k=knots, v=values: np.interp(t - t[0], k, v))
        return p
    if effect == "resonance":
        if shape == "two_modes":
            f1 = rng.uniform(15.0, 30.0)
            p.after += [SecondOrderLag(2 * np.pi * f1, rng.uniform(0.03, 0.1)),
                        SecondOrderLag(2 * np.pi * f1 * rng.uniform(2.0, 3.0), rng.uniform(0.05, 0.15))]
            return p
        p.after.append(SecondOrderLag(2 * np.pi * rng.uniform(5.0, 12.0), rng.uniform(0.05, 0.2)))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "load_band":
            p.before.append(LoadBandFriction(r / 1.5))
            return p
        p.before.append(ViscousCoulomb(r, rng.uniform(0.002, 0.01)))
        return p
    if effect == "thermo_rheological":
        if shape == "lagged_core_temperature":
            b = float(np.interp(m, [0, 1], [0.06, 0.2])) * rng.uniform(0.8, 1.2)
            return Parts("burgers", LaggedShiftBurgers(c, b, rng.uniform(10.0, 60.0)), core_changed=True)
        b = rng.uniform(0.2, 0.35)
        return Parts("burgers", LaggedShiftBurgers(c, b, 1e-3), core_changed=True)
    if effect == "span_ripple":
        g, hz = float(np.interp(m, [0, 1], [0.01, 0.04])), rng.uniform(0.5, 2.0)
        out = core_output(c)
        p.extra.append(lambda t, f, T, g=g, hz=hz, out=out: g * np.sin(2 * np.pi * hz * t) * out(t, f))
        return p
    if effect == "permanent_set":
        k = float(np.interp(m, [0, 1], [0.002, 0.008]))  # V per N of the largest load so far
        p.extra.append(lambda t, f, T, k=k: k * np.maximum.accumulate(f))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["flow_on_two_kelvins", "fast_flow"], "delayed_elasticity": ["zener_to_zener2", "from_maxwell_fast"],
    "hysteresis": ["load_width_plays", "directional_gain"], "sensor_lag": ["bessel4", "lead_lag"],
    "nonlinear_gain": ["power_law", "tanh_squared"], "thermal_drift": ["thermal_hysteresis", "gradient"],
    "thermal_sensitivity": ["span_thermal_hysteresis", "quadratic_lagged"], "offset_drift": ["staircase", "wander"],
    "resonance": ["two_modes", "low_mode"], "friction": ["load_band", "viscous_coulomb"],
    "thermo_rheological": ["lagged_core_temperature", "strong_arrhenius"],
}
PAIRS = (("hysteresis", "offset_drift"), ("sensor_lag", "thermal_sensitivity"), ("friction", "thermal_drift"),
         ("resonance", "nonlinear_gain"), ("thermo_rheological", "offset_drift"), ("delayed_elasticity", "hysteresis"))
OUTSIDE = ("span_ripple", "permanent_set")
RATES = (250.0, 400.0, 1000.0)


SPLIT = ShapeSplit("independent split D", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.25, 0.75), pair_shapes=(-1, 0),
                   rates=RATES, profiles=PROFILES, temperature=temperature, make_parts=make_parts,
                   duration_s=DURATION_S, noise_v=(2e-3, 2.5e-3), jitter=0.35, gap_s=(0.2, 2.0))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
