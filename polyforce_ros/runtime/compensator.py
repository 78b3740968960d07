"""What to do with each raw sample: the compensation policy, ROS-free.

One home for the rules that decide which bridge samples are used and what force
leaves the compensator. ``compensation_node`` is subscribe -> :meth:`Compensator.step`
-> publish; ``polyforce compensate`` runs the same object over a bag
(:meth:`Compensator.run`), so a bag and a live stream with the same samples give
the same wrench, bit for bit.

Rules, in the order they are applied:

1. a non-finite voltage, or one beyond ``input_limit_v``, is dropped and counted;
2. stamps are checked against the receive clock (host time live, log time in a bag):
   a sample stamped more than ``stamp_tolerance_s`` further ahead of its arrival
   than any used sample of this history (``stamp - receive`` above its running
   maximum by more than that) claims to come from the future: a DAQ or clock
   glitch. It is dropped and never becomes the "last stamp". Samples that arrive
   late (a buffer delivering after a stall) are plausible: their stamps only lag;
   a glitch into the past is caught by rule 3;
3. a stamp earlier than or equal to the last used one is dropped (backwards /
   duplicate: never two wrenches with one stamp, no history rewritten);
4. healing: when rejected samples keep arriving, consistent among themselves
   (increasing stamps, a steady ``stamp - receive``), for ``reanchor_after_s`` of
   receive time, the stamp history re-anchors on them (counted, the compensator's
   history restarts). A glitch therefore blinds the force for at most that long;
5. a gap longer than ``gap_warn_s`` is integrated as a linear change across it
   (the compensator's exact assumption) and counted;
6. a non-finite force resets the history, is counted and is never output;
7. the force is clamped to +-``force_limit_n`` (counted);
8. no valid sample for ``stale_timeout_s`` -> the caller outputs zero (:meth:`stale`);
9. temperature (thermal elements): the last finite reading received is used
   (:meth:`Compensator.temperature`); a non-finite reading is ignored; none
   before the first;
10. zero before force: after start or :meth:`reset` the bridge output is tested for
   rest over windows of ``auto_tare_s`` (its spread and its drift across the window
   below ``auto_tare_max_std_v``, and its mean within ``auto_tare_max_shift_v`` of
   the model's offset, which a load would exceed); the first window at rest becomes
   the bridge offset (counted ``auto_tares``). A window that is not at rest is
   slid on by half its length and tried again, for up to ``auto_tare_timeout_s``.
   Until that decision the output is zero (``zero_before_tare``, counted) or,
   with ``publish_zero_before_tare=False``, nothing. When no rest came in time
   the model's offset is used, counted (``auto_tare_refused``) and flagged
   (:attr:`Compensator.auto_tare_failed`, cleared by a tare); the reason is in
   :attr:`Compensator.auto_tare_status`. Off with ``auto_tare=False`` (a sensor
   that starts under load);
11. the model itself: a chain whose inverse amplifies white bridge noise more
   than ``max_noise_gain`` (N/V, RMS over RMS, judged at ``noise_gain_rate_hz``)
   is refused with a :class:`~polyforce_ros.physics.chain.ModelError` naming the
   element that amplifies most (:func:`~polyforce_ros.physics.noise_gain.backward_noise_gain`).

Tare and drift tracking change a bridge offset held here, never the model: the
model chain is an immutable description (see :meth:`SensorChain.with_offset`).
"""
from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, fields, replace
from typing import Any, Mapping, Optional

import numpy as np
import numpy.typing as npt

from ..physics.chain import BridgeHysteresisElement, ModelError, SensorChain, TimeDriftElement
from ..physics.noise_gain import NoiseGain, backward_noise_gain
from ..settings import setting
from ..stamps import REANCHOR_AFTER_S, STAMP_TOLERANCE_S, ConsistentRun

__all__ = ["CompensatorConfig", "SampleGate", "Compensator", "check_noise_gain",
           "GATE_COUNTERS", "COMPENSATOR_COUNTERS", "WARN_COUNTERS",
           "ACCEPT", "ACCEPT_FRESH"]

