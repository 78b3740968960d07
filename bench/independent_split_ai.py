"""Independent split AI for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split AI is a held-out set kept apart: written without looking at the engine it scores (at how that engine detects or
fits anything), run once, and nothing is ever chosen from its results. Each name of the catalogue is hidden in two
shapes that appear neither among the registry's families (``polyforce_ros/sim/truths.py``) nor in splits A to AH. Every
case has a core whose Kelvin spring is at most 20 N/V (its retardation time kept) and whose flow's viscosity is at most
2.5e4 N s/V:

* a core filled with a viscoelastic polymer solution leaking through a micro-contraction, whose flow turns elastically
  unstable (elastic turbulence) once the force passes 2-5 N, the resistance rising 2-4 fold within 0.2-1.5 s and
  falling back only below 55-85 % of that force, within 1-5 s (2-4 times the plain fluidity of 1/42000-1/3600 V/(N s)
  while stable), or a core of a dense paste that the load's own vibration fluidises (its fluidity, 0.5-1 times the
  plain one at rest, rising 3-9 fold as sigma^2 / (sigma^2 + s^2), sigma the RMS of the force above 2-6 Hz over the
  last 0.1-0.5 s, s 0.05-0.4 N); neither ever recovers;
* a Kelvin unit whose oil passes into its pocket through a soft (PDMS) microchannel that its own pressure dilates
  (Gervais: the flow as ((1 + p_in / E)^4 - (1 + p_out / E)^4) / 4, E 1.5-6 N: large steps start fast, and emptying
  the pocket, at a lower mean pressure, runs slower than filling it; 2-20 s for small steps), or a pad of a
  polydomain liquid-crystal elastomer whose directors rotate only above a threshold of 0.5-2.5 N (semi-soft
  elasticity: a plateau ending 2-5 N higher, the rotation running at a rate proportional to the force's distance from
  the threshold, 1-12 s at 1 N); both settle at 5-23 % of the instantaneous response (the pad at the plateau's end);
* a touch-mode capacitive read-out whose diaphragm, softened by its bias (the parallel-plate law, pulling in at a third
  of its gap), collapses onto its insulated floor once the core's output passes 30-65 % of the range, reading 2-7.5 %
  of the range more while down (25-50 % of that just before), and sticks there (adhesion) until the output falls to
  55-85 % of the collapse, or a stack of 3-6 Kresling origami cells under the read head that the force snaps flat one
  by one (at 1.5-7 N, each springing back at 35-70 % of its own snap force; each branch softening toward its fold as
  the square root of the distance, by 15-30 % of the snap), 2-7.5 % of the range in all;
* a hydraulic line to the transducer carrying entrained air (Wood's law: the wave speed grows as the square root of
  the absolute pressure, the line's pressure 3-9 fold at the top of the range: the transit shortens as the load rises,
  a lag of 10-25 % of it behind), or a host that smooths the stream in blocks of 0.25-1 s forward and backward (a
  second-order Butterworth, zero-phase inside each block, with steps and anticipation at the blocks' seams); 12-100 ms
  (the transit unloaded, the filter's time constant);
* an astigmatic focus-error read-out of a mirror on the core (the four-quadrant signal of an elliptical Gaussian spot,
  arcsin(2 a z / (1 + z^2)), z the defocus over the spot's depth, a the line foci's half separation over it, 0.4-0.85,
  the focus 0-0.35 of it off: compressive or S-shaped), or a chromatic confocal read-out (a lens of Cauchy glass, A
  1.5-1.75, B 0.004-0.02 um^2, focusing 450-600 nm on the mirror at rest, the peak wavelength read as the load moves
  the mirror either way); 5-19 % at the top of the range;
* the zero of a housing tied to the robot's flange (0.5 degC below to 2.5 degC above the reference) by a thermosiphon
  that carries heat only from the housing to the flange (once it is 0.1-0.6 degC warmer; 4-12 times faster than the
  air's 20-80 s), or of a read-out pressed by a thermoresponsive hydrogel cushion that collapses as it warms through
  its transition (a logistic 0.4-1 degC wide, at the 35-65th percentile of its temperature over the record; swelling
  back within 15-60 s and shrinking 2-5 times slower behind its skin; lag 5-20 s); 0.008-0.032 V/degC (the cushion's
  at its steepest);
* the span of an optical read-out lit by a vertical-cavity laser at a constant current, its output a Gaussian of the
  gain peak's detuning from the cavity mode (moving 0.21-0.25 nm/degC against a width of 8-16 nm, at most 1.3 times
  the shift over the coefficient, either side of the optimum; lag 3-15 s), or of a carrier bridge excited from a
  Wien-bridge oscillator whose amplitude an NTC thermistor stabilises (the thermistor held at its own set temperature,
  14-36 degC above the reference, so the amplitude goes as the square root of that margin; lag 5-25 s); 1.4-3.5
  %/degC at the reference;
* the zero of a read-out whose cable runs beside the robot's vacuum hose (each pick, 1-8 s every 4-30 s, shortens the
  evacuated hose within 0.2-0.6 s, its pull relaxing by 20-40 % over 2-10 s; each release leaving 5-15 % that
  recovers over 20-60 s), or of one whose cable runs in the drag chain of a linear axis (moves every 10-60 s within 1-4
  s; the pull quadratic in the position, through the links' friction, a play of 10-30 % of its range); 20-96 mV at
  most;
* a needle holder's mode (15-45 Hz) carrying an electromagnetic vibration harvester that charges a cell through a
  bridge rectifier (it damps only while its voltage exceeds the diodes and the cell, 20-60 % of the largest speed a
  linear mode would reach, then 2-6 times the holder's own damping), or a holder on a magnetic base that rocks on its
  edge once a knock lifts it (beyond 15-50 % of the largest motion a linear mode would reach: a restoring force that
  no longer grows and weakens by 10-40 % per such width, landings keeping 60-90 % of the speed); damping ratio
  0.0042-0.028 (the holder's);
* a Coulomb band of 0.28-5.5 % of the range: a needle guide on a carriage whose weight presses its shoes as the robot
  tilts the tool (the band 15-35 % of its steepest at the flattest pose, as the sine of a tilt of 0-90 degrees; poses
  held 5-40 s, moved within 0.5-2 s), or a guide sealed by an O-ring that the pressure nibbles into its clearance whenever the
  force passes 2-5 N (the band growing 0.5-1.5 times the excess over that force, at most threefold, 40-80 % of each
  rise recovering over 20-120 s);
* a core whose dashpots follow a liquid-crystal elastomer's order parameter (Haller: (1 - T / T_NI)^beta, beta
  0.15-0.25, T_NI 15-40 degC above the reference; 40-70 % of the slope from it, the rest Arrhenius), or a core filled
  with a thermogelling poloxamer whose micelles pack tighter as it warms (their share of the packing limit a logistic
  at 50-80 % at the reference and 90-97 % at most, Krieger and Dougherty's law, the water's own 2.45 %/degC aside:
  the clock slows as it warms); 1.2-1.5 times 0.16-0.48 per degC at the reference, lag 5-25 s.

It also holds six pairs, two effects outside the catalogue (the core's deflection counted by an incremental encoder
whose decoder loses 2-8 % of the counts whenever the deflection moves faster than it can follow, above the
97-99.5th percentile of the speed in the record: the zero walks at each fast swing; a read-out firmware that holds
the last accepted sample whenever the next jumps by more than the 96.5-98.5th percentile of the record's steps,
accepting again after 5-16 rejections) and four clean records. Profiles: a bakery robot probing loaves for their core
temperature (the measured Okamura insertion, ``../shared/data``, ``time_force.csv``, from its onset to the start of its
withdrawal as the crust and the crumb, 0.5-1.4 times its length, scaled to a 2.2-8.8 N peak, an air pocket in a third
of them; a dwell of 3-8 s while the thermometer settles and the crumb relaxes by 15-40 %, then withdrawn; loaves 4-12
s apart, a rack swapped every 6-12 loaves; a train of synthetic punctures when the data are absent); a robot kneading
bread dough (pushes with the heel of the hand at 0.4-0.8 Hz, each peaking and flowing away, a fold back, a quarter
turn, the peak growing 30-80 % as the gluten develops); and a robot embossing Braille with a slate and stylus (each dot
a press to the paper's yield at 2.5-6 N, a give as the paper stretches into the pit and the stylus bottoming out,
cells, words, lines and pages). Rates 175, 355, 745 and 1220 Hz (a mode at 1000 Hz with knocks that excite it),
0.56-2.17 mV noise, stamp jitter, gaps, and a sensor on a robot in an artisan bakery: the room warming through the
bake, the robot moving between its bench, the deck ovens, a proofer and the cool flour store, hot air from the ovens'
doors reaching it while it works at them, a ceiling fan stirring the air.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size against its
noise without diagnosing (for a leak on a Zener base, against that bare Zener core).

    .venv/bin/python bench/independent_split_ai.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, signal

from independent_split import puncture_train
from polyforce_ros.physics.viscoelastic import Burgers
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (GridMode, LeakingCore, Parts, ShapeSplit, SimOnly, band_play, coarse, ease, fit_departure,
                       follow, lagged, logistic, on_clock, schedule, sized, temp_of, uniform_grid, within)

SEED0 = 2_700_000  # clear of the registry's seeds and of splits A (90000..) to AH (2600000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 425.0
HORIZON_S = DURATION_S + 60.0  # what a schedule drawn for a record covers, its gaps' slack included


# ----------------------------------------------------------------------------- small tools

def softened(c):
    """The drawn Burgers core within the split's limits: a Kelvin spring of at most 20 N/V (the retardation time kept)
    and a flow of at most 2.5e4 N s/V."""
    k2 = min(c.k2_n_per_v, 20.0)
    return Burgers(c.k1_n_per_v, k2, min(c.eta1_n_s_per_v, 2.5e4), c.eta2_n_s_per_v * k2 / c.k2_n_per_v)


def first_order(x, keep, start=None):
    """``x`` through y[i] = keep y[i-1] + (1 - keep) x[i], settled at ``start`` (x[0] when None) before it."""
    y0 = float(x[0]) if start is None else start
    y, _ = signal.lfilter([1.0 - keep], [1.0, -keep], x, zi=[keep * y0])
    return y


def rise_fall(x, keep_up, keep_down, start=None):
    """``x`` followed with retention ``keep_up`` per step while the state lies below it and ``keep_down`` while above,
    from ``start`` (x[0] when None)."""
    out, y = np.empty(x.size), float(x[0]) if start is None else start
    for i, xi in enumerate(x.tolist()):
        y = xi + (y - xi) * (keep_up if xi > y else keep_down)
        out[i] = y
    return out


def latch(x, up, down):
    """Per sample: True from a sample at or above ``up`` until the next at or below ``down`` (False before either)."""
    idx = np.arange(x.size)
    last_up = np.maximum.accumulate(np.where(x >= up, idx, -1))
    last_down = np.maximum.accumulate(np.where(x <= down, idx, -1))
    return last_up > last_down


def poses(rng, held_s, move_s, low, high, step_s=0.02):
    """A value held for ``held_s`` (range) and moved to another uniform draw in [``low``, ``high``] within ``move_s``
    (range, minimum jerk), as a function of the seconds since the first sample."""
    grid = np.arange(-60.0, HORIZON_S + step_s, step_s)
    out = np.full(grid.size, rng.uniform(low, high))
    at = rng.uniform(-held_s[1], held_s[0])
    while at < HORIZON_S:
        length, goal = rng.uniform(*move_s), rng.uniform(low, high)
        sel = grid >= at
        here = float(np.interp(at, grid, out))
        out[sel] = here + (goal - here) * ease((grid[sel] - at) / length)
        at += length + rng.uniform(*held_s)
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, out)


def plain_mode(xu, w, zeta, fs):
    """A linear mode of unit gain (``w`` rad/s, damping ratio ``zeta``) driven by ``xu`` on a grid of ``fs`` Hz, from
    rest: its motion relative to the drive and that motion's speed."""
    b, a = signal.bilinear([w * w], [1.0, 2.0 * zeta * w, w * w], fs=fs)
    z = signal.lfilter(b, a, xu) - xu
    return z, np.gradient(z, 1.0 / fs)


