"""Independent split Z for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split Z is an untouched held-out set: written blind to the engine it measures (to how it detects and fits anything),
run once, never used to choose anything. Every name of the catalogue is hidden in two shapes that neither the
registry's families (``polyforce_ros/sim/truths.py``) nor splits A to Y use:

* a core leaking through its grain structure by two creep mechanisms at once (diffusional creep linear in the force,
  0.5-0.9 times the plain fluidity of 1/30000-1/6000 V/(N s), plus dislocation creep as the force to the power 3-5,
  equal to it at 3-6 N), or a core leaking past a face gasket whose slot the load itself squeezes shut (Reynolds: the
  flow as the force times the cube of the gap, the gap closing linearly to nothing at 15-30 N; 2.5-4.5 times the plain
  fluidity at light loads, its flow largest at a quarter of the closing force); neither ever recovers;
* a Kelvin unit whose dashpot oil is pressurised by the load (Barus: its viscosity, and so the retardation time of
  0.5-6 s at rest, grows 1.5-4 fold at 9 N: loaded creep slows, recovery at rest is quick), or a Kelvin unit whose
  dashpot plunger enters a tapered cup (the annular gap narrows as it creeps, the damping rising as the inverse cube
  of the gap, 2.4-8 times at the deformation 9 N gives; 1-8 s at rest: creep slowing toward its end, recovery
  starting slowly); both settle at 3-20 % of the instantaneous response;
* a read-out whose reference body (an LVDT's coil former) rides in a friction clip that the housing's strain drags
  along (5-15 % of the core's deformation, the clip holding within a band): the reading is the core's deformation
  less the body's, so the loop runs clockwise (above the mean curve on loading, below it on unloading), or an
  inductive read-out through a soft-iron flux path after Coleman and Hodgdon's model (its anhysteretic curve
  stiffening as a cubic by 20-60 % at the top, a reversible slope of 0.1-0.4 of it, the irreversible part
  approaching it at a rate of 6-14 per range: the loop widest at the top); loops of 1-6 % of the range (the
  clip's over the whole loop, the flux path's halfway up);
* a lock-in (carrier) amplifier's output filter of four equal RC stages (24 dB per octave), or a fourth-order
  Legendre-Papoulis (optimum-L) anti-alias low-pass (the steepest monotonic response); 10-100 ms of mean delay;
* a read-out through an anisotropic magnetoresistive bridge with barber poles (h sqrt(1 - h^2) of the field over the
  anisotropy field, compressive), or an optical lever whose Gaussian spot (0.2-0.5 of the half-length wide) runs
  toward the edge of a position-sensitive detector (the centroid of the part still on it: compressive); 6-18 % at the
  top of the range (the detector's at 70 % of it);
* the zero of constantan gauges self-temperature-compensated for another alloy than their flexure's (a linear
  mismatch plus the alloy's apparent-strain cubic, flattest 3-8 degC above the reference, 12-20 degC wide; lag 10-40 s),
  or the null of a carrier read-out whose demodulator's phase moves with its phase-shifter's temperature (0.02-0.05
  rad/degC, the quadrature residual 0.3-1.2 rad off: a sine of the temperature; lag 10-40 s); 0.008-0.03 V/degC at
  the reference;
* an optical read-out whose laser diode runs at a fixed current 1.6-2.2 times its threshold, the threshold growing
  as exp(T / T0) (the span falling ever faster as it warms), or an avalanche photodiode at a fixed bias below its
  breakdown, which rises with temperature (a gain of 2.2-11 at the reference as 1 / (1 - (V / V_br)^n), n 1.5-3:
  the span falling as it warms, rising steeply as it cools); lag 10-40 s, 1.5-3 %/degC at the reference;
* the zero of gauges whose solvent-borne protective coat was brushed on 1-10 min before the record (its shrinkage as
  the solvent diffuses out of a film, Crank's series, 300-3000 s), or of a magnetic read-out near a lift shaft whose
  counterweight's steel moves between 3-6 floors (trips of 4-12 s, 30-150 s apart; the field of a dipole passing at
  0.6-1.5 of its distance per floor); 20-90 mV at most;
* a needle holder's mode (15-45 Hz) behind a firmware notch set for it before a tool change (0.75-0.88 or 1.14-1.3
  of the mode now, quality 1-3), or a preload spring that carries 60-90 % of the load beside a stiff path and surges
  (its fixed-free standing wave: the first at 15-45 Hz, its odd harmonics above); damping ratio 0.0048-0.03 (the
  spring's 0.7 of that), the frequencies fixed;
* a Coulomb band of 0.4-3.6 % of the range, the same at every load and always: a needle feed through a one-way
  roller clutch and a friction brake (it overruns with 5-15 % of the band while the force rises and the brake holds
  the whole band while it falls), or a magnetic hysteresis brake on the needle feed (the band reverses over 0.1-0.4 N
  of force travel after each reversal, as a tanh);
* a core (soft enough for its clock to show) whose dashpots follow the Avramov-Milchev law (log viscosity as (Tg /
  T)^a, a 2-6, Tg 30-70 degC below the reference), or a supramolecular core whose hydrogen-bonded stickers' lifetime
  is Arrhenius (60-80 % of the clock's slope) and whose bound fraction (75-90 % at the reference) falls as it warms
  (van 't Hoff; the clock as its power -2..-3); 1.2-1.5 times 0.2-0.5 per degC at the reference, lag 5-20 s.

It also holds six pairs, two effects outside the catalogue (a DAQ whose watchdog resets it every 40-150 s and whose
firmware fills the 0.3-1.5 s of each reset with zeros; a 16-bit stream of which 0.2-1.5 % of the packets arrive
with their bytes swapped) and four clean records. Profiles: a needle inserted and retracted through the measured
Okamura insertion (``../shared/data``, ``time_force.csv``, at 0.6-1.5 times its speed, a hold while the tissue
relaxes, a retraction along the measured curve reversed at 30-60 % of it; a train of synthetic punctures when the
data are absent); a rehabilitation robot's sets of pushes (minimum-jerk, the effort falling as the patient tires);
and a suturing robot tying knots (throws of rising tension, some slipping, with light needle passes between).
Rates 320, 510, 680 and 770 Hz (a mode at 1000 Hz with knocks that excite it), 0.95-2.35 mV noise, stamp jitter,
gaps, and a sensor on a bench by a sunlit window: clouds passing, the room's air-conditioning swinging.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size against its
noise without diagnosing (for a leak on a Zener base, against that bare Zener core).

    .venv/bin/python bench/independent_split_z.py [--json out.json] [--workers 1] [--stride 1] [--check]
"""
from __future__ import annotations

