"""Fuzz-proof model files: every bad file is a ModelError naming the reason, every accepted model is finite.

The cases of the "Fuzz-proof" issue (huge/tiny parameters that gave NaN forces
or an IndexError, YAML nested 5 000 / 100 000 deep, a 400-digit integer, a list
as the element type), the parameter bounds against the identification search
boxes, hypothesis mutation of the shipped model and of a model of every element
type, and the CLI (exit 2, no traceback).
"""
import copy
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from conftest import REPO
from polyforce_ros.model_file import (
    MAX_DEPTH, MAX_FILE_BYTES, SensorModel, default_model_path, load_model, model_from_mapping, model_to_mapping,
    parse_model_yaml, save_model, validate_chain_numerics,
)
from polyforce_ros.physics.chain import (
    ELEMENT_TYPES, PARAMETER_BOUNDS, GainElement, ModelError, NonlinearGainElement, OffsetDriftElement,
    OffsetElement, PreisachElement, SensorChain, SensorLagElement, ThermalDriftElement, ViscoelasticElement,
)
from polyforce_ros.physics.viscoelastic import MODEL_TYPES, PAPER_BURGERS, Burgers, Zener

MAX = sys.float_info.max
PAPER_TEXT = (REPO / "config" / "paper_burgers.yaml").read_text()
_FUZZ = bool(os.environ.get("POLYFORCE_FUZZ"))  # see conftest: a longer random campaign by hand


def fuzz_settings(n):
    return settings(derandomize=not _FUZZ, database=None, max_examples=n * (20 if _FUZZ else 1), deadline=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                           HealthCheck.function_scoped_fixture])


def paper():
    return yaml.safe_load(PAPER_TEXT)


def with_element(element, core=True):
    """The paper model with ``element`` (a mapping) between the core and the offset."""
    data = paper()
    data["elements"].insert(1 if core else 0, element)
    return data


def with_elements(elements):
    data = paper()
    data["elements"][1:1] = elements
    return data


def set_core(**values):
    data = paper()
    data["elements"][0].update(values)
    return data


def load_text(tmp_path, text, name="bad.yaml"):
    path = tmp_path / name
    path.write_text(text) if isinstance(text, str) else path.write_bytes(text)
    return load_model(path)


def dump(data):
    return yaml.safe_dump(data, sort_keys=False)


def record(n=200, h=1e-3):
    t = 50.0 + h * np.arange(n)
    return t, 0.5 + 0.3 * np.sin(2 * np.pi * 0.5 * (t - t[0])), {"temperature_c": 25.0 + 5.0 * np.sin(t)}


def assert_finite_model(model):
    t, v, aux = record()
    with np.errstate(all="ignore"):
        assert np.all(np.isfinite(model.chain.backward(t, v, aux)))
        assert np.all(np.isfinite(model.chain.forward(t, 2.0 + np.cos(t), aux)))


# -- the issue's cases, one by one --------------------------------------------------------------------

