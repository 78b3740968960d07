"""Independent split AB for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split AB is an untouched held-out set: written blind to the engine it measures (to how it detects and fits anything),
run once, and nothing is ever chosen from it. Every name of the catalogue is hidden in two shapes that neither the
registry's families (``polyforce_ros/sim/truths.py``) nor splits A to AA use:

* a core leaking a wormlike-micelle solution that shear-bands (a low-shear branch at 0.3-0.7 times the plain fluidity
  of 1/40000-1/4500 V/(N s); above 1.5-5 N a high-shear band, 3-9 times it, nucleates and fills the gap within 0.3-5 s
  and dissolves only once the force falls below 40-80 % of that: hysteresis between the two branches of the flow
  curve), or a freshly annealed fine-grained core creeping by grain-boundary and lattice diffusion (Coble, d^-3, 30-80 %
  of it, and Nabarro-Herring, d^-2) while its grains coarsen (d^2 growing linearly, 30-300 s per doubling of the area,
  annealed 0-600 s before the first sample; 1.5-4.5 times the plain fluidity at the first sample); neither ever
  recovers;
* a Kelvin unit whose spring is a paper-phenolic spacer that creeps faster while its moisture content changes
  (mechanosorption: the rate 1 + 2-8 times the normalised rate of change of its moisture, which follows the
  enclosure's wandering humidity with 30-120 s; 1-20 s when dry and still), or a fluid-filled core whose expelled oil
  rises in a long line to a compliant bellows, so that its delayed share settles with an overshoot (the column's
  inertance against the bellows' compliance: an undamped period of 1.5-12 s, damping ratio 0.2-0.65); both settle at
  2-24 % of the instantaneous response;
* a magnetic read-out whose thin-film flux guide switches as a random-field Ising model at zero temperature (Sethna's
  crackling noise: 20 x 20 grains coupled to their four neighbours, random fields of spread 0.9-2.2 times the
  coupling, the loop centred at 25-50 % of the range, avalanches, return-point memory; the firmware linearises the
  mean curve of two full-range cycles made before use), or a capacitive read-out whose gap holds a drop of dielectric
  liquid (permittivity 2-30 times air's) whose contact line stays pinned while the drop's bulge is within its
  advancing (3-10 %) and receding (6-25 %) limits (contact-angle hysteresis; the gap closing by 15-45 % over the
  range); loops of 1-7 % of the range in a full-range cycle (at the loop's centre, or half-way up);
* firmware that averages the ADC's codes exponentially in integer arithmetic at 1 or 2 kHz (y += (x - y) >> k: a lag
  of 2^k samples that, approaching from below, stalls up to 2^k - 1 codes short, those codes 0.2-1.2 % of the range
  in all and at most 1.5 mV each), or a fibre-Bragg-grating read-out whose interrogator sweeps a laser across its
  window once a period (50-90 % of it sweeping, up or down, reported 5-30 % of a period after the sweep and held):
  the force sampled at a moment that depends on the force itself; 8-120 ms of mean delay;
* an intensity read-out that couples light between two fibres whose cores the load moves apart sideways (Gaussian
  modes: exp(-d^2), from an offset of 0.25-1.2 mode radii: expansive then compressive, or compressive), or a conical
  compression spring in the read-out whose coils bottom out one by one, the widest first (a taper of 0.3-0.7; read as
  the spring's force under the core's deformation, stiffening, or as its travel under the core's force, softening);
  4.5-20 % at the top of the range;
* the zero of a quartz double-ended tuning fork whose working mode couples to a spurious one with another temperature
  coefficient (the activity dip: a dispersive anomaly, the pull g^2 / dT on either side and a jump of 2g where their
  frequencies cross, 1.5-6 degC from the reference, g 0.2-1 degC; the anomaly 0.5-3 degC of the plain slope), or of
  an amplifier's input transistor whose 24 oxide traps each relax toward a Fermi occupancy of the temperature (centres
  spread by 6-20 degC about the reference, 1.5-4 degC wide) at an Arrhenius rate (3-300 s at the reference, 0.04-0.1
  e-folds faster per degC); lag 5-35 s; 0.006-0.034 V/degC at the reference;
* an optical read-out whose laser diode's wavelength drifts with its temperature across a wavelength-selective
  coupler and mode-hops back every 1.2-4 degC (by 50-90 % of the drift between hops, with a hysteresis of 10-35 %
  of the hop: a sawtooth with memory), or a read-out lever whose arm is a liquid-crystal elastomer strip that
  contracts with its nematic order (Landau-de Gennes: the order falling ever faster toward the nematic-isotropic
  transition, up to 40 degC above the reference, supercooling 1.5-3 degC, the strip 0.7-1.1 times the order's share
  of the span); lag 5-30 s; 1.4-3.6 %/degC at the reference, either sign;
* the zero of an optical read-out whose connector's ferrule gap holds an index-matching gel that the connector's
  spring squeezes out (Stefan: the gap thinning as (1 + t / 20-300 s)^-0.5 from 0-300 s before the first sample,
  a parasitic etalon sweeping 0.7-4 fringes over the record, ever more slowly), or a sealed-gauge read-out in an
  isolation room whose exhaust damper hunts (a van der Pol limit cycle, mu 0.5-4, a small-swing period of 25-90 s;
  1-4 door openings kick it); 15-100 mV at most;
* a needle holder built as a cantilever with three bending modes (1 : 6.27 : 17.5, the first at 11-52 Hz; the second
  and third carrying 2-15 % and 0.5-5 % of the static response; Rayleigh damping, 20-80 % of the first mode's
  stiffness-proportional, so the higher modes are damped more), or a holder's mode (11-52 Hz) whose oil damper heats
  with the energy it dissipates (its damping falling by up to 30-70 % after the largest knocks, recovering with 1-10
  s); damping ratio 0.0034-0.036 (the cold damper's), the frequencies fixed;
* a Coulomb band of 0.2-5.3 % of the range, the same at every load: a needle guide whose sliding charges it
  triboelectrically (the electroadhesion growing the band from 35-60 % to 110-140 % of it over 2-15 N of slid force,
  leaking away with 15-120 s), or a needle feed with a spring-applied holding brake that the controller applies once
  the force has been still for 0.3-1.5 s and releases 20-80 ms after it starts to change (15-40 % of the band
  remaining while released);
* a core (soft enough for its clock to show) whose clock follows Dyre's shoving model (log tau as the instantaneous
  shear modulus over T, the modulus softening by 0.5-2 %/degC), or the power law of mode-coupling theory (tau as (T -
  T_c)^-gamma, gamma 1.6-3.2, T_c below the reference by gamma over the slope); 1.2-1.5 times 0.16-0.56 per degC at
  the reference, lag 5-25 s.

It also holds six pairs, two effects outside the catalogue (a two-scale interferometric read-out whose phasemeter,
updating at 0.8-2.5 kHz with a little phase noise, unwraps the phase and loses or gains a whole fringe of 3-8 % of the
range whenever the reading moves more than half a fringe between its updates, until its coarse channel re-resolves
the fringe order, every 0.2-1.2 s; a data logger that stores the reading
as 6-9 bit mu-law codes, mu 100-255, over 1.5-2 times the core's output at 9 N, clipped beyond) and four clean
records. Profiles: a needle robot inserting along paths whose layers are drawn from the measured Okamura insertion
(``../shared/data``, ``time_force.csv``: the curve cut at its puncture drops into layers, 2-5 of them drawn with
replacement, each stretched 0.6-1.8 times in time and 0.5-1.5 times in force and chained end to end, then the
measured hold's relaxation compressed to 20-100 % of its length and the measured withdrawal at 0.5-1.6 times its
length, each insertion scaled to a 2-8.8 N peak, 3-20 s apart; a train of synthetic punctures when the data are
absent); a robot polishing panels under force control (set points of 1.5-7 N reached through its closed loop, 4-14
rad/s, damping 0.3-0.75, 2-4 passes of 2-5 strokes, the surface's waviness partly rejected, the tool lifting off at
each stroke's edge); and a liquid-handling robot's pipetting head (tip pick-up with a snap over the cone's sealing
ring, the tip's grip, foil seals pierced, touch-offs, aspiration and dispensing, touching off on the well's wall,
blow-out, ejection).
Rates 125, 305, 495 and 805 Hz (a mode at 1000 Hz with knocks that excite it), 0.8-2.6 mV noise, stamp jitter,
gaps, and a sensor on a mobile manipulator in a server room that moves between its cold aisles, its hot aisles and
its open floor.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size against its
noise without diagnosing (for a leak on a Zener base, against that bare Zener core).

    .venv/bin/python bench/independent_split_ab.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, optimize, signal

from independent_split import puncture_train
from polyforce_ros.physics.viscoelastic import Burgers
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (coarse_force, cutter, ease, fit_departure, follow, LeakingCore, on_clock, Parts, ShapeSplit,
                       GridMode, SimOnly, sized as sized_over, temp_of)

SEED0 = 2_000_000  # never a seed of the registry's splits nor of splits A (90000..) to AA (1900000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 470.0
HORIZON_S = DURATION_S + 60.0  # what a schedule drawn before the record covers (the record plus its gaps' slack)

sized = functools.partial(sized_over, horizon_s=HORIZON_S)


# ----------------------------------------------------------------------------- small tools

def held(t, when, values, before):
    """At each of ``t``, the last of ``values`` whose time ``when`` (increasing) has come; ``before`` until the
    first."""
    idx = np.searchsorted(when, t, side="right") - 1
    return np.where(idx >= 0, np.asarray(values, dtype=float)[np.clip(idx, 0, None)], before)


def closed_loop(u, wn, zeta):
    """The step response of a damped pole pair (``wn`` rad/s, damping ``zeta`` < 1) ``u`` seconds after the step;
    0 before it."""
    u = np.maximum(np.asarray(u, dtype=float), 0.0)
    root = math.sqrt(1.0 - zeta * zeta)
    return 1.0 - np.exp(-zeta * wn * u) * (np.cos(wn * root * u) + zeta / root * np.sin(wn * root * u))


# ----------------------------------------------------------------------------- profiles and temperature

@functools.lru_cache(maxsize=1)
def okamura_pieces():
    """The measured Okamura insertion (``../shared/data``, ``time_force.csv``) at 1 kHz, its peak 1, cut into its
    parts: the layers (from the onset, or from the bottom of one puncture drop, to the bottom of the next: each a rise
    that ends in a tear), the hold that follows the last (the liver relaxing, relative to where it starts) and the
    withdrawal (from 1 to 0). None when the data are absent."""
    try:
        _, fp = profiles.okamura_insertion(peak_n=1.0, rate_hz=1000.0, pre_s=0.0, post_s=0.0)
    except FileNotFoundError:
        return None
    s = np.convolve(fp, np.ones(25) / 25.0, mode="same")
    onset, peak = int(np.argmax(s > 0.03)), int(np.argmax(s))
    bottoms, i = [], onset + 30
    while i < min(peak + 150, s.size - 80):
        ahead = s[i:i + 80]
        if s[i] >= s[i - 30:i + 30].max() and s[i] - ahead.min() > 0.08:
            bottoms.append(i + int(np.argmin(ahead)))
            i = bottoms[-1] + 30
        else:
            i += 1
    if not bottoms:
        bottoms = [peak]
    cuts = [onset] + bottoms
    layers = tuple(np.clip(fp[a:b + 1], 0.0, None) for a, b in zip(cuts[:-1], cuts[1:]))
    end = bottoms[-1]
    w = min(end + 2000, s.size - 1)
    while w < s.size - 1 and s[w] >= 0.8 * s[w - 300]:
        w += 1
    w0 = max(end + 100, w - 200)
    hold = np.clip(s[end:w0] / max(float(s[end]), 1e-6), 0.0, None)
    tail = s[w0:]
    stop = int(np.argmax(tail <= 0.01)) if np.any(tail <= 0.01) else tail.size - 1
    withdraw = np.clip(tail[:stop + 1] / max(float(tail[0]), 1e-6), 0.0, None)
    withdraw[-1] = 0.0
    return layers, hold, withdraw


def layer_bootstrap(duration_s, rate_hz, rng):
    """A needle robot inserting along paths whose layers are drawn from the measured Okamura insertion
    (:func:`okamura_pieces`): 2-5 layers drawn with replacement, each stretched 0.6-1.8 times in time and 0.5-1.5
    times in force and chained end to end (each starting where the last ended); then the measured hold's relaxation
    compressed to 20-100 % of its length and the measured withdrawal at 0.5-1.6 times its length. Each insertion is
    scaled to a 2-8.8 N peak; 3-20 s to the next. A train of synthetic punctures when the data are absent."""
    pieces = okamura_pieces()
    if pieces is None:
        return puncture_train(duration_s, rate_hz, rng)
    layers, hold, withdraw = pieces
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)

    def resampled(y, seconds):
        n = max(2, int(round(seconds * rate_hz)))
        return np.interp(np.linspace(0.0, y.size - 1.0, n), np.arange(y.size), y)

    cursor = rng.uniform(2.0, 6.0)
    while True:
        level, parts = 0.0, []
        for _ in range(int(rng.integers(2, 6))):
            layer = layers[int(rng.integers(len(layers)))]
            y = resampled(layer, layer.size / 1000.0 * rng.uniform(0.6, 1.8))
            y = level + rng.uniform(0.5, 1.5) * (y - y[0])
            parts.append(y)
            level = float(y[-1])
        parts.append(level * resampled(hold, hold.size / 1000.0 * rng.uniform(0.2, 1.0)))
        level = float(parts[-1][-1])
        parts.append(level * resampled(withdraw, withdraw.size / 1000.0 * rng.uniform(0.5, 1.6)))
        one = np.clip(np.concatenate(parts), 0.0, None)
        one *= rng.uniform(2.0, 8.8) / max(float(one.max()), 1e-9)
        i0 = int(cursor * rate_hz)
        if i0 + one.size >= t.size - 1:
            break
        f[i0:i0 + one.size] = one
        cursor += one.size / rate_hz + rng.uniform(3.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def lift_off(u, width_s, wn, zeta):
    """The share of the set point lost when the tool lifts off a panel's edge ``u`` seconds ago: gone over
    ``width_s``, then restored through the closed loop."""
    u = np.asarray(u, dtype=float)
    return np.where(u < 0.0, 0.0, np.where(u < width_s, ease(u / width_s), 1.0 - closed_loop(u - width_s, wn, zeta)))


def force_controlled_polishing(duration_s, rate_hz, rng):
    """A robot polishing panels under force control. Each panel: the closed loop (a damped pole pair of 4-14 rad/s,
    damping 0.3-0.75) takes the force to set points of 1.5-7 N in 2-4 passes of 2-5 strokes of 2-8 s (+-15 %), a
    new set point each pass; at the end of each stroke but the pass's last the tool runs over the panel's edge and
    loses 50-80 % of the force within 40-120 ms, which the loop restores; the surface's waviness (2-3 waves of
    0.2-2.5 Hz, 2-8 % of the mean set point each) comes through as much as the loop fails to reject it; the tool
    retracts over 0.15-0.5 s; 3-12 s to the next panel."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cursor = rng.uniform(1.0, 5.0)
    while cursor < duration_s - 30.0:
        wn, zeta = rng.uniform(4.0, 14.0), rng.uniform(0.3, 0.75)
        steps, dips, level, at, points = [], [], 0.0, 0.0, []
        for _ in range(int(rng.integers(2, 5))):
            point = rng.uniform(1.5, 7.0)
            steps.append((at, point - level))
            level = point
            points.append(point)
            strokes, stroke_s = int(rng.integers(2, 6)), rng.uniform(2.0, 8.0)
            for k in range(strokes):
                at += stroke_s * rng.uniform(0.85, 1.15)
                if k < strokes - 1:
                    dips.append((at, point * rng.uniform(0.5, 0.8), rng.uniform(0.04, 0.12)))
        retract = rng.uniform(0.15, 0.5)
        i0, i1 = np.searchsorted(t, [cursor, cursor + at + retract])
        s = t[i0:i1] - cursor
        y = np.zeros_like(s)
        for when, delta in steps:
            y += delta * closed_loop(s - when, wn, zeta)
        for when, depth, width in dips:
            y -= depth * lift_off(s - when, width, wn, zeta)
        band = wn / (2.0 * math.pi)
        for _ in range(int(rng.integers(2, 4))):
            hz = rng.uniform(0.2, 2.5)
            passed = (hz / band) / math.sqrt(1.0 + (hz / band) ** 2)
            y += (rng.uniform(0.02, 0.08) * float(np.mean(points)) * passed
                  * np.sin(2.0 * math.pi * hz * s + rng.uniform(0.0, 2.0 * math.pi)) * closed_loop(s, wn, zeta))
        y *= 1.0 - ease((s - at) / retract)
        f[i0:i1] = y
        cursor += at + retract + rng.uniform(3.0, 12.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def pipetting_head(duration_s, rate_hz, rng):
    """A liquid-handling robot's pipetting head, the sensor behind its tip cone. For each tip: the head presses onto a
    tip in its rack toward 3-8.8 N over 0.15-0.5 s; at 55-85 % of that the tip's collar snaps over the cone's sealing
    ring (the force dropping by 15-35 % within 8-15 ms before it climbs again); held 0.1-0.4 s and lifted (gone
    within 60-150 ms but for the tip's grip, 0.1-0.4 N, which stays); 2-6 transfers: in half of them the tip first
    pierces a plate's foil seal (2-7 N more over 0.2-0.6 s, torn within 10-20 ms down to 20-40 % of that, then
    dragging 0.3-1 N through the torn foil for 0.3-1 s); the tip touches the liquid's surface (0.05-0.2 N for 0.1
    s), aspirates (the liquid's weight, 0.02-0.15 N, over 0.5-1.5 s), travels, touches off on the well's wall
    (0.3-1.2 N for 0.1-0.4 s), dispenses over 0.3-1 s and blows out (0.1-0.4 N for 50-150 ms); the ejector then
    pushes the tip off (the force climbing to 2-6 N in 60-200 ms and gone within 4-10 ms, the grip with it); 4-15 s
    to the next tip."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cut = cutter(t)

    def go(cursor, length, start, end):
        seg, s = cut(cursor, length)
        f[seg] = start + (end - start) * ease(s / length)
        return cursor + length

    def stay(cursor, length, level):
        seg, _ = cut(cursor, length)
        f[seg] = level
        return cursor + length

    cursor = rng.uniform(1.0, 4.0)
    while cursor < duration_s - 40.0:
        press, rise = rng.uniform(3.0, 8.8), rng.uniform(0.15, 0.5)
        snap = press * rng.uniform(0.55, 0.85)
        cursor = go(cursor, rise * snap / press, 0.0, snap)
        seated = snap * (1.0 - rng.uniform(0.15, 0.35))
        cursor = go(cursor, rng.uniform(0.008, 0.015), snap, seated)
        cursor = go(cursor, rise * (press - seated) / press, seated, press)
        cursor = stay(cursor, rng.uniform(0.1, 0.4), press)
        grip = rng.uniform(0.1, 0.4)
        cursor = go(cursor, rng.uniform(0.06, 0.15), press, grip)
        cursor = stay(cursor, rng.uniform(0.5, 2.0), grip)
        for _ in range(int(rng.integers(2, 7))):
            if rng.random() < 0.5:  # a foil-sealed plate: the tip pierces the seal
                pierce = grip + rng.uniform(2.0, 7.0)
                cursor = go(cursor, rng.uniform(0.2, 0.6), grip, pierce)
                torn = grip + (pierce - grip) * rng.uniform(0.2, 0.4)
                cursor = go(cursor, rng.uniform(0.01, 0.02), pierce, torn)
                drag = grip + rng.uniform(0.3, 1.0)
                cursor = go(cursor, 0.1, torn, drag)
                cursor = stay(cursor, rng.uniform(0.3, 1.0), drag)
                cursor = go(cursor, 0.1, drag, grip)
            touch = grip + rng.uniform(0.05, 0.2)
            cursor = go(cursor, 0.03, grip, touch)
            cursor = go(cursor, 0.07, touch, grip)
            loaded = grip + rng.uniform(0.02, 0.15)
            cursor = go(cursor, rng.uniform(0.5, 1.5), grip, loaded)
            cursor = stay(cursor, rng.uniform(0.5, 2.0), loaded)
            wall = loaded + rng.uniform(0.3, 1.2)
            cursor = go(cursor, 0.05, loaded, wall)
            cursor = stay(cursor, rng.uniform(0.1, 0.4), wall)
            cursor = go(cursor, 0.05, wall, loaded)
            cursor = go(cursor, rng.uniform(0.3, 1.0), loaded, grip)
            blow = grip + rng.uniform(0.1, 0.4)
            cursor = go(cursor, 0.03, grip, blow)
            cursor = stay(cursor, rng.uniform(0.05, 0.15), blow)
            cursor = go(cursor, 0.03, blow, grip)
            cursor = stay(cursor, rng.uniform(0.5, 2.5), grip)
        eject = rng.uniform(2.0, 6.0)
        cursor = go(cursor, rng.uniform(0.06, 0.2), grip, eject)
        cursor = go(cursor, rng.uniform(0.004, 0.01), eject, 0.0)
        cursor += rng.uniform(4.0, 15.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (layer_bootstrap, force_controlled_polishing, pipetting_head)


def server_aisles(t, rng, step_s=0.5):
    """A sensor on a mobile manipulator servicing a server room, from 600 s before the record: the room 1.5 degC below
    to 0.5 degC above the reference, drifting by up to +-0.3 degC over the record, its air conditioner cycling by
    0.15-0.5 degC (a triangle with a period of 240-700 s); the robot works 20-150 s at a time in a cold aisle
    (0.5-2.5 degC below the room), a hot aisle (1.5-4.5 degC above it) or on the open floor, each visit within 20 % of
    its aisle's level, and moves between them in 5-15 s (a linear blend); the air's turbulence adds a random swing (an
    Ornstein-Uhlenbeck signal of 0.1-0.35 degC with 3-15 s, half as large again in a hot aisle). The sensor follows
    with 6-30 s (exact per step of ``step_s``)."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-600.0, d + 2.0 * step_s, step_s)
    room = T_REF_C + rng.uniform(-1.5, 0.5) + rng.uniform(-0.3, 0.3) * np.clip(grid / d, 0.0, 1.0)
    swing, period, phase = rng.uniform(0.15, 0.5), rng.uniform(240.0, 700.0), rng.uniform(0.0, 2.0 * math.pi)
    crac = swing * (2.0 / math.pi) * np.arcsin(np.sin(2.0 * math.pi * grid / period + phase))
    levels = (rng.uniform(-2.5, -0.5), rng.uniform(1.5, 4.5), 0.0)
    place = int(rng.integers(3))
    offs, hot = np.zeros(grid.size), np.zeros(grid.size, dtype=bool)
    at, was = float(grid[0]), levels[place] * rng.uniform(0.8, 1.2)
    while at < grid[-1]:
        dwell = rng.uniform(20.0, 150.0)
        sel = (grid >= at) & (grid < at + dwell)
        offs[sel], hot[sel] = was, place == 1
        at += dwell
        place = (place + int(rng.integers(1, 3))) % 3
        new, move = levels[place] * rng.uniform(0.8, 1.2), rng.uniform(5.0, 15.0)
        sel = (grid >= at) & (grid < at + move)
        offs[sel] = was + (new - was) * (grid[sel] - at) / move
        at += move
        was = new
    sigma, keep = rng.uniform(0.1, 0.35), math.exp(-step_s / rng.uniform(3.0, 15.0))
    kicks = rng.normal(0.0, sigma * math.sqrt(1.0 - keep * keep), grid.size)
    swirl, _ = signal.lfilter([1.0], [1.0, -keep], kicks, zi=[0.0])
    air = room + crac + offs + swirl * np.where(hot, 1.5, 1.0)
    keep = math.exp(-step_s / rng.uniform(6.0, 30.0))
    sensor, _ = signal.lfilter([1.0 - keep], [1.0, -keep], air, zi=[keep * air[0]])
    return np.interp(s, grid, sensor)


# ----------------------------------------------------------------------------- viscous flow

def banding_leak(low, high, up_n, down_n, nucleate_s, step_s=0.01):
    """x' = A F: a core leaking a wormlike-micelle solution that shear-bands. On the low-shear branch the fluidity is
    ``low``; once the force passes ``up_n`` a high-shear band (fluidity ``high``) nucleates and fills the gap with a
    time constant ``nucleate_s``, and it dissolves again (as fast) only once the force falls below ``down_n``: the two
    branches of a non-monotonic flow curve, with hysteresis between them. Exact exponential steps of ``step_s``, from
    the low branch. It never recovers."""
    def rule(t, f):
        grid, fg = coarse_force(t, f, step_s)
        keep = math.exp(-step_s / nucleate_s)
        share, goal = 0.0, 0.0
        rate = np.empty(grid.size)
        for i, fi in enumerate(fg.tolist()):
            if fi > up_n:
                goal = 1.0
            elif fi < down_n:
                goal = 0.0
            share = goal + (share - goal) * keep
            rate[i] = (low + (high - low) * share) * max(fi, 0.0)
        return np.interp(t, grid, integrate.cumulative_trapezoid(rate, grid, initial=0.0))
    return rule


def coarsening_leak(fresh, ago_s, grow_s, coble):
    """x' = A(t) F: a fine-grained core annealed ``ago_s`` before the first sample, creeping by grain-boundary
    diffusion (Coble, A ~ d^-3; ``coble`` of the fluidity at the first sample) and lattice diffusion (Nabarro-Herring,
    A ~ d^-2) while its grains coarsen (normal grain growth, d^2 = d0^2 (1 + t / ``grow_s``) from the anneal): the
    fluidity, ``fresh`` at the first sample, falls as the powers -1.5 and -1 of 1 + (t + ago) / grow. It never
    recovers."""
    d0 = 1.0 + ago_s / grow_s
    a_c, a_n = fresh * coble * d0 ** 1.5, fresh * (1.0 - coble) * d0

    def rule(t, f):
        d = 1.0 + (t - t[0] + ago_s) / grow_s
        return integrate.cumulative_trapezoid((a_c * d ** -1.5 + a_n / d) * np.maximum(f, 0.0), t, initial=0.0)
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def spacer_moisture(seed, horizon_s, step_s=0.5):
    """The moisture of a paper-phenolic spacer (relative units), from 300 s before the first sample: the enclosure's
    humidity wanders (an Ornstein-Uhlenbeck signal with 40-200 s, from ``seed``) and the spacer follows it with
    30-120 s. (seconds since the first sample, moisture) on a grid of ``step_s``."""
    rng = np.random.default_rng(seed)
    grid = np.arange(-300.0, horizon_s + 2.0 * step_s, step_s)
    keep = math.exp(-step_s / rng.uniform(40.0, 200.0))
    humid, _ = signal.lfilter([1.0], [1.0, -keep], rng.normal(0.0, math.sqrt(1.0 - keep * keep), grid.size), zi=[0.0])
    keep = math.exp(-step_s / rng.uniform(30.0, 120.0))
    moist, _ = signal.lfilter([1.0 - keep], [1.0, -keep], humid, zi=[keep * humid[0]])
    return grid, moist


def mechanosorptive_kelvin(t, f, compliance_v_per_n, tau_s, boost, seed, step_s=0.005):
    """A Kelvin unit in series with the core whose spring is a paper-phenolic spacer: it creeps toward C F (C =
    ``compliance_v_per_n``) at the rate (1 + ``boost`` |m'| / mean |m'|) / ``tau_s``, m the spacer's moisture
    (:func:`spacer_moisture` from ``seed``): it creeps faster while its moisture changes (mechanosorption). Exact
    exponential steps of ``step_s``, settled at the first force."""
    grid, fg = coarse_force(t, f, step_s)
    mg, moist = spacer_moisture(seed, grid[-1] - grid[0])
    change = np.abs(np.gradient(moist, mg))
    speed = 1.0 + boost * np.interp(grid - grid[0], mg, change) / max(float(np.mean(change[mg >= 0.0])), 1e-12)
    decay = np.exp(-step_s * speed / tau_s).tolist()
    u = compliance_v_per_n * float(fg[0])
    out = np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        out[i] = u
        goal = compliance_v_per_n * fi
        u = goal + (u - goal) * decay[i]
    return np.interp(t, grid, out)


def oil_column_kelvin(t, f, compliance_v_per_n, period_s, zeta, step_s=0.005):
    """The delayed share of a fluid-filled core whose expelled oil rises in a long line to a compliant bellows: the
    column's inertance against the bellows' compliance, C w^2 / (s^2 + 2 zeta w s + w^2) on the force (C =
    ``compliance_v_per_n``, 2 pi / w = ``period_s``, damping ratio ``zeta``): it settles at C F with an overshoot.
    Bilinear on a uniform grid of ``step_s``, settled at the first force."""
    grid, fg = coarse_force(t, f, step_s)
    w = 2.0 * math.pi / period_s
    b, a = signal.bilinear([compliance_v_per_n * w * w], [1.0, 2.0 * zeta * w, w * w], fs=1.0 / step_s)
    y = signal.lfilter(b, a, fg - fg[0]) + compliance_v_per_n * fg[0]
    return np.interp(t, grid, y)


# ----------------------------------------------------------------------------- hysteresis

class CracklingFluxGuide(SimOnly):
    """A magnetic read-out whose thin-film flux guide switches as a random-field Ising model at zero temperature
    (Sethna's crackling noise): ``side`` x ``side`` grains on a periodic square lattice, each coupled to its four
    neighbours (J = 1) and pinned by a random field, normal with a spread ``disorder`` (in J), all in the drive H =
    span (u / ``centre`` - 1), u = x / ``top`` (span 4 + 2.5 disorder: saturated at no load and at the top of the
    range, the loop centred at ``centre`` of it). A grain flips when its local field changes sign, and its flip may
    flip its neighbours (avalanches); return-point memory holds. The reading is x plus ``sign`` k top times the mean
    state less its mean curve (the firmware linearised that after two full-range cycles made before use), k set for a
    loop of ``width`` of the range at the loop's centre in such a cycle."""

    def __init__(self, top, width, disorder, centre, sign, seed, side=20):
        rng = np.random.default_rng(seed)
        n = side * side
        self.field = rng.normal(0.0, disorder, n)
        idx = np.arange(n).reshape(side, side)
        self.nb = np.stack([np.roll(idx, 1, 0), np.roll(idx, -1, 0), np.roll(idx, 1, 1), np.roll(idx, -1, 1)],
                           axis=-1).reshape(n, 4)
        self.nbl = self.nb.tolist()
        self.span, self.centre, self.top, self.sign = 4.0 + 2.5 * disorder, centre, top, sign
        cycle = np.concatenate([np.linspace(0.0, 1.0, 1001), np.linspace(1.0, 0.0, 1001)[1:]])
        _, start = self._run(np.concatenate([cycle, cycle]), -np.ones(n))
        m, _ = self._run(cycle, start)
        up, down = m[:1001], m[1000:][::-1]
        self.start, self.grid, self.mean = start, np.linspace(0.0, 1.0, 1001), 0.5 * (up + down)
        at = int(round(1000 * centre))
        self.k = width / max(abs(float(down[at] - up[at])), 1e-12)

    def _run(self, u, start):
        """The mean state per sample of the drive ``u`` from the grains' states ``start`` (+-1); returns it and the
        states at the end."""
        s = start.copy()
        local = self.field + s[self.nb].sum(axis=1)
        nbl, n = self.nbl, s.size
        total = float(s.sum())

        def bounds():
            down = s < 0.0
            lo = float(np.min(-local[down])) if down.any() else math.inf
            hi = float(np.max(-local[~down])) if (~down).any() else -math.inf
            return lo, hi

        lo, hi = bounds()
        out = np.empty(np.size(u))
        for i, h in enumerate((self.span * (np.asarray(u, dtype=float) / self.centre - 1.0)).tolist()):
            if h > lo:
                stack = np.flatnonzero((s < 0.0) & (local + h > 0.0)).tolist()
                while stack:
                    k = stack.pop()
                    if s[k] > 0.0 or local[k] + h <= 0.0:
                        continue
                    s[k] = 1.0
                    total += 2.0
                    for j in nbl[k]:
                        local[j] += 2.0
                        if s[j] < 0.0 and local[j] + h > 0.0:
                            stack.append(j)
                lo, hi = bounds()
            elif h < hi:
                stack = np.flatnonzero((s > 0.0) & (local + h < 0.0)).tolist()
                while stack:
                    k = stack.pop()
                    if s[k] < 0.0 or local[k] + h >= 0.0:
                        continue
                    s[k] = -1.0
                    total -= 2.0
                    for j in nbl[k]:
                        local[j] -= 2.0
                        if s[j] > 0.0 and local[j] + h < 0.0:
                            stack.append(j)
                lo, hi = bounds()
            out[i] = total / n
        return out, s

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        u = x / self.top
        m, _ = self._run(u, self.start)
        return x + self.sign * self.k * self.top * (m - np.interp(u, self.grid, self.mean))


class PinnedBridge(SimOnly):
    """A capacitive read-out whose gap holds a drop of dielectric liquid bridging its electrodes (``eps`` times air's
    permittivity). The core's deformation narrows the gap, g = 1 - ``close`` u (u = x / ``top``); the drop, its volume
    fixed, would wet a = ``wet`` / g of the electrodes if its contact line slid freely. The line stays pinned at r
    while the drop's bulge (a - r) / a lies between -``recede`` and ``advance`` (contact-angle hysteresis) and slides
    with that limit beyond them; the pinned drop still fills ``fill`` of a - r. The capacitance is (1 + (eps - 1)
    (r + fill (a - r))) / g; the reading is x plus ``sign`` k top times it less its mean curve (the firmware's
    linearisation over a full-range cycle made before use), k set for a loop of ``width`` of the range half-way up
    such a cycle. Rate-independent, from the drop at rest."""

    def __init__(self, top, width, close, wet, eps, advance, recede, fill, sign):
        self.top, self.close, self.wet, self.eps = top, close, wet, eps
        self.advance, self.recede, self.fill, self.sign = advance, recede, fill, sign
        cycle = np.concatenate([np.linspace(0.0, 1.0, 1001), np.linspace(1.0, 0.0, 1001)[1:]])
        c = self._cap(cycle)
        up, down = c[:1001], c[1000:][::-1]
        self.grid, self.mean = np.linspace(0.0, 1.0, 1001), 0.5 * (up + down)
        self.k = width / max(abs(float(down[500] - up[500])), 1e-12)

    def _cap(self, u):
        g = 1.0 - self.close * np.clip(u, -0.5, 1.5)
        a = self.wet / g
        r, adv, rec = float(a[0]), self.advance, self.recede
        pinned = np.empty(a.size)
        for i, ai in enumerate(a.tolist()):
            if ai - r > adv * ai:
                r = ai * (1.0 - adv)
            elif ai - r < -rec * ai:
                r = ai * (1.0 + rec)
            pinned[i] = r
        return (1.0 + (self.eps - 1.0) * (pinned + self.fill * (a - pinned))) / g

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        u = x / self.top
        return x + self.sign * self.k * self.top * (self._cap(u) - np.interp(u, self.grid, self.mean))


# ----------------------------------------------------------------------------- sensor lag

class FixedPointAverage(SimOnly):
    """Firmware that averages the ADC's codes (``lsb_v`` each) exponentially in integer arithmetic at ``fw_hz``:
    y += (x - y) >> ``shift`` (an arithmetic shift, toward minus infinity): a first-order lag of 2^shift samples that,
    approaching from below, stalls up to 2^shift - 1 codes short of its input (from above it arrives). The DAQ reads
    the latest output (held); settled at the first sample."""

    def __init__(self, shift, lsb_v, fw_hz):
        self.shift, self.lsb, self.h = shift, lsb_v, 1.0 / fw_hz

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        grid = np.arange(t[0], t[-1] + self.h, self.h)
        codes = np.floor(np.interp(grid, t, x) / self.lsb + 0.5).astype(np.int64).tolist()
        y, sh = codes[0], self.shift
        out = []
        for c in codes:
            y += (c - y) >> sh
            out.append(y)
        return held(t, grid, np.asarray(out, dtype=float) * self.lsb, x[0])


class SweptInterrogator(SimOnly):
    """A fibre-Bragg-grating read-out whose interrogator sweeps a tunable laser across its window once every
    ``period_s`` (the sweep taking ``duty`` of it, upward or downward in wavelength; the first sweep at ``phase`` of a
    period), finds the grating's reflection at the moment the sweep passes it and reports ``latency_s`` after the
    sweep; the DAQ reads the latest report (held). The grating's wavelength follows x, its place in the window from
    ``lo_v`` to ``hi_v``: the reading is x sampled at a moment that depends on x itself (early in the sweep at one end
    of the range, late at the other)."""

    def __init__(self, period_s, duty, latency_s, lo_v, hi_v, upward, phase):
        self.period, self.duty, self.latency = period_s, duty, latency_s
        self.lo, self.hi, self.upward, self.phase = lo_v, hi_v, upward, phase

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        starts = np.arange(t[0] - (1.0 - self.phase) * self.period, t[-1], self.period)
        where = np.full(starts.size, 0.5)
        for _ in range(4):
            seen = np.interp(starts + self.duty * self.period * where, t, x)
            pos = np.clip((seen - self.lo) / (self.hi - self.lo), 0.0, 1.0)
            where = pos if self.upward else 1.0 - pos
        return held(t, starts + self.period + self.latency, seen, x[0])


# ----------------------------------------------------------------------------- nonlinear gain

def lateral_offset_fibres(rel, reach, d0):
    """x read as the light two fibres stop coupling as the load moves their cores apart sideways: Gaussian modes
    offset by d mode radii couple exp(-d^2); d = d0 + k x from ``d0`` (below 0.71 the reading starts expansive and
    turns compressive past the inflection; beyond it, compressive); the light lost, scaled to slope 1 at no load;
    k set for a departure of ``rel`` at ``reach`` (d at most 2.2 there)."""
    e0 = math.exp(-d0 * d0)

    def read(x, k):
        d = d0 + k * np.asarray(x, dtype=float)
        return (e0 - np.exp(-d * d)) / (2.0 * d0 * e0 * k)
    return fit_departure(read, rel, reach, (2.2 - d0) / reach)


def conical_spring(rel, reach, taper, stiffen, segments=200):
    """x read through a conical compression spring whose coils bottom out one by one, the widest first: ``segments``
    pieces of wire whose radius falls linearly from 1 to ``taper``, each compliant as the cube of its radius and each
    closing the same pitch gap. With ``stiffen`` the gauge reads the spring's force as the core's deformation
    compresses it (linear, then ever stiffer as the coils bottom: expansive); otherwise it reads the spring's travel
    under the core's force (compressive). Scaled to slope 1 at no load (odd about it); the gap set for a departure of
    ``rel`` at ``reach``."""
    radii = np.linspace(1.0, taper, segments)
    comp = radii ** 3 / np.sum(radii ** 3)
    forces = np.concatenate([[0.0], np.sort(1.0 / comp)])
    travels = np.minimum(np.outer(forces, comp), 1.0).sum(axis=1)

    if stiffen:
        def read(x, k):
            x = np.asarray(x, dtype=float)
            return np.sign(x) * np.interp(k * np.abs(x), travels, forces) / k
        return fit_departure(read, rel, reach, 0.8 * segments / reach)

    def read_travel(x, k):
        x = np.asarray(x, dtype=float)
        return np.sign(x) * np.interp(k * np.abs(x), forces, travels) / k
    return fit_departure(read_travel, rel, reach, float(forces[-1]) / reach)


# ----------------------------------------------------------------------------- thermal drift

def activity_dip_zero(t, temp, k_v_per_c, cross_c, coupling_c, anomaly_c, lag_s):
    """The zero of a quartz double-ended tuning fork whose working mode couples to a spurious mode with another
    temperature coefficient (the activity dip): where their frequencies cross, ``cross_c`` from the reference, the
    working mode is pushed away from the spurious one, by g^2 / dT far from it and by g (``coupling_c``) at it, where
    it jumps to the other side: p = (dT - sign(dT) sqrt(dT^2 + 4 g^2)) / 2, dT = T - T_x. The zero follows T plus
    ``anomaly_c`` / g times p (in degC of the plain slope), scaled to ``k_v_per_c`` at the reference, on the quartz's
    temperature (lag ``lag_s``)."""
    tx, g = T_REF_C + cross_c, coupling_c

    def pull(temp_c):
        d = np.asarray(temp_c, dtype=float) - tx
        return 0.5 * (d - np.sign(d) * np.sqrt(d * d + 4.0 * g * g))

    d_ref = T_REF_C - tx
    slope = 1.0 + anomaly_c / g * 0.5 * (1.0 - abs(d_ref) / math.sqrt(d_ref * d_ref + 4.0 * g * g))
    quartz = follow(t, temp, lag_s)
    return k_v_per_c / slope * (quartz - T_REF_C + anomaly_c / g * (pull(quartz) - pull(T_REF_C)))


def trap_ensemble_zero(t, temp, k_v_per_c, spread_c, width_c, speed_per_c, lag_s, seed, traps=24, step_s=0.5):
    """The zero of an amplifier whose input transistor's ``traps`` oxide traps (from ``seed``) each relax toward a
    Fermi occupancy of its temperature (lag ``lag_s``), 1 / (1 + exp((T - T_i) / w_i)), T_i normal about the
    reference with ``spread_c``, w_i 0.7-1.3 times ``width_c``, at an Arrhenius rate (3-300 s at the reference,
    log-uniform, ``speed_per_c`` e-folds faster per degC warmer); each holds a charge of 0.2-1 (the same sign). The
    zero is their charge, scaled so that the settled slope at the reference is ``k_v_per_c``; exact exponential steps
    of ``step_s``, settled at the first sample."""
    rng = np.random.default_rng(seed)
    centre = T_REF_C + rng.normal(0.0, spread_c, traps)
    width = width_c * rng.uniform(0.7, 1.3, traps)
    tau = np.exp(rng.uniform(math.log(3.0), math.log(300.0), traps))
    charge = rng.uniform(0.2, 1.0, traps)

    def fermi(temp_c):
        return 1.0 / (1.0 + np.exp(np.clip((temp_c - centre) / width, -60.0, 60.0)))

    settled = fermi(T_REF_C)
    slope = float(np.sum(charge * settled * (1.0 - settled) / width))  # minus the settled slope
    grid = np.arange(t[0], t[-1] + step_s, step_s)
    body = np.interp(grid, t, follow(t, temp, lag_s))
    occ = fermi(body[0])
    zero = np.empty(grid.size)
    for i, b in enumerate(body.tolist()):
        zero[i] = float(np.sum(charge * (occ - settled)))
        goal = fermi(b)
        occ = goal + (occ - goal) * np.exp(-step_s / tau * math.exp(speed_per_c * (b - T_REF_C)))
    return np.interp(t, grid, -k_v_per_c / max(slope, 1e-12) * zero)


# ----------------------------------------------------------------------------- thermal sensitivity

class ModeHopSpan(SimOnly):
    """An optical read-out whose laser diode's wavelength (lag ``lag_s``) drifts with its temperature across a
    wavelength-selective coupler, ``tc`` of span per degC of drift, and mode-hops back by ``back`` of the drift between
    hops, which come every ``hop_c`` degC (offset by ``offset`` of that from the reference) with a hysteresis of ``band`` of a hop
    (a hop up happens that far past the mid-point when warming, a hop down that far before it when cooling): the
    span 1 + tc (dT - back hop n), n the hops made since the reference. Exact per step of ``step_s``."""

    def __init__(self, tc, hop_c, back, band, offset, lag_s, step_s=0.5):
        self.tc, self.hop, self.back, self.band, self.offset, self.lag, self.step = (tc, hop_c, back, band, offset,
                                                                                     lag_s, step_s)

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        grid = np.arange(t[0], t[-1] + self.step, self.step)
        dt = np.interp(grid, t, follow(t, temp_of(aux, t.size), self.lag)) - T_REF_C
        hop, off, half = self.hop, self.offset, 0.5 * self.band
        n = int(round(dt[0] / hop - off))
        hops = np.empty(grid.size)
        for i, d in enumerate((dt / hop - off).tolist()):
            while d > n + 0.5 + half:
                n += 1
            while d < n - 0.5 - half:
                n -= 1
            hops[i] = n
        gain = 1.0 + self.tc * (dt - self.back * hop * hops)
        return np.asarray(x, dtype=float) * np.interp(t, grid, gain)


class NematicSpacerSpan(SimOnly):
    """A read-out lever whose arm is a liquid-crystal elastomer strip (lag ``lag_s``) that contracts with its nematic
    order: after Landau and de Gennes the order is S / S_NI = 3/4 (1 + sqrt(1 - 8/9 (T - T*) / (T_NI - T*))) in the
    nematic phase and 0 in the isotropic one, T_NI - T* = ``supercool_c``; on warming the strip stays nematic up to
    the superheating limit (T* + 9/8 (T_NI - T*)), on cooling isotropic down to T*. The span is 1 + ``share`` (S /
    S_ref - 1), the transition T_NI placed above the reference where the order's slope gives ``tc`` per degC of span
    there (at most 40 degC above it); the strip starts nematic. Exact per step of ``step_s``."""

    def __init__(self, tc, supercool_c, share, lag_s, step_s=0.5):
        self.d, self.share, self.lag, self.step = supercool_c, share, lag_s, step_s

        def rel_slope(gap):  # d(S/S_ref)/dT at the reference, the reference ``gap`` below T_NI
            root = math.sqrt(1.0 / 9.0 + 8.0 / 9.0 * gap / supercool_c)
            return -(4.0 / 9.0) / (supercool_c * root * (1.0 + root))

        want = abs(tc) / share
        if want >= abs(rel_slope(40.0)):
            gap = optimize.brentq(lambda g: abs(rel_slope(g)) - want, 1e-3, 40.0)
        else:
            gap = 40.0
        self.t_ni = T_REF_C + gap
        self.t_star = self.t_ni - supercool_c
        self.s_ref = self._order(np.array([T_REF_C]))[0]
        self.sign = 1.0 if tc * rel_slope(gap) > 0 else -1.0  # the strip lengthens or shortens with the order

    def _order(self, temp_c):
        arg = np.clip(1.0 - 8.0 / 9.0 * (temp_c - self.t_star) / self.d, 0.0, None)
        return 0.75 * (1.0 + np.sqrt(arg))

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        grid = np.arange(t[0], t[-1] + self.step, self.step)
        temp = np.interp(grid, t, follow(t, temp_of(aux, t.size), self.lag))
        hot_limit, cold_limit = self.t_star + 9.0 / 8.0 * self.d, self.t_star
        nematic = np.empty(grid.size, dtype=bool)
        state_n = True
        for i, c in enumerate(temp.tolist()):
            if state_n and c > hot_limit:
                state_n = False
            elif not state_n and c < cold_limit:
                state_n = True
            nematic[i] = state_n
        order = np.where(nematic, self._order(temp), 0.0)
        gain = 1.0 + self.sign * self.share * (order / self.s_ref - 1.0)
        return np.asarray(x, dtype=float) * np.interp(t, grid, gain)


# ----------------------------------------------------------------------------- offset drift

def gel_etalon(rng, horizon_s=HORIZON_S):
    """The zero of an optical read-out whose connector's ferrule gap holds an index-matching gel that the connector's
    spring squeezes out: the gap thins as (1 + (t + ago) / tau)^-0.5 (Stefan's squeeze film; ago 0-300 s, tau 20-300
    s), and the parasitic etalon it forms sweeps 0.7-4 fringes over the horizon, from a random phase, ever more slowly
    (as a function of the seconds since the first sample, zero there)."""
    ago, tau = rng.uniform(0.0, 300.0), rng.uniform(20.0, 300.0)
    fringes, phase = rng.uniform(0.7, 4.0), rng.uniform(0.0, 2.0 * math.pi)
    h0, h_end = (1.0 + ago / tau) ** -0.5, (1.0 + (ago + horizon_s) / tau) ** -0.5

    def zero(s):
        h = (1.0 + (np.asarray(s, dtype=float) + ago) / tau) ** -0.5
        return np.cos(phase + 2.0 * math.pi * fringes * (h0 - h) / (h0 - h_end)) - math.cos(phase)
    return zero


def hunting_damper(rng, horizon_s=HORIZON_S, step_s=0.1):
    """The zero of a sealed-gauge read-out in an isolation room whose exhaust damper hunts: the room's pressure follows
    a van der Pol limit cycle (mu 0.5-4, a small-swing period of 25-90 s) from a random state 600 s before the first
    sample; 1-4 door openings (from 300 s before it) kick the pressure by 0.5-1.5 of the cycle's half-height either
    way (as a function of the seconds since the first sample, zero there). Fourth-order Runge-Kutta on a grid of
    ``step_s``."""
    mu, w = rng.uniform(0.5, 4.0), 2.0 * math.pi / rng.uniform(25.0, 90.0)
    grid = np.arange(-600.0, horizon_s + 2.0 * step_s, step_s)
    kicks = {int((at + 600.0) / step_s): rng.uniform(0.5, 1.5) * rng.choice([-1.0, 1.0])
             for at in rng.uniform(-300.0, horizon_s, int(rng.integers(1, 5)))}
    y, v = rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)
    h = step_s * w

    def acc(y_, v_):
        return mu * (1.0 - y_ * y_) * v_ - y_

    out = np.empty(grid.size)
    for i in range(grid.size):
        out[i] = y
        y += kicks.get(i, 0.0)
        k1y, k1v = v, acc(y, v)
        k2y, k2v = v + 0.5 * h * k1v, acc(y + 0.5 * h * k1y, v + 0.5 * h * k1v)
        k3y, k3v = v + 0.5 * h * k2v, acc(y + 0.5 * h * k2y, v + 0.5 * h * k2v)
        k4y, k4v = v + h * k3v, acc(y + h * k3y, v + h * k3v)
        y += h * (k1y + 2.0 * k2y + 2.0 * k3y + k4y) / 6.0
        v += h * (k1v + 2.0 * k2v + 2.0 * k3v + k4v) / 6.0
    first = float(np.interp(0.0, grid, out))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, out) - first


