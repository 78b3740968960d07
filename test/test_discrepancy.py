"""Discrepancy workflow on records with hidden effects (the workflow is never told which).

Every case draws the family of each hidden effect at random (from all of its
families, the held-out ones included) and its magnitude from the upper part of
the generator's range, with seeds of a range used by no tuning run
(3000..3999); the sensor's base parameters are random too (+-30 %). The
workflow must name exactly the hidden effects (and nothing on clean data or
out-of-catalogue effects), bring the out-of-sample error near the noise
floor it estimates from the data, and write every named effect to JSON, the
report and the saved model.
"""
import json
import math
import re
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st_
from scipy import signal as scipy_signal

from conftest import REPO
from polyforce_ros.discrepancy.effects import EFFECTS, NAMES
from polyforce_ros.discrepancy.engine import Fitter, Signals, Structure, Term, _polish, _without, diagnose, fold_of
from polyforce_ros.model_file import load_model
from polyforce_ros.physics.viscoelastic import MODEL_TYPES, simulate_deformation
from polyforce_ros.sim.bench import EXTRA_EFFECTS, OUT_OF_CATALOGUE, bench_record, default_base, write_bench_bag
from polyforce_ros.sim.truths import FAMILIES

DURATION_S, RATE_HZ = 420.0, 100.0


def _family(effect, seed):
    return str(np.random.default_rng(seed).choice(list(FAMILIES[effect])))


def _magnitude(seed):
    return float(np.random.default_rng(seed + 1).uniform(0.5, 1.0))


#: Known gaps (docs/discrepancy.md's held-out matrix shows them): family drawn -> why the case fails today.
KNOWN_GAPS: dict = {}


def _single_cases():
    for i, effect in enumerate(NAMES):
        seed = 3000 + 11 * i
        family = _family(effect, seed)
        marks = [pytest.mark.xfail(reason=KNOWN_GAPS[family], strict=False)] if family in KNOWN_GAPS else []
        yield pytest.param(effect, seed, marks=marks, id=f"{effect}[{family}]")


@pytest.mark.parametrize("effect, seed", list(_single_cases()))
def test_hidden_effect_of_a_random_family_is_named_and_the_error_reaches_the_noise_floor(effect, seed):
    family = _family(effect, seed)
    rec, case = bench_record(effect, _magnitude(seed), default_base([effect]), DURATION_S, RATE_HZ, seed, split="held_out",
                             families={effect: family})
    d = diagnose(rec, base=case.base)
    info = (family, [c.summary() for c in d.candidates if c.step == 1])
    assert d.missing_effects == [effect], info
    assert d.missing_effect == effect
    assert 0.5 <= d.confidences[effect] <= 1.0
    # most of the error above the noise floor is gone (a ratio of RMSEs would ask a small effect to beat the floor)
    floor2 = d.noise_floor_v ** 2
    assert d.rmse_after ** 2 - floor2 <= 0.2 * (d.rmse_before ** 2 - floor2), info
    assert d.rmse_after <= 2.0 * d.noise_floor_v, (d.rmse_after, d.noise_floor_v, info)
    # the noise floor is estimated from the data: the truth is 2 mV bridge noise + 5 mN reference noise
    assert 1.5e-3 < d.noise_floor_v < 3.5e-3


@pytest.mark.parametrize("base, seed", [("burgers", 3101), ("zener", 3102), ("elastic", 3103), ("maxwell", 3104),
                                        ("kelvin", 3105), ("zener2", 3106), ("burgers2", 3107), ("zener3", 3108),
                                        ("burgers3", 3109)])
def test_clean_data_is_none_and_nothing_is_unexplained(base, seed):
    """Every core type of the fitting stack is a base the diagnosis can run against (BASES = MODEL_TYPES)."""
    rec, case = bench_record("none", 0.0, base, DURATION_S, RATE_HZ, seed)
    d = diagnose(rec, base=base)
    assert d.missing_effects == [] and d.missing_effect == "none", [c.summary() for c in d.candidates]
    assert not d.unexplained["present"]
    assert d.rmse_after == d.rmse_before <= 1.3 * d.noise_floor_v
    assert 0.0 <= d.unexplained["explained_share"] <= 1.0  # a share, not a ratio over ~0 (was ~1e300)
    # the floor is the truth's: 2 mV of bridge noise, and 5 mN of reference noise through the core's instantaneous
    # compliance (through the static gain it was 9 % high here for a burgers, 17 % for a kelvin)
    core = next(e.model for e in case.truth.elements if hasattr(e, "model"))
    j0_v_per_n = float(simulate_deformation(core, np.array([0.0, 1e-3]), np.array([0.0, 1.0]))[1])
    assert d.noise_floor_v == pytest.approx(math.hypot(0.002, 0.005 * j0_v_per_n), rel=0.08)


@pytest.mark.parametrize("pair, seed", [
    pytest.param(("hysteresis", "thermal_drift"), 3201, id="hysteresis+thermal_drift"),
    pytest.param(("sensor_lag", "nonlinear_gain"), 3202, id="sensor_lag+nonlinear_gain"),
    pytest.param(("viscous_flow", "offset_drift"), 3203, id="viscous_flow+offset_drift"),
    pytest.param(("hysteresis", "offset_drift"), 3204, id="hysteresis+offset_drift")])
def test_two_hidden_effects_are_both_named(pair, seed):
    rec, case = bench_record(list(pair), 0.8, default_base(pair), DURATION_S, RATE_HZ, seed, split="held_out")
    d = diagnose(rec, base=case.base)
    assert sorted(d.missing_effects) == sorted(pair), (case.families, [c.summary() for c in d.candidates])
    assert d.missing_effect == d.missing_effects[0]
    assert d.rmse_after <= 2.0 * d.noise_floor_v


def test_a_missing_dashpot_beside_a_drift_is_named_flow_not_a_slow_delayed_elasticity():
    """A zener sensor that flows, with a settling offset drift (a tune-split case of the matrix): greedy selection
    had named a delayed elasticity whose retardation time the polish took to 1e4 s (flow in disguise, on a 600 s
    record), which then beat the real flow plus the drift in every block."""
    rec, case = bench_record(["viscous_flow", "offset_drift"], 1.0, "zener", 600.0, 200.0, 4559, split="tune",
                             families={"viscous_flow": "eta_two_decades", "offset_drift": "exp_approach"},
                             jitter=0.3, drops=4, temperature=False)
    d = diagnose(rec, base=case.base)
    assert sorted(d.missing_effects) == ["offset_drift", "viscous_flow"], [c.summary() for c in d.candidates]
    longest = max((tau for c in d.candidates for tau in c.fit.structure.taus), default=0.0)
    assert longest <= rec.t_s[-1] - rec.t_s[0]  # no retardation time beyond the record


@given(st_.sampled_from(["t_s", "force_n", "voltage_v", "temperature_c"]), st_.integers(0, 5999),
       st_.sampled_from([np.nan, np.inf, -np.inf, "short", "2-D"]))
@settings(max_examples=60, deadline=None)
def test_a_record_with_a_bad_signal_is_refused_with_a_message_before_any_fit(name, at, bad):
    """Any signal (the temperature too) holding a non-finite sample, of another length or not 1-D: a ValueError that
    names it, raised before the diagnosis builds the signals it fits."""
    import dataclasses
    from unittest import mock

    from polyforce_ros.discrepancy import engine
    from polyforce_ros.record import Record

    t = np.arange(6000) * 0.01
    good = {"t_s": t, "force_n": np.sin(t), "voltage_v": 0.1 * np.sin(t), "temperature_c": 23.0 + 0.01 * t}
    rec = Record(**good)
    value = good[name].copy()
    if bad == "short":
        value = value[:-1]
    elif bad == "2-D":
        value = value.reshape(-1, 2)
    else:
        value[at] = bad
    reached = AssertionError("a bad record reached the fit")
    with mock.patch.object(engine, "_signals", side_effect=reached), \
            pytest.raises(ValueError, match=f"(non-finite|shapes).*{name}"):
        diagnose(dataclasses.replace(rec, **{name: value}), base="burgers")


