"""Independent split Q for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split Q is an untouched held-out set: written before the engine it measures and blind to it (to how it detects and
fits anything), run once at its end, never used to choose anything. Every name of the catalogue is hidden in two
shapes that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A to P use:

* a printed hinge plasticised by the water it takes up from the irrigated field (its fluidity rising from 0.3-0.6 to
  2-4 times the plain one as the uptake follows Fick's law in a slab, L^2 / D 150-600 s, wetted 0-120 s before the
  record), or the steel pivot pin of the mechanism's lever cold-flowing into its printed bore (the contact widens as
  the pin sinks in, so the flow rate falls as 1 / sqrt(1 + x / x_w): x = x_w ((1 + 1.5 A I / x_w)^(2/3) - 1), I the
  impulse of the force, A 2-4 times the plain fluidity, x_w what 40-300 s of the plain flow under 1 N gives; it
  never stops);
* a silicone grommet around the needle guide that carries part of the force to the frame beside the sensor and
  relaxes (a Maxwell path: 5-30 % of each change of force at first, none at rest, 3-40 s), handing its share to the
  sensor's core, or a Kelvin unit (0.008-0.07 V/N, 2-25 s) whose printed lattice walls buckle elastically beyond the
  deformation that 1.5-4 N gives at rest (the retarded spring 2-4 times softer past it: more creep, and slower, at
  high loads);
* crazes in the printed walls (64, opening at 10-100 % of the range and closing at 20-70 % of that) whose opening
  sheds load onto the others (a mean-field coupling worth 15-30 % of the range: openings and closings run as
  avalanches), the open share adding 2.5-15 % of the range to the deformation (a moving Preisach model), or cracks
  between printed layers under the peak-oriented rule of cracked members (Clough: unloading pinched toward the
  origin as a power 1.04-1.29 of the deformation, by 1.5-9 % of the peak at half of it; reloading along a line aimed
  at the largest deformation reached so far);
* a fluid-filled (CT-compatible) transmission whose snubber orifice passes a flow as the square root of the pressure
  difference (the force behind it approaches the applied one at a rate sqrt(|e| + 0.05 N): a change of 1 N settles to
  63 % in 6-54 ms, larger changes take longer, small ones less), or an autoranging DAQ whose high-gain range (below
  25-50 % of the span, switching back 10 % lower) has a heavier first-order digital filter (6-60 ms) than its
  low-gain range (3-6 times lighter);
* a double-ended tuning fork read by counting its period (its frequency as sqrt(1 +- x / x_b) as the load stretches or
  compresses it: compressive or expansive, 6-15 % at the top of the range), or gauges on a clamped diaphragm whose
  membrane stretching stiffens it at large deflections (Timoshenko: the deflection w solves w + beta w^3 = x, a
  compression of 6-15 % at the top of the range);
* a freshly glued gauge whose adhesive post-cures during the record (its thermal output, 0.006-0.02 V/degC of the
  bond's temperature, lag 10-40 s, is 1 + g (1 - X) times that, g 0.5-1.5, the cure X advancing at an Arrhenius rate,
  0.1-0.3 per degC, 300-1500 s at the reference, from 30-70 %), or a bridge board held by a Peltier element under a
  PI controller of limited reach (the board kept at a set point 0.5-2 degC above the reference while its
  surroundings, lag 5-20 s, stay within 0.3-1 degC of it; beyond, it follows them (20-60 s), and the integrator that
  wound up meanwhile overshoots on the way back; 0.012-0.04 V/degC of the board's departure);
* a bimetal switch that shunts a span-trimming resistor when the electronics (lag 15-60 s) pass 0-1 degC above the
  reference and releases it 0.5-1.2 degC lower (the span steps by 2.5-9 %, either way), or a magnetic read-out (a
  magnet in the polymer) whose flux guide is a low-Curie ferrite (the span falls as ((T_c - T) / (T_c - T_ref))^beta,
  beta 0.3-0.45, 3-12 % lower 4 degC above the reference; lag 10-40 s);
* radiation-induced conductivity in the cable during the shots of CT fluoroscopy (8-25 shots of 0.5-3 s: a prompt
  offset within 50-300 ms, then a delayed part, 30-60 %, that decays as a power law (1 + t / 1-5 s)^-(0.5-1), and
  5-20 % of trapped charge that stays; 15-80 mV at most), or triboelectric charge that the cable picks up each time
  the robot repositions the arm (every 8-40 s on average, 0.5-2 s moves, charges of either sign leaking away in
  20-120 s; 15-80 mV at most);
* a mode (20-50 Hz) of a needle holder with an active damper whose DSP latency (the phase at the mode 117-162
  degrees) turns its velocity feedback against the mode (sized to take back 50-120 % of a damping ratio of
  0.012-0.072 from a passive damping that much larger), or a mode with a particle damper (a free ball of 5-15 % of
  the moving mass in a cavity worth 0.1-0.4 N, restitution 0.3-0.7: a fast decay while the ball strikes, a light
  ringing, damping ratio 0.012-0.072, once the amplitude fits within the cavity);
* rate-and-state friction in the needle guide (Dieterich-Ruina with the ageing law: a band of 0.5-3 % of the range
  that grows with the logarithm of the time the contact has been stuck and falls with the logarithm of the slip
  rate, a 0.02-0.05, b - a 0.1-0.2, L 0.05-0.3 N of the passed force, held within 0.4-2.5 times the band), or a
  greased guide whose film is squeezed out under load (5-30 s at 3 N) and reflows at rest (20-90 s), the band rising
  from 30-60 % of its dry value (0.7-4.3 % of the range) as the film goes;
* an Arrhenius clock (0.1-0.25 per degC) on a core that follows the air through its mount, whose thermal contact
  closes as the core expands (the lag 60-150 s below a closing temperature within -0.5 to +1.5 degC of the reference,
  4-10 times shorter above it), or a core whose thin hinge walls (the retardation, lag 3-15 s) and thick base (the
  flow, lag 60-200 s) each run on the Arrhenius clock (0.1-0.25 per degC) of their own temperature.

It also holds six pairs, two effects outside the catalogue (the weight of the tool, 0.5-3 N, whose share along the
sensor's axis changes as the robot tilts the tool between 0 and 60 degrees every 20-80 s, a force the reference does
not see; a wireless link that conceals its lost bursts of samples, 15-450 ms every 3-15 s on average, by drawing a
straight line across them) and four clean records. Profiles: a robotic brachytherapy applicator that drives its needle
through the measured force-depth curve (``../shared/data``, ``depth_force.csv``, its first insertion) on the measured
stage trajectory (``time_displacement.csv``) at 1.5-4 mm/s, holds while the tissue relaxes as the measured record
relaxes (``time_force.csv`` during the stage's hold, 0.6-1.6 times slower or faster), then pushes 3-7 seeds out with
its stylet (0.4-2 N pulses), retracting 5-10 mm between seeds (synthetic layers and a synthetic relaxation when the
data are absent); peck drilling through one or two cortices of bone (thrust 2-5 N at 0.6-2 mm/s, a softer cancellous
layer between, chips packing the flutes until each peck, the flutes' 12-30 Hz ripple, breakthrough); and a pneumatic
palpation probe held by on-off valves (a dead band of 0.04-0.15 N and a valve delay of 10-30 ms: a limit cycle around
each set point; holds and slow sweeps of 1-6 N). Rates 190, 440, 670 and 910 Hz (a mode at 1000 Hz with knocks that
excite it), 1.2-2.5 mV noise, stamp jitter, gaps, and a sensor on the table of a CT scanner in a room kept 0.5-2.5
degC below the reference, whose bore the scan sessions warm by 4-8 degC.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_q.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, optimize, signal

from polyforce_ros.physics.viscoelastic import Zener, simulate_deformation
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (band_play, coarse, ForcePath, kelvin, mode_steps, Parts, quintic, ShapeSplit, SimOnly,
                       uniform_grid, ZenerWithFlow)

SEED0 = 1_170_000  # never a seed of the registry's splits nor of splits A (90000..) to P (1100000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 470.0


# ----------------------------------------------------------------------------- profiles and temperature

@functools.lru_cache(maxsize=1)
def measured_needle(bin_mm=0.1):
    """The measured insertion (``../shared/data/needle_insertion_okamura``), or None when it is absent: the first
    insertion of ``depth_force.csv`` binned on ``bin_mm`` (the mean force per bin, empty bins interpolated) and split
    into the shaft's friction (the lower envelope from the deepest point back) and the rest (stiffness build-ups and
    cutting peaks); the stage's trajectory up to its hold (``time_displacement.csv``, normalised to 0-1 in time and
    depth); and the tissue's relaxation during the stage's hold (``time_force.csv`` over a 0.3 s running mean,
    relative to its value when the stage stops, made non-increasing). A dict of arrays."""
    csv = profiles.okamura_csv_path()
    if csv is None or not all((csv.parent / name).is_file() for name in ("depth_force.csv", "time_displacement.csv")):
        return None
    raw = np.loadtxt(csv.parent / "depth_force.csv", delimiter=",", ndmin=2)
    depth, force = 1e3 * raw[:, 0], raw[:, 1]
    jumps = np.flatnonzero(np.diff(depth) < -5.0)
    end = int(jumps[0]) + 1 if jumps.size else depth.size
    depth, force = depth[:end], force[:end]
    grid = np.arange(0.0, float(depth.max()) + bin_mm, bin_mm)
    which = np.clip(np.round(depth / bin_mm).astype(int), 0, grid.size - 1)
    count = np.bincount(which, minlength=grid.size)
    total = np.bincount(which, weights=force, minlength=grid.size)
    filled = count > 0
    mean = np.maximum(np.interp(grid, grid[filled], total[filled] / count[filled]), 0.0)
    friction = np.minimum.accumulate(mean[::-1])[::-1]

    stage = np.loadtxt(csv.parent / "time_displacement.csv", delimiter=",", ndmin=2)
    ts, xs = stage[:, 0], stage[:, 1]
    peak = int(np.argmax(xs))
    rising = np.maximum.accumulate(np.maximum(xs[:peak + 1], 0.0))
    t_stop = float(np.interp(0.97 * xs[peak], rising, ts[:peak + 1]))
    t_back = float(ts[np.flatnonzero(xs >= 0.97 * xs[peak])[-1]])
    stage_u = np.linspace(0.0, 1.0, 101)
    stage_d = np.clip(np.interp(stage_u * t_stop, ts[:peak + 1], rising) / (0.97 * xs[peak]), 0.0, 1.0)
    stage_d = np.maximum.accumulate(stage_d)
    stage_d[-1] = 1.0

    tf, ff = profiles.okamura_insertion(peak_n=1.0, rate_hz=100.0, pre_s=0.0, post_s=0.0)
    smooth = np.convolve(ff, np.ones(30) / 30.0, mode="same")
    hold = (tf >= t_stop) & (tf <= t_back)
    start = float(np.max(smooth[(tf >= t_stop - 0.1) & (tf <= t_stop + 0.1)]))
    ratio = np.clip(np.minimum.accumulate(smooth[hold] / max(start, 1e-9)), 0.2, 1.0)
    return {"depth": grid, "friction": friction, "cutting": mean - friction, "stage_u": stage_u,
            "stage_d": stage_d, "relax_s": tf[hold] - tf[hold][0], "relax_ratio": ratio / ratio[0]}


def synthetic_needle(rng):
    """What :func:`measured_needle` gives, made up: a shaft friction growing 0.008-0.02 N/mm over 50 mm, 2-4 layers
    that build up over 2-6 mm and tear (leaving 20 % that fades over 0.5 mm), a stage at constant speed, and a
    relaxation to 55 % over 1.5 s."""
    grid = np.arange(0.0, 50.0, 0.1)
    friction = rng.uniform(0.008, 0.02) * grid
    cutting = np.zeros_like(grid)
    for at in np.sort(rng.uniform(5.0, 45.0, int(rng.integers(2, 5)))):
        build, height = rng.uniform(2.0, 6.0), rng.uniform(0.3, 1.0)
        rising = (grid > at - build) & (grid <= at)
        cutting[rising] += height * (grid[rising] - at + build) / build
        torn = grid > at
        cutting[torn] += 0.2 * height * np.exp(-(grid[torn] - at) / 0.5)
    relax_s = np.arange(0.0, 10.0, 0.05)
    return {"depth": grid, "friction": friction, "cutting": cutting, "stage_u": np.linspace(0.0, 1.0, 11),
            "stage_d": np.linspace(0.0, 1.0, 11), "relax_s": relax_s, "relax_ratio": 0.55 + 0.45 * np.exp(-relax_s / 1.5)}


def brachytherapy_seeds(duration_s, rate_hz, rng):
    """A robotic brachytherapy applicator: the needle is driven through the measured force-depth curve on the
    measured stage trajectory (``measured_needle``) to 60-100 % of its depth at 1.5-4 mm/s on average, the curve
    scaled to a 2.5-7 N peak; it holds 2-6 s while the force relaxes as the measured record does (0.6-1.6 times
    slower or faster); then the stylet, driven from the same carriage, pushes 3-7 seeds out (each a pulse of 0.4-2 N:
    rising in 0.15-0.4 s, held 0.2-0.8 s, released in 0.15-0.4 s, the first on the force left from the hold), and the
    needle is retracted 5-10 mm at 3-8 mm/s between seeds (the carriage pulls: the sensor, which reads push only,
    reads nothing) and waits 0.5-2 s; after the last seed it is withdrawn and the next insertion begins 5-20 s later.
    Made-up layers and relaxation (``synthetic_needle``) when ``../shared/data`` is absent."""
    needle = measured_needle() or synthetic_needle(rng)
    depth_mm, total = needle["depth"], needle["friction"] + needle["cutting"]
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)

    def span(now, length):
        seg = (t >= now) & (t < now + length)
        return seg, t[seg] - now
    now = rng.uniform(3.0, 8.0)
    while now < duration_s - 25.0:
        scale = rng.uniform(2.5, 7.0) / max(float(np.max(total)), 1e-3)
        target, speed = rng.uniform(0.6, 1.0) * depth_mm[-1], rng.uniform(1.5, 4.0)
        seg, s = span(now, target / speed)
        depth = target * np.interp(s * speed / target, needle["stage_u"], needle["stage_d"])
        f[seg] = scale * np.interp(depth, depth_mm, total)
        now += target / speed
        last = scale * float(np.interp(target, depth_mm, total))
        hold, stretch = rng.uniform(2.0, 6.0), rng.uniform(0.6, 1.6)
        seg, s = span(now, hold)
        f[seg] = last * np.interp(s / stretch, needle["relax_s"], needle["relax_ratio"])
        now += hold
        base = last * float(np.interp(hold / stretch, needle["relax_s"], needle["relax_ratio"]))
        for _ in range(int(rng.integers(3, 8))):
            push, rise, keep, fall = rng.uniform(0.4, 2.0), rng.uniform(0.15, 0.4), rng.uniform(0.2, 0.8), \
                rng.uniform(0.15, 0.4)
            seg, s = span(now, rise)
            f[seg] = base + push * quintic(s / rise)
            now += rise
            seg, s = span(now, keep)
            f[seg] = base + push
            now += keep
            seg, s = span(now, fall)
            f[seg] = (base + push) * (1.0 - quintic(s / fall))
            now += fall + rng.uniform(5.0, 10.0) / rng.uniform(3.0, 8.0) + rng.uniform(0.5, 2.0)
            base = 0.0
        now += rng.uniform(5.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def peck_drilling(duration_s, rate_hz, rng):
    """Peck drilling through bone, the sensor behind the drill guide: the thrust (2-5 N in cortical bone) builds up
    over the first 0.3-0.6 mm of each cortex as the chisel edge engages and falls over its last 0.3-0.6 mm as the drill
    breaks through; one hole in two or three is unicortical (a cortex of 1.5-3.5 mm), the others cross 3-12 mm of
    cancellous bone (15-35 % of the thrust) to a second cortex. The feed is 0.6-2 mm/s; every 1-2.5 mm the drill is
    withdrawn to clear its flutes (the thrust falls in 50-100 ms, the drill is out 0.4-1.2 s and re-engages in
    100-200 ms), the chips packing the flutes raising the thrust by 10-40 % over each peck. The flutes' passing gives a
    ripple of 3-8 % at 12-30 Hz; the bone's grain a slow modulation of 10 % (below 0.5-2 Hz). 8-25 s between holes."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    grid = np.arange(0.0, duration_s + 1.0, 0.05)
    grain = signal.sosfiltfilt(signal.butter(2, rng.uniform(0.5, 2.0), fs=20.0, output="sos"),
                               rng.normal(0.0, 1.0, grid.size))
    grain = np.interp(t, grid, grain / max(float(np.max(np.abs(grain))), 1e-9))

    def span(now, length):
        seg = (t >= now) & (t < now + length)
        return seg, t[seg] - now
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 20.0:
        thrust, feed = rng.uniform(2.0, 5.0), rng.uniform(0.6, 2.0)
        outer, soft = rng.uniform(1.5, 3.5), rng.uniform(0.15, 0.35)
        engage, leave = rng.uniform(0.3, 0.6), rng.uniform(0.3, 0.6)
        inner = rng.uniform(3.0, 12.0) if rng.random() < 0.6 else 0.0
        knots_d, knots_l = [0.0, engage, outer - leave, outer], [0.0, 1.0, 1.0, soft if inner else 0.0]
        total = outer
        if inner:
            far = rng.uniform(1.5, 3.5)
            total = outer + inner + far
            knots_d += [outer + inner, outer + inner + engage, total - leave, total]
            knots_l += [soft, 1.0, 1.0, 0.0]
        peck, packing = rng.uniform(1.0, 2.5), rng.uniform(0.1, 0.4)
        flutes, ripple, phase = rng.uniform(12.0, 30.0), rng.uniform(0.03, 0.08), rng.uniform(0.0, 2.0 * np.pi)
        clear, lift, reengage = rng.uniform(0.4, 1.2), rng.uniform(0.05, 0.1), rng.uniform(0.1, 0.2)
        depth = 0.0
        while depth < total - 1e-9:
            stretch = min(peck, total - depth)
            seg, s = span(now, stretch / feed)
            d = depth + feed * s
            f[seg] = thrust * np.interp(d, knots_d, knots_l) * (1.0 + packing * (d - depth) / peck) \
                * (1.0 + ripple * np.sin(2.0 * np.pi * flutes * t[seg] + phase)) * (1.0 + 0.1 * grain[seg]) \
                * quintic(s / reengage)
            now, depth = now + stretch / feed, depth + stretch
            last = float(f[seg][-1]) if seg.any() else 0.0
            seg, s = span(now, lift)
            f[seg] = last * (1.0 - quintic(s / lift))
            now += lift + clear
        now += rng.uniform(8.0, 25.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def pneumatic_probe(duration_s, rate_hz, rng, step_s=0.002):
    """A pneumatic palpation probe held by on-off valves: presses to set points of 1-6 N held 3-12 s, or (two in
    five) slow sweeps of the set point up to 1-6 N and back (3-8 s each way), 2-10 s vented between. The fill valve
    opens while the force, seen through the valves' 10-30 ms delay, is below the set point less a dead band of
    0.04-0.15 N, the vent while it is above it plus the band: the force approaches a supply of 8.5 N (0.15-0.6 s) or
    vents (0.2-0.8 s), leaks slowly otherwise (20-60 s), and cycles about each set point. Exact per step of
    ``step_s``, from rest."""
    grid = np.arange(0.0, duration_s + step_s, step_s)
    goal = np.zeros(grid.size)
    now = rng.uniform(2.0, 5.0)
    while now < duration_s - 5.0:
        level = rng.uniform(1.0, 6.0)
        if rng.random() < 0.4:
            up, down = rng.uniform(3.0, 8.0), rng.uniform(3.0, 8.0)
            seg = (grid >= now) & (grid < now + up)
            goal[seg] = level * (grid[seg] - now) / up
            seg = (grid >= now + up) & (grid < now + up + down)
            goal[seg] = level * (1.0 - (grid[seg] - now - up) / down)
            now += up + down
        else:
            hold = rng.uniform(3.0, 12.0)
            goal[(grid >= now) & (grid < now + hold)] = level
            now += hold
        now += rng.uniform(2.0, 10.0)
    band, delay = rng.uniform(0.04, 0.15), max(1, int(round(rng.uniform(0.01, 0.03) / step_s)))
    fill, vent, leak = (math.exp(-step_s / rng.uniform(*r)) for r in ((0.15, 0.6), (0.2, 0.8), (20.0, 60.0)))
    supply, force = 8.5, [0.0] * grid.size
    x, goals = 0.0, goal.tolist()
    for i in range(grid.size):
        seen, aim = (force[i - delay], goals[i - delay]) if i >= delay else (0.0, 0.0)
        if aim <= 0.0 or seen > aim + band:
            x *= vent
        elif seen < aim - band:
            x = supply + (x - supply) * fill
        else:
            x *= leak
        force[i] = x
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    return t, np.clip(np.interp(t, grid, np.asarray(force)), 0.0, FORCE_MAX_N)


PROFILES = (brachytherapy_seeds, peck_drilling, pneumatic_probe)


def temperature(t, rng, step_s=0.5):
    """A sensor on the table of a CT scanner during a CT-guided intervention: the room's air conditioning holds it
    0.5-2.5 degC below the reference, drifting by up to +-0.3 degC over the record, its louvres swinging it by
    0.05-0.2 degC (a period of 200-600 s); scan sessions of 60-150 s, 40-150 s apart (the first from 200 s before the
    record to 20 % into it), warm the air in the bore toward 4-8 degC above the room (30-90 s), which cools again
    between them (60-200 s); the sensor follows the air with a time constant of 20-60 s (exact per step of
    ``step_s``), from 400 s before the record."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-400.0, d + 2.0 * step_s, step_s)
    room = T_REF_C + rng.uniform(-2.5, -0.5) + rng.uniform(-0.3, 0.3) * grid / d \
        + rng.uniform(0.05, 0.2) * np.sin(2.0 * np.pi * grid / rng.uniform(200.0, 600.0) + rng.uniform(0.0, 2.0 * np.pi))
    scanning = np.zeros(grid.size, dtype=bool)
    now = rng.uniform(-200.0, 0.2 * d)
    while now < d:
        length = rng.uniform(60.0, 150.0)
        scanning |= (grid >= now) & (grid < now + length)
        now += length + rng.uniform(40.0, 150.0)
    rise, heat, cool = rng.uniform(4.0, 8.0), math.exp(-step_s / rng.uniform(30.0, 90.0)), \
        math.exp(-step_s / rng.uniform(60.0, 200.0))
    excess, bore = 0.0, np.empty(grid.size)
    for i, on in enumerate(scanning.tolist()):
        bore[i] = excess
        excess = rise + (excess - rise) * heat if on else excess * cool
    around = room + bore
    keep = math.exp(-step_s / rng.uniform(20.0, 60.0))
    out, y = np.empty_like(grid), float(around[0])
    for i, goal in enumerate(around.tolist()):
        out[i] = y
        y = goal + (y - goal) * keep
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


def fick_uptake(tau, terms=60):
    """The share of its final water content a slab has taken up at the reduced time ``tau`` = D t / L^2 (Crank:
    1 - sum 8 / ((2n+1)^2 pi^2) exp(-(2n+1)^2 pi^2 tau)), from dry."""
    k = (2.0 * np.arange(terms)[:, None] + 1.0) ** 2
    tau = np.maximum(np.asarray(tau, dtype=float), 0.0)
    return np.clip(1.0 - np.sum(8.0 / (k * np.pi ** 2) * np.exp(-k * np.pi ** 2 * tau[None, :]), axis=0), 0.0, 1.0)


def wetting_flow(dry, wet, diffusion_s, wetted_before_s, step_s=0.5):
    """x' = A(t) max(F, 0), the fluidity A rising from ``dry`` to ``wet`` as the Fickian uptake of a slab
    (L^2 / D = ``diffusion_s``) wetted ``wetted_before_s`` before the first sample."""
    def rule(t, f):
        grid = np.arange(t[0], t[-1] + step_s, step_s)
        share = np.interp(t, grid, fick_uptake((grid - t[0] + wetted_before_s) / diffusion_s))
        return integrate.cumulative_trapezoid((dry + (wet - dry) * share) * np.maximum(f, 0.0), t, initial=0.0)
    return rule


def pivot_cold_flow(fluidity, width_v):
    """x' = A F / sqrt(1 + x / x_w) (a pin sinking into its bore, the contact widening): in closed form
    x = x_w ((1 + 1.5 A I / x_w)^(2/3) - 1), I the impulse of max(F, 0)."""
    def rule(t, f):
        impulse = integrate.cumulative_trapezoid(np.maximum(f, 0.0), t, initial=0.0)
        return width_v * ((1.0 + 1.5 * fluidity * impulse / width_v) ** (2.0 / 3.0) - 1.0)
    return rule


def relaxing_grommet(share, tau_s):
    """The force the core carries beside a Maxwell path that takes ``share`` of each change of force and relaxes it
    with ``tau_s``: (1 - share) F + share lowpass(F), from rest."""
    return lambda t, f: (1.0 - share) * f + share * kelvin(t, f, 1.0, tau_s)


def buckling_kelvin(t, f, compliance, tau_s, buckle_v, ratio, step_s=0.02):
    """A Kelvin unit tau w' = c F - g(w) whose spring softens past ``buckle_v`` (g(w) = w below it,
    buckle + (w - buckle) / ``ratio`` above): exact per step of ``step_s`` on the branch it starts on, from rest."""
    grid, fg = coarse(t, f, step_s)
    soft, stiff = math.exp(-step_s / (ratio * tau_s)), math.exp(-step_s / tau_s)
    w, out = 0.0, np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        out[i] = w
        goal = compliance * fi
        if w <= buckle_v:
            w = goal + (w - goal) * stiff
        else:
            goal = buckle_v + ratio * (goal - buckle_v)
            w = goal + (w - goal) * soft
    return np.interp(t, grid, out)


class CrazeAvalanches(SimOnly):
    """Crazes that open when x + J b passes their ``up`` thresholds and close when it falls below their ``down``
    ones, b the share open (each opening sheds load onto the others, so openings and closings run as avalanches): the
    output x + kappa b. From all closed; only the thresholds next to the state are tested per sample."""

    def __init__(self, up, down, coupling_v, kappa_v):
        self.up, self.down, self.j, self.kappa = np.asarray(up), np.asarray(down), coupling_v, kappa_v

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        n = self.up.size
        is_open = np.zeros(n, dtype=bool)
        share, out = 0.0, np.empty_like(x)
        next_up, next_down = float(self.up.min()), -np.inf
        for i, xi in enumerate(x.tolist()):
            u = xi + self.j * share
            for _ in range(4 * n):  # an avalanche: until no threshold next to the state is crossed
                if next_down <= u <= next_up:
                    break
                is_open |= ~is_open & (self.up < u)
                is_open &= ~(is_open & (self.down > u))
                share = float(is_open.sum()) / n
                u = xi + self.j * share
                closed = self.up[~is_open]
                opened = self.down[is_open]
                next_up = float(closed.min()) if closed.size else np.inf
                next_down = float(opened.max()) if opened.size else -np.inf
            out[i] = share
        return x + self.kappa * out


class PeakOrientedCracks(SimOnly):
    """Cracks between layers under the peak-oriented rule: on the backbone y = x beyond the largest x so far; on
    unloading from (x_p, y_p), y = y_p (x / x_p)^``power``; on reloading from (x_r, y_r), the line to the largest
    point (x_m, x_m). Below zero, y = x."""

    def __init__(self, power):
        self.power = power

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        out = np.empty_like(x)
        peak, prev, y = max(float(x[0]), 1e-12), float(x[0]), float(x[0])
        rising, origin = True, (0.0, 0.0)
        for i, xi in enumerate(x.tolist()):
            if xi <= 0.0:
                y, rising, origin = xi, True, (0.0, 0.0)
            elif xi >= prev:
                if not rising:
                    rising, origin = True, (prev, y)
                if xi >= peak:
                    peak, y = xi, xi
                else:
                    xr, yr = origin
                    y = yr + (xi - xr) * (peak - yr) / max(peak - xr, 1e-12)
            else:
                if rising:
                    rising, origin = False, (prev, y)
                xp, yp = origin
                y = yp * (xi / xp) ** self.power if xp > 1e-12 else xi
            prev = xi
            out[i] = y
        return out


class OrificeSnubber(SimOnly):
    """The force behind a snubber orifice: y' = g (x - y) / sqrt(|x - y| + d0), g = 0.78 / ``tau_s`` (a change of
    1 N settles to 63 % in ``tau_s``), d0 = ``floor_n``; implicit per quarter step of a uniform grid, from x[0]."""

    def __init__(self, tau_s, floor_n=0.05):
        self.g, self.floor = 0.78 / tau_s, floor_n

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        sub = h / 4.0
        y, out = float(xu[0]), np.empty(tu.size)
        for i, xi in enumerate(xu.tolist()):
            for _ in range(4):
                k = self.g * sub / math.sqrt(abs(xi - y) + self.floor)
                y = (y + k * xi) / (1.0 + k)
            out[i] = y
        return np.interp(t, tu, out)


class RangeSwitchedFilter(SimOnly):
    """A first-order filter of ``tau_low`` while the reading is in the high-gain range (below ``up_v``, switching
    back below ``down_v``) and ``tau_high`` above: exact per sample, from x[0]."""

    def __init__(self, tau_low, tau_high, up_v, down_v):
        self.low, self.high, self.up, self.down = tau_low, tau_high, up_v, down_v

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        dt = np.diff(t, prepend=t[0]).tolist()
        y = float(x[0])
        upper, out = y > self.up, np.empty_like(x)
        for i, (xi, h) in enumerate(zip(x.tolist(), dt)):
            y = xi + (y - xi) * math.exp(-h / (self.high if upper else self.low))
            upper = y > (self.down if upper else self.up)
            out[i] = y
        return out


def tuning_fork(rel, top, stretched):
    """x read through a double-ended tuning fork by counting its period, slope 1 at zero: 2 x_b (1 - (1 + x /
    x_b)^(-1/2)) when the load stretches it (compressive), 2 x_b ((1 - x / x_b)^(-1/2) - 1) when it compresses it
    (expansive), x_b set for a departure ``rel`` at ``top``."""
    if stretched:
        def read(x, xb):
            return 2.0 * xb * (1.0 - np.maximum(1.0 + x / xb, 0.05) ** -0.5)
        xb = optimize.brentq(lambda b: read(top, b) / top - (1.0 - rel), 0.01 * top, 1e4 * top)
    else:
        def read(x, xb):
            return 2.0 * xb * (np.maximum(1.0 - x / xb, 0.05) ** -0.5 - 1.0)
        xb = optimize.brentq(lambda b: read(top, b) / top - (1.0 + rel), 1.06 * top, 1e4 * top)
    return lambda x: read(x, xb)


def diaphragm(rel, top):
    """The real root w of w + beta w^3 = x (Cardano), beta set for w = (1 - ``rel``) ``top`` at x = ``top``."""
    w_top = (1.0 - rel) * top
    beta = (top - w_top) / w_top ** 3

    def deflection(x):
        half = x / (2.0 * beta)
        root = np.sqrt(half * half + 1.0 / (27.0 * beta ** 3))
        return np.cbrt(half + root) + np.cbrt(half - root)
    return deflection


def post_curing_zero(t, temp, k_v_per_c, lag_s, uncured_gain, cure_s, b_per_c, cured0, step_s=0.5):
    """k (1 + g (1 - X)) (T_b - T_ref): the thermal output of a bond (temperature T_b, lag ``lag_s``) whose cure X
    advances as X' = exp(b (T_b - T_ref)) (1 - X) / ``cure_s`` from ``cured0`` (exact per coarse step)."""
    tb = follow(t, temp, lag_s)
    grid, tg = coarse(t, tb, step_s)
    cure, out = cured0, np.empty_like(tg)
    for i, ti in enumerate(tg.tolist()):
        out[i] = cure
        cure = 1.0 - (1.0 - cure) * math.exp(-step_s * math.exp(b_per_c * (ti - T_REF_C)) / cure_s)
    return k_v_per_c * (1.0 + uncured_gain * (1.0 - np.interp(t, grid, out))) * (tb - T_REF_C)


