"""Independent split Y for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split Y is an untouched held-out set: written blind to the engine it measures (to how it detects and fits anything),
run once, never used to choose anything. Every name of the catalogue is hidden in two shapes that neither the
registry's families (``polyforce_ros/sim/truths.py``) nor splits A to X use:

* a core leaking a dense suspension of hard particles (packing 0.50-0.545) whose viscosity thickens continuously
  with the force (Wyart-Cates: frictional contacts, exp(-F* / F) of them, onset F* 0.5-2.5 N, jam at 0.57-0.59
  instead of 0.64; 2-3.5 times the plain fluidity of 1/30000-1/6000 V/(N s) at light loads), or a core leaking an
  oil thickened by a long-chain polymer that the leak's shear breaks (the viscosity falling with the dissipated work
  toward the base oil's, 1/2-1/4 of it, over the work that 100-400 s of flow under 3 N dissipate; 0.6-1 times the
  plain fluidity at first); neither ever recovers;
* a Kelvin unit damped by a magnet in a copper sleeve (eddy currents: the damping falls with the overlap as the unit
  creeps, to 25-50 % of its rest value at 9 N; 1-15 s at rest), or a hydrogel pad whose water leaves and returns
  through a semipermeable skin against the gel's Flory-Huggins osmotic pressure (polymer fraction 0.05-0.15, chi
  0.35-0.48, 15-35 % strain at 3-5 N: stiffening as it dehydrates; 2-20 s at rest); both settle at 3-20 % of the
  instantaneous response (the pad at 3-5 N);
* a printed lattice whose struts touch once the core's deformation passes 15-45 % of the range and then carry
  25-50 % of each further deformation through their contacts' elastic shear until they slide (no pull), or a
  read-out plunger coupled by a soft spring and rubbing in a PTFE bearing whose friction follows Bliman and Sorine's
  two-state model in the distance travelled (a break-away hump of 30-80 % more after each reversal, over 0.5-2 % of
  the range); loops of 1-6 % of the range;
* a delta-sigma ADC's low-latency, minimum-phase decimation filter (a Kaiser low-pass made minimum-phase, at 4 kHz:
  a step overshoots by 10-13 %), or a PWM output (the duty set once a period of 2.5-10 ms) decoded through two RC
  stages; 8-100 ms of mean delay;
* a resonator read by slope detection at a fixed drive frequency (the Lorentzian amplitude 1 / sqrt(1 + d^2),
  biased at d = 0.5-1.6 and detuned toward its peak by the load), or an LVDT pushed past its linear stroke (two
  secondaries, a core of 0.6-0.9 of a secondary's length each side, its ends blurred by fringing over 0.05-0.15:
  the ratiometric output compresses as a core end leaves its secondary); 5-16 % at the top of the range;
* the zero set by the thermoelectric voltage of copper leads on the gauges' constantan tabs (the body's junction
  with a lag of 5-20 s against the connector's, which sits 30-70 % toward the room (lag 30-120 s) and the rest
  toward the robot's thermostatted flange), or the zero of a fluid-filled read-out whose fill (lag 10-40 s)
  compresses a trapped gas bubble (Boyle: u / (1 - u), the bubble gone 6-20 degC above the reference: convex);
  0.008-0.03 V/degC at the reference (the junctions' once settled);
* a piezoresistive bridge fed by a constant current near the end of its compliance (the span follows the gauges'
  resistance until the source runs out of voltage 1-4 degC above the reference, beyond which it stays put: a soft
  knee over 0.3-1 degC; lag 5-25 s), or a carbon-filled gauge just above its percolation threshold whose matrix's
  expansion (1.5e-4-2.5e-4 per degC) dilutes the filler (the span as 1 / (phi - phi_c): ever faster as it warms;
  lag 5-30 s); 1.8-3 %/degC at the reference;
* the zero of an amplifier whose stored electrolytic bypass capacitor re-forms its oxide after switch-on (20-300 s
  before the record; a leakage decaying as (1 + t / 2-30 s)^-(0.5-1.1)), or of a read-out in a hygroscopic housing
  (30-120 s) while the room's steam humidifier cycles on its dead band (3-8 %RH about 45-55 %RH: climbing with
  60-200 s toward 65-75 %RH, falling with 100-400 s toward 25-35 %RH); 25-90 mV at most;
* a needle holder's mode (15-45 Hz) damped by a copper fin in a magnet's gap whose eddy currents build up with the
  fin's inductive time constant (0.1-0.6 of 1/omega: part of the damper is a spring at the mode), or a holder on a
  kinematic mount (balls in vee-grooves under a fixed preload) whose balls' micro-slip adds damping in proportion to
  the mode's amplitude (large knocks die faster); the frequency fixed, damping ratio 0.0048-0.026 (the mount's
  0.6-0.9 of that before the micro-slip);
* a Coulomb band of 0.4-3.6 % of the range, the same at every load and always: a needle collar between the
  friction washers of a slip clutch with an axial free play of 0.5-2 bands (within it the force passes in full), or
  a hard slider ploughing its soft liner (0.8 of that band after each reversal, rising by 30-80 % over 0.2-1 N of
  slip as the ridge ahead of it builds);
* a core whose dashpots hold a glycerol-based gel following Cohen and Grest's free-volume law (T0 60-110 degC below
  the reference, v 50-200 K), or an Arrhenius clock on a core that follows the air through its contact with the
  holder, whose conductance grows with the force pressing it (Mikic: (1 + F / 1-4 N)^0.95; lag 30-90 s unloaded);
  1.2-1.5 times 0.2-0.5 per degC at the reference, both on a core soft enough for its clock to show.

It also holds six pairs, two effects outside the catalogue (an MR scanner's switched gradients inducing pulses in the
bridge's leads during imaging sequences, sampled without an anti-alias filter; firmware that keeps the reading in a
signed register that wraps around above 0.45-0.94 times the core's output at 9 N) and four clean records. Profiles: a
needle robot under a force limit (the measured Okamura insertion, ``../shared/data``, ``time_force.csv``, replayed at
0.6-1.6 times its speed and scaled past a limit of 2.5-6 N, at which the advance stops while the tissue relaxes; a
train of synthetic punctures when the data are absent); a robot-held laryngoscope blade (lifts, held views with
corrections and regrips, tremor); and a fruit-firmness penetrometer (skin loading, rupture, flesh, relaxation,
withdrawal). Rates 210, 380, 650 and 930 Hz (a mode at 1000 Hz with knocks that excite it), 1.05-2.45 mV noise,
stamp jitter, gaps, and a sensor on a robot in a sterile-processing room: warming through the record, its
air-conditioning cycling on a thermostat, warm puffs from the autoclaves' doors.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size against its
noise without diagnosing (for a leak on a Zener base, against that bare Zener core).

    .venv/bin/python bench/independent_split_y.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, signal

from independent_split import puncture_train
from polyforce_ros.physics.viscoelastic import Burgers
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (coarse_force, cutter, ease, fit_departure, follow, LeakingCore, LinearFilter, on_clock, Parts,
                       ShapeSplit, SimOnly, sized as sized_over, temp_of, uniform_grid)

SEED0 = 1_730_000  # never a seed of the registry's splits nor of splits A (90000..) to X (1660000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 480.0
HORIZON_S = DURATION_S + 60.0  # what a schedule drawn before the record covers (the record plus its gaps' slack)

sized = functools.partial(sized_over, horizon_s=HORIZON_S)
reach_fit = functools.partial(fit_departure, points=301)


# ----------------------------------------------------------------------------- small tools

# ----------------------------------------------------------------------------- profiles and temperature

def force_capped_insertions(duration_s, rate_hz, rng):
    """A needle robot under a force limit: the measured Okamura insertion (``../shared/data``, ``time_force.csv``)
    replayed at 0.6-1.6 times its speed and scaled to a peak of 1.25-1.9 times the limit (2.5-6 N, drawn per
    insertion). Whenever the force reaches the limit the advance stops for 1-4 s while the tissue relaxes to 65-85 %
    of it (with 0.4-1.5 s); the advance then resumes from where it stopped, the relaxed deficit built back over
    0.5-2 s of advance (after four stops the limit is lifted for that insertion). 4-25 s between insertions; a
    train of synthetic punctures when the data are absent."""
    try:
        tp, fp = profiles.okamura_insertion(peak_n=1.0, rate_hz=rate_hz, pre_s=0.0, post_s=0.5)
    except FileNotFoundError:
        return puncture_train(duration_s, rate_hz, rng)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    h = 1.0 / rate_hz
    i = int(rng.uniform(2.0, 8.0) * rate_hz)
    while i < t.size - int(5.0 * rate_hz):
        speed, cap = rng.uniform(0.6, 1.6), rng.uniform(2.5, 6.0)
        gain = cap * rng.uniform(1.25, 1.9)
        reload_s, stops = rng.uniform(0.5, 2.0), 0
        u, deficit = 0.0, 0.0
        while u < tp[-1] and i < t.size:
            raw = gain * float(np.interp(u, tp, fp))
            value = raw - deficit
            if value >= cap and stops < 4:
                stops += 1
                hold, keep, relax = rng.uniform(1.0, 4.0), rng.uniform(0.65, 0.85), rng.uniform(0.4, 1.5)
                s = np.arange(0.0, hold, h)
                seg = cap * (keep + (1.0 - keep) * np.exp(-s / relax))
                n = min(seg.size, t.size - i)
                f[i:i + n] = seg[:n]
                i += n
                deficit = raw - float(seg[-1])
                continue
            f[i] = value
            i += 1
            u += speed * h
            deficit *= math.exp(-speed * h / reload_s)
        i += int(rng.uniform(4.0, 25.0) * rate_hz)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def laryngoscope_lifts(duration_s, rate_hz, rng):
    """A robot-held laryngoscope blade, intubation after intubation: the blade is lifted in 1.5-4 s to 4-8.5 N and
    held for 8-35 s while the view is corrected (a step of 0.3-1.2 N either way every 1.5-6 s, each eased over
    0.3-0.8 s, kept within 2-9 N), one time in three with a regrip (down to 0.5-1.5 N within 0.3 s, 1-3 s there,
    lifted again over 1-2 s); a hand tremor of 0.02-0.05 N at 8-12 Hz throughout the hold; the blade is released
    in 0.5-1.5 s and rests 4-25 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cut = cutter(t)
    now = rng.uniform(1.0, 6.0)
    while now < duration_s - 6.0:
        lift, level = rng.uniform(1.5, 4.0), rng.uniform(4.0, 8.5)
        seg, s = cut(now, lift)
        f[seg] = level * ease(s / lift)
        now += lift
        end = now + rng.uniform(8.0, 35.0)
        tremor_amp, tremor_hz = rng.uniform(0.02, 0.05), rng.uniform(8.0, 12.0)
        regrip_at = now + rng.uniform(2.0, 6.0) if rng.random() < 1.0 / 3.0 else math.inf
        while now < end:
            if now >= regrip_at:
                regrip_at = math.inf
                low, down, stay, up = rng.uniform(0.5, 1.5), 0.3, rng.uniform(1.0, 3.0), rng.uniform(1.0, 2.0)
                seg, s = cut(now, down)
                f[seg] = level + (low - level) * ease(s / down)
                now += down
                seg, s = cut(now, stay)
                f[seg] = low
                now += stay
                seg, s = cut(now, up)
                f[seg] = low + (level - low) * ease(s / up)
                now += up
                continue
            move, dwell = rng.uniform(0.3, 0.8), rng.uniform(1.5, 6.0)
            new = float(np.clip(level + rng.choice([-1.0, 1.0]) * rng.uniform(0.3, 1.2), 2.0, 9.0))
            seg, s = cut(now, move + dwell)
            f[seg] = (level + (new - level) * ease(s / move)
                      + tremor_amp * np.sin(2.0 * np.pi * tremor_hz * (s + now)))
            level = new
            now += move + dwell
        release = rng.uniform(0.5, 1.5)
        seg, s = cut(now, release)
        f[seg] = level * (1.0 - ease(s / release))
        now += release + rng.uniform(4.0, 25.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def fruit_penetrometer(duration_s, rate_hz, rng):
    """A robot testing fruit firmness with a penetrometer plunger, fruit after fruit: the skin is loaded at
    0.8-5 N/s (stiffening by 0-40 % over the push) until it ruptures at 3-8.5 N, the force dropping within
    10-40 ms to 40-70 % of it; the plunger runs on through the flesh for 1-3 s (a plateau wandering by 5-10 % over
    0.2-0.8 s), stops and holds for 2-8 s while the flesh relaxes by 10-25 % (with 0.5-2 s), and is withdrawn in
    0.2-0.6 s; 3-15 s to the next fruit."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cut = cutter(t)
    now = rng.uniform(1.0, 5.0)
    while now < duration_s - 15.0:
        rate, peak, stiff = rng.uniform(0.8, 5.0), rng.uniform(3.0, 8.5), rng.uniform(0.0, 0.4)
        push = peak / rate / (1.0 + stiff / 2.0)
        seg, s = cut(now, push)
        u = s / push
        f[seg] = peak * (u + stiff * u * u) / (1.0 + stiff)
        now += push
        drop, after = rng.uniform(0.01, 0.04), peak * rng.uniform(0.4, 0.7)
        seg, s = cut(now, drop)
        f[seg] = peak + (after - peak) * ease(s / drop)
        now += drop
        run = rng.uniform(1.0, 3.0)
        seg, s = cut(now, run)
        knots = np.arange(0.0, run + 0.8, rng.uniform(0.2, 0.8))
        wander = np.interp(s, knots, rng.uniform(-1.0, 1.0, knots.size)) * rng.uniform(0.05, 0.1)
        f[seg] = after * (1.0 + wander - wander[0] if wander.size else 1.0)
        now += run
        last = float(f[seg][-1]) if s.size else after
        hold, loss, relax = rng.uniform(2.0, 8.0), rng.uniform(0.1, 0.25), rng.uniform(0.5, 2.0)
        seg, s = cut(now, hold)
        f[seg] = last * (1.0 - loss * (1.0 - np.exp(-s / relax)))
        now += hold
        last = last * (1.0 - loss * (1.0 - math.exp(-hold / relax)))
        out = rng.uniform(0.2, 0.6)
        seg, s = cut(now, out)
        f[seg] = last * (1.0 - ease(s / out))
        now += out + rng.uniform(3.0, 15.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (force_capped_insertions, laryngoscope_lifts, fruit_penetrometer)


def sterile_processing_room(t, rng, step_s=0.5):
    """A sensor on a robot in a sterile-processing room, from 900 s before the record: the room warms from 1-3.5
    degC below the reference by 1-3.5 degC over the record's span as the washers run up; its air-conditioning cycles on
    a thermostat (a dead band of 1-2.5 degC, cooling at 0.006-0.015 degC/s, warming at 0.003-0.01 degC/s); each time
    an autoclave door opens (every 120-360 s) a warm puff of 2-5 degC reaches the robot within 10-30 s and clears
    with 40-120 s. The sensor follows its surroundings with 10-30 s (exact per step
    of ``step_s``)."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-900.0, d + 2.0 * step_s, step_s)
    start, rise = T_REF_C + rng.uniform(-3.5, -1.0), rng.uniform(1.0, 3.5)
    room = start + rise * np.clip((grid + 900.0) / (d + 900.0), 0.0, 1.0)
    band, cool, warm = rng.uniform(1.0, 2.5), rng.uniform(0.006, 0.015), rng.uniform(0.003, 0.01)
    hvac, cooling, swing = 0.0, bool(rng.random() < 0.5), np.empty(grid.size)
    for i in range(grid.size):
        hvac += (-cool if cooling else warm) * step_s
        if hvac <= -band / 2.0:
            cooling = False
        elif hvac >= band / 2.0:
            cooling = True
        swing[i] = hvac
    puffs = np.zeros(grid.size)
    now = -900.0 + rng.uniform(0.0, 300.0)
    while now < d + 60.0:
        size, onset, clear = rng.uniform(2.0, 5.0), rng.uniform(10.0, 30.0), rng.uniform(40.0, 120.0)
        after = np.clip(grid - now, 0.0, None)
        puffs += size * (1.0 - np.exp(-after / (onset / 3.0))) * np.exp(-after / clear) * (grid >= now)
        now += rng.uniform(120.0, 360.0)
    air = room + swing + puffs
    keep = math.exp(-step_s / rng.uniform(10.0, 30.0))
    sensor, _ = signal.lfilter([1.0 - keep], [1.0, -keep], air, zi=[keep * air[0]])
    return np.interp(s, grid, sensor)


# ----------------------------------------------------------------------------- viscous flow

def shear_thickening_suspension(fluidity, packing, frictional_jam, onset_n):
    """x' = A F r(F): a core that leaks a dense suspension of hard particles (packing fraction ``packing``) through
    its bleed channel, its viscosity after Wyart and Cates, (1 - phi / phi_J)^-2 with phi_J = f phi_m + (1 - f) phi_0,
    the share f = exp(-F* / F) of frictional contacts rising with the stress (frictionless jamming at phi_0 = 0.64,
    frictional at ``frictional_jam``, onset F* = ``onset_n``): r(F) is the fluidity relative to its low-force value
    ``fluidity``, so the flow is proportional to the force at light loads and thickens continuously above the onset.
    It never recovers."""
    phi0 = 0.64

    def ratio(force):
        share = np.exp(-onset_n / np.maximum(force, 1e-6))
        jam = share * frictional_jam + (1.0 - share) * phi0
        return ((1.0 - packing / jam) / (1.0 - packing / phi0)) ** 2

    def rule(t, f):
        load = np.maximum(f, 0.0)
        return integrate.cumulative_trapezoid(fluidity * load * ratio(load), t, initial=0.0)
    return rule


def shear_degraded_oil(fluidity, widest, work_scale):
    """x' = A(W) F: a core leaking an oil thickened by a long-chain polymer that the leak's own shear breaks
    (mechanical degradation): the viscosity falls from its fresh value toward the base oil's, 1 / ``widest`` of it, as
    exp(-W / ``work_scale``) of the work W = int F dx the leak has dissipated, so the fluidity rises from ``fluidity``
    toward ``widest`` times it, faster under heavy loads, and never comes back. With Q = int F^2 dt, W solves
    W / R + (1 - 1 / R) W_d (1 - exp(-W / W_d)) = A Q (R = ``widest``, W_d = ``work_scale``)."""
    grid_w = np.concatenate([[0.0], np.geomspace(work_scale * 1e-6, work_scale * 200.0, 4000)])
    spent = grid_w / widest + (1.0 - 1.0 / widest) * work_scale * -np.expm1(-grid_w / work_scale)

    def rule(t, f):
        load = np.maximum(f, 0.0)
        q = integrate.cumulative_trapezoid(load * load, t, initial=0.0)
        work = np.interp(fluidity * q, spent, grid_w)
        now = fluidity / (1.0 / widest + (1.0 - 1.0 / widest) * np.exp(-work / work_scale))
        return integrate.cumulative_trapezoid(now * load, t, initial=0.0)
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def eddy_current_kelvin(t, f, compliance_v_per_n, tau_rest_s, left, step_s=0.005):
    """A Kelvin unit in series with the core, damped by a magnet in a copper sleeve (an eddy-current damper, linear in
    the speed): as the unit creeps, the magnet leaves the sleeve and the damping falls with the overlap, to ``left``
    of its rest value at the deformation 9 N gives (at least half of that), so the creep speeds up toward its end and
    a recovery starts fast and ends slowly. tau(u) u' = C F - u, tau(0) = ``tau_rest_s``, C =
    ``compliance_v_per_n``; exact exponential steps of ``step_s`` at the present damping, from rest."""
    grid, fg = coarse_force(t, f, step_s)
    full = compliance_v_per_n * FORCE_MAX_N
    u, out = 0.0, np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        out[i] = u
        damping = max(1.0 - (1.0 - left) * abs(u) / full, 0.5 * left)
        goal = compliance_v_per_n * fi
        u = goal + (u - goal) * math.exp(-step_s / (tau_rest_s * damping))
    return np.interp(t, grid, out)


def osmotic_gel_pad(t, f, compliance_v_per_n, ref_n, rest_s, phi0, chi, strain_ref, step_s=0.005):
    """A hydrogel pad under the core (polymer fraction ``phi0`` swollen free, Flory-Huggins parameter ``chi``) whose
    water leaves and returns through a semipermeable skin (Starling: a flux proportional to the load's pressure less
    the gel's osmotic pressure): the pad's strain s obeys tau s' = F / F_u - p(s), p the rise of the mixing pressure
    -ln(1 - phi) - phi - chi phi^2 over its free value (phi = phi0 / (1 - s)) per its slope there, so the creep
    stiffens as the gel dehydrates and recovers at rest with ``rest_s``; ``ref_n`` settles at ``strain_ref`` of
    strain and at ``compliance_v_per_n`` times ``ref_n`` of output. Exact exponential steps of ``step_s`` about the
    present slope, from rest."""
    def pressure(phi):
        return -np.log1p(-phi) - phi - chi * phi * phi

    slope0 = (phi0 / (1.0 - phi0) - 2.0 * chi * phi0) * phi0

    def p(s):
        return (pressure(phi0 / (1.0 - s)) - pressure(phi0)) / slope0

    def dp(s):
        phi = phi0 / (1.0 - s)
        return (phi / (1.0 - phi) - 2.0 * chi * phi) * phi / (1.0 - s) / slope0

    unit_n = ref_n / float(p(strain_ref))
    volts = compliance_v_per_n * ref_n / strain_ref
    top = 0.95 * (1.0 - phi0) - 0.02
    grid, fg = coarse_force(t, f, step_s)
    s, out = 0.0, np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        out[i] = s
        k = float(dp(s))
        goal = s + (max(fi, 0.0) / unit_n - float(p(s))) / k
        s = min(max(goal + (s - goal) * math.exp(-step_s * k / rest_s), 0.0), top)
    return volts * np.interp(t, grid, out)


# ----------------------------------------------------------------------------- hysteresis

class LatticeStrutContacts(SimOnly):
    """A printed lattice core whose struts touch once its deformation passes ``gap`` (V of the output): the touching
    struts carry a share ``share`` of each further deformation through their contacts' elastic shear until it
    reaches ``slip`` (V), then slide (Coulomb), and they cannot pull. The output is the deformation less what the
    contacts carry: on loading past the gap the read-out falls behind by ``share`` times ``slip``, on unloading the
    contacts let go and it runs free; below the gap nothing is held. Rate-independent, from rest."""

    def __init__(self, gap, slip, share):
        self.gap, self.slip, self.share = gap, slip, share

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        held, anchor = 0.0, 0.0
        out = np.empty_like(x)
        gap, slip, share = self.gap, self.slip, self.share
        for i, xi in enumerate(x.tolist()):
            z = xi - gap
            if z <= 0.0:
                anchor, held = 0.0, 0.0
            else:
                e = z - anchor
                if e > slip:
                    anchor = z - slip
                    e = slip
                elif e < -slip:
                    anchor = z + slip
                    e = -slip
                held = max(e, 0.0)
            out[i] = xi - share * held
        return out


class PtfeRodBearing(SimOnly):
    """A read-out plunger that follows the core's deformation through a soft coupling spring and rubs in a PTFE
    bearing: the plunger lags the deformation by the friction over the spring. The friction follows Bliman and
    Sorine's two-state model in the distance travelled (rate-independent): two first-order states, reaching
    (1 + ``hump``) and ``hump`` times ``half_width`` (V) with ``lengths`` (V of travel, the second the longer), whose
    difference is the friction: after each reversal it overshoots the sliding value (a break-away hump) and settles
    to it. From rest."""

    def __init__(self, half_width, hump, lengths):
        self.a1, self.a2 = half_width * (1.0 + hump), half_width * hump
        self.l1, self.l2 = lengths

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        dx = np.diff(x, prepend=x[0])
        z1 = z2 = 0.0
        out = np.empty_like(x)
        a1, a2, l1, l2 = self.a1, self.a2, self.l1, self.l2
        for i, (xi, step) in enumerate(zip(x.tolist(), dx.tolist())):
            if step != 0.0:
                way, run = (1.0 if step > 0.0 else -1.0), abs(step)
                z1 += (way * a1 - z1) * -math.expm1(-run / l1)
                z2 += (way * a2 - z2) * -math.expm1(-run / l2)
            out[i] = xi - (z1 - z2)
        return out


# ----------------------------------------------------------------------------- sensor lag

class MinimumPhaseDecimator(SimOnly):
    """A delta-sigma ADC in its low-latency mode: its decimation filter is the minimum-phase version (homomorphic) of a
    Kaiser-window low-pass (beta ``beta``, 6-9) of 3 fs / fc taps, run at the modulator's output rate of 4 kHz: most
    of its weight comes early, a short ringing follows (a step overshoots by 10-13 %). Its cut-off is set for a mean
    (centroid) delay of ``delay_s``. On a 4 kHz grid, from rest."""

    fs = 4000.0

    def __init__(self, delay_s, beta):
        fc = 0.3 / delay_s
        for _ in range(4):
            taps = self.design(fc, beta)
            centroid = float(np.sum(np.arange(taps.size) * taps) / np.sum(taps)) / self.fs
            fc *= centroid / delay_s
        self.taps = self.design(fc, beta)

    def design(self, fc, beta):
        n = int(2 * math.ceil(1.5 * self.fs / fc) + 1)
        lin = signal.firwin(n, min(fc, 0.45 * self.fs), window=("kaiser", beta), fs=self.fs)
        taps = signal.minimum_phase(lin, method="homomorphic")
        return taps / taps.sum()

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu = np.arange(t[0], t[-1] + 1.0 / self.fs, 1.0 / self.fs)
        xu = np.interp(tu, t, x)
        y = signal.fftconvolve(xu - xu[0], self.taps)[:xu.size] + xu[0]
        return np.interp(t, tu, y)


class PwmOutputRc(SimOnly):
    """A sensor module whose output is a pulse-width-modulated line (the duty cycle set from the reading at the start
    of each period of ``period_s`` and held over it), decoded by the DAQ through two RC stages of ``taus``; the
    carrier's ripple left after them is far below the noise and is not simulated (the stages see the period's mean).
    Mean delay: half a period plus both time constants. On a 0.25 ms grid, from rest."""

    def __init__(self, period_s, taus):
        self.period, self.taus = period_s, taus

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        h = 2.5e-4
        tu = np.arange(t[0], t[-1] + h, h)
        starts = t[0] + self.period * np.floor((tu - t[0]) / self.period)
        y = np.interp(starts, t, x)
        for tau in self.taus:
            keep = math.exp(-h / tau)
            y, _ = signal.lfilter([1.0 - keep], [1.0, -keep], y, zi=[keep * y[0]])
        return np.interp(t, tu, y)


# ----------------------------------------------------------------------------- nonlinear gain

def detuned_resonator_flank(rel, reach, detuning0):
    """x read by slope detection: a resonator (a quartz or surface-wave element the core's push detunes) driven at a
    fixed frequency, its amplitude the Lorentzian 1 / sqrt(1 + d^2) of the normalised detuning d = 2 Q df / f,
    biased at ``detuning0`` (0.5-1.6) on its flank and pushed toward the peak (never past 10 % of the bias): the
    amplitude's change scaled to slope 1 at no load, the detuning per volt set for a departure of ``rel`` at
    ``reach`` (as far as the peak allows)."""
    def amplitude(d):
        return 1.0 / np.sqrt(1.0 + d * d)

    slope = detuning0 / (1.0 + detuning0 ** 2) ** 1.5

    def read(x, k):
        d = np.maximum(detuning0 - k * np.asarray(x, dtype=float), 0.1 * detuning0)
        return (amplitude(d) - amplitude(detuning0)) / (k * slope)
    return reach_fit(read, rel, reach, 0.9 * detuning0 / reach)


def lvdt_overtravel(rel, reach, core_half, fringe):
    """x read by an LVDT pushed past its linear stroke: two secondaries (0.1-1.1 and -1.1 to -0.1, in units of a
    secondary's length) beside the primary, a core of half-length ``core_half`` (0.6-0.9) centred at the null, its
    coupling to each secondary the overlap of the core with it, each end blurred by the fringing field over
    ``fringe`` (a logistic of 0.05-0.15): the ratiometric output (A - B) / (A + B) of the core's travel, scaled to
    slope 1 at the null, compressive as an end of the core leaves its secondary; the travel per volt set for a
    departure of ``rel`` at ``reach`` (at most one secondary's length at ``reach``)."""
    z = np.linspace(-1.1, 1.1, 2201)
    dz = z[1] - z[0]
    in_a, in_b = (z >= 0.1), (z <= -0.1)
    travel = np.linspace(0.0, 1.2, 601)
    ratio = np.empty(travel.size)
    for j, d in enumerate(travel.tolist()):
        occ = (1.0 / (1.0 + np.exp(-(z - (d - core_half)) / fringe))) / (1.0 + np.exp(-((d + core_half) - z) / fringe))
        a, b = occ[in_a].sum() * dz, occ[in_b].sum() * dz
        ratio[j] = (a - b) / (a + b)
    slope0 = (ratio[1] - ratio[0]) / (travel[1] - travel[0])

    def read(x, k):
        d = k * np.asarray(x, dtype=float)
        return np.sign(d) * np.interp(np.abs(d), travel, ratio) / (slope0 * k)
    return reach_fit(read, rel, reach, 1.0 / reach)


# ----------------------------------------------------------------------------- thermal drift

def seebeck_junction_zero(t, temp, k_v_per_c, tab_s, share_room, conn_s, flange_c):
    """The zero set by the thermoelectric voltage of the bridge's leads: copper leads meet the gauges' constantan tabs
    at the body (lag ``tab_s``) and at the connector on the robot's flange, which sits ``share_room`` toward the room
    (lag ``conn_s``) and the rest toward the flange's thermostat (``flange_c``): the zero follows the two junctions'
    difference, ``k_v_per_c`` per degC of the room once both have settled (more while the body leads the connector)."""
    tab = follow(t, temp, tab_s)
    conn = share_room * follow(t, temp, conn_s) + (1.0 - share_room) * flange_c
    at_start = (1.0 - share_room) * (T_REF_C - flange_c)
    return k_v_per_c / (1.0 - share_room) * (tab - conn - at_start)


def trapped_bubble_zero(t, temp, k_v_per_c, lag_s, vanish_c):
    """The zero of a fluid-filled read-out with a gas bubble trapped in its fill: the fill (lag ``lag_s``) expands
    into the bubble, whose pressure rises by Boyle's law as 1 / (1 - u) - 1, u the temperature above the reference
    over ``vanish_c`` (6-20 degC, where the bubble would be gone; kept below 0.7): convex, ``k_v_per_c`` per degC at
    the reference, steeper warm and flatter cold."""
    u = np.minimum((follow(t, temp, lag_s) - T_REF_C) / vanish_c, 0.7)
    return k_v_per_c * vanish_c * u / (1.0 - u)


# ----------------------------------------------------------------------------- thermal sensitivity

class ConstantCurrentCompliance(SimOnly):
    """A piezoresistive gauge bridge fed by a constant current near the end of the source's compliance: the output is
    I dR, so the span follows the gauges' resistance, rising ``tc`` per degC of their temperature (lag ``lag_s``),
    until the voltage the source must supply reaches its compliance at ``knee_c`` above the reference; beyond, the
    source is a fixed voltage and the span stops rising (a soft knee over ``soft_c``)."""

    def __init__(self, tc, knee_c, soft_c, lag_s):
        self.tc, self.knee, self.soft, self.lag = tc, knee_c, soft_c, lag_s

    def span(self, dt):
        soft = self.soft
        return dt - soft * np.logaddexp(0.0, (dt - self.knee) / soft)

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        dt = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        gain = 1.0 + self.tc * (self.span(dt) - self.span(np.zeros(1))[0])
        return np.asarray(x, dtype=float) * gain


class PercolationGauge(SimOnly):
    """A carbon-filled polymer gauge just above its percolation threshold: its gauge factor grows as 1 / (phi -
    phi_c), and the matrix's expansion (``alpha`` per degC, linear; lag ``lag_s``) dilutes the filler, phi = phi0 /
    (1 + 3 alpha dT), so the span rises as the gauge warms, faster and faster; phi0 / (phi0 - phi_c) = ``closeness``."""

    def __init__(self, alpha, closeness, lag_s):
        self.alpha, self.r, self.lag = alpha, closeness, lag_s

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        dt = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        dt = np.minimum(dt, 0.8 / (3.0 * self.alpha * (self.r - 1.0)))
        gain = 1.0 / (self.r / (1.0 + 3.0 * self.alpha * dt) - (self.r - 1.0))
        return np.asarray(x, dtype=float) * gain


# ----------------------------------------------------------------------------- offset drift

def reforming_electrolytic(rng, horizon_s=HORIZON_S, step_s=0.1):
    """The zero of an amplifier whose input's aluminium electrolytic bypass capacitor was stored unpowered and
    re-forms its oxide after switch-on (20-300 s before the first sample): its leakage current, flowing through the
    input's bias network, decays as the power law (1 + t / t0)^-n (t0 2-30 s, n 0.5-1.1) (as a function of the
    seconds since the first sample, zero there)."""
    on, t0, n = rng.uniform(20.0, 300.0), rng.uniform(2.0, 30.0), rng.uniform(0.5, 1.1)
    grid = np.arange(0.0, horizon_s + 1.0, step_s)
    leak = (1.0 + (grid + on) / t0) ** -n
    leak -= leak[0]
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, leak)


