"""Independent split AG for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split AG is an untouched held-out set: written blind to the engine it measures (to how it detects and fits anything),
run once, and nothing is ever chosen from it. Every name of the catalogue is hidden in two shapes that neither the
registry's families (``polyforce_ros/sim/truths.py``) nor splits A to AF use, on a core whose Kelvin spring is at most
20 N/V (its retardation time kept) and whose flow's viscosity is at most 2.5e4 N s/V, in every case alike:

* a fluid-filled core whose elastomer skin has slits that the bulge opens (the open share a logistic in the force,
  its midpoint at 1.5-4 N, 0.3-1 N wide, followed through the skin's lag, 0.2-1 s opening and 2-10 s closing; the
  open skin leaks at 2-4 times the plain fluidity of 1/36000-1/3400 V/(N s), the shut slits 10-30 % of that), or a
  core leaking through a sintered filter whose fines migrate (the log of its fluidity a smooth random process, an
  Ornstein-Uhlenbeck process of 0.3-0.6 e-folds RMS correlated over 40-150 s, about 1.3-2.3 times the plain fluidity
  on average); neither ever recovers;
* a Kelvin unit whose clock follows the free volume its own dilatation opens (Knauss and Emri: Doolittle's law on a
  free-volume fraction of 0.025 at rest, the dilatation the core's instantaneous and retarded deformation, 3-10
  times faster at what 9 N gives; 2-20 s at rest: creep speeding up under heavy loads, recovery slowing as it nears
  rest), or a pad of glass beads in a latex skin, a jamming pad, whose Kelvin unit settles 4-12 times faster while the
  robot's moves shake it (moves of 1-6 s every 6-30 s; 10-40 s at rest); both settle at 4.5-22 % of the
  instantaneous response;
* a rack and pinion turning a rotary encoder with backlash (a play of 1.8-7 % of the range), whose firmware adds a
  backlash step at each reversal it sees, set to 30-70 % or 130-170 % of the true backlash: the reading stays put
  after each reversal, then jumps and goes on with a residual offset of either sign; or a subranging read-out whose
  firmware steps a coarse offset DAC (steps of 6-14 % of the range) to keep its fine ADC within a window that
  overlaps the next step's by 50-90 % of a step, the DAC's codes each off by its own residual of up to 0.5-1 times
  1.8-7 % of the range (uniform, independent): the code in use, and so the error, depends on the way the reading came;
* a battery-powered wireless node that samples every 1.8-2.6 delays while the reading is still and every 0.5-0.8
  delays for 0.4-1.5 s after a sample that moved by more than 0.4-1.5 % of the range, each sample held until the
  next, behind a radio latency of 0.2-0.35 delays; or a fibre Bragg grating read-out whose interrogator tracks the
  grating's reflection peak with a dither-locked laser (a first-order servo whose error signal is the derivative of
  a Lorentzian line 0.5-1.1 times the range wide: large fast changes are followed ever more slowly); 11-100 ms of
  delay (the servo's for small changes);
* an absorbance read-out of a dyed plunger that the core's push drives into the beam (the absorbance 0.1-0.4 at rest
  and 1.6-2.6 at the top of the range, read with stray light around the plunger: compressive), or the diffuse
  reflectance of a scattering (TiO2-filled) silicone layer over a black backing, which the load thins (Kubelka and
  Munk, an optical thickness of 0.6-2.5 at rest and an absorption of 2-30 % of the scattering: expansive); 5.2-19 %
  at the top of the range;
* the zero of a fluid-filled cylindrical read-out whose water-glycol fill expands with a coefficient rising 3-8 % per
  degC, its mean temperature following the air through radial conduction in the cylinder (the Bessel series of a
  cylinder with a surface film, Biot number 2-12, R^2 / alpha 60-300 s), or of a read-out whose holder carries a
  bimetal snap disc (a thermal cut-out, lag 8-30 s) that snaps through above the 40-75th percentile of its
  temperature over the record and back 0.8-2 degC lower, pressing the housing by what 2-4 degC of the coefficient
  gives, either way, through a pad of 1-4 s, beside a linear zero of 30-60 % of the coefficient; 0.008-0.032
  V/degC;
* the span of an iontronic capacitive read-out whose double layer is read at a fixed frequency through the gel's
  ionic resistance (Arrhenius; omega R C 0.8-1.6 at the reference: the span rises as it warms, levelling off; lag 5-30
  s), or of an inductive read-out through a MnZn ferrite biased toward its saturation by a magnet (the incremental
  permeability as (1 - B / B_s)^p, p 0.8-2, B_s falling 0.25-0.4 %/degC, biased at 60-95 % of it: falling ever faster
  as it warms; lag 10-40 s); 1.3-3.4 %/degC at the reference;
* the zero of a read-out whose offset-trim register is upset by the electrical fast transients of the field
  generator's switched loads (one every 25-80 s on average, each flipping one of its six upper bits, the bit's weight
  doubling from one to the next) until the firmware rewrites the register from its EEPROM copy (every 20-60 s), or
  of a fluid-filled read-out filled with a residual air bubble that dissolves into the degassed fill (Epstein and
  Plesset with surface tension, a Laplace length of 0.1-1 initial radii, filled 0-300 s before the first sample and
  gone 0.5-2.5 records after it; the zero as the bubble's volume); 18-95 mV at most;
* a needle holder's mode (15-45 Hz) with a Lanchester damper (a brass ring of 10-30 % of the moving mass riding in a
  friction-lined groove: it rides along below its slip force, 15-50 % of what the largest knock's acceleration
  needs, and slides above it), or a slender holder whose two bending planes ring at nearly the same frequency
  (0.97-1.03 apart), coupled by its geometric stretching (a quartic potential, hardening 15-50 % at the largest
  motion a linear mode would reach), the knocks 3-12 % off the read plane: large knocks set it whirling; damping
  ratio 0.0038-0.037 (the stuck ring's, the read plane's);
* a Coulomb band of 0.24-5.4 % of the range: a needle guide on a carriage riding a slightly bent guide rod (the
  band 1 + kappa s^2 along it, kappa 1-3, normalised over the rod; the robot moves the carriage every 15-60 s over
  1-4 s), or a needle guide cantilevered off its carriage whose thrust acts off its axis (the moment presses the
  guide's shoes on the rail, the preload's moment balancing the thrust's at 2-5 N: the band 20-40 % there, growing as
  the distance of the passed force from that balance, at most three times the band);
* a core whose dashpots follow the configuron law of Douglas, Doremus and Ojovan (viscosity as T (1 + A e^(B / T))
  (1 + C e^(D / T)): the slope switching from B + D to B as it warms through a crossover near the reference, D
  30-60 % of the slope there, its share 30-80 % through the crossover), or Adam and Gibbs's law with the
  configurational entropy of two-level defects (a Schottky entropy, the gap 4-9 times the reference temperature); 1.2
  to 1.5 times 0.17-0.5 per degC at the reference, lag 5-25 s.

It also holds six pairs, two effects outside the catalogue (a slow automatic gain control in the read-out, which
divides the reading by its own envelope over 4-20 s to the power 0.3-0.7, held within 2-4 times either way; an input
crowbar that trips whenever the reading passes 80-92 % of the record's largest and holds the output at the bridge's
zero for 0.24-2.4 s) and four clean records. Profiles: a CT-guided lung biopsy under breath holds (the measured Okamura
insertion, ``../shared/data``, ``time_force.csv``, at 0.6-1.6 times its length and a 2.4-8.8 N peak, cut at 1-3
points; between breath holds the needle is held for 6-15 s while the tissue relaxes by 5-20 % and the breathing lung
swings it by 8-25 % at 12-20 breaths a minute, a cough in one break of five; after the last breath hold the measured
withdrawal; sites 8-25 s apart; a train of synthetic punctures when the data are absent); a robotic sewing head, the
sensor in its presser-foot bar (a preload of 1-3.5 N while a seam is sewn, stitches at 2-6 Hz through 2-4 plies that the
needle's piercing pushes away from the foot and its withdrawal and the feed dog drive up under it, seam crossings that
double the plies and lift the foot, pivots at corners, the fabric moved between seams); and a strawberry-harvesting
gripper (a grasp, a pull with a twist until the peduncle yields and snaps, a carry that swings, a release into the
punnet; a fifth of the fruits slip from the grip and are grasped again; a longer move to the next plant now and
then). Rates 115, 275, 605 and 1175 Hz (a mode at 1000 Hz with knocks that
excite it), 0.66-2.22 mV noise, stamp jitter, gaps, and a sensor on a robot in an expeditionary field hospital tent:
the sun warming the tent through passing clouds, an environmental control unit cooling it on a thermostat, its
supply air near the duct, the vestibule door letting in hot gusts at the far end, the robot moving between them.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size against its
noise without diagnosing (for a leak on a Zener base, against that bare Zener core).

    .venv/bin/python bench/independent_split_ag.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, optimize, signal, special

from independent_split import puncture_train
from polyforce_ros.physics.viscoelastic import Burgers
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (ForcePath, GridMode, LeakingCore, Parts, ShapeSplit, SimOnly, band_play, coarse, ease, fit_departure,
                       follow, lagged, logistic, on_clock, schedule, sized, temp_of, within)

SEED0 = 2_500_000  # never a seed of the registry's splits nor of splits A (90000..) to AF (2400000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 445.0
HORIZON_S = DURATION_S + 60.0  # what a schedule drawn before the record covers (the record plus its gaps' slack)


# ----------------------------------------------------------------------------- small tools

def chase(goal, rise, fall):
    """A state that approaches ``goal`` (per grid step) keeping ``rise`` of the distance when below it and ``fall``
    when above it, from ``goal[0]``."""
    out, y = np.empty(goal.size), float(goal[0])
    for i, g in enumerate(goal.tolist()):
        y = g + (y - g) * (rise if g > y else fall)
        out[i] = y
    return out


def relay(x, on, off):
    """Per sample: True from a sample above ``on`` until the next below ``off`` (True at the start when above ``on``)."""
    idx = np.arange(x.size)
    last_on = np.maximum.accumulate(np.where(x > on, idx, -1))
    last_off = np.maximum.accumulate(np.where(x < off, idx, -1))
    return last_on > last_off


def resampled(y, seconds, rate_hz):
    """``y`` stretched over ``seconds`` at ``rate_hz`` (at least two samples)."""
    n = max(2, int(round(seconds * rate_hz)))
    return np.interp(np.linspace(0.0, y.size - 1.0, n), np.arange(y.size), y)


def linear_mode(xu, w, zeta, fs):
    """A linear unit-gain mode (``w`` rad/s, ``zeta``, bilinear at ``fs``) driven by ``xu`` from rest: its output."""
    b, a = signal.bilinear([w * w], [1.0, 2.0 * zeta * w, w * w], fs=fs)
    return signal.lfilter(b, a, xu)


def soft(c):
    """The core kept soft enough for its creep to show: its Kelvin spring at most 20 N/V (the retardation time kept),
    its flow's viscosity at most 2.5e4 N s/V."""
    k2 = min(c.k2_n_per_v, 20.0)
    return Burgers(c.k1_n_per_v, k2, min(c.eta1_n_s_per_v, 2.5e4), c.eta2_n_s_per_v * k2 / c.k2_n_per_v)


