"""Independent split AC for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split AC is an untouched held-out set: written blind to the engine it measures (to how it detects and fits anything),
run once, and nothing is ever chosen from it. Every name of the catalogue is hidden in two shapes that neither the
registry's families (``polyforce_ros/sim/truths.py``) nor splits A to AB use:

* a pneumatic core venting to the atmosphere through an orifice (ISO 6358: the leak as the square root of light forces,
  constant once the vent chokes at a critical pressure ratio of 0.25-0.53; the atmosphere worth 1-4 N; 1.2-2.6 times
  the plain fluidity of 1/40000-1/4500 V/(N s) at 3 N), or a hydraulic core draining through a check valve into a line
  whose head changes as the robot tilts the tool (nothing flows below the head, 0.1-0.5 N at the flattest pose and
  1-2.8 N at the steepest, poses held 10-60 s and changed in 1-4 s; 1.6-3.5 times the plain fluidity above it);
  neither ever recovers;
* the strain at the centre of a poroelastic core read by gauges buried in it (the Mandel-Cryer effect: after each
  change of force the centre first goes back as the skin drains, a share a of 0.2-0.8 draining in 0.04-0.6 a / (1 + a)
  of the centre's 1-25 s, then creeps on as the centre drains), or a piezoelectric stack in the load path shunted
  by a current-regulating diode (it softens as its charge bleeds, resistively with 0.2-2 s until the diode caps the
  current: a 4 N change takes 2-15 s, in a straight line); both settle at 2-24 % of the instantaneous response;
* a Fabry-Perot read-out whose absorbing mirrors warm the cavity and tilt its resonance (thermo-optic bistability, 2.2-5
  times the critical heating: the transmission stays bright or dark over a band of 6-20 % of the range centred at 18-50
  % of it and jumps at its ends), or a resistive tactile read-out touching on 80 adhesive asperities (Greenwood and
  Williamson's heights about 15-50 % of the range, spread 8-25 %; each a JKR contact under displacement control that
  jumps in at touch and holds a neck to -0.693 of its adhesion length, 0.75-10.5 % of the range, before snapping off);
  the firmware linearises the mean curve of a cycle to three ranges and back; loops of 1-7 % of the range in a
  full-range cycle;
* the core's push read as pressure at the closed end of a liquid-filled line (echoes between the transducer and the
  core's compliant chamber, reflection 0.3-0.8 of the same sign: a staircase of (1 - r) r^n, each step rounded by the
  line's loss, 5-20 % of the delay), or firmware reporting a fixed-lag (Rauch-Tung-Striebel) smoothed estimate (a
  two-sided exponential window 15-50 % of its lag wide, centred that lag back and cut at the present); 8-120 ms of
  mean delay;
* an optical lever read on a flat detector (tan of twice the mirror's angle, at rest -15 to 25 degrees: expansive, or
  compressive from below the normal), or a passive LC tag whose resonance (1 / sqrt(C_p + C), C_p 0.2-3 times the
  sensing capacitor's) a gap-closing (expansive) or gap-opening (compressive) capacitor tunes; 4.5-20 % at the top of
  the range;
* the zero of a read-out bolted to a base of another metal through a clamped joint that takes the thermal mismatch
  until 0.6-3 degC worth has built up and then slips, keeping 0-60 % of it (thermal stick-slip; lag 5-30 s), or of a
  Hall read-out whose bias magnet follows the temperature 30-70 % at once and the rest through its magnetic viscosity
  (Street and Woolley: ln(1 + t / 0.5-5 s), complete after 100-1000 s; lag 5-30 s); 0.006-0.034 V/degC once settled;
* a flexure raised in sensitivity by attracting magnets (a quasi-zero-stiffness design cancelling 79-94 % of its
  stiffness, NdFeB or ferrite losing 0.11-0.2 % of their remanence per degC: the span falls as they warm, ever more
  steeply as they cool toward instability), or preloaded angular-contact bearings in series with the core (25-65 % of
  the compliance, Hertzian, as the preload to the power -1/3; the housing's expansion moves the preload, lifting it
  off 3-16 degC away, either way); lag 5-30 s; 1.4-3.6 %/degC at the reference;
* the weight of 3-7 saline drops splashed onto the read-out's exposed diaphragm (each evaporating over 60-400 s, first
  with its contact line pinned, falling linearly to 35-60 % over 40-70 % of its life, then at a constant contact angle
  as (1 - s)^(3/2)), or the zero of a two-channel optical read-out whose reference channel looks through a photochromic
  window that the operating lamp darkens (the lamp off or at 40-100 % for 20-150 s at a time; darkening within 20-60 s
  at full light, fading over 120-400 s); 15-100 mV at most;
* a needle holder's mode (14-48 Hz) on a carbon-black filled rubber mount (the Payne effect after Kraus: 15-40 % softer
  once the relative motion passes 20-60 % of the largest a linear mode would give, recovering over 0.5-5 s, its loss
  peaking as it softens), or on a suspension 30-70 % of whose stiffness is a pair of repelling magnets (the inverse
  fourth power of a gap 1.5-5 times that largest motion: stiffer toward the magnet than away); damping ratio
  0.0034-0.036 at rest;
* a Coulomb band of 0.2-5.3 % of the range: a core that bulges against its sleeve as it deforms (the band 20-50 % of
  its nominal width unloaded, growing with the core's own deformation, creep and flow included, to at most three times
  it), or a telescopic needle guide (the inner tube sliding with 30-60 % of the band over a stroke worth 0.2-1.2 N of
  the passed force's travel, the outer tube in its clamp with 1.1-1.5 times it at either end of that stroke);
* a core (soft enough for its clock to show) whose clock follows Bendler and Shlesinger's defect-diffusion law (log
  tau as (T - T0)^(-3/2), T0 25-80 degC below the reference), or the frustration-limited-domain law of Kivelson and
  Tarjus (Arrhenius above an avoided critical point 1-12 degC above the reference, 25-60 % of the slope there, plus B
  (T* - T)^(8/3) / T below it); 1.2-1.5 times 0.16-0.56 per degC at the reference, lag 5-25 s.

It also holds six pairs, two effects outside the catalogue (a 16-bit ADC one of whose parallel data lines is shorted
high or low, so every code has that bit forced, the bit nearest to 34-98 mV, over 1.2-2 times the core's output at
9 N; a read-out whose PEAK key bounces, 3-5 bouts of 3-35 s in which it streams the running maximum since the bout
began) and four clean records. Profiles: a needle robot pecking its way along the measured Okamura insertion
(``../shared/data``, ``time_force.csv``: its rise replayed 1.2-4.5 times slower and cut at 1-4 points, at each of
which the needle backs off to 8-40 % of the force, rests and comes back before going on; then the measured hold and
withdrawal; each insertion scaled to a 2-8.6 N peak, 4-25 s apart; a train of synthetic punctures when the data are
absent); a bioprinter's syringe plunger extruding a shear-thinning ink (perimeters, infill with turnarounds,
retractions and travel moves, layer changes, partial clogs); and a robot playing the cello, the sensor in its bow hold
(phrases with their dynamics, bow changes, accents, spiccato and tremolo passages, the bow lifted between phrases).
Rates 255, 415, 1150 and 1450 Hz (a mode at 1000 Hz with knocks that excite it), 0.85-2.55 mV noise, stamp jitter,
gaps, and a sensor on a plant-phenotyping robot in a greenhouse: the sun through passing clouds, the fogging system's
bursts of evaporative cooling, the roof vent, the robot moving between a sunny aisle and the shaded potting bench.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size against its
noise without diagnosing (for a leak on a Zener base, against that bare Zener core).

    .venv/bin/python bench/independent_split_ac.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, signal

from independent_split import puncture_train
from polyforce_ros.physics.expconv import exp_convolve
from polyforce_ros.physics.viscoelastic import Burgers, simulate_deformation
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (ForcePath, GridMode, LeakingCore, Parts, ShapeSplit, SimOnly, band_play, coarse, ease,
                       fit_departure, follow, kelvin, on_clock, sized as sized_over, temp_of, uniform_grid)

SEED0 = 2_100_000  # never a seed of the registry's splits nor of splits A (90000..) to AB (2000000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 450.0
HORIZON_S = DURATION_S + 60.0  # what a schedule drawn before the record covers (the record plus its gaps' slack)

sized = functools.partial(sized_over, horizon_s=HORIZON_S)


# ----------------------------------------------------------------------------- small tools

def relay(on, off, start):
    """A two-state switch per sample: True after the latest sample where ``on`` holds, False after the latest where
    ``off`` holds (``start`` before either)."""
    idx = np.arange(on.size)
    last_on = np.maximum.accumulate(np.where(on, idx, -1))
    last_off = np.maximum.accumulate(np.where(off, idx, -1))
    return np.where(last_on > last_off, True, np.where(last_off > last_on, False, start))


def schedule(rng, horizon_s, dwell_s, levels, move_s, before_s=600.0, step_s=0.1):
    """A piecewise-constant schedule from ``before_s`` before the first sample: a level drawn by ``levels(rng)`` held
    for ``dwell_s`` (min, max) seconds, then blended to the next over ``move_s`` (min, max) seconds with a
    minimum-jerk move. (seconds since the first sample, value) on a grid of ``step_s``."""
    grid = np.arange(-before_s, horizon_s + 2.0 * step_s, step_s)
    out = np.empty(grid.size)
    at, was = float(grid[0]), float(levels(rng))
    while at <= grid[-1]:
        dwell = rng.uniform(*dwell_s)
        sel = (grid >= at) & (grid < at + dwell)
        out[sel] = was
        at += dwell
        new, move = float(levels(rng)), rng.uniform(*move_s)
        sel = (grid >= at) & (grid < at + move)
        out[sel] = was + (new - was) * ease((grid[sel] - at) / move)
        at += move
        was = new
    return grid, out


# ----------------------------------------------------------------------------- profiles and temperature

@functools.lru_cache(maxsize=1)
def okamura_parts():
    """The measured Okamura insertion (``../shared/data``, ``time_force.csv``) at 1 kHz, its peak 1, cut into the
    rise (from the onset through the puncture to the bottom of the drop after the peak), the hold that follows
    (relative to where it starts) and the withdrawal (from 1 to 0). None when the data are absent."""
    try:
        _, fp = profiles.okamura_insertion(peak_n=1.0, rate_hz=1000.0, pre_s=0.0, post_s=0.0)
    except FileNotFoundError:
        return None
    s = np.convolve(fp, np.ones(25) / 25.0, mode="same")
    onset, peak = int(np.argmax(s > 0.03)), int(np.argmax(s))
    drop = peak + int(np.argmin(s[peak:peak + 500]))
    level = float(np.median(s[drop:drop + 4000]))
    late = s[drop + 2000:]
    w = drop + 2000 + (int(np.argmax(late < 0.75 * level)) if np.any(late < 0.75 * level) else late.size - 1)
    w0 = max(drop + 500, w - 200)
    rise = np.clip(fp[onset:drop + 1], 0.0, None)
    hold = np.clip(s[drop:w0] / max(float(s[drop]), 1e-6), 0.0, None)
    tail = s[w0:]
    stop = int(np.argmax(tail <= 0.01)) if np.any(tail <= 0.01) else tail.size - 1
    withdraw = np.clip(tail[:stop + 1] / max(float(tail[0]), 1e-6), 0.0, None)
    withdraw[-1] = 0.0
    return rise, hold, withdraw


def pecking_insertions(duration_s, rate_hz, rng):
    """A needle robot that pecks its way along the measured Okamura insertion (:func:`okamura_parts`): the measured
    rise replayed 1.2-4.5 times slower and cut at 1-4 random points; at each cut the needle backs off (the force
    falling to 8-40 % of where it was within 0.1-0.45 s as the shaft's friction reverses), rests 0.2-1.5 s, comes
    back (0.15-0.7 s to regain the force as the tissue is compressed again) and goes on along the measured curve;
    then the measured hold (0.3-1.4 times its length) and withdrawal (0.5-2 times). Each insertion scaled to a
    2-8.6 N peak; 4-25 s to the next. A train of synthetic punctures when the data are absent."""
    parts = okamura_parts()
    if parts is None:
        return puncture_train(duration_s, rate_hz, rng)
    rise, hold, withdraw = parts
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)

    def resampled(y, seconds):
        n = max(2, int(round(seconds * rate_hz)))
        return np.interp(np.linspace(0.0, y.size - 1.0, n), np.arange(y.size), y)

    def blend(a, b, seconds):
        n = max(2, int(round(seconds * rate_hz)))
        return a + (b - a) * ease(np.linspace(0.0, 1.0, n))

    cursor = rng.uniform(2.0, 8.0)
    while True:
        slow = rise.size / 1000.0 * rng.uniform(1.2, 4.5)
        y = resampled(rise, slow)
        cuts = np.sort(rng.uniform(0.15, 0.95, int(rng.integers(1, 5))))
        pieces, start = [], 0
        for c in cuts:
            stop = max(start + 2, int(c * y.size))
            pieces.append(y[start:stop])
            level = float(y[stop - 1])
            floor = level * rng.uniform(0.08, 0.4)
            rest = np.full(max(2, int(rng.uniform(0.2, 1.5) * rate_hz)), floor)
            pieces += [blend(level, floor, rng.uniform(0.1, 0.45)), rest, blend(floor, level, rng.uniform(0.15, 0.7))]
            start = stop
        pieces.append(y[start:])
        level = float(pieces[-1][-1])
        pieces.append(level * resampled(hold, hold.size / 1000.0 * rng.uniform(0.3, 1.4)))
        level = float(pieces[-1][-1])
        pieces.append(level * resampled(withdraw, withdraw.size / 1000.0 * rng.uniform(0.5, 2.0)))
        one = np.clip(np.concatenate(pieces), 0.0, None)
        one *= rng.uniform(2.0, 8.6) / max(float(one.max()), 1e-9)
        i0 = int(cursor * rate_hz)
        if i0 + one.size >= t.size - 1:
            break
        f[i0:i0 + one.size] = one
        cursor += one.size / rate_hz + rng.uniform(4.0, 25.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def bioprinter_plunger(duration_s, rate_hz, rng, step_s=0.002):
    """The plunger of a bioprinter's syringe pushing a shear-thinning hydrogel ink through its nozzle (the flow as the
    pressure to the power 1/n, n 0.3-0.6, plus a Newtonian part, 0.2-0.6 of the flow at the perimeter's pressure, that
    keeps the pressure falling at rest). The ink and the syringe's compliance make the force follow the commanded flow
    with 0.2-1.2 s (s' = (q - (s / r)^(1/n) - c s / r) / tau, in units of the force at the perimeter's flow, 1.4-3.4
    N); perimeters at that flow, infill 1.4-2.8 times faster with turnarounds every 0.4-2 s (the flow dipping to 25-60
    % for 0.06-0.2 s), travel moves between them (retracted at 2-4 times the flow for 0.05-0.2 s, 0.3-1.5 s of travel,
    primed again), layer changes (1-4 s), a new print every 40-160 s (5-20 s between); one extrusion in ten is partly
    clogged (the nozzle's resistance r rising to 1.4-2.5 over 2-8 s, then clearing at once); the plunger's O-ring adds
    0.05-0.35 N while it moves."""
    n_exp, tau = rng.uniform(0.3, 0.6), rng.uniform(0.2, 1.2)
    unit, seal = rng.uniform(1.4, 3.4), rng.uniform(0.05, 0.35)
    grid = np.arange(0.0, duration_s + step_s, step_s)
    q = np.zeros(grid.size)
    r = np.ones(grid.size)

    def put(at, length, value):
        i0, i1 = np.searchsorted(grid, [at, at + length])
        q[i0:i1] = value
        return at + length

    def extrude(at, length, flow, turns_s):
        end = put(at, length, flow)
        if turns_s:
            when = at + turns_s * rng.uniform(0.7, 1.3)
            while when < end - 0.3:
                put(when, rng.uniform(0.06, 0.2), flow * rng.uniform(0.25, 0.6))
                when += turns_s * rng.uniform(0.7, 1.3)
        if rng.random() < 0.1:
            grow = rng.uniform(2.0, 8.0)
            i0, i1 = np.searchsorted(grid, [at, min(at + grow, end)])
            r[i0:i1] = 1.0 + (rng.uniform(1.4, 2.5) - 1.0) * np.linspace(0.0, 1.0, i1 - i0)
        return end

    def travel(at):
        at = put(at, rng.uniform(0.05, 0.2), -rng.uniform(2.0, 4.0))
        at += rng.uniform(0.3, 1.5)
        return put(at, rng.uniform(0.05, 0.2), rng.uniform(2.0, 4.0))

    cursor = rng.uniform(1.0, 6.0)
    while cursor < duration_s:
        end_print = cursor + rng.uniform(40.0, 160.0)
        infill = rng.uniform(1.4, 2.8)
        while cursor < min(end_print, duration_s):
            for _ in range(int(rng.integers(1, 4))):
                cursor = extrude(cursor, rng.uniform(2.0, 8.0), 1.0, 0.0)
                cursor = travel(cursor)
            cursor = extrude(cursor, rng.uniform(3.0, 12.0), infill, rng.uniform(0.4, 2.0))
            cursor = travel(cursor) + rng.uniform(1.0, 4.0)
        cursor += rng.uniform(5.0, 20.0)
    s, inv, plateau = 0.0, 1.0 / n_exp, rng.uniform(0.2, 0.6)
    out = np.empty(grid.size)
    for i, (qi, ri) in enumerate(zip(q.tolist(), r.tolist())):
        s = max(s + step_s * (qi - (s / ri) ** inv - plateau * s / ri) / tau, 0.0)
        out[i] = unit * s + (seal if qi > 0.0 else 0.0)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    return t, np.clip(np.interp(t, grid, out), 0.0, FORCE_MAX_N)


def bowed_string(duration_s, rate_hz, rng):
    """A robot playing the cello, the sensor in its bow hold: phrases of 6-20 s with the bow lifted for 0.5-3 s
    between them; a phrase's bow force follows its dynamics (a swell, a crescendo or a diminuendo about 0.6-3.5 N);
    legato strokes of 0.4-2.5 s whose bow changes dip the force to 30-70 % for 40-100 ms; one note in five accented
    (1.5-2.2 times for 0.1-0.25 s, decaying); a quarter of the phrases spiccato (the bow bouncing at 5-12 Hz,
    touching the string 35-60 % of each bounce, peaks of 1-3.5 N) and some tremolo (12-18 Hz strokes modulating the
    force by 20-40 %); the arm's own unsteadiness (3 % of the force, 0.3 s)."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cursor = rng.uniform(0.5, 3.0)
    while cursor < duration_s:
        length = rng.uniform(6.0, 20.0)
        i0, i1 = np.searchsorted(t, [cursor, cursor + length])
        s = t[i0:i1] - cursor
        base = rng.uniform(0.6, 3.5)
        kind = int(rng.integers(3))
        shape = (np.sin(np.pi * s / length) if kind == 0 else s / length if kind == 1 else 1.0 - s / length)
        level = base * (0.5 + rng.uniform(0.5, 1.0) * shape)
        style = rng.random()
        if style < 0.25:  # spiccato
            hz, touch = rng.uniform(5.0, 12.0), rng.uniform(0.35, 0.6)
            phase = (s * hz) % 1.0
            y = np.where(phase < touch, np.clip(np.sin(np.pi * phase / touch), 0.0, None) ** 1.5, 0.0) * rng.uniform(1.0, 3.5) * (
                level / base)
        else:
            y = level.copy()
            if style > 0.85:  # tremolo
                y *= 1.0 + rng.uniform(0.2, 0.4) * np.sin(2.0 * np.pi * rng.uniform(12.0, 18.0) * s)
            at = 0.0
            while True:
                at += rng.uniform(0.4, 2.5)
                if at >= length - 0.2:
                    break
                width = rng.uniform(0.04, 0.1)
                near = np.abs(s - at) < width / 2.0
                y[near] *= 1.0 - rng.uniform(0.3, 0.7) * 0.5 * (1.0 + np.cos(2.0 * np.pi * (s[near] - at) / width))
                if rng.random() < 0.2:
                    after = s - at
                    y *= 1.0 + np.where(after > 0.0, rng.uniform(0.5, 1.2) * np.exp(-after / rng.uniform(0.1, 0.25)), 0.0)
        f[i0:i1] = y * ease(s / 0.08) * ease((length - s) / 0.08)
        cursor += length + rng.uniform(0.5, 3.0)
    keep = math.exp(-1.0 / (0.3 * rate_hz))
    wobble, _ = signal.lfilter([1.0], [1.0, -keep], rng.normal(0.0, math.sqrt(1.0 - keep * keep), t.size), zi=[0.0])
    return t, np.clip(f * (1.0 + 0.03 * wobble), 0.0, FORCE_MAX_N)


PROFILES = (pecking_insertions, bioprinter_plunger, bowed_string)


def greenhouse(t, rng, step_s=0.5):
    """A sensor on a plant-phenotyping robot in a greenhouse, from 900 s before the record: the heating's base 2-5 degC
    below the reference, drifting by up to +-0.5 degC over the record; the sun's load 3-7 degC, 10-40 % of it under the
    clouds that pass (sunny spells of 30-200 s, cloudy ones of 20-150 s, edges of 5-20 s); the air follows with 40-150 s;
    the climate computer fogs for 15-40 s (cooling the air by 0.06-0.16 degC/s) whenever the air is 0.5-2 degC above
    the reference and it has not fogged for 60-150 s, and opens the roof vent 0.5-1.5 degC above that (cooling the
    air's target by 0.8-2 degC, with 30-90 s) until the air is 0.3 degC below the fogging point; the robot works in a
    sunny aisle (1-3 degC of radiant gain under a clear sky) or at the shaded potting bench (30-150 s each, 5-15 s
    between). The sensor follows with 5-25 s (exact per step of ``step_s``)."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-900.0, d + 2.0 * step_s, step_s)
    base = T_REF_C + rng.uniform(-5.0, -2.0) + rng.uniform(-0.5, 0.5) * np.clip(grid / d, 0.0, 1.0)
    sun_c, cloud = rng.uniform(3.0, 7.0), rng.uniform(0.1, 0.4)
    sky = np.empty(grid.size)
    at, sunny = float(grid[0]), bool(rng.random() < 0.5)
    while at <= grid[-1]:
        dwell = rng.uniform(30.0, 200.0) if sunny else rng.uniform(20.0, 150.0)
        edge = rng.uniform(5.0, 20.0)
        sel = (grid >= at) & (grid < at + dwell + edge)
        u = ease((grid[sel] - at - dwell) / edge)
        now, nxt = (1.0, cloud) if sunny else (cloud, 1.0)
        sky[sel] = now + (nxt - now) * u
        at += dwell + edge
        sunny = not sunny
    radiant = rng.uniform(1.0, 3.0)
    where, aisle = schedule(rng, d, (30.0, 150.0), lambda r: float(r.random() < 0.5), (5.0, 15.0), before_s=900.0,
                            step_s=step_s)
    aisle = np.interp(grid, where, aisle)
    tau_air, fog_rate = rng.uniform(40.0, 150.0), rng.uniform(0.06, 0.16)
    fog_at, fog_len, fog_gap = T_REF_C + rng.uniform(0.5, 2.0), rng.uniform(15.0, 40.0), rng.uniform(60.0, 150.0)
    vent_at, vent_c, vent_tau = fog_at + rng.uniform(0.5, 1.5), rng.uniform(0.8, 2.0), rng.uniform(30.0, 90.0)
    air = float(base[0]) + sun_c * float(sky[0])
    fog_until, last_fog, vent_open, vent = -1e9, -1e9, False, 0.0
    air_out = np.empty(grid.size)
    for i, g in enumerate(grid.tolist()):
        if air > fog_at and g - last_fog > fog_gap and g >= fog_until:
            fog_until, last_fog = g + fog_len, g + fog_len
        if air > vent_at:
            vent_open = True
        elif air < fog_at - 0.3:
            vent_open = False
        vent += ((vent_c if vent_open else 0.0) - vent) * (1.0 - math.exp(-step_s / vent_tau))
        target = float(base[i]) + sun_c * float(sky[i]) - vent
        air += (target - air) * (1.0 - math.exp(-step_s / tau_air)) - (fog_rate * step_s if g < fog_until else 0.0)
        air_out[i] = air
    felt = air_out + radiant * aisle * np.clip((sky - cloud) / (1.0 - cloud), 0.0, 1.0)
    keep = math.exp(-step_s / rng.uniform(5.0, 25.0))
    sensor, _ = signal.lfilter([1.0 - keep], [1.0, -keep], felt, zi=[keep * felt[0]])
    return np.interp(s, grid, sensor)


# ----------------------------------------------------------------------------- viscous flow

def choked_vent_leak(fluidity_at_3n, atm_n, critical):
    """A pneumatic core venting to the atmosphere through an orifice, after ISO 6358: the mass flow C p1 sqrt(1 -
    ((p2 / p1 - b) / (1 - b))^2) while subsonic and C p1 once the pressure ratio p2 / p1 falls to the critical b
    (``critical``), p1 = atmosphere + F (the atmosphere worth ``atm_n``), p2 = atmosphere. The gas lost shrinks the
    core by that flow over the gas's density (as p1): the leak grows as the square root of light forces and stays
    constant once the vent chokes. Scaled to ``fluidity_at_3n`` times 3 N at 3 N. It never recovers."""
    def shape(f):
        ratio = atm_n / (atm_n + np.maximum(f, 0.0))
        sub = np.sqrt(np.clip(1.0 - ((ratio - critical) / (1.0 - critical)) ** 2, 0.0, None))
        return np.where(ratio <= critical, 1.0, sub)

    k = fluidity_at_3n * 3.0 / float(shape(np.array([3.0]))[0])

    def rule(t, f):
        return integrate.cumulative_trapezoid(k * shape(f), t, initial=0.0)
    return rule


def drain_head(rng, horizon_s=HORIZON_S):
    """The back pressure (in N) of a drain line that rises from the core to an outlet above it, as the robot tilts the
    tool: poses held 10-60 s, moved between in 1-4 s, the outlet's head 0.1-0.5 N at the flattest pose and 1-2.8 N at
    the steepest (the sine of a tilt of 10-80 degrees). A function of the seconds since the first sample."""
    low, high = rng.uniform(0.1, 0.5), rng.uniform(1.0, 2.8)
    grid, tilt = schedule(rng, horizon_s, (10.0, 60.0), lambda r: r.uniform(10.0, 80.0), (1.0, 4.0))
    s_lo, s_hi = math.sin(math.radians(10.0)), math.sin(math.radians(80.0))
    head = low + (high - low) * (np.sin(np.radians(tilt)) - s_lo) / (s_hi - s_lo)
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, head)


def drain_leak(fluidity, head_fn):
    """x' = A max(F - H(t), 0): a hydraulic core draining through a check valve into a line whose head H (``head_fn``)
    changes with the tool's tilt; nothing flows below the head and nothing flows back. It never recovers."""
    def rule(t, f):
        return integrate.cumulative_trapezoid(fluidity * np.maximum(f - head_fn(t - t[0]), 0.0), t, initial=0.0)
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def mandel_cryer(t, f, compliance_v_per_n, drained_s, skin_share, skin_ratio):
    """The strain at the centre of a poroelastic (hydrogel) core read by gauges buried in it: as the skin drains first
    it squeezes the centre (the Mandel-Cryer effect), so after a change of force the centre's strain first goes back by
    a share and then creeps on as the centre drains: C ((1 + a) K(tau) - a K(r tau)) on the force, K a unit Kelvin lag
    (C = ``compliance_v_per_n``, tau = ``drained_s``, a = ``skin_share``, r = ``skin_ratio`` < 1/(1 + 1/a)); it
    settles at C F."""
    return ((1.0 + skin_share) * kelvin(t, f, compliance_v_per_n, drained_s)
            - skin_share * kelvin(t, f, compliance_v_per_n, drained_s * skin_ratio))


def shunted_stack(t, f, compliance_v_per_n, tau_s, slew_v_per_s, step_s=0.005):
    """A piezoelectric stack in the load path shunted by a current-regulating diode: open-circuited it is stiff; as its
    charge bleeds through the shunt it softens toward its short-circuit compliance, C F more (C =
    ``compliance_v_per_n``). The diode passes the charge resistively (``tau_s``) until its regulated current caps the
    bleed (``slew_v_per_s`` of deformation): small changes settle exponentially, large ones in a straight line. Exact
    exponential steps of ``step_s``, each capped; settled at the first force."""
    grid, fg = coarse(t, f, step_s)
    keep, cap = math.exp(-step_s / tau_s), slew_v_per_s * step_s
    u = compliance_v_per_n * float(fg[0])
    out = np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        out[i] = u
        goal = compliance_v_per_n * fi
        u += min(max(goal + (u - goal) * keep - u, -cap), cap)
    return np.interp(t, grid, out)


# ----------------------------------------------------------------------------- hysteresis

def linearised(read, reach=3.0, n=3001):
    """What the firmware makes of a read-out ``read(u)`` with a loop (u the core's output over the range's): the
    mean of its branches over a cycle from 0 to ``reach`` ranges and back (its linearisation, on that grid), and the
    loop's largest height over a full-range cycle."""
    def branches(top):
        cycle = np.concatenate([np.linspace(0.0, top, n), np.linspace(top, 0.0, n)[1:]])
        c = read(cycle)
        return c[:n], c[n - 1:][::-1]
    up, down = branches(reach)
    full_up, full_down = branches(1.0)
    return np.linspace(0.0, reach, n), 0.5 * (up + down), float(np.max(np.abs(full_up - full_down)))


class ThermoOpticCavity(SimOnly):
    """A Fabry-Perot read-out whose mirrors absorb a little of the circulating light and warm the cavity, which tilts
    its resonance (thermo-optic bistability): the transmission I solves I (1 + (D - ``beta`` I)^2) = 1 at the
    detuning D, which the load sweeps, D = D_mid + s (u - ``centre``), u = x / ``top``. Over a band of ``band`` of the
    range about ``centre`` two transmissions are stable: sweeping up the cavity stays on the bright branch to the
    band's top and drops there, sweeping down it stays dark to the band's bottom and jumps there. The reading is x plus
    ``sign`` k top times I less the firmware's linearisation (:func:`linearised`), k set for a loop of ``width`` of
    the range at its widest in a full-range cycle."""

    def __init__(self, top, width, beta, centre, band, sign):
        i = np.linspace(1e-4, 1.0, 40001)
        root = np.sqrt(1.0 / i - 1.0)
        plus, minus = beta * i + root, beta * i - root
        turns = np.flatnonzero(np.diff(np.sign(np.diff(plus))))
        ib, ia = int(turns[0]) + 1, int(turns[-1]) + 1
        self.d_lo, self.d_hi = float(plus[ib]), float(plus[ia])
        self.low_d, self.low_i = plus[:ib + 1][::-1], i[:ib + 1][::-1]
        self.up_d = np.concatenate([minus, plus[ia:][::-1][1:]])
        self.up_i = np.concatenate([i, i[ia:][::-1][1:]])
        self.mid, self.slope = 0.5 * (self.d_lo + self.d_hi), (self.d_hi - self.d_lo) / band
        self.top, self.centre, self.sign = top, centre, sign
        self.grid, self.mean, loop = linearised(self._light)
        self.k = width / max(loop, 1e-12)

    def _light(self, u):
        d = self.mid + self.slope * (np.asarray(u, dtype=float) - self.centre)
        bright = relay(d < self.d_lo, d > self.d_hi, bool(d[0] <= self.mid))
        return np.where(bright, np.interp(d, self.up_d, self.up_i), np.interp(d, self.low_d, self.low_i))

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        u = x / self.top
        return x + self.sign * self.k * self.top * (self._light(u) - np.interp(u, self.grid, self.mean))


class AdhesiveAsperities(SimOnly):
    """A resistive tactile read-out whose soft electrode meets its counter-electrode on ``n`` adhesive asperities
    (Greenwood and Williamson's heights, normal about ``height`` of the range with ``spread``, from ``seed``), each a
    JKR contact under displacement control: in Maugis' units d = a^2 - 4/3 sqrt(a) of its own adhesion length (0.5-1.5
    times ``adhesion`` of the range), it jumps into contact when the core's deformation reaches it (a = (4/3)^(2/3)) and
    holds a neck down to d = -0.693 before it snaps off (a = 3^(-2/3)). The conductance is the sum of the contact radii
    (in the range's units); the reading is x plus ``sign`` k top times it less the firmware's linearisation
    (:func:`linearised`), k set for a loop of ``width`` of the range at its widest in a full-range cycle."""

    _a = np.linspace(3.0 ** (-2.0 / 3.0), 60.0, 6000)
    _d = _a * _a - 4.0 / 3.0 * np.sqrt(_a)

    def __init__(self, top, width, n, height, spread, adhesion, sign, seed):
        rng = np.random.default_rng(seed)
        self.h = np.clip(rng.normal(height, spread, n), 0.02, 0.98)
        self.len = adhesion * rng.uniform(0.5, 1.5, n)
        self.top, self.sign = top, sign
        self.grid, self.mean, loop = linearised(self._conductance)
        self.k = width / max(loop, 1e-12)

    def _conductance(self, u):
        u = np.asarray(u, dtype=float)
        total = np.zeros(u.size)
        for h, ell in zip(self.h.tolist(), self.len.tolist()):
            depth = (u - h) / ell
            touching = relay(depth >= 0.0, depth < float(self._d[0]), False)
            total += np.where(touching, ell * np.interp(depth, self._d, self._a), 0.0)
        return total

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        u = x / self.top
        return x + self.sign * self.k * self.top * (self._conductance(u) - np.interp(u, self.grid, self.mean))


# ----------------------------------------------------------------------------- sensor lag

class EchoingLine(SimOnly):
    """The core's push read as pressure at the closed end of a liquid-filled line: the pressure wave takes
    ``transit_s`` each way and echoes between the transducer (a closed end) and the core's compliant chamber
    (reflection ``reflect`` of the same sign), so the reading climbs in a staircase, (1 - r) r^n of each change
    arriving (2n + 1) transits late; the line's viscous loss rounds each step (a lag of ``round_s``). Settled at the
    first sample."""

    def __init__(self, transit_s, reflect, round_s):
        self.transit, self.r, self.round = transit_s, reflect, round_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        n = int(math.ceil(math.log(1e-4) / math.log(self.r)))
        y = np.zeros_like(x)
        for k in range(n):
            y += self.r ** k * np.interp(t - (2 * k + 1) * self.transit, t, x, left=x[0])
        y *= (1.0 - self.r) / (1.0 - self.r ** n)
        return x[0] + exp_convolve(t, y - x[0], [1.0 / self.round])[:, 0] / self.round


class FixedLagSmoother(SimOnly):
    """Firmware that reports a fixed-lag (Rauch-Tung-Striebel) smoothed estimate of the reading: the force ``lag_s``
    ago from the samples up to now, for a random-walk model in white noise a two-sided exponential (Laplace) window of
    ``width_s`` centred ``lag_s`` back and cut at the present. On a uniform grid at the median step, from rest."""

    def __init__(self, lag_s, width_s):
        self.lag, self.width = lag_s, width_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        taps = np.arange(int(math.ceil((self.lag + 10.0 * self.width) / h)) + 1) * h
        w = np.exp(-np.abs(taps - self.lag) / self.width)
        y = signal.fftconvolve(xu - xu[0], w / w.sum())[:xu.size] + xu[0]
        return np.interp(t, tu, y)


def smoother_for(delay_s, share):
    """A :class:`FixedLagSmoother` whose window (``share`` of its lag wide) has a mean delay of ``delay_s``."""
    lag = delay_s
    for _ in range(8):
        taps = np.linspace(0.0, lag * (1.0 + 10.0 * share), 4001)
        w = np.exp(-np.abs(taps - lag) / (share * lag))
        lag += delay_s - float(np.sum(w * taps) / np.sum(w))
    return FixedLagSmoother(lag, share * lag)


# ----------------------------------------------------------------------------- nonlinear gain

def optical_lever(rel, reach, rest_deg):
    """x read as the spot of an optical lever on a flat detector: the mirror turns from ``rest_deg`` by k x and the
    spot moves as tan(2 theta) (expansive from a rest angle at or above zero, S-shaped from below it: compressive until
    the beam passes the detector's normal); scaled to slope 1 at no load, k set for a departure of ``rel`` at ``reach``
    (2 theta at most 76 degrees)."""
    th0 = math.radians(rest_deg)
    slope = 2.0 / math.cos(2.0 * th0) ** 2

    def read(x, k):
        return (np.tan(2.0 * (th0 + k * np.asarray(x, dtype=float))) - math.tan(2.0 * th0)) / (slope * k)
    return fit_departure(read, rel, reach, (math.radians(38.0) - th0) / reach)


def lc_tag(rel, reach, parasitic, closing):
    """x read as the shift of a passive LC tag's resonance, f = 1 / sqrt(L (C_p + C(x))), its sensing capacitor a gap
    that the load closes (C / (1 - k x): expansive, then saturating as f falls toward 0) or opens (C / (1 + k x)), the
    fixed capacitance C_p ``parasitic`` times the sensing one at rest; scaled to slope 1 at no load, k set for a
    departure of ``rel`` at ``reach`` (the gap closing by 92 % at most)."""
    def freq(v):
        return (parasitic + 1.0 / (1.0 - v if closing else 1.0 + v)) ** -0.5

    d0 = (freq(1e-6) - freq(-1e-6)) / 2e-6

    def read(x, k):
        return (freq(k * np.asarray(x, dtype=float)) - freq(0.0)) / (d0 * k)
    return fit_departure(read, rel, reach, (0.92 if closing else 6.0) / reach)


# ----------------------------------------------------------------------------- thermal drift

def slipping_joint_zero(t, temp, k_v_per_c, lag_s, slip_c, residual, start, step_s=0.5):
    """The zero of a read-out bolted to a base of another metal through a clamped joint: the joint (lag ``lag_s``)
    takes the thermal mismatch elastically, k per degC (``k_v_per_c``), until it has built up ``slip_c`` degC worth,
    then slips and keeps only ``residual`` of that (thermal stick-slip: a sawtooth in temperature that remembers its
    path); the joint held ``start`` of its limit at the first sample. Exact per step of ``step_s``."""
    grid = np.arange(t[0], t[-1] + step_s, step_s)
    body = np.interp(grid, t, follow(t, temp, lag_s)) - T_REF_C
    shift = float(body[0]) - start * slip_c
    out = np.empty(grid.size)
    for i, b in enumerate(body.tolist()):
        held_c = b - shift
        if held_c > slip_c:
            shift, held_c = b - residual * slip_c, residual * slip_c
        elif held_c < -slip_c:
            shift, held_c = b + residual * slip_c, -residual * slip_c
        out[i] = held_c
    return np.interp(t, grid, k_v_per_c * out)


def viscous_magnet_zero(t, temp, k_v_per_c, prompt, tau0_s, settle_s, lag_s, step_s=0.5):
    """The zero of a Hall read-out set by its bias magnet (lag ``lag_s``), whose field follows the temperature partly
    at once (``prompt``) and partly through its magnetic viscosity (Street and Woolley: thermally activated switching
    over a broad spread of barriers, each change followed as ln(1 + t / ``tau0_s``), complete after ``settle_s``); k
    per degC (``k_v_per_c``) once settled. Exact per step of ``step_s``, settled at the first sample."""
    grid = np.arange(t[0], t[-1] + step_s, step_s)
    body = np.interp(grid, t, follow(t, temp, lag_s)) - T_REF_C
    steps = np.diff(body, prepend=body[0])
    after = np.arange(grid.size) * step_s
    kernel = np.minimum(np.log1p(after / tau0_s) / math.log1p(settle_s / tau0_s), 1.0)
    slow = signal.fftconvolve(steps, kernel)[:grid.size] + body[0]
    return np.interp(t, grid, k_v_per_c * (prompt * body + (1.0 - prompt) * slow))


# ----------------------------------------------------------------------------- thermal sensitivity

class NegativeStiffnessSpan(SimOnly):
    """A flexure raised in sensitivity by a pair of attracting magnets (a quasi-zero-stiffness design: their negative
    stiffness cancels ``cancel`` of the flexure's), the magnets (lag ``lag_s``) losing ``remanence_per_c`` of their
    remanence per degC (their stiffness as its square): the span (1 - c) / (1 - c (1 - a dT)^2) falls as they warm,
    the more steeply the closer the design sits to zero stiffness."""

    def __init__(self, cancel, remanence_per_c, lag_s):
        self.c, self.a, self.lag = cancel, remanence_per_c, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        den = np.maximum(1.0 - self.c * (1.0 - self.a * d) ** 2, 0.2 * (1.0 - self.c))
        return np.asarray(x, dtype=float) * (1.0 - self.c) / den


class PreloadedBearingSpan(SimOnly):
    """A pair of preloaded angular-contact bearings in series with the core, ``share`` of the compliance at the
    reference, their Hertzian compliance as the preload to the power -1/3; the housing's expansion against the shaft
    (lag ``lag_s``) moves the preload, F = F0 (1 + ``way`` dT / ``lift_c``) (at least 5 % of it left): the span (1 +
    s (F / F0)^(-1/3)) / (1 + s), steepening toward the unloading side."""

    def __init__(self, share, lift_c, way, lag_s):
        self.s, self.lift, self.way, self.lag = share, lift_c, way, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        load = np.maximum(1.0 + self.way * d / self.lift, 0.05)
        return np.asarray(x, dtype=float) * (1.0 + self.s * load ** (-1.0 / 3.0)) / (1.0 + self.s)


# ----------------------------------------------------------------------------- offset drift

def evaporating_drops(rng, horizon_s=HORIZON_S):
    """The weight of saline drops splashed onto the read-out's exposed diaphragm: 3-7 drops (0.3-1 each, from 240 s
    before the first sample), each arriving within 0.1-0.3 s and evaporating over 60-400 s, first with its contact
    line pinned (its mass falling linearly to 35-60 % over 40-70 % of its life) and then at a constant contact angle
    (the rest as (1 - s)^(3/2)). As a function of the seconds since the first sample, zero there."""
    drops = [(rng.uniform(-240.0, horizon_s), rng.uniform(0.3, 1.0), rng.uniform(60.0, 400.0), rng.uniform(0.4, 0.7),
              rng.uniform(0.35, 0.6), rng.uniform(0.1, 0.3)) for _ in range(int(rng.integers(3, 8)))]

    def weight(s):
        s = np.asarray(s, dtype=float)
        out = np.zeros(s.shape)
        for at, mass, life, pinned, left, land in drops:
            u = (s - at) / life
            first = 1.0 - (1.0 - left) * u / pinned
            second = left * np.clip(1.0 - (u - pinned) / (1.0 - pinned), 0.0, 1.0) ** 1.5
            out += mass * ease((s - at) / land) * np.where(u < pinned, first, np.where(u < 1.0, second, 0.0))
        return out

    w0 = float(weight(np.array([0.0]))[0])
    return lambda s: weight(s) - w0


def photochromic_window(rng, horizon_s=HORIZON_S, step_s=0.5):
    """The zero of a two-channel optical read-out whose reference channel looks through a photochromic window that
    the operating lamp's ultraviolet darkens: the lamp (from 600 s before the first sample) off or at 40-100 % for
    20-150 s at a time (moved or dimmed in 1-5 s); the darkened share D' = k_d I (1 - D) - k_f D, darkening within
    20-60 s at full light and fading over 120-400 s in the dark. As a function of the seconds since the first sample,
    zero there."""
    grid, lamp = schedule(rng, horizon_s, (20.0, 150.0),
                          lambda r: 0.0 if r.random() < 0.4 else r.uniform(0.4, 1.0), (1.0, 5.0), step_s=step_s)
    dark, fade = 1.0 / rng.uniform(20.0, 60.0), 1.0 / rng.uniform(120.0, 400.0)
    d = 0.0
    out = np.empty(grid.size)
    for i, light in enumerate(lamp.tolist()):
        rate = dark * light + fade
        goal = dark * light / rate
        d = goal + (d - goal) * math.exp(-rate * step_s)
        out[i] = d
    first = float(np.interp(0.0, grid, out))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, out) - first


