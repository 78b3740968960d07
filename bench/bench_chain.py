"""Live benchmark: the whole teleop chain, from the device's conversion to the haptic command, against bare relays.

    chain: virtual_device (pty) -> driver_node (serial) -> compensation_node -> haptic_bridge_node -> sink
    relay: virtual_device (pty) -> driver_node (serial) -> relay ------------> relay ------------> sink

Every stage runs as its own process: firmware/host/virtual_device (built with ``make -C firmware`` into a
temporary folder) streams 1 kHz frames into a pty, the installed console scripts driver_node (serial
backend, reading the pty through a stable link), compensation_node and haptic_bridge_node carry them on.
The baseline replaces the two nodes after the driver with as many bare rclpy relays (``--relays``, 2: the
same number of processes and DDS hops; the first turns ``bridge_voltage`` into a WrenchStamped, the last
publishes ``haptic_command`` with the bridge's command QoS; no computation). One sink process records
``wrench`` (the second stage's output: the sample's stamp and force) and ``haptic_command`` (force and
arrival time) in both arms.

End-to-end latency of a sample: its stamp (the driver's host-time mapping of the device's acquisition
instant) -> arrival of the first command carrying it. The bridge stamps its command when it publishes, so
commands are paired with wrenches by value, in order (:func:`match_in_order`); in the relay arm the
command keeps the sample's stamp: it is timed by that stamp, and the pairing by value is checked against
it (``stamp_agrees``). Delivered share: the measured samples whose command arrived, over the frames the
device acquired in the measured window (its log; the window's edges are exact to the stamp's offset from
the acquisition, about a frame).

Each arm runs in a ROS domain of its own (nothing of the previous arm is discovered) and waits until the
whole chain flows (the sink holds a command that is not zero), then 1 s more, then measures
``--seconds / --pairs`` s. Relay and chain arms are interleaved in pairs (both see the same
machine state); latencies are pooled per arm. Reported: p50, p99, max and the delivered share per arm,
and as ratios chain / relay in one run (the p99 ratio with a 90 % bootstrap interval over pairs, and over
the pairs without a stall, a latency over 100 ms in either arm, beside it); the 1-minute load average
after each arm tells what else the machine was doing.

    .venv/bin/python bench/bench_chain.py [--seconds 30] [--pairs 3] [--rate 1000] [--relays 2]
DDS stays on loopback in an isolated domain (chosen by main(); the processes it starts inherit it).
"""
from __future__ import annotations

import argparse
import bisect
import json
import os
import queue
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

from processes import isolate_dds, stop_pid

from polyforce_ros.evaluation.latency import BRIDGE_PARAMETERS, HIST_EDGES_US, percentiles, pooled_p99_ratio

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))  # bench/ is a folder of scripts, not a package: the parts import live_parts
BIN = Path(sys.executable).parent
REPO = HERE.parent
KINDS = ("relay", "chain")
NS = "/polyforce"
#: The device's counts map to volts exactly (8 V reference, gain 1: 2**-20 V per count); 1.0e6 counts of
#: sine amplitude are 0.95 V, about 4.6 N through the shipped model: inside its 12 N clamp, so the forces
#: stay distinct and the bridge passes each one on unchanged (BRIDGE_PARAMETERS).
VOLTS_PER_COUNT = 2.0 ** -20
DEVICE_ARGS = ("--vref-uv", "8000000", "--gain", "1", "--amplitude", "1000000", "--offset", "100000",
               "--freq", "1.7", "--status-period", "1", "--temp-period", "0")
#: compensation_node: no start-up zeroing (the simulated sensor moves from its first frame), so every
#: sample is compensated; a stale timeout well above any stall of a loaded machine.
COMPENSATION_PARAMETERS = {"auto_tare": "false", "stale_timeout_s": "5.0"}


