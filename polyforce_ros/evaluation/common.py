"""What every experiment of the evaluation report shares: settings, rows, figures."""
from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import TYPE_CHECKING, Any, Optional, Union

import numpy as np
import numpy.typing as npt

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: A cell of a results table: a number, a text, or nothing.
Value = Optional[Union[float, str]]
#: A JSON-ready value (:func:`finite_or_text`).
JSONValue = Optional[Union[str, float, list[Any], dict[Any, Any]]]


@dataclass(frozen=True)
class Settings:
    """Simulator settings, stated in the report so it can be reproduced."""

    seed: int = 0
    noise_std_v: float = 1e-3
    adc_bits: int = 16
    offset_v: float = 0.05
    rate_hz: float = 1000.0
    quick: bool = False  # shorter records (tests); the numbers move little

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass
class Row:
    """One line of a results table.

    ``paper``: the published number (or text) and ``ours_*`` our figures;
    ``target``: how ours is judged ("<=", ">=", "~" with a tolerance, or "" for
    information only); ``passed`` is filled from the compensated (or only)
    figure of ours against the paper's number.
    """

    experiment: str
    metric: str
    unit: str
    paper_baseline: Value = None
    paper_ours_method: Value = None
    ours_baseline: Value = None
    ours_method: Value = None
    target: str = ""
    passed: bool | None = None
    note: str = ""

    def judge(self, tolerance: float = 0.0) -> Row:
        ours, paper = self.ours_method, self.paper_ours_method
        if self.target not in ("<=", ">=") or ours is None or paper is None or isinstance(paper, str):
            return self
        if isinstance(ours, str):
            raise TypeError(f"{self.metric}: a judged figure must be a number, got {ours!r}")
        if self.target == "<=":
            self.passed = bool(ours <= paper * (1 + tolerance))
        else:
            self.passed = bool(ours >= paper * (1 - tolerance))
        return self


@dataclass
class Section:
    """The outcome of one group of experiments (one seed paper)."""

    title: str
    rows: list[Row] = field(default_factory=list)
    figures: list[tuple[str, Figure, str]] = field(default_factory=list)  # (file name, matplotlib Figure, caption)
    notes: list[str] = field(default_factory=list)


def finite_or_text(x: object) -> JSONValue:
    """JSON-friendly number: inf as the string 'inf'."""
    if isinstance(x, float) and not np.isfinite(x):
        return "inf" if x > 0 else "-inf"
    if isinstance(x, np.generic):
        return finite_or_text(x.item())
    if isinstance(x, (str, int, float, bool, list, dict)) or x is None:
        return x
    return str(x)


def figure(rows: int = 1, cols: int = 1, size: tuple[float, float] = (9, 4.5)) -> tuple[Figure, npt.NDArray[np.object_]]:
    """A figure with a ``rows`` x ``cols`` grid of axes, indexed ``ax[row, col]`` (Agg backend)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt.subplots(rows, cols, figsize=size, squeeze=False)
