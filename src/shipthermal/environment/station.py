"""Station weather records: NDBC buoys, EPW, TMY3 and CSV files onto a regular hourly axis.

A real record is irregular: buoys report at :50, stations miss hours, a sensor is out
for days, an anemometer is not at 10 m. This module turns any supported file into the
validated, regular :class:`~shipthermal.environment.weather.Weather` the solver uses,
and says what it did:

    read_station(path, format)  ──►  StationRecord (observations, NaN where missing)
    to_weather(record, start, end)  ──►  Weather on the hour + a report of every gap

* **Off-the-hour times** (NDBC's :50) are interpolated linearly onto the hours.
* **Short gaps** (valid observations at most ``max_gap`` apart) are interpolated and
  listed in the report; **long gaps** are refused, naming the field and the span.
* **Missing-value codes** are turned into NaN by the readers (NDBC 99 / 999 / 9999 by
  column, EPW's codes through pvlib's documented values).
* **Wind height**: the speed measured at ``wind_height`` is reduced to 10 m by the
  neutral logarithmic profile over the sea (:func:`reduce_wind_to_10m`).
* Quantities a file does not carry (NDBC: cloud cover; EPW/TMY: sea temperature) come
  from constants given by the caller (``fallback``), and the report says so.

Every problem of a record over the requested span (missing fields, long gaps, values out
of their physical range, a span the file does not cover) is collected by
:func:`check_weather` so a user sees all of them at once.
"""

from __future__ import annotations

import dataclasses
import os
from typing import Mapping, Optional

import numpy as np
import pandas as pd
import pvlib

from shipthermal.errors import InputError, require
from shipthermal.parameters import (AIR_SEA_DIFFERENCE_K, AIR_SEA_WARN_K, HUMIDITY_FRACTION_MAX,
                                    MAX_GAP_HOURS, MAX_SITE_DISTANCE_KM, STATION_FORMATS,
                                    STATION_SUFFIXES, WIND_SPEED_WARN)
from shipthermal.units import ZERO_CELSIUS

from .convection.wind import SEA_ROUGHNESS_LENGTH, wind_speed_at_height
from .sky import relative_humidity_from_dew_point
from .weather import _LIMITS, Weather, interpolate_wind_direction, read_csv_frame

__all__ = ["STATION_FORMATS", "FIELDS", "REQUIRED_FIELDS", "MAX_GAP_HOURS", "EDGE_HOLD_S",
           "NDBC_MISSING", "StationRecord", "WeatherReport", "read_station", "read_ndbc",
           "to_weather", "check_weather", "weather_sense", "great_circle_km",
           "guess_format", "reduce_wind_to_10m"]

FIELDS = ("temp_air", "relative_humidity", "wind_speed", "wind_direction", "cloud_cover",
          "temp_sea", "ghi", "longwave_down")
"""Quantities of a :class:`Weather` (SI units, kelvin)."""

REQUIRED_FIELDS = FIELDS[:6]
"""Quantities a run needs (from the file or a constant); ``ghi`` and ``longwave_down``
are optional (the sky models replace them)."""

EDGE_HOLD_S = 3600.0
"""How far beyond the first or last valid observation a value is held constant [s]
(one hour: a record at :50 that starts at 00:50 still gives 00:00)."""

NDBC_MISSING = {
    "WDIR": (999.0,), "MWD": (999.0,), "WSPD": (99.0,), "GST": (99.0,), "WVHT": (99.0,),
    "DPD": (99.0,), "APD": (99.0,), "PRES": (9999.0,), "ATMP": (99.0, 999.0),
    "WTMP": (99.0, 999.0), "DEWP": (99.0, 999.0), "VIS": (99.0,), "TIDE": (99.0,),
}
"""Missing-value codes of the NDBC standard meteorological format by column
(NDBC, "Measurement Descriptions and Units", https://www.ndbc.noaa.gov/faq/measdes.shtml:
missing data are 99, 999 or 9999 by field width). Only codes that cannot be real values
are listed: a wind direction of 99° and a pressure of 999 hPa are real."""

_NDBC_USED = ("ATMP", "WTMP", "DEWP", "WSPD", "WDIR")  # the columns a thermal run uses
_NDBC_TZ = "UTC"
_NDBC_ALIASES = {"#YY": "YY", "WD": "WDIR", "BAR": "PRES"}  # NDBC historical files are in UTC ("hh mm" of the file)

# scenario keys that give a constant for a quantity a file lacks (named in messages)
_FALLBACK_KEY = {"temp_sea": "weather.temp_sea", "cloud_cover": "weather.cloud_cover",
                 "wind_direction": "weather.wind_direction"}
_FALLBACK_UNIT = {"temp_sea": "K", "cloud_cover": "fraction 0-1", "wind_direction": "deg"}


