"""Bench experiments with one physical effect hidden in them (tests of the discrepancy workflow).

A bench record is a random load profile (holds, rests, ramps, reversals,
fast steps, short sine bursts) applied to a sensor whose truth is a base
viscoelastic model plus, optionally, one effect of the catalogue at a given
magnitude. Temperature always varies (independently of the load), so its
mere presence gives nothing away. The discrepancy workflow is never told
which effect was hidden.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..physics.chain import (
    NonlinearGainElement, OffsetDriftElement, OffsetElement, PreisachElement, SensorChain, SensorLagElement,
    ThermalDriftElement, ViscoelasticElement,
)
from ..physics.preisach import PreisachModel
from ..physics.viscoelastic import PAPER_BURGERS, Burgers, Burgers2, Elastic, Maxwell, Zener, Zener2
from .sensor import BridgeSimulator

EFFECTS = ("none", "viscous_flow", "delayed_elasticity", "hysteresis", "sensor_lag", "nonlinear_gain", "thermal_drift",
           "offset_drift")

#: The base model's truth (what a fit of the base can describe exactly) for each base type.
BASE_TRUTH = {
    "elastic": Elastic(3.24),
    "maxwell": Maxwell(4.8, 4627.94),
    "zener": Zener(4.8, 10.0, 85.12),
    "burgers": PAPER_BURGERS,
}


def random_load(duration_s, rate_hz, seed):
    """Force (N) of a random bench session: holds, rests, ramps, reversals, fast steps, sine bursts."""
    rng = np.random.default_rng(seed)
    knots_t, knots_f, bursts = [0.0, 2.0], [0.0, 0.0], []
    t_now, f_now = 2.0, 0.0
    while t_now < duration_s:
        kind = rng.choice(["hold", "rest", "ramp", "triangle", "fast", "sine"], p=[0.25, 0.15, 0.2, 0.15, 0.15, 0.1])
        if kind == "hold":
            level = rng.uniform(1.0, 8.0)
            rise = rng.uniform(0.1, 1.0)
            dur = rng.uniform(8.0, 40.0)
            knots_t += [t_now + rise, t_now + rise + dur]
            knots_f += [level, level]
            t_now, f_now = t_now + rise + dur, level
        elif kind == "rest":
            fall = rng.uniform(0.1, 1.0)
            dur = rng.uniform(8.0, 30.0)
            knots_t += [t_now + fall, t_now + fall + dur]
            knots_f += [0.0, 0.0]
            t_now, f_now = t_now + fall + dur, 0.0
        elif kind == "ramp":
            target = rng.uniform(0.0, 9.0)
            dur = abs(target - f_now) / rng.uniform(0.3, 3.0) + 0.1
            knots_t.append(t_now + dur)
            knots_f.append(target)
            t_now, f_now = t_now + dur, target
        elif kind == "triangle":
            peak = rng.uniform(2.0, 9.0)
            rate = rng.uniform(0.5, 3.0)
            for _ in range(rng.integers(2, 5)):
                knots_t += [t_now + abs(peak - f_now) / rate + 0.05]
                knots_f += [peak]
                t_now, f_now = knots_t[-1], peak
                low = rng.uniform(0.0, 0.4 * peak)
                knots_t += [t_now + (peak - low) / rate + 0.05]
                knots_f += [low]
                t_now, f_now = knots_t[-1], low
        elif kind == "fast":
            for _ in range(rng.integers(2, 6)):
                target = rng.uniform(0.0, 8.0)
                knots_t += [t_now + rng.uniform(0.02, 0.05), t_now + rng.uniform(1.0, 3.0)]
                knots_f += [target, target]
                t_now, f_now = knots_t[-1], target
        else:  # a short sine burst around the current level
            dur = rng.uniform(3.0, 10.0)
            bursts.append((t_now, t_now + dur, rng.uniform(0.5, 5.0), rng.uniform(0.2, 1.0)))
            knots_t.append(t_now + dur)
            knots_f.append(max(f_now, 1.2))
            t_now, f_now = t_now + dur, max(f_now, 1.2)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.interp(t, knots_t, knots_f)
    for start, stop, freq, amp in bursts:
        inside = (t >= start) & (t < stop)
        f[inside] += amp * np.sin(2 * np.pi * freq * (t[inside] - start))
    return t, np.clip(f, 0.0, None)


def random_temperature(t_s, seed):
    """A slow, load-independent temperature swing of 2-6 degC around 24 degC (degC)."""
    rng = np.random.default_rng(seed + 99)
    period = rng.uniform(150.0, 400.0)
    return 24.0 + rng.uniform(2.0, 6.0) * np.sin(2 * np.pi * np.asarray(t_s) / period + rng.uniform(0, 2 * np.pi))


def hysteretic_identity(u_min, u_max, loop_fraction, n_levels=24):
    """A continuous Preisach operator close to y = u (y = u_min at rest) with a loop of ``loop_fraction`` of the span.

    Diagonal relays are reversible ramps (the identity part); weight moved to a
    band off the diagonal opens the loop.
    """
    n = n_levels
    i, j = np.tril_indices(n)
    density = np.zeros((n, n))
    off = np.exp(-(((i - j) - 0.3 * n) / (0.15 * n)) ** 2) * (i != j)
    diag = (i == j).astype(float)
    share = min(max(3.0 * loop_fraction, 0.0), 0.9)
    density[i, j] = (1 - share) * diag / diag.sum() + share * off / off.sum()
    density *= (u_max - u_min) / 2.0
    return PreisachModel(u_min, u_max, density, offset=u_min + (u_max - u_min) / 2.0)


@dataclass
class BenchCase:
    effect: str
    magnitude: float  # 0..1, from barely detectable to large
    base: str
    truth: SensorChain
    seed: int


def truth_chain(effect, magnitude, base="burgers", seed=0, force_range_n=10.0):
    """The sensor truth: the base model plus one effect of relative size ``magnitude`` (0..1)."""
    rng = np.random.default_rng(seed + 1234)
    core = BASE_TRUTH[base]
    m = float(np.clip(magnitude, 0.0, 1.0))
    before, extra = [], []
    if effect == "viscous_flow":
        if base not in ("elastic", "zener"):
            raise ValueError("viscous_flow is hidden against an elastic or zener base")
        eta1 = float(np.exp(np.interp(m, [0, 1], np.log([40000.0, 1500.0]))))
        core = Maxwell(core.k_n_per_v, eta1) if base == "elastic" else Burgers(core.k1_n_per_v, core.k2_n_per_v, eta1, core.eta2_n_s_per_v)
    elif effect == "delayed_elasticity":
        if base == "kelvin":
            raise ValueError("delayed_elasticity is hidden against an elastic, maxwell, zener or burgers base")
        k_new = float(np.interp(m, [0, 1], [60.0, 6.0]))
        if base in ("elastic", "maxwell"):
            tau = rng.uniform(3.0, 15.0)
            core = (Zener(core.k_n_per_v, k_new, k_new * tau) if base == "elastic"
                    else Burgers(core.k_n_per_v, k_new, core.eta_n_s_per_v, k_new * tau))
        else:  # a second Kelvin element, faster than the base's own (8.5 s)
            tau = rng.uniform(0.8, 2.5)
            core = (Zener2(core.k1_n_per_v, core.k2_n_per_v, core.eta2_n_s_per_v, k_new, k_new * tau) if base == "zener"
                    else Burgers2(core.k1_n_per_v, core.k2_n_per_v, core.eta1_n_s_per_v, core.eta2_n_s_per_v, k_new, k_new * tau))
    elif effect == "hysteresis":
        # rate-independent hysteresis of the force path (friction in the mechanism), before the core
        before.append(PreisachElement(hysteretic_identity(0.0, force_range_n, loop_fraction=0.01 + 0.07 * m), continuous=True))
    elif effect == "sensor_lag":
        extra.append(SensorLagElement(tau_s=float(np.interp(m, [0, 1], [0.01, 0.15]))))
    elif effect == "nonlinear_gain":
        extra.append(NonlinearGainElement(quadratic_per_v=float(np.interp(m, [0, 1], [0.005, 0.05]) * rng.choice([-1, 1]))))
    elif effect == "thermal_drift":
        extra.append(ThermalDriftElement(coefficient_v_per_c=float(np.interp(m, [0, 1], [0.001, 0.01])), reference_c=24.0))
    elif effect == "offset_drift":
        extra.append(OffsetDriftElement(rate_v_per_s=float(np.interp(m, [0, 1], [2e-5, 2e-4]) * rng.choice([-1, 1]))))
    elif effect != "none":
        raise ValueError(f"unknown effect {effect!r}; choose from {EFFECTS}")
    return SensorChain([*before, ViscoelasticElement(core), *extra, OffsetElement(0.05)])


def simulate_bench(effect, magnitude, base="burgers", duration_s=600.0, rate_hz=200.0, seed=0, noise_std_v=1e-3):
    """(t_s, force_n, voltage_v, temperature_c, BenchCase) of a bench session with the effect hidden."""
    t, f = random_load(duration_s, rate_hz, seed)
    temp = random_temperature(t, seed)
    chain = truth_chain(effect, magnitude, base, seed)
    volts = BridgeSimulator(chain=chain, noise_std_v=noise_std_v, seed=seed).simulate(t, f, temperature_c=temp)
    return t, f, volts, temp, BenchCase(effect, magnitude, base, chain, seed)


def write_bench_bag(path, effect, magnitude, base="burgers", duration_s=600.0, rate_hz=200.0, seed=0):
    """Write a hidden-effect bench session as a bag of the topic contract; returns the BenchCase."""
    from .recording import write_bench_bag as write

    t, f, volts, temp, case = simulate_bench(effect, magnitude, base, duration_s, rate_hz, seed)
    write(path, t, f, volts, temperature_c=temp, temperature_every=max(1, int(rate_hz / 10)))
    return case
