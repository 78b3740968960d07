"""Independent split AD for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split AD is an untouched held-out set: written blind to the engine it measures (to how it detects and fits anything),
run once, and nothing is ever chosen from it. Every name of the catalogue is hidden in two shapes that neither the
registry's families (``polyforce_ros/sim/truths.py``) nor splits A to AC use:

* a core whose oil leaks drop by drop from a fine nozzle (the meniscus a spherical cap whose Laplace pressure peaks,
  at 0.3-2.2 N, when it is a hemisphere: below that force only a meniscus bulges and goes back, above it a drop grows
  and falls off at 3-8 hemispheres' volume, one drop per 1.5-15 s at 3 N; 1.2-2.8 times the plain fluidity of
  1/50000-1/4000 V/(N s) at 3 N), or a core of glass microbeads discharging through an aperture (Beverloo: at a rate
  set by the aperture and not by the load once the load passes a feed force of 0.2-0.8 N, 2-4 times what the plain
  fluidity gives at 3 N; arches clog it after exponentially distributed runs of 3-25 s of flow, and an arch breaks
  only when the force rises 0.3-1.5 N above the force it formed at or the load is taken off); neither ever recovers;
* a core held together by 24-60 sacrificial bonds, each a two-state site with Bell-Evans kinetics (open with the
  logistic of (F - F_i) / w, F_i log-normal about 1.2-4 N with a spread of 0.2-0.6, w 0.25-1 N, relaxing at cosh((F -
  F_i) / 2 w) / tau_i, tau_i about 1-25 s: the creep is slowest where a bond is half open), or a hydraulic core whose
  expelled oil fills a rolling-diaphragm chamber against a constant-force (negator) spring of 0.3-1.6 N (3-12 % stiffer
  at the end of its stroke): nothing moves below the spring's force, above it the chamber fills through a capillary, a
  4 N load filling it in 0.6-10 s, and empties likewise once the force falls below it; both give 3-22 % of the
  instantaneous response at 4 N;
* an autoranging DAQ switching to its low-gain range as the reading passes 30-60 % of the range and back 30-60 %
  lower, its high-gain range's gain off by what makes the loop (the firmware linearising the mean of both: a band in
  which the reading depends on the way it came), or a read-out on a spherical seat preloaded off-centre by 0.1-0.4 rad
  that the load's moment rolls toward and past alignment (0.4-0.9 rad per range), its tilt sticking within the
  friction band of the seat's wave spring, the gauges reading x (cos(theta) + beta sin(theta)), beta 0.6-1.5 of the
  moment the tilted line of action puts on them (the firmware linearising the mean of a cycle); loops of 1.6-7 % of
  the range in a full-range cycle (the seat's as wide as its tilt allows);
* an anti-alias inverse-Chebyshev (type II) low-pass (order 3-5, stopband 25-50 dB down: a monotonic passband and
  notches above), or a capacitive read-out through a relaxation oscillator whose period the load lengthens by 15-60 %
  over the range, the firmware counting a fixed number of periods back to back and reporting the mean of each count
  until the next; 9-100 ms of mean delay at low frequencies (the counter's at no load);
* an eddy-current probe facing a conductive target on the core (the coupling to its image as (1 + (2 g / a)^2)^(-3/2),
  from a standoff of 0.15-0.6 coil radii, the load closing or opening the gap), or an optical read-out whose vane (a
  disc) slides across a circular aperture of its own size (the light the two circles' lens-shaped overlap, the load
  uncovering it from a centre distance of 0.9-1.8 radii or covering it from 0.2-1.2); 5-19 % at the top of the range;
* the zero of a read-out preloaded by a nickel-titanium wire in its R-phase transformation (20-50 % of the
  coefficient linear, 1.5-4 degC worth of it through the austenite fraction, which follows logistic branches 0.3-1.2
  degC wide centred at the 30-70th percentile of the wire's temperature over the record, 0.8-2.5 degC apart between
  heating and cooling, with minor loops; lag 8-30 s), or of a carrier-frequency bridge whose cable's plasticised PVC
  has its dielectric loss peak near the carrier (a Debye relaxation with an apparent activation of 1.5-4 eV, the
  in-phase leakage as sech(ln omega tau), steepest at the 25-75th percentile of the cable's temperature, on either
  flank; lag 10-50 s); a coefficient of 0.007-0.032 V/degC (the cable's at its steepest);
* a differential capacitive read-out whose gaps hold a (Ba,Sr)TiO3 paraelectric (Curie-Weiss, 8-25 degC above its
  Curie point) tuned by the read-out's bias field (Johnson's law: the span as x / (1 + b x^3)^(1/3), x = (T_ref - T_c)
  / (T - T_c): falling as it warms, levelling off as it cools), or a span compensated by firmware through a cubic
  B-spline in the temperature with knots every 1.5-3 degC, one knot (at the 30-70th percentile of the electronics'
  temperature over the record) off by 2.4-14 % (a bump either way); lag 5-25 s; 1.2-3.4 %/degC at the reference (the
  knot's at its steepest);
* the zero of a capacitive read-out whose dielectric traps charge under the DC bias (switched on 0-300 s before the
  first sample; the firmware drops the bias to 10-35 % while idle, 15-90 s at a time between active spells of 40-200 s;
  ten trap families log-spaced between 8-30 s and 300-1500 s, weighted as tau^(-0-0.6)), or of a bridge whose
  thin-film arm pits through a pinhole in its passivation wetted by saline (1-4 stable pits started 300 s before to
  400 s into the record, each as the cube root of its age over 30-300 s; metastable pits every 15-60 s that rise as
  the square root of their age over 1-6 s and repassivate in 0.2-0.6 s, keeping 10-30 %); 16-95 mV at most;
* a needle holder's mode (13-46 Hz) on a hydraulic mount (a rubber spring beside a fluid chamber 0.3-1 times as stiff,
  whose free-floating decoupler passes the chamber's volume while the relative motion stays within 15-50 % of the
  largest a linear mode would give, so large knocks drive the fluid through an inertia track tuned to 0.6-1.5 of the
  mode, damping ratio 0.15-0.5: small knocks ring on the rubber alone), or a holder whose paddle squeezes an air film
  between two plates (the damping as the mean of the inverse cubes of both gaps, 1.3-4 times that largest motion);
  damping ratio 0.0036-0.038 at rest, the small-amplitude frequency fixed;
* a Coulomb band of 0.24-5 % of the range: an O-ring on the needle whose rubber friction follows Grosch's bell in the
  logarithm of the slip rate (35-70 % of the band at rest and far from the peak, the full band at 0.3-5 N/s, 0.4-1
  decade wide, the rate smoothed over 20-60 ms), or a needle guide with a push-push latch that toggles between locked
  (the band) and free (15-40 % of it) at each push past 35-65 % of the record's heaviest, re-armed once the force has
  fallen below 30-60 % of that;
* a core (soft enough for its clock to show) whose clock follows Roessler's excess activation energy (log tau as (E_inf
  + E_inf exp(-mu (T - T_A) / E_inf)) / T, T_A 20-80 degC above the reference, 25-50 % of the slope there from
  E_inf), or Tanaka's two-order-parameter model (log tau as (E + Delta E S(T)) / T, S the share of locally favoured
  structures, a logistic in 1 / T, 10-40 % at the reference, an ordering energy of 3000-15000 K; 30-60 % of the slope
  from E); 1.2-1.5 times 0.15-0.5 per degC at the reference, lag 5-25 s.

It also holds six pairs, two effects outside the catalogue (a bridge whose zero-balance resistor sits on a board the
load flexes, its cracked joint opening whenever the reading passes 50-80 % of the record's largest and closing 8-25 %
lower, chattering 2-5 times over 5-30 ms as it opens, the zero jumping by 31-55 mV meanwhile; a wireless link that
compresses blocks of 64, 128 or 256 samples by a discrete cosine transform with its coefficients quantised in steps of
50-133 mV) and four clean records. Profiles: a robot piercing sites in ex-vivo liver along the measured Okamura
insertion (``../shared/data``, ``time_force.csv``, at 0.7-2 times its length) and re-entering each 1-3 times through
the tract it cut, where the capsule's stiffness peak and the cutting are gone: the measured curve's lower envelope
(each sample no higher than any later one before the withdrawal), 45-80 % of it and a little less each time, then the
measured withdrawal (each site's peak 2.2-8.8 N, sites 5-20 s apart; a train of synthetic punctures when the data are
absent); a robot writing Chinese calligraphy with a brush (strokes with their pressed starts, pressed or lifted ends,
hooks, tapering and swelling sweeps, dots, re-inking on the inkstone's rim, new sheets, the bristles' lag); and a robot
testing the strength of a weak hand's muscles (make tests held 3-5 s with a wavering effort and tremor, break tests in
which the robot pushes until the limb gives way, fatigue from trial to trial). Rates 185, 325, 1070 and 1310 Hz (a
mode at 1000 Hz with knocks that excite it), 0.75-2.65 mV noise, stamp jitter, gaps, and a sensor on a robot at a
molecular-biology bench: the room's air handling hunting, the robot moving between the bench, a thermal cycler whose
Peltier exhaust blows warm at each cooling ramp and cool while it heats, and an ultra-low freezer whose compressor
cycles and whose door, opened on some visits, spills cold air.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size against its
noise without diagnosing (for a leak on a Zener base, against that bare Zener core).

    .venv/bin/python bench/independent_split_ad.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import fft, integrate, optimize, signal

from independent_split import puncture_train
from polyforce_ros.physics.expconv import exp_convolve
from polyforce_ros.physics.viscoelastic import Burgers
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (ForcePath, LeakingCore, LinearFilter, Parts, ShapeSplit, GridMode, SimOnly, band_play, coarse, ease,
                       fit_departure, follow, logistic, on_clock, sized, temp_of)

SEED0 = 2_200_000  # never a seed of the registry's splits nor of splits A (90000..) to AC (2100000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 450.0
HORIZON_S = DURATION_S + 60.0  # what a schedule drawn before the record covers (the record plus its gaps' slack)


# ----------------------------------------------------------------------------- small tools

def latch(set_, reset, start):
    """Per sample: True after the latest sample where ``set_`` holds, False after the latest where ``reset`` holds,
    ``start`` before either."""
    idx = np.arange(set_.size)
    last_set = np.maximum.accumulate(np.where(set_, idx, -1))
    last_reset = np.maximum.accumulate(np.where(reset, idx, -1))
    return np.where(last_set == last_reset, start, last_set > last_reset)


def stretched(y, seconds, rate_hz):
    """``y`` replayed over ``seconds`` at ``rate_hz`` (linear interpolation, at least two samples)."""
    n = max(2, int(round(seconds * rate_hz)))
    return np.interp(np.linspace(0.0, y.size - 1.0, n), np.arange(y.size), y)


def first_order(x, tau_s, rate_hz):
    """``x`` through a first-order lag of ``tau_s`` at ``rate_hz``, at rest with its first value."""
    keep = math.exp(-1.0 / (tau_s * rate_hz))
    y, _ = signal.lfilter([1.0 - keep], [1.0, -keep], x, zi=[keep * x[0]])
    return y


def mean_branches(read, reach=3.0, n=3001):
    """The firmware's linearisation of a read-out ``read(u)`` that has a loop (u the core's output over the range's):
    the mean of its rising and falling branches over a cycle from 0 to ``reach`` ranges and back (grid, mean), and the
    widest gap between the branches of a cycle over the range."""
    def cycle(top):
        u = np.concatenate([np.linspace(0.0, top, n), np.linspace(top, 0.0, n)[1:]])
        r = read(u)
        return r[:n], r[n - 1:][::-1]
    up, down = cycle(reach)
    full_up, full_down = cycle(1.0)
    return np.linspace(0.0, reach, n), 0.5 * (up + down), float(np.max(np.abs(full_up - full_down)))


def largest_linear_motion(xu, f0_hz, zeta, fs):
    """The largest relative motion a linear unit-gain mode (``f0_hz``, ``zeta``, bilinear at ``fs``) driven by
    ``xu`` (from rest) goes through."""
    w = 2.0 * math.pi * f0_hz
    b, a = signal.bilinear([w * w], [1.0, 2.0 * zeta * w, w * w], fs=fs)
    return max(float(np.max(np.abs(signal.lfilter(b, a, xu) - xu))), 1e-12)


def stations(rng, grid, dwell_s, move_s, odds):
    """Where the robot works: one weight per station and grid time (1 there, 0 elsewhere, minimum-jerk moves between),
    stations drawn with ``odds``, dwells of ``dwell_s`` (min, max), moves of ``move_s``."""
    out = np.zeros((len(odds), grid.size))
    at, here = float(grid[0]), int(rng.choice(len(odds), p=odds))
    while at <= grid[-1]:
        dwell, move = rng.uniform(*dwell_s), rng.uniform(*move_s)
        nxt = int(rng.choice(len(odds), p=odds))
        sel = (grid >= at) & (grid < at + dwell + move)
        u = ease((grid[sel] - at - dwell) / move)
        out[here, sel] += 1.0 - u
        out[nxt, sel] += u
        at += dwell + move
        here = nxt
    return out


# ----------------------------------------------------------------------------- profiles and temperature

@functools.lru_cache(maxsize=1)
def tract_parts():
    """The measured Okamura insertion (``../shared/data``, ``time_force.csv``) at 1 kHz, its peak 1: the first
    insertion (from the onset to the end of the withdrawal, tension clipped), the re-entry through the cut tract (the
    measured curve's lower envelope from the onset to the withdrawal: every sample no higher than any later one, which
    strips the capsule's stiffness peak and the puncture's drop) and the withdrawal (from 1 to 0). None when the data
    are absent."""
    try:
        _, fp = profiles.okamura_insertion(peak_n=1.0, rate_hz=1000.0, pre_s=0.0, post_s=0.0)
    except FileNotFoundError:
        return None
    s = np.convolve(fp, np.ones(31) / 31.0, mode="same")
    onset, peak = int(np.argmax(s > 0.03)), int(np.argmax(s))
    level = float(np.median(s[peak + 1000:peak + 6000]))
    late = s[peak + 2000:]
    w0 = peak + 2000 + (int(np.argmax(late < 0.7 * level)) if np.any(late < 0.7 * level) else late.size - 1) - 150
    tail = s[w0:]
    end = w0 + (int(np.argmax(tail <= 0.005)) if np.any(tail <= 0.005) else tail.size - 1)
    first = np.clip(fp[onset:end + 1], 0.0, None)
    first[-1] = 0.0
    envelope = np.clip(np.minimum.accumulate(s[onset:w0][::-1])[::-1], 0.0, None)
    withdraw = np.clip(s[w0:end + 1] / max(float(s[w0]), 1e-6), 0.0, 1.0)
    withdraw[-1] = 0.0
    return first, envelope / max(float(envelope.max()), 1e-9), withdraw


def tract_reentries(duration_s, rate_hz, rng):
    """A robot piercing sites in ex-vivo liver along the measured Okamura insertion (:func:`tract_parts`), replayed
    over 0.7-2 times its length and scaled to a 2.2-8.8 N peak, then re-entering the tract it cut 1-3 times after
    1.5-8 s at rest: the lower envelope over 0.6-1.6 times its length, eased in over 0.15-0.5 s, at 45-80 % of the
    first insertion's post-puncture level (the tract's friction without cutting), each re-entry 85-100 % of the one
    before, then the measured withdrawal over 0.5-1.5 times its length. Sites 5-20 s apart. A train of synthetic
    punctures when the data are absent."""
    parts = tract_parts()
    if parts is None:
        return puncture_train(duration_s, rate_hz, rng)
    first, envelope, withdraw = parts
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    plateau = float(np.median(first[first.size // 3:2 * first.size // 3]))
    cursor = rng.uniform(1.0, 6.0)
    while True:
        peak = rng.uniform(2.2, 8.8)
        pieces = [peak * stretched(first, first.size / 1000.0 * rng.uniform(0.7, 2.0), rate_hz)]
        share = rng.uniform(0.45, 0.8)
        for _ in range(int(rng.integers(1, 4))):
            pieces.append(np.zeros(max(2, int(rng.uniform(1.5, 8.0) * rate_hz))))
            body = stretched(envelope, envelope.size / 1000.0 * rng.uniform(0.6, 1.6), rate_hz)
            body = body * ease(np.arange(body.size) / (rng.uniform(0.15, 0.5) * rate_hz))
            level = peak * plateau * share
            out = stretched(withdraw, withdraw.size / 1000.0 * rng.uniform(0.5, 1.5), rate_hz)
            pieces += [level * body, level * float(body[-1]) * out]
            share *= rng.uniform(0.85, 1.0)
        one = np.clip(np.concatenate(pieces), 0.0, None)
        i0 = int(cursor * rate_hz)
        if i0 + one.size >= t.size - 1:
            break
        f[i0:i0 + one.size] = one
        cursor += one.size / rate_hz + rng.uniform(5.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def brush_calligraphy(duration_s, rate_hz, rng):
    """A robot writing Chinese calligraphy with a brush, the sensor in its wrist: characters of 3-14 strokes, each
    pressed at its start (the force rising in 0.08-0.18 s to 1.3-2 times the stroke's 0.4-2.8 N and held 0.08-0.3 s)
    before a body of 0.3-1.6 s: horizontals rising 0-15 % and ending pressed (1.2-1.6 times for 0.1-0.25 s), verticals
    falling 0-10 % and ending pressed, left-falling sweeps tapering to 15-35 % and lifted in 0.05-0.1 s, right-falling
    sweeps swelling to 1.5-1.9 times and lifted over 0.15-0.3 s, hooks pressed to 1.4-1.8 times and flicked off in
    0.04-0.08 s, and dots (a press to 1.3-1.8 times over 0.08-0.16 s, off in 0.12-0.3 s); 0.15-0.9 s lifted between
    strokes, 0.8-3.5 s between characters, a heavier or lighter hand per character (0.7-1.3); re-inking after 1-3
    characters (2-3 wipes on the inkstone's rim of 0.6-2 N over 0.3-0.8 s); a new sheet every 25-70 s (4-12 s). The
    bristles lag the wrist by 40-110 ms."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)

    def put(at, knots_s, knots_n):
        i0, i1 = np.searchsorted(t, [at, at + knots_s[-1]])
        f[i0:i1] = np.interp(t[i0:i1] - at, knots_s, knots_n)
        return at + knots_s[-1]

    def stroke(at, level):
        kind = int(rng.integers(6))
        if kind == 5:  # a dot
            rise = rng.uniform(0.08, 0.16)
            return put(at, [0.0, rise, rise + rng.uniform(0.12, 0.3)], [0.0, level * rng.uniform(1.3, 1.8), 0.0])
        rise, hold, settle = rng.uniform(0.08, 0.18), rng.uniform(0.08, 0.3), rng.uniform(0.1, 0.2)
        press = level * rng.uniform(1.3, 2.0)
        ks, kn = [0.0, rise, rise + hold, rise + hold + settle], [0.0, press, press, level]
        body = rng.uniform(0.3, 1.6)
        now = ks[-1]
        if kind in (0, 1):  # horizontal or vertical: a pressed end
            end = level * (rng.uniform(1.0, 1.15) if kind == 0 else rng.uniform(0.9, 1.0))
            stop = end * rng.uniform(1.2, 1.6)
            ks += [now + body, now + body + 0.05, now + body + 0.05 + rng.uniform(0.1, 0.25)]
            kn += [end, stop, stop]
            ks.append(ks[-1] + rng.uniform(0.08, 0.2))
            kn.append(0.0)
        elif kind == 2:  # left-falling: tapering to a point
            ks += [now + body, now + body + rng.uniform(0.05, 0.1)]
            kn += [level * rng.uniform(0.15, 0.35), 0.0]
        elif kind == 3:  # right-falling: swelling, then lifted
            ks += [now + body * rng.uniform(0.7, 0.85), now + body, now + body + rng.uniform(0.15, 0.3)]
            swell = level * rng.uniform(1.5, 1.9)
            kn += [swell, swell * 0.9, 0.0]
        else:  # a hook: pressed and flicked off
            hook = level * rng.uniform(1.4, 1.8)
            ks += [now + body, now + body + 0.05, now + body + 0.05 + rng.uniform(0.1, 0.2)]
            kn += [level, hook, hook]
            ks.append(ks[-1] + rng.uniform(0.04, 0.08))
            kn.append(0.0)
        return put(at, ks, kn)

    cursor, sheet_end = rng.uniform(0.5, 3.0), rng.uniform(25.0, 70.0)
    inked = int(rng.integers(1, 4))
    while cursor < duration_s:
        hand = rng.uniform(0.7, 1.3)
        for _ in range(int(rng.integers(3, 15))):
            cursor = stroke(cursor, float(np.clip(hand * rng.uniform(0.4, 2.8), 0.2, 4.0))) + rng.uniform(0.15, 0.9)
        cursor += rng.uniform(0.8, 3.5)
        inked -= 1
        if inked == 0:
            for _ in range(int(rng.integers(2, 4))):
                length = rng.uniform(0.3, 0.8)
                cursor = put(cursor, [0.0, 0.4 * length, 0.6 * length, length], [0.0, rng.uniform(0.6, 2.0), 0.8, 0.0])
                cursor += rng.uniform(0.2, 0.5)
            cursor += rng.uniform(0.8, 2.0)
            inked = int(rng.integers(1, 4))
        if cursor > sheet_end:
            cursor += rng.uniform(4.0, 12.0)
            sheet_end = cursor + rng.uniform(25.0, 70.0)
    return t, np.clip(first_order(f, rng.uniform(0.04, 0.11), rate_hz), 0.0, FORCE_MAX_N)


def strength_tests(duration_s, rate_hz, rng):
    """A robot testing the strength of a weak hand's muscles: 4-8 muscles of 2.5-8.5 N each, three trials per muscle
    5-20 s apart (10-30 s to reposition between muscles), each trial 3-8 % weaker than the one before. Make tests
    (60 %): the patient's push rises over 1-3 s to 85-100 % of the strength, is held 3-5 s while it wavers (3-8 % at
    0.3-1.2 Hz, a physiological tremor of 1-2 % at 8-12 Hz) and fades by 3-10 %, and is released over 0.3-1 s. Break
    tests: the robot pushes at 1.5-4 N/s until the limb gives way at 1.1-1.3 times the strength, the force falling by
    25-50 % within 0.15-0.4 s, then releases over 0.5-1 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cursor = rng.uniform(1.0, 5.0)
    while cursor < duration_s:
        strength = rng.uniform(2.5, 8.5)
        for trial in range(3):
            s = strength * (1.0 - rng.uniform(0.03, 0.08)) ** trial
            if rng.random() < 0.6:
                rise, hold, off = rng.uniform(1.0, 3.0), rng.uniform(3.0, 5.0), rng.uniform(0.3, 1.0)
                i0, i1 = np.searchsorted(t, [cursor, cursor + rise + hold + off])
                u = t[i0:i1] - cursor
                top = s * rng.uniform(0.85, 1.0)
                fade = 1.0 - rng.uniform(0.03, 0.1) * np.clip((u - rise) / hold, 0.0, 1.0)
                waver = (1.0 + rng.uniform(0.03, 0.08) * np.sin(2.0 * np.pi * rng.uniform(0.3, 1.2) * u + rng.uniform(0, 6.3))
                         + rng.uniform(0.01, 0.02) * np.sin(2.0 * np.pi * rng.uniform(8.0, 12.0) * u + rng.uniform(0, 6.3)))
                shape = ease(u / rise) * (1.0 - ease((u - rise - hold) / off))
                f[i0:i1] = top * shape * fade * (1.0 + (waver - 1.0) * ease(u / rise))
                cursor += rise + hold + off
            else:
                give = s * rng.uniform(1.1, 1.3)
                push = give / rng.uniform(1.5, 4.0)
                drop, off = rng.uniform(0.15, 0.4), rng.uniform(0.5, 1.0)
                low = give * (1.0 - rng.uniform(0.25, 0.5))
                knots = [0.0, push, push + drop, push + drop + off]
                i0, i1 = np.searchsorted(t, [cursor, cursor + knots[-1]])
                f[i0:i1] = np.interp(t[i0:i1] - cursor, knots, [0.0, give, low, 0.0])
                cursor += knots[-1]
            cursor += rng.uniform(5.0, 20.0)
        cursor += rng.uniform(10.0, 30.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (tract_reentries, brush_calligraphy, strength_tests)


def cycler_exhaust(rng, grid):
    """The exhaust of a thermal cycler's Peltier heat sink, relative (1: the full heat of a cooling ramp), on ``grid``:
    runs of 25-40 cycles (the first under way before the grid starts) of a denaturation at 95 degC for 10-30 s, a
    cooling ramp at 2-4 degC/s to an annealing at 50-65 degC for 15-30 s, a heating ramp at 3-5 degC/s to an extension at
    72 degC for 15-60 s and another to 95 degC; the sink runs hot (1) on cooling ramps, cool (-0.35 to -0.6) on heating
    ramps and slightly cool (-0.15) in the holds above the room; after the final extension a hold at 4-10 degC keeps it
    warm (0.5-0.7) for 60-600 s until the plate is taken; idle for 60-400 s before the next run."""
    out = np.zeros(grid.size)
    heat_cool, hold_cool, chill = -rng.uniform(0.35, 0.6), -0.15, rng.uniform(0.5, 0.7)

    def put(at, length, value):
        i0, i1 = np.searchsorted(grid, [at, at + length])
        out[i0:i1] = value
        return at + length

    at = float(grid[0]) - rng.uniform(0.0, 1500.0)
    while at < grid[-1]:
        cool, heat = rng.uniform(2.0, 4.0), rng.uniform(3.0, 5.0)
        anneal_c = rng.uniform(50.0, 65.0)
        at = put(at, rng.uniform(60.0, 180.0), hold_cool)
        for _ in range(int(rng.integers(25, 41))):
            at = put(at, rng.uniform(10.0, 30.0), hold_cool)
            at = put(at, (95.0 - anneal_c) / cool, 1.0)
            at = put(at, rng.uniform(15.0, 30.0), hold_cool)
            at = put(at, (72.0 - anneal_c) / heat, heat_cool)
            at = put(at, rng.uniform(15.0, 60.0), hold_cool)
            at = put(at, 23.0 / heat, heat_cool)
            if at > grid[-1]:
                return out
        at = put(at, rng.uniform(60.0, 300.0), hold_cool)
        at = put(at, rng.uniform(60.0, 600.0), chill)
        at += rng.uniform(60.0, 400.0)
    return out


def molecular_bench(t, rng, step_s=0.5):
    """A sensor on a robot at a molecular-biology bench, from 900 s before the record: the room 3 degC below to 0.5
    degC above the reference, drifting by up to +-0.4 degC over the record, its air handling hunting by 0.3-1 degC
    with a period of 500-1400 s; the robot works at the bench (40 %), beside a thermal cycler (35 %) or at an
    ultra-low freezer (25 %), 30-150 s at a time with 4-12 s moves. The cycler's exhaust (:func:`cycler_exhaust`,
    through its sink's and the plume's lag of 4-12 s, meandering by 20-40 % with 5-20 s) is worth 1.5-4 degC beside it
    and 20-40 % of that at the bench. The freezer's compressor (on 200-600 s, off 150-500 s) warms the air beside it by
    0.4-1.2 degC while it runs; on 60 % of the visits its door is opened 3-10 s after the robot arrives, for 8-30 s,
    spilling air 1.5-4 degC colder (approached with 4-10 s, recovered with 30-90 s). The sensor follows with 6-28 s
    (exact per step of ``step_s``)."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-900.0, d + 2.0 * step_s, step_s)
    room = (T_REF_C + rng.uniform(-3.0, 0.5) + rng.uniform(-0.4, 0.4) * np.clip(grid / d, 0.0, 1.0)
            + rng.uniform(0.3, 1.0) * np.sin(2.0 * np.pi * grid / rng.uniform(500.0, 1400.0) + rng.uniform(0.0, 6.3)))
    where = stations(rng, grid, (30.0, 150.0), (4.0, 12.0), (0.4, 0.35, 0.25))
    near_cycler = where[1] + rng.uniform(0.2, 0.4) * where[0]
    keep = math.exp(-step_s / rng.uniform(4.0, 12.0))
    exhaust, _ = signal.lfilter([1.0 - keep], [1.0, -keep], cycler_exhaust(rng, grid), zi=[0.0])
    fade = math.exp(-step_s / rng.uniform(5.0, 20.0))
    meander, _ = signal.lfilter([math.sqrt(1.0 - fade * fade)], [1.0, -fade], rng.normal(0.0, 1.0, grid.size), zi=[0.0])
    plume = rng.uniform(1.5, 4.0) * exhaust * (1.0 + rng.uniform(0.2, 0.4) * np.clip(meander, -2.5, 2.5))
    compressor = np.zeros(grid.size)
    at, running = float(grid[0]) - rng.uniform(0.0, 600.0), bool(rng.random() < 0.5)
    while at <= grid[-1]:
        length = rng.uniform(200.0, 600.0) if running else rng.uniform(150.0, 500.0)
        if running:
            compressor[(grid >= at) & (grid < at + length)] = 1.0
        at += length
        running = not running
    arrive = np.flatnonzero(np.diff((where[2] > 0.5).astype(int)) == 1)
    door = np.zeros(grid.size)
    for i in arrive.tolist():
        if rng.random() < 0.6:
            start = grid[i] + rng.uniform(3.0, 10.0)
            door[(grid >= start) & (grid < start + rng.uniform(8.0, 30.0))] = 1.0
    spill, cold = rng.uniform(1.5, 4.0), 0.0
    fall, rise = math.exp(-step_s / rng.uniform(4.0, 10.0)), math.exp(-step_s / rng.uniform(30.0, 90.0))
    chill = np.empty(grid.size)
    for i, opened in enumerate(door.tolist()):
        goal = spill * opened
        cold = goal + (cold - goal) * (fall if goal > cold else rise)
        chill[i] = cold
    air = room + near_cycler * plume + where[2] * (rng.uniform(0.4, 1.2) * compressor - chill)
    keep = math.exp(-step_s / rng.uniform(6.0, 28.0))
    sensor, _ = signal.lfilter([1.0 - keep], [1.0, -keep], air, zi=[keep * air[0]])
    return np.interp(s, grid, sensor)


# ----------------------------------------------------------------------------- viscous flow

def dripping_leak(fluidity_at_3n, peak_n, drop_ratio, drop_s, step_s=0.01):
    """A core whose oil leaks drop by drop from a fine nozzle. The meniscus is a spherical cap: at a height eta of
    the nozzle's radius its volume is eta (3 + eta^2) / 4 hemispheres and its Laplace pressure ``peak_n`` 2 eta / (1 +
    eta^2), largest for a hemisphere; the volume grows as a (F - P), backing into the nozzle while F < P, and a drop
    falls off at ``drop_ratio`` hemispheres, the meniscus flat again. At 3 N a drop takes ``drop_s``; the mean leak
    there is ``fluidity_at_3n`` times 3 N. The core's output gains the oil lost (the fallen drops and the meniscus).
    Explicit steps of ``step_s``, the meniscus settled at the first force. It never recovers."""
    def laplace(v):
        q = 2.0 * np.asarray(v, dtype=float)
        r = np.sqrt(q * q + 1.0)
        eta = np.cbrt(q + r) + np.cbrt(q - r)
        return peak_n * 2.0 * eta / (1.0 + eta * eta)

    vs = np.linspace(0.0, drop_ratio, 4001)
    per = float(integrate.trapezoid(1.0 / (3.0 - laplace(vs)), vs))
    a = per / drop_s  # hemispheres per N s
    hemisphere = fluidity_at_3n * 3.0 * drop_s / drop_ratio  # V
    table_v = np.linspace(0.0, drop_ratio, 2001)
    table_p = laplace(table_v)
    dv = table_v[1]

    def rule(t, f):
        grid, fg = coarse(t, f, step_s)
        r0 = min(float(fg[0]) / peak_n, 1.0)
        eta0 = 0.0 if r0 <= 0.0 or r0 >= 1.0 else (1.0 - math.sqrt(1.0 - r0 * r0)) / r0
        v, lost = eta0 * (3.0 + eta0 * eta0) / 4.0, 0.0
        out = np.empty(grid.size)
        last = table_p.size - 1
        for i, fi in enumerate(fg.tolist()):
            j = min(int(v / dv), last - 1)
            p = table_p[j] + (table_p[j + 1] - table_p[j]) * (v / dv - j)
            v = max(v + a * (fi - p) * step_s, 0.0)
            if v >= drop_ratio:
                lost, v = lost + v, 0.0
            out[i] = lost + v
        return np.interp(t, grid, hemisphere * (out - out[0]))
    return rule


def jammed_aperture_leak(rate_v_per_s, feed_n, break_n, mean_run_s, rng, step_s=0.01):
    """A core of glass microbeads discharging through an aperture (Beverloo): once the load passes ``feed_n`` the
    core shrinks at ``rate_v_per_s`` whatever the load. Arches clog the aperture after runs of flow drawn from an
    exponential law (mean ``mean_run_s``, Zuriguel's avalanches); an arch holds until the force rises ``break_n``
    above the force it formed at, or the load falls below ``feed_n`` and the grains relax. Steps of ``step_s``. It
    never recovers."""
    runs = rng.exponential(mean_run_s, 512)

    def rule(t, f):
        grid, fg = coarse(t, f, step_s)
        x, k, left, jam = 0.0, 0, float(runs[0]), None
        out = np.empty(grid.size)
        for i, fi in enumerate(fg.tolist()):
            if jam is not None:
                if fi > jam + break_n or fi < feed_n:
                    jam = None
            elif fi > feed_n:
                x += rate_v_per_s * step_s
                left -= step_s
                if left <= 0.0:
                    k += 1
                    jam, left = fi, float(runs[k % runs.size])
            out[i] = x
        return np.interp(t, grid, out)
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def sacrificial_bonds(t, f, opens_v, centre_n, width_n, slow_s, step_s=0.02):
    """A core held together by sacrificial bonds, each a two-state site with Bell-Evans kinetics: site i adds
    ``opens_v[i]`` while open, opening with the logistic of u = (F - ``centre_n[i]``) / ``width_n[i]`` at equilibrium
    and relaxing toward it at cosh(u / 2) / ``slow_s[i]`` (slowest when half open). Exact exponential steps of
    ``step_s``, every site settled at the first force; zero at the first sample."""
    grid, fg = coarse(t, f, step_s)
    n = logistic((fg[0] - centre_n) / width_n)
    out = np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        u = (fi - centre_n) / width_n
        goal = logistic(u)
        n = goal + (n - goal) * np.exp(-np.cosh(0.5 * np.minimum(np.abs(u), 80.0)) * step_s / slow_s)
        out[i] = float(np.dot(opens_v, n))
    return np.interp(t, grid, out - out[0])


def negator_chamber(t, f, stroke_v, spring_n, stiffer, fill_s, step_s=0.01):
    """A hydraulic core whose expelled oil fills a rolling-diaphragm chamber of ``stroke_v`` against a constant-force
    (negator) spring of ``spring_n``, ``stiffer`` more at the end of its stroke: the chamber fills at (F - spring) /
    R through a capillary (R such that 4 N fills it in ``fill_s``), empties likewise below the spring's force, and
    stops at either end. Exact exponential steps of ``step_s``, settled at the first force."""
    resist = fill_s * (4.0 - spring_n * (1.0 + 0.5 * stiffer)) / stroke_v
    rate = spring_n * stiffer / (stroke_v * resist)
    grid, fg = coarse(t, f, step_s)
    goal = np.clip((fg - spring_n) * stroke_v / (spring_n * stiffer), -10.0 * stroke_v, 11.0 * stroke_v)
    keep = math.exp(-rate * step_s)
    y = float(np.clip(goal[0], 0.0, stroke_v))
    out = np.empty(grid.size)
    for i, g in enumerate(goal.tolist()):
        y = min(max(g + (y - g) * keep, 0.0), stroke_v)
        out[i] = y
    return np.interp(t, grid, out - out[0])


# ----------------------------------------------------------------------------- hysteresis

class AutorangeGain(SimOnly):
    """An autoranging DAQ: its high-gain range reads (1 + ``error``) x, its low-gain range x; it switches to the
    low-gain range as |x| passes ``up`` of the range (``top``) and back below ``down`` of it. The firmware linearises
    the mean of both (the high-gain gain below ``down``, their mean between, the low-gain gain above ``up``), so the
    reading departs from x only between the two switching points, by +-``error`` x / 2 depending on the way it came."""

    def __init__(self, top, up, down, error):
        self.top, self.up, self.down, self.error = top, up, down, error

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        u = np.abs(x) / self.top
        high = latch(u < self.down, u > self.up, bool(u[0] < 0.5 * (self.up + self.down)))
        mean = np.where(u < self.down, 1.0, np.where(u > self.up, 0.0, 0.5))
        return x + self.error * x * (high - mean)


class StickySeat(SimOnly):
    """A read-out on a spherical seat preloaded off-centre at ``tilt0``: the load's moment rolls it toward and past
    alignment, to ``tilt0`` - ``roll`` u (u = x / ``top``, ``roll`` in radians per range), while the friction of the wave
    spring that preloads the seat holds the tilt theta within +-w of that (a play, whatever the load). The gauges read
    the axial component and, through the bridge's imperfect compensation, ``bending`` of the moment the tilted line of
    action puts on them: x (cos(theta) + ``bending`` sin(theta)) / (cos(``tilt0``) + ``bending`` sin(``tilt0``)). The
    firmware linearises the mean of a cycle (:func:`mean_branches`); w set for a loop of ``width`` of the range at its
    widest in a full-range cycle (the widest loop any w gives, when that is narrower)."""

    def __init__(self, top, width, tilt0, roll, bending):
        self.top, self.tilt0, self.roll, self.bending = top, tilt0, roll, bending
        self.norm = math.cos(tilt0) + bending * math.sin(tilt0)
        trial = np.linspace(0.02, 0.49, 25) * roll
        widest = float(trial[int(np.argmax([self._loop(w) for w in trial]))])
        self.w = widest
        if self._loop(widest) > width:
            self.w = optimize.brentq(lambda w: self._loop(w) - width, 1e-6, widest, xtol=1e-8)
        self.grid, self.mean, _ = mean_branches(self._read)

    def _loop(self, w):
        self.w = w
        return mean_branches(self._read, n=1201)[2]

    def _read(self, u):
        u = np.asarray(u, dtype=float)
        theta = band_play(self.tilt0 - self.roll * u, self.w, self.w)
        return u * (np.cos(theta) + self.bending * np.sin(theta)) / self.norm

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        u = x / self.top
        return x + self.top * (self._read(u) - np.interp(u, self.grid, self.mean))


# ----------------------------------------------------------------------------- sensor lag

def inverse_chebyshev(delay_s, order, stop_db):
    """An analogue inverse-Chebyshev (type II) low-pass of ``order`` whose stopband is ``stop_db`` down, its cutoff
    set for a group delay of ``delay_s`` at low frequencies (the sum of -1/p over its poles; its zeros, on the imaginary
    axis, add none)."""
    _, poles, _ = signal.cheby2(order, stop_db, 1.0, analog=True, output="zpk")
    edge = float(np.sum((-1.0 / poles).real)) / delay_s
    b, a = signal.cheby2(order, stop_db, edge, analog=True)
    return LinearFilter(b, a)


class PeriodCounter(SimOnly):
    """A capacitive read-out through a relaxation oscillator whose period the load lengthens, P = P0 (1 + ``pull`` x /
    ``top``); the firmware counts a fixed number of periods back to back (``window_s`` at no load) and reports, until
    the next count ends, the mean over the periods of the last one (a mean weighted by 1 / P over its window). Settled
    at the first sample."""

    def __init__(self, top, window_s, pull):
        self.top, self.window, self.pull = top, window_s, pull

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        per = self.window * (1.0 + self.pull * np.clip(x / self.top, -0.5, None))
        phase = integrate.cumulative_trapezoid(1.0 / per, t, initial=0.0)
        held = integrate.cumulative_trapezoid(x / per, t, initial=0.0)
        ends = np.arange(1.0, math.floor(phase[-1]) + 1.0)
        if ends.size == 0:
            return np.full_like(x, x[0])
        t_end = np.interp(ends, phase, t)
        means = np.diff(np.interp(ends, phase, held), prepend=0.0)
        j = np.searchsorted(t_end, t, side="right") - 1
        return np.where(j >= 0, means[np.maximum(j, 0)], x[0])


# ----------------------------------------------------------------------------- nonlinear gain

def eddy_probe(rel, reach, standoff, closing):
    """x read by an eddy-current probe facing a conductive target on the core: the coupling to the target's image,
    (1 + (2 g / a)^2)^(-3/2), the gap g from ``standoff`` coil radii a closed (``closing``) or opened by k x; scaled
    to slope 1 at no load, k set for a departure of ``rel`` at ``reach`` (the gap closed to 0.05 radii or opened by 3 at
    most)."""
    way = -1.0 if closing else 1.0

    def coupling(g):
        return (1.0 + 4.0 * g * g) ** -1.5

    slope = (coupling(standoff + 1e-6) - coupling(standoff - 1e-6)) / 2e-6

    def read(x, k):
        return (coupling(standoff + way * k * np.asarray(x, dtype=float)) - coupling(standoff)) / (way * slope * k)
    return fit_departure(read, rel, reach, ((standoff - 0.05) if closing else 3.0) / reach)


def aperture_shutter(rel, reach, start, opening):
    """x read as the light through a circular aperture across which the core slides a disc of the same size: the
    lens-shaped overlap of two unit circles, 2 acos(d / 2) - (d / 2) sqrt(4 - d^2), the centre distance d from
    ``start`` radii, closed (``opening``: more light) or opened by k x; scaled to slope 1 at no load, k set for a
    departure of ``rel`` at ``reach`` (d kept within 0.02-1.98)."""
    way = -1.0 if opening else 1.0

    def light(d):
        d = np.clip(d, 0.0, 2.0)
        return 2.0 * np.arccos(d / 2.0) - 0.5 * d * np.sqrt(4.0 - d * d)

    slope = (light(start + 1e-6) - light(start - 1e-6)) / 2e-6

    def read(x, k):
        return (light(start + way * k * np.asarray(x, dtype=float)) - light(start)) / (way * slope * k)
    return fit_departure(read, rel, reach, ((start - 0.02) if opening else (1.98 - start)) / reach)


# ----------------------------------------------------------------------------- thermal drift

def rphase_preload_zero(t, temp, k_v_per_c, lag_s, linear, worth_c, apart_c, width_c, where, step_s=0.5):
    """The zero of a read-out preloaded by a nickel-titanium wire in its R-phase transformation (lag ``lag_s``): k
    (``k_v_per_c``) times ``linear`` of the departure plus ``worth_c`` degC times the austenite fraction, which
    stays between two logistic branches of ``width_c`` (the heating branch ``apart_c`` / 2 above the record's
    ``where`` quantile of the wire's temperature, the cooling branch as far below): it follows the heating branch while
    warming, the cooling branch while cooling, and holds between them (minor loops). Steps of ``step_s``; zero at the
    first sample."""
    grid, body = coarse(t, follow(t, temp, lag_s), step_s)
    centre = float(np.quantile(body, where))
    a = float(logistic((body[0] - centre) / width_c))
    share = np.empty(grid.size)
    for i, b in enumerate(body.tolist()):
        low = 1.0 / (1.0 + math.exp(-(b - centre - 0.5 * apart_c) / width_c))
        high = 1.0 / (1.0 + math.exp(-(b - centre + 0.5 * apart_c) / width_c))
        a = min(max(a, low), high)
        share[i] = a
    zero = k_v_per_c * (linear * (body - body[0]) + worth_c * (share - share[0]))
    return np.interp(t, grid, zero)


def cable_loss_zero(t, temp, k_v_per_c, lag_s, activation_k, where, side):
    """The zero of a carrier-frequency bridge whose cable's plasticised PVC (lag ``lag_s``) has its dielectric loss
    peak near the carrier: a Debye relaxation, ln(omega tau) = ``activation_k`` (1 / T - 1 / T_p), the in-phase leakage
    as its loss, sech(ln omega tau), steepest (k, ``k_v_per_c``) at the record's ``where`` quantile of the cable's
    temperature, on the peak's cold (``side`` 1) or warm (-1) flank. Zero at the first sample."""
    body = follow(t, temp, lag_s) + 273.15
    steep = float(np.quantile(body, where))
    inv_peak = 1.0 / steep - side * math.asinh(1.0) / activation_k
    loss = 1.0 / np.cosh(activation_k * (1.0 / body - inv_peak))
    steepest = 0.5 * activation_k / steep ** 2  # the largest |d sech / dT|
    return k_v_per_c / steepest * (loss - loss[0])


# ----------------------------------------------------------------------------- thermal sensitivity

class ParaelectricSpan(SimOnly):
    """A differential capacitive read-out whose gaps hold a (Ba,Sr)TiO3 paraelectric ``above_c`` above its Curie point
    (lag ``lag_s``): Curie-Weiss, x = (T_ref - T_c) / (T - T_c), tuned down by the read-out's bias field (Johnson: the
    span x (1 + b) ^ (1/3) / (1 + b x^3) ^ (1/3), b set for ``tc`` per degC at the reference); it falls as it warms and
    levels off as it cools (held 0.2 of the distance above T_c at least)."""

    def __init__(self, tc, above_c, lag_s):
        self.above, self.lag = above_c, lag_s
        self.b = 1.0 / (tc * above_c) - 1.0

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        ratio = self.above / np.maximum(d + self.above, 0.2 * self.above)
        span = ratio * ((1.0 + self.b) / (1.0 + self.b * ratio ** 3)) ** (1.0 / 3.0)
        return np.asarray(x, dtype=float) * span


def cubic_bspline(u):
    """The cubic B-spline kernel (support -2..2, 2/3 at 0)."""
    a = np.abs(u)
    return np.where(a < 1.0, 2.0 / 3.0 - a * a + 0.5 * a ** 3, np.where(a < 2.0, (2.0 - np.minimum(a, 2.0)) ** 3 / 6.0, 0.0))


class MisfitKnotSpan(SimOnly):
    """A span compensated by firmware through a cubic B-spline in the electronics' temperature (lag ``lag_s``) with
    knots every ``spacing_c``, one knot (the record's ``where`` quantile of that temperature) off by ``error``: the
    span 1 + ``error`` B((T - T_k) / ``spacing_c``) / B(0) relative to where it starts."""

    def __init__(self, error, spacing_c, where, lag_s):
        self.error, self.spacing, self.where, self.lag = error, spacing_c, where, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag)
        knot = float(np.quantile(body, self.where))
        bump = 1.5 * self.error * cubic_bspline((body - knot) / self.spacing)
        return np.asarray(x, dtype=float) * (1.0 + bump) / (1.0 + bump[0])


