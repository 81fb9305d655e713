"""The embedded tables evaluated for one model, band, state and geometry: the named bands'
columns at the day's state, a user response integrated from the spectra and carried to the
day's state bin by bin, LOWTRAN's cloud decks, the single-scattered sunlight, and the view
transmittance weighted with each source's spectrum."""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from shipthermal.optics.responses import BAND_NAMES, SpectralResponse, named_band

from . import models as mdl
from . import spectral_bins as sb
from . import tables as tb
from .bands import band_weights


def _reference_band(resp: SpectralResponse) -> str:
    """Named band with the closest response-weighted mean wavelength (its state factors
    stand for a response the tables do not hold)."""
    mean = resp.mean_wavelength_um
    return min(BAND_NAMES, key=lambda b: abs(named_band(b).mean_wavelength_um - mean))


def _state_key(model: str, state) -> tuple:
    """(ΔT [K], surface relative humidity [%], wind [m s⁻¹]) of a state, rounded (cache)."""
    dt, _ = state.offsets(model)
    return (round(float(dt), 4), round(float(state.surface_humidity(model)), 6),
            round(float(state.wind(model)), 4))


@lru_cache(maxsize=4096)  # a day has ~145 frames x bands: states repeat across bands
def _thermal_columns(model: str, band: str, dt: float, rh: float, w: float) -> np.ndarray:
    """Band values of all thermal columns (:func:`tables.columns`) at a state.

    ``T(ΔT, RH) · W(ΔT, RH, w) / W(ΔT, RH, w₀)``: the temperature × humidity grid at the
    model's default wind ``w₀``, times the wind's effect from the humidity × wind grids at
    three offsets (the sea-salt aerosol grows with the humidity; what it adds depends on the
    water vapour around it); PCHIP of the logarithms.
    """
    t = tb.load_table()
    ib = t.band_index(band)
    g_dt = t.grid("state_temp_offset_K")
    g_rh, g_w = t.get(model, "state_rh"), t.get(model, "state_wind")
    la = tb.interp_nd(_log_table(model, "thermal_t", ib), [g_dt, g_rh], [dt, rh])
    w0 = mdl.default_wind_speed(model)
    if abs(w - w0) > 1e-9:
        lw = _log_table(model, "thermal_w", ib)
        g_l = t.grid("wind_layer_temp_offset_K")
        la = (la + tb.interp_nd(lw, [g_l, g_rh, g_w], [dt, rh, w])
              - tb.interp_nd(lw, [g_l, g_rh, g_w], [dt, rh, w0]))
    out = np.where(la > _LOG_ZERO, np.exp(la), 0.0)
    out.setflags(write=False)
    return out


_LOG_ZERO = -600.0  # log of a table zero (the sun at the horizon)


@lru_cache(maxsize=256)
def _log_table(model: str, key: str, ib: int) -> np.ndarray:
    """Natural log of a state table of one band (zeros → :data:`_LOG_ZERO` − 1): the
    quantities vary nearly exponentially with the absorber and aerosol amounts."""
    v = tb.load_table().state_log(model, key)[..., ib, :]
    out = np.where(np.isfinite(v), v, _LOG_ZERO - 1.0)
    out.setflags(write=False)
    return out


@lru_cache(maxsize=1024)
def _cloud_columns(model: str, band: str, cloud: int, dt: float, rh: float) -> np.ndarray:
    t = tb.load_table()
    ib = t.band_index(band)
    v = _log_table(model, "cloud", ib)[cloud - 1]
    out = np.exp(tb.interp_nd(v, [t.grid("state_temp_offset_K"), t.grid("cloud_rel_humidity")],
                              [dt, rh]))
    out.setflags(write=False)
    return out


def _geom(axis: str, nodes, values, zenith):
    return tb.interpolate_axis(axis, nodes, values, zenith)


def band_value(model, band: str, quantity: str, zenith_deg, state=None):
    """A thermal table quantity (``transmittance``, ``path_radiance``, ``solar_irradiance``,
    ``sky_radiance``) of a named band at zenith angle(s) [deg] and a state."""
    name = mdl.model_name(model)
    st = mdl.AtmosphereState() if state is None else state
    cols = _thermal_columns(name, band, *_state_key(name, st))
    axis = tb._AXIS_OF[quantity]
    return _geom(axis, tb.load_table().grid(axis), cols[tb.columns(quantity)], zenith_deg)


def _ratio_std(name, band, state, quantity, zenith):
    """Quantity at ``state`` over the same at the model's own state."""
    cur = band_value(name, band, quantity, zenith, state)
    std = band_value(name, band, quantity, zenith, None)
    return np.where(std > 0.0, cur / np.where(std > 0.0, std, 1.0), 1.0)