def humidifier_cycling(rng, horizon_s=HORIZON_S, step_s=0.5):
    """The zero of a read-out in a hygroscopic housing while the room's steam humidifier cycles on its controller's
    dead band (3-8 %RH about 45-55 %RH): on, the humidity climbs toward 65-75 %RH with 60-200 s; off, it falls toward
    25-35 %RH with 100-400 s (a sawtooth of unequal flanks, its period set by the band); the housing takes the water up
    and gives it off with 30-120 s, and the zero follows its water (as a function of the seconds since the first
    sample, zero there). The room's temperature plays no part."""
    point, band = rng.uniform(45.0, 55.0), rng.uniform(3.0, 8.0)
    wet, dry = rng.uniform(65.0, 75.0), rng.uniform(25.0, 35.0)
    keep_on, keep_off = math.exp(-step_s / rng.uniform(60.0, 200.0)), math.exp(-step_s / rng.uniform(100.0, 400.0))
    grid = np.arange(-1200.0, horizon_s + 1.0, step_s)
    rh, on, out = point + rng.uniform(-band, band) / 2.0, bool(rng.random() < 0.5), np.empty(grid.size)
    for i in range(grid.size):
        rh = wet + (rh - wet) * keep_on if on else dry + (rh - dry) * keep_off
        if rh >= point + band / 2.0:
            on = False
        elif rh <= point - band / 2.0:
            on = True
        out[i] = rh
    keep = math.exp(-step_s / rng.uniform(30.0, 120.0))
    water, _ = signal.lfilter([1.0 - keep], [1.0, -keep], out, zi=[keep * out[0]])
    first = float(np.interp(0.0, grid, water))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, water) - first


