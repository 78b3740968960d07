"""polyforce_ros.bags.cdr: CDR bytes that every ROS tool reads, with every byte owned.

Each encoded message must decode to the same values with three independent
decoders (rosbags' strict decoder, mcap_ros2's dynamic decoder, rclpy), and be
byte-for-byte what rosbags' ``serialize_cdr`` gives (zero padding, no
trailing bytes). Bags written by ``BagWriter.write_series`` are byte-identical
whatever the process memory held, and rosbags' reader strictly decodes them.
"""
import functools
import hashlib
import math
import os
import struct
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from rosbags.typesys import Stores, get_typestore

from polyforce_ros import bags, contract
from polyforce_ros.bags import cdr
from polyforce_ros.bags.cdr import STAMP_MAX_NS, STAMP_MIN_NS
from polyforce_ros.contract import FLOAT64, JOINT_STATE, TEMPERATURE_MSG, WRENCH_STAMPED

REPO = Path(__file__).resolve().parents[1]
TYPES = (JOINT_STATE, WRENCH_STAMPED, TEMPERATURE_MSG, FLOAT64)
TS = get_typestore(Stores.ROS2_JAZZY)
_FUZZ = bool(os.environ.get("POLYFORCE_FUZZ"))  # see conftest: derandomised unless exploring by hand
PROPERTY = settings(derandomize=not _FUZZ, database=None, max_examples=200 * (20 if _FUZZ else 1), deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])


# ----------------------------------------------------------------------------- decoders
@functools.cache
def _mcap_ros2_decoder(type_name):
    from mcap_ros2._dynamic import generate_dynamic

    return generate_dynamic(type_name, bags.schema_text(type_name))[type_name]


def _rclpy_class(type_name):
    import importlib

    pkg, _, name = type_name.split("/")
    return getattr(importlib.import_module(f"{pkg}.msg"), name)


def decode_rosbags(data, type_name):
    return TS.deserialize_cdr(data, type_name)  # strict: the message must end exactly at its last field


def decode_mcap_ros2(data, type_name):
    return _mcap_ros2_decoder(type_name)(data)


def decode_rclpy(data, type_name):
    from rclpy.serialization import deserialize_message

    return deserialize_message(data, _rclpy_class(type_name))


DECODERS = {"rosbags": decode_rosbags, "mcap_ros2": decode_mcap_ros2, "rclpy": decode_rclpy}


def _bits(values):
    """Floats as their IEEE bit patterns, so NaN payloads and -0.0 count."""
    return [struct.pack("<d", float(v)).hex() for v in values]


def content(type_name, msg):
    """A decoded message (any decoder's object) as comparable plain values."""
    out = {}
    if type_name != FLOAT64:
        out["stamp"] = (int(msg.header.stamp.sec), int(msg.header.stamp.nanosec))
        out["frame_id"] = str(msg.header.frame_id)
    if type_name == JOINT_STATE:
        out["name"] = [str(s) for s in msg.name]
        for f in ("position", "velocity", "effort"):
            out[f] = _bits(getattr(msg, f))
    elif type_name == WRENCH_STAMPED:
        w = msg.wrench
        out["wrench"] = _bits([w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y, w.torque.z])
    elif type_name == TEMPERATURE_MSG:
        out["values"] = _bits([msg.temperature, msg.variance])
    else:
        out["data"] = _bits([msg.data])
    return out


def expected_content(type_name, fields):
    """What ``content`` must give for a message encoded from ``fields``."""
    out = {}
    if type_name != FLOAT64:
        out["stamp"] = divmod(fields["stamp_ns"], 1_000_000_000)
        out["frame_id"] = fields["frame_id"]
    if type_name == JOINT_STATE:
        out["name"] = list(fields["name"])
        for f in ("position", "velocity", "effort"):
            out[f] = _bits(fields[f])
    elif type_name == WRENCH_STAMPED:
        out["wrench"] = _bits(list(fields["force"]) + list(fields["torque"]))
    elif type_name == TEMPERATURE_MSG:
        out["values"] = _bits([fields["temperature"], fields["variance"]])
    else:
        out["data"] = _bits([fields["data"]])
    return out


