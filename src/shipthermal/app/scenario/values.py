"""Allowed values and defaults of the scenario keys (one place; the sections and the
checks import them).
"""

from __future__ import annotations

# surface optics, bands and convection models are the parameter module's (one source for
# both stages), re-exported here for the sections; DAY is the units module's
from ...parameters import (  # noqa: F401
    ATMOSPHERE_WAVELENGTH_UM,
    BAND_EMISSIVITY,
    BANDS,
    CONVECTION_MODEL_SOURCES,
    DEFAULT_CONVECTION_MODEL,
    LONGWAVE_EMISSIVITY,
    SOLAR_ABSORPTIVITY,
)
from ...units import DAY  # noqa: F401

# ---------------------------------------------------------------------------------------
# Allowed values mirrored from slow-to-import modules (kept equal by the sync tests)
# ---------------------------------------------------------------------------------------
SEASONS = ("summer", "winter")
"""Seasons of the built-in climatology, atmosphere and synthetic port."""

CLEAR_SKY_MODELS = ("brutsaert", "prata", "swinbank")
"""= sorted(shipthermal.environment.sky.CLEAR_SKY_MODELS)."""
CLOUD_MODELS = ("crawford_duchon", "unsworth_monteith")
"""= sorted(shipthermal.environment.sky.CLOUD_MODELS)."""
DECOMPOSITIONS = ("dirint", "erbs")
"""GHI decompositions accepted by shipthermal.environment.Environment."""
WEATHER_FORMATS = ("auto", "csv", "epw", "ndbc", "tmy2", "tmy3")
"""'auto' + shipthermal.environment.station.STATION_FORMATS."""
WEATHER_SUFFIXES = {".csv": "csv", ".epw": "epw", ".tm2": "tmy2", ".txt": "ndbc"}
"""File name endings that 'auto' recognises (= station.guess_format)."""
MAX_GAP_HOURS = 6.0
"""= shipthermal.environment.station.MAX_GAP_HOURS (default of weather.max_gap_hours)."""
MAX_RECORD_DAYS = 31
"""Longest weather.day = 'record' run [days] (forcing tables grow with the span)."""
TEMP_UNITS = ("C", "K")
CLOUD_UNITS = ("fraction", "oktas", "percent", "tenths")
"""Units accepted by shipthermal.environment.read_weather_csv."""

DALIAN = {"latitude": 38.91, "longitude": 121.63, "time_zone": "Etc/GMT-8"}
"""Site of the built-in climatology (= shipthermal.environment.climatology.DALIAN)."""
CLIMATE_DATES = {"summer": "2023-07-15", "winter": "2023-01-15"}
"""Dates of the built-in design days (= climatology.dalian_summer/winter().date)."""
CLIMATE_MONTHS = {"summer": (6, 7, 8), "winter": (12, 1, 2)}
"""Months a built-in design day may stand for (mid-July / mid-January climatology)."""
CLIMATE_RADIUS_DEG = 3.0
"""How far [deg] from Dalian the built-in climatology may be used (the northern Yellow Sea /
Bohai coast: Qingdao is 2.8 deg away)."""

ATMOSPHERE_BACKENDS = ("table", "lowtran")
MAX_VIEW_ZENITH = {"table": 80.0, "lowtran": 85.0}
"""= imaging.atmosphere.core.MAX_VIEW_ZENITH [deg]."""
PAPER_SENSOR = {"altitude_m": 795.0e3, "focal_length_m": 1.06, "aperture_m": 0.53,
                "pixel_pitch_m": 40.0e-6, "optics_transmittance": 0.7}
"""= imaging.sensor.PAPER_SENSOR (paper §5)."""
VARIOGRAM_MODELS = ("exponential", "gaussian", "linear", "power", "spherical")
"""= sorted(imaging.background.kriging.VARIOGRAM_MODELS)."""
MET_UNITS = ("auto", "K", "degC", "degF")
"""= imaging.background.met.MET_UNITS."""
DEM_NODATA = ("error", "mask", "fill")
"""What the background does with DEM voids over land (imaging.background.background)."""
SYNTHETIC_PIXEL_M = 30.0
"""Pixel size of the built-in synthetic port [m]."""
ROI_SPLITS = 10
"""= imaging.background.classify.N_SPLITS (held-out ROI splits of the accuracy)."""

BUILTIN_SHIP_NAMES = ("cargo_ship", "frigate", "patrol_boat")
"""= sorted(shipthermal.geometry.BUILTIN_SHIPS)."""
MESH_EXTENSIONS = (".glb", ".gltf", ".obj", ".off", ".ply", ".stl", ".vtk", ".vtp", ".vtu")
"""Surface formats read by shipthermal.geometry.io.read_ship."""
MESH_WITH_PART_ARRAY = (".vtk", ".vtp", ".vtu")
"""Formats that may carry a per-cell ``part`` array instead of a part map."""
MESH_WITH_PART_NAMES = (".glb", ".gltf", ".obj")
"""= shipthermal.geometry.cad.SCENE_EXTENSIONS: part names from OBJ groups / glTF meshes."""
MAX_REPAIR_CHANGE = 0.01
"""= shipthermal.geometry.cad.MAX_REPAIR_CHANGE: largest accepted relative change of area or
volume by a mesh repair."""
OUTPUT_FORMATS = ("csv", "geotiff", "html", "json", "netcdf", "png", "vtkhdf", "vtu")

# Typical times of the paper's Figs. 14–17 (summer 01:00, 06:00, 07:00, 13:00; winter 00:00,
# 08:30, 12:00, 18:30) and the validation moments of §3.1 (summer 07:00 / 12:00, winter
# 08:00 / 12:00).
PAPER_IMAGE_TIMES = {"summer": ("01:00", "06:00", "07:00", "13:00"),
                     "winter": ("00:00", "08:30", "12:00", "18:30")}
VALIDATION_TIMES = {"summer": ("07:00", "12:00"), "winter": ("08:00", "12:00")}

