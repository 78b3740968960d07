"""Independent split AE for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split AE is an untouched held-out set: written blind to the engine it measures (to how it detects and fits anything),
run once, and nothing is ever chosen from it. Every name of the catalogue is hidden in two shapes that neither the
registry's families (``polyforce_ros/sim/truths.py``) nor splits A to AD use:

* a core leaking through a porous wall by Darcy and Forchheimer (the force as a q + b q^2 of the leak rate q, the
  inertial term equal to the viscous one at 0.8-3 N: linear at light loads, as the square root at heavy ones; 1.5-3
  times the plain fluidity of 1/46000-1/3800 V/(N s) at light loads), or a core whose leaking oil warms with the power
  it dissipates (F^2 followed over 20-120 s) and thins (its fluidity, 0.7-1.2 times the plain one cold, rising toward
  2-5 times its cold value, half-way there under a sustained 3 N); neither ever recovers;
* a flexure whose thermoelastic relaxation (Zener: the adiabatic strain of a loaded beam relaxing to the isothermal one
  as heat diffuses across it, eight terms of the diffusion series, weights 1/(2n+1)^2 and times tau/(2n+1)^2, tau
  3-40 s), or a Kelvin unit whose dashpot's bellows has a flap valve (the oil passes the open flap 3-10 times faster
  than the bleed hole, 0.4-4 s, opening on loading or on unloading); 3.5-21 % of the instantaneous response;
* a wireless node that reports by exception (a new reading sent only once the reading has moved by a dead band of
  1.7-6.8 % of the range from the last one sent; the receiver holds the last), or a read-out diaphragm that oil-cans
  (it snaps through to its other dimple as the reading passes 45-80 % of the range and back below 15-40 %, the reading
  offset by the same 1.7-6.8 % meanwhile, either way);
* a hydraulic read-out whose pressure reaches the transducer through a long dead-ended capillary (a diffusion line,
  1 / cosh(sqrt(s tau)), as a cascade of its first twenty poles and one for the rest), or firmware smoothing with a
  causal Gaussian FIR (truncated at +-3 sigma, linear phase); 10-95 ms of mean delay;
* a laser triangulation read-out (the spot on its detector as the inverse of the target's distance, which the load
  shortens: expansive, or lengthens: compressive), or a semiconductor gauge in a quarter bridge (the silicon's
  quadratic piezoresistance, r = G e (1 + q G e), q 1.5-2.5 for p-type or -0.3-0 for n-type, through the bridge's r /
  (2 (2 + r))); 5-18.5 % at the top of the range;
* the zero of a piezoelectric element's pyroelectric charge drained through its input resistance (the element's
  temperature, lag 5-25 s, less its own follower with 20-150 s: it answers changes and forgets them), or of an
  amplifier whose JFET input's gate leakage through the bridge's resistance doubles every 8-12 degC (lag 5-30 s); a
  coefficient of 0.0075-0.031 V/degC (the leakage's at the reference);
* the span of an optical read-out lit by an amber AlGaInP LED (its flux as exp(-dT / T1), the photodiode's
  responsivity rising 0.05-0.2 %/degC; lag 5-30 s), or of a resistive read-out through an electrolyte read with a
  constant current (its conductivity Vogel-Fulcher, T0 150-200 K: the span as the inverse; lag 10-40 s); 1.25-3.3
  %/degC at the reference;
* the zero of a charge amplifier whose input leakage integrates on its feedback capacitor (a current wandering by
  10-30 % about its mean over 60-200 s, drained by its feedback resistor with 100-600 s) and which a reset switch
  empties every 40-160 s, or of an unshielded piezoresistive die's photocurrent (a window's sun through passing
  clouds of 20-120 s that keep 20-60 % of it, the room's lights switched on or off 0-2 times, worth 20-50 % of the
  sun); 17-92 mV at most;
* a needle holder's mode (14-44 Hz) damped also by air drag (velocity-squared: 1.5-5 times the linear damping at the
  largest speed a linear mode reaches), or one that hits a rubber bump stop at 25-70 % of the largest relative motion
  a linear mode would give (2-6 times stiffer beyond it); damping ratio 0.004-0.036 at rest, the small-amplitude
  frequency fixed;
* a Coulomb band of 0.26-4.8 % of the range: a needle in a recirculating-ball bushing whose band ripples with the
  force (the balls passing the load zone: 30-70 % about the mean every 0.4-1.5 N), or a greased needle guide whose
  grease stiffens as it cools (the band as exp(-alpha (T - T_mean)), alpha 4-10 %/degC, T the guide's, lag 10-40 s);
* a core (soft enough for its clock to show) whose clock follows Ngai's coupling model (tau = (t_c^-n tau_0)^(1 /
  (1 - n)), tau_0 Arrhenius, t_c 2 ps, the coupling n 0.3-0.55 at the reference and rising 0.005-0.02 per degC
  colder), or a core whose binder crosses its glass transition 1-5 degC from the reference (the slope of ln tau
  switching from 30-50 % of its rubbery value below T_g to all of it above, over 0.5-1.5 degC); 1.2-1.5 times
  0.16-0.48 per degC at the reference, lag 5-25 s.

It also holds six pairs, two effects outside the catalogue (a slip ring in the read-out's leads whose contacts crackle
while the wrist turns, bouts of 1-6 s every 10-40 s of band-limited noise 10-50 mV RMS; a 16-bit ADC of +-10 V (305
uV codes) with one bit stuck high or low, that bit worth 20-78 mV) and four clean records. Profiles: vibration-assisted
needle insertions along the measured Okamura curve (``../shared/data``, ``time_force.csv``, at 0.7-1.8 times its length and
a 2.5-8.8 N peak; in half the sites an axial vibration of 4-15 Hz, 8-20 % of the force, runs until the puncture and
lowers the force by 20-45 %; a hold of 1-4 s, then the measured withdrawal; sites 6-20 s apart; a train of synthetic
punctures when the data are absent); a nasopharyngeal swab robot (insertion along the nasal floor with 2-4 turbinate
contacts, the posterior wall at 1.5-6 N, 10-15 s of rotation that makes the force wobble by 10-30 % at 0.5-1.5 Hz, a
flinch in a third of them, withdrawal); and a robot testing keyboard switches (tactile, linear or clicky: the force
against travel with a preload, a tactile peak, a drop and a bottom-out up to 2-8.8 N, slow characterisation strokes
and typing bursts at 3-8 Hz, a new switch every 20-60 s). Rates 155, 445, 1025 and 1235 Hz (a mode at 1000 Hz with
knocks that excite it), 0.62-2.35 mV noise, stamp jitter, gaps, and a sensor on a robot in a restaurant kitchen: the
room warming over the service, the extraction hood's fan stepping, a combi oven whose door lets out hot blasts and a
walk-in cold room whose door spills cold air.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size against its
noise without diagnosing (for a leak on a Zener base, against that bare Zener core).

    .venv/bin/python bench/independent_split_ae.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, signal

from independent_split import puncture_train
from polyforce_ros.physics.expconv import exp_convolve
from polyforce_ros.physics.viscoelastic import Burgers
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (ForcePath, GridMode, LeakingCore, Parts, ShapeSplit, SimOnly, band_play, coarse, ease, fit_departure,
                       follow, logistic, on_clock, schedule, sized, temp_of, uniform_grid, within)

SEED0 = 2_300_000  # never a seed of the registry's splits nor of splits A (90000..) to AD (2200000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 440.0
HORIZON_S = DURATION_S + 60.0  # what a schedule drawn before the record covers (the record plus its gaps' slack)


# ----------------------------------------------------------------------------- small tools

def lag_at(x, tau_s, rate_hz):
    """``x`` (uniform at ``rate_hz``) through an exact first-order lag of ``tau_s``, at rest with its first value."""
    keep = math.exp(-1.0 / (tau_s * rate_hz))
    y, _ = signal.lfilter([1.0 - keep], [1.0, -keep], x, zi=[keep * x[0]])
    return y


def chase(goal, rise, fall):
    """A state that approaches ``goal`` (per grid step) keeping ``rise`` of the distance when below it and ``fall``
    when above it (two first-order lags, one per direction), from ``goal[0]``."""
    out, y = np.empty(goal.size), float(goal[0])
    for i, g in enumerate(goal.tolist()):
        y = g + (y - g) * (rise if g > y else fall)
        out[i] = y
    return out


def snapped(x, on, off):
    """Per sample: True from a sample above ``on`` until the next below ``off`` (False at the start)."""
    idx = np.arange(x.size)
    last_on = np.maximum.accumulate(np.where(x > on, idx, -1))
    last_off = np.maximum.accumulate(np.where(x < off, idx, -1))
    return last_on > last_off


def linear_peak(xu, w, zeta, fs):
    """The largest relative motion and speed of a linear unit-gain mode (``w`` rad/s, ``zeta``, bilinear at ``fs``)
    driven by ``xu`` from rest."""
    b, a = signal.bilinear([w * w], [1.0, 2.0 * zeta * w, w * w], fs=fs)
    z = signal.lfilter(b, a, xu) - xu
    return max(float(np.max(np.abs(z))), 1e-12), max(float(np.max(np.abs(np.diff(z)))) * fs, 1e-12)


def resampled(y, seconds, rate_hz):
    """``y`` stretched over ``seconds`` at ``rate_hz`` (at least two samples)."""
    n = max(2, int(round(seconds * rate_hz)))
    return np.interp(np.linspace(0.0, y.size - 1.0, n), np.arange(y.size), y)


# ----------------------------------------------------------------------------- profiles and temperature

@functools.lru_cache(maxsize=1)
def measured_insertion():
    """The measured Okamura insertion (``../shared/data``, ``time_force.csv``) at 1 kHz, its peak 1, from its onset to
    the end of its withdrawal, tension clipped: (the curve, the index of the puncture, the index where the withdrawal
    begins). None when the data are absent."""
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
    return curve, peak - onset, w0 - onset


def vibrated_insertions(duration_s, rate_hz, rng):
    """Needle insertions along the measured Okamura curve (:func:`measured_insertion`) at 0.7-1.8 times its length and
    a 2.5-8.8 N peak. In half the sites an axial vibration of 4-15 Hz runs from the onset to the puncture: the force
    lowered by 20-45 % (the friction it breaks) and modulated by 8-20 % of itself. After the puncture the needle is held
    1-4 s (the force relaxing by 5-20 %), then withdrawn along the measured withdrawal. Sites 6-20 s apart; a train of
    synthetic punctures when the data are absent."""
    parts = measured_insertion()
    if parts is None:
        return puncture_train(duration_s, rate_hz, rng)
    curve, punct, w0 = parts
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cursor = rng.uniform(1.0, 5.0)
    while True:
        speed = rng.uniform(0.7, 1.8)
        ins = resampled(curve[:w0], w0 / 1000.0 * speed, rate_hz) * rng.uniform(2.5, 8.8)
        if rng.random() < 0.5:
            cut = int(round(punct / w0 * ins.size))
            u = np.arange(cut) / rate_hz
            freq, depth, ripple = rng.uniform(4.0, 15.0), rng.uniform(0.2, 0.45), rng.uniform(0.08, 0.2)
            ins[:cut] *= (1.0 - depth) * (1.0 + ripple * np.sin(2.0 * np.pi * freq * u))
        hold_s = rng.uniform(1.0, 4.0)
        u = np.arange(int(hold_s * rate_hz)) / rate_hz
        hold = ins[-1] * (1.0 - rng.uniform(0.05, 0.2) * (1.0 - np.exp(-u / (0.3 * hold_s))))
        out = resampled(curve[w0:] / max(float(curve[w0]), 1e-6), (curve.size - w0) / 1000.0 * speed, rate_hz)
        one = np.clip(np.concatenate([ins, hold, (hold[-1] if hold.size else ins[-1]) * out]), 0.0, None)
        i0 = int(cursor * rate_hz)
        if i0 + one.size >= t.size - 1:
            break
        f[i0:i0 + one.size] = one
        cursor += one.size / rate_hz + rng.uniform(6.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def swab_sampling(duration_s, rate_hz, rng):
    """A nasopharyngeal swab robot: the swab advanced along the nasal floor over 2-5 s at 0.1-0.6 N with 2-4 turbinate
    contacts (0.3-1.2 N more for 0.1-0.4 s), pressed on the posterior wall at 1.5-6 N within 0.3-1 s, rotated for 10-15
    s (the force wobbling by 10-30 % at 0.5-1.5 Hz and sagging by 0-15 %), a flinch in a third of the patients (1.3-1.8
    times for 0.2-0.5 s), withdrawn over 1-2.5 s along the floor; patients 10-25 s apart."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cursor = rng.uniform(1.0, 4.0)
    while cursor < duration_s:
        glide, advance = rng.uniform(0.1, 0.6), rng.uniform(2.0, 5.0)
        wall, press = rng.uniform(1.5, 6.0), rng.uniform(0.3, 1.0)
        spin, back = rng.uniform(10.0, 15.0), rng.uniform(1.0, 2.5)
        total = advance + press + spin + back
        i0, i1 = np.searchsorted(t, [cursor, cursor + total])
        u = t[i0:i1] - cursor
        seg = glide * ease(u / 0.3)
        for at in rng.uniform(0.2, 0.9, int(rng.integers(2, 5))) * advance:
            width = rng.uniform(0.1, 0.4)
            seg = seg + rng.uniform(0.3, 1.2) * np.where(np.abs(u - at) < width / 2.0,
                                                        0.5 * (1.0 + np.cos(2.0 * np.pi * (u - at) / width)), 0.0)
        s_spin = u - advance - press
        wobble = 1.0 + rng.uniform(0.1, 0.3) * np.sin(2.0 * np.pi * rng.uniform(0.5, 1.5) * s_spin + rng.uniform(0, 6.3))
        sag = 1.0 - rng.uniform(0.0, 0.15) * np.clip(s_spin / spin, 0.0, 1.0)
        on_wall = ease((u - advance) / press) * (1.0 - ease((s_spin - spin) / (0.3 * back)))
        contact = wall * np.where(s_spin > 0.0, wobble * sag, 1.0)
        if rng.random() < 1.0 / 3.0:
            at, width = rng.uniform(0.2, 0.8) * spin, rng.uniform(0.2, 0.5)
            contact = contact * (1.0 + rng.uniform(0.3, 0.8) * np.clip(1.0 - np.abs(s_spin - at) / width, 0.0, 1.0))
        leaving = 1.0 - ease((s_spin - spin) / back)
        f[i0:i1] = np.maximum(seg * leaving, on_wall * contact)
        cursor += total + rng.uniform(10.0, 25.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def keyswitch_tests(duration_s, rate_hz, rng):
    """A robot testing keyboard switches. Each switch (tactile, linear or clicky) has a force against travel: a preload
    of 0.2-0.5 N rising to a tactile peak of 0.5-0.9 N at 30-50 % of the travel (none when linear), a drop of 25-45 %
    after it (a sharp one when clicky), the spring again, and a bottom-out whose stop the robot presses to 2-8.8 N; the
    release runs 10-20 % lower. Slow characterisation strokes (1-3 s down, 0.3-1.5 s held on the stop, 1-3 s up, 1-3 s
    apart) and typing bursts (10-40 strokes at 3-8 Hz bottoming at 1.5-5 N); a new switch every 20-60 s (3-8 s to
    change)."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cursor = rng.uniform(0.5, 3.0)
    while cursor < duration_s:
        kind = int(rng.integers(3))
        pre, peak = rng.uniform(0.2, 0.5), rng.uniform(0.5, 0.9)
        at, drop = rng.uniform(0.3, 0.5), rng.uniform(0.25, 0.45)
        if kind == 1:
            knots = [0.0, 1e-3, 0.95, 1.0]
            curve = [0.0, pre, pre + 0.4, pre + 0.45]
        else:
            sharp = 0.02 if kind == 2 else 0.12
            knots = [0.0, 1e-3, at, at + sharp, 0.95, 1.0]
            curve = [0.0, pre, peak, peak * (1.0 - drop), peak * (1.0 - drop) + 0.25, peak * (1.0 - drop) + 0.3]
        spring = np.array(curve)
        end = cursor + rng.uniform(20.0, 60.0)
        while cursor < min(end, duration_s):
            if rng.random() < 0.55:
                down, held, up = rng.uniform(1.0, 3.0), rng.uniform(0.3, 1.5), rng.uniform(1.0, 3.0)
                top, times = rng.uniform(2.0, 8.8), [down, held, up]
            else:
                top, times = rng.uniform(1.5, 5.0), None
            if times is not None:
                i0, i1 = np.searchsorted(t, [cursor, cursor + sum(times)])
                u = t[i0:i1] - cursor
                travel = np.where(u < down, u / down, np.where(u < down + held, 1.0, 1.0 - (u - down - held) / up))
                release = np.where(u > down + held, rng.uniform(0.8, 0.9), 1.0)
                bottom = top * ease((u - down + 0.05) / 0.15) * (1.0 - ease((u - down - held) / 0.15))
                f[i0:i1] = np.maximum(np.interp(np.clip(travel, 0.0, 1.0), knots, spring) * release, bottom)
                cursor += sum(times) + rng.uniform(1.0, 3.0)
            else:
                period = 1.0 / rng.uniform(3.0, 8.0)
                n = int(rng.integers(10, 41))
                i0, i1 = np.searchsorted(t, [cursor, cursor + n * period])
                u = (t[i0:i1] - cursor) / period
                phase = u - np.floor(u)
                lift = np.sin(np.pi * np.clip(phase / 0.6, 0.0, 1.0))
                f[i0:i1] = np.maximum(np.interp(np.clip(lift * 1.2, 0.0, 1.0), knots, spring),
                                      top * np.clip((lift - 0.83) / 0.17, 0.0, 1.0))
                cursor += n * period + rng.uniform(1.0, 3.0)
        cursor = max(cursor, end) + rng.uniform(3.0, 8.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (vibrated_insertions, swab_sampling, keyswitch_tests)


def restaurant_kitchen(t, rng, step_s=0.5):
    """A sensor on a robot in a restaurant kitchen, from 900 s before the record: the room 2 degC below to 2 degC above
    the reference, warming by 0.5-2 degC from then to the record's end as the service builds; the extraction hood's fan stepping
    between speeds every 120-400 s (each worth -0.8 to +0.3 degC, approached with 60-150 s). The robot works at the prep
    counter (45 %), beside a combi oven (30 %) or beside the walk-in cold room (25 %), 30-150 s at a time with 3-10 s
    moves. The oven radiates 1-2.5 degC beside it and its door, opened every 60-240 s for 5-20 s, blows out 3-8 degC
    (rising with 2-5 s, fading with 20-60 s); the cold room's door, opened every 90-300 s for 4-15 s, spills air 2-5 degC
    colder (with 3-8 s and 30-90 s). The sensor follows with 5-24 s (exact per step of ``step_s``)."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-900.0, d + 2.0 * step_s, step_s)
    room = T_REF_C + rng.uniform(-2.0, 2.0) + rng.uniform(0.5, 2.0) * np.clip((grid + 900.0) / (d + 900.0), 0.0, 1.0)
    fan = np.zeros(grid.size)
    for start, length in schedule(rng, (0.0, 0.0), (120.0, 400.0), d + 1000.0):
        fan[(grid + 900.0 >= start) & (grid + 900.0 < start + length)] = rng.uniform(-0.8, 0.3)
    room = room + chase(fan, math.exp(-step_s / rng.uniform(60.0, 150.0)), math.exp(-step_s / rng.uniform(60.0, 150.0)))
    where = np.zeros((3, grid.size))
    at, here = float(grid[0]), int(rng.choice(3, p=(0.45, 0.3, 0.25)))
    while at <= grid[-1]:
        dwell, move = rng.uniform(30.0, 150.0), rng.uniform(3.0, 10.0)
        nxt = int(rng.choice(3, p=(0.45, 0.3, 0.25)))
        sel = (grid >= at) & (grid < at + dwell + move)
        u = ease((grid[sel] - at - dwell) / move)
        where[here, sel] += 1.0 - u
        where[nxt, sel] += u
        at, here = at + dwell + move, nxt
    rel = grid + 900.0
    oven_door = within(rel, schedule(rng, (60.0, 240.0), (5.0, 20.0), d + 1000.0)).astype(float)
    blast = chase(rng.uniform(3.0, 8.0) * oven_door, math.exp(-step_s / rng.uniform(2.0, 5.0)),
                  math.exp(-step_s / rng.uniform(20.0, 60.0)))
    cold_door = within(rel, schedule(rng, (90.0, 300.0), (4.0, 15.0), d + 1000.0)).astype(float)
    spill = chase(rng.uniform(2.0, 5.0) * cold_door, math.exp(-step_s / rng.uniform(3.0, 8.0)),
                  math.exp(-step_s / rng.uniform(30.0, 90.0)))
    air = room + where[1] * (rng.uniform(1.0, 2.5) + blast) - where[2] * spill
    keep = math.exp(-step_s / rng.uniform(5.0, 24.0))
    sensor, _ = signal.lfilter([1.0 - keep], [1.0, -keep], air, zi=[keep * air[0]])
    return np.interp(s, grid, sensor)


# ----------------------------------------------------------------------------- viscous flow

def forchheimer_leak(fluidity, crossover_n):
    """A leak through a porous wall by Darcy and Forchheimer: F = a q + b q^2 (a = 1 / ``fluidity``, the two terms
    equal at ``crossover_n``), the output gaining the volume passed."""
    a = 1.0 / fluidity
    b = 2.0 * a * a / crossover_n

    def rule(t, f):
        q = np.sign(f) * (np.sqrt(a * a + 4.0 * b * np.abs(f)) - a) / (2.0 * b)
        return integrate.cumulative_trapezoid(q, t, initial=0.0)
    return rule


def heated_leak(fluidity, gain, warm_s):
    """A leak whose oil warms with the power it dissipates (F^2, followed over ``warm_s``, relative to a sustained 3
    N): the fluidity ``fluidity`` (1 + (``gain`` - 1) W / (W + 1)), W that relative power."""
    def rule(t, f):
        warm = np.maximum(follow(t, f * f, warm_s, step_s=0.1), 0.0) / 9.0
        phi = fluidity * (1.0 + (gain - 1.0) * warm / (warm + 1.0))
        return integrate.cumulative_trapezoid(phi * f, t, initial=0.0)
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def thermoelastic_flexure(t, f, compliance, tau_s, terms=8):
    """The delayed deformation of a flexure's thermoelastic relaxation: ``compliance`` (V/N) shared over the
    diffusion series' terms, weights 1/(2n+1)^2, times ``tau_s``/(2n+1)^2, from rest."""
    odd = 2.0 * np.arange(terms) + 1.0
    weights = odd ** -2.0 / float(np.sum(odd ** -2.0))
    rates = odd * odd / tau_s
    return compliance * exp_convolve(t, f, rates) @ (weights * rates)


def flap_valve_kelvin(t, f, compliance, slow_s, ratio, on_load, step_s=0.01):
    """A Kelvin unit (``compliance`` V/N) whose dashpot's bellows has a flap valve: it moves with ``slow_s`` / ``ratio``
    while the flap is open (toward more deformation when ``on_load``, toward less otherwise) and with ``slow_s``
    through the bleed hole. Exact per step of ``step_s``, from rest."""
    grid, fg = coarse(t, f, step_s)
    fast, slow = math.exp(-step_s * ratio / slow_s), math.exp(-step_s / slow_s)
    goal = compliance * fg
    y = chase(goal - goal[0], fast if on_load else slow, slow if on_load else fast) + goal[0]
    return np.interp(t, grid, y)


# ----------------------------------------------------------------------------- hysteresis

class ReportByException(SimOnly):
    """A wireless node that reports by exception: the receiver holds the last reading sent, and a new one is sent as
    soon as the reading has moved more than ``band_v`` from it."""

    def __init__(self, band_v):
        self.band = band_v

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        out, last = np.empty_like(x), float(x[0])
        for i, xi in enumerate(x.tolist()):
            if abs(xi - last) > self.band:
                last = xi
            out[i] = last
        return out


class OilCanDiaphragm(SimOnly):
    """A read-out diaphragm that oil-cans: it snaps through as the reading passes ``on`` of ``top`` and back below
    ``off`` of it, the reading offset by ``step_v`` while it is snapped."""

    def __init__(self, top, step_v, on, off):
        self.top, self.step, self.on, self.off = top, step_v, on, off

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        return x + self.step * snapped(x, self.on * self.top, self.off * self.top)


# ----------------------------------------------------------------------------- sensor lag

class CapillaryLine(SimOnly):
    """A hydraulic read-out whose pressure reaches the transducer through a long dead-ended capillary: 1 /
    cosh(sqrt(s tau)) (mean delay tau / 2 = ``delay_s``), as a cascade of its first ``poles`` poles (time constants 4
    tau / ((2k - 1)^2 pi^2)) and one lag holding the rest of the mean delay; on a uniform grid, from rest."""

    def __init__(self, delay_s, poles=20):
        tau = 2.0 * delay_s
        k = np.arange(1, poles + 1)
        self.taus = list(4.0 * tau / ((2.0 * k - 1.0) ** 2 * math.pi ** 2))
        self.taus.append(max(delay_s - float(np.sum(self.taus)), 1e-6))

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, y, h = uniform_grid(t, x)
        for tau in self.taus:
            y = lag_at(y, tau, 1.0 / h)
        return np.interp(t, tu, y)


class GaussianFir(SimOnly):
    """Firmware smoothing with a causal Gaussian FIR: sigma ``delay_s`` / 3, truncated at +-3 sigma (linear phase, a
    delay of ``delay_s``); on a uniform grid, settled at the first sample."""

    def __init__(self, delay_s):
        self.delay = delay_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        sigma = self.delay / 3.0
        lags = np.arange(0.0, 6.0 * sigma + h, h)
        taps = np.exp(-0.5 * ((lags - self.delay) / sigma) ** 2)
        taps /= taps.sum()
        y = signal.lfilter(taps, [1.0], xu - x[0]) + x[0]
        return np.interp(t, tu, y)


# ----------------------------------------------------------------------------- nonlinear gain

def triangulation(rel, reach, approaching):
    """x read by laser triangulation: the spot on the detector as the inverse of the target's distance, 1 - k x
    (``approaching``: expansive) or 1 + k x (compressive); slope 1 at no load, k for a departure of ``rel`` at
    ``reach``."""
    if approaching:
        def read(x, k):
            return (1.0 / (1.0 - k * np.minimum(x, 0.9 / k)) - 1.0) / k
        return fit_departure(read, rel, reach, 0.9 / reach)

    def read(x, k):
        return (1.0 - 1.0 / (1.0 + k * np.maximum(x, -0.5 / k))) / k
    return fit_departure(read, rel, reach, 4.0 / reach)


def silicon_quarter_bridge(rel, reach, q):
    """x read by a semiconductor gauge in a quarter bridge: r = k x (1 + ``q`` k x), the output r / (1 + r / 2) / k
    (slope 1 at no load), k for a departure of ``rel`` at ``reach``."""
    def read(x, k):
        u = k * np.clip(x, -0.3 * reach, None)
        r = np.maximum(u * (1.0 + q * u), -1.0)
        return r / (1.0 + 0.5 * r) / k
    return fit_departure(read, rel, reach, (1.5 if q > 0 else 0.9) / reach)


# ----------------------------------------------------------------------------- thermal drift

def pyroelectric_zero(t, temp, k_v_per_c, lag_s, drain_s):
    """The zero of a piezoelectric element's pyroelectric charge drained through its input resistance: ``k_v_per_c``
    times its temperature (lag ``lag_s``) less that temperature's follower with ``drain_s``."""
    body = follow(t, temp, lag_s)
    return k_v_per_c * (body - follow(t, body, drain_s))


def gate_leakage_zero(t, temp, k_v_per_c, lag_s, doubling_c):
    """The zero of an amplifier whose JFET gate leakage through the bridge's resistance doubles every ``doubling_c``
    (its slope ``k_v_per_c`` at the reference; lag ``lag_s``), zero at the first sample."""
    body = np.minimum(follow(t, temp, lag_s) - T_REF_C, 25.0)
    grow = doubling_c / math.log(2.0) * np.exp2(body / doubling_c)
    return k_v_per_c * (grow - grow[0])


# ----------------------------------------------------------------------------- thermal sensitivity

class AmberLedSpan(SimOnly):
    """An optical read-out lit by an amber LED: its flux as exp(-(``tc`` + ``resp``) dT), the photodiode's
    responsivity as 1 + ``resp`` dT; dT from the reference on the junction (lag ``lag_s``)."""

    def __init__(self, tc, resp, lag_s):
        self.tc, self.resp, self.lag = tc, resp, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = np.clip(follow(t, temp_of(aux, t.size), self.lag) - T_REF_C, -30.0, 30.0)
        return np.asarray(x, dtype=float) * np.exp(-(self.tc + self.resp) * d) * (1.0 + self.resp * d)


class ElectrolyteSpan(SimOnly):
    """A resistive read-out through an electrolyte read with a constant current: the span as the inverse of its
    Vogel-Fulcher conductivity, exp(-B / (T - ``t0_k``)), B for ``tc`` per degC at the reference (lag ``lag_s``)."""

    def __init__(self, tc, t0_k, lag_s):
        self.ref = T_REF_C + 273.15
        self.t0, self.lag = t0_k, lag_s
        self.b = tc * (self.ref - t0_k) ** 2

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = np.maximum(follow(t, temp_of(aux, t.size), self.lag) + 273.15, self.t0 + 40.0)
        return np.asarray(x, dtype=float) * np.exp(self.b * (1.0 / (self.ref - self.t0) - 1.0 / (body - self.t0)))


# ----------------------------------------------------------------------------- offset drift

def charge_amplifier(rng, horizon_s=HORIZON_S, step_s=0.05):
    """The zero of a charge amplifier: its input leakage (wandering by 10-30 % about its mean, correlated over 60-200
    s) integrating on the feedback capacitor, drained by the feedback resistor with 100-600 s, emptied by a reset switch
    every 40-160 s (the last one before the record 0-160 s before it). As a function of the seconds since the first
    sample, zero there."""
    grid = np.arange(-400.0, horizon_s + step_s, step_s)
    fade = math.exp(-step_s / rng.uniform(60.0, 200.0))
    wander, _ = signal.lfilter([math.sqrt(1.0 - fade * fade)], [1.0, -fade], rng.normal(0.0, 1.0, grid.size), zi=[0.0])
    current = 1.0 + rng.uniform(0.1, 0.3) * np.clip(wander, -2.5, 2.5)
    keep = math.exp(-step_s / rng.uniform(100.0, 600.0))
    resets = np.zeros(grid.size, dtype=bool)
    at = -rng.uniform(0.0, 160.0)
    while at > grid[0]:
        at -= rng.uniform(40.0, 160.0)
    while at < grid[-1]:
        resets[min(int(np.searchsorted(grid, at)), grid.size - 1)] = True
        at += rng.uniform(40.0, 160.0)
    out, y = np.empty(grid.size), 0.0
    for i, (c, r) in enumerate(zip(current.tolist(), resets.tolist())):
        y = 0.0 if r else y * keep + c * step_s
        out[i] = y
    first = float(np.interp(0.0, grid, out))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, out) - first