import functools
import math

import numpy as np
from scipy import integrate, signal
from scipy.special import ndtr

from independent_split import puncture_train
from polyforce_ros.physics.viscoelastic import Burgers
from polyforce_ros.sim import profiles
from polyforce_ros.sim.truths import StaticMap
from split_kit import (band_play, coarse_force, cutter, ease, fit_departure, follow, LeakingCore, LinearFilter,
                       on_clock, Parts, ShapeSplit, SimOnly, sized as sized_over, temp_of)

SEED0 = 1_800_000  # never a seed of the registry's splits nor of splits A (90000..) to Y (1730000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 480.0
HORIZON_S = DURATION_S + 60.0  # what a schedule drawn before the record covers (the record plus its gaps' slack)

sized = functools.partial(sized_over, horizon_s=HORIZON_S)
reach_fit = functools.partial(fit_departure, points=301)


# ----------------------------------------------------------------------------- small tools

# ----------------------------------------------------------------------------- profiles and temperature

def insert_retract_okamura(duration_s, rate_hz, rng):
    """A needle inserted and retracted, site after site: the measured Okamura insertion (``../shared/data``,
    ``time_force.csv``) replayed at 0.6-1.5 times its speed and scaled to a 2.5-8.5 N peak; held 2-6 s while the
    tissue relaxes to 60-85 % of the last force (with 0.5-2 s); then retracted along the measured curve played
    backwards at 30-60 % of its force (the shaft's friction pulling out; the switch eased over 0.1-0.3 s); 4-20 s to
    the next site. A train of synthetic punctures when the data are absent."""
    try:
        tp, fp = profiles.okamura_insertion(peak_n=1.0, rate_hz=rate_hz, pre_s=0.0, post_s=0.0)
    except FileNotFoundError:
        return puncture_train(duration_s, rate_hz, rng)
    fp = np.clip(fp, 0.0, None)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cut = cutter(t)
    now = rng.uniform(2.0, 8.0)
    while now < duration_s - 10.0:
        speed, peak = rng.uniform(0.6, 1.5), rng.uniform(2.5, 8.5)
        length = tp[-1] / speed
        seg, s = cut(now, length)
        f[seg] = peak * np.interp(s * speed, tp, fp)
        now += length
        last = peak * float(fp[-1])
        hold, keep, relax = rng.uniform(2.0, 6.0), rng.uniform(0.6, 0.85), rng.uniform(0.5, 2.0)
        seg, s = cut(now, hold)
        f[seg] = last * (keep + (1.0 - keep) * np.exp(-s / relax))
        now += hold
        held = last * (keep + (1.0 - keep) * math.exp(-hold / relax))
        share, back, switch = rng.uniform(0.3, 0.6), rng.uniform(0.6, 1.5), rng.uniform(0.1, 0.3)
        length = tp[-1] / back
        seg, s = cut(now, length)
        pull = share * peak * np.interp(tp[-1] - s * back, tp, fp)
        w = ease(s / switch)
        f[seg] = (1.0 - w) * held + w * pull
        now += length + rng.uniform(4.0, 20.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def rehab_pushes(duration_s, rate_hz, rng):
    """A rehabilitation robot's handle pushed in sets: 6-12 pushes a set, each a minimum-jerk rise of 0.8-2 s, a hold
    of 0.5-2 s with a tremor of 0.05-0.15 N at 5-9 Hz, a fall of 0.8-2 s and 0.5-2 s apart; the first push of a set
    reaches 4-8.5 N and each next one 3-10 % less (fatigue); 15-45 s of rest between sets."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cut = cutter(t)
    now = rng.uniform(1.0, 6.0)
    while now < duration_s - 8.0:
        level, fade = rng.uniform(4.0, 8.5), rng.uniform(0.03, 0.1)
        for _ in range(int(rng.integers(6, 13))):
            rise, hold, fall = rng.uniform(0.8, 2.0), rng.uniform(0.5, 2.0), rng.uniform(0.8, 2.0)
            seg, s = cut(now, rise)
            f[seg] = level * ease(s / rise)
            now += rise
            amp, hz = rng.uniform(0.05, 0.15), rng.uniform(5.0, 9.0)
            seg, s = cut(now, hold)
            f[seg] = level + amp * np.sin(2.0 * np.pi * hz * s)
            now += hold
            end = level + amp * math.sin(2.0 * math.pi * hz * hold)
            seg, s = cut(now, fall)
            f[seg] = end * (1.0 - ease(s / fall))
            now += fall + rng.uniform(0.5, 2.0)
            level *= 1.0 - fade
        now += rng.uniform(15.0, 45.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def knot_tying(duration_s, rate_hz, rng):
    """A suturing robot tying knots: 3-5 throws a knot, each a tension rising over 0.4-1.2 s (faster toward its end)
    to 2-7 N; in half the throws the knot slips once on the way (10-30 % lost within 50 ms, then taken up again);
    held 0.3-1.5 s and released in 0.2-0.5 s; 1-3 s between throws; between knots (8-30 s) the needle passes the
    tissue with a bump of 0.3-1 N over 1-2 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    cut = cutter(t)
    now = rng.uniform(1.0, 6.0)
    while now < duration_s - 12.0:
        for _ in range(int(rng.integers(3, 6))):
            rise, top = rng.uniform(0.4, 1.2), rng.uniform(2.0, 7.0)
            seg, s = cut(now, rise)
            u = s / rise
            shape = ease(u) ** 1.5
            if rng.random() < 0.5:
                at, loss = rng.uniform(0.3, 0.8), rng.uniform(0.1, 0.3)
                dip = loss * np.clip((u - at) / (0.05 / rise), 0.0, 1.0) * np.clip(1.0 - (u - at) / 0.4, 0.0, 1.0)
                shape = shape * (1.0 - dip)
            f[seg] = top * shape
            now += rise
            hold = rng.uniform(0.3, 1.5)
            seg, s = cut(now, hold)
            f[seg] = top
            now += hold
            release = rng.uniform(0.2, 0.5)
            seg, s = cut(now, release)
            f[seg] = top * (1.0 - ease(s / release))
            now += release + rng.uniform(1.0, 3.0)
        gap = rng.uniform(8.0, 30.0)
        bump, width = rng.uniform(0.3, 1.0), rng.uniform(1.0, 2.0)
        seg, s = cut(now + 0.3 * gap, width)
        f[seg] = bump * np.sin(np.pi * s / width) ** 2
        now += gap
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (insert_retract_okamura, rehab_pushes, knot_tying)


def sunlit_window(t, rng, step_s=0.5):
    """A sensor on a bench by a sunlit window, from 600 s before the record: the room drifts by -1 to 2 degC over the
    record from 1-3.5 degC below the reference; its air-conditioning swings it by 0.3-1 degC with a period of
    200-600 s; the sun warms the bench toward 3-7 degC above the room (with 40-120 s) while it shines (60-240 s at a
    time) and the bench cools back (with 60-180 s) while a cloud passes (40-180 s). The sensor follows the bench's air
    with 10-30 s (exact per step of ``step_s``)."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(-600.0, d + 2.0 * step_s, step_s)
    room = T_REF_C + rng.uniform(-3.5, -1.0) + rng.uniform(-1.0, 2.0) * np.clip(grid / d, 0.0, 1.0)
    room = room + rng.uniform(0.3, 1.0) * np.sin(2.0 * np.pi * grid / rng.uniform(200.0, 600.0) + rng.uniform(0, 6.3))
    gain, warm, cool = rng.uniform(3.0, 7.0), rng.uniform(40.0, 120.0), rng.uniform(60.0, 180.0)
    sun, shining = np.empty(grid.size), bool(rng.random() < 0.5)
    switch_at, heat = grid[0] + rng.uniform(0.0, 60.0), 0.0
    for i, g in enumerate(grid.tolist()):
        if g >= switch_at:
            shining = not shining
            switch_at = g + (rng.uniform(60.0, 240.0) if shining else rng.uniform(40.0, 180.0))
        heat = (gain + (heat - gain) * math.exp(-step_s / warm)) if shining else heat * math.exp(-step_s / cool)
        sun[i] = heat
    air = room + sun
    keep = math.exp(-step_s / rng.uniform(10.0, 30.0))
    sensor, _ = signal.lfilter([1.0 - keep], [1.0, -keep], air, zi=[keep * air[0]])
    return np.interp(s, grid, sensor)


# ----------------------------------------------------------------------------- viscous flow

def diffusion_dislocation_creep(fluidity, cross_n, exponent):
    """x' = A F (1 + (F / F_x)^(n - 1)): a core creeping by two mechanisms at once, diffusional (Nabarro-Herring /
    Coble) creep linear in the force with the fluidity A = ``fluidity``, and dislocation (power-law) creep as the force
    to the power n = ``exponent`` (3-5), the two equal at F_x = ``cross_n``. It never recovers."""
    def rule(t, f):
        load = np.maximum(f, 0.0)
        return integrate.cumulative_trapezoid(fluidity * load * (1.0 + (load / cross_n) ** (exponent - 1.0)), t,
                                              initial=0.0)
    return rule


def gasket_slot_leak(fluidity, closing_n):
    """x' = A F (1 - F / F_c)^3: a core leaking past a face gasket whose slot the load squeezes shut (the gap closing
    linearly with the force to nothing at F_c = ``closing_n``, the flow through it as the pressure times the cube of
    the gap, Reynolds), A = ``fluidity`` at light loads: the flow largest at F_c / 4, never reversing, never
    recovering."""
    def rule(t, f):
        load = np.clip(f, 0.0, 0.95 * closing_n)
        return integrate.cumulative_trapezoid(fluidity * load * (1.0 - load / closing_n) ** 3, t, initial=0.0)
    return rule


# ----------------------------------------------------------------------------- delayed elasticity

def pressurised_oil_kelvin(t, f, compliance_v_per_n, tau_rest_s, growth_at_top, step_s=0.005):
    """A Kelvin unit in series with the core whose dashpot oil is pressurised by the load on the housing: its viscosity
    follows Barus's law, exp(alpha p), so the retardation time grows from ``tau_rest_s`` at rest by
    ``growth_at_top`` at 9 N (tau(F) = tau0 growth^(F / 9 N)): loaded creep slows, recovery at rest is quick.
    tau(F) u' = C F - u, C = ``compliance_v_per_n``; exact exponential steps of ``step_s``, from rest."""
    grid, fg = coarse_force(t, f, step_s)
    log_growth = math.log(growth_at_top) / FORCE_MAX_N
    u, out = 0.0, np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        out[i] = u
        tau = tau_rest_s * math.exp(log_growth * min(max(fi, 0.0), 1.5 * FORCE_MAX_N))
        goal = compliance_v_per_n * fi
        u = goal + (u - goal) * math.exp(-step_s / tau)
    return np.interp(t, grid, out)