def ou_process(rng, horizon_s, corr_s, step_s=0.5, lead_s=600.0):
    """A unit-variance Ornstein-Uhlenbeck process correlated over ``corr_s``: (grid of seconds since the first sample,
    values), from ``lead_s`` before it."""
    grid = np.arange(-lead_s, horizon_s + step_s, step_s)
    keep = math.exp(-step_s / corr_s)
    drive = rng.normal(0.0, math.sqrt(1.0 - keep * keep), grid.size)
    out, _ = signal.lfilter([1.0], [1.0, -keep], drive, zi=[keep * rng.normal()])
    return grid, out


def robot_moves(rng, every_s, length_s, horizon_s=HORIZON_S, step_s=0.02, edge_s=0.15):
    """Whether the robot is moving, eased over ``edge_s`` at each end, as a function of the seconds since the first
    sample: moves of ``length_s`` every ``every_s`` (:func:`split_kit.schedule`)."""
    grid = np.arange(-60.0, horizon_s + step_s, step_s)
    level = np.zeros(grid.size)
    for start, length in schedule(rng, every_s, length_s, horizon_s):
        level = np.maximum(level, ease((grid - start) / edge_s) * (1.0 - ease((grid - start - length) / edge_s)))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, level)


# ----------------------------------------------------------------------------- profiles and temperature

@functools.lru_cache(maxsize=1)
def measured_insertion():
    """The measured Okamura insertion (``../shared/data``, ``time_force.csv``) at 1 kHz, its peak 1, from its onset to
    the end of its withdrawal, tension clipped: (the curve, the index where the withdrawal begins). None when the data
    are absent."""
    try:
        _, fp = profiles.okamura_insertion(peak_n=1.0, rate_hz=1000.0, pre_s=0.0, post_s=0.0)
    except FileNotFoundError:
        return None
    s = np.convolve(fp, np.ones(25) / 25.0, mode="same")
    onset, peak = int(np.argmax(s > 0.03)), int(np.argmax(s))
    level = float(np.median(s[peak + 1000:peak + 6000]))
    late = s[peak + 2000:]
    below = late < 0.7 * level
    w0 = peak + 2000 + (int(np.argmax(below)) if np.any(below) else late.size - 1) - 150
    tail = s[w0:]
    end = w0 + (int(np.argmax(tail <= 0.005)) if np.any(tail <= 0.005) else tail.size - 1)
    curve = np.clip(fp[onset:end + 1], 0.0, None)
    curve[-1] = 0.0
    return curve, w0 - onset