def hf_rms(t, f, corner_hz, window_s):
    """The RMS of ``f`` above ``corner_hz`` (a second-order high-pass) over the last ``window_s`` (a first-order average
    of its square), on a uniform grid at the median step, read back at ``t``."""
    tu, fu, h = uniform_grid(t, f)
    b, a = signal.butter(2, min(corner_hz, 0.4 / h), btype="high", fs=1.0 / h)
    shake = signal.lfilter(b, a, fu - fu[0])
    return np.interp(t, tu, np.sqrt(first_order(shake * shake, math.exp(-h / window_s), start=0.0)))


# ----------------------------------------------------------------------------- profiles

@functools.lru_cache(maxsize=1)
def measured_probe():
    """The measured Okamura insertion (``../shared/data``, ``time_force.csv``) at 1 kHz from its onset to the start of
    its withdrawal, tension clipped, its peak 1: the crust's rupture and the crumb's cutting. None when absent."""
    try:
        _, fp = profiles.okamura_insertion(peak_n=1.0, rate_hz=1000.0, pre_s=0.0, post_s=0.0)
    except FileNotFoundError:
        return None
    smooth = np.convolve(fp, np.ones(51) / 51.0, mode="same")
    top, onset = int(np.argmax(smooth)), int(np.argmax(smooth > 0.03))
    level = float(np.median(smooth[top + 1000:top + 6000]))
    after = np.flatnonzero(smooth[top + 1000:] < 0.5 * level)
    stop = top + 1000 + (int(after[0]) if after.size else smooth.size - top - 1000) - 200
    curve = np.clip(fp[onset:stop], 0.0, None)
    return curve / max(float(curve.max()), 1e-9)


