"""The image's sky from the thermal stage's weather: one day, hour by hour.

The thermal stage describes each hour by its screen-level air temperature, humidity and
cloud cover (and, from an EPW file, a measured downwelling long-wave). The image's
atmosphere takes the same hour as LOWTRAN's own inputs (:mod:`.core`):

* the model atmosphere scaled to the hour's air temperature and humidity
  (:class:`.models.AtmosphereState`, LOWTRAN's user profile);
* the cloud cover ``c`` as the share of the sky under one of LOWTRAN's cloud decks
  (``cloud_type``): ``L = (1 − c) L_clear + c L_deck``. A measured long-wave sets the share
  through the thermal stage's own cloud model: ``ε_all = ε_clr + k c (1 − ε_clr)`` with
  ``k = 0.84`` (Unsworth–Monteith) or 1 (Crawford–Duchon), solved for ``c`` (clipped to
  0-1), so that both stages see the same cloud.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from shipthermal.errors import check_range, require
from shipthermal.units import SIGMA

from ..parameters import DEFAULT_CLOUD_TYPE
from . import models as mdl
from . import tables as tb
from .core import sky_radiance

__all__ = ["SkyWeather", "cloud_share", "weather_state", "weather_sky_radiance",
           "weather_sky_irradiance"]

_CLOUD_K = {"unsworth_monteith": 0.84, "crawford_duchon": 1.0}


def cloud_share(temp_air, relative_humidity, cloud_cover=0.0, longwave_down=None,
                clear_model: str = "brutsaert", cloud_model: str = "unsworth_monteith"
                ) -> float:
    """Share of the sky under cloud [0-1]: the weather's cloud cover, or the one a measured
    downwelling long-wave [W m⁻²] implies through the thermal stage's sky models."""
    if longwave_down is None:
        return float(np.clip(cloud_cover, 0.0, 1.0))
    # deferred: shipthermal.environment loads pvlib and pandas (0.5 s over the atmosphere's
    # imports, measured); only a measured long-wave needs the sky models
    from shipthermal.environment.sky import sky_emissivity

    eps_clr = float(sky_emissivity(temp_air, relative_humidity, 0.0, clear_model, cloud_model))
    eps_all = float(longwave_down) / (SIGMA * float(temp_air) ** 4)
    k = _CLOUD_K.get(cloud_model, 1.0)
    return float(np.clip((eps_all - eps_clr) / (k * max(1.0 - eps_clr, 1e-9)), 0.0, 1.0))


def weather_state(temp_air: float, relative_humidity: float, wind_speed=None
                  ) -> mdl.AtmosphereState:
    """The :class:`.models.AtmosphereState` of an hour: air temperature [K], relative
    humidity [%] (clipped to 1-100), wind [m s⁻¹] (None: LOWTRAN's default)."""
    check_range("temp_air", temp_air, 200.0, 340.0, "K")
    check_range("relative_humidity", relative_humidity, 0.0, 100.0, "%")
    return mdl.AtmosphereState(temp_air_K=float(temp_air),
                               rel_humidity=float(np.clip(relative_humidity, 1.0, 100.0)),
                               wind_speed=wind_speed)


def weather_sky_radiance(band, zenith_deg, temp_air: float, relative_humidity: float,
                         cloud_cover: float = 0.0, longwave_down: float | None = None,
                         clear_model: str = "brutsaert",
                         cloud_model: str = "unsworth_monteith", model="summer",
                         wind_speed=None, cloud_type: str = DEFAULT_CLOUD_TYPE):
    """Band sky radiance [W m⁻² sr⁻¹] from zenith angle(s) [deg] for an hour's weather:
    air temperature [K], relative humidity [%], cloud cover [0-1] or measured long-wave
    [W m⁻²], in the model atmosphere ``model`` with the Navy maritime wind ``wind_speed``
    [m s⁻¹] and LOWTRAN cloud deck ``cloud_type``."""
    c = cloud_share(temp_air, relative_humidity, cloud_cover, longwave_down, clear_model,
                    cloud_model)
    return sky_radiance(model, band, zenith_deg, state=weather_state(
        temp_air, relative_humidity, wind_speed), cloud_cover=c, cloud_type=cloud_type)


def weather_sky_irradiance(band, temp_air: float, relative_humidity: float,
                           cloud_cover: float = 0.0, longwave_down: float | None = None,
                           clear_model: str = "brutsaert",
                           cloud_model: str = "unsworth_monteith", model="summer",
                           wind_speed=None, cloud_type: str = DEFAULT_CLOUD_TYPE,
                           n_nodes: int = 16) -> float:
    """Hemispherical band sky irradiance [W m⁻²] on a horizontal surface for an hour's
    weather (arguments as :func:`weather_sky_radiance`), ``2π ∫ L(μ) μ dμ``
    (Gauss–Legendre, ``n_nodes`` nodes in μ)."""
    g = tb.load_table().grid("sky")
    nodes = weather_sky_radiance(band, g, temp_air, relative_humidity, cloud_cover,
                                 longwave_down, clear_model, cloud_model, model, wind_speed,
                                 cloud_type)
    return float(tb.hemispherical(g, nodes, n_nodes))


