"""What a bench record is, and the one way to make one from a bag or from live samples.

A :class:`Record` is the raw bridge voltage on its own stamps, with the reference
force (and the temperature, when recorded) interpolated onto them. Calibration,
diagnosis, the evaluation report and live calibration all use it; the samples
kept are those the compensation runtime would use
(:func:`polyforce_ros.workflows.clean_samples`).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterable, Optional, cast

import numpy as np
import numpy.typing as npt

from . import bags, contract
from .runtime import CompensatorConfig, SampleGate

__all__ = ["Record", "load_record", "record_from_bag", "record_from_samples", "resample_onto", "REFERENCE_GATE"]

#: Gate settings for the reference force and temperature: not a bridge voltage, so no input limit.
REFERENCE_GATE = CompensatorConfig(input_limit_v=np.inf)


@dataclass(frozen=True)
class Record:
    """A bench record on the raw sample stamps.

    Attributes
    ----------
    t_s : (n,) seconds since the first kept raw sample.
    force_n : (n,) reference force, N (None when not asked for).
    voltage_v : (n,) raw bridge output, V.
    temperature_c : (n,) degC, or None when not recorded.
    stamp_ns : (n,) header stamps of the raw samples, ns (None for synthetic records).
    warnings : what the reader and the sample rules dropped or could not read.
    """

    t_s: npt.NDArray[np.float64]
    force_n: Optional[npt.NDArray[np.float64]]
    voltage_v: npt.NDArray[np.float64]
    temperature_c: Optional[npt.NDArray[np.float64]] = None
    stamp_ns: Optional[npt.NDArray[np.int64]] = None
    warnings: tuple[str, ...] = ()

    def aux(self) -> dict[str, Optional[npt.NDArray[np.float64]]]:
        """Auxiliary signals for sensor chains (thermal elements)."""
        return {"temperature_c": self.temperature_c}


def resample_onto(t_s: npt.NDArray[np.float64], t0_ns: int, stamp_ns: npt.ArrayLike, values: npt.ArrayLike,
                  what: str) -> npt.NDArray[np.float64]:
    """Samples of another topic, cleaned by the runtime's rules (no input limit) and linearly
    interpolated onto ``t_s`` (seconds since ``t0_ns``)."""
    stamps, vals = np.asarray(stamp_ns, dtype=np.int64), np.asarray(values, dtype=np.float64)
    keep: npt.NDArray[np.bool_] = SampleGate(REFERENCE_GATE).mask(stamps, vals)
    if keep.sum() < 2:
        raise bags.BagError(f"no usable samples on {what}")
    return np.interp(t_s, (stamps[keep] - t0_ns) * 1e-9, vals[keep])


def record_from_samples(raw_stamp_ns: npt.ArrayLike, raw_v: npt.ArrayLike,
                        ref_stamp_ns: Optional[npt.ArrayLike] = None, ref_force_n: Optional[npt.ArrayLike] = None,
                        temp_stamp_ns: Optional[npt.ArrayLike] = None, temp_c: Optional[npt.ArrayLike] = None,
                        raw_receive_ns: Optional[npt.ArrayLike] = None,
                        source: str = "record", warnings: Iterable[str] = ()) -> Record:
    """A :class:`Record` from the samples of each topic (arrays of stamps and values).

    Raw samples pass the runtime's gate (``raw_receive_ns``: their log or arrival
    times, for the stamp plausibility check); the reference and temperature are
    interpolated onto the kept raw stamps. ``BagError`` when a topic has too few
    usable samples.
    """
    raw_stamps, raw_volts = np.asarray(raw_stamp_ns, dtype=np.int64), np.asarray(raw_v, dtype=np.float64)
    keep: npt.NDArray[np.bool_] = SampleGate().mask(raw_stamps, raw_volts, raw_receive_ns)
    if not keep.any():
        raise bags.BagError(f"{source}: no usable samples on {contract.BRIDGE_VOLTAGE}")
    warnings = list(warnings)
    if (~keep).any():
        warnings.append(f"{int((~keep).sum())} raw samples dropped (non-finite, out of range, implausible, backwards "
                        "or duplicate stamps)")
    stamps, volts = raw_stamps[keep], raw_volts[keep]
    t0 = int(stamps[0])
    t_s = ((stamps - t0) * 1e-9).astype(np.float64, copy=False)  # float64 already: typed, not copied
    # a topic's values are given with its stamps
    force = None if ref_stamp_ns is None else resample_onto(t_s, t0, ref_stamp_ns, cast(npt.ArrayLike, ref_force_n),
                                                            f"{source}: {contract.REFERENCE_FORCE}")
    temp = None if temp_stamp_ns is None else resample_onto(t_s, t0, temp_stamp_ns, cast(npt.ArrayLike, temp_c),
                                                            f"{source}: {contract.TEMPERATURE}")
    return Record(t_s, force, volts, temp, stamps, tuple(warnings))


def record_from_bag(bag: bags.BagData, bag_path: str | Path, need_reference: bool = True) -> Record:
    """The :class:`Record` of a read bag (temperature included when it holds two samples or more)."""
    raw = bag[contract.BRIDGE_VOLTAGE]
    if len(raw) == 0 or "position" not in raw.fields:
        raise bags.BagError(f"{bag_path}: no usable samples on {contract.BRIDGE_VOLTAGE}")
    ref = bag[contract.REFERENCE_FORCE] if need_reference else None
    temp: Any = bag.topics.get(contract.TEMPERATURE)  # a TopicData or None; used only when has_temp
    has_temp = temp is not None and len(temp) >= 2
    return record_from_samples(
        raw.stamp_ns, raw.fields["position"],
        ref.stamp_ns if ref is not None else None,
        (ref.fields.get("force_z", np.zeros(len(ref))) if ref is not None else None),
        temp.stamp_ns if has_temp else None, temp.fields["temperature"] if has_temp else None,
        raw_receive_ns=raw.log_time_ns, source=str(bag_path), warnings=bag.warnings)


def load_record(bag_path: str | Path, need_reference: bool = True) -> Record:
    """:func:`record_from_bag` of the bag at ``bag_path`` (one read)."""
    topics = [contract.BRIDGE_VOLTAGE] + ([contract.REFERENCE_FORCE] if need_reference else [])
    return record_from_bag(bags.read_bag(bag_path, topics=topics, optional=[contract.TEMPERATURE]), bag_path, need_reference)
