"""The rules of the haptic bridge: compensated needle force -> force command of a haptic master.

ROS-free (``nodes/haptic_bridge_node.py`` is a thin shell around it), so every
rule is tested without DDS. Every input sample of the compensated axial force
(N, compression positive) gives one command for the operator's hand (N), at
once, by

1. validation: a non-finite force (or time) is rejected and counted; it never
   reaches the output and does not count as "fresh" input (the command stays
   where it is, or keeps ramping);
2. :func:`deadband` on the needle force (sensor noise around zero is not felt);
3. :func:`scale` by ``force_scale`` (hand force per needle force);
4. :func:`saturate` at the device's maximum force ``max_force_n``;
5. :func:`slew` of the command towards that target by at most
   ``max_slew_n_per_s`` times the stamp time elapsed since the previous valid
   sample (no steps into the operator's hand). The sample's stamp, not its
   arrival, sets the step: samples delivered late or in a burst are rendered as
   they were acquired. A stamp step outside ``[0, stale_timeout_s]`` (a stamp
   going backwards, a jump no live stream makes) and the first sample after a
   silence move nothing: the command slews on from the next sample;
6. staleness, on the arrival clock: no valid input for ``stale_timeout_s``
   starts a linear :func:`stale_ramp` from the command at that instant to
   exactly zero within ``ramp_s``. A force is never held on stale input. The
   ramp moves towards zero only and is not slew-limited (releasing the force is
   the safe direction). Only the ramp advances without input (:meth:`HapticBridge.tick`).

Invariants (property-tested): the command is always finite and
``|command| <= max_force_n``; between two valid samples it moves by at most
``max_slew_n_per_s`` times their stamp step, and otherwise only towards zero;
``stale_timeout_s + ramp_s`` after the last valid input it is exactly zero.

Times are seconds. Arrival times (``now_s``) are on any monotonic clock (the
node uses the host's monotonic clock at receipt); an arrival earlier than the
last one seen is treated as that last one. Stamps (``stamp_s``) are the
samples' own times (the node passes the header stamps); without them the
arrival time is the stamp.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields, replace
from typing import Any, Optional

from .settings import setting, settings_of

__all__ = [
    "HapticConfig", "HapticBridge", "AXES",
    "deadband", "scale", "saturate", "slew", "stale_ramp", "shape", "parse_axis", "device_vector",
]

#: Device axes a needle force can be mapped to: name -> (index in [x, y, z], sign).
AXES = {"x": (0, 1.0), "y": (1, 1.0), "z": (2, 1.0), "-x": (0, -1.0), "-y": (1, -1.0), "-z": (2, -1.0)}


@dataclass(frozen=True)
class HapticConfig:
    """Settings of the bridge's rules, each declared once with its default, description and range
    (:func:`~polyforce_ros.settings.setting`); the haptic bridge node declares a parameter of each.

    Every value must be a finite number within its range (``ValueError`` otherwise) and is kept as a float.

    Attributes
    ----------
    force_scale : float
        Hand force per needle force, N/N.
    deadband_n : float
        Deadband on the needle force, N.
    max_force_n : float
        Saturation of the command, N.
    max_slew_n_per_s : float
        Slew-rate limit of the command, N/s.
    stale_timeout_s : float
        Time without valid input after which the stale ramp starts, s.
    ramp_s : float
        Duration of the stale ramp to zero, s.
    """

    force_scale: float = setting(1.0, "Hand force per needle force (N/N); 0 = no force feedback", 0.0, 100.0)
    deadband_n: float = setting(0.02, "Needle forces within +-this are not felt; outside it the band is subtracted, "
                                "so the command is continuous at its edge (N)", 0.0, 10.0)
    max_force_n: float = setting(
        3.0, "Saturation: |command| never exceeds this; set to the device's safe maximum (N)", 0.0, 100.0)
    max_slew_n_per_s: float = setting(100.0, "Slew-rate limit of the command (N/s)", 0.01, 1.0e6)
    stale_timeout_s: float = setting(0.1, "No valid wrench for this long -> ramp the command to zero (s)", 0.001, 10.0)
    ramp_s: float = setting(0.2, "The stale ramp reaches zero within this time; 0 = drop at once (s)", 0.0, 10.0)

    def __post_init__(self) -> None:
        for f, meta in settings_of(type(self)):
            value = getattr(self, f.name)
            low, high = meta["low"], meta["high"]
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ValueError(f"{f.name} must be a finite number, got {value!r}")
            if not low <= value <= high:
                raise ValueError(f"{f.name}={value} is outside [{low}, {high}]")
            object.__setattr__(self, f.name, float(value))

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """Field names: the haptic bridge node declares a parameter of each name."""
        return tuple(f.name for f in fields(cls))


# ---------------------------------------------------------------------- pure rules
def deadband(force_n: float, band_n: float) -> float:
    """Continuous deadband.

    Parameters
    ----------
    force_n : float
        Force, N.
    band_n : float
        Half width of the band, N (>= 0).

    Returns
    -------
    float
        0 inside ``[-band_n, band_n]``, else ``force_n`` moved towards zero by ``band_n`` (N),
        so the output has no step at the band's edge.
    """
    magnitude = abs(force_n) - band_n
    return math.copysign(magnitude, force_n) if magnitude > 0.0 else 0.0


def scale(force_n: float, force_scale: float) -> float:
    """Needle force (N) -> hand force (N): ``force_n * force_scale`` (``force_scale`` in N/N).

    A product beyond the float range is ``+-inf``, which :func:`saturate` turns into the maximum.
    """
    return force_n * force_scale


def saturate(force_n: float, max_n: float) -> float:
    """Clamp a force (N) to ``[-max_n, max_n]`` (``max_n`` in N, >= 0); ``+-inf`` becomes ``+-max_n``."""
    return max(-max_n, min(max_n, force_n))


def slew(current_n: float, target_n: float, max_step_n: float) -> float:
    """Move ``current_n`` towards ``target_n`` by at most ``max_step_n`` (all N).

    Returns
    -------
    float
        ``target_n`` if it is within ``max_step_n`` of ``current_n``, else the point ``max_step_n`` towards it (N).
    """
    delta = target_n - current_n
    if abs(delta) <= max_step_n:
        return target_n
    return current_n + math.copysign(max_step_n, delta)


def stale_ramp(start_n: float, elapsed_s: float, ramp_s: float) -> float:
    """Linear ramp from ``start_n`` (N) to zero over ``ramp_s`` (s), ``elapsed_s`` (s) after its start.

    Returns
    -------
    float
        ``start_n * (1 - elapsed_s / ramp_s)`` while ``elapsed_s < ramp_s``, then exactly 0.0 (N).
        ``ramp_s == 0`` gives 0.0 at once.
    """
    if elapsed_s >= ramp_s:
        return 0.0
    return start_n * (1.0 - max(0.0, elapsed_s) / ramp_s)


def shape(force_n: float, config: HapticConfig) -> float:
    """The target command (N) for a valid needle force (N): deadband, then scale, then saturation."""
    return saturate(scale(deadband(force_n, config.deadband_n), config.force_scale), config.max_force_n)


def parse_axis(axis: str) -> tuple[int, float]:
    """Device axis name (``x``, ``y``, ``z``, ``-x``, ``-y``, ``-z``) -> (index in [x, y, z], sign)."""
    try:
        return AXES[axis.strip().lower()]
    except KeyError:
        raise ValueError(f"device axis must be one of {sorted(AXES)}, got {axis!r}") from None


def device_vector(force_n: float, axis: str, size: int = 3) -> list[float]:
    """A command vector of ``size`` efforts with the force (N) on ``axis`` and zeros elsewhere.

    The layout of a ros2_control effort controller of a Force Dimension device
    (joints ``[fd_x, fd_y, fd_z, (fd_roll, fd_pitch, fd_yaw), (fd_clutch)]``):
    translational forces in N first, in the device base frame.
    """
    index, sign = parse_axis(axis)
    if size < index + 1:
        raise ValueError(f"a command of {size} efforts has no {axis} entry")
    vector = [0.0] * size
    vector[index] = sign * force_n + 0.0  # + 0.0: no negative zero on the wire
    return vector


_RAMP_TOLERANCE_S = 1e-9


def _finite(value: Any) -> bool:
    try:
        return math.isfinite(value)
    except TypeError:
        return False


# ---------------------------------------------------------------------- the bridge
class HapticBridge:
    """Stateful haptic bridge: :meth:`step` on every input sample, :meth:`tick` between them.

    Parameters
    ----------
    config : HapticConfig, optional
        The rules' settings (default: :class:`HapticConfig` ``()``).

    Notes
    -----
    The command starts at zero and stale (no input yet). ``step`` first brings
    the stale rule up to the arrival time (the input may have gone stale before
    this sample arrived; the ramp runs until then), then takes the sample: the
    command slews towards its shaped target by at most the slew rate times the
    stamp step from the previous valid sample. ``tick`` only advances the stale
    rule; it never moves the command towards a target.
    """

    COUNTERS = ("inputs", "invalid", "deadbanded", "saturated", "slew_limited", "stale_events", "recoveries",
                "stamp_jumps")

    def __init__(self, config: HapticConfig | None = None) -> None:
        self.config = config if config is not None else HapticConfig()
        self.counts = dict.fromkeys(self.COUNTERS, 0)
        self.reset()

    def reset(self) -> None:
        """Back to the start state: zero command, stale, no time seen (counters are kept)."""
        self._t: Optional[float] = None           # last arrival time the state was advanced to (s)
        self._last_valid: Optional[float] = None  # arrival time of the last valid input (s)
        self._last_stamp: Optional[float] = None  # stamp of the last valid input (s)
        self._last_input: Optional[float] = None  # last valid needle force (N), re-shaped when the config changes
        self._target = 0.0        # shaped target (N)
        self._command = 0.0       # current command (N)
        self._stale = True
        self._ramp: Optional[tuple[float, float]] = None  # (start time s, start command N) of the running stale ramp

    def configure(self, **changes: float) -> HapticConfig:
        """Change parameters at run time (validated; the target is re-shaped, the command re-saturated at once)."""
        self.config = replace(self.config, **changes)
        if self._last_input is not None and not self._stale:
            self._target = shape(self._last_input, self.config)
        self._command = saturate(self._command, self.config.max_force_n)
        if self._ramp is not None:
            self._ramp = (self._ramp[0], saturate(self._ramp[1], self.config.max_force_n))
        return self.config

    # ------------------------------------------------------------------ state
    @property
    def command(self) -> float:
        """The current command, N (finite, within +-max_force_n)."""
        c = self._command
        return saturate(c, self.config.max_force_n) if math.isfinite(c) else 0.0

    @property
    def target(self) -> float:
        """The shaped target of the last valid input, N (0 while stale)."""
        return self._target

    @property
    def stale(self) -> bool:
        """True before the first valid input and from ``stale_timeout_s`` after the last one."""
        return self._stale

    @property
    def last_valid_s(self) -> Optional[float]:
        """Arrival time of the last valid input, s (None before the first)."""
        return self._last_valid

    # ------------------------------------------------------------------ input / output
    def step(self, now_s: float, force_n: float, stamp_s: float | None = None) -> float:
        """Take one sample of the compensated needle force; returns the command for it.

        Parameters
        ----------
        now_s : float
            Arrival time, s (the clock of :meth:`tick` and of the stale rule).
        force_n : float
            Compensated axial needle force, N (compression positive). Non-finite values are rejected.
        stamp_s : float, optional
            The sample's own time, s (any clock of its source); the slew limit runs on its steps.
            None: the arrival time (as advanced: never earlier than the last one).

        Returns
        -------
        float
            The command after the sample, N.
        """
        self.counts["inputs"] += 1
        if not _finite(now_s) or not _finite(force_n) or (stamp_s is not None and not _finite(stamp_s)):
            self.counts["invalid"] += 1
            if _finite(now_s):
                self._advance(float(now_s))
            return self.command
        now = self._advance(float(now_s))
        stamp = now if stamp_s is None else float(stamp_s)
        force_n = float(force_n)
        target = shape(force_n, self.config)
        if force_n != 0.0 and target == 0.0 and abs(force_n) <= self.config.deadband_n:
            self.counts["deadbanded"] += 1
        if abs(target) >= self.config.max_force_n and target != 0.0:
            self.counts["saturated"] += 1
        if self._stale:  # the first sample after a silence: the command stays where the ramp has brought it
            if self._last_valid is not None:
                self.counts["recoveries"] += 1
        else:
            assert self._last_stamp is not None  # not stale: a valid sample has come
            elapsed = stamp - self._last_stamp
            if 0.0 <= elapsed <= self.config.stale_timeout_s:
                new = slew(self._command, target, self.config.max_slew_n_per_s * elapsed)
                if new != target:
                    self.counts["slew_limited"] += 1
                self._command = new
            else:
                self.counts["stamp_jumps"] += 1
        self._target, self._last_input, self._last_valid, self._last_stamp = target, force_n, now, stamp
        self._stale, self._ramp = False, None
        return self.command

    def tick(self, now_s: float) -> float:
        """Advance the stale rule to ``now_s`` (s): start or run the stale ramp. Returns the command, N."""
        if _finite(now_s):
            self._advance(float(now_s))
        return self.command

    # ------------------------------------------------------------------ internals
    def _advance(self, now: float) -> float:
        if self._t is None:
            self._t = now
            return now
        now = max(now, self._t)
        if not self._stale:
            assert self._last_valid is not None  # not stale: a valid sample has come
            deadline = max(self._last_valid + self.config.stale_timeout_s, self._t)  # max: a shortened timeout
            if now < deadline:  # stale from the instant the input is stale_timeout_s old
                self._t = now
                return now
            self._stale = True
            self._target = 0.0
            self._ramp = (deadline, self._command)
            self.counts["stale_events"] += 1
        if self._ramp is not None:
            self._command = self._ramp_value(self._ramp, now)
            if self._command == 0.0:
                self._ramp = None
        else:
            self._command = 0.0
        self._t = now
        return now

    def _ramp_value(self, ramp: tuple[float, float], now: float) -> float:
        start_s, start_n = ramp
        # exactly zero from start + ramp_s on: compared (not subtracted) with 1 ns to spare, so no
        # rounding of the caller's time arithmetic leaves a residue of force at the end of the ramp
        if now >= start_s + self.config.ramp_s - _RAMP_TOLERANCE_S:
            return 0.0
        return stale_ramp(start_n, now - start_s, self.config.ramp_s)

    def summary(self) -> dict[str, Any]:
        """State and counters for diagnostics."""
        return dict(self.counts, command_n=self.command, target_n=self._target, stale=self._stale, **asdict(self.config))
