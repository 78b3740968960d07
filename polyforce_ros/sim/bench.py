"""Bench experiments with hidden effects (tests and the confusion matrix of the discrepancy workflow).

A bench record is a random load profile (holds, rests, ramps, reversals, fast
steps, short sine bursts) applied to a sensor whose truth is a base
viscoelastic model with random parameters (+-30 % around the base's) plus
any number of hidden effects. Each effect is drawn from one of its
*families* (:mod:`.truths`) with random parameters; none is the element the
engine fits. Families marked ``held_out`` and the seeds of the held-out split
(:data:`~.truths.SPLITS`) are never used while tuning the engine.
Effects simulated beside the families (:data:`EXTRA_EFFECTS`) are either shapes
of a catalogue effect that no family draws, or out of the catalogue
(:data:`OUT_OF_CATALOGUE`: no catalogue effect describes them at all). Temperature always varies (independently of
the load), so its mere presence gives nothing away; :func:`bench_record`
adds real recording conditions (rate, stamp jitter, dropped blocks, no
temperature topic, a reference load cell with its own noise).
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from ..discrepancy.effects import EFFECTS as REGISTRY, NAMES
from ..physics.chain import ForwardElement, OffsetElement, SensorChain, ViscoelasticElement
from ..physics.preisach import hysteretic_identity as hysteretic_identity  # the bench's Preisach truths (re-exported)
from ..physics.viscoelastic import (PAPER_BURGERS, Burgers2, Elastic, KelvinVoigt, Maxwell, ViscoelasticModel, Zener,
                                    Zener2, Zener3, Burgers3)
from .sensor import BridgeSimulator
from .truths import (FAMILIES, HIDDEN_AGAINST, Additive, FloatArray, MakeFn, Truth, TruthContext,
                     families as split_families)

if TYPE_CHECKING:
    from ..record import Record

#: Hidden effects as a caller names them: one name, several, or "none".
Hidden = Union[str, Sequence[str]]


def random_load(duration_s: float, rate_hz: float, seed: int) -> tuple[FloatArray, FloatArray]:
    """Force (N) of a random bench session: holds, rests, ramps, reversals, fast steps, sine bursts."""
    rng = np.random.default_rng(seed)
    knots_t, knots_f = [0.0, 2.0], [0.0, 0.0]
    bursts: list[tuple[float, float, float, float]] = []
    t_now, f_now = 2.0, 0.0
    while t_now < duration_s:
        kind = rng.choice(["hold", "rest", "ramp", "triangle", "fast", "sine"], p=[0.25, 0.15, 0.2, 0.15, 0.15, 0.1])
        if kind == "hold":
            level = rng.uniform(1.0, 8.0)
            rise = rng.uniform(0.1, 1.0)
            dur = rng.uniform(8.0, 40.0)
            knots_t += [t_now + rise, t_now + rise + dur]
            knots_f += [level, level]
            t_now, f_now = t_now + rise + dur, level
        elif kind == "rest":
            fall = rng.uniform(0.1, 1.0)
            dur = rng.uniform(8.0, 30.0)
            knots_t += [t_now + fall, t_now + fall + dur]
            knots_f += [0.0, 0.0]
            t_now, f_now = t_now + fall + dur, 0.0
        elif kind == "ramp":
            target = rng.uniform(0.0, 9.0)
            dur = abs(target - f_now) / rng.uniform(0.3, 3.0) + 0.1
            knots_t.append(t_now + dur)
            knots_f.append(target)
            t_now, f_now = t_now + dur, target
        elif kind == "triangle":
            peak = rng.uniform(2.0, 9.0)
            rate = rng.uniform(0.5, 3.0)
            for _ in range(rng.integers(2, 5)):
                knots_t += [t_now + abs(peak - f_now) / rate + 0.05]
                knots_f += [peak]
                t_now, f_now = knots_t[-1], peak
                low = rng.uniform(0.0, 0.4 * peak)
                knots_t += [t_now + (peak - low) / rate + 0.05]
                knots_f += [low]
                t_now, f_now = knots_t[-1], low
        elif kind == "fast":
            for _ in range(rng.integers(2, 6)):
                target = rng.uniform(0.0, 8.0)
                knots_t += [t_now + rng.uniform(0.02, 0.05), t_now + rng.uniform(1.0, 3.0)]
                knots_f += [target, target]
                t_now, f_now = knots_t[-1], target
        else:  # a short sine burst around the current level
            dur = rng.uniform(3.0, 10.0)
            bursts.append((t_now, t_now + dur, rng.uniform(0.5, 5.0), rng.uniform(0.2, 1.0)))
            knots_t.append(t_now + dur)
            knots_f.append(max(f_now, 1.2))
            t_now, f_now = t_now + dur, max(f_now, 1.2)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.interp(t, knots_t, knots_f)
    for start, stop, freq, amp in bursts:
        inside = (t >= start) & (t < stop)
        f[inside] += amp * np.sin(2 * np.pi * freq * (t[inside] - start))
    return t, np.clip(f, 0.0, None)


def random_temperature(t_s: npt.ArrayLike, seed: int) -> FloatArray:
    """A slow, load-independent temperature swing of 2-6 degC around 24 degC (degC)."""
    rng = np.random.default_rng(seed + 99)
    period = rng.uniform(150.0, 400.0)
    out: FloatArray = 24.0 + rng.uniform(2.0, 6.0) * np.sin(2 * np.pi * np.asarray(t_s) / period + rng.uniform(0, 2 * np.pi))
    return out


#: The base model's truth (randomised +-30 % per seed) for each base type.
BASE_TRUTH: dict[str, ViscoelasticModel] = {
    "elastic": Elastic(3.24),
    "maxwell": Maxwell(4.8, 4627.94),
    "kelvin": KelvinVoigt(3.24, 30.0),
    "zener": Zener(4.8, 10.0, 85.12),
    "burgers": PAPER_BURGERS,
    "zener2": Zener2(4.8, 10.0, 85.12, 20.0, 2000.0),
    "burgers2": Burgers2(4.8, 10.0, 4627.94, 85.12, 20.0, 2000.0),
    "zener3": Zener3(4.8, 10.0, 85.12, 20.0, 2000.0, 40.0, 40.0),
    "burgers3": Burgers3(4.8, 10.0, 4627.94, 85.12, 20.0, 2000.0, 40.0, 40.0),
}


class LoadDependentCore:
    """Out of catalogue: the delayed (Kelvin) stiffness grows with load, k2(F) = k2 (1 + alpha F).

    The instantaneous and viscous parts stay linear, so the creep amplitude grows
    less than in proportion to the load; no static gain curve or linear core
    describes that.
    """

    kind = "sim"

    def __init__(self, core: ViscoelasticModel, alpha: float) -> None:
        self.core, self.alpha = core, alpha

    def forward_state(self) -> Any:
        """A fresh state (an empty mapping: each block is simulated from rest)."""
        return {}

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Any = None) -> FloatArray:
        """Core output [V] for the force ``x`` [N] at times ``t_s``."""
        from ..physics.viscoelastic import simulate_deformation

        t = np.asarray(t_s, dtype=float)
        f = np.asarray(x, dtype=float)
        comp = self.core.compliance()
        instant = comp.j0_v_per_n * f
        flow = (comp.fluidity_v_per_n_s * np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(t))])
                if comp.fluidity_v_per_n_s else 0.0)
        delayed = simulate_deformation(self.core, t, np.log1p(self.alpha * np.clip(f, 0, None)) / self.alpha)
        delayed = delayed - comp.j0_v_per_n * np.log1p(self.alpha * np.clip(f, 0, None)) / self.alpha
        if comp.fluidity_v_per_n_s:
            g = np.log1p(self.alpha * np.clip(f, 0, None)) / self.alpha
            delayed = delayed - comp.fluidity_v_per_n_s * np.concatenate([[0.0], np.cumsum(0.5 * (g[1:] + g[:-1]) * np.diff(t))])
        out: FloatArray = instant + flow + delayed
        return out


def _sens_drift(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    rel = float(np.interp(m, [0, 1], [0.02, 0.1]) * rng.choice([-1, 1]))  # sensitivity change over the record
    p, d = rng.uniform(0.6, 1.4), ctx["duration_s"]

    def gain(s: FloatArray) -> FloatArray:
        out: FloatArray = 1.0 + rel * (s / d) ** p
        return out

    truth = Truth()
    truth.after.append(_TimeGain(gain))
    return truth


def _stiffening(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    alpha = float(np.interp(m, [0, 1], [0.1, 0.4]))
    return Truth(core=LoadDependentCore(ctx["core"], alpha))


def _periodic(rng: np.random.Generator, m: float, ctx: TruthContext) -> Truth:
    amp = float(np.interp(m, [0, 1], [0.004, 0.03]))
    period = rng.uniform(20.0, 90.0)
    phase = rng.uniform(0, 2 * np.pi)
    w = 2 * np.pi / period

    def interference(s: FloatArray, T: Optional[FloatArray]) -> FloatArray:
        out: FloatArray = amp * np.sin(w * s + phase)
        return out

    return Truth(late=[Additive(interference)])


class _TimeGain:
    """Out of catalogue: a sensitivity that changes over time, y = x fn(t - t_first)."""

    kind = "sim"

    def __init__(self, fn: Callable[[FloatArray], FloatArray]) -> None:
        self.fn = fn

    def forward_state(self) -> Any:
        """A fresh state (an empty mapping)."""
        return {}

    def forward(self, t_s: npt.ArrayLike, x: npt.ArrayLike, aux: Optional[Mapping[str, Any]] = None,
                state: Any = None) -> FloatArray:
        """The input times the gain at the block's times (counted from the block's first)."""
        t = np.asarray(t_s, dtype=float)
        out: FloatArray = np.asarray(x, dtype=float) * self.fn(t - t[0])
        return out


#: Effects simulated beside the families (their order fixes the matrix's seeds), each with the catalogue effect that
#: describes it, or None when no catalogue effect does: then the workflow must answer "unexplained" (or "none"),
#: never a catalogue name. A Kelvin stiffness that grows with the load is a delayed elasticity whose size changes with
#: the load (the catalogue's knee variants).
EXTRA_EFFECTS: dict[str, tuple[MakeFn, Optional[str]]] = {
    "sensitivity_drift": (_sens_drift, None), "load_stiffening": (_stiffening, "delayed_elasticity"),
    "periodic_interference": (_periodic, None)}
#: The simulated effects no catalogue effect describes (:data:`EXTRA_EFFECTS`).
OUT_OF_CATALOGUE: tuple[str, ...] = tuple(name for name, (_, holder) in EXTRA_EFFECTS.items() if holder is None)
EFFECTS = ("none",) + NAMES
#: Order of effects along the chain (core first, drift last).
_ORDER = ("viscous_flow", "delayed_elasticity", "thermo_rheological", "friction", "hysteresis", "resonance",
          "nonlinear_gain", "thermal_sensitivity", "sensor_lag", "thermal_drift", "offset_drift")


def default_base(effects: Sequence[str]) -> str:
    """A base the hidden effects can be hidden against (core effects need a core without them)."""
    effects = [e for e in effects if e in REGISTRY]
    if "viscous_flow" in effects:
        return "zener"
    if "delayed_elasticity" in effects:
        return "maxwell"
    return "burgers"


def random_core(base: str, rng: np.random.Generator) -> ViscoelasticModel:
    """The base's truth core with every parameter scaled by a random factor of 0.7-1.3."""
    core = BASE_TRUTH[base]
    return type(core).from_vector(core.as_vector() * rng.uniform(0.7, 1.3, core.as_vector().size))