@dataclasses.dataclass(frozen=True)
class StationRecord:
    """Observations as read from a file (SI units, kelvin; NaN = missing).

    Attributes
    ----------
    frame : pandas.DataFrame
        Indexed by tz-aware time (sorted); columns a subset of :data:`FIELDS`.
    source : str
        Format and file name (for reports).
    format : str
        One of :data:`STATION_FORMATS`.
    notes : tuple of str
        What the reader did (codes mapped to missing, conventions applied).
    site : (latitude, longitude, name) or None
        The station of a typical-year file's header [deg, deg north and east].
    temp_unit : str or None
        The temperature unit a CSV file was read in ('C', 'K', 'F').
    solar_interval : str
        What the file's irradiance is (:data:`~shipthermal.environment.weather.SOLAR_INTERVALS`):
        typical-year files give the hour's energy at its end (``'ending'``).
    """

    frame: pd.DataFrame
    source: str
    format: str
    notes: tuple = ()
    site: Optional[tuple] = None
    temp_unit: Optional[str] = None
    solar_interval: str = "instant"


@dataclasses.dataclass(frozen=True)
class WeatherReport:
    """What :func:`to_weather` did to a record over a span.

    Attributes
    ----------
    interpolated : tuple of (field, first, last, hours)
        Gaps bridged by linear interpolation: the field, the valid observations on either
        side and the time between them [h].
    held : tuple of (field, instant, observation, hours)
        Ends of the span beyond the first / last valid observation: the value of that
        observation is held.
    constants : dict
        field → constant used because the file lacks it over the span.
    notes : tuple of str
        Reader notes and the wind-height reduction.
    """

    interpolated: tuple = ()
    held: tuple = ()
    constants: dict = dataclasses.field(default_factory=dict)
    notes: tuple = ()

    def lines(self) -> list:
        """Human-readable lines (one per gap, constant and note)."""
        out = list(self.notes)
        spans: dict = {}
        for f, a, b, h in self.interpolated:
            spans.setdefault((a, b, h), []).append(f)
        for (a, b, h), names in spans.items():
            out.append(f"gap of {h:g} h between observations {a:%Y-%m-%d %H:%M} and "
                       f"{b:%Y-%m-%d %H:%M %Z} interpolated: {', '.join(names)}")
        ends: dict = {}
        for f, t, ref, h in self.held:
            ends.setdefault((t, ref), []).append(f)
        for (t, ref), names in ends.items():
            out.append(f"{t:%Y-%m-%d %H:%M %Z} lies beyond the record: value of the nearest "
                       f"observation ({ref:%Y-%m-%d %H:%M}) held: {', '.join(names)}")
        for f, v in self.constants.items():
            out.append(f"{f}: not in the file over the span, constant {v:g} "
                       f"{_FALLBACK_UNIT.get(f, '')} ({_FALLBACK_KEY.get(f, f)})")
        return out

    def to_dict(self) -> dict:
        return {"interpolated_gaps": [{"field": f, "from": str(a), "to": str(b), "hours": h}
                                      for f, a, b, h in self.interpolated],
                "held_ends": [{"field": f, "at": str(t), "observation": str(o), "hours": h}
                              for f, t, o, h in self.held],
                "constants": dict(self.constants), "notes": list(self.notes)}


# ---------------------------------------------------------------------------------------
# Readers
# ---------------------------------------------------------------------------------------
def guess_format(path) -> Optional[str]:
    """Format from the file name (:data:`~shipthermal.parameters.STATION_SUFFIXES`: .csv →
    csv, .epw → epw, .tm2 → tmy2, .txt → ndbc); None if unknown. TMY3 files end in .csv too:
    name the format."""
    return STATION_SUFFIXES.get(os.path.splitext(str(path))[1].lower())


def read_station(path, format: str, *, tz: Optional[str] = None, temp_unit: str = "C",
                 cloud_unit: str = "fraction", year: Optional[int] = None,
                 use_measured_irradiance: bool = True,
                 use_measured_longwave: bool = True) -> StationRecord:
    """Read a weather file of any supported format as observations.

    Parameters
    ----------
    path : str or path-like
    format : {'csv', 'epw', 'tmy2', 'tmy3', 'ndbc'}
    tz : str, optional
        Time zone the record is returned in (IANA name); CSV: also the zone of naive
        times.
    temp_unit, cloud_unit : str
        CSV only (see :func:`~shipthermal.environment.weather.read_weather_csv`).
    year : int, optional
        EPW / TMY2 / TMY3: the year the typical year's rows are coerced to.
    use_measured_irradiance, use_measured_longwave : bool
        Keep the file's global irradiance / downwelling long-wave columns.

    Returns
    -------
    StationRecord
    """
    require(format in STATION_FORMATS, "weather.format", format,
            f"must be one of {', '.join(STATION_FORMATS)}")
    require(os.path.isfile(path), "weather.source", str(path), "must be an existing file")
    name = os.path.basename(str(path))
    notes: list = []
    site = None
    if format == "csv":
        frame = read_csv_frame(path, tz=tz, temp_unit=temp_unit, cloud_unit=cloud_unit)
    elif format == "ndbc":
        frame, notes = _ndbc_frame(path)
    else:
        frame, notes, site = _typical_year_frame(path, format, year)
    if not use_measured_irradiance and "ghi" in frame:
        frame = frame.drop(columns="ghi")
    if not use_measured_longwave and "longwave_down" in frame:
        frame = frame.drop(columns="longwave_down")
    if tz is not None:
        frame.index = frame.index.tz_convert(tz)
    dup = frame.index.duplicated(keep=False)
    if dup.any():
        t = frame.index[dup][0]
        raise InputError("weather.source", name, f"has {int(dup.sum())} rows sharing a time "
                         f"(first {t:%Y-%m-%d %H:%M %Z}): each time may appear once",
                         "Remove the repeated rows")
    if not frame.index.is_monotonic_increasing:
        notes = list(notes) + ["rows were not in time order: sorted"]
        frame = frame.sort_index()
    return StationRecord(frame=frame, source=f"{format}:{name}", format=format,
                         notes=tuple(notes), site=site,
                         temp_unit=temp_unit if format == "csv" else None,
                         solar_interval="ending" if format in ("epw", "tmy2", "tmy3")
                         else "instant")


