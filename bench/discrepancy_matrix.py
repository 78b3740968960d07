"""Confusion matrix of the discrepancy workflow over hidden-effect bench records.

For every effect, several seeds (random load profiles) and magnitudes from
barely detectable (0) to large (1): simulate, diagnose against the base the
effect applies to, and count what was named. Prints the confusion matrix,
the accuracy per magnitude and the median shrink (rmse_before / rmse_after)
of correctly named effects, so weaknesses show.

    .venv/bin/python bench/discrepancy_matrix.py [--seeds 3] [--duration 240] [--json out.json]
"""
import argparse
import json
import time

import numpy as np
from tqdm import tqdm

from polyforce_ros.discrepancy.engine import diagnose
from polyforce_ros.record import Record
from polyforce_ros.sim.bench import EFFECTS, simulate_bench

BASE_FOR = {"viscous_flow": "zener", "delayed_elasticity": "maxwell"}
MAGNITUDES = (0.0, 0.5, 1.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--duration", type=float, default=240.0, help="record length, s")
    ap.add_argument("--rate", type=float, default=100.0, help="sample rate, Hz")
    ap.add_argument("--json", help="write every case as JSON")
    args = ap.parse_args()
    cases = [(e, m, s) for e in EFFECTS for m in (MAGNITUDES if e != "none" else (0.0,)) for s in range(args.seeds)]
    results = []
    t0 = time.perf_counter()
    for effect, mag, seed in tqdm(cases, desc="diagnoses"):
        base = BASE_FOR.get(effect, "burgers")
        t, f, v, temp, _ = simulate_bench(effect, mag, base, args.duration, args.rate, seed=1000 + 17 * seed + len(results))
        d = diagnose(Record(t, f, v, temp), base=base)
        results.append({"effect": effect, "magnitude": mag, "seed": seed, "base": base, "named": d.missing_effect,
                        "rmse_before": d.rmse_before, "rmse_after": d.rmse_after})
    elapsed = time.perf_counter() - t0
    names = list(EFFECTS)
    width = max(map(len, names)) + 2
    print(f"\nconfusion matrix: rows hidden, columns named ({len(results)} diagnoses, {elapsed:.0f} s, "
          f"{args.duration:.0f} s records at {args.rate:.0f} Hz)")
    print(" " * width + "".join(f"{n[:8]:>9}" for n in names))
    for hidden in names:
        row = [sum(r["effect"] == hidden and r["named"] == n for r in results) for n in names]
        print(f"{hidden:<{width}}" + "".join(f"{c:>9}" for c in row))
    for mag in MAGNITUDES:
        sel = [r for r in results if r["effect"] != "none" and r["magnitude"] == mag]
        ok = sum(r["named"] == r["effect"] for r in sel)
        print(f"magnitude {mag:.1f}: {ok}/{len(sel)} named correctly")
    none = [r for r in results if r["effect"] == "none"]
    print(f"clean data: {sum(r['named'] == 'none' for r in none)}/{len(none)} said none")
    shrink = [r["rmse_before"] / r["rmse_after"] for r in results if r["effect"] != "none" and r["named"] == r["effect"]]
    print(f"median shrink of correctly named effects: x{np.median(shrink):.1f} (min x{np.min(shrink):.1f})")
    for effect in names[1:]:
        s = [r["rmse_before"] / r["rmse_after"] for r in results if r["effect"] == effect and r["named"] == effect]
        print(f"  {effect:<20} median shrink x{np.median(s):.1f}" if s else f"  {effect:<20} never named")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(results, fh, indent=1)


if __name__ == "__main__":
    main()
