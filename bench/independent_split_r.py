"""Independent split R for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split R is an untouched held-out set: written before the engine it measures and blind to it (to how it detects and
fits anything), run once at its end, never used to choose anything. Every name of the catalogue is hidden in two
shapes that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A to Q use:

* printed struts that crack at each new peak of the force, every crack leaving a ligament that flows (the fluidity
  rising from 0.6-1.1 times the plain one, 1/60000-1/4000 V/(N s), to 3-6 times that as the largest force so far
  passes from 0.5-2.5 N to 6 N, as a power 1-2 of the excess, and no more beyond; it never recovers), or a
  fluid-filled core whose oil leaks through a long printed labyrinth (a laminar pressure drop, linear in the rate, in
  series with a turbulent one as its power 1.75 (Blasius), equal at 0.5-2 N: the rate linear in the force below
  that, as F^0.57 above; 1.5-3 times the plain fluidity at 3 N);
* a core's fast creep (3-22 % of each change of the output over 0.5-5 s) that the gauge carrier's negative creep (0.6
  to 1.3 times as much, 4-15 times slower) was meant to cancel: the output creeps, then creeps back short of or past
  its start (a compensated load cell's creep mismatch), or a Kelvin unit (0.006-0.06 V/N, 4-30 s) whose dashpot is a
  thixotropic gel: its structure, broken down by its own deformation (an e-fold per what 0.3-1.5 N gives) and rebuilt
  at rest (15-90 s), sets the retardation time (15-40 % of it once broken: the creep starts slowly after a rest and
  speeds up as it goes);
* a carbon-filled printed gauge read directly, whose unloading passes through a shoulder (its conductive network
  breaking and re-forming: a bump of 1.5-15 % of the excursion's peak, largest 25-50 % of the way down; loading follows
  the backbone, reloading within an excursion fades back to it at the excursion's peak), or a soft printed contact
  pad read through its contact area, whose adhesion (JKR) is 3-8 times larger while its contact line recedes than
  while it advances (a loop of 1.2-11 % of the range, largest near no load, the contact line switching over 2-8 % of
  the range's travel);
* an anti-alias Sallen-Key low-pass (a delay of 5-54 ms, quality 0.55-0.75) whose class-II (Y5V) ceramic capacitors
  lose capacitance as the electronics warm (a Lorentzian peaked at 0-15 degC, 20-40 degC wide; lag 10-40 s), or a
  carrier read by a true-RMS converter (an exponential average of the square over 6-72 ms, then the square root, its
  sign from a phase comparator: a fast rise, a slow fall);
* the wiper of a printed potentiometric track loaded by the amplifier's input resistance (a / (1 + k a (1 - a)), the
  range over 31-50 % of the track from 0-8 % of it: a compression of 5-16 % at the top of the range), or a clamped
  diaphragm electrode read as a capacitance over a gap (artanh(sqrt(s)) / sqrt(s), s the centre's deflection over the
  gap: an expansion of 5-16 % at the top of the range);
* the water in a thin printed skin over the gauges, which swells it (at a fixed absolute humidity the air's relative
  humidity falls as it warms, by the Magnus slope of 6 %/degC, and the skin's water follows it by Fickian diffusion,
  L^2 / D 300-1500 s: 0.009-0.066 V/degC at equilibrium), or a printed membrane clamped in a stiffer frame that buckles
  as it warms (an imperfect pitchfork, w^3 - theta w = e, setting in 2 degC below to 1.5 degC above the reference over
  0.7-1.5 degC, an imperfection of 2-15 %: 0.01-0.053 V for the deflection one such width past the onset, growing as
  the square root of the excess; lag 10-40 s);
* an optical read-out through a dyed light guide whose LED's wavelength drifts with its junction's temperature (lag
  5-30 s) along the dye's (Urbach) absorption edge (the span exp(-a (exp(-beta dT) - 1)): 3-13 % higher 4 degC to one
  side of the reference, falling faster and faster to the other), or an optical read-out lit by a laser diode through
  a fibre whose parasitic etalon sweeps a fringe as the fibre's temperature (lag 10-60 s) changes its optical path
  (the span periodic in the temperature, a period of 2-6 degC, 1.5-8 % either way); the zero of both a closed shutter;
* ambient light through the translucent printed housing (the room's lights dimmed to 10-40 % for 3-6 scan sessions
  of 30-120 s, the gantry's positioning lasers on for 5-20 s at 6-20 table moves, an examination lamp swung in 0-2
  times; 12-80 mV at most), or electrochemical migration on a bridge board contaminated with saline (dendrites whose
  leakage grows as a power 1.5-3 of their age over 40-150 s and then fuse within 0.1-1 s, leaving 0-30 % of it, 5-40 s
  before the next; 12-80 mV at most);
* a mode of the robot's belt-driven carriage (18-40 Hz mid-belt, stiffer toward either end as the belt's two free
  lengths change, up to 1.5 times the frequency; the carriage moved every 10-40 s), or a mode (20-50 Hz) whose inertial
  error an accelerometer on the moving mass measures and the DAQ subtracts, 30-70 % of it, 0.5-3 ms late; both with a
  damping ratio of 0.012-0.072;
* a rubber septum on the needle whose grip, and so its Coulomb band, relaxes to 25-65 % over 3-30 s while the needle
  is in it (the force above 0.05-0.2 N) and recovers over 2-10 s when it is out (1.2-1.6 times 0.5-3 % of the range at
  full grip), or a self-locking collet that sets deeper under the push (its band 0.5-3 % of the range after a 4 N
  push, 20-50 % of that with none, growing with the largest force since the force last fell below 0.1-0.3 N);
* an Arrhenius clock (0.09-0.26 per degC) on a core buffered by a paraffin jacket whose temperature stalls while it
  melts (0.5 degC below to 2 degC above the reference, over 0.3-1 degC, a latent heat worth 1-4 degC of its sensible
  heat; the jacket follows the air with 20-60 s, the core the jacket with 5-20 s), or on a core confined by a stiffer
  sleeve that it presses as it warms (lag 10-40 s): the pressure slows the clock by 40-80 % of what the warming speeds
  it, and relaxes through the core's own creep (30-150 s at the reference).

It also holds six pairs, two effects outside the catalogue (the patient's ECG coupled into the bridge through the
needle or tool while it touches the patient, an R wave of 4-40 mV at 55-110 beats per minute with a respiratory
arrhythmia; the radiation-induced darkening of an optical read-out's fibre during 6-20 runs of CT fluoroscopy of 2-12
s, which lowers the span by 1-8 % at most and partly anneals (30-60 % stays, the rest as 1 / (1 + t / 20-120 s))) and
four clean records. Profiles: CT-guided fine-needle aspiration through a coaxial introducer, which the robot drives
through the measured force-depth curve (``../shared/data``, ``depth_force.csv``, its first insertion split into the
shaft's friction and the cutting peaks) to 40-70 % of its depth at 1-3 mm/s in 2-3 advances with check scans (the
tissue relaxing), before 3-6 aspiration passes that move to and fro in the lesion beyond the introducer's tip
(synthetic layers when the data are absent); a vertebroplasty (a trocar tapped into the vertebra with a mallet, then
cement injected by turns of a screw injector while it cures); and a robotic catheter drive advancing in strokes
through bends (capstan friction), catches at branch ostia and the arterial pulse. Rates 170, 390, 630 and 870 Hz (a
mode at 1000 Hz with knocks that excite it), 1.3-2.6 mV noise, stamp jitter, gaps, and a sensor under the sterile
drape beside a patient warmed by a forced-air blanket (the room 0.5-3 degC below the reference, the blanket's setting
changed and the drape lifted now and then).

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_r.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, optimize

from polyforce_ros.physics.expconv import exp_convolve
from polyforce_ros.physics.viscoelastic import simulate_deformation
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (band_play, coarse, dead_time, ForcePath, kelvin, LinearFilter, mode_steps, Parts, quintic,
                       ShapeSplit, SimOnly, uniform_grid, ZenerWithFlow)

SEED0 = 1_240_000  # never a seed of the registry's splits nor of splits A (90000..) to Q (1170000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 440.0


# ----------------------------------------------------------------------------- profiles and temperature

def spans(t):
    """``span(now, length)``: the slice of ``t`` in [now, now + length) and the times since ``now`` there."""
    def span(now, length):
        i0, i1 = np.searchsorted(t, [now, now + length])
        return slice(int(i0), int(i1)), t[i0:i1] - now
    return span


@functools.lru_cache(maxsize=1)
def measured_depth_force(bin_mm=0.1):
    """The measured force-depth curve (``../shared/data/needle_insertion_okamura/depth_force.csv``), or None when it is
    absent: its first insertion binned on ``bin_mm`` (the mean force per bin, empty bins interpolated) and split into
    the shaft's friction (the lower envelope from the deepest point back, non-decreasing with depth) and the rest (the
    stiffness build-ups and cutting peaks). A dict of arrays over depth in mm."""
    csv = profiles.okamura_csv_path()
    if csv is None or not (csv.parent / "depth_force.csv").is_file():
        return None
    raw = np.loadtxt(csv.parent / "depth_force.csv", delimiter=",", ndmin=2)
    depth, force = 1e3 * raw[:, 0], raw[:, 1]
    jumps = np.flatnonzero(np.diff(depth) < -5.0)  # the needle withdrawn: the first insertion ends there
    end = int(jumps[0]) + 1 if jumps.size else depth.size
    depth, force = depth[:end], force[:end]
    grid = np.arange(0.0, float(depth.max()) + bin_mm, bin_mm)
    which = np.clip(np.round(depth / bin_mm).astype(int), 0, grid.size - 1)
    count = np.bincount(which, minlength=grid.size)
    total = np.bincount(which, weights=force, minlength=grid.size)
    filled = count > 0
    mean = np.maximum(np.interp(grid, grid[filled], total[filled] / count[filled]), 0.0)
    friction = np.minimum.accumulate(mean[::-1])[::-1]
    return {"depth": grid, "friction": friction, "cutting": mean - friction}


def synthetic_depth_force(rng):
    """What :func:`measured_depth_force` gives, made up: a shaft friction growing 0.008-0.02 N/mm over 50 mm and 2-4
    layers that build up over 2-6 mm and tear (leaving 20 % that fades over 0.5 mm)."""
    grid = np.arange(0.0, 50.0, 0.1)
    cutting = np.zeros_like(grid)
    for at in np.sort(rng.uniform(5.0, 45.0, int(rng.integers(2, 5)))):
        build, height = rng.uniform(2.0, 6.0), rng.uniform(0.3, 1.0)
        rising = (grid > at - build) & (grid <= at)
        cutting[rising] += height * (grid[rising] - at + build) / build
        torn = grid > at
        cutting[torn] += 0.2 * height * np.exp(-(grid[torn] - at) / 0.5)
    return {"depth": grid, "friction": rng.uniform(0.008, 0.02) * grid, "cutting": cutting}


def coaxial_fna(duration_s, rate_hz, rng):
    """CT-guided fine-needle aspiration through a coaxial introducer, the sensor behind the robot's needle driver. The
    introducer is driven through the measured force-depth curve (``measured_depth_force``, scaled to a 2.5-7 N peak on
    the way in) to 40-70 % of its depth at 1-3 mm/s, in 2-3 advances each followed by a check scan (a hold of 5-15 s,
    10-25 s for the last, the confirmation, in which the force relaxes to 55-85 % of its value with a time constant of
    1-3 s; the next advance re-engages the curve over 0.8 mm). The stylet is pulled out (the force falls in 0.3 s; 3-8 s
    pass) and the aspiration needle makes 3-6 passes through the introducer: it slides in at 4-10 mm/s against the
    introducer's lining (0.1-0.4 N at full length), then moves to and fro 4-10 times in the lesion beyond the
    introducer's tip (4-10 mm strokes at 1-2 Hz) against the tissue's force there (the measured friction and cutting
    beyond the tip, scaled by 1.5-4 N over the curve's peak; tissue already cut by an earlier stroke cut again at
    30-60 %); each pull reads nothing (the sensor reads push only). 3-8 s between passes (the smear is made), 8-20 s
    before the next introducer. Made-up layers (``synthetic_depth_force``) when ``../shared/data`` is absent."""
    curve = measured_depth_force() or synthetic_depth_force(rng)
    depth_mm, friction, cutting = curve["depth"], curve["friction"], curve["cutting"]
    total = friction + cutting
    peak_n = max(float(total.max()), 1e-3)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    span = spans(t)
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 40.0:
        target, speed = rng.uniform(0.4, 0.7) * depth_mm[-1], rng.uniform(1.0, 3.0)
        scale = rng.uniform(2.5, 7.0) / max(float(total[depth_mm <= target].max()), 1e-3)  # the peak on the way in
        reached, relaxed = 0.0, 0.0
        stops = target * np.cumsum(rng.dirichlet(np.ones(int(rng.integers(2, 4)))))
        for stop in stops:
            seg, s = span(now, (stop - reached) / speed)
            on_curve = scale * np.interp(reached + speed * s, depth_mm, total)
            f[seg] = relaxed + (on_curve - relaxed) * quintic(s * speed / 0.8)
            now += (stop - reached) / speed
            last = scale * float(np.interp(stop, depth_mm, total))
            hold = rng.uniform(10.0, 25.0) if stop == stops[-1] else rng.uniform(5.0, 15.0)  # the last: a confirmation
            keep, tau = rng.uniform(0.55, 0.85), rng.uniform(1.0, 3.0)
            seg, s = span(now, hold)
            f[seg] = last * (keep + (1.0 - keep) * np.exp(-s / tau))
            now += hold
            reached, relaxed = stop, last * (keep + (1.0 - keep) * math.exp(-hold / tau))
        seg, s = span(now, 0.3)
        f[seg] = relaxed * (1.0 - quintic(s / 0.3))
        now += 0.3 + rng.uniform(3.0, 8.0)
        lining, fna, again = rng.uniform(0.1, 0.4), rng.uniform(1.5, 4.0) / peak_n, rng.uniform(0.3, 0.6)
        deepest = target
        for _ in range(int(rng.integers(3, 7))):
            slide = rng.uniform(4.0, 10.0)
            seg, s = span(now, target / slide)
            f[seg] = lining * s * slide / target * quintic(s / 0.1)
            now += target / slide
            amp, freq, strokes = rng.uniform(4.0, 10.0), rng.uniform(1.0, 2.0), int(rng.integers(4, 11))
            seg, s = span(now, strokes / freq)
            depth = target + 0.5 * amp * (1.0 - np.cos(2.0 * np.pi * freq * s))
            fresh = depth >= np.maximum.accumulate(np.maximum(depth, deepest))
            beyond = fna * (np.interp(depth, depth_mm, friction) - float(np.interp(target, depth_mm, friction))
                            + np.interp(depth, depth_mm, cutting) * np.where(fresh, 1.0, again))
            f[seg] = (lining + beyond) * quintic(0.5 + np.sin(2.0 * np.pi * freq * s) / 0.4)  # pushing strokes only
            deepest = max(deepest, float(depth.max())) if depth.size else deepest
            now += strokes / freq + rng.uniform(3.0, 8.0)
        now += rng.uniform(8.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def vertebroplasty(duration_s, rate_hz, rng):
    """Vertebroplasty under CT, the sensor in the robot's trocar holder and then in its cement injector. The trocar is
    tapped into the vertebra with a mallet: 15-40 taps 0.7-1.5 s apart (+-15 %), half-sines of 8-25 ms and 2-5 N
    (falling to half by the last as the trocar passes from cortical into cancellous bone, +-20 % each) on a hold that
    rises from 0.5-1.2 to 1.5-3 N as the trocar engages. The stylet is pulled out (0.3 s) and the cement mixed (5-15 s).
    Then the robot turns the injector's screw every 2-5 s: each turn raises the force by 0.5-1.5 N in 0.2-0.5 s, which
    relaxes as the cement flows out of the cannula toward a yield of 0.3-0.8 N (a time constant of 0.8-2.5 s); the
    cement cures, its viscosity doubling every 60-150 s, and both the steps and the relaxation grow as its square root;
    10-30 turns, or until a turn reaches 7 N. Released in 0.4 s; 10-30 s to the next level."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    span = spans(t)
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 60.0:
        taps = int(rng.integers(15, 41))
        gaps = rng.uniform(0.7, 1.5) * rng.uniform(0.85, 1.15, taps)
        hold0, hold1, length = rng.uniform(0.5, 1.2), rng.uniform(1.5, 3.0), float(gaps.sum()) + 0.5
        seg, s = span(now, length)
        f[seg] = (hold0 + (hold1 - hold0) * quintic(s / length)) * quintic(s / 0.5)
        for k, at in enumerate(0.5 + np.cumsum(gaps) - gaps[0]):
            width = rng.uniform(0.008, 0.025)
            seg, s = span(now + at, width)
            f[seg] += rng.uniform(2.0, 5.0) * (1.0 - 0.5 * k / taps) * rng.uniform(0.8, 1.2) * np.sin(np.pi * s / width)
        now += length
        seg, s = span(now, 0.3)
        f[seg] = hold1 * (1.0 - quintic(s / 0.3))
        now += 0.3 + rng.uniform(5.0, 15.0)
        doubling, step, relax, yield_n = rng.uniform(60.0, 150.0), rng.uniform(0.5, 1.5), rng.uniform(0.8, 2.5), \
            rng.uniform(0.3, 0.8)
        start, level = now, 0.0
        for _ in range(int(rng.integers(10, 31))):
            thick = math.sqrt(2.0 ** ((now - start) / doubling))  # the square root of the cement's relative viscosity
            rise, wait = rng.uniform(0.2, 0.5), rng.uniform(2.0, 5.0)
            peak = min(level + step * thick, FORCE_MAX_N - 0.5)
            seg, s = span(now, rise)
            f[seg] = level + (peak - level) * quintic(s / rise)
            now += rise
            base, tau = yield_n * thick, relax * thick
            seg, s = span(now, wait)
            f[seg] = base + (peak - base) * np.exp(-s / tau)
            level = base + (peak - base) * math.exp(-wait / tau)
            now += wait
            if peak >= 7.0:
                break
        seg, s = span(now, 0.4)
        f[seg] = level * (1.0 - quintic(s / 0.4))
        now += 0.4 + rng.uniform(10.0, 30.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def catheter_advance(duration_s, rate_hz, rng):
    """A robotic catheter drive (the sensor behind its gripper) navigating 250-600 mm of vessel: the push is the
    haemostatic valve's friction (0.2-0.6 N) plus the catheter's friction along its inserted length, raised by the
    capstan effect of the bends it has passed (a bend every 40-120 mm, 20-70 degrees each, mu 0.1-0.25: exp(mu theta)),
    scaled to a 2.5-7 N peak; the tip catches at 1-3 branch ostia per 100 mm (the push rising by 0.5-2 N over 2-5 mm,
    then released at once as it slips past), and the arterial pulse (1-1.6 Hz) modulates the friction by 3-8 %. The
    gripper advances in strokes of 10-25 mm at 5-15 mm/s (a grip of 80 ms at the start, a release of 50 ms at the end)
    and regrips in 0.3-0.8 s, reading nothing meanwhile; 10-30 s between navigations."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    span = spans(t)
    now = rng.uniform(2.0, 5.0)
    while now < duration_s - 30.0:
        reach = rng.uniform(250.0, 600.0)
        grid = np.arange(0.0, reach + 1.0, 0.5)
        bends = np.cumsum(rng.uniform(40.0, 120.0, 32))
        wrap = np.concatenate([[0.0], np.cumsum(np.radians(rng.uniform(20.0, 70.0, bends.size)))])
        drag = grid * np.exp(rng.uniform(0.1, 0.25) * wrap[np.searchsorted(bends, grid, side="right")])
        valve = rng.uniform(0.2, 0.6)
        push = valve + drag * (rng.uniform(2.5, 7.0) - valve) / max(float(drag.max()), 1e-9)
        catches = rng.uniform(20.0, reach, max(1, int(rng.uniform(1.0, 3.0) * reach / 100.0)))
        for at, height, length in zip(catches, rng.uniform(0.5, 2.0, catches.size), rng.uniform(2.0, 5.0, catches.size)):
            rising = (grid > at - length) & (grid <= at)
            push[rising] += height * (grid[rising] - at + length) / length
        pulse, depth, phase = rng.uniform(1.0, 1.6), rng.uniform(0.03, 0.08), rng.uniform(0.0, 2.0 * np.pi)
        done = 0.0
        while done < reach - 1e-9 and now < duration_s:
            stroke, speed = min(rng.uniform(10.0, 25.0), reach - done), rng.uniform(5.0, 15.0)
            seg, s = span(now, stroke / speed)
            f[seg] = np.interp(done + speed * s, grid, push) * quintic(s / 0.08) \
                * (1.0 + depth * np.sin(2.0 * np.pi * pulse * (now + s) + phase))
            last = float(f[seg][-1]) if s.size else 0.0
            now, done = now + stroke / speed, done + stroke
            seg, s = span(now, 0.05)
            f[seg] = last * (1.0 - quintic(s / 0.05))
            now += rng.uniform(0.3, 0.8)
        now += rng.uniform(10.0, 30.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (coaxial_fna, vertebroplasty, catheter_advance)


def temperature(t, rng, step_s=0.5):
    """A sensor under the sterile drape of a CT-guided procedure, beside a patient kept warm by a forced-air blanket:
    the room's air conditioning holds it 0.5-3 degC below the reference, drifting by up to +-0.4 degC over the record
    and swinging by 0.03-0.12 degC (a period of 300-900 s). The drape went on 150-600 s before the record; from then
    the air under it approaches the blanket's setting (medium, 2.5-4 degC above the room, or high, 4.5-7 degC, at
    first; 1-3 changes during the record to off, low (1-2 degC), medium or high) with a time constant of 60-180 s, and
    2-5 times the radiologist lifts the drape for 5-30 s, the air under it then falling toward the room's with 8-20 s.
    The sensor follows that air with a time constant of 20-60 s (exact per step of ``step_s``), from 600 s before the
    record, at the room's temperature then."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-600.0, d + 2.0 * step_s, step_s)
    room = T_REF_C + rng.uniform(-3.0, -0.5) + rng.uniform(-0.4, 0.4) * grid / d \
        + rng.uniform(0.03, 0.12) * np.sin(2.0 * np.pi * grid / rng.uniform(300.0, 900.0) + rng.uniform(0.0, 2.0 * np.pi))
    settings = {"off": (0.0, 0.0), "low": (1.0, 2.0), "medium": (2.5, 4.0), "high": (4.5, 7.0)}
    changes = np.concatenate([[rng.uniform(-600.0, -150.0)], np.sort(rng.uniform(0.0, d, int(rng.integers(1, 4))))])
    names = [str(rng.choice(["medium", "high"]))] + [str(rng.choice(list(settings))) for _ in changes[1:]]
    levels = np.array([0.0] + [rng.uniform(*settings[n]) for n in names])
    goal = levels[np.searchsorted(changes, grid, side="right")]
    lifted = np.zeros(grid.size, dtype=bool)
    for at, length in zip(rng.uniform(0.0, d, int(rng.integers(2, 6))), rng.uniform(5.0, 30.0, 5)):
        lifted |= (grid >= at) & (grid < at + length)
    blanket, lift = math.exp(-step_s / rng.uniform(60.0, 180.0)), math.exp(-step_s / rng.uniform(8.0, 20.0))
    keep = math.exp(-step_s / rng.uniform(20.0, 60.0))
    excess, y, out = 0.0, float(room[0]), np.empty(grid.size)
    for i, (g, up, r) in enumerate(zip(goal.tolist(), lifted.tolist(), room.tolist())):
        out[i] = y
        excess = excess * lift if up else g + (excess - g) * blanket
        y = r + excess + (y - r - excess) * keep
    return np.interp(s, grid, out)


