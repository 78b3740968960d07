"""Independent split AH for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split AH is a held-out set that stays untouched: it was written without looking at the engine it scores (at how that
engine detects or fits anything), it is run once, and nothing is ever chosen from its results. Each name of the
catalogue is hidden in two shapes that appear neither among the registry's families (``polyforce_ros/sim/truths.py``)
nor in splits A to AG. Every case has a core whose Kelvin spring is at most 20 N/V (its retardation time kept) and
whose flow's viscosity is at most 2.5e4 N s/V:

* a core filled with a magnetorheological fluid beside the robot's electro-permanent magnet gripper: while the gripper
  holds a part (holds of 4-30 s, 8-45 s apart, the field switching over 0.1-0.3 s) the fluid carries a Bingham yield
  of 1-3.5 N and flows at 0.3-0.7 times its field-free fluidity above it; without the field it leaks as a Newtonian
  fluid at 1.5-3 times the plain fluidity of 1/42000-1/3600 V/(N s); or a core of a water-soaked open-cell foam that
  drains through its skin, the leak following Brooks and Corey's relative permeability of the water still held
  (S_e^((2 + 3 lambda) / lambda), lambda 1.5-4; 70-100 % of the drainable water held at the first sample; 1.5-3 times
  the plain fluidity there; the drainable water what 300-1500 s of the plain flow under 3 N would pass), so the leak
  slows as the foam dries; neither ever recovers;
* a Kelvin unit of a crumpled metal foil that creeps by discrete snaps of its folds (each 1-3 % of what 9 N gives it,
  at random times, at a rate that makes the mean creep exponential with 2-20 s: a crackling creep that stops within
  half a snap of its end), or a Kelvin unit damped by an electrorheological fluid energised by the read-out's
  excitation, which the firmware idles once the load has stayed within +-0.5-2 % of the range for 0.8-3 s: its
  retardation of 2-20 s while active falls 4-10 fold while idle, so creep and recovery speed up as soon as the load
  holds still; both settle at 5-23 % of the instantaneous response;
* a spin-crossover (Fe(II) triazole) film between the core and its read-out whose low-spin share, denser, adds to
  the deformation read: a first-order transition with mean-field cooperativity (Slichter and Drickamer, an
  interaction of 2.4-4 RT, bistable above 2 RT) whose metastable branches end at spinodals 8-25 % of the range
  apart, centred at 25-60 % of it, the collapse worth 2-7.5 % of the range; or a hydraulic read-out whose transducer
  port is sealed by a plug of thixotropic gel that moves only once the reading leaves its yield band (half-width
  0.5-0.8 times 1-3.75 % of the range while sliding), its yield growing by 15-40 % per e-fold of (1 + t / 0.5-3 s)
  while it rests and collapsing as soon as it slides;
* a read-out behind a long silicone push-rod that carries the core's push as a stress wave (a Kelvin-Voigt rod,
  exp(-s T / sqrt(1 + s tau)), tau 0.3-2 times T: a transit of T with a dispersion that grows toward high
  frequencies), or a read-out on the robot's CAN bus whose frames queue behind the joint controllers' traffic during
  the robot's moves (2-8 s every 2-12 s), stamped on arrival: the delay 20-40 % of its busy value between moves; 12-100
  ms of delay (the transit, or the busy queue);
* a thermal (hot-film) gap read-out whose heater, driven at constant power, loses heat across the gas gap the core's
  push closes or opens (the gap's conductance as 1 / (gap + a temperature-jump distance of 0.05-0.3 gaps), beside
  other losses 0.4-2 times it: expansive while closing, compressive while opening), or a read-out of the mutual
  inductance of two coaxial coils (radii 0.5-0.95 apart, Maxwell's elliptic-integral formula) whose spacing of
  0.3-1.2 radii the load closes or opens; 5-19 % at the top of the range;
* the zero of a read-out on the robot's forearm whose housing the arm's own motion ventilates (forced convection while
  the arm moves, 1-5 s at 30-100 % of its top speed every 3-20 s: its lag of 50-200 s when still falls toward 4-15 s
  at full speed as the square root of the speed), or of a vibrating-wire read-out whose steel wire, in an aluminium
  frame, slackens as both warm (the tension falling 4-12 % per degC; the zero as the wire's frequency, the square root
  of its tension; lag 8-30 s); 0.008-0.032 V/degC at the reference;
* the span of an optical read-out at 1000-1064 nm whose thin silicon photodiode absorbs near its band edge (the
  absorbed share 1 - exp(-A e^(g dT)), A 0.05-0.8 at the reference: rising as it warms; lag 5-30 s), or of a
  capacitive read-out sampled some time after each charge through a protection diode whose leakage doubles every
  6-10 degC (the charge kept exp(-r e^(a dT)), falling ever faster as it warms; lag 5-25 s); 1.4-3.5 %/degC at the
  reference;
* the zero of a read-out whose window seal is a light-curing resin left under-cured (35-75 % converted), which the
  curing light's exposures (8-30 s every 15-90 s) cure further and shrink (the radicals rising within 0.3-1.5 s and
  living on for 5-40 s of dark cure; each 20 s of full light converting 10-35 % of what remains), or of a read-out
  wired through the robot's tool changer, whose contacts grow a tarnish film (its thickness squared growing linearly,
  Wagner's parabolic law, the film's resistance exponential in its thickness) that each tool change (every 35-140 s,
  the first 0-60 s into the record) wipes back to 0-25 % of it; 20-96 mV at most;
* a needle holder hanging like an elastic pendulum whose axial mode (15-45 Hz) is twice its swinging mode's frequency
  (within 3 %), the knocks 2-8 % off its axis: the swing is pumped parametrically once a knock's axial motion passes
  a threshold (the largest a linear mode would reach is 10-30 % of the hanging length; the swing 0.3-1 times as
  damped) and hands its energy back in beats; or a holder whose spring includes a superelastic NiTi wire (20-45 % of
  its stiffness) that transforms beyond 15-50 % of the largest motion a linear mode would reach (a flag-shaped loop:
  the plateau 3-15 % as stiff, 20-45 % of the wire's force dissipative): large knocks ring softer and die fast, small
  ones ring on; damping ratio 0.0022-0.022 for the pendulum's axial mode (on its coil spring), 0.0034-0.034 for the
  elastic holder;
* a Coulomb band of 0.28-5.5 % of the range: a needle guide whose band the load's own vibration dithers away (the band
  over 1 + (sigma / 0.05-0.3 N)^2, sigma the RMS of the force above 2-5 Hz over the last 0.1-0.4 s), or a needle guide
  floating on an aerostatic bearing fed from the dental unit's air line, which the turbine handpiece's bursts (3-20 s
  every 4-30 s) sag by 35-70 % within 0.3-1 s, recovering over 3-15 s: the bearing lifts fully above 70-85 % of the
  line's pressure (8-20 % of the band remaining) and rests on its pads below 35-55 % of it;
* a core whose dashpots follow Krausser, Samwer and Zaccone's law (ln viscosity as (C / T) exp((2 + lambda) alpha_T (T_g
  - T)), the steepness (2 + lambda) alpha_T 0.005-0.04 per K, T_g 15-60 K below the reference), or a core filled with a
  dense paste of thermoresponsive (PNIPAM) microgels that shrink as it warms, its viscosity following the packing
  fraction as (1 - phi / phi_m)^-2 (0.5-0.58 at the reference, 0.02-0.06 below phi_m; the water's own 2.45 %/degC
  aside): jammed when cool enough; 1.2-1.5 times 0.16-0.48 per degC at the reference, lag 5-25 s.

It also holds six pairs, two effects outside the catalogue (a capacitive read-out that senses the object the tool
approaches, 25-70 mV in contact, rising as (1 + t / 0.1-0.5 s)^-2 of the time left before each contact and falling
likewise after it; a rotary transformer at the robot's continuous wrist whose coupling swings by 3-8 % with the
wrist's angle as its cosine, the wrist turned every 8-40 s by 30-180 degrees either way within 0.6-2.5 s) and four
clean records. Profiles: needle insertions through a series-elastic drive (the measured Okamura insertion,
``../shared/data``, ``time_force.csv``, read as force against depth to the start of its withdrawal and scaled to a
2.2-8.8 N peak; a drive at 0.5-1.6 times the measured speed winds a spring whose give at the peak is 4-30 % of the
insertion's length, so the needle stalls while it winds and snaps ahead when the tissue gives way; a hold of 1.5-6 s
while the tissue relaxes by 8-25 %, the spring unloaded by the retracting drive; sites 6-24 s apart; a train of
synthetic punctures when the data are absent); a robot cracking pistachio shells between its jaws (a Hertzian rise to
a Weibull strength, the shell splitting within 5-20 ms, 0-2 further cracks, the kernel pinched, a shell too strong for
the jaws' 8.6 N turned and pressed again, a hopper refilled every 12-30 nuts); and a robot throwing pots on a wheel
(centring pushes against an eccentric wobble at 2.5-4 rev/s that dies as the clay centres, coning, opening, three or
four pulls of the wall with a light wobble, the pot cut off between). Rates 165, 345, 715 and 1280 Hz (a mode at 1000
Hz with knocks that excite it), 0.53-2.14 mV noise, stamp jitter, gaps, and a sensor on a dental robot in an
operatory: the split air conditioner cycling on its thermostat against the warmth of the people and equipment, the
patient's exhaled breath reaching the sensor while it works at the mouth, the handpiece's water spray cooling it in
bursts, the operating light warming it.

Scoring follows the other splits (``bench/independent_split.py``). With ``--check`` it diagnoses nothing and prints each
case's effect size against its noise (a leak on a Zener base measured against that bare Zener core).

    .venv/bin/python bench/independent_split_ah.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import fft, integrate, ndimage, signal, special

from independent_split import puncture_train
from polyforce_ros.physics.viscoelastic import Burgers
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (ForcePath, GridMode, LeakingCore, Parts, ShapeSplit, SimOnly, band_play, coarse, ease, fit_departure,
                       follow, on_clock, schedule, sized, temp_of, uniform_grid, within)

SEED0 = 2_600_000  # clear of the registry's seeds and of splits A (90000..) to AG (2500000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 435.0
HORIZON_S = DURATION_S + 60.0  # what a schedule drawn for a record covers, its gaps' slack included


# ----------------------------------------------------------------------------- small tools

def softened(c):
    """The drawn Burgers core within the split's limits: a Kelvin spring of at most 20 N/V (the retardation time kept)
    and a flow of at most 2.5e4 N s/V."""
    k2 = min(c.k2_n_per_v, 20.0)
    return Burgers(c.k1_n_per_v, k2, min(c.eta1_n_s_per_v, 2.5e4), c.eta2_n_s_per_v * k2 / c.k2_n_per_v)


def smooth_lag(x, keep, start=None):
    """``x`` through y[i] = keep y[i-1] + (1 - keep) x[i], settled at ``start`` (x[0] when None) before it."""
    y0 = float(x[0]) if start is None else start
    y, _ = signal.lfilter([1.0 - keep], [1.0, -keep], x, zi=[keep * y0])
    return y


def stepwise_lag(x, keep):
    """``x`` through a first-order lag whose retention per step ``keep`` changes from step to step, from x[0]."""
    out, y = np.empty(x.size), float(x[0])
    for i, (xi, k) in enumerate(zip(x.tolist(), keep.tolist())):
        y = xi + (y - xi) * k
        out[i] = y
    return out


def two_speed_lag(x, keep_up, keep_down):
    """``x`` followed with retention ``keep_up`` per step while the state lies below it and ``keep_down`` while
    above, from x[0]."""
    out, y = np.empty(x.size), float(x[0])
    for i, xi in enumerate(x.tolist()):
        y = xi + (y - xi) * (keep_up if xi > y else keep_down)
        out[i] = y
    return out


def hysteron(x, up, down):
    """Per sample: True from a sample at or above ``up`` until the next at or below ``down`` (False before either)."""
    idx = np.arange(x.size)
    last_up = np.maximum.accumulate(np.where(x >= up, idx, -1))
    last_down = np.maximum.accumulate(np.where(x <= down, idx, -1))
    return last_up > last_down


def bouts(rng, every_s, length_s, edge_s, level=(1.0, 1.0), step_s=0.02):
    """A level that is 0 between bouts and, during each, a value drawn from ``level``, eased over ``edge_s`` at both
    ends; bouts of ``length_s`` with gaps of ``every_s`` (:func:`split_kit.schedule`). A function of the seconds since
    the first sample."""
    grid = np.arange(-60.0, HORIZON_S + step_s, step_s)
    out = np.zeros(grid.size)
    for start, length in schedule(rng, every_s, length_s, HORIZON_S):
        height = rng.uniform(*level)
        out = np.maximum(out, height * ease((grid - start) / edge_s) * (1.0 - ease((grid - start - length) / edge_s)))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, out)


def plain_mode(xu, w, zeta, fs):
    """A linear mode of unit gain (``w`` rad/s, damping ratio ``zeta``) driven by ``xu`` on a grid of ``fs`` Hz, from
    rest: its output."""
    b, a = signal.bilinear([w * w], [1.0, 2.0 * zeta * w, w * w], fs=fs)
    return signal.lfilter(b, a, xu)


def ramp_to(a, b, seconds, rate_hz):
    """A minimum-jerk move from ``a`` to ``b`` over ``seconds`` (at least two samples, ``a`` excluded)."""
    n = max(2, int(seconds * rate_hz))
    return a + (b - a) * ease(np.arange(1, n + 1) / n)


# ----------------------------------------------------------------------------- profiles

@functools.lru_cache(maxsize=1)
def insertion_by_depth():
    """The measured Okamura insertion (``../shared/data``, ``time_force.csv``) at 1 kHz read as force against depth (the
    needle advanced at a constant speed, so a millisecond of the record is a step of depth): from its onset to the start
    of its withdrawal, tension clipped, its peak 1. None when the data are absent."""
    try:
        _, fp = profiles.okamura_insertion(peak_n=1.0, rate_hz=1000.0, pre_s=0.0, post_s=0.0)
    except FileNotFoundError:
        return None
    smooth = np.convolve(fp, np.ones(41) / 41.0, mode="same")
    top, onset = int(np.argmax(smooth)), int(np.argmax(smooth > 0.03))
    cruise = float(np.median(smooth[top + 1500:top + 5000]))
    late = smooth[top + 1500:]
    below = np.flatnonzero(late < 0.6 * cruise)
    stop = top + 1500 + (int(below[0]) if below.size else late.size) - 250
    curve = np.clip(fp[onset:stop], 0.0, None)
    return curve / max(float(curve.max()), 1e-9)


def series_elastic_insertions(duration_s, rate_hz, rng):
    """Needle insertions through a series-elastic drive. The tissue's resistance is the measured insertion read against
    depth (:func:`insertion_by_depth`), scaled to a 2.2-8.8 N peak; the drive advances at 0.5-1.6 times the measured
    speed and winds a spring whose give at the peak is 4-30 % of the insertion's length. Quasi-statically the needle
    stays put while the spring's force is below the resistance where it stands and advances to the first depth whose
    resistance holds the spring back: it stalls while the spring winds and snaps ahead where the tissue gives way.
    At the end a hold of 1.5-6 s in which the tissue relaxes the force by 8-25 % over 0.5-2.5 s, then the drive
    retracts at 0.5-1.5 times its speed and unloads the spring. Sites 6-24 s apart; a train of synthetic punctures
    when the data are absent."""
    curve = insertion_by_depth()
    if curve is None:
        return puncture_train(duration_s, rate_hz, rng)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    depth = np.arange(curve.size, dtype=float)  # milliseconds of the measured advance
    cursor = rng.uniform(1.0, 6.0)
    while True:
        peak = rng.uniform(2.2, 8.8)
        give = rng.uniform(0.04, 0.3) * curve.size / peak  # depth per newton of the spring
        passed = np.maximum.accumulate(give * peak * curve + depth)  # the drive's travel at which each depth is passed
        speed = rng.uniform(0.5, 1.6) * 1000.0
        drive = np.arange(int(passed[-1] / speed * rate_hz) + 2) * speed / rate_hz
        needle = np.minimum(np.searchsorted(passed, drive), curve.size - 1)
        push = np.clip((drive - needle) / give, 0.0, None)
        hold_s, relax, settle = rng.uniform(1.5, 6.0), rng.uniform(0.08, 0.25), rng.uniform(0.5, 2.5)
        u = np.arange(int(hold_s * rate_hz)) / rate_hz
        held = push[-1] * (1.0 - relax * (1.0 - np.exp(-u / settle)))
        back = rng.uniform(0.5, 1.5) * speed / give  # newtons per second shed by the retracting drive
        last = float(held[-1]) if held.size else float(push[-1])
        unload = np.clip(last - np.arange(1, int(last / back * rate_hz) + 2) * back / rate_hz, 0.0, None)
        one = np.concatenate([push, held, unload])
        i0 = int(cursor * rate_hz)
        if i0 + one.size >= t.size:
            break
        f[i0:i0 + one.size] = one
        cursor += one.size / rate_hz + rng.uniform(6.0, 24.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def pistachio_cracking(duration_s, rate_hz, rng):
    """A robot cracking pistachio shells between its jaws. Each shell's strength is a Weibull draw (scale 2.8-7 N,
    modulus 3-8); the jaws close at a constant speed, so the force rises as the power 1.5 of the time (Hertz), reaching
    5 N in 0.15-0.8 s. A shell too strong for the jaws' 8.6 N is held there for 0.3-1 s, released, turned within
    0.4-1.2 s and pressed again, weakened to 60-90 %. The shell splits within 5-20 ms to 15-45 % of its strength,
    cracks 0-2 times more (re-loading within 50-200 ms to 35-75 % of it and dropping to 20-60 % of that), the kernel is
    pinched at 0.25-1 N for 0.2-0.6 s and the jaws open within 0.05-0.2 s. Shells 0.8-3.5 s apart; the hopper is
    refilled for 8-25 s every 12-30 shells."""
    knot_t, knot_f = [0.0], [0.0]

    def add(dt, level):
        knot_t.append(knot_t[-1] + max(dt, 1e-4))
        knot_f.append(level)

    add(rng.uniform(0.5, 3.0), 0.0)
    count, refill, limit = 0, int(rng.integers(12, 31)), 8.6
    while knot_t[-1] < duration_s:
        strength = rng.uniform(2.8, 7.0) * (-math.log(1.0 - rng.random())) ** (1.0 / rng.uniform(3.0, 8.0))
        while True:
            top = min(strength, limit)
            rise = rng.uniform(0.15, 0.8) * (top / 5.0) ** (2.0 / 3.0)
            for u in np.linspace(0.1, 1.0, 10):
                add(0.1 * rise, top * u ** 1.5)
            if strength <= limit:
                break
            add(rng.uniform(0.3, 1.0), limit)
            add(rng.uniform(0.08, 0.2), 0.0)
            add(rng.uniform(0.4, 1.2), 0.0)
            strength *= rng.uniform(0.6, 0.9)
        add(rng.uniform(0.005, 0.02), strength * rng.uniform(0.15, 0.45))
        for _ in range(int(rng.integers(0, 3))):
            again = strength * rng.uniform(0.35, 0.75)
            add(rng.uniform(0.05, 0.2), again)
            add(rng.uniform(0.005, 0.02), again * rng.uniform(0.2, 0.6))
        kernel = rng.uniform(0.25, 1.0)
        add(rng.uniform(0.03, 0.1), kernel)
        add(rng.uniform(0.2, 0.6), kernel * rng.uniform(0.85, 1.05))
        add(rng.uniform(0.05, 0.2), 0.0)
        add(rng.uniform(0.8, 3.5), 0.0)
        count += 1
        if count >= refill:
            add(rng.uniform(8.0, 25.0), 0.0)
            count, refill = 0, int(rng.integers(12, 31))
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    return t, np.clip(np.interp(t, knot_t, knot_f), 0.0, FORCE_MAX_N)


def one_pot(rng, rate_hz):
    """The force on the throwing rib for one pot (see :func:`pottery_throwing`)."""
    h = 1.0 / rate_hz
    parts, clock = [], 0.0
    spin, wobble, centred = rng.uniform(2.5, 4.0), rng.uniform(0.2, 0.5), rng.uniform(3.0, 10.0)
    phase = rng.uniform(0.0, 2.0 * math.pi)
    rest = rng.uniform(0.3, 0.8)

    def wobbling(level):
        nonlocal clock
        u = clock + np.arange(level.size) * h
        clock = float(u[-1]) + h
        return level * (1.0 + wobble * np.exp(-u / centred) * np.sin(2.0 * math.pi * spin * u + phase))

    parts.append(ramp_to(0.0, rest, 0.4, rate_hz))
    for _ in range(int(rng.integers(2, 4))):  # centring pushes
        push, up, hold = rng.uniform(2.5, 6.0), rng.uniform(0.8, 2.0), rng.uniform(4.0, 10.0)
        u = np.arange(int((up + hold + 0.6) * rate_hz)) * h
        parts.append(wobbling(rest + (push - rest) * ease(u / up) * (1.0 - ease((u - up - hold) / 0.6))))
        parts.append(wobbling(np.full(int(rng.uniform(0.5, 1.5) * rate_hz), rest)))
    for _ in range(int(rng.integers(2, 4))):  # coning up and down
        cone, half = rng.uniform(1.0, 3.0), rng.uniform(1.5, 3.0)
        u = np.arange(int(2.0 * half * rate_hz)) * h
        parts.append(wobbling(rest + (cone - rest) * np.sin(math.pi * u / (2.0 * half)) ** 2))
    opening, up, hold = rng.uniform(1.5, 4.0), rng.uniform(2.0, 5.0), rng.uniform(1.0, 3.0)
    u = np.arange(int((up + hold) * rate_hz)) * h
    parts.append(wobbling(rest + (opening - rest) * ease(u / up)))
    parts.append(ramp_to(parts[-1][-1], 0.0, 0.4, rate_hz))
    pull_spin = rng.uniform(1.5, 2.5)
    for _ in range(int(rng.integers(3, 5))):  # pulling the wall up
        parts.append(np.zeros(int(rng.uniform(1.0, 3.0) * rate_hz)))
        grip, length, ripple = rng.uniform(0.8, 2.5), rng.uniform(3.0, 8.0), rng.uniform(0.05, 0.15)
        u = np.arange(int(length * rate_hz)) * h
        level = grip * (1.0 - 0.35 * u / length) * ease(u / 0.3)
        parts.append(level * (1.0 + ripple * np.sin(2.0 * math.pi * pull_spin * u + rng.uniform(0.0, 6.3))))
        parts.append(ramp_to(parts[-1][-1], 0.0, 0.1, rate_hz))
    return np.clip(np.concatenate(parts), 0.0, None)


def pottery_throwing(duration_s, rate_hz, rng):
    """A robot throwing pots on a wheel, the sensor in its rib's holder. Each pot: two or three centring pushes of
    2.5-6 N (reached in 0.8-2 s, held 4-10 s) against clay spinning at 2.5-4 rev/s, whose eccentricity makes the force
    wobble at the wheel's frequency by 20-50 % at first, dying with 3-10 s as the clay centres (the rib resting on it
    at 0.3-0.8 N between pushes); two or three conings up to 1-3 N and down (1.5-3 s each way); the opening (1.5-4 N
    within 2-5 s, held 1-3 s); three or four pulls of the wall at 1.5-2.5 rev/s (0.8-2.5 N easing off by a third
    toward the rim over 3-8 s, a wobble of 5-15 %, the rib leaving the rim within 0.1 s, 1-3 s between pulls). The
    pot is cut off and replaced for 12-30 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    pieces = [np.zeros(int(rng.uniform(0.5, 4.0) * rate_hz))]
    total = pieces[0].size
    while total < t.size:
        pot = one_pot(rng, rate_hz)
        gap = np.zeros(int(rng.uniform(12.0, 30.0) * rate_hz))
        pieces += [pot, gap]
        total += pot.size + gap.size
    return t, np.clip(np.concatenate(pieces)[:t.size], 0.0, FORCE_MAX_N)


