"""The ROS-free compensation runtime: sample rules, stamp healing, finite output, immutable models."""
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from polyforce_ros.physics.chain import ModelError, OffsetElement, SensorChain
from polyforce_ros.physics.viscoelastic import PAPER_BURGERS, compensate
from polyforce_ros.runtime import Compensator, CompensatorConfig, SampleGate
from polyforce_ros.runtime.compensator import ACCEPT, ACCEPT_FRESH

MS = 1_000_000
T0 = 1_780_000_000 * 1_000_000_000
YEARS_3 = 3 * 365 * 86400 * 1_000_000_000
CHAIN = SensorChain.from_model(PAPER_BURGERS, offset_v=0.0)


def stream_1khz(n, t0=T0):
    """Stamps and receive times of a 1 kHz stream with 0.3 ms transport latency."""
    stamps = t0 + np.arange(n, dtype=np.int64) * MS
    return stamps, stamps + 300_000


def volts_of(stamps):
    t = (stamps - stamps[0]) * 1e-9
    return 1.5 * (t > 0.05) + 0.01 * np.sin(2 * np.pi * 5 * t)


@pytest.mark.parametrize("glitch_ns, counter", [(T0 + YEARS_3, "implausible_stamp"),
                                                ((2**31 - 1) * 1_000_000_000, "implausible_stamp"),
                                                (T0 - YEARS_3, "backwards")])
def test_one_glitched_stamp_is_dropped_and_never_blinds_the_stream(glitch_ns, counter):
    stamps, receive = stream_1khz(400)
    volts = volts_of(stamps)
    comp = Compensator(CHAIN, CompensatorConfig(auto_tare=False))
    forces = []
    for i in range(400):
        if i == 200:
            assert comp.step(glitch_ns, 0.3, int(receive[i]) + 100_000) is None
        forces.append(comp.step(int(stamps[i]), float(volts[i]), int(receive[i])))
    assert comp.counts[counter] == 1
    assert comp.counts["implausible_stamp"] + comp.counts["backwards"] == 1 and comp.counts["reanchored"] == 0
    # nothing lost, and the force is the undisturbed compensation
    np.testing.assert_allclose(forces, compensate(PAPER_BURGERS, (stamps - stamps[0]) * 1e-9, volts), atol=1e-9)


def test_a_glitch_accepted_first_heals_by_itself_within_reanchor_after_s():
    config = CompensatorConfig(reanchor_after_s=0.2, auto_tare=False)
    comp = Compensator(CHAIN, config)
    stamps, receive = stream_1khz(1000)
    volts = volts_of(stamps)
    assert comp.step(T0 + YEARS_3, 0.1, int(receive[0])) is not None  # nothing to compare the first one with
    out = [comp.step(int(s), float(v), int(r)) for s, v, r in zip(stamps[1:], volts[1:], receive[1:])]
    first_ok = next(i for i, f in enumerate(out) if f is not None)
    assert comp.counts["reanchored"] == 1
    assert (receive[1 + first_ok] - receive[1]) * 1e-9 <= 0.2 + 2e-3  # blind for at most reanchor_after_s
    assert all(f is not None for f in out[first_ok:])
    # after healing the history restarts at the re-anchoring sample
    k = 1 + first_ok
    expected = compensate(PAPER_BURGERS, (stamps[k:] - stamps[k]) * 1e-9, volts[k:])
    np.testing.assert_allclose(out[first_ok:], expected, atol=1e-9)


def test_a_clock_that_jumps_for_good_is_followed_after_reanchor_after_s():
    comp = Compensator(CHAIN)
    stamps, receive = stream_1khz(600)
    stamps = stamps.copy()
    stamps[300:] += YEARS_3  # e.g. a device clock reset to another epoch, or a replay that loops
    out = [comp.step(int(s), 0.2, int(r)) for s, r in zip(stamps, receive)]
    assert comp.counts["reanchored"] == 1
    blind = [i for i, f in enumerate(out) if f is None]
    assert blind and blind[0] == 300 and len(blind) <= 201


def test_a_late_burst_after_a_stall_is_used_and_does_not_blind_what_follows():
    """A buffer that delivers 2 s of samples at once after a stall: late, not implausible."""
    comp = Compensator(CHAIN)
    stamps, receive = stream_1khz(6000)
    receive = receive.copy()
    receive[1000:3000] = receive[3000]  # samples 1000..2999 arrive together, 2 s late at worst
    out = [comp.step(int(s), 0.2, int(r)) for s, r in zip(stamps, receive)]
    assert all(f is not None for f in out)
    assert comp.counts["implausible_stamp"] == 0 and comp.counts["reanchored"] == 0


