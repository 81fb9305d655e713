"""Ordinary Kriging of hourly met grids onto the scene grid (paper eqs. 9–12), with pykrige.

For each hour the experimental semivariogram (eq. 11) of the valid grid cells is fitted by
pykrige (least squares over ``nlags`` lag bins) and the OK system (eq. 10) is solved
independently (eq. 12). Fitted parameters and pykrige's leave-one-out statistics (Q1, Q2, cR)
are reported per hour when asked for (``statistics=True``: pykrige computes them by kriging
every point from the others, O(n^4); off by default).

Fast path (:func:`krige_hourly`, default ``method="dual"``): the variogram is fitted by pykrige
(same experimental variogram, same bounded least squares), then the OK system of eq. 10 is
solved once per hour in its dual form, ``[Gamma 1; 1' 0] [w; mu] = [z; 0]``, and the estimate
at any point is ``z*(x0) = mu - sum_i gamma(|x0 - x_i|) w_i`` — algebraically the same
estimate as pykrige's per-point solve (``b' A^-1 [z; 0]`` with symmetric ``A``), in
O(n_query x n) work; all hours are evaluated in one parallel numba pass over the query
points, with distances computed once. ``benchmarks/bench_kriging.py`` measures the speed-up
and the difference from pykrige's full solution.

Fitted ranges, sills or nuggets that end on a bound of pykrige's fit (range = the largest lag:
the field keeps rising over the whole window, i.e. a trend larger than the data) are flagged
per hour (:attr:`VariogramFit.at_bound`).

Speed: the met field varies on the met grid scale (~6 km for CLDAS' 0.0625 deg), so kriging
every ``coarsen``-th scene pixel (150 m at the default 5) and interpolating bilinearly to
30 m changes the field by far less than the kriging error itself (the test suite measures the
difference). ``coarsen=1`` krige every pixel.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numba
from pykrige.ok import OrdinaryKriging
from scipy.linalg import solve as dense_solve
from rasterio.warp import transform as warp_transform

from shipthermal.errors import InputError, require

from ..parameters import VARIOGRAM_MODELS
from .landsat.grid import SceneGrid

__all__ = ["VariogramFit", "met_points_on_grid", "krige_points", "krige_hourly", "linear_weights",
           "fit_variogram", "krige_dual", "variogram_values"]


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
        standardised error (ideal 1), and the geometric mean of the kriging variances [K^2];
        NaN unless computed (``statistics=True``).
    at_bound : tuple[str, ...]
        Parameters that ended on a bound of the fit, e.g. ``("range=max lag",)``.
    max_lag : float
        Largest lag of the experimental variogram [m] (the upper bound of the range).
    """

    model: str
    parameters: dict
    n_points: int
    q1: float
    q2: float
    cr: float
    at_bound: tuple = ()
    max_lag: float = float("nan")


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


def _build_ok(x, y, z, model, variogram_parameters, nlags, statistics=True):
    if model not in VARIOGRAM_MODELS:
        raise InputError("variogram_model", model, f"must be one of {VARIOGRAM_MODELS}")
    return OrdinaryKriging(x, y, z, variogram_model=model, variogram_parameters=variogram_parameters,
                           nlags=nlags, enable_statistics=statistics)


def _bounds_hit(model: str, params, lags, semivariance, rtol: float = 1e-4) -> tuple:
    """Parameters of a pykrige fit that sit on the bounds of its least squares
    (pykrige.core._calculate_variogram_model)."""
    lags = np.asarray(lags, float)
    sv = np.asarray(semivariance, float)
    if lags.size == 0 or not np.isfinite(sv).any():
        return ()
    smax, lmax = float(np.nanmax(sv)), float(np.nanmax(lags))
    p = [float(v) for v in params]
    names = {"linear": ("slope", "nugget"), "power": ("scale", "exponent", "nugget")}.get(
        model, ("psill", "range", "nugget"))
    upper = {"linear": (np.inf, smax), "power": (np.inf, 1.999, smax)}.get(model, (10.0 * smax, lmax, smax))
    lower = {"power": (0.0, 0.001, 0.0)}.get(model, (0.0,) * len(names))
    label = {lmax: "max lag", smax: "max semivariance", 10.0 * smax: "10 x max semivariance"}
    hits = []
    for name, v, lo, hi in zip(names, p, lower, upper):
        if np.isfinite(hi) and v >= hi * (1 - rtol):
            hits.append(f"{name}={label.get(hi, 'upper bound')}")
        elif name in ("range", "psill") and v <= lo + rtol * max(abs(hi) if np.isfinite(hi) else 1.0, 1e-12):
            hits.append(f"{name}=0")
    return tuple(hits)