# ----------------------------------------------------------------------------- resonance

def copper_fin_mode(f0_hz, zeta, lag_ratio):
    """A needle holder's mode (unit gain at rest) damped by a copper fin moving in a magnet's gap: the eddy currents
    build up with the fin's own inductive time constant tau = ``lag_ratio`` / omega, so the damper is a Maxwell
    element c / (1 + s tau) (part of it a spring at the mode), c set for a damping ratio ``zeta`` at the mode:
    (k (1 + s tau) + c s) / (m s^2 (1 + s tau) + k (1 + s tau) + c s). The frequency and the damping do not change."""
    w = 2.0 * math.pi * f0_hz
    tau, k = lag_ratio / w, w * w
    c = 2.0 * zeta * w * (1.0 + lag_ratio ** 2)
    return LinearFilter([k * tau + c, k], [tau, 1.0, k * tau + c, k])


class KinematicMountMode(SimOnly):
    """A needle holder on a kinematic mount (balls in vee-grooves under a fixed preload) whose mode, at ``f0_hz``
    (fixed), is damped by the viscous damping ratio ``zeta`` plus the micro-slip of the balls' contacts (Mindlin: an
    energy per cycle growing as the amplitude cubed, a damping ratio growing with the amplitude a of the mode's
    motion: zeta (1 + ``growth`` a / ``a_ref``)): large knocks die faster than small ones. Unit gain at rest;
    symplectic steps of at most 1/25 of a period on a uniform grid at the median step, from rest."""

    def __init__(self, f0_hz, zeta, growth, a_ref):
        self.w, self.zeta, self.growth, self.a_ref = 2.0 * math.pi * f0_hz, zeta, growth, a_ref

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu, xu, h = uniform_grid(t, x)
        w, zeta, growth, a_ref = self.w, self.zeta, self.growth, self.a_ref
        n = max(1, int(math.ceil(h * w * 25.0 / (2.0 * math.pi))))
        hs = h / n
        speed = np.diff(xu, append=xu[-1]) / h
        y, v = float(xu[0]), 0.0
        out = np.empty(xu.size)
        for i, (xi, vi) in enumerate(zip(xu.tolist(), speed.tolist())):
            out[i] = y
            for j in range(n):
                base = xi + vi * hs * j
                e, de = y - base, v - vi
                a = math.sqrt(e * e + (de / w) ** 2)
                z = zeta * (1.0 + growth * a / a_ref)
                v += hs * (-w * w * e - 2.0 * z * w * de)
                y += hs * v
        return np.interp(t, tu, out)