def test_duplicates_never_reanchor():
    comp = Compensator(CHAIN)
    stamps, receive = stream_1khz(10)
    for s, r in zip(stamps, receive):
        comp.step(int(s), 0.1, int(r))
    frozen = int(stamps[-1])
    out = [comp.step(frozen, 0.1, int(receive[-1]) + i * MS) for i in range(1, 600)]  # a DAQ with a stuck clock
    assert all(f is None for f in out)
    assert comp.counts["reanchored"] == 0 and comp.counts["duplicate"] == 599


def test_stale_follows_the_receive_clock():
    comp = Compensator(CHAIN, CompensatorConfig(stale_timeout_s=0.1))
    assert comp.stale(T0)
    comp.step(T0, 0.1, T0)
    assert not comp.stale(T0 + 99 * MS) and comp.stale(T0 + 101 * MS)
    comp.step(T0 + 5 * MS, float("nan"), T0 + 150 * MS)  # bad samples do not feed the watchdog
    assert comp.stale(T0 + 151 * MS)


values = st.one_of(st.floats(allow_nan=True, allow_infinity=True, width=64),
                   st.floats(-20.0, 20.0), st.sampled_from([1e308, -1e308, 1e12, 5e-324, 0.0]))
steps = st.integers(-5 * MS, 5 * MS)


@settings(derandomize=True, max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(steps, values, st.booleans()), min_size=1, max_size=300))
def test_any_stream_gives_finite_bounded_forces_and_unique_increasing_stamps(items):
    comp = Compensator(CHAIN, CompensatorConfig(force_limit_n=12.0))
    stamp = T0
    last_out = None
    for step_ns, v, glitch in items:
        stamp += step_ns
        s = stamp + (YEARS_3 if glitch else 0)
        f = comp.step(s, v, T0 + abs(step_ns))
        if f is not None:
            assert math.isfinite(f) and abs(f) <= 12.0
            assert last_out is None or s > last_out or comp.counts["reanchored"]
            last_out = s


@settings(derandomize=True, max_examples=200, deadline=None)
@given(st.lists(st.tuples(steps, values, st.integers(0, 2 * MS), st.sampled_from([0, 0, 0, YEARS_3])),
                min_size=0, max_size=200),
       st.sampled_from([0.0, 1.0]))
def test_gate_mask_equals_the_per_sample_rule(items, tolerance_s):
    config = CompensatorConfig(stamp_tolerance_s=tolerance_s)
    stamps = T0 + np.cumsum([i[0] for i in items], dtype=np.int64) + np.array([i[3] for i in items], dtype=np.int64)
    volts = np.array([i[1] for i in items], dtype=float)
    receive = T0 + np.cumsum([i[2] for i in items], dtype=np.int64)
    gate = SampleGate(config)
    one_by_one = [gate.admit(int(s), float(v), int(r)) in (ACCEPT, ACCEPT_FRESH) for s, v, r in zip(stamps, volts, receive)]
    batch = SampleGate(config)
    np.testing.assert_array_equal(batch.mask(stamps, volts, receive), np.array(one_by_one, dtype=bool))
    assert batch.counts == gate.counts


def test_clean_arrays_take_the_vectorised_path_and_match():
    stamps, receive = stream_1khz(5000)
    volts = volts_of(stamps)
    stamps[2500:] += 100 * MS  # one real gap (arrival gap too)
    receive[2500:] += 100 * MS
    gate = SampleGate()
    assert gate.mask(stamps, volts, receive).all()
    assert gate.counts["gaps"] == 1 and gate.counts["samples"] == 5000


def test_run_is_step_by_step_exactly():
    rng = np.random.default_rng(3)
    stamps, receive = stream_1khz(3000)
    volts = volts_of(stamps) + rng.normal(0, 1e-3, stamps.size)
    volts[[10, 500, 1700]] = [np.nan, 1e12, -np.inf]
    stamps[900] = stamps[899]
    used, force = Compensator(CHAIN).run(stamps, volts, receive)
    comp = Compensator(CHAIN)
    one = [comp.step(int(s), float(v), int(r)) for s, v, r in zip(stamps, volts, receive)]
    assert used.tolist() == [f is not None for f in one]
    assert force[used].tolist() == [f for f in one if f is not None]  # bit for bit


class _NaNAfter:
    """A stream that breaks down (stands in for a numerically unusable model)."""

    def __init__(self, n):
        self.n, self.k = n, 0

    def reset(self):
        pass

    def step(self, t_s, v, aux=None):
        self.k += 1
        return float("nan") if self.k == self.n else v