def sunlit_die(rng, horizon_s=HORIZON_S, step_s=0.1):
    """The zero of an unshielded piezoresistive die's photocurrent: a window's sun through passing clouds (20-120 s
    each, 20-120 s apart, keeping 20-60 % of it, their edges 3-15 s), and the room's lights (20-50 % of the sun)
    switched 0-2 times. As a function of the seconds since the first sample, zero there."""
    grid = np.arange(-60.0, horizon_s + step_s, step_s)
    sun = np.ones(grid.size)
    for start, length in schedule(rng, (20.0, 120.0), (20.0, 120.0), horizon_s):
        edge = rng.uniform(3.0, 15.0)
        shade = ease((grid - start) / edge) * (1.0 - ease((grid - start - length) / edge))
        sun = sun - (1.0 - rng.uniform(0.2, 0.6)) * shade
    lit = bool(rng.random() < 0.5)
    lights = np.full(grid.size, float(lit))
    for at in np.sort(rng.uniform(0.0, horizon_s - 60.0, int(rng.integers(0, 3)))):
        lit = not lit
        lights[grid >= at] = float(lit)
    out = sun + rng.uniform(0.2, 0.5) * lights
    first = float(np.interp(0.0, grid, out))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, out) - first


# ----------------------------------------------------------------------------- resonance