# ----------------------------------------------------------------------------- friction

def collar_free_play(f, band_n, play_n):
    """The force passed by a needle whose collar sits between two friction washers of a slip clutch with axial free
    play: within the play the collar touches neither and the whole force passes; once it meets a washer, the washer
    holds it (Coulomb, ``band_n``, the same at every load and always) until the force beyond the washer exceeds the
    band, and the clutch slides, carrying the play's window (``play_n`` wide, in the force the core sees) along.
    Started with the play centred on ``f[0]``."""
    f = np.asarray(f, dtype=float)
    lo = float(f[0]) - play_n / 2.0
    hi = lo + play_n
    out = np.empty_like(f)
    for i, fi in enumerate(f.tolist()):
        if fi > hi + band_n:
            hi = fi - band_n
            lo = hi - play_n
        elif fi < lo - band_n:
            lo = fi + band_n
            hi = lo + play_n
        out[i] = min(max(fi, lo), hi)
    return out


def ploughing_liner(f, band_n, growth, length_n):
    """The force passed through a needle guide whose hard slider ploughs its soft liner: sliding one way it pushes up
    a ridge ahead of it, so the Coulomb band rises from ``band_n`` by up to ``growth`` of it as exp over ``length_n``
    of slip (in the force the core sees); reversed, the ridge is behind it and the band starts again from
    ``band_n``. The band depends on the slip since the last reversal only (the same every cycle). Started at
    ``f[0]``."""
    f = np.asarray(f, dtype=float)
    p, way, slid = float(f[0]), 0.0, 0.0
    out = np.empty_like(f)
    for i, fi in enumerate(f.tolist()):
        grown = band_n * (1.0 + growth * -math.expm1(-slid / length_n))
        if fi - p > (grown if way > 0.0 else band_n):
            if way <= 0.0:
                way, slid, grown = 1.0, 0.0, band_n
            move = fi - grown - p
            slid += move
            p += move
        elif p - fi > (grown if way < 0.0 else band_n):
            if way >= 0.0:
                way, slid, grown = -1.0, 0.0, band_n
            move = p - (fi + grown)
            slid += move
            p -= move
        out[i] = p
    return out


