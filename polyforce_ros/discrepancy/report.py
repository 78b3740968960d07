"""`polyforce diagnose`: read a bench bag, diagnose it, write JSON, report and the augmented model."""
from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Callable, Collection, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from ..model_file import SensorModel, now_iso, save_model
from ..record import Record, load_record
from .engine import Diagnosis, diagnose, fold_of

__all__ = ["write_report", "run"]

#: A path as the CLI gives it.
PathLike = Union[str, Path]


def write_report(diag: Diagnosis, rec: Record, out_dir: PathLike, bag_name: str = "") -> Path:
    """Write ``report.md`` and its figures (``figures/*.png``) of a diagnosis into ``out_dir``; returns the report's path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if rec.force_n is None:
        raise ValueError("record has no reference force")
    force_n = rec.force_n
    out = Path(out_dir)
    (out / "figures").mkdir(parents=True, exist_ok=True)
    t = rec.t_s
    named = ", ".join(diag.missing_effects) or diag.missing_effect
    before = rec.voltage_v - diag.simulated_before_v
    after = rec.voltage_v - diag.simulated_after_v

    def over_the_reference(traces: Sequence[tuple[npt.ArrayLike, str, float, str]], ylabel: str, title: str,
                           name: str) -> None:
        """A figure of ``traces`` (y, style, width, label) above the reference force, saved as figures/``name``."""
        fig, ax = plt.subplots(2, 1, figsize=(11, 6), sharex=True)
        for y, style, width, label in traces:
            ax[0].plot(t, y, style, lw=width, label=label)
        ax[0].set(ylabel=ylabel, title=title)
        ax[0].legend(fontsize=8)
        ax[1].plot(t, force_n, "g", lw=0.8)
        ax[1].set(xlabel="time [s]", ylabel="reference force [N]")
        fig.tight_layout()
        fig.savefig(out / "figures" / name, dpi=100)
        plt.close(fig)

    over_the_reference(
        [(rec.voltage_v, "k", 0.8, "measured"),
         (diag.simulated_before_v, "r", 0.8, f"base {diag.base} (RMSE {diag.rmse_before:.2e} V)"),
         (diag.simulated_after_v, "b--", 0.8, f"with {named} (RMSE {diag.rmse_after:.2e} V)")],
        "bridge output [V]", f"Out-of-sample predictions ({diag.folds} folds of interleaved time blocks, each block "
        "predicted by the fit that left its fold out)", "measured_vs_simulated.png")

    conc = diag.localisation["concentration"]
    top = max(conc, key=lambda k: conc[k]["rms_ratio"]) if conc else None
    fig, ax = plt.subplots(figsize=(11, 4))
    if top is not None:
        mask = diag.localisation["masks"][top]
        ax.fill_between(t, 0, 1, where=mask, transform=ax.get_xaxis_transform(), color="orange", alpha=0.25,
                        label=f"{top.replace('_', ' ')} (residual x{conc[top]['rms_ratio']:.2f})")
    ax.plot(t, before, "r", lw=0.6, label=f"base {diag.base}")
    ax.plot(t, after, "b", lw=0.6, label=f"with {named}")
    # block boundaries as the diagnosis cut them, each block labelled with its fold
    fold = fold_of(t, t[0], t[-1] - t[0], diag.folds, diag.blocks_per_fold)
    starts = np.r_[0, np.flatnonzero(np.diff(fold)) + 1]
    for a, b in zip(starts, np.r_[starts[1:], t.size]):
        if a:
            ax.axvline(t[a], color="k", ls=":", lw=0.8)
        ax.text(0.5 * (t[a] + t[b - 1]), 1.0, str(fold[a] + 1), transform=ax.get_xaxis_transform(), ha="center",
                va="bottom", fontsize=7)
    ax.axhspan(-diag.noise_floor_v, diag.noise_floor_v, color="grey", alpha=0.3, label="noise floor (+-1 sigma)")
    ax.set(xlabel="time [s]", ylabel="residual, measured - simulated [V]", title="Out-of-sample residual over time")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "figures" / "residual.png", dpi=100)
    plt.close(fig)

    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    names = sorted(conc, key=lambda k: -conc[k]["rms_ratio"])
    axes[0].barh([n.replace("_", " ") for n in names], [conc[n]["rms_ratio"] for n in names], color="tab:orange")
    axes[0].axvline(1.0, color="k", lw=0.8)
    axes[0].set(xlabel="RMS residual inside / overall [-]", title="Where the residual concentrates")
    corr = diag.localisation["correlation"]
    axes[1].barh([n.replace("_", " ") for n in corr], list(corr.values()), color="tab:blue")
    axes[1].set(xlabel="correlation with the residual [-]", title="What the residual follows", xlim=(-1, 1))
    fig.tight_layout()
    fig.savefig(out / "figures" / "localisation.png", dpi=100)
    plt.close(fig)

    base_q, saved_q = diag.newtons["base"], diag.newtons["saved"]
    over_the_reference(
        [(diag.compensated_before_n - force_n, "r", 0.6,
          f"base {diag.base} (RMSE {base_q['rmse_n']:.3f} N, R2 {base_q['r2']:.4f})"),
         (diag.compensated_after_n - force_n, "b", 0.6,
          f"saved model (RMSE {saved_q['rmse_n']:.3f} N, R2 {saved_q['r2']:.4f})")],
        "compensated - reference [N]",
        "Force error at the haptic master (each block compensated by the model fitted without it)", "force_error.png")

    data = diag.to_json()
    u = diag.unexplained
    def saved(effect: str) -> str:
        text = diag.saved_text(effect)
        return "; " + text if text else ""

    named = ", ".join(f"`{e}` (confidence {diag.confidences[e]:.0%}{saved(e)})" for e in diag.missing_effects)
    lines = [f"# Discrepancy diagnosis {bag_name}", "",
             f"**Missing effects: {named or '`' + diag.missing_effect + '`'}** "
             f"(base `{diag.base}`). Out-of-sample RMSE {diag.rmse_before:.3e} V -> {diag.rmse_after:.3e} V "
             f"(x{diag.rmse_before / max(diag.rmse_after, 1e-300):.1f}); noise floor estimated from the data "
             f"{diag.noise_floor_v:.3e} V. Validation: {data['validation']}.", ""]
    if u["present"]:
        lines += [f"**Unexplained:** a structured residual of {u['rms_v']:.3e} V remains "
                  f"(Ljung-Box p = {u['ljung_box_p']:.1e}), {u['rms_v'] / max(u['noise_floor_v'], 1e-300):.1f}x the noise "
                  f"floor; no effect of the catalogue describes it. Where: {u['where']}.", ""]
    lines += ["## Compensated force (what the haptic master receives)", "",
              "| model | RMSE [N] | RMSE [% FS] | largest error [N] | largest [% FS] | R2 | noise gain [N/V] |",
              "|---|---|---|---|---|---|---|"]
    runtime_q = diag.newtons.get("saved_runtime") or {}
    for label, q in (("base", base_q), ("saved", saved_q), ("saved, as the runtime runs it (time drifts left out)",
                                                             runtime_q)):
        if not q:
            continue
        lines.append(f"| {label} | {q['rmse_n']:.4f} | {q['rmse_percent_full_scale']:.2f} | {q['max_error_n']:.4f} | "
                     f"{q['max_error_percent_full_scale']:.2f} | {q['r2']:.4f} | {q['noise_gain_n_per_v']:.3g} |")
    if diag.newtons.get("lag_bandwidth"):
        bw = diag.newtons["lag_bandwidth"]
        lines += ["", f"The sensor lag is inverted with a bandwidth: filter time {bw['filter_factor']:g} x its time "
                      f"constant, roll-off of order {bw['filter_order']}, added delay {1e3 * bw['added_delay_s']:.1f} ms."]
    if runtime_q:
        lines += ["", f"As the runtime runs it by default, the saved model leaves its time drifts "
                      f"({', '.join(runtime_q['time_drifts_left_out'])}) out: this record's drift stays in the force "
                      f"({runtime_q['drift_in_force_rms_n']:.4f} N rms); live, the start-up zeroing and ~/tare set the "
                      "zero, and drift_tracking follows it at rest."]
    if diag.newtons.get("rejected"):
        lines += ["", f"Not saved: {', '.join(diag.newtons['rejected']['effects'])} (they compensate the force worse "
                      "than the base)."]
    lines += ["", "![force error](figures/force_error.png)", ""]
    for name, why in diag.skipped.items():
        lines.append(f"- `{name}` not tested: {why}")
    lines += ["", "## Evidence", ""]
    lines += [f"- {e}" for e in diag.evidence]
    lines += ["", "## Candidates (forward selection)", "",
              "| step | effect | variant | out-of-sample RMSE [V] (fit rate) | fitting RMSE [V] | folds improved | "
              "share of excess removed | BIC | accepted |", "|---|---|---|---|---|---|---|---|---|"]
    for c in data["candidates"]:
        lines.append(f"| {c['step']} | {c['effect']} | {c['variant']} | {c['rmse']:.3e} | {c['rmse_fit']:.3e} | "
                     f"{c['confidence']:.0%} | {c['excess_share']:+.2f} | {c['criterion']:.1f} | "
                     f"{'yes' if c['accepted'] else ''} |")
    lines += ["", "![measured vs simulated](figures/measured_vs_simulated.png)", "", "![residual](figures/residual.png)", "",
              "![localisation](figures/localisation.png)", ""]
    (out / "report.md").write_text("\n".join(lines) + "\n")
    return out / "report.md"


def run(bag: PathLike, base: str, json_path: Optional[PathLike] = None, report_dir: Optional[PathLike] = None,
        save_model_path: Optional[PathLike] = None, progress: Optional[Callable[[str], None]] = None, n_folds: int = 5,
        effects: Optional[Collection[str]] = None, sensor_serial: Optional[str] = None) -> tuple[Diagnosis, dict[str, Any]]:
    """``polyforce diagnose``: load the bag, diagnose it, write the JSON (``json_path``), the report (``report_dir``)
    and the model with every named effect (``save_model_path``, its provenance carrying the figures); returns the
    diagnosis and its JSON data."""
    rec = load_record(bag)
    diag = diagnose(rec, base=base, n_folds=n_folds, effects=effects, progress=progress)
    data = diag.to_json()
    data["bag"] = str(bag)
    data["record_warnings"] = list(rec.warnings)
    if json_path:
        Path(json_path).parent.mkdir(parents=True, exist_ok=True)
        Path(json_path).write_text(json.dumps(data, indent=2, default=float))
    if report_dir:
        write_report(diag, rec, report_dir, Path(bag).name)
    if save_model_path:
        provenance = {"source": str(bag), "created": now_iso(), "method": f"polyforce diagnose --base {base}",
                      "missing_effect": diag.missing_effect, "missing_effects": list(diag.missing_effects),
                      "confidence": {k: float(v) for k, v in diag.confidences.items()},
                      "rmse_before_v": diag.rmse_before, "rmse_after_v": diag.rmse_after,
                      "noise_floor_v": diag.noise_floor_v,
                      "unexplained": {"present": bool(diag.unexplained["present"]), "rms_v": float(diag.unexplained["rms_v"])},
                      "compensated_force": {k: {m: v for m, v in diag.newtons[k].items() if m != "noise_gain"}
                                            for k in ("base", "saved", "saved_runtime") if k in diag.newtons},
                      "noise_gain": diag.newtons["saved"]["noise_gain"]}
        if sensor_serial and str(sensor_serial).strip():  # compensation_node compares it with the live device's
            provenance["sensor_serial"] = str(sensor_serial).strip()
        save_model(save_model_path, SensorModel(diag.chain, provenance))
    return diag, data