CORE_KEYS = ("k1_n_per_v", "k2_n_per_v", "eta1_n_s_per_v", "eta2_n_s_per_v")
ISSUE_CASES = {
    # 3: exit 0 with 20 000-30 000 NaN forces
    **{f"k1={v!r}": (lambda v=v: set_core(k1_n_per_v=v), "k1_n_per_v") for v in (1e300, 1e308, MAX)},
    "every value 1e300": (lambda: set_core(**{k: 1e300 for k in CORE_KEYS}), "k1_n_per_v"),
    "offset 1e308 V": (lambda: (d := paper(), d["elements"][1].update(voltage_v=1e308))[0], "voltage_v"),
    "offset_drift +1e308 V/s": (lambda: with_element({"type": "offset_drift", "rate_v_per_s": 1e308}), "rate_v_per_s"),
    "offset_drift -1e308 V/s": (lambda: with_element({"type": "offset_drift", "rate_v_per_s": -1e308}), "rate_v_per_s"),
    "gain 1e-308": (lambda: with_element({"type": "gain", "gain": 1e-308}), "gain"),
    "sensor_lag tau 1e308 s": (lambda: with_element({"type": "sensor_lag", "tau_s": 1e308}), "tau_s"),
    # 6: IndexError traceback
    **{f"{k}={v!r}": (lambda k=k, v=v: set_core(**{k: v}), k)
       for k in ("k2_n_per_v", "eta1_n_s_per_v", "eta2_n_s_per_v") for v in (1e300, 1e308, MAX, 1e-300)},
    # 8: OverflowError / TypeError
    "400-digit integer": (lambda: set_core(k1_n_per_v=10**400 - 1), "k1_n_per_v"),
    "type: [burgers]": (lambda: (d := paper(), d["elements"][0].update(type=["burgers"]))[0], "type"),
    # more of the same kinds
    "negative 400-digit integer": (lambda: set_core(eta2_n_s_per_v=-(10**400)), "eta2_n_s_per_v"),
    "list as a number": (lambda: set_core(k2_n_per_v=[10.0]), "k2_n_per_v"),
    "mapping as a number": (lambda: set_core(eta1_n_s_per_v={"value": 4627.94}), "eta1_n_s_per_v"),
    "bool as a number": (lambda: set_core(k1_n_per_v=True), "k1_n_per_v"),
    "subnormal stiffness": (lambda: set_core(k2_n_per_v=5e-324), "k2_n_per_v"),
    "type: {burgers: 1}": (lambda: (d := paper(), d["elements"][0].update(type={"burgers": 1}))[0], "type"),
    "integer key in an element": (lambda: (d := paper(), d["elements"][0].update({7: 1.0}))[0], "keys must be strings"),
    "integer top-level key": (lambda: (d := paper(), d.update({3: 4}))[0], "keys must be strings"),
    "elements: 5": (lambda: (d := paper(), d.update(elements=5))[0], "elements"),
    "element is a list": (lambda: (d := paper(), d["elements"].append([1, 2]))[0], "element 2"),
    "quadratic 1e300": (lambda: with_element({"type": "nonlinear_gain", "quadratic_per_v": 1e300}), "quadratic_per_v"),
    "noise filter 1e-300 s": (lambda: with_element({"type": "sensor_lag", "tau_s": 0.03, "noise_filter_tau_s": 1e-300}),
                              "noise_filter_tau_s"),
    "thermal coefficient 1e300": (lambda: with_element({"type": "thermal_drift", "coefficient_v_per_c": 1e300,
                                                        "reference_c": 20.0}), "coefficient_v_per_c"),
    "reference -1e308 degC": (lambda: with_element({"type": "thermal_drift", "coefficient_v_per_c": 1e-3,
                                                    "reference_c": -1e308}), "reference_c"),
    "preisach 10**400 levels": (lambda: with_element({"type": "preisach", "u_min": 0.0, "u_max": 10.0, "n_levels": 10**400,
                                                      "offset": 0.0, "density": [1.0], "continuous": True}, core=False),
                                "n_levels"),
    "preisach density 10**400": (lambda: with_element({"type": "preisach", "u_min": 0.0, "u_max": 10.0, "n_levels": 1,
                                                       "offset": 0.0, "density": [10**400], "continuous": True}, core=False),
                                 "density"),
    "preisach u_max 1e308": (lambda: with_element({"type": "preisach", "u_min": 0.0, "u_max": 1e308, "n_levels": 1,
                                                   "offset": 0.0, "density": [1.0], "continuous": True}, core=False),
                             "u_max"),
    # inside every bound, but 40 gains of 1e9 overflow: the chain check names the element
    "40 gains of 1e9": (lambda: with_elements([{"type": "gain", "gain": 1e9}] * 40), "element 35 (gain)"),
    # inside every bound, but too far apart for float64 (relaxation no longer inverts the compliance)
    "burgers 1e12/1e-6/1e-6/1e-6": (lambda: set_core(k1_n_per_v=1e12, k2_n_per_v=1e-6, eta1_n_s_per_v=1e-6,
                                                     eta2_n_s_per_v=1e-6), "float64"),
}


