"""Independent split X for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split X is an untouched held-out set: written blind to the engine it measures (to how it detects and fits anything),
run once, never used to choose anything. Every name of the catalogue is hidden in two shapes that neither the
registry's families (``polyforce_ros/sim/truths.py``) nor splits A to W use:

* a metal-filled polymer core whose flow (0.5-1 times the plain fluidity of 1/60000-1/8000 V/(N s)) runs 3-8 times
  faster while the ultrasonic transducer of the robot's tool runs (bouts of 3-30 s, 10-60 s apart: acoustic
  softening), or a hydraulic core whose piston uncovers a tapered bleed slot as the oil leaks past it (0.3-0.6 times
  the plain fluidity at first, gaining that much again for each distance that 100-400 s of the plain flow under 1 N
  would flow, up to 3-6 times its first value once the slot is fully open); neither ever recovers;
* a gas bubble in a fluid-filled core that the load's pressure (doubled by 12-30 N) dissolves by Henry's law and that
  comes out of solution at rest, at the rate of a quasi-steady Epstein-Plesset bubble (proportional to its radius,
  2-20 s at rest: slower as it shrinks), its volume lost beyond the instantaneous Boyle compression read, or a
  piezoresistive gauge fed at constant current whose own Joule heat, and so its resistance, follows the load's
  change of resistance (an electrothermal creep through the film's substrate, 0.3-2 s, 30-70 % of it, and the
  housing, 8-40 s); both settle at 3-20 % of the instantaneous response (the bubble at 3-5 N);
* a Hall read-out through a soft-ferrite flux guide after Tellinen's scalar model (limiting curves tanh(u -+ c),
  centred at 0-30 % of the range, 25-50 % of it wide, c 0.2-0.6, a reversible slope of 0.1-0.4 of the mean curve's;
  minor loops that do not close exactly; the loop widest at light loads, open at no load, closing toward the top),
  or a jammed granular interlayer of glass microbeads between the core and the gauges' flexure (Kondner's hyperbolic
  backbone, the range 0.6-2.5 yield deformations, with Pyke's rule for the branches: no memory beyond the last
  reversal, so repeated cycles shake down over about ten of them); the firmware linearises the mean of the full-range
  loop, which spans 1-6 % of the range;
* a continuously-variable-slope delta-modulation (CVSD) link (one bit per clock at 2-3.2 kHz, a step that grows while
  three bits agree and relaxes with 4-20 ms, from 1/4000-1/1500 of the range up to what follows 4-12 ranges per
  second, leaky integrators of 0.05-0.5 s, a reconstruction RC of 60-90 % of the delay: fast changes overload it), or
  a luminescent read-out whose phosphor's afterglow is a stretched exponential (beta 0.55-0.85: a fast start and a
  long tail) behind an RC of 1-3 ms; about 5-90 ms of mean delay (4-108 ms for the phosphor);
* gauges at the root of a slender cantilevered blade that the core's push bends into an elastica (the root moment's
  lever arm shortens as it curls: compressive), or a pneumatic nozzle-flapper read-out (the back pressure 1 / (1 +
  g^2) of the gap, from 0.35-1.4 of the matching gap: expansive, S-shaped or compressive); 5-16 % at the top of the
  range (the flapper's as far as half its gap allows);
* the zero of a printed two-material flexure bending like a bimetal strip (Timoshenko's curvature, thickness ratio
  0.3-3, stiffness ratio 5-50, the soft layer losing 3-8 % of its modulus per degC; lag 10-40 s), or a leakage
  current across the bridge board's adsorbed water film into the amplifier's input (the film's conductance
  exponential in the relative humidity, 45-75 % at the reference, which falls 6.3 %/degC as the board warms, lag
  10-40 s; the film following with 5-30 s: its conductance 10-25 % higher per degC colder); 0.008-0.03 V/degC at the
  reference;
* a capacitive read-out biased near pull-in (its electrostatic spring, 30-70 % of the stiffness, as the inverse cube
  of a gap that a polymer spacer widens or narrows as it warms; either way), or a variable-reluctance read-out whose
  ferrite core's permeability climbs toward its Hopkinson maximum 4-60 degC above the reference as the power 0.5-1
  of the distance to it (the core 20-60 % of the circuit's reluctance: the span rises); lag 10-40 s, 1-2.5 %/degC at
  the reference;
* the zero of a sealed-reference read-out into whose cavity helium permeates through its silicone lid once the
  chamber's gas is switched to heliox (30 s before to 120 s after the first sample: the Daynes-Barrer time-lag curve,
  L^2 / D 150-600 s: nothing, a slow start, then a steady rise), or a floating guard charged by an ionising blower
  (bouts of 20-120 s, 15-90 s apart, charging with 20-80 s and leaking away with 60-300 s); 12-80 mV at most;
* a holder of a filled polymer whose loss factor is the same at every frequency (16 Maxwell arms from 0.1 Hz to 6 kHz:
  structural damping), or a tool whose battery pack on a soft mount puts an antiresonance at 0.55-0.85 of the mode's
  frequency below it (damping ratio 0.5-1.5 times the mode's); 15-45 Hz, damping ratio 0.0064-0.036, both fixed;
* a Coulomb band of 0.4-3.6 % of the range in a needle guide in parallel with the core, the same at every load and
  always: a clamped bushing whose shear spring is 20-60 times the core's instantaneous stiffness, or a spring-loaded
  ball plunger that micro-slips before it slides (Cattaneo-Mindlin, 3-12 times at first, Masing's rule); while the
  guide holds, the core's creep is held back and hands its load to the guide;
* a core between the robot's thermostatted flange (within 0.5 degC of the reference) and the chamber's air (lag 5-20
  s), the temperature falling linearly across it, each of eight layers on the Arrhenius clock of its own temperature
  (1.6-2.2 times 0.15-0.45 per degC: the whole's a log-mean), or dashpots of a sugar syrup following the MYEGA law
  (fragility 90-130, 1.2-1.5 times 0.15-0.45 per degC at the reference; lag 5-20 s).

It also holds six pairs, two effects outside the catalogue (a wireless stream of sample-to-sample differences, in
packets of 10-40 ms with an absolute keyframe every 0.5-3 s, of which 0.4-1.5 % are lost: the receiver holds over a
lost packet and then misses its increment until the next keyframe arrives; a process historian's swinging-door
compression, 8-40 mV of deviation and at most 5-30 s between archived samples, rebuilt by straight lines) and four
clean records. Profiles: a needle-insertion rig characterising ex-vivo liver through the measured force-depth curve
(``../shared/data``, ``depth_force.csv``, its first insertion mapped onto 25-50 mm; stand-in layers when the data are
absent) at 0.5-16 mm/s in a shuffled order, a dwell at depth while the liver relaxes, one site after another; a
massage robot (effleurage strokes, petrissage kneading, tapotement, trigger-point compression); and the foot of a
small quadruped robot (standing, walking, trotting, lying down, jumping). Rates 100, 290, 470 and 740 Hz (a mode at
1000 Hz with knocks that excite it), 1.1-2.5 mV noise, stamp jitter, gaps, and a sensor on a robot in a multiplace
hyperbaric chamber: warmed by each compression, cooled by each decompression and by fresh-air flushes, pulled back by
the chamber's chiller.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size against its
noise without diagnosing (for a leak on a Zener base, against that bare Zener core).

    .venv/bin/python bench/independent_split_x.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, optimize, signal
from scipy.special import gamma as gamma_fn

from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (cutter, ease, fit_departure, follow, LeakingCore, LinearFilter, on_clock, Parts, ShapeSplit,
                       SimOnly, sized as sized_over, temp_of, uniform_grid)

SEED0 = 1_660_000  # never a seed of the registry's splits nor of splits A (90000..) to W (1590000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 480.0
HORIZON_S = DURATION_S + 60.0  # what a schedule drawn before the record covers (the record plus its gaps' slack)

sized = functools.partial(sized_over, horizon_s=HORIZON_S)
reach_fit = functools.partial(fit_departure, points=301)


# ----------------------------------------------------------------------------- small tools

def final(values, fallback):
    return float(values[-1]) if np.size(values) else float(fallback)


def bouts(rng, off_s, on_s, start_s=(-120.0, 0.0), horizon_s=HORIZON_S):
    """Bouts (start, length), seconds since the first sample: ``on_s`` long, ``off_s`` apart (ranges), the first
    starting within ``start_s``."""
    out, now = [], rng.uniform(*start_s)
    while now < horizon_s:
        length = rng.uniform(*on_s)
        out.append((now, length))
        now += length + rng.uniform(*off_s)
    return out


# ----------------------------------------------------------------------------- profiles and temperature

@functools.lru_cache(maxsize=1)
def liver_depth_force(bin_mm=0.25):
    """The first insertion of the measured force-depth curve (``../shared/data/needle_insertion_okamura/
    depth_force.csv``: the points until the depth first falls 5 mm short of the deepest so far), binned to
    ``bin_mm`` by the median, empty bins bridged linearly, pulls set to zero: (depth in mm, force in N), or None when
    the file is absent."""
    located = profiles.okamura_csv_path()
    if located is None or not (located.parent / "depth_force.csv").is_file():
        return None
    raw = np.loadtxt(located.parent / "depth_force.csv", delimiter=",", ndmin=2)
    depth, force = 1e3 * raw[:, 0], raw[:, 1]
    behind = np.maximum.accumulate(depth) - depth
    stop = int(np.argmax(behind > 5.0)) if np.any(behind > 5.0) else depth.size
    depth, force = depth[:stop], force[:stop]
    slots = np.rint(np.clip(depth, 0.0, None) / bin_mm).astype(int)
    grid = bin_mm * np.arange(slots.max() + 1)
    med = np.full(grid.size, np.nan)
    for k in np.unique(slots):
        med[k] = np.median(force[slots == k])
    ok = ~np.isnan(med)
    return grid, np.clip(np.interp(grid, grid[ok], med[ok]), 0.0, None)


def stand_in_layers(rng):
    """When the measured curve is absent: 48 mm of shaft friction growing linearly (0.01-0.03 N/mm) and 2-4
    capsules that stiffen as a quadratic over 1.5-4 mm before they tear by 0.4-1.4 N, keeping a third of it."""
    grid = np.arange(0.0, 48.0, 0.25)
    force = rng.uniform(0.01, 0.03) * grid
    for at in np.sort(rng.uniform(5.0, 45.0, int(rng.integers(2, 5)))):
        build, height = rng.uniform(1.5, 4.0), rng.uniform(0.4, 1.4)
        rise = height * np.clip(1.0 - (at - grid) / build, 0.0, 1.0) ** 2
        force += np.where(grid <= at, rise, height / 3.0 * np.exp(-(grid - at) / 2.0))
    return grid, force


SPEEDS_MM_S = (0.5, 1.0, 2.0, 4.0, 8.0, 16.0)


def speed_sweep_insertions(duration_s, rate_hz, rng):
    """A needle-insertion rig characterising ex-vivo liver: one insertion per fresh site, its speed taken in turn from
    0.5, 1, 2, 4, 8 and 16 mm/s in a shuffled order (reshuffled once all were used), through the measured force-depth
    curve (``liver_depth_force``, measured at 3 mm/s) mapped onto 25-50 mm of this site and cut short at 70-100 % of
    it; its force scaled to a 3-5 N peak at 3 mm/s, by 0.8-1.2 for the site and by the speed over 3 mm/s to the power
    0.1-0.25 (cutting is harder fast). The needle dwells 5-20 s at depth while the liver relaxes to 65-85 % with 0.8-4
    s, is pulled out (the push gone within 0.15-0.5 s) and the rig moves on for 3-12 s. Stand-in layers
    (``stand_in_layers``) when ``../shared/data`` is absent."""
    measured = liver_depth_force()
    depth_mm, force_n = measured if measured is not None else stand_in_layers(rng)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cut = cutter(t)
    full, peak = float(depth_mm[-1]), max(float(force_n.max()), 1e-3)
    level, power = rng.uniform(3.0, 5.0) / peak, rng.uniform(0.1, 0.25)
    queue, now = [], rng.uniform(2.0, 8.0)
    while now < duration_s - 12.0:
        if not queue:
            queue = [float(v) for v in rng.permutation(SPEEDS_MM_S)]
        speed = queue.pop()
        stretch = rng.uniform(25.0, 50.0) / full
        goal = min(stretch * full * rng.uniform(0.7, 1.0), (duration_s - now - 4.0) * speed)
        gain = level * rng.uniform(0.8, 1.2) * (speed / 3.0) ** power
        if goal < 3.0:
            break
        span = goal / speed
        seg, s = cut(now, span)
        f[seg] = gain * np.interp(speed * s / stretch, depth_mm, force_n)
        end = gain * float(np.interp(goal / stretch, depth_mm, force_n))
        now += span
        hold, keep, relax = rng.uniform(5.0, 20.0), rng.uniform(0.65, 0.85), rng.uniform(0.8, 4.0)
        seg, s = cut(now, hold)
        f[seg] = end * (keep + (1.0 - keep) * np.exp(-s / relax))
        now += hold
        last = end * (keep + (1.0 - keep) * math.exp(-hold / relax))
        out = rng.uniform(0.15, 0.5)
        seg, s = cut(now, out)
        f[seg] = last * (1.0 - ease(s / out))
        now += out + rng.uniform(3.0, 12.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def robot_massage(duration_s, rate_hz, rng):
    """A massage robot's hand on a back, block after block with 2-10 s pauses between: effleurage (3-6 gliding
    strokes, each pressed on within 0.3-0.6 s to 3-7 N, glided for 2-5 s over the muscles' relief, two or three sines
    of 3-8 % at 0.4-2 Hz, lifted within 0.2-0.5 s, brought back in 1-2 s), petrissage (10-30 s of kneading at
    0.5-1.2 Hz between a base of 1.5-3 N and 1.5-4 N more, swelling and fading by 20 % over 5-12 s), tapotement (3-8 s
    of cupped taps at 4-8 Hz, each a half-sine of 20-50 ms and 1-4 N over a rest of up to 0.5 N) and trigger-point
    compression (4-8 N reached in 2-4 s, held for 10-30 s with a 0.02-0.06 N tremor at 6-10 Hz, released in 1-2 s)."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cut = cutter(t)
    now = rng.uniform(1.0, 5.0)
    while now < duration_s - 8.0:
        kind = rng.choice(4, p=[0.3, 0.3, 0.2, 0.2])
        if kind == 0:  # effleurage
            for _ in range(int(rng.integers(3, 7))):
                on, glide, lift, back = (rng.uniform(0.3, 0.6), rng.uniform(2.0, 5.0), rng.uniform(0.2, 0.5),
                                         rng.uniform(1.0, 2.0))
                level = rng.uniform(3.0, 7.0)
                seg, s = cut(now, on)
                f[seg] = level * ease(s / on)
                now += on
                seg, s = cut(now, glide)
                relief = np.ones_like(s)
                for _ in range(int(rng.integers(2, 4))):
                    relief += rng.uniform(0.03, 0.08) * np.sin(2.0 * np.pi * rng.uniform(0.4, 2.0) * s
                                                               + rng.uniform(0.0, 6.3))
                relief -= relief[0] - 1.0 if relief.size else 0.0
                f[seg] = level * relief
                now += glide
                last = final(f[seg], level)
                seg, s = cut(now, lift)
                f[seg] = last * (1.0 - ease(s / lift))
                now += lift + back
        elif kind == 1:  # petrissage
            length, base, amp, hz = rng.uniform(10.0, 30.0), rng.uniform(1.5, 3.0), rng.uniform(1.5, 4.0), \
                rng.uniform(0.5, 1.2)
            seg, s = cut(now, length)
            envelope = ease(s / 2.0) * (1.0 - ease((s - length + 2.0) / 2.0))
            swell = 1.0 + 0.2 * np.sin(2.0 * np.pi * s / rng.uniform(5.0, 12.0))
            f[seg] = envelope * (base + amp * swell * (0.5 - 0.5 * np.cos(2.0 * np.pi * hz * s)))
            now += length
        elif kind == 2:  # tapotement
            length, hz, wide, rest = rng.uniform(3.0, 8.0), rng.uniform(4.0, 8.0), rng.uniform(0.02, 0.05), \
                rng.uniform(0.0, 0.5)
            seg, s = cut(now, length)
            level = np.full(s.size, rest)
            for k in range(int(length * hz)):
                u = (s - k / hz) / wide
                level += np.where((u >= 0.0) & (u < 1.0), rng.uniform(1.0, 4.0) * np.sin(np.pi * np.clip(u, 0, 1)),
                                  0.0)
            f[seg] = level * ease(s / 0.2) * (1.0 - ease((s - length + 0.2) / 0.2))
            now += length
        else:  # trigger-point compression
            rise, hold, out, level = rng.uniform(2.0, 4.0), rng.uniform(10.0, 30.0), rng.uniform(1.0, 2.0), \
                rng.uniform(4.0, 8.0)
            seg, s = cut(now, rise)
            f[seg] = level * ease(s / rise)
            now += rise
            seg, s = cut(now, hold)
            f[seg] = level + rng.uniform(0.02, 0.06) * np.sin(2.0 * np.pi * rng.uniform(6.0, 10.0) * s)
            now += hold
            last = final(f[seg], level)
            seg, s = cut(now, out)
            f[seg] = last * (1.0 - ease(s / out))
            now += out
        now += rng.uniform(2.0, 10.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def legged_robot_foot(duration_s, rate_hz, rng):
    """The sensor in the foot of a small quadruped robot (3-4 N on the foot when it stands), bout after bout:
    standing (5-20 s, swaying by 5-12 % at 0.3-1 Hz), walking (10-40 s, strides of 0.8-1.2 s, the foot down for 60-75 %
    of them, a double-humped stance of 1.3-1.7 times the standing load, each step within 10 % of it), trotting (10-40
    s, strides of 0.45-0.7 s, the foot down for 45-55 %, a single hump of 1.6-2.0 times the standing load with a
    touchdown spike of 15-30 ms), lying down (the foot eased to 0-0.4 N over 0.5-1 s for 3-10 s) and jumping (a crouch
    to 1.3 times the standing load, a push-off to 7-9 N, 0.2-0.4 s in the air, a landing spike of 7-9 N that settles in
    a damped bounce); the foot lifts within 0.2 s before a gait and sets down within 0.3 s after it."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cut = cutter(t)
    weight = rng.uniform(3.0, 4.0)
    now = 0.0
    seg, s = cut(now, 2.0)
    f[seg] = weight * ease(s / 2.0)
    now = 2.0
    while now < duration_s:
        kind = rng.choice(5, p=[0.25, 0.3, 0.25, 0.1, 0.1])
        if kind == 0:  # stand
            length, sway = rng.uniform(5.0, 20.0), rng.uniform(0.05, 0.12)
            seg, s = cut(now, length)
            f[seg] = weight * (1.0 + sway * np.sin(2.0 * np.pi * rng.uniform(0.3, 1.0) * s))
            now += length
        elif kind in (1, 2):  # walk or trot
            walk = kind == 1
            seg, s = cut(now, 0.2)
            f[seg] = weight * (1.0 - ease(s / 0.2))
            now += 0.2
            stride = rng.uniform(0.8, 1.2) if walk else rng.uniform(0.45, 0.7)
            duty = rng.uniform(0.6, 0.75) if walk else rng.uniform(0.45, 0.55)
            top = weight * (rng.uniform(1.3, 1.7) if walk else rng.uniform(1.6, 2.0))
            dip, spike, spike_s = rng.uniform(0.12, 0.25), rng.uniform(0.15, 0.3), rng.uniform(0.015, 0.03)
            end = now + rng.uniform(10.0, 40.0)
            while now < end:
                this = stride * rng.uniform(0.95, 1.05)
                stance = duty * this
                seg, s = cut(now, stance)
                u = s / stance
                level = top * rng.uniform(0.9, 1.1)
                if walk:
                    f[seg] = level * (np.sin(np.pi * u) - dip * np.sin(3.0 * np.pi * u)) / (1.0 + dip)
                else:
                    bump = np.where(s < spike_s, np.sin(np.pi * s / spike_s), 0.0)
                    f[seg] = level * (np.sin(np.pi * u) ** 1.3 + spike * bump)
                now += this
            seg, s = cut(now, 0.3)
            f[seg] = weight * ease(s / 0.3)
            now += 0.3
        elif kind == 3:  # lie down
            down, length, low = rng.uniform(0.5, 1.0), rng.uniform(3.0, 10.0), rng.uniform(0.0, 0.4)
            seg, s = cut(now, down)
            f[seg] = weight + (low - weight) * ease(s / down)
            now += down
            seg, s = cut(now, length)
            f[seg] = low
            now += length
            seg, s = cut(now, down)
            f[seg] = low + (weight - low) * ease(s / down)
            now += down
        else:  # jump
            crouch, push, push_s, air = rng.uniform(0.3, 0.5), rng.uniform(7.0, 9.0), rng.uniform(0.15, 0.25), \
                rng.uniform(0.2, 0.4)
            seg, s = cut(now, crouch)
            f[seg] = weight * (1.0 + 0.3 * ease(s / crouch))
            now += crouch
            seg, s = cut(now, push_s)
            rise = 1.3 * weight + (push - 1.3 * weight) * np.sin(0.5 * np.pi * s / (0.6 * push_s))
            f[seg] = np.where(s < 0.6 * push_s, rise, push * (1.0 - ease((s - 0.6 * push_s) / (0.4 * push_s))))
            now += push_s + air
            land, settle, ring = rng.uniform(7.0, 9.0), rng.uniform(0.3, 0.6), rng.uniform(2.5, 5.0)
            seg, s = cut(now, settle + 0.5)
            impact = land * np.sin(np.pi * np.clip(s / 0.045, 0.0, 1.0)) * (s < 0.045)
            after = np.clip(s - 0.045, 0.0, None)
            bounce = weight * (1.0 - np.exp(-after / (0.3 * settle)) * np.cos(2.0 * np.pi * ring * after))
            f[seg] = np.maximum(impact, np.where(s >= 0.045, bounce, 0.0))
            now += settle + 0.5
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (speed_sweep_insertions, robot_massage, legged_robot_foot)


def hyperbaric_chamber(t, rng, step_s=0.5):
    """A sensor on a robot inside a multiplace hyperbaric chamber, its air 1.5 degC below to 1 degC above the reference
    at the start. The chamber is pressurised by 0.8-1.8 bar at 0.006-0.02 bar/s (from 150 s before to 100 s into the
    record; one time in two with a pause of 20-60 s part-way for the occupants' ears), held for 120-300 s and
    decompressed at 0.004-0.012 bar/s: the compression heats the air by 3-7 degC per bar, the decompression cools it
    as much, and the chamber's chiller pulls it back toward its start with 150-400 s. During the hold the chamber is
    flushed every 60-180 s for 15-40 s with fresh air 2-5 degC cooler (with 30-80 s). The sensor follows the air with
    10-30 s; all of it runs from 600 s before the record (exact per step of ``step_s``)."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-600.0, d + 2.0 * step_s, step_s)
    start = T_REF_C + rng.uniform(-1.5, 1.0)
    depth, c0 = rng.uniform(0.8, 1.8), rng.uniform(-150.0, 100.0)
    up = depth / rng.uniform(0.006, 0.02)
    knots_t, knots_p = [-600.0, c0], [0.0, 0.0]
    if rng.random() < 0.5:
        part, pause = rng.uniform(0.3, 0.7), rng.uniform(20.0, 60.0)
        knots_t += [c0 + part * up, c0 + part * up + pause]
        knots_p += [part * depth, part * depth]
        c0 += pause
    hold = rng.uniform(120.0, 300.0)
    down = depth / rng.uniform(0.004, 0.012)
    knots_t += [c0 + up, c0 + up + hold, c0 + up + hold + down, max(c0 + up + hold + down, d) + 10.0]
    knots_p += [depth, depth, 0.0, 0.0]
    bar = np.interp(grid, knots_t, knots_p)
    heat = rng.uniform(3.0, 7.0) * np.diff(bar, prepend=bar[0])
    chill = math.exp(-step_s / rng.uniform(150.0, 400.0))
    flushing = np.zeros(grid.size, dtype=bool)
    now = c0 + up + rng.uniform(10.0, 60.0)
    while now < c0 + up + hold:
        flushing |= (grid >= now) & (grid < now + rng.uniform(15.0, 40.0))
        now += rng.uniform(60.0, 180.0)
    fresh, flush_keep = start - rng.uniform(2.0, 5.0), math.exp(-step_s / rng.uniform(30.0, 80.0))
    air, out = start, np.empty(grid.size)
    for i, (dq, flush) in enumerate(zip(heat.tolist(), flushing.tolist())):
        air = start + (air + dq - start) * chill
        if flush:
            air = fresh + (air - fresh) * flush_keep
        out[i] = air
    keep = math.exp(-step_s / rng.uniform(10.0, 30.0))
    sensor, _ = signal.lfilter([1.0 - keep], [1.0, -keep], out, zi=[keep * out[0]])
    return np.interp(s, grid, sensor)


# ----------------------------------------------------------------------------- viscous flow

def acoustic_softening(fluidity, boost, runs):
    """x' = A F (1 + (``boost`` - 1) u(t)): a metal-filled polymer core that flows at ``fluidity`` and flows
    ``boost`` times faster while the ultrasonic transducer of the robot's tool runs (``runs``: start, length in
    seconds since the first sample; on and off within 0.2 s), acoustic softening. It never recovers."""
    def rule(t, f):
        s = t - t[0]
        on = np.zeros_like(s)
        for start, length in runs:
            on = np.maximum(on, ease((s - start) / 0.2) * (1.0 - ease((s - start - length) / 0.2)))
        rate = fluidity * np.maximum(f, 0.0) * (1.0 + (boost - 1.0) * on)
        return integrate.cumulative_trapezoid(rate, t, initial=0.0)
    return rule


def tapered_bleed_slot(fluidity, x_open, widest):
    """x' = A F (1 + x / ``x_open``), at most ``widest`` A F: a hydraulic core whose piston, as the oil leaks past it,
    uncovers a tapered bleed slot in its bore, so the leak's path widens with the distance already flowed until the
    slot is fully open. With u the plain flow (the integral of A F), x = x_open (exp(u / x_open) - 1) until then and a
    straight continuation after; it never recovers."""
    u_full = x_open * math.log(widest)

    def rule(t, f):
        u = integrate.cumulative_trapezoid(fluidity * np.maximum(f, 0.0), t, initial=0.0)
        early = x_open * np.expm1(np.minimum(u, u_full) / x_open)
        return early + widest * np.maximum(u - u_full, 0.0)
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def dissolving_bubble(t, f, compliance_v_per_n, ref_n, double_n, rest_s, step_s=0.01):
    """A gas bubble trapped in a fluid-filled core: the load raises the fluid's pressure p = 1 + F / ``double_n``
    (in units of the pressure at rest), the bubble's gas n (1 at rest) dissolves toward n = 1 - H (p - 1) (Henry's law
    in a closed fluid volume, H set so that n stays above 0.4 at the top of the range) and comes out of solution again
    at rest, at the rate of a quasi-steady Epstein-Plesset bubble, n' = -k R (H p - (1 + H - n)), R = (n / p)^(1/3)
    its radius (k = 1 / ``rest_s``): the smaller the bubble, the slower. The volume it loses beyond its instantaneous
    (Boyle) compression, (1 - n) / p, is read, scaled to settle at ``compliance_v_per_n`` times ``ref_n`` under
    ``ref_n``. Explicit per coarse step of ``step_s``, from rest."""
    p_top = 1.0 + FORCE_MAX_N / double_n
    henry = 0.6 / (p_top - 1.0)
    p_ref = 1.0 + ref_n / double_n
    gain = compliance_v_per_n * ref_n / (henry * (p_ref - 1.0) / p_ref)
    grid = np.arange(t[0], t[-1] + step_s, step_s)
    pg = 1.0 + np.maximum(np.interp(grid, t, f), 0.0) / double_n
    n, out, k = 1.0, np.empty(grid.size), step_s / rest_s
    for i, p in enumerate(pg.tolist()):
        out[i] = (1.0 - n) / p
        n -= k * (n / p) ** (1.0 / 3.0) * (henry * p - (1.0 + henry - n))
    return gain * np.interp(t, grid, out)


class ElectrothermalGauge(SimOnly):
    """A piezoresistive gauge fed at constant current, so its Joule heat grows with its resistance: the load's change
    of resistance heats the film, and its positive temperature coefficient raises the resistance further (an
    electrothermal creep that settles and recovers). The heat leaves through the film's substrate (``fast_s``) and the
    housing (``slow_s``), the substrate's share ``share``; settled, the creep adds ``creep`` of each change of the
    output."""

    def __init__(self, creep, share, fast_s, slow_s):
        self.creep, self.share, self.fast, self.slow = creep, share, fast_s, slow_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        warm = self.share * follow(t, x, self.fast, 0.02) + (1.0 - self.share) * follow(t, x, self.slow, 0.1)
        return x + self.creep * (warm - x[0])


# ----------------------------------------------------------------------------- hysteresis

class TellinenFluxGuide(SimOnly):
    """A Hall read-out whose magnet's field reaches the Hall plate through a soft-ferrite flux guide with magnetic
    hysteresis, after Tellinen's scalar model. Its major loop lies between two limiting curves, tanh(u - c) (rising)
    and tanh(u + c) (falling), u = (x - ``centre``) / ``width`` the field the load sets; inside, the state moves with
    the reversible slope r (``reversible`` of the mean curve's) and turns toward the limiting curve of its direction in
    proportion to how far it has come from the other: rising, M' = r + (M - M_fall) / (M_rise - M_fall) (M_rise' - r).
    Minor loops do not close exactly (no return-point memory). The firmware linearises the mean of the limiting curves;
    what remains, ``gain`` (M - mean), is added to the output. The guide starts on its falling curve (the last load
    came down from above)."""

    def __init__(self, frac, reach, centre, width, coercive, reversible):
        self.centre, self.width, self.c, self.rho = centre, width, coercive, reversible
        sweep = np.linspace(0.0, reach, 600)
        loop = self._state(np.concatenate([sweep, sweep[::-1], sweep, sweep[::-1]]))
        up, down = loop[1200:1800], loop[1800:][::-1]
        self.gain = frac * reach / max(float(np.max(down - up)), 1e-12)

    def _state(self, x):
        c, rho = self.c, self.rho
        u_all = (np.asarray(x, dtype=float) - self.centre) / self.width
        out = np.empty(u_all.size)
        u_prev = float(u_all[0])
        m = math.tanh(u_prev + c)
        for i, u_next in enumerate(u_all.tolist()):
            steps = max(1, int(abs(u_next - u_prev) / 0.02) + 1)
            du = (u_next - u_prev) / steps
            u = u_prev
            for _ in range(steps):
                u += du
                rise, fall = math.tanh(u - c), math.tanh(u + c)
                r = rho * 0.5 * (2.0 - rise * rise - fall * fall)
                gap = max(fall - rise, 1e-12)
                if du > 0.0:
                    m += (r + (fall - m) / gap * ((1.0 - rise * rise) - r)) * du
                elif du < 0.0:
                    m += (r + (m - rise) / gap * ((1.0 - fall * fall) - r)) * du
                m = min(max(m, math.tanh(u - c)), math.tanh(u + c))
            u_prev = u_next
            out[i] = m - 0.5 * (math.tanh(u - c) + math.tanh(u + c))
        return out

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        return x + self.gain * self._state(x)


class GranularInterlayer(SimOnly):
    """The core's deformation reaching the gauges' flexure through a thin layer of glass microbeads (a jammed granular
    interlayer) whose contact network yields and re-forms: Kondner's hyperbolic backbone, s = v / (1 + |v|) (v the
    deformation in units of ``yield_v``, s in units of the layer's ultimate), with Pyke's rule for the branches: from
    each reversal (v_r, s_r) toward the ultimate d of the new direction, s = s_r + c B((v - v_r) / c), c = |d - s_r|
    (no memory beyond the last reversal: cycles between fixed limits shake down over about ten of them). The layer was
    last loaded over the whole range before use; the firmware linearises the mean of that full-range loop, and
    ``gain`` of what remains is added to the output."""

    def __init__(self, frac, reach, yield_v):
        self.yield_v = yield_v
        sweep = np.linspace(0.0, reach, 600)
        loop = self._read(np.concatenate([sweep, sweep[::-1], sweep, sweep[::-1]]), reach)
        up, down = loop[1200:1800], loop[1800:][::-1]
        self.mean_x, self.mean_y = sweep, 0.5 * (up + down)
        self.gain = frac * reach / max(float(np.max(np.abs(up - down))), 1e-12)
        self.reach = reach

    def _read(self, x, reach):
        v_all = np.asarray(x, dtype=float) / self.yield_v
        v_top = reach / self.yield_v
        s_r = v_top / (1.0 + v_top)
        v_r, way = v_top, -1.0
        scale = abs(way - s_r)
        out = np.empty(v_all.size)
        v_prev = float(v_all[0])
        s = s_r + scale * ((v_prev - v_r) / scale) / (1.0 + abs(v_prev - v_r) / scale)
        for i, v in enumerate(v_all.tolist()):
            move = v - v_prev
            if move * way < 0.0:
                v_r, s_r, way = v_prev, s, math.copysign(1.0, move)
                scale = max(abs(way - s_r), 1e-9)
            if move:
                w = (v - v_r) / scale
                s = s_r + scale * w / (1.0 + abs(w))
            v_prev = v
            out[i] = s * self.yield_v
        return out

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        return x + self.gain * (self._read(x, self.reach) - np.interp(x, self.mean_x, self.mean_y))


# ----------------------------------------------------------------------------- sensor lag

class CvsdLink(SimOnly):
    """The bridge voltage sent over a continuously-variable-slope delta-modulation (CVSD) link, one bit per clock at
    ``clock_hz``: the encoder's and the decoder's leaky integrators (``leak_s``) step by +-delta, delta growing by a
    syllabic increment while the last three bits agree and relaxing toward ``step_min`` with ``syllabic_s`` otherwise
    (up to ``step_max``: fast changes overload the slope and lag), the decoder's output smoothed by a reconstruction
    RC of ``rc_s`` and read at the record's stamps."""

    def __init__(self, clock_hz, step_min, step_max, syllabic_s, leak_s, rc_s):
        self.clock, self.lo, self.hi = clock_hz, step_min, step_max
        self.relax = math.exp(-1.0 / (clock_hz * syllabic_s))
        self.leak = math.exp(-1.0 / (clock_hz * leak_s))
        self.rc = rc_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tc = np.arange(t[0], t[-1] + 1.0 / self.clock, 1.0 / self.clock)
        xc = np.interp(tc, t, x)
        lo, hi, relax, leak = self.lo, self.hi, self.relax, self.leak
        bump = (hi - lo) * (1.0 - relax)
        y, delta, b1, b2 = float(xc[0]), lo, 1, -1
        out = np.empty(tc.size)
        for i, target in enumerate(xc.tolist()):
            bit = 1 if target >= y else -1
            delta = lo + (delta - lo) * relax + (bump if bit == b1 == b2 else 0.0)
            delta = min(delta, hi)
            y = y * leak + bit * delta
            out[i] = y
            b2, b1 = b1, bit
        keep = math.exp(-1.0 / (self.clock * self.rc))
        smooth, _ = signal.lfilter([1.0 - keep], [1.0, -keep], out, zi=[keep * out[0]])
        return np.interp(t, tc, smooth)


class PhosphorAfterglow(SimOnly):
    """A luminescent read-out: the load moves a vane in the light that excites a phosphor, and a photodiode reads the
    phosphor's emission, which follows the excitation through its afterglow, a stretched exponential exp(-(t /
    ``tau_s``)^``beta``) (a spread of trap depths: a fast start and a long tail), behind an RC of ``rc_s``. On a uniform
    grid at the median step, from rest."""

    def __init__(self, tau_s, beta, rc_s):
        self.tau, self.beta, self.rc = tau_s, beta, LinearFilter([1.0], [rc_s, 1.0])

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        tu, xu, h = uniform_grid(t, self.rc.forward(t, np.asarray(x, dtype=float)))
        span = min(self.tau * 40.0 ** (1.0 / self.beta), 60.0)
        lags = np.arange(0.0, span, h)
        kernel = np.exp(-(lags / self.tau) ** self.beta)
        kernel /= kernel.sum()
        y = signal.fftconvolve(xu - xu[0], kernel)[:xu.size] + xu[0]
        return np.interp(t, tu, y)


# ----------------------------------------------------------------------------- nonlinear gain

@functools.lru_cache(maxsize=1)
def elastica_table(alpha_top=6.0, n=49):
    """The tip's horizontal reach X / L of a slender cantilever under a vertical tip load, against alpha = P L^2 / EI
    (the elastica, theta'' = -alpha cos theta, theta(0) = 0, theta'(1) = 0, shot on theta'(0) = alpha X / L)."""
    alphas = np.linspace(0.0, alpha_top, n)
    reach = np.ones(n)

    def end_slope(q, a):
        sol = integrate.solve_ivp(lambda s, y: [y[1], -a * math.cos(y[0])], (0.0, 1.0), [0.0, q], rtol=1e-9,
                                  atol=1e-11)
        return sol.y[1, -1]
    for i, a in enumerate(alphas[1:], start=1):
        q = optimize.brentq(end_slope, 1e-9, a, args=(a,), xtol=1e-12)
        reach[i] = q / a
    return alphas, reach


def elastica_blade(rel, reach):
    """x read by gauges at the root of a slender cantilevered blade that the core's push loads at its tip: the gauges
    read the root moment P X, the tip's lever arm X shortening as the blade curls (the elastica: compressive), scaled to
    slope 1 at no load, the load per volt set for a departure of ``rel`` at ``reach``."""
    alphas, lever = elastica_table()
    alpha_top = float(np.interp(1.0 - rel, lever[::-1], alphas[::-1]))

    def read(x):
        x = np.asarray(x, dtype=float)
        return x * np.interp(alpha_top * np.abs(x) / reach, alphas, lever)
    return read


def nozzle_flapper(rel, reach, gap0):
    """x read by a pneumatic nozzle-flapper whose flapper the core's push moves toward the nozzle: the back pressure
    over the supply is 1 / (1 + g^2) (the nozzle's and the restrictor's flows equal, g the gap in units of the gap
    where they match), from ``gap0`` (0.35-1.4: above 1/sqrt(3) expansive and then compressive as the gap closes past
    the inflection, below it compressive); scaled to slope 1 at no load, the travel per volt set for a departure of
    ``rel`` at ``reach`` as far as a gap of at least half its rest value there allows (the flapper seats, flat, only
    at twice the range)."""
    slope = 2.0 * gap0 / (1.0 + gap0 * gap0) ** 2

    def read(x, k):
        gap = np.maximum(gap0 - k * np.asarray(x, dtype=float), 0.0)
        return (1.0 / (1.0 + gap * gap) - 1.0 / (1.0 + gap0 * gap0)) / (k * slope)
    return reach_fit(read, rel, reach, 0.5 * gap0 / reach)


# ----------------------------------------------------------------------------- thermal drift

def bimaterial_zero(t, temp, k_v_per_c, thick_ratio, stiff_ratio, soft_per_c, lag_s):
    """The zero of a read-out on a printed two-material flexure that bends like a bimetal strip as it warms
    (Timoshenko: the curvature per degC 6 (1 + m)^2 / (3 (1 + m)^2 + (1 + m n)(m^2 + 1 / (m n))) over the thickness,
    m the layers' thickness ratio, n their stiffness ratio), its soft layer near its transition losing
    ``soft_per_c`` of its modulus per degC (n rising as it warms): the zero k dT f(n(T)) / f(n_ref) on the flexure's
    temperature (lag ``lag_s``)."""
    m = thick_ratio

    def bend(n):
        return 6.0 * (1.0 + m) ** 2 / (3.0 * (1.0 + m) ** 2 + (1.0 + m * n) * (m * m + 1.0 / (m * n)))
    dt = follow(t, temp, lag_s) - T_REF_C
    return k_v_per_c * dt * bend(stiff_ratio * np.exp(soft_per_c * dt)) / bend(stiff_ratio)


def surface_leakage_zero(t, temp, k_v_per_c, rh_ref, steep, board_s, sorb_s):
    """The zero set by a leakage current across the bridge board's surface into the amplifier's high-impedance input:
    the adsorbed water film's conductance grows as exp(``steep`` RH), the relative humidity at the board falling by
    the Magnus slope (6.3 %/degC) as the board (lag ``board_s``) warms in air of fixed absolute humidity (``rh_ref`` at
    the reference), the film taking it up or giving it off with ``sorb_s``: steeper when cold, flatter when warm;
    ``k_v_per_c`` at the reference."""
    board = follow(t, temp, board_s) - T_REF_C
    film = follow(t, rh_ref * np.exp(-0.063 * board), sorb_s, 0.5)
    slope = steep * 0.063 * rh_ref * math.exp(steep * rh_ref)
    return -k_v_per_c * (np.exp(steep * film) - math.exp(steep * rh_ref)) / slope


# ----------------------------------------------------------------------------- thermal sensitivity

class ElectrostaticSoftening(SimOnly):
    """A capacitive read-out biased near its pull-in: the bias's electrostatic spring takes ``share`` of the
    mechanical stiffness away at the reference and grows as the inverse cube of the gap, which a polymer spacer (lag
    ``lag_s``) widens or narrows as it warms (1 + gamma dT); the span (1 - s) / (1 - s g^-3), gamma set for
    ``coefficient`` per degC at the reference, the softening kept below 95 % of the stiffness."""

    def __init__(self, coefficient, share, lag_s):
        self.share, self.lag = share, lag_s
        self.gamma = -coefficient * (1.0 - share) / (3.0 * share)

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        dt = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        gap = np.maximum(1.0 + self.gamma * dt, 0.3)
        soft = np.minimum(self.share * gap ** -3.0, 0.95)
        return np.asarray(x, dtype=float) * (1.0 - self.share) / (1.0 - soft)


class HopkinsonFerrite(SimOnly):
    """A variable-reluctance read-out whose ferrite core's permeability climbs toward its Hopkinson maximum as it warms
    (as ((T_h - T_ref) / (T_h - T))^p, T_h ``peak_above_c`` above the reference, the core within 0.5 degC of it at
    most; lag ``lag_s``): the core's share ``core_share`` of the magnetic circuit's reluctance falls and the air gap
    that the load changes carries more of the signal; p set for ``coefficient`` per degC at the reference."""

    def __init__(self, coefficient, core_share, peak_above_c, lag_s):
        self.share, self.peak, self.lag = core_share, peak_above_c, lag_s
        self.power = coefficient * peak_above_c / core_share

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        dt = np.minimum(follow(t, temp_of(aux, t.size), self.lag) - T_REF_C, self.peak - 0.5)
        relative = ((self.peak - dt) / self.peak) ** self.power  # mu_ref / mu
        return np.asarray(x, dtype=float) / (1.0 - self.share + self.share * relative)


# ----------------------------------------------------------------------------- offset drift

def heliox_permeation(rng, horizon_s=HORIZON_S, step_s=0.1):
    """The zero of a sealed-reference read-out into whose cavity helium permeates through its silicone lid once the
    chamber's breathing gas is switched to heliox (30 s before to 120 s after the first sample): the Daynes-Barrer
    time-lag curve, theta - 1/6 - (2 / pi^2) sum (-1)^n / n^2 exp(-n^2 pi^2 theta), theta the time since the switch
    over L^2 / D (150-600 s): nothing, then a slow start, then a steady rise (as a function of the seconds since the
    first sample, zero there)."""
    switch, scale = rng.uniform(-30.0, 120.0), rng.uniform(150.0, 600.0)
    n = np.arange(1, 40)
    weight = 2.0 / math.pi ** 2 * (-1.0) ** n / n ** 2
    grid = np.arange(0.0, horizon_s + 1.0, step_s)
    theta = np.maximum(grid - switch, 0.0) / scale
    passed = theta - 1.0 / 6.0 - np.exp(-np.multiply.outer(theta, n ** 2 * math.pi ** 2)) @ weight
    passed = np.maximum(passed, 0.0)  # the series' last digits at theta = 0
    passed -= passed[0]
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, passed)


def ioniser_guard(rng, horizon_s=HORIZON_S, step_s=0.1):
    """The zero of a read-out whose input's floating guard an ionising air blower charges: while it runs (bouts of
    20-120 s, 15-90 s apart) the guard charges toward the blower's ion balance with 20-80 s (the ion current is
    small), and between bouts it leaks away through the air with 60-300 s (as a function of the seconds since the
    first sample, zero there)."""
    runs = bouts(rng, (15.0, 90.0), (20.0, 120.0), start_s=(-200.0, 30.0))
    charge_s, leak_s = rng.uniform(20.0, 80.0), rng.uniform(60.0, 300.0)
    grid = np.arange(-300.0, horizon_s + 1.0, step_s)
    on = np.zeros(grid.size, dtype=bool)
    for start, length in runs:
        on |= (grid >= start) & (grid < start + length)
    keep_on, keep_off = math.exp(-step_s / charge_s), math.exp(-step_s / leak_s)
    z, level = 0.0, np.empty(grid.size)
    for i, running in enumerate(on.tolist()):
        z = 1.0 + (z - 1.0) * keep_on if running else z * keep_off
        level[i] = z
    first = float(np.interp(0.0, grid, level))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, level) - first


