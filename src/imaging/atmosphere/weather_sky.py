"""The image's thermal sky from the thermal stage's weather: one sky for both stages.

The embedded tables hold LOWTRAN 7's sky for two standard atmospheres. The thermal stage
describes the sky by its broadband effective emissivity ``ε = L_down / (σ T_air⁴)`` from
the scenario's near-surface air temperature, humidity and cloud
(:func:`shipthermal.environment.sky.sky_emissivity`, or a measured ``L_down``). This module
carries that same sky into the imaging bands:

1. Clear sky. Each table season ``s`` (mid-latitude summer, winter) has a surface state
   ``(T_s, RH_s)`` (LOWTRAN's model atmosphere), a band sky emissivity
   ``e_s(θ) = L_s(θ) / B(T_s)`` (band radiance over the band Planck radiance) and a
   broadband clear-sky emissivity ``ε_s`` of the thermal stage's clear-sky model at that
   state. For the scenario's ``ε_clr`` the band emissivity is interpolated linearly in
   ``ε_clr`` between the two seasons (extrapolated beyond), clipped to [0, 1], and the sky
   radiance is ``e(θ) B(T_air)``. At a table season's surface state this returns the table
   exactly; the scheme assumes that the band emissivity of the sky follows the broadband
   one as it does between the two standard atmospheres.
2. Cloud. The thermal stage's cloud models treat cloud as a black body at the screen
   temperature filling a share ``f = (ε_all − ε_clr) / (1 − ε_clr)`` of the sky (0.84 c for
   Unsworth–Monteith, c for Crawford–Duchon): the band sky gets the same,
   ``e_all(θ) = e(θ) + f (1 − e(θ))``.

Checked against live LOWTRAN 7 (own Navy maritime aerosol, 23 km) for the four standard
atmospheres that are not in the tables (tropical, sub-arctic summer and winter, US 1976),
predicting them from their surface states with the Brutsaert clear sky: see
:data:`SCHEME_ERROR`. The interpolation runs in the optical depths ``−ln(1 − e)`` and
``−ln(1 − ε)`` (linear in the emissivities errs up to 15 % instead of 12 %). The tables
themselves (no weather) err by 25–75 % for those atmospheres.

Scattered sunlight in the sky is not part of this (it stays the tables').
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from shipthermal.errors import check_range, require

from ..quadrature import gauss_legendre

__all__ = ["SCHEME_ERROR", "SkyWeather", "standard_states", "band_sky_emissivity",
           "weather_sky_radiance", "weather_sky_irradiance", "broadband_emissivities"]

#: Measured error of the scheme against live LOWTRAN 7 for the standard atmospheres outside
#: the tables (tropical, sub-arctic summer, US 1976), band sky radiance at zenith 0 and 60
#: deg and the hemispherical irradiance, clear sky (Brutsaert): max |predicted / LOWTRAN - 1|
#: per band (tests re-measure it where LOWTRAN builds). Sub-arctic winter, whose sky is
#: warmed by a surface inversion the screen temperature does not see, comes out 13-14 %
#: (3-5 µm) and 31-36 % (8-14 µm) low.
SCHEME_ERROR = {"3-5": 0.09, "8-14": 0.13}

_SEASON_MODELS = {"summer": 2, "winter": 3}


@lru_cache(maxsize=8)
def standard_states(clear_model: str = "brutsaert") -> dict:
    """Surface air temperature [K], relative humidity [%] and the thermal stage's clear-sky
    broadband emissivity [-] of each table season's model atmosphere."""
    from shipthermal.environment.sky import sky_emissivity

    from . import aerosol as aer

    tabs = aer.load_aerosol_tables()
    out = {}
    for season, model in _SEASON_MODELS.items():
        t = float(tabs["model_temp_k"][model - 1, 0])
        rh = aer.surface_relative_humidity(model, tabs)
        out[season] = (t, rh, float(sky_emissivity(t, rh, 0.0, clear_model)))
    return out


def _table_band_emissivity(season: str, band: str, zenith_deg):
    from ..radiometry import band_radiance
    from .core import sky_radiance

    t = standard_states()[season][0]
    return sky_radiance(season, band, zenith_deg) / band_radiance(t, band)


