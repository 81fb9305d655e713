"""DEM reading onto the scene grid, slope and aspect (paper eqs. 13–14), eq. 15 regression.

Conventions: map x points east, y north; rows of a north-up raster run southward, so
``dZ/dy = -dZ/drow / pixel``. Gradients use Horn's (1981) 3x3 weighted differences (the
ArcGIS/GDAL default the paper's ArcGIS work used), which are exact for any plane.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np
import rasterio
from rasterio.warp import Resampling, reproject

from shipthermal.errors import InputError, require

from .landsat.grid import SceneGrid

__all__ = [
    "DemOnGrid",
    "load_dem",
    "read_dem",
    "horn_gradient",
    "slope_aspect",
    "southness",
    "TerrainFit",
    "fit_terrain_regression",
    "terrain_term",
]


DEM_FILL_MAX_DISTANCE_PX = 100
"""Largest distance [source pixels] over which :func:`load_dem` fills a void (GDAL
``FillNodata``'s search radius); SRTM voids in steep terrain span up to a few kilometres
(~100 pixels at 3 arc-seconds); larger holes stay voids and are reported."""


@dataclass(frozen=True)
class DemOnGrid:
    """A DEM resampled onto the scene grid, with what was done to its voids.

    Attributes
    ----------
    elevation : ndarray float64 (rows, cols)
        Elevation [m]; NaN where no value (voids left unfilled, outside the DEM).
    crs : str
        CRS of the source DEM.
    voids_source : int
        Void (nodata/NaN) pixels of the source window that covers the scene (+2 pixels).
    filled_source : int
        Of those, the pixels filled (``fill_voids=True``).
    notes : tuple[str, ...]
        One line per decision, for the background summary.
    """

    elevation: np.ndarray
    crs: str
    voids_source: int
    filled_source: int
    notes: tuple


def load_dem(path: str | os.PathLike, grid: SceneGrid, fill_voids: bool = False,
             max_fill_px: int = DEM_FILL_MAX_DISTANCE_PX, field: str = "dem_path") -> DemOnGrid:
    """Read the part of a DEM GeoTIFF that covers the scene, optionally fill its voids, and
    resample it onto the scene grid (bilinear, rasterio/GDAL).

    Parameters
    ----------
    path : path-like
        DEM GeoTIFF in any CRS (geographic, e.g. SRTM in EPSG:4326, or projected).
    grid : SceneGrid
        Target grid.
    fill_voids : bool
        Fill voids (nodata/NaN) in the source DEM before resampling, by GDAL's inverse-distance
        ``FillNodata`` (:func:`rasterio.fill.fillnodata`) up to ``max_fill_px`` pixels away.
        False leaves them NaN (the caller masks them or refuses).
    max_fill_px : int
        Search radius of the fill [source pixels].

    Returns
    -------
    DemOnGrid

    Raises
    ------
    InputError
        Truncated file, no CRS, no overlap with the scene.
    rasterio.errors.RasterioIOError
        GDAL cannot open the file at all.
    """
    from affine import Affine
    from rasterio.errors import RasterioError
    from rasterio.fill import fillnodata
    from rasterio.warp import transform_bounds
    from rasterio.windows import Window, from_bounds

    path = os.fspath(path)
    require(os.path.isfile(path), field, path, "must be an existing DEM GeoTIFF")
    t = grid.transform
    xs = (t.c, t.c + grid.shape[1] * t.a)
    ys = (t.f, t.f + grid.shape[0] * t.e)
    # A file GDAL cannot open at all raises rasterio's RasterioIOError unchanged (the scenario
    # layer names the key); a file that opens but cannot be read (truncated) is an InputError.
    with rasterio.open(path) as src:
        try:
            require(src.crs is not None, f"{field}.crs", path, "the DEM must carry a CRS",
                    "Assign one (e.g. gdal_edit.py -a_srs EPSG:4326 for SRTM/ASTER tiles)")
            b = transform_bounds(grid.crs, src.crs, min(xs), min(ys), max(xs), max(ys), densify_pts=21)
            sb = src.bounds
            if b[0] >= sb.right or b[2] <= sb.left or b[1] >= sb.top or b[3] <= sb.bottom:
                raise InputError(f"{field}.extent",
                                 f"{sb.left:.4f}..{sb.right:.4f}, {sb.bottom:.4f}..{sb.top:.4f}",
                                 f"does not overlap the scene ({b[0]:.4f}..{b[2]:.4f}, {b[1]:.4f}..{b[3]:.4f} "
                                 f"in the DEM's CRS)", "Use the DEM tile(s) covering the port")
            # the covering window, padded for the bilinear kernel and for the void fill
            pad = 2 + (int(max_fill_px) if fill_voids else 0)
            w = from_bounds(*b, transform=src.transform)
            full = Window(0, 0, src.width, src.height)
            core = Window(int(np.floor(w.col_off)) - 2, int(np.floor(w.row_off)) - 2,
                          int(np.ceil(w.col_off + w.width)) - int(np.floor(w.col_off)) + 4,
                          int(np.ceil(w.row_off + w.height)) - int(np.floor(w.row_off)) + 4).intersection(full)
            w = Window(core.col_off - pad + 2, core.row_off - pad + 2, core.width + 2 * (pad - 2),
                       core.height + 2 * (pad - 2)).intersection(full)
            inner = (slice(int(core.row_off - w.row_off), int(core.row_off - w.row_off + core.height)),
                     slice(int(core.col_off - w.col_off), int(core.col_off - w.col_off + core.width)))
            data = src.read(1, window=w).astype(np.float64)
            src_transform = src.transform @ Affine.translation(w.col_off, w.row_off)
            src_crs = src.crs
            nodata = src.nodata
        except RasterioError as exc:
            raise InputError(field, path, "must be a readable GeoTIFF", f"GDAL: {exc}") from None
    if nodata is not None:
        data[data == nodata] = np.nan
    void = ~np.isfinite(data)
    n_void = int(void[inner].sum())     # voids of the part that covers the scene
    filled = 0
    notes = [f"DEM {os.path.basename(path)} ({src_crs.to_string()}) resampled bilinearly onto the scene grid"]
    if fill_voids and n_void:
        # voids out of reach keep their input value: NaN
        out = fillnodata(data.copy(), mask=(~void).astype(np.uint8),
                         max_search_distance=float(max_fill_px), smoothing_iterations=0)
        filled = int((void & np.isfinite(out))[inner].sum())
        data = out
        notes.append(f"DEM voids filled: {filled} of {n_void} void source pixels (GDAL FillNodata, "
                     f"<= {max_fill_px} px)")
    elif n_void:
        notes.append(f"DEM voids kept: {n_void} void source pixels are NaN (masked or refused)")
    # GDAL's warper still interpolates the coordinate transform along scan lines (measured on
    # SRTM 3" -> UTM 30 m: <= 0.02 source pixel, i.e. <= 2 m of position, whatever the
    # tolerance): negligible against the 30 m pixels and the eq. 15 terms it feeds.
    elevation = np.full(grid.shape, np.nan)
    reproject(data, elevation, src_transform=src_transform, src_crs=src_crs, src_nodata=np.nan,
              dst_transform=grid.transform, dst_crs=grid.crs, dst_nodata=np.nan,
              resampling=Resampling.bilinear, tolerance=0.0)
    return DemOnGrid(elevation, src_crs.to_string(), n_void, filled, tuple(notes))


def read_dem(path: str | os.PathLike, grid: SceneGrid) -> np.ndarray:
    """Read a DEM GeoTIFF and resample it onto the scene grid (bilinear, rasterio/GDAL).

    Parameters
    ----------
    path : path-like
        DEM GeoTIFF in any CRS (e.g. SRTM/ASTER GDEM in EPSG:4326 at 1 arc-second).
    grid : SceneGrid
        Target grid.

    Returns
    -------
    ndarray, float64, shape ``grid.shape``
        Elevation [m]; NaN where the source is nodata/NaN or does not cover the scene
        (masked explicitly, never filled).
    """
    return load_dem(path, grid).elevation


def horn_gradient(elevation, pixel_size: float):
    """Elevation gradient by Horn's 3x3 method.

    Parameters
    ----------
    elevation : ndarray (rows, cols)
        Elevation [m] on a north-up grid; NaN marks nodata.
    pixel_size : float
        Pixel size [m].

    Returns
    -------
    dz_dx, dz_dy : ndarray
        Gradient towards east and north [m m-1]. Edge pixels use replicated borders; any
        NaN in the 3x3 window gives NaN.

    Notes
    -----
    Horn (1981), Proc. IEEE 69(1):14–47; the "differences between adjacent pixels" of the
    paper's eq. 13 weighted 1-2-1 across the difference direction.
    """
    z = np.pad(np.asarray(elevation, dtype=np.float64), 1, mode="edge")
    a, b, c = z[:-2, :-2], z[:-2, 1:-1], z[:-2, 2:]
    d, f = z[1:-1, :-2], z[1:-1, 2:]
    g, h, i = z[2:, :-2], z[2:, 1:-1], z[2:, 2:]
    dz_dcol = ((c + 2 * f + i) - (a + 2 * d + g)) / (8.0 * pixel_size)
    dz_drow = ((g + 2 * h + i) - (a + 2 * b + c)) / (8.0 * pixel_size)
    # The border rows/cols repeat the edge value, so the one-sided difference there spans one
    # pixel, not two: double it so a plane keeps its exact gradient up to the edge.
    dz_dcol[:, [0, -1]] *= 2.0
    dz_drow[[0, -1], :] *= 2.0
    return dz_dcol, -dz_drow


def slope_aspect(elevation, pixel_size: float):
    """Slope and aspect of a DEM (paper eqs. 13–14).

    Parameters
    ----------
    elevation : ndarray
        Elevation [m] (north-up grid, NaN = nodata).
    pixel_size : float
        Pixel size [m].

    Returns
    -------
    slope_deg : ndarray
        ``arctan(sqrt(Zx^2 + Zy^2))`` [deg], eq. 13.
    aspect_deg : ndarray
        Azimuth of the downslope direction, clockwise from north, in [0, 360) [deg];
        NaN on flat pixels (gradient < 1e-9). This is eq. 14's ``arctan(Zy/Zx)`` resolved to
        the full circle with ``atan2`` and expressed as a compass azimuth.
    """
    zx, zy = horn_gradient(elevation, pixel_size)
    # Horn's stencil skips the centre pixel: a nodata centre must stay nodata.
    zx = np.where(np.isfinite(elevation), zx, np.nan)
    grad = np.hypot(zx, zy)
    slope = np.degrees(np.arctan(grad))
    aspect = np.degrees(np.arctan2(-zx, -zy)) % 360.0
    aspect = np.where(grad > 1e-9, aspect, np.nan)
    return slope, aspect


def southness(aspect_deg):
    """Aspect as a regression variable: ``-cos(aspect)`` [-], +1 south-facing, -1 north-facing.

    A linear term in the raw angle is discontinuous at north (0 = 360 deg); the paper states the
    aspect effect is "positive in the south and negative in the north", which this variable
    expresses. Flat pixels (aspect NaN) get 0.
    """
    out = -np.cos(np.radians(aspect_deg))
    return np.where(np.isfinite(out), out, 0.0)


@dataclass(frozen=True)
class TerrainFit:
    """Result of the eq. 15 regression.

    Attributes
    ----------
    beta_elevation : float
        beta_1 [K m-1].
    beta_slope : float
        beta_2 [K deg-1].
    beta_aspect : float
        beta_3 [K] per unit southness (see :func:`southness`).
    intercepts : dict[str, float]
        Intercept per class (or ``{"all": b0}``) [K].
    r2 : float
        Coefficient of determination of the fit [-].
    rmse : float
        Root-mean-square residual [K].
    n_pixels : int
        Pixels used.
    stderr : ndarray
        Standard errors of (beta_1, beta_2, beta_3) [K m-1, K deg-1, K].
    """

    beta_elevation: float
    beta_slope: float
    beta_aspect: float
    intercepts: dict
    r2: float
    rmse: float
    n_pixels: int
    stderr: np.ndarray

    @property
    def beta(self) -> np.ndarray:
        return np.array([self.beta_elevation, self.beta_slope, self.beta_aspect])


def fit_terrain_regression(delta_temp, elevation, slope_deg, aspect_term, groups=None,
                           group_names=None, min_pixels: int = 30) -> TerrainFit:
    """Least-squares fit of eq. 15: ``T - T0 = b0[group] + b1 Dem + b2 Slope + b3 Aspect``.

    Parameters
    ----------
    delta_temp : array_like
        ``LST - T0(t_overpass)`` on the pixels to fit [K].
    elevation : array_like
        [m].
    slope_deg : array_like
        [deg].
    aspect_term : array_like
        Aspect regressor [-] (:func:`southness`).
    groups : array_like of int, optional
        Class code per pixel; one intercept per class (keeps class offsets out of beta).
        ``None`` fits one common intercept.
    group_names : dict[int, str], optional
        Names for the intercepts.
    min_pixels : int
        Fewer finite pixels raise :class:`InputError`.

    Returns
    -------
    TerrainFit

    Notes
    -----
    Paper eq. 15. Solved with ``numpy.linalg.lstsq``; R^2 = 1 - SS_res/SS_tot about the mean.
    """
    y = np.ravel(np.asarray(delta_temp, dtype=np.float64))
    cols = [np.ravel(np.asarray(v, dtype=np.float64)) for v in (elevation, slope_deg, aspect_term)]
    g = np.zeros(y.shape, dtype=np.int64) if groups is None else np.ravel(np.asarray(groups))
    ok = np.isfinite(y) & np.isfinite(cols[0]) & np.isfinite(cols[1]) & np.isfinite(cols[2])
    n = int(ok.sum())
    if n < min_pixels:
        raise InputError("terrain_regression.pixels", n, f"need at least {min_pixels} finite land pixels",
                         "Check the DEM covers the land part of the scene")
    y = y[ok]
    cols = [c[ok] for c in cols]
    g = g[ok]
    codes = np.unique(g)
    design = np.column_stack([(g == c).astype(np.float64) for c in codes] + cols)
    coef, *_ = np.linalg.lstsq(design, y, rcond=None)
    resid = y - design @ coef
    ss_res = float(resid @ resid)
    ss_tot = float(((y - y.mean()) ** 2).sum())
    dof = max(n - design.shape[1], 1)
    sigma2 = ss_res / dof
    try:
        cov = sigma2 * np.linalg.inv(design.T @ design)
        stderr = np.sqrt(np.diag(cov)[-3:])
    except np.linalg.LinAlgError:
        stderr = np.full(3, np.nan)
    if groups is None:
        intercepts = {"all": float(coef[0])}
    else:
        names = group_names or {}
        intercepts = {names.get(int(c), str(int(c))): float(coef[k]) for k, c in enumerate(codes)}
    return TerrainFit(
        beta_elevation=float(coef[-3]), beta_slope=float(coef[-2]), beta_aspect=float(coef[-1]),
        intercepts=intercepts, r2=1.0 - ss_res / ss_tot if ss_tot > 0 else float("nan"),
        rmse=float(np.sqrt(ss_res / n)), n_pixels=n, stderr=stderr)


def terrain_term(fit: TerrainFit, elevation, slope_deg, aspect_term):
    """``b1 Dem + b2 Slope + b3 Aspect`` of eq. 15 [K] (no intercept)."""
    return (fit.beta_elevation * np.asarray(elevation) + fit.beta_slope * np.asarray(slope_deg)
            + fit.beta_aspect * np.asarray(aspect_term))