def read_ndbc(path, tz: Optional[str] = None) -> StationRecord:
    """Read an NDBC standard meteorological file (historical ``*h<year>.txt`` or the
    real-time ``*.txt`` layout).

    Parameters
    ----------
    path : str or path-like
    tz : str, optional
        Time zone of the returned index (the file's times are UTC).

    Returns
    -------
    StationRecord
        ``temp_air`` from ATMP, ``temp_sea`` from WTMP, ``relative_humidity`` from DEWP
        (Magnus), ``wind_speed`` from WSPD (at the anemometer height: see
        :func:`~.convection.wind_speed_at_height`), ``wind_direction`` from WDIR. No cloud
        cover (NDBC buoys do not observe it) and no irradiance.
    """
    return read_station(path, "ndbc", tz=tz)


def _ndbc_frame(path):
    with open(path, encoding="utf-8", errors="replace") as fh:
        head = [fh.readline() for _ in range(2)]
    require(head[0].startswith("#") or head[0][:4].strip().upper() in ("YY", "YYYY"),
            "weather.source", str(path), "must be an NDBC standard meteorological file "
            "(first line: '#YY  MM DD hh mm WDIR WSPD ...')",
            "Check weather.format, or download the 'Standard meteorological data' file")
    # files before 2007 name two columns differently and have no units line
    names = [_NDBC_ALIASES.get(n, n) for n in head[0].lstrip("#").split()]
    require(len(names) >= 5 and names[0] in ("YY", "YYYY") and "MM" in names,
            "weather.source", os.path.basename(str(path)), "must start with the NDBC column "
            "names (#YY MM DD hh [mm] WDIR WSPD ... ATMP WTMP DEWP ...)",
            "Check weather.format, or download the 'Standard meteorological data' file")
    skip = sum(1 for line in head if line.startswith("#")) or 1
    try:
        df = pd.read_csv(path, sep=r"\s+", skiprows=skip, header=None, na_values=["MM"],
                         comment=None, dtype=float)
    except (ValueError, pd.errors.ParserError, pd.errors.EmptyDataError):
        raise InputError("weather.source", os.path.basename(str(path)), "must hold NDBC data "
                         "rows of numbers ('MM' for a missing value), one per line, as many "
                         "as the header's columns") from None
    require(df.shape[1] == len(names), "weather.source", str(path),
            f"rows must have {len(names)} columns like the header ({df.shape[1]} found)")
    require(len(df) > 0, "weather.source", str(path), "holds no data rows")
    df.columns = names
    notes = []
    for col, codes in NDBC_MISSING.items():
        if col in df:
            miss = df[col].isin(codes)
            if miss.any() and col in _NDBC_USED:
                notes.append(f"{col}: {int(miss.sum())} of {len(df)} rows carry the "
                             f"missing code {'/'.join(f'{c:g}' for c in codes)}")
            df.loc[miss, col] = np.nan
    year = df[names[0]].astype(int)
    year = np.where(year < 100, year + 1900, year)
    minute = df["mm"] if "mm" in df else 0
    time = pd.to_datetime(dict(year=year, month=df["MM"].astype(int),
                               day=df["DD"].astype(int), hour=df["hh"].astype(int),
                               minute=np.asarray(minute, dtype=int)), errors="coerce")
    require(not time.isna().any(), "weather.source", str(path),
            "has rows whose YY MM DD hh mm is not a date")
    idx = pd.DatetimeIndex(time).tz_localize(_NDBC_TZ)
    out = {}
    if "ATMP" in df:
        out["temp_air"] = df["ATMP"].to_numpy() + ZERO_CELSIUS
    if "WTMP" in df:
        out["temp_sea"] = df["WTMP"].to_numpy() + ZERO_CELSIUS
    if "DEWP" in df and "ATMP" in df:
        out["relative_humidity"] = np.minimum(relative_humidity_from_dew_point(
            out["temp_air"], df["DEWP"].to_numpy() + ZERO_CELSIUS), 100.0)
    if "WSPD" in df:
        out["wind_speed"] = df["WSPD"].to_numpy()
    if "WDIR" in df:
        out["wind_direction"] = df["WDIR"].to_numpy() % 360.0
    return pd.DataFrame(out, index=pd.DatetimeIndex(idx, name="time")), notes