def peltier_zero(t, temp, k_v_per_c, lag_s, set_c, reach_c, board_s, step_s=0.5):
    """k (T_b - T_set): a board (time constant ``board_s``) in surroundings that follow ``temp`` (lag ``lag_s``),
    held at ``set_c`` by a Peltier element under PI control whose output is limited to hold ``reach_c`` against
    them (the integrator clamped at three times that: it winds up); Euler per coarse step, settled at the start."""
    grid, tg = coarse(t, follow(t, temp, lag_s), step_s)
    limit = reach_c / board_s  # degC/s the element can pump
    gain, integral_gain = 4.0 / board_s, 4.0 / board_s / 15.0
    board = min(max(float(tg[0]), set_c - reach_c), set_c + reach_c)
    integral = min(max((board - float(tg[0])) / board_s, -limit), limit)
    out = np.empty_like(tg)
    for i, ti in enumerate(tg.tolist()):
        out[i] = board
        error = set_c - board
        integral = min(max(integral + integral_gain * error * step_s, -3.0 * limit), 3.0 * limit)
        pump = min(max(gain * error + integral, -limit), limit)
        board += ((ti - board) / board_s + pump) * step_s
    return k_v_per_c * (np.interp(t, grid, out) - set_c)


class BimetalTrim(SimOnly):
    """The span times 1 + ``step`` while a bimetal switch on the electronics (lag ``lag_s``) is closed: it closes
    above ``on_c`` and opens below ``off_c`` (per coarse step of 0.5 s)."""

    def __init__(self, step, on_c, off_c, lag_s):
        self.step, self.on, self.off, self.lag = step, on_c, off_c, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        grid, tg = coarse(t, follow(t, temp_of(aux, t.size), self.lag), 0.5)
        closed, out = float(tg[0]) > self.on, np.empty(grid.size)
        for i, ti in enumerate(tg.tolist()):
            closed = ti > (self.off if closed else self.on)
            out[i] = closed
        return x * (1.0 + self.step * out[np.clip(np.searchsorted(grid, t, side="right") - 1, 0, grid.size - 1)])


