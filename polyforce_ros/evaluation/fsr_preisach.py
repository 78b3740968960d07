"""Seed 001 experiments: Preisach hysteresis of force sensing resistors, CMA vs linear regression.

The simulated FSR is a continuous Preisach operator (ramp hysterons, so the
truth is not the discrete model we identify) from force (N) to voltage, with
repeatability noise. Identification follows the paper: 40 triangles of
increasing amplitude up to 4.5 N, n_h = 40 (820 hysterons), non-negative
least squares. Force is then estimated on a grip-like profile by the CMA,
by the continuous inverse, and by the two linear regressions the paper uses
as baselines.
"""
from __future__ import annotations

from typing import Callable, TypedDict

import numpy as np
import numpy.typing as npt

from ..physics.preisach import PreisachModel, hysteresis_error_percent, identify
from .common import Row, Section, Settings, figure

FloatArray = npt.NDArray[np.float64]


class _PaperFigures(TypedDict):
    mse_reduction_vs_increasing_pct: float
    mse_reduction_vs_whole_pct: float
    he_range_pct: tuple[float, float]


PAPER: _PaperFigures = {"mse_reduction_vs_increasing_pct": 54.0, "mse_reduction_vs_whole_pct": 76.0,
                        "he_range_pct": (7.6, 17.0)}
F_MAX_N = 4.5
N_LEVELS = 40


def fsr_truth(hysteresis_scale: float = 1.0, b0_v: float = 0.05, v_nom_v: float = 2.0, seed: int = 0,
              n: int = N_LEVELS) -> PreisachModel:
    """A continuous-Preisach FSR: weights spread off the diagonal by ``hysteresis_scale`` (wider = more HE)."""
    rng = np.random.default_rng(seed)
    i, j = np.tril_indices(n)
    width = 0.25 * n * hysteresis_scale
    density = np.zeros((n, n))
    density[i, j] = (0.5 + rng.uniform(0, 1, i.size)) * np.exp(-((i - j) / width) ** 2)
    density *= (v_nom_v - b0_v) / 2 / density.sum()  # output spans b0 .. V_nom over 0 .. F_max
    offset = b0_v + (v_nom_v - b0_v) / 2
    return PreisachModel(0.0, F_MAX_N, density, offset)


def run_truth(model: PreisachModel, force: FloatArray, noise_v: float, rng: np.random.Generator) -> FloatArray:
    stream = model.stream(continuous=True)
    return np.array([stream.forward(f) for f in force]) + rng.normal(0, noise_v, np.size(force))


def triangles(points: int = 50) -> FloatArray:
    parts = [np.zeros(1)]
    for a in np.linspace(0, F_MAX_N, N_LEVELS + 1)[1:]:
        parts += [np.linspace(0, a, points + 1)[1:], np.linspace(a, 0, points + 1)[1:]]
    return np.concatenate(parts)


def grip_profile(seed: int = 1, duration_s: float = 60.0, rate_hz: float = 50.0) -> tuple[FloatArray, FloatArray]:
    """Grip-like force: grasps of varying strength with holds and releases (0 .. 4.5 N)."""
    rng = np.random.default_rng(seed)
    t_knots, f_knots, t_now = [0.0], [0.0], 0.0
    while t_now < duration_s:
        peak = rng.uniform(0.8, F_MAX_N)
        for dur, val in ((rng.uniform(0.4, 1.0), peak), (rng.uniform(0.5, 2.0), peak * rng.uniform(0.85, 1.0)),
                         (rng.uniform(0.3, 0.8), peak * rng.uniform(0.0, 0.4)), (rng.uniform(0.3, 1.2), 0.0)):
            t_now += dur
            t_knots.append(t_now)
            f_knots.append(val)
    t = np.arange(0, duration_s, 1.0 / rate_hz)
    return t, np.interp(t, t_knots, f_knots)


def _linear_fit(volts: FloatArray, force: FloatArray) -> Callable[[npt.ArrayLike], FloatArray]:
    m, b = np.polyfit(volts, force, 1)
    return lambda v: m * np.asarray(v) + b


