"""Thin-film force sensor on a pneumatic artificial muscle (seed 002).

* first-order sensor/circuit dynamics, eq. 10-11: tau V' + V = kappa F + b;
* the pressure-geometry patch-force model, eq. 4-9:
  F = A_eff [c0 + (k0 + k1 g) p + c2 p^2 + c3 p'],  g = 3 (L / b_braid)^2 - 1;
* joint nonlinear least-squares identification of eq. 12 from (p, L, V);
* a system simulation: valve logic, chamber filling and exhaust through a flow
  resistance, pressure between ~120 and 600 kPa, patch force, voltage;
* the inverse of the first-order sensor (force from voltage) and its bandwidth.

Units: pressure in Pa inside the models (kPa only in the linear summary, as
the paper's F = 0.810 p - 51.42 uses), force N, voltage V, time s.

Identifiability: in eq. 12 kappa multiplies every patch-force coefficient,
so kappa and (c0, k0, k1, c2, c3) cannot be separated from (p, L, V) data:
scaling kappa by s and the coefficients by 1/s gives the same voltage. And
kappa A_eff c0 (a constant) is indistinguishable from the offset b. The
identification therefore holds kappa (from a static calibration), A_eff and
c0 fixed and fits c2, c3, k0, k1, tau and b, which the data determine as
long as the muscle length varies independently of the pressure (otherwise
g p is a combination of p and p^2 and k1 is lost too).
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Iterable, Optional

import numpy as np
import numpy.typing as npt
from scipy import optimize, signal

from .chain import SensorLagElement

__all__ = ["PAPER_TABLE5", "PAPER_LINEAR_SUMMARY", "PAPER_FIT", "PatchSensor", "inversion_bode",
    "identify_patch_sensor", "PneumaticMuscle", "linear_summary"]

#: Seed 002, Table 5 (pressure coefficients per Pa) and eq. 13.
PAPER_TABLE5 = dict(c0_pa=-9.083, c2_per_pa=3.254e-6, c3_s=-2.158e-3, k0=-1.435, k1=0.6377,
                    tau_s=3.321e-2, kappa_v_per_n=8.325e-3, b_v=0.147)
PAPER_LINEAR_SUMMARY = dict(slope_n_per_kpa=0.810, intercept_n=-51.42, r2=0.9912)
PAPER_FIT = dict(r2=0.934, rmse_v=0.1493)


@dataclass(frozen=True)
class PatchSensor:
    """Parameters of eq. 12 (see module docstring for units)."""

    c0_pa: float = PAPER_TABLE5["c0_pa"]
    c2_per_pa: float = PAPER_TABLE5["c2_per_pa"]
    c3_s: float = PAPER_TABLE5["c3_s"]
    k0: float = PAPER_TABLE5["k0"]
    k1: float = PAPER_TABLE5["k1"]
    tau_s: float = PAPER_TABLE5["tau_s"]
    kappa_v_per_n: float = PAPER_TABLE5["kappa_v_per_n"]
    b_v: float = PAPER_TABLE5["b_v"]
    a_eff_m2: float = 9.0e-4
    braid_m: float = 0.1277

    def geometry(self, length_m: npt.ArrayLike) -> np.ndarray:
        """g = 3 (L / b)^2 - 1 (eq. 8)."""
        return 3.0 * (np.asarray(length_m) / self.braid_m) ** 2 - 1.0

    def patch_force(self, t_s: npt.ArrayLike, pressure_pa: npt.ArrayLike, length_m: npt.ArrayLike) -> np.ndarray:
        """Eq. 9: patch force in N; p' by finite differences of the sampled pressure."""
        p = np.asarray(pressure_pa, dtype=float)
        dp = np.gradient(p, np.asarray(t_s, dtype=float)) if p.size > 1 else np.zeros_like(p)
        g = self.geometry(length_m)
        force_n: np.ndarray = self.a_eff_m2 * (self.c0_pa + (self.k0 + self.k1 * g) * p + self.c2_per_pa * p * p
                                               + self.c3_s * dp)
        return force_n

    def voltage(self, t_s: npt.ArrayLike, force_n: npt.ArrayLike) -> np.ndarray:
        """Eq. 11: tau V' + V = kappa F + b, started at rest (V = b + kappa F(0))."""
        f = np.asarray(force_n, dtype=float)
        lag = SensorLagElement(tau_s=self.tau_s)
        drive = self.kappa_v_per_n * f
        out: np.ndarray = self.b_v + drive[0] + lag.forward(t_s, drive - drive[0])
        return out

    def force_from_voltage(self, t_s: npt.ArrayLike, voltage_v: npt.ArrayLike,
                           cutoff_hz: Optional[float] = None) -> np.ndarray:
        """Inverse of eq. 11: F = (V + tau V' - b) / kappa, optionally low-passed (causal, 2nd order).

        The inverse differentiates, so it amplifies noise by about tau / h; a
        low-pass at ``cutoff_hz`` (several times 1 / (2 pi tau)) keeps it usable.
        """
        lag = SensorLagElement(tau_s=self.tau_s)
        force = (lag.backward(t_s, voltage_v) - self.b_v) / self.kappa_v_per_n
        if cutoff_hz:
            fs = 1.0 / float(np.median(np.diff(t_s)))
            sos = signal.butter(2, cutoff_hz, fs=fs, output="sos")
            force = signal.sosfilt(sos, force, zi=signal.sosfilt_zi(sos) * force[0])[0]
        return force

    def bandwidth_hz(self) -> float:
        """-3 dB bandwidth of the first-order sensor, 1 / (2 pi tau)."""
        return 1.0 / (2 * np.pi * self.tau_s)


