"""What the independent splits built from sensor pieces (C, D and S on) share: the pieces, the random core, the knocks
that excite a mode, the small tools their shapes are written with (smooth steps, windows, lags, clocks, schedules, sizes
over a horizon), and :class:`ShapeSplit`, which simulates, diagnoses, scores and checks a split's cases.

A split module declares its shapes, pairs, profiles, temperature and ``make_parts(effect, shape, m, core, rng) ->
Parts``, and runs ``ShapeSplit(...).main(__doc__)``.
"""
from __future__ import annotations

import argparse
import math
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from scipy import integrate, optimize, signal
from tqdm import tqdm

from independent_split import Truth, as_recorded, case_list, compensates, puncture_train, summarise, verdict_with
from polyforce_ros.discrepancy.engine import diagnose
from polyforce_ros.physics.chain import OffsetElement, SensorChain, ViscoelasticElement
from polyforce_ros.physics.expconv import exp_convolve
from polyforce_ros.physics.viscoelastic import Burgers, Zener, simulate_deformation
from polyforce_ros.sim import profiles

OFFSET_V = 0.025
DRIFTS = frozenset({"offset_drift", "thermal_drift"})


class SimOnly:
    """A truth element that only simulates (stateless between blocks)."""

    kind = "sim"

    def forward_state(self):
        return {}


class GridMode(SimOnly):
    """A simulated element (a mode) that runs from rest on a uniform grid of ``fs`` Hz: the input less its first
    value is interpolated onto the grid, :meth:`on_grid` runs there (``t`` the record's times, ``tu`` the grid's,
    ``xu`` the input on it, ``h`` the step), and its output is read back at ``t`` with the first value added."""

    fs = 3000.0

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        h = 1.0 / self.fs
        tu = np.arange(t[0], t[-1] + h, h)
        return np.interp(t, tu, self.on_grid(t, tu, np.interp(tu, t, x) - x[0], h)) + x[0]

    def on_grid(self, t, tu, xu, h):
        raise NotImplementedError


@dataclass
class Parts:
    """A sensor in pieces, so that two effects can be put into one: elements before and after the core, the core
    (a model or a simulate-only element), elements after the offset, and terms added at the bridge."""

    base: str
    core: object
    before: list = field(default_factory=list)
    after: list = field(default_factory=list)
    outer: list = field(default_factory=list)
    extra: list = field(default_factory=list)
    core_changed: bool = False

    def truth(self):
        core = self.core if isinstance(self.core, SimOnly) else ViscoelasticElement(self.core)
        chain = SensorChain([*self.before, core, *self.after, OffsetElement(OFFSET_V), *self.outer],
                            forward_only=True)
        extras = list(self.extra)
        return Truth(chain, (lambda t, f, T: sum(x(t, f, T) for x in extras)) if extras else None)


def merge(a, b):
    """Both effects in one sensor: the base and core of whichever changed them, every other piece of both."""
    core_of = b if b.core_changed else a
    base = b.base if b.base != "burgers" else a.base
    return Parts(base, core_of.core, a.before + b.before, a.after + b.after, a.outer + b.outer, a.extra + b.extra,
                 a.core_changed or b.core_changed)


def core(rng):
    """A random Burgers core: k1 1-12 N/V, k2 2-60 N/V, eta1 1e3-2e5 N s/V, a retardation of 0.5-60 s."""
    k1, k2 = rng.uniform(1.0, 12.0), rng.uniform(2.0, 60.0)
    return Burgers(k1, k2, float(np.exp(rng.uniform(np.log(1e3), np.log(2e5)))), k2 * rng.uniform(0.5, 60.0))


def core_output(c):
    """The core's own output (without offset) as a function of the force history."""
    return lambda t, f: simulate_deformation(c, t, f)


def dead_time(t, x, delay_s):
    """``x`` as it was ``delay_s`` earlier, settled before the record."""
    return np.interp(t - delay_s, t, x, left=x[0])


def coarse(t, x, step_s=0.5):
    """``x`` on a grid of ``step_s`` over ``t`` (for slow thermal signals): (grid, values)."""
    grid = np.arange(t[0], t[-1] + step_s, step_s)
    return grid, np.interp(grid, t, x)


