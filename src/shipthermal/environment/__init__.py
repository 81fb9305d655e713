"""Environment of a ship at sea: sun, weather, sky, sea and convection.

Modules (one physical process each):

* :mod:`.sun`         — SPA sun position, clear-sky / cloudy / measured irradiance;
* :mod:`.weather`     — the :class:`Weather` record, CSV / EPW / TMY3 readers, interpolation;
* :mod:`.climatology` — built-in Dalian summer and winter design days, sourced;
* :mod:`.sky`         — sky emissivity, long-wave down, sky temperature;
* :mod:`.sea`         — SST diurnal cycle, sea emissivity, sea-leaving radiation, albedo;
* :mod:`.sea_skin`    — the sea's skin temperature: COARE 3.6 fluxes, cool skin, warm layer;
* :mod:`.convection`  — forced / natural / mixed convection in air and sea water.

:class:`Environment` wires them: for any array of times it returns the sun vector
(East-North-Up), DNI, DHI, air temperature, long-wave down, the bulk and skin sea
temperatures and the wind relative to the moving ship (:class:`EnvironmentState`). It
does no ray tracing: shadows and view factors belong to the ship/tracing stage.

Example
-------
>>> from shipthermal.environment import Environment, climate_day
>>> env = Environment.from_climate_day(climate_day("summer"), ship_heading=90.0)
>>> state = env.at(np.arange(0, 86400, 1800.0))   # seconds after local midnight
"""

from __future__ import annotations

import dataclasses
from typing import Optional

import numpy as np
import pandas as pd

from shipthermal.errors import InputError, check_range, require
from shipthermal.parameters import (DECOMPOSITIONS, DEFAULT_SEA_SKIN_MODEL, LATITUDE_MAX,
                                    SEA_SKIN_MODEL_NAMES, SHIP_SPEED_MAX)
from shipthermal.units import DAY as DAY_SECONDS
from shipthermal.units import ZERO_CELSIUS

from ..optics import sea_emissivity_rough
from . import climatology, convection, sea, sea_skin, sky, sun, weather
from .climatology import ClimateDay, climate_day, dalian_summer, dalian_winter
from .weather import Weather, read_weather_csv

__all__ = [
    "Environment",
    "to_ship_frame",
    "EnvironmentState",
    "Weather",
    "ClimateDay",
    "climate_day",
    "dalian_summer",
    "dalian_winter",
    "read_weather_csv",
    "sun",
    "weather",
    "climatology",
    "sky",
    "sea",
    "sea_skin",
    "convection",
    "SEA_SKIN_STEP",
    "SOLAR_KNOT",
]

SOLAR_KNOT = 600.0
"""Spacing [s] of the knots on which a weather file's hourly irradiance is spread over its
hour (:meth:`Environment.solar_profile`): the forcing tables' spacing, so the tables hold
the profile exactly (and a lit fraction per 10 min resolves the sun's course)."""

SEA_SKIN_STEP = 600.0
"""Longest step [s] of the grid on which an :class:`Environment` integrates the sea's warm
layer once (then interpolated to any time): against a 1 min step, 10 min keeps the time
error of ΔT_warm on clear tropical days below 0.015 K with the COARE warm layer (1 m s-1,
peak 2.7 K; 0.003 K from 3 m s-1) and 2e-3 K with Zeng & Beljaars
(``tests/environment/test_env_sea_skin.py``), and matches the forcing tables."""


