"""Named parameters of the imaging stage, each written once with its source.

The sensor, the atmosphere and the port background read them from here, and so does the
scenario, which validates a file against them without importing the heavy modules (scipy,
rasterio, the atmosphere tables). The module imports only the named sensor bands
(:data:`SENSOR_BANDS`: the names of :data:`shipthermal.optics.responses.NAMED_BANDS`, where each
band is defined once; numpy only).

The paper's band list, the surface optics and the other values both stages share live in
:mod:`shipthermal.parameters`.
"""

from __future__ import annotations

from dataclasses import dataclass

from shipthermal.optics.responses import BAND_NAMES as SENSOR_BANDS

__all__ = ["PAPER_SENSOR_PARAMETERS", "MAX_VIEW_ZENITH", "VARIOGRAM_MODELS", "MET_UNITS",
           "N_SPLITS", "DEM_NODATA", "SYNTHETIC_PIXEL_M", "BACKGROUND_MODELS", "RESIDUAL_MODES",
           "SATELLITE_NAMES", "ATMOSPHERE_MODELS", "CLOUD_TYPES", "DEFAULT_CLOUD_TYPE",
           "SENSOR_BANDS", "SENSOR_PRESETS", "MAX_TLE_DISTANCE_DAYS", "CLASS_NAMES",
           "EmissivityValue", "BACKGROUND_EMISSIVITY"]

# ---------------------------------------------------------------------------------------
# Sensor
# ---------------------------------------------------------------------------------------
PAPER_SENSOR_PARAMETERS: dict[str, float] = {
    "altitude_m": 795.0e3,
    "focal_length_m": 1.06,
    "aperture_m": 0.53,
    "pixel_pitch_m": 40.0e-6,
    "optics_transmittance": 0.7,
}
"""The paper's sensor (§5): 795 km orbit [m], focal length 1.06 m, aperture 0.53 m
(f-number 2.0), 40 µm pixels [m], optics transmittance 0.7 [-]; nadir ground sample
distance ``795e3 * 40e-6 / 1.06 = 30.0 m``. The defaults of
:class:`imaging.sensor.SensorSpec`."""

# ---------------------------------------------------------------------------------------
# Atmosphere
# ---------------------------------------------------------------------------------------
MAX_VIEW_ZENITH: dict[str, float] = {"table": 80.0, "lowtran": 85.0}
"""Largest view zenith angle at the ground per atmosphere backend [deg]: the embedded
tables' view-zenith axis ends at 80°; live LOWTRAN is accepted to 85°."""

# ---------------------------------------------------------------------------------------
# Port background
# ---------------------------------------------------------------------------------------
VARIOGRAM_MODELS = ("spherical", "exponential", "gaussian", "linear", "power")
"""Variogram models of the ordinary kriging of the met grid (pykrige's names)."""

MET_UNITS = ("auto", "K", "degC", "degF")
"""Accepted temperature unit overrides of a met grid (``auto`` = the file's ``units``
attribute)."""

N_SPLITS = 10
"""Held-out ROI splits the classification accuracy is averaged over (one split swings with
its seed)."""

DEM_NODATA = ("error", "mask", "fill")
"""What the background may do with DEM voids over land: refuse, mask the pixels, or fill
them by interpolation."""

SYNTHETIC_PIXEL_M = 30.0
"""Pixel size of the built-in synthetic port [m]: the Landsat 8/9 surface-temperature and
reflectance grid."""

BACKGROUND_MODELS = ("physical", "paper")
"""Port background models: ``physical`` (a surface energy balance per pixel driven by the
run's environment, :mod:`imaging.background.physical`) and ``paper`` (the paper's Landsat
LST + kriged met grid + terrain regression, :mod:`imaging.background.background`)."""

RESIDUAL_MODES = ("solar", "constant", "none")
"""How the physical background carries the part of a scene's LST its fitted model cannot
reach through the day (:mod:`imaging.background.physical`): ``solar`` (default: scaled by
the global irradiance relative to the overpass, so a daytime misfit — a weather that does
not match the scene's day, a surface the class table does not describe — fades at night; a
night overpass keeps it constant), ``constant`` (the observed detail the model cannot
explain stays all day), ``none`` (the model alone, ``T(t_ov) = LST - residual``). With
``solar`` and ``constant``, ``T(t_ov) = LST`` exactly."""

MAX_TLE_DISTANCE_DAYS = 366.0
"""Farthest a span's instant may lie from the epoch of the user's two-line elements [days].
ASSUMPTION, from SGP4's error growth: about 1 km at the epoch and 1-3 km a day along the
track (Vallado et al. 2006, "Revisiting Spacetrack Report #3", AIAA 2006-6753). A year puts
a pass 50-150 s off (at ~7 km/s), and the Earth turns the ground track by
465 m/s x cos(latitude) x that time: 20-70 km at the equator, inside a 185 km swath's half
width but not far from its edge; orbit-keeping manoeuvres after the epoch are in no element
set. Beyond a year the passes are guesses, decades away SGP4 does not hold at all."""

SATELLITE_NAMES = ("landsat8", "landsat9")
"""Satellites the overpass calendar knows by name (:data:`imaging.overpass.SATELLITES`
holds their orbits; the two lists are kept equal by a test)."""

ATMOSPHERE_MODELS = ("tropical", "midlatitude_summer", "midlatitude_winter", "subarctic_summer",
                     "subarctic_winter", "us_standard_1976")
"""LOWTRAN 7's six model atmospheres, in the order of its ``MODEL`` number 1-6 (Kneizys et
al. 1988, card 1); :mod:`imaging.atmosphere.models`."""

CLOUD_TYPES = ("cumulus", "altostratus", "stratus", "stratocumulus", "nimbostratus")
"""LOWTRAN 7's cloud decks, in the order of its ``ICLD`` 1-5 (Kneizys et al. 1988, card 2)."""

DEFAULT_CLOUD_TYPE = "stratocumulus"
"""Cloud deck of the cloudy share of the sky unless the scenario names one: stratocumulus,
the most frequent cloud type over the oceans (Warren et al. 1988, NCAR/TN-317+STR, global
ocean cloud atlas: ~1/3 of the ocean area covered on average)."""

SENSOR_PRESETS = ("paper", "landsat8_tirs", "landsat9_tirs2", "sdgsat1_tis", "ecostress")
"""Instrument presets (:mod:`imaging.instruments`); the paper's generic instrument first."""


# ---------------------------------------------------------------------------------------
# Background classes
# ---------------------------------------------------------------------------------------
CLASS_NAMES = {1: "water", 2: "vegetation", 3: "land", 4: "building"}
"""Class codes of the class map (0 = unclassified/fill), in the paper's Table 1 order. A
background class is its code and name here, its band emissivities in
:data:`BACKGROUND_EMISSIVITY`, and its physics in
:data:`imaging.background.surface_classes.SURFACE_CLASSES`."""


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
Fresnel value computed by :func:`shipthermal.optics.sea.sea_emissivity` at nadir (the
test checks this)."""