# ---------------------------------------------------------------------- analysis (pure numpy, no DDS)
def match_in_order(in_values, out_values, lookahead=5000):
    """Pair each output with the input it carries: the first input at or after the previous output's
    input with the same value (outputs come in input order; an output may repeat its input).

    Zero never matches (an idle or stale command). An output whose value appears no further than
    ``lookahead`` inputs ahead is unmatched (-1) and does not move the search on.
    """
    positions: dict = {}
    for i, v in enumerate(np.asarray(in_values, dtype=float).tolist()):
        if v != 0.0:
            positions.setdefault(v, []).append(i)
    out = np.full(len(out_values), -1, dtype=np.int64)
    j = 0
    for n, v in enumerate(np.asarray(out_values, dtype=float).tolist()):
        lst = positions.get(v)
        if not lst:
            continue
        k = bisect.bisect_left(lst, j)
        if k < len(lst) and lst[k] - j <= lookahead:
            j = out[n] = lst[k]
    return out


def chain_latency(in_stamp_ns, in_value, out_value, out_ns, t0_ns, t1_ns, frames, out_stamp_ns=None):
    """Latency and delivery of the samples stamped in [t0_ns, t1_ns).

    ``in_*``: the second stage's messages (sample stamp, value) in arrival order; ``out_*``: the commands
    (value, arrival time, and for a relay its header stamp) in arrival order; ``frames``: the device's
    conversions in the window.

    With ``out_stamp_ns`` (a relay: the command keeps its sample's stamp) the commands are timed by their
    own stamps, and the pairing by value is only checked against them (``stamp_agrees``: the share of
    paired commands whose stamp is their sample's). Without, each sample is timed by the first command
    paired with it (:func:`match_in_order`); a non-zero command arriving in the window that no sample
    explains (the sink missed that ``wrench``) still delivered a sample, untimed (``delivered_untimed``).

    Returns ``p50_us``/``p99_us``/``max_us`` (stamp -> first command carrying the sample), ``hist`` (1 us
    bins, for :func:`pooled_p99_ratio`), ``lat_us``, ``frames``, ``delivered`` (distinct measured samples
    whose command arrived), ``delivered_share``, ``delivered_untimed``, ``commands``,
    ``unmatched_commands`` (non-zero commands arriving in [t0_ns, t1_ns) that no ``wrench`` explains; after
    t1_ns the arms are being stopped, and a stage that exits can leave the sink without its last
    ``wrench`` messages while the next stage already passed them on; those are ``unmatched_after_window``) and
    ``stamp_agrees`` (None without stamps).
    """
    in_stamp_ns, out_ns = np.asarray(in_stamp_ns, dtype=np.int64), np.asarray(out_ns, dtype=np.int64)
    out_value = np.asarray(out_value, dtype=float)
    idx = match_in_order(in_value, out_value)
    hit = idx >= 0
    unmatched = ~hit & (out_value != 0.0)
    untimed = 0
    if out_stamp_ns is not None:
        out_stamp_ns = np.asarray(out_stamp_ns, dtype=np.int64)
        stamps, first = np.unique(out_stamp_ns[out_value != 0.0], return_index=True)  # first command per stamp
        first_ns = out_ns[out_value != 0.0][first]
    else:
        samples, first = np.unique(idx[hit], return_index=True)  # the first command carrying each sample
        first_ns, stamps = out_ns[hit][first], in_stamp_ns[samples]
        untimed = int(np.sum(unmatched & (out_ns >= t0_ns) & (out_ns < t1_ns)))
    measured = (stamps >= t0_ns) & (stamps < t1_ns)
    stamps, first_ns = stamps[measured], first_ns[measured]
    # a sample that reached the sink's `wrench` twice (a DDS duplicate) counts once
    unique_stamps, keep = np.unique(stamps, return_index=True)
    lat_us = (first_ns[keep] - unique_stamps) / 1e3
    delivered = int(unique_stamps.size) + untimed
    out = dict(percentiles(lat_us, ""), hist=np.histogram(lat_us, HIST_EDGES_US)[0], lat_us=lat_us,
               frames=int(frames), delivered=delivered, delivered_untimed=untimed,
               delivered_share=float(delivered / frames) if frames else float("nan"),
               commands=int(out_value.size),
               unmatched_commands=int(np.sum(unmatched & (out_ns >= t0_ns) & (out_ns < t1_ns))),
               unmatched_after_window=int(np.sum(unmatched & (out_ns >= t1_ns))))
    out["stamp_agrees"] = None
    if out_stamp_ns is not None and hit.any():
        out["stamp_agrees"] = float(np.mean(out_stamp_ns[hit] == in_stamp_ns[idx[hit]]))
    return out