def test_a_non_finite_force_is_counted_never_output_and_restarts_the_history():
    comp = Compensator(CHAIN)
    comp._stream = _NaNAfter(5)
    stamps, receive = stream_1khz(10)
    out = [comp.step(int(s), 0.1, int(r)) for s, r in zip(stamps, receive)]
    assert out[4] is None and all(f is not None for i, f in enumerate(out) if i != 4)
    assert comp.counts["nonfinite_output"] == 1


def test_tare_and_drift_never_write_into_the_model():
    chain = SensorChain.from_model(PAPER_BURGERS, offset_v=0.01)
    comp = Compensator(chain, CompensatorConfig(tare_window=10))
    stamps, receive = stream_1khz(20)
    for s, r in zip(stamps, receive):
        comp.step(int(s), 0.05, int(r))
    ok, message = comp.tare()
    assert ok and "0.050000 V" in message
    assert chain.offset_v == 0.01 and comp.offset_v == pytest.approx(0.05)
    assert comp.step(int(stamps[-1]) + MS, 0.05, int(receive[-1]) + MS) == pytest.approx(0.0, abs=1e-12)
    with pytest.raises(AttributeError):
        chain.offset.voltage_v = 1.0
    moved = chain.with_offset(0.2)
    assert moved.offset_v == 0.2 and chain.offset_v == 0.01 and moved.viscoelastic == chain.viscoelastic
    bare = SensorChain(chain.elements[:1])
    assert bare.offset_v == 0.0 and len(bare.elements) == 1  # reading the offset adds nothing
    assert isinstance(bare.with_offset(0.3).elements[-1], OffsetElement) and len(bare.elements) == 1


def _feed(comp, volts, t0=T0):
    stamps = t0 + np.arange(len(volts), dtype=np.int64) * MS
    return [comp.step(int(s), float(v), int(s)) for s, v in zip(stamps, volts)]


def test_auto_tare_zeroes_a_resting_sensor_at_start():
    rng = np.random.default_rng(0)
    comp = Compensator(CHAIN)  # model offset 0 V; the sensor's is 0.05 V
    out = _feed(comp, 0.05 + rng.normal(0, 1e-3, 1500))
    assert comp.counts["auto_tares"] == 1 and comp.tare_offset_v == pytest.approx(0.05, abs=3e-4)
    assert abs(np.mean(out[600:])) < 2e-3  # ~0 N after the window, where it read 0.24 N before
    assert comp.auto_tare_status.startswith("zeroed")


@pytest.mark.parametrize("volts, why", [
    (np.full(800, 0.93), "offset shift"),                     # a steady 3 N load at start
    (0.05 + np.linspace(0.0, 0.05, 800), "drift"),            # creeping: loaded polymer
    (0.05 + 0.02 * np.sin(np.arange(800) * 0.05), "spread"),  # moving
])
def test_auto_tare_refuses_a_loaded_or_moving_sensor(volts, why):
    comp = Compensator(CHAIN, CompensatorConfig(auto_tare_timeout_s=0.6))
    out = _feed(comp, volts)
    assert comp.counts["auto_tare_refused"] == 1 and comp.tare_offset_v is None
    assert comp.auto_tare_status.startswith("not zeroed") and why in comp.auto_tare_status
    assert comp.auto_tare_failed and comp.counts["auto_tare_retries"] >= 1
    decided = comp.counts["zero_before_tare"]
    assert decided > 600 and not any(out[:decided])  # zero until the decision, then the model's offset
    assert all(abs(f) > 0.1 for f in out[decided:] if why == "offset shift")
    comp.tare()
    assert not comp.auto_tare_failed


def test_auto_tare_rearms_after_reset_and_can_be_off():
    comp = Compensator(CHAIN)
    _feed(comp, np.full(600, 0.05))
    comp.reset()
    assert comp.auto_tare_status == "pending"
    _feed(comp, np.full(600, 0.04), t0=T0 + 10**9)
    assert comp.counts["auto_tares"] == 2 and comp.tare_offset_v == pytest.approx(0.04)
    off = Compensator(CHAIN, CompensatorConfig(auto_tare=False))
    _feed(off, np.full(600, 0.05))
    assert off.tare_offset_v is None and off.auto_tare_status == "off"