PROFILES = (series_elastic_insertions, pistachio_cracking, pottery_throwing)


def dental_operatory(t, rng, step_s=0.5):
    """A sensor on a dental robot in an operatory, simulated from 900 s before the record. The people and equipment warm
    the room toward 2-5 degC above the reference; a split air conditioner set within 1 degC of the reference (a
    dead band of 0.8-2 degC, a cooling capacity of 4-8 degC, the room settling with 80-300 s) cycles against
    them. The robot works at the patient's mouth for 20-120 s at a time, 10-60 s apart, moving in and out over 2-4 s:
    there the patient's exhaled breath warms the air about the sensor by 2-5 degC (more on each exhalation, 12-20
    breaths a minute), the operating light warms it by 0.5-1.5 degC (through 30-90 s), and the handpiece's water spray,
    in bursts of 3-20 s every 5-40 s, cools it by 2-4 degC (within 1-3 s, recovering over 5-20 s). The sensor follows
    with 4-12 s (exact per step of ``step_s``)."""
    s = t - t[0]
    d = float(s[-1]) if s[-1] > 0 else 1.0
    grid = np.arange(-900.0, d + 2.0 * step_s, step_s)
    since = grid + 900.0
    warmth = T_REF_C + rng.uniform(2.0, 5.0)
    setpoint, band = T_REF_C + rng.uniform(-1.0, 1.0), rng.uniform(0.8, 2.0)
    capacity, settle = rng.uniform(4.0, 8.0), math.exp(-step_s / rng.uniform(80.0, 300.0))
    room, cooling, air = np.empty(grid.size), False, setpoint + rng.uniform(-0.5, 0.5)
    for i in range(grid.size):
        cooling = air > setpoint + 0.5 * band or (cooling and air > setpoint - 0.5 * band)
        target = warmth - capacity * cooling
        air = target + (air - target) * settle
        room[i] = air
    edge = rng.uniform(2.0, 4.0)
    mouth = np.zeros(grid.size)
    for start, length in schedule(rng, (10.0, 60.0), (20.0, 120.0), d + 1000.0):
        mouth = np.maximum(mouth, ease((since - start) / edge) * (1.0 - ease((since - start - length) / edge)))
    breaths = rng.uniform(12.0, 20.0) / 60.0
    exhale = np.maximum(np.sin(2.0 * math.pi * breaths * since + rng.uniform(0.0, 6.3)), 0.0)
    breath = rng.uniform(2.0, 5.0) * mouth * (0.55 + 0.45 * exhale)
    light = smooth_lag(rng.uniform(0.5, 1.5) * mouth, math.exp(-step_s / rng.uniform(30.0, 90.0)), start=0.0)
    running = within(since, schedule(rng, (5.0, 40.0), (3.0, 20.0), d + 1000.0)) & (mouth > 0.5)
    spray = two_speed_lag(rng.uniform(2.0, 4.0) * running, math.exp(-step_s / rng.uniform(1.0, 3.0)),
                          math.exp(-step_s / rng.uniform(5.0, 20.0)))
    sensor = smooth_lag(room + breath + light - spray, math.exp(-step_s / rng.uniform(4.0, 12.0)))
    return np.interp(s, grid, sensor)