# ----------------------------------------------------------------------------- simulate-only truth elements

def temp_of(aux, n):
    """The chain's temperature as an array of ``n`` samples."""
    return np.broadcast_to(np.asarray(aux["temperature_c"], dtype=float), (n,))


def follow(t, temp, tau_s, step_s=0.5):
    """``temp`` seen by a body that follows it with a time constant ``tau_s`` (exact per coarse step), settled at
    the start."""
    grid, tg = coarse(t, temp, step_s)
    keep, y = math.exp(-step_s / tau_s), float(tg[0])
    out = np.empty_like(tg)
    for i, goal in enumerate(tg.tolist()):
        y = goal + (y - goal) * keep
        out[i] = y
    return np.interp(t, grid, out)


def lowpass(t, x, tau_s):
    """``x`` through a first-order lag of ``tau_s``, settled at ``x[0]``."""
    return x[0] + kelvin(t, x - x[0], 1.0, tau_s)


def overload_cracked_flow(fluidity, gain, onset_n, power, full_n=6.0):
    """x' = A(P) F: the fluidity A = ``fluidity`` (1 + (``gain`` - 1) u^``power``), u = (P - F_0) / (``full_n`` - F_0)
    held within [0, 1], P the largest force so far (struts cracked by each new peak, every crack leaving a ligament
    that flows)."""
    def rule(t, f):
        peak = np.maximum.accumulate(np.maximum(f, 0.0))
        excess = np.clip((peak - onset_n) / (full_n - onset_n), 0.0, 1.0)  # every strut cracked by ``full_n``
        rate = fluidity * (1.0 + (gain - 1.0) * excess ** power) * np.maximum(f, 0.0)
        return integrate.cumulative_trapezoid(rate, t, initial=0.0)
    return rule