@pytest.mark.parametrize("how", ["configure", "assign"])
def test_every_way_of_setting_the_config_reaches_the_sample_rules(how):
    """``configure(...)`` and assigning ``comp.config`` are one setter: gate limits, tare window, auto-tare."""
    from dataclasses import replace
    comp = Compensator(CHAIN)
    changes = dict(input_limit_v=0.5, tare_window=7, auto_tare=False, force_limit_n=0.2)
    if how == "configure":
        comp.configure(**changes)
    else:
        comp.config = replace(comp.config, **changes)
    assert comp.gate.config is comp.config and comp.auto_tare_status == "off"
    stamps, receive = stream_1khz(20)
    volts = np.full(20, 0.3)
    volts[5] = 0.7                     # above the new input limit, below the default 10 V
    forces = [comp.step(int(s), float(v), int(r)) for s, v, r in zip(stamps, volts, receive)]
    assert forces[5] is None and comp.counts["out_of_range"] == 1
    assert max(abs(f) for f in forces if f is not None) == pytest.approx(0.2)   # the new clamp
    assert comp.counts["clamped"] > 0 and comp._recent_v.maxlen == 7
    assert comp.tare()[0] and comp.tare_offset_v == pytest.approx(0.3)


def test_simulated_source_hands_out_what_is_due_on_its_schedule():
    from polyforce_ros.runtime.sources import MAX_BURST, SimulatedSource
    from polyforce_ros.sim.sensor import BridgeSimulator

    profile = np.linspace(0.0, 5.0, 500)
    source = SimulatedSource(lambda: BridgeSimulator(noise_std_v=0.0, adc_bits=0, offset_v=0.0), profile, 1000.0,
                             lambda t: np.full(np.shape(t), 24.0), loop=False)
    assert source.due(T0) is None  # not started
    source.start(T0)
    first = source.due(T0 + 100 * MS)
    assert first.first == 0 and first.stamp_ns.size == 101 and first.stamp_ns[0] == T0
    np.testing.assert_array_equal(np.diff(first.stamp_ns), MS)
    burst = source.due(T0 + 10**10)  # a long stall is caught up gradually
    assert burst.first == 101 and burst.stamp_ns.size == MAX_BURST
    while source.due(T0 + 10**10) is not None:
        pass
    assert source.published == 500 and source.due(T0 + 10**10) is None and source.done
    np.testing.assert_allclose(first.force_n, profile[:101])
    source.restart()
    assert not source.started and source.published == 0 and not source.done


def test_serial_source_scales_valid_frames_and_gives_nothing_for_corrupt_ones():
    from polyforce_ros.runtime.sources import SerialSource
    from polyforce_ros.serial_protocol import encode_frame

    source = SerialSource(volts_per_count=1e-6, volts_offset=0.5)
    bad = bytearray(encode_frame(3, 3000, 7))
    bad[-1] ^= 0xFF
    got = source.feed(encode_frame(1, 1000, 2000), arrival_ns=T0)
    got += source.feed(encode_frame(2, 2000, -2000) + bytes(bad), arrival_ns=T0 + MS)
    assert [v for _, v in got] == pytest.approx([0.502, 0.498])
    assert got[1][0] - got[0][0] == MS and source.parser.crc_errors == 1


def test_offline_tools_list_exactly_the_counters_the_node_warns_on():
    """One list (WARN_COUNTERS) for the node's WARN and the offline tools' warning lines."""
    from polyforce_ros.runtime.compensator import COMPENSATOR_COUNTERS, WARN_COUNTERS
    from polyforce_ros.workflows import runtime_warnings

    for name in WARN_COUNTERS:
        [line] = runtime_warnings({name: 3})
        assert line.startswith("3 ")
    assert runtime_warnings({name: 5 for name in COMPENSATOR_COUNTERS if name not in WARN_COUNTERS}) == []
    assert {"gaps", "clamped", "backwards", "nonfinite_output"} <= set(WARN_COUNTERS)


def test_a_chain_and_its_elements_cannot_be_changed_in_place():
    from polyforce_ros.physics.chain import PlayHysteresisElement

    play = PlayHysteresisElement(1.0, [0.1, 0.3], [0.2, 0.1])
    chain = SensorChain([play, *SensorChain.from_model(PAPER_BURGERS, offset_v=0.1).elements])
    with pytest.raises(AttributeError):
        chain.elements = ()
    with pytest.raises(AttributeError):
        chain.elements.append(OffsetElement(0.0))   # a tuple
    with pytest.raises(ValueError):
        play.radii[0] = 5.0                          # read-only arrays
    from polyforce_ros.physics.preisach import PreisachModel

    preisach = PreisachModel(0.0, 10.0, np.ones((3, 3)))
    with pytest.raises(ValueError):
        preisach.density[0, 0] = 2.0
    with pytest.raises(AttributeError):
        preisach.u_max = 20.0
    assert chain.with_offset(0.2).offset_v == 0.2 and chain.offset_v == 0.1


