"""Independent split P for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split P is an untouched held-out set: written before the engine it measures and blind to it (to how it detects and
fits anything), run once at its end, never used to choose anything. Every name of the catalogue is hidden in two
shapes that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A to O use:

* a press-fit insert that slides in its printed bore until its collar seats on the shoulder (a fluidity 3-6 times
  the plain one, falling to 0.4-0.8 times it once the insert has moved as far as 500-2000 s of the plain flow under
  1 N would take it), or a gasket extruding through a clearance that its own pressure widens (x' = A F (1 + F /
  F_g)^3, F_g 2-6 N, A 2-4 times the plain fluidity at 3 N: linear at light loads, cubic at high ones);
* the bond of the gauges relaxing under the strain they carry (the negative creep that compensates a load cell's,
  here overdone: the output loses 5-25 % of each change of the core's deformation over 3-40 s), or a Kelvin unit
  (0.008-0.09 V/N, 3-30 s) that creeps onto a backstop (its deformation held below what 1.5-4 N gives at rest);
* the conductive paths of a carbon-filled printed gauge, which break as the strain passes their thresholds (64 paths,
  5-100 % of the range) and reform only once it falls below 20-70 % of them (the output x (1 - kappa b), b the share
  broken, kappa 4-24 %), or an internal slider that moves only on its overstress (Perzyna: a play whose stuck value
  follows the excess over its half-width with a time constant of 10-120 ms, on 30-60 % of the output, a loop of
  0.5-3 % of the span);
* a wireless stream played out through an adaptive jitter buffer (a delay of 3-20 ms to which each late packet, every
  15-60 s on average, adds up to 5-75 ms, drained again at 2-10 ms/s), or a run-down (Wilkinson) ADC whose samples
  are held at the start of each conversion and stamped at its end (late by 1-3 ms plus 8-72 ms times the reading's
  place in its span: the higher the force, the later);
* gauges on the convex face of a crooked printed strut whose bending the axial load amplifies (Southwell:
  x (1 + g / (1 - x / x_cr)), x_cr 2.5-4 times the range, an expansion of 6-15 % at its top), or a spring pin in one
  arm of the bridge whose contact resistance falls as the sensor's deflection presses it (Holm, elastic:
  (1 + x / x0)^(-1/3), x0 10-50 % of the range, a departure of 6-15 % at its top, either way);
* a holder clamping a body that expands more than it (a thermal force, 0.006-0.02 V/degC through the core's instant
  spring, that acts through the creeping core; the body's temperature lags by 10-40 s), or a DAQ whose electronics
  heat themselves by 2-5 degC until a thermostatic fan cuts that by 50-80 % (on once the room is 0.5-3 degC above
  the reference, off 1-2 degC lower; the electronics lag by 30-90 s; 0.006-0.02 V/degC);
* a carrier-frequency amplifier whose oscillator drifts with the electronics' temperature (lag 20-90 s) off its
  band-pass (Q 2-6, tuned within 3 degC of the reference: the span a Lorentzian in temperature, 4-14 % lower 5 degC
  away from the tuning), or a printed body whose radial clearance in its aluminium sleeve closes as it expands above
  1 degC below to 2.5 degC above the reference (the fit then carries a share of the force that grows as the cube
  root of its pressure: the span 3-11 % lower 4 degC above; lag 20-60 s);
* galvanic films of saline splashed across the connector's dissimilar metals (2-5 splashes, each wetting in 0.5 s
  and growing from 40 to 100 % of up to 15-80 mV as it concentrates over 20-90 s, lost in 2-6 s as it dries), or a
  freshly tightened clamp settling by 15-40 micro-slips of one sign at a rate that decays as Omori's law
  (1 / (t + c), c 5-40 s, tightened 0-60 s before the record; 15-80 mV in all, each slip over 20-100 ms);
* a holder in a loose fit (22-55 Hz against the walls of its clearance, 0.2-0.5 times as stiff within it, a
  clearance worth 0.1-0.4 N; damping ratio 0.012-0.072), or a mode whose damping the needle's sliding turns
  negative (friction falling with speed: a limit cycle of 0.6-0.8 times 15-50 mV while the signal moves faster than
  0.3-1.5 N/s, light ringing otherwise);
* a Coulomb band that fades as the contact warms with the friction's work (by up to 30-60 %, cooling again in 5-30
  s), or a grain of debris trapped in the guide now and then (the band 40-100 % wider while it is, 10-60 s, and
  15-90 s between); both bands 0.5-3 % of the range;
* an Arrhenius clock (0.1-0.25 per degC) on a core that anneals: whenever its temperature (lag 10-40 s) exceeds the
  warmest it has been (0-1.5 degC above its start), the clock slows by 40-90 % of what that warming speeds it,
  approached in 30-120 s and never recovered; or an Arrhenius process (0.13-0.33 per degC) in series with one that
  no temperature speeds up (the clock at most 2.5-5 times faster; lag 3-15 s).

It also holds six pairs, two effects outside the catalogue (the mass of the tool, 100-500 g, a motorised needle driver
accelerated by the robot that carries it: minimum-jerk moves of 30-150 mm in 0.5-1.5 s, 2-8 s apart on average, m a
along the sensor's axis, which the reference does not see; a wireless stream whose packets of 20-80 ms now and then,
every 1.5-6 s on average, arrive out of order and are recorded as they arrive) and four clean records. Profiles: a
core-biopsy needle driven through the measured force-depth curve (``../shared/data``, ``depth_force.csv``, its first
insertion) at 2-6 mm/s and fired (the spring-loaded cannula cutting 12-22 mm further in 15-40 ms, its cutting force
raised by the speed), held while the core is severed, withdrawn (a train of synthetic punctures when the data are
absent); a syringe's plunger pushed through injections (breakout, a glide with the fluid's force behind the tubing's
lag, bottoming out); and a chewing simulator's bites (a sample that stiffens as it is compressed, brittle fractures, a
bolus that softens, swallows). Rates 330, 490, 710 and 940 Hz (a mode at 1000 Hz with knocks that excite it), 1.1-2.7 mV
noise, stamp jitter, gaps, and a sensor in a water-jacketed fixture that a circulator warms 3-6 degC above the room (a
rate-limited second-order approach, its thermostat's ripple, the lid opened once).

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_p.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import math

import numpy as np
from scipy import integrate, signal

from independent_split import puncture_train
from independent_split_o import follow, measured_insertion, telegraph, telegraph_level, temp_of
from polyforce_ros.physics.viscoelastic import simulate_deformation
from polyforce_ros.sim.truths import StaticMap
from split_kit import (band_play, coarse, core_output, ForcePath, kelvin, mode_steps, Parts, quintic, ShapeSplit,
                       SimOnly, ZenerWithFlow)

SEED0 = 1_100_000  # never a seed of the registry's splits nor of splits A (90000..) to O (1030000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 460.0


# ----------------------------------------------------------------------------- profiles and temperature

def biopsy_gun(duration_s, rate_hz, rng):
    """A core-biopsy needle driven through the measured force-depth curve (``measured_insertion``: its friction and
    its cutting part) on a minimum-jerk trajectory at 2-6 mm/s on average to 30-100 % of the depth that leaves room for
    the throw; the operator aims for 0.5-2 s (the force relaxing to 70-90 %, 0.5-2 s), then fires the spring-loaded
    cannula: it cuts 12-22 mm further in 15-40 ms, its cutting force raised by (v / 3 mm/s)^0.08-0.15 at that speed.
    The needle is held 1-3 s while the core is severed (relaxing to 60-85 %), then withdrawn (the holder lifting off
    the sensor's button in 0.2-0.5 s) and rests 5-20 s. The curve scaled to a 2.5-6 N peak; a train of synthetic
    punctures when ``../shared/data`` is absent."""
    curve = measured_insertion()
    if curve is None:
        return puncture_train(duration_s, rate_hz, rng)
    depth_mm, friction, cutting = curve
    total = friction + cutting
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)

    def relax(now, span_s, last, keep, tau_s):
        seg = (t >= now) & (t < now + span_s)
        f[seg] = last * (keep + (1.0 - keep) * np.exp(-(t[seg] - now) / tau_s))
        return now + span_s, last * (keep + (1.0 - keep) * math.exp(-span_s / tau_s))
    now = rng.uniform(3.0, 8.0)
    while now < duration_s - 6.0:
        throw, scale = rng.uniform(12.0, 22.0), rng.uniform(2.5, 6.0) / max(float(np.max(total)), 1e-3)
        target, v_mean = rng.uniform(0.3, 1.0) * (depth_mm[-1] - throw), rng.uniform(2.0, 6.0)
        seg = (t >= now) & (t < now + target / v_mean)
        if not seg.any():
            break
        f[seg] = scale * np.interp(target * quintic((t[seg] - now) * v_mean / target), depth_mm, total)
        now += target / v_mean
        now, last = relax(now, rng.uniform(0.5, 2.0), scale * float(np.interp(target, depth_mm, total)),
                          rng.uniform(0.7, 0.9), rng.uniform(0.5, 2.0))
        fire = rng.uniform(0.015, 0.04)
        boost = (throw / fire / 3.0) ** rng.uniform(0.08, 0.15)
        seg = (t >= now) & (t < now + fire)
        depth = target + throw * (t[seg] - now) / fire
        cut = np.interp(depth, depth_mm, friction) + boost * np.interp(depth, depth_mm, cutting)
        f[seg] = np.maximum(scale * cut, last)
        now += fire
        now, last = relax(now, rng.uniform(1.0, 3.0), scale * float(np.interp(target + throw, depth_mm, total)),
                          rng.uniform(0.6, 0.85), rng.uniform(0.5, 2.0))
        lift = rng.uniform(0.2, 0.5)
        seg = (t >= now) & (t < now + lift)
        f[seg] = last * (1.0 - quintic((t[seg] - now) / lift))
        now += lift + rng.uniform(5.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def syringe_injections(duration_s, rate_hz, rng):
    """A syringe's plunger pushed through an injection (a glide-force test, as ISO 7886 measures one): the stopper
    breaks away at 1.5-4 N (reached in 0.2-0.8 s) and its friction falls to a glide of 0.6-1.6 N within 50-150 ms;
    the fluid's force follows the pushing rate (2-4 segments of 3-12 s, each at its own rate, 0.5-3.5 N) through the
    compliance of the tubing (a lag of 0.3-2 s); at the end the stopper bottoms out (1-3 N more in 0.3-0.8 s, pressed
    0.5-2 s), is released in 0.2-0.5 s and rests 4-15 s while the syringe is refilled (a pull the sensor does not
    read)."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 10.0:
        breakout, glide, rise, drop = rng.uniform(1.5, 4.0), rng.uniform(0.6, 1.6), rng.uniform(0.2, 0.8), \
            rng.uniform(0.05, 0.15)
        seg = (t >= now) & (t < now + rise)
        f[seg] = breakout * quintic((t[seg] - now) / rise)
        now += rise
        steps = int(rng.integers(2, 5))
        ends, levels = np.cumsum(rng.uniform(3.0, 12.0, steps)), rng.uniform(0.5, 3.5, steps)
        seg = (t >= now) & (t < now + ends[-1])
        s = t[seg] - now
        pushed = levels[np.minimum(np.searchsorted(ends, s, side="right"), steps - 1)]
        fade = math.exp(-1.0 / (rate_hz * rng.uniform(0.3, 2.0)))
        f[seg] = glide + (breakout - glide) * np.exp(-s / drop) + signal.lfilter([1.0 - fade], [1.0, -fade], pushed)
        now += ends[-1]
        last = float(f[seg][-1]) if seg.any() else glide
        bottom, press, hold, release = rng.uniform(1.0, 3.0), rng.uniform(0.3, 0.8), rng.uniform(0.5, 2.0), \
            rng.uniform(0.2, 0.5)
        seg = (t >= now) & (t < now + press)
        f[seg] = last + bottom * quintic((t[seg] - now) / press)
        now += press
        f[(t >= now) & (t < now + hold)] = last + bottom
        now += hold
        seg = (t >= now) & (t < now + release)
        f[seg] = (last + bottom) * (1.0 - quintic((t[seg] - now) / release))
        now += release + rng.uniform(4.0, 15.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def chewing_cycles(duration_s, rate_hz, rng):
    """A chewing simulator's bites on a food sample: sequences of 8-25 bites at 0.8-1.6 Hz (each period within 10 %),
    the jaw closed for 40-60 % of it, the force stiffening as the sample is compressed (exp(a u) - 1, a 2-4) and
    released in 15-30 % of the period; the first 0-4 bites of a sequence fracture a brittle sample (at 50-80 % of the
    closing the force drops by 20-50 % and builds again); the peak (2.5-8 N) falls to 35-65 % as the bolus softens
    (3-8 bites); 4-12 s between sequences (a swallow)."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    now = rng.uniform(2.0, 5.0)
    while now < duration_s - 10.0:
        bites, period = int(rng.integers(8, 26)), 1.0 / rng.uniform(0.8, 1.6)
        p0, floor, soft = rng.uniform(2.5, 8.0), rng.uniform(0.35, 0.65), rng.uniform(3.0, 8.0)
        brittle, closed, stiff = int(rng.integers(0, 5)), rng.uniform(0.4, 0.6), rng.uniform(2.0, 4.0)
        for k in range(bites):
            cycle = period * rng.uniform(0.9, 1.1)
            peak, close, opening = p0 * (floor + (1.0 - floor) * math.exp(-k / soft)), closed * cycle, \
                rng.uniform(0.15, 0.3) * cycle
            seg = (t >= now) & (t < now + close)
            u = (t[seg] - now) / close
            shape = np.expm1(stiff * u) / math.expm1(stiff)
            if k < brittle:
                at, drop = rng.uniform(0.5, 0.8), rng.uniform(0.2, 0.5)
                shape = np.where(u > at, shape * (1.0 - drop * np.exp(-(u - at) / 0.15)), shape)
            f[seg] = peak * shape
            seg = (t >= now + close) & (t < now + close + opening)
            f[seg] = peak * (1.0 - quintic((t[seg] - now - close) / opening))
            now += cycle
        now += rng.uniform(4.0, 12.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (biopsy_gun, syringe_injections, chewing_cycles)


def temperature(t, rng, step_s=0.5):
    """A sensor in a water-jacketed fixture: the room at 21.5-24 degC drifting by up to +-0.4 degC over the record;
    the circulator was set 3-6 degC above the room 250 s before the record to 30 % into it, its loop approaching the
    set point as a second-order system (a period of 80-200 s, damping 0.3-0.6: an overshoot) whose heating rate its
    heater limits to 0.01-0.03 degC/s, with the on-off ripple of its thermostat (a triangle of 0.05-0.15 degC, 20-60
    s); at 40-80 % of the record the lid is opened for 10-40 s (the sensor's surroundings fall 30-60 % of the way
    back to the room); the sensor follows its surroundings with a time constant of 15-50 s (exact per step of
    ``step_s``), settled at the start."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    on, rise = rng.uniform(-250.0, 0.3 * d), rng.uniform(3.0, 6.0)
    grid = np.arange(min(on, 0.0), d + 2.0 * step_s, step_s)
    room = T_REF_C + rng.uniform(-1.5, 1.0) + rng.uniform(-0.4, 0.4) * grid / d
    w, zeta, limit = 2.0 * math.pi / rng.uniform(80.0, 200.0), rng.uniform(0.3, 0.6), rng.uniform(0.01, 0.03)
    excess, speed, jacket = 0.0, 0.0, np.empty(grid.size)
    for i, g in enumerate(grid.tolist()):
        jacket[i] = excess
        speed += (w * w * ((rise if g >= on else 0.0) - excess) - 2.0 * zeta * w * speed) * step_s
        speed = min(speed, limit)
        excess += speed * step_s
    ripple = rng.uniform(0.05, 0.15) * signal.sawtooth(2.0 * math.pi * grid / rng.uniform(20.0, 60.0)
                                                       + rng.uniform(0.0, 2.0 * math.pi), width=0.5)
    jacket += np.where(grid >= on, ripple, 0.0)
    lid, opened = rng.uniform(0.4, 0.8) * d, rng.uniform(10.0, 40.0)
    around = room + jacket * np.where((grid >= lid) & (grid < lid + opened), 1.0 - rng.uniform(0.3, 0.6), 1.0)
    keep = math.exp(-step_s / rng.uniform(15.0, 50.0))
    out, y = np.empty_like(grid), float(around[0])
    for i, goal in enumerate(around.tolist()):
        y = goal + (y - goal) * keep
        out[i] = y
    return np.interp(s, grid, out)


# ----------------------------------------------------------------------------- simulate-only truth elements

def seating_flow(fast, slow, gap_v, step_s=0.05):
    """A press-fit insert sliding in its bore (x' = A F, A = ``fast``) until its collar seats on the shoulder after
    ``gap_v`` of flow (A falls smoothly to ``slow`` over 0.9-1.1 gap), on a grid of ``step_s``, from rest."""
    def rule(t, f):
        grid = np.arange(t[0], t[-1] + step_s, step_s)
        x, out = 0.0, np.empty(grid.size)
        for i, fi in enumerate(np.interp(grid, t, f).tolist()):
            out[i] = x
            seated = float(quintic((x / gap_v - 0.9) / 0.2))
            x += (fast + (slow - fast) * seated) * max(fi, 0.0) * step_s
        return np.interp(t, grid, out)
    return rule


def gap_extrusion(fluidity, gap_n):
    """A gasket extruding through a clearance that the pressure widens: x' = A F (1 + F / F_g)^3."""
    def rule(t, f):
        f = np.maximum(f, 0.0)
        return integrate.cumulative_trapezoid(fluidity * f * (1.0 + f / gap_n) ** 3, t, initial=0.0)
    return rule


def bottoming_kelvin(t, f, compliance, tau_s, stop_v, step_s=0.02):
    """A Kelvin unit (tau w' + w = c F) whose deformation a backstop holds below ``stop_v``: exact per step of
    ``step_s``, then held, from rest."""
    grid, fg = coarse(t, f, step_s)
    fade, w, out = math.exp(-step_s / tau_s), 0.0, np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        out[i] = w
        w = min(compliance * fi + (w - compliance * fi) * fade, stop_v)
    return np.interp(t, grid, out)


def relay_states(x, upper, lower):
    """Each relay's state (True once ``x`` rises above its ``upper``, False once it falls below its ``lower``,
    False at first): (n, relays)."""
    out = np.empty((x.size, upper.size), dtype=bool)
    index = np.arange(x.size)
    for j, (u, lo) in enumerate(zip(upper.tolist(), lower.tolist())):
        above = x > u
        last = np.maximum.accumulate(np.where(above | (x < lo), index, -1))
        out[:, j] = (last >= 0) & above[np.maximum(last, 0)]
    return out


class PercolationPaths(SimOnly):
    """A gauge whose conductive paths break as it is strained past their ``upper`` thresholds and reform only when
    it relaxes below their ``lower`` ones: the output x (1 - kappa b), b the share of broken paths."""

    def __init__(self, upper, lower, kappa):
        self.upper, self.lower, self.kappa = upper, lower, kappa

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        return x * (1.0 - self.kappa * relay_states(x, self.upper, self.lower).mean(axis=1))


class OverstressPlay(SimOnly):
    """A play of half-width ``radius_v`` whose stuck value moves only on the overstress, at a speed of the excess
    over ``tau_s`` (Perzyna): exact per sample; the output (1 - share) x + share p, p from x[0]."""

    def __init__(self, radius_v, tau_s, share):
        self.r, self.tau, self.share = radius_v, tau_s, share

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        dt = np.diff(t, prepend=t[0]).tolist()
        p, out = float(x[0]), np.empty_like(x)
        for i, (xi, h) in enumerate(zip(x.tolist(), dt)):
            edge = xi - self.r if xi - p > self.r else (xi + self.r if p - xi > self.r else p)
            p = edge + (p - edge) * math.exp(-h / self.tau)
            out[i] = p
        return (1.0 - self.share) * x + self.share * out


class JitterBuffer(SimOnly):
    """A wireless stream played out through an adaptive jitter buffer: the delay is ``floor_s`` plus the largest
    ``jump_s[k] - drain (s - times_s[k])`` of the late packets so far (each sets the buffer's depth, which then
    drains at ``drain`` s/s)."""

    def __init__(self, floor_s, times_s, jump_s, drain):
        self.floor, self.times, self.jumps, self.drain = floor_s, np.asarray(times_s), np.asarray(jump_s), drain

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        s, depth = t - t[0], np.zeros_like(t)
        for at, jump in zip(self.times[self.times < s[-1]].tolist(), self.jumps.tolist()):
            np.maximum(depth, np.where(s >= at, jump - self.drain * (s - at), 0.0), out=depth)
        return np.interp(t - self.floor - depth, t, x, left=x[0])


class WilkinsonStamps(SimOnly):
    """A run-down (Wilkinson) ADC whose sample is held at the conversion's start and stamped at its end: late by
    ``latency_s`` plus ``conversion_s`` times the reading's place in [lo_v, hi_v]."""

    def __init__(self, latency_s, conversion_s, lo_v, hi_v):
        self.latency, self.conversion, self.lo, self.hi = latency_s, conversion_s, lo_v, hi_v

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        late = self.latency + self.conversion * np.clip((x - self.lo) / (self.hi - self.lo), 0.0, 1.0)
        return np.interp(t, np.maximum.accumulate(t + late), x, left=x[0])


def southwell_gauges(rel, ratio, top):
    """x (1 + g / (1 - x / x_cr)) / (1 + g): gauges on the convex face of a crooked strut whose bending the axial
    load amplifies (Southwell), x_cr = top / ``ratio``, g set for a departure ``rel`` at ``top`` (x / x_cr held below
    0.8)."""
    g = rel * (1.0 - ratio) / (ratio - rel * (1.0 - ratio))
    critical = top / ratio
    return lambda x: x * (1.0 + g / (1.0 - np.minimum(x / critical, 0.8))) / (1.0 + g)


def pin_contact(rel, x0, top, sign):
    """(x + a (1 - (1 + x / x0)^(-1/3))) / (1 + a / (3 x0)): a spring pin in one arm of the bridge whose contact
    resistance falls as the deflection presses it (Holm, an elastic contact), a set for a departure ``rel`` at ``top``
    (compressive for ``sign`` > 0, in the arm that lowers the output as it conducts better, else expansive)."""
    g0, big = 1.0 / (3.0 * x0), (1.0 - (1.0 + top / x0) ** (-1.0 / 3.0)) / top
    a = rel / ((1.0 - rel) * g0 - big) if sign > 0 else rel / (big - (1.0 + rel) * g0)
    return lambda x: (x + a * (1.0 - (1.0 + np.maximum(x, -0.5 * x0) / x0) ** (-1.0 / 3.0))) / (1.0 + a * g0)


def mismatch_zero(t, temp, load_n_per_c, lag_s, core_of):
    """The core's response (``core_of(t, F)``) to the force a holder exerts on a clamped body that expands more than
    it, ``load_n_per_c`` per degC of the body's temperature (lag ``lag_s``) since the record began (what it exerted
    before is settled in the zero)."""
    ts = follow(t, temp, lag_s)
    return core_of(t, load_n_per_c * (ts - ts[0]))


def fan_zero(t, temp, k_v_per_c, lag_s, heat_c, cooling, on_c, band_c, step_s=0.5):
    """k (T_e - T_ref - heat): a DAQ's electronics at the room's temperature plus their own ``heat_c``, less
    ``cooling`` of it while a thermostatic fan runs (on above ``on_c``, off below on - ``band_c``), followed with a
    lag ``lag_s`` (exact per step), settled at the start."""
    grid, tg = coarse(t, temp, step_s)
    keep = math.exp(-step_s / lag_s)
    te = float(tg[0]) + heat_c
    fan = te > on_c
    te -= cooling * heat_c * fan
    out = np.empty_like(tg)
    for i, ti in enumerate(tg.tolist()):
        goal = ti + heat_c * (1.0 - cooling * fan)
        te = goal + (te - goal) * keep
        fan = te > (on_c - band_c if fan else on_c)
        out[i] = te
    return k_v_per_c * (np.interp(t, grid, out) - T_REF_C - heat_c)


class DetunedCarrier(SimOnly):
    """A carrier-frequency amplifier whose oscillator drifts (r = 1 + ``drift`` (T_e - T_tune)) off its band-pass of
    quality ``q``: the span follows 1 / sqrt(1 + q^2 (r - 1/r)^2), T_e the electronics' temperature (lag ``lag_s``),
    relative to T_ref."""

    def __init__(self, q, drift_per_c, tune_c, lag_s):
        self.q, self.drift, self.tune, self.lag = q, drift_per_c, tune_c, lag_s

    def gain(self, temp):
        r = 1.0 + self.drift * (temp - self.tune)
        return 1.0 / np.sqrt(1.0 + (self.q * (r - 1.0 / r)) ** 2)

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        return x * self.gain(follow(t, temp_of(aux, t.size), self.lag)) / self.gain(T_REF_C)


class ClosingFit(SimOnly):
    """The force the core carries beside a sleeve whose radial clearance the body's expansion closes above
    ``close_c``: F / (1 + kappa (T_s - close_c)^(1/3)) (a Hertzian fit, its stiffness growing as the cube root of its
    pressure), T_s the body's temperature (lag ``lag_s``)."""

    def __init__(self, kappa, close_c, lag_s):
        self.kappa, self.close, self.lag = kappa, close_c, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        ts = follow(t, temp_of(aux, t.size), self.lag)
        return f / (1.0 + self.kappa * np.cbrt(np.maximum(ts - self.close, 0.0)))


def splash_zero(s, times, sizes, lives, fade_s):
    """Galvanic films of saline splashed at ``times`` since the first sample: each wets in 0.5 s, its potential
    growing from 40 to 100 % of ``sizes`` as it concentrates over ``lives``, then lost in ``fade_s`` as it dries."""
    out = np.zeros_like(s)
    for at, size, life in zip(times, sizes, lives):
        age = s - at
        out += size * (0.4 + 0.6 * np.clip(age / life, 0.0, 1.0)) * quintic(age / 0.5) \
            * (1.0 - quintic((age - life) / fade_s))
    return out


def slips_zero(s, times, steps, widths):
    """A clamp settling by micro-slips: a smooth step of ``steps[k]`` over ``widths[k]`` at each of ``times``."""
    return sum(step * quintic((s - at) / w) for at, step, w in zip(times, steps, widths))


class ClearanceMode(SimOnly):
    """y'' + 2 zeta w (y' - x') + w^2 (soft d + (1 - soft) (d - clip(d, +-gap))) = 0, d = y - x: a holder in a loose
    fit, soft within its clearance and stiff against its walls; semi-implicit Euler, four sub-steps, from rest."""

    def __init__(self, f0_hz, zeta, soft, gap_v):
        self.w, self.zeta, self.soft, self.gap = 2.0 * math.pi * f0_hz, zeta, soft, gap_v

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        tu, xu, rate, sub = mode_steps(t, np.asarray(x, dtype=float))
        w2, c = self.w * self.w, 2.0 * self.zeta * self.w
        y, v, out = xu[0], 0.0, np.empty(len(xu))
        for i, (xi, ri) in enumerate(zip(xu, rate)):
            for _ in range(4):
                d = y - xi
                walls = d - min(max(d, -self.gap), self.gap)
                v += (-c * (v - ri) - w2 * (self.soft * d + (1.0 - self.soft) * walls)) * sub
                y += v * sub
            out[i] = y
        return np.interp(t, tu, out)


class ChatterMode(SimOnly):
    """A mode whose damping turns negative while the needle slides (friction falling with speed): damping
    zeta - nu g (1 - E / a^2) (at most 1), E = d^2 + (d' / w)^2, g = min(|x'| / rate, 1) with x' averaged over
    0.2 s: a limit cycle of about a sqrt(1 - zeta / nu) while the signal moves fast, light ringing otherwise;
    semi-implicit Euler, four sub-steps, from rest."""

    def __init__(self, f0_hz, zeta, nu, amp_v, rate_v_per_s):
        self.w, self.zeta, self.nu, self.amp, self.rate = 2.0 * math.pi * f0_hz, zeta, nu, amp_v, rate_v_per_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        tu, xu, rate, sub = mode_steps(t, np.asarray(x, dtype=float))
        n = max(1, int(round(0.2 / (4.0 * sub))))
        gate = np.minimum(np.convolve(np.abs(rate), np.ones(n) / n)[:len(xu)] / self.rate, 1.0).tolist()
        w, w2 = self.w, self.w * self.w
        y, v, out = xu[0], 0.0, np.empty(len(xu))
        for i, (xi, ri, gi) in enumerate(zip(xu, rate, gate)):
            for _ in range(4):
                d, dv = y - xi, v - ri
                damping = min(self.zeta - self.nu * gi * (1.0 - (d * d + dv * dv / w2) / self.amp ** 2), 1.0)
                v += (-2.0 * w * damping * dv - w2 * d) * sub
                y += v * sub
            out[i] = y
        return np.interp(t, tu, out)


def fading_band(band_n, fade, heat_n, tau_s):
    """A Coulomb band band (1 - fade theta / (1 + theta)) whose contact warms with the friction's work
    (theta' = band |p'| / ``heat_n`` - theta / ``tau_s``: ``heat_n`` the work, in N of force passed at the full band,
    that warms it by one unit) and cools at rest; exact per sample, from p = F[0], cold."""
    def passed(t, f):
        dt = np.diff(t, prepend=t[0]).tolist()
        p, theta, out = float(f[0]), 0.0, np.empty_like(f)
        for i, (fi, h) in enumerate(zip(f.tolist(), dt)):
            band = band_n * (1.0 - fade * theta / (1.0 + theta))
            moved = max(fi - band, min(fi + band, p))
            theta = theta * math.exp(-h / tau_s) + band * abs(moved - p) / heat_n
            p = moved
            out[i] = p
        return out
    return passed


def on_clock(c, t, f, rate):
    """The core's deformation on the clock ``rate`` (its reduced time, from t[0])."""
    return simulate_deformation(c, integrate.cumulative_trapezoid(rate, t, initial=0.0) + t[0], f)


class AnnealedClock(SimOnly):
    """A Burgers core on the clock exp(b (T_c - T_ref) - beta (A - A_0)): T_c the core's temperature (lag
    ``lag_s``), A its annealing, which rises toward T_c whenever T_c is above it (``anneal_s``) and never falls,
    from A_0 = T_c[0] + ``head_c`` (the warmest the core was before the record)."""

    def __init__(self, c, b_per_c, beta_per_c, lag_s, anneal_s, head_c):
        self.c, self.b, self.beta, self.lag, self.anneal, self.head = c, b_per_c, beta_per_c, lag_s, anneal_s, head_c

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        grid, tc = coarse(t, follow(t, temp_of(aux, t.size), self.lag), 0.5)
        gain = 1.0 - math.exp(-0.5 / self.anneal)
        a0 = a = float(tc[0]) + self.head
        level = np.empty_like(tc)
        for i, ti in enumerate(tc.tolist()):
            a += max(ti - a, 0.0) * gain
            level[i] = a
        log_rate = self.b * (tc - T_REF_C) - self.beta * (level - a0)
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.interp(t, grid, log_rate)))