@functools.lru_cache(maxsize=1)
def blasius_table(top=200.0, n=4001):
    """rho(phi) solving rho + rho^1.75 = 2 phi on phi in [0, ``top``] (a laminar and a turbulent (Blasius) pressure
    drop in series, equal at phi = 1), by Newton from the larger of the two limits."""
    phi = np.linspace(0.0, top, n)
    rho = np.minimum(2.0 * phi, (2.0 * phi) ** (1.0 / 1.75))
    for _ in range(50):
        rho = np.maximum(rho - (rho + rho ** 1.75 - 2.0 * phi) / (1.0 + 1.75 * rho ** 0.75), 0.0)
    return phi, rho


def labyrinth_flow(fluidity, transition_n):
    """x' = r(F) solving F = r / A + b r^1.75 (the oil of a fluid-filled core leaking through a long labyrinth: a
    laminar drop linear in the rate, a turbulent one as its power 1.75, equal at ``transition_n``); r = A F at light
    loads, A = ``fluidity``."""
    phi, rho = blasius_table()

    def rule(t, f):
        rate = 0.5 * fluidity * transition_n * np.interp(np.maximum(f, 0.0) / transition_n, phi, rho)
        return integrate.cumulative_trapezoid(rate, t, initial=0.0)
    return rule


