"""The sea as a radiating, reflecting boundary: SST, emissivity, albedo.

Sea surface temperature with a small diurnal warming cycle, sea emissivity (broadband
hemispherical ≈ 0.98, or angular from Fresnel's equations with water's complex
refractive index), long-wave leaving the sea (emitted + reflected sky) and short-wave
reflected by the sea (albedo for direct and diffuse light, Taylor et al. 1996).

Temperatures in K, irradiance in W m-2, angles in degrees.
"""

from __future__ import annotations

import numpy as np

from shipthermal.parameters import SEA_EMISSIVITY
from shipthermal.units import SIGMA

__all__ = [
    "SEA_EMISSIVITY",
    "WATER_REFRACTIVE_INDEX_10UM",
    "sst_diurnal",
    "fresnel_reflectance",
    "sea_emissivity_angular",
    "sea_emissivity_hemispherical",
    "ROUGH_SEA_WIND_NODES",
    "ROUGH_SEA_HEMISPHERICAL_EMISSIVITY",
    "sea_emissivity_rough",
    "sea_longwave_up",
    "sea_albedo_direct",
    "SEA_ALBEDO_DIFFUSE",
    "sea_reflected_shortwave",
]

WATER_REFRACTIVE_INDEX_10UM = complex(1.218, 0.0508)
"""Complex refractive index of water at 10 µm, Hale & Querry (1973), Appl. Opt. 12,
555–563, Table I (n = 1.218, k = 5.08e-2); representative of the 8–14 µm window."""

ROUGH_SEA_WIND_NODES = tuple(float(u) for u in range(21))
"""Wind speeds [m s-1] of :data:`ROUGH_SEA_HEMISPHERICAL_EMISSIVITY`."""
ROUGH_SEA_HEMISPHERICAL_EMISSIVITY = (
    0.94681, 0.94935, 0.95135, 0.95302, 0.95446, 0.95574, 0.95688, 0.95792, 0.95887,
    0.95974, 0.96055, 0.9613, 0.962, 0.96266, 0.96328, 0.96386, 0.96442, 0.96495,
    0.96545, 0.96592, 0.96638)
"""Hemispherical emissivity [-] of the wind-roughened sea at :data:`ROUGH_SEA_WIND_NODES`:
``imaging.radiometry.rough_sea_emissivity_hemispherical("8-14", u)`` (one minus the
directional albedo of the shadowed Cox-Munk BRDF the imaging reflects sun and sky with,
Hale & Querry 8-14 µm band-mean index), rounded to 1e-5; the test recomputes it. The 8-14
µm window carries most of ``σT⁴ − L_down`` (outside it the sky is nearly black at the
air temperature), so its emissivity is the one that matters for the sea's net long-wave.
Linear interpolation between the 1 m/s nodes errs by < 1e-4."""

SEA_ALBEDO_DIFFUSE = 0.06
"""Sea albedo for diffuse (sky) short-wave [-]: Payne (1972), J. Atmos. Sci. 29,
959–970 (≈ 0.06 for overcast skies), the value adopted by Taylor et al. (1996)."""


def sst_diurnal(hour_local, temp_sea_mean, amplitude=0.15, hour_peak=14.0):
    """Sea surface temperature with a sinusoidal diurnal cycle.

    Parameters
    ----------
    hour_local : array_like
        Local solar-ish clock time [h] (any real number; the cycle is 24 h periodic).
    temp_sea_mean : array_like
        Daily mean bulk SST [K].
    amplitude : array_like
        Half the diurnal range [K].
    hour_peak : float
        Local time of the daily maximum [h].

    Returns
    -------
    numpy.ndarray
        ``T_mean + A cos(2π (h − h_peak) / 24)`` [K].

    Notes
    -----
    Kawai & Wada (2007), "Diurnal sea surface temperature variation and its impact on
    the atmosphere and ocean: a review", J. Oceanogr. 63, 721–744: the bulk-SST
    diurnal range is typically a few tenths of a kelvin, with the maximum in the early
    afternoon (≈ 13–15 LT); it reaches > 1–3 K only under calm, sunny conditions. The
    shape here is the first harmonic only (the real curve rises faster than it falls).
    The default amplitude 0.15 K (range 0.3 K) is an ASSUMPTION within that range.
    """
    h = np.asarray(hour_local, dtype=float)
    return np.asarray(temp_sea_mean, dtype=float) + np.asarray(amplitude, dtype=float) * \
        np.cos(2.0 * np.pi * (h - hour_peak) / 24.0)


