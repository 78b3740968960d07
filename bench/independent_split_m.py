"""Independent split M for ``polyforce diagnose``: shapes, profiles and rates that no other split uses.

Split M is an untouched held-out set: written before the engine it measures, blind to how it works, run once at its
end, never used to choose anything. Every name of the catalogue is hidden in two shapes that neither the registry's
families (``polyforce_ros/sim/truths.py``) nor splits A to L use:

* a serrated (jerky) flow: slips of a fixed size at random times, a Poisson process whose intensity is proportional to
  the force (Portevin-Le Chatelier-like), or a piezoviscous dashpot whose viscosity grows exponentially with the
  force (Barus: the flow rate F exp(-F / F_p) peaks at F_p = 2.5-6 N);
* creep on a Davidson-Cole spectrum (regularised incomplete gamma P(beta, t / tau0), beta 0.25-0.55, tau0 8-120 s:
  a power-law start and a sharp cut at tau0), or a Kelvin unit whose dashpot is a squeezed oil film (damping as the
  inverse cube of the gap the creep closes, Reynolds: 6-37x slower at the top of the range);
* an endochronic loop on the force before the core (Valanis: a power-law memory kernel (1 + z / z0)^-p in the
  intrinsic time z, the force travelled), or an elastic-plastic bond layer on the bridge voltage (an elastic range,
  then Armstrong-Frederick kinematic hardening, with a yield range that softens as plastic travel accumulates);
* a distributed RC line between the bridge and the ADC (a long resistive trace: 1 / cosh(sqrt(s tau))), or an RC
  low-pass whose resistance is the piezoresistive element's own, falling 3-7x as the load rises;
* an interferometric (Fabry-Perot) read-out biased off quadrature (sin(phi0 +- kappa x) - sin(phi0): compressive
  when the load moves it away from quadrature, S-shaped when it moves it across), or a magnetoresistive bridge
  reading a magnet in the polymer (the field as the inverse cube of the gap);
* a zero that follows the sensor's body temperature behind natural convection (heat flux as dT^1.25: slow for small
  differences), or the temperature at a gauge buried in a thick wall (semi-infinite diffusion, erfc step response,
  d^2 / kappa of 30-240 s);
* a span of the retarded and flowing response only (an entropic rubbery network; the instantaneous, glassy response
  keeps its span), or the share of the force that reaches the sensor past a parallel seal whose stiffness is
  exponential in temperature (load sharing, before the core);
* an offset that follows a battery's discharge curve through the amplifier's supply rejection (an initial sag, a
  plateau, an end-of-charge knee), or one that follows the electronics' own heating as a radio switches on and off
  (a duty-cycled heat source behind a 20-80 s thermal lag);
* a mode whose spring is a viscoelastic (Zener) elastomer mount (frequency and damping set by the mount's relaxation),
  or the organ-pipe modes of a hydraulic load cell's oil line (f, 3f, 5f ... with alternating signs, 4 / ((2n + 1)
  pi), lighter as they rise);
* a Coulomb band that a fan or pump dithers away while it runs (vibration-induced friction reduction, switched on and
  off for 15-90 s), or an O-ring whose squeeze, and so its band, falls as the diaphragm lifts with the load;
* a clock that runs faster while the temperature changes, either way (transient thermal creep: exp(b dT) (1 + g |dT/dt|
  / 0.02 degC/s, at most 10)), or a clock plasticised by water that the polymer loses slowly when warm (an instantaneous
  Arrhenius term less a lagged one, 60-200 s).

It also holds six pairs, two effects outside the catalogue (a span that changes from press to press with the point
of contact, eccentric loading; a GSM handset's 217 Hz TDMA buzz rectified by the amplifier during calls) and four
clean records. Profiles: a robot driving a needle through the measured force-depth curve (``../shared/data``,
``depth_force.csv``: strokes at 1-8 mm/s with pauses in which the tissue relaxes, a train of synthetic punctures when
it is absent), a surgical retractor re-tensioned now and then while the tissue relaxes under it, and a gripper's
pick-and-place cycles (close, lift, a swaying carry, set down, open). Rates 280, 460, 690 and 960 Hz (a mode at 1000
Hz with knocks that excite it), 1-3 mV noise, stamp jitter, gaps, a sensor warmed by an operating lamp (switched on,
moved, sometimes switched off) and cooled by flushes of saline irrigation.

Scored like the other splits (``bench/independent_split.py``). ``--check`` prints each case's effect size
against its noise without diagnosing.

    .venv/bin/python bench/independent_split_m.py [--json out.json] [--workers 1] [--stride 1] [--check]
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
from split_kit import ForcePath, LinearFilter, Parts, ShapeSplit, SimOnly, band_play, coarse, core_output, kelvin

SEED0 = 890_000  # never a seed of the registry's splits nor of splits A (90000..) to L (820000..)
FORCE_MAX_N = 9.0
T_REF_C = 23.0
DURATION_S = 480.0


# ----------------------------------------------------------------------------- profiles and temperature

def min_jerk(t, knots_t, knots_f):
    """A force through ``knots_f`` at ``knots_t`` (increasing), each pair joined by a minimum-jerk move, flat
    beyond the ends."""
    kt, kf = np.asarray(knots_t, dtype=float), np.asarray(knots_f, dtype=float)
    k = np.clip(np.searchsorted(kt, t, side="right") - 1, 0, kt.size - 2)
    u = np.clip((t - kt[k]) / np.maximum(kt[k + 1] - kt[k], 1e-9), 0.0, 1.0)
    return kf[k] + (kf[k + 1] - kf[k]) * u ** 3 * (10.0 - 15.0 * u + 6.0 * u * u)


def needle_robot(duration_s, rate_hz, rng):
    """A robot drives a needle through the measured force-depth curve (Okamura, bovine liver, 48 mm): to 60-100 % of
    its depth in 1-3 strokes at 1-8 mm/s each, pausing 1-6 s between strokes while the tissue relaxes the force to
    55-85 % (time constant 0.5-3 s; restored within 0.3 s once the needle moves again); 0.5-3 s of dwell at the
    end, a retraction at 5-15 mm/s in which the compressive force is gone within 0.5-2 mm, and 3-15 s of rest. Each
    insertion is scaled to a 3-9 N peak. A train of synthetic punctures when ``../shared/data`` is absent."""
    csv = profiles.okamura_csv_path()
    table = None if csv is None else csv.parent / "depth_force.csv"
    if table is None or not table.is_file():
        return puncture_train(duration_s, rate_hz, rng)
    raw = np.loadtxt(table, delimiter=",", ndmin=2)
    depth_mm = 1e3 * np.maximum.accumulate(raw[:, 0]) + 1e-4 * np.arange(raw.shape[0])  # drops kept in file order
    force = raw[:, 1]
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    now = rng.uniform(3.0, 8.0)
    while now < duration_s:
        target = rng.uniform(0.6, 1.0) * depth_mm[-1]
        ends = np.append(np.sort(rng.uniform(0.2, 0.9, int(rng.integers(0, 3)))) * target, target)
        scale = rng.uniform(3.0, 9.0) / max(float(force[depth_mm <= target].max()), 1e-3)
        d0, r0 = 0.0, 1.0
        for i, d1 in enumerate(ends):
            v = rng.uniform(1.0, 8.0)
            seg = (t >= now) & (t < now + (d1 - d0) / v)
            u = t[seg] - now
            r = 1.0 - (1.0 - r0) * np.exp(-u / 0.3)
            f[seg] = scale * np.interp(d0 + v * u, depth_mm, force) * r
            now += (d1 - d0) / v
            r0 = float(r[-1]) if r.size else r0
            pause = rng.uniform(1.0, 6.0) if i < ends.size - 1 else rng.uniform(0.5, 3.0)
            floor, tau = rng.uniform(0.55, 0.85), rng.uniform(0.5, 3.0)
            seg = (t >= now) & (t < now + pause)
            u = t[seg] - now
            r = floor + (r0 - floor) * np.exp(-u / tau)
            f[seg] = scale * float(np.interp(d1, depth_mm, force)) * r
            now += pause
            d0, r0 = d1, (float(r[-1]) if r.size else r0)
        last = scale * float(np.interp(d0, depth_mm, force)) * r0
        out = rng.uniform(0.5, 2.0) / rng.uniform(5.0, 15.0)  # s to lose the compressive force
        seg = (t >= now) & (t < now + out)
        f[seg] = last * (1.0 - (t[seg] - now) / out)
        now += d0 / rng.uniform(5.0, 15.0) + rng.uniform(3.0, 15.0)
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def retractor_tension(duration_s, rate_hz, rng):
    """A surgical retractor held by the tissue: pulled by minimum-jerk moves of 0.3-1.5 s to 1.5-8 N and left
    10-40 s while the tissue relaxes under the held displacement (to 35-70 % of the pull, two time constants of
    1-5 s and 15-60 s), then re-tensioned from where it has relaxed to; one time in five it is released to zero
    (0.3-1 s) and rests 5-20 s."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    f = np.zeros_like(t)
    now, level = rng.uniform(2.0, 8.0), 0.0
    while now < duration_s:
        release = level > 0.0 and rng.random() < 0.2
        move = rng.uniform(0.3, 1.0) if release else rng.uniform(0.3, 1.5)
        target = 0.0 if release else rng.uniform(1.5, 8.0)
        seg = (t >= now) & (t < now + move)
        u = (t[seg] - now) / move
        f[seg] = level + (target - level) * u ** 3 * (10.0 - 15.0 * u + 6.0 * u * u)
        now += move
        hold = rng.uniform(5.0, 20.0) if release else rng.uniform(10.0, 40.0)
        seg = (t >= now) & (t < now + hold)
        u = t[seg] - now
        floor, share = rng.uniform(0.35, 0.7), rng.uniform(0.3, 0.6)
        tau1, tau2 = rng.uniform(1.0, 5.0), rng.uniform(15.0, 60.0)
        relaxed = target * (floor + (1.0 - floor) * (share * np.exp(-u / tau1) + (1.0 - share) * np.exp(-u / tau2)))
        f[seg] = relaxed
        level = float(relaxed[-1]) if relaxed.size else target
        now += hold
    return t, np.clip(f, 0.0, FORCE_MAX_N)