# ----------------------------------------------------------------------------- offset drift

def dielectric_charging(rng, horizon_s=HORIZON_S, step_s=0.5):
    """Charge trapped in a capacitive read-out's dielectric under its DC bias, switched on 0-300 s before the first
    sample: active spells of 40-200 s at the full bias, idle spells of 15-90 s at 10-35 % of it; ten trap families
    log-spaced between 8-30 s and 300-1500 s, weighted as tau^(-0-0.6), each approaching the bias it sees. As a
    function of the seconds since the first sample, zero there."""
    on = -rng.uniform(0.0, 300.0)
    grid = np.arange(on, horizon_s + step_s, step_s)
    bias = np.empty(grid.size)
    at, active = on, True
    while at <= grid[-1]:
        length = rng.uniform(40.0, 200.0) if active else rng.uniform(15.0, 90.0)
        sel = (grid >= at) & (grid < at + length)
        bias[sel] = 1.0 if active else rng.uniform(0.1, 0.35)
        at += length
        active = not active
    taus = np.geomspace(rng.uniform(8.0, 30.0), rng.uniform(300.0, 1500.0), 10)
    weights = taus ** -rng.uniform(0.0, 0.6)
    charge = exp_convolve(grid - grid[0], bias, 1.0 / taus) @ (weights / taus) / weights.sum()
    first = float(np.interp(0.0, grid, charge))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, charge) - first


