"""Radiometry of the scene: band emissivities of the ship and the background, and the
radiance leaving a surface toward the sensor (paper eq. 2).

The optics both stages share live in :mod:`shipthermal.optics` and are re-exported here
under their usual names: Planck band radiance and its inverse
(:mod:`shipthermal.optics.planck`), sensor spectral responses
(:mod:`shipthermal.optics.responses`), water's index and Fresnel
(:mod:`shipthermal.optics.water`), the sea's band emissivity
(:mod:`shipthermal.optics.sea`) and the BRDFs (:mod:`shipthermal.optics.brdf`).
"""

from __future__ import annotations

import numpy as np

from shipthermal.errors import InputError
from shipthermal.geometry.parts import part_value
from shipthermal.optics.planck import (BandRadianceTable, as_response, band_radiance,
                                       band_radiance_dt, band_radiance_rectangular_exact,
                                       band_radiance_table, brightness_temperature,
                                       planck_radiance, planck_radiance_dt, standard_band)
from shipthermal.optics.responses import SpectralResponse, rectangular_response
from shipthermal.optics.sea import (ROUGH_SEA_QUADRATURE, rough_sea_emissivity,
                                    rough_sea_emissivity_hemispherical, sea_emissivity,
                                    water_band_mean_index)
from shipthermal.parameters import BAND_EMISSIVITY, BANDS

from .parameters import BACKGROUND_EMISSIVITY, EmissivityValue

__all__ = [
    "SHIP_EMISSIVITY", "ship_emissivity", "background_emissivity", "leaving_radiance",
]
# The optics' names stay importable from here under their earlier path; they are defined and
# documented in shipthermal.optics.
_REEXPORTS = (BandRadianceTable, as_response, band_radiance, band_radiance_dt,
              band_radiance_rectangular_exact, band_radiance_table, brightness_temperature,
              planck_radiance, planck_radiance_dt, standard_band, SpectralResponse,
              rectangular_response, ROUGH_SEA_QUADRATURE, rough_sea_emissivity,
              rough_sea_emissivity_hemispherical, sea_emissivity, water_band_mean_index,
              BACKGROUND_EMISSIVITY, EmissivityValue)

# ---------------------------------------------------------------------------------------
# Emissivities
# ---------------------------------------------------------------------------------------
SHIP_EMISSIVITY = {band: {part: values[band] for part, values in BAND_EMISSIVITY.items()}
                   for band in BANDS}
"""Ship part emissivities per band [-]: :data:`shipthermal.parameters.BAND_EMISSIVITY` (paper
§5) arranged band first."""




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

    See :data:`imaging.parameters.BACKGROUND_EMISSIVITY` for sources and uncertainties.
    """
    if band not in BACKGROUND_EMISSIVITY:
        raise InputError("band", band, f"must be one of {sorted(BACKGROUND_EMISSIVITY)}")
    classes = BACKGROUND_EMISSIVITY[band]
    if cls not in classes:
        raise InputError("class", cls, f"must be one of {sorted(classes)}")
    return classes[cls].value


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
        BRDF for (sun direction, view direction) [sr-1] (:mod:`shipthermal.optics.brdf`).
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