def tapered_cup_kelvin(t, f, compliance_v_per_n, tau_rest_s, closing, step_s=0.005):
    """A Kelvin unit in series with the core whose dashpot plunger enters a tapered cup as the unit creeps: the
    annular gap narrows to 1 - ``closing`` of its rest width at the deformation 9 N gives, and the damping rises as
    the inverse cube of the gap (tau(u) = tau0 / (1 - closing u / u_9)^3): the creep slows toward its end and a
    recovery starts slowly. tau0 = ``tau_rest_s``, C = ``compliance_v_per_n``; exact exponential steps of ``step_s``
    at the present damping, from rest."""
    grid, fg = coarse_force(t, f, step_s)
    full = compliance_v_per_n * FORCE_MAX_N
    u, out = 0.0, np.empty(grid.size)
    for i, fi in enumerate(fg.tolist()):
        out[i] = u
        gap = max(1.0 - closing * abs(u) / full, 0.25)
        goal = compliance_v_per_n * fi
        u = goal + (u - goal) * math.exp(-step_s * gap ** 3 / tau_rest_s)
    return np.interp(t, grid, out)


# ----------------------------------------------------------------------------- hysteresis

class FloatingReferenceClip(SimOnly):
    """A read-out whose reference body (an LVDT's coil former, a capacitive gauge's fixed plate) rides in a friction
    clip on the housing, which the housing's strain drags along by ``share`` of the core's deformation: the body
    follows the housing within +-``half_band`` (V) of it (a play) and the reading is the core's deformation less the
    body's, scaled back by the calibration (1 / (1 - share)). On loading the body lags the housing, so the reading
    runs above the mean curve, and below it on unloading: a clockwise loop of 2 ``half_band`` / (1 - share).
    Rate-independent, started with the body centred."""

    def __init__(self, share, half_band):
        self.share, self.half = share, half_band

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        housing = self.share * x
        body = band_play(housing, self.half, self.half)
        return (x - body) / (1.0 - self.share)


