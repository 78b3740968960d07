"""An independent held-out split for ``polyforce diagnose``: shapes, ranges and profiles the engine never saw.

The tune and held-out splits of ``bench/discrepancy_matrix.py`` draw their truths from the effect registry's own
families. This split does not: every effect appears in other shapes (an arctan saturation, a logarithmic or a
sigmoid drift, a quadratic thermal zero, a span quadratic in temperature, a first-order lag up to 0.5 s, a plain
transport delay, a hysteresis added at the bridge), over ranges wider than the registry's, under other force
profiles (staircases with slow sines, trains of needle punctures, series of the measured Okamura insertion when
``../shared/data`` is present) and other recording conditions (200, 500 and 1000 Hz, stamp jitter, gaps). It is
run once per engine and never used to choose anything.

Each case is scored like the matrix (fully correct = exactly the hidden catalogue effects named; out of catalogue
= ``unexplained``; clean = ``none``). For every correctly named case without a drift the saved model also
compensates a new needle record of the same sensor, judged against 1 % of full scale RMSE.

    .venv/bin/python bench/independent_split.py [--json out.json] [--stride 1]
"""
from __future__ import annotations

import argparse
import json
import time
from collections import Counter

import numpy as np
from tqdm import tqdm

from polyforce_ros.discrepancy.effects import EFFECTS
from polyforce_ros.discrepancy.engine import diagnose
from polyforce_ros.physics.chain import (ModelError, OffsetElement, PlayHysteresisElement, SensorChain, SensorLagElement,
                                         ThermalLagElement, TransportDelayElement, ViscoelasticElement, play_operator)
from polyforce_ros.physics.viscoelastic import Burgers, Burgers2
from polyforce_ros.record import Record
from polyforce_ros.runtime import Compensator, CompensatorConfig
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import BoucWen, SecondOrderLag, StaticMap

SEED0 = 90_000  # never a seed of the registry's splits (0.. and 5000..)
DRIFTS = {"offset_drift", "thermal_drift"}


# ----------------------------------------------------------------------------- profiles and temperature

def staircase_sine(duration_s, rate_hz, rng):
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    edges = np.cumsum(rng.uniform(10.0, 60.0, 64))
    levels = rng.uniform(0.0, 8.0, edges.size) * (rng.random(edges.size) > 0.25)
    f = levels[np.minimum(np.searchsorted(edges, t), edges.size - 1)]
    f = np.convolve(f, np.ones(int(0.2 * rate_hz)) / int(0.2 * rate_hz), mode="same")  # 0.2 s ramps
    for _ in range(3):
        freq, amp = rng.uniform(0.05, 2.0), rng.uniform(0.2, 1.0)
        f += amp * np.sin(2 * np.pi * freq * t + rng.uniform(0, 2 * np.pi)) * (f > amp)
    return t, np.clip(f, 0.0, 9.5)


def puncture_train(duration_s, rate_hz, rng):
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    start = rng.uniform(3.0, 10.0)
    while start < duration_s - 35.0:
        tp, fp = profiles.needle_insertion(peak_n=rng.uniform(2.0, 9.0), punctures=int(rng.integers(1, 5)),
                                           seed=int(rng.integers(1 << 30)), rate_hz=rate_hz)
        i = int(start * rate_hz)
        n = min(fp.size, f.size - i)
        f[i:i + n] = fp[:n]
        start += tp[-1] + rng.uniform(5.0, 40.0)
    return t, f


def okamura_series(duration_s, rate_hz, rng):
    try:
        tp, fp = profiles.okamura_insertion(peak_n=1.0, rate_hz=rate_hz)
    except FileNotFoundError:
        return puncture_train(duration_s, rate_hz, rng)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    start = rng.uniform(3.0, 10.0)
    while start < duration_s - tp[-1]:
        i = int(start * rate_hz)
        n = min(fp.size, f.size - i)
        f[i:i + n] = rng.uniform(2.0, 9.0) * fp[:n]
        start += tp[-1] + rng.uniform(5.0, 40.0)
    return t, f