def pitting_arm(rng, horizon_s=HORIZON_S, step_s=0.1):
    """The zero of a bridge whose thin-film arm corrodes through a pinhole in its passivation wetted by saline: 1-4
    stable pits started 300 s before to 400 s into the record, each growing as the cube root of its age over 30-300 s
    (weights 0.4-1); metastable pits every 15-60 s on average that rise as the square root of their age over 1-6 s (to
    5-25 % of a stable pit's weight), repassivate within 0.2-0.6 s and keep 10-30 % of it. As a function of the seconds
    since the first sample, zero there."""
    grid = np.arange(-300.0, horizon_s + step_s, step_s)
    out = np.zeros(grid.size)
    for _ in range(int(rng.integers(1, 5))):
        start, grow, weight = rng.uniform(-300.0, 400.0), rng.uniform(30.0, 300.0), rng.uniform(0.4, 1.0)
        out += weight * np.cbrt(np.maximum(grid - start, 0.0) / grow)
    at, gap = -60.0, rng.uniform(15.0, 60.0)
    while True:
        at += rng.exponential(gap)
        if at > grid[-1]:
            break
        rise, drop, size = rng.uniform(1.0, 6.0), rng.uniform(0.2, 0.6), rng.uniform(0.05, 0.25)
        kept = rng.uniform(0.1, 0.3)
        age = grid - at
        growing = size * np.sqrt(np.clip(age / rise, 0.0, 1.0))
        fading = size * (kept + (1.0 - kept) * (1.0 - ease((age - rise) / drop)))
        out += np.where(age < 0.0, 0.0, np.where(age < rise, growing, fading))
    first = float(np.interp(0.0, grid, out))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, out) - first


