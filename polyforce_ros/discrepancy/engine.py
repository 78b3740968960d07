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
   Each gap in the record that can hide load history gets a bounded offset
   step of its own in every model, and a bounded decay of each fast
   retardation of the base core (:func:`_gap_steps`). Where the base's
   residual jumps while its core's output does not (:func:`_zero_jumps`),
   the ``steps`` and ``jumps`` variants of an offset drift put theirs.
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
   drifts the best in and out of sample only; a core effect that a refit makes
   slower than the core's own times, too; a refit that
   predicts the left-out blocks worse is not kept; a candidate that removes that
   share but not in enough folds is tried again with the shapes of the effects
   named before it re-chosen beside it, and kept if it passes the test against
   the current model re-chosen alike; an effect whose refitted model, the one
   saved, predicts no better than the step's model is not named, and the step's
   next choice is judged). Between models that both hold effects (two candidates of a step, an effect beside
   those named, a drop, a swap), the better must also differ from the other by what step 5's test would see
   (:meth:`.selection.Selection.beats`; a flow beside a drift, nearly collinear, is judged by the test above
   alone). Then the next step runs with it included; an effect that the newer ones make redundant (the
   others re-chosen in their best shape without it) is dropped again, and
   one that a rival of its own step now describes as well is swapped for it,
   until nothing more is justified or a set of effects recurs. Of two or more
   effects named, one without which the record still shows no structure at its
   own rate, and which adds less than it can show, is dropped (:func:`_drop_unseen`).
5. **Unexplained residual.** The out-of-sample residual of the final model
   at the record's rate (its nonlinear columns driven by the reference force
   as smooth as they were fitted on: a centred mean over a fit bin) is averaged
   to ~1 s and tested for whiteness (Ljung-Box), and split into octave bands
   up to the Nyquist frequency; structure whose RMS is at least
   ``unexplained_ratio`` of the noise floor, in the 1 s averages or in any
   band, is reported as ``unexplained``. When no effect was justified but structure remains, the
   answer is ``"unexplained"``, never a catalogue name; so it is when the
   named effects worsen the out-of-sample error at the record's rate, or
   leave structure, or an error whose excess over the floor is itself at least
   ``unexplained_ratio`` of the floor (structure the tests above do not see:
   bursts, chatter), while explaining less than ``min_explained`` of the
   base's error above the floor (partial fits of something outside the
   catalogue, listed under ``unexplained.partial_fits``). Before that judgement, structure in the residual, or
   a named sensor lag, is offered to a mechanical mode fitted at the record's rate (:mod:`.resonance`), named
   ``resonance`` when it passes the forward step's test; a sensor lag it makes redundant is dropped. With no
   structure left, a mode may replace a named lag but not join it.
6. **Judged in newtons** (:mod:`.newtons`). Each left-out block is
   compensated by the model fitted without it and compared with the
   reference force; a sensor lag's inverse gets an explicit bandwidth, a
   transport delay is stated as latency. A model that compensates the force
   worse than the base is not saved: its effects become partial fits.

Every candidate fit is a bounded linear least-squares problem on per-block
normal matrices (cheap to refit with any block left out); only the few time
constants are nonlinear. Fitting runs on block averages at ``fit_rate_hz``;
the reported RMSEs are out-of-sample at the record's own rate.