PROFILES = (staircase_sine, puncture_train, okamura_series)


def temperature(t, rng):
    """A ramp and a slow swing, 2-8 degC in all."""
    d = t[-1] - t[0]
    return (23.0 + rng.uniform(-2.0, 2.0) * (t - t[0]) / d
            + rng.uniform(1.0, 4.0) * np.sin(2 * np.pi * t / rng.uniform(100.0, 500.0) + rng.uniform(0, 6.3)))


# ----------------------------------------------------------------------------- truths

def core(rng):
    k1, k2 = rng.uniform(2.0, 8.0), rng.uniform(4.0, 40.0)
    return Burgers(k1, k2, rng.uniform(2e3, 6e4), k2 * rng.uniform(1.0, 30.0))


class Truth:
    """A sensor: a forward-only chain, plus terms added at the bridge that follow force, time or temperature."""

    def __init__(self, chain, extra=None):
        self.chain, self.extra = chain, extra

    def voltage(self, t, f, temp):
        v = self.chain.forward(t, f, aux={"temperature_c": temp})
        return v + (self.extra(t, f, temp) if self.extra else 0.0)


def _chain(before=(), c=None, after=(), late=()):
    return SensorChain([*before, ViscoelasticElement(c), *after, *late, OffsetElement(0.04)], forward_only=True)


