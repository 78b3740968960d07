"""Independent split T for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split T is an untouched held-out set: written before the engine it measures and blind to it (to how it detects and
fits anything), run once at its end, never used to choose anything. Every name of the catalogue is hidden in two
shapes that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A to S use:

* a fluid-filled core whose leak channel a gas bubble now and then blocks (the fluidity a random telegraph: open at
  1-2.5 times the plain fluidity of 1/60000-1/4000 V/(N s), blocked at 5-30 % of it, dwells of 8-60 s open and 5-40 s
  blocked; it never recovers), or a leak through a pressure-compensated flow regulator (an infusion set's: the flow
  linear in the force at 1-2 times the plain fluidity below its regulating force of 1.5-4 N, held at what that force
  gives above it, the corner as a p-norm of order 2-4);
* a Kelvin unit (compliance 3-20 % of the instantaneous one, 2-20 s) whose dashpot has a blow-off valve (once the
  unit's deficit exceeds what 0.3-1.5 N gives, the excess bleeds 5-20 times faster: a quick start after a large step,
  then the slow approach), or a Kelvin unit in an open-cell foam that sustained loads compact (its retardation of 0.5-5 s
  grows by 1.5-5 times per 4 N of the force averaged over 30-120 s: after a long press the creep and its recovery
  slow down);
* the skin film bonded over the core, which peels back as the core bulges (its front advances once the force exceeds
  0-1 N plus 3-8 N times the peeled share, heals only below 30-70 % of that; the peeled share adds its compliance,
  the force times the share, at the bridge: a loop of 1-6 % of the range that closes at no load), or a magnetic
  read-out whose flux guide is a soft-magnetic wire, its domain wall hopping between random pinning sites (sites every
  1-3 % of the range, pinning radii 0.3-1.7 times a mean of 4-12 % of it: a jagged Barkhausen loop of 1-6 % of the
  range on the bridge voltage);
* a speed-adaptive low-pass in the firmware (the 1-euro filter: a time constant of 1.3-2 times 12-90 ms at rest,
  its cutoff rising 3-10 fold at a speed of the range per second, the speed itself smoothed at 1-5 Hz), or an
  analogue delay equaliser (two first-order all-pass sections behind an RC of 1-3 ms: 12-90 ms of delay at low
  frequencies, a dip before each step);
* a fibre-optic reflective (intensity) read-out, two fibres side by side facing a mirror on the core (the power
  u^-2 exp(1 - u^-2) of the gap u in units of its peak's), on the front slope (u 0.55-0.85) as the load closes the
  gap or on the back slope (u 1.05-2) as it opens it: compressive or S-shaped, 5-16 % at the top of the range; or a
  fibre Bragg grating read through an edge filter (a Gaussian flank, the grating's wavelength 0.3-2 widths from the
  filter's centre moving away from it with the load: expansive, S-shaped or compressive, 5-16 %);
* a fluoropolymer spacer whose crystalline transition (at the 30-70th percentile of its temperature over the record,
  0.3-0.8 degC wide, lag 5-20 s) adds an expansion worth 1-3 degC of its linear one (0.006-0.022 V/degC), or a
  thermal zero (0.006-0.022 V/degC) behind a lag that the incubator's fan shortens to 5-15 s while it heats (the air
  below its set point, at the 60-85th percentile, with 0.1-0.3 degC of switching band) and leaves at 40-120 s
  otherwise;
* a magnetic read-out whose bonded magnet loses remanence reversibly (the span 0.6-1.6 %/degC, lag 5-20 s) and
  irreversibly whenever it is warmed past the warmest it has been (a further 30-100 % of that per degC, never
  recovered; the magnet was last warmed 0-1.5 degC above its start), or a polymer span (0.8-2 %/degC, lag 5-20 s)
  corrected by firmware from a table indexed by the thermometer's reading rounded to bins of 1.5-3 degC, with 60-140 %
  of the true coefficient (a sawtooth in temperature and steps at the bins' edges);
* the earth's magnetic field seen by a magnetic read-out as the robot turns the tool (its heading moved every 10-50 s
  by 20-120 degrees in 1-4 s: the zero as the cosine of the heading from a random reference; 12-80 mV at most), or gas
  bubbles from electrolysis on the bridge's saline-wetted pads (3-8 sites, each bubble covering more of its pad as it
  grows over 10-60 s and then detaching: a sum of random sawtooths; 12-80 mV at most);
* the bending mode of a spinning burr seen through its holder (18-45 Hz), split by gyroscopic coupling into a forward
  and a backward whirl 3-12 % apart while the burr spins (5-30 s every 15-60 s), or a holder's mode (15-40 Hz) under
  a semi-active magnetorheological damper that the controller switches on while the robot moves (1-5 s every 5-25
  s: the damping 8-20 times heavier, at most 0.5); damping ratio 0.0064-0.036 otherwise;
* a Coulomb band of 0.4-3.6 % of the range in a lead-screw stage whose nut's preload changes once per turn (the band
  times 1 +- 0.3-0.7 along the force's travel, a turn per 2-10 N of it), or in a linear ball guide whose cage creeps
  (the balls roll with 10-30 % of the band until the cage reaches its end stop, 0.2-1.5 N of slip from where it sits,
  then slide with all of it);
* an Arrhenius clock (0.1-0.3 per degC) on a foam core whose thermal contact with the air the load improves (its lag
  of 60-200 s 3-8 times shorter under 5 N or more), or on a core the incubator's air reaches through a duct (a
  transport delay of 10-40 s, then a lag of 5-20 s).

It also holds six pairs, two effects outside the catalogue (a harmonic (ultrasonic) scalpel's 55.5 kHz blade,
wandering by 50-300 Hz with its load, aliased into the record during 5-15 activations of 2-10 s; the idle tones of a
first-order sigma-delta modulator leaking through a weak decimation filter, a tone whose frequency follows the bridge
voltage as a triangle of it with a period of 20-80 mV) and four clean records. Profiles: robotic acupuncture through
the measured force-depth curve (``../shared/data``, ``depth_force.csv``, its first insertion stretched over 15-40 mm),
then lifting-thrusting at 1-2.5 Hz and twirling that makes the tissue grasp the needle, a retention that relaxes and
a withdrawal (synthetic layers when the data are absent); a robot holding an ultrasound probe for elastography
(contact, the patient's breathing, quasi-static compression cycles, sliding sweeps under a force controller, lift-off);
and spinal mobilisation by a physiotherapy robot (Maitland's grades I-IV of oscillation in a stiffening range, now and
then a high-velocity thrust). Rates 130, 430, 570 and 970 Hz (a mode at 1000 Hz with knocks that excite it), 1.0-2.3
mV noise, stamp jitter, gaps, and a sensor on a robot beside a neonatal incubator, which warms up from the room to its
set point under a thermostat with a lagging heater and cools whenever its portholes are opened.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_t.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, optimize

from polyforce_ros.physics.viscoelastic import simulate_deformation
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (band_play, coarse, cutter as window, dead_time, ForcePath, LinearFilter, logistic, Parts,
                       quintic, schedule as schedule_until, ShapeSplit, SimOnly, sized, temp_of, uniform_grid, within,
                       ZenerWithFlow)

SEED0 = 1_380_000  # never a seed of the registry's splits nor of splits A (90000..) to S (1310000..)
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
    insertion (up to the first withdrawal of more than 5 mm), as (depth in mm, force in N): the median force per bin
    of ``bin_mm`` (digitised curves carry stray points), empty bins interpolated, no negative force; None when the file
    is absent."""
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
        median[k] = np.median(force_n[which == k])
    filled = np.isfinite(median)
    return grid, np.maximum(np.interp(grid, grid[filled], median[filled]), 0.0)