#: :meth:`SampleGate.admit` results that use the sample (FRESH: the history restarts with it).
ACCEPT, ACCEPT_FRESH = 0, 1
_DROPS = ("nonfinite", "out_of_range", "implausible_stamp", "backwards", "duplicate")
GATE_COUNTERS = ("samples",) + _DROPS + ("gaps", "reanchored")
COMPENSATOR_COUNTERS = GATE_COUNTERS + ("nonfinite_output", "clamped", "drift_corrections", "tares", "auto_tares",
                                        "auto_tare_retries", "auto_tare_refused", "zero_before_tare")
#: Counters that mean the stream was not clean: a sample dropped, altered or after an irregularity. The node's
#: diagnostics WARN on them and the offline tools list them; one list, so both tell the same story.
WARN_COUNTERS = _DROPS + ("gaps", "reanchored", "nonfinite_output", "clamped")
#: Most samples an auto-tare window keeps (bounds memory at any rate).
AUTO_TARE_MAX_SAMPLES = 100_000


@dataclass(frozen=True)
class CompensatorConfig:
    """Policy settings, each declared once with its description and range (:func:`~polyforce_ros.settings.setting`);
    the compensation node declares a parameter of each, ``polyforce compensate`` takes its defaults from them."""

    force_limit_n: float = setting(12.0, "Output clamp: |force.z| never exceeds this (N)", 0.1, 1000.0)
    input_limit_v: float = setting(10.0, "Samples with |voltage| above this are dropped (V)", 0.001, 1000.0)
    stale_timeout_s: float = setting(0.1, "No valid input for this long -> zero wrench and ERROR (s)", 0.002, 60.0)
    gap_warn_s: float = setting(0.05, "Stamp gaps longer than this are counted as gaps (s)", 0.0001, 3600.0)
    stamp_tolerance_s: float = setting(
        STAMP_TOLERANCE_S, "A sample stamped further ahead of its arrival than any used sample by more than this is an "
        "implausible stamp and is dropped (s); 0 = no check (fast replays of bags with gaps)", 0.0, 3600.0)
    reanchor_after_s: float = setting(
        REANCHOR_AFTER_S, "Rejected but self-consistent samples for this long re-anchor the stamp history (s)", 0.001, 60.0)
    tare_window: int = setting(200, "Samples averaged by ~/tare", 1, 100000)
    auto_tare: bool = setting(
        True, "Zero the bridge offset at the first rest of auto_tare_s after start, ~/reset or sensor_reset (zero "
        "force until then); false for a sensor that starts under load")
    auto_tare_s: float = setting(0.5, "Window of the start-up zeroing (s)", 0.01, 60.0)
    auto_tare_max_std_v: float = setting(  # ~5x the bridge noise
        0.005, "At rest: spread and drift of the bridge output below this (V)", 1e-6, 1.0)
    auto_tare_max_shift_v: float = setting(  # 0.5 N at 4.8 N/V
        0.1, "At rest: mean output within this of the model's offset (V); a load shifts it further", 1e-4, 10.0)
    auto_tare_timeout_s: float = setting(
        10.0, "Retry the zeroing at the first rest within this long after start or reset; then use the model's "
        "offset, WARN, and diagnostics ERROR until ~/tare (s)", 0.01, 3600.0)
    publish_zero_before_tare: bool = setting(
        True, "Until the zeroing decided: publish zero force (true) or nothing (false)")
    # 2 mV of bridge noise (twice the simulated amplifier's) then reaches the master as at most 0.02 N, the haptic
    # bridge's deadband
    max_noise_gain: float = setting(
        10.0, "Refuse a model whose inverse turns white bridge noise into more than this force (N per V rms); "
        "10: 2 mV of noise reaches the master as at most 0.02 N", 0.1, 1e6, read_only=True)
    noise_gain_rate_hz: float = setting(
        1000.0, "Sample rate at which max_noise_gain is judged (Hz)", 1.0, 1e6, read_only=True)
    apply_time_drifts: bool = setting(
        False, "Apply the model's time drifts (offset, exponential, polynomial, spline and step drifts) from the first "
        "sample after each start, ~/reset or tare; off by default: they describe the record they were fitted on, and "
        "would replay its drift (a polynomial without bound) after every reset", read_only=True)
    drift_tracking: bool = setting(
        False, "Re-zero the bridge offset whenever the force rests inside +-drift_band_n for drift_window_s "
        "(tracks slow baseline drift; off by default: it would also zero a real steady load that small)")
    drift_band_n: float = setting(0.05, "Force band counted as 'at rest' for drift tracking (N)", 0.001, 5.0)
    drift_window_s: float = setting(5.0, "Rest time before a drift correction (s)", 0.1, 3600.0)

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """Field names: the compensation node declares a parameter of each name."""
        return tuple(f.name for f in fields(cls))