class CurieGuide(SimOnly):
    """The span times ((T_c - T) / (T_c - T_ref))^beta, T the electronics' temperature (lag ``lag_s``), held 0.5
    degC below T_c."""

    def __init__(self, curie_c, beta, lag_s):
        self.curie, self.beta, self.lag = curie_c, beta, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tl = np.minimum(follow(t, temp_of(aux, t.size), self.lag), self.curie - 0.5)
        return x * ((self.curie - tl) / (self.curie - T_REF_C)) ** self.beta


def fluoroscopy_zero(s, shots, prompt_s, delayed, trapped, tail_s, power):
    """The offset of radiation-induced conductivity: for each shot (start, length, level) a prompt part approaching
    the level with ``prompt_s``, and after it the reached level split into a prompt part that fades with
    ``prompt_s``, a ``delayed`` share decaying as (1 + u / ``tail_s``)^-``power`` and a ``trapped`` share that
    stays."""
    out = np.zeros_like(s)
    for at, length, level in shots:
        on = (s >= at) & (s < at + length)
        out[on] += level * -np.expm1(-(s[on] - at) / prompt_s)
        reached = level * -math.expm1(-length / prompt_s)
        after = s >= at + length
        u = s[after] - at - length
        out[after] += reached * (trapped + delayed * (1.0 + u / tail_s) ** -power
                                 + (1.0 - delayed - trapped) * np.exp(-u / prompt_s))
    return out