def bread_probing(duration_s, rate_hz, rng):
    """A bakery robot probing loaves for their core temperature. Each probe is the measured insertion
    (:func:`measured_probe`) stretched to 0.5-1.4 times its length and scaled to a 2.2-8.8 N peak (the crust); a third
    of the loaves hold an air pocket (15-30 % of the insertion, from 30-60 % of it on, at 30-60 % of the force, its
    edges eased over 40 ms). The probe dwells 3-8 s while the thermometer settles and the crumb relaxes by 15-40 %
    (0.5-2 s), then is withdrawn within 0.15-0.5 s. Loaves 4-12 s apart; every 6-12 loaves the rack is swapped
    (15-35 s). A train of synthetic punctures when the data are absent."""
    curve = measured_probe()
    if curve is None:
        return puncture_train(duration_s, rate_hz, rng)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cursor, count, rack = rng.uniform(1.0, 6.0), 0, int(rng.integers(6, 13))
    while True:
        n = max(8, int(curve.size / 1000.0 * rng.uniform(0.5, 1.4) * rate_hz))
        u = np.linspace(0.0, 1.0, n)
        push = rng.uniform(2.2, 8.8) * np.interp(u, np.linspace(0.0, 1.0, curve.size), curve)
        if rng.random() < 1.0 / 3.0:
            a, w, edge = rng.uniform(0.3, 0.6), rng.uniform(0.15, 0.3), 0.04 / max(n / rate_hz, 1e-3)
            pocket = ease((u - a) / edge) * (1.0 - ease((u - a - w) / edge))
            push *= 1.0 - (1.0 - rng.uniform(0.3, 0.6)) * pocket
        s = np.arange(int(rng.uniform(3.0, 8.0) * rate_hz)) / rate_hz
        dwell = push[-1] * (1.0 - rng.uniform(0.15, 0.4) * (1.0 - np.exp(-s / rng.uniform(0.5, 2.0))))
        last = float(dwell[-1]) if dwell.size else float(push[-1])
        n_out = int(rng.uniform(0.15, 0.5) * rate_hz) + 1
        out = last * (1.0 - ease(np.arange(1, n_out + 1) / n_out))
        one = np.concatenate([push, dwell, out])
        i0 = int(cursor * rate_hz)
        if i0 + one.size >= t.size:
            break
        f[i0:i0 + one.size] = one
        cursor += one.size / rate_hz + rng.uniform(4.0, 12.0)
        count += 1
        if count >= rack:
            cursor += rng.uniform(15.0, 35.0)
            count, rack = 0, int(rng.integers(6, 13))
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def dough_kneading(duration_s, rate_hz, rng):
    """A robot kneading bread dough. Batches of 30-90 s, 10-30 s apart. Within a batch, strokes at 0.4-0.8 Hz (each
    period 8 % either way): a push with the heel of the hand over 40-50 % of the period, reaching its peak within a
    third of it and flowing away by 15-30 % before the release; a fold back at 0.2-0.6 N over 25-35 %; a quarter turn off
    the dough for the rest. The peak, 1.5-4 N at first, grows by 30-80 % as the gluten develops (over 15-40 s), 10 % from
    stroke to stroke; every 6-10 strokes the dough is folded and turned (1-2.5 s off it). Smoothed over 60 ms."""
    knot_t, knot_f = [0.0], [0.0]

    def add(dt, level):
        knot_t.append(knot_t[-1] + max(dt, 1e-3))
        knot_f.append(level)

    add(rng.uniform(1.0, 8.0), 0.0)
    while knot_t[-1] < duration_s:
        start, length = knot_t[-1], rng.uniform(30.0, 90.0)
        hz, p0, grow, develop = rng.uniform(0.4, 0.8), rng.uniform(1.5, 4.0), rng.uniform(0.3, 0.8), rng.uniform(15.0, 40.0)
        until_turn = int(rng.integers(6, 11))
        while knot_t[-1] < start + length:
            period = rng.uniform(0.92, 1.08) / hz
            peak = p0 * (1.0 + grow * (1.0 - math.exp(-(knot_t[-1] - start) / develop))) * rng.uniform(0.9, 1.1)
            push, fold = rng.uniform(0.4, 0.5) * period, rng.uniform(0.25, 0.35) * period
            add(push * rng.uniform(0.25, 0.35), peak)
            add(push * 0.4, peak * rng.uniform(0.78, 0.9))
            add(push * 0.3, peak * rng.uniform(0.7, 0.85))
            light = rng.uniform(0.2, 0.6)
            add(0.08 * period, light)
            add(fold, light)
            add(0.06 * period, 0.0)
            add(max(period - push - fold - 0.14 * period, 0.02), 0.0)
            until_turn -= 1
            if until_turn <= 0:
                add(rng.uniform(1.0, 2.5), 0.0)
                until_turn = int(rng.integers(6, 11))
        add(rng.uniform(10.0, 30.0), 0.0)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    k = max(1, int(0.06 * rate_hz))
    f = np.convolve(np.interp(t, knot_t, knot_f), np.ones(k) / k, mode="same")
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def braille_embossing(duration_s, rate_hz, rng):
    """A robot embossing Braille with a slate and stylus. Each dot: a press rising as the power 1.5 of the time to the
    paper's yield (2.5-6 N per page, 8 % from dot to dot) within 40-120 ms, a give of 20-40 % within 10-25 ms as the
    paper stretches into the pit, the stylus bottoming out at 1.05-1.35 times the yield within 30-80 ms, held 30-80 ms,
    released within 30-60 ms. Dots 0.12-0.3 s apart, 1-5 dots a cell, cells 0.3-0.8 s apart, words of 2-7 cells with a
    space of 0.6-1.2 s, lines of 18-28 cells with 2-4 s to move the slate, pages of 4-6 lines with 20-40 s."""
    knot_t, knot_f = [0.0], [0.0]

    def add(dt, level):
        knot_t.append(knot_t[-1] + max(dt, 2e-4))
        knot_f.append(level)

    add(rng.uniform(1.0, 5.0), 0.0)
    while knot_t[-1] < duration_s:
        paper = rng.uniform(2.5, 6.0)
        for _ in range(int(rng.integers(4, 7))):
            cells, line = 0, int(rng.integers(18, 29))
            while cells < line:
                for _ in range(int(rng.integers(2, 8))):
                    for _ in range(int(rng.choice([1, 2, 2, 3, 3, 4, 5]))):
                        yield_n, rise = paper * rng.uniform(0.92, 1.08), rng.uniform(0.04, 0.12)
                        for u in (0.25, 0.5, 0.75, 1.0):
                            add(0.25 * rise, yield_n * u ** 1.5)
                        add(rng.uniform(0.01, 0.025), yield_n * (1.0 - rng.uniform(0.2, 0.4)))
                        bottom = yield_n * rng.uniform(1.05, 1.35)
                        add(rng.uniform(0.03, 0.08), bottom)
                        add(rng.uniform(0.03, 0.08), bottom)
                        add(rng.uniform(0.03, 0.06), 0.0)
                        add(rng.uniform(0.12, 0.3), 0.0)
                    add(rng.uniform(0.3, 0.8), 0.0)
                    cells += 1
                add(rng.uniform(0.6, 1.2), 0.0)
                if knot_t[-1] > duration_s:
                    break
            add(rng.uniform(2.0, 4.0), 0.0)
        add(rng.uniform(20.0, 40.0), 0.0)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    return t, np.clip(np.interp(t, knot_t, knot_f), 0.0, FORCE_MAX_N)


PROFILES = (bread_probing, dough_kneading, braille_embossing)


