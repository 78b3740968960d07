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

Loading never raises anything but :class:`ModelError` (with the reason) and
never returns a model that turns a finite record into inf or NaN:

* the file is at most ``MAX_FILE_BYTES``; its YAML is composed by a loader that
  refuses nesting deeper than ``MAX_DEPTH`` (counted while composing, before
  any recursion gets deep), recursive aliases, alias expansions beyond
  ``MAX_NODES`` nodes and duplicate keys;
* every type mismatch (a list where a number or a type name belongs, keys
  that are not strings, integers too large for a float) is named;
* every parameter is checked against its documented range
  (``physics.chain.PARAMETER_BOUNDS``), a viscoelastic core also by its
  derived relaxation modulus;
* :func:`validate_chain_numerics` runs the whole chain forward, backward and
  streaming on short test records (10 kHz to 0.1 Hz, and 24 hours) and names
  the first element whose output is not finite.
"""
from __future__ import annotations

import datetime as _dt
import os
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Mapping, NoReturn, Optional

import numpy as np
import numpy.typing as npt
import yaml

from .physics.chain import (ELEMENT_TYPES, Element, ElementStream, ForwardElement, ModelError, SensorChain, short_repr,
                            smoke_records)

__all__ = ["FORMAT", "MAX_FILE_BYTES", "MAX_DEPTH", "MAX_NODES", "parse_model_yaml", "SensorModel",
    "model_from_mapping", "validate_chain_numerics", "load_model", "model_to_mapping", "save_model", "now_iso",
    "default_model_path"]

FORMAT = "polyforce_model/1"
_TOP_KEYS = {"format", "elements", "provenance"}
#: A model file is a few hundred bytes (a Preisach density of 200 levels ~ 400 kB).
MAX_FILE_BYTES = 1_000_000
#: Nesting of YAML collections (a model needs 4: file, elements, element, density).
MAX_DEPTH = 32
#: Nodes after expanding aliases (a 1 MB file without aliases has fewer).
MAX_NODES = 1_000_000
_MERGE_TAG = "tag:yaml.org,2002:merge"


class _ModelLoader(yaml.SafeLoader):
    """SafeLoader that refuses, while composing, what would surprise later code.

    ``compose_node`` is where PyYAML recurses; counting there stops a deep file
    at ``MAX_DEPTH`` before Python's recursion limit is near (the scanner and
    parser are iterative and lazy, so the rest of the file is never read). The
    same count follows aliases: an alias adds the size and depth of its anchor,
    so a "billion laughs" file or a long chain of merges is refused too, as is
    an alias inside its own anchor (a recursive structure).
    """

    def __init__(self, stream: str) -> None:
        super().__init__(stream)
        self._open: list[list[int]] = []  # per open node: [expanded size of its children, max expanded depth of its children]
        self._open_anchors: set[str] = set()
        self._anchor_size: dict[str, tuple[int, int]] = {}  # anchor -> (expanded size, expanded depth)

    def _refuse(self, message: str, event: object) -> NoReturn:
        mark = getattr(event, "start_mark", None)
        where = f" (line {mark.line + 1}, column {mark.column + 1})" if mark is not None else ""
        raise ModelError(f"{message}{where}")

    def _account(self, size: int, depth: int, event: object) -> None:
        if self._open:
            self._open[-1][0] += size
            self._open[-1][1] = max(self._open[-1][1], depth)
        if len(self._open) + depth > MAX_DEPTH:
            self._refuse(f"YAML nested deeper than {MAX_DEPTH} levels", event)
        if size > MAX_NODES or (self._open and self._open[-1][0] > MAX_NODES):
            self._refuse(f"YAML expands to more than {MAX_NODES} nodes (aliases)", event)

    def compose_node(self, parent: Optional[yaml.Node], index: int) -> Optional[yaml.Node]:
        event = self.peek_event()  # type: ignore[no-untyped-call]  # unannotated in types-PyYAML
        if isinstance(event, yaml.AliasEvent):
            if event.anchor in self._open_anchors:
                self._refuse(f"recursive YAML alias *{event.anchor}", event)
            node = super().compose_node(parent, index)
            size, depth = self._anchor_size.get(event.anchor, (1, 1))
            self._account(size, depth, event)
            return node
        if len(self._open) + 1 > MAX_DEPTH:
            self._refuse(f"YAML nested deeper than {MAX_DEPTH} levels", event)
        anchor = getattr(event, "anchor", None)
        if anchor is not None:
            self._open_anchors.add(anchor)
        self._open.append([0, 0])
        try:
            node = super().compose_node(parent, index)
        finally:
            children_size, children_depth = self._open.pop()
            if anchor is not None:
                self._open_anchors.discard(anchor)
        size, depth = 1 + children_size, 1 + children_depth
        if anchor is not None:
            self._anchor_size[anchor] = (size, depth)
        self._account(size, depth, event)
        return node

    def compose_mapping_node(self, anchor: dict[Any, yaml.Node]) -> yaml.MappingNode:  # anchor: as types-PyYAML has it
        node = super().compose_mapping_node(anchor)
        seen: set[tuple[str, str]] = set()
        for key, _ in node.value:
            if isinstance(key, yaml.ScalarNode) and key.tag != _MERGE_TAG:
                if (key.tag, key.value) in seen:
                    self._refuse(f"duplicate key {short_repr(key.value)}", key)
                seen.add((key.tag, key.value))
        return node


def _clip(text: object, limit: int) -> str:
    """``text`` on one line, cut to ``limit`` characters."""
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def parse_model_yaml(text: str) -> object:
    """The YAML of a model file as Python data, within the limits above; ModelError otherwise."""
    if len(text) > MAX_FILE_BYTES:
        raise ModelError(f"larger than {MAX_FILE_BYTES} bytes; a model file is a few hundred")
    bad = yaml.reader.Reader.NON_PRINTABLE.search(text)  # YAML's own rule, which its reader applies on construction
    if bad:
        line = text.count("\n", 0, bad.start()) + 1
        column = bad.start() - (text.rfind("\n", 0, bad.start()) + 1) + 1
        raise ModelError(f"not valid YAML: non-printable character U+{ord(bad.group()):04X} at line {line}, "
                         f"column {column} (a model file is plain text)")
    loader = _ModelLoader(text)
    try:
        return loader.get_single_data()
    except ModelError:  # a limit above
        raise
    except yaml.YAMLError as exc:
        raise ModelError(f"not valid YAML: {_clip(str(exc), 400)}") from None
    except (ArithmeticError, LookupError, TypeError, ValueError, AttributeError) as exc:
        # a scalar its tag cannot hold: an integer beyond Python's 4300-digit limit, a date like
        # 2024-13-45, "!!timestamp 1" (PyYAML's constructors raise these, not YAMLError)
        raise ModelError(f"not valid YAML: a value cannot be read ({type(exc).__name__}: {_clip(str(exc), 200)})") from None
    except RecursionError:  # not reached within MAX_DEPTH; kept as a last line of defence
        raise ModelError(f"YAML nested too deeply (limit {MAX_DEPTH})") from None
    finally:
        loader.dispose()  # type: ignore[no-untyped-call]  # unannotated in types-PyYAML


@dataclass
class SensorModel:
    """A chain plus where it came from."""

    chain: SensorChain
    provenance: dict[str, Any] = field(default_factory=dict)


def _check_string_keys(where: str, mapping: Iterable[object]) -> None:
    bad = [k for k in mapping if not isinstance(k, str)]
    if bad:
        raise ModelError(f"{where}: keys must be strings, got {short_repr(bad)}")


def model_from_mapping(data: object) -> SensorModel:
    """Validate parsed model data (structure, types, parameter ranges, numerics) and build the model."""
    if not isinstance(data, dict):
        raise ModelError(f"model file must hold a mapping, got {type(data).__name__}")
    _check_string_keys("model file", data)
    unknown = sorted(set(data) - _TOP_KEYS)
    if unknown:
        raise ModelError(f"unknown top-level keys {short_repr(unknown, 200)} (expected {sorted(_TOP_KEYS)})")
    if data.get("format") != FORMAT:
        raise ModelError(f"format must be {FORMAT!r}, got {short_repr(data.get('format'))}")
    provenance = data.get("provenance") or {}
    if not isinstance(provenance, dict):
        raise ModelError("provenance must be a mapping")
    elements = data.get("elements")
    if not isinstance(elements, list):
        raise ModelError(f"model must hold a list under 'elements', got {short_repr(elements)}")
    for i, item in enumerate(elements):
        if not isinstance(item, dict) or "type" not in item:
            raise ModelError(f"element {i}: must be a mapping with a 'type', got {short_repr(item)}")
        _check_string_keys(f"element {i}", item)
        kind = item["type"]
        if not isinstance(kind, str):
            raise ModelError(f"element {i}: type must be a string, one of {sorted(ELEMENT_TYPES)}; got {short_repr(kind)}")
        if kind not in ELEMENT_TYPES:
            raise ModelError(f"element {i}: unknown type {short_repr(kind)}; known: {sorted(ELEMENT_TYPES)}")
    try:
        chain = SensorChain.from_dict(data)
    except ModelError:
        raise
    except (ArithmeticError, LookupError, TypeError, ValueError, AttributeError, RecursionError) as exc:
        # Every case above has its own message; this is the net under them.
        raise ModelError(f"elements cannot be built ({type(exc).__name__}: {_clip(str(exc), 200)})") from None
    validate_chain_numerics(chain)
    return SensorModel(chain, provenance)


_RUN_ERRORS = (ArithmeticError, LookupError, TypeError, ValueError, AttributeError)


def _finite(x: Optional[npt.ArrayLike]) -> bool:
    return x is not None and bool(np.all(np.isfinite(np.asarray(x, dtype=float))))


def _first_bad_element(chain: SensorChain, stage: str, t: npt.NDArray[np.floating[Any]], x: npt.NDArray[np.float64],
                       aux: Mapping[str, npt.NDArray[np.float64]]
                       ) -> Optional[tuple[int, ForwardElement, Optional[Exception]]]:
    """(index, element, exception or None) of the first element whose ``stage`` output is not finite."""
    if stage == "forward":
        for i, element in enumerate(chain.elements):
            try:
                x = element.forward(t, x, aux, element.forward_state())
            except _RUN_ERRORS as exc:
                return i, element, exc
            if not _finite(x):
                return i, element, None
        return None
    order = list(reversed(list(enumerate(chain.invertible_elements))))
    if stage == "backward":
        for i, element in order:
            try:
                x = element.backward(t, x, aux)
            except _RUN_ERRORS as exc:
                return i, element, exc
            if not _finite(x):
                return i, element, None
        return None
    streams: list[tuple[int, Element, ElementStream]] = []
    for i, element in order:
        try:
            streams.append((i, element, element.streaming()))
        except _RUN_ERRORS as exc:
            return i, element, exc
    for ti, xi, ci in zip(t, x, aux["temperature_c"]):
        value = float(xi)
        for i, element, stream in streams:
            try:
                stepped = stream.step(float(ti), value, {"temperature_c": float(ci)})
            except _RUN_ERRORS as exc:
                return i, element, exc
            if stepped is None or not _finite(stepped):
                return i, element, None
            value = stepped
    return None


def validate_chain_numerics(chain: SensorChain) -> None:
    """Refuse a chain that turns a finite record into inf or NaN (or raises on one).

    Runs ``chain.forward`` on test force records (5 +- 4 N with temperature
    25 +- 10 degC; uniform at 10 kHz .. 0.1 Hz and one irregular record over 24
    hours), ``chain.backward`` on that voltage and on a plain 0.5 +- 0.4 V record,
    and ``chain.streaming()`` sample by sample on the 1 kHz and 24-hour
    records. On a failure the stage is rerun element by element and the first
    element whose output is not finite is named in the ModelError.
    """
    for t, force, aux, label in smoke_records():
        plain = 0.5 + 0.4 * np.cos(np.linspace(0.0, 5.0, t.size))
        stage, x = "forward", force
        error: Optional[Exception] = None
        with np.errstate(all="ignore"):
            try:
                volts = chain.forward(t, force, aux)
                ok = _finite(volts)
                if ok:
                    stage = "backward"  # stage and x name what failed, for _first_bad_element below
                    for x in (volts, plain):
                        if not _finite(chain.backward(t, x, aux)):
                            ok = False
                            break
                if ok and label.startswith(("irregular", "uniform, step 0.001 ")):
                    stage, x = "streaming", volts
                    stream = chain.streaming()
                    out = [stream.step(float(ti), float(vi), {"temperature_c": float(ci)})
                           for ti, vi, ci in zip(t, volts, aux["temperature_c"])]
                    ok = all(_finite(o) for o in out)
            except _RUN_ERRORS as exc:
                ok, error = False, exc
            if ok:
                continue
            try:
                culprit = _first_bad_element(chain, stage, t, x, aux)
            except Exception:  # noqa: BLE001 - only the message depends on it
                culprit = None
        if culprit is not None:
            i, element, error = culprit[0], culprit[1], culprit[2] or error
            try:
                described = short_repr(element.to_dict(), 300) if isinstance(element, Element) else type(element).__name__
            except Exception:  # noqa: BLE001
                described = type(element).__name__
            who = f"element {i} ({getattr(element, 'kind', '?')}): {described}"
        else:
            who = "the chain"
        what = f"raises {type(error).__name__}: {_clip(str(error), 200)}" if error is not None else "gives non-finite output"
        raise ModelError(f"{who} {what} in the {stage} run on a test record ({label}); "
                         f"its parameters are numerically unusable together")


def load_model(path: str | os.PathLike[str]) -> SensorModel:
    """Read and validate a model file; raises ModelError with the reason (and nothing else)."""
    path = Path(path)
    try:
        with open(path, "rb") as fh:
            raw = fh.read(MAX_FILE_BYTES + 1)
    except OSError as exc:
        raise ModelError(f"cannot read model file {path}: {exc.strerror}") from exc
    if len(raw) > MAX_FILE_BYTES:
        raise ModelError(f"{path}: larger than {MAX_FILE_BYTES} bytes; a model file is a few hundred")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ModelError(f"{path}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    try:
        data = parse_model_yaml(text)
    except ModelError as exc:
        raise ModelError(f"{path}: {exc}") from None
    try:
        return model_from_mapping(data)
    except ModelError as exc:
        raise ModelError(f"{path}: {exc}") from exc


def model_to_mapping(model: SensorModel) -> dict[str, Any]:
    """The YAML mapping of a model file (format, elements, provenance)."""
    return {"format": FORMAT, **model.chain.to_dict(), "provenance": dict(model.provenance)}


def save_model(path: str | os.PathLike[str], model: SensorModel, keep_previous: bool = True) -> Path:
    """Write atomically; the replaced file (if any) is kept as ``<path>.prev``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = "# polyforce_ros sensor model (force -> voltage chain)\n" + yaml.safe_dump(
        model_to_mapping(model), sort_keys=False
    )
    model_from_mapping(parse_model_yaml(text))  # never write what we could not load
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
    """Current UTC time, ISO 8601 to the second (for provenance)."""
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
