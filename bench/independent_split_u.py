"""Independent split U for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split U is an untouched held-out set: written before the engine it measures and blind to it (to how it detects and
fits anything), run once at its end, never used to choose anything. Every name of the catalogue is hidden in two
shapes that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A to T use:

* a core packed with a thixotropic grease that has a yield force (Coussot's viscosity bifurcation: it flows at 1-2
  times the plain fluidity of 1/60000-1/8000 V/(N s) times the force above its yield, the yield 0.5-2.5 N times its
  structure; the flow breaks the structure down, an e-fold per what 2-10 s of flow under 1 N gives, and rest rebuilds
  it over 20-120 s: no flow under light loads after a rest, an avalanche once it yields; it never recovers), or a
  hydraulic core leaking past a relief valve (open once the force passes its cracking force of 1-3 N, reseated only
  below 50-85 % of it; the leak 1-2 times the plain fluidity open, a seep of 0-30 % of it shut);
* the core's foot, a rounded (Hertzian) button, indenting a thin Kelvin-Voigt pad (Lee-Radok: the indentation to the
  power 3/2 follows the force through the pad's retarded compliance, 1-20 s, so the creep settles as the force to
  the power 2/3: as large as 3-20 % of the instantaneous response at a force of 2-5 N, relatively larger at light
  loads), or a fluid-filled core connected through a capillary to a gas-charged bladder (precharged to what 2-8 N
  gives: the fluid that the force pushes into it compresses the gas by Boyle's law, so the creep saturates as
  P0 F / (P0 + F), 3-20 % of the instantaneous response at light loads, and runs faster under load, its 3-30 s at
  rest shortened by (P0 / (P0 + p))^2);
* a magnetoresistive read-out whose free layer is an ensemble of 40-80 single-domain (Stoner-Wohlfarth) grains,
  easy axes 5-85 degrees from the field of the core's magnet, which sweeps +-0.75-1 anisotropy fields over the range:
  each grain switches at its astroid field, a stepped loop of 1-6 % of the range on the bridge voltage (the firmware
  linearises the mean curve), or a stack of disc (Belleville) springs beside the core whose interfaces' friction is
  proportional to the load they carry (a loop of 1-6 % of the force, 30-70 % of it below the applied force while
  loading and the rest above it while unloading, stuck in between: it scales with the load and closes at no load);
* an optical read-out whose light reaches a CdS photoresistor (the load brightens or dims it; the cell follows a rise
  of light 2-6 times faster than a fall and faster in brighter light, as its level to the power -0.3-0.7: 12-90 ms
  of mean delay), or a sigma-delta converter's simultaneous 50 and 60 Hz rejection (two moving averages of n x 20 ms
  and n x 16.7 ms, n from the delay of 12-90 ms, behind an anti-alias RC of 1-3 ms);
* the core's push read through an air cushion (a sealed bellows between the core and the gauges' flexure, 1-4 times
  as stiff as it at rest, whose stiffness grows as its air is compressed by Boyle's law: expansive, 5-16 % at the top
  of the range), or a plate clamped between two preloaded Hertzian ball seats, in series with the gauges' flexure
  (the seats 40-70 % of the travel read: stiffer while both seats carry the plate, softer once the far one unloads,
  then stiffening as F^(2/3): expansive with a knee, 5-16 % over 60 % of the range as far as their share allows);
* a sealed reference cavity holding a drop of water from its assembly (its pressure, and so the zero, rises with the
  cavity's temperature (lag 10-40 s) by the gas law and, 30-80 % of it at the reference, by the water's vapour
  pressure, exponential by Magnus: 0.006-0.022 V/degC at the reference), or an oil-filled core whose fill expands
  with its temperature (lag 5-20 s, 0.006-0.022 V/degC) with a pressure transient 50-200 % as large again, which its
  vent bellows relieves over 30-150 s (the zero overshoots each change of temperature);
* a resistive read-out of an ionic hydrogel gauge in a divider (the gel's resistance Arrhenius, 6-12 %/degC lower as
  it warms, lag 5-30 s; the span 4 rho / (1 + rho)^2 peaks where the gel matches the fixed resistor, set 0.6-1.6
  %/degC either side of that at the reference), or an indium antimonide Hall read-out at constant current (its Hall
  coefficient falls as carriers thermally activated across its narrow gap, 1.6-2.6 %/degC, join the donors'
  electrons: the span 0.6-1.6 %/degC lower per degC at the reference, convex; lag 10-40 s);
* the shrinkage stress of a potting compound curing around the amplifier (Kamal's autocatalytic kinetics over
  300-1500 s, the stress building only past the gel point at 30-60 % conversion, reached 150 s before to 250 s into
  the record: flat, then rising, then levelling; 12-80 mV at most), or the stray field of the robot's joint brakes on
  a magnetic read-out (1-3 of six brakes released during each move of 1-6 s every 5-40 s, each with its own
  coupling, the field following through the housing's eddy currents in 0.05-0.5 s, and the housing's steel keeping a
  remanence of 0-30 % of each release: 12-80 mV at most);
* the needle holder's mode (15-35 Hz full) carrying a reservoir of saline that the robot injects in 3-8 boluses of
  1-4 s (25-60 % of the moving mass drained over the record: the frequency and the damping ratio rising as the inverse
  square root of the mass), or a holder in a pneumatic clamp (15-45 Hz at the compressor's cut-out pressure) whose
  contact stiffness follows the clamp's pressure to the power 0.4-1, the pressure leaking away over 30-120 s to
  50-75 % until the compressor refills it in 2-6 s (a sawtooth of the frequency); damping ratio 0.0064-0.036;
* a Coulomb band of 0.4-3.6 % of the range in a haemostatic (Tuohy-Borst) valve on the introducer whose knob is
  tightened or loosened 2-5 times over the record (the band a factor exp(-0.7..0.6) each time, kept within 0.3-2.5
  times its start, over 0.5-2 s), or in a lip seal whose lip inverts at each reversal of the slip (the band 30-100 %
  higher until 0.05-0.3 N of slip has turned the lip over, then the plain band until the slip reverses);
* an Arrhenius clock (0.16-0.72 per degC of its own temperature) on a core wrapped in saline-soaked gauze, which sits
  at the air's wet-bulb temperature (Stull's formula, the air's absolute humidity fixed at 35-60 % relative humidity
  at the reference: the wet bulb moves about 40 % as much as the air; lag 10-40 s), or an Arrhenius clock (30-70 % of
  0.1-0.3 per degC, lag 5-20 s) on a silicone core in a housing with a volatile siloxane, whose vapour pressure
  (7 %/degC) the core absorbs over 40-200 s, plasticising it (the rest of 0.1-0.3 per degC once absorbed).

It also holds six pairs, two effects outside the catalogue (a weighing indicator's automatic zero tracking, which
follows the output toward zero with 1-5 s while it is within 0.35-0.55 N of its zero and moving slower than that band
per 1-3 s, so it eats light holds and what a load leaves behind; brownouts of the sensor's microcontroller as the
robot's motors start a move while the sensor is at rest, 2-4 of 0.2-1.2 s, the output 0 V meanwhile and re-tared at
power-up to read its first value again, so whatever the core still holds from earlier loads is taken for zero) and
four clean records. Profiles: a multi-tine radiofrequency ablation electrode placed under CT guidance through the
measured force-depth curve (``../shared/data``, ``depth_force.csv``, its first insertion stretched over 30-70 mm), in
2-3 advances with check scans, its tines deployed in stages, an ablation hold that the heated tissue relaxes and the
patient's breathing rides, then withdrawn (synthetic layers when the data are absent); a robot harvesting hair
follicles (fast punches with an oscillating cut on a skin tensioner's push, rows between re-tensionings); and a
robot-held pressure algometer (pain-threshold ramps, temporal-summation pulse trains, tonic holds under a force
controller). Rates 150, 340, 530 and 790 Hz (a mode at 1000 Hz with knocks that excite it), 1.0-2.5 mV noise, stamp
jitter, gaps, and a sensor on the electrode holder of a robot for CT-guided radiofrequency ablation, in a CT suite
whose air conditioning cycles, warmed by the heat each ablation conducts up the electrode and its cable.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_u.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, optimize, signal

from polyforce_ros.physics.viscoelastic import simulate_deformation
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (band_play, coarse, cutter as window, ForcePath, kelvin, Parts, quintic,
                       schedule as schedule_until, ShapeSplit, SimOnly, sized, temp_of, uniform_grid, ZenerWithFlow)

SEED0 = 1_450_000  # never a seed of the registry's splits nor of splits A (90000..) to T (1380000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 460.0
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


def rf_ablation(duration_s, rate_hz, rng):
    """A robot placing a multi-tine radiofrequency ablation electrode under CT guidance (the sensor behind its holder).
    The trocar goes in through the measured insertion (``measured_insertion``), stretched over 30-70 mm and scaled to
    a 3-6.5 N peak, at 1-3 mm/s in 2-3 advances; between them the robot holds 3-8 s for a check scan (the force
    relaxing to 60-85 % with 1-3 s, and building back within 0.8 mm of the next advance). At the target the tines are
    deployed in 3-4 stages (each pushes 0.4-1.2 N more in 0.5-1.5 s as they cut out into the tissue, then 1-3 s in
    which 20-40 % of that relaxes with 1-4 s). The ablation holds 25-70 s: the heated tissue softens (the force falling
    to 40-75 % with 10-30 s) and the patient's breathing rides on it (0.1-0.35 N at 0.2-0.3 Hz). The tines retract (the
    force to 50-80 % of the trocar's in 0.5-1 s), the electrode is withdrawn in 1-3 s, and 6-20 s pass before the next
    placement. Made-up layers (``synthetic_insertion``) when ``../shared/data`` is absent."""
    depth_mm, force_n = measured_insertion() or synthetic_insertion(rng)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    at = window(t)
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 40.0:
        goal_mm = rng.uniform(30.0, 70.0)
        stretch = goal_mm / float(depth_mm[-1])
        scale = rng.uniform(3.0, 6.5) / max(float(force_n.max()), 1e-3)

        def resistance(d, stretch=stretch, scale=scale):
            return scale * np.interp(np.asarray(d, dtype=float) / stretch, depth_mm, force_n)
        speed = rng.uniform(1.0, 3.0)
        stops = np.sort(rng.uniform(0.25, 0.85, int(rng.integers(1, 3)))) * goal_mm
        start_mm, deficit = 0.0, 0.0
        for end_mm in [*stops.tolist(), goal_mm]:
            seg, s = at(now, (end_mm - start_mm) / speed)
            d = start_mm + speed * s
            f[seg] = resistance(d) - deficit * np.exp(-(d - start_mm) / 0.8)
            now += (end_mm - start_mm) / speed
            if end_mm < goal_mm:
                level = float(resistance(end_mm))
                hold, keep, tau = rng.uniform(3.0, 8.0), rng.uniform(0.6, 0.85), rng.uniform(1.0, 3.0)
                seg, s = at(now, hold)
                f[seg] = level * (keep + (1.0 - keep) * np.exp(-s / tau))
                now += hold
                deficit = level * (1.0 - keep) * (1.0 - math.exp(-hold / tau))
            start_mm = end_mm
        trocar = float(resistance(goal_mm))
        base = trocar
        for _ in range(int(rng.integers(3, 5))):
            push, rise = rng.uniform(0.4, 1.2), rng.uniform(0.5, 1.5)
            seg, s = at(now, rise)
            f[seg] = base + push * quintic(s / rise)
            now += rise
            settle, lose, tau = rng.uniform(1.0, 3.0), rng.uniform(0.2, 0.4), rng.uniform(1.0, 4.0)
            seg, s = at(now, settle)
            f[seg] = base + push * (1.0 - lose * -np.expm1(-s / tau))
            now += settle
            base += push * (1.0 - lose * -math.expm1(-settle / tau))
        ablate, keep, tau = rng.uniform(25.0, 70.0), rng.uniform(0.4, 0.75), rng.uniform(10.0, 30.0)
        breath_n, breath_hz, phase = rng.uniform(0.1, 0.35), rng.uniform(0.2, 0.3), rng.uniform(0.0, 2.0 * np.pi)
        seg, s = at(now, ablate)
        f[seg] = base * (keep + (1.0 - keep) * np.exp(-s / tau)) \
            + breath_n * np.sin(2.0 * np.pi * breath_hz * s + phase) * quintic(s / 3.0)
        now += ablate
        last = base * (keep + (1.0 - keep) * math.exp(-ablate / tau)) \
            + breath_n * math.sin(2.0 * math.pi * breath_hz * ablate + phase)
        retract, after = rng.uniform(0.5, 1.0), trocar * rng.uniform(0.5, 0.8)
        seg, s = at(now, retract)
        f[seg] = last + (after - last) * quintic(s / retract)
        now += retract
        out = rng.uniform(1.0, 3.0)
        seg, s = at(now, out)
        f[seg] = after * (1.0 - quintic(s / out))
        now += out + rng.uniform(6.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def hair_harvesting(duration_s, rate_hz, rng):
    """A robot harvesting hair follicles (follicular unit extraction; the sensor behind its punch). Each graft: the
    punch meets the scalp (0.3-0.8 N over 80-200 ms), the sharp inner punch pierces it (the force rising to 1.5-4 N in
    60-200 ms, then falling by 30-60 % within 20 ms as it cuts through the epidermis), the blunt outer punch follows
    with an oscillating cut for 0.3-1 s (0.2-0.6 N at 8-20 Hz about 60-90 % of the force left), and both retract in
    80-200 ms; a graft every 1.2-3.5 s. The grafts come in rows of 8-25; between rows, 5-20 s in which the robot
    re-tensions the skin (the tensioner's 0.5-1.5 N on the punch's guide, settling with 0.5-1.5 s, released after)."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    at = window(t)
    now = rng.uniform(1.0, 4.0)
    while now < duration_s - 10.0:
        tension, settle = rng.uniform(0.5, 1.5), rng.uniform(0.5, 1.5)
        row_start = now
        for _ in range(int(rng.integers(8, 26))):
            if now > duration_s - 5.0:
                break
            every = rng.uniform(1.2, 3.5)
            touch, contact = rng.uniform(0.08, 0.2), rng.uniform(0.3, 0.8)
            seg, s = at(now, touch)
            f[seg] = tension + contact * quintic(s / touch)
            pierce, peak = rng.uniform(0.06, 0.2), rng.uniform(1.5, 4.0)
            seg, s = at(now + touch, pierce)
            f[seg] = tension + contact + (peak - contact) * (s / pierce) ** 1.5
            drop = peak * (1.0 - rng.uniform(0.3, 0.6))
            seg, s = at(now + touch + pierce, 0.02)
            f[seg] = tension + peak + (drop - peak) * quintic(s / 0.02)
            cut, amp, freq = rng.uniform(0.3, 1.0), rng.uniform(0.2, 0.6), rng.uniform(8.0, 20.0)
            level = drop * rng.uniform(0.6, 0.9)
            seg, s = at(now + touch + pierce + 0.02, cut)
            f[seg] = tension + drop + (level - drop) * quintic(s / 0.1) + amp * np.sin(2.0 * np.pi * freq * s) ** 2
            back = rng.uniform(0.08, 0.2)
            seg, s = at(now + touch + pierce + 0.02 + cut, back)
            f[seg] = tension + level * (1.0 - quintic(s / back))
            spent = touch + pierce + 0.02 + cut + back
            seg, s = at(now + spent, max(every - spent, 0.0))
            f[seg] = tension
            now += max(every, spent)
        seg, s = at(row_start, now - row_start)
        f[seg] -= tension * np.exp(-s / settle)  # the tensioner settling at the row's start
        seg, s = at(now, 0.5)
        f[seg] = tension * (1.0 - quintic(s / 0.5))
        now += rng.uniform(5.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def pressure_algometry(duration_s, rate_hz, rng):
    """A robot-held pressure algometer on a patient's muscles (a 1 cm^2 probe; the sensor behind it), blocks in random
    order: pressure-pain thresholds (3 ramps at 0.3-1 N/s from a 0.2 N contact until the patient presses the button at
    3-8 N, released in 0.2-0.5 s, 8-20 s of rest between); temporal summation (10 pulses to 2-5.5 N, rising and falling
    in 0.2-0.3 s, held 0.8-1.2 s, one per 1.5-2.5 s); and a tonic pressure (a ramp in 1-3 s to 2-5 N, held 30-90 s by a
    force controller with a 5-15 % overshoot that settles with 0.3-1 s and a ripple of 0.03-0.12 N at 1-4 Hz, then
    released in 0.5-1 s). 5-15 s between blocks."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    at = window(t)
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 20.0:
        kind = int(rng.integers(0, 3))
        if kind == 0:
            for _ in range(3):
                speed, threshold = rng.uniform(0.3, 1.0), rng.uniform(3.0, 8.0)
                seg, s = at(now, 0.3)
                f[seg] = 0.2 * quintic(s / 0.3)
                now += 0.3
                rise = (threshold - 0.2) / speed
                seg, s = at(now, rise)
                f[seg] = 0.2 + speed * s
                now += rise
                release = rng.uniform(0.2, 0.5)
                seg, s = at(now, release)
                f[seg] = threshold * (1.0 - quintic(s / release))
                now += release + rng.uniform(8.0, 20.0)
        elif kind == 1:
            for _ in range(10):
                level, edge, hold, every = rng.uniform(2.0, 5.5), rng.uniform(0.2, 0.3), rng.uniform(0.8, 1.2), \
                    rng.uniform(1.5, 2.5)
                seg, s = at(now, 2.0 * edge + hold)
                f[seg] = level * (quintic(s / edge) - quintic((s - edge - hold) / edge))
                now += max(every, 2.0 * edge + hold + 0.1)
        else:
            level, rise, hold = rng.uniform(2.0, 5.0), rng.uniform(1.0, 3.0), rng.uniform(30.0, 90.0)
            seg, s = at(now, rise)
            f[seg] = level * quintic(s / rise)
            now += rise
            over, settle = rng.uniform(0.05, 0.15), rng.uniform(0.3, 1.0)
            ripple, freq = rng.uniform(0.03, 0.12), rng.uniform(1.0, 4.0)
            seg, s = at(now, hold)
            f[seg] = level * (1.0 + over * np.sin(np.pi * np.minimum(s / (3.0 * settle), 1.0)) * np.exp(-s / settle)) \
                + ripple * np.sin(2.0 * np.pi * freq * s) * quintic(s / 1.0)
            now += hold
            last = float(f[seg][-1]) if s.size else level
            release = rng.uniform(0.5, 1.0)
            seg, s = at(now, release)
            f[seg] = last * (1.0 - quintic(s / release))
            now += release
        now += rng.uniform(5.0, 15.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (rf_ablation, hair_harvesting, pressure_algometry)


def temperature(t, rng, step_s=0.5):
    """A sensor on the electrode holder of a robot for CT-guided radiofrequency ablation. The CT suite's air
    conditioning holds the room 0.5-2.5 degC below the reference, drifting by up to +-0.3 degC over the record, its
    compressor cycling (a triangle of 0.15-0.5 degC peak to peak, period 180-420 s). Ablations of 90-300 s, 60-250 s
    apart (the first starting 400 s before to 150 s into the record), heat the air around the holder (the heat
    conducted up the electrode's shaft and its cable) toward 2-5 degC above the room with 30-90 s; it cools back with
    60-180 s. The sensor follows that air with 10-30 s (exact per step of ``step_s``), from 900 s before the record."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-900.0, d + 2.0 * step_s, step_s)
    period, phase = rng.uniform(180.0, 420.0), rng.uniform(0.0, 1.0)
    cycle = rng.uniform(0.15, 0.5) * (2.0 * np.abs(np.mod(grid / period + phase, 1.0) - 0.5) - 0.5)
    room = T_REF_C + rng.uniform(-2.5, -0.5) + rng.uniform(-0.3, 0.3) * grid / d + cycle
    heating = np.zeros(grid.size, dtype=bool)
    now = rng.uniform(-400.0, 150.0)
    while now < d + 60.0:
        length = rng.uniform(90.0, 300.0)
        heating |= (grid >= now) & (grid < now + length)
        now += length + rng.uniform(60.0, 250.0)
    reach = rng.uniform(2.0, 5.0)
    up_keep, down_keep = math.exp(-step_s / rng.uniform(30.0, 90.0)), math.exp(-step_s / rng.uniform(60.0, 180.0))
    sensor_keep = math.exp(-step_s / rng.uniform(10.0, 30.0))
    heat, sensor = 0.0, float(room[0])
    out = np.empty(grid.size)
    for i, (r, on) in enumerate(zip(room.tolist(), heating.tolist())):
        out[i] = sensor
        heat = reach + (heat - reach) * up_keep if on else heat * down_keep
        sensor = r + heat + (sensor - r - heat) * sensor_keep
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


def forward_fill(values, first):
    """``values`` with each nan replaced by the last value before it (``first`` before any)."""
    known = np.isfinite(values)
    idx = np.maximum.accumulate(np.where(known, np.arange(values.size), -1))
    return np.where(idx >= 0, values[np.maximum(idx, 0)], first)


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


# ----------------------------------------------------------------------------- viscous flow


def thixotropic_grease(fluidity, yield_n, rebuild_s, breakdown_v, step_s=0.02):
    """x' = A (F - lambda Y)+: a grease whose structure lambda (1 at rest) sets its yield force lambda ``yield_n``. The
    flow breaks it down (lambda' = -lambda x' / ``breakdown_v``) and rest rebuilds it (lambda' = (1 - lambda) /
    ``rebuild_s``); per coarse step of ``step_s``, from an intact structure."""
    def rule(t, f):
        grid, fg = coarse(t, np.maximum(f, 0.0), step_s)
        rebuild = -math.expm1(-step_s / rebuild_s)
        lam, x, out = 1.0, 0.0, np.empty(grid.size)
        for i, fi in enumerate(fg.tolist()):
            out[i] = x
            dx = fluidity * max(fi - lam * yield_n, 0.0) * step_s
            x += dx
            lam *= math.exp(-dx / breakdown_v)
            lam += (1.0 - lam) * rebuild
        return np.interp(t, grid, out)
    return rule


def relief_valve_leak(open_fluidity, seep_fluidity, crack_n, reseat, step_s=0.01):
    """x' = A F: the leak of a hydraulic core past a relief valve, A ``open_fluidity`` once the force has passed
    ``crack_n`` and until it falls below ``reseat`` times that, ``seep_fluidity`` otherwise (shut at the start)."""
    def rule(t, f):
        grid, fg = coarse(t, np.maximum(f, 0.0), step_s)
        state = np.full(grid.size, np.nan)
        state[fg <= reseat * crack_n] = 0.0
        state[fg >= crack_n] = 1.0
        fluidity = np.where(forward_fill(state, 0.0) > 0.5, open_fluidity, seep_fluidity)
        return np.interp(t, grid, integrate.cumulative_trapezoid(fluidity * fg, grid, initial=0.0))
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def hertzian_pad(t, f, compliance_v_per_n, ref_n, tau_s):
    """c F_r (K / F_r)^(2/3): a rounded foot indenting a thin Kelvin-Voigt pad (Lee-Radok: the indentation to the power
    3/2 follows the force through the pad's retarded compliance, K = the force through a Kelvin lag ``tau_s``); at
    the force ``ref_n`` the settled creep is ``compliance_v_per_n`` times it."""
    k = kelvin(t, np.maximum(np.asarray(f, dtype=float), 0.0), 1.0, tau_s)
    return compliance_v_per_n * ref_n * (np.maximum(k, 0.0) / ref_n) ** (2.0 / 3.0)


def gas_accumulator(t, f, compliance_v_per_n, precharge_n, tau0_s, step_s=0.01):
    """c P0 p / (P0 + p): the fluid pushed from a core through a capillary into a bladder precharged to ``precharge_n``
    (in units of the force): the bladder's pressure p approaches the force as p' = (F - p) (P0 + p)^2 / (tau0 P0^2)
    (Boyle's law: its compliance falls as it fills). Exact per coarse step of ``step_s`` at the step's rate, from
    rest."""
    grid, fg = coarse(t, np.maximum(np.asarray(f, dtype=float), 0.0), step_s)
    p, out = 0.0, np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        out[i] = p
        tau = tau0_s * (precharge_n / (precharge_n + p)) ** 2
        p = fi + (p - fi) * math.exp(-step_s / tau)
    p = np.interp(t, grid, out)
    return compliance_v_per_n * precharge_n * p / (precharge_n + p)


# ----------------------------------------------------------------------------- hysteresis

def stoner_wohlfarth_upper(psi, h):
    """The magnetisation along the field of Stoner-Wohlfarth grains (easy axes ``psi`` from the field) on the branch
    that comes down from positive saturation, for the fields ``h`` (descending, in anisotropy fields); nan where the
    branch has switched (below minus the astroid's field)."""
    theta = np.zeros_like(psi)
    out = np.full((h.size, psi.size), np.nan)
    h_sw = (np.cos(psi) ** (2.0 / 3.0) + np.sin(psi) ** (2.0 / 3.0)) ** -1.5
    for i, hi in enumerate(h.tolist()):
        for _ in range(8):  # Newton (warm-started from the previous field) on dE/dtheta = sin(2 (theta - psi)) / 2 + h sin(theta)
            g = 0.5 * np.sin(2.0 * (theta - psi)) + hi * np.sin(theta)
            dg = np.cos(2.0 * (theta - psi)) + hi * np.cos(theta)
            theta = theta - g / np.where(np.abs(dg) > 1e-6, dg, 1e-6)
        out[i] = np.where(hi > -h_sw, np.cos(theta), np.nan)
    return out


class StonerWohlfarthGrains(SimOnly):
    """A magnetoresistive read-out whose free layer is an ensemble of Stoner-Wohlfarth grains (easy axes ``psi``), the
    field h = a (2 x / ``reach`` - 1): each grain flips to the upper branch where h passes its astroid field and to the
    lower one where -h does; y = x + ``weight`` (M - M_mean), M_mean the mean of the two branches (what a calibration
    along the mean curve linearises). Before the record a full load (0 -> ``reach`` -> 0) set the states."""

    def __init__(self, psi, half_range, reach, weight):
        self.a, self.reach, self.w = half_range, reach, weight
        self.h = np.linspace(3.0, -3.0, 2401)
        self.upper = stoner_wohlfarth_upper(psi, self.h)
        self.h_sw = (np.cos(psi) ** (2.0 / 3.0) + np.sin(psi) ** (2.0 / 3.0)) ** -1.5
        self.switching = self.h_sw < half_range

    def magnetisation(self, x):
        """The switching grains' mean magnetisation less their mean curve, for the core's outputs ``x``."""
        h = self.a * (2.0 * np.asarray(x, dtype=float) / self.reach - 1.0)
        grid = self.h[::-1]
        total = np.zeros(h.size)
        chosen = np.flatnonzero(self.switching)
        for j in chosen.tolist():
            col = self.upper[::-1, j]
            ok = np.isfinite(col)
            up = np.interp(h, grid[ok], col[ok])  # the last valid value where the branch ends
            low = -np.interp(-h, grid[ok], col[ok])
            state = np.full(h.size, np.nan)
            state[h >= self.h_sw[j]] = 1.0
            state[h <= -self.h_sw[j]] = 0.0
            on = forward_fill(state, 0.0)  # the full load before the record left each grain down
            total += np.where(on > 0.5, up, low) - 0.5 * (up + low)
        return total / max(chosen.size, 1)

    def loop_height(self):
        sweep = np.concatenate([np.linspace(0.0, self.reach, 400), np.linspace(self.reach, 0.0, 400)])
        m = self.magnetisation(sweep)
        return float(np.max(np.abs(m[:400] - m[400:][::-1])))

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        return x + self.w * self.magnetisation(x)


def disc_spring_stack(loading, unloading):
    """The force a core passes beside a stack of disc springs whose interfaces' friction is proportional to the load:
    ``loading`` of the force below it while the force rises, ``unloading`` above it while it falls, stuck between."""
    def passed(t, f):
        load = np.abs(f)
        return band_play(f, loading * load, unloading * load)
    return passed


# ----------------------------------------------------------------------------- sensor lag

class Photoresistor(SimOnly):
    """An optical read-out through a CdS photoresistor: the light L = ``bias`` + x (``brighter``) or ``bias`` +
    ``reach`` - x, at least 5 % of ``bias``; the cell's conductance G follows it with ``tau_rise`` while the light rises,
    ``tau_fall`` while it falls, both times (G / L_mid)^-``power`` (faster in bright light), L_mid the light at half
    the reach; per sample, exact for each step's time constant, settled at the start."""

    def __init__(self, tau_rise, tau_fall, power, bias, reach, brighter):
        self.rise, self.fall, self.p, self.bias, self.reach, self.sign = tau_rise, tau_fall, power, bias, reach, \
            (1.0 if brighter else -1.0)

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        base = self.bias if self.sign > 0 else self.bias + self.reach
        light = np.maximum(base + self.sign * x, 0.05 * self.bias)
        mid = self.bias + 0.5 * self.reach
        steps = np.diff(t, prepend=t[0]).tolist()
        g, out = float(light[0]), np.empty_like(x)
        for i, (li, h) in enumerate(zip(light.tolist(), steps)):
            tau = (self.rise if li > g else self.fall) * (g / mid) ** -self.p
            g = li + (g - li) * math.exp(-h / tau)
            out[i] = g
        return (out - base) / self.sign


class DualMainsRejection(SimOnly):
    """A sigma-delta converter's simultaneous 50 and 60 Hz rejection: moving averages over ``n`` x 20 ms and ``n`` x
    16.7 ms in cascade, behind an anti-alias RC of ``rc_s``; on a uniform grid at the median step, from rest."""

    def __init__(self, n, rc_s):
        self.n, self.rc = n, rc_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        b, a = signal.bilinear([1.0], [self.rc, 1.0], fs=1.0 / h)
        y = signal.lfilter(b, a, xu - xu[0]) + xu[0]
        for length_s in (self.n * 0.02, self.n / 60.0):
            k = max(int(round(length_s / h)), 1)
            padded = np.concatenate([np.full(k, y[0]), y])
            csum = np.cumsum(padded)
            y = (csum[k:] - csum[:-k]) / k
        return np.interp(t, tu, y)


# ----------------------------------------------------------------------------- nonlinear gain

def air_cushion(rel, reach, ratio):
    """x read through an air cushion: the flexure's deflection y under the cushion's force a c / (1 - c / L) (Boyle's
    law; c = x - y its compression, the flexure ``ratio`` times a as stiff), times 1 + ``ratio`` (slope 1 at zero):
    expansive, monotone for any load; L set for a departure of ``rel`` at ``reach``."""
    def read(x, q):
        x = np.asarray(x, dtype=float)
        length = 1.0 / q
        b = ratio * x + ratio * length + length
        c = 2.0 * ratio * x * length / (b + np.sqrt(np.maximum(b * b - 4.0 * ratio * ratio * x * length, 0.0)))
        return (x - c) * (1.0 + ratio)
    return calibrated(read, rel, reach, 1000.0 / reach)


@functools.lru_cache(maxsize=1)
def seat_pair_table(n=4001):
    """The travel of a plate between two Hertzian seats each preloaded by 1: P_A^(2/3) + P_B^(2/3) = 2, P_A - P_B = u,
    travel P_A^(2/3) - 1, for u up to 2^1.5 (where the far seat unloads): (u, travel)."""
    u = np.linspace(0.0, 2.0 ** 1.5, n)
    lo, hi = np.zeros(n), np.ones(n)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        over = (mid + u) ** (2.0 / 3.0) + mid ** (2.0 / 3.0) > 2.0
        hi, lo = np.where(over, mid, hi), np.where(over, lo, mid)
    return u, (0.5 * (lo + hi) + u) ** (2.0 / 3.0) - 1.0


def preloaded_seats(rel, reach, share):
    """x read as the travel of a plate between two preloaded Hertzian seats in series with the gauges' flexure (the
    seats' share of the travel at zero load ``share``; the force in units of the preload, u = k x): (1 - share) x +
    share 3 travel(u) / k (slope 1 at zero); once the far seat unloads, travel = u^(2/3) - 1. Expansive with a knee,
    then stiffening (the departure at most 15.5 % times ``share``); odd in x; the preload set for a departure of
    ``rel`` over [0, ``reach``] (or as near as the share allows)."""
    table_u, table_d = seat_pair_table()

    def travel(u):
        a = np.abs(u)
        inner = np.interp(a, table_u, table_d)
        return np.sign(u) * np.where(a <= table_u[-1], inner, a ** (2.0 / 3.0) - 1.0)

    def read(x, k):
        x = np.asarray(x, dtype=float)
        return (1.0 - share) * x + share * 3.0 * travel(k * x) / k
    return calibrated(read, rel, reach, 5.2 / reach)


# ----------------------------------------------------------------------------- thermal drift

def magnus(temp_c):
    """The saturation vapour pressure of water relative to its value at 0 degC (Magnus)."""
    temp_c = np.asarray(temp_c, dtype=float)
    return np.exp(17.62 * temp_c / (243.12 + temp_c))


def wet_cavity_zero(t, temp, k_v_per_c, vapour_share, lag_s):
    """k ((1 - w) (T_c - T_ref) + w (e_s(T_c) / e_s(T_ref) - 1) / g): a sealed cavity (lag ``lag_s``) holding a drop of
    water, its pressure rising by the gas law and by the water's vapour pressure e_s (g its relative slope at the
    reference, ``vapour_share`` = w of the slope there)."""
    body = follow(t, temp, lag_s)
    slope = 17.62 * 243.12 / (243.12 + T_REF_C) ** 2
    vapour = (magnus(body) / magnus(T_REF_C) - 1.0) / slope
    return k_v_per_c * ((1.0 - vapour_share) * (body - T_REF_C) + vapour_share * vapour)


def oil_fill_zero(t, temp, k_v_per_c, lag_s, vent_s, surge):
    """k (T_o - T_ref + s (T_o - T_v)): an oil fill (lag ``lag_s``) whose expansion pushes the zero, and whose vent
    bellows relieves a transient ``surge`` times as large over ``vent_s`` (T_v the fill's temperature behind that lag)."""
    oil = follow(t, temp, lag_s)
    return k_v_per_c * (oil - T_REF_C + surge * (oil - follow(t, oil, vent_s)))


# ----------------------------------------------------------------------------- thermal sensitivity

class HydrogelDividerSpan(SimOnly):
    """A hydrogel gauge in a divider: the span 4 rho / (1 + rho)^2 (relative to its value at the reference), rho =
    rho0 exp(-``beta`` (T_g - T_ref)) the gel's resistance over the fixed one (Arrhenius), T_g the gel's temperature
    behind ``lag_s``; rho0 = (1 + q) / (1 - q), q = ``coefficient`` / beta, so the span's slope at the reference is
    ``coefficient``."""

    def __init__(self, coefficient, beta, lag_s):
        q = coefficient / beta
        self.beta, self.lag, self.rho0 = beta, lag_s, (1.0 + q) / (1.0 - q)

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        rho = self.rho0 * np.exp(-self.beta * (follow(t, temp_of(aux, t.size), self.lag) - T_REF_C))
        span = 4.0 * rho / (1.0 + rho) ** 2 / (4.0 * self.rho0 / (1.0 + self.rho0) ** 2)
        return np.asarray(x, dtype=float) * span


class IntrinsicHallSpan(SimOnly):
    """An InSb Hall element at constant current: the span (1 + r) / (1 + r exp(``beta`` (T_h - T_ref))), r the thermally
    activated carriers over the donors' at the reference (chosen for a slope of minus ``coefficient`` there), T_h the
    element's temperature behind ``lag_s``."""

    def __init__(self, coefficient, beta, lag_s):
        share = coefficient / beta
        self.beta, self.lag, self.r = beta, lag_s, share / (1.0 - share)

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        hall = follow(t, temp_of(aux, t.size), self.lag)
        span = (1.0 + self.r) / (1.0 + self.r * np.exp(self.beta * (hall - T_REF_C)))
        return np.asarray(x, dtype=float) * span


# ----------------------------------------------------------------------------- offset drift

def potting_cure(rng, horizon_s=HORIZON_S):
    """The shrinkage stress of a potting compound curing around the amplifier (Kamal: da/du = (k1 + a^m) (1 - a)^n, u
    the time over 300-1500 s, k1 0.01-0.1, m 0.5-1, n 1-2), building only past the gel point (a 0.3-0.6), reached 150 s
    before to 250 s after the first sample; as a function of the seconds since the first sample, zero there."""
    scale, k1, m, n = rng.uniform(300.0, 1500.0), rng.uniform(0.01, 0.1), rng.uniform(0.5, 1.0), rng.uniform(1.0, 2.0)
    gel, gel_at = rng.uniform(0.3, 0.6), rng.uniform(-150.0, 250.0)
    u = np.linspace(0.0, 40.0, 40001)
    a, alpha = 0.0, np.empty(u.size)
    for i in range(u.size):
        alpha[i] = a
        a = min(a + (k1 + a ** m) * (1.0 - a) ** n * (u[1] - u[0]), 1.0)
    u_gel = float(np.interp(gel, alpha, u))
    stress = np.maximum(alpha - gel, 0.0) / (1.0 - gel)

    def at(s):
        return np.interp((np.asarray(s, dtype=float) - gel_at) / scale + u_gel, u, stress)
    first = float(at(np.array([0.0]))[0])
    return lambda s: at(s) - first


def brake_coils(rng, horizon_s=HORIZON_S):
    """The stray field of the robot's joint brakes: six brakes with couplings drawn from a normal law; during each move
    (1-6 s every 5-40 s) 1-3 of them are released, their field following through the housing's eddy currents with
    0.05-0.5 s, and the housing keeps a remanence of 0-30 % of that move's field, either sign, from its end on."""
    coupling, eddy = rng.normal(0.0, 1.0, 6), rng.uniform(0.05, 0.5)
    moves = []
    for start, length in schedule(rng, (5.0, 40.0), (1.0, 6.0), horizon_s=horizon_s):
        level = float(np.sum(coupling[rng.choice(6, int(rng.integers(1, 4)), replace=False)]))
        moves.append((start, length, level, level * rng.uniform(0.0, 0.3) * rng.choice([-1.0, 1.0])))

    def field(s):
        s = np.asarray(s, dtype=float)
        out = np.zeros_like(s)
        for start, length, level, kept in moves:
            since, after = s - start, s - start - length
            grown = -np.expm1(-np.clip(since, 0.0, length) / eddy)
            out += np.where(since > 0.0, level * grown * np.exp(-np.maximum(after, 0.0) / eddy), 0.0)
            out += kept * -np.expm1(-np.maximum(after, 0.0) / eddy)
        return out
    first = float(field(np.array([0.0]))[0])
    return lambda s: field(s) - first


# ----------------------------------------------------------------------------- resonance

def switched_mode(t, x, w_rad_s, zeta, sub=4):
    """A base-excited mode, y'' + 2 zeta w (y' - x') + w^2 (y - x) = 0, whose ``w_rad_s`` and ``zeta`` (arrays, one
    value per sample of ``t``, or scalars) change with time; semi-implicit Euler with ``sub`` sub-steps on the uniform
    grid at the median step, from rest, read back at ``t``."""
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


class DrainingReservoirMode(SimOnly):
    """A holder's mode at ``f0_hz`` (damping ratio ``zeta``) when its saline reservoir is full; each bolus (start,
    length, share) drains a share of the moving mass over its length (a quintic): w and zeta grow as the inverse square
    root of the mass left."""

    def __init__(self, f0_hz, zeta, boluses):
        self.w0, self.zeta, self.boluses = 2.0 * math.pi * f0_hz, zeta, boluses

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        s = t - t[0]
        mass = 1.0 - sum(share * quintic((s - start) / length) for start, length, share in self.boluses)
        return switched_mode(t, x, self.w0 / np.sqrt(mass), self.zeta / np.sqrt(mass))


class PneumaticClampMode(SimOnly):
    """A holder's mode in a pneumatic clamp: w^2 grows as the clamp's pressure to the power ``exponent`` (``f0_hz`` at
    the cut-out pressure, the damping ratio ``zeta`` there, falling as w rises); the pressure leaks away with
    ``leak_s`` to ``low`` of the cut-out, then the compressor refills it linearly in ``refill_s``; ``phase`` of the
    first cycle gone at the first sample."""

    def __init__(self, f0_hz, zeta, exponent, low, leak_s, refill_s, phase):
        self.w0, self.zeta, self.exponent = 2.0 * math.pi * f0_hz, zeta, exponent
        self.low, self.leak, self.refill, self.phase = low, leak_s, refill_s, phase

    def pressure(self, s):
        drain = -self.leak * math.log(self.low)  # the time to leak down to low
        cycle = drain + self.refill
        u = np.mod(s + self.phase * cycle, cycle)
        return np.where(u < drain, np.exp(-u / self.leak), self.low + (1.0 - self.low) * (u - drain) / self.refill)

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        stiff = self.pressure(t - t[0]) ** self.exponent
        return switched_mode(t, x, self.w0 * np.sqrt(stiff), self.zeta / np.sqrt(stiff))


# ----------------------------------------------------------------------------- friction

def tuohy_borst(band_n, changes):
    """A Coulomb band on the force passed through a haemostatic valve whose knob is turned at each of ``changes``
    (start, length, log factor) (a quintic over the length; times in seconds since the first sample)."""
    def passed(t, f):
        s = t - t[0]
        log_factor = sum(step * quintic((s - start) / length) for start, length, step in changes)
        band = band_n * np.exp(log_factor)
        return band_play(f, band, band)
    return passed


def lip_seal(band_n, extra, flip_n):
    """A Coulomb band on the force passed through a lip seal whose lip inverts at each reversal of the slip: the band
    times 1 + ``extra`` (1 - slip / ``flip_n``)+, the slip counted since the last reversal (a first slip counts as
    one)."""
    def passed(t, f):
        f = np.asarray(f, dtype=float)
        p, way, slip, out = float(f[0]), 0.0, 0.0, np.empty(f.size)
        full = band_n * (1.0 + extra)
        for i, fi in enumerate(f.tolist()):
            ahead = fi - p
            if ahead != 0.0:
                direction = 1.0 if ahead > 0.0 else -1.0
                if direction != way:
                    if abs(ahead) > full:
                        way, slip = direction, 0.0
                        q = fi - direction * full
                        slip += abs(q - p)
                        p = q
                else:
                    band = band_n * (1.0 + extra * max(0.0, 1.0 - slip / flip_n))
                    if abs(ahead) > band:
                        q = fi - direction * band
                        slip += abs(q - p)
                        p = q
            out[i] = p
        return out
    return passed


# ----------------------------------------------------------------------------- thermo-rheological

def stull_wet_bulb(temp_c, rh_percent):
    """The wet-bulb temperature in degC (Stull 2011) of air at ``temp_c`` degC and ``rh_percent`` % relative
    humidity."""
    t, rh = np.asarray(temp_c, dtype=float), np.clip(np.asarray(rh_percent, dtype=float), 5.0, 99.0)
    return (t * np.arctan(0.151977 * np.sqrt(rh + 8.313659)) + np.arctan(t + rh) - np.arctan(rh - 1.676331)
            + 0.00391838 * rh ** 1.5 * np.arctan(0.023101 * rh) - 4.686035)


class WetGauzeClock(SimOnly):
    """A core wrapped in saline-soaked gauze on the Arrhenius clock exp(b (T_g - T_g,ref)): the gauze at the air's
    wet-bulb temperature (the air's absolute humidity fixed at ``rh_ref`` % relative humidity at the reference), the
    core following it with ``lag_s``."""

    def __init__(self, c, b_per_c, rh_ref, lag_s):
        self.c, self.b, self.rh, self.lag = c, b_per_c, rh_ref, lag_s

    def wet_bulb(self, air):
        return stull_wet_bulb(air, self.rh * magnus(T_REF_C) / magnus(air))

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        gauze = follow(t, self.wet_bulb(temp_of(aux, t.size)), self.lag)
        rate = np.exp(self.b * (gauze - float(self.wet_bulb(np.array([T_REF_C]))[0])))
        return on_clock(self.c, t, np.asarray(x, dtype=float), rate)


class SiloxaneVapourClock(SimOnly):
    """A silicone core on the clock exp(b_f (T_c - T_ref) + g (u - 1)): the Arrhenius part on the core's temperature
    (lag ``lag_s``), and the plasticising siloxane it absorbs, u following exp(0.07 (T_c - T_ref)) (the vapour's
    pressure) with ``sorb_s``; g = ``slow_b`` / 0.07."""

    def __init__(self, c, fast_b, slow_b, lag_s, sorb_s):
        self.c, self.fast, self.gain, self.lag, self.sorb = c, fast_b, slow_b / 0.07, lag_s, sorb_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        core = follow(t, temp_of(aux, t.size), self.lag)
        absorbed = follow(t, np.exp(0.07 * (core - T_REF_C)), self.sorb)
        rate = np.exp(self.fast * (core - T_REF_C) + self.gain * (absorbed - 1.0))
        return on_clock(self.c, t, np.asarray(x, dtype=float), rate)


# ----------------------------------------------------------------------------- outside the catalogue

class ZeroTracking(SimOnly):
    """A weighing indicator's automatic zero tracking: while the output (less its correction) is within ``band_v`` of
    its first value and moves slower than ``rate_v_per_s`` (over 0.2 s), the correction follows it with ``tau_s``; the
    output less the correction, on a coarse grid of ``step_s``."""

    def __init__(self, band_v, rate_v_per_s, tau_s, step_s=0.01):
        self.band, self.rate, self.tau, self.step = band_v, rate_v_per_s, tau_s, step_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        grid, xg = coarse(t, x, self.step)
        lag = max(int(round(0.2 / self.step)), 1)
        keep = -math.expm1(-self.step / self.tau)
        zero, z, out = float(xg[0]), 0.0, np.empty(grid.size)
        for i, xi in enumerate(xg.tolist()):
            moving = abs(xi - xg[max(i - lag, 0)]) / (lag * self.step) >= self.rate
            net = xi - z - zero
            if abs(net) < self.band and not moving:
                z += net * keep
            out[i] = z
        return x - np.interp(t, grid, out)


class BrownoutRetare(SimOnly):
    """Brownouts of the sensor's microcontroller as the robot's motors start a repositioning move: each (place,
    length) falls at a sample where the output is within 10 % of its excursion of its first value (the ``place``
    quantile of those: the sensor at rest), the output 0 V for ``length`` s, then re-tared at power-up so that it reads
    its first value again (whatever the core still holds from the loads before is taken for zero)."""

    def __init__(self, events):
        self.events = events

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        rest = np.flatnonzero(np.abs(x - x[0]) < 0.1 * (np.max(x) - np.min(x)))
        rest = rest[t[rest] > t[0] + 5.0]
        y = x.copy()
        if rest.size == 0:
            return y
        starts = sorted((float(t[rest[min(int(place * rest.size), rest.size - 1)]]), length)
                        for place, length in self.events)
        tare = np.zeros_like(x)
        for start, length in starts:
            end = int(np.searchsorted(t, start + length))
            if end < t.size:
                tare[end:] = x[end] - x[0]
        y = x - tare
        for start, length in starts:
            y[(t >= start) & (t < start + length)] = 0.0
        return y


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([6e4, 8e3]))))  # V / (N s)
        if shape == "thixotropic_grease":
            fluidity = phi * rng.uniform(1.0, 2.0)
            rule = thixotropic_grease(fluidity, rng.uniform(0.5, 2.5), rng.uniform(20.0, 120.0),
                                      fluidity * rng.uniform(2.0, 10.0))
            return Parts("zener", ZenerWithFlow(c, rule), core_changed=True)
        rule = relief_valve_leak(phi * rng.uniform(1.0, 2.0), phi * rng.uniform(0.0, 0.3), rng.uniform(1.0, 3.0),
                                 rng.uniform(0.5, 0.85))
        return Parts("zener", ZenerWithFlow(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        compliance = float(np.interp(m, [0, 1], [0.03, 0.2])) / g0  # V / N: a share of the instantaneous response
        if shape == "hertzian_pad":
            a = (compliance, rng.uniform(2.0, 5.0), rng.uniform(1.0, 20.0))
            p.extra.append(lambda t, f, T, a=a: hertzian_pad(t, f, *a))
            return p
        a = (compliance, rng.uniform(2.0, 8.0), rng.uniform(3.0, 30.0))
        p.extra.append(lambda t, f, T, a=a: gas_accumulator(t, f, *a))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.01, 0.06]))
        if shape == "stoner_wohlfarth_grains":
            psi = np.radians(rng.uniform(5.0, 85.0, int(rng.integers(40, 81))))
            grains = StonerWohlfarthGrains(psi, rng.uniform(0.75, 1.0), top, 1.0)
            grains.w = frac * top / max(grains.loop_height(), 1e-9)
            return Parts("burgers", c, after=[grains])
        share = rng.uniform(0.3, 0.7)
        p.before.append(ForcePath(disc_spring_stack(frac * share, frac * (1.0 - share))))
        return p
    if effect == "sensor_lag":
        delay = float(np.interp(m, [0, 1], [0.012, 0.09]))
        if shape == "photoresistor":
            ratio = rng.uniform(2.0, 6.0)
            rise = 2.0 * delay * rng.uniform(0.8, 1.2) / (1.0 + ratio)
            p.after.append(Photoresistor(rise, rise * ratio, rng.uniform(0.3, 0.7), top * rng.uniform(0.2, 1.0), top,
                                         rng.random() < 0.5))
            return p
        n = max(int(round(delay * rng.uniform(0.8, 1.2) / (0.01 + 1.0 / 120.0))), 1)
        p.after.append(DualMainsRejection(n, rng.uniform(0.001, 0.003)))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.05, 0.16]))
        if shape == "air_cushion":
            p.after.append(StaticMap(air_cushion(rel, top, rng.uniform(0.25, 1.0))))
            return p
        # odd, so cubic near zero: the departure set over 60 % of the range
        p.after.append(StaticMap(preloaded_seats(rel, 0.6 * top, rng.uniform(0.4, 0.7))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.022]) * rng.choice([-1, 1]))
        if shape == "wet_reference_cavity":
            a = (k, rng.uniform(0.3, 0.8), rng.uniform(10.0, 40.0))
            p.extra.append(lambda t, f, T, a=a: wet_cavity_zero(t, T, *a))
            return p
        a = (k, rng.uniform(5.0, 20.0), rng.uniform(30.0, 150.0), rng.uniform(0.5, 2.0))
        p.extra.append(lambda t, f, T, a=a: oil_fill_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.006, 0.016]))
        if shape == "hydrogel_divider":
            p.after.append(HydrogelDividerSpan(a * rng.choice([-1, 1]), rng.uniform(0.06, 0.12), rng.uniform(5.0, 30.0)))
            return p
        p.after.append(IntrinsicHallSpan(a, rng.uniform(max(0.016, a / 0.85), 0.026), rng.uniform(10.0, 40.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.012, 0.08]) * rng.choice([-1, 1]))
        zero = normalised(potting_cure(rng) if shape == "potting_cure" else brake_coils(rng), size)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.03, 0.008])) * rng.uniform(0.8, 1.2)
        if shape == "draining_reservoir":
            n = int(rng.integers(3, 9))
            shares = rng.dirichlet(np.ones(n)) * rng.uniform(0.25, 0.6)
            boluses = list(zip(rng.uniform(0.0, HORIZON_S, n).tolist(), rng.uniform(1.0, 4.0, n).tolist(),
                               shares.tolist()))
            p.after.append(DrainingReservoirMode(rng.uniform(15.0, 35.0), zeta, boluses))
            return p
        p.after.append(PneumaticClampMode(rng.uniform(15.0, 45.0), zeta, rng.uniform(0.4, 1.0), rng.uniform(0.5, 0.75),
                                          rng.uniform(30.0, 120.0), rng.uniform(2.0, 6.0), rng.uniform(0.0, 1.0)))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "tuohy_borst_valve":
            changes, level = [], 0.0
            for start in np.sort(rng.uniform(0.0, HORIZON_S, int(rng.integers(2, 6)))).tolist():
                goal = float(np.clip(level + rng.uniform(-0.7, 0.6), math.log(0.3), math.log(2.5)))
                changes.append((start, rng.uniform(0.5, 2.0), goal - level))
                level = goal
            p.before.append(ForcePath(tuohy_borst(r, changes)))
            return p
        p.before.append(ForcePath(lip_seal(r, rng.uniform(0.3, 1.0), rng.uniform(0.05, 0.3))))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.1, 0.3]))
        if shape == "wet_gauze_clock":
            return Parts("burgers", WetGauzeClock(c, b * rng.uniform(1.6, 2.4), rng.uniform(35.0, 60.0),
                                                  rng.uniform(10.0, 40.0)), core_changed=True)
        fast = b * rng.uniform(0.3, 0.7)
        return Parts("burgers", SiloxaneVapourClock(c, fast, b - fast, rng.uniform(5.0, 20.0), rng.uniform(40.0, 200.0)),
                     core_changed=True)
    if effect == "zero_tracking":
        band = float(np.interp(m, [0, 1], [0.2, 0.6])) / g0
        p.outer.append(ZeroTracking(band, band / rng.uniform(1.0, 3.0), rng.uniform(1.0, 5.0)))
        return p
    if effect == "brownout_retare":
        n = 2 if m < 0.5 else int(rng.integers(3, 5))
        p.outer.append(BrownoutRetare(list(zip(rng.uniform(0.0, 1.0, n).tolist(), rng.uniform(0.2, 1.2, n).tolist()))))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["thixotropic_grease", "relief_valve_leak"],
    "delayed_elasticity": ["hertzian_pad", "gas_accumulator"],
    "hysteresis": ["stoner_wohlfarth_grains", "disc_spring_stack"],
    "sensor_lag": ["photoresistor", "dual_mains_rejection"],
    "nonlinear_gain": ["air_cushion", "preloaded_seats"],
    "thermal_drift": ["wet_reference_cavity", "oil_fill_expansion"],
    "thermal_sensitivity": ["hydrogel_divider", "intrinsic_hall"],
    "offset_drift": ["potting_cure", "brake_coils"],
    "resonance": ["draining_reservoir", "pneumatic_clamp"],
    "friction": ["tuohy_borst_valve", "lip_seal_inversion"],
    "thermo_rheological": ["wet_gauze_clock", "siloxane_vapour_clock"],
}
PAIRS = (("viscous_flow", "friction"), ("delayed_elasticity", "nonlinear_gain"), ("hysteresis", "sensor_lag"),
         ("thermal_drift", "resonance"), ("thermal_sensitivity", "offset_drift"), ("thermo_rheological", "hysteresis"))
OUTSIDE = ("zero_tracking", "brownout_retare")
RATES = (150.0, 340.0, 530.0, 790.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split U", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.0e-3, 2.5e-3), jitter=0.35,
                   gap_s=(0.25, 2.6))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
