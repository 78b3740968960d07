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
from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any, ClassVar, Iterable, Optional, Sequence, TypeVar, Union

import numpy as np
import numpy.typing as npt

from scipy import linalg, signal

from .expconv import ExpConvState, exp_convolve, exp_convolve_columns, step_weights, uniform_step_after

__all__ = ["CreepCompliance", "RelaxationModulus", "ViscoelasticModel", "Elastic", "Maxwell", "KelvinVoigt", "Zener",
    "Burgers", "Zener2", "Burgers2", "MODEL_TYPES", "PAPER_BURGERS", "simulate_deformation",
    "simulate_deformation_columns", "ForwardState", "compensate", "BackwardState", "StreamingCompensator"]

_Model = TypeVar("_Model", bound="ViscoelasticModel")


@dataclass(frozen=True)
class CreepCompliance:
    """J(t) = j0 + sum_k c_k (1 - exp(-t / tau_k)) + fluidity * t   [V/N].

    j0_v_per_n: instantaneous compliance; c_v_per_n / tau_s: retarded
    (Kelvin) compliances and their retardation times; fluidity_v_per_n_s:
    1/eta of a free dashpot (unbounded creep), 0 for a solid.
    """

    j0_v_per_n: float
    c_v_per_n: tuple[float, ...] = ()
    tau_s: tuple[float, ...] = ()
    fluidity_v_per_n_s: float = 0.0

    def __call__(self, t_s: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """J(t) [V/N] at the given times.

        Parameters
        ----------
        t_s : float or array_like of float
            Time since the unit force step [s].

        Returns
        -------
        ndarray of float
            J(t_s) [V/N], shaped like ``t_s`` (a numpy scalar for a scalar ``t_s``).
        """
        t = np.asarray(t_s, dtype=float)
        j = self.j0_v_per_n + self.fluidity_v_per_n_s * t
        for c, tau in zip(self.c_v_per_n, self.tau_s):
            j = j - c * np.expm1(-t / tau)
        return j


@dataclass(frozen=True)
class RelaxationModulus:
    """G(t) = g_inf + sum_k a_k exp(-r_k t) + eta_impulse * delta(t)   [N/V].

    eta_impulse_n_s_per_v is non-zero only for a model without instantaneous
    elasticity (Kelvin-Voigt), whose inverse needs the deformation rate.
    """

    g_inf_n_per_v: float
    a_n_per_v: tuple[float, ...] = ()
    r_per_s: tuple[float, ...] = ()
    eta_impulse_n_s_per_v: float = 0.0

    @property
    def g0_n_per_v(self) -> float:
        """G(0+), the instantaneous stiffness in N/V."""
        return self.g_inf_n_per_v + float(sum(self.a_n_per_v))

    def __call__(self, t_s: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """G(t) [N/V] at the given times, without the impulse term.

        Parameters
        ----------
        t_s : float or array_like of float
            Time since the unit deformation step [s].

        Returns
        -------
        ndarray of float
            ``g_inf + sum_k a_k exp(-r_k t)`` [N/V], shaped like ``t_s`` (0-d for a scalar ``t_s``:
            a numpy scalar, or a 0-d array without exponential terms); ``eta_impulse_n_s_per_v``
            is not included.
        """
        t = np.asarray(t_s, dtype=float)
        g = np.full_like(t, self.g_inf_n_per_v)
        for a, r in zip(self.a_n_per_v, self.r_per_s):
            g = g + a * np.exp(-r * t)
        return g


def _relaxation_from_ode(char_poly: Sequence[float], g0: float, g0_dot: Optional[float],
                         g_inf: float = 0.0) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Rates and coefficients of G(t) = g_inf + sum a_k exp(-r_k t).

    char_poly: coefficients (highest power first) of the polynomial whose roots
    are the rates r_k (eq. 8 for Burgers). The coefficients solve the initial
    conditions G(0) = g0 and, for two rates, G'(0) = g0_dot (then not None).
    """
    rates = np.sort(np.real(np.roots(char_poly)))
    if rates.size == 1:
        return (g0 - g_inf,), (float(rates[0]),)
    vander = np.vstack([np.ones_like(rates), -rates])
    assert g0_dot is not None, "two rates need G'(0)"
    coeffs = np.linalg.solve(vander, [g0 - g_inf, g0_dot])
    return tuple(float(a) for a in coeffs), tuple(float(r) for r in rates)


@dataclass(frozen=True)
class ViscoelasticModel:
    """Base class: subclasses list their parameters as dataclass fields (all > 0)."""

    kind: ClassVar[str] = ""
    #: (Kelvin units, an instantaneous spring, a free dashpot): what a fit of this type must
    #: provide (the discrepancy engine's columns, the fluid kinds of identification)
    shape: ClassVar[tuple[int, bool, bool]] = (0, True, False)

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if not isinstance(value, (int, float)) or isinstance(value, bool):
                raise TypeError(f"{self.kind}: {f.name} must be a number, got {value!r}")
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{self.kind}: {f.name} must be finite and > 0, got {value!r}")

    @classmethod
    def parameter_names(cls) -> tuple[str, ...]:
        """The names of the model's parameters (its dataclass fields, units in their names), in field order.

        Returns
        -------
        tuple of str
            Field names such as ``k1_n_per_v`` or ``eta2_n_s_per_v``; the suffix is the unit.
        """
        return tuple(f.name for f in fields(cls))

    def as_dict(self) -> dict[str, float]:
        """The model's parameters as ``{name: value}`` floats (units in their names).

        Returns
        -------
        dict of str to float
            Parameter values in the units their names carry (N/V, N*s/V), in field order.
        """
        return {name: float(getattr(self, name)) for name in self.parameter_names()}

    def as_vector(self) -> npt.NDArray[np.float64]:
        """The model's parameters in the order of parameter_names() (units in their names).

        Returns
        -------
        (p,) ndarray of float
            Parameter values (N/V, N*s/V as their names say), one per field.
        """
        return np.array([getattr(self, n) for n in self.parameter_names()], dtype=float)

    @classmethod
    def from_vector(cls: type[_Model], values: Iterable[float]) -> _Model:
        """The model built from parameter values in the order of parameter_names() (inverse of as_vector).

        Parameters
        ----------
        values : iterable of float
            One value per parameter, in the units their names carry (N/V, N*s/V).

        Returns
        -------
        ViscoelasticModel
            An instance of the class it is called on. Raises TypeError for a wrong number of
            values and ValueError for a value that is not finite and > 0.
        """
        return cls(*(float(v) for v in values))

    # Subclasses implement these two.
    def compliance(self) -> CreepCompliance:  # pragma: no cover - abstract
        """The creep compliance J(t) as a Prony series in V/N; implemented by each subclass.

        Returns
        -------
        CreepCompliance
            J(t) [V/N]: instantaneous, retarded (Kelvin) and viscous-flow terms.
        """
        raise NotImplementedError

    def relaxation(self) -> RelaxationModulus:  # pragma: no cover - abstract
        """The relaxation modulus G(t) as exponentials in N/V; implemented by each subclass.

        Returns
        -------
        RelaxationModulus
            G(t) [N/V]: the equilibrium modulus, exponential terms with their rates [1/s], and
            an impulse term [N*s/V] for a model without instantaneous elasticity.
        """
        raise NotImplementedError

    def creep_compliance(self, t_s: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """J(t) in V/N (eq. 4 for Burgers).

        Parameters
        ----------
        t_s : float or array_like of float
            Time since the unit force step [s].

        Returns
        -------
        ndarray of float
            J(t_s) [V/N], shaped like ``t_s`` (a numpy scalar for a scalar ``t_s``).
        """
        return self.compliance()(t_s)

    def static_gain_v_per_n(self) -> float:
        """The elastic (non-flowing) gain 1/k1 + 1/k2 + ... in V/N.

        For Burgers this is the paper's static gain k_s = 0.31 V/N (the inverse
        of the static stiffness k1 k2 / (k1 + k2)); the free dashpot is left
        out because its creep is unbounded.

        Returns
        -------
        float
            ``j0 + sum_k c_k`` of the creep compliance [V/N].
        """
        c = self.compliance()
        return c.j0_v_per_n + float(sum(c.c_v_per_n))


@dataclass(frozen=True)
class Elastic(ViscoelasticModel):
    """A pure spring k: the static-gain sensor (no viscoelasticity)."""

    kind: ClassVar[str] = "elastic"
    shape: ClassVar[tuple[int, bool, bool]] = (0, True, False)
    k_n_per_v: float

    def compliance(self) -> CreepCompliance:
        """The creep compliance J(t) = 1/k in V/N, constant.

        Returns
        -------
        CreepCompliance
            Only the instantaneous compliance j0 = 1/k [V/N].
        """
        return CreepCompliance(1.0 / self.k_n_per_v)

    def relaxation(self) -> RelaxationModulus:
        """The relaxation modulus G(t) = k in N/V, constant.

        Returns
        -------
        RelaxationModulus
            Only the equilibrium modulus g_inf = k [N/V].
        """
        return RelaxationModulus(self.k_n_per_v)


@dataclass(frozen=True)
class Maxwell(ViscoelasticModel):
    """Spring k in series with dashpot eta (fluid)."""

    kind: ClassVar[str] = "maxwell"
    shape: ClassVar[tuple[int, bool, bool]] = (0, True, True)
    k_n_per_v: float
    eta_n_s_per_v: float

    def compliance(self) -> CreepCompliance:
        """The creep compliance J(t) = 1/k + t/eta in V/N (unbounded creep).

        Returns
        -------
        CreepCompliance
            j0 = 1/k [V/N] and fluidity 1/eta [V/(N*s)].
        """
        return CreepCompliance(1.0 / self.k_n_per_v, fluidity_v_per_n_s=1.0 / self.eta_n_s_per_v)

    def relaxation(self) -> RelaxationModulus:
        """The relaxation modulus G(t) = k exp(-(k/eta) t) in N/V, relaxing to 0.

        Returns
        -------
        RelaxationModulus
            One exponential: a = k [N/V] at rate r = k/eta [1/s]; g_inf = 0.
        """
        # eta/k F' + F = eta gamma'  ->  root r = k/eta, G(0) = k, G(inf) = 0.
        a, r = _relaxation_from_ode([self.eta_n_s_per_v / self.k_n_per_v, -1.0], self.k_n_per_v, None)
        return RelaxationModulus(0.0, a, r)


@dataclass(frozen=True)
class KelvinVoigt(ViscoelasticModel):
    """Spring k in parallel with dashpot eta (no instantaneous elasticity)."""

    kind: ClassVar[str] = "kelvin"
    shape: ClassVar[tuple[int, bool, bool]] = (1, False, False)
    k_n_per_v: float
    eta_n_s_per_v: float

    def compliance(self) -> CreepCompliance:
        """The creep compliance J(t) = (1/k) (1 - exp(-t k/eta)) in V/N, no instantaneous compliance.

        Returns
        -------
        CreepCompliance
            One retarded term c = 1/k [V/N] with tau = eta/k [s]; j0 = 0.
        """
        return CreepCompliance(0.0, (1.0 / self.k_n_per_v,), (self.eta_n_s_per_v / self.k_n_per_v,))

    def relaxation(self) -> RelaxationModulus:
        """The relaxation modulus G(t) = k + eta delta(t), without exponentials.

        Returns
        -------
        RelaxationModulus
            g_inf = k [N/V] and the impulse term eta [N*s/V].
        """
        # F = k gamma + eta gamma': G(t) = k + eta delta(t), no exponential term.
        return RelaxationModulus(self.k_n_per_v, eta_impulse_n_s_per_v=self.eta_n_s_per_v)


@dataclass(frozen=True)
class Zener(ViscoelasticModel):
    """Spring k1 in series with a Kelvin element (k2, eta2): the standard linear solid."""

    kind: ClassVar[str] = "zener"
    shape: ClassVar[tuple[int, bool, bool]] = (1, True, False)
    k1_n_per_v: float
    k2_n_per_v: float
    eta2_n_s_per_v: float

    def compliance(self) -> CreepCompliance:
        """The creep compliance J(t) = 1/k1 + (1/k2) (1 - exp(-t k2/eta2)) in V/N.

        Returns
        -------
        CreepCompliance
            j0 = 1/k1 [V/N] and one retarded term c = 1/k2 [V/N] with tau = eta2/k2 [s].
        """
        return CreepCompliance(
            1.0 / self.k1_n_per_v, (1.0 / self.k2_n_per_v,), (self.eta2_n_s_per_v / self.k2_n_per_v,)
        )

    def relaxation(self) -> RelaxationModulus:
        """The relaxation modulus G(t) in N/V: one exponential from G(0) = k1 to G(inf) = k1 k2/(k1 + k2).

        Returns
        -------
        RelaxationModulus
            g_inf = k1 k2/(k1 + k2) [N/V] and one exponential of rate (k1 + k2)/eta2 [1/s]
            with a = k1 - g_inf [N/V].
        """
        k1, k2, eta2 = self.k1_n_per_v, self.k2_n_per_v, self.eta2_n_s_per_v
        # (eta2/k1) F' + (1 + k2/k1) F = k2 gamma + eta2 gamma' with gamma fixed:
        # root r = (k1 + k2)/eta2, G(0) = k1, G(inf) = k1 k2/(k1 + k2).
        g_inf = k1 * k2 / (k1 + k2)
        a, r = _relaxation_from_ode([eta2 / k1, -(1.0 + k2 / k1)], k1, None, g_inf)
        return RelaxationModulus(g_inf, a, r)


@dataclass(frozen=True)
class Burgers(ViscoelasticModel):
    """Maxwell element (k1, eta1) in series with a Kelvin element (k2, eta2); eq. 2-4."""

    kind: ClassVar[str] = "burgers"
    shape: ClassVar[tuple[int, bool, bool]] = (1, True, True)
    k1_n_per_v: float
    k2_n_per_v: float
    eta1_n_s_per_v: float
    eta2_n_s_per_v: float

    def compliance(self) -> CreepCompliance:
        """The creep compliance of the Burgers model, J(t) = 1/k1 + t/eta1 + (1/k2) (1 - exp(-t k2/eta2)) in V/N (eq. 4).

        Returns
        -------
        CreepCompliance
            j0 = 1/k1 [V/N], one retarded term c = 1/k2 [V/N] with tau = eta2/k2 [s], and
            fluidity 1/eta1 [V/(N*s)].
        """
        return CreepCompliance(
            1.0 / self.k1_n_per_v,
            (1.0 / self.k2_n_per_v,),
            (self.eta2_n_s_per_v / self.k2_n_per_v,),
            1.0 / self.eta1_n_s_per_v,
        )

    def retardation_time_s(self) -> float:
        """The retardation time lambda = eta2 / k2 of the Kelvin element (8.51 s for eq. 5).

        Returns
        -------
        float
            lambda [s].
        """
        return self.eta2_n_s_per_v / self.k2_n_per_v

    def relaxation(self) -> RelaxationModulus:
        """The relaxation modulus of the Burgers model: two exponentials whose rates are the roots of eq. 8.

        The coefficients solve G(0) = k1 and G'(0) = -k1^2 (1/eta1 + 1/eta2), with G(inf) = 0.

        Returns
        -------
        RelaxationModulus
            Two exponentials (coefficients [N/V], rates [1/s], slowest first); g_inf = 0.
        """
        k1, k2 = self.k1_n_per_v, self.k2_n_per_v
        eta1, eta2 = self.eta1_n_s_per_v, self.eta2_n_s_per_v
        # Eq. 8: (eta2/k1) r^2 - (1 + k2/k1 + eta2/eta1) r + k2/eta1 = 0,
        # G(0) = k1, G'(0) = -k1^2 (1/eta1 + 1/eta2), G(inf) = 0.
        poly = [eta2 / k1, -(1.0 + k2 / k1 + eta2 / eta1), k2 / eta1]
        a, r = _relaxation_from_ode(poly, k1, -k1 * k1 * (1.0 / eta1 + 1.0 / eta2))
        return RelaxationModulus(0.0, a, r)


def _relaxation_from_compliance(comp: CreepCompliance) -> RelaxationModulus:
    """G(t) of any creep compliance with instantaneous elasticity (j0 > 0), via Laplace.

    s J(s) = j0 + sum_k c_k / (1 + tau_k s) + fluidity / s = N(s) / D(s), and
    s G(s) s J(s) = 1, so G(s) = D(s) / (s N(s)): the rates are the roots of N
    and each coefficient is a residue, a_i = D(p_i) / (p_i N'(p_i)) at p_i = -r_i;
    G(inf) = D(0) / N(0) (zero for a fluid).
    """
    factors = [np.array([tau, 1.0]) for tau in comp.tau_s]  # 1 + tau s, highest power first
    flow = np.array([1.0, 0.0]) if comp.fluidity_v_per_n_s else np.ones(1)  # the 1/s of the dashpot
    den = np.polymul(flow, _polyprod(factors))
    num: npt.NDArray[np.floating[Any]] = comp.j0_v_per_n * den
    for k, c in enumerate(comp.c_v_per_n):
        num = np.polyadd(num, c * np.polymul(flow, _polyprod(factors[:k] + factors[k + 1:])))
    if comp.fluidity_v_per_n_s:
        num = np.polyadd(num, comp.fluidity_v_per_n_s * _polyprod(factors))
    poles = np.roots(num)
    if np.any(np.abs(poles.imag) > 1e-9 * np.abs(poles.real)) or np.any(poles.real >= 0):
        raise ValueError("compliance without a passive relaxation (complex or non-negative rates)")
    poles = np.sort(poles.real)[::-1]  # slowest first, like the closed forms
    dnum = np.polyder(num)
    a = tuple(float(np.polyval(den, p) / (p * np.polyval(dnum, p))) for p in poles)
    g_inf = 0.0 if comp.fluidity_v_per_n_s else float(np.polyval(den, 0.0) / np.polyval(num, 0.0))
    return RelaxationModulus(g_inf, a, tuple(float(-p) for p in poles))


@dataclass(frozen=True)
class Zener2(ViscoelasticModel):
    """Spring k1 in series with two Kelvin elements (k2, eta2) and (k3, eta3): a solid with two
    retardation times, i.e. a Zener sensor with a second delayed elasticity."""

    kind: ClassVar[str] = "zener2"
    shape: ClassVar[tuple[int, bool, bool]] = (2, True, False)
    k1_n_per_v: float
    k2_n_per_v: float
    eta2_n_s_per_v: float
    k3_n_per_v: float
    eta3_n_s_per_v: float

    def compliance(self) -> CreepCompliance:
        """The creep compliance J(t) = 1/k1 + sum over the two Kelvin elements of (1/k_i) (1 - exp(-t k_i/eta_i)) in V/N.

        Returns
        -------
        CreepCompliance
            j0 = 1/k1 [V/N] and two retarded terms c_i = 1/k_i [V/N] with tau_i = eta_i/k_i [s].
        """
        return _two_kelvin_compliance(self)

    def relaxation(self) -> RelaxationModulus:
        """The relaxation modulus G(t) in N/V from the compliance via Laplace (two exponentials).

        Raises ValueError if the rates come out complex or non-negative.

        Returns
        -------
        RelaxationModulus
            g_inf = the static stiffness 1/(1/k1 + 1/k2 + 1/k3) [N/V] and two exponentials
            (coefficients [N/V], rates [1/s], slowest first).
        """
        return _relaxation_from_compliance(self.compliance())


def _two_kelvin_compliance(model: Union[Zener2, Burgers2], fluidity_v_per_n_s: float = 0.0) -> CreepCompliance:
    """J(t) of spring k1 + Kelvin (k2, eta2) + Kelvin (k3, eta3) [+ a free dashpot]."""
    return CreepCompliance(
        1.0 / model.k1_n_per_v,
        (1.0 / model.k2_n_per_v, 1.0 / model.k3_n_per_v),
        (model.eta2_n_s_per_v / model.k2_n_per_v, model.eta3_n_s_per_v / model.k3_n_per_v),
        fluidity_v_per_n_s,
    )


@dataclass(frozen=True)
class Burgers2(ViscoelasticModel):
    """Burgers (k1, eta1, Kelvin k2/eta2) with a second Kelvin element (k3, eta3): a Burgers
    sensor with a second delayed elasticity."""

    kind: ClassVar[str] = "burgers2"
    shape: ClassVar[tuple[int, bool, bool]] = (2, True, True)
    k1_n_per_v: float
    k2_n_per_v: float
    eta1_n_s_per_v: float
    eta2_n_s_per_v: float
    k3_n_per_v: float
    eta3_n_s_per_v: float

    def compliance(self) -> CreepCompliance:
        """The creep compliance J(t) = 1/k1 + t/eta1 + sum over the two Kelvin elements of (1/k_i) (1 - exp(-t k_i/eta_i)) in V/N.

        Returns
        -------
        CreepCompliance
            j0 = 1/k1 [V/N], two retarded terms c_i = 1/k_i [V/N] with tau_i = eta_i/k_i [s], and
            fluidity 1/eta1 [V/(N*s)].
        """
        return _two_kelvin_compliance(self, 1.0 / self.eta1_n_s_per_v)

    def relaxation(self) -> RelaxationModulus:
        """The relaxation modulus G(t) in N/V from the compliance via Laplace (exponentials only: a fluid).

        Raises ValueError if the rates come out complex or non-negative.

        Returns
        -------
        RelaxationModulus
            Three exponentials (coefficients [N/V], rates [1/s], slowest first); g_inf = 0.
        """
        return _relaxation_from_compliance(self.compliance())


MODEL_TYPES: dict[str, type[ViscoelasticModel]] = {
    cls.kind: cls for cls in (Elastic, Maxwell, KelvinVoigt, Zener, Burgers, Zener2, Burgers2)
}

#: Seed 000, eq. 5: the Burgers parameters identified from the 5 N creep test.
PAPER_BURGERS = Burgers(k1_n_per_v=4.8, k2_n_per_v=10.0, eta1_n_s_per_v=4627.94, eta2_n_s_per_v=85.12)


def simulate_deformation(model: ViscoelasticModel, t_s: npt.ArrayLike, force_n: npt.ArrayLike,
                         state: Optional[ForwardState] = None) -> npt.NDArray[np.float64]:
    """Forward run: deformation (bridge volts above offset) for a sampled force history.

    gamma(t) = j0 F(t) + sum_k c_k x_k(t) + fluidity * int F dt, where each
    Kelvin state obeys tau_k x_k' + x_k = F (the creep compliance applied by
    Boltzmann superposition). Exact for force varying linearly between samples
    (exact exponential recursion of :mod:`~.expconv`); any (non-decreasing) spacing.

    Parameters
    ----------
    model : ViscoelasticModel
        The sensor model; its :meth:`~ViscoelasticModel.compliance` drives the run.
    t_s : (n,) array_like of float
        Sample times [s], non-decreasing (ValueError otherwise, also when they start
        before the last sample of ``state``).
    force_n : (n,) array_like of float
        Force [N], compression positive.
    state : ForwardState, optional
        Carries the element states across calls (block-wise simulation); a
        relaxed, unloaded sensor when omitted. Updated in place.

    Returns
    -------
    (n,) ndarray of float
        Deformation [V] (bridge volts above offset).
    """
    t = np.asarray(t_s, dtype=float)
    f = np.asarray(force_n, dtype=float)
    comp = model.compliance()
    st = state if state is not None else ForwardState(model)
    rates = st.rates_per_s
    if st.t_prev_s is None:
        y = exp_convolve(t, f, rates, y0=st.y)
    else:
        y = exp_convolve(t, f, rates, y0=st.y, u_prev=st.f_prev_n, t_prev_s=st.t_prev_s)
    gamma = comp.j0_v_per_n * f
    for k, (c, tau) in enumerate(zip(comp.c_v_per_n, comp.tau_s)):
        gamma = gamma + (c / tau) * y[:, k]
    if comp.fluidity_v_per_n_s:
        gamma = gamma + comp.fluidity_v_per_n_s * y[:, -1]
    if t.size:
        st.y = y[-1].copy()
        st.t_prev_s, st.f_prev_n = float(t[-1]), float(f[-1])
    return gamma


def simulate_deformation_columns(model: ViscoelasticModel, t_s: npt.ArrayLike,
                                 forces_n: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """:func:`simulate_deformation` of every column of ``forces_n`` from rest, at once.

    Parameters
    ----------
    model : ViscoelasticModel
        The sensor model; its creep compliance drives the run.
    t_s : (n,) array_like of float
        Sample times [s], non-decreasing.
    forces_n : (n, m) array_like of float
        Force histories [N] as columns, compression positive.

    Returns
    -------
    (n, m) ndarray of float
        Deformation [V] (bridge volts above offset) of each column.
    """
    comp = model.compliance()
    x = np.asarray(forces_n, dtype=float)
    gamma = comp.j0_v_per_n * x
    for c, tau in zip(comp.c_v_per_n, comp.tau_s):
        gamma = gamma + (c / tau) * exp_convolve_columns(t_s, x, 1.0 / tau)
    if comp.fluidity_v_per_n_s:
        gamma = gamma + comp.fluidity_v_per_n_s * exp_convolve_columns(t_s, x, 0.0)
    return gamma


class ForwardState:
    """Element states of a forward simulation, for simulating in blocks.

    Parameters
    ----------
    model : ViscoelasticModel
        The model whose creep compliance sets the states: one per Kelvin element
        (rate 1/tau [1/s]) plus one of rate 0 for a free dashpot. They start at
        zero (a relaxed, unloaded sensor) with no previous sample.
    """

    def __init__(self, model: ViscoelasticModel) -> None:
        comp = model.compliance()
        rates = [1.0 / tau for tau in comp.tau_s]
        if comp.fluidity_v_per_n_s:
            rates.append(0.0)  # the free dashpot integrates the force
        self.rates_per_s: npt.NDArray[np.float64] = np.array(rates, dtype=float)
        self.y: npt.NDArray[np.float64] = np.zeros(len(rates))
        self.t_prev_s: Optional[float] = None
        self.f_prev_n = 0.0


class _UniformCascade:
    """The compensation law at a fixed step h as one cascade of first-order IIR sections.

    With uniform stamps the modal recursions of :func:`compensate`
    (``y_k[n] = E_k y_k[n-1] + h (alpha_k g[n-1] + beta_k g[n])``, force
    ``G0 g - sum_k a_k r_k y_k``) add up to one rational transfer function in
    ``w = z**-1``. ``scipy.signal.sosfilt`` runs its factored form in a single
    pass over the record, where one filter per mode needs one pass each plus a sum.

    Why this factorisation: the poles sit within 1e-6 of 1 (E = 1 - 7e-7 for
    the slow Burgers mode at 1 kHz), so a polynomial in ``w`` would cancel away
    most digits (one common second-order section lost 1e-7 relative). In
    ``u = 1 - w`` each factor ``1 - E_k w = d_k + E_k u`` with ``d_k = 1 - E_k``
    taken from ``expm1``, and, writing ``G0 = G_inf + sum_k a_k``, the numerator
    becomes

        N(u) = G_inf prod_k (d_k + E_k u) + u sum_k (a_k E_k + c_k alpha_k) prod_{j != k} (d_j + E_j u)

    (``c_k = a_k r_k h``): a sum of positive terms, computed without
    cancellation, whose roots ``u_i`` are exact zero for a fluid (G_inf = 0)
    and otherwise real and negative for one mode. Each section keeps its own
    pole: section i is ``((1 - u_i) - w) / (1 - E_i w)``, zeros and poles
    paired by size.

    The history stays in the modal form of :class:`BackwardState` so blocks
    can switch between this path and the general one. The two forms are
    related through their zero-input responses: after sample n both decay as
    ``sum_k A_k E_k**j``; for the modes ``A_k = -a_k r_k (E_k y_k + h alpha_k g_n)``,
    for the cascade ``A = R^T s`` with ``R`` the (upper triangular) residues
    of each section state at each pole.
    """

    def __init__(self, rel: RelaxationModulus, h_s: float, sos: npt.NDArray[np.float64],
                 residues: npt.NDArray[np.float64], order: npt.NDArray[np.intp], e: npt.NDArray[np.float64],
                 alpha: npt.NDArray[np.float64], beta: npt.NDArray[np.float64]) -> None:
        self.h_s, self.sos, self.residues = h_s, sos, residues
        self.order = order  # section i carries mode order[i]
        self.e, self.alpha, self.beta = e, alpha, beta
        self.ar = np.array(rel.a_n_per_v)[order] * np.array(rel.r_per_s)[order]

    @classmethod
    def for_record(cls, rel: RelaxationModulus, t_s: npt.ArrayLike,
                   state: BackwardState) -> Optional[_UniformCascade]:
        """The cascade for stamps ``t_s`` continuing ``state``, or None if the stamps are not
        uniform (or too few) or the model falls outside the positive case treated here."""
        h = uniform_step_after(state.t_prev_s, t_s)
        return None if h is None else cls.build(rel, h)

    @classmethod
    def build(cls, rel: RelaxationModulus, h_s: float) -> Optional[_UniformCascade]:
        """The cascade for the fixed step ``h_s`` (s), or None if a coefficient or rate is not
        positive, G(inf) < 0, or the factorisation fails (complex or missing zeros, a pole
        cancelled by a zero)."""
        a = np.array(rel.a_n_per_v, dtype=float)
        r = np.array(rel.r_per_s, dtype=float)
        if a.size == 0 or np.any(a <= 0) or np.any(r <= 0) or rel.g_inf_n_per_v < 0:
            return None
        order = np.argsort(r)  # slowest mode first: its pole pairs with the zero nearest u = 0
        a, r = a[order], r[order]
        z = r * h_s
        e, alpha, beta = (np.atleast_1d(x) for x in step_weights(z))
        d = -np.expm1(-z)
        c = a * z
        factors = [np.array([ek, dk]) for ek, dk in zip(e, d)]  # E_k u + d_k, highest power first
        num = rel.g_inf_n_per_v * _polyprod(factors)
        weighted = np.zeros(1)
        for k in range(a.size):
            term = (a[k] * e[k] + c[k] * alpha[k]) * _polyprod(factors[:k] + factors[k + 1:])
            weighted = np.polyadd(weighted, term)
        num = np.polyadd(num, np.polymul(weighted, [1.0, 0.0]))
        u = np.roots(num)
        # np.roots drops leading zero coefficients (a mode whose exp(-r h) underflowed): fewer
        # zeros than sections leaves the cascade undefined; the modal path handles such records
        if u.size != a.size or np.any(np.abs(u.imag) > 0):
            return None
        u = np.sort(u.real)[::-1]  # nearest 0 first (all roots <= 0)
        sos = np.zeros((a.size, 6))
        sos[:, 0], sos[:, 1], sos[:, 3], sos[:, 4] = 1.0 - u, -1.0, 1.0, -e
        sos[0, :2] *= num[0]
        residues = np.zeros((a.size, a.size))
        for i in range(a.size):
            for k in range(i, a.size):
                zeros_after = np.prod([-(u[m] + d[k] / e[k]) for m in range(i + 1, a.size)])
                poles_others = np.prod([(d[m] - d[k]) / e[k] for m in range(i, a.size) if m != k])
                residues[i, k] = zeros_after / poles_others
        if not np.all(np.isfinite(residues)) or np.any(np.diag(residues) == 0):
            return None  # a pole cancelled by a zero: the modal path handles it
        return cls(rel, h_s, sos, residues, order, e, alpha, beta)

    def run(self, g_v: npt.NDArray[np.float64], state: BackwardState) -> npt.NDArray[np.float64]:
        """Force (N) for deformations ``g_v``; ``state`` is read and then advanced."""
        h = self.h_s
        if state.t_prev_s is None:
            # A relaxed sensor stepped to g[0]: as if a sample g[0] preceded with the history
            # that makes y_k[0] = 0, so the first output is G0 g[0].
            amp = self.ar * h * self.beta * g_v[0]
        else:
            y = np.asarray(state.y, dtype=float)[self.order]
            amp = -self.ar * (self.e * y + h * self.alpha * state.g_prev_v)
        s0 = linalg.solve_triangular(self.residues, amp, trans="T")
        zi = np.zeros((self.sos.shape[0], 2))
        zi[:, 0] = s0
        force, zf = signal.sosfilt(self.sos, g_v, zi=zi)
        amp_end = self.residues.T @ zf[:, 0]
        y_end = (-amp_end / self.ar - h * self.alpha * g_v[-1]) / self.e
        state.y = np.empty_like(y_end)
        state.y[self.order] = y_end
        return force


def _polyprod(factors: Iterable[npt.NDArray[np.floating[Any]]]) -> npt.NDArray[np.floating[Any]]:
    out: npt.NDArray[np.floating[Any]] = np.ones(1)
    for f in factors:
        out = np.polymul(out, f)
    return out


def compensate(model: ViscoelasticModel, t_s: npt.ArrayLike, deformation_v: npt.ArrayLike,
               state: Optional[BackwardState] = None) -> npt.NDArray[np.float64]:
    """Backward run, batch: force in N from deformation (volts above offset).

    Boltzmann superposition with the relaxation modulus, in the derivative-free
    form of eq. 10-11:
    F(t) = G(0) gamma(t) - sum_k a_k r_k int exp(-r_k (t - s)) gamma(s) ds,
    evaluated exactly for gamma linear between samples (the exact exponential
    recursion of :mod:`~.expconv`). For a
    Kelvin-Voigt model the impulsive term eta * dgamma/dt is added as the slope
    over the last interval (this differentiates noise; prefer a model with
    instantaneous elasticity). Uniformly stamped blocks run as one IIR cascade
    in a single pass (:class:`_UniformCascade`), others through the general
    recursion; both give the same result to float64 rounding.

    Parameters
    ----------
    model : ViscoelasticModel
        The sensor model; its :meth:`~ViscoelasticModel.relaxation` drives the run.
    t_s : (n,) array_like of float
        Sample times [s], non-decreasing. For a model with exponential relaxation
        terms, decreasing stamps (also a first stamp before the last one of
        ``state``) raise ValueError; for one without (elastic, Kelvin-Voigt) they
        are not checked, and the Kelvin-Voigt slope term is zero over a
        non-increasing interval.
    deformation_v : (n,) array_like of float
        Deformation [V] (bridge volts above offset).
    state : BackwardState, optional
        Carries the history across calls (block-wise compensation of long
        records); a relaxed, unloaded sensor when omitted. Updated in place
        (unchanged for an empty block).

    Returns
    -------
    (n,) ndarray of float
        Force [N], compression positive.
    """
    t = np.asarray(t_s, dtype=float)
    g = np.asarray(deformation_v, dtype=float)
    rel = model.relaxation()
    st = state if state is not None else BackwardState(model)
    if t.size == 0:
        return rel.g0_n_per_v * g
    force = None
    if rel.r_per_s:
        cascade = _UniformCascade.for_record(rel, t, st)
        if cascade is not None:
            force = cascade.run(g, st)
        else:
            if st.t_prev_s is None:  # the first sample is the step from rest: no history yet
                y = exp_convolve(t, g, rel.r_per_s, y0=st.y)
            else:
                y = exp_convolve(t, g, rel.r_per_s, y0=st.y, u_prev=st.g_prev_v, t_prev_s=st.t_prev_s)
            force = rel.g0_n_per_v * g
            for k, (a, r) in enumerate(zip(rel.a_n_per_v, rel.r_per_s)):
                force = force - (a * r) * y[:, k]
            st.y = y[-1].copy()
    else:
        force = rel.g0_n_per_v * g
    if rel.eta_impulse_n_s_per_v:
        t_all = t if st.t_prev_s is None else np.concatenate(([st.t_prev_s], t))
        g_all = g if st.t_prev_s is None else np.concatenate(([st.g_prev_v], g))
        dt, dg = np.diff(t_all), np.diff(g_all)
        slope = np.where(dt > 0, dg / np.where(dt > 0, dt, 1.0), 0.0)
        if st.t_prev_s is None:
            slope = np.concatenate(([0.0], slope))
        force = force + rel.eta_impulse_n_s_per_v * slope
    st.t_prev_s, st.g_prev_v = float(t[-1]), float(g[-1])
    return force


class BackwardState:
    """History of a batch compensation, for compensating in blocks.

    Parameters
    ----------
    model : ViscoelasticModel
        The model whose relaxation modulus sets the states: one per exponential
        term, starting at zero (a relaxed, unloaded sensor) with no previous sample.
    """

    def __init__(self, model: ViscoelasticModel) -> None:
        self.y: npt.NDArray[np.float64] = np.zeros(len(model.relaxation().r_per_s))
        self.t_prev_s: Optional[float] = None
        self.g_prev_v = 0.0


class StreamingCompensator:
    """Backward run, one sample at a time, O(1) work and memory per sample.

    Gives the same result as :func:`compensate` on the same samples (to float64
    rounding). ``step`` returns the force in N, or ``None`` for a sample that
    cannot be used (stamp earlier than the previous one; the state is left
    untouched). A duplicate stamp is processed as a zero-length step: the
    history integral does not change and the instantaneous term follows the
    new value.

    Parameters
    ----------
    model : ViscoelasticModel
        The sensor model; its relaxation modulus drives the run (Boltzmann
        superposition by the exact exponential recursion of :class:`~.expconv.ExpConvState`).
    """

    def __init__(self, model: ViscoelasticModel) -> None:
        self.model = model
        rel = model.relaxation()
        self._g0 = rel.g0_n_per_v
        self._ar = [a * r for a, r in zip(rel.a_n_per_v, rel.r_per_s)]
        self._eta = rel.eta_impulse_n_s_per_v
        self._conv = ExpConvState(rel.r_per_s)
        self._t_prev_s: Optional[float] = None  # previous sample, for the Kelvin-Voigt slope
        self._gamma_prev_v = 0.0

    def reset(self) -> None:
        """Forget the deformation history (sensor assumed relaxed and unloaded)."""
        self._conv.reset()
        self._t_prev_s = None

    @property
    def last_time_s(self) -> Optional[float]:
        """Stamp (s) of the last sample processed by step(), or None before the first one and after reset()."""
        return self._conv.t_prev_s if self._ar else self._t_prev_s

    def step(self, t_s: float, deformation_v: float, aux: object = None) -> Optional[float]:
        """Force for one sample, or None for a stamp before the previous one.

        Parameters
        ----------
        t_s : float
            Sample time [s]. A stamp equal to the previous one is a zero-length step.
        deformation_v : float
            Deformation [V] (bridge volts above offset).
        aux : object, optional
            Not used (the signature of a chain element's stream).

        Returns
        -------
        float or None
            Force [N], compression positive; None, with the state left untouched, when
            ``t_s`` is earlier than the previous sample's stamp.
        """
        # The convolution state has seen every accepted stamp (and is reset with this object), so
        # its refusal of a stamp before its previous one is exactly the "earlier than the previous
        # sample" test: one comparison per sample, and it narrows ``y`` for the loop below.
        y = self._conv.update(t_s, deformation_v)
        if y is None:
            return None
        t_prev = self._t_prev_s
        force = self._g0 * deformation_v
        for ar, yk in zip(self._ar, y):
            force -= ar * yk
        if self._eta and t_prev is not None and t_s > t_prev:
            force += self._eta * (deformation_v - self._gamma_prev_v) / (t_s - t_prev)
        self._t_prev_s, self._gamma_prev_v = t_s, deformation_v
        return force
