"""Radiometric kernels of Landsat bands (LSDS-1822, LSDS-1574 §5): DN to radiance and
reflectance, band radiance to brightness temperature and back."""

from __future__ import annotations


import numpy as np



def dn_to_radiance(dn, mult, add):
    """TOA spectral radiance from Level-1 DN.

    Parameters
    ----------
    dn : array_like
        Quantised calibrated pixel value ``Q_cal`` [DN].
    mult : float
        ``RADIANCE_MULT_BAND_x`` [W m-2 sr-1 um-1 DN-1].
    add : float
        ``RADIANCE_ADD_BAND_x`` [W m-2 sr-1 um-1].

    Returns
    -------
    ndarray
        Radiance [W m-2 sr-1 um-1], float64.

    Notes
    -----
    Landsat 8 Data Users Handbook (LSDS-1574) eq. 5-1.
    """
    return mult * np.asarray(dn, dtype=np.float64) + add


def dn_to_reflectance(dn, mult, add, sun_elevation_deg):
    """Sun-angle-corrected TOA reflectance from Level-1 DN.

    Parameters
    ----------
    dn : array_like
        ``Q_cal`` [DN].
    mult, add : float
        ``REFLECTANCE_MULT_BAND_x`` [DN-1] and ``REFLECTANCE_ADD_BAND_x`` [-].
    sun_elevation_deg : float
        Scene-centre sun elevation [deg].

    Returns
    -------
    ndarray
        Reflectance [-].

    Notes
    -----
    LSDS-1574 eqs. 5-2 and 5-3.
    """
    return (mult * np.asarray(dn, dtype=np.float64) + add) / np.sin(np.radians(sun_elevation_deg))


def radiance_to_brightness_temperature(radiance, k1, k2):
    """At-sensor brightness temperature: Planck inversion with the band constants.

    Parameters
    ----------
    radiance : array_like
        Band spectral radiance [W m-2 sr-1 um-1], > 0.
    k1 : float
        ``K1_CONSTANT_BAND_x`` [W m-2 sr-1 um-1].
    k2 : float
        ``K2_CONSTANT_BAND_x`` [K].

    Returns
    -------
    ndarray
        Brightness temperature [K] (NaN where radiance <= 0).

    Notes
    -----
    LSDS-1574 eq. 5-4, ``T = K2 / ln(K1/L + 1)``: the monochromatic Planck law solved for T
    with ``K1 = c1/lambda^5`` and ``K2 = c2/lambda`` fitted to the band's response.
    """
    rad = np.asarray(radiance, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = k2 / np.log(k1 / rad + 1.0)
    return np.where(rad > 0, out, np.nan)


def brightness_temperature_to_radiance(temp, k1, k2):
    """Band radiance of a blackbody at ``temp`` [K] with the band constants [W m-2 sr-1 um-1].

    The exact inverse of :func:`radiance_to_brightness_temperature`.
    """
    return k1 / np.expm1(k2 / np.asarray(temp, dtype=np.float64))
