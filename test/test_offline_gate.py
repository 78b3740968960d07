"""Offline equals live on stamps: ``polyforce compensate`` (workflows.compensate_bag) of a bag with corrupted
stamps and values writes exactly the wrenches a Compensator stepping the same samples in order gives (the
compensation node's rule: same drops, same stamps, same forces bit for bit). Their stamps strictly increase
within each stamp history: they step back only where the gate re-anchored on a consistent run of samples it
had rejected (the runtime's healing rule), never more often than it counts re-anchors.

The bags are bags/step_5n.mcap's first 2.4 s with mutated header stamps (year jumps forward and back, repeats,
swapped and reversed blocks, a clock stepping back or ahead, the largest and the smallest stamp) and values
(NaN, infinities, huge); the log times stay the recorder's arrival times.
"""
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from conftest import REPO
from polyforce_ros import bags, contract
from polyforce_ros.model_file import default_model_path, load_model
from polyforce_ros.runtime import Compensator, CompensatorConfig
from polyforce_ros.workflows import compensate_bag

SOURCE = REPO / "bags" / "step_5n.mcap"
N = 1200  # 2.4 s at 500 Hz: room for blocks longer than reanchor_after_s (0.2 s)
YEAR_NS = 365 * 86400 * 1_000_000_000
MAX_STAMP_NS = (2**31 - 1) * 1_000_000_000 + 999_999_999  # builtin_interfaces/Time's largest
MODEL = load_model(default_model_path())
PROPERTY = settings(deadline=None, max_examples=100, suppress_health_check=[HealthCheck.too_slow])


@pytest.fixture(scope="module")
def source():
    bag = bags.read_bag(SOURCE, topics=[bags.BRIDGE_VOLTAGE], optional=[contract.TEMPERATURE])
    raw, temp = bag[bags.BRIDGE_VOLTAGE], bag[contract.TEMPERATURE]
    end = raw.log_time_ns[N - 1]
    keep = temp.log_time_ns <= end
    return (raw.stamp_ns[:N].copy(), raw.fields["position"][:N].copy(), raw.log_time_ns[:N].copy(),
            temp.stamp_ns[keep], temp.fields["temperature"][keep], temp.log_time_ns[keep])


_index = st.integers(1, N - 2)
_length = st.integers(1, 500)
MUTATION = st.one_of(
    st.tuples(st.just("year"), _index, _length, st.sampled_from([1, -1])),
    st.tuples(st.just("repeat"), _index, _length),
    st.tuples(st.just("swap"), _index),
    st.tuples(st.just("reverse"), _index, _length),
    st.tuples(st.just("extreme"), _index, _length, st.sampled_from([MAX_STAMP_NS, 0])),
    st.tuples(st.just("clock_step"), _index, st.integers(-3_000_000_000, 3_000_000_000)),
    st.tuples(st.just("value"), _index, st.sampled_from([math.nan, math.inf, -math.inf, 1e308, -1e12, 11.0])),
)


def mutate(stamps, volts, mutations):
    stamps, volts = stamps.copy(), volts.copy()
    for kind, i, *args in mutations:
        block = slice(i, i + args[0]) if kind in ("year", "repeat", "reverse", "extreme") else None
        if kind == "year":
            stamps[block] += args[1] * YEAR_NS
        elif kind == "repeat":
            stamps[block] = stamps[i - 1]
        elif kind == "swap":
            stamps[[i, i + 1]] = stamps[[i + 1, i]]
        elif kind == "reverse":
            stamps[block] = stamps[block][::-1].copy()
        elif kind == "extreme":
            stamps[block] = args[1]
        elif kind == "clock_step":
            stamps[i:] += args[0]
        else:
            volts[i] = args[0]
    return np.clip(stamps, 0, MAX_STAMP_NS), volts


def stepped(stamps, volts, log_ns, temp_log_ns, temp_c, config):
    """What the compensation node publishes for these samples, received in this order at ``log_ns``
    ((stamp, force) pairs), and its count of re-anchors."""
    comp = Compensator(MODEL.chain, config)
    out, k = [], 0
    for s, v, r in zip(stamps.tolist(), volts.tolist(), log_ns.tolist()):
        while k < len(temp_log_ns) and temp_log_ns[k] <= r:
            comp.temperature(float(temp_c[k]))
            k += 1
        f = comp.step(int(s), float(v), int(r))
        if f is not None:
            out.append((int(s), f))
    return out, comp.counts["reanchored"]


@PROPERTY
@example(mutations=[("year", 1, 101, 1)], auto_tare=False)  # a year ahead for 0.2 s: healed onto, then back
@example(mutations=[("clock_step", 600, -3_000_000_000)], auto_tare=True)  # the clock steps back 3 s
@example(mutations=[("repeat", 300, 50), ("swap", 700), ("value", 800, math.nan)], auto_tare=True)
@example(mutations=[("swap", 249)], auto_tare=True)  # a stamp stepping back just after the zeroing decided
@given(mutations=st.lists(MUTATION, min_size=1, max_size=4), auto_tare=st.booleans())
def test_compensate_follows_the_live_gate_on_mutated_bags(source, tmp_path_factory, mutations, auto_tare):
    stamps0, volts0, log_ns, t_stamp, t_c, t_log = source
    stamps, volts = mutate(stamps0, volts0, mutations)
    folder = tmp_path_factory.mktemp("gate")
    src, out = folder / "in.mcap", folder / "out.mcap"
    with bags.BagWriter(src) as w:
        w.write_series(bags.BRIDGE_VOLTAGE, bags.JOINT_STATE, stamps, volts, log_time_ns=log_ns)
        w.write_series(contract.TEMPERATURE, bags.TEMPERATURE_MSG, t_stamp, t_c, log_time_ns=t_log)
    config = CompensatorConfig(auto_tare=auto_tare)
    expected, reanchored = stepped(stamps, volts, log_ns, t_log, t_c, config)
    if not expected:
        with pytest.raises(bags.BagError, match="no usable samples"):
            compensate_bag(src, out, MODEL, config)
        return
    written, _warnings = compensate_bag(src, out, MODEL, config)
    wrench = bags.read_bag(out)[bags.WRENCH]
    got = list(zip(wrench.stamp_ns.tolist(), wrench.fields["force_z"].tolist()))
    assert written == len(expected) == len(got)
    assert got == expected  # same drops, same stamps, same forces, bit for bit
    steps_back = int(np.sum(np.diff(wrench.stamp_ns) <= 0))
    assert steps_back <= reanchored, f"wrench stamps repeat or go back {steps_back} times, {reanchored} re-anchors"


def test_a_tare_or_a_new_model_restarts_the_history_but_not_the_stamps():
    comp = Compensator(MODEL.chain, CompensatorConfig(auto_tare=False))
    ms = 1_000_000
    assert comp.step(10 * ms, 0.1) is not None and comp.step(11 * ms, 0.1) is not None
    comp.tare()
    assert comp.step(11 * ms, 0.1) is None and comp.step(10 * ms, 0.1) is None  # a repeat and a step back
    assert (comp.counts["duplicate"], comp.counts["backwards"]) == (1, 1)
    assert comp.step(12 * ms, 0.1) == pytest.approx(0.0, abs=1e-12)  # zeroed, a fresh history from 12 ms on
    comp.set_chain(MODEL.chain)
    assert comp.step(12 * ms, 0.1) is None and comp.step(13 * ms, 0.1) is not None
    # a sensor restart (reset) does forget the stamps: the restarted sensor's first sample starts them again
    comp.reset()
    assert comp.step(5 * ms, 0.1) is not None