# ----------------------------------------------------------------------------- resonance

class ConstantLossMode(SimOnly):
    """A needle holder of a filled engineering polymer whose material loss factor is nearly the same at every
    frequency (structural damping): the holder's spring is a ladder of 16 Maxwell arms, their relaxation frequencies
    spread evenly in log from 0.1 Hz to 6 kHz, weighted for a loss factor ``2 zeta`` across that band (its real part
    rising slowly with frequency, as causality asks); the tool's mass on it sets the mode at ``f0_hz``. The frequency
    and the damping do not change. Run through the exact frequency response on an FFT grid (20 s of padding), from
    rest."""

    def __init__(self, f0_hz, zeta):
        self.f0, self.eta = f0_hz, 2.0 * zeta
        self.taus = 1.0 / (2.0 * math.pi * np.geomspace(0.1, 6000.0, 16))
        spacing = math.log(6000.0 / 0.1) / 15.0
        self.weight = self.eta * spacing * 2.0 / math.pi

    def spring(self, w):
        out = np.ones(np.shape(w), dtype=complex)
        for tau in self.taus.tolist():
            out += self.weight * (1j * w * tau) / (1.0 + 1j * w * tau)
        return out

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        w0 = 2.0 * math.pi * self.f0
        mass = float(np.real(self.spring(np.array([w0]))[0])) / w0 ** 2
        size = 1 << int(math.ceil(math.log2(xu.size + int(20.0 / h))))
        w = 2.0 * math.pi * np.fft.rfftfreq(size, h)
        k = self.spring(w)
        response = k / (k - mass * w * w)
        y = np.fft.irfft(np.fft.rfft(xu - xu[0], size) * response, size)[:xu.size] + xu[0]
        return np.interp(t, tu, y)


