"""Water, moist air and gravity for the bulk fluxes: saturation humidity over the sea and in
the air, the sea water's thermal expansion, normal gravity.

References in brackets: :mod:`shipthermal.environment.sea_skin`.
"""

from __future__ import annotations

import numpy as np

from shipthermal.units import ZERO_CELSIUS

from .constants import SALINITY


def normal_gravity(latitude):
    """Normal gravity on the WGS 84 ellipsoid [m s-2] at ``latitude`` [deg] ([WGS] eq. 4-1,
    Somigliana's formula; 9.7803 at the equator, 9.8322 at the poles)."""
    phi = np.radians(np.asarray(latitude, dtype=float))
    e2 = 6.69437999014e-3          # first eccentricity squared [WGS Table 3.3]
    k = 1.931852652458e-3          # Somigliana's constant [WGS Table 3.3]
    s2 = np.sin(phi) ** 2
    return 9.7803253359 * (1.0 + k * s2) / np.sqrt(1.0 - e2 * s2)


def saturation_vapour_pressure_buck(temp, pressure):
    """Saturation vapour pressure over pure water in moist air [Pa] ([B81]).

    Parameters
    ----------
    temp : array_like
        Temperature [K].
    pressure : array_like
        Air pressure [Pa].

    Notes
    -----
    [B81]: ``e_w = 6.1121 exp(17.502 T / (240.97 + T))`` hPa (T in °C) times his
    enhancement factor for moist air ``f = 1.0007 + 3.46e-6 P`` (P in hPa), the form of
    [C36].
    """
    t = np.asarray(temp, dtype=float) - ZERO_CELSIUS
    p_hpa = np.asarray(pressure, dtype=float) / 100.0
    return 611.21 * np.exp(17.502 * t / (240.97 + t)) * (1.0007 + 3.46e-6 * p_hpa)


def specific_humidity_sea(temp_sea, pressure, salinity=SALINITY):
    """Saturation specific humidity at the sea surface [kg kg-1].

    The vapour pressure of [B81] lowered by the salt, ``e = (1 − 0.02 S/35) e_w`` (0.98 at
    35 psu; [C36] 3.6, the 2 % reduction of [F96a]), then ``q = 0.622 e / (P − 0.378 e)``.
    """
    es = (1.0 - 0.02 * np.asarray(salinity, dtype=float) / 35.0) * \
        saturation_vapour_pressure_buck(temp_sea, pressure)
    p = np.asarray(pressure, dtype=float)
    return 0.622 * es / (p - 0.378 * es)


def specific_humidity_air(temp_air, relative_humidity, pressure):
    """Specific humidity of air [kg kg-1] from temperature [K], relative humidity [%] and
    pressure [Pa] ([B81] saturation, ``q = 0.62197 e / (P − 0.378 e)``, [C36])."""
    e = np.asarray(relative_humidity, dtype=float) / 100.0 * \
        saturation_vapour_pressure_buck(temp_air, pressure)
    p = np.asarray(pressure, dtype=float)
    return 0.62197 * e / (p - 0.378 * e)


def thermal_expansion_seawater(temp_sea):
    """Thermal expansion coefficient of sea water at 35 psu [K-1].

    ``α = 2.1e-5 (T + 3.2)^0.79`` with T in °C (SOURCED: [C36], the fit COARE's cool skin
    uses; 2.7e-4 at 22 °C, 1.1e-4 at 5 °C). Clipped at −3.2 °C (below sea water's freezing
    point the fit is undefined).
    """
    t = np.maximum(np.asarray(temp_sea, dtype=float) - ZERO_CELSIUS + 3.2, 0.0)
    return 2.1e-5 * t ** 0.79
