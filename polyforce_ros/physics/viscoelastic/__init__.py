"""Linear viscoelastic sensor models (seed 000, section IV) and their runs over a record.

:mod:`.models`: each model's creep compliance J(t) [V/N] and relaxation modulus G(t) [N/V] (stiffnesses in N/V,
viscosities in N*s/V: the deformation is read as bridge volts). :mod:`.superposition`: ``simulate_deformation``
(force -> volts) and ``compensate`` / :class:`StreamingCompensator` (volts -> force) by Boltzmann superposition,
exact for piecewise-linear signals; the sensor is unloaded and relaxed before the first sample.
"""
from .models import (MODEL_TYPES, PAPER_BURGERS, Burgers, Burgers2, CreepCompliance, Elastic, KelvinVoigt, Maxwell,
                     RelaxationModulus, ViscoelasticModel, Zener, Zener2, Zener3, Burgers3)
from .superposition import (BackwardState, ForwardState, StreamingCompensator, compensate, simulate_deformation,
                            simulate_deformation_columns)

__all__ = ["CreepCompliance", "RelaxationModulus", "ViscoelasticModel", "Elastic", "Maxwell", "KelvinVoigt", "Zener",
           "Burgers", "Zener2", "Burgers2", "Zener3", "Burgers3", "MODEL_TYPES", "PAPER_BURGERS", "simulate_deformation",
           "simulate_deformation_columns", "ForwardState", "compensate", "BackwardState", "StreamingCompensator"]