def device_frames(log_path, t0_ns, t1_ns):
    """Valid frames the virtual device acquired in [t0_ns, t1_ns) (its log's F lines, acq_ns field)."""
    text = Path(log_path).read_text()
    n = 0
    for line in text[: text.rfind("\n") + 1].splitlines():
        if line.startswith("F "):
            acq = int(line.split()[4])
            n += t0_ns <= acq < t1_ns
    return n


# ---------------------------------------------------------------------- processes
def build_device(build_dir):
    """firmware/host/virtual_device built with ``make -C firmware`` into ``build_dir``; returns its path."""
    cc = shutil.which("gcc") or shutil.which("clang")
    if cc is None or shutil.which("make") is None:
        raise SystemExit("gcc or clang, and make, are needed to build the virtual device")
    exe = Path(build_dir) / "virtual_device"
    proc = subprocess.run(["make", "-C", str(REPO / "firmware"), f"BUILD={build_dir}", f"CC={cc}", str(exe)],
                          capture_output=True, text=True, timeout=300)
    if proc.returncode != 0:
        raise SystemExit(proc.stdout[-2000:] + proc.stderr[-4000:])
    return exe


class Device:
    """The virtual device on a pty behind the link ``folder/tty``, logging every frame to ``folder/device.log``."""

    def __init__(self, exe, folder, rate_hz):
        self.link, self.log = Path(folder) / "tty", Path(folder) / "device.log"
        self._err = open(Path(folder) / "device.err", "w")
        self.proc = subprocess.Popen([str(exe), "--link", str(self.link), "--log", str(self.log), "--rate",
                                      str(int(rate_hz)), *DEVICE_ARGS], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=self._err, text=True, bufsize=1)
        self.lines: queue.Queue = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        for line in self.proc.stdout:
            self.lines.put(line.rstrip("\n"))

    def wait_for_pty(self, timeout=20.0):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            try:
                if self.lines.get(timeout=0.1).startswith("pty "):
                    return
            except queue.Empty:
                if self.proc.poll() is not None:
                    break
        raise RuntimeError(f"the virtual device made no pty (exit status {self.proc.poll()})")

    def stop(self):
        stop_pid(self.proc)
        with_suppressed(self.proc.stdin.close)
        self._err.close()


def with_suppressed(fn):
    try:
        fn()
    except OSError:
        pass


def ros_args(params):
    return ["--ros-args", "-r", f"__ns:={NS}", *[a for k, v in params.items() for a in ("-p", f"{k}:={v}")]]


def stage_cmds(kind, relays):
    """The processes after the driver, first stage first."""
    if kind == "chain":
        return [[str(BIN / "compensation_node"), *ros_args(COMPENSATION_PARAMETERS)],
                [str(BIN / "haptic_bridge_node"), *ros_args(BRIDGE_PARAMETERS)]]
    return [[sys.executable, str(Path(__file__).resolve()), "part", "relay", str(i), str(relays)] for i in range(relays)]