def tribo_zero(s, moves, leak_s):
    """The offset of charges picked up during moves (start, length, charge): each builds up linearly over its move
    and leaks away with ``leak_s``."""
    out = np.zeros_like(s)
    for at, length, charge in moves:
        on = (s >= at) & (s < at + length)
        out[on] += charge * (s[on] - at) / length
        after = s >= at + length
        out[after] += charge * np.exp(-(s[after] - at - length) / leak_s)
    return out


class LatencyDamper(SimOnly):
    """y'' + 2 zeta w (y' - x') + w^2 (y - x) + g (y' - x')(t - d) = 0: a mode with a velocity feedback that
    arrives ``delay_s`` late; semi-implicit Euler, four sub-steps, from rest (the feedback's history at zero)."""

    def __init__(self, f0_hz, zeta, gain, delay_s):
        self.w, self.zeta, self.gain, self.delay = 2.0 * math.pi * f0_hz, zeta, gain, delay_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        tu, xu, rate, sub = mode_steps(t, np.asarray(x, dtype=float))
        lag = max(1, int(round(self.delay / sub)))
        history, at = [0.0] * lag, 0
        w2, c = self.w * self.w, 2.0 * self.zeta * self.w
        y, v, out = xu[0], 0.0, np.empty(len(xu))
        for i, (xi, ri) in enumerate(zip(xu, rate)):
            for _ in range(4):
                dv = v - ri
                v += (-c * dv - w2 * (y - xi) - self.gain * history[at]) * sub
                y += v * sub
                history[at] = dv
                at = (at + 1) % lag
            out[i] = y
        return np.interp(t, tu, out)