def fit_variogram(x, y, z, model: str = "spherical", nlags: int = 6, statistics: bool = False):
    """Fit the variogram of one time step with pykrige (eq. 11 + bounded least squares).

    Parameters
    ----------
    x, y : array_like
        Data coordinates [m].
    z : array_like
        Data values [K].
    model : str
        pykrige variogram model.
    nlags : int
        Lag bins of the experimental variogram.
    statistics : bool
        Also compute pykrige's leave-one-out statistics (costly for many points).

    Returns
    -------
    VariogramFit
    """
    ok = _build_ok(np.asarray(x, float), np.asarray(y, float), np.asarray(z, float), model, None, nlags,
                   statistics)
    p = ok.variogram_model_parameters
    nan = float("nan")
    return VariogramFit(model, _param_dict(model, p), int(np.size(z)),
                        float(ok.Q1) if statistics else nan, float(ok.Q2) if statistics else nan,
                        float(ok.cR) if statistics else nan,
                        _bounds_hit(model, p, ok.lags, ok.semivariance), float(np.max(ok.lags)))


_MODEL_CODE = {"linear": 0, "power": 1, "gaussian": 2, "exponential": 3, "spherical": 4}


def _param_vector(fit_or_model, parameters=None) -> np.ndarray:
    """(a, b, nugget) of a model: linear (slope, -, nugget), power (scale, exponent, nugget),
    bounded models (psill, range, nugget)."""
    model = fit_or_model.model if isinstance(fit_or_model, VariogramFit) else fit_or_model
    p = fit_or_model.parameters if isinstance(fit_or_model, VariogramFit) else parameters
    if model == "linear":
        return np.array([p["slope"], 0.0, p["nugget"]])
    if model == "power":
        return np.array([p["scale"], p["exponent"], p["nugget"]])
    return np.array([p["psill"], p["range"], p["nugget"]])


@numba.njit(cache=True, fastmath=False, inline="always")
def _gamma(code, a, b, nugget, d):
    # pykrige.variogram_models, term by term
    if code == 0:
        return a * d + nugget
    if code == 1:
        return a * d ** b + nugget
    if code == 2:
        r = b * 4.0 / 7.0
        return a * (1.0 - np.exp(-(d * d) / (r * r))) + nugget
    if code == 3:
        return a * (1.0 - np.exp(-d / (b / 3.0))) + nugget
    if d <= b:
        return a * ((3.0 * d) / (2.0 * b) - (d * d * d) / (2.0 * b * b * b)) + nugget
    return a + nugget


def variogram_values(model: str, params, d) -> np.ndarray:
    """Semivariance of a pykrige model at distances ``d`` [K^2] (``params`` as
    :attr:`VariogramFit.parameters`)."""
    v = _param_vector(model, params)
    d = np.asarray(d, dtype=np.float64)
    return _gamma_array(_MODEL_CODE[model], v[0], v[1], v[2], d.ravel()).reshape(d.shape)


@numba.njit(cache=True)
def _gamma_array(code, a, b, nugget, d):
    out = np.empty(d.size)
    for i in range(d.size):
        out[i] = _gamma(code, a, b, nugget, d[i])
    return out


_EPS = 1e-10
"""Distance below which a query coincides with a data point (pykrige's ``eps``) [m]."""


