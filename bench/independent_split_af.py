"""Independent split AF for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split AF is an untouched held-out set: written blind to the engine it measures (to how it detects and fits anything),
run once, and nothing is ever chosen from it. Every name of the catalogue is hidden in two shapes that neither the
registry's families (``polyforce_ros/sim/truths.py``) nor splits A to AE use:

* a core of a biodegradable polyester hydrolysing in the sea water around it (random chain scission lowers its molar
  mass as 1 / (1 + t / t_s) and the melt's viscosity follows the molar mass to the power 3.4, so the fluidity climbs as
  (1 + t / T)^3.4, 1.6-4 times over the record, from 0.8-1.4 times the plain fluidity of 1/52000-1/4200 V/(N s)), or
  a core leaking through a capillary that holds a train of 6-14 gas bubbles (the Jamin effect: the bubbles hold back
  1-3 N together, shared equally; the leak, 2-4 times the plain fluidity, runs only on the force above what the
  bubbles still in the capillary hold back, and each time the volume passed reaches a bubble spacing, what 10-40 s of
  the plain flow under 1 N passes, one more bubble leaves: the threshold falls in steps as the leak goes on); neither
  ever recovers;
* a core whose polymer network carries dangling chains that relax by their Rouse modes (12-24 Kelvin units of equal
  compliance, the p-th with tau_R / p^2, tau_R 6-80 s: a square-root start and a slow end), or a Kelvin unit (0.6-8 s)
  whose dashpot's oil cavitates while the unit springs back (it holds a suction worth 0.15-0.6 N, so a recovery from a
  large load runs at a capped speed, nearly in a straight line, while creep under load is plain); both settle at
  3.2-22 % of the instantaneous response;
* an overload stop that the core's push meets beyond 12-35 % of the range and that slides on a rough face with a
  friction proportional to how far it is pushed past contact (0.3-0.6 of it: a loop that opens only above the stop and
  widens toward the top of the range; the firmware linearises the mean curve), or the read head of a magnetic scale
  whose poles, 5-14 % of the range apart, pull it onto its guide (a play whose half-width swings as cos^2 along the
  range between 15-45 % and all of its largest); loops of 1.6-7 % of the range (the stop's at 70 % of the range, the
  head's at their widest);
* a diaphragm seal filled with silicone oil (a lag of 75-95 % of the delay and, for the transducer's cavity, a second
  one of the rest; the oil's viscosity, and with it the first lag, falling by 2-4.5 %/degC of the seal's temperature,
  lag 10-40 s), or a DAQ on a distributed-clock fieldbus whose synchronisation servo hunts (the bridge's delay behind
  the force swinging by 15-35 % about its mean as a rounded triangle with a period of 30-150 s); 11-100 ms of delay (at
  the reference, or on average);
* a capacitive read-out whose electrode is hinged at one edge (the gap tapers along the plate, the capacitance as
  -ln(1 - u) / u of the tilt u at its free edge: expansive when the load closes the gap, compressive when it opens it),
  or an evanescent directional coupler between two fibre cores whose gap the load closes (the power crossing over as
  sin^2 of a coupling of 0.25-1.2 rad at rest that grows exponentially as the gap closes: expansive, S-shaped or
  compressive); 5.5-19 % at the top of the range (at most, over the range);
* the zero of an oil-filled housing whose pressure compensator (a spring-loaded piston) takes up the fill's expansion
  over +-0.4-1.3 degC about a centre within 0.8 degC of the reference (15-35 % of the slope there), the fill pressing on
  the gauges with the whole slope once the piston meets an end stop (knees 0.2-0.5 degC wide; lag 8-35 s), or of a two-wire
  quarter bridge whose copper leads run partly inside the housing (35-75 %, lag 2-8 s) and partly along the
  manipulator's arm (lag 40-120 s); 0.0078-0.032 V/degC (the compensator's beyond its travel);
* the span of a read-out excited, without a ratiometric reference, from a primary lithium battery (the drop across the
  cell's internal resistance, Arrhenius, 4.5-9 %/degC lower as it warms, takes a share of its voltage; lag 12-45 s),
  or of a conducting-polymer gauge read at constant current whose resistance follows variable-range hopping (exp((T0 /
  T)^p), p from 1/4 (Mott) to 1/2 (Efros-Shklovskii); lag 5-30 s); 1.4-3.6 %/degC at the reference;
* the weight of silt settling on the read-out's exposed diaphragm (each burst of the thrusters, 2-6 s every 15-90 s,
  stirs up a cloud that settles over 15-80 s; 0-2 sweeps of the arm wash 30-70 % of the deposit off within 1-3 s), or
  a chopper amplifier's ripple aliased by the ADC's clock into a slow rounded triangle (a period of 60-300 s that wanders
  by 10-30 % as the two clocks drift apart); 16-94 mV at most;
* a holder's mode (12-50 Hz) on a strut preloaded near its buckling load (its spring softening as the tanh of the
  motion, whose scale is 0.5-1.5 times the largest relative motion a linear mode would reach), or a mode damped by a
  butyl-rubber pad whose loss rises by 8-20 % per degC as it cools (and its stiffness by 1-3 % per degC; the pad follows
  with 15-60 s); damping ratio 0.0036-0.038 at the reference, the small-amplitude frequency constant for the strut;
* a Coulomb band of 0.22-5.5 % of the range, the same at every load: a fresh shaft seal that runs in (1.6-2.4 times its
  run-in band at first, wearing toward it as exp(-s / s0) of the slip s, s0 5-30 N of the passed force's travel), or a
  bushing whose aluminium housing shrinks onto the tool's steel sleeve below a temperature from 0.5 degC below to 2
  degC above the reference (25-50 % of the band at the reference while the clearance is open, growing with the
  interference over a knee of 0.4-1.2 degC, at most three times that band; the bushing follows with 20-80 s);
* a core (soft enough for its clock to show) whose clock follows Bassler's law (ln tau as (T_B / T)^2), or the hybrid
  free-volume and activation law of Macedo and Litovitz (ln tau = E / T + B / (T - T0), 30-70 % of the slope from the
  activation, T0 45-110 K below the reference); 1.2-1.5 times 0.18-0.5 per degC at the reference, lag 4-28 s.

It also holds six pairs, two effects outside the catalogue (the foil gauge's grid fatiguing under the record's own
cycling, its span falling with Miner's sum of the half-cycles' ranges to the power 3-5, by 6.8-12.8 % at the record's
end; a reference load cell read over the tether's serial link whose samples are stamped 50-145 ms late, so that the
sensor seems to answer before the force) and four clean records. Profiles: sponge biopsies through a teleoperated
manipulator (the measured Okamura insertion, ``../shared/data``, ``time_force.csv``, replayed along the pilot's progress,
0.5-1.6 times its speed with a wander of 25 % and 1-3 stops of 0.4-2.5 s, the measured hold passed 1.5-3 times faster,
each scaled to a 2.2-8.6 N peak and rendered through the slave arm's position servo (6-16 Hz, damping ratio
0.45-0.8); sites 6-22 s apart; a train of synthetic punctures when the data are absent); kelp pulled off a mooring line
(the pull loading at 0.8-3.5 N/s, 3-12 haptera letting go one by one, each taking 6-30 % of the force, the rate falling
as fewer hold, up to 2.5-8.8 N, the stipe swaying in the current); and push cores of the seabed's sediment (2-4
strokes, the force growing with depth as the tip resistance and the wall friction grow, 0-3 shell layers, the pilot
regripping between strokes, a breakaway at each new stroke, a hold on the full core while it relaxes, up to 2.5-7.5
N at full depth). Rates 145, 395, 1110 and 1390 Hz (a mode at 1000 Hz with knocks that excite it), 0.58-2.42 mV
noise, stamp jitter, gaps, and a sensor in the oil-filled wrist of a work-class ROV's manipulator in a fjord: warm
surface water over a thermocline and cold deep water, internal waves heaving the thermocline, the ROV moving between
work sites about it and keeping station, its hydraulic power unit warming the wrist's oil while it works.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size against its
noise without diagnosing (for a leak on a Zener base, against that bare Zener core).

    .venv/bin/python bench/independent_split_af.py [--json out.json] [--workers 1] [--stride 1] [--check]
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

SEED0 = 2_400_000  # never a seed of the registry's splits nor of splits A (90000..) to AE (2300000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 430.0
HORIZON_S = DURATION_S + 60.0  # what a schedule drawn before the record covers (the record plus its gaps' slack)


# ----------------------------------------------------------------------------- small tools

def softplus(u, width):
    """width ln(1 + exp(u / width)): a knee of ``width`` between 0 and u, without overflow."""
    return width * np.logaddexp(0.0, np.asarray(u, dtype=float) / width)


def rounded_triangle(phase):
    """A triangle wave of unit amplitude in ``phase`` (rad) with rounded tips."""
    return (2.0 / math.pi) * np.arcsin(0.96 * np.sin(phase)) / ((2.0 / math.pi) * math.asin(0.96))


def ou_path(rng, n, keep):
    """A unit Ornstein-Uhlenbeck path of ``n`` steps (``keep`` of it kept per step), from zero, held within +-2.5."""
    path, _ = signal.lfilter([math.sqrt(1.0 - keep * keep)], [1.0, -keep], rng.normal(0.0, 1.0, n), zi=[0.0])
    return np.clip(path, -2.5, 2.5)


def lag_steps(x, keep):
    """``x`` through a first-order lag that keeps ``keep`` per step, at rest with its first value."""
    y, _ = signal.lfilter([1.0 - keep], [1.0, -keep], x, zi=[keep * x[0]])
    return y


def servo(x, f_hz, zeta, rate_hz):
    """``x`` (uniform at ``rate_hz``) through a unit-gain second-order low-pass (``f_hz``, ``zeta``), from rest."""
    w = 2.0 * math.pi * f_hz
    b, a = signal.bilinear([w * w], [1.0, 2.0 * zeta * w, w * w], fs=rate_hz)
    return signal.lfilter(b, a, x)


def linear_reach(xu, w, zeta, fs):
    """The largest relative motion of a linear unit-gain mode (``w`` rad/s, ``zeta``, bilinear at ``fs``) driven by
    ``xu`` from rest."""
    b, a = signal.bilinear([w * w], [1.0, 2.0 * zeta * w, w * w], fs=fs)
    return max(float(np.max(np.abs(signal.lfilter(b, a, xu) - xu))), 1e-12)


def raised_bumps(u, centres, widths, heights):
    """A sum of raised-cosine bumps in ``u`` (each ``widths`` wide at its foot, ``heights`` high)."""
    out = np.zeros_like(u)
    for c, w, h in zip(centres, widths, heights):
        near = np.abs(u - c) < 0.5 * w
        out[near] += h * 0.5 * (1.0 + np.cos(2.0 * math.pi * (u[near] - c) / w))
    return out


# ----------------------------------------------------------------------------- profiles and temperature

@functools.lru_cache(maxsize=1)
def measured_curve():
    """The measured Okamura insertion (``../shared/data``, ``time_force.csv``) at 1 kHz, its peak 1, from its onset to
    the end of its withdrawal, tension clipped: (the curve, the index where its hold begins, the index where its
    withdrawal begins). None when the data are absent."""
    try:
        _, fp = profiles.okamura_insertion(peak_n=1.0, rate_hz=1000.0, pre_s=0.0, post_s=0.0)
    except FileNotFoundError:
        return None
    s = np.convolve(fp, np.ones(31) / 31.0, mode="same")
    onset, peak = int(np.argmax(s > 0.04)), int(np.argmax(s))
    hold = min(peak + 600, s.size - 1)
    level = float(np.median(s[hold:hold + 4000]))
    late = np.nonzero(s[hold:] < 0.6 * level)[0]
    release = hold + (int(late[0]) if late.size else s.size - 1 - hold)
    after = np.nonzero(s[release:] < 0.02)[0]
    end = release + (int(after[0]) if after.size else s.size - 1 - release)
    curve = np.clip(fp[onset:end + 1], 0.0, None)
    curve[0], curve[-1] = 0.0, 0.0
    return curve / max(float(curve.max()), 1e-9), hold - onset, release - onset


def teleoperated_biopsies(duration_s, rate_hz, rng):
    """Sponge biopsies through a teleoperated manipulator: the measured insertion (:func:`measured_curve`) replayed along
    the pilot's progress (0.5-1.6 times its speed, wandering by 25 % over 2-10 s, 1-3 stops of 0.4-2.5 s in which the
    force is held, the measured hold passed 1.5-3 times faster), scaled to a 2.2-8.6 N peak and rendered through the slave
    arm's position servo (6-16 Hz, damping ratio 0.45-0.8). Sites 6-22 s apart; a train of synthetic punctures when the
    data are absent."""
    parts = measured_curve()
    if parts is None:
        return puncture_train(duration_s, rate_hz, rng)
    curve, hold, release = parts
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cursor = rng.uniform(1.0, 6.0)
    while True:
        base, skip = rng.uniform(0.5, 1.6), rng.uniform(1.5, 3.0)
        span_s = 3.0 * curve.size / 1000.0 / base + 10.0
        u = np.arange(0.0, span_s, 1.0 / rate_hz)
        wander = sum(np.sin(2.0 * math.pi * u / rng.uniform(2.0, 10.0) + rng.uniform(0.0, 2.0 * math.pi)) for _ in range(2))
        speed = base * np.clip(1.0 + 0.125 * wander, 0.3, None)
        nominal = curve.size / 1000.0 / base
        for at in rng.uniform(0.05, 0.7, int(rng.integers(1, 4))) * nominal:
            stop, edge = rng.uniform(0.4, 2.5), rng.uniform(0.15, 0.4)
            speed *= 1.0 - ease((u - at) / edge) * (1.0 - ease((u - at - stop) / edge))
        raw = np.cumsum(speed) / rate_hz * 1000.0  # samples of the measured curve at the pilot's pace
        passed = hold + (release - hold) / skip
        progress = np.interp(raw, [0.0, hold, passed, passed + 1e7], [0.0, hold, release, release + 1e7])
        inside = progress < curve.size - 1
        one = np.interp(progress[inside], np.arange(curve.size), curve) * rng.uniform(2.2, 8.6)
        one = servo(np.concatenate([one, np.zeros(int(0.6 * rate_hz))]), rng.uniform(6.0, 16.0), rng.uniform(0.45, 0.8),
                    rate_hz)
        i0 = int(cursor * rate_hz)
        if i0 + one.size >= t.size - 1:
            break
        f[i0:i0 + one.size] = one
        cursor += one.size / rate_hz + rng.uniform(6.0, 22.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def kelp_pulls(duration_s, rate_hz, rng):
    """Kelp pulled off a mooring line: after 0.2-0.6 s of slack the pull loads at 0.8-3.5 N/s; its 3-12 haptera let go
    one by one at loads spread over 25-100 % of the holdfast's strength (2.5-8.8 N), each failure taking 6-30 % of the
    force within 10-50 ms, the loading rate falling as the square root of the share still holding; the last one releases
    the plant. The stipe sways in the current (0.3-0.8 Hz, 3-8 % of the force). A new plant every 6-20 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cursor = rng.uniform(1.0, 4.0)
    while cursor < duration_s:
        strength, n = rng.uniform(2.5, 8.8), int(rng.integers(3, 13))
        fails = np.sort(rng.uniform(0.25, 1.0, n)) * strength
        fails[-1] = strength
        rate0 = rng.uniform(0.8, 3.5)
        elapsed = rng.uniform(0.2, 0.6)
        knots_t, knots_f, level = [0.0, elapsed], [0.0, 0.0], 0.0
        for j, fj in enumerate(fails):
            target = max(float(fj), level + 0.05)
            elapsed += (target - level) / (rate0 * math.sqrt((n - j) / n))
            knots_t.append(elapsed)
            knots_f.append(target)
            elapsed += rng.uniform(0.01, 0.05)
            level = 0.0 if j == n - 1 else target * (1.0 - rng.uniform(0.06, 0.3))
            knots_t.append(elapsed)
            knots_f.append(level)
        i0, i1 = np.searchsorted(t, [cursor, cursor + elapsed])
        u = t[i0:i1] - cursor
        sway = 1.0 + rng.uniform(0.03, 0.08) * np.sin(2.0 * math.pi * rng.uniform(0.3, 0.8) * u + rng.uniform(0, 6.3))
        f[i0:i1] = np.interp(u, knots_t, knots_f) * sway
        cursor += elapsed + rng.uniform(6.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def push_cores(duration_s, rate_hz, rng):
    """Push cores of the seabed's sediment: the tube driven in 2-4 strokes of 1.5-5 s (minimum-jerk in depth), the force
    a z + (1 - a) z^2 of the depth z (tip resistance and wall friction growing with depth, a 0.3-0.7) up to 2.5-7.5 N,
    0-3 shell layers (0.3-1.5 N more over 1-4 % of the depth); between strokes the pilot regrips (the force falling to
    0-15 % of itself within 0.2-0.5 s for 1-3 s) and each new stroke breaks the sediment away again (10-30 % more,
    fading within 0.1-0.4 s); the full core held 2-6 s while the sediment relaxes by 10-25 % (1-3 s), then pulled out.
    A new core every 8-30 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cursor = rng.uniform(1.0, 4.0)
    while True:
        top, a = rng.uniform(2.5, 7.5), rng.uniform(0.3, 0.7)
        k = int(rng.integers(0, 4))
        layers = (rng.uniform(0.1, 0.95, k), rng.uniform(0.01, 0.04, k), rng.uniform(0.3, 1.5, k))

        def load(z, top=top, a=a, layers=layers):
            return top * (a * z + (1.0 - a) * z * z) + raised_bumps(z, *layers)
        strokes = int(rng.integers(2, 5))
        depths = np.concatenate([[0.0], np.sort(rng.uniform(0.0, 1.0, strokes - 1)), [1.0]])
        pieces = []
        for j in range(strokes):
            length = rng.uniform(1.5, 5.0)
            u = np.arange(int(length * rate_hz)) / rate_hz
            z = depths[j] + (depths[j + 1] - depths[j]) * ease(u / length)
            piece = load(z)
            if j:
                start = float(load(np.array([depths[j]]))[0])
                piece = piece + start * rng.uniform(0.1, 0.3) * np.exp(-u / rng.uniform(0.1, 0.4)) * ease(u / 0.03)
            pieces.append(piece)
            end = float(load(np.array([depths[j + 1]]))[0])
            if j < strokes - 1:
                drop, rest = rng.uniform(0.2, 0.5), rng.uniform(1.0, 3.0)
                u = np.arange(int((drop + rest) * rate_hz)) / rate_hz
                pieces.append(end * (1.0 - (1.0 - rng.uniform(0.0, 0.15)) * ease(u / drop)))
        u = np.arange(int(rng.uniform(2.0, 6.0) * rate_hz)) / rate_hz
        held = end * (1.0 - rng.uniform(0.1, 0.25) * -np.expm1(-u / rng.uniform(1.0, 3.0)))
        out = np.linspace(held[-1], 0.0, max(2, int(rng.uniform(0.1, 0.3) * rate_hz)))
        one = np.concatenate(pieces + [held, out])
        i0 = int(cursor * rate_hz)
        if i0 + one.size >= t.size - 1:
            break
        f[i0:i0 + one.size] = one
        cursor += one.size / rate_hz + rng.uniform(8.0, 30.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (teleoperated_biopsies, kelp_pulls, push_cores)


def fjord_dive(t, rng, step_s=0.5):
    """A sensor in the oil-filled wrist of a work-class ROV's manipulator in a fjord, from 900 s before the record. The
    water is 0.5-3 degC above the reference in the surface layer and 2-5 degC below it in the deep, across a
    thermocline at 12-30 m, 1.5-5 m thick, that internal waves heave by 1-4 m (a period of 180-600 s) and 0.3-1.2 m (60-150
    s). The ROV works at sites within 1.2 thicknesses of the thermocline, 60-240 s at each, 15-60 s to move between
    them, keeping station within 0.3-1 m (correlated over 10-30 s); its hydraulic power unit warms the wrist's oil by
    0.3-1.2 degC while it works (60-150 s). The sensor follows the water through the housing with 12-45 s (exact per
    step of ``step_s``)."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-900.0, d + 2.0 * step_s, step_s)
    surface, deep = T_REF_C + rng.uniform(0.5, 3.0), T_REF_C - rng.uniform(2.0, 5.0)
    centre, thick = rng.uniform(12.0, 30.0), rng.uniform(1.5, 5.0)
    heave = (rng.uniform(1.0, 4.0) * np.sin(2.0 * math.pi * grid / rng.uniform(180.0, 600.0) + rng.uniform(0, 6.3))
             + rng.uniform(0.3, 1.2) * np.sin(2.0 * math.pi * grid / rng.uniform(60.0, 150.0) + rng.uniform(0, 6.3)))
    depth, working = np.empty(grid.size), np.zeros(grid.size)
    at, here = float(grid[0]), centre + rng.uniform(-1.2, 1.2) * thick
    while at <= grid[-1]:
        dwell, move = rng.uniform(60.0, 240.0), rng.uniform(15.0, 60.0)
        there = centre + rng.uniform(-1.2, 1.2) * thick
        sel = (grid >= at) & (grid < at + dwell + move)
        depth[sel] = here + (there - here) * ease((grid[sel] - at - dwell) / move)
        working[sel] = (grid[sel] < at + dwell).astype(float)
        at, here = at + dwell + move, there
    depth = depth + rng.uniform(0.3, 1.0) * ou_path(rng, grid.size, math.exp(-step_s / rng.uniform(10.0, 30.0)))
    water = deep + (surface - deep) * logistic((centre + heave - depth) / (0.3 * thick))
    oil = rng.uniform(0.3, 1.2) * lag_steps(working, math.exp(-step_s / rng.uniform(60.0, 150.0)))
    sensor = lag_steps(water + oil, math.exp(-step_s / rng.uniform(12.0, 45.0)))
    return np.interp(s, grid, sensor)


# ----------------------------------------------------------------------------- viscous flow

def hydrolysing_leak(fluidity, growth, duration_s):
    """A core hydrolysing as it flows: the fluidity ``fluidity`` (1 + t / T)^3.4, T such that it grows ``growth``
    times over ``duration_s``."""
    scale = duration_s / (growth ** (1.0 / 3.4) - 1.0)

    def rule(t, f):
        phi = fluidity * (1.0 + (t - t[0]) / scale) ** 3.4
        return integrate.cumulative_trapezoid(phi * f, t, initial=0.0)
    return rule


def jamin_leak(fluidity, bubbles, hold_n, spacing_v, step_s=0.02):
    """A leak (``fluidity``) through a capillary holding ``bubbles`` gas bubbles, each holding back ``hold_n``: it runs
    on the force above what the bubbles left hold back, and a bubble leaves each time the volume passed grows by
    ``spacing_v``. Exact per step of ``step_s``, from rest."""
    def rule(t, f):
        grid, fg = coarse(t, f, step_s)
        out, x, left, exit_at = np.empty(grid.size), 0.0, bubbles, spacing_v
        for i, fi in enumerate(fg.tolist()):
            out[i] = x
            x += fluidity * max(fi - left * hold_n, 0.0) * step_s
            while left and x >= exit_at:
                left -= 1
                exit_at += spacing_v
        return np.interp(t, grid, out)
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def rouse_creep(t, f, compliance, tau_r, modes):
    """The delayed deformation of dangling chains relaxing by their Rouse modes: ``compliance`` (V/N) shared equally
    over ``modes`` Kelvin units, the p-th with ``tau_r`` / p^2, from rest."""
    p = np.arange(1.0, modes + 1.0)
    rates = p * p / tau_r
    return compliance / modes * exp_convolve(t, f, rates) @ rates


def cavitating_kelvin(t, f, compliance, tau_s, suction_n, step_s=0.01):
    """A Kelvin unit (``compliance`` V/N, ``tau_s``) whose dashpot's oil cavitates while it springs back: the force
    drawing it back is held within ``suction_n``. Exact per step of ``step_s`` while it creeps, from rest at the first
    force."""
    grid, fg = coarse(t, f, step_s)
    keep, cap = -math.expm1(-step_s / tau_s), suction_n * step_s / tau_s
    out, u = np.empty(grid.size), float(fg[0])
    for i, g in enumerate(fg.tolist()):
        out[i] = u
        u += (g - u) * keep if g >= u else -min((u - g) * keep, cap)
    return compliance * np.interp(t, grid, out)


# ----------------------------------------------------------------------------- hysteresis

class OverloadStop(SimOnly):
    """An overload stop met beyond ``knee_v``, sliding with a friction of ``mu`` times how far it is pushed past
    contact; the reading gains ``gain`` times the stop's stick (its travel less the play that friction leaves)."""

    def __init__(self, knee_v, mu, gain):
        self.knee, self.mu, self.gain = knee_v, mu, gain

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        e = np.maximum(x - self.knee, 0.0)
        return x + self.gain * (e - band_play(e, self.mu * e, self.mu * e))


class PoleStripHead(SimOnly):
    """The read head of a magnetic scale pulled onto its guide by the poles: a play of half-width ``band_v`` (``floor``
    + (1 - ``floor``) cos^2(pi x / ``pitch_v`` + ``phase``)) along the reading x."""

    def __init__(self, band_v, pitch_v, floor, phase):
        self.band, self.pitch, self.floor, self.phase = band_v, pitch_v, floor, phase

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        band = self.band * (self.floor + (1.0 - self.floor) * np.cos(math.pi * x / self.pitch + self.phase) ** 2)
        return band_play(x, band, band)


# ----------------------------------------------------------------------------- sensor lag

class SiliconeOilSeal(SimOnly):
    """A diaphragm seal filled with silicone oil: a lag of ``tau_s`` at the reference that shortens by ``per_c`` per
    degC of the seal's temperature (lag ``lag_s``), behind it the transducer's cavity (``cavity_s``); on a uniform grid
    (the slow lag constant over steps of 0.25 s), at rest with the first value."""

    def __init__(self, tau_s, cavity_s, per_c, lag_s):
        self.tau, self.cavity, self.per_c, self.lag = tau_s, cavity_s, per_c, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, y, h = uniform_grid(t, x)
        seal = np.interp(tu, t, follow(t, temp_of(aux, t.size), self.lag)) - T_REF_C
        keep = np.exp(-h / (self.tau * np.exp(-self.per_c * np.clip(seal, -15.0, 15.0))))
        chunk, last = max(1, int(round(0.25 / h))), float(y[0])
        out = np.empty_like(y)
        for i0 in range(0, y.size, chunk):
            a = float(np.mean(keep[i0:i0 + chunk]))
            out[i0:i0 + chunk], _ = signal.lfilter([1.0 - a], [1.0, -a], y[i0:i0 + chunk], zi=[a * last])
            last = float(out[min(i0 + chunk, y.size) - 1])
        out = lag_steps(out, math.exp(-h / self.cavity))
        return np.interp(t, tu, out)


class HuntingSync(SimOnly):
    """A DAQ whose clock synchronisation hunts: the bridge's delay ``delay_s`` (1 + ``swing`` w(t)), w a rounded
    triangle of period ``period_s``."""

    def __init__(self, delay_s, swing, period_s, phase):
        self.delay, self.swing, self.period, self.phase = delay_s, swing, period_s, phase

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        w = rounded_triangle(2.0 * math.pi * (t - t[0]) / self.period + self.phase)
        return np.interp(t - self.delay * (1.0 + self.swing * w), t, x, left=x[0])


# ----------------------------------------------------------------------------- nonlinear gain

def tilted_plate(rel, reach, closing):
    """x read as the capacitance of a hinged electrode: -ln(1 - u) / u - 1 of the tilt u = k x at its free edge
    (``closing``: expansive) or 1 - ln(1 + u) / u as it opens (compressive); slope 1 at no load, k for a departure of
    ``rel`` at ``reach``."""
    def share(u):
        small = np.abs(u) < 1e-5
        safe = np.where(small, 0.5, u)
        return np.where(small, 0.5 * u, -np.log1p(-safe) / safe - 1.0)

    if closing:
        def read(x, k):
            return 2.0 / k * share(np.clip(k * x, -0.5, 0.95))
        return fit_departure(read, rel, reach, 0.95 / reach)

    def read(x, k):
        return 2.0 / k * -share(-np.clip(k * x, -0.5, None))
    return fit_departure(read, rel, reach, 8.0 / reach)


def evanescent_coupler(rel, reach, kappa0):
    """x read through an evanescent coupler: the power crossing over as sin^2(``kappa0`` exp(k x)) (slope 1 at no load,
    the coupling held below 1.5 rad), k for a departure of ``rel`` at ``reach``."""
    s0, slope = math.sin(kappa0) ** 2, math.sin(2.0 * kappa0) * kappa0
    room = math.log(1.5 / kappa0)

    def read(x, k):
        kappa = kappa0 * np.exp(np.clip(k * x, -3.0, room))
        return (np.sin(kappa) ** 2 - s0) / (slope * k)
    return fit_departure(read, rel, reach, room / reach)


# ----------------------------------------------------------------------------- thermal drift

def compensator_zero(t, temp, k_v_per_c, inside, centre_c, half_c, knee_c, lag_s):
    """The zero of an oil-filled housing whose compensator takes up the fill's expansion within ``half_c`` of
    ``centre_c`` (``inside`` of the slope ``k_v_per_c`` there, all of it beyond, knees ``knee_c`` wide); on the fill's
    temperature (lag ``lag_s``), zero at the reference."""
    def shape(d):
        return (inside * d + (1.0 - inside) * (softplus(d - centre_c - half_c, knee_c) - softplus(centre_c - half_c - d, knee_c)))
    d = follow(t, temp, lag_s) - T_REF_C
    return k_v_per_c * (shape(d) - shape(0.0))


def lead_zero(t, temp, k_v_per_c, inner, inner_lag_s, arm_lag_s):
    """The zero of a two-wire quarter bridge's copper leads: ``k_v_per_c`` times their mean temperature's departure,
    ``inner`` of them inside the housing (lag ``inner_lag_s``), the rest along the arm (lag ``arm_lag_s``)."""
    mean = inner * follow(t, temp, inner_lag_s, step_s=0.1) + (1.0 - inner) * follow(t, temp, arm_lag_s)
    return k_v_per_c * (mean - T_REF_C)


# ----------------------------------------------------------------------------- thermal sensitivity

class BatteryExcitation(SimOnly):
    """A span set by a primary battery's voltage less the drop across its internal resistance (exp(-``per_c`` dT),
    dT of the cell's temperature, lag ``lag_s``), that drop taking the share that gives ``tc`` per degC at the
    reference."""

    def __init__(self, tc, per_c, lag_s):
        self.q, self.per_c, self.lag = tc / (per_c + tc), per_c, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = np.clip(follow(t, temp_of(aux, t.size), self.lag) - T_REF_C, -15.0, 15.0)
        span = (1.0 - self.q * np.exp(-self.per_c * d)) / (1.0 - self.q)
        return np.asarray(x, dtype=float) * np.maximum(span, 0.2)


class HoppingGauge(SimOnly):
    """A conducting-polymer gauge read at constant current: the span as its resistance, exp((T0 / T)^``p``) relative
    to the reference, T0 for ``tc`` per degC at the reference; on the gauge's temperature (lag ``lag_s``)."""

    def __init__(self, tc, p, lag_s):
        self.ref = T_REF_C + 273.15
        self.a, self.p, self.lag = tc * self.ref / p, p, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = np.clip(follow(t, temp_of(aux, t.size), self.lag), T_REF_C - 20.0, T_REF_C + 20.0) + 273.15
        return np.asarray(x, dtype=float) * np.exp(self.a * ((self.ref / body) ** self.p - 1.0))


# ----------------------------------------------------------------------------- offset drift

def silt_deposit(rng, horizon_s=HORIZON_S, step_s=0.1):
    """The weight of silt settling on an exposed diaphragm: thruster bursts of 2-6 s every 15-90 s (from 240 s before the
    first sample), each stirring up 0.3-1 of a cloud that settles over 15-80 s; 0-2 sweeps of the arm wash 30-70 % of
    the deposit off within 1-3 s. As a function of the seconds since the first sample, zero there."""
    grid = np.arange(-240.0, horizon_s + step_s, step_s)
    stir = np.zeros(grid.size)
    for start, length in schedule(rng, (15.0, 90.0), (2.0, 6.0), horizon_s + 240.0):
        stir += rng.uniform(0.3, 1.0) * within(grid + 240.0, [(start, length)])
    cloud = lag_steps(stir, math.exp(-step_s / rng.uniform(15.0, 80.0)))
    deposit = np.cumsum(cloud) * step_s
    washed = deposit.copy()
    for at in rng.uniform(0.0, horizon_s, int(rng.integers(0, 3))):
        washed -= rng.uniform(0.3, 0.7) * float(np.interp(at, grid, deposit)) * ease((grid - at) / rng.uniform(1.0, 3.0))
    first = float(np.interp(0.0, grid, washed))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, washed) - first