@pytest.mark.parametrize("case", list(ISSUE_CASES))
def test_issue_cases_are_model_errors_naming_the_key(tmp_path, case):
    make, key = ISSUE_CASES[case]
    with pytest.raises(ModelError) as info:
        load_text(tmp_path, dump(make()))
    assert key in str(info.value)
    assert len(str(info.value)) < 1000  # a 400-digit number or a huge list is not echoed in full


@pytest.mark.parametrize("value", [1e300, 1e308, MAX, 1e-300, 0.5e-7, 2e13])
@pytest.mark.parametrize("key", CORE_KEYS)
def test_out_of_range_core_values_name_key_and_range(tmp_path, key, value):
    with pytest.raises(ModelError, match=rf"burgers: {key} = .* outside the allowed range \[1e-07, 1e\+13\]"):
        load_text(tmp_path, dump(set_core(**{key: value})))


YAML_CASES = {
    "flow, 5 000 deep": lambda: "provenance: " + "[" * 5000 + "]" * 5000 + "\n" + PAPER_TEXT,
    "flow, 100 000 deep": lambda: PAPER_TEXT + "provenance2: " + "[" * 100_000 + "]" * 100_000 + "\n",
    "flow mappings, 5 000 deep": lambda: "x: " + "{a: " * 5000 + "1" + "}" * 5000 + "\n",
    "block mappings, 900 deep": lambda: "".join("  " * i + f"k{i}:\n" for i in range(900)) + "  " * 900 + "x: 1\n",
    "block sequences, 1 200 deep": lambda: "".join(" " * i + "-\n" for i in range(1200)),
    "merge chain 3 000 long": lambda: "a0: &a0 {x: 1}\n" + "".join(f"a{i}: &a{i} {{<<: *a{i - 1}}}\n" for i in range(1, 3000)),
}


@pytest.mark.parametrize("case", list(YAML_CASES))
def test_deep_yaml_is_refused_before_recursion(tmp_path, case):
    with pytest.raises(ModelError, match=f"nested deeper than {MAX_DEPTH} levels"):
        load_text(tmp_path, YAML_CASES[case]())


def test_yaml_surprises_are_refused(tmp_path):
    laughs = "a: &a [x, x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"{chr(98 + i)}: &{chr(98 + i)} [" + ", ".join([f"*{chr(97 + i)}"] * 10) + "]\n" for i in range(9))
    cases = {
        "recursive YAML alias": "a: &a [*a]\n",
        "expands to more than": laughs,
        "duplicate key 'k2_n_per_v'": PAPER_TEXT.replace("k2_n_per_v: 10.0", "k2_n_per_v: 10.0\n  k2_n_per_v: 1.0e+300"),
        "not valid YAML": PAPER_TEXT.replace("k1_n_per_v: 4.8", "k1_n_per_v: !!python/object/apply:os.getcwd []"),
        "larger than": PAPER_TEXT + "# " + "x" * MAX_FILE_BYTES + "\n",
        "must hold a mapping": "- 1\n- 2\n",
    }
    for message, text in cases.items():
        with pytest.raises(ModelError, match=message):
            load_text(tmp_path, text)
    for scalar in ("9" * 5000, "2024-13-45", "!!timestamp 1", "!!float abc", "!!bool maybe", "!!int 1e3"):
        with pytest.raises(ModelError, match="not valid YAML: a value cannot be read"):
            load_text(tmp_path, PAPER_TEXT.replace("k1_n_per_v: 4.8", f"k1_n_per_v: {scalar}"))
    for scalar in ("0x" + "f" * 5000, "1:2:3:" + ":".join(["59"] * 3000), "2024-01-05", "!!binary AAAA", "!!set {a}"):
        with pytest.raises(ModelError, match="k1_n_per_v must be a number"):
            load_text(tmp_path, PAPER_TEXT.replace("k1_n_per_v: 4.8", f"k1_n_per_v: {scalar}"))
    with pytest.raises(ModelError, match="not UTF-8"):
        load_text(tmp_path, b"format: \xff\xfe\n")
    # the limits apply to what save_model writes back too, and a good file is untouched by them
    assert parse_model_yaml(PAPER_TEXT) == paper()


