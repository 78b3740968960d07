"""Independent split AA for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split AA is an untouched held-out set: written blind to the engine it measures (to how it detects and fits anything),
run once, and nothing is ever chosen from it. Every name of the catalogue is hidden in two shapes that neither the
registry's families (``polyforce_ros/sim/truths.py``) nor splits A to Z use:

* a core leaking through a hydrophobic porous plug whose pores let the fluid through only once the force has passed
  their capillary entry force (entry forces spread log-normally, median 1.5-4.5 N, log spread 0.25-0.7; a wetted pore
  stays wetted, so the leak is 1.5-3 times the plain fluidity of 1/36000-1/5000 V/(N s) times the share of pores that
  the largest force so far has opened), or a core whose flow layer crystallises under stress (a crystallisation
  clock that runs only above 1.5-4 N, in proportion to the excess, one unit per 40-300 s at twice that force; Avrami's
  1 - exp(-clock^n), n 1.5-3; the crystals block 50-85 % of a fluidity 1.5-3 times the plain one and never melt);
  neither ever recovers;
* a Kelvin unit whose spring is a carbon-black filled rubber (the Payne effect after Kraus: its stiffness falls 1.6-3.2
  fold with the force travelled over the last 20-120 s, half-way at 15-80 N of travel, exponent 1-1.6; 0.5-6 s at
  rest, slower as it softens), or a Kelvin unit whose dashpot hangs on a slack link (a loose pin in its clevis: a change
  of force within what 0.4-2 N gives reaches the spring at once, only the rest creeps, 1-15 s); 2.5-22 % of the
  instantaneous response (the filled rubber's a quarter of the way into its softening, on a log scale);
* a woven polyester strap in the force path whose yarns slide on each other (rate-independent branches that depart
  from the chord between two reversals as a sine arch, its height a power 0.3-0.9 of the excursion, Madelung's
  return-point memory: Lapshin's harmonic loops, 1.5-5 % of the range wide for a cycle to three quarters of it), or
  an inductive read-out whose iron-cobalt pole piece has an air gap (its particles switch as 200 elementary Preisach
  loops, coercivities log-normal about 4-15 % of the range, log spread 0.3-0.7, centres spread by 12-30 % of it about
  mid-range, all in the drive less the gap's demagnetising field, 0.3-1.5 times the pole's mean state, which shears
  the loops; the firmware linearises the mean curve of two full-range cycles made before use; loops of 1.2-6.5 % of
  the range);
* a magnetic read-out whose flux closes through a solid steel yoke (eddy currents in a slab: tanh(sqrt(s tau)) /
  sqrt(s tau), a sum of forty first-order lags), or an optical read-out through a logarithmic amplifier whose output
  is low-passed by an RC before the firmware takes its antilog (the photocurrent biased by 5-40 % of the range: slower
  rises than falls); 10-110 ms of mean delay;
* an intensity read-out through a loop of fibre whose bend the load tightens (a macrobend loss exponential in the
  bend, so the light lost is exp(-L0) - exp(-L0 exp(k x)), L0 0.05-0.6: expansive, then compressive), or a lever that
  turns a diametric magnet over a two-axis Hall sensor mounted off the shaft (60-150 degrees of turn from 0-40
  degrees, read as atan2 of axes whose amplitudes differ, either way, with a quadrature error of up to 6 degrees); 5-19
  % at the top of the range;
* a capacitive read-out whose reference capacitor is a Y5V ceramic (its capacitance peaked 3-15 degC below the
  reference, falling away as a Lorentzian 12-30 degC wide above the peak and 25-50 degC wide below it; lag 8-45 s), or
  gauges bonded with an adhesive near its glass transition whose volume recovers toward the temperature with a
  structural relaxation after Tool, Narayanaswamy and Moynihan (15-50 % of the slope glassy and at once, the rest
  through the fictive temperature, 20-200 s at the reference, 0.25-0.6 e-folds faster per degC, a nonlinearity of
  0.3-0.6; lag 5-30 s); 0.007-0.032 V/degC at the reference;
* an optical read-out lit by a phosphor whose luminescence quenches thermally (Mott and Seitz: 1 / (1 + C exp(-E /
  kT)), half quenched 2.8-14 degC above the reference, the reference on the flat side; lag 5-30 s), or an optical lever
  read by a bi-cell photodiode whose spot the lens mount's expansion defocuses (the span as the inverse of the Gaussian
  beam's width, sqrt(1 + u^2), the reference 0.35-2.2 Rayleigh lengths to either side of the focus; lag 10-40 s);
  1.6-3.4 %/degC at the reference;
* the zero of gauges bonded with an epoxy that takes up water from a humidified enclosure the sensor went into 0-300
  s before the first sample (Carter and Kibler's two-phase uptake: Fickian diffusion of mobile water, L^2 / D 150-1200
  s, and its binding over 200-1500 s to 0.5-2 times as much bound water), or of a fluid-filled read-out line
  connected to an infusion bag (the head falls as the bag drains, the bag's level as its content to the power
  0.35-0.8; 1-3 changes of the roller clamp, a new bag hung from time to time, the drip stand moved up or down in half
  the records); 18-95 mV at most;
* a needle holder's mode (14-48 Hz) with a nonlinear energy sink (a 2-8 % mass on an essentially cubic spring, engaged
  at what 0.1-0.5 N gives, its damping ratio 0.05-0.2: knocks above it are drained into the sink, smaller ones ring
  on), or a holder on a spindle's rolling bearing whose stiffness varies by 6-20 % as the balls pass (2-12 Hz) while
  the spindle turns (bouts of 3-25 s, 5-40 s apart); damping ratio 0.0044-0.034, the mean frequency fixed;
* a Coulomb band of 0.3-4.1 % of the range, the same at every load and always: a needle feed whose carriage a
  spring-loaded pawl holds over a finely toothed rack (Prandtl and Tomlinson: the passed force hops from tooth to
  tooth, a stickiness 2 pi b / pitch of 1.6-4.5), or a needle drawn through the felt wiper of a guide (the stuck force
  released in avalanches whose sizes follow a truncated power law, 3 % to 30-70 % of the band, exponent 0.8-1.6);
* a core (soft enough for its clock to show) whose clock follows the parabolic law of dynamic facilitation (Elmatad,
  Garrahan and Chandler: log tau as J^2 (1 / T - 1 / T_o)^2, the onset T_o 8-35 degC above the reference, constant
  above it), or Adam and Gibbs's law with the configurational entropy of a constant excess heat capacity (log tau as C
  / (T ln(T / T_K)), T_K 40-110 degC below the reference); 1.2-1.5 times 0.18-0.52 per degC at the reference, lag 5-25
  s.

It also holds six pairs, two effects outside the catalogue (a carrier read-out whose demodulator's phase-locked loop
relocks 180 degrees out after a carrier dropout, inverting the whole reading for 3-6 bouts of 2.4-14 s; a DAQ whose
DMA ring buffer of 0.5-4 s is read in blocks of 16-64 samples, the first 1-3 samples of 6-12 % of the blocks coming
from the buffer's previous lap) and four clean records. Profiles: a needle robot under an admittance controller that
slows as the force rises (the measured Okamura insertion, ``../shared/data``, ``time_force.csv``, replayed at 0.9-2.4
times its speed at no force and slower by 1 + (F / F_a)^q above it, F_a 1.2-4 N, q 1-2.2, scaled to a 2.2-8.8 N peak;
held while the liver relaxes, withdrawn; a train of synthetic punctures when the data are absent); an assembly
robot's peg-in-hole insertions (contact, a spiral search that ripples the force, the drop into the hole, the chamfer,
a jam and its wiggle in a third of them, the sliding fit, a snap-fit press); and a robot finger playing the piano
(scales, repeated notes, chords and two-note figures, each keystroke a key dip, a key-bed contact through its felt
that follows the dynamics and a sustained press). Rates 135, 265, 455 and 735 Hz (a mode at 1000 Hz with knocks that
excite it), 0.9-2.5 mV noise, stamp jitter, gaps, and a sensor on a robot working in a laboratory fume hood: the room
recovering from its night setback under a cycling thermostat, cool air drawn in while the sash is raised, a hot plate
switched on and the arm reaching over it.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size against its
noise without diagnosing (for a leak on a Zener base, against that bare Zener core).

    .venv/bin/python bench/independent_split_aa.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, optimize, signal
from scipy.special import ndtr

from independent_split import puncture_train
from polyforce_ros.physics.viscoelastic import Burgers
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (coarse_force, cutter, ease, fit_departure, follow, LeakingCore, on_clock, Parts, ShapeSplit,
                       GridMode, SimOnly, sized as sized_over, temp_of, uniform_grid)

SEED0 = 1_900_000  # never a seed of the registry's splits nor of splits A (90000..) to Z (1800000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 460.0
HORIZON_S = DURATION_S + 60.0  # what a schedule drawn before the record covers (the record plus its gaps' slack)

sized = functools.partial(sized_over, horizon_s=HORIZON_S)


# ----------------------------------------------------------------------------- small tools

def okamura_unit(rate_hz):
    """The measured Okamura insertion (``../shared/data``, ``time_force.csv``) at ``rate_hz``, its peak 1, without
    padding and never below zero; None when the data are absent."""
    try:
        tp, fp = profiles.okamura_insertion(peak_n=1.0, rate_hz=rate_hz, pre_s=0.0, post_s=0.0)
    except FileNotFoundError:
        return None
    return tp - tp[0], np.clip(fp, 0.0, None)


# ----------------------------------------------------------------------------- profiles and temperature

def admittance_okamura(duration_s, rate_hz, rng):
    """A needle robot under an admittance controller that slows as the force rises: the measured Okamura insertion
    scaled to a 2.2-8.8 N peak and replayed at v0 / (1 + (F / F_a)^q) times its speed (v0 0.9-2.4, F_a 1.2-4 N,
    q 1-2.2: the punctures come late and the force peaks are drawn out); held 0.5-3 s while the liver relaxes to
    55-85 % of the last force (with 0.4-2 s); withdrawn over 0.3-1.5 s; 3-25 s to the next site. A train of synthetic
    punctures when the data are absent."""
    unit = okamura_unit(rate_hz)
    if unit is None:
        return puncture_train(duration_s, rate_hz, rng)
    tp, fp = unit
    h = 1.0 / rate_hz
    t = np.arange(0.0, duration_s, h)
    f = np.zeros_like(t)
    cut = cutter(t)
    cursor = rng.uniform(2.0, 7.0)
    while cursor < duration_s - 8.0:
        peak, v0, f_a, q = rng.uniform(2.2, 8.8), rng.uniform(0.9, 2.4), rng.uniform(1.2, 4.0), rng.uniform(1.0, 2.2)
        fs = peak * fp
        clock = np.concatenate([[0.0], np.cumsum((1.0 + (fs[:-1] / f_a) ** q) / v0) * h])  # robot time of data time
        length = float(clock[-1])
        seg, s = cut(cursor, length)
        f[seg] = np.interp(s, clock, fs)
        cursor += length
        last = float(fs[-1])
        hold, keep, relax = rng.uniform(0.5, 3.0), rng.uniform(0.55, 0.85), rng.uniform(0.4, 2.0)
        seg, s = cut(cursor, hold)
        f[seg] = last * (keep + (1.0 - keep) * np.exp(-s / relax))
        cursor += hold
        held = last * (keep + (1.0 - keep) * math.exp(-hold / relax))
        out = rng.uniform(0.3, 1.5)
        seg, s = cut(cursor, out)
        f[seg] = held * (1.0 - ease(s / out))
        cursor += out + rng.uniform(3.0, 25.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def peg_in_hole(duration_s, rate_hz, rng):
    """An assembly robot inserting pegs: contact at 1-3 N reached in 0.2-0.8 s; a spiral search of 1.5-7 s (the force
    rippling at the spiral's 0.6-2 revolutions per second, by up to 0.08-0.35 N as its radius grows); the drop into the
    hole (to 10-40 % within 30-80 ms); the chamfer (a bump of 2-5 N over 0.15-0.5 s); in a third of the pegs a jam (the
    force climbing to 5-8.8 N over 0.3-1 s, wiggled by 0.2-0.6 N at 3-6 Hz for 0.5-2 s, freed within 40 ms); the
    sliding fit (0.4-1 N rising to 0.8-2 N over 0.5-2.5 s); a snap-fit press to 4-8.8 N (a click that loses 30-50 %
    within 20 ms and regains half of it), held 0.3-1.5 s and released over 0.2-0.6 s; 3-12 s to the next peg."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cut = cutter(t)

    def go(cursor, length, start, end, shape=ease):
        seg, s = cut(cursor, length)
        f[seg] = start + (end - start) * shape(s / length)
        return cursor + length

    cursor = rng.uniform(1.0, 5.0)
    while cursor < duration_s - 12.0:
        contact = rng.uniform(1.0, 3.0)
        cursor = go(cursor, rng.uniform(0.2, 0.8), 0.0, contact)
        search, rev, ripple = rng.uniform(1.5, 7.0), rng.uniform(0.6, 2.0), rng.uniform(0.08, 0.35)
        seg, s = cut(cursor, search)
        f[seg] = contact + ripple * np.sqrt(s / search) * np.sin(2.0 * np.pi * rev * s)
        cursor += search
        end = contact + ripple * math.sin(2.0 * math.pi * rev * search)
        dropped = contact * rng.uniform(0.1, 0.4)
        cursor = go(cursor, rng.uniform(0.03, 0.08), end, dropped)
        bump, width = rng.uniform(2.0, 5.0), rng.uniform(0.15, 0.5)
        seg, s = cut(cursor, width)
        f[seg] = dropped + bump * np.sin(np.pi * s / width) ** 2
        cursor += width
        slide0, slide1 = rng.uniform(0.4, 1.0), rng.uniform(0.8, 2.0)
        cursor = go(cursor, 0.05, dropped, slide0)
        if rng.random() < 1.0 / 3.0:
            jam = rng.uniform(5.0, 8.8)
            cursor = go(cursor, rng.uniform(0.3, 1.0), slide0, jam)
            wig, amp, hz = rng.uniform(0.5, 2.0), rng.uniform(0.2, 0.6), rng.uniform(3.0, 6.0)
            seg, s = cut(cursor, wig)
            f[seg] = jam - amp * np.sin(np.pi * hz * s) ** 2
            cursor += wig
            cursor = go(cursor, 0.04, jam - amp * math.sin(math.pi * hz * wig) ** 2, slide0)
        cursor = go(cursor, rng.uniform(0.5, 2.5), slide0, slide1, shape=lambda u: np.clip(u, 0.0, 1.0))
        press = rng.uniform(4.0, 8.8)
        cursor = go(cursor, rng.uniform(0.2, 0.6), slide1, press)
        click = press * (1.0 - rng.uniform(0.3, 0.5))
        cursor = go(cursor, 0.02, press, click)
        back = 0.5 * (press + click)
        cursor = go(cursor, 0.1, click, back)
        hold = rng.uniform(0.3, 1.5)
        seg, _ = cut(cursor, hold)
        f[seg] = back
        cursor += hold
        cursor = go(cursor, rng.uniform(0.2, 0.6), back, 0.0)
        cursor += rng.uniform(3.0, 12.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def piano_keystrokes(duration_s, rate_hz, rng):
    """A robot finger playing the piano in phrases (scales of 6-16 notes 0.25-0.5 s apart, 4-12 repeated notes
    0.25-0.45 s apart, 2-6 chords held 0.8-3 s, two-note figures of 2-6 s at 2-4 Hz in which the finger plays every
    other note), each phrase swelling or fading by 0.6-1.4 times its dynamic of 0.3-1; a keystroke is the key's dip
    (0.4-0.8 N over 60-150 ms, faster when louder), the key-bed contact through its felt (a sine-squared pulse of
    0.2-0.8 N times the dynamic over 60-120 ms, the press of 0.5-2.5 N times 0.5 more than the dynamic, 1.4 times that in
    chords, rising over 0.15-0.3 s) that relaxes by 10-30 % (with 0.5-2 s) while the note is held, and the release in 60-120 ms,
    all shortened when needed so that the key is back up before the next note; each note's spacing stretched or
    shortened by up to 15 % (rubato); 1.5-8 s between phrases."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cut = cutter(t)

    def key(cursor, loud, hold, gap, extra=1.0):
        weight, dip = rng.uniform(0.4, 0.8), 0.15 - 0.09 * loud
        width, strike = rng.uniform(0.06, 0.12), loud * rng.uniform(0.2, 0.8)
        rise, release = rng.uniform(0.15, 0.3), rng.uniform(0.06, 0.12)
        room = 0.9 * gap  # the key is back up before the next note
        squeeze = min(1.0, room / (dip + rise + release + 0.02))
        dip, width, rise, release = dip * squeeze, width * squeeze, rise * squeeze, release * squeeze
        seg, s = cut(cursor, dip)
        f[seg] = weight * ease(s / dip)
        cursor += dip
        press = extra * rng.uniform(0.5, 2.5) * (0.5 + loud)
        seg, s = cut(cursor, rise)
        f[seg] = weight + press * ease(s / rise) + strike * np.sin(np.pi * np.minimum(s / width, 1.0)) ** 2
        cursor += rise
        width = rise
        relax, lose = rng.uniform(0.5, 2.0), rng.uniform(0.1, 0.3)
        sustain = min(max(hold - dip - width, 0.02), room - dip - width - release)
        seg, s = cut(cursor, sustain)
        f[seg] = weight + press * (1.0 - lose * -np.expm1(-s / relax))
        cursor += sustain
        last = weight + press * (1.0 - lose * -math.expm1(-sustain / relax))
        seg, s = cut(cursor, release)
        f[seg] = last * (1.0 - ease(s / release))
        return cursor + release

    cursor = rng.uniform(1.0, 4.0)
    while cursor < duration_s - 10.0:
        kind = rng.integers(4)
        level, swell = rng.uniform(0.3, 1.0), rng.uniform(0.6, 1.4)
        if kind == 0:
            notes, gap = int(rng.integers(6, 17)), rng.uniform(0.25, 0.5)
            plan = [(gap, 0.7 * gap, 1.0)] * notes
        elif kind == 1:
            notes, gap = int(rng.integers(4, 13)), rng.uniform(0.25, 0.45)
            plan = [(gap, 0.6 * gap, 1.0)] * notes
        elif kind == 2:
            plan = []
            for _ in range(int(rng.integers(2, 7))):
                hold = rng.uniform(0.8, 3.0)
                plan.append((hold + rng.uniform(0.2, 0.6), hold, 1.4))
        else:
            rate = rng.uniform(2.0, 4.0)
            notes = max(2, int(rng.uniform(2.0, 6.0) * rate / 2.0))
            plan = [(2.0 / rate, 0.8 / rate, 1.0)] * notes
        for j, (gap, hold, extra) in enumerate(plan):
            loud = float(np.clip(level * (1.0 + (swell - 1.0) * j / max(len(plan) - 1, 1)), 0.1, 1.0))
            gap *= rng.uniform(0.85, 1.15)  # the phrase's rubato
            key(cursor, loud, min(hold, 0.9 * gap), gap, extra)
            cursor += gap
        cursor += rng.uniform(1.5, 8.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (admittance_okamura, peg_in_hole, piano_keystrokes)


def fume_hood(t, rng, step_s=0.5):
    """A sensor on a robot working in a laboratory fume hood, from 600 s before the record: the room recovers from
    its night setback (2-4.5 degC below the reference, toward -0.5 to +1.5 degC of it with 400-1200 s) under a
    thermostat that swings it by 0.2-0.5 degC with a period of 300-900 s; the sash is raised 2-5 times for 20-150 s,
    the hood then drawing in corridor air 0.8-2.5 degC cooler (with 15-40 s, recovering with 30-90 s); a hot plate
    switched on 200 s before to 60 % into the record warms the hood's air by 1-3 degC (with 60-200 s), and while the
    arm reaches over it (10-50 s, every 30-120 s) by 0.5-2 degC more (with 5-15 s). The sensor follows with 8-25 s
    (exact per step of ``step_s``)."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-600.0, d + 2.0 * step_s, step_s)
    room = T_REF_C - rng.uniform(2.0, 4.5)
    target, recover = T_REF_C + rng.uniform(-0.5, 1.5), rng.uniform(400.0, 1200.0)
    swing, period, phase = rng.uniform(0.2, 0.5), rng.uniform(300.0, 900.0), rng.uniform(0.0, 6.3)
    sash = np.zeros(grid.size, dtype=bool)
    for _ in range(int(rng.integers(2, 6))):
        at = rng.uniform(-300.0, d)
        sash |= (grid >= at) & (grid < at + rng.uniform(20.0, 150.0))
    draw, draw_in, draw_out = rng.uniform(0.8, 2.5), rng.uniform(15.0, 40.0), rng.uniform(30.0, 90.0)
    plate_on, plate, plate_tau = rng.uniform(-200.0, 0.6 * d), rng.uniform(1.0, 3.0), rng.uniform(60.0, 200.0)
    reach, reach_tau = rng.uniform(0.5, 2.0), rng.uniform(5.0, 15.0)
    near = np.zeros(grid.size, dtype=bool)
    at = plate_on + rng.uniform(10.0, 60.0)
    while at < d:
        length = rng.uniform(10.0, 50.0)
        near |= (grid >= at) & (grid < at + length)
        at += length + rng.uniform(30.0, 120.0)
    air = np.empty(grid.size)
    cool, warm, close = 0.0, 0.0, 0.0
    for i, g in enumerate(grid.tolist()):
        room = target + (room - target) * math.exp(-step_s / recover)
        goal = -draw if sash[i] else 0.0
        cool = goal + (cool - goal) * math.exp(-step_s / (draw_in if sash[i] else draw_out))
        on = g >= plate_on
        warm = (plate if on else 0.0) + (warm - (plate if on else 0.0)) * math.exp(-step_s / plate_tau)
        goal = reach if (on and near[i]) else 0.0
        close = goal + (close - goal) * math.exp(-step_s / reach_tau)
        air[i] = room + swing * math.sin(2.0 * math.pi * g / period + phase) + cool + warm + close
    keep = math.exp(-step_s / rng.uniform(8.0, 25.0))
    sensor, _ = signal.lfilter([1.0 - keep], [1.0, -keep], air, zi=[keep * air[0]])
    return np.interp(s, grid, sensor)


# ----------------------------------------------------------------------------- viscous flow

def breakthrough_plug(full_fluidity, median_n, spread):
    """x' = A W(max F) F: a core leaking through a hydrophobic porous plug whose pores pass fluid only once the force
    has exceeded their capillary entry force, log-normal about ``median_n`` with a log spread ``spread``; a wetted pore
    stays wetted, so the share W of open pores follows the largest force so far and A = ``full_fluidity`` is the leak
    with every pore open. It never recovers."""
    def rule(t, f):
        load = np.maximum(f, 0.0)
        wet = ndtr(np.log(np.maximum(np.maximum.accumulate(load), 1e-9) / median_n) / spread)
        return integrate.cumulative_trapezoid(full_fluidity * wet * load, t, initial=0.0)
    return rule


def crystallising_flow(fluidity, onset_n, clock_s, avrami, block):
    """x' = A (1 - b X) F: a core whose flow layer crystallises under stress. A crystallisation clock runs only above
    ``onset_n``, in proportion to the excess (one unit per ``clock_s`` at twice that force); the crystalline share
    follows Avrami, X = 1 - exp(-clock^n), n = ``avrami``; the crystals block ``block`` of the fluidity A =
    ``fluidity`` and never melt. It never recovers."""
    def rule(t, f):
        load = np.maximum(f, 0.0)
        clock = integrate.cumulative_trapezoid(np.maximum(load / onset_n - 1.0, 0.0) / clock_s, t, initial=0.0)
        crystal = -np.expm1(-clock ** avrami)
        return integrate.cumulative_trapezoid(fluidity * (1.0 - block * crystal) * load, t, initial=0.0)
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def payne_kelvin(t, f, compliance_v_per_n, tau_s, softening, travel_n, memory_s, exponent, step_s=0.005):
    """A Kelvin unit in series with the core whose spring is a carbon-black filled rubber: its filler network breaks
    with the deformation it is put through and re-forms at rest (the Payne effect, Kraus's form), so its stiffness,
    relative to the rested one, is 1 / s + (1 - 1 / s) / (1 + (A / A_c)^(2 m)), s = ``softening``, A the force
    travelled over the last ``memory_s`` (an exponential memory), A_c = ``travel_n``, m = ``exponent``. The dashpot
    stays as it is: the softer spring creeps further and more slowly. C = ``compliance_v_per_n`` and tau =
    ``tau_s`` at rest; exact exponential steps of ``step_s`` at the present stiffness, from rest."""
    grid, fg = coarse_force(t, f, step_s)
    keep = math.exp(-step_s / memory_s)
    u, travel, prev = 0.0, 0.0, float(fg[0])
    floor, power = 1.0 / softening, 2.0 * exponent
    out = np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        out[i] = u
        travel = travel * keep + abs(fi - prev)
        prev = fi
        g = floor + (1.0 - floor) / (1.0 + (travel / travel_n) ** power)
        goal = compliance_v_per_n * fi / g
        u = goal + (u - goal) * math.exp(-step_s * g / tau_s)
    return np.interp(t, grid, out)


def slack_link_kelvin(t, f, compliance_v_per_n, tau_s, slack_v, step_s=0.005):
    """A Kelvin unit in series with the core whose dashpot hangs on a slack link (a loose pin in its clevis): within
    +-``slack_v`` of the dashpot's place the spring takes the force at once; beyond it the link is taut and the dashpot
    drags (tau = ``tau_s``) until the spring is within the slack of its goal C F again (C = ``compliance_v_per_n``).
    Small changes of force do not creep, large ones creep by what exceeds the slack; at rest the unit always reaches
    C F. Exact exponential steps of ``step_s``, from rest."""
    grid, fg = coarse_force(t, f, step_s)
    decay = math.exp(-step_s / tau_s)
    place = compliance_v_per_n * float(fg[0])
    out = np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        goal = compliance_v_per_n * fi
        if goal - place > slack_v:
            place = goal - slack_v + (place - goal + slack_v) * decay
        elif goal - place < -slack_v:
            place = goal + slack_v + (place - goal - slack_v) * decay
        out[i] = min(max(goal, place - slack_v), place + slack_v)
    return np.interp(t, grid, out)


# ----------------------------------------------------------------------------- hysteresis

def arch_branches(f, amp, exponent, lo, hi):
    """Rate-independent loops whose branches depart from the chord between two reversal points as a sine arch (an
    arch of ``amp`` times the span between them to the power ``exponent``, below the chord while the input rises and
    above it while it falls) with Madelung's rules: a branch aims at the reversal point it started from, and once the
    input passes that point the inner loop is wiped out and the branch it interrupted resumes. Sentinels ``lo`` and
    ``hi`` bound the input; the first branch runs from ``lo`` toward ``hi``. Returns the deviation from the input."""
    f = np.asarray(f, dtype=float)
    at, dev = [hi, lo], [0.0, 0.0]
    way = 1.0

    def branch(x):
        fs, ds, ft, dt = at[-1], dev[-1], at[-2], dev[-2]
        span = ft - fs
        if abs(span) < 1e-12:
            return ds
        u = (x - fs) / span
        return ds + (dt - ds) * u - way * amp * abs(span) ** exponent * math.sin(math.pi * u)

    out = np.empty_like(f)
    prev = float(f[0])
    for i, x in enumerate(f.tolist()):
        if (x - prev) * way < 0.0:
            at.append(prev)
            dev.append(branch(prev))
            way = -way
        while len(at) > 2 and (x - at[-2]) * way > 0.0:
            del at[-2:]
            del dev[-2:]
        out[i] = branch(x)
        prev = x
    return out


class WovenStrap(SimOnly):
    """A woven polyester strap in the force path (a sling holding the needle holder) whose yarns slide on each other:
    the force it passes is the force plus :func:`arch_branches` (Lapshin's harmonic loops), scaled so that a cycle to
    three quarters of the range is ``width_n`` wide half-way up it. Rate-independent, on the force before the core."""

    def __init__(self, width_n, exponent):
        self.exponent = exponent
        self.lo, self.hi = -1e-6, 1.25 * FORCE_MAX_N
        reach = 0.75 * FORCE_MAX_N
        probe = np.concatenate([np.linspace(0.0, reach, 901), np.linspace(reach, 0.0, 901)[1:]])
        d = arch_branches(probe, 1.0, exponent, self.lo, self.hi)
        width = abs(d[450] - d[1350])
        self.amp = width_n / max(width, 1e-12)

    def forward(self, t_s, x, aux=None, state=None):
        f = np.asarray(x, dtype=float)
        lo, hi = min(self.lo, float(f.min()) - 1e-6), max(self.hi, float(f.max()) + 1e-6)
        return f + arch_branches(f, self.amp, self.exponent, lo, hi)


class GappedPolePreisach(SimOnly):
    """An inductive (variable-reluctance) read-out whose iron-cobalt pole piece has an air gap: the pole piece's
    particles switch as elementary rectangular loops (Preisach: ``count`` of them, coercivities log-normal about
    ``coercive`` of the range with a log spread ``spread``, at least 2 %, centres spread normally by ``centre_sd``
    about mid-range) in the drive u = x / ``top`` less the gap's demagnetising field, ``shear`` times the pole's mean
    state, which shears the loops. The reading is x plus ``sign`` k top times the state less its mean curve (the
    firmware linearised that after two full-range cycles made before use), k set for a loop of ``width`` of the range
    half-way up such a cycle. Rate-independent, with return-point memory; each sample's field is solved with the
    feedback (the particles switched in the order of their thresholds while the field still reaches them)."""

    def __init__(self, top, width, coercive, spread, centre_sd, shear, sign, seed, count=200):
        rng = np.random.default_rng(seed)
        half = np.maximum(coercive * np.exp(spread * rng.standard_normal(count)), 0.02)
        centre = 0.5 + centre_sd * rng.standard_normal(count)
        self.up, self.down = centre + half, centre - half
        self.top, self.shear, self.sign = top, shear, sign
        cycle = np.concatenate([np.linspace(0.0, 1.0, 1001), np.linspace(1.0, 0.0, 1001)[1:]])
        _, start = self._run(np.concatenate([cycle, cycle]), (-np.ones(count), -math.inf))
        m, _ = self._run(cycle, (start[0].copy(), start[1]))
        self.start = start
        up, down = m[:1001], m[1000:][::-1]
        self.grid, self.mean = np.linspace(0.0, 1.0, 1001), 0.5 * (up + down)
        self.k = width / max(abs(float(down[500] - up[500])), 1e-12)

    def _run(self, u, start):
        """The mean state per sample of the drive ``u`` from ``start`` = (states, last drive); returns it and the
        state at the end."""
        up, down, shear = self.up, self.down, self.shear
        state, last = start
        step = 2.0 / state.size
        level = float(state.mean())
        out = np.empty(u.size)
        for i, x in enumerate(u.tolist()):
            if x > last:
                cand = np.flatnonzero((state < 0.0) & (up <= x - shear * level))
                for k in cand[np.argsort(up[cand])].tolist():
                    if up[k] > x - shear * level:
                        break
                    state[k] = 1.0
                    level += step
            elif x < last:
                cand = np.flatnonzero((state > 0.0) & (down >= x - shear * level))
                for k in cand[np.argsort(-down[cand])].tolist():
                    if down[k] < x - shear * level:
                        break
                    state[k] = -1.0
                    level -= step
            last = x
            out[i] = level
        return out, (state, last)

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        u = x / self.top
        m, _ = self._run(u, (self.start[0].copy(), self.start[1]))
        return x + self.sign * self.k * self.top * (m - np.interp(u, self.grid, self.mean))


# ----------------------------------------------------------------------------- sensor lag

class EddyYoke(SimOnly):
    """A magnetic read-out whose flux closes through a solid steel yoke: eddy currents let the field into the slab by
    diffusion, and the flux it carries follows as tanh(sqrt(s tau)) / sqrt(s tau) = sum 2 / (s tau + ((2k + 1) pi /
    2)^2) (tau three times the mean delay ``delay_s``): forty first-order lags (the rest passes at once), exact
    per step on a uniform grid at the median step, from rest."""

    def __init__(self, delay_s, terms=40):
        tau = 3.0 * delay_s
        lam = ((2.0 * np.arange(terms) + 1.0) * math.pi / 2.0) ** 2
        self.taus, self.weights = tau / lam, 2.0 / lam
        self.direct = 1.0 - float(self.weights.sum())

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        z = xu - x[0]
        y = self.direct * z
        for tau, w in zip(self.taus.tolist(), self.weights.tolist()):
            keep = math.exp(-h / tau)
            y = y + w * signal.lfilter([1.0 - keep], [1.0, -keep], z)
        return np.interp(t, tu, y) + x[0]


class LogAmpRc(SimOnly):
    """An optical read-out whose photocurrent (the signal plus a bias ``bias_v`` of dark and background light) is
    logged by a transdiode amplifier, low-passed by an RC of ``delay_s`` and antilogged by the firmware: a lag of
    ``delay_s`` on the logarithm, so a rise is slower than a fall of the same size. On a uniform grid, from rest."""

    def __init__(self, delay_s, bias_v):
        self.tau, self.bias = delay_s, bias_v

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        lx = np.log(np.maximum(xu + self.bias, 1e-3 * self.bias))
        keep = math.exp(-h / self.tau)
        y, _ = signal.lfilter([1.0 - keep], [1.0, -keep], lx, zi=[keep * lx[0]])
        return np.interp(t, tu, np.exp(y) - self.bias)


# ----------------------------------------------------------------------------- nonlinear gain

def macrobend_loop(rel, reach, base_loss):
    """x read as the light a loop of fibre loses as the load tightens its bend: the macrobend loss (in nepers) grows
    exponentially as the bend radius shrinks, L = L0 exp(k x), L0 = ``base_loss``, and the read-out takes the light
    lost, exp(-L0) - exp(-L), scaled to slope 1 at no load: expansive while the loss is small, compressive as the light
    runs out; k set for a departure of ``rel`` at ``reach`` (the loss at most 6 nepers there)."""
    e0 = math.exp(-base_loss)

    def read(x, k):
        z = np.clip(k * np.asarray(x, dtype=float), -6.0, 8.0)
        return (e0 - np.exp(-base_loss * np.exp(z))) / (base_loss * e0 * k)
    return fit_departure(read, rel, reach, math.log(6.0 / base_loss) / reach)


def off_shaft_angle(rel, reach, start, sweep, quadrature, sign):
    """x read through a lever that turns a diametric magnet over a two-axis Hall sensor mounted off its shaft: the
    magnet turns from ``start`` by ``sweep`` (rad) over ``reach``, the axes read (a sin theta, cos(theta +
    ``quadrature``)) with a = 1 + ``sign`` delta (their amplitudes apart), the firmware takes atan2 of them, scaled to
    slope 1 at no load; delta set for a departure of ``rel`` at ``reach`` (at most 0.6)."""
    def angle(theta, delta):
        raw = np.arctan2((1.0 + sign * delta) * np.sin(theta), np.cos(theta + quadrature))
        return theta + np.mod(raw - theta + math.pi, 2.0 * math.pi) - math.pi

    def read(x, delta):
        theta = start + sweep * np.asarray(x, dtype=float) / reach
        a0 = float(angle(np.array([start]), delta)[0])
        slope = float((angle(np.array([start + 1e-6]), delta)[0] - angle(np.array([start - 1e-6]), delta)[0]) / 2e-6)
        return (angle(theta, delta) - a0) / (slope * sweep / reach)
    return fit_departure(read, rel, reach, 0.6)


# ----------------------------------------------------------------------------- thermal drift

def y5v_reference_zero(t, temp, k_v_per_c, below_c, wide_below_c, wide_above_c, lag_s):
    """The zero of a capacitive half-bridge read-out whose reference capacitor is a Y5V ceramic (lag ``lag_s``): its
    capacitance peaks ``below_c`` below the reference and falls away as a Lorentzian, ``wide_above_c`` wide above the
    peak and ``wide_below_c`` below it; the zero is A (C(T) / C(T_ref) - 1), A set for ``k_v_per_c`` at the
    reference (either sign)."""
    peak = T_REF_C - below_c

    def cap(x):
        w = np.where(x > peak, wide_above_c, wide_below_c)
        return 1.0 / (1.0 + ((x - peak) / w) ** 2)

    ref = float(cap(np.array([T_REF_C]))[0])
    u = below_c / wide_above_c
    rel_slope = -2.0 * u / wide_above_c / (1.0 + u * u)  # d ln C / dT at the reference
    return k_v_per_c / rel_slope * (cap(follow(t, temp, lag_s)) / ref - 1.0)


def tnm_bond_zero(t, temp, k_v_per_c, glassy, tau_ref_s, b_per_c, nonlinearity, lag_s, step_s=0.5):
    """The zero of gauges bonded with an adhesive near its glass transition: its volume follows the bond's temperature
    (lag ``lag_s``) at once by ``glassy`` of the slope, and by the rest through the fictive temperature T_f, which
    relaxes toward the temperature after Tool, Narayanaswamy and Moynihan, tau = tau_ref exp(-x b dT - (1 - x) b
    dT_f) (tau_ref = ``tau_ref_s``, b = ``b_per_c``, x = ``nonlinearity``): warming recovers faster than cooling
    settles. ``k_v_per_c`` at the reference once settled; exact exponential steps of ``step_s``, settled at the
    start."""
    grid = np.arange(t[0], t[-1] + step_s, step_s)
    bond = np.interp(grid, t, follow(t, temp, lag_s)) - T_REF_C
    fictive = float(bond[0])
    fic = np.empty(grid.size)
    for i, b in enumerate(bond.tolist()):
        fic[i] = fictive
        tau = tau_ref_s * math.exp(min(max(-nonlinearity * b_per_c * b - (1.0 - nonlinearity) * b_per_c * fictive,
                                           -8.0), 8.0))
        fictive = b + (fictive - b) * math.exp(-step_s / tau)
    zero = k_v_per_c * (glassy * bond + (1.0 - glassy) * fic)
    return np.interp(t, grid, zero)


# ----------------------------------------------------------------------------- thermal sensitivity

class PhosphorQuench(SimOnly):
    """An optical read-out lit by a phosphor whose luminescence quenches thermally (Mott and Seitz: the efficiency 1 /
    (1 + exp(a (1 / T_q - 1 / T))), half at T_q = ``gap_c`` above the reference, a set for ``tc`` per degC of span
    lost at the reference, which lies on the flat side), on the phosphor's temperature (lag ``lag_s``): the span falls
    ever faster as it warms and hardly rises as it cools."""

    def __init__(self, tc, gap_c, lag_s):
        self.lag = lag_s
        ref = T_REF_C + 273.15
        self.inv_q = 1.0 / (ref + gap_c)
        delta = 1.0 / ref - self.inv_q
        y = optimize.brentq(lambda y: y / ((1.0 + math.exp(y)) * delta * ref * ref) - tc, 1.2785, 60.0)
        self.a = y / delta
        self.ref = self._eff(np.array([ref]))[0]

    def _eff(self, kelvin):
        return 1.0 / (1.0 + np.exp(np.clip(self.a * (self.inv_q - 1.0 / kelvin), -60.0, 60.0)))

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        kelvin = follow(t, temp_of(aux, t.size), self.lag) + 273.15
        return np.asarray(x, dtype=float) * self._eff(kelvin) / self.ref


class BicellDefocus(SimOnly):
    """An optical lever read by a bi-cell photodiode: the difference signal per volt is the inverse of the Gaussian
    spot's width, sqrt(1 + u^2) in Rayleigh lengths from the focus, and the lens mount's expansion moves the focus with
    the mount's temperature (lag ``lag_s``), u = u0 + beta dT (u0 = ``u0``), beta set for ``tc`` per degC (either
    sign) at the reference."""

    def __init__(self, tc, u0, lag_s):
        self.u0, self.lag = u0, lag_s
        self.beta = tc * (1.0 + u0 * u0) / u0

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        gain = math.sqrt(1.0 + self.u0 ** 2) / np.sqrt(1.0 + (self.u0 + self.beta * d) ** 2)
        return np.asarray(x, dtype=float) * gain


# ----------------------------------------------------------------------------- offset drift

def carter_kibler_uptake(rng, horizon_s=HORIZON_S):
    """The zero of gauges whose epoxy takes up water from a humidified enclosure the sensor went into 0-300 s before
    the first sample: Carter and Kibler's two-phase model, mobile water diffusing through the film (L^2 / D 150-1200 s,
    the surface saturated) and binding at a rate gamma (1 / 200-1500 s) to sites it leaves at beta, bound water
    0.5-2 times the mobile at equilibrium: a Fickian rise to a plateau, then a slower second rise (as a function of
    the seconds since the first sample, zero there)."""
    ago, diffuse = rng.uniform(0.0, 300.0), rng.uniform(150.0, 1200.0)
    gamma = 1.0 / rng.uniform(200.0, 1500.0)
    beta = gamma / rng.uniform(0.5, 2.0)
    cells = 16
    dx = 1.0 / cells
    dt = min(0.5, 0.4 * dx * dx * diffuse)
    mobile, bound = np.zeros(cells + 1), np.zeros(cells + 1)
    mobile[-1] = 1.0
    times, uptake = [0.0], [0.0]
    cursor = 0.0
    while cursor < ago + horizon_s + 1.0:
        lap = np.empty_like(mobile)
        lap[1:-1] = mobile[2:] - 2.0 * mobile[1:-1] + mobile[:-2]
        lap[0] = 2.0 * (mobile[1] - mobile[0])  # the film's middle: no flux
        lap[-1] = 0.0
        bind = gamma * mobile - beta * bound
        mobile = mobile + dt * (lap / (dx * dx * diffuse) - bind)
        mobile[-1] = 1.0
        bound = bound + dt * bind
        cursor += dt
        times.append(cursor)
        uptake.append(float(np.mean(mobile[:-1] + bound[:-1])))
    times, uptake = np.asarray(times) - ago, np.asarray(uptake)
    first = float(np.interp(0.0, times, uptake))
    return lambda s: np.interp(np.asarray(s, dtype=float), times, uptake) - first


def infusion_head(rng, horizon_s=HORIZON_S, step_s=0.5):
    """The zero of a fluid-filled read-out line connected to an infusion bag: the head falls as the bag drains (its
    level as its content to the power 0.35-0.8, a collapsing bag; the content falls at one bag per 900-4000 s, from
    30-95 % full), 1-3 changes of the roller clamp scale the drip by exp(+-1.1), in half the records a new bag is hung
    (2-6 s) when this one runs dry or earlier, and in half the drip stand is moved up or down by 20-60 % of a bag's
    height over 1-3 s (as a function of the seconds since the first sample, zero there)."""
    grid = np.arange(0.0, horizon_s + 1.0, step_s)
    content, drain = rng.uniform(0.3, 0.95), 1.0 / rng.uniform(900.0, 4000.0)
    power = rng.uniform(0.35, 0.8)
    rate = np.full(grid.size, drain)
    for _ in range(int(rng.integers(1, 4))):
        rate[grid >= rng.uniform(0.0, horizon_s)] *= math.exp(rng.uniform(-1.1, 1.1))
    swap_at = rng.uniform(0.2, 1.0) * horizon_s if rng.random() < 0.5 else math.inf
    hang = rng.uniform(2.0, 6.0)
    level = np.empty(grid.size)
    swapping, start, was = False, 0.0, 0.0
    for i, g in enumerate(grid.tolist()):
        if not swapping and (g >= swap_at or (content <= 0.0 and math.isfinite(swap_at))):
            swapping, start, swap_at, was = True, g, math.inf, content ** power
        if swapping:
            u = (g - start) / hang
            if u >= 1.0:
                swapping, content = False, 1.0
            level[i] = was + (1.0 - was) * float(ease(u)) if swapping else 1.0
            continue
        content = max(content - rate[i] * step_s, 0.0)
        level[i] = content ** power
    stand = np.zeros(grid.size)
    if rng.random() < 0.5:
        at, move = rng.uniform(0.0, horizon_s), rng.uniform(0.2, 0.6) * rng.choice([-1.0, 1.0])
        stand = move * ease((grid - at) / rng.uniform(1.0, 3.0))
    head = level + stand
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, head - head[0])


# ----------------------------------------------------------------------------- resonance

class EnergySinkMode(GridMode):
    """A needle holder's mode at ``f0_hz`` (damping ratio ``zeta``; unit gain at rest) with a nonlinear energy sink: a
    mass of ``mass_ratio`` of the mode's on an essentially cubic spring (hardening from nothing, its frequency equal to
    the mode's at a relative travel ``engage_v``, straightened beyond three times that) and a damper of ratio
    ``sink_zeta``: a knock that moves the mode past the engagement is drained into the sink, a smaller one rings on.
    Semi-implicit Euler on a uniform grid of 4 kHz, from rest."""

    fs = 4000.0

    def __init__(self, f0_hz, zeta, mass_ratio, engage_v, sink_zeta):
        self.w, self.zeta, self.eps = 2.0 * math.pi * f0_hz, zeta, mass_ratio
        self.kappa = mass_ratio * self.w ** 2 / (3.0 * engage_v ** 2)
        self.r_max = 3.0 * engage_v
        self.damp = 2.0 * sink_zeta * self.w * mass_ratio

    def on_grid(self, t, tu, xu, h):
        w2, c1, eps, kappa, damp, r_max = self.w ** 2, 2.0 * self.zeta * self.w, self.eps, self.kappa, self.damp, self.r_max
        edge, slope = kappa * r_max ** 3, 3.0 * kappa * r_max ** 2
        y = v = z = vz = 0.0
        out = np.empty(tu.size)
        for i, xi in enumerate(xu.tolist()):
            r = y - z
            if r > r_max:
                spring = edge + slope * (r - r_max)
            elif r < -r_max:
                spring = -edge + slope * (r + r_max)
            else:
                spring = kappa * r * r * r
            fc = spring + damp * (v - vz)
            v += (w2 * (xi - y) - c1 * v - fc) * h
            vz += fc / eps * h
            y += v * h
            z += vz * h
            out[i] = y
        return out


class BallPassMode(GridMode):
    """A needle holder's mode at ``f0_hz`` (damping ratio ``zeta``; unit gain at rest) on a spindle's rolling bearing:
    while the spindle turns (bouts of 3-25 s, 5-40 s apart, drawn from ``seed``) the stiffness varies by +-``depth`` as
    the balls pass at ``pass_hz`` (the frequency with its square root, the damping fixed). Semi-implicit Euler on a
    uniform grid of 4 kHz, from rest."""

    fs = 4000.0

    def __init__(self, f0_hz, zeta, depth, pass_hz, seed):
        self.w, self.zeta, self.depth, self.pass_hz, self.seed = 2.0 * math.pi * f0_hz, zeta, depth, pass_hz, seed

    def on_grid(self, t, tu, xu, h):
        rng = np.random.default_rng(self.seed)
        turning = np.zeros(tu.size, dtype=bool)
        at = t[0] + rng.uniform(0.0, 30.0)
        while at < t[-1]:
            length = rng.uniform(3.0, 25.0)
            turning |= (tu >= at) & (tu < at + length)
            at += length + rng.uniform(5.0, 40.0)
        phase = rng.uniform(0.0, 2.0 * math.pi)
        w2 = self.w ** 2 * (1.0 + self.depth * turning * np.sin(2.0 * math.pi * self.pass_hz * (tu - t[0]) + phase))
        c1 = 2.0 * self.zeta * self.w
        y = v = 0.0
        out = np.empty(tu.size)
        for i, (xi, k) in enumerate(zip(xu.tolist(), w2.tolist())):
            v += (k * (xi - y) - c1 * v) * h
            y += v * h
            out[i] = y
        return out


# ----------------------------------------------------------------------------- friction

def toothed_detent(f, band_n, stickiness):
    """The force passed by a needle feed whose carriage a spring-loaded pawl holds over a finely toothed rack
    (Prandtl and Tomlinson): the passed force P solves F = P + b sin(2 pi P / p) on the stable branch it sits on (p
    the pitch, b the detent's hold, 2 pi b / p = ``stickiness`` > 1), hopping to the next tooth's branch when the
    force leaves its own; the largest lag of P behind F is ``band_n`` (Coulomb-like, the same at every load and
    always). Started on the branch nearest ``f[0]``."""
    kappa = stickiness
    b = band_n / math.sqrt(1.0 - 1.0 / kappa ** 2)
    pitch = 2.0 * math.pi * b / kappa
    half = math.acos(-1.0 / kappa) * pitch / (2.0 * math.pi)  # a stable branch: |P - j pitch| < half
    reach = half + b * math.sin(math.acos(-1.0 / kappa))  # the forces it holds: |F - j pitch| <= reach
    w = 2.0 * math.pi / pitch
    f = np.asarray(f, dtype=float)
    j = int(round(float(f[0]) / pitch))
    p = float(f[0])
    out = np.empty_like(f)
    for i, fi in enumerate(f.tolist()):
        if fi > j * pitch + reach:
            j = int(math.ceil((fi - reach) / pitch))
        elif fi < j * pitch - reach:
            j = int(math.floor((fi + reach) / pitch))
        lo, hi = j * pitch - half, j * pitch + half
        p = min(max(p, lo), hi)
        for _ in range(60):
            g = p + b * math.sin(w * p) - fi
            if abs(g) < 1e-10:
                break
            if g > 0.0:
                hi = p
            else:
                lo = p
            slope = 1.0 + kappa * math.cos(w * p)
            nxt = p - g / slope if slope > 1e-9 else 0.5 * (lo + hi)
            p = nxt if lo < nxt < hi else 0.5 * (lo + hi)
        out[i] = p
    return out


def felt_avalanches(f, band_n, seed, largest, exponent):
    """The force passed by a needle drawn through the felt wiper of a guide: the fibres hold up to ``band_n`` (the same
    at every load and always) and, whenever that is exceeded, let go in an avalanche that releases a share of the band
    drawn from a power law of ``exponent`` between 3 % and ``largest`` (from ``seed``); then they hold again.
    Started at ``f[0]``."""
    rng = np.random.default_rng(seed)
    small = 0.03
    u = rng.random(1 << 16)
    ratio = (small / largest) ** exponent
    sizes = (small * (1.0 - u * (1.0 - ratio)) ** (-1.0 / exponent)).tolist()
    f = np.asarray(f, dtype=float)
    p, k = float(f[0]), 0
    out = np.empty_like(f)
    for i, fi in enumerate(f.tolist()):
        e = fi - p
        if e > band_n:
            p = fi - band_n * (1.0 - sizes[k & 0xFFFF])
            k += 1
        elif e < -band_n:
            p = fi + band_n * (1.0 - sizes[k & 0xFFFF])
            k += 1
        out[i] = p
    return out


class ForcePath(SimOnly):
    """A map of the force history before the core: ``fn(F)``."""

    def __init__(self, fn):
        self.fn = fn

    def forward(self, t_s, x, aux=None, state=None):
        return self.fn(np.asarray(x, dtype=float))


# ----------------------------------------------------------------------------- thermo-rheological

def creeping(c):
    """The core made soft enough for its clock to show: its Kelvin spring at most 18 N/V (the retardation time kept)
    and its flow's viscosity at most 3.5e4 N s/V."""
    k2 = min(c.k2_n_per_v, 18.0)
    return Burgers(c.k1_n_per_v, k2, min(c.eta1_n_s_per_v, 3.5e4), c.eta2_n_s_per_v * k2 / c.k2_n_per_v)


class FacilitationClock(SimOnly):
    """A core whose clock follows the parabolic law of dynamic facilitation (Elmatad, Garrahan and Chandler): log tau
    = J^2 (1 / T - 1 / T_o)^2 below the onset T_o (``onset_c`` above the reference), tau constant above it; J set for
    ``b_per_c`` per degC of the clock at the reference, on the core's temperature (lag ``lag_s``), held within e^+-6."""

    def __init__(self, c, b_per_c, onset_c, lag_s):
        self.c, self.lag = c, lag_s
        ref = T_REF_C + 273.15
        self.inv_o = 1.0 / (ref + onset_c)
        self.ref_term = (1.0 / ref - self.inv_o) ** 2
        self.j2 = b_per_c * ref * ref / (2.0 * (1.0 / ref - self.inv_o))

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        kelvin = np.minimum(follow(t, temp_of(aux, t.size), self.lag) + 273.15, 1.0 / self.inv_o)
        log_rate = -self.j2 * ((1.0 / kelvin - self.inv_o) ** 2 - self.ref_term)
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(log_rate, -6.0, 6.0)))


