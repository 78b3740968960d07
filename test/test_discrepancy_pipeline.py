"""The whole user pipeline on an unknown sensor with hidden hysteresis, for every hysteresis family.

An unknown sensor (random Burgers parameters, +-30 %) hides a hysteresis of one
family (Preisach on the force path, Prandtl-Ishlinskii on the force or on the
voltage path, Bouc-Wen; random parameters, 3-5 % of full scale). A ~7-minute
mixed bench record goes through ``polyforce diagnose --base burgers
--save-model M.yaml``; then the same sensor reads a 0-10 N sawtooth and the
Okamura needle profile (the synthetic one when the data is absent), and
``polyforce compensate --model M.yaml`` must leave at most 1 % hysteresis
(seed 000's normalised first-cycle measure) and R^2 >= 0.99.
"""
import dataclasses
import json
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO
from polyforce_ros import bags
from polyforce_ros.physics.metrics import hysteresis_percent, r_squared
from polyforce_ros.sim import profiles, truths
from polyforce_ros.sim.bench import simulate_bench
from polyforce_ros.sim.recording import write_bench_bag
from polyforce_ros.sim.sensor import BridgeSimulator

FAMILIES = list(truths.FAMILIES["hysteresis"])
#: Known gaps (see the matrix in docs/discrepancy.md): family -> why the whole pipeline fails for it today (none at present).
KNOWN_GAPS: dict = {}


def _polyforce(*args):
    return subprocess.run([sys.executable, "-m", "polyforce_ros.cli", *args], cwd=REPO, capture_output=True, text=True,
                          timeout=600)


def _diagnose_saving(bench, tmp_path):
    """``polyforce diagnose BENCH --base burgers --save-model M.yaml --json d.json``: (JSON answer, model path)."""
    model = tmp_path / "M.yaml"
    proc = _polyforce("diagnose", str(bench), "--base", "burgers", "--save-model", str(model), "--json",
                      str(tmp_path / "d.json"))
    assert proc.returncode == 0, proc.stderr
    return json.loads((tmp_path / "d.json").read_text()), model


def _read_through(truth, t, f, path, seed, noise_std_v=1e-3):
    sim = BridgeSimulator(noise_std_v=noise_std_v, seed=seed)
    sim.chain, sim._states = truth, truth.forward_states()
    write_bench_bag(path, t, f, sim.simulate(t, f, temperature_c=24.0), temperature_c=24.0)


def _compensated(bag_in, bag_out, model):
    proc = _polyforce("compensate", str(bag_in), str(bag_out), "--model", str(model))
    assert proc.returncode == 0, proc.stderr
    data = bags.read_bag(bag_out)
    raw, wrench = data[bags.BRIDGE_VOLTAGE], data[bags.WRENCH]
    return (raw.stamp_ns - raw.stamp_ns[0]) * 1e-9, wrench.fields["force_z"]


def _diagnosed_bench(family, tmp_path, rate_hz):
    """The unknown sensor hiding ``family`` (seed 3600 + its index, 3-5 % of full scale), a ~7-minute bench record at
    ``rate_hz`` through ``polyforce diagnose --base burgers --save-model``: (case, seed, JSON answer, model path)."""
    seed = 3600 + FAMILIES.index(family)
    magnitude = float(np.random.default_rng(seed).uniform(0.4, 0.8))
    t, f, v, temp, case = simulate_bench(["hysteresis"], magnitude, "burgers", duration_s=420.0, rate_hz=rate_hz,
                                         seed=seed, split="held_out", families={"hysteresis": family})
    bench = tmp_path / "bench.mcap"
    write_bench_bag(bench, t, f, v, temperature_c=temp, temperature_every=10)
    data, model = _diagnose_saving(bench, tmp_path)
    return case, seed, data, model