class CeilingClock(SimOnly):
    """A Burgers core on the clock (1 + 1/A) / (exp(-b (T_c - T_ref)) + 1/A): an Arrhenius process in series with
    one that no temperature speeds up, so the clock cannot run more than A + 1 times faster; T_c lags by
    ``lag_s``."""

    def __init__(self, c, b_per_c, ceiling, lag_s):
        self.c, self.b, self.ceiling, self.lag = c, b_per_c, ceiling, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        tc = follow(t, temp_of(aux, t.size), self.lag)
        rate = (1.0 + 1.0 / self.ceiling) / (np.exp(-self.b * (tc - T_REF_C)) + 1.0 / self.ceiling)
        return on_clock(self.c, t, np.asarray(x, dtype=float), rate)


def robot_moves(rng, horizon_s):
    """Minimum-jerk moves of the robot that carries the tool: 30-150 mm in 0.5-1.5 s (at most 3.5 m/s^2), 2-8 s apart
    on average, each along a direction whose share on the sensor's axis is +-0.3-1: (starts, lengths [m], durations,
    shares)."""
    n = int(horizon_s / 2.0)
    durations, gaps = rng.uniform(0.5, 1.5, n), rng.exponential(rng.uniform(2.0, 8.0), n)
    starts = np.cumsum(gaps + durations) - durations
    return starts, rng.uniform(0.03, 0.15, n), durations, rng.uniform(0.3, 1.0, n) * rng.choice([-1.0, 1.0], n)


