"""Black-box start-up probe: the nodes started as ``polyforce bringup --with-bridge`` starts them, judged from outside.

Each run: a listener process subscribes to ``wrench``, ``reference_force`` and ``/diagnostics``; then the
haptic bridge, the compensation node and the driver (simulator backend) start as processes with the
parameter files and overrides of :func:`polyforce_ros.bringup.plan` (so the simulated profile starts once
the compensation node listens). Optionally ``--load L`` background busy processes share the machine
(``int(L)`` spinning all the time, one more spinning the fraction ``L - int(L)`` of every 100 ms). The
driver starts once the listener sees the compensation node's ``wrench`` writer (so it misses no early
wrench; bringup itself does not wait there). Every process is stopped by its PID: SIGINT, then SIGKILL
after 10 s.

Checks per run, from the messages alone:

* zero before force: no sample wrench above 0.05 N in magnitude before the start-up zeroing decided (the
  first ``zero_before_tare`` sample wrenches by stamp, the count the node's diagnostics give once it
  decided);
* zeroed in time: the diagnostics say "zeroed" (one auto-tare, none refused) within ``auto_tare_timeout_s``;
* compensated: R^2 >= 0.99 of the sample wrenches against the simulator's reference force over
  ``--after-s`` seconds of samples from the decision on (from the first reference received, if later).

Sample wrenches carry their sample's stamp, on the simulator's grid (the reference's stamps, 1 ms apart);
the watchdog's zero wrenches carry the time they were sent and are left out. ``from_start``: the
sample wrenches begin with exactly ``zero_before_tare`` zeros, so the listener saw the first sample (if it
missed early ones, the boundary is a few samples late; right after a zeroing at rest the force is near
zero, so the first check keeps its meaning).

    .venv/bin/python bench/probe_startup.py [--runs 10] [--load 2.5] [--after-s 4]
Prints one table row per run and a JSON summary; exits 1 if any run failed a check.
DDS stays on loopback in an isolated domain.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from processes import isolate_dds, stop_pid

from polyforce_ros import bringup
from polyforce_ros.physics.metrics import error_summary

PHANTOM_N = 0.05
MIN_R2 = 0.99
HOG = ("import sys, time\nduty = float(sys.argv[1])\nwhile True:\n    t = time.monotonic()\n"
       "    while time.monotonic() - t < 0.1 * duty:\n        pass\n    if duty < 1.0:\n"
       "        time.sleep(0.1 * (1.0 - duty))\n")


# ---------------------------------------------------------------------- processes
def start_hogs(load):
    """``int(load)`` processes spinning all the time and one spinning ``load - int(load)`` of the time."""
    duties = [1.0] * int(load) + ([load - int(load)] if load - int(load) > 1e-9 else [])
    return [subprocess.Popen([sys.executable, "-c", HOG, repr(d)], stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL) for d in duties]


def run_once(index, after_s, max_s, tmp):
    """One start-up: listener, then the bringup children; returns the judged result."""
    folder = Path(tempfile.mkdtemp(prefix=f"run{index}_", dir=tmp))
    out = folder / "listener.json"
    specs = bringup.plan(folder, backend="sim", with_bridge=True)
    env = bringup.child_env()
    timeout_s = float(bringup.load_params(specs[[s.name for s in specs].index("compensation_node")].params_file)
                      .get("auto_tare_timeout_s", 10.0))
    logs, nodes = [], []
    listener = subprocess.Popen([sys.executable, str(Path(__file__).resolve()), "listen", str(out), repr(after_s),
                                 repr(max_s)], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env)
    try:
        ready = Path(str(out) + ".ready")
        deadline = time.monotonic() + 30.0
        while not ready.exists() and listener.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        sees = Path(str(out) + ".sees_wrench")
        for spec in specs:  # bringup's start order: bridge, compensation, driver
            if spec.name == "driver_node":  # the listener must not miss the first wrenches: it sees their writer
                deadline = time.monotonic() + 30.0
                while not sees.exists() and listener.poll() is None and time.monotonic() < deadline:
                    time.sleep(0.02)
            log = open(folder / f"{spec.name}.log", "w")
            logs.append(log)
            nodes.append((spec.name, subprocess.Popen(spec.argv, env=env, stdout=log, stderr=subprocess.STDOUT,
                                                      process_group=0)))
        try:
            _, err = listener.communicate(timeout=max_s + 60.0)
        except subprocess.TimeoutExpired:
            stop_pid(listener)
            err = "listener timed out"
    finally:
        stops = {name: stop_pid(proc) for name, proc in reversed(nodes)}  # the driver first
        stop_pid(listener)
        for log in logs:
            log.close()
    if not out.exists():
        return {"run": index, "ok": False, "error": f"listener wrote nothing: {(err or '')[-1500:]}", "stops": stops}
    data = json.loads(out.read_text())
    result = judge(data, timeout_s)
    result.update(run=index, stops={k: {"code": c, "killed": killed} for k, (c, killed) in stops.items()},
                  killed=[k for k, (_c, killed) in stops.items() if killed])
    return result


# ---------------------------------------------------------------------- the checks (pure numpy)
def judge(data, timeout_s, after_s=None):
    """The three checks on what the listener recorded (see the module docstring)."""
    w_stamp = np.asarray(data["wrench_stamp_ns"], dtype=np.int64)
    w_force = np.asarray(data["wrench_force"], dtype=float)
    r_stamp = np.asarray(data["ref_stamp_ns"], dtype=np.int64)
    r_force = np.asarray(data["ref_force"], dtype=float)
    diag = data.get("diag") or {}
    after_s = data.get("after_s", 4.0) if after_s is None else after_s
    out = {"ok": False, "status": diag.get("auto_tare", "no diagnostics")}
    ref = dict(zip(r_stamp.tolist(), r_force.tolist()))
    if r_stamp.size < 2:
        out.update(max_before_n=None, r2=None, samples_after=0, error="no reference received")
        return out
    period = int(np.min(np.diff(np.unique(r_stamp))))
    sample = (w_stamp - r_stamp[0]) % period == 0  # on the simulator's grid: not a watchdog zero
    order = np.argsort(w_stamp[sample], kind="stable")
    s_stamp, s_force = w_stamp[sample][order], w_force[sample][order]
    zeroed = str(diag.get("auto_tare", "")).startswith("zeroed")
    tares, refused = int(diag.get("auto_tares", 0)), int(diag.get("auto_tare_refused", 0))
    waited = re.search(r"\(([0-9.]+) s after start\)", str(diag.get("auto_tare", "")))
    out["zeroed_after_s"] = float(waited.group(1)) if waited else None
    out["zeroed_in_time"] = bool(zeroed and tares == 1 and refused == 0 and waited and float(waited.group(1)) <= timeout_s)
    before = int(diag.get("zero_before_tare", -1))
    if not zeroed or before < 0 or s_stamp.size <= before:
        out.update(max_before_n=None, r2=None, samples_after=0)
        return out
    out["max_before_n"] = float(np.max(np.abs(s_force[:before]))) if before else 0.0
    out["zero_before_force"] = out["max_before_n"] <= PHANTOM_N
    out["from_start"] = bool(np.all(s_force[:before] == 0.0) and s_force[before] != 0.0)
    start = max(int(s_stamp[before]), int(r_stamp.min()))
    window = (s_stamp >= start) & (s_stamp < start + int(after_s * 1e9)) & np.isin(s_stamp, r_stamp)
    out["samples_after"] = int(window.sum())
    if out["samples_after"] < 10:
        out["r2"] = None
        return out
    summary = error_summary(np.array([ref[s] for s in s_stamp[window]]), s_force[window])
    out.update(r2=float(summary["r2"]), rmse_n=float(summary["rmse_n"]))
    out["compensated"] = out["r2"] >= MIN_R2
    out["ok"] = bool(out["zero_before_force"] and out["zeroed_in_time"] and out["compensated"])
    return out


# ---------------------------------------------------------------------- the listener (run as `listen ...`)
def listen(out_path, after_s, max_s):
    import rclpy
    from diagnostic_msgs.msg import DiagnosticArray
    from geometry_msgs.msg import WrenchStamped
    from rclpy.node import Node
    from rclpy.qos import QoSProfile, ReliabilityPolicy

    rclpy.init()
    node = Node("startup_probe", namespace="/polyforce")
    qos = QoSProfile(depth=10000, reliability=ReliabilityPolicy.RELIABLE)
    rec = {"wrench_stamp_ns": [], "wrench_force": [], "ref_stamp_ns": [], "ref_force": [], "diag": None,
           "after_s": after_s}

    def stamp(msg):
        return msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec

    def on_wrench(msg):
        rec["wrench_stamp_ns"].append(stamp(msg))
        rec["wrench_force"].append(msg.wrench.force.z)

    def on_ref(msg):
        rec["ref_stamp_ns"].append(stamp(msg))
        rec["ref_force"].append(msg.wrench.force.z)

    def on_diag(msg):
        for status in msg.status:
            if status.hardware_id == "compensation_node":
                rec["diag"] = {kv.key: kv.value for kv in status.values}

    node.create_subscription(WrenchStamped, "wrench", on_wrench, qos)
    node.create_subscription(WrenchStamped, "reference_force", on_ref, qos)
    node.create_subscription(DiagnosticArray, "/diagnostics", on_diag, 100)
    stop = {"flag": False}
    signal.signal(signal.SIGINT, lambda *_: stop.update(flag=True))
    signal.signal(signal.SIGTERM, lambda *_: stop.update(flag=True))
    open(out_path + ".ready", "w").close()
    deadline, checked, sees = time.monotonic() + max_s, time.monotonic(), out_path + ".sees_wrench"
    while not stop["flag"] and time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.05)
        if sees and node.count_publishers("/polyforce/wrench") > 0:
            open(sees, "w").close()
            sees = None
        diag = rec["diag"] or {}
        if time.monotonic() - checked < 0.5 or diag.get("auto_tares", "0") == diag.get("auto_tare_refused", "0") == "0":
            continue
        checked = time.monotonic()  # decided: refused (judged as it is), or a full window after the zeroing
        if diag.get("auto_tare_refused", "0") != "0" or len(rec["ref_stamp_ns"]) < 2:
            if diag.get("auto_tare_refused", "0") != "0":
                break
            continue
        period_s = float(np.min(np.diff(np.unique(rec["ref_stamp_ns"][-100:])))) * 1e-9
        if judge(dict(rec, diag=diag), float("inf")).get("samples_after", 0) >= 0.95 * after_s / period_s:
            break
    Path(out_path).write_text(json.dumps(rec))
    node.destroy_node()
    rclpy.shutdown()


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["listen"]:
        return listen(argv[1], float(argv[2]), float(argv[3]))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=10)
    ap.add_argument("--load", type=float, default=0.0, help="background busy processes (2.5: two and a half cores)")
    ap.add_argument("--after-s", type=float, default=4.0, help="seconds of samples after the zeroing judged by R^2")
    ap.add_argument("--max-s", type=float, default=40.0, help="longest a run waits for the decision and its samples")
    args = ap.parse_args(argv)
    isolate_dds()
    hogs = start_hogs(args.load)
    results = []
    try:
        with tempfile.TemporaryDirectory() as tmp:
            print(f"{'run':>3}  {'ok':<4} {'zeroed after':>12}  {'max |F| before':>14}  {'R2 after':>8}  "
                  f"{'samples':>7}  {'from start':<10}  stopped", flush=True)
            for i in range(args.runs):
                r = run_once(i, args.after_s, args.max_s, tmp)
                results.append(r)
                fmt = lambda v, f: "-" if v is None else format(v, f)  # noqa: E731
                print(f"{i:>3}  {'yes' if r['ok'] else 'NO':<4} {fmt(r.get('zeroed_after_s'), '.2f'):>10} s  "
                      f"{fmt(r.get('max_before_n'), '.4f'):>12} N  {fmt(r.get('r2'), '.4f'):>8}  "
                      f"{r.get('samples_after', 0):>7}  {str(r.get('from_start', '-')):<10}  "
                      f"{'killed ' + ','.join(r['killed']) if r.get('killed') else 'SIGINT'}"
                      + ("" if r["ok"] else f"  ({r.get('error') or r.get('status')})"), flush=True)
    finally:
        for hog in hogs:
            stop_pid(hog, 2.0)
    passed = sum(r["ok"] for r in results)
    print(f"{passed} of {len(results)} runs passed (load {args.load:g}, {os.cpu_count()} cores)", flush=True)
    print(json.dumps({"load": args.load, "runs": len(results), "passed": passed, "results": results}))
    return 0 if passed == len(results) else 1


if __name__ == "__main__":
    sys.exit(main())
