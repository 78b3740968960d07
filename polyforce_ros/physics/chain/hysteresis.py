"""Rate-independent hysteresis: the Preisach relay model, the Prandtl-Ishlinskii play operator, and Coulomb friction
in the mechanism (play operators at the bridge beside a viscoelastic core: :mod:`.bridge`).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Mapping, Optional, Self, TypedDict, Union

import numpy as np
import numpy.typing as npt

from .base import (
    MAX_PREISACH_LEVELS,
    ElementStream,
    FloatArray,
    Frozen,
    FunctionStream,
    ModelError,
    Numbers,
    abscissae_and_values,
    check_keys,
    check_number,
    short_repr,
    temperature_c_of,
)
from .drift import LaggedTemperatureStream, ThermalForwardState, lagged_temperature_c, thermal_forward_state

if TYPE_CHECKING:  # for annotations only: at run time the Preisach model loads when first used
    from ..preisach import ContinuousPreisachStream, PreisachModel, PreisachStream

__all__ = ["PreisachElement", "play_operator", "history_input", "play_states_after", "PlayHysteresisElement",
           "FrictionElement"]


class _PreisachForwardState(TypedDict):
    stream: Union[PreisachStream, ContinuousPreisachStream]


class PreisachElement(Frozen):
    """Rate-independent hysteresis (seed 001): a Preisach operator from input to output (same or any units).

    ``continuous`` selects ramp hysterons and their exact inverse; otherwise the
    discrete relays and the closest-match inverse (quantised to the levels).
    Forward and backward start from all relays down (an unloaded sensor).
    """

    kind = "preisach"
    KEYS = ("u_min", "u_max", "n_levels", "offset", "density", "continuous")
    model: PreisachModel
    continuous: bool

    def __init__(self, model: PreisachModel, continuous: bool = True) -> None:
        self._freeze(model=model, continuous=bool(continuous))

    def forward_state(self) -> _PreisachForwardState:
        """A fresh state for block-wise :meth:`forward` runs (all relays down)."""
        return {"stream": self.model.stream(self.continuous)}

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_PreisachForwardState] = None) -> FloatArray:
        """Preisach output for each input sample (discrete or continuous per ``continuous``)."""
        stream = (state or self.forward_state())["stream"]
        return np.array([stream.forward(float(v)) for v in np.asarray(x, dtype=float)])

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The inverse of each output sample, from all relays down (closest-match, or exact when ``continuous``)."""
        stream = self.model.stream(self.continuous)
        return np.array([stream.inverse(float(v)) for v in np.asarray(y, dtype=float)])

    def streaming(self) -> ElementStream:
        """The per-sample inverse of the operator."""
        stream = self.model.stream(self.continuous)
        return FunctionStream(lambda t_s, y, aux=None: stream.inverse(y), stream.reset)

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping."""
        return {"type": self.kind, **self.model.to_dict(), "continuous": self.continuous}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The element from a model-file mapping."""
        from ..preisach import PreisachModel

        check_keys(cls.kind, d, cls.KEYS)
        if not isinstance(d["density"], list) or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                                         for v in d["density"]):
            raise ModelError("preisach: density must be a list of numbers")
        n_levels = d["n_levels"]
        if isinstance(n_levels, bool) or not isinstance(n_levels, int) or not 1 <= n_levels <= MAX_PREISACH_LEVELS:
            raise ModelError(f"preisach: n_levels must be an integer in [1, {MAX_PREISACH_LEVELS}] "
                             f"(the operator costs O(n**2) per sample), got {short_repr(n_levels)}")
        if not isinstance(d["continuous"], bool):
            raise ModelError("preisach: continuous must be true or false")
        for key in ("u_min", "u_max", "offset"):
            check_number(cls.kind, key, d[key], positive=False)
        for value in d["density"]:
            check_number(cls.kind, "density", value, positive=False)
        try:
            model = PreisachModel.from_dict(d)
        except (ValueError, ArithmeticError) as exc:
            raise ModelError(f"preisach: {exc}") from exc
        return cls(model, d["continuous"])