@dataclasses.dataclass(frozen=True)
class EnvironmentState:
    """Environment at a set of times (all arrays of length n, SI units, kelvin).

    Attributes
    ----------
    times : pandas.DatetimeIndex
        The instants (tz-aware; for periodic weather, folded into the design day).
    seconds : numpy.ndarray
        Seconds after the environment start, as requested [s].
    sun_vector : numpy.ndarray
        (n, 3) unit vector toward the sun, x = East, y = North, z = Up [-].
    zenith, azimuth : numpy.ndarray
        Apparent solar zenith and azimuth (clockwise from north) [deg].
    dni, dhi, ghi : numpy.ndarray
        Direct normal, diffuse horizontal, global horizontal irradiance [W m-2]
        (0 at night; ghi = dni cos(zenith) + dhi).
    temp_air : numpy.ndarray
        Air temperature [K].
    relative_humidity : numpy.ndarray
        [%].
    cloud_cover : numpy.ndarray
        [0-1].
    longwave_down : numpy.ndarray
        Downwelling sky long-wave on a horizontal surface [W m-2].
    temp_sky : numpy.ndarray
        Effective sky temperature ``(L_down / σ)^(1/4)`` [K].
    temp_sea : numpy.ndarray
        Bulk sea temperature [K]: the weather's SST, taken at 3 m depth (below most of the
        warm layer; what the wetted hull is in contact with).
    temp_sea_skin : numpy.ndarray
        Skin temperature of the sea [K], ``temp_sea + sea_warm_layer − sea_cool_skin``: what
        radiates (what an infrared sensor sees, what the hull sees and reflects).
    sea_warm_layer, sea_cool_skin : numpy.ndarray
        ΔT_warm ≥ 0 (the warming between the bulk SST's depth and the surface) and ΔT_cool
        [K] (:mod:`.sea_skin`; both 0 with ``sea_skin='none'``).
    sea_emissivity : float or numpy.ndarray
        Hemispherical sea emissivity [-] (per time when it follows the wind).
    sea_longwave_up : numpy.ndarray
        Long-wave leaving the sea (emitted at the skin temperature + reflected sky)
        [W m-2].
    sea_shortwave_up : numpy.ndarray
        Short-wave reflected by the sea (albedo direct + diffuse) [W m-2].
    wind_speed, wind_direction : numpy.ndarray
        True wind at 10 m [m s-1], [deg from N, blowing from] (the forcing brings it to
        each face's height and subtracts the ship's velocity:
        :func:`~shipthermal.environment.convection.relative_wind`).
    ship_speed : float
        [m s-1].
    ship_heading : float
        [deg clockwise from N].
    """

    times: pd.DatetimeIndex
    seconds: np.ndarray
    sun_vector: np.ndarray
    zenith: np.ndarray
    azimuth: np.ndarray
    dni: np.ndarray
    dhi: np.ndarray
    ghi: np.ndarray
    temp_air: np.ndarray
    relative_humidity: np.ndarray
    cloud_cover: np.ndarray
    longwave_down: np.ndarray
    temp_sky: np.ndarray
    temp_sea: np.ndarray
    temp_sea_skin: np.ndarray
    sea_warm_layer: np.ndarray
    sea_cool_skin: np.ndarray
    sea_emissivity: float | np.ndarray
    sea_longwave_up: np.ndarray
    sea_shortwave_up: np.ndarray
    wind_speed: np.ndarray
    wind_direction: np.ndarray
    ship_speed: float
    ship_heading: float

    def to_frame(self) -> pd.DataFrame:
        """Scalar-per-time fields as a DataFrame (sun vector as sun_x/y/z)."""
        cols = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)
                if isinstance(getattr(self, f.name), np.ndarray)
                and getattr(self, f.name).ndim == 1}
        df = pd.DataFrame(cols, index=self.times)
        for i, c in enumerate("xyz"):
            df[f"sun_{c}"] = self.sun_vector[:, i]
        return df


