"""Find where simulation and measurement disagree, name the missing effect, add it, refit.

Procedure (``diagnose``):
1. split the record in time: the first ``fit_fraction`` is fitted, the rest
   validates (the fit never sees it);
2. fit the base model (force -> voltage, offset by projection) on the fitting
   part and simulate the whole record;
3. localise the residual: in which kinds of segment it concentrates and how
   it correlates with candidate signals (:mod:`.localise`);
4. for each effect of the catalogue that applies to the base, refit the
   augmented model and score it by BIC on the fitting part and RMSE on the
   validation part;
5. name the effect with the lowest BIC if it beats the base's BIC by a clear
   margin *and* shrinks the validation RMSE by at least ``min_gain``;
   otherwise ``none``.

All fitting runs on block averages at ``fit_rate_hz`` (fast, and the same
data for every candidate); RMSEs are reported at the record's own rate.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize

from ..physics.chain import (
    NonlinearGainElement, OffsetDriftElement, OffsetElement, PreisachElement, SensorChain, SensorLagElement,
    ThermalDriftElement, ViscoelasticElement,
)
from ..record import Record  # noqa: F401 - the record type diagnose takes (re-exported)
from ..physics.fitting import LOG_BOUNDS, information_criteria, log_bounds, multistart_least_squares, starts_from_compliance
from ..physics.identification import block_average
from ..physics.viscoelastic import MODEL_TYPES, Burgers, Burgers2, Maxwell, Zener, Zener2, simulate_deformation_columns

EFFECTS = ("viscous_flow", "delayed_elasticity", "hysteresis", "sensor_lag", "nonlinear_gain", "thermal_drift", "offset_drift")
BASES = tuple(MODEL_TYPES)  # every core type the fitting stack knows
PREISACH_LEVELS = 16


@dataclass
class Candidate:
    effect: str  # "none" for the base model itself
    chain: SensorChain
    n_params: int
    bic: float
    rmse_fit_v: float
    rmse_val_v: float
    simulated_v: np.ndarray = field(repr=False, default=None)

    def summary(self):
        return {"effect": self.effect, "rmse": self.rmse_val_v, "rmse_fit": self.rmse_fit_v, "criterion": self.bic,
                "n_params": self.n_params}


class _Problem:
    """Decimated data and the fit/validation split shared by every candidate."""

    def __init__(self, rec: Record, fit_fraction, fit_rate_hz):
        self.rec = rec
        t = rec.t_s
        self.split_s = t[0] + fit_fraction * (t[-1] - t[0])
        self.fit_full = t < self.split_s
        temp = rec.temperature_c if rec.temperature_c is not None else np.zeros_like(t)
        self.td, self.fd, self.vd, self.tempd = block_average(t, rec.force_n, rec.voltage_v, temp, rate_hz=fit_rate_hz)
        self.auxd = {"temperature_c": self.tempd if rec.temperature_c is not None else None}
        self.fit_d = self.td < self.split_s
        self.n = int(self.fit_d.sum())
        slope = np.polyfit(rec.force_n[self.fit_full], rec.voltage_v[self.fit_full], 1)[0]
        self.k_static = 1.0 / max(abs(slope), 1e-9)  # N/V, for starting values

    def bic(self, rss, p):
        return information_criteria(rss, self.n, p)[1]

    def evaluate(self, effect, chain, n_params, rss_d):
        """Full-rate simulation, offset from the fitting part, RMSE on both parts."""
        sim = chain.forward(self.rec.t_s, self.rec.force_n, self.rec.aux())
        resid = self.rec.voltage_v - sim
        offset = float(resid[self.fit_full].mean())
        chain = chain.with_offset(chain.offset_v + offset)
        resid = resid - offset
        rmse = lambda m: float(np.sqrt(np.mean(resid[m] ** 2)))  # noqa: E731
        return Candidate(effect, chain, n_params + 1, self.bic(rss_d, n_params + 1), rmse(self.fit_full),
                         rmse(~self.fit_full), sim + offset)


def _initial_cores(kind, ks):
    """Starting vectors (log space) of a core type from the static stiffness ks (N/V) of a mixed record."""
    return starts_from_compliance(kind, 1.0 / (1.5 * ks), 1.0 / ks, 1.0 / (1500.0 * ks), (2.0, 8.0, 30.0))


def _fit(problem: _Problem, build, starts, lower, upper):
    """Least squares of ``build(theta) -> chain`` on the fitting part (offset projected out)."""
    fit, vd, td, fd, aux = problem.fit_d, problem.vd, problem.td, problem.fd, problem.auxd

    def residual(theta):
        try:
            r = vd - build(theta).forward(td, fd, aux)
        except (ValueError, FloatingPointError):
            return np.full(int(fit.sum()), 1e3)
        r = r[fit]
        r = r - r.mean()
        return np.where(np.isfinite(r), r, 1e3)

    best = multistart_least_squares(residual, starts, lower, upper, max_nfev=200)
    return best.x, 2.0 * float(best.cost)


def _core_chain(model, extras=()):
    return SensorChain([ViscoelasticElement(model), *extras, OffsetElement(0.0)])


def fit_base(problem, base):
    model_type = MODEL_TYPES[base]
    n = len(model_type.parameter_names())
    lower, upper = log_bounds(n)

    def build(theta):
        return _core_chain(model_type.from_vector(np.exp(theta)))

    theta, rss = _fit(problem, build, _initial_cores(base, problem.k_static), lower, upper)
    return problem.evaluate("none", build(theta), n, rss), np.exp(theta)


def _augmented_core(base, effect, base_params):
    """(model type, starts in log space) of the core with the effect added, or None if it does not apply."""
    p = list(base_params)
    if effect == "viscous_flow":
        if base == "elastic":
            return Maxwell, [np.log([p[0], 2000.0 * p[0]]), np.log([p[0], 200.0 * p[0]])]
        if base == "zener":
            return Burgers, [np.log([p[0], p[1], 2000.0 * p[0], p[2]]), np.log([p[0], p[1], 200.0 * p[0], p[2]])]
        if base == "zener2":
            return Burgers2, [np.log([p[0], p[1], eta, p[2], p[3], p[4]]) for eta in (2000.0 * p[0], 200.0 * p[0])]
        return None
    if effect == "delayed_elasticity":
        if base == "elastic":
            return Zener, [np.log([p[0], 3 * p[0], 3 * p[0] * tau]) for tau in (2.0, 8.0, 30.0)]
        if base == "maxwell":
            return Burgers, [np.log([p[0], 3 * p[0], p[1], 3 * p[0] * tau]) for tau in (2.0, 8.0, 30.0)]
        if base in ("zener", "burgers"):  # a second Kelvin element beside the fitted one
            model_type = Zener2 if base == "zener" else Burgers2
            return model_type, [np.log(p + [3 * p[0], 3 * p[0] * tau]) for tau in (1.0, 4.0, 30.0)]
        return None
    raise ValueError(effect)


def fit_candidate(problem, base, effect, base_fit, base_params):
    """Refit the base with ``effect`` added; None when it does not apply (or has no data, e.g. no temperature)."""
    base_type = MODEL_TYPES[base]
    if effect in ("viscous_flow", "delayed_elasticity"):
        aug = _augmented_core(base, effect, base_params)
        if aug is None:
            return None
        model_type, starts = aug
        n = len(model_type.parameter_names())
        lower, upper = log_bounds(n)
        theta, rss = _fit(problem, lambda th: _core_chain(model_type.from_vector(np.exp(th))), starts, lower, upper)
        return problem.evaluate(effect, _core_chain(model_type.from_vector(np.exp(theta))), n, rss)
    if effect == "hysteresis":
        return _fit_hysteresis(problem, base_fit)
    if effect == "thermal_drift" and problem.rec.temperature_c is None:
        return None
    n_core = len(base_type.parameter_names())
    log_core = np.log(base_params)
    t_ref = float(np.mean(problem.tempd[problem.fit_d])) if problem.rec.temperature_c is not None else 0.0
    extra = {
        "sensor_lag": (lambda x: SensorLagElement(tau_s=float(np.exp(x))), [np.log(0.01), np.log(0.08)], (math.log(1e-4), math.log(10.0))),
        "nonlinear_gain": (lambda x: NonlinearGainElement(quadratic_per_v=float(x)), [0.0], (-1.0, 1.0)),
        "thermal_drift": (lambda x: ThermalDriftElement(coefficient_v_per_c=float(x), reference_c=t_ref), [0.0], (-1.0, 1.0)),
        "offset_drift": (lambda x: OffsetDriftElement(rate_v_per_s=float(x)), [0.0], (-1.0, 1.0)),
    }[effect]
    make_element, extra_starts, (lo, hi) = extra

    def build(theta):
        return _core_chain(base_type.from_vector(np.exp(theta[:n_core])), [make_element(theta[n_core])])

    starts = [np.concatenate([log_core, [x]]) for x in extra_starts]
    lower = np.concatenate([np.full(n_core, LOG_BOUNDS[0]), [lo]])
    upper = np.concatenate([np.full(n_core, LOG_BOUNDS[1]), [hi]])
    theta, rss = _fit(problem, build, starts, lower, upper)
    return problem.evaluate(effect, build(theta), n_core + 1, rss)


def _fit_hysteresis(problem, base_fit, rate_hz=10.0):
    """A continuous Preisach operator on the force path, then the core: F -> P(F) -> core -> V.

    Rate-independent hysteresis of the force path (friction in the
    mechanism). Because P acts on force it cannot mimic creep (which grows
    with the time integral of force), so hysteresis and viscous effects stay
    separable. The core is linear, so for given core parameters the voltage
    is linear in the density: each relay's ramp signal (zero at rest, so
    P(0) = 0 and the core never integrates a constant) is run through the
    core, and the density follows by non-negative least squares. The core
    parameters are then optimised with the density projected out (variable
    projection), on block averages at ``rate_hz`` (hysteresis and creep are
    slow; the other candidates keep the faster rate).
    """
    from ..physics.preisach import PreisachModel, ramp_states

    td, fd, vd, fitf = block_average(problem.td, problem.fd, problem.vd, problem.fit_d.astype(float), rate_hz=rate_hz)
    fit = fitf > 0.5
    core0 = base_fit.chain.viscoelastic
    model_type = type(core0)
    n_core = len(model_type.parameter_names())
    f_lo, f_hi = float(min(fd.min(), 0.0)), float(fd.max())  # the force of the whole record is known
    f_hi += 0.05 * (f_hi - f_lo)
    deviation = ramp_states(fd, f_lo, f_hi, PREISACH_LEVELS) + 1.0  # 0 at rest
    v_fit = vd[fit] - vd[fit].mean()  # the free voltage offset, projected out by centring

    def project(theta):
        """Density (>= 0) for these core parameters, and the centred residual."""
        columns = simulate_deformation_columns(model_type.from_vector(np.exp(theta)), td, deviation)[fit]
        columns -= columns.mean(axis=0)
        weights, _ = optimize.nnls(columns, v_fit)
        return weights, columns @ weights - v_fit

    def residual(theta):
        return project(theta)[1]

    lower, upper = log_bounds(n_core)
    opt = optimize.least_squares(residual, np.log(core0.as_vector()), bounds=(lower, upper), x_scale="jac", max_nfev=60)
    weights, _ = project(opt.x)
    density = np.zeros((PREISACH_LEVELS, PREISACH_LEVELS))
    density[np.tril_indices(PREISACH_LEVELS)] = weights
    model = PreisachModel(f_lo, f_hi, density, offset=float(weights.sum()))  # P(rest) = 0
    chain = SensorChain([PreisachElement(model, continuous=True), ViscoelasticElement(model_type.from_vector(np.exp(opt.x))),
                         OffsetElement(0.0)])
    # criterion on the same (faster) data as every other candidate
    sim_d = chain.forward(problem.td, problem.fd, problem.auxd)
    r = problem.vd[problem.fit_d] - sim_d[problem.fit_d]
    r -= r.mean()
    n_params = n_core + int(np.count_nonzero(weights)) + 1
    return problem.evaluate("hysteresis", chain, n_params, float(r @ r))


@dataclass
class Diagnosis:
    base: str
    missing_effect: str
    rmse_before: float
    rmse_after: float
    candidates: list
    evidence: list
    base_fit: Candidate
    chosen: Candidate
    localisation: dict
    split_s: float

    def to_json(self):
        from ..model_file import model_to_mapping, SensorModel

        return {
            "base": self.base,
            "missing_effect": self.missing_effect,
            "rmse_before": self.rmse_before,
            "rmse_after": self.rmse_after,
            "evidence": self.evidence,
            "candidates": [c.summary() for c in self.candidates],
            "model": model_to_mapping(SensorModel(self.chosen.chain)),
            "validation_starts_s": self.split_s,
            "localisation": {k: v for k, v in self.localisation.items() if k != "masks"},
        }


def diagnose(rec: Record, base="burgers", fit_fraction=0.6, fit_rate_hz=100.0, min_gain=0.1, min_delta_bic=10.0,
             progress=None) -> Diagnosis:
    """Run the whole workflow on one record (see the module docstring)."""
    from .localise import describe, localise

    if base not in BASES:
        raise ValueError(f"base must be one of {BASES}, got {base!r}")
    bad = ~(np.isfinite(rec.t_s) & np.isfinite(rec.force_n) & np.isfinite(rec.voltage_v))
    if bad.any():
        raise ValueError(f"record holds {int(bad.sum())} non-finite samples")
    if rec.t_s.size < 100 or rec.t_s[-1] - rec.t_s[0] < 30.0:
        raise ValueError("record too short for a diagnosis (need at least 30 s)")
    problem = _Problem(rec, fit_fraction, fit_rate_hz)
    if progress:
        progress(f"fitting base {base}")
    base_fit, base_params = fit_base(problem, base)
    loc = localise(rec, rec.voltage_v - base_fit.simulated_v)
    candidates = [base_fit]
    for effect in EFFECTS:
        if progress:
            progress(f"candidate {effect}")
        cand = fit_candidate(problem, base, effect, base_fit, base_params)
        if cand is not None:
            candidates.append(cand)
    candidates.sort(key=lambda c: c.bic)
    best = candidates[0]
    accepted = (best.effect != "none" and best.bic < base_fit.bic - min_delta_bic
                and best.rmse_val_v <= (1.0 - min_gain) * base_fit.rmse_val_v)
    chosen = best if accepted else base_fit
    evidence = describe(loc, base_fit, chosen, candidates)
    return Diagnosis(base, chosen.effect, base_fit.rmse_val_v, chosen.rmse_val_v, candidates, evidence, base_fit, chosen,
                     loc, float(problem.split_s - rec.t_s[0]))
