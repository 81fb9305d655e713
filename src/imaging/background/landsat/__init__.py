"""Landsat-8/9 readers: MTL metadata (text and JSON, groups kept) and GeoTIFF bands of
Collection-2 Level-1 and Level-2 (SR + ST_B10), Collection-1 and pre-collection Level-1
products; quality bands (QA_PIXEL / BQA); the MTL's georeferencing for TIFFs without a CRS.

Radiometric conversions follow the USGS *Landsat 8-9 Collection 2 Level 1 Data Format
Control Book* (LSDS-1822) and the *Landsat 8 Data Users Handbook* (LSDS-1574, §5):

- TOA spectral radiance   ``L = M_L * Q_cal + A_L``            [W m-2 sr-1 um-1]
- TOA reflectance          ``rho = (M_rho * Q_cal + A_rho) / sin(theta_SE)``   [-]
- brightness temperature   ``T_B = K2 / ln(K1 / L + 1)``        [K]

``K1``/``K2`` are the band-effective Planck constants published in the MTL file, so
``T_B`` is the Planck inversion of the band radiance.

Modules: ``grid`` (the scene grid, Landsat's band numbers), ``mtl`` (MTL metadata),
``bands`` (band GeoTIFFs, quality flags), ``scene`` (a scene on one grid), ``radiometry``
(DN, radiance, reflectance and brightness temperature).
"""

from .bands import MASK_BITS, QA_LAYOUTS, QA_MASK_FLAGS, band_grid, qa_flags, read_band
from .grid import (NIR_BAND, RED_BAND, REFLECTIVE_BANDS, THERMAL_BAND, SceneGrid,
                   north_up_transform, window_of_bounds)
from .mtl import MtlGeoreference, MtlMetadata, parse_mtl_groups, parse_mtl_text, read_mtl
from .radiometry import (brightness_temperature_to_radiance, dn_to_radiance, dn_to_reflectance,
                         radiance_to_brightness_temperature)
from .scene import LST_ACCURACY_ST_B10_K, LandsatScene, read_landsat_scene

__all__ = [
    "SceneGrid",
    "north_up_transform",
    "MtlMetadata",
    "MtlGeoreference",
    "read_mtl",
    "parse_mtl_text",
    "parse_mtl_groups",
    "qa_flags",
    "QA_LAYOUTS",
    "LST_ACCURACY_ST_B10_K",
    "read_band",
    "band_grid",
    "window_of_bounds",
    "LandsatScene",
    "read_landsat_scene",
    "dn_to_radiance",
    "dn_to_reflectance",
    "radiance_to_brightness_temperature",
    "brightness_temperature_to_radiance",
    "REFLECTIVE_BANDS",
    "THERMAL_BAND",
    "RED_BAND",
    "NIR_BAND",
    "QA_MASK_FLAGS",
    "MASK_BITS",
]

