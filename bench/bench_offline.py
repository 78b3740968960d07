"""Offline benchmarks 2-5 (docs/benchmarks.md): each figure beside its baseline, measured in the same run.

    .venv/bin/python bench/bench_offline.py [--quick]
"""
import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy import signal

sys.path.insert(0, str(Path(__file__).resolve().parent))

from polyforce_ros import bags  # noqa: E402
from polyforce_ros.physics.viscoelastic import PAPER_BURGERS, compensate  # noqa: E402
from polyforce_ros.sim import profiles  # noqa: E402
from polyforce_ros.sim.recording import write_bench_bag  # noqa: E402
from polyforce_ros.sim.sensor import BridgeSimulator  # noqa: E402


def best_of(fn, repeat=3):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def offline_compensation(n):
    t = np.arange(n) / 1000.0
    g = 0.3 * (2 + np.sin(2 * np.pi * 0.5 * t)) + np.random.default_rng(0).normal(0, 1e-3, n)
    ours = best_of(lambda: compensate(PAPER_BURGERS, t, g))
    ref = best_of(lambda: signal.lfilter([1.0], [1.0, -0.999], g))
    return {"samples": n, "ours_samples_per_s": n / ours, "lfilter_samples_per_s": n / ref, "ratio": ref / ours,
            "target": ">= 0.5"}


def bag_reading(n, tmp):
    path = Path(tmp) / "read.mcap"
    stamps = 1_700_000_000_000_000_000 + np.arange(n, dtype=np.int64) * 1_000_000
    with bags.BagWriter(path) as w:
        w.write_series(bags.BRIDGE_VOLTAGE, bags.JOINT_STATE, stamps, np.zeros(n))
        w.write_series(bags.REFERENCE_FORCE, bags.WRENCH_STAMPED, stamps, np.zeros(n))
    ours = best_of(lambda: bags.read_bag(path), repeat=2)
    from mcap_ros2.reader import read_ros2_messages

    def reference():
        out = [m.ros_msg for m in read_ros2_messages(str(path))]
        return len(out)

    ref = best_of(reference, repeat=1)
    return {"messages": 2 * n, "ours_msg_per_s": 2 * n / ours, "mcap_ros2_msg_per_s": 2 * n / ref, "ratio": ref / ours,
            "target": ">= 10"}


def preisach_inverse(n):
    from baseline_cma import NaiveCMA

    from polyforce_ros.evaluation.fsr_preisach import fsr_truth, grip_profile

    model = fsr_truth(seed=0)
    _, force = grip_profile(duration_s=n / 50.0)
    fwd = model.stream()
    volts = [fwd.forward(f) for f in force]
    ours = model.stream()
    t0 = time.perf_counter()
    for v in volts:
        ours.inverse(v)
    t_ours = (time.perf_counter() - t0) / len(volts)
    naive = NaiveCMA(model)
    m = min(len(volts), 2000)
    t0 = time.perf_counter()
    got = [naive.inverse(v) for v in volts[:m]]
    t_naive = (time.perf_counter() - t0) / m
    check = model.stream()
    assert np.allclose([check.inverse(v) for v in volts[:m]], got), "the two CMAs disagree"
    cont = model.stream(continuous=True)
    fwd_c = model.stream(continuous=True)
    vc = [fwd_c.forward(f) for f in force[:m]]
    t0 = time.perf_counter()
    for v in vc:
        cont.inverse(v)
    t_cont = (time.perf_counter() - t0) / m
    return {"n_levels": model.n_levels, "hysterons": model.n_hysterons, "ours_us_per_sample": 1e6 * t_ours,
            "naive_us_per_sample": 1e6 * t_naive, "continuous_us_per_sample": 1e6 * t_cont, "ratio": t_naive / t_ours,
            "target": "<= 20 us/sample"}


def calibration_hour(tmp, hours=1.0):
    from polyforce_ros.workflows import calibrate_bag

    rate = 1000.0
    parts, t0 = [], 0.0
    while t0 < hours * 3600.0 - 1:
        t, f = profiles.creep(5.0, hold_s=240.0, rest_s=240.0, rate_hz=rate)
        parts.append((t + t0, f))
        t0 += t[-1] + 1.0 / rate
    t = np.concatenate([p[0] for p in parts])[: int(hours * 3600 * rate)]
    f = np.concatenate([p[1] for p in parts])[: t.size]
    v = BridgeSimulator(seed=1).simulate(t, f)
    path = Path(tmp) / "creep_1h.mcap"
    write_bench_bag(path, t, f, v)
    out = Path(tmp) / "model.yaml"
    t_start = time.perf_counter()
    result = calibrate_bag(path, out)
    elapsed = time.perf_counter() - t_start
    return {"samples": int(t.size), "bag_mb": os.path.getsize(path) / 1e6, "seconds": elapsed,
            "selected": result.fits[0]["model"], "written": result.written, "target": "<= 10 s"}


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true", help="smaller sizes (smoke test)")
    args = ap.parse_args()
    q = args.quick
    with tempfile.TemporaryDirectory() as tmp:
        results = {
            "2 offline compensation": offline_compensation(1_000_000 if q else 10_000_000),
            "3 bag reading": bag_reading(50_000 if q else 500_000, tmp),
            "4 Preisach inverse": preisach_inverse(5_000 if q else 50_000),
            "5 calibration of a 1-hour 1 kHz creep bag": calibration_hour(tmp, hours=0.05 if q else 1.0),
        }
    for name, r in results.items():
        print(f"{name}: " + ", ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}" for k, v in r.items()))
    return results


if __name__ == "__main__":
    main()
