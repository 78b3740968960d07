"""Live benchmarks of issue 6: latency of the 1 kHz haptic path and memory of the compensation node.

1. raw sample stamp -> `wrench` received in another process: p50/p99/max and losses for the
   compensation node and, in the same run, a bare relay (same types, no computation);
   then the highest rate with zero loss for both.
6. RSS of the compensation node at the start and the end of a long 1 kHz run.

    .venv/bin/python bench/bench_live.py [--seconds 30] [--memory-minutes 10] [--quick]
DDS stays on loopback in an isolated domain.
"""
import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
BIN = Path(sys.executable).parent
os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
os.environ["ROS_DOMAIN_ID"] = str(100 + os.getpid() % 100)
os.environ.setdefault("AMENT_PREFIX_PATH", sys.prefix)


def spawn(args):
    return subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)


def stop(proc):
    if proc.poll() is None:
        proc.send_signal(signal.SIGTERM)
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def node_cmd(kind):
    if kind == "relay":
        return [sys.executable, str(HERE / "live_parts.py"), "relay"]
    return [str(BIN / "compensation_node"), "--ros-args", "-p", "stale_timeout_s:=5.0"]


def rss_kb(pid):
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    return None


def run_path(kind, rate_hz, seconds, tmp, sample_rss=False):
    out = Path(tmp) / f"{kind}_{rate_hz}.json"
    node = spawn(node_cmd(kind))
    sink = spawn([sys.executable, str(HERE / "live_parts.py"), "sink", str(out)])
    ready = Path(str(out) + ".ready")
    deadline = time.monotonic() + 30.0
    while not ready.exists() and time.monotonic() < deadline:  # the sink sees the node's wrench publisher
        time.sleep(0.05)
    time.sleep(1.0)  # and the match settles
    rss_start = rss_kb(node.pid) if sample_rss else None
    source = spawn([sys.executable, str(HERE / "live_parts.py"), "source", str(rate_hz), str(seconds)])
    sent = json.loads(source.communicate(timeout=seconds + 60)[0].strip().splitlines()[-1])["sent"]
    rss_end = rss_kb(node.pid) if sample_rss else None
    time.sleep(0.5)
    stop(sink)
    stop(node)
    result = json.loads(out.read_text())
    result.update(sent=sent, lost=sent - result["received"], rate_hz=rate_hz, kind=kind)
    if sample_rss:
        result.update(rss_start_kb=rss_start, rss_end_kb=rss_end)
    return result


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--memory-minutes", type=float, default=10.0)
    ap.add_argument("--rates", default="1000,2000,4000,8000")
    ap.add_argument("--repeats", type=int, default=3, help="interleaved relay/compensation pairs at 1 kHz")
    ap.add_argument("--quick", action="store_true", help="5 s runs, 1 min memory run")
    args = ap.parse_args()
    if args.quick:
        args.seconds, args.memory_minutes = 5.0, 1.0
    report = {}
    with tempfile.TemporaryDirectory() as tmp:
        ratios = []
        for rep in range(args.repeats):  # interleaved: both see the same machine state
            pair = {}
            for kind in ("relay", "compensation"):
                r = pair[kind] = run_path(kind, 1000.0, args.seconds, tmp)
                print(f"1 kHz {kind:<13} p50 {r['p50_us']:7.0f} us  p99 {r['p99_us']:7.0f} us  max {r['max_us']:8.0f} us  "
                      f"lost {r['lost']} of {r['sent']} (largest gap {r['largest_gap_ms']:.0f} ms at {r['largest_gap_at_s']:.1f} s)",
                      flush=True)
            ratios.append(pair["compensation"]["p99_us"] / pair["relay"]["p99_us"])
            report[f"pair{rep}"] = pair
        ratio = float(sorted(ratios)[len(ratios) // 2])
        print(f"p99(compensation) / p99(relay): {', '.join(f'{r:.2f}' for r in ratios)}; median {ratio:.2f}   "
              f"(target <= 1.10)", flush=True)
        for kind in ("relay", "compensation"):
            best = None
            for rate in [float(r) for r in args.rates.split(",")]:
                r = run_path(kind, rate, min(args.seconds, 5.0), tmp)
                print(f"  {kind:<13} {rate:6.0f} Hz: lost {r['lost']} of {r['sent']}, p99 {r['p99_us']:.0f} us", flush=True)
                if r["lost"] == 0:
                    best = rate
                else:
                    break
            report[f"{kind}_max_zero_loss_hz"] = best
            print(f"highest rate with zero loss, {kind}: {best} Hz", flush=True)
        mem = run_path("compensation", 1000.0, args.memory_minutes * 60.0, tmp, sample_rss=True)
        print(f"memory over {args.memory_minutes:.0f} min at 1 kHz: RSS {mem['rss_start_kb']} kB -> {mem['rss_end_kb']} kB, "
              f"lost {mem['lost']} of {mem['sent']}", flush=True)
        report["memory"] = mem
        report["ratio_p99"] = ratio
    print(json.dumps(report))


if __name__ == "__main__":
    main()