def grasp_cycles(duration_s, rate_hz, rng):
    """A gripper's pick-and-place: the fingers close in 0.1-0.4 s to a grip of 1.5-6 N, settle 0.5-2 s, lifting
    adds 0.5-2.5 N (the object's weight onto the pad) over 0.3-0.8 s, it is carried 2-8 s, set down over 0.3-0.8 s
    and released in 0.1-0.3 s, 3-15 s apart. The object sways at 1.5-4 Hz (10-30 % of its weight, decaying in 1-4
    s) when lifted and when stopped; one grasp in four regrips mid-carry (the grip eases by 30-60 % for 0.3-0.8 s)."""
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    knots_t, knots_f, extras = [0.0], [0.0], []
    now = rng.uniform(2.0, 6.0)
    while now < duration_s - 5.0:
        grip, load = rng.uniform(1.5, 6.0), rng.uniform(0.5, 2.5)
        steps = rng.uniform([0.1, 0.5, 0.3, 2.0, 0.3, 0.1], [0.4, 2.0, 0.8, 8.0, 0.8, 0.3])
        at = now + np.cumsum(np.concatenate([[0.0], steps]))
        knots_t += at.tolist()
        knots_f += [0.0, grip, grip, grip + load, grip + load, grip, 0.0]
        sway_hz, sway, decay = rng.uniform(1.5, 4.0), rng.uniform(0.1, 0.3) * load, rng.uniform(1.0, 4.0)
        extras += [("sway", at[2], at[5], sway_hz, sway, decay), ("sway", at[4], at[5], sway_hz, -sway, decay)]
        if rng.random() < 0.25:
            extras.append(("regrip", at[3] + rng.uniform(0.2, 0.8) * steps[3], rng.uniform(0.3, 0.8),
                           rng.uniform(0.3, 0.6) * grip, 0.0, 0.0))
        now = at[-1] + rng.uniform(3.0, 15.0)
    f = min_jerk(t, knots_t + [max(duration_s, knots_t[-1]) + 1.0], knots_f + [0.0])
    for kind, a, b, c, d, e in extras:
        if kind == "sway":
            inside = (t >= a) & (t < b)
            u = t[inside] - a
            f[inside] += d * np.sin(2.0 * np.pi * c * u) * np.exp(-u / e)
        else:
            inside = (t >= a) & (t < a + b)
            f[inside] -= c * 0.5 * (1.0 - np.cos(2.0 * np.pi * (t[inside] - a) / b))
    return t, np.clip(f, 0.0, FORCE_MAX_N)