Modules: :mod:`.signals` (the record at a rate), :mod:`.effects` (the
catalogue), :mod:`.design` (structures, design matrices, cross-validated fits,
chains), :mod:`.refit` (time constants, the structures a step tries),
:mod:`.residual` (stages 1 and 5), :mod:`.resonance` (stage 5's mode), :mod:`.selection` (stage 4),
:mod:`.newtons` (stage 6), :mod:`.result` (the answer and its JSON); this
module runs them in order.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial
from typing import Any, Callable, Collection, Optional, Sequence

import numpy as np
from scipy import ndimage

from ..physics.chain import FrictionElement, SensorChain
from ..record import Record  # the record type diagnose takes (re-exported)
from ..runtime import CompensatorConfig
from ..runtime.compensator import runtime_chain, time_drifts
from .design import (BASES, BLOCKS_PER_FOLD, Fit, Fitter, Structure, Term, build_chain, core_model, fitted,
                     fold_of, predict, refresh_ref)
from .effects import EFFECTS as REGISTRY, NAMES, lag_stages
from .localise import describe, localise
from .newtons import (FRICTION_INVERSE_SHARES, fold_chains, force_quality, rate_of, runtime_guard, with_filter,
                      with_friction_deadband, with_friction_share, with_safe_bandwidth)
from .refit import base_structure, refine, settle
from .refit import polish as _polish, without as _without  # noqa: F401 - stages the tests run on their own, named here
from .residual import (excess, noise_floor, out_of_sample, shown_share, something_left, unexplained_test, where,
                       zero_jumps)
from .resonance import ModeFit, choose_mode, with_mode
from .result import Diagnosis
from .selection import Candidate, Selection
from .selection import parsimonious as _parsimonious  # noqa: F401 - likewise
from .signals import BoolArray, FloatArray, GapStep, IntArray, Signals, record_gaps, uniform_blocks

__all__ = ["EFFECTS", "BASES", "BLOCKS_PER_FOLD", "diagnose", "Diagnosis", "Candidate", "Record", "Signals", "Fitter",
           "Fit", "Structure", "Term", "fold_of"]

EFFECTS = NAMES


def _check(rec: Record, base: str, effects: Optional[Collection[str]]) -> FloatArray:
    """The record's reference force, after the checks that the record and the options can be diagnosed."""
    if base not in BASES:
        raise ValueError(f"base must be one of {BASES}, got {base!r}")
    if rec.force_n is None:
        raise ValueError("record has no reference force")
    signals = [("t_s", rec.t_s), ("force_n", rec.force_n), ("voltage_v", rec.voltage_v)]
    signals += [] if rec.temperature_c is None else [("temperature_c", rec.temperature_c)]
    shapes = {name: np.shape(x) for name, x in signals}
    if len(set(shapes.values())) > 1 or len(shapes["t_s"]) != 1:
        raise ValueError(f"record's signals must be 1-D of one length, got shapes {shapes}")
    bad = {name: int(np.sum(~np.isfinite(np.asarray(x, dtype=float)))) for name, x in signals}
    if any(bad.values()):
        raise ValueError("record holds non-finite samples: "
                         + ", ".join(f"{count} in {name}" for name, count in bad.items() if count))
    if rec.t_s.size < 100 or rec.t_s[-1] - rec.t_s[0] < 30.0:
        raise ValueError("record too short for a diagnosis (need at least 30 s)")
    unknown = sorted(set(effects or ()) - set(NAMES))
    if unknown:
        raise ValueError(f"unknown effects {unknown}; the catalogue holds {list(NAMES)}")
    return rec.force_n


@dataclass
class _Record:
    """The record at the fit rate and at its own, with what maps one onto the other."""

    t: FloatArray            # the record's times [s]
    temperature_c: Optional[FloatArray]
    fit_rate: Signals        # block means at the fit rate
    full_rate: Signals       # every sample
    valid: BoolArray         # fit-rate bins that hold samples
    bin_of_sample: IntArray  # the fit-rate bin of each sample


def _signals(rec: Record, force_n: FloatArray, fit_rate_hz: float) -> _Record:
    """The record at the fit rate (block means on a uniform grid) and at its own rate."""
    has_temp = rec.temperature_c is not None
    t = np.asarray(rec.t_s, dtype=float)
    temp_full = np.asarray(rec.temperature_c, dtype=float) if has_temp else np.zeros_like(t)
    td, fd, vd, tempd, valid, bin_of_sample = uniform_blocks(t, force_n, rec.voltage_v, temp_full, fit_rate_hz)
    t_ref = float(np.mean(temp_full)) if has_temp else 0.0
    span_f = max(float(np.max(fd) - min(float(np.min(fd)), 0.0)), 1e-9)
    t0, duration_s = float(t[0]), float(t[-1] - t[0])
    sig = Signals(td, fd, vd, tempd if has_temp else None, t0=t0, duration_s=duration_s, temp_ref=t_ref, span_f=span_f,
                  valid=valid)
    # at the record's rate the nonlinear columns (plays, powers of the core output) are driven by the reference force
    # as smooth as they were fitted on: a centred moving mean over a fit bin's samples (the raw force when a bin
    # holds one sample). The raw reference carries its own noise, which plays of small radii follow and block means
    # do not: driven by it, a stop hysteresis fitted to 0.0013 V at the fit rate predicts a 1 kHz record to 2.5x
    # the floor, and each sample's own block mean (a staircase) to 1.25x. The linear columns keep the raw force:
    # its fast content is worth more than its noise there. (The saved chain, run on a raw reference, still moves
    # its small plays with that noise.)
    per_bin = int(round(t.size / max(int(valid.sum()), 1)))
    f_smooth = ndimage.uniform_filter1d(np.asarray(force_n, float), per_bin, mode="nearest") if per_bin > 1 else None
    sig_full = Signals(t, np.asarray(force_n, float), np.asarray(rec.voltage_v, float),
                       temp_full if has_temp else None, t0=t0, duration_s=duration_s, temp_ref=t_ref, span_f=span_f,
                       f_smooth=f_smooth)
    return _Record(t, temp_full if has_temp else None, sig, sig_full, valid, bin_of_sample)


def _zero_jumps(data: _Record, sig: Signals, base_fit: Fit, fit_mse: float) -> None:
    """Find where the base's residual at the fit rate jumps while its core's output does not
    (:func:`.residual.zero_jumps`; not at a gap that has its own step), and give those jumps to the record at both
    rates (``sig``, the fit rate's with the base as reference core, too): every offset drift of the ``steps`` and
    ``jumps`` variants steps there."""
    stepped = [(gap.at_s - 0.5 * gap.length_s, gap.at_s + 0.5 * gap.length_s) for gap in sig.gap_steps]
    jumps = zero_jumps(sig.t, sig.v - fitted(sig, base_fit), sig.core_output,
                       sig.valid if sig.valid is not None else np.ones(sig.t.size, dtype=bool), math.sqrt(fit_mse),
                       stepped)
    data.fit_rate.zero_jumps = data.full_rate.zero_jumps = sig.zero_jumps = jumps


def _skipped(base: str, has_temperature: bool) -> dict[str, str]:
    """Effects of the catalogue that cannot be tested on this record or base -> why."""
    skipped = {}
    for name in NAMES if not has_temperature else ():
        if REGISTRY[name].needs_temperature:
            skipped[name] = f"no temperature topic in the record: {name} cannot be tested"
    for name in NAMES:
        eff = REGISTRY[name]
        if eff.core_change and base not in eff.core_change and name not in skipped:
            skipped[name] = f"does not apply to a {base} base (no core type adds it)"
    return skipped


#: How much record each side of a gap [s] the force's move across it is measured on (means over it: the reference's
#: noise averages out).
EDGE_S = 0.1


def _gap_steps(data: _Record, st: Structure, base_fit: Fit, margin_s: float) -> bool:
    """Give the record after each gap that can hide load history its own offset step, and a decay of each of the
    base core's retardations faster than ``margin_s`` (:class:`.signals.GapStep`, :func:`.signals.record_gaps`), at
    both rates; returns whether any was given. Every model gets the same steps and decays.

    A step is bounded by what the hidden load can leave: the gap's length times the force's move across it (the
    means over :data:`EDGE_S` each side; a load that moved monotonically leaves at most half of that) times the base
    core's creep rate per newton that lasts, its flow's compliance rate and the compliance over the time of each
    Kelvin unit no faster than ``margin_s``. A faster unit forgets the hidden load within the blocks that fit the step,
    but not at once: its state leaves the gap off by at most its compliance times the force's move (the hidden load
    departs from the interpolated one by no more), and decays with its own time; the bound takes the base's static
    compliance, which no unit of a refitted core exceeds. The decays run at the base's times, whatever core a model
    has: nuisance columns that differ between the models compared would favour those with more fast units. A gap in
    a hold leaves nothing and gets neither. A looser step bound (the force span), or none, lets the steps take a
    drift's events, and the drift is not found; without the decays, a fast unit's transient after a gap is structure
    no effect explains."""
    coef = base_fit.coef_map
    rate_v_per_n_s = coef.get("phi", 0.0) + sum(coef.get(f"c{i}", 0.0) / tau for i, tau in enumerate(st.taus)
                                                if tau >= margin_s)
    static_v_per_n = coef.get("j0", 0.0) + sum(coef.get(f"c{i}", 0.0) for i in range(len(st.taus)))
    decay_taus_s = tuple(tau for tau in st.taus if tau < margin_s)
    t, f = data.full_rate.t, data.full_rate.f
    steps: list[GapStep] = []
    for at, length_s in record_gaps(t, margin_s):
        before = f[np.searchsorted(t, at - length_s / 2 - EDGE_S):np.searchsorted(t, at)]
        after = f[np.searchsorted(t, at):np.searchsorted(t, at + length_s / 2 + EDGE_S)]
        moved_n = abs(float(np.mean(after)) - float(np.mean(before))) if before.size and after.size else 0.0
        if moved_n * max(rate_v_per_n_s, static_v_per_n) > 0.0:
            steps.append(GapStep(at, length_s, length_s * moved_n * rate_v_per_n_s, moved_n * static_v_per_n,
                                 decay_taus_s))
    data.fit_rate.gap_steps = data.full_rate.gap_steps = tuple(steps)
    return bool(steps)


@dataclass
class _Judgement:
    """Stage 6's answer: the chain to save, the ``newtons`` JSON, the compensated forces and whether the named
    effects were rejected."""

    chain: SensorChain
    newtons: dict[str, Any]
    force_before_n: FloatArray
    force_after_n: FloatArray
    rejected: bool


def _as_saved(chain: SensorChain, finish: Callable[[SensorChain], SensorChain], noise_v: float, factor: float,
              order: int, share: float) -> SensorChain:
    """A fold's chain as the saved model runs it: the mode, the friction's dead band and share, the lag's bandwidth."""
    return with_friction_share(with_filter(with_friction_deadband(finish(chain), noise_v), factor, order), share)


def _judge_in_newtons(rec: Record, force_n: FloatArray, data: _Record, fold_rec: IntArray, chain: SensorChain,
                      base_chain: SensorChain, base_fit: Fit, fit: Fit, sig: Signals, named: Sequence[str], noise_v: float,
                      say: Callable[[str], None],
                      finish: Callable[[SensorChain], SensorChain] = lambda c: c) -> _Judgement:
    """Stage 6: the saved model compensates the left-out blocks at least as well as the base, with a bounded inverse;
    otherwise its effects are partial fits (they predict the voltage but not the force) and the base is saved.
    ``noise_v``: the record's noise floor, which sets the friction inverse's dead band; ``finish``: what each fold's
    chain adds beyond the fitted structure (a mode fitted at the record's rate)."""
    say("judge in newtons")
    t, rec_temp = data.t, data.temperature_c
    chain = with_friction_deadband(chain, noise_v)
    chain, bandwidth = with_safe_bandwidth(chain, t, rec.voltage_v, force_n, rec_temp,
                                           rates_hz=(CompensatorConfig.noise_gain_rate_hz,))
    factor, order = bandwidth.get("filter_factor", 0.0), bandwidth.get("filter_order", 1)
    base_q = force_quality(fold_chains(lambda m: build_chain(base_fit.structure, m, sig), base_fit.names,
                                       base_fit.coef_folds), fold_rec, t, rec.voltage_v, force_n, rec_temp,
                           noise_chain=base_chain)
    saved_q = base_q
    # a friction's inverse adds back the share of it that compensates the force best: the whole of it while the
    # force slides, but the force inside the band never reaches the bridge
    shares = FRICTION_INVERSE_SHARES if "friction" in named else (1.0,)
    share_rmse_n: dict[str, float] = {}
    chosen_share = 1.0

    def saved_folds(share: float, runs: Callable[[SensorChain], SensorChain] = lambda c: c) -> list[SensorChain]:
        """One chain per fold as the saved model (friction inverse share ``share``), then ``runs``, runs it."""
        as_saved = partial(_as_saved, finish=finish, noise_v=noise_v, factor=factor, order=order, share=share)
        return fold_chains(lambda m: build_chain(fit.structure, m, sig), fit.names, fit.coef_folds,
                           lambda c: runs(as_saved(c)))

    if named:
        full = chain
        for share in shares:
            shared = with_friction_share(full, share)  # the chain saved with this share, whose noise gain is reported
            q = force_quality(saved_folds(share), fold_rec, t, rec.voltage_v, force_n, rec_temp, noise_chain=shared)
            share_rmse_n[f"{share:g}"] = q.rmse_n
            if share == shares[0] or q.rmse_n < saved_q.rmse_n:
                saved_q, chain, chosen_share = q, shared, share
    judged = _Judgement(chain, {"base": base_q.to_dict(), "saved": saved_q.to_dict(), "lag_bandwidth": bandwidth,
                                "latency_s": chain.latency_s,
                                "validation": "each left-out block compensated by the model fitted without it"},
                        base_q.force_n, saved_q.force_n, False)
    if len(share_rmse_n) > 1 and any(isinstance(e, FrictionElement) for e in chain.elements):
        judged.newtons["friction_inverse_share"] = {"chosen": chosen_share, "force_rmse_n": share_rmse_n}
    if named and not saved_q.rmse_n <= base_q.rmse_n:
        say("worse in newtons: effects not saved")
        judged.newtons["rejected"] = {"effects": list(named), "saved_rmse_n": saved_q.rmse_n,
                                      "base_rmse_n": base_q.rmse_n}
        judged.newtons["saved"] = base_q.to_dict()
        judged.force_after_n = base_q.force_n
        judged.chain, judged.rejected = base_chain, True
        judged.newtons["latency_s"] = judged.chain.latency_s
        judged.newtons.pop("friction_inverse_share", None)  # nothing of it is saved
    judged.newtons["runtime_guard"] = runtime_guard(judged.chain, rate_of(t))
    if time_drifts(judged.chain) and not judged.rejected:
        judged.newtons["saved_runtime"] = _runtime_view(judged, saved_folds(chosen_share, runtime_chain), fold_rec, t,
                                                        rec.voltage_v, force_n, rec_temp)
    return judged


def _runtime_view(judged: _Judgement, chains: Sequence[SensorChain], fold_rec: IntArray, t: FloatArray,
                  voltage_v: FloatArray, force_n: FloatArray, temperature_c: Optional[FloatArray]) -> dict[str, Any]:
    """The saved model judged as the runtime runs it by default (:func:`.runtime_chain`: its time drifts left out,
    no zeroing): the force the haptic master would receive from this record, the record's own drift left in it
    (``drift_in_force_rms_n``: what the drifts applied take out, which live the start-up zeroing, ``~/tare`` and
    ``drift_tracking`` follow instead). The saved chain always keeps its core, so the runtime never refuses it as
    a model of time drifts alone. ``chains``: the saved model's chain of each fold, as the runtime runs it."""
    q = force_quality(chains, fold_rec, t, voltage_v, force_n, temperature_c, noise_chain=runtime_chain(judged.chain))
    left_in = q.force_n - judged.force_after_n
    return {**q.to_dict(), "time_drifts_left_out": list(time_drifts(judged.chain)),
            "drift_in_force_rms_n": float(np.sqrt(np.mean(left_in ** 2)))}


def _at_full_rate(full_rate: Signals, sig: Signals) -> Signals:
    """The record at its own rate on the reference core of ``sig`` (the fit rate's), with its plays' span: the core
    the columns of a fit on ``sig`` were made with."""
    return refresh_ref(full_rate, sig.reference_core, sig.span_x)


def _own_part_v(sig_full: Signals, fit: Fit, name: str) -> Optional[FloatArray]:
    """What ``name`` adds to ``fit``'s prediction at the record's rate [V]: the prediction less that of the structure
    without it, every other coefficient as fitted (None when it cannot be removed).

    The core's columns are numbered by position: without a retardation time that is not the last, the later ones
    are renumbered, so the structure without it takes each time's coefficient by the time, not by the number."""
    reduced = _without(fit.structure, name)
    if reduced is None:
        return None
    coef, full_taus = fit.coef_map, list(fit.structure.taus)
    # column c<i> holds the i-th retardation time (a gap's decays, gap<k>_c<i>, follow the base core's times)
    as_fitted = {f"c{i}": coef.get(f"c{full_taus.index(tau)}", 0.0) for i, tau in enumerate(reduced.taus)
                 if tau in full_taus}
    return fitted(sig_full, fit) - predict(sig_full, reduced, {**coef, **as_fitted})


def _drop_unseen(selection: Selection, full_rate: Signals, bin_of_sample: IntArray, floor_v: float, ratio: float,
                 say: Callable[[str], None]) -> Signals:
    """Stage 4b: of two or more effects named, drop one that the record cannot show, while two or more are named
    and the model leaves no structure (:func:`.residual.unexplained_test`, out of sample, at the record's rate).
    An effect the record cannot show adds less to the prediction than the test sees (:func:`_own_part_v`,
    :func:`.residual.shown_share`), and
    without it (the others re-chosen) the residual still holds no structure; the smallest goes first. A drop
    re-chooses the others' shapes on the selection's reference core. ``full_rate``: the record at its own rate.

    The acceptance test's least gain (``min_excess_share`` of a quarter of the floor's mean square at the fit rate)
    lies far below what the record can show at its own rate; an effect named beside another for less than that
    describes the model's misfit of the other's shape (a lag beside creep of another spectrum at a low rate), not an
    effect of its own. An effect that adds more is kept even when the others, re-chosen, could take it: a drift
    beside a flow.

    After a drop the model is refined on its own core and kept when it predicts the left-out blocks better (as the
    backward check does) and still leaves no structure. Returns the record at its own rate on the reference core
    of the model kept (:func:`_at_full_rate`)."""
    fitter, t_s = selection.fitter, full_rate.t
    sig_full = _at_full_rate(full_rate, fitter.sig)

    def leaves_structure(fit: Fit, at_full_rate: Signals) -> bool:
        resid_v = out_of_sample(at_full_rate, fit, fitter, bin_of_sample)[1]
        return unexplained_test(t_s, resid_v, floor_v, ratio).present

    while len(selection.accepted) >= 2:
        if leaves_structure(selection.current, sig_full):
            break
        small: list[tuple[float, str]] = []
        for name in selection.accepted:
            own = _own_part_v(sig_full, selection.current, name)
            if own is None:
                continue
            shown = shown_share(t_s, own, floor_v, ratio)
            if shown < ratio:
                small.append((shown, name))
        for _, name in sorted(small):
            fit = selection.without(selection.current, name)
            if fit is None or leaves_structure(fit, sig_full):
                continue
            say(f"drop {name}: the record cannot show it")
            selection.drop(name)
            judged_sig, selection.current = fitter.sig, fit
            refined = refine(fitter, fit.structure, rounds=1)
            refined_full = sig_full if fitter.sig is judged_sig else _at_full_rate(full_rate, fitter.sig)
            if refined.cv_mse <= fit.cv_mse and not leaves_structure(refined, refined_full):
                selection.current, sig_full = refined, refined_full
            else:
                fitter.sig = judged_sig
            selection.settle_variants()
            break
        else:
            break
    return sig_full


#: Damping of the mode a named lag's delay starts the mode search from: the middle of what a lag can hide (a mode
#: damped below ~0.2 rings, and leaves structure of its own).
LAG_MODE_ZETA = 0.3


def _mode_stage(rec: Record, fitter: Fitter, sig_full: Signals, bin_of_sample: IntArray, current: Fit,
                selection: Selection, predicted_v: FloatArray, test: Any, floor_v: float, min_confidence: float,
                min_excess_share: float, say: Callable[[str], None]) -> tuple[Optional[ModeFit], Fit]:
    """Stage 5b: a mechanical mode fitted at the record's rate (:func:`.resonance.choose_mode`), named in
    ``selection`` when it passes; returns it (None when not) and the fit kept (without a sensor lag it replaces).

    The search starts from the residual's strongest band when the residual holds structure; else (a named lag
    offered as the mode's rival) from the mode that delays the signal as the lag does: 2 zeta / w = the lag's
    delay, zeta 0.3 (:data:`LAG_MODE_ZETA`)."""
    strongest = max(test.bands, key=lambda b: b["rms_v"]) if test.bands and test.present else None
    band = (strongest["low_hz"], strongest["high_hz"]) if strongest else None
    lag = current.structure.term("sensor_lag")
    if band is None and lag is not None and lag.param:  # every variant's parameter is its delay [s]
        f0_hz = LAG_MODE_ZETA / (np.pi * float(lag.param))
        band = (f0_hz / 2.0, f0_hz * 2.0)
    reduced = _without(current.structure, "sensor_lag") if "sensor_lag" in selection.accepted else None
    reduced_fit = fitter.evaluate(reduced) if reduced is not None else None
    fold = fitter.fold[bin_of_sample]
    without_lag = None if reduced_fit is None else out_of_sample(sig_full, reduced_fit, fitter, bin_of_sample)[2]
    stages_s = lag_stages(lag.variant, float(lag.param)) if lag is not None and lag.param and reduced is not None else []
    mode, drop_lag = choose_mode(rec.t_s, rec.voltage_v, predicted_v, fold, floor_v, band, min_confidence,
                                 min_excess_share, without_lag, structure_seen=bool(test.present), lag_stages_s=stages_s)
    if drop_lag and reduced_fit is not None:
        say("drop sensor_lag: the mode holds it")
        selection.drop("sensor_lag")
        current = reduced_fit
    if mode is not None:
        selection.name_at_record_rate("resonance", mode.confidence, mode.excess_share)
    return mode, current


def diagnose(rec: Record, base: str = "burgers", fit_rate_hz: float = 100.0, n_folds: int = 5,
             min_confidence: float = 0.8, min_excess_share: float = 0.3, unexplained_ratio: float = 0.5,
             min_explained: float = 0.8, max_effects: int = 4, effects: Optional[Collection[str]] = None,
             progress: Optional[Callable[[str], None]] = None, blocks_per_fold: int = BLOCKS_PER_FOLD) -> Diagnosis:
    """Run the whole workflow on one record (see the module docstring).

    ``effects``: names of the catalogue to consider (default: all of :data:`EFFECTS`).
    ``progress``: called with a short text before each step (a progress bar).
    """
    force_n = _check(rec, base, effects)
    say: Callable[[str], None] = progress or (lambda step: None)
    catalogue = [n for n in NAMES if effects is None or n in effects]
    has_temp = rec.temperature_c is not None
    data = _signals(rec, force_n, fit_rate_hz)
    t, valid, bin_of_sample = data.t, data.valid, data.bin_of_sample
    fitter = Fitter(data.fit_rate, n_folds, blocks_per_fold)
    say(f"base {base}")
    st = base_structure(fitter, base)
    base_fit = fitter.evaluate(st)
    if _gap_steps(data, st, base_fit, 2.0 * (t[-1] - t[0]) / (n_folds * blocks_per_fold)):
        base_fit = fitter.evaluate(st)
    # 1. noise floor from the data
    noise = noise_floor(rec.voltage_v, force_n, base_fit.coef_map.get("j0", 0.0), t.size / int(valid.sum()))
    floor = noise.floor_v
    base_core = core_model(st, base_fit.coef_map)
    fitter.sig = refresh_ref(data.fit_rate, base_core)
    if "offset_drift" in catalogue:
        _zero_jumps(data, fitter.sig, base_fit, noise.fit_mse)
    skipped = _skipped(base, has_temp)
    # 4. forward selection, backward check and swap
    selection = Selection(fitter, base_fit, noise.fit_mse, has_temp, min_confidence, min_excess_share, say,
                          floor_v=floor, unexplained_ratio=unexplained_ratio)
    selection.run(catalogue, list(skipped), max_effects)
    sig_full = _drop_unseen(selection, data.full_rate, bin_of_sample, floor, unexplained_ratio, say)
    if selection.current.structure.term("nonlinear_gain") is not None:
        # the model saved is the model scored: a fit kept from before a refit (a drop, a re-choice) has its gain's
        # columns on another core than its own
        judged_sig = fitter.sig
        selection.current = settle(fitter, selection.current.structure, rounds=0)
        if fitter.sig is not judged_sig:
            sig_full = _at_full_rate(data.full_rate, fitter.sig)
    sig = fitter.sig
    current = selection.current
    say("unexplained residual")
    # 5. out-of-sample residual at the record's rate, whiteness of the slow part
    sig_full_base = refresh_ref(data.full_rate, base_core, fitter.sig.span_x)
    rmse_before, _, sim_before = out_of_sample(sig_full_base, base_fit, fitter, bin_of_sample)
    rmse_after, resid_after, sim_after = out_of_sample(sig_full, current, fitter, bin_of_sample)
    test = unexplained_test(t, resid_after, floor, unexplained_ratio)
    # 5b. a mechanical mode, at the record's rate, on what the selection predicts
    mode = None
    # a moderately damped mode is also a low-pass: a sensor lag named at the fit rate may hold all of it and leave
    # no structure, so a named lag is always offered to the mode as a rival
    if "resonance" in catalogue and (test.present or "sensor_lag" in selection.accepted):
        say("resonance at the record's rate")
        mode, current = _mode_stage(rec, fitter, sig_full, bin_of_sample, current, selection, sim_after, test, floor,
                                    min_confidence, min_excess_share, say)
        if mode is not None:
            sim_after = mode.predicted_v
            resid_after = rec.voltage_v - sim_after
            rmse_after = float(np.sqrt(np.mean(resid_after ** 2)))
            test = unexplained_test(t, resid_after, floor, unexplained_ratio)
    # the named effects must explain most of the base's error above the floor at the record's rate, out of
    # sample; when structure remains and they explain little of it, they are partial fits of something the
    # catalogue does not hold (a time drift following the mean of a sensitivity that drifts explains about
    # two thirds of it), and naming them would be worse than saying so. The base's excess is counted as the
    # acceptance test counts it, so a base at the floor does not make the share a ratio over ~0.
    explained = float(np.clip(1.0 - (rmse_after ** 2 - floor ** 2) / excess(rmse_before ** 2, floor ** 2), 0.0, 1.0))
    partial: list[str] = []
    if selection.accepted and (rmse_after >= rmse_before or (
            something_left(test.present, rmse_after, floor, unexplained_ratio) and explained < min_explained)):
        partial = list(selection.accepted)
        say("named effects dropped as partial fits")
        selection.clear()
        current = base_fit
        sig = fitter.sig = refresh_ref(fitter.sig, base_core)
        rmse_after, resid_after, sim_after = rmse_before, rec.voltage_v - sim_before, sim_before
        test = unexplained_test(t, resid_after, floor, unexplained_ratio)
    def finish(c: SensorChain) -> SensorChain:  # what the selection's structure does not hold: the mode
        return with_mode(c, mode) if mode is not None and "resonance" in selection.accepted else c

    chain = finish(build_chain(current.structure, current.coef_map, sig))
    base_chain = build_chain(base_fit.structure, base_fit.coef_map, sig)
    # 6. judged in newtons
    judged = _judge_in_newtons(rec, force_n, data, fitter.fold[bin_of_sample], chain, base_chain, base_fit, current, sig,
                               selection.accepted, floor, say, finish)
    # partial fits of what the base leaves well above the floor are something the catalogue does not hold, whether
    # or not its residual shows structure; names that only predict worse than the base, at the floor, leave nothing
    present = test.present or (bool(partial) and something_left(False, rmse_after, floor, unexplained_ratio))
    if judged.rejected:
        partial = partial + [e for e in selection.accepted if e not in partial]
        selection.clear()
        present = True
    accepted = selection.accepted
    loc = localise(rec, rec.voltage_v - sim_after if accepted else rec.voltage_v - sim_before)
    bands = test.bands
    unexplained = {"present": present, "rms_v": test.rms_v, "noise_floor_v": floor, "ljung_box_q": test.ljung_box_q,
                   "bands": bands, "ljung_box_p": test.ljung_box_p, "where": where(loc) if present else None,
                   "partial_fits": partial, "explained_share": float(explained),
                   "strongest_band_hz": [(b["low_hz"], b["high_hz"]) for b in bands
                                         if b["rms_v"] == max(x["rms_v"] for x in bands)][0] if bands else None}
    diag = Diagnosis(base, accepted, selection.confidences, rmse_before, rmse_after, floor, unexplained,
                     selection.candidates, skipped, [], judged.chain, base_chain, sim_before, sim_after, loc, n_folds,
                     blocks_per_fold, selection.variants, current.coefficients(), judged.newtons, judged.force_before_n,
                     judged.force_after_n)
    diag.evidence = describe(loc, diag)
    return diag