def kelvin(t, f, compliance_v_per_n, tau_s):
    """A Kelvin unit's deformation, tau x' + x = c F, from rest."""
    return compliance_v_per_n * exp_convolve(t, f, [1.0 / tau_s])[:, 0] / tau_s


def ramp_and_hold(knots_t, knots_f, now, level, ramp_s, hold_s):
    """Append to a piecewise-linear load the knots of a ramp of ``ramp_s`` to ``level`` and a hold of ``hold_s``
    from time ``now``; returns the time the hold ends."""
    knots_t += [now + ramp_s, now + ramp_s + hold_s]
    knots_f += [level, level]
    return now + ramp_s + hold_s


def repeated_insertions(duration_s, rate_hz, rng, one_insertion, force_max_n=9.0):
    """The measured Okamura insertion, reshaped by ``one_insertion(t, f, rng) -> force`` (a 1 N peak in, one
    insertion out), scaled to a 2-``force_max_n`` N peak and repeated with 5-30 s of rest from 3-10 s on; a train
    of synthetic punctures when ``../shared/data`` is absent."""
    try:
        tp, fp = profiles.okamura_insertion(peak_n=1.0, rate_hz=rate_hz)
    except FileNotFoundError:
        return puncture_train(duration_s, rate_hz, rng)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    start = rng.uniform(3.0, 10.0)
    while True:
        one = one_insertion(tp, fp, rng)
        i0 = int(start * rate_hz)
        if i0 + one.size >= t.size:
            break
        f[i0:i0 + one.size] = rng.uniform(2.0, force_max_n) * one / max(one.max(), 1e-9)
        start += one.size / rate_hz + rng.uniform(5.0, 30.0)
    return t, f


def band_play(f, up_n, down_n):
    """A play that sticks by ``up_n`` while ``f`` rises and by ``down_n`` while it falls (scalars, or one value per
    sample), started at ``f[0]``: the force a friction contact passes on."""
    f = np.asarray(f, dtype=float)
    up, down = np.broadcast_to(up_n, f.shape), np.broadcast_to(down_n, f.shape)
    out, p = np.empty_like(f), f[0]
    for i, fi in enumerate(f):
        p = max(fi - up[i], min(fi + down[i], p))
        out[i] = p
    return out


def dahl(x, y_max, sigma):
    """A Dahl state driven by ``x``: dy/dx = sigma (1 - y / y_max sign(dx)), from zero, held within +-y_max."""
    x = np.asarray(x, dtype=float)
    dx = np.diff(x, prepend=x[0])
    y, out = 0.0, np.empty_like(x)
    for i, step in enumerate(dx.tolist()):
        y += sigma * (1.0 - y / y_max * np.sign(step)) * step
        y = min(max(y, -y_max), y_max)
        out[i] = y
    return out


def relaxing_play(t, x, r, tau_s):
    """A play of half-width ``r`` whose stuck value creeps toward the input with ``tau_s``, started at ``x[0]``."""
    dt = np.diff(t, prepend=t[0])
    out, p = np.empty_like(x), x[0]
    for i, (xi, h) in enumerate(zip(x.tolist(), dt.tolist())):
        p += (xi - p) * (1.0 - np.exp(-h / tau_s))
        p = max(xi - r, min(xi + r, p))
        out[i] = p
    return out


class ForcePath(SimOnly):
    """A map of the force history before the core: ``fn(t, F)``."""

    def __init__(self, fn):
        self.fn = fn

    def forward(self, t_s, x, aux=None, state=None):
        return self.fn(np.asarray(t_s, dtype=float), np.asarray(x, dtype=float))


def uniform_grid(t, x):
    """``x`` on a uniform grid at the median step of ``t``: (grid, values, step). A simulated element that needs
    equal steps runs there and is read back at ``t`` by interpolation."""
    h = float(np.median(np.diff(t)))
    tu = np.arange(t[0], t[-1] + h, h)
    return tu, np.interp(tu, t, x), h


class LinearFilter(SimOnly):
    """A continuous-time filter (numerator, denominator in s), from rest, on a uniform grid at the median step."""

    def __init__(self, num, den):
        self.num, self.den = num, den

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        b, a = signal.bilinear(self.num, self.den, fs=1.0 / h)
        y = signal.lfilter(b, a, xu - x[0]) + x[0]
        return np.interp(t, tu, y)


