"""Ordinary Kriging of hourly met grids onto the scene grid (paper eqs. 9–12), with pykrige.

For each hour the experimental semivariogram (eq. 11) of the valid grid cells is fitted by
pykrige (least squares over ``nlags`` lag bins) and the OK system (eq. 10) is solved
independently (eq. 12). Fitted parameters and pykrige's leave-one-out statistics (Q1, Q2, cR)
are reported per hour.

Speed: the met field varies on the met grid scale (~6 km for CLDAS' 0.0625 deg), so kriging
every ``coarsen``-th scene pixel (150 m at the default 5) and interpolating bilinearly to
30 m changes the field by far less than the kriging error itself (the test suite measures the
difference). ``coarsen=1`` krige every pixel.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pykrige.ok import OrdinaryKriging
from rasterio.warp import transform as warp_transform

from shipthermal.errors import InputError, require

from .landsat import SceneGrid

__all__ = ["VariogramFit", "met_points_on_grid", "krige_points", "krige_hourly", "linear_weights"]

VARIOGRAM_MODELS = ("spherical", "exponential", "gaussian", "linear", "power")


@dataclass(frozen=True)
class VariogramFit:
    """Fitted variogram of one time step.

    Attributes
    ----------
    model : str
    parameters : dict[str, float]
        pykrige's fitted parameters (``psill`` [K^2], ``range`` [m], ``nugget`` [K^2] for the
        bounded models).
    n_points : int
        Valid data points used.
    q1, q2, cr : float
        Leave-one-out statistics: mean standardised error (ideal 0), mean squared
        standardised error (ideal 1), and the geometric mean of the kriging variances [K^2].
    """

    model: str
    parameters: dict
    n_points: int
    q1: float
    q2: float
    cr: float


def _param_dict(model: str, p) -> dict:
    p = [float(v) for v in p]
    if model == "linear":
        return {"slope": p[0], "nugget": p[1]}
    if model == "power":
        return {"scale": p[0], "exponent": p[1], "nugget": p[2]}
    return {"psill": p[0], "range": p[1], "nugget": p[2]}


def met_points_on_grid(lat, lon, grid: SceneGrid):
    """Met grid cell centres in the scene CRS [m] (rasterio/PROJ), as flattened (x, y)."""
    lon2, lat2 = np.meshgrid(lon, lat)
    xs, ys = warp_transform("EPSG:4326", grid.crs, lon2.ravel().tolist(), lat2.ravel().tolist())
    return np.asarray(xs), np.asarray(ys)


def _build_ok(x, y, z, model, variogram_parameters, nlags):
    if model not in VARIOGRAM_MODELS:
        raise InputError("variogram_model", model, f"must be one of {VARIOGRAM_MODELS}")
    return OrdinaryKriging(x, y, z, variogram_model=model, variogram_parameters=variogram_parameters,
                           nlags=nlags, enable_statistics=True)


def krige_points(x, y, z, xq, yq, model: str = "spherical", variogram_parameters=None, nlags: int = 6,
                 chunk: int = 200_000):
    """Ordinary Kriging of scattered data at query points.

    Parameters
    ----------
    x, y : array_like
        Data coordinates [m].
    z : array_like
        Data values [K].
    xq, yq : array_like
        Query coordinates [m].
    model : str
        pykrige variogram model.
    variogram_parameters : dict, optional
        Fixed parameters; ``None`` fits them (eq. 11 + least squares).
    nlags : int
        Lag bins of the experimental variogram.

    Returns
    -------
    values : ndarray
        Estimates at the query points [K].
    fit : VariogramFit
    """
    ok = _build_ok(np.asarray(x, float), np.asarray(y, float), np.asarray(z, float), model,
                   variogram_parameters, nlags)
    xq = np.ravel(np.asarray(xq, float))
    yq = np.ravel(np.asarray(yq, float))
    out = np.empty(xq.size)
    # pykrige's vectorised backend holds an (n_query x n_data) matrix: chunk to bound memory.
    for s in range(0, xq.size, chunk):
        zz, _ = ok.execute("points", xq[s:s + chunk], yq[s:s + chunk], backend="vectorized")
        out[s:s + chunk] = np.asarray(zz)
    fit = VariogramFit(model, _param_dict(model, ok.variogram_model_parameters), int(np.size(z)),
                       float(ok.Q1), float(ok.Q2), float(ok.cR))
    return out, fit


def linear_weights(n_full: int, nodes: np.ndarray) -> np.ndarray:
    """Dense (n_full, n_nodes) matrix of 1-D linear interpolation from ``nodes`` (sorted pixel
    indices including 0 and n_full-1) to every index 0..n_full-1."""
    w = np.zeros((n_full, nodes.size))
    pos = np.arange(n_full, dtype=float)
    k = np.clip(np.searchsorted(nodes, pos, side="right") - 1, 0, nodes.size - 2)
    t = (pos - nodes[k]) / (nodes[k + 1] - nodes[k])
    w[np.arange(n_full), k] = 1.0 - t
    w[np.arange(n_full), k + 1] = t
    return w


def _nodes(n: int, step: int) -> np.ndarray:
    return np.unique(np.r_[np.arange(0, n, step), n - 1])


def krige_hourly(x, y, values, grid: SceneGrid, model: str = "spherical", coarsen: int = 5,
                 nlags: int = 6, min_points: int = 6, progress=None):
    """Krige each time step of a met grid onto the scene grid (eq. 12).

    Parameters
    ----------
    x, y : ndarray (n_points,)
        Met cell centres in the scene CRS [m].
    values : ndarray (n_times, n_points)
        Temperature [K]; NaN cells are left out of that step.
    grid : SceneGrid
    model : str
        Variogram model fitted per step.
    coarsen : int
        Krige every ``coarsen``-th pixel, then bilinear to full resolution (1 = every pixel).
    min_points : int
        Fewer valid points in a step raise :class:`InputError`.

    Returns
    -------
    fields : ndarray float32 (n_times, rows, cols)
        Baseline temperature T0 [K].
    fits : list[VariogramFit]
    """
    require(int(coarsen) >= 1, "krige_coarsen", coarsen, "must be an integer >= 1")
    rows_n = _nodes(grid.shape[0], int(coarsen))
    cols_n = _nodes(grid.shape[1], int(coarsen))
    xc = grid.transform.c + (cols_n + 0.5) * grid.transform.a
    yc = grid.transform.f + (rows_n + 0.5) * grid.transform.e
    xq, yq = np.meshgrid(xc, yc)
    wr = linear_weights(grid.shape[0], rows_n)
    wc = linear_weights(grid.shape[1], cols_n)
    fields = np.empty((values.shape[0], *grid.shape), dtype=np.float32)
    fits = []
    steps = range(values.shape[0]) if progress is None else progress(range(values.shape[0]))
    for k in steps:
        ok = np.isfinite(values[k])
        n = int(ok.sum())
        if n < min_points:
            raise InputError(f"met.temperature[time {k}].valid_points", n,
                             f"need at least {min_points} valid cells to fit a variogram")
        est, fit = krige_points(x[ok], y[ok], values[k][ok], xq.ravel(), yq.ravel(), model, None, nlags)
        coarse = est.reshape(xq.shape)
        fields[k] = (wr @ coarse @ wc.T) if coarsen > 1 else coarse
        fits.append(fit)
    return fields, fits