def mismatched_compensation(core_share, bond_share, core_s, bond_s):
    """x + s1 lag(x - x0, tau1) - s2 lag(x - x0, tau2): a creep of the core (``core_share`` of each change of the
    output over ``core_s``) that the gauge carrier's negative creep (``bond_share`` over ``bond_s``) was meant to
    cancel."""
    def passed(t, x):
        d = x - x[0]
        return x + core_share * kelvin(t, d, 1.0, core_s) - bond_share * kelvin(t, d, 1.0, bond_s)
    return passed


def thixotropic_kelvin(t, f, compliance, tau_s, broken, rebuild_s, break_v, step_s=0.02):
    """A Kelvin unit tau(lambda) w' = c F - w whose gel dashpot thins as its structure lambda breaks down: tau =
    ``tau_s`` (r + (1 - r) lambda), r = ``broken``; lambda' = (1 - lambda) / ``rebuild_s`` - lambda |w'| / ``break_v``
    (broken by its own rate of deformation, rebuilt at rest). Exact per step of ``step_s`` at the step's state, from
    rest and a whole structure."""
    grid, fg = coarse(t, f, step_s)
    w, structure, rate, out = 0.0, 1.0, 0.0, np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        out[i] = w
        shear = 1.0 / rebuild_s + rate / break_v
        structure = (1.0 / rebuild_s) / shear + (structure - (1.0 / rebuild_s) / shear) * math.exp(-shear * step_s)
        goal = compliance * fi
        moved = (goal - w) * -math.expm1(-step_s / (tau_s * (broken + (1.0 - broken) * structure)))
        w += moved
        rate = abs(moved) / step_s
    return np.interp(t, grid, out)


class ShoulderPeak(SimOnly):
    """A carbon-filled printed gauge read directly, whose unloading passes through a shoulder: y = x + d, d = 0 on
    the loading backbone; unloading from a turning point (x_a, d_a), d = d_a x / x_a + ``kappa`` x_a b(u),
    u = (x_a - x) / x_a, b(u) = u (1 - u)^q scaled to a peak of 1 (at u = 1 / (1 + q)); reloading from (x_r, d_r),
    d fades linearly to zero at the largest x of the excursion (x_m), beyond which the backbone holds. Zero below
    x = 0. Rate-independent (reversals of the input alone)."""

    def __init__(self, kappa, q):
        self.kappa, self.q = kappa, q
        u = 1.0 / (1.0 + q)
        self.norm = 1.0 / (u * (1.0 - u) ** q)

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        out = np.empty_like(x)
        kappa, q, norm = self.kappa, self.q, self.norm
        prev, d, falling = float(x[0]), 0.0, False
        top, turn = max(prev, 0.0), (prev, 0.0)
        for i, xi in enumerate(x.tolist()):
            if xi != prev:
                now_falling = xi < prev
                if now_falling != falling:
                    turn, falling = (prev, d), now_falling
            if xi <= 0.0:
                d, top = 0.0, 0.0
            elif falling:
                xa, da = turn
                if xa > 0.0:
                    u = min(max((xa - xi) / xa, 0.0), 1.0)
                    d = da * xi / xa + kappa * xa * norm * u * (1.0 - u) ** q
            elif xi >= top:
                d, top = 0.0, xi
            else:
                xr, dr = turn
                d = dr * (top - xi) / (top - xr) if top > xr else 0.0
            prev = xi
            out[i] = xi + d
        return out


def jkr_area(u, w):
    """The contact area of a JKR contact (normalised) at the load ``u`` with the adhesion ``w``:
    (u + 2 w + 2 sqrt(w u + w^2))^(2/3)."""
    u = np.maximum(u, 0.0)
    return (u + 2.0 * w + 2.0 * np.sqrt(w * u + w * w)) ** (2.0 / 3.0)