@lru_cache(maxsize=64)
def _user_weights(resp_key: tuple) -> np.ndarray:
    wl, rr, name = resp_key
    resp = SpectralResponse(name, np.array(wl), np.array(rr))
    return band_weights(tb.load_table().wavelength_um, None, resp)


def _user_std(model, resp: SpectralResponse, quantity: str, zenith):
    """A thermal quantity of a user response at the model's own state (tables' spectra)."""
    t = tb.load_table()
    w = _user_weights((tuple(resp.wavelength_um), tuple(resp.response), resp.name))
    spec = t.get(model, f"spectral_{quantity}")
    vals = spec @ w
    if quantity == "transmittance":
        vals = vals / w.sum()
    axis = tb._AXIS_OF[quantity]
    return _geom(axis, t.grid(axis), vals, zenith)


_SPECTRA = {"transmittance": ("view", "spectral_transmittance"),
            "path_radiance": ("view", "spectral_path_radiance"),
            "solar_irradiance": ("sun", "spectral_solar_irradiance"),
            "sky_radiance": ("sky", "spectral_sky_radiance")}


@lru_cache(maxsize=1)
def _bin_matrix() -> np.ndarray:
    """(n_wavelength, n_bin) one-hot: the spectral bin of each table wavelength."""
    k = sb.bin_index(tb.load_table().wavelength_um)
    m = np.zeros((k.size, sb.BIN_EDGES_CM1.size - 1))
    m[np.arange(k.size)[k >= 0], k[k >= 0]] = 1.0
    m.setflags(write=False)
    return m


def _user_ratio(name, resp: SpectralResponse, state, quantity: str, zenith):
    """A user response's value at the day's state over its value at the model's own:
    ``Σ_j a_j F_j / Σ_j a_j`` over the spectral bins (:mod:`.spectral_bins`), ``a_j`` the
    response-weighted own-state spectrum in bin ``j``, ``F_j`` the bin's state factor at
    the day's temperature, humidity and wind."""
    t = tb.load_table()
    w = _user_weights((tuple(resp.wavelength_um), tuple(resp.response), resp.name))
    if quantity == "tau_sky":
        g = t.grid("view")
        src = (_geom("view", g, t.get(name, "spectral_transmittance"), zenith)
               * _geom("sky", t.grid("sky"), t.get(name, "spectral_sky_radiance"), zenith))
    else:
        axis, key = _SPECTRA[quantity]
        src = _geom(axis, t.grid(axis), t.get(name, key), zenith)
    a = (np.asarray(src) * w) @ _bin_matrix()                      # (..., n_bin)
    f = np.exp(sb.bin_log_factors(name, quantity, *_state_key(name, state), zenith))
    den = a.sum(axis=-1)
    return np.where(den > 0, (a * f).sum(axis=-1) / np.where(den > 0, den, 1.0), 1.0)


def _user_cloudy(name, resp: SpectralResponse, cloud: int, state, zenith):
    """Sky radiance of a user response under LOWTRAN cloud deck ``cloud`` at the day's ΔT
    and humidity: ``Σ_j a_j C_j``, ``a_j`` the response-weighted own-state clear sky in bin
    ``j``, ``C_j`` the bin's cloudy sky over that clear sky (:mod:`.spectral_bins`)."""
    t = tb.load_table()
    w = _user_weights((tuple(resp.wavelength_um), tuple(resp.response), resp.name))
    src = _geom("sky", t.grid("sky"), t.get(name, "spectral_sky_radiance"), zenith)
    a = (np.asarray(src) * w) @ _bin_matrix()                      # (..., n_bin)
    dt, rh, _ = _state_key(name, state)
    return (a * np.exp(sb.bin_log_cloud(name, cloud, dt, rh, zenith))).sum(axis=-1)


_SS_AXES = {"ss_path": ("ss_view", "ss_sun", "ss_azimuth"),
            "ss_sky": ("ss_sky", "ss_sun", "ss_azimuth"),
            "ss_sky_attenuated": ("ss_sky", "ss_sun", "ss_azimuth"),
            "ss_irradiance": ("ss_sun",), "ss_tau_irradiance": ("view", "ss_sun")}
def _phase(name, band, cos_theta):
    """LOWTRAN's band phase function of the model's aerosol (relative, 1 at 90°), measured
    from its runs (``ss_phase``): the scattered-sunlight tables are divided by it before
    interpolation, which takes out the forward peak that no grid in the angles resolves."""
    t = tb.load_table()
    ang, val = t.get(name, "ss_phase_angle"), t.get(name, "ss_phase")[t.band_index(band)]
    theta = np.degrees(np.arccos(np.clip(cos_theta, -1.0, 1.0)))
    return np.exp(np.interp(theta, ang, np.log(np.maximum(val, 1e-30))))


