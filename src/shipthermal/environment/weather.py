"""Hourly weather: a validated record, the CSV parser and time interpolation.

:class:`Weather` holds one station record on a regular, time-zone-aware time axis
(SI units, kelvin). The CSV parser (:func:`read_csv_frame`, documented columns, also
RadTherm-style names AIRT, SOLAR, WIND, HUMID, CLOUD, LWIR, WINDIR, SST) gives a strict,
regular record directly (:func:`read_weather_csv`); every format (CSV, EPW, TMY2, TMY3,
NDBC) is read, gap-checked and put on the hours by
:func:`shipthermal.environment.station.read_station` and
:func:`~shipthermal.environment.station.to_weather`: one parser per format.

:meth:`Weather.at` interpolates every field to arbitrary solver times (vectorised;
the wind direction is interpolated as a vector so 350° → 10° passes through north).

CSV format (one header line, one row per time step, comma separated)::

    time,temp_air,relative_humidity,wind_speed,wind_direction,cloud_cover,ghi,longwave_down,temp_sea
    2024-07-15T00:00:00+08:00,21.0,88,4.0,180,0.5,0,,22.2

=================  =========================================  ====================
column             meaning                                     unit
=================  =========================================  ====================
time               ISO 8601 instant; offset in the string, or  -
                   naive local time plus ``tz=`` argument
temp_air (AIRT)    air temperature at screen height            degC (or K, see
                                                               ``temp_unit``)
relative_humidity  relative humidity over water                %
(HUMID)            — or ``temp_dew`` (dew point)               degC / K
wind_speed (WIND)  true wind speed at 10 m (scenarios: at      m/s
                   ``weather.wind_height``, reduced to 10 m)
wind_direction     direction the wind blows FROM, clockwise    deg
(WINDIR)           from north
cloud_cover        total cloud fraction                        0–1 (or % / tenths /
(CLOUD)                                                        oktas: ``cloud_unit``)
ghi (SOLAR)        global horizontal irradiance — optional     W/m2
longwave_down      downwelling long-wave — optional            W/m2
(LWIR)
temp_sea (SST)     sea surface temperature                     degC (or K)
=================  =========================================  ====================

Optional columns may be absent or empty; an empty cell in an optional column means
"not measured" for that column only if the whole column is empty — partial gaps are
rejected, as are NaN in required columns, unknown units and missing time steps.
Records with gaps, off-the-hour times or other formats (NDBC) go through
:mod:`shipthermal.environment.station`, which interpolates short gaps and reports them
(the user documentation of the columns: docs/WEATHER.md).
"""

from __future__ import annotations

import dataclasses
import os
import re
from typing import Optional

import numpy as np
import pandas as pd

from shipthermal.errors import InputError, require
from shipthermal.parameters import CLOUD_COVER_SCALE, TEMP_UNITS
from shipthermal.units import ZERO_CELSIUS, fold_time

from .sky import dew_point, relative_humidity_from_dew_point

__all__ = [
    "Weather",
    "WeatherSample",
    "CSV_COLUMNS",
    "RADTHERM_ALIASES",
    "read_weather_csv",
    "read_csv_frame",
    "SOLAR_INTERVALS",
    "CALM_WIND_SPEED",
    "interpolate_wind_direction",
]

SOLAR_INTERVALS = ("instant", "ending", "centred")
"""What a record's ``ghi`` value at time t is: the irradiance at t (``instant``), or its mean
over the step ending at t (``ending``: EPW, TMY2, TMY3 files, whose irradiance is the
energy of the hour before the time given) or centred on t (``centred``)."""

CSV_COLUMNS = ("time", "temp_air", "relative_humidity", "temp_dew", "wind_speed",
               "wind_direction", "cloud_cover", "ghi", "longwave_down", "temp_sea")
"""Canonical CSV column names."""

