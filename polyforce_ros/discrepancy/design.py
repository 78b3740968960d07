"""Model structures, their design matrices and their cross-validated fits, and the chain a fit becomes.

A :class:`Structure` (core type, retardation times, effect terms) is linear in its coefficients: its design
columns (:func:`design`) are the core's compliance terms and the columns of each effect of the catalogue
(:mod:`.effects`), filtered by a sensor lag when the structure holds one. A :class:`Fitter` fits any structure on
one record with each cross-validation fold left out in turn, from per-fold normal matrices (:class:`Fit`);
:func:`build_chain` turns the coefficients into the model-file chain.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace
from functools import partial
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence, cast

import numpy as np
import numpy.typing as npt
from scipy import linalg, optimize

from ..physics.chain import (BridgeHysteresisElement, Element, KneeKelvinElement, OffsetElement, PowerFlowElement,
                             SensorChain, ThermoRheologicalElement, ViscoelasticElement, lagged_temperature_c,
                             reduced_time_s)
from ..physics.fitting import LOG_BOUNDS, TAU_GRID_S, TAU_LOG_BOUNDS, block_jackknife_standard_errors, information_criteria
from ..physics.viscoelastic import MODEL_TYPES, KelvinVoigt, ViscoelasticModel, simulate_deformation
from .columns import Col, lag_columns, parameter
from .effects import EFFECTS as REGISTRY, PLAY_RIDGE, clock_of, clock_shift_per_c, knee_beside, lag_stages, volume_beside
from .signals import BoolArray, FloatArray, IntArray, Signals

__all__ = ["BASES", "BLOCKS_PER_FOLD", "CORE_SHAPE", "TAU_GRID", "TAU_BOUNDS", "Term", "Structure", "Design", "design",
           "design_columns", "stack", "Fit", "fold_of", "Fitter", "bounded_solve", "core_model", "build_chain",
           "refresh_ref", "n_params", "size"]

BASES = tuple(MODEL_TYPES)  # every core type the fitting stack knows
#: The design's name of the decay of a fast retardation after a gap (:class:`.signals.GapStep`).
GAP_DECAY = re.compile(r"gap\d+_c\d+")
#: Contiguous time blocks dealt to each cross-validation fold (interleaved): a left-out block (but the record's
#: first and last) lies between blocks that are fitted, so a term that follows time is judged on how it
#: interpolates, not extrapolates.
BLOCKS_PER_FOLD = 3
#: Number of retardation times of each core type, and whether it has instantaneous compliance / flow.
CORE_SHAPE = {kind: cls.shape for kind, cls in MODEL_TYPES.items()}  # declared by the model types
TAU_GRID, TAU_BOUNDS = TAU_GRID_S, TAU_LOG_BOUNDS  # physics/fitting.py declares them


# ----------------------------------------------------------------------------- model structures

@dataclass(frozen=True)
class Term:
    """An effect in a structure: its name, variant and the value of its nonlinear parameter (None: none)."""

    effect: str
    variant: str = ""
    param: float | None = None


@dataclass(frozen=True)
class Structure:
    """A model: the core type, its retardation times [s] and the effects added to it."""

    core: str
    taus: tuple[float, ...] = ()
    terms: tuple[Term, ...] = ()

    @property
    def effects(self) -> list[str]:
        """The names of the effects added, in order."""
        return [t.effect for t in self.terms]

    def term(self, effect: str) -> Optional[Term]:
        """The term of ``effect`` (None when the structure does not hold it)."""
        return next((t for t in self.terms if t.effect == effect), None)


def _core_columns(sig: Signals, kind: str, taus: Sequence[float], shift_per_c: Optional[float] = None,
                  lag_s: float = 0.0, wlf_c2_c: float = 0.0) -> list[Col]:
    """The core's compliance columns; with ``shift_per_c`` (a thermo-rheological core) on the reduced time, the
    clock of viscosities that follow temperature (:func:`~polyforce_ros.physics.chain.reduced_time_s`, bent by
    ``wlf_c2_c``): the thermometer's, or the core's own ``lag_s`` behind it."""
    n_tau, inst, flow = CORE_SHAPE[kind]
    clock = sig.t
    if shift_per_c is not None:
        temp = sig.temperature if lag_s <= 0.0 else lagged_temperature_c(sig.t, sig.temperature, lag_s)
        clock = reduced_time_s(sig.t, temp, shift_per_c, sig.temp_ref, wlf_c2_c)
    cols: list[Col] = []
    if inst:
        cols.append(("j0", sig.f, 0.0, np.inf, "sensor", None))
    if flow:
        cols.append(("phi", _integral(clock, sig.f), 0.0, np.inf, "sensor", None))
    for i, tau in enumerate(taus[:n_tau]):
        cols.append((f"c{i}", lag_columns(clock, sig.f, tau), 0.0, np.inf, "sensor", None))
    return cols


def _integral(t: FloatArray, f: FloatArray) -> FloatArray:
    from ..physics.expconv import exp_convolve

    out: FloatArray = exp_convolve(t, f, [0.0])[:, 0]
    return out


def _cached(sig: Signals, key: Any, make: Callable[[], Iterable[Col]]) -> list[Col]:
    """Design columns ``make()`` (tuples of name, column, ...), made once per signals and kept contiguous (a column
    of a 2-D basis is a strided view, slow to copy at every evaluation)."""
    if key not in sig.cache:
        sig.cache[key] = [(c[0], np.ascontiguousarray(c[1], dtype=float), *c[2:]) for c in make()]
    cols: list[Col] = sig.cache[key]
    return cols


def term_columns(sig: Signals, term: Term) -> list[Col]:
    """The design columns of an effect's ``term`` on these signals (:attr:`.effects.Effect.columns`), made once per
    signals; before a sensor lag filters its ``sensor`` columns (:func:`design_columns`)."""
    eff = REGISTRY[term.effect]
    return _cached(sig, (term.effect, term.variant, term.param), partial(eff.columns, sig, term.variant, term.param))


#: A structure's design on one record: (column names, the columns, lower bounds, upper bounds, ridge mask).
Design = tuple[list[str], list[FloatArray], FloatArray, FloatArray, BoolArray]


def design(sig: Signals, st: Structure, extra: Sequence[Col] = ()
           ) -> tuple[list[str], FloatArray, FloatArray, FloatArray, BoolArray]:
    """(names, A, lower, upper, ridge group mask) of a structure on these signals, with the additive columns
    ``extra`` beside it (a rival that is no effect of the catalogue)."""
    names, mats, lo, hi, ridge = design_columns(sig, st, extra)
    return names, stack(mats), lo, hi, ridge


def predict(sig: Signals, st: Structure, coef: Mapping[str, float]) -> FloatArray:
    """The prediction of structure ``st`` on ``sig`` with coefficients ``coef`` by column name (a column it does not
    name counts as zero) [V]."""
    names, a, *_ = design(sig, st)
    out: FloatArray = a @ np.array([coef.get(n, 0.0) for n in names])
    return out


def fitted(sig: Signals, fit: Fit) -> FloatArray:
    """``fit``'s prediction on ``sig`` (the signals its columns were made on) with the coefficients fitted on every
    block [V]."""
    return predict(sig, fit.structure, fit.coef_map)


_ALL_ROWS = slice(None)


def stack(columns: Sequence[FloatArray], rows: slice = _ALL_ROWS) -> FloatArray:
    """The columns (rows ``rows`` of each) as one column-major matrix: each column is one contiguous copy
    (``np.column_stack`` writes row-major, a strided store per element, which costs a fifth of a diagnosis)."""
    first = columns[0][rows]
    a = np.empty((first.size, len(columns)), order="F")
    for j, c in enumerate(columns):
        a[:, j] = c[rows]
    return a


def _gap_columns(sig: Signals) -> list[tuple[str, FloatArray, float]]:
    """(name, column, bound) of the record after each gap that hid load history (:attr:`.signals.Signals.gap_steps`):
    a step, and the decay of each base retardation fast enough to forget the hidden load within the record."""
    gaps: list[tuple[str, FloatArray, float]] = []
    for k, gap in enumerate(sig.gap_steps):
        after = sig.t >= gap.at_s
        if gap.step_bound_v > 0.0:
            gaps.append((f"gap{k}", np.where(after, 1.0, 0.0), gap.step_bound_v))
        for i, (tau, bound_v) in enumerate(zip(gap.decay_taus_s, gap.decay_bounds_v())):
            if bound_v > 0.0:
                decay = np.where(after, np.exp(-np.clip(sig.t - gap.at_s, 0.0, None) / tau), 0.0)
                gaps.append((f"gap{k}_c{i}", decay, bound_v))  # named as GAP_DECAY matches
    return gaps


def design_columns(sig: Signals, st: Structure, extra: Sequence[Col] = ()) -> Design:
    """:func:`design` with the columns of A as a list of arrays (not stacked: the polish needs a few rows)."""
    shift = st.term("thermo_rheological")
    b = None if shift is None else clock_shift_per_c(shift.variant, shift.param)
    lag_s, c2 = (0.0, 0.0) if shift is None else clock_of(shift.variant)
    cols = list(_cached(sig, ("core", st.core, st.taus, b, lag_s, c2),
                        lambda: _core_columns(sig, st.core, st.taus, b, lag_s, c2)))
    lag: Optional[list[float]] = None
    delay_s = 0.0
    for term in st.terms:
        if term.effect == "sensor_lag":
            lag = lag_stages(term.variant, parameter(term.param))
            delay_s = parameter(term.param) if term.variant == "delay" else 0.0
            continue
        cols += term_columns(sig, term)
    cols += list(extra)
    if ("gaps", sig.gap_steps) not in sig.cache:  # the same for every structure: made once per signals
        sig.cache[("gaps", sig.gap_steps)] = _gap_columns(sig)
    gaps: list[tuple[str, FloatArray, float]] = sig.cache[("gaps", sig.gap_steps)]
    names = [c[0] for c in cols] + ["offset"] + [g[0] for g in gaps]
    mats = []
    for c in cols:
        x = np.asarray(c[1], dtype=float)
        if lag is not None and c[4] == "sensor":
            for tau in lag:
                x = lag_columns(sig.t, x, tau)
            if delay_s > 0.0:  # the column as it was delay_s earlier, settled before the record
                x = np.interp(sig.t - delay_s, sig.t, x, left=x[0])
        mats.append(x)
    mats.append(np.ones_like(sig.t))
    mats += [g[1] for g in gaps]
    lo = np.array([c[2] for c in cols] + [-np.inf] + [-g[2] for g in gaps])
    hi = np.array([c[3] for c in cols] + [np.inf] + [g[2] for g in gaps])
    ridge = np.array([c[5] is not None for c in cols] + [False] * (1 + len(gaps)))  # ridge groups: play weights, knots
    return names, mats, lo, hi, ridge


# ----------------------------------------------------------------------------- cross-validated fits

@dataclass
class Fit:
    """A structure fitted on one record, with each cross-validation fold left out in turn.

    Attributes
    ----------
    structure : Structure
    names : list of str
        The design's column names.
    scale : ndarray
        The columns' RMS (the solves run on unit-RMS columns).
    coef : ndarray
        Coefficients fitted on all blocks, natural units of the columns.
    coef_folds : list of ndarray
        One coefficient vector per left-out fold.
    sse_folds : ndarray
        Out-of-sample SSE per fold [V^2] (fit rate).
    cv_mse, fit_mse : float
        Out-of-sample and in-sample mean squared error [V^2].
    n : int
        Samples scored.
    bic : float
        Bayesian information criterion of the in-sample fit.
    """

    structure: Structure
    names: list[str]
    scale: FloatArray
    coef: FloatArray
    coef_folds: list[FloatArray]
    sse_folds: FloatArray
    cv_mse: float
    fit_mse: float
    n: int
    bic: float = 0.0

    @property
    def coef_map(self) -> dict[str, float]:
        """Coefficient by column name."""
        return dict(zip(self.names, self.coef))

    def coefficients(self) -> dict[str, dict[str, float]]:
        """Each fitted coefficient (units of its design column) with its standard error by the block
        jackknife over the cross-validation folds."""
        errors = block_jackknife_standard_errors(self.coef_folds)
        return {name: {"value": float(c), "standard_error": float(e)}
                for name, c, e in zip(self.names, self.coef, errors)}


def fold_of(t_s: npt.ArrayLike, t0_s: float, duration_s: float, n_folds: int,
            blocks_per_fold: int = BLOCKS_PER_FOLD) -> IntArray:
    """Fold (0..n_folds-1) of each time in ``t_s`` (s): the record is cut into ``n_folds * blocks_per_fold``
    contiguous blocks of equal length, dealt to the folds in turn (block j belongs to fold j mod n_folds)."""
    u = (np.asarray(t_s, dtype=float) - t0_s) / max(duration_s, 1e-9)
    n_blocks = n_folds * blocks_per_fold
    folds: IntArray = np.clip((u * n_blocks).astype(int), 0, n_blocks - 1) % n_folds
    return folds


def _total(terms: Iterable[FloatArray]) -> FloatArray:
    """The builtin ``sum`` of arrays, left to right from 0 (the first term's values exactly)."""
    return cast(FloatArray, sum(terms))


class Fitter:
    """Per-fold normal matrices and bounded solves for any structure on one record (fit rate).

    ``sig`` is the record at the fit rate; the stages replace it when they change the reference core.
    """

    def __init__(self, sig: Signals, n_folds: int, blocks_per_fold: int = BLOCKS_PER_FOLD) -> None:
        self.sig = sig
        self.fold = fold = fold_of(sig.t, sig.t0, sig.duration_s, n_folds, blocks_per_fold)
        self.k, self.blocks_per_fold = n_folds, blocks_per_fold
        # each fold is a few contiguous runs of rows: slices (no copies)
        edges = np.flatnonzero(np.diff(fold)) + 1
        starts, stops = np.r_[0, edges], np.r_[edges, fold.size]
        self.rows = [[slice(int(a), int(b)) for a, b in zip(starts, stops) if fold[a] == k] for k in range(n_folds)]
        self.evaluations = 0

    def evaluate(self, st: Structure, extra: Sequence[Col] = ()) -> Fit:
        """Fit ``st`` (with the additive columns ``extra`` beside it) on all blocks and with each fold left out; score
        each fold out of sample."""
        self.evaluations += 1
        names, a, lo, hi, ridge = design(self.sig, st, extra)
        v = self.sig.v
        if self.sig.valid is not None and not self.sig.valid.all():  # empty bins count for nothing
            a = a * self.sig.valid[:, None]
            v = v * self.sig.valid
        raw = []
        for runs in self.rows:
            ab = [a[r] for r in runs]
            vb = [v[r] for r in runs]
            raw.append((_total(x.T @ x for x in ab), _total(x.T @ y for x, y in zip(ab, vb)),
                        float(sum(y @ y for y in vb))))
        scale = np.sqrt(np.diag(_total(g for g, _, _ in raw)) / max(v.size, 1))  # columns scaled to unit RMS
        scale[~(scale > 0)] = 1.0
        grams = [(g / np.outer(scale, scale), h / scale, vv) for g, h, vv in raw]
        g_all = _total(g for g, _, _ in grams)
        h_all = _total(h for _, h, _ in grams)
        vv_all = sum(w for _, _, w in grams)
        lo_s, hi_s = lo * scale, hi * scale
        reg = PLAY_RIDGE * float(np.trace(g_all)) / g_all.shape[0] * ridge.astype(float)
        coef = bounded_solve(g_all, h_all, lo_s, hi_s, reg)
        fit_sse = float(coef @ g_all @ coef - 2 * h_all @ coef + vv_all)
        # a gap's decays are nuisances of the record that live within the block after the gap: every fold keeps the
        # values fitted on all blocks (the same for every model), or the fold that leaves that block out has nothing
        # to fit them on
        fixed = np.array([GAP_DECAY.fullmatch(name) is not None for name in names])
        free = ~fixed
        folds, sse = [], []
        for g, h, vv in grams:
            g_in, h_in = g_all - g, h_all - h
            c = coef.copy()
            c[free] = bounded_solve(g_in[np.ix_(free, free)], h_in[free] - g_in[np.ix_(free, fixed)] @ coef[fixed],
                                    lo_s[free], hi_s[free], reg[free] * (1 - 1.0 / self.k))
            folds.append(c / scale)
            sse.append(max(float(c @ g @ c - 2 * h @ c + vv), 0.0))
        n = v.size if self.sig.valid is None else int(self.sig.valid.sum())
        fit = Fit(st, names, scale, coef / scale, folds, np.array(sse), float(np.sum(sse) / n), max(fit_sse, 0.0) / n, n)
        fit.bic = information_criteria(max(fit_sse, 1e-300), n, n_params(fit))[1]
        return fit


def bounded_solve(g: FloatArray, h: FloatArray, lo: FloatArray, hi: FloatArray, reg: FloatArray) -> FloatArray:
    """The bounded least-squares solution of the normal equations ``(g + diag(reg)) c = h``, ``lo <= c <= hi``."""
    pinned = ~(lo < hi)  # bounds that meet (a bound scaled below the float range): the coefficient is the bound
    if pinned.any():
        c = np.where(pinned, np.nan_to_num(lo, posinf=0.0, neginf=0.0), 0.0)
        free = ~pinned
        if free.any():
            c[free] = bounded_solve(g[np.ix_(free, free)], h[free] - g[np.ix_(free, pinned)] @ c[pinned], lo[free],
                                    hi[free], reg[free])
        return cast(FloatArray, c)
    p = g.shape[0]
    g = g + np.diag(reg) + (1e-12 * float(np.trace(g)) / p + 1e-300) * np.eye(p)
    try:
        chol = linalg.cholesky(g, lower=True)
    except linalg.LinAlgError:
        g = g + 1e-8 * float(np.trace(g)) / p * np.eye(p)
        chol = linalg.cholesky(g, lower=True)
    b = linalg.solve_triangular(chol, h, lower=True)
    if np.all(np.isinf(lo)) and np.all(np.isinf(hi)):
        return cast(FloatArray, linalg.solve_triangular(chol.T, b, lower=False))
    return cast(FloatArray, optimize.lsq_linear(chol.T, b, bounds=(lo, hi), method="bvls").x)


def n_params(fit: Fit) -> int:
    """Free parameters of a fit: non-zero coefficients and nonlinear time constants."""
    st = fit.structure
    return int(np.count_nonzero(fit.coef)) + len(st.taus) + sum(t.param is not None for t in st.terms)


def size(fit: Fit) -> int:
    """Nominal size of a structure: its design columns and nonlinear time constants (whatever values they took).

    A delayed elasticity that takes all of the instantaneous compliance is a sensor lag in disguise; counted
    by its non-zero coefficients it would look as small as the lag."""
    st = fit.structure
    return len(fit.names) + len(st.taus) + sum(t.param is not None for t in st.terms)


# ----------------------------------------------------------------------------- the reference core and the chain

def core_model(st: Structure, coef: Mapping[str, float]) -> ViscoelasticModel:
    """The viscoelastic model of the fitted compliances (zero compliance -> the stiffest bound)."""
    kmax = math.exp(LOG_BOUNDS[1])
    kmin = math.exp(LOG_BOUNDS[0])

    def stiff(c: float) -> float:
        return float(np.clip(1.0 / c, kmin, kmax)) if c > 0 else kmax

    k1 = stiff(coef.get("j0", 0.0))
    eta1 = stiff(coef.get("phi", 0.0))
    kel = [(stiff(coef.get(f"c{i}", 0.0)), tau) for i, tau in enumerate(st.taus)]
    kel = [(k, float(np.clip(k * tau, kmin, kmax))) for k, tau in kel]
    kind = st.core
    model: Callable[..., ViscoelasticModel] = MODEL_TYPES[kind]
    if kind == "elastic":
        return model(k1)
    if kind == "maxwell":
        return model(k1, eta1)
    if kind == "kelvin":
        return KelvinVoigt(*kel[0])
    if kind == "zener":
        return model(k1, *kel[0])
    if kind == "burgers":
        return model(k1, kel[0][0], eta1, kel[0][1])
    if kind in ("zener2", "zener3"):
        return model(k1, *(x for k in kel for x in k))
    return model(k1, kel[0][0], eta1, kel[0][1], *(x for k in kel[1:] for x in k))


def build_chain(st: Structure, coef: Mapping[str, float], sig: Signals) -> SensorChain:
    """Model-file chain: [force-path hysteresis] core [gain, voltage-path hysteresis] [lag] [thermal, drift] offset.
    The core is the fitted one, on the reduced time when viscosities follow temperature, beside a power-law dashpot
    and a knee unit when those are named, with plays beside it at the bridge."""
    slots: dict[str, list[Element]] = {"before": [], "core": [], "bridge": [], "after": [], "lag": [], "late": []}
    for term in st.terms:
        for slot, element in REGISTRY[term.effect].to_elements(coef, term.variant, term.param, sig):
            slots[slot].append(element)
    slots["after"].sort(key=lambda e: 0 if e.kind == "nonlinear_gain" else 1)
    fitted = ViscoelasticElement(core_model(st, coef))
    shifted = [e for e in slots["core"] if isinstance(e, ThermoRheologicalElement)]
    if shifted:  # viscosities that follow temperature: the fitted core on the reduced time
        fitted = ThermoRheologicalElement(fitted, shifted[0].shift_per_c, shifted[0].reference_c,
                                          shifted[0].temperature_lag_s, shifted[0].wlf_c2_c)
    flows = [e for e in slots["core"] if isinstance(e, PowerFlowElement)]
    if flows:  # a power-law dashpot beside the fitted core (on its clock's core, shifted or not)
        flow = flows[0]
        if flow.flow_volume_rates_v_per_n_s:  # with the fitted core's own fluidity, never a negative one
            fitted = volume_beside(fitted, flow.flow_volume_scale_n_s, flow.flow_volume_rates_v_per_n_s)
        else:
            fitted = PowerFlowElement(fitted, flow.flow_rate_v_per_s, flow.flow_exponent, flow.flow_force_scale_n,
                                      flow.flow_yield_n)
    knees = [e for e in slots["core"] if isinstance(e, KneeKelvinElement)]
    if knees:  # a Kelvin unit that only the force above a knee loads, beside the fitted core (flowing or not)
        k = knees[0]
        fitted = knee_beside(fitted, k.knees_n, list(k.knee_compliances_v_per_n), k.knee_tau_s)
    core: Element = fitted
    bridges = [e for e in slots["bridge"] if isinstance(e, BridgeHysteresisElement)]
    if bridges:  # hysteresis at the bridge (one term per effect, so one element): the fitted core, plays beside it
        b = bridges[0]
        core = b.with_core(fitted)
    return SensorChain([*slots["before"], core, *slots["after"], *slots["lag"], *slots["late"],
                        OffsetElement(float(np.clip(coef.get("offset", 0.0), -1e3, 1e3)))])


def refresh_ref(sig: Signals, core: ViscoelasticModel, span_x: Optional[float] = None) -> Signals:
    """``sig`` with ``core`` as the reference core: its output ``x_ref`` and, unless ``span_x`` is given (the record at
    another rate takes the fit rate's), the play radii's span from it. Radii that kept an earlier core's span would
    drift against the signal when a voltage-path hysteresis takes part of the core's gain (a play of small radius is
    nearly the input itself): each settling round would fit worse, and the loss be named as a drift."""
    x = simulate_deformation(core, sig.t, sig.f_nonlinear)
    return replace(sig, core_ref=core, x_ref=x, span_x=span_x if span_x is not None else max(float(np.ptp(x)), 1e-9))
