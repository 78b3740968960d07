"""Live benchmark: the latency haptic_bridge_node adds at 1 kHz over a bare relay.

A source process publishes `wrench` at 1 kHz, the node under test turns it into `haptic_command`,
a sink process records every command. The node is haptic_bridge_node with parameters that make
its output the latest input unchanged (force scale 1, no deadband, slew limit 1e6 N/s, saturation
at 100 N, above every test force; device_axis z) or, as the baseline in the same run, a bare relay
(`wrench` -> a WrenchStamped copy on `haptic_command`, the bridge's command QoS).

The bridge publishes one command per wrench, from the wrench's callback, stamped when it publishes,
so inputs and outputs are matched by value: message k carries force.z = SEQ_STEP_N * (k + 1),
distinct for every message and passed through the bridge unchanged. For each measured input:
publish -> arrival of the first command carrying its value. An input with no command of its own is
"unmatched"; "to the first command as new" (carrying that input or a newer one) covers every input.
Gaps: the largest pause between two measured inputs' publications and between two commands'
arrivals while they flow (a bridge that adds no pause of its own leaves the second at the first
plus the transport's jitter).

Relay and bridge runs are interleaved in pairs (both see the same machine state); the latencies are
pooled per kind. Reported: p50, p99 and max per kind, the added p50 (bridge - relay, us) and the p99
ratio (bridge / relay, with a bootstrap interval over pairs). Every run warms up until the first
command reaches the sink.

    .venv/bin/python bench/bench_bridge.py [--seconds 30] [--pairs 5]
DDS stays on loopback in an isolated domain (set by bench_live on import).
"""
import argparse
import json
import signal
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))  # bench/ is a folder of scripts, not a package
from bench_live import BIN, HERE, cpu_s, spawn, stop  # noqa: E402  (importing it sets the DDS environment)

from polyforce_ros.evaluation.latency import (  # noqa: E402
    BRIDGE_PARAMETERS, SEQ_STEP_N, percentiles, pooled_p99_ratio, value_latency)

KINDS = ("relay", "bridge")


def node_cmd(kind):
    if kind == "relay":
        return [sys.executable, str(HERE / "live_parts.py"), "wrench_relay"]
    return [str(BIN / "haptic_bridge_node"), "--ros-args",
            *[a for name, value in BRIDGE_PARAMETERS.items() for a in ("-p", f"{name}:={value}")]]


# ---------------------------------------------------------------------- processes
def run_arm(kind, rate_hz, seconds, tmp):
    """One run: node under test, command sink, then the wrench source; returns :func:`value_latency`'s stats."""
    out = Path(tmp) / f"{kind}_{time.monotonic_ns()}.npz"
    sent_path = Path(str(out) + ".sent.npz")
    procs = []
    try:
        node = spawn(node_cmd(kind))
        procs.append(node)
        sink = spawn([sys.executable, str(HERE / "live_parts.py"), "command_sink", str(out)])
        procs.append(sink)
        ready = Path(str(out) + ".ready")
        deadline = time.monotonic() + 30.0
        while not ready.exists() and time.monotonic() < deadline:  # the sink sees the node's command publisher
            time.sleep(0.05)
        cpu_start, wall_start = cpu_s(node.pid), time.monotonic()
        source = spawn([sys.executable, str(HERE / "live_parts.py"), "wrench_source", str(rate_hz), str(seconds),
                        str(out) + ".flowing", str(sent_path), repr(SEQ_STEP_N)])
        procs.append(source)
        started = json.loads(source.communicate(timeout=seconds + 90)[0].strip().splitlines()[-1])
        node_cpu = (cpu_s(node.pid) - cpu_start) / (time.monotonic() - wall_start)
        time.sleep(0.5)
        stop(sink, signal.SIGINT)
        stop(node, signal.SIGINT)
    finally:
        for proc in reversed(procs):
            stop(proc, signal.SIGINT)
    with np.load(sent_path) as s, np.load(out) as o:
        result = value_latency(s["value_n"], s["sent_ns"], o["value_n"], o["stamp_ns"], o["received_ns"],
                               started["t0_ns"], started["sent"])
    result.update(rate_hz=rate_hz, kind=kind, warmup=started["warmup"], node_cpu_fraction=node_cpu)
    return result


