"""Independent split S for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split S is an untouched held-out set: written before the engine it measures and blind to it (to how it detects and
fits anything), run once at its end, never used to choose anything. Every name of the catalogue is hidden in two
shapes that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A to R use:

* a glassy core that ages physically and is rejuvenated by load (its fluidity falls as (1 + a / 30-120 s)^-(0.4-0.7)
  with an effective age a that grows with time from 200-2000 s at the start, rested at 1-1.8 times the plain fluidity
  of 1/60000-1/4000 V/(N s); a load beyond 1.5-3.5 N takes the age back, a' = 1 - a (F - F_r) / (1 N 5-30 s), so the
  flow speeds up under heavy loads and slows again at rest; it never recovers), or a thin viscous layer softened by
  its own dissipation (the fluidity 1-2 times the plain one times exp(u), u gaining F x' and losing itself over 10-60
  s, 0.5-1 e-folds held at 9 N: the flow grows faster than the force);
* the air in a closed-cell printed lattice core, warmed adiabatically by each compression (its pressure 1 + F / 6-20
  N, the temperature as its power 0.286) and cooled back through the cells' walls in 1-8 s, so the core settles
  further as it cools and springs back further as it warms after an unloading (3-20 % of the instantaneous response
  after a 4 N step, less at higher loads), or the dielectric absorption of a capacitive read-out (3-20 % of each
  change soaking in as Jonscher's 1 - (1 + t / 0.5-6 s)^-(0.6-1.2): a fast start and a long algebraic tail);
* a freshly printed silver trace in the bridge that yields micro-plastically (three plays on the bridge voltage, radii
  4-15 % of the range, a fresh loop of 1.4-15 % of it that shrinks to 30-60 % as it shakes down over 4-12 ranges of
  travel), or the ink-bottle pores of a porous printed core (60 pores that the core's oil invades through their necks
  at forces spread log-normally, median 2-4 N, log spread 0.4-0.7, and leaves only at 25-75 % of that, through their
  bodies; the pores filled by 9 N add 1-6 % of the range to the core's settlement);
* a vision-based (gel and camera) tactile read-out (each frame averages over an exposure of 30-80 % of a frame, is
  processed for 1-2 frames and held until the next: a mean delay of 10-108 ms), or a passive twin-T mains notch at 50
  or 60 Hz (q 0.25-0.6) behind an anti-alias RC, 10-108 ms of delay in all at low frequencies;
* the squeeze of an elastomer O-ring that carries the load, read through Lindley's law (1.25 e^1.5 + 50 e^6, inverted,
  from a preload of 8-15 %: a compression of 5-16 % at the top of the range), or a preloaded force-sensing resistor
  (its conductance as (1 + x / x0)^(1.1-2)) in a divider whose fixed resistor is 0.3-10 times smaller than the film's
  resting resistance (expansive, compressive or S-shaped: 5-16 % at most over the range);
* a water film that condenses on the bridge board whenever it (lag 5-20 s) is colder than the air's dew point (at the
  15-40th percentile of its temperature over the record: the cryoprobe's freezes condense) and dries when warmer (a
  full film in 30-120 degC s of subcooling, gone in 20-90 degC s; 18-66 mV), or the gauges' thermal zero (lag 5-20 s,
  0.006-0.022 V/degC) trimmed by an NTC thermistor on the amplifier board (lag 20-90 s, beta 3000-4200 K, in a divider
  0.4-2.5 times its resistance) meant to take 45-80 % or 120-155 % of it;
* a polymer span (0.6-1.6 %/degC, lag 5-20 s) corrected by firmware from a thermometer it polls every 40-150 s with
  85-115 % of the true coefficient (stale between polls: steps at each poll), or a core blended with a low-melting
  crystalline phase (lag 10-40 s; melting range at the 50-80th percentile of its temperature over the record, 0.3-0.8
  degC wide, crystallising 1-2.5 degC lower, melting over 10-40 s and crystallising over 20-80 s): the molten share
  softens the core, the span up to 4-14 % higher, with a thermal hysteresis;
* the body capacitance of theatre staff near a capacitive read-out's input (10-30 passes 0.5-2 m away at 0.3-0.8 m/s,
  coupling as a power 1.5-3 of the distance, and 1-3 times someone leaning over the sensor for 20-120 s; 12-80 mV at
  most), or the shrinkage of a polymer desorbing the ethylene oxide of its sterilisation (Crank's series in a slab,
  L^2 / D 300-2500 s, aerated from 0-400 s before the record: a square-root start, an exponential end; 12-80 mV over
  the record);
* the string modes of a taut tendon of the robot's transmission (15-35 Hz and its first 2-4 harmonics, weighted 1 /
  n^2, damping zeta_1 / n from the terminations plus 5-20 % of zeta_1 times n of the tendon's own), or a needle
  holder on a wire-rope isolator (18-45 Hz, 50-80 % of its spring linear, the rest a Bouc-Wen strand friction
  saturating at what 0.45-1.35 N gives: large swings ring softer and die fast, small ones ring long); zeta_1 or the
  damping ratio 0.0064-0.036;
* a tendon in a sheath (the capstan law, e^(+-mu theta), plus its entry seal, 25-45 % of the band; the band 0.4-3.6
  % of the range at 3.5 N at the mean bend, the bend moved every 10-40 s between 0.3-1 rad and 1.5-3.5 rad more as the
  robot steers the flexible instrument), or a Coulomb band of 0.4-3.6 % of the range on a needle the robot spins now
  and then (5-40 s every 15-80 s): while it spins the contact slides around the needle and the axial friction falls to
  the axial share of the sliding velocity (a friction cone, the spin worth 0.5-3 N/s), so the stuck force creeps to
  the applied one;
* an Arrhenius clock (0.1-0.3 per degC, lag 5-20 s) on a freshly printed resin core that is still curing (the cure
  advancing from 30-70 % at an Arrhenius rate of 0.1-0.2 per degC, 300-1500 s at the reference, the clock slowing by
  0.5-1.5 e-folds per unit of cure), or on a core kept warm by a heating foil under a proportional controller (gain
  2-6) of limited reach (1.5-4 degC of warming), set 0-1.5 degC above the reference (the core, 20-60 s, holds near
  its set point until the air leaves the heater's reach, then follows it).

It also holds six pairs, two effects outside the catalogue (the electrosurgical unit's activations, 6-20 of 0.5-4 s,
rectified by the bridge amplifier: 2-40 mV reached in 20-100 ms, flickering by 20-40 % with the coagulation bursts,
recovering in 0.2-1 s; the fading of a polarimetric optical read-out as its fibre's state of polarisation wanders, a
random angle with a correlation of 20-120 s, the span 1 - v sin^2 of it, v 2-12 %) and four clean records. Profiles:
an epidural needle placed by the loss-of-resistance technique through the measured force-depth curve (``../shared/
data``, ``depth_force.csv``, its first insertion stretched over 30-55 mm), in increments with stops in which the tissue
relaxes and the syringe's plunger is pressed, through a ligamentum flavum that gives way, then a catheter threaded and
the needle withdrawn (synthetic layers when the data are absent); a cochlear implant's electrode array inserted by a
robot (capstan friction along the cochlea's turns, catches where the array buckles, grips that click); and robotic
suturing (punctures, the needle's arc, the thread pulled through with a stick-slip, knots of 3-4 throws, jaw clicks).
Rates 140, 410, 660 and 890 Hz (a mode at 1000 Hz with knocks that excite it), 1.1-2.4 mV noise, stamp jitter, gaps,
and a sensor on the needle guide of a robot for CT-guided cryoablation, cooled by the freezes of a cryoprobe beside it
and warmed by its thaws.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_s.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, optimize

from polyforce_ros.physics.expconv import exp_convolve
from polyforce_ros.physics.viscoelastic import simulate_deformation
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (band_play, coarse, cutter as window, ForcePath, LinearFilter, logistic, Parts, quintic,
                       schedule as schedule_until, ShapeSplit, SimOnly, sized, temp_of, uniform_grid, within,
                       ZenerWithFlow)

SEED0 = 1_310_000  # never a seed of the registry's splits nor of splits A (90000..) to R (1240000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 450.0
HORIZON_S = DURATION_S + 60.0  # what a schedule drawn before the record covers (the record plus its gaps' slack)

normalised = functools.partial(sized, horizon_s=HORIZON_S)
schedule = functools.partial(schedule_until, horizon_s=HORIZON_S)


# ----------------------------------------------------------------------------- profiles and temperature


@functools.lru_cache(maxsize=1)
def measured_insertion(bin_mm=0.25):
    """The measured force-depth curve (``../shared/data/needle_insertion_okamura/depth_force.csv``) of its first
    insertion (up to the first withdrawal of more than 5 mm), as (depth in mm, force in N): the median force per bin of
    ``bin_mm``, empty bins interpolated, a three-bin running mean, no negative force; None when the file is absent."""
    csv = profiles.okamura_csv_path()
    if csv is None or not (csv.parent / "depth_force.csv").is_file():
        return None
    raw = np.loadtxt(csv.parent / "depth_force.csv", delimiter=",", ndmin=2)
    depth_mm, force_n = 1e3 * raw[:, 0], raw[:, 1]
    back = np.flatnonzero(np.diff(depth_mm) < -5.0)
    end = int(back[0]) + 1 if back.size else depth_mm.size
    depth_mm, force_n = depth_mm[:end], force_n[:end]
    grid = np.arange(0.0, float(depth_mm.max()) + bin_mm, bin_mm)
    which = np.clip(np.round(depth_mm / bin_mm).astype(int), 0, grid.size - 1)
    median = np.full(grid.size, np.nan)
    for k in np.unique(which):
        median[k] = np.median(force_n[which == k])  # the median: digitised curves carry stray points
    filled = np.isfinite(median)
    curve = np.interp(grid, grid[filled], median[filled])
    curve = np.convolve(np.pad(curve, 1, mode="edge"), np.ones(3) / 3.0, mode="valid")
    return grid, np.maximum(curve, 0.0)


def synthetic_insertion(rng):
    """What :func:`measured_insertion` gives, made up: a friction of 0.01-0.03 N/mm over 48 mm and 2-3 membranes that
    build up over 3-8 mm by 0.4-1.2 N and tear (leaving 30 % that fades over 1 mm)."""
    grid = np.arange(0.0, 48.0, 0.25)
    force_n = rng.uniform(0.01, 0.03) * grid
    for at in np.sort(rng.uniform(8.0, 44.0, int(rng.integers(2, 4)))):
        build, height = rng.uniform(3.0, 8.0), rng.uniform(0.4, 1.2)
        rising = (grid > at - build) & (grid <= at)
        force_n[rising] += height * (grid[rising] - at + build) / build
        torn = grid > at
        force_n[torn] += 0.3 * height * np.exp(-(grid[torn] - at))
    return grid, force_n


def click(f, at, now, rng, low_n, high_n):
    """Add to ``f`` at ``now`` a click of a gripper's jaws closing: a raised cosine of 4-10 ms and ``low_n`` to
    ``high_n`` (what excites a mode of the holder)."""
    width = rng.uniform(0.004, 0.01)
    seg, s = at(now, width)
    f[seg] += rng.uniform(low_n, high_n) * 0.5 * (1.0 - np.cos(2.0 * np.pi * s / width))


def epidural_loss_of_resistance(duration_s, rate_hz, rng):
    """A robot placing an epidural needle (Tuohy) by the loss-of-resistance technique, the sensor behind its needle
    holder. The measured insertion (``measured_insertion``) is stretched over the 30-55 mm of skin, fat and
    supraspinous and interspinous ligaments before the ligamentum flavum and scaled to a 1.5-3.5 N peak. The robot
    advances in increments of 1-2.5 mm at 1-3 mm/s; after each it stops for 1.5-4 s (the tissue relaxing to 60-85 % of
    the force with a time constant of 0.5-2 s) while the plunger of the loss-of-resistance syringe is pressed 2-4
    times (raised-cosine pulses of 0.2-0.5 s that add 0.2-0.8 N through the hub while the tip is in dense tissue);
    the next increment re-engages the tissue over 0.5 mm. The ligamentum flavum (3-6 mm) adds 1.5-3.5 N as a power
    1.5-2.5 of the way through it; past it the resistance is lost within 40-120 ms, to the shaft's drag (30-60 % of
    the force before the ligament). The robot holds 5-12 s, a catheter is threaded through the needle for 10-25 s
    (its drag of 0.1-0.4 N pushed in strokes at 0.5-1.5 Hz), the needle is withdrawn (the push gone in 0.5 s) and the
    next attempt follows 8-25 s later. Made-up layers (``synthetic_insertion``) when ``../shared/data`` is absent."""
    curve = measured_insertion() or synthetic_insertion(rng)
    depth_mm, force_n = curve
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    at = window(t)
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 40.0:
        before_mm, flavum_mm = rng.uniform(30.0, 55.0), rng.uniform(3.0, 6.0)
        stretch = before_mm / float(depth_mm[-1])
        scale = rng.uniform(1.5, 3.5) / max(float(force_n.max()), 1e-3)
        end_n = scale * float(force_n[-1])
        flavum_n, power = rng.uniform(1.5, 3.5), rng.uniform(1.5, 2.5)

        def resistance(d, end_n=end_n, flavum_n=flavum_n, power=power, stretch=stretch, scale=scale,
                       before_mm=before_mm, flavum_mm=flavum_mm):
            inside = np.clip((d - before_mm) / flavum_mm, 0.0, 1.0)
            return np.where(d < before_mm, scale * np.interp(d / stretch, depth_mm, force_n),
                            end_n + flavum_n * inside ** power)

        reached, relaxed, lost = 0.0, 0.0, False
        while not lost and now < duration_s:
            step, speed = rng.uniform(1.0, 2.5), rng.uniform(1.0, 3.0)
            goal = min(reached + step, before_mm + flavum_mm)
            seg, s = at(now, (goal - reached) / speed)
            d = reached + speed * s
            f[seg] = relaxed + (resistance(d) - relaxed) * quintic((d - reached) / 0.5)
            now += (goal - reached) / speed
            last = float(resistance(np.array([goal]))[0])
            reached = goal
            if goal >= before_mm + flavum_mm:  # the loss of resistance
                drag, drop = rng.uniform(0.3, 0.6) * end_n, rng.uniform(0.04, 0.12)
                seg, s = at(now, drop)
                f[seg] = last + (drag - last) * quintic(s / drop)
                now += drop
                lost = True
                relaxed = drag
                break
            stop, keep, tau = rng.uniform(1.5, 4.0), rng.uniform(0.6, 0.85), rng.uniform(0.5, 2.0)
            seg, s = at(now, stop)
            f[seg] = last * (keep + (1.0 - keep) * np.exp(-s / tau))
            for press in np.sort(rng.uniform(0.1, stop - 0.5, int(rng.integers(2, 5)))):
                width = rng.uniform(0.2, 0.5)
                seg, s = at(now + press, width)
                f[seg] += rng.uniform(0.2, 0.8) * 0.5 * (1.0 - np.cos(2.0 * np.pi * s / width))
            now += stop
            relaxed = last * (keep + (1.0 - keep) * math.exp(-stop / tau))
        hold = rng.uniform(5.0, 12.0)
        seg, s = at(now, hold)
        f[seg] = relaxed * (0.85 + 0.15 * np.exp(-s / 2.0))
        now += hold
        relaxed *= 0.85 + 0.15 * math.exp(-hold / 2.0)
        thread, drag, strokes = rng.uniform(10.0, 25.0), rng.uniform(0.1, 0.4), rng.uniform(0.5, 1.5)
        seg, s = at(now, thread)
        f[seg] = relaxed + drag * 0.5 * (1.0 - np.cos(2.0 * np.pi * strokes * s)) * quintic(s / 0.5)
        now += thread
        seg, s = at(now, 0.5)
        f[seg] = relaxed * (1.0 - quintic(s / 0.5))
        now += 0.5 + rng.uniform(8.0, 25.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def cochlear_insertion(duration_s, rate_hz, rng):
    """A robot inserting a cochlear implant's electrode array through the round window (the sensor behind the array's
    holder), again and again into a cochlea phantom: 20-28 mm at 0.3-1.2 mm/s in 2-4 advances with pauses of 2-6 s
    (the array's push relaxing by 10-30 % with a time constant of 1-3 s). The push is a base of 0.05-0.2 N, a drag
    growing 0.01-0.04 N per mm, and the capstan friction of the array on the outer wall of the scala once past its
    straight basal part (6-10 mm): exp(mu theta) - 1, mu 0.1-0.3, the wrap theta growing a turn per 12-18 mm; all scaled
    to a 2.5-7 N peak. Beyond 55-90 % of the depth the tip catches on the wall 2-5 times: the push builds by 0.2-0.6 N
    over 0.3-1 mm and is released in 20-60 ms as the array buckles past. A hold of 5-20 s at full depth (the push
    relaxing by 10-25 %), a retraction in 1-2 s, 10-30 s before the next insertion. The tool regrips the array at the
    start of each advance: a click of its jaws (4-10 ms, 0.3-1 N)."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    at = window(t)
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 30.0:
        depth, speed = rng.uniform(20.0, 28.0), rng.uniform(0.3, 1.2)
        grid = np.arange(0.0, depth + 0.05, 0.05)
        wrap = 2.0 * np.pi * np.maximum(grid - rng.uniform(6.0, 10.0), 0.0) / rng.uniform(12.0, 18.0)
        push = rng.uniform(0.05, 0.2) + rng.uniform(0.01, 0.04) * grid + np.expm1(rng.uniform(0.1, 0.3) * wrap)
        push *= rng.uniform(2.5, 7.0) / max(float(push.max()), 1e-9)
        for catch in rng.uniform(0.55, 0.9, int(rng.integers(2, 6))) * depth:
            build, height = rng.uniform(0.3, 1.0), rng.uniform(0.2, 0.6)
            rising = (grid > catch - build) & (grid <= catch)
            push[rising] += height * (grid[rising] - catch + build) / build  # released within one 0.05 mm step
        stops = np.sort(rng.uniform(0.15, 0.9, int(rng.integers(1, 4)))) * depth
        reached, relaxed = 0.0, 0.0
        for goal in [*stops.tolist(), depth]:
            click(f, at, now, rng, 0.3, 1.0)  # the insertion tool regrips the array
            seg, s = at(now, (goal - reached) / speed)
            d = reached + speed * s
            f[seg] = relaxed + (np.interp(d, grid, push) - relaxed) * quintic((d - reached) / 0.3)
            now += (goal - reached) / speed
            last = float(np.interp(goal, grid, push))
            pause = rng.uniform(2.0, 6.0) if goal < depth else rng.uniform(5.0, 20.0)
            drop, tau = rng.uniform(0.1, 0.3), rng.uniform(1.0, 3.0)
            seg, s = at(now, pause)
            f[seg] = last * (1.0 - drop * -np.expm1(-s / tau))
            now += pause
            reached, relaxed = goal, last * (1.0 - drop * -math.expm1(-pause / tau))
        back = rng.uniform(1.0, 2.0)
        seg, s = at(now, back)
        f[seg] = relaxed * (1.0 - quintic(s / back))
        now += back + rng.uniform(10.0, 30.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def robotic_suturing(duration_s, rate_hz, rng):
    """A surgical robot suturing (the sensor in its needle driver's wrist). Each stitch: the curved needle pierces the
    tissue (1-3 N reached in 0.5-1.5 s, then a puncture that drops it by 30-60 % in 30 ms), is rotated along its arc for
    1-3 s (the force waning to 30-60 % of the pierce and rising again to an exit peak of 50-90 % of it, released in 30
    ms), let go and regrasped (1-3 s of nothing), and the thread pulled through (2-5 s: a drag growing from 0.2 N to
    0.3-1 N with a stick-slip serration of 0.02-0.1 N at 3-8 Hz); then a knot of 3-4 throws, each tightened to 2-7 N in
    0.3-0.8 s, held 0.5-1.5 s while it settles by 10-20 %, released in 0.2 s, 2-5 s apart. 5-15 s between stitches.
    Each grasp of the needle or the thread closes the jaws with a click (4-10 ms, 0.5-1.5 N)."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    at = window(t)
    now = rng.uniform(2.0, 5.0)
    while now < duration_s - 25.0:
        pierce, rise = rng.uniform(1.0, 3.0), rng.uniform(0.5, 1.5)
        click(f, at, now, rng, 0.5, 1.5)
        seg, s = at(now, rise)
        f[seg] = pierce * quintic(s / rise) ** 1.5
        now += rise
        dropped = pierce * rng.uniform(0.4, 0.7)
        seg, s = at(now, 0.03)
        f[seg] = pierce + (dropped - pierce) * quintic(s / 0.03)
        now += 0.03
        arc, low, exit_n = rng.uniform(1.0, 3.0), pierce * rng.uniform(0.3, 0.6), pierce * rng.uniform(0.5, 0.9)
        seg, s = at(now, arc)
        u = s / arc
        f[seg] = np.where(u < 0.5, dropped + (low - dropped) * quintic(2.0 * u), low + (exit_n - low) * quintic(2.0 * u - 1.0))
        now += arc
        seg, s = at(now, 0.03)
        f[seg] = exit_n * (1.0 - quintic(s / 0.03))
        now += 0.03 + rng.uniform(1.0, 3.0)
        pull, top, serration, rate = rng.uniform(2.0, 5.0), rng.uniform(0.3, 1.0), rng.uniform(0.02, 0.1), \
            rng.uniform(3.0, 8.0)
        click(f, at, now, rng, 0.5, 1.5)
        seg, s = at(now, pull)
        f[seg] = (0.2 + (top - 0.2) * s / pull + serration * np.abs(np.sin(np.pi * rate * s))) * quintic(s / 0.2)
        now += pull
        seg, s = at(now, 0.2)
        f[seg] = top * (1.0 - quintic(s / 0.2))
        now += 0.2 + rng.uniform(1.0, 2.0)
        for _ in range(int(rng.integers(3, 5))):
            tight, rise, hold, settle = rng.uniform(2.0, 7.0), rng.uniform(0.3, 0.8), rng.uniform(0.5, 1.5), \
                rng.uniform(0.1, 0.2)
            click(f, at, now, rng, 0.5, 1.5)
            seg, s = at(now, rise)
            f[seg] = tight * quintic(s / rise)
            now += rise
            seg, s = at(now, hold)
            f[seg] = tight * (1.0 - settle * -np.expm1(-s / 0.4))
            now += hold
            last = tight * (1.0 - settle * -math.expm1(-hold / 0.4))
            seg, s = at(now, 0.2)
            f[seg] = last * (1.0 - quintic(s / 0.2))
            now += 0.2 + rng.uniform(2.0, 5.0)
        now += rng.uniform(5.0, 15.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (epidural_loss_of_resistance, cochlear_insertion, robotic_suturing)


def temperature(t, rng, step_s=0.5):
    """A sensor on the needle guide of a robot for CT-guided percutaneous cryoablation. The room's air conditioning
    holds it 0.5 degC below to 1.5 degC above the reference, drifting by up to +-0.3 degC over the record and cycling
    by 0.05-0.2 degC (a period of 120-400 s). A cryoprobe beside the guide runs freeze-thaw cycles that began 100-600 s
    before the record: freezes of 120-220 s (the probe's gas return cooling the guide toward 2.5-5 degC below the
    room), a passive thaw of 50-100 s (toward the room), an active thaw of 20-50 s (toward 0.5-2 degC above it), now
    and then a pause of 30-120 s while the next probe is placed. The guide approaches its goal with a time constant of
    15-40 s, the sensor the guide with 10-30 s (exact per step of ``step_s``), from 900 s before the record."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-900.0, d + 2.0 * step_s, step_s)
    room = T_REF_C + rng.uniform(-0.5, 1.5) + rng.uniform(-0.3, 0.3) * grid / d \
        + rng.uniform(0.05, 0.2) * np.sin(2.0 * np.pi * grid / rng.uniform(120.0, 400.0) + rng.uniform(0.0, 2.0 * np.pi))
    edges, goals, now = [-900.0], [0.0], -rng.uniform(100.0, 600.0)
    while now < d:
        for length, goal in ((rng.uniform(120.0, 220.0), -rng.uniform(2.5, 5.0)), (rng.uniform(50.0, 100.0), 0.0),
                             (rng.uniform(20.0, 50.0), rng.uniform(0.5, 2.0))):
            edges.append(now)
            goals.append(goal)
            now += length
        if rng.random() < 0.4:  # the next probe placed
            edges.append(now)
            goals.append(0.0)
            now += rng.uniform(30.0, 120.0)
    goal = np.asarray(goals)[np.searchsorted(np.asarray(edges), grid, side="right") - 1]
    guide_keep, sensor_keep = math.exp(-step_s / rng.uniform(15.0, 40.0)), math.exp(-step_s / rng.uniform(10.0, 30.0))
    guide = sensor = float(room[0])
    out = np.empty(grid.size)
    for i, (r, g) in enumerate(zip(room.tolist(), goal.tolist())):
        out[i] = sensor
        guide = r + g + (guide - r - g) * guide_keep
        sensor = guide + (sensor - guide) * sensor_keep
    return np.interp(s, grid, out)


# ----------------------------------------------------------------------------- helpers of the truth elements


def follow(t, temp, tau_s, step_s=0.5):
    """``temp`` seen by a body that follows it with a time constant ``tau_s`` (exact per coarse step), settled at the
    start."""
    grid, tg = coarse(t, temp, step_s)
    keep, y = math.exp(-step_s / tau_s), float(tg[0])
    out = np.empty_like(tg)
    for i, goal in enumerate(tg.tolist()):
        y = goal + (y - goal) * keep
        out[i] = y
    return np.interp(t, grid, out)


def on_clock(c, t, f, rate):
    """The core's deformation on the clock ``rate`` (its reduced time, from t[0])."""
    return simulate_deformation(c, integrate.cumulative_trapezoid(rate, t, initial=0.0) + t[0], f)


# ----------------------------------------------------------------------------- viscous flow


def rejuvenated_ageing_flow(young, age0_s, age_scale_s, mu, rejuvenate_n, rejuvenate_s, step_s=0.05):
    """x' = A F, A = ``young`` (1 + a / ``age_scale_s``)^-``mu``: a glassy core whose effective age a grows with time
    (physical ageing, a' = 1) and is taken back by a load beyond ``rejuvenate_n`` (stress-induced rejuvenation,
    a' = 1 - a (F - F_r) / (1 N ``rejuvenate_s``)), from ``age0_s`` at the start (the core rested before the record).
    The age is exact per coarse step of ``step_s`` at the step's force."""
    def rule(t, f):
        grid, fg = coarse(t, f, step_s)
        age, out = age0_s, np.empty(grid.size)
        for i, fi in enumerate(fg.tolist()):
            out[i] = age
            r = max(fi - rejuvenate_n, 0.0) / rejuvenate_s  # 1/s per N of excess
            age = 1.0 / r + (age - 1.0 / r) * math.exp(-r * step_s) if r > 0.0 else age + step_s
        fluidity = young * (1.0 + np.interp(t, grid, out) / age_scale_s) ** -mu
        return integrate.cumulative_trapezoid(fluidity * np.maximum(f, 0.0), t, initial=0.0)
    return rule


def self_heated_flow(fluidity, heat_s, work_nv, cap=1.5, step_s=0.05):
    """x' = A0 exp(u) F: a thin viscous layer whose own dissipation F x' warms it (u, in e-folds of its viscosity,
    gains F x' / ``work_nv`` and loses u / ``heat_s``), held below ``cap``; exact per coarse step of ``step_s`` for the
    loss, from a cool layer."""
    def rule(t, f):
        grid, fg = coarse(t, np.maximum(f, 0.0), step_s)
        keep = math.exp(-step_s / heat_s)
        u, out = 0.0, np.empty(grid.size)
        for i, fi in enumerate(fg.tolist()):
            out[i] = u
            power = fi * fluidity * math.exp(u) * fi
            u = min(u * keep + heat_s * (1.0 - keep) * power / work_nv, cap)
        rate = fluidity * np.exp(np.interp(t, grid, out)) * np.maximum(f, 0.0)
        return integrate.cumulative_trapezoid(rate, t, initial=0.0)
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

KAPPA_AIR = 0.4 / 1.4  # (gamma - 1) / gamma of air: an adiabatic change of pressure warms it by this power


def adiabatic_cells(t, f, scale_v, doubling_n, tau_s, step_s=0.01):
    """-``scale_v`` (theta - 1) / r: the air in a closed-cell (printed lattice) core, at the relative pressure
    r = 1 + F / ``doubling_n``, warmed adiabatically by each compression (theta *= (r1 / r0)^kappa) and cooled back to
    the cells' walls (theta - 1 decaying with ``tau_s``); at a given force warm air fills more volume than cool air,
    so the core settles further as the air cools, and springs back further as it warms after an unloading. Per coarse
    step of ``step_s``, from equilibrium."""
    grid, fg = coarse(t, np.maximum(f, 0.0), step_s)
    r = 1.0 + fg / doubling_n
    jumps = np.exp(KAPPA_AIR * np.diff(np.log(r), prepend=math.log(r[0]))).tolist()
    keep, theta, out = math.exp(-step_s / tau_s), 1.0, np.empty(grid.size)
    for i, jump in enumerate(jumps):
        theta = 1.0 + (theta * jump - 1.0) * keep
        out[i] = theta
    return np.interp(t, grid, -scale_v * (out - 1.0) / r)


class DielectricAbsorption(SimOnly):
    """A capacitive read-out whose dielectric soaks up a share of each change of its charge: y = x + ``share`` sum_k
    w_k lag_k(x - x0), the rates of the lags gamma-distributed (density lambda^(n-1) exp(-lambda t0), 28 on a log grid
    from 1/3000 to 20 / t0 per second): a creep of 1 - (1 + t / t0)^-n after each change (Jonscher's universal
    response). On a coarse grid of 10 ms."""

    def __init__(self, share, t0_s, n):
        self.rates = np.logspace(math.log10(1.0 / 3000.0), math.log10(20.0 / t0_s), 28)
        w = self.rates ** n * np.exp(-self.rates * t0_s)  # on a log grid: d lambda = lambda d ln lambda
        self.share, self.w = share, w / w.sum()

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        grid, xg = coarse(t, x, 0.01)
        lags = exp_convolve(grid, xg - xg[0], self.rates) * self.rates
        return x + self.share * np.interp(t, grid, lags @ self.w)


# ----------------------------------------------------------------------------- hysteresis

class ShakedownPlays(SimOnly):
    """A fresh printed silver trace in the bridge that yields micro-plastically: y = x + sum_k w_k (p_k(x) - x), plays
    of radii r_k s(tau), s = ``final`` + (1 - ``final``) exp(-tau / ``travel_v``), tau the travel of x so far (the loops
    shrink as the trace shakes down, by cyclic hardening)."""

    def __init__(self, radii_v, weights, final, travel_v):
        self.radii, self.w, self.final, self.travel = radii_v, weights, final, travel_v

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        travel = np.cumsum(np.abs(np.diff(x, prepend=x[0])))
        shrink = self.final + (1.0 - self.final) * np.exp(-travel / self.travel)
        out = x.copy()
        for r, w in zip(self.radii, self.w):
            out += w * (band_play(x, r * shrink, r * shrink) - x)
        return out


def ink_bottle_pores(t, f, fill_n, empty_n, volume_v):
    """sum_i v_i s_i: a porous printed core whose pores a liquid (the core's oil) invades as the load raises its
    pressure, each through its narrow neck (filled once F reaches ``fill_n``) and leaves only when the pressure has
    fallen to what its wide body holds (emptied once F falls to ``empty_n``: the ink-bottle effect); every filled pore
    adds its volume ``volume_v`` to the core's settlement. Independent domains (relays), all empty at the start."""
    f = np.asarray(f, dtype=float)
    idx = np.arange(f.size)
    out = np.zeros_like(f)
    for a, b, v in zip(fill_n, empty_n, volume_v):
        on = np.maximum.accumulate(np.where(f >= a, idx, -1))
        off = np.maximum.accumulate(np.where(f <= b, idx, -1))
        out += v * (on > off)
    return out


# ----------------------------------------------------------------------------- sensor lag

class CameraTactile(SimOnly):
    """A vision-based (gel and camera) tactile read-out: each frame (every ``frame_s``, from ``phase_s``) averages the
    signal over its exposure ``exposure_s``, is processed for ``latency_s`` and then held until the next one arrives."""

    def __init__(self, frame_s, exposure_s, latency_s, phase_s):
        self.frame, self.exposure, self.latency, self.phase = frame_s, exposure_s, latency_s, phase_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        area = integrate.cumulative_trapezoid(x, t, initial=0.0)

        def integral(u):  # before the first sample, the signal as it was then
            return np.where(u < t[0], x[0] * (u - t[0]), np.interp(u, t, area))
        frames = t[0] + self.phase + self.frame * np.arange(int((t[-1] - t[0]) / self.frame) + 2)
        means = (integral(frames) - integral(frames - self.exposure)) / self.exposure
        k = np.floor((t - t[0] - self.phase - self.latency) / self.frame).astype(int)
        return np.where(k >= 0, means[np.clip(k, 0, means.size - 1)], x[0])


def twin_t_notch(notch_hz, q, tau_s):
    """A passive twin-T mains notch, (s^2 + w0^2) / (s^2 + w0 s / q + w0^2), behind a first-order anti-alias RC of
    ``tau_s``: at low frequencies a delay of 1 / (q w0) + tau."""
    w0 = 2.0 * math.pi * notch_hz
    return LinearFilter([1.0, 0.0, w0 * w0], np.polymul([1.0, w0 / q, w0 * w0], [tau_s, 1.0]).tolist())


# ----------------------------------------------------------------------------- nonlinear gain

def lindley_oring(rel, reach, preload):
    """x read through the squeeze of an elastomer O-ring that carries the load: Lindley's law, F ~ 1.25 e^1.5 + 50
    e^6 (e the squeeze), inverted for e, from a squeeze ``preload`` in its gland; slope 1 at zero, the load's scale set
    for a compression ``rel`` at ``reach``."""
    squeeze = np.linspace(0.0, 0.6, 6001)
    load = 1.25 * squeeze ** 1.5 + 50.0 * squeeze ** 6
    at_rest = 1.25 * preload ** 1.5 + 50.0 * preload ** 6
    slope0 = 1.0 / (1.875 * preload ** 0.5 + 300.0 * preload ** 5)  # d squeeze / d load at the preload

    rest = float(np.interp(at_rest, load, squeeze))  # the table's own, so that zero reads zero

    def read(x, scale):
        goal = np.clip(at_rest + scale * np.asarray(x, dtype=float), 0.0, load[-1])
        return (np.interp(goal, load, squeeze) - rest) / (scale * slope0)
    most = (load[-1] - at_rest) / reach
    scale = optimize.brentq(lambda k: float(read(reach, k)) / reach - 1.0 + rel, 1e-4 * most, 0.999 * most)
    return lambda x: read(x, scale)


def fsr_divider(rel, reach, ratio, exponent):
    """x read by a force-sensing resistor (a preloaded carbon-filled film whose conductance grows as (1 + x / x0)^t)
    in a voltage divider with a fixed resistor ``ratio`` times smaller than its resting resistance: D = 1 / (1 + ratio
    (1 + x / x0)^-t), slope 1 at zero; x0 set for a largest departure ``rel`` over [0, ``reach``] (expansive at first
    when the film is much the larger resistor, compressive when it is the smaller, S-shaped in between)."""
    def divider(x, x0):
        return 1.0 / (1.0 + ratio * np.maximum(1.0 + np.asarray(x, dtype=float) / x0, 1e-6) ** -exponent)

    def read(x, x0):
        slope = ratio * exponent / x0 / (1.0 + ratio) ** 2
        return (divider(x, x0) - divider(0.0, x0)) / slope

    probe = np.linspace(0.0, reach, 201)

    def excess(log_x0):
        x0 = math.exp(log_x0)
        return float(np.max(np.abs(read(probe, x0) - probe))) / reach - rel
    grid = np.linspace(math.log(reach * 1e3), math.log(reach * 1e-2), 121)  # from nearly linear to strongly bent
    values = [excess(g) for g in grid]
    k = next(i for i, v in enumerate(values) if v > 0.0)
    x0 = math.exp(optimize.brentq(excess, grid[k - 1], grid[k]))
    return lambda x: read(x, x0)


# ----------------------------------------------------------------------------- thermal drift

def dew_point_zero(t, temp, size_v, quantile, condense_cs, dry_cs, lag_s, step_s=0.5):
    """``size_v`` h: a water film that condenses on the bridge board whenever it (lag ``lag_s``) is colder than the
    room air's dew point (set at the ``quantile`` of the board's temperature over the record: the air's humidity is
    such that the cold phases condense) and evaporates when it is warmer; h (0..1) gains (T_dew - T_b) / ``condense_cs``
    per second and loses (T_b - T_dew) / ``dry_cs``; the film's leakage sets the zero. Dry at the start."""
    board = follow(t, temp, lag_s)
    dew = float(np.quantile(board, quantile))
    grid, bg = coarse(t, board, step_s)
    h, out = 0.0, np.empty(grid.size)
    for i, b in enumerate(bg.tolist()):
        out[i] = h
        h = min(h + (dew - b) * step_s / condense_cs, 1.0) if b < dew else max(h - (b - dew) * step_s / dry_cs, 0.0)
    return size_v * np.interp(t, grid, out)


def ntc_trimmed_zero(t, temp, k_v_per_c, gauge_s, board_s, beta_k, divider, cover):
    """k (T_g - T_ref - ``cover`` c(T_b)): the gauges' thermal zero (their temperature T_g lagging by ``gauge_s``)
    trimmed by an NTC thermistor on the amplifier board (T_b, lag ``board_s``) in a divider with a fixed resistor
    ``divider`` times its resistance at the reference: c the divider's change in degC of its slope at the reference
    (exponential in 1 / T, beta ``beta_k``), ``cover`` the share of the zero the trim was meant to take."""
    def ntc(temp_c):
        resistance = np.exp(beta_k * (1.0 / (np.asarray(temp_c) + 273.15) - 1.0 / (T_REF_C + 273.15)))
        return divider / (divider + resistance)
    slope = float(ntc(T_REF_C + 0.01) - ntc(T_REF_C - 0.01)) / 0.02
    trimmed = (ntc(follow(t, temp, board_s)) - float(ntc(T_REF_C))) / slope
    return k_v_per_c * (follow(t, temp, gauge_s) - T_REF_C - cover * trimmed)


# ----------------------------------------------------------------------------- thermal sensitivity

class StaleSpanCorrection(SimOnly):
    """A polymer core whose span rises by ``coefficient`` per degC of its temperature (lag ``lag_s``), corrected by
    firmware that reads the thermometer every ``poll_s`` (from ``phase_s``) and divides by 1 + ``applied`` (T - T_ref):
    between polls the correction is stale."""

    def __init__(self, coefficient, applied, lag_s, poll_s, phase_s):
        self.a, self.applied, self.lag, self.poll, self.phase = coefficient, applied, lag_s, poll_s, phase_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        temp = temp_of(aux, t.size)
        polls = t[0] + self.phase + self.poll * np.arange(-1, int((t[-1] - t[0]) / self.poll) + 2)
        read = np.interp(polls, t, temp)  # before the record: the first reading
        k = np.clip(np.searchsorted(polls, t, side="right") - 1, 0, polls.size - 1)
        span = (1.0 + self.a * (follow(t, temp, self.lag) - T_REF_C)) / (1.0 + self.applied * (read[k] - T_REF_C))
        return np.asarray(x, dtype=float) * span


class CrystallineSpan(SimOnly):
    """A core blended with a low-melting crystalline phase (lag ``lag_s``): its molten share phi melts toward
    logistic((T - T_m) / w) (time constant ``melt_s``) when below it and crystallises toward logistic((T - T_c) / w),
    T_c = T_m - ``supercool_c``, (``freeze_s``) when above that; the molten share softens the core, the span
    1 + ``gain`` (phi - phi_0). T_m is set at the ``quantile`` of the core's temperature over the record (a blend whose
    melting range the record visits). Exact per coarse step of 0.5 s; at the start on its melting branch."""

    def __init__(self, gain, quantile, width_c, supercool_c, melt_s, freeze_s, lag_s):
        self.gain, self.q, self.w, self.supercool = gain, quantile, width_c, supercool_c
        self.melt, self.freeze, self.lag = melt_s, freeze_s, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        core_t = follow(t, temp_of(aux, t.size), self.lag)
        melt_c = float(np.quantile(core_t, self.q))
        grid, cg = coarse(t, core_t, 0.5)
        melting, freezing = logistic((cg - melt_c) / self.w), logistic((cg - melt_c + self.supercool) / self.w)
        km, kf = math.exp(-0.5 / self.melt), math.exp(-0.5 / self.freeze)
        phi, out = float(melting[0]), np.empty(grid.size)
        for i, (up, down) in enumerate(zip(melting.tolist(), freezing.tolist())):
            out[i] = phi
            if phi < up:
                phi = up + (phi - up) * km
            elif phi > down:
                phi = down + (phi - down) * kf
        return np.asarray(x, dtype=float) * (1.0 + self.gain * (np.interp(t, grid, out) - out[0]))


# ----------------------------------------------------------------------------- offset drift

def staff_proximity(s, passes, stands):
    """The body capacitance of theatre staff near a capacitive read-out's high-impedance input: each pass (time,
    closest distance b in m, speed in m/s, weight, power p) couples as (0.5 / b)^p (1 + ((s - t0) v / b)^2)^(-p/2); each
    stand (start, length, ramp, level) someone leaning over the sensor."""
    out = np.zeros_like(s)
    for at, closest, speed, weight, power in passes:
        out += weight * (0.5 / closest) ** power * (1.0 + ((s - at) * speed / closest) ** 2) ** (-0.5 * power)
    for at, length, ramp, level in stands:
        out += level * quintic((s - at) / ramp) * (1.0 - quintic((s - at - length) / ramp))
    return out


def desorption(s, started_s, diffusion_s, modes=200):
    """The share of a sterilant (ethylene oxide) that a freshly aerated polymer slab has lost, Crank's series
    1 - sum 8 / ((2n+1)^2 pi^2) exp(-(2n+1)^2 pi^2 u), u = (s + ``started_s``) / ``diffusion_s``."""
    odd = (2.0 * np.arange(modes) + 1.0) ** 2 * np.pi ** 2
    u = np.maximum(np.asarray(s, dtype=float) + started_s, 0.0) / diffusion_s
    return 1.0 - np.exp(-np.multiply.outer(u, odd)) @ (8.0 / odd)


def desorption_zero(size_v, started_s, diffusion_s, horizon_s=HORIZON_S):
    """``size_v`` times the desorption since the first sample, over what it reaches by ``horizon_s``: the polymer
    shrinks as it loses the sterilant, and the zero with it. On a 0.5 s grid."""
    grid = np.arange(0.0, horizon_s + 0.5, 0.5)
    lost = desorption(grid, started_s, diffusion_s)
    lost = (lost - lost[0]) / max(lost[-1] - lost[0], 1e-12)
    return lambda s: size_v * np.interp(s, grid, lost)


# ----------------------------------------------------------------------------- resonance

def mode_steps(t, x, sub=4):
    """A mode driven by ``x`` on a uniform grid at the median step: (grid, drive, its rate, sub-step)."""
    tu, xu, h = uniform_grid(t, x)
    return tu, xu.tolist(), np.gradient(xu, h).tolist(), h / sub


class StringModes(SimOnly):
    """A taut tendon of the robot's transmission that runs to the sensor: its string modes n f1 (n = 1..``count``),
    base-excited ((2 zeta_n w_n s + w_n^2) / (s^2 + 2 zeta_n w_n s + w_n^2)), weighted 1 / n^2 (a load at its end),
    zeta_n = zeta_1 / n (losses at the terminations, the same decay per second for every mode) + eta n (the tendon's
    own)."""

    def __init__(self, f1_hz, zeta1, eta, count):
        weights = 1.0 / np.arange(1, count + 1) ** 2
        self.w = weights / weights.sum()
        self.modes = []
        for n in range(1, count + 1):
            w, zeta = 2.0 * math.pi * n * f1_hz, zeta1 / n + eta * n
            self.modes.append(LinearFilter([2.0 * zeta * w, w * w], [1.0, 2.0 * zeta * w, w * w]))

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        return sum(w * mode.forward(t, x) for w, mode in zip(self.w, self.modes))


class WireRopeMode(SimOnly):
    """A needle holder on a wire-rope isolator: y'' + 2 zeta w (y' - x') + w^2 (a e + (1 - a) z) = 0, e = y - x, the
    rope's hysteretic part z a Bouc-Wen state (n = 1, beta = gamma) saturating at ``z_max_v``: small swings ring at w
    and lightly damped, large ones at a softer spring with hysteretic damping. Semi-implicit Euler, four sub-steps,
    from rest."""

    def __init__(self, f0_hz, zeta, share, z_max_v):
        self.w, self.zeta, self.a, self.z_max = 2.0 * math.pi * f0_hz, zeta, share, z_max_v

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        tu, xu, rate, sub = mode_steps(t, np.asarray(x, dtype=float))
        c, w2, a, z_max = 2.0 * self.zeta * self.w, self.w * self.w, self.a, self.z_max
        y, v, z, out = xu[0], 0.0, 0.0, np.empty(len(xu))
        for i, (xi, ri) in enumerate(zip(xu, rate)):
            for _ in range(4):
                v += (-c * (v - ri) - w2 * (a * (y - xi) + (1.0 - a) * z)) * sub
                de = (v - ri) * sub
                y += v * sub
                z += de * (1.0 - abs(z) / z_max) if de * z > 0.0 else de
            out[i] = y
        return np.interp(t, tu, out)


# ----------------------------------------------------------------------------- friction

def tendon_sheath(mu, seal_n, moves, first_rad):
    """The force passed through a tendon in a sheath (the capstan law) and its entry seal: stuck between
    F e^(-mu theta) - ``seal_n`` and F e^(mu theta) + ``seal_n``, theta the sheath's total bend, which the robot changes
    by minimum-jerk moves (start, length, to) as it steers the flexible instrument."""
    def passed(t, f):
        s = t - t[0]
        theta = np.full(s.size, float(first_rad))
        for start, length, goal in moves:
            theta = np.where(s >= start, theta + (goal - theta) * quintic((s - start) / length), theta)
        load = np.abs(f)
        return band_play(f, load * -np.expm1(-mu * theta) + seal_n, load * np.expm1(mu * theta) + seal_n)
    return passed


def spun_needle_band(band_n, spin_n_per_s, sessions):
    """A Coulomb band ``band_n`` on the needle in its guide, which the robot spins now and then (``sessions``): while
    it spins the contact slides around the needle, so the axial friction is the band times the axial share of the
    sliding velocity, p' / sqrt(p'^2 + q^2), q = ``spin_n_per_s`` (a friction cone): the stuck force creeps toward the
    applied one. Per sample, the creep exact at the sample's rate."""
    def passed(t, f):
        spinning = within(t - t[0], sessions).tolist()
        steps = np.diff(t, prepend=t[0]).tolist()
        p, out = float(f[0]), np.empty(f.size)
        for i, (fi, h, spin) in enumerate(zip(f.tolist(), steps, spinning)):
            if spin:
                d = min(abs(fi - p) / band_n, 0.999)
                p += (fi - p) * -math.expm1(-h * spin_n_per_s / (band_n * math.sqrt(1.0 - d * d)))
            p = max(fi - band_n, min(fi + band_n, p))
            out[i] = p
        return out
    return passed


# ----------------------------------------------------------------------------- thermo-rheological

class CuringClock(SimOnly):
    """A freshly printed resin core still curing: its clock exp(b (T_c - T_ref) - ``slowing`` (X - X_0)), T_c its
    temperature (lag ``lag_s``), the cure X advancing from ``start`` at the Arrhenius rate exp(``b_cure`` (T_c - T_ref))
    / ``cure_s`` of (1 - X) (the network tightening slows the creep). Exact per coarse step of 0.5 s."""

    def __init__(self, c, b_per_c, lag_s, cure_s, b_cure, start, slowing):
        self.c, self.b, self.lag, self.cure, self.b_cure, self.start, self.slowing = \
            c, b_per_c, lag_s, cure_s, b_cure, start, slowing

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        core_t = follow(t, temp_of(aux, t.size), self.lag)
        grid, cg = coarse(t, core_t, 0.5)
        cured, out = self.start, np.empty(grid.size)
        for i, ti in enumerate(cg.tolist()):
            out[i] = cured
            cured = 1.0 - (1.0 - cured) * math.exp(-0.5 * math.exp(self.b_cure * (ti - T_REF_C)) / self.cure)
        rate = np.exp(self.b * (core_t - T_REF_C) - self.slowing * (np.interp(t, grid, out) - self.start))
        return on_clock(self.c, t, np.asarray(x, dtype=float), rate)


class HeatedCoreClock(SimOnly):
    """A core kept warm by a heating foil under a proportional controller of limited power: T_c' = (T - T_c + P) /
    ``tau_s``, P = clip(``gain`` (T_set - T_c), 0, ``reach_c``) (P in degC of steady warming): within the heater's
    reach the core holds near T_set, beyond it follows the air; its clock exp(b (T_c - T_ref)). Exact per coarse step
    of 0.5 s for the approach, at the step's power; settled at the start."""

    def __init__(self, c, b_per_c, set_c, gain, reach_c, tau_s):
        self.c, self.b, self.set, self.gain, self.reach, self.tau = c, b_per_c, set_c, gain, reach_c, tau_s

    def settled(self, air):
        """The core's steady temperature in ``air``."""
        held = (air + self.gain * self.set) / (1.0 + self.gain)
        return air + self.reach if self.gain * (self.set - held) > self.reach else max(held, air)

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        grid, tg = coarse(t, temp_of(aux, t.size), 0.5)
        keep = math.exp(-0.5 / self.tau)
        core, out = self.settled(float(tg[0])), np.empty(grid.size)
        for i, air in enumerate(tg.tolist()):
            out[i] = core
            power = min(max(self.gain * (self.set - core), 0.0), self.reach)
            core = air + power + (core - air - power) * keep
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(self.b * (np.interp(t, grid, out) - T_REF_C)))


# ----------------------------------------------------------------------------- outside the catalogue

def electrosurgery(s, activations, flicker, step_s):
    """Each activation of the electrosurgical unit (start, length, level, rise, tail) rectified by the bridge
    amplifier: the level reached within ``rise``, modulated by the coagulation waveform's bursts (``flicker``, on a grid
    of ``step_s`` from 0), and a recovery over ``tail`` seconds once it stops."""
    wobble = 1.0 + np.interp(s, step_s * np.arange(flicker.size), flicker)
    out = np.zeros_like(s)
    for at, length, level, rise, tail in activations:
        u = s - at
        on = (u >= 0.0) & (u < length)
        out[on] += level * quintic(u[on] / rise) * wobble[on]
        after = u >= length
        out[after] += level * np.exp(-(u[after] - length) / tail)
    return out


class PolarisationFading(SimOnly):
    """An optical (polarimetric) read-out through a fibre whose state of polarisation wanders: the span
    (1 - v sin^2 psi(s)) / (1 - v sin^2 psi(0)), psi a smooth random angle (``angle``: values on a grid of 0.5 s from
    the first sample)."""

    def __init__(self, depth, angle):
        self.v, self.angle = depth, angle

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        psi = np.interp(t - t[0], 0.5 * np.arange(self.angle.size), self.angle)
        return np.asarray(x, dtype=float) * (1.0 - self.v * np.sin(psi) ** 2) / (1.0 - self.v * math.sin(self.angle[0]) ** 2)


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([6e4, 4e3]))))  # V / (N s)
        if shape == "rejuvenated_ageing_flow":
            age0, scale, mu = rng.uniform(200.0, 2000.0), rng.uniform(30.0, 120.0), rng.uniform(0.4, 0.7)
            young = phi * rng.uniform(1.0, 1.8) * (1.0 + age0 / scale) ** mu  # the rested core's fluidity: 1-1.8 phi
            rule = rejuvenated_ageing_flow(young, age0, scale, mu, rng.uniform(1.5, 3.5), rng.uniform(5.0, 30.0))
            return Parts("zener", ZenerWithFlow(c, rule), core_changed=True)
        fluidity, heat_s, warm = phi * rng.uniform(1.0, 2.0), rng.uniform(10.0, 60.0), rng.uniform(0.5, 1.0)
        work = heat_s * fluidity * FORCE_MAX_N ** 2 / (warm * math.exp(-warm))  # u = ``warm`` held at 9 N
        return Parts("zener", ZenerWithFlow(c, self_heated_flow(fluidity, heat_s, work)), core_changed=True)
    if effect == "delayed_elasticity":
        share = float(np.interp(m, [0, 1], [0.03, 0.2]))
        if shape == "adiabatic_cells":
            doubling, tau = rng.uniform(6.0, 20.0), rng.uniform(1.0, 8.0)
            r4 = 1.0 + 4.0 / doubling
            a = (share * 4.0 / g0 * r4 / (r4 ** KAPPA_AIR - 1.0), doubling, tau)  # the creep after a 4 N step
            p.extra.append(lambda t, f, T, a=a: adiabatic_cells(t, f, *a))
            return p
        p.after.append(DielectricAbsorption(share, rng.uniform(0.5, 6.0), rng.uniform(0.6, 1.2)))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.01, 0.06]))
        if shape == "shakedown_trace":
            radii = np.sort(rng.uniform(0.04, 0.15, 3)) * top
            w = rng.gamma(2.0, 1.0, 3)
            w *= frac * top / (2.0 * np.sum(w * radii)) / rng.uniform(0.4, 0.7)  # the fresh loop, before it shrinks
            if w.sum() > 0.8:  # wider plays, lighter: the trace's output never runs backwards
                radii, w = radii * w.sum() / 0.8, w * 0.8 / w.sum()
            return Parts("burgers", c, after=[ShakedownPlays(radii, w, rng.uniform(0.3, 0.6),
                                                             top * rng.uniform(4.0, 12.0))])
        n = 60
        fill = np.exp(rng.normal(math.log(rng.uniform(2.0, 4.0)), rng.uniform(0.4, 0.7), n))
        empty = fill * rng.uniform(0.25, 0.75, n)
        volume = rng.gamma(2.0, 1.0, n)
        volume *= frac * top / max(float(volume[fill < FORCE_MAX_N].sum()), 1e-9)
        p.extra.append(lambda t, f, T, a=(fill, empty, volume): ink_bottle_pores(t, f, *a))
        return p
    if effect == "sensor_lag":
        delay = float(np.interp(m, [0, 1], [0.012, 0.09])) * rng.uniform(0.8, 1.2)
        if shape == "camera_tactile":
            exposure, latency = rng.uniform(0.3, 0.8), rng.uniform(1.0, 2.0)  # in frames
            frame = delay / (0.5 * exposure + latency + 0.5)
            p.after.append(CameraTactile(frame, exposure * frame, latency * frame, rng.uniform(0.0, frame)))
            return p
        notch_hz, q = float(rng.choice([50.0, 60.0])), rng.uniform(0.25, 0.6)
        p.after.append(twin_t_notch(notch_hz, q, max(delay - 1.0 / (q * 2.0 * math.pi * notch_hz), 0.002)))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.05, 0.16]))
        if shape == "lindley_oring":
            p.after.append(StaticMap(lindley_oring(rel, top, rng.uniform(0.08, 0.15))))
            return p
        p.after.append(StaticMap(fsr_divider(rel, top, float(np.exp(rng.uniform(math.log(0.3), math.log(10.0)))),
                                             rng.uniform(1.1, 2.0))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.022]) * rng.choice([-1, 1]))
        if shape == "dew_point_film":
            a = (3.0 * k, rng.uniform(0.15, 0.4), rng.uniform(30.0, 120.0), rng.uniform(20.0, 90.0), rng.uniform(5.0, 20.0))
            p.extra.append(lambda t, f, T, a=a: dew_point_zero(t, T, *a))
            return p
        cover = rng.uniform(0.45, 0.8) if rng.random() < 0.5 else rng.uniform(1.2, 1.55)
        a = (k, rng.uniform(5.0, 20.0), rng.uniform(20.0, 90.0), rng.uniform(3000.0, 4200.0),
             float(np.exp(rng.uniform(math.log(0.4), math.log(2.5)))), cover)
        p.extra.append(lambda t, f, T, a=a: ntc_trimmed_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        if shape == "stale_span_correction":
            a = float(np.interp(m, [0, 1], [0.006, 0.016]))
            p.after.append(StaleSpanCorrection(a, a * rng.uniform(0.85, 1.15), rng.uniform(5.0, 20.0),
                                               rng.uniform(40.0, 150.0), rng.uniform(0.0, 40.0)))
            return p
        p.after.append(CrystallineSpan(float(np.interp(m, [0, 1], [0.04, 0.14])), rng.uniform(0.5, 0.8),
                                       rng.uniform(0.3, 0.8), rng.uniform(1.0, 2.5), rng.uniform(10.0, 40.0),
                                       rng.uniform(20.0, 80.0), rng.uniform(10.0, 40.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.012, 0.08]) * rng.choice([-1, 1]))
        if shape == "staff_proximity":
            n = int(rng.integers(10, 31))
            passes = list(zip(rng.uniform(0.0, HORIZON_S, n), rng.uniform(0.5, 2.0, n), rng.uniform(0.3, 0.8, n),
                              rng.uniform(0.3, 1.0, n), rng.uniform(1.5, 3.0, n)))
            n = int(rng.integers(1, 4))
            stands = list(zip(rng.uniform(0.0, HORIZON_S, n), rng.uniform(20.0, 120.0, n), rng.uniform(2.0, 6.0, n),
                              rng.uniform(1.0, 3.0, n)))
            zero = normalised(lambda s, a=(passes, stands): staff_proximity(s, *a), size)
            p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
            return p
        zero = desorption_zero(size, rng.uniform(0.0, 400.0), rng.uniform(300.0, 2500.0))
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.03, 0.008])) * rng.uniform(0.8, 1.2)
        if shape == "tendon_string_modes":
            p.after.append(StringModes(rng.uniform(15.0, 35.0), zeta, zeta * rng.uniform(0.05, 0.2),
                                       int(rng.integers(3, 6))))
            return p
        p.after.append(WireRopeMode(rng.uniform(18.0, 45.0), zeta, rng.uniform(0.5, 0.8),
                                    rng.uniform(0.5, 1.5) * 0.9 / g0))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "tendon_sheath":
            low, high = rng.uniform(0.3, 1.0), rng.uniform(1.5, 3.5)  # rad: the sheath's total bend
            first = rng.uniform(low, low + high)
            moves, now = [], rng.uniform(0.0, 20.0)
            while now < HORIZON_S:
                length = rng.uniform(1.0, 4.0)
                moves.append((now, length, rng.uniform(low, low + high)))
                now += length + rng.uniform(10.0, 40.0)
            seal = r * rng.uniform(0.25, 0.45)
            mu = math.log1p((r - seal) / 3.5) / (low + 0.5 * high)  # the band r at 3.5 N at the mean bend
            p.before.append(ForcePath(tendon_sheath(mu, seal, moves, first)))
            return p
        p.before.append(ForcePath(spun_needle_band(r, rng.uniform(0.5, 3.0), schedule(rng, (15.0, 80.0), (5.0, 40.0)))))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.1, 0.3]))
        if shape == "curing_resin_clock":
            return Parts("burgers", CuringClock(c, b, rng.uniform(5.0, 20.0), rng.uniform(300.0, 1500.0),
                                                rng.uniform(0.1, 0.2), rng.uniform(0.3, 0.7), rng.uniform(0.5, 1.5)),
                         core_changed=True)
        return Parts("burgers", HeatedCoreClock(c, b, T_REF_C + rng.uniform(0.0, 1.5), rng.uniform(2.0, 6.0),
                                                rng.uniform(1.5, 4.0), rng.uniform(20.0, 60.0)), core_changed=True)
    if effect == "electrosurgery":
        n = int(rng.integers(6, 21))
        activations = list(zip(rng.uniform(0.0, HORIZON_S, n), rng.uniform(0.5, 4.0, n), rng.uniform(0.5, 1.0, n),
                               rng.uniform(0.02, 0.1, n), rng.uniform(0.2, 1.0, n)))
        step = 0.002
        flicker = rng.normal(0.0, 1.0, int(HORIZON_S / step) + 2)
        corr = int(rng.uniform(0.005, 0.02) / step) + 1  # the bursts' correlation, in grid steps
        flicker = np.convolve(flicker, np.ones(corr) / math.sqrt(corr), mode="same") * rng.uniform(0.2, 0.4)
        amp = float(np.interp(m, [0, 1], [0.004, 0.04]))
        p.extra.append(lambda t, f, T, a=(activations, flicker, step), amp=amp: amp * electrosurgery(t - t[0], *a))
        return p
    if effect == "polarisation_fading":
        corr, n = rng.uniform(20.0, 120.0), int(HORIZON_S / 0.5) + 2
        keep = math.exp(-0.5 / corr)
        kicks = rng.normal(0.0, rng.uniform(0.6, 1.2) * math.sqrt(1.0 - keep * keep), n)
        angle = np.empty(n)
        angle[0] = rng.uniform(0.0, np.pi)
        for i in range(1, n):  # an Ornstein-Uhlenbeck wander about the first angle
            angle[i] = angle[0] + (angle[i - 1] - angle[0]) * keep + kicks[i]
        p.after.append(PolarisationFading(float(np.interp(m, [0, 1], [0.02, 0.12])), angle))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["rejuvenated_ageing_flow", "self_heated_flow"],
    "delayed_elasticity": ["adiabatic_cells", "dielectric_absorption"],
    "hysteresis": ["shakedown_trace", "ink_bottle_pores"],
    "sensor_lag": ["camera_tactile", "twin_t_notch"],
    "nonlinear_gain": ["lindley_oring", "fsr_divider"],
    "thermal_drift": ["dew_point_film", "ntc_trimmed_zero"],
    "thermal_sensitivity": ["stale_span_correction", "crystalline_span"],
    "offset_drift": ["staff_proximity", "sterilant_desorption"],
    "resonance": ["tendon_string_modes", "wire_rope_mode"], "friction": ["tendon_sheath", "spun_needle"],
    "thermo_rheological": ["curing_resin_clock", "heated_core_clock"],
}
PAIRS = (("viscous_flow", "nonlinear_gain"), ("delayed_elasticity", "sensor_lag"), ("hysteresis", "resonance"),
         ("offset_drift", "thermal_drift"), ("friction", "thermal_sensitivity"),
         ("thermo_rheological", "thermal_sensitivity"))
OUTSIDE = ("electrosurgery", "polarisation_fading")
RATES = (140.0, 410.0, 660.0, 890.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split S", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8),
                   pair_shapes=(-1, 0), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.1e-3, 2.4e-3), jitter=0.25,
                   gap_s=(0.2, 3.0))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