def carried_mass(mass_kg, moves):
    """The force the tool's mass puts on the sensor as the robot accelerates it (m a along the axis), added to the
    applied force."""
    starts, lengths, durations, shares = moves

    def passed(t, f):
        s, accel = t - t[0], np.zeros_like(t)
        for at, length, span, share in zip(starts[starts < s[-1]], lengths, durations, shares):
            u = (s - at) / span
            on = (u >= 0.0) & (u <= 1.0)
            accel[on] += share * length / span ** 2 * (60.0 * u[on] - 180.0 * u[on] ** 2 + 120.0 * u[on] ** 3)
        return f + mass_kg * accel
    return passed


class SwappedPackets(SimOnly):
    """A wireless stream whose packets of ``packet_s`` now and then arrive out of order (at ``times_s`` since the
    first sample a packet and the next swap places) and are recorded in the order they arrive."""

    def __init__(self, times_s, packet_s):
        self.times, self.packet = np.asarray(times_s), packet_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        n = max(1, int(round(self.packet / float(np.median(np.diff(t))))))
        y = x.copy()
        for i0 in (np.searchsorted(t - t[0], self.times) // n * n).tolist():
            if i0 + 2 * n <= x.size:
                y[i0:i0 + n], y[i0 + n:i0 + 2 * n] = x[i0 + n:i0 + 2 * n], x[i0:i0 + n]
        return y


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    top = FORCE_MAX_N / c.relaxation().g0_n_per_v  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([8e4, 4e3]))))  # V / (N s)
        if shape == "seating_flow":
            fast, slow = phi * rng.uniform(3.0, 6.0), phi * rng.uniform(0.4, 0.8)
            return Parts("zener", ZenerWithFlow(c, seating_flow(fast, slow, phi * rng.uniform(500.0, 2000.0))),
                         core_changed=True)
        gap = rng.uniform(2.0, 6.0)
        rule = gap_extrusion(phi * rng.uniform(2.0, 4.0) / (1.0 + 3.0 / gap) ** 3, gap)  # 2-4 phi at 3 N
        return Parts("zener", ZenerWithFlow(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        if shape == "gauge_bond_creep":
            share, tau = float(np.interp(m, [0, 1], [0.05, 0.25])), rng.uniform(3.0, 40.0)
            p.after.append(ForcePath(lambda t, x, k=share, tau=tau: x - kelvin(t, x - x[0], k, tau)))  # on the voltage
            return p
        compliance, tau, stop_n = float(np.interp(m, [0, 1], [0.008, 0.09])), rng.uniform(3.0, 30.0), \
            rng.uniform(1.5, 4.0)
        p.extra.append(lambda t, f, T, a=(compliance, tau, compliance * stop_n): bottoming_kelvin(t, f, *a))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.01, 0.06]))
        if shape == "percolation_paths":
            upper = rng.uniform(0.05, 1.0, 64) * top
            p.after.append(PercolationPaths(upper, upper * rng.uniform(0.2, 0.7, 64), 4.0 * frac))
            return p
        share = rng.uniform(0.3, 0.6)
        p.after.append(OverstressPlay(frac * top / (4.0 * share), rng.uniform(0.01, 0.12), share))  # a loop of frac / 2
        return p
    if effect == "sensor_lag":
        if shape == "jitter_buffer":
            times = np.cumsum(rng.exponential(rng.uniform(15.0, 60.0), 64))
            jumps = float(np.interp(m, [0, 1], [0.01, 0.05])) * rng.uniform(0.5, 1.5, times.size)
            p.after.append(JitterBuffer(float(np.interp(m, [0, 1], [0.003, 0.02])), times, jumps,
                                        rng.uniform(0.002, 0.01)))
            return p
        conversion = float(np.interp(m, [0, 1], [0.01, 0.06])) * rng.uniform(0.8, 1.2)
        p.after.append(WilkinsonStamps(rng.uniform(0.001, 0.003), conversion, -0.2 * top, 1.6 * top))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.06, 0.15]))
        if shape == "southwell_strut":
            p.after.append(StaticMap(southwell_gauges(rel, rng.uniform(0.25, 0.4), top)))
            return p
        p.after.append(StaticMap(pin_contact(rel, top * rng.uniform(0.1, 0.5), top, rng.choice([-1, 1]))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.02]) * rng.choice([-1, 1]))
        if shape == "clamped_mismatch_load":
            a = (k * c.k1_n_per_v, rng.uniform(10.0, 40.0), core_output(c))  # N/degC: k V/degC on the instant spring
            p.extra.append(lambda t, f, T, a=a: mismatch_zero(t, T, *a))
            return p
        heat = rng.uniform(2.0, 5.0)
        a = (k, rng.uniform(30.0, 90.0), heat, rng.uniform(0.5, 0.8), T_REF_C + heat + rng.uniform(0.5, 3.0),
             rng.uniform(1.0, 2.0))
        p.extra.append(lambda t, f, T, a=a: fan_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        net = float(np.interp(m, [0, 1], [0.008, 0.028]))  # the span's fall 5 degC from the tuning, per degC
        if shape == "detuned_carrier":
            q, tune = rng.uniform(2.0, 6.0), T_REF_C + rng.uniform(-3.0, 3.0)
            z = math.sqrt(1.0 / (1.0 - 5.0 * net) ** 2 - 1.0) / q
            p.after.append(DetunedCarrier(q, ((z + math.sqrt(z * z + 4.0)) / 2.0 - 1.0) / 5.0, tune,
                                          rng.uniform(20.0, 90.0)))
            return p
        kappa = (1.0 / (1.0 - 4.0 * net) - 1.0) / 4.0 ** (1.0 / 3.0)  # the share falls by 4 net at 4 degC
        p.before.append(ClosingFit(kappa, T_REF_C + rng.uniform(-1.0, 2.5), rng.uniform(20.0, 60.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.08]) * rng.choice([-1, 1]))
        if shape == "saline_splash":
            n = int(rng.integers(2, 6))
            times, sizes, lives = rng.uniform(0.05, 0.85, n) * DURATION_S, size * rng.uniform(0.4, 1.0, n), \
                rng.uniform(20.0, 90.0, n)
            fade = rng.uniform(2.0, 6.0)
            p.extra.append(lambda t, f, T, a=(times, sizes, lives, fade): splash_zero(t - t[0], *a))
            return p
        n, omori, before = int(rng.integers(15, 41)), rng.uniform(5.0, 40.0), rng.uniform(0.0, 60.0)
        times = omori * ((1.0 + (DURATION_S + before) / omori) ** rng.random(n) - 1.0) - before
        slips = (times, size / n * rng.exponential(1.0, n), rng.uniform(0.02, 0.1, n))
        p.extra.append(lambda t, f, T, a=slips: slips_zero(t - t[0], *a))
        return p
    if effect == "resonance":
        f0, zeta = rng.uniform(22.0, 55.0), float(np.interp(m, [0, 1], [0.06, 0.015])) * rng.uniform(0.8, 1.2)
        if shape == "clearance_mode":
            p.after.append(ClearanceMode(f0, zeta, rng.uniform(0.2, 0.5), top / FORCE_MAX_N * rng.uniform(0.1, 0.4)))
            return p
        amp = float(np.interp(m, [0, 1], [0.015, 0.05]))
        p.after.append(ChatterMode(f0, zeta, zeta * rng.uniform(1.5, 3.0), amp,
                                   top / FORCE_MAX_N * rng.uniform(0.3, 1.5)))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "friction_fade":
            p.before.append(ForcePath(fading_band(r, rng.uniform(0.3, 0.6), r * rng.uniform(2.0, 8.0),
                                                  rng.uniform(5.0, 30.0))))
            return p
        first, times = telegraph(rng, (rng.uniform(15.0, 90.0), rng.uniform(10.0, 60.0)), DURATION_S + 200.0)
        jump = rng.uniform(0.4, 1.0)
        p.before.append(ForcePath(lambda t, f, a=(first, times), r=r, j=jump:
                                  band_play(f, *(2 * [r * (1.0 + j * telegraph_level(*a, t - t[0]))]))))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.1, 0.25]))
        if shape == "annealed_clock":
            return Parts("burgers", AnnealedClock(c, b, b * rng.uniform(0.4, 0.9), rng.uniform(10.0, 40.0),
                                                  rng.uniform(30.0, 120.0), rng.uniform(0.0, 1.5)), core_changed=True)
        return Parts("burgers", CeilingClock(c, 1.3 * b, rng.uniform(1.5, 4.0), rng.uniform(3.0, 15.0)),
                     core_changed=True)  # 0.13-0.33 per degC below the ceiling
    if effect == "carried_tool_inertia":
        mass = float(np.interp(m, [0, 1], [0.1, 0.5]))
        p.before.append(ForcePath(carried_mass(mass, robot_moves(rng, DURATION_S + 200.0))))
        return p
    if effect == "swapped_packets":
        times = np.cumsum(rng.exponential(rng.uniform(1.5, 6.0), 512))
        p.outer.append(SwappedPackets(times, float(np.interp(m, [0, 1], [0.02, 0.08]))))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["seating_flow", "gap_extrusion"],
    "delayed_elasticity": ["gauge_bond_creep", "bottoming_kelvin"],
    "hysteresis": ["percolation_paths", "overstress_play"],
    "sensor_lag": ["jitter_buffer", "wilkinson_stamps"],
    "nonlinear_gain": ["southwell_strut", "pin_contact"],
    "thermal_drift": ["clamped_mismatch_load", "fan_thermostat"],
    "thermal_sensitivity": ["detuned_carrier", "closing_fit"],
    "offset_drift": ["saline_splash", "settling_slips"],
    "resonance": ["clearance_mode", "chatter_mode"], "friction": ["friction_fade", "trapped_debris"],
    "thermo_rheological": ["annealed_clock", "ceiling_clock"],
}
PAIRS = (("viscous_flow", "friction"), ("offset_drift", "delayed_elasticity"), ("thermal_drift", "hysteresis"),
         ("resonance", "sensor_lag"), ("thermal_sensitivity", "nonlinear_gain"), ("thermo_rheological", "resonance"))
OUTSIDE = ("carried_tool_inertia", "swapped_packets")
RATES = (330.0, 490.0, 710.0, 940.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split P", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.1e-3, 2.7e-3), jitter=0.4,
                   gap_s=(0.15, 2.4))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