def _typical_year_frame(path, fmt, year):
    try:
        if fmt == "epw":
            data, meta = pvlib.iotools.read_epw(path, coerce_year=year)
        elif fmt == "tmy2":
            data, meta = pvlib.iotools.read_tmy2(str(path))
        else:
            data, meta = pvlib.iotools.read_tmy3(path, coerce_year=year or 2001,
                                                 map_variables=True)
    except Exception:  # pvlib raises assorted parser errors (their text quotes the file)
        raise InputError("weather.source", os.path.basename(str(path)), f"must be a valid "
                         f"{fmt.upper()} file (its header or rows do not parse as "
                         f"{fmt.upper()})", "Check weather.format, or the file") from None
    notes = []
    if fmt == "tmy2":
        # typical months come from different years: put every row into one year (pvlib's
        # reader has no coerce_year); a 29 February row cannot move to a common year
        y = int(year or 2001)
        idx = data.index
        keep = ~((idx.month == 2) & (idx.day == 29))
        data = data[keep]
        idx = pd.DatetimeIndex([t.replace(year=y) for t in data.index])
        data = data.set_axis(idx).sort_index()
    else:
        data = data.sort_index()
    if fmt == "tmy2":
        # TMY2 (NREL 1995, User's Manual Table 3-2): hour h is the hour ending at h,
        # pvlib labels it h - 1; dry bulb and dew point in 0.1 °C, wind speed in 0.1 m/s,
        # cloud in tenths; irradiance as Wh m-2 over the hour ending at h
        idx = data.index + pd.Timedelta(hours=1)
        cols = {"temp_air": data["DryBulb"].to_numpy(dtype=float) / 10.0,
                "relative_humidity": data["RHum"].to_numpy(dtype=float),
                "wind_speed": data["Wspd"].to_numpy(dtype=float) / 10.0,
                "wind_direction": data["Wdir"].to_numpy(dtype=float),
                "cloud_cover": data["TotCld"].to_numpy(dtype=float) / 10.0,
                "ghi": data["GHI"].to_numpy(dtype=float)}
        notes.append("TMY2: hour-ending rows labelled at their end; 0.1 degC and 0.1 m/s "
                     "converted; irradiance: the hour's energy, spread over the hour by the "
                     "sun's course")
    elif fmt == "epw":
        # EPW "hour h" is the hour ending at h; pvlib labels it h - 1 (the start)
        idx = data.index + pd.Timedelta(hours=1)
        cloud = data["total_sky_cover"].to_numpy(dtype=float)
        miss = {"temp_air": 99.9, "relative_humidity": 999.0, "wind_speed": 999.0,
                "wind_direction": 999.0}
        cols = {k: np.where(data[k].to_numpy(dtype=float) >= v, np.nan,
                            data[k].to_numpy(dtype=float)) for k, v in miss.items()}
        cols["cloud_cover"] = np.where(cloud >= 99, np.nan, cloud) / 10.0
        lw = data["ghi_infrared"].to_numpy(dtype=float) if "ghi_infrared" in data else None
        ghi = data["ghi"].to_numpy(dtype=float)
        cols["ghi"] = np.where(ghi >= 9999, np.nan, ghi)
        if lw is not None:
            cols["longwave_down"] = np.where(lw >= 9999, np.nan, lw)
        notes.append("EPW: hour-ending rows labelled at their end; irradiance: the hour's "
                     "energy, spread over the hour by the sun's course; infrared: the value "
                     "at the hour's end (as EnergyPlus reads it)")
    else:
        idx = data.index
        cols = {k: data[k].to_numpy(dtype=float) for k in
                ("temp_air", "relative_humidity", "wind_speed", "wind_direction")}
        cols["cloud_cover"] = data["TotCld (tenths)"].to_numpy(dtype=float) / 10.0
        cols["ghi"] = data["ghi"].to_numpy(dtype=float)
        notes.append("TMY3: irradiance: the hour's energy (hour-ending means), spread over "
                     "the hour by the sun's course")
    cols["temp_air"] = cols["temp_air"] + ZERO_CELSIUS
    cols["wind_direction"] = cols["wind_direction"] % 360.0
    site = None
    try:
        lat, lon = float(meta["latitude"]), float(meta["longitude"])
        name = str(meta.get("city") or meta.get("City") or meta.get("Name") or "").strip('" ')
        if np.isfinite(lat) and np.isfinite(lon):
            site = (lat, lon, name)
    except (KeyError, TypeError, ValueError):
        pass
    return pd.DataFrame(cols, index=pd.DatetimeIndex(idx, name="time")), notes, site


# ---------------------------------------------------------------------------------------
# Onto the hours, with gaps
# ---------------------------------------------------------------------------------------
def _epoch_seconds(index) -> np.ndarray:
    """Seconds since 1970-01-01 UTC of a tz-aware index (any datetime resolution)."""
    utc = pd.DatetimeIndex(index).tz_convert("UTC").tz_localize(None)
    return np.asarray((utc - pd.Timestamp(0)).total_seconds(), dtype=float)


