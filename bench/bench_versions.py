"""Benchmark 1 across versions: did a change make the 1 kHz path slower?

Three arms in one run, at 1 kHz as in ``bench_live.py``: the bare relay, the compensation node of
an earlier git revision (checked out into a temporary worktree and run from there), and the node
of this working tree. The order of the arms rotates every round, so none always runs first, and
the p99 ratios are pooled with a bootstrap interval that resamples whole rounds.

    .venv/bin/python bench/bench_versions.py REV [--rounds 10] [--seconds 20]

DDS stays on loopback in an isolated domain (as ``bench_live.py``).
"""
import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

import bench_live as live
from polyforce_ros.evaluation.latency import pooled_p99_ratio

REPO = Path(__file__).resolve().parent.parent


def commands(old_tree):
    node_args = ["--ros-args", "-p", "stale_timeout_s:=5.0"]
    return {
        "relay": [sys.executable, str(live.HERE / "live_parts.py"), "relay"],
        # the earlier package first on the path (an editable install does not shadow PYTHONPATH)
        "before": ["env", f"PYTHONPATH={old_tree}", sys.executable, "-c",
                   "import sys; from polyforce_ros.nodes.compensation_node import main; sys.exit(main())", *node_args],
        "now": [str(live.BIN / "compensation_node"), *node_args],
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("rev", help="the earlier git revision (e.g. a commit before a refactoring)")
    ap.add_argument("--rounds", type=int, default=10)
    ap.add_argument("--seconds", type=float, default=20.0)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        old_tree = Path(tmp) / "before"
        try:
            subprocess.run(["git", "-C", str(REPO), "worktree", "add", "--detach", "-q", str(old_tree), args.rev],
                           check=True, capture_output=True, text=True)
        except subprocess.CalledProcessError as exc:
            print(f"bench_versions: error: cannot check out {args.rev!r}: {exc.stderr.strip()}", file=sys.stderr)
            return 2
        try:
            cmds = commands(old_tree)
            live.node_cmd = cmds.__getitem__
            arms = list(cmds)
            hists, rows = {a: [] for a in arms}, []
            for r in range(args.rounds):
                row = {}
                for arm in arms[r % 3:] + arms[:r % 3]:
                    res = row[arm] = live.run_path(arm, 1000.0, args.seconds, tmp)
                    hists[arm].append(res.pop("hist"))
                    print(f"round {r} {arm:6s} p50 {res['p50_us']:6.0f} us  p99 {res['p99_us']:6.0f} us  max "
                          f"{res['max_us']:7.0f} us  lost {res['lost']}  node CPU {100 * res['node_cpu_fraction']:.1f} %",
                          flush=True)
                rows.append(row)
            for x, y in (("now", "relay"), ("before", "relay"), ("now", "before")):
                ratio, low, high = pooled_p99_ratio(hists[x], hists[y])
                per = ", ".join(f"{row[x]['p99_us'] / row[y]['p99_us']:.2f}" for row in rows)
                print(f"pooled p99 {x}/{y}: {ratio:.3f} (90 % interval {low:.3f}-{high:.3f}); per round {per}", flush=True)
        finally:
            subprocess.run(["git", "-C", str(REPO), "worktree", "remove", "--force", str(old_tree)], capture_output=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
