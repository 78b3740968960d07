"""Speed of ``diagnose`` on a 10-minute bench record, forward selection included.

Simulates 10-minute records (Prandtl-Ishlinskii hysteresis on the force path and a lagged thermal drift hidden, 2 mV noise, a
reference load cell with 5 mN noise) at 200 Hz and at 1 kHz (stamp jitter of
0.3 sample, four dropped blocks), and times the whole diagnosis (noise floor,
base fit, forward selection with the time-blocked cross-validation, the
out-of-sample residual at the record's rate, localisation). Prints the machine
state (cores, load average) next to the figures; targets: <= 15 s at 200 Hz,
<= 30 s at 1 kHz on the project's 2-core machine.

    .venv/bin/python bench/bench_diagnose.py [--repeat 2] [--duration 600]
"""
import argparse
import os
import platform
import time

import numpy as np

from polyforce_ros.discrepancy.engine import diagnose
from polyforce_ros.sim.bench import bench_record

TARGETS_S = {200.0: 15.0, 1000.0: 30.0}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--duration", type=float, default=600.0)
    args = ap.parse_args()
    print(f"machine: {os.cpu_count()} cores, {platform.processor() or platform.machine()}, "
          f"load average before {os.getloadavg()[0]:.2f} / {os.getloadavg()[1]:.2f} (1 / 5 min)")
    ok = True
    for rate, jitter, drops in ((200.0, 0.0, 0), (1000.0, 0.3, 4)):
        times = []
        for k in range(args.repeat):
            rec, _ = bench_record(["hysteresis", "thermal_drift"], 0.7, "burgers", args.duration, rate, seed=8000 + k,
                                  split="held_out", jitter=jitter, drops=drops,
                                  families={"hysteresis": "play_force", "thermal_drift": "thermal_lag"})
            t0 = time.perf_counter()
            d = diagnose(rec, base="burgers")
            times.append(time.perf_counter() - t0)
        worst = max(times)
        ok &= worst <= TARGETS_S[rate] * args.duration / 600.0
        print(f"{rate:6.0f} Hz, {args.duration:.0f} s record ({rec.t_s.size} samples): diagnose median "
              f"{np.median(times):.1f} s, worst {worst:.1f} s (target {TARGETS_S[rate]:.0f} s); named {d.missing_effects}; "
              f"load average now {os.getloadavg()[0]:.2f}")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
