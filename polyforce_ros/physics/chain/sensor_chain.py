"""A sensor as a chain of elements between applied force and measured voltage.

    force -> [viscoelastic core] -> ... -> [offset] -> voltage

The chain runs its elements forward in order and backward in reverse order. Elements receive ``aux``, a
mapping of auxiliary signals sampled with the main one (e.g. ``temperature_c``), which elements that need
it (thermal terms) read and others ignore. :data:`ELEMENT_TYPES` maps a model file's ``type`` to its element.
"""
from __future__ import annotations

from typing import Any, Mapping, NoReturn, Optional, Protocol, Self, Sequence, cast

import numpy as np
import numpy.typing as npt

from ..viscoelastic import MODEL_TYPES, ViscoelasticModel
from .base import Element, ElementStream, FloatArray, ForwardElement, ModelError
from .core import KneeKelvinElement, PowerFlowElement, ThermoRheologicalElement, ViscoelasticElement
from .drift import (
    ExponentialDriftElement,
    OffsetDriftElement,
    PolynomialDriftElement,
    SplineDriftElement,
    StepDriftElement,
    ThermalDriftElement,
    ThermalLagElement,
)
from .dynamics import ResonanceElement, SensorLagElement, TransportDelayElement
from .bridge import BridgeHysteresisElement
from .hysteresis import FrictionElement, PlayHysteresisElement, PreisachElement
from .static import (
    GainElement,
    NonlinearGainElement,
    OffsetElement,
    OffsetStream,
    PolynomialGainElement,
    ThermalSensitivityElement,
)

__all__ = ["SensorChain", "ChainStream", "ELEMENT_TYPES"]


class _ElementType(Protocol):
    """An element class as :meth:`SensorChain.from_dict` uses it: every value of ELEMENT_TYPES."""

    def from_dict(self, d: Mapping[str, Any]) -> Element: ...


ELEMENT_TYPES: dict[str, type] = {name: ViscoelasticElement for name in MODEL_TYPES}
ELEMENT_TYPES["offset"] = OffsetElement
ELEMENT_TYPES["thermo_rheological"] = ThermoRheologicalElement
ELEMENT_TYPES["power_flow"] = PowerFlowElement
ELEMENT_TYPES["knee_kelvin"] = KneeKelvinElement
for _element in (GainElement, NonlinearGainElement, SensorLagElement, TransportDelayElement, ResonanceElement,
                 ThermalDriftElement,
                 ThermalSensitivityElement, OffsetDriftElement, PreisachElement, PlayHysteresisElement, BridgeHysteresisElement,
                 FrictionElement,
                 ThermalLagElement, PolynomialDriftElement, PolynomialGainElement, ExponentialDriftElement, SplineDriftElement,
                 StepDriftElement):
    ELEMENT_TYPES[_element.kind] = _element