def counterweight_mode(f0_hz, zeta, notch_ratio, notch_zeta):
    """A tool whose battery pack rides on a soft mount beside the sensor: the pack's inertia reaches the sensor, so the
    tool's mode at ``f0_hz`` (damping ratio ``zeta``) is preceded by an antiresonance at ``notch_ratio`` of it (damping
    ratio ``notch_zeta``), (p/z)^2 (s^2 + 2 zeta_z z s + z^2) / (s^2 + 2 zeta p s + p^2), unit gain at rest. The
    frequency and the damping do not change."""
    p, z = 2.0 * math.pi * f0_hz, 2.0 * math.pi * f0_hz * notch_ratio
    g = (p / z) ** 2
    return LinearFilter([g, g * 2.0 * notch_zeta * z, g * z * z], [1.0, 2.0 * zeta * p, p * p])


# ----------------------------------------------------------------------------- friction

class GuidedCore(SimOnly):
    """The Burgers core with a needle guide in parallel: the guide clamps the needle that the core's deformation moves
    and passes up to ``band_n`` (the same at every load, always) to the frame, the rest of the force reaching the core.
    ``law`` "jenkins": a clamped bushing whose shear spring (``stiff`` times the core's instantaneous stiffness) holds
    the needle until its force reaches the band, then slides; "mindlin": a spring-loaded ball plunger whose Hertzian
    contact micro-slips before it slides (Cattaneo-Mindlin: its tangential stiffness, ``stiff`` times the core's at
    first, falls as (1 - d (g - g_r) / 2 band)^(1/3) from the last reversal (g_r) of the needle's motion, Masing's
    rule), the contact last slid the other way. While the guide holds, the core's creep is held back and it hands its
    load to the guide; exact exponential steps of the core's units with the force held over each sample, from rest."""

    def __init__(self, c, band_n, stiff, law):
        self.k1, self.k2, self.eta1, self.eta2 = c.k1_n_per_v, c.k2_n_per_v, c.eta1_n_s_per_v, c.eta2_n_s_per_v
        self.band, self.kg, self.law = band_n, stiff * c.k1_n_per_v, law

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        k1, k2, eta1, eta2, band, kg = self.k1, self.k2, self.eta1, self.eta2, self.band, self.kg
        steps = np.diff(t, append=t[-1]).tolist()
        xk = xd = 0.0
        out = np.empty(t.size)
        if self.law == "jenkins":
            slip = 0.0
            for i, (fi, h) in enumerate(zip(f.tolist(), steps)):
                q = xk + xd
                fc = (fi - kg * (q - slip)) / (1.0 + kg / k1)
                g = fi - fc
                if abs(g) > band:
                    g = math.copysign(band, g)
                    fc = fi - g
                    slip = fc / k1 + q - g / kg
                xi = fc / k1 + q
                out[i] = xi
                xk = fc / k2 + (xk - fc / k2) * math.exp(-h * k2 / eta2)
                xd += h * fc / eta1
            return out
        g, g_rev, way, x_prev = 0.0, -band, 1.0, 0.0
        for i, (fi, h) in enumerate(zip(f.tolist(), steps)):
            q = xk + xd
            trial = (fi - g) / k1 + q - x_prev
            if trial * way < 0.0:
                way, g_rev = math.copysign(1.0, trial), g
            kt = kg * max(1.0 - way * (g - g_rev) / (2.0 * band), 0.0) ** (1.0 / 3.0)
            g_new = (g + kt * (fi / k1 + q - x_prev)) / (1.0 + kt / k1)
            g = min(max(g_new, -band), band)
            fc = fi - g
            x_prev = fc / k1 + q
            out[i] = x_prev
            xk = fc / k2 + (xk - fc / k2) * math.exp(-h * k2 / eta2)
            xd += h * fc / eta1
        return out