def rosbags_message(type_name, fields):
    """The same message built independently as a rosbags object (its serializer zero-fills padding)."""
    T = TS.types
    if type_name == FLOAT64:
        return T[FLOAT64](data=fields["data"])
    sec, nanosec = divmod(fields["stamp_ns"], 1_000_000_000)
    header = T["std_msgs/msg/Header"](stamp=T["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec),
                                      frame_id=fields["frame_id"])
    if type_name == JOINT_STATE:
        return T[JOINT_STATE](header=header, name=list(fields["name"]),
                              **{f: np.array(fields[f], dtype=np.float64) for f in ("position", "velocity", "effort")})
    if type_name == WRENCH_STAMPED:
        vec = T["geometry_msgs/msg/Vector3"]
        return T[WRENCH_STAMPED](header=header, wrench=T["geometry_msgs/msg/Wrench"](
            force=vec(*fields["force"]), torque=vec(*fields["torque"])))
    return T[TEMPERATURE_MSG](header=header, temperature=fields["temperature"], variance=fields["variance"])


def check_message(type_name, fields, data):
    """``data`` (our bytes for ``fields``) equals rosbags' serialization and decodes right everywhere."""
    assert data[:4] == b"\x00\x01\x00\x00"
    reference = bytes(TS.serialize_cdr(rosbags_message(type_name, fields), type_name))
    assert len(data) == len(reference)
    assert data == reference
    want = expected_content(type_name, fields)
    for name, decode in DECODERS.items():
        assert content(type_name, decode(data, type_name)) == want, name


# ----------------------------------------------------------------------------- strategies
#: Strings of every length (padding after them is 0..3 bytes), multi-byte UTF-8 included; no NUL.
names = st.one_of(
    st.sampled_from(["", "a", "ab", "abc", "abcd", "é", "日本", "\U0001f600", "polyforce_sensor"]),
    st.text(st.characters(exclude_characters="\x00", exclude_categories=("Cs",)), max_size=11),
)
stamps = st.one_of(st.sampled_from([0, STAMP_MAX_NS, STAMP_MIN_NS, 1, -1, 999_999_999, 1_000_000_000]),
                   st.integers(STAMP_MIN_NS, STAMP_MAX_NS))
#: Finite and non-finite floats, NaN payloads (quiet, signalling, negative) and signed zeros included.
_ODD_NANS = [struct.unpack("<d", bytes.fromhex(h))[0] for h in ("010000000000f07f", "0000000000f8ffff", "efbeadde0000f87f")]
floats = st.one_of(st.floats(allow_nan=True, allow_infinity=True),
                   st.sampled_from([0.0, -0.0, math.inf, -math.inf, math.nan, 5e-324, *_ODD_NANS]))
float_seqs = st.lists(floats, max_size=4)

MESSAGES = {
    JOINT_STATE: st.fixed_dictionaries({"stamp_ns": stamps, "frame_id": names, "name": st.lists(names, max_size=4),
                                        "position": float_seqs, "velocity": float_seqs, "effort": float_seqs}),
    WRENCH_STAMPED: st.fixed_dictionaries({"stamp_ns": stamps, "frame_id": names, "force": st.tuples(floats, floats, floats),
                                           "torque": st.tuples(floats, floats, floats)}),
    TEMPERATURE_MSG: st.fixed_dictionaries({"stamp_ns": stamps, "frame_id": names, "temperature": floats,
                                            "variance": floats}),
    FLOAT64: st.fixed_dictionaries({"data": floats}),
}


# ----------------------------------------------------------------------------- properties
@pytest.mark.parametrize("type_name", TYPES)
def test_message_round_trip_through_every_decoder(type_name):
    @PROPERTY
    @given(MESSAGES[type_name])
    def prop(fields):
        check_message(type_name, fields, cdr.encode(type_name, **fields))

    prop()


@PROPERTY
@given(type_name=st.sampled_from(TYPES), frame_id=names, joint_name=names,
       samples=st.lists(st.tuples(stamps, floats), min_size=1, max_size=6))
@example(type_name=JOINT_STATE, frame_id="", joint_name="", samples=[(0, 0.0), (STAMP_MAX_NS, math.nan)])
@example(type_name=TEMPERATURE_MSG, frame_id="abc", joint_name="", samples=[(STAMP_MIN_NS, -math.inf)])
def test_series_records_are_the_single_messages(type_name, frame_id, joint_name, samples):
    stamp_ns = np.array([s for s, _ in samples], dtype=np.int64)
    values = np.array([v for _, v in samples], dtype=np.float64)
    layout = cdr.series_layout(type_name, frame_id, joint_name)
    block = layout.encode(stamp_ns, values)
    assert block.dtype == np.uint8 and block.shape == (len(samples), layout.size)
    for row, (stamp, value) in zip(block, samples):
        fields = _scalar_fields(type_name, stamp, value, frame_id, joint_name)
        data = row.tobytes()
        assert data == cdr.encode(type_name, **fields)
        check_message(type_name, fields, data)


def _scalar_fields(type_name, stamp, value, frame_id, joint_name):
    if type_name == FLOAT64:
        return {"data": value}
    base = {"stamp_ns": stamp, "frame_id": frame_id}
    if type_name == JOINT_STATE:
        return {**base, "name": [joint_name], "position": [value], "velocity": [], "effort": []}
    if type_name == WRENCH_STAMPED:
        return {**base, "force": (0.0, 0.0, value), "torque": (0.0, 0.0, 0.0)}
    return {**base, "temperature": value, "variance": 0.0}


def test_out_of_range_stamps_and_nul_strings_are_refused(tmp_path):
    with pytest.raises(ValueError):
        cdr.encode(JOINT_STATE, stamp_ns=STAMP_MAX_NS + 1)
    with pytest.raises(ValueError):
        cdr.series_layout(TEMPERATURE_MSG, "polyforce_sensor").encode([STAMP_MIN_NS - 1], [1.0])
    with pytest.raises(ValueError):
        cdr.encode(JOINT_STATE, frame_id="a\x00b")
    with pytest.raises(ValueError):
        cdr.encode("std_msgs/msg/String")
    with bags.BagWriter(tmp_path / "b.mcap") as w:
        with pytest.raises(ValueError):  # silently wrapped seconds before
            w.write_series(bags.BRIDGE_VOLTAGE, JOINT_STATE, [0, STAMP_MAX_NS + 1], [1.0, 2.0])
        with pytest.raises(ValueError):
            w.write_series(bags.BRIDGE_VOLTAGE, JOINT_STATE, [1, 2], [1.0])
        with pytest.raises(bags.BagError):
            w.write_series(bags.BRIDGE_VOLTAGE, JOINT_STATE, [1], [1.0], joint_name="a\x00")
    assert len(bags.read_bag(tmp_path / "b.mcap").topics.get(bags.BRIDGE_VOLTAGE, [])) == 0


# ----------------------------------------------------------------------------- bags
SCALAR_TOPIC = contract.BRIDGE_VOLTAGE_SCALAR  # the Float64 topic
T0 = 1_700_000_000_123_456_789


def write_all_types(path, n=3000):
    """A bag with every contract type, unusual names, edge stamps and non-finite values."""
    rng = np.random.default_rng(7)
    stamps = T0 + np.arange(n, dtype=np.int64) * 1_000_003
    stamps[:2] = [0, STAMP_MAX_NS]
    log = T0 + np.arange(n, dtype=np.int64) * 1_000_000
    values = rng.normal(size=n)
    values[2:6] = [math.nan, math.inf, -math.inf, -0.0]
    with bags.BagWriter(path, chunk_size=1 << 14) as w:
        w.write_series(bags.BRIDGE_VOLTAGE, JOINT_STATE, stamps, values, frame_id="bridge", joint_name="ax\u00e9",
                       log_time_ns=log)
        w.write_series(bags.REFERENCE_FORCE, WRENCH_STAMPED, stamps, -values, frame_id="", log_time_ns=log)
        w.write_series(bags.WRENCH, WRENCH_STAMPED, stamps[::3], values[::3] * 2, frame_id="odd", log_time_ns=log[::3])
        w.write_series(bags.TEMPERATURE, TEMPERATURE_MSG, stamps[::10], 24.0 + values[::10], frame_id="thermo1",
                       log_time_ns=log[::10])
        w.write_series(SCALAR_TOPIC, FLOAT64, stamps, values * 3, log_time_ns=log)


_CHILD = textwrap.dedent("""
    import gc, os, sys
    import numpy as np
    if sys.argv[2] == "dirty":  # leave the heap full of freed random bytes
        junk = [os.urandom(n) for n in range(64, 4096, 7)] + [np.random.default_rng().bytes(1 << 20) for _ in range(32)]
        arrays = [np.random.default_rng().normal(size=(1000, 92)) for _ in range(50)]
        del junk, arrays
        gc.collect()
    sys.path.insert(0, {test_dir!r})
    from test_cdr import write_all_types
    write_all_types(sys.argv[1])
""")


def test_bags_are_byte_identical_whatever_the_memory_held(tmp_path):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH", "")])),
               PYTHONHASHSEED="random")
    code = _CHILD.format(test_dir=str(Path(__file__).parent))
    digests = []
    for state in ("clean", "dirty"):
        path = tmp_path / state / "bag.mcap"  # one file name: the rosbag2 metadata record names the file
        path.parent.mkdir()
        proc = subprocess.run([sys.executable, "-c", code, str(path), state], env=env, capture_output=True, text=True,
                              timeout=120)
        assert proc.returncode == 0, proc.stderr
        digests.append(hashlib.sha256(path.read_bytes()).hexdigest())
    (tmp_path / "here").mkdir()
    write_all_types(tmp_path / "here" / "bag.mcap")
    digests.append(hashlib.sha256((tmp_path / "here" / "bag.mcap").read_bytes()).hexdigest())
    assert len(set(digests)) == 1, digests