def _mse(a: npt.ArrayLike, b: npt.ArrayLike) -> float:
    return float(np.mean((np.asarray(a) - np.asarray(b)) ** 2))


class SensorEvaluation(TypedDict):
    """:func:`evaluate_sensor`'s outcome: force MSE per estimator, the grip profile, the estimates, the identified
    model, the hysteresis error and the training record."""

    mse: dict[str, float]
    t: FloatArray
    f: FloatArray
    est: dict[str, FloatArray]
    model: PreisachModel
    he: float
    train: tuple[FloatArray, FloatArray]


def evaluate_sensor(truth: PreisachModel, seed: int, noise_v: float) -> SensorEvaluation:
    """Identify one sensor and compare the four force estimators on a grip profile. Returns MSEs and data."""
    rng = np.random.default_rng(seed)
    f_train = triangles()
    v_train = run_truth(truth, f_train, noise_v, rng)
    model = identify(f_train, v_train, n_levels=N_LEVELS, u_min=0.0, u_max=F_MAX_N)
    rising = np.concatenate(([True], np.diff(f_train) > 0))
    lr_inc = _linear_fit(v_train[rising], f_train[rising])
    lr_all = _linear_fit(v_train, f_train)
    t, f_test = grip_profile(seed=seed + 100)
    v_test = run_truth(truth, f_test, noise_v, rng)
    cma, cont = model.stream(), model.stream(continuous=True)
    est = {
        "CMA (discrete)": np.array([cma.inverse(v) for v in v_test]),
        "continuous inverse": np.array([cont.inverse(v) for v in v_test]),
        "linear, increasing data": lr_inc(v_test),
        "linear, whole data": lr_all(v_test),
    }
    he = hysteresis_error_percent(f_train[-2 * 50 - 1:], v_train[-2 * 50 - 1:])
    return {"mse": {k: _mse(e, f_test) for k, e in est.items()}, "t": t, "f": f_test, "est": est, "model": model, "he": he,
            "train": (f_train, v_train)}


def generalised(settings: Settings, n_sensors: int) -> list[dict[str, float]]:
    """Eq. 6: one Preisach model on normalised outputs for a batch of sensors with spread hysteresis."""
    rng = np.random.default_rng(settings.seed + 7)
    sensors = [fsr_truth(hysteresis_scale=rng.uniform(0.5, 1.6), b0_v=rng.uniform(0.02, 0.1), v_nom_v=rng.uniform(1.6, 2.4),
                         seed=settings.seed + 20 + k) for k in range(n_sensors)]
    f_train = triangles(points=25)
    pooled_f: list[FloatArray] = []
    pooled_v: list[FloatArray] = []
    data: list[tuple[PreisachModel, float, float]] = []
    for s in sensors:
        v = run_truth(s, f_train, 0.005, rng)
        b0, v_nom = v[0], v[np.argmax(f_train)]  # measured at null force and at the nominal force
        data.append((s, b0, v_nom))
        pooled_f.append(f_train)
        pooled_v.append((v - b0) / (v_nom - b0))
    general = identify(np.concatenate(pooled_f), np.concatenate(pooled_v), n_levels=N_LEVELS, u_min=0.0, u_max=F_MAX_N)
    rows: list[dict[str, float]] = []
    for k, (s, b0, v_nom) in enumerate(data):
        t, f_test = grip_profile(seed=settings.seed + 300 + k, duration_s=30.0)
        v_test = run_truth(s, f_test, 0.005, rng)
        cma = general.stream()
        f_general = np.array([cma.inverse((v - b0) / (v_nom - b0)) for v in v_test])
        own = evaluate_sensor(s, settings.seed + 400 + k, 0.005)["mse"]
        rows.append({"he": hysteresis_error_percent(f_train[-51:], (run_truth(s, f_train, 0.0, rng))[-51:]),
                     "generalised": _mse(f_general, f_test), **own})
    return rows