# ----------------------------------------------------------------------------- viscous flow

def magnetorheological_leak(fluidity, yield_n, plastic, field):
    """The leak of a magnetorheological fill: Newtonian at ``fluidity`` V/(N s) without the field; under it (``field``,
    0-1, of the seconds since the first sample) a Bingham fluid with a yield of ``yield_n`` flowing at ``plastic`` times
    that fluidity on the force above it."""
    def rule(t, f):
        on = field(t - t[0])
        rate = fluidity * ((1.0 - on) * f + on * plastic * np.maximum(f - yield_n, 0.0))
        return integrate.cumulative_trapezoid(rate, t, initial=0.0)
    return rule


def draining_foam_leak(fluidity0, held0, drainable_v, exponent):
    """The leak of a water-soaked foam through its skin at a fluidity that follows the water still held, S, as S^
    ``exponent`` (Brooks and Corey): ``fluidity0`` V/(N s) at the first sample, where ``held0`` of the ``drainable_v``
    is held. With dS/dt = -(phi / V) F S^n the held share is (S0^(1-n) + (n - 1) (phi / V) I)^(-1 / (n - 1)), I the
    force's impulse."""
    def rule(t, f):
        impulse = integrate.cumulative_trapezoid(f, t, initial=0.0)
        k = fluidity0 / held0 ** exponent / drainable_v
        held = (held0 ** (1.0 - exponent) + (exponent - 1.0) * k * impulse) ** (-1.0 / (exponent - 1.0))
        return drainable_v * (held0 - held)
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def crumpled_foil_kelvin(t, f, compliance, tau_s, snap_v, seed, step_s=0.005):
    """A Kelvin unit (``compliance`` V/N) of a crumpled foil whose folds snap one at a time: the deformation moves by
    ``snap_v`` toward its goal at random times, at a hazard of |goal - u| / (``tau_s`` snap_v) (a mean creep exponential
    with tau_s), and stops within half a snap of the goal. Per step of ``step_s``, from rest; the snaps' timing drawn
    from ``seed``."""
    grid, fg = coarse(t, f, step_s)
    waits = np.random.default_rng(seed).exponential(1.0, 4096)
    scale, half = step_s / (tau_s * snap_v), 0.5 * snap_v
    u, hazard, k = 0.0, 0.0, 0
    out = np.empty(grid.size)
    for i, goal in enumerate((compliance * fg).tolist()):
        gap = goal - u
        if abs(gap) < half:
            hazard = 0.0
        else:
            hazard += abs(gap) * scale
            while abs(gap) >= half and hazard >= waits[k % waits.size]:
                hazard -= waits[k % waits.size]
                k += 1
                u += snap_v if gap > 0.0 else -snap_v
                gap = goal - u
        out[i] = u
    return np.interp(t, grid, out)