@dataclass
class BenchCase:
    """A bench session's truth: the hidden effects, their magnitude (0..1, from barely detectable to large) and
    family, the base, the sensor truth chain and the seed."""

    effects: tuple[str, ...]
    magnitude: float
    base: str
    truth: SensorChain
    seed: int
    families: dict[str, str] = field(default_factory=dict)

    @property
    def effect(self) -> str:
        """The first hidden effect, or "none"."""
        return self.effects[0] if self.effects else "none"


def truth_chain(effects: Hidden, magnitude: float, base: str = "burgers", seed: int = 0, force_range_n: float = 9.0,
                duration_s: float = 600.0, split: str = "tune",
                families: Optional[Mapping[str, str]] = None) -> tuple[SensorChain, dict[str, str]]:
    """The sensor truth and the family of each hidden effect: ``(SensorChain, {effect: family})``.

    ``effects``: a name, a list of names (catalogue or :data:`EXTRA_EFFECTS`), or "none".
    ``families``: {effect: family} to force a family; otherwise one is drawn from ``split``.
    """
    if isinstance(effects, str):
        effects = [] if effects == "none" else [effects]
    rng = np.random.default_rng(seed + 1234)
    core = random_core(base, rng)
    comp = core.compliance()
    ctx: TruthContext = {"core": core, "force_range_n": force_range_n, "duration_s": duration_s,
                         "gain_v_per_n": comp.j0_v_per_n + sum(comp.c_v_per_n)}
    m = float(np.clip(magnitude, 0.0, 1.0))
    before: list[ForwardElement] = []
    after: list[ForwardElement] = []
    lags: list[ForwardElement] = []
    late: list[ForwardElement] = []
    chosen: dict[str, str] = {}
    core_el: Optional[ForwardElement] = None
    for name in sorted(effects, key=lambda e: _ORDER.index(e) if e in _ORDER else len(_ORDER)):
        if name in EXTRA_EFFECTS:
            truth, chosen[name] = EXTRA_EFFECTS[name][0](rng, m, ctx), name
        elif name in REGISTRY:
            needs_base = HIDDEN_AGAINST.get(name, ())
            if needs_base and base not in needs_base:
                raise ValueError(f"{name} is hidden against a base in {needs_base}, not {base}")
            fam = (families or {}).get(name) or rng.choice(split_families(name, split))
            chosen[name] = str(fam)
            truth = FAMILIES[name][fam].make(rng, m, ctx)
        else:
            raise ValueError(f"unknown effect {name!r}; choose from {EFFECTS + tuple(EXTRA_EFFECTS)}")
        if truth.core is not None:
            if isinstance(truth.core, ViscoelasticModel):
                core = truth.core
                ctx["core"] = core
            else:  # an element that simulates the core itself (LoadDependentCore)
                core_el = truth.core
        before += truth.before
        (lags if name == "sensor_lag" else after).extend(truth.after)
        late += truth.late
    core_el = core_el or ViscoelasticElement(core)
    # truth chains may hold elements that can only simulate
    chain = SensorChain([*before, core_el, *after, *lags, *late, OffsetElement(0.05)], forward_only=True)
    return chain, chosen


