"""The cool skin: the molecular sub-layer's temperature drop and thickness ([F96b]).

References in brackets: :mod:`shipthermal.environment.sea_skin`.
"""

from __future__ import annotations

import numpy as np

from shipthermal.units import ZERO_CELSIUS

from .constants import (_SALINE_CONTRACTION_S, SAUNDERS_LAMBDA, SKIN_THICKNESS_MAX,
                        WATER_CONDUCTIVITY, WATER_DENSITY, WATER_HEAT_CAPACITY,
                        WATER_VISCOSITY)
from .thermodynamics import thermal_expansion_seawater


def cool_skin_solar_fraction(thickness):
    """Fraction of the net solar flux absorbed in the cool skin [-].

    Parameters
    ----------
    thickness : array_like
        Cool-skin thickness δ [m].

    Returns
    -------
    numpy.ndarray
        ``f_s = 0.065 + 11 δ − 6.6e-5/δ (1 − exp(−δ / 8e-4))`` ([F96b]; [ZB05] eq. 5):
        0.009, 0.029, 0.057 at δ = 0.5, 1, 2 mm. Negative below δ ≈ 0.31 mm (gales, u*_w
        > 0.02 m s-1), where the fit leaves its range; kept as published, as COARE does.
    """
    d = np.asarray(thickness, dtype=float)
    return 0.065 + 11.0 * d - 6.6e-5 / d * (1.0 - np.exp(-d / 8.0e-4))


def cool_skin(heat_loss, latent_heat_flux, shortwave_net, ustar_water, temp_sea, thickness,
              latent_heat=None, gravity=9.80665):
    """Temperature drop across the cool skin and its thickness (one fixed-point update).

    Parameters
    ----------
    heat_loss : array_like
        Surface heat loss ``H_s + H_l + LW_net`` (sensible, latent and net long-wave, positive
        upward) [W m-2].
    latent_heat_flux : array_like
        Latent heat flux, positive upward [W m-2] (its salt flux adds buoyancy).
    shortwave_net : array_like
        Net solar flux into the sea [W m-2].
    ustar_water : array_like
        Friction velocity in the water ``u*_w = u* (ρ_a/ρ_w)^(1/2)`` [m s-1].
    temp_sea : array_like
        Water temperature below the skin [K] (for the expansion coefficient and the latent
        heat).
    thickness : array_like
        Previous estimate of the skin thickness δ [m] (sets the solar fraction).
    latent_heat : array_like, optional
        Latent heat of vaporisation [J kg-1]; default ``(2.501 − 0.00237 T[°C]) 1e6``
        ([C36]).
    gravity : float
        [m s-2].

    Returns
    -------
    delta_cool : numpy.ndarray
        ``ΔT_cool = T(−δ) − T_skin = Q δ / k_w`` [K] with ``Q = heat_loss − f_s(δ) R_ns``
        (positive: the skin is cooler).
    thickness : numpy.ndarray
        The new δ [m].

    Notes
    -----
    [F96b] (their eqs. 12 and 14; [ZB05] eqs. 4–6): ``δ = λ ν_w / u*_w`` with Saunders'
    ``λ = 6`` [S67] reduced by free convection when the skin's buoyancy flux is upward,
    ``λ = 6 [1 + (16 g c_w ρ_w ν_w³ B / (k_w² u*_w⁴))^(3/4)]^(−1/3)``,
    ``B = α Q + β S c_w H_l / L_e`` (the salt left by evaporation makes the skin heavier).
    δ is bounded by :data:`SKIN_THICKNESS_MAX`. Called in the bulk iteration (the heat loss
    depends on the skin temperature, the solar fraction on δ) until both settle.
    """
    q_loss = np.asarray(heat_loss, dtype=float)
    hl = np.asarray(latent_heat_flux, dtype=float)
    rns = np.asarray(shortwave_net, dtype=float)
    usw = np.asarray(ustar_water, dtype=float)
    ts_c = np.asarray(temp_sea, dtype=float) - ZERO_CELSIUS
    lv = (2.501 - 0.00237 * ts_c) * 1e6 if latent_heat is None else np.asarray(latent_heat)
    q = q_loss - cool_skin_solar_fraction(thickness) * rns
    alpha = thermal_expansion_seawater(temp_sea)
    buoy = alpha * q + _SALINE_CONTRACTION_S * hl * WATER_HEAT_CAPACITY / lv
    big_c = 16.0 * gravity * WATER_HEAT_CAPACITY * WATER_DENSITY * WATER_VISCOSITY ** 3 \
        / WATER_CONDUCTIVITY ** 2
    ratio = np.maximum(big_c * buoy / usw ** 4, 0.0)
    lam = SAUNDERS_LAMBDA / (1.0 + ratio ** 0.75) ** (1.0 / 3.0)
    delta = np.minimum(lam * WATER_VISCOSITY / usw, SKIN_THICKNESS_MAX)
    return q * delta / WATER_CONDUCTIVITY, delta