def _dual_solution(x, y, z, code, a, b, nugget):
    """``[w; mu]`` of the dual OK system, with pykrige's matrix (zero diagonal)."""
    n = x.size
    d = np.hypot(x[:, None] - x[None, :], y[:, None] - y[None, :])
    A = np.zeros((n + 1, n + 1))
    A[:n, :n] = -_gamma_array(code, a, b, nugget, d.ravel()).reshape(n, n)
    A[np.diag_indices(n)] = 0.0
    A[n, :n] = 1.0
    A[:n, n] = 1.0
    rhs = np.zeros(n + 1)
    rhs[:n] = z
    # LU (getrf) measured 2x faster than the symmetric-indefinite solver (sytrf) here
    return dense_solve(A, rhs, assume_a="gen", check_finite=False)


@numba.njit(parallel=True, cache=True)
def _eval_dual(xd, yd, wt, mu, codes, params, xq, yq, out):
    """out[h, q] = mu[h] + sum_i b_i(q) wt[i, h], b_i = -gamma_h(d_iq) (0 where d_iq <= eps):
    any model per hour."""
    n, nh = wt.shape
    for q in numba.prange(xq.size):
        acc = mu.copy()
        for i in range(n):
            dx = xq[q] - xd[i]
            dy = yq[q] - yd[i]
            d = np.sqrt(dx * dx + dy * dy)
            if d <= 1e-10:
                continue
            for h in range(nh):
                acc[h] -= _gamma(codes[h], params[h, 0], params[h, 1], params[h, 2], d) * wt[i, h]
        out[:, q] = acc


@numba.njit(parallel=True, cache=True)
def _eval_dual_spherical(xd, yd, wt, mu, params, xq, yq, out):
    """:func:`_eval_dual` for the spherical model in every hour (the default), without the
    per-pair model dispatch: ~3x faster."""
    n, nh = wt.shape
    inv_r = 1.0 / params[:, 1]
    sill = params[:, 0] + params[:, 2]
    for q in numba.prange(xq.size):
        acc = mu.copy()
        for i in range(n):
            dx = xq[q] - xd[i]
            dy = yq[q] - yd[i]
            d = np.sqrt(dx * dx + dy * dy)
            if d <= 1e-10:
                continue
            for h in range(nh):
                t = d * inv_r[h]
                if t <= 1.0:
                    g = params[h, 2] + params[h, 0] * (1.5 * t - 0.5 * t * t * t)
                else:
                    g = sill[h]
                acc[h] -= g * wt[i, h]
        out[:, q] = acc


def krige_dual(x, y, values, fits, xq, yq):
    """Ordinary Kriging of several time steps at query points, dual form (module docstring).

    Parameters
    ----------
    x, y : ndarray (n,)
        Data coordinates [m].
    values : ndarray (n_times, n)
        Data [K]; NaN cells are left out of their step.
    fits : list[VariogramFit]
        Variogram per step.
    xq, yq : ndarray
        Query coordinates [m].

    Returns
    -------
    ndarray (n_times, n_query)
        Estimates [K]; identical to pykrige's ``execute`` up to round-off.
    """
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    values = np.atleast_2d(np.asarray(values, float))
    nt, n = values.shape
    w = np.zeros((nt, n))
    mu = np.zeros(nt)
    codes = np.empty(nt, np.int64)
    params = np.empty((nt, 3))
    for k, fit in enumerate(fits):
        ok = np.isfinite(values[k])
        codes[k] = _MODEL_CODE[fit.model]
        params[k] = _param_vector(fit)
        sol = _dual_solution(x[ok], y[ok], values[k][ok], codes[k], *params[k])
        w[k, ok] = sol[:-1]
        mu[k] = sol[-1]
    xq = np.ascontiguousarray(np.ravel(xq), dtype=np.float64)
    yq = np.ascontiguousarray(np.ravel(yq), dtype=np.float64)
    out = np.empty((nt, xq.size))
    wt = np.ascontiguousarray(w.T)
    if np.all(codes == _MODEL_CODE["spherical"]):
        _eval_dual_spherical(x, y, wt, mu, params, xq, yq, out)
    else:
        _eval_dual(x, y, wt, mu, codes, params, xq, yq, out)
    return out