def run(settings: Settings) -> Section:
    section = Section("Hysteresis in force sensing resistors: Preisach model and closest-match inverse")
    truth = fsr_truth(seed=settings.seed)
    res = evaluate_sensor(truth, settings.seed, noise_v=0.005)
    mse = res["mse"]
    red_inc = 100 * (1 - mse["CMA (discrete)"] / mse["linear, increasing data"])
    red_all = 100 * (1 - mse["CMA (discrete)"] / mse["linear, whole data"])
    section.rows += [
        Row("Characterisation (Fig. 4)", "hysteresis error HE (eq. 3) of the simulated FSR", "%", None, "7.6-17",
            None, res["he"], "", passed=7.6 <= res["he"] <= 17.0),
        Row("Preisach model (Sect. 3.2)", "hysterons for n_h = 40", "", 820, None, None, res["model"].n_hysterons, "",
            passed=res["model"].n_hysterons == 820),
        Row("Grip profile (Fig. 8-9)", "MSE reduction of CMA vs linear, increasing data", "%", None,
            PAPER["mse_reduction_vs_increasing_pct"], None, red_inc, ">=").judge(),
        Row("Grip profile (Fig. 8-9)", "MSE reduction of CMA vs linear, whole data", "%", None,
            PAPER["mse_reduction_vs_whole_pct"], None, red_all, ">=").judge(),
    ]
    for name, value in mse.items():
        section.rows.append(Row("Grip profile (Fig. 9)", f"force MSE, {name}", "N²", None, None, None, value))
    n_sensors = 6 if settings.quick else 16
    batch = generalised(settings, n_sensors)
    better = sum(r["generalised"] < r["linear, whole data"] for r in batch)
    section.rows += [
        Row("Generalised parameters (eq. 6)", f"mean MSE over {n_sensors} sensors: generalised CMA", "N²", None,
            "higher than tuned", None, float(np.mean([r["generalised"] for r in batch]))),
        Row("Generalised parameters (eq. 6)", "mean MSE: sensor-tuned CMA", "N²", None, None, None,
            float(np.mean([r["CMA (discrete)"] for r in batch]))),
        Row("Generalised parameters (eq. 6)", "sensors where generalised beats linear (whole data)", "", None, "mixed",
            None, f"{better} of {n_sensors}"),
    ]
    fig, ax = figure(1, 2, (13, 4.5))
    t = res["t"]
    ax[0, 0].plot(t, res["f"], "b", lw=1.5, label="applied")
    for (name, est), color in zip(res["est"].items(), ("r", "m", "g", "k")):
        ax[0, 0].plot(t, est, color, lw=0.7, label=f"{name} (MSE {mse[name]:.4f} N²)")
    ax[0, 0].set(xlabel="time [s]", ylabel="force [N]", title="Force estimation on a grip profile (Fig. 8)")
    ax[0, 0].legend(fontsize=7)
    dens = np.where(np.tril(np.ones((N_LEVELS, N_LEVELS))) > 0, res["model"].density, np.nan)
    im = ax[0, 1].imshow(dens, origin="lower", cmap="viridis")
    ax[0, 1].set(xlabel="down-switching level j", ylabel="up-switching level i",
                 title="Identified Preisach density, n_h = 40 (Fig. 7)")
    fig.colorbar(im, ax=ax[0, 1], label="weight [V]")
    section.figures.append(("s001_preisach.png", fig, "Seed 001: estimators on a grip profile and the identified density."))
    fig, ax = figure()
    xs = np.arange(len(batch))
    for off, key, color in ((-0.3, "CMA (discrete)", "r"), (-0.1, "linear, increasing data", "g"),
                            (0.1, "linear, whole data", "k"), (0.3, "generalised", "b")):
        ax[0, 0].bar(xs + off, [r[key] for r in batch], width=0.2, color=color, label=key)
    ax[0, 0].set(xlabel="sensor", ylabel="force MSE [N²]", title="MSE per sensor and method (Fig. 9)")
    ax[0, 0].legend(fontsize=8)
    section.figures.append(("s001_batch.png", fig, "Seed 001: per-sensor MSE, including the generalised (eq. 6) parameters."))
    section.notes.append("The simulated FSRs are continuous Preisach operators (ramp hysterons); the identified model is the "
                         "discrete one of the paper, so the CMA keeps its level quantisation and the continuous inverse "
                         "removes it.")
    return section
