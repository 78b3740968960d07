"""``polyforce evaluate``: run the experiments of the three seed papers and write one report.

Writes ``report.md`` (tables with the papers' numbers beside ours, figures,
settings) and ``report.json`` (every metric) into the output folder.
"""
from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Callable, Iterable, Optional, cast

import numpy as np
import numpy.typing as npt

from .. import bags
from ..model_file import default_model_path, load_model
from ..physics.metrics import error_summary
from ..record import load_record
from ..runtime.compensator import time_drifts, time_drifts_note
from ..workflows import compensate_record
from . import fsr_preisach, polymer_sarrus_sensor, thinfilm_muscle
from .common import Row, Section, Settings, figure, finite_or_text

#: Title of the section whose rows decide the exit code of ``polyforce evaluate``.
POLYMER_SENSOR = polymer_sarrus_sensor.TITLE
EXPERIMENTS = (("polymer_sarrus_sensor", polymer_sarrus_sensor.run), ("fsr_preisach", fsr_preisach.run),
               ("thinfilm_muscle", thinfilm_muscle.run))


def evaluate_bag(path: str | Path, model_path: Optional[str | Path] = None) -> Section:
    """Static gain vs compensation on a recorded bag with a reference force."""
    model = load_model(model_path or default_model_path())
    rec = load_record(path)  # need_reference: its force_n is set
    t, force, volts, warnings = rec.t_s, cast("npt.NDArray[np.float64]", rec.force_n), rec.voltage_v, list(rec.warnings)
    # what the node would output (auto-tare at start, gate, clamp), beside static gain zeroed the same way
    out = compensate_record(model.chain, t, volts, rec.temperature_c)
    used = out.used
    if not out.zeroing.startswith("zeroed"):
        warnings.append(f"bridge offset: {out.zeroing}")
    if not used.all():
        warnings.append(f"{int((~used).sum())} samples gave no force (see the compensator's rules)")
    note = time_drifts_note(time_drifts(model.chain))
    if note:
        warnings.append(note)
    t, force, static, comp = t[used], force[used], out.static_n[used], out.compensated_n[used]
    es, ec = error_summary(force, static), error_summary(force, comp)
    section = Section(f"Recorded bag {Path(path).name}", notes=[f"model: {model_path or default_model_path()}"] + warnings)
    for key, unit in (("rmse_n", "N"), ("max_abs_n", "N"), ("r2", "")):
        section.rows.append(Row(Path(path).name, key, unit, None, None, es[key], ec[key]))
    fig, ax = figure()
    ax[0, 0].plot(t, force, "r", lw=1.5, label="reference")
    ax[0, 0].plot(t, static, "k", lw=0.7, label=f"static gain, R² {es['r2']:.3f}")
    ax[0, 0].plot(t, comp, "b", lw=0.7, label=f"compensated, R² {ec['r2']:.4f}")
    ax[0, 0].set(xlabel="time [s]", ylabel="force [N]", title=f"Recorded bag {Path(path).name}")
    ax[0, 0].legend()
    section.figures.append((f"bag_{Path(path).stem}.png", fig, f"{Path(path).name}: reference, static gain and compensated."))
    return section


def _fmt(x: object) -> str:
    if x is None:
        return ""
    if isinstance(x, float):
        if not np.isfinite(x):
            return "> range" if x > 0 else "-inf"
        return f"{x:.6g}" if abs(x) < 1 and abs(x) > 0.99 else f"{x:.4g}"  # R² close to 1 keeps its digits
    return str(x).replace("|", "/")


def write_report(sections: Iterable[Section], settings: Settings, out_dir: str | Path,
                 progress: Optional[Callable[[str], object]] = None) -> tuple[Path, dict[str, Any]]:
    out = Path(out_dir)
    (out / "figures").mkdir(parents=True, exist_ok=True)
    import matplotlib.pyplot as plt

    lines = ["# polyforce_ros evaluation report", "",
             "Experiments of the three seed papers run on the embedded simulator (and on recorded bags, if given), "
             "with the papers' published numbers beside ours. *Baseline* is the uncompensated reading (static gain) "
             "or the paper's comparison method; *method* is the compensated reading or the paper's method.", "",
             "## Settings", "", "| setting | value |", "|---|---|"]
    lines += [f"| {k} | {v} |" for k, v in settings.as_dict().items()]
    lines += ["| simulated sensor truth | seed 000 eq. 5 Burgers parameters, bridge offset, white noise, ADC |", ""]
    data: dict[str, Any] = {"settings": settings.as_dict(), "sections": []}
    for section in sections:
        lines += [f"## {section.title}", "",
                  "| experiment | metric | unit | paper: baseline | paper: method | ours: baseline | ours: method "
                  "| meets paper | note |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for r in section.rows:
            verdict = {True: "yes", False: "**no**", None: ""}[r.passed]
            lines.append(f"| {r.experiment} | {r.metric} | {r.unit} | {_fmt(r.paper_baseline)} | {_fmt(r.paper_ours_method)} | "
                         f"{_fmt(r.ours_baseline)} | {_fmt(r.ours_method)} | {verdict} | {r.note} |")
        lines.append("")
        for note in section.notes:
            lines.append(f"- {note}")
        if section.notes:
            lines.append("")
        for name, fig, caption in section.figures:
            fig.tight_layout()
            fig.savefig(out / "figures" / name, dpi=100)
            plt.close(fig)
            lines += [f"![{caption}](figures/{name})", "", f"*{caption}*", ""]
        data["sections"].append({"title": section.title, "notes": section.notes,
                                 "figures": [f"figures/{n}" for n, _, _ in section.figures],
                                 "rows": [{k: finite_or_text(v) for k, v in vars(r).items()} for r in section.rows]})
    sensor_rows: list[dict[str, Any]] = next((s for s in data["sections"] if s["title"].startswith(POLYMER_SENSOR)),
                                             {"rows": []})["rows"]
    judged = [r for r in sensor_rows if r["passed"] is not None]
    data["polymer_sensor_all_met"] = bool(judged) and all(r["passed"] for r in judged)
    lines.insert(4, f"**{POLYMER_SENSOR}: the compensated sensor meets or beats {sum(r['passed'] for r in judged)} of "
                    f"{len(judged)} published figures.**\n")
    (out / "report.md").write_text("\n".join(lines) + "\n")
    (out / "report.json").write_text(json.dumps(data, indent=2, default=finite_or_text))
    return out / "report.md", data


def run_evaluation(out_dir: str | Path, settings: Settings = Settings(),
                   bag_paths: Iterable[str | Path] = (), model_path: Optional[str | Path] = None,
                   progress: Optional[Callable[[str], object]] = None) -> tuple[Path, dict[str, Any]]:
    sections = []
    for name, experiment in EXPERIMENTS:
        sections.append(experiment(settings))
        if progress:
            progress(f"{name} done")
    for path in bag_paths:
        sections.append(evaluate_bag(path, model_path))
        if progress:
            progress(f"{Path(path).name} done")
    return write_report(sections, settings, out_dir)


__all__ = ["run_evaluation", "evaluate_bag", "Settings", "bags"]