# ----------------------------------------------------------------------------- resonance

class CantileverModes(GridMode):
    """A needle holder built as a cantilever: three bending modes at f1 (``f1_hz``), 6.27 f1 and 17.55 f1, carrying
    1 - w2 - w3, ``w2`` and ``w3`` of the static response (unit gain at rest), with Rayleigh damping (the first mode's
    ratio ``zeta``, ``stiff_share`` of it stiffness-proportional: the higher modes are damped more). Bilinear on a
    uniform grid of ``fs`` Hz, from rest."""

    fs = 5000.0

    def __init__(self, f1_hz, zeta, stiff_share, w2, w3):
        w1 = 2.0 * math.pi * f1_hz
        alpha, beta = 2.0 * (1.0 - stiff_share) * zeta * w1, 2.0 * stiff_share * zeta / w1
        self.modes = []
        for ratio, weight in ((1.0, 1.0 - w2 - w3), (6.267, w2), (17.547, w3)):
            w = w1 * ratio
            z = min(alpha / (2.0 * w) + beta * w / 2.0, 0.9)
            self.modes.append((weight, signal.bilinear([w * w], [1.0, 2.0 * z * w, w * w], fs=self.fs)))

    def on_grid(self, t, tu, xu, h):
        y = sum(weight * signal.lfilter(b, a, xu) for weight, (b, a) in self.modes)
        return y


