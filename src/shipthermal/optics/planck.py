"""Planck band radiance over a sensor's spectral response, and its inverse (paper eq. 1-2).

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

import numpy as np
from scipy.special import bernoulli

from shipthermal.errors import InputError, check_positive, require
from shipthermal.units import PLANCK_C1, PLANCK_C2

from .responses import SpectralResponse, named_band

__all__ = [
    "standard_band", "as_response",
    "planck_radiance", "planck_radiance_dt",
    "band_radiance", "band_radiance_dt", "band_radiance_rectangular_exact",
    "brightness_temperature", "BandRadianceTable", "band_radiance_table",
]

# ---------------------------------------------------------------------------------------
# Spectral response (the classes live in shipthermal.optics.responses with the named bands)
# ---------------------------------------------------------------------------------------
def standard_band(name: str) -> SpectralResponse:
    """A named band's response: the paper's rectangles ``"3-5"`` and ``"8-14"`` or a real
    sensor's band (:data:`shipthermal.optics.responses.BAND_NAMES`)."""
    return named_band(name)


def as_response(band) -> SpectralResponse:
    """``band`` as a :class:`SpectralResponse`: a response passes through, a name is
    looked up (:func:`standard_band`)."""
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
    resp = as_response(band)
    w, wl = resp.quadrature(nodes_per_segment)
    t = np.asarray(temp, dtype=float)
    out = np.zeros(t.shape, dtype=float)
    # one pass per node keeps memory at the size of the image (no (npix, nnodes) temporary)
    for wj, lj in zip(w, wl):
        out += wj * kernel(lj, t, c1, c2)
    return out


def _band_sum_and_dt(temp, band, nodes_per_segment, c1, c2):
    """:func:`band_radiance` and :func:`band_radiance_dt` in one pass over the quadrature
    nodes, one ``expm1`` per node for both (the Newton steps of
    :func:`brightness_temperature`)."""
    resp = as_response(band)
    w, wl = resp.quadrature(nodes_per_segment)
    t = np.asarray(temp, dtype=float)
    lum = np.zeros(t.shape, dtype=float)
    dlum = np.zeros(t.shape, dtype=float)
    for wj, lj in zip(w, wl):
        x = c2 / (lj * t)
        em1 = np.expm1(x)
        node = (wj * c1 / lj**5) / em1
        lum += node
        dlum += node * x * (em1 + 1.0) / (em1 * t)
    return lum, dlum


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


BRIGHTNESS_NEWTON_STEP_K = 1e-9
"""Newton step of :func:`brightness_temperature` below which it stops [K]: the error
after a step is about ``(L''/2L') step²``, and ``L''/L' ≈ (x − 2)/T`` with ``x = c2/(λT)``
(0.03 K⁻¹ at 4 um and 300 K, 2.2 K⁻¹ at 4 um and 40 K): at most ~1e-18 K, far below the
round-off of the band sum. Measured on 200,000 pixels at 270–320 K: 1.1e-13 K from the
true temperature in the Landsat 8 band 10 response (800 quadrature nodes; 5.7e-14 K with
six steps), 5.7e-14 K in 8–14 um; 5.7× and 2.5× faster than six steps of separate radiance
and derivative passes."""


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
        Newton steps after the tabulated first guess, at most [-]; 6 reach round-off
        (tested). They stop once no step exceeded :data:`BRIGHTNESS_NEWTON_STEP_K` (the
        error after such a step is of the order of its square: round-off).

    Returns
    -------
    numpy.ndarray
        Brightness temperature [K].

    Notes
    -----
    First guess: linear interpolation in ``log L`` on a 40-1500 K table (log L is nearly
    linear in 1/T, so the guess is within ~1 K); then Newton on ``L(T) - radiance``, the
    radiance and its derivative from one pass over the quadrature nodes.
    """
    lum = np.asarray(radiance, dtype=float)
    check_positive("radiance", lum, "W m-2 sr-1")
    t_grid = 1.0 / np.linspace(1 / 40.0, 1 / 1500.0, 400)
    l_grid = band_radiance(t_grid, band, nodes_per_segment, c1, c2)
    ok = l_grid > 0
    temp = 1.0 / np.interp(np.log(lum), np.log(l_grid[ok]), 1.0 / t_grid[ok])
    for _ in range(iterations):
        value, slope = _band_sum_and_dt(temp, band, nodes_per_segment, c1, c2)
        step = (value - lum) / slope
        temp = temp - step
        if not np.any(np.abs(step) > BRIGHTNESS_NEWTON_STEP_K):
            break
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