# ----------------------------------------------------------------------------- resonance

def mode_coefficients(f0_hz, zeta, fs):
    """A unit-gain damped mode (bilinear at ``fs``): (b, a)."""
    w = 2.0 * math.pi * f0_hz
    return signal.bilinear([w * w], [1.0, 2.0 * zeta * w, w * w], fs=fs)


class PayneMountMode(GridMode):
    """A needle holder's mode at ``f0_hz`` (unit gain at rest) on a carbon-black filled rubber mount: the mount softens
    with the amplitude it carries (the Payne effect after Kraus: the stiffness 1 - ``drop`` q / (1 + q), q = (e /
    e_c)^2, e the envelope of the relative motion, which rises at once and recovers with ``recover_s``; e_c ``knee`` of
    the largest relative motion the record gives a mode that did not soften) and its loss peaks where it softens fastest
    (the damping ratio ``zeta`` times 1 + ``bump`` sqrt(q) / (1 + q)). Semi-implicit Euler on a uniform grid of ``fs``
    Hz, from rest."""

    fs = 3000.0

    def __init__(self, f0_hz, zeta, drop, knee, recover_s, bump):
        self.w, self.zeta, self.drop, self.knee, self.recover, self.bump = (2.0 * math.pi * f0_hz, zeta, drop, knee,
                                                                            recover_s, bump)

    def on_grid(self, t, tu, xu, h):
        b, a = mode_coefficients(self.w / (2.0 * math.pi), self.zeta, self.fs)
        ec = self.knee * max(float(np.max(np.abs(signal.lfilter(b, a, xu) - xu))), 1e-12)
        w, z0, drop, bump = self.w, self.zeta, self.drop, self.bump
        fade = math.exp(-h / self.recover)
        y = v = e = 0.0
        out = np.empty(tu.size)
        for i, xi in enumerate(xu.tolist()):
            e = max(abs(y - xi), e * fade)
            q = (e / ec) ** 2
            stiff = 1.0 - drop * q / (1.0 + q)
            zeta = z0 * (1.0 + bump * math.sqrt(q) / (1.0 + q))
            v += (w * w * stiff * (xi - y) - 2.0 * zeta * w * math.sqrt(stiff) * v) * h
            y += v * h
            out[i] = y
        return out


