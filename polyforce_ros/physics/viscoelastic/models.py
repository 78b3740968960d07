"""Linear viscoelastic sensor models (seed 000, section IV): creep compliance and relaxation modulus.

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
                             forward simulation (:mod:`.superposition`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any, ClassVar, Iterable, Optional, Sequence, TypeVar, Union

import numpy as np
import numpy.typing as npt

__all__ = ["CreepCompliance", "RelaxationModulus", "ViscoelasticModel", "Elastic", "Maxwell", "KelvinVoigt", "Zener",
    "Burgers", "Zener2", "Burgers2", "MODEL_TYPES", "PAPER_BURGERS", "polynomial_product"]

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
    den = np.polymul(flow, polynomial_product(factors))
    num: npt.NDArray[np.floating[Any]] = comp.j0_v_per_n * den
    for k, c in enumerate(comp.c_v_per_n):
        num = np.polyadd(num, c * np.polymul(flow, polynomial_product(factors[:k] + factors[k + 1:])))
    if comp.fluidity_v_per_n_s:
        num = np.polyadd(num, comp.fluidity_v_per_n_s * polynomial_product(factors))
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


def _kelvin_chain_compliance(k1_n_per_v: float, kelvins: Sequence[tuple[float, float]],
                             fluidity_v_per_n_s: float = 0.0) -> CreepCompliance:
    """J(t) of spring k1 + Kelvin elements (k_i, eta_i) in series [+ a free dashpot]."""
    return CreepCompliance(1.0 / k1_n_per_v, tuple(1.0 / k for k, _ in kelvins), tuple(eta / k for k, eta in kelvins),
                           fluidity_v_per_n_s)


def _two_kelvin_compliance(model: Union[Zener2, Burgers2], fluidity_v_per_n_s: float = 0.0) -> CreepCompliance:
    """J(t) of spring k1 + Kelvin (k2, eta2) + Kelvin (k3, eta3) [+ a free dashpot]."""
    return _kelvin_chain_compliance(model.k1_n_per_v, ((model.k2_n_per_v, model.eta2_n_s_per_v),
                                                       (model.k3_n_per_v, model.eta3_n_s_per_v)), fluidity_v_per_n_s)


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


@dataclass(frozen=True)
class Zener3(ViscoelasticModel):
    """Spring k1 in series with three Kelvin elements (k2, eta2), (k3, eta3) and (k4, eta4): a solid with three
    retardation times (a spread retardation spectrum)."""

    kind: ClassVar[str] = "zener3"
    shape: ClassVar[tuple[int, bool, bool]] = (3, True, False)
    k1_n_per_v: float
    k2_n_per_v: float
    eta2_n_s_per_v: float
    k3_n_per_v: float
    eta3_n_s_per_v: float
    k4_n_per_v: float
    eta4_n_s_per_v: float

    def compliance(self) -> CreepCompliance:
        """The creep compliance J(t) = 1/k1 + sum over the three Kelvin elements of (1/k_i) (1 - exp(-t k_i/eta_i))
        in V/N.

        Returns
        -------
        CreepCompliance
            j0 = 1/k1 [V/N] and three retarded terms c_i = 1/k_i [V/N] with tau_i = eta_i/k_i [s].
        """
        return _kelvin_chain_compliance(self.k1_n_per_v, ((self.k2_n_per_v, self.eta2_n_s_per_v),
                                                          (self.k3_n_per_v, self.eta3_n_s_per_v),
                                                          (self.k4_n_per_v, self.eta4_n_s_per_v)))

    def relaxation(self) -> RelaxationModulus:
        """The relaxation modulus G(t) in N/V from the compliance via Laplace (three exponentials).

        Raises ValueError if the rates come out complex or non-negative.
        """
        return _relaxation_from_compliance(self.compliance())


@dataclass(frozen=True)
class Burgers3(ViscoelasticModel):
    """Burgers (k1, eta1, Kelvin k2/eta2) with two more Kelvin elements (k3, eta3) and (k4, eta4): a fluid with
    three retardation times."""

    kind: ClassVar[str] = "burgers3"
    shape: ClassVar[tuple[int, bool, bool]] = (3, True, True)
    k1_n_per_v: float
    k2_n_per_v: float
    eta1_n_s_per_v: float
    eta2_n_s_per_v: float
    k3_n_per_v: float
    eta3_n_s_per_v: float
    k4_n_per_v: float
    eta4_n_s_per_v: float

    def compliance(self) -> CreepCompliance:
        """The creep compliance J(t) = 1/k1 + t/eta1 + sum over the three Kelvin elements of
        (1/k_i) (1 - exp(-t k_i/eta_i)) in V/N.

        Returns
        -------
        CreepCompliance
            j0 = 1/k1 [V/N], three retarded terms c_i = 1/k_i [V/N] with tau_i = eta_i/k_i [s], and
            fluidity 1/eta1 [V/(N*s)].
        """
        return _kelvin_chain_compliance(self.k1_n_per_v, ((self.k2_n_per_v, self.eta2_n_s_per_v),
                                                          (self.k3_n_per_v, self.eta3_n_s_per_v),
                                                          (self.k4_n_per_v, self.eta4_n_s_per_v)),
                                        1.0 / self.eta1_n_s_per_v)

    def relaxation(self) -> RelaxationModulus:
        """The relaxation modulus G(t) in N/V from the compliance via Laplace (four exponentials: a fluid).

        Raises ValueError if the rates come out complex or non-negative.
        """
        return _relaxation_from_compliance(self.compliance())


MODEL_TYPES: dict[str, type[ViscoelasticModel]] = {
    cls.kind: cls for cls in (Elastic, Maxwell, KelvinVoigt, Zener, Burgers, Zener2, Burgers2, Zener3, Burgers3)
}

#: Seed 000, eq. 5: the Burgers parameters identified from the 5 N creep test.
PAPER_BURGERS = Burgers(k1_n_per_v=4.8, k2_n_per_v=10.0, eta1_n_s_per_v=4627.94, eta2_n_s_per_v=85.12)


def polynomial_product(factors: Iterable[npt.NDArray[np.floating[Any]]]) -> npt.NDArray[np.floating[Any]]:
    """The product of polynomials given by their coefficients, highest power first (as :func:`numpy.polymul`)."""
    out: npt.NDArray[np.floating[Any]] = np.ones(1)
    for f in factors:
        out = np.polymul(out, f)
    return out