RADTHERM_ALIASES = {
    "AIRT": "temp_air", "SOLAR": "ghi", "WIND": "wind_speed", "HUMID": "relative_humidity",
    "CLOUD": "cloud_cover", "LWIR": "longwave_down", "WINDIR": "wind_direction",
    "SST": "temp_sea", "DEWPT": "temp_dew", "TIME": "time",
}
"""RadTherm-like column names accepted by the CSV reader (case-insensitive)."""

# Physical plausibility limits used by validation (what a user could mistype).
_LIMITS = {
    "temp_air": (183.0, 333.0, "K (−90…60 degC)"),
    "temp_sea": (269.0, 310.0, "K (−4…37 degC; sea water freezes near −1.9 degC)"),
    "relative_humidity": (0.0, 100.0, "%"),
    "wind_speed": (0.0, 75.0, "m/s"),
    "wind_direction": (0.0, 360.0, "deg"),
    "cloud_cover": (0.0, 1.0, "fraction"),
    "ghi": (0.0, 1500.0, "W/m2"),
    "longwave_down": (50.0, 600.0, "W/m2"),
}


CALM_WIND_SPEED = 1e-3
"""Least weight [m/s] of an hour's wind vector when the direction is interpolated between
hours (:meth:`Weather.at`): a calm hour then does not steer the direction, yet still has one."""


def interpolate_wind_direction(x, xp, wind_direction, weight=1.0):
    """Wind direction at ``x`` from directions at ``xp``: the direction of the linearly
    interpolated wind vector, so that 350° → 10° passes through north.

    The one rule for the wind direction between observations or record steps.

    Parameters
    ----------
    x : array_like
        Times to interpolate to [s] (any common origin with ``xp``).
    xp : array_like
        Increasing times of the directions [s].
    wind_direction : array_like
        Direction the wind blows from at ``xp``, clockwise from north [deg].
    weight : array_like
        Length of each vector: the wind speed [m/s] where it is known at the same times
        (a record: :meth:`Weather.at`), or 1 (unit vectors: a station's observations,
        whose speed and direction go missing independently).

    Returns
    -------
    numpy.ndarray
        Direction in [0, 360) [deg].
    """
    phi = np.radians(wind_direction)
    u = np.interp(x, xp, weight * np.sin(phi))
    v = np.interp(x, xp, weight * np.cos(phi))
    return np.degrees(np.arctan2(u, v)) % 360.0


@dataclasses.dataclass(frozen=True)
class WeatherSample:
    """Weather interpolated to given times (arrays of the same length).

    Attributes: ``temp_air`` [K], ``relative_humidity`` [%], ``wind_speed`` [m/s],
    ``wind_direction`` [deg from N, blowing from], ``cloud_cover`` [0-1], ``ghi``
    [W/m2] or None, ``longwave_down`` [W/m2] or None, ``temp_sea`` [K].
    """

    temp_air: np.ndarray
    relative_humidity: np.ndarray
    wind_speed: np.ndarray
    wind_direction: np.ndarray
    cloud_cover: np.ndarray
    ghi: Optional[np.ndarray]
    longwave_down: Optional[np.ndarray]
    temp_sea: np.ndarray