@pytest.mark.parametrize("char", ["\x00", "\x07", "\x1b", "\x7f", "\x80", "\ufffe"])
@pytest.mark.parametrize("where", ["value", "comment", "key"])
def test_non_printable_characters_are_refused_with_their_place(tmp_path, char, where):
    lines = PAPER_TEXT.splitlines(keepends=True)
    row = next(i for i, line in enumerate(lines) if "k1_n_per_v: 4.8" in line)
    line = lines[row]
    edited = {"value": line.replace("4.8", "4" + char + ".8"), "comment": line.rstrip("\n") + " # a" + char + "\n",
              "key": line.replace("k1_n", "k1" + char + "_n")}[where]
    column = edited.index(char) + 1
    lines[row] = edited
    text = "".join(lines)
    with pytest.raises(ModelError, match=rf"non-printable character U\+{ord(char):04X} at line {row + 1}, "
                                         rf"column {column} "):
        load_text(tmp_path, text)
    with pytest.raises(ModelError, match="non-printable"):
        parse_model_yaml(text)
    # what YAML allows stays allowed: tabs, CR LF line ends, a byte-order mark, non-ASCII text
    allowed = "\ufeff" + PAPER_TEXT.replace("\n", "\r\n").replace("provenance:", "provenance:\r\n  note: \"\t\u00b5m\"", 1)
    assert parse_model_yaml(allowed)["provenance"]["note"] == "\t\u00b5m"


# -- bounds: wide enough for every fit, and fitted extremes stay loadable -----------------------------

def test_bounds_hold_the_identification_search_boxes():
    import importlib

    # the search box of the core fits (log space); wherever it lives (it is moving to physics/fitting.py)
    boxes = []
    for module, name in (("polyforce_ros.physics.fitting", "LOG_BOUNDS"), ("polyforce_ros.physics.identification", "_LOG_BOUNDS"),
                         ("polyforce_ros.discrepancy.engine", "_LOG_BOUNDS"), ("polyforce_ros.discrepancy.engine", "LOG_BOUNDS")):
        try:
            boxes.append(getattr(importlib.import_module(module), name))
        except (ImportError, AttributeError):
            pass
    assert boxes
    for box in boxes:
        low, high = math.exp(box[0]), math.exp(box[1])
        for key, (lo, hi, _, _) in PARAMETER_BOUNDS.items():
            if key.endswith(("_n_per_v", "_n_s_per_v")):
                assert lo <= low and high <= hi, key
    # the effects a diagnosis fits (discrepancy/engine.py): tau 1e-4..10 s, q / coefficient / rate within +-1
    for key, (low, high) in {"tau_s": (1e-4, 10.0), "quadratic_per_v": (-1.0, 1.0), "coefficient_v_per_c": (-1.0, 1.0),
                             "rate_v_per_s": (-1.0, 1.0)}.items():
        assert PARAMETER_BOUNDS[key][0] <= low and high <= PARAMETER_BOUNDS[key][1], key
    every_key = {n for m in MODEL_TYPES.values() for n in m.parameter_names()}
    every_key |= {n for e in ELEMENT_TYPES.values() for n, _ in getattr(e, "PARAMS", ())}
    every_key |= {n for e in ELEMENT_TYPES.values() for n in getattr(e, "OPTIONAL", {})}
    every_key |= {"voltage_v", "u_min", "u_max", "offset", "density"}
    assert every_key <= set(PARAMETER_BOUNDS)  # every number a file can hold has a documented range