def _cos_scattering(key, zenith, sun, azimuth):
    """cos of the scattering angle: sunlight turned toward the sensor (path) or down to
    the observer from the sky direction (sky); azimuths from the sun [deg]."""
    t, t0, p = (np.radians(a) for a in (zenith, sun, azimuth))
    c = np.cos(t) * np.cos(t0) + np.sin(t) * np.sin(t0) * np.cos(p)
    return -c if key == "ss_path" else c


@lru_cache(maxsize=256)
def _ss_prepared(name, band, key):
    """The table of one band in ascending interpolation coordinates (cos of the zeniths,
    azimuth), divided by the Henyey–Greenstein phase function at its nodes."""
    t = tb.load_table()
    arr = np.asarray(t.get(name, key)[t.band_index(band)], dtype=float)
    axes = _SS_AXES[key]
    nodes = []
    for i, ax in enumerate(axes):
        g = t.grid(ax)
        if ax == "ss_azimuth":
            nodes.append(g)
        else:  # cos(zenith) ascending = zenith descending
            nodes.append(np.cos(np.radians(g[::-1])))
            arr = np.flip(arr, axis=i)
    if len(axes) == 3:
        z, s0, a = np.meshgrid(*(np.degrees(np.arccos(n)) if k < 2 else n
                                 for k, n in enumerate(nodes)), indexing="ij")
        arr = arr / _phase(name, band, _cos_scattering(key, z, s0, a))
    arr.setflags(write=False)
    return arr, nodes


def _ss(name, band, key, *coords):
    arr, nodes = _ss_prepared(name, band, key)
    axes = _SS_AXES[key]
    points = [c if ax == "ss_azimuth" else math.cos(math.radians(min(c, 90.0)))
              for ax, c in zip(axes, coords)]
    val = float(tb.interp_nd(arr, nodes, points))
    if len(axes) == 3:
        val *= float(_phase(name, band, _cos_scattering(key, *coords)))
    return val


def _ss_factor(name, band, state, which: int) -> float:
    """Scattered sunlight at the state over the model's own, from the humidity × wind grid
    (ΔT = 0; the aerosol's humidity and wind), in logarithms (the sea-salt modes grow
    exponentially with the wind, Gathman 1983)."""
    t = tb.load_table()
    f = t.get(name, "ss_factor")[:, :, t.band_index(band), which]
    _, rh, w = _state_key(name, state)
    return float(np.exp(tb.interp_nd(np.log(np.maximum(f, 1e-30)),
                                     [t.get(name, "state_rh"), t.get(name, "state_wind")],
                                     [rh, w])))


def _fold_azimuth(a) -> float:
    return abs((float(a) + 180.0) % 360.0 - 180.0)


