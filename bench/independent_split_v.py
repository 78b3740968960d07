"""Independent split V for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split V is an untouched held-out set: written before the engine it measures and blind to it (to how it detects and
fits anything), run once at its end, never used to choose anything. Every name of the catalogue is hidden in two
shapes that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A to U use:

* a pneumatic (air-sprung) core whose charge seeps out through a sintered vent as a compressible Darcy flow with
  Klinkenberg's slip (the mass flow as the difference of the squared pressures: x' = A F (F + 2 (P0 + b)) / (2 (P0 +
  b)), A 0.5-1 times the plain fluidity of 1/60000-1/8000 V/(N s), P0 1-4 N, b 0-1 N: linear at light loads, 1.7-5.5
  times faster per newton at 9 N; it never recovers), or a hydraulic core leaking through an excess-flow valve (a
  hydraulic fuse: 1.5-3 times the plain fluidity while open, its poppet shut once the force passes 2.5-6 N and
  reopened only below 10-40 % of that, a seep of 5-25 % of the plain fluidity through its bleed orifice while shut);
* the fluid a core pushes through a capillary into a prestretched rubber balloon (neo-Hookean, 1 / l - 1 / l^7,
  prestretched 1.02-1.12, stretched to 1.22-1.32 by the full range, short of its pressure peak at 1.38: the balloon
  softens as it fills, so the creep grows faster than the force and slows under heavy loads; 3-20 % of the
  instantaneous response at 3-5 N, 2-20 s at rest), or the fluid a core pushes up a capillary standpipe against a
  spring-backed piston (Lucas-Washburn: the column's drag grows with its length, u' = (F - u) / (tau_e (1 + u / F_e)),
  tau_e 0.5-4 s, F_e 0.3-2 N: slower creep under heavy loads and a recovery at a nearly constant speed; it settles at
  3-20 % of the instantaneous response);
* a multi-leaf spring beside the core (Fancher's model of its interleaf friction: the force passed approaches a
  loading envelope 30-70 % of 1.5-2.5 times 1-6 % below the force and an unloading one the rest above it,
  exponentially over 0.1-0.6 N of force travelled, following each change in full just after a reversal: loops that
  scale with the load and close at none), or a piezoceramic read-out whose domains switch by 90 degrees under the
  stress (3-5 coercive half-widths of 3-20 % of the range, each with 6-12 Krasnosel'skii-Pokrovskii ramps, centres at
  2-90 % and widths of 5-30 % of it: a smooth loop of 1-6 % of the range on the bridge voltage with return-point
  memory, the firmware linearising the mean curve);
* the core's push read as air pressure through a 2-8 m line by a transducer outside the CT's bore (the acoustic transit,
  15-35 % of the delay and at most 23 ms, then the transducer's volume filling through the line as a compressible
  laminar flow, P' = (P_in^2 - P^2) / (2 tau0), 0.3-1.5 atm over the range: faster under load; 0.8-1.2 times 12-90 ms
  in all at rest), or a firmware comb filter against the robot's stepper vibration (each sample averaged with the one
  19-216 ms earlier, 1.6-2.4 times the delay of 12-90 ms, behind an anti-alias RC of 1-3 ms: a staircase after each
  step);
* a liquid-metal channel gauge read in a quarter bridge (its resistance as the square of its stretch, (1 +- k x)^2,
  read as (r - 1) / (2 (r + 1)): compressive when the load stretches it, expansive when it compresses it, 5-16 % at the
  top of the range), or a Hall element beside which the load slides a magnet (the dipole's field along the slide,
  u / (1 + u^2)^(5/2), from u0 = -0.35 to 0.1 toward its peak at 1/2: S-shaped, expansive then compressive, or
  compressive; 5-16 %);
* the preload of a Belleville washer holding the sensor in its holder, which the holder's expansion (lag 10-40 s, 0.04
  to 0.12 of the washer's thickness per degC) moves along the Almen-Laszlo curve (free height 1.1-1.5 thicknesses,
  seated at 70-120 % of it: flat, even falling, near full flattening; 0.006-0.022 V/degC on average over +-3 degC), or
  the zero of a frequency read-out counted against a miscut AT quartz timebase (Bechmann's cubic about an inflection
  -1.5 to +2.5 degC from the reference, turning points 2-6 degC either side of it, lag 5-20 s; 0.006-0.022 V/degC on
  average over -2 to +4 degC);
* leads printed in a carbon ink with a positive temperature coefficient (exp(gamma dT), gamma 2-8 %/degC, lag 5-25
  s) in series with the bridge (the span (1 + rho) / (1 + rho exp(gamma dT)), 0.8-2 %/degC lower at the reference,
  falling ever more slowly), or a patient-isolation barrier passing the read-out through a linear optocoupler without
  feedback (its current transfer ratio a Gaussian of 8-20 degC in the board's temperature, lag 10-40 s, peaked so that
  the span moves 0.8-2 %/degC either way at the reference);
* the housing's polymer swelling with the isopropanol of 2-5 disinfectant wipes (each wet for 5-25 s: taken up and lost
  again as Crank's slab, l^2 / D 40-300 s: a square-root rise, a slow tail; 12-80 mV at most), or the sterile drape's
  pull on the cable gland, changed at 3-8 adjustments of 0.5-2 s and relaxed by the polyethylene film as 1 - q
  log10(1 + t / t0) (q 0.08-0.2, t0 0.5-5 s; 12-80 mV at most);
* a holder's mode (15-45 Hz) in a clamp whose screw its own vibration loosens (Junker: the preload falls toward 40-70 %
  as 1 - exp(-E / E0), E the mode's relative motion so far, E0 20-100 % of what the record gives; the frequency as the
  preload's power 1/6, down by 6-14 %, the damping ratio as its power -0.3), or a telescopic needle guide extended and
  retracted before each placement (every 20-90 s in 1-4 s, its length up to 1.3-1.8 times the retracted one: the
  cantilever's mode, 25-55 Hz retracted, as the length's power -1.5, down to 10-37 Hz); damping ratio 0.0064-0.036,
  at most 0.047;
* a Coulomb band of 0.4-3.6 % of the range in a needle guide that frets (each reversal after a stroke shorter than
  0.3-1.5 N adds debris, 5-20 % of what is missing, each longer stroke sweeps out 50-90 % of it; the band 0.62-0.8 to
  1.2-1.38 times its nominal width, the same at every load), or in a needle guide resting on the patient, whose
  breathing presses it (the band +-30-70 % at 11-20 breaths a minute, the rhythm wandering by up to 10 % over 60-200 s);
* an Arrhenius clock (0.15-0.4 per degC, lag 5-20 s) on a core of a thermoresponsive (UCST) gel that takes up solvent
  above its upper critical solution temperature (the 40-80th percentile of its temperature over the record, a logistic
  of 0.2-0.6 degC; it swells over 20-80 s and deswells over 60-240 s), the solvent speeding the clock by 0.3-1 further
  e-folds, or a WLF clock (the universal constants, re-referenced 5-56 K above the glass transition for 0.18-0.64 per
  degC at the reference) on a core potted in a thick silicone boot (the air's temperature reaching it through a
  half-order lag, 1 / (1 + sqrt(s tau)), tau 3-15 s).

It also holds six pairs, two effects outside the catalogue (a DAQ whose converter is two time-interleaved ADCs taking
turns sample by sample with gains apart by what makes 20-80 mV at the top of the range, alternating about the bridge
signal; bit slips on the SPI link from the ADC while the CT scans, 2-10 s every 15-60 s, each word then doubled or
halved with a chance of 0.2-1 %) and four clean records. Profiles: CT-guided drainage by the Seldinger technique
through the measured force-depth curve (``../shared/data``, ``depth_force.csv``, its first insertion stretched over
40-80 mm: the access needle in 2-3 advances with check scans, a guidewire, 2-3 twisting dilators of growing size
through the same layers, the drain; synthetic layers when the data are absent); a venipuncture robot (skin, vein wall,
vacuum tubes pushed onto its holder); and pedicle screws (an awl through the cortex, a thread biting once a turn, a
graze of the cortex, seating). Rates 120, 350, 620 and 840 Hz (a mode at 1000 Hz with knocks that excite it), 1.1-2.5
mV noise, stamp jitter, gaps, and a sensor on the wrist of a robot in an interventional suite recovering from its night
setback, under a laminar-flow ceiling whose cool supply air reaches it in bouts, warmed by the robot's wrist motor
while it works.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_v.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, optimize, signal, special

from polyforce_ros.physics.viscoelastic import simulate_deformation
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (band_play, coarse, cutter as window, dead_time, ForcePath, LinearFilter, Parts, quintic,
                       schedule as schedule_until, ShapeSplit, SimOnly, sized, temp_of, uniform_grid, ZenerWithFlow)

SEED0 = 1_520_000  # never a seed of the registry's splits nor of splits A (90000..) to U (1450000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 440.0
HORIZON_S = DURATION_S + 60.0  # what a schedule drawn before the record covers (the record plus its gaps' slack)

normalised = functools.partial(sized, horizon_s=HORIZON_S)
schedule = functools.partial(schedule_until, horizon_s=HORIZON_S)


# ----------------------------------------------------------------------------- profiles and temperature


def last_of(values, default):
    """The last of ``values`` (a float), ``default`` when there are none."""
    return float(values[-1]) if np.size(values) else float(default)


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


def seldinger_drain(duration_s, rate_hz, rng):
    """A robot placing drainage catheters under CT guidance by the Seldinger technique (the sensor behind its instrument
    holder). The access needle goes in through the measured insertion (``measured_insertion``), stretched over 40-80 mm
    and scaled to a 2-4 N peak, at 1-3 mm/s in 2-3 advances with check scans between (3-8 s holds, the force
    relaxing to 60-85 % with 1-3 s and building back within 0.8 mm of the next advance). The stylet comes out (the force
    down to the shaft's friction, 30-60 %, in 0.5 s) and a guidewire is threaded for 5-15 s (nudges of 0.05-0.15 N at
    0.5-2 Hz); the needle is withdrawn in 1-3 s. 2-3 dilators of growing size follow the wire, each pushed through the
    same layers (the measured curve again, 1.15-1.4 times the force of the last) to 60-90 % of the depth in 5-15 s with a
    twisting motion (+-15-30 % at 0.5-1.5 Hz), the force dipping by 30-50 % (back within 50-150 ms) where it passes the
    fascia, 40-70 % of the way in; each withdrawn in 1-2 s, 3-8 s apart. The drain then glides in over the wire (a ramp
    in 4-10 s to 1.5-4 N with a stick-slip of 0.1-0.3 N at 1-3 Hz), released in 0.5-1 s; 10-30 s before the next
    placement. Made-up layers (``synthetic_insertion``) when ``../shared/data`` is absent."""
    depth_mm, force_n = measured_insertion() or synthetic_insertion(rng)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    at = window(t)
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 50.0:
        goal_mm = rng.uniform(40.0, 80.0)
        stretch = goal_mm / float(depth_mm[-1])
        scale = rng.uniform(2.0, 4.0) / max(float(force_n.max()), 1e-3)

        def resistance(d, stretch=stretch, scale=scale):
            return scale * np.interp(np.asarray(d, dtype=float) / stretch, depth_mm, force_n)
        speed = rng.uniform(1.0, 3.0)
        stops = np.sort(rng.uniform(0.3, 0.8, int(rng.integers(1, 3)))) * goal_mm
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
        needle = float(resistance(goal_mm))
        shaft = needle * rng.uniform(0.3, 0.6)
        seg, s = at(now, 0.5)
        f[seg] = needle + (shaft - needle) * quintic(s / 0.5)
        now += 0.5
        thread, nudge, freq = rng.uniform(5.0, 15.0), rng.uniform(0.05, 0.15), rng.uniform(0.5, 2.0)
        seg, s = at(now, thread)
        f[seg] = shaft + nudge * np.sin(2.0 * np.pi * freq * s) ** 2
        now += thread
        out = rng.uniform(1.0, 3.0)
        seg, s = at(now, out)
        f[seg] = shaft * (1.0 - quintic(s / out))
        now += out + rng.uniform(2.0, 5.0)
        size = 1.0
        for _ in range(int(rng.integers(2, 4))):
            size *= rng.uniform(1.15, 1.4)
            depth, advance = goal_mm * rng.uniform(0.6, 0.9), rng.uniform(5.0, 15.0)
            twist_hz, twist, phase = rng.uniform(0.5, 1.5), rng.uniform(0.15, 0.3), rng.uniform(0.0, 2.0 * np.pi)
            fascia, dip, back = rng.uniform(0.4, 0.7) * advance, rng.uniform(0.3, 0.5), rng.uniform(0.05, 0.15)
            seg, s = at(now, advance)
            push = size * resistance(depth * s / advance) * (1.0 + twist * np.sin(2.0 * np.pi * twist_hz * s + phase))
            f[seg] = push * np.where(s > fascia, 1.0 - dip * np.exp(-(s - fascia) / back), 1.0)
            now += advance
            last = last_of(f[seg], 0.0)
            out = rng.uniform(1.0, 2.0)
            seg, s = at(now, out)
            f[seg] = last * (1.0 - quintic(s / out))
            now += out + rng.uniform(3.0, 8.0)
        glide, level = rng.uniform(4.0, 10.0), rng.uniform(1.5, 4.0)
        slip, slip_hz = rng.uniform(0.1, 0.3), rng.uniform(1.0, 3.0)
        seg, s = at(now, glide)
        f[seg] = level * quintic(s / glide) + slip * np.mod(slip_hz * s, 1.0) * quintic(s / 1.0)
        now += glide
        last = last_of(f[seg], level)
        release = rng.uniform(0.5, 1.0)
        seg, s = at(now, release)
        f[seg] = last * (1.0 - quintic(s / release))
        now += release + rng.uniform(10.0, 30.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def robotic_venipuncture(duration_s, rate_hz, rng):
    """A venipuncture robot drawing blood (the sensor behind its needle). Each draw: the needle presses the skin
    (0.8-2 N reached in 0.2-0.6 s as the power 1.5 of the time) and punctures it (40-70 % of that lost within 30 ms),
    advances at 2-6 mm/s through 3-8 mm of subcutaneous tissue (its friction rising by 0.1-0.4 N), tents the vein's wall
    (0.4-1.2 N more over 1-3 mm, quadratic) until it pops (50-80 % of that gone within 20 ms), and holds while 2-4
    vacuum tubes are pushed onto the holder's back needle (1-3 s apart; each push a bump to 3-8 N over 0.3-0.8 s, the
    tube filling for 4-10 s while the hold creeps by up to 0.15 N either way, its removal a pull of 0.2-0.6 N for 0.4 s); then the
    needle comes out in 0.5-1.5 s and 10-25 s pass before the next draw."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    at = window(t)
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 30.0:
        touch, skin = rng.uniform(0.2, 0.6), rng.uniform(0.8, 2.0)
        seg, s = at(now, touch)
        f[seg] = skin * (s / touch) ** 1.5
        now += touch
        left = skin * rng.uniform(0.3, 0.6)
        seg, s = at(now, 0.03)
        f[seg] = skin + (left - skin) * quintic(s / 0.03)
        now += 0.03
        speed, sub_mm, fric = rng.uniform(2.0, 6.0), rng.uniform(3.0, 8.0), rng.uniform(0.1, 0.4)
        seg, s = at(now, sub_mm / speed)
        f[seg] = left + fric * speed * s / sub_mm
        now += sub_mm / speed
        base = left + fric
        tent_mm, tent = rng.uniform(1.0, 3.0), rng.uniform(0.4, 1.2)
        seg, s = at(now, tent_mm / speed)
        f[seg] = base + tent * (speed * s / tent_mm) ** 2
        now += tent_mm / speed
        hold = base + tent * rng.uniform(0.2, 0.5)
        seg, s = at(now, 0.02)
        f[seg] = base + tent + (hold - base - tent) * quintic(s / 0.02)
        now += 0.02
        for _ in range(int(rng.integers(2, 5))):
            wait = rng.uniform(1.0, 3.0)
            seg, s = at(now, wait)
            f[seg] = hold
            now += wait
            push, spike = rng.uniform(0.3, 0.8), rng.uniform(3.0, 8.0)
            seg, s = at(now, push)
            f[seg] = hold + (spike - hold) * np.sin(np.pi * s / push) ** 2
            now += push
            fill, sag = rng.uniform(4.0, 10.0), rng.uniform(-0.15, 0.15)
            seg, s = at(now, fill)
            f[seg] = hold + sag * quintic(s / fill)
            now += fill
            hold = max(hold + sag, 0.1)
            pull = rng.uniform(0.2, 0.6)
            seg, s = at(now, 0.4)
            f[seg] = hold - pull * np.sin(np.pi * s / 0.4)
            now += 0.4
        out = rng.uniform(0.5, 1.5)
        seg, s = at(now, out)
        f[seg] = hold * (1.0 - quintic(s / out))
        now += out + rng.uniform(10.0, 25.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def pedicle_screw(duration_s, rate_hz, rng):
    """A robot placing pedicle screws (the sensor behind its screwdriver). An awl opens the cortex (a push rising to
    3-7 N in 1-2 s, quadratic, that gives way to 40-60 % within 0.1 s; out in 0.5 s, 2-5 s to load the screw); the
    screw is then driven 10-25 turns at 0.5-1.5 turns/s under a push of 1-2.5 N that grows by 0.02-0.08 N a turn in the
    cancellous bone, with a ripple of 0.2-0.6 N per turn as the thread bites, and one time in two a bump of 1-2 N over
    1-3 turns where it grazes the pedicle's cortex; its head seats (the force rising to 5-8.5 N in 0.5-1.5 s, quadratic)
    and the driver lets go in 0.3-0.6 s. 15-40 s between screws (the robot repositions, a check scan)."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    at = window(t)
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 40.0:
        rise, peak = rng.uniform(1.0, 2.0), rng.uniform(3.0, 7.0)
        seg, s = at(now, rise)
        f[seg] = peak * (s / rise) ** 2
        now += rise
        gave = peak * rng.uniform(0.4, 0.6)
        seg, s = at(now, 0.1)
        f[seg] = peak + (gave - peak) * quintic(s / 0.1)
        now += 0.1
        seg, s = at(now, 0.5)
        f[seg] = gave * (1.0 - quintic(s / 0.5))
        now += 0.5 + rng.uniform(2.0, 5.0)
        turns, per_s = int(rng.integers(10, 26)), rng.uniform(0.5, 1.5)
        push, grow, ripple = rng.uniform(1.0, 2.5), rng.uniform(0.02, 0.08), rng.uniform(0.2, 0.6)
        length = turns / per_s
        seg, s = at(now, length)
        n = per_s * s
        level = push * quintic(s / 0.5) + grow * n + ripple * np.sin(np.pi * n) ** 2
        if rng.random() < 0.5:
            graze, width, bump = rng.uniform(0.3, 0.8) * turns, rng.uniform(1.0, 3.0), rng.uniform(1.0, 2.0)
            level = level + bump * np.sin(np.pi * np.clip((n - graze) / width, 0.0, 1.0))
        f[seg] = level
        now += length
        last = last_of(level, push)
        seat, top = rng.uniform(0.5, 1.5), rng.uniform(5.0, 8.5)
        seg, s = at(now, seat)
        f[seg] = last + (top - last) * (s / seat) ** 2
        now += seat
        release = rng.uniform(0.3, 0.6)
        seg, s = at(now, release)
        f[seg] = top * (1.0 - quintic(s / release))
        now += release + rng.uniform(15.0, 40.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (seldinger_drain, robotic_venipuncture, pedicle_screw)


def alternating(rng, first_s, second_s, start, end):
    """Bouts (start, end) of a two-state process between ``start`` and ``end``: bouts of ``first_s`` (min, max)
    seconds, separated by ``second_s``, the first under way at ``start`` with even chance."""
    out, now, on = [], start, rng.random() < 0.5
    while now < end:
        length = rng.uniform(*(first_s if on else second_s))
        if on:
            out.append((now, now + length))
        now, on = now + length, not on
    return out


def temperature(t, rng, step_s=0.5):
    """A sensor on the wrist of a robot for CT-guided drainage, venipuncture and screw placement, in an interventional
    suite recovering from its night setback: the room warms by 1.5-3.5 degC toward 0.5 degC below to 1.5 degC above
    the reference (with 300-900 s, the recovery begun 0-600 s before the record). The laminar-flow ceiling's supply
    air, 2-4 degC cooler than the room, reaches the sensor in bouts of 20-90 s (15-75 s between them, while the staff
    and the lamps deflect it; it takes hold with 3-10 s); the robot's wrist motor warms the sensor's flange toward 2-5
    degC above the room while it works (bouts of 30-150 s, 20-90 s idle) with 40-120 s, and it cools with 80-240 s. The
    sensor follows its surroundings with 8-25 s (exact per step of ``step_s``), from 900 s before the record."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-900.0, d + 2.0 * step_s, step_s)
    rise, begun = rng.uniform(1.5, 3.5), rng.uniform(-600.0, 0.0)
    room = T_REF_C + rng.uniform(-0.5, 1.5) - rise * np.exp(-np.maximum(grid - begun, 0.0) / rng.uniform(300.0, 900.0))
    draught = np.zeros(grid.size, dtype=bool)
    for a, b in alternating(rng, (20.0, 90.0), (15.0, 75.0), -900.0, d + 60.0):
        draught |= (grid >= a) & (grid < b)
    working = np.zeros(grid.size, dtype=bool)
    for a, b in alternating(rng, (30.0, 150.0), (20.0, 90.0), -900.0, d + 60.0):
        working |= (grid >= a) & (grid < b)
    cool, reach = rng.uniform(2.0, 4.0), rng.uniform(2.0, 5.0)
    air_keep = math.exp(-step_s / rng.uniform(3.0, 10.0))
    up_keep, down_keep = math.exp(-step_s / rng.uniform(40.0, 120.0)), math.exp(-step_s / rng.uniform(80.0, 240.0))
    sensor_keep = math.exp(-step_s / rng.uniform(8.0, 25.0))
    chill, heat, sensor = 0.0, 0.0, float(room[0])
    out = np.empty(grid.size)
    for i, (r, blow, on) in enumerate(zip(room.tolist(), draught.tolist(), working.tolist())):
        out[i] = sensor
        chill = (cool if blow else 0.0) + (chill - (cool if blow else 0.0)) * air_keep
        heat = reach + (heat - reach) * up_keep if on else heat * down_keep
        goal = r - chill + heat
        sensor = goal + (sensor - goal) * sensor_keep
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


def within(s, sessions):
    """Whether each of ``s`` falls in one of ``sessions`` (start, length)."""
    inside = np.zeros(np.shape(s), dtype=bool)
    for start, length in sessions:
        inside |= (s >= start) & (s < start + length)
    return inside


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


def plays(x, halves):
    """Play operators of half-widths ``halves`` on ``x``, each started at ``x[0]`` plus its half-width (where a load
    taken off before the record left it): an array (len(halves), len(x))."""
    stuck = [float(x[0]) + h for h in halves]
    out = np.empty((len(halves), np.size(x)))
    for i, xi in enumerate(np.asarray(x, dtype=float).tolist()):
        for k, h in enumerate(halves):
            stuck[k] = max(xi - h, min(xi + h, stuck[k]))
            out[k, i] = stuck[k]
    return out


# ----------------------------------------------------------------------------- viscous flow


def gas_seepage(fluidity, charge_n, slip_n, step_s=0.02):
    """x' = A F (F + 2 (P0 + b)) / (2 (P0 + b)): the air of a pneumatic core (charged to ``charge_n`` = P0, in units of
    the force on its piston) seeping out through a sintered vent as a compressible Darcy flow (the mass flow as the
    difference of the squared pressures) with Klinkenberg's slip ``slip_n`` = b; A = ``fluidity`` at light loads."""
    def rule(t, f):
        grid, fg = coarse(t, np.maximum(f, 0.0), step_s)
        p = charge_n + slip_n
        return np.interp(t, grid, integrate.cumulative_trapezoid(fluidity * fg * (fg + 2.0 * p) / (2.0 * p), grid,
                                                                 initial=0.0))
    return rule


def excess_flow_fuse(open_fluidity, seep_fluidity, trip_n, reset, step_s=0.01):
    """x' = A F: the leak of a hydraulic core through an excess-flow valve (a hydraulic fuse), A ``open_fluidity``
    while it is open; its poppet shuts once the force (and so the flow) passes ``trip_n`` and reopens only when the
    force falls below ``reset`` times that, ``seep_fluidity`` (its bleed orifice) while shut (open at the start)."""
    def rule(t, f):
        grid, fg = coarse(t, np.maximum(f, 0.0), step_s)
        state = np.full(grid.size, np.nan)
        state[fg <= reset * trip_n] = 0.0
        state[fg >= trip_n] = 1.0
        fluidity = np.where(forward_fill(state, 0.0) > 0.5, seep_fluidity, open_fluidity)
        return np.interp(t, grid, integrate.cumulative_trapezoid(fluidity * fg, grid, initial=0.0))
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def balloon_pressure(stretch):
    """A thin neo-Hookean balloon's pressure, in units of its shear modulus times its wall over its radius, at the
    stretch ``stretch``: 1 / l - 1 / l^7 (it peaks at l = 7^(1/6), 1.38)."""
    return 1.0 / stretch - stretch ** -7.0


def rubber_balloon(t, f, compliance_v_per_n, ref_n, prestretch, top_stretch, tau0_s, step_s=0.01):
    """The fluid a core pushes through a capillary into a rubber balloon (prestretched to ``prestretch``; the full range
    of force would stretch it to ``top_stretch``, short of its pressure peak): its volume V = l^3 follows
    V' = (P0 + F - p(V)) / R, the balloon softening as it fills (more creep, and slower, under heavy loads); R set for a
    retardation of ``tau0_s`` at rest. The output is V's rise scaled so that at ``ref_n`` the settled creep is
    ``compliance_v_per_n`` times the force. Explicit per coarse step of ``step_s``, from rest."""
    scale = FORCE_MAX_N / (balloon_pressure(top_stretch) - balloon_pressure(prestretch))  # N per unit of pressure
    v0 = prestretch ** 3
    rest_p = scale * balloon_pressure(prestretch)
    slope0 = 3.0 * prestretch ** 2 / (scale * (-prestretch ** -2 + 7.0 * prestretch ** -8))  # dV/dp at rest
    resistance = tau0_s / slope0

    def settled(force):  # V at equilibrium under ``force``
        return optimize.brentq(lambda lam: scale * balloon_pressure(lam) - rest_p - force, prestretch,
                               7.0 ** (1.0 / 6.0)) ** 3
    gain = compliance_v_per_n * ref_n / (settled(ref_n) - v0)
    grid, fg = coarse(t, np.maximum(np.asarray(f, dtype=float), 0.0), step_s)
    v, out = v0, np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        out[i] = v
        lam = v ** (1.0 / 3.0)
        v += step_s * (rest_p + fi - scale * balloon_pressure(lam)) / resistance
    return gain * (np.interp(t, grid, out) - v0)


def capillary_standpipe(t, f, compliance_v_per_n, entry_s, entry_n, step_s=0.01):
    """c u: the fluid a core pushes into a capillary standpipe against a spring-backed piston (u, the force the column
    holds, settles at the force); the column's own drag grows with its length (Lucas-Washburn): u' = (F - u) /
    (``entry_s`` (1 + u / ``entry_n``)), so the creep is slower the longer the column and the recovery runs at a nearly
    constant speed. Exact per coarse step of ``step_s`` at the step's rate, from rest."""
    grid, fg = coarse(t, np.maximum(np.asarray(f, dtype=float), 0.0), step_s)
    u, out = 0.0, np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        out[i] = u
        u = fi + (u - fi) * math.exp(-step_s / (entry_s * (1.0 + u / entry_n)))
    return compliance_v_per_n * np.interp(t, grid, out)


# ----------------------------------------------------------------------------- hysteresis

def leaf_spring(loading, unloading, travel_n):
    """The force a core passes beside a multi-leaf spring (Fancher's model of its interleaf friction): the passed force
    approaches its loading envelope, (1 - ``loading``) F, while the force rises and its unloading one, (1 +
    ``unloading``) F, while it falls, exponentially in the force travelled (``travel_n``), following each change in full
    at first after a reversal (the leaves stuck)."""
    def passed(t, f):
        f = np.asarray(f, dtype=float)
        p, prev, out = float(f[0]), float(f[0]), np.empty(f.size)
        for i, fi in enumerate(f.tolist()):
            step = fi - prev
            if step != 0.0:
                envelope = (1.0 - loading) * fi if step > 0.0 else (1.0 + unloading) * fi
                p = envelope + (p + step - envelope) * math.exp(-abs(step) / travel_n)
            prev = fi
            out[i] = p
        return out
    return passed


class DomainSwitching(SimOnly):
    """A piezoceramic read-out whose domains switch by 90 degrees under the stress (ferroelastic switching): the domains
    of play ``k`` (a coercive half-width ``halves[k]`` of the read-out's range) switch over smooth ramps
    (Krasnosel'skii-Pokrovskii hysterons: centres ``centres[k]``, widths ``ramps[k]``, weights ``weights[k]``), with
    return-point memory; y = x + ``gain`` (S(plays) - S(x)), S(x) the switched share along the mean curve (what a
    calibration along it linearises). A load taken off before the record set the domains."""

    def __init__(self, halves, centres, ramps, weights):
        self.halves, self.centres, self.ramps, self.weights, self.gain = halves, centres, ramps, weights, 1.0

    def switched(self, z, k):
        return np.clip((z[:, None] - self.centres[k]) / self.ramps[k], 0.0, 1.0) @ self.weights[k]

    def departure(self, x):
        z = plays(x, self.halves)
        return sum(self.switched(z[k], k) - self.switched(x, k) for k in range(len(self.halves)))

    def loop_height(self, reach):
        sweep = np.concatenate([np.linspace(0.0, reach, 400), np.linspace(reach, 0.0, 400)])
        m = self.departure(sweep)
        return float(np.max(np.abs(m[:400] - m[400:][::-1])))

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        return x + self.gain * self.departure(x)


# ----------------------------------------------------------------------------- sensor lag

class PneumaticLine(SimOnly):
    """The core's push read as air pressure through a line (2-8 m) to a transducer outside the CT's bore: the acoustic
    transit ``transit_s``, then the transducer's volume filling through the line's laminar resistance as a compressible
    flow, P' = (P_in^2 - P^2) / (2 ``tau0_s``) in atmospheres (faster at high pressure); the full ``reach`` of the output
    is ``swing`` atmospheres. Exact per step for a constant P_in, on a uniform grid at the median step, from rest."""

    def __init__(self, transit_s, tau0_s, swing, reach):
        self.transit, self.tau0, self.swing, self.reach = transit_s, tau0_s, swing, reach

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, dead_time(t, x, self.transit))
        p_in = np.maximum(1.0 + self.swing * (xu - xu[0]) / self.reach, 0.05)
        p, out = float(p_in[0]), np.empty(tu.size)
        for i, pi in enumerate(p_in.tolist()):
            g = (p - pi) / (p + pi) * math.exp(-pi * h / self.tau0)
            p = pi * (1.0 + g) / (1.0 - g)
            out[i] = p
        return np.interp(t, tu, xu[0] + (out - 1.0) * self.reach / self.swing)


