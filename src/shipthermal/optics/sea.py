"""The sea's band emissivity, flat and wind-roughened, from water's index and Fresnel.

Flat water: Kirchhoff over the Fresnel reflectance with Hale & Querry's index, band-mean or
Planck-weighted over a sensor's response (:func:`sea_emissivity`). Rough water: one minus the
directional albedo of the same shadowed Cox-Munk BRDF that reflects sun and sky in the image
(:func:`rough_sea_emissivity`), so emission and reflection add to one. The thermal stage's
hemispherical table (:data:`shipthermal.optics.water.ROUGH_SEA_HEMISPHERICAL_EMISSIVITY`) is
this module's :func:`rough_sea_emissivity_hemispherical` at 8-14 µm (the tests recompute it).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from shipthermal.errors import check_range, require
from shipthermal.parameters import check_wind_speed

from .brdf import cox_munk_brdf, directional_albedo
from .planck import as_response, planck_radiance
from .quadrature import gauss_legendre
from .responses import SpectralResponse
from .water import WATER_INDEX_HALE_QUERRY, fresnel_reflectance, water_refractive_index

__all__ = ["water_band_mean_index", "sea_emissivity", "ROUGH_SEA_QUADRATURE",
           "rough_sea_emissivity", "rough_sea_emissivity_hemispherical"]


def water_band_mean_index(band="8-14") -> complex:
    """Response-weighted band mean of the Hale & Querry complex index of water [-]
    (:data:`shipthermal.optics.water.WATER_INDEX_HALE_QUERRY`).

    ``band`` is ``"3-5"``, ``"8-14"`` or a :class:`SpectralResponse` inside 2.6-16 um.
    Means of n and of k taken separately (``int R n d lambda / int R d lambda``); 3-5 um:
    1.3706 + 0.0307 i (k raised by the 3.0 um O-H band edge), 8-14 um: 1.1895 + 0.1487 i.
    """
    resp = as_response(band)
    # band-mean of a piecewise-linear table: integrate on the union of both knot sets
    knots = np.union1d(resp.wavelength_um, WATER_INDEX_HALE_QUERRY[:, 0])
    knots = knots[(knots >= resp.wavelength_um[0]) & (knots <= resp.wavelength_um[-1])]
    r = np.interp(knots, resp.wavelength_um, resp.response)
    m = water_refractive_index(knots)
    # product of two linear functions on each knot interval: Simpson is exact
    mid = 0.5 * (knots[1:] + knots[:-1])
    rm = np.interp(mid, resp.wavelength_um, resp.response)
    mm = water_refractive_index(mid)
    h = np.diff(knots)
    num = np.sum(h / 6 * (r[:-1] * m[:-1] + 4 * rm * mm + r[1:] * m[1:]))
    den = np.sum(h / 6 * (r[:-1] + 4 * rm + r[1:]))
    return complex(num / den)


def sea_emissivity(view_zenith, band="8-14", temp=None, nodes_per_segment: int = 8,
                   wind_speed=None):
    """Directional emissivity of the sea: flat (``1 - R_Fresnel(theta)``) or, with a
    ``wind_speed``, rough (:func:`rough_sea_emissivity`).

    Parameters
    ----------
    view_zenith : array_like
        Emission (view) zenith angle at the surface [deg], 0..90.
    band : str or SpectralResponse
        Band (within 2.6-16 um).
    temp : float or None
        If given, water temperature [K]: the emissivity is the Planck-weighted spectral
        average ``int R eps(lambda) B(lambda,T) / int R B`` with the tabulated spectral index.
        If None (default), Fresnel with the band-mean index of :func:`water_band_mean_index`.
    nodes_per_segment : int
        Quadrature nodes for the spectral average [-].
    wind_speed : float or None
        None: flat water. Otherwise the wind speed [m s-1] of the Cox-Munk slopes: the
        rough-sea emissivity :func:`rough_sea_emissivity` (band-mean index; ``temp`` must
        then be None).

    Returns
    -------
    numpy.ndarray
        Emissivity [-].

    Notes
    -----
    Kirchhoff's law for an opaque specular surface: ``eps(theta) = 1 - (R_s + R_p)/2``
    with the complex-index Fresnel equations (:func:`shipthermal.optics.water.fresnel_reflectance`).
    The flat surface ignores the wave slopes that raise the emissivity at large view
    angles (Masuda et al. 1988, Remote Sens. Environ. 24:313): the imaging uses the
    rough form, which closes with its Cox-Munk reflectance.
    """
    theta = np.asarray(view_zenith, dtype=float)
    check_range("view_zenith", theta, 0.0, 90.0, "deg")
    if wind_speed is not None:
        require(temp is None, "temp", temp, "must be None with wind_speed (the rough-sea "
                "emissivity uses the band-mean index)")
        return rough_sea_emissivity(theta, band, wind_speed)
    cos_t = np.cos(np.radians(theta))
    if temp is None:
        return 1.0 - fresnel_reflectance(cos_t, water_band_mean_index(band))
    resp = as_response(band)
    w, wl = resp.quadrature(nodes_per_segment)
    b = w * planck_radiance(wl, temp)
    n = water_refractive_index(wl)
    refl = fresnel_reflectance(cos_t[..., None], n)
    return 1.0 - np.sum(refl * b, axis=-1) / np.sum(b)


ROUGH_SEA_QUADRATURE = (96, 192)
"""Nodes (polar, azimuth) of the albedo integral behind :func:`rough_sea_emissivity`
(half-vector Gauss-Legendre x periodic trapezoid): against 256 x 512 nodes the emissivity
differs by < 6e-5 over 0-89 deg, 0-20 m/s, both bands (largest at 80 deg, 0-1 m/s)."""


@lru_cache(maxsize=4096)  # pure function of floats; scenes ask for few (band, wind, angle)
def _rough_albedo(theta_deg: float, index_re: float, index_im: float,
                  wind_speed: float) -> float:
    n_mu, n_phi = ROUGH_SEA_QUADRATURE
    return directional_albedo(cox_munk_brdf, theta_deg, 0.0, n_mu=n_mu, n_phi=n_phi,
                              method="half", wind_speed=wind_speed,
                              refractive_index=complex(index_re, index_im), shadowing=True)


def rough_sea_emissivity(view_zenith, band, wind_speed):
    """Directional emissivity of a wind-roughened sea, consistent with its reflectance.

    ``eps(theta) = 1 - a(theta)``, ``a`` the directional-hemispherical reflectance of the
    same Cox-Munk BRDF with Smith shadowing that reflects sun and sky in the image
    (:func:`shipthermal.optics.brdf.cox_munk_brdf`, isotropic slopes, band-mean index of
    :func:`water_band_mean_index`). By Kirchhoff's law and reciprocity emission toward
    ``theta`` and reflection of isotropic light into ``theta`` then add to one.

    Parameters
    ----------
    view_zenith : array_like
        Emission (view) zenith angle [deg], 0..90.
    band : str or SpectralResponse
        Band (within 2.6-16 um).
    wind_speed : float
        Wind speed [m s-1] of the Cox-Munk slope variance.

    Returns
    -------
    numpy.ndarray
        Emissivity [-].

    Notes
    -----
    Near nadir it equals the flat-water Fresnel value within 1e-4 (5 m/s); at large angles
    the slopes raise it (8-14 um, 5 m/s: 0.806 -> 0.857 at 75 deg, 0.670 -> 0.797 at 80
    deg), as in Masuda, Takashima & Takayama (1988), Remote Sens. Environ. 24:313-329.
    Radiation reflected between facets (emitted by one wave, reflected by another) and
    light shadowed by the Smith term count as absorbed: the emissivity is that of the
    single-reflection BRDF, exactly the complement of the reflectance the renderer uses.
    Cost: ~20 ms per new (angle, band, wind) on one core, cached.
    """
    theta = np.asarray(view_zenith, dtype=float)
    check_range("view_zenith", theta, 0.0, 90.0, "deg")
    check_wind_speed("wind_speed", wind_speed)
    m = water_band_mean_index(band)
    alb = [_rough_albedo(float(t), m.real, m.imag, float(wind_speed)) for t in theta.ravel()]
    return 1.0 - np.reshape(alb, theta.shape)


def rough_sea_emissivity_hemispherical(band, wind_speed, n_nodes: int = 24):
    """Hemispherical emissivity of the rough sea, ``2 int eps(theta) cos sin dtheta`` [-].

    Gauss-Legendre in ``mu = cos(theta)`` with ``n_nodes`` nodes over
    :func:`rough_sea_emissivity` (smooth in mu: 24 nodes agree with 48 within 1e-5).
    """
    resp = as_response(band)
    return _rough_sea_hemispherical(resp.name, resp.wavelength_um.tobytes(),
                                    resp.response.tobytes(), float(wind_speed), int(n_nodes))


@lru_cache(maxsize=64)  # per (response, wind): the renderer asks once per frame
def _rough_sea_hemispherical(name, wavelength_bytes, response_bytes, wind_speed, n_nodes):
    band = SpectralResponse(name, np.frombuffer(wavelength_bytes), np.frombuffer(response_bytes))
    x, w = gauss_legendre(int(n_nodes))
    mu = 0.5 * (x + 1.0)
    eps = rough_sea_emissivity(np.degrees(np.arccos(mu)), band, wind_speed)
    return float(np.sum(w * mu * eps))
