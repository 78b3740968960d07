"""Independent split O for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split O is an untouched held-out set: written before the engine it measures and blind to it (to how it detects and
fits anything), run once at its end, never used to choose anything. Every name of the catalogue is hidden in two
shapes that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A to N use:

* recovery creep (Bailey-Orowan: the flow runs at a rate proportional to the force less an internal back stress that
  the flow itself builds up and that recovers with time, so each load flows fast at first, then at a steady rate, and
  flows fast again after a rest), or a press-fit pin creeping out of its printed bore past the layer lines (a flow
  above a yield force that ripples with the distance flowed, one period per layer: the flow advances in bursts through
  the weak lines and stalls at the strong ones, never recovering);
* a Kelvin unit in a polymer that ages physically from the start of the record (Struik's effective time: its clock
  slows as (1 + t / t_a)^-mu, mu 0.7-0.95, t_a 30-150 s), or a Kelvin unit behind a pre-tensioned membrane (it creeps
  and recovers only on the share of the force above a preload of 1.5-3.5 N);
* a bistable (curved) printed flexure beside the core, engaged over a band of force about 1.5-3.5 N (it resists, snaps
  through and then pulls ahead: under force control the core's share jumps at two forces 0.4-0.7 N apart, one on
  loading and one on unloading), or the smooth elastic-plastic transitions of the printed layers on the bridge voltage
  (Menegotto-Pinto branches from each reversal toward the intersection of the elastic line and a hardening asymptote
  of 0.85-0.95 times its slope, the curvature falling with the previous excursion (Bauschinger), with return-point
  memory);
* an input stage with a diode across its series resistor (an envelope detector: the hold capacitor charges 3-8 times
  faster than it discharges, 5-21 ms on the rise), or a USB DAQ that delivers the bridge in packets of 18-50 ms and
  stamps them at arrival (a latency of 2-8 ms plus a sawtooth delay that falls across each packet);
* the cosine error of a self-aligning seat whose tilt changes with the load (x cos(theta0 + kappa x) / cos(theta0),
  theta0 -11 to 26 degrees, a departure of 6-10 % at the top of the range: compressive, or expansive at first while
  the seat straightens), or a microcontroller's bipolar successive-approximation ADC (over +-1.6 times the range, the
  zero just above its mid-scale carry) whose top seven bit weights are mismatched (a staircase of errors at the major
  carries, 0.6-0.9 % of its span at most over the sensor's range);
* a zero from the thermal stress in the bond, which relaxes at an Arrhenius rate (warm: fast, 60-400 s at the
  reference) on top of a reversible zero, or a zero trimmed by a DAC that a microcontroller updates from a thermometer
  polled every 30-120 s with a coefficient 40-80 % of the true one (the residual follows the temperature since the
  last update);
* a span compensated by an NTC thermistor in the excitation's divider, under- or over-compensating (the polymer's span
  rising linearly as it softens, 0.2-4.5 %/degC, against the thermistor's exponential in 1/T, which lowers the
  excitation as it warms, leaving 0.9-1.7 %/degC either way and a curvature, on the sensor's lagged temperature), or a
  span of the instantaneous (glassy, energy-elastic) compliance only, which grows exponentially (1.5-2.6 %/degC) as
  the body warms while the creep's compliances keep theirs;
* an amplifier's burst (popcorn) noise: the zero switches between two levels at random (a random telegraph signal,
  dwells of 10-80 s), or a DAQ that reverses the bridge excitation every 40-120 s against thermal EMFs and leaves a
  dielectric after-effect (a kick of alternating sign after each reversal, decaying as a Curie-von Schweidler power
  law);
* a mode (18-45 Hz) of the needle holder moving in the fluid of the organ bath (Bagley-Torvik: the Basset history
  force of its Stokes layer, a damping of order 3/2 that also adds mass, 60-90 % of a damping ratio of 0.02-0.055), or
  a mode damped by a check-valve damper (a light damping both ways, about as much again only while it moves one way);
* a seal energised by the pressure of a fluid chamber behind it (a Coulomb band that grows with the force seen through
  the chamber's vent, a lag of 0.3-3 s: wider on unloading than on loading at the same force), or a slender needle
  that bows under its axial load and presses on its guide (a band growing as F / (1 - F / F_cr), F_cr 12-20 N); both
  bands 1.2-2.5 % of the range at 4 N;
* a co-continuous blend of two phases sharing the load in parallel, each on its own Arrhenius clock (the fast phase
  exp(0.17-0.26 dT), the slow one 0-25 % of that: the fast phase relaxes and hands its load to the slow one), or an
  Arrhenius clock (0.15-0.22 per degC) on a core that leads the thermometer (the thermometer, in the housing, lags the
  core by 8-20 s: the core's temperature is the reading plus 8-20 s times its rate).

It also holds six pairs, two effects outside the catalogue (a DAQ whose voltage stream loses 9-55 ms of samples at
each buffer overrun, every 20-90 s on average, while its stamps keep counting, so the voltage runs ahead of the force
by what has been lost so far; an intermittent joint on one of the amplifier's two parallel gain resistors, which
switches the whole output's gain by 3-5.5 % at random) and four clean records. Profiles: a spinning needle driven
through the measured force-depth curve (``../shared/data``, ``depth_force.csv``, its first insertion split into its
friction, the lower envelope that grows with depth, and its stiffness and cutting peaks; the needle advances on a
minimum-jerk trajectory at 1-5 mm/s on average, and one insertion in two it spins at 4-16 mm/s at its surface, which
tilts the shaft's friction away from the axis, v / sqrt(v^2 + (omega r)^2), and cuts 10-30 % more easily; a train of
synthetic punctures when the data are absent); a rolling indenter scanning a tissue phantom for stiff nodules
(back-and-forth passes at a set depth over a track whose stiffness varies, 1-3 Gaussian nodules, the operator's hand
wobbling); and contacts made through a teleoperator with a communication delay (the tool bounces 2-6 times with a
restitution of 0.4-0.75 before it settles into a hold whose force wanders). Rates 260, 370, 590 and 830 Hz (a mode at
1000 Hz with knocks that excite it), 1-2.6 mV noise, stamp jitter, gaps, and a sensor carried by the robot between a
warmed organ bath (the air over it warming as the bath's heater comes up to temperature, with a flickering plume) and
its parking place in the room.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_o.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import math

import numpy as np
from scipy import integrate, optimize, signal

from independent_split import puncture_train
from polyforce_ros.physics.viscoelastic import simulate_deformation
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (band_play, coarse, ForcePath, kelvin, Parts, quintic, ShapeSplit, SimOnly, uniform_grid,
                       ZenerWithFlow)

SEED0 = 1_030_000  # never a seed of the registry's splits nor of splits A (90000..) to N (960000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 450.0


# ----------------------------------------------------------------------------- profiles and temperature

def quintic_rate(u):
    """d quintic / du."""
    u = np.clip(u, 0.0, 1.0)
    return 30.0 * (u * (1.0 - u)) ** 2


def measured_insertion(bin_mm=0.1):
    """The first insertion of the measured force-depth curve (``depth_force.csv``, which holds several digitised
    curves: the first ends at the first jump back in depth), binned on a grid of ``bin_mm`` (the mean force per bin,
    empty bins interpolated), and split into its friction (the lower envelope from the deepest point back: what the
    shaft drags, growing with depth) and the rest (the stiffness build-ups and the cutting peaks). (depth [mm],
    friction [N], rest [N]), or None when the data are absent."""
    csv = profiles.okamura_csv_path()
    if csv is None or not (csv.parent / "depth_force.csv").is_file():
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
    mean = np.interp(grid, grid[filled], total[filled] / count[filled])
    mean = np.maximum(mean, 0.0)
    friction = np.minimum.accumulate(mean[::-1])[::-1]
    return grid, friction, mean - friction


def spinning_needle(duration_s, rate_hz, rng):
    """A needle driven through the measured force-depth curve (``measured_insertion``) on a minimum-jerk trajectory
    to 40-100 % of its depth (1-5 mm/s on average, so the speed is bell-shaped); one insertion in two the needle spins
    (4-16 mm/s at its surface): the shaft's friction is then tilted away from the axis, its axial share
    v / sqrt(v^2 + (omega r)^2), and the tip cuts 10-30 % more easily. The cutting part grows with the axial speed as
    (v / 3 mm/s)^0.1-0.25 (at least 0.3 mm/s), the whole curve scaled to a 3.5-8 N peak. At the target the needle
    stops (and stops spinning) for 1-6 s while the force relaxes to 55-85 % (1-4 s); it is then withdrawn, the
    holder lifting off the sensor's button in 0.2-0.6 s (the sensor only reads push), and rests 4-15 s. A train of
    synthetic punctures when ``../shared/data`` is absent."""
    curve = measured_insertion()
    if curve is None:
        return puncture_train(duration_s, rate_hz, rng)
    depth_mm, friction, cutting = curve
    peak = max(float(np.max(friction + cutting)), 1e-3)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    now = rng.uniform(3.0, 8.0)
    while now < duration_s - 5.0:
        target, v_mean = rng.uniform(0.4, 1.0) * depth_mm[-1], float(np.exp(rng.uniform(0.0, np.log(5.0))))
        spin = rng.random() < 0.5
        surface, easier = (rng.uniform(4.0, 16.0), rng.uniform(0.1, 0.3)) if spin else (0.0, 0.0)
        scale, power = rng.uniform(3.5, 8.0) / peak, rng.uniform(0.1, 0.25)
        hold, keep, tau_r, lift = rng.uniform(1.0, 6.0), rng.uniform(0.55, 0.85), rng.uniform(1.0, 4.0), \
            rng.uniform(0.2, 0.6)
        t_in = target / v_mean
        seg = (t >= now) & (t < now + t_in)
        if not seg.any():
            break
        u = (t[seg] - now) / t_in
        depth, speed = target * quintic(u), target / t_in * quintic_rate(u)
        axial = speed / np.hypot(speed, surface) if spin else np.ones_like(speed)
        f[seg] = scale * (np.interp(depth, depth_mm, cutting) * (1.0 - easier) * (np.maximum(speed, 0.3) / 3.0) ** power
                          + np.interp(depth, depth_mm, friction) * axial)
        last = float(f[seg][-1])
        now += t_in
        seg = (t >= now) & (t < now + hold)
        f[seg] = last * (keep + (1.0 - keep) * np.exp(-(t[seg] - now) / tau_r))
        last *= keep + (1.0 - keep) * math.exp(-hold / tau_r)
        now += hold
        seg = (t >= now) & (t < now + lift)
        f[seg] = last * (1.0 - quintic((t[seg] - now) / lift))
        now += lift + rng.uniform(4.0, 15.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def rolling_indentation(duration_s, rate_hz, rng):
    """A rolling indenter scanning a tissue phantom for stiff nodules: a track of 40-80 mm whose stiffness varies
    smoothly (three random sinusoids along it, 10-25 % in all) with 1-3 nodules (Gaussian bumps 2-5 mm wide that
    raise it by 30-120 %). Each scan presses in at one end (0.5-1.5 s) to a depth that gives 1.5-3.5 N on the
    background, rolls 2-6 passes at 3-12 mm/s (each pass a minimum-jerk move, 0.2-0.6 s of pause at the ends), the
    depth wobbling with the operator's hand (1-3 % at 0.5-2 Hz), then lifts off (0.3-0.8 s) and rests 5-20 s. The
    force at a set depth follows the stiffness under the roller."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    length = rng.uniform(40.0, 80.0)
    waves = [(a, rng.uniform(8.0, 40.0), rng.uniform(0.0, 2.0 * np.pi))
             for a in rng.dirichlet(np.ones(3)) * rng.uniform(0.1, 0.25)]
    nodules = [(rng.uniform(0.15, 0.85) * length, rng.uniform(2.0, 5.0), rng.uniform(0.3, 1.2))
               for _ in range(int(rng.integers(1, 4)))]

    def stiffness(x):
        k = 1.0 + sum(a * np.sin(2.0 * np.pi * x / lam + ph) for a, lam, ph in waves)
        return k * (1.0 + sum(h * np.exp(-0.5 * ((x - c) / w) ** 2) for c, w, h in nodules))
    wobble, f_hand, phase = rng.uniform(0.01, 0.03), rng.uniform(0.5, 2.0), rng.uniform(0.0, 2.0 * np.pi)
    hand = 1.0 + wobble * np.sin(2.0 * np.pi * f_hand * t + phase)
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 6.0:
        level, press, speed = rng.uniform(1.5, 3.5), rng.uniform(0.5, 1.5), rng.uniform(3.0, 12.0)
        at = 0.0 if rng.random() < 0.5 else length
        seg = (t >= now) & (t < now + press)
        f[seg] = level * stiffness(at) * quintic((t[seg] - now) / press) * hand[seg]
        now += press
        for _ in range(int(rng.integers(2, 7))):
            pause, move = rng.uniform(0.2, 0.6), length / speed
            seg = (t >= now) & (t < now + pause)
            f[seg] = level * stiffness(at) * hand[seg]
            now += pause
            to = length - at
            seg = (t >= now) & (t < now + move)
            f[seg] = level * stiffness(at + (to - at) * quintic((t[seg] - now) / move)) * hand[seg]
            now, at = now + move, to
        lift, last = rng.uniform(0.3, 0.8), level * float(stiffness(at))
        seg = (t >= now) & (t < now + lift)
        f[seg] = last * (1.0 - quintic((t[seg] - now) / lift))
        now += lift + rng.uniform(5.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def delayed_contacts(duration_s, rate_hz, rng):
    """Contacts made through a teleoperator with a communication delay: the tool reaches a stiff surface too fast and
    bounces 2-6 times (impacts of 20-60 ms, half sines, the first 2.5-7 N; each rebound's peak and flight time the
    previous ones times a restitution of 0.4-0.75, the first flight 0.2-0.5 s), then settles (0.2-0.5 s) into a hold
    of 1-4 N for 3-15 s whose force wanders by 10-30 % (a random force below 0.5-1.5 Hz), is released in 0.2-0.5 s
    and rests 3-12 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    grid = np.arange(0.0, duration_s + 1.0, 0.05)
    sos = signal.butter(2, rng.uniform(0.5, 1.5), fs=20.0, output="sos")
    wander = signal.sosfiltfilt(sos, rng.normal(0.0, 1.0, grid.size))
    wander = np.interp(t, grid, wander / max(float(np.max(np.abs(wander))), 1e-9))
    now = rng.uniform(2.0, 5.0)
    while now < duration_s - 8.0:
        peak, e, flight = rng.uniform(2.5, 7.0), rng.uniform(0.4, 0.75), rng.uniform(0.2, 0.5)
        for k in range(int(rng.integers(2, 7))):
            width = rng.uniform(0.02, 0.06)
            seg = (t >= now) & (t < now + width)
            f[seg] = peak * e ** k * np.sin(np.pi * (t[seg] - now) / width)
            now += width + flight * e ** (k + 1)
        level, settle, hold, release = rng.uniform(1.0, 4.0), rng.uniform(0.2, 0.5), rng.uniform(3.0, 15.0), \
            rng.uniform(0.2, 0.5)
        share = rng.uniform(0.1, 0.3)
        seg = (t >= now) & (t < now + settle)
        f[seg] = level * (1.0 + share * wander[seg]) * quintic((t[seg] - now) / settle)
        now += settle
        seg = (t >= now) & (t < now + hold)
        f[seg] = level * (1.0 + share * wander[seg])
        now += hold
        last = level * (1.0 + share * float(np.interp(now, t, wander)))
        seg = (t >= now) & (t < now + release)
        f[seg] = last * (1.0 - quintic((t[seg] - now) / release))
        now += release + rng.uniform(3.0, 12.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (spinning_needle, rolling_indentation, delayed_contacts)


def temperature(t, rng, step_s=0.5):
    """A sensor carried by the robot between a warmed organ bath and its parking place: the room at 21.5-24 degC,
    drifting by up to +-0.5 degC over the record; the bath's heater was switched on 0-600 s before the record and
    warms the air over the bath toward 3-7 degC above the room (time constant 200-600 s), a plume that flickers by
    0.1-0.3 degC (a random signal below 0.07-0.2 Hz); the robot dwells 40-150 s over the bath and 20-90 s parked, the
    sensor following the air where it is with a time constant of 25-80 s (exact per step of ``step_s``), settled at
    the start."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(0.0, d + 2.0 * step_s, step_s)
    room = T_REF_C + rng.uniform(-1.5, 1.0) + rng.uniform(-0.5, 0.5) * grid / d
    rise, tau_h, since = rng.uniform(3.0, 7.0), rng.uniform(200.0, 600.0), rng.uniform(0.0, 600.0)
    sos = signal.butter(1, rng.uniform(0.07, 0.2), fs=1.0 / step_s, output="sos")
    flicker = signal.sosfilt(sos, rng.normal(0.0, 1.0, grid.size))
    flicker *= rng.uniform(0.1, 0.3) / max(float(np.std(flicker)), 1e-9)
    plume = room + rise * -np.expm1(-(grid + since) / tau_h) + flicker
    over = np.zeros(grid.size, dtype=bool)
    now, above = 0.0, rng.random() < 0.5
    while now < d + step_s:
        dwell = rng.uniform(40.0, 150.0) if above else rng.uniform(20.0, 90.0)
        over[(grid >= now) & (grid < now + dwell)] = above
        now += dwell
        above = not above
    target = np.where(over, plume, room)
    keep = math.exp(-step_s / rng.uniform(25.0, 80.0))
    out, y = np.empty_like(grid), float(target[0])
    for i, goal in enumerate(target.tolist()):
        out[i] = y
        y = goal + (y - goal) * keep
    return np.interp(s, grid, out)


# ----------------------------------------------------------------------------- simulate-only truth elements

def temp_of(aux, n):
    """The chain's temperature as an array of ``n`` samples."""
    return np.broadcast_to(np.asarray(aux["temperature_c"], dtype=float), (n,))


def follow(t, temp, tau_s, step_s=0.5):
    """``temp`` seen by a body that follows it with a time constant ``tau_s`` (exact per coarse step for the step's
    end value), settled at the start."""
    grid, tg = coarse(t, temp, step_s)
    keep, y = math.exp(-step_s / tau_s), float(tg[0])
    out = np.empty_like(tg)
    for i, goal in enumerate(tg.tolist()):
        y = goal + (y - goal) * keep
        out[i] = y
    return np.interp(t, grid, out)


def recovery_creep(fluidity, hardening, recovery, step_s=0.05):
    """Bailey-Orowan: x' = A max(F - B, 0), B' = h x' - r B (the back stress B, N, built by the flow and recovering
    with time), on a grid of ``step_s``, from rest."""
    def rule(t, f):
        grid = np.arange(t[0], t[-1] + step_s, step_s)
        fg = np.interp(grid, t, f)
        fade = math.exp(-recovery * step_s)
        gain = (1.0 - fade) / recovery
        x, back, out = 0.0, 0.0, np.empty(grid.size)
        for i, fi in enumerate(fg.tolist()):
            out[i] = x
            rate = fluidity * max(fi - back, 0.0)
            x += rate * step_s
            back = back * fade + hardening * rate * gain
        return np.interp(t, grid, out)
    return rule


def layered_pull_out(fluidity, yield_n, ripple, pitch_v, phase, step_s=0.05):
    """A pin creeping out of a printed bore: x' = A max(F - Y (1 + a cos(2 pi x / pitch + phase)), 0), a yield that
    ripples with the distance flowed (one period per layer line), on a grid of ``step_s``, from rest."""
    def rule(t, f):
        grid = np.arange(t[0], t[-1] + step_s, step_s)
        fg = np.interp(grid, t, f)
        x, out, k = 0.0, np.empty(grid.size), 2.0 * math.pi / pitch_v
        for i, fi in enumerate(fg.tolist()):
            out[i] = x
            x += fluidity * max(fi - yield_n * (1.0 + ripple * math.cos(k * x + phase)), 0.0) * step_s
        return np.interp(t, grid, out)
    return rule


def struik_time(t, t_age_s, mu):
    """Struik's effective time of a polymer ageing from the first sample: int (1 + s / t_a)^-mu ds (mu < 1)."""
    s = t - t[0]
    return t[0] + t_age_s / (1.0 - mu) * ((1.0 + s / t_age_s) ** (1.0 - mu) - 1.0)


def snap_through_map(centre_n, loop_n, ratio):
    """A bistable flexure beside the core under force control: the applied force F = v - q s exp(-s^2),
    s = (v - v_m) / w, q = ``ratio`` w, v the force the core sees, w set so that the loop is ``loop_n`` wide in F.
    Where dF/dv < 0 the state jumps: the lower branch holds up to the force at the start of that band, the upper one
    down to the force at its end. Returns a function of the force history (a relay between the two branches, from the
    lower one)."""
    def branches(w):
        v = np.arange(centre_n - 40.0 * w, centre_n + 40.0 * w, w / 400.0)
        s = (v - centre_n) / w
        applied = v - ratio * w * s * np.exp(-s * s)
        falling = np.flatnonzero(np.diff(applied) <= 0.0)
        return v, applied, int(falling[0]), int(falling[-1]) + 1
    v, applied, lo_end, hi_start = branches(1.0)
    v, applied, lo_end, hi_start = branches(loop_n / float(applied[lo_end] - applied[hi_start]))
    v, applied = np.concatenate([[-50.0], v, [50.0]]), np.concatenate([[-50.0], applied, [50.0]])
    lo_end, hi_start = lo_end + 1, hi_start + 1
    up_at, down_at = float(applied[lo_end]), float(applied[hi_start])
    low_f, low_v = applied[:lo_end + 1], v[:lo_end + 1]
    high_f, high_v = applied[hi_start:], v[hi_start:]

    def core_force(f):
        upper, state = np.empty(f.size, dtype=bool), False
        for i, fi in enumerate(f.tolist()):
            state = fi > down_at if state else fi > up_at
            upper[i] = state
        return np.where(upper, np.interp(f, high_f, high_v), np.interp(f, low_f, low_v))
    return core_force


class MenegottoPinto(SimOnly):
    """Smooth elastic-plastic branches on the voltage: from each reversal (x_r, y_r) a unit slope bends toward the
    asymptote y = b x +- (1 - b) x_y through the curve y* = b x* + (1 - b) x* / (1 + |x*|^R)^(1/R), normalised by
    the intersection of the two lines; R = R0 (1 - 0.5 xi / (0.15 + xi)), xi the excursion of the previous branch
    past its intersection over x_y (Bauschinger). A branch that opens inside another is scaled to end at the reversal
    where that one began, and when it gets there the inner loop is closed and the older branch goes on (return-point
    memory). Starts on the lower asymptote; the output is shifted to start at x[0]."""

    def __init__(self, x_y, b, r0):
        self.x_y, self.b, self.r0 = x_y, b, r0

    def branch(self, xr, yr, d, r, aim):
        """(origin x, origin y, direction, R, asymptote corner x, y, aim or None, scale)."""
        corner_x = d * self.x_y + (xr - yr) / (1.0 - self.b)
        corner_y = self.b * corner_x + d * (1.0 - self.b) * self.x_y
        new = [xr, yr, d, r, corner_x, corner_y, aim, 1.0]
        if aim is not None:
            reach = self.value(new, aim[0]) - yr
            new[7] = (aim[1] - yr) / reach if abs(reach) > 1e-12 else 1.0
        return new

    def value(self, br, xi):
        xr, yr, d, r, cx, cy, aim, scale = br
        span = cx - xr
        if abs(span) < 1e-15:
            return yr
        u = (xi - xr) / span
        return yr + scale * (cy - yr) * (self.b * u + (1.0 - self.b) * u / (1.0 + abs(u) ** r) ** (1.0 / r))

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        prev = float(x[0])
        stack = [self.branch(prev, self.b * prev - (1.0 - self.b) * self.x_y, 1.0, self.r0, None)]
        opened = [False]  # whether each branch began at a reversal inside the record
        y, out = stack[-1][1], np.empty_like(x)
        for i, xi in enumerate(x.tolist()):
            if xi != prev:
                step = 1.0 if xi > prev else -1.0
                cur = stack[-1]
                if step != cur[2]:
                    excursion = abs(prev - cur[4]) / self.x_y
                    r = max(self.r0 * (1.0 - 0.5 * excursion / (0.15 + excursion)), 1.0)
                    stack.append(self.branch(prev, y, step, r, (cur[0], cur[1]) if opened[-1] else None))
                    opened.append(True)
                while stack[-1][6] is not None and (xi - stack[-1][6][0]) * step > 0.0:
                    del stack[-2:], opened[-2:]
                y = self.value(stack[-1], xi)
                prev = xi
            out[i] = y
        return out - out[0] + x[0]


class EnvelopeDetector(SimOnly):
    """A hold capacitor charged through a diode (``tau_up_s``) and discharged through a resistor (``tau_down_s``):
    exact per step for the step's own time constant, from x[0]."""

    def __init__(self, tau_up_s, tau_down_s):
        self.up, self.down = tau_up_s, tau_down_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        dt = np.diff(t, prepend=t[0]).tolist()
        y, out = float(x[0]), np.empty_like(x)
        for i, (xi, h) in enumerate(zip(x.tolist(), dt)):
            y = xi + (y - xi) * math.exp(-h / (self.up if xi > y else self.down))
            out[i] = y
        return out


class PacketStamps(SimOnly):
    """A sample reaches the record ``latency_s`` plus a sawtooth 0..``packet_s`` later than it was taken: the packets
    of ``packet_s`` (phase ``phase_s``) are stamped at their arrival."""

    def __init__(self, latency_s, packet_s, phase_s):
        self.latency, self.packet, self.phase = latency_s, packet_s, phase_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        wait = self.packet * (1.0 - np.mod(t - t[0] + self.phase, self.packet) / self.packet)
        return np.interp(t - self.latency - wait, t, x, left=x[0])


def tilted_seat(theta0, kappa, top):
    """x cos(theta0 + kappa x / top) / cos(theta0): the axial share of a load through a seat that tilts with it."""
    return lambda x: x * np.cos(theta0 + kappa * x / top) / math.cos(theta0)


def largest_departure(fn, top):
    """The largest relative departure of ``fn`` from the unit slope over (0, top]."""
    xs = np.linspace(0.02 * top, top, 50)
    return float(np.max(np.abs(fn(xs) / xs - 1.0)))


def seat_tilt(theta0, rel, top):
    """The tilt rate kappa whose cosine error departs by ``rel`` at most up to ``top``, cut (by 10 % at a time) until
    the map rises up to 1.6 top."""
    kappa = optimize.brentq(lambda k: largest_departure(tilted_seat(theta0, k, top), top) - rel, 1e-6, 1.5)
    xs = np.linspace(0.0, 1.6 * top, 200)
    while np.any(np.diff(tilted_seat(theta0, kappa, top)(xs)) <= 0.0):
        kappa *= 0.9
    return kappa


def sar_bits(lo_v, hi_v, errors):
    """A successive-approximation ADC over [lo, hi] whose top bits weigh 2^-k (1 + e_k) of its span instead of 2^-k
    (``errors`` the absolute errors e_k 2^-k, as fractions of the span); the lower bits exact."""
    def convert(v):
        u = np.clip((np.asarray(v, dtype=float) - lo_v) / (hi_v - lo_v), 0.0, 1.0 - 1e-12)
        rest, out = u.copy(), u.copy()
        for k, err in enumerate(errors, start=1):
            bit = rest >= 2.0 ** -k
            rest = rest - bit * 2.0 ** -k
            out = out + bit * err
        return lo_v + (hi_v - lo_v) * out
    return convert


def relaxing_bond_zero(t, temp, k_v_per_c, lag_s, weight, tau0_s, b_per_c, step_s=0.5):
    """k ((T_s - T_ref) + weight sigma), T_s the sensor's temperature (a lag ``lag_s``), sigma the thermal stress in
    the bond: sigma' = T_s' - sigma / tau(T_s), tau = tau0 exp(-b (T_s - T_ref)) (exact per step for a ramp), from
    zero."""
    ts = follow(t, temp, lag_s)
    grid, tg = coarse(t, ts, step_s)
    sigma, out = 0.0, np.empty_like(tg)
    out[0] = 0.0
    for i in range(1, tg.size):
        tau = tau0_s * math.exp(-b_per_c * (tg[i] - T_REF_C))
        fade = math.exp(-step_s / tau)
        sigma = sigma * fade + (tg[i] - tg[i - 1]) / step_s * tau * (1.0 - fade)
        out[i] = sigma
    return k_v_per_c * (ts - T_REF_C + weight * np.interp(t, grid, out))


def stale_trim_zero(t, temp, k_v_per_c, trim_share, lag_s, period_s, phase_s):
    """k (T_s - T_ref) - k_c (T_s(t_n) - T_ref): a zero trimmed from a reading of T_s taken at the last poll t_n
    (every ``period_s`` from ``phase_s``; the poll before the record read the settled start)."""
    ts = follow(t, temp, lag_s)
    s = t - t[0]
    polls = phase_s + period_s * np.floor((s - phase_s) / period_s)
    read = np.interp(np.maximum(polls, 0.0), s, ts)
    return k_v_per_c * (ts - T_REF_C) - trim_share * k_v_per_c * (read - T_REF_C)


class ThermistorSpan(SimOnly):
    """A span (1 + a (T_s - T_ref)) D(T_s) / D(T_ref), D = 1 / (1 + sigma exp(-B (1/T - 1/T_ref))): the polymer's
    span rising linearly as it softens, against an NTC thermistor (B) in the excitation's divider, in series with
    sigma times its resistance at T_ref, which lowers the excitation as it warms; T_s the sensor's temperature (lag
    ``lag_s``)."""

    def __init__(self, a_per_c, sigma, b_kelvin, lag_s):
        self.a, self.sigma, self.b, self.lag = a_per_c, sigma, b_kelvin, lag_s

    def divider(self, temp):
        return 1.0 / (1.0 + self.sigma * np.exp(-self.b * (1.0 / (temp + 273.15) - 1.0 / (T_REF_C + 273.15))))

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        ts = follow(t, temp_of(aux, t.size), self.lag)
        return x * (1.0 + self.a * (ts - T_REF_C)) * self.divider(ts) / self.divider(T_REF_C)


def telegraph(rng, mean_dwell_s, horizon_s):
    """Switch times of a random telegraph signal (exponential dwells of the given means, the first state drawn):
    (first state, sorted switch times) over [0, horizon_s]."""
    state = bool(rng.random() < 0.5)
    first, times, now, on = state, [], 0.0, state
    while now < horizon_s:
        now += rng.exponential(mean_dwell_s[1] if on else mean_dwell_s[0])
        times.append(now)
        on = not on
    return first, np.asarray(times)


def telegraph_level(first, times, s):
    """1.0 where the telegraph is on at times ``s``, else 0.0."""
    flips = np.searchsorted(times, s, side="right")
    return ((flips % 2 == 0) == first).astype(float)


def reversal_aftereffect(size_v, period_s, phase_s, t0_s, n):
    """After each excitation reversal (every ``period_s`` from ``phase_s``, five before the record too) a kick of
    alternating sign decaying as (1 + age / t0)^-n; a function of the time since the first sample, zero there."""
    starts = phase_s + period_s * np.arange(-5, int((DURATION_S + 200.0) / period_s) + 2)
    signs = np.where(np.arange(starts.size) % 2 == 0, 1.0, -1.0)

    def zero(s):
        out = np.zeros_like(s)
        for at, sign in zip(starts.tolist(), signs.tolist()):
            age = s - at
            live = age >= 0.0
            out[live] += sign * (1.0 + age[live] / t0_s) ** -n
        return size_v * out
    return lambda s: zero(s) - zero(np.zeros(1))[0]


class BassetMode(SimOnly):
    """A mode in a fluid (Bagley-Torvik): w^2 / (s^2 + c w^0.5 s^1.5 + 2 zeta w s + w^2), applied by FFT on a
    uniform grid at the median step with 20 s of padding, from rest."""

    def __init__(self, f0_hz, fluid, zeta):
        self.w, self.c, self.zeta = 2.0 * math.pi * f0_hz, fluid, zeta

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        xu = xu - x[0]
        n = tu.size + int(20.0 / h)
        s = 2j * math.pi * np.fft.rfftfreq(n, h)
        w = self.w
        gain = w * w / (s * s + self.c * math.sqrt(w) * s ** 1.5 + 2.0 * self.zeta * w * s + w * w)
        y = np.fft.irfft(np.fft.rfft(xu, n) * gain, n)[:tu.size] + x[0]
        return np.interp(t, tu, y)


class CheckValveMode(SimOnly):
    """y'' + 2 w (zeta + zeta_v [y' > 0]) y' + w^2 (y - x) = 0: a mode whose damper works one way only; semi-implicit
    Euler with four sub-steps per sample of a uniform grid at the median step, from rest at x[0]."""

    def __init__(self, f0_hz, zeta, zeta_valve):
        self.w, self.zeta, self.valve = 2.0 * math.pi * f0_hz, zeta, zeta_valve

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        xu = xu.tolist()
        w2, sub = self.w * self.w, h / 4.0
        light, heavy = 2.0 * self.w * self.zeta, 2.0 * self.w * (self.zeta + self.valve)
        y, v, out = xu[0], 0.0, np.empty(len(xu))
        prev = xu[0]
        for i, xi in enumerate(xu):
            for j in range(1, 5):
                drive = prev + (xi - prev) * j / 4.0
                v += (-(heavy if v > 0.0 else light) * v - w2 * (y - drive)) * sub
                y += v * sub
            prev = xi
            out[i] = y
        return np.interp(t, tu, out)


def energised_seal(band_n, vent_s):
    """A Coulomb band band (0.35 + 0.65 P / 4 N), P the force seen through the chamber's vent (a lag ``vent_s``)."""
    def passed(t, f):
        pressure = kelvin(t, f, 1.0, vent_s)
        width = band_n * (0.35 + 0.65 * np.maximum(pressure, 0.0) / 4.0)
        return band_play(f, width, width)
    return passed


def bowing_needle(band_n, critical_n):
    """A Coulomb band band (0.3 + 0.7 g(F) / g(4 N)), g(F) = F / (1 - F / F_cr): a needle bowing under its axial
    load presses on its guide."""
    def g(f):
        f = np.clip(f, 0.0, 0.95 * critical_n)
        return f / (1.0 - f / critical_n)

    def passed(t, f):
        width = band_n * (0.3 + 0.7 * g(f) / g(4.0))
        return band_play(f, width, width)
    return passed


class ParallelPhases(SimOnly):
    """Two phases of a blend in parallel, each the Burgers core at half its constants, each on its own clock
    exp(b_i (T - T_ref)): x = F / k1 + (w_a + w_b) / 2, w_i = s_i + K_i, with the load shared as
    F_a = F / 2 + k1 (w_b - w_a) / 4, s_i' = 2 r_i F_i / eta1, K_i' = r_i (2 F_i - k2 K_i) / eta2; trapezoidal
    steps of ``step_s``, from rest. At equal clocks it is the core itself."""

    def __init__(self, c, b_fast, b_slow, step_s=0.005):
        self.c, self.b, self.step = c, (b_fast, b_slow), step_s

    def matrices(self, ra, rb):
        k1, k2, e1, e2 = self.c.k1_n_per_v, self.c.k2_n_per_v, self.c.eta1_n_s_per_v, self.c.eta2_n_s_per_v
        share = np.array([-1.0, -1.0, 1.0, 1.0]) * k1 / 4.0  # F_a = F / 2 + share . z, F_b = F / 2 - share . z
        a, b = np.zeros((4, 4)), np.zeros(4)
        for row, (r, sign) in enumerate(((ra, 1.0), (rb, -1.0))):
            i = 2 * row
            a[i] = 2.0 * r / e1 * sign * share
            a[i + 1] = 2.0 * r / e2 * sign * share
            a[i + 1, i + 1] -= r * k2 / e2
            b[i], b[i + 1] = r / e1, r / e2
        return a, b

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        grid = np.arange(t[0], t[-1] + self.step, self.step)
        fg = np.interp(grid, t, f)
        tg = np.interp(grid, t, temp_of(aux, t.size))
        rates = np.exp(np.outer(tg - T_REF_C, self.b))
        z, eye, h = np.zeros(4), np.eye(4), self.step
        a0, b0 = self.matrices(*rates[0])
        w = np.zeros(grid.size)
        for i in range(1, grid.size):
            a1, b1 = self.matrices(*rates[i])
            rhs = z + 0.5 * h * (a0 @ z + b0 * fg[i - 1] + b1 * fg[i])
            z = np.linalg.solve(eye - 0.5 * h * a1, rhs)
            w[i] = 0.5 * (z[0] + z[1] + z[2] + z[3])
            a0, b0 = a1, b1
        return f / self.c.k1_n_per_v + np.interp(t, grid, w)


class LeadingCoreClock(SimOnly):
    """A Burgers core on the clock exp(b (T_c - T_ref)), T_c = T + tau dT/dt: the thermometer lags the core by
    ``tau_s`` (the derivative on a grid of 0.5 s)."""

    def __init__(self, c, b_per_c, tau_s):
        self.c, self.b, self.tau = c, b_per_c, tau_s

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        grid, tg = coarse(t, temp_of(aux, t.size), 0.5)
        core_t = tg + self.tau * np.gradient(tg, grid)
        rate = np.exp(self.b * (np.interp(t, grid, core_t) - T_REF_C))
        return simulate_deformation(self.c, integrate.cumulative_trapezoid(rate, t, initial=0.0) + t[0], f)


class OverrunLead(SimOnly):
    """A voltage stream that loses ``lost_s[k]`` of samples at each buffer overrun (at ``times_s`` since the first
    sample) while its stamps keep counting: the voltage at t is the one taken at t + the time lost so far."""

    def __init__(self, times_s, lost_s):
        self.times, self.lost = np.asarray(times_s), np.cumsum(lost_s)

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        k = np.searchsorted(self.times, t - t[0], side="right")
        ahead = np.concatenate([[0.0], self.lost])[k]
        return np.interp(t + ahead, t, x, right=x[-1])


class IntermittentGain(SimOnly):
    """The whole output times 1 + ``change`` while a telegraph (``first``, ``times`` since the first sample) is on."""

    def __init__(self, change, first, times):
        self.change, self.first, self.times = change, first, times

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        return x * (1.0 + self.change * telegraph_level(self.first, self.times, t - t[0]))


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    top = FORCE_MAX_N / c.relaxation().g0_n_per_v  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([8e4, 4e3]))))  # V / (N s)
        if shape == "recovery_creep":
            share, speed = rng.uniform(0.4, 0.75), 1.0 / rng.uniform(15.0, 80.0)  # steady back stress / F, 1/s
            fluidity = phi * rng.uniform(1.5, 2.5)
            rule = recovery_creep(fluidity, share * speed / fluidity, (1.0 - share) * speed)
            return Parts("zener", ZenerWithFlow(c, rule), core_changed=True)
        fluidity, yield_n, ripple = phi * rng.uniform(2.0, 3.0), rng.uniform(0.5, 1.5), rng.uniform(0.4, 0.8)
        pitch = phi * 1100.0 / rng.uniform(2.0, 6.0)  # 2-6 layer lines over a plain flow of the record
        rule = layered_pull_out(fluidity, yield_n, ripple, pitch, rng.uniform(0.0, 2.0 * np.pi))
        return Parts("zener", ZenerWithFlow(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        if shape == "ageing_kelvin":
            compliance, tau = float(np.interp(m, [0, 1], [0.004, 0.05])), rng.uniform(3.0, 30.0)
            t_age, mu = rng.uniform(30.0, 150.0), rng.uniform(0.7, 0.95)
            p.extra.append(lambda t, f, T, k=compliance, tau=tau, ta=t_age, mu=mu:
                           kelvin(struik_time(t, ta, mu), f, k, tau))
            return p
        compliance, tau, preload = float(np.interp(m, [0, 1], [0.008, 0.09])), rng.uniform(2.0, 30.0), \
            rng.uniform(1.5, 3.5)
        p.extra.append(lambda t, f, T, k=compliance, tau=tau, f0=preload: kelvin(t, np.maximum(f - f0, 0.0), k, tau))
        return p
    if effect == "hysteresis":
        if shape == "snap_through_flexure":
            snap = snap_through_map(rng.uniform(1.5, 3.5), float(np.interp(m, [0, 1], [0.2, 0.8])),
                                    float(np.interp(m, [0, 1], [2.5, 4.0])))
            p.before.append(ForcePath(lambda t, x, fn=snap: fn(x)))
            return p
        frac, b = float(np.interp(m, [0, 1], [0.03, 0.11])), rng.uniform(0.85, 0.95)
        p.after.append(MenegottoPinto(frac * top / (2.0 * (1.0 - b)), b, rng.uniform(2.5, 6.0)))
        return p
    if effect == "sensor_lag":
        if shape == "envelope_detector":
            up = float(np.exp(np.interp(m, [0, 1], np.log([0.004, 0.025])))) * rng.uniform(0.8, 1.2)
            p.after.append(EnvelopeDetector(up, up * rng.uniform(3.0, 8.0)))
            return p
        packet = float(np.interp(m, [0, 1], [0.01, 0.05])) * rng.uniform(0.8, 1.2)
        p.after.append(PacketStamps(rng.uniform(0.002, 0.008), packet, rng.uniform(0.0, packet)))
        return p
    if effect == "nonlinear_gain":
        if shape == "tilting_seat":
            theta0 = rng.uniform(-0.2, 0.45)
            kappa = seat_tilt(theta0, float(np.interp(m, [0, 1], [0.04, 0.12])), top)
            p.after.append(StaticMap(tilted_seat(theta0, kappa, top)))
            return p
        errors = rng.normal(0.0, 1.0, 7) * 2.0 ** (-0.5 * np.arange(7))  # a bipolar ADC over +-1.6 top
        u = np.linspace(0.5, 0.5 + 1.0 / 3.2, 2049)  # the sensor's range: zero force to top
        worst = float(np.max(np.abs(sar_bits(0.0, 1.0, errors)(u) - u)))
        errors *= float(np.interp(m, [0, 1], [0.004, 0.01])) / max(worst, 1e-12)
        p.outer.append(StaticMap(sar_bits(-1.6 * top, 1.6 * top, errors)))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.02]) * rng.choice([-1, 1]))
        if shape == "relaxing_bond_stress":
            lag, weight, tau0, b = rng.uniform(5.0, 20.0), rng.uniform(1.0, 3.0), rng.uniform(60.0, 400.0), \
                rng.uniform(0.1, 0.3)
            p.extra.append(lambda t, f, T, a=(k, lag, weight, tau0, b): relaxing_bond_zero(t, T, *a))
            return p
        share, lag, period = rng.uniform(0.4, 0.8), rng.uniform(5.0, 20.0), rng.uniform(30.0, 120.0)
        phase = rng.uniform(0.0, period)
        p.extra.append(lambda t, f, T, a=(k, share, lag, period, phase): stale_trim_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        if shape == "thermistor_compensated_span":
            net = float(np.interp(m, [0, 1], [0.005, 0.02]))  # |d ln(span) / dT| at T_ref
            b_kelvin, share = rng.uniform(3000.0, 4200.0), rng.uniform(0.2, 0.6)  # the thermistor's share of the divider
            compensation = share * b_kelvin / (T_REF_C + 273.15) ** 2
            a = compensation + net * float(rng.choice([-1, 1]))
            a = a if a > 0.002 else compensation + net
            p.after.append(ThermistorSpan(a, share / (1.0 - share), b_kelvin, rng.uniform(10.0, 40.0)))
            return p
        lag, k1, soften = rng.uniform(10.0, 40.0), c.k1_n_per_v, float(np.interp(m, [0, 1], [0.008, 0.03]))  # 1/degC
        p.extra.append(lambda t, f, T, a=soften, lag=lag, k1=k1: f / k1 * np.expm1(a * (follow(t, T, lag) - T_REF_C)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.08]) * rng.choice([-1, 1]))
        if shape == "popcorn_telegraph":
            first, times = telegraph(rng, (rng.uniform(10.0, 80.0), rng.uniform(10.0, 80.0)), DURATION_S + 200.0)
            p.extra.append(lambda t, f, T, a=0.5 * size, fi=first, ti=times:
                           a * (telegraph_level(fi, ti, t - t[0]) - float(fi)))
            return p
        period = rng.uniform(40.0, 120.0)
        zero = reversal_aftereffect(0.8 * size, period, rng.uniform(0.0, period), rng.uniform(1.0, 5.0),
                                    rng.uniform(0.5, 1.0))
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        f0 = rng.uniform(18.0, 45.0)
        zeta = float(np.interp(m, [0, 1], [0.06, 0.015])) * rng.uniform(0.8, 1.2)
        if shape == "basset_fluid_mode":
            fluid = rng.uniform(0.6, 0.9)  # the share of the damping from the fluid's history force
            p.after.append(BassetMode(f0, fluid * zeta / 0.3536, (1.0 - fluid) * zeta))
            return p
        p.after.append(CheckValveMode(f0, 0.5 * zeta, zeta * rng.uniform(0.6, 1.4)))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "energised_seal":
            p.before.append(ForcePath(energised_seal(r, rng.uniform(0.3, 3.0))))
            return p
        p.before.append(ForcePath(bowing_needle(r, rng.uniform(12.0, 20.0))))
        return p
    if effect == "thermo_rheological":
        if shape == "parallel_phases":
            b = float(np.interp(m, [0, 1], [0.12, 0.3]))
            return Parts("burgers", ParallelPhases(c, b, b * rng.uniform(0.0, 0.25)), core_changed=True)
        b = float(np.interp(m, [0, 1], [0.1, 0.25]))
        return Parts("burgers", LeadingCoreClock(c, b, rng.uniform(8.0, 20.0)), core_changed=True)
    if effect == "buffer_overrun_lead":
        times = np.cumsum(rng.exponential(rng.uniform(20.0, 90.0), 64))
        lost = float(np.interp(m, [0, 1], [0.002, 0.04])) * rng.uniform(0.5, 1.5, times.size)
        p.outer.append(OverrunLead(times, lost))
        return p
    if effect == "intermittent_gain_joint":
        first, times = telegraph(rng, (rng.uniform(10.0, 60.0), rng.uniform(3.0, 30.0)), DURATION_S + 200.0)
        change = float(np.interp(m, [0, 1], [0.01, 0.06]) * rng.choice([-1, 1]))
        p.outer.append(IntermittentGain(change, first, times))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["recovery_creep", "layered_pull_out"],
    "delayed_elasticity": ["ageing_kelvin", "preloaded_kelvin"],
    "hysteresis": ["snap_through_flexure", "menegotto_pinto_voltage"],
    "sensor_lag": ["envelope_detector", "packet_stamps"],
    "nonlinear_gain": ["tilting_seat", "sar_bit_weights"],
    "thermal_drift": ["relaxing_bond_stress", "stale_trim"],
    "thermal_sensitivity": ["thermistor_compensated_span", "glassy_spring_span"],
    "offset_drift": ["popcorn_telegraph", "reversal_aftereffect"],
    "resonance": ["basset_fluid_mode", "check_valve_mode"], "friction": ["energised_seal", "bowing_needle"],
    "thermo_rheological": ["parallel_phases", "leading_core_clock"],
}
PAIRS = (("viscous_flow", "thermal_sensitivity"), ("delayed_elasticity", "resonance"), ("hysteresis", "offset_drift"),
         ("friction", "nonlinear_gain"), ("thermo_rheological", "sensor_lag"), ("thermal_drift", "delayed_elasticity"))
OUTSIDE = ("buffer_overrun_lead", "intermittent_gain_joint")
RATES = (260.0, 370.0, 590.0, 830.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split O", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.0e-3, 2.6e-3), jitter=0.35,
                   gap_s=(0.2, 2.2))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