def chopper_alias(rng, horizon_s=HORIZON_S, step_s=0.5):
    """A chopper amplifier's ripple aliased by the ADC's clock: a rounded triangle whose period of 60-300 s wanders by
    10-30 % (correlated over 40-150 s) as the two clocks drift. As a function of the seconds since the first sample,
    zero there."""
    grid = np.arange(0.0, horizon_s + step_s, step_s)
    rate = (1.0 + rng.uniform(0.1, 0.3) * ou_path(rng, grid.size, math.exp(-step_s / rng.uniform(40.0, 150.0))) / 2.5
            ) / rng.uniform(60.0, 300.0)
    wave = rounded_triangle(2.0 * math.pi * np.cumsum(rate) * step_s + rng.uniform(0.0, 2.0 * math.pi))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, wave) - wave[0]


# ----------------------------------------------------------------------------- resonance

class SofteningStrut(GridMode):
    """A holder's mode at ``f0_hz`` (unit gain, damping ratio ``zeta``) on a strut preloaded near buckling: its spring
    force w^2 z_s tanh(z / z_s), z_s ``reach`` times the largest relative motion a linear mode gives the record.
    Semi-implicit Euler on a uniform grid of ``fs`` Hz, from rest."""

    fs = 3000.0

    def __init__(self, f0_hz, zeta, reach):
        self.w, self.zeta, self.reach = 2.0 * math.pi * f0_hz, zeta, reach

    def on_grid(self, t, tu, xu, h):
        zs = self.reach * linear_reach(xu, self.w, self.zeta, self.fs)
        w2, c = self.w * self.w, 2.0 * self.zeta * self.w
        y = v = 0.0
        out = np.empty(tu.size)
        for i, xi in enumerate(xu.tolist()):
            v += (-w2 * zs * math.tanh((y - xi) / zs) - c * v) * h
            y += v * h
            out[i] = y
        return out