class SelfHeatingDamperMode(GridMode):
    """A needle holder's mode at ``f0_hz`` (unit gain at rest) whose oil damper heats with the power it dissipates and
    cools with ``cool_s``: its damping ratio ``zeta`` when cold falls as exp(-theta), theta the damper's heat in units
    such that the record's largest heat on a damper that did not thin would be -ln(1 - ``drop``): after the largest
    knocks the damping has fallen by about ``drop`` and recovers as the damper cools. The frequency fixed;
    semi-implicit Euler on a uniform grid of ``fs`` Hz, from rest."""

    fs = 3000.0

    def __init__(self, f0_hz, zeta, drop, cool_s):
        self.w, self.zeta, self.drop, self.cool = 2.0 * math.pi * f0_hz, zeta, drop, cool_s

    def on_grid(self, t, tu, xu, h):
        w, c0 = self.w, 2.0 * self.zeta * self.w
        b, a = signal.bilinear([w * w], [1.0, c0, w * w], fs=self.fs)
        cold = signal.lfilter(b, a, xu)
        speed = np.gradient(cold, h)
        keep = math.exp(-h / self.cool)
        heat, _ = signal.lfilter([h], [1.0, -keep], c0 * speed * speed, zi=[0.0])
        scale = -math.log(1.0 - self.drop) / max(float(heat.max()), 1e-30)
        y = v = theta = 0.0
        w2, gain, loss = w * w, scale * h, keep
        out = np.empty(tu.size)
        for i, xi in enumerate(xu.tolist()):
            c = c0 * math.exp(-theta)
            v += (w2 * (xi - y) - c * v) * h
            y += v * h
            theta = theta * loss + gain * c * v * v
            out[i] = y
        return out