class AdhesionPad(SimOnly):
    """A soft printed contact pad read through its contact area, whose adhesion is larger while the contact line
    recedes than while it advances: y = x + ``height`` (A(u, w(s)) - A(u, w_a)) / g_max, u = x / ``top``,
    w(s) = w_a + s (w_r - w_a), the pinning state s moving toward 1 while x falls and toward 0 while it rises, by
    |dx| / ``pin_v`` of the way (rate-independent); g_max the largest difference over the range."""

    def __init__(self, height, top, advancing, receding, pin_v):
        self.height, self.top, self.wa, self.wr, self.pin = height, top, advancing, receding, pin_v
        u = np.linspace(0.0, 1.0, 101)
        self.gmax = float(np.max(jkr_area(u, receding) - jkr_area(u, advancing)))

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        dx = np.diff(x, prepend=x[0]).tolist()
        s, out = 0.0, np.empty_like(x)
        for i, step in enumerate(dx):
            share = min(abs(step) / self.pin, 1.0)
            s += ((1.0 if step < 0.0 else 0.0) - s) * share if step else 0.0
            out[i] = s
        u = x / self.top
        w = self.wa + out * (self.wr - self.wa)
        return x + self.height * (jkr_area(u, w) - jkr_area(u, self.wa)) / self.gmax


def ceramic_ratio(temp, peak_c, width_c):
    """A class-II (Y5V) ceramic capacitor's capacitance relative to the reference, 1 / (1 + ((T - T_p) / W)^2)
    normalised at T_ref."""
    return (1.0 + ((T_REF_C - peak_c) / width_c) ** 2) / (1.0 + ((temp - peak_c) / width_c) ** 2)


class CeramicSallenKey(SimOnly):
    """A unity-gain Sallen-Key low-pass of quality ``q`` whose capacitors are class-II ceramics: w0 = w_ref / C(T_e),
    T_e the electronics' temperature (lag ``lag_s``); w_ref = 1 / (q ``delay_s``) (the delay 1 / (q w0) at T_ref).
    Trapezoidal per sample of a uniform grid with the step's own w0, from x[0]."""

    def __init__(self, delay_s, q, peak_c, width_c, lag_s):
        self.w_ref, self.q, self.peak, self.width, self.lag = 1.0 / (q * delay_s), q, peak_c, width_c, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        tu, xu, h = uniform_grid(t, np.asarray(x, dtype=float))
        electronics = np.interp(tu, t, follow(t, temp_of(aux, t.size), self.lag))
        omega = (self.w_ref / ceramic_ratio(electronics, self.peak, self.width)).tolist()
        y, v, prev, out = float(xu[0]), 0.0, float(xu[0]), np.empty(tu.size)
        for i, (xi, w) in enumerate(zip(xu.tolist(), omega)):
            # y' = v, v' = w^2 (x - y) - (w / q) v, trapezoidal: a 2 x 2 solve
            a, b = w * w, w / self.q
            m11, m12, m21, m22 = 1.0, -0.5 * h, 0.5 * h * a, 1.0 + 0.5 * h * b
            r1 = y + 0.5 * h * v
            r2 = v + 0.5 * h * (a * (prev - y) - b * v) + 0.5 * h * a * xi
            det = m11 * m22 - m12 * m21
            y, v = (r1 * m22 - m12 * r2) / det, (m11 * r2 - m21 * r1) / det
            prev = xi
            out[i] = y
        return np.interp(t, tu, out)


class TrueRms(SimOnly):
    """A carrier read by a true-RMS converter (the square of the signal, an exponential average of ``tau_s``, the
    square root) with its sign from a phase comparator: sign(m) sqrt(|m|), m = lag(x |x|), settled at x[0]; exact
    per sample of a uniform grid."""

    def __init__(self, tau_s):
        self.tau = tau_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        tu, xu, _ = uniform_grid(t, np.asarray(x, dtype=float))
        mean = lowpass(tu, xu * np.abs(xu), self.tau)
        return np.interp(t, tu, np.sign(mean) * np.sqrt(np.abs(mean)))


def loaded_potentiometer(rel, reach, start, travel):
    """x read by the wiper of a printed potentiometric track loaded by the amplifier's input resistance: the divider
    a / (1 + k a (1 - a)), a = start + travel x / ``reach`` (held on the track), taken from its value at ``start``
    and scaled to slope 1 there; k (the track's resistance over the load's) set for a compression ``rel`` at ``reach``,
    the smallest k that gives it."""
    def divider(a, k):
        return a / (1.0 + k * a * (1.0 - a))

    def read(x, k):
        a = np.clip(start + travel * np.asarray(x, dtype=float) / reach, 0.0, 1.0)
        slope = (1.0 + k * start * start) / (1.0 + k * start * (1.0 - start)) ** 2 * travel / reach
        return (divider(a, k) - divider(start, k)) / slope

    ks = np.logspace(-3.0, 3.0, 241)
    most = float(ks[np.argmin([float(read(reach, k)) for k in ks])])  # beyond it the departure turns back
    k = optimize.brentq(lambda k: float(read(reach, k)) / reach - 1.0 + rel, 1e-6, most)
    return lambda x: read(x, k)


def capacitive_diaphragm(rel, reach):
    """x read as the capacitance of a clamped diaphragm electrode over a gap, C / C0 = artanh(sqrt(s)) / sqrt(s),
    s = x / g (the centre's deflection over the gap; arctan for s < 0, held below touch-down at 0.95): 3 g (C / C0 - 1),
    slope 1 at zero; g set for an expansion ``rel`` at ``reach``."""
    def read(x, g):
        s = np.minimum(np.asarray(x, dtype=float) / g, 0.95)
        r = np.sqrt(np.abs(s)) + 1e-12
        ratio = np.where(s >= 0.0, np.arctanh(np.minimum(r, 0.999)) / r, np.arctan(r) / r)
        return 3.0 * g * (ratio - 1.0)
    g = optimize.brentq(lambda g: float(read(reach, g)) / reach - 1.0 - rel, 1.06 * reach, 1e4 * reach)
    return lambda x: read(x, g)


MAGNUS_PER_C = 17.27 * 237.7 / (237.7 + T_REF_C) ** 2  # d ln p_sat / dT at the reference (Magnus), 1/degC


def hygroscopic_zero(t, temp, k_v_per_c, diffusion_s, modes=12, step_s=0.5):
    """k (1 - M) / b: the swelling of a thin printed skin over the gauges by the water it holds, M its mean water
    content relative to the start, which follows the air's relative humidity exp(-b (T - T_0)) (the absolute humidity
    fixed, b the Magnus slope) by Fickian diffusion in a slab (Crank's modes: weights 8 / ((2n+1)^2 pi^2), rates
    (2n+1)^2 pi^2 / ``diffusion_s``); settled at the start. Per degC at equilibrium: ``k_v_per_c``."""
    grid, tg = coarse(t, temp, step_s)
    humidity = np.exp(-MAGNUS_PER_C * (tg - tg[0]))
    odd = (2.0 * np.arange(modes) + 1.0) ** 2 * np.pi ** 2
    weights, rates = 8.0 / odd, odd / diffusion_s
    lagged = exp_convolve(grid, humidity - 1.0, rates.tolist()) * rates  # each mode, from the start's equilibrium
    content = 1.0 + lagged @ (weights / weights.sum())
    return k_v_per_c * (1.0 - np.interp(t, grid, content)) / MAGNUS_PER_C


