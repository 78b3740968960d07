"""One Record: from a bag and from live samples alike, cleaned by the runtime's rules."""
import numpy as np
import pytest

from conftest import REPO
from polyforce_ros import bags
from polyforce_ros.record import Record, load_record, record_from_samples


def test_a_bag_and_its_samples_give_the_same_record():
    path = REPO / "bags" / "step_5n.mcap"
    bag = bags.read_bag(path)
    raw, ref = bag[bags.BRIDGE_VOLTAGE], bag[bags.REFERENCE_FORCE]
    from_bag = load_record(path)
    live = record_from_samples(raw.stamp_ns, raw.fields["position"], ref.stamp_ns, ref.fields["force_z"],
                               raw_receive_ns=raw.log_time_ns)
    for name in ("t_s", "force_n", "voltage_v", "stamp_ns"):
        np.testing.assert_array_equal(getattr(from_bag, name), getattr(live, name))
    assert from_bag.t_s[0] == 0.0 and np.all(np.diff(from_bag.stamp_ns) > 0)


def test_bad_raw_samples_are_dropped_with_a_warning_and_temperature_follows():
    stamps = 1_700_000_000_000_000_000 + np.arange(100, dtype=np.int64) * 10_000_000
    volts = np.linspace(0.0, 1.0, 100)
    volts[[5, 6]] = [np.nan, 1e12]
    rec = record_from_samples(stamps, volts, stamps, volts * 3.0, stamps[::10], np.arange(10.0))
    assert rec.t_s.size == 98 and rec.warnings and "2 raw samples dropped" in rec.warnings[0]
    np.testing.assert_allclose(rec.force_n, rec.voltage_v * 3.0)
    inside = rec.t_s <= 0.9  # 1 degC per 0.1 s, interpolated; held after the last temperature sample
    np.testing.assert_allclose(rec.temperature_c[inside], rec.t_s[inside] / 0.1)
    assert np.all(rec.temperature_c[~inside] == 9.0)
    assert rec.aux() == {"temperature_c": rec.temperature_c}


def test_a_topic_without_usable_samples_is_a_clear_error():
    stamps = np.arange(10, dtype=np.int64) * 1_000_000
    with pytest.raises(bags.BagError, match="reference_force"):
        record_from_samples(stamps, np.zeros(10), stamps[:1], np.zeros(1))
    with pytest.raises(bags.BagError, match="bridge_voltage"):
        record_from_samples(stamps, np.full(10, np.nan))
    assert Record(np.zeros(1), None, np.zeros(1)).temperature_c is None  # positional form of synthetic records
