"""When a satellite sees the port, and from where: overpass times and view geometry.

Three sources, one result (a list of :class:`Overpass`, each an instant with the view
zenith and azimuth at the ground):

* **a named satellite** (:data:`SATELLITES`): its two-line elements (NORAD, public
  domain) are propagated with SGP4 (``skyfield``) over one ground-track repeat cycle around
  their epoch, and the passes that put the site inside the swath are repeated every cycle
  over the requested span. This is how the Landsat acquisition schedule (WRS-2) works: the
  orbit is kept on its reference ground track (within a few km) and local time, so a path
  is imaged at the same UTC time of day every 16 days, year after year; SGP4 alone drifts
  along the track when propagated for years past its epoch. Checked against a real
  acquisition: the Landsat-8 elements of 2025-08-13 put their near-nadir passes over the
  Mersey scene of ``examples/real_port`` on the days that are a whole number of cycles from
  its acquisition (2020-09-27 11:10:50 UTC), at 11:10:10–11:10:30 UTC;
* **the user's two-line elements** (any satellite, e.g. the ISS carrying ECOSTRESS, or a
  fresher set for a named one): propagated directly over the span (SGP4's error grows by
  roughly a kilometre a day away from the epoch: give elements within a few weeks of the
  span);
* **a list of instants** (e.g. the acquisition times of scenes you have), with a view
  direction.

A pass counts when the site lies within the sensor's swath: its off-nadir angle seen from
the satellite is at most half the swath's angle (:func:`swath_half_angle`). Day and night
passes both count (a thermal sensor images both).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import pandas as pd

from shipthermal.errors import InputError, check_range, require

from .parameters import MAX_TLE_DISTANCE_DAYS

__all__ = ["Overpass", "Satellite", "SATELLITES", "swath_half_angle", "satellite",
           "parse_tle", "check_tle_epoch", "tle_overpasses", "satellite_overpasses",
           "listed_overpasses", "EARTH_RADIUS_M"]

EARTH_RADIUS_M = 6371.0e3
"""Mean Earth radius [m] (IUGG), for the swath's angle from the satellite."""


@dataclass(frozen=True)
class Overpass:
    """One look at the site.

    Attributes
    ----------
    time_utc : pandas.Timestamp
        Instant of the closest approach (tz-aware, UTC).
    view_zenith_deg : float
        Zenith angle of the satellite seen from the site [deg] (0 nadir view).
    view_azimuth_deg : float
        Compass azimuth of the satellite seen from the site [deg].
    off_nadir_deg : float
        The site's angle from nadir seen from the satellite [deg].
    satellite : str
    source : str
        How the instant was found.
    """

    time_utc: pd.Timestamp
    view_zenith_deg: float
    view_azimuth_deg: float
    off_nadir_deg: float
    satellite: str
    source: str


@dataclass(frozen=True)
class Satellite:
    """A satellite's orbit and swath.

    Attributes
    ----------
    name : str
    norad_id : int
    tle : tuple of str
        Two-line elements (NORAD / CelesTrak, public domain) and their epoch.
    repeat_days : float
        Ground-track repeat cycle [days] (None: not a repeating orbit, give fresh elements).
    swath_m : float
        Swath width at the ground [m].
    altitude_m : float
        Nominal altitude [m].
    launched : str
        Launch date (no overpass before it).
    source : str
    """

    name: str
    norad_id: int
    tle: tuple
    repeat_days: float | None
    swath_m: float
    altitude_m: float
    launched: str
    source: str