class MagnetSuspensionMode(GridMode):
    """A needle holder's mode at ``f0_hz`` (unit gain at rest, damping ratio ``zeta``) whose spring is ``share`` a pair
    of repelling magnets (their force as the inverse fourth power of the gap, which the holder's motion closes on the
    ``way`` side): the magnets' part of the restoring force is s (k_m g / 4) ((1 - s z / g)^-4 - 1), stiffer toward the
    magnet than away from it (an asymmetric, softening-hardening spring); the gap g is ``gap`` times the largest
    relative motion the record gives a linear mode (closed to 20 % at most). Semi-implicit Euler on a uniform grid of
    ``fs`` Hz, from rest."""

    fs = 3000.0

    def __init__(self, f0_hz, zeta, share, gap, way):
        self.w, self.zeta, self.share, self.gap, self.way = 2.0 * math.pi * f0_hz, zeta, share, gap, way

    def on_grid(self, t, tu, xu, h):
        b, a = mode_coefficients(self.w / (2.0 * math.pi), self.zeta, self.fs)
        g = self.gap * max(float(np.max(np.abs(signal.lfilter(b, a, xu) - xu))), 1e-12)
        w2, c, q, s = self.w * self.w, 2.0 * self.zeta * self.w, self.share, self.way
        y = v = 0.0
        out = np.empty(tu.size)
        for i, xi in enumerate(xu.tolist()):
            z = y - xi
            close = min(s * z / g, 0.8)
            push = s * q * g / 4.0 * ((1.0 - close) ** -4 - 1.0)
            v += (-w2 * ((1.0 - q) * z + push) - c * v) * h
            y += v * h
            out[i] = y
        return out


