"""Embedded atmosphere tables (no Fortran needed) and their interpolation.

``data/atmosphere_tables.npz`` is written by ``scripts/make_atmosphere_tables.py`` from
live LOWTRAN 7 + Navy maritime aerosol (23 km) for mid-latitude summer (model 2) and
winter (model 3). The three geometric dependences are separable, so the tables are
1-D per quantity:

* view zenith θv (0–80°): transmittance and path radiance, interpolated with a
  monotone cubic (PCHIP) in the air mass 1/cos θv;
* sun zenith θs (0–90°): direct solar irradiance, PCHIP in cos θs (0 at 90°);
* sky zenith θ (0–89.9°): thermal sky radiance, PCHIP in cos θ;
* hemispherical sky irradiance: one value (no interpolation).

Each quantity is stored spectrally (LOWTRAN's 5 cm⁻¹ grid, 2.9–14.5 µm) and
band-integrated for the default rectangular 3–5 and 8–14 µm bands. The maximum
interpolation errors, measured by the script at off-grid points (1/4, 1/2 and 3/4 of every
interval) against live LOWTRAN, are stored in the file and exposed as
:func:`interpolation_errors` (band values: transmittance ≤ 0.0015 absolute, path and sky
radiance ≤ 0.3 %, direct solar ≤ 1.1 % relative). The file also records the largest
deviation of the tables from LOWTRAN 7 run with its own Navy maritime aerosol
(``meta["aerosol_reference_check"]``, ≤ 0.17 %).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources

import numpy as np
from scipy.interpolate import PchipInterpolator

__all__ = ["AtmosphereTable", "load_table", "interpolation_errors", "axis_coordinate",
           "interpolate_axis", "pchip", "table_lookup", "TABLE_FILE"]

TABLE_FILE = "atmosphere_tables.npz"


def axis_coordinate(axis: str, zenith_deg):
    """Interpolation coordinate of a zenith angle [deg] on a table axis.

    ``view`` → air mass 1/cos θ (transmittance ~ exp(−k m) is smooth in m);
    ``sun`` and ``sky`` → cos θ (defined down to the horizon).
    """
    mu = np.cos(np.radians(np.asarray(zenith_deg, dtype=float)))
    return 1.0 / mu if axis == "view" else mu


def pchip(axis: str, nodes_deg, values) -> PchipInterpolator:
    """PCHIP interpolant of ``values`` (nodes along axis 0) in the axis coordinate."""
    x = axis_coordinate(axis, nodes_deg)
    order = np.argsort(x)
    return PchipInterpolator(x[order], np.asarray(values)[order], axis=0, extrapolate=False)


def interpolate_axis(axis: str, nodes_deg, values, zenith_deg):
    """PCHIP interpolation of ``values`` (nodes along axis 0) at ``zenith_deg``.

    Exact at the nodes; monotone between nodes wherever the node data are.
    """
    xq = axis_coordinate(axis, np.clip(zenith_deg, np.min(nodes_deg), np.max(nodes_deg)))
    return pchip(axis, nodes_deg, values)(xq)


@lru_cache(maxsize=256)  # interpolants of the immutable embedded table, built once
def _table_pchip(axis: str, key: str) -> PchipInterpolator:
    t = load_table()
    return pchip(axis, t.nodes(axis), t.arrays[key])


def table_lookup(axis: str, season: str, name: str, band: str | None, zenith_deg):
    """Interpolate an embedded-table quantity at zenith angle(s) [deg] (see
    :func:`interpolate_axis`)."""
    key = f"{season}__{name}" if band is None else f"{season}__{band}__{name}"
    nodes = load_table().nodes(axis)
    xq = axis_coordinate(axis, np.clip(zenith_deg, nodes.min(), nodes.max()))
    return _table_pchip(axis, key)(xq)


@dataclass(frozen=True)
class AtmosphereTable:
    """Contents of the embedded table file (arrays read-only)."""

    arrays: dict
    meta: dict

    def get(self, season: str, name: str, band: str | None = None) -> np.ndarray:
        key = f"{season}__{name}" if band is None else f"{season}__{band}__{name}"
        return self.arrays[key]

    @property
    def wavelength_um(self) -> np.ndarray:
        return self.arrays["wavelength_um"]

    def nodes(self, axis: str) -> np.ndarray:
        return self.arrays[f"{axis}_zenith_deg"]


@lru_cache(maxsize=1)  # immutable package data: read the file once per process
def load_table() -> AtmosphereTable:
    """Load ``data/atmosphere_tables.npz`` shipped with the package."""
    ref = resources.files("imaging.atmosphere") / "data" / TABLE_FILE
    with resources.as_file(ref) as path, np.load(path) as npz:
        arrays = {}
        for k in npz.files:
            if k == "meta_json":
                continue
            a = np.asarray(npz[k], dtype=float)
            a.setflags(write=False)
            arrays[k] = a
        meta = json.loads(str(npz["meta_json"]))
    return AtmosphereTable(arrays=arrays, meta=meta)


def interpolation_errors() -> dict:
    """Stated maximum interpolation errors of the tables (from the file's metadata).

    ``{season: {band: {quantity: {"abs": …, "rel": …, "unit": …}}}}``; ``abs`` in the
    quantity's unit, ``rel`` as a fraction of the live value.
    """
    return load_table().meta["interpolation_error"]