class ButylPadMode(GridMode):
    """A holder's mode at ``f0_hz`` (unit gain) damped by a butyl pad: the damping ratio ``zeta`` exp(-``loss_c`` dT)
    (at most 0.3) and the stiffness exp(-``stiff_c`` dT), dT the pad's temperature's departure (lag ``lag_s``).
    Semi-implicit Euler on a uniform grid of ``fs`` Hz, from rest."""

    fs = 3000.0

    def __init__(self, f0_hz, zeta, loss_c, stiff_c, lag_s):
        self.w, self.zeta, self.loss, self.stiff, self.lag = 2.0 * math.pi * f0_hz, zeta, loss_c, stiff_c, lag_s
        self.pad = None

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        self.pad = (t, np.clip(follow(t, temp_of(aux, t.size), self.lag) - T_REF_C, -15.0, 15.0))
        return super().forward(t_s, x, aux, state)

    def on_grid(self, t, tu, xu, h):
        d = np.interp(tu, *self.pad)
        w = self.w * np.exp(-0.5 * self.stiff * d)
        c = 2.0 * np.minimum(self.zeta * np.exp(-self.loss * d), 0.3) * w
        y = v = 0.0
        out = np.empty(tu.size)
        for i, (xi, wi, ci) in enumerate(zip(xu.tolist(), (w * w).tolist(), c.tolist())):
            v += (wi * (xi - y) - ci * v) * h
            y += v * h
            out[i] = y
        return out


