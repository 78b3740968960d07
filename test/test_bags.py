"""MCAP bags: rosbag2 conventions, bulk reading, and what happens to broken files."""
import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_ros2.reader import read_ros2_messages

from polyforce_ros import bags
from polyforce_ros.bags import (
    BRIDGE_VOLTAGE, JOINT_STATE, REFERENCE_FORCE, TEMPERATURE, TEMPERATURE_MSG, WRENCH_STAMPED,
    BagError, BagWriter, make_message, read_bag,
)

T0 = 1_700_000_000_123_456_789


def write_sample(path, n=5000, chunk_size=1 << 14):
    stamps = T0 + np.arange(n, dtype=np.int64) * 1_000_000
    rng = np.random.default_rng(0)
    volts, force = rng.normal(size=n), rng.normal(size=n)
    with BagWriter(path, chunk_size=chunk_size) as w:
        w.write_series(BRIDGE_VOLTAGE, JOINT_STATE, stamps, volts)
        w.write_series(REFERENCE_FORCE, WRENCH_STAMPED, stamps, force)
        w.write_series(TEMPERATURE, TEMPERATURE_MSG, stamps[::100], np.full(n // 100, 24.5))
    return stamps, volts, force


def test_round_trip_is_exact(tmp_path):
    path = tmp_path / "b.mcap"
    stamps, volts, force = write_sample(path)
    bag = read_bag(path)
    assert bag.warnings == []
    np.testing.assert_array_equal(bag[BRIDGE_VOLTAGE].stamp_ns, stamps)
    np.testing.assert_array_equal(bag[BRIDGE_VOLTAGE].fields["position"], volts)
    np.testing.assert_array_equal(bag[REFERENCE_FORCE].fields["force_z"], force)
    np.testing.assert_array_equal(bag[TEMPERATURE].fields["temperature"], 24.5)


def test_rosbag2_conventions_and_interop(tmp_path):
    path = tmp_path / "b.mcap"
    stamps, volts, _ = write_sample(path)
    with open(path, "rb") as fh:
        reader = make_reader(fh)
        header, summary = reader.get_header(), reader.get_summary()
    assert header.profile == "ros2"
    assert {s.name for s in summary.schemas.values()} == {JOINT_STATE, WRENCH_STAMPED, TEMPERATURE_MSG}
    assert {s.encoding for s in summary.schemas.values()} == {"ros2msg"}
    assert {c.message_encoding for c in summary.channels.values()} == {"cdr"}
    assert summary.statistics.message_count == 2 * 5000 + 50
    assert summary.chunk_indexes and all(ci.message_index_offsets for ci in summary.chunk_indexes)
    schema = next(s for s in summary.schemas.values() if s.name == JOINT_STATE).data.decode()
    assert "=" * 80 + "\nMSG: std_msgs/Header" in schema and "MSG: builtin_interfaces/Time" in schema
    # The reference reader decodes what we wrote.
    first = next(iter(read_ros2_messages(str(path), topics=[BRIDGE_VOLTAGE])))
    assert list(first.ros_msg.position) == [volts[0]] and first.ros_msg.name == ["sarrus_axial"]
    assert first.ros_msg.header.stamp.sec * 10**9 + first.ros_msg.header.stamp.nanosec == stamps[0]


def test_messages_of_different_layouts_on_one_topic(tmp_path):
    path = tmp_path / "mixed.mcap"
    frames = ["a", "frame_b", "", "a_much_longer_frame_name"] * 25
    with BagWriter(path) as w:
        for i, frame in enumerate(frames):
            msg = make_message(JOINT_STATE, T0 + i * 1000, float(i), frame_id=frame)
            if i % 7 == 0:
                msg.velocity = [1.0, 2.0]
            w.write(BRIDGE_VOLTAGE, JOINT_STATE, msg, T0 + i * 1000)
    data = read_bag(path)[BRIDGE_VOLTAGE]
    np.testing.assert_array_equal(data.fields["position"], np.arange(100.0))
    np.testing.assert_array_equal(data.stamp_ns, T0 + np.arange(100) * 1000)


def test_truncated_bag_reads_what_came_before_the_cut(tmp_path):
    path = tmp_path / "b.mcap"
    stamps, volts, _ = write_sample(path)
    raw = path.read_bytes()
    for cut in (len(raw) // 5, len(raw) // 2, len(raw) - 100):
        cut_path = tmp_path / f"cut{cut}.mcap"
        cut_path.write_bytes(raw[:cut])
        bag = read_bag(cut_path, topics=[BRIDGE_VOLTAGE])
        got = bag[BRIDGE_VOLTAGE]
        assert len(got) > 0
        np.testing.assert_array_equal(got.fields["position"], volts[: len(got)])  # a clean prefix
        if cut < len(raw) - 1000:
            assert any("truncated" in w for w in bag.warnings), bag.warnings
    with pytest.raises(BagError, match="not an MCAP"):
        (tmp_path / "tiny.mcap").write_bytes(raw[:5])
        read_bag(tmp_path / "tiny.mcap")


def test_corrupt_chunk_is_skipped_with_a_warning(tmp_path):
    path = tmp_path / "b.mcap"
    write_sample(path)
    raw = bytearray(path.read_bytes())
    with open(path, "rb") as fh:
        chunks = make_reader(fh).get_summary().chunk_indexes
    target = chunks[len(chunks) // 2]
    mid = target.chunk_start_offset + target.chunk_length // 2
    raw[mid : mid + 64] = bytes(64)
    bad = tmp_path / "bad.mcap"
    bad.write_bytes(bytes(raw))
    bag = read_bag(bad, topics=[BRIDGE_VOLTAGE])
    assert any("corrupt chunk" in w for w in bag.warnings)
    assert 0 < len(bag[BRIDGE_VOLTAGE]) < 5000


def test_missing_topic_and_wrong_type_are_clear_errors(tmp_path):
    path = tmp_path / "b.mcap"
    with BagWriter(path) as w:
        w.write_series(REFERENCE_FORCE, WRENCH_STAMPED, [T0], [1.0])
        w.write_series(BRIDGE_VOLTAGE, WRENCH_STAMPED, [T0], [1.0])  # wrong type on the topic
    with pytest.raises(BagError, match="topic /polyforce/temperature not in bag"):
        read_bag(path, topics=[TEMPERATURE])
    with pytest.raises(BagError, match="has type geometry_msgs/msg/WrenchStamped, expected sensor_msgs/msg/JointState"):
        read_bag(path, topics=[BRIDGE_VOLTAGE])
    with pytest.raises(BagError, match="cannot read bag"):
        read_bag(tmp_path / "absent.mcap")


def test_empty_bag(tmp_path):
    path = tmp_path / "empty.mcap"
    with BagWriter(path):
        pass
    assert read_bag(path).topics == {}
    with pytest.raises(BagError, match="no topics"):
        read_bag(path, topics=[BRIDGE_VOLTAGE])


from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    frames=st.lists(st.tuples(st.booleans(), st.sampled_from(["", "a", "ab", "frame_b"])), min_size=1, max_size=300),
    chunk_size=st.sampled_from([64, 700, 1 << 14]),
)
def test_bulk_reader_agrees_with_the_reference_reader_on_any_interleaving(tmp_path, frames, chunk_size):
    """Runs of equal records are read in bulk, everything else record by record; the
    boundaries between the two (topic switches, size changes, chunk ends) must not matter."""
    path = tmp_path / f"mix_{chunk_size}_{len(frames)}.mcap"
    with BagWriter(path, chunk_size=chunk_size) as w:
        for i, (is_force, frame) in enumerate(frames):
            topic, kind = (REFERENCE_FORCE, WRENCH_STAMPED) if is_force else (BRIDGE_VOLTAGE, JOINT_STATE)
            w.write(topic, kind, make_message(kind, T0 + i * 1000, float(i), frame_id=frame), T0 + i * 1000)
    bag = read_bag(path, topics=[], optional=[BRIDGE_VOLTAGE, REFERENCE_FORCE])
    reference = {BRIDGE_VOLTAGE: [], REFERENCE_FORCE: []}
    for m in read_ros2_messages(str(path)):
        value = m.ros_msg.position[0] if m.channel.topic == BRIDGE_VOLTAGE else m.ros_msg.wrench.force.z
        reference[m.channel.topic].append((m.log_time_ns, value))
    for topic, field_name in ((BRIDGE_VOLTAGE, "position"), (REFERENCE_FORCE, "force_z")):
        expected = sorted(reference[topic])
        if not expected:
            assert topic not in bag.topics
            continue
        np.testing.assert_array_equal(bag[topic].log_time_ns, [t for t, _ in expected])
        np.testing.assert_array_equal(bag[topic].fields[field_name], [v for _, v in expected])


def test_compensate_uses_the_latest_recorded_temperature_like_the_node(tmp_path):
    """A thermal model offline: each sample uses the last temperature logged before it (none before the first)."""
    from polyforce_ros.model_file import SensorModel
    from polyforce_ros.physics.chain import OffsetElement, SensorChain, ThermalDriftElement, ViscoelasticElement
    from polyforce_ros.physics.viscoelastic import PAPER_BURGERS
    from polyforce_ros.runtime import Compensator, CompensatorConfig
    from polyforce_ros.workflows import compensate_bag

    rng = np.random.default_rng(5)
    chain = SensorChain([ViscoelasticElement(PAPER_BURGERS),
                         ThermalDriftElement(coefficient_v_per_c=0.01, reference_c=24.0), OffsetElement(0.0)])
    n = 4000
    stamps = 1_780_000_000 * 10**9 + np.arange(n, dtype=np.int64) * 10**6
    t = (stamps - stamps[0]) * 1e-9
    temp_stamps = stamps[500::50] - 300_000          # temperature from 0.5 s on, at 20 Hz
    temp_c = 24.0 + 3.0 * np.sin(t[500::50]) + rng.normal(0, 0.01, temp_stamps.size)
    temp_c[7] = np.nan                               # a non-finite reading is ignored, as by the node
    volts = 0.1 + 0.02 * np.sin(3 * t)
    src, out = tmp_path / "in.mcap", tmp_path / "out.mcap"
    with bags.BagWriter(src) as w:
        w.write_series(BRIDGE_VOLTAGE, JOINT_STATE, stamps, volts)
        w.write_series(TEMPERATURE, TEMPERATURE_MSG, temp_stamps, temp_c)
    config = CompensatorConfig(auto_tare=False)
    written, warnings = compensate_bag(src, out, SensorModel(chain, {}), config)
    got = read_bag(out)[bags.WRENCH].fields["force_z"]
    # the node's rule by hand: step each sample with the last finite temperature received before it
    expected, latest, k = [], None, 0
    node_like = Compensator(chain, config)
    for s, v in zip(stamps, volts):
        while k < temp_stamps.size and temp_stamps[k] <= s:
            latest = temp_c[k] if np.isfinite(temp_c[k]) else latest
            k += 1
        expected.append(node_like.step(int(s), float(v), int(s), {"temperature_c": latest}))
    assert written == n and not warnings
    np.testing.assert_array_equal(got, expected)
    no_temp = compensate_bag(_without_temperature(src, tmp_path), tmp_path / "o2.mcap", SensorModel(chain, {}), config)[1]
    assert any("temperature" in w for w in no_temp)


def _without_temperature(src, tmp_path):
    bag = read_bag(src)
    path = tmp_path / "no_temp.mcap"
    with bags.BagWriter(path) as w:
        raw = bag[BRIDGE_VOLTAGE]
        w.write_series(BRIDGE_VOLTAGE, JOINT_STATE, raw.stamp_ns, raw.fields["position"])
    return path
