"""A sensor as a chain of elements between applied force and measured voltage.

    force -> [viscoelastic core] -> ... -> [offset] -> voltage

Each element runs forward (simulate), backward in batch (compensate an array)
and backward per sample (``streaming()``, O(1) state), and describes itself as
a plain mapping for the YAML model file. The chain runs its elements forward in
order and backward in reverse order. Elements receive ``aux``, a mapping of
auxiliary signals sampled with the main one (e.g. ``temperature_c``), which
elements that need it (thermal terms) read and others ignore.
"""
from __future__ import annotations

import math

import numpy as np

from .viscoelastic import MODEL_TYPES, StreamingCompensator, ViscoelasticModel, compensate, simulate_deformation


class ModelError(ValueError):
    """A model description that cannot be used (bad type, keys or values)."""


def _number(kind, key, value, positive):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ModelError(f"{kind}: {key} must be a number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise ModelError(f"{kind}: {key} must be finite, got {value!r}")
    if positive and value <= 0.0:
        raise ModelError(f"{kind}: {key} must be > 0, got {value!r}")
    return value


def _check_keys(kind, mapping, expected):
    keys = set(mapping) - {"type"}
    missing, unknown = sorted(set(expected) - keys), sorted(keys - set(expected))
    if missing:
        raise ModelError(f"{kind}: missing keys {missing}")
    if unknown:
        raise ModelError(f"{kind}: unknown keys {unknown} (expected {sorted(expected)})")


class ViscoelasticElement:
    """The viscoelastic core: force (N) <-> deformation read as volts (seed 000)."""

    def __init__(self, model: ViscoelasticModel):
        self.model = model
        self.kind = model.kind

    def forward(self, t_s, force_n, aux=None):
        return simulate_deformation(self.model, t_s, force_n)

    def backward(self, t_s, deformation_v, aux=None):
        return compensate(self.model, t_s, deformation_v)

    def streaming(self):
        return _ViscoelasticStream(self.model)

    def to_dict(self):
        return {"type": self.kind, **self.model.as_dict()}

    @classmethod
    def from_dict(cls, d):
        model_type = MODEL_TYPES[d["type"]]
        names = model_type.parameter_names()
        _check_keys(d["type"], d, names)
        values = [_number(d["type"], n, d[n], positive=True) for n in names]
        return cls(model_type(*values))


class _ViscoelasticStream:
    def __init__(self, model):
        self._comp = StreamingCompensator(model)

    def reset(self):
        self._comp.reset()

    def step(self, t_s, value, aux=None):
        return self._comp.step(t_s, value)


class OffsetElement:
    """Bridge output at zero force: voltage = input + voltage_v."""

    kind = "offset"

    def __init__(self, voltage_v: float = 0.0):
        self.voltage_v = float(voltage_v)

    def forward(self, t_s, x, aux=None):
        return np.asarray(x, dtype=float) + self.voltage_v

    def backward(self, t_s, y, aux=None):
        return np.asarray(y, dtype=float) - self.voltage_v

    def streaming(self):
        return _OffsetStream(self)

    def to_dict(self):
        return {"type": self.kind, "voltage_v": self.voltage_v}

    @classmethod
    def from_dict(cls, d):
        _check_keys(cls.kind, d, ("voltage_v",))
        return cls(_number(cls.kind, "voltage_v", d["voltage_v"], positive=False))


class _OffsetStream:
    def __init__(self, element):
        self.element = element  # read live, so a tare applies at once

    def reset(self):
        pass

    def step(self, t_s, value, aux=None):
        return value - self.element.voltage_v


ELEMENT_TYPES = {name: ViscoelasticElement for name in MODEL_TYPES}
ELEMENT_TYPES["offset"] = OffsetElement


class SensorChain:
    """Ordered elements from force (first) to voltage (last)."""

    def __init__(self, elements):
        self.elements = list(elements)
        if not self.elements:
            raise ModelError("a sensor model needs at least one element")
        cores = [e for e in self.elements if isinstance(e, ViscoelasticElement)]
        if len(cores) > 1:
            raise ModelError("a sensor model holds at most one viscoelastic core")

    @classmethod
    def from_model(cls, model: ViscoelasticModel, offset_v: float = 0.0):
        return cls([ViscoelasticElement(model), OffsetElement(offset_v)])

    @property
    def viscoelastic(self):
        """The viscoelastic model of the core, or None."""
        for e in self.elements:
            if isinstance(e, ViscoelasticElement):
                return e.model
        return None

    @property
    def offset(self) -> OffsetElement:
        """The offset element (added at the end when the model has none)."""
        for e in self.elements:
            if isinstance(e, OffsetElement):
                return e
        element = OffsetElement(0.0)
        self.elements.append(element)
        return element

    def forward(self, t_s, force_n, aux=None):
        x = np.asarray(force_n, dtype=float)
        for element in self.elements:
            x = element.forward(t_s, x, aux)
        return x

    def backward(self, t_s, voltage_v, aux=None):
        x = np.asarray(voltage_v, dtype=float)
        for element in reversed(self.elements):
            x = element.backward(t_s, x, aux)
        return x

    def streaming(self):
        return ChainStream([e.streaming() for e in reversed(self.elements)])

    def static_gain_v_per_n(self) -> float:
        core = self.viscoelastic
        return core.static_gain_v_per_n() if core is not None else 1.0

    def to_dict(self):
        return {"elements": [e.to_dict() for e in self.elements]}

    @classmethod
    def from_dict(cls, d):
        if not isinstance(d, dict) or not isinstance(d.get("elements"), list):
            raise ModelError("model must be a mapping with a list under 'elements'")
        elements = []
        for i, item in enumerate(d["elements"]):
            if not isinstance(item, dict) or "type" not in item:
                raise ModelError(f"element {i}: must be a mapping with a 'type'")
            kind = item["type"]
            if kind not in ELEMENT_TYPES:
                raise ModelError(f"element {i}: unknown type {kind!r}; known: {sorted(ELEMENT_TYPES)}")
            elements.append(ELEMENT_TYPES[kind].from_dict(item))
        return cls(elements)


class ChainStream:
    """Per-sample inverse of a chain: voltage in, force out (or None if rejected)."""

    def __init__(self, streams):
        self.streams = streams

    def reset(self):
        for s in self.streams:
            s.reset()

    def step(self, t_s, voltage_v, aux=None):
        x = voltage_v
        for s in self.streams:
            x = s.step(t_s, x, aux)
            if x is None:
                return None
        return x