class TwoTapComb(SimOnly):
    """A firmware comb filter against the robot's stepper vibration: each sample averaged with the one ``period_s``
    earlier, (x(t) + x(t - T)) / 2, behind an anti-alias RC of ``rc_s``."""

    def __init__(self, period_s, rc_s):
        self.period, self.rc = period_s, LinearFilter([1.0], [rc_s, 1.0])

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        y = self.rc.forward(t, np.asarray(x, dtype=float))
        return 0.5 * (y + dead_time(t, y, self.period))


# ----------------------------------------------------------------------------- nonlinear gain

def liquid_metal_gauge(rel, reach, stretched):
    """x read by a liquid-metal (gallium alloy) channel gauge in a quarter bridge: the channel incompressible, so its
    resistance goes as the square of its stretch, r = (1 +- k x)^2 (stretched or compressed by the load), read as
    (r - 1) / (2 (r + 1)), scaled to slope 1 at zero: compressive when stretched, expansive when compressed; k set for
    a departure of ``rel`` at ``reach``."""
    sign = 1.0 if stretched else -1.0

    def read(x, k):
        r = (1.0 + sign * k * np.asarray(x, dtype=float)) ** 2
        return (r - 1.0) / (2.0 * (r + 1.0)) / (0.5 * sign * k)
    return calibrated(read, rel, reach, (0.8 if stretched else 0.6) / reach)