def make_truth(effect, shape, m, rng, duration_s):
    c = core(rng)
    span = 9.0 / c.relaxation().g0_n_per_v * 2.0  # ~ the core's output over the force range, V
    if effect == "none":
        return "burgers", Truth(_chain(c=c))
    if effect == "viscous_flow":
        return "zener", Truth(_chain(c=Burgers(c.k1_n_per_v, c.k2_n_per_v, np.exp(rng.uniform(np.log(800), np.log(1e5))),
                                                c.eta2_n_s_per_v)))
    if effect == "delayed_elasticity":  # a second retardation of minutes, or of a fraction of a second
        tau = rng.uniform(60.0, 400.0) if shape == "minutes" else rng.uniform(0.3, 0.8)
        k3 = np.interp(m, [0, 1], [80.0, 8.0])
        return "burgers", Truth(_chain(c=Burgers2(c.k1_n_per_v, c.k2_n_per_v, c.eta1_n_s_per_v, c.eta2_n_s_per_v,
                                                   k3, k3 * tau)))
    if effect == "hysteresis":
        frac = np.interp(m, [0, 1], [0.015, 0.07])
        if shape == "bridge_plays":  # plays on the applied force, added at the bridge (no creep)
            radii = np.linspace(0.05, 0.25, 8) * 9.0
            w = rng.uniform(0.2, 1.0, 8)
            w *= frac * span / (2 * np.sum(w * radii))
            return "burgers", Truth(_chain(c=c), lambda t, f, T, r=radii, w=w: play_operator(f, r) @ w)
        if shape == "bouc_wen_n2":
            a = rng.uniform(0.5, 1.0)
            total = a / (frac * span / 2.0) ** 2  # n = 2: z_max = sqrt(A / (beta + gamma))
            return "burgers", Truth(_chain(c=c, after=[BoucWen(a, total * 0.6, total * 0.4, 2.0)]))
        radii = np.sort(rng.uniform(0.02, 0.6, 10)) * 9.0  # many wide stops on the force path
        w = rng.gamma(2.0, 1.0, 10)
        w *= frac * 9.0 / (2 * np.sum(w * radii))
        return "burgers", Truth(_chain(before=[PlayHysteresisElement(1.0 + w.sum(), radii + 1e-6 * np.arange(10), -w)],
                                       c=c))
    if effect == "sensor_lag":
        if shape == "slow_first_order":
            return "burgers", Truth(_chain(c=c, after=[SensorLagElement(tau_s=float(np.interp(m, [0, 1], [0.15, 0.5])))]))
        if shape == "delay":
            return "burgers", Truth(_chain(c=c, after=[TransportDelayElement(delay_s=float(np.interp(m, [0, 1],
                                                                                                     [0.005, 0.04])))]))
        tau, zeta = float(np.interp(m, [0, 1], [0.02, 0.1])), rng.uniform(0.6, 0.8)
        return "burgers", Truth(_chain(c=c, after=[SecondOrderLag(2 * zeta / tau, zeta)]))
    if effect == "nonlinear_gain":
        rel = np.interp(m, [0, 1], [0.02, 0.1])
        if shape == "arctan":
            s = span / np.sqrt(3 * rel)
            return "burgers", Truth(_chain(c=c, after=[StaticMap(lambda x, s=s: s * np.arctan(x / s))]))
        s = span / (2 * rel)  # logarithmic softening s log(1 + x / s) = x - x^2 / (2 s) ...
        return "burgers", Truth(_chain(c=c, after=[StaticMap(lambda x, s=s: s * np.log1p(np.maximum(x, -0.9 * s) / s))]))
    if effect == "thermal_drift":
        k = np.interp(m, [0, 1], [0.002, 0.012]) * rng.choice([-1, 1])
        if shape == "slow_lag":
            return "burgers", Truth(_chain(c=c, late=[ThermalLagElement(coefficient_v_per_c=k, reference_c=23.0,
                                                                        tau_s=rng.uniform(100.0, 300.0))]))
        return "burgers", Truth(_chain(c=c), lambda t, f, T, k=k: k * (T - 23.0) + 0.3 * abs(k) * (T - 23.0) ** 2)
    if effect == "thermal_sensitivity":
        a = np.interp(m, [0, 1], [0.001, 0.006]) * rng.choice([-1, 1])
        return "burgers", Truth(_chain(c=c), lambda t, f, T, a=a, cc=c: (a * (T - 23.0) + 0.2 * abs(a) * (T - 23.0) ** 2)
                                * _chain(c=cc).forward(t, f) - 0.04 * (a * (T - 23.0) + 0.2 * abs(a) * (T - 23.0) ** 2))
    if effect == "offset_drift":
        size = np.interp(m, [0, 1], [0.015, 0.1]) * rng.choice([-1, 1])
        if shape == "log":
            tau = rng.uniform(5.0, 60.0)
            return "burgers", Truth(_chain(c=c), lambda t, f, T: size * np.log1p((t - t[0]) / tau) / np.log1p(duration_s / tau))
        centre, width = rng.uniform(0.3, 0.7) * duration_s, rng.uniform(0.05, 0.2) * duration_s
        return "burgers", Truth(_chain(c=c), lambda t, f, T: size / (1 + np.exp(-((t - t[0]) - centre) / width)))
    if effect == "resonance":
        f0, zeta = rng.uniform(12.0, 40.0), rng.uniform(0.02, 0.1)
        return "burgers", Truth(_chain(c=c, after=[SecondOrderLag(2 * np.pi * f0, zeta)]))
    if effect == "friction":  # one play on the force the core sees: Coulomb friction in the mechanism
        r = np.interp(m, [0, 1], [0.05, 0.3])
        return "burgers", Truth(_chain(before=[PlayHysteresisElement(1e-6, [r], [1.0 - 1e-6])], c=c))
    if effect == "gain_drift":  # the span drifts over time
        g = np.interp(m, [0, 1], [0.01, 0.06]) * rng.choice([-1, 1])
        return "burgers", Truth(_chain(c=c), lambda t, f, T, cc=c: g * (t - t[0]) / duration_s
                                * (_chain(c=cc).forward(t, f) - 0.04))
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["wide_eta"], "delayed_elasticity": ["minutes", "subsecond"],
    "hysteresis": ["bridge_plays", "bouc_wen_n2", "wide_stops"],
    "sensor_lag": ["slow_first_order", "delay", "underdamped_pair"], "nonlinear_gain": ["arctan", "log"],
    "thermal_drift": ["quadratic", "slow_lag"], "thermal_sensitivity": ["quadratic_span"], "offset_drift": ["log", "sigmoid"],
}
PAIRS = (("hysteresis", "sensor_lag"), ("thermal_sensitivity", "offset_drift"), ("nonlinear_gain", "thermal_drift"))
OUTSIDE = ("resonance", "friction", "gain_drift")
RATES = (200.0, 500.0, 1000.0)


