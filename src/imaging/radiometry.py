"""Radiometry: Planck band radiance, sensor spectral response, emissivities (paper eqs. 1-2).

Everything here is a pure function of numpy arrays. Wavelengths are in micrometres
(``wavelength_um``), temperatures in kelvin, spectral radiance in W m-2 sr-1 um-1 and band
radiance in W m-2 sr-1 (the band radiance is the response-weighted integral
``L_band(T) = int R(lambda) L_lambda(lambda, T) d lambda``, *not* divided by the band width).

Constants
---------
The radiation constants are those of :mod:`shipthermal.units` (``c1 = 2 h c^2``, ``c2 = h c /
k`` from the exact SI constants), with which the full-band integral equals ``sigma T^4 / pi``
to round-off. The paper (eq. 2) rounds them to ``c1 = 1.191e8 W um4 m-2 sr-1`` and ``c2 =
1.4388e4 um K``: that changes the full-band radiance by ``(1.191 / 1.191043) (1.438777 /
1.4388)^4 - 1 = -1.00e-4`` relative (c1 -3.6e-5, c2 -6.4e-5; the tests check it).

Paper typo: eq. 2 writes ``eps/pi * int c1 / (lambda^5 (exp(c2/lambda T) - 1))``. With
``c1 = 1.191e8 W um4 m-2 sr-1`` (that is ``2 h c^2``, the *radiance* constant) the extra
``1/pi`` would be counted twice; ``1/pi`` belongs with the exitance constant
``2 pi h c^2 = 3.742e8``. We use ``L = eps * int c1 / (lambda^5 (...))`` which is the
dimensionally consistent reading and reproduces ``sigma T^4 / pi``.

Band integration
----------------
:func:`band_radiance` uses Gauss-Legendre quadrature on each segment of the
spectral-response table (one segment for a rectangular band). With the default 8 nodes per
segment the relative error against the exact series of :func:`band_radiance_rectangular_exact`
is below 3e-12 for 3-5 um and 8-14 um between 150 K and 1000 K (tested). For whole images
with a long response table, :func:`band_radiance_table` builds a cubic-Hermite table in T
whose maximum relative interpolation error is measured when it is built (``max_rel_error``;
at 1 K spacing on 150-450 K: 4.4e-7 for 3-5 um, worst at 150 K where L is steepest in
relative terms, and 1.8e-9 for 8-14 um).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.special import bernoulli

from shipthermal.errors import InputError, check_positive, check_range, require
from shipthermal.geometry.parts import part_value
from shipthermal.optics import WATER_INDEX_HALE_QUERRY, fresnel_reflectance, water_refractive_index
from shipthermal.parameters import BAND_EMISSIVITY, BANDS, check_wind_speed
from shipthermal.units import PLANCK_C1, PLANCK_C2

from .quadrature import gauss_legendre
from .spectral_bands import SpectralResponse, named_band, rectangular_response

__all__ = [
    "SpectralResponse", "rectangular_response", "standard_band",
    "planck_radiance", "planck_radiance_dt",
    "band_radiance", "band_radiance_dt", "band_radiance_rectangular_exact",
    "brightness_temperature", "BandRadianceTable", "band_radiance_table",
    "SHIP_EMISSIVITY", "BACKGROUND_EMISSIVITY", "EmissivityValue",
    "ship_emissivity", "background_emissivity",
    "water_band_mean_index",
    "sea_emissivity", "rough_sea_emissivity", "rough_sea_emissivity_hemispherical",
    "leaving_radiance",
]

# ---------------------------------------------------------------------------------------
# Spectral response (the classes live in imaging.spectral_bands with the named bands)
# ---------------------------------------------------------------------------------------
def standard_band(name: str) -> SpectralResponse:
    """A named band's response: the paper's rectangles ``"3-5"`` and ``"8-14"`` or a real
    sensor's band (:data:`imaging.spectral_bands.BAND_NAMES`)."""
    return named_band(name)


def _as_response(band) -> SpectralResponse:
    return band if isinstance(band, SpectralResponse) else standard_band(band)


