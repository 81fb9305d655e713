"""What the imaging stage takes from the run's one :class:`~shipthermal.environment.Environment`.

:meth:`Scenario.environment <shipthermal.app.scenario.Scenario.environment>` builds the
environment once per scenario object (the weather file is read there, the offsets applied
there); the thermal stage runs on it, and the functions below hand the imaging stage the
same hourly weather over the simulated day (local midnight of ``time.date`` + 24 h):

* the sea's Cox–Munk slopes: the day-mean true wind;
* the Navy maritime aerosol: the day-mean wind and relative humidity;
* the image's thermal sky: the hourly air temperature, humidity, cloud (and measured
  long-wave) with the thermal stage's sky models.

Winds are the weather record's, at its reference height of 10 m (a file's anemometer
height is converted on reading, ``weather.wind_height``). Cox & Munk (1954) fitted their
slopes to the wind at 12.5 m: for a neutral log profile over the sea (z0 ≈ 0.2 mm) that is
2 % above the 10 m wind used here.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..units import DAY

__all__ = ["day_weather", "sea_glint_wind_speed", "aerosol_conditions", "sky_weather"]


def day_weather(environment) -> dict:
    """The environment's weather over its first day ``[start, start + 24 h)`` (a weather
    record: over the whole record from ``start``): arrays of ``wind_speed`` [m s-1],
    ``relative_humidity`` [%] and ``temp_air`` [K] (the whole record if no sample falls in
    that span).

    A record's images keep one sea-glint wind and one aerosol for the whole record (their
    means): the renderer's sea optics are set up once per run."""
    w = environment.weather
    t = pd.DatetimeIndex(w.time)
    start = environment.start
    sel = (t >= start) & ((t < start + pd.Timedelta(seconds=DAY)) | (not w.periodic))
    if not sel.any():
        sel = np.ones(len(t), dtype=bool)
    return {"wind_speed": np.asarray(w.wind_speed, dtype=float)[sel],
            "relative_humidity": np.asarray(w.relative_humidity, dtype=float)[sel],
            "temp_air": np.asarray(w.temp_air, dtype=float)[sel]}


def sea_glint_wind_speed(environment) -> float:
    """Day-mean true wind speed [m s-1]: the sea's Cox–Munk slope statistics."""
    return float(np.mean(day_weather(environment)["wind_speed"]))


def aerosol_conditions(environment) -> dict:
    """Conditions of the Navy maritime aerosol (:mod:`imaging.atmosphere.aerosol`): the
    day-mean wind as both the current and the 24-h wind [m s-1], and the day-mean relative
    humidity [%] (one atmosphere per day, as the paper's one MODTRAN setting per season)."""
    d = day_weather(environment)
    wind = float(np.mean(d["wind_speed"]))
    return {"wind_speed": wind, "wind_speed_24h": wind,
            "rel_humidity": float(np.mean(d["relative_humidity"]))}


def sky_weather(environment):
    """The image's thermal sky (:class:`imaging.atmosphere.weather_sky.SkyWeather`): the
    environment's near-surface weather with its sky models (the periodic day, or the whole
    record of a record run)."""
    # deferred: imaging.atmosphere adds 34 ms to every command's start-up (0.45 s where the
    # thermal stage is not loaded, measured)
    from imaging.atmosphere.weather_sky import SkyWeather

    return SkyWeather.from_weather(environment.weather, environment.start,
                                   environment.clear_sky_model, environment.cloud_model,
                                   record=not environment.weather.periodic)