class ColemanHodgdonFlux(SimOnly):
    """An inductive read-out whose flux path is soft iron, magnetised after Coleman and Hodgdon's rate-independent
    model in the drive h = x / ``top``: dB = alpha |dh| (f(h) - B) + g(h) dh, the anhysteretic f(h) = h (1 + ``cubic``
    h^2) and the reversible slope g = ``reversible`` f'(h): the irreversible part approaches f at the rate alpha per
    range (6-14), lagging it by (1 - reversible) f'(h) / alpha, so the loop is widest where f is steepest (the top).
    The reading is x plus ``weight`` top (B - f(h)) (the firmware linearises f). Sub-steps keep alpha |dh| below
    0.1; from B = f(h[0])."""

    def __init__(self, top, alpha, cubic, reversible, weight):
        self.top, self.alpha, self.cubic, self.rev, self.weight = top, alpha, cubic, reversible, weight

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        h = x / self.top
        alpha, cubic, rev = self.alpha, self.cubic, self.rev

        def anh(v):
            return v * (1.0 + cubic * v * v)

        b, prev = anh(float(h[0])), float(h[0])
        out = np.empty_like(h)
        for i, hi in enumerate(h.tolist()):
            dh = hi - prev
            if dh != 0.0:
                n = max(1, int(math.ceil(alpha * abs(dh) / 0.1)))
                step = dh / n
                for j in range(n):
                    v = prev + step * (j + 0.5)
                    b += alpha * abs(step) * (anh(v) - b) + rev * (1.0 + 3.0 * cubic * v * v) * step
                prev = hi
            out[i] = b - anh(hi)
        return x + self.weight * self.top * out


def coleman_hodgdon_weight(frac, alpha, cubic, reversible):
    """The weight that makes the full-range loop of :class:`ColemanHodgdonFlux` ``frac`` of the range wide halfway up
    (h = 0.5: 2 (1 - reversible) f'(0.5) / alpha; wider above)."""
    return frac / (2.0 * (1.0 - reversible) * (1.0 + 0.75 * cubic) / alpha)


# ----------------------------------------------------------------------------- sensor lag

def lockin_four_pole(delay_s):
    """A lock-in (carrier) amplifier's output low-pass: four equal RC stages after the demodulator (24 dB per octave),
    each of a quarter of the mean delay ``delay_s``."""
    tau = delay_s / 4.0
    den = np.poly1d([tau, 1.0]) ** 4
    return LinearFilter([1.0], list(den.coeffs))


def legendre_papoulis4(delay_s):
    """A fourth-order Legendre-Papoulis (optimum-L) anti-alias low-pass: |H(w)|^2 = 1 / (1 + L4(w^2)), L4(x) = 6 x^4 -
    8 x^3 + 3 x^2 (the steepest cut-off with a monotonic pass band), its cut-off set for a mean (DC group) delay of
    ``delay_s``."""
    # 1 + L4(-s^2) in s: 6 s^8 + 8 s^6 + 3 s^4 + 1
    roots = np.roots([6.0, 0.0, 8.0, 0.0, 3.0, 0.0, 0.0, 0.0, 1.0])
    poles = roots[roots.real < 0.0]
    unit_delay = float(np.sum((-1.0 / poles).real))
    wc = unit_delay / delay_s
    den = np.real(np.poly(poles * wc))
    return LinearFilter([float(den[-1])], list(den))


# ----------------------------------------------------------------------------- nonlinear gain