# ---------------------------------------------------------------------------------------
# Planck
# ---------------------------------------------------------------------------------------
def planck_radiance(wavelength_um, temp, c1: float = PLANCK_C1, c2: float = PLANCK_C2):
    """Blackbody spectral radiance.

    Parameters
    ----------
    wavelength_um : array_like
        Wavelength [um].
    temp : array_like
        Temperature [K]; broadcast against ``wavelength_um``.
    c1 : float
        First radiation constant [W um4 m-2 sr-1]; default ``2 h c^2`` (SI exact).
    c2 : float
        Second radiation constant [um K]; default ``h c / k`` (SI exact).

    Returns
    -------
    numpy.ndarray
        Spectral radiance [W m-2 sr-1 um-1].

    Notes
    -----
    Paper eq. 2 integrand, ``L = c1 / (lambda^5 (exp(c2 / (lambda T)) - 1))``; ``expm1``
    keeps full precision in the Rayleigh-Jeans limit.
    """
    wl = np.asarray(wavelength_um, dtype=float)
    t = np.asarray(temp, dtype=float)
    return c1 / (wl**5 * np.expm1(c2 / (wl * t)))


def planck_radiance_dt(wavelength_um, temp, c1: float = PLANCK_C1, c2: float = PLANCK_C2):
    """Temperature derivative of :func:`planck_radiance` [W m-2 sr-1 um-1 K-1].

    ``dL/dT = L * x exp(x) / (T (exp(x) - 1))`` with ``x = c2 / (lambda T)``.
    Parameters as :func:`planck_radiance` (``wavelength_um`` [um], ``temp`` [K]).
    """
    wl = np.asarray(wavelength_um, dtype=float)
    t = np.asarray(temp, dtype=float)
    x = c2 / (wl * t)
    em1 = np.expm1(x)
    return c1 / (wl**5 * em1) * x * (em1 + 1.0) / (em1 * t)


def _band_sum(kernel, temp, band, nodes_per_segment, c1, c2):
    resp = _as_response(band)
    w, wl = resp.quadrature(nodes_per_segment)
    t = np.asarray(temp, dtype=float)
    out = np.zeros(t.shape, dtype=float)
    # one pass per node keeps memory at the size of the image (no (npix, nnodes) temporary)
    for wj, lj in zip(w, wl):
        out += wj * kernel(lj, t, c1, c2)
    return out


def band_radiance(temp, band="8-14", nodes_per_segment: int = 8,
                  c1: float = PLANCK_C1, c2: float = PLANCK_C2):
    """Blackbody band radiance ``int R(lambda) L_lambda(lambda, T) d lambda``.

    Parameters
    ----------
    temp : array_like
        Temperature [K], any shape (e.g. a whole image).
    band : str or SpectralResponse
        ``"3-5"``, ``"8-14"`` (rectangular) or a user response table.
    nodes_per_segment : int
        Gauss-Legendre nodes per response-table segment [-].
    c1, c2 : float
        Radiation constants [W um4 m-2 sr-1], [um K] (SI exact by default).

    Returns
    -------
    numpy.ndarray
        Band radiance [W m-2 sr-1], same shape as ``temp``.

    Notes
    -----
    Paper eq. 2, first term (with ``eps = 1``). Relative quadrature error < 3e-12 for the
    default bands and 8 nodes at 150-1000 K (tested against the exact series).
    """
    return _band_sum(planck_radiance, temp, band, nodes_per_segment, c1, c2)


def band_radiance_dt(temp, band="8-14", nodes_per_segment: int = 8,
                     c1: float = PLANCK_C1, c2: float = PLANCK_C2):
    """Temperature derivative of :func:`band_radiance` [W m-2 sr-1 K-1].

    Same parameters as :func:`band_radiance` (``temp`` [K]). Used for NETD -> noise-equivalent
    radiance and for Newton steps in :func:`brightness_temperature`.
    """
    return _band_sum(planck_radiance_dt, temp, band, nodes_per_segment, c1, c2)


_BERNOULLI = bernoulli(40)