def band_sky_emissivity(band: str, zenith_deg, eps_clear: float, eps_all: float | None = None,
                        clear_model: str = "brutsaert"):
    """Band sky emissivity [-] from zenith ``zenith_deg`` [deg] for a broadband clear-sky
    emissivity ``eps_clear`` [-] and all-sky ``eps_all`` [-] (None: clear)."""
    states = standard_states(clear_model)
    es, ew = states["summer"][2], states["winter"][2]
    def depth(e):
        return -np.log(np.clip(1.0 - np.asarray(e, dtype=float), 1e-12, 1.0))

    w = (depth(eps_clear) - depth(ew)) / (depth(es) - depth(ew))
    d = ((1.0 - w) * depth(_table_band_emissivity("winter", band, zenith_deg))
         + w * depth(_table_band_emissivity("summer", band, zenith_deg)))
    e = 1.0 - np.exp(-np.maximum(d, 0.0))
    if eps_all is None:
        return e
    f = float(np.clip((float(eps_all) - eps_clear) / max(1.0 - eps_clear, 1e-9), 0.0, 1.0))
    return e + f * (1.0 - e)


def broadband_emissivities(temp_air, relative_humidity, cloud_cover=0.0, longwave_down=None,
                           clear_model: str = "brutsaert",
                           cloud_model: str = "unsworth_monteith"):
    """``(ε_clr, ε_all)`` [-] of the thermal stage for these conditions (a measured
    ``longwave_down`` [W m-2] sets ``ε_all``, as in the thermal stage)."""
    from shipthermal.environment.sky import longwave_down as lw_down
    from shipthermal.environment.sky import sky_emissivity
    from shipthermal.units import SIGMA

    eps_clr = float(sky_emissivity(temp_air, relative_humidity, 0.0, clear_model, cloud_model))
    lw = lw_down(temp_air, relative_humidity, cloud_cover, longwave_down, clear_model,
                 cloud_model)
    return eps_clr, float(lw) / (SIGMA * float(temp_air) ** 4)


def weather_sky_radiance(band: str, zenith_deg, temp_air: float, relative_humidity: float,
                         cloud_cover: float = 0.0, longwave_down: float | None = None,
                         clear_model: str = "brutsaert",
                         cloud_model: str = "unsworth_monteith"):
    """Thermal band sky radiance [W m⁻² sr⁻¹] from zenith angle(s) [deg] for the
    near-surface air temperature [K], relative humidity [%], cloud cover [0-1] (and an
    optional measured downwelling long-wave [W m⁻²]) of the thermal stage."""
    from ..radiometry import band_radiance

    check_range("temp_air", temp_air, 200.0, 340.0, "K")
    check_range("relative_humidity", relative_humidity, 0.0, 100.0, "%")
    check_range("cloud_cover", cloud_cover, 0.0, 1.0)
    eps_clr, eps_all = broadband_emissivities(temp_air, relative_humidity, cloud_cover,
                                              longwave_down, clear_model, cloud_model)
    z = np.asarray(zenith_deg, dtype=float)
    return band_sky_emissivity(band, z, eps_clr, eps_all, clear_model) * float(
        band_radiance(float(temp_air), band))


def weather_sky_irradiance(band: str, temp_air: float, relative_humidity: float,
                           cloud_cover: float = 0.0, longwave_down: float | None = None,
                           clear_model: str = "brutsaert",
                           cloud_model: str = "unsworth_monteith", n_nodes: int = 16) -> float:
    """Hemispherical band sky irradiance [W m⁻²] on a horizontal surface,
    ``2π ∫ L(μ) μ dμ`` (Gauss–Legendre, ``n_nodes`` nodes in μ, as the tables)."""
    x, w = gauss_legendre(int(n_nodes))
    mu = 0.5 * (x + 1.0)
    rad = weather_sky_radiance(band, np.degrees(np.arccos(mu)), temp_air, relative_humidity,
                               cloud_cover, longwave_down, clear_model, cloud_model)
    return float(2.0 * np.pi * np.sum(0.5 * w * mu * rad))


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