def test_every_element_that_follows_temperature_makes_the_chain_need_it():
    """One rule (SensorChain.needs_temperature) for the node's WARN and the offline warning: lag included."""
    from polyforce_ros.physics.chain import ThermalDriftElement, ThermalLagElement

    core = SensorChain.from_model(PAPER_BURGERS, offset_v=0.0).elements
    assert not SensorChain(core).needs_temperature
    assert SensorChain([*core, ThermalDriftElement(coefficient_v_per_c=0.01, reference_c=24.0)]).needs_temperature
    assert SensorChain([*core, ThermalLagElement(coefficient_v_per_c=0.01, reference_c=24.0, tau_s=30.0)]).needs_temperature


def _rest_then_load(offset_v=0.05, n=3000, seed=3):
    """1 kHz: 0.8 s at rest on ``offset_v``, then a 2 N ramp-and-hold through the paper's Burgers sensor."""
    t = np.arange(n) * 1e-3
    force = np.clip((t - 0.8) * 4.0, 0.0, 2.0)
    volts = SensorChain.from_model(PAPER_BURGERS, offset_v=offset_v).forward(t, force)
    return t, force, volts + np.random.default_rng(seed).normal(0, 1e-3, n)


def test_a_record_is_compensated_by_the_runtime_zeroed_by_its_auto_tare_rule():
    from polyforce_ros.workflows import compensate_record

    t, force, volts = _rest_then_load()
    out = compensate_record(CHAIN, t, volts)
    zeroing = Compensator(CHAIN)
    _feed(zeroing, volts[:1200])
    assert out.offset_v == zeroing.tare_offset_v and out.offset_v == pytest.approx(0.05, abs=3e-4)
    assert out.zeroing == zeroing.auto_tare_status and out.zeroing.startswith("zeroed")
    stamps = np.round(t * 1e9).astype(np.int64)
    node = Compensator(CHAIN.with_offset(out.offset_v), CompensatorConfig(auto_tare=False))
    expected = [node.step(int(s), float(v), int(s)) for s, v in zip(stamps, volts)]
    assert out.used.all() and out.compensated_n.tolist() == expected  # the node's rule, bit for bit
    assert np.abs(out.compensated_n - force).max() < 0.05
    assert out.static_n == pytest.approx((volts - out.offset_v) / CHAIN.static_gain_v_per_n())


def test_a_record_that_starts_loaded_keeps_the_model_offset_and_a_spike_is_dropped():
    from polyforce_ros.workflows import compensate_record

    t, force, volts = _rest_then_load(offset_v=0.0)
    loaded = compensate_record(CHAIN, t, volts + 0.5)  # ~2.4 N from the first sample: no rest to zero on
    assert loaded.offset_v == CHAIN.offset_v == 0.0 and loaded.used.all()
    assert loaded.zeroing.startswith("not zeroed") and "offset shift" in loaded.zeroing
    volts[1700] = 1e12
    out = compensate_record(CHAIN, t, volts)
    assert not out.used[1700] and out.used.sum() == t.size - 1
    assert np.isnan(out.compensated_n[1700]) and np.isnan(out.static_n[1700])
    assert np.isfinite(out.compensated_n[out.used]).all() and np.abs(out.compensated_n[out.used] - force[out.used]).max() < 0.05


def test_a_record_zeroes_on_its_first_rest_however_late_its_samples_start_and_follows_temperature():
    from polyforce_ros.physics.chain import ThermalDriftElement, ViscoelasticElement
    from polyforce_ros.workflows import compensate_record

    t, force, volts = _rest_then_load()
    t = np.concatenate([t[:3], t[3:] + 2.0])  # three samples, then 2 s missing, then the rest (still at rest)
    out = compensate_record(CHAIN, t, volts)
    assert out.zeroing.startswith("zeroed") and out.offset_v == pytest.approx(0.05, abs=3e-4)
    thermal = SensorChain([ViscoelasticElement(PAPER_BURGERS), ThermalDriftElement(coefficient_v_per_c=0.01, reference_c=20.0),
                           OffsetElement(0.0)])
    hot = compensate_record(thermal, t, volts + 0.03, temperature_c=np.full(t.size, 23.0))  # 0.03 V not force
    cold = compensate_record(thermal, t, volts + 0.03, temperature_c=np.full(t.size, 20.0))
    # zeroed alike (the auto-tare averages raw volts), then the thermal element takes 0.03 V off the hot record:
    # a step of -0.03 V from the first sample, whose force relaxes as the model's G(t)
    assert hot.offset_v == cold.offset_v == pytest.approx(0.08, abs=3e-4)
    g0 = PAPER_BURGERS.relaxation().g0_n_per_v
    assert hot.compensated_n[0] - cold.compensated_n[0] == pytest.approx(-0.03 * g0, rel=1e-6)
    assert np.all(hot.compensated_n < cold.compensated_n)