# ----------------------------------------------------------------------------- thermo-rheological

class FlangeGradientClock(SimOnly):
    """A core clamped between the robot's flange, held by its own thermostat at ``flange_c``, and the chamber's air,
    which reaches the core's free face with ``lag_s``: the temperature falls linearly across the core, and each of its
    eight layers (in series) runs on the Arrhenius clock exp(b (T_layer - T_ref)) of its own temperature; the core's
    deformation is their mean (the clock of the whole a log-mean of the two faces')."""

    def __init__(self, c, b_per_c, flange_c, lag_s, layers=8):
        self.c, self.b, self.flange, self.lag = c, b_per_c, flange_c, lag_s
        self.depths = (np.arange(layers) + 0.5) / layers

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        face = follow(t, temp_of(aux, t.size), self.lag)
        total = np.zeros(t.size)
        for z in self.depths:
            layer = self.flange + z * (face - self.flange)
            total += on_clock(self.c, t, f, np.exp(self.b * (layer - T_REF_C)))
        return total / self.depths.size


class MyegaSyrupClock(SimOnly):
    """A core whose dashpots hold a sugar syrup, a fragile glass former, its viscosity following the MYEGA law (Mauro et
    al.), log10 eta = -3 + 15 (Tg / T) exp((m / 15 - 1)(Tg / T - 1)) (fragility ``fragility``, Tg set for ``b_per_c``
    per degC of the clock at the reference), on the core's temperature (lag ``lag_s``): the clock runs at eta_ref /
    eta."""

    def __init__(self, c, b_per_c, fragility, lag_s):
        self.c, self.lag, self.m = c, lag_s, fragility
        t_ref = T_REF_C + 273.15
        bend = fragility / 15.0 - 1.0

        def slope(ratio):  # -d ln eta / dT at the reference for Tg = ratio T_ref
            return math.log(10.0) * 15.0 * math.exp(bend * (ratio - 1.0)) * (1.0 + bend * ratio) * ratio / t_ref
        self.tg = optimize.brentq(lambda r: slope(r) - b_per_c, 0.3, 1.0) * t_ref
        self.log_ref = self.log_eta(np.array([t_ref]))[0]

    def log_eta(self, kelvin):
        ratio = self.tg / kelvin
        return -3.0 + 15.0 * ratio * np.exp((self.m / 15.0 - 1.0) * (ratio - 1.0))

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        kelvin = follow(t, temp_of(aux, t.size), self.lag) + 273.15
        rate = 10.0 ** np.clip(self.log_ref - self.log_eta(kelvin), -6.0, 6.0)
        return on_clock(self.c, t, np.asarray(x, dtype=float), rate)