def _spans(mask):
    """(first, last) index pairs of runs of True."""
    m = np.concatenate([[False], np.asarray(mask, bool), [False]])
    d = np.diff(m.astype(int))
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1) - 1))


def check_weather(record: StationRecord, start, end, *, step: float = 3600.0,
                  max_gap_hours: float = MAX_GAP_HOURS, wind_height: float = 10.0,
                  fallback: Optional[Mapping] = None, periodic: bool = False,
                  site: Optional[tuple] = None,
                  max_site_distance_km: float = MAX_SITE_DISTANCE_KM):
    """Put a record onto a regular axis over ``[start, end]``, collecting every problem.

    Parameters
    ----------
    record : StationRecord
    start, end : pandas.Timestamp
        First and last instant needed (tz-aware; ``end`` included).
    step : float
        Output step [s].
    max_gap_hours : float
        Longest bridged gap between valid observations [h] (:data:`MAX_GAP_HOURS`).
    wind_height : float
        Anemometer height above the sea [m]; the speed is reduced to 10 m.
    fallback : mapping, optional
        Constants for quantities the record lacks over the span: ``temp_sea`` [K],
        ``cloud_cover`` [0-1], ``wind_direction`` [deg]. A constant is used only where
        the file has no valid value of that field in the span.
    periodic : bool
        Flag of the returned Weather.
    site : (latitude, longitude), optional
        The run's site [deg]: a typical-year file whose header names a station farther
        than ``max_site_distance_km`` [km] is refused.

    Besides the ranges, every day of the span is checked for physical sense
    (:func:`weather_sense`: air against sea temperature, humidity written as a fraction,
    a storm-force mean wind).

    Returns
    -------
    weather : Weather or None
        None when there are problems.
    report : WeatherReport
    problems : list of InputError
        Every problem found (empty when ``weather`` is returned).
    """
    fallback = {k: v for k, v in (fallback or {}).items() if v is not None}
    src = record.source
    start = pd.Timestamp(start)
    end = pd.Timestamp(end)
    grid = pd.date_range(start, end, freq=pd.Timedelta(seconds=step))
    if len(record.frame) == 0:
        return None, WeatherReport(), [InputError("weather.source", src, "holds no rows")]
    refused = _site_refusal(record, site, max_site_distance_km)
    if refused is None:
        refused = _coverage_refusal(record, start, end)
    if refused is not None:
        return None, WeatherReport(notes=record.notes), [refused]
    values, interpolated, held, constants, problems = _fields_on_grid(
        record, grid, start, end, max_gap_hours, step, fallback)
    notes = list(record.notes)
    if "wind_speed" in values:
        values["wind_speed"], note = reduce_wind_to_10m(values["wind_speed"], wind_height)
        if note is not None:
            notes.append(note)
    problems += _range_problems(values, grid)
    if not problems:
        sense_problems, sense_notes = weather_sense(
            values, grid, src, maybe_fahrenheit=record.temp_unit == "C", from_file={
                f for f in ("temp_sea",) if f not in constants})
        problems += sense_problems
        notes += sense_notes
    report = WeatherReport(interpolated=tuple(interpolated), held=tuple(held),
                           constants=constants, notes=tuple(notes))
    if problems:
        return None, report, problems
    weather = Weather(time=grid, temp_air=values["temp_air"],
                      relative_humidity=values["relative_humidity"],
                      wind_speed=values["wind_speed"], wind_direction=values["wind_direction"],
                      cloud_cover=values["cloud_cover"], temp_sea=values["temp_sea"],
                      ghi=values.get("ghi"), longwave_down=values.get("longwave_down"),
                      periodic=periodic, source=src, solar_interval=record.solar_interval)
    return weather, report, []


def reduce_wind_to_10m(wind_speed, wind_height: float):
    """The wind speed [m s-1] measured at ``wind_height`` [m] reduced to 10 m by the neutral
    logarithmic profile over the sea
    (:func:`~shipthermal.environment.convection.wind_speed_at_height`), and the report's note
    of the reduction and its factor: ``(speed, note)``; ``(wind_speed, None)`` itself when the
    anemometer is at 10 m."""
    if abs(wind_height - 10.0) <= 1e-9:
        return wind_speed, None
    reduced = wind_speed_at_height(wind_speed, 10.0, reference_height=wind_height)
    factor = float(wind_speed_at_height(1.0, 10.0, reference_height=wind_height))
    return reduced, (f"wind_speed: reduced from {wind_height:g} m to 10 m (log law, z0 = "
                     f"{SEA_ROUGHNESS_LENGTH:g} m: x {factor:.4f})")


def _site_refusal(record: StationRecord, site, max_site_distance_km):
    """The error refusing a typical-year file whose header names a station farther than
    ``max_site_distance_km`` from ``site``, or None."""
    src = record.source
    if site is not None and record.site is not None:
        # a file of another place: its other problems would only be noise
        km = great_circle_km(site[0], site[1], record.site[0], record.site[1])
        if km > max_site_distance_km:
            return InputError(
                "weather.source", src, f"is the record of {record.site[2] or 'a station'} at "
                f"{record.site[0]:.2f} N, {record.site[1]:.2f} E (its header), {km:,.0f} km from "
                f"the site [location] {site[0]:.2f} N, {site[1]:.2f} E; at most "
                f"{max_site_distance_km:g} km (weather.max_site_distance) is accepted",
                "Give the weather file of the site, set [location] to the station's, or raise "
                "weather.max_site_distance for a deliberate stand-in")
    return None