def krige_points(x, y, z, xq, yq, model: str = "spherical", variogram_parameters=None, nlags: int = 6,
                 chunk: int = 200_000, statistics: bool = True):
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
    statistics : bool
        Compute pykrige's leave-one-out statistics.

    Returns
    -------
    values : ndarray
        Estimates at the query points [K].
    fit : VariogramFit
    """
    ok = _build_ok(np.asarray(x, float), np.asarray(y, float), np.asarray(z, float), model,
                   variogram_parameters, nlags, statistics)
    xq = np.ravel(np.asarray(xq, float))
    yq = np.ravel(np.asarray(yq, float))
    out = np.empty(xq.size)
    # pykrige's vectorised backend holds an (n_query x n_data) matrix: chunk to bound memory.
    for s in range(0, xq.size, chunk):
        zz, _ = ok.execute("points", xq[s:s + chunk], yq[s:s + chunk], backend="vectorized")
        out[s:s + chunk] = np.asarray(zz)
    p = ok.variogram_model_parameters
    nan = float("nan")
    fit = VariogramFit(model, _param_dict(model, p), int(np.size(z)), float(ok.Q1) if statistics else nan,
                       float(ok.Q2) if statistics else nan, float(ok.cR) if statistics else nan,
                       _bounds_hit(model, p, ok.lags, ok.semivariance) if variogram_parameters is None else (),
                       float(np.max(ok.lags)))
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
                 nlags: int = 6, min_points: int = 6, progress=None, statistics: bool = False,
                 method: str = "dual"):
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
    progress : callable, optional
        Wraps the iterable of time steps (a progress bar over the variogram fits).
    statistics : bool
        pykrige's leave-one-out statistics per step (slow for many points; off by default).
    method : {"dual", "pykrige"}
        Dual-form evaluation (fast, default) or pykrige's ``execute`` per step (reference).

    Returns
    -------
    fields : ndarray float32 (n_times, rows, cols)
        Baseline temperature T0 [K].
    fits : list[VariogramFit]
    """
    require(int(coarsen) >= 1, "krige_coarsen", coarsen, "must be an integer >= 1")
    require(method in ("dual", "pykrige"), "krige_method", method, "must be 'dual' or 'pykrige'")
    rows_n = _nodes(grid.shape[0], int(coarsen))
    cols_n = _nodes(grid.shape[1], int(coarsen))
    xc = grid.transform.c + (cols_n + 0.5) * grid.transform.a
    yc = grid.transform.f + (rows_n + 0.5) * grid.transform.e
    xq, yq = np.meshgrid(xc, yc)
    values = np.asarray(values, float)
    fits = []
    steps = range(values.shape[0]) if progress is None else progress(range(values.shape[0]))
    coarse = np.empty((values.shape[0], xq.size))
    for k in steps:
        ok = np.isfinite(values[k])
        n = int(ok.sum())
        if n < min_points:
            raise InputError(f"met.temperature[time {k}].valid_points", n,
                             f"need at least {min_points} valid cells to fit a variogram")
        if method == "pykrige":
            coarse[k], fit = krige_points(x[ok], y[ok], values[k][ok], xq.ravel(), yq.ravel(), model, None,
                                          nlags, statistics=statistics)
        else:
            fit = fit_variogram(x[ok], y[ok], values[k][ok], model, nlags, statistics)
        fits.append(fit)
    if method == "dual":
        coarse = krige_dual(x, y, values, fits, xq, yq)
    fields = np.empty((values.shape[0], *grid.shape), dtype=np.float32)
    if coarsen > 1:
        wr = linear_weights(grid.shape[0], rows_n)
        wc = linear_weights(grid.shape[1], cols_n)
        for k in range(values.shape[0]):
            fields[k] = wr @ coarse[k].reshape(xq.shape) @ wc.T
    else:
        fields[:] = coarse.reshape(values.shape[0], *grid.shape)
    return fields, fits