class ParticleDamperMode(SimOnly):
    """y'' + 2 zeta w (y' - x') + w^2 (y - x) = 0 plus a free ball of ``mass_ratio`` in a cavity of +-``gap_v``
    about y, striking its walls with restitution ``restitution`` (momentum kept); semi-implicit Euler, four
    sub-steps, from rest with the ball centred."""

    def __init__(self, f0_hz, zeta, mass_ratio, gap_v, restitution):
        self.w, self.zeta, self.mu, self.gap, self.e = 2.0 * math.pi * f0_hz, zeta, mass_ratio, gap_v, restitution

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        tu, xu, rate, sub = mode_steps(t, np.asarray(x, dtype=float))
        w2, c, mu, e, gap = self.w * self.w, 2.0 * self.zeta * self.w, self.mu, self.e, self.gap
        y, v, ball, vb, out = xu[0], 0.0, xu[0], 0.0, np.empty(len(xu))
        for i, (xi, ri) in enumerate(zip(xu, rate)):
            for _ in range(4):
                v += (-c * (v - ri) - w2 * (y - xi)) * sub
                y += v * sub
                ball += vb * sub
                r = ball - y
                if (r > gap and vb > v) or (r < -gap and vb < v):
                    common = (v + mu * vb) / (1.0 + mu)
                    v, vb = common + mu * e * (vb - v) / (1.0 + mu), common - e * (vb - v) / (1.0 + mu)
                    ball = y + (gap if r > 0.0 else -gap)
            out[i] = y
        return np.interp(t, tu, out)


