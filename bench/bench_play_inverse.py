"""Per-sample cost of the streaming inverse of ``bridge_hysteresis`` on the 1 kHz path, against the core alone.

The inverse sorts the plays' breakpoints at every sample, so its cost grows with the number of plays: the core alone,
the 22 plays on the force a diagnosis fits, and those with the 26 scaled plays beside them (the most it saves).

    .venv/bin/python bench/bench_play_inverse.py [--seconds 5] [--repeats 3]
"""
from __future__ import annotations

import argparse
import os
import time

import numpy as np

from polyforce_ros.discrepancy.effects import PLAY_FRACTIONS, SCALED_RADII
from polyforce_ros.physics.chain import BridgeHysteresisElement, OffsetElement, SensorChain, ViscoelasticElement
from polyforce_ros.physics.viscoelastic import PAPER_BURGERS


def chains() -> dict[str, SensorChain]:
    """The core alone, with 22 plays on the force beside it, and with 26 scaled plays beside those."""
    core = ViscoelasticElement(PAPER_BURGERS)
    radii, weights = PLAY_FRACTIONS * 10.0, np.full(PLAY_FRACTIONS.size, 1e-3)
    return {"core alone": SensorChain([core, OffsetElement(0.0)]),
            "22 plays": SensorChain([BridgeHysteresisElement(core, radii, weights), OffsetElement(0.0)]),
            "22 plays + 26 scaled": SensorChain([BridgeHysteresisElement(
                core, radii, weights, scaled_radii=SCALED_RADII, scaled_weights_v_per_n=np.full(SCALED_RADII.size, 1e-3),
                floor_n=0.2), OffsetElement(0.0)])}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seconds", type=float, default=5.0, help="record length at 1 kHz")
    ap.add_argument("--repeats", type=int, default=3, help="runs per chain; the fastest is reported")
    args = ap.parse_args()
    t = np.arange(0.0, args.seconds, 1e-3)
    force = 5.0 + 4.0 * np.sin(2 * np.pi * t / 1.3)
    best = {}
    for name, chain in chains().items():
        volts = chain.forward(t, force)
        runs = []
        for _ in range(args.repeats):
            stream = chain.streaming()
            start = time.perf_counter()
            for ti, vi in zip(t.tolist(), volts.tolist()):
                stream.step(ti, vi)
            runs.append((time.perf_counter() - start) / t.size)
        best[name] = min(runs)
    print(f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}")
    for name, seconds in best.items():
        print(f"{name:22s} {1e6 * seconds:7.1f} us/sample  {seconds / best['core alone']:6.1f}x the core alone")


if __name__ == "__main__":
    main()
