"""Hysteresis at the bridge: play operators on the applied force, and plays whose bands grow with the load, added to
the voltage beside a viscoelastic core, with an exact per-sample inverse.
"""
from __future__ import annotations

import math
from typing import Any, Mapping, Optional, Self, TypedDict

import numpy as np
import numpy.typing as npt

from .base import (
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
from .hysteresis import play_operator, play_states_after

__all__ = ["BridgeHysteresisElement", "scaled_input", "scaled_output", "MAX_BRIDGE_PLAYS", "SCALED_STATE_MAX"]


class _BridgeForwardState(TypedDict):
    core: Any  # the core's ForwardState
    y: FloatArray  # play states [N]
    u: FloatArray  # scaled play states [1, on asinh(F / floor_n)]


#: Plays of both kinds one bridge_hysteresis holds: its inverse sorts their breakpoints at every sample (22 plays on
#: the force and 26 scaled ones, the most a diagnosis saves, take about 0.1 ms per sample in Python).
MAX_BRIDGE_PLAYS = 64
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
        The force below which a scaled play's band stops shrinking with the load [N]; given with scaled plays and
        only with them.
    history_max_n : float >= 0, optional
        The force came down from this value to 0 before the record (plays of radius <= half of it start
        at their radius, and likewise for the scaled plays on its scaled value); 0 is a virgin sensor.

    At least one kind of play is given. The inverse solves, per sample, the core's next step (an affine map of the
    deformation, :meth:`~polyforce_ros.physics.viscoelastic.StreamingCompensator.affine`) together with the plays.
    Between two of the plays' breakpoints every play is dragged down, stuck or dragged up, so the sum to solve is
    ``a + b F + c sqrt(F**2 + floor_n**2)`` with ``b >= |c|``: one sweep over the breakpoints finds the piece and a
    closed form its root, exact. At most :data:`MAX_BRIDGE_PLAYS` plays in all.
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
        if radii.size + scaled.size > MAX_BRIDGE_PLAYS:
            raise ModelError(f"{self.kind}: {radii.size + scaled.size} plays in all; at most {MAX_BRIDGE_PLAYS} (the "
                             f"inverse sorts their breakpoints at every sample)")
        # scaled_weights_v_per_n >= 0 by its bounds: each scaled term never falls while the force rises
        floor = check_number(self.kind, "floor_n", floor_n, positive=False)
        if bool(scaled.size) != (floor > 0):
            raise ModelError(f"{self.kind}: floor_n > 0 goes with scaled plays and only with them (the force below "
                             f"which their bands stop shrinking)")
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
        rest = float(start @ weights) + float(scaled_output(scaled_start, floor) @ scaled_weights)
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
        start = [float(y) for y in self._start]
        scaled_start = [float(u) for u in self._scaled_start]
        plays, scaled_plays = list(start), list(scaled_start)
        # below every breakpoint every play is dragged down, whatever its state: where each sweep starts
        down_a, down_b, down_c = _piece_coefficients(-math.inf, plays, radii, weights, scaled_plays, scaled,
                                                     scaled_weights, floor, linear)

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
            # the piece by running sums (fast); then its coefficients summed afresh from each play's status: the
            # running sums keep a rounding residue of the plays that left them, which a stiff core (up to 1e13 N/V)
            # times the floor turns into newtons, and a neighbouring piece is taken when that residue chose wrong
            a, b, c = down_a, down_b, down_c
            piece = len(events)
            for i, (f_event, da, db, dc) in enumerate(events):
                if target <= _bridge_g(f_event, a, b, c, stiffness, floor):
                    piece = i
                    break
                a, b, c = a + da, b + db, c + dc
            for _ in range(len(events) + 1):
                low = events[piece - 1][0] if piece > 0 else -math.inf
                high = events[piece][0] if piece < len(events) else math.inf
                a, b, c = _piece_coefficients(_inside(low, high), plays, radii, weights, scaled_plays, scaled,
                                              scaled_weights, floor, linear)
                if piece < len(events) and target > _bridge_g(high, a, b, c, stiffness, floor):
                    piece += 1
                elif piece > 0 and target < _bridge_g(low, a, b, c, stiffness, floor):
                    piece -= 1
                else:
                    break
            force = _bridge_root(target, a, b, c, stiffness, floor, low, high)
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


def _inside(low: float, high: float) -> float:
    """A force inside the piece [low, high] of the bridge's inverse (either end may be infinite) [N]."""
    if math.isfinite(low) and math.isfinite(high):
        return 0.5 * (low + high)
    if math.isfinite(high):
        return high - max(1.0, abs(high))
    if math.isfinite(low):
        return low + max(1.0, abs(low))
    return 0.0


def _piece_coefficients(force_n: float, plays: list[float], radii: list[float], weights: list[float],
                        scaled_plays: list[float], scaled: list[float], scaled_weights: list[float], floor_n: float,
                        linear: float) -> tuple[float, float, float]:
    """(a, b, c) of the plays' term ``a + b F + c sqrt(F**2 + floor_n**2)`` on the piece holding ``force_n``, each
    play dragged down, stuck or dragged up there, summed exactly (``math.fsum``)."""
    a, b, c = [], [linear], []
    for p, r, w in zip(plays, radii, weights):
        if force_n < p - r:
            a.append(w * r)
            b.append(w)
        elif force_n > p + r:
            a.append(-w * r)
            b.append(w)
        else:
            a.append(w * p)
    for q, r, w in zip(scaled_plays, scaled, scaled_weights):
        if force_n < floor_n * _sinh(q - r):
            b.append(w * math.cosh(r))
            c.append(w * math.sinh(r))
        elif force_n > floor_n * _sinh(q + r):
            b.append(w * math.cosh(r))
            c.append(-w * math.sinh(r))
        else:
            a.append(w * floor_n * _sinh(q))
    return math.fsum(a), math.fsum(b), math.fsum(c)


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
    (B - |C| >= 1: each dragged scaled play's cosh r is above its sinh r, and a stuck one adds to neither), and
    squaring it leaves a quadratic whose root with ``T - B F`` of the sign of C is ``(B T - C R) / D``,
    D = B**2 - C**2, R = sqrt(T**2 + D floor**2); written as ``(T**2 - C**2 floor**2) / (B T + C R)`` where B T and
    C R share a sign, so that nothing cancels."""
    big_b = 1.0 + stiffness * b
    big_c = stiffness * c
    # rounding of a stiff core's products (stiffness up to 1e13 N/V) must not take the slope below 1
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
