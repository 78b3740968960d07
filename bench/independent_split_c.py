"""Independent split C for ``polyforce diagnose``: shapes, ranges, profiles and rates that no other split uses.

Splits A and B (``bench/independent_split.py``, ``bench/independent_split_b.py``) were each run once and the engine
changed after them, so neither is untouched. Split C was written before the engine it measured and run once at
commit ``927eebf`` (the result is in docs/discrepancy.md); it is spent. Every name of the catalogue is hidden in two
shapes that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A and B use:

* viscous flow from an elastic base (a Maxwell sensor) or a very slow flow; a delayed elasticity spread over three
  retardation times, or from a Maxwell base;
* a smooth (Duhem) loop at the bridge; asymmetric plays on the force path;
* a sinc-cubed decimation filter (a sigma-delta ADC) or two real poles; a kinked or a square-root gain;
* a thermal zero behind a dead time or exponential in temperature; a span through the bridge excitation (the zero
  scales too) or behind a dead time; a hinge or a damped wave of offset;
* a mode on the force path or a high mode (60-120 Hz); stiction with a breakaway above the sliding friction, or two
  seals; a Vogel-Fulcher shift or one on the Kelvin viscosity only.

It also holds six pairs, two effects outside the catalogue (mains hum, a span step) and four clean records.
Profiles: chirped sinusoid blocks, low-passed random force with rests, and the measured Okamura insertion with a
dwell at its peak (``../shared/data``; a train of synthetic punctures when it is absent). Rates 300, 600 and 800 Hz
(a mode always at 1000 Hz), 1.5-3 mV noise, stamp jitter, gaps, a temperature step with a slow ramp.

Each case is scored like the other splits: fully correct = exactly the hidden catalogue effects named; out of
catalogue = ``unexplained``; clean = ``none``. For every correctly named case without a drift, the saved model
compensates a new record of the same sensor (a train of needle punctures), judged against 1 % of full scale RMSE.

It is run once per engine and never used to choose anything: no threshold, grid or bound of the engine may be set
from its output. ``--check`` prints each case's effect size against its noise without diagnosing anything.

    .venv/bin/python bench/independent_split_c.py [--json out.json] [--workers 2] [--stride 1] [--check]
"""
from __future__ import annotations

import numpy as np
from scipy import signal

from independent_split import puncture_train
from polyforce_ros.physics.chain import PlayHysteresisElement, SensorLagElement
from polyforce_ros.physics.viscoelastic import Burgers, Maxwell, simulate_deformation
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import SecondOrderLag, StaticMap
from split_kit import OFFSET_V, Parts, ShapeSplit, SimOnly, core_output, dead_time, kelvin

SEED0 = 210_000  # never a seed of the registry's splits (0.., 5000..), of split A (90000..) nor of split B (140000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 450.0


# ----------------------------------------------------------------------------- profiles and temperature

def chirp_blocks(duration_s, rate_hz, rng):
    """Blocks of 20-60 s of sinusoidal loading whose frequency sweeps 0.02-1.5 Hz, between rests of 5-30 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    now = rng.uniform(3.0, 10.0)
    while now < duration_s:
        length = rng.uniform(20.0, 60.0)
        s = (t >= now) & (t < now + length)
        mean, amp = rng.uniform(1.5, 6.0), rng.uniform(0.5, 3.0)
        f0, f1 = rng.uniform(0.02, 0.2), rng.uniform(0.3, 1.5)
        ramp = np.clip((t[s] - now) / 2.0, 0.0, 1.0) * np.clip((now + length - t[s]) / 2.0, 0.0, 1.0)
        f[s] = ramp * np.clip(mean + amp * signal.chirp(t[s] - now, f0, length, f1, method="logarithmic"), 0.0,
                              FORCE_MAX_N)
        now += length + rng.uniform(5.0, 30.0)
    return t, f


def smooth_random(duration_s, rate_hz, rng):
    """Low-passed random force (0.05-0.5 Hz corner), switched on and off for 10-60 s at a time."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    sos = signal.butter(2, rng.uniform(0.05, 0.5), fs=rate_hz, output="sos")
    x = signal.sosfiltfilt(sos, rng.normal(size=t.size))
    x = np.abs(x) / np.quantile(np.abs(x), 0.99) * rng.uniform(3.0, FORCE_MAX_N)
    gate, now, on = np.zeros_like(t), rng.uniform(3.0, 10.0), True
    while now < duration_s:
        length = rng.uniform(10.0, 60.0)
        gate[(t >= now) & (t < now + length)] = float(on)
        now, on = now + length, not on
    gate = signal.sosfiltfilt(signal.butter(1, 1.0, fs=rate_hz, output="sos"), gate)  # ~0.3 s edges
    return t, np.clip(x * np.clip(gate, 0.0, 1.0), 0.0, FORCE_MAX_N)