def play_operator(x: npt.ArrayLike, radii: npt.ArrayLike, y0: Optional[npt.ArrayLike] = None,
                  chunk: Optional[int] = None) -> FloatArray:
    """Play (backlash) operators of half-widths ``radii`` on the sequence ``x``.

    ``y_k = min(max(y_{k-1}, x_k - r), x_k + r)``, starting from ``y0`` before
    the first sample. Each step is a clamp, and clamps compose into clamps, so
    the sequence is a prefix composition, computed with log2(chunk) vectorised
    doubling passes per chunk (no Python loop over samples).

    Parameters
    ----------
    x : (n,) array_like of float
        Input sequence [any unit, e.g. N or V].
    radii : (m,) or (n, m) array_like of float
        Half-widths of the plays [the input's unit]; (n, m): a half-width per sample (a band that moves, each step
        still a clamp).
    y0 : (m,) array_like of float, optional
        Each play's state before the first sample [the input's unit]; zeros when omitted.
    chunk : int, optional
        Samples per vectorised chunk. By default about 2**15 values (chunk x m): the passes then run in
        cache, and fewer of them (512-sample chunks of 44 plays run 3x faster than 32768-sample ones).

    Returns
    -------
    (n, m) ndarray of float
        Each play's output at each sample [the input's unit].
    """
    x = np.asarray(x, dtype=float)
    r = np.asarray(radii, dtype=float)
    moving = r.ndim == 2
    r = r if moving else np.atleast_1d(r)
    m = r.shape[-1]
    y = np.zeros(m) if y0 is None else np.array(y0, dtype=float)
    out = np.empty((x.size, m))
    if x.size == 0:
        return out
    if chunk is None:
        chunk = 1 << max(6, int(math.log2(max(1, (1 << 15) // max(m, 1)))))
    width = min(chunk, x.size)
    lo_buf, hi_buf, tmp = (np.empty((width, m)) for _ in range(3))
    for start in range(0, x.size, chunk):
        xc = x[start:start + chunk, None]
        n = xc.shape[0]
        lo, hi = lo_buf[:n], hi_buf[:n]
        rc = r[start:start + n] if moving else r
        np.subtract(xc, rc, out=lo)
        np.add(xc, rc, out=hi)
        shift = 1
        while shift < n:
            # the block ending at k composed after the block ending at k - shift, in place:
            #   hi[k] <- min(max(hi[k - shift], lo[k]), hi[k]);  lo[k] <- min(max(lo[k - shift], lo[k]), hi[k])
            # (the new hi may clamp the new lo: max(lo[k - shift], lo[k]) <= max(hi[k - shift], lo[k]))
            m, a = n - shift, tmp[:n - shift]
            np.maximum(hi[:m], lo[shift:], out=a)
            np.minimum(a, hi[shift:], out=hi[shift:])
            np.maximum(lo[:m], lo[shift:], out=a)
            np.minimum(a, hi[shift:], out=lo[shift:])
            shift *= 2
        block = out[start:start + n]
        np.maximum(y, lo, out=block)
        np.minimum(block, hi, out=block)
        y = block[-1].copy()
    return out



def history_input(history_max: float) -> FloatArray:
    """The input before a record whose input came down from ``history_max`` to 0: 0, up to it and back to 0
    (no samples for 0, a virgin sensor). Play operators run over it give their states at the record's start."""
    return np.array([0.0, history_max, 0.0]) if history_max > 0 else np.zeros(0)


def play_states_after(history_max: float, radii: FloatArray) -> FloatArray:
    """Each play's state after :func:`history_input` (zeros for a virgin sensor) [the input's unit]."""
    h = history_input(history_max)
    return play_operator(h, radii)[-1] if h.size else np.zeros(radii.size)


class _PlayForwardState(TypedDict):
    y: FloatArray  # forward play states, input unit


class PlayHysteresisElement(Frozen):
    """Rate-independent hysteresis as a Prandtl-Ishlinskii operator: a weighted sum of play operators.

        y = linear_weight * x + sum_i weights[i] * play_{radii[i]}[x]

    Parameters (model file keys)
    ----------------------------
    linear_weight : float > 0
        Weight of the input itself (the reversible part), output unit per input unit.
    radii : list of float > 0, strictly increasing
        Half-widths of the play (backlash) operators, in the input unit (N on the
        force path, V on the voltage path).
    weights : list of float
        Weight of each play operator (same length as ``radii``). Positive weights
        steepen the curve after a reversal (loading below unloading, the play
        type); negative weights flatten it (a stop-type or Bouc-Wen-like loop,
        loading above unloading). Every partial sum ``linear_weight + weights[0]
        + ... + weights[i]`` (the slope once the input has moved ``2 radii[i]``
        from a reversal) must be at least 1e-6: the operator is then strictly
        monotone and invertible.
    history_max : float >= 0, optional
        The input's history before the record: 0 (default) is a virgin sensor
        (every play at zero); a value M means the input came down from M to 0
        before the record (every play of radius r <= M/2 then starts at r).

    Every play operator starts at zero before the first sample (an unloaded
    sensor). With positive partial sums the operator is monotone and its inverse
    is again a Prandtl-Ishlinskii operator (Kuhnen 2003): radii
    ``r'_i = sum_{j<=i} a_j (r_i - r_j)`` (a_0 = linear_weight, r_0 = 0) and weights
    ``b_0 = 1/a_0``, ``b_i = -a_i / (A_i A_{i-1})`` with ``A_i = sum_{j<=i} a_j``,
    exact for the same initial state. ``backward`` (batch) and ``streaming()``
    (O(n) per sample) both run it.
    """

    kind = "play_hysteresis"
    KEYS = ("linear_weight", "radii", "weights")
    OPTIONAL = {"history_max": 0.0}
    linear_weight: float
    radii: FloatArray
    weights: FloatArray
    history_max: float

    def __init__(self, linear_weight: float, radii: Numbers, weights: Numbers, history_max: float = 0.0) -> None:
        linear_weight = check_number(self.kind, "linear_weight", linear_weight, positive=True)
        radii, weights = abscissae_and_values(self.kind, "radii", radii, "weights", weights)
        slopes = linear_weight + np.cumsum(weights)
        if np.any(slopes < 1e-6):
            raise ModelError(f"{self.kind}: every partial sum linear_weight + weights[0] + ... + weights[i] must be "
                             f">= 1e-6 (a monotone, invertible operator); the smallest is {slopes.min():.6g}")
        history_max = check_number(self.kind, "history_max", history_max, positive=False)
        if history_max < 0:
            raise ModelError(f"{self.kind}: history_max must be >= 0")
        self._freeze(linear_weight=linear_weight, radii=radii, weights=weights, history_max=history_max)

    def initial_states(self) -> tuple[FloatArray, FloatArray]:
        """The play states after the ``history_max`` history (zeros for a virgin sensor).

        Returns
        -------
        forward : (m,) ndarray of float
            States of the forward plays (half-widths ``radii``) [input unit].
        inverse : (m,) ndarray of float
            States of the inverse plays (radii from :meth:`inverse_parameters`) [output unit].
        """
        h = history_input(self.history_max)
        fwd = play_states_after(self.history_max, self.radii)
        b0, r_inv, b = self.inverse_parameters()
        if h.size:
            y_hist = self.linear_weight * h + play_operator(h, self.radii) @ self.weights
            inv = play_operator(y_hist, np.where(r_inv > 0, r_inv, 1e-300))[-1]
        else:
            inv = np.zeros(r_inv.size)
        return fwd, inv

    def inverse_parameters(self) -> tuple[float, FloatArray, FloatArray]:
        """The parameters of the inverse Prandtl-Ishlinskii operator (formulas in the class docstring).

        Returns
        -------
        b0 : float
            Weight of the output itself, ``1 / linear_weight`` [input unit per output unit].
        radii : (m,) ndarray of float
            Half-widths ``r'_i`` of the inverse plays [output unit].
        weights : (m,) ndarray of float
            Weights ``b_i`` of the inverse plays [input unit per output unit].
        """
        a = np.concatenate([[self.linear_weight], self.weights])
        r = np.concatenate([[0.0], self.radii])
        cum = np.cumsum(a)
        r_inv = np.array([np.sum(a[: i + 1] * (r[i] - r[: i + 1])) for i in range(1, r.size)])
        b = -a[1:] / (cum[1:] * cum[:-1])
        return 1.0 / a[0], r_inv, b

    def forward_state(self) -> _PlayForwardState:
        """A fresh state for block-wise :meth:`forward` runs."""
        return {"y": self.initial_states()[0]}

    def _rest_output(self) -> float:
        """Sum of the weighted play states after the history: subtracted so that y = 0 at x = 0 at the start."""
        return float(self.initial_states()[0] @ self.weights)

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_PlayForwardState] = None) -> FloatArray:
        """Prandtl-Ishlinskii output ``linear_weight * x + sum_i weights[i] * play_i[x]``."""
        x = np.asarray(x, dtype=float)
        st = state if state is not None else self.forward_state()
        plays = play_operator(x, self.radii, st["y"])
        if x.size:
            st["y"] = plays[-1].copy()
        return self.linear_weight * x + plays @ self.weights - self._rest_output()

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The input for output ``y`` over the record, by the inverse Prandtl-Ishlinskii operator."""
        y = np.asarray(y, dtype=float) + self._rest_output()
        b0, r_inv, b = self.inverse_parameters()
        keep = r_inv > 0  # r' > 0 for every i >= 1 (radii > 0, linear_weight > 0)
        return b0 * y + play_operator(y, r_inv[keep], self.initial_states()[1][keep]) @ b[keep]

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`, O(m) per sample for m plays."""
        b0, r_inv, b = self.inverse_parameters()
        keep = r_inv > 0
        radii, weights = [float(v) for v in r_inv[keep]], [float(v) for v in b[keep]]
        start = [float(v) for v in self.initial_states()[1][keep]]
        state = list(start)
        rest = self._rest_output()

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
            y = y + rest
            total = b0 * y
            for i, (r, w) in enumerate(zip(radii, weights)):
                p = min(max(state[i], y - r), y + r)
                state[i] = p
                total += w * p
            return total

        def reset() -> None:
            state[:] = start

        return FunctionStream(step, reset)

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping."""
        out = {"type": self.kind, "linear_weight": float(self.linear_weight), "radii": [float(v) for v in self.radii],
               "weights": [float(v) for v in self.weights]}
        if self.history_max:
            out["history_max"] = float(self.history_max)
        return out

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The element from a model-file mapping."""
        check_keys(cls.kind, d, cls.KEYS, cls.OPTIONAL)
        return cls(d["linear_weight"], d["radii"], d["weights"], d.get("history_max", 0.0))


class _FrictionForwardState(TypedDict):
    play_n: float  # the forward play's state [N]
    thermal: ThermalForwardState  # the band's lagged temperature


#: A band that follows temperature stays within this factor of ``radius_n`` either way.
BAND_FACTOR_MAX = 1e3
_LOG_BAND_MAX = math.log(BAND_FACTOR_MAX)


class FrictionElement(Frozen):
    """Coulomb friction in the mechanism, on the force path before the core: the core sees

        F_core = F - coupling * stop_r(F),    stop_r(F) = F - play_r(F),  |stop_r| <= r

    With ``coupling`` 1 the mechanism sticks inside a band of +-r about the force it passes on: the core's force
    moves only once the applied force has moved 2 r since a reversal (a play with no linear part). Below 1, part of
    the force passes while it sticks.

    No exact inverse exists: every force inside the band gives the same core force. The inverse runs the same
    friction on the core's force the other way, ``F = F_core + s * coupling * stop_r(q)`` with s =
    ``inverse_share``, where ``q = play_d(F_core)`` is the core's force with a dead band ``d`` that noise does not
    cross. With s = 1 it is exact while the force moves one way (once the core's force has moved 2 (r + d) since a
    reversal), and while the mechanism sticks and during a reversal the error is at most ``2 coupling r``; with
    s = 0 it is the core's force, never more than ``coupling r`` away; in between, a mix of the two. The inverse
    never divides by the stuck slope (1 - coupling), which an exact inverse of a partial coupling would; noise
    smaller than ``d`` passes with gain 1 (1 + s coupling without the dead band: a stop moves with its input
    inside its band).

    Parameters (model file keys)
    ----------------------------
    radius_n : float > 0
        Half-width r of the stiction band [N] (the Coulomb friction force).
    coupling : float in [0, 1]
        Share of the stop taken from the force; 1 is a rigid friction contact.
    deadband_n : float >= 0, optional
        Half-width d of the inverse's dead band on the core's force [N]: a few times its noise (0: none).
    inverse_share : float in [0, 1], optional
        Share of the friction the inverse adds back (1 by default). While the force slides the whole friction is
        the best estimate; while the contact sticks the applied force lies anywhere in the band, and the core's
        force itself (share 0) is never more than r away. Which is better depends on how the force is used (long
        holds, or reversals and puncture drops): ``polyforce diagnose`` chooses it by the compensated force.
    band_log_slope_per_c : float, optional
        How the band follows the mechanism's temperature T [1/degC]: r = radius_n exp(band_log_slope_per_c
        (T - reference_c)), within a factor :data:`BAND_FACTOR_MAX` of radius_n either way (a grease that stiffens
        as it cools, a housing that shrinks onto its sleeve: negative). 0 (the default): the same band at every
        temperature. T is ``aux['temperature_c']``; without it, or where it is not finite, the band is radius_n.
    reference_c : float, optional
        The temperature at which the band is radius_n [degC].
    temperature_lag_s : float, optional
        The mechanism's temperature follows the thermometer's through a first-order lag of this time, settled at the
        first temperature [s]; 0 (the default): the thermometer's own.

    Both runs start from rest (the play at 0: a virgin mechanism). The inverse's band follows the same temperature
    as the forward one, sample by sample.
    """

    kind = "friction"
    KEYS = ("radius_n", "coupling")
    OPTIONAL = {"deadband_n": 0.0, "inverse_share": 1.0, "band_log_slope_per_c": 0.0, "reference_c": 0.0,
                "temperature_lag_s": 0.0}
    radius_n: float
    coupling: float
    deadband_n: float
    inverse_share: float
    band_log_slope_per_c: float
    reference_c: float
    temperature_lag_s: float

    def __init__(self, radius_n: float, coupling: float = 1.0, deadband_n: float = 0.0,
                 inverse_share: float = 1.0, band_log_slope_per_c: float = 0.0, reference_c: float = 0.0,
                 temperature_lag_s: float = 0.0) -> None:
        radius_n = check_number(self.kind, "radius_n", radius_n, positive=True)
        coupling = check_number(self.kind, "coupling", coupling, positive=False)
        deadband_n = check_number(self.kind, "deadband_n", deadband_n, positive=False)
        inverse_share = check_number(self.kind, "inverse_share", inverse_share, positive=False)
        slope = check_number(self.kind, "band_log_slope_per_c", band_log_slope_per_c, positive=False)
        reference = check_number(self.kind, "reference_c", reference_c, positive=False)
        lag = check_number(self.kind, "temperature_lag_s", temperature_lag_s, positive=False)
        self._freeze(radius_n=radius_n, coupling=coupling, deadband_n=deadband_n, inverse_share=inverse_share,
                     band_log_slope_per_c=slope, reference_c=reference, temperature_lag_s=lag)

    def _band_of(self, temp_c: float) -> float:
        """The band's half-width at the mechanism's temperature ``temp_c`` [N] (radius_n where it is not finite)."""
        exponent = self.band_log_slope_per_c * (temp_c - self.reference_c)
        if not math.isfinite(exponent):
            return self.radius_n
        return self.radius_n * math.exp(min(max(exponent, -_LOG_BAND_MAX), _LOG_BAND_MAX))

    def _bands(self, t_s: npt.ArrayLike, n: int, aux: Optional[Mapping[str, Any]],
               state: Optional[ThermalForwardState] = None) -> Optional[FloatArray]:
        """The band's half-width at each sample [N], or None for a band that does not follow temperature here."""
        temp = temperature_c_of(aux, n) if self.band_log_slope_per_c else None
        if temp is None or n == 0:
            return None
        if self.temperature_lag_s > 0:
            temp = lagged_temperature_c(t_s, np.asarray(temp, dtype=float), self.temperature_lag_s, state)
        with np.errstate(invalid="ignore", over="ignore"):
            exponent = np.clip(self.band_log_slope_per_c * (np.asarray(temp, dtype=float) - self.reference_c),
                               -_LOG_BAND_MAX, _LOG_BAND_MAX)
        bands: FloatArray = np.where(np.isfinite(exponent), self.radius_n * np.exp(np.nan_to_num(exponent)),
                                     self.radius_n)
        return bands

    def forward_state(self) -> _FrictionForwardState:
        """A fresh state for block-wise :meth:`forward` runs (the play at rest, the temperature lag unsettled)."""
        return {"play_n": 0.0, "thermal": thermal_forward_state()}

    def forward(self, t_s: npt.ArrayLike, force_n: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_FrictionForwardState] = None) -> FloatArray:
        """The force the core sees [N] for the applied force ``force_n`` [N]."""
        f = np.asarray(force_n, dtype=float)
        st = state if state is not None else self.forward_state()
        bands = self._bands(t_s, f.size, aux, st["thermal"])
        play = play_operator(f, [self.radius_n] if bands is None else bands[:, None], [st["play_n"]])[:, 0]
        if f.size:
            st["play_n"] = float(play[-1])
        out: FloatArray = f - self.coupling * (f - play)
        return out

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The applied force [N] for the core's force ``y`` [N] (see the class docstring for its error bound)."""
        y = np.asarray(y, dtype=float)
        q = play_operator(y, [self.deadband_n])[:, 0] if self.deadband_n > 0 else y
        bands = self._bands(t_s, y.size, aux)
        play = play_operator(q, [self.radius_n] if bands is None else bands[:, None])[:, 0]
        out: FloatArray = y + self.coupling * self.inverse_share * (q - play)
        return out

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`, O(1) per sample."""
        r, c, d = self.radius_n, self.coupling * self.inverse_share, self.deadband_n
        state = [0.0, 0.0]  # the dead band's play, the stiction band's play [N]
        lag = LaggedTemperatureStream(self.temperature_lag_s) if self.temperature_lag_s > 0 else None
        follows = bool(self.band_log_slope_per_c)

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
            band = r
            temp = aux.get("temperature_c") if follows and aux else None
            if temp is not None:
                band = self._band_of(lag.update(t_s, temp) if lag is not None else float(temp))
            q = min(max(state[0], y - d), y + d)
            p = min(max(state[1], q - band), q + band)
            state[0], state[1] = q, p
            return y + c * (q - p)

        def reset() -> None:
            state[:] = [0.0, 0.0]
            if lag is not None:
                lag.reset()

        return FunctionStream(step, reset)

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping (defaults left out)."""
        out: dict[str, Any] = {"type": self.kind, "radius_n": float(self.radius_n), "coupling": float(self.coupling)}
        out.update({key: float(getattr(self, key)) for key, default in self.OPTIONAL.items()
                    if getattr(self, key) != default})
        return out

    def _with(self, **changes: float) -> FrictionElement:
        keys = {k: getattr(self, k) for k in ("radius_n", "coupling", *self.OPTIONAL)}
        return FrictionElement(**{**keys, **changes})

    def with_deadband(self, deadband_n: float) -> FrictionElement:
        """The same friction with the inverse's dead band ``deadband_n`` [N]."""
        return self._with(deadband_n=deadband_n)

    def with_inverse_share(self, inverse_share: float) -> FrictionElement:
        """The same friction whose inverse adds back ``inverse_share`` of it."""
        return self._with(inverse_share=inverse_share)

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The element from a model-file mapping."""
        check_keys(cls.kind, d, cls.KEYS, cls.OPTIONAL)
        return cls(d["radius_n"], d["coupling"], **{k: d.get(k, v) for k, v in cls.OPTIONAL.items()})