SATELLITES = {
    "landsat8": Satellite(
        "Landsat 8", 39084,
        ("1 39084U 13008A   25225.93518726  .00000330  00000-0  83304-4 0  9991",
         "2 39084  98.2219 295.6904 0001221  90.8808 269.2530 14.57106224653150"),
        16.0, 185.0e3, 705.0e3, "2013-02-11",
        "SOURCED: NORAD two-line elements of 2025-08-13 (CelesTrak; checksums valid); WRS-2 "
        "16-day repeat, 185 km swath, 705 km (USGS Landsat 8 Data Users Handbook)"),
    "landsat9": Satellite(
        "Landsat 9", 49260,
        ("1 49260U 21088A   25225.90087331  .00000343  00000-0  86120-4 0  9998",
         "2 49260  98.2240 295.6621 0001152  92.7233 267.4097 14.57102349206250"),
        16.0, 185.0e3, 705.0e3, "2021-09-27",
        "SOURCED: NORAD two-line elements of 2025-08-13 (CelesTrak; checksums valid); the "
        "Landsat 8 orbit, 8 days apart (USGS Landsat 9 Data Users Handbook)"),
}
"""Named satellites with their reference elements. The thermal bands of the instruments
(response, optics, noise) are in :mod:`imaging.sensor`; the same names select both."""


def swath_half_angle(swath_m: float, altitude_m: float) -> float:
    """Off-nadir angle [deg] of the swath's edge seen from the satellite, on a spherical
    Earth: the edge lies at the ground arc ``swath/2``, angle ``atan(R sin θ / (R + h − R
    cos θ))`` with ``θ = swath / (2 R)``."""
    theta = 0.5 * swath_m / EARTH_RADIUS_M
    return math.degrees(math.atan2(EARTH_RADIUS_M * math.sin(theta),
                                   EARTH_RADIUS_M + altitude_m - EARTH_RADIUS_M * math.cos(theta)))


def satellite(name: str) -> Satellite:
    """A named satellite; an unknown name lists the known ones."""
    key = str(name).strip().lower().replace("-", "").replace(" ", "").replace("_", "")
    if key not in SATELLITES:
        import difflib

        close = difflib.get_close_matches(key, list(SATELLITES), n=1)
        raise InputError("calendar.satellites", name, f"must be one of {', '.join(SATELLITES)}",
                         f"Did you mean {close[0]!r}?" if close else
                         "For another satellite give its two-line elements: calendar.tle "
                         "with calendar.swath [m]")
    return SATELLITES[key]


def _checksum(line: str) -> int:
    return sum(int(c) if c.isdigit() else (1 if c == "-" else 0) for c in line[:68]) % 10


_TLE_NUMBERS = ((1, 18, 32, "epoch"), (2, 8, 16, "inclination"), (2, 17, 25, "right ascension"),
                (2, 26, 33, "eccentricity"), (2, 52, 63, "mean motion"))
"""(line, first column - 1, last column, name) of the numbers SGP4 needs (NORAD format)."""


def parse_tle(text: str, field: str = "calendar.tle", source: str | None = None) -> tuple:
    """``(name, line1, line2)`` of the first two-line element set in ``text`` (an optional
    name line before it), each line checked (length, line numbers, matching catalogue
    numbers, checksum, the numbers SGP4 reads). ``source`` (the file's name) is the value
    the messages show."""
    lines = [ln.rstrip() for ln in str(text).splitlines() if ln.strip()]
    for i in range(len(lines) - 1):
        l1, l2 = lines[i], lines[i + 1]
        if l1.startswith("1 ") and l2.startswith("2 "):
            name = lines[i - 1].strip() if i > 0 and not lines[i - 1].startswith(("1 ", "2 ")) \
                else l1[2:7].strip()
            for k, ln in ((1, l1), (2, l2)):
                if len(ln) < 69:
                    raise InputError(field, source or f"line {k}", f"line {k} has {len(ln)} "
                                     "characters; a two-line element line has 69",
                                     "Copy both lines whole from CelesTrak or Space-Track")
                if not ln[68].isdigit() or _checksum(ln) != int(ln[68]):
                    raise InputError(field, source or f"line {k}", f"line {k} fails its "
                                     f"checksum (column 69 is {ln[68]!r}, the digits give "
                                     f"{_checksum(ln)})", "The line was altered: copy it again")
            if l1[2:7] != l2[2:7]:
                raise InputError(field, source or f"{l1[2:7]} / {l2[2:7]}", "lines 1 and 2 "
                                 f"must belong to the same satellite (catalogue numbers "
                                 f"{l1[2:7].strip()} and {l2[2:7].strip()})",
                                 "Copy both lines of one satellite")
            for k, a, b, what in _TLE_NUMBERS:
                cell = (l1, l2)[k - 1][a:b]
                try:
                    float(("0." + cell.strip()) if what == "eccentricity" else cell)
                except ValueError:
                    raise InputError(field, source or f"line {k}", f"line {k} columns "
                                     f"{a + 1}-{b} ({what}) must be a number, not "
                                     f"{cell.strip()[:12]!r}",
                                     "Copy both lines whole from CelesTrak or Space-Track") \
                        from None
            return name, l1, l2
    shown = source or ((lines[0][:30] + "…") if lines else "(empty)")
    raise InputError(field, shown, "must hold two-line elements: a line starting '1 ' then "
                     "one starting '2 '", "Save the satellite's elements from CelesTrak as "
                     "a text file")