def case_list(shapes, pairs, outside, magnitudes, pair_shapes=(0, -1)):
    """A split's cases: every shape at each of ``magnitudes``, each pair at 0.7 (the first effect in its shape
    ``pair_shapes[0]``, the second in ``pair_shapes[1]``), each outside effect at 0.4 and 0.9, four clean records.
    Each case is (hidden [(effect, shape)], magnitude)."""
    out = []
    for effect, names in shapes.items():
        for shape in names:
            for m in magnitudes:
                out.append(([(effect, shape)], m))
    for a, b in pairs:
        out.append(([(a, shapes[a][pair_shapes[0]]), (b, shapes[b][pair_shapes[1]])], 0.7))
    for name in outside:
        for m in (0.4, 0.9):
            out.append(([(name, "")], m))
    out += [([], 0.0)] * 4
    return out


def cases():
    return case_list(SHAPES, PAIRS, OUTSIDE, (0.3, 0.9))


def simulate(hidden, m, i, duration_s=500.0):
    rng = np.random.default_rng(SEED0 + i)
    rate = RATES[i % len(RATES)]
    t, f = PROFILES[i % len(PROFILES)](duration_s, rate, rng)
    temp = temperature(t, rng)
    base, truths = "burgers", []
    for effect, shape in hidden or [("none", "")]:
        b, truth = make_truth(effect, shape, m, rng, duration_s)
        base = b if b != "burgers" else base
        truths.append(truth)
    truth = truths[0]
    if len(truths) > 1:  # a pair: the first's chain, the extras of both; the second's chain elements appended
        first, second = truths
        els = list(first.chain.elements[:-1]) + [e for e in second.chain.elements
                                                  if not isinstance(e, (ViscoelasticElement, OffsetElement))]
        extras = [x.extra for x in truths if x.extra]
        truth = Truth(SensorChain([*els, OffsetElement(0.04)], forward_only=True),
                      (lambda t, f, T: sum(x(t, f, T) for x in extras)) if extras else None)
    v = truth.voltage(t, f, temp) + rng.normal(0.0, 2e-3, t.size)
    rec = as_recorded(t, f, v, temp, i, rate, rng, duration_s, jitter=0.3, gap_s=(0.05, 0.5))
    return rec, truth, base, rate


def as_recorded(t, force, volts, temp, i, rate, rng, duration_s, jitter, gap_s):
    """The simulated record as the bench records it: stamps jittered by ``jitter`` of a sample on odd cases, ``i % 3``
    gaps of ``gap_s`` (min, max) seconds, 5 mN of noise on the reference force."""
    stamps = t + (jitter if i % 2 else 0.0) * rng.uniform(-1, 1, t.size) / rate
    keep = np.ones(t.size, dtype=bool)
    for _ in range(i % 3):
        s0 = rng.uniform(0.1, 0.9) * duration_s
        keep &= ~((t >= s0) & (t < s0 + rng.uniform(*gap_s)))
    return Record(stamps[keep] - stamps[keep][0], (force + rng.normal(0, 0.005, t.size))[keep], volts[keep], temp[keep])


def verdict(hidden, d):
    return verdict_with(OUTSIDE, hidden, d)