def time_drifts(chain: SensorChain) -> tuple[str, ...]:
    """The kinds of the chain's time drifts (elements that run on the time since a start or reset), in order."""
    return tuple(e.kind for e in chain.elements if isinstance(e, TimeDriftElement))


def time_drifts_note(kinds: tuple[str, ...]) -> str:
    """Why the runtime leaves these time drifts out, for a log line ('' for none)."""
    if not kinds:
        return ""
    return (f"the model's time drifts are left out ({', '.join(kinds)}): they describe the record they were fitted "
            "on; the zero is set by the start-up zeroing and ~/tare, and followed at rest only with drift_tracking "
            "(apply_time_drifts applies them from each start, reset or tare)")


def runtime_chain(chain: SensorChain, apply_time_drifts: bool = False) -> SensorChain:
    """The chain the runtime runs for ``chain``: without its time drifts unless ``apply_time_drifts`` (the one
    home of that rule: the compensator, its noise-gain guard and the diagnosis's judgement of the runtime use it).

    Raises
    ------
    ModelError
        The chain holds nothing but time drifts (nothing is left to compensate with).
    """
    if apply_time_drifts or not time_drifts(chain):
        return chain
    kept = [e for e in chain.elements if not isinstance(e, TimeDriftElement)]
    if not kept:
        raise ModelError(f"the model holds only time drifts ({', '.join(time_drifts(chain))}): nothing is left to "
                         "compensate with unless apply_time_drifts")
    return SensorChain(kept)


class _Configured:
    """A ``config`` attribute whose per-sample values the subclass keeps at hand (``_keep``) whenever it is set."""

    _config: CompensatorConfig

    @property
    def config(self) -> CompensatorConfig:
        """Policy settings."""
        return self._config

    @config.setter
    def config(self, config: CompensatorConfig) -> None:
        self._config = config
        self._keep(config)

    def _keep(self, config: CompensatorConfig) -> None:
        raise NotImplementedError


