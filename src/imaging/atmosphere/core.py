"""One entry point for the atmosphere: table (default, no Fortran) or live LOWTRAN.

Quantities are those of the paper's eqs. (1), (2) and (21): transmittance τa along the
view, path radiance La↑ (thermal + single-scattered sunlight), direct solar irradiance at
the ground (τs Esun), and the sky radiance / irradiance that the background and the ship
reflect (thermal, under the day's cloud, + single-scattered sunlight), each with the view
transmittance weighted by its own spectrum.

Everything is LOWTRAN 7's (:mod:`.lowtran_backend`): one of its six model atmospheres,
scaled to the day's weather (:class:`.models.AtmosphereState`), Navy maritime aerosol at
23 km driven by the day's wind and humidity, LOWTRAN's cloud decks and its
single-scattering of sunlight. The tables (:mod:`.tables`) hold it for every named band;
other responses are integrated from the tables' spectra at the model's own state and
carried to the day's state bin by bin (:mod:`.spectral_bins`, also their sky under the
cloud decks); their scattered sunlight is the nearest named band's (in mean wavelength).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from scipy.interpolate import CubicSpline

from shipthermal.errors import InputError, check_finite, check_range
from shipthermal.optics.planck import planck_radiance
from shipthermal.optics.responses import (BAND_NAMES, SpectralResponse, named_band,
                                          rectangular_response, response_from_table,
                                          user_band_names)

from ..parameters import DEFAULT_CLOUD_TYPE, MAX_VIEW_ZENITH
from . import lowtran_backend as lb
from . import models as mdl
from . import spectral_bins as sb
from . import tables as tb
from .bands import band_weights, parse_band
from .lookup import (_bin_matrix, _cloud_columns, _geom, _ratio_std, _state_key, _table_spectra,
                     _table_values, _thermal_columns, _user_cloudy, _user_ratio, _user_std,
                     _user_weights, band_value)

__all__ = ["SEASONS", "MODELS", "AtmosphereResult", "atmosphere", "sky_radiance",
           "season_model", "planck_weighted_transmittance", "band_value", "resolve_band",
           "cloud_type_number"]

#: Model atmospheres by name → LOWTRAN model number (the paper's two under their labels)
MODELS = dict(mdl.MODEL_NUMBERS)
SEASONS = {"summer": 2, "winter": 3}
"""The paper's two labels → LOWTRAN model (mid-latitude summer / winter)."""


def season_model(season) -> tuple[str, int]:
    """(label, LOWTRAN model number) of a model atmosphere: ``"summer"``/``"winter"`` for
    the paper's two (also for ``"midlatitude_summer"``, 2, ...), else the model's name."""
    return mdl.model_label(season), mdl.model_number(season)


def cloud_type_number(cloud_type) -> int:
    """LOWTRAN ``ICLD`` (1-5) of a cloud deck name (:data:`.models.CLOUD_TYPES`)."""
    key = str(cloud_type).strip().lower()
    if key not in mdl.CLOUD_TYPES:
        raise InputError("cloud_type", cloud_type, f"must be one of "
                         f"{', '.join(mdl.CLOUD_TYPES)} (LOWTRAN 7's cloud decks)")
    return mdl.CLOUD_TYPES[key]


def resolve_band(band, response=None) -> tuple[str, SpectralResponse, bool]:
    """``(name, response, named)`` of a band: a named band (:data:`BAND_NAMES`, also
    ``"mwir"``/``"lwir"``), a ``"lo-hi"`` string or pair [µm] (rectangular), a
    :class:`SpectralResponse`, or a legacy ``response=(wavelength_um, response)`` table."""
    if isinstance(band, SpectralResponse):
        return _as_named(band)
    if response is not None:
        resp = response if isinstance(response, SpectralResponse) else response_from_table(
            str(band), *response)
        return _as_named(resp)
    if isinstance(band, str) and band in BAND_NAMES:
        return band, named_band(band), True
    if isinstance(band, str) and band in user_band_names():     # a user sensor's, by name
        return _as_named(named_band(band))
    name, lim = parse_band(band)
    if name in BAND_NAMES:
        return name, named_band(name), True
    return name, rectangular_response(*lim, name=name), False


