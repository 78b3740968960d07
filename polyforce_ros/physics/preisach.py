"""Rate-independent hysteresis: the discrete Preisach operator of seed 001.

The input range [u_min, u_max] is cut into ``n`` levels with edges
e_0 < e_1 < ... < e_n. Relay (i, j), 0 <= j <= i < n, switches up (+1) when
the input reaches e_{i+1} and down (-1) when it falls to e_j, so there are
n (n + 1) / 2 relays (820 for n = 40). The output is

    y = offset + sum_ij density[i, j] * H_ij,   density >= 0.

All relays start down (-1), as in seed 001.

* :func:`relay_states` / :meth:`PreisachModel.forward`: batch forward run;
* :func:`identify`: non-negative least squares of density and offset from a
  record (e.g. increasing-amplitude triangles), as in seed 001;
* :class:`PreisachStream`: per-sample forward run and the closest-match
  inverse (CMA) of the discrete operator. It keeps the outputs every
  reachable level would give and recomputes them only when a relay switches,
  so a sample costs a bisection and a few comparisons;
* :class:`ContinuousPreisachStream`: the continuous operator (ramp hysterons,
  the paper's future work) and its exact inverse.
"""
from __future__ import annotations

import bisect
from dataclasses import dataclass
from typing import Any, Mapping, Optional, Union

import numpy as np
import numpy.typing as npt
from scipy import optimize

__all__ = ["PreisachModel", "relay_states", "ramp_states", "identify", "PreisachStream", "ContinuousPreisachStream",
    "hysteresis_error_percent", "hysteretic_identity"]


