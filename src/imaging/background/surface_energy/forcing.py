"""Forcing of the columns on a uniform time grid, and the forcing of tilted pixels from the
environment the ship sees (short-wave transposition, sky view, incoming long-wave)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pvlib

from shipthermal.errors import InputError, check_range, require
from shipthermal.units import DAY, SIGMA



@dataclass(frozen=True)
class SurfaceForcing:
    """Forcing of N columns on a uniform time grid (n_t instants, ``time_step`` apart).

    Attributes
    ----------
    time_step : float
        Spacing of the grid [s]; a day must be a whole number of steps.
    shortwave_absorbed : numpy.ndarray
        (n_t, N) absorbed short-wave [W m-2] ((1 − albedo) × incident).
    longwave_down : numpy.ndarray
        (n_t, N) incoming long-wave [W m-2] (sky and surroundings weighted by the sky view:
        :func:`longwave_incoming`); the surface absorbs ε of it.
    temp_air : numpy.ndarray
        (n_t,) or (n_t, N) air temperature [K].
    relative_humidity : numpy.ndarray
        (n_t,) or (n_t, N) [%].
    wind_speed : numpy.ndarray
        (n_t,) or (n_t, N) wind speed at the height the convection model expects [m s-1].
    pressure : float or numpy.ndarray
        Air pressure [Pa], scalar, (n_t,) or (n_t, N).
    """

    time_step: float
    shortwave_absorbed: np.ndarray
    longwave_down: np.ndarray
    temp_air: np.ndarray
    relative_humidity: np.ndarray
    wind_speed: np.ndarray
    pressure: float | np.ndarray = 101325.0

    @property
    def n_times(self) -> int:
        return self.shortwave_absorbed.shape[0]

    @property
    def n_columns(self) -> int:
        return self.shortwave_absorbed.shape[1]

    def field(self, name: str) -> np.ndarray:
        """A field broadcast to (n_t, N) (a view, not a copy)."""
        return np.broadcast_to(_column_shape(getattr(self, name), self.n_times),
                               (self.n_times, self.n_columns))

    def validate(self) -> None:
        """Shapes and physical ranges, naming the field."""
        check_range("forcing.time_step", self.time_step, 1.0, DAY, "s")
        require(self.shortwave_absorbed.ndim == 2, "forcing.shortwave_absorbed",
                self.shortwave_absorbed.shape, "must be (n_t, N)")
        nt, n = self.shortwave_absorbed.shape
        for name, lo, hi, unit in (("shortwave_absorbed", 0.0, 1500.0, "W m-2"),
                                   ("longwave_down", 0.0, 700.0, "W m-2"),
                                   ("temp_air", 180.0, 340.0, "K"),
                                   ("relative_humidity", 0.0, 100.0, "%"),
                                   ("wind_speed", 0.0, 75.0, "m s-1"),
                                   ("pressure", 3.0e4, 1.2e5, "Pa")):
            value = _floats(getattr(self, name))
            try:
                np.broadcast_to(_column_shape(value, nt), (nt, n))
            except ValueError:
                raise InputError(f"forcing.{name}", value.shape,
                                 f"must broadcast to (n_t, N) = ({nt}, {n})") from None
            # extremes first (no float64 copy of a long record's float32 arrays); the full
            # check names the first bad entry
            low, high = (np.min(value), np.max(value)) if value.size else (lo, hi)
            if not (np.isfinite(low) and np.isfinite(high) and lo <= low and high <= hi):
                check_range(f"forcing.{name}", value, lo, hi, unit)


def _floats(value) -> np.ndarray:
    """``value`` as a float array: float32 kept as it is (a long record's forcing), anything
    else as float64."""
    a = np.asarray(value)
    return a if a.dtype == np.float32 else np.asarray(a, dtype=float)


def _column_shape(value, n_times: int) -> np.ndarray:
    """(n_t,) → (n_t, 1) so a per-time series broadcasts over columns."""
    a = _floats(value)
    return a[:, None] if a.ndim == 1 and a.shape[0] == n_times else a


# ---------------------------------------------------------------------------------------------
# Forcing of tilted pixels
# ---------------------------------------------------------------------------------------------
def sky_view_factor(surface_tilt):
    """Sky-view factor of an unobstructed tilted plane, isotropic sky: (1 + cos s)/2 [-].

    Parameters
    ----------
    surface_tilt : array_like
        Slope s [deg] (0 horizontal).
    """
    return 0.5 * (1.0 + np.cos(np.radians(np.asarray(surface_tilt, dtype=float))))


def shortwave_on_tilted(surface_tilt, surface_azimuth, solar_zenith, solar_azimuth, dni, ghi,
                        dhi, albedo_ground=0.2, model: str = "isotropic", dni_extra=None,
                        airmass=None) -> dict:
    """Short-wave incident on tilted pixels (pvlib transposition).

    Parameters
    ----------
    surface_tilt : array_like
        (N,) terrain slope [deg].
    surface_azimuth : array_like
        (N,) aspect: compass azimuth of the downslope direction, the direction the surface
        faces [deg clockwise from north].
    solar_zenith, solar_azimuth : array_like
        (n_t,) apparent sun position [deg] (azimuth clockwise from north).
    dni, ghi, dhi : array_like
        (n_t,) irradiance [W m-2].
    albedo_ground : float or array_like
        Albedo of the surroundings seen below the horizon [-].
    model : {'isotropic', 'haydavies', 'perez', ...}
        pvlib's sky-diffuse model (``haydavies`` and ``perez`` need ``dni_extra``;
        ``perez`` also ``airmass``).
    dni_extra, airmass : array_like, optional
        (n_t,) extraterrestrial DNI [W m-2] and relative air mass [-].

    Returns
    -------
    dict
        ``poa_global``, ``poa_direct``, ``poa_sky_diffuse``, ``poa_ground_diffuse``:
        (n_t, N) [W m-2].

    Notes
    -----
    :func:`pvlib.irradiance.get_total_irradiance` with pvlib's conventions (surface_azimuth
    is the azimuth the surface normal points to); direct = DNI · max(cos θ_i, 0).
    """
    col = lambda x: None if x is None else np.asarray(x, dtype=float)[:, None]  # noqa: E731
    row = lambda x: np.asarray(x, dtype=float).reshape(1, -1)  # noqa: E731
    tilt = row(surface_tilt)
    azim = row(surface_azimuth)
    out = pvlib.irradiance.get_total_irradiance(
        tilt, azim, col(solar_zenith), col(solar_azimuth), col(dni), col(ghi), col(dhi),
        dni_extra=col(dni_extra), airmass=col(airmass), albedo=albedo_ground, model=model)
    shape = np.broadcast_shapes(tilt.shape, np.shape(col(dni)))
    return {k: np.nan_to_num(np.broadcast_to(np.asarray(out[k], dtype=float), shape))
            for k in ("poa_global", "poa_direct", "poa_sky_diffuse", "poa_ground_diffuse")}


def longwave_incoming(longwave_sky, sky_view, temp_surroundings, emissivity_surroundings=0.95):
    """Long-wave reaching a pixel: sky through its sky view, surroundings through the rest.

    Parameters
    ----------
    longwave_sky : array_like
        (n_t, 1) or (n_t, N) long-wave down on a horizontal plane [W m-2].
    sky_view : array_like
        (N,) sky-view factor [-].
    temp_surroundings : array_like
        Temperature of the terrain and buildings seen instead of the sky [K].
    emissivity_surroundings : float
        Their emissivity [-] (their reflection of the sky is neglected).

    Returns
    -------
    numpy.ndarray
        ``V L_sky + (1 − V) ε σ T⁴`` [W m-2].
    """
    v = np.asarray(sky_view, dtype=float)
    ts = np.asarray(temp_surroundings, dtype=float)
    return v * np.asarray(longwave_sky) + (1.0 - v) * emissivity_surroundings * SIGMA * ts ** 4


def forcing_from_environment(state, time_step: float, albedo, surface_tilt=0.0,
                             surface_azimuth=180.0, sky_view=None, temp_surroundings=None,
                             albedo_ground: float = 0.2, diffuse_model: str = "isotropic",
                             pressure=101325.0) -> SurfaceForcing:
    """Forcing of N land pixels from the environment the ship sees.

    Parameters
    ----------
    state : shipthermal.environment.EnvironmentState
        The environment at the n_t instants of a uniform grid (``env.at(times)``).
    time_step : float
        Spacing of those instants [s].
    albedo : float or array_like
        (N,) short-wave albedo of each pixel [-] (the class's, or fitted per pixel).
    surface_tilt, surface_azimuth : float or array_like
        (N,) terrain slope and aspect (downslope compass azimuth) [deg].
    sky_view : array_like, optional
        (N,) sky-view factor [-]; default that of the tilted plane alone
        (:func:`sky_view_factor`); pass a smaller one where buildings hide the sky.
    temp_surroundings : float or array_like, optional
        Temperature of what fills the rest of the view [K]; default the air temperature.
    albedo_ground : float
        Albedo of the surroundings for the ground-reflected short-wave [-].
    diffuse_model : str
        pvlib sky-diffuse model (:func:`shortwave_on_tilted`); ``haydavies``/``perez`` get
        pvlib's extraterrestrial DNI and air mass at the state's times.
    pressure : float or array_like
        Air pressure [Pa].

    Returns
    -------
    SurfaceForcing
        Absorbed short-wave ``(1 − albedo) · poa_global``, incoming long-wave
        ``V L↓ + (1 − V) σ T_surr⁴`` (:func:`longwave_incoming`, surroundings black), air
        temperature, humidity and the 10 m wind of the state.
    """
    tilt = np.atleast_1d(np.asarray(surface_tilt, dtype=float))
    azim = np.atleast_1d(np.asarray(surface_azimuth, dtype=float))
    alb = np.atleast_1d(np.asarray(albedo, dtype=float))
    n = max(tilt.size, azim.size, alb.size, 1 if sky_view is None else np.size(sky_view))
    tilt, azim, alb = (np.broadcast_to(x, (n,)) for x in (tilt, azim, alb))
    check_range("forcing.albedo", alb, 0.0, 1.0)
    check_range("forcing.surface_tilt", tilt, 0.0, 90.0, "deg")
    extra = airmass = None
    if diffuse_model != "isotropic":
        extra = pvlib.irradiance.get_extra_radiation(state.times).to_numpy()
        airmass = pvlib.atmosphere.get_relative_airmass(np.asarray(state.zenith))
    sw = shortwave_on_tilted(tilt, azim, state.zenith, state.azimuth, state.dni, state.ghi,
                             state.dhi, albedo_ground, diffuse_model, extra, airmass)
    view = sky_view_factor(tilt) if sky_view is None else np.broadcast_to(
        np.asarray(sky_view, dtype=float), (n,))
    t_surr = (np.asarray(state.temp_air)[:, None] if temp_surroundings is None
              else np.asarray(temp_surroundings, dtype=float))
    lw = longwave_incoming(np.asarray(state.longwave_down)[:, None], view, t_surr, 1.0)
    return SurfaceForcing(float(time_step), (1.0 - alb) * sw["poa_global"],
                          np.ascontiguousarray(np.broadcast_to(lw, sw["poa_global"].shape)),
                          np.asarray(state.temp_air, dtype=float),
                          np.asarray(state.relative_humidity, dtype=float),
                          np.asarray(state.wind_speed, dtype=float), pressure)