@dataclasses.dataclass(frozen=True)
class Weather:
    """A regular time series of weather at one site (validated on construction).

    Parameters
    ----------
    time : pandas.DatetimeIndex
        Time-zone-aware, strictly increasing, constant step (normally 1 h).
    temp_air : array_like
        Air temperature [K].
    relative_humidity : array_like
        Relative humidity [%].
    wind_speed : array_like
        True wind speed [m/s].
    wind_direction : array_like
        Wind direction, blowing FROM, clockwise from north [deg].
    cloud_cover : array_like
        Total cloud fraction [0-1].
    temp_sea : array_like
        Sea surface (bulk) temperature [K].
    ghi : array_like, optional
        Measured global horizontal irradiance [W/m2]: at each time, or the mean over the
        step ending at or centred on each time (``solar_interval``).
    longwave_down : array_like, optional
        Measured downwelling long-wave [W/m2].
    solar_interval : {'instant', 'ending', 'centred'}
        What ``ghi`` means (:data:`SOLAR_INTERVALS`). With a mean, :meth:`at` gives the mean
        of the step a time falls in; :class:`~shipthermal.environment.Environment` spreads
        each step's energy over the step by the sun's course, keeping every step's integral.
    periodic : bool
        The record is one period of a repeating cycle (e.g. a climatological day):
        :meth:`at` wraps times modulo ``len(time) * step`` and interpolates across
        the wrap from the last sample back to the first.
    source : str
        Where the data came from (for reports).
    """

    time: pd.DatetimeIndex
    temp_air: np.ndarray
    relative_humidity: np.ndarray
    wind_speed: np.ndarray
    wind_direction: np.ndarray
    cloud_cover: np.ndarray
    temp_sea: np.ndarray
    ghi: Optional[np.ndarray] = None
    longwave_down: Optional[np.ndarray] = None
    periodic: bool = False
    source: str = ""
    solar_interval: str = "instant"

    def __post_init__(self):
        time = self.time
        if not isinstance(time, pd.DatetimeIndex):
            try:
                time = pd.DatetimeIndex(time)
            except (TypeError, ValueError) as exc:
                raise InputError("weather.time", self.time, "must be datetimes") from exc
        require(time.tz is not None, "weather.time", time[:3].astype(str).tolist(),
                "must be time-zone aware",
                "Give an offset in the time strings or pass tz='Etc/GMT-8' (UTC+8) to the reader")
        require(len(time) >= 2, "weather.time", len(time), "needs at least 2 time steps")
        require(self.solar_interval in SOLAR_INTERVALS, "weather.solar_interval",
                self.solar_interval, f"must be one of {', '.join(SOLAR_INTERVALS)}")
        object.__setattr__(self, "time", time)
        n = len(time)
        for name in ("temp_air", "relative_humidity", "wind_speed", "wind_direction",
                     "cloud_cover", "temp_sea", "ghi", "longwave_down"):
            val = getattr(self, name)
            if val is None:
                continue
            arr = np.broadcast_to(np.asarray(val, dtype=float), (n,)).copy() \
                if np.ndim(val) == 0 else np.asarray(val, dtype=float)
            require(arr.shape == (n,), f"weather.{name}", arr.shape,
                    f"must have one value per time step ({n})")
            bad = np.flatnonzero(~np.isfinite(arr))
            if bad.size:
                raise InputError(f"weather.{name}[{time[bad[0]]}]", float(arr[bad[0]]),
                                 "must be a finite number (no NaN / missing value)",
                                 f"{bad.size} missing value(s); fill or drop these rows")
            lo, hi, unit = _LIMITS[name]
            out = np.flatnonzero((arr < lo) | (arr > hi))
            if out.size:
                fix = ""
                if name in ("temp_air", "temp_sea"):
                    fix = "Temperatures are kelvin inside; check the file's temperature unit"
                elif name == "cloud_cover":
                    fix = "Cloud cover is a fraction 0-1; convert % / tenths / oktas"
                raise InputError(f"weather.{name}[{time[out[0]]}]", float(arr[out[0]]),
                                 f"must lie in [{lo:g}, {hi:g}] {unit}", fix)
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        dt = np.diff(time.asi8)
        if not np.all(dt > 0):
            raise InputError("weather.time", _first_bad(time, dt <= 0),
                             "must be strictly increasing (no duplicates, sorted)",
                             "Sort the file by time; for TMY3 pass coerce_year")
        if not np.all(dt == dt[0]):
            i = int(np.flatnonzero(dt != dt[0])[0])
            step = time[1] - time[0]
            raise InputError("weather.time", f"{time[i]} -> {time[i + 1]}",
                             f"must have a constant step of {step} (missing or extra time "
                             "steps found)", "Fill the missing hours in the file")

    # ------------------------------------------------------------------ helpers
    @property
    def step(self) -> float:
        """Time step [s]."""
        return (self.time[1] - self.time[0]).total_seconds()

    @property
    def start(self) -> pd.Timestamp:
        """First instant (tz-aware)."""
        return self.time[0]

    @property
    def period(self) -> Optional[float]:
        """Length of the repeated cycle of a periodic record, ``len(time) * step`` [s];
        None for a record that does not repeat."""
        return len(self.time) * self.step if self.periodic else None

    def fold(self, seconds):
        """Seconds after :attr:`start` folded into the cycle of a periodic record
        (``seconds mod period``); unchanged for a record that does not repeat.

        The one place where a time is folded into the weather's period.
        """
        return fold_time(np.asarray(seconds), self.period) if self.periodic else seconds

    @property
    def temp_dew(self) -> np.ndarray:
        """Dew point [K] (Magnus)."""
        return dew_point(self.temp_air, np.maximum(self.relative_humidity, 0.1))

    @property
    def tz(self):
        return self.time.tz

    def seconds(self, times) -> np.ndarray:
        """Convert instants (tz-aware) or floats [s after :attr:`start`] to seconds."""
        arr = times if isinstance(times, (pd.DatetimeIndex, pd.Timestamp)) else np.asarray(times)
        if isinstance(arr, (pd.DatetimeIndex, pd.Timestamp)) or arr.dtype.kind in "MO":
            idx = pd.DatetimeIndex(np.atleast_1d(times))
            require(idx.tz is not None, "times", idx[:3].astype(str).tolist(),
                    "must be time-zone aware (or floats in seconds after weather.start)")
            return np.asarray((idx - self.start).total_seconds(), dtype=float)
        return np.asarray(times, dtype=float)

    def at(self, times) -> WeatherSample:
        """Interpolate all fields linearly to ``times``.

        Parameters
        ----------
        times : pandas.DatetimeIndex or array_like of float
            Instants, or seconds after :attr:`start`.

        Returns
        -------
        WeatherSample
            Arrays shaped like ``times``. Wind speed is interpolated as a scalar and the
            direction from the interpolated wind vector (so the direction never
            sweeps the long way round); cloud cover, humidity and irradiance linearly
            (a ``ghi`` given as step means: the mean of the step ``t`` falls in).

        Raises
        ------
        InputError
            If a time lies outside the record and the record is not periodic.
        """
        s = np.atleast_1d(self.seconds(times)).astype(float)
        tk = np.asarray((self.time - self.start).total_seconds(), dtype=float)
        if self.periodic:
            s = self.fold(s)
            tk = np.append(tk, self.period)

            def wrap(a):
                return np.append(a, a[0])
        else:
            lo, hi = tk[0], tk[-1]
            bad = np.flatnonzero((s < lo - 1e-6) | (s > hi + 1e-6))
            if bad.size:
                t_bad = self.start + pd.Timedelta(seconds=float(s[bad[0]]))
                raise InputError("times", str(t_bad),
                                 f"must lie within the weather record {self.time[0]} … "
                                 f"{self.time[-1]}", "Extend the weather file or make it periodic")

            def wrap(a):
                return a

        def lin(a):
            return None if a is None else np.interp(s, tk, wrap(a))

        ghi = lin(self.ghi)
        if self.ghi is not None and self.solar_interval != "instant":
            # the mean of the step the time falls in (the ends of a step belong to it)
            offset = {"ending": 0.0, "centred": 0.5 * self.step}[self.solar_interval]
            k = np.ceil((s - offset) / self.step - 1e-9).astype(int)
            n = len(self.ghi)
            ghi = self.ghi[np.mod(k, n)] if self.periodic else self.ghi[np.clip(k, 0, n - 1)]

        direction = interpolate_wind_direction(
            s, tk, wrap(self.wind_direction), wrap(np.maximum(self.wind_speed, CALM_WIND_SPEED)))
        return WeatherSample(
            temp_air=lin(self.temp_air),
            relative_humidity=lin(self.relative_humidity),
            wind_speed=lin(self.wind_speed),
            wind_direction=direction,
            cloud_cover=lin(self.cloud_cover),
            ghi=ghi,
            longwave_down=lin(self.longwave_down),
            temp_sea=lin(self.temp_sea),
        )

    def to_frame(self) -> pd.DataFrame:
        """The record as a DataFrame (SI units, kelvin)."""
        cols = {k: getattr(self, k) for k in ("temp_air", "relative_humidity", "wind_speed",
                                              "wind_direction", "cloud_cover", "temp_sea",
                                              "ghi", "longwave_down")
                if getattr(self, k) is not None}
        return pd.DataFrame(cols, index=self.time)