def inversion_bode(sensor: PatchSensor, freqs_hz: Iterable[float], cutoff_hz: float = 50.0, mean_n: float = 200.0,
                   amplitude_n: float = 100.0, rate_hz: float = 1e4) -> tuple[np.ndarray, np.ndarray]:
    """Magnitudes (dB re. the applied force) of the raw reading (V - b) / kappa and of the inverse.

    A sine of ``amplitude_n`` around ``mean_n`` per frequency, judged on the
    second half of 12 periods (+1 s); the inverse uses a ``cutoff_hz`` filter.
    """
    from .metrics import sine_component

    raw_db, inv_db = [], []
    for f in freqs_hz:
        t = np.arange(0, 12 / f + 1.0, 1.0 / rate_hz)
        force = mean_n + amplitude_n * np.sin(2 * np.pi * f * t)
        v = sensor.voltage(t, force)
        steady = t > t[-1] / 2
        raw = (v[steady] - sensor.b_v) / sensor.kappa_v_per_n
        raw_db.append(20 * np.log10(sine_component(t[steady], raw, f)[0] / amplitude_n))
        est = sensor.force_from_voltage(t, v, cutoff_hz=cutoff_hz)[steady]
        inv_db.append(20 * np.log10(sine_component(t[steady], est, f)[0] / amplitude_n))
    return np.array(raw_db), np.array(inv_db)


_FITTED = ("c2_per_pa", "c3_s", "k0", "k1", "tau_s", "b_v")


def identify_patch_sensor(t_s: npt.ArrayLike, pressure_pa: npt.ArrayLike, length_m: npt.ArrayLike,
                          voltage_v: npt.ArrayLike, fixed: PatchSensor) -> tuple[PatchSensor, float, float]:
    """Joint nonlinear least squares of eq. 12 (seed 002 Sect. 4.1).

    ``fixed`` supplies kappa, A_eff, c0 and the braid length (held, see the
    module docstring) and the starting values of the others. Returns ``(sensor, r2, rmse_v)``.
    """
    t = np.asarray(t_s, dtype=float)
    v = np.asarray(voltage_v, dtype=float)
    x0 = np.array([getattr(fixed, k) for k in _FITTED])
    scale = np.where(x0 != 0, np.abs(x0), 1.0)

    def model(x: np.ndarray) -> tuple[PatchSensor, np.ndarray]:
        sensor = replace(fixed, **dict(zip(_FITTED, x * scale)))
        return sensor, sensor.voltage(t, sensor.patch_force(t, pressure_pa, length_m))

    def residual(x: np.ndarray) -> np.ndarray:
        if x[_FITTED.index("tau_s")] <= 0:
            return np.full(v.size, 1e3)
        r: np.ndarray = model(x)[1] - v
        return r

    lower = np.full(x0.size, -np.inf)
    lower[_FITTED.index("tau_s")] = 1e-4 / scale[_FITTED.index("tau_s")]
    sol = optimize.least_squares(residual, x0 / scale, bounds=(lower, np.inf), x_scale="jac")
    sensor, fitted = model(sol.x)
    res = fitted - v
    r2 = 1.0 - float(res @ res) / float(((v - v.mean()) ** 2).sum())
    return sensor, r2, float(np.sqrt(np.mean(res * res)))