class SensorChain:
    """Ordered elements from force (first) to voltage (last); an immutable value like its elements.

    ``forward_only=True`` admits elements that can only simulate (:class:`ForwardElement`): such a chain
    runs :meth:`forward` and nothing else (a simulator's truth, never a model file).
    """

    _elements: tuple[ForwardElement, ...]
    forward_only: bool

    def __init__(self, elements: Sequence[ForwardElement], *, forward_only: bool = False) -> None:
        items = tuple(elements)
        object.__setattr__(self, "_elements", items)
        object.__setattr__(self, "forward_only", bool(forward_only))
        if not items:
            raise ModelError("a sensor model needs at least one element")
        required = ForwardElement if forward_only else Element
        odd = [type(e).__name__ for e in items if not isinstance(e, required)]
        if odd:
            raise ModelError(f"not sensor-chain elements: {odd}")
        cores = [e for e in self.elements if isinstance(e, (ViscoelasticElement, BridgeHysteresisElement))]
        if len(cores) > 1:
            raise ModelError("a sensor model holds at most one viscoelastic core")

    @property
    def elements(self) -> tuple[ForwardElement, ...]:
        """The elements, force end first (a tuple: a changed chain is a new chain)."""
        return self._elements

    @property
    def invertible_elements(self) -> tuple[Element, ...]:
        """The elements, force end first, for the runs a forward-only chain cannot make (backward, streaming,
        the model file); a :class:`ModelError` for a forward-only chain."""
        if self.forward_only:
            raise ModelError("a forward-only chain (a simulator's truth) runs forward only: it has no inverse "
                             "and no model file")
        return cast(tuple[Element, ...], self._elements)

    def __setattr__(self, name: str, value: Any) -> NoReturn:
        raise AttributeError(f"SensorChain is immutable (tried to set {name}); build a new one "
                             "(SensorChain([...]), with_offset)")

    @classmethod
    def from_model(cls, model: ViscoelasticModel, offset_v: float = 0.0) -> Self:
        """The usual chain: a viscoelastic core followed by an offset.

        Parameters
        ----------
        model : ViscoelasticModel
            The core [N/V, N*s/V].
        offset_v : float, optional
            Bridge output at zero force [V].

        Returns
        -------
        SensorChain
            ``[ViscoelasticElement(model), OffsetElement(offset_v)]``.
        """
        return cls([ViscoelasticElement(model), OffsetElement(offset_v)])

    @property
    def viscoelastic(self) -> Optional[ViscoelasticModel]:
        """The viscoelastic model of the core, or None."""
        for e in self.elements:
            if isinstance(e, (ViscoelasticElement, BridgeHysteresisElement)):
                return e.model
        return None

    @property
    def offset(self) -> OffsetElement:
        """The offset element (a zero offset when the model has none; never added to the chain)."""
        for e in self.elements:
            if isinstance(e, OffsetElement):
                return e
        return OffsetElement(0.0)

    @property
    def needs_temperature(self) -> bool:
        """Whether an element follows temperature (``aux['temperature_c']``, degC): without it, it is not corrected."""
        thermal = (ThermalDriftElement, ThermalLagElement, ThermalSensitivityElement, ThermoRheologicalElement)
        return any(isinstance(e, thermal) for e in self.elements)

    @property
    def offset_v(self) -> float:
        """Bridge output at zero force, V (0 without an offset element)."""
        return self.offset.voltage_v

    def with_offset(self, voltage_v: float) -> "SensorChain":
        """A new chain with another bridge offset; this one is left as it is.

        The offset element is replaced where it stands, or appended at the
        voltage end when the chain has none.

        Parameters
        ----------
        voltage_v : float
            Bridge output at zero force [V].

        Returns
        -------
        SensorChain
            The new chain.
        """
        element = OffsetElement(voltage_v)
        if any(isinstance(e, OffsetElement) for e in self.elements):
            return SensorChain([element if isinstance(e, OffsetElement) else e for e in self.elements],
                               forward_only=self.forward_only)
        return SensorChain([*self.elements, element], forward_only=self.forward_only)

    def forward_states(self) -> list[Any]:
        """Fresh element states for block-wise forward runs (relaxed, unloaded sensor).

        Returns
        -------
        list
            Each element's :meth:`~Element.forward_state`, force end first.
        """
        return [e.forward_state() for e in self.elements]

    def forward(self, t_s: npt.ArrayLike, force_n: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                states: Optional[Sequence[Any]] = None) -> FloatArray:
        """Voltage for a force history: each element's :meth:`~Element.forward` from the force end.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s], non-decreasing.
        force_n : (n,) array_like of float
            Applied force [N].
        aux : mapping of str to array_like, optional
            Auxiliary signals sampled with the force (``temperature_c`` [degC]).
        states : sequence, optional
            From :meth:`forward_states`, to continue from a previous block (updated in place);
            a relaxed, unloaded sensor when omitted.

        Returns
        -------
        (n,) ndarray of float
            Bridge voltage [V].
        """
        states = states if states is not None else self.forward_states()
        x = np.asarray(force_n, dtype=float)
        for element, state in zip(self.elements, states):
            x = element.forward(t_s, x, aux, state)
        return x

    def backward(self, t_s: npt.ArrayLike, voltage_v: npt.ArrayLike,
                 aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """Force for a voltage record: each element's :meth:`~Element.backward` from the voltage end.

        Parameters
        ----------
        t_s : (n,) array_like of float
            Sample times [s].
        voltage_v : (n,) array_like of float
            Bridge voltage [V].
        aux : mapping of str to array_like, optional
            Auxiliary signals sampled with the voltage (``temperature_c`` [degC]).

        Returns
        -------
        (n,) ndarray of float
            Force [N].
        """
        x = np.asarray(voltage_v, dtype=float)
        for element in reversed(self.invertible_elements):
            x = element.backward(t_s, x, aux)
        return x

    def streaming(self) -> ChainStream:
        """The per-sample inverse of the chain.

        Returns
        -------
        ChainStream
            The elements' fresh per-sample inverses from the voltage end [V in, N out].
        """
        return ChainStream([e.streaming() for e in reversed(self.invertible_elements)])

    @property
    def latency_s(self) -> float:
        """How late the compensated force follows the applied force [s]: every transport delay, which the
        inverse cannot undo, plus the filter time of every bandwidth-limited lag inverse."""
        return float(sum(e.delay_s for e in self.elements if isinstance(e, TransportDelayElement))
                     + sum(e.latency_s for e in self.elements if isinstance(e, (SensorLagElement, ResonanceElement))))

    def static_gain_v_per_n(self) -> float:
        """The core's static gain (1.0 without a core), with the large-signal slope of hysteresis at the bridge
        beside it; the other elements are not included.

        Returns
        -------
        float
            Static gain [V/N].
        """
        core = self.viscoelastic
        gain = core.static_gain_v_per_n() if core is not None else 1.0
        for e in self.elements:
            if isinstance(e, BridgeHysteresisElement):
                gain += e.large_signal_slope_v_per_n()
        return gain

    def to_dict(self) -> dict[str, Any]:
        """The chain as a model-file mapping.

        Returns
        -------
        dict
            ``{'elements': [...]}``: each element's :meth:`~Element.to_dict`, force end first.
        """
        return {"elements": [e.to_dict() for e in self.invertible_elements]}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The chain from a model-file mapping, each element built by its ``type``.

        Parameters
        ----------
        d : mapping
            ``{'elements': [...]}``, force end first.

        Returns
        -------
        SensorChain
            The chain.

        Raises
        ------
        ModelError
            If anything is invalid.
        """
        if not isinstance(d, dict) or not isinstance(d.get("elements"), list):
            raise ModelError("model must be a mapping with a list under 'elements'")
        elements: list[Element] = []
        for i, item in enumerate(d["elements"]):
            if not isinstance(item, dict) or "type" not in item:
                raise ModelError(f"element {i}: must be a mapping with a 'type'")
            kind = item["type"]
            if kind not in ELEMENT_TYPES:
                raise ModelError(f"element {i}: unknown type {kind!r}; known: {sorted(ELEMENT_TYPES)}")
            # ELEMENT_TYPES holds plain types for its readers; every one of them builds from a mapping
            elements.append(cast(_ElementType, ELEMENT_TYPES[kind]).from_dict(item))
        return cls(elements)


class ChainStream:
    """Per-sample inverse of a chain: voltage in, force out (or None if rejected)."""

    def __init__(self, streams: Sequence[ElementStream]) -> None:
        self.streams = streams
        # The usual chain, an offset then the viscoelastic core, runs at 1 kHz: its offset is one
        # subtraction here and its one stateful stream is called directly (the same arithmetic as the loop).
        rest = list(streams)
        self._offset_v = 0.0
        if rest and isinstance(rest[0], OffsetStream):
            self._offset_v = rest[0].voltage_v
            del rest[0]
        self._only = rest[0] if len(rest) == 1 else None
        self._rest = rest

    def reset(self) -> None:
        """Reset every element's stream (the next sample starts from a relaxed, unloaded sensor)."""
        for s in self.streams:
            s.reset()

    def step(self, t_s: float, voltage_v: float, aux: Optional[Mapping[str, Any]] = None) -> Optional[float]:
        """Force for one voltage sample, or None if an element rejects the sample.

        Parameters
        ----------
        t_s : float
            Sample time [s].
        voltage_v : float
            Bridge voltage [V].
        aux : mapping of str to float, optional
            Auxiliary samples at ``t_s`` (``temperature_c`` [degC]).

        Returns
        -------
        float or None
            Force [N], or None when an element cannot use the sample.
        """
        x: Optional[float]  # declared apart from its value, so that mypy narrows it to float here
        x = voltage_v - self._offset_v
        only = self._only
        if only is not None:
            return only.step(t_s, x, aux)
        for s in self._rest:
            x = s.step(t_s, x, aux)
            if x is None:
                return None
        return x
