"""The value matching of bench/bench_bridge.py and its bridge parameters, without DDS or timing."""
import numpy as np
import pytest

from polyforce_ros.evaluation import latency as bench_bridge
from polyforce_ros.haptics import HapticBridge, HapticConfig


MS = 1_000_000  # ns


def test_value_latency_pairs_each_input_with_the_first_command_carrying_it():
    step = bench_bridge.SEQ_STEP_N
    # inputs 0..5; 0 is warm-up; 2 is superseded by 3 before the 2.5 ms tick; 5 is never sent on
    sent_ns = np.array([0.0, 1.0, 2.0, 2.2, 4.0, 5.0]) * MS
    values = step * np.arange(1, 7)
    # a zero-order hold ticking at x.5 ms, its commands arriving 0.1 ms later, plus an idle zero,
    # repeats and a foreign value (twice: one distinct foreign output)
    ticks = np.array([-0.5, 0.5, 1.5, 2.5, 3.5, 4.5, 4.6, 4.7, 5.5]) * MS
    out_values = np.array([0.0, values[0], values[1], values[3], values[3], values[4], 0.123, 0.123, values[4]])
    out_ns = ticks + 0.1 * MS

    out_index, first_out = bench_bridge.match_by_value(values, out_values)
    assert out_index.tolist() == [-1, 0, 1, 3, 3, 4, -1, -1, 4]
    assert first_out.tolist() == [1, 2, -1, 3, 5, -1]
    assert bench_bridge.first_as_new(out_index, values.size).tolist() == [1, 2, 3, 3, 5, -1]

    stats = bench_bridge.value_latency(values, sent_ns, out_values, ticks, out_ns, t0_ns=1 * MS, sent=5)
    assert (stats["sent"], stats["matched"], stats["unmatched"]) == (5, 3, 2)
    assert stats["lat_us"].tolist() == pytest.approx([600.0, 400.0, 600.0])
    assert (stats["p50_us"], stats["max_us"]) == pytest.approx((600.0, 600.0))
    assert stats["node_p50_us"] == pytest.approx(500.0)  # input publish -> the command's stamp (its tick)
    assert stats["fresh_lat_us"].tolist() == pytest.approx([600.0, 600.0, 400.0, 600.0])  # 2 counts via 3
    assert stats["never_fresh"] == 1
    assert (stats["outputs"], stats["foreign_outputs"]) == (9, 1)
    assert stats["in_gap_ms"] == pytest.approx(1.8)  # inputs 2.2 -> 4.0 ms
    assert stats["out_gap_ms"] == pytest.approx(1.0)  # commands arriving 1.6 ... 4.6 ms, the first to the last matched


def test_match_by_value_refuses_repeated_inputs_and_ignores_nan():
    with pytest.raises(ValueError):
        bench_bridge.match_by_value([1.0, 2.0, 1.0], [1.0])
    out_index, first_out = bench_bridge.match_by_value([1.0, 2.0], [np.nan, 2.0, 3.0])
    assert out_index.tolist() == [-1, 1, -1] and first_out.tolist() == [-1, 1]


def test_the_bench_parameters_make_the_bridge_pass_every_sent_value_unchanged():
    """Each input's command is that input's value (the first, after the silence before it, excepted)."""
    config = HapticConfig(**{k: v for k, v in bench_bridge.BRIDGE_PARAMETERS.items() if k in HapticConfig.names()})
    bridge = HapticBridge(config)
    rng = np.random.default_rng(3)
    arrival, stamp, latest = 0.0, 0.0, 0.0
    for k in range(20_000):  # stamps 1 us - 60 ms apart (1 kHz mostly), arriving in bursts and with gaps
        stamp += rng.choice([1e-6, 1e-3, 0.06], p=[0.1, 0.89, 0.01])
        arrival += rng.choice([0.0, 1e-6, 1e-3, 0.06], p=[0.2, 0.1, 0.69, 0.01])
        latest = bench_bridge.SEQ_STEP_N * (k + 1)
        command = bridge.step(arrival, latest, stamp)
        assert command == (latest if k else 0.0)
        if rng.random() < 0.7:
            assert bridge.tick(arrival + 1e-6) == command  # the timer changes nothing while inputs flow
    assert latest < config.max_force_n and bridge.counts["saturated"] == 0