def _first_bad(time, mask):
    i = int(np.flatnonzero(mask)[0])
    return f"{time[i]} -> {time[i + 1]}"


_TEMP_UNIT_ALIASES = {"degC": "C", "celsius": "C", "kelvin": "K", "degF": "F",
                      "fahrenheit": "F"}


def _temperature(values, unit: str, field: str):
    unit = _TEMP_UNIT_ALIASES.get(unit, unit)
    if unit not in TEMP_UNITS:
        raise InputError(field, unit, "must be " + " or ".join(repr(u) for u in TEMP_UNITS))
    if unit == "F":
        return (values - 32.0) / 1.8 + ZERO_CELSIUS
    return values + ZERO_CELSIUS if unit == "C" else values


def _cloud(values, unit: str):
    try:
        return values / CLOUD_COVER_SCALE[unit]
    except KeyError:
        raise InputError("cloud_unit", unit, f"must be one of {sorted(CLOUD_COVER_SCALE)}")


def read_weather_csv(path, tz: Optional[str] = None, temp_unit: str = "C",
                     cloud_unit: str = "fraction", temp_sea=None,
                     periodic: bool = False) -> Weather:
    """Read a weather CSV file (columns documented in the module docstring).

    Parameters
    ----------
    path : str or path-like
        CSV file.
    tz : str, optional
        Time zone for naive time strings, e.g. ``'Etc/GMT-8'`` (UTC+8; note the
        POSIX sign) or ``'Asia/Shanghai'``. Times with an offset are converted to it.
    temp_unit : {'C', 'K', 'F'}
        Unit of temp_air, temp_dew and temp_sea in the file.
    cloud_unit : {'fraction', 'percent', 'tenths', 'oktas'}
        Unit of cloud_cover in the file.
    temp_sea : float, optional
        Constant SST [K] when the file has no temp_sea / SST column.
    periodic : bool
        See :class:`Weather`.

    Returns
    -------
    Weather
        The rows as they are: a regular time step and no missing value in a required
        column. Records with gaps or off-the-hour times go through
        :func:`shipthermal.environment.station.to_weather` instead.
    """
    df = read_csv_frame(path, tz=tz, temp_unit=temp_unit, cloud_unit=cloud_unit)
    require("temp_sea" in df.columns or temp_sea is not None, "weather.columns",
            list(df.columns), "needs 'temp_sea' (SST) or the temp_sea= argument")
    for col in ("wind_speed", "wind_direction", "cloud_cover"):
        require(col in df.columns, "weather.columns", list(df.columns),
                f"missing required column {col!r}", f"Add a {col!r} column (see docs)")

    def optional(col):
        if col not in df.columns:
            return None
        vals = df[col].to_numpy(dtype=float)
        return None if np.all(np.isnan(vals)) else vals

    sst = df["temp_sea"].to_numpy(dtype=float) if "temp_sea" in df.columns else temp_sea
    return Weather(time=df.index, temp_air=df["temp_air"].to_numpy(dtype=float),
                   relative_humidity=df["relative_humidity"].to_numpy(dtype=float),
                   wind_speed=df["wind_speed"].to_numpy(dtype=float),
                   wind_direction=df["wind_direction"].to_numpy(dtype=float) % 360.0,
                   cloud_cover=df["cloud_cover"].to_numpy(dtype=float),
                   temp_sea=sst, ghi=optional("ghi"), longwave_down=optional("longwave_down"),
                   periodic=periodic, source=f"csv:{os.path.basename(str(path))}")