def _planck_tail(x):
    """``G(x) = int_x^inf t^3 / (e^t - 1) dt`` to round-off, vectorised (x >= 0 or inf).

    x >= 1: ``sum_n e^{-n x} (x^3/n + 3x^2/n^2 + 6x/n^3 + 6/n^4)`` (Widger & Woodall 1976),
    45 terms (``e^{-45} ~ 3e-20``). x < 1: ``pi^4/15 - sum_m B_m x^{m+3} / (m! (m+3))`` from
    the Bernoulli expansion of ``t/(e^t - 1)`` (radius 2 pi; 40 terms -> ``(1/2pi)^40``).
    """
    x = np.asarray(x, dtype=float)
    out = np.empty_like(x)
    big = x >= 1.0
    xb = np.where(big & np.isfinite(x), x, 1.0)
    n = np.arange(1, 46, dtype=float).reshape((-1,) + (1,) * x.ndim)
    series = np.exp(-n * xb) * (xb**3 / n + 3 * xb**2 / n**2 + 6 * xb / n**3 + 6 / n**4)
    out[big] = series.sum(axis=0)[big]
    out[np.isinf(x)] = 0.0
    xs = np.where(big, 0.0, x)
    acc = np.zeros_like(xs)
    for m in range(40, -1, -1):
        if _BERNOULLI[m] != 0.0:
            acc += _BERNOULLI[m] * xs ** (m + 3) / (math.factorial(m) * (m + 3))
    out[~big] = (math.pi**4 / 15.0 - acc)[~big]
    return out


def band_radiance_rectangular_exact(temp, low_um, high_um,
                                    c1: float = PLANCK_C1, c2: float = PLANCK_C2):
    """Exact blackbody radiance over a rectangular band, from a convergent series.

    Parameters
    ----------
    temp : array_like
        Temperature [K].
    low_um, high_um : float
        Band edges [um]; ``low_um = 0`` and ``high_um = inf`` are allowed (full band).
    c1, c2 : float
        Radiation constants [W um4 m-2 sr-1], [um K].

    Returns
    -------
    numpy.ndarray
        Band radiance [W m-2 sr-1].

    Notes
    -----
    With ``x = c2 / (lambda T)``: ``L = c1 T^4 / c2^4 [G(x_high) - G(x_low)]``, ``G`` from
    :func:`_planck_tail`. Independent of any wavelength quadrature, so it is the reference
    for :func:`band_radiance`. Full band: ``c1 pi^4 T^4 / (15 c2^4)`` (= ``sigma T^4 / pi``
    with the default constants).
    """
    t = np.asarray(temp, dtype=float)
    with np.errstate(divide="ignore"):
        x_low = c2 / (low_um * t) if low_um > 0 else np.full(t.shape, np.inf)
    x_high = c2 / (high_um * t) if np.isfinite(high_um) else np.zeros(t.shape)
    return c1 * t**4 / c2**4 * (_planck_tail(x_high) - _planck_tail(x_low))


def brightness_temperature(radiance, band="8-14", nodes_per_segment: int = 8,
                           c1: float = PLANCK_C1, c2: float = PLANCK_C2, iterations: int = 6):
    """Invert :func:`band_radiance`: the blackbody temperature giving ``radiance``.

    Parameters
    ----------
    radiance : array_like
        Band radiance [W m-2 sr-1], > 0.
    band : str or SpectralResponse
        The band the radiance belongs to.
    nodes_per_segment : int
        Quadrature nodes, as in :func:`band_radiance` [-].
    c1, c2 : float
        Radiation constants [W um4 m-2 sr-1], [um K].
    iterations : int
        Newton steps after the tabulated first guess [-]; 6 reach round-off (tested).

    Returns
    -------
    numpy.ndarray
        Brightness temperature [K].

    Notes
    -----
    First guess: linear interpolation in ``log L`` on a 40-1500 K table (log L is nearly
    linear in 1/T, so the guess is within ~1 K); then Newton on ``L(T) - radiance``.
    """
    lum = np.asarray(radiance, dtype=float)
    check_positive("radiance", lum, "W m-2 sr-1")
    t_grid = 1.0 / np.linspace(1 / 40.0, 1 / 1500.0, 400)
    l_grid = band_radiance(t_grid, band, nodes_per_segment, c1, c2)
    ok = l_grid > 0
    temp = 1.0 / np.interp(np.log(lum), np.log(l_grid[ok]), 1.0 / t_grid[ok])
    for _ in range(iterations):
        f = band_radiance(temp, band, nodes_per_segment, c1, c2) - lum
        temp = temp - f / band_radiance_dt(temp, band, nodes_per_segment, c1, c2)
    return temp