PROFILES = (needle_robot, retractor_tension, grasp_cycles)


def temperature(t, rng, step_s=0.25):
    """A sensor under an operating lamp, cooled by irrigation: in a room of 22-24 degC, the lamp is switched on at
    3-25 % of the record (its heat would warm the sensor by 2-5 degC, time constant 60-180 s), moved 1-2 times
    (its heat scaled by 0.4-1.4), and two times in five switched off at 70-95 %; 3-7 flushes of saline 2.5-6 degC below
    the room, 3-10 s long, pull it toward their temperature with a time constant of 4-12 s. Exact per step of
    ``step_s`` for the step's own coefficients, from the room's temperature."""
    s = t - t[0]
    d = s[-1] if s[-1] > 0 else 1.0
    grid = np.arange(0.0, d + 2.0 * step_s, step_s)
    room, tau_lamp, tau_flush = T_REF_C + rng.uniform(-1.0, 1.0), rng.uniform(60.0, 180.0), rng.uniform(4.0, 12.0)
    heat = rng.uniform(2.0, 5.0)
    switches = np.sort(np.concatenate([[rng.uniform(0.03, 0.25)], rng.uniform(0.3, 0.9, int(rng.integers(1, 3)))])) * d
    levels = heat * np.concatenate([[1.0], rng.uniform(0.4, 1.4, switches.size - 1)])
    lamp = np.where(grid >= switches[0], levels[np.maximum(np.searchsorted(switches, grid, side="right") - 1, 0)], 0.0)
    if rng.random() < 0.4:
        lamp[grid >= rng.uniform(0.7, 0.95) * d] = 0.0
    flush = np.zeros_like(grid)
    for a in rng.uniform(0.05, 0.95, int(rng.integers(3, 8))) * d:
        flush[(grid >= a) & (grid < a + rng.uniform(3.0, 10.0))] = 1.0
    saline = room - rng.uniform(2.5, 6.0)
    rate = 1.0 / tau_lamp + flush / tau_flush
    target = ((room + lamp) / tau_lamp + flush * saline / tau_flush) / rate
    keep = np.exp(-rate * step_s)
    out, y = np.empty_like(grid), room
    for i, (eq, kp) in enumerate(zip(target.tolist(), keep.tolist())):
        out[i] = y
        y = eq + (y - eq) * kp
    return np.interp(s, grid, out)


# ----------------------------------------------------------------------------- simulate-only truth elements

class FlowAddedCore(SimOnly):
    """A Zener core plus a flow ``flow(t, F)`` (V) added to its deformation."""

    def __init__(self, zener, flow):
        self.zener, self.flow = zener, flow

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        return simulate_deformation(self.zener, t, f) + self.flow(t, f)


def jerky_flow(phi_v_per_n_s, slip_v, thresholds):
    """A flow of slips of ``slip_v`` each, a Poisson process of intensity phi |F| / slip (its mean rate phi |F|):
    the n-th slip happens where the integrated intensity passes ``thresholds[n]`` (the cumulated sum of unit
    exponential draws, fixed with the sensor)."""
    def flow(t, f):
        intensity = integrate.cumulative_trapezoid(phi_v_per_n_s * np.abs(f) / slip_v, t, initial=0.0)
        return slip_v * np.searchsorted(thresholds, intensity, side="right")
    return flow