def breath_hold_biopsy(duration_s, rate_hz, rng):
    """A CT-guided lung biopsy under breath holds: the measured Okamura insertion (:func:`measured_insertion`) at 0.6-1.6
    times its length and a 2.4-8.8 N peak, cut at 1-3 points (15-90 % of the way in). Between breath holds the needle
    is held for 6-15 s: the tissue relaxes by 5-20 % over 0.5-2 s and the breathing lung swings the force by 8-25 % at
    12-20 breaths a minute (easing in over 1 s and out over 0.5 s before the next hold), a cough in one break of five
    (+30-80 % for 0.15-0.4 s); each resumed advance rejoins the curve over 0.2 s. After the last hold the measured
    withdrawal. Sites 8-25 s apart; a train of synthetic punctures when the data are absent."""
    parts = measured_insertion()
    if parts is None:
        return puncture_train(duration_s, rate_hz, rng)
    curve, w0 = parts
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cursor = rng.uniform(1.0, 5.0)
    while True:
        speed = rng.uniform(0.6, 1.6)
        ins = resampled(curve[:w0], w0 / 1000.0 * speed, rate_hz) * rng.uniform(2.4, 8.8)
        cuts = np.sort((rng.uniform(0.15, 0.9, int(rng.integers(1, 4))) * ins.size).astype(int))
        pieces = np.split(ins, cuts)
        segs = []
        for k, piece in enumerate(pieces):
            piece = piece.copy()
            if segs and piece.size:
                nb = min(piece.size, max(2, int(0.2 * rate_hz)))
                start = segs[-1][-1]
                piece[:nb] = start + (piece[:nb] - start) * ease(np.arange(nb) / nb)
            if piece.size:
                segs.append(piece)
            if k == len(pieces) - 1 or not segs:
                continue
            dur = rng.uniform(6.0, 15.0)
            u = np.arange(int(dur * rate_hz)) / rate_hz
            level = segs[-1][-1] * (1.0 - rng.uniform(0.05, 0.2) * (1.0 - np.exp(-u / rng.uniform(0.5, 2.0))))
            env = ease(u / 1.0) * (1.0 - ease((u - (dur - 1.3)) / 0.5))
            swing = rng.uniform(0.08, 0.25) * env * np.sin(2.0 * np.pi * rng.uniform(12.0, 20.0) / 60.0 * u
                                                           + rng.uniform(0.0, 2.0 * np.pi))
            hold = level * (1.0 + swing)
            if rng.random() < 0.2:
                at, width = rng.uniform(1.0, max(1.5, dur - 2.0)), rng.uniform(0.15, 0.4)
                hold = hold * (1.0 + rng.uniform(0.3, 0.8) * np.clip(1.0 - np.abs(u - at) / (0.5 * width), 0.0, 1.0))
            segs.append(hold)
        out = resampled(curve[w0:] / max(float(curve[w0]), 1e-6), (curve.size - w0) / 1000.0 * speed, rate_hz)
        one = np.clip(np.concatenate(segs + [segs[-1][-1] * out]), 0.0, None)
        i0 = int(cursor * rate_hz)
        if i0 + one.size >= t.size - 1:
            break
        f[i0:i0 + one.size] = one
        cursor += one.size / rate_hz + rng.uniform(8.0, 25.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def robotic_sewing(duration_s, rate_hz, rng):
    """A robotic sewing head, the sensor in its presser-foot bar. Seams of 6-20 s stitched at 2-6 Hz through 2-4 plies:
    the foot is lowered onto the fabric at each seam's start (0.2-0.4 s) with a spring preload of 1-3.5 N and lifted at
    its end (0.15-0.3 s). In each stitch the needle's piercing pushes the plies down and away from the foot (a dip of
    5-12 % of the preload per ply after 5-20 % of the cycle), the needle's withdrawal drags them up against it (0.2-0.8 N
    times the square root of the plies, peaking at 57 % of the cycle) and the feed dog drives them up under it (0.4-1.5 N
    over 55-95 % of the cycle). 0-2 seam crossings per seam double the plies for 0.4-1.5 s and lift the foot against its
    spring (0.5-1.5 N more); in half the seams a pivot at a corner stops the stitching for 1-3 s with the foot eased to
    30-60 % of its preload. The fabric is moved for 3-12 s between seams."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cursor = rng.uniform(0.5, 3.0)
    while cursor < duration_s:
        seam, stitch_hz = rng.uniform(6.0, 20.0), rng.uniform(2.0, 6.0)
        preload, plies0 = rng.uniform(1.0, 3.5), float(rng.integers(2, 5))
        dip, drag, feed = rng.uniform(0.05, 0.12), rng.uniform(0.2, 0.8), rng.uniform(0.4, 1.5)
        lower, lift = rng.uniform(0.2, 0.4), rng.uniform(0.15, 0.3)
        i0, i1 = np.searchsorted(t, [cursor, cursor + seam])
        u = t[i0:i1] - cursor
        plies, ride = np.full(u.size, plies0), np.zeros(u.size)
        for at in rng.uniform(0.1, 0.9, int(rng.integers(0, 3))) * seam:
            width = rng.uniform(0.4, 1.5)
            on = ease((u - at) / 0.1) * (1.0 - ease((u - at - width) / 0.1))
            plies = plies * (1.0 + on)
            ride = ride + rng.uniform(0.5, 1.5) * on
        clock, foot = u * stitch_hz, np.ones(u.size)
        if rng.random() < 0.5:
            at, stop = rng.uniform(0.2, 0.8) * seam, rng.uniform(1.0, 3.0)
            eased = 1.0 - (1.0 - rng.uniform(0.3, 0.6)) * ease((u - at) / 0.2) * (1.0 - ease((u - at - stop) / 0.2))
            clock = np.where(u < at, clock, np.where(u < at + stop, at * stitch_hz, clock - stop * stitch_hz))
            foot = eased
        phase = clock - np.floor(clock)
        stitching = foot > 0.999
        pierce = preload * dip * plies * np.clip(1.0 - np.abs(phase - 0.125) / 0.075, 0.0, 1.0)
        pull = drag * np.sqrt(plies) * np.clip(1.0 - np.abs(phase - 0.57) / np.where(phase < 0.57, 0.03, 0.1), 0.0, 1.0)
        dog = feed * np.sin(np.pi * np.clip((phase - 0.55) / 0.4, 0.0, 1.0)) ** 2
        level = (preload + ride) * foot + stitching * (pull + dog - pierce)
        f[i0:i1] = np.maximum(level, 0.0) * ease(u / lower) * (1.0 - ease((u - seam + lift) / lift))
        cursor += seam + rng.uniform(3.0, 12.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def strawberry_harvest(duration_s, rate_hz, rng):
    """A strawberry-harvesting gripper. Each fruit: a grasp closing to 0.5-1.8 N in 0.2-0.5 s, a pull at 1-4 N/s whose
    rise slows as the peduncle yields (concave, 1 - e^(-k u), k 1-2.5), twisted at 1.5-4 Hz (+-10-25 %), until the
    peduncle snaps at 2.5-8.8 N (the force falling within 5-20 ms to the grip plus the fruit's 0.2-0.6 N), a carry of
    1.5-3 s that swings by 0.2-0.6 N at 1-2.5 Hz (dying over 0.5-1.5 s), a release over 0.2-0.5 s. A fifth of the fruits
    slip from the grip at 50-85 % of the snap force (down to 0.2-0.5 N in 50 ms) and are grasped again after 0.5-1.5 s.
    Fruits 2-8 s apart; every 6-12 fruits the robot moves to the next plant for 10-25 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    h = 1.0 / rate_hz
    cursor, count, next_move = rng.uniform(0.5, 3.0), 0, int(rng.integers(6, 13))

    def ramp(a, b, seconds):
        n = max(2, int(seconds * rate_hz))
        return a + (b - a) * ease(np.arange(1, n + 1) / n)

    while cursor < duration_s:
        grip, snap = rng.uniform(0.5, 1.8), rng.uniform(2.5, 8.8)
        pull, bend = rng.uniform(1.0, 4.0), rng.uniform(1.0, 2.5)
        twist_hz, twist = rng.uniform(1.5, 4.0), rng.uniform(0.1, 0.25)
        parts = [ramp(0.0, grip, rng.uniform(0.2, 0.5))]
        tries = [rng.uniform(0.5, 0.85) * snap, snap] if rng.random() < 0.2 else [snap]
        for j, top in enumerate(tries):
            span = max(top - grip, 0.05)
            n = max(2, int(span / pull * (1.0 + 0.3 * bend) * rate_hz))
            u = np.arange(1, n + 1) / n
            rise = grip + span * (1.0 - np.exp(-bend * u)) / (1.0 - math.exp(-bend))
            tw = 1.0 + twist * np.sin(2.0 * np.pi * twist_hz * u * n * h) * ease(u * n * h / 0.3) * (1.0 - ease((u - 0.9) / 0.1))
            parts.append(rise * tw)
            if j < len(tries) - 1:
                low = rng.uniform(0.2, 0.5)
                parts += [ramp(top, low, 0.05), np.full(int(rng.uniform(0.5, 1.5) * rate_hz), low), ramp(low, grip, 0.3)]
        held = grip + rng.uniform(0.2, 0.6)
        parts.append(ramp(parts[-1][-1], held, rng.uniform(0.005, 0.02)))
        carry = rng.uniform(1.5, 3.0)
        u = np.arange(int(carry * rate_hz)) * h
        parts.append(held + rng.uniform(0.2, 0.6) * np.sin(2.0 * np.pi * rng.uniform(1.0, 2.5) * u)
                     * np.exp(-u / rng.uniform(0.5, 1.5)))
        parts.append(ramp(parts[-1][-1], 0.0, rng.uniform(0.2, 0.5)))
        one = np.clip(np.concatenate(parts), 0.0, None)
        i0 = int(cursor * rate_hz)
        n = min(one.size, t.size - i0)
        if n <= 0:
            break
        f[i0:i0 + n] = one[:n]
        cursor += one.size * h + rng.uniform(2.0, 8.0)
        count += 1
        if count >= next_move:
            cursor += rng.uniform(10.0, 25.0)
            count, next_move = 0, int(rng.integers(6, 13))
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (breath_hold_biopsy, robotic_sewing, strawberry_harvest)


def field_tent(t, rng, step_s=0.5):
    """A sensor on a robot in an expeditionary field hospital tent, from 900 s before the record. The sun-warmed air
    outside the tent 1.5-4 degC above the reference plus a solar gain of 1-2.5 degC through the fabric (lag 60-180 s)
    that passing clouds (20-120 s each, 30-150 s apart) cut by 40-80 %. An environmental control unit cools the tent on
    a thermostat (set within 1.2 degC of the reference, a dead band of 0.8-1.8 degC, a cooling capacity of 4-8 degC, the
    tent's air settling with 150-400 s). The robot works near the unit's duct (35 %), mid-tent (40 %) or at the far end
    by the vestibule door (25 %), 40-150 s at a time with 3-10 s moves: the duct's supply air is 1-3 degC colder while
    the unit runs (mixing over 5-15 s), the far end 0.3-1 degC warmer, and the door, opened every 60-300 s for 5-25 s,
    lets in hot gusts of 2-5 degC (rising with 2-6 s, fading with 20-60 s) felt fully at the far end, 40 % mid-tent
    and 10 % by the duct. The sensor follows with 6-22 s (exact per step of ``step_s``)."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-900.0, d + 2.0 * step_s, step_s)
    rel = grid + 900.0
    outside = T_REF_C + rng.uniform(1.5, 4.0)
    sun = np.ones(grid.size)
    for start, length in schedule(rng, (30.0, 150.0), (20.0, 120.0), d + 1000.0):
        sun[(rel >= start) & (rel < start + length)] = 1.0 - rng.uniform(0.4, 0.8)
    keep = math.exp(-step_s / rng.uniform(60.0, 180.0))
    solar = rng.uniform(1.0, 2.5) * sun
    gain, _ = signal.lfilter([1.0 - keep], [1.0, -keep], solar, zi=[keep * solar[0]])
    load = outside + gain
    setpoint, band = T_REF_C + rng.uniform(-1.2, 1.2), rng.uniform(0.8, 1.8)
    capacity, settle = rng.uniform(4.0, 8.0), math.exp(-step_s / rng.uniform(150.0, 400.0))
    room, running = np.empty(grid.size), np.zeros(grid.size)
    air, on = setpoint, False
    for i, goal in enumerate(load.tolist()):
        on = air > setpoint + 0.5 * band or (on and air > setpoint - 0.5 * band)
        air = (goal - capacity * on) + (air - goal + capacity * on) * settle
        room[i], running[i] = air, float(on)
    mix = math.exp(-step_s / rng.uniform(5.0, 15.0))
    supply, _ = signal.lfilter([1.0 - mix], [1.0, -mix], -rng.uniform(1.0, 3.0) * running, zi=[0.0])
    door = within(rel, schedule(rng, (60.0, 300.0), (5.0, 25.0), d + 1000.0)).astype(float)
    gust = chase(rng.uniform(2.0, 5.0) * door, math.exp(-step_s / rng.uniform(2.0, 6.0)),
                 math.exp(-step_s / rng.uniform(20.0, 60.0)))
    where = np.zeros((3, grid.size))
    at, here = float(grid[0]), int(rng.choice(3, p=(0.35, 0.4, 0.25)))
    while at <= grid[-1]:
        dwell, move = rng.uniform(40.0, 150.0), rng.uniform(3.0, 10.0)
        nxt = int(rng.choice(3, p=(0.35, 0.4, 0.25)))
        sel = (grid >= at) & (grid < at + dwell + move)
        u = ease((grid[sel] - at - dwell) / move)
        where[here, sel] += 1.0 - u
        where[nxt, sel] += u
        at, here = at + dwell + move, nxt
    far = rng.uniform(0.3, 1.0)
    air = room + where[0] * (supply + 0.1 * gust) + where[1] * 0.4 * gust + where[2] * (far + gust)
    lag = math.exp(-step_s / rng.uniform(6.0, 22.0))
    sensor, _ = signal.lfilter([1.0 - lag], [1.0, -lag], air, zi=[lag * air[0]])
    return np.interp(s, grid, sensor)


# ----------------------------------------------------------------------------- viscous flow

def slit_skin_leak(fluidity, closed, mid_n, width_n, open_s, close_s, step_s=0.05):
    """A leak through slits in the core's elastomer skin that the bulge opens: the open share a logistic in the force
    (midpoint ``mid_n``, width ``width_n``) followed through the skin's lag (``open_s`` opening, ``close_s`` closing);
    ``fluidity`` open, ``closed`` of it shut."""
    def rule(t, f):
        grid, fg = coarse(t, f, step_s)
        share = chase(logistic((fg - mid_n) / width_n), math.exp(-step_s / open_s), math.exp(-step_s / close_s))
        phi = fluidity * (closed + (1.0 - closed) * np.interp(t, grid, share))
        return integrate.cumulative_trapezoid(phi * f, t, initial=0.0)
    return rule


def fines_leak(fluidity, spread, wander):
    """A leak through a sintered filter whose fines migrate: its fluidity ``fluidity`` exp(``spread`` w - spread^2 / 2),
    w ``wander`` (a unit Ornstein-Uhlenbeck process: grid, values) at the seconds since the first sample."""
    grid, w = wander

    def rule(t, f):
        phi = fluidity * np.exp(spread * np.interp(t - t[0], grid, w) - 0.5 * spread * spread)
        return integrate.cumulative_trapezoid(phi * f, t, initial=0.0)
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def free_volume_kelvin(t, f, compliance, tau_s, speedup, instant, step_s=0.01):
    """A Kelvin unit (``compliance`` V/N, ``tau_s`` at rest) whose clock follows the free volume its dilatation opens
    (Knauss and Emri: Doolittle's ln a = -B df / (f0 (f0 + df)), B 1, f0 0.025, df in proportion to the core's
    instantaneous (``instant`` V/N) and retarded deformation, ``speedup`` times faster at what 9 N gives). Exact per
    step of ``step_s``, from rest."""
    grid, fg = coarse(t, f, step_s)
    f0, big_b = 0.025, 1.0
    s = math.log(speedup)
    reach = (instant + compliance) * FORCE_MAX_N
    delta = s * f0 * f0 / (big_b - s * f0)
    u, out = 0.0, np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        df = delta * max(instant * fi + u, 0.0) / reach
        rate = math.exp(min(big_b * df / (f0 * (f0 + df)), 8.0)) / tau_s
        goal = compliance * fi
        u = goal + (u - goal) * math.exp(-step_s * rate)
        out[i] = u
    return np.interp(t, grid, out)


def jamming_pad(t, f, compliance, tau_s, fold, moving, step_s=0.01):
    """A Kelvin unit (``compliance`` V/N, ``tau_s`` at rest) of glass beads in a latex skin that settles ``fold`` times
    faster while the robot moves (``moving(s)``, 0-1, of the seconds since the first sample). Exact per step of
    ``step_s``, from rest."""
    grid, fg = coarse(t, f, step_s)
    keep = np.exp(-step_s * (1.0 + (fold - 1.0) * moving(grid - t[0])) / tau_s)
    goal = compliance * fg
    u, out = 0.0, np.empty(grid.size)
    for i, (g, k) in enumerate(zip(goal.tolist(), keep.tolist())):
        u = g + (u - g) * k
        out[i] = u
    return np.interp(t, grid, out)


# ----------------------------------------------------------------------------- hysteresis

class CompensatedBacklash(SimOnly):
    """A rack and pinion turning a rotary encoder with backlash (a play of half-width ``half_v``) whose firmware adds
    ``step_v`` in the sense of the last movement it saw (none before the first)."""

    def __init__(self, half_v, step_v):
        self.r, self.c = half_v, step_v

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        out, p, sense = np.empty_like(x), float(x[0]), 0.0
        for i, xi in enumerate(x.tolist()):
            q = max(xi - self.r, min(xi + self.r, p))
            if q > p:
                sense = 1.0
            elif q < p:
                sense = -1.0
            p = q
            out[i] = p + sense * self.c
        return out


class SubrangingDac(SimOnly):
    """A subranging read-out: a coarse offset DAC in steps of ``step_v`` whose firmware moves its code once the fine
    residual leaves +-(step / 2 + ``overlap_v``); code k is off by ``errors[k]`` (the codes about the first reading's,
    centred on the middle of the table)."""

    def __init__(self, step_v, overlap_v, errors):
        self.step, self.window, self.errors = step_v, 0.5 * step_v + overlap_v, np.asarray(errors, dtype=float)

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        mid = self.errors.size // 2
        k = int(round(x[0] / self.step))
        out = np.empty_like(x)
        for i, xi in enumerate(x.tolist()):
            while xi - k * self.step > self.window:
                k += 1
            while xi - k * self.step < -self.window:
                k -= 1
            out[i] = xi - self.errors[min(max(mid + k, 0), self.errors.size - 1)]
        return out - (out[0] - x[0])


# ----------------------------------------------------------------------------- sensor lag

class WakeOnChange(SimOnly):
    """A battery-powered wireless node: it samples every ``idle_s`` while the reading is still and every ``fast_s`` for
    ``awake_s`` after a sample that moved by more than ``band_v`` from the one before; each sample is held until the
    next arrives, ``latency_s`` after it was taken."""

    def __init__(self, idle_s, fast_s, awake_s, band_v, latency_s):
        self.idle, self.fast, self.awake, self.band, self.latency = idle_s, fast_s, awake_s, band_v, latency_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        times, values = [], []
        now, last, until = float(t[0]), float(x[0]), float(t[0]) - 1.0
        while now <= t[-1]:
            v = float(np.interp(now, t, x))
            if abs(v - last) > self.band:
                until = now + self.awake
            times.append(now)
            values.append(v)
            last = v
            now += self.fast if now < until else self.idle
        idx = np.searchsorted(np.asarray(times) + self.latency, t, side="right") - 1
        return np.where(idx >= 0, np.asarray(values)[np.maximum(idx, 0)], x[0])


class DitherLockedFbg(GridMode):
    """An FBG read-out whose interrogator tracks the grating's peak with a dither-locked laser: y' = e(x - y) / ``tau_s``,
    the error signal e(d) = d / (1 + (d / ``width_v``)^2)^2 (a Lorentzian line's derivative, slope 1 at lock). Euler on a
    uniform grid of ``fs`` Hz, from rest."""

    fs = 2000.0

    def __init__(self, tau_s, width_v):
        self.tau, self.w = tau_s, width_v

    def on_grid(self, t, tu, xu, h):
        y, k, inv = 0.0, h / self.tau, 1.0 / self.w
        out = np.empty(tu.size)
        for i, xi in enumerate(xu.tolist()):
            d = xi - y
            q = 1.0 + (d * inv) ** 2
            y += k * d / (q * q)
            out[i] = y
        return out


# ----------------------------------------------------------------------------- nonlinear gain

def plunger_absorbance(rel, reach, a_rest, a_top):
    """x read as the absorbance of a dyed plunger driven into the beam (a_rest at rest, a_top at ``reach``) with a
    share s of stray light around it: -log10((1 - s) 10^-A + s), slope 1 at no load, s for a departure of ``rel`` at
    ``reach`` (compressive)."""
    span = a_top - a_rest

    def read(x, s):
        u = np.clip(x / reach, -0.2, 1.3)

        def seen(a):
            return -np.log10((1.0 - s) * 10.0 ** (-a) + s)
        slope = span * (1.0 - s) * 10.0 ** (-a_rest) / ((1.0 - s) * 10.0 ** (-a_rest) + s)
        return (seen(a_rest + span * u) - seen(a_rest)) / slope * reach
    return fit_departure(read, rel, reach, 0.3)


def kubelka_munk(rel, reach, thickness, absorb):
    """x read as the fall of the diffuse reflectance of a scattering layer over a black backing (Kubelka and Munk, R =
    1 / (a + b coth(b S X)), a = 1 + K / S = 1 + ``absorb``, optical thickness ``thickness`` at rest) that the load
    thins by a share q over ``reach``: slope 1 at no load, q for a departure of ``rel`` (expansive)."""
    a = 1.0 + absorb
    b = math.sqrt(a * a - 1.0)

    def refl(z):
        return 1.0 / (a + b / np.tanh(b * thickness * np.maximum(z, 1e-6)))

    def read(x, q):
        u = np.clip(x / reach, -0.2, 1.0)
        h = 1e-5
        slope = (refl(1.0) - refl(1.0 - q * h)) / h
        return (refl(1.0) - refl(1.0 - q * u)) / slope * reach
    return fit_departure(read, rel, reach, 0.85)


# ----------------------------------------------------------------------------- thermal drift

def cylinder_weights(biot, terms=8):
    """The roots b_n of b J1(b) = Bi J0(b) and the weights 4 Bi^2 / (b_n^2 (b_n^2 + Bi^2)) of a cylinder's mean
    temperature (normalised over the terms kept)."""
    def fn(b):
        return b * special.j1(b) - biot * special.j0(b)
    grid = np.linspace(1e-6, 40.0, 8001)
    vals = fn(grid)
    roots = [optimize.brentq(fn, grid[i], grid[i + 1]) for i in np.flatnonzero(np.sign(vals[:-1]) != np.sign(vals[1:]))]
    roots = np.asarray(roots[:terms])
    w = 4.0 * biot * biot / (roots ** 2 * (roots ** 2 + biot * biot))
    return roots, w / w.sum()


def glycol_cylinder_zero(t, temp, k_v_per_c, rise, biot, diff_s):
    """The zero of a fluid-filled cylindrical read-out: the fill's expansion, ``k_v_per_c`` (1 + ``rise`` dT) per degC,
    of its mean temperature (radial conduction with a surface film: :func:`cylinder_weights`, times ``diff_s`` / b_n^2)."""
    roots, w = cylinder_weights(biot)
    mean = sum(wi * follow(t, temp, diff_s / (b * b)) for b, wi in zip(roots, w))
    d = np.clip(mean - T_REF_C, -25.0, 25.0)
    return k_v_per_c * (d + 0.5 * rise * d * d)


def snap_disc_zero(t, temp, k_v_per_c, linear, jump_c, on_q, gap_c, lag_s, pad_s):
    """The zero of a read-out whose holder carries a bimetal snap disc (lag ``lag_s``): it snaps through above the
    ``on_q`` quantile of its temperature over the record and back ``gap_c`` lower, pressing the housing by what
    ``jump_c`` degC of ``k_v_per_c`` gives through a pad (lag ``pad_s``), beside a linear zero of ``linear`` of
    ``k_v_per_c``."""
    body = follow(t, temp, lag_s)
    on = float(np.quantile(body, on_q))
    pressed = relay(body, on, on - gap_c).astype(float)
    return k_v_per_c * (linear * (body - body[0]) + jump_c * (lagged(t, pressed, pad_s) - pressed[0]))


# ----------------------------------------------------------------------------- thermal sensitivity

class IontronicSpan(SimOnly):
    """An iontronic read-out whose double layer is read at a fixed frequency through the gel's ionic resistance
    (Arrhenius, exp(-a dT)): the span sqrt((1 + q^2) / (1 + q^2 exp(-2 a dT))), q = omega R C at the reference, a for
    ``tc`` per degC there; dT on the gel (lag ``lag_s``)."""

    def __init__(self, tc, q, lag_s):
        self.q2, self.lag = q * q, lag_s
        self.a = tc * (1.0 + self.q2) / self.q2

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = np.clip(follow(t, temp_of(aux, t.size), self.lag) - T_REF_C, -30.0, 30.0)
        return np.asarray(x, dtype=float) * np.sqrt((1.0 + self.q2) / (1.0 + self.q2 * np.exp(-2.0 * self.a * d)))


class SaturatedFerriteSpan(SimOnly):
    """An inductive read-out through a MnZn ferrite biased toward saturation: the span ((1 - b / m) / (1 - b))^p, m =
    1 - ``fall`` dT the saturation's share of its value at the reference, b for ``tc`` per degC there (falling as it
    warms); dT on the ferrite (lag ``lag_s``)."""

    def __init__(self, tc, p, fall, lag_s):
        self.p, self.c, self.lag = p, fall, lag_s
        self.b = tc / (tc + p * fall)

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = np.clip(follow(t, temp_of(aux, t.size), self.lag) - T_REF_C, -30.0, 30.0)
        r = np.clip(self.b / (1.0 - self.c * d), 0.0, 0.999)
        return np.asarray(x, dtype=float) * ((1.0 - r) / (1.0 - self.b)) ** self.p


# ----------------------------------------------------------------------------- offset drift

def trim_upsets(rng, horizon_s=HORIZON_S, step_s=0.02):
    """The zero of a read-out whose offset-trim register is upset by fast transients (one every 25-80 s on average, the
    first 5-60 s into the record), each flipping one of its six upper bits (weights 1, 2, 4 ... 32), until the firmware
    rewrites the register from its EEPROM copy every 20-60 s (from a random phase). As a function of the seconds since
    the first sample, zero there."""
    grid = np.arange(-60.0, horizon_s + step_s, step_s)
    scrub, mean_gap = rng.uniform(20.0, 60.0), rng.uniform(25.0, 80.0)
    ticks = np.arange(-60.0 + rng.uniform(0.0, scrub), horizon_s + scrub, scrub)
    events = [rng.uniform(5.0, 60.0)]
    while events[-1] < horizon_s:
        events.append(events[-1] + rng.exponential(mean_gap))
    reg0 = int(rng.integers(0, 64))
    changes = sorted([(e, int(rng.integers(0, 6))) for e in events] + [(s, -1) for s in ticks])
    out, reg, j = np.zeros(grid.size), reg0, 0
    for i, g in enumerate(grid.tolist()):
        while j < len(changes) and changes[j][0] <= g:
            reg = reg0 if changes[j][1] < 0 else reg ^ (1 << changes[j][1])
            j += 1
        out[i] = reg - reg0
    first = float(np.interp(0.0, grid, out))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, out) - first


def dissolving_bubble(rng, horizon_s=HORIZON_S):
    """The zero of a fluid-filled read-out as the volume of a residual air bubble that dissolves into the degassed fill
    (Epstein and Plesset with surface tension: R' = -k (1 + l / R) / R, the Laplace length l 0.1-1 initial radii),
    filled 0-300 s before the first sample and gone 0.5-2.5 records after it. As a function of the seconds since the
    first sample, zero there."""
    filled, lap = rng.uniform(0.0, 300.0), rng.uniform(0.1, 1.0)
    life = filled + rng.uniform(0.5, 2.5) * DURATION_S
    radius = np.linspace(1.0, 0.0, 2001)

    def prim(r):
        return 0.5 * r * r - lap * r + lap * lap * np.log(r + lap)
    since = (prim(1.0) - prim(radius)) / (prim(1.0) - prim(0.0)) * life
    grid = np.arange(0.0, horizon_s + 1.0, 0.1)
    vol = np.interp(grid + filled, since, radius ** 3, right=0.0)
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, vol) - vol[0]


# ----------------------------------------------------------------------------- resonance

class LanchesterMode(GridMode):
    """A needle holder's mode at ``f0_hz`` (with the ring stuck; unit gain, damping ratio ``zeta``) with a Lanchester
    damper: a ring of ``ring`` of the moving mass in a friction-lined groove that slips once the force it needs passes
    ``grip`` of what the largest acceleration of the stuck mode over the record needs. Semi-implicit Euler on a uniform
    grid of ``fs`` Hz, from rest."""

    fs = 3000.0

    def __init__(self, f0_hz, zeta, ring, grip):
        self.w0, self.zeta, self.mu, self.grip = 2.0 * math.pi * f0_hz, zeta, ring, grip

    def on_grid(self, t, tu, xu, h):
        lin = linear_mode(xu, self.w0, self.zeta, self.fs)
        a_max = max(float(np.max(np.abs(np.diff(lin, 2)))) / (h * h), 1e-9)
        mu = self.mu
        slip = self.grip * mu * a_max
        w2, c = self.w0 * self.w0 * (1.0 + mu), 2.0 * self.zeta * self.w0 * (1.0 + mu)
        ud = np.gradient(xu, h).tolist()
        y = vy = vr = 0.0
        stuck = True
        out = np.empty(tu.size)
        for i, (ui, udi) in enumerate(zip(xu.tolist(), ud)):
            spring = w2 * (ui - y) + c * (udi - vy)
            if stuck and abs(mu * spring / (1.0 + mu)) > slip:
                stuck = False
            if stuck:
                vy += spring / (1.0 + mu) * h
                vr = vy
            else:
                rel = vy - vr
                force = slip * (math.copysign(1.0, rel) if rel != 0.0 else math.copysign(1.0, spring))
                vy += (spring - force) * h
                vr += force / mu * h
                if (vy - vr) * rel < 0.0:
                    vy = vr = (vy + mu * vr) / (1.0 + mu)
                    stuck = True
            y += vy * h
            out[i] = y
        return out


class WhirlingHolder(GridMode):
    """A slender holder whose bending planes ring at ``f0_hz`` (read) and ``split`` times it, damping ratio ``zeta``
    each, coupled by a quartic potential g (z^2 + q^2)^2 / 4 of the relative motions, g for a hardening of ``harden``
    at the largest motion a linear mode would reach, the drive ``off`` off the read plane. Semi-implicit Euler on a
    uniform grid of ``fs`` Hz, from rest."""

    fs = 3000.0

    def __init__(self, f0_hz, zeta, split, harden, off):
        self.w1, self.zeta, self.split, self.harden, self.off = 2.0 * math.pi * f0_hz, zeta, split, harden, off

    def on_grid(self, t, tu, xu, h):
        zmax = max(float(np.max(np.abs(linear_mode(xu, self.w1, self.zeta, self.fs) - xu))), 1e-12)
        w1, w2 = self.w1, self.w1 * self.split
        g = self.harden * w1 * w1 / (zmax * zmax)
        c1, c2, e = 2.0 * self.zeta * w1, 2.0 * self.zeta * w2, self.off
        ud = np.gradient(xu, h).tolist()
        y = vy = q = vq = 0.0
        out = np.empty(tu.size)
        for i, (ui, udi) in enumerate(zip(xu.tolist(), ud)):
            z, r = y - ui, q - e * ui
            cube = g * (z * z + r * r)
            vy += (-w1 * w1 * z - c1 * (vy - udi) - cube * z) * h
            vq += (-w2 * w2 * r - c2 * (vq - e * udi) - cube * r) * h
            y += vy * h
            q += vq * h
            out[i] = y
        return out


# ----------------------------------------------------------------------------- friction

def carriage_positions(rng, horizon_s=HORIZON_S, step_s=0.05):
    """The carriage's place along its rod (-1..1): moved by the robot every 15-60 s over 1-4 s (minimum jerk) to a place
    drawn uniformly; as a function of the seconds since the first sample."""
    grid = np.arange(-60.0, horizon_s + step_s, step_s)
    pos = np.full(grid.size, rng.uniform(-1.0, 1.0))
    at = rng.uniform(-10.0, 40.0)
    while at < horizon_s:
        length, goal = rng.uniform(1.0, 4.0), rng.uniform(-1.0, 1.0)
        start = float(np.interp(at, grid, pos))
        sel = grid >= at
        pos[sel] = start + (goal - start) * ease((grid[sel] - at) / length)
        at += length + rng.uniform(15.0, 60.0)
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, pos)


class BentRodGuide(SimOnly):
    """The force passed by a needle guide on a carriage riding a slightly bent rod: a Coulomb band ``band_n`` (1 +
    ``kappa`` s^2) / (1 + kappa / 3), s the carriage's place (``place(seconds)``). Started at the first force."""

    def __init__(self, band_n, kappa, place):
        self.band, self.kappa, self.place = band_n, kappa, place

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        band = self.band * (1.0 + self.kappa * self.place(t - t[0]) ** 2) / (1.0 + self.kappa / 3.0)
        return band_play(np.asarray(x, dtype=float), band, band)


def eccentric_guide(f, band_n, least, balance_n):
    """The force passed by a cantilevered needle guide whose thrust acts off its axis: a Coulomb band ``band_n`` (least
    + (1 - least) |p - ``balance_n``| / balance_n), at most three times ``band_n``, p the force passed so far. Started
    at ``f[0]``."""
    out, p = np.empty_like(f), float(f[0])
    for i, fi in enumerate(f.tolist()):
        b = band_n * min(least + (1.0 - least) * abs(p - balance_n) / balance_n, 3.0)
        p = max(fi - b, min(fi + b, p))
        out[i] = p
    return out


# ----------------------------------------------------------------------------- thermo-rheological

class ConfiguronClock(SimOnly):
    """A core whose dashpots follow Douglas, Doremus and Ojovan's law: ln a = ln(T / T_r) + B (1 / T - 1 / T_r) + ln((1
    + C e^(D / T)) / (1 + C e^(D / T_r))); D carries ``share_d`` of ``b_per_c`` per degC at the reference, where the
    crossover's share is ``cross``. On the core's temperature (lag ``lag_s``), held within e^+-6."""

    def __init__(self, c, b_per_c, share_d, cross, lag_s):
        self.c, self.lag = c, lag_s
        self.tr = T_REF_C + 273.15
        self.d = share_d * b_per_c * self.tr ** 2 / cross
        self.b = (1.0 - share_d) * b_per_c * self.tr ** 2 + self.tr
        self.ln_c = math.log(cross / (1.0 - cross)) - self.d / self.tr

    def log_shift(self, kelvin):
        return (np.log(kelvin / self.tr) + self.b * (1.0 / kelvin - 1.0 / self.tr)
                + np.logaddexp(0.0, self.ln_c + self.d / kelvin) - np.logaddexp(0.0, self.ln_c + self.d / self.tr))

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag) + 273.15
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(-self.log_shift(body), -6.0, 6.0)))