# ----------------------------------------------------------------------------- friction

def running_in(f, band_n, fresh, slip_n):
    """The force passed by a fresh shaft seal: a Coulomb band ``band_n`` (1 + (``fresh`` - 1) exp(-s / ``slip_n``)), s
    the slip so far (the passed force's travel). Started at ``f[0]``."""
    out, p, worn = np.empty_like(f), float(f[0]), 0.0
    for i, fi in enumerate(f.tolist()):
        b = band_n * (1.0 + (fresh - 1.0) * math.exp(-worn / slip_n))
        q = max(fi - b, min(fi + b, p))
        worn += abs(q - p)
        p = q
        out[i] = p
    return out


class ShrinkingBushing(SimOnly):
    """The force passed by a bushing whose housing shrinks onto the sleeve below ``close_c``: a Coulomb band ``band_n``
    (``floor`` + (1 - ``floor``) the interference's softplus over ``knee_c`` relative to the reference's), at most three
    times ``band_n``, on the bushing's temperature (lag ``lag_s``). Started at the first force."""

    def __init__(self, band_n, floor, close_c, knee_c, lag_s):
        self.band, self.floor, self.close, self.knee, self.lag = band_n, floor, close_c, knee_c, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag)
        share = softplus(self.close - body, self.knee) / float(softplus(self.close - T_REF_C, self.knee))
        band = self.band * np.clip(self.floor + (1.0 - self.floor) * share, 0.0, 3.0)
        return band_play(np.asarray(x, dtype=float), band, band)