def verdict_with(outside, hidden, d):
    """Fully correct ("ok"), "missed" (a strict subset named) or "wrong", with ``outside`` the effects no catalogue
    name may answer."""
    names = {e for e, _ in hidden}
    if names & set(outside):
        return "ok" if d.missing_effect == "unexplained" else "wrong"
    if not names:
        return "ok" if d.missing_effect == "none" else "wrong"
    return "ok" if set(d.missing_effects) == names else ("missed" if set(d.missing_effects) < names else "wrong")


def compensates(d, truth, rate, i, seed0=None, temperature_fn=None):
    """RMSE of the saved model compensating a new record of the sensor (a train of needle punctures), as a fraction
    of full scale, against the reference as late as the model states; inf when the runtime refuses the model."""
    rng = np.random.default_rng((SEED0 if seed0 is None else seed0) + 50_000 + i)
    t, f = puncture_train(120.0, rate, rng)
    temp = (temperature if temperature_fn is None else temperature_fn)(t, rng)
    v = truth.voltage(t, f, temp) + rng.normal(0.0, 2e-3, t.size)
    try:  # the runtime's own guard: a model it refuses compensates nothing
        comp = Compensator(d.chain, CompensatorConfig(auto_tare=False, noise_gain_rate_hz=rate))
    except ModelError:
        return float("inf")
    used, out = comp.run(np.round(t * 1e9).astype(np.int64), v, temperature_c=temp)
    ref = np.interp(t - d.chain.latency_s, t, f, left=f[0])
    return float(np.sqrt(np.mean((out[used] - ref[used]) ** 2)) / np.ptp(f))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", help="write every case as JSON")
    ap.add_argument("--stride", type=int, default=1, help="run every n-th case only")
    args = ap.parse_args()
    todo = list(enumerate(cases()))[::args.stride]
    results, t0 = [], time.perf_counter()
    for i, (hidden, m) in tqdm(todo, desc="independent split"):
        rec, truth, base, rate = simulate(hidden, m, i)
        d = diagnose(rec, base=base)
        row = {"index": i, "hidden": ["/".join(h) for h in hidden], "magnitude": m, "rate_hz": rate, "base": base,
               "answer": d.missing_effect, "named": d.missing_effects, "verdict": verdict(hidden, d)}
        if row["verdict"] == "ok" and hidden and not ({e for e, _ in hidden} & (DRIFTS | set(OUTSIDE))):
            row["compensated_rmse_fraction_of_full_scale"] = compensates(d, truth, rate, i)
        results.append(row)
    summarise(results, time.perf_counter() - t0, "independent split", args.json)


def summarise(results, elapsed, label, json_path=None):
    """Print every case and the split's figures; write them as JSON to ``json_path`` when given."""
    ok = sum(r["verdict"] == "ok" for r in results)
    comp = [r["compensated_rmse_fraction_of_full_scale"] for r in results if "compensated_rmse_fraction_of_full_scale" in r]
    clean_named = sum(1 for r in results if not r["hidden"] and r["named"])
    print(f"\n{label}: {len(results)} diagnoses in {elapsed:.0f} s")
    for r in results:
        extra = (f"  compensated RMSE {100 * r['compensated_rmse_fraction_of_full_scale']:.2f} % FS"
                 if "compensated_rmse_fraction_of_full_scale" in r else "")
        print(f"{'+'.join(r['hidden']) or 'clean':<50} m={r['magnitude']:.2f} {r['rate_hz']:>6.0f} Hz  "
              f"{r['verdict']:<7} {'+'.join(r['named']) or r['answer']}{extra}")
    print(f"fully correct: {ok}/{len(results)} ({100 * ok / len(results):.1f} %); catalogue names on clean data: {clean_named}")
    print(f"saved models within 1 % FS RMSE on a new record: {sum(c <= 0.01 for c in comp)}/{len(comp)}")
    print("verdicts:", dict(Counter(r["verdict"] for r in results)))
    if json_path:
        with open(json_path, "w") as fh:
            json.dump({"results": results, "elapsed_s": elapsed, "catalogue": list(EFFECTS)}, fh, indent=1, default=float)


if __name__ == "__main__":
    main()