def bakery(t, rng, step_s=0.5):
    """A sensor on a robot in an artisan bakery, simulated from 900 s before the record. The room, 1.5 degC below to 1
    degC above the reference, warms by 0.5-3 degC an hour through the bake. The robot moves within 3-6 s between its
    bench, the deck ovens (1.5-3 degC warmer), a proofer (4-8 degC) and the flour store (2-5 degC cooler), staying 20-120
    s at each. The ovens' doors open every 40-150 s for 5-20 s, and their hot air (2-6 degC; a third of it at the bench)
    reaches the sensor within 2-5 s and clears over 20-60 s. A ceiling fan stirs the air (0.1-0.3 degC, 20-60 s). The
    sensor follows with 4-12 s (exact per step of ``step_s``)."""
    s = t - t[0]
    d = float(s[-1]) if s[-1] > 0 else 1.0
    grid = np.arange(-900.0, d + 2.0 * step_s, step_s)
    since = grid + 900.0
    room = T_REF_C + rng.uniform(-1.5, 1.0) + rng.uniform(0.5, 3.0) * since / 3600.0
    offsets = np.array([0.0, rng.uniform(1.5, 3.0), rng.uniform(4.0, 8.0), -rng.uniform(2.0, 5.0)])
    exposure = np.array([1.0 / 3.0, 1.0, 0.0, 0.0])
    here = int(rng.integers(4))
    knot_t, knot_o, knot_e = [-900.0], [offsets[here]], [exposure[here]]
    while knot_t[-1] < d + 10.0:
        knot_t.append(knot_t[-1] + rng.uniform(20.0, 120.0))
        knot_o.append(offsets[here])
        knot_e.append(exposure[here])
        here = int((here + rng.integers(1, 4)) % 4)
        knot_t.append(knot_t[-1] + rng.uniform(3.0, 6.0))
        knot_o.append(offsets[here])
        knot_e.append(exposure[here])
    station = np.interp(grid, knot_t, knot_o)
    door = within(since, schedule(rng, (40.0, 150.0), (5.0, 20.0), d + 1000.0)).astype(float)
    plume = rise_fall(rng.uniform(2.0, 6.0) * door * np.interp(grid, knot_t, knot_e),
                      math.exp(-step_s / rng.uniform(2.0, 5.0)), math.exp(-step_s / rng.uniform(20.0, 60.0)), start=0.0)
    keep = math.exp(-step_s / rng.uniform(20.0, 60.0))
    fan = first_order(rng.normal(0.0, 1.0, grid.size), keep, start=0.0)
    fan *= rng.uniform(0.1, 0.3) / max(float(np.std(fan)), 1e-9)
    sensor = first_order(room + station + plume + fan, math.exp(-step_s / rng.uniform(4.0, 12.0)))
    return np.interp(s, grid, sensor)


# ----------------------------------------------------------------------------- viscous flow

def unstable_contraction_leak(fluidity, on_n, off_n, ratio, onset_s, settle_s, step_s=0.01):
    """x' = A F / (1 + (r - 1) s): a core leaking a viscoelastic polymer solution through a micro-contraction at
    ``fluidity`` A V/(N s) while the flow is stable; once the force passes ``on_n`` the flow turns elastically unstable
    and stays so until it falls below ``off_n``, the unstable share s following within ``onset_s`` on the way in and
    ``settle_s`` on the way out, the resistance ``ratio`` r times higher when fully unstable. Per step of ``step_s``."""
    def rule(t, f):
        grid, fg = coarse(t, f, step_s)
        share = rise_fall(latch(fg, on_n, off_n).astype(float), math.exp(-step_s / onset_s), math.exp(-step_s / settle_s),
                          start=0.0)
        rate = fluidity * fg / (1.0 + (ratio - 1.0) * share)
        return np.interp(t, grid, integrate.cumulative_trapezoid(rate, grid, initial=0.0))
    return rule


def vibrated_paste_leak(fluidity, gain, corner_hz, window_s, shake_n):
    """x' = A F (1 + g sigma^2 / (sigma^2 + s^2)): a core of a dense paste at ``fluidity`` A V/(N s) at rest, fluidised by
    the load's own vibration, sigma the RMS of the force above ``corner_hz`` over the last ``window_s`` (:func:`hf_rms`),
    s ``shake_n``, up to 1 + ``gain`` times faster."""
    def rule(t, f):
        sigma2 = hf_rms(t, f, corner_hz, window_s) ** 2
        rate = fluidity * f * (1.0 + gain * sigma2 / (sigma2 + shake_n ** 2))
        return integrate.cumulative_trapezoid(rate, t, initial=0.0)
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def dilating_channel_kelvin(t, f, compliance, tau_s, stiff_n, step_s=0.005):
    """A Kelvin unit (``compliance`` V/N) whose oil passes into its pocket through a soft microchannel that its own
    pressure dilates (Gervais): the pocket's force q follows q' = (E / 4 tau) ((1 + F / E)^4 - (1 + q / E)^4), E
    ``stiff_n``, tau ``tau_s`` for small steps. Implicit (one Newton step) per step of ``step_s``, from rest."""
    grid, fg = coarse(t, f, step_s)
    a, q = stiff_n / (4.0 * tau_s), 0.0
    out = np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        drive = (1.0 + max(fi, -0.9 * stiff_n) / stiff_n) ** 4
        base = 1.0 + q / stiff_n
        q += step_s * a * (drive - base ** 4) / (1.0 + step_s * a * 4.0 * base ** 3 / stiff_n)
        q = max(q, -0.9 * stiff_n)
        out[i] = q
    return compliance * np.interp(t, grid, out)


def soft_lce_pad(t, f, plateau_v, threshold_n, span_n, tau1_s, step_s=0.01):
    """A polydomain liquid-crystal elastomer pad: its directors' rotated share s heads for (F - ``threshold_n``) /
    ``span_n`` held within [0, 1] at a rate (0.25 N + |F - threshold|) / (1.25 N ``tau1_s``), adding ``plateau_v`` s.
    Exact per step of ``step_s``, from rest."""
    grid, fg = coarse(t, f, step_s)
    goal = np.clip((fg - threshold_n) / span_n, 0.0, 1.0)
    keep = np.exp(-step_s * (0.25 + np.abs(fg - threshold_n)) / (1.25 * tau1_s))
    s, out = 0.0, np.empty(grid.size)
    for i, (g, k) in enumerate(zip(goal.tolist(), keep.tolist())):
        s = g + (s - g) * k
        out[i] = s
    return plateau_v * np.interp(t, grid, out)


# ----------------------------------------------------------------------------- hysteresis

class TouchModeCollapse(SimOnly):
    """A touch-mode capacitive read-out: its diaphragm, softened by its bias after the parallel-plate law (the excess
    deflection of w - b / (1 - w)^2 + b = v, pulling in at w = 1/3), reads ``soft_v`` more at its pull-in; it
    collapses once the core's output reaches ``collapse_v`` and then reads ``down_v`` more, until the output falls to
    ``release_v`` (adhesion). The first sample reads as the plain output."""

    def __init__(self, collapse_v, release_v, down_v, soft_v):
        self.up, self.release, self.down, self.soft = collapse_v, release_v, down_v, soft_v
        w = np.linspace(-0.6, 1.0 / 3.0, 801)
        v = w - (4.0 / 27.0) / (1.0 - w) ** 2 + 4.0 / 27.0
        self.v, self.e = v / v[-1], (w - v) / (w - v)[-1]

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        free = self.soft * np.interp(x / self.up, self.v, self.e)
        y = x + np.where(latch(x, self.up, self.release), self.down, free)
        return y - (y[0] - x[0])