class DragMode(GridMode):
    """A needle holder's mode at ``f0_hz`` (unit gain, damping ratio ``zeta``) whose paddle also meets air drag: the
    damping (1 + ``drag`` |v| / v_max) times the linear one, v_max the largest relative speed a linear mode gives the
    record. Semi-implicit Euler on a uniform grid of ``fs`` Hz, from rest."""

    fs = 3000.0

    def __init__(self, f0_hz, zeta, drag):
        self.w, self.zeta, self.drag = 2.0 * math.pi * f0_hz, zeta, drag

    def on_grid(self, t, tu, xu, h):
        _, vmax = linear_peak(xu, self.w, self.zeta, self.fs)
        w2, c0, per = self.w * self.w, 2.0 * self.zeta * self.w, self.drag / vmax
        y = v = 0.0
        out = np.empty(tu.size)
        for i, xi in enumerate(xu.tolist()):
            v += (w2 * (xi - y) - c0 * (1.0 + per * abs(v)) * v) * h
            y += v * h
            out[i] = y
        return out


class BumpStopMode(GridMode):
    """A needle holder's mode at ``f0_hz`` (unit gain, damping ratio ``zeta``) that hits a rubber bump stop once its
    relative motion passes ``clearance`` of the largest a linear mode gives the record, ``stiffer`` times as stiff
    beyond it. Semi-implicit Euler on a uniform grid of ``fs`` Hz, from rest."""

    fs = 3000.0

    def __init__(self, f0_hz, zeta, clearance, stiffer):
        self.w, self.zeta, self.clearance, self.stiffer = 2.0 * math.pi * f0_hz, zeta, clearance, stiffer

    def on_grid(self, t, tu, xu, h):
        zmax, _ = linear_peak(xu, self.w, self.zeta, self.fs)
        gap, w2, c = self.clearance * zmax, self.w * self.w, 2.0 * self.zeta * self.w
        extra = (self.stiffer - 1.0) * w2
        y = v = 0.0
        out = np.empty(tu.size)
        for i, xi in enumerate(xu.tolist()):
            z = y - xi
            over = z - gap if z > gap else (z + gap if z < -gap else 0.0)
            v += (-w2 * z - extra * over - c * v) * h
            y += v * h
            out[i] = y
        return out