def read_csv_frame(path, tz: Optional[str] = None, temp_unit: str = "C",
                   cloud_unit: str = "fraction") -> pd.DataFrame:
    """The rows of a weather CSV file in SI units, missing values kept as NaN.

    Parameters are those of :func:`read_weather_csv`. Returns a DataFrame indexed by the
    time-zone-aware time, with the canonical columns the file has (``temp_dew`` turned
    into ``relative_humidity``; temperatures in K, cloud cover as a fraction). Empty
    cells are NaN; text in a number column, unknown or repeated columns, a missing
    ``time`` / ``temp_air`` column, or neither humidity nor dew point are refused.
    """
    require(os.path.isfile(path), "weather.source", str(path), "must be an existing file")
    name = os.path.basename(str(path))
    _sniff_csv(path, name)
    try:
        df = pd.read_csv(path, comment="#", skipinitialspace=True)
    except UnicodeDecodeError as exc:
        raise InputError("weather.source", name, f"must be UTF-8 text (byte {exc.start} is "
                         "not)", "Save the file as UTF-8 CSV") from None
    except pd.errors.EmptyDataError:
        raise InputError("weather.source", name, "is empty", "Give the weather CSV "
                         "(docs/WEATHER.md)") from None
    except pd.errors.ParserError:
        raise InputError("weather.source", name, f"is not a readable CSV file "
                         f"({_ragged_line(path) or 'rows do not match the header'})",
                         "Every row needs one value per header column, separated by "
                         "commas") from None
    rename = {}
    for k, col in enumerate(df.columns):
        key = str(col).strip()
        if key.upper() in RADTHERM_ALIASES:
            rename[col] = RADTHERM_ALIASES[key.upper()]
        elif key.lower() in CSV_COLUMNS:
            rename[col] = key.lower()
        else:
            raise InputError(f"weather.source ({name}) column {k + 1}", _shown(key),
                             f"is an unknown column; allowed: {', '.join(CSV_COLUMNS)} or "
                             f"{', '.join(RADTHERM_ALIASES)}",
                             "See docs/WEATHER.md for the columns and their units")
    df = df.rename(columns=rename)
    dup = df.columns[df.columns.duplicated()].tolist()
    require(not dup, "weather.columns", dup, "each quantity may appear only once")
    for col in ("time", "temp_air"):
        require(col in df.columns, "weather.columns", list(df.columns),
                f"missing required column {col!r}", f"Add a {col!r} column (see docs)")
    require("relative_humidity" in df.columns or "temp_dew" in df.columns,
            "weather.columns", list(df.columns),
            "missing required column 'relative_humidity' (HUMID) or 'temp_dew' (DEWPT)",
            "Add one of them (docs/WEATHER.md)")
    require(len(df) > 0, "weather.source", name, "holds no data rows")
    time = pd.to_datetime(df["time"].astype(str), format="ISO8601", errors="coerce")
    if time.isna().any():
        i = int(np.flatnonzero(time.isna().to_numpy())[0])
        raise InputError(f"weather.source ({name}) row {i + 2}: time",
                         _shown(str(df["time"].iloc[i])), "must be an ISO 8601 instant",
                         "e.g. 2023-07-15T00:00:00+08:00, or 2023-07-15 00:00 with "
                         "[location] time_zone for local times")
    try:
        time = pd.DatetimeIndex(time)
    except (ValueError, TypeError):
        raise InputError(f"weather.source ({name}): time", None, "must give every row the "
                         "same UTC offset, or none", "Write offsets in every row, or none "
                         "(local times in [location] time_zone)") from None
    if time.tz is None:
        require(tz is not None, "weather.time", str(df["time"].iloc[0]),
                "has no UTC offset", "Pass tz='Etc/GMT-8' (UTC+8) or write offsets in the file")
        time = time.tz_localize(tz)
    elif tz is not None:
        time = time.tz_convert(tz)

    def num(col):
        vals = pd.to_numeric(df[col], errors="coerce").to_numpy(dtype=float)
        text_bad = df[col].notna().to_numpy() & ~np.isfinite(vals)
        if text_bad.any():
            i = int(np.flatnonzero(text_bad)[0])
            raise InputError(f"weather.source ({name}) row {i + 2}: {col}",
                             _shown(str(df[col].iloc[i])), "must be a number",
                             "Leave the cell empty for a missing value")
        return vals

    out = {"temp_air": _temperature(num("temp_air"), temp_unit, "temp_unit")}
    if "relative_humidity" in df.columns:
        out["relative_humidity"] = num("relative_humidity")
    else:
        td = _temperature(num("temp_dew"), temp_unit, "temp_unit")
        out["relative_humidity"] = np.minimum(
            relative_humidity_from_dew_point(out["temp_air"], td), 100.0)
    if "temp_sea" in df.columns:
        out["temp_sea"] = _temperature(num("temp_sea"), temp_unit, "temp_unit")
    for col in ("wind_speed", "ghi", "longwave_down"):
        if col in df.columns:
            out[col] = num(col)
    if "wind_direction" in df.columns:
        out["wind_direction"] = num("wind_direction") % 360.0
    if "cloud_cover" in df.columns:
        out["cloud_cover"] = _cloud(num("cloud_cover"), cloud_unit)
    return pd.DataFrame(out, index=pd.DatetimeIndex(time, name="time"))