class ShiftedBurgers(SimOnly):
    """A Burgers core whose flow alone (``flow_only``) or whole clock runs at the rate ``rate_of(T)``."""

    def __init__(self, c, rate_of, flow_only):
        self.c, self.rate_of, self.flow_only = c, rate_of, flow_only

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        rate = self.rate_of(np.broadcast_to(aux["temperature_c"], t.shape))
        xi = integrate.cumulative_trapezoid(rate, t, initial=0.0)  # the reduced time
        if not self.flow_only:
            return simulate_deformation(self.c, xi, f)
        zener = Zener(self.c.k1_n_per_v, self.c.k2_n_per_v, self.c.eta2_n_s_per_v)
        integrand = rate * f / self.c.eta1_n_s_per_v
        flow = integrate.cumulative_trapezoid(integrand, t, initial=0.0)
        return simulate_deformation(zener, t, f) + flow


def with_knocks(t, f, rng):
    """20-40 knocks on the tool (raised-cosine pulses of 5-15 ms, 0.3-1.5 N): what excites a mechanical mode in
    use. A mode that nothing excites cannot be seen, so every case that hides one has them."""
    f = f.copy()
    rate = 1.0 / float(np.median(np.diff(t)))
    for at in rng.uniform(0.05, 0.95, int(rng.integers(20, 41))) * t[-1]:
        width = rng.uniform(0.005, 0.015)
        i0, n = int(at * rate), max(2, int(width * rate))
        f[i0:i0 + n] += rng.uniform(0.3, 1.5) * 0.5 * (1 - np.cos(2 * np.pi * np.arange(n)[:n] / n))[:f[i0:i0 + n].size]
    return t, f


def ease(u):
    """A minimum-jerk blend: 0 at and below 0, 1 at and above 1."""
    u = np.clip(u, 0.0, 1.0)
    return u ** 3 * (6.0 * u * u - 15.0 * u + 10.0)


def cutter(t):
    """``cut(start, length)`` -> (the index slice of ``t`` in [start, start + length), the seconds since start)."""
    def cut(start, length):
        i0, i1 = np.searchsorted(t, [start, start + max(length, 0.0)])
        return slice(int(i0), int(i1)), t[i0:i1] - start
    return cut


def temp_of(aux, n):
    """The chain's temperature, one value per sample."""
    return np.broadcast_to(np.asarray(aux["temperature_c"], dtype=float), (n,))


def follow(t, x, tau_s, step_s=0.5):
    """``x`` seen through a first-order lag of ``tau_s`` (exact per coarse step of ``step_s``), at rest with its
    first value before the record."""
    grid = np.arange(t[0], t[-1] + step_s, step_s)
    xg = np.interp(grid, t, x)
    keep = math.exp(-step_s / tau_s)
    yg, _ = signal.lfilter([1.0 - keep], [1.0, -keep], xg, zi=[keep * xg[0]])
    return np.interp(t, grid, yg)


def sized(fn, size, horizon_s):
    """``fn(s)`` (zero at s = 0) scaled so that its largest magnitude over [0, ``horizon_s``) is ``|size|``, with the sign of
    ``size``."""
    probe = np.abs(fn(np.arange(0.0, horizon_s, 0.1)))
    scale = size / max(float(probe.max()), 1e-12)
    return lambda s: scale * fn(s)


def fit_departure(read, rel, reach, k_top, points=401):
    """``read(x, k)`` with the k in (0, ``k_top``] whose largest departure from x over [0, ``reach``] is ``rel`` of
    ``reach`` (on ``points`` values) (``k_top`` when even that departs less)."""
    xs = np.linspace(0.0, reach, points)

    def miss(k):
        return float(np.max(np.abs(read(xs, k) - xs))) / reach - rel
    if miss(k_top) <= 0.0:
        return lambda x: read(x, k_top)
    lo = k_top
    while miss(lo) > 0.0 and lo > k_top * 1e-6:
        lo *= 0.5
    k = optimize.brentq(miss, lo, k_top, xtol=k_top * 1e-9)
    return lambda x: read(x, k)


