"""Dynamic elements between the sensor and the ADC: a sensor lag (first order, pole pair, with an
explicitly band-limited inverse), a transport delay (never inverted) and a lightly damped mechanical mode
(inverted with its damping raised).
"""
from __future__ import annotations

import cmath
import math

from typing import Any, Mapping, Optional, TypedDict

import numpy as np
import numpy.typing as npt

from ..expconv import ExpConvState, exp_convolve
from .base import ElementStream, FloatArray, FunctionStream, ModelError, SimpleElement, short_repr

__all__ = ["SensorLagElement", "TransportDelayElement", "ResonanceElement"]


class _LagForwardState(TypedDict):
    y: FloatArray  # the lag's integral state, input unit * s
    t_prev: Optional[float]  # s; None before the first sample
    x_prev: float  # input unit


class _LastSample(TypedDict):
    t: Optional[float]  # s; None before the first sample
    y: float  # V


class SensorLagElement(SimpleElement):
    """First-order sensor/electronics dynamics (seed 002, eq. 10-11 with unit gain): tau y' + y = x.

    Forward: exact for piecewise-linear x (the shared recursion), output zero
    before the first sample.

    Backward, ``noise_filter_tau_s = 0`` (default): x = y + tau dy/dt with the
    slope over the last sample interval; white noise grows by about sqrt(2) tau / h.
    With ``noise_filter_tau_s = tau_f > 0`` the inverse is rolled off into
    (1 + tau s) / (1 + tau_f s) = tau/tau_f + (1 - tau/tau_f) / (1 + tau_f s):
    a weighted sum of y and of y through a lag of tau_f, run with the same
    exact recursion. Noise then grows by at most tau / tau_f, and the
    bandwidth ends near 1 / (2 pi tau_f). With ``noise_filter_order = 2`` the
    roll-off is (1 + tau s) / (1 + tau_f s)**2 = (tau/tau_f) L + (1 - tau/tau_f) L L,
    L a lag of tau_f: the inverse falls off above 1 / (2 pi tau_f) instead of
    staying at tau / tau_f, so white noise passes far less for the same tau_f
    (the compensated force then follows the applied one through 1 / (1 + tau_f s)**2,
    about 2 tau_f late). All assume y constant before its first sample (no
    start-up transient).
    """

    kind = "sensor_lag"
    PARAMS = (("tau_s", True),)
    OPTIONAL = {"noise_filter_tau_s": 0.0, "noise_filter_order": 1.0}
    tau_s: float
    noise_filter_tau_s: float
    noise_filter_order: float

    def __init__(self, **values: float) -> None:
        super().__init__(**values)
        if self.noise_filter_order not in (1.0, 2.0):
            raise ModelError(f"{self.kind}: noise_filter_order must be 1 or 2, got {short_repr(self.noise_filter_order)}")

    @property
    def latency_s(self) -> float:
        """How late the compensated signal follows: ``noise_filter_order * noise_filter_tau_s`` [s]."""
        return self.noise_filter_order * self.noise_filter_tau_s

    def forward_state(self) -> _LagForwardState:
        """A fresh lag state (output zero, no previous sample) for block-wise :meth:`forward` runs."""
        return {"y": np.zeros(1), "t_prev": None, "x_prev": 0.0}

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_LagForwardState] = None) -> FloatArray:
        """Output of the lag tau y' + y = x, exact for piecewise-linear ``x``."""
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        st = state if state is not None else self.forward_state()
        rate = 1.0 / self.tau_s
        if st["t_prev"] is None:
            y = exp_convolve(t, x, [rate], y0=st["y"])[:, 0]
        else:
            y = exp_convolve(t, x, [rate], y0=st["y"], u_prev=st["x_prev"], t_prev_s=st["t_prev"])[:, 0]
        y = y * rate
        if t.size:
            st["y"] = np.array([y[-1] / rate])
            st["t_prev"], st["x_prev"] = float(t[-1]), float(x[-1])
        return y

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The input ``y + tau dy/dt`` over the record, or its roll-off when ``noise_filter_tau_s`` > 0."""
        t, y = np.asarray(t_s, dtype=float), np.asarray(y, dtype=float)
        tau_f = self.noise_filter_tau_s
        if tau_f > 0.0:
            if y.size == 0:
                return y.copy()
            # the lag starts settled at y[0]: its integral state is y[0] * tau_f
            lagged = exp_convolve(t, y, [1.0 / tau_f], y0=[y[0] * tau_f])[:, 0] / tau_f
            if self.noise_filter_order == 2.0:
                twice = exp_convolve(t, lagged, [1.0 / tau_f], y0=[y[0] * tau_f])[:, 0] / tau_f
                return (self.tau_s / tau_f) * lagged + (1.0 - self.tau_s / tau_f) * twice
            return (self.tau_s / tau_f) * y + (1.0 - self.tau_s / tau_f) * lagged
        slope = np.zeros_like(y)
        if y.size > 1:
            dt = np.diff(t)
            slope[1:] = np.where(dt > 0, np.diff(y) / np.where(dt > 0, dt, 1.0), 0.0)
        return y + self.tau_s * slope

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward` (slope over the last interval, or the rolled-off inverse)."""
        tau, tau_f = self.tau_s, self.noise_filter_tau_s
        if tau_f > 0.0 and self.noise_filter_order == 2.0:
            first, second = ExpConvState([1.0 / tau_f]), ExpConvState([1.0 / tau_f])
            w_once, w_twice = tau / tau_f, 1.0 - tau / tau_f

            def filtered2(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
                if first.t_prev_s is None:
                    first.reset([y * tau_f])
                    second.reset([y * tau_f])
                state = first.update(t_s, y)
                once = (state if state is not None else first.y)[0] / tau_f
                state = second.update(t_s, once)
                twice = (state if state is not None else second.y)[0] / tau_f
                return w_once * once + w_twice * twice

            def reset2() -> None:
                first.reset()
                second.reset()

            return FunctionStream(filtered2, reset2)
        if tau_f > 0.0:
            lag = ExpConvState([1.0 / tau_f])
            w_direct, w_lag = tau / tau_f, 1.0 - tau / tau_f

            def filtered(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
                if lag.t_prev_s is None:
                    lag.reset([y * tau_f])
                state = lag.update(t_s, y)
                if state is None:  # time went backwards: the lag holds, as over a zero-length step
                    state = lag.y
                return w_direct * y + w_lag * state[0] / tau_f

            return FunctionStream(filtered, lag.reset)

        prev: _LastSample = {"t": None, "y": 0.0}

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> float:
            slope = 0.0
            if prev["t"] is not None and t_s > prev["t"]:
                slope = (y - prev["y"]) / (t_s - prev["t"])
            prev["t"], prev["y"] = t_s, y
            return y + tau * slope

        # a TypedDict's update takes a mapping, not keywords
        return FunctionStream(step, lambda: prev.update({"t": None, "y": 0.0}))


class _DelayForwardState(TypedDict):
    t: FloatArray  # s; the input samples of the last delay_s (the interpolation's support)
    x: FloatArray  # input unit


class TransportDelayElement(SimpleElement):
    """A pure delay (DAQ buffering, transport): y(t) = x(t - delay_s).

    Forward: the input interpolated linearly at ``t - delay_s``, held at its first sample
    before it (a settled sensor). Backward: a delay cannot be undone without predicting the
    future, so the inverse passes the signal unchanged and the chain states the latency
    (:attr:`SensorChain.latency_s`) instead of boosting noise to fake a prediction.
    """

    kind = "transport_delay"
    PARAMS = (("delay_s", True),)
    delay_s: float

    def forward_state(self) -> _DelayForwardState:
        """A fresh delay state (no input seen) for block-wise :meth:`forward` runs."""
        return {"t": np.zeros(0), "x": np.zeros(0)}

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_DelayForwardState] = None) -> FloatArray:
        """The input delayed by ``delay_s`` (linear interpolation; the first input before the record); ``state``
        carries the last ``delay_s`` of input across blocks (see :meth:`Element.forward`)."""
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        st = state if state is not None else self.forward_state()
        if t.size == 0:
            return x.copy()
        support_t, support_x = np.concatenate([st["t"], t]), np.concatenate([st["x"], x])
        y: FloatArray = np.interp(t - self.delay_s, support_t, support_x, left=support_x[0])
        keep = support_t >= t[-1] - self.delay_s
        keep[max(int(np.argmax(keep)) - 1, 0)] = True  # one sample before the window: the interpolation's left end
        st["t"], st["x"] = support_t[keep], support_x[keep]
        return y

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The output unchanged: the delay stays, stated as latency, never undone by amplifying noise."""
        return np.array(y, dtype=float)

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward` (the sample unchanged)."""
        return FunctionStream(lambda t_s, y, aux=None: y)