class SchottkyClock(SimOnly):
    """A core whose clock follows Adam and Gibbs's law, ln a = K (1 / (T S_c(T)) - 1 / (T_r S_c(T_r))), with the
    configurational entropy of two-level defects of gap ``gap`` T_r (a Schottky entropy, ln(1 + e^-x) + x e^-x / (1 +
    e^-x), x the gap over T); K for ``b_per_c`` per degC at the reference. On the core's temperature (lag ``lag_s``),
    held within e^+-6."""

    def __init__(self, c, b_per_c, gap, lag_s):
        self.c, self.lag = c, lag_s
        self.tr = T_REF_C + 273.15
        self.eps = gap * self.tr
        h = 1e-3
        slope = (self.inverse(self.tr + h) - self.inverse(self.tr - h)) / (2.0 * h)
        self.k = -b_per_c / slope

    def inverse(self, kelvin):
        x = self.eps / np.asarray(kelvin, dtype=float)
        e = np.exp(-x)
        return 1.0 / (kelvin * (np.log1p(e) + x * e / (1.0 + e)))

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag) + 273.15
        log_shift = self.k * (self.inverse(body) - self.inverse(self.tr))
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(-log_shift, -6.0, 6.0)))


# ----------------------------------------------------------------------------- outside the catalogue