class SampleGate(_Configured):
    """Rules 1-5: which samples are used, and when the history must restart."""

    def __init__(self, config: CompensatorConfig = CompensatorConfig()) -> None:
        self.config = config
        self.counts = dict.fromkeys(GATE_COUNTERS, 0)
        self.last_stamp_ns: Optional[int] = None
        self._skew_ns = 0                          # largest stamp - receive of this history's used samples
        self._run = ConsistentRun(self._tol_ns, self.config.reanchor_after_s * 1e9)  # rejected samples that agree
        self._fresh = False                        # the next used sample starts a new history (ACCEPT_FRESH)

    def _keep(self, config: CompensatorConfig) -> None:
        # per-sample comparisons at 1 kHz: attribute chains and unit conversions done once, not per sample
        self._limit_v = config.input_limit_v
        self._tol_ns = config.stamp_tolerance_s * 1e9
        self._gap_s = config.gap_warn_s
        if hasattr(self, "_run"):  # a new config: the run of rejected samples is judged by its limits from now on
            self._run.tolerance_ns, self._run.after_ns = self._tol_ns, config.reanchor_after_s * 1e9

    def restart(self, keep_stamps: bool = False) -> None:
        """Forget the stamp history: the next finite sample starts a fresh one.

        With ``keep_stamps`` only the history restarts: the next used sample is still later than the
        last used stamp (the compensator's deformation history restarts, the stamps go on), and is
        admitted as ACCEPT_FRESH.
        """
        if not keep_stamps:
            self.last_stamp_ns = None
        self._run.reset()
        self._fresh = True

    def admit(self, stamp_ns: int, voltage_v: float, receive_ns: Optional[int] = None) -> Any:
        """ACCEPT, ACCEPT_FRESH, or the name of the counter of the drop."""
        c = self.counts
        c["samples"] += 1
        if not math.isfinite(voltage_v):
            c["nonfinite"] += 1
            return "nonfinite"
        if abs(voltage_v) > self._limit_v:
            c["out_of_range"] += 1
            return "out_of_range"
        receive_ns = stamp_ns if receive_ns is None else receive_ns
        skew = stamp_ns - receive_ns
        last = self.last_stamp_ns
        if last is None:
            return self._anchor(stamp_ns, skew)
        tol_ns = self._tol_ns
        if tol_ns > 0 and skew - self._skew_ns > tol_ns:
            reason = "implausible_stamp"
        elif stamp_ns < last:
            reason = "backwards"
        elif stamp_ns == last:
            reason = "duplicate"
        else:
            self._run.reset()
            if (stamp_ns - last) * 1e-9 > self._gap_s:  # the arithmetic of mask(): counts agree at the boundary
                c["gaps"] += 1
            if skew > self._skew_ns:
                self._skew_ns = skew
            self.last_stamp_ns = stamp_ns
            if self._fresh:
                self._fresh = False
                return ACCEPT_FRESH
            return ACCEPT
        c[reason] += 1
        if self._heals(stamp_ns, skew, receive_ns, tol_ns):
            c["reanchored"] += 1
            return self._anchor(stamp_ns, skew)
        return reason

    def _anchor(self, stamp_ns: int, skew: int) -> int:
        self.last_stamp_ns, self._skew_ns, self._fresh = stamp_ns, skew, False
        self._run.reset()
        return ACCEPT_FRESH

    def _heals(self, stamp_ns: int, skew: int, receive_ns: int, tol_ns: float) -> bool:
        """Whether this rejected sample completes a run of consistent ones long enough to re-anchor on."""
        return self._run.add(stamp_ns, skew, receive_ns)

    def mask(self, stamp_ns: npt.ArrayLike, voltage_v: npt.ArrayLike,
             receive_ns: Optional[npt.ArrayLike] = None) -> np.ndarray:
        """Samples :meth:`admit` would use, for whole arrays (fresh gate state).

        When vectorised checks show that every sample passes (the usual clean
        record) no per-sample work is done; otherwise the samples are admitted
        one by one, so this is always exactly the per-sample rule.
        """
        stamp_ns = np.asarray(stamp_ns, dtype=np.int64)
        voltage_v = np.asarray(voltage_v, dtype=float)
        receive = stamp_ns if receive_ns is None else np.asarray(receive_ns, dtype=np.int64)
        if self.last_stamp_ns is None and stamp_ns.size:
            skew = stamp_ns - receive
            tol_ns = self.config.stamp_tolerance_s * 1e9
            clean = (np.isfinite(voltage_v).all() and (np.abs(voltage_v) <= self.config.input_limit_v).all()
                     and (np.diff(stamp_ns) > 0).all()
                     and (tol_ns <= 0 or (skew[1:] - np.maximum.accumulate(skew)[:-1] <= tol_ns).all()))
            if clean:
                dt = np.diff(stamp_ns) * 1e-9
                self.counts["samples"] += stamp_ns.size
                self.counts["gaps"] += int((dt > self.config.gap_warn_s).sum())
                self.last_stamp_ns, self._skew_ns = int(stamp_ns[-1]), int(skew.max())
                return np.ones(stamp_ns.size, dtype=bool)
        out = np.zeros(stamp_ns.size, dtype=bool)
        for i in range(stamp_ns.size):
            out[i] = self.admit(int(stamp_ns[i]), float(voltage_v[i]), int(receive[i])) in (ACCEPT, ACCEPT_FRESH)
        return out