def _coverage_refusal(record: StationRecord, start, end):
    """The error refusing a record that does not cover ``[start, end]`` (to within
    :data:`EDGE_HOLD_S`), or None."""
    first, last, src = record.frame.index[0], record.frame.index[-1], record.source
    if first > start + pd.Timedelta(seconds=EDGE_HOLD_S) or \
            last < end - pd.Timedelta(seconds=EDGE_HOLD_S):
        return InputError(
            "weather.source", src, f"covers {first:%Y-%m-%d %H:%M} … {last:%Y-%m-%d %H:%M %Z}"
            f", not the span needed {start:%Y-%m-%d %H:%M} … {end:%Y-%m-%d %H:%M %Z}",
            "Pick time.date (and weather.days) inside the record, or a longer file")
    return None


@dataclasses.dataclass(frozen=True)
class _Axis:
    """The regular axis a record is put on, and what a field's messages need of the record."""

    grid: pd.DatetimeIndex      #: the output times
    gx: np.ndarray              #: their epoch seconds
    tz: object                  #: the record's time zone
    src: str                    #: the record's source (for messages)
    max_gap: float              #: longest bridged gap [s]
    max_gap_hours: float        #: the same [h] (for messages)
    spacing: float              #: the record's typical spacing [s]


def _fields_on_grid(record: StationRecord, grid, start, end, max_gap_hours, step, fallback):
    """Every field of :data:`FIELDS` on ``grid``: interpolated from the file, or a constant
    of ``fallback`` where the file has no valid value near the span.

    Returns the values by field, the bridged gaps, the held ends, the constants used and the
    problems, as :func:`check_weather` reports them."""
    frame = record.frame
    tx = _epoch_seconds(frame.index)
    axis = _Axis(grid=grid, gx=_epoch_seconds(grid), tz=frame.index.tz, src=record.source,
                 max_gap=max_gap_hours * 3600.0, max_gap_hours=max_gap_hours,
                 spacing=float(np.median(np.diff(tx))) if len(tx) > 1 else step)
    gx, max_gap = axis.gx, axis.max_gap
    values, interpolated, held, constants, problems = {}, [], [], {}, []
    for field in FIELDS:
        col = frame[field].to_numpy(dtype=float) if field in frame else None
        ok = np.isfinite(col) if col is not None else None
        # valid observations that matter for the span
        near = (tx >= gx[0] - max_gap) & (tx <= gx[-1] + max_gap)
        if col is None or not ok[near].any():
            if field in fallback:
                values[field] = np.full(len(grid), float(fallback[field]))
                constants[field] = float(fallback[field])
            elif field in REQUIRED_FIELDS:
                problems.append(_absent_field(field, col is None, record, start, end))
            continue
        v_grid, field_problems, field_held, bridged = _field_on_axis(field, tx[ok], col[ok], axis)
        problems += field_problems
        held += field_held
        interpolated += bridged
        if v_grid is not None:
            values[field] = v_grid
    return values, interpolated, held, constants, problems


def _absent_field(field, no_column: bool, record: StationRecord, start, end) -> InputError:
    """The problem of a required field the file lacks over the span (no column, or no valid
    value), with the fix that applies."""
    what = "has no column for" if no_column else "has no valid value of"
    if field in _FALLBACK_KEY:
        fix = f"Set {_FALLBACK_KEY[field]} (a constant, {_FALLBACK_UNIT[field]})"
    elif no_column and record.format == "csv":
        fix = f"Add a {field!r} column" + (" (or 'temp_dew')" if field ==
                                            "relative_humidity" else "") + \
            " (docs/WEATHER.md)"
    elif no_column:
        fix = "This file does not carry it: give a CSV record (docs/WEATHER.md)"
    else:
        fix = "Pick a span the file covers for this quantity, or another file"
    return InputError(f"weather.source[{field}]", record.source,
                      f"{what} {field} between {start:%Y-%m-%d %H:%M} "
                      f"and {end:%Y-%m-%d %H:%M %Z}", fix)


