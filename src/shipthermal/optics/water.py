"""Water's refractive index, Fresnel reflectance and the sea's emissivity, for both stages.

The thermal stage (:mod:`shipthermal.environment`: the sea's long-wave) and the imaging
(:mod:`shipthermal.optics.sea`, :mod:`shipthermal.optics.brdf`: the sea's band emissivity and
Cox-Munk reflectance) take one refractive index of water, one Fresnel law and one rough-sea
emissivity from here.

* Hale & Querry's (1973) complex index of liquid water (:data:`WATER_INDEX_HALE_QUERRY`),
* the unpolarised Fresnel reflectance of a smooth interface (:func:`fresnel_reflectance`),
* the flat sea's directional and hemispherical emissivity (Kirchhoff),
* the wind-roughened sea's hemispherical emissivity (:func:`sea_emissivity_rough`): the
  Cox-Munk model of :mod:`shipthermal.optics.sea` tabulated per wind speed
  (:data:`ROUGH_SEA_HEMISPHERICAL_EMISSIVITY`; the tests recompute the table from
  :func:`shipthermal.optics.sea.rough_sea_emissivity_hemispherical`).

Angles in degrees, wavelengths in micrometres, emissivities and reflectances [-].
"""

from __future__ import annotations

import numpy as np

from shipthermal.errors import check_range

__all__ = [
    "WATER_INDEX_HALE_QUERRY",
    "water_refractive_index",
    "WATER_REFRACTIVE_INDEX_10UM",
    "fresnel_reflectance",
    "sea_emissivity_angular",
    "sea_emissivity_hemispherical",
    "ROUGH_SEA_WIND_NODES",
    "ROUGH_SEA_HEMISPHERICAL_EMISSIVITY",
    "sea_emissivity_rough",
]

# Hale & Querry (1973), Appl. Opt. 12:555, Table 1, liquid water at 25 °C, 2.6-16 um:
# columns wavelength [um], n, k. (Public-domain data, as tabulated in the original paper.)
WATER_INDEX_HALE_QUERRY = np.array([
    (2.60, 1.242, 3.17e-3), (2.65, 1.219, 6.70e-3), (2.70, 1.188, 0.019), (2.75, 1.157, 0.059),
    (2.80, 1.142, 0.115), (2.85, 1.149, 0.185), (2.90, 1.201, 0.268), (2.95, 1.292, 0.298),
    (3.00, 1.371, 0.272), (3.05, 1.426, 0.240), (3.10, 1.467, 0.192), (3.15, 1.483, 0.135),
    (3.20, 1.478, 0.0924), (3.25, 1.467, 0.0610), (3.30, 1.450, 0.0368),
    (3.35, 1.432, 0.0261), (3.40, 1.420, 0.0195), (3.45, 1.410, 0.0132),
    (3.50, 1.400, 0.0094), (3.6, 1.385, 0.00515), (3.7, 1.374, 0.00360),
    (3.8, 1.364, 0.00340), (3.9, 1.357, 0.00380), (4.0, 1.351, 0.00460),
    (4.1, 1.346, 0.00562), (4.2, 1.342, 0.00688), (4.3, 1.338, 0.00845),
    (4.4, 1.334, 0.0103), (4.5, 1.332, 0.0134), (4.6, 1.330, 0.0147), (4.7, 1.330, 0.0157),
    (4.8, 1.330, 0.0150), (4.9, 1.328, 0.0137), (5.0, 1.325, 0.0124), (5.1, 1.322, 0.0111),
    (5.2, 1.317, 0.0101), (5.3, 1.312, 0.0098), (5.4, 1.305, 0.0103), (5.5, 1.298, 0.0116),
    (5.6, 1.289, 0.0142), (5.7, 1.277, 0.0203), (5.8, 1.262, 0.0330), (5.9, 1.248, 0.0622),
    (6.0, 1.265, 0.107), (6.1, 1.319, 0.131), (6.2, 1.363, 0.0880), (6.3, 1.357, 0.0570),
    (6.4, 1.347, 0.0449), (6.5, 1.339, 0.0392), (6.6, 1.334, 0.0356), (6.7, 1.329, 0.0337),
    (6.8, 1.324, 0.0327), (6.9, 1.321, 0.0322), (7.0, 1.317, 0.0320), (7.1, 1.314, 0.0320),
    (7.2, 1.312, 0.0321), (7.3, 1.309, 0.0322), (7.4, 1.307, 0.0324), (7.5, 1.304, 0.0326),
    (7.6, 1.302, 0.0328), (7.7, 1.299, 0.0331), (7.8, 1.297, 0.0335), (7.9, 1.294, 0.0339),
    (8.0, 1.291, 0.0343), (8.2, 1.286, 0.0351), (8.4, 1.281, 0.0361), (8.6, 1.275, 0.0372),
    (8.8, 1.269, 0.0385), (9.0, 1.262, 0.0399), (9.2, 1.255, 0.0415), (9.4, 1.247, 0.0433),
    (9.6, 1.239, 0.0454), (9.8, 1.229, 0.0479), (10.0, 1.218, 0.0508), (10.5, 1.185, 0.0662),
    (11.0, 1.153, 0.0968), (11.5, 1.126, 0.142), (12.0, 1.111, 0.199), (12.5, 1.123, 0.259),
    (13.0, 1.146, 0.305), (13.5, 1.177, 0.343), (14.0, 1.210, 0.370), (14.5, 1.241, 0.388),
    (15.0, 1.270, 0.402), (15.5, 1.297, 0.414), (16.0, 1.325, 0.422),
])
WATER_INDEX_HALE_QUERRY.setflags(write=False)


