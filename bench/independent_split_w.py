"""Independent split W for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split W is an untouched held-out set: written before the engine it measures and blind to it (to how it detects and
fits anything), run once at its end, never used to choose anything. Every name of the catalogue is hidden in two
shapes that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A to V use:

* a fluid-filled core leaking through a fatigue crack in its printed shell (each completed half cycle of the force
  extends the crack by its range to the power 2-4, Paris; the leak as the cube of the crack's opening, from 0.4-0.8 to
  2.5-5 times the plain fluidity of 1/60000-1/8000 V/(N s) by the end of the record; it never recovers), or one
  leaking through a filter that the fines it carries clog (1.5-3 times the plain fluidity clean; the cake grows with
  the volume passed, so that a steady 3 N cuts the leak to 30-59 %, and falls away at rest over 30-150 s: a long
  press slows it, a rest restores it, it never recovers);
* the core resting on a hydrostatic oil pad fed through a capillary restrictor (the pocket at 20-40 % of the supply
  pressure unloaded, 80-90 % under 9 N; the film thins as C h' = (1 - P) / R - P h^3, 1-15 s at rest, less per newton
  and more slowly under heavy loads, and comes back at rest), or a Kelvin unit whose spring is a pre-curved diaphragm
  pressed toward flat (the Almen-Laszlo curve of a disc spring 1.0-1.35 thicknesses high, flat at 2.5-6 N, 4-32 times
  softer there than at rest; 1-10 s at rest: the creep largest and slowest about the flattening force); both settle
  at up to 3-20 % of the instantaneous response;
* gauges on a work-hardened beryllium-copper flexure that yields micro-plastically (Ramberg-Osgood's backbone with an
  exponent of 3-4 under Masing's rules and return-point memory, as 48 plays on the bridge voltage; cycled over the
  full range before use and calibrated along the middle of that loop: a loop of 1.5-9 % of the range over the full
  range, 0.45-0.65 of that share for a cycle to 6 N, scarcely any for small cycles), or a magnetoelastic (Villari)
  read-out whose domain walls lag each reversal (a state approaching the sense of travel over 2-8 % of the range)
  with an effect that changes sign at the Villari reversal, 35-75 % of the range up: a butterfly whose lobes reach
  1-6 % of the range;
* the firmware's Savitzky-Golay smoother (order 2 or 4, read at the middle of its window, run at 1 kHz behind an RC
  of 1-3 ms), or a wireless node sampling every 2-54 ms whose host rebuilds the stream by a Catmull-Rom spline, two
  samples late (its kernel dips below zero beside each step); 4-108 ms of delay;
* a differential capacitive read-out whose stray capacitance (0.3-3 times the plates') turns the ratio into
  u / (1 + p (1 - u^2)) (the plate at rest 0.3 gaps to one side to 0.4 to the other: expansive, or S-shaped when the
  load carries it across the centre), or a rotary encoder turned by the core's plunger through a slider-crank (rod
  ratio 0.2-0.5, the crank starting 20-55 degrees past the top dead centre: compressive, or 115-150 degrees:
  expansive); 5-16 % at the top of the range;
* the zero of a sealed-reference read-out whose cavity (lag 5-15 s) holds a zeolite getter (30-60 % of the slope at
  once by the gas law, the rest as the getter gives off or takes back gas over 60-300 s toward exp(a dT) - 1, a
  0.1-0.3 per degC), or of a Hall read-out whose bias magnet is partly shunted by a thermomagnetic Ni-Fe strip (lag
  10-40 s) whose permeability falls as (T_c - T)^0.3-0.5 toward its Curie point 3-10 degC above the reference;
  0.008-0.03 V/degC;
* a Hall read-out whose span is the dipole's field gradient, as the gap to the power -4, the polymer carrier (lag
  20-60 s) moving the magnet away or closer as it warms, the NdFeB magnet (lag 5-15 s) losing 0.12 %/degC, or a read-out
  membrane stretched like a drum over a frame (its pretension 50-90 % of its stiffness; lag 10-40 s) that expands more
  or less than it (the span 1 / (1 - a dT)); 0.8-2 %/degC either way at the reference;
* the zero of a sealed-gauge read-out as the ambulance drives (12 Pa per metre of altitude, 8-25 m up or down over
  each stretch of 20-90 s; the cabin 10-40 Pa above the outside while the doors are shut, lost at each of 1-3
  openings of 5-30 s and rebuilt with 5-20 s), or of a bridge one of whose arms passes a tin-plated connector pin that
  the vehicle's vibration frets (its contact resistance as the power 1.5-3 of the vibration taken since it set off,
  the vibration on while it drives: 20-120 s bouts, 10-60 s stops, roads 0.5-1.5 times as rough); 12-80 mV at most;
* a holder's mode (15-45 Hz) damped by an oil damper with a blow-off valve (cracking at 10-40 % of the largest relative
  speed the record gives it: damping ratio 2.5-4 times higher below that than above: large knocks ring long, small
  ones die fast), or a mode (15-45 Hz) that radiates 50-80 % of its damping into a taut instrument cable whose far end,
  17-150 ms there and back, returns it with a reflection of 30-70 % of either sign (the ringing revives); the
  frequency fixed, damping ratio 0.0064-0.036 (the open valve's);
* a Coulomb band of 0.4-3.6 % of the range in a needle guide that the ambulance's braking (0.2-0.5 g for 2-6 s) and
  bends (0.1-0.4 g for 3-10 s), 8-40 s apart, press the tool into (the band 1.6-2.5 times wider at 0.5 g), or in a
  guide with a hydrophilic coating that a saline flush every 20-90 s wets (the band down to 30-50 % within 0.5-1.5 s,
  back as it dries over 20-90 s); the same at every load;
* a core whose dashpots hold a heavy polybutene (1e5-1e7 cSt) following Walther's relation, log log (nu + 0.7) = A -
  B log T, on its own temperature (lag 5-20 s; 0.15-0.45 per degC at the reference), or an Arrhenius clock (0.18-0.72
  per degC) on a core bolted to the robot's aluminium wrist, its temperature 40-70 % the cabin air's (lag 5-20 s) and
  the rest the wrist's (lag 90-300 s).

It also holds six pairs, two effects outside the catalogue (the ambulance's siren amplifier picked up by the bridge's
leads and sampled without an anti-alias filter, 2-5 runs of 10-60 s of a wail sweeping 600-1400 Hz every 2-6 s,
10-60 mV, aliased into the record; a second sensor, a gripper's, on the same I2C bus answering to the bridge's address
while its controller polls it, 5-20 s every 10-40 s, so that 0.2-1 % of the readings are its zero and grip instead)
and four clean records. Profiles: fiducial markers placed by an impact (tap) needle driver through the measured
force-depth curve (``../shared/data``, ``depth_force.csv``, its first insertion stretched over 30-70 mm: taps of 0.4-1.5
mm every 0.25-1 s cutting at 1.3-2.2 times the static resistance and relaxing between, a stylet's push, withdrawal;
synthetic layers when the data are absent); a robot holding a transcranial magnetic stimulation coil on a scalp under
force control (breathing, the head wandering and shifting, pulse trains); and a mechanical chest-compression device on a
manikin (100-120 a minute, 30:2 or continuous with ventilations, rhythm checks). Rates 110, 360, 560 and 820 Hz (a mode
at 1000 Hz with knocks that excite it), 1.0-2.4 mV noise, stamp jitter, gaps, and a sensor on a robot in a mobile
stroke unit on a cold day: the cabin's heater on a thermostat, the rear door opened now and then, the sun through a
window as the vehicle turns.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size against its
noise without diagnosing (for a leak on a Zener base, against that base without it).

    .venv/bin/python bench/independent_split_w.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, optimize, signal

from polyforce_ros.physics.chain import play_operator
from polyforce_ros.physics.viscoelastic import Zener, simulate_deformation
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import ForcePath, LinearFilter, Parts, ShapeSplit, SimOnly, band_play, coarse, core, uniform_grid

SEED0 = 1_590_000  # never a seed of the registry's splits nor of splits A (90000..) to V (1520000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 450.0
HORIZON_S = DURATION_S + 60.0  # what a schedule drawn before the record covers (the record plus its gaps' slack)


# ----------------------------------------------------------------------------- small tools

def smooth_step(u):
    """0 below 0, 1 above 1, the minimum-jerk polynomial between."""
    u = np.clip(u, 0.0, 1.0)
    return u * u * u * (10.0 + u * (6.0 * u - 15.0))


def spans(t):
    """``take(start, length)``: the index slice of ``t`` within [start, start + length) and the seconds since start."""
    def take(start, length):
        lo, hi = np.searchsorted(t, (start, start + max(length, 0.0)))
        return slice(int(lo), int(hi)), t[lo:hi] - start
    return take


def last_value(values, fallback):
    return float(values[-1]) if np.size(values) else float(fallback)


def temp_at(aux, n):
    """The chain's temperature, one value per sample."""
    return np.broadcast_to(np.asarray(aux["temperature_c"], dtype=float), (n,))