def kresling_stack(f, snaps_n, backs_n, drops_v, fold):
    """The deflection of a stack of bistable Kresling cells: each snaps flat at its force in ``snaps_n``, adding its
    share of ``drops_v``, and springs back once the force falls to its ``backs_n``; each branch softens toward its fold
    as the square root of the distance (``fold`` of the drop). Zero at the first sample."""
    out = np.zeros(f.size)
    for up, back, drop in zip(snaps_n, backs_n, drops_v):
        flat = latch(f, up, back)
        stand = drop * fold * (1.0 - np.sqrt(np.clip(1.0 - f / up, 0.0, 1.0)))
        lying = drop * (1.0 - fold * (1.0 - np.sqrt(np.clip((f - back) / (up - back), 0.0, 1.0))))
        out += np.where(flat, lying, stand)
    return out - out[0]


# ----------------------------------------------------------------------------- sensor lag

class BubblyLine(SimOnly):
    """A hydraulic line carrying entrained air between the core and the transducer (Wood's law): the transit ``transit_s``
    unloaded shortens as 1 / sqrt(1 + (s - 1) u), u the core's output over ``reach_v`` (held within [0, 1.5]), s
    ``swell`` the line's absolute pressure at reach over the atmosphere's; a first-order lag of ``lag_share`` of the
    transit behind it. The transit is found from the output it carries, by three successive passes."""

    def __init__(self, transit_s, swell, reach_v, lag_share):
        self.transit, self.swell, self.reach, self.lag = transit_s, swell, reach_v, lag_share * transit_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        d = np.full(t.size, self.transit)
        for _ in range(3):
            seen = np.interp(t - d, t, x, left=x[0])
            d = self.transit / np.sqrt(1.0 + (self.swell - 1.0) * np.clip((seen - x[0]) / self.reach, 0.0, 1.5))
        return lagged(t, np.interp(t - d, t, x, left=x[0]), self.lag)


class BlockSmoother(SimOnly):
    """A host that smooths the stream in blocks of ``block_s`` (the first ``phase`` of a block into the record)
    forward and backward through a second-order Butterworth low-pass of time constant ``tau_s`` (zero-phase inside each
    block, odd extension at its seams). On a uniform grid at the median step."""

    def __init__(self, tau_s, block_s, phase):
        self.tau, self.block, self.phase = tau_s, block_s, phase

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        sos = signal.butter(2, min(1.0 / (2.0 * math.pi * self.tau), 0.4 / h), fs=1.0 / h, output="sos")
        n = max(16, int(round(self.block / h)))
        z, y = xu - xu[0], np.empty(xu.size)
        edges = [0, *range(int(self.phase * n) % n or n, z.size, n), z.size]
        for i0, i1 in zip(edges[:-1], edges[1:]):
            seg = z[i0:i1]
            y[i0:i1] = signal.sosfiltfilt(sos, seg, padlen=min(seg.size - 1, 9)) if seg.size > 3 else seg
        return np.interp(t, tu, y + xu[0])


# ----------------------------------------------------------------------------- nonlinear gain

def focus_error_read(rel, reach, sep, z0, way):
    """x read by an astigmatic focus-error detector: the four-quadrant signal of an elliptical Gaussian spot,
    arcsin(2 a z / (1 + z^2)) / 2 a, z the defocus in units of the spot's depth (a ``sep`` the line foci's half
    separation), z = ``z0`` + ``way`` k x / reach; slope 1 at no load, k for a departure of ``rel`` at reach."""
    def fes(z):
        return np.arcsin(2.0 * sep * z / (1.0 + z * z)) / (2.0 * sep)
    slope = float(fes(z0 + 1e-6) - fes(z0 - 1e-6)) / 2e-6

    def read(x, k):
        u = np.clip(x / reach, -0.3, 1.3)
        return (fes(z0 + way * k * u) - fes(z0)) / (way * k * slope) * reach
    return fit_departure(read, rel, reach, (0.97 - way * z0) / 1.3)


def chromatic_read(rel, reach, glass_a, glass_b, lam0, way):
    """x read by a chromatic confocal probe: a lens of Cauchy glass (n = ``glass_a`` + ``glass_b`` / lambda^2, um)
    focuses ``lam0`` um on the mirror at rest; the load moves the mirror (``way``) by k of the focal length over
    ``reach`` and the read is the wavelength then in focus; slope 1 at no load, k for a departure of ``rel`` at reach
    (the focus kept within 0.38-0.9 um)."""
    d0 = glass_a - 1.0 + glass_b / lam0 ** 2

    def lam(z):
        return np.sqrt(glass_b / np.maximum(d0 / z - (glass_a - 1.0), 1e-6))

    def focal(wave):
        return d0 / (glass_a - 1.0 + glass_b / wave ** 2)
    slope = float(lam(1.0 + 1e-6) - lam(1.0 - 1e-6)) / 2e-6

    def read(x, k):
        u = np.clip(x / reach, -0.3, 1.3)
        return (lam(1.0 + way * k * u) - lam0) / (way * k * slope) * reach
    return fit_departure(read, rel, reach, ((focal(0.9) - 1.0) if way > 0 else (1.0 - focal(0.38))) / 1.3)


# ----------------------------------------------------------------------------- thermal drift

def thermosiphon_zero(t, temp, k_v_per_c, flange_c, air_s, pipe_s, onset_c, step_s=0.25):
    """k (T_h - T_ref): a housing that follows the air with ``air_s`` and is tied to the robot's flange (``flange_c``) by
    a thermosiphon that works only while the housing is warmer than the flange by ``onset_c`` (a logistic over 0.1
    degC), pulling it toward the flange with ``pipe_s``. Exact per step of ``step_s``, settled at the start."""
    grid, air = coarse(t, temp, step_s)

    def pull(h):
        return 1.0 / (1.0 + math.exp(-(h - flange_c - onset_c) / 0.1))
    h = float(air[0])
    for _ in range(200):
        on = pull(h)
        h = (air[0] / air_s + on * flange_c / pipe_s) / (1.0 / air_s + on / pipe_s)
    out = np.empty(grid.size)
    for i, ta in enumerate(air.tolist()):
        on = pull(h)
        rate = 1.0 / air_s + on / pipe_s
        goal = (ta / air_s + on * flange_c / pipe_s) / rate
        h = goal + (h - goal) * math.exp(-step_s * rate)
        out[i] = h
    return k_v_per_c * (np.interp(t, grid, out) - T_REF_C)


