"""Physical constants and unit helpers (SI throughout, kelvin for temperature)."""

import datetime
import zoneinfo

SIGMA = 5.670374419e-8
"""Stefan–Boltzmann constant [W m-2 K-4] (CODATA 2018, exact)."""

PLANCK = 6.62607015e-34
"""Planck constant h [J s] (SI 2019, exact)."""
SPEED_OF_LIGHT = 299792458.0
"""Speed of light in vacuum c [m s-1] (SI, exact)."""
BOLTZMANN = 1.380649e-23
"""Boltzmann constant k [J K-1] (SI 2019, exact)."""

PLANCK_C1 = 2.0 * PLANCK * SPEED_OF_LIGHT ** 2 * 1e24
"""First radiation constant for spectral radiance, 2 h c² = 1.191042972e8
[W µm4 m-2 sr-1] (from the exact SI constants; the paper's eq. 2 rounds it to 1.191e8)."""
PLANCK_C2 = PLANCK * SPEED_OF_LIGHT / BOLTZMANN * 1e6
"""Second radiation constant, h c / k = 1.438776877e4 [µm K] (from the exact SI constants;
the paper's eq. 2 rounds it to 1.4388e4)."""

ZERO_CELSIUS = 273.15
"""0 °C in kelvin [K]."""

MINUTE = 60.0
HOUR = 3600.0
DAY = 86400.0
"""Durations [s]."""


# ---- the local clock -------------------------------------------------------------------
# Every time of a run is counted in seconds after local midnight of the scenario's date in
# its IANA zone (elapsed time, so a record that crosses a daylight-saving change stays
# continuous). These helpers say which instant that origin is, in the words every product
# uses, so that no file or page leaves "local" to be guessed.


def fold_time(seconds, period, origin=0.0):
    """``origin + (seconds − origin) mod period`` [s]: a time folded into the cycle of a
    periodic axis that starts at ``origin`` (floats or numpy arrays).

    The one place a time is folded into a period: the weather's cycle
    (:meth:`shipthermal.environment.weather.Weather.fold`), the forcing's time tables, the
    ship's recorded thermal history and the background's periodic day. The floating-point
    ``mod`` is exact (Python's and numpy's agree): ``t`` and ``t + k·period`` fold to the
    same time whenever the sum itself is exact.
    """
    return origin + (seconds - origin) % period


def clock_origin(date: str, time_zone: str):
    """Local midnight of ``date`` (``YYYY-MM-DD``) in the IANA zone ``time_zone``, as an
    aware :class:`datetime.datetime`: the instant the run's clock counts from."""
    day = datetime.date.fromisoformat(str(date)[:10])
    return datetime.datetime(day.year, day.month, day.day,
                             tzinfo=zoneinfo.ZoneInfo(str(time_zone)))


def utc_offset_text(offset_hours: float, iso: bool = False) -> str:
    """A UTC offset [h] as people read it: ``UTC+8``, ``UTC-3:30``, ``UTC+0`` (``iso``:
    ``+08:00``, ``-03:30``). The sign is the direction from UTC (east positive), never the
    POSIX sign of zone names such as ``Etc/GMT-8``."""
    minutes = int(round(float(offset_hours) * 60.0))
    sign = "-" if minutes < 0 else "+"
    h, m = divmod(abs(minutes), 60)
    if iso:
        return f"{sign}{h:02d}:{m:02d}"
    return f"UTC{sign}{h}" + (f":{m:02d}" if m else "")


def clock_offset_hours(date: str, time_zone: str) -> float:
    """UTC offset of the local clock at the run's origin (:func:`clock_origin`) [h]."""
    return clock_origin(date, time_zone).utcoffset().total_seconds() / HOUR


def zone_text(date: str, time_zone: str) -> str:
    """``"UTC+8 (Etc/GMT-8)"``: the local clock's offset at the run's origin with the zone's
    name, so that a POSIX name such as ``Etc/GMT-8`` (which is UTC+8) cannot be misread."""
    return f"{utc_offset_text(clock_offset_hours(date, time_zone))} ({time_zone})"


def cf_time_units(date: str, time_zone: str, unit: str = "hours") -> str:
    """CF/UDUNITS time units counted from the run's origin with its UTC offset, e.g.
    ``"hours since 2023-07-15 00:00:00+08:00"`` (``cfchecks`` accepts it; xarray decodes
    it to UTC)."""
    origin = clock_origin(date, time_zone)
    iso = utc_offset_text(origin.utcoffset().total_seconds() / HOUR, iso=True)
    return f"{unit} since {origin:%Y-%m-%d} 00:00:00{iso}"


def longitude_text(longitude: float, digits: int = 2) -> str:
    """A longitude [deg] with its hemisphere, ``121.63 E`` / ``70.50 W`` (input in
    [-180, 360))."""
    lon = ((float(longitude) + 180.0) % 360.0) - 180.0
    return f"{abs(lon):.{digits}f} {'W' if lon < 0 else 'E'}"