def buckled_membrane_zero(t, temp, k_v, lag_s, onset_c, scale_c, imperfection):
    """k (w - w_ref): a printed membrane clamped in a stiffer frame, buckling as it warms (an imperfect pitchfork,
    w^3 - theta w = e, theta = (T_m - T_ref - ``onset_c``) / ``scale_c``, e = ``imperfection``, on the branch of e's
    sign), T_m the membrane's temperature (lag ``lag_s``); Newton from the larger of the two limits."""
    theta = (follow(t, temp, lag_s) - T_REF_C - onset_c) / scale_c
    ref = np.array([-onset_c / scale_c])

    def root(th):
        w = np.maximum(np.sqrt(np.maximum(th, 0.0)), abs(imperfection) ** (1.0 / 3.0))
        for _ in range(60):
            w = w - (w ** 3 - th * w - abs(imperfection)) / np.maximum(3.0 * w * w - th, 1e-9)
            w = np.maximum(w, 1e-12)
        return w
    return k_v * math.copysign(1.0, imperfection) * (root(theta) - root(ref)[0])


class UrbachEdgeSpan(SimOnly):
    """An optical read-out through a dyed light guide (ratioed to a reference photodiode that views the LED
    directly, the zero a closed shutter): the LED's wavelength drifts with its junction's temperature (lag
    ``lag_s``) along the dye's absorption (Urbach) edge, the span exp(-a (exp(-beta (T_j - T_ref)) - 1)), a the
    guide's absorbance at the reference, ``direction`` -1 for an edge on the other side."""

    def __init__(self, absorbance, beta, direction, lag_s):
        self.a, self.beta, self.dir, self.lag = absorbance, beta, direction, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        dt = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        return np.asarray(x, dtype=float) * np.exp(-self.a * np.expm1(-self.beta * self.dir * dt))


class EtalonSpan(SimOnly):
    """An optical read-out lit by a laser diode through a fibre whose parasitic etalon (two end faces ~9 mm apart)
    sweeps a fringe as the fibre's temperature (lag ``lag_s``) changes its optical path: the span (1 + v cos(2 pi
    (T_f - T_ref) / P + phi)) / (1 + v cos phi); the zero a closed shutter."""

    def __init__(self, visibility, period_c, phase, lag_s):
        self.v, self.period, self.phase, self.lag = visibility, period_c, phase, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        dt = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        span = (1.0 + self.v * np.cos(2.0 * np.pi * dt / self.period + self.phase)) / (1.0 + self.v * math.cos(self.phase))
        return np.asarray(x, dtype=float) * span


def normalised(fn, size, horizon_s=DURATION_S + 60.0):
    """``fn(s)`` scaled so that its largest magnitude over ``horizon_s`` (on a 0.1 s grid) is ``|size|``, with the
    sign of ``size``."""
    peak = float(np.max(np.abs(fn(np.arange(0.0, horizon_s, 0.1)))))
    return lambda s: size / max(peak, 1e-12) * fn(s)


def stray_light_zero(s, sessions, lasers, lamps, dim, laser_w, lamp_w):
    """The photocurrent of ambient light through a translucent printed housing: the room's lights dimmed to ``dim``
    during each scan session (start, length, ramp), the gantry's positioning lasers (start, length) weighted
    ``laser_w``, an examination lamp swung in (start, length, ramp) weighted ``lamp_w``; relative to full room light."""
    out = np.zeros_like(s)
    for at, length, ramp in sessions:
        out -= (1.0 - dim) * quintic((s - at) / ramp) * (1.0 - quintic((s - at - length) / ramp))
    for at, length in lasers:
        out += laser_w * ((s >= at) & (s < at + length))
    for at, length, ramp in lamps:
        out += lamp_w * quintic((s - at) / ramp) * (1.0 - quintic((s - at - length) / ramp))
    return out


def dendrite_zero(s, episodes):
    """The leakage of electrochemical migration on a contaminated bridge board: each episode (start, growth time T,
    power n, level L, residual r, fuse time) grows as L ((s - start) / T)^n, then the dendrite fuses and the leakage
    falls to r L within the fuse time, which stays."""
    out = np.zeros_like(s)
    for at, grow, power, level, residual, fuse in episodes:
        u = s - at
        growing = (u >= 0.0) & (u < grow)
        out[growing] += level * (u[growing] / grow) ** power
        after = u >= grow
        out[after] += level * (residual + (1.0 - residual) * (1.0 - quintic((u[after] - grow) / fuse)))
    return out


class BeltDriveMode(SimOnly):
    """y'' + 2 zeta w (y' - x') + w^2 (y - x) = 0, the carriage of a belt drive at the position p(t) (0..1 along the
    belt): w = w_mid sqrt((1 / p + 1 / (1 - p)) / 4) (the belt's two free lengths in parallel); p moves by
    minimum-jerk moves (``moves``: start, length, from, to, in seconds since the first sample). Semi-implicit Euler,
    four sub-steps, from rest."""

    def __init__(self, f_mid_hz, zeta, first, moves):
        self.w, self.zeta, self.first, self.moves = 2.0 * math.pi * f_mid_hz, zeta, first, moves

    def position(self, s):
        p = np.full(s.size, float(self.first))
        for at, length, frm, to in self.moves:
            p = np.where(s >= at, frm + (to - frm) * quintic((s - at) / length), p)
        return p

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        tu, xu, rate, sub = mode_steps(t, np.asarray(x, dtype=float))
        p = self.position(tu - tu[0])
        omega = (self.w * np.sqrt((1.0 / p + 1.0 / (1.0 - p)) / 4.0)).tolist()
        y, v, out = xu[0], 0.0, np.empty(len(xu))
        for i, (xi, ri, w) in enumerate(zip(xu, rate, omega)):
            c, w2 = 2.0 * self.zeta * w, w * w
            for _ in range(4):
                v += (-c * (v - ri) - w2 * (y - xi)) * sub
                y += v * sub
            out[i] = y
        return np.interp(t, tu, out)


class CompensatedMode(SimOnly):
    """A mode (y'' + 2 zeta w (y' - x') + w^2 (y - x) = 0) whose inertial error e = y - x an accelerometer on the
    moving mass measures and the DAQ subtracts, ``gain`` of it, ``delay_s`` late: x + e(t) - gain e(t - delay)."""

    def __init__(self, f0_hz, zeta, gain, delay_s):
        w = 2.0 * math.pi * f0_hz
        self.mode, self.gain, self.delay = LinearFilter([2.0 * zeta * w, w * w], [1.0, 2.0 * zeta * w, w * w]), gain, delay_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        e = self.mode.forward(t, x) - x
        return x + e - self.gain * dead_time(t, e, self.delay)


def relaxing_septum_band(band_n, relaxed, relax_s, recover_s, inside_n, step_s=0.05):
    """A Coulomb band ``band_n`` g through a rubber septum whose grip g relaxes toward ``relaxed`` (``relax_s``) while
    the needle is in it (the force above ``inside_n``) and recovers toward 1 (``recover_s``) while it is out; exact per
    step of ``step_s``, from a full grip."""
    def passed(t, f):
        grid, fg = coarse(t, f, step_s)
        into, out_ = math.exp(-step_s / relax_s), math.exp(-step_s / recover_s)
        grip, out = 1.0, np.empty(grid.size)
        for i, fi in enumerate(fg.tolist()):
            out[i] = grip
            grip = relaxed + (grip - relaxed) * into if fi > inside_n else 1.0 + (grip - 1.0) * out_
        width = band_n * np.interp(t, grid, out)
        return band_play(f, width, width)
    return passed


def self_locking_band(band_n, floor, release_n):
    """A Coulomb band ``band_n`` (``floor`` + (1 - ``floor``) P / 4 N) of a collet that sets deeper under the push, P
    the largest force since the force last fell below ``release_n`` (which releases it)."""
    def passed(t, f):
        released = f < release_n
        era = np.cumsum(released) * 100.0  # larger than any force: a running maximum that restarts at each release
        peak = np.where(released, 0.0, np.maximum.accumulate(f + era) - era)
        width = band_n * (floor + (1.0 - floor) * peak / 4.0)
        return band_play(f, width, width)
    return passed