def _table_values(name, band, resp, named, view_z, sun_z, sky_z, view_az, sky_az, state,
                  cloud_cover, cloud):
    t = tb.load_table()
    ref = band if named else _reference_band(resp)
    sun = min(sun_z, 90.0)
    out = {}
    if named:
        cols = _thermal_columns(name, band, *_state_key(name, state))
        for q, z in (("transmittance", view_z), ("path_radiance", view_z),
                     ("solar_irradiance", sun), ("sky_radiance", sky_z)):
            axis = tb._AXIS_OF[q]
            out[q] = float(_geom(axis, t.grid(axis), cols[tb.columns(q)], z))
        sky_nodes = cols[tb.columns("sky_radiance")]
    else:
        for q, z in (("transmittance", view_z), ("path_radiance", view_z),
                     ("solar_irradiance", sun), ("sky_radiance", sky_z)):
            out[q] = float(_user_std(name, resp, q, z)
                           * _user_ratio(name, resp, state, q, z))
        g = t.grid("sky")
        sky_nodes = _user_std(name, resp, "sky_radiance", g) * _user_ratio(
            name, resp, state, "sky_radiance", g)
    out["sky_irradiance"] = float(tb.hemispherical(t.grid("sky"), sky_nodes))
    if cloud_cover > 0.0:
        dt, rh, _ = _state_key(name, state)
        cloudy = (_cloud_columns(name, band, cloud, dt, rh) if named
                  else _user_cloudy(name, resp, cloud, state, t.grid("sky")))
        out["sky_radiance_cloudy"] = float(_geom("sky", t.grid("sky"), cloudy, sky_z))
        out["sky_irradiance_cloudy"] = float(tb.hemispherical(t.grid("sky"), cloudy))
    # view transmittance weighted with each source spectrum: the specular thermal sky's
    # is in the state tables; the others at the model's own state, carried to the day's
    # by the ratio of the nearest state-table transmittance (sky-weighted for the
    # hemispherical sky, band mean for the sun's window spectrum)
    if named:
        tau_ratio = float(_ratio_std(name, ref, state, "transmittance", view_z))
        sky_ratio = float(_ratio_std(name, ref, state, "tau_sky", view_z))
    else:
        tau_ratio = float(_user_ratio(name, resp, state, "transmittance", view_z))
        sky_ratio = float(_user_ratio(name, resp, state, "tau_sky", view_z))
    ib = t.band_index(ref)
    if named:
        out["tau_sky"] = float(band_value(name, band, "tau_sky", view_z, state))
        out["tau_sky_mean"] = float(_geom("view", t.grid("view"), t.get(name, "tau_sky_mean")[
            ib], view_z)) * sky_ratio
        tsun = _geom("view", t.grid("view"), t.get(name, "tau_sun")[ib], view_z)
        out["tau_sun"] = float(_geom("sun", t.grid("sun"), tsun, sun)) * tau_ratio
    else:
        for key, ratio in (("tau_sky", sky_ratio), ("tau_sky_mean", sky_ratio),
                           ("tau_sun", tau_ratio)):
            out[key] = _user_weighted(name, resp, key, view_z, sun) * ratio
    # single-scattered sunlight (reference band and solar ratio for a user response)
    night = sun_z >= 90.0
    if night:
        out.update(path_solar=0.0, sky_solar=0.0, sky_solar_att=0.0, e_solar=0.0,
                   tau_e_solar=out["tau_sun"])
    else:
        k_path = _ss_factor(name, ref, state, 0)
        k_sky = _ss_factor(name, ref, state, 1)
        gain = 1.0
        if not named:
            e_ref = float(band_value(name, ref, "solar_irradiance", sun, None))
            e_usr = float(_user_std(name, resp, "solar_irradiance", sun))
            gain = e_usr / e_ref if e_ref > 0 else 0.0
        view_phi, sky_phi = _fold_azimuth(view_az), _fold_azimuth(sky_az)
        out["path_solar"] = gain * k_path * _ss(name, ref, "ss_path", view_z, sun, view_phi)
        sky_z_ss = min(sky_z, 89.0)
        out["sky_solar"] = gain * k_sky * _ss(name, ref, "ss_sky", sky_z_ss, sun, sky_phi)
        att = gain * k_sky * _ss(name, ref, "ss_sky_attenuated", sky_z_ss, sun, sky_phi)
        out["tau_sky_solar"] = (att / out["sky_solar"] * tau_ratio if out["sky_solar"] > 0
                                else out["tau_sky"])
        out["e_solar"] = gain * k_sky * _ss(name, ref, "ss_irradiance", sun)
        out["tau_e_solar"] = _ss(name, ref, "ss_tau_irradiance", view_z, sun) * tau_ratio
    out.setdefault("tau_sky_solar", out["tau_sky"])
    return out


def _user_weighted(name, resp, key, view_z, sun_z) -> float:
    """Source-weighted view transmittance of a user response at the model's own state."""
    t = tb.load_table()
    w = _user_weights((tuple(resp.wavelength_um), tuple(resp.response), resp.name))
    tau = t.get(name, "spectral_transmittance")
    g = t.grid("view")
    tau_v = _geom("view", g, tau, view_z)
    if key == "tau_sun":
        src = _geom("sun", t.grid("sun"), t.get(name, "spectral_solar_irradiance"), sun_z)
    elif key == "tau_sky":
        src = _geom("sky", t.grid("sky"), t.get(name, "spectral_sky_radiance"), view_z)
    else:
        src = tb.hemispherical(t.grid("sky"), t.get(name, "spectral_sky_radiance"))
    den = float(w @ src)
    return float(w @ (tau_v * src) / den) if den > 0 else float(w @ tau_v / w.sum())


def _table_spectra(name, view_z, sun_z, sky_z) -> dict:
    t = tb.load_table()
    return {"wavelength_um": t.wavelength_um,
            "transmittance_spectral": _geom("view", t.grid("view"),
                                            t.get(name, "spectral_transmittance"), view_z),
            "path_radiance_spectral": _geom("view", t.grid("view"),
                                            t.get(name, "spectral_path_radiance"), view_z),
            "solar_irradiance_spectral": (_geom("sun", t.grid("sun"), t.get(
                name, "spectral_solar_irradiance"), min(sun_z, 90.0)) if sun_z < 90.0
                else np.zeros_like(t.wavelength_um)),
            "sky_radiance_spectral": _geom("sky", t.grid("sky"),
                                           t.get(name, "spectral_sky_radiance"), sky_z)}