def idling_er_kelvin(t, f, compliance, tau_active_s, thinning, band_n, still_s, step_s=0.01):
    """A Kelvin unit (``compliance`` V/N) damped by an electrorheological fluid that the read-out's excitation energises:
    the firmware idles the excitation once the load has stayed within +-``band_n`` for ``still_s`` and wakes it at the
    next change beyond that; the fluid answers within 0.1 s, its retardation ``tau_active_s`` while energised and
    ``thinning`` times shorter while idle. Exact per step of ``step_s``, from rest."""
    grid, fg = coarse(t, f, step_s)
    w = max(2, int(round(still_s / step_s)))
    high = ndimage.maximum_filter1d(fg, w, mode="nearest", origin=(w - 1) // 2)  # over the last still_s
    low = ndimage.minimum_filter1d(fg, w, mode="nearest", origin=(w - 1) // 2)
    active = smooth_lag(((high - low) > 2.0 * band_n).astype(float), math.exp(-step_s / 0.1))
    tau = tau_active_s * (1.0 / thinning + (1.0 - 1.0 / thinning) * active)
    out, u = np.empty(grid.size), 0.0
    for i, (goal, keep) in enumerate(zip((compliance * fg).tolist(), np.exp(-step_s / tau).tolist())):
        u = goal + (u - goal) * keep
        out[i] = u
    return np.interp(t, grid, out)


# ----------------------------------------------------------------------------- hysteresis

class SpinCrossoverFilm(SimOnly):
    """A spin-crossover film read with the core's push: its low-spin share m adds ``collapse_v`` m to the reading. The
    share follows Slichter and Drickamer's mean-field law, x = c + a (ln(m / (1 - m)) + g (1 - 2 m)), g ``coop`` (above
    2: bistable), on the lower branch up to its spinodal, on the upper one down to its own; the spinodals ``width_v``
    apart about ``centre_v``. The film starts low-spin."""

    def __init__(self, centre_v, width_v, coop, collapse_v):
        root = math.sqrt(1.0 - 2.0 / coop)
        self.coop, self.c, self.d = coop, centre_v, collapse_v
        m1, m2 = 0.5 * (1.0 - root), 0.5 * (1.0 + root)  # the spinodals
        self.a = width_v / (2.0 * self.h(m1))
        self.up, self.down = self.c + self.a * self.h(m1), self.c + self.a * self.h(m2)
        self.m_low = np.concatenate([np.geomspace(1e-9, 1e-2, 200), np.linspace(1e-2, m1, 400)[1:]])
        self.m_high = 1.0 - self.m_low[::-1]  # the upper branch mirrors the lower one (m2 = 1 - m1)

    def h(self, m):
        return np.log(m / (1.0 - m)) + self.coop * (1.0 - 2.0 * m)

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        low = np.interp(x, self.c + self.a * self.h(self.m_low), self.m_low)
        high = np.interp(x, self.c + self.a * self.h(self.m_high), self.m_high)
        share = np.where(hysteron(x, self.up, self.down), high, low)
        return x + self.d * (share - share[0])


class GelPlugPort(SimOnly):
    """A read-out whose transducer port is sealed by a plug of thixotropic gel: the plug (the reading) moves only once
    the core's output leaves its yield band, of half-width ``slide_v`` (1 + ``ageing`` ln(1 + r / ``age_s``)), r the
    time it has rested; sliding breaks it back to slide_v. Started at the first value."""

    def __init__(self, slide_v, ageing, age_s):
        self.r, self.beta, self.tau = slide_v, ageing, age_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        dt = np.diff(t, prepend=t[0]).tolist()
        plug, rested = float(x[0]), 0.0
        out = np.empty(x.size)
        for i, xi in enumerate(x.tolist()):
            rested += dt[i]
            r = self.r * (1.0 + self.beta * math.log1p(rested / self.tau))
            if xi - plug > r:
                plug, rested = xi - self.r, 0.0
            elif plug - xi > r:
                plug, rested = xi + self.r, 0.0
            out[i] = plug
        return out


# ----------------------------------------------------------------------------- sensor lag

class PushRod(SimOnly):
    """The core's push carried to the read-out by a long Kelvin-Voigt rod: exp(-s ``transit_s`` / sqrt(1 + s
    ``smear_s``)), run by FFT on a uniform grid at the median step, from rest (the record continued at its last value,
    then brought back to rest, so nothing wraps)."""

    def __init__(self, transit_s, smear_s):
        self.T, self.tau = transit_s, smear_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        pad = int(max(2.0, 40.0 * (self.T + self.tau)) / h)
        z = np.concatenate([xu - xu[0], np.full(pad, xu[-1] - xu[0]), np.zeros(pad)])
        size = fft.next_fast_len(z.size, real=True)
        s = 2j * math.pi * fft.rfftfreq(size, h)
        y = fft.irfft(fft.rfft(z, size) * np.exp(-s * self.T / np.sqrt(1.0 + s * self.tau)), size)[:xu.size]
        return np.interp(t, tu, y + xu[0])


class BusQueue(SimOnly):
    """Frames queued on a shared bus and stamped on arrival: the reading at t is the core's output at t - d, d
    ``idle_s`` plus (``busy_s`` - idle_s) times the traffic (``traffic(seconds)``, 0-1)."""

    def __init__(self, idle_s, busy_s, traffic):
        self.idle, self.busy, self.traffic = idle_s, busy_s, traffic

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        late = self.idle + (self.busy - self.idle) * self.traffic(t - t[0])
        return np.interp(t - late, t, x, left=x[0])


# ----------------------------------------------------------------------------- nonlinear gain

def thermal_gap_read(rel, reach, jump, shunt, closing):
    """x read by a hot-film heater at constant power across a gas gap that the core's push closes (``closing``) or opens
    by a share k of the gap over ``reach``: its temperature 1 / (1 / (gap + ``jump``) + ``shunt``) in units of the gap,
    the reading its change scaled to slope 1 at no load, k for a departure of ``rel`` at reach (expansive while
    closing, compressive while opening)."""
    sign = -1.0 if closing else 1.0

    def heater(u, k):
        return 1.0 / (1.0 / np.maximum(1.0 + jump + sign * k * u, 1e-3) + shunt)

    def read(x, k):
        u = np.clip(x / reach, -0.2, 1.3)
        slope = (heater(1e-6, k) - heater(0.0, k)) / 1e-6
        return (heater(u, k) - heater(0.0, k)) / slope * reach
    return fit_departure(read, rel, reach, 0.95 * (1.0 + jump) / 1.3 if closing else 5.0)


def coil_mutual(gap, ratio):
    """The mutual inductance (in mu0 units) of coaxial loops of radii 1 and ``ratio`` ``gap`` apart (Maxwell)."""
    k2 = 4.0 * ratio / ((1.0 + ratio) ** 2 + gap ** 2)
    k = np.sqrt(k2)
    return math.sqrt(ratio) * ((2.0 / k - k) * special.ellipk(k2) - 2.0 / k * special.ellipe(k2))


def coaxial_coils_read(rel, reach, ratio, gap0, closing):
    """x read as the mutual inductance of two coaxial coils (radii 1 and ``ratio``) whose spacing ``gap0`` the core's
    push closes (``closing``) or opens by k over ``reach``: slope 1 at no load, k for a departure of ``rel`` at
    reach."""
    sign = -1.0 if closing else 1.0

    def read(x, k):
        u = np.clip(x / reach, -0.2, 1.3)
        base = coil_mutual(gap0, ratio)
        slope = (coil_mutual(gap0 + sign * k * 1e-6, ratio) - base) / 1e-6
        return (coil_mutual(np.maximum(gap0 + sign * k * u, 0.02), ratio) - base) / slope * reach
    return fit_departure(read, rel, reach, (gap0 - 0.03) / 1.3 if closing else 3.0)


# ----------------------------------------------------------------------------- thermal drift

def ventilated_housing_zero(t, temp, k_v_per_c, still_s, moving_s, motion, step_s=0.5):
    """The zero of a read-out on the robot's forearm, ``k_v_per_c`` of its housing's departure from the reference; the
    housing follows the air through a lag of ``still_s`` when the arm is still, its conductance growing with the square
    root of the arm's speed (``motion(seconds)``, 0-1) toward that of ``moving_s`` at full speed. Exact per step."""
    grid, air = coarse(t, temp, step_s)
    speed = np.sqrt(np.clip(motion(grid - t[0]), 0.0, 1.0))
    keep = np.exp(-step_s * (1.0 / still_s + (1.0 / moving_s - 1.0 / still_s) * speed))
    return k_v_per_c * (np.interp(t, grid, stepwise_lag(air, keep)) - T_REF_C)


def vibrating_wire_zero(t, temp, k_v_per_c, slack, lag_s):
    """The zero of a vibrating-wire read-out whose wire's tension falls by ``slack`` per degC of the gauge's departure
    (lag ``lag_s``): the frequency's change, as the square root of the tension, ``k_v_per_c`` per degC at the reference
    (held above 5 % of the tension)."""
    d = follow(t, temp, lag_s) - T_REF_C
    return k_v_per_c * 2.0 / slack * (1.0 - np.sqrt(np.maximum(1.0 - slack * d, 0.05)))


# ----------------------------------------------------------------------------- thermal sensitivity

class BandEdgeSpan(SimOnly):
    """The span of an optical read-out on a thin silicon photodiode near its band edge: the absorbed share 1 -
    exp(-A e^(g dT)) over its value at the reference, A ``depth`` there, g for ``tc`` per degC at the reference; dT
    on the photodiode (lag ``lag_s``)."""

    def __init__(self, tc, depth, lag_s):
        self.A, self.lag = depth, lag_s
        self.g = tc * (1.0 - math.exp(-depth)) / (depth * math.exp(-depth))

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = np.clip(follow(t, temp_of(aux, t.size), self.lag) - T_REF_C, -20.0, 20.0)
        share = (1.0 - np.exp(-self.A * np.exp(self.g * d))) / (1.0 - math.exp(-self.A))
        return np.asarray(x, dtype=float) * share


class LeakyNodeSpan(SimOnly):
    """The span of a capacitive read-out whose sense node leaks through a protection diode between its charge and its
    sampling: the charge kept exp(-r e^(a dT)) over its value at the reference, the leakage doubling every
    ``doubling_c`` (a = ln 2 / doubling_c), r for ``tc`` per degC at the reference; dT on the input stage (lag
    ``lag_s``)."""

    def __init__(self, tc, doubling_c, lag_s):
        self.a, self.lag = math.log(2.0) / doubling_c, lag_s
        self.r = tc / self.a

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = np.clip(follow(t, temp_of(aux, t.size), self.lag) - T_REF_C, -20.0, 20.0)
        return np.asarray(x, dtype=float) * np.exp(-self.r * (np.exp(self.a * d) - 1.0))


# ----------------------------------------------------------------------------- offset drift

def photo_cured_seal(rng, step_s=0.1):
    """The zero of a read-out whose window seal is an under-cured light-curing resin, as its conversion: the curing
    light's exposures (8-30 s every 15-90 s) raise the radicals within 0.3-1.5 s, which live on for 5-40 s after
    (dark cure); the conversion advances as k R (1 - X), k converting 10-35 % of what remains in 20 s of full light,
    from 35-75 %. As a function of the seconds since the first sample, zero there."""
    grid = np.arange(-60.0, HORIZON_S + step_s, step_s)
    lit = within(grid, schedule(rng, (15.0, 90.0), (8.0, 30.0), HORIZON_S)).astype(float)
    radicals = two_speed_lag(lit, math.exp(-step_s / rng.uniform(0.3, 1.5)), math.exp(-step_s / rng.uniform(5.0, 40.0)))
    k = -math.log(1.0 - rng.uniform(0.1, 0.35)) / 20.0
    converted = 1.0 - (1.0 - rng.uniform(0.35, 0.75)) * np.exp(-k * np.cumsum(radicals) * step_s)
    first = float(np.interp(0.0, grid, converted))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, converted) - first


def tarnishing_contacts(rng, step_s=0.1):
    """The zero of a read-out wired through the tool changer's contacts, as the tarnish film's resistance, e^(b h) - 1
    (b 1-2.5): the film's thickness squared grows by one unit per 60-300 s (Wagner's parabolic law), from 0.2-1.5 units
    60 s before the first sample; each tool change (every 35-140 s, the first 0-60 s into the record) wipes it to
    0-25 % of its thickness. As a function of the seconds since the first sample, zero there."""
    grid = np.arange(-60.0, HORIZON_S + step_s, step_s)
    unit_s, b = rng.uniform(60.0, 300.0), rng.uniform(1.0, 2.5)
    changes = [rng.uniform(0.0, 60.0)]
    while changes[-1] < HORIZON_S:
        changes.append(changes[-1] + rng.uniform(35.0, 140.0))
    squared, start, since = np.empty(grid.size), rng.uniform(0.2, 1.5), -60.0
    for edge in changes + [np.inf]:
        sel = (grid >= since) & (grid < edge)
        squared[sel] = start + (grid[sel] - since) / unit_s
        if not np.isfinite(edge):
            break
        start = (rng.uniform(0.0, 0.25) ** 2) * (start + (edge - since) / unit_s)
        since = edge
    film = np.exp(b * np.sqrt(squared)) - 1.0
    first = float(np.interp(0.0, grid, film))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, film) - first