# ----------------------------------------------------------------------------- friction

class ForceMap(SimOnly):
    """A map of the force history before the core: ``fn(t, F)``."""

    def __init__(self, fn):
        self.fn = fn

    def forward(self, t_s, x, aux=None, state=None):
        return self.fn(np.asarray(t_s, dtype=float), np.asarray(x, dtype=float))


def tribo_band(t, f, band_n, low, high, travel_n, leak_s):
    """The force passed by a needle guide that its sliding charges triboelectrically: the band (the same at every load)
    is ``band_n`` times low + (high - low) (1 - exp(-q)), q the charge, which grows by the force slid (the passed
    force's travel while the needle slides) over ``travel_n`` and leaks away with ``leak_s``; electroadhesion makes a
    charged guide hold more. From no charge, started at ``f[0]``."""
    dt = np.diff(t, prepend=t[0]).tolist()
    p, q = float(f[0]), 0.0
    out = np.empty_like(f)
    for i, fi in enumerate(f.tolist()):
        q *= math.exp(-dt[i] / leak_s)
        b = band_n * (low + (high - low) * (1.0 - math.exp(-q)))
        new = min(max(p, fi - b), fi + b)
        q += abs(new - p) / travel_n
        p = new
        out[i] = p
    return out


def holding_brake(t, f, band_n, sliding, still_s, release_s, moving_n_per_s):
    """The force passed by a needle feed with a spring-applied holding brake: the controller applies it once the force
    has been still (its rate over 50 ms below ``moving_n_per_s``) for ``still_s`` and releases it ``release_s`` after
    the force starts to change; applied, the feed holds a band of ``band_n`` (the same at every load), released only
    ``sliding`` of it (the guide's own friction). Started at ``f[0]``, the brake released."""
    rate = 1.0 / max(float(np.median(np.diff(t))), 1e-6)
    n = max(1, int(round(0.05 * rate)))
    speed = np.abs(np.convolve(np.gradient(f, t), np.ones(n) / n, mode="same")).tolist()
    tl = t.tolist()
    applied, since_still, since_move = False, None, None
    p = float(f[0])
    out = np.empty_like(f)
    for i, fi in enumerate(f.tolist()):
        if speed[i] < moving_n_per_s:
            since_move = None
            since_still = tl[i] if since_still is None else since_still
            if not applied and tl[i] - since_still >= still_s:
                applied = True
        else:
            since_still = None
            since_move = tl[i] if since_move is None else since_move
            if applied and tl[i] - since_move >= release_s:
                applied = False
        b = band_n if applied else band_n * sliding
        p = min(max(p, fi - b), fi + b)
        out[i] = p
    return out