class ForcePath(SimOnly):
    """A map of the force history before the core: ``fn(F)``."""

    def __init__(self, fn):
        self.fn = fn

    def forward(self, t_s, x, aux=None, state=None):
        return self.fn(np.asarray(x, dtype=float))


# ----------------------------------------------------------------------------- thermo-rheological

def creeping(c):
    """The core made soft enough for its clock to show: its Kelvin spring at most 20 N/V (the retardation time kept)
    and its flow's viscosity at most 4e4 N s/V."""
    k2 = min(c.k2_n_per_v, 20.0)
    return Burgers(c.k1_n_per_v, k2, min(c.eta1_n_s_per_v, 4e4), c.eta2_n_s_per_v * k2 / c.k2_n_per_v)


class CohenGrestClock(SimOnly):
    """A core whose dashpots hold a glycerol-based gel, its viscosity following Cohen and Grest's free-volume law,
    log10 eta = A - B / (T - T0 + sqrt((T - T0)^2 + 4 v T)) (the liquid-like cells percolating: Arrhenius-like far
    above T0, Vogel-like near it; T0 ``t0_below`` below the reference, v ``v_k`` K), B set for ``b_per_c`` per degC of
    the clock at the reference, on the core's temperature (lag ``lag_s``): the clock runs at eta_ref / eta."""

    def __init__(self, c, b_per_c, t0_below, v_k, lag_s):
        self.c, self.lag = c, lag_s
        self.t0, self.v = T_REF_C + 273.15 - t0_below, v_k
        ref = T_REF_C + 273.15
        probe = np.array([ref - 0.05, ref + 0.05])
        shape = self.shape(probe)
        self.b = b_per_c / (math.log(10.0) * float(shape[1] - shape[0]) / 0.1)
        self.ref = float(self.shape(np.array([ref]))[0])

    def shape(self, kelvin):
        d = kelvin - self.t0
        return 1.0 / (d + np.sqrt(d * d + 4.0 * self.v * kelvin))

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        kelvin = follow(t, temp_of(aux, t.size), self.lag) + 273.15
        rate = 10.0 ** np.clip(self.b * (self.shape(kelvin) - self.ref), -6.0, 6.0)
        return on_clock(self.c, t, np.asarray(x, dtype=float), rate)