def davidson_cole_weights(tau0_s, beta, points=24):
    """Kelvin units (retardation times, weights to a unit sum) fitted by non-negative least squares to the
    Davidson-Cole creep function P(beta, t / tau0) (the regularised lower incomplete gamma function) over
    1 ms-3000 s."""
    taus = tau0_s * np.geomspace(1e-4, 3.0, points)
    ts = np.geomspace(1e-3, 3e3, 400)
    design = -np.expm1(-ts[:, None] / taus[None, :])
    weights, _ = optimize.nnls(design, special.gammainc(beta, ts / tau0_s))
    return taus, weights / max(weights.sum(), 1e-12)


def multi_kelvin(t, f, compliance_v_per_n, taus, weights):
    """The deformation of Kelvin units of retardation times ``taus`` [s] sharing ``compliance_v_per_n`` by
    ``weights``, from rest."""
    rates = 1.0 / np.asarray(taus)
    return exp_convolve(t, f, rates) @ (compliance_v_per_n * np.asarray(weights) * rates)


def squeeze_film_kelvin(t, f, compliance_v_per_n, tau0_s, gap_v):
    """A Kelvin unit whose dashpot is a squeezed film: tau(x) x' + x = c F with tau = tau0 / (1 - x / gap)^3 (the
    film's damping as the inverse cube of its thickness, the gap closing as the unit deforms); exact per step for
    the step's own tau and mean force; from rest."""
    tl, fl = t.tolist(), np.asarray(f, dtype=float).tolist()
    out, x = np.zeros(len(tl)), 0.0
    for i in range(1, len(tl)):
        g = compliance_v_per_n * 0.5 * (fl[i] + fl[i - 1])
        tau = tau0_s / (1.0 - min(x / gap_v, 0.9)) ** 3
        x = g + (x - g) * math.exp(-(tl[i] - tl[i - 1]) / tau)
        out[i] = x
    return out


def endochronic_memory(x, rates, weights):
    """Valanis' endochronic memory of ``x``: sum_k w_k int exp(-r_k (z - z')) dx(z') over the intrinsic time z,
    the travel sum |dx|; exact for x linear in z between samples (integrated by parts into one exponential
    convolution per rate)."""
    x = np.asarray(x, dtype=float)
    z = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(x)))])
    conv = exp_convolve(z, x, rates)
    return (x[:, None] - x[0] * np.exp(-np.outer(z, rates)) - rates * conv) @ weights


def power_kernel(z0, p, points=12):
    """Rates and weights of exponentials in the intrinsic time fitted (non-negative least squares) to the kernel
    (1 + z / z0)^-p over 1e-3 z0 to 1e3 z0."""
    rates = np.geomspace(1e-3, 30.0, points) / z0
    zs = z0 * np.geomspace(1e-3, 1e3, 300)
    weights, _ = optimize.nnls(np.exp(-np.outer(zs, rates)), (1.0 + zs / z0) ** -p)
    return rates, weights


class EndochronicForce(SimOnly):
    """The force the core sees: F - a M(F), M the endochronic memory of a power-law kernel (1 + z / z0)^-p, a set so
    that a 0-6-0 N cycle opens by ``opening_n`` at 3 N."""

    def __init__(self, z0_n, p, opening_n):
        self.rates, self.weights = power_kernel(z0_n, p)
        cycle = np.concatenate([np.linspace(0.0, 6.0, 601), np.linspace(6.0, 0.0, 601)])
        memory = endochronic_memory(cycle, self.rates, self.weights)
        self.a = opening_n / max(abs(memory[300] - memory[901]), 1e-9)  # both at 3 N

    def forward(self, t_s, x, aux=None, state=None):
        f = np.asarray(x, dtype=float)
        return f - self.a * endochronic_memory(f, self.rates, self.weights)


class BondLayerPlasticity(SimOnly):
    """A bond layer between the polymer and the gauge that yields: y = x + q, q = k (x - p) its stress (V) with an
    elastic slope k, a yield range |q - alpha| <= R and Armstrong-Frederick kinematic hardening dalpha = H dp -
    (H / B) alpha |dp| (the back stress saturating at +-B); R softens from R0 by a share ``soften`` as the plastic
    travel accumulates over ``travel_v``. Return mapping per sample, from rest at x[0]."""

    def __init__(self, k, r0_v, b_v, h, soften, travel_v):
        self.k, self.r0, self.b, self.h, self.soften, self.travel = k, r0_v, b_v, h, soften, travel_v

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        k, h, gamma = self.k, self.h, self.h / self.b
        p, alpha, used = float(x[0]), 0.0, 0.0
        out = np.empty_like(x)
        for i, xi in enumerate(x.tolist()):
            q = k * (xi - p)
            radius = self.r0 * (1.0 - self.soften * -math.expm1(-used / self.travel))
            excess = abs(q - alpha) - radius
            if excess > 0.0:
                s = 1.0 if q > alpha else -1.0
                dl = excess / (k + h - gamma * alpha * s)
                p += s * dl
                alpha = min(max(alpha + h * s * dl - gamma * alpha * dl, -self.b), self.b)
                used += dl
                q = k * (xi - p)
            out[i] = xi + q
        return out


class RcLine(SimOnly):
    """A distributed RC line, 1 / cosh(sqrt(s tau)) (mean delay tau / 2): its modes, first-order lags of rates
    (2n + 1)^2 pi^2 / (4 tau) weighted 4 (-1)^n / ((2n + 1) pi), those faster than 20 per sample passed straight
    through; settled at x[0]."""

    def __init__(self, tau_s):
        self.tau = tau_s

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        h = float(np.median(np.diff(t)))
        odd = 2.0 * np.arange(400) + 1.0
        rates = odd ** 2 * math.pi ** 2 / (4.0 * self.tau)
        weights = 4.0 * (-1.0) ** np.arange(400) / (odd * math.pi)
        slow = rates * h < 20.0
        lagged = exp_convolve(t, x - x[0], rates[slow]) @ (weights[slow] * rates[slow])
        return x[0] + lagged + (1.0 - weights[slow].sum()) * (x - x[0])