def rate_state_band(band_n, a, b, slip_n, floor_rate=0.2, ref_rate=1.0):
    """A Coulomb play whose band is band (1 + a ln(v / v*) + b ln(theta v* / L)), held within 0.4-2.5 times band:
    v the rate the passed force slides at (N/s, at least ``floor_rate``), theta the contact's state under the ageing
    law theta' = 1 - theta v / L (L = ``slip_n``); exact per sample for theta, the band from the previous sample, from
    p = F[0] at the steady state of v*."""
    def passed(t, f):
        dt = np.diff(t, prepend=t[0]).tolist()
        p, theta, rate, out = float(f[0]), slip_n / ref_rate, ref_rate, np.empty_like(f)
        for i, (fi, h) in enumerate(zip(f.tolist(), dt)):
            width = band_n * (1.0 + a * math.log(max(rate, floor_rate) / ref_rate) + b * math.log(theta * ref_rate / slip_n))
            width = min(max(width, 0.4 * band_n), 2.5 * band_n)
            moved = max(fi - width, min(fi + width, p))
            rate = abs(moved - p) / h if h > 0.0 else 0.0
            if rate > 0.0:
                steady = slip_n / rate
                theta = steady + (theta - steady) * math.exp(-rate * h / slip_n)
            else:
                theta += h
            p = moved
            out[i] = p
        return out
    return passed