def water_refractive_index(wavelength_um):
    """Complex refractive index ``n + i k`` of liquid water [-] at ``wavelength_um`` [um].

    Linear interpolation in Hale & Querry (1973) Table 1 (2.6-16 um; 25 °C). Sea water's
    salinity changes n by < 0.01 in the thermal IR (Friedman 1969), neglected here.
    """
    wl = np.asarray(wavelength_um, dtype=float)
    tab = WATER_INDEX_HALE_QUERRY
    check_range("wavelength_um", wl, tab[0, 0], tab[-1, 0], "um")
    return np.interp(wl, tab[:, 0], tab[:, 1]) + 1j * np.interp(wl, tab[:, 0], tab[:, 2])


WATER_REFRACTIVE_INDEX_10UM = complex(
    *WATER_INDEX_HALE_QUERRY[WATER_INDEX_HALE_QUERRY[:, 0] == 10.0][0, 1:])
"""Complex refractive index of water at 10 µm, Hale & Querry (1973), Appl. Opt. 12,
555–563, Table I (n = 1.218, k = 5.08e-2; the 10 µm row of
:data:`WATER_INDEX_HALE_QUERRY`); representative of the 8–14 µm window."""

ROUGH_SEA_WIND_NODES = tuple(float(u) for u in range(21))
"""Wind speeds [m s-1] of :data:`ROUGH_SEA_HEMISPHERICAL_EMISSIVITY`."""
ROUGH_SEA_HEMISPHERICAL_EMISSIVITY = (
    0.94681, 0.94935, 0.95135, 0.95302, 0.95446, 0.95574, 0.95688, 0.95792, 0.95887,
    0.95974, 0.96055, 0.9613, 0.962, 0.96266, 0.96328, 0.96386, 0.96442, 0.96495,
    0.96545, 0.96592, 0.96638)
"""Hemispherical emissivity [-] of the wind-roughened sea at :data:`ROUGH_SEA_WIND_NODES`:
``shipthermal.optics.sea.rough_sea_emissivity_hemispherical("8-14", u)`` (one minus the
directional albedo of the shadowed Cox-Munk BRDF the imaging reflects sun and sky with,
Hale & Querry 8-14 µm band-mean index), rounded to 1e-5; the test recomputes it. The 8-14
µm window carries most of ``σT⁴ − L_down`` (outside it the sky is nearly black at the
air temperature), so its emissivity is the one that matters for the sea's net long-wave.
Linear interpolation between the 1 m/s nodes errs by < 1e-4."""

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