class ResistiveRcLag(SimOnly):
    """A first-order RC low-pass whose resistance is the piezoresistive element's: tau = tau0 / (1 + g clip(x /
    top, 0, 1)) (the resistance falls as the load rises); exact per step for the step's own tau; from x[0]."""

    def __init__(self, tau0_s, gain, top_v):
        self.tau0, self.gain, self.top = tau0_s, gain, top_v

    def forward(self, t_s, x, aux=None, state=None):
        t, x = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        decay = np.exp(-np.diff(t, prepend=t[0]) * (1.0 + self.gain * np.clip(x / self.top, 0.0, 1.0)) / self.tau0)
        y, out = float(x[0]), np.empty_like(x)
        for i, (xi, di) in enumerate(zip(x.tolist(), decay.tolist())):
            y = xi + (y - xi) * di
            out[i] = y
        return out


def fringe_map(phi0, sign, kappa):
    """An interferometric read-out biased at phase ``phi0``: (sin(phi0 + sign kappa x) - sin(phi0)) / (sign kappa
    cos(phi0)), unit slope at zero."""
    return lambda x: (np.sin(phi0 + sign * kappa * x) - math.sin(phi0)) / (sign * kappa * math.cos(phi0))


def fringe_deviation(phi0, sign, kappa, top):
    """The largest relative departure of :func:`fringe_map` from its unit slope over (0, top]."""
    xs = np.linspace(top / 50.0, top, 50)
    return float(np.max(np.abs(fringe_map(phi0, sign, kappa)(xs) / xs - 1.0)))


def convective_lag(t, temp, tau_s, step_s=0.5):
    """The body's temperature coupled to ``temp`` by natural convection: dT_b/dt = (T - T_b) |T - T_b|^0.25 /
    (tau 1 degC^0.25), exact per step of ``step_s`` for the step's own coefficient; from temp[0]."""
    grid, tg = coarse(t, temp, step_s)
    y, out = float(tg[0]), np.empty_like(tg)
    for i, ti in enumerate(tg.tolist()):
        d = ti - y
        y += d * -math.expm1(-step_s * abs(d) ** 0.25 / tau_s)
        out[i] = y
    return np.interp(t, grid, out)


def buried_temperature(t, temp, tau_d_s, step_s=0.5):
    """The temperature at depth d in a thick wall whose face follows ``temp`` (semi-infinite diffusion): every
    change of the face arrives as erfc(sqrt(tau_d / (4 u))) after u seconds, tau_d = d^2 / kappa; from equilibrium
    at temp[0]."""
    grid, tg = coarse(t, temp, step_s)
    u = np.arange(grid.size) * step_s
    response = special.erfc(np.sqrt(tau_d_s / (4.0 * np.maximum(u, 1e-12))))
    inner = tg[0] + signal.fftconvolve(np.diff(tg, prepend=tg[0]), response)[:grid.size]
    return np.interp(t, grid, inner)


class LoadSharing(SimOnly):
    """The force that reaches the sensor past a parallel seal: F k_s / (k_s + k_p(T)) over its share at T_ref, the
    seal's stiffness k_p = rho k_s exp(-b (T - T_ref))."""

    def __init__(self, rho, b_per_c):
        self.rho, self.b = rho, b_per_c

    def forward(self, t_s, x, aux=None, state=None):
        f = np.asarray(x, dtype=float)
        temp = np.broadcast_to(np.asarray(aux["temperature_c"], dtype=float), f.shape)
        return f * (1.0 + self.rho) / (1.0 + self.rho * np.exp(-self.b * (temp - T_REF_C)))


def battery_curve(tau_sag_s, tau_knee_s, sag, knee):
    """A battery's voltage drop over the record, 0 at the start and 1 at its end: a share ``sag`` as an
    exponential sag (``tau_sag_s``), ``knee`` as an end-of-charge knee rising exponentially (``tau_knee_s``), the
    rest a linear plateau; a function of the time since the first sample."""
    d = DURATION_S

    def curve(s):
        first = -np.expm1(-s / tau_sag_s) / -math.expm1(-d / tau_sag_s)
        last = (np.exp((s - d) / tau_knee_s) - math.exp(-d / tau_knee_s)) / -math.expm1(-d / tau_knee_s)
        return sag * first + (1.0 - sag - knee) * s / d + knee * last
    return curve


def switched(rng, on_s, off_s):
    """A random on/off schedule over the record (durations drawn from ``on_s`` and ``off_s``, either state
    first): a function of the time since the first sample, 1 while on."""
    edges, now, state = [], -rng.uniform(0.0, 60.0), rng.random() < 0.5
    first = state
    while now < DURATION_S + 60.0:
        now += rng.uniform(*(on_s if state else off_s))
        edges.append(now)
        state = not state
    edges = np.asarray(edges)
    return lambda s: ((np.searchsorted(edges, s, side="right") % 2 == 0) == first).astype(float)


