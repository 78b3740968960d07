"""The ``friction`` effect's fit: a stop of half-width r on the force path before the core (Coulomb friction in the
mechanism), its search grid, its design columns and its chain element.

The core sees ``F - c stop_r(F)``, ``stop_r(F) = F - play_r(F)``: c is the coupling (1 for a rigid contact) and
the stop's design column is the reference core's output for it. In the ``thermal`` variants the band follows the
mechanism's temperature, ``r(T) = r exp(s (T - T_ref))`` (grease that stiffens in the cold, a bushing that grows
into its bore), directly or through a first-order lag (starting from :data:`LAGGED_START_S`, refined by the polish
within :data:`.columns.TEMPERATURE_LAG_BOUNDS_S`). The band moves the contact only while it slides: after the last slide at time
t*, in direction sigma, the play holds ``F(t*) - sigma r(T(t*))``, so the stop ``F(t) - F(t*) + sigma r(T(t*))``
changes with the band by ``sigma (r(T(t*)) - r)``, and to first order in s the band adds the column
``-core(sigma r (T(t*) - T_ref))`` with the coefficient ``c s``. The saved element runs the exact moving band
(:class:`~polyforce_ros.physics.chain.FrictionElement`). What the first order leaves out: a contact resting at its
band's edge (a hold after a ramp) is dragged by a band that narrows there and left alone by one that widens, which
no column linear in s holds; the fit sees only the part of that drag the holds' noise does not already move.
"""
from __future__ import annotations

from typing import Mapping, Optional

import numpy as np

from ..physics.chain import PARAMETER_BOUNDS, FrictionElement, lagged_temperature_c, play_operator
from ..physics.viscoelastic import simulate_deformation_columns
from .columns import Col, Slot, log_grid, parameter
from .signals import FloatArray, IntArray, Signals, noise_std

__all__ = ["FRICTION_FRACTIONS", "FRICTION_NOISE_SIGMAS", "LAGGED_START_S", "BAND_LAGS_S", "BAND_SLOPE_BOUNDS_PER_C",
           "VARIANTS", "band_lag_variant", "band_lag_s", "is_band", "grid_variant", "force_noise_n", "at_noise_limit",
           "last_slides", "grid", "columns", "elements"]

#: Stiction half-widths searched for a friction, as fractions of the force span; the polish refines the radius
#: within them (:func:`.refit.param_log_bounds`).
FRICTION_FRACTIONS = (0.001, 0.15)

#: The narrowest stiction band searched, in standard deviations of the reference force's noise: a play narrower
#: than a few of them acts on that noise (it smooths the force the model reads), not on the sensor.
FRICTION_NOISE_SIGMAS = 4.0

#: The lagged band's lag where the polish starts to refine it [s]: a mechanism a quarter of a minute behind the
#: thermometer (a guide or a bushing warms through the housing).
LAGGED_START_S = 15.0
#: The band's temperature lag of each thermal variant on the grid [s]: the thermometer's own temperature, or
#: :data:`LAGGED_START_S`. Each variant is named by its lag (:func:`band_lag_variant`).
BAND_LAGS_S = {"thermal": 0.0, f"thermal_lag{LAGGED_START_S:g}": LAGGED_START_S}
#: The band's log-slope's bounds [1/degC] (the model file's): the bounds of its column's weight, and of the slope saved.
BAND_SLOPE_BOUNDS_PER_C = PARAMETER_BOUNDS["band_log_slope_per_c"][:2]

#: The friction's variants: a band of one width, and the bands that follow temperature.
VARIANTS = ("", *BAND_LAGS_S)


def band_lag_variant(lag_s: float, digits: int = 3) -> str:
    """The thermal variant whose band trails the thermometer by ``lag_s`` [s] (0: ``thermal``), its lag kept to
    ``digits`` significant digits (3 in an answer: ``thermal_lag21.4``; 12 while the polish refines the lag through
    the name, finer than the least squares' steps)."""
    return f"thermal_lag{lag_s:.{digits}g}" if lag_s > 0.0 else "thermal"


def band_lag_s(variant: str) -> float:
    """The band's temperature lag [s] a variant names (0: the thermometer's own temperature, or no band)."""
    return float(variant[len("thermal_lag"):]) if variant.startswith("thermal_lag") else 0.0


def is_band(variant: str) -> bool:
    """Whether a variant's band follows the temperature (a thermal variant, its lag refined or not)."""
    return variant.startswith("thermal")


def grid_variant(variant: str) -> str:
    """The grid variant a variant was refined from (:attr:`.effects.Effect.grid_variant`): a lagged band's start,
    whatever lag the polish gave it."""
    return band_lag_variant(LAGGED_START_S) if band_lag_s(variant) > 0.0 else variant


def force_noise_n(sig: Signals) -> float:
    """Standard deviation of the reference force's noise at the fit rate [N] (:func:`.signals.noise_std`: a smooth
    load cancels in second differences), once per record."""
    key = "force noise"
    if key not in sig.record_cache:
        sig.record_cache[key] = noise_std(sig.f)
    return float(sig.record_cache[key])