@pytest.mark.parametrize("core", [
    Burgers(4.8, 10.0, 1e12, 85.12),    # no flow in the data: eta1 at the top of the search box
    Burgers(4.8, 10.0, 4627.94, 1e-6),  # an instantaneous Kelvin element
    Burgers(1e12, 10.0, 4627.94, 85.12),  # no instantaneous compliance
    Burgers(4.8, 1e12, 4627.94, 85.12),
    *[MODEL_TYPES[k].from_vector(np.full(len(MODEL_TYPES[k].parameter_names()), v)) for k in MODEL_TYPES for v in (1e-6, 1e12)],
], ids=repr)
def test_fits_at_the_edge_of_the_search_box_still_save_and_load(tmp_path, core):
    path = save_model(tmp_path / "m.yaml", SensorModel(SensorChain.from_model(core), {"source": "edge"}))
    model = load_model(path)
    assert model.chain.viscoelastic == core
    assert_finite_model(model)


# -- hypothesis: mutate the shipped model and a model of every element type ----------------------------

def _example_chains():
    from polyforce_ros.sim.bench import hysteretic_identity

    effects = {
        "offset": OffsetElement(0.02),
        "gain": GainElement(gain=0.8),
        "nonlinear_gain": NonlinearGainElement(quadratic_per_v=0.08),
        "sensor_lag": SensorLagElement(tau_s=0.03, noise_filter_tau_s=0.005),
        "transport_delay": ELEMENT_TYPES["transport_delay"](delay_s=0.02),
        "resonance": ELEMENT_TYPES["resonance"](frequency_hz=25.0, damping_ratio=0.05),
        "thermal_sensitivity": ELEMENT_TYPES["thermal_sensitivity"](span_coefficient_per_c=0.003, reference_c=22.0,
                                                                    thermal_tau_s=30.0, span_curvature_per_c2=-2e-4),
        "thermal_drift": ThermalDriftElement(coefficient_v_per_c=2e-3, reference_c=22.0, curvature_v_per_c2=-1e-4),
        "offset_drift": OffsetDriftElement(rate_v_per_s=1e-4),
        "preisach": PreisachElement(hysteretic_identity(0.0, 10.0, 0.05, n_levels=4), continuous=True),
        "play_hysteresis": ELEMENT_TYPES["play_hysteresis"](1.0, [0.1, 0.5], [0.05, 0.02]),
        "friction": ELEMENT_TYPES["friction"](radius_n=0.1, coupling=0.9, deadband_n=0.01, inverse_share=0.5,
                                             band_log_slope_per_c=-0.05, reference_c=22.0, temperature_lag_s=30.0),
        "thermal_lag": ELEMENT_TYPES["thermal_lag"](coefficient_v_per_c=2e-3, reference_c=22.0, tau_s=60.0,
                                                    curvature_v_per_c2=2e-4),
        "exponential_drift": ELEMENT_TYPES["exponential_drift"](amplitude_v=0.02, tau_s=120.0),
        "polynomial_gain": ELEMENT_TYPES["polynomial_gain"](quadratic_per_v=0.05, cubic_per_v2=0.01, quartic_per_v3=0.0),
        "polynomial_drift": ELEMENT_TYPES["polynomial_drift"](rate_v_per_s=1e-4, curvature_v_per_s2=1e-7, cubic_v_per_s3=0.0),
        "spline_drift": ELEMENT_TYPES["spline_drift"](knots_s=[100.0, 200.0, 300.0], values_v=[0.01, -0.02, 0.005]),
        "step_drift": ELEMENT_TYPES["step_drift"](times_s=[50.0, 120.0], steps_v=[0.01, -0.02], recovery_tau_s=20.0,
                                                  recoveries_v=[0.005, 0.0]),
    }
    chains = {}
    for kind in ELEMENT_TYPES:
        if kind in MODEL_TYPES:
            n = len(MODEL_TYPES[kind].parameter_names())
            chains[kind] = SensorChain.from_model(MODEL_TYPES[kind].from_vector(1.0 + 3.0 * np.arange(n)), offset_v=0.02)
        elif kind == "preisach":
            chains[kind] = SensorChain([effects[kind], ViscoelasticElement(PAPER_BURGERS), OffsetElement(0.0)])
        elif kind == "thermo_rheological":  # the core on the reduced time
            chains[kind] = SensorChain([ELEMENT_TYPES[kind](ViscoelasticElement(PAPER_BURGERS), 0.05, 22.0, 30.0, 60.0),
                                        OffsetElement(0.02)])
        elif kind == "power_flow":  # a zener core with a power-law dashpot beside it, its fluidity changing as it flows
            chains[kind] = SensorChain([ELEMENT_TYPES[kind](ViscoelasticElement(Zener(3.0, 20.0, 200.0)), 0.01, 2.5, 9.0,
                                                            flow_volume_scale_n_s=400.0,
                                                            flow_volume_rates_v_per_n_s=[2e-4, -1e-4, 5e-5]),
                                        OffsetElement(0.02)])
        elif kind == "knee_kelvin":  # a zener core beside a Kelvin unit loaded above a knee
            chains[kind] = SensorChain([ELEMENT_TYPES[kind](ViscoelasticElement(Zener(3.0, 20.0, 200.0)), [2.0, 5.0],
                                                            [0.05, -0.1], 8.0),
                                        OffsetElement(0.02)])
        elif kind == "bridge_hysteresis":  # the core and its plays in one element
            chains[kind] = SensorChain([ELEMENT_TYPES[kind](ViscoelasticElement(PAPER_BURGERS), [0.1, 0.5], [0.01, 0.005],
                                                            history_max_n=2.0, scaled_radii=[0.05, 0.2],
                                                            scaled_weights_v_per_n=[0.01, 0.01], floor_n=0.2),
                                        OffsetElement(0.02)])
        else:
            chains[kind] = SensorChain([ViscoelasticElement(PAPER_BURGERS), effects[kind]])
    return chains