def amr_barber_pole(rel, reach):
    """x read by an anisotropic magnetoresistive bridge with barber poles (its current at 45 degrees to the strip):
    the core's magnet turns the magnetisation by arcsin h, h the field over the anisotropy field, and the bridge gives
    h sqrt(1 - h^2), scaled to slope 1 at no field; h per volt set for a departure of ``rel`` at ``reach``."""
    h_top = math.sqrt(1.0 - (1.0 - rel) ** 2)
    k = h_top / reach

    def read(x):
        h = np.clip(k * np.asarray(x, dtype=float), -0.99, 0.99)
        return h * np.sqrt(1.0 - h * h) / k
    return read


def psd_spot_truncation(rel, reach, spot):
    """x read by an optical lever onto a position-sensitive detector of half-length 1: a Gaussian spot (sigma
    ``spot``, 0.2-0.5) whose centre moves with x, read as the centroid of the light still on the detector (a spot
    running toward the edge loses its far side: compressive), scaled to slope 1 at the centre; the travel per volt set
    for a departure of ``rel`` at ``reach`` (the spot's centre at most 0.95 of the half-length there)."""
    def centroid(d):
        a, b = (-1.0 - d) / spot, (1.0 - d) / spot
        mass = np.maximum(ndtr(b) - ndtr(a), 1e-12)
        pdf = (np.exp(-0.5 * a * a) - np.exp(-0.5 * b * b)) / math.sqrt(2.0 * math.pi)
        return d + spot * pdf / mass

    slope0 = float((centroid(np.array([1e-4])) - centroid(np.array([-1e-4])))[0] / 2e-4)

    def read(x, k):
        d = np.clip(k * np.asarray(x, dtype=float), -1.2, 1.2)
        return centroid(d) / (slope0 * k)
    return reach_fit(read, rel, reach, 0.95 / reach)


# ----------------------------------------------------------------------------- thermal drift

def stc_mismatch_zero(t, temp, k_v_per_c, flat_c, width_c, lag_s):
    """The zero of constantan gauges self-temperature-compensated for another alloy than the flexure's: their
    apparent strain is the expansion mismatch, linear in the temperature, plus the alloy's own apparent-strain curve, a
    cubic whose flat point is ``flat_c`` above the reference and whose curvature is set by ``width_c``: the slope
    ``k_v_per_c`` (1 + ((dT - flat)^2 - flat^2) / width^2), on the gauges' temperature (lag ``lag_s``)."""
    d = follow(t, temp, lag_s) - T_REF_C
    return k_v_per_c * (d + ((d - flat_c) ** 3 + flat_c ** 3) / (3.0 * width_c ** 2) - flat_c ** 2 * d / width_c ** 2)


def carrier_null_phase_zero(t, temp, k_v_per_c, phase_per_c, phase0, lag_s):
    """The null of a carrier-excited read-out (an LVDT, an AC bridge): the quadrature residual at the null, A, is
    rejected by the phase-sensitive demodulator only as well as its reference phase is right, and the reference's
    phase-shifter (ceramic capacitors) turns by ``phase_per_c`` rad per degC of the electronics (lag ``lag_s``), so
    the zero is A (sin(phase0 + b dT) - sin(phase0)), ``phase0`` the error at the reference; A set for
    ``k_v_per_c`` at the reference."""
    d = follow(t, temp, lag_s) - T_REF_C
    amp = k_v_per_c / (phase_per_c * math.cos(phase0))
    return amp * (np.sin(phase0 + phase_per_c * d) - math.sin(phase0))


# ----------------------------------------------------------------------------- thermal sensitivity

class LaserThreshold(SimOnly):
    """An optical read-out whose laser diode runs at a fixed current ``ratio`` times its threshold at the reference;
    the threshold grows as exp(dT / T0) (T0 the diode's characteristic temperature, set for ``tc`` per degC of span
    at the reference: T0 = 1 / (tc (ratio - 1))), so the light, and the span, fall as (ratio - exp(dT / T0)) /
    (ratio - 1), ever faster as it warms (the diode's temperature lagging by ``lag_s``)."""

    def __init__(self, tc, ratio, lag_s):
        self.ratio, self.lag = ratio, lag_s
        self.t0 = 1.0 / (tc * (ratio - 1.0))

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        gain = (self.ratio - np.exp(d / self.t0)) / (self.ratio - 1.0)
        return np.asarray(x, dtype=float) * np.maximum(gain, 0.05)


class ApdFixedBias(SimOnly):
    """An optical read-out through an avalanche photodiode at a fixed bias: its breakdown voltage rises by ``beta`` per
    degC (lag ``lag_s``) and its gain is 1 / (1 - (V / V_br)^n), ``gain0`` at the reference (V / V_br0 set by it),
    so the span falls as it warms and rises steeply as it cools toward breakdown ((V / V_br)^n kept below 0.98)."""

    def __init__(self, gain0, n, beta, lag_s):
        self.gain0, self.n, self.beta, self.lag = gain0, n, beta, lag_s
        self.q0 = 1.0 - 1.0 / gain0  # (V / V_br0)^n

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        d = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        q = np.minimum(self.q0 * (1.0 + self.beta * d) ** -self.n, 0.98)
        return np.asarray(x, dtype=float) / (1.0 - q) / self.gain0


# ----------------------------------------------------------------------------- offset drift

def solvent_coat(rng, horizon_s=HORIZON_S, step_s=0.5):
    """The zero of gauges whose solvent-borne protective coat (a nitrile or acrylic lacquer) was brushed on 60-600 s
    before the first sample: the coat shrinks, and pulls on the gauges, as its solvent diffuses out of the film
    (Crank's series for a plane sheet, 1 - sum 8 / ((2j + 1)^2 pi^2) exp(-(2j + 1)^2 pi^2 s / tau), tau = 4 L^2 / D
    of 300-3000 s: fast at first, then slower and slower) (as a function of the seconds since the first sample,
    zero there)."""
    ago, tau = rng.uniform(60.0, 600.0), rng.uniform(300.0, 3000.0)
    grid = np.arange(0.0, horizon_s + 1.0, step_s)
    age = grid + ago
    lost = np.ones(grid.size)
    for j in range(40):
        odd = (2 * j + 1) ** 2
        lost -= 8.0 / (odd * math.pi ** 2) * np.exp(-odd * math.pi ** 2 * age / tau)
    lost -= lost[0]
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, lost)