def run_arm(kind, exe, seconds, rate_hz, relays, tmp, flow_timeout=60.0, settle_s=1.0, domain=None):
    """One run of ``kind``: device, sink, stages, driver; waits for the flow, measures ``seconds``; returns stats.

    ``domain``: the ROS domain of this run's processes (default: the environment's).
    """
    env = dict(os.environ) if domain is None else dict(os.environ, ROS_DOMAIN_ID=str(domain))
    folder = Path(tempfile.mkdtemp(prefix=f"{kind}_", dir=tmp))
    out = folder / "sink.npz"
    procs, logs, device = [], [], None

    def spawn(name, argv):
        log = open(folder / f"{name}.log", "w")
        logs.append(log)
        procs.append((name, subprocess.Popen(argv, stdout=log, stderr=subprocess.STDOUT, env=env)))

    try:
        device = Device(exe, folder, rate_hz)
        device.wait_for_pty()
        spawn("sink", [sys.executable, str(Path(__file__).resolve()), "part", "sink", str(out)])
        for i, argv in reversed(list(enumerate(stage_cmds(kind, relays)))):  # the last stage listens first
            spawn(f"stage{i}", argv)
        driver_params = dict(backend="serial", port=str(device.link), volts_per_count=repr(VOLTS_PER_COUNT),
                             volts_offset="0.0", reconnect_period_s="0.05", expected_rate_hz=repr(float(rate_hz)))
        spawn("driver", [str(BIN / "driver_node"), *ros_args(driver_params)])
        flowing, deadline = Path(str(out) + ".flowing"), time.monotonic() + flow_timeout
        while not flowing.exists():
            dead = [(name, p.returncode) for name, p in procs if p.poll() is not None]
            if dead or time.monotonic() > deadline:
                for log in logs:
                    log.flush()
                tails = {p.name: p.read_text()[-1500:] for p in folder.glob("*.log") if p.name != "device.log"}
                raise RuntimeError(f"{kind}: the chain did not flow within {flow_timeout:g} s (exited: {dead}); "
                                   f"logs: {json.dumps(tails, indent=1)}")
            time.sleep(0.05)
        warmup_s = flow_timeout - (deadline - time.monotonic())
        time.sleep(settle_s)
        t0_ns = time.time_ns()
        time.sleep(seconds)
        t1_ns = time.time_ns()
        time.sleep(1.0)  # the last measured samples reach the sink
    finally:
        for _name, proc in reversed(procs):  # the driver first, the sink last (it saves on SIGINT)
            stop_pid(proc)
        if device is not None:
            device.stop()
        for log in logs:
            log.close()
    with np.load(out) as d:
        stats = chain_latency(d["in_stamp_ns"], d["in_value"], d["out_value"], d["out_ns"], t0_ns, t1_ns,
                              device_frames(device.log, t0_ns, t1_ns), d["out_stamp_ns"] if kind == "relay" else None)
        # where a delay arises: the sample's stamp -> its `wrench` reaching the sink (device, driver, first stage)
        wrench = (d["in_stamp_ns"] >= t0_ns) & (d["in_stamp_ns"] < t1_ns)
        to_wrench_us = (d["in_ns"][wrench] - d["in_stamp_ns"][wrench]) / 1e3
        stats.update(percentiles(to_wrench_us, "to_wrench_"), wrenches=int(np.sum(wrench)))
        if to_wrench_us.size:
            stats["to_wrench_max_at_s"] = float((d["in_stamp_ns"][wrench][np.argmax(to_wrench_us)] - t0_ns) / 1e9)
    stats.update(kind=kind, rate_hz=rate_hz, seconds=seconds, warmup_s=warmup_s, load1=os.getloadavg()[0])
    shutil.rmtree(folder, ignore_errors=True)
    return stats


