"""Independent split N for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split N is an untouched held-out set: written before the engine it measures and blind to it (to how it detects and
fits anything), run once at its end, never used to choose anything. Every name of the catalogue is hidden in two
shapes that neither the registry's families (``polyforce_ros/sim/truths.py``) nor splits A to M use:

* a gel interlayer squeezed out from under the load (Stefan's squeeze flow: the gap closes as dh/dt = -F h^3 / K, so
  the flow starts linear in the force and slows as the layer thins, never recovering), or cyclic creep (ratchetting:
  besides a plain flow, each cycle of load adds flow in proportion to the force times the force travelled, the force
  seen through a memory of 0.3-1 s);
* a Kelvin unit whose spring stiffens exponentially as it stretches (Fung: collagen-like fibres recruited as it
  creeps, so the creep saturates at high loads and speeds up there), or a pneumatic Kelvin unit (air trapped in the
  cells of a foam that leaks through an orifice, the flow as the square root of the pressure: a 5 N step settles in
  a finite 3-30 s);
* a loop of tanh branches on the force before the core (a filled-rubber bushing that carries part of the load beside
  the core; Takacs' shifted-tanh branches, each scaled through its reversal point and the point where the loop it
  opened began, with return-point memory), or the micro-slip of a clamped joint on the bridge voltage
  (Mindlin-Deresiewicz: a 3/2-power approach to full slip, reached at a finite travel, with Masing's branches);
* an amplifier whose output slews at a limited rate (0.2-0.8 s to rise across the range, 0.5-2x that rate falling)
  behind its small-signal pole of 1-4 ms, or a force-balance (null-balance) read-out whose PI servo gives a type-2
  closed loop ((2 zeta w s + w^2) / (s^2 + 2 zeta w s + w^2): no lag on a ramp, an overshoot after a bend);
* an AC-excited bridge read by an amplitude (not phase-sensitive) detector with a quadrature residual (a hyperbola,
  sqrt((x + b)^2 + q^2)), or an optical read-out whose knife edge cuts a Gaussian beam (an erf, biased below or above
  the beam's centre);
* a zero that follows a body buffered by a phase-change material (the latent heat stalls its temperature in a melting
  range the record visits), or a reversible zero plus a permanent shift each time the lagged temperature exceeds its
  previous maximum (an adhesive relieving its cure stress: thermal annealing);
* a span set by the strain transfer through the gauge's adhesive (Volkersen shear lag: 1 - tanh(l) / l, the
  adhesive's shear modulus and so l falling with temperature), or a span that follows the polymer's water content
  (the relative humidity falls as the air warms; the water follows it by Fickian diffusion in a slab and plasticises
  the polymer);
* an offset from a ground loop that a compressor's motor switches (60-150 s on, a start-up surge decaying in 2-6 s),
  or the zero of a sealed reference cavity breathing with the ventilation's pressure (an Ornstein-Uhlenbeck process,
  30-150 s correlation);
* a mode read through a non-collocated (flexible) path (a pair of real zeros at 1.3-3 times its frequency,
  w^2 (1 - s^2 / z^2): an inverted response to a knock), or a mode split by a tuned-mass absorber (two peaks about a
  notch: Den Hartog's layout with a lightly damped absorber of 2-8 % of the mass, tuned to 0.85-1.1 of the mode);
* Coulomb friction that weakens as it slips (linear slip-weakening from a static band 1.5-2.5 times the dynamic one
  over 0.1-0.6 N of slip, healing whenever it sticks), or a band that rises with the logarithm of the sliding speed
  (velocity strengthening of a polymer on metal, Eyring);
* a core of grains whose activation spreads about its mean (a thermo-rheologically complex blend: each grain's clock
  exp(b_i dT), b_i spread by 30-60 %, the deformation their mean), or an Arrhenius clock on a core temperature that
  follows the thermometer faster on heating than on cooling (radiant gain through one face, convective loss).

It also holds six pairs, two effects outside the catalogue (Mullins softening: the compliance grows by 3-8 % with the
largest force so far; the charge a multiplexer injects each time it switches to the bridge's channel, a glitch every
0.5-2 s decaying in 10-40 ms) and four clean records. Profiles: a needle driven through the measured force-depth curve
(``../shared/data``, ``depth_force.csv``, its first insertion) into a liver that breathes (2-6 mm excursions every 3-5 s
along the needle: the tissue is cut anew only where the tip passes its deepest point, the cutting force is relieved
over 1-3 mm when the tissue moves back while the shaft's friction holds 30-60 % of it until the needle is withdrawn;
the force rising with the speed, 0.8-6 mm/s, as a power 0.15-0.3; a train of synthetic punctures when the data are
absent); a hand's grip efforts (sustained grips that fatigue, with a wavering force and re-boosts, and series of quick
squeezes); and a surgical stapler's firings (a trial clamp now and then, a clamp that stiffens as the tissue is
compressed and relaxes while it waits, a firing stroke with a bump per staple row, release). Rates 230, 420, 610 and
880 Hz (a mode at 1000 Hz with knocks that excite it), 1.2-2.8 mV noise, stamp jitter, gaps, and a sensor on a bench
by a window: the sun reaches it after a while, clouds pass, the blinds are sometimes lowered, the building's heating
drifts.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_n.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import math

import numpy as np
from scipy import integrate, optimize, signal, special

from independent_split import puncture_train
from polyforce_ros.physics.expconv import exp_convolve
from polyforce_ros.physics.viscoelastic import Zener, simulate_deformation
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import ForcePath, LinearFilter, Parts, ShapeSplit, SimOnly, band_play, coarse, kelvin

SEED0 = 960_000  # never a seed of the registry's splits nor of splits A (90000..) to M (890000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 450.0


# ----------------------------------------------------------------------------- profiles and temperature

def min_jerk(u):
    """The minimum-jerk blend from 0 to 1 over ``u`` in [0, 1]."""
    u = np.clip(u, 0.0, 1.0)
    return u ** 3 * (10.0 - 15.0 * u + 6.0 * u * u)


def needle_curve():
    """The first insertion of the measured force-depth curve (``depth_force.csv``; the file holds several digitised
    curves, the first ends where the depth falls back): depth [mm], increasing, and force [N], >= 0; None when the
    data are absent."""
    csv = profiles.okamura_csv_path()
    table = None if csv is None else csv.parent / "depth_force.csv"
    if table is None or not table.is_file():
        return None
    raw = np.loadtxt(table, delimiter=",", ndmin=2)
    depth = 1e3 * raw[:, 0]
    back = np.flatnonzero(depth < np.maximum.accumulate(depth) - 5.0)
    n = int(back[0]) if back.size else depth.size
    return np.maximum.accumulate(depth[:n]) + 1e-4 * np.arange(n), np.maximum(raw[:n, 1], 0.0)


def breathing_needle(duration_s, rate_hz, rng):
    """A needle driven through the measured force-depth curve into a liver that breathes: the organ moves 2-6 mm
    along the needle every 3-5 s, so the tip's depth in the tissue is the needle's plus the organ's excursion. The
    tissue is cut (the measured force at the deepest point reached) only where the tip passes its deepest point so
    far; when the tissue moves back the cutting force is relieved over 1-3 mm (the shaft's friction holding 30-60 %
    of it until the needle is withdrawn). Insertions at 0.8-6 mm/s to 50-100 % of the curve's depth, the force
    3.5-7.5 N per measured peak at 3 mm/s, times (v / 3 mm/s)^0.15-0.3; 2-8 s of hold, retraction at 5-15 mm/s,
    4-15 s of rest. A train of synthetic punctures when ``../shared/data`` is absent."""
    curve = needle_curve()
    if curve is None:
        return puncture_train(duration_s, rate_hz, rng)
    depth_mm, force = curve
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    amp, period, phase = rng.uniform(2.0, 6.0), rng.uniform(3.0, 5.0), rng.uniform(0.0, 2.0 * np.pi)
    organ = amp * 0.5 * (1.0 - np.cos(2.0 * np.pi * t / period + phase))
    tissue, exponent, relief_mm = rng.uniform(3.5, 7.5) / max(float(force.max()), 1e-3), rng.uniform(0.15, 0.3), \
        rng.uniform(1.0, 3.0)
    shaft = rng.uniform(0.3, 0.6)  # the share the shaft's friction holds while the needle is not withdrawn
    start = -amp - 2.0  # the tip clear of the tissue at any phase of the breath
    now = rng.uniform(3.0, 8.0)
    while now < duration_s - 5.0:
        target = rng.uniform(0.5, 1.0) * depth_mm[-1]
        v_in, hold, v_out = float(np.exp(rng.uniform(np.log(0.8), np.log(6.0)))), rng.uniform(2.0, 8.0), \
            rng.uniform(5.0, 15.0)
        t_in, t_out = (target - start) / v_in, (target - start) / v_out
        seg = (t >= now) & (t < now + t_in + hold + t_out)
        u = t[seg] - now
        needle = np.where(u < t_in, start + v_in * u, np.where(u < t_in + hold, target, target - v_out * (u - t_in - hold)))
        tip = needle + organ[seg]
        deepest = np.maximum.accumulate(tip)
        relief = np.clip(1.0 - (deepest - tip) / relief_mm, 0.0, 1.0)
        held = np.where(u < t_in + hold, shaft, 0.0)
        f[seg] = (tissue * (v_in / 3.0) ** exponent * np.interp(np.maximum(deepest, 0.0), depth_mm, force)
                  * (held + (1.0 - held) * relief) * (tip > 0.0))
        now += t_in + hold + t_out + rng.uniform(4.0, 15.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def grip_efforts(duration_s, rate_hz, rng):
    """A hand's grip efforts: seven in ten are sustained grips (a 0.2-0.8 s rise to 3-8.5 N, held 5-25 s while the
    muscles fatigue by 10-40 % with a time constant of 5-20 s, the force wavering by 1-3 % (a random signal below
    1-3 Hz) and 0-2 re-boosts of 5-15 % over 0.8-2 s, released in 0.1-0.4 s), the others a series of 3-6 quick
    squeezes (raised cosines to 3-7 N at 0.8-2 Hz); 5-20 s of rest between efforts."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    grid = np.arange(0.0, duration_s + 1.0, 0.05)
    corner = rng.uniform(1.0, 3.0)
    waver = signal.lfilter([1.0 - math.exp(-2 * math.pi * corner * 0.05)], [1.0, -math.exp(-2 * math.pi * corner * 0.05)],
                           rng.normal(0.0, 1.0, grid.size))
    waver = np.interp(t, grid, waver / max(float(np.std(waver)), 1e-9))
    cv = rng.uniform(0.01, 0.03)
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 4.0:
        if rng.random() < 0.3:
            n, hz, level = int(rng.integers(3, 7)), rng.uniform(0.8, 2.0), rng.uniform(3.0, 7.0)
            seg = (t >= now) & (t < now + n / hz)
            f[seg] = level * 0.5 * (1.0 - np.cos(2.0 * np.pi * hz * (t[seg] - now)))
            now += n / hz + rng.uniform(5.0, 20.0)
            continue
        target, rise, hold, release = rng.uniform(3.0, 8.5), rng.uniform(0.2, 0.8), rng.uniform(5.0, 25.0), \
            rng.uniform(0.1, 0.4)
        fatigue, tau_f = rng.uniform(0.1, 0.4), rng.uniform(5.0, 20.0)
        seg = (t >= now) & (t < now + rise)
        f[seg] = target * min_jerk((t[seg] - now) / rise)
        now += rise
        seg = (t >= now) & (t < now + hold)
        u = t[seg] - now
        held = target * (1.0 - fatigue * -np.expm1(-u / tau_f)) * (1.0 + cv * waver[seg])
        for _ in range(int(rng.integers(0, 3))):
            at, width, boost = rng.uniform(0.2, 0.9) * hold, rng.uniform(0.8, 2.0), rng.uniform(0.05, 0.15)
            held += target * boost * 0.5 * (1.0 - np.cos(2.0 * np.pi * np.clip((u - at) / width, 0.0, 1.0)))
        f[seg] = held
        last = float(held[-1]) if held.size else target
        now += hold
        seg = (t >= now) & (t < now + release)
        f[seg] = last * (1.0 - min_jerk((t[seg] - now) / release))
        now += release + rng.uniform(5.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def stapler_firings(duration_s, rate_hz, rng):
    """A surgical stapler's firings: one time in three a trial clamp (0.8-2 N, released after 1-3 s: the jaws are
    repositioned); the jaws close in 1-2.5 s on tissue that stiffens as it is compressed (exponential in the
    closure, 2.5-6 N at the end), wait 5-15 s while the tissue relaxes under them (to 60-85 %, 2-8 s), fire in
    0.6-1.5 s (the sledge's force rising by 1-3 N over the stroke as sin^2, with a bump of 0.3-0.8 N as each of 4-8
    staple rows forms), hold 1-4 s (the firing force fading in 0.5-2 s), open in 0.3-0.8 s and rest 8-30 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    now = rng.uniform(2.0, 6.0)

    def put(a, b, values_of):
        seg = (t >= a) & (t < b)
        f[seg] = values_of(t[seg] - a)
    while now < duration_s - 10.0:
        if rng.random() < 1.0 / 3.0:
            level, close, hold, open_s = rng.uniform(0.8, 2.0), rng.uniform(0.5, 1.2), rng.uniform(1.0, 3.0), \
                rng.uniform(0.3, 0.6)
            put(now, now + close, lambda u, lv=level, c=close: lv * min_jerk(u / c))
            put(now + close, now + close + hold, lambda u, lv=level: np.full_like(u, lv))
            put(now + close + hold, now + close + hold + open_s, lambda u, lv=level, o=open_s: lv * (1.0 - min_jerk(u / o)))
            now += close + hold + open_s + rng.uniform(1.0, 4.0)
        clamp, close, k = rng.uniform(2.5, 6.0), rng.uniform(1.0, 2.5), rng.uniform(2.0, 4.0)
        wait, floor, tau = rng.uniform(5.0, 15.0), rng.uniform(0.6, 0.85), rng.uniform(2.0, 8.0)
        fire, extra, rows, bump = rng.uniform(0.6, 1.5), rng.uniform(1.0, 3.0), int(rng.integers(4, 9)), rng.uniform(0.3, 0.8)
        after, fade, open_s = rng.uniform(1.0, 4.0), rng.uniform(0.5, 2.0), rng.uniform(0.3, 0.8)
        put(now, now + close, lambda u, c=clamp, d=close, k=k: c * np.expm1(k * u / d) / math.expm1(k))
        now += close
        put(now, now + wait, lambda u, c=clamp, fl=floor, ta=tau: c * (fl + (1.0 - fl) * np.exp(-u / ta)))
        held = clamp * (floor + (1.0 - floor) * math.exp(-wait / tau))
        now += wait

        def firing(u, h=held, e=extra, d=fire, n=rows, b=bump):
            s = u / d
            return h + e * np.sin(np.pi * s / 2.0) ** 2 * (s <= 1.0) + b * np.sin(np.pi * n * s) ** 2
        put(now, now + fire, firing)
        now += fire
        put(now, now + after, lambda u, h=held, e=extra, fd=fade: h + e * np.exp(-u / fd))
        last = held + extra * math.exp(-after / fade)
        now += after
        put(now, now + open_s, lambda u, lv=last, o=open_s: lv * (1.0 - min_jerk(u / o)))
        now += open_s + rng.uniform(8.0, 30.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (breathing_needle, grip_efforts, stapler_firings)


def temperature(t, rng, step_s=0.25):
    """A sensor on a bench by a window: the room starts at 22-24 degC and the building's heating drifts it by up to
    +-0.8 degC over the record; the sun reaches the bench at 0-30 % of the record and would warm the sensor by
    1.5-4 degC (time constant 40-150 s); clouds pass (sunny spells of 20-120 s, clouds of 10-60 s letting 15-40 %
    through), and three times in ten the blinds are lowered at 60-90 % (20 % let through). Exact per step of
    ``step_s`` for the step's own target, from the room's temperature."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(0.0, d + 2.0 * step_s, step_s)
    room0 = T_REF_C + rng.uniform(-1.0, 1.0)
    room = room0 + rng.uniform(-0.8, 0.8) * grid / d
    tau, gain = rng.uniform(40.0, 150.0), rng.uniform(1.5, 4.0)
    light = np.zeros_like(grid)
    now, sunny = rng.uniform(0.0, 0.3) * d, True
    while now < d:
        spell = rng.uniform(20.0, 120.0) if sunny else rng.uniform(10.0, 60.0)
        light[(grid >= now) & (grid < now + spell)] = 1.0 if sunny else rng.uniform(0.15, 0.4)
        now += spell
        sunny = not sunny
    if rng.random() < 0.3:
        light[grid >= rng.uniform(0.6, 0.9) * d] *= 0.2
    target = room + gain * light
    keep = math.exp(-step_s / tau)
    out, y = np.empty_like(grid), room0
    for i, eq in enumerate(target.tolist()):
        out[i] = y
        y = eq + (y - eq) * keep
    return np.interp(s, grid, out)


# ----------------------------------------------------------------------------- simulate-only truth elements

def temperature_of(aux, shape):
    """The temperature the chain passes its elements, broadcast to ``shape``."""
    return np.broadcast_to(np.asarray(aux["temperature_c"], dtype=float), shape)


class FlowOnZener(SimOnly):
    """A Zener core plus a flow ``flow(t, F)`` (V) added to its deformation."""

    def __init__(self, zener, flow):
        self.zener, self.flow = zener, flow

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        return simulate_deformation(self.zener, t, f) + self.flow(t, f)


def stefan_flow(gap_v, impulse_n_s):
    """A Newtonian layer squeezed out between discs (Stefan: dh/dt = -F h^3 / K): h = h0 (1 + int F dt / I0)^-1/2, the
    flow h0 - h (V); its initial rate is F h0 / (2 I0). Compression only squeezes it; nothing brings it back."""
    def flow(t, f):
        impulse = integrate.cumulative_trapezoid(np.maximum(f, 0.0), t, initial=0.0)
        return gap_v * (1.0 - 1.0 / np.sqrt(1.0 + impulse / impulse_n_s))
    return flow


def ratchet_flow(phi_v_per_n_s, ratchet_v_per_n2, memory_s):
    """Cyclic creep: a plain flow phi int F dt plus ratchet int |G| |dG|, G the force behind a lag ``memory_s`` (the
    polymer ratchets with cycles of load, not with what is faster than its memory): a load cycle 0 -> F -> 0 slower
    than the memory adds ratchet F^2."""
    def flow(t, f):
        plain = integrate.cumulative_trapezoid(phi_v_per_n_s * f, t, initial=0.0)
        g = kelvin(t, f, 1.0, memory_s)
        mid = 0.5 * (g[1:] + g[:-1])
        return plain + ratchet_v_per_n2 * np.concatenate([[0.0], np.cumsum(np.abs(mid) * np.abs(np.diff(g)))])
    return flow


def fung_kelvin(t, f, compliance_v_per_n, x0_v, tau0_s):
    """A Kelvin unit whose spring stiffens exponentially with its stretch (Fung): eta x' + k0 x0 (exp(x / x0) - 1) = F,
    k0 = 1 / compliance, eta = k0 tau0; per step linearised about its start (its own stiffness) for its mean force,
    from rest."""
    k0 = 1.0 / compliance_v_per_n
    tl, fl = t.tolist(), np.asarray(f, dtype=float).tolist()
    out, x = np.zeros(len(tl)), 0.0
    for i in range(1, len(tl)):
        g = 0.5 * (fl[i] + fl[i - 1])
        e = math.exp(min(x / x0_v, 50.0))
        stiff = k0 * e
        target = x + (g - k0 * x0_v * (e - 1.0)) / stiff
        x = target + (x - target) * math.exp(-(tl[i] - tl[i - 1]) * e / tau0_s)
        out[i] = x
    return out


def pneumatic_kelvin(t, f, compliance_v_per_n, settle_s, step_n=5.0):
    """A Kelvin unit whose dashpot is an orifice (turbulent: flow as the square root of the pressure): x' = c sign(u)
    sqrt(|u|), u = F - x / compliance, c set so that a step of ``step_n`` settles in ``settle_s`` (it settles in a
    finite time: sqrt(u) falls linearly); exact per step for the step's mean force, from rest."""
    k = 1.0 / compliance_v_per_n
    c = 2.0 * math.sqrt(step_n) / (k * settle_s)
    tl, fl = t.tolist(), np.asarray(f, dtype=float).tolist()
    out, x = np.zeros(len(tl)), 0.0
    for i in range(1, len(tl)):
        u = 0.5 * (fl[i] + fl[i - 1]) - k * x
        root = max(math.sqrt(abs(u)) - 0.5 * k * c * (tl[i] - tl[i - 1]), 0.0)
        x += math.copysign(abs(u) - root * root, u) / k
        out[i] = x
    return out


def return_point_memory(x, stack, direction, branch):
    """Madelung's return-point memory over the input ``x``. ``stack`` holds the reversal points (x, y) still open: the
    last is the origin of the current branch, the one before it its target; a reversal opens a new branch, a branch
    that passes its target closes its loop (both points leave the stack) and the branch it interrupted goes on. The
    first two entries (the history before the record) stay. ``branch(origin, target, direction, x) -> y``."""
    stack = [tuple(p) for p in stack]
    out = np.empty(x.size)
    prev = float(x[0])
    y = branch(stack[-1], stack[-2], direction, prev)
    for i, xi in enumerate(x.tolist()):
        if xi != prev:
            d = 1 if xi > prev else -1
            if d != direction:
                stack.append((prev, y))
                direction = d
            while len(stack) > 3 and (xi - stack[-2][0]) * d > 0:
                del stack[-2:]
            y = branch(stack[-1], stack[-2], direction, xi)
            prev = xi
        out[i] = y
    return out


class TakacsForce(SimOnly):
    """A filled-rubber bushing beside the core: the force the core sees is F + Q (M - (A + D) / 2 - c0), M a state on
    Takacs' branches of v = (F - F_mid) / w, ascending A(v) = tanh(v - a), descending D(v) = tanh(v + a), each branch
    a A + b (or a D + b) through its reversal point and its target (return-point memory; the major loop between
    +-1 at +-inf), from the descending major branch; c0 so that the rest force passes unchanged."""

    def __init__(self, f_mid_n, width_n, coercive, q_n):
        self.f_mid, self.w, self.a, self.q = f_mid_n, width_n, coercive, q_n

    def branch(self, origin, target, direction, v):
        a = self.a if direction > 0 else -self.a

        def shape(x):
            return math.copysign(1.0, x) if math.isinf(x) else math.tanh(x - a)
        den = shape(target[0]) - shape(origin[0])
        if abs(den) < 1e-12:
            return origin[1]
        return origin[1] + (target[1] - origin[1]) * (shape(v) - shape(origin[0])) / den

    def forward(self, t_s, x, aux=None, state=None):
        f = np.asarray(x, dtype=float)
        v = (f - self.f_mid) / self.w
        m = return_point_memory(v, [(-math.inf, -1.0), (math.inf, 1.0)], -1, self.branch)
        lag = m - 0.5 * (np.tanh(v - self.a) + np.tanh(v + self.a))
        return f + self.q * (lag - lag[0])


class MindlinMicroslip(SimOnly):
    """The read-out's clamped joint slipping partially (Mindlin-Deresiewicz): y = x + T, the joint's traction T on
    the backbone T* (1 - (1 - d / d*)^(3/2)) (full slip, T*, at d >= d*), Masing's branches T_r +- 2 B(|x - x_r| / 2)
    from each reversal, return-point memory; the joint cycled once over the record's range before it (so no virgin
    set), y shifted to start at x."""

    def __init__(self, t_star_v, d_star_v):
        self.t_star, self.d_star = t_star_v, d_star_v

    def backbone(self, d):
        return self.t_star * (1.0 - (1.0 - min(d / self.d_star, 1.0)) ** 1.5)

    def branch(self, origin, target, direction, x):
        return origin[1] + direction * 2.0 * self.backbone(abs(x - origin[0]) / 2.0)

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        lo, hi = min(float(x.min()), 0.0), float(x.max()) + 0.05 * self.d_star
        traction = return_point_memory(x, [(lo, 0.0), (hi, self.backbone(hi - lo))], -1, self.branch)
        return x + traction - traction[0]


class SlewLimited(SimOnly):
    """An amplifier whose output follows its input through a small-signal pole ``tau_s`` but changes at most by
    ``up_v_per_s`` (rising) and ``down_v_per_s`` (falling); exact per step for the pole, from x[0]."""

    def __init__(self, tau_s, up_v_per_s, down_v_per_s):
        self.tau, self.up, self.down = tau_s, up_v_per_s, down_v_per_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        dt = np.diff(t, prepend=t[0])
        keep = np.exp(-dt / self.tau)
        y, out = float(x[0]), np.empty_like(x)
        for i, (xi, k, h) in enumerate(zip(x.tolist(), keep.tolist(), dt.tolist())):
            step = (xi - y) * (1.0 - k)
            y += min(max(step, -self.down * h), self.up * h)
            out[i] = y
        return out


def detector_map(b, q):
    """An amplitude detector's output for a bridge signal x with an in-phase imbalance b and a quadrature residual
    q: sqrt((x + b)^2 + q^2) - sqrt(b^2 + q^2), over its slope at zero b / sqrt(b^2 + q^2)."""
    r0 = math.hypot(b, q)
    return lambda x: (np.hypot(np.maximum(x + b, 0.0), q) - r0) * r0 / b


def knife_edge_map(xc, sigma):
    """The light a knife edge lets past a Gaussian beam of width ``sigma``, the edge moving with x from ``xc`` below
    the beam's centre: Phi((x - xc) / sigma) - Phi(-xc / sigma), over its slope at zero."""
    slope = math.exp(-0.5 * (xc / sigma) ** 2) / (math.sqrt(2.0 * math.pi) * sigma)
    base = special.ndtr(-xc / sigma)
    return lambda x: (special.ndtr((x - xc) / sigma) - base) / slope


def largest_deviation(fn, top):
    """The largest relative departure of ``fn`` from its unit slope over (0, top]."""
    xs = np.linspace(top / 50.0, top, 50)
    return float(np.max(np.abs(fn(xs) / xs - 1.0)))


def latent_body(t, temp, tau_s, melt_c, width_c, latent, step_s=0.5):
    """A body coupled to ``temp`` by a lag ``tau_s`` whose heat capacity rises by ``latent`` times (a Gaussian of
    ``width_c`` about ``melt_c``) as a phase-change material melts: exact per step of ``step_s`` for the step's own
    capacity, from temp[0]."""
    grid, tg = coarse(t, temp, step_s)
    y, out = float(tg[0]), np.empty_like(tg)
    for i, ti in enumerate(tg.tolist()):
        out[i] = y
        capacity = 1.0 + latent * math.exp(-0.5 * ((y - melt_c) / width_c) ** 2)
        y = ti + (y - ti) * math.exp(-step_s / (tau_s * capacity))
    return np.interp(t, grid, out)


def lagged(t, temp, tau_s, step_s=0.5):
    """``temp`` behind a first-order lag ``tau_s``, from temp[0]."""
    grid, tg = coarse(t, temp, step_s)
    return np.interp(t, grid, tg[0] + kelvin(grid, tg - tg[0], 1.0, tau_s))


def annealing_zero(t, temp, k_v_per_c, tau_s, share):
    """k (T_l - T_ref) + share k (max so far of T_l - T_l(0)), T_l the temperature behind a lag ``tau_s``: a reversible
    zero plus a permanent shift each time the adhesive is warmer than it has been (its cure stress relieved)."""
    tl = lagged(t, temp, tau_s)
    return k_v_per_c * (tl - T_REF_C + share * (np.maximum.accumulate(tl) - tl[0]))


class ShearLagSpan(SimOnly):
    """The strain a bonded gauge takes from the polymer through its adhesive (Volkersen's shear lag): 1 - tanh(l) / l,
    l = l0 exp(-c (T - T_ref) / 2) (the adhesive's shear modulus exp(-c dT)), over its value at T_ref."""

    def __init__(self, l0, c_per_c):
        self.l0, self.c = l0, c_per_c

    @staticmethod
    def transfer(lam):
        return 1.0 - np.tanh(lam) / lam

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        lam = self.l0 * np.exp(-self.c * (temperature_of(aux, x.shape) - T_REF_C) / 2.0)
        return x * self.transfer(lam) / self.transfer(self.l0)


class HygroscopicSpan(SimOnly):
    """A span 1 + s (w - 1), w the polymer's water content relative to its content at T_ref: the air's relative
    humidity exp(-h (T - T_ref)) (warmer air, drier) reached by Fickian diffusion in a slab (modes of rates
    (2n + 1)^2 / tau_d, weights 8 / ((2n + 1)^2 pi^2)), from equilibrium at the first temperature."""

    def __init__(self, share, h_per_c, tau_d_s, modes=6):
        odd = 2.0 * np.arange(modes) + 1.0
        self.share, self.h = share, h_per_c
        self.rates, self.weights = odd ** 2 / tau_d_s, 8.0 / (odd ** 2 * np.pi ** 2)
        self.weights /= self.weights.sum()

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        grid, tg = coarse(t, temperature_of(aux, x.shape))
        rh = np.exp(-self.h * (tg - T_REF_C))
        w = rh[0] + exp_convolve(grid, rh - rh[0], self.rates) @ (self.weights * self.rates)
        return x * (1.0 + self.share * (np.interp(t, grid, w) - 1.0))


def compressor_zero(rng, size_v):
    """A ground loop through a compressor's motor: while it runs (60-150 s on, 60-240 s off, either first) the zero
    is shifted by ``size_v`` with a start-up surge of 50-150 % decaying in 2-6 s; a function of the time since the
    first sample, zero there."""
    starts, ends, now, on = [], [], -rng.uniform(0.0, 120.0), rng.random() < 0.5
    while now < DURATION_S + 60.0:
        length = rng.uniform(60.0, 150.0) if on else rng.uniform(60.0, 240.0)
        if on:
            starts.append(now)
            ends.append(now + length)
        now += length
        on = not on
    surge, tau = rng.uniform(0.5, 1.5), rng.uniform(2.0, 6.0)

    def shift(s):
        out = np.zeros_like(s)
        for a, b in zip(starts, ends):
            inside = (s >= a) & (s < b)
            out[inside] = size_v * (1.0 + surge * np.exp(-(s[inside] - a) / tau))
        return out
    return lambda s: shift(s) - shift(np.zeros(1))[0]


def cavity_zero(rng, size_v, tau_s, step_s=0.5):
    """A sealed reference cavity breathing with the ventilation's pressure: an Ornstein-Uhlenbeck process of standard
    deviation ``size_v`` and correlation time ``tau_s`` (stationary at the start), less its value there; a function
    of the time since the first sample."""
    grid = np.arange(0.0, DURATION_S + 60.0, step_s)
    keep = math.exp(-step_s / tau_s)
    kicks = rng.normal(0.0, size_v * math.sqrt(1.0 - keep * keep), grid.size)
    kicks[0] = rng.normal(0.0, size_v)
    walk = signal.lfilter([1.0], [1.0, -keep], kicks)
    return lambda s: np.interp(s, grid, walk) - walk[0]


def non_collocated_mode(f0_hz, zeta, zero_ratio):
    """(num, den) of w^2 (1 - s^2 / z^2) / (s^2 + 2 zeta w s + w^2), z = ``zero_ratio`` w: a mode read through a
    flexible path (a pair of real zeros, one in the right half plane)."""
    w = 2.0 * math.pi * f0_hz
    z = zero_ratio * w
    return [-(w / z) ** 2, 0.0, w * w], [1.0, 2.0 * zeta * w, w * w]


def absorber_mode(f0_hz, zeta, mass_ratio, tuning, zeta_a):
    """(num, den) of the mount's force over the applied force for a mass on its mount (w, zeta) with a tuned-mass
    absorber (mass ratio mu, frequency ``tuning`` w, damping zeta_a): k1 X1 / F, unit gain at rest."""
    w = 2.0 * math.pi * f0_hz
    wa = tuning * w
    k1, c1 = w * w, 2.0 * zeta * w
    k2, c2 = mass_ratio * wa * wa, 2.0 * zeta_a * mass_ratio * wa
    absorber = np.array([mass_ratio, c2, k2])
    coupling = np.array([c2, k2])
    den = np.polysub(np.polymul([1.0, c1 + c2, k1 + k2], absorber), np.polymul(coupling, coupling))
    return list(k1 * absorber), list(den)


def slip_weakening_play(f, static_n, dynamic_n, dc_n):
    """A Coulomb band that weakens as it slips: half-width dynamic + (static - dynamic) max(0, 1 - slip / dc), the slip
    counted while it slides and healed (reset) whenever it sticks; started at f[0]."""
    out, p, slip = np.empty_like(f), float(f[0]), 0.0
    span = static_n - dynamic_n
    for i, fi in enumerate(f.tolist()):
        r = dynamic_n + span * max(0.0, 1.0 - slip / dc_n)
        if fi - p > r:
            slip += fi - r - p
            p = fi - r
        elif p - fi > r:
            slip += p - fi - r
            p = fi + r
        else:
            slip = 0.0
        out[i] = p
    return out


def log_rate_band(t, f, r0_n, beta, v0_n_per_s, tau_s):
    """A band r0 (1 + beta ln(1 + v / v0)), v the force's speed smoothed over ``tau_s``: friction that strengthens
    with the logarithm of the sliding speed."""
    speed = np.abs(np.gradient(f, t))
    smooth = kelvin(t, speed, 1.0, tau_s)
    band = r0_n * (1.0 + beta * np.log1p(smooth / v0_n_per_s))
    return band_play(f, band, band)


class GrainClocks(SimOnly):
    """A Burgers core made of grains in series, each on its own Arrhenius-like clock exp(b_i (T - T_ref)): the
    deformation the weighted mean of the core run on each grain's reduced time."""

    def __init__(self, c, slopes, weights):
        self.c, self.slopes, self.weights = c, slopes, weights

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        dt = temperature_of(aux, t.shape) - T_REF_C
        out = np.zeros_like(f)
        for b, w in zip(self.slopes, self.weights):
            xi = integrate.cumulative_trapezoid(np.exp(b * dt), t, initial=0.0)
            out += w * simulate_deformation(self.c, xi, f)
        return out


class AsymmetricClock(SimOnly):
    """A Burgers core on the clock exp(b (T_c - T_ref)), T_c the core's temperature: it follows the thermometer with
    ``tau_up_s`` while warmer air (or sun) heats it and ``tau_down_s`` while it cools (exact per step of 0.5 s)."""

    def __init__(self, c, b_per_c, tau_up_s, tau_down_s, step_s=0.5):
        self.c, self.b, self.up, self.down, self.step = c, b_per_c, tau_up_s, tau_down_s, step_s

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        grid, tg = coarse(t, temperature_of(aux, t.shape), self.step)
        y, core_t = float(tg[0]), np.empty_like(tg)
        for i, ti in enumerate(tg.tolist()):
            core_t[i] = y
            y = ti + (y - ti) * math.exp(-self.step / (self.up if ti > y else self.down))
        rate = np.exp(self.b * (np.interp(t, grid, core_t) - T_REF_C))
        return simulate_deformation(self.c, integrate.cumulative_trapezoid(rate, t, initial=0.0), f)


def mux_glitches(period_s, phase_s, size_v, tau_s):
    """The charge a multiplexer injects each time it switches to the bridge's channel (every ``period_s``): a glitch
    of ``size_v`` decaying with ``tau_s``, on the sensor's own clock."""
    def glitch(t, f, T):
        age = np.mod(t - t[0] - phase_s, period_s)
        return size_v * np.exp(-age / tau_s)
    return glitch


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    top = FORCE_MAX_N / c.relaxation().g0_n_per_v  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([8e4, 4e3]))))  # V / (N s) at the start
        zener = Zener(c.k1_n_per_v, c.k2_n_per_v, c.eta2_n_s_per_v)
        if shape == "stefan_squeeze_flow":
            impulse = 1.5 * DURATION_S / rng.uniform(1.0, 5.0)  # the mean force's impulse over the record: 1-5 I0
            return Parts("zener", FlowOnZener(zener, stefan_flow(10.0 * phi * impulse, impulse)), core_changed=True)
        share, cycle_s, memory = rng.uniform(0.3, 0.6), rng.uniform(2.0, 10.0), rng.uniform(0.3, 1.0)
        flow = ratchet_flow(share * phi, phi * cycle_s / 5.0, memory)  # a 5 N cycle adds the plain flow of 5 N for 2-10 s
        return Parts("zener", FlowOnZener(zener, flow), core_changed=True)
    if effect == "delayed_elasticity":
        if shape == "fung_kelvin":
            total = float(np.interp(m, [0, 1], [0.005, 0.065]))  # added compliance at no load, V/N
            x0, tau = total * FORCE_MAX_N * rng.uniform(0.25, 0.6), rng.uniform(2.0, 30.0)  # linear creep 1.7-4x x0
            p.extra.append(lambda t, f, T, k=total, x0=x0, tau=tau: fung_kelvin(t, f, k, x0, tau))
            return p
        total, settle = float(np.interp(m, [0, 1], [0.0025, 0.0325])), rng.uniform(3.0, 30.0)  # V/N, s
        p.extra.append(lambda t, f, T, k=total, s=settle: pneumatic_kelvin(t, f, k, s))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.03, 0.11]))
        if shape == "takacs_force":
            a = rng.uniform(0.3, 0.8)
            p.before.append(TakacsForce(rng.uniform(3.0, 5.5), rng.uniform(1.0, 2.5), a,
                                        frac * FORCE_MAX_N / (2.0 * math.tanh(a))))
            return p
        p.after.append(MindlinMicroslip(0.35 * frac * top, rng.uniform(0.3, 1.0) * top))
        return p
    if effect == "sensor_lag":
        if shape == "slew_limited_amplifier":
            across = float(np.exp(np.interp(m, [0, 1], np.log([0.15, 1.0])))) * rng.uniform(0.8, 1.2)  # s across the range
            up = top / across
            p.after.append(SlewLimited(rng.uniform(0.001, 0.004), up, up * rng.uniform(0.5, 2.0)))
            return p
        zeta, delay = rng.uniform(0.5, 0.8), float(np.exp(np.interp(m, [0, 1], np.log([0.03, 0.12]))))
        w = 2.0 * zeta / delay  # the servo's bandwidth: an equivalent delay 2 zeta / w of 30-120 ms
        p.after.append(LinearFilter([2.0 * zeta * w, w * w], [1.0, 2.0 * zeta * w, w * w]))
        return p
    if effect == "nonlinear_gain":  # rel: the largest relative departure from the unit slope up to 1-1.5 top
        span = top * rng.uniform(1.0, 1.5)
        if shape == "quadrature_residual_detector":
            rel = float(np.interp(m, [0, 1], [0.03, 0.12]))
            ratio = rng.uniform(0.6, 1.5)  # q / b: the slope rises toward sqrt(1 + ratio^2) times its value at zero
            b = optimize.brentq(lambda b: largest_deviation(detector_map(b, ratio * b), span) - rel, 1e-3 * span, 1e5 * span)
            p.after.append(StaticMap(detector_map(b, ratio * b)))
            return p
        kappa, rel = rng.uniform(-0.3, 1.0), float(np.interp(m, [0, 1], [0.06, 0.13]))  # edge kappa sigma below the centre
        sigma = optimize.brentq(lambda s: largest_deviation(knife_edge_map(kappa * s, s), span) - rel, 0.05 * span, 1e5 * span)
        p.after.append(StaticMap(knife_edge_map(kappa * sigma, sigma)))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.02]) * rng.choice([-1, 1]))
        if shape == "latent_heat_zero":
            tau, where, width, latent = rng.uniform(20.0, 60.0), rng.uniform(0.3, 0.7), rng.uniform(0.3, 1.0), \
                rng.uniform(4.0, 15.0)

            def zero(t, f, T, k=k, tau=tau, q=where, w=width, lat=latent):
                melt = float(T.min() + q * (T.max() - T.min()))  # a melting range the record visits
                return 1.5 * k * (latent_body(t, T, tau, melt, w, lat) - T_REF_C)
            p.extra.append(zero)
            return p
        tau, share = rng.uniform(20.0, 60.0), rng.uniform(0.3, 0.8)
        p.extra.append(lambda t, f, T, k=k, tau=tau, s=share: annealing_zero(t, T, k, tau, s))
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.002, 0.01]))
        if shape == "shear_lag_span":
            l0 = rng.uniform(1.5, 4.0)
            slope = (ShearLagSpan.transfer(l0 * 1.001) - ShearLagSpan.transfer(l0)) / (0.001 * ShearLagSpan.transfer(l0))
            p.after.append(ShearLagSpan(l0, 6.0 * a / slope))  # d ln(span) / dT = -3 a at T_ref
            return p
        h = rng.uniform(0.05, 0.07)
        p.after.append(HygroscopicSpan(6.0 * a / h * float(rng.choice([-1, 1])), h, rng.uniform(60.0, 300.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.08]) * rng.choice([-1, 1]))
        if shape == "compressor_ground_loop":
            shift = compressor_zero(rng, 0.5 * size)
            p.extra.append(lambda t, f, T, u=shift: u(t - t[0]))
            return p
        zero = cavity_zero(rng, 0.5 * abs(size), rng.uniform(30.0, 150.0))
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        f0 = rng.uniform(18.0, 45.0)
        zeta = float(np.interp(m, [0, 1], [0.06, 0.015])) * rng.uniform(0.8, 1.2)
        if shape == "non_collocated_mode":
            p.after.append(LinearFilter(*non_collocated_mode(f0, zeta, rng.uniform(1.3, 3.0))))
            return p
        p.after.append(LinearFilter(*absorber_mode(f0, 0.5 * zeta, rng.uniform(0.02, 0.08), rng.uniform(0.85, 1.1),
                                                   rng.uniform(0.01, 0.04))))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "slip_weakening_band":
            strong, dc = rng.uniform(1.5, 2.5), rng.uniform(0.1, 0.6)
            p.before.append(ForcePath(lambda t, x, r=r, s=strong, dc=dc: slip_weakening_play(x, s * r, r, dc)))
            return p
        beta, v0, tau = rng.uniform(0.2, 0.5), rng.uniform(0.5, 2.0), rng.uniform(0.02, 0.05)
        p.before.append(ForcePath(lambda t, x, r=r, b=beta, v=v0, ta=tau: log_rate_band(t, x, r, b, v, ta)))
        return p
    if effect == "thermo_rheological":
        if shape == "distributed_activation":
            b, z = float(np.interp(m, [0, 1], [0.1, 0.28])), special.ndtri((np.arange(7) + 0.5) / 7.0)
            slopes = np.maximum(b * (1.0 + rng.uniform(0.3, 0.6) * z), 0.0)
            return Parts("burgers", GrainClocks(c, slopes, np.full(7, 1.0 / 7.0)), core_changed=True)
        up, b = rng.uniform(10.0, 40.0), float(np.interp(m, [0, 1], [0.19, 0.21]))
        return Parts("burgers", AsymmetricClock(c, b, up, up * rng.uniform(3.0, 8.0)), core_changed=True)
    if effect == "mullins_softening":
        d = float(np.interp(m, [0, 1], [0.03, 0.08]))
        p.before.append(ForcePath(lambda t, x, d=d: x * (1.0 + d * np.maximum.accumulate(x) / FORCE_MAX_N)))
        return p
    if effect == "mux_charge_injection":
        period = rng.uniform(0.5, 2.0)
        p.extra.append(mux_glitches(period, rng.uniform(0.0, period), float(np.interp(m, [0, 1], [0.04, 0.1])),
                                    rng.uniform(0.01, 0.04)))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["stefan_squeeze_flow", "ratchetting_flow"],
    "delayed_elasticity": ["fung_kelvin", "pneumatic_kelvin"],
    "hysteresis": ["takacs_force", "mindlin_microslip_voltage"],
    "sensor_lag": ["slew_limited_amplifier", "force_balance_servo"],
    "nonlinear_gain": ["quadrature_residual_detector", "knife_edge_beam"],
    "thermal_drift": ["latent_heat_zero", "annealing_ratchet_zero"],
    "thermal_sensitivity": ["shear_lag_span", "hygroscopic_span"],
    "offset_drift": ["compressor_ground_loop", "ventilated_cavity"],
    "resonance": ["non_collocated_mode", "absorber_split_mode"], "friction": ["slip_weakening_band", "log_rate_band"],
    "thermo_rheological": ["distributed_activation", "asymmetric_lag_clock"],
}
PAIRS = (("viscous_flow", "hysteresis"), ("delayed_elasticity", "friction"), ("sensor_lag", "offset_drift"),
         ("nonlinear_gain", "thermo_rheological"), ("thermal_sensitivity", "resonance"), ("thermal_drift", "sensor_lag"))
OUTSIDE = ("mullins_softening", "mux_charge_injection")
RATES = (230.0, 420.0, 610.0, 880.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split N", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.2e-3, 2.8e-3), jitter=0.3,
                   gap_s=(0.15, 2.5))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