def duty_heating(rng, tau_s, step_s=0.5):
    """The electronics' own temperature rise (0 to 1 over its range) as a radio switches on for 15-60 s and off for
    20-90 s, behind a first-order thermal lag ``tau_s``; a function of the time since the first sample."""
    grid = np.arange(0.0, DURATION_S + 60.0, step_s)
    rise = kelvin(grid, switched(rng, (15.0, 60.0), (20.0, 90.0))(grid), 1.0, tau_s)
    rise = (rise - rise.min()) / max(np.ptp(rise), 1e-12)
    return lambda s: np.interp(s, grid, rise)


def mount_mode(f0_hz, zeta, u):
    """A unit mass on a Zener elastomer mount (a spring k0 beside a Maxwell arm k1, tau = u / omega, omega = 2 pi
    f0 the mode at high frequency with k0 + k1 = omega^2): (num, den) of K(s) / (s^2 + K(s)), the arm's strength
    k1 / k0 chosen so that the mode's damping ratio is ``zeta`` (as near as it gets)."""
    w = 2.0 * math.pi * f0_hz
    tau = u / w

    def filt(r):
        k0 = w * w / (1.0 + r)
        return [w * w * tau, k0], [tau, 1.0, w * w * tau, k0]

    def damping(r):
        poles = np.roots(filt(r)[1])
        pole = poles[np.argmax(poles.imag)]
        return float(-pole.real / abs(pole))
    r = optimize.brentq(lambda r: damping(r) - zeta, 1e-5, 3.0) if damping(3.0) > zeta else 3.0
    return filt(r)


class OilLineModes(SimOnly):
    """A hydraulic load cell read through an oil line (a quarter-wave pipe): modes at (2n + 1) f1 below
    ``top_hz``, weights 4 (-1)^n / ((2n + 1) pi) and damping zeta1 / sqrt(2n + 1), the rest of the unit gain
    passed straight through."""

    def __init__(self, f1_hz, zeta1, top_hz=300.0):
        self.modes = []
        for n in range(int((top_hz / f1_hz - 1.0) / 2.0) + 1):
            w, z = 2.0 * math.pi * f1_hz * (2 * n + 1), zeta1 / math.sqrt(2 * n + 1)
            self.modes.append((4.0 * (-1) ** n / ((2 * n + 1) * math.pi), LinearFilter([w * w], [1.0, 2.0 * z * w, w * w])))
        self.direct = 1.0 - sum(c for c, _ in self.modes)

    def forward(self, t_s, x, aux=None, state=None):
        x = np.asarray(x, dtype=float)
        return self.direct * x + sum(c * m.forward(t_s, x) for c, m in self.modes)


class ClockCore(SimOnly):
    """A Burgers core on the reduced time int rate(t, T) dt."""

    def __init__(self, c, rate_of):
        self.c, self.rate_of = c, rate_of

    def forward(self, t_s, x, aux=None, state=None):
        t, f = np.asarray(t_s, dtype=float), np.asarray(x, dtype=float)
        temp = np.broadcast_to(np.asarray(aux["temperature_c"], dtype=float), t.shape)
        return simulate_deformation(self.c, integrate.cumulative_trapezoid(self.rate_of(t, temp), t, initial=0.0), f)


def transient_clock(b_per_c, g, rate_ref=0.02):
    """exp(b (T - T_ref)) (1 + g min(|dT/dt| / rate_ref, 10)): a clock that runs faster while the temperature
    changes (the rate on a 0.5 s grid)."""
    def rate(t, temp):
        grid, tg = coarse(t, temp)
        slope = np.abs(np.interp(t, grid, np.gradient(tg, grid))) if grid.size > 1 else np.zeros_like(t)
        return np.exp(b_per_c * (temp - T_REF_C)) * (1.0 + g * np.minimum(slope / rate_ref, 10.0))
    return rate


def plasticised_clock(b_per_c, share, tau_s):
    """exp(b (T - T_ref) - share b (T_lag - T_ref)): the Arrhenius clock less the water the polymer loses as it
    warms (its content following the temperature behind a lag ``tau_s``)."""
    def rate(t, temp):
        lagged = temp[0] + kelvin(t, temp - temp[0], 1.0, tau_s)
        return np.exp(b_per_c * (temp - T_REF_C) - share * b_per_c * (lagged - T_REF_C))
    return rate


def press_gains(x, gains, contact_n=0.3):
    """A gain per press: the k-th rise of ``x`` above ``contact_n`` takes ``gains[k]`` (the last beyond)."""
    contact = x > contact_n
    presses = np.cumsum(contact & ~np.concatenate([[False], contact[:-1]]))
    return gains[np.minimum(presses, gains.size - 1)]


def tdma_buzz(starts_s, lengths_s, size_v, phase, frame_hz=1.0 / 4.615e-3):
    """A GSM handset's buzz: while a call is on, the amplifier rectifies one burst of 577 us per TDMA frame of 4.615
    ms (a 1/8-duty pulse train of ``size_v``), sampled as it comes (no anti-alias filter ahead of the pick-up)."""
    def buzz(t, f, T):
        s = t - t[0]
        on = np.zeros_like(s, dtype=bool)
        for a, n in zip(starts_s, lengths_s):
            on |= (s >= a) & (s < a + n)
        return size_v * (on & (np.mod(s * frame_hz + phase, 1.0) < 0.125))
    return buzz


# ----------------------------------------------------------------------------- truths