def _compensated_readings(case, seed, model, tmp_path, saw_rate_hz, needle_rate_hz, noise_std_v):
    """The same sensor reading a 0-10 N sawtooth and the needle profile, compensated with ``model``: (first-cycle
    hysteresis %, R^2 on the needle profile)."""
    ts, fs = profiles.sawtooth(peak_n=10.0, cycles=4, ramp_rate_n_per_s=1.0, rate_hz=saw_rate_hz)
    _read_through(case.truth, ts, fs, tmp_path / "saw.mcap", seed, noise_std_v)
    tc, comp = _compensated(tmp_path / "saw.mcap", tmp_path / "saw_out.mcap", model)
    first = (tc >= 2.0) & (tc < 22.0)
    h = hysteresis_percent(np.interp(tc, ts, fs)[first], comp[first])
    name = "okamura" if profiles.okamura_csv_path() is not None else "needle_insertion"
    tn, fn = profiles.make_profile(name, rate_hz=needle_rate_hz, seed=seed)
    _read_through(case.truth, tn, fn, tmp_path / "needle.mcap", seed + 1, noise_std_v)
    tc, comp = _compensated(tmp_path / "needle.mcap", tmp_path / "needle_out.mcap", model)
    return h, r_squared(np.interp(tc, tn, fn), comp)


@pytest.mark.parametrize("family", [pytest.param(f, marks=pytest.mark.xfail(reason=KNOWN_GAPS[f], strict=False))
                                    if f in KNOWN_GAPS else f for f in FAMILIES])
def test_diagnose_save_model_then_compensate_removes_hidden_hysteresis(family, tmp_path):
    case, seed, data, model = _diagnosed_bench(family, tmp_path, 100.0)
    assert "hysteresis" in data["missing_effects"], data["candidates"]  # (a spurious extra name is tested elsewhere)
    assert data["rmse_after"] <= 2.0 * data["noise_floor_v"], (data["rmse_after"], data["noise_floor_v"])
    # the same sensor on a 0-10 N sawtooth (static reading shows the hidden hysteresis, compensation removes it)
    # and on the needle-insertion profile
    h, r2 = _compensated_readings(case, seed, model, tmp_path, 100.0, 200.0, 1e-3)
    assert h <= 1.0, h
    assert r2 >= 0.99, r2


@pytest.mark.parametrize("family", ["play_voltage", "stop_force"])
def test_the_pipeline_holds_at_1khz_where_bridge_noise_reaches_the_small_plays(family, tmp_path):
    """The saved chain runs its hysteresis on the raw signal: on the voltage path the inverse's plays of small radius
    (0.3 % of the span, 3-5 standard deviations of 2 mV) see every sample's bridge noise, on the force path the core's
    noise-driven input does. At 1 kHz, with 2 mV of noise on the bench record and on the readings, the whole
    pipeline still meets the issue's bounds (measured for all six families: <= 0.52 % and R^2 >= 0.990)."""
    case, seed, data, model = _diagnosed_bench(family, tmp_path, 1000.0)
    assert "hysteresis" in data["missing_effects"], data["candidates"]
    h, r2 = _compensated_readings(case, seed, model, tmp_path, 1000.0, 1000.0, 2e-3)
    assert h <= 1.0, h
    assert r2 >= 0.99, r2


#: The catalogue's newer effects through the whole user pipeline: (effect, its tune family, magnitude, rate Hz, seed).
NEW_EFFECTS = [("thermal_sensitivity", "linear_span", 0.7, 200.0, 3701), ("friction", "rigid_contact", 0.2, 200.0, 3702),
               ("resonance", "light_mode", 0.7, 1000.0, 3703), ("thermo_rheological", "arrhenius", 0.7, 200.0, 3704)]