def lagged(t, temp, tau_s, step_s=0.5):
    """``temp`` as a body that follows it with the time constant ``tau_s`` sees it (exact for each coarse step of
    ``step_s``), at rest with it before the record."""
    grid, tg = coarse(t, temp, step_s)
    keep, body = math.exp(-step_s / tau_s), float(tg[0])
    out = np.empty(grid.size)
    for i, goal in enumerate(tg.tolist()):
        body = goal + (body - goal) * keep
        out[i] = body
    return np.interp(t, grid, out)


def bouts(rng, gap_s, length_s, horizon_s=HORIZON_S, first_s=None):
    """Bouts (start, length) in seconds since the first sample, ``length_s`` long and ``gap_s`` apart (ranges), the
    first starting within ``first_s`` (by default up to one gap before the record)."""
    out = []
    now = rng.uniform(*(first_s if first_s else (-gap_s[1], gap_s[0])))
    while now < horizon_s:
        length = rng.uniform(*length_s)
        out.append((now, length))
        now += length + rng.uniform(*gap_s)
    return out


def in_bouts(s, listed):
    """Whether each of ``s`` lies in one of the bouts ``listed`` (start, length)."""
    hit = np.zeros(np.shape(s), dtype=bool)
    for start, length in listed:
        hit |= (s >= start) & (s < start + length)
    return hit


def peak_scaled(fn, size, horizon_s=HORIZON_S):
    """``fn(s)`` scaled so that its largest magnitude over ``horizon_s`` (0.1 s apart) is ``|size|``, sign of
    ``size``."""
    peak = float(np.max(np.abs(fn(np.arange(0.0, horizon_s, 0.1)))))
    gain = size / max(peak, 1e-12)
    return lambda s: gain * fn(s)


def fit_reach(read, rel, reach, k_top):
    """``read(x, k)`` with the k in (0, ``k_top``] that makes its largest departure from x over [0, ``reach``] ``rel``
    of ``reach`` (``k_top`` when even that departs less)."""
    xs = np.linspace(0.0, reach, 241)

    def excess(k):
        return float(np.max(np.abs(read(xs, k) - xs))) / reach - rel
    if excess(k_top) <= 0.0:
        return lambda x: read(x, k_top)
    ks = np.geomspace(k_top * 1e-4, k_top, 90)
    above = [excess(k) > 0.0 for k in ks]
    j = above.index(True)
    k = ks[0] if j == 0 else optimize.brentq(excess, ks[j - 1], ks[j])
    return lambda x: read(x, k)


def clocked(c, t, f, rate):
    """The core's deformation when its clock runs at ``rate`` (reduced time from t[0])."""
    return simulate_deformation(c, t[0] + integrate.cumulative_trapezoid(rate, t, initial=0.0), f)


# ----------------------------------------------------------------------------- profiles and temperature

@functools.lru_cache(maxsize=1)
def okamura_depth_force(bin_mm=0.25):
    """The first insertion of the measured force-depth curve (``../shared/data/needle_insertion_okamura/
    depth_force.csv``, up to where the depth first falls 5 mm below its running maximum), as (depth in mm, force in N)
    on a grid of ``bin_mm``: the median of the digitised points in each bin, gaps filled linearly, negative force
    set to zero; None without the file."""
    csv = profiles.okamura_csv_path()
    path = None if csv is None else csv.parent / "depth_force.csv"
    if path is None or not path.is_file():
        return None
    data = np.loadtxt(path, delimiter=",", ndmin=2)
    depth, force = 1e3 * data[:, 0], data[:, 1]
    fallen = np.flatnonzero(np.maximum.accumulate(depth) - depth > 5.0)
    stop = int(fallen[0]) if fallen.size else depth.size
    depth, force = depth[:stop], force[:stop]
    grid = np.arange(0.0, float(depth.max()) + bin_mm, bin_mm)
    slot = np.clip(np.floor(depth / bin_mm + 0.5).astype(int), 0, grid.size - 1)
    med = np.full(grid.size, np.nan)
    for k in np.unique(slot):
        med[k] = np.median(force[slot == k])
    known = np.isfinite(med)
    return grid, np.maximum(np.interp(grid, grid[known], med[known]), 0.0)


def made_up_layers(rng):
    """A stand-in for :func:`okamura_depth_force`: 45 mm of shaft friction growing as the depth to the power 1.2
    (0.005-0.015 N at 1 mm) and 2-4 membranes that stiffen exponentially over the last 1-3 mm before they tear by
    0.3-1.2 N, keeping 20-40 % of it, which fades over the next 1.5 mm."""
    grid = np.arange(0.0, 45.0, 0.25)
    force = rng.uniform(0.005, 0.015) * grid ** 1.2
    for where in np.sort(rng.uniform(4.0, 42.0, int(rng.integers(2, 5)))):
        build, height, kept = rng.uniform(1.0, 3.0), rng.uniform(0.3, 1.2), rng.uniform(0.2, 0.4)
        force += np.where(grid <= where, height * np.exp((grid - where) / build),
                          kept * height * np.exp(-(grid - where) / 1.5))
    return grid, force