# ----------------------------------------------------------------------------- thermo-rheological

def soft_core(c):
    """The core made soft enough for its clock to show: its Kelvin spring at most 18 N/V (the retardation time kept)
    and its flow's viscosity within 6e3-3.5e4 N s/V."""
    k2 = min(c.k2_n_per_v, 18.0)
    return Burgers(c.k1_n_per_v, k2, float(np.clip(c.eta1_n_s_per_v, 6e3, 3.5e4)), c.eta2_n_s_per_v * k2 / c.k2_n_per_v)


class BasslerClock(SimOnly):
    """A core whose clock follows Bassler's law, ln tau = (T_B / T)^2, T_B for ``b_per_c`` per degC at the reference;
    on the core's temperature (lag ``lag_s``), held within e^+-6."""

    def __init__(self, c, b_per_c, lag_s):
        self.c, self.lag = c, lag_s
        self.ref = T_REF_C + 273.15
        self.tb2 = b_per_c * self.ref ** 3 / 2.0

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag) + 273.15
        log_rate = self.tb2 * (1.0 / self.ref ** 2 - 1.0 / body ** 2)
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(log_rate, -6.0, 6.0)))


class MacedoLitovitzClock(SimOnly):
    """A core whose clock follows the hybrid law of Macedo and Litovitz, ln tau = E / T + B / (T - ``t0_k``), ``share``
    of ``b_per_c`` per degC at the reference from the activation; on the core's temperature (lag ``lag_s``), held
    within e^+-6."""

    def __init__(self, c, b_per_c, share, t0_k, lag_s):
        self.c, self.t0, self.lag = c, t0_k, lag_s
        ref = T_REF_C + 273.15
        self.e = share * b_per_c * ref ** 2
        self.b = (1.0 - share) * b_per_c * (ref - t0_k) ** 2
        self.ref_log = self.e / ref + self.b / (ref - t0_k)

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = np.maximum(follow(t, temp_of(aux, t.size), self.lag) + 273.15, self.t0 + 20.0)
        log_rate = self.ref_log - (self.e / body + self.b / (body - self.t0))
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(log_rate, -6.0, 6.0)))