def check_tle_epoch(line1: str, start, end, field: str = "calendar.tle",
                    source: str | None = None) -> pd.Timestamp:
    """The epoch of a set of elements, refused when an instant of ``[start, end]`` lies
    more than :data:`~imaging.parameters.MAX_TLE_DISTANCE_DAYS` from it."""
    epoch = _tle_epoch(line1)
    start, end = pd.Timestamp(start).tz_convert("UTC"), pd.Timestamp(end).tz_convert("UTC")
    far = max(abs((start - epoch).total_seconds()), abs((end - epoch).total_seconds())) / 86400.0
    if far > MAX_TLE_DISTANCE_DAYS:
        raise InputError(field, source or line1[18:32].strip(), f"holds elements of "
                         f"{epoch:%Y-%m-%d}, {far:,.0f} days from the record "
                         f"({start:%Y-%m-%d} … {end:%Y-%m-%d}); SGP4 is trusted to "
                         f"{MAX_TLE_DISTANCE_DAYS:g} days from the epoch",
                         "Give elements from within a few weeks of the record (Space-Track "
                         "keeps every past set), or list the overpass times (calendar.times)")
    return epoch


def _passes(l1, l2, name, latitude, longitude, start, end, half_angle, altitude_m, source):
    """SGP4 passes within the swath between two UTC instants."""
    from skyfield.api import EarthSatellite, load, wgs84

    ts = load.timescale(builtin=True)
    sat = EarthSatellite(l1, l2, name, ts)
    site = wgs84.latlon(latitude, longitude)
    # the elevation of the swath's edge at the site: off-nadir a, zenith z = asin((R+h)/R sin a)
    z_edge = math.degrees(math.asin(min(1.0, (EARTH_RADIUS_M + altitude_m) / EARTH_RADIUS_M
                                        * math.sin(math.radians(half_angle)))))
    t0 = ts.from_datetime(pd.Timestamp(start).tz_convert("UTC").floor("us").to_pydatetime())
    t1 = ts.from_datetime(pd.Timestamp(end).tz_convert("UTC").floor("us").to_pydatetime())
    times, events = sat.find_events(site, t0, t1, altitude_degrees=max(0.0, 90.0 - z_edge - 1))
    out = []
    for t, e in zip(times, events):
        if e != 1:
            continue
        alt, az, dist = (sat - site).at(t).altaz()
        zen = 90.0 - alt.degrees
        # law of sines in (Earth's centre, site, satellite): sin(off) = R sin(z) / |r_sat|
        r_sat = float(sat.at(t).distance().m)
        off = math.degrees(math.asin(min(1.0, EARTH_RADIUS_M / r_sat
                                         * math.sin(math.radians(zen)))))
        if off > half_angle:
            continue
        when = pd.Timestamp(t.utc_datetime()).tz_convert("UTC")
        out.append(Overpass(when, float(zen), float(az.degrees) % 360.0, float(off), name,
                            source))
    return out


