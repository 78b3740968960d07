"""Offline workflows shared by the CLI and the nodes (no rclpy needed).

* :func:`calibrate_bag`: creep bag -> fitted, selected model -> YAML, never
  replacing a good model by a failed or worse one;
* :func:`compensate_bag`: copy a bag and add the compensated ``wrench`` topic;
* :func:`compensate_record`: a record through the runtime, beside static gain;
* :func:`clean_samples`: the runtime's sample rules as a mask (for records).
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence, cast

import numpy as np
import numpy.typing as npt

from . import bags, contract
from .model_file import SensorModel, load_model, now_iso, save_model
from .physics.chain import ModelError, SensorChain
from .physics.fitting import information_criteria
from .physics.identification import DEFAULT_CANDIDATES, select_model
from .physics.viscoelastic import ViscoelasticModel, simulate_deformation
from .record import load_record
from .runtime import Compensator, CompensatorConfig, SampleGate
from .runtime.compensator import WARN_COUNTERS
from .settings import setting

__all__ = ["clean_samples", "static_force_n", "static_and_compensated", "RecordCompensation", "compensate_record",
           "CalibrationResult", "rmse_of_model", "calibrate_record", "calibrate_bag", "compensate_bag", "runtime_warnings"]


def clean_samples(stamp_ns: npt.ArrayLike, values: npt.ArrayLike, receive_ns: Optional[npt.ArrayLike] = None,
                  config: CompensatorConfig = CompensatorConfig()) -> npt.NDArray[np.bool_]:
    """Mask of the samples the compensation runtime would use (:meth:`SampleGate.mask`).

    Dropped: non-finite values, ``|value| > config.input_limit_v``, implausible
    stamps (against ``receive_ns``, e.g. the log times), and stamps not later
    than the last used one (backwards or duplicate).
    """
    return SampleGate(config).mask(stamp_ns, values, receive_ns)


def static_force_n(chain: SensorChain, voltage_v: npt.ArrayLike, offset_v: float) -> npt.NDArray[np.float64]:
    """Force read by static gain: ``(V - offset_v) / G``, G the chain's static gain [V/N].

    Parameters
    ----------
    chain : SensorChain
        Sensor model (its static gain).
    voltage_v : (n,) array_like
        Bridge output [V].
    offset_v : float
        Bridge output at zero force [V].

    Returns
    -------
    (n,) ndarray
        Force [N].
    """
    return (np.asarray(voltage_v, dtype=np.float64) - offset_v) / chain.static_gain_v_per_n()


def static_and_compensated(chain: SensorChain, t_s: npt.NDArray[np.float64], voltage_v: npt.NDArray[np.float64],
                           offset_v: float) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Force read by static gain and by the chain's inverse, for a known bridge offset (model evaluation).

    The paper experiments use it: the offset is known there and no sample policy
    applies. Records and simulated runs go through :func:`compensate_record`.

    Parameters
    ----------
    chain : SensorChain
        Sensor model; not changed.
    t_s : (n,) ndarray
        Sample times [s].
    voltage_v : (n,) ndarray
        Bridge output [V].
    offset_v : float
        Bridge output at zero force [V].

    Returns
    -------
    static_n, compensated_n : (n,) ndarray
        Force [N] by static gain and by the chain's inverse.
    """
    return static_force_n(chain, voltage_v, offset_v), chain.with_offset(offset_v).backward(t_s, voltage_v)


@dataclass(frozen=True)
class RecordCompensation:
    """A record through the runtime (:func:`compensate_record`)."""

    used: npt.NDArray[np.bool_]             #: (n,) bool: samples that gave a force
    static_n: npt.NDArray[np.float64]       #: (n,) force by static gain [N]; NaN where not used
    compensated_n: npt.NDArray[np.float64]  #: (n,) force by the compensator [N]; NaN where not used
    offset_v: float            #: bridge output at zero force used [V]
    zeroing: str               #: how the offset was found (the runtime's auto-tare status)