# ----------------------------------------------------------------------------- friction

def bulging_core_band(c, band_n, floor, t, f):
    """The force passed by a core that bulges against its sleeve as it deforms: the sleeve's Coulomb band is
    ``band_n`` times ``floor`` + (1 - ``floor``) x / x_4 (x the core's own deformation, its creep and flow included,
    x_4 the instantaneous deformation at 4 N; at most 3 times ``band_n``): wider the longer and harder the core has been
    pressed, narrowing again as it recovers. Started at ``f[0]``."""
    x = simulate_deformation(c, t, f)
    band = band_n * np.clip(floor + (1.0 - floor) * x * c.k1_n_per_v / 4.0, floor, 3.0)
    return band_play(f, band, band)


def telescoping_guide(f, light_n, heavy_n, stroke_n):
    """The force passed by a telescopic needle guide: its inner tube slides in the outer with a light Coulomb band
    (``light_n``) over a stroke worth ``stroke_n`` of the passed force's travel; at either end of that stroke the outer
    tube must slide in its clamp, with a heavy band (``heavy_n``). Small strokes show the light band, long ones the heavy
    one, and each reversal slides the inner tube back first. Started at ``f[0]``, the inner tube mid-stroke."""
    p, y = float(f[0]), 0.5 * stroke_n
    out = np.empty_like(f)
    for i, fi in enumerate(f.tolist()):
        if fi > p + light_n and y < stroke_n:
            d = min(fi - light_n - p, stroke_n - y)
            p, y = p + d, y + d
        elif fi < p - light_n and y > 0.0:
            d = min(p - light_n - fi, y)
            p, y = p - d, y - d
        if fi > p + heavy_n:
            p = fi - heavy_n
        elif fi < p - heavy_n:
            p = fi + heavy_n
        out[i] = p
    return out


