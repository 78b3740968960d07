"""Rate-independent hysteresis: the Preisach relay model, the Prandtl-Ishlinskii play operator, play
operators at the bridge beside a viscoelastic core, and Coulomb friction in the mechanism.
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
    stream_backward,
)
from .core import KneeKelvinElement, ViscoelasticElement, wrapped_core_from_dict

if TYPE_CHECKING:  # for annotations only: at run time the Preisach model loads when first used
    from ..preisach import ContinuousPreisachStream, PreisachModel, PreisachStream

__all__ = ["PreisachElement", "play_operator", "history_input", "play_states_after", "PlayHysteresisElement",
           "BridgeHysteresisElement", "FrictionElement", "scaled_input", "scaled_output", "SCALED_STATE_MAX"]


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
    radii : (m,) array_like of float
        Half-widths of the plays [the input's unit].
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
    r = np.atleast_1d(np.asarray(radii, dtype=float))
    y = np.zeros(r.size) if y0 is None else np.array(y0, dtype=float)
    out = np.empty((x.size, r.size))
    if x.size == 0:
        return out
    if chunk is None:
        chunk = 1 << max(6, int(math.log2(max(1, (1 << 15) // max(r.size, 1)))))
    width = min(chunk, x.size)
    lo_buf, hi_buf, tmp = (np.empty((width, r.size)) for _ in range(3))
    for start in range(0, x.size, chunk):
        xc = x[start:start + chunk, None]
        n = xc.shape[0]
        lo, hi = lo_buf[:n], hi_buf[:n]
        np.subtract(xc, r, out=lo)
        np.add(xc, r, out=hi)
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


class _BridgeForwardState(TypedDict):
    core: Any  # the core's ForwardState
    y: FloatArray  # play states [N]
    u: FloatArray  # scaled play states [1, on asinh(F / floor_n)]


#: A scaled play's state is kept within +-SCALED_STATE_MAX before the sinh back to newtons: e**700 is near the largest
#: float, and a force of that size is clamped long before it reaches a haptic master.
SCALED_STATE_MAX = 700.0


def scaled_input(force_n: npt.ArrayLike, floor_n: float) -> FloatArray:
    """The scaled plays' input ``asinh(F / floor_n)``: about ``ln(2 F / floor_n)`` above the floor, so a play of
    half-width r there is a band of about ``+-r F``, and odd, so a pull is a push mirrored [1]."""
    out: FloatArray = np.arcsinh(np.asarray(force_n, dtype=float) / floor_n)
    return out


def scaled_output(state: npt.ArrayLike, floor_n: float) -> FloatArray:
    """A scaled play's state back in newtons, ``floor_n sinh(state)`` [N]."""
    out: FloatArray = floor_n * np.sinh(np.clip(np.asarray(state, dtype=float), -SCALED_STATE_MAX, SCALED_STATE_MAX))
    return out