@dataclass(frozen=True, eq=False)
class PreisachModel:
    """u_min, u_max: input range (input unit); density: (n, n) lower-triangular
    weights >= 0 (output unit); offset: eta_0 (output unit). Immutable (the density a read-only copy)."""

    u_min: float
    u_max: float
    density: npt.NDArray[np.float64]
    offset: float = 0.0

    def __post_init__(self) -> None:
        density = np.tril(np.asarray(self.density, dtype=float))
        density.flags.writeable = False
        object.__setattr__(self, "density", density)
        n = self.density.shape[0]
        if self.density.shape != (n, n) or n < 1:
            raise ValueError("density must be a square (n, n) matrix")
        if not (np.isfinite(self.u_min) and np.isfinite(self.u_max) and self.u_max > self.u_min):
            raise ValueError("need finite u_min < u_max")
        if np.any(self.density < 0) or not np.all(np.isfinite(self.density)):
            raise ValueError("Preisach density must be finite and non-negative")

    @property
    def n_levels(self) -> int:
        """Number n of input levels (the density is n x n)."""
        return int(self.density.shape[0])

    @property
    def n_hysterons(self) -> int:
        """Number of relays, n (n + 1) / 2."""
        n = self.n_levels
        return n * (n + 1) // 2

    @property
    def edges(self) -> npt.NDArray[np.float64]:
        """The n + 1 level edges e_0 = u_min < ... < e_n = u_max, evenly spaced (input unit)."""
        return np.linspace(self.u_min, self.u_max, self.n_levels + 1)

    @property
    def level_step(self) -> float:
        """Width of one level, (u_max - u_min) / n (input unit)."""
        return (self.u_max - self.u_min) / self.n_levels

    def forward(self, u: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """Discrete output for an input sequence, starting with all relays down.

        Parameters
        ----------
        u : (n,) array_like of float
            Input samples (input unit, e.g. N or V).

        Returns
        -------
        (n,) ndarray of float
            ``offset + sum_ij density[i, j] * H_ij`` at each sample (output unit).
        """
        states = relay_states(u, self.u_min, self.u_max, self.n_levels)
        i, j = np.tril_indices(self.n_levels)
        return self.offset + states @ self.density[i, j]

    def stream(self, continuous: bool = False) -> Union[PreisachStream, ContinuousPreisachStream]:
        """Per-sample operator: discrete relays with the CMA inverse, or continuous ramps.

        Parameters
        ----------
        continuous : bool, optional
            False (default): the discrete operator; True: the continuous (ramp) operator.

        Returns
        -------
        PreisachStream or ContinuousPreisachStream
            A new stream with all relays down and the input at ``u_min``.
        """
        return ContinuousPreisachStream(self) if continuous else PreisachStream(self)

    def to_dict(self) -> dict[str, Any]:
        """Plain (JSON-ready) dict of the model, the inverse of :meth:`from_dict`.

        Returns
        -------
        dict
            ``u_min``, ``u_max`` (float, input unit), ``n_levels`` (int), ``offset`` (float,
            output unit) and ``density``: the n (n + 1) / 2 lower-triangular density values
            (output unit) as a flat list of floats in row-major (``np.tril_indices``) order.
        """
        i, j = np.tril_indices(self.n_levels)
        return {"u_min": float(self.u_min), "u_max": float(self.u_max), "n_levels": self.n_levels,
                "offset": float(self.offset), "density": [float(v) for v in self.density[i, j]]}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> PreisachModel:
        """The model from a :meth:`to_dict` dict.

        Parameters
        ----------
        d : mapping
            With the keys ``u_min``, ``u_max`` (input unit), ``n_levels``, ``offset`` (output
            unit) and ``density`` (n (n + 1) / 2 values in ``np.tril_indices`` order, output
            unit); other keys are ignored.

        Returns
        -------
        PreisachModel
            The model. Raises ValueError if ``density`` does not hold n (n + 1) / 2 values for
            ``n_levels`` or the model's own checks reject the values, KeyError for a missing key.
        """
        n = int(d["n_levels"])
        values = np.asarray(d["density"], dtype=float)
        if values.size != n * (n + 1) // 2:
            raise ValueError(f"density needs {n * (n + 1) // 2} values for {n} levels, got {values.size}")
        density = np.zeros((n, n))
        density[np.tril_indices(n)] = values
        return cls(float(d["u_min"]), float(d["u_max"]), density, float(d["offset"]))


def relay_states(u: npt.ArrayLike, u_min: float, u_max: float, n_levels: int,
                 chunk: int = 20000) -> npt.NDArray[np.int8]:
    """Relay outputs (+1/-1) of the discrete operator for every sample, starting with all relays down.

    Relay (i, j) is up at sample k when the input last reached e_{i+1} after it
    last fell to e_j; both "last" indices are running maxima, so the whole
    record is vectorised.

    Parameters
    ----------
    u : (n,) array_like of float
        Input samples (input unit).
    u_min, u_max : float
        Input range (input unit), cut into ``n_levels`` even levels.
    n_levels : int
        Number of levels.
    chunk : int, optional
        Samples transposed into the output at a time (memory only; the result does not depend on it).

    Returns
    -------
    (n, n_levels (n_levels + 1) / 2) ndarray of int8
        +1 (up) or -1 (down) per sample and relay, relays in ``np.tril_indices`` order.
    """
    u = np.asarray(u, dtype=float)
    edges = np.linspace(u_min, u_max, n_levels + 1)
    idx = np.arange(u.size)
    last_up = np.maximum.accumulate(np.where(u[None, :] >= edges[1:, None], idx, -1), axis=1)
    last_dn = np.maximum.accumulate(np.where(u[None, :] <= edges[:-1, None], idx, -1), axis=1)
    i, j = np.tril_indices(n_levels)
    out = np.empty((u.size, i.size), dtype=np.int8)
    for start in range(0, u.size, chunk):
        sl = slice(start, start + chunk)
        out[sl] = np.where(last_up[i, sl] > last_dn[j, sl], 1, -1).T
    return out


def ramp_states(u: npt.ArrayLike, u_min: float, u_max: float, n_levels: int) -> npt.NDArray[np.float64]:
    """Relay values of the continuous operator (ramp hysterons) for every sample, starting with all ramps at -1.

    Parameters
    ----------
    u : (n,) array_like of float
        Input samples (input unit).
    u_min, u_max : float
        Input range (input unit), cut into ``n_levels`` even levels.
    n_levels : int
        Number of levels.

    Returns
    -------
    (n, n_levels (n_levels + 1) / 2) ndarray of float
        Ramp values in [-1, 1] per sample and relay, relays in ``np.tril_indices`` order.
    """
    probe = ContinuousPreisachStream(PreisachModel(u_min, u_max, np.zeros((n_levels, n_levels)) + 1e-300, 0.0))
    i, j = np.tril_indices(n_levels)
    out = np.empty((np.size(u), i.size))
    for k, x in enumerate(np.asarray(u, dtype=float)):
        probe.forward(float(x))
        out[k] = probe.r[i, j]
    return out


def identify(u: npt.ArrayLike, y: npt.ArrayLike, n_levels: int = 40, u_min: Optional[float] = None,
             u_max: Optional[float] = None) -> PreisachModel:
    """Density >= 0 and offset by least squares from an input/output record (seed 001).

    Samples with the same relay state are merged (mean output, weighted by
    count), which leaves the least-squares problem unchanged and makes it
    small. The input should switch every relay both ways (e.g. triangles of
    increasing amplitude over the whole range), or the unexcited relays'
    weights stay undetermined (they come out as 0).

    Parameters
    ----------
    u : (n,) array_like of float
        Input samples (input unit), starting from the all-relays-down state.
    y : (n,) array_like of float
        Output samples (output unit).
    n_levels : int, optional
        Number of levels (default 40, as in seed 001).
    u_min, u_max : float, optional
        Input range (input unit); the record's minimum and maximum input when omitted.

    Returns
    -------
    PreisachModel
        The identified model (density and offset in the output unit).
    """
    u, y = np.asarray(u, dtype=float), np.asarray(y, dtype=float)
    lo = float(np.min(u)) if u_min is None else u_min
    hi = float(np.max(u)) if u_max is None else u_max
    states = relay_states(u, lo, hi, n_levels)
    packed = np.packbits(states > 0, axis=1)
    _, first, inverse, counts = np.unique(packed, axis=0, return_index=True, return_inverse=True, return_counts=True)
    inverse = inverse.ravel()
    y_mean = np.bincount(inverse, weights=y) / counts
    a = np.column_stack([states[first].astype(float), np.ones(first.size)])
    w = np.sqrt(counts)
    n_q = states.shape[1]
    lower = np.concatenate([np.zeros(n_q), [-np.inf]])
    upper = np.full(n_q + 1, np.inf)
    sol = optimize.lsq_linear(a * w[:, None], y_mean * w, bounds=(lower, upper), method="bvls")
    density = np.zeros((n_levels, n_levels))
    density[np.tril_indices(n_levels)] = np.clip(sol.x[:-1], 0.0, None)
    return PreisachModel(lo, hi, density, float(sol.x[-1]))


class PreisachStream:
    """Per-sample forward run and closest-match inverse (CMA) of the discrete operator.

    ``forward(u)`` moves the input and returns the output; ``inverse(y)``
    returns the edge whose output, reached from the current state, is closest
    to ``y`` (seed 001's CMA: quantised to the levels) and moves the state
    there. A target reachable without switching any relay keeps the previous
    input.

    Parameters
    ----------
    model : PreisachModel
        The operator; the stream starts with all relays down and the input at ``u_min``.
    """

    def __init__(self, model: PreisachModel) -> None:
        self.model = model
        n = model.n_levels
        self._w = model.density
        self._tril = np.tril(np.ones((n, n), dtype=bool))
        self._edges: list[float] = model.edges.tolist()
        self._step = model.level_step
        self.reset()

    def reset(self) -> None:
        """All relays down, input at u_min."""
        self._h = np.where(self._tril, -1.0, 0.0)
        self.y: float = self.model.offset - float(self._w.sum())
        self.u = self.model.u_min
        self._candidates()

    def _candidates(self) -> None:
        """Outputs after moving the input up to each edge (rising) and down to each edge (falling)."""
        row_off = ((self._h < 0) * self._w).sum(axis=1)
        col_on = ((self._h > 0) * self._w).sum(axis=0)
        self._up: list[float] = (self.y + 2.0 * np.concatenate(([0.0], np.cumsum(row_off)))).tolist()
        self._down: list[float] = (self.y - 2.0 * np.concatenate((np.cumsum(col_on[::-1])[::-1], [0.0]))).tolist()

    def _move_up(self, k: int) -> None:
        if self._up[k] != self.y:
            self._h[:k][self._tril[:k]] = 1.0
            self.y = self._up[k]
            self._candidates()

    def _move_down(self, k: int) -> None:
        if self._down[k] != self.y:
            self._h[:, k:][self._tril[:, k:]] = -1.0
            self.y = self._down[k]
            self._candidates()

    def forward(self, u: float) -> float:
        """Move the input to ``u``, switching relays as needed.

        Parameters
        ----------
        u : float
            New input (input unit).

        Returns
        -------
        float
            The discrete output (output unit).
        """
        n = self.model.n_levels
        pos = (u - self.model.u_min) / self._step
        self._move_up(min(max(int(np.floor(pos)), 0), n))  # relays with e_{i+1} <= u switch up
        self._move_down(min(max(int(np.ceil(pos)), 0), n))  # relays with e_j >= u switch down
        self.u = u
        return self.y

    def inverse(self, y_target: float) -> float:
        """CMA inverse: the input that gives the output closest to ``y_target``.

        Searches the edges reachable from the current state in the direction of
        ``y_target`` and moves the state there.

        Parameters
        ----------
        y_target : float
            Wanted output (output unit).

        Returns
        -------
        float
            The input (input unit): the level edge whose output is closest to ``y_target``,
            or the previous input when ``y_target`` equals the current output or the nearest
            candidate switches no relay.
        """
        if y_target == self.y:
            return self.u
        if y_target > self.y:
            up = self._up
            k = bisect.bisect_right(up, y_target) - 1  # up[k] <= y_target < up[k + 1]
            if k < len(up) - 1 and up[k + 1] - y_target < y_target - up[k]:
                k += 1
            u = self._edges[k] if up[k] != self.y else self.u
            self._move_up(k)
        else:
            down = self._down  # non-decreasing in k
            k = bisect.bisect_left(down, y_target)  # down[k - 1] < y_target <= down[k]
            if k > 0 and y_target - down[k - 1] < down[k] - y_target:
                k -= 1
            u = self._edges[k] if down[k] != self.y else self.u
            self._move_down(k)
        self.u = u
        return u


class ContinuousPreisachStream:
    """The continuous Preisach operator and its exact inverse (seed 001's future work).

    Each relay (i, j) is a ramp with memory: its value r in [-1, 1] is pushed
    up by the ramp f_i(u) = -1 + 2 clip((u - e_i) / h, 0, 1) across the level
    below its up-edge e_{i+1} and down by f_j(u) across the level above its
    down-edge e_j, and holds in between: r <- min(max(r, f_i(u)), f_j(u)).
    At the edges it agrees with the discrete relay; between them the output
    varies continuously, so there is no level quantisation.

    The inverse uses that, from a given state, the output is monotone and
    piecewise linear in the input: candidate outputs at the edges locate the
    level, and inside it the ramp value solves a sorted piecewise-linear sum.

    Parameters
    ----------
    model : PreisachModel
        The operator; the stream starts with all ramps at -1 and the input at ``u_min``.
    """

    def __init__(self, model: PreisachModel) -> None:
        self.model = model
        n = model.n_levels
        self._w = model.density
        self._tril = np.tril(np.ones((n, n), dtype=bool))
        self._e = model.edges
        self._h = model.level_step
        self.reset()

    def reset(self) -> None:
        """All ramps at -1 (relays down), input at u_min, output offset - sum(density)."""
        self.r = np.where(self._tril, -1.0, 0.0)
        self.u = self.model.u_min
        self.y = self.model.offset - float(self._w.sum())

    def _ramps(self, u: float) -> npt.NDArray[np.float64]:
        return -1.0 + 2.0 * np.clip((u - self._e[:-1]) / self._h, 0.0, 1.0)

    def forward(self, u: float) -> float:
        """Move the input to ``u``, updating the ramps.

        Parameters
        ----------
        u : float
            New input (input unit).

        Returns
        -------
        float
            The continuous output (output unit).
        """
        f = self._ramps(u)
        self.r = np.minimum(np.maximum(self.r, f[:, None]), f[None, :]) * self._tril
        self.u = u
        self.y = self.model.offset + float((self._w * self.r).sum())
        return self.y

    def inverse(self, y_target: float) -> float:
        """Exact inverse: the input whose output, from the current state, equals ``y_target``.

        The state is moved there (as :meth:`forward`).

        Parameters
        ----------
        y_target : float
            Wanted output (output unit).

        Returns
        -------
        float
            The input (input unit). A target beyond reach is clamped to u_max (rising) or
            u_min (falling); if ``y_target`` equals the current output the current input is
            returned and nothing changes.
        """
        n = self.model.n_levels
        if y_target > self.y:
            deficit = (self._w * (1.0 - self.r)).sum(axis=1)  # what each row adds when fully up
            up = self.y + np.concatenate(([0.0], np.cumsum(deficit)))
            k = int(np.searchsorted(up, y_target, side="right")) - 1
            if k >= n:
                u = self._e[-1]
            else:
                # Inside level k only row k moves: sum_j w_kj * max(0, s - r_kj) = need.
                s = _solve_ramp(self._w[k, : k + 1], self.r[k, : k + 1], y_target - up[k])
                u = self._e[k] + self._h * (s + 1.0) / 2.0
        elif y_target < self.y:
            excess = (self._w * (1.0 + self.r)).sum(axis=0)  # what each column removes when fully down
            down = self.y - np.concatenate((np.cumsum(excess[::-1])[::-1], [0.0]))
            k = int(np.searchsorted(down, y_target, side="left"))  # down[k-1] < y_target <= down[k]
            if k == 0:
                u = self._e[0]
            else:
                j = k - 1  # inside level j only column j moves: sum_i w_ij * max(0, r_ij - s) = need
                col_w, col_r = self._w[j:, j], self.r[j:, j]
                s = -_solve_ramp(col_w, -col_r, down[k] - y_target)
                u = self._e[j] + self._h * (s + 1.0) / 2.0
        else:
            return self.u
        self.forward(u)
        return float(u)


def _solve_ramp(weights: npt.NDArray[np.float64], values: npt.NDArray[np.float64], need: float) -> float:
    """s in [-1, 1] with sum_k weights_k * max(0, s - values_k) = need (monotone, piecewise linear)."""
    order = np.argsort(values)
    v, w = values[order], weights[order]
    # at breakpoint v_m the sum is sum_{k<m} w_k (v_m - v_k) = v_m W_m - S_m
    cw, cs = np.cumsum(w), np.cumsum(w * v)
    at_breaks = np.concatenate(([0.0], v[1:] * cw[:-1] - cs[:-1]))
    m = int(np.searchsorted(at_breaks, need, side="right")) - 1
    m = min(max(m, 0), v.size - 1)
    if cw[m] <= 0:
        return float(np.clip(v[m], -1.0, 1.0))
    return float(np.clip((need + cs[m]) / cw[m], -1.0, 1.0))


def hysteresis_error_percent(u: npt.ArrayLike, y: npt.ArrayLike) -> float:
    """Seed 001 eq. 3: 100 * max (unloading - loading output at equal input) / max output.

    Computed by :func:`~.metrics.hysteresis_percent` (one loading/unloading cycle, split
    at the input's maximum, branches compared over 2-98 % of the input range).

    Parameters
    ----------
    u : (n,) array_like of float
        Input of one loading/unloading cycle (input unit).
    y : (n,) array_like of float
        Output (output unit).

    Returns
    -------
    float
        Hysteresis error [%] of the normalised output. Raises ValueError if the cycle has
        no loading and unloading branch.
    """
    from .metrics import hysteresis_percent

    return hysteresis_percent(u, y)


def hysteretic_identity(u_min: float, u_max: float, loop_fraction: float, n_levels: int = 24) -> PreisachModel:
    """A continuous Preisach operator close to y = u (y = u_min at rest) with a loop of ``loop_fraction`` of the span.

    Diagonal relays are reversible ramps (the identity part); weight moved to a
    band off the diagonal opens the loop.
    """
    n = n_levels
    i, j = np.tril_indices(n)
    density = np.zeros((n, n))
    off = np.exp(-(((i - j) - 0.3 * n) / (0.15 * n)) ** 2) * (i != j)
    diag = (i == j).astype(float)
    share = min(max(3.0 * loop_fraction, 0.0), 0.9)
    density[i, j] = (1 - share) * diag / diag.sum() + share * off / off.sum()
    density *= (u_max - u_min) / 2.0
    return PreisachModel(u_min, u_max, density, offset=u_min + (u_max - u_min) / 2.0)
