"""`polyforce diagnose`: read a bench bag, diagnose it, write JSON, report and the augmented model."""
from __future__ import annotations

import json
from pathlib import Path

from ..model_file import SensorModel, now_iso, save_model
from ..record import load_record
from .engine import diagnose


def write_report(diag, rec, out_dir, bag_name=""):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out_dir)
    (out / "figures").mkdir(parents=True, exist_ok=True)
    t = rec.t_s
    val = t >= diag.split_s
    before = rec.voltage_v - diag.base_fit.simulated_v
    after = rec.voltage_v - diag.chosen.simulated_v

    fig, ax = plt.subplots(2, 1, figsize=(11, 6), sharex=True)
    ax[0].plot(t[val], rec.voltage_v[val], "k", lw=0.8, label="measured")
    ax[0].plot(t[val], diag.base_fit.simulated_v[val], "r", lw=0.8, label=f"base {diag.base} (RMSE {diag.rmse_before:.2e} V)")
    ax[0].plot(t[val], diag.chosen.simulated_v[val], "b--", lw=0.8,
               label=f"with {diag.missing_effect} (RMSE {diag.rmse_after:.2e} V)")
    ax[0].set(ylabel="bridge output [V]", title="Validation part (never fitted): measured vs simulated")
    ax[0].legend(fontsize=8)
    ax[1].plot(t[val], rec.force_n[val], "g", lw=0.8)
    ax[1].set(xlabel="time [s]", ylabel="reference force [N]")
    fig.tight_layout()
    fig.savefig(out / "figures" / "measured_vs_simulated.png", dpi=100)
    plt.close(fig)

    conc = diag.localisation["concentration"]
    top = max(conc, key=lambda k: conc[k]["rms_ratio"]) if conc else None
    fig, ax = plt.subplots(figsize=(11, 4))
    if top is not None:
        mask = diag.localisation["masks"][top]
        ax.fill_between(t, 0, 1, where=mask, transform=ax.get_xaxis_transform(), color="orange", alpha=0.25,
                        label=f"{top.replace('_', ' ')} (residual x{conc[top]['rms_ratio']:.2f})")
    ax.plot(t, before, "r", lw=0.6, label=f"base {diag.base}")
    ax.plot(t, after, "b", lw=0.6, label=f"with {diag.missing_effect}")
    ax.axvline(diag.split_s, color="k", ls="--", lw=1, label="fit | validation")
    ax.set(xlabel="time [s]", ylabel="residual, measured - simulated [V]", title="Residual over time")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "figures" / "residual.png", dpi=100)
    plt.close(fig)

    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    names = sorted(conc, key=lambda k: -conc[k]["rms_ratio"])
    ax[0].barh([n.replace("_", " ") for n in names], [conc[n]["rms_ratio"] for n in names], color="tab:orange")
    ax[0].axvline(1.0, color="k", lw=0.8)
    ax[0].set(xlabel="RMS residual inside / overall [-]", title="Where the base model's residual concentrates")
    corr = diag.localisation["correlation"]
    ax[1].barh([n.replace("_", " ") for n in corr], list(corr.values()), color="tab:blue")
    ax[1].set(xlabel="correlation with the residual [-]", title="What the residual follows", xlim=(-1, 1))
    fig.tight_layout()
    fig.savefig(out / "figures" / "localisation.png", dpi=100)
    plt.close(fig)

    data = diag.to_json()
    base_bic = next(c["criterion"] for c in data["candidates"] if c["effect"] == "none")
    lines = [f"# Discrepancy diagnosis {bag_name}", "",
             f"**Missing effect: `{diag.missing_effect}`** (base `{diag.base}`). Validation RMSE "
             f"{diag.rmse_before:.3e} V -> {diag.rmse_after:.3e} V (x{diag.rmse_before / diag.rmse_after:.1f}); "
             f"the validation part starts at {diag.split_s:.1f} s and was never fitted.", "", "## Evidence", ""]
    lines += [f"- {e}" for e in diag.evidence]
    lines += ["", "## Candidates", "", "| effect | validation RMSE [V] | fitting RMSE [V] | BIC vs base | parameters |", "|---|---|---|---|---|"]
    for c in data["candidates"]:
        lines.append(f"| {c['effect']} | {c['rmse']:.3e} | {c['rmse_fit']:.3e} | {c['criterion'] - base_bic:+.1f} | {c['n_params']} |")
    lines += ["", "![measured vs simulated](figures/measured_vs_simulated.png)", "", "![residual](figures/residual.png)", "",
              "![localisation](figures/localisation.png)", ""]
    (out / "report.md").write_text("\n".join(lines) + "\n")
    return out / "report.md"


def run(bag, base, json_path=None, report_dir=None, save_model_path=None, fit_fraction=0.6, progress=None):
    rec = load_record(bag)
    diag = diagnose(rec, base=base, fit_fraction=fit_fraction, progress=progress)
    data = diag.to_json()
    data["bag"] = str(bag)
    if json_path:
        Path(json_path).parent.mkdir(parents=True, exist_ok=True)
        Path(json_path).write_text(json.dumps(data, indent=2))
    if report_dir:
        write_report(diag, rec, report_dir, Path(bag).name)
    if save_model_path:
        provenance = {"source": str(bag), "created": now_iso(), "method": f"polyforce diagnose --base {base}",
                      "missing_effect": diag.missing_effect, "rmse_before_v": diag.rmse_before, "rmse_after_v": diag.rmse_after}
        save_model(save_model_path, SensorModel(diag.chosen.chain, provenance))
    return diag, data
