"""Sun position and solar irradiance at the sea surface.

Sun position is pvlib's implementation of the NREL Solar Position Algorithm (SPA);
clear-sky irradiance is pvlib's Ineichen–Perez model with the Linke turbidity
climatology that ships with pvlib (works offline). Clouds attenuate the clear sky by
Kasten & Czeplak (1980); a measured global horizontal irradiance is split into direct
and diffuse parts by a published decomposition (Erbs et al. 1982 or DIRINT).

Angles are in degrees (pvlib convention), irradiance in W m-2, times tz-aware.
The local frame is East-North-Up: x = East, y = North, z = Up.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pvlib

from shipthermal.errors import InputError, check_range, require
from shipthermal.parameters import DECOMPOSITIONS

__all__ = [
    "interval_profile",
    "solar_position",
    "sun_vector",
    "clearsky_irradiance",
    "cloud_attenuation_kasten_czeplak",
    "cloudy_sky_irradiance",
    "decompose_ghi",
    "sunrise_sunset",
]


def _as_times(times, field: str = "times") -> pd.DatetimeIndex:
    idx = pd.DatetimeIndex(np.atleast_1d(times)) if not isinstance(times, pd.DatetimeIndex) \
        else times
    require(idx.tz is not None, field, times,
            "must be time-zone aware (pandas DatetimeIndex with tz)",
            "Use pd.DatetimeIndex(...).tz_localize('Etc/GMT-8') or a Weather time index")
    return idx


def solar_position(times, latitude: float, longitude: float, altitude: float = 0.0,
                   pressure: float = 101325.0, temperature: float = 12.0,
                   delta_t: float = 67.0) -> pd.DataFrame:
    """Topocentric sun position by the NREL SPA (pvlib ``spa_python``).

    Parameters
    ----------
    times : pandas.DatetimeIndex
        Time-zone-aware instants.
    latitude : float
        Latitude, north positive [deg].
    longitude : float
        Longitude, east positive [deg].
    altitude : float
        Observer height above sea level [m].
    pressure : float
        Station pressure, used for refraction [Pa].
    temperature : float
        Air temperature, used for refraction [degC] (SPA convention).
    delta_t : float
        TT − UT1 [s] (SPA input; 67 s is the 2003 value of the SPA report).

    Returns
    -------
    pandas.DataFrame
        Columns ``apparent_zenith`` (refraction-corrected), ``zenith``, ``azimuth``
        (clockwise from north) [deg] and ``elevation`` [deg].

    Notes
    -----
    Reda & Andreas (2004), "Solar position algorithm for solar radiation applications",
    Solar Energy 76, 577–589; NREL/TP-560-34302. Uncertainty ±0.0003° (−2000…6000).
    """
    idx = _as_times(times)
    check_range("latitude", latitude, -90.0, 90.0, "deg")
    check_range("longitude", longitude, -180.0, 360.0, "deg")
    pos = pvlib.solarposition.spa_python(idx, latitude, longitude, altitude=altitude,
                                         pressure=pressure, temperature=temperature,
                                         delta_t=delta_t)
    return pos[["apparent_zenith", "zenith", "azimuth", "elevation"]]


def sun_vector(zenith, azimuth):
    """Unit vector toward the sun in the local East-North-Up frame.

    Parameters
    ----------
    zenith : array_like
        Solar zenith angle [deg] (use the apparent, refraction-corrected one).
    azimuth : array_like
        Solar azimuth, clockwise from north [deg].

    Returns
    -------
    numpy.ndarray
        Shape ``(..., 3)``: (East, North, Up) components [-].
    """
    z = np.radians(np.asarray(zenith, dtype=float))
    a = np.radians(np.asarray(azimuth, dtype=float))
    sz = np.sin(z)
    return np.stack([sz * np.sin(a), sz * np.cos(a), np.cos(z)], axis=-1)


def clearsky_irradiance(times, latitude: float, longitude: float, altitude: float = 0.0,
                        apparent_zenith=None, linke_turbidity=None) -> pd.DataFrame:
    """Clear-sky GHI, DNI and DHI by the Ineichen–Perez model (pvlib).

    Parameters
    ----------
    times : pandas.DatetimeIndex
        Time-zone-aware instants.
    latitude, longitude : float
        Site [deg].
    altitude : float
        Site height [m] (enters the air mass and the Ineichen fh coefficients).
    apparent_zenith : array_like, optional
        Refraction-corrected zenith [deg]; computed by SPA if omitted.
    linke_turbidity : float or array_like, optional
        Linke turbidity [-]. Default: pvlib's monthly climatology for the site
        (Remund et al. 2003 maps, interpolated to the day of year).

    Returns
    -------
    pandas.DataFrame
        ``ghi``, ``dni``, ``dhi`` [W m-2]. By construction of the model
        ``ghi = dni cos(zenith) + dhi``.

    Notes
    -----
    Ineichen & Perez (2002), Solar Energy 73, 151–157; Perez et al. (2002) for the
    DNI part. pvlib.clearsky.ineichen.
    """
    idx = _as_times(times)
    if apparent_zenith is None:
        apparent_zenith = solar_position(idx, latitude, longitude, altitude)["apparent_zenith"]
    apparent_zenith = np.asarray(apparent_zenith, dtype=float)
    if linke_turbidity is None:
        linke_turbidity = pvlib.clearsky.lookup_linke_turbidity(idx, latitude, longitude)
    am_rel = pvlib.atmosphere.get_relative_airmass(apparent_zenith)
    pressure = pvlib.atmosphere.alt2pres(altitude)
    am_abs = pvlib.atmosphere.get_absolute_airmass(am_rel, pressure)
    dni_extra = pvlib.irradiance.get_extra_radiation(idx)
    # pvlib divides by cos(zenith) for the night rows and then zeroes them: silence it
    with np.errstate(divide="ignore", invalid="ignore"):
        cs = pvlib.clearsky.ineichen(apparent_zenith, am_abs, np.asarray(linke_turbidity),
                                     altitude=altitude, dni_extra=np.asarray(dni_extra))
    out = pd.DataFrame({k: np.nan_to_num(np.asarray(cs[k], dtype=float)) for k in
                        ("ghi", "dni", "dhi")}, index=idx)
    return out


def cloud_attenuation_kasten_czeplak(cloud_cover):
    """Ratio of cloudy to clear-sky GHI and diffuse fraction (Kasten & Czeplak 1980).

    Parameters
    ----------
    cloud_cover : array_like
        Total cloud cover fraction [0-1] (oktas / 8).

    Returns
    -------
    ratio : numpy.ndarray
        ``GHI / GHI_clear = 1 − 0.75 C^3.4`` [-].
    diffuse_fraction : numpy.ndarray
        ``DHI / GHI = 0.3 + 0.7 C^2`` [-].

    Notes
    -----
    Kasten, F. & Czeplak, G. (1980), "Solar and terrestrial radiation dependent on the
    amount and type of cloud", Solar Energy 24, 177–189, fitted to
    ten years of Hamburg data; C is N/8 with N the cloud amount in oktas.
    """
    c = np.clip(np.asarray(cloud_cover, dtype=float), 0.0, 1.0)
    return 1.0 - 0.75 * c ** 3.4, 0.3 + 0.7 * c ** 2


def cloudy_sky_irradiance(clear: pd.DataFrame, apparent_zenith, cloud_cover) -> pd.DataFrame:
    """Clear-sky irradiance attenuated by clouds (Kasten & Czeplak 1980).

    Parameters
    ----------
    clear : pandas.DataFrame
        Clear-sky ``ghi``, ``dni``, ``dhi`` [W m-2].
    apparent_zenith : array_like
        Refraction-corrected zenith [deg].
    cloud_cover : array_like
        Cloud cover fraction [0-1].

    Returns
    -------
    pandas.DataFrame
        ``ghi``, ``dni``, ``dhi`` [W m-2] with ``ghi = dni cos Z + dhi``.

    Notes
    -----
    The global irradiance is scaled by ``1 − 0.75 C^3.4``. With no cloud the clear-sky
    split is kept; with cloud the diffuse share is the larger of the clear-sky share
    and Kasten & Czeplak's ``0.3 + 0.7 C^2`` (their fit is for all skies, so for thin
    cloud it would otherwise undercut the clear-sky diffuse share), and the direct
    beam takes the rest.
    """
    c = np.clip(np.asarray(cloud_cover, dtype=float), 0.0, 1.0)
    ratio, kd_cloud = cloud_attenuation_kasten_czeplak(c)
    ghi_clear = clear["ghi"].to_numpy()
    ghi = ghi_clear * ratio
    with np.errstate(divide="ignore", invalid="ignore"):
        kd_clear = np.where(ghi_clear > 0, clear["dhi"].to_numpy() / ghi_clear, 1.0)
    kd = np.where(c > 0, np.maximum(kd_clear, kd_cloud), kd_clear)
    dhi = ghi * kd
    cosz = np.cos(np.radians(np.asarray(apparent_zenith, dtype=float)))
    with np.errstate(divide="ignore", invalid="ignore"):
        dni = np.where(cosz > 0.0, (ghi - dhi) / cosz, 0.0)
    return pd.DataFrame({"ghi": ghi, "dni": dni, "dhi": dhi}, index=clear.index)


def decompose_ghi(ghi, times, apparent_zenith, model: str = "erbs", pressure=101325.0,
                  temp_dew=None) -> pd.DataFrame:
    """Split measured global horizontal irradiance into DNI and DHI.

    Parameters
    ----------
    ghi : array_like
        Measured global horizontal irradiance [W m-2].
    times : pandas.DatetimeIndex
        Instants of the measurements (tz-aware).
    apparent_zenith : array_like
        Refraction-corrected solar zenith [deg].
    model : {'erbs', 'dirint'}
        Decomposition: Erbs, Klein & Duffie (1982), Solar Energy 28, 293–302 (diffuse
        fraction from the clearness index, pvlib.irradiance.erbs), or DIRINT, Perez et
        al. (1992), ASHRAE Trans. 98, 354–369 (pvlib.irradiance.dirint).
    pressure : float
        Station pressure [Pa] (DIRINT only).
    temp_dew : array_like, optional
        Dew point [degC] (DIRINT only, improves the precipitable-water term).

    Returns
    -------
    pandas.DataFrame
        ``ghi``, ``dni``, ``dhi`` [W m-2] with ``ghi = dni cos Z + dhi`` (the diffuse
        part is taken as the remainder, so the split closes exactly).
    """
    idx = _as_times(times)
    ghi = np.clip(np.asarray(ghi, dtype=float), 0.0, None)
    zen = np.asarray(apparent_zenith, dtype=float)
    cosz = np.cos(np.radians(zen))
    if model == "erbs":
        out = pvlib.irradiance.erbs(ghi, zen, idx)
        dni = np.asarray(out["dni"], dtype=float)
    elif model == "dirint":
        dni = np.asarray(pvlib.irradiance.dirint(pd.Series(ghi, index=idx),
                                                 pd.Series(zen, index=idx), idx,
                                                 pressure=pressure, temp_dew=temp_dew),
                         dtype=float)
    else:
        raise InputError("decomposition", model,
                         "must be " + " or ".join(repr(d) for d in DECOMPOSITIONS))
    dni = np.nan_to_num(np.clip(dni, 0.0, None))
    # the beam cannot carry more than the measured global: keep closure and positivity
    dni = np.where(cosz > 0, np.minimum(dni, ghi / np.maximum(cosz, 1e-9)), 0.0)
    dhi = ghi - dni * np.clip(cosz, 0.0, None)
    return pd.DataFrame({"ghi": ghi, "dni": dni, "dhi": dhi}, index=idx)


def interval_profile(means, shape, n_sub: int, periodic: bool = False) -> np.ndarray:
    """Knot values of a piecewise-linear irradiance whose mean over every interval is the
    interval's given mean, exactly.

    Parameters
    ----------
    means : (m,) array_like
        Mean irradiance of each interval (a file's hourly value) [W m-2], ≥ 0.
    shape : (m * n_sub + 1,) array_like
        The within-interval shape at the knots, ≥ 0: the extraterrestrial irradiance on a
        horizontal plane ``I0 max(cos Z, 0)`` (a constant clearness index within the
        interval) [W m-2].
    n_sub : int
        Knot steps per interval (6: every 10 min of an hour).
    periodic : bool
        The last knot is the first (a design day repeated).

    Returns
    -------
    numpy.ndarray
        (m * n_sub + 1,) values at the knots [W m-2], ≥ 0, such that the trapezoid integral
        of every interval (the exact integral of the linear interpolation between knots)
        is its mean times its length.

    Notes
    -----
    Each interval's clearness index is ``k = mean / <shape>`` (``<·>`` the trapezoid mean
    over its knots). A knot shared by two intervals takes the smaller of their ``k ×
    shape``; the interval's remainder goes to its inner knots in proportion to the shape,
    which is then never negative. An interval with sunshine in its mean but none at its
    inner knots (the sun rising in its last minutes, twilight) spreads the remainder evenly
    over them. ASSUMPTION: the clearness index is constant within an interval (Liu & Jordan
    1960's hourly clearness index; the within-hour variation of cloud is unknown to an
    hourly file), so the hour's sun follows the sun's own course and no sun falls outside
    the hours that had it.
    """
    mean = np.asarray(means, dtype=float)
    g = np.asarray(shape, dtype=float)
    n = int(n_sub)
    m = len(mean)
    require(n >= 2, "n_sub", n, "must be >= 2 (knots inside each interval)")
    require(g.shape == (m * n + 1,), "shape", g.shape, f"must have m * n_sub + 1 = {m * n + 1} "
            "values (one per knot)")
    require(bool(np.all(mean >= 0)) and bool(np.all(g >= 0)), "means", float(np.min(mean)),
            "must be >= 0 (and the shape too)")
    seg = np.lib.stride_tricks.sliding_window_view(g, n + 1)[::n]      # (m, n + 1)
    w = np.full(n + 1, 1.0 / n)
    w[[0, -1]] = 0.5 / n
    avg = seg @ w
    dark = avg <= 0.0
    k = np.divide(mean, avg, out=np.zeros(m), where=~dark)
    # shared knots: the smaller of the two intervals' k × shape (a dark interval's own
    # shape is uniform: its k × 1 = its mean)
    left_of = np.where(dark, mean, k * seg[:, 0])        # value wished at each interval start
    right_of = np.where(dark, mean, k * seg[:, -1])      # … and end
    knots = np.empty(m * n + 1)
    inner = np.minimum(right_of[:-1], left_of[1:])
    knots[n:m * n:n] = inner
    if periodic:
        knots[0] = knots[-1] = min(right_of[-1], left_of[0])
    else:
        knots[0], knots[-1] = left_of[0], right_of[-1]
    ends = 0.5 / n * (knots[0:m * n:n] + knots[n::n])
    rest = np.maximum(mean - ends, 0.0) * n               # what the inner knots must sum to
    s_in = seg[:, 1:-1]
    tot = s_in.sum(axis=1)
    even = tot <= 0.0
    vals = np.where(even[:, None], (rest / (n - 1))[:, None],
                    s_in * np.divide(rest, tot, out=np.zeros(m), where=~even)[:, None])
    for j in range(1, n):
        knots[j:m * n:n] = vals[:, j - 1]
    return knots


def sunrise_sunset(date, latitude: float, longitude: float, tz: str):
    """Sunrise, solar transit and sunset of a local calendar day (SPA).

    Parameters
    ----------
    date : str or datetime-like
        Local calendar date.
    latitude, longitude : float
        Site [deg].
    tz : str
        Time zone name, e.g. ``'Etc/GMT-8'`` for UTC+8.

    Returns
    -------
    tuple of float
        Sunrise, transit, sunset in local clock hours after midnight [h].
    """
    day = pd.Timestamp(date).normalize()
    day = day.tz_localize(tz) if day.tzinfo is None else day.tz_convert(tz)
    r = pvlib.solarposition.sun_rise_set_transit_spa(pd.DatetimeIndex([day]), latitude,
                                                     longitude)
    hours = []
    for col in ("sunrise", "transit", "sunset"):
        t = r[col].iloc[0]
        require(not pd.isna(t), "latitude", latitude,
                "the sun must rise and set on this date (no polar day/night)")
        hours.append((t.tz_convert(tz) - day).total_seconds() / 3600.0)
    return tuple(hours)