def lateral_magnet(rel, reach, u0):
    """x read by a Hall element beside which the load slides a magnet (a dipole at unit height; the field along the
    slide, u / (1 + u^2)^(5/2), u = ``u0`` + k x), scaled to slope 1 at zero: S-shaped about the field's inflection
    (u = 0), compressive toward its peak (u = 1/2); k set for a departure of ``rel`` at ``reach``, u kept below 0.45."""
    def field(u):
        return u / (1.0 + u * u) ** 2.5
    slope = (1.0 - 4.0 * u0 * u0) / (1.0 + u0 * u0) ** 3.5

    def read(x, k):
        return (field(u0 + k * np.asarray(x, dtype=float)) - field(u0)) / (k * slope)
    return calibrated(read, rel, reach, (0.45 - u0) / reach)


# ----------------------------------------------------------------------------- thermal drift

def belleville_zero(t, temp, k_v_per_c, ratio, seat, travel_per_c, lag_s):
    """The preload of a Belleville washer holding the sensor in its holder, the holder's expansion (lag ``lag_s``)
    moving its deflection by ``travel_per_c`` thicknesses per degC from ``seat`` times its free height (``ratio``
    thicknesses): the Almen-Laszlo load d ((h - d) (h - d / 2) + 1) in thicknesses (flat, even falling, near d = h);
    scaled so that its mean slope over -3 to +3 degC is ``k_v_per_c``."""
    body = follow(t, temp, lag_s) - T_REF_C
    d0 = seat * ratio

    def load(d):
        return d * ((ratio - d) * (ratio - 0.5 * d) + 1.0)
    probe = np.linspace(-3.0, 3.0, 121)
    mean_slope = float(np.mean(np.abs(np.gradient(load(d0 + travel_per_c * probe), probe))))
    return k_v_per_c * (load(d0 + travel_per_c * body) - load(d0)) / max(mean_slope, 1e-9)