# ----------------------------------------------------------------------------- thermo-rheological

def creeping(c):
    """The core made soft enough for its clock to show: its Kelvin spring at most 18 N/V (the retardation time kept)
    and its flow's viscosity at most 3.5e4 N s/V."""
    k2 = min(c.k2_n_per_v, 18.0)
    return Burgers(c.k1_n_per_v, k2, min(c.eta1_n_s_per_v, 3.5e4), c.eta2_n_s_per_v * k2 / c.k2_n_per_v)


class ShovingClock(SimOnly):
    """A core whose clock follows Dyre's shoving model: log tau = A G(T) / T, the instantaneous shear modulus G
    softening by ``soften_per_c`` of its value per degC (linearly about the reference), A set for ``b_per_c`` per degC
    of the clock at the reference; on the core's temperature (lag ``lag_s``), held within e^+-6."""

    def __init__(self, c, b_per_c, soften_per_c, lag_s):
        self.c, self.g, self.lag = c, soften_per_c, lag_s
        ref = T_REF_C + 273.15
        self.a = b_per_c / (soften_per_c / ref + 1.0 / ref ** 2)
        self.ref_term = 1.0 / ref

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag)
        modulus = np.maximum(1.0 - self.g * (body - T_REF_C), 0.05)
        log_rate = self.a * (self.ref_term - modulus / (body + 273.15))
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(log_rate, -6.0, 6.0)))