def _as_named(resp: SpectralResponse) -> tuple[str, SpectralResponse, bool]:
    """A response the tables hold as a named band (the same knots and values, e.g. a user's
    copy of Landsat-8 band 10 or of the 8-14 µm rectangle) is looked up as that band;
    any other goes through the spectral bins."""
    match = _named_match(tuple(resp.wavelength_um), tuple(resp.response))
    return (match, resp, True) if match else (resp.name, resp, False)


@lru_cache(maxsize=64)
def _named_match(wavelength_um: tuple, response: tuple) -> str | None:
    resp = SpectralResponse("?", np.array(wavelength_um), np.array(response))
    return next((b for b in BAND_NAMES if _same(resp, named_band(b))), None)


def _same(a: SpectralResponse, b: SpectralResponse) -> bool:
    return (a.wavelength_um.shape == b.wavelength_um.shape
            and np.allclose(a.wavelength_um, b.wavelength_um)
            and np.allclose(a.response, b.response))


@dataclass(frozen=True)
class AtmosphereResult:
    """Atmosphere for one model, state, band and geometry (band values integrated with the
    sensor response, ∫ · R dλ; ``*_spectral`` on ``wavelength_um``, None when not
    requested or not available)."""

    season: str
    band: str
    band_um: tuple
    view_zenith_deg: float
    sun_zenith_deg: float
    view_azimuth_from_sun_deg: float
    sky_zenith_deg: float
    sky_azimuth_from_sun_deg: float
    backend: str
    #: Band-mean slant transmittance ground → space along the view, ∫τR dλ/∫R dλ [-]
    transmittance: float
    #: Upward atmospheric path radiance at the sensor, thermal + scattered solar,
    #: ∫L R dλ [W m⁻² sr⁻¹] (La↑ of the paper's eq. 1)
    path_radiance: float
    #: Thermal emission part of the path radiance [W m⁻² sr⁻¹]
    path_radiance_thermal: float
    #: Single-scattered solar part of the path radiance (0 at night) [W m⁻² sr⁻¹]
    path_radiance_solar: float
    #: Direct solar irradiance at the ground on a surface normal to the beam, times the
    #: cloud-free share of the sky [W m⁻²]
    solar_irradiance_ground: float
    #: Direct solar irradiance on a horizontal surface, × cos θs (0 at night) [W m⁻²]
    solar_irradiance_horizontal: float
    #: Downwelling thermal sky radiance at the ground from zenith angle ``sky_zenith_deg``
    #: (default: the view zenith, the specular sky of a level surface), clear and cloudy
    #: shares mixed [W m⁻² sr⁻¹]
    sky_radiance: float
    #: Hemispherical thermal sky irradiance on a horizontal surface [W m⁻²]
    sky_irradiance: float
    #: Single-scattered solar radiance from the sky direction [W m⁻² sr⁻¹] (0 at night)
    sky_radiance_solar: float
    #: Hemispherical single-scattered solar irradiance on a horizontal surface [W m⁻²]
    sky_irradiance_solar: float
    #: View transmittance weighted with the direct-sun spectrum (reflected sunlight) [-]
    transmittance_solar_weighted: float
    #: View transmittance weighted with the thermal sky spectrum from the sky direction [-]
    transmittance_sky_weighted: float
    #: View transmittance weighted with the scattered-sunlight sky spectrum from the sky
    #: direction [-]
    transmittance_sky_solar_weighted: float = float("nan")
    #: View transmittance weighted with the hemispherical thermal sky spectrum [-]
    transmittance_sky_mean_weighted: float = float("nan")
    #: View transmittance weighted with the hemispherical scattered-sunlight spectrum [-]
    transmittance_sky_solar_mean_weighted: float = float("nan")
    #: Model atmosphere (canonical name), the day's state and cloud
    model: str = ""
    state: object = None
    cloud_cover: float = 0.0
    cloud_type: str = ""
    #: Wavelengths of the spectral arrays [µm]
    wavelength_um: np.ndarray | None = field(default=None, repr=False)
    #: Spectral transmittance along the view [-]
    transmittance_spectral: np.ndarray | None = field(default=None, repr=False)
    #: Spectral thermal path radiance [W m⁻² sr⁻¹ µm⁻¹]
    path_radiance_spectral: np.ndarray | None = field(default=None, repr=False)
    #: Spectral beam-normal direct solar irradiance at the ground [W m⁻² µm⁻¹]
    solar_irradiance_spectral: np.ndarray | None = field(default=None, repr=False)
    #: Spectral thermal sky radiance from the sky direction [W m⁻² sr⁻¹ µm⁻¹]
    sky_radiance_spectral: np.ndarray | None = field(default=None, repr=False)
    #: Stated table errors for this model (None: live backend)
    interpolation_error: dict | None = field(default=None, repr=False)