# ----------------------------------------------------------------------------- resonance

class HydraulicMountMode(GridMode):
    """A needle holder's mode at ``f0_hz`` (unit gain at rest, damping ratio ``zeta`` on its rubber spring) on a
    hydraulic mount: beside the rubber a fluid chamber ``chamber`` times as stiff whose volume a free-floating
    decoupler passes (a fast first-order bypass) while it stays within ``travel`` of the largest relative motion a
    linear mode gives the record; beyond, the decoupler bottoms and the fluid must go through an inertia track (tuned
    to ``track`` of the mode, damping ratio ``track_zeta``): large knocks ring stiffer and die in the track, small ones
    ring on the rubber. Semi-implicit Euler on a uniform grid of ``fs`` Hz, from rest."""

    fs = 3000.0

    def __init__(self, f0_hz, zeta, chamber, travel, track, track_zeta):
        self.w, self.zeta, self.chamber, self.travel = 2.0 * math.pi * f0_hz, zeta, chamber, travel
        self.wt, self.zt = self.w * track, track_zeta

    def on_grid(self, t, tu, xu, h):
        stop = self.travel * largest_linear_motion(xu, self.w / (2.0 * math.pi), self.zeta, self.fs)
        w2, kc, wt2 = self.w * self.w, self.chamber * self.w * self.w, self.wt * self.wt
        c, ct = 2.0 * self.zeta * self.w, 2.0 * self.zt * self.wt
        bypass = math.exp(-8.0 * self.w * h)
        y = v = qt = vt = qd = 0.0
        out = np.empty(tu.size)
        for i, xi in enumerate(xu.tolist()):
            e = xi - y
            goal = e - qt
            qd = min(max(goal + (qd - goal) * bypass, -stop), stop)
            squeeze = e - qt - qd
            vt += (wt2 * squeeze - ct * vt) * h
            qt += vt * h
            v += (w2 * e + kc * squeeze - c * v) * h
            y += v * h
            out[i] = y
        return out