def _field_on_axis(field, t_ok, v_ok, axis: _Axis):
    """One field's valid observations (times ``t_ok`` [epoch s], values ``v_ok``) on the axis.

    Returns the values (None when the field cannot be bridged), its problems (a span beyond
    the record's ends longer than :data:`EDGE_HOLD_S`, gaps longer than ``max_gap``), its
    held ends and its bridged gaps."""
    gx, grid, tz, max_gap = axis.gx, axis.grid, axis.tz, axis.max_gap
    if field == "wind_direction":
        v_grid = interpolate_wind_direction(gx, t_ok, v_ok)
    else:
        v_grid = np.interp(gx, t_ok, v_ok)
    # the valid observations around each grid time
    j = np.searchsorted(t_ok, gx, side="left")
    exact = (j < len(t_ok)) & (t_ok[np.minimum(j, len(t_ok) - 1)] == gx)
    left = np.where(exact, gx, t_ok[np.maximum(j - 1, 0)])
    right = np.where(j < len(t_ok), t_ok[np.minimum(j, len(t_ok) - 1)], np.inf)
    before = j == 0
    after = j >= len(t_ok)
    left = np.where(before & ~exact, -np.inf, left)
    gap = np.where(exact, 0.0, right - left)
    # ends: hold the first / last value for up to EDGE_HOLD_S
    beyond = np.where(before & ~exact, t_ok[0] - gx, np.where(after, gx - t_ok[-1], 0.0))
    if np.any(beyond > EDGE_HOLD_S):
        # the quantity starts after the span's start or stops before its end
        k = int(np.flatnonzero(beyond > EDGE_HOLD_S)[0])
        late = bool(before[k])
        ref = pd.Timestamp(t_ok[0] if late else t_ok[-1], unit="s", tz="UTC").tz_convert(tz)
        edge = grid[0] if late else grid[-1]
        span = abs((edge - ref).total_seconds()) / 3600.0
        span_text = f"{span / 24:.1f} days" if span >= 48 else f"{span:.1f} h"
        return None, [InputError(
            f"weather.source[{field}]", axis.src,
            f"has no valid {field} {'before' if late else 'after'} "
            f"{ref:%Y-%m-%d %H:%M %Z} (its {'first' if late else 'last'} valid "
            f"observation): the span {'starts' if late else 'runs'} {span_text} "
            f"{'earlier, at' if late else 'longer, to'} {edge:%Y-%m-%d %H:%M}; a value is "
            f"held at most {EDGE_HOLD_S / 3600:g} h",
            ("Start the span later (time.date)" if late else
             "End the span before it (time.date, weather.days)")
            + ", or give a file that has it")], [], []
    held = []
    for k in np.flatnonzero(beyond > 0):
        ref = t_ok[0] if before[k] else t_ok[-1]
        held.append((field, grid[k],
                     pd.Timestamp(ref, unit="s", tz="UTC").tz_convert(tz),
                     round(float(beyond[k]) / 3600.0, 2)))
    inner = np.isfinite(gap)
    long = inner & (gap > max_gap + 1e-6)
    if long.any():
        return None, _long_gaps(field, long, left, right, axis), held, []
    bridged = inner & ~exact & (gap > 1.5 * axis.spacing)
    interpolated = []
    seen = set()
    for k in np.flatnonzero(bridged):
        key = (left[k], right[k])
        if key in seen:
            continue
        seen.add(key)
        ta = pd.Timestamp(left[k], unit="s", tz="UTC").tz_convert(tz)
        tb = pd.Timestamp(right[k], unit="s", tz="UTC").tz_convert(tz)
        interpolated.append((field, ta, tb, round((tb - ta).total_seconds() / 3600.0, 2)))
    return v_grid, [], held, interpolated


def _long_gaps(field, long, left, right, axis: _Axis) -> list:
    """The problems of a field's gaps longer than ``max_gap`` (one per run of grid times)."""
    problems = []
    for a, b in _spans(long):
        ta = pd.Timestamp(left[a], unit="s", tz="UTC").tz_convert(axis.tz)
        tb = pd.Timestamp(right[b], unit="s", tz="UTC").tz_convert(axis.tz)
        problems.append(InputError(
            f"weather.source[{field}]", axis.src,
            f"has no valid {field} from {ta:%Y-%m-%d %H:%M} to {tb:%Y-%m-%d %H:%M %Z} "
            f"({(tb - ta).total_seconds() / 3600:g} h), longer than weather."
            f"max_gap_hours = {axis.max_gap_hours:g} h",
            "Pick another span, raise weather.max_gap_hours, or fill the gap"
            + (f"; or set weather.use_measured_"
               f"{'irradiance' if field == 'ghi' else 'longwave'} = false"
               if field in ("ghi", "longwave_down") else "")))
    return problems


def _range_problems(values, grid) -> list:
    """The values outside their physical ranges (:data:`~.weather._LIMITS`), one problem per
    field."""
    problems = []
    for field, arr in values.items():
        lo, hi, unit = _LIMITS[field]
        bad = np.flatnonzero((arr < lo) | (arr > hi))
        if bad.size:
            k = int(bad[0])
            hint = ("the file's temperature unit (weather.temp_unit)" if field.startswith("temp")
                    else "the cloud unit (weather.cloud_unit)" if field == "cloud_cover"
                    else "the file's units (docs/WEATHER.md)")
            problems.append(InputError(f"weather.source[{field}]", float(arr[k]),
                                       f"must lie in [{lo:g}, {hi:g}] {unit} ({bad.size} "
                                       f"value(s) outside, first at {grid[k]:%Y-%m-%d %H:%M %Z})",
                                       f"Check {hint}"))
    return problems