def interleaved_pairs(pairs, seconds, rate_hz, tmp):
    """Relay/bridge pairs of ``seconds`` each; pooled percentiles per kind and the ratios bridge / relay."""
    report, pooled = {}, {kind: {"lat": [], "fresh": [], "hist": []} for kind in KINDS}
    counts = {kind: dict.fromkeys(("sent", "matched", "unmatched", "never_fresh", "foreign_outputs", "outputs"), 0)
              for kind in KINDS}
    gaps = {kind: {"in_gap_ms": 0.0, "out_gap_ms": 0.0} for kind in KINDS}
    warmups = []
    for rep in range(pairs):
        pair = {}
        for kind in KINDS:
            r = pair[kind] = run_arm(kind, rate_hz, seconds, tmp)
            pooled[kind]["lat"].append(r.pop("lat_us"))
            pooled[kind]["fresh"].append(r.pop("fresh_lat_us"))
            pooled[kind]["hist"].append(r.pop("hist"))
            for key in counts[kind]:
                counts[kind][key] += r[key]
            for key in gaps[kind]:
                gaps[kind][key] = max(gaps[kind][key], r[key])
            warmups.append(r["warmup"])
            print(f"{rate_hz / 1000:g} kHz {kind:<6} p50 {r['p50_us']:6.0f} us  p99 {r['p99_us']:6.0f} us  "
                  f"max {r['max_us']:7.0f} us  (to the first command as new: p50 {r['fresh_p50_us']:6.0f}, "
                  f"p99 {r['fresh_p99_us']:6.0f} us)  publish->node stamp p50 {r['node_p50_us']:5.0f} us  "
                  f"node CPU {100 * r['node_cpu_fraction']:4.1f} %  sent {r['sent']}, matched {r['matched']}, "
                  f"unmatched {r['unmatched']}, foreign outputs {r['foreign_outputs']}, outputs {r['outputs']}; "
                  f"largest gap: inputs {r['in_gap_ms']:.1f} ms, commands {r['out_gap_ms']:.1f} ms", flush=True)
        report[f"pair{rep}"] = pair
    per_pair = {key: [report[f"pair{rep}"]["bridge"][key] / report[f"pair{rep}"]["relay"][key] for rep in range(pairs)]
                for key in ("p50_us", "p99_us", "fresh_p99_us")}
    print("bridge / relay per pair: " + "; ".join(
        f"{label} {', '.join(f'{r:.2f}' for r in per_pair[key])}"
        for label, key in (("p50", "p50_us"), ("p99", "p99_us"), ("p99 to the first command as new", "fresh_p99_us"))),
        flush=True)
    summary = {}
    for kind in KINDS:
        lat, fresh = np.concatenate(pooled[kind]["lat"]), np.concatenate(pooled[kind]["fresh"])
        summary[kind] = dict(percentiles(lat, ""), **percentiles(fresh, "fresh_"), **counts[kind], **gaps[kind])
    bridge, relay = summary["bridge"], summary["relay"]
    # p99 ratio from 1 us histograms as bench_live (latencies over 100 ms count as 100 ms), bootstrap over pairs
    ratio, low, high = pooled_p99_ratio(pooled["bridge"]["hist"], pooled["relay"]["hist"])
    stalled = {kind: [rep for rep in range(pairs) if report[f"pair{rep}"][kind]["max_us"] > 100_000] for kind in KINDS}
    calm = [rep for rep in range(pairs) if not any(rep in stalled[kind] for kind in KINDS)]  # pairs without a stall
    ratio_calm = (pooled_p99_ratio([pooled["bridge"]["hist"][rep] for rep in calm],
                                   [pooled["relay"]["hist"][rep] for rep in calm]) if calm else (float("nan"),) * 3)
    summary.update(ratio_p50=bridge["p50_us"] / relay["p50_us"], ratio_p99=ratio, ratio_p99_interval=[low, high],
                   pairs_with_a_stall=stalled, ratio_p99_without_stalls=ratio_calm[0],
                   ratio_p99_without_stalls_interval=list(ratio_calm[1:]), added_p50_us=bridge["p50_us"] - relay["p50_us"],
                   added_fresh_p50_us=bridge["fresh_p50_us"] - relay["fresh_p50_us"],
                   ratio_fresh_p99=bridge["fresh_p99_us"] / relay["fresh_p99_us"],
                   warmup_samples=[min(warmups), max(warmups)],
                   ratios_per_pair={key.removesuffix("_us"): values for key, values in per_pair.items()})
    for kind in KINDS:
        s = summary[kind]
        print(f"pooled {kind:<6} ({pairs} x {seconds:g} s): p50 {s['p50_us']:.0f} us, p99 {s['p99_us']:.0f} us, "
              f"max {s['max_us']:.0f} us; to the first command as new: p50 {s['fresh_p50_us']:.0f} us, "
              f"p99 {s['fresh_p99_us']:.0f} us, max {s['fresh_max_us']:.0f} us; sent {s['sent']}, matched {s['matched']}, "
              f"unmatched {s['unmatched']} (never followed by a command as new: {s['never_fresh']}), "
              f"foreign outputs {s['foreign_outputs']}, outputs {s['outputs']}; largest gap: inputs "
              f"{s['in_gap_ms']:.1f} ms, commands {s['out_gap_ms']:.1f} ms", flush=True)
    print(f"bridge / relay: p50 {summary['ratio_p50']:.2f} ({summary['added_p50_us']:+.0f} us), p99 {ratio:.2f} "
          f"(90 % bootstrap interval over pairs {low:.2f}-{high:.2f}); to the first command as new: "
          f"{summary['added_fresh_p50_us']:+.0f} us at p50, p99 ratio {summary['ratio_fresh_p99']:.2f}; "
          f"warm-up before the chain flowed: {min(warmups)}-{max(warmups)} samples", flush=True)
    if any(stalled.values()):
        print("pairs with a latency over 100 ms (a stall: the pooled p99 is the stall's, see the ratios per pair): "
              + ", ".join(f"{kind} {stalled[kind]}" for kind in KINDS if stalled[kind])
              + f"; p99 ratio over the {len(calm)} pairs without one: {ratio_calm[0]:.2f} "
              f"(interval {ratio_calm[1]:.2f}-{ratio_calm[2]:.2f})", flush=True)
    report["pooled"] = summary
    return report


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seconds", type=float, default=30.0, help="measured seconds per arm (relay, bridge), split over the pairs")
    ap.add_argument("--pairs", type=int, default=5, help="interleaved relay/bridge runs of seconds / pairs each")
    ap.add_argument("--rate", type=float, default=1000.0, help="wrench rate, Hz (the bridge publishes one command per wrench)")
    args = ap.parse_args()
    if args.pairs < 1 or args.seconds <= 0:
        ap.error("--pairs must be >= 1 and --seconds > 0")
    if SEQ_STEP_N * args.rate * (args.seconds / args.pairs + 25.0) >= BRIDGE_PARAMETERS["max_force_n"]:  # 20 s warm-up at most
        ap.error("runs this long would reach the bridge's saturation: use more --pairs")
    with tempfile.TemporaryDirectory() as tmp:
        report = interleaved_pairs(args.pairs, args.seconds / args.pairs, args.rate, tmp)
    print(json.dumps(report))


if __name__ == "__main__":
    main()
