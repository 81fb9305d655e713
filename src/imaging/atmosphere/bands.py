"""Sensor bands: band integration of spectral atmosphere quantities.

The bands and their parser are :data:`shipthermal.parameters.BANDS` and
:func:`shipthermal.parameters.parse_band`; Planck's law is
:func:`shipthermal.optics.planck.planck_radiance`.
"""

from __future__ import annotations

import numpy as np

from shipthermal.parameters import BANDS, parse_band

__all__ = ["BANDS", "parse_band", "band_integrate", "band_weights"]


def band_integrate(wavelength_um, values, band, response=None, mean: bool = False):
    """Integrate spectral values over a band with a sensor response.

    Parameters
    ----------
    wavelength_um : array_like, shape (n,)
        Ascending wavelengths [µm].
    values : array_like, shape (..., n)
        Spectral quantity (e.g. [W m⁻² sr⁻¹ µm⁻¹]); linear between samples.
    band : tuple of float
        (low, high) [µm]; the rectangular response is 1 inside.
    response : tuple of arrays or SpectralResponse, optional
        ``(wavelength_um, relative_response)`` table replacing the rectangle
        (linear between entries, 0 outside; ``band`` is then ignored).
    mean : bool
        Return the response-weighted mean ∫v R dλ / ∫R dλ (for transmittance) instead
        of ∫v R dλ.

    Returns
    -------
    ndarray, shape (...)
        ∫ v R dλ [unit of values × µm], or the weighted mean [unit of values].

    Notes
    -----
    With a rectangle the integral of the piecewise-linear interpolant is exact
    (trapezoid on the samples plus the two band edges).
    """
    lam = np.asarray(wavelength_um, dtype=float)
    v = np.asarray(values, dtype=float)
    if response is None:
        lo, hi = band
        inner = lam[(lam > lo) & (lam < hi)]
        grid = np.concatenate([[lo], inner, [hi]])
        weight = np.ones_like(grid)
    else:
        if hasattr(response, "wavelength_um"):  # a SpectralResponse
            response = (response.wavelength_um, response.response)
        rl = np.asarray(response[0], dtype=float)
        rr = np.asarray(response[1], dtype=float)
        lo, hi = max(rl[0], lam[0]), min(rl[-1], lam[-1])
        grid = np.unique(np.concatenate([lam, rl]))
        grid = grid[(grid >= lo) & (grid <= hi)]
        weight = np.interp(grid, rl, rr, left=0.0, right=0.0)
    vi = np.apply_along_axis(lambda y: np.interp(grid, lam, y), -1, v) if v.ndim > 1 \
        else np.interp(grid, lam, v)
    total = np.trapezoid(vi * weight, grid, axis=-1)
    if mean:
        return total / np.trapezoid(weight, grid)
    return total


def band_weights(wavelength_um, band, response=None) -> np.ndarray:
    """Weights ``w`` with ``w @ values == band_integrate(wavelength_um, values, band,
    response)`` for every spectrum on ``wavelength_um`` [µm] (the integral is linear in
    the values): one dot product per band instead of an interpolation.

    Returns
    -------
    ndarray (n,)
        [µm] (times the response).
    """
    lam = np.asarray(wavelength_um, dtype=float)
    return np.asarray(band_integrate(lam, np.eye(lam.size), band, response), dtype=float)