@dataclass(frozen=True)
class BandRadianceTable:
    """Cubic-Hermite table of band radiance in temperature (fast path for big images).

    Attributes
    ----------
    temp : numpy.ndarray
        Uniform temperature knots [K].
    radiance : numpy.ndarray
        Band radiance at the knots [W m-2 sr-1].
    radiance_dt : numpy.ndarray
        Its temperature derivative at the knots [W m-2 sr-1 K-1].
    max_rel_error : float
        Largest relative error against :func:`band_radiance`, measured when built at five
        points around each interval midpoint (where the Hermite error term
        ``h^4 L''''/384`` peaks) [-].
    """

    temp: np.ndarray
    radiance: np.ndarray
    radiance_dt: np.ndarray
    max_rel_error: float

    def __call__(self, temp):
        """Band radiance [W m-2 sr-1] at ``temp`` [K] (must lie inside the table)."""
        t = np.asarray(temp, dtype=float)
        t0, h = self.temp[0], self.temp[1] - self.temp[0]
        if t.size and (t.min() < t0 or t.max() > self.temp[-1]):
            raise InputError("temp", t, f"must lie in the table range [{t0:g}, "
                             f"{self.temp[-1]:g}] K", "Build a wider table")
        u = (t - t0) / h
        i = np.minimum(u.astype(np.intp), self.temp.size - 2)
        s = u - i
        s2, s3 = s * s, s * s * s
        return ((2 * s3 - 3 * s2 + 1) * self.radiance[i] + (s3 - 2 * s2 + s) * h
                * self.radiance_dt[i] + (-2 * s3 + 3 * s2) * self.radiance[i + 1]
                + (s3 - s2) * h * self.radiance_dt[i + 1])


def band_radiance_table(band="8-14", temp_min: float = 150.0, temp_max: float = 450.0,
                        temp_step: float = 1.0, nodes_per_segment: int = 8,
                        c1: float = PLANCK_C1, c2: float = PLANCK_C2) -> BandRadianceTable:
    """Build a :class:`BandRadianceTable` for ``band`` on ``[temp_min, temp_max]`` [K].

    ``temp_step`` [K] is the knot spacing; the achieved maximum relative error is measured
    and stored in ``max_rel_error`` (4.4e-7 for 3-5 um, 1.8e-9 for 8-14 um at 1 K).
    """
    check_positive("temp_min", temp_min, "K")
    require(temp_max > temp_min, "temp_max", temp_max, f"must exceed temp_min={temp_min}")
    check_positive("temp_step", temp_step, "K")
    n = int(math.ceil((temp_max - temp_min) / temp_step)) + 1
    t = temp_min + temp_step * np.arange(n)
    lum = band_radiance(t, band, nodes_per_segment, c1, c2)
    dl = band_radiance_dt(t, band, nodes_per_segment, c1, c2)
    table = BandRadianceTable(t, lum, dl, 0.0)
    # the Hermite error s^2 (1-s)^2 h^4 L''''(xi) / 24 peaks near s = 0.5; probing five
    # points per interval catches the drift of L'''' across it
    probe = (t[:-1, None] + temp_step * np.array([0.3, 0.4, 0.5, 0.6, 0.7])[None, :]).ravel()
    exact = band_radiance(probe, band, nodes_per_segment, c1, c2)
    err = float(np.max(np.abs(table(probe) / exact - 1.0)))
    return BandRadianceTable(t, lum, dl, err)


# ---------------------------------------------------------------------------------------
# Emissivities
# ---------------------------------------------------------------------------------------
SHIP_EMISSIVITY = {band: {part: values[band] for part, values in BAND_EMISSIVITY.items()}
                   for band in BANDS}