def on_clock(c, t, f, rate):
    """The core's deformation on the clock ``rate`` (its reduced time, from t[0])."""
    return simulate_deformation(c, integrate.cumulative_trapezoid(rate, t, initial=0.0) + t[0], f)


class PcmBufferedClock(SimOnly):
    """A Burgers core on the Arrhenius clock exp(b (T_c - T_ref)), T_c following (``core_s``) a paraffin jacket whose
    temperature stalls while it melts: its enthalpy H follows the air, H' = (T - T_j(H)) / ``jacket_s``, with a latent
    heat ``latent_c`` (in degC of its sensible heat) spread over ``width_c`` about ``melt_c`` (Euler per coarse step of
    0.5 s, settled at the start)."""

    def __init__(self, c, b_per_c, melt_c, width_c, latent_c, jacket_s, core_s):
        self.c, self.b, self.lo, self.width, self.latent = c, b_per_c, melt_c - 0.5 * width_c, width_c, latent_c
        self.jacket, self.core = jacket_s, core_s

    def jacket_temperature(self, h):
        lo, width, latent = self.lo, self.width, self.latent
        if h < lo:
            return h
        return lo + (h - lo) * width / (width + latent) if h < lo + width + latent else h - latent

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        grid, tg = coarse(t, temp_of(aux, t.size), 0.5)
        first = float(tg[0])
        lo, width, latent = self.lo, self.width, self.latent
        h = first if first < lo else (lo + (first - lo) * (width + latent) / width if first < lo + width else first + latent)
        out = np.empty(grid.size)
        for i, ti in enumerate(tg.tolist()):
            out[i] = self.jacket_temperature(h)
            h += (ti - out[i]) * 0.5 / self.jacket
        core_t = follow(t, np.interp(t, grid, out), self.core)
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(self.b * (core_t - T_REF_C)))


class ConfinedClock(SimOnly):
    """A Burgers core in a stiffer sleeve, on the clock exp(b (T_c - T_ref) - b kappa p): warming the core (lag
    ``lag_s``) presses it against the sleeve (p, in degC, rises with T_c) and pressure slows its molecular motion;
    the pressure relaxes through the core's own creep, p' = T_c' - a p / ``relax_s`` (a the clock). Per coarse step of
    0.5 s, unpressed at the start."""

    def __init__(self, c, b_per_c, kappa, relax_s, lag_s):
        self.c, self.b, self.kappa, self.relax, self.lag = c, b_per_c, kappa, relax_s, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        core_t = follow(t, temp_of(aux, t.size), self.lag)
        grid, cg = coarse(t, core_t, 0.5)
        p, out, cl = 0.0, np.empty(grid.size), cg.tolist()
        for i, ti in enumerate(cl):
            out[i] = p
            clock = math.exp(self.b * (ti - T_REF_C) - self.b * self.kappa * p)
            p = p * math.exp(-0.5 * clock / self.relax) + ((cl[i + 1] - ti) if i + 1 < len(cl) else 0.0)
        pressure = np.interp(t, grid, out)
        return on_clock(self.c, t, np.asarray(x, dtype=float),
                        np.exp(self.b * (core_t - T_REF_C) - self.b * self.kappa * pressure))


def ecg(s, beats):
    """A synthetic ECG (P, Q, R, S and T waves as Gaussians, the T wave's delay growing with the square root of the
    RR interval), R = 1, at ``s``, from the beats (times) nearest before and after each sample."""
    rr = float(np.median(np.diff(beats)))
    waves = ((0.12, -0.2, 0.025), (-0.12, -0.035, 0.01), (1.0, 0.0, 0.012), (-0.25, 0.035, 0.012),
             (0.3, 0.28 * math.sqrt(rr), 0.06))
    i = np.clip(np.searchsorted(beats, s), 1, beats.size - 1)
    out = np.zeros_like(s)
    for near in (beats[i - 1], beats[i]):
        u = s - near
        for a, mu, sigma in waves:
            out += a * np.exp(-0.5 * ((u - mu) / sigma) ** 2)
    return out


def ecg_pickup(amp_v, beats, contact_n):
    """``amp_v`` times the ECG, coupled into the bridge while the needle or tool touches the patient (the force above
    ``contact_n``, the coupling settling over 0.3 s)."""
    def term(t, f, temp):
        touching = kelvin(t, (f > contact_n).astype(float), 1.0, 0.3)
        return amp_v * touching * ecg(t - t[0], beats)
    return term


def darkening(s, shots, permanent, anneal_s):
    """The radiation-induced attenuation of a fibre: each CT fluoroscopy run (start, length, dose rate) darkens it
    linearly while it lasts; of each run's darkening ``permanent`` stays and the rest anneals as 1 / (1 + u /
    ``anneal_s``) after it."""
    out = np.zeros_like(s)
    for at, length, dose in shots:
        grown = dose * length * np.clip((s - at) / length, 0.0, 1.0)
        since = np.maximum(s - at - length, 0.0)
        out += grown * (permanent + (1.0 - permanent) / (1.0 + since / anneal_s))
    return out