def _as_state(state, aerosol) -> mdl.AtmosphereState:
    if state is not None and aerosol is not None:
        raise InputError("aerosol", aerosol, "cannot be given with state",
                         "Put the wind into the AtmosphereState")
    if state is not None:
        return state
    if aerosol is None:
        return mdl.AtmosphereState()
    a = dict(aerosol)
    allowed = {"wind_speed", "wind_speed_24h", "rel_humidity", "vis_km", "temp_air"}
    extra = sorted(set(a) - allowed)
    if extra:
        raise InputError("aerosol", extra, f"keys must be among {sorted(allowed)}")
    ws, wh = a.get("wind_speed"), a.get("wind_speed_24h")
    if ws is not None and wh is not None and not math.isclose(ws, wh, rel_tol=1e-9):
        raise InputError("aerosol.wind_speed_24h", wh, f"must equal wind_speed ({ws}): the "
                         "atmosphere takes one wind for LOWTRAN's current and 24-h wind")
    return mdl.AtmosphereState(temp_air_K=a.get("temp_air"), rel_humidity=a.get("rel_humidity"),
                               wind_speed=ws if ws is not None else wh,
                               vis_km=a.get("vis_km", 23.0))


# ------------------------------------------------------------------- live backend
def _live_values(name, resp, view_z, sun_z, sky_z, view_az, sky_az, state, cloud_cover,
                 cloud):
    up = lb.upward(name, view_z, state)
    lam = up["wavelength_um"]
    w = band_weights(lam, None, resp)
    sun = min(sun_z, 90.0)
    sol = lb.direct_solar(name, sun, state)["solar_irradiance"]
    sky = lb.sky(name, min(sky_z, 89.9), state)["sky_radiance"]
    spec_sky_spec = lb.sky(name, min(view_z, 89.9), state)["sky_radiance"]
    _, e_sky = lb.sky_irradiance(name, state)
    tau = up["transmittance"]

    def wt(src):
        den = float(w @ src)
        return float(w @ (tau * src) / den) if den > 0 else float(w @ tau / w.sum())

    out = {"transmittance": float(w @ tau / w.sum()), "path_radiance": float(w @ up[
        "path_radiance"]), "solar_irradiance": float(w @ sol), "sky_radiance": float(w @ sky),
        "sky_irradiance": float(w @ e_sky), "tau_sun": wt(sol), "tau_sky": wt(spec_sky_spec),
        "tau_sky_mean": wt(e_sky)}
    if cloud_cover > 0.0:
        out["sky_radiance_cloudy"] = float(w @ lb.sky(name, min(sky_z, 89.9), state,
                                                      cloud)["sky_radiance"])
        out["sky_irradiance_cloudy"] = float(w @ lb.sky_irradiance(name, state, cloud)[1])
    if sun_z >= 90.0:
        out.update(path_solar=0.0, sky_solar=0.0, e_solar=0.0, tau_sky_solar=out["tau_sky"],
                   tau_e_solar=out["tau_sun"])
        return out, {"wavelength_um": lam, "transmittance_spectral": tau,
                     "path_radiance_spectral": up["path_radiance"],
                     "solar_irradiance_spectral": sol, "sky_radiance_spectral": sky}
    p = lb.scattered_path(name, view_z, sun, view_az, state)["path_radiance_solar"]
    k = lb.scattered_sky(name, min(sky_z, 89.0), sun, sky_az, state)["sky_radiance_solar"]
    out["path_solar"] = float(w @ p)
    out["sky_solar"] = float(w @ k)
    out["tau_sky_solar"] = wt(k) if out["sky_solar"] > 0 else out["tau_sky"]
    # hemispherical scattered irradiance: the tables' grid, live
    g = tb.load_table()
    zs, az = g.grid("ss_sky"), g.grid("ss_azimuth")
    grid = np.array([[lb.scattered_sky(name, z, sun, a, state)["sky_radiance_solar"]
                      for a in az] for z in zs])
    e_ss = tb.hemispherical_solar(zs, az, grid)
    out["e_solar"] = float(w @ e_ss)
    out["tau_e_solar"] = wt(e_ss)
    return out, {"wavelength_um": lam, "transmittance_spectral": tau,
                 "path_radiance_spectral": up["path_radiance"],
                 "solar_irradiance_spectral": sol, "sky_radiance_spectral": sky}