BASES = {kind: dump(model_to_mapping(SensorModel(chain, {"source": "fuzz", "fit": {"r2": 0.9}})))
         for kind, chain in _example_chains().items()}


def test_every_element_type_has_a_fuzz_base_that_loads():
    assert set(BASES) == set(ELEMENT_TYPES)
    for text in BASES.values():
        assert_finite_model(model_from_mapping(parse_model_yaml(text)))


def _nested(depth):
    value = 1.0
    for i in range(depth):
        value = [value] if i % 2 else {"n": value}
    return value


SPECIAL = [0, 0.0, -0.0, 5e-324, 2.2250738585072014e-308, 1e-300, 1e-12, 1e-7, 1e6, 1e13, 1e300, 1e308, MAX, -MAX,
           -1.0, float("nan"), float("inf"), -float("inf"), 2**53 + 1, 10**400, -(10**400), True, False, None,
           "", "4.8", "burgers", [], [1.0], [[1.0]], {}, {"a": 1.0}]
WEIRD = st.one_of(
    st.sampled_from(SPECIAL),
    st.floats(),  # every float: subnormals, huge, nan, inf
    st.floats(min_value=-1e4, max_value=1e4),
    st.integers(min_value=-(10**400), max_value=10**400),
    st.text(max_size=12),
    st.lists(st.floats(), max_size=4),
    st.dictionaries(st.text(max_size=6), st.floats(), max_size=3),
    st.integers(1, 60).map(_nested),  # deep nesting inside a value (limit 32)
).map(copy.deepcopy)  # SPECIAL's lists and dicts are mutated by later steps


def _paths(obj, prefix=()):
    """Every position in a parsed document: (path, value)."""
    out = [(prefix, obj)]
    if isinstance(obj, dict):
        for k, v in obj.items():
            out += _paths(v, prefix + (k,))
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            out += _paths(v, prefix + (i,))
    return out