def latitude_text(latitude: float, digits: int = 2) -> str:
    """A latitude [deg] with its hemisphere, ``38.91 N`` / ``33.90 S``."""
    return f"{abs(float(latitude)):.{digits}f} {'S' if latitude < 0 else 'N'}"


# ---- units in table headers ------------------------------------------------------------
# Every CSV product writes a numeric column as ``name [unit]`` (UDUNITS spelling, ``-`` for
# a dimensionless number or a count) and a column of local clock times as ``name [UTC+8]``;
# docs/DATA.md says what each column means. Readers in this package strip the brackets
# (:func:`strip_units`), so files written before units were added read the same way.

#: Units of the product columns whose unit is not in their name [UDUNITS; "-": none]
COLUMN_UNITS = {
    # imaging: metrics_<season>_<band>.csv
    "time_utc": "UTC", "scr": "-", "contrast": "W m-2 sr-1", "mean_target": "W m-2 sr-1",
    "mean_background": "W m-2 sr-1", "std_background": "W m-2 sr-1", "n_target": "-",
    "n_background": "-", "ship_mean_temp": "K", "water_mean_temp": "K",
    "path_radiance": "W m-2 sr-1", "tau_300k": "-",
    # imaging: band_comparison.csv
    "n_crossovers": "-", "scr_in_crossover_mean": "-", "scr_in_crossover_median": "-",
    "scr_out_crossover_mean": "-", "scr_out_crossover_median": "-", "scr_min": "-",
    "scr_max": "-", "n_frames_in": "-", "n_frames_out": "-",
    # thermal: forcing_summary.csv
    "faces": "-", "area": "m2", "alpha": "-", "epsilon": "-", "F_sky": "-", "F_sea": "-",
    "F_ship": "-", "sw_peak_mean": "W m-2", "sw_peak_face": "W m-2", "sw_time_of_peak": "h",
    "sw_daily_mean": "W m-2", "h_mean": "W m-2 K-1", "h_inner_mean": "W m-2 K-1",
    "temp_compartment": "K",
    # thermal: energy.csv (per step)
    "time": "s", "stored": "J", "stored_plain": "J", "boundary": "J", "source": "J",
    "gross": "J", "imbalance": "J",
    # thermal: part_means.csv (the parts' columns are K too)
    "hour": "h", "temp_air": "K", "temp_sea": "K", "temp_sea_skin": "K",
    # background: columns.csv, fit_by_class.csv
    "albedo": "-", "pixels": "-", "albedo_reflectance_median": "-", "at_bound_fraction": "-",
}

#: Unit suffixes of column names, longest first [UDUNITS]
_SUFFIX_UNITS = (("_s_m", "s m-1"), ("_W_m2", "W m-2"), ("_deg", "degree"), ("_min", "min"),
                 ("_K", "K"), ("_h", "h"), ("_s", "s"), ("_m", "m"), ("_J", "J"))


def column_unit(name: str):
    """The unit of a product column: :data:`COLUMN_UNITS`, else its name's unit suffix
    (``_K``, ``_h``, ``_deg``, ...); None when neither says."""
    if name in COLUMN_UNITS:
        return COLUMN_UNITS[name]
    for suffix, unit in _SUFFIX_UNITS:
        if name.endswith(suffix):
            return unit
    return None


def split_header(header: str) -> tuple[str, str | None]:
    """``"contrast [W m-2 sr-1]"`` → ``("contrast", "W m-2 sr-1")``; no brackets → unit None."""
    h = str(header)
    if h.endswith("]") and " [" in h:
        name, unit = h[:-1].rsplit(" [", 1)
        return name, unit
    return h, None


def with_units(df, units: dict | None = None, clock: str | None = None):
    """A copy of ``df`` whose headers carry units: ``name [unit]`` from ``units`` (column →
    unit), else :func:`column_unit`; columns named ``*_local`` or ``*_times`` hold local
    clock times and get the zone ``clock`` (e.g. ``"UTC+8"``). A named index is treated like
    a column. Text columns without a unit keep their name."""
    units = dict(units or {})

    def head(name):
        if name is None or split_header(name)[1] is not None:
            return name
        unit = units.get(name) or (clock if clock and str(name).endswith(("_local", "_times"))
                                   else column_unit(str(name)))
        return f"{name} [{unit}]" if unit else name

    out = df.rename(columns=head)
    if out.index.name is not None:
        out.index = out.index.rename(head(out.index.name))
    return out


def strip_units(df):
    """``df`` with ``name [unit]`` headers (and index name) back to ``name``; the units are
    kept in ``df.attrs["units"]`` (name → unit)."""
    units = {}

    def bare(h):
        if h is None:
            return h
        name, unit = split_header(h)
        if unit is not None:
            units[name] = unit
        return name

    out = df.rename(columns=bare)
    if out.index.name is not None:
        out.index = out.index.rename(bare(out.index.name))
    out.attrs["units"] = units
    return out