class PressedContactClock(SimOnly):
    """A core on an Arrhenius clock exp(b (T_core - T_ref)) whose temperature follows the air through its contact with
    the holder, and the contact's thermal conductance grows with the force pressing it (as (1 + F / ``f_half``)^0.95,
    Mikic's plastic contact; the lag ``lag_s`` unloaded, shorter under load): a loaded core follows the air sooner.
    Exact per coarse step of 0.5 s."""

    def __init__(self, c, b_per_c, lag_s, f_half):
        self.c, self.b, self.lag, self.f_half = c, b_per_c, lag_s, f_half

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        step = 0.5
        grid, fg = coarse_force(t, f, step)
        air = np.interp(grid, t, temp_of(aux, t.size))
        core_t, out = float(air[0]), np.empty(grid.size)
        for i, (ai, fi) in enumerate(zip(air.tolist(), fg.tolist())):
            out[i] = core_t
            tau = self.lag / (1.0 + max(fi, 0.0) / self.f_half) ** 0.95
            core_t = ai + (core_t - ai) * math.exp(-step / tau)
        rate = np.exp(np.clip(self.b * (np.interp(t, grid, out) - T_REF_C), -12.0, 12.0))
        return on_clock(self.c, t, f, rate)


# ----------------------------------------------------------------------------- outside the catalogue

