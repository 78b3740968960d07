"""bench/probe_startup.py's checks on made-up listener records (no DDS, no processes)."""
import sys

import numpy as np
import pytest

from conftest import REPO

sys.path.insert(0, str(REPO / "bench"))
import probe_startup  # noqa: E402

MS = 1_000_000
T0 = 1_790_000_000 * 1_000_000_000


def record(before=500, n=6000, phantom_at=None, gain=1.0, status=None, tares=1, refused=0, missed=0):
    """A start: watchdog zeros (off the grid), ``before`` exact zeros, then the compensated force; the
    reference is a ramp from rest after 0.8 s; the listener missed the first ``missed`` wrenches."""
    stamps = T0 + np.arange(n, dtype=np.int64) * MS
    ref = np.clip((np.arange(n) - 800) / 1000.0, 0.0, None) * 2.0
    force = np.where(np.arange(n) < before, 0.0, gain * ref + 0.001 * np.sin(np.arange(n)))
    if phantom_at is not None:
        force[phantom_at] = 0.2
    watchdog = T0 - np.array([37_123, 20_037_123, 40_037_123])
    return {"wrench_stamp_ns": np.concatenate([watchdog, stamps[missed:]]).tolist(),
            "wrench_force": np.concatenate([np.zeros(3), force[missed:]]).tolist(),
            "ref_stamp_ns": stamps.tolist(), "ref_force": ref.tolist(), "after_s": 4.0,
            "diag": {"auto_tare": status or f"zeroed: bridge offset 0.050000 V from 501 samples at rest "
                                               f"({before / 1000:.2f} s after start)",
                     "auto_tares": str(tares), "auto_tare_refused": str(refused), "zero_before_tare": str(before)}}


@pytest.mark.unit
def test_a_clean_start_passes_every_check():
    r = probe_startup.judge(record(), timeout_s=10.0)
    assert r["ok"] and r["from_start"] and r["max_before_n"] == 0.0 and r["zeroed_after_s"] == 0.5
    assert r["samples_after"] == 4000 and r["r2"] > 0.999


@pytest.mark.unit
def test_each_check_fails_on_its_own_fault():
    phantom = probe_startup.judge(record(phantom_at=300), 10.0)
    assert not phantom["ok"] and not phantom["zero_before_force"] and phantom["max_before_n"] == 0.2
    late = probe_startup.judge(record(before=5000, n=12000), timeout_s=4.0)  # zeroed after 5 s, 4 s allowed
    assert not late["ok"] and not late["zeroed_in_time"] and late["zero_before_force"]
    refused = probe_startup.judge(record(tares=0, refused=1, status="not zeroed: the sensor did not rest"), 10.0)
    assert not refused["ok"] and not refused["zeroed_in_time"]
    poor = probe_startup.judge(record(gain=0.8), 10.0)
    assert not poor["ok"] and not poor["compensated"] and poor["r2"] < 0.99
    # a listener that missed the first wrenches: the boundary is late, and said so
    missed = probe_startup.judge(record(missed=40), 10.0)
    assert not missed["from_start"]