class SqueezeFilmMode(GridMode):
    """A needle holder's mode at ``f0_hz`` (unit gain at rest) whose paddle squeezes an air film between two plates,
    each ``gap`` times the largest relative motion a linear mode gives the record away at rest: the damping ratio
    ``zeta`` times the mean of (g / (g - z))^3 and (g / (g + z))^3 (Reynolds; z held within 0.8 g), so large swings are
    braked hard near their ends. Semi-implicit Euler on a uniform grid of ``fs`` Hz, from rest."""

    fs = 3000.0

    def __init__(self, f0_hz, zeta, gap):
        self.w, self.zeta, self.gap = 2.0 * math.pi * f0_hz, zeta, gap

    def on_grid(self, t, tu, xu, h):
        g = self.gap * largest_linear_motion(xu, self.w / (2.0 * math.pi), self.zeta, self.fs)
        w2, c0 = self.w * self.w, 2.0 * self.zeta * self.w
        y = v = 0.0
        out = np.empty(tu.size)
        for i, xi in enumerate(xu.tolist()):
            z = min(max((y - xi) / g, -0.8), 0.8)
            c = 0.5 * c0 * ((1.0 - z) ** -3 + (1.0 + z) ** -3)
            v += (w2 * (xi - y) - c * v) * h
            y += v * h
            out[i] = y
        return out