def interleaved_pairs(exe, pairs, seconds, rate_hz, relays, tmp, log=print):
    """Relay/chain pairs of ``seconds`` each; pooled statistics per arm and the ratios chain / relay."""
    report, pooled = {}, {kind: {"lat": [], "hist": [], "frames": 0, "delivered": 0} for kind in KINDS}
    for rep in range(pairs):
        pair = {}
        for kind in KINDS:
            # each arm in a domain of its own: nothing of the previous arm is discovered or matched
            domain = 100 + (int(os.environ.get("ROS_DOMAIN_ID", "100")) + 2 * rep + KINDS.index(kind)) % 100
            r = pair[kind] = run_arm(kind, exe, seconds, rate_hz, relays, tmp, domain=domain)
            pooled[kind]["lat"].append(r.pop("lat_us"))
            pooled[kind]["hist"].append(r.pop("hist"))
            pooled[kind]["frames"] += r["frames"]
            pooled[kind]["delivered"] += r["delivered"]
            log(f"{kind:<5} p50 {r['p50_us']:7.0f} us  p99 {r['p99_us']:7.0f} us  max {r['max_us']:8.0f} us  "
                f"delivered {r['delivered']} of {r['frames']} ({100 * r['delivered_share']:.2f} %, untimed "
                f"{r['delivered_untimed']})  `wrench` {r['wrenches']}, commands {r['commands']}, "
                f"unmatched {r['unmatched_commands']} (after the window {r['unmatched_after_window']})  "
                f"flowing after {r['warmup_s']:.1f} s  load {r['load1']:.1f}  stamp -> `wrench` at the sink: "
                f"p50 {r['to_wrench_p50_us']:.0f} us, max {r['to_wrench_max_us']:.0f} us"
                + (f"  stamps agree {100 * r['stamp_agrees']:.2f} %" if kind == "relay" else ""))
        report[f"pair{rep}"] = pair
    summary = {}
    for kind in KINDS:
        p = pooled[kind]
        summary[kind] = dict(percentiles(np.concatenate(p["lat"]), ""), frames=p["frames"], delivered=p["delivered"],
                             delivered_share=p["delivered"] / p["frames"] if p["frames"] else float("nan"))
    chain, relay = summary["chain"], summary["relay"]
    ratio, low, high = pooled_p99_ratio(pooled["chain"]["hist"], pooled["relay"]["hist"])
    stalled = {kind: [rep for rep in range(pairs) if report[f"pair{rep}"][kind]["max_us"] > 100_000] for kind in KINDS}
    calm = [rep for rep in range(pairs) if not any(rep in stalled[kind] for kind in KINDS)]  # pairs without a stall
    ratio_calm = (pooled_p99_ratio([pooled["chain"]["hist"][rep] for rep in calm],
                                   [pooled["relay"]["hist"][rep] for rep in calm]) if calm else (float("nan"),) * 3)
    summary.update(pairs_with_a_stall=stalled, ratio_p99_without_stalls=ratio_calm[0],
                   ratio_p99_without_stalls_interval=list(ratio_calm[1:]))
    summary.update(ratio_p50=chain["p50_us"] / relay["p50_us"], ratio_p99=ratio, ratio_p99_interval=[low, high],
                   ratio_delivered=chain["delivered_share"] / relay["delivered_share"],
                   added_p50_us=chain["p50_us"] - relay["p50_us"], pairs=pairs, seconds_per_arm=seconds,
                   rate_hz=rate_hz, relays=relays)
    for kind in KINDS:
        s = summary[kind]
        log(f"pooled {kind:<5} ({pairs} x {seconds:g} s): p50 {s['p50_us']:.0f} us, p99 {s['p99_us']:.0f} us, "
            f"max {s['max_us']:.0f} us, delivered {s['delivered']} of {s['frames']} ({100 * s['delivered_share']:.2f} %)")
    log(f"chain / relay: p50 {summary['ratio_p50']:.2f} ({summary['added_p50_us']:+.0f} us), p99 {ratio:.2f} "
        f"(90 % bootstrap interval over pairs {low:.2f}-{high:.2f}), delivered {summary['ratio_delivered']:.4f}")
    if any(stalled.values()):
        log("pairs with a latency over 100 ms (a stall: the pooled p99 is the stall's): "
            + ", ".join(f"{kind} {stalled[kind]}" for kind in KINDS if stalled[kind])
            + f"; p99 ratio over the {len(calm)} pairs without one: {ratio_calm[0]:.2f} "
            f"(interval {ratio_calm[1]:.2f}-{ratio_calm[2]:.2f})")
    report["pooled"] = summary
    return report


