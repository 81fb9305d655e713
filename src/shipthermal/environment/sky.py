"""Downwelling long-wave (thermal) radiation from the sky.

Clear-sky effective emissivity from screen-level air temperature and humidity
(Brutsaert 1975, Prata 1996; Swinbank 1963 for comparison), corrected for cloud
(Unsworth & Monteith 1975 or Crawford & Duchon 1999), giving the downwelling
long-wave irradiance on a horizontal surface and the effective sky temperature.
A measured value from a weather file replaces the model where it is present.

Temperatures in K, vapour pressure in Pa, irradiance in W m-2.
"""

from __future__ import annotations

import numpy as np

from shipthermal.errors import InputError
from shipthermal.parameters import CLEAR_SKY_MODEL_NAMES, CLOUD_MODEL_NAMES
from shipthermal.units import SIGMA, ZERO_CELSIUS

__all__ = [
    "saturation_vapour_pressure",
    "vapour_pressure",
    "dew_point",
    "relative_humidity_from_dew_point",
    "emissivity_brutsaert",
    "emissivity_prata",
    "emissivity_swinbank",
    "cloud_correction",
    "sky_emissivity",
    "longwave_down",
    "sky_temperature",
    "CLEAR_SKY_MODELS",
    "CLOUD_MODELS",
]

# Magnus coefficients over water, Alduchov & Eskridge (1996), J. Appl. Meteor. 35,
# 601–609 (their recommended "AERK" fit): relative error < 0.4 % for -40…50 degC.
_MAGNUS_A = 610.94   # [Pa]
_MAGNUS_B = 17.625   # [-]
_MAGNUS_C = 243.04   # [degC]


def saturation_vapour_pressure(temp):
    """Saturation vapour pressure over water [Pa] (Magnus, Alduchov & Eskridge 1996).

    Parameters
    ----------
    temp : array_like
        Temperature [K].
    """
    t_c = np.asarray(temp, dtype=float) - ZERO_CELSIUS
    return _MAGNUS_A * np.exp(_MAGNUS_B * t_c / (t_c + _MAGNUS_C))


def vapour_pressure(temp_air, relative_humidity):
    """Water vapour partial pressure [Pa].

    Parameters
    ----------
    temp_air : array_like
        Air temperature [K].
    relative_humidity : array_like
        Relative humidity over water [%].
    """
    return np.asarray(relative_humidity, dtype=float) / 100.0 * \
        saturation_vapour_pressure(temp_air)


def dew_point(temp_air, relative_humidity):
    """Dew-point temperature [K] by inverting the Magnus formula.

    Parameters
    ----------
    temp_air : array_like
        Air temperature [K].
    relative_humidity : array_like
        Relative humidity [%] (> 0).
    """
    g = np.log(vapour_pressure(temp_air, relative_humidity) / _MAGNUS_A)
    return _MAGNUS_C * g / (_MAGNUS_B - g) + ZERO_CELSIUS


def relative_humidity_from_dew_point(temp_air, temp_dew):
    """Relative humidity [%] from air and dew-point temperature [K] (Magnus)."""
    return 100.0 * saturation_vapour_pressure(temp_dew) / saturation_vapour_pressure(temp_air)


def emissivity_brutsaert(temp_air, vapour_pressure_pa):
    """Clear-sky effective emissivity, Brutsaert (1975).

    Parameters
    ----------
    temp_air : array_like
        Screen-level air temperature [K].
    vapour_pressure_pa : array_like
        Screen-level vapour pressure [Pa].

    Returns
    -------
    numpy.ndarray
        ``1.24 (e / T)^(1/7)`` with e in hPa [-].

    Notes
    -----
    Brutsaert, W. (1975), "On a derivable formula for long-wave radiation from clear
    skies", Water Resour. Res. 11, 742–744 (the 1.24 coefficient is for e in
    mbar and T in K; derived for a standard-atmosphere lapse rate).
    """
    e_hpa = np.asarray(vapour_pressure_pa, dtype=float) / 100.0
    return 1.24 * (e_hpa / np.asarray(temp_air, dtype=float)) ** (1.0 / 7.0)


def emissivity_prata(temp_air, vapour_pressure_pa):
    """Clear-sky effective emissivity, Prata (1996).

    Parameters
    ----------
    temp_air : array_like
        Screen-level air temperature [K].
    vapour_pressure_pa : array_like
        Screen-level vapour pressure [Pa].

    Returns
    -------
    numpy.ndarray
        ``1 − (1 + w) exp(−(1.2 + 3 w)^0.5)`` with the precipitable water
        ``w = 46.5 e / T`` [cm] (e in hPa) [-].

    Notes
    -----
    Prata, A. J. (1996), "A new long-wave formula for estimating downward clear-sky
    radiation at the surface", Q. J. R. Meteorol. Soc. 122, 1127–1151.
    """
    e_hpa = np.asarray(vapour_pressure_pa, dtype=float) / 100.0
    w = 46.5 * e_hpa / np.asarray(temp_air, dtype=float)
    return 1.0 - (1.0 + w) * np.exp(-np.sqrt(1.2 + 3.0 * w))


def emissivity_swinbank(temp_air, vapour_pressure_pa=None):
    """Clear-sky effective emissivity, Swinbank (1963) (temperature only).

    Parameters
    ----------
    temp_air : array_like
        Screen-level air temperature [K].
    vapour_pressure_pa : ignored
        Accepted for a uniform call signature.

    Returns
    -------
    numpy.ndarray
        ``5.31e-13 T^6 / (σ T^4) = 9.365e-6 T^2`` [-].

    Notes
    -----
    Swinbank, W. C. (1963), "Long-wave radiation from clear skies", Q. J. R. Meteorol.
    Soc. 89, 339–348: L = 5.31e-13 T^6 W m-2 (T in K).
    """
    t = np.asarray(temp_air, dtype=float)
    return 5.31e-13 * t ** 2 / SIGMA