def make_parts(effect, shape, m, c, rng):  # noqa: C901 - one branch per shape is the clearest catalogue of the split
    span = FORCE_MAX_N / c.relaxation().g0_n_per_v * 2.0  # ~ the core's output over the force range, V
    p = Parts("burgers", c)
    if effect == "none":
        return p
    if effect == "viscous_flow":
        phi = 1.0 / float(np.exp(np.interp(m, [0, 1], np.log([8e4, 4e3]))))  # V / (N s) at 1 N
        zener = Zener(c.k1_n_per_v, c.k2_n_per_v, c.eta2_n_s_per_v)
        if shape == "jerky_flow":
            slip = phi * 3.0 * DURATION_S / rng.uniform(25.0, 100.0)  # 25-100 slips at a mean 3 N over the record
            thresholds = np.cumsum(rng.exponential(1.0, 20000))
            return Parts("zener", FlowAddedCore(zener, jerky_flow(1.5 * phi, slip, thresholds)), core_changed=True)
        f_p = rng.uniform(2.5, 6.0)
        rate = 1.6 * phi * math.exp(2.0 / f_p)  # phi F at 2 N

        def piezoviscous(t, f, a=rate, fp=f_p):
            return integrate.cumulative_trapezoid(a * f * np.exp(-np.abs(f) / fp), t, initial=0.0)
        return Parts("zener", FlowAddedCore(zener, piezoviscous), core_changed=True)
    if effect == "delayed_elasticity":
        total = float(np.interp(m, [0, 1], [1 / 60.0, 1 / 6.0]))  # added compliance, V/N
        if shape == "davidson_cole_creep":
            taus, weights = davidson_cole_weights(rng.uniform(8.0, 120.0), rng.uniform(0.25, 0.55))
            p.extra.append(lambda t, f, T, k=total, ta=taus, w=weights: multi_kelvin(t, f, k, ta, w))
            return p
        tau0, closing = rng.uniform(1.0, 6.0), rng.uniform(0.45, 0.7)
        gap = total * FORCE_MAX_N / closing  # the full-range creep closes the film by 45-70 %
        p.extra.append(lambda t, f, T, k=total, tau=tau0, g=gap: squeeze_film_kelvin(t, f, k, tau, g))
        return p
    if effect == "hysteresis":
        frac = float(np.interp(m, [0, 1], [0.02, 0.07]))
        if shape == "endochronic_force":
            p.before.append(EndochronicForce(rng.uniform(0.2, 1.0), rng.uniform(1.5, 2.5), frac * FORCE_MAX_N))
            return p
        bound = frac * span / 2.0  # the loop opens by about frac span
        r0 = rng.uniform(0.2, 0.5) * bound
        p.after.append(BondLayerPlasticity(rng.uniform(0.2, 0.6), r0, bound - r0, rng.uniform(0.3, 1.5),
                                           rng.uniform(0.2, 0.5), rng.uniform(10.0, 40.0) * span))
        return p
    if effect == "sensor_lag":
        delay = float(np.exp(np.interp(m, [0, 1], np.log([0.01, 0.12]))))
        if shape == "rc_line":
            p.after.append(RcLine(2.0 * delay))
            return p
        gain = rng.uniform(2.0, 6.0)
        p.after.append(ResistiveRcLag(delay * (1.0 + gain / 2.0), gain, span / 2.0))
        return p
    if effect == "nonlinear_gain":
        rel = float(np.interp(m, [0, 1], [0.02, 0.08]))
        top = span / 2 * rng.uniform(1.0, 1.5)
        if shape == "off_quadrature_fringe":
            sign = float(rng.choice([-1, 1]))
            phi0 = rng.uniform(0.2, 0.9) if sign > 0 else rng.uniform(0.15, 0.45)  # away from or across quadrature
            kmax = ((1.5 - phi0) if sign > 0 else (phi0 + 1.2)) / top

            def dev(k, p0=phi0, sg=sign, top=top, rel=rel):
                return fringe_deviation(p0, sg, k, top) - 2.0 * rel
            kappa = optimize.brentq(dev, 1e-9 / top, kmax) if dev(kmax) > 0 else kmax
            p.after.append(StaticMap(fringe_map(phi0, sign, kappa)))
            return p
        d = optimize.brentq(lambda d: ((1.0 - top / d) ** -3 - 1.0) * d / (3.0 * top) - 1.0 - 2.0 * rel,
                            1.05 * top, 1e4 * top)
        p.after.append(StaticMap(lambda x, d=d: d / 3.0 * ((1.0 - np.minimum(x, 0.9 * d) / d) ** -3 - 1.0)))
        return p
    if effect == "thermal_drift":
        k = float(np.interp(m, [0, 1], [0.006, 0.02]) * rng.choice([-1, 1]))
        if shape == "convective_lag_zero":
            tau = rng.uniform(40.0, 150.0)
            p.extra.append(lambda t, f, T, k=2.0 * k, tau=tau: k * (convective_lag(t, T, tau) - T_REF_C))
            return p
        tau_d = rng.uniform(30.0, 240.0)
        p.extra.append(lambda t, f, T, k=2.5 * k, tau=tau_d: k * (buried_temperature(t, T, tau) - T_REF_C))
        return p
    if effect == "thermal_sensitivity":
        a = float(np.interp(m, [0, 1], [0.002, 0.01]) * rng.choice([-1, 1]))
        if shape == "rubbery_span":
            out = core_output(c)
            retarded = 1.0 / c.k2_n_per_v + 60.0 / c.eta1_n_s_per_v
            ratio = min(max((1.0 / c.k1_n_per_v + retarded) / retarded, 1.0), 8.0)  # a whole-span 4a after 60 s
            p.extra.append(lambda t, f, T, a=4.0 * a * ratio, out=out, k1=c.k1_n_per_v:
                           a * (T - T_REF_C) * (out(t, f) - f / k1))
            return p
        rho = rng.uniform(0.1, 0.5)
        p.before.append(LoadSharing(rho, 5.0 * a * (1.0 + rho) / rho))
        return p
    if effect == "offset_drift":
        size = float(np.interp(m, [0, 1], [0.015, 0.08]) * rng.choice([-1, 1]))
        if shape == "battery_discharge":
            curve = battery_curve(rng.uniform(15.0, 60.0), rng.uniform(30.0, 120.0), rng.uniform(0.15, 0.35),
                                  rng.uniform(0.25, 0.5))
            p.extra.append(lambda t, f, T, s=size, u=curve: s * u(t - t[0]))
            return p
        heating = duty_heating(rng, rng.uniform(20.0, 80.0))
        p.extra.append(lambda t, f, T, s=size, u=heating: s * (u(t - t[0]) - u(0.0)))
        return p
    if effect == "resonance":
        f0 = rng.uniform(18.0, 45.0)
        zeta = float(np.interp(m, [0, 1], [0.06, 0.015])) * rng.uniform(0.8, 1.2)
        if shape == "viscoelastic_mount_mode":
            p.after.append(LinearFilter(*mount_mode(f0, 0.6 * zeta, rng.uniform(0.5, 2.0))))
            return p
        p.after.append(OilLineModes(f0, 0.8 * zeta))
        return p
    if effect == "friction":
        r = float(np.interp(m, [0, 1], [0.005, 0.03]) * FORCE_MAX_N)
        if shape == "dithered_band":
            fan, drop = switched(rng, (15.0, 90.0), (15.0, 90.0)), rng.uniform(0.5, 0.8)

            def dithered(t, x, r=1.4 * r, fan=fan, d=drop):
                band = r * (1.0 - d * fan(t - t[0]))
                return band_play(x, band, band)
            p.before.append(ForcePath(dithered))
            return p
        lift, drop = rng.uniform(4.0, 8.0), rng.uniform(0.6, 0.85)

        def lifting(t, x, r=1.6 * r, fl=lift, d=drop):
            band = r * (1.0 - d * np.clip(x / fl, 0.0, 1.0))
            return band_play(x, band, band)
        p.before.append(ForcePath(lifting))
        return p
    if effect == "thermo_rheological":
        b = float(np.interp(m, [0, 1], [0.15, 0.4]))
        if shape == "transient_thermal_creep":
            g = float(np.interp(m, [0, 1], [0.15, 0.5])) * rng.uniform(0.8, 1.2)
            return Parts("burgers", ClockCore(c, transient_clock(0.8 * b, g)), core_changed=True)
        clock = plasticised_clock(0.75 * b, rng.uniform(0.5, 0.9), rng.uniform(60.0, 200.0))
        return Parts("burgers", ClockCore(c, clock), core_changed=True)
    if effect == "eccentric_contact":
        spread = float(np.interp(m, [0, 1], [0.03, 0.08]))
        gains = 1.0 + spread * np.clip(rng.normal(0.0, 1.0, 500), -2.5, 2.5)
        p.before.append(ForcePath(lambda t, x, g=gains: x * press_gains(x, g)))
        return p
    if effect == "gsm_buzz":
        n = int(rng.integers(3, 8))
        starts, lengths = rng.uniform(0.02, 0.95, n) * DURATION_S, rng.uniform(5.0, 40.0, n)
        p.extra.append(tdma_buzz(starts, lengths, float(np.interp(m, [0, 1], [0.03, 0.08])), rng.uniform()))
        return p
    raise ValueError(effect)


