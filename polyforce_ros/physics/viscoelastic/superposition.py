"""Boltzmann superposition of a linear viscoelastic model: forward (force -> deformation volts) and backward
(deformation volts -> force) runs over a record, and the per-sample backward stream.

Both directions rest on :mod:`polyforce_ros.physics.expconv`, exact for piecewise-linear signals and stable for
any record length (seed 000, eq. 10-12). The sensor is taken to be unloaded and relaxed before the first sample.
"""
from __future__ import annotations

from typing import Optional

import numpy as np
import numpy.typing as npt
from scipy import linalg, signal

from ..expconv import (ExpConvState, exp_convolve, exp_convolve_columns, step_weights, step_weights_scalar,
                       uniform_step_after)
from .models import RelaxationModulus, ViscoelasticModel, polynomial_product

__all__ = ["simulate_deformation", "simulate_deformation_columns", "ForwardState", "compensate", "BackwardState",
           "StreamingCompensator"]


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
        num = rel.g_inf_n_per_v * polynomial_product(factors)
        weighted = np.zeros(1)
        for k in range(a.size):
            term = (a[k] * e[k] + c[k] * alpha[k]) * polynomial_product(factors[:k] + factors[k + 1:])
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
        force: npt.NDArray[np.float64]
        force, zf = signal.sosfilt(self.sos, g_v, zi=zi)
        amp_end = self.residues.T @ zf[:, 0]
        y_end = (-amp_end / self.ar - h * self.alpha * g_v[-1]) / self.e
        state.y = np.empty_like(y_end)
        state.y[self.order] = y_end
        return force



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

    def affine(self, t_s: float, aux: object = None) -> Optional[tuple[float, float]]:
        """The next :meth:`step` at ``t_s`` as an affine map of its deformation, without advancing the state.

        ``step(t_s, d)`` returns ``force0_n + stiffness_n_per_v * d`` for every ``d``: an element that adds
        to the deformation a term depending on the force (hysteresis at the bridge) solves for the force with
        it before it steps.

        Parameters
        ----------
        t_s : float
            Stamp of the next sample [s].
        aux : object, optional
            Ignored (the signature of every core stream's ``affine``).

        Returns
        -------
        (float, float) or None
            ``(force0_n, stiffness_n_per_v)`` [N, N/V]; None when ``t_s`` is earlier than the previous sample.
        """
        conv = self._conv
        if conv.t_prev_s is None:  # the first sample only initialises the convolution: its state does not move
            state = [(yk, 0.0) for yk in conv.y]
        else:
            h = t_s - conv.t_prev_s
            if h < 0.0:
                return None
            state = []
            for r, yk in zip(conv.rates_per_s, conv.y):
                e, alpha, beta = step_weights_scalar(r * h)
                state.append((e * yk + h * alpha * conv.u_prev, h * beta))
        force0, stiffness = 0.0, self._g0
        for ar, (y0, dy) in zip(self._ar, state):
            force0 -= ar * y0
            stiffness -= ar * dy
        t_prev = self._t_prev_s
        if self._eta and t_prev is not None and t_s > t_prev:
            force0 -= self._eta * self._gamma_prev_v / (t_s - t_prev)
            stiffness += self._eta / (t_s - t_prev)
        return force0, stiffness

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