# ----------------------------------------------------------------------------- thermo-rheological

def creeping(c):
    """The core made soft enough for its clock to show, and no softer: its Kelvin spring at most 18 N/V (the
    retardation time kept) and its flow's viscosity within 6e3-3.5e4 N s/V."""
    k2 = min(c.k2_n_per_v, 18.0)
    return Burgers(c.k1_n_per_v, k2, float(np.clip(c.eta1_n_s_per_v, 6e3, 3.5e4)), c.eta2_n_s_per_v * k2 / c.k2_n_per_v)


class DefectDiffusionClock(SimOnly):
    """A core whose clock follows Bendler and Shlesinger's defect-diffusion law, log tau = A + B (T - T0)^(-3/2), T0
    ``below_c`` below the reference, B set for ``b_per_c`` per degC of the clock there; on the core's temperature (lag
    ``lag_s``), never closer to T0 than a fifth of the reference's distance, held within e^+-6."""

    def __init__(self, c, b_per_c, below_c, lag_s):
        self.c, self.lag, self.below = c, lag_s, below_c
        self.bb = 2.0 / 3.0 * b_per_c * below_c ** 2.5

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag)
        dist = np.maximum(body - T_REF_C + self.below, 0.2 * self.below)
        log_rate = self.bb * (self.below ** -1.5 - dist ** -1.5)
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(log_rate, -6.0, 6.0)))