"""Ship part emissivities per band [-]: :data:`shipthermal.parameters.BAND_EMISSIVITY` (paper
§5) arranged band first."""


@dataclass(frozen=True)
class EmissivityValue:
    """A band emissivity with its uncertainty and source.

    Attributes
    ----------
    value : float
        Band-mean hemispherical (near-normal) emissivity [-].
    uncertainty : float
        Spread of the cited measurements around ``value`` [-].
    source : str
        Where the number comes from.
    """

    value: float
    uncertainty: float
    source: str


_SD92 = ("Salisbury & D'Aria 1992, Remote Sens. Environ. 42:83-106 (8-14 um, "
         "directional-hemispherical reflectance -> emissivity by Kirchhoff)")
_SD94 = ("Salisbury & D'Aria 1994, Remote Sens. Environ. 47:345-361 (3-5 um)")
_SUTH = "Sutherland 1986, J. Atmos. Oceanic Technol. 3:199-202 (8-14 um radiometer)"
_HQ = ("Fresnel, flat water, nadir, band-mean complex index of Hale & Querry 1973, "
       "Appl. Opt. 12:555; see sea_emissivity() for the angular dependence")

BACKGROUND_EMISSIVITY = {
    "3-5": {
        "water": EmissivityValue(0.975, 0.005, _HQ),
        "vegetation": EmissivityValue(0.96, 0.02, "green foliage; " + _SD94),
        "land": EmissivityValue(0.86, 0.05, "soils / sand / bare concrete yard, dry; " + _SD94),
        "building": EmissivityValue(0.89, 0.04, "concrete, roofing; " + _SD94),
    },
    "8-14": {
        "water": EmissivityValue(0.988, 0.005, _HQ),
        "vegetation": EmissivityValue(0.98, 0.01, "green foliage, grass; " + _SD92
                                      + "; " + _SUTH),
        "land": EmissivityValue(0.94, 0.03, "soils 0.89-0.96 (quartz sands lowest); " + _SD92
                                + "; " + _SUTH),
        "building": EmissivityValue(0.94, 0.02, "concrete, roofing; " + _SD92),
    },
}
"""Background class emissivities per band [-]. Representative band means of the cited
measurements, rounded to 0.01 with the spread of the materials as ``uncertainty``: they were
*not* recomputed here from library spectra (no spectral library ships offline). Water is the
Fresnel value computed by :func:`sea_emissivity` at nadir (the test checks this)."""


def ship_emissivity(part: str, band: str) -> float:
    """Emissivity [-] of ship ``part`` in ``band`` (3-5, 8-14): a main part, ``hull`` or a
    sub-part, looked up by the one part policy (:func:`shipthermal.geometry.parts.part_value`:
    part, main part, hull).

    Notes
    -----
    :data:`shipthermal.parameters.BAND_EMISSIVITY` (paper §5).
    """
    if band not in SHIP_EMISSIVITY:
        raise InputError("band", band, f"must be one of {sorted(SHIP_EMISSIVITY)}")
    return part_value(SHIP_EMISSIVITY[band], part, f"{band} emissivity")


def background_emissivity(cls: str, band: str) -> float:
    """Emissivity [-] of a background class (water, vegetation, land, building) in ``band``.

    See :data:`BACKGROUND_EMISSIVITY` for sources and uncertainties.
    """
    if band not in BACKGROUND_EMISSIVITY:
        raise InputError("band", band, f"must be one of {sorted(BACKGROUND_EMISSIVITY)}")
    classes = BACKGROUND_EMISSIVITY[band]
    if cls not in classes:
        raise InputError("class", cls, f"must be one of {sorted(classes)}")
    return classes[cls].value