def fresnel_reflectance(cos_incidence, refractive_index):
    """Unpolarised Fresnel reflectance of a smooth interface from air.

    Parameters
    ----------
    cos_incidence : array_like
        Cosine of the local incidence angle [-], in [0, 1].
    refractive_index : complex or array_like
        Complex refractive index ``n + i k`` of the medium [-] (k >= 0 absorbing).

    Returns
    -------
    numpy.ndarray
        Reflectance ``(|r_s|² + |r_p|²) / 2`` [-].

    Notes
    -----
    Born & Wolf, Principles of Optics, §1.5 and §14.2 (absorbing media through a complex
    index): ``cos t = sqrt(1 − sin² i / m²)`` (principal branch), ``r_s = (cos i − m cos
    t)/(cos i + m cos t)``, ``r_p = (m cos i − cos t)/(m cos i + cos t)``.
    """
    ci = np.clip(np.asarray(cos_incidence, dtype=float), 0.0, 1.0)
    m = np.asarray(refractive_index, dtype=complex)
    sin2 = 1.0 - ci * ci
    ct = np.sqrt(1.0 - sin2 / (m * m))
    rs = (ci - m * ct) / (ci + m * ct)
    rp = (m * ci - ct) / (m * ci + ct)
    return 0.5 * (np.abs(rs) ** 2 + np.abs(rp) ** 2)


def sea_emissivity_angular(view_zenith, refractive_index=WATER_REFRACTIVE_INDEX_10UM):
    """Directional emissivity of a flat water surface, ``1 − R(θ)`` (Fresnel).

    Parameters
    ----------
    view_zenith : array_like
        Angle between the viewing direction and the surface normal [deg].
    refractive_index : complex
        Complex refractive index ``n + i k`` of water [-].

    Returns
    -------
    numpy.ndarray
        Emissivity averaged over s and p polarisation [-]; at nadir
        ``1 − ((n−1)² + k²) / ((n+1)² + k²)``, zero at grazing incidence.

    Notes
    -----
    :func:`fresnel_reflectance` with Kirchhoff's law ε = 1 − R for an opaque surface. A
    flat sea; wind roughening (Masuda et al. 1988) raises the emissivity at large angles.
    """
    th = np.radians(np.asarray(view_zenith, dtype=float))
    return 1.0 - fresnel_reflectance(np.cos(th), complex(refractive_index))


def sea_emissivity_hemispherical(refractive_index=WATER_REFRACTIVE_INDEX_10UM, n: int = 2000):
    """Hemispherical emissivity of a flat water surface [-].

    ``ε_h = 2 ∫_0^{π/2} ε(θ) cos θ sin θ dθ`` evaluated by the midpoint rule with ``n``
    intervals (integrand smooth; error O(n⁻²)).
    """
    th = (np.arange(n) + 0.5) * (0.5 * np.pi / n)
    eps = sea_emissivity_angular(np.degrees(th), refractive_index)
    return float(np.sum(2.0 * eps * np.cos(th) * np.sin(th)) * (0.5 * np.pi / n))