# ----------------------------------------------------------------------------- friction

def ball_bushing(f, band_n, ripple, pitch_n, phase):
    """The force passed by a needle in a recirculating-ball bushing: a Coulomb band ``band_n`` (1 + ``ripple``
    sin(2 pi F / ``pitch_n`` + ``phase``)). Started at ``f[0]``."""
    band = band_n * (1.0 + ripple * np.sin(2.0 * np.pi * f / pitch_n + phase))
    return band_play(f, band, band)


class GreasedGuide(SimOnly):
    """The force passed by a greased needle guide whose grease stiffens as it cools: a Coulomb band ``band_n`` exp(-
    ``alpha`` (T - T_mean)), T the guide's temperature (lag ``lag_s``), T_mean its mean over the record (the band
    held within 0.3-3 times ``band_n``). Started at the first force."""

    def __init__(self, band_n, alpha, lag_s):
        self.band, self.alpha, self.lag = band_n, alpha, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag)
        band = self.band * np.clip(np.exp(-self.alpha * (body - body.mean())), 0.3, 3.0)
        return band_play(np.asarray(x, dtype=float), band, band)


# ----------------------------------------------------------------------------- thermo-rheological

def softened(c):
    """The core made soft enough for its clock to show: its Kelvin spring at most 15 N/V (the retardation time kept)
    and its flow's viscosity within 8e3-3.2e4 N s/V."""
    k2 = min(c.k2_n_per_v, 15.0)
    return Burgers(c.k1_n_per_v, k2, float(np.clip(c.eta1_n_s_per_v, 8e3, 3.2e4)), c.eta2_n_s_per_v * k2 / c.k2_n_per_v)