def simulate_bench(effects: Hidden, magnitude: float, base: str = "burgers", duration_s: float = 600.0,
                   rate_hz: float = 200.0, seed: int = 0, noise_std_v: float = 2e-3, split: str = "tune",
                   families: Optional[Mapping[str, str]] = None
                   ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, BenchCase]:
    """(t_s, force_n, voltage_v, temperature_c, BenchCase) of a bench session with the effects hidden."""
    t, f = random_load(duration_s, rate_hz, seed)
    temp = random_temperature(t, seed)
    chain, chosen = truth_chain(effects, magnitude, base, seed, duration_s=duration_s, split=split, families=families)
    sim = BridgeSimulator(noise_std_v=noise_std_v, seed=seed)
    sim.chain, sim._states = chain, chain.forward_states()
    volts = sim.simulate(t, f, temperature_c=temp)
    names = tuple([] if effects == "none" else [effects] if isinstance(effects, str) else effects)
    return t, f, volts, temp, BenchCase(names, magnitude, base, chain, seed, chosen)


def bench_record(effects: Hidden, magnitude: float, base: str = "burgers", duration_s: float = 600.0,
                 rate_hz: float = 200.0, seed: int = 0, split: str = "tune", families: Optional[Mapping[str, str]] = None,
                 jitter: float = 0.0, drops: int = 0, temperature: bool = True, reference_noise_n: float = 0.005,
                 noise_std_v: float = 2e-3) -> tuple[Record, BenchCase]:
    """A :class:`~polyforce_ros.record.Record` of a bench session under recording conditions, and its BenchCase.

    jitter: stamp jitter as a fraction of the sample interval (uniform +-); drops: number of
    dropped blocks (each up to 0.5 s); temperature: whether the temperature topic exists;
    reference_noise_n: white noise of the reference load cell (N, 1 sigma).
    """
    from ..record import Record

    t, f, v, temp, case = simulate_bench(effects, magnitude, base, duration_s, rate_hz, seed, noise_std_v, split, families)
    rng = np.random.default_rng(seed + 77)
    keep = np.ones(t.size, dtype=bool)
    for _ in range(drops):
        start = rng.uniform(0.05, 0.95) * duration_s
        keep &= ~((t >= start) & (t < start + rng.uniform(0.05, 0.5)))
    stamps = t + jitter * rng.uniform(-1.0, 1.0, t.size) / rate_hz
    f_meas = f + rng.normal(0.0, reference_noise_n, t.size)
    stamps, f_meas, v, temp = stamps[keep], f_meas[keep], v[keep], temp[keep]
    return Record(stamps - stamps[0], f_meas, v, temp if temperature else None), case


def write_bench_bag(path: Union[str, os.PathLike[str]], effects: Hidden, magnitude: float, base: str = "burgers",
                    duration_s: float = 600.0, rate_hz: float = 200.0, seed: int = 0, split: str = "tune",
                    families: Optional[Mapping[str, str]] = None, temperature: bool = True) -> BenchCase:
    """Write a hidden-effect bench session as a bag of the topic contract; returns the BenchCase."""
    from .recording import write_bench_bag as write

    t, f, volts, temp, case = simulate_bench(effects, magnitude, base, duration_s, rate_hz, seed, split=split,
                                             families=families)
    write(path, t, f, volts, temperature_c=temp if temperature else None, temperature_every=max(1, int(rate_hz / 10)))
    return case
