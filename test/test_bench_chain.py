"""bench/bench_chain.py: its pairing of commands with samples and its statistics on made-up data (unit), and
one short relay/chain pair through the virtual device, the installed nodes and the relays (process; no
timing is judged, only that every stage carried samples and the pairing agrees with the relay's stamps)."""
import shutil
import sys

import numpy as np
import pytest

from conftest import REPO

sys.path.insert(0, str(REPO / "bench"))
import bench_chain  # noqa: E402

MS = 1_000_000  # ns


@pytest.mark.unit
def test_match_in_order_pairs_repeats_and_skips_zero_and_strangers():
    # the sine's values come back later (2.0 at 1 and 5): an output matches the first one at or after the
    # previous output's input; a repeated command keeps its input; zero and a stranger match nothing
    inputs = [1.0, 2.0, 3.0, 0.0, 4.0, 2.0]
    outputs = [0.0, 1.0, 2.0, 2.0, 9.0, 3.0, 0.0, 4.0, 2.0]
    assert bench_chain.match_in_order(inputs, outputs).tolist() == [-1, 0, 1, 1, -1, 2, -1, 4, 5]
    # beyond the lookahead an equal value is another sample's: unmatched, and the search does not jump there
    assert bench_chain.match_in_order([1.0, 5.0, 6.0, 7.0, 8.0, 1.0], [1.0, 8.0, 5.0], lookahead=2).tolist() == [0, -1, 1]


@pytest.mark.unit
def test_chain_latency_counts_each_measured_sample_once_from_its_stamp():
    stamps = np.arange(10) * MS                      # samples 0..9, 1 ms apart
    values = 0.5 + np.arange(10)
    # commands: sample 0 (warm-up), 2 twice (the second arrival is not its latency), 3, 5 (4 never came),
    # a zero, 6, 7, 8 (after the window's end: not measured)
    cmd_values = np.array([0.5, 2.5, 2.5, 3.5, 5.5, 0.0, 6.5, 7.5, 8.5])
    cmd_ns = np.array([0.3, 2.4, 2.9, 3.2, 5.6, 5.7, 6.1, 7.2, 8.1]) * MS
    cmd_stamps = np.array([0, 2, 2, 3, 5, 0, 6, 7, 8]) * MS
    s = bench_chain.chain_latency(stamps, values, cmd_values, cmd_ns, t0_ns=2 * MS, t1_ns=8 * MS, frames=6,
                                  out_stamp_ns=cmd_stamps)
    assert s["lat_us"].tolist() == pytest.approx([400.0, 200.0, 600.0, 100.0, 200.0])  # samples 2, 3, 5, 6, 7
    assert (s["delivered"], s["frames"], s["delivered_share"]) == (5, 6, pytest.approx(5 / 6))
    assert (s["commands"], s["unmatched_commands"]) == (9, 0)
    assert s["p50_us"] == pytest.approx(200.0) and s["max_us"] == pytest.approx(600.0)
    assert s["hist"].sum() == 5 and s["stamp_agrees"] == 1.0
    # a stranger before the window (a warm-up command whose wrench the sink missed) is not counted, one in it is
    strangers = cmd_values.copy()
    strangers[[0, 3]] = 42.0
    s = bench_chain.chain_latency(stamps, values, strangers, cmd_ns, 2 * MS, 8 * MS, 6)
    assert s["unmatched_commands"] == 1  # and it delivered a sample in the window, untimed
    assert (s["delivered"], s["delivered_untimed"], s["lat_us"].size) == (5, 1, 4)
    # a relay's command is timed by its own stamp, whether or not the sink saw the sample's `wrench`; the
    # commands the sink cannot explain are counted in the window only (8.5 arrives after it, at 8.1 ms)
    s = bench_chain.chain_latency(stamps[:4], values[:4], cmd_values, cmd_ns, 2 * MS, 8 * MS, 6, out_stamp_ns=cmd_stamps)
    assert s["lat_us"].tolist() == pytest.approx([400.0, 200.0, 600.0, 100.0, 200.0]) and s["unmatched_commands"] == 3
    assert s["unmatched_after_window"] == 1
    # a command carrying another sample's stamp shows in stamp_agrees
    cmd_stamps[3] = 4 * MS
    assert bench_chain.chain_latency(stamps, values, cmd_values, cmd_ns, 2 * MS, 8 * MS, 6,
                                     cmd_stamps)["stamp_agrees"] == pytest.approx(7 / 8)  # 8 matched
    assert bench_chain.chain_latency(stamps, values, cmd_values, cmd_ns, 2 * MS, 8 * MS, 6)["stamp_agrees"] is None


@pytest.mark.unit
def test_device_frames_counts_valid_frames_acquired_in_the_window(tmp_path):
    log = tmp_path / "device.log"
    log.write_text("M info 5\nF 0 0 10 100 150\nF 1 1000 11 200 250\nX 2 2000 12 300 350\nN 4 360\n"
                   "F 3 3000 13 400 450\nF 4 4000 14 500")  # the last line is still being written
    assert bench_chain.device_frames(log, 200, 500) == 2  # frames 1 and 3; the corrupt one is no frame


@pytest.mark.skipif(shutil.which("make") is None or not (shutil.which("gcc") or shutil.which("clang")),
                    reason="gcc or clang, and make, are needed to build the virtual device")
def test_one_short_pair_runs_through_every_stage(tmp_path):
    exe = bench_chain.build_device(tmp_path)
    lines: list = []
    report = bench_chain.interleaved_pairs(exe, pairs=1, seconds=1.0, rate_hz=1000.0, relays=2, tmp=tmp_path,
                                           log=lines.append)
    pair, pooled, printed = report["pair0"], report["pooled"], "\n".join(lines)
    for kind in bench_chain.KINDS:
        assert pair[kind]["frames"] > 0 and pair[kind]["delivered"] > 0, f"{kind}: {printed}"
        assert pair[kind]["delivered"] <= pair[kind]["frames"] + 2, f"{kind}: {printed}"  # the edges: a frame
    assert pair["relay"]["stamp_agrees"] == 1.0, printed  # the pairing by value agrees with the relays' stamps
    assert pair["relay"]["unmatched_commands"] == 0 and pair["chain"]["unmatched_commands"] == 0, printed
    assert np.isfinite([pooled["ratio_p50"], pooled["ratio_p99"], pooled["ratio_delivered"]]).all()
    # the ratios' line, then a line on stalls if a loaded machine stalled an arm
    stalled = any(pooled["pairs_with_a_stall"].values())
    assert lines[-2 if stalled else -1].startswith("chain / relay: p50 "), printed