def test_the_last_finite_temperature_is_used_and_a_log_is_taken_in_order_of_arrival():
    from polyforce_ros.physics.chain import ThermalDriftElement, ViscoelasticElement

    chain = SensorChain([ViscoelasticElement(PAPER_BURGERS), ThermalDriftElement(coefficient_v_per_c=0.01, reference_c=20.0),
                         OffsetElement(0.0)])
    comp = Compensator(chain, CompensatorConfig(auto_tare=False))
    assert comp.temperature_c is None
    assert comp.temperature(30.0) and not comp.temperature(float("nan")) and not comp.temperature(float("inf"))
    assert comp.temperature_c == 30.0  # ignored readings leave the last finite one
    assert comp.step(T0, 0.1) == pytest.approx(0.0, abs=1e-9)  # 10 degC over reference: 0.1 V that is not force
    stamps = T0 + np.arange(1, 200, dtype=np.int64) * MS
    log_ns = np.array([T0 + 50 * MS, T0 + 50 * MS, T0 + 70 * MS, T0 + 120 * MS, T0 + 10 * MS])  # unsorted; two at 50 ms
    log_c = np.array([25.0, 28.0, np.nan, 20.0, 35.0])
    by_hand = Compensator(chain, CompensatorConfig(auto_tare=False))
    by_hand.temperature(30.0)
    by_hand.step(T0, 0.1)
    expected = []
    for s in stamps:
        for when, c in sorted(zip(log_ns, log_c), key=lambda x: x[0]):
            if s - MS < when <= s:
                by_hand.temperature(c)
        expected.append(by_hand.step(int(s), 0.1))
    used, force = comp.run(stamps, np.full(stamps.size, 0.1), temperature_log=(log_ns, log_c))
    assert used.all() and force.tolist() == expected
    assert comp.temperature_c == 20.0 and abs(force[-1] - 0.0) > 1e-3  # at reference: 0.1 V is force again


def test_zero_before_force_no_phantom_load_while_the_auto_tare_decides():
    rng = np.random.default_rng(3)
    comp = Compensator(CHAIN)  # model offset 0 V; the sensor rests at 0.05 V, which reads as ~0.24 N untared
    out = np.array(_feed(comp, 0.05 + rng.normal(0, 1e-3, 1500)))
    decided = comp.counts["zero_before_tare"]
    # one window of auto_tare_s at 1 kHz: the 501 samples from 0 to 0.5 s, the last of which decides
    assert decided == 501 and comp.counts["auto_tares"] == 1
    assert np.all(out[:decided] == 0.0)
    assert np.abs(out[decided:]).max() < 0.03  # noise only after it
    quiet = Compensator(CHAIN, CompensatorConfig(publish_zero_before_tare=False))
    out = _feed(quiet, 0.05 + rng.normal(0, 1e-3, 1500))
    assert all(f is None for f in out[:501]) and all(f is not None for f in out[501:])


@pytest.mark.parametrize("moving_s", [0.3, 1.7, 4.2])
def test_a_late_compensator_zeroes_at_the_first_rest_after_a_moving_start(moving_s):
    # the node joined while the profile was already running: a ramp up and down, then the sensor rests
    n_move = int(moving_s * 1000)
    ramp = 0.05 + 0.3 * np.sin(np.linspace(0, np.pi, n_move))
    rest = 0.05 + np.random.default_rng(1).normal(0, 1e-3, 1500)
    comp = Compensator(CHAIN)
    out = np.array(_feed(comp, np.concatenate([ramp, rest])))
    assert comp.counts["auto_tares"] == 1 and comp.counts["auto_tare_retries"] >= 1 and not comp.auto_tare_failed
    assert comp.tare_offset_v == pytest.approx(0.05, abs=5e-4)
    decided = comp.counts["zero_before_tare"]
    assert decided <= n_move + 1000  # a rest of 1.5 windows is always found
    assert np.all(out[:decided] == 0.0) and np.abs(out[decided:]).max() < 0.03


