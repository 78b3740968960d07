"""Statistics of the live latency benchmark (bench/bench_live.py): pooled p99 ratios with a
bootstrap over whole pairs, latency percentiles and where losses sit. Pure numpy, tested in
test/test_bench_stats.py."""
from __future__ import annotations

import numpy as np

__all__ = ["HIST_EDGES_US", "pooled_p99_ratio", "latency_stats"]

# Latency histograms in 1 us bins up to 100 ms (above: last bin), so pairs can be pooled and resampled.
HIST_EDGES_US = np.append(np.arange(0.0, 100_000.0 + 1.0, 1.0), np.inf)


def pooled_p99_ratio(hist_comp, hist_relay, n_boot=2000, seed=0):
    """p99 of the pooled compensation latencies over p99 of the pooled relay latencies,
    with a 90 % bootstrap interval that resamples whole pairs (the unit that shares machine state)."""
    rng = np.random.default_rng(seed)
    picks = rng.integers(0, len(hist_comp), size=(n_boot, len(hist_comp)))
    comp, relay = _P99Pool(hist_comp), _P99Pool(hist_relay)
    ratio = comp.p99_us(np.arange(len(hist_comp))[None])[0] / relay.p99_us(np.arange(len(hist_relay))[None])[0]
    boot = comp.p99_us(picks) / relay.p99_us(picks)
    return float(ratio), float(np.percentile(boot, 5)), float(np.percentile(boot, 95))


class _P99Pool:
    """p99 (us) of the union of chosen runs, from their latency histograms.

    The pooled CDF is a weighted mean of the runs' CDFs, so its p99 lies between the
    smallest and the largest per-run p99: only that window of bins is kept.
    """

    def __init__(self, hists):
        cum = np.cumsum(np.asarray(hists), axis=1)
        total = cum[:, -1:]
        first = np.argmax(cum >= 0.99 * total, axis=1)
        self.lo = int(first.min())
        self.window = cum[:, self.lo:int(first.max()) + 1]
        self.total = total[:, 0]

    def p99_us(self, picks):
        """picks: (n_resamples, n_runs) run indices; returns one p99 per resample (bin centres)."""
        counts, total = self.window[picks].sum(axis=1), self.total[picks].sum(axis=1)
        return self.lo + np.argmax(counts >= 0.99 * total[:, None], axis=1) + 0.5


def latency_stats(stamp_ns, received_ns, t0_ns, sent):
    """Latency percentiles (us) and losses of the measured samples (stamped at or after ``t0_ns``)."""
    keep = stamp_ns >= t0_ns
    st, lat_us = stamp_ns[keep], (received_ns[keep] - stamp_ns[keep]) / 1e3
    unique = np.unique(st)
    out = {"sent": sent, "received": int(unique.size), "lost": int(sent - unique.size),
           "duplicates": int(st.size - unique.size), "hist": np.histogram(lat_us, HIST_EDGES_US)[0]}
    if unique.size:
        out.update(p50_us=float(np.percentile(lat_us, 50)), p99_us=float(np.percentile(lat_us, 99)),
                   max_us=float(lat_us.max()))
    else:
        out.update(p50_us=float("nan"), p99_us=float("nan"), max_us=float("nan"))
    if unique.size > 1:  # where a loss sits: the largest hole between received stamps
        gaps = np.diff(unique)
        worst = int(np.argmax(gaps))
        out.update(largest_gap_ms=float(gaps[worst] / 1e6), largest_gap_at_s=float((unique[worst] - t0_ns) / 1e9))
    else:
        out.update(largest_gap_ms=float("nan"), largest_gap_at_s=float("nan"))
    return out


