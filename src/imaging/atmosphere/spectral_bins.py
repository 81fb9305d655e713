"""Spectral state factors: how each narrow spectral bin changes with the day's state.

The band tables (:mod:`.tables`) hold the state dependence of the named bands only; a
user's response is integrated from the spectra of the model's own state. To carry it to
the day's air temperature and humidity, ``data/atmosphere_bins.npz`` (written by
``scripts/make_atmosphere_tables.py --bins`` from live LOWTRAN 7) holds, per model and
for every bin of :data:`BIN_EDGES_CM1`, the factor

    F_j(ΔT, RH, θ) = Q_j(ΔT, RH, θ) / Q_j(own state, θ)

of transmittance, thermal path radiance, direct sun, thermal sky radiance and the
sky-weighted view transmittance, over the band tables' ΔT × RH grid (LOWTRAN's default
wind), times the wind's factor ``W(ΔT, RH, w) / W(ΔT, RH, w₀)`` over their RH × wind
grids at three temperature offsets (the sea-salt aerosol: in a clean window it is most of
the path radiance, and what it adds depends on the water vapour around it), at the zenith
nodes :data:`BIN_GRID`; and the sky radiance under each of LOWTRAN's cloud decks over ΔT
× the band tables' cloud humidity grid, relative to the bin's own-state clear sky. A
response ``R`` then takes

    Q_R(state, θ) = Σ_j a_j(θ) F_j(state, θ),   a_j(θ) = Σ_{λ ∈ j} w_λ q_own(λ, θ)

(``w`` the response's integration weights on the tables' wavelengths, ``q_own`` the
model's own spectrum): exact at the model's own state, and as good elsewhere as the
factor is uniform across a bin. Bins are 20 cm⁻¹ wide from 710 to 1430 cm⁻¹
(6.99-14.1 µm; LOWTRAN 7's resolution, four of its samples each; the first from 680),
two across the opaque 5.5-7 µm water band, and 40 cm⁻¹ from 1820 to 3460 cm⁻¹
(2.89-5.49 µm).

Stored as int16 steps of ln F (:data:`.tables.STATE_LOG_STEP`; ``STATE_ZERO`` where the
bin's own value is zero). Measured errors against live LOWTRAN are in the file's
metadata (:func:`bin_errors`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from . import tables as tb

__all__ = ["BIN_FILE", "BIN_EDGES_CM1", "BIN_GRID", "BIN_QUANTITIES", "bin_index",
           "BinTable", "load_bins", "bin_log_factors", "bin_log_cloud", "bin_errors"]

BIN_FILE = "atmosphere_bins.npz"

BIN_EDGES_CM1 = np.unique(np.concatenate([
    [680.0],                                   # the tables' last sample, 689.99998 cm-1
    np.arange(710.0, 1430.0 + 1e-9, 20.0),     # 14.08-6.99 µm: LOWTRAN 7's 20 cm-1
    [1625.0, 1820.0],                          # the opaque 6.15-5.49 µm water band
    np.arange(1860.0, 3460.0 + 1e-9, 40.0),    # 5.38-2.89 µm
]))
"""Edges of the spectral bins [cm⁻¹], ascending (the tables' 2.9-14.5 µm inside)."""

BIN_GRID = {
    "view": np.array([0.0, 40.0, 60.0, 70.0, 80.0]),
    "sun": np.array([0.0, 60.0, 75.0, 84.0, 88.0, 89.5]),
    "sky": np.array([0.0, 40.0, 60.0, 70.0, 80.0, 86.0, 89.9]),
}
"""Zenith nodes of the bin factors [deg] (the factor is smooth in the air mass; the sky
nodes hold the view nodes, for the sky-weighted transmittance)."""

BIN_QUANTITIES = ("transmittance", "path_radiance", "solar_irradiance", "sky_radiance",
                  "tau_sky")
"""Columns of the bin tables, each at its axis' nodes (:data:`BIN_AXIS`)."""

BIN_AXIS = {"transmittance": "view", "path_radiance": "view", "solar_irradiance": "sun",
            "sky_radiance": "sky", "tau_sky": "view"}


def bin_columns(quantity: str) -> slice:
    """Columns of ``quantity`` in the bin tables."""
    start = 0
    for q in BIN_QUANTITIES:
        n = BIN_GRID[BIN_AXIS[q]].size
        if q == quantity:
            return slice(start, start + n)
        start += n
    raise KeyError(quantity)


def bin_index(wavelength_um) -> np.ndarray:
    """Bin of each wavelength [µm] (−1 outside :data:`BIN_EDGES_CM1`)."""
    nu = 1e4 / np.asarray(wavelength_um, dtype=float)
    k = np.searchsorted(BIN_EDGES_CM1, nu, side="right") - 1
    return np.where((k >= 0) & (k < BIN_EDGES_CM1.size - 1), k, -1)


@dataclass(frozen=True)
class BinTable:
    """Contents of the bin file (arrays read-only)."""

    arrays: dict
    meta: dict

    def log_factor(self, model: str) -> np.ndarray:
        """ln F (n_ΔT, n_RH, n_bin, n_col), −inf where the bin's value is zero."""
        return tb.decode_log_steps(self.arrays[f"{model}__bins_q"])

    def log_wind_factor(self, model: str) -> np.ndarray:
        """ln W(w) / W(w₀) (n_layer, n_RH, n_wind, n_bin, n_col) at the temperature offsets
        :data:`.tables.GRID` ``["wind_layer_temp_offset_K"]``, −inf where zero."""
        return tb.decode_log_steps(self.arrays[f"{model}__bins_w_q"])

    def log_cloud(self, model: str) -> np.ndarray:
        """ln (sky under a cloud deck / own-state clear sky) (n_cloud, n_ΔT, n_RH_cloud,
        n_bin, n_sky), −inf where zero."""
        return tb.decode_log_steps(self.arrays[f"{model}__bins_cloud_q"])

    def rh_nodes(self, model: str) -> np.ndarray:
        return self.arrays[f"{model}__state_rh"]

    def wind_nodes(self, model: str) -> np.ndarray:
        return self.arrays[f"{model}__state_wind"]


@lru_cache(maxsize=1)  # immutable package data: read the file once per process
def load_bins() -> BinTable:
    """Load ``data/atmosphere_bins.npz`` shipped with the package."""
    arrays, meta = tb.read_package_npz(BIN_FILE)
    return BinTable(arrays=arrays, meta=meta)


@lru_cache(maxsize=1024)  # a day's states repeat across frames and bands
def _log_factors_at(model: str, dt: float, rh: float, wind: float) -> np.ndarray:
    t = load_bins()
    v = t.log_factor(model)
    out = tb.interp_nd(np.where(np.isfinite(v), v, -600.0),
                       [tb.GRID["state_temp_offset_K"], t.rh_nodes(model)], [dt, rh])
    vw = t.log_wind_factor(model)
    out = out + tb.interp_nd(np.where(np.isfinite(vw), vw, 0.0),
                             [tb.GRID["wind_layer_temp_offset_K"], t.rh_nodes(model),
                              t.wind_nodes(model)], [dt, rh, wind])
    out.setflags(write=False)
    return out


def bin_log_factors(model: str, quantity: str, dt: float, rh: float, wind: float,
                    zenith_deg):
    """ln F of every bin at a state (ΔT [K], surface RH [%], wind [m s⁻¹]) and zenith(s)
    [deg]: ``ln F(ΔT, RH) + ln W(ΔT, RH, wind) / W(ΔT, RH, wind₀)``, PCHIP over the state
    grids (the band tables' nodes), then over the zenith nodes in the air mass.

    Returns
    -------
    ndarray, shape (n_bin,) or (n_zenith, n_bin)
    """
    cols = _log_factors_at(model, float(dt), float(rh), float(wind))[:, bin_columns(quantity)]
    # in the air mass for every axis: ln F of an absorber change grows like the path,
    # ~ 1 / cos θ, which cos θ (the band tables' sun and sky coordinate) bends
    return tb.interpolate_axis("view", BIN_GRID[BIN_AXIS[quantity]], cols.T, zenith_deg)


@lru_cache(maxsize=256)
def _log_cloud_at(model: str, cloud: int, dt: float, rh: float) -> np.ndarray:
    v = load_bins().log_cloud(model)[cloud - 1]
    out = tb.interp_nd(np.where(np.isfinite(v), v, -600.0),
                       [tb.GRID["state_temp_offset_K"], tb.GRID["cloud_rel_humidity"]],
                       [dt, rh])
    out.setflags(write=False)
    return out


def bin_log_cloud(model: str, cloud: int, dt: float, rh: float, zenith_deg):
    """ln of every bin's sky radiance under LOWTRAN cloud deck ``cloud`` (ICLD 1-5) at a
    state (ΔT [K], surface RH [%]) over its own-state clear sky, at zenith(s) [deg]: PCHIP
    over ΔT × the cloud humidity grid, then over the sky nodes in the air mass.

    Returns
    -------
    ndarray, shape (n_bin,) or (n_zenith, n_bin)
    """
    cols = _log_cloud_at(model, int(cloud), float(dt), float(rh))
    return tb.interpolate_axis("view", BIN_GRID["sky"], cols.T, zenith_deg)


def bin_errors() -> dict:
    """Measured errors of user responses through the bins against live LOWTRAN (file
    metadata): ``{model: {response: {quantity: max relative error}}}``."""
    return load_bins().meta.get("verification", {})