def compensate_record(chain: SensorChain, t_s: npt.ArrayLike, voltage_v: npt.ArrayLike,
                      temperature_c: Optional[npt.ArrayLike] = None,
                      config: CompensatorConfig = CompensatorConfig()) -> RecordCompensation:
    """What the compensation node outputs for a record once zeroed, beside the static-gain reading.

    Two passes through the runtime's :class:`Compensator`, with the record's
    times as both stamps and receive clock. The first steps the samples until
    the node's auto-tare rule has decided (the mean of the first ``auto_tare_s``
    if the sensor rests there, else the model's offset); the second runs the
    whole record with that offset and auto-tare off, as a sensor that was zeroed
    at rest before the record. The static reading uses the same offset, so both
    methods are zeroed the same way.

    Parameters
    ----------
    chain : SensorChain
        Sensor model; not changed.
    t_s : (n,) array_like
        Sample times [s], increasing.
    voltage_v : (n,) array_like
        Bridge output [V].
    temperature_c : (n,) array_like, optional
        A temperature reading [degC] taken before each sample (thermal models). A record's
        temperature is interpolated onto its samples; ``polyforce compensate`` instead takes a
        bag's messages in order of arrival, as the node does.
    config : CompensatorConfig
        The sample policy (the node's defaults unless given).

    Returns
    -------
    RecordCompensation
        Used samples, static and compensated force [N], the offset [V] and how it was found.
    """
    t = np.asarray(t_s, dtype=np.float64)
    volts = np.asarray(voltage_v, dtype=np.float64)
    stamp_ns = np.round((t - t[0]) * 1e9).astype(np.int64) if t.size else np.zeros(0, dtype=np.int64)
    zeroing = Compensator(chain, config)
    for i in range(stamp_ns.size):  # until the auto-tare rule has decided (at once when it is off)
        if not zeroing.auto_tare_pending:
            break
        zeroing.step(int(stamp_ns[i]), float(volts[i]))
    zeroed_how = zeroing.auto_tare_status
    if zeroing.auto_tare_pending:
        zeroed_how = (f"not zeroed: the sensor did not rest for {config.auto_tare_s} s in the record "
                      f"({zeroing.auto_tare_reason or 'too short'}); the model's offset is used")
    offset_v = zeroing.offset_v
    compensator = Compensator(chain.with_offset(offset_v), replace(config, auto_tare=False))
    used, force = compensator.run(stamp_ns, volts, temperature_c=temperature_c)
    static = static_force_n(chain, volts, offset_v)
    return RecordCompensation(used, np.where(used, static, np.nan), np.where(used, force, np.nan), offset_v,
                              zeroed_how)


@dataclass(frozen=True)
class CalibrationConfig:
    """Calibration settings, each declared once (:func:`~polyforce_ros.settings.setting`): calibration_node
    declares a parameter of each, ``polyforce calibrate`` takes its defaults from them."""

    candidates: tuple[str, ...] = setting(DEFAULT_CANDIDATES, "Model types to fit; the lowest BIC wins")
    min_r2: float = setting(0.9, "A best fit below this R^2 is not written", 0.0, 1.0)


@dataclass
class CalibrationResult:
    """Outcome of a calibration: whether the model file was written and why, and every fit."""
    written: bool
    reason: str
    output: str
    fits: list[dict[str, Any]] = field(default_factory=list)  # summaries, best first
    previous_rmse_v: float | None = None
    warnings: list[str] = field(default_factory=list)
    sensor_serial: str | None = None  #: serial of the calibrated sensor, as written into the provenance

    def summary(self) -> dict[str, Any]:
        """JSON-ready outcome: written or not and why, the output path, every fit, the previous RMSE [V], warnings,
        the sensor serial."""
        return {"written": self.written, "reason": self.reason, "output": self.output, "fits": self.fits,
                "previous_rmse_v": self.previous_rmse_v, "warnings": self.warnings, "sensor_serial": self.sensor_serial}