# ----------------------------------------------------------------------------- friction

def grosch_oring(t, f, band_n, floor, peak_rate, decades, smooth_s):
    """The force passed by an O-ring on the needle whose rubber friction follows Grosch's bell in the logarithm of
    the slip rate: the band ``band_n`` times ``floor`` + (1 - ``floor``) exp(-(log10(r / ``peak_rate``) /
    ``decades``)^2 / 2), r the rate of the force in N/s smoothed over ``smooth_s``. Started at ``f[0]``."""
    rate_hz = 1.0 / float(np.median(np.diff(t)))
    r = first_order(np.abs(np.gradient(f, t)), smooth_s, rate_hz)
    bell = np.exp(-0.5 * (np.log10(np.maximum(r, 1e-6) / peak_rate) / decades) ** 2)
    band = band_n * (floor + (1.0 - floor) * bell)
    return band_play(f, band, band)


def push_latch(f, band_n, free, click, rearm, locked):
    """The force passed by a needle guide with a push-push latch: locked (a Coulomb band ``band_n``) or free (``free``
    of it), toggled each time the force rises past ``click`` of the record's heaviest after it has fallen below
    ``rearm`` of that click force since the last toggle; ``locked`` at the start. Started at ``f[0]``."""
    top = click * float(np.max(f))
    above, below = f > top, f < rearm * top
    rising = np.flatnonzero(above[1:] & ~above[:-1]) + 1
    low = np.flatnonzero(below)
    flips = np.zeros(f.size)
    armed_from = -1
    for i in rising.tolist():
        j = int(np.searchsorted(low, armed_from, side="right"))
        if armed_from < 0 or (j < low.size and low[j] < i):
            flips[i] = 1.0
            armed_from = i
    state = (np.cumsum(flips) % 2 == 0) == locked
    band = band_n * np.where(state, 1.0, free)
    return band_play(f, band, band)