def great_circle_km(lat1, lon1, lat2, lon2) -> float:
    """Great-circle distance [km] between two points [deg] (haversine, mean Earth radius
    6371.0 km)."""
    p1, p2 = np.radians(lat1), np.radians(lat2)
    dp, dl = p2 - p1, np.radians(lon2 - lon1)
    a = np.sin(dp / 2) ** 2 + np.cos(p1) * np.cos(p2) * np.sin(dl / 2) ** 2
    return float(2 * 6371.0 * np.arcsin(np.sqrt(np.clip(a, 0.0, 1.0))))


def weather_sense(values: Mapping, grid, source: str, maybe_fahrenheit: bool = False,
                  from_file=frozenset({"temp_sea"})) -> tuple[list, list]:
    """Days of a weather record that make no physical sense, though every value lies in
    its range.

    Parameters
    ----------
    values : mapping field -> (n,) array
        The record on ``grid`` (SI units, kelvin; relative humidity in %).
    grid : pandas.DatetimeIndex
        Times of the values.
    source : str
        Named in the messages.
    maybe_fahrenheit : bool
        The temperatures were read as degrees Celsius from a CSV, so they may be degrees
        Fahrenheit: a message then says when they look like it.
    from_file : set of str
        Fields read from the file (a constant ``temp_sea`` from the scenario is not in the
        file's unit).

    Returns
    -------
    problems : list of InputError
        Per day: air minus sea temperature outside :data:`AIR_SEA_DIFFERENCE_K`; a span
        whose relative humidity never exceeds :data:`HUMIDITY_FRACTION_MAX` %.
    notes : list of str
        Warnings: air minus sea outside :data:`AIR_SEA_WARN_K`, a daily-mean wind above
        :data:`WIND_SPEED_WARN`.
    """
    problems, notes = [], []
    day = np.asarray((grid - grid[0]).total_seconds() // 86400.0, dtype=int)
    air, sea = values.get("temp_air"), values.get("temp_sea")
    lo, hi = AIR_SEA_DIFFERENCE_K
    wlo, whi = AIR_SEA_WARN_K
    if air is not None and sea is not None:
        for d in np.unique(day):
            sel = day == d
            diff = float(np.mean(air[sel]) - np.mean(sea[sel]))
            when = f"{grid[sel][0]:%Y-%m-%d}"
            if lo <= diff <= hi:
                if not wlo <= diff <= whi:
                    notes.append(f"warning: on {when} the air is {diff:+.1f} K from the sea "
                                 "(daily means): a rare day; check the record")
                continue
            c = np.mean(air[sel]) - ZERO_CELSIUS
            s_c = np.mean(sea[sel]) - ZERO_CELSIUS
            fix = "Check the file's temperature unit (weather.temp_unit) and columns"
            if maybe_fahrenheit:
                air_f = (c - 32.0) / 1.8
                sea_f = (s_c - 32.0) / 1.8 if "temp_sea" in from_file else s_c
                if lo <= air_f - sea_f <= hi:
                    fix = ("The temperatures look like degrees Fahrenheit: set "
                           "weather.temp_unit = \"F\"")
                elif lo <= air_f - s_c <= hi:
                    fix = ("The air temperatures look like degrees Fahrenheit, the sea's like "
                           "degrees Celsius: convert the temp_air column ((F - 32) / 1.8) so "
                           "that every temperature has the unit weather.temp_unit says")
            problems.append(InputError(
                "weather.source[temp_air]", source,
                f"has a daily-mean air temperature of {c:.1f} degC over a {s_c:.1f} degC sea on "
                f"{when} ({diff:+.1f} K): the air over the sea stays within {lo:g} to "
                f"{hi:+g} K of the water", fix))
            break
    rh = values.get("relative_humidity")
    if rh is not None and len(rh) and 0.0 < float(np.max(rh)) <= HUMIDITY_FRACTION_MAX:
        problems.append(InputError(
            "weather.source[relative_humidity]", source,
            f"never exceeds {float(np.max(rh)):.2g} % over the span: relative humidity is in "
            "percent (0-100); these look like fractions",
            "Multiply the column by 100 (0.86 is 86 %)"))
    wind = values.get("wind_speed")
    if wind is not None:
        for d in np.unique(day):
            mean = float(np.mean(wind[day == d]))
            if mean > WIND_SPEED_WARN:
                notes.append(f"warning: on {grid[day == d][0]:%Y-%m-%d} the mean wind is "
                             f"{mean:.1f} m/s (storm force): is the file's wind in km/h or "
                             "knots? (docs/WEATHER.md: m/s)")
                break
    return problems, notes


def to_weather(record: StationRecord, start, end, **kwargs):
    """:func:`check_weather`, raising the first problem (the message counts the others).

    Returns ``(Weather, WeatherReport)``.
    """
    weather, report, problems = check_weather(record, start, end, **kwargs)
    if problems:
        e = problems[0]
        rest = "; ".join(str(p) for p in problems[1:])
        more = f" (and {len(problems) - 1} more problem(s): {rest})" if rest else ""
        raise InputError(e.field, e.value, e.allowed + more, e.fix)
    return weather, report