def rmse_of_model(model: ViscoelasticModel, t_s: npt.NDArray[np.float64], force_n: npt.NDArray[np.float64],
                  voltage_v: npt.NDArray[np.float64]) -> float:
    """RMS voltage error (V) of a model on a record, offset fitted by the mean."""
    residual = voltage_v - simulate_deformation(model, t_s, force_n)
    residual = residual - residual.mean()
    return float(np.sqrt(np.mean(residual * residual)))


def calibrate_record(t_s: npt.NDArray[np.float64], force_n: npt.NDArray[np.float64], voltage_v: npt.NDArray[np.float64],
                     output: str | Path, source: str | Path, candidates: Sequence[str] = CalibrationConfig.candidates,
                     min_r2: float = CalibrationConfig.min_r2, progress: Optional[Callable[[str], Any]] = None,
                     warnings: Iterable[str] = (), sensor_serial: Optional[str] = None) -> CalibrationResult:
    """Fit and select a model; write it to ``output`` only if it is good and better.

    The new model is written (atomically, the old file kept as ``.prev``) when
    its fit has R^2 >= ``min_r2`` and, if ``output`` already holds a valid
    model, it explains this record better than that model by the Bayesian
    information criterion. Comparing raw errors would not do: a model fitted
    to a record always reproduces that record at least as well as any other,
    noise included. BIC charges the new fit for its p + 1 free parameters and
    the existing model for its one (the offset).
    ``sensor_serial`` names the sensor the record was taken on: it goes into the
    provenance (``sensor_serial``), where compensation_node compares it with the
    serial the live device reports. A model there whose provenance names another
    sensor is no standard for this one: the new fit replaces it when good.
    Raises ``ValueError`` when no fit is possible (e.g. no creep segment).
    """
    output = Path(output).expanduser()
    sensor_serial = str(sensor_serial).strip() if sensor_serial is not None else ""
    selection = select_model(t_s, force_n, voltage_v, candidates=candidates, progress=progress)
    best = selection.best
    fits = [f.summary() for f in selection.fits]
    result = CalibrationResult(False, "", str(output), fits, warnings=list(warnings),
                               sensor_serial=sensor_serial or None)
    if not np.isfinite(best.r2) or best.r2 < min_r2:
        result.reason = f"best fit ({best.kind}) has R^2 {best.r2:.4f} < {min_r2}: previous model kept"
        return result
    previous: Optional[ViscoelasticModel] = None  # the model already at output
    previous_serial = ""  # the sensor its provenance names
    if output.exists():
        try:
            previous_model = load_model(output)
        except ModelError:
            previous_model = None
        previous = previous_model.chain.viscoelastic if previous_model is not None else None
        if previous_model is not None:
            previous_serial = str(previous_model.provenance.get("sensor_serial") or "").strip()
        if previous is not None and not (sensor_serial and previous_serial and previous_serial != sensor_serial):
            n = len(voltage_v)  # both criteria over every sample of this record
            rmse_new = rmse_of_model(best.model, t_s, force_n, voltage_v)
            result.previous_rmse_v = rmse_of_model(previous, t_s, force_n, voltage_v)
            bic_new = information_criteria(n * rmse_new**2, n, len(best.parameters) + 1)[1]
            bic_old = information_criteria(n * result.previous_rmse_v**2, n, 1)[1]
            if bic_old <= bic_new:
                result.reason = (f"existing model explains this record as well or better (RMSE "
                                 f"{result.previous_rmse_v:.4e} V vs {rmse_new:.4e} V, BIC {bic_old:.1f} <= {bic_new:.1f}): kept")
                return result
    provenance = {
        "source": str(source),
        "created": now_iso(),
        "method": "creep fit with measured force history, model selected by BIC",
        "segments": len(selection.segments),
        "fit": {"r2": best.r2, "rmse_v": best.rmse_v, "bic": best.bic, "stderr": best.stderr},
        "candidates": {f.kind: {"bic": f.bic, "r2": f.r2} for f in selection.fits},
    }
    if sensor_serial:
        provenance["sensor_serial"] = sensor_serial
    save_model(output, SensorModel(SensorChain.from_model(best.model, offset_v=best.offset_v), provenance))
    result.written = True
    result.reason = f"{best.kind} written (R^2 {best.r2:.4f}, RMSE {best.rmse_v:.3e} V)"
    if sensor_serial:
        result.reason += f" for sensor {sensor_serial}"
        if previous is not None and previous_serial and previous_serial != sensor_serial:
            result.reason += f", in place of the model of sensor {previous_serial}"
    return result