class AdamGibbsClock(SimOnly):
    """A core whose clock follows Adam and Gibbs with the configurational entropy of a constant excess heat capacity,
    log tau = C / (T ln(T / T_K)), T_K ``kauzmann_below`` below the reference; C set for ``b_per_c`` per degC of the
    clock at the reference, on the core's temperature (lag ``lag_s``), held within e^+-6."""

    def __init__(self, c, b_per_c, kauzmann_below, lag_s):
        self.c, self.lag = c, lag_s
        ref = T_REF_C + 273.15
        self.tk = ref - kauzmann_below
        lr = math.log(ref / self.tk)
        self.big_c = b_per_c * (ref * lr) ** 2 / (lr + 1.0)
        self.ref_term = 1.0 / (ref * lr)

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        kelvin = follow(t, temp_of(aux, t.size), self.lag) + 273.15
        log_rate = self.big_c * (self.ref_term - 1.0 / (kelvin * np.log(kelvin / self.tk)))
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(log_rate, -6.0, 6.0)))


# ----------------------------------------------------------------------------- outside the catalogue

class DemodulatorFlips(SimOnly):
    """A carrier read-out whose demodulator's phase-locked loop, after a dropout of the carrier, relocks 180 degrees
    out: ``count`` bouts (drawn from ``seed``, each 0.5-1.5 times ``length_s``) in which the whole reading is
    inverted, until the firmware's next resynchronisation."""

    def __init__(self, count, length_s, seed):
        self.count, self.length, self.seed = count, length_s, seed

    def forward(self, t_s, x, aux=None, state=None):
        t, v = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float).copy()
        rng = np.random.default_rng(self.seed)
        for at in rng.uniform(0.05, 0.9, self.count) * (t[-1] - t[0]) + t[0]:
            sel = (t >= at) & (t < at + self.length * rng.uniform(0.5, 1.5))
            v[sel] = -v[sel]
        return v