class CouplingClock(SimOnly):
    """A core whose clock follows the power law of mode-coupling theory, tau ~ (T - T_c)^-gamma (``gamma``), T_c set
    below the reference for ``b_per_c`` per degC of the clock there (gamma / b below it); on the core's temperature
    (lag ``lag_s``), never closer to T_c than a tenth of that, held within e^+-6."""

    def __init__(self, c, b_per_c, gamma, lag_s):
        self.c, self.gamma, self.lag = c, gamma, lag_s
        self.above = gamma / b_per_c

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        body = follow(t, temp_of(aux, t.size), self.lag)
        rel = np.maximum((body - T_REF_C + self.above) / self.above, 0.1)
        log_rate = self.gamma * np.log(rel)
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(log_rate, -6.0, 6.0)))


# ----------------------------------------------------------------------------- outside the catalogue

class FringeSlips(SimOnly):
    """A two-scale interferometric read-out: a homodyne interferometer (a fringe every ``fringe_v`` of the core's
    deformation) whose phasemeter updates at ``meter_hz`` with a phase noise of ``noise`` of a fringe (from ``seed``)
    and unwraps the phase between its updates, so that whenever the reading moves more than half a fringe between two
    of them it loses or gains a whole fringe; a coarse channel re-resolves the fringe order every ``resync_s`` (from a
    random phase), which clears what was lost since. The fine phase is read at every sample."""

    def __init__(self, fringe_v, meter_hz, noise, resync_s, seed):
        self.fringe, self.h, self.noise, self.resync, self.seed = fringe_v, 1.0 / meter_hz, noise, resync_s, seed

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        rng = np.random.default_rng(self.seed)
        grid = np.arange(t[0], t[-1] + self.h, self.h)
        seen = np.interp(grid, t, x) / self.fringe + rng.normal(0.0, self.noise, grid.size)
        lost = np.concatenate([[0.0], np.cumsum(np.round(np.diff(seen)))])  # fringes lost by each update
        marks = np.arange(t[0] - rng.uniform(0.0, self.resync), t[-1] + self.resync, self.resync)
        last = marks[np.searchsorted(marks, grid, side="right") - 1]  # the last re-resolution before each update
        cleared = lost[np.searchsorted(grid, last, side="left") - 1 + (last < grid[0])]
        return x - self.fringe * held(t, grid, lost - cleared, 0.0)


