"""Confusion matrix of the discrepancy workflow on hidden effects of every family.

Rows: every family of every catalogue effect (from the effect registry), the
tested pairs of effects, the out-of-catalogue cases and clean data, at
magnitudes from barely detectable (0) to large (1); recording conditions
alternate between 200 Hz and 1 kHz with stamp jitter, dropped blocks and (for
some) no temperature topic. Each record is simulated, diagnosed against the
base the effects apply to, and the answer compared with the truth:

* catalogue effects: fully correct when ``missing_effects`` names exactly the hidden set;
* out of catalogue: fully correct when the answer is ``unexplained`` (``none`` is
  counted apart; any catalogue name is wrong); a simulated shape that a catalogue effect
  describes (``EXTRA_EFFECTS``) counts as that effect;
* clean data: fully correct when the answer is ``none``.

``--split held_out`` (default) uses the seeds (and families) the engine was
never tuned on; ``--split tune`` the tuning split.

    .venv/bin/python bench/discrepancy_matrix.py [--split held_out] [--seeds 1] [--duration 300] [--workers 2] [--json out.json]
"""
import argparse
import json
import multiprocessing
import os
import time
from collections import Counter, defaultdict
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

import numpy as np
from tqdm import tqdm

from polyforce_ros.discrepancy.effects import EFFECTS
from polyforce_ros.discrepancy.engine import diagnose
from polyforce_ros.sim.bench import EXTRA_EFFECTS, OUT_OF_CATALOGUE, bench_record, default_base
from polyforce_ros.sim.truths import SPLITS, families

PAIRS = (("hysteresis", "thermal_drift"), ("sensor_lag", "nonlinear_gain"), ("viscous_flow", "offset_drift"),
         ("hysteresis", "offset_drift"))
MAGNITUDES = (0.0, 0.5, 1.0)
#: Recording conditions, cycled over the cases: (label, rate Hz, jitter fraction, dropped blocks, temperature topic)
CONDITIONS = (("200Hz", 200.0, 0.0, 0, True), ("1kHz-jitter-gaps", 1000.0, 0.3, 4, True),
              ("200Hz-jitter-gaps-notemp", 200.0, 0.3, 4, False))


def cases(split, seeds):
    out = []
    for effect in EFFECTS:
        for fam in families(effect, split):
            for m in MAGNITUDES:
                out += [((effect,), {effect: fam}, m, s) for s in range(seeds)]
    for pair in PAIRS:
        for m in MAGNITUDES[1:]:
            out += [(pair, None, m, s) for s in range(seeds)]
    for name in EXTRA_EFFECTS:
        for m in MAGNITUDES[1:]:
            out += [((name,), None, m, s) for s in range(seeds)]
    out += [((), None, 0.0, s) for s in range(3 * seeds)]
    return out


def verdict(hidden, d, temperature):
    hidden = [(EXTRA_EFFECTS[h][1] or h) if h in EXTRA_EFFECTS else h for h in hidden]  # a catalogue effect's shape
    catalogue = [h for h in hidden if h in EFFECTS]
    if not temperature:  # a thermal effect cannot be seen without the topic: it is not expected
        catalogue = [h for h in catalogue if not EFFECTS[h].needs_temperature]
    named = set(d.missing_effects)
    if any(h in OUT_OF_CATALOGUE for h in hidden):
        return "ok" if d.missing_effect == "unexplained" else ("none" if d.missing_effect == "none" else "wrong name")
    if not hidden:
        return "ok" if d.missing_effect == "none" else "wrong name"
    if named == set(catalogue):
        return "ok"
    return "missed" if named < set(catalogue) else "wrong name"