class StaleLapSamples(SimOnly):
    """A DAQ whose DMA ring buffer of 0.5-4 s is read in blocks of 16-64 samples by firmware that races the DMA: in
    ``share`` of the blocks (drawn from ``seed``) the first 1-3 samples are still those of the buffer's previous lap,
    one buffer length earlier."""

    def __init__(self, share, seed):
        self.share, self.seed = share, seed

    def forward(self, t_s, x, aux=None, state=None):
        t, v = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        rng = np.random.default_rng(self.seed)
        lap = max(1, int(round(rng.uniform(0.5, 4.0) / float(np.median(np.diff(t))))))
        block, count = int(rng.integers(16, 65)), int(rng.integers(1, 4))
        starts = np.flatnonzero(rng.random(v.size // block + 1) < self.share) * block
        idx = (starts[:, None] + np.arange(count)[None, :]).ravel()
        idx = idx[(idx < v.size) & (idx >= lap)]
        out = v.copy()
        out[idx] = v[idx - lap]
        return out


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([3.6e4, 5e3]))))  # V / (N s)
        if shape == "breakthrough_plug":
            rule = breakthrough_plug(phi * rng.uniform(1.5, 3.0), rng.uniform(1.5, 4.5), rng.uniform(0.25, 0.7))
        else:
            rule = crystallising_flow(phi * rng.uniform(1.5, 3.0), rng.uniform(1.5, 4.0), rng.uniform(40.0, 300.0),
                                      rng.uniform(1.5, 3.0), rng.uniform(0.5, 0.85))
        return Parts("zener", LeakingCore.of(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        share = float(np.interp(m, [0, 1], [0.025, 0.22]))  # of the instantaneous response
        if shape == "payne_kelvin":
            soft = rng.uniform(1.6, 3.2)
            a = (share / g0 / soft ** 0.25, rng.uniform(0.5, 6.0), soft, rng.uniform(15.0, 80.0),
                 rng.uniform(20.0, 120.0), rng.uniform(0.5, 0.8))
            p.extra.append(lambda t, f, T, a=a: payne_kelvin(t, f, *a))
            return p
        a = (share / g0, rng.uniform(1.0, 15.0), share / g0 * rng.uniform(0.4, 2.0))
        p.extra.append(lambda t, f, T, a=a: slack_link_kelvin(t, f, *a))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.012, 0.065]))
        if shape == "woven_strap_arches":
            p.before.append(WovenStrap(float(np.interp(m, [0, 1], [0.015, 0.05])) * FORCE_MAX_N, rng.uniform(0.3, 0.9)))
            return p
        p.after.append(GappedPolePreisach(top, frac, rng.uniform(0.04, 0.15), rng.uniform(0.3, 0.7),
                                          rng.uniform(0.12, 0.3), rng.uniform(0.3, 1.5), float(rng.choice([-1.0, 1.0])),
                                          int(rng.integers(1 << 30))))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.01, 0.11]))))
        if shape == "eddy_current_yoke":
            p.after.append(EddyYoke(delay))
            return p
        p.after.append(LogAmpRc(delay, rng.uniform(0.05, 0.4) * top))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.05, 0.19]))
        if shape == "macrobend_loop":
            p.after.append(StaticMap(macrobend_loop(rel, top, rng.uniform(0.05, 0.6))))
            return p
        p.after.append(StaticMap(off_shaft_angle(rel, top, math.radians(rng.uniform(0.0, 40.0)),
                                                 math.radians(rng.uniform(60.0, 150.0)),
                                                 math.radians(rng.uniform(-6.0, 6.0)), float(rng.choice([-1.0, 1.0])))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.007, 0.032]) * rng.choice([-1, 1]))
        if shape == "y5v_reference":
            a = (k, rng.uniform(3.0, 15.0), rng.uniform(25.0, 50.0), rng.uniform(12.0, 30.0), rng.uniform(8.0, 45.0))
            p.extra.append(lambda t, f, T, a=a: y5v_reference_zero(t, T, *a))
            return p
        a = (k, rng.uniform(0.15, 0.5), rng.uniform(20.0, 200.0), rng.uniform(0.25, 0.6), rng.uniform(0.3, 0.6),
             rng.uniform(5.0, 30.0))
        p.extra.append(lambda t, f, T, a=a: tnm_bond_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        tc = float(np.interp(m, [0, 1], [0.016, 0.034]))
        if shape == "phosphor_quenching":
            p.after.append(PhosphorQuench(tc, rng.uniform(0.35, 0.8) * 0.2785 / tc, rng.uniform(5.0, 30.0)))
            return p
        p.after.append(BicellDefocus(tc * float(rng.choice([-1.0, 1.0])),
                                     rng.uniform(0.35, 2.2) * float(rng.choice([-1.0, 1.0])), rng.uniform(10.0, 40.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.018, 0.095]) * rng.choice([-1, 1]))
        zero = sized(carter_kibler_uptake(rng) if shape == "carter_kibler_bond" else infusion_head(rng), size)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.028, 0.0055])) * rng.uniform(0.8, 1.2)
        if shape == "nonlinear_energy_sink":
            p.after.append(EnergySinkMode(rng.uniform(14.0, 48.0), zeta, rng.uniform(0.02, 0.08),
                                          rng.uniform(0.1, 0.5) / g0, rng.uniform(0.05, 0.2)))
            return p
        p.after.append(BallPassMode(rng.uniform(14.0, 48.0), zeta, rng.uniform(0.06, 0.2), rng.uniform(2.0, 12.0),
                                    int(rng.integers(1 << 30))))
        return p
    if effect == "friction":
        band = float(np.interp(m, [0, 1], [0.004, 0.034]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "toothed_detent":
            a = (band, rng.uniform(1.6, 4.5))
            p.before.append(ForcePath(lambda x, a=a: toothed_detent(x, *a)))
            return p
        a = (band, int(rng.integers(1 << 30)), rng.uniform(0.3, 0.7), rng.uniform(0.8, 1.6))
        p.before.append(ForcePath(lambda x, a=a: felt_avalanches(x, *a)))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.18, 0.52])) * rng.uniform(1.2, 1.5)
        c = creeping(c)
        if shape == "facilitation_clock":
            return Parts("burgers", FacilitationClock(c, b, rng.uniform(8.0, 35.0), rng.uniform(5.0, 25.0)),
                         core_changed=True)
        return Parts("burgers", AdamGibbsClock(c, b, rng.uniform(40.0, 110.0), rng.uniform(5.0, 25.0)), core_changed=True)
    if effect == "demodulator_relock":
        count = int(round(float(np.interp(m, [0, 1], [1.0, 5.0])))) + int(rng.integers(0, 2))
        p.outer.append(DemodulatorFlips(count, float(np.interp(m, [0, 1], [1.5, 10.0])), int(rng.integers(1 << 30))))
        return p
    if effect == "stale_dma_lap":
        p.outer.append(StaleLapSamples(float(np.interp(m, [0, 1], [0.02, 0.13])), int(rng.integers(1 << 30))))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["breakthrough_plug", "crystallising_flow"],
    "delayed_elasticity": ["payne_kelvin", "slack_link_kelvin"],
    "hysteresis": ["woven_strap_arches", "gapped_pole_preisach"],
    "sensor_lag": ["eddy_current_yoke", "log_amp_rc"],
    "nonlinear_gain": ["macrobend_loop", "off_shaft_angle"],
    "thermal_drift": ["y5v_reference", "tnm_bond"],
    "thermal_sensitivity": ["phosphor_quenching", "bicell_defocus"],
    "offset_drift": ["carter_kibler_bond", "infusion_head"],
    "resonance": ["nonlinear_energy_sink", "ball_pass_bearing"],
    "friction": ["toothed_detent", "felt_avalanches"],
    "thermo_rheological": ["facilitation_clock", "adam_gibbs_clock"],
}
PAIRS = (("delayed_elasticity", "thermal_drift"), ("viscous_flow", "resonance"), ("hysteresis", "offset_drift"),
         ("friction", "thermal_sensitivity"), ("nonlinear_gain", "thermo_rheological"),
         ("sensor_lag", "delayed_elasticity"))
OUTSIDE = ("demodulator_relock", "stale_dma_lap")
RATES = (135.0, 265.0, 455.0, 735.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split AA", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.28, 0.88),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=fume_hood,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(0.9e-3, 2.5e-3), jitter=0.32,
                   gap_s=(0.15, 2.6))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
