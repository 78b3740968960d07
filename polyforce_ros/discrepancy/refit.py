"""The nonlinear side of a fit and the structures a selection step tries.

:func:`polish` refits the few nonlinear parameters of a structure (the core's retardation times, a lag's, a
thermal lag's, a settling drift's, a clock's slope and lag) by multi-start least squares; :func:`settle` and :func:`refine`
make the columns that follow the core consistent with the core they fit. :func:`base_structure` fits the base core,
:func:`candidates_for` lists the structures that add one effect, :func:`without` removes one.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import replace
from typing import Optional

import numpy as np
from scipy import optimize

from ..physics.fitting import multistart_least_squares
from .design import (CORE_SHAPE, TAU_BOUNDS, TAU_GRID, Fit, Fitter, Structure, Term, bounded_solve, core_model,
                     design_columns, refresh_ref, stack)
from .columns import TEMPERATURE_LAG_BOUNDS_S, parameter
from .effects import EFFECTS as REGISTRY, KNEE_FRACTIONS, PLAY_RIDGE, SPREAD_RATIO, clock_lag_variant, clock_of, clock_sign
from .friction import band_lag_s, band_lag_variant
from .signals import FloatArray, Signals

__all__ = ["polish", "is_core_time", "param_log_bounds", "settle", "refine", "without", "base_structure", "candidates_for"]

#: The bounds of a clock's and of a friction band's temperature lag in the polish [ln s].
TEMPERATURE_LAG_LOG_BOUNDS = (math.log(TEMPERATURE_LAG_BOUNDS_S[0]), math.log(TEMPERATURE_LAG_BOUNDS_S[1]))
#: The effects whose variant names a temperature lag the polish refines, in the order their lags are polished.
LAGGED_EFFECTS = ("thermo_rheological", "friction")


def polish(fitter: Fitter, st: Structure) -> Structure:
    """Polish the nonlinear parameters (the core's times, a lag's, a thermal lag's [s], a clock's slope [1/degC] and
    lag [s], a friction band's lag [s]) by multi-start least squares in log space."""
    idx = [("core", i) for i in range(len(st.taus))]
    # a core effect's parameter (a delayed elasticity's time) is one of the core's times, not a column's: it is not
    # polished on its own (it would stay at its grid value while the core's time moves, and without() drops the core
    # time nearest to it) but follows the core time it names
    own_tau = {k: int(np.argmin([abs(math.log(tau / parameter(t.param))) for tau in st.taus]))
               for k, t in enumerate(st.terms) if is_core_time(t) and st.taus}
    idx += [("term", k) for k, t in enumerate(st.terms) if t.param is not None and not is_core_time(t)]
    # a clock's temperature lag is named by its variant (lag15) and refined beside the clock's parameter, and so is a
    # friction band's (thermal_lag15): the core's or the guide's temperature trails the thermometer's by however long
    # its part takes to warm, not by a grid value
    idx += [("temperature lag", k) for effect in LAGGED_EFFECTS for k, t in enumerate(st.terms)
            if t.effect == effect and _temperature_lag_s(t) > 0.0]
    if not idx:
        return st
    x0 = np.log([st.taus[i] if kind == "core" else _temperature_lag_s(st.terms[i]) if kind == "temperature lag"
                 else parameter(st.terms[i].param) for kind, i in idx])

    def make(theta: FloatArray, digits: int = 12) -> Structure:
        taus, terms = list(st.taus), list(st.terms)
        for (kind, i), th in zip(idx, theta):
            if kind == "core":
                taus[i] = float(math.exp(th))
            elif kind == "temperature lag":
                terms[i] = _with_temperature_lag(terms[i], math.exp(th), digits)
            else:
                terms[i] = replace(terms[i], param=float(math.exp(th)))
        for k, i in own_tau.items():
            terms[k] = replace(terms[k], param=taus[i])
        return Structure(st.core, tuple(taus), tuple(terms))

    sig = fitter.sig
    sub = slice(None, None, max(1, sig.t.size // 10000))  # at most ~10000 rows for the polish
    w = np.ones(sig.t.size) if sig.valid is None else sig.valid.astype(float)
    target = (sig.v * w)[sub]

    def residual(theta: FloatArray) -> FloatArray:
        s = make(theta)
        names, mats, lo, hi, ridge = design_columns(sig, s)
        # scaled by the whole record's RMS, but only the rows used are stacked: stacking every row at every
        # evaluation costs a third of a diagnosis
        scale = np.array([math.sqrt(float(m @ m) / m.size) for m in mats])
        scale[scale <= 0] = 1.0
        a = stack(mats, sub) / scale * w[sub, None]
        g, h = a.T @ a, a.T @ target
        reg = PLAY_RIDGE * float(np.trace(g)) / g.shape[0] * ridge.astype(float)
        c = bounded_solve(g, h, lo * scale, hi * scale, reg)
        out: FloatArray = a @ c - target
        return out

    # a retardation time longer than the record cannot be told from flow within it (its creep is still a
    # straight line at the end): bounded by the record, so that a missing dashpot is not fitted as a slow Kelvin
    longest = min(TAU_BOUNDS[1], math.log(max(fitter.sig.duration_s, 1.0)))
    bounds = [(TAU_BOUNDS[0], longest) if kind == "core" else TEMPERATURE_LAG_LOG_BOUNDS if kind == "temperature lag"
              else param_log_bounds(st.terms[i], sig) for kind, i in idx]
    lower, upper = np.array(bounds).T
    x0 = np.clip(x0, lower, upper)
    starts = [x0]
    for j, (kind, i) in enumerate(idx):
        if kind != "term":
            continue
        eff = REGISTRY[st.terms[i].effect]
        grid_variant = eff.grid_variant(st.terms[i].variant)
        if grid_variant in eff.extends:
            # a variant that extends a smaller one has that variant's optima too: start from each grid value
            for g in eff.grid(grid_variant, sig):
                if g is not None:
                    x = x0.copy()
                    x[j] = np.clip(math.log(g), lower[j], upper[j])
                    starts.append(x)
    sol = multistart_least_squares(residual, starts, lower, upper, max_nfev=8 * len(idx))
    return make(sol.x, digits=3)


def _temperature_lag_s(term: Term) -> float:
    """The temperature lag [s] a term's variant names: a thermo-rheological core's or a friction band's (0: none)."""
    if term.effect == "thermo_rheological":
        return clock_of(term.variant)[0]
    return band_lag_s(term.variant) if term.effect == "friction" else 0.0


def _with_temperature_lag(term: Term, lag_s: float, digits: int) -> Term:
    """``term`` whose variant names the temperature lag ``lag_s`` [s] (a clock keeps its sign), to ``digits``."""
    if term.effect == "friction":
        return replace(term, variant=band_lag_variant(lag_s, digits))
    return replace(term, variant=clock_lag_variant(lag_s, digits, slowing=clock_sign(term.variant) < 0))


def is_core_time(term: Term) -> bool:
    """Whether a term's parameter is one of the core's retardation times (a core effect's variant that adds them)."""
    return term.param is not None and term.variant in REGISTRY[term.effect].core_times


def param_log_bounds(term: Term, sig: Signals) -> tuple[float, float]:
    """Log bounds of a term's nonlinear parameter in the polish: the span of the effect's grid, which is where the
    parameter can be told apart in this record (a settling drift faster than a twentieth of the record is an offset
    step in the first block, one slower than the record its linear part; either left the split with the collinear
    column undetermined), or the time-constant bounds when the grid is a single value."""
    grid = [g for g in REGISTRY[term.effect].grid(term.variant, sig) if g is not None]
    if len(grid) < 2:
        return TAU_BOUNDS
    return math.log(min(grid)), math.log(max(grid))


def settle(fitter: Fitter, st: Structure, rounds: int = 2) -> Fit:
    """Fit ``st`` with the columns that follow the core (hysteresis, gain) made from the core it fits, so that the
    model scored is the model saved (:func:`.design.build_chain` places them after/before that core); ``rounds``
    refreshes, and a gain's fit is then taken to the point where the two cores are one
    (:func:`_gain_on_its_own_core`)."""
    fit = fitter.evaluate(st)
    for _ in range(rounds):
        fitter.sig = refresh_ref(fitter.sig, core_model(st, fit.coef_map))
        fit = fitter.evaluate(st)
    if st.term("nonlinear_gain") is not None:
        fit = _gain_on_its_own_core(fitter, st, fit)
    return fit


#: The core's compliances a reference core is made of (:func:`.design.core_model`), besides one per retardation time.
_CORE_COMPLIANCES = ("j0", "phi")


def _gain_on_its_own_core(fitter: Fitter, st: Structure, fit: Fit) -> Fit:
    """``fit`` with its reference core equal to its fitted core, when such a fit exists (else ``fit`` as given).

    The gain's columns are powers of the reference core's output, and the chain saved applies the fitted curve to
    the fitted core's output: the two are one model only where the fitted core is the reference core. Settling
    rounds need not reach that fixed point: powers of a one-signed output are nearly collinear, so the fit trades
    the core's compliances against large alternating coefficients and each round moves the core (the curve saved
    then predicts several times worse than the one scored). The fixed point is solved for directly: the compliances
    whose reference core the fit returns (:func:`scipy.optimize.root`, steps scaled to the settled values)."""
    keys = [k for k in (*_CORE_COMPLIANCES, *(f"c{i}" for i in range(len(st.taus)))) if k in fit.coef_map]
    start = np.array([fit.coef_map[k] for k in keys])
    if not keys or not np.all(np.isfinite(start)) or not np.max(np.abs(start)) > 0.0:
        return fit
    scale = np.maximum(np.abs(start), 1e-3 * float(np.max(np.abs(start))))
    sig0 = fitter.sig

    def fitted_less_reference(step: FloatArray) -> FloatArray:
        reference = start + scale * step
        fitter.sig = refresh_ref(sig0, core_model(st, {**fit.coef_map, **dict(zip(keys, reference))}))
        fitted = fitter.evaluate(st).coef_map
        out: FloatArray = (np.array([fitted.get(k, 0.0) for k in keys]) - reference) / scale
        return out

    found = False
    try:  # hybr's own verdict is not asked: "no good progress" near a fixed point is judged by the tolerance
        solution = optimize.root(fitted_less_reference, np.zeros(len(keys)), method="hybr",
                                 options={"maxfev": GAIN_CORE_EVALUATIONS * (len(keys) + 1)})
        found = float(np.max(np.abs(fitted_less_reference(solution.x)))) < GAIN_CORE_TOLERANCE
    finally:
        if not found:
            fitter.sig = sig0
    return fitter.evaluate(st) if found else fit


#: How far (a share of each compliance) the fitted core of a gain's fit may be from its reference core, and the
#: fits the search may make per compliance (it converges in about five; a search that does not gives up).
GAIN_CORE_TOLERANCE = 1e-6
GAIN_CORE_EVALUATIONS = 20


def refine(fitter: Fitter, st: Structure, rounds: int = 2) -> Fit:
    """Polish the time constants, then make the columns that follow the core (hysteresis, gain) consistent
    with the refitted core; ``rounds`` times. The polish fits in sample: when the result predicts the left-out
    blocks worse than the structure as given (e.g. a settling time shorter than a block, which no other block
    can pin down), the structure as given is kept. Either way the result is settled (:func:`settle`)."""
    sig0, given = fitter.sig, fitter.evaluate(st)
    polished = st
    for _ in range(rounds):
        polished = polish(fitter, polished)
        fit = fitter.evaluate(polished)
        fitter.sig = refresh_ref(fitter.sig, core_model(polished, fit.coef_map))
    if fitter.evaluate(polished).cv_mse > given.cv_mse:
        fitter.sig = sig0
        return settle(fitter, st)
    return settle(fitter, polished)


def without(st: Structure, effect: str) -> Optional[Structure]:
    """The structure without ``effect`` (None for a core effect other than viscous flow's dashpot)."""
    term = st.term(effect)
    if term is None:
        return None
    terms = tuple(t for t in st.terms if t.effect != effect)
    eff = REGISTRY[effect]
    if eff.core_change:
        back: Optional[str] = st.core
        reverse = {v: k for k, v in eff.core_change.items()}
        for _ in range(max(1, eff.core_times.get(term.variant, 1))):
            back = reverse.get(back) if back is not None else None
        if back is None:
            return None
        taus = st.taus
        # the times it added: the core time nearest its parameter, and each further one nearest a spread's start
        for k in range(eff.core_times.get(term.variant, 0)):
            if term.param is None or len(taus) <= CORE_SHAPE[back][0]:
                break
            at = term.param * SPREAD_RATIO ** k
            drop = int(np.argmin([abs(math.log(t / at)) for t in taus]))
            taus = tuple(t for i, t in enumerate(taus) if i != drop)
        return Structure(back, taus, terms)
    return Structure(st.core, st.taus, terms)


def base_structure(fitter: Fitter, base: str) -> Structure:
    """The base core's structure, its retardation times chosen on the grid (out of sample) and polished."""
    n_tau = CORE_SHAPE[base][0]
    if n_tau == 0:
        return Structure(base)
    grid: list[tuple[float, ...]]
    if n_tau == 1:
        grid = [(tau,) for tau in TAU_GRID]
    elif n_tau == 2:
        grid = [(a, b) for i, a in enumerate(TAU_GRID[::2]) for b in TAU_GRID[::2][i + 1:]]
    else:  # three Kelvin units: every three distinct times of every third grid value (20 starts)
        grid = list(itertools.combinations(TAU_GRID[::3], n_tau))
    best = min(grid, key=lambda taus: fitter.evaluate(Structure(base, taus)).cv_mse)
    return polish(fitter, Structure(base, best))


def candidates_for(st: Structure, effect: str, has_temperature: bool, sig: Signals) -> list[Structure]:
    """Structures that add ``effect`` to ``st`` (each variant, each grid value); [] when it does not apply."""
    eff = REGISTRY[effect]
    if eff.core_change:
        new = eff.core_change.get(st.core)
        if new is None:
            return []
        if effect == "viscous_flow":
            # the base's retardation times may have stood in for the flow: restart them from the grid too
            out = [Structure(new, st.taus, st.terms + (Term(effect),))]
            if len(st.taus) == 1:
                limit = sig.duration_s / 4.0
                out += [Structure(new, (tau,), st.terms + (Term(effect),)) for tau in TAU_GRID if tau <= limit]
            if not _bridge_hysteresis(st):  # the bridge's inverse solves its plays with a plain core beside them
                out += [Structure(new, st.taus, st.terms + (Term(effect, variant, p),))
                        for variant in eff.variants if variant for p in eff.grid(variant, sig)]
            return out
        out = []
        for variant, n_times in eff.core_times.items():
            kind: Optional[str] = st.core
            for _ in range(n_times):
                kind = eff.core_change.get(kind) if kind is not None else None
            if kind is None:
                continue
            if variant in KNEE_FRACTIONS and _bridge_hysteresis(st):
                continue  # the bridge's inverse solves its plays with a plain core beside them
            for tau in eff.grid(variant, sig):
                added = tuple(tau * SPREAD_RATIO ** k for k in range(n_times)) if tau is not None else ()
                if added and all(abs(math.log(a / t)) > 0.5 for a in added for t in st.taus):
                    out.append(Structure(kind, tuple(sorted(st.taus + added)), st.terms + (Term(effect, variant, tau),)))
        return out
    if eff.needs_temperature and not has_temperature:
        return []
    out = []
    flow = st.term("viscous_flow")
    power_flow = flow is not None and bool(flow.variant)  # a dashpot beside the core, not the core's own
    delayed = st.term("delayed_elasticity")
    beside_core = power_flow or (delayed is not None and delayed.variant in KNEE_FRACTIONS)
    for variant in eff.variants:
        if effect == "hysteresis" and beside_core and variant.startswith("bridge"):
            continue  # a power-law dashpot or a knee unit wraps the core that the bridge's plays would sit beside
        for param in eff.grid(variant, sig):
            out.append(Structure(st.core, st.taus, st.terms + (Term(effect, variant, param),)))
    if effect == "sensor_lag":
        out += _lag_from_core(st, sig)
    return out


def _bridge_hysteresis(st: Structure) -> bool:
    """Whether ``st`` holds hysteresis at the bridge (plays on the applied force beside the core)."""
    term = st.term("hysteresis")
    return term is not None and term.variant.startswith("bridge")


def _lag_from_core(st: Structure, sig: Signals) -> list[Structure]:
    """A sensor lag that a fast retardation time of the core stood in for (a unit-gain lag on an elastic core is a
    Kelvin unit that carries all the compliance): the lag at that time, the core's time restarted from the grid
    above it."""
    longest_lag = max(g for g in REGISTRY["sensor_lag"].grid("", sig) if g is not None)
    out = []
    for i, fast in enumerate(st.taus):
        if fast > longest_lag:
            continue
        others = st.taus[:i] + st.taus[i + 1:]
        for tau in TAU_GRID[::2]:
            # above the lag, within the record, and apart from the core's other times (collinear columns otherwise)
            if 4.0 * fast < tau <= sig.duration_s / 4.0 and all(abs(math.log(tau / o)) > 0.5 for o in others):
                taus = tuple(sorted(others + (float(tau),)))
                out += [Structure(st.core, taus, st.terms + (Term("sensor_lag", variant, fast),))
                        for variant in ("", "pole_pair")]
    return out