class _Mode:
    """One complex first-order mode z' = p z + a u, exact for piecewise-linear u, one sample at a time or over a record.

    A real second-order section is the real part of two conjugate modes: 2 Re(z) with one of them.
    """

    def __init__(self, pole: complex, residue: complex) -> None:
        self.pole, self.residue = pole, residue
        self.z: complex = 0.0j
        self.t_prev: Optional[float] = None
        self.u_prev = 0.0
        self._h: Optional[float] = None
        self._weights = (1.0 + 0.0j, 0.0j, 0.0j)

    def weights(self, h: float) -> tuple[complex, complex, complex]:
        """(e^{p h}, a (I0 - I1/h), a I1/h): z_next = e z + w_prev u_prev + w_next u_next for u linear over h > 0."""
        if self._h is not None and abs(h - self._h) <= 1e-12 * self._h:
            return self._weights
        p, ph = self.pole, self.pole * h
        e = cmath.exp(ph)
        if abs(ph) < 1e-3:  # series: the closed forms cancel
            i0 = h * (1.0 + ph / 2.0 + ph * ph / 6.0)
            i1 = h * h * (0.5 + ph / 6.0 + ph * ph / 24.0)
        else:
            i0 = (e - 1.0) / p
            i1 = (e - 1.0 - ph) / (p * p)
        self._h, self._weights = h, (e, self.residue * (i0 - i1 / h), self.residue * i1 / h)
        return self._weights

    def settle(self, u: float) -> None:
        """The state of a mode that has seen ``u`` for ever: z = -a u / p."""
        self.z = -self.residue * u / self.pole

    def step(self, t_s: float, u: float) -> Optional[complex]:
        """The state after a sample at ``t_s``; None (nothing changed) for a stamp before the previous one."""
        if self.t_prev is not None:
            h = t_s - self.t_prev
            if h < 0.0:
                return None
            if h > 0.0:
                e, w_prev, w_next = self.weights(h)
                self.z = e * self.z + w_prev * self.u_prev + w_next * u
        self.t_prev, self.u_prev = t_s, u
        return self.z

    def run(self, t_s: FloatArray, u: FloatArray) -> npt.NDArray[np.complex128]:
        """The states over a record (one :meth:`step` per sample; one IIR filter when the step is constant, a
        block that continues an earlier one included)."""
        out = np.empty(u.size, dtype=complex)
        if u.size == 0:
            return out
        first = 0
        if self.t_prev is None:  # the first sample only becomes the previous one
            out[0], self.t_prev, self.u_prev, first = self.z, float(t_s[0]), float(u[0]), 1
        steps = np.diff(t_s[first - 1:] if first else np.concatenate([[self.t_prev], t_s]))
        if steps.size and steps[0] > 0 and np.all(np.abs(steps - steps[0]) <= 1e-9 * steps[0]):
            from scipy import signal

            e, w_prev, w_next = self.weights(float(steps[0]))
            out[first:], _ = signal.lfilter([w_next, w_prev], [1.0, -e], u[first:],
                                            zi=[e * self.z + w_prev * self.u_prev])  # e z + w_prev u before the block
            self.z, self.t_prev, self.u_prev = complex(out[-1]), float(t_s[-1]), float(u[-1])
            return out
        for i in range(first, u.size):
            z = self.step(float(t_s[i]), float(u[i]))
            out[i] = z if z is not None else self.z
        return out