# ----------------------------------------------------------------------------- thermo-rheological

def soft_core(c):
    """The core made soft enough for its clock to show: its Kelvin spring at most 16 N/V (the retardation time kept)
    and its flow's viscosity within 7e3-3e4 N s/V."""
    k2 = min(c.k2_n_per_v, 16.0)
    return Burgers(c.k1_n_per_v, k2, float(np.clip(c.eta1_n_s_per_v, 7e3, 3e4)), c.eta2_n_s_per_v * k2 / c.k2_n_per_v)


class ExcessActivationClock(SimOnly):
    """A core whose clock follows Roessler's excess activation energy: ln tau = (E + E exp(-mu (T - T_A) / E)) / T (T
    and E in kelvin), T_A ``onset_c`` above the reference, E giving ``share`` of ``b_per_c`` per degC at the reference
    and mu the rest; on the core's temperature (lag ``lag_s``), held within e^+-6."""

    def __init__(self, c, b_per_c, onset_c, share, lag_s):
        ref = T_REF_C + 273.15
        self.c, self.lag, self.onset = c, lag_s, ref + onset_c
        self.e = share * b_per_c * ref * ref
        rest = (1.0 - share) * b_per_c

        def miss(mu):
            x = math.exp(-mu * (ref - self.onset) / self.e)
            return x * (self.e / ref ** 2 + mu / ref) - rest
        self.mu = optimize.brentq(miss, 1e-9, self.e / onset_c * 50.0)
        self.ref_log = self._log_tau(np.array([ref]))[0]

    def _log_tau(self, kelvin_t):
        return (self.e + self.e * np.exp(-self.mu * (kelvin_t - self.onset) / self.e)) / kelvin_t

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag) + 273.15
        rate = np.exp(np.clip(self.ref_log - self._log_tau(body), -6.0, 6.0))
        return on_clock(self.c, t, np.asarray(x, dtype=float), rate)


class FavouredStructuresClock(SimOnly):
    """A core whose clock follows Tanaka's two-order-parameter model: ln tau = (E + dE S(T)) / T (kelvin), S the share
    of locally favoured structures, logistic(``order_k`` (1 / T - 1 / T_s)) with T_s set for ``s_ref`` at the
    reference; E gives ``share`` of ``b_per_c`` per degC there and dE the rest; on the core's temperature (lag
    ``lag_s``), held within e^+-6."""

    def __init__(self, c, b_per_c, share, order_k, s_ref, lag_s):
        ref = T_REF_C + 273.15
        self.c, self.lag, self.order = c, lag_s, order_k
        self.inv_ts = 1.0 / ref - math.log(s_ref / (1.0 - s_ref)) / order_k
        self.e = share * b_per_c * ref * ref
        self.de = (1.0 - share) * b_per_c / (s_ref / ref ** 2 + order_k * s_ref * (1.0 - s_ref) / ref ** 3)
        self.ref_log = self._log_tau(np.array([ref]))[0]

    def _log_tau(self, kelvin_t):
        s = logistic(self.order * (1.0 / kelvin_t - self.inv_ts))
        return (self.e + self.de * s) / kelvin_t

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag) + 273.15
        rate = np.exp(np.clip(self.ref_log - self._log_tau(body), -6.0, 6.0))
        return on_clock(self.c, t, np.asarray(x, dtype=float), rate)


# ----------------------------------------------------------------------------- outside the catalogue

class CrackedTrimJoint(SimOnly):
    """A bridge whose zero-balance resistor sits on a board the load flexes: its cracked joint opens whenever the
    reading passes ``opens`` of the record's largest rise above its first value and closes below ``closes`` of that
    level, chattering 2-5 times over 5-30 ms as it opens (from ``seed``); while it is open the zero is off by
    ``step_v``."""

    def __init__(self, step_v, opens, closes, seed):
        self.step, self.opens, self.closes, self.seed = step_v, opens, closes, seed

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        level = x[0] + self.opens * max(float(np.max(x - x[0])), 1e-9)
        opened = latch(x > level, x < x[0] + self.closes * (level - x[0]), False).astype(float)
        rng = np.random.default_rng(self.seed)
        for i in (np.flatnonzero(np.diff(opened) > 0) + 1).tolist():
            bounces = np.cumsum(rng.uniform(0.2, 1.0, 2 * int(rng.integers(2, 6))))
            edges = t[i] + bounces / bounces[-1] * rng.uniform(0.005, 0.03)
            for a, b in zip(edges[0::2], edges[1::2]):
                j0, j1 = np.searchsorted(t, [a, b])
                opened[j0:j1] = 0.0
        return x + self.step * opened