def _narrowest_band_n(sig: Signals) -> float:
    """The narrowest stiction half-width searched (N): 0.1 % of the force span, and never narrower than
    :data:`FRICTION_NOISE_SIGMAS` standard deviations of the reference force's noise."""
    return max(FRICTION_FRACTIONS[0] * sig.span_f, FRICTION_NOISE_SIGMAS * force_noise_n(sig))


def grid(variant: str, sig: Signals) -> list[Optional[float]]:
    """Half-widths (N) of the stiction band searched: from :func:`_narrowest_band_n` to 15 % of the force span;
    none for a thermal variant on a record without temperature."""
    if is_band(variant) and sig.temp is None:
        return []
    low = _narrowest_band_n(sig)
    return log_grid(low, max(FRICTION_FRACTIONS[1] * sig.span_f, 2.0 * low), 12)


def at_noise_limit(effect: str, param: Optional[float], sig: Signals) -> bool:
    """Whether ``effect``'s fitted parameter sits at the bound the record sets: a stiction band as narrow as the
    search goes (:func:`_narrowest_band_n`: the reference force's noise, or 0.1 % of the span) was wanted narrower
    still, where the play acts on the force's smallest wiggles (it smooths the noise of the force the model reads),
    not on a mechanism."""
    if effect != "friction" or param is None:
        return False
    return param <= 1.05 * _narrowest_band_n(sig)


def last_slides(play: FloatArray) -> tuple[FloatArray, IntArray]:
    """The direction of each sample's last slide and its index, from a play's output (y0 = 0).

    Parameters
    ----------
    play : (n,) ndarray of float
        The play's output [N]: it moves only while the contact slides.

    Returns
    -------
    sigma : (n,) ndarray of float
        +1 after a slide up, -1 after a slide down, 0 before the first slide.
    last : (n,) ndarray of int
        Index of the last sample at which it slid (0 before the first slide).
    """
    step = np.diff(play, prepend=0.0)
    moved = step != 0.0  # stuck, the play holds its value exactly
    last = np.maximum.accumulate(np.where(moved, np.arange(play.size), 0))
    sigma = np.where(np.maximum.accumulate(moved), np.sign(step[last]), 0.0)
    return sigma, last


def columns(sig: Signals, variant: str, param: Optional[float]) -> list[Col]:
    """The reference core's output for the stop of half-width ``param`` on the force, taken away
    (F_core = F - w stop_r(F)); its weight w is the coupling, 1 for a rigid contact. A thermal variant adds the
    first-order column of the band's change with temperature (module docstring), its weight the coupling times
    the band's log-slope."""
    r = parameter(param)
    key = ("friction column", r)
    if key not in sig.cache:
        f = sig.f_nonlinear
        play = play_operator(f, [r])[:, 0]
        sig.cache[key] = (-simulate_deformation_columns(sig.reference_core, sig.t, (f - play)[:, None])[:, 0], play)
    stop_column, play = sig.cache[key]
    out: list[Col] = [("friction", stop_column, 0.0, 1.0, "sensor", None)]
    if not is_band(variant):
        return out
    band_key = ("friction band column", variant, r)
    if band_key not in sig.cache:
        lag_s = band_lag_s(variant)
        lagged = lagged_temperature_c(sig.t, sig.temperature, lag_s) if lag_s > 0.0 else None
        departure_c = (sig.temperature if lagged is None else lagged) - sig.temp_ref
        sigma, last = last_slides(play)
        band_change_n_c = sigma * r * departure_c[last]  # the stop's change per unit log-slope [N degC]
        sig.cache[band_key] = -simulate_deformation_columns(sig.reference_core, sig.t, band_change_n_c[:, None])[:, 0]
    low, high = BAND_SLOPE_BOUNDS_PER_C
    return out + [("friction_band", sig.cache[band_key], low, high, "sensor", None)]


def elements(coef: Mapping[str, float], variant: str, param: Optional[float], sig: Signals) -> list[Slot]:
    """The fitted friction as a :class:`~polyforce_ros.physics.chain.FrictionElement` before the core (none at zero
    coupling); a thermal variant's band log-slope is its band weight over the coupling, within its bounds."""
    coupling = float(np.clip(coef.get("friction", 0.0), 0.0, 1.0))
    if coupling <= 0.0:
        return []
    if not is_band(variant):
        return [("before", FrictionElement(radius_n=parameter(param), coupling=coupling))]
    low, high = BAND_SLOPE_BOUNDS_PER_C
    ref_low, ref_high = PARAMETER_BOUNDS["reference_c"][:2]
    slope = float(np.clip(coef.get("friction_band", 0.0) / coupling, low, high))
    return [("before", FrictionElement(radius_n=parameter(param), coupling=coupling, band_log_slope_per_c=slope,
                                       reference_c=float(np.clip(sig.temp_ref, ref_low, ref_high)),
                                       temperature_lag_s=band_lag_s(variant)))]