# ---------------------------------------------------------------------- the ROS parts (run as `part ...`)
def part(role, args):
    import rclpy
    from geometry_msgs.msg import WrenchStamped
    from rclpy.node import Node
    from sensor_msgs.msg import JointState

    from live_parts import COMMAND_QOS, QOS, run
    from polyforce_ros import contract
    from polyforce_ros.nodes.haptic_bridge_node import HAPTIC_COMMAND

    rclpy.init()
    try:
        if role == "relay":  # relay i of n: bridge_voltage -> ... -> wrench -> haptic_command
            i, n = int(args[0]), int(args[1])
            topics = [contract.Rel.BRIDGE_VOLTAGE] + [f"relay_{k}" for k in range(1, n - 1)] + [
                contract.Rel.WRENCH, HAPTIC_COMMAND]
            node = Node(f"relay_{i}", namespace=NS)
            pub = node.create_publisher(WrenchStamped, topics[i + 1], COMMAND_QOS if i == n - 1 else QOS)
            if i == 0:
                out = WrenchStamped()

                def on_raw(msg):
                    out.header = msg.header
                    out.wrench.force.z = msg.position[0]
                    pub.publish(out)

                node.create_subscription(JointState, topics[0], on_raw, QOS)
            else:
                node.create_subscription(WrenchStamped, topics[i], pub.publish, QOS)
            run(node)
        elif role == "sink":  # `wrench` (stamp, force) and `haptic_command` (force, stamp, arrival), saved on SIGINT
            path = args[0]
            node = Node("bench_chain_sink", namespace=NS)
            ins, outs = ([], [], []), ([], [], [])
            flowing = {"path": path + ".flowing"}

            def mark_flowing():
                # the whole chain flows once the sink hears both ends: a command alone can arrive before the
                # sink's `wrench` subscription is discovered, and every command would then be unmatched
                if flowing["path"] and ins[1] and outs[0][-1] != 0.0:
                    open(flowing["path"], "w").close()
                    flowing["path"] = None

            def on_wrench(msg):
                ins[2].append(time.time_ns())
                ins[0].append(msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec)
                ins[1].append(msg.wrench.force.z)

            def on_command(msg):
                outs[2].append(time.time_ns())
                outs[0].append(msg.wrench.force.z)
                outs[1].append(msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec)
                mark_flowing()

            node.create_subscription(WrenchStamped, contract.Rel.WRENCH, on_wrench, QOS)
            node.create_subscription(WrenchStamped, HAPTIC_COMMAND, on_command, QOS)
            run(node)
            np.savez(path, in_stamp_ns=np.array(ins[0], dtype=np.int64), in_value=np.array(ins[1]),
                     in_ns=np.array(ins[2], dtype=np.int64),
                     out_value=np.array(outs[0]), out_stamp_ns=np.array(outs[1], dtype=np.int64),
                     out_ns=np.array(outs[2], dtype=np.int64))
        else:
            raise SystemExit(f"unknown part {role!r}")
    finally:
        if rclpy.ok():
            rclpy.shutdown()


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["part"]:
        return part(argv[1], argv[2:])
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seconds", type=float, default=30.0, help="measured seconds per arm, split over the pairs")
    ap.add_argument("--pairs", type=int, default=3, help="interleaved relay/chain runs of seconds / pairs each")
    ap.add_argument("--rate", type=float, default=1000.0, help="the device's conversion rate (Hz)")
    ap.add_argument("--relays", type=int, default=2, help="bare relays in the baseline (2: one per node they stand for)")
    args = ap.parse_args(argv)
    isolate_dds()
    if args.pairs < 1 or args.seconds <= 0 or args.relays < 2:
        ap.error("--pairs must be >= 1, --relays >= 2 (the sink reads the last but one's `wrench`), --seconds > 0")
    with tempfile.TemporaryDirectory() as tmp:
        exe = build_device(tmp)
        report = interleaved_pairs(exe, args.pairs, args.seconds / args.pairs, args.rate, args.relays, tmp,
                                   log=lambda text: print(text, flush=True))
    print(json.dumps(report))


if __name__ == "__main__":
    main()