def on_clock(c, t, f, rate):
    """The core's deformation when its clock runs at ``rate`` (reduced time from t[0])."""
    return simulate_deformation(c, t[0] + integrate.cumulative_trapezoid(rate, t, initial=0.0), f)


def coarse_force(t, f, step_s):
    """The force on a grid of ``step_s`` over ``t``: (grid, values)."""
    grid = np.arange(t[0], t[-1] + step_s, step_s)
    return grid, np.interp(grid, t, f)


class LeakingCore(SimOnly):
    """A Zener core (the Burgers core's springs and Kelvin dashpot, no dashpot of its own in series) whose output gains
    a leak, ``rule(t, F) -> V`` (a Zener sensor and nothing more when ``rule`` is None)."""

    def __init__(self, zener, rule):
        self.zener, self.rule = zener, rule

    @classmethod
    def of(cls, c, rule):
        return cls(Zener(c.k1_n_per_v, c.k2_n_per_v, c.eta2_n_s_per_v), rule)

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        held = simulate_deformation(self.zener, t, f)
        return held + (0.0 if self.rule is None else self.rule(t, f))


def quintic(u):
    """A smooth step from 0 to 1 over ``u`` in [0, 1] (zero speed and acceleration at both ends)."""
    u = np.clip(u, 0.0, 1.0)
    return ((6.0 * u - 15.0) * u + 10.0) * u ** 3


def schedule(rng, every_s, length_s, horizon_s):
    """Sessions (start, length) in seconds since the first sample: lengths drawn from ``length_s``, the gaps between
    them from ``every_s``, the first gap from its lower bound down to minus a length (the first may be under way),
    until ``horizon_s``."""
    out, now = [], rng.uniform(-length_s[0], every_s[0])
    while now < horizon_s:
        length = rng.uniform(*length_s)
        out.append((now, length))
        now += length + rng.uniform(*every_s)
    return out


def within(s, sessions):
    """Whether each time of ``s`` falls in one of ``sessions`` (start, length)."""
    on = np.zeros(s.size, dtype=bool)
    for start, length in sessions:
        on |= (s >= start) & (s < start + length)
    return on


def logistic(u):
    """1 / (1 + exp(-u)), without overflow."""
    return 0.5 * (1.0 + np.tanh(0.5 * np.asarray(u, dtype=float)))


class ZenerWithFlow(SimOnly):
    """A Zener core (the Burgers core without its dashpot) plus a flow ``rule(t, F) -> V``."""

    def __init__(self, c, rule):
        self.zener, self.rule = Zener(c.k1_n_per_v, c.k2_n_per_v, c.eta2_n_s_per_v), rule

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        return simulate_deformation(self.zener, t, f) + self.rule(t, f)


def lagged(t, x, tau_s):
    """``x`` through a first-order lag of ``tau_s``, settled at ``x[0]`` before the record."""
    return x[0] + kelvin(t, x - x[0], 1.0, tau_s)


def mode_steps(t, x, sub=4):
    """A mode driven by ``x`` on a uniform grid at the median step: (grid, drive, its rate, sub-step)."""
    tu, xu, h = uniform_grid(t, x)
    return tu, xu.tolist(), np.gradient(xu, h).tolist(), h / sub