class FrustratedDomainsClock(SimOnly):
    """A core whose clock follows the frustration-limited-domain theory of Kivelson and Tarjus: log tau = E / T + B
    (T* - T)^(8/3) / T below the avoided critical point T* (``above_c`` above the reference) and Arrhenius above it,
    the Arrhenius part ``arrhenius`` of ``b_per_c`` per degC of the clock at the reference (T in kelvin); on the core's
    temperature (lag ``lag_s``), held within e^+-6."""

    def __init__(self, c, b_per_c, above_c, arrhenius, lag_s):
        ref = T_REF_C + 273.15
        self.c, self.lag, self.star = c, lag_s, ref + above_c
        self.e = arrhenius * b_per_c * ref * ref
        gap = above_c
        self.b = (1.0 - arrhenius) * b_per_c / (8.0 / 3.0 * gap ** (5.0 / 3.0) / ref + gap ** (8.0 / 3.0) / ref ** 2)
        self.ref_log = self._log_tau(np.array([ref]))[0]

    def _log_tau(self, kelvin_t):
        return self.e / kelvin_t + self.b * np.maximum(self.star - kelvin_t, 0.0) ** (8.0 / 3.0) / kelvin_t

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag) + 273.15
        log_rate = self.ref_log - self._log_tau(body)
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(log_rate, -6.0, 6.0)))


