"""Where and when: the [location], [time] and [weather] sections of a scenario, each a
frozen dataclass whose fields carry their specification, with its cross-field checks in
``_check``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from .spec import _opt
from .values import (CLEAR_SKY_MODELS, CLIMATE_DATES, CLOUD_MODELS, CLOUD_UNITS, DALIAN, DAY,
                     DECOMPOSITIONS, LATITUDE_MAX, MAX_GAP_HOURS, MAX_RECORD_DAYS,
                     MAX_SITE_DISTANCE_KM, OUTPUT_INTERVAL, SEA_SKIN_MODELS, SEASONS, TEMP_UNITS,
                     VALIDATION_TIMES, WEATHER_FORMATS, WEATHER_SUFFIXES)


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
    output_interval: float = _opt(OUTPUT_INTERVAL, "float", "Thermal output interval over the "
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
