"""Find where simulation and measurement disagree, name every missing effect, add them, refit.

Procedure (:func:`diagnose`):

1. **Noise floor from the data.** The white part of the bridge voltage and of
   the reference force is estimated from high-frequency (second) differences
   of the raw samples (median absolute deviation, robust to load steps); the
   reference noise enters the residual through the base fit's instantaneous
   compliance (its creep terms low-pass it).
2. **Time-blocked cross-validation.** The record is cut into
   ``n_folds * blocks_per_fold`` contiguous blocks, dealt to ``n_folds``
   folds in turn. Every model is fitted with each fold left out in turn and
   predicts it; its score is the out-of-sample mean squared error over all
   folds. No single split decides, and every left-out block but the first and
   the last lies between fitted ones, so a drift-like term cannot win or lose
   on how it extrapolates alone
   (with one block per fold, a step of the drift inside a left-out block
   cannot be predicted from the others, and what it leaves would be taken by
   another effect that follows time).
3. **Base model.** The base core (compliance form, linear in its compliances
   once its retardation times are fixed) is fitted; times from a grid, then
   polished by :func:`~polyforce_ros.physics.fitting.multistart_least_squares`.
4. **Forward selection.** Every effect of the registry (:mod:`.effects`) that
   applies is added in turn to the current model (each variant, each value of
   its nonlinear parameter on its grid) and scored out of sample. The best is
   accepted when it lowers the out-of-sample error in at least
   ``min_confidence`` of the folds and removes at least ``min_excess_share`` of
   the current error above the noise floor (counted as at least a quarter of
   the floor's own mean square); among candidates of one step, a smaller one
   (fewer columns and time constants) is preferred unless the better one
   passes that same test against it (a promising candidate has its time
   constants, the core's included, refitted before it is judged, of the spline
   drifts the best in and out of sample only; a refit that
   predicts the left-out blocks worse is not kept; a candidate that removes that
   share but not in enough folds is tried again with the shapes of the effects
   named before it re-chosen beside it, and kept if it passes the test against
   the current model re-chosen alike). Then the next step runs
   with it included; an effect that the newer ones make redundant (the
   others re-chosen in their best shape without it) is dropped again, and
   one that a rival of its own step now describes as well is swapped for it,
   until nothing more is justified or a set of effects recurs.
5. **Unexplained residual.** The out-of-sample residual of the final model
   at the record's rate (its nonlinear columns driven by the reference force
   as smooth as they were fitted on: a centred mean over a fit bin) is averaged
   to ~1 s and tested for whiteness (Ljung-Box), and split into octave bands
   up to the Nyquist frequency; structure whose RMS is at least
   ``unexplained_ratio`` of the noise floor, in the 1 s averages or in any
   band, is reported as ``unexplained``. When no effect was justified but structure remains, the
   answer is ``"unexplained"``, never a catalogue name; so it is when the
   named effects worsen the out-of-sample error at the record's rate, or
   leave structure while explaining less than ``min_explained`` of the
   base's error above the floor (partial fits of something outside the
   catalogue, listed under ``unexplained.partial_fits``).
6. **Judged in newtons** (:mod:`.newtons`). Each left-out block is
   compensated by the model fitted without it and compared with the
   reference force; a sensor lag's inverse gets an explicit bandwidth, a
   transport delay is stated as latency. A model that compensates the force
   worse than the base is not saved: its effects become partial fits.

Every candidate fit is a bounded linear least-squares problem on per-block
normal matrices (cheap to refit with any block left out); only the few time
constants are nonlinear. Fitting runs on block averages at ``fit_rate_hz``;
the reported RMSEs are out-of-sample at the record's own rate.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from scipy import linalg, ndimage, optimize, stats

from ..physics.chain import OffsetElement, SensorChain, ViscoelasticElement
from ..physics.fitting import (LOG_BOUNDS, TAU_GRID_S, TAU_LOG_BOUNDS, block_jackknife_standard_errors,
                               information_criteria, multistart_least_squares)
from ..physics.identification import block_average
from ..physics.viscoelastic import MODEL_TYPES, KelvinVoigt, simulate_deformation
from ..record import Record  # noqa: F401 - the record type diagnose takes (re-exported)
from .effects import EFFECTS as REGISTRY, NAMES, PLAY_RIDGE, lag_columns, lag_stages, variant_group
from .newtons import fold_chains, force_quality, with_filter, with_safe_bandwidth

EFFECTS = NAMES
BASES = tuple(MODEL_TYPES)  # every core type the fitting stack knows
#: Contiguous time blocks dealt to each cross-validation fold (interleaved): a left-out block (but the record's
#: first and last) lies between blocks that are fitted, so a term that follows time is judged on how it
#: interpolates, not extrapolates.
BLOCKS_PER_FOLD = 3
#: Number of retardation times of each core type, and whether it has instantaneous compliance / flow.
_CORE_SHAPE = {kind: cls.shape for kind, cls in MODEL_TYPES.items()}  # declared by the model types
_TAU_GRID, _TAU_BOUNDS = TAU_GRID_S, TAU_LOG_BOUNDS  # physics/fitting.py declares them


# ----------------------------------------------------------------------------- signals and noise

@dataclass
class Signals:
    """The record at one rate, with what design columns need."""

    t: np.ndarray
    f: np.ndarray
    v: np.ndarray
    temp: np.ndarray | None
    t0: float
    duration_s: float
    temp_ref: float
    x_ref: np.ndarray | None = None  # core output of the current model (V)
    valid: np.ndarray | None = None  # samples that are fitted and scored (None: all)
    core_ref: object = None          # its viscoelastic model
    f_smooth: np.ndarray | None = None  # the force behind x_ref and the force plays (N); None: f itself
    span_f: float = 1.0              # force span (N) and span of x_ref (V) at the fit rate: the play radii scale
    span_x: float = 1.0              # with them (the same at every rate of one reference core)
    cache: dict = field(default_factory=dict, init=False, repr=False)  # design columns (new with every ref)
    # what depends on the record alone (force, time), not on the reference core: kept by every refresh
    record_cache: dict = field(default_factory=dict, repr=False)

    @property
    def f_nonlinear(self) -> np.ndarray:
        """The force that drives the nonlinear columns (x_ref, the force plays), N."""
        return self.f if self.f_smooth is None else self.f_smooth


def uniform_blocks(t_s, force_n, voltage_v, temperature_c, rate_hz):
    """Block means on a uniform time grid of step 1/rate_hz (the record's own step when slower).

    Returns ``(t, force, voltage, temperature, valid, bin_of_sample)``: bins without samples (dropped blocks)
    get force and temperature interpolated (the model needs its input everywhere) and are
    marked invalid (never fitted, never scored). A uniform grid keeps every exponential
    convolution on its fast path whatever the stamp jitter. ``bin_of_sample``: the bin each sample
    was averaged into (its cross-validation fold is the bin's).
    """
    t = np.asarray(t_s, dtype=float)
    step = max(1.0 / rate_hz, float(np.median(np.diff(t))))
    k = np.floor((t - t[0]) / step).astype(np.int64)
    n = int(k[-1]) + 1
    counts = np.bincount(k, minlength=n).astype(float)
    valid = counts > 0
    grid = t[0] + (np.arange(n) + 0.5) * step

    def mean(x):
        m = np.bincount(k, weights=np.asarray(x, dtype=float), minlength=n)[valid] / counts[valid]
        return np.interp(grid, grid[valid], m)

    return grid, mean(force_n), mean(voltage_v), mean(temperature_c), valid, k


def noise_std(x):
    """White-noise standard deviation of a sampled signal from its second differences (robust MAD)."""
    d2 = np.diff(np.asarray(x, dtype=float), 2)
    if d2.size < 10:
        return 0.0
    return float(1.4826 * np.median(np.abs(d2 - np.median(d2))) / math.sqrt(6.0))


def ljung_box(x, lags=20):
    """Ljung-Box statistic and p-value of the first ``lags`` autocorrelations of x (white -> large p)."""
    x = np.asarray(x, dtype=float) - np.mean(x)
    n = x.size
    lags = min(lags, n // 4)
    denom = float(x @ x)
    if lags < 1 or denom <= 0:
        return 0.0, 1.0
    rho = np.array([float(x[:-k] @ x[k:]) / denom for k in range(1, lags + 1)])
    q = n * (n + 2) * float(np.sum(rho ** 2 / (n - np.arange(1, lags + 1))))
    return q, float(stats.chi2.sf(q, lags))


def band_structure(resid_v, t_s, floor_v, lowest_hz=0.5):
    """Structured RMS of a residual in octave bands from ``lowest_hz`` to Nyquist, over a white floor.

    The residual's one-sided power spectrum (Welch, segments of ~8 s) is integrated over each octave and the
    power white noise of RMS ``floor_v`` would put there is subtracted: what remains is structure at that time
    scale (a resonance rings in its band, an unmodelled lag in the fast ones) that 1 s averages do not see.

    Returns
    -------
    list of dict
        ``low_hz``, ``high_hz``, ``rms_v`` (the structured RMS in the band, 0 when below the floor).
    """
    from scipy import signal

    resid_v = np.asarray(resid_v, dtype=float)
    rate_hz = 1.0 / float(np.median(np.diff(t_s)))
    nperseg = int(min(resid_v.size, 2 ** round(math.log2(max(8.0 * rate_hz, 16.0)))))
    freq, psd = signal.welch(resid_v - resid_v.mean(), fs=rate_hz, nperseg=nperseg)
    white = 2.0 * floor_v ** 2 / rate_hz
    df = freq[1] - freq[0]
    out, low = [], lowest_hz
    while low < rate_hz / 2.0:
        high = min(2.0 * low, rate_hz / 2.0)
        band = (freq >= low) & (freq < high)
        excess = float(np.sum(psd[band] - white) * df) if band.any() else 0.0
        out.append({"low_hz": low, "high_hz": high, "rms_v": math.sqrt(max(excess, 0.0))})
        low = high
    return out


# ----------------------------------------------------------------------------- model structures

@dataclass(frozen=True)
class Term:
    effect: str
    variant: str = ""
    param: float | None = None


@dataclass(frozen=True)
class Structure:
    core: str
    taus: tuple = ()
    terms: tuple = ()

    @property
    def effects(self):
        return [t.effect for t in self.terms]

    def term(self, effect):
        return next((t for t in self.terms if t.effect == effect), None)


def _core_columns(sig, kind, taus):
    n_tau, inst, flow = _CORE_SHAPE[kind]
    cols = []
    if inst:
        cols.append(("j0", sig.f, 0.0, np.inf, "sensor", None))
    if flow:
        cols.append(("phi", _integral(sig.t, sig.f), 0.0, np.inf, "sensor", None))
    for i, tau in enumerate(taus[:n_tau]):
        cols.append((f"c{i}", lag_columns(sig.t, sig.f, tau), 0.0, np.inf, "sensor", None))
    return cols


def _integral(t, f):
    from ..physics.expconv import exp_convolve

    return exp_convolve(t, f, [0.0])[:, 0]


def _cached(sig, key, make):
    """Design columns ``make()`` (tuples of name, column, ...), made once per signals and kept contiguous (a column
    of a 2-D basis is a strided view, slow to copy at every evaluation)."""
    if key not in sig.cache:
        sig.cache[key] = [(c[0], np.ascontiguousarray(c[1], dtype=float), *c[2:]) for c in make()]
    return sig.cache[key]


def design(sig, st: Structure):
    """(names, A, lower, upper, ridge group mask) of a structure on these signals."""
    names, mats, lo, hi, ridge = design_columns(sig, st)
    return names, _stack(mats), lo, hi, ridge


_ALL_ROWS = slice(None)


def _stack(columns, rows=_ALL_ROWS):
    """The columns (rows ``rows`` of each) as one column-major matrix: each column is one contiguous copy
    (``np.column_stack`` writes row-major, a strided store per element, which costs a fifth of a diagnosis)."""
    first = columns[0][rows]
    a = np.empty((first.size, len(columns)), order="F")
    for j, c in enumerate(columns):
        a[:, j] = c[rows]
    return a


def design_columns(sig, st: Structure):
    """:func:`design` with the columns of A as a list of arrays (not stacked: the polish needs a few rows)."""
    cols = list(_cached(sig, ("core", st.core, st.taus), lambda: _core_columns(sig, st.core, st.taus)))
    lag, delay_s = None, 0.0
    for term in st.terms:
        eff = REGISTRY[term.effect]
        if eff.core_change:
            continue
        if term.effect == "sensor_lag":
            lag = lag_stages(term.variant, term.param)
            delay_s = term.param if term.variant == "delay" else 0.0
            continue
        cols += _cached(sig, (term.effect, term.variant, term.param),
                        lambda eff=eff, term=term: eff.columns(sig, term.variant, term.param))
    names = [c[0] for c in cols] + ["offset"]
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
    lo = np.array([c[2] for c in cols] + [-np.inf])
    hi = np.array([c[3] for c in cols] + [np.inf])
    ridge = np.array([c[5] is not None for c in cols] + [False])  # ridge groups: play weights, spline knots
    return names, mats, lo, hi, ridge


@dataclass
class Fit:
    structure: Structure
    names: list
    scale: np.ndarray
    coef: np.ndarray                  # all blocks, natural units of the columns
    coef_folds: list                  # one per left-out block
    sse_folds: np.ndarray             # out-of-sample SSE per block (fit rate)
    cv_mse: float
    fit_mse: float
    n: int
    bic: float = 0.0

    @property
    def coef_map(self):
        return dict(zip(self.names, self.coef))

    def coefficients(self) -> dict:
        """Each fitted coefficient (units of its design column) with its standard error by the block
        jackknife over the cross-validation folds."""
        errors = block_jackknife_standard_errors(self.coef_folds)
        return {name: {"value": float(c), "standard_error": float(e)}
                for name, c, e in zip(self.names, self.coef, errors)}


def fold_of(t_s, t0_s, duration_s, n_folds, blocks_per_fold=BLOCKS_PER_FOLD):
    """Fold (0..n_folds-1) of each time in ``t_s`` (s): the record is cut into ``n_folds * blocks_per_fold``
    contiguous blocks of equal length, dealt to the folds in turn (block j belongs to fold j mod n_folds)."""
    u = (np.asarray(t_s, dtype=float) - t0_s) / max(duration_s, 1e-9)
    n_blocks = n_folds * blocks_per_fold
    return np.clip((u * n_blocks).astype(int), 0, n_blocks - 1) % n_folds


class Fitter:
    """Per-fold normal matrices and bounded solves for any structure on one record (fit rate)."""

    def __init__(self, sig: Signals, n_folds, blocks_per_fold=BLOCKS_PER_FOLD):
        self.sig = sig
        self.fold = fold = fold_of(sig.t, sig.t0, sig.duration_s, n_folds, blocks_per_fold)
        self.k, self.blocks_per_fold = n_folds, blocks_per_fold
        # each fold is a few contiguous runs of rows: slices (no copies)
        edges = np.flatnonzero(np.diff(fold)) + 1
        starts, stops = np.r_[0, edges], np.r_[edges, fold.size]
        self.rows = [[slice(int(a), int(b)) for a, b in zip(starts, stops) if fold[a] == k] for k in range(n_folds)]
        self.evaluations = 0

    def evaluate(self, st: Structure) -> Fit:
        self.evaluations += 1
        names, a, lo, hi, ridge = design(self.sig, st)
        v = self.sig.v
        if self.sig.valid is not None and not self.sig.valid.all():  # empty bins count for nothing
            a = a * self.sig.valid[:, None]
            v = v * self.sig.valid
        raw = []
        for runs in self.rows:
            ab = [a[r] for r in runs]
            vb = [v[r] for r in runs]
            raw.append((sum(x.T @ x for x in ab), sum(x.T @ y for x, y in zip(ab, vb)), float(sum(y @ y for y in vb))))
        scale = np.sqrt(np.diag(sum(g for g, _, _ in raw)) / max(v.size, 1))  # columns scaled to unit RMS
        scale[~(scale > 0)] = 1.0
        grams = [(g / np.outer(scale, scale), h / scale, vv) for g, h, vv in raw]
        g_all = sum(g for g, _, _ in grams)
        h_all = sum(h for _, h, _ in grams)
        vv_all = sum(w for _, _, w in grams)
        lo_s, hi_s = lo * scale, hi * scale
        reg = PLAY_RIDGE * float(np.trace(g_all)) / g_all.shape[0] * ridge.astype(float)
        coef = _bounded_solve(g_all, h_all, lo_s, hi_s, reg)
        fit_sse = float(coef @ g_all @ coef - 2 * h_all @ coef + vv_all)
        folds, sse = [], []
        for g, h, vv in grams:
            c = _bounded_solve(g_all - g, h_all - h, lo_s, hi_s, reg * (1 - 1.0 / self.k))
            folds.append(c / scale)
            sse.append(max(float(c @ g @ c - 2 * h @ c + vv), 0.0))
        n = v.size if self.sig.valid is None else int(self.sig.valid.sum())
        fit = Fit(st, names, scale, coef / scale, folds, np.array(sse), float(np.sum(sse) / n), max(fit_sse, 0.0) / n, n)
        fit.bic = information_criteria(max(fit_sse, 1e-300), n, _n_params(fit))[1]
        return fit


def _bounded_solve(g, h, lo, hi, reg):
    p = g.shape[0]
    g = g + np.diag(reg) + (1e-12 * float(np.trace(g)) / p + 1e-300) * np.eye(p)
    try:
        chol = linalg.cholesky(g, lower=True)
    except linalg.LinAlgError:
        g = g + 1e-8 * float(np.trace(g)) / p * np.eye(p)
        chol = linalg.cholesky(g, lower=True)
    b = linalg.solve_triangular(chol, h, lower=True)
    if np.all(np.isinf(lo)) and np.all(np.isinf(hi)):
        return linalg.solve_triangular(chol.T, b, lower=False)
    return optimize.lsq_linear(chol.T, b, bounds=(lo, hi), method="bvls").x


# ----------------------------------------------------------------------------- chain building

def core_model(st: Structure, coef: dict):
    """The viscoelastic model of the fitted compliances (zero compliance -> the stiffest bound)."""
    kmax = math.exp(LOG_BOUNDS[1])
    kmin = math.exp(LOG_BOUNDS[0])
    stiff = lambda c: float(np.clip(1.0 / c, kmin, kmax)) if c > 0 else kmax  # noqa: E731
    k1 = stiff(coef.get("j0", 0.0))
    eta1 = stiff(coef.get("phi", 0.0))
    kel = [(stiff(coef.get(f"c{i}", 0.0)), tau) for i, tau in enumerate(st.taus)]
    kel = [(k, float(np.clip(k * tau, kmin, kmax))) for k, tau in kel]
    kind = st.core
    if kind == "elastic":
        return MODEL_TYPES[kind](k1)
    if kind == "maxwell":
        return MODEL_TYPES[kind](k1, eta1)
    if kind == "kelvin":
        return KelvinVoigt(*kel[0])
    if kind == "zener":
        return MODEL_TYPES[kind](k1, *kel[0])
    if kind == "burgers":
        return MODEL_TYPES[kind](k1, kel[0][0], eta1, kel[0][1])
    if kind == "zener2":
        return MODEL_TYPES[kind](k1, *kel[0], *kel[1])
    return MODEL_TYPES[kind](k1, kel[0][0], eta1, kel[0][1], *kel[1])


def build_chain(st: Structure, coef: dict, sig: Signals) -> SensorChain:
    """Model-file chain: [force-path hysteresis] core [gain, voltage-path hysteresis] [lag] [thermal, drift] offset."""
    slots = {"before": [], "after": [], "lag": [], "late": []}
    for term in st.terms:
        eff = REGISTRY[term.effect]
        if eff.core_change:
            continue
        for slot, element in eff.to_elements(coef, term.variant, term.param, sig):
            slots[slot].append(element)
    slots["after"].sort(key=lambda e: 0 if e.kind == "nonlinear_gain" else 1)
    return SensorChain([*slots["before"], ViscoelasticElement(core_model(st, coef)), *slots["after"], *slots["lag"],
                        *slots["late"], OffsetElement(float(np.clip(coef.get("offset", 0.0), -1e3, 1e3)))])


# ----------------------------------------------------------------------------- the diagnosis

@dataclass
class Candidate:
    effect: str
    variant: str
    fit: Fit
    rmse_v: float          # out-of-sample RMSE at the fit rate
    confidence: float      # share of folds where it lowers the out-of-sample error
    excess_share: float    # share of the current error above the noise floor it removes
    step: int
    accepted: bool = False

    def summary(self):
        return {"effect": self.effect, "variant": self.variant, "step": self.step, "rmse": self.rmse_v,
                "rmse_fit": math.sqrt(self.fit.fit_mse), "criterion": self.fit.bic, "confidence": self.confidence,
                "excess_share": self.excess_share, "accepted": self.accepted,
                "n_params": _n_params(self.fit)}


@dataclass
class Diagnosis:
    base: str
    missing_effects: list
    confidences: dict
    rmse_before: float
    rmse_after: float
    noise_floor_v: float
    unexplained: dict
    candidates: list
    skipped: dict
    evidence: list
    chain: SensorChain
    base_chain: SensorChain
    simulated_before_v: np.ndarray = field(repr=False, default=None)
    simulated_after_v: np.ndarray = field(repr=False, default=None)
    localisation: dict = field(default_factory=dict)
    folds: int = 5
    blocks_per_fold: int = BLOCKS_PER_FOLD
    variants: dict = field(default_factory=dict)
    coefficients: dict = field(default_factory=dict)  # the final fit's, with block-jackknife standard errors
    newtons: dict = field(default_factory=dict)       # compensated force of the base and the saved model (newtons.py)
    compensated_before_n: np.ndarray = field(repr=False, default=None)  # the base's, each block left out (N)
    compensated_after_n: np.ndarray = field(repr=False, default=None)   # the saved model's (N)

    @property
    def missing_effect(self):
        if self.missing_effects:
            return self.missing_effects[0]
        return "unexplained" if self.unexplained.get("present") else "none"

    def to_json(self):
        from ..model_file import SensorModel, model_to_mapping

        return {
            "base": self.base,
            "missing_effect": self.missing_effect,
            "missing_effects": list(self.missing_effects),
            "effects": [{"effect": e, "variant": self.variants.get(e, ""), "confidence": self.confidences[e]}
                        for e in self.missing_effects],
            "rmse_before": self.rmse_before,
            "rmse_after": self.rmse_after,
            "noise_floor_v": self.noise_floor_v,
            "unexplained": self.unexplained,
            "skipped": self.skipped,
            "validation": (f"time-blocked cross-validation, {self.folds} folds of {self.blocks_per_fold} interleaved blocks; "
                           "RMSEs out of sample"),
            "evidence": self.evidence,
            "candidates": [c.summary() for c in self.candidates],
            "coefficients": self.coefficients,
            "newtons": self.newtons,
            "model": model_to_mapping(SensorModel(self.chain)),
            "localisation": {k: v for k, v in self.localisation.items() if k != "masks"},
        }


def _refresh_ref(sig: Signals, core, span_x=None):
    """``sig`` with ``core`` as the reference core: its output ``x_ref`` and, unless ``span_x`` is given (the record at
    another rate takes the fit rate's), the play radii's span from it. Radii that kept an earlier core's span would
    drift against the signal when a voltage-path hysteresis takes part of the core's gain (a play of small radius is
    nearly the input itself): each settling round would fit worse, and the loss be named as a drift."""
    x = simulate_deformation(core, sig.t, sig.f_nonlinear)
    return replace(sig, core_ref=core, x_ref=x, span_x=span_x if span_x is not None else max(float(np.ptp(x)), 1e-9))


def _excess(mse, floor_mse):
    """A mean square error's excess over the noise floor's, counted as at least a quarter of the floor's own: the
    denominator of every share of the excess (acceptance, candidates' report, explained share), which a model at or
    below the floor would otherwise make a ratio over ~0."""
    return max(mse - floor_mse, 0.25 * floor_mse)


def _polish(fitter: Fitter, st: Structure) -> Structure:
    """Polish the nonlinear time constants (core, lag, thermal lag) by multi-start least squares in log space."""
    idx = [("core", i) for i in range(len(st.taus))]
    # a core effect's parameter (a delayed elasticity's time) is one of the core's times, not a column's: it is not
    # polished on its own (it would stay at its grid value while the core's time moves, and _without drops the core
    # time nearest to it) but follows the core time it names
    own_tau = {k: int(np.argmin([abs(math.log(tau / t.param)) for tau in st.taus]))
               for k, t in enumerate(st.terms) if t.param is not None and REGISTRY[t.effect].core_change and st.taus}
    idx += [("term", k) for k, t in enumerate(st.terms)
            if t.param is not None and not REGISTRY[t.effect].core_change]
    if not idx:
        return st
    x0 = np.log([st.taus[i] if kind == "core" else st.terms[i].param for kind, i in idx])

    def make(theta):
        taus, terms = list(st.taus), list(st.terms)
        for (kind, i), th in zip(idx, theta):
            if kind == "core":
                taus[i] = float(math.exp(th))
            else:
                terms[i] = replace(terms[i], param=float(math.exp(th)))
        for k, i in own_tau.items():
            terms[k] = replace(terms[k], param=taus[i])
        return Structure(st.core, tuple(taus), tuple(terms))

    sig = fitter.sig
    sub = slice(None, None, max(1, sig.t.size // 10000))  # at most ~10000 rows for the polish
    w = np.ones(sig.t.size) if sig.valid is None else sig.valid.astype(float)
    target = (sig.v * w)[sub]

    def residual(theta):
        s = make(theta)
        names, mats, lo, hi, ridge = design_columns(sig, s)
        # scaled by the whole record's RMS, but only the rows used are stacked: stacking every row at every
        # evaluation costs a third of a diagnosis
        scale = np.array([math.sqrt(float(m @ m) / m.size) for m in mats])
        scale[scale <= 0] = 1.0
        a = _stack(mats, sub) / scale * w[sub, None]
        g, h = a.T @ a, a.T @ target
        reg = PLAY_RIDGE * float(np.trace(g)) / g.shape[0] * ridge.astype(float)
        c = _bounded_solve(g, h, lo * scale, hi * scale, reg)
        return a @ c - target

    # a retardation time longer than the record cannot be told from flow within it (its creep is still a
    # straight line at the end): bounded by the record, so that a missing dashpot is not fitted as a slow Kelvin
    longest = min(_TAU_BOUNDS[1], math.log(max(fitter.sig.duration_s, 1.0)))
    bounds = [(_TAU_BOUNDS[0], longest) if kind == "core" else _param_log_bounds(st.terms[i], sig) for kind, i in idx]
    lower, upper = np.array(bounds).T
    x0 = np.clip(x0, lower, upper)
    sol = multistart_least_squares(residual, [x0], lower, upper, max_nfev=8 * len(idx))
    return make(sol.x)


def _param_log_bounds(term: Term, sig: Signals):
    """Log bounds of a term's nonlinear parameter in the polish: the span of the effect's grid, which is where the
    parameter can be told apart in this record (a settling drift faster than a twentieth of the record is an offset
    step in the first block, one slower than the record its linear part; either left the split with the collinear
    column undetermined), or the time-constant bounds when the grid is a single value."""
    grid = [g for g in REGISTRY[term.effect].grid(term.variant, sig) if g is not None]
    if len(grid) < 2:
        return _TAU_BOUNDS
    return math.log(min(grid)), math.log(max(grid))


def _settle(fitter: Fitter, st: Structure, rounds=2) -> Fit:
    """Fit ``st`` with the columns that follow the core (hysteresis, gain) made from the core it fits, so that the
    model scored is the model saved (:func:`build_chain` places them after/before that core); ``rounds`` refreshes."""
    fit = fitter.evaluate(st)
    for _ in range(rounds):
        fitter.sig = _refresh_ref(fitter.sig, core_model(st, fit.coef_map))
        fit = fitter.evaluate(st)
    return fit


def _refine(fitter: Fitter, st: Structure, rounds=2) -> Fit:
    """Polish the time constants, then make the columns that follow the core (hysteresis, gain) consistent
    with the refitted core; ``rounds`` times. The polish fits in sample: when the result predicts the left-out
    blocks worse than the structure as given (e.g. a settling time shorter than a block, which no other block
    can pin down), the structure as given is kept. Either way the result is settled (:func:`_settle`)."""
    sig0, given = fitter.sig, fitter.evaluate(st)
    polished = st
    for _ in range(rounds):
        polished = _polish(fitter, polished)
        fit = fitter.evaluate(polished)
        fitter.sig = _refresh_ref(fitter.sig, core_model(polished, fit.coef_map))
    if fitter.evaluate(polished).cv_mse > given.cv_mse:
        fitter.sig = sig0
        return _settle(fitter, st)
    return _settle(fitter, polished)


def _without(st: Structure, effect):
    """The structure without ``effect`` (None for a core effect other than viscous flow's dashpot)."""
    term = st.term(effect)
    if term is None:
        return None
    terms = tuple(t for t in st.terms if t.effect != effect)
    eff = REGISTRY[effect]
    if eff.core_change:
        back = {v: k for k, v in eff.core_change.items()}.get(st.core)
        if back is None:
            return None
        taus = st.taus
        if effect == "delayed_elasticity" and term.param is not None and len(taus) > _CORE_SHAPE[back][0]:
            drop = int(np.argmin([abs(math.log(t / term.param)) for t in taus]))
            taus = tuple(t for i, t in enumerate(taus) if i != drop)
        return Structure(back, taus, terms)
    return Structure(st.core, st.taus, terms)


def _base_structure(fitter, base):
    n_tau = _CORE_SHAPE[base][0]
    if n_tau == 0:
        return Structure(base)
    if n_tau == 1:
        grid = [(tau,) for tau in _TAU_GRID]
    else:
        grid = [(a, b) for i, a in enumerate(_TAU_GRID[::2]) for b in _TAU_GRID[::2][i + 1:]]
    best = min(grid, key=lambda taus: fitter.evaluate(Structure(base, taus)).cv_mse)
    return _polish(fitter, Structure(base, best))


def _candidates_for(st: Structure, effect, has_temperature, sig=None):
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
                limit = sig.duration_s / 4.0 if sig is not None else 300.0
                out += [Structure(new, (tau,), st.terms + (Term(effect),)) for tau in _TAU_GRID if tau <= limit]
            return out
        grid = eff.grid("", sig)
        return [Structure(new, tuple(sorted(st.taus + (tau,))), st.terms + (Term(effect, "", tau),))
                for tau in grid if all(abs(math.log(tau / t)) > 0.5 for t in st.taus)]
    if eff.needs_temperature and not has_temperature:
        return []
    out = []
    for variant in eff.variants:
        for param in eff.grid(variant, sig):
            out.append(Structure(st.core, st.taus, st.terms + (Term(effect, variant, param),)))
    return out


def _n_params(fit: Fit) -> int:
    """Free parameters of a fit: non-zero coefficients and nonlinear time constants."""
    st = fit.structure
    return int(np.count_nonzero(fit.coef)) + len(st.taus) + sum(t.param is not None for t in st.terms)


def _size(fit: Fit) -> int:
    """Nominal size of a structure: its design columns and nonlinear time constants (whatever values they took).

    A delayed elasticity that takes all of the instantaneous compliance is a sensor lag in disguise; counted
    by its non-zero coefficients it would look as small as the lag."""
    st = fit.structure
    return len(fit.names) + len(st.taus) + sum(t.param is not None for t in st.terms)


def _parsimonious(cands, acceptable, justified):
    """The candidate of one step to judge: the lowest out-of-sample error, unless the acceptable candidates of
    smaller nominal size (:func:`_size`) include some that it does not improve on as an added effect would have to
    improve on the current model (``justified(better, than)``: the acceptance test itself); then the smallest of
    those (the lower error among equals). Always compared with the overall best, so the choice is not path-bound."""
    if not cands:
        return None
    best = min(cands, key=lambda c: c.fit.cv_mse)
    equivalent = [c for c in cands if acceptable(c) and _size(c.fit) < _size(best.fit) and not justified(best.fit, c.fit)]
    if not equivalent:
        return best
    return min(equivalent, key=lambda c: (_size(c.fit), c.fit.cv_mse))


def diagnose(rec: Record, base="burgers", fit_rate_hz=100.0, n_folds=5, min_confidence=0.8, min_excess_share=0.3,
             unexplained_ratio=0.5, min_explained=0.8, max_effects=4, effects=None, progress=None,
             blocks_per_fold=BLOCKS_PER_FOLD) -> Diagnosis:
    """Run the whole workflow on one record (see the module docstring).

    ``effects``: names of the catalogue to consider (default: all of :data:`EFFECTS`).
    ``progress``: called with a short text before each step (a progress bar).
    """
    from .localise import describe, localise

    if base not in BASES:
        raise ValueError(f"base must be one of {BASES}, got {base!r}")
    if rec.force_n is None:
        raise ValueError("record has no reference force")
    bad = ~(np.isfinite(rec.t_s) & np.isfinite(rec.force_n) & np.isfinite(rec.voltage_v))
    if bad.any():
        raise ValueError(f"record holds {int(bad.sum())} non-finite samples")
    if rec.t_s.size < 100 or rec.t_s[-1] - rec.t_s[0] < 30.0:
        raise ValueError("record too short for a diagnosis (need at least 30 s)")
    say = progress or (lambda step: None)
    unknown = sorted(set(effects or ()) - set(NAMES))
    if unknown:
        raise ValueError(f"unknown effects {unknown}; the catalogue holds {list(NAMES)}")
    catalogue = [n for n in NAMES if effects is None or n in effects]
    has_temp = rec.temperature_c is not None
    t = np.asarray(rec.t_s, dtype=float)
    temp_full = np.asarray(rec.temperature_c, dtype=float) if has_temp else np.zeros_like(t)
    td, fd, vd, tempd, valid, bin_of_sample = uniform_blocks(t, rec.force_n, rec.voltage_v, temp_full, fit_rate_hz)
    t_ref = float(np.mean(temp_full)) if has_temp else 0.0
    span_f = max(float(np.max(fd) - min(float(np.min(fd)), 0.0)), 1e-9)
    common = dict(t0=float(t[0]), duration_s=float(t[-1] - t[0]), temp_ref=t_ref, span_f=span_f)
    sig = Signals(td, fd, vd, tempd if has_temp else None, **common, valid=valid)
    # at the record's rate the nonlinear columns (plays, powers of the core output) are driven by the reference force
    # as smooth as they were fitted on: a centred moving mean over a fit bin's samples (the raw force when a bin
    # holds one sample). The raw reference carries its own noise, which plays of small radii follow and block means
    # do not: driven by it, a stop hysteresis fitted to 0.0013 V at the fit rate predicts a 1 kHz record to 2.5x
    # the floor, and each sample's own block mean (a staircase) to 1.25x. The linear columns keep the raw force:
    # its fast content is worth more than its noise there. (The saved chain, run on a raw reference, still moves
    # its small plays with that noise.)
    per_bin = int(round(t.size / max(int(valid.sum()), 1)))
    f_smooth = ndimage.uniform_filter1d(np.asarray(rec.force_n, float), per_bin, mode="nearest") if per_bin > 1 else None
    sig_full = Signals(t, np.asarray(rec.force_n, float), np.asarray(rec.voltage_v, float),
                       temp_full if has_temp else None, **common, f_smooth=f_smooth)
    fitter = Fitter(sig, n_folds, blocks_per_fold)
    say(f"base {base}")
    st = _base_structure(fitter, base)
    base_fit = fitter.evaluate(st)
    # 1. noise floor from the data: the voltage's white noise, and the reference's through the model's instantaneous
    # compliance (the creep terms low-pass it away; the static gain, 1.5-2x larger for a burgers, would overestimate
    # the floor, and validation RMSEs would come out at 0.73-0.93x of it)
    sigma_v, sigma_f = noise_std(rec.voltage_v), noise_std(rec.force_n)
    gain = abs(float(base_fit.coef_map.get("j0", 0.0)))
    floor = math.sqrt(sigma_v ** 2 + (gain * sigma_f) ** 2)
    m_eff = t.size / int(valid.sum())
    floor_d2 = floor ** 2 / m_eff  # white noise after block averaging
    base_core = core_model(st, base_fit.coef_map)
    fitter.sig = sig = _refresh_ref(sig, base_core)
    current = base_fit
    candidates, accepted, confidences, variants = [], [], {}, {}
    skipped = {}
    for name in NAMES if not has_temp else ():
        if REGISTRY[name].needs_temperature:
            skipped[name] = f"no temperature topic in the record: {name} cannot be tested"
    for name in NAMES:
        eff = REGISTRY[name]
        if eff.core_change and base not in eff.core_change and name not in skipped:
            skipped[name] = f"does not apply to a {base} base (no core type adds it)"
    def justified(fit: Fit, than: Fit) -> bool:
        """The acceptance test: ``fit`` lowers the out-of-sample error of ``than`` in ``min_confidence`` of the
        blocks and removes ``min_excess_share`` of its error above the floor (at least a quarter of the floor's own)."""
        excess = _excess(than.cv_mse, floor_d2)
        return (float(np.mean(fit.sse_folds < than.sse_folds)) >= min_confidence
                and (than.cv_mse - fit.cv_mse) / excess >= min_excess_share)

    def acceptable(c: Candidate) -> bool:
        return c.confidence >= min_confidence and c.excess_share >= min_excess_share

    def addition(to: Fit, name: str, polish: bool | str = True) -> Fit | None:
        """The best fit of ``to``'s structure with ``name`` added (every variant and grid value), None if it does not apply;
        ``polish``: the promising ones also with their time constants refitted (``"parametric"``: only the variants
        with a nonlinear parameter of their own)."""
        structs = _candidates_for(to.structure, name, has_temp, fitter.sig)
        if not structs:
            return None
        fits = [fitter.evaluate(s) for s in structs]
        excess = _excess(to.cv_mse, floor_d2)
        best_of = {}
        for f in fits:  # the best in sample of each variant
            v = f.structure.term(name).variant if f.structure.term(name) else ""
            if v not in best_of or f.fit_mse < best_of[v].fit_mse:
                best_of[v] = f
        groups = {}
        for v, f in best_of.items():
            groups.setdefault(variant_group(v), []).append(f)
        # of variants that differ only in size (the splines), the best in sample (the largest, mostly) and the best
        # out of sample: polishing each of the 5 splines at every step, swap and rebuild makes the slowest bench
        # record take 21 s, and the best in sample alone misses marginal drift events
        to_polish = {id(f): f for fs in groups.values() for f in (min(fs, key=lambda f: f.fit_mse),
                                                                  min(fs, key=lambda f: f.cv_mse))}
        # promising in sample: the time constants (the core's too) are refitted with the effect in place (inherited
        # ones let the folds trade the effect against the core); the grid fits compete too, because a polish fits in
        # sample and can predict the left-out blocks worse
        polished = [fitter.evaluate(_polish(fitter, f.structure)) for f in to_polish.values()
                    if polish and (polish != "parametric" or f.structure.term(name).param is not None)
                    and (to.fit_mse - f.fit_mse) / excess >= min_excess_share]
        return min([*polished, *fits], key=lambda f: f.cv_mse)

    def rebuild(rival: Candidate, name: str) -> Fit | None:
        """The rival's own step with every effect named since (but ``name``) added back in order, each re-chosen."""
        st: Structure | None = rival.fit.structure
        for gone in [e for e in rival.fit.structure.effects if e != rival.effect and e not in accepted]:
            st = _without(st, gone) if st is not None else None  # dropped or swapped away since that step
        if st is None:
            return None
        fit = fitter.evaluate(st)
        for other in accepted:
            if other != name and fit.structure.term(other) is None:
                added = addition(fit, other)
                if added is None:
                    return None
                fit = added
        return fit

    def rechosen(fit: Fit, skip: str, polish: bool = True) -> Fit:
        """``fit`` with each named effect (but ``skip``) re-chosen in its best shape beside the others: the shape
        chosen beside an effect now dropped may have stood in for part of it (a spline drift beside a slow delayed
        elasticity, where the drift is a settling one)."""
        for other in accepted:
            if other == skip or fit.structure.term(other) is None or REGISTRY[other].core_change:
                continue
            without = _without(fit.structure, other)
            # every shape on its grid, the best of them polished, and (``polish``) the promising variants with a
            # parameter of their own polished too: an unpolished settling drift loses to a fine spline that stands
            # in for the dropped effect (a flow beside a settling drift at 1 kHz). Polishing every promising variant
            # (8 of a hysteresis, 5 splines) makes the backward check of a three-effect record take 9 s
            again = (addition(fitter.evaluate(without), other, "parametric" if polish else False)
                     if without is not None else None)
            if again is not None and again.structure.term(other) != fit.structure.term(other):
                again = min(again, fitter.evaluate(_polish(fitter, again.structure)), key=lambda f: f.cv_mse)
            if again is not None and again.cv_mse < fit.cv_mse:
                fit = again
        return fit

    def without(fit: Fit, name: str) -> Fit | None:
        """``fit`` without ``name``: time constants polished, the other named effects re-chosen (None: not removable)."""
        reduced = _without(fit.structure, name)
        if reduced is None:
            return None
        return rechosen(fitter.evaluate(_polish(fitter, reduced)), skip=name)

    step = 0
    accepted_at = {}  # effect -> the step that named it
    seen = {frozenset()}  # sets of named effects reached: a set met again (add one, drop another) ends the search
    while len(accepted) < max_effects:
        sig = fitter.sig
        step += 1
        step_candidates = []
        reshaped = None  # the current model with its named shapes re-chosen (made when a retry needs it)
        for name in catalogue:
            if name in accepted or name in skipped:
                continue
            say(f"step {step}: {name}")
            fit = addition(current, name)
            if fit is None:
                continue
            excess = _excess(current.cv_mse, floor_d2)
            if accepted and not justified(fit, current) and (current.cv_mse - fit.cv_mse) / excess >= min_excess_share:
                # large but not consistent over the folds: the shapes named before it were chosen without it (a
                # fine spline drift standing in for a flow's creep) and may be what its folds trade against. The
                # retry is taken only when it passes the acceptance test against the current model re-chosen the
                # same way: the gain must be the new effect's, not the re-choice's alone
                again = rechosen(fit, skip=name, polish=False)
                if reshaped is None:
                    reshaped = rechosen(current, skip="", polish=False)
                if again.cv_mse < fit.cv_mse and justified(again, reshaped):
                    say(f"retry {name} with the shapes named before it re-chosen")
                    fit = again
            cand = Candidate(name, fit.structure.term(name).variant if fit.structure.term(name) else "", fit,
                             math.sqrt(fit.cv_mse), float(np.mean(fit.sse_folds < current.sse_folds)),
                             float((current.cv_mse - fit.cv_mse) / excess), step)
            candidates.append(cand)
            step_candidates.append(cand)
        best = _parsimonious(step_candidates, acceptable, justified)
        if best is None or best.confidence < min_confidence or best.excess_share < min_excess_share:
            break
        best.accepted = True
        accepted_at[best.effect] = step
        accepted.append(best.effect)
        confidences[best.effect] = best.confidence
        variants[best.effect] = best.variant
        say(f"refit with {best.effect}")
        current = _refine(fitter, best.fit.structure)
        # backward check: an effect named earlier that the newer ones make redundant is dropped. After a drop every
        # effect is checked again, the newest too: the test each had passed was against a model that still held the
        # dropped one
        to_check = list(accepted[:-1])
        while to_check:
            dropped = False
            for name in to_check:
                fit = without(current, name)
                if fit is None:
                    continue
                if not justified(current, fit):
                    say(f"drop {name}")
                    dropped = True
                    accepted.remove(name)
                    confidences.pop(name)
                    variants.pop(name)
                    for c in candidates:
                        if c.effect == name and c.accepted:
                            c.accepted = False
                    # the model kept is the one the drop was judged on, unless its refit predicts the left-out
                    # blocks better: a refit that moves the reference core can lose what the others explained,
                    # and every later check is judged against this model
                    judged_sig = fitter.sig
                    current = _refine(fitter, fit.structure, rounds=1)
                    if current.cv_mse > fit.cv_mse:
                        fitter.sig, current = judged_sig, fit
                else:
                    confidences[name] = float(np.mean(current.sse_folds < fit.sse_folds))
            to_check = list(accepted) if dropped else []
        # swap check: an effect named earlier, when a rival of its own step describes the data as well now that
        # the newer ones are in (greedy selection can name a stand-in first, e.g. a slow delayed elasticity for a
        # viscous flow plus a drift), gives way to the rival that is smaller or better by the acceptance test
        for name in list(accepted[:-1]):
            rivals = [c for c in candidates if c.step == accepted_at[name] and c.effect not in accepted and acceptable(c)]
            reduced = _without(current.structure, name) if rivals else None
            if reduced is None:
                continue
            reduced_fit = fitter.evaluate(_polish(fitter, reduced))
            for rival in sorted(rivals, key=lambda c: c.fit.cv_mse):
                fit = addition(reduced_fit, rival.effect)
                # the effects named after ``name`` were chosen (variant, grid value) beside it; beside the rival
                # they may take another shape: rebuild from the rival's own step too, and take the better
                again = rebuild(rival, name)
                if again is not None and (fit is None or again.cv_mse < fit.cv_mse):
                    fit = again
                if fit is None or not justified(fit, reduced_fit) or not (
                        (_size(fit) < _size(current) and not justified(current, fit)) or justified(fit, current)):
                    continue
                say(f"swap {name} for {rival.effect}")
                accepted[accepted.index(name)] = rival.effect
                accepted_at[rival.effect] = accepted_at.pop(name)
                confidences.pop(name)
                variants.pop(name)
                confidences[rival.effect] = float(np.mean(fit.sse_folds < reduced_fit.sse_folds))
                variants[rival.effect] = fit.structure.term(rival.effect).variant if fit.structure.term(rival.effect) else ""
                for c in candidates:
                    if c.effect == name and c.accepted:
                        c.accepted = False
                # the report shows the fit that was taken (the rival added to the reduced model), not the
                # rival's own step, whose model still held the effect it replaces
                excess = _excess(reduced_fit.cv_mse, floor_d2)
                candidates.append(Candidate(rival.effect, variants[rival.effect], fit, math.sqrt(fit.cv_mse),
                                            confidences[rival.effect],
                                            float((reduced_fit.cv_mse - fit.cv_mse) / excess), step, accepted=True))
                current = _refine(fitter, fit.structure)
                break
        if frozenset(accepted) in seen:
            break
        seen.add(frozenset(accepted))
    # the shapes saved are those of the final fit (a backward check or a swap may have re-chosen them); the
    # candidates that named them say so too (the evidence and the report's table)
    variants = {e: getattr(current.structure.term(e), "variant", "") for e in accepted}
    for c in candidates:
        if c.accepted and c.effect in variants:
            c.variant = variants[c.effect]
    say("unexplained residual")
    # 5. out-of-sample residual at the record's rate, whiteness of the slow part
    sig_full_base = _refresh_ref(sig_full, base_core, fitter.sig.span_x)
    rmse_before, _, sim_before = _oos_full(sig_full_base, base_fit, fitter, bin_of_sample)
    sig = fitter.sig
    sig_full = _refresh_ref(sig_full, sig.core_ref, sig.span_x)  # the core the columns of the fit were made with
    rmse_after, resid_after, sim_after = _oos_full(sig_full, current, fitter, bin_of_sample)
    present, structured, q, p_value, bands = _structure(t, resid_after, floor, unexplained_ratio)
    # the named effects must explain most of the base's error above the floor at the record's rate, out of
    # sample; when structure remains and they explain little of it, they are partial fits of something the
    # catalogue does not hold (a time drift following the mean of a sensitivity that drifts explains about
    # two thirds of it), and naming them would be worse than saying so. The base's excess is counted as the
    # acceptance test counts it, so a base at the floor does not make the share a ratio over ~0.
    explained = float(np.clip(1.0 - (rmse_after ** 2 - floor ** 2) / _excess(rmse_before ** 2, floor ** 2), 0.0, 1.0))
    partial = []
    if accepted and (rmse_after >= rmse_before or (present and explained < min_explained)):
        partial = list(accepted)
        say("partial fits only: unexplained")
        accepted, confidences, variants = [], {}, {}
        for c in candidates:
            c.accepted = False
        current = base_fit
        sig = fitter.sig = _refresh_ref(fitter.sig, base_core)
        rmse_after, resid_after, sim_after = rmse_before, rec.voltage_v - sim_before, sim_before
        present, structured, q, p_value, bands = _structure(t, resid_after, floor, unexplained_ratio)
    chain = build_chain(current.structure, current.coef_map, sig)
    base_chain = build_chain(base_fit.structure, base_fit.coef_map, sig)
    # 6. judged in newtons: the saved model compensates the left-out blocks at least as well as the base, with a
    # bounded inverse; otherwise its effects are partial fits (they predict the voltage but not the force)
    say("judge in newtons")
    rec_temp = temp_full if has_temp else None
    fold_rec = fitter.fold[bin_of_sample]
    from ..runtime import CompensatorConfig

    chain, bandwidth = with_safe_bandwidth(chain, t, rec.voltage_v, rec.force_n, rec_temp,
                                           rates_hz=(CompensatorConfig.noise_gain_rate_hz,))
    factor, order = bandwidth.get("filter_factor", 0.0), bandwidth.get("filter_order", 1)
    base_q = force_quality(fold_chains(lambda m: build_chain(base_fit.structure, m, sig), base_fit.names,
                                       base_fit.coef_folds), fold_rec, t, rec.voltage_v, rec.force_n, rec_temp,
                           noise_chain=base_chain)
    saved_q = base_q
    if accepted:
        saved_q = force_quality(fold_chains(lambda m: build_chain(current.structure, m, sig), current.names,
                                            current.coef_folds, lambda c: with_filter(c, factor, order)),
                                fold_rec, t, rec.voltage_v, rec.force_n, rec_temp, noise_chain=chain)
    forces_n = (base_q.force_n, saved_q.force_n)
    newtons = {"base": base_q.to_dict(), "saved": saved_q.to_dict(), "lag_bandwidth": bandwidth,
               "latency_s": chain.latency_s,
               "validation": "each left-out block compensated by the model fitted without it"}
    if accepted and not saved_q.rmse_n <= base_q.rmse_n:
        say("worse in newtons: effects not saved")
        partial = partial + [e for e in accepted if e not in partial]
        newtons["rejected"] = {"effects": list(accepted), "saved_rmse_n": saved_q.rmse_n, "base_rmse_n": base_q.rmse_n}
        newtons["saved"] = base_q.to_dict()
        forces_n = (base_q.force_n, base_q.force_n)
        accepted, confidences, variants = [], {}, {}
        for c in candidates:
            c.accepted = False
        chain, present = base_chain, True
        newtons["latency_s"] = chain.latency_s
    loc = localise(rec, rec.voltage_v - sim_after if accepted else rec.voltage_v - sim_before)
    where = _where(loc)
    unexplained = {"present": present, "rms_v": structured, "noise_floor_v": floor, "ljung_box_q": q, "bands": bands,
                   "ljung_box_p": p_value, "where": where if present else None, "partial_fits": partial,
                   "explained_share": float(explained),
                   "strongest_band_hz": [(b["low_hz"], b["high_hz"]) for b in bands
                                         if b["rms_v"] == max(x["rms_v"] for x in bands)][0] if bands else None}
    diag = Diagnosis(base, accepted, confidences, rmse_before, rmse_after, floor, unexplained, candidates, skipped, [],
                     chain, base_chain, sim_before, sim_after, loc, n_folds, blocks_per_fold, variants, current.coefficients(),
                     newtons, *forces_n)
    diag.evidence = describe(loc, diag)
    return diag


def _structure(t_s, resid_v, floor_v, ratio):
    """Whether an out-of-sample residual holds structure: ``(present, rms_v, ljung_box_q, p, bands)``.

    Two views, each against the white noise floor: the residual averaged to ~1 s, tested for whiteness
    (Ljung-Box) with a structured RMS of at least ``ratio`` of the floor; and the residual at the record's rate
    in octave bands (:func:`band_structure`), any band holding at least ``ratio`` of the floor (a resonance or
    a fast dynamic leaves nothing in 1 s averages). ``rms_v`` is the larger structured RMS of the two views.
    """
    slow = block_average(t_s, resid_v, rate_hz=1.0)[1]
    q, p_value = ljung_box(slow, lags=20)
    m_slow = t_s.size / max(slow.size, 1)
    structured = math.sqrt(max(float(np.var(slow)) - floor_v ** 2 / m_slow, 0.0))
    bands = band_structure(resid_v, t_s, floor_v)
    in_bands = max((b["rms_v"] for b in bands), default=0.0)
    present = bool((p_value < 1e-3 and structured >= ratio * floor_v) or in_bands >= ratio * floor_v)
    return present, max(structured, in_bands), q, p_value, bands


def _where(loc):
    conc = loc.get("concentration", {})
    top = sorted(conc.items(), key=lambda kv: -kv[1]["rms_ratio"])[:2]
    corr = sorted(loc.get("correlation", {}).items(), key=lambda kv: -abs(kv[1]))[:2]
    return {"segments": {k: round(v["rms_ratio"], 3) for k, v in top},
            "follows": {k: round(v, 3) for k, v in corr}}


def _oos_full(sig_full, fit: Fit, fitter: Fitter, bin_of_sample):
    """Out-of-sample RMSE at the record's rate: each sample predicted by the fit that left its fold out.

    A sample's fold is that of the fit-rate bin it was averaged into (a fold of its own, from its own time,
    would put the few samples of a bin that straddles a block boundary in a fold whose fit used them)."""
    names, a, lo, hi, ridge = design(sig_full, fit.structure)
    block = fitter.fold[bin_of_sample]
    pred = np.empty_like(sig_full.v)
    for b in range(fitter.k):
        rows = block == b
        pred[rows] = a[rows] @ fit.coef_folds[b]
    resid = sig_full.v - pred
    return float(np.sqrt(np.mean(resid ** 2))), resid, pred