def test_a_sensor_restart_clears_the_history_rezeroes_and_drops_older_samples():
    t = np.arange(3000) * 1e-3
    force = np.clip((t - 0.8) * 4.0, 0.0, 2.0)  # loaded to 2 N: the history holds creep
    volts = SensorChain.from_model(PAPER_BURGERS, offset_v=0.05).forward(t, force)
    comp = Compensator(CHAIN)
    _feed(comp, volts)
    restart_ns = T0 + 4 * 10**9
    comp.reset(from_stamp_ns=restart_ns)
    assert comp.auto_tare_pending and comp.step(restart_ns - MS, 0.05, restart_ns) is None  # the old sensor's sample
    assert comp.counts["backwards"] == 1
    rest = 0.051 + np.random.default_rng(2).normal(0, 1e-3, 1500)  # relaxed sensor, its zero moved by 1 mV
    out = np.array(_feed(comp, rest, t0=restart_ns))
    assert comp.counts["auto_tares"] == 2 and comp.tare_offset_v == pytest.approx(0.051, abs=3e-4)
    assert np.abs(out).max() < 0.03  # no pull on the master in the unloaded second after the restart


def test_drift_tracking_re_zeroes_a_bridge_hysteresis_model_in_one_window():
    """A stop-type term at the bridge adds its linear part to the instantaneous compliance at rest: the drift
    correction divides by the small-signal stiffness G0 / (1 + G0 linear), so one window takes the whole error."""
    from polyforce_ros.physics.chain import BridgeHysteresisElement, ViscoelasticElement
    from polyforce_ros.physics.viscoelastic import PAPER_BURGERS

    w = np.array([0.02, 0.03, 0.04])
    chain = SensorChain([BridgeHysteresisElement(ViscoelasticElement(PAPER_BURGERS), [0.2, 0.5, 1.0], -w,
                                                 linear_v_per_n=float(w.sum())), OffsetElement(0.1)])
    comp = Compensator(chain, CompensatorConfig(auto_tare=False, drift_tracking=True, drift_band_n=0.5,
                                                drift_window_s=1.0))
    t = np.arange(0.0, 3.0, 1e-3)
    volts = chain.forward(t, np.zeros(t.size)) + 0.02  # unloaded, with the bridge zero 20 mV off
    _, out = comp.run(np.round(t * 1e9).astype(np.int64), volts)
    assert comp.counts["drift_corrections"] >= 1
    assert abs(out[(t > 1.2) & (t < 2.0)].mean()) < 0.01  # N: the first correction took the whole offset error


def _time_drifts():
    from polyforce_ros.physics.chain import (ExponentialDriftElement, OffsetDriftElement, PolynomialDriftElement,
                                             SplineDriftElement, StepDriftElement)

    return [OffsetDriftElement(rate_v_per_s=2e-3), ExponentialDriftElement(amplitude_v=0.05, tau_s=0.5),
            PolynomialDriftElement(rate_v_per_s=1e-3, curvature_v_per_s2=2e-3, cubic_v_per_s3=1e-3),
            SplineDriftElement([0.5, 1.0, 1.5], [0.02, -0.03, 0.04]), StepDriftElement([0.7, 1.2], [0.04, -0.02])]


@pytest.mark.parametrize("drift", _time_drifts(), ids=lambda e: e.kind)
def test_time_drifts_are_left_out_unless_asked_and_replay_after_every_reset_when_asked(drift):
    """A time drift describes its record: by default the runtime compensates as without it and names it; asked
    to apply it, the runtime subtracts it again from each reset on (what the default avoids)."""
    with_drift = SensorChain([*CHAIN.elements, drift])
    stamps, receive = stream_1khz(2000)
    volts = np.zeros(stamps.size)  # an unloaded sensor whose zero does not move
    config = CompensatorConfig(auto_tare=False)
    plain, left_out = Compensator(CHAIN, config), Compensator(with_drift, config)
    assert left_out.time_drifts_left_out == (drift.kind,) and drift.kind in left_out.time_drifts_note
    assert plain.time_drifts_left_out == () and plain.time_drifts_note == ""
    np.testing.assert_array_equal(left_out.run(stamps, volts, receive)[1], plain.run(stamps, volts, receive)[1])
    applied = Compensator(with_drift, CompensatorConfig(auto_tare=False, apply_time_drifts=True))
    assert applied.time_drifts_left_out == ()
    first = applied.run(stamps[:1000], volts[:1000], receive[:1000])[1]
    assert np.abs(first).max() > 1e-3  # N: the drift is subtracted from a zero that never moved
    applied.reset()
    again = applied.run(stamps[1000:], volts[1000:], receive[1000:])[1]
    np.testing.assert_allclose(again, first, atol=1e-9)  # the same phantom force, from the reset on