class CouplingModelClock(SimOnly):
    """A core whose clock follows Ngai's coupling model: ln tau = (E / T - n ln t_c) / (1 - n), t_c 2 ps, the coupling
    n = ``n_ref`` + ``dn`` (T_ref - T) (held within 0.05-0.8), E set for ``b_per_c`` per degC at the reference; on the
    core's temperature (lag ``lag_s``), held within e^+-6."""

    LN_TC = math.log(2e-12)

    def __init__(self, c, b_per_c, n_ref, dn, lag_s):
        self.c, self.n_ref, self.dn, self.lag = c, n_ref, dn, lag_s
        ref = T_REF_C + 273.15

        def slope(e):
            h = 1e-3
            return float((self._log_tau(np.array([ref + h]), e) - self._log_tau(np.array([ref - h]), e))[0] / (2 * h))
        s0, s1 = slope(0.0), slope(1.0)
        self.e = (-b_per_c - s0) / (s1 - s0)
        self.ref_log = float(self._log_tau(np.array([ref]), self.e)[0])

    def _log_tau(self, kelvin_t, e):
        n = np.clip(self.n_ref + self.dn * (T_REF_C + 273.15 - kelvin_t), 0.05, 0.8)
        return (e / kelvin_t - n * self.LN_TC) / (1.0 - n)

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag) + 273.15
        rate = np.exp(np.clip(self.ref_log - self._log_tau(body, self.e), -6.0, 6.0))
        return on_clock(self.c, t, np.asarray(x, dtype=float), rate)