def tle_overpasses(tle_text: str, latitude: float, longitude: float, start, end, *,
                   swath_m: float, altitude_m: float | None = None,
                   source: str | None = None) -> list:
    """Passes of a satellite given by its two-line elements over ``[start, end]``
    (tz-aware) with the site inside the swath ``swath_m`` [m]; elements farther than
    :data:`~imaging.parameters.MAX_TLE_DISTANCE_DAYS` from the span are refused
    (``source``, the file's name, is what the messages show)."""
    name, l1, l2 = parse_tle(tle_text, source=source)
    check_tle_epoch(l1, start, end, source=source)
    check_range("calendar.swath", swath_m, 1.0e3, 3.0e6, "m")
    if altitude_m is None:
        n = float(l2[52:63])                     # mean motion [rev/day] -> semi-major axis
        mu = 3.986004418e14
        a = (mu / (2.0 * math.pi * n / 86400.0) ** 2) ** (1.0 / 3.0)
        altitude_m = a - 6378.137e3
    return _passes(l1, l2, name, latitude, longitude, start, end,
                   swath_half_angle(swath_m, altitude_m), altitude_m, "two-line elements")


def satellite_overpasses(name: str, latitude: float, longitude: float, start, end) -> list:
    """Overpasses of a named satellite (:data:`SATELLITES`) over ``[start, end]``: its
    passes over the site in the repeat cycle around its elements' epoch, repeated every
    cycle (the reference ground track; module docstring)."""
    sat = satellite(name)
    _, l1, l2 = parse_tle("\n".join(sat.tle))
    epoch = _tle_epoch(l1)
    cycle = pd.Timedelta(days=sat.repeat_days)
    ref = _passes(l1, l2, sat.name, latitude, longitude, epoch - 0.5 * cycle,
                  epoch + 0.5 * cycle, swath_half_angle(sat.swath_m, sat.altitude_m),
                  sat.altitude_m, f"{sat.name} reference orbit")
    start, end = pd.Timestamp(start).tz_convert("UTC"), pd.Timestamp(end).tz_convert("UTC")
    start = max(start, pd.Timestamp(sat.launched, tz="UTC"))
    out = []
    for p in ref:
        k0 = math.floor((start - p.time_utc) / cycle)
        k1 = math.ceil((end - p.time_utc) / cycle)
        for k in range(k0, k1 + 1):
            t = p.time_utc + k * cycle
            if start <= t <= end:
                out.append(Overpass(t, p.view_zenith_deg, p.view_azimuth_deg, p.off_nadir_deg,
                                    p.satellite, f"{p.source}, repeated every "
                                    f"{sat.repeat_days:g} days"))
    return sorted(out, key=lambda o: o.time_utc)


def listed_overpasses(times, view_zenith_deg: float = 0.0, view_azimuth_deg: float = 0.0,
                      name: str = "listed") -> list:
    """Overpasses at given instants (tz-aware, or ISO strings with an offset) with one view
    direction."""
    out = []
    for i, t in enumerate(times):
        ts_ = pd.Timestamp(t)
        require(ts_.tzinfo is not None, f"calendar.times[{i}]", str(t),
                "must carry its time zone or offset", "e.g. 2020-09-27T11:10:50Z")
        out.append(Overpass(ts_.tz_convert("UTC"), float(view_zenith_deg),
                            float(view_azimuth_deg), float(view_zenith_deg), name, "listed"))
    return sorted(out, key=lambda o: o.time_utc)


def _tle_epoch(line1: str) -> pd.Timestamp:
    yy = int(line1[18:20])
    day = float(line1[20:32])
    year = 2000 + yy if yy < 57 else 1900 + yy
    return pd.Timestamp(f"{year}-01-01", tz="UTC") + pd.Timedelta(days=day - 1.0)
