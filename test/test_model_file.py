"""The YAML model file: shipped default, round trip, atomic write, validation messages."""
import os

import numpy as np
import pytest
import yaml

from polyforce_ros.model_file import SensorModel, default_model_path, load_model, model_to_mapping, save_model
from polyforce_ros.physics.chain import ModelError, SensorChain
from polyforce_ros.physics.viscoelastic import MODEL_TYPES, PAPER_BURGERS, Zener


def test_shipped_default_is_the_paper_model():
    model = load_model(default_model_path())
    assert model.chain.viscoelastic == PAPER_BURGERS
    assert model.chain.offset.voltage_v == 0.0


def test_round_trip_and_previous_file_kept(tmp_path):
    path = tmp_path / "model.yaml"
    first = load_model(default_model_path())
    save_model(path, first)
    assert not (tmp_path / "model.yaml.prev").exists()
    second = load_model(default_model_path())
    second.chain = SensorChain.from_model(Zener(5.0, 9.0, 80.0), offset_v=0.01)
    second.provenance = {"source": "test"}
    save_model(path, second)
    assert load_model(path).chain.viscoelastic == Zener(5.0, 9.0, 80.0)
    assert load_model(tmp_path / "model.yaml.prev").chain.viscoelastic == PAPER_BURGERS
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []  # no temp files left


def write(tmp_path, mutate):
    data = model_to_mapping(load_model(default_model_path()))
    mutate(data)
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


@pytest.mark.parametrize(
    "mutate, message",
    [
        (lambda d: d["elements"][0].update(k1_n_per_v=0.0), "k1_n_per_v must be > 0"),
        (lambda d: d["elements"][0].update(k2_n_per_v=-3.0), "k2_n_per_v must be > 0"),
        (lambda d: d["elements"][0].pop("eta1_n_s_per_v"), "missing keys"),
        (lambda d: d["elements"][0].update(colour="red"), "unknown keys"),
        (lambda d: d["elements"][0].update(k1_n_per_v="stiff"), "must be a number"),
        (lambda d: d["elements"][0].update(type="spring"), "unknown type"),
        (lambda d: d.update(format="other/9"), "format must be"),
        (lambda d: d.update(extra=1), "unknown top-level keys"),
        (lambda d: d["elements"][1].update(voltage_v=float("nan")), "must be finite"),
    ],
)
def test_bad_model_files_give_clear_errors(tmp_path, mutate, message):
    with pytest.raises(ModelError, match=message):
        load_model(write(tmp_path, mutate))


def test_unreadable_and_invalid_yaml(tmp_path):
    with pytest.raises(ModelError, match="cannot read"):
        load_model(tmp_path / "missing.yaml")
    bad = tmp_path / "broken.yaml"
    bad.write_text("elements: [\n")
    with pytest.raises(ModelError, match="not valid YAML"):
        load_model(bad)


def test_failed_write_keeps_the_good_file(tmp_path, monkeypatch):
    path = tmp_path / "model.yaml"
    save_model(path, load_model(default_model_path()))
    good = path.read_text()

    def boom(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(os, "fsync", boom)
    with pytest.raises(OSError):
        save_model(path, load_model(default_model_path()))
    assert path.read_text() == good
    assert sorted(p.name for p in tmp_path.iterdir()) == ["model.yaml"]


@pytest.mark.parametrize("kind", sorted(MODEL_TYPES))
def test_every_core_type_round_trips_through_yaml(tmp_path, kind):
    """Every core a diagnosis may save (incl. the two-Kelvin types) loads back equal."""
    model_type = MODEL_TYPES[kind]
    core = model_type.from_vector(1.0 + 3.0 * np.arange(len(model_type.parameter_names())))
    path = tmp_path / f"{kind}.yaml"
    save_model(path, SensorModel(SensorChain.from_model(core, offset_v=0.02), {"source": "test"}))
    loaded = load_model(path).chain
    assert loaded.viscoelastic == core and loaded.offset.voltage_v == 0.02