def squeezed_grease_band(band_n, lubricated, squeeze_s, reflow_s, squeeze_at_n=3.0, step_s=0.05):
    """A Coulomb band band (w + (1 - w) s) / 0.7 (w = ``lubricated``), s the share of the grease film squeezed out:
    s' = (1 - s) F / (F_s ``squeeze_s``) - s / ``reflow_s`` (exact per step of ``step_s`` at the step's force),
    from a full film."""
    def passed(t, f):
        grid, fg = coarse(t, f, step_s)
        share, out = 0.0, np.empty(grid.size)
        for i, fi in enumerate(fg.tolist()):
            out[i] = share
            press, back = max(fi, 0.0) / (squeeze_at_n * squeeze_s), 1.0 / reflow_s
            goal = press / (press + back)
            share = goal + (share - goal) * math.exp(-(press + back) * step_s)
        width = band_n * (lubricated + (1.0 - lubricated) * np.interp(t, grid, out)) / 0.7
        return band_play(f, width, width)
    return passed


def on_clock(c, t, f, rate):
    """The core's deformation on the clock ``rate`` (its reduced time, from t[0])."""
    return simulate_deformation(c, integrate.cumulative_trapezoid(rate, t, initial=0.0) + t[0], f)


class GapConductanceClock(SimOnly):
    """A Burgers core on the clock exp(b (T_c - T_ref)), T_c following the temperature with ``open_s`` below
    ``close_c`` and ``closed_s`` above it (a mount whose thermal contact closes as the core expands; a smooth
    switch over 0.3 degC), exact per coarse step of 0.5 s, settled at the start."""

    def __init__(self, c, b_per_c, close_c, open_s, closed_s):
        self.c, self.b, self.close, self.open, self.closed = c, b_per_c, close_c, open_s, closed_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        grid, tg = coarse(t, temp_of(aux, t.size), 0.5)
        core_t, out = float(tg[0]), np.empty(grid.size)
        for i, ti in enumerate(tg.tolist()):
            out[i] = core_t
            contact = float(quintic((core_t - self.close) / 0.3 + 0.5))
            rate = (1.0 - contact) / self.open + contact / self.closed
            core_t = ti + (core_t - ti) * math.exp(-0.5 * rate)
        clock = np.exp(self.b * (np.interp(t, grid, out) - T_REF_C))
        return on_clock(self.c, t, np.asarray(x, dtype=float), clock)


class SkinBulkClock(SimOnly):
    """A Burgers core whose retardation (the Zener part) runs on exp(b (T_skin - T_ref)) and whose flow on
    exp(b (T_bulk - T_ref)), the two following the temperature with ``skin_s`` and ``bulk_s``."""

    def __init__(self, c, b_per_c, skin_s, bulk_s):
        self.c, self.b, self.skin, self.bulk = c, b_per_c, skin_s, bulk_s

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        temp = temp_of(aux, t.size)
        skin = np.exp(self.b * (follow(t, temp, self.skin) - T_REF_C))
        bulk = np.exp(self.b * (follow(t, temp, self.bulk) - T_REF_C))
        zener = Zener(self.c.k1_n_per_v, self.c.k2_n_per_v, self.c.eta2_n_s_per_v)
        flow = integrate.cumulative_trapezoid(bulk * f / self.c.eta1_n_s_per_v, t, initial=0.0)
        return on_clock(zener, t, f, skin) + flow


def tool_tilt(weight_n, times_s, spans_s, angles):
    """The share of the tool's weight along the sensor's axis, W (cos theta - cos theta_0), theta moving to
    ``angles[k]`` by a minimum-jerk move of ``spans_s[k]`` at ``times_s[k]`` since the first sample, added to the
    applied force."""
    def passed(t, f):
        s, theta = t - t[0], np.full(t.size, float(angles[0]))
        for at, span, frm, to in zip(times_s, spans_s, angles[:-1], angles[1:]):
            theta = np.where(s >= at, frm + (to - frm) * quintic((s - at) / span), theta)
        return f + weight_n * (np.cos(theta) - math.cos(float(angles[0])))
    return passed


class ConcealedLoss(SimOnly):
    """Bursts of lost samples (at ``times_s`` since the first sample, ``lengths_s`` long) replaced by the straight
    line from the last sample before each burst to the first after it."""

    def __init__(self, times_s, lengths_s):
        self.times, self.lengths = np.asarray(times_s), np.asarray(lengths_s)

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        y, s = x.copy(), t - t[0]
        for at, length in zip(self.times.tolist(), self.lengths.tolist()):
            i0, i1 = int(np.searchsorted(s, at)), int(np.searchsorted(s, at + length))
            if 0 < i0 < i1 < x.size:
                y[i0:i1] = np.interp(t[i0:i1], [t[i0 - 1], t[i1]], [x[i0 - 1], x[i1]])
        return y