def synthetic_insertion(rng):
    """What :func:`measured_insertion` gives, made up: a friction of 0.01-0.03 N/mm over 40 mm and 2-3 membranes that
    build up over 2-6 mm by 0.3-1 N and tear (leaving 30 % that fades over 1 mm)."""
    grid = np.arange(0.0, 40.0, 0.25)
    force_n = rng.uniform(0.01, 0.03) * grid
    for at in np.sort(rng.uniform(5.0, 36.0, int(rng.integers(2, 4)))):
        build, height = rng.uniform(2.0, 6.0), rng.uniform(0.3, 1.0)
        rising = (grid > at - build) & (grid <= at)
        force_n[rising] += height * (grid[rising] - at + build) / build
        torn = grid > at
        force_n[torn] += 0.3 * height * np.exp(-(grid[torn] - at))
    return grid, force_n


def robotic_acupuncture(duration_s, rate_hz, rng):
    """A robot needling acupuncture points (the sensor behind its needle holder). Each needle goes in through the
    measured insertion (``measured_insertion``), stretched over 15-40 mm and scaled to a 3-7 N peak: the skin at
    8-20 mm/s for its first 3-6 mm, then 1.5-4 mm/s. At depth the robot seeks the de qi sensation for 10-30 s:
    lifting-thrusting (1-3 mm at 1-2.5 Hz, the force the shaft's friction, 50-80 % of the insertion force there, while
    it thrusts and 5-20 % of it while it lifts) alternating with twirling (4-10 s, the tissue winding onto the shaft and
    gripping it: the friction 30-100 % higher within 2-6 s, released over 1-3 s afterwards). A retention of 5-20 s (the
    force relaxing to 40-70 % with 1-4 s), a withdrawal of 1-3 s, 8-25 s before the next point. Made-up layers
    (``synthetic_insertion``) when ``../shared/data`` is absent."""
    depth_mm, force_n = measured_insertion() or synthetic_insertion(rng)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    at = window(t)
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 45.0:
        goal_mm = rng.uniform(15.0, 40.0)
        stretch = goal_mm / float(depth_mm[-1])
        scale = rng.uniform(3.0, 7.0) / max(float(force_n.max()), 1e-3)

        def resistance(d, stretch=stretch, scale=scale):
            return scale * np.interp(d / stretch, depth_mm, force_n)
        skin_mm, fast, slow = rng.uniform(3.0, 6.0), rng.uniform(8.0, 20.0), rng.uniform(1.5, 4.0)
        for start_mm, end_mm, speed in ((0.0, skin_mm, fast), (skin_mm, goal_mm, slow)):
            seg, s = at(now, (end_mm - start_mm) / speed)
            f[seg] = resistance(start_mm + speed * s)
            now += (end_mm - start_mm) / speed
        level = float(resistance(np.array([goal_mm]))[0])
        friction, lifting = level * rng.uniform(0.5, 0.8), rng.uniform(0.05, 0.2)
        seg, s = at(now, 0.3)
        f[seg] = level + (friction - level) * quintic(s / 0.3)  # the cutting stops with the advance
        now += 0.3
        manipulate, grip = now + rng.uniform(10.0, 30.0), 1.0
        while now < manipulate:
            span, freq, amp = rng.uniform(3.0, 8.0), rng.uniform(1.0, 2.5), rng.uniform(1.0, 3.0)
            seg, s = at(now, span)
            speed = np.sin(2.0 * np.pi * freq * s)  # the stroke's velocity, in units of its peak
            thrusting = 0.5 * (1.0 + np.tanh(speed / 0.2))
            depth = goal_mm - amp * 0.5 * (1.0 + np.cos(2.0 * np.pi * freq * s))  # in the channel already cut
            fric = friction * grip * np.interp(depth, [0.0, goal_mm], [0.0, 1.0])
            f[seg] = fric * (lifting + (1.0 - lifting) * thrusting)
            now += span
            twirl, rise, gain = rng.uniform(4.0, 10.0), rng.uniform(2.0, 6.0), rng.uniform(0.3, 1.0)
            seg, s = at(now, twirl)
            gripped = grip * (1.0 + gain * -np.expm1(-s / rise))
            f[seg] = friction * gripped * (0.6 + 0.1 * np.sin(2.0 * np.pi * rng.uniform(1.0, 3.0) * s))
            now += twirl
            release = rng.uniform(1.0, 3.0)
            held = float(gripped[-1]) if gripped.size else grip
            seg, s = at(now, release)
            f[seg] = friction * 0.6 * (held + (1.0 - held) * quintic(s / release))
            now += release
        retain, keep, tau = rng.uniform(5.0, 20.0), rng.uniform(0.4, 0.7), rng.uniform(1.0, 4.0)
        start_n = friction * 0.6
        seg, s = at(now, retain)
        f[seg] = start_n * (keep + (1.0 - keep) * np.exp(-s / tau))
        now += retain
        last = start_n * (keep + (1.0 - keep) * math.exp(-retain / tau))
        out = rng.uniform(1.0, 3.0)
        seg, s = at(now, out)
        f[seg] = last * (1.0 - quintic(s / out))
        now += out + rng.uniform(8.0, 25.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def ultrasound_elastography(duration_s, rate_hz, rng):
    """A robot holding an ultrasound probe on a patient's abdomen for elastography (the sensor in its wrist). Each
    session: contact made by a quintic ramp to 2-6 N over 1-3 s; a hold of 8-25 s on which the patient's breathing
    rides (0.2-0.8 N at 0.2-0.33 Hz, its shape sharpened at inspiration); 5-15 s of quasi-static compressions for the
    strain image (triangles of 0.5-2 N at 0.5-2 Hz, on the breathing); 5-20 s of sliding sweep under the force
    controller (its ripple, three sines of 0.1-0.4 N at 0.5-4 Hz, and a skin friction catch of 0.3-1 N now and then);
    a lift-off in 0.3-1 s and 3-15 s away (gel, repositioning)."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    at = window(t)
    now = rng.uniform(2.0, 5.0)
    breath_hz, breath_n, phase = rng.uniform(0.2, 0.33), rng.uniform(0.2, 0.8), rng.uniform(0.0, 2.0 * np.pi)

    def breathing(times):
        wave = np.sin(2.0 * np.pi * breath_hz * times + phase)
        return breath_n * (np.abs(wave) ** 0.7 * np.sign(wave))
    while now < duration_s - 20.0:
        level, rise = rng.uniform(2.0, 6.0), rng.uniform(1.0, 3.0)
        seg, s = at(now, rise)
        f[seg] = level * quintic(s / rise)
        now += rise
        hold = rng.uniform(8.0, 25.0)
        seg, s = at(now, hold)
        f[seg] = level + breathing(t[seg]) * quintic(s / 2.0)
        now += hold
        press, amp, freq = rng.uniform(5.0, 15.0), rng.uniform(0.5, 2.0), rng.uniform(0.5, 2.0)
        seg, s = at(now, press)
        triangle = 2.0 * np.abs(((freq * s) % 1.0) - 0.5)  # 1 at the start of each cycle, 0 at its middle
        f[seg] = level + breathing(t[seg]) + amp * (1.0 - triangle)
        now += press
        sweep = rng.uniform(5.0, 20.0)
        seg, s = at(now, sweep)
        ripple = sum(rng.uniform(0.1, 0.4) * np.sin(2.0 * np.pi * rng.uniform(0.5, 4.0) * s + rng.uniform(0.0, 6.3))
                     for _ in range(3))
        f[seg] = level + breathing(t[seg]) + ripple * quintic(s / 0.5)
        for catch in rng.uniform(0.0, sweep, int(rng.integers(0, 4))):
            build = rng.uniform(0.3, 1.0)
            cseg, cs = at(now + catch, build + 0.05)
            f[cseg] += rng.uniform(0.3, 1.0) * np.where(cs < build, cs / build, 1.0 - (cs - build) / 0.05)
        now += sweep
        last = float(f[min(np.searchsorted(t, now) - 1, t.size - 1)])
        lift = rng.uniform(0.3, 1.0)
        seg, s = at(now, lift)
        f[seg] = last * (1.0 - quintic(s / lift))
        now += lift + rng.uniform(3.0, 15.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


GRADES = {1: (0.0, 0.05, 0.1, 0.2), 2: (0.1, 0.2, 0.5, 0.7), 3: (0.3, 0.4, 0.9, 1.0), 4: (0.8, 0.85, 0.95, 1.0)}


def spinal_mobilisation(duration_s, rate_hz, rng):
    """A physiotherapy robot mobilising a lumbar segment (the sensor behind its pisiform contact). Each set: a preload
    of 0.5-2 N reached in 1-2 s, then Maitland oscillations of one grade for 15-40 s at 0.5-2.5 Hz (the rate wandering
    by 10 %): the displacement, as a share of the available range, between the grade's bounds (I small at its start,
    II large in its middle, III large to its end, IV small at its end), the force the preload plus 4-8 N times the
    share to the power 1.5-2.5 (the segment stiffens toward the end of its range). One set in three ends with a
    high-velocity thrust from the end of the range (1-2.5 N more in 80-150 ms). Release in 0.5-1 s, 5-20 s of rest."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    at = window(t)
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 25.0:
        preload, rise = rng.uniform(0.5, 2.0), rng.uniform(1.0, 2.0)
        span, power = rng.uniform(4.0, 8.0), rng.uniform(1.5, 2.5)
        seg, s = at(now, rise)
        f[seg] = preload * quintic(s / rise)
        now += rise
        low_lo, low_hi, high_lo, high_hi = GRADES[int(rng.integers(1, 5))]
        low, high = rng.uniform(low_lo, low_hi), rng.uniform(high_lo, high_hi)
        length, freq = rng.uniform(15.0, 40.0), rng.uniform(0.5, 2.5)
        seg, s = at(now, length)
        wander = 1.0 + 0.1 * np.sin(2.0 * np.pi * s / rng.uniform(5.0, 15.0))
        cycle = integrate.cumulative_trapezoid(freq * wander, s, initial=0.0) if s.size > 1 else freq * s
        share = low + (high - low) * 0.5 * (1.0 - np.cos(2.0 * np.pi * cycle)) * quintic(s / 1.0) \
            + low * (quintic(s / 1.0) - 1.0)
        f[seg] = preload + span * np.maximum(share, 0.0) ** power
        now += length
        last = float(f[seg][-1]) if s.size else preload
        if rng.random() < 1.0 / 3.0:
            end_n = preload + span * high ** power
            seg, s = at(now, 0.5)
            f[seg] = last + (end_n - last) * quintic(s / 0.5)
            now += 0.5
            width, extra = rng.uniform(0.08, 0.15), rng.uniform(1.0, 2.5)
            seg, s = at(now, width)
            f[seg] = end_n + extra * 0.5 * (1.0 - np.cos(2.0 * np.pi * s / width))
            now += width
            last = end_n
        release = rng.uniform(0.5, 1.0)
        seg, s = at(now, release)
        f[seg] = last * (1.0 - quintic(s / release))
        now += release + rng.uniform(5.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (robotic_acupuncture, ultrasound_elastography, spinal_mobilisation)


def temperature(t, rng, step_s=0.5):
    """A sensor on a robot beside a neonatal incubator. The room is 0.5-2 degC below the reference, drifting by up to
    +-0.3 degC over the record. The incubator was switched on 0-150 s before the record; its thermostat heats the air
    toward a set point 2-4 degC above the reference, switching its heater with a band of 0.1-0.25 degC; the heater
    (lag 20-60 s) would take the air 1.5-2.5 times as far above the room as the set point is, with the air's own time
    constant of 100-250 s. Its portholes are opened 2-5 times (10-40 s each: the air then also loses to the room with
    20-60 s). The sensor follows the air with 10-30 s (exact per step of ``step_s``), from 900 s before the record."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-900.0, d + 2.0 * step_s, step_s)
    room = T_REF_C + rng.uniform(-2.0, -0.5) + rng.uniform(-0.3, 0.3) * grid / d
    set_c, band = T_REF_C + rng.uniform(2.0, 4.0), rng.uniform(0.1, 0.25)
    reach = (set_c - float(room[0])) * rng.uniform(1.5, 2.5)
    switched_on = -rng.uniform(0.0, 150.0)
    openings = [(at, rng.uniform(10.0, 40.0)) for at in rng.uniform(-100.0, d, int(rng.integers(2, 6)))]
    porthole = np.zeros(grid.size, dtype=bool)
    for at, length in openings:
        porthole |= (grid >= at) & (grid < at + length)
    heater_keep, air_keep = math.exp(-step_s / rng.uniform(20.0, 60.0)), math.exp(-step_s / rng.uniform(100.0, 250.0))
    open_keep, sensor_keep = math.exp(-step_s / rng.uniform(20.0, 60.0)), math.exp(-step_s / rng.uniform(10.0, 30.0))
    air = sensor = float(room[0])
    heat, on = 0.0, False
    out = np.empty(grid.size)
    for i, (r, g, opened) in enumerate(zip(room.tolist(), grid.tolist(), porthole.tolist())):
        out[i] = sensor
        if g >= switched_on:
            on = air < set_c - band if not on else air < set_c + band
        heat = (reach if on else 0.0) + (heat - (reach if on else 0.0)) * heater_keep
        air = r + heat + (air - r - heat) * air_keep
        if opened:
            air = r + (air - r) * open_keep
        sensor = air + (sensor - air) * sensor_keep
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


def bubble_gated_leak(open_fluidity, blocked_fluidity, open_s, blocked_s, rng, horizon_s=HORIZON_S):
    """x' = A(t) F: the leak of a fluid-filled core, which a gas bubble now and then lodges in and blocks (A switches
    between ``open_fluidity`` and ``blocked_fluidity``, dwells drawn exponentially with the means ``open_s`` and
    ``blocked_s``; the state at the first sample drawn in proportion to them)."""
    edges, states, now = [], [], 0.0
    blocked = rng.random() < blocked_s / (open_s + blocked_s)
    while now < horizon_s:
        edges.append(now)
        states.append(blocked_fluidity if blocked else open_fluidity)
        now += rng.exponential(blocked_s if blocked else open_s)
        blocked = not blocked
    edges, states = np.asarray(edges), np.asarray(states)

    def rule(t, f):
        fluidity = states[np.clip(np.searchsorted(edges, t - t[0], side="right") - 1, 0, states.size - 1)]
        return integrate.cumulative_trapezoid(fluidity * np.maximum(f, 0.0), t, initial=0.0)
    return rule


def regulated_leak(fluidity, regulating_n, order):
    """x' = A F / (1 + (F / F_r)^p)^(1/p): a leak through a pressure-compensated flow regulator, linear in the force
    below its regulating force ``regulating_n``, held at A F_r above it (the corner a p-norm of order ``order``)."""
    def rule(t, f):
        load = np.maximum(f, 0.0)
        rate = fluidity * load / (1.0 + (load / regulating_n) ** order) ** (1.0 / order)
        return integrate.cumulative_trapezoid(rate, t, initial=0.0)
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def blow_off_kelvin(t, f, compliance_v_per_n, tau_s, blow_off_v, fast_s, step_s=0.01):
    """A Kelvin unit (x' = e / ``tau_s``, e = c F - x its deficit) whose dashpot has a blow-off valve: beyond a deficit
    of ``blow_off_v`` the excess bleeds with ``fast_s`` (x' = sign(e) (e_b / tau + (|e| - e_b) / tau_f)). Exact per
    coarse step of ``step_s`` for each regime, from rest."""
    grid, goal = coarse(t, compliance_v_per_n * np.asarray(f, dtype=float), step_s)
    slow, fast = math.exp(-step_s / tau_s), math.exp(-step_s / fast_s)
    floor = blow_off_v * (1.0 - fast_s / tau_s)  # |e| - floor decays with fast_s while the valve is open
    x, out = 0.0, np.empty(grid.size)
    for i, g in enumerate(goal.tolist()):
        out[i] = x
        e = g - x
        if abs(e) > blow_off_v:
            e = math.copysign(max((abs(e) - floor) * fast + floor, blow_off_v), e)
        else:
            e *= slow
        x = g - e
    return np.interp(t, grid, out)


def compacted_foam_kelvin(t, f, compliance_v_per_n, tau0_s, growth, memory_s, step_s=0.01):
    """A Kelvin unit in an open-cell foam (x' = (c F - x) / tau) whose retardation grows as sustained loads compact the
    cells and slow the air's escape: tau = ``tau0_s`` (1 + ``growth`` F_avg / 4 N), F_avg the force averaged with a
    lag of ``memory_s``. Exact per coarse step of ``step_s``, from rest."""
    grid, fg = coarse(t, np.maximum(np.asarray(f, dtype=float), 0.0), step_s)
    keep_avg, avg = math.exp(-step_s / memory_s), 0.0
    x, out = 0.0, np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        out[i] = x
        avg = fi + (avg - fi) * keep_avg
        goal = compliance_v_per_n * fi
        x = goal + (x - goal) * math.exp(-step_s / (tau0_s * (1.0 + growth * avg / 4.0)))
    return np.interp(t, grid, out)


# ----------------------------------------------------------------------------- hysteresis

def peel_front(t, f, threshold_n, spread_n, heal, compliance_v_per_n):
    """c F a: a skin film bonded over the core, peeled back over a share a (0..1) of its bond as the core bulges. The
    front advances once F exceeds ``threshold_n`` + ``spread_n`` a and heals only once F falls below ``heal`` times
    that, so a stays within [(F - F_0) / F_s, (F / h - F_0) / F_s]; the peeled share no longer stiffens the core."""
    f = np.maximum(np.asarray(f, dtype=float), 0.0)
    low = np.clip((f - threshold_n) / spread_n, 0.0, 1.0)
    high = np.clip((f / heal - threshold_n) / spread_n, 0.0, 1.0)
    middle = 0.5 * (low + high)
    share = band_play(middle, middle - low, high - middle)  # max(low, min(high, a))
    return compliance_v_per_n * f * share


def peel_loop_height(threshold_n, spread_n, heal):
    """The largest height (in N times share) of :func:`peel_front`'s loop over a cycle 0 -> 9 N -> 0."""
    grid = np.linspace(0.0, FORCE_MAX_N, 901)
    low = np.clip((grid - threshold_n) / spread_n, 0.0, 1.0)
    high = np.clip((grid / heal - threshold_n) / spread_n, 0.0, 1.0)
    unloading = np.minimum(low[-1], high)
    return float(np.max(grid * (unloading - low)))


class BarkhausenWire(SimOnly):
    """A flux guide of soft-magnetic wire whose domain wall hops between pinning sites (every ``spacing_v`` of the
    input from 0, their pinning radii ``radii_v`` repeating along the wire): the wall at q stays while |x - q| is
    within the radius of its site and hops site by site otherwise; y = x + ``weight`` (q - x)."""

    def __init__(self, spacing_v, radii_v, weight):
        self.d, self.radii, self.w = spacing_v, radii_v.tolist(), weight

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        d, radii, n = self.d, self.radii, len(self.radii)
        k = round(float(x[0]) / d)
        q = np.empty_like(x)
        for i, xi in enumerate(x.tolist()):
            while xi - d * k > radii[k % n]:
                k += 1
            while d * k - xi > radii[k % n]:
                k -= 1
            q[i] = d * k
        return x + self.w * (q - x)


# ----------------------------------------------------------------------------- sensor lag

class OneEuroFilter(SimOnly):
    """The 1-euro filter (Casiez et al. 2012) in the read-out's firmware: an exponential smoother whose cutoff is
    ``min_hz`` + ``beta`` |x'|, the speed x' itself smoothed at ``speed_hz``; per sample, from the first."""

    def __init__(self, min_hz, beta, speed_hz):
        self.min_hz, self.beta, self.speed_hz = min_hz, beta, speed_hz

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        steps = np.diff(t, prepend=t[0]).tolist()
        y, speed, out = float(x[0]), 0.0, np.empty_like(x)
        two_pi = 2.0 * math.pi
        for i, (xi, h) in enumerate(zip(x.tolist(), steps)):
            if h > 0.0:
                a_speed = 1.0 / (1.0 + 1.0 / (two_pi * self.speed_hz * h))
                speed += a_speed * ((xi - y) / h - speed)
                a = 1.0 / (1.0 + 1.0 / (two_pi * (self.min_hz + self.beta * abs(speed)) * h))
                y += a * (xi - y)
            out[i] = y
        return out


def delay_equaliser(delay_s, rc_s):
    """Two first-order all-pass sections ((1 - s T) / (1 + s T))^2 behind an RC of ``rc_s``: an analogue delay
    equaliser, 4 T + rc of delay at low frequencies (T set for ``delay_s`` in all)."""
    lag = max((delay_s - rc_s) / 4.0, 5e-4)
    num = np.polymul([-lag, 1.0], [-lag, 1.0])
    den = np.polymul(np.polymul([lag, 1.0], [lag, 1.0]), [rc_s, 1.0])
    return LinearFilter(num.tolist(), den.tolist())


# ----------------------------------------------------------------------------- nonlinear gain

def reflected_power(u):
    """The power two side-by-side fibres exchange through a mirror at the gap u (in units of the gap of the peak),
    normalised to 1 there: u^-2 exp(1 - u^-2) (a Gaussian beam spreading with the gap, collected off its axis)."""
    u = np.maximum(np.asarray(u, dtype=float), 1e-3)
    return u ** -2.0 * np.exp(1.0 - u ** -2.0)


def calibrated(read, rel, reach, k_max):
    """``read(x, k)`` with the k in (0, ``k_max``] for which its largest departure from x over [0, ``reach``] is
    ``rel`` of ``reach`` (``k_max`` when even that departs less)."""
    probe = np.linspace(0.0, reach, 201)

    def excess(k):
        return float(np.max(np.abs(read(probe, k) - probe))) / reach - rel
    if excess(k_max) <= 0.0:
        k = k_max
    else:
        grid = np.geomspace(k_max * 1e-4, k_max, 80)
        j = next(i for i, g in enumerate(grid) if excess(g) > 0.0)
        k = grid[0] if j == 0 else optimize.brentq(excess, grid[j - 1], grid[j])
    return lambda x: read(x, k)


def fibre_reflective(rel, reach, u0, closing):
    """x read as the power a fibre-optic reflective probe receives (:func:`reflected_power`), the load moving the
    gap from ``u0`` (closing it on the front slope, opening it on the back one: monotone for any load); slope 1 at
    zero."""
    sign = -1.0 if closing else 1.0
    p0 = float(reflected_power(u0))
    slope0 = 2.0 * math.exp(1.0 - u0 ** -2) * u0 ** -5 * (1.0 - u0 * u0)  # dP/du at u0

    def read(x, k):
        return (reflected_power(u0 + sign * k * np.asarray(x, dtype=float)) - p0) / (sign * k * slope0)
    k_max = (u0 - 0.05) / reach if closing else 20.0 / reach
    return calibrated(read, rel, reach, k_max)


def bragg_edge(rel, reach, z0):
    """x read through an edge filter by the power a fibre Bragg grating passes: the filter a Gaussian of its
    wavelength, exp(-z^2 / 2), the grating at ``z0`` widths from its centre and moving away from it with the load
    (monotone for any load); slope 1 at zero."""
    t0, slope0 = math.exp(-0.5 * z0 * z0), -z0 * math.exp(-0.5 * z0 * z0)

    def read(x, k):
        z = z0 + k * np.asarray(x, dtype=float)
        return (np.exp(-0.5 * z * z) - t0) / (k * slope0)
    return calibrated(read, rel, reach, 4.0 / reach)


# ----------------------------------------------------------------------------- thermal drift

def fluoropolymer_zero(t, temp, k_v_per_c, quantile, width_c, jump_c, lag_s):
    """k (T_s - T_ref + J (logistic((T_s - T_tr) / w) - logistic((T_ref - T_tr) / w))): a fluoropolymer spacer whose
    crystalline transition (at the ``quantile`` of its temperature T_s over the record, lag ``lag_s``) adds an
    expansion worth ``jump_c`` degC of its linear one."""
    body = follow(t, temp, lag_s)
    tr = float(np.quantile(body, quantile))
    step = logistic((body - tr) / width_c) - float(logistic((T_REF_C - tr) / width_c))
    return k_v_per_c * (body - T_REF_C + jump_c * step)


def fan_switched_zero(t, temp, k_v_per_c, quantile, band_c, fan_s, still_s, step_s=0.5):
    """k (T_b - T_ref): a thermal zero whose body T_b follows the air with ``fan_s`` while the incubator's fan runs
    (the air below its set point, at the ``quantile`` of the air's temperature over the record, switching with
    ``band_c``) and with ``still_s`` otherwise. Exact per coarse step of ``step_s``, settled at the start."""
    grid, tg = coarse(t, temp, step_s)
    set_c = float(np.quantile(tg, quantile))
    fan_keep, still_keep = math.exp(-step_s / fan_s), math.exp(-step_s / still_s)
    body, fan, out = float(tg[0]), True, np.empty(grid.size)
    for i, air in enumerate(tg.tolist()):
        out[i] = body
        fan = air < set_c + band_c if fan else air < set_c - band_c
        body = air + (body - air) * (fan_keep if fan else still_keep)
    return k_v_per_c * (np.interp(t, grid, out) - T_REF_C)


# ----------------------------------------------------------------------------- thermal sensitivity

class MagnetSpan(SimOnly):
    """A magnetic read-out whose bonded magnet (temperature lag ``lag_s``) loses remanence reversibly, the span
    1 + ``coefficient`` (T_m - T_ref), and irreversibly whenever it is warmed past the warmest it has been (starting
    ``above_c`` above its first temperature): times 1 - ``loss`` |coefficient| (M - M_0), M that running maximum."""

    def __init__(self, coefficient, loss, lag_s, above_c):
        self.a, self.loss, self.lag, self.above = coefficient, loss, lag_s, above_c

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        magnet = follow(t, temp_of(aux, t.size), self.lag)
        start = float(magnet[0]) + self.above
        warmest = np.maximum.accumulate(np.maximum(magnet, start))
        span = (1.0 + self.a * (magnet - T_REF_C)) * (1.0 - self.loss * abs(self.a) * (warmest - start))
        return np.asarray(x, dtype=float) * span


class BinnedSpanTable(SimOnly):
    """A polymer span 1 + ``coefficient`` (T_c - T_ref) (the core lagging by ``lag_s``) that firmware corrects by a
    table indexed by the thermometer's reading rounded to bins of ``bin_c`` (from ``phase_c``): it divides by
    1 + ``applied`` (T_bin - T_ref), T_bin the bin's centre."""

    def __init__(self, coefficient, applied, lag_s, bin_c, phase_c):
        self.a, self.applied, self.lag, self.bin, self.phase = coefficient, applied, lag_s, bin_c, phase_c

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        temp = temp_of(aux, t.size)
        centre = T_REF_C + self.phase + self.bin * np.round((temp - T_REF_C - self.phase) / self.bin)
        span = (1.0 + self.a * (follow(t, temp, self.lag) - T_REF_C)) / (1.0 + self.applied * (centre - T_REF_C))
        return np.asarray(x, dtype=float) * span


# ----------------------------------------------------------------------------- offset drift

def heading_moves(rng, horizon_s=HORIZON_S):
    """The tool's heading in rad as a function of the seconds since the first sample: minimum-jerk turns of 20-120
    degrees either way, 1-4 s long, every 10-50 s."""
    moves, now, heading = [], rng.uniform(0.0, 30.0), 0.0
    while now < horizon_s:
        length = rng.uniform(1.0, 4.0)
        goal = heading + math.radians(rng.uniform(20.0, 120.0)) * rng.choice([-1.0, 1.0])
        moves.append((now, length, heading, goal))
        heading = goal
        now += length + rng.uniform(10.0, 50.0)

    def at(s):
        out = np.zeros_like(np.asarray(s, dtype=float))
        for start, length, before, goal in moves:
            out = np.where(s >= start, before + (goal - before) * quintic((s - start) / length), out)
        return out
    return at


def bubble_sawtooths(rng, horizon_s=HORIZON_S):
    """sum_i w_i a_i(s): gas bubbles that electrolysis grows on 3-8 saline-wetted pads, each covering its pad as it
    grows (a_i rising linearly over a life of 0.6-1.4 times the site's mean of 10-60 s) and detaching (a_i back to 0)."""
    sites = []
    for _ in range(int(rng.integers(3, 9))):
        mean_s = rng.uniform(10.0, 60.0)
        lives = mean_s * rng.uniform(0.6, 1.4, int(horizon_s / (0.6 * mean_s)) + 3)
        births = np.cumsum(lives) - lives - rng.uniform(0.0, lives[0])  # the first bubble already growing
        sites.append((births, lives, rng.uniform(0.3, 1.0)))

    def covered(s):
        s = np.asarray(s, dtype=float)
        out = np.zeros_like(s)
        for births, lives, weight in sites:
            k = np.clip(np.searchsorted(births, s, side="right") - 1, 0, births.size - 1)
            out += weight * np.clip((s - births[k]) / lives[k], 0.0, 1.0)
        return out
    first = float(covered(np.array([0.0]))[0])
    return lambda s: covered(s) - first


# ----------------------------------------------------------------------------- resonance

def switched_mode(t, x, w_rad_s, zeta, sub=4):
    """A base-excited mode, y'' + 2 zeta w (y' - x') + w^2 (y - x) = 0, whose ``w_rad_s`` and ``zeta`` (arrays, one
    value per sample of the uniform grid at the median step, or scalars) change with time; semi-implicit Euler with
    ``sub`` sub-steps, from rest, read back at ``t``."""
    tu, xu, h = uniform_grid(t, x)
    rate = np.gradient(xu, h)
    w = np.broadcast_to(np.interp(tu, t, np.broadcast_to(w_rad_s, t.shape)), tu.shape)
    z = np.broadcast_to(np.interp(tu, t, np.broadcast_to(zeta, t.shape)), tu.shape)
    dt = h / sub
    y, v, out = float(xu[0]), 0.0, np.empty(tu.size)
    for i, (xi, ri, wi, zi) in enumerate(zip(xu.tolist(), rate.tolist(), w.tolist(), z.tolist())):
        c, k = 2.0 * zi * wi, wi * wi
        for _ in range(sub):
            v += (-c * (v - ri) - k * (y - xi)) * dt
            y += v * dt
        out[i] = y
    return np.interp(t, tu, out)


class GyroscopicWhirl(SimOnly):
    """The bending mode of a spinning burr seen through its holder: at ``f0_hz`` at rest; while it spins
    (``sessions``, from the first sample) split into a forward and a backward whirl at f0 (1 +- ``split`` / 2), each
    carrying half of the response."""

    def __init__(self, f0_hz, zeta, split, sessions):
        self.w0, self.zeta, self.split, self.sessions = 2.0 * math.pi * f0_hz, zeta, split, sessions

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        spin = within(t - t[0], self.sessions) * 0.5 * self.split
        return 0.5 * (switched_mode(t, x, self.w0 * (1.0 + spin), self.zeta)
                      + switched_mode(t, x, self.w0 * (1.0 - spin), self.zeta))


class SwitchedDamperMode(SimOnly):
    """A holder's mode at ``f0_hz`` under a semi-active (magnetorheological) damper that the controller switches on
    while the robot moves (``sessions``): the damping ratio ``zeta`` times ``boost`` (at most 0.5) then."""

    def __init__(self, f0_hz, zeta, boost, sessions):
        self.w0, self.zeta, self.boost, self.sessions = 2.0 * math.pi * f0_hz, zeta, boost, sessions

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        moving = within(t - t[0], self.sessions)
        return switched_mode(t, x, self.w0, np.where(moving, min(self.zeta * self.boost, 0.5), self.zeta))


# ----------------------------------------------------------------------------- friction

def eccentric_leadscrew(band_n, depth, turn_n, phase):
    """A Coulomb band on the force passed through a lead-screw stage whose nut's preload changes once per turn: the
    band times 1 + ``depth`` sin(2 pi travel / ``turn_n`` + ``phase``), the travel that of the applied force (the stage
    follows it through the tissue)."""
    def passed(t, f):
        travel = np.cumsum(np.abs(np.diff(f, prepend=f[0])))
        band = band_n * (1.0 + depth * np.sin(2.0 * np.pi * travel / turn_n + phase))
        return band_play(f, band, band)
    return passed


def cage_creep(band_n, rolling, free_n):
    """The force passed through a linear ball guide whose cage creeps: while the cage is off its end stops the balls
    roll, a band of ``rolling`` times ``band_n``; the cage moves by half the slip and stops ``free_n`` either side of
    where it started, after which the guide slides with the full band until the slip reverses."""
    def passed(t, f):
        p, cage, out = float(f[0]), 0.0, np.empty(f.size)
        roll = band_n * rolling
        for i, fi in enumerate(f.tolist()):
            band = band_n if abs(cage) >= free_n else roll
            q = max(fi - band, min(fi + band, p))
            cage = max(-free_n, min(free_n, cage + 0.5 * (q - p)))
            p = q
            out[i] = p
        return out
    return passed


# ----------------------------------------------------------------------------- thermo-rheological

class CompressedFoamClock(SimOnly):
    """A foam core on the Arrhenius clock exp(b (T_c - T_ref)), its temperature T_c following the air with a lag of
    ``free_s`` that the load shortens (the cells' air squeezed out, the contact closed): free_s / (1 + (g - 1)
    min(F / 5 N, 1)). Exact per coarse step of 0.5 s at the step's force, settled at the start."""

    def __init__(self, c, b_per_c, free_s, gain):
        self.c, self.b, self.free, self.gain = c, b_per_c, free_s, gain

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        grid, tg = coarse(t, temp_of(aux, t.size), 0.5)
        fg = np.interp(grid, t, f)
        core, out = float(tg[0]), np.empty(grid.size)
        for i, (air, fi) in enumerate(zip(tg.tolist(), fg.tolist())):
            out[i] = core
            tau = self.free / (1.0 + (self.gain - 1.0) * min(max(fi, 0.0) / 5.0, 1.0))
            core = air + (core - air) * math.exp(-0.5 / tau)
        return on_clock(self.c, t, f, np.exp(self.b * (np.interp(t, grid, out) - T_REF_C)))


class DuctedAirClock(SimOnly):
    """A core on the Arrhenius clock exp(b (T_c - T_ref)) that the incubator's air reaches through a duct: a transport
    delay of ``delay_s``, then a lag of ``lag_s``."""

    def __init__(self, c, b_per_c, delay_s, lag_s):
        self.c, self.b, self.delay, self.lag = c, b_per_c, delay_s, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        core = follow(t, dead_time(t, np.asarray(temp_of(aux, t.size), dtype=float), self.delay), self.lag)
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(self.b * (core - T_REF_C)))


# ----------------------------------------------------------------------------- outside the catalogue

def scalpel_alias(activations, wander, step_s, carrier_hz=55_500.0):
    """A harmonic scalpel's blade (``carrier_hz`` plus a wander of its frequency under load, ``wander`` in Hz on a grid
    of ``step_s`` from the first sample) picked up during its activations (start, length, level) and sampled without
    an anti-alias filter: the tone lands wherever the record's rate folds it. Each activation ramps in and out over
    50 ms."""
    def at(t):
        s = t - t[0]
        drift = integrate.cumulative_trapezoid(np.interp(s, step_s * np.arange(wander.size), wander), s, initial=0.0)
        phase = 2.0 * np.pi * (np.mod(carrier_hz * s, 1.0) + drift)
        level = np.zeros_like(s)
        for start, length, amp in activations:
            level += amp * quintic((s - start) / 0.05) * (1.0 - quintic((s - start - length) / 0.05))
        return level * np.sin(phase)
    return at


class IdleTones(SimOnly):
    """The idle tones of a first-order sigma-delta modulator leaking through a weak decimation filter: a tone of
    ``amp_v`` whose frequency, a share 0.02-0.45 of the record's rate, follows the input as a triangle of it with a
    period of ``period_v``."""

    def __init__(self, amp_v, period_v, phase):
        self.amp, self.period, self.phase = amp_v, period_v, phase

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        rate = 1.0 / float(np.median(np.diff(t)))
        level = np.abs(np.mod(x / self.period + self.phase, 1.0) - 0.5) * 2.0  # a triangle of the input, 0..1
        freq = rate * (0.02 + 0.43 * level)
        return x + self.amp * np.sin(2.0 * np.pi * integrate.cumulative_trapezoid(freq, t, initial=0.0))


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([6e4, 4e3]))))  # V / (N s)
        if shape == "bubble_gated_leak":
            rule = bubble_gated_leak(phi * rng.uniform(1.0, 2.5), phi * rng.uniform(0.05, 0.3), rng.uniform(8.0, 60.0),
                                     rng.uniform(5.0, 40.0), rng)
            return Parts("zener", ZenerWithFlow(c, rule), core_changed=True)
        rule = regulated_leak(phi * rng.uniform(1.0, 2.0), rng.uniform(1.5, 4.0), rng.uniform(2.0, 4.0))
        return Parts("zener", ZenerWithFlow(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        compliance = float(np.interp(m, [0, 1], [0.03, 0.2])) / g0  # V / N: a share of the instantaneous response
        if shape == "blow_off_kelvin":
            tau = rng.uniform(2.0, 20.0)
            a = (compliance, tau, compliance * rng.uniform(0.3, 1.5), tau / rng.uniform(5.0, 20.0))
            p.extra.append(lambda t, f, T, a=a: blow_off_kelvin(t, f, *a))
            return p
        a = (compliance, rng.uniform(0.5, 5.0), rng.uniform(1.5, 5.0), rng.uniform(30.0, 120.0))
        p.extra.append(lambda t, f, T, a=a: compacted_foam_kelvin(t, f, *a))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.01, 0.06]))
        if shape == "peel_front":
            threshold, spread, heal = rng.uniform(0.0, 1.0), rng.uniform(3.0, 8.0), rng.uniform(0.3, 0.7)
            compliance = frac * top / max(peel_loop_height(threshold, spread, heal), 1e-9)
            p.extra.append(lambda t, f, T, a=(threshold, spread, heal, compliance): peel_front(t, f, *a))
            return p
        mean = top * rng.uniform(0.04, 0.12)
        weight = frac * top / (2.0 * mean)
        if weight > 0.8:  # wider pinning, lighter coupling: the output never runs backwards
            mean, weight = mean * weight / 0.8, 0.8
        spacing = top * rng.uniform(0.01, 0.03)
        radii = mean * rng.uniform(0.3, 1.7, int(rng.integers(60, 120)))
        return Parts("burgers", c, after=[BarkhausenWire(spacing, radii, weight)])
    if effect == "sensor_lag":
        delay = float(np.interp(m, [0, 1], [0.012, 0.09]))
        if shape == "one_euro_filter":
            rest_s = delay * rng.uniform(1.3, 2.0)
            min_hz = 1.0 / (2.0 * math.pi * rest_s)
            beta = (rng.uniform(3.0, 10.0) - 1.0) * min_hz / top  # the cutoff k-fold at a speed of top per second
            p.after.append(OneEuroFilter(min_hz, beta, rng.uniform(1.0, 5.0)))
            return p
        p.after.append(delay_equaliser(delay * rng.uniform(0.8, 1.2), rng.uniform(0.001, 0.003)))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.05, 0.16]))
        if shape == "fibre_reflective":
            closing = rng.random() < 0.5
            u0 = rng.uniform(0.55, 0.85) if closing else rng.uniform(1.05, 2.0)
            p.after.append(StaticMap(fibre_reflective(rel, top, u0, closing)))
            return p
        p.after.append(StaticMap(bragg_edge(rel, top, rng.uniform(0.3, 2.0))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.022]) * rng.choice([-1, 1]))
        if shape == "fluoropolymer_transition":
            a = (k, rng.uniform(0.3, 0.7), rng.uniform(0.3, 0.8), rng.uniform(1.0, 3.0), rng.uniform(5.0, 20.0))
            p.extra.append(lambda t, f, T, a=a: fluoropolymer_zero(t, T, *a))
            return p
        a = (k, rng.uniform(0.6, 0.85), rng.uniform(0.1, 0.3), rng.uniform(5.0, 15.0), rng.uniform(40.0, 120.0))
        p.extra.append(lambda t, f, T, a=a: fan_switched_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.006, 0.016]))
        if shape == "magnet_irreversible_loss":
            p.after.append(MagnetSpan(-a, rng.uniform(0.3, 1.0), rng.uniform(5.0, 20.0), rng.uniform(0.0, 1.5)))
            return p
        a = float(np.interp(m, [0, 1], [0.008, 0.02]))  # a softer polymer than the magnet's binder
        p.after.append(BinnedSpanTable(a, a * rng.uniform(0.6, 1.4), rng.uniform(5.0, 20.0), rng.uniform(1.5, 3.0),
                                       rng.uniform(-0.5, 0.5)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.012, 0.08]) * rng.choice([-1, 1]))
        if shape == "geomagnetic_heading":
            heading, reference = heading_moves(rng), rng.uniform(0.0, 2.0 * np.pi)
            zero = normalised(lambda s, h=heading, r=reference: np.cos(h(s) - r) - math.cos(r), size)
            p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
            return p
        zero = normalised(bubble_sawtooths(rng), size)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.03, 0.008])) * rng.uniform(0.8, 1.2)
        if shape == "gyroscopic_whirl":
            p.after.append(GyroscopicWhirl(rng.uniform(18.0, 45.0), zeta, rng.uniform(0.03, 0.12),
                                           schedule(rng, (15.0, 60.0), (5.0, 30.0))))
            return p
        p.after.append(SwitchedDamperMode(rng.uniform(15.0, 40.0), zeta, rng.uniform(8.0, 20.0),
                                          schedule(rng, (5.0, 25.0), (1.0, 5.0))))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "eccentric_leadscrew":
            p.before.append(ForcePath(eccentric_leadscrew(r, rng.uniform(0.3, 0.7), rng.uniform(2.0, 10.0),
                                                          rng.uniform(0.0, 2.0 * np.pi))))
            return p
        p.before.append(ForcePath(cage_creep(r, rng.uniform(0.1, 0.3), rng.uniform(0.2, 1.5))))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.1, 0.3]))
        if shape == "compressed_foam_clock":
            return Parts("burgers", CompressedFoamClock(c, b, rng.uniform(60.0, 200.0), rng.uniform(3.0, 8.0)),
                         core_changed=True)
        return Parts("burgers", DuctedAirClock(c, b, rng.uniform(10.0, 40.0), rng.uniform(5.0, 20.0)),
                     core_changed=True)
    if effect == "scalpel_alias":
        n = int(rng.integers(5, 16))
        activations = list(zip(rng.uniform(0.0, HORIZON_S, n), rng.uniform(2.0, 10.0, n), rng.uniform(0.5, 1.0, n)))
        step, corr = 0.05, rng.uniform(0.2, 2.0)  # the blade's frequency wanders as its load changes
        keep = math.exp(-step / corr)
        kicks = rng.normal(0.0, math.sqrt(1.0 - keep * keep), int(HORIZON_S / step) + 2)
        wander = np.empty(kicks.size)
        wander[0] = kicks[0]
        for i in range(1, kicks.size):
            wander[i] = wander[i - 1] * keep + kicks[i]
        wander *= rng.uniform(50.0, 300.0)
        amp, tone = float(np.interp(m, [0, 1], [0.006, 0.06])), scalpel_alias(activations, wander, step)
        p.extra.append(lambda t, f, T, u=tone, amp=amp: amp * u(t))
        return p
    if effect == "sigma_delta_idle_tones":
        p.after.append(IdleTones(float(np.interp(m, [0, 1], [0.003, 0.02])), rng.uniform(0.02, 0.08),
                                 rng.uniform(0.0, 1.0)))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["bubble_gated_leak", "regulated_leak"],
    "delayed_elasticity": ["blow_off_kelvin", "compacted_foam_kelvin"],
    "hysteresis": ["peel_front", "barkhausen_wire"],
    "sensor_lag": ["one_euro_filter", "delay_equaliser"],
    "nonlinear_gain": ["fibre_reflective", "bragg_edge"],
    "thermal_drift": ["fluoropolymer_transition", "fan_switched_lag"],
    "thermal_sensitivity": ["magnet_irreversible_loss", "binned_span_table"],
    "offset_drift": ["geomagnetic_heading", "electrolytic_bubbles"],
    "resonance": ["gyroscopic_whirl", "switched_mr_damper"],
    "friction": ["eccentric_leadscrew", "cage_creep"],
    "thermo_rheological": ["compressed_foam_clock", "ducted_air_clock"],
}
PAIRS = (("viscous_flow", "thermal_drift"), ("delayed_elasticity", "friction"), ("hysteresis", "thermal_sensitivity"),
         ("sensor_lag", "thermo_rheological"), ("nonlinear_gain", "resonance"), ("offset_drift", "hysteresis"))
OUTSIDE = ("scalpel_alias", "sigma_delta_idle_tones")
RATES = (130.0, 430.0, 570.0, 970.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split T", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8),
                   pair_shapes=(-1, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.0e-3, 2.3e-3), jitter=0.3,
                   gap_s=(0.3, 2.2))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