def quartz_timebase_zero(t, temp, k_v_per_c, inflection_c, turnover_c, lag_s):
    """The zero of a frequency-output read-out counted against a miscut AT quartz timebase: the crystal (lag ``lag_s``)
    follows Bechmann's cubic about its inflection (``inflection_c`` from the reference), its turning points
    ``turnover_c`` either side of it; scaled so that its mean slope over -2 to +4 degC is ``k_v_per_c``."""
    crystal = follow(t, temp, lag_s) - T_REF_C

    def shift(u):
        v = u - inflection_c
        return v - v ** 3 / (3.0 * turnover_c ** 2)
    probe = np.linspace(-2.0, 4.0, 121)
    mean_slope = float(np.mean(np.abs(1.0 - (probe - inflection_c) ** 2 / turnover_c ** 2)))
    return k_v_per_c * (shift(crystal) - shift(0.0)) / max(mean_slope, 1e-9)


# ----------------------------------------------------------------------------- thermal sensitivity

class PtcLeadSpan(SimOnly):
    """A printed sensor whose leads are a carbon ink with a positive temperature coefficient (exp(``gamma`` dT), the
    flex's temperature behind ``lag_s``), in series with the bridge: the span (1 + rho) / (1 + rho exp(gamma dT)), rho
    the leads over the bridge at the reference, set for a slope of minus ``coefficient`` there."""

    def __init__(self, coefficient, gamma, lag_s):
        q = coefficient / gamma
        self.gamma, self.lag, self.rho = gamma, lag_s, q / (1.0 - q)

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        lead = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        return np.asarray(x, dtype=float) * (1.0 + self.rho) / (1.0 + self.rho * np.exp(self.gamma * lead))