@dataclass(frozen=True)
class ShapeSplit:
    """A split of cases built from :class:`Parts`: which shapes, how they are recorded, and the runs over them.

    ``profiles`` are ``(duration_s, rate_hz, rng) -> (t, force)``; ``temperature`` is ``(t, rng) -> degC``;
    ``make_parts`` is ``(effect, shape, magnitude, core, rng) -> Parts``; ``noise_v`` the range the bridge noise's
    RMS is drawn from; ``jitter`` and ``gap_s`` as :func:`independent_split.as_recorded`."""

    label: str
    seed0: int
    shapes: dict
    pairs: tuple
    outside: tuple
    magnitudes: tuple
    pair_shapes: tuple
    rates: tuple
    profiles: tuple
    temperature: Callable
    make_parts: Callable
    duration_s: float
    noise_v: tuple
    jitter: float
    gap_s: tuple

    def cases(self):
        return case_list(self.shapes, self.pairs, self.outside, self.magnitudes, self.pair_shapes)

    def sensor(self, hidden, m, rng):
        c, parts = core(rng), None
        for effect, shape in hidden or [("none", "")]:
            one = self.make_parts(effect, shape, m, c, rng)
            parts = one if parts is None else merge(parts, one)
        return parts.base, parts.truth()

    def rate(self, hidden, i):
        return 1000.0 if any(e == "resonance" for e, _ in hidden) else self.rates[i % len(self.rates)]

    def load(self, hidden, i, rate, rng):
        t, f = self.profiles[i % len(self.profiles)](self.duration_s, rate, rng)
        return with_knocks(t, f, rng) if any(e == "resonance" for e, _ in hidden) else (t, f)

    def simulate(self, hidden, m, i):
        rng = np.random.default_rng(self.seed0 + i)
        rate = self.rate(hidden, i)
        t, f = self.load(hidden, i, rate, rng)
        temp = self.temperature(t, rng)
        base, truth = self.sensor(hidden, m, rng)
        v = truth.voltage(t, f, temp) + rng.normal(0.0, rng.uniform(*self.noise_v), t.size)
        rec = as_recorded(t, f, v, temp, i, rate, rng, self.duration_s, jitter=self.jitter, gap_s=self.gap_s)
        return rec, truth, base, rate

    def run_case(self, item):
        """Diagnose case ``item = (i, (hidden, m))`` and score it; a correctly named case without a drift also
        compensates a new record of the sensor."""
        i, (hidden, m) = item
        rec, truth, base, rate = self.simulate(hidden, m, i)
        d = diagnose(rec, base=base)
        row = {"index": i, "hidden": ["/".join(h) for h in hidden], "magnitude": m, "rate_hz": rate, "base": base,
               "answer": d.missing_effect, "named": d.missing_effects,
               "verdict": verdict_with(self.outside, hidden, d)}
        if row["verdict"] == "ok" and hidden and not ({e for e, _ in hidden} & (DRIFTS | set(self.outside))):
            row["compensated_rmse_fraction_of_full_scale"] = compensates(d, truth, rate, i, seed0=self.seed0,
                                                                         temperature_fn=self.temperature)
        return row

    def check_case(self, item):
        """The hidden effects' size on the bridge: the RMS of the voltage they add, in units of 2 mV; a leak on a
        Zener base (:class:`LeakingCore`) against that bare Zener core, with neither the leak nor the other hidden
        effect (nan when another effect changes the base)."""
        i, (hidden, m) = item
        rate = self.rate(hidden, i)
        voltages = []
        for what in (hidden, []):
            rng = np.random.default_rng(self.seed0 + i)
            t, f = self.load(hidden, i, rate, rng)
            temp = self.temperature(t, rng)
            base, truth = self.sensor(what, m, rng)
            leaking = [e for e in truth.chain.elements if isinstance(e, LeakingCore)]
            if what and leaking:
                bare = Parts(base, LeakingCore(leaking[0].zener, None)).truth()
                voltages = [truth.voltage(t, f, temp), bare.voltage(t, f, temp)]
                break
            if what and base != "burgers":
                return i, hidden, float("nan")
            voltages.append(truth.voltage(t, f, temp))
        gap = voltages[0] - voltages[1]
        return i, hidden, float(np.sqrt(np.mean((gap - gap.mean()) ** 2)) / 2e-3)

    def main(self, doc):
        ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
        ap.add_argument("--json", help="write every case as JSON")
        ap.add_argument("--workers", type=int, default=1, help="processes")
        ap.add_argument("--stride", type=int, default=1, help="run every n-th case only")
        ap.add_argument("--check", action="store_true", help="print each case's effect size only (no diagnosis)")
        args = ap.parse_args()
        todo = list(enumerate(self.cases()))[::args.stride]
        t0 = time.perf_counter()
        with ProcessPoolExecutor(args.workers) as pool:
            if args.check:
                for i, hidden, size in pool.map(self.check_case, todo):
                    print(f"{i:3d} {'+'.join('/'.join(h) for h in hidden) or 'clean':<60} effect RMS {size:6.1f} x 2 mV")
                return
            results = list(tqdm(pool.map(self.run_case, todo), total=len(todo), desc=self.label))
        summarise(results, time.perf_counter() - t0, self.label, args.json)