# ----------------------------------------------------------------------------- resonance

class SpringPendulum(GridMode):
    """A needle holder hanging like an elastic pendulum: its axial mode at ``axial_hz`` (damping ratio ``zeta``), its
    swing at half that times ``tune`` (damping ratio ``zeta_swing``), the hanging length such that the largest axial
    motion a linear mode would reach is ``reach`` of it, the drive ``skew`` off its axis. The reading is the drive plus
    the axial motion (L + z) cos(theta) - L. Semi-implicit Euler on a uniform grid of ``fs`` Hz, from rest."""

    fs = 3000.0

    def __init__(self, axial_hz, zeta, tune, zeta_swing, reach, skew):
        self.w1, self.zeta, self.zeta2 = 2.0 * math.pi * axial_hz, zeta, zeta_swing
        self.w2, self.reach, self.skew = math.pi * axial_hz * tune, reach, skew

    def on_grid(self, t, tu, xu, h):
        zmax = max(float(np.max(np.abs(plain_mode(xu, self.w1, self.zeta, self.fs) - xu))), 1e-12)
        length = zmax / self.reach
        g, w1s = self.w2 * self.w2 * length, self.w1 * self.w1
        c1, c2, skew = 2.0 * self.zeta * self.w1, 2.0 * self.zeta2 * self.w2, self.skew
        accel = np.gradient(np.gradient(xu, h), h).tolist()
        z = vz = th = vth = 0.0
        out = np.empty(tu.size)
        for i, (ui, ai) in enumerate(zip(xu.tolist(), accel)):
            arm, felt = length + z, g - ai
            sin_t, cos_t = math.sin(th), math.cos(th)
            vz += (arm * vth * vth + felt * cos_t - g - w1s * z - c1 * vz) * h
            vth += ((-felt * sin_t - skew * ai * cos_t - 2.0 * vz * vth) / arm - c2 * vth) * h
            z += vz * h
            th += vth * h
            out[i] = ui + (length + z) * math.cos(th) - length
        return out