class SlowAgc(SimOnly):
    """A read-out with a slow automatic gain control: the reading times (``ref_v`` / its envelope)^``power``, the
    envelope the reading's magnitude followed over ``tau_s`` (at least 5 % of ref_v), the gain held within 1 / ``limit``
    to ``limit``."""

    def __init__(self, power, tau_s, ref_v, limit):
        self.power, self.tau, self.ref, self.limit = power, tau_s, ref_v, limit

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        env = np.maximum(follow(t, np.abs(x), self.tau, step_s=0.05), 0.05 * self.ref)
        return x * np.clip((self.ref / env) ** self.power, 1.0 / self.limit, self.limit)


class InputCrowbar(SimOnly):
    """An input crowbar that trips whenever the reading passes ``share`` of the record's largest and holds the output
    at the bridge's zero for ``hold_s``."""

    def __init__(self, share, hold_s):
        self.share, self.hold = share, hold_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        limit = self.share * float(np.max(x))
        out, until = x.copy(), -np.inf
        for i in np.flatnonzero(x > limit).tolist():
            if t[i] >= until:
                until = t[i] + self.hold
                out[(t >= t[i]) & (t < until)] = 0.0
        return out


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):
    c = soft(c)
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([3.6e4, 3.4e3]))))  # V / (N s)
        if shape == "slit_skin":
            rule = slit_skin_leak(phi * rng.uniform(2.0, 4.0), rng.uniform(0.1, 0.3), rng.uniform(1.5, 4.0),
                                  rng.uniform(0.3, 1.0), rng.uniform(0.2, 1.0), rng.uniform(2.0, 10.0))
        else:
            rule = fines_leak(phi * rng.uniform(1.3, 2.3), rng.uniform(0.3, 0.6),
                              ou_process(rng, HORIZON_S, rng.uniform(40.0, 150.0)))
        return Parts("zener", LeakingCore.of(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        comp = float(np.interp(m, [0, 1], [0.045, 0.22])) / g0  # of the instantaneous response, V / N
        if shape == "free_volume_kelvin":
            a = (comp, rng.uniform(2.0, 20.0), rng.uniform(3.0, 10.0), 1.0 / g0)
            p.extra.append(lambda t, f, T, a=a: free_volume_kelvin(t, f, *a))
            return p
        a = (comp, rng.uniform(10.0, 40.0), rng.uniform(4.0, 12.0), robot_moves(rng, (6.0, 30.0), (1.0, 6.0)))
        p.extra.append(lambda t, f, T, a=a: jamming_pad(t, f, *a))
        return p
    if effect == "hysteresis":
        width = float(np.interp(m, [0, 1], [0.018, 0.07]))
        if shape == "compensated_backlash":
            ratio = rng.uniform(0.3, 0.7) if rng.random() < 0.5 else rng.uniform(1.3, 1.7)
            p.after.append(CompensatedBacklash(0.5 * width * top, 0.5 * ratio * width * top))
            return p
        step = rng.uniform(0.06, 0.14) * top
        errors = rng.uniform(-1.0, 1.0, 64) * rng.uniform(0.5, 1.0) * width * top
        p.after.append(SubrangingDac(step, rng.uniform(0.25, 0.45) * step, errors))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.011, 0.1]))))
        if shape == "wake_on_change":
            p.after.append(WakeOnChange(rng.uniform(1.8, 2.6) * delay, rng.uniform(0.5, 0.8) * delay, rng.uniform(0.4, 1.5),
                                        rng.uniform(0.004, 0.015) * top, rng.uniform(0.2, 0.35) * delay))
            return p
        p.after.append(DitherLockedFbg(delay, rng.uniform(0.5, 1.1) * top))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.052, 0.19]))
        if shape == "plunger_absorbance":
            p.after.append(StaticMap(plunger_absorbance(rel, top, rng.uniform(0.1, 0.4), rng.uniform(1.6, 2.6))))
            return p
        p.after.append(StaticMap(kubelka_munk(rel, top, rng.uniform(0.6, 2.5), rng.uniform(0.02, 0.3))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.008, 0.032]) * rng.choice([-1, 1]))
        if shape == "glycol_cylinder":
            a = (k, rng.uniform(0.03, 0.08), rng.uniform(2.0, 12.0), rng.uniform(60.0, 300.0))
            p.extra.append(lambda t, f, T, a=a: glycol_cylinder_zero(t, T, *a))
            return p
        a = (k, rng.uniform(0.3, 0.6), float(rng.choice([-1.0, 1.0])) * rng.uniform(2.0, 4.0), rng.uniform(0.4, 0.75),
             rng.uniform(0.8, 2.0), rng.uniform(8.0, 30.0), rng.uniform(1.0, 4.0))
        p.extra.append(lambda t, f, T, a=a: snap_disc_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        tc = float(np.interp(m, [0, 1], [0.013, 0.034]))
        if shape == "iontronic_layer":
            p.after.append(IontronicSpan(tc, rng.uniform(0.8, 1.6), rng.uniform(5.0, 30.0)))
            return p
        p.after.append(SaturatedFerriteSpan(tc, rng.uniform(0.8, 2.0), rng.uniform(0.0025, 0.004), rng.uniform(10.0, 40.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.018, 0.095]) * rng.choice([-1, 1]))
        zero = sized(trim_upsets(rng) if shape == "trim_upsets" else dissolving_bubble(rng), size, HORIZON_S)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.031, 0.0047])) * rng.uniform(0.8, 1.2)
        if shape == "lanchester_damper":
            p.after.append(LanchesterMode(rng.uniform(15.0, 45.0), zeta, rng.uniform(0.1, 0.3), rng.uniform(0.15, 0.5)))
            return p
        p.after.append(WhirlingHolder(rng.uniform(15.0, 45.0), zeta, rng.uniform(0.97, 1.03), rng.uniform(0.15, 0.5),
                                      rng.uniform(0.03, 0.12)))
        return p
    if effect == "friction":
        band = float(np.interp(m, [0, 1], [0.003, 0.045]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "bent_rod":
            p.before.append(BentRodGuide(band, rng.uniform(1.0, 3.0), carriage_positions(rng)))
            return p
        a = (band, rng.uniform(0.2, 0.4), rng.uniform(2.0, 5.0))
        p.before.append(ForcePath(lambda t, x, a=a: eccentric_guide(x, *a)))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.17, 0.5])) * rng.uniform(1.2, 1.5)
        if shape == "configuron_clock":
            return Parts("burgers", ConfiguronClock(c, b, rng.uniform(0.3, 0.6), rng.uniform(0.3, 0.8),
                                                    rng.uniform(5.0, 25.0)), core_changed=True)
        return Parts("burgers", SchottkyClock(c, b, rng.uniform(4.0, 9.0), rng.uniform(5.0, 25.0)), core_changed=True)
    if effect == "slow_agc":
        power = float(np.interp(m, [0.4, 0.9], [0.3, 0.7]))
        p.after.append(SlowAgc(power, rng.uniform(4.0, 20.0), 0.3 * top, rng.uniform(2.0, 4.0)))
        return p
    if effect == "input_crowbar":
        share = float(np.interp(m, [0.4, 0.9], [0.92, 0.8]))
        p.after.append(InputCrowbar(share, float(np.interp(m, [0.4, 0.9], [0.3, 2.0])) * rng.uniform(0.8, 1.2)))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["slit_skin", "migrating_fines"],
    "delayed_elasticity": ["free_volume_kelvin", "jamming_pad"],
    "hysteresis": ["compensated_backlash", "subranging_dac"],
    "sensor_lag": ["wake_on_change", "dither_locked_fbg"],
    "nonlinear_gain": ["plunger_absorbance", "kubelka_munk"],
    "thermal_drift": ["glycol_cylinder", "snap_disc"],
    "thermal_sensitivity": ["iontronic_layer", "saturated_ferrite"],
    "offset_drift": ["trim_upsets", "dissolving_bubble"],
    "resonance": ["lanchester_damper", "whirling_holder"],
    "friction": ["bent_rod", "eccentric_guide"],
    "thermo_rheological": ["configuron_clock", "schottky_clock"],
}
PAIRS = (("viscous_flow", "thermal_drift"), ("delayed_elasticity", "nonlinear_gain"), ("hysteresis", "sensor_lag"),
         ("resonance", "thermo_rheological"), ("offset_drift", "friction"), ("thermal_sensitivity", "viscous_flow"))
OUTSIDE = ("slow_agc", "input_crowbar")
RATES = (115.0, 275.0, 605.0, 1175.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split AG", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.34, 0.82),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=field_tent,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(0.66e-3, 2.22e-3), jitter=0.27,
                   gap_s=(0.2, 1.9))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