class Compensator(_Configured):
    """Raw bridge samples in, force out: the gate, the chain's inverse, tare, drift, clamp, staleness.

    Parameters
    ----------
    chain : SensorChain
        The sensor model (immutable; never written to).
    config : CompensatorConfig
        Policy settings.
    """

    _rest_since_ns: Optional[int]   # start of the current rest (drift tracking), ns; None = not resting
    noise_gain: NoiseGain           # of the chain in use, at noise_gain_rate_hz (set with the chain)
    _checked_with: tuple[bool, float, float]  # apply_time_drifts, max_noise_gain, rate: what the chain in use was built with

    def __init__(self, chain: SensorChain, config: CompensatorConfig = CompensatorConfig()) -> None:
        self.config = config
        self.gate = SampleGate(config)
        self.counts = self.gate.counts
        for name in COMPENSATOR_COUNTERS:
            self.counts.setdefault(name, 0)
        self._recent_v: deque[float] = deque(maxlen=int(config.tare_window))
        self.tare_offset_v: Optional[float] = None   # bridge offset from the last tare, V
        self.drift_v = 0.0                           # drift corrections since then, V
        self.last_valid_receive_ns: Optional[int] = None
        self.auto_tare_status = "pending" if config.auto_tare else "off"
        self.auto_tare_failed = False                # no rest within auto_tare_timeout_s: the model's offset in use
        self.auto_tare_reason = ""                   # why the last window was not at rest
        self._auto: Optional[list[tuple[int, float]]] = [] if config.auto_tare else None   # (stamp_ns, V) of the window
        self._auto_since_ns: Optional[int] = None    # stamp of the first sample since the auto-tare was armed
        self._aux: dict[str, Optional[float]] = {"temperature_c": None}  # auxiliary signals for the chain
        self.set_chain(chain)

    # ------------------------------------------------------------------ settings
    def _keep(self, config: CompensatorConfig) -> None:
        # every way of setting the config (the constructor, configure, an assignment) ends here
        self._drift_tracking, self._force_limit_n = config.drift_tracking, config.force_limit_n  # read per sample
        if not hasattr(self, "gate"):  # the constructor: nothing built yet
            return
        self.gate.config = config
        if self._recent_v.maxlen != int(config.tare_window):
            self._recent_v = deque(self._recent_v, maxlen=int(config.tare_window))
        if not config.auto_tare and self.auto_tare_status != "off":
            self._auto, self.auto_tare_status, self.auto_tare_failed = None, "off", False
        checked = self._checked_with
        if (config.apply_time_drifts, config.max_noise_gain, config.noise_gain_rate_hz) != checked:
            try:  # the chain in use is built, and guarded, with these settings
                self.set_chain(self.chain)
            except ModelError:
                self._config = replace(config, apply_time_drifts=checked[0], max_noise_gain=checked[1],
                                       noise_gain_rate_hz=checked[2])
                raise

    def set_chain(self, chain: SensorChain) -> None:
        """Use another model; the history restarts (it belongs to the old model), a tare is kept.

        Raises
        ------
        ModelError
            The chain's inverse amplifies white bridge noise more than ``max_noise_gain`` (the
            model in use, if any, is kept).
        """
        cfg = self.config
        # everything is built before anything is kept: a refused chain leaves the one in use whole
        in_use = runtime_chain(chain, cfg.apply_time_drifts)
        gain = check_noise_gain(in_use, cfg.noise_gain_rate_hz, cfg.max_noise_gain)
        stream = in_use.streaming()
        core = chain.viscoelastic
        g0 = core.relaxation().g0_n_per_v if core is not None else 1.0
        # plays at the bridge rest inside their bands at a steady force: only their linear part adds to the
        # instantaneous compliance that turns a resting force into an offset error
        linear_v_per_n = sum(e.linear_v_per_n for e in chain.elements if isinstance(e, BridgeHysteresisElement))
        self.noise_gain, self.chain, self._stream = gain, chain, stream
        #: the model's time drifts the stream leaves out (``apply_time_drifts`` off), by kind
        self.time_drifts_left_out = () if in_use is chain else time_drifts(chain)
        self._g0 = g0 / (1.0 + g0 * linear_v_per_n)
        self._checked_with = (cfg.apply_time_drifts, cfg.max_noise_gain, cfg.noise_gain_rate_hz)
        self._update_shift()
        self._restart()

    @property
    def time_drifts_note(self) -> str:
        """What the model's left-out time drifts mean, for a log line ('' when none is left out)."""
        return time_drifts_note(self.time_drifts_left_out)

    def _update_shift(self) -> None:
        # what the input is moved by before the chain's inverse (its own offset element stays as it is);
        # kept up to date here rather than derived per sample, which walked the chain twice at 1 kHz
        self._shift_v = self.offset_v - self.chain.offset_v

    def configure(self, **changes: Any) -> None:
        """New policy settings (names of :class:`CompensatorConfig`); take effect at the next sample."""
        self.config = replace(self.config, **changes)

    @property
    def offset_v(self) -> float:
        """Bridge output at zero force now in use (model offset, or tare, plus drift corrections), V."""
        base = self.tare_offset_v if self.tare_offset_v is not None else self.chain.offset_v
        return base + self.drift_v

    # ------------------------------------------------------------------ per sample
    def temperature(self, temperature_c: float) -> bool:
        """Take a sensor temperature reading for the thermal elements, used from the next sample on.

        Parameters
        ----------
        temperature_c : float
            Reading [degC].

        Returns
        -------
        bool
            False when the reading is not finite: it is ignored and the last finite one stays in use.
        """
        if not math.isfinite(temperature_c):
            return False
        self._aux["temperature_c"] = float(temperature_c)
        return True

    @property
    def temperature_c(self) -> Optional[float]:
        """The temperature in use [degC]; None before the first finite reading."""
        return self._aux["temperature_c"]

    def step(self, stamp_ns: int, voltage_v: float, receive_ns: Optional[int] = None,
             aux: Optional[Mapping[str, Any]] = None) -> Optional[float]:
        """Force (N) for one raw sample, or None when the sample is dropped.

        ``receive_ns`` is the time the sample arrived on the clock its stamps
        should follow (host time live, the log time in a bag); None = the stamp.
        ``aux`` overrides the auxiliary signals (default: the readings taken by
        :meth:`temperature`).
        """
        verdict = self.gate.admit(stamp_ns, voltage_v, receive_ns)
        if verdict == ACCEPT_FRESH:
            self._stream.reset()
            self._epoch_ns = stamp_ns
        elif verdict != ACCEPT:
            return None
        self._recent_v.append(voltage_v)
        zeroing = self._collect_auto_tare(stamp_ns, voltage_v) if self._auto is not None else "off"
        self.last_valid_receive_ns = stamp_ns if receive_ns is None else receive_ns
        if zeroing == "zeroed":  # this sample closed the rest window; the history starts at the next one
            self.counts["zero_before_tare"] += 1
            return 0.0 if self.config.publish_zero_before_tare else None
        force = self._stream.step((stamp_ns - self._epoch_ns) * 1e-9, voltage_v - self._shift_v,
                                  self._aux if aux is None else aux)
        if force is None or not math.isfinite(force):
            self.counts["nonfinite_output"] += 1
            self._restart()
            return None
        if zeroing == "pending":  # zero before force: an untared bridge offset reads as a phantom load
            self.counts["zero_before_tare"] += 1
            return 0.0 if self.config.publish_zero_before_tare else None
        if self._drift_tracking:
            force = self._track_drift(stamp_ns, force)
        limit = self._force_limit_n
        if abs(force) > limit:
            self.counts["clamped"] += 1
            force = math.copysign(limit, force)
        return force

    def stale(self, now_ns: int) -> bool:
        """Whether no valid sample arrived for ``stale_timeout_s`` before ``now_ns`` (receive clock)."""
        last = self.last_valid_receive_ns
        return last is None or (now_ns - last) * 1e-9 > self.config.stale_timeout_s

    # ------------------------------------------------------------------ batch
    def run(self, stamp_ns: npt.ArrayLike, voltage_v: npt.ArrayLike, receive_ns: Optional[npt.ArrayLike] = None,
            temperature_c: Optional[npt.ArrayLike] = None,
            temperature_log: Optional[tuple[npt.ArrayLike, npt.ArrayLike]] = None) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`step` over arrays, exactly (sample by sample).

        Parameters
        ----------
        stamp_ns, voltage_v : (n,) array_like
            Header stamps [ns] and bridge output [V] of the raw samples.
        receive_ns : (n,) array_like, optional
            Arrival of each sample on the receive clock [ns] (a bag's log times); default the stamps.
        temperature_c : (n,) array_like, optional
            A temperature reading [degC] taken before each sample (:meth:`temperature`).
        temperature_log : ((m,), (m,)) array_like, optional
            Temperature messages as received: their receive times [ns] and readings [degC]. Before each
            sample, every message received at or before it is taken, in order, as the node would.

        Returns
        -------
        used : (n,) ndarray of bool
            Samples that gave a force.
        force_n : (n,) ndarray
            Their forces [N] (0 where not used).
        """
        stamp_ns = np.asarray(stamp_ns, dtype=np.int64)
        voltage_v = np.asarray(voltage_v, dtype=float)
        receive = stamp_ns if receive_ns is None else np.asarray(receive_ns, dtype=np.int64)
        per_sample = None if temperature_c is None else np.broadcast_to(np.asarray(temperature_c, dtype=float),
                                                                         stamp_ns.shape)
        log_ns, log_c = np.zeros(0, dtype=np.int64), np.zeros(0)
        if temperature_log is not None:
            log_ns, log_c = np.asarray(temperature_log[0], dtype=np.int64), np.asarray(temperature_log[1], dtype=float)
            order = np.argsort(log_ns, kind="stable")
            log_ns, log_c = log_ns[order], log_c[order]
        used = np.zeros(stamp_ns.size, dtype=bool)
        force = np.zeros(stamp_ns.size)
        k = 0
        for i in range(stamp_ns.size):
            while k < log_ns.size and log_ns[k] <= receive[i]:
                self.temperature(float(log_c[k]))
                k += 1
            if per_sample is not None:
                self.temperature(float(per_sample[i]))
            f = self.step(int(stamp_ns[i]), float(voltage_v[i]), int(receive[i]))
            if f is not None:
                used[i], force[i] = True, f
        return used, force

    # ------------------------------------------------------------------ tare, reset, drift
    def tare(self) -> tuple[bool, str]:
        """Take the mean of the last ``tare_window`` used samples as the bridge offset; restart the history."""
        if not self._recent_v:
            return False, "no valid samples received yet; nothing to tare"
        offset = sum(self._recent_v) / len(self._recent_v)
        self.tare_offset_v, self.drift_v = offset, 0.0
        self._update_shift()
        self.counts["tares"] += 1
        self.auto_tare_failed = False
        if self._auto is not None:  # a tare by hand decides what the auto-tare was waiting for
            self._auto, self.auto_tare_status = None, f"tared by hand: bridge offset {offset:.6f} V"
        self._restart()
        return True, f"tared: bridge offset {offset:.6f} V from {len(self._recent_v)} samples; history cleared"

    @property
    def auto_tare_pending(self) -> bool:
        """Whether the auto-tare is still waiting for a rest (the output is held at zero meanwhile)."""
        return self._auto is not None

    def reset(self, from_stamp_ns: Optional[int] = None) -> None:
        """Forget the deformation and stamp history (sensor assumed relaxed); re-arm the auto-tare.

        ``from_stamp_ns``: the sensor restarted at this acquisition time (a device reset, a restarted
        simulator); samples stamped before it belong to the old history and are dropped as ``backwards``.
        """
        self._restart(stamps=True)
        if from_stamp_ns is not None:
            self.gate.last_stamp_ns = int(from_stamp_ns) - 1
        if self.config.auto_tare:
            self._auto, self.auto_tare_status, self._auto_since_ns = [], "pending", None

    def _collect_auto_tare(self, stamp_ns: int, voltage_v: float) -> str:
        """Add a sample to the rest window: "pending", "zeroed" (the history restarted) or "failed" (given up)."""
        window = self._auto
        assert window is not None  # called only while armed
        if self._auto_since_ns is None:
            self._auto_since_ns = stamp_ns
        if len(window) < AUTO_TARE_MAX_SAMPLES:
            window.append((stamp_ns, voltage_v))
        if (stamp_ns - window[0][0]) * 1e-9 < self.config.auto_tare_s:
            return "pending"
        data = np.array(window, dtype=float)
        t, v = (data[:, 0] - data[0, 0]) * 1e-9, data[:, 1]
        cfg = self.config
        spread = float(v.std())
        drift = float(abs(np.polyfit(t, v, 1)[0]) * t[-1]) if v.size > 2 else 0.0
        shift = float(v.mean() - self.chain.offset_v)
        waited_s = (stamp_ns - self._auto_since_ns) * 1e-9
        if spread <= cfg.auto_tare_max_std_v and drift <= cfg.auto_tare_max_std_v and abs(shift) <= cfg.auto_tare_max_shift_v:
            self._auto = None
            self.tare_offset_v, self.drift_v, self.auto_tare_failed = float(v.mean()), 0.0, False
            self._update_shift()
            self.counts["auto_tares"] += 1
            self.auto_tare_status = (f"zeroed: bridge offset {v.mean():.6f} V from {v.size} samples at rest "
                                     f"({waited_s:.2f} s after start)")
            self._restart()
            return "zeroed"
        reason = self.auto_tare_reason = f"spread {spread:.4f} V, drift {drift:.4f} V, offset shift {shift:+.4f} V"
        if waited_s < cfg.auto_tare_timeout_s:  # slide on by half a window: a rest as long as 1.5 windows is found
            self.counts["auto_tare_retries"] += 1
            del window[: len(window) // 2]
            self.auto_tare_status = f"pending: waiting for the sensor to rest ({reason})"
            return "pending"
        self._auto = None
        self.auto_tare_failed = True
        self.counts["auto_tare_refused"] += 1
        self.auto_tare_status = (f"not zeroed: the sensor did not rest for {cfg.auto_tare_s} s within "
                                 f"{cfg.auto_tare_timeout_s} s ({reason}); the model's offset is used until a tare")
        return "failed"

    def _restart(self, stamps: bool = False) -> None:
        """Restart the deformation history (a tare, a new model, a non-finite force); with ``stamps`` the stamp
        history too (a sensor restart): otherwise the next used sample is still later than the last one used,
        so no wrench repeats a stamp or goes back across a tare."""
        self._stream.reset()
        self.gate.restart(keep_stamps=not stamps)
        self._epoch_ns = 0
        self._rest_since_ns, self._rest_force_sum, self._rest_count = None, 0.0, 0

    def _track_drift(self, stamp_ns: int, force: float) -> float:
        """Fold a resting force into the bridge offset (see ``drift_tracking``)."""
        cfg = self.config
        if abs(force) > cfg.drift_band_n:
            self._rest_since_ns, self._rest_force_sum, self._rest_count = None, 0.0, 0
            return force
        if self._rest_since_ns is None:
            self._rest_since_ns = stamp_ns
        self._rest_force_sum += force
        self._rest_count += 1
        if (stamp_ns - self._rest_since_ns) * 1e-9 >= cfg.drift_window_s:
            mean_force = self._rest_force_sum / self._rest_count
            # F = G(0) (V - offset) - history: a resting force F reads as an offset error of F / G(0).
            self.drift_v += mean_force / self._g0
            self._update_shift()
            self.counts["drift_corrections"] += 1
            self._rest_since_ns, self._rest_force_sum, self._rest_count = stamp_ns, 0.0, 0
            force -= mean_force
        return force


def check_noise_gain(chain: SensorChain, rate_hz: float, max_gain: float) -> NoiseGain:
    """The noise gain of ``chain``'s inverse at ``rate_hz``, or a ModelError when it exceeds ``max_gain`` [N/V].

    The message names the element that amplifies most, by how much, and what bounds it.
    """
    gain = backward_noise_gain(chain, rate_hz)
    if not gain.gain_n_per_v <= max_gain:
        # a chain still above the limit without its loudest element is refused for its core's own inverse: no
        # bandwidth on that element can bring it within the limit
        rest_n_per_v = gain.gain_n_per_v / gain.element_factor
        if gain.element_factor == 1.0:
            culprit = (f"the {gain.element} core's own inverse passes it on at that gain (no other element adds to "
                       f"it): a sensor like this needs a raised max_noise_gain")
        elif not rest_n_per_v <= max_gain:
            culprit = (f"the {gain.element} element multiplies it by {gain.element_factor:.3g}, and without it the "
                       f"core's own inverse still passes {rest_n_per_v:.4g} N per V: a sensor like this needs a raised "
                       f"max_noise_gain")
        else:
            culprit = (f"the {gain.element} element multiplies it by {gain.element_factor:.3g}: give it a bandwidth "
                       f"(sensor_lag: noise_filter_tau_s) or raise max_noise_gain")
        raise ModelError(
            f"model refused: its inverse turns white bridge noise into {gain.gain_n_per_v:.4g} N per V "
            f"at {rate_hz:g} Hz, above max_noise_gain {max_gain:g} N/V (1 mV of noise would move the master by "
            f"{gain.force_noise_n(1e-3):.3g} N rms); {culprit}")
    return gain