class SuperelasticHolder(GridMode):
    """A holder's mode at ``f0_hz`` (damping ratio ``zeta``) whose spring includes a superelastic NiTi wire carrying
    ``share`` of its stiffness: the wire's force a flag, (1 - ``loss``) of it self-centring (its stiffness falling to
    ``plateau`` beyond the onset) and ``loss`` of it elastic-perfectly-plastic, both yielding at ``onset`` of the largest
    motion a linear mode would reach. Semi-implicit Euler on a uniform grid of ``fs`` Hz, from rest."""

    fs = 3000.0

    def __init__(self, f0_hz, zeta, share, onset, plateau, loss):
        self.w, self.zeta, self.share = 2.0 * math.pi * f0_hz, zeta, share
        self.onset, self.plateau, self.loss = onset, plateau, loss

    def on_grid(self, t, tu, xu, h):
        zmax = max(float(np.max(np.abs(plain_mode(xu, self.w, self.zeta, self.fs) - xu))), 1e-12)
        zs, share, loss, soft = self.onset * zmax, self.share, self.loss, self.plateau
        ws, c = self.w * self.w, 2.0 * self.zeta * self.w
        accel = np.gradient(np.gradient(xu, h), h).tolist()
        z = vz = slip = 0.0
        out = np.empty(tu.size)
        for i, (ui, ai) in enumerate(zip(xu.tolist(), accel)):
            size = abs(z)
            centring = z if size <= zs else math.copysign(zs + soft * (size - zs), z)
            if z - slip > zs:
                slip = z - zs
            elif slip - z > zs:
                slip = z + zs
            wire = (1.0 - loss) * centring + loss * (z - slip)
            vz += (-ai - c * vz - ws * ((1.0 - share) * z + share * wire)) * h
            z += vz * h
            out[i] = ui + z
        return out