class MriGradientPickup(SimOnly):
    """The EMF that an MR scanner's switched gradients induce in the bridge's leads during imaging (sequences of
    20-90 s, 30-120 s apart): each repetition of ``tr_s`` has two to four trapezoidal lobes of alternating sign, whose
    ramps of 0.2-0.6 ms induce rectangular pulses (the flat tops none), seen through the amplifier's input RC of
    0.5-3 ms with a peak of ``emf_v`` and sampled as recorded (no anti-alias filter for it). Drawn from ``seed``."""

    def __init__(self, emf_v, tr_s, seed):
        self.emf, self.tr, self.seed = emf_v, tr_s, seed

    def forward(self, t_s, x, aux=None, state=None):
        t, v = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        rng = np.random.default_rng(self.seed)
        lobes, ramp, rc = int(rng.integers(2, 5)), rng.uniform(2e-4, 6e-4), rng.uniform(5e-4, 3e-3)
        flat = rng.uniform(0.5, 1.0) * (self.tr * 0.6 / lobes - 2.0 * ramp)
        h = 5e-5
        one = np.zeros(int(round(self.tr / h)))
        for k in range(lobes):
            sign = 1.0 if k % 2 == 0 else -1.0
            a = int((k * self.tr * 0.6 / lobes) / h)
            r, fl = max(1, int(ramp / h)), max(1, int(flat / h))
            one[a:a + r] += sign
            one[a + r + fl:a + 2 * r + fl] -= sign
        keep = math.exp(-h / rc)
        out = np.zeros(t.size)
        now = t[0] + rng.uniform(-60.0, 60.0)
        while now < t[-1]:
            length = rng.uniform(20.0, 90.0)
            sel = (t >= now) & (t < now + length)
            if np.any(sel):
                reps = int(math.ceil(length / self.tr)) + 1
                wave = np.tile(one, reps)
                fine = signal.lfilter([1.0 - keep], [1.0, -keep], wave)
                idx = np.minimum(((t[sel] - now) / h).astype(int), fine.size - 1)
                out[sel] = self.emf * fine[idx] / -math.expm1(-ramp / rc)
            now += length + rng.uniform(30.0, 120.0)
        return v + out