class FibreDarkening(SimOnly):
    """The span of an optical read-out times 1 - ``loss(s)``, s the time since the first sample."""

    def __init__(self, loss):
        self.loss = loss

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        return np.asarray(x, dtype=float) * (1.0 - self.loss(t - t[0]))


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    top = FORCE_MAX_N / c.relaxation().g0_n_per_v  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([6e4, 4e3]))))  # V / (N s)
        if shape == "overload_cracked_flow":
            rule = overload_cracked_flow(phi * rng.uniform(0.6, 1.1), rng.uniform(3.0, 6.0), rng.uniform(0.5, 2.5),
                                         rng.uniform(1.0, 2.0))
            return Parts("zener", ZenerWithFlow(c, rule), core_changed=True)
        transition = rng.uniform(0.5, 2.0)
        phi_t, rho_t = blasius_table()
        at_3n = 0.5 * transition * float(np.interp(3.0 / transition, phi_t, rho_t))  # the rate at 3 N per unit fluidity
        rule = labyrinth_flow(3.0 * phi * rng.uniform(1.5, 3.0) / at_3n, transition)
        return Parts("zener", ZenerWithFlow(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        if shape == "mismatched_creep_compensation":
            share, fast = float(np.interp(m, [0, 1], [0.03, 0.22])), rng.uniform(0.5, 5.0)
            p.after.append(ForcePath(mismatched_compensation(share, share * rng.uniform(0.6, 1.3), fast,
                                                             fast * rng.uniform(4.0, 15.0))))
            return p
        compliance = float(np.interp(m, [0, 1], [0.006, 0.06]))
        a = (compliance, rng.uniform(4.0, 30.0), rng.uniform(0.15, 0.4), rng.uniform(15.0, 90.0),
             compliance * rng.uniform(0.3, 1.5))  # an e-fold of the structure per the deformation 0.3-1.5 N gives
        p.extra.append(lambda t, f, T, a=a: thixotropic_kelvin(t, f, *a))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.01, 0.06]))
        if shape == "shoulder_peak_gauge":
            p.after.append(ShoulderPeak(frac * rng.uniform(1.5, 2.5), rng.uniform(1.0, 3.0)))
            return p
        wa = rng.uniform(0.005, 0.02)
        p.after.append(AdhesionPad(1.5 * frac * top * rng.uniform(0.8, 1.2), top, wa, wa * rng.uniform(3.0, 8.0),
                                   top * rng.uniform(0.02, 0.08)))
        return p
    if effect == "sensor_lag":
        if shape == "ceramic_sallen_key":
            delay = float(np.interp(m, [0, 1], [0.006, 0.045])) * rng.uniform(0.8, 1.2)
            p.after.append(CeramicSallenKey(delay, rng.uniform(0.55, 0.75), rng.uniform(0.0, 15.0), rng.uniform(20.0, 40.0),
                                            rng.uniform(10.0, 40.0)))
            return p
        p.after.append(TrueRms(float(np.interp(m, [0, 1], [0.008, 0.06])) * rng.uniform(0.8, 1.2)))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.05, 0.16]))
        if shape == "loaded_potentiometer":
            start = rng.uniform(0.0, 0.08)
            p.after.append(StaticMap(loaded_potentiometer(rel, top, start, (1.0 - start) / rng.uniform(2.0, 3.0))))
            return p
        p.after.append(StaticMap(capacitive_diaphragm(rel, top)))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.022]) * rng.choice([-1, 1]))
        if shape == "hygroscopic_skin":
            a = (k * rng.uniform(1.5, 3.0), rng.uniform(300.0, 1500.0))
            p.extra.append(lambda t, f, T, a=a: hygroscopic_zero(t, T, *a))
            return p
        a = (2.0 * abs(k) * rng.uniform(0.8, 1.2), rng.uniform(10.0, 40.0), rng.uniform(-2.0, 1.5), rng.uniform(0.7, 1.5),
             math.copysign(rng.uniform(0.02, 0.15), k))
        p.extra.append(lambda t, f, T, a=a: buckled_membrane_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        if shape == "urbach_edge_led":
            rel = float(np.interp(m, [0, 1], [0.03, 0.13]))
            absorbance = math.log1p(rel) * rng.uniform(1.5, 3.0)
            beta = -math.log(1.0 - math.log1p(rel) / absorbance) / 4.0  # the span rel higher 4 degC above the reference
            p.after.append(UrbachEdgeSpan(absorbance, beta, float(rng.choice([-1, 1])), rng.uniform(5.0, 30.0)))
            return p
        p.after.append(EtalonSpan(float(np.interp(m, [0, 1], [0.015, 0.08])), rng.uniform(2.0, 6.0),
                                  rng.uniform(0.0, 2.0 * np.pi), rng.uniform(10.0, 60.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.012, 0.08]) * rng.choice([-1, 1]))
        horizon = DURATION_S + 60.0
        if shape == "stray_light":
            n = int(rng.integers(3, 7))
            sessions = list(zip(rng.uniform(0.0, horizon, n), rng.uniform(30.0, 120.0, n), rng.uniform(2.0, 5.0, n)))
            n = int(rng.integers(6, 21))
            lasers = list(zip(rng.uniform(0.0, horizon, n), rng.uniform(5.0, 20.0, n)))
            n = int(rng.integers(0, 3))
            lamps = list(zip(rng.uniform(0.0, horizon, n), rng.uniform(30.0, 150.0, n), rng.uniform(1.0, 3.0, n)))
            a = (sessions, lasers, lamps, rng.uniform(0.1, 0.4), rng.uniform(0.2, 0.7), rng.uniform(0.5, 1.5))
            zero = normalised(lambda s, a=a: stray_light_zero(s, *a), size)
            p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
            return p
        episodes, at = [], rng.uniform(-30.0, 60.0)
        while at < horizon:
            grow, fuse = rng.uniform(40.0, 150.0), rng.uniform(0.1, 1.0)
            episodes.append((at, grow, rng.uniform(1.5, 3.0), rng.lognormal(0.0, 0.4), rng.uniform(0.0, 0.3), fuse))
            at += grow + fuse + rng.uniform(5.0, 40.0)
        zero = normalised(lambda s, a=episodes: dendrite_zero(s, a), size)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.06, 0.015])) * rng.uniform(0.8, 1.2)
        if shape == "belt_drive_mode":
            times = np.cumsum(rng.uniform(10.0, 40.0, 64))
            times = times[times < DURATION_S + 60.0]
            ends = rng.uniform(0.12, 0.88, times.size + 1)
            moves = list(zip(times, rng.uniform(1.0, 4.0, times.size), ends[:-1], ends[1:]))
            p.after.append(BeltDriveMode(rng.uniform(18.0, 40.0), zeta, float(ends[0]), moves))
            return p
        p.after.append(CompensatedMode(rng.uniform(20.0, 50.0), zeta, rng.uniform(0.3, 0.7), rng.uniform(0.5e-3, 3e-3)))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "relaxing_septum":
            p.before.append(ForcePath(relaxing_septum_band(r * rng.uniform(1.2, 1.6), rng.uniform(0.25, 0.65),
                                                           rng.uniform(3.0, 30.0), rng.uniform(2.0, 10.0),
                                                           rng.uniform(0.05, 0.2))))
            return p
        p.before.append(ForcePath(self_locking_band(r, rng.uniform(0.2, 0.5), rng.uniform(0.1, 0.3))))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.09, 0.26]))
        if shape == "pcm_buffered_clock":
            return Parts("burgers", PcmBufferedClock(c, b, T_REF_C + rng.uniform(-0.5, 2.0), rng.uniform(0.3, 1.0),
                                                     rng.uniform(1.0, 4.0), rng.uniform(20.0, 60.0), rng.uniform(5.0, 20.0)),
                         core_changed=True)
        return Parts("burgers", ConfinedClock(c, b, rng.uniform(0.4, 0.8), rng.uniform(30.0, 150.0), rng.uniform(10.0, 40.0)),
                     core_changed=True)
    if effect == "ecg_pickup":
        rr = 60.0 / rng.uniform(55.0, 110.0)
        n = int((DURATION_S + 60.0) / rr) + 4
        breathing = rng.uniform(3.0, 6.0)  # s: the respiratory sinus arrhythmia's period
        beats = rng.uniform(-1.0, 0.0) + np.cumsum(rr * (1.0 + 0.04 * np.sin(2.0 * np.pi * rr * np.arange(n) / breathing)
                                                         + 0.01 * rng.normal(0.0, 1.0, n)))
        p.extra.append(ecg_pickup(float(np.interp(m, [0, 1], [0.004, 0.04])), beats, rng.uniform(0.1, 0.3)))
        return p
    if effect == "fibre_darkening":
        n = int(rng.integers(6, 21))
        shots = list(zip(np.sort(rng.uniform(0.0, DURATION_S, n)), rng.uniform(2.0, 12.0, n), rng.uniform(0.5, 1.0, n)))
        a = (shots, rng.uniform(0.3, 0.6), rng.uniform(20.0, 120.0))
        loss = normalised(lambda s, a=a: darkening(s, *a), float(np.interp(m, [0, 1], [0.01, 0.08])))
        p.after.append(FibreDarkening(loss))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["overload_cracked_flow", "labyrinth_leak"],
    "delayed_elasticity": ["mismatched_creep_compensation", "thixotropic_kelvin"],
    "hysteresis": ["shoulder_peak_gauge", "adhesion_pad"],
    "sensor_lag": ["ceramic_sallen_key", "true_rms_converter"],
    "nonlinear_gain": ["loaded_potentiometer", "capacitive_diaphragm"],
    "thermal_drift": ["hygroscopic_skin", "buckled_membrane"],
    "thermal_sensitivity": ["urbach_edge_led", "fibre_etalon"],
    "offset_drift": ["stray_light", "dendrite_leakage"],
    "resonance": ["belt_drive_mode", "compensated_mode"], "friction": ["relaxing_septum", "self_locking_collet"],
    "thermo_rheological": ["pcm_buffered_clock", "confined_clock"],
}
PAIRS = (("viscous_flow", "thermal_sensitivity"), ("delayed_elasticity", "offset_drift"), ("hysteresis", "sensor_lag"),
         ("friction", "nonlinear_gain"), ("resonance", "thermal_drift"), ("thermo_rheological", "delayed_elasticity"))
OUTSIDE = ("ecg_pickup", "fibre_darkening")
RATES = (170.0, 390.0, 630.0, 870.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split R", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.3e-3, 2.6e-3), jitter=0.35,
                   gap_s=(0.1, 2.6))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