_CLEAR_SKY_FUNCTIONS = {"brutsaert": emissivity_brutsaert, "prata": emissivity_prata,
                        "swinbank": emissivity_swinbank}

CLEAR_SKY_MODELS = {name: _CLEAR_SKY_FUNCTIONS[name] for name in CLEAR_SKY_MODEL_NAMES}
"""Clear-sky emissivity models by name: f(temp_air [K], vapour_pressure [Pa]) -> [-]; names
from :data:`shipthermal.parameters.CLEAR_SKY_MODEL_NAMES`."""


def _unsworth_monteith(eps_clear, cloud_cover):
    c = np.asarray(cloud_cover, dtype=float)
    return (1.0 - 0.84 * c) * eps_clear + 0.84 * c


def _crawford_duchon(eps_clear, cloud_cover):
    c = np.asarray(cloud_cover, dtype=float)
    return c + (1.0 - c) * eps_clear


_CLOUD_FUNCTIONS = {"unsworth_monteith": _unsworth_monteith,
                    "crawford_duchon": _crawford_duchon}

CLOUD_MODELS = {name: _CLOUD_FUNCTIONS[name] for name in CLOUD_MODEL_NAMES}
"""Cloud corrections by name: f(eps_clear [-], cloud_cover [0-1]) -> eps [-]; names from
:data:`shipthermal.parameters.CLOUD_MODEL_NAMES`."""


def cloud_correction(eps_clear, cloud_cover, model: str = "unsworth_monteith"):
    """All-sky effective emissivity from the clear-sky value and the cloud cover.

    Parameters
    ----------
    eps_clear : array_like
        Clear-sky effective emissivity [-].
    cloud_cover : array_like
        Cloud cover fraction [0-1].
    model : {'unsworth_monteith', 'crawford_duchon'}
        ``unsworth_monteith``: ε = (1 − 0.84 c) ε_clr + 0.84 c, Unsworth & Monteith
        (1975), Q. J. R. Meteorol. Soc. 101, 13–24 (cloud base radiating as a
        near-black body at screen temperature, 0.84 from their Sutton Bonington data).
        ``crawford_duchon``: ε = c + (1 − c) ε_clr, Crawford & Duchon (1999),
        J. Appl. Meteor. 38, 474–480 (there c is the cloud fraction inferred
        as 1 − s, s the ratio of measured to clear-sky solar irradiance).

    Returns
    -------
    numpy.ndarray
        All-sky effective emissivity [-], ≤ 1.
    """
    try:
        fn = CLOUD_MODELS[model]
    except KeyError:
        raise InputError("sky.cloud_model", model, f"must be one of {sorted(CLOUD_MODELS)}")
    return np.minimum(fn(np.asarray(eps_clear, dtype=float),
                         np.clip(np.asarray(cloud_cover, dtype=float), 0.0, 1.0)), 1.0)


def sky_emissivity(temp_air, relative_humidity, cloud_cover=0.0, clear_model: str = "brutsaert",
                   cloud_model: str = "unsworth_monteith"):
    """Effective all-sky emissivity from air temperature, humidity and cloud.

    Parameters
    ----------
    temp_air : array_like
        Screen-level air temperature [K].
    relative_humidity : array_like
        Relative humidity [%].
    cloud_cover : array_like
        Cloud cover fraction [0-1].
    clear_model : {'brutsaert', 'prata', 'swinbank'}
        Clear-sky model (see :data:`CLEAR_SKY_MODELS`).
    cloud_model : {'unsworth_monteith', 'crawford_duchon'}
        Cloud correction (see :func:`cloud_correction`).

    Returns
    -------
    numpy.ndarray
        Effective emissivity ε with ``L_down = ε σ T_air^4`` [-].
    """
    try:
        fn = CLEAR_SKY_MODELS[clear_model]
    except KeyError:
        raise InputError("sky.clear_model", clear_model,
                         f"must be one of {sorted(CLEAR_SKY_MODELS)}")
    eps = fn(temp_air, vapour_pressure(temp_air, relative_humidity))
    return cloud_correction(np.minimum(eps, 1.0), cloud_cover, cloud_model)


def longwave_down(temp_air, relative_humidity, cloud_cover=0.0, measured=None,
                  clear_model: str = "brutsaert", cloud_model: str = "unsworth_monteith"):
    """Downwelling long-wave irradiance on a horizontal surface [W m-2].

    Parameters
    ----------
    temp_air : array_like
        Screen-level air temperature [K].
    relative_humidity : array_like
        Relative humidity [%].
    cloud_cover : array_like
        Cloud cover fraction [0-1].
    measured : array_like, optional
        Measured downwelling long-wave [W m-2] (weather file); used wherever finite,
        the model fills the rest.
    clear_model, cloud_model : str
        See :func:`sky_emissivity`.

    Returns
    -------
    numpy.ndarray
        ``ε σ T_air^4`` or the measured value [W m-2].
    """
    t = np.asarray(temp_air, dtype=float)
    model = sky_emissivity(t, relative_humidity, cloud_cover, clear_model, cloud_model) * \
        SIGMA * t ** 4
    if measured is None:
        return model
    m = np.broadcast_to(np.asarray(measured, dtype=float), model.shape)
    return np.where(np.isfinite(m), m, model)


def sky_temperature(longwave_down_wm2):
    """Effective (black-body) sky temperature ``(L_down / σ)^(1/4)`` [K].

    Parameters
    ----------
    longwave_down_wm2 : array_like
        Downwelling long-wave irradiance [W m-2].
    """
    return (np.asarray(longwave_down_wm2, dtype=float) / SIGMA) ** 0.25