# ----------------------------------------------------------------------------- outside the catalogue

class DeltaStreamLoss(SimOnly):
    """A low-power wireless stream that sends each sample as its difference from the one before, in packets of
    ``packet_s``, with an absolute keyframe at the start of every ``keyframe_s``: when a packet is lost (chance
    ``loss``) the receiver holds its last value over it and then carries on adding the deltas that follow, so the
    increment the lost packet carried is missing from every reading until the next keyframe arrives (a lost keyframe
    leaves it for one period more); drawn from ``seed``."""

    def __init__(self, packet_s, keyframe_s, loss, seed):
        self.packet, self.keyframe, self.loss, self.seed = packet_s, keyframe_s, loss, seed

    def forward(self, t_s, x, aux=None, state=None):
        t, v = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        rng = np.random.default_rng(self.seed)
        packet = np.floor((t - t[0]) / self.packet).astype(int)
        period = np.floor((t - t[0]) / self.keyframe).astype(int)
        starts = np.flatnonzero(np.diff(packet, prepend=-1))
        ends = np.append(starts[1:], t.size)
        lost = rng.random(starts.size) < self.loss
        out, error = v.copy(), 0.0
        for a, b, gone in zip(starts.tolist(), ends.tolist(), lost.tolist()):
            if a == 0:
                continue
            if gone:
                out[a:b] = out[a - 1]
                error += v[b - 1] - v[a - 1]
                continue
            if period[a] != period[a - 1]:
                error = 0.0
            out[a:b] = v[a:b] - error
        return out