def lift_counterweight(rng, horizon_s=HORIZON_S, step_s=0.1):
    """The zero of a magnetic read-out on a robot beside a lift shaft: the counterweight's steel moves between 3-6
    floors in trips of 4-12 s (minimum-jerk), 30-150 s apart, and waits at each; its field at the sensor is that of
    a dipole passing along the shaft, (2 u^2 - 1) / (1 + u^2)^2.5, u its height over its distance to the sensor
    (0.6-1.5 distances per floor, the sensor level with a floor drawn between them). As a function of the seconds
    since the first sample, zero there."""
    floors, per_floor = int(rng.integers(3, 7)), rng.uniform(0.6, 1.5)
    level = rng.uniform(0.0, floors - 1.0)
    grid = np.arange(-200.0, horizon_s + 1.0, step_s)
    height = np.empty(grid.size)
    at, now = float(rng.integers(0, floors)), -200.0 + rng.uniform(0.0, 100.0)
    height[:] = at
    while now < horizon_s:
        to = float(rng.choice([k for k in range(floors) if k != at]))
        trip = rng.uniform(4.0, 12.0) * max(1.0, abs(to - at)) ** 0.5
        sel = grid >= now
        height[sel] = at + (to - at) * ease((grid[sel] - now) / trip)
        at, now = to, now + trip + rng.uniform(30.0, 150.0)
    u = (height - level) * per_floor
    field = (2.0 * u * u - 1.0) / (1.0 + u * u) ** 2.5
    first = float(np.interp(0.0, grid, field))
    return lambda s: np.interp(np.asarray(s, dtype=float), grid, field) - first


# ----------------------------------------------------------------------------- resonance

def notched_mode(f0_hz, zeta, ratio, q):
    """A needle holder's mode at ``f0_hz`` (damping ratio ``zeta``; unit gain at rest) behind the firmware's notch
    (s^2 + wn^2) / (s^2 + wn s / q + wn^2), set for the mode before a tool change and now at ``ratio`` of it: the mode
    rings on, a little shaped by the notch's skirt. Both fixed."""
    w, wn = 2.0 * math.pi * f0_hz, 2.0 * math.pi * f0_hz * ratio
    num = np.polymul([w * w], [1.0, 0.0, wn * wn])
    den = np.polymul([1.0, 2.0 * zeta * w, w * w], [1.0, wn / q, wn * wn])
    return LinearFilter(list(num), list(den))


class PreloadSpringSurge(SimOnly):
    """A helical preload spring that carries ``share`` of the load beside a stiff path and surges: a force entering
    its free end reaches the fixed end as a travelling wave (transit ``T`` = 1 / (4 f0)) reflected with loss, so the
    spring passes (1 + r) F(t - T) - r P(t - 2T) (its modes at f0, 3 f0, 5 f0 ..., r = exp(-pi zeta) for a damping
    ratio ``zeta`` at f0, the same decay rate for every harmonic), and the read-out sees (1 - share) F + share P.
    Unit gain at rest; on a uniform grid of 8 kHz, from rest."""

    fs = 8000.0

    def __init__(self, f0_hz, zeta, share):
        self.lag = max(1, int(round(self.fs / (4.0 * f0_hz))))
        self.r, self.share = math.exp(-math.pi * zeta), share

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        tu = np.arange(t[0], t[-1] + 1.0 / self.fs, 1.0 / self.fs)
        xu = np.interp(tu, t, x) - x[0]
        b = np.zeros(self.lag + 1)
        b[-1] = 1.0 + self.r
        a = np.zeros(2 * self.lag + 1)
        a[0], a[-1] = 1.0, self.r
        p = signal.lfilter(b, a, xu)
        return np.interp(t, tu, (1.0 - self.share) * xu + self.share * p) + x[0]


# ----------------------------------------------------------------------------- friction

def roller_clutch_band(band_n, overrun):
    """The force passed by a needle feed through a one-way roller clutch and a friction brake: while the force rises
    the clutch overruns and only its drag, ``overrun`` of the band, holds it back; while it falls the clutch locks and
    the brake holds the whole band ``band_n`` (Coulomb, the same at every load and always). Started at ``f[0]``."""
    return lambda f: band_play(f, overrun * band_n, band_n)


def hysteresis_brake(f, band_n, reverse_n):
    """The force passed by a needle feed through a magnetic hysteresis brake: a constant drag ``band_n`` (Coulomb,
    speed-independent, the same at every load and always) that reverses as the rotor's magnetisation does, over
    ``reverse_n`` of force travel after each reversal (the drag going from its value at the reversal toward the
    opposite bound as tanh of the travel over ``reverse_n``); the force passed is the force less the drag. Started with
    no drag at ``f[0]``."""
    f = np.asarray(f, dtype=float)
    drag, start, origin, way = 0.0, 0.0, float(f[0]), 0.0
    out = np.empty_like(f)
    prev = float(f[0])
    for i, fi in enumerate(f.tolist()):
        step = fi - prev
        if step != 0.0:
            sense = 1.0 if step > 0.0 else -1.0
            if sense != way:
                way, start, origin = sense, drag, prev
            travel = abs(fi - origin)
            drag = start + (way * band_n - start) * math.tanh(travel / reverse_n)
            prev = fi
        out[i] = fi - drag
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