def okamura_dwell(duration_s, rate_hz, rng):
    """The measured insertion scaled to a 2-9 N peak, held at its peak for 2-20 s before the needle withdraws."""
    try:
        tp, fp = profiles.okamura_insertion(peak_n=1.0, rate_hz=rate_hz)
    except FileNotFoundError:
        return puncture_train(duration_s, rate_hz, rng)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    k = int(np.argmax(fp))
    start = rng.uniform(3.0, 10.0)
    while True:
        hold = rng.uniform(2.0, 20.0)
        one = np.concatenate([fp[:k + 1], np.full(int(hold * rate_hz), fp[k]), fp[k + 1:]])
        i0 = int(start * rate_hz)
        if i0 + one.size >= t.size:
            break
        f[i0:i0 + one.size] = rng.uniform(2.0, FORCE_MAX_N) * one
        start += one.size / rate_hz + rng.uniform(3.0, 30.0)
    return t, f


PROFILES = (chirp_blocks, smooth_random, okamura_dwell)


def temperature(t, rng):
    """A step of 2-6 degC (a door, a lamp) approached with a 20-120 s time constant, on a ramp of up to 3 degC."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    at = rng.uniform(0.2, 0.6) * d
    step = rng.uniform(2.0, 6.0) * rng.choice([-1, 1]) * -np.expm1(-np.maximum(s - at, 0.0) / rng.uniform(20.0, 120.0))
    return T_REF_C + rng.uniform(-1.0, 1.0) + rng.uniform(-3.0, 3.0) * s / d + step


# ----------------------------------------------------------------------------- simulate-only truth elements

class DuhemLoop(SimOnly):
    """A smooth rate-independent loop at the bridge: z follows x at an x-distance w (dz = |dx| (x - z) / w), and
    y = x - c (x - z); the loop is 2 c w high."""

    def __init__(self, width_v, coupling):
        self.w, self.c = width_v, coupling

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        out, z, xp = np.empty_like(x), x[0], x[0]
        for i, xi in enumerate(x):
            z += min(abs(xi - xp) / self.w, 1.0) * (xi - z)
            xp = xi
            out[i] = xi - self.c * (xi - z)
        return out


class AsymmetricPlays(SimOnly):
    """Plays with different rising and falling radii on the force path: the core sees F + sum w_i (p_i(F) - F)."""

    def __init__(self, up_n, down_n, weights):
        self.up, self.down, self.w = np.asarray(up_n), np.asarray(down_n), np.asarray(weights)

    def forward(self, t_s, x, aux=None, state=None):
        f = np.asarray(x, dtype=float)
        out, p = np.empty_like(f), np.full(self.w.size, f[0])
        for i, fi in enumerate(f):
            p = np.maximum(fi - self.up, np.minimum(fi + self.down, p))
            out[i] = fi + float(self.w @ (p - fi))
        return out


class Stiction(SimOnly):
    """Coulomb friction with a breakaway: the contact holds until the force moves ``breakaway_n`` from where it
    stuck, then slides ``sliding_n`` behind it; it sticks again when the force turns."""

    def __init__(self, breakaway_n, sliding_n):
        self.rs, self.rk = breakaway_n, sliding_n

    def forward(self, t_s, x, aux=None, state=None):
        f = np.asarray(x, dtype=float)
        out, held, direction = np.empty_like(f), f[0], 0.0
        for i, fi in enumerate(f):
            if direction and np.sign(fi - held) == direction and abs(fi - held) >= self.rk:
                held = fi - direction * self.rk  # sliding
            elif abs(fi - held) > self.rs:
                direction = float(np.sign(fi - held))
                held = fi - direction * self.rk
            elif direction:
                direction = 0.0  # turned: stuck again
            out[i] = held
        return out


class SincCubed(SimOnly):
    """A sigma-delta ADC's sinc^3 decimation filter: three moving averages of one notch period each."""

    def __init__(self, notch_hz):
        self.notch = notch_hz

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        n = max(1, int(round(1.0 / self.notch / float(np.median(np.diff(t_s))))))
        y = np.concatenate([np.full(3 * n, x[0]), x])
        for _ in range(3):
            y = signal.lfilter(np.ones(n) / n, [1.0], y)
        return y[3 * n:]