def test_folds_are_interleaved_blocks_of_equal_length():
    t = np.linspace(0.0, 600.0, 60001)
    fold = fold_of(t, 0.0, 600.0, n_folds=5, blocks_per_fold=3)
    runs = np.flatnonzero(np.diff(fold)) + 1
    assert runs.size == 14 and np.allclose(np.diff(t[np.r_[0, runs, t.size - 1]]), 40.0, atol=0.02)
    assert [int(fold[i]) for i in np.r_[0, runs]] == [j % 5 for j in range(15)]  # block j in fold j mod 5
    assert np.allclose(np.bincount(fold), np.bincount(fold_of(t, 0.0, 600.0, 5, blocks_per_fold=1)), atol=2)
    assert np.array_equal(np.unique(fold_of(t, 0.0, 600.0, 5, blocks_per_fold=1)[:12000]), [0])  # one block: contiguous
    # the fitter's row slices of each fold cover every row once, each row in its own fold
    sig = Signals(t, np.zeros_like(t), np.zeros_like(t), None, t0=0.0, duration_s=600.0, temp_ref=0.0)
    fitter = Fitter(sig, 5, blocks_per_fold=3)
    covered = np.concatenate([np.arange(t.size)[r] for runs in fitter.rows for r in runs])
    assert np.array_equal(np.sort(covered), np.arange(t.size))
    for k, runs in enumerate(fitter.rows):
        assert len(runs) == 3 and all(np.all(fold[r] == k) for r in runs)


def test_the_polish_moves_a_delayed_elasticitys_time_with_the_core_time_it_names():
    """A burgers with a second Kelvin element (true times 8 s and 60 s) fitted from grid times 20 s and 150 s: the
    delayed elasticity's time is one of the core's, and after the polish the term names the polished core time (it
    had stayed at its grid value, and dropping the effect removes the core time nearest to it)."""
    t = np.arange(0.0, 600.0, 0.1)
    f = 5.0 + 4.0 * np.sign(np.sin(2 * np.pi * t / 97.0)) + 2.0 * np.sin(2 * np.pi * t / 23.0)
    core = MODEL_TYPES["burgers2"](30.0, 60.0, 5e4, 60.0 * 8.0, 40.0, 40.0 * 60.0)
    v = simulate_deformation(core, t, f)
    sig = Signals(t, f, v, None, t0=0.0, duration_s=600.0, temp_ref=0.0)
    fitter = Fitter(sig, 5)
    st = Structure("burgers2", (20.0, 150.0), (Term("delayed_elasticity", "", 150.0),))
    polished = _polish(fitter, st)
    assert polished.term("delayed_elasticity").param in polished.taus
    assert sorted(polished.taus) == pytest.approx([8.0, 60.0], rel=0.05)
    assert _without(polished, "delayed_elasticity").taus == (polished.taus[0],)


def test_a_drift_with_sharp_steps_is_named_offset_drift():
    """Humidity-like drift events (tune family, 1 kHz with jitter and gaps, barely detectable): with one contiguous
    block per fold, a step inside a left-out block could not be predicted from the others and the answer was
    'unexplained'; with interleaved blocks the spline drift predicts it from both sides."""
    rec, case = bench_record(["offset_drift"], 0.0, "burgers", 600.0, 1000.0, 1093, split="tune",
                             families={"offset_drift": "events"}, jitter=0.3, drops=4)
    d = diagnose(rec, base="burgers")
    assert d.missing_effects == ["offset_drift"], [c.summary() for c in d.candidates]
    assert d.rmse_after <= 1.2 * d.noise_floor_v
    assert "3 interleaved blocks" in d.to_json()["validation"]


def test_drift_events_shorter_than_a_coarse_spline_interval_are_named_offset_drift_alone():
    """Drift events of 3-15 % of the record (tune case, 200 Hz, jitter, gaps, no temperature). A spline of at most 8
    intervals could not follow them; what it left rang, and a slow delayed elasticity was named for it. A finer
    spline variant follows them, and the cross-validation chose it."""
    rec, case = bench_record(["offset_drift"], 0.5, "burgers", 600.0, 200.0, 7760, split="tune",
                             families={"offset_drift": "events"}, jitter=0.3, drops=4, temperature=False)
    d = diagnose(rec, base="burgers")
    assert d.missing_effects == ["offset_drift"], [c.summary() for c in d.candidates]
    assert d.variants["offset_drift"] in ("spline12", "spline16"), d.variants
    assert d.rmse_after <= 1.2 * d.noise_floor_v, (d.rmse_after, d.noise_floor_v)


def test_a_flow_with_a_settling_drift_under_a_slow_load_is_named_with_the_drift_not_a_slow_delayed_elasticity():
    """A zener that flows, with a settling drift (tune case, 200 Hz), under a slow load that seldom rests: the flow
    and the drift are nearly collinear, and a slow delayed elasticity or a fine spline in time follows either's
    creep. The flow is named first (its fluidity following the load-time integral passed takes the part of the
    drift its rests do not tell apart), the settling drift beside it; no delayed elasticity is named, and the record
    is explained to its floor. (Whether an effect beside a drift must make a difference the record shows is the
    acceptance rule tested in test_discrepancy_newtons: a flow and a drift judged by the acceptance test alone.)"""
    rec, case = bench_record(["viscous_flow", "offset_drift"], 0.5, "zener", 600.0, 200.0, 9022, split="tune",
                             families={"viscous_flow": "eta_two_decades", "offset_drift": "exp_approach"})
    d = diagnose(rec, base=case.base)
    assert sorted(d.missing_effects) == ["offset_drift", "viscous_flow"], [c.summary() for c in d.candidates]
    assert not any(c.effect == "delayed_elasticity" and c.accepted for c in d.candidates)
    assert d.rmse_after <= 1.2 * d.noise_floor_v, (d.rmse_after, d.noise_floor_v)


def test_a_large_voltage_path_hysteresis_is_named_alone_and_settling_keeps_its_fit():
    """A large play hysteresis on the voltage path (tune case, 200 Hz, jitter, gaps, no temperature). Its small plays
    take part of the core's gain, so the refitted core's output is smaller than the base's; play radii that kept
    the base's span drifted against it at each settling round, the refit was 40 % worse than the fit that named
    the hysteresis, and a drift was named for the loss."""
    rec, case = bench_record(["hysteresis"], 1.0, "burgers", 600.0, 200.0, 2232, split="tune",
                             families={"hysteresis": "play_voltage"}, jitter=0.3, drops=4, temperature=False)
    d = diagnose(rec, base="burgers")
    assert d.missing_effects == ["hysteresis"], [c.summary() for c in d.candidates]
    assert d.rmse_after <= 1.1 * d.noise_floor_v  # was 1.29 x: the settled model, not the one named, is saved


def test_a_large_stop_hysteresis_at_1khz_is_validated_at_the_floor_with_nothing_unexplained():
    """Stop hysteresis on the voltage path, 1 kHz with jitter and gaps (tune case). Driven by the raw reference force
    at the record's rate, the plays of small radius followed its noise (which the fit-rate block means do not
    carry): the validation RMSE was 2.5x the floor and the residual was reported unexplained."""
    rec, case = bench_record(["hysteresis"], 1.0, "burgers", 600.0, 1000.0, 3298, split="tune",
                             families={"hysteresis": "stop_voltage"}, jitter=0.3, drops=4)
    d = diagnose(rec, base="burgers")
    assert d.missing_effects == ["hysteresis"], [c.summary() for c in d.candidates]
    assert d.rmse_after <= 1.1 * d.noise_floor_v, (d.rmse_after, d.noise_floor_v)
    assert not d.unexplained["present"], d.unexplained


def test_a_flow_with_a_settling_drift_is_named_with_the_drift_in_the_shape_saved():
    """A zener that flows, with a settling drift (tune case, 1 kHz). With splines of at most 8 intervals, a spline drift
    took the creep first, then a delayed elasticity and the flow were named beside it, and the backward check had to
    re-choose the drift's shape to drop the stand-in. With the finer splines (and the variants of each size group
    polished), the flow is named first and the drift beside it in a settling shape; whatever the path, no stand-in
    is left and the variant reported is the one saved."""
    rec, case = bench_record(["viscous_flow", "offset_drift"], 0.5, "zener", 600.0, 1000.0, 4462, split="tune",
                             families={"viscous_flow": "eta_two_decades", "offset_drift": "exp_approach"},
                             jitter=0.3, drops=4)
    d = diagnose(rec, base=case.base)
    assert sorted(d.missing_effects) == ["offset_drift", "viscous_flow"], [c.summary() for c in d.candidates]
    variant = d.variants["offset_drift"]
    assert {c.variant for c in d.candidates if c.accepted and c.effect == "offset_drift"} == {variant}
    assert not variant.startswith("spline"), variant
    saved = {e.kind for e in d.chain.elements} & {"polynomial_drift", "exponential_drift", "spline_drift", "step_drift"}
    assert saved == {"polynomial": {"polynomial_drift"}, "settling": {"polynomial_drift", "exponential_drift"}}.get(variant)