def test_rosbags_reader_strictly_decodes_every_message(tmp_path):
    from rosbags.rosbag2 import Reader

    path = tmp_path / "all.mcap"
    write_all_types(path)
    ours = bags.read_bag(path, optional=[SCALAR_TOPIC], expected_types={SCALAR_TOPIC: FLOAT64})
    assert ours.warnings == []
    got = {}
    with Reader(path) as reader:
        for conn, log_time, data in reader.messages():
            msg = TS.deserialize_cdr(data, conn.msgtype)  # raises on any size mismatch
            assert bytes(TS.serialize_cdr(msg, conn.msgtype)) == bytes(data)
            got.setdefault(conn.topic, []).append((log_time, conn.msgtype, msg))
    assert set(got) == set(ours.topics) == {bags.BRIDGE_VOLTAGE, bags.REFERENCE_FORCE, bags.WRENCH, bags.TEMPERATURE,
                                            SCALAR_TOPIC}
    for topic, rows in got.items():
        rows.sort(key=lambda r: r[0])
        data = ours[topic]
        type_name = rows[0][1]
        assert type_name == data.type_name
        np.testing.assert_array_equal([r[0] for r in rows], data.log_time_ns)
        scalar = bags.SCALAR_FIELD[type_name]
        if type_name == FLOAT64:
            values = [r[2].data for r in rows]
        else:
            np.testing.assert_array_equal([r[2].header.stamp.sec * 1_000_000_000 + r[2].header.stamp.nanosec
                                           for r in rows], data.stamp_ns)
            values = {JOINT_STATE: lambda m: m.position[0], WRENCH_STAMPED: lambda m: m.wrench.force.z,
                      TEMPERATURE_MSG: lambda m: m.temperature}[type_name]
            values = [values(r[2]) for r in rows]
        assert _bits(values) == _bits(data.fields[scalar]), topic
    joint = got[bags.BRIDGE_VOLTAGE][0][2]
    assert joint.name == ["ax\u00e9"] and joint.header.frame_id == "bridge"
    assert joint.velocity.size == 0 and joint.effort.size == 0
