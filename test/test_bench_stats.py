"""The statistics of bench/latency.py: pooled p99 ratio from histograms, losses located."""
import numpy as np
import pytest

from polyforce_ros.evaluation import latency


def _hist(lat_us):
    return np.histogram(lat_us, latency.HIST_EDGES_US)[0]


def test_pooled_p99_ratio_matches_percentiles_of_the_pooled_samples():
    rng = np.random.default_rng(1)
    relay = [rng.gamma(4.0, 70.0, 20000) for _ in range(6)]
    comp = [1.2 * rng.gamma(4.0, 70.0, 20000) for _ in range(6)]
    ratio, low, high = latency.pooled_p99_ratio([_hist(x) for x in comp], [_hist(x) for x in relay])
    expected = np.percentile(np.concatenate(comp), 99) / np.percentile(np.concatenate(relay), 99)
    assert ratio == pytest.approx(expected, abs=0.01)
    assert low <= ratio <= high
    assert 1.1 < low and high < 1.3  # the 20 % slower path is resolved, not hidden in the interval


def test_losses_count_only_the_measured_window_and_locate_the_hole():
    t0 = 10_000_000_000
    stamps = t0 + np.arange(-50, 1000) * 1_000_000  # 50 warm-up samples before t0
    keep = (stamps < t0 + 400_000_000) | (stamps >= t0 + 430_000_000)  # 30 lost at 0.4 s
    stamps = stamps[keep]
    stats = latency.latency_stats(stamps, stamps + 300_000, t0, sent=1000)
    assert stats["lost"] == 30 and stats["received"] == 970
    assert stats["largest_gap_ms"] == pytest.approx(31.0)
    assert stats["largest_gap_at_s"] == pytest.approx(0.399)
    assert stats["p50_us"] == pytest.approx(300.0)