class RegisterOverflow(SimOnly):
    """Firmware that keeps the reading, offset included, in a signed register whose range is +-``limit_v``: a reading
    above the top wraps around to the bottom (two's complement) and comes back when it falls again."""

    def __init__(self, limit_v):
        self.limit = limit_v

    def forward(self, t_s, x, aux=None, state=None):
        v = np.asarray(x, dtype=float)
        return np.mod(v + self.limit, 2.0 * self.limit) - self.limit


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([3e4, 6e3]))))  # V / (N s)
        if shape == "shear_thickening_suspension":
            rule = shear_thickening_suspension(phi * rng.uniform(2.0, 3.5), rng.uniform(0.50, 0.545),
                                               rng.uniform(0.57, 0.59), rng.uniform(0.5, 2.5))
        else:
            a0 = phi * rng.uniform(0.6, 1.0)
            rule = shear_degraded_oil(a0, rng.uniform(2.0, 4.0), a0 * 9.0 * rng.uniform(100.0, 400.0))
        return Parts("zener", LeakingCore.of(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        share = float(np.interp(m, [0, 1], [0.03, 0.2]))  # of the instantaneous response
        if shape == "eddy_current_kelvin":
            a = (share / g0, rng.uniform(1.0, 15.0), rng.uniform(0.25, 0.5))
            p.extra.append(lambda t, f, T, a=a: eddy_current_kelvin(t, f, *a))
            return p
        a = (share / g0, rng.uniform(3.0, 5.0), rng.uniform(2.0, 20.0), rng.uniform(0.05, 0.15), rng.uniform(0.35, 0.48),
             rng.uniform(0.15, 0.35))
        p.extra.append(lambda t, f, T, a=a: osmotic_gel_pad(t, f, *a))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.01, 0.06]))
        if shape == "lattice_strut_contacts":
            share = rng.uniform(0.25, 0.5)
            p.after.append(LatticeStrutContacts(top * rng.uniform(0.15, 0.45), frac * top / share, share))
            return p
        length = top * rng.uniform(0.005, 0.02)
        p.after.append(PtfeRodBearing(frac * top / 2.0, rng.uniform(0.3, 0.8), (length, length * rng.uniform(3.0, 6.0))))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.008, 0.1]))))
        if shape == "minimum_phase_decimator":
            p.after.append(MinimumPhaseDecimator(delay, rng.uniform(6.0, 9.0)))
            return p
        period = float(np.clip(delay * rng.uniform(0.3, 0.7), 0.0025, 0.01))
        rest = max(delay - period / 2.0, 0.4 * delay)
        split = rng.uniform(0.3, 0.7)
        p.after.append(PwmOutputRc(period, (rest * split, rest * (1.0 - split))))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.05, 0.16]))
        if shape == "detuned_resonator_flank":
            p.after.append(StaticMap(detuned_resonator_flank(rel, top, rng.uniform(0.5, 1.6))))
            return p
        p.after.append(StaticMap(lvdt_overtravel(rel, top, rng.uniform(0.6, 0.9), rng.uniform(0.05, 0.15))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.008, 0.03]) * rng.choice([-1, 1]))
        if shape == "seebeck_lead_junctions":
            a = (k, rng.uniform(5.0, 20.0), rng.uniform(0.3, 0.7), rng.uniform(30.0, 120.0),
                 T_REF_C + rng.uniform(-0.5, 0.5))
            p.extra.append(lambda t, f, T, a=a: seebeck_junction_zero(t, T, *a))
            return p
        a = (k, rng.uniform(10.0, 40.0), rng.uniform(6.0, 20.0))
        p.extra.append(lambda t, f, T, a=a: trapped_bubble_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        tc = float(np.interp(m, [0, 1], [0.018, 0.03]))
        if shape == "constant_current_compliance":
            p.after.append(ConstantCurrentCompliance(tc, rng.uniform(1.0, 4.0), rng.uniform(0.3, 1.0),
                                                     rng.uniform(5.0, 25.0)))
            return p
        alpha = rng.uniform(1.5e-4, 2.5e-4)
        p.after.append(PercolationGauge(alpha, tc / (3.0 * alpha), rng.uniform(5.0, 30.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.025, 0.09]) * rng.choice([-1, 1]))
        drift = reforming_electrolytic(rng) if shape == "reforming_electrolytic" else humidifier_cycling(rng)
        zero = sized(drift, size)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.022, 0.006])) * rng.uniform(0.8, 1.2)
        if shape == "copper_fin_damper":
            p.after.append(copper_fin_mode(rng.uniform(15.0, 45.0), zeta, rng.uniform(0.1, 0.6)))
            return p
        p.after.append(KinematicMountMode(rng.uniform(15.0, 45.0), zeta * rng.uniform(0.6, 0.9), rng.uniform(0.5, 2.0),
                                          2.0 / g0))
        return p
    if effect == "friction":
        band = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "clutch_collar_play":
            a = (band, band * rng.uniform(0.5, 2.0))
            p.before.append(ForcePath(lambda x, a=a: collar_free_play(x, *a)))
            return p
        a = (band * 0.8, rng.uniform(0.3, 0.8), rng.uniform(0.2, 1.0))
        p.before.append(ForcePath(lambda x, a=a: ploughing_liner(x, *a)))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.2, 0.5]))
        c = creeping(c)
        if shape == "cohen_grest_gel":
            return Parts("burgers", CohenGrestClock(c, b * rng.uniform(1.2, 1.5), rng.uniform(60.0, 110.0),
                                                    rng.uniform(50.0, 200.0), rng.uniform(5.0, 20.0)),
                         core_changed=True)
        return Parts("burgers", PressedContactClock(c, b * rng.uniform(1.2, 1.5), rng.uniform(30.0, 90.0),
                                                    rng.uniform(1.0, 4.0)), core_changed=True)
    if effect == "mri_gradient_pickup":
        p.outer.append(MriGradientPickup(float(np.interp(m, [0, 1], [0.03, 0.08])), rng.uniform(0.02, 0.08),
                                         int(rng.integers(1 << 30))))
        return p
    if effect == "register_overflow":
        p.outer.append(RegisterOverflow(top * float(np.interp(m, [0, 1], [0.85, 0.5])) * rng.uniform(0.9, 1.1)))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["shear_thickening_suspension", "shear_degraded_oil"],
    "delayed_elasticity": ["eddy_current_kelvin", "osmotic_gel_pad"],
    "hysteresis": ["lattice_strut_contacts", "ptfe_rod_bearing"],
    "sensor_lag": ["minimum_phase_decimator", "pwm_output_rc"],
    "nonlinear_gain": ["detuned_resonator_flank", "lvdt_overtravel"],
    "thermal_drift": ["seebeck_lead_junctions", "trapped_bubble_fill"],
    "thermal_sensitivity": ["constant_current_compliance", "percolation_gauge"],
    "offset_drift": ["reforming_electrolytic", "humidifier_cycling"],
    "resonance": ["copper_fin_damper", "kinematic_mount_microslip"],
    "friction": ["clutch_collar_play", "ploughing_liner"],
    "thermo_rheological": ["cohen_grest_gel", "pressed_contact_clock"],
}
PAIRS = (("viscous_flow", "sensor_lag"), ("delayed_elasticity", "friction"), ("hysteresis", "thermal_drift"),
         ("nonlinear_gain", "offset_drift"), ("resonance", "thermal_sensitivity"),
         ("thermo_rheological", "hysteresis"))
OUTSIDE = ("mri_gradient_pickup", "register_overflow")
RATES = (210.0, 380.0, 650.0, 930.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split Y", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.85),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=sterile_processing_room,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.05e-3, 2.45e-3), jitter=0.33,
                   gap_s=(0.25, 2.3))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