def _mutate(data, draw):
    positions = [p for p, _ in _paths(data) if p]
    numbers = [p for p, v in _paths(data) if p and isinstance(v, (int, float)) and not isinstance(v, bool)]
    path = draw(st.sampled_from(numbers if numbers and draw(st.integers(0, 9)) < 7 else positions))
    parent = data
    for step in path[:-1]:
        parent = parent[step]
    action = draw(st.sampled_from(["replace", "replace", "replace", "delete", "add", "rename"]))
    if action == "replace":
        parent[path[-1]] = draw(WEIRD)
    elif action == "delete":
        del parent[path[-1]]
    elif action == "add" and isinstance(parent, dict):
        parent[draw(st.one_of(st.text(max_size=8), st.integers(), st.none()))] = draw(WEIRD)
    elif action == "add":
        parent.insert(path[-1], draw(WEIRD))
    elif isinstance(parent, dict):  # rename a key, possibly to a non-string
        parent[draw(st.one_of(st.text(max_size=8), st.integers(), st.floats(), st.none()))] = parent.pop(path[-1])


def _check_mutant(text, tmp_path):
    try:
        model = load_text(tmp_path, text, "mutant.yaml")
    except ModelError as exc:
        assert str(exc) and len(str(exc)) < 2000
        reason = str(exc).split(": ", 1)[1]  # after the path
        if "float64" in reason or "test record" in reason:
            event("refused: numerics (" + reason.split(":")[0] + ")")
        else:
            event("refused: " + (reason.split(" = ")[0] if " = " in reason else " ".join(reason.split()[:4])))
        return False
    event("loaded")
    assert_finite_model(model)
    return True


@fuzz_settings(300)
@given(st.data())
def test_mutated_element_models_load_finite_or_refuse(tmp_path, data):
    kind = data.draw(st.sampled_from(sorted(BASES)))
    doc = yaml.safe_load(BASES[kind])
    for _ in range(data.draw(st.integers(1, 3))):
        _mutate(doc, data.draw)
    _check_mutant(dump(doc), tmp_path)


@fuzz_settings(150)
@given(st.data())
def test_mutated_paper_model_loads_finite_or_refuses(tmp_path, data):
    doc = paper()
    for _ in range(data.draw(st.integers(1, 3))):
        _mutate(doc, data.draw)
    _check_mutant(dump(doc), tmp_path)


def _around_bounds(key):
    """Numbers for ``key``: mostly log-uniform over its range widened 100x each way, sometimes any float."""
    low, high = PARAMETER_BOUNDS[key][:2]
    if low > 0:
        near = st.floats(math.log10(low) - 2, math.log10(high) + 2).map(lambda e: 10.0 ** e)
    else:
        near = st.builds(lambda e, sign: sign * 10.0 ** e, st.floats(-12.0, math.log10(high) + 2),
                         st.sampled_from([1.0, -1.0]))
    anywhere = st.builds(lambda e, sign: sign * 10.0 ** e, st.floats(-320.0, 308.0), st.sampled_from([1.0, 1.0, -1.0]))
    return st.one_of(near, near, near, anywhere, st.sampled_from([0.0, low, high, float("nan"), float("inf")]))


@fuzz_settings(200)
@given(st.sampled_from(sorted(BASES)), st.data())
def test_random_numbers_in_every_parameter_load_finite_or_refuse(tmp_path, kind, data):
    """Every number of a model replaced at once, around its documented range and anywhere in float64."""
    doc = yaml.safe_load(BASES[kind])
    for element in doc["elements"]:
        for key, value in list(element.items()):
            if isinstance(value, list) and value and all(isinstance(v, float) for v in value):
                element[key] = [data.draw(_around_bounds(key)) for _ in value]
            elif isinstance(value, float):
                element[key] = data.draw(_around_bounds(key))
    _check_mutant(dump(doc), tmp_path)