class SplitClockBurgers(SimOnly):
    """A Burgers core whose Kelvin viscosity follows temperature (ln a(T) = log_shift(T)) while its flow does not."""

    def __init__(self, core, log_shift):
        self.core, self.log_shift = core, log_shift

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        rate = np.exp(-self.log_shift(np.broadcast_to(aux["temperature_c"], t.shape)))
        xi = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(t))])
        c = self.core
        maxwell = simulate_deformation(Maxwell(c.k1_n_per_v, c.eta1_n_s_per_v), t, f)
        return maxwell + kelvin(xi, f, 1.0 / c.k2_n_per_v, c.eta2_n_s_per_v / c.k2_n_per_v)


class ShiftedBurgers(SimOnly):
    """A Burgers core on the reduced time of ln a(T) = log_shift(T)."""

    def __init__(self, core, log_shift):
        self.core, self.log_shift = core, log_shift

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        rate = np.exp(-self.log_shift(np.broadcast_to(aux["temperature_c"], t.shape)))
        xi = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(t))])
        return simulate_deformation(self.core, xi, np.asarray(x, dtype=float))


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    span = FORCE_MAX_N / c.relaxation().g0_n_per_v * 2.0  # ~ the core's output over the force range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        if shape == "maxwell_from_elastic":
            eta = float(np.exp(np.interp(m, [0, 1], np.log([1e5, 2e3]))) * rng.uniform(0.7, 1.4))
            return Parts("elastic", Maxwell(c.k1_n_per_v, eta), core_changed=True)
        eta = float(np.exp(np.interp(m, [0, 1], np.log([5e5, 2e4]))) * rng.uniform(0.7, 1.4))
        return Parts("zener", Burgers(c.k1_n_per_v, c.k2_n_per_v, eta, c.eta2_n_s_per_v), core_changed=True)
    if effect == "delayed_elasticity":
        if shape == "from_maxwell":
            k2 = float(np.interp(m, [0, 1], [60.0, 5.0]) * rng.uniform(0.8, 1.2))
            return Parts("maxwell", Burgers(c.k1_n_per_v, k2, c.eta1_n_s_per_v, k2 * rng.uniform(1.0, 60.0)),
                         core_changed=True)
        total = float(np.interp(m, [0, 1], [0.015, 0.15])) / c.k1_n_per_v  # extra compliance, V/N
        taus = np.sort(np.exp(rng.uniform(np.log(0.5), np.log(200.0), 3)))
        share = rng.dirichlet(np.ones(3))
        p.extra.append(lambda t, f, T, s=share * total, taus=taus: sum(kelvin(t, f, sk, tk) for sk, tk in zip(s, taus)))
        return p
    if effect == "hysteresis":
        frac = np.interp(m, [0, 1], [0.02, 0.08])
        if shape == "duhem_voltage":
            w = rng.uniform(0.05, 0.3) * span
            p.after.append(DuhemLoop(w, min(0.9, frac * span / (2 * w))))
            return p
        n = int(rng.integers(2, 5))
        up = np.sort(rng.uniform(0.02, 0.3, n)) * FORCE_MAX_N
        down = up * rng.uniform(0.3, 2.0, n)
        w = rng.uniform(0.3, 1.0, n)
        w *= frac * FORCE_MAX_N / np.sum(w * (up + down))
        p.before.append(AsymmetricPlays(up, down, w))
        return p
    if effect == "sensor_lag":
        if shape == "sinc_cubed":
            p.after.append(SincCubed(float(np.exp(np.interp(m, [0, 1], np.log([60.0, 10.0]))))))
            return p
        taus = np.exp(np.interp(m, [0, 1], np.log([0.005, 0.15]))) * rng.uniform([0.3, 0.8], [0.6, 1.2])
        p.after += [SensorLagElement(tau_s=float(taus[0])), SensorLagElement(tau_s=float(taus[1]))]
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.02, 0.1]))
        if shape == "kinked":  # the slope changes by rel past a knee, over a softplus of 5 % of the span
            knee, width, sign = rng.uniform(0.1, 0.35) * span, 0.05 * span, rng.choice([-1, 1])
            rel *= 2.0  # the slope changes past the knee only
            p.after.append(StaticMap(lambda x, k=knee, w=width, s=sign * rel: x + s * w * np.logaddexp(0.0, (x - k) / w)))
            return p
        p.after.append(StaticMap(lambda x, s=span, r=rel: x * (1 - r * np.sqrt(np.abs(x) / s))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.003, 0.01]) * rng.choice([-1, 1]))
        if shape == "dead_time":
            delay = rng.uniform(10.0, 60.0)
            p.extra.append(lambda t, f, T, k=k, d=delay: k * (dead_time(t, T, d) - T_REF_C))
            return p
        theta = rng.uniform(4.0, 12.0)
        p.extra.append(lambda t, f, T, k=k, th=theta: k * th * np.expm1((T - T_REF_C) / th))
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.002, 0.01]) * rng.choice([-1, 1]))
        out = core_output(c)
        if shape == "excitation":  # the bridge's excitation follows temperature: zero and span scale together
            p.extra.append(lambda t, f, T, a=a, out=out: a * (T - T_REF_C) * (out(t, f) + OFFSET_V))
            return p
        delay = rng.uniform(15.0, 60.0)
        p.extra.append(lambda t, f, T, a=a, out=out, d=delay: a * (dead_time(t, T, d) - T_REF_C) * out(t, f))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.08]) * rng.choice([-1, 1]))
        if shape == "hinge":
            onset = rng.uniform(0.2, 0.6) * DURATION_S
            p.extra.append(lambda t, f, T, s=size, o=onset: s * np.maximum(t - t[0] - o, 0.0) / (DURATION_S - o))
            return p
        period, decay = rng.uniform(0.6, 1.5) * DURATION_S, rng.uniform(0.3, 1.0) * DURATION_S
        p.extra.append(lambda t, f, T, s=size, P=period, D=decay: s * np.sin(2 * np.pi * (t - t[0]) / P)
                       * np.exp(-(t - t[0]) / D))
        return p
    if effect == "resonance":
        if shape == "force_path":
            f0, zeta = rng.uniform(12.0, 50.0), rng.uniform(0.03, 0.2)
            p.before.append(SecondOrderLag(2 * np.pi * f0, zeta))
            return p
        p.after.append(SecondOrderLag(2 * np.pi * rng.uniform(60.0, 120.0), rng.uniform(0.02, 0.1)))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "stiction":
            p.before.append(Stiction(r, r * rng.uniform(0.4, 0.8)))
            return p
        ratio, share = rng.uniform(2.0, 4.0), rng.uniform(0.3, 0.7)
        p.before.append(PlayHysteresisElement(1e-6, [r, r * ratio], [share - 1e-6, 1.0 - share]))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.06, 0.2])) * rng.uniform(0.8, 1.2)  # slope of -ln a at the reference
        if shape == "vogel_fulcher":  # ln a = B / (T - T_inf) - B / (T_ref - T_inf)
            gap = rng.uniform(50.0, 120.0)
            big_b = b * gap ** 2

            def log_shift(T, B=big_b, g=gap):
                return B / (T - T_REF_C + g) - B / g
            return Parts("burgers", ShiftedBurgers(c, log_shift), core_changed=True)
        return Parts("burgers", SplitClockBurgers(c, lambda T, b=b: -b * (T - T_REF_C)), core_changed=True)
    if effect == "mains_hum":
        amp, hz, phase = float(np.interp(m, [0, 1], [0.004, 0.012])), rng.choice([50.0, 60.0]), rng.uniform(0, 6.3)
        p.extra.append(lambda t, f, T, a=amp, hz=hz, ph=phase: a * np.sin(2 * np.pi * hz * t + ph))
        return p
    if effect == "span_step":
        g, at = float(np.interp(m, [0, 1], [0.03, 0.08]) * rng.choice([-1, 1])), rng.uniform(0.3, 0.7) * DURATION_S
        out = core_output(c)
        p.extra.append(lambda t, f, T, g=g, at=at, out=out: g * (t - t[0] >= at) * out(t, f))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["maxwell_from_elastic", "slow_flow"], "delayed_elasticity": ["three_times", "from_maxwell"],
    "hysteresis": ["duhem_voltage", "asymmetric_plays"], "sensor_lag": ["sinc_cubed", "two_real_poles"],
    "nonlinear_gain": ["kinked", "square_root"], "thermal_drift": ["dead_time", "exponential"],
    "thermal_sensitivity": ["excitation", "span_dead_time"], "offset_drift": ["hinge", "damped_wave"],
    "resonance": ["force_path", "high_mode"], "friction": ["stiction", "two_seals"],
    "thermo_rheological": ["vogel_fulcher", "kelvin_only"],
}
PAIRS = (("hysteresis", "thermal_drift"), ("sensor_lag", "offset_drift"), ("friction", "thermal_sensitivity"),
         ("resonance", "viscous_flow"), ("delayed_elasticity", "nonlinear_gain"), ("thermo_rheological", "hysteresis"))
OUTSIDE = ("mains_hum", "span_step")
RATES = (300.0, 600.0, 800.0)


SPLIT = ShapeSplit("independent split C", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8), pair_shapes=(0, -1),
                   rates=RATES, profiles=PROFILES, temperature=temperature, make_parts=make_parts,
                   duration_s=DURATION_S, noise_v=(1.5e-3, 3e-3), jitter=0.2, gap_s=(0.1, 1.0))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
