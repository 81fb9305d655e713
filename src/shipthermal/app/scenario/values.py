"""Allowed values and defaults of the scenario keys (one place; the sections and the
checks import them).
"""

from __future__ import annotations

# Every allowed value and default that the physics also uses is imported from its one home:
# the parameter modules (cheap to import) or, where already loaded, the module itself. The
# names below are the scenario's views of them (sorted choices, the scenario's key names).
from imaging.parameters import (  # noqa: F401
    ATMOSPHERE_MODELS,
    CLOUD_TYPES,
    DEFAULT_CLOUD_TYPE,
    BACKGROUND_MODELS,
    SATELLITE_NAMES,
    RESIDUAL_MODES,
    DEM_NODATA,
    MAX_VIEW_ZENITH,
    MET_UNITS,
    N_SPLITS as ROI_SPLITS,
    PAPER_SENSOR_PARAMETERS as PAPER_SENSOR,
    SENSOR_BANDS,
    SENSOR_PRESETS,
    SYNTHETIC_PIXEL_M,
    VARIOGRAM_MODELS as _VARIOGRAM_MODELS,
)

from ...geometry.cad import MAX_REPAIR_CHANGE, SCENE_EXTENSIONS, SHIP_LENGTH_RANGE  # noqa: F401
from ...geometry.io import MESH_EXTENSIONS, PYVISTA_EXTENSIONS, UNITS  # noqa: F401
from ...geometry.ship import BUILTIN_SHIPS
from ...parameters import (  # noqa: F401
    ATMOSPHERE_WAVELENGTH_UM,
    BAND_EMISSIVITY,
    BANDS,
    CLEAR_SKY_MODEL_NAMES,
    CLOUD_COVER_SCALE,
    CLOUD_MODEL_NAMES,
    CONVECTION_MODEL_SOURCES,
    CONVECTION_ROUGHNESS,
    ROUGHNESS_CLASSES,
    DECOMPOSITIONS as _DECOMPOSITIONS,
    DEFAULT_CONVECTION_MODEL,
    DESIGN_DAY_DATES,
    LATITUDE_MAX,
    LONGWAVE_EMISSIVITY,
    MAX_GAP_HOURS,
    SEA_SKIN_MODEL_NAMES,
    MAX_SITE_DISTANCE_KM,
    OUTPUT_INTERVAL,
    SHIP_SPEED_MAX,
    SEASONS,
    SOLAR_ABSORPTIVITY,
    STATION_FORMATS,
    STATION_SUFFIXES as WEATHER_SUFFIXES,
    TEMP_UNITS,
)
from ...parameters import DALIAN as _DALIAN_STATION
from ...units import DAY  # noqa: F401

# ---------------------------------------------------------------------------------------
# The physics' allowed values as the scenario lists them
# ---------------------------------------------------------------------------------------
CLEAR_SKY_MODELS = tuple(sorted(CLEAR_SKY_MODEL_NAMES))
CLOUD_MODELS = tuple(sorted(CLOUD_MODEL_NAMES))
SEA_SKIN_MODELS = tuple(SEA_SKIN_MODEL_NAMES)
DECOMPOSITIONS = tuple(sorted(_DECOMPOSITIONS))
WEATHER_FORMATS = ("auto",) + tuple(sorted(STATION_FORMATS))
"""'auto' (the format from the file name, :data:`WEATHER_SUFFIXES`) and the readable ones."""

MAX_RECORD_DAYS = 400
"""Longest weather.day = 'record' run [days]: a year (366 days in a leap year) and a month
of the next. A record runs window by window with its outputs streamed to disk
(:func:`shipthermal.diurnal.run_record`), so its memory does not grow with the span; the
bound catches a mistyped span (3650 for 365) before it fills a disk: the streamed outputs
take 4 bytes per ship triangle and output time (a year of the built-in frigate at 0.5 m
and 30-min outputs: 4.2 GB)."""
CLOUD_UNITS = tuple(sorted(CLOUD_COVER_SCALE))

DALIAN = {"latitude": _DALIAN_STATION["latitude"], "longitude": _DALIAN_STATION["longitude"],
          "time_zone": _DALIAN_STATION["tz"]}
"""Site of the built-in climatology, under the scenario's key names."""
CLIMATE_DATES = DESIGN_DAY_DATES
CLIMATE_MONTHS = {"summer": (6, 7, 8), "winter": (12, 1, 2)}
"""Months a built-in design day may stand for (mid-July / mid-January climatology)."""
CLIMATE_RADIUS_DEG = 3.0
"""How far [deg] from Dalian the built-in climatology may be used (the northern Yellow Sea /
Bohai coast: Qingdao is 2.8 deg away)."""

ATMOSPHERE_BACKENDS = tuple(MAX_VIEW_ZENITH)
VARIOGRAM_MODELS = tuple(sorted(_VARIOGRAM_MODELS))
WATER_VAPOUR_RANGE = (0.2, 6.0)
"""Column water vapour accepted by the single-channel LST [g cm-2]: the range of
``imaging.background.lst.WATER_VAPOUR_RANGE`` (written here because that module's package
is heavy to import; a test keeps the two equal)."""

BUILTIN_SHIP_NAMES = tuple(sorted(BUILTIN_SHIPS))
MESH_WITH_PART_ARRAY = tuple(sorted(PYVISTA_EXTENSIONS))
"""Formats that may carry a per-cell ``part`` array instead of a part map."""
MESH_WITH_PART_NAMES = tuple(sorted(SCENE_EXTENSIONS))
"""Formats whose part names may come from the file (OBJ groups, glTF meshes)."""
OUTPUT_FORMATS = ("csv", "geotiff", "html", "json", "netcdf", "pdf", "png", "svg", "vtkhdf", "vtu")

# Typical times of the paper's Figs. 14–17 (summer 01:00, 06:00, 07:00, 13:00; winter 00:00,
# 08:30, 12:00, 18:30) and the validation moments of §3.1 (summer 07:00 / 12:00, winter
# 08:00 / 12:00).
PAPER_IMAGE_TIMES = {"summer": ("01:00", "06:00", "07:00", "13:00"),
                     "winter": ("00:00", "08:30", "12:00", "18:30")}
VALIDATION_TIMES = {"summer": ("07:00", "12:00"), "winter": ("08:00", "12:00")}