@dataclass(frozen=True)
class PneumaticMuscle:
    """Valve-driven chamber of a pneumatic muscle (Festo DMSP-40-120 class).

    Inlet open: p -> supply through the flow resistance (time constant
    ``fill_tau_s``); outlet open: p -> atmosphere (``exhaust_tau_s``); both
    closed: hold. The gauge reading adds ``bias_kpa`` and is clamped to
    [``p_min_kpa``, ``p_max_kpa``] as in the paper's model. Length contracts
    linearly with pressure up to ``max_contraction`` of ``length_m`` and
    moves with the joint it spans (a slow sine of ``knee_amplitude_m``).
    """

    supply_kpa: float = 600.0
    atmosphere_kpa: float = 101.325
    bias_kpa: float = 20.0
    p_min_kpa: float = 120.0
    p_max_kpa: float = 600.0
    fill_tau_s: float = 0.45
    exhaust_tau_s: float = 0.35
    length_m: float = 0.120
    max_contraction: float = 0.25
    t_in_s: float = 2.5
    t_hold_s: float = 1.0
    t_out_s: float = 2.0
    t_rest_s: float = 0.5
    knee_amplitude_m: float = 0.006
    knee_period_s: float = 13.0

    def valves(self, t_s: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Inlet and outlet commands (bool arrays) of the cyclic schedule: rest, fill, hold, exhaust."""
        period = self.t_rest_s + self.t_in_s + self.t_hold_s + self.t_out_s
        phase = np.mod(np.asarray(t_s, dtype=float), period) - self.t_rest_s
        inlet = (phase >= 0) & (phase < self.t_in_s)
        outlet = (phase >= self.t_in_s + self.t_hold_s) | (phase < 0)
        return inlet, outlet

    def simulate(self, t_s: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Chamber pressure (Pa, clamped gauge reading) and muscle length (m) over ``t_s``."""
        t = np.asarray(t_s, dtype=float)
        inlet, outlet = self.valves(t)
        p = np.empty_like(t)
        p_now = self.atmosphere_kpa
        for k in range(t.size):  # piecewise-constant valve states: exact exponential steps
            if k:
                h = t[k] - t[k - 1]
                if inlet[k - 1]:
                    p_now = self.supply_kpa + (p_now - self.supply_kpa) * np.exp(-h / self.fill_tau_s)
                elif outlet[k - 1]:
                    p_now = self.atmosphere_kpa + (p_now - self.atmosphere_kpa) * np.exp(-h / self.exhaust_tau_s)
            p[k] = p_now
        gauge_kpa = np.clip(p + self.bias_kpa, self.p_min_kpa, self.p_max_kpa)
        frac = (gauge_kpa - self.p_min_kpa) / (self.p_max_kpa - self.p_min_kpa)
        knee = self.knee_amplitude_m * np.sin(2 * np.pi * t / self.knee_period_s)
        length = self.length_m * (1.0 - self.max_contraction * frac) + knee
        return gauge_kpa * 1e3, length


def linear_summary(pressure_pa: npt.ArrayLike, force_n: np.ndarray) -> dict[str, float]:
    """Least-squares line F = slope * p[kPa] + intercept and its R^2 (the paper's eq. 13 form)."""
    p_kpa = np.asarray(pressure_pa) / 1e3
    slope, intercept = np.polyfit(p_kpa, force_n, 1)
    pred = slope * p_kpa + intercept
    res = np.asarray(force_n) - pred
    r2 = 1.0 - float(res @ res) / float(((force_n - np.mean(force_n)) ** 2).sum())
    return {"slope_n_per_kpa": float(slope), "intercept_n": float(intercept), "r2": r2}