def _check_geometry(view_zenith_deg, sun_zenith_deg, sky_zenith_deg, azimuths, backend):
    check_range("view_zenith_deg", view_zenith_deg, 0.0, MAX_VIEW_ZENITH[backend], "deg")
    check_range("sun_zenith_deg", sun_zenith_deg, 0.0, 180.0, "deg")
    check_range("sky_zenith_deg", sky_zenith_deg, 0.0, 90.0, "deg")
    for name, value in azimuths.items():
        check_finite(name, value)


def _band_values(name, band_name, resp, named, backend, view_zenith_deg, sun_zenith_deg,
                 sky_z, view_az, sky_az, st, cloud_cover, cloud, spectral) -> tuple:
    """The band values of one geometry from the tables or a live run, the spectral arrays
    requested and the tables' stated errors (None live)."""
    arrays = {}
    if backend == "table":
        v = _table_values(name, band_name, resp, named, float(view_zenith_deg),
                          float(sun_zenith_deg), float(sky_z), view_az,
                          sky_az, st, cloud_cover, cloud)
        if spectral:
            arrays = _table_spectra(name, view_zenith_deg, sun_zenith_deg, sky_z)
        err = tb.interpolation_errors().get(name)
    else:
        v, spec = _live_values(name, resp, float(view_zenith_deg), float(sun_zenith_deg),
                               float(sky_z), view_az, sky_az, st,
                               cloud_cover, cloud)
        arrays = spec if spectral else {}
        err = None
    return v, arrays, err


def _cloudy_sky(v: dict, c: float, name, band_name, resp, named, view_zenith_deg, backend,
                st) -> tuple:
    """Sky radiance and irradiance with a cloud share ``c`` (clear and cloudy mixed) and
    the view transmittances weighted with their spectra."""
    sky_th, sky_hemis = v["sky_radiance"], v["sky_irradiance"]
    tau_sky, tau_sky_mean = v["tau_sky"], v["tau_sky_mean"]
    if c > 0.0:
        # the cloudy share radiates like a blackbody near the air temperature: its
        # transmittance is the Planck-weighted one at the air temperature
        t_air = mdl.surface_state(name).temp_air_K + st.offsets(name)[0]
        tau_cl = float(planck_weighted_transmittance(name, resp if not named else band_name,
                                                     view_zenith_deg, t_air, backend=backend,
                                                     state=st))
        lc_, ec_ = v["sky_radiance_cloudy"], v["sky_irradiance_cloudy"]
        mix = (1.0 - c) * sky_th + c * lc_
        tau_sky = ((1.0 - c) * sky_th * tau_sky + c * lc_ * tau_cl) / mix if mix > 0 else tau_sky
        mix_e = (1.0 - c) * sky_hemis + c * ec_
        tau_sky_mean = (((1.0 - c) * sky_hemis * tau_sky_mean + c * ec_ * tau_cl) / mix_e
                        if mix_e > 0 else tau_sky_mean)
        sky_th, sky_hemis = mix, mix_e
    return sky_th, sky_hemis, tau_sky, tau_sky_mean