def tap_insertion(duration_s, rate_hz, rng):
    """A robot placing fiducial markers with an impact (tap) needle driver, behind which the sensor sits. Each
    placement drives the needle through the measured force-depth curve (``okamura_depth_force``), stretched over
    30-70 mm and scaled to a static resistance of 2-5 N at its peak, in taps: every 0.25-1 s the driver advances it by
    0.4-1.5 mm within 15-40 ms, the force rising to 1.3-2.2 times the static resistance there (the liver cut at speed)
    and relaxing with 80-400 ms toward 55-85 % of it until the next tap. At the target the marker is pushed out of the
    cannula by its stylet (a push of 0.5-1.5 N for 0.3-0.8 s within a 2-6 s hold that relaxes further), the needle is
    withdrawn in 1-3 s, and 8-25 s pass before the next placement. Made-up layers (``made_up_layers``) when
    ``../shared/data`` is absent."""
    depth_mm, force_n = okamura_depth_force() or made_up_layers(rng)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    take = spans(t)
    now = rng.uniform(2.0, 8.0)
    while now < duration_s - 45.0:
        goal = rng.uniform(30.0, 70.0)
        stretch = goal / float(depth_mm[-1])
        scale = rng.uniform(2.0, 5.0) / max(float(force_n.max()), 1e-3)
        boost, keep, relax = rng.uniform(1.3, 2.2), rng.uniform(0.55, 0.85), rng.uniform(0.08, 0.4)
        advance, period, tap = rng.uniform(0.4, 1.5), rng.uniform(0.25, 1.0), rng.uniform(0.015, 0.04)
        depth, level, static = 0.0, 0.0, 0.0
        while depth < goal and now < duration_s - 20.0:
            depth = min(depth + advance * rng.uniform(0.8, 1.2), goal)
            static = scale * float(np.interp(depth / stretch, depth_mm, force_n))
            top = max(boost * static, level)
            seg, s = take(now, tap)
            f[seg] = level + (top - level) * smooth_step(s / tap)
            now += tap
            rest = period * rng.uniform(0.85, 1.15) - tap
            floor = keep * static
            seg, s = take(now, rest)
            f[seg] = floor + (top - floor) * np.exp(-s / relax)
            now += rest
            level = floor + (top - floor) * math.exp(-rest / relax)
        hold, push, push_s = rng.uniform(2.0, 6.0), rng.uniform(0.5, 1.5), rng.uniform(0.3, 0.8)
        push_at = rng.uniform(0.3, 0.6) * hold
        floor = keep * keep * static
        seg, s = take(now, hold)
        bump = np.where((s >= push_at) & (s < push_at + push_s), np.sin(np.pi * (s - push_at) / push_s) ** 2, 0.0)
        f[seg] = floor + (level - floor) * np.exp(-s / (4.0 * relax)) + push * bump
        now += hold
        last = last_value(f[seg], level)
        out = rng.uniform(1.0, 3.0)
        seg, s = take(now, out)
        f[seg] = last * (1.0 - smooth_step(s / out))
        now += out + rng.uniform(8.0, 25.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def tms_coil(duration_s, rate_hz, rng):
    """A robot holding a transcranial magnetic stimulation coil against a patient's scalp (the sensor behind the
    coil). Each sitting: the coil is brought on under force control to a set point of 1.5-4 N (a rise of 1-3 s and a
    settling swing of 5-20 % with a 0.8-1.6 s period), held for 60-150 s while the patient breathes (0.03-0.1 N at
    0.2-0.33 Hz), the head wanders (three slow sines of 0.05-0.2 N in all) and shifts now and then (every 15-50 s a
    step of 0.5-2 N either way within 0.1-0.4 s, which the controller takes back with 0.5-2 s), and trains of pulses
    are fired (every 10-30 s, 2-5 s at 5-20 Hz, each pulse a click of 0.05-0.3 N for 8-20 ms); the coil lifts off
    within 0.5-1.5 s and 5-15 s pass while the robot moves to the next target."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    take = spans(t)
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 25.0:
        point, rise, swing, swing_s = rng.uniform(1.5, 4.0), rng.uniform(1.0, 3.0), rng.uniform(0.05, 0.2), \
            rng.uniform(0.8, 1.6)
        length = min(rng.uniform(60.0, 150.0), duration_s - now - 3.0)
        seg, s = take(now, length)
        after = np.maximum(s - rise, 0.0)
        level = point * (smooth_step(s / rise) + swing * np.exp(-after / swing_s) * np.sin(2.0 * np.pi * after / swing_s))
        on = smooth_step(s / rise)
        level += on * rng.uniform(0.03, 0.1) * np.sin(2.0 * np.pi * rng.uniform(0.2, 0.33) * s + rng.uniform(0, 6.3))
        wander = rng.uniform(0.05, 0.2)
        for share in rng.dirichlet(np.ones(3)):
            level += on * wander * share * np.sin(2.0 * np.pi * s / rng.uniform(8.0, 60.0) + rng.uniform(0, 6.3))
        at = rise + rng.uniform(5.0, 20.0)
        while at < length - 2.0:
            jump, quick, back = rng.choice([-1.0, 1.0]) * rng.uniform(0.5, 2.0), rng.uniform(0.1, 0.4), \
                rng.uniform(0.5, 2.0)
            level += jump * smooth_step((s - at) / quick) * np.exp(-np.maximum(s - at - quick, 0.0) / back)
            at += rng.uniform(15.0, 50.0)
        at = rise + rng.uniform(5.0, 15.0)
        while at < length - 6.0:
            burst, hz, click, wide = rng.uniform(2.0, 5.0), rng.uniform(5.0, 20.0), rng.uniform(0.05, 0.3), \
                rng.uniform(0.008, 0.02)
            for k in range(int(burst * hz)):
                u = (s - at - k / hz) / wide
                level += np.where((u >= 0.0) & (u < 1.0), click * np.sin(np.pi * u) ** 2, 0.0)
            at += burst + rng.uniform(10.0, 30.0)
        f[seg] = level
        now += length
        last = last_value(level, point)
        off = rng.uniform(0.5, 1.5)
        seg, s = take(now, off)
        f[seg] = last * (1.0 - smooth_step(s / off))
        now += off + rng.uniform(5.0, 15.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def cpr_compressions(duration_s, rate_hz, rng):
    """A mechanical chest-compression device on a resuscitation manikin (the sensor in its piston): 100-120
    compressions a minute, each pressing for 40-50 % of its cycle (a flattened half-sine to a peak of 5.5-8.5 N, the
    manikin's chest softening it by 8-20 % with 60-180 s, 1-3 adjustments of the depth by 10-20 % either way), the
    piston leaning on the chest with 0-0.4 N in between. One record in two pauses for two ventilations (3-5 s, the
    lean halved) after every 30 compressions; the other compresses continuously while the ventilator inflates the
    chest every 5-7 s (the lean rising by 0.2-0.6 N for about a second). Every 90-150 s the device stops for a rhythm
    check (5-10 s, the piston lifted off)."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    take = spans(t)
    start = now = rng.uniform(2.0, 6.0)
    cycle, duty = 60.0 / rng.uniform(100.0, 120.0), rng.uniform(0.4, 0.5)
    peak, lean = rng.uniform(5.5, 8.5), rng.uniform(0.0, 0.4)
    soften, soften_s = rng.uniform(0.08, 0.2), rng.uniform(60.0, 180.0)
    changes = sorted(rng.uniform(start, duration_s, int(rng.integers(1, 4))).tolist())
    factors = np.cumprod(1.0 + rng.choice([-1.0, 1.0], len(changes)) * rng.uniform(0.1, 0.2, len(changes)))
    continuous = rng.random() < 0.5
    breath_every, breath_lift = rng.uniform(5.0, 7.0), rng.uniform(0.2, 0.6)
    check = now + rng.uniform(90.0, 150.0)
    count = 0
    while now < duration_s - cycle:
        if now >= check:
            pause = rng.uniform(5.0, 10.0)
            now += pause
            check = now + rng.uniform(90.0, 150.0)
            continue
        depth = np.prod(factors[[c <= now for c in changes]]) if changes else 1.0
        top = peak * depth * (1.0 - soften * (1.0 - math.exp(-(now - start) / soften_s))) * rng.uniform(0.96, 1.04)
        seg, s = take(now, cycle)
        u = s / cycle
        press = np.where(u < duty, np.sin(np.pi * np.clip(u / duty, 0.0, 1.0)) ** 0.7, 0.0)
        rest = lean
        if continuous:
            phase = np.mod(now + s - start, breath_every)
            rest = lean + breath_lift * np.where(phase < 1.0, np.sin(np.pi * phase) ** 2, 0.0)
        f[seg] = rest + (top - rest) * press
        now += cycle
        count += 1
        if not continuous and count % 30 == 0:
            pause = rng.uniform(3.0, 5.0)
            seg, s = take(now, pause)
            f[seg] = 0.5 * lean
            now += pause
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (tap_insertion, tms_coil, cpr_compressions)


def temperature(t, rng, step_s=0.5):
    """A sensor on a robot in a mobile stroke unit (an ambulance) on a cold day, 8-16 degC outside. The cabin's heater
    runs under a thermostat (set 0.5 degC below to 1.5 degC above the reference, switching band 0.8-2 degC, heating
    at 0.025-0.05 degC/s against a loss to the outside with 500-1200 s); the rear door is opened 1-3 times (15-50 s, the
    cabin losing heat to the outside with 60-150 s meanwhile); the sun reaches the sensor through a window by 0-2.5 degC,
    changed as the vehicle turns every 20-90 s (with 3-8 s). The sensor follows with 10-30 s; all of it runs from 600 s
    before the record (exact per step of ``step_s``)."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-600.0, d + 2.0 * step_s, step_s)
    outside = T_REF_C - rng.uniform(8.0, 16.0)
    set_c, band = T_REF_C + rng.uniform(-0.5, 1.5), rng.uniform(0.8, 2.0)
    heat, loss = rng.uniform(0.025, 0.05), math.exp(-step_s / rng.uniform(500.0, 1200.0))
    door_keep = math.exp(-step_s / rng.uniform(60.0, 150.0))
    open_door = np.zeros(grid.size, dtype=bool)
    for _ in range(int(rng.integers(1, 4))):
        at = rng.uniform(-200.0, d)
        open_door |= (grid >= at) & (grid < at + rng.uniform(15.0, 50.0))
    sun_goal, now = np.zeros(grid.size), -600.0
    while now < d + 1.0:
        length = rng.uniform(20.0, 90.0)
        sun_goal[(grid >= now) & (grid < now + length)] = rng.uniform(0.0, 2.5)
        now += length
    sun_keep, sensor_keep = math.exp(-step_s / rng.uniform(3.0, 8.0)), math.exp(-step_s / rng.uniform(10.0, 30.0))
    cabin, heater, sun = set_c, rng.random() < 0.5, float(sun_goal[0])
    sensor = cabin + sun
    out = np.empty(grid.size)
    for i, (door, glare) in enumerate(zip(open_door.tolist(), sun_goal.tolist())):
        out[i] = sensor
        heater = cabin < set_c - 0.5 * band or (heater and cabin < set_c + 0.5 * band)
        cabin = outside + (cabin - outside) * loss + (heat * step_s if heater else 0.0)
        if door:
            cabin = outside + (cabin - outside) * door_keep
        sun = glare + (sun - glare) * sun_keep
        sensor = cabin + sun + (sensor - cabin - sun) * sensor_keep
    return np.interp(s, grid, out)


# ----------------------------------------------------------------------------- viscous flow

class LeakyCore(SimOnly):
    """The Burgers core without its own dashpot (a Zener core) plus a leak ``rule(t, F) -> V`` (none when ``rule``
    is None)."""

    def __init__(self, c, rule):
        self.zener, self.rule = Zener(c.k1_n_per_v, c.k2_n_per_v, c.eta2_n_s_per_v), rule

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        out = simulate_deformation(self.zener, t, f)
        return out if self.rule is None else out + self.rule(t, f)


def fatigue_crack_leak(fluidity, first, last, paris_m, step_s=0.01):
    """x' = A(t) F: a fluid-filled core leaking through a fatigue crack in its printed shell. Each completed half
    cycle of the force (a reversal past 0.05 N) extends the crack by its range to the power ``paris_m`` (Paris); the
    leak goes as the cube of the crack's opening, which grows with its length (the cubic law), so A = ``fluidity``
    ``first`` (1 + g D)^3, D the damage so far over the record's, g set for ``last`` times ``fluidity`` at the end.
    It never recovers."""
    grow = (last / first) ** (1.0 / 3.0) - 1.0

    def rule(t, f):
        grid, fg = coarse(t, np.maximum(f, 0.0), step_s)
        damage, total = np.empty(grid.size), 0.0
        turn = extreme = float(fg[0])
        way = 0
        for i, fi in enumerate(fg.tolist()):
            if way == 0:
                if abs(fi - turn) > 0.05:
                    way, extreme = (1 if fi > turn else -1), fi
            elif way * (fi - extreme) > 0.0:
                extreme = fi
            elif abs(fi - extreme) > 0.05:
                total += abs(extreme - turn) ** paris_m
                turn, extreme, way = extreme, fi, -way
            damage[i] = total
        share = damage / damage[-1] if damage[-1] > 0.0 else np.zeros(grid.size)
        rate = fluidity * first * (1.0 + grow * share) ** 3 * fg
        return np.interp(t, grid, integrate.cumulative_trapezoid(rate, grid, initial=0.0))
    return rule


def clogging_filter(fluidity, clog_at_3n, clear_s, step_s=0.01):
    """x' = A F / (1 + c): a fluid-filled core leaking through a filter that the fines carried by the leak clog, c' =
    beta x' - c / ``clear_s`` (the cake grows with the volume passed and falls away at rest); beta set so that a
    steady 3 N clogs it to c = ``clog_at_3n`` (the leak then 1 / (1 + c) of the clean one, A = ``fluidity``). It slows
    under a long press, runs clean again after a rest and never recovers."""
    beta = clog_at_3n * (1.0 + clog_at_3n) / (clear_s * fluidity * 3.0)
    keep = math.exp(-step_s / clear_s)

    def rule(t, f):
        grid, fg = coarse(t, np.maximum(f, 0.0), step_s)
        x, cake, out = 0.0, 0.0, np.empty(grid.size)
        for i, fi in enumerate(fg.tolist()):
            out[i] = x
            rate = fluidity * fi / (1.0 + cake)
            x += rate * step_s
            cake = cake * keep + beta * rate * step_s
        return np.interp(t, grid, out)
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def hydrostatic_pad(t, f, compliance_v_per_n, ref_n, p_rest, p_top, rest_s, step_s=0.01):
    """The core resting on a hydrostatic (externally pressurised) oil pad fed through a capillary restrictor: the
    pocket pressure P (a share of the supply) is ``p_rest`` at no load and ``p_top`` under 9 N; the film h follows
    C h' = (1 - P) / R - P h^3 (inflow through the restrictor, outflow through the land), R set for h = 1 at rest, C
    for a time constant of ``rest_s`` there. The film thins as the load rises (less per newton, and more slowly, under
    heavy loads) and comes back at rest; the output is the film's loss scaled so that it settles at
    ``compliance_v_per_n`` times ``ref_n`` under ``ref_n``. Explicit per coarse step of ``step_s``, from rest."""
    resist, cap = (1.0 - p_rest) / p_rest, 3.0 * p_rest * rest_s

    def pressure(force):
        return np.minimum(p_rest + (p_top - p_rest) * np.maximum(force, 0.0) / FORCE_MAX_N, 0.97)

    def settled(force):
        p = pressure(force)
        return ((1.0 - p) / (resist * p)) ** (1.0 / 3.0)
    gain = compliance_v_per_n * ref_n / (1.0 - float(settled(ref_n)))
    grid, fg = coarse(t, np.asarray(f, dtype=float), step_s)
    h, out = 1.0, np.empty(grid.size)
    for i, p in enumerate(pressure(fg).tolist()):
        out[i] = h
        h += step_s * ((1.0 - p) / resist - p * h ** 3) / cap
    return gain * (1.0 - np.interp(t, grid, out))


def dome_kelvin(t, f, compliance_v_per_n, flat_n, ratio, rest_s, step_s=0.01):
    """A Kelvin unit whose spring is a pre-curved diaphragm (a disc spring of height ``ratio`` times its thickness,
    1.0-1.35: no snap) that the retarded deformation presses toward flat: its force in thickness units is the
    Almen-Laszlo d ((r - d)(r - d / 2) + 1), reached at the flat point d = r by ``flat_n``; tau u' = F / sigma - P(u)
    with tau set for a retardation of ``rest_s`` at rest. The creep is small and quick at light loads, largest and
    slowest about ``flat_n`` (the diaphragm's stiffness 1 - r^2 / 2 there against 1 + r^2 at rest), smaller again
    above; scaled so that its settled value is at most ``compliance_v_per_n`` times the force. Explicit per coarse
    step of ``step_s``, from rest."""
    sigma, tau = flat_n / ratio, rest_s * (1.0 + ratio * ratio)

    def spring(d):
        return d * ((ratio - d) * (ratio - 0.5 * d) + 1.0)
    dd = np.linspace(0.0, 4.0 * ratio, 4001)
    forces = np.linspace(0.2, FORCE_MAX_N, 200)
    settled = np.interp(forces / sigma, spring(dd), dd)
    gain = compliance_v_per_n / float(np.max(settled / forces))
    grid, fg = coarse(t, np.maximum(np.asarray(f, dtype=float), 0.0) / sigma, step_s)
    u, out = 0.0, np.empty(grid.size)
    for i, goal in enumerate(fg.tolist()):
        out[i] = u
        u += step_s * (goal - u * ((ratio - u) * (ratio - 0.5 * u) + 1.0)) / tau
    return gain * np.interp(t, grid, out)


# ----------------------------------------------------------------------------- hysteresis

class MicroYield(SimOnly):
    """Gauges on a work-hardened beryllium-copper flexure that yields micro-plastically: Ramberg-Osgood's backbone
    (a plastic strain as the stress to the power ``exponent``) with Masing's rules and return-point memory, built as
    plays on the bridge voltage whose weights grow as the radius to the power ``exponent`` - 2 (radii over the span
    ``reach``). The flexure was cycled over the full span before use (the plays start as a load to ``reach`` and back
    left them) and calibrated along the middle of that loop; what remains are loops that grow as the excursion to the
    power ``exponent``: scarcely any for small cycles, marked for those that span the range."""

    def __init__(self, exponent, reach, k=48):
        self.radii = reach * (np.arange(k) + 0.5) / k
        w = self.radii ** (exponent - 2.0)
        self.weights, self.gain = w / w.sum(), 1.0
        self.start = np.minimum(self.radii, np.maximum(reach - self.radii, 0.0))
        sweep = np.linspace(0.0, reach, 400)
        loop = play_operator(np.concatenate([sweep, sweep[::-1]]), self.radii, self.start) @ self.weights
        self.mid_x, self.mid_y = sweep, 0.5 * (loop[:400] + loop[400:][::-1])

    def height(self, excursion):
        """The loop's largest width for a cycle from no load to ``excursion`` and back."""
        sweep = np.linspace(0.0, excursion, 400)
        loop = play_operator(np.concatenate([sweep, sweep[::-1]]), self.radii, self.start) @ self.weights
        return float(np.max(loop[400:][::-1] - loop[:400]))

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        stuck = play_operator(x, self.radii, self.start) @ self.weights
        return x + self.gain * (stuck - np.interp(x, self.mid_x, self.mid_y))


class VillariButterfly(SimOnly):
    """A magnetoelastic (Villari) read-out: a bias-magnetised steel sleeve whose magnetisation the stress moves. Its
    domain walls lag each reversal of the stress (a state z that approaches the sense of travel exponentially over
    ``travel`` of the signal, rate-independent), and the lag's effect on the read magnetisation changes sign at the
    Villari reversal, ``cross`` of the span ``reach`` up: y = x + g z (cross - x) / reach, loops of one sense below it
    and of the other above (a butterfly), ``g`` set for the largest loop over the span."""

    def __init__(self, frac, reach, travel, cross):
        self.reach, self.travel, self.cross = reach, travel, cross
        self.gain = frac * reach / (2.0 * max(cross, reach - cross) / reach)

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        steps = np.diff(x, prepend=x[0]).tolist()
        z, out = -1.0, np.empty(x.size)
        for i, dx in enumerate(steps):
            if dx:
                z = math.copysign(1.0, dx) + (z - math.copysign(1.0, dx)) * math.exp(-abs(dx) / self.travel)
            out[i] = z
        return x + self.gain * out * (self.cross - x) / self.reach


# ----------------------------------------------------------------------------- sensor lag

class SavitzkyGolay(SimOnly):
    """The firmware's Savitzky-Golay smoother (a polynomial of order ``order`` fitted over ``window_s`` and read at its
    middle, so half the window late) behind an anti-alias RC of ``rc_s``; run at 1 kHz (or the record's rate when
    faster) and read at the record's stamps."""

    def __init__(self, window_s, order, rc_s):
        self.window, self.order, self.rc = window_s, order, LinearFilter([1.0], [rc_s, 1.0])

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        y = self.rc.forward(t, np.asarray(x, dtype=float))
        h = min(float(np.median(np.diff(t))), 1e-3)  # the firmware's own rate, 1 kHz or the record's if faster
        tu = np.arange(t[0], t[-1] + h, h)
        xu = np.interp(tu, t, y)
        half = max(int(round(0.5 * self.window / h)), self.order // 2 + 1)
        taps = signal.savgol_coeffs(2 * half + 1, self.order)
        padded = np.concatenate([np.full(2 * half, xu[0]), xu])
        y = np.convolve(padded, taps, mode="valid")
        return np.interp(t, tu, y)


class CatmullRomLink(SimOnly):
    """A wireless node that samples the bridge every ``period_s`` (behind an RC of ``rc_s``) and a host that rebuilds
    the stream at the record's rate by a Catmull-Rom spline, which needs the two samples after each interval: the
    output is the spline through the node's samples, two periods late (its kernel dips below zero beside each
    step)."""

    def __init__(self, period_s, phase, rc_s):
        self.period, self.phase, self.rc = period_s, phase, LinearFilter([1.0], [rc_s, 1.0])

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        y = self.rc.forward(t, np.asarray(x, dtype=float))
        p, origin = self.period, t[0] + self.phase * self.period
        shown = t - 2.0 * p
        k = np.floor((shown - origin) / p)
        u = (shown - origin) / p - k
        at = origin + k * p
        p0, p1, p2, p3 = (np.interp(at + j * p, t, y, left=y[0]) for j in (-1, 0, 1, 2))
        return 0.5 * (2.0 * p1 + (p2 - p0) * u + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * u * u
                      + (3.0 * (p1 - p2) + p3 - p0) * u ** 3)


# ----------------------------------------------------------------------------- nonlinear gain

def differential_capacitor(rel, reach, rest, stray):
    """x read by a differential capacitive read-out (a plate between two electrodes, its position u in units of the
    gap, ``rest`` at no load) through the ratio (C1 - C2) / (C1 + C2 + 2 C_p): with a stray capacitance worth
    ``stray`` of the plates', u / (1 + p (1 - u^2)), expansive away from the centre (S-shaped when the load carries
    the plate across it); scaled to slope 1 at no load, the travel per volt set for a departure of ``rel`` at
    ``reach``, |u| kept below 0.9."""
    def ratio(u):
        return u / (1.0 + stray * (1.0 - u * u))
    slope = (1.0 + stray + stray * rest * rest) / (1.0 + stray - stray * rest * rest) ** 2

    def read(x, k):
        return (ratio(rest + k * np.asarray(x, dtype=float)) - ratio(rest)) / (k * slope)
    return fit_reach(read, rel, reach, (0.9 - rest) / reach)


def slider_crank(rel, reach, start_rad, rod_ratio):
    """x read by a rotary encoder that the core's plunger turns through a slider-crank (crank over rod ``rod_ratio``):
    the plunger's travel s(theta) = cos theta0 - cos theta + sqrt(1/l^2 - sin^2 theta0) - sqrt(1/l^2 - sin^2 theta)
    (in crank radii) from ``start_rad``; the angle read for the travel, scaled to slope 1 at no load: compressive near
    the top dead centre, expansive toward the bottom one; the travel per volt set for a departure of ``rel`` at
    ``reach``, the crank kept below 170 degrees."""
    inv = 1.0 / rod_ratio

    def travel(theta):
        return (math.cos(start_rad) - np.cos(theta) + math.sqrt(inv * inv - math.sin(start_rad) ** 2)
                - np.sqrt(inv * inv - np.sin(theta) ** 2))
    angles = np.linspace(start_rad, 2.97, 6001)
    moved = travel(angles)
    slope = float(np.gradient(moved, angles)[0])

    def read(x, k):
        return (np.interp(k * np.asarray(x, dtype=float), moved, angles) - start_rad) * slope / k
    return fit_reach(read, rel, reach, float(moved[-1]) / reach)


# ----------------------------------------------------------------------------- thermal drift

def getter_cavity_zero(t, temp, k_v_per_c, fast_share, desorb_per_c, lag_s, sorb_s):
    """The zero of a sealed-reference read-out whose cavity holds a zeolite getter: the cavity (lag ``lag_s``) presses
    as the gas law says at once (``fast_share`` of the slope at the reference), and the getter gives off gas as it
    warms and takes it back as it cools, toward exp(a dT) - 1 over a (convex) with ``sorb_s``; ``k_v_per_c`` in all
    at the reference."""
    cavity = lagged(t, temp, lag_s) - T_REF_C
    grid, cg = coarse(t, cavity, 0.5)
    goal = np.expm1(desorb_per_c * cg) / desorb_per_c
    keep, q, out = math.exp(-0.5 / sorb_s), float(goal[0]), np.empty(grid.size)
    for i, g in enumerate(goal.tolist()):
        q = g + (q - g) * keep
        out[i] = q
    return k_v_per_c * (fast_share * cavity + (1.0 - fast_share) * np.interp(t, grid, out))


def thermomagnetic_zero(t, temp, k_v_per_c, curie_above_c, beta, lag_s):
    """The zero of a Hall read-out whose bias magnet is partly shunted by a thermomagnetic (Ni-Fe) alloy strip: the
    strip's permeability, and so the flux it diverts, falls as (T_c - T)^beta toward its Curie point ``curie_above_c``
    above the reference (none beyond), the strip lagging by ``lag_s``; the zero follows the flux left to the Hall
    element, scaled for a mean slope of ``k_v_per_c`` over -2 to +3 degC."""
    def shunt(dt):
        return np.maximum(curie_above_c - dt, 0.0) ** beta
    probe = np.linspace(-2.0, 3.0, 101)
    mean_slope = abs(float(shunt(probe[-1]) - shunt(probe[0]))) / 5.0
    strip = lagged(t, temp, lag_s) - T_REF_C
    return k_v_per_c * (shunt(0.0) - shunt(strip)) / max(mean_slope, 1e-12)


# ----------------------------------------------------------------------------- thermal sensitivity

class HallGradientSpan(SimOnly):
    """A Hall read-out of a magnet the load moves, whose span is the dipole field's gradient at the Hall element, as
    the gap to the power -4: the polymer carrier (lag ``slow_s``) moves the magnet away from or toward the element as
    it warms (the gap 1 + ``coefficient`` / 4 dT), and the NdFeB magnet itself (lag ``fast_s``) loses 0.12 %/degC of
    its remanence."""

    def __init__(self, coefficient, fast_s, slow_s):
        self.coefficient, self.fast, self.slow = coefficient, fast_s, slow_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        temp = temp_at(aux, t.size)
        magnet, carrier = lagged(t, temp, self.fast) - T_REF_C, lagged(t, temp, self.slow) - T_REF_C
        gap = np.maximum(1.0 + 0.25 * self.coefficient * carrier, 0.5)
        return np.asarray(x, dtype=float) * (1.0 - 0.0012 * magnet) * gap ** -4.0


class DrumMembraneSpan(SimOnly):
    """A read-out membrane stretched over a frame like a drum (its pretension ``share`` of its stiffness at the
    reference, the rest its bending); the membrane (lag ``lag_s``) expands more or less than the frame, so its tension
    falls or rises by ``coefficient`` / ``share`` per degC: the span 1 / (1 - coefficient dT), the tension never below
    10 % of its reference value."""

    def __init__(self, coefficient, share, lag_s):
        self.coefficient, self.share, self.lag = coefficient, share, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        dt = lagged(t, temp_at(aux, t.size), self.lag) - T_REF_C
        tension = np.maximum(1.0 - self.coefficient / self.share * dt, 0.1)
        return np.asarray(x, dtype=float) / (1.0 - self.share + self.share * tension)


# ----------------------------------------------------------------------------- offset drift

def barometric_route(rng, horizon_s=HORIZON_S):
    """The zero of a sealed-gauge read-out as the ambulance drives (as a function of the seconds since the first
    sample, zero there): the air pressure falls by 12 Pa per metre of altitude, which changes along the route by
    8-25 m (normal, either way) over each stretch of 20-90 s (smooth); the cabin's ventilation holds it 10-40 Pa above
    the outside while the doors are shut, lost within 0.3-1 s at each of 1-3 openings (5-30 s) and built up again with
    5-20 s."""
    stretches, now = [], -60.0
    while now < horizon_s:
        length = rng.uniform(20.0, 90.0)
        stretches.append((now, length, rng.normal(0.0, 1.0) * rng.uniform(8.0, 25.0)))
        now += length
    lift = rng.uniform(10.0, 40.0)
    doors = [(rng.uniform(0.0, horizon_s), rng.uniform(5.0, 30.0), rng.uniform(0.3, 1.0), rng.uniform(5.0, 20.0))
             for _ in range(int(rng.integers(1, 4)))]

    def pressure(s):
        s = np.asarray(s, dtype=float)
        height = sum(rise * smooth_step((s - start) / length) for start, length, rise in stretches)
        cabin = np.ones_like(s)
        for start, open_s, quick, back in doors:
            since = s - start
            shut = np.where(since < open_s, smooth_step(since / quick),
                            np.exp(-np.maximum(since - open_s, 0.0) / back))
            cabin = np.minimum(cabin, 1.0 - np.where(since >= 0.0, shut, 0.0))
        return -12.0 * height + lift * cabin
    first = float(pressure(np.zeros(1))[0])
    return lambda s: pressure(s) - first


def fretting_connector(rng, horizon_s=HORIZON_S):
    """The zero of a bridge one of whose arms passes a tin-plated connector pin that the ambulance's vibration frets:
    its contact resistance grows as the power 1.5-3 of the vibration taken since the vehicle set off (up to 150 s
    before the record: an incubation, then faster and faster), the vibration on while the vehicle drives (bouts of
    20-120 s, 10-60 s stopped, each road 0.5-1.5 times as rough); as a function of the seconds since the first
    sample, zero there."""
    driving = bouts(rng, (10.0, 60.0), (20.0, 120.0), first_s=(-150.0, 0.0))
    power = rng.uniform(1.5, 3.0)
    grid = np.arange(-150.0, horizon_s + 1.0, 0.1)
    shake = np.zeros(grid.size)
    for start, length in driving:
        shake[(grid >= start) & (grid < start + length)] = rng.uniform(0.5, 1.5)
    wear = integrate.cumulative_trapezoid(shake, grid, initial=0.0) ** power
    zero_at_start = float(np.interp(0.0, grid, wear))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, wear) - zero_at_start


# ----------------------------------------------------------------------------- resonance

class BlowOffMode(SimOnly):
    """A needle holder's mode (``f0_hz``) damped by an oil damper with a blow-off valve: below the relative speed at
    which the valve cracks (``share`` of the largest the mode reaches on the record with the valve open) the damping
    ratio is ``zeta_shut``, beyond it the extra force grows only at ``zeta_open``: large knocks ring long and lightly,
    their tails and small ones die faster. The frequency does not change. Semi-implicit Euler with ``sub`` sub-steps
    on the uniform grid at the median step, from rest."""

    def __init__(self, f0_hz, zeta_open, zeta_shut, share, sub=4):
        self.w, self.zo, self.zs, self.share, self.sub = 2.0 * math.pi * f0_hz, zeta_open, zeta_shut, share, sub

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        w = self.w
        b, a = signal.bilinear([2.0 * self.zo * w, w * w], [1.0, 2.0 * self.zo * w, w * w], fs=1.0 / h)
        light = signal.lfilter(b, a, xu - xu[0]) + xu[0]
        crack = max(self.share * float(np.max(np.abs(np.gradient(light - xu, h)))), 1e-12)
        shut, open_ = 2.0 * self.zs * w, 2.0 * self.zo * w
        rate, dt = np.gradient(xu, h), h / self.sub
        y, v, out = float(xu[0]), 0.0, np.empty(tu.size)
        for i, (xi, ri) in enumerate(zip(xu.tolist(), rate.tolist())):
            for _ in range(self.sub):
                rel = v - ri
                if abs(rel) <= crack:
                    drag = shut * rel
                else:
                    drag = math.copysign(shut * crack + open_ * (abs(rel) - crack), rel)
                v += (-drag - w * w * (y - xi)) * dt
                y += v * dt
            out[i] = y
        return np.interp(t, tu, out)


class CableEchoMode(SimOnly):
    """A holder's mode (``f0_hz``, damping ratio ``zeta``) that loses ``radiated`` of its damping as waves into the
    taut instrument cable fixed to it; the cable's far end, ``round_trip_s`` of travel there and back, returns them
    with the reflection ``reflection``, so the ringing after a knock revives as the echoes come back. The frequency
    does not change. Semi-implicit Euler with ``sub`` sub-steps on the uniform grid at the median step, from rest."""

    def __init__(self, f0_hz, zeta, radiated, round_trip_s, reflection, sub=4):
        self.w, self.zeta, self.radiated = 2.0 * math.pi * f0_hz, zeta, radiated
        self.round_trip, self.reflection, self.sub = round_trip_s, reflection, sub

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        w, dt = self.w, h / self.sub
        own, cable = 2.0 * self.zeta * (1.0 - self.radiated) * w, 2.0 * self.zeta * self.radiated * w
        lag = max(int(round(self.round_trip / dt)), 1)
        sent = np.zeros(lag)
        rate = np.gradient(xu, h)
        y, v, j, out = float(xu[0]), 0.0, 0, np.empty(tu.size)
        for i, (xi, ri) in enumerate(zip(xu.tolist(), rate.tolist())):
            for _ in range(self.sub):
                rel = v - ri
                back = self.reflection * sent[j]
                sent[j] = rel - back
                j = (j + 1) % lag
                v += (-own * rel - cable * (rel - 2.0 * back) - w * w * (y - xi)) * dt
                y += v * dt
            out[i] = y
        return np.interp(t, tu, out)


# ----------------------------------------------------------------------------- friction

def braking_and_cornering(rng, horizon_s=HORIZON_S):
    """The ambulance's acceleration in g (as a function of the seconds since the first sample): braking (0.2-0.5 g for
    2-6 s) or a bend (0.1-0.4 g for 3-10 s), each reached and left within 0.5-1.5 s, 8-40 s apart."""
    events, now = [], rng.uniform(-10.0, 15.0)
    while now < horizon_s:
        braking = rng.random() < 0.5
        size = rng.uniform(0.2, 0.5) if braking else rng.uniform(0.1, 0.4)
        edge, hold = rng.uniform(0.5, 1.5), rng.uniform(2.0, 6.0) if braking else rng.uniform(3.0, 10.0)
        events.append((now, edge, hold, size))
        now += 2.0 * edge + hold + rng.uniform(8.0, 40.0)

    def accel(s):
        s = np.asarray(s, dtype=float)
        return sum(size * (smooth_step((s - at) / edge) - smooth_step((s - at - edge - hold) / edge))
                   for at, edge, hold, size in events)
    return accel


def flushed_coating(rng, horizon_s=HORIZON_S):
    """The wetness (0 dry, 1 wet) of a hydrophilic coating on the needle guide (as a function of the seconds since the
    first sample): a saline flush every 20-90 s wets it within 0.5-1.5 s and keeps it wet for 1-3 s, after which it
    dries along a smooth curve over 20-90 s."""
    flushes = [(start, rng.uniform(0.5, 1.5), length, rng.uniform(20.0, 90.0))
               for start, length in bouts(rng, (20.0, 90.0), (1.0, 3.0), horizon_s, first_s=(-90.0, 30.0))]

    def wet(s):
        s = np.asarray(s, dtype=float)
        out = np.zeros_like(s)
        for start, quick, soak, dry in flushes:
            since = s - start
            level = np.where(since < quick + soak, smooth_step(since / quick),
                             1.0 - smooth_step((since - quick - soak) / dry))
            out = np.maximum(out, np.where(since >= 0.0, level, 0.0))
        return out
    return wet


def varying_band(band_n, factor):
    """A Coulomb band of half-width ``band_n`` times ``factor(seconds since the first sample)`` on the force the core
    sees, the same at every load."""
    def passed(t, f):
        width = band_n * factor(t - t[0])
        return band_play(f, width, width)
    return passed


# ----------------------------------------------------------------------------- thermo-rheological

class WaltherClock(SimOnly):
    """A core whose dashpots are filled with a heavy polybutene (``viscosity_cst`` at the reference) following
    Walther's relation, log log (nu + 0.7) = A - B log T (T absolute, the core's temperature behind ``lag_s``), B set
    so that the clock's slope at the reference is ``b_per_c``: the core's clock runs at nu_ref / nu."""

    def __init__(self, c, b_per_c, viscosity_cst, lag_s):
        self.c, self.lag = c, lag_s
        self.z_ref, self.t_ref = math.log10(viscosity_cst + 0.7), T_REF_C + 273.15
        self.b_walther = b_per_c * self.t_ref / (math.log(10.0) * self.z_ref)
        self.nu_ref = viscosity_cst

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        kelvin = lagged(t, temp_at(aux, t.size), self.lag) + 273.15
        z = self.z_ref * (kelvin / self.t_ref) ** -self.b_walther
        nu = 10.0 ** z - 0.7
        return clocked(self.c, t, np.asarray(x, dtype=float), self.nu_ref / nu)


class WristClock(SimOnly):
    """A core on an Arrhenius clock (``b_per_c`` per degC) whose temperature is a mix of two paths: the cabin air
    reaching it by convection (``air_share``, lag ``air_s``) and the robot's aluminium wrist it is bolted to
    (the rest, lag ``wrist_s``)."""

    def __init__(self, c, b_per_c, air_share, air_s, wrist_s):
        self.c, self.b, self.share, self.air, self.wrist = c, b_per_c, air_share, air_s, wrist_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        temp = temp_at(aux, t.size)
        core_c = self.share * lagged(t, temp, self.air) + (1.0 - self.share) * lagged(t, temp, self.wrist)
        return clocked(self.c, t, np.asarray(x, dtype=float), np.exp(self.b * (core_c - T_REF_C)))


# ----------------------------------------------------------------------------- outside the catalogue

def siren_pickup(rng, amplitude_v, horizon_s=HORIZON_S):
    """The ambulance's siren amplifier picked up by the bridge's leads and sampled without an anti-alias filter: during
    2-5 runs of 10-60 s (faded in and out over 0.5 s) a wail sweeping 600-1400 Hz and back every 2-6 s, of
    ``amplitude_v``, aliased into the record by its sampling (as a function of the seconds since the first sample)."""
    runs = [(rng.uniform(-20.0, horizon_s), rng.uniform(10.0, 60.0), rng.uniform(2.0, 6.0), rng.uniform(0.0, 6.3))
            for _ in range(int(rng.integers(2, 6)))]

    def pick(s):
        s = np.asarray(s, dtype=float)
        out = np.zeros_like(s)
        for start, length, sweep_s, phase in runs:
            since = s - start
            fade = smooth_step(since / 0.5) * (1.0 - smooth_step((since - length + 0.5) / 0.5))
            cycles = 600.0 * since + 800.0 * (0.5 * since - sweep_s / (4.0 * math.pi) * np.sin(2.0 * math.pi * since
                                                                                              / sweep_s))
            out += np.where((since >= 0.0) & (since < length), fade * np.sin(2.0 * math.pi * cycles + phase), 0.0)
        return amplitude_v * out
    return pick


class AddressConflict(SimOnly):
    """A second sensor (a gripper's force sensor) on the same I2C bus answering to the bridge's address: while the
    gripper's controller polls it (bouts ``polls``: start, length in seconds since the first sample) each reading has
    a chance ``prob`` of being the gripper's instead, its own zero (10-50 mV) plus 0.05-0.3 V/N of a grip that wanders
    between 0 and 3 N over 5-60 s; drawn from ``seed``."""

    def __init__(self, polls, prob, seed):
        self.polls, self.prob, self.seed = polls, prob, seed

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        rng = np.random.default_rng(self.seed)
        s = t - t[0]
        grip = np.full(s.size, 1.5)
        for share in rng.dirichlet(np.ones(3)):
            grip += 1.5 * share * np.sin(2.0 * math.pi * s / rng.uniform(5.0, 60.0) + rng.uniform(0.0, 6.3))
        other = rng.uniform(0.01, 0.05) + rng.uniform(0.05, 0.3) * np.clip(grip, 0.0, 3.0)
        hit = (rng.random(s.size) < self.prob) & in_bouts(s, self.polls)
        return np.where(hit, other, x)


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([6e4, 8e3]))))  # V / (N s)
        if shape == "fatigue_crack_leak":
            rule = fatigue_crack_leak(phi, rng.uniform(0.4, 0.8), rng.uniform(2.5, 5.0), rng.uniform(2.0, 4.0))
        else:
            rule = clogging_filter(phi * rng.uniform(1.5, 3.0), rng.uniform(0.7, 2.3), rng.uniform(30.0, 150.0))
        return Parts("zener", LeakyCore(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        compliance = float(np.interp(m, [0, 1], [0.03, 0.2])) / g0  # V / N: a share of the instantaneous response
        if shape == "hydrostatic_pad":
            a = (compliance, rng.uniform(3.0, 5.0), rng.uniform(0.2, 0.4), rng.uniform(0.8, 0.9), rng.uniform(1.0, 15.0))
            p.extra.append(lambda t, f, T, a=a: hydrostatic_pad(t, f, *a))
            return p
        a = (compliance, rng.uniform(2.5, 6.0), rng.uniform(1.0, 1.35), rng.uniform(1.0, 10.0))
        p.extra.append(lambda t, f, T, a=a: dome_kelvin(t, f, *a))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.01, 0.06]))
        if shape == "microyield_flexure":
            element = MicroYield(rng.uniform(3.0, 4.0), top)  # 1.5 frac over the full range, 0.45-0.65 frac at 6 N
            element.gain = 1.5 * frac * top / max(element.height(top), 1e-12)
            p.after.append(element)
            return p
        p.after.append(VillariButterfly(frac, top, top * rng.uniform(0.02, 0.08), top * rng.uniform(0.35, 0.75)))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.005, 0.09]))))
        if shape == "savitzky_golay":
            p.after.append(SavitzkyGolay(2.0 * delay * rng.uniform(0.8, 1.2), int(rng.choice([2, 4])),
                                         rng.uniform(0.001, 0.003)))
            return p
        p.after.append(CatmullRomLink(0.5 * delay * rng.uniform(0.8, 1.2), rng.uniform(0.0, 1.0),
                                      rng.uniform(0.001, 0.003)))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.05, 0.16]))
        if shape == "differential_capacitor":
            p.after.append(StaticMap(differential_capacitor(rel, top, rng.uniform(-0.3, 0.4), rng.uniform(0.3, 3.0))))
            return p
        start = math.radians(rng.uniform(20.0, 55.0) if rng.random() < 0.5 else rng.uniform(115.0, 150.0))
        p.after.append(StaticMap(slider_crank(rel, top, start, rng.uniform(0.2, 0.5))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.008, 0.03]) * rng.choice([-1, 1]))
        if shape == "getter_cavity":
            a = (k, rng.uniform(0.3, 0.6), rng.uniform(0.1, 0.3), rng.uniform(5.0, 15.0), rng.uniform(60.0, 300.0))
            p.extra.append(lambda t, f, T, a=a: getter_cavity_zero(t, T, *a))
            return p
        a = (k, rng.uniform(3.0, 10.0), rng.uniform(0.3, 0.5), rng.uniform(10.0, 40.0))
        p.extra.append(lambda t, f, T, a=a: thermomagnetic_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.008, 0.02]) * rng.choice([-1, 1]))
        if shape == "hall_gradient":
            p.after.append(HallGradientSpan(a, rng.uniform(5.0, 15.0), rng.uniform(20.0, 60.0)))
            return p
        p.after.append(DrumMembraneSpan(a, rng.uniform(0.5, 0.9), rng.uniform(10.0, 40.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.012, 0.08]) * rng.choice([-1, 1]))
        zero = peak_scaled(barometric_route(rng) if shape == "barometric_route" else fretting_connector(rng), size)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.03, 0.008])) * rng.uniform(0.8, 1.2)
        if shape == "blow_off_damper":
            p.after.append(BlowOffMode(rng.uniform(15.0, 45.0), zeta, zeta * rng.uniform(2.5, 4.0),
                                       rng.uniform(0.1, 0.4)))
            return p
        p.after.append(CableEchoMode(rng.uniform(15.0, 45.0), zeta, rng.uniform(0.5, 0.8), rng.uniform(0.017, 0.15),
                                     rng.choice([-1.0, 1.0]) * rng.uniform(0.3, 0.7)))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "ambulance_guide":
            accel, grip = braking_and_cornering(rng), rng.uniform(0.6, 1.5)
            p.before.append(ForcePath(varying_band(r, lambda s, a=accel, g=grip: 1.0 + g * a(s) / 0.5)))
            return p
        wet, slick = flushed_coating(rng), rng.uniform(0.5, 0.7)
        p.before.append(ForcePath(varying_band(r, lambda s, w=wet, k=slick: 1.0 - k * w(s))))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.15, 0.45]))
        if shape == "walther_polybutene":
            return Parts("burgers", WaltherClock(c, b, float(np.exp(rng.uniform(np.log(1e5), np.log(1e7)))),
                                                 rng.uniform(5.0, 20.0)), core_changed=True)
        # the wrist passes little of a minute's swing of the air: a steeper clock
        return Parts("burgers", WristClock(c, b * rng.uniform(1.2, 1.6), rng.uniform(0.4, 0.7), rng.uniform(5.0, 20.0),
                                           rng.uniform(90.0, 300.0)), core_changed=True)
    if effect == "siren_pickup":
        pick = siren_pickup(rng, float(np.interp(m, [0, 1], [0.01, 0.06])))
        p.extra.append(lambda t, f, T, u=pick: u(t - t[0]))
        return p
    if effect == "address_conflict":
        polls = bouts(rng, (10.0, 40.0), (5.0, 20.0))
        p.outer.append(AddressConflict(polls, float(np.interp(m, [0, 1], [0.002, 0.01])), int(rng.integers(1 << 30))))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["fatigue_crack_leak", "clogging_filter"],
    "delayed_elasticity": ["hydrostatic_pad", "dome_kelvin"],
    "hysteresis": ["microyield_flexure", "villari_butterfly"],
    "sensor_lag": ["savitzky_golay", "catmull_rom_link"],
    "nonlinear_gain": ["differential_capacitor", "slider_crank"],
    "thermal_drift": ["getter_cavity", "thermomagnetic_shunt"],
    "thermal_sensitivity": ["hall_gradient", "drum_membrane"],
    "offset_drift": ["barometric_route", "fretting_connector"],
    "resonance": ["blow_off_damper", "cable_echo"],
    "friction": ["ambulance_guide", "flushed_coating"],
    "thermo_rheological": ["walther_polybutene", "wrist_clock"],
}
PAIRS = (("viscous_flow", "thermal_drift"), ("delayed_elasticity", "sensor_lag"), ("hysteresis", "thermal_sensitivity"),
         ("friction", "nonlinear_gain"), ("offset_drift", "thermo_rheological"), ("resonance", "viscous_flow"))
OUTSIDE = ("siren_pickup", "address_conflict")
RATES = (110.0, 360.0, 560.0, 820.0)  # four rates, three profiles: every profile at every rate


class SplitW(ShapeSplit):
    """:class:`ShapeSplit`, whose ``--check`` also sizes what a leak adds to a case on a Zener base (against the same
    Zener core without it and without the other hidden effect)."""

    def check_case(self, item):
        i, (hidden, m) = item
        rate = self.rate(hidden, i)
        rng = np.random.default_rng(self.seed0 + i)
        t, f = self.load(hidden, i, rate, rng)
        temp = self.temperature(t, rng)
        before = rng.bit_generator.state
        base, truth = self.sensor(hidden, m, rng)
        if base == "burgers":
            return super().check_case(item)
        rng.bit_generator.state = before
        plain = Parts(base, LeakyCore(core(rng), None)).truth()
        gap = truth.voltage(t, f, temp) - plain.voltage(t, f, temp)
        return i, hidden, float(np.sqrt(np.mean((gap - gap.mean()) ** 2)) / 2e-3)


SPLIT = SplitW("independent split W", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.85),
               pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
               make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.0e-3, 2.4e-3), jitter=0.3,
               gap_s=(0.2, 2.2))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