class LossyDctLink(SimOnly):
    """A wireless link that compresses the reading in blocks of ``block`` samples by an orthonormal discrete cosine
    transform, its coefficients rounded to multiples of ``step_v`` (the small ones to zero), and rebuilds it on
    arrival (the last block padded with its last sample)."""

    def __init__(self, block, step_v):
        self.block, self.step = block, step_v

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        pad = (-x.size) % self.block
        blocks = np.concatenate([x, np.full(pad, x[-1])]).reshape(-1, self.block)
        coeffs = fft.dct(blocks, norm="ortho", axis=1)
        rebuilt = fft.idct(np.round(coeffs / self.step) * self.step, norm="ortho", axis=1)
        return rebuilt.reshape(-1)[:x.size]


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([5.0e4, 4.0e3]))))  # V / (N s)
        if shape == "dripping_nozzle":
            rule = dripping_leak(phi * rng.uniform(1.2, 2.8), rng.uniform(0.3, 2.2), rng.uniform(3.0, 8.0),
                                 rng.uniform(1.5, 15.0))
        else:
            rule = jammed_aperture_leak(phi * rng.uniform(2.0, 4.0) * 3.0, rng.uniform(0.2, 0.8), rng.uniform(0.3, 1.5),
                                        rng.uniform(3.0, 25.0), rng)
        return Parts("zener", LeakingCore.of(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        comp = float(np.interp(m, [0, 1], [0.03, 0.22])) / g0  # of the instantaneous response, V / N
        if shape == "sacrificial_bonds":
            n = int(rng.integers(24, 61))
            centre = np.clip(rng.uniform(1.2, 4.0) * np.exp(rng.uniform(0.2, 0.6) * rng.normal(0.0, 1.0, n)), 0.3, 8.5)
            width = rng.uniform(0.25, 1.0) * rng.uniform(0.7, 1.3, n)
            slow = rng.uniform(1.0, 25.0) * np.exp(rng.uniform(-0.7, 0.7, n))
            gain = float(np.sum(logistic((4.0 - centre) / width) - logistic(-centre / width)))
            opens = np.full(n, comp * 4.0 / max(gain, 1e-9))
            a = (opens, centre, width, slow)
            p.extra.append(lambda t, f, T, a=a: sacrificial_bonds(t, f, *a))
            return p
        spring = rng.uniform(0.3, 1.6)
        a = (comp * 4.0, spring, rng.uniform(0.03, 0.12), rng.uniform(0.6, 10.0))
        p.extra.append(lambda t, f, T, a=a: negator_chamber(t, f, *a))
        return p
    if effect == "hysteresis":
        width = float(np.interp(m, [0, 1], [0.016, 0.07]))
        if shape == "autorange_gain":
            up = rng.uniform(0.3, 0.6)
            p.after.append(AutorangeGain(top, up, up * rng.uniform(0.4, 0.7), float(rng.choice([-1.0, 1.0])) * width / up))
            return p
        p.after.append(StickySeat(top, width, rng.uniform(0.1, 0.4), rng.uniform(0.4, 0.9), rng.uniform(0.6, 1.5)))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.009, 0.1]))))
        if shape == "inverse_chebyshev":
            p.after.append(inverse_chebyshev(delay, int(rng.integers(3, 6)), rng.uniform(25.0, 50.0)))
            return p
        p.after.append(PeriodCounter(top, delay, rng.uniform(0.15, 0.6)))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.05, 0.19]))
        if shape == "eddy_probe":
            p.after.append(StaticMap(eddy_probe(rel, top, rng.uniform(0.15, 0.6), bool(rng.random() < 0.55))))
            return p
        opening = bool(rng.random() < 0.5)
        start = rng.uniform(0.9, 1.8) if opening else rng.uniform(0.2, 1.2)
        p.after.append(StaticMap(aperture_shutter(rel, top, start, opening)))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.007, 0.032]) * rng.choice([-1, 1]))
        if shape == "rphase_preload":
            a = (k, rng.uniform(8.0, 30.0), rng.uniform(0.2, 0.5), rng.uniform(1.5, 4.0), rng.uniform(0.8, 2.5),
                 rng.uniform(0.3, 1.2), rng.uniform(0.3, 0.7))
            p.extra.append(lambda t, f, T, a=a: rphase_preload_zero(t, T, *a))
            return p
        a = (k, rng.uniform(10.0, 50.0), rng.uniform(1.5, 4.0) * 11604.5, rng.uniform(0.25, 0.75), float(rng.choice([-1.0, 1.0])))
        p.extra.append(lambda t, f, T, a=a: cable_loss_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        tc = float(np.interp(m, [0, 1], [0.012, 0.034]))
        if shape == "paraelectric_gap":
            p.after.append(ParaelectricSpan(tc, rng.uniform(8.0, min(25.0, 0.9 / tc)), rng.uniform(5.0, 25.0)))
            return p
        spacing = rng.uniform(1.5, 3.0)
        error = float(rng.choice([-1.0, 1.0])) * tc * spacing / 0.75  # the bump's steepest slope is tc per degC
        p.after.append(MisfitKnotSpan(error, spacing, rng.uniform(0.3, 0.7), rng.uniform(5.0, 25.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.016, 0.095]) * rng.choice([-1, 1]))
        zero = sized(dielectric_charging(rng) if shape == "dielectric_charging" else pitting_arm(rng), size, HORIZON_S)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.032, 0.0045])) * rng.uniform(0.8, 1.2)
        if shape == "hydraulic_mount":
            p.after.append(HydraulicMountMode(rng.uniform(13.0, 46.0), zeta, rng.uniform(0.3, 1.0), rng.uniform(0.15, 0.5),
                                              rng.uniform(0.6, 1.5), rng.uniform(0.15, 0.5)))
            return p
        p.after.append(SqueezeFilmMode(rng.uniform(13.0, 46.0), zeta, rng.uniform(1.3, 4.0)))
        return p
    if effect == "friction":
        band = float(np.interp(m, [0, 1], [0.003, 0.042]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "grosch_oring":
            a = (band, rng.uniform(0.35, 0.7), float(np.exp(rng.uniform(np.log(0.3), np.log(5.0)))), rng.uniform(0.4, 1.0),
                 rng.uniform(0.02, 0.06))
            p.before.append(ForcePath(lambda t, x, a=a: grosch_oring(t, x, *a)))
            return p
        a = (band, rng.uniform(0.15, 0.4), rng.uniform(0.35, 0.65), rng.uniform(0.3, 0.6), bool(rng.random() < 0.5))
        p.before.append(ForcePath(lambda t, x, a=a: push_latch(x, *a)))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.15, 0.5])) * rng.uniform(1.2, 1.5)
        c = soft_core(c)
        if shape == "excess_activation_clock":
            return Parts("burgers", ExcessActivationClock(c, b, rng.uniform(20.0, 80.0), rng.uniform(0.25, 0.5),
                                                          rng.uniform(5.0, 25.0)), core_changed=True)
        return Parts("burgers", FavouredStructuresClock(c, b, rng.uniform(0.3, 0.6), rng.uniform(3000.0, 15000.0),
                                                        rng.uniform(0.1, 0.4), rng.uniform(5.0, 25.0)), core_changed=True)
    if effect == "cracked_trim_joint":
        step = float(np.interp(m, [0, 1], [0.012, 0.06]) * rng.choice([-1, 1]))
        opens = rng.uniform(0.5, 0.8)
        p.outer.append(CrackedTrimJoint(step, opens, rng.uniform(0.75, 0.92), int(rng.integers(1 << 30))))
        return p
    if effect == "lossy_dct_link":
        step = float(np.interp(m, [0, 1], [0.025, 0.12])) * rng.uniform(0.8, 1.2)
        p.outer.append(LossyDctLink(int(rng.choice([64, 128, 256])), step))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["dripping_nozzle", "jammed_aperture"],
    "delayed_elasticity": ["sacrificial_bonds", "negator_chamber"],
    "hysteresis": ["autorange_gain", "sticky_seat"],
    "sensor_lag": ["inverse_chebyshev", "period_counter"],
    "nonlinear_gain": ["eddy_probe", "aperture_shutter"],
    "thermal_drift": ["rphase_preload", "cable_dielectric_loss"],
    "thermal_sensitivity": ["paraelectric_gap", "misfit_knot"],
    "offset_drift": ["dielectric_charging", "pitting_arm"],
    "resonance": ["hydraulic_mount", "squeeze_film"],
    "friction": ["grosch_oring", "push_latch"],
    "thermo_rheological": ["excess_activation_clock", "favoured_structures_clock"],
}
PAIRS = (("friction", "offset_drift"), ("thermal_drift", "delayed_elasticity"), ("hysteresis", "resonance"),
         ("sensor_lag", "viscous_flow"), ("nonlinear_gain", "thermal_sensitivity"), ("thermo_rheological", "friction"))
OUTSIDE = ("cracked_trim_joint", "lossy_dct_link")
RATES = (185.0, 325.0, 1070.0, 1310.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split AD", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.32, 0.84),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=molecular_bench,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(0.75e-3, 2.65e-3), jitter=0.38,
                   gap_s=(0.12, 2.7))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