class MuLawLogger(SimOnly):
    """A data logger that stores the reading as ``bits``-bit mu-law codes (``mu``) over +-``full_v`` (clipped beyond)
    and expands them again on playback."""

    def __init__(self, bits, mu, full_v):
        self.levels, self.mu, self.full = 2 ** (bits - 1) - 1, mu, full_v

    def forward(self, t_s, x, aux=None, state=None):
        u = np.clip(np.asarray(x, dtype=float) / self.full, -1.0, 1.0)
        code = np.round(np.sign(u) * np.log1p(self.mu * np.abs(u)) / math.log1p(self.mu) * self.levels)
        v = code / self.levels
        return np.sign(v) * np.expm1(np.abs(v) * math.log1p(self.mu)) / self.mu * self.full


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([4.0e4, 4.5e3]))))  # V / (N s)
        if shape == "shear_banding_leak":
            up = rng.uniform(1.5, 5.0)
            rule = banding_leak(phi * rng.uniform(0.3, 0.7), phi * rng.uniform(3.0, 9.0), up, up * rng.uniform(0.4, 0.8),
                                rng.uniform(0.3, 5.0))
        else:
            rule = coarsening_leak(phi * rng.uniform(1.5, 4.5), rng.uniform(0.0, 600.0), rng.uniform(30.0, 300.0),
                                   rng.uniform(0.3, 0.8))
        return Parts("zener", LeakingCore.of(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        comp = float(np.interp(m, [0, 1], [0.02, 0.24])) / g0  # of the instantaneous response, V / N
        if shape == "mechanosorptive_spacer":
            a = (comp, rng.uniform(1.0, 20.0), rng.uniform(2.0, 8.0), int(rng.integers(1 << 30)))
            p.extra.append(lambda t, f, T, a=a: mechanosorptive_kelvin(t, f, *a))
            return p
        a = (comp, rng.uniform(1.5, 12.0), rng.uniform(0.2, 0.65))
        p.extra.append(lambda t, f, T, a=a: oil_column_kelvin(t, f, *a))
        return p
    if effect == "hysteresis":
        width = float(np.interp(m, [0, 1], [0.01, 0.07]))
        sign = float(rng.choice([-1.0, 1.0]))
        if shape == "crackling_flux_guide":
            p.after.append(CracklingFluxGuide(top, width, rng.uniform(0.9, 2.2), rng.uniform(0.25, 0.5), sign,
                                              int(rng.integers(1 << 30))))
            return p
        close = rng.uniform(0.15, 0.45)
        p.after.append(PinnedBridge(top, width, close, rng.uniform(0.2, 0.8 * (1.0 - close)), rng.uniform(2.0, 30.0),
                                    rng.uniform(0.03, 0.1), rng.uniform(0.06, 0.25), rng.uniform(0.2, 0.6), sign))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.008, 0.12]))))
        if shape == "fixed_point_average":
            fw = float(rng.choice([1000.0, 2000.0]))
            shift = int(np.clip(round(math.log2(delay * fw)), 2, 9))
            p.after.append(FixedPointAverage(shift, min(top * rng.uniform(0.002, 0.012) / 2 ** shift, 1.5e-3), fw))
            return p
        duty, late = rng.uniform(0.5, 0.9), rng.uniform(0.05, 0.3)
        period = delay / (1.5 - 0.4 * duty + late)
        p.after.append(SweptInterrogator(period, duty, late * period, -top * rng.uniform(0.05, 0.2),
                                         top * rng.uniform(1.1, 1.3), bool(rng.random() < 0.5), rng.uniform(0.0, 1.0)))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.045, 0.2]))
        if shape == "lateral_offset_fibres":
            p.after.append(StaticMap(lateral_offset_fibres(rel, top, rng.uniform(0.25, 1.2))))
            return p
        p.after.append(StaticMap(conical_spring(rel, top, rng.uniform(0.3, 0.7), bool(rng.random() < 0.5))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.034]) * rng.choice([-1, 1]))
        if shape == "quartz_activity_dip":
            a = (k, rng.uniform(1.5, 6.0) * rng.choice([-1.0, 1.0]), rng.uniform(0.2, 1.0), rng.uniform(0.5, 3.0),
                 rng.uniform(5.0, 35.0))
            p.extra.append(lambda t, f, T, a=a: activity_dip_zero(t, T, *a))
            return p
        a = (k, rng.uniform(6.0, 20.0), rng.uniform(1.5, 4.0), rng.uniform(0.04, 0.1), rng.uniform(5.0, 35.0),
             int(rng.integers(1 << 30)))
        p.extra.append(lambda t, f, T, a=a: trap_ensemble_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        tc = float(np.interp(m, [0, 1], [0.014, 0.036])) * float(rng.choice([-1.0, 1.0]))
        if shape == "mode_hopping_laser":
            p.after.append(ModeHopSpan(tc, rng.uniform(1.2, 4.0), rng.uniform(0.5, 0.9), rng.uniform(0.1, 0.35),
                                       rng.uniform(-0.5, 0.5), rng.uniform(5.0, 30.0)))
            return p
        p.after.append(NematicSpacerSpan(tc, rng.uniform(1.5, 3.0), rng.uniform(0.7, 1.1), rng.uniform(5.0, 30.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.1]) * rng.choice([-1, 1]))
        zero = sized(gel_etalon(rng) if shape == "gel_etalon" else hunting_damper(rng), size)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.03, 0.0042])) * rng.uniform(0.8, 1.2)
        if shape == "cantilever_modes":
            p.after.append(CantileverModes(rng.uniform(11.0, 52.0), zeta, rng.uniform(0.2, 0.8), rng.uniform(0.02, 0.15),
                                           rng.uniform(0.005, 0.05)))
            return p
        p.after.append(SelfHeatingDamperMode(rng.uniform(11.0, 52.0), zeta, rng.uniform(0.3, 0.7), rng.uniform(1.0, 10.0)))
        return p
    if effect == "friction":
        band = float(np.interp(m, [0, 1], [0.0025, 0.044]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "tribocharged_guide":
            a = (band, rng.uniform(0.35, 0.6), rng.uniform(1.1, 1.4), rng.uniform(2.0, 15.0), rng.uniform(15.0, 120.0))
            p.before.append(ForceMap(lambda t, x, a=a: tribo_band(t, x, *a)))
            return p
        a = (band, rng.uniform(0.15, 0.4), rng.uniform(0.3, 1.5), rng.uniform(0.02, 0.08), rng.uniform(0.2, 0.6))
        p.before.append(ForceMap(lambda t, x, a=a: holding_brake(t, x, *a)))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.16, 0.56])) * rng.uniform(1.2, 1.5)
        c = creeping(c)
        if shape == "shoving_clock":
            return Parts("burgers", ShovingClock(c, b, rng.uniform(0.005, 0.02), rng.uniform(5.0, 25.0)),
                         core_changed=True)
        return Parts("burgers", CouplingClock(c, b, rng.uniform(1.6, 3.2), rng.uniform(5.0, 25.0)), core_changed=True)
    if effect == "fringe_slips":
        p.after.append(FringeSlips(top * float(np.interp(m, [0, 1], [0.08, 0.03])), rng.uniform(800.0, 2500.0),
                                   rng.uniform(0.02, 0.06), rng.uniform(0.2, 1.2), int(rng.integers(1 << 30))))
        return p
    if effect == "mu_law_logging":
        bits = int(round(float(np.interp(m, [0, 1], [9.4, 6.0]))))
        p.outer.append(MuLawLogger(bits, rng.uniform(100.0, 255.0), top * rng.uniform(1.5, 2.0)))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["shear_banding_leak", "coarsening_grains"],
    "delayed_elasticity": ["mechanosorptive_spacer", "oil_column_kelvin"],
    "hysteresis": ["crackling_flux_guide", "pinned_liquid_bridge"],
    "sensor_lag": ["fixed_point_average", "swept_interrogator"],
    "nonlinear_gain": ["lateral_offset_fibres", "conical_spring"],
    "thermal_drift": ["quartz_activity_dip", "oxide_trap_ensemble"],
    "thermal_sensitivity": ["mode_hopping_laser", "nematic_spacer"],
    "offset_drift": ["gel_etalon", "hunting_damper"],
    "resonance": ["cantilever_modes", "self_heating_damper"],
    "friction": ["tribocharged_guide", "holding_brake"],
    "thermo_rheological": ["shoving_clock", "mode_coupling_clock"],
}
PAIRS = (("viscous_flow", "thermal_sensitivity"), ("delayed_elasticity", "offset_drift"), ("hysteresis", "sensor_lag"),
         ("nonlinear_gain", "thermal_drift"), ("resonance", "friction"), ("thermo_rheological", "nonlinear_gain"))
OUTSIDE = ("fringe_slips", "mu_law_logging")
RATES = (125.0, 305.0, 495.0, 805.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split AB", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.27, 0.87),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=server_aisles,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(0.8e-3, 2.6e-3), jitter=0.34,
                   gap_s=(0.1, 2.8))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