class GlassCrossingClock(SimOnly):
    """A core whose binder crosses its glass transition ``tg_off`` degC from the reference: the slope of ln tau (per
    degC, falling) ``glassy`` of its rubbery value below T_g, all of it above, switching as a logistic over ``width_c``;
    ``b_per_c`` at the reference; on the core's temperature (lag ``lag_s``), held within e^+-6."""

    def __init__(self, c, b_per_c, tg_off, glassy, width_c, lag_s):
        self.c, self.lag, self.w = c, lag_s, width_c
        self.tg = T_REF_C + tg_off
        share = float(logistic((T_REF_C - self.tg) / width_c))
        self.hi = b_per_c / (glassy + (1.0 - glassy) * share)
        self.lo = glassy * self.hi

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = follow(t, temp_of(aux, t.size), self.lag)
        soft = np.logaddexp(0.0, (d - self.tg) / self.w) - math.log1p(math.exp((T_REF_C - self.tg) / self.w))
        log_rate = self.lo * (d - T_REF_C) + (self.hi - self.lo) * self.w * soft
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(log_rate, -6.0, 6.0)))


# ----------------------------------------------------------------------------- outside the catalogue

class SlipRingCrackle(SimOnly):
    """A slip ring in the read-out's leads whose contacts crackle while the wrist turns: bouts of 1-6 s every 10-40 s
    (from ``seed``) of noise low-passed at 30-200 Hz (below 0.4 of the rate), ``rms_v`` RMS."""

    def __init__(self, rms_v, seed):
        self.rms, self.seed = rms_v, seed

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        rng = np.random.default_rng(self.seed)
        bouts = within(t - t[0], schedule(rng, (10.0, 40.0), (1.0, 6.0), t[-1] - t[0] + 1.0))
        rate = 1.0 / float(np.median(np.diff(t)))
        corner = min(rng.uniform(30.0, 200.0), 0.4 * rate)
        b, a = signal.butter(2, corner, fs=rate)
        noise = signal.lfilter(b, a, rng.normal(0.0, 1.0, t.size))
        noise *= self.rms / max(float(np.std(noise)), 1e-12)
        return x + noise * bouts