def hydrogel_zero(t, temp, k_v_per_c, lag_s, where, width_c, swell_s, slower, step_s=0.5):
    """The zero of a read-out pressed by a thermoresponsive hydrogel cushion (lag ``lag_s``): its swollen share at
    equilibrium 1 - logistic((T - T_c) / ``width_c``), T_c at the ``where`` quantile of its temperature over the record,
    which the cushion follows within ``swell_s`` as it swells and ``slower`` times slower as it shrinks; ``k_v_per_c``
    at the steepest. Per step of ``step_s``, settled at the start."""
    grid, tg = coarse(t, follow(t, temp, lag_s), step_s)
    eq = 1.0 - logistic((tg - float(np.quantile(tg, where))) / width_c)
    held = rise_fall(eq, math.exp(-step_s / swell_s), math.exp(-step_s / (slower * swell_s)))
    return k_v_per_c * 4.0 * width_c * np.interp(t, grid, held)


# ----------------------------------------------------------------------------- thermal sensitivity

class VcselSpan(SimOnly):
    """The span of an optical read-out lit by a vertical-cavity laser at a constant current: exp(-(d / w)^2) over its value
    at the reference, d the gain peak's detuning from the cavity mode, moving ``shift_nm`` per degC of the laser's
    temperature (lag ``lag_s``), w ``width_nm``, d at the reference set for ``tc`` per degC."""

    def __init__(self, tc, width_nm, shift_nm, lag_s):
        self.w, self.s, self.lag = width_nm, shift_nm, lag_s
        self.d0 = -tc * width_nm ** 2 / (2.0 * shift_nm)

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = self.d0 + self.s * np.clip(follow(t, temp_of(aux, t.size), self.lag) - T_REF_C, -25.0, 25.0)
        return np.asarray(x, dtype=float) * np.exp((self.d0 / self.w) ** 2 - (d / self.w) ** 2)


class WienNtcSpan(SimOnly):
    """The span of a carrier bridge excited from a Wien-bridge oscillator whose amplitude an NTC thermistor stabilises:
    the thermistor held at a set temperature 1 / (2 ``tc``) above the reference, the amplitude as the square root of
    its margin over the board's temperature (lag ``lag_s``), held above 5 % of its power."""

    def __init__(self, tc, lag_s):
        self.margin, self.lag = 1.0 / (2.0 * tc), lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        return np.asarray(x, dtype=float) * np.sqrt(np.clip(1.0 - d / self.margin, 0.05, None))


# ----------------------------------------------------------------------------- offset drift

def vacuum_hose(rng, step_s=0.02):
    """The pull of the robot's vacuum hose on the read-out's cable: each pick (1-8 s every 4-30 s) evacuates it within
    0.2-0.6 s, a pull of 1 (10 % from pick to pick) that relaxes by 20-40 % over 2-10 s; each release vents it within
    0.1-0.3 s, leaving 5-15 % that recovers over 20-60 s. As a function of the seconds since the first sample, zero
    there."""
    grid = np.arange(-60.0, HORIZON_S + step_s, step_s)
    out = np.zeros(grid.size)
    relax, relax_s, rise_s = rng.uniform(0.2, 0.4), rng.uniform(2.0, 10.0), rng.uniform(0.2, 0.6) / 3.0
    vent_s, kept, kept_s = rng.uniform(0.1, 0.3) / 3.0, rng.uniform(0.05, 0.15), rng.uniform(20.0, 60.0)
    for start, length in schedule(rng, (4.0, 30.0), (1.0, 8.0), HORIZON_S):
        pull, u = rng.normal(1.0, 0.1), grid - start
        held = pull * (1.0 - relax * (1.0 - np.exp(-np.clip(u, 0.0, None) / relax_s)))
        out += np.where((u >= 0.0) & (u < length), held * (1.0 - np.exp(-np.clip(u, 0.0, None) / rise_s)), 0.0)
        last = pull * (1.0 - relax * (1.0 - math.exp(-length / relax_s))) * (1.0 - math.exp(-length / rise_s))
        v = np.clip(u - length, 0.0, None)
        out += np.where(u >= length, last * (kept * np.exp(-v / kept_s) + (1.0 - kept) * np.exp(-v / vent_s)), 0.0)
    first = float(np.interp(0.0, grid, out))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, out) - first


def drag_chain(rng, step_s=0.05):
    """The pull of a linear axis's drag chain on the read-out's cable: the axis moves every 10-60 s to another position
    within 1-4 s (minimum jerk); the pull p + a p^2 of the position (a 0.3-1) passed through the links' friction (a play
    of 10-30 % of its range). As a function of the seconds since the first sample, zero there."""
    grid = np.arange(-60.0, HORIZON_S + step_s, step_s)
    where = poses(rng, (10.0, 60.0), (1.0, 4.0), 0.0, 1.0)(grid)
    a = rng.uniform(0.3, 1.0)
    r = 0.5 * rng.uniform(0.1, 0.3) * (1.0 + a)
    held = band_play(where + a * where ** 2, r, r)
    first = float(np.interp(0.0, grid, held))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, held) - first


# ----------------------------------------------------------------------------- resonance

class HarvesterMode(GridMode):
    """A holder's mode at ``f0_hz`` (damping ratio ``zeta``) carrying an electromagnetic harvester that charges a cell
    through a bridge rectifier: it pulls c (|v| - v_d) against the motion only while the speed passes v_d, ``threshold``
    of the largest a linear mode would reach, c ``boost`` times the holder's own damping. Semi-implicit Euler on a
    uniform grid of ``fs`` Hz, from rest."""

    fs = 3000.0

    def __init__(self, f0_hz, zeta, threshold, boost):
        self.w, self.zeta, self.threshold, self.boost = 2.0 * math.pi * f0_hz, zeta, threshold, boost

    def on_grid(self, t, tu, xu, h):
        _, speed = plain_mode(xu, self.w, self.zeta, self.fs)
        v_d = self.threshold * max(float(np.max(np.abs(speed))), 1e-12)
        c, ws = 2.0 * self.zeta * self.w, self.w * self.w
        ch = self.boost * c
        accel = np.gradient(np.gradient(xu, h), h).tolist()
        z = vz = 0.0
        out = np.empty(tu.size)
        for i, (ui, ai) in enumerate(zip(xu.tolist(), accel)):
            over = abs(vz) - v_d
            vz += (-ai - c * vz - ws * z - (math.copysign(ch * over, vz) if over > 0.0 else 0.0)) * h
            z += vz * h
            out[i] = ui + z
        return out


class RockingBase(GridMode):
    """A holder's mode at ``f0_hz`` (damping ratio ``zeta``) on a magnetic base that rocks on its edge once the motion
    passes ``uplift`` of the largest a linear mode would reach: beyond it the restoring force no longer grows and
    weakens by ``soften`` per such width (at least a fifth stays), the damping a fifth of the seated one, and each
    landing keeps ``restitution`` of the speed. Semi-implicit Euler on a uniform grid of ``fs`` Hz, from rest."""

    fs = 3000.0

    def __init__(self, f0_hz, zeta, uplift, soften, restitution):
        self.w, self.zeta, self.uplift, self.soften, self.keep = 2.0 * math.pi * f0_hz, zeta, uplift, soften, restitution

    def on_grid(self, t, tu, xu, h):
        reach, _ = plain_mode(xu, self.w, self.zeta, self.fs)
        zu = self.uplift * max(float(np.max(np.abs(reach))), 1e-12)
        c, ws = 2.0 * self.zeta * self.w, self.w * self.w
        accel = np.gradient(np.gradient(xu, h), h).tolist()
        z = vz = 0.0
        out = np.empty(tu.size)
        for i, (ui, ai) in enumerate(zip(xu.tolist(), accel)):
            size = abs(z)
            if size <= zu:
                vz += (-ai - c * vz - ws * z) * h
            else:
                hold = ws * zu * max(1.0 - self.soften * (size - zu) / zu, 0.2)
                vz += (-ai - 0.2 * c * vz - math.copysign(hold, z)) * h
            znew = z + vz * h
            if size > zu >= abs(znew):
                vz *= self.keep
            z = znew
            out[i] = ui + z
        return out