def calibrate_bag(bag_path: str | Path, output: str | Path, **kwargs: Any) -> CalibrationResult:
    """:func:`calibrate_record` of the creep bag at ``bag_path`` (keyword arguments as there)."""
    rec = load_record(bag_path)  # need_reference: its force_n is set
    return calibrate_record(rec.t_s, cast("npt.NDArray[np.float64]", rec.force_n), rec.voltage_v, output, source=bag_path,
                            warnings=rec.warnings, **kwargs)


def compensate_bag(in_path: str | Path, out_path: str | Path, model: SensorModel,
                   config: CompensatorConfig = CompensatorConfig(), directory: bool = False) -> tuple[int, list[str]]:
    """Copy every message of ``in_path`` to ``out_path`` and add ``/polyforce/wrench``.

    The raw samples go through the same :class:`Compensator` as in
    compensation_node (log time as the receive clock), so the wrench equals the
    node's for the same stream: each used raw sample gets a wrench with the
    same header stamp and log time. Returns the number of wrench messages
    written and the warnings (reader: truncation, corrupt chunks; runtime:
    dropped samples).
    """
    bag = bags.read_bag(in_path, topics=[contract.BRIDGE_VOLTAGE], optional=[contract.TEMPERATURE])
    raw = bag[contract.BRIDGE_VOLTAGE]
    if contract.WRENCH in bag.types:
        raise bags.BagError(f"{in_path} already holds {contract.WRENCH}")
    volts = raw.fields.get("position", np.zeros(len(raw)))
    compensator = Compensator(model.chain, config)
    temperature_log = None
    if contract.TEMPERATURE in bag.types:  # taken in order of arrival, as by the node
        temperature_log = (bag[contract.TEMPERATURE].log_time_ns, bag[contract.TEMPERATURE].fields["temperature"])
    used, force = compensator.run(raw.stamp_ns, volts, raw.log_time_ns, temperature_log=temperature_log)
    if not used.any():
        raise bags.BagError(f"{in_path}: no usable samples on {contract.BRIDGE_VOLTAGE}")
    warnings = list(bag.warnings) + runtime_warnings(compensator.counts)
    if compensator.time_drifts_note:
        warnings.append(compensator.time_drifts_note)
    if temperature_log is None and model.chain.needs_temperature:
        warnings.append(f"the model follows temperature but {in_path} holds no {contract.TEMPERATURE}: not corrected")
    with bags.BagWriter(out_path, directory=directory) as writer:
        bags.copy_messages(in_path, writer)  # survives truncation and corrupt chunks, like read_bag
        writer.write_series(contract.WRENCH, contract.WRENCH_STAMPED, raw.stamp_ns[used], force[used],
                            log_time_ns=raw.log_time_ns[used], frame_id=contract.FRAME_ID)
    return int(used.sum()), warnings


def runtime_warnings(counts: Mapping[str, int]) -> list[str]:
    """One line per nonzero warning counter of a :class:`Compensator` (the list the node's diagnostics WARN on)."""
    return [f"{counts[name]} {'stamp gaps over gap_warn_s' if name == 'gaps' else 'samples ' + name.replace('_', ' ')}"
            for name in WARN_COUNTERS if counts.get(name)]