class ResonanceElement(SimpleElement):
    """A lightly damped mechanical mode: y'' + 2 zeta w y' + w^2 y = w^2 x, w = 2 pi frequency_hz (unit DC gain).

    Forward: exact for piecewise-linear x, from rest. The exact inverse (s^2 + 2 zeta w s + w^2) / w^2 would
    differentiate twice; the saved inverse keeps the mode's frequency and replaces its damping:
    (s^2 + 2 zeta w s + w^2) / (s^2 + 2 zeta_f w s + w^2), zeta_f = ``inverse_damping_ratio`` > zeta. It cancels
    the ringing without amplifying noise (its gain never exceeds 1), and the compensated signal then follows
    the input through a well-damped mode at the same frequency, about 2 zeta_f / w late. The inverse assumes
    y constant before its first sample.
    """

    kind = "resonance"
    PARAMS = (("frequency_hz", True), ("damping_ratio", True))
    OPTIONAL = {"inverse_damping_ratio": 0.7}
    frequency_hz: float
    damping_ratio: float
    inverse_damping_ratio: float

    def __init__(self, **values: float) -> None:
        super().__init__(**values)
        if not self.damping_ratio < self.inverse_damping_ratio:
            raise ModelError(f"{self.kind}: inverse_damping_ratio ({self.inverse_damping_ratio:g}) must exceed "
                             f"damping_ratio ({self.damping_ratio:g}): the inverse damps the mode, never rings more")

    @property
    def latency_s(self) -> float:
        """How late the compensated signal follows: ``2 inverse_damping_ratio / w`` [s]."""
        return 2.0 * self.inverse_damping_ratio / (2.0 * math.pi * self.frequency_hz)

    def _pole(self, zeta: float) -> complex:
        w = 2.0 * math.pi * self.frequency_hz
        return complex(-zeta * w, w * math.sqrt(1.0 - zeta * zeta))

    def _forward_mode(self) -> _Mode:
        p, w = self._pole(self.damping_ratio), 2.0 * math.pi * self.frequency_hz
        return _Mode(p, w * w / (p - p.conjugate()))

    def _inverse_mode(self) -> _Mode:
        q, w = self._pole(self.inverse_damping_ratio), 2.0 * math.pi * self.frequency_hz
        c = 2.0 * (self.damping_ratio - self.inverse_damping_ratio) * w
        return _Mode(q, c * q / (q - q.conjugate()))

    def forward_state(self) -> _Mode:
        """A fresh mode (at rest, no previous sample) for block-wise :meth:`forward` runs."""
        return self._forward_mode()

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Optional[_Mode] = None) -> FloatArray:
        """The mode's output, exact for piecewise-linear ``x``, from rest."""
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        if t.size > 1 and np.any(np.diff(t) < 0):
            raise ValueError("t_s must be non-decreasing")
        mode = state if state is not None else self.forward_state()
        y: FloatArray = 2.0 * mode.run(t, x).real
        return y

    def backward(self, t_s: npt.ArrayLike, y: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None) -> FloatArray:
        """The input, through the inverse with the mode's damping raised to ``inverse_damping_ratio``."""
        t, y = np.asarray(t_s, dtype=float), np.asarray(y, dtype=float)
        if y.size == 0:
            return y.copy()
        if t.size > 1 and np.any(np.diff(t) < 0):
            raise ValueError("t_s must be non-decreasing")
        mode = self._inverse_mode()
        mode.settle(float(y[0]))
        x: FloatArray = y + 2.0 * mode.run(t, y).real
        return x

    def streaming(self) -> ElementStream:
        """The per-sample form of :meth:`backward`, O(1) per sample."""
        mode = self._inverse_mode()

        def step(t_s: float, y: float, aux: Optional[Mapping[str, Any]] = None) -> Optional[float]:
            if mode.t_prev is None:
                mode.settle(y)
            z = mode.step(t_s, y)
            return None if z is None else y + 2.0 * z.real

        def reset() -> None:
            mode.z, mode.t_prev, mode.u_prev = 0.0j, None, 0.0

        return FunctionStream(step, reset)