class BridgeHysteresisElement(Frozen):
    """A viscoelastic core with rate-independent hysteresis at the bridge: applied force (N) -> volts.

        V = core(F) + linear_v_per_n * F + sum_i weights_v_per_n[i] * play_{radii_n[i]}[F]
                    + sum_j scaled_weights_v_per_n[j] * floor_n sinh(play_{scaled_radii[j]}[asinh(F / floor_n)]) - rest

    The hysteresis acts on the applied force and adds to the deformation without creeping (e.g. strain
    gauges or their adhesive with a friction-like loop), so it is neither before the core (its loop would
    creep with it) nor after it (its input would be the creeping deformation). ``rest`` keeps V = core(F)
    at zero force before the record.

    The plays on F have bands of a fixed width in newtons. The scaled plays act on ``asinh(F / floor_n)``, about
    ``ln(2 F / floor_n)`` above the floor: their bands grow with the load (a play of half-width r holds the force
    within about ``F e**-r .. F e**r`` after a reversal), the loop of a friction whose normal force the load makes
    (disc springs, wedges, a capstan), and at zero force they keep a band of about ``+-r floor_n``.

    Parameters (model file keys)
    ----------------------------
    core : mapping
        The viscoelastic core (as a model file's core element).
    radii_n : list of float > 0, strictly increasing, optional
        Half-widths of the play operators [N].
    weights_v_per_n : list of float, optional
        Weight of each play [V/N]; ``linear_v_per_n`` plus every partial sum of them must be >= 0, so the
        added term never falls while the force rises and the inverse is unique.
    linear_v_per_n : float >= 0, optional
        Weight of the force itself [V/N] (with negative play weights: a stop-type loop).
    scaled_radii : list of float > 0, strictly increasing, optional
        Half-widths of the scaled plays, on ``asinh(F / floor_n)`` [1] (0.1 is a band of about +-10 % of the load).
    scaled_weights_v_per_n : list of float >= 0, optional
        Weight of each scaled play [V/N]: non-negative, so each scaled term never falls while the force rises.
    floor_n : float > 0
        The force below which a scaled play's band stops shrinking with the load [N]; needed with scaled plays.
    history_max_n : float >= 0, optional
        The force came down from this value to 0 before the record (plays of radius <= half of it start
        at their radius, and likewise for the scaled plays on its scaled value); 0 is a virgin sensor.

    At least one kind of play is given. The inverse solves, per sample, the core's next step (an affine map of the
    deformation, :meth:`~polyforce_ros.physics.viscoelastic.StreamingCompensator.affine`) together with the plays.
    Between two of the plays' breakpoints every play is dragged down, stuck or dragged up, so the sum to solve is
    ``a + b F + c sqrt(F**2 + floor_n**2)`` with ``b > |c|``: one sweep over the breakpoints finds the piece and a
    closed form its root, exact.
    """

    kind = "bridge_hysteresis"
    KEYS = ("core",)
    OPTIONAL = {"radii_n": (), "weights_v_per_n": (), "linear_v_per_n": 0.0, "scaled_radii": (),
                "scaled_weights_v_per_n": (), "floor_n": 0.0, "history_max_n": 0.0}
    core: ViscoelasticElement
    radii_n: FloatArray
    weights_v_per_n: FloatArray
    linear_v_per_n: float
    scaled_radii: FloatArray
    scaled_weights_v_per_n: FloatArray
    floor_n: float
    history_max_n: float
    _start: FloatArray  # play states after the history [N]
    _scaled_start: FloatArray  # scaled play states after the history [1]
    _rest_v: float  # the plays' term at zero force before the record [V]

    def __init__(self, core: ViscoelasticElement, radii_n: Numbers = (), weights_v_per_n: Numbers = (),
                 linear_v_per_n: float = 0.0, history_max_n: float = 0.0, scaled_radii: Numbers = (),
                 scaled_weights_v_per_n: Numbers = (), floor_n: float = 0.0) -> None:
        if not isinstance(core, ViscoelasticElement) or isinstance(core, KneeKelvinElement):
            # the inverse solves the plays with the core's next step as an affine map of its deformation
            raise ModelError(f"{self.kind}: core must be a viscoelastic core whose step is affine (not knee_kelvin), "
                             f"got {short_repr(core)}")
        radii, weights = _optional_pairs(self.kind, "radii_n", radii_n, "weights_v_per_n", weights_v_per_n)
        scaled, scaled_weights = _optional_pairs(self.kind, "scaled_radii", scaled_radii, "scaled_weights_v_per_n",
                                                 scaled_weights_v_per_n)
        if radii.size == 0 and scaled.size == 0:
            raise ModelError(f"{self.kind}: needs radii_n and weights_v_per_n, or scaled_radii and "
                             f"scaled_weights_v_per_n (a loop without plays is the core alone)")
        if np.any(scaled_weights < 0):
            raise ModelError(f"{self.kind}: every scaled_weights_v_per_n must be >= 0 (a term that never falls while "
                             f"the force rises)")
        floor = check_number(self.kind, "floor_n", floor_n, positive=False)
        if scaled.size and floor <= 0:
            raise ModelError(f"{self.kind}: scaled plays need floor_n > 0 (the force below which their bands stop "
                             f"shrinking)")
        linear = check_number(self.kind, "linear_v_per_n", linear_v_per_n, positive=False)
        history = check_number(self.kind, "history_max_n", history_max_n, positive=False)
        if linear < 0 or history < 0:
            raise ModelError(f"{self.kind}: linear_v_per_n and history_max_n must be >= 0")
        if radii.size:
            slopes = linear + np.cumsum(weights)
            # a stop-type term sums to zero at its last play: rounding may leave -1e-17 there
            if np.any(slopes < -1e-12 * (linear + float(np.sum(np.abs(weights))))):
                raise ModelError(f"{self.kind}: linear_v_per_n + weights_v_per_n[0] + ... + weights_v_per_n[i] must "
                                 f"be >= 0 for every i (a term that never falls while the force rises); the smallest "
                                 f"is {slopes.min():.6g}")
            linear += max(0.0, -float(slopes.min()))  # within rounding of 0: raised so that every slope is >= 0 exactly
        start = play_states_after(history, radii)
        scaled_start = play_states_after(float(scaled_input(history, floor)) if scaled.size else 0.0, scaled)
        rest = float(start @ weights) + float(scaled_output(scaled_start, floor) @ scaled_weights) if scaled.size \
            else float(start @ weights)
        self._freeze(core=core, radii_n=radii, weights_v_per_n=weights, linear_v_per_n=linear,
                     scaled_radii=scaled, scaled_weights_v_per_n=scaled_weights, floor_n=floor,
                     history_max_n=history, _start=start, _scaled_start=scaled_start, _rest_v=rest)

    @property
    def model(self) -> Any:
        """The viscoelastic model of the core."""
        return self.core.model

    def with_core(self, core: ViscoelasticElement) -> BridgeHysteresisElement:
        """The same plays beside another core."""
        return BridgeHysteresisElement(core, self.radii_n, self.weights_v_per_n, self.linear_v_per_n,
                                       self.history_max_n, self.scaled_radii, self.scaled_weights_v_per_n, self.floor_n)

    def large_signal_slope_v_per_n(self) -> float:
        """The plays' slope with every play dragged [V/N]: ``linear_v_per_n`` plus the weights, each scaled play's
        weight times ``cosh(r)`` (the mean of its loading and unloading slopes far above the floor)."""
        return (self.linear_v_per_n + float(np.sum(self.weights_v_per_n))
                + float(np.cosh(self.scaled_radii) @ self.scaled_weights_v_per_n))

    def forward_state(self) -> _BridgeForwardState:
        """A fresh state for block-wise :meth:`forward` runs (relaxed core, plays after the history)."""
        return {"core": self.core.forward_state(), "y": self._start.copy(), "u": self._scaled_start.copy()}

    def forward(self, t_s: npt.ArrayLike, force_n: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_BridgeForwardState] = None) -> FloatArray:
        """The core's deformation plus the hysteresis term, both driven by the applied force."""
        f = np.asarray(force_n, dtype=float)
        st = state if state is not None else self.forward_state()
        out: FloatArray = self.core.forward(t_s, f, state=st["core"]) + self.linear_v_per_n * f - self._rest_v
        if self.radii_n.size:
            plays = play_operator(f, self.radii_n, st["y"])
            if f.size:
                st["y"] = plays[-1].copy()
            out = out + plays @ self.weights_v_per_n
        if self.scaled_radii.size:
            scaled = play_operator(scaled_input(f, self.floor_n), self.scaled_radii, st["u"])
            if f.size:
                st["u"] = scaled[-1].copy()
            out = out + scaled_output(scaled, self.floor_n) @ self.scaled_weights_v_per_n
        return out

    def backward(self, t_s: npt.ArrayLike, voltage_v: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The force for a deformation record, sample by sample (the inverse is implicit)."""
        return stream_backward(self.streaming(), t_s, voltage_v, aux)

    def streaming(self) -> ElementStream:
        """The per-sample inverse: O(m log m) per sample for m plays of both kinds."""
        core = self.core.streaming()
        radii = [float(r) for r in self.radii_n]
        weights = [float(w) for w in self.weights_v_per_n]
        scaled = [float(r) for r in self.scaled_radii]
        scaled_weights = [float(w) for w in self.scaled_weights_v_per_n]
        floor, linear, rest = self.floor_n, self.linear_v_per_n, self._rest_v
        # every play dragged down: the term's slope in F and in sqrt(F**2 + floor**2), and its constant
        down_b = linear + sum(weights) + sum(w * math.cosh(r) for r, w in zip(scaled, scaled_weights))
        down_c = sum(w * math.sinh(r) for r, w in zip(scaled, scaled_weights))
        down_a = sum(w * r for r, w in zip(radii, weights))
        start = [float(y) for y in self._start]
        scaled_start = [float(u) for u in self._scaled_start]
        plays, scaled_plays = list(start), list(scaled_start)

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> Optional[float]:
            coefficients = core.affine(t_s)
            if coefficients is None:
                return None
            f0, stiffness = coefficients
            stiffness = max(stiffness, 0.0)
            # F = f0 + stiffness (V - H(F)): solve g(F) = F + stiffness (H(F) + rest) = f0 + stiffness (V + rest).
            # Between breakpoints H(F) + rest = a + b F + c s(F), s(F) = sqrt(F**2 + floor**2); each play below its
            # band is dragged down, inside it stuck (a constant), above it dragged up. Events change (a, b, c).
            target = f0 + stiffness * (y + rest)
            events = []
            for p, r, w in zip(plays, radii, weights):  # w (F + r) -> w p -> w (F - r)
                events.append((p - r, w * (p - r), -w, 0.0))
                events.append((p + r, -w * (p + r), w, 0.0))
            for q, r, w in zip(scaled_plays, scaled, scaled_weights):
                # floor sinh(u + r) = F cosh r + s sinh r -> floor sinh(q) -> F cosh r - s sinh r
                held = w * floor * _sinh(q)
                events.append((floor * _sinh(q - r), held, -w * math.cosh(r), -w * math.sinh(r)))
                events.append((floor * _sinh(q + r), -held, w * math.cosh(r), -w * math.sinh(r)))
            events.sort(key=lambda e: e[0])
            a, b, c = down_a, down_b, down_c
            force = None
            low = -math.inf
            for f_event, da, db, dc in events:
                if target <= _bridge_g(f_event, a, b, c, stiffness, floor):
                    force = _bridge_root(target, a, b, c, stiffness, floor, low, f_event)
                    break
                a, b, c, low = a + da, b + db, c + dc, f_event
            if force is None:
                force = _bridge_root(target, a, b, c, stiffness, floor, low, math.inf)
            hyst = linear * force - rest
            for i, (r, w) in enumerate(zip(radii, weights)):
                plays[i] = min(max(plays[i], force - r), force + r)
                hyst += w * plays[i]
            if scaled:
                u = math.asinh(force / floor)
                for i, (r, w) in enumerate(zip(scaled, scaled_weights)):
                    scaled_plays[i] = min(max(scaled_plays[i], u - r), u + r)
                    hyst += w * floor * _sinh(scaled_plays[i])
            return core.step(t_s, y - hyst)

        def reset() -> None:
            core.reset()
            plays[:] = start
            scaled_plays[:] = scaled_start

        return FunctionStream(step, reset)

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping (defaults left out)."""
        out: dict[str, Any] = {"type": self.kind, "core": self.core.to_dict()}
        for key in ("radii_n", "weights_v_per_n", "scaled_radii", "scaled_weights_v_per_n"):
            values = getattr(self, key)
            if values.size:
                out[key] = [float(v) for v in values]
        for key in ("linear_v_per_n", "floor_n", "history_max_n"):
            if getattr(self, key) != 0.0:
                out[key] = float(getattr(self, key))
        return out

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The element from a model-file mapping."""
        check_keys(cls.kind, d, cls.KEYS, cls.OPTIONAL)
        return cls(wrapped_core_from_dict(cls.kind, d["core"]), d.get("radii_n", ()), d.get("weights_v_per_n", ()),
                   d.get("linear_v_per_n", 0.0), d.get("history_max_n", 0.0), d.get("scaled_radii", ()),
                   d.get("scaled_weights_v_per_n", ()), d.get("floor_n", 0.0))


def _optional_pairs(kind: str, x_key: str, x: object, y_key: str, y: object) -> tuple[FloatArray, FloatArray]:
    """:func:`abscissae_and_values`, or two empty arrays when both lists are empty (that kind of play left out)."""
    if isinstance(x, (list, tuple, np.ndarray)) and isinstance(y, (list, tuple, np.ndarray)) and len(x) == len(y) == 0:
        return np.zeros(0), np.zeros(0)
    return abscissae_and_values(kind, x_key, x, y_key, y)


def _sinh(x: float) -> float:
    """``sinh`` of a scaled play's state within +-:data:`SCALED_STATE_MAX` (``math.sinh`` raises beyond ~710)."""
    return math.sinh(min(max(x, -SCALED_STATE_MAX), SCALED_STATE_MAX))


def _bridge_g(force_n: float, a: float, b: float, c: float, stiffness: float, floor_n: float) -> float:
    """``F + stiffness (a + b F + c sqrt(F**2 + floor_n**2))`` on one piece of the bridge's inverse."""
    return force_n + stiffness * (a + b * force_n + (c * math.hypot(force_n, floor_n) if c else 0.0))


def _bridge_root(target: float, a: float, b: float, c: float, stiffness: float, floor_n: float, low: float,
                 high: float) -> float:
    """The root of ``_bridge_g(F) = target`` on the piece [low, high] [N].

    With B = 1 + stiffness b and C = stiffness c, ``B F + C s(F) = T`` (T = target - stiffness a) rises with F
    (B - |C| >= 1: each scaled play's cosh r is above its sinh r), and squaring it leaves a quadratic whose root with
    ``T - B F`` of the sign of C is ``(B T - C R) / D``, D = B**2 - C**2, R = sqrt(T**2 + D floor**2); written as
    ``(T**2 - C**2 floor**2) / (B T + C R)`` where B T and C R share a sign, so that nothing cancels."""
    big_b = 1.0 + stiffness * b
    big_c = stiffness * c
    # a running sum's rounding (stiffness up to 1e13 N/V) must not take the slope below 1
    big_b = max(big_b, 1.0 + abs(big_c))
    t = target - stiffness * a
    if big_c == 0.0:
        force = t / big_b
    else:
        d = (big_b - big_c) * (big_b + big_c)
        r = math.hypot(t, math.sqrt(d) * floor_n)
        if big_b * t * big_c > 0.0:
            force = (t - big_c * floor_n) * (t + big_c * floor_n) / (big_b * t + big_c * r)
        else:
            force = (big_b * t - big_c * r) / d
    return min(max(force, low), high)


class _FrictionForwardState(TypedDict):
    play_n: float  # the forward play's state [N]


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

    Both runs start from rest (the play at 0: a virgin mechanism).
    """

    kind = "friction"
    KEYS = ("radius_n", "coupling")
    OPTIONAL = {"deadband_n": 0.0, "inverse_share": 1.0}
    radius_n: float
    coupling: float
    deadband_n: float
    inverse_share: float

    def __init__(self, radius_n: float, coupling: float = 1.0, deadband_n: float = 0.0,
                 inverse_share: float = 1.0) -> None:
        radius_n = check_number(self.kind, "radius_n", radius_n, positive=True)
        coupling = check_number(self.kind, "coupling", coupling, positive=False)
        deadband_n = check_number(self.kind, "deadband_n", deadband_n, positive=False)
        inverse_share = check_number(self.kind, "inverse_share", inverse_share, positive=False)
        self._freeze(radius_n=radius_n, coupling=coupling, deadband_n=deadband_n, inverse_share=inverse_share)

    def forward_state(self) -> _FrictionForwardState:
        """A fresh state for block-wise :meth:`forward` runs (the play at rest)."""
        return {"play_n": 0.0}

    def forward(self, t_s: npt.ArrayLike, force_n: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_FrictionForwardState] = None) -> FloatArray:
        """The force the core sees [N] for the applied force ``force_n`` [N]."""
        f = np.asarray(force_n, dtype=float)
        st = state if state is not None else self.forward_state()
        play = play_operator(f, [self.radius_n], [st["play_n"]])[:, 0]
        if f.size:
            st["play_n"] = float(play[-1])
        out: FloatArray = f - self.coupling * (f - play)
        return out

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The applied force [N] for the core's force ``y`` [N] (see the class docstring for its error bound)."""
        y = np.asarray(y, dtype=float)
        q = play_operator(y, [self.deadband_n])[:, 0] if self.deadband_n > 0 else y
        out: FloatArray = y + self.coupling * self.inverse_share * (q - play_operator(q, [self.radius_n])[:, 0])
        return out

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`, O(1) per sample."""
        r, c, d = self.radius_n, self.coupling * self.inverse_share, self.deadband_n
        state = [0.0, 0.0]  # the dead band's play, the stiction band's play [N]

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
            q = min(max(state[0], y - d), y + d)
            p = min(max(state[1], q - r), q + r)
            state[0], state[1] = q, p
            return y + c * (q - p)

        def reset() -> None:
            state[:] = [0.0, 0.0]

        return FunctionStream(step, reset)

    def to_dict(self) -> dict[str, Any]:
        """The element as a model-file mapping."""
        out = {"type": self.kind, "radius_n": float(self.radius_n), "coupling": float(self.coupling)}
        if self.deadband_n:
            out["deadband_n"] = float(self.deadband_n)
        if self.inverse_share != 1.0:
            out["inverse_share"] = float(self.inverse_share)
        return out

    def with_deadband(self, deadband_n: float) -> FrictionElement:
        """The same friction with the inverse's dead band ``deadband_n`` [N]."""
        return FrictionElement(self.radius_n, self.coupling, deadband_n, self.inverse_share)

    def with_inverse_share(self, inverse_share: float) -> FrictionElement:
        """The same friction whose inverse adds back ``inverse_share`` of it."""
        return FrictionElement(self.radius_n, self.coupling, self.deadband_n, inverse_share)

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Self:
        """The element from a model-file mapping."""
        check_keys(cls.kind, d, cls.KEYS, cls.OPTIONAL)
        return cls(d["radius_n"], d["coupling"], d.get("deadband_n", 0.0), d.get("inverse_share", 1.0))