_SHOWN = re.compile(r"[A-Za-z0-9_ .,+%()\-]{1,24}")


def _shown(text: str) -> str:
    """A cell or column name of a user's file as it may appear in a message: short,
    word-like text as it is; anything else only by its length (a path may point at a file
    that must not be shown)."""
    text = str(text)
    return text if _SHOWN.fullmatch(text) else f"({len(text)} characters not shown)"


def _sniff_csv(path, name: str) -> None:
    """Refuse, with the format key, files that are another weather format named .csv,
    and files separated by semicolons (the file's contents are not quoted)."""
    with open(path, "rb") as fh:
        head = fh.read(4096)
    lines = head.decode("utf-8", "replace").splitlines()
    first = lines[0].strip() if lines else ""
    second = lines[1] if len(lines) > 1 else ""
    if first.startswith("#YY") or first[:4] in ("YY M", "YYYY"):
        raise InputError("weather.source", name, "looks like an NDBC standard meteorological "
                         "file (first line '#YY MM DD hh ...'), not a weather CSV",
                         'Set weather.format = "ndbc" (and weather.wind_height: the '
                         "anemometer height)")
    if "Date (MM/DD/YYYY)" in second:
        raise InputError("weather.source", name, "looks like a TMY3 file (second line 'Date "
                         "(MM/DD/YYYY),Time (HH:MM),...'), not a weather CSV",
                         'Set weather.format = "tmy3" (and weather.temp_sea)')
    if first.startswith("LOCATION,"):
        raise InputError("weather.source", name, "looks like an EPW file (first line "
                         "'LOCATION,...'), not a weather CSV", "Give it the suffix .epw "
                         "(and set weather.temp_sea)")
    if ";" in first and "," not in first.replace(";", ""):
        raise InputError("weather.source", name, "is separated by semicolons; a weather CSV "
                         "is separated by commas, with decimal points",
                         "Save it as comma-separated CSV (decimal point '.')")


def _ragged_line(path) -> str:
    """``"line N has k fields, the header m"`` for the first row whose field count differs
    from the header's (quotes not considered), or ""."""
    with open(path, encoding="utf-8", errors="replace") as fh:
        n = None
        for k, line in enumerate(fh, start=1):
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            m = line.count(",") + 1
            if n is None:
                n = m
            elif m != n:
                return f"line {k} has {m} fields, the header {n}"
    return ""