def atmosphere(model, band, view_zenith_deg: float, sun_zenith_deg: float,
               backend: str = "table", view_azimuth_from_sun_deg: float = 90.0,
               sky_zenith_deg: float | None = None,
               sky_azimuth_from_sun_deg: float | None = None, response=None,
               aerosol: dict | None = None, spectral: bool = True, state=None,
               cloud_cover: float = 0.0, cloud_type: str = DEFAULT_CLOUD_TYPE) -> AtmosphereResult:
    """Transmittance, path radiance, solar irradiance and sky radiance for one geometry.

    Parameters
    ----------
    model : str or int
        Model atmosphere: ``"tropical"``, ``"midlatitude_summer"``,
        ``"midlatitude_winter"``, ``"subarctic_summer"``, ``"subarctic_winter"``,
        ``"us_standard_1976"`` (or ``"summer"``/``"winter"``, the paper's two).
    band : str, tuple or SpectralResponse
        A named band (:data:`shipthermal.optics.responses.BAND_NAMES`: ``"3-5"``, ``"8-14"``,
        ``"landsat8_tirs_b10"``, ...), ``"lo-hi"`` or ``(lo, hi)`` [µm] (rectangular) or a
        sensor response.
    view_zenith_deg : float
        Sensor view zenith angle at the ground [deg], ≤ 80 (table) or 85 (live).
    sun_zenith_deg : float
        Sun zenith angle [deg]; ≥ 90 gives zero solar terms.
    backend : {"table", "lowtran"}
        Embedded tables (default, no Fortran) or live LOWTRAN 7 (optional dependency,
        seconds per call; ~1 min with sunlight, whose hemispherical integral takes ~1000
        runs).
    view_azimuth_from_sun_deg : float
        Azimuth of the sensor seen from the ground minus the sun's azimuth [deg]
        (0: sensor on the sun's side, backscatter).
    sky_zenith_deg, sky_azimuth_from_sun_deg : float, optional
        Sky direction of ``sky_radiance`` [deg]; default the specular direction of a level
        surface: zenith = view zenith, azimuth = view azimuth + 180.
    response : tuple of arrays, optional
        ``(wavelength_um, relative_response)`` replacing the band's shape (legacy form of
        passing a :class:`SpectralResponse` as ``band``).
    aerosol : dict, optional
        Legacy form of ``state``: ``wind_speed`` (= ``wind_speed_24h``) [m s⁻¹],
        ``rel_humidity`` [%], ``temp_air`` [K], ``vis_km`` (live backend only).
    spectral : bool
        Return the ``*_spectral`` arrays (live: the day's; table: the model's own state).
    state : AtmosphereState, optional
        The day's near-surface air temperature, humidity and wind (default: the model's
        own state and LOWTRAN's default wind).
    cloud_cover : float
        Cloud fraction [0-1]: the sky is ``(1 − c)`` clear + ``c`` under LOWTRAN's
        ``cloud_type`` deck; the direct and scattered sunlight keep the clear share
        ``1 − c`` (the decks are opaque to the beam; light the cloud scatters down is not
        modelled). The line of sight to the sensor is taken as clear.
    cloud_type : str
        ``"cumulus"``, ``"altostratus"``, ``"stratus"``, ``"stratocumulus"``,
        ``"nimbostratus"`` (LOWTRAN 7 ``ICLD`` 1-5).

    Returns
    -------
    AtmosphereResult
    """
    name = mdl.model_name(model)
    label = mdl.model_label(name)
    band_name, resp, named = resolve_band(band, response)
    if backend not in MAX_VIEW_ZENITH:
        raise InputError("backend", backend, "'table' or 'lowtran'")
    st = _as_state(state, aerosol)
    if backend == "table" and st.vis_km != 23.0:
        raise InputError("vis_km", st.vis_km, "must be 23 km with the table backend (the "
                         "tables hold the paper's visibility)", "Use backend='lowtran'")
    check_range("cloud_cover", cloud_cover, 0.0, 1.0)
    cloud = cloud_type_number(cloud_type)
    sky_z = view_zenith_deg if sky_zenith_deg is None else sky_zenith_deg
    sky_az = (view_azimuth_from_sun_deg + 180.0 if sky_azimuth_from_sun_deg is None
              else sky_azimuth_from_sun_deg)
    _check_geometry(view_zenith_deg, sun_zenith_deg, sky_z,
                    {"view_azimuth_from_sun_deg": view_azimuth_from_sun_deg,
                     "sky_azimuth_from_sun_deg": sky_az}, backend)
    v, arrays, err = _band_values(name, band_name, resp, named, backend, view_zenith_deg,
                                  sun_zenith_deg, sky_z, view_azimuth_from_sun_deg, sky_az, st,
                                  cloud_cover, cloud, spectral)
    c = float(cloud_cover)
    sky_th, sky_hemis, tau_sky, tau_sky_mean = _cloudy_sky(
        v, c, name, band_name, resp, named, view_zenith_deg, backend, st)
    clear = 1.0 - c
    e_sun = v["solar_irradiance"] * clear if sun_zenith_deg < 90.0 else 0.0
    lo_hi = (float(resp.wavelength_um[0]), float(resp.wavelength_um[-1]))
    return AtmosphereResult(
        season=label, band=band_name, band_um=lo_hi, view_zenith_deg=float(view_zenith_deg),
        sun_zenith_deg=float(sun_zenith_deg),
        view_azimuth_from_sun_deg=float(view_azimuth_from_sun_deg),
        sky_zenith_deg=float(sky_z), sky_azimuth_from_sun_deg=float(sky_az), backend=backend,
        transmittance=v["transmittance"],
        path_radiance=v["path_radiance"] + v["path_solar"],
        path_radiance_thermal=v["path_radiance"], path_radiance_solar=v["path_solar"],
        solar_irradiance_ground=e_sun,
        solar_irradiance_horizontal=float(e_sun * max(math.cos(math.radians(sun_zenith_deg)),
                                                      0.0)),
        sky_radiance=sky_th, sky_irradiance=sky_hemis,
        sky_radiance_solar=v["sky_solar"] * clear, sky_irradiance_solar=v["e_solar"] * clear,
        transmittance_solar_weighted=v["tau_sun"], transmittance_sky_weighted=tau_sky,
        transmittance_sky_solar_weighted=v["tau_sky_solar"],
        transmittance_sky_mean_weighted=tau_sky_mean,
        transmittance_sky_solar_mean_weighted=v["tau_e_solar"],
        model=name, state=st, cloud_cover=c, cloud_type=str(cloud_type),
        interpolation_error=err, **arrays)


