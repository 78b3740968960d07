"""Simulated bench experiments written as bags of the topic contract."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Callable, Optional, Union

import numpy as np
import numpy.typing as npt

from .. import bags
from . import profiles
from .sensor import BridgeSimulator

__all__ = ["T0_NS", "SAMPLE_BAGS", "write_bench_bag", "simulate_bag", "make_sample_bags"]

#: A bag's path: a file (``.mcap``) or a bag directory.
PathLike = Union[str, os.PathLike[str]]

#: Start of simulated records (2025-01-01T00:00:00Z): a realistic epoch for stamps.
T0_NS = 1_735_689_600_000_000_000

#: The shipped sample bags: name -> (profile, rate in Hz, profile options).
#: Rates keep each bag under 5 MB; the needle insertion is at the 1 kHz sensor rate.
SAMPLE_BAGS: dict[str, tuple[str, float, dict[str, Any]]] = {
    "creep_5n": ("creep", 200.0, {"force_n": 5.0, "hold_s": 120.0, "rest_s": 60.0}),
    "sawtooth": ("sawtooth", 200.0, {}),
    "step_5n": ("step", 500.0, {"force_n": 5.0}),
    "sine_sweep": ("sine_sweep", 200.0, {"duration_s": 300.0}),
    "needle_insertion": ("needle_insertion", 1000.0, {}),
    "resolution": ("resolution", 50.0, {}),
}


def write_bench_bag(path: PathLike, t_s: npt.ArrayLike, force_n: npt.ArrayLike, voltage_v: npt.ArrayLike,
                    temperature_c: Optional[npt.ArrayLike] = None, t0_ns: int = T0_NS, temperature_every: int = 10,
                    directory: bool = False) -> Path:
    """Write a bench record (raw voltage, reference force, optional temperature) as a bag.

    Stamps and log times are ``t0_ns + t_s``; temperature is written every
    ``temperature_every`` samples when given (scalar or per-sample array).
    ``directory``: write the rosbag2 bag-directory form (``path/`` with ``metadata.yaml``).
    """
    stamps = t0_ns + np.round(np.asarray(t_s) * 1e9).astype(np.int64)
    with bags.BagWriter(path, directory=directory) as writer:
        writer.write_series(bags.BRIDGE_VOLTAGE, bags.JOINT_STATE, stamps, voltage_v)
        writer.write_series(bags.REFERENCE_FORCE, bags.WRENCH_STAMPED, stamps, force_n)
        if temperature_c is not None:
            temp = np.broadcast_to(np.asarray(temperature_c, dtype=float), stamps.shape)
            writer.write_series(bags.TEMPERATURE, bags.TEMPERATURE_MSG, stamps[::temperature_every], temp[::temperature_every])
    return Path(path)


def simulate_bag(path: PathLike, profile: str, rate_hz: float = 1000.0, simulator: Optional[BridgeSimulator] = None,
                 seed: int = 0, temperature_c: Optional[npt.ArrayLike] = 24.0, directory: bool = False,
                 **profile_kwargs: Any) -> Path:
    """Run a profile through the simulator (default: paper truth, 1 mV noise) and write the bag."""
    t, f = profiles.make_profile(profile, rate_hz=rate_hz, seed=seed, **profile_kwargs)
    sim = simulator if simulator is not None else BridgeSimulator(seed=seed)
    return write_bench_bag(path, t, f, sim.simulate(t, f), temperature_c, directory=directory)


def make_sample_bags(out_dir: PathLike, progress: Optional[Callable[[str], None]] = None,
                     directory: bool = False) -> list[Path]:
    """(Re)generate the shipped sample bags into ``out_dir``; returns their paths.

    Deterministic: fixed seeds and epoch, no wall-clock time in the content, so every run gives
    byte-identical files (tested against the shipped ones).
    """
    out = []
    for i, (name, (profile, rate, kwargs)) in enumerate(SAMPLE_BAGS.items()):
        if progress:
            progress(name)
        target = Path(out_dir) / (name if directory else f"{name}.mcap")
        out.append(simulate_bag(target, profile, rate_hz=rate, seed=i, directory=directory, **kwargs))
    return out
