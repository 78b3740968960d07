"""Seed 002 experiments: thin-film sensor on a pneumatic muscle, identified, simulated, inverted."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..physics.metrics import bandwidth_3db
from ..physics.thinfilm import (
    PAPER_FIT, PAPER_LINEAR_SUMMARY, PatchSensor, PneumaticMuscle, identify_patch_sensor, inversion_bode, linear_summary,
)
from .common import Row, Section, Settings, figure

#: Noise of the simulated recording: chosen so the fit residual is near the paper's 0.149 V.
RECORDING_NOISE_V = 0.15


def run(settings: Settings) -> Section:
    section = Section("Thin-film force sensor on pneumatic artificial muscles: geometry-modulated model")
    truth = PatchSensor()
    muscle = PneumaticMuscle()
    rng = np.random.default_rng(settings.seed + 2)
    # Identification (Sect. 4.1): a recording of (p, L, V) with the joint moving.
    t = np.arange(0, 30.0 if settings.quick else 60.0, 1e-2)
    p, length = muscle.simulate(t)
    v = truth.voltage(t, truth.patch_force(t, p, length)) + rng.normal(0, RECORDING_NOISE_V, t.size)
    start = replace(truth, c2_per_pa=2e-6, c3_s=-1e-3, k0=-1.0, k1=0.5, tau_s=0.1, b_v=0.0)
    fit, r2, rmse = identify_patch_sensor(t, p, length, v, start)
    section.rows += [
        Row("Identification, eq. 12 (Fig. 4)", "R² of the voltage fit", "", None, PAPER_FIT["r2"], None, r2, ">=").judge(),
        Row("Identification, eq. 12 (Fig. 4)", "RMSE of the voltage fit", "V", None, PAPER_FIT["rmse_v"], None, rmse, "<=",
            note=f"recording noise {RECORDING_NOISE_V} V").judge(tolerance=0.05),
    ]
    for name in ("c2_per_pa", "c3_s", "k0", "k1", "tau_s", "b_v"):
        section.rows.append(Row("Identification, Table 5", name, "", None, getattr(truth, name), None,
                                f"{getattr(fit, name):.4g}"))
    section.notes.append("kappa, A_eff and c0 are held in the fit: kappa scales every patch coefficient and kappa A_eff c0 "
                         "is indistinguishable from the offset b, so the data cannot separate them.")
    # System simulation without joint motion (Sect. 4.2, Fig. 5), the paper's setting.
    still = replace(muscle, knee_amplitude_m=0.0)
    ts = np.arange(0, 36.0, 1e-3)
    ps, ls = still.simulate(ts)
    fs = fit.patch_force(ts, ps, ls)
    vs = fit.voltage(ts, fs)
    summary = linear_summary(ps, fs)
    section.rows += [
        Row("System simulation (Fig. 5)", "chamber pressure range", "kPa", None, "120-600", None,
            f"{ps.min() / 1e3:.0f}-{ps.max() / 1e3:.0f}", "",
            passed=abs(ps.min() / 1e3 - 120) < 5 and abs(ps.max() / 1e3 - 600) < 1),
        Row("System simulation (Fig. 5)", "peak patch force", "N", None, "~450", None, float(fs.max())),
        Row("System simulation (eq. 13)", "slope of F vs p", "N/kPa", None, PAPER_LINEAR_SUMMARY["slope_n_per_kpa"], None,
            summary["slope_n_per_kpa"]),
        Row("System simulation (eq. 13)", "intercept of F vs p", "N", None, PAPER_LINEAR_SUMMARY["intercept_n"], None,
            summary["intercept_n"]),
        Row("System simulation (eq. 13)", "R² of the linear summary", "", None, PAPER_LINEAR_SUMMARY["r2"], None, summary["r2"]),
    ]
    # Inverse of the first-order sensor: bandwidth before and after.
    freqs = np.array([0.5, 1, 2, 4, 8, 16, 32])
    raw_db, inv_db = inversion_bode(fit, freqs, cutoff_hz=50.0)
    bw_raw, bw_inv = bandwidth_3db(freqs, raw_db, 0.0), bandwidth_3db(freqs, inv_db, 0.0)
    section.rows.append(Row("Sensor inversion (Sect. 3.2)", "-3 dB bandwidth of the force reading", "Hz", None, "(future work)",
                            bw_raw, bw_inv, "", passed=bw_inv > 5 * bw_raw,
                            note="inverse tau V' + V with a 50 Hz noise filter"))
    fig, ax = figure(1, 2, (13, 4.5))
    ax[0, 0].plot(ts, ps / 1e3, "b", lw=1, label="pressure [kPa]")
    ax[0, 0].plot(ts, fs, "r", lw=1, label="patch force [N]")
    ax[0, 0].plot(ts, vs * 100, "k", lw=0.8, label="voltage x 100 [V]")
    ax[0, 0].set(xlabel="time [s]", title="System simulation (Fig. 5)")
    ax[0, 0].legend(fontsize=8)
    ax[0, 1].plot(ps / 1e3, fs, "r.", ms=1, label="simulated")
    pk = np.linspace(120, 600, 10)
    ax[0, 1].plot(pk, summary["slope_n_per_kpa"] * pk + summary["intercept_n"], "k",
                  label=f"ours: {summary['slope_n_per_kpa']:.3f} p {summary['intercept_n']:+.1f}")
    ax[0, 1].plot(pk, 0.810 * pk - 51.42, "g--", label="paper: 0.810 p - 51.42")
    ax[0, 1].set(xlabel="pressure [kPa]", ylabel="patch force [N]", title="Pressure-force relation (eq. 13)")
    ax[0, 1].legend(fontsize=8)
    section.figures.append(("s002_system.png", fig, "Seed 002: system simulation and the linear pressure-force summary."))
    return section