def water_band_mean_index(band="8-14") -> complex:
    """Response-weighted band mean of the Hale & Querry complex index of water [-]
    (:data:`shipthermal.optics.WATER_INDEX_HALE_QUERRY`).

    ``band`` is ``"3-5"``, ``"8-14"`` or a :class:`SpectralResponse` inside 2.6-16 um.
    Means of n and of k taken separately (``int R n d lambda / int R d lambda``); 3-5 um:
    1.3706 + 0.0307 i (k raised by the 3.0 um O-H band edge), 8-14 um: 1.1895 + 0.1487 i.
    """
    resp = _as_response(band)
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
    with the complex-index Fresnel equations (:func:`shipthermal.optics.fresnel_reflectance`).
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
    resp = _as_response(band)
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
    from imaging.brdf import cox_munk_brdf, directional_albedo

    n_mu, n_phi = ROUGH_SEA_QUADRATURE
    return directional_albedo(cox_munk_brdf, theta_deg, 0.0, n_mu=n_mu, n_phi=n_phi,
                              method="half", wind_speed=wind_speed,
                              refractive_index=complex(index_re, index_im), shadowing=True)


def rough_sea_emissivity(view_zenith, band, wind_speed):
    """Directional emissivity of a wind-roughened sea, consistent with its reflectance.

    ``eps(theta) = 1 - a(theta)``, ``a`` the directional-hemispherical reflectance of the
    same Cox-Munk BRDF with Smith shadowing that reflects sun and sky in the image
    (:func:`imaging.brdf.cox_munk_brdf`, isotropic slopes, band-mean index of
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
    resp = _as_response(band)
    return _rough_sea_hemispherical(resp.name, resp.wavelength_um.tobytes(),
                                    resp.response.tobytes(), float(wind_speed), int(n_nodes))


@lru_cache(maxsize=64)  # per (response, wind): the renderer asks once per frame
def _rough_sea_hemispherical(name, wavelength_bytes, response_bytes, wind_speed, n_nodes):
    band = SpectralResponse(name, np.frombuffer(wavelength_bytes), np.frombuffer(response_bytes))
    x, w = gauss_legendre(int(n_nodes))
    mu = 0.5 * (x + 1.0)
    eps = rough_sea_emissivity(np.degrees(np.arccos(mu)), band, wind_speed)
    return float(np.sum(w * mu * eps))


# ---------------------------------------------------------------------------------------
# Surface-leaving radiance (eq. 2)
# ---------------------------------------------------------------------------------------
def leaving_radiance(emitted_blackbody, emissivity, brdf=0.0, cos_sun_zenith=0.0,
                     solar_irradiance=0.0, sky_radiance=0.0, sky_reflectance=None):
    """Radiance leaving an opaque surface toward the sensor, paper eq. 2.

    Parameters
    ----------
    emitted_blackbody : array_like
        Blackbody band radiance at the surface temperature [W m-2 sr-1]
        (:func:`band_radiance`).
    emissivity : array_like
        Directional band emissivity toward the sensor [-].
    brdf : array_like
        BRDF for (sun direction, view direction) [sr-1] (:mod:`imaging.brdf`).
    cos_sun_zenith : array_like
        Cosine of the sun's incidence angle on the surface [-]; values < 0 (sun behind the
        surface) count as 0.
    solar_irradiance : array_like
        In-band solar irradiance at ground level on a plane normal to the beam
        (``tau_s E_sun`` of eq. 2) [W m-2].
    sky_radiance : array_like
        Mean in-band downwelling sky radiance [W m-2 sr-1].
    sky_reflectance : array_like or None
        Hemispherical-directional reflectance for the sky term [-]; default ``1 -
        emissivity`` (Kirchhoff, opaque surface).

    Returns
    -------
    numpy.ndarray
        Leaving radiance [W m-2 sr-1].

    Notes
    -----
    ``L = eps B(T) + tau_s E_sun cos(theta_i) f_r + rho L_sky`` (eq. 2). The sky term
    treats the sky as isotropic; ``rho`` is then exactly the directional-hemispherical
    reflectance by reciprocity.
    """
    eps = np.asarray(emissivity, dtype=float)
    rho = 1.0 - eps if sky_reflectance is None else np.asarray(sky_reflectance, dtype=float)
    mu = np.maximum(np.asarray(cos_sun_zenith, dtype=float), 0.0)
    return eps * emitted_blackbody + solar_irradiance * mu * brdf + rho * sky_radiance