SHAPES = {
    "viscous_flow": ["jerky_flow", "piezoviscous_flow"],
    "delayed_elasticity": ["davidson_cole_creep", "squeeze_film_kelvin"],
    "hysteresis": ["endochronic_force", "bond_layer_plasticity"],
    "sensor_lag": ["rc_line", "resistive_rc_lag"],
    "nonlinear_gain": ["off_quadrature_fringe", "magnet_gap_bridge"],
    "thermal_drift": ["convective_lag_zero", "buried_gauge_zero"],
    "thermal_sensitivity": ["rubbery_span", "load_sharing_span"],
    "offset_drift": ["battery_discharge", "duty_cycle_heating"],
    "resonance": ["viscoelastic_mount_mode", "oil_line_modes"], "friction": ["dithered_band", "lift_off_band"],
    "thermo_rheological": ["transient_thermal_creep", "plasticised_clock"],
}
PAIRS = (("viscous_flow", "friction"), ("offset_drift", "resonance"), ("thermo_rheological", "thermal_sensitivity"),
         ("resonance", "thermal_drift"), ("delayed_elasticity", "hysteresis"), ("nonlinear_gain", "sensor_lag"))
OUTSIDE = ("eccentric_contact", "gsm_buzz")
RATES = (280.0, 460.0, 690.0, 960.0)  # four rates, three profiles: every profile at every rate


SPLIT = ShapeSplit("independent split M", SEED0, SHAPES, PAIRS, OUTSIDE, magnitudes=(0.3, 0.8),
                   pair_shapes=(0, -1), rates=RATES, profiles=PROFILES, temperature=temperature,
                   make_parts=make_parts, duration_s=DURATION_S, noise_v=(1.0e-3, 3.0e-3), jitter=0.35,
                   gap_s=(0.2, 3.0))
cases, simulate = SPLIT.cases, SPLIT.simulate


if __name__ == "__main__":
    SPLIT.main(__doc__)