# ----------------------------------------------------------------------------- friction

def self_dithered_guide(t, f, band_n, corner_hz, window_s, dither_n):
    """The force passed by a needle guide whose band the load's own vibration dithers away: ``band_n`` / (1 + (sigma /
    ``dither_n``)^2), sigma the RMS of the force above ``corner_hz`` (a second-order high-pass) over the last
    ``window_s`` (a first-order average of its square). Started at the first force."""
    tu, fu, h = uniform_grid(t, f)
    b, a = signal.butter(2, corner_hz, btype="high", fs=1.0 / h)
    shake = signal.lfilter(b, a, fu - fu[0])
    sigma = np.sqrt(smooth_lag(shake * shake, math.exp(-h / window_s), start=0.0))
    band = np.interp(t, tu, band_n / (1.0 + (sigma / dither_n) ** 2))
    return band_play(f, band, band)


class AirBearingGuide(SimOnly):
    """The force passed by a needle guide on an aerostatic bearing fed from the dental unit's air line (``supply(seconds)``,
    1 at its usual pressure): the band ``band_n`` times ``floor`` while the pressure is above ``lift``, all of it below
    ``touch``, in proportion between. Started at the first force."""

    def __init__(self, band_n, floor, lift, touch, supply):
        self.band, self.floor, self.lift, self.touch, self.supply = band_n, floor, lift, touch, supply

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        contact = np.clip((self.lift - self.supply(t - t[0])) / (self.lift - self.touch), 0.0, 1.0)
        band = self.band * (self.floor + (1.0 - self.floor) * contact)
        return band_play(np.asarray(x, dtype=float), band, band)


def air_line_pressure(rng, step_s=0.02):
    """The dental unit's air-line pressure (1 at rest) as a function of the seconds since the first sample: the turbine
    handpiece's bursts (3-20 s every 4-30 s) sag it by 35-70 % within 0.3-1 s, the compressor bringing it back over
    3-15 s."""
    grid = np.arange(-60.0, HORIZON_S + step_s, step_s)
    running = within(grid, schedule(rng, (4.0, 30.0), (3.0, 20.0), HORIZON_S)).astype(float)
    dip = two_speed_lag(rng.uniform(0.35, 0.7) * running, math.exp(-step_s / rng.uniform(0.3, 1.0)),
                        math.exp(-step_s / rng.uniform(3.0, 15.0)))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, 1.0 - dip)


# ----------------------------------------------------------------------------- thermo-rheological

class ZacconeClock(SimOnly):
    """A core whose dashpots follow Krausser, Samwer and Zaccone's law, ln eta = (C / T) exp(q (T_g - T)), q ``steep``
    per K, T_g ``below_k`` under the reference, C for ``b_per_c`` per degC at the reference. On the core's temperature
    (lag ``lag_s``), the clock held within e^+-6."""

    def __init__(self, c, b_per_c, below_k, steep, lag_s):
        self.c, self.q, self.lag = c, steep, lag_s
        self.tr = T_REF_C + 273.15
        self.tg = self.tr - below_k
        self.cc = b_per_c / (math.exp(steep * (self.tg - self.tr)) * (1.0 / self.tr ** 2 + steep / self.tr))

    def log_shift(self, kelvin):
        return self.cc * (np.exp(self.q * (self.tg - kelvin)) / kelvin - math.exp(self.q * (self.tg - self.tr)) / self.tr)

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag) + 273.15
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(-self.log_shift(body), -6.0, 6.0)))


class MicrogelPasteClock(SimOnly):
    """A core filled with a paste of thermoresponsive microgels: their packing fraction ``packing`` at the reference
    shrinks as exp(-s dT) as they deswell, the paste's viscosity following (1 - phi / phi_m)^-2 (phi_m ``margin``
    above the packing) times the water's own (-2.45 %/degC), s for ``b_per_c`` per degC in all at the reference. On
    the core's temperature (lag ``lag_s``), the clock held within e^+-6 (jammed at phi_m)."""

    water = 0.0245

    def __init__(self, c, b_per_c, packing, margin, lag_s):
        self.c, self.z, self.zm, self.lag = c, packing, packing + margin, lag_s
        self.s = max(b_per_c - self.water, 0.01) * margin / (2.0 * packing)

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        free = np.maximum(1.0 - self.z * np.exp(-self.s * d) / self.zm, 1e-6) / (1.0 - self.z / self.zm)
        log_rate = 2.0 * np.log(free) + self.water * d
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(log_rate, -6.0, 6.0)))


# ----------------------------------------------------------------------------- outside the catalogue

def proximity_pickup(t, f, size_v, contact_n, approach_s, retreat_s):
    """A capacitive read-out's pickup of the object the tool approaches: ``size_v`` in contact (the force above
    ``contact_n``), (1 + t / ``approach_s``)^-2 of the time left before the next contact and (1 + t / ``retreat_s``)^-2 of
    the time since the last, the larger; none without contact."""
    touching = t[f > contact_n]
    if touching.size == 0:
        return np.zeros_like(t)
    nxt = np.searchsorted(touching, t)
    ahead = np.where(nxt < touching.size, touching[np.minimum(nxt, touching.size - 1)] - t, np.inf)
    prev = np.searchsorted(touching, t, side="right") - 1
    behind = np.where(prev >= 0, t - touching[np.maximum(prev, 0)], np.inf)
    return size_v * np.maximum((1.0 + ahead / approach_s) ** -2, (1.0 + behind / retreat_s) ** -2)


def wrist_angles(rng, step_s=0.02):
    """The robot's wrist angle (rad) as a function of the seconds since the first sample: turned every 8-40 s by 30-180
    degrees either way within 0.6-2.5 s (minimum jerk)."""
    grid = np.arange(-60.0, HORIZON_S + step_s, step_s)
    angle = np.full(grid.size, rng.uniform(0.0, 2.0 * math.pi))
    at = rng.uniform(-20.0, 30.0)
    while at < HORIZON_S:
        turn, length = math.radians(rng.uniform(30.0, 180.0)) * rng.choice([-1.0, 1.0]), rng.uniform(0.6, 2.5)
        sel = grid >= at
        angle[sel] = float(np.interp(at, grid, angle)) + turn * ease((grid[sel] - at) / length)
        at += length + rng.uniform(8.0, 40.0)
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, angle)