YAML_SCALARS = ["9" * 5000, "0x" + "f" * 400, "-" + "9" * 400, "1:2:3:4", "0o777", "0b101", "1_000", "2024-13-45",
                "2024-01-05", "!!timestamp 1", "!!float abc", "!!binary AAAA", "!!set {a}", "!!omap [a: 1]",
                "!!python/name:os.system", "*undefined", "&a [*a]", "{", "[", "'open", "~", ".nan", "-.inf", ".inf",
                "[4.8]", "{v: 4.8}", "- 4.8", "4.8e400", "-4.8e-400", "1e-7", "1e13", "0", "-0.0", "true", "''",
                "[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]", "!!str 4.8", "!!int 5",
                "!!float 1e400", "? [a]\n  : 1", "|\n    4.8", "4.8 # comment", "\"\\x00\""]


@fuzz_settings(150)
@given(st.sampled_from(sorted(BASES)), st.data())
def test_yaml_text_mutations_load_finite_or_refuse(tmp_path, kind, data):
    """The value text of a line replaced by raw YAML: tags, anchors, dates, huge integers, broken syntax."""
    lines = BASES[kind].splitlines()
    for _ in range(data.draw(st.integers(1, 2))):
        valued = [i for i, line in enumerate(lines) if ": " in line]
        i = data.draw(st.sampled_from(valued))
        key = lines[i].split(": ", 1)[0]
        lines[i] = f"{key}: {data.draw(st.sampled_from(YAML_SCALARS))}"
    _check_mutant("\n".join(lines) + "\n", tmp_path)


def test_validate_chain_numerics_names_the_element(tmp_path):
    chain = SensorChain([ViscoelasticElement(PAPER_BURGERS), *[GainElement(gain=1e9)] * 40, OffsetElement(0.0)])
    with pytest.raises(ModelError, match=r"element 35 \(gain\).*forward run"):
        validate_chain_numerics(chain)
    validate_chain_numerics(load_model(default_model_path()).chain)
    with pytest.raises(ModelError, match="element 35"):  # save_model refuses to write what could not load
        save_model(tmp_path / "m.yaml", SensorModel(chain, {}))
    assert not (tmp_path / "m.yaml").exists()


# -- the CLI: exit 2, the reason, no traceback ----------------------------------------------------------

def _polyforce():
    exe = Path(sys.executable).parent / "polyforce"
    return [str(exe)] if exe.exists() else [sys.executable, "-m", "polyforce_ros.cli"]


CLI_CASES = {
    "k2_n_per_v 1e300 (was an IndexError)": (lambda: dump(set_core(k2_n_per_v=1e300)), "k2_n_per_v"),
    "100 000 deep (was a RecursionError)": (lambda: PAPER_TEXT + "x: " + "[" * 100_000 + "]" * 100_000 + "\n",
                                            "nested deeper"),
    "type: [burgers] (was a TypeError)": (lambda: dump((d := paper(), d["elements"][0].update(type=["burgers"]))[0]),
                                          "type must be a string"),
    "a NUL byte in a value": (lambda: PAPER_TEXT.replace("k1_n_per_v: 4.8", "k1_n_per_v: 4\x00.8"),
                              "non-printable character U+0000"),
}


@pytest.mark.process  # starts the CLI
@pytest.mark.parametrize("case", list(CLI_CASES))
def test_cli_compensate_refuses_bad_model_with_exit_2(tmp_path, case):
    make, message = CLI_CASES[case]
    bad = tmp_path / "bad.yaml"
    bad.write_text(make())
    proc = subprocess.run([*_polyforce(), "compensate", str(REPO / "bags" / "step_5n.mcap"), str(tmp_path / "out.mcap"),
                           "--model", str(bad)], cwd=REPO, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr and message in proc.stderr, proc.stderr
    assert len(proc.stderr.strip().splitlines()) <= 3, proc.stderr
    assert not (tmp_path / "out.mcap").exists()