def planck_weighted_transmittance(model, band, view_zenith_deg: float, temp_K,
                                  backend: str = "table", response=None,
                                  aerosol: dict | None = None, state=None):
    """View transmittance weighted with a blackbody spectrum, ∫τ B(T) R dλ / ∫B(T) R dλ.

    The right band transmittance for emitted radiance (grey emissivity within the band)
    in the paper's eq. (1): τ̄·∫B differs from ∫τB by +10-15 % (3-5 µm) and −2-3 %
    (8-14 µm) at 300 K.

    Parameters
    ----------
    model, band, view_zenith_deg, backend, response, aerosol, state
        As :func:`atmosphere`.
    temp_K : array_like
        Source temperature(s) [K], 100-2000.

    Returns
    -------
    ndarray, shape of ``temp_K``
        Planck-weighted band transmittance [-]. Table backend: the tables' weighting at
        the model's own state (10 K grid, cubic in T) times the ratio of the day's 300 K
        weighted transmittance (state tables) to the model's own; a user response: its
        own-state spectrum weighted with the blackbody, bin by bin times the bins'
        transmittance factors (:mod:`.spectral_bins`).
    """
    t = np.asarray(temp_K, dtype=float)
    check_range("temp_K", t, 100.0, 2000.0, "K")
    name = mdl.model_name(model)
    band_name, resp, named = resolve_band(band, response)
    st = _as_state(state, aerosol)
    if backend == "table":
        tab = tb.load_table()
        grid_t = tab.grid("planck_temp_K")
        if named:
            ratio = float(_ratio_std(name, band_name, st, "tau_planck300", view_zenith_deg))
            if float(t.min()) >= grid_t[0] and float(t.max()) <= grid_t[-1]:
                return _tau_planck_spline(name, band_name, float(view_zenith_deg))(t) * ratio
        w = _user_weights((tuple(resp.wavelength_um), tuple(resp.response), resp.name))
        tau = _geom("view", tab.grid("view"), tab.get(name, "spectral_transmittance"),
                    view_zenith_deg)
        b = planck_radiance(tab.wavelength_um[None, :], t.reshape(-1, 1))
        if not named:     # each bin's own-state share carried by its factor (spectral bins)
            f = np.exp(sb.bin_log_factors(name, "transmittance", *_state_key(name, st),
                                          view_zenith_deg))
            return (((b * tau * w) @ _bin_matrix()) @ f / (b @ w)).reshape(t.shape)
        return ((b * tau) @ w / (b @ w)).reshape(t.shape) * ratio
    up = lb.upward(name, view_zenith_deg, st)
    lam = up["wavelength_um"]
    w = band_weights(lam, None, resp)
    b = planck_radiance(lam[None, :], t.reshape(-1, 1))
    return ((b * up["transmittance"]) @ w / (b @ w)).reshape(t.shape)


