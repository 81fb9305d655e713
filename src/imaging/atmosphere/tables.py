"""Embedded atmosphere tables (no Fortran needed) and their interpolation.

``data/atmosphere_tables.npz`` is written by ``scripts/make_atmosphere_tables.py`` from
live LOWTRAN 7 run from its card decks (:mod:`.lowtran_backend`): the six model
atmospheres with Navy maritime aerosol at 23 km, band values of every named band
(:data:`shipthermal.optics.responses.BAND_NAMES`).

Layout per model ``m`` (arrays ``"{m}__<name>"``; grids in ``"grid__<axis>"``,
:data:`GRID`):

* ``thermal_t`` (n_ΔT, n_RH, n_band, n_col) and ``thermal_w`` (n_layer, n_RH, n_wind, n_band,
  n_col),
  stored as int16 steps of the logarithm relative to the model's own state ``state_ref``
  (n_band, n_col) (:data:`STATE_LOG_STEP`, :meth:`AtmosphereTable.state`):
  transmittance and thermal path radiance at the view nodes, direct solar irradiance at
  the sun nodes and thermal sky radiance at the sky nodes (the columns,
  :func:`columns`), over surface temperature offset ΔT × surface relative humidity RH
  (LOWTRAN's default wind) and RH × wind at three offsets (``wind_layer_temp_offset_K``,
  −15, 0, +15 K: the wind's effect depends on the water vapour the aerosol competes
  with; ``thermal_w`` holds the wind's factor ``W(w) / W(w₀)`` times ``state_ref``, all
  that is used); the humidity nodes ``state_rh`` and the
  wind nodes ``state_wind`` of a model are the grid's plus the model's own;
* ``cloud`` (n_cloud, n_ΔT, n_RH_cloud, n_band, n_sky): sky radiance under each LOWTRAN
  cloud deck (stored as the state tables, relative to the clear sky of ``state_ref``);
* the model's own state: ``spectral_*`` (spectra on ``wavelength_um``), ``tau_planck`` /
  ``tau_sun`` / ``tau_sky`` / ``tau_sky_mean`` (view transmittance weighted with a
  blackbody, the direct sun, the sky from the specular direction, the hemispherical sky);
* scattered sunlight: ``ss_path`` (band, view, sun, azimuth), ``ss_sky`` and
  ``ss_sky_attenuated`` (band, sky zenith, sun, azimuth), ``ss_irradiance`` (band, sun),
  ``ss_tau_irradiance`` (band, view, sun), and ``ss_factor`` (RH, wind, band, path/sky).

Interpolation
-------------
Geometry: monotone cubic (PCHIP) in the air mass 1/cos θ (view) or cos θ (sun, sky, and the
zeniths of the scattered-sunlight tables), in degrees for the azimuth; the scattered-sunlight
tables are divided by LOWTRAN's own phase function (``ss_phase``) first. State: PCHIP of the
logarithms in ΔT, RH and wind, one axis after the other; a day's value is
``T(ΔT, RH) · W(ΔT, RH, wind) / W(ΔT, RH, wind₀)`` (wind₀ the model's default; W
interpolated over its three offset layers), exact on the grids (errors measured in the
file's ``interpolation_error``). Points outside a grid are clamped to its edge.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources

import numpy as np
from scipy.interpolate import PchipInterpolator

from shipthermal.optics.quadrature import gauss_legendre

__all__ = ["AtmosphereTable", "load_table", "interpolation_errors", "axis_coordinate",
           "interpolate_axis", "pchip", "TABLE_FILE", "GRID", "THERMAL_QUANTITIES", "FORMAT",
           "columns", "humidity_nodes", "wind_nodes", "hemispherical", "hemispherical_solar",
           "interp_nd", "pchip_point", "STATE_LOG_STEP", "STATE_ZERO", "decode_log_steps",
           "read_package_npz"]

TABLE_FILE = "atmosphere_tables.npz"
FORMAT = 2

GRID = {
    "view": np.array([0, 10, 20, 30, 40, 45, 50, 55, 60, 65, 70, 75, 80], dtype=float),
    "sun": np.array([0, 20, 40, 50, 60, 65, 70, 74, 78, 81, 84, 86, 87, 88, 89, 89.5, 90]),
    "sky": np.array([0, 10, 20, 30, 40, 45, 50, 55, 60, 65, 70, 75, 80, 83, 86, 88, 89, 89.9]),
    "planck_temp_K": np.arange(180.0, 421.0, 10.0),
    "state_temp_offset_K": np.array([-20, -15, -10, -5, 0, 5, 10, 15, 20], dtype=float),
    "state_rel_humidity": np.array([5, 20, 35, 50, 65, 75, 85, 90, 95, 98, 100], dtype=float),
    "state_wind": np.array([0.0, 2.3, 2.6, 3.0, 4.0, 6.0, 8.0, 10.0, 13.0, 16.0, 20.0]),
    "wind_layer_temp_offset_K": np.array([-15.0, 0.0, 15.0]),
    "cloud_rel_humidity": np.array([20, 50, 75, 90, 100], dtype=float),
    "ss_view": np.array([0, 15, 30, 45, 60, 70, 80], dtype=float),
    "ss_sky": np.array([0, 15, 30, 45, 60, 70, 80, 85, 89], dtype=float),
    "ss_sun": np.array([0, 20, 40, 55, 65, 75, 82, 86, 88, 89.5, 90]),
    "ss_azimuth": np.array([0, 5, 10, 20, 35, 50, 70, 90, 120, 150, 180], dtype=float),
    "ss_ref_path": np.array([30.0, 40.0, 90.0]),
    "ss_ref_sky": np.array([45.0, 40.0, 90.0]),
}
"""Table grids: zenith angles [deg], temperatures [K], offsets [K], scales [-], wind [m/s]."""

STATE_LOG_STEP = 4e-4
"""Step of the stored state tables: ``q = round(ln(v / v_own) / STATE_LOG_STEP)`` as int16
(v_own the model's own state, ``state_ref``): 0.02 % of the value at most (half a step).
The logarithm is clipped to ±13 (values below 2e-6 of the model's own, which only the
grid's far corners reach, e.g. four times the tropical water column at 80°, are stored
as that); :data:`STATE_ZERO` marks a zero (the sun at the horizon)."""
STATE_ZERO = -32768

THERMAL_QUANTITIES = ("transmittance", "path_radiance", "solar_irradiance", "sky_radiance",
                      "tau_planck300", "tau_sky")
"""Columns of the state tables: band-mean transmittance, thermal path radiance (view
nodes), direct solar irradiance (sun nodes), thermal sky radiance (sky nodes), and the view
transmittance weighted with a 300 K blackbody and with the sky from the same zenith (view
nodes)."""
_AXIS_OF = {"transmittance": "view", "path_radiance": "view", "solar_irradiance": "sun",
            "sky_radiance": "sky", "tau_planck300": "view", "tau_sky": "view"}


def humidity_nodes(own_rel_humidity: float) -> np.ndarray:
    """Humidity nodes of a model's state grids [%]: :data:`GRID`'s (LOWTRAN's Navy
    maritime humidity nodes 50, 85, 95, 98 among them: its aerosol is linear between them)
    and the model's own surface humidity, so that the model's own state is a node."""
    return np.unique(np.concatenate([GRID["state_rel_humidity"],
                                     [round(float(own_rel_humidity), 6)]]))


def wind_nodes(default_wind: float) -> np.ndarray:
    """Wind nodes of a model's water × wind grid [m s⁻¹]: :data:`GRID`'s and the model's
    default wind (the temperature × water grid's), so that the wind factor is 1 there."""
    return np.unique(np.concatenate([GRID["state_wind"], [float(default_wind)]]))


def columns(quantity: str) -> slice:
    """Columns of ``quantity`` in the ``thermal_*`` tables."""
    start = 0
    for q in THERMAL_QUANTITIES:
        n = GRID[_AXIS_OF[q]].size
        if q == quantity:
            return slice(start, start + n)
        start += n
    raise KeyError(quantity)


def axis_coordinate(axis: str, zenith_deg):
    """Interpolation coordinate of a zenith angle [deg] on a table axis.

    ``view`` → air mass 1/cos θ (transmittance ~ exp(−k m) is smooth in m);
    ``sun`` and ``sky`` → cos θ (defined down to the horizon).
    """
    mu = np.cos(np.radians(np.asarray(zenith_deg, dtype=float)))
    return 1.0 / mu if axis in ("view", "ss_view") else mu


def pchip(axis: str, nodes_deg, values) -> PchipInterpolator:
    """PCHIP interpolant of ``values`` (nodes along axis 0) in the axis coordinate."""
    x = axis_coordinate(axis, nodes_deg)
    order = np.argsort(x)
    return PchipInterpolator(x[order], np.asarray(values)[order], axis=0, extrapolate=False)


def interpolate_axis(axis: str, nodes_deg, values, zenith_deg):
    """PCHIP interpolation of ``values`` (nodes along axis 0) at ``zenith_deg`` [deg]
    (clamped to the nodes). Exact at the nodes; monotone between nodes wherever the node
    data are."""
    z = np.clip(zenith_deg, np.min(nodes_deg), np.max(nodes_deg))
    xq = axis_coordinate(axis, z)
    if np.ndim(xq) == 0:
        x = axis_coordinate(axis, nodes_deg)
        order = np.argsort(x)
        return pchip_point(x[order], np.asarray(values)[order], float(xq))
    return pchip(axis, nodes_deg, values)(xq)


def _pchip_slope(x, y, i):
    """PCHIP (Fritsch–Carlson, as scipy's) derivative at node ``i`` of ``y`` (axis 0)."""
    n = x.size
    if n == 2:
        return (y[1] - y[0]) / (x[1] - x[0])
    if 0 < i < n - 1:
        h0, h1 = x[i] - x[i - 1], x[i + 1] - x[i]
        m0, m1 = (y[i] - y[i - 1]) / h0, (y[i + 1] - y[i]) / h1
        w1, w2 = 2.0 * h1 + h0, h1 + 2.0 * h0
        same = (np.sign(m0) == np.sign(m1)) & (m0 != 0.0) & (m1 != 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            d = (w1 + w2) / (w1 / np.where(same, m0, 1.0) + w2 / np.where(same, m1, 1.0))
        return np.where(same, d, 0.0)
    if i == 0:
        h0, h1 = x[1] - x[0], x[2] - x[1]
        m0, m1 = (y[1] - y[0]) / h0, (y[2] - y[1]) / h1
    else:
        h0, h1 = x[-1] - x[-2], x[-2] - x[-3]
        m0, m1 = (y[-1] - y[-2]) / h0, (y[-2] - y[-3]) / h1
    d = ((2.0 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
    d = np.where(np.sign(d) != np.sign(m0), 0.0, d)
    return np.where((np.sign(m0) != np.sign(m1)) & (np.abs(d) > 3.0 * np.abs(m0)), 3.0 * m0, d)


def pchip_point(x, y, xq: float):
    """scipy's PCHIP of ``y`` (nodes along axis 0, ``x`` ascending) at one point ``xq``,
    from the two bracketing nodes only (the cost of a few array operations instead of an
    interpolant's construction; same numbers)."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    k = int(np.clip(np.searchsorted(x, xq, side="right") - 1, 0, x.size - 2))
    h = x[k + 1] - x[k]
    t = (xq - x[k]) / h
    d0, d1 = _pchip_slope(x, y, k), _pchip_slope(x, y, k + 1)
    h00, h10 = (1 + 2 * t) * (1 - t) ** 2, t * (1 - t) ** 2
    h01, h11 = t * t * (3 - 2 * t), t * t * (t - 1)
    return h00 * y[k] + h10 * h * d0 + h01 * y[k + 1] + h11 * h * d1


def interp_nd(values, axes: list, points: list):
    """Interpolate ``values`` along its leading ``len(axes)`` axes at one point (PCHIP,
    one axis after the other; each coordinate clamped to its nodes).

    ``axes``: node coordinates per axis (ascending); ``points``: the point's coordinates.
    Returns the trailing block.
    """
    out = np.asarray(values, dtype=float)
    for nodes, x in zip(axes, points):
        nodes = np.asarray(nodes, dtype=float)
        xq = float(np.clip(x, nodes[0], nodes[-1]))
        k = int(np.searchsorted(nodes, xq))
        if k < nodes.size and nodes[k] == xq:
            out = out[k]
        else:
            out = pchip_point(nodes, out, xq)
    return out


def hemispherical(sky_nodes_deg, radiance, n_nodes: int = 16):
    """Hemispherical irradiance ``2π ∫₀¹ L(μ) μ dμ`` of an azimuth-independent sky given at
    zenith nodes (axis 0 of ``radiance``): PCHIP in μ = cos θ, Gauss–Legendre in μ."""
    x, w = gauss_legendre(int(n_nodes))
    mu, w = 0.5 * (x + 1.0), 0.5 * w
    lq = interpolate_axis("sky", sky_nodes_deg, radiance, np.degrees(np.arccos(mu)))
    return 2.0 * np.pi * np.tensordot(w * mu, lq, axes=(0, 0))


def hemispherical_solar(sky_nodes_deg, azimuth_nodes_deg, radiance, n_mu: int = 16,
                        n_phi: int = 181):
    """Hemispherical irradiance ``∫∫ L μ dΩ`` of a sky symmetric about the sun's azimuth,
    given on (zenith, azimuth from the sun 0-180°, ...) nodes: PCHIP in μ then azimuth,
    Gauss–Legendre in μ, trapezoid on ``n_phi`` points over 0-180° (twice for the other
    half)."""
    x, w = gauss_legendre(int(n_mu))
    mu, w = 0.5 * (x + 1.0), 0.5 * w
    lq = interpolate_axis("sky", sky_nodes_deg, radiance, np.degrees(np.arccos(mu)))
    phi = np.linspace(0.0, 180.0, n_phi)
    lp = PchipInterpolator(azimuth_nodes_deg, lq, axis=1)(phi)     # (n_mu, n_phi, ...)
    inner = np.trapezoid(lp, np.radians(phi), axis=1) * 2.0
    return np.tensordot(w * mu, inner, axes=(0, 0))


@dataclass(frozen=True)
class AtmosphereTable:
    """Contents of the embedded table file (arrays read-only)."""

    arrays: dict
    meta: dict

    def get(self, model: str, name: str) -> np.ndarray:
        return self.arrays[f"{model}__{name}"]

    def grid(self, axis: str) -> np.ndarray:
        return self.arrays[f"grid__{axis}"]

    @property
    def wavelength_um(self) -> np.ndarray:
        return self.arrays["wavelength_um"]

    @property
    def bands(self) -> tuple:
        return tuple(self.meta["bands"])

    def band_index(self, band: str) -> int:
        return self.bands.index(band)

    def nodes(self, axis: str) -> np.ndarray:
        return self.grid(axis)

    def state_log(self, model: str, key: str) -> np.ndarray:
        """Natural log of a state table (``thermal_t``, ``thermal_w``, ``cloud``) decoded from
        its int16 steps (:data:`STATE_LOG_STEP`); zeros as −inf."""
        q = self.arrays[f"{model}__{key}_q"]
        ref = self.arrays[f"{model}__state_ref"]
        if key == "cloud":
            ref = ref[:, columns("sky_radiance")]
        with np.errstate(divide="ignore"):
            return decode_log_steps(q, np.log(ref))

    def state(self, model: str, key: str) -> np.ndarray:
        """A state table's values (see :meth:`state_log`)."""
        return np.exp(self.state_log(model, key))


def decode_log_steps(q, log_ref=0.0) -> np.ndarray:
    """Natural log of values stored as int16 steps (:data:`STATE_LOG_STEP`) above
    ``log_ref``; :data:`STATE_ZERO` (a zero) as −inf."""
    return np.where(q == STATE_ZERO, -np.inf, log_ref + q * STATE_LOG_STEP)


def read_package_npz(filename: str) -> tuple[dict, dict]:
    """``(arrays, meta)`` of an npz in ``imaging/atmosphere/data``: arrays read-only, the
    ``*_q`` step tables as int16, the rest as float; ``meta`` from ``meta_json``."""
    ref = resources.files("imaging.atmosphere") / "data" / filename
    with resources.as_file(ref) as path, np.load(path) as npz:
        arrays = {}
        for k in npz.files:
            if k == "meta_json":
                continue
            a = np.asarray(npz[k], dtype=np.int16 if k.endswith("_q") else float)
            a.setflags(write=False)
            arrays[k] = a
        meta = json.loads(str(npz["meta_json"]))
    return arrays, meta


@lru_cache(maxsize=1)  # immutable package data: read the file once per process
def load_table() -> AtmosphereTable:
    """Load ``data/atmosphere_tables.npz`` shipped with the package."""
    arrays, meta = read_package_npz(TABLE_FILE)
    return AtmosphereTable(arrays=arrays, meta=meta)


def interpolation_errors() -> dict:
    """Stated interpolation errors of the tables against live LOWTRAN (file metadata).

    ``{model: {"geometry" | "state" | "cloud" | "scattered": {band: {quantity: {"abs":
    …, "rel": …, "unit": …}}}}}``; ``abs`` in the quantity's unit, ``rel`` as a fraction of
    the live value.
    """
    return load_table().meta.get("interpolation_error", {})