class SwingingDoor(SimOnly):
    """The bridge voltage as a process historian stores it, compressed by the swinging-door algorithm (a sample is
    archived when no straight line from the last archived one keeps every sample since within ``deviation``, or when
    ``max_gap_s`` has passed) and rebuilt by straight lines between the archived samples."""

    def __init__(self, deviation, max_gap_s):
        self.dev, self.gap = deviation, max_gap_s

    def forward(self, t_s, x, aux=None, state=None):
        t, v = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        dev, gap = self.dev, self.gap
        kept = [0]
        a, ta, va = 0, float(t[0]), float(v[0])
        low, high = -math.inf, math.inf
        tl, vl = t.tolist(), v.tolist()
        i = 1
        while i < len(tl):
            dt = tl[i] - ta
            if dt <= 0.0:
                i += 1
                continue
            new_low, new_high = max(low, (vl[i] - va - dev) / dt), min(high, (vl[i] - va + dev) / dt)
            if new_low > new_high or dt > gap:
                a = i - 1 if i - 1 > a else i
                kept.append(a)
                ta, va = tl[a], vl[a]
                low, high = -math.inf, math.inf
                i = a + 1
                continue
            low, high = new_low, new_high
            i += 1
        if kept[-1] != len(tl) - 1:
            kept.append(len(tl) - 1)
        idx = np.asarray(kept)
        return np.interp(t, t[idx], v[idx])


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([6e4, 8e3]))))  # V / (N s)
        if shape == "acoustic_softening":
            runs = bouts(rng, (10.0, 60.0), (3.0, 30.0))
            rule = acoustic_softening(phi * rng.uniform(0.5, 1.0), rng.uniform(3.0, 8.0), runs)
        else:
            rule = tapered_bleed_slot(phi * rng.uniform(0.3, 0.6), phi * rng.uniform(100.0, 400.0),
                                      rng.uniform(3.0, 6.0))
        return Parts("zener", LeakingCore.of(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        share = float(np.interp(m, [0, 1], [0.03, 0.2]))  # of the instantaneous response
        if shape == "dissolving_bubble":
            a = (share / g0, rng.uniform(3.0, 5.0), rng.uniform(12.0, 30.0), rng.uniform(2.0, 20.0))
            p.extra.append(lambda t, f, T, a=a: dissolving_bubble(t, f, *a))
            return p
        p.after.append(ElectrothermalGauge(share, rng.uniform(0.3, 0.7), rng.uniform(0.3, 2.0),
                                           rng.uniform(8.0, 40.0)))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.01, 0.06]))
        if shape == "tellinen_flux_guide":
            p.after.append(TellinenFluxGuide(frac, top, top * rng.uniform(0.0, 0.3), top * rng.uniform(0.25, 0.5),
                                             rng.uniform(0.2, 0.6), rng.uniform(0.1, 0.4)))
            return p
        p.after.append(GranularInterlayer(frac, top, top / rng.uniform(0.6, 2.5)))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.005, 0.09]))))
        if shape == "cvsd_link":
            clock = rng.uniform(2000.0, 3200.0)  # the largest step follows 4-12 ranges per second
            p.after.append(CvsdLink(clock, top / rng.uniform(1500.0, 4000.0), top * rng.uniform(4.0, 12.0) / clock,
                                    rng.uniform(0.004, 0.02), rng.uniform(0.05, 0.5), delay * rng.uniform(0.6, 0.9)))
            return p
        beta, rc = rng.uniform(0.55, 0.85), rng.uniform(0.001, 0.003)
        tau = max(delay * rng.uniform(0.8, 1.2) - rc, 0.5 * delay) * gamma_fn(1.0 / beta) / gamma_fn(2.0 / beta)
        p.after.append(PhosphorAfterglow(tau, beta, rc))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.05, 0.16]))
        if shape == "elastica_blade":
            p.after.append(StaticMap(elastica_blade(rel, top)))
            return p
        p.after.append(StaticMap(nozzle_flapper(rel, top, rng.uniform(0.35, 1.4))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.008, 0.03]) * rng.choice([-1, 1]))
        if shape == "bimaterial_flexure":
            a = (k, rng.uniform(0.3, 3.0), rng.uniform(5.0, 50.0), rng.uniform(0.03, 0.08), rng.uniform(10.0, 40.0))
            p.extra.append(lambda t, f, T, a=a: bimaterial_zero(t, T, *a))
            return p
        rh = rng.uniform(0.45, 0.75)
        a = (k, rh, rng.uniform(0.1, 0.25) / (0.063 * rh), rng.uniform(10.0, 40.0), rng.uniform(5.0, 30.0))
        p.extra.append(lambda t, f, T, a=a: surface_leakage_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.01, 0.025]))
        if shape == "electrostatic_softening":
            p.after.append(ElectrostaticSoftening(a * rng.choice([-1, 1]), rng.uniform(0.3, 0.7),
                                                  rng.uniform(10.0, 40.0)))
            return p
        share = rng.uniform(0.2, 0.6)
        p.after.append(HopkinsonFerrite(a, share, share * rng.uniform(0.5, 1.0) / a, rng.uniform(10.0, 40.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.012, 0.08]) * rng.choice([-1, 1]))
        zero = sized(heliox_permeation(rng) if shape == "heliox_permeation" else ioniser_guard(rng), size)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.03, 0.008])) * rng.uniform(0.8, 1.2)
        if shape == "constant_loss_holder":
            p.after.append(ConstantLossMode(rng.uniform(15.0, 45.0), zeta))
            return p
        p.after.append(counterweight_mode(rng.uniform(15.0, 45.0), zeta, rng.uniform(0.55, 0.85),
                                          zeta * rng.uniform(0.5, 1.5)))
        return p
    if effect == "friction":
        band = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "clamped_bushing":
            return Parts("burgers", GuidedCore(c, band, rng.uniform(20.0, 60.0), "jenkins"), core_changed=True)
        return Parts("burgers", GuidedCore(c, band, rng.uniform(3.0, 12.0), "mindlin"), core_changed=True)
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.15, 0.45]))
        if shape == "flange_gradient":
            # a layer halfway sees half the air's swing: the layers' own clocks are steeper
            return Parts("burgers", FlangeGradientClock(c, b * rng.uniform(1.6, 2.2), T_REF_C + rng.uniform(-0.5, 0.5),
                                                        rng.uniform(5.0, 20.0)), core_changed=True)
        # a syrup's clock is steep: 1.2-1.5 times the slope of the other shapes at the reference
        return Parts("burgers", MyegaSyrupClock(c, b * rng.uniform(1.2, 1.5), rng.uniform(90.0, 130.0),
                                                rng.uniform(5.0, 20.0)), core_changed=True)
    if effect == "delta_stream_loss":
        p.outer.append(DeltaStreamLoss(rng.uniform(0.01, 0.04), rng.uniform(0.5, 3.0),
                                       float(np.interp(m, [0, 1], [0.004, 0.015])), int(rng.integers(1 << 30))))
        return p
    if effect == "swinging_door":
        p.outer.append(SwingingDoor(float(np.interp(m, [0, 1], [0.008, 0.04])), rng.uniform(5.0, 30.0)))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["acoustic_softening", "tapered_bleed_slot"],
    "delayed_elasticity": ["dissolving_bubble", "electrothermal_gauge"],
    "hysteresis": ["tellinen_flux_guide", "granular_interlayer"],
    "sensor_lag": ["cvsd_link", "phosphor_afterglow"],
    "nonlinear_gain": ["elastica_blade", "nozzle_flapper"],
    "thermal_drift": ["bimaterial_flexure", "surface_leakage"],
    "thermal_sensitivity": ["electrostatic_softening", "hopkinson_ferrite"],
    "offset_drift": ["heliox_permeation", "ioniser_guard"],
    "resonance": ["constant_loss_holder", "counterweight_antiresonance"],
    "friction": ["clamped_bushing", "ball_plunger"],
    "thermo_rheological": ["flange_gradient", "myega_syrup"],
}
PAIRS = (("viscous_flow", "resonance"), ("delayed_elasticity", "thermal_drift"), ("hysteresis", "nonlinear_gain"),
         ("friction", "sensor_lag"), ("thermal_sensitivity", "offset_drift"),
         ("thermo_rheological", "delayed_elasticity"))
OUTSIDE = ("delta_stream_loss", "swinging_door")
RATES = (100.0, 290.0, 470.0, 740.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split X", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.85),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=hyperbaric_chamber,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.1e-3, 2.5e-3), jitter=0.25,
                   gap_s=(0.3, 2.5))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