def sea_emissivity_rough(wind_speed):
    """Hemispherical emissivity of the wind-roughened sea [-] at ``wind_speed`` [m s-1].

    The imaging's rough-sea model (:data:`ROUGH_SEA_HEMISPHERICAL_EMISSIVITY`),
    interpolated linearly; winds above 20 m/s use the 20 m/s value (the Cox-Munk slope fit
    is for 1-14 m/s). Flat water (0 m/s) gives 0.947; 5 m/s 0.956; 10 m/s 0.961. Lower
    than the measured broadband 0.984 of :data:`SEA_EMISSIVITY` (Konda et al. 1994): the
    flux form ``ε σT⁴ + (1 − ε) L_down`` treats the sky as isotropic, whereas the real sky
    is warmest near the horizon, where the sea reflects most (with the LOWTRAN sky of the
    imaging the effective 8-14 µm value is 0.962-0.970 at 0-10 m/s).
    """
    u = np.clip(np.asarray(wind_speed, dtype=float), 0.0, ROUGH_SEA_WIND_NODES[-1])
    return np.interp(u, ROUGH_SEA_WIND_NODES, ROUGH_SEA_HEMISPHERICAL_EMISSIVITY)


def sea_longwave_up(temp_sea, longwave_down_wm2, emissivity=SEA_EMISSIVITY):
    """Long-wave irradiance leaving the sea surface [W m-2].

    Parameters
    ----------
    temp_sea : array_like
        Sea skin temperature [K].
    longwave_down_wm2 : array_like
        Downwelling sky long-wave irradiance [W m-2].
    emissivity : array_like
        Sea emissivity [-].

    Returns
    -------
    numpy.ndarray
        ``ε σ T_sea^4 + (1 − ε) L_down`` (emitted + reflected sky; Kirchhoff) [W m-2].
        Divide by σ and take the 4th root for the sea's effective radiating
        temperature seen by a ship face.
    """
    eps = np.asarray(emissivity, dtype=float)
    return eps * SIGMA * np.asarray(temp_sea, dtype=float) ** 4 + \
        (1.0 - eps) * np.asarray(longwave_down_wm2, dtype=float)


def sea_albedo_direct(zenith):
    """Sea albedo for the direct solar beam, Taylor et al. (1996).

    Parameters
    ----------
    zenith : array_like
        Solar zenith angle [deg].

    Returns
    -------
    numpy.ndarray
        ``0.037 / (1.1 μ^1.4 + 0.15)`` with μ = cos(zenith) (μ clipped at 0) [-].

    Notes
    -----
    Taylor, J. P., Edwards, J. M., Glew, M. D., Hignett, P. & Slingo, A. (1996),
    "Studies with a flexible new radiation code. II: Comparisons with aircraft
    short-wave observations", Q. J. R. Meteorol. Soc. 122, 839–861; a fit to
    Payne's (1972) measured albedos. Values: 0.0296 at μ = 1, 0.247 at μ = 0.
    """
    mu = np.clip(np.cos(np.radians(np.asarray(zenith, dtype=float))), 0.0, 1.0)
    return 0.037 / (1.1 * mu ** 1.4 + 0.15)


def sea_reflected_shortwave(dni, dhi, zenith, albedo_diffuse=SEA_ALBEDO_DIFFUSE):
    """Short-wave irradiance reflected upward by the sea [W m-2].

    Parameters
    ----------
    dni : array_like
        Direct normal irradiance [W m-2].
    dhi : array_like
        Diffuse horizontal irradiance [W m-2].
    zenith : array_like
        Solar zenith angle [deg].
    albedo_diffuse : float
        Albedo for diffuse light [-].

    Returns
    -------
    numpy.ndarray
        ``α_dir(Z) DNI cos Z + α_dif DHI`` [W m-2], to be treated as isotropic upward
        radiance ``/π`` by the face loading (specular glint is the imaging stage's job).
    """
    z = np.asarray(zenith, dtype=float)
    mu = np.clip(np.cos(np.radians(z)), 0.0, 1.0)
    return sea_albedo_direct(z) * np.asarray(dni, dtype=float) * mu + \
        albedo_diffuse * np.asarray(dhi, dtype=float)
