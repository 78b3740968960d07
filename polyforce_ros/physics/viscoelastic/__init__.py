"""Linear viscoelastic sensor models (seed 000, section IV) and their forward/backward runs.

Convention (as in seed 000): the sensor "deformation" gamma is measured as the
bridge voltage, so stiffnesses are in N/V and viscosities in N*s/V. Force is in
newtons, compression positive.

Each model is a frozen dataclass of its mechanical parameters and exposes

* ``creep_compliance(t_s)``  J(t) in V/N: deformation per newton of a unit force step;
* ``relaxation()``           G(t) in N/V as exponentials, derived like eq. 7-8:
                             the roots of the relaxation ODE's characteristic
                             polynomial give the rates, the initial conditions
                             G(0) and G'(0) (plus G(inf)) give the coefficients;
* ``compliance()``           the creep compliance as a Prony series, which drives
                             forward simulation.

``simulate_deformation`` runs a model forward (force -> volts) and
``compensate`` / :class:`StreamingCompensator` run it backward (volts -> force)
with the Boltzmann-superposition law of eq. 10-12. Both rest on
:mod:`polyforce_ros.physics.expconv`, exact for piecewise-linear signals and
stable for any record length. The sensor is taken to be unloaded and relaxed
before the first sample.
"""
from .models import (MODEL_TYPES, PAPER_BURGERS, Burgers, Burgers2, CreepCompliance, Elastic, KelvinVoigt, Maxwell,
                     RelaxationModulus, ViscoelasticModel, Zener, Zener2)
from .superposition import (BackwardState, ForwardState, StreamingCompensator, compensate, simulate_deformation,
                            simulate_deformation_columns)

__all__ = ["CreepCompliance", "RelaxationModulus", "ViscoelasticModel", "Elastic", "Maxwell", "KelvinVoigt", "Zener",
           "Burgers", "Zener2", "Burgers2", "MODEL_TYPES", "PAPER_BURGERS", "simulate_deformation",
           "simulate_deformation_columns", "ForwardState", "compensate", "BackwardState", "StreamingCompensator"]