# ----------------------------------------------------------------------------- friction

class TiltingCarriage(SimOnly):
    """The force passed by a needle guide on a carriage whose weight presses its shoes as the robot tilts the tool:
    the band ``band_n`` (floor + (1 - floor) |sin(tilt)|), ``floor`` the preload's share, the tilt ``tilt(seconds)``."""

    def __init__(self, band_n, floor, tilt):
        self.band, self.floor, self.tilt = band_n, floor, tilt

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        band = self.band * (self.floor + (1.0 - self.floor) * np.abs(np.sin(self.tilt(t - t[0]))))
        return band_play(np.asarray(x, dtype=float), band, band)


class NibbledSeal(SimOnly):
    """The force passed by a guide sealed by an O-ring that the pressure nibbles into its clearance whenever the force
    passes ``extrude_n``: its band ``band_n`` (1 + ``growth`` e) (at most threefold), e the largest excess so far over
    that force in its units, ``recover`` of each rise of e recovering with ``recover_s``. Per step of ``step_s``."""

    def __init__(self, band_n, extrude_n, growth, recover, recover_s, step_s=0.02):
        self.band, self.at, self.growth = band_n, extrude_n, growth
        self.recover, self.recover_s, self.step = recover, recover_s, step_s

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        grid, fg = coarse(t, f, self.step)
        keep, kept, back = math.exp(-self.step / self.recover_s), 0.0, 0.0
        e = np.empty(grid.size)
        for i, fi in enumerate(fg.tolist()):
            back *= keep
            rise = max(fi - self.at, 0.0) / self.at - (kept + back)
            if rise > 0.0:
                kept, back = kept + (1.0 - self.recover) * rise, back + self.recover * rise
            e[i] = kept + back
        band = self.band * np.minimum(1.0 + self.growth * np.interp(t, grid, e), 3.0)
        return band_play(f, band, band)


# ----------------------------------------------------------------------------- thermo-rheological

class HallerClock(SimOnly):
    """A core of a liquid-crystal elastomer whose dashpots follow its order parameter (Haller: S = (1 - T / T_NI)^beta,
    T_NI ``above_k`` above the reference, beta ``beta``): ln eta = E / T + C S, ``share`` of ``b_per_c`` per degC at the
    reference from the Arrhenius term. On the core's temperature (lag ``lag_s``), the clock held within e^+-6."""

    def __init__(self, c, b_per_c, above_k, beta, share, lag_s):
        self.c, self.beta, self.lag = c, beta, lag_s
        self.tr = T_REF_C + 273.15
        self.tni = self.tr + above_k
        self.e = share * b_per_c * self.tr ** 2
        self.cc = (1.0 - share) * b_per_c * self.tni / (beta * (1.0 - self.tr / self.tni) ** (beta - 1.0))

    def log_eta(self, kelvin):
        return self.e / kelvin + self.cc * np.clip(1.0 - kelvin / self.tni, 1e-4, None) ** self.beta

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag) + 273.15
        log_rate = float(self.log_eta(self.tr)) - self.log_eta(body)
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(log_rate, -6.0, 6.0)))


class MicelleClock(SimOnly):
    """A core filled with a thermogelling poloxamer: its micelles' share r of the packing limit a logistic in the
    temperature, ``packed`` at the reference, ``ceiling`` at most; the viscosity as (1 - r)^-1.6 (Krieger and Dougherty)
    times the water's own (-2.45 %/degC), the logistic's width set for the clock to slow by ``b_per_c`` per degC at the
    reference. On the core's temperature (lag ``lag_s``), the clock held within e^+-6."""

    water = 0.0245

    def __init__(self, c, b_per_c, packed, ceiling, lag_s):
        self.c, self.top, self.lag = c, ceiling, lag_s
        self.w = 1.6 * packed * (1.0 - packed / ceiling) / ((1.0 - packed) * (b_per_c + self.water))
        self.mid = T_REF_C - self.w * math.log(packed / (ceiling - packed))
        self.ref = -1.6 * math.log(1.0 - packed)

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag)
        r = self.top * logistic((body - self.mid) / self.w)
        log_eta = -1.6 * np.log(np.maximum(1.0 - r, 1e-6)) - self.water * (body - T_REF_C)
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(self.ref - log_eta, -6.0, 6.0)))


# ----------------------------------------------------------------------------- outside the catalogue

class EncoderOverspeed(SimOnly):
    """The core's deflection counted by an incremental encoder whose decoder loses ``share`` of the counts whenever the
    deflection moves faster than it can follow (the ``quantile`` of the speed over the record): the lost counts pile
    up as a zero that walks at each fast swing. On a uniform grid at the median step."""

    def __init__(self, share, quantile):
        self.share, self.q = share, quantile

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        v = np.gradient(xu, h)
        limit = float(np.quantile(np.abs(v), self.q))
        lost = np.cumsum(self.share * np.clip(np.abs(v) - limit, 0.0, None) * np.sign(v)) * h
        return x - np.interp(t, tu, lost)


