"""The selection of effects (stage 4 of :func:`.engine.diagnose`): forward selection, backward check and swap.

A :class:`Selection` holds the state of the search on one record: the current model, the effects named (in
order), their confidences and shapes, and every candidate scored. Each round
(:meth:`Selection.run`) is three stages:

1. :meth:`~Selection.forward_step` adds every applicable effect in turn and scores it out of sample; the best
   (or a smaller one it does not beat, :func:`parsimonious`) is named when it passes the acceptance test
   (:meth:`~Selection.justified`) and the model refitted with it predicts better (:meth:`~Selection.accept`;
   else the step's next choice is judged).
2. :meth:`~Selection.backward_check` drops an effect named earlier that the newer ones make redundant.
3. :meth:`~Selection.swap_check` swaps an effect named earlier for a rival of its own step that now describes the
   data as well.

Between models that hold effects (two candidates of a step, an effect beside those named, a drop, a swap), one is
better than the other only by a difference the record can show at its own rate (:meth:`~Selection.beats`), except
between a flow and a drift, where the acceptance test alone decides (:data:`COLLINEAR`).

The rounds end when nothing more is justified, the most effects are named, or a set of effects recurs.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Optional, Sequence, Union

import numpy as np

from ..physics.fitting import block_jackknife_standard_errors
from .design import Fit, Fitter, Structure, design_columns, fitted, n_params, size, term_columns
from .effects import EFFECTS as REGISTRY, SPREAD_RATIO, variant_group
from .friction import at_noise_limit
from .refit import candidates_for, is_core_time, polish, refine, without
from .residual import drift_follows_load, excess, passes, shown_share, slow_response_columns

__all__ = ["Candidate", "parsimonious", "Selection"]


@dataclass
class Candidate:
    """An effect tried at one step of the selection, with its best fit and how it scored.

    Attributes
    ----------
    effect, variant : str
        The effect and the shape it was fitted in.
    fit : Fit
    rmse_v : float
        Out-of-sample RMSE at the fit rate [V].
    confidence : float
        Share of folds where it lowers the out-of-sample error.
    excess_share : float
        Share of the current error above the noise floor it removes.
    step : int
        The selection step that tried it.
    accepted : bool
        Whether it names an effect of the answer.
    retried : bool
        Whether it was judged with the shapes named before it re-chosen beside it.
    """

    effect: str
    variant: str
    fit: Fit
    rmse_v: float
    confidence: float
    excess_share: float
    step: int
    accepted: bool = False
    retried: bool = False

    def summary(self) -> dict[str, Any]:
        """Plain data for the JSON's ``candidates`` list."""
        return {"effect": self.effect, "variant": self.variant, "step": self.step, "rmse": self.rmse_v,
                "rmse_fit": math.sqrt(self.fit.fit_mse), "criterion": self.fit.bic, "confidence": self.confidence,
                "excess_share": self.excess_share, "accepted": self.accepted,
                "n_params": n_params(self.fit)}


#: Effects whose columns a load that seldom rests makes nearly collinear: one named beside the other is judged by
#: the acceptance test alone (:meth:`Selection.beats`).
COLLINEAR = frozenset({"viscous_flow", "offset_drift"})


def _collinear(a: Structure, b: Structure) -> bool:
    """Whether two structures differ by one effect of :data:`COLLINEAR` and both hold the other."""
    ea, eb = set(a.effects), set(b.effects)
    differing = ea ^ eb
    return len(differing) == 1 and differing < COLLINEAR and COLLINEAR - differing <= ea & eb


def parsimonious(cands: Sequence[Candidate], acceptable: Callable[[Candidate], bool],
                 justified: Callable[[Fit, Fit], bool]) -> Optional[Candidate]:
    """The candidate of one step to judge: the lowest out-of-sample error, unless the acceptable candidates of
    smaller nominal size (:func:`.design.size`) include some that it does not beat (``justified(better, than)``:
    :meth:`Selection.beats`, the acceptance test by a margin the record can show); then the smallest of those (the
    lower error among equals). Always compared with the overall best, so the choice is not path-bound."""
    if not cands:
        return None
    best = min(cands, key=lambda c: c.fit.cv_mse)
    equivalent = [c for c in cands if acceptable(c) and size(c.fit) < size(best.fit) and not justified(best.fit, c.fit)]
    if not equivalent:
        return best
    return min(equivalent, key=lambda c: (size(c.fit), c.fit.cv_mse))