class StuckAdcBit(SimOnly):
    """A 16-bit ADC (codes of ``lsb_v``, offset binary about zero) with bit ``bit`` stuck high or low."""

    def __init__(self, bit, high, lsb_v=20.0 / 65536.0):
        self.bit, self.high, self.lsb = bit, high, lsb_v

    def forward(self, t_s, x, aux=None, state=None):
        code = np.clip(np.round(np.asarray(x, dtype=float) / self.lsb).astype(np.int64) + 32768, 0, 65535)
        mask = np.int64(1 << self.bit)
        code = (code | mask) if self.high else (code & ~mask)
        return (code - 32768) * self.lsb


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([4.6e4, 3.8e3]))))  # V / (N s)
        if shape == "forchheimer_wall":
            rule = forchheimer_leak(phi * rng.uniform(1.5, 3.0), rng.uniform(0.8, 3.0))
        else:
            rule = heated_leak(phi * rng.uniform(0.7, 1.2), rng.uniform(2.0, 5.0), rng.uniform(20.0, 120.0))
        return Parts("zener", LeakingCore.of(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        comp = float(np.interp(m, [0, 1], [0.035, 0.21])) / g0  # of the instantaneous response, V / N
        if shape == "thermoelastic_flexure":
            a = (comp, rng.uniform(3.0, 40.0))
            p.extra.append(lambda t, f, T, a=a: thermoelastic_flexure(t, f, *a))
            return p
        ratio = rng.uniform(3.0, 10.0)
        a = (comp, rng.uniform(0.4, 4.0) * ratio, ratio, bool(rng.random() < 0.5))
        p.extra.append(lambda t, f, T, a=a: flap_valve_kelvin(t, f, *a))
        return p
    if effect == "hysteresis":
        width = float(np.interp(m, [0, 1], [0.017, 0.068]))
        if shape == "report_by_exception":
            p.after.append(ReportByException(width * top))
            return p
        p.after.append(OilCanDiaphragm(top, float(rng.choice([-1.0, 1.0])) * width * top, rng.uniform(0.45, 0.8),
                                       rng.uniform(0.15, 0.4)))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.01, 0.095]))))
        p.after.append(CapillaryLine(delay) if shape == "capillary_line" else GaussianFir(delay))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.05, 0.185]))
        if shape == "laser_triangulation":
            p.after.append(StaticMap(triangulation(rel, top, bool(rng.random() < 0.5))))
            return p
        q = rng.uniform(1.5, 2.5) if rng.random() < 0.5 else rng.uniform(-0.3, 0.0)
        p.after.append(StaticMap(silicon_quarter_bridge(rel, top, q)))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.0075, 0.031]) * rng.choice([-1, 1]))
        if shape == "pyroelectric_charge":
            a = (k, rng.uniform(5.0, 25.0), rng.uniform(20.0, 150.0))
            p.extra.append(lambda t, f, T, a=a: pyroelectric_zero(t, T, *a))
            return p
        a = (k, rng.uniform(5.0, 30.0), rng.uniform(8.0, 12.0))
        p.extra.append(lambda t, f, T, a=a: gate_leakage_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        tc = float(np.interp(m, [0, 1], [0.0125, 0.033]))
        if shape == "amber_led":
            p.after.append(AmberLedSpan(tc, rng.uniform(0.0005, 0.002), rng.uniform(5.0, 30.0)))
            return p
        p.after.append(ElectrolyteSpan(tc, rng.uniform(150.0, 200.0), rng.uniform(10.0, 40.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.017, 0.092]) * rng.choice([-1, 1]))
        zero = sized(charge_amplifier(rng) if shape == "charge_amplifier" else sunlit_die(rng), size, HORIZON_S)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.03, 0.005])) * rng.uniform(0.8, 1.2)
        if shape == "air_drag":
            p.after.append(DragMode(rng.uniform(14.0, 44.0), zeta, rng.uniform(1.5, 5.0)))
            return p
        p.after.append(BumpStopMode(rng.uniform(14.0, 44.0), zeta, rng.uniform(0.25, 0.7), rng.uniform(2.0, 6.0)))
        return p
    if effect == "friction":
        band = float(np.interp(m, [0, 1], [0.0032, 0.04]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "ball_bushing":
            a = (band, rng.uniform(0.3, 0.7), rng.uniform(0.4, 1.5), rng.uniform(0.0, 2.0 * math.pi))
            p.before.append(ForcePath(lambda t, x, a=a: ball_bushing(x, *a)))
            return p
        p.before.append(GreasedGuide(band, rng.uniform(0.04, 0.1), rng.uniform(10.0, 40.0)))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.16, 0.48])) * rng.uniform(1.2, 1.5)
        c = softened(c)
        if shape == "coupling_model_clock":
            return Parts("burgers", CouplingModelClock(c, b, rng.uniform(0.3, 0.55), rng.uniform(0.005, 0.02),
                                                       rng.uniform(5.0, 25.0)), core_changed=True)
        return Parts("burgers", GlassCrossingClock(c, b, float(rng.choice([-1.0, 1.0])) * rng.uniform(1.0, 5.0),
                                                   rng.uniform(0.3, 0.5), rng.uniform(0.5, 1.5), rng.uniform(5.0, 25.0)),
                     core_changed=True)
    if effect == "slip_ring_crackle":
        rms = float(np.interp(m, [0, 1], [0.01, 0.05]))
        p.outer.append(SlipRingCrackle(rms, int(rng.integers(1 << 30))))
        return p
    if effect == "stuck_adc_bit":
        bit = int(np.clip(round(np.interp(m, [0, 1], [5.6, 8.2]) + rng.uniform(-0.4, 0.4)), 6, 8))
        p.outer.append(StuckAdcBit(bit, bool(rng.random() < 0.5)))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["forchheimer_wall", "heated_oil"],
    "delayed_elasticity": ["thermoelastic_flexure", "flap_valve"],
    "hysteresis": ["report_by_exception", "oil_can_diaphragm"],
    "sensor_lag": ["capillary_line", "gaussian_fir"],
    "nonlinear_gain": ["laser_triangulation", "silicon_quarter_bridge"],
    "thermal_drift": ["pyroelectric_charge", "gate_leakage"],
    "thermal_sensitivity": ["amber_led", "electrolyte_cell"],
    "offset_drift": ["charge_amplifier", "sunlit_die"],
    "resonance": ["air_drag", "bump_stop"],
    "friction": ["ball_bushing", "greased_guide"],
    "thermo_rheological": ["coupling_model_clock", "glass_crossing_clock"],
}
PAIRS = (("hysteresis", "viscous_flow"), ("offset_drift", "thermo_rheological"), ("friction", "nonlinear_gain"),
         ("resonance", "delayed_elasticity"), ("thermal_sensitivity", "sensor_lag"), ("thermal_drift", "friction"))
OUTSIDE = ("slip_ring_crackle", "stuck_adc_bit")
RATES = (155.0, 445.0, 1025.0, 1235.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split AE", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.34, 0.82),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=restaurant_kitchen,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(0.62e-3, 2.35e-3), jitter=0.31,
                   gap_s=(0.15, 2.3))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