class AvramovMilchevClock(SimOnly):
    """A core whose dashpots follow the Avramov-Milchev law, log10 eta = A + B (Tg / T)^a (a ``power``, 2-6; Tg
    ``tg_below`` below the reference, in kelvin), B set for ``b_per_c`` per degC of the clock at the reference, on the
    core's temperature (lag ``lag_s``): the clock runs at eta_ref / eta."""

    def __init__(self, c, b_per_c, tg_below, power, lag_s):
        self.c, self.a, self.lag = c, power, lag_s
        ref = T_REF_C + 273.15
        self.tg = ref - tg_below
        self.ref_term = (self.tg / ref) ** power
        self.coef = b_per_c * ref / (power * self.ref_term)  # ln(rate) slope b at the reference

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        kelvin = follow(t, temp_of(aux, t.size), self.lag) + 273.15
        rate = np.exp(np.clip(self.coef * (self.ref_term - (self.tg / kelvin) ** self.a), -12.0, 12.0))
        return on_clock(self.c, t, np.asarray(x, dtype=float), rate)


class SupramolecularClock(SimOnly):
    """A supramolecular core whose network is held by hydrogen-bonded stickers: a sticker's lifetime is Arrhenius
    (``share`` of the clock's slope ``b_per_c`` at the reference) and the bound fraction p = K / (1 + K) (``bound``
    at the reference) falls as it warms (van 't Hoff: ln K falls by h per degC at the reference, as 1 / T), the clock
    running as exp(b_life dT) (p_ref / p)^m (m ``power``, 2-3; h set for the rest of the slope), held within e^+-5. On the core's
    temperature (lag ``lag_s``)."""

    def __init__(self, c, b_per_c, share, bound, power, lag_s):
        self.c, self.lag, self.m = c, lag_s, power
        self.b_life = share * b_per_c
        self.k_ref = bound / (1.0 - bound)
        self.bound = bound
        self.h = (1.0 - share) * b_per_c / (power * (1.0 - bound))

    def forward(self, t_s, x, aux=None, state=None):
        t = np.asarray(t_s, dtype=float)
        dt = follow(t, temp_of(aux, t.size), self.lag) - T_REF_C
        ref = T_REF_C + 273.15
        ln_k = math.log(self.k_ref) - self.h * ref * dt / (ref + dt)
        kk = np.exp(ln_k)
        p = kk / (1.0 + kk)
        log_rate = self.b_life * dt + self.m * np.log(self.bound / p)
        return on_clock(self.c, t, np.asarray(x, dtype=float), np.exp(np.clip(log_rate, -5.0, 5.0)))


# ----------------------------------------------------------------------------- outside the catalogue

class WatchdogZeroFill(SimOnly):
    """A DAQ whose watchdog resets it every 40-150 s (drawn from ``seed``): while it reboots (``gap_s`` times 0.7-1.3)
    the firmware fills the stream with zeros, and the readings resume after."""

    def __init__(self, gap_s, seed):
        self.gap, self.seed = gap_s, seed

    def forward(self, t_s, x, aux=None, state=None):
        t, v = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float).copy()
        rng = np.random.default_rng(self.seed)
        now = t[0] + rng.uniform(5.0, 60.0)
        while now < t[-1]:
            length = self.gap * rng.uniform(0.7, 1.3)
            v[(t >= now) & (t < now + length)] = 0.0
            now += length + rng.uniform(40.0, 150.0)
        return v