@pytest.mark.parametrize("effect, family, magnitude, rate_hz, seed", NEW_EFFECTS, ids=[e[0] for e in NEW_EFFECTS])
def test_diagnose_save_model_then_compensate_for_each_newer_effect(effect, family, magnitude, rate_hz, seed, tmp_path):
    """``polyforce diagnose --save-model`` names the effect, and ``polyforce compensate`` with that model file takes a
    new record of the same sensor (a needle profile under a temperature swing, in a bag with its temperature topic)
    to within 1 % of full scale RMSE, against the reference as late as the model states (its latency); a friction
    within the band it fitted."""
    from polyforce_ros.discrepancy.effects import EFFECTS
    from polyforce_ros.model_file import load_model
    from polyforce_ros.sim.bench import random_temperature

    t, f, v, temp, case = simulate_bench([effect], magnitude, "burgers", duration_s=420.0, rate_hz=rate_hz, seed=seed,
                                         families={effect: family})
    write_bench_bag(tmp_path / "bench.mcap", t, f, v, temperature_c=temp, temperature_every=10)
    data, model = _diagnose_saving(tmp_path / "bench.mcap", tmp_path)
    assert data["missing_effects"] == [effect], (data["missing_effects"], data["unexplained"])
    chain = load_model(model).chain
    # the JSON reports the saved element's own figures (a mode's frequency and damping, a friction's band...)
    held = next(e for e in chain.elements if e.kind in EFFECTS[effect].elements)
    assert data["effects"][0]["saved"] == pytest.approx({k: v for k, v in held.to_dict().items()
                                                         if isinstance(v, float)})
    tn, fn = profiles.make_profile("needle_insertion", rate_hz=rate_hz, seed=seed)
    tempn = random_temperature(tn + 200.0, seed + 1)
    sim = BridgeSimulator(noise_std_v=2e-3, seed=seed + 1)
    sim.chain, sim._states = case.truth, case.truth.forward_states()
    write_bench_bag(tmp_path / "needle.mcap", tn, fn, sim.simulate(tn, fn, temperature_c=tempn), temperature_c=tempn,
                    temperature_every=1)
    tc, comp = _compensated(tmp_path / "needle.mcap", tmp_path / "needle_out.mcap", model)
    late = np.interp(tc - chain.latency_s, tn, fn, left=fn[0])
    rmse_n = float(np.sqrt(np.mean((comp - late) ** 2)))
    if effect == "friction":  # a band of one width under the bench's temperature swing: none that follows it
        assert data["effects"][0]["variant"] == "", data["effects"]
        band_n = next(e.radius_n for e in chain.elements if e.kind == "friction")
        assert rmse_n <= band_n
    else:
        assert rmse_n <= 0.01 * np.ptp(fn), (rmse_n, np.ptp(fn))


def _kelvin_held(t, f, shape, rng):
    """A Kelvin unit of random time and compliance (V/N) whose load a preload keeps out of play below a soft knee
    (``preload``: softplus(F - F0) over a 0.3 N wide bend), or whose spring stiffens as it is loaded (``stiffening``:
    its load F0 log(1 + F / F0)): neither is the sharp knee the engine fits. Returns a function (t, f) -> V."""
    from polyforce_ros.physics.expconv import exp_convolve

    tau_s, compliance = float(rng.uniform(3.0, 30.0)), float(rng.uniform(0.02, 0.05))
    knee_n, bend_n = float(rng.uniform(2.0, 4.0)), 0.3

    def unit(t, load):
        return compliance * exp_convolve(t, load, [1.0 / tau_s])[:, 0] / tau_s

    if shape == "preload":
        return lambda t, f: unit(t, bend_n * np.logaddexp(0.0, (f - knee_n) / bend_n))
    return lambda t, f: unit(t, knee_n * np.log1p(np.maximum(f, 0.0) / knee_n))


@pytest.mark.parametrize("shape, seed", [("preload", 3711), ("stiffening", 3712)])
def test_a_kelvin_unit_that_a_preload_holds_or_that_stiffens_is_named_saved_and_compensated(shape, seed, tmp_path):
    """A load-dependent delayed elasticity through the whole user pipeline: named ``delayed_elasticity``, saved with a
    ``knee_kelvin`` element, and the same sensor's new records (a needle profile, a 0-10 N sawtooth that crosses the
    knee) compensated to within 1 % of full scale RMSE."""
    from polyforce_ros.model_file import load_model

    rng = np.random.default_rng(seed)
    t, f, v, temp, case = simulate_bench("none", 0.0, "burgers", duration_s=420.0, rate_hz=200.0, seed=seed)
    extra = _kelvin_held(t, f, shape, rng)
    write_bench_bag(tmp_path / "bench.mcap", t, f, v + extra(t, f), temperature_c=temp, temperature_every=10)
    data, model = _diagnose_saving(tmp_path / "bench.mcap", tmp_path)
    assert data["missing_effects"] == ["delayed_elasticity"], (data["missing_effects"], data["unexplained"])
    assert any(e.kind == "knee_kelvin" for e in load_model(model).chain.elements)
    ts, fs = profiles.sawtooth(peak_n=10.0, cycles=3, ramp_rate_n_per_s=0.5, rate_hz=200.0)
    tn, fn = profiles.make_profile("needle_insertion", rate_hz=200.0, seed=seed)
    for name, (tr, fr) in {"sawtooth": (ts, fs), "needle": (tn, fn)}.items():
        sim = BridgeSimulator(noise_std_v=2e-3, seed=seed + 1)
        sim.chain, sim._states = case.truth, case.truth.forward_states()
        volts = sim.simulate(tr, fr, temperature_c=24.0) + extra(tr, fr)
        write_bench_bag(tmp_path / f"{name}.mcap", tr, fr, volts, temperature_c=24.0)
        tc, comp = _compensated(tmp_path / f"{name}.mcap", tmp_path / f"{name}_out.mcap", model)
        rmse_n = float(np.sqrt(np.mean((comp - np.interp(tc, tr, fr)) ** 2)))
        assert rmse_n <= 0.01 * np.ptp(fr), (name, rmse_n, np.ptp(fr))