@dataclass(frozen=True, eq=False)
class SkyWeather:
    """The thermal stage's near-surface weather over one day, for the image's sky.

    Attributes
    ----------
    hours_local : (n,) float
        Local clock hours [h], increasing within one day (24-h periodic, linear between).
    temp_air : (n,) float
        Screen-level air temperature [K].
    relative_humidity : (n,) float
        [%].
    cloud_cover : (n,) float
        [0-1].
    longwave_down : (n,) float or None
        Measured downwelling long-wave [W m-2] (NaN where missing), as the thermal stage
        uses it.
    clear_model, cloud_model : str
        The thermal stage's sky models.
    periodic : bool
        True (default): one day, repeated; False: a weather record, ``hours_local`` counted
        from local midnight of its first day and running on past 24 h.
    """

    hours_local: np.ndarray
    temp_air: np.ndarray
    relative_humidity: np.ndarray
    cloud_cover: np.ndarray
    longwave_down: np.ndarray | None = None
    clear_model: str = "brutsaert"
    cloud_model: str = "unsworth_monteith"
    periodic: bool = True

    def __post_init__(self):
        h = np.asarray(self.hours_local, dtype=float).reshape(-1)
        require(h.size >= 1 and bool(np.all(np.diff(h) > 0))
                and (h[-1] - h[0] < 24.0 or not self.periodic),
                "sky_weather.hours_local", h, "must increase within one day [h]")
        for name in ("temp_air", "relative_humidity", "cloud_cover", "longwave_down"):
            v = getattr(self, name)
            if v is None:
                continue
            v = np.asarray(v, dtype=float).reshape(-1)
            require(v.shape == h.shape, f"sky_weather.{name}", v.shape,
                    f"must have one value per hour ({h.size})")
            object.__setattr__(self, name, v)
        object.__setattr__(self, "hours_local", h)

    @classmethod
    def from_weather(cls, weather, start=None, clear_model: str = "brutsaert",
                     cloud_model: str = "unsworth_monteith", record: bool = False
                     ) -> "SkyWeather":
        """From a :class:`shipthermal.environment.Weather`: the day starting at ``start``
        (a tz-aware timestamp; default the record's first instant), or with ``record`` the
        whole record from ``start`` on (not periodic)."""
        import pandas as pd

        t = pd.DatetimeIndex(weather.time)
        t0 = t[0] if start is None else pd.Timestamp(start)
        if record:
            sel = t >= t0
            hours = np.asarray((t[sel] - t0.normalize()).total_seconds(), dtype=float) / 3600.0
            lw = getattr(weather, "longwave_down", None)

            def cut(v):
                return np.asarray(v, dtype=float)[sel]

            return cls(hours, cut(weather.temp_air), cut(weather.relative_humidity),
                       cut(weather.cloud_cover), None if lw is None else cut(lw),
                       clear_model, cloud_model, periodic=False)
        sel = (t >= t0) & (t < t0 + pd.Timedelta(days=1))
        if not sel.any():
            sel = np.ones(len(t), dtype=bool)
        tt = t[sel]
        hours = (np.asarray((tt - tt[0].normalize()).total_seconds(), dtype=float)
                 / 3600.0) % 24.0
        order = np.argsort(hours, kind="stable")

        def pick(v):
            return np.asarray(v, dtype=float)[sel][order]

        lw = getattr(weather, "longwave_down", None)
        return cls(hours[order], pick(weather.temp_air), pick(weather.relative_humidity),
                   pick(weather.cloud_cover), None if lw is None else pick(lw),
                   clear_model, cloud_model)

    def at(self, time_s: float) -> dict:
        """Keyword arguments of :func:`weather_sky_radiance` at ``time_s`` [s after local
        midnight of the first day] (linear; 24-h periodic unless a record)."""
        h = self.hours_local
        x = float(time_s) / 3600.0

        def value(v):
            if h.size == 1:
                return float(v[0])
            if not self.periodic:
                return float(np.interp(x, h, v))
            return float(np.interp(x, h, v, period=24.0))

        lw = None
        if self.longwave_down is not None:
            lw = value(self.longwave_down)
            lw = lw if np.isfinite(lw) else None
        return dict(temp_air=value(self.temp_air), relative_humidity=value(
            self.relative_humidity), cloud_cover=value(self.cloud_cover), longwave_down=lw,
            clear_model=self.clear_model, cloud_model=self.cloud_model)