class OptocouplerSpan(SimOnly):
    """A patient-isolation barrier passing the read-out through a linear optocoupler without feedback: its current
    transfer ratio peaks at a temperature (the LED's efficiency falls, the phototransistor's gain rises), a Gaussian
    of width ``width_c`` in the board's temperature (lag ``lag_s``), its peak placed for a slope of ``coefficient`` at
    the reference."""

    def __init__(self, coefficient, width_c, lag_s):
        self.peak, self.width, self.lag = 0.5 * coefficient * width_c ** 2, width_c, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        board = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        span = np.exp(-((board - self.peak) ** 2 - self.peak ** 2) / self.width ** 2)
        return np.asarray(x, dtype=float) * span


# ----------------------------------------------------------------------------- offset drift

def slab_uptake(x):
    """The share of its equilibrium content a slab wetted on both faces has taken up at x = t D / l^2 (Crank's
    series)."""
    x = np.maximum(np.asarray(x, dtype=float), 0.0)
    k = 2.0 * np.arange(60) + 1.0
    return 1.0 - np.exp(-np.multiply.outer(x, k * k * np.pi ** 2 / 4.0)) @ (8.0 / (k * k * np.pi ** 2))


def alcohol_wipes(rng, horizon_s=HORIZON_S, step_s=0.25):
    """The housing's polymer swelling with the isopropanol of 2-5 disinfectant wipes (from 60 s before the record on;
    each keeps the surface wet for 5-25 s, a dose of 0.5-1.5): the alcohol taken up while wet (Crank's slab, l^2 / D
    40-300 s: a square-root start) and lost again once dry (the same law), the zero following the content; as a
    function of the seconds since the first sample, zero there."""
    n = int(rng.integers(2, 6))
    wipes = list(zip(rng.uniform(-60.0, horizon_s, n).tolist(), rng.uniform(5.0, 25.0, n).tolist(),
                     rng.uniform(0.5, 1.5, n).tolist()))
    tau = rng.uniform(40.0, 300.0)

    def content(s):
        out = np.zeros_like(s)
        for start, wet, dose in wipes:
            since = s - start
            taken = slab_uptake(np.minimum(since, wet) / tau)
            lost = slab_uptake((since - wet) / tau)
            out += dose * np.where(since <= 0.0, 0.0, np.where(since < wet, taken, taken * (1.0 - lost)))
        return out

    def zero(s):
        s = np.asarray(s, dtype=float)
        grid = np.arange(min(float(np.min(s)), 0.0) - step_s, float(np.max(s)) + 2.0 * step_s, step_s)
        return np.interp(s, grid, content(grid)) - float(content(np.array([0.0]))[0])
    return zero