def test_the_noise_gain_guard_judges_the_chain_the_runtime_runs():
    """A drift moves a nonlinear gain's working point: the guard (and the gain the node reports) must be the chain
    in use, without the drift by default and with it when asked."""
    from polyforce_ros.physics.chain import PolynomialGainElement, StepDriftElement, ViscoelasticElement
    from polyforce_ros.physics.noise_gain import backward_noise_gain

    plain = SensorChain([ViscoelasticElement(PAPER_BURGERS),
                         PolynomialGainElement(quadratic_per_v=0.3, cubic_per_v2=0.0, quartic_per_v3=0.0),
                         OffsetElement(0.0)])
    drifted = SensorChain([*plain.elements, StepDriftElement([0.001], [-0.8])])
    without, with_drift = (backward_noise_gain(c, 1000.0).gain_n_per_v for c in (plain, drifted))
    assert abs(without - with_drift) > 0.5  # N/V: the drift matters to the probe
    assert Compensator(drifted).noise_gain.gain_n_per_v == pytest.approx(without, rel=1e-9)
    applied = Compensator(drifted, CompensatorConfig(apply_time_drifts=True))
    assert applied.noise_gain.gain_n_per_v == pytest.approx(with_drift, rel=1e-9)
    # the limit between the two: refused only as the runtime would run it
    limit = 0.5 * (without + with_drift)
    refuses = with_drift > limit
    for apply in (False, True):
        config = CompensatorConfig(apply_time_drifts=apply, max_noise_gain=limit)
        if refuses == apply:
            with pytest.raises(ModelError, match="max_noise_gain"):
                Compensator(drifted, config)
        else:
            Compensator(drifted, config)


def test_a_refused_chain_leaves_the_one_in_use_whole():
    """A model of time drifts alone has nothing to compensate with: refused, and the compensator keeps its chain,
    its stream, its offset and what its output is."""
    from polyforce_ros.physics.chain import PolynomialDriftElement, StepDriftElement

    comp = Compensator(SensorChain.from_model(PAPER_BURGERS, offset_v=0.1), CompensatorConfig(auto_tare=False))
    stamps, receive = stream_1khz(400)
    volts = 0.1 + volts_of(stamps)
    before = comp.run(stamps[:200], volts[:200], receive[:200])[1]
    chain, gain = comp.chain, comp.noise_gain
    drifts_only = SensorChain([PolynomialDriftElement(rate_v_per_s=1e-3, curvature_v_per_s2=0.0, cubic_v_per_s3=0.0),
                               StepDriftElement([1.0], [0.01])])
    with pytest.raises(ModelError, match="only time drifts"):
        comp.set_chain(drifts_only)
    assert comp.chain is chain and comp.noise_gain is gain and comp.offset_v == pytest.approx(0.1)
    after = comp.run(stamps[200:], volts[200:], receive[200:])[1]
    reference = Compensator(SensorChain.from_model(PAPER_BURGERS, offset_v=0.1), CompensatorConfig(auto_tare=False))
    np.testing.assert_allclose(np.concatenate([before, after]), reference.run(stamps, volts, receive)[1], atol=1e-12)
    # asked to apply them, the same model is a chain like any other (drifts only: force = what the bridge says)
    Compensator(drifts_only, CompensatorConfig(apply_time_drifts=True))


def test_changing_the_drift_or_guard_settings_rebuilds_the_chain_in_use_or_refuses_and_keeps_them():
    from polyforce_ros.physics.chain import StepDriftElement

    comp = Compensator(SensorChain([*CHAIN.elements, StepDriftElement([0.1], [0.05])]))
    assert comp.time_drifts_left_out == ("step_drift",)
    comp.configure(apply_time_drifts=True)
    assert comp.time_drifts_left_out == () and comp.config.apply_time_drifts
    with pytest.raises(ModelError, match="max_noise_gain"):
        comp.configure(max_noise_gain=1.0)  # the paper sensor passes noise at 4.8 N/V
    assert comp.config.max_noise_gain == CompensatorConfig.max_noise_gain and comp.config.apply_time_drifts
    comp.configure(apply_time_drifts=False, tare_window=10)
    assert comp.time_drifts_left_out == ("step_drift",) and comp.config.tare_window == 10