class ByteSwappedWords(SimOnly):
    """A 16-bit stream (+-10.24 V, two's complement) sent in packets of 8-32 samples, of which ``share`` arrive with
    each word's two bytes swapped (drawn from ``seed``): those readings land anywhere in the range."""

    lsb = 10.24 / 32768.0

    def __init__(self, share, seed):
        self.share, self.seed = share, seed

    def forward(self, t_s, x, aux=None, state=None):
        v = np.asarray(x, dtype=float)
        rng = np.random.default_rng(self.seed)
        size = int(rng.integers(8, 33))
        code = np.clip(np.round(v / self.lsb), -32768, 32767).astype(np.int64) & 0xFFFF
        swapped = ((code & 0xFF) << 8) | (code >> 8)
        hit = np.repeat(rng.random(v.size // size + 1) < self.share, size)[:v.size]
        out = np.where(hit, swapped, code)
        out = np.where(out >= 32768, out - 65536, out)
        return out.astype(float) * self.lsb


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):
    g0 = c.relaxation().g0_n_per_v
    top = FORCE_MAX_N / g0  # ~ the core's instantaneous output at the top of the range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([3e4, 6e3]))))  # V / (N s)
        if shape == "diffusion_dislocation_creep":
            rule = diffusion_dislocation_creep(phi * rng.uniform(0.5, 0.9), rng.uniform(3.0, 6.0), rng.uniform(3.0, 5.0))
        else:
            rule = gasket_slot_leak(phi * rng.uniform(2.5, 4.5), rng.uniform(15.0, 30.0))
        return Parts("zener", LeakingCore.of(c, rule), core_changed=True)
    if effect == "delayed_elasticity":
        share = float(np.interp(m, [0, 1], [0.03, 0.2]))  # of the instantaneous response
        if shape == "pressurised_oil_kelvin":
            a = (share / g0, rng.uniform(0.5, 6.0), rng.uniform(1.5, 4.0))
            p.extra.append(lambda t, f, T, a=a: pressurised_oil_kelvin(t, f, *a))
            return p
        closing = 1.0 - rng.uniform(2.4, 8.0) ** (-1.0 / 3.0)
        a = (share / g0, rng.uniform(1.0, 8.0), closing)
        p.extra.append(lambda t, f, T, a=a: tapered_cup_kelvin(t, f, *a))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.01, 0.06]))
        if shape == "floating_reference_clip":
            share = rng.uniform(0.05, 0.15)
            p.after.append(FloatingReferenceClip(share, frac * top * (1.0 - share) / 2.0))
            return p
        alpha, cubic, rev = rng.uniform(6.0, 14.0), rng.uniform(0.2, 0.6), rng.uniform(0.1, 0.4)
        p.after.append(ColemanHodgdonFlux(top, alpha, cubic, rev, coleman_hodgdon_weight(frac, alpha, cubic, rev)))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.01, 0.1]))))
        if shape == "lockin_four_pole":
            p.after.append(lockin_four_pole(delay))
            return p
        p.after.append(legendre_papoulis4(delay))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.06, 0.18]))
        if shape == "amr_barber_pole":
            p.after.append(StaticMap(amr_barber_pole(rel, top)))
            return p
        p.after.append(StaticMap(psd_spot_truncation(rel, 0.7 * top, rng.uniform(0.2, 0.5))))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.008, 0.03]) * rng.choice([-1, 1]))
        if shape == "stc_gauge_mismatch":
            a = (k, rng.uniform(3.0, 8.0), rng.uniform(12.0, 20.0), rng.uniform(10.0, 40.0))
            p.extra.append(lambda t, f, T, a=a: stc_mismatch_zero(t, T, *a))
            return p
        a = (k, rng.uniform(0.02, 0.05), rng.uniform(0.3, 1.2) * rng.choice([-1, 1]), rng.uniform(10.0, 40.0))
        p.extra.append(lambda t, f, T, a=a: carrier_null_phase_zero(t, T, *a))
        return p
    if effect == "thermal_sensitivity":
        tc = float(np.interp(m, [0, 1], [0.015, 0.03]))
        if shape == "laser_diode_threshold":
            p.after.append(LaserThreshold(tc, rng.uniform(1.6, 2.2), rng.uniform(10.0, 40.0)))
            return p
        n, beta = rng.uniform(1.5, 3.0), rng.uniform(0.002, 0.004)
        p.after.append(ApdFixedBias(1.0 + tc / (n * beta), n, beta, rng.uniform(10.0, 40.0)))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.02, 0.09]) * rng.choice([-1, 1]))
        zero = sized(solvent_coat(rng) if shape == "solvent_coat_shrinkage" else lift_counterweight(rng), size)
        p.extra.append(lambda t, f, T, u=zero: u(t - t[0]))
        return p
    if effect == "resonance":
        zeta = float(np.interp(m, [0, 1], [0.025, 0.006])) * rng.uniform(0.8, 1.2)
        if shape == "mistuned_notch":
            ratio = rng.uniform(0.75, 0.88) if rng.random() < 0.5 else rng.uniform(1.14, 1.3)
            p.after.append(notched_mode(rng.uniform(15.0, 45.0), zeta, ratio, rng.uniform(1.0, 3.0)))
            return p
        p.after.append(PreloadSpringSurge(rng.uniform(15.0, 45.0), 0.7 * zeta, rng.uniform(0.6, 0.9)))
        return p
    if effect == "friction":
        band = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N) * rng.uniform(0.8, 1.2)
        if shape == "roller_clutch_brake":
            p.before.append(ForcePath(roller_clutch_band(band, rng.uniform(0.05, 0.15))))
            return p
        a = (band, rng.uniform(0.1, 0.4))
        p.before.append(ForcePath(lambda x, a=a: hysteresis_brake(x, *a)))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.2, 0.5]))
        c = creeping(c)
        if shape == "avramov_milchev_clock":
            return Parts("burgers", AvramovMilchevClock(c, b * rng.uniform(1.2, 1.5), rng.uniform(30.0, 70.0),
                                                        rng.uniform(2.0, 6.0), rng.uniform(5.0, 20.0)),
                         core_changed=True)
        return Parts("burgers", SupramolecularClock(c, b * rng.uniform(1.2, 1.5), rng.uniform(0.6, 0.8),
                                                    rng.uniform(0.75, 0.9), rng.uniform(2.0, 3.0),
                                                    rng.uniform(5.0, 20.0)), core_changed=True)
    if effect == "watchdog_zero_fill":
        p.outer.append(WatchdogZeroFill(float(np.interp(m, [0, 1], [0.3, 1.5])), int(rng.integers(1 << 30))))
        return p
    if effect == "byte_swapped_words":
        p.outer.append(ByteSwappedWords(float(np.interp(m, [0, 1], [0.002, 0.015])), int(rng.integers(1 << 30))))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["diffusion_dislocation_creep", "gasket_slot_leak"],
    "delayed_elasticity": ["pressurised_oil_kelvin", "tapered_cup_kelvin"],
    "hysteresis": ["floating_reference_clip", "coleman_hodgdon_flux"],
    "sensor_lag": ["lockin_four_pole", "legendre_papoulis4"],
    "nonlinear_gain": ["amr_barber_pole", "psd_spot_truncation"],
    "thermal_drift": ["stc_gauge_mismatch", "carrier_null_phase"],
    "thermal_sensitivity": ["laser_diode_threshold", "apd_fixed_bias"],
    "offset_drift": ["solvent_coat_shrinkage", "lift_counterweight"],
    "resonance": ["mistuned_notch", "preload_spring_surge"],
    "friction": ["roller_clutch_brake", "hysteresis_brake"],
    "thermo_rheological": ["avramov_milchev_clock", "supramolecular_clock"],
}
PAIRS = (("viscous_flow", "hysteresis"), ("delayed_elasticity", "resonance"), ("sensor_lag", "thermal_drift"),
         ("nonlinear_gain", "friction"), ("thermal_sensitivity", "thermo_rheological"),
         ("offset_drift", "sensor_lag"))
OUTSIDE = ("watchdog_zero_fill", "byte_swapped_words")
RATES = (320.0, 510.0, 680.0, 770.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split Z", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.85),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=sunlit_window,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(0.95e-3, 2.35e-3), jitter=0.28,
                   gap_s=(0.2, 2.2))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