@pytest.mark.parametrize("effect, seed", [(e, 3300 + i) for i, e in enumerate(EXTRA_EFFECTS) if e in OUT_OF_CATALOGUE],
                         ids=list(OUT_OF_CATALOGUE))
def test_out_of_catalogue_effect_is_unexplained_never_a_catalogue_name(effect, seed):
    rec, _ = bench_record(effect, 0.9, "burgers", DURATION_S, RATE_HZ, seed)
    d = diagnose(rec, base="burgers")
    assert d.missing_effects == [], [c.summary() for c in d.candidates]
    assert d.missing_effect == "unexplained"
    u = d.unexplained
    assert u["present"] and u["rms_v"] > u["noise_floor_v"] and u["ljung_box_p"] < 1e-3
    assert set(u["where"]) == {"segments", "follows"}


def test_a_kelvin_stiffness_that_grows_with_the_load_is_a_delayed_elasticity_with_knees():
    """The simulated Kelvin stiffness k2 (1 + alpha F) (``load_stiffening``: its creep grows less than in proportion
    to the load) is a delayed elasticity whose size changes with the load: named so, in a knee variant, and the saved
    model compensates the left-out blocks better than the base."""
    rec, _ = bench_record("load_stiffening", 0.9, "burgers", DURATION_S, RATE_HZ, 3301)
    d = diagnose(rec, base="burgers")
    assert d.missing_effects == ["delayed_elasticity"], [c.summary() for c in d.candidates]
    assert d.variants["delayed_elasticity"].startswith("knee")
    assert any(e.kind == "knee_kelvin" for e in d.chain.elements)
    assert d.newtons["saved"]["rmse_n"] < d.newtons["base"]["rmse_n"]


def test_without_temperature_thermal_is_skipped_with_the_reason_and_answers_match():
    hidden = ["hysteresis"]
    with_temp, case = bench_record(hidden, 0.8, "burgers", DURATION_S, 200.0, 3401, split="held_out")
    real, _ = bench_record(hidden, 0.8, "burgers", DURATION_S, 1000.0, 3401, split="held_out", families=case.families,
                           jitter=0.4, drops=5, temperature=False)
    assert real.temperature_c is None and np.diff(real.t_s).max() > 0.05  # gaps are really there
    a, b = diagnose(with_temp, base="burgers"), diagnose(real, base="burgers")
    assert a.missing_effects == b.missing_effects == hidden
    assert "thermal_drift" in b.skipped and "temperature" in b.skipped["thermal_drift"]
    assert "thermal_drift" not in a.skipped
    assert not any(c.effect == "thermal_drift" for c in b.candidates)
    assert any("thermal_drift not tested" in e for e in b.evidence)


def test_registry_is_the_one_source_of_effect_names():
    from polyforce_ros.cli import build_parser
    from polyforce_ros.discrepancy.localise import HINTS
    from polyforce_ros.physics.chain import ELEMENT_TYPES
    from polyforce_ros.sim import bench

    assert bench.EFFECTS == ("none",) + NAMES
    sub = next(a for a in build_parser()._subparsers._group_actions[0].choices["diagnose"]._actions if a.dest == "effects")
    assert tuple(sub.choices) == NAMES
    for effect in EFFECTS.values():
        assert set(effect.elements) <= set(ELEMENT_TYPES), effect.name
        assert FAMILIES[effect.name] and effect.hint
        assert any(effect.name in HINTS[k] for k in effect.segments + effect.signals)
        assert any(not f.held_out for f in FAMILIES[effect.name].values())  # something to tune on


