"""Statistics of the live latency benchmarks (bench/bench_live.py, bench/bench_bridge.py): pooled p99
ratios with a bootstrap over whole pairs, latency percentiles and where losses sit, and the matching
of outputs to inputs by value (for a node that stamps its output itself). Pure numpy, tested in
test/test_bench_stats.py and test/test_bench_bridge.py."""
from __future__ import annotations

from typing import Any, Sequence, Union

import numpy as np
import numpy.typing as npt

__all__ = ["HIST_EDGES_US", "pooled_p99_ratio", "latency_stats", "BRIDGE_PARAMETERS", "SEQ_STEP_N", "match_by_value",
           "first_as_new", "value_latency", "percentiles"]

#: A value of a statistics mapping: a count or a time (int, float), or an array (histogram counts, latencies in us).
Stat = Union[float, npt.NDArray[np.integer[Any]], npt.NDArray[np.float64]]

# Latency histograms in 1 us bins up to 100 ms (above: last bin), so pairs can be pooled and resampled.
HIST_EDGES_US = np.append(np.arange(0.0, 100_000.0 + 1.0, 1.0), np.inf)


def pooled_p99_ratio(hist_comp: Sequence[npt.ArrayLike], hist_relay: Sequence[npt.ArrayLike], n_boot: int = 2000,
                     seed: int = 0) -> tuple[float, float, float]:
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

    def __init__(self, hists: Sequence[npt.ArrayLike]) -> None:
        cum = np.cumsum(np.asarray(hists), axis=1)
        total = cum[:, -1:]
        first = np.argmax(cum >= 0.99 * total, axis=1)
        self.lo = int(first.min())
        self.window = cum[:, self.lo:int(first.max()) + 1]
        self.total = total[:, 0]

    def p99_us(self, picks: npt.NDArray[np.integer[Any]]) -> npt.NDArray[np.floating[Any]]:
        """picks: (n_resamples, n_runs) run indices; returns one p99 per resample (bin centres)."""
        counts, total = self.window[picks].sum(axis=1), self.total[picks].sum(axis=1)
        first: npt.NDArray[np.intp] = np.argmax(counts >= 0.99 * total[:, None], axis=1)
        return self.lo + first + 0.5


def latency_stats(stamp_ns: npt.NDArray[np.int64], received_ns: npt.NDArray[np.int64], t0_ns: int,
                  sent: int) -> dict[str, Stat]:
    """Latency percentiles (us) and losses of the measured samples (stamped at or after ``t0_ns``)."""
    keep = stamp_ns >= t0_ns
    st, lat_us = stamp_ns[keep], (received_ns[keep] - stamp_ns[keep]) / 1e3
    unique = np.unique(st)
    out: dict[str, Stat] = {"sent": sent, "received": int(unique.size), "lost": int(sent - unique.size),
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


#: haptic_bridge_node parameters under which its command is the latest input, unchanged.
BRIDGE_PARAMETERS = {
    "force_scale": 1.0,
    "deadband_n": 0.0,
    "max_force_n": 100.0,          # 24 N after 100 000 messages: never saturated
    "max_slew_n_per_s": 1.0e6,     # the highest allowed: 1 N per us, messages differ by 2**-12 N
    "stale_timeout_s": 10.0,       # no stale ramp during the run
    "device_axis": "z",            # the command on force.z, where the relay copies it
}
#: Force of the wrench source's message k: SEQ_STEP_N * (k + 1) N, exact in binary, distinct for every message
#: (24 N after 100 000 messages), and passed unchanged by a bridge with BRIDGE_PARAMETERS.
SEQ_STEP_N = 2.0 ** -12


# ---------------------------------------------------------------------- value matching (bench/bench_bridge.py)
def match_by_value(sent_value: npt.ArrayLike,
                   out_value: npt.ArrayLike) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]:
    """Pair outputs with inputs by exact value.

    Parameters
    ----------
    sent_value : array (n_sent,)
        The inputs' values in publish order, all distinct.
    out_value : array (n_out,)
        The outputs' values in arrival order (repeats, zeros and foreign values allowed).

    Returns
    -------
    out_index : int array (n_out,)
        For each output, the index of the input it carries, -1 if none.
    first_out : int array (n_sent,)
        For each input, the position of the first output that carries it, -1 if none.
    """
    sent_value = np.asarray(sent_value, dtype=float)
    out_value = np.asarray(out_value, dtype=float)
    order = np.argsort(sent_value, kind="stable")
    ordered = sent_value[order]
    if np.any(ordered[1:] == ordered[:-1]):
        raise ValueError("sent values must be distinct to be matched by value")
    out_index = np.full(out_value.size, -1, dtype=np.int64)
    if ordered.size:
        pos = np.minimum(np.searchsorted(ordered, out_value), ordered.size - 1)
        hit = ordered[pos] == out_value  # NaN never hits
        out_index[hit] = order[pos[hit]]
    first_out = np.full(sent_value.size, -1, dtype=np.int64)
    carried, first = np.unique(out_index, return_index=True)
    first_out[carried[carried >= 0]] = first[carried >= 0]
    return out_index, first_out