@pytest.mark.parametrize("seed, sign, lagged", [(3721, 1.0, False), (3722, -1.0, True)])
def test_a_friction_band_that_follows_temperature_is_named_saved_and_compensated_warm_and_cold(seed, sign, lagged,
                                                                                               tmp_path):
    """A rigid Coulomb contact whose band follows the mechanism's temperature (a log-slope of 4-12 %/degC, widening
    as it warms or as it cools, on the thermometer's own temperature or on one 8-25 s behind it): named
    ``friction`` with a band that follows temperature and saved with the slope's sign, within a factor of two; the
    same sensor's new records, colder and warmer than the bench, are compensated better than with the band held at
    its reference width, and within the band at that temperature."""
    from polyforce_ros.model_file import load_model, save_model
    from polyforce_ros.physics.chain import FrictionElement, SensorChain

    rng = np.random.default_rng(seed)
    t, f, _, temp, case = simulate_bench("none", 0.0, "burgers", duration_s=420.0, rate_hz=200.0, seed=seed)
    slope = sign * float(rng.uniform(0.04, 0.12))
    lag_s = float(rng.uniform(8.0, 25.0)) if lagged else 0.0
    band = FrictionElement(radius_n=float(rng.uniform(0.02, 0.03) * np.ptp(f)), coupling=1.0, band_log_slope_per_c=slope,
                           reference_c=24.0, temperature_lag_s=lag_s)
    truth = SensorChain([band, *case.truth.elements], forward_only=True)

    def read(t_s, f_n, temp_c, noise_seed):
        sim = BridgeSimulator(noise_std_v=2e-3, seed=noise_seed)
        sim.chain, sim._states = truth, truth.forward_states()
        return sim.simulate(t_s, f_n, temperature_c=temp_c)

    write_bench_bag(tmp_path / "bench.mcap", t, f, read(t, f, temp, seed), temperature_c=temp, temperature_every=10)
    data, model = _diagnose_saving(tmp_path / "bench.mcap", tmp_path)
    assert data["missing_effects"] == ["friction"], (data["missing_effects"], data["unexplained"])
    saved = next(e for e in load_model(model).chain.elements if isinstance(e, FrictionElement))
    assert 0.5 <= saved.band_log_slope_per_c / slope <= 2.0, (saved.to_dict(), slope, lag_s)

    # the same sensor on slow 0-10 N ramps, 7 degC below and above the reference: while it slides the band's width
    # is the whole error of a compensator that holds it at its reference width
    loaded = load_model(model)
    held = SensorChain([FrictionElement.from_dict({**e.to_dict(), "band_log_slope_per_c": 0.0})
                        if isinstance(e, FrictionElement) else e for e in loaded.chain.elements])
    save_model(tmp_path / "held.yaml", dataclasses.replace(loaded, chain=held))
    ts, fs = profiles.sawtooth(peak_n=10.0, cycles=3, ramp_rate_n_per_s=0.5, rate_hz=200.0)
    for label, temp_c in {"cold": 17.0, "warm": 31.0}.items():
        write_bench_bag(tmp_path / f"{label}.mcap", ts, fs, read(ts, fs, temp_c, seed + 2), temperature_c=temp_c)
        errors = {}
        for name, path in {"saved": model, "held": tmp_path / "held.yaml"}.items():
            tc, comp = _compensated(tmp_path / f"{label}.mcap", tmp_path / f"{label}_{name}.mcap", path)
            errors[name] = float(np.sqrt(np.mean((comp - np.interp(tc, ts, fs)) ** 2)))
        band_there_n = band.radius_n * np.exp(slope * (temp_c - band.reference_c))
        assert errors["saved"] < errors["held"], (label, errors, saved.to_dict(), slope, lag_s)
        assert errors["saved"] <= band_there_n, (label, errors, band_there_n)