def test_cli_contract_json_report_and_saved_model(tmp_path):
    bag = tmp_path / "bench.mcap"
    write_bench_bag(bag, ["nonlinear_gain", "offset_drift"], 0.8, "burgers", duration_s=DURATION_S, rate_hz=RATE_HZ, seed=3501,
                    families={"nonlinear_gain": "polynomial", "offset_drift": "linear"})
    out_json, report, model = tmp_path / "d.json", tmp_path / "report", tmp_path / "aug.yaml"
    proc = subprocess.run([sys.executable, "-m", "polyforce_ros.cli", "diagnose", str(bag), "--base", "burgers", "--json",
                           str(out_json), "--report", str(report), "--save-model", str(model), "--progress"],
                          cwd=REPO, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert "diagnose" in proc.stderr  # the progress bar
    data = json.loads(out_json.read_text())
    assert {"base", "missing_effect", "missing_effects", "effects", "rmse_before", "rmse_after", "noise_floor_v",
            "unexplained", "skipped", "evidence", "candidates", "model"} <= set(data)
    # the contract, whatever else the engine names beside the hidden two (exact naming: the tests above, the matrix)
    named = data["missing_effects"]
    assert {"nonlinear_gain", "offset_drift"} <= set(named)
    assert data["missing_effect"] == named[0] and [e["effect"] for e in data["effects"]] == named
    assert all(0.5 <= e["confidence"] <= 1.0 for e in data["effects"])
    assert {"present", "rms_v", "noise_floor_v", "where"} <= set(data["unexplained"])
    assert data["rmse_after"] <= data["rmse_before"] / 3
    assert all({"effect", "rmse", "criterion", "confidence", "step"} <= set(c) for c in data["candidates"])
    coefficients = data["coefficients"]  # the final fit's, each with its block-jackknife standard error
    assert "offset" in coefficients and all(np.isfinite(c["value"]) and 0.0 <= c["standard_error"] < np.inf
                                            for c in coefficients.values())
    # the folds disagree a little on a noisy record; the offset is pinned to well within its own size
    assert 0.0 < coefficients["offset"]["standard_error"] < 0.05 * abs(coefficients["offset"]["value"]) + 1e-3
    text = (report / "report.md").read_text()
    assert all(name in text for name in named) and "confidence" in text
    for fig in ("measured_vs_simulated.png", "residual.png", "localisation.png"):
        assert (report / "figures" / fig).is_file()
    saved = load_model(model)
    kinds = [e.kind for e in saved.chain.elements]
    assert kinds[-1] == "offset" and sum(k in MODEL_TYPES for k in kinds) == 1
    for name in named:  # every named effect is in the saved chain, as one of its registry elements
        assert set(EFFECTS[name].elements) & set(kinds), (name, kinds)
    assert saved.provenance["missing_effects"] == data["missing_effects"]
    # the saved model compensates the sensor far better than its base would
    from polyforce_ros.record import load_record

    rec = load_record(bag)
    err_aug = np.sqrt(np.mean((saved.chain.backward(rec.t_s, rec.voltage_v) - rec.force_n) ** 2))
    from polyforce_ros.physics.chain import SensorChain

    base = SensorChain([e for e in load_model(model).chain.elements if e.kind in (*MODEL_TYPES, "offset")])
    err_base = np.sqrt(np.mean((base.backward(rec.t_s, rec.voltage_v) - rec.force_n) ** 2))
    assert err_aug < err_base / 3


def test_bad_bags_are_clear_errors(tmp_path):
    from polyforce_ros.bags import BRIDGE_VOLTAGE, JOINT_STATE, BagWriter

    bag = tmp_path / "raw_only.mcap"
    with BagWriter(bag) as w:
        w.write_series(BRIDGE_VOLTAGE, JOINT_STATE, np.arange(1000) * 10_000_000, np.zeros(1000))
    proc = subprocess.run([sys.executable, "-m", "polyforce_ros.cli", "diagnose", str(bag), "--base", "burgers"],
                          cwd=REPO, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2 and "reference_force not in bag" in proc.stderr


def test_bag_recorded_from_the_driver_node_then_augmented_model_runs_live(tmp_path):
    """driver_node (sim, a nonlinear gain hidden in its truth) -> recorder_node -> diagnose -> compensation_node.

    A Zener sensor and base: 40 s of recording cannot pin a Burgers dashpot of
    ~4600 N s/V, which would blur what this test is about.
    """
    from rclpy.parameter import Parameter

    from polyforce_ros.model_file import SensorModel, save_model
    from polyforce_ros.nodes.compensation_node import CompensationNode
    from polyforce_ros.nodes.driver_node import DriverNode
    from polyforce_ros.nodes.recorder_node import RecorderNode
    from polyforce_ros.physics.chain import NonlinearGainElement, OffsetElement, SensorChain, ViscoelasticElement
    from polyforce_ros.physics.viscoelastic import Zener
    from ros_harness import ros

    truth = tmp_path / "truth.yaml"
    save_model(truth, SensorModel(SensorChain([ViscoelasticElement(Zener(4.8, 10.0, 85.12)),
                                               NonlinearGainElement(quadratic_per_v=0.06), OffsetElement(0.0)])))
    bag = tmp_path / "driver.mcap"
    with ros() as h:
        recorder = h.add(RecorderNode(context=h.context, parameter_overrides=[
            Parameter("bag_path", value=str(bag)),
            Parameter("topics", value=["bridge_voltage", "reference_force", "temperature"])]))
        h.spin_for(0.5)
        h.add(DriverNode(context=h.context, parameter_overrides=[
            Parameter("truth_model_file", value=str(truth)), Parameter("rate_hz", value=200.0),
            Parameter("profile", value="needle_insertion")]))
        h.spin_for(40.0)
        h.executor.remove_node(recorder)
        h.nodes.remove(recorder)
        recorder.destroy_node()
    assert recorder.counts["bridge_voltage"] > 7000
    proc = subprocess.run([sys.executable, "-m", "polyforce_ros.cli", "diagnose", str(bag), "--base", "zener",
                           "--json", str(tmp_path / "d.json"), "--save-model", str(tmp_path / "aug.yaml")],
                          cwd=REPO, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    data = json.loads((tmp_path / "d.json").read_text())
    assert data["missing_effects"] == ["nonlinear_gain"] and data["rmse_after"] <= data["rmse_before"] / 3, data["candidates"]
    # The augmented model runs in the compensation node unchanged.
    from polyforce_ros.record import load_record

    rec = load_record(bag)
    t, force, volts = rec.t_s, rec.force_n, rec.voltage_v
    chain = load_model(tmp_path / "aug.yaml").chain
    expected = chain.backward(t[:400], volts[:400])
    with ros() as h:
        comp = h.add(CompensationNode(context=h.context, parameter_overrides=[
            Parameter("model_file", value=str(tmp_path / "aug.yaml")), Parameter("stale_timeout_s", value=30.0)]))
        assert [e.kind for e in comp.model.chain.elements] == ["zener", "polynomial_gain", "offset"]
        stream = comp.compensator.chain.streaming()
        aux = {"temperature_c": comp.compensator.temperature_c}  # what the node hands its chain
        forces = [stream.step(ti, vi, aux) for ti, vi in zip(t[:400], volts[:400])]
    np.testing.assert_allclose(forces, expected, rtol=1e-9, atol=1e-9)
    assert np.sqrt(np.mean((np.array(forces) - force[:400]) ** 2)) < 0.05


def test_the_generator_has_a_truth_for_every_base_the_diagnosis_offers():
    from polyforce_ros.discrepancy.engine import BASES
    from polyforce_ros.sim.bench import BASE_TRUTH

    assert set(BASE_TRUTH) == set(BASES)


# ----------------------------------------------------------------------------- effects a time drift stood in for

def _held_steps(duration_s, rate_hz, rng, levels_n=(1.0, 9.0), hold_s=(10.0, 40.0)):
    """Loads held 10-40 s at random levels (a fifth of them at rest), each reached in 0.2-1 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    knots_t, knots_f, now = [0.0, 3.0], [0.0, 0.0], 3.0
    while now < duration_s:
        level, ramp = rng.uniform(*levels_n) * (rng.random() > 0.2), rng.uniform(0.2, 1.0)
        knots_t += [now + ramp, now + ramp + rng.uniform(*hold_s)]
        knots_f += [level, level]
        now = knots_t[-1]
    return t, np.interp(t, knots_t, knots_f)


def _kept(t, gaps_s):
    """The samples of ``t`` outside every ``(start_s, length_s)`` of ``gaps_s``."""
    keep = np.ones(t.size, dtype=bool)
    for start, length in gaps_s:
        keep &= ~((t >= start) & (t < start + length))
    return keep


def _record_of(core, seed, duration_s=500.0, rate_hz=200.0, gaps_s=()):
    """A record of ``core`` under held steps, 2 mV of bridge noise and 5 mN of reference noise, with the samples of
    each ``(start_s, length_s)`` of ``gaps_s`` dropped."""
    from polyforce_ros.record import Record
    rng = np.random.default_rng(seed)
    t, f = _held_steps(duration_s, rate_hz, rng)
    v = simulate_deformation(core, t, f) + 0.02 + rng.normal(0.0, 2e-3, t.size)
    keep = _kept(t, gaps_s)
    return Record(t[keep], f[keep] + rng.normal(0.0, 5e-3, int(keep.sum())), v[keep])


def test_record_gaps_are_the_longest_gaps_with_record_on_both_sides():
    from polyforce_ros.discrepancy.signals import MAX_GAPS, record_gaps
    rng = np.random.default_rng(3500)
    for _ in range(20):
        t = np.arange(0.0, 300.0, 0.005) + rng.uniform(-0.3, 0.3) * 0.005  # jittered stamps: never a gap
        gaps = [(s, rng.uniform(0.02, 3.0)) for s in np.sort(rng.uniform(2.0, 298.0, int(rng.integers(0, 12))))]
        kept = t[_kept(t, gaps)]
        found = record_gaps(kept, margin_s=20.0)
        holes = [(a, b) for a, b in zip(kept[:-1], kept[1:]) if b - a >= 0.1 and a >= 20.0 and b <= kept[-1] - 20.0]
        wanted = sorted(sorted(holes, key=lambda h: h[1] - h[0], reverse=True)[:MAX_GAPS])
        assert [g[0] for g in found] == pytest.approx([0.5 * (a + b) for a, b in wanted])
        assert [g[1] for g in found] == pytest.approx([b - a for a, b in wanted])
    assert record_gaps(np.arange(0.0, 10.0, 0.01), margin_s=1.0) == ()
    assert record_gaps(np.array([0.0, 1.0]), margin_s=0.0) == ()


@pytest.mark.parametrize("seed", [3511, 3513])
def test_a_flow_across_recording_gaps_is_named_flow_not_a_drift(seed):
    """A zener that flows, recorded at 1 kHz with three gaps of 1.5-2.5 s over load changes: across a gap the force
    is interpolated, but the flow integrated the load it really had, and the output carries the difference as a step
    from the gap on. Without an offset step of its own per gap (bounded by what the hidden load can leave), a time
    drift was fitted to the steps and named beside the flow (these two seeds)."""
    rng = np.random.default_rng(seed)
    t, f = _held_steps(500.0, 1000.0, np.random.default_rng(seed))
    moves = t[np.flatnonzero(np.diff(f))]
    picks = rng.choice(np.unique(np.round(moves[(moves > 50.0) & (moves < 400.0)])), 3, replace=False)
    gaps = tuple((float(p) - rng.uniform(0.3, 0.8), rng.uniform(1.5, 2.5)) for p in picks)
    core = MODEL_TYPES["burgers"](rng.uniform(5, 8), rng.uniform(30, 60), rng.uniform(1500, 3000), rng.uniform(1500, 3000))
    d = diagnose(_record_of(core, seed, rate_hz=1000.0, gaps_s=gaps), base="zener")
    assert d.missing_effects == ["viscous_flow"], [c.summary() for c in d.candidates if c.step <= 2]
    assert sum(re.fullmatch(r"gap\d+", name) is not None for name in d.coefficients) == 3
    assert not any(e.kind.startswith("gap") for e in d.chain.elements)  # a nuisance of the record, never saved


@pytest.mark.parametrize("seed", [3521, 3522, 3523])
def test_a_clean_record_with_gaps_over_load_changes_is_none_with_nothing_unexplained(seed):
    """A clean burgers sensor whose Kelvin unit retards in 3-20 s, recorded at 1 kHz with three gaps of 1.5-2.5 s over
    load changes: the unit's state leaves each gap off by what the hidden load did, and decays with its own time, which
    a step cannot follow. Each gap gives the record after it a bounded decay of every fast retardation, so the answer
    is ``none`` and no structure is left (a clean record with one such gap was answered ``unexplained``)."""
    rng = np.random.default_rng(seed)
    t, f = _held_steps(450.0, 1000.0, np.random.default_rng(seed))
    moves = t[np.flatnonzero(np.diff(f))]
    picks = rng.choice(np.unique(np.round(moves[(moves > 50.0) & (moves < 380.0)])), 3, replace=False)
    gaps = tuple((float(p) - rng.uniform(0.3, 0.8), rng.uniform(1.5, 2.5)) for p in picks)
    k2 = rng.uniform(10.0, 30.0)
    core = MODEL_TYPES["burgers"](rng.uniform(2.0, 6.0), k2, rng.uniform(3e3, 3e4), k2 * rng.uniform(3.0, 20.0))
    d = diagnose(_record_of(core, seed, duration_s=450.0, rate_hz=1000.0, gaps_s=gaps), base="burgers")
    assert d.missing_effect == "none", (d.missing_effects, d.unexplained["partial_fits"])
    assert not d.unexplained["present"], d.unexplained["rms_v"] / d.unexplained["noise_floor_v"]
    assert any(re.fullmatch(r"gap\d+_c\d+", name) for name in d.coefficients)


@pytest.mark.parametrize("seed", [3502, 3503, 3504])
def test_a_kelvin_unit_slower_than_the_cores_own_is_a_delayed_elasticity_not_a_drift(seed):
    """A zener sensor with a second Kelvin unit 8-15x slower than its first: the base's only retardation time stands
    in for part of it, so a delayed elasticity fitted beside that time leaves much of it and is not promising enough to
    have its times refitted. A core effect is refitted when the refit makes it slower (a time drift needs no refit,
    and was named in its place for one of these seeds)."""
    rng = np.random.default_rng(seed)
    k2, eta2 = rng.uniform(30.0, 60.0), rng.uniform(150.0, 600.0)
    tau3 = eta2 / k2 * rng.uniform(8.0, 15.0)
    k3 = rng.uniform(25.0, 50.0)
    core = MODEL_TYPES["zener2"](rng.uniform(5.0, 8.0), k2, eta2, k3, k3 * tau3)
    d = diagnose(_record_of(core, seed), base="zener")
    assert d.missing_effects == ["delayed_elasticity"], [c.summary() for c in d.candidates if c.step == 1]


def _taps(duration_s, rate_hz, rng):
    """Presses of 1-8 N held 1-10 s, with 2-8 s of rest between them."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    knots_t, knots_f, now = [0.0], [0.0], rng.uniform(2.0, 5.0)
    while now < duration_s:
        level, rise, hold = rng.uniform(1.0, 8.0), rng.uniform(0.1, 0.5), rng.uniform(1.0, 10.0)
        knots_t += [now, now + rise, now + rise + hold, now + 2 * rise + hold]
        knots_f += [0.0, level, level, 0.0]
        now += 2 * rise + hold + rng.uniform(2.0, 8.0)
    return t, np.interp(t, knots_t, knots_f)


def test_a_drift_in_time_holds_at_rest_and_a_drift_that_follows_the_load_does_not():
    """drift_follows_load on random records: a drift in time (linear, settling or a slow sine) is a drift whatever the
    load; what a load leaves (creep integrated while loaded, with or without recovery at rest), described by the
    smooth drift fitted to it, follows the load."""
    from polyforce_ros.discrepancy.residual import drift_follows_load
    rng = np.random.default_rng(3520)
    for _ in range(12):
        t, f = _taps(rng.uniform(200.0, 500.0), 100.0, rng)
        noise = rng.normal(0.0, 2e-4, t.size)
        s = t / t[-1]
        in_time = [rng.uniform(-0.02, 0.02) * s, rng.uniform(-0.02, 0.02) * -np.expm1(-t / rng.uniform(10.0, 100.0)),
                   rng.uniform(0.005, 0.02) * np.sin(2 * np.pi * t / rng.uniform(100.0, 300.0))]
        for drift in in_time:
            sig = Signals(t, f, drift + noise, None, 0.0, float(t[-1]), 23.0, span_f=float(np.ptp(f)))
            assert not drift_follows_load(sig, np.zeros_like(t), drift)
        flow = rng.uniform(1e-5, 1e-4) * np.cumsum(f) / 100.0  # creeps while loaded, stays at rest
        a = math.exp(-0.01 / rng.uniform(2.0, 10.0))
        lagged = scipy_signal.lfilter([1.0 - a], [1.0, -a], flow, zi=[a * flow[0]])[0]
        for left in (flow, flow + 0.4 * (flow - lagged)):  # and a creep that partly recovers at rest
            smooth = np.polyval(np.polyfit(s, left, 3), s)  # the drift fitted to it: smooth in time
            sig = Signals(t, f, left + noise, None, 0.0, float(t[-1]), 23.0, span_f=float(np.ptp(f)))
            assert drift_follows_load(sig, np.zeros_like(t), smooth)
    # three rests (two presses): a creep that follows the load, too few rests for a verdict by default
    t = np.arange(0.0, 100.0, 0.01)
    f = np.where(((t > 10.0) & (t < 40.0)) | ((t > 55.0) & (t < 85.0)), 5.0, 0.0)
    flow = 1e-3 * np.cumsum(f) / 100.0
    sig = Signals(t, f, flow + rng.normal(0.0, 2e-4, t.size), None, 0.0, 100.0, 23.0, span_f=5.0)
    smooth = np.polyval(np.polyfit(t, flow, 1), t)
    assert not drift_follows_load(sig, np.zeros_like(t), smooth)
    assert drift_follows_load(sig, np.zeros_like(t), smooth, min_runs=3)
    # fit bins left empty by stamp jitter (every 0.5 s) split no rest: the verdict stands
    sig.valid = (np.arange(t.size) % 50) != 7
    assert drift_follows_load(sig, np.zeros_like(t), smooth, min_runs=3)


@given(st_.lists(st_.booleans(), max_size=60), st_.integers(0, 40))
def test_near_marks_every_sample_within_reach_of_a_marked_one(mask, reach):
    """residual.near against its definition, sample by sample, for any mask and reach (a reach longer than the
    record too: the answer keeps the record's length)."""
    from polyforce_ros.discrepancy.residual import near

    mask = np.array(mask, dtype=bool)
    marked = np.flatnonzero(mask)
    want = np.array([bool(marked.size) and bool(np.min(np.abs(marked - i)) <= reach) for i in range(mask.size)],
                    dtype=bool)
    assert np.array_equal(near(mask, reach), want)


@settings(max_examples=40, deadline=None)
@given(seed=st_.integers(0, 2 ** 31 - 1))
def test_zero_jumps_are_found_where_the_zero_jumps_and_nowhere_else(seed):
    """zero_jumps on random records at 100 Hz: taps (the core's output, with a gain misfit of up to 5 % and a
    curvature the base lacks), a slow misfit of periods above 60 s, white noise, bins that stamp jitter left empty.
    Each jump of the zero (8-40 sigma, at least 8 s apart, where the load holds or rests for a second each side, half
    of them settling part of the way back) is found within the guard; without jumps, none. At gaps of 0.1-0.5 s (the
    record interpolated across, as the fit rate's bins hold it) the zero jumps too: found within a guard of the gap,
    unless the models give that gap a step of its own. Steps (jumps or gaps) nearer than a window (3.5 s) are seen as
    one: not promised; nor is a jump while the load moves, unless much larger than the misfit's bends."""
    from polyforce_ros.discrepancy.residual import JUMP_GUARD_S, zero_jumps
    rng = np.random.default_rng(seed)
    t, f = _taps(rng.uniform(200.0, 500.0), 100.0, rng)
    x = 0.05 * f  # V
    sigma = rng.uniform(2e-4, 1e-3)
    misfit = rng.uniform(-0.05, 0.05) * x + rng.uniform(-0.3, 0.3) * x ** 2
    slow = sum(rng.uniform(0.0, 20.0) * sigma * np.sin(2 * np.pi * t / rng.uniform(60.0, 400.0) + rng.uniform(0, 6))
               for _ in range(3))
    base = misfit + slow + rng.normal(0.0, sigma, t.size)
    valid = rng.uniform(size=t.size) > 0.05

    def recorded(r):  # what the fit rate's bins hold: the record interpolated across empty ones
        return np.interp(t, t[valid], r[valid])

    assert zero_jumps(t, recorded(base), x, valid, sigma) == ()
    n = int(rng.integers(1, 6))
    steady = np.array([np.ptp(f[(t > at - 1.0) & (t < at + 1.0)]) < 1e-9 for at in t[::50]])
    times = []
    for at in rng.permutation(t[::50][steady]):
        if 10.0 < at < t[-1] - 10.0 and all(abs(at - b) >= 8.0 for b in times) and len(times) < n:
            times.append(float(at) + rng.uniform(0.0, 0.01))
    zero, sizes, near, steady_load = np.zeros_like(t), [], [], [True] * len(times)
    for at in times:
        size = rng.choice([-1.0, 1.0]) * rng.uniform(8.0, 40.0) * sigma
        settles = rng.uniform(0.0, 0.8) * size if rng.uniform() < 0.5 else 0.0
        zero += np.where(t >= at, size - settles + settles * np.exp(-np.maximum(t - at, 0.0) / rng.uniform(5.0, 40.0)), 0.0)
        sizes.append(size)
        near.append((at - JUMP_GUARD_S, at + JUMP_GUARD_S))
    stepped = []
    for at in rng.uniform(10.0, t[-1] - 10.0, 3):
        if all(abs(at - b) > 8.0 for b in [*times, *(s for s, _ in stepped)]):
            end = at + rng.uniform(0.1, 0.5)
            valid &= ~((t >= at) & (t < end))
            size = rng.choice([-1.0, 1.0]) * rng.uniform(8.0, 20.0) * sigma
            zero += np.where(t >= at, size, 0.0)
            if rng.uniform() < 0.5:
                stepped.append((at, end))  # the models step there: not kept
            else:
                times.append(at)
                sizes.append(size)
                near.append((at - JUMP_GUARD_S, end + JUMP_GUARD_S))
                steady_load.append(False)  # a gap falls anywhere, the load moving or not
    order = np.argsort(times)
    sizes, near, steady_load = np.asarray(sizes)[order], np.asarray(near).reshape(-1, 2)[order], np.asarray(steady_load)[order]
    jumps = zero_jumps(t, recorded(base + zero), x, valid, sigma, stepped)
    found = np.array([j.at_s for j in jumps])
    assert found.size == len(times), (found, np.sort(times), stepped)
    assert np.all((found >= near[:, 0]) & (found <= near[:, 1])), (found, near)
    # the size is the gap between lines 0.5 s either side: under a steady load, the whole jump less what settled
    # meanwhile (where the load moves, what the misfit's bends leave is added)
    shown = np.array([j.size_v for j in jumps])
    assert np.all(np.sign(shown) == np.sign(sizes)), (shown, sizes)
    assert np.all(np.abs(shown[steady_load]) <= 1.1 * np.abs(sizes[steady_load]) + sigma), (shown, sizes)


@pytest.mark.parametrize("seed", [3531, 3532])
def test_a_zero_that_jumps_is_named_offset_drift_and_saved_as_its_jumps(seed):
    """A clean sensor (registry core, 200 Hz, jitter, gaps) whose zero jumps 3-6 times by 5-20 mV (a charge, a slipping
    clamp), each settling the same share of the way back (0-60 %, one mechanism) over one time of 5-40 s. No smooth
    drift follows a jump; the steps at the jumps the residual shows do, and the saved drift steps within the guard of
    each true jump."""
    from polyforce_ros.discrepancy.residual import JUMP_GUARD_S
    from polyforce_ros.record import Record
    rng = np.random.default_rng(seed)
    rec, _ = bench_record("none", 0.0, "burgers", 600.0, 200.0, seed, jitter=0.3, drops=3)
    n = int(rng.integers(3, 7))
    times = np.sort(rng.choice(np.arange(30.0, 570.0, 15.0), n, replace=False) + rng.uniform(0.0, 5.0, n))
    zero = np.zeros_like(rec.t_s)
    settling_s, share = rng.uniform(5.0, 40.0), rng.uniform(0.0, 0.6)
    for at in times:
        size = rng.choice([-1.0, 1.0]) * rng.uniform(0.005, 0.02)
        settles = share * size
        age = rec.t_s - at
        zero += np.where(age >= 0.0, size - settles + settles * np.exp(-np.maximum(age, 0.0) / settling_s), 0.0)
    d = diagnose(Record(rec.t_s, rec.force_n, rec.voltage_v + zero, rec.temperature_c), base="burgers")
    assert d.missing_effects == ["offset_drift"], [c.summary() for c in d.candidates]
    assert d.variants["offset_drift"] in ("steps", "jumps"), d.variants
    assert d.rmse_after <= 1.2 * d.noise_floor_v, (d.rmse_after, d.noise_floor_v)
    saved = [e for e in d.chain.elements if e.kind == "step_drift"]  # the jumps the record shows, not the truth's
    assert len(saved) == 1
    kept = times[(times > rec.t_s[0] + 5.0) & (times < rec.t_s[-1] - 5.0)]
    gaps = np.abs(np.asarray(saved[0].times_s)[:, None] + rec.t_s[0] - kept[None, :])
    assert np.all(gaps.min(axis=0) <= JUMP_GUARD_S), (saved[0].times_s, kept)


@pytest.mark.parametrize("seed", [3521, 3522])
def test_asymmetric_friction_is_named_friction_without_a_drift_beside_it(seed):
    """Friction that sticks more while the force rises than while it falls, under presses with rests: the play the
    model fits is symmetric, and a settling drift took what the asymmetry leaves while loaded (these seeds). A drift
    that moves the record under load but not at rest follows the load, and is not judged."""
    from polyforce_ros.record import Record
    rng = np.random.default_rng(seed)
    t, f = _taps(480.0, 350.0, rng)
    r_n, share = rng.uniform(0.15, 0.3), rng.uniform(0.2, 0.4)
    passed, p = np.empty_like(f), f[0]
    for i, fi in enumerate(f):  # the force through the contact: it sticks by 2 r (1 - share) up, 2 r share down
        p = max(fi - 2 * r_n * (1 - share), min(fi + 2 * r_n * share, p))
        passed[i] = p
    core = MODEL_TYPES["burgers"](rng.uniform(3.0, 8.0), rng.uniform(10.0, 40.0), rng.uniform(2e4, 1e5),
                                  rng.uniform(50.0, 400.0))
    v = simulate_deformation(core, t, passed) + 0.02 + rng.normal(0.0, 2e-3, t.size)
    d = diagnose(Record(t, f + rng.normal(0.0, 5e-3, t.size), v), base="burgers")
    assert d.missing_effects == ["friction"], [c.summary() for c in d.candidates if c.step <= 2]


@pytest.mark.parametrize("seed", [3531, 3532])
def test_a_clean_record_of_taps_at_900_hz_names_nothing(seed):
    """A clean Burgers sensor pressed in taps held 1-10 s, recorded at 900 Hz with 3 mV of bridge noise and 5 mN on the
    reference: a play of the narrowest band searched (0.1 % of the span) smooths the reference's noise and predicted
    the left-out blocks better, so friction was named, then refused in newtons, and the answer was `unexplained`.
    A band at the narrowest searched is at its noise limit and is not judged."""
    from polyforce_ros.record import Record
    rng = np.random.default_rng(seed)
    t, f = _taps(480.0, 900.0, rng)
    k2 = rng.uniform(2.0, 60.0)
    core = MODEL_TYPES["burgers"](rng.uniform(1.0, 12.0), k2, float(np.exp(rng.uniform(np.log(1e3), np.log(2e5)))),
                                  k2 * rng.uniform(0.5, 60.0))
    v = simulate_deformation(core, t, f) + 0.025 + rng.normal(0.0, 3e-3, t.size)
    d = diagnose(Record(t, f + rng.normal(0.0, 5e-3, t.size), v), base="burgers")
    assert d.missing_effect == "none", [c.summary() for c in d.candidates if c.step == 1]


@pytest.mark.parametrize("seed", [3541, 3542])
def test_a_well_damped_mode_is_named_resonance_not_a_sensor_lag(seed):
    """A mode of 20-50 Hz with a damping ratio of 0.25-0.4 on the voltage path, excited by knocks on the tool, at
    1 kHz: a low-pass too, so a sensor lag named at the fit rate held all of it, no structure was left, and the mode
    was never tried (these seeds). A named lag is always offered to the mode as a rival."""
    from polyforce_ros.physics.chain import ResonanceElement
    from polyforce_ros.record import Record
    rng = np.random.default_rng(seed)
    t, f = _taps(300.0, 1000.0, rng)
    for at in rng.uniform(10.0, 290.0, int(rng.integers(20, 41))):  # raised-cosine knocks of 5-15 ms
        i0, n = int(at * 1000.0), int(rng.uniform(5.0, 15.0))
        f[i0:i0 + n] += rng.uniform(0.2, 0.6) * 0.5 * (1.0 - np.cos(2 * np.pi * np.arange(n) / n))
    core = MODEL_TYPES["burgers"](rng.uniform(3.0, 8.0), rng.uniform(10.0, 40.0), rng.uniform(2e4, 1e5),
                                  rng.uniform(50.0, 400.0))
    mode = ResonanceElement(frequency_hz=rng.uniform(20.0, 50.0), damping_ratio=rng.uniform(0.25, 0.4))
    v = np.asarray(mode.forward(t, simulate_deformation(core, t, f)), dtype=float) + 0.02
    d = diagnose(Record(t, f + rng.normal(0.0, 5e-3, t.size), v + rng.normal(0.0, 2e-3, t.size)), base="burgers")
    assert d.missing_effects == ["resonance"], [c.summary() for c in d.candidates if c.step == 1]


@given(st_.integers(0, 2 ** 31 - 1), st_.sampled_from(["zener", "burgers", "zener2", "burgers3"]),
       st_.lists(st_.tuples(st_.floats(0.05, 0.95), st_.floats(0.0, 5.0), st_.floats(0.0, 1e-2), st_.floats(0.0, 0.1),
                            st_.lists(st_.floats(0.01, 100.0), max_size=3)), max_size=8),
       st_.booleans())
@settings(max_examples=40, deadline=None)
def test_any_gaps_and_the_slow_rival_give_a_finite_bounded_fit(seed, kind, gaps, temperature):
    """Every gap a record can hold (a step bound of zero, no fast unit or several, a decay bound of zero, gaps at the
    record's ends) and the rival of a drift (:func:`slow_response_columns`) give a design whose every lower bound lies below
    its upper bound and a fit whose coefficients and errors are finite, and whose gap decays keep one value in every
    fold."""
    from polyforce_ros.discrepancy.design import GAP_DECAY, TAU_GRID, design
    from polyforce_ros.discrepancy.residual import slow_response_columns
    from polyforce_ros.discrepancy.signals import GapStep
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 120.0, 0.05)
    f = np.clip(np.cumsum(rng.normal(0.0, 0.2, t.size)), 0.0, None)
    temp = 23.0 + rng.uniform(-3, 3) * np.sin(t / rng.uniform(10, 60)) if temperature else None
    sig = Signals(t, f, 0.1 * f + rng.normal(0.0, 1e-3, t.size), temp, t0=0.0, duration_s=float(t[-1]),
                  temp_ref=23.0, span_f=max(float(np.ptp(f)), 1e-9))
    sig.gap_steps = tuple(GapStep(at * t[-1], length, step, state, tuple(taus)) for at, length, step, state, taus in gaps)
    n_tau = {"zener": 1, "burgers": 1, "zener2": 2, "burgers3": 3}[kind]
    structure = Structure(kind, tuple(sorted(rng.choice(TAU_GRID, n_tau, replace=False))))
    names, a, lo, hi, _ = design(sig, structure, slow_response_columns(sig))
    assert np.all(lo < hi) and np.all(np.isfinite(a))
    assert any(n.startswith("slow_zero") for n in names) == temperature
    fit = Fitter(sig, 5).evaluate(structure, slow_response_columns(sig))
    assert np.all(np.isfinite(fit.coef)) and np.all(np.isfinite(fit.sse_folds)) and math.isfinite(fit.cv_mse)
    decays = [i for i, n in enumerate(fit.names) if GAP_DECAY.fullmatch(n)]
    for folded in fit.coef_folds:
        np.testing.assert_array_equal(folded[decays], fit.coef[decays])


def _held_levels(duration_s, rate_hz, rng):
    """Force held at random levels (0-8 N, 5-30 s) reached by minimum-jerk moves of 0.3-1.5 s: little content
    above a few Hz."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f, now, level = np.zeros_like(t), 2.0, 0.0
    while now < duration_s:
        move, target = rng.uniform(0.3, 1.5), rng.uniform(0.0, 8.0)
        moving = (t >= now) & (t < now + move)
        u = (t[moving] - now) / move
        f[moving] = level + (target - level) * u ** 3 * (10.0 - 15.0 * u + 6.0 * u * u)
        now += move
        f[t >= now], level = target, target
        now += rng.uniform(5.0, 30.0)
    return t, f


@pytest.mark.parametrize("seed", [0, 1])
def test_the_low_pass_rival_replaces_a_named_lags_stages_by_the_equal_poles_the_record_holds(seed):
    """``through_equal_poles``: a record through three equal poles, predicted through a pole pair of the same total
    delay (the fit rate's choice), is taken by the rival to within a small share of the pair's error, the pair's
    stages undone first; without them undone the rival can only add poles to the pair, and does worse."""
    from polyforce_ros.discrepancy.resonance import through_equal_poles
    from polyforce_ros.discrepancy.columns import lag_columns

    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 60.0, 1e-3)
    x = np.cumsum(rng.normal(0.0, 0.02, t.size))  # a random walk: content at every frequency
    delay_s = rng.uniform(0.03, 0.09)
    measured, predicted = x.copy(), x.copy()
    for _ in range(3):
        measured = lag_columns(t, measured, delay_s / 3.0)
    for _ in range(2):
        predicted = lag_columns(t, predicted, delay_s / 2.0)

    def sse(y):
        return float(np.sum((y - measured) ** 2))

    replaced = through_equal_poles(t, measured, predicted, [delay_s / 2.0] * 2)
    added = through_equal_poles(t, measured, predicted, [])
    assert sse(replaced) <= 0.05 * sse(predicted) and sse(replaced) < sse(added)


def _light_mode_record(seed, duration_s=120.0):
    """A coloured drive (like a load) through a mode of 10-80 Hz damped at 0.005-0.05 (at least 0.1 Hz of
    half-power width), 1 mV of noise at 1 kHz: (t, drive, measured, f0_hz, zeta)."""
    from polyforce_ros.physics.chain import ResonanceElement

    rng = np.random.default_rng(seed)
    f0_hz = rng.uniform(10.0, 80.0)
    zeta = max(rng.uniform(0.005, 0.05), 0.05 / f0_hz)
    t = np.arange(0.0, duration_s, 1e-3)
    drive = scipy_signal.lfilter([1.0], [1.0, -0.9], rng.normal(0.0, 0.01, t.size))
    rung = np.asarray(ResonanceElement(frequency_hz=f0_hz, damping_ratio=zeta).forward(t, drive), dtype=float)
    return t, drive, rung + rng.normal(0.0, 1e-3, t.size), f0_hz, zeta


@pytest.mark.parametrize("seed", range(6))
def test_the_transfer_peak_finds_a_light_modes_frequency_and_damping(seed):
    """The empirical transfer's peak (the light mode's start) lies within the mode's half-power band (or one Welch
    bin of 1/15 Hz, for the lightest), with a damping within a factor of 1.6 (the window smears the peak); a
    transfer with no gain above 1 gives none."""
    from polyforce_ros.discrepancy.resonance import transfer_peak

    t, drive, measured, f0_hz, zeta = _light_mode_record(seed)
    peak = transfer_peak(drive, measured, 1e-3, 450.0)
    assert peak is not None and abs(peak[0] - f0_hz) <= max(1.0 / 15.0, zeta * f0_hz)
    assert zeta / 1.6 <= peak[1] <= 1.6 * zeta
    assert transfer_peak(drive, 0.5 * drive, 1e-3, 450.0) is None
    assert transfer_peak(np.zeros(t.size), measured, 1e-3, 450.0) is None


@pytest.mark.parametrize("seed", range(3))
def test_a_light_mode_is_fitted_from_a_band_an_octave_away(seed):
    """A mode damped at 0.005-0.05 is fitted within 0.5 % in frequency and 20 % in damping when the search band
    given (the residual's strongest) starts an octave below it: the transfer's peak is a start of its own."""
    from polyforce_ros.discrepancy.resonance import fit_mode

    t, drive, measured, f0_hz, zeta = _light_mode_record(seed)
    fold = (np.arange(t.size) * 5 // t.size).astype(int)
    mode = fit_mode(t, measured, drive, fold, 1e-3, (f0_hz / 4.0, f0_hz / 2.0), 0.8, 0.3)
    assert mode is not None and mode.frequency_hz == pytest.approx(f0_hz, rel=0.005)
    assert mode.damping_ratio == pytest.approx(zeta, rel=0.2)


@given(st_.integers(0, 2**32 - 1), st_.integers(0, 40000), st_.sampled_from([1e-3, 4e-3, 0.05, 0.0, -1e-3, np.nan]),
       st_.sampled_from(["noise", "constant", "nan", "huge"]))
@settings(max_examples=40, deadline=None)
def test_the_transfer_peak_of_any_record_is_none_or_a_mode_inside_its_bounds(seed, n, step_s, content):
    from polyforce_ros.discrepancy.resonance import LOWEST_MODE_HZ, ZETA_BOUNDS, transfer_peak

    rng = np.random.default_rng(seed)
    x = {"noise": rng.normal(0.0, 1.0, n), "constant": np.full(n, 0.3), "huge": rng.normal(0.0, 1e150, n),
         "nan": np.where(rng.random(n) < 0.01, np.nan, rng.normal(0.0, 1.0, n))}[content]
    y = np.roll(x, 1) * 3.0 + rng.normal(0.0, 0.1, n)
    highest_hz = 0.45 / step_s if step_s > 0 else 1.0
    peak = transfer_peak(x, y, step_s, highest_hz)
    assert peak is None or (LOWEST_MODE_HZ <= peak[0] <= highest_hz and ZETA_BOUNDS[0] <= peak[1] <= ZETA_BOUNDS[1])


@pytest.mark.parametrize("seed", [3, 9])
def test_a_mode_that_only_smooths_the_reference_forces_noise_is_not_named(seed):
    """``choose_mode``: a soft sensor's prediction carries the reference force's noise (5 mN through about 1 N/V
    is about 5 mV, white), which the bridge never saw. Under smooth holds a lightly damped mode low in the band
    takes that noise out of the prediction at little cost and passed the fold test (these seeds); a low-pass that
    cannot ring takes it out as well, so no mode is named. A mode that knocks on the tool make the record ring with
    is still named over the same noise."""
    from polyforce_ros.discrepancy.resonance import _through_mode, choose_mode
    from polyforce_ros.physics.viscoelastic import Burgers

    rng = np.random.default_rng(seed)
    rate_hz = 690.0
    t, f = _held_levels(120.0, rate_hz, rng)
    core = Burgers(rng.uniform(0.8, 1.5), rng.uniform(3.0, 10.0), 3e4, rng.uniform(20.0, 200.0))
    clean = simulate_deformation(core, t, f) + 0.05
    predicted = simulate_deformation(core, t, f + rng.normal(0.0, 5e-3, t.size)) + 0.05
    fold = (np.arange(t.size) * 5 // t.size).astype(int)
    mode, _ = choose_mode(t, clean + rng.normal(0.0, 2.5e-3, t.size), predicted, fold, 2.5e-3, (1.0, 2.0), 0.8, 0.3)
    assert mode is None, (mode.frequency_hz, mode.damping_ratio, mode.excess_share)
    for at in rng.uniform(5.0, 115.0, 30):  # knocks of 5-15 ms on the tool excite a mode
        i0, n = int(at * rate_hz), int(rng.uniform(0.005, 0.015) * rate_hz)
        f[i0:i0 + n] += rng.uniform(0.2, 0.6) * 0.5 * (1.0 - np.cos(2 * np.pi * np.arange(n) / n))
    f0_hz = rng.uniform(15.0, 30.0)
    rings = (_through_mode(simulate_deformation(core, t, f) + 0.05, 1.0 / rate_hz, f0_hz, 0.05)
             + rng.normal(0.0, 2.5e-3, t.size))
    predicted = simulate_deformation(core, t, f + rng.normal(0.0, 5e-3, t.size)) + 0.05
    mode, _ = choose_mode(t, rings, predicted, fold, 2.5e-3, (8.0, 32.0), 0.8, 0.3)
    assert mode is not None and mode.frequency_hz == pytest.approx(f0_hz, rel=0.05)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_mode_is_added_beside_a_lag_only_for_structure_the_record_shows(seed):
    """``choose_mode``: a 20-40 Hz mode that does take the prediction to the measurement is named on top of a lag's
    prediction when the unexplained test saw structure, and not when it saw none (``structure_seen`` False): then
    a mode could only replace the lag, and here the lag's prediction is the better one. Where the mode alone
    predicts better than the lag, it replaces the lag either way."""
    from polyforce_ros.discrepancy.resonance import _through_mode, choose_mode

    rng = np.random.default_rng(seed)
    rate_hz = 1000.0
    t = np.arange(0.0, 60.0, 1.0 / rate_hz)
    knocks = np.zeros_like(t)
    for at in rng.uniform(1.0, 59.0, 40):
        knocks += np.exp(-np.clip(t - at, 0.0, None) / 0.01) * (t >= at) * rng.uniform(-0.05, 0.05)
    predicted = 0.02 * np.sin(2 * np.pi * 0.3 * t) + knocks
    measured = _through_mode(predicted, 1.0 / rate_hz, rng.uniform(20.0, 40.0), rng.uniform(0.03, 0.1)) \
        + rng.normal(0.0, 2e-3, t.size)
    fold = (np.arange(t.size) * 5 // t.size).astype(int)
    without_lag = np.roll(predicted, 50)  # a worse prediction: the model without its lag
    seen, _ = choose_mode(t, measured, predicted, fold, 2e-3, (15.0, 60.0), 0.8, 0.3, without_lag)
    assert seen is not None and 15.0 < seen.frequency_hz < 45.0
    unseen, drop_lag = choose_mode(t, measured, predicted, fold, 2e-3, (15.0, 60.0), 0.8, 0.3, without_lag,
                                   structure_seen=False)
    assert unseen is None and not drop_lag
    # the record rings through the mode of what the model without its lag predicts, and the lag's prediction (a
    # delay of it) is the worse one: the mode replaces the lag, structure seen or not
    rings = _through_mode(without_lag, 1.0 / rate_hz, rng.uniform(20.0, 40.0), rng.uniform(0.03, 0.1)) \
        + rng.normal(0.0, 2e-3, t.size)
    for seen_there in (True, False):
        alone, drop_lag = choose_mode(t, rings, np.roll(without_lag, 8), fold, 2e-3, (15.0, 60.0), 0.8, 0.3,
                                      without_lag, structure_seen=seen_there)
        assert alone is not None and drop_lag and 15.0 < alone.frequency_hz < 45.0


def test_the_column_cache_drops_its_least_recently_used_columns_past_its_bound_never_the_newest():
    """A polish makes columns for every retardation time and shift factor it tries: the cache keeps the most recently
    used up to its bound in bytes (one entry larger than the bound too), counts what it holds, and a key set again
    is counted once."""
    from polyforce_ros.discrepancy.signals import CACHE_BYTES, ColumnCache, Signals

    cache = ColumnCache(max_bytes=4 * 8000)
    column = np.zeros(1000)  # 8000 bytes
    for k in range(4):
        cache[k] = [("c", column.copy(), 0.0, 1.0, "sensor", None)]
    assert list(cache) == [0, 1, 2, 3] and cache.held_bytes == 4 * 8000
    _ = cache[0]  # used: now the newest
    cache[4] = (column.copy(), 1.5)
    assert list(cache) == [2, 3, 0, 4] and cache.held_bytes == 4 * 8000
    cache[4] = column[:500].copy()  # the same key again
    assert cache.held_bytes == 3 * 8000 + 4000 and len(cache) == 4
    cache["big"] = np.zeros(10000)  # larger than the bound alone: kept, everything older dropped
    assert list(cache) == ["big"] and cache.held_bytes == 80000
    cache["scalar"] = 3.0
    assert list(cache) == ["scalar"] and cache.held_bytes == 0
    sig = Signals(np.arange(3.0), np.zeros(3), np.zeros(3), None, 0.0, 2.0, 20.0)
    assert isinstance(sig.cache, ColumnCache) and sig.cache.max_bytes == CACHE_BYTES


@settings(max_examples=200, deadline=None)
@given(floor=st_.floats(1e-5, 1e-1), over=st_.floats(0.0, 3.0), ratio=st_.floats(0.1, 2.0), seen=st_.booleans())
def test_something_is_left_when_structure_is_seen_or_the_error_stands_ratio_floors_above_the_floor(floor, over, ratio,
                                                                                                      seen):
    """An error whose own excess over the floor is ``over`` floors: left exactly when ``over >= ratio`` (away from
    the line, where rounding decides), or whenever the tests of structure see something."""
    from polyforce_ros.discrepancy.residual import something_left

    rmse = floor * math.hypot(1.0, over)
    left = something_left(seen, rmse, floor, ratio)
    if seen:
        assert left
    elif abs(over - ratio) > 1e-9 * max(ratio, 1.0):
        assert left == (over >= ratio), (over, ratio)
    assert not something_left(False, 0.5 * floor, floor, ratio)  # below the floor: nothing
