"""Dynamic elements between the sensor and the ADC: a sensor lag (first order, pole pair, with an
explicitly band-limited inverse) and a transport delay (never inverted).
"""
from __future__ import annotations

from typing import Any, Mapping, Optional, TypedDict

import numpy as np
import numpy.typing as npt

from ..expconv import ExpConvState, exp_convolve
from .base import ElementStream, FloatArray, FunctionStream, ModelError, SimpleElement, short_repr

__all__ = ["SensorLagElement", "TransportDelayElement"]


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
