"""Sensor bands: band integration of spectral atmosphere quantities and Planck radiance."""

from __future__ import annotations

import numpy as np

from shipthermal.errors import InputError

__all__ = ["BANDS", "parse_band", "band_integrate", "planck_radiance_um"]

#: Default rectangular sensor bands [µm] (paper §5)
BANDS = {"3-5": (3.0, 5.0), "8-14": (8.0, 14.0)}
_ALIASES = {"mwir": "3-5", "3-5um": "3-5", "lwir": "8-14", "8-14um": "8-14"}

#: Second radiation constant [µm K] and 2hc² [W µm⁴ m⁻² sr⁻¹] (CODATA 2018)
_C2 = 14387.7688
_C1L = 1.191042972e8


def parse_band(band) -> tuple[str, tuple[float, float]]:
    """Name and limits [µm] of a band given as ``"3-5"``, ``"8-14"``, ``"mwir"``,
    ``"lwir"`` or a ``(low_um, high_um)`` pair."""
    if isinstance(band, str):
        key = _ALIASES.get(band.lower().replace(" ", "").replace("µm", "um"), band)
        if key not in BANDS:
            raise InputError("band", band, f"one of {sorted(BANDS)} or a (low_um, high_um) pair",
                             "Use '3-5' or '8-14', or pass wavelengths in micrometres")
        return key, BANDS[key]
    try:
        lo, hi = (float(b) for b in band)
    except (TypeError, ValueError):
        raise InputError("band", band, "a band name or a (low_um, high_um) pair") from None
    if not (2.9 <= lo < hi <= 14.5):
        raise InputError("band", band, "must satisfy 2.9 <= low < high <= 14.5 µm",
                         "The atmosphere tables cover 2.9–14.5 µm")
    for name, lim in BANDS.items():
        if np.allclose(lim, (lo, hi)):
            return name, lim
    return f"{lo:g}-{hi:g}", (lo, hi)


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
    response : tuple of arrays, optional
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


def planck_radiance_um(wavelength_um, temp_k):
    """Blackbody spectral radiance [W m⁻² sr⁻¹ µm⁻¹] at wavelength [µm], temperature [K]."""
    lam = np.asarray(wavelength_um, dtype=float)
    t = np.asarray(temp_k, dtype=float)
    return _C1L / lam ** 5 / np.expm1(_C2 / (lam * t))