class GlitchFilter(SimOnly):
    """Firmware that holds the last accepted sample whenever the next differs from it by more than the ``quantile`` of
    the record's sample-to-sample steps, and accepts again after ``patience`` rejections in a row."""

    def __init__(self, quantile, patience):
        self.q, self.patience = quantile, patience

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        limit = float(np.quantile(np.abs(np.diff(x)), self.q))
        out, last, held = np.empty(x.size), float(x[0]), 0
        for i, xi in enumerate(x.tolist()):
            if abs(xi - last) > limit and held < self.patience:
                held += 1
            else:
                last, held = xi, 0
            out[i] = last
        return out


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
        if shape == "unstable_contraction":
            on = rng.uniform(2.0, 5.0)
            rule = unstable_contraction_leak(phi * rng.uniform(2.0, 4.0), on, on * rng.uniform(0.55, 0.85), rng.uniform(2.0, 4.0),
                                             rng.uniform(0.2, 1.5), rng.uniform(1.0, 5.0))
        else:
            rule = vibrated_paste_leak(phi * rng.uniform(0.5, 1.0), rng.uniform(2.0, 8.0), rng.uniform(2.0, 6.0),
                                       rng.uniform(0.1, 0.5), rng.uniform(0.05, 0.4))
        return Parts("zener", LeakingCore.of(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        share = float(np.interp(m, [0, 1], [0.05, 0.23]))  # of the instantaneous response
        if shape == "dilating_microchannel":
            a = (share / g0, rng.uniform(2.0, 20.0), rng.uniform(1.5, 6.0))
            p.extra.append(lambda t, f, T, a=a: dilating_channel_kelvin(t, f, *a))
            return p
        threshold, span = rng.uniform(0.5, 2.5), rng.uniform(2.0, 5.0)
        a = (share * (threshold + span) / g0, threshold, span, rng.uniform(1.0, 12.0))
        p.extra.append(lambda t, f, T, a=a: soft_lce_pad(t, f, *a))
        return p
    if effect == "hysteresis":
        wid = float(np.interp(m, [0, 1], [0.02, 0.075]))
        if shape == "touch_mode_collapse":
            up = rng.uniform(0.3, 0.65) * top
            p.after.append(TouchModeCollapse(up, up * rng.uniform(0.55, 0.85), wid * top, rng.uniform(0.25, 0.5) * wid * top))
            return p
        n = int(rng.integers(3, 7))
        snaps = np.sort(rng.uniform(1.5, 7.0, n))
        a = (snaps, snaps * rng.uniform(0.35, 0.7, n), wid * top * rng.dirichlet(np.full(n, 3.0)), rng.uniform(0.15, 0.3))
        p.extra.append(lambda t, f, T, a=a: kresling_stack(f, *a))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.012, 0.1]))))
        if shape == "bubbly_oil_line":
            p.after.append(BubblyLine(delay, rng.uniform(3.0, 9.0), top, rng.uniform(0.1, 0.25)))
            return p
        p.after.append(BlockSmoother(delay, rng.uniform(0.25, 1.0), rng.uniform(0.0, 1.0)))
        return p
    if effect == "nonlinear_gain":
        rel, way = float(np.interp(m, [0, 1], [0.05, 0.19])), float(rng.choice([-1.0, 1.0]))
        if shape == "astigmatic_focus":
            p.after.append(StaticMap(focus_error_read(rel, top, rng.uniform(0.4, 0.85), rng.uniform(-0.35, 0.35), way)))
            return p
        p.after.append(StaticMap(chromatic_read(rel, top, rng.uniform(1.5, 1.75), rng.uniform(0.004, 0.02),
                                                rng.uniform(0.45, 0.6), way)))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.008, 0.032]) * rng.choice([-1, 1]))
        if shape == "thermosiphon_flange":
            air = rng.uniform(20.0, 80.0)
            a = (k, T_REF_C + rng.uniform(-0.5, 2.5), air, air / rng.uniform(4.0, 12.0), rng.uniform(0.1, 0.6))
            p.extra.append(lambda t, f, T, a=a: thermosiphon_zero(t, T, *a))
            return p
        a = (k, rng.uniform(5.0, 20.0), rng.uniform(0.35, 0.65), rng.uniform(0.4, 1.0), rng.uniform(15.0, 60.0),
             rng.uniform(2.0, 5.0))
        p.extra.append(lambda t, f, T, a=a: hydrogel_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        tc = float(np.interp(m, [0, 1], [0.014, 0.035]))
        if shape == "vcsel_detuning":
            shift = rng.uniform(0.21, 0.25)
            width = min(rng.uniform(8.0, 16.0), 1.3 * shift / tc)
            p.after.append(VcselSpan(tc * float(rng.choice([-1.0, 1.0])), width, shift, rng.uniform(3.0, 15.0)))
            return p
        p.after.append(WienNtcSpan(tc, rng.uniform(5.0, 25.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.02, 0.096]) * rng.choice([-1, 1]))
        zero = sized(vacuum_hose(rng) if shape == "vacuum_hose" else drag_chain(rng), size, HORIZON_S)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.028, 0.0042])) * rng.uniform(0.8, 1.2)
        if shape == "rectified_harvester":
            p.after.append(HarvesterMode(rng.uniform(15.0, 45.0), zeta, rng.uniform(0.2, 0.6), rng.uniform(2.0, 6.0)))
            return p
        p.after.append(RockingBase(rng.uniform(15.0, 45.0), zeta, rng.uniform(0.15, 0.5), rng.uniform(0.1, 0.4),
                                   rng.uniform(0.6, 0.9)))
        return p
    if effect == "friction":
        band = float(np.interp(m, [0, 1], [0.0035, 0.046]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "tilting_carriage":
            tilt = poses(rng, (5.0, 40.0), (0.5, 2.0), 0.0, 0.5 * math.pi)
            p.before.append(TiltingCarriage(band, rng.uniform(0.15, 0.35), tilt))
            return p
        p.before.append(NibbledSeal(band, rng.uniform(2.0, 5.0), rng.uniform(0.5, 1.5), rng.uniform(0.4, 0.8),
                                    rng.uniform(20.0, 120.0)))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.16, 0.48])) * rng.uniform(1.2, 1.5)
        if shape == "haller_clock":
            return Parts("burgers", HallerClock(c, b, rng.uniform(15.0, 40.0), rng.uniform(0.15, 0.25), rng.uniform(0.3, 0.6),
                                                rng.uniform(5.0, 25.0)), core_changed=True)
        return Parts("burgers", MicelleClock(c, b, rng.uniform(0.5, 0.8), rng.uniform(0.9, 0.97), rng.uniform(5.0, 25.0)),
                     core_changed=True)
    if effect == "encoder_overspeed":
        p.after.append(EncoderOverspeed(float(np.interp(m, [0.4, 0.9], [0.02, 0.08])),
                                        float(np.interp(m, [0.4, 0.9], [0.995, 0.97]))))
        return p
    if effect == "glitch_filter":
        patience = int(round(float(np.interp(m, [0.4, 0.9], [6.0, 16.0])) * rng.uniform(0.85, 1.0)))
        p.outer.append(GlitchFilter(float(np.interp(m, [0.4, 0.9], [0.985, 0.965])), max(patience, 4)))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["unstable_contraction", "vibrated_paste"],
    "delayed_elasticity": ["dilating_microchannel", "semi_soft_lce_pad"],
    "hysteresis": ["touch_mode_collapse", "kresling_stack"],
    "sensor_lag": ["bubbly_oil_line", "block_smoother"],
    "nonlinear_gain": ["astigmatic_focus", "chromatic_confocal"],
    "thermal_drift": ["thermosiphon_flange", "hydrogel_cushion"],
    "thermal_sensitivity": ["vcsel_detuning", "ntc_wien_oscillator"],
    "offset_drift": ["vacuum_hose", "drag_chain"],
    "resonance": ["rectified_harvester", "rocking_magnetic_base"],
    "friction": ["tilting_carriage", "nibbled_oring"],
    "thermo_rheological": ["haller_clock", "poloxamer_clock"],
}
PAIRS = (("viscous_flow", "nonlinear_gain"), ("delayed_elasticity", "sensor_lag"), ("hysteresis", "thermal_drift"),
         ("resonance", "thermal_sensitivity"), ("friction", "offset_drift"), ("thermo_rheological", "hysteresis"))
OUTSIDE = ("encoder_overspeed", "glitch_filter")
RATES = (175.0, 355.0, 745.0, 1220.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split AI", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.33, 0.85),
                   pair_shapes=(-1, 0), rates=RATES, profiles=PROFILES, temperature=bakery,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(0.56e-3, 2.17e-3), jitter=0.33,
                   gap_s=(0.17, 1.85))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