def drape_tugs(rng, horizon_s=HORIZON_S):
    """The sterile drape over the sensor's cable gland, adjusted 3-8 times (from 30 s before the record on, each in
    0.5-2 s): each adjustment changes its pull on the housing by a step of random sign (normal), which the
    polyethylene film then relaxes as 1 - q log10(1 + t / t0) (q 0.08-0.2 per decade, t0 0.5-5 s); as a function of
    the seconds since the first sample, zero there."""
    n = int(rng.integers(3, 9))
    tugs = list(zip(rng.uniform(-30.0, horizon_s, n).tolist(), rng.normal(0.0, 1.0, n).tolist(),
                    rng.uniform(0.5, 2.0, n).tolist()))
    q, t0 = rng.uniform(0.08, 0.2), rng.uniform(0.5, 5.0)

    def pull(s):
        s = np.asarray(s, dtype=float)
        out = np.zeros_like(s)
        for start, step, length in tugs:
            since = s - start
            out += step * quintic(since / length) * (1.0 - q * np.log10(1.0 + np.maximum(since, 0.0) / t0))
        return out
    first = float(pull(np.array([0.0]))[0])
    return lambda s: pull(s) - first


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


class LooseningClampMode(SimOnly):
    """A holder's mode (``f0_hz``, damping ratio ``zeta``) in a clamp whose screw the holder's own vibration loosens
    (Junker): the preload P falls from 1 toward ``floor`` as 1 - exp(-E / E0), E the relative motion the mode has
    made, integral |y - x| dt; E0 ``share`` of what the record would give at full preload. The contact's stiffness
    goes as P^(1/3) (Hertz), so w as P^(1/6), and the damping ratio as P^-0.3 (micro-slip); semi-implicit Euler with
    ``sub`` sub-steps on the uniform grid at the median step, from rest."""

    def __init__(self, f0_hz, zeta, floor, share, sub=4):
        self.w0, self.zeta, self.floor, self.share, self.sub = 2.0 * math.pi * f0_hz, zeta, floor, share, sub

    def motion(self, tu, xu, h):
        """E over the record at full preload (a fixed mode: a digital filter)."""
        w, z = self.w0, self.zeta
        b, a = signal.bilinear([2.0 * z * w, w * w], [1.0, 2.0 * z * w, w * w], fs=1.0 / h)
        y = signal.lfilter(b, a, xu - xu[0]) + xu[0]
        return float(np.sum(np.abs(y - xu)) * h)

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        e0 = max(self.share * self.motion(tu, xu, h), 1e-12)
        rate = np.gradient(xu, h)
        dt = h / self.sub
        y, v, moved, out = float(xu[0]), 0.0, 0.0, np.empty(tu.size)
        for i, (xi, ri) in enumerate(zip(xu.tolist(), rate.tolist())):
            p = 1.0 - (1.0 - self.floor) * -math.expm1(-moved / e0)
            w = self.w0 * p ** (1.0 / 6.0)
            c, k = 2.0 * self.zeta * p ** -0.3 * w, w * w
            for _ in range(self.sub):
                v += (-c * (v - ri) - k * (y - xi)) * dt
                y += v * dt
            moved += abs(y - xi) * h
            out[i] = y
        return np.interp(t, tu, out)


class TelescopingGuideMode(SimOnly):
    """A telescopic needle guide that the robot extends or retracts before each placement (``moves``: start, length,
    extension in [0, 1], a quintic over the length; ``first`` the extension at the first sample): its length 1 +
    ``gain`` e times the retracted one, the cantilever's mode (``f0_hz`` retracted) falling as the length to the power
    -1.5 and its damping ratio (``zeta`` retracted) rising as the power 0.25."""

    def __init__(self, f0_hz, zeta, gain, first, moves):
        self.w0, self.zeta, self.gain, self.first, self.moves = 2.0 * math.pi * f0_hz, zeta, gain, first, moves

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        s = t - t[0]
        ext, level = np.full(s.size, self.first), self.first
        for start, length, goal in self.moves:
            ext = ext + (goal - level) * quintic((s - start) / length)
            level = goal
        length = 1.0 + self.gain * ext
        return switched_mode(t, x, self.w0 * length ** -1.5, self.zeta * length ** 0.25)