class Environment:
    """Wires sun, weather, sky, sea and ship motion for a location and date.

    Parameters
    ----------
    latitude, longitude : float
        Site [deg], north / east positive.
    weather : Weather
        Hourly (or any regular) record; periodic for a design day.
    ship_heading : float
        Heading, clockwise from north [deg].
    ship_speed : float
        Speed over ground [m s-1] (0 when moored).
    altitude : float
        Site height above sea level [m] (clear-sky air mass only).
    date : str, optional
        Local calendar date the (periodic) weather day represents; default: the
        weather's first date. Not allowed for non-periodic weather (its times are real).
    clear_sky_model : {'brutsaert', 'prata', 'swinbank'}
        Clear-sky emissivity (used unless the weather has measured long-wave).
    cloud_model : {'unsworth_monteith', 'crawford_duchon'}
        Long-wave cloud correction.
    decomposition : {'erbs', 'dirint'}
        GHI split when the weather carries measured GHI.
    linke_turbidity : float, optional
        Override pvlib's Linke turbidity climatology [-].
    sea_emissivity : float or None
        Hemispherical sea emissivity [-]; None (default): the rough-sea model of the imaging
        at each time's wind speed (:func:`shipthermal.optics.sea_emissivity_rough`), so both
        stages see
        the same sea.
    sea_skin : {'fairall_coare', 'zeng_beljaars', 'none'} or bool
        Model of the sea's skin temperature (:mod:`.sea_skin`): the weather's bulk SST plus
        a diurnal warm layer minus the cool skin of Fairall et al. (1996b), with COARE 3.6
        fluxes. ``'fairall_coare'`` (default, also ``True``): the COARE warm layer of
        Fairall et al. (1996b), reset at local solar midnight; ``'zeng_beljaars'``: the
        warm layer of Zeng & Beljaars (2005), the ECMWF model's skin scheme, which warms
        far more at ordinary winds (clear tropical day, peaks Z&B / COARE: 4.1 / 2.7 K at 1
        m/s, 2.4 / 0.6 K at 3 m/s, 1.0 / 0.1 K at 5 m/s; observed: < 1.5 K at 3–5 m/s):
        for consistency with ECMWF skin temperatures or as an upper bound. ``'none'``
        (also ``False``) takes the bulk SST as the skin.

    Notes
    -----
    Times given to :meth:`at` as floats are seconds after :attr:`start` (local
    midnight of ``date`` for periodic weather, else the first weather instant); for
    periodic weather they are folded into the design day, so the sun and the weather
    repeat exactly each day of a spin-up.

    The skin temperature is integrated once per environment, on a grid of at most
    :data:`SEA_SKIN_STEP` over the weather's span (a periodic day spun up until it
    repeats; a record from its first instant with no warm layer), and interpolated to the
    times :meth:`at` is asked for.
    """

    def __init__(self, latitude: float, longitude: float, weather: Weather,
                 ship_heading: float = 0.0, ship_speed: float = 0.0, altitude: float = 0.0,
                 date: Optional[str] = None, clear_sky_model: str = "brutsaert",
                 cloud_model: str = "unsworth_monteith", decomposition: str = "erbs",
                 linke_turbidity: Optional[float] = None,
                 sea_emissivity: Optional[float] = None,
                 sea_skin: str | bool = DEFAULT_SEA_SKIN_MODEL):
        check_range("environment.latitude", latitude, -LATITUDE_MAX, LATITUDE_MAX, "deg")
        check_range("environment.longitude", longitude, -180.0, 360.0, "deg")
        check_range("environment.ship_heading", ship_heading, -360.0, 720.0, "deg")
        check_range("environment.ship_speed", ship_speed, 0.0, SHIP_SPEED_MAX, "m/s")
        if sea_emissivity is not None:
            check_range("environment.sea_emissivity", sea_emissivity, 0.5, 1.0)
        require(isinstance(weather, Weather), "environment.weather", type(weather).__name__,
                "must be a shipthermal.environment.Weather")
        require(clear_sky_model in sky.CLEAR_SKY_MODELS, "environment.clear_sky_model",
                clear_sky_model, f"must be one of {sorted(sky.CLEAR_SKY_MODELS)}")
        require(cloud_model in sky.CLOUD_MODELS, "environment.cloud_model", cloud_model,
                f"must be one of {sorted(sky.CLOUD_MODELS)}")
        require(decomposition in DECOMPOSITIONS, "environment.decomposition", decomposition,
                "must be " + " or ".join(repr(d) for d in DECOMPOSITIONS))
        self.latitude = float(latitude)
        self.longitude = float(longitude)
        self.altitude = float(altitude)
        self.weather = weather
        self.ship_heading = float(ship_heading) % 360.0
        self.ship_speed = float(ship_speed)
        self.clear_sky_model = clear_sky_model
        self.cloud_model = cloud_model
        self.decomposition = decomposition
        self.sea_emissivity = None if sea_emissivity is None else float(sea_emissivity)
        self.sea_skin = sea_skin_model(sea_skin)
        self._skin_table = None
        self._solar = None
        tz = weather.tz
        if date is not None:
            require(weather.periodic, "environment.date", date,
                    "can only be set for periodic (design-day) weather",
                    "Real weather records carry their own dates")
            start = pd.Timestamp(date).normalize()
            start = start.tz_localize(tz) if start.tzinfo is None else start.tz_convert(tz)
            wstart = weather.start
            require(wstart == wstart.normalize(), "environment.weather.start", str(wstart),
                    "a periodic weather record must start at local midnight")
        else:
            start = weather.start
        self.start = start
        if linke_turbidity is None:
            # daily climatology for the year, looked up once (the HDF5 read is slow)
            year = pd.date_range(f"{start.year}-01-01 12:00", periods=366, freq="D", tz=tz)
            self._linke = np.asarray(pvlib_linke(year, self.latitude, self.longitude))
        else:
            check_range("environment.linke_turbidity", linke_turbidity, 1.0, 10.0)
            self._linke = np.full(366, float(linke_turbidity))

    @classmethod
    def from_climate_day(cls, day: ClimateDay, ship_heading: float = 0.0,
                         ship_speed: float = 0.0, step_minutes: int = 60, **kwargs):
        """Environment of a built-in climatological design day (periodic).

        With a skin model the day's SST is its daily mean (the warm layer's base) and the
        warm layer makes the diurnal cycle; without, the design day's prescribed cycle
        (:meth:`ClimateDay.weather`)."""
        skin = sea_skin_model(kwargs.get("sea_skin", DEFAULT_SEA_SKIN_MODEL))
        return cls(day.latitude, day.longitude,
                   day.weather(step_minutes, sst_cycle=skin == "none"),
                   ship_heading=ship_heading, ship_speed=ship_speed, altitude=day.altitude,
                   **kwargs)

    def first_day(self) -> "Environment":
        """The same site, ship and sky models with the first 24 h of this environment's
        weather record repeated (periodic): the spin-up day of a record run."""
        return self.record_day(0)

    def record_day(self, k: int) -> "Environment":
        """The same site, ship and sky models with day ``k`` (from 0) of this environment's
        weather record repeated (periodic): the spin-up day of a record run, or of a
        segment of one starting on that day."""
        import copy

        w = self.weather
        require(not w.periodic, "environment.weather.periodic", w.periodic,
                "record_day() takes a weather record (non-periodic weather)")
        n = int(round(DAY_SECONDS / w.step))
        k = int(k)
        require(abs(n * w.step - DAY_SECONDS) < 1e-6 and len(w.time) >= (k + 1) * n,
                "environment.weather", f"{len(w.time)} steps of {w.step:g} s",
                f"must hold at least {k + 1} whole day(s) on a step dividing 24 h")
        require(w.start == w.start.normalize(), "environment.weather.start", str(w.start),
                "must be local midnight for a spin-up day")
        fields = ("temp_air", "relative_humidity", "wind_speed", "wind_direction",
                  "cloud_cover", "temp_sea", "ghi", "longwave_down")
        rows = slice(k * n, (k + 1) * n)
        label = "first day" if k == 0 else f"day {k + 1}"
        day = Weather(time=w.time[rows], periodic=True, source=f"{w.source} ({label})",
                      solar_interval=w.solar_interval,
                      **{f: None if getattr(w, f) is None else getattr(w, f)[rows]
                         for f in fields})
        env = copy.copy(self)
        env.weather = day
        env.start = w.time[k * n]
        env._skin_table = None      # the periodic day's own warm layer
        env._solar = None
        return env

    def _seconds(self, times) -> np.ndarray:
        arr = times if isinstance(times, (pd.DatetimeIndex, pd.Timestamp)) else np.asarray(times)
        if isinstance(arr, (pd.DatetimeIndex, pd.Timestamp)) or arr.dtype.kind in "MO":
            idx = pd.DatetimeIndex(np.atleast_1d(times))
            require(idx.tz is not None, "times", idx[:3].astype(str).tolist(),
                    "must be time-zone aware (or floats in seconds after Environment.start)")
            return np.asarray((idx - self.start).total_seconds(), dtype=float)
        s = np.atleast_1d(np.asarray(times, dtype=float))
        if not np.all(np.isfinite(s)):
            raise InputError("times", s, "must be finite seconds after Environment.start")
        return s

    def at(self, times) -> EnvironmentState:
        """The environment at ``times`` (vectorised; call once with all solver times).

        Parameters
        ----------
        times : array_like of float or pandas.DatetimeIndex
            Seconds after :attr:`start`, or tz-aware instants.

        Returns
        -------
        EnvironmentState
        """
        s = self._seconds(times)
        ws, instants, zen, azi, dni, dhi, ghi, lw = self._sample(s)
        eps_sea = (sea_emissivity_rough(ws.wind_speed) if self.sea_emissivity is None
                   else self.sea_emissivity)
        warm, cool = self.sea_skin_deltas(s)
        skin = ws.temp_sea + warm - cool
        return EnvironmentState(
            times=instants, seconds=s, sun_vector=sun.sun_vector(zen, azi), zenith=zen,
            azimuth=azi, dni=dni, dhi=dhi, ghi=ghi, temp_air=ws.temp_air,
            relative_humidity=ws.relative_humidity, cloud_cover=ws.cloud_cover,
            longwave_down=lw, temp_sky=sky.sky_temperature(lw), temp_sea=ws.temp_sea,
            temp_sea_skin=skin, sea_warm_layer=warm, sea_cool_skin=cool,
            sea_emissivity=eps_sea,
            sea_longwave_up=sea.sea_longwave_up(skin, lw, eps_sea),
            sea_shortwave_up=sea.sea_reflected_shortwave(dni, dhi, zen),
            wind_speed=ws.wind_speed, wind_direction=ws.wind_direction,
            ship_speed=self.ship_speed, ship_heading=self.ship_heading)

    def _sample(self, s):
        """Weather, sun and sky at ``s`` [s after :attr:`start`]: ``(WeatherSample,
        instants, zenith, azimuth, dni, dhi, ghi, longwave_down)``."""
        w = self.weather
        if w.periodic:
            folded = w.fold(s)
            ws = w.at(folded)
            instants = self.start + pd.to_timedelta(folded, unit="s")
        else:
            ws = w.at(s + (self.start - w.start).total_seconds())
            instants = self.start + pd.to_timedelta(s, unit="s")
        instants = pd.DatetimeIndex(instants)
        pos = sun.solar_position(instants, self.latitude, self.longitude, self.altitude,
                                 temperature=ws.temp_air - ZERO_CELSIUS)
        zen = pos["apparent_zenith"].to_numpy()
        azi = pos["azimuth"].to_numpy()
        ghi_in = ws.ghi
        if ghi_in is not None and w.solar_interval != "instant":
            knots, values = self.solar_profile()
            t = w.fold(s)
            ghi_in = np.interp(t, knots, values)
            ws = dataclasses.replace(ws, ghi=ghi_in)
        if ghi_in is not None:
            irr = sun.decompose_ghi(ghi_in, instants, zen, self.decomposition,
                                    temp_dew=sky.dew_point(ws.temp_air, np.maximum(
                                        ws.relative_humidity, 0.1)) - ZERO_CELSIUS)
        else:
            lt = self._linke[np.clip(instants.day_of_year.to_numpy() - 1, 0, 365)]
            clear = sun.clearsky_irradiance(instants, self.latitude, self.longitude,
                                            self.altitude, zen, lt)
            irr = sun.cloudy_sky_irradiance(clear, zen, ws.cloud_cover)
        up = zen < 90.0
        dni = np.where(up, irr["dni"].to_numpy(), 0.0)
        # a measured global with the sun just below the horizon (twilight, or an hour's
        # energy spread where it has no sun at its knots) is diffuse: kept, not dropped
        dhi = np.where(up, irr["dhi"].to_numpy(),
                       np.clip(ghi_in, 0.0, None) if ghi_in is not None else 0.0)
        ghi = dni * np.clip(np.cos(np.radians(zen)), 0.0, None) + dhi
        lw = sky.longwave_down(ws.temp_air, ws.relative_humidity, ws.cloud_cover,
                               measured=ws.longwave_down, clear_model=self.clear_sky_model,
                               cloud_model=self.cloud_model)
        return ws, instants, zen, azi, dni, dhi, ghi, lw

    def solar_profile(self):
        """The weather's irradiance within its steps, when it gives step means
        (``weather.solar_interval`` 'ending' or 'centred'): ``(knots, values)``, seconds
        after :attr:`start` and the global horizontal irradiance there [W m-2], linear in
        between (computed once, then cached).

        Each step's energy is spread over the step by the sun's course (a constant
        clearness index within the step: :func:`.sun.interval_profile`) on knots every
        :data:`SOLAR_KNOT` s, so that the integral of every step, hence of every day, is
        the file's exactly. The forcing's table times (every 600 s from midnight) fall on
        the knots: its interpolation is this very profile.
        """
        if self._solar is None:
            w = self.weather
            n_sub = max(2, int(round(w.step / SOLAR_KNOT)))
            offset = {"ending": -w.step, "centred": -0.5 * w.step}[w.solar_interval]
            t0 = (w.time[0] - self.start).total_seconds() + offset
            knots = t0 + np.arange(len(w.time) * n_sub + 1) * (w.step / n_sub)
            instants = pd.DatetimeIndex(self.start + pd.to_timedelta(knots, unit="s"))
            zen = sun.solar_position(instants, self.latitude, self.longitude,
                                     self.altitude)["apparent_zenith"].to_numpy()
            import pvlib

            extra = np.asarray(pvlib.irradiance.get_extra_radiation(instants), dtype=float)
            shape = extra * np.clip(np.cos(np.radians(zen)), 0.0, None)
            values = sun.interval_profile(w.ghi, shape, n_sub, periodic=w.periodic)
            if w.periodic:
                # one period from 0: roll the knots that lie before 0 to its end
                k = w.fold(knots[:-1])
                order = np.argsort(k)
                knots = np.append(k[order], w.period)
                values = np.append(values[:-1][order], values[:-1][order][0])
            self._solar = (knots, values)
        return self._solar

    def sea_skin_series(self) -> Optional[sea_skin.SeaSkin]:
        """The sea's skin temperature on the environment's own grid (computed once, then
        cached): :class:`~.sea_skin.SeaSkin` with ``seconds`` after :attr:`start` — one
        period of a periodic weather (spun up), or the whole record. None with
        ``sea_skin='none'``.

        The forcing comes from the same place as :meth:`at`'s: the weather's bulk SST
        (taken at the warm layer's base), 10 m wind, air temperature and humidity (at
        screen height, ASSUMPTION 2 m), the global horizontal irradiance with the sea's
        albedo of :func:`.sea.sea_reflected_shortwave` (direct and diffuse), the long-wave
        down of the sky model (or measured), standard pressure
        (:data:`.sea_skin.STANDARD_PRESSURE`: the weather carries none); for the COARE warm
        layer's midnight reset, the local mean solar time (UTC + longitude / 15 h).
        """
        if self.sea_skin == "none":
            return None
        if self._skin_table is None:
            w = self.weather
            period = w.period
            if w.periodic:
                n = max(int(np.ceil(period / SEA_SKIN_STEP - 1e-9)), 2)
                grid = np.arange(n) * (period / n)
            else:
                span = (w.time[-1] - self.start).total_seconds()
                n = max(int(np.ceil(span / SEA_SKIN_STEP - 1e-9)), 1) + 1
                grid = np.linspace(0.0, span, n)
            ws, instants, zen, _, dni, dhi, ghi, lw = self._sample(grid)
            up = sea.sea_reflected_shortwave(dni, dhi, zen)
            albedo = np.divide(up, ghi, out=np.full_like(ghi, sea.SEA_ALBEDO_DIFFUSE),
                               where=ghi > 0.0)
            utc = instants.tz_convert("UTC")
            solar = np.mod((utc - utc.normalize()).total_seconds().to_numpy() / 3600.0
                           + self.longitude / 15.0, 24.0)
            self._skin_table = sea_skin.sea_skin_temperature(
                grid, ws.temp_sea, ws.wind_speed, ws.temp_air, ws.relative_humidity, ghi,
                lw, np.clip(albedo, 0.0, 1.0), period=period, latitude=self.latitude,
                warm_layer=self.sea_skin, solar_hours=solar)
        return self._skin_table

    def sea_skin_deltas(self, seconds):
        """ΔT_warm and ΔT_cool [K] at ``seconds`` after :attr:`start` (interpolated
        linearly from :meth:`sea_skin_series`; periodic weather folded into its period;
        zeros with ``sea_skin='none'``)."""
        s = np.atleast_1d(np.asarray(seconds, dtype=float))
        table = self.sea_skin_series()
        if table is None:
            return np.zeros_like(s), np.zeros_like(s)
        g, warm, cool = table.seconds, table.delta_warm, table.delta_cool
        if table.periodic:
            period = self.weather.period
            s = self.weather.fold(s)
            g = np.append(g, g[0] + period)
            warm, cool = np.append(warm, warm[0]), np.append(cool, cool[0])
        return np.interp(s, g, warm), np.interp(s, g, cool)