# ----------------------------------------------------------------------------- outside the catalogue

class GridFatigue(SimOnly):
    """A foil gauge's grid fatiguing: the span falls by ``loss`` times Miner's sum of the reading's half-cycles (their
    ranges, counted once the reading has turned back by ``gate_v``, over its largest magnitude, to the power
    ``exponent``) relative to the sum over the whole record."""

    def __init__(self, loss, exponent, gate_v):
        self.loss, self.exponent, self.gate = loss, exponent, gate_v

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        grid, xg = coarse(t, x, 0.02)
        scale = max(float(np.max(np.abs(xg))), 1e-9)
        damage, total = np.empty(grid.size), 0.0
        last = ext = float(xg[0])
        rising = None
        for i, xi in enumerate(xg.tolist()):
            if rising is None:
                if abs(xi - last) > self.gate:
                    rising, ext = xi > last, xi
            elif (xi - ext) * (1.0 if rising else -1.0) > 0.0:
                ext = xi
            elif abs(ext - xi) > self.gate:
                total += (abs(ext - last) / scale) ** self.exponent
                last, ext, rising = ext, xi, not rising
            damage[i] = total
        if total <= 0.0:
            return x
        return x * (1.0 - self.loss * np.interp(t, grid, damage) / total)


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([5.2e4, 4.2e3]))))  # V / (N s)
        if shape == "hydrolysing_core":
            rule = hydrolysing_leak(phi * rng.uniform(0.8, 1.4), rng.uniform(1.6, 4.0), DURATION_S)
        else:
            bubbles = int(rng.integers(6, 15))
            rule = jamin_leak(phi * rng.uniform(2.0, 4.0), bubbles, rng.uniform(1.0, 3.0) / bubbles,
                              phi * rng.uniform(10.0, 40.0))
        return Parts("zener", LeakingCore.of(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        comp = float(np.interp(m, [0, 1], [0.032, 0.22])) / g0  # of the instantaneous response, V / N
        if shape == "rouse_network":
            a = (comp, rng.uniform(6.0, 80.0), int(rng.integers(12, 25)))
            p.extra.append(lambda t, f, T, a=a: rouse_creep(t, f, *a))
            return p
        a = (comp, rng.uniform(0.6, 8.0), rng.uniform(0.15, 0.6))
        p.extra.append(lambda t, f, T, a=a: cavitating_kelvin(t, f, *a))
        return p
    if effect == "hysteresis":
        width = float(np.interp(m, [0, 1], [0.016, 0.07]))
        if shape == "overload_stop":
            knee, mu = rng.uniform(0.12, 0.35) * top, rng.uniform(0.3, 0.6)
            p.after.append(OverloadStop(knee, mu, width * top / (2.0 * mu * (0.7 * top - knee))))
            return p
        p.after.append(PoleStripHead(0.5 * width * top, rng.uniform(0.05, 0.14) * top, rng.uniform(0.15, 0.45),
                                     rng.uniform(0.0, math.pi)))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.011, 0.1]))))
        if shape == "silicone_oil_seal":
            share = rng.uniform(0.75, 0.95)
            p.after.append(SiliconeOilSeal(share * delay, (1.0 - share) * delay, rng.uniform(0.02, 0.045),
                                           rng.uniform(10.0, 40.0)))
            return p
        p.after.append(HuntingSync(delay, rng.uniform(0.15, 0.35), rng.uniform(30.0, 150.0), rng.uniform(0.0, 2.0 * math.pi)))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.055, 0.19]))
        if shape == "hinged_electrode":
            p.after.append(StaticMap(tilted_plate(rel, top, bool(rng.random() < 0.5))))
            return p
        p.after.append(StaticMap(evanescent_coupler(rel, top, rng.uniform(0.25, 1.2))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.0078, 0.032]) * rng.choice([-1, 1]))
        if shape == "compensator_end_stops":
            a = (k, rng.uniform(0.15, 0.35), rng.uniform(-0.8, 0.8), rng.uniform(0.4, 1.3), rng.uniform(0.2, 0.5),
                 rng.uniform(8.0, 35.0))
            p.extra.append(lambda t, f, T, a=a: compensator_zero(t, T, *a))
            return p
        a = (k, rng.uniform(0.35, 0.75), rng.uniform(2.0, 8.0), rng.uniform(40.0, 120.0))
        p.extra.append(lambda t, f, T, a=a: lead_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        tc = float(np.interp(m, [0, 1], [0.014, 0.036]))
        if shape == "battery_excitation":
            p.after.append(BatteryExcitation(tc, rng.uniform(0.045, 0.09), rng.uniform(12.0, 45.0)))
            return p
        p.after.append(HoppingGauge(tc, rng.uniform(0.25, 0.5), rng.uniform(5.0, 30.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.016, 0.094]) * rng.choice([-1, 1]))
        zero = sized(silt_deposit(rng) if shape == "silt_deposit" else chopper_alias(rng), size, HORIZON_S)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.032, 0.0045])) * rng.uniform(0.8, 1.2)
        if shape == "softening_strut":
            p.after.append(SofteningStrut(rng.uniform(12.0, 50.0), zeta, rng.uniform(0.5, 1.5)))
            return p
        p.after.append(ButylPadMode(rng.uniform(12.0, 50.0), zeta, rng.uniform(0.08, 0.2), rng.uniform(0.01, 0.03),
                                    rng.uniform(15.0, 60.0)))
        return p
    if effect == "friction":
        band = float(np.interp(m, [0, 1], [0.0028, 0.046]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "running_in_seal":
            a = (band, rng.uniform(1.6, 2.4), rng.uniform(5.0, 30.0))
            p.before.append(ForcePath(lambda t, x, a=a: running_in(x, *a)))
            return p
        p.before.append(ShrinkingBushing(band, rng.uniform(0.25, 0.5), T_REF_C + rng.uniform(-0.5, 2.0),
                                         rng.uniform(0.4, 1.2), rng.uniform(20.0, 80.0)))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.18, 0.5])) * rng.uniform(1.2, 1.5)
        c = soft_core(c)
        if shape == "bassler_clock":
            return Parts("burgers", BasslerClock(c, b, rng.uniform(4.0, 28.0)), core_changed=True)
        return Parts("burgers", MacedoLitovitzClock(c, b, rng.uniform(0.3, 0.7), T_REF_C + 273.15 - rng.uniform(45.0, 110.0),
                                                    rng.uniform(4.0, 28.0)), core_changed=True)
    if effect == "grid_fatigue":
        loss = float(np.interp(m, [0, 1], [0.02, 0.12]))
        p.after.append(GridFatigue(loss, rng.uniform(3.0, 5.0), 0.02 * top))
        return p
    if effect == "late_reference":
        lead = float(np.interp(m, [0, 1], [0.006, 0.14])) * rng.uniform(0.85, 1.15)
        p.before.append(ForcePath(lambda t, x, d=lead: np.interp(t + d, t, x, right=x[-1])))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["hydrolysing_core", "jamin_chain"],
    "delayed_elasticity": ["rouse_network", "cavitating_dashpot"],
    "hysteresis": ["overload_stop", "pole_strip_head"],
    "sensor_lag": ["silicone_oil_seal", "hunting_clock_sync"],
    "nonlinear_gain": ["hinged_electrode", "evanescent_coupler"],
    "thermal_drift": ["compensator_end_stops", "two_wire_leads"],
    "thermal_sensitivity": ["battery_excitation", "hopping_gauge"],
    "offset_drift": ["silt_deposit", "chopper_alias"],
    "resonance": ["softening_strut", "butyl_pad"],
    "friction": ["running_in_seal", "shrinking_bushing"],
    "thermo_rheological": ["bassler_clock", "macedo_litovitz_clock"],
}
PAIRS = (("viscous_flow", "thermal_drift"), ("delayed_elasticity", "nonlinear_gain"), ("hysteresis", "offset_drift"),
         ("sensor_lag", "resonance"), ("thermal_sensitivity", "friction"), ("thermo_rheological", "hysteresis"))
OUTSIDE = ("grid_fatigue", "late_reference")
RATES = (145.0, 395.0, 1110.0, 1390.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split AF", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.29, 0.83),
                   pair_shapes=(-1, 0), rates=RATES, profiles=PROFILES, temperature=fjord_dive,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(0.58e-3, 2.42e-3), jitter=0.36,
                   gap_s=(0.18, 2.45))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
