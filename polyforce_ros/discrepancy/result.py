"""The answer of a diagnosis (:class:`Diagnosis`) and its JSON (``polyforce diagnose --json``)."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..physics.chain import SensorChain
from .design import BLOCKS_PER_FOLD
from .effects import EFFECTS as REGISTRY
from .selection import Candidate
from .signals import FloatArray

__all__ = ["Diagnosis"]


def _empty() -> FloatArray:
    return np.zeros(0)


@dataclass
class Diagnosis:
    """What :func:`.engine.diagnose` found on one record.

    Attributes
    ----------
    base : str
        The base core type.
    missing_effects : list of str
        The effects named, in the order they were named (empty: none).
    confidences : dict
        Each named effect's share of folds it improves.
    rmse_before, rmse_after : float
        Out-of-sample RMSE of the base and of the saved model at the record's rate [V].
    noise_floor_v : float
        The noise floor estimated from the data [V].
    unexplained : dict
        The structure left in the residual (``present``, ``rms_v``, Ljung-Box, bands, ``where``, ``partial_fits``,
        ``explained_share``).
    candidates : list of Candidate
        Every candidate scored by the selection.
    skipped : dict
        Effects not tested -> why.
    evidence : list of str
        The evidence in sentences (:func:`.localise.describe`).
    chain, base_chain : SensorChain
        The saved model and the base model.
    simulated_before_v, simulated_after_v : ndarray
        Out-of-sample predictions of the base and the saved model [V].
    localisation : dict
        Where the residual concentrates and what it follows (:func:`.localise.localise`).
    folds, blocks_per_fold : int
        The cross-validation's folds and blocks per fold.
    variants : dict
        Each named effect's variant.
    coefficients : dict
        The final fit's coefficients with their block-jackknife standard errors.
    newtons : dict
        The compensated force of the base and the saved model (:mod:`.newtons`).
    compensated_before_n, compensated_after_n : ndarray
        The compensated force of the base and of the saved model, each block left out [N].
    """

    base: str
    missing_effects: list[str]
    confidences: dict[str, float]
    rmse_before: float
    rmse_after: float
    noise_floor_v: float
    unexplained: dict[str, Any]
    candidates: list[Candidate]
    skipped: dict[str, str]
    evidence: list[str]
    chain: SensorChain
    base_chain: SensorChain
    simulated_before_v: FloatArray = field(repr=False, default_factory=_empty)
    simulated_after_v: FloatArray = field(repr=False, default_factory=_empty)
    localisation: dict[str, Any] = field(default_factory=dict)
    folds: int = 5
    blocks_per_fold: int = BLOCKS_PER_FOLD
    variants: dict[str, str] = field(default_factory=dict)
    coefficients: dict[str, dict[str, float]] = field(default_factory=dict)
    newtons: dict[str, Any] = field(default_factory=dict)
    compensated_before_n: FloatArray = field(repr=False, default_factory=_empty)
    compensated_after_n: FloatArray = field(repr=False, default_factory=_empty)

    @property
    def missing_effect(self) -> str:
        """The first effect named; "unexplained" when none is but structure remains; else "none"."""
        if self.missing_effects:
            return self.missing_effects[0]
        return "unexplained" if self.unexplained.get("present") else "none"

    def saved_parameters(self, effect: str) -> dict[str, float]:
        """The scalar parameters of the saved element that holds ``effect`` (a mode's frequency and damping, a
        friction's band, a shift per degree...), by their model-file keys; empty when no element holds it alone."""
        kinds = REGISTRY[effect].elements
        for element in self.chain.invertible_elements:
            if element.kind in kinds:
                return {k: float(v) for k, v in element.to_dict().items()
                        if k != "type" and isinstance(v, (int, float)) and not isinstance(v, bool)}
        return {}

    def saved_text(self, effect: str) -> str:
        """:meth:`saved_parameters` as the printout and the report write them (``key value, ...``; empty for none)."""
        return ", ".join(f"{k} {v:.4g}" for k, v in self.saved_parameters(effect).items())

    def to_json(self) -> dict[str, Any]:
        """Plain data: the JSON of ``polyforce diagnose`` (see its ``--help``)."""
        from ..model_file import SensorModel, model_to_mapping

        return {
            "base": self.base,
            "missing_effect": self.missing_effect,
            "missing_effects": list(self.missing_effects),
            "effects": [{"effect": e, "variant": self.variants.get(e, ""), "confidence": self.confidences[e],
                         "saved": self.saved_parameters(e)} for e in self.missing_effects],
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