def run_case(i, hidden, fams, mag, seed, split, duration_s):
    """Simulate and diagnose case ``i`` (its recording condition is the i-th of :data:`CONDITIONS`, cycled)."""
    label, rate, jitter, drops, temperature = CONDITIONS[i % len(CONDITIONS)]
    if any(EFFECTS[h].needs_temperature for h in hidden if h in EFFECTS) and not temperature:  # it needs the topic
        label, rate, jitter, drops, temperature = CONDITIONS[1]
    base = default_base(hidden)
    rec, case = bench_record(list(hidden) or "none", mag, base, duration_s, rate, seed, split=split,
                             families=fams, jitter=jitter, drops=drops, temperature=temperature)
    case_info = {"index": i, "hidden": list(hidden), "families": case.families, "magnitude": mag, "seed": seed,
                 "base": base, "conditions": label}
    try:
        d = diagnose(rec, base=base)
    except Exception as exc:  # noqa: BLE001 - one failing case is reported, the others still run
        nan = float("nan")
        return {**case_info, "named": [], "answer": f"error: {exc!r}", "verdict": "error", "confidence": {},
                "rmse_before": nan, "rmse_after": nan, "noise_floor_v": nan, "unexplained_rms_v": nan}
    return {**case_info, "named": d.missing_effects, "answer": d.missing_effect, "verdict": verdict(hidden, d, temperature),
            "confidence": d.confidences, "rmse_before": d.rmse_before, "rmse_after": d.rmse_after,
            "noise_floor_v": d.noise_floor_v, "unexplained_rms_v": d.unexplained["rms_v"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--split", default="held_out", choices=sorted(SPLITS))
    ap.add_argument("--seeds", type=int, default=1)
    ap.add_argument("--duration", type=float, default=600.0, help="record length, s")
    ap.add_argument("--only", nargs="*", help="only cases whose hidden effects include these")
    ap.add_argument("--json", help="write every case as JSON (rewritten after each case)")
    ap.add_argument("--budget", type=float, default=840.0, help="start no new case after this many seconds")
    ap.add_argument("--workers", type=int, default=1, help="cases diagnosed at once (processes)")
    ap.add_argument("--stride", type=int, default=1, help="run every n-th case only (a spread subset)")
    args = ap.parse_args()
    if not 1 <= args.seeds <= 53:  # tune seeds are 0..seeds-1 modulo 97, held-out ones 53.. : never the same
        ap.error("--seeds must be 1..53")
    seed0 = SPLITS[args.split]
    # seed and condition follow the case's index in the full list, so a filtered run repeats the full run's cases
    jobs = [(i, hidden, fams, mag, seed0 + 97 * i + s, args.split, args.duration)
            for i, (hidden, fams, mag, s) in enumerate(cases(args.split, args.seeds))]
    if args.only:
        jobs = [j for j in jobs if set(j[1]) & set(args.only) or (not j[1] and "none" in args.only)]
    jobs = jobs[::args.stride]
    results = []
    t0 = time.perf_counter()
    # each worker gets its share of the cores for BLAS: workers x default threads oversubscribe the machine. The
    # variables are read when numpy loads, so the workers are spawned (a forked one keeps the parent's BLAS)
    threads = str(max(1, (os.cpu_count() or 1) // args.workers))
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[var] = threads
    with ProcessPoolExecutor(args.workers, mp_context=multiprocessing.get_context("spawn")) as pool:
        # at most ``workers`` cases in flight: the budget is checked before each new case starts
        pending, queue = set(), list(jobs)
        with tqdm(total=len(jobs), desc="diagnoses") as bar:
            while queue or pending:
                while queue and len(pending) < args.workers and time.perf_counter() - t0 <= args.budget:
                    pending.add(pool.submit(run_case, *queue.pop(0)))
                if not pending:
                    print(f"time budget of {args.budget:.0f} s spent: {len(queue)} cases not run")
                    break
                done, pending = wait(pending, return_when=FIRST_COMPLETED)
                for fut in done:
                    results.append(fut.result())
                    bar.update()
                if args.json:
                    with open(args.json, "w") as fh:
                        json.dump(sorted(results, key=lambda r: r["index"]), fh, indent=1, default=float)
    results.sort(key=lambda r: r["index"])
    elapsed = time.perf_counter() - t0
    print(f"\nsplit {args.split}: {len(results)} diagnoses in {elapsed:.0f} s ({args.duration:.0f} s records; "
          f"conditions cycled over {[c[0] for c in CONDITIONS]})")
    rows = defaultdict(Counter)
    for r in results:
        key = "+".join(r["hidden"]) or "clean"
        if len(r["hidden"]) == 1 and r["hidden"][0] in EFFECTS:
            key += f" [{r['families'][r['hidden'][0]]}]"
        rows[key][r["answer"] if len(r["named"]) <= 1 else "+".join(r["named"])] += 1
        rows[key]["_ok"] += r["verdict"] == "ok"
        rows[key]["_n"] += 1
    width = max(map(len, rows)) + 2
    print(f"{'hidden [family]':<{width}} {'ok':>6}  answers")
    for key, c in rows.items():
        answers = ", ".join(f"{k}: {v}" for k, v in c.items() if not k.startswith("_"))
        print(f"{key:<{width}} {c['_ok']:>2}/{c['_n']:<3}  {answers}")
    ok = sum(r["verdict"] == "ok" for r in results)
    print(f"fully correct: {ok}/{len(results)} ({100 * ok / len(results):.1f} %)")
    for mag in MAGNITUDES:
        sel = [r for r in results if r["hidden"] and r["magnitude"] == mag]
        if sel:
            print(f"  magnitude {mag:.1f}: {sum(r['verdict'] == 'ok' for r in sel)}/{len(sel)}")
    for label, *_ in CONDITIONS:
        sel = [r for r in results if r["conditions"] == label]
        print(f"  {label}: {sum(r['verdict'] == 'ok' for r in sel)}/{len(sel)}")
    bad_clean = [r for r in results if (not r["hidden"] or r["hidden"][0] in OUT_OF_CATALOGUE) and r["named"]]
    print(f"catalogue names on clean or out-of-catalogue data: {len(bad_clean)}")
    ratio = [r["rmse_after"] / r["noise_floor_v"] for r in results
             if r["verdict"] == "ok" and r["hidden"] and r["hidden"][0] in EFFECTS]
    if ratio:
        print(f"validation RMSE after augmentation / noise floor, correctly named: median {np.median(ratio):.2f}, "
              f"90th percentile {np.percentile(ratio, 90):.2f}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(results, fh, indent=1, default=float)


if __name__ == "__main__":
    main()