def _variant(fit: Fit, effect: str) -> str:
    """The variant ``effect`` has in ``fit`` ("" when the fit does not hold it)."""
    term = fit.structure.term(effect)
    return term.variant if term else ""


#: How many block-jackknife standard errors a column that a larger variant adds must lie from zero.
SIGNIFICANT_SE = 3.0


class Selection:
    """The search for the effects that explain a record, from its base fit.

    Parameters
    ----------
    fitter : Fitter
        The record at the fit rate, with its reference core set to the base's.
    base_fit : Fit
        The base model: the first current model.
    floor_mse : float
        The noise floor's mean square at the fit rate [V^2] (:class:`.residual.NoiseFloor`).
    has_temperature : bool
        Whether the record has a temperature topic.
    min_confidence, min_excess_share : float
        The acceptance test's thresholds (:meth:`justified`).
    say : callable
        Called with a short text before each step (a progress bar).
    floor_v : float
        The noise floor at the record's rate [V]; 0: every difference between two models counts as shown.
    unexplained_ratio : float
        What the record can show, as a share of ``floor_v`` (step 5's test; :meth:`shows`).

    Attributes
    ----------
    current : Fit
        The current model.
    accepted : list of str
        The effects named, in the order they were named.
    confidences, variants : dict
        The confidence and the variant of each effect named.
    candidates : list of Candidate
        Every candidate scored, in order.
    """

    def __init__(self, fitter: Fitter, base_fit: Fit, floor_mse: float, has_temperature: bool, min_confidence: float,
                 min_excess_share: float, say: Callable[[str], None], floor_v: float = 0.0,
                 unexplained_ratio: float = 0.5) -> None:
        self.fitter = fitter
        self.floor_mse = floor_mse
        self.floor_v = floor_v
        self.unexplained_ratio = unexplained_ratio
        self.has_temperature = has_temperature
        self.min_confidence = min_confidence
        self.min_excess_share = min_excess_share
        self.say = say
        self.current = base_fit
        self.candidates: list[Candidate] = []
        self.accepted: list[str] = []
        self.confidences: dict[str, float] = {}
        self.variants: dict[str, str] = {}
        self.accepted_at: dict[str, int] = {}  # effect -> the step that named it
        self.step = 0

    # ------------------------------------------------------------------------- the acceptance test

    def justified(self, fit: Fit, than: Fit) -> bool:
        """The acceptance test: ``fit`` lowers the out-of-sample error of ``than`` in ``min_confidence`` of the
        blocks and removes ``min_excess_share`` of its error above the floor (at least a quarter of the floor's own)."""
        share = excess(than.cv_mse, self.floor_mse)
        return passes(float(np.mean(fit.sse_folds < than.sse_folds)), (than.cv_mse - fit.cv_mse) / share,
                      self.min_confidence, self.min_excess_share)

    def shows(self, fit: Fit, than: Fit) -> bool:
        """Whether the record can show how ``fit`` differs from ``than``: the unexplained test (step 5) would see the
        difference of their predictions (every block, the fit rate) at ``unexplained_ratio`` of the floor
        (:func:`.residual.shown_share`). Both are fitted on the signals the fitter holds."""
        sig = self.fitter.sig
        part_v = fitted(sig, fit) - fitted(sig, than)
        return shown_share(sig.t, part_v, self.floor_v, self.unexplained_ratio) >= self.unexplained_ratio

    def beats(self, fit: Fit, than: Fit) -> bool:
        """Whether ``fit`` is better than ``than``, a model that holds effects too: it passes the acceptance test
        against it (:meth:`justified`) and the record can show the difference (:meth:`shows`).

        Against the base alone the acceptance test decides (over a whole record it finds an effect far smaller than
        any one second shows). Between models that hold effects (a larger candidate of a step over a smaller one,
        an effect beside those named, one kept in the backward check, a swap) its least gain lies far below what
        the record shows at its own rate: a model better by less describes another's misfit of a shape it nearly
        holds (a spline in time following a zero that a buffered thermometer moves, a Kelvin unit beside a drift
        that wanders), not an effect of its own.

        Except between a flow and a drift (:data:`COLLINEAR`): a flow creeps as the integral of the force and a
        drift moves with time, two columns that a load which seldom rests makes nearly the same. Refitted without
        one, the other takes most of it, so the refits differ by less than the record holds of either; the record
        tells them apart only at its rests and load changes, which is what the acceptance test's fold-by-fold gain
        weighs, so it decides alone there."""
        if not than.structure.terms or _collinear(fit.structure, than.structure):
            return self.justified(fit, than)
        return self.justified(fit, than) and self.shows(fit, than)

    def noise_limited(self, fit: Fit, name: str) -> bool:
        """Whether ``name``'s parameter in ``fit`` sits at the narrowest bound its search allows
        (:func:`.friction.at_noise_limit`): such a fit describes the input's noise, and names nothing."""
        term = fit.structure.term(name)
        return term is not None and at_noise_limit(name, term.param, self.fitter.sig)

    def follows_load(self, fit: Fit) -> bool:
        """Whether ``fit``'s offset drift follows the load rather than time (:func:`.residual.drift_follows_load`):
        such a drift stands in for a load-dependent shape the model misses, and names nothing."""
        term = fit.structure.term("offset_drift")
        if term is None:
            return False
        sig = self.fitter.sig
        coef = fit.coef_map
        # the drift's columns are additive (no lag filters them): as they stand in the design
        drift = sum((coef[name] * col for name, col, *_ in term_columns(sig, term)), np.zeros_like(sig.v))
        names, mats, *_ = design_columns(sig, fit.structure)
        model = sum((coef[n] * m for n, m in zip(names, mats)), np.zeros_like(sig.v))
        return drift_follows_load(sig, model - drift, drift)

    def driven_as_well(self, fit: Fit) -> bool:
        """Whether ``fit``'s offset drift is predicted as well by a generic slow response to the load and the
        temperature (:func:`.residual.slow_response_columns`) in its place: the left-out blocks are predicted at
        least as well by what drives the sensor as by time, so the drift stands in for the shape of an effect of
        the load or the temperature, and names nothing."""
        term = fit.structure.term("offset_drift")
        reduced = without(fit.structure, "offset_drift") if term is not None else None
        if reduced is None:
            return False
        sig = self.fitter.sig
        key = ("slow rival", reduced)  # per reference core, as the design's columns are
        if key not in sig.cache:
            sig.cache[key] = self.fitter.evaluate(reduced, slow_response_columns(sig)).cv_mse
        return bool(sig.cache[key] <= fit.cv_mse)

    def why_not_judged(self, fit: Fit, name: str) -> Optional[str]:
        """Why ``name`` in ``fit`` names nothing (at its noise limit, an offset drift that follows the load, or one
        that the load or temperature history predicts as well), None when it is judged: such a fit is neither
        judged in its step, nor re-judged, nor swapped in later."""
        if self.noise_limited(fit, name):
            return "at its noise limit"
        if name == "offset_drift" and self.follows_load(fit):
            return "follows the load"
        if name == "offset_drift" and self.driven_as_well(fit):
            return "predicted as well by the load and temperature history"
        return None

    def not_judged(self, fit: Fit, name: str) -> bool:
        """Whether ``name`` in ``fit`` names nothing (:meth:`why_not_judged`)."""
        return self.why_not_judged(fit, name) is not None

    def acceptable(self, c: Candidate) -> bool:
        """Whether a candidate passed the acceptance test against the model of its step."""
        return passes(c.confidence, c.excess_share, self.min_confidence, self.min_excess_share)

    # ------------------------------------------------------------------------- models tried

    def addition(self, to: Fit, name: str, polish_: Union[bool, str] = True) -> Optional[Fit]:
        """The best fit of ``to``'s structure with ``name`` added (every variant and grid value), None if it does not
        apply; ``polish_``: the promising ones also with their time constants refitted (``"parametric"``: only the
        variants with a nonlinear parameter of their own)."""
        fitter = self.fitter
        structs = candidates_for(to.structure, name, self.has_temperature, fitter.sig)
        if not structs:
            return None
        fits = [fitter.evaluate(s) for s in structs]
        share = excess(to.cv_mse, self.floor_mse)
        best_of: dict[str, Fit] = {}
        for f in fits:  # the best in sample of each variant
            v = _variant(f, name)
            if v not in best_of or f.fit_mse < best_of[v].fit_mse:
                best_of[v] = f
        groups: dict[str, list[Fit]] = {}
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
        promising = {k: f for k, f in to_polish.items() if (to.fit_mse - f.fit_mse) / share >= self.min_excess_share}
        polished = [fitter.evaluate(polish(fitter, f.structure)) for f in promising.values()
                    if polish_ and (polish_ != "parametric" or _has_param(f, name))]
        if polish_ is True and REGISTRY[name].core_change:  # by id: Fits compare by value, arrays and all
            polished += self._slower_core(to, name, [f for k, f in to_polish.items() if k not in promising])
        return min(self._nested([*polished, *fits], name), key=lambda f: f.cv_mse)

    def _slower_core(self, to: Fit, name: str, fits: list[Fit]) -> list[Fit]:
        """``fits`` of the core effect ``name`` polished, of those that then add flow or hold a retardation slower
        than every time of ``to``'s core: the current core's slowest time stood in for such an effect (it holds part of a
        missing flow, or of a Kelvin unit slower than the record), so its grid fits, which keep that time, understate
        it, and a time drift, which needs no such refit, would be named in its place. A polish that takes a time
        outside the effect's own grid is not kept: below it, a retardation not promising on its grid would take a
        sensor lag's misfit; above it, one that a flow beside a drift describes as well (a delayed elasticity's
        grid ends at a quarter of the record)."""
        slowest = max(to.structure.taus, default=0.0)
        out = []
        for f in fits:
            p = self.fitter.evaluate(polish(self.fitter, f.structure))
            term = p.structure.term(name)  # a flow has no time of its own: a dashpot is the slowest there is
            if term is None or not is_core_time(term):
                out.append(p)
                continue
            taus = p.structure.taus
            grid = [g for g in REGISTRY[name].grid(term.variant, self.fitter.sig) if g is not None]
            reach = SPREAD_RATIO ** (REGISTRY[name].core_times.get(term.variant, 1) - 1)  # a spread's further units
            if grid and max(taus) > slowest and min(grid) <= min(taus) and max(taus) <= max(grid) * reach:
                out.append(p)  # slower, and every time within the effect's own range
        return out

    def _nested(self, fits: list[Fit], name: str) -> list[Fit]:
        """``fits`` without those of a variant that extends a smaller one (:attr:`.effects.Effect.extends`) whose
        added columns are not each at least :data:`SIGNIFICANT_SE` block-jackknife standard errors from zero (a
        column the folds cannot agree on describes nothing the smaller variant misses; for a variant of
        :attr:`.effects.Effect.summed`, the sum of its added weights), or that does not improve on
        the smaller variant's best fit as an added effect must improve on the current model (:meth:`justified`),
        nor on the best fit of each further variant it holds (:attr:`.effects.Effect.also_holds`): a column that is
        certain but small describes a misfit of the record, not the shape of the effect."""
        extends, also_holds = REGISTRY[name].extends, REGISTRY[name].also_holds
        smaller = {v: {n for f in fits if _variant(f, name) == s for n in f.names} for v, s in extends.items()}
        held = {*extends.values(), *(s for group in also_holds.values() for s in group)}
        smallest_fit: dict[str, Fit] = {}
        for f in fits:
            v = _variant(f, name)
            if v in held and (v not in smallest_fit or f.cv_mse < smallest_fit[v].cv_mse):
                smallest_fit[v] = f

        def kept_beside_smaller(f: Fit) -> bool:
            v = REGISTRY[name].grid_variant(_variant(f, name))
            if v not in extends:
                return True
            co = f.coefficients()
            added = [n for n in f.names if n not in smaller[v] and n in co]
            if v in REGISTRY[name].summed:  # weights of one distribution: most sit at zero, their sum says it all
                if not smaller[v] or not added:  # without the smaller fit nothing says which columns it adds
                    return False
                at = [f.names.index(n) for n in added]
                total = float(np.sum(f.coef[at]))
                error = float(block_jackknife_standard_errors([[float(np.sum(c[at]))] for c in f.coef_folds])[0])
                if not (np.isfinite(error) and abs(total) > SIGNIFICANT_SE * error):  # a sum of zeros is not 0 >= 0
                    return False
            elif not all(abs(co[n]["value"]) >= SIGNIFICANT_SE * co[n]["standard_error"] for n in added):
                return False
            rivals = [smallest_fit.get(s) for s in (extends[v], *also_holds.get(v, ()))]
            return all(rival is None or self.justified(f, rival) for rival in rivals)

        kept = [f for f in fits if kept_beside_smaller(f)]
        return kept or fits

    def rebuild(self, rival: Candidate, name: str) -> Optional[Fit]:
        """The rival's own step with every effect named since (but ``name``) added back in order, each re-chosen."""
        st: Optional[Structure] = rival.fit.structure
        for gone in [e for e in rival.fit.structure.effects if e != rival.effect and e not in self.accepted]:
            st = without(st, gone) if st is not None else None  # dropped or swapped away since that step
        if st is None:
            return None
        fit = self.fitter.evaluate(st)
        for other in self.accepted:
            if other != name and fit.structure.term(other) is None:
                added = self.addition(fit, other)
                if added is None:
                    return None
                fit = added
        return fit

    def rechosen(self, fit: Fit, skip: str, polish_: bool = True) -> Fit:
        """``fit`` with each named effect (but ``skip``) re-chosen in its best shape beside the others: the shape
        chosen beside an effect now dropped may have stood in for part of it (a spline drift beside a slow delayed
        elasticity, where the drift is a settling one)."""
        fitter = self.fitter
        for other in self.accepted:
            if other == skip or fit.structure.term(other) is None or REGISTRY[other].core_change:
                continue
            reduced = without(fit.structure, other)
            # every shape on its grid, the best of them polished, and (``polish_``) the promising variants with a
            # parameter of their own polished too: an unpolished settling drift loses to a fine spline that stands
            # in for the dropped effect (a flow beside a settling drift at 1 kHz). Polishing every promising variant
            # (8 of a hysteresis, 5 splines) makes the backward check of a three-effect record take 9 s
            again = (self.addition(fitter.evaluate(reduced), other, "parametric" if polish_ else False)
                     if reduced is not None else None)
            if again is not None and again.structure.term(other) != fit.structure.term(other):
                again = min(again, fitter.evaluate(polish(fitter, again.structure)), key=lambda f: f.cv_mse)
            if again is not None and again.cv_mse < fit.cv_mse and not self.noise_limited(again, other):
                fit = again
        return fit

    def without(self, fit: Fit, name: str) -> Optional[Fit]:
        """``fit`` without ``name``: time constants polished, the other named effects re-chosen (None: not removable)."""
        reduced = without(fit.structure, name)
        if reduced is None:
            return None
        return self.rechosen(self.fitter.evaluate(polish(self.fitter, reduced)), skip=name)

    # ------------------------------------------------------------------------- the stages

    def forward_step(self, catalogue: Sequence[str], skipped: Sequence[str]) -> list[Candidate]:
        """One step of the forward selection: every effect of ``catalogue`` not named yet nor ``skipped`` nor a
        rival of a named one (:attr:`.effects.Effect.rivals`) nor fitted at the record's rate added to the current
        model and scored; returns the candidates judged (the one to judge first is :func:`parsimonious`'s).

        A candidate that removes ``min_excess_share`` of the current error above the floor but not in enough folds
        is tried again with the shapes named before it re-chosen beside it (they were chosen without it, e.g. a fine
        spline drift standing in for a flow's creep, and may be what its folds trade against); the retry is kept
        only when it passes the acceptance test against the current model re-chosen the same way, so that the gain
        is the new effect's, not the re-choice's alone. Once one candidate is retried, every other that removes that
        share is judged with the shapes re-chosen beside it too (:meth:`_reshaped_too`)."""
        self.step += 1
        current = self.current
        step_candidates = []
        reshaped: Optional[Fit] = None  # the current model with its named shapes re-chosen (made when a retry needs it)
        for name in catalogue:
            if (name in self.accepted or name in skipped or set(REGISTRY[name].rivals) & set(self.accepted)
                    or REGISTRY[name].record_rate):
                continue
            self.say(f"step {self.step}: {name}")
            fit = self.addition(current, name)
            if fit is None:
                continue
            retried = False
            share = excess(current.cv_mse, self.floor_mse)
            if (self.accepted and not self.justified(fit, current)
                    and (current.cv_mse - fit.cv_mse) / share >= self.min_excess_share):
                again = self.rechosen(fit, skip=name, polish_=False)
                if reshaped is None:
                    reshaped = self.rechosen(current, skip="", polish_=False)
                if again.cv_mse < fit.cv_mse and self.justified(again, reshaped):
                    self.say(f"retry {name} with the shapes named before it re-chosen")
                    fit, retried = again, True
            cand = Candidate(name, _variant(fit, name), fit,
                             math.sqrt(fit.cv_mse), float(np.mean(fit.sse_folds < current.sse_folds)),
                             float((current.cv_mse - fit.cv_mse) / share), self.step, retried=retried)
            self.candidates.append(cand)
            why = self.why_not_judged(fit, name)
            if why is None and self.justified(fit, current) and not self.beats(fit, current):
                why = "adds less than the record can show"
            if why is not None:
                self.say(f"step {self.step}: {name} {why}, not judged")
                continue
            step_candidates.append(cand)
        if any(c.retried for c in step_candidates):
            step_candidates = [self._reshaped_too(c, current) for c in step_candidates]
        return step_candidates

    def _reshaped_too(self, cand: Candidate, current: Fit) -> Candidate:
        """``cand`` with the shapes named before it re-chosen beside it, when that predicts better and it was not
        retried so: once one candidate of a step is judged with the named shapes re-chosen, every candidate that
        removes enough of the excess is, or a larger rival wins on the re-choice alone (a slow delayed elasticity
        over a flow, each beside a settling drift)."""
        share = excess(current.cv_mse, self.floor_mse)
        if cand.retried or cand.excess_share < self.min_excess_share:
            return cand
        again = self.rechosen(cand.fit, skip=cand.effect, polish_=False)
        if again.cv_mse >= cand.fit.cv_mse or self.not_judged(again, cand.effect):
            return cand
        self.say(f"re-choose the shapes beside {cand.effect} too")
        out = Candidate(cand.effect, _variant(again, cand.effect), again, math.sqrt(again.cv_mse),
                        float(np.mean(again.sse_folds < current.sse_folds)),
                        float((current.cv_mse - again.cv_mse) / share), self.step, retried=True)
        # by identity: candidates compare by value, and a Fit's arrays have no single truth value
        self.candidates[next(i for i, c in enumerate(self.candidates) if c is cand)] = out
        return out

    def accept(self, best: Candidate) -> bool:
        """Name ``best``'s effect and refit the model with it (:func:`.refit.refine`); False, with nothing named
        and the model as before, when the refitted model predicts the left-out blocks no better than the model of
        the step. The candidate was scored with columns made from the step's reference core; the model kept (and
        saved) has them made from its own core (:func:`.refit.settle`), and where the two differ in shape (a
        voltage-path hysteresis that takes part of the core's gain and creep) the effect in its saved form may
        not help at all: every later step would be judged against a model worse than the one it replaced."""
        best.accepted = True
        self.accepted_at[best.effect] = self.step
        self.accepted.append(best.effect)
        self.confidences[best.effect] = best.confidence
        self.variants[best.effect] = best.variant
        self.say(f"refit with {best.effect}")
        # the shapes named before it were chosen without it
        refined = self.saved_form(best.fit.structure, self.current, best.effect if len(self.accepted) > 1 else "")
        if refined is not None:
            self.current = refined
            return True
        self.say(f"{best.effect}: its refitted model predicts no better, not named")
        self.drop(best.effect)
        return False

    def saved_form(self, structure: Structure, than: Fit, rechoose_beside: str = "") -> Optional[Fit]:
        """``structure`` as the model keeps (and saves) it: refined on its own reference core (:func:`.refit.refine`),
        with the shapes named beside ``rechoose_beside`` re-chosen (:meth:`rechosen`) when given; None, with the
        fitter's reference core as before, when it predicts the left-out blocks no better than ``than``. The rule
        by which an effect is named (:meth:`accept`) or swapped in (:meth:`swap_check`) only when it helps in its
        saved form."""
        sig_before = self.fitter.sig
        fit = refine(self.fitter, structure)
        if rechoose_beside:
            fit = self.rechosen(fit, skip=rechoose_beside)
        if fit.cv_mse < than.cv_mse:
            return fit
        self.fitter.sig = sig_before
        return None

    def _unname(self, name: str) -> None:
        """``name`` no longer names an effect of the answer."""
        self.confidences.pop(name)
        self.variants.pop(name)
        for c in self.candidates:
            if c.effect == name and c.accepted:
                c.accepted = False

    def backward_check(self) -> None:
        """Drop an effect named earlier that the newer ones make redundant. After a drop every effect is checked
        again, the newest too: the test each had passed was against a model that still held the dropped one."""
        fitter = self.fitter
        to_check = list(self.accepted[:-1])
        while to_check:
            dropped = False
            for name in to_check:
                fit = self.without(self.current, name)
                if fit is None:
                    continue
                if not self.beats(self.current, fit):
                    self.say(f"drop {name}")
                    dropped = True
                    self.drop(name)
                    # the model kept is the one the drop was judged on, unless its refit predicts the left-out
                    # blocks better: a refit that moves the reference core can lose what the others explained,
                    # and every later check is judged against this model
                    judged_sig = fitter.sig
                    self.current = refine(fitter, fit.structure, rounds=1)
                    if self.current.cv_mse > fit.cv_mse:
                        fitter.sig, self.current = judged_sig, fit
                else:
                    self.confidences[name] = float(np.mean(self.current.sse_folds < fit.sse_folds))
            to_check = list(self.accepted) if dropped else []

    def swap_check(self) -> None:
        """Swap an effect named earlier for a rival of its own step that describes the data as well now that the
        newer ones are in (greedy selection can name a stand-in first, e.g. a slow delayed elasticity for a viscous
        flow plus a drift): the rival takes its place when it is smaller or better by the acceptance test."""
        fitter = self.fitter
        for name in list(self.accepted[:-1]):
            rivals = [c for c in self.candidates if c.step == self.accepted_at[name] and c.effect not in self.accepted
                      and self.acceptable(c) and not self.not_judged(c.fit, c.effect)]
            reduced = without(self.current.structure, name) if rivals else None
            if reduced is None:
                continue
            reduced_fit = fitter.evaluate(polish(fitter, reduced))
            for rival in sorted(rivals, key=lambda c: c.fit.cv_mse):
                fit = self.addition(reduced_fit, rival.effect)
                # the effects named after ``name`` were chosen (variant, grid value) beside it; beside the rival
                # they may take another shape: rebuild from the rival's own step too, and take the better
                again = self.rebuild(rival, name)
                if again is not None and (fit is None or again.cv_mse < fit.cv_mse):
                    fit = again
                if fit is None or self.not_judged(fit, rival.effect) or not self.beats(fit, reduced_fit) or not (
                        (size(fit) < size(self.current) and not self.beats(self.current, fit))
                        or self.beats(fit, self.current)):
                    continue
                refined = self.saved_form(fit.structure, reduced_fit)
                if refined is None:
                    self.say(f"{rival.effect}: its refitted model predicts no better, not swapped in")
                    continue
                self.say(f"swap {name} for {rival.effect}")
                self.accepted[self.accepted.index(name)] = rival.effect
                self.accepted_at[rival.effect] = self.accepted_at.pop(name)
                self.confidences.pop(name)
                self.variants.pop(name)
                self.confidences[rival.effect] = float(np.mean(fit.sse_folds < reduced_fit.sse_folds))
                self.variants[rival.effect] = _variant(fit, rival.effect)
                for c in self.candidates:
                    if c.effect == name and c.accepted:
                        c.accepted = False
                # the report shows the fit that was taken (the rival added to the reduced model), not the
                # rival's own step, whose model still held the effect it replaces
                share = excess(reduced_fit.cv_mse, self.floor_mse)
                self.candidates.append(Candidate(rival.effect, self.variants[rival.effect], fit, math.sqrt(fit.cv_mse),
                                                 self.confidences[rival.effect],
                                                 float((reduced_fit.cv_mse - fit.cv_mse) / share), self.step,
                                                 accepted=True))
                self.current = refined
                break

    def run(self, catalogue: Sequence[str], skipped: Sequence[str], max_effects: int) -> None:
        """Rounds of forward step, backward check and swap check until nothing more is justified, ``max_effects``
        are named or a set of named effects recurs (add one, drop another); then :meth:`settle_variants`."""
        seen: set[frozenset[str]] = {frozenset()}
        while len(self.accepted) < max_effects:
            judged = self.forward_step(catalogue, skipped)
            best = parsimonious(judged, self.acceptable, self.beats)
            while best is not None and self.acceptable(best) and not self.accept(best):
                # the next choice of the step, without the effect whose refitted model did not help
                judged = [c for c in judged if c.effect != best.effect]
                best = parsimonious(judged, self.acceptable, self.beats)
            if best is None or not self.acceptable(best):
                break
            self.backward_check()
            self.swap_check()
            if frozenset(self.accepted) in seen:
                break
            seen.add(frozenset(self.accepted))
        self.settle_variants()

    def settle_variants(self) -> None:
        """The variants named, and the candidates that named them, take the shapes of the current fit (a backward
        check, a swap or a drop may have re-chosen them)."""
        self.variants = {e: getattr(self.current.structure.term(e), "variant", "") for e in self.accepted}
        for c in self.candidates:
            if c.accepted and c.effect in self.variants:
                c.variant = self.variants[c.effect]

    def drop(self, name: str) -> None:
        """``name`` no longer names an effect (another stands in for it, or its refitted model did not help)."""
        self.accepted.remove(name)
        self.accepted_at.pop(name, None)
        self._unname(name)

    def name_at_record_rate(self, name: str, confidence: float, excess_share: float) -> None:
        """Name ``name``, fitted after the selection at the record's rate (:mod:`.resonance`): it has no candidate
        of the fit-rate steps."""
        self.accepted.append(name)
        self.confidences[name] = float(confidence)
        self.variants[name] = ""
        self.say(f"{name}: {100.0 * excess_share:.0f} % of the excess removed at the record's rate")

    def clear(self) -> None:
        """Name nothing: the effects become partial fits (the caller keeps their names)."""
        self.accepted, self.confidences, self.variants = [], {}, {}
        for c in self.candidates:
            c.accepted = False


def _has_param(fit: Fit, name: str) -> bool:
    """Whether ``name``'s term in ``fit`` has a nonlinear parameter of its own."""
    term = fit.structure.term(name)
    return term is not None and term.param is not None