def first_as_new(out_index: npt.ArrayLike, n_sent: int) -> npt.NDArray[np.intp]:
    """For each input (by index in publish order), the position of the first output carrying it or a
    newer input (the time the receiver holds a command at least that fresh), -1 if none."""
    newest = np.maximum.accumulate(np.asarray(out_index, dtype=np.int64))  # non-decreasing: searchable
    pos = np.searchsorted(newest, np.arange(n_sent), side="left")
    return np.where(pos < newest.size, pos, -1)


def percentiles(lat_us: npt.NDArray[np.float64], prefix: str) -> dict[str, float]:
    """p50, p99 and max of latencies (us) under keys ``{prefix}p50_us`` etc.; NaN when there are none."""
    if lat_us.size == 0:
        return {f"{prefix}p50_us": float("nan"), f"{prefix}p99_us": float("nan"), f"{prefix}max_us": float("nan")}
    return {f"{prefix}p50_us": float(np.percentile(lat_us, 50)), f"{prefix}p99_us": float(np.percentile(lat_us, 99)),
            f"{prefix}max_us": float(lat_us.max())}


def value_latency(sent_value: npt.ArrayLike, sent_ns: npt.ArrayLike, out_value: npt.ArrayLike, out_stamp_ns: npt.ArrayLike,
                  out_ns: npt.ArrayLike, t0_ns: int, sent: int) -> dict[str, Stat]:
    """Latency statistics of the inputs published at or after ``t0_ns`` (``sent`` of them), matched by value.

    ``p50_us``/``p99_us``/``max_us``, ``hist`` and ``largest_gap_*`` as
    :func:`latency_stats` (publish -> arrival of the first output carrying
    the input); ``matched``/``unmatched`` inputs; ``outputs`` received and ``foreign_outputs``
    (distinct non-zero output values no input carried); ``fresh_*``: publish -> arrival of the first output
    carrying that input or a newer one, over every measured input (``never_fresh``: none arrived);
    ``node_p50_us``: publish -> the output's header stamp (the relay copies the input's stamp: 0);
    ``in_gap_ms``: the largest gap between two measured inputs' publish times; ``out_gap_ms``: the largest
    gap between two outputs' arrivals while matched outputs arrive (from the first to the last output
    carrying a measured input); ``lat_us``: the matched latencies (us).
    """
    sent_value, out_value = np.asarray(sent_value, dtype=float), np.asarray(out_value, dtype=float)
    sent_ns, out_ns, out_stamp_ns = (np.asarray(a, dtype=np.int64) for a in (sent_ns, out_ns, out_stamp_ns))
    out_index, first_out = match_by_value(sent_value, out_value)
    measured = sent_ns >= t0_ns
    matched = measured & (first_out >= 0)
    first = first_out[matched]
    stats = latency_stats(sent_ns[matched], out_ns[first], t0_ns, sent)
    stats["matched"], stats["unmatched"] = stats.pop("received"), stats.pop("lost")
    stats.pop("duplicates")  # one first arrival per input by construction
    stats["lat_us"] = (out_ns[first] - sent_ns[matched]) / 1e3
    node_us = (out_stamp_ns[first] - sent_ns[matched]) / 1e3
    stats["node_p50_us"] = float(np.median(node_us)) if node_us.size else float("nan")
    fresh = first_as_new(out_index, sent_value.size)[measured]
    fresh_lat_us = (out_ns[fresh[fresh >= 0]] - sent_ns[measured][fresh >= 0]) / 1e3
    stats.update(percentiles(fresh_lat_us, "fresh_"), never_fresh=int(np.sum(fresh < 0)), fresh_lat_us=fresh_lat_us)
    stats["outputs"] = int(out_value.size)
    stats["foreign_outputs"] = int(np.unique(out_value[(out_index < 0) & (out_value != 0.0)]).size)
    measured_sent = np.sort(sent_ns[measured])
    stats["in_gap_ms"] = float(np.diff(measured_sent).max() / 1e6) if measured_sent.size > 1 else float("nan")
    if first.size:
        arrivals = out_ns[out_ns.argsort(kind="stable")]
        span = arrivals[(arrivals >= out_ns[first].min()) & (arrivals <= out_ns[first].max())]
        stats["out_gap_ms"] = float(np.diff(span).max() / 1e6) if span.size > 1 else float("nan")
    else:
        stats["out_gap_ms"] = float("nan")
    return stats