def normalised(fn, size, horizon_s=DURATION_S + 60.0):
    """``fn(s)`` scaled so that its largest magnitude over ``horizon_s`` (on a 0.1 s grid) is ``|size|``, with the
    sign of ``size``."""
    peak = float(np.max(np.abs(fn(np.arange(0.0, horizon_s, 0.1)))))
    return lambda s: size / max(peak, 1e-12) * fn(s)


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    top = FORCE_MAX_N / c.relaxation().g0_n_per_v  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([8e4, 4e3]))))  # V / (N s)
        if shape == "wetting_flow":
            rule = wetting_flow(phi * rng.uniform(0.3, 0.6), phi * rng.uniform(2.0, 4.0), rng.uniform(150.0, 600.0),
                                rng.uniform(0.0, 120.0))
            return Parts("zener", ZenerWithFlow(c, rule), core_changed=True)
        rule = pivot_cold_flow(phi * rng.uniform(2.0, 4.0), phi * rng.uniform(40.0, 300.0))
        return Parts("zener", ZenerWithFlow(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        if shape == "relaxing_grommet":
            p.before.append(ForcePath(relaxing_grommet(float(np.interp(m, [0, 1], [0.05, 0.3])),
                                                       rng.uniform(3.0, 40.0))))
            return p
        compliance = float(np.interp(m, [0, 1], [0.008, 0.07]))
        a = (compliance, rng.uniform(2.0, 25.0), compliance * rng.uniform(1.5, 4.0), rng.uniform(2.0, 4.0))
        p.extra.append(lambda t, f, T, a=a: buckling_kelvin(t, f, *a))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.01, 0.06]))
        if shape == "craze_avalanches":
            coupling = rng.uniform(0.15, 0.3) * top
            up = rng.uniform(0.1, 1.0, 64) * top
            down = np.maximum(up * rng.uniform(0.2, 0.7, 64), 1.2 * coupling)
            p.after.append(CrazeAvalanches(up, np.minimum(down, 0.95 * up), coupling, 2.5 * frac * top))
            return p
        p.after.append(PeakOrientedCracks(-math.log2(0.5 - 1.5 * frac)))  # pinched by 1.5 frac of the peak at its half
        return p
    if effect == "sensor_lag":
        if shape == "orifice_snubber":
            p.before.append(OrificeSnubber(float(np.interp(m, [0, 1], [0.008, 0.045])) * rng.uniform(0.8, 1.2)))
            return p
        slow = float(np.interp(m, [0, 1], [0.008, 0.05])) * rng.uniform(0.8, 1.2)
        up = rng.uniform(0.25, 0.5) * top
        p.after.append(RangeSwitchedFilter(slow, slow / rng.uniform(3.0, 6.0), up, 0.9 * up))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.06, 0.15]))
        if shape == "tuning_fork_period":
            p.after.append(StaticMap(tuning_fork(rel, top, bool(rng.random() < 0.5))))
            return p
        p.after.append(StaticMap(diaphragm(rel, top)))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.02]) * rng.choice([-1, 1]))
        if shape == "post_curing_adhesive":
            a = (k, rng.uniform(10.0, 40.0), rng.uniform(0.5, 1.5), rng.uniform(300.0, 1500.0), rng.uniform(0.1, 0.3),
                 rng.uniform(0.3, 0.7))
            p.extra.append(lambda t, f, T, a=a: post_curing_zero(t, T, *a))
            return p
        a = (2.0 * k, rng.uniform(5.0, 20.0), T_REF_C + rng.uniform(0.5, 2.0), rng.uniform(0.3, 1.0), rng.uniform(20.0, 60.0))
        p.extra.append(lambda t, f, T, a=a: peltier_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        if shape == "bimetal_trim":
            on = T_REF_C + rng.uniform(0.0, 1.0)
            step = float(np.interp(m, [0, 1], [0.025, 0.09]) * rng.choice([-1, 1]))
            p.after.append(BimetalTrim(step, on, on - rng.uniform(0.5, 1.2), rng.uniform(15.0, 60.0)))
            return p
        drop, beta = float(np.interp(m, [0, 1], [0.03, 0.12])), rng.uniform(0.3, 0.45)
        distance = 4.0 / (1.0 - (1.0 - drop) ** (1.0 / beta))  # T_c - T_ref for the drop at 4 degC
        p.after.append(CurieGuide(T_REF_C + distance, beta, rng.uniform(10.0, 40.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.08]) * rng.choice([-1, 1]))
        if shape == "fluoroscopy_charge":
            n = int(rng.integers(8, 26))
            shots = list(zip(np.sort(rng.uniform(0.03, 0.95, n)) * DURATION_S, rng.uniform(0.5, 3.0, n),
                             rng.uniform(0.5, 1.0, n)))
            a = (shots, rng.uniform(0.05, 0.3), rng.uniform(0.3, 0.6), rng.uniform(0.05, 0.2), rng.uniform(1.0, 5.0),
                 rng.uniform(0.5, 1.0))
            zero = normalised(lambda s, a=a: fluoroscopy_zero(s, *a), size)
            p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
            return p
        times = np.cumsum(rng.exponential(rng.uniform(8.0, 40.0), 128))
        times = times[times < DURATION_S + 60.0]
        moves = list(zip(times, rng.uniform(0.5, 2.0, times.size), rng.normal(0.0, 1.0, times.size)
                         * rng.lognormal(0.0, 0.5, times.size)))
        leak = rng.uniform(20.0, 120.0)
        zero = normalised(lambda s, a=(moves, leak): tribo_zero(s, *a), size)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        f0, zeta = rng.uniform(20.0, 50.0), float(np.interp(m, [0, 1], [0.06, 0.015])) * rng.uniform(0.8, 1.2)
        if shape == "latency_damper":
            phase, taken = rng.uniform(0.65, 0.9) * math.pi, zeta * rng.uniform(0.5, 1.2)
            w = 2.0 * math.pi * f0
            p.after.append(LatencyDamper(f0, zeta + taken, 2.0 * w * taken / -math.cos(phase), phase / w))
            return p
        p.after.append(ParticleDamperMode(f0, zeta, rng.uniform(0.05, 0.15), top / FORCE_MAX_N * rng.uniform(0.1, 0.4),
                                          rng.uniform(0.3, 0.7)))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "rate_state_friction":
            a = rng.uniform(0.02, 0.05)
            p.before.append(ForcePath(rate_state_band(r, a, a + rng.uniform(0.1, 0.2), rng.uniform(0.05, 0.3))))
            return p
        p.before.append(ForcePath(squeezed_grease_band(r, rng.uniform(0.3, 0.6), rng.uniform(5.0, 30.0),
                                                       rng.uniform(20.0, 90.0))))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.1, 0.25]))
        if shape == "gap_conductance_clock":
            open_s = rng.uniform(60.0, 150.0)
            return Parts("burgers", GapConductanceClock(c, b, T_REF_C + rng.uniform(-0.5, 1.5), open_s,
                                                        open_s / rng.uniform(4.0, 10.0)), core_changed=True)
        return Parts("burgers", SkinBulkClock(c, b, rng.uniform(3.0, 15.0), rng.uniform(60.0, 200.0)), core_changed=True)
    if effect == "tool_weight_tilt":
        weight = float(np.interp(m, [0, 1], [0.5, 3.0]))
        times = np.cumsum(rng.uniform(20.0, 80.0, 40))
        times = times[times < DURATION_S + 60.0]
        angles = np.radians(rng.uniform(0.0, 60.0, times.size + 1))
        p.before.append(ForcePath(tool_tilt(weight, times, rng.uniform(2.0, 5.0, times.size), angles)))
        return p
    if effect == "concealed_packet_loss":
        times = np.cumsum(rng.exponential(rng.uniform(3.0, 15.0), 512))
        times = times[times < DURATION_S + 60.0]
        lengths = float(np.interp(m, [0, 1], [0.03, 0.3])) * rng.uniform(0.5, 1.5, times.size)
        p.outer.append(ConcealedLoss(times, lengths))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["wetting_flow", "pivot_cold_flow"],
    "delayed_elasticity": ["relaxing_grommet", "buckling_wall_kelvin"],
    "hysteresis": ["craze_avalanches", "peak_oriented_cracks"],
    "sensor_lag": ["orifice_snubber", "range_switched_filter"],
    "nonlinear_gain": ["tuning_fork_period", "diaphragm_stretching"],
    "thermal_drift": ["post_curing_adhesive", "peltier_windup"],
    "thermal_sensitivity": ["bimetal_trim", "curie_flux_guide"],
    "offset_drift": ["fluoroscopy_charge", "tribo_cable_charge"],
    "resonance": ["latency_damper", "particle_damper_mode"], "friction": ["rate_state_friction", "squeezed_grease"],
    "thermo_rheological": ["gap_conductance_clock", "skin_bulk_clock"],
}
PAIRS = (("viscous_flow", "sensor_lag"), ("delayed_elasticity", "nonlinear_gain"), ("hysteresis", "thermal_sensitivity"),
         ("friction", "offset_drift"), ("thermo_rheological", "thermal_drift"), ("resonance", "viscous_flow"))
OUTSIDE = ("tool_weight_tilt", "concealed_packet_loss")
RATES = (190.0, 440.0, 670.0, 910.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split Q", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.2e-3, 2.5e-3), jitter=0.3,
                   gap_s=(0.1, 2.0))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