@lru_cache(maxsize=64)
def _tau_planck_spline(name: str, band_name: str, view_zenith_deg: float) -> CubicSpline:
    """The tables' Planck-weighted view transmittance of a model and named band at its own
    state, cubic in the source temperature (10 K grid): the same for every frame of a view,
    built once (every call built it again: twice a frame and band, 8 760 frames of a year's
    hourly calendar)."""
    tab = tb.load_table()
    per_t = _geom("view", tab.grid("view"),
                  tab.get(name, "tau_planck")[tab.band_index(band_name)], view_zenith_deg)
    return CubicSpline(tab.grid("planck_temp_K"), per_t)


def sky_radiance(model, band, zenith_deg, backend: str = "table", state=None,
                 cloud_cover: float = 0.0, cloud_type: str = DEFAULT_CLOUD_TYPE):
    """Band thermal sky radiance at the ground from zenith angle(s) [W m⁻² sr⁻¹].

    Vectorised over ``zenith_deg`` [deg] (0-90), e.g. for the reflected sky in a Cox–Munk
    or BRDF integral; ``state``, ``cloud_cover`` and ``cloud_type`` as :func:`atmosphere`.
    """
    name = mdl.model_name(model)
    band_name, resp, named = resolve_band(band)
    z = np.asarray(zenith_deg, dtype=float)
    check_range("zenith_deg", z, 0.0, 90.0, "deg")
    check_range("cloud_cover", cloud_cover, 0.0, 1.0)
    cloud = cloud_type_number(cloud_type)
    st = _as_state(state, None)
    if backend == "table":
        t = tb.load_table()
        g = t.grid("sky")
        if named:
            clear = _thermal_columns(name, band_name, *_state_key(name, st))[
                tb.columns("sky_radiance")]
        else:
            clear = _user_std(name, resp, "sky_radiance", g) * _user_ratio(
                name, resp, st, "sky_radiance", g)
        nodes = clear
        if cloud_cover > 0.0:
            dt, rh, _ = _state_key(name, st)
            cl = (_cloud_columns(name, band_name, cloud, dt, rh) if named
                  else _user_cloudy(name, resp, cloud, st, g))
            nodes = (1.0 - cloud_cover) * clear + cloud_cover * cl
        return _geom("sky", g, nodes, z)
    if backend != "lowtran":
        raise InputError("backend", backend, "'table' or 'lowtran'")
    out = []
    for zi in z.ravel():
        d = lb.sky(name, min(float(zi), 89.9), st)
        w = band_weights(d["wavelength_um"], None, resp)
        val = float(w @ d["sky_radiance"])
        if cloud_cover > 0.0:
            val = (1.0 - cloud_cover) * val + cloud_cover * float(
                w @ lb.sky(name, min(float(zi), 89.9), st, cloud)["sky_radiance"])
        out.append(val)
    return np.reshape(out, z.shape)