# ----------------------------------------------------------------------------- friction

def fretting_debris(band_n, growth, clear_n, sweep, boost):
    """A Coulomb band on the force passed through a needle guide that frets: each reversal after a stroke shorter than
    ``clear_n`` (of the force) adds wear debris, D += ``growth`` (1 - D), and each longer stroke sweeps out ``sweep`` of
    it; the band ``band_n`` (1 + ``boost`` D) / (1 + ``boost`` / 2) (``band_n`` half-way), the same at every load."""
    def passed(t, f):
        f = np.asarray(f, dtype=float)
        p, prev, turn, way, debris, out = float(f[0]), float(f[0]), float(f[0]), 0.0, 0.0, np.empty(f.size)
        for i, fi in enumerate(f.tolist()):
            step = fi - prev
            if step != 0.0:
                direction = 1.0 if step > 0.0 else -1.0
                if direction != way:
                    if way != 0.0:
                        if abs(prev - turn) < clear_n:
                            debris += (1.0 - debris) * growth
                        else:
                            debris *= 1.0 - sweep
                        turn = prev
                    way = direction
            band = band_n * (1.0 + boost * debris) / (1.0 + 0.5 * boost)
            p = max(fi - band, min(fi + band, p))
            prev = fi
            out[i] = p
        return out
    return passed


def breathing_guide(band_n, depth, period_s, wander, wander_s, phase):
    """A Coulomb band on the force passed through a needle guide resting on the patient, whose breathing presses it
    (the band ``band_n`` (1 + ``depth`` sin(phi)), phi advancing at one cycle per ``period_s`` (1 +- ``wander`` over
    ``wander_s``)); times since the first sample."""
    def passed(t, f):
        s = t - t[0]
        period = period_s * (1.0 + wander * np.sin(2.0 * np.pi * s / wander_s + phase))
        phi = 2.0 * np.pi * integrate.cumulative_trapezoid(1.0 / period, s, initial=0.0) + 3.0 * phase
        band = band_n * (1.0 + depth * np.sin(phi))
        return band_play(f, band, band)
    return passed


# ----------------------------------------------------------------------------- thermo-rheological

class UcstGelClock(SimOnly):
    """A core of a thermoresponsive (UCST) gel on the Arrhenius clock exp(b (T_c - T_ref)), T_c the core's temperature
    behind ``lag_s``: above its upper critical solution temperature (at the ``quantile`` of T_c over the record, a
    logistic of ``width_c``) the network takes up solvent and swells (over ``swell_s``; it expels it again over
    ``deswell_s``), the solvent plasticising it: the clock a further ``boost`` e-folds faster per unit of swollen
    share."""

    def __init__(self, c, b_per_c, quantile, width_c, boost, lag_s, swell_s, deswell_s, step_s=0.5):
        self.c, self.b, self.q, self.width, self.boost = c, b_per_c, quantile, width_c, boost
        self.lag, self.swell, self.deswell, self.step = lag_s, swell_s, deswell_s, step_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        core = follow(t, temp_of(aux, t.size), self.lag)
        ucst = float(np.quantile(core, self.q))
        grid, cg = coarse(t, core, self.step)
        goal = 1.0 / (1.0 + np.exp(-(cg - ucst) / self.width))
        share, out = float(goal[0]), np.empty(grid.size)
        for i, g in enumerate(goal.tolist()):
            share = g + (share - g) * math.exp(-self.step / (self.swell if g > share else self.deswell))
            out[i] = share
        at_ref = 1.0 / (1.0 + math.exp(-(T_REF_C - ucst) / self.width))
        rate = np.exp(self.b * (core - T_REF_C) + self.boost * (np.interp(t, grid, out) - at_ref))
        return on_clock(self.c, t, np.asarray(x, dtype=float), rate)


def half_order_lag(t, temp, tau_s, step_s=0.5):
    """``temp`` seen through a half-order lag, 1 / (1 + sqrt(s tau)) (heat diffusing through a thick boot: a step
    answered as 1 - exp(t / tau) erfc(sqrt(t / tau))), on a coarse grid of ``step_s``, settled at the start."""
    grid, tg = coarse(t, temp, step_s)
    steps = np.diff(tg, prepend=tg[0])
    answer = 1.0 - special.erfcx(np.sqrt(np.arange(grid.size) * step_s / tau_s))
    return np.interp(t, grid, tg[0] + np.convolve(steps, answer)[:grid.size])


class PottedBootClock(SimOnly):
    """A core potted in a thick silicone boot (its temperature the air's through a half-order lag, ``tau_s``) on the
    WLF clock with the universal constants (17.44, 51.6 K at the glass transition), re-referenced to T_ref placed
    above the glass transition so that the clock's slope there is ``b_per_c``: log_e rate = ln 10 C1' dT / (C2' + dT)."""

    def __init__(self, c, b_per_c, tau_s):
        c2 = math.sqrt(math.log(10.0) * 17.44 * 51.6 / b_per_c)
        self.c, self.c1, self.c2, self.tau = c, 17.44 * 51.6 / c2, c2, tau_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        dt = half_order_lag(t, temp_of(aux, t.size), self.tau) - T_REF_C
        rate = np.exp(math.log(10.0) * self.c1 * dt / (self.c2 + dt))
        return on_clock(self.c, t, np.asarray(x, dtype=float), rate)


# ----------------------------------------------------------------------------- outside the catalogue

class InterleavedConverters(SimOnly):
    """A DAQ whose converter is two time-interleaved ADCs taking turns sample by sample, their gains ``mismatch`` apart
    (each +- half of it): the bridge signal (less its offset) times 1 +- mismatch / 2, alternating."""

    def __init__(self, mismatch):
        self.mismatch = mismatch

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        sign = np.where(np.arange(x.size) % 2 == 0, 0.5, -0.5)
        return x * (1.0 + self.mismatch * sign)