class RotaryCoupler(SimOnly):
    """A rotary transformer at the robot's continuous wrist: its coupling (1 + ``depth`` cos(angle - ``phase``)) over its
    value at the first sample, the angle ``angle(seconds)``."""

    def __init__(self, depth, phase, angle):
        self.depth, self.phase, self.angle = depth, phase, angle

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        coupling = 1.0 + self.depth * np.cos(self.angle(t - t[0]) - self.phase)
        return np.asarray(x, dtype=float) * coupling / coupling[0]


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):
    c = softened(c)
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # V: roughly what 9 N gives at once
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([4.2e4, 3.6e3]))))  # V / (N s)
        if shape == "mr_fluid_core":
            field = bouts(rng, (8.0, 45.0), (4.0, 30.0), rng.uniform(0.1, 0.3))
            rule = magnetorheological_leak(phi * rng.uniform(1.5, 3.0), rng.uniform(1.0, 3.5), rng.uniform(0.3, 0.7), field)
        else:
            rule = draining_foam_leak(phi * rng.uniform(1.5, 3.0), rng.uniform(0.7, 1.0), phi * 3.0 * rng.uniform(300.0, 1500.0),
                                      2.0 / rng.uniform(1.5, 4.0) + 3.0)
        return Parts("zener", LeakingCore.of(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        comp = float(np.interp(m, [0, 1], [0.05, 0.23])) / g0  # of the instantaneous response, V / N
        if shape == "crumpled_foil_kelvin":
            a = (comp, rng.uniform(2.0, 20.0), rng.uniform(0.01, 0.03) * comp * FORCE_MAX_N, int(rng.integers(1 << 30)))
            p.extra.append(lambda t, f, T, a=a: crumpled_foil_kelvin(t, f, *a))
            return p
        a = (comp, rng.uniform(2.0, 20.0), rng.uniform(4.0, 10.0), rng.uniform(0.005, 0.02) * FORCE_MAX_N,
             rng.uniform(0.8, 3.0))
        p.extra.append(lambda t, f, T, a=a: idling_er_kelvin(t, f, *a))
        return p
    if effect == "hysteresis":
        wid = float(np.interp(m, [0, 1], [0.02, 0.075]))
        if shape == "spin_crossover_film":
            p.after.append(SpinCrossoverFilm(rng.uniform(0.25, 0.6) * top, rng.uniform(0.08, 0.25) * top,
                                             rng.uniform(2.4, 4.0), wid * top))
            return p
        p.after.append(GelPlugPort(0.5 * wid * top * rng.uniform(0.5, 0.8), rng.uniform(0.15, 0.4), rng.uniform(0.5, 3.0)))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.012, 0.1]))))
        if shape == "viscoelastic_pushrod":
            p.after.append(PushRod(delay, rng.uniform(0.3, 2.0) * delay))
            return p
        p.after.append(BusQueue(rng.uniform(0.2, 0.4) * delay, delay, bouts(rng, (2.0, 12.0), (2.0, 8.0), 0.3)))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.05, 0.19]))
        closing = bool(rng.random() < 0.5)
        if shape == "thermal_gap_gauge":
            p.after.append(StaticMap(thermal_gap_read(rel, top, rng.uniform(0.05, 0.3), rng.uniform(0.4, 2.0), closing)))
            return p
        p.after.append(StaticMap(coaxial_coils_read(rel, top, rng.uniform(0.5, 0.95), rng.uniform(0.3, 1.2), closing)))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.008, 0.032]) * rng.choice([-1, 1]))
        if shape == "ventilated_housing":
            a = (k, rng.uniform(50.0, 200.0), rng.uniform(4.0, 15.0), bouts(rng, (3.0, 20.0), (1.0, 5.0), 0.4, (0.3, 1.0)))
            p.extra.append(lambda t, f, T, a=a: ventilated_housing_zero(t, T, *a))
            return p
        a = (k, rng.uniform(0.04, 0.12), rng.uniform(8.0, 30.0))
        p.extra.append(lambda t, f, T, a=a: vibrating_wire_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        tc = float(np.interp(m, [0, 1], [0.014, 0.035]))
        if shape == "band_edge_photodiode":
            p.after.append(BandEdgeSpan(tc, rng.uniform(0.05, 0.8), rng.uniform(5.0, 30.0)))
            return p
        p.after.append(LeakyNodeSpan(tc, rng.uniform(6.0, 10.0), rng.uniform(5.0, 25.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.02, 0.096]) * rng.choice([-1, 1]))
        zero = sized(photo_cured_seal(rng) if shape == "photo_cured_seal" else tarnishing_contacts(rng), size, HORIZON_S)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.028, 0.0042])) * rng.uniform(0.8, 1.2)
        if shape == "spring_pendulum":
            axial = 0.65 * zeta  # a coil spring, lighter damped than the holders' joints
            p.after.append(SpringPendulum(rng.uniform(15.0, 45.0), axial, rng.uniform(0.97, 1.03), axial * rng.uniform(0.3, 1.0),
                                          rng.uniform(0.1, 0.3), rng.uniform(0.02, 0.08)))
            return p
        p.after.append(SuperelasticHolder(rng.uniform(15.0, 45.0), zeta, rng.uniform(0.2, 0.45), rng.uniform(0.15, 0.5),
                                          rng.uniform(0.03, 0.15), rng.uniform(0.2, 0.45)))
        return p
    if effect == "friction":
        band = float(np.interp(m, [0, 1], [0.0035, 0.046]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "self_dithered_guide":
            a = (band, rng.uniform(2.0, 5.0), rng.uniform(0.1, 0.4), rng.uniform(0.05, 0.3))
            p.before.append(ForcePath(lambda t, x, a=a: self_dithered_guide(t, x, *a)))
            return p
        p.before.append(AirBearingGuide(band, rng.uniform(0.08, 0.2), rng.uniform(0.7, 0.85), rng.uniform(0.35, 0.55),
                                        air_line_pressure(rng)))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.16, 0.48])) * rng.uniform(1.2, 1.5)
        if shape == "zaccone_clock":
            return Parts("burgers", ZacconeClock(c, b, rng.uniform(15.0, 60.0), rng.uniform(0.005, 0.04),
                                                 rng.uniform(5.0, 25.0)), core_changed=True)
        return Parts("burgers", MicrogelPasteClock(c, b, rng.uniform(0.5, 0.58), rng.uniform(0.02, 0.06),
                                                   rng.uniform(5.0, 25.0)), core_changed=True)
    if effect == "object_proximity":
        a = (float(np.interp(m, [0.4, 0.9], [0.025, 0.07])), rng.uniform(0.03, 0.1), rng.uniform(0.1, 0.5),
             rng.uniform(0.1, 0.5))
        p.extra.append(lambda t, f, T, a=a: proximity_pickup(t, f, *a))
        return p
    if effect == "rotary_coupler":
        depth = float(np.interp(m, [0.4, 0.9], [0.03, 0.08]))
        p.outer.append(RotaryCoupler(depth, rng.uniform(0.0, 2.0 * math.pi), wrist_angles(rng)))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["mr_fluid_core", "draining_foam_core"],
    "delayed_elasticity": ["crumpled_foil_kelvin", "idling_er_kelvin"],
    "hysteresis": ["spin_crossover_film", "gel_plug_port"],
    "sensor_lag": ["viscoelastic_pushrod", "bus_queue"],
    "nonlinear_gain": ["thermal_gap_gauge", "coaxial_coils"],
    "thermal_drift": ["ventilated_housing", "vibrating_wire"],
    "thermal_sensitivity": ["band_edge_photodiode", "leaky_sample_node"],
    "offset_drift": ["photo_cured_seal", "tarnishing_contacts"],
    "resonance": ["spring_pendulum", "superelastic_holder"],
    "friction": ["self_dithered_guide", "air_bearing_guide"],
    "thermo_rheological": ["zaccone_clock", "microgel_paste"],
}
PAIRS = (("sensor_lag", "viscous_flow"), ("friction", "nonlinear_gain"), ("thermal_sensitivity", "hysteresis"),
         ("delayed_elasticity", "thermal_drift"), ("resonance", "offset_drift"), ("thermo_rheological", "sensor_lag"))
OUTSIDE = ("object_proximity", "rotary_coupler")
RATES = (165.0, 345.0, 715.0, 1280.0)  # 4 rates against 3 profiles: each profile meets each rate


SPLIT = ShapeSplit("independent split AH", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.34, 0.82),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=dental_operatory,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(0.53e-3, 2.14e-3), jitter=0.29,
                   gap_s=(0.14, 1.75))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