def sea_skin_model(value) -> str:
    """The sea skin model's name from a name or a switch (True: the default model)."""
    if value is True:
        return DEFAULT_SEA_SKIN_MODEL
    if value is False or value is None:
        return "none"
    require(value in SEA_SKIN_MODEL_NAMES, "environment.sea_skin", value,
            "must be " + " or ".join(repr(m) for m in SEA_SKIN_MODEL_NAMES) + " (or a bool)")
    return str(value)


def to_ship_frame(vectors_enu, ship_heading):
    """Rotate East-North-Up vectors into the ship frame (x bow, y port, z up).

    Parameters
    ----------
    vectors_enu : array_like
        Shape (..., 3) vectors in East-North-Up [-].
    ship_heading : float
        Heading, clockwise from north [deg].

    Returns
    -------
    numpy.ndarray
        Shape (..., 3): components along the bow, the port side and up. The frame is
        right-handed (bow × port = up). A mesh with another convention (e.g. y to
        starboard) flips the sign of y.
    """
    v = np.asarray(vectors_enu, dtype=float)
    psi = np.radians(ship_heading)
    bow = np.array([np.sin(psi), np.cos(psi), 0.0])
    port = np.array([-np.cos(psi), np.sin(psi), 0.0])
    return np.stack([v @ bow, v @ port, v[..., 2]], axis=-1)


def pvlib_linke(times, latitude, longitude):
    """pvlib's Linke turbidity climatology (Remund et al. 2003) at ``times`` [-]."""
    import pvlib

    return pvlib.clearsky.lookup_linke_turbidity(times, latitude, longitude)
