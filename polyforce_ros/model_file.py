"""The YAML model file: one schema for every sensor model, validated on load.

    format: polyforce_model/1
    elements:                 # force -> voltage order
      - type: burgers
        k1_n_per_v: 4.8
        k2_n_per_v: 10.0
        eta1_n_s_per_v: 4627.94
        eta2_n_s_per_v: 85.12
      - type: offset
        voltage_v: 0.0
    provenance:               # free-form: source, fit quality, date
      source: seed 000, eq. 5

Writes are atomic (temporary file, fsync, rename) and keep the file they
replace as ``<name>.prev``, so a crash while writing never loses a good model.
"""
from __future__ import annotations

import datetime as _dt
import os
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from .physics.chain import ModelError, SensorChain

FORMAT = "polyforce_model/1"
_TOP_KEYS = {"format", "elements", "provenance"}


@dataclass
class SensorModel:
    """A chain plus where it came from."""

    chain: SensorChain
    provenance: dict = field(default_factory=dict)


def model_from_mapping(data) -> SensorModel:
    if not isinstance(data, dict):
        raise ModelError("model file must hold a mapping")
    unknown = sorted(set(data) - _TOP_KEYS)
    if unknown:
        raise ModelError(f"unknown top-level keys {unknown} (expected {sorted(_TOP_KEYS)})")
    if data.get("format") != FORMAT:
        raise ModelError(f"format must be {FORMAT!r}, got {data.get('format')!r}")
    provenance = data.get("provenance") or {}
    if not isinstance(provenance, dict):
        raise ModelError("provenance must be a mapping")
    return SensorModel(SensorChain.from_dict(data), provenance)


def load_model(path) -> SensorModel:
    """Read and validate a model file; raises ModelError with the reason."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise ModelError(f"cannot read model file {path}: {exc.strerror}") from exc
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise ModelError(f"{path}: not valid YAML: {exc}") from exc
    try:
        return model_from_mapping(data)
    except ModelError as exc:
        raise ModelError(f"{path}: {exc}") from exc


def model_to_mapping(model: SensorModel) -> dict:
    return {"format": FORMAT, **model.chain.to_dict(), "provenance": dict(model.provenance)}


def save_model(path, model: SensorModel, keep_previous=True) -> Path:
    """Write atomically; the replaced file (if any) is kept as ``<path>.prev``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = "# polyforce_ros sensor model (force -> voltage chain)\n" + yaml.safe_dump(
        model_to_mapping(model), sort_keys=False
    )
    model_from_mapping(yaml.safe_load(text))  # never write what we could not load
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        if keep_previous and path.exists():
            # Copy, not move: ``path`` must hold a complete model at every instant.
            prev_tmp = f"{tmp}.prev"
            shutil.copy2(path, prev_tmp)
            os.replace(prev_tmp, path.with_name(path.name + ".prev"))
        os.replace(tmp, path)
        dir_fd = os.open(path.parent, os.O_RDONLY)
        try:
            os.fsync(dir_fd)
        finally:
            os.close(dir_fd)
    except BaseException:
        for leftover in (tmp, f"{tmp}.prev"):
            if os.path.exists(leftover):
                os.unlink(leftover)
        raise
    return path


def now_iso() -> str:
    return _dt.datetime.now(_dt.timezone.utc).replace(microsecond=0).isoformat()


def default_model_path() -> Path:
    """The shipped model (seed 000 eq. 5): the package share dir, else the source tree."""
    try:
        from ament_index_python.packages import get_package_share_directory

        share = Path(get_package_share_directory("polyforce_ros")) / "config" / "paper_burgers.yaml"
        if share.is_file():
            return share
    except Exception:  # noqa: BLE001 - no ament index in a plain venv: fall through
        pass
    return Path(__file__).resolve().parents[1] / "config" / "paper_burgers.yaml"