# ----------------------------------------------------------------------------- outside the catalogue

class StuckDataBit(SimOnly):
    """A 16-bit ADC over +-``full_v`` whose parallel data line for bit ``bit`` is shorted high (``high``) or low: every
    code has that bit forced, so the reading is off by up to 2^bit codes in a square wave along the range."""

    def __init__(self, full_v, bit, high):
        self.full, self.lsb, self.mask, self.high = full_v, 2.0 * full_v / 65536.0, 1 << bit, high

    def forward(self, t_s, x, aux=None, state=None):
        code = np.clip(np.floor((np.asarray(x, dtype=float) + self.full) / self.lsb), 0, 65535).astype(np.int64)
        code = code | self.mask if self.high else code & ~self.mask
        return (code + 0.5) * self.lsb - self.full


class PeakHoldBouts(SimOnly):
    """A read-out whose PEAK key bounces: in each bout (``bouts``, (start, length) in seconds since the first sample)
    it streams the running maximum of the reading since the bout began instead of the reading."""

    def __init__(self, bouts):
        self.bouts = bouts

    def forward(self, t_s, x, aux=None, state=None):
        t, y = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float).copy()
        s = t - t[0]
        for at, length in self.bouts:
            sel = (s >= at) & (s < at + length)
            if sel.any():
                y[sel] = np.maximum.accumulate(y[sel])
        return y


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([4.0e4, 4.5e3]))))  # V / (N s)
        if shape == "choked_vent":
            rule = choked_vent_leak(phi * rng.uniform(1.2, 2.6), rng.uniform(1.0, 4.0), rng.uniform(0.25, 0.53))
        else:
            rule = drain_leak(phi * rng.uniform(1.6, 3.5), drain_head(rng))
        return Parts("zener", LeakingCore.of(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        comp = float(np.interp(m, [0, 1], [0.02, 0.24])) / g0  # of the instantaneous response, V / N
        if shape == "mandel_cryer_core":
            share = rng.uniform(0.2, 0.8)
            a = (comp, rng.uniform(1.0, 25.0), share, rng.uniform(0.04, 0.6 / (1.0 + 1.0 / share)))
            p.extra.append(lambda t, f, T, a=a: mandel_cryer(t, f, *a))
            return p
        a = (comp, rng.uniform(0.2, 2.0), comp * 4.0 / rng.uniform(2.0, 15.0))
        p.extra.append(lambda t, f, T, a=a: shunted_stack(t, f, *a))
        return p
    if effect == "hysteresis":
        width = float(np.interp(m, [0, 1], [0.01, 0.07]))
        sign = float(rng.choice([-1.0, 1.0]))
        if shape == "thermo_optic_cavity":
            p.after.append(ThermoOpticCavity(top, width, rng.uniform(2.2, 5.0), rng.uniform(0.18, 0.5),
                                             rng.uniform(0.06, 0.2), sign))
            return p
        p.after.append(AdhesiveAsperities(top, width, 80, rng.uniform(0.15, 0.5), rng.uniform(0.08, 0.25),
                                          rng.uniform(0.015, 0.07), sign, int(rng.integers(1 << 30))))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.008, 0.12]))))
        if shape == "echoing_fluid_line":
            r, rounding = rng.uniform(0.3, 0.8), rng.uniform(0.05, 0.2)
            p.after.append(EchoingLine(delay * (1.0 - rounding) * (1.0 - r) / (1.0 + r), r, delay * rounding))
            return p
        p.after.append(smoother_for(delay, rng.uniform(0.15, 0.5)))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.045, 0.2]))
        if shape == "optical_lever":
            p.after.append(StaticMap(optical_lever(rel, top, rng.uniform(-15.0, 25.0))))
            return p
        p.after.append(StaticMap(lc_tag(rel, top, rng.uniform(0.2, 3.0), bool(rng.random() < 0.6))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.034]) * rng.choice([-1, 1]))
        if shape == "slipping_joint":
            a = (k, rng.uniform(5.0, 30.0), rng.uniform(0.6, 3.0), rng.uniform(0.0, 0.6), rng.uniform(-0.5, 0.5))
            p.extra.append(lambda t, f, T, a=a: slipping_joint_zero(t, T, *a))
            return p
        a = (k, rng.uniform(0.3, 0.7), rng.uniform(0.5, 5.0), rng.uniform(100.0, 1000.0), rng.uniform(5.0, 30.0))
        p.extra.append(lambda t, f, T, a=a: viscous_magnet_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        tc = float(np.interp(m, [0, 1], [0.014, 0.036]))
        if shape == "negative_stiffness_magnets":
            per_c = rng.uniform(0.0011, 0.0013) if rng.random() < 0.6 else rng.uniform(0.0018, 0.002)  # NdFeB, ferrite
            p.after.append(NegativeStiffnessSpan(tc / (2.0 * per_c + tc), per_c, rng.uniform(5.0, 30.0)))
            return p
        share_of = rng.uniform(max(0.25, 9.0 * tc), 0.65)  # the bearings' share of the whole compliance
        way = float(rng.choice([-1.0, 1.0]))
        p.after.append(PreloadedBearingSpan(share_of / (1.0 - share_of), share_of / (3.0 * tc), way,
                                            rng.uniform(5.0, 30.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.1]) * rng.choice([-1, 1]))
        zero = sized(evaporating_drops(rng) if shape == "evaporating_drops" else photochromic_window(rng), size)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.03, 0.0042])) * rng.uniform(0.8, 1.2)
        if shape == "payne_mount":
            p.after.append(PayneMountMode(rng.uniform(14.0, 48.0), zeta, rng.uniform(0.15, 0.4), rng.uniform(0.2, 0.6),
                                          rng.uniform(0.5, 5.0), rng.uniform(0.5, 2.0)))
            return p
        p.after.append(MagnetSuspensionMode(rng.uniform(14.0, 48.0), zeta, rng.uniform(0.3, 0.7), rng.uniform(1.5, 5.0),
                                            float(rng.choice([-1.0, 1.0]))))
        return p
    if effect == "friction":
        band = float(np.interp(m, [0, 1], [0.0025, 0.044]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "bulging_core":
            a = (c, band, rng.uniform(0.2, 0.5))
            p.before.append(ForcePath(lambda t, x, a=a: bulging_core_band(*a, t, x)))
            return p
        heavy = band * rng.uniform(1.1, 1.5)
        a = (heavy * rng.uniform(0.3, 0.6), heavy, rng.uniform(0.2, 1.2))
        p.before.append(ForcePath(lambda t, x, a=a: telescoping_guide(x, *a)))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.16, 0.56])) * rng.uniform(1.2, 1.5)
        c = creeping(c)
        if shape == "defect_diffusion_clock":
            return Parts("burgers", DefectDiffusionClock(c, b, rng.uniform(25.0, 80.0), rng.uniform(5.0, 25.0)),
                         core_changed=True)
        return Parts("burgers", FrustratedDomainsClock(c, b, rng.uniform(1.0, 12.0), rng.uniform(0.25, 0.6),
                                                       rng.uniform(5.0, 25.0)), core_changed=True)
    if effect == "stuck_adc_bit":
        full = top * rng.uniform(1.2, 2.0)
        want = float(np.interp(m, [0, 1], [0.01, 0.09])) * rng.uniform(0.8, 1.2)
        bit = int(np.clip(round(math.log2(want / (2.0 * full / 65536.0))), 3, 14))
        p.outer.append(StuckDataBit(full, bit, bool(rng.random() < 0.5)))
        return p
    if effect == "peak_hold_bouts":
        count = int(rng.integers(2, 4)) + int(round(2.0 * m))
        bouts = [(rng.uniform(10.0, DURATION_S - 30.0), rng.uniform(3.0, 25.0) * (0.5 + m)) for _ in range(count)]
        p.outer.append(PeakHoldBouts(bouts))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["choked_vent", "drain_head"],
    "delayed_elasticity": ["mandel_cryer_core", "shunted_piezo_stack"],
    "hysteresis": ["thermo_optic_cavity", "adhesive_asperities"],
    "sensor_lag": ["echoing_fluid_line", "fixed_lag_smoother"],
    "nonlinear_gain": ["optical_lever", "lc_tag"],
    "thermal_drift": ["slipping_joint", "magnetic_viscosity"],
    "thermal_sensitivity": ["negative_stiffness_magnets", "preloaded_bearings"],
    "offset_drift": ["evaporating_drops", "photochromic_window"],
    "resonance": ["payne_mount", "magnetic_suspension"],
    "friction": ["bulging_core", "telescoping_guide"],
    "thermo_rheological": ["defect_diffusion_clock", "frustrated_domains_clock"],
}
PAIRS = (("viscous_flow", "offset_drift"), ("delayed_elasticity", "sensor_lag"), ("hysteresis", "thermal_sensitivity"),
         ("nonlinear_gain", "friction"), ("resonance", "thermal_drift"), ("thermo_rheological", "hysteresis"))
OUTSIDE = ("stuck_adc_bit", "peak_hold_bouts")
RATES = (255.0, 415.0, 1150.0, 1450.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split AC", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.86),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=greenhouse,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(0.85e-3, 2.55e-3), jitter=0.31,
                   gap_s=(0.15, 2.5))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
