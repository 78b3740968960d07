"""A sensor as a chain of elements between applied force and measured voltage.

    force -> [viscoelastic core] -> ... -> [offset] -> voltage

Each element runs forward (simulate), backward in batch (compensate an array) and backward per sample
(``streaming()``, O(1) state), and describes itself as a plain mapping for the YAML model file.

Modules: :mod:`.base` (protocols, bounds, validation), :mod:`.core` (the viscoelastic core), :mod:`.static`
(offset and gains), :mod:`.dynamics` (lag, delay), :mod:`.drift` (thermal and time drifts),
:mod:`.hysteresis` (Preisach, play operator, friction), :mod:`.bridge` (plays at the bridge beside the core) and
:mod:`.sensor_chain` (the chain, its stream and the
registry of element types).
"""
from .base import (
                   MAX_PREISACH_LEVELS,
                   PARAMETER_BOUNDS,
                   Element,
                   ElementStream,
                   ForwardElement,
                   ModelError,
                   short_repr,
                   smoke_records,
)
from .core import (MAX_VOLUME_TERMS, KneeKelvinElement, PowerFlowElement, lowest_volume_fluidity, series_fluidity,
                   ThermoRheologicalElement, ViscoelasticElement, log_shift, reduced_time_s)
from .drift import (
                   ExponentialDriftElement,
                   OffsetDriftElement,
                   PolynomialDriftElement,
                   SplineDriftElement,
                   StepDriftElement,
                   ThermalDriftElement,
                   ThermalLagElement,
                   TimeDriftElement,
                   lagged_temperature_c,
)
from .bridge import BridgeHysteresisElement, scaled_input, scaled_output
from .dynamics import ResonanceElement, SensorLagElement, TransportDelayElement
from .hysteresis import FrictionElement, PlayHysteresisElement, PreisachElement, play_operator
from .sensor_chain import ELEMENT_TYPES, ChainStream, SensorChain
from .static import GainElement, NonlinearGainElement, OffsetElement, PolynomialGainElement, ThermalSensitivityElement

__all__ = ["ModelError", "short_repr", "smoke_records", "ElementStream", "ForwardElement", "Element", "PARAMETER_BOUNDS",
           "MAX_PREISACH_LEVELS", "ViscoelasticElement", "ThermoRheologicalElement", "PowerFlowElement",
           "MAX_VOLUME_TERMS", "lowest_volume_fluidity", "series_fluidity", "KneeKelvinElement",
           "reduced_time_s", "log_shift", "OffsetElement",
           "GainElement", "NonlinearGainElement",
           "SensorLagElement", "TransportDelayElement", "ResonanceElement", "ThermalDriftElement", "ThermalSensitivityElement",
           "OffsetDriftElement", "PreisachElement", "play_operator", "PlayHysteresisElement", "BridgeHysteresisElement",
           "FrictionElement", "scaled_input", "scaled_output",
           "ThermalLagElement",
           "ExponentialDriftElement", "SplineDriftElement", "StepDriftElement", "TimeDriftElement",
           "PolynomialGainElement", "PolynomialDriftElement",
           "lagged_temperature_c", "ELEMENT_TYPES", "SensorChain", "ChainStream"]