class SpiBitSlips(SimOnly):
    """Bit slips on the SPI link from the ADC while the CT scans (``scans``: start, length in seconds since the first
    sample): each word then has a chance ``prob`` of arriving shifted by one bit, doubled or halved (even odds); drawn
    from ``seed``."""

    def __init__(self, scans, prob, seed):
        self.scans, self.prob, self.seed = scans, prob, seed

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        rng = np.random.default_rng(self.seed)
        hit = (rng.random(x.size) < self.prob) & within(t - t[0], self.scans)
        left = rng.random(x.size) < 0.5
        return np.where(hit, np.where(left, 2.0 * x, 0.5 * x), x)


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([6e4, 8e3]))))  # V / (N s)
        if shape == "gas_seepage":
            rule = gas_seepage(phi * rng.uniform(0.5, 1.0), rng.uniform(1.0, 4.0), rng.uniform(0.0, 1.0))
            return Parts("zener", ZenerWithFlow(c, rule), core_changed=True)
        rule = excess_flow_fuse(phi * rng.uniform(1.5, 3.0), phi * rng.uniform(0.05, 0.25), rng.uniform(2.5, 6.0),
                                rng.uniform(0.1, 0.4))
        return Parts("zener", ZenerWithFlow(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        compliance = float(np.interp(m, [0, 1], [0.03, 0.2])) / g0  # V / N: a share of the instantaneous response
        if shape == "rubber_balloon":
            a = (compliance, rng.uniform(3.0, 5.0), rng.uniform(1.02, 1.12), rng.uniform(1.22, 1.32),
                 rng.uniform(2.0, 20.0))
            p.extra.append(lambda t, f, T, a=a: rubber_balloon(t, f, *a))
            return p
        a = (compliance, rng.uniform(0.5, 4.0), rng.uniform(0.3, 2.0))
        p.extra.append(lambda t, f, T, a=a: capillary_standpipe(t, f, *a))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.01, 0.06]))
        if shape == "leaf_spring":
            share, spread = rng.uniform(0.3, 0.7), rng.uniform(1.5, 2.5)
            p.before.append(ForcePath(leaf_spring(frac * spread * share, frac * spread * (1.0 - share),
                                                  rng.uniform(0.1, 0.6))))
            return p
        n = int(rng.integers(3, 6))
        halves = (top * rng.uniform(0.03, 0.2, n)).tolist()
        centres = [top * rng.uniform(0.02, 0.9, int(rng.integers(6, 13))) for _ in range(n)]
        ramps = [top * rng.uniform(0.05, 0.3, k.size) for k in centres]
        weights = [rng.uniform(0.2, 1.0, k.size) for k in centres]
        domains = DomainSwitching(halves, centres, ramps, weights)
        domains.gain = frac * top / max(domains.loop_height(top), 1e-9)
        return Parts("burgers", c, after=[domains])
    if effect == "sensor_lag":
        delay = float(np.interp(m, [0, 1], [0.012, 0.09]))
        if shape == "pneumatic_line":
            transit = min(delay * rng.uniform(0.15, 0.35), 0.023)
            p.after.append(PneumaticLine(transit, delay * rng.uniform(0.8, 1.2) - transit, rng.uniform(0.3, 1.5), top))
            return p
        p.after.append(TwoTapComb(2.0 * delay * rng.uniform(0.8, 1.2), rng.uniform(0.001, 0.003)))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.05, 0.16]))
        if shape == "liquid_metal_gauge":
            p.after.append(StaticMap(liquid_metal_gauge(rel, top, rng.random() < 0.5)))
            return p
        p.after.append(StaticMap(lateral_magnet(rel, top, rng.uniform(-0.35, 0.1))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.022]) * rng.choice([-1, 1]))
        if shape == "belleville_preload":
            a = (k, rng.uniform(1.1, 1.5), rng.uniform(0.7, 1.2), rng.uniform(0.04, 0.12), rng.uniform(10.0, 40.0))
            p.extra.append(lambda t, f, T, a=a: belleville_zero(t, T, *a))
            return p
        a = (k, rng.uniform(-1.5, 2.5), rng.uniform(2.0, 6.0), rng.uniform(5.0, 20.0))
        p.extra.append(lambda t, f, T, a=a: quartz_timebase_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.008, 0.02]))
        if shape == "ptc_ink_leads":
            p.after.append(PtcLeadSpan(a, rng.uniform(max(0.02, 1.25 * a), 0.08), rng.uniform(5.0, 25.0)))
            return p
        p.after.append(OptocouplerSpan(a * rng.choice([-1, 1]), rng.uniform(8.0, 20.0), rng.uniform(10.0, 40.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.012, 0.08]) * rng.choice([-1, 1]))
        zero = normalised(alcohol_wipes(rng) if shape == "alcohol_wipes" else drape_tugs(rng), size)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.03, 0.008])) * rng.uniform(0.8, 1.2)
        if shape == "loosening_clamp":
            p.after.append(LooseningClampMode(rng.uniform(15.0, 45.0), zeta, rng.uniform(0.4, 0.7),
                                              rng.uniform(0.2, 1.0)))
            return p
        moves = [(start, length, float(rng.uniform(0.0, 1.0))) for start, length in
                 schedule(rng, (20.0, 90.0), (1.0, 4.0))]
        p.after.append(TelescopingGuideMode(rng.uniform(25.0, 55.0), zeta, rng.uniform(0.3, 0.8), rng.uniform(0.0, 1.0),
                                            moves))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "fretting_debris":
            p.before.append(ForcePath(fretting_debris(r, rng.uniform(0.05, 0.2), rng.uniform(0.3, 1.5),
                                                      rng.uniform(0.5, 0.9), rng.uniform(0.5, 1.2))))
            return p
        p.before.append(ForcePath(breathing_guide(r, rng.uniform(0.3, 0.7), rng.uniform(3.0, 5.5), rng.uniform(0.0, 0.1),
                                                  rng.uniform(60.0, 200.0), rng.uniform(0.0, 2.0 * np.pi))))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.15, 0.4]))
        if shape == "ucst_gel_clock":
            return Parts("burgers", UcstGelClock(c, b, rng.uniform(0.4, 0.8), rng.uniform(0.2, 0.6), rng.uniform(0.3, 1.0),
                                                 rng.uniform(5.0, 20.0), rng.uniform(20.0, 80.0),
                                                 rng.uniform(60.0, 240.0)), core_changed=True)
        # the boot passes 60-80 % of a minute's swing of the air: a steeper clock behind it
        return Parts("burgers", PottedBootClock(c, b * rng.uniform(1.2, 1.6), rng.uniform(3.0, 15.0)), core_changed=True)
    if effect == "interleaved_converters":
        p.after.append(InterleavedConverters(float(np.interp(m, [0, 1], [0.02, 0.08])) / top))
        return p
    if effect == "spi_bit_slips":
        scans = schedule(rng, (15.0, 60.0), (2.0, 10.0))
        p.outer.append(SpiBitSlips(scans, float(np.interp(m, [0, 1], [0.002, 0.01])), int(rng.integers(1 << 30))))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["gas_seepage", "excess_flow_fuse"],
    "delayed_elasticity": ["rubber_balloon", "capillary_standpipe"],
    "hysteresis": ["leaf_spring", "piezoceramic_domains"],
    "sensor_lag": ["pneumatic_line", "two_tap_comb"],
    "nonlinear_gain": ["liquid_metal_gauge", "lateral_magnet"],
    "thermal_drift": ["belleville_preload", "quartz_timebase"],
    "thermal_sensitivity": ["ptc_ink_leads", "optocoupler_ctr"],
    "offset_drift": ["alcohol_wipes", "drape_tugs"],
    "resonance": ["loosening_clamp", "telescoping_guide"],
    "friction": ["fretting_debris", "breathing_guide"],
    "thermo_rheological": ["ucst_gel_clock", "potted_boot_clock"],
}
PAIRS = (("viscous_flow", "offset_drift"), ("delayed_elasticity", "thermal_sensitivity"), ("hysteresis", "friction"),
         ("sensor_lag", "nonlinear_gain"), ("thermal_drift", "thermo_rheological"), ("resonance", "delayed_elasticity"))
OUTSIDE = ("interleaved_converters", "spi_bit_slips")
RATES = (120.0, 350.0, 620.0, 840.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split V", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8),
                   pair_shapes=(-1, 0), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.1e-3, 2.5e-3), jitter=0.3,
                   gap_s=(0.2, 2.4))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
