"""Open every input of the port background without running it, and report every problem.

:func:`check_background_inputs` reads headers (and the last row of each band, which finds
truncated files), the MTL with its georeferencing, the quality band, the ROIs (rasterised,
inside the scene, every class present), the DEM (CRS, overlap with the scene) and the met
grid (variables and units by its reader, the overpass inside its time span, the scene
inside its extent). Used by ``shipthermal check``.
"""

from __future__ import annotations

import os

import numpy as np

from shipthermal.errors import InputError

from .classify import CLASS_CODES, CLASS_NAMES, read_roi
from .landsat.bands import _open_grid, _rio_open
from .landsat.mtl import read_mtl
from .met import met_for_scene, read_met_grid

__all__ = ["check_background_inputs"]


def _collect(problems: list, key: str, func, *args, **kwargs):
    try:
        return func(*args, **kwargs)
    except InputError as exc:
        problems.append(InputError(f"background.{key}: {exc.field}", exc.value, exc.allowed, exc.fix))
    return None


def _check_bands(mtl, problems: list):
    """Grids of all bands (header + last row): the scene grid (or None) and whether it came
    from the MTL."""
    from rasterio.errors import RasterioIOError
    from rasterio.windows import Window

    files = dict(mtl.band_files)
    if mtl.qa_file is not None:
        files["qa"] = mtl.qa_file
    grid0 = None
    from_mtl = False
    for band, path in files.items():
        key = "QA" if band == "qa" else f"FILE_NAME_BAND_{band}"
        try:
            with _rio_open(path, key) as src:
                grid, by_mtl = _open_grid(src, path, key, mtl.georef)
                from_mtl |= by_mtl
                try:
                    src.read(1, window=Window(0, src.height - 1, src.width, 1))
                except RasterioIOError as exc:
                    raise InputError(key, path, "must be a readable GeoTIFF (truncated or corrupt?)",
                                     str(exc).splitlines()[0]) from None
        except InputError as exc:
            problems.append(InputError(f"background.mtl: {exc.field}", exc.value, exc.allowed, exc.fix))
            continue
        if grid0 is None:
            grid0 = grid
        elif not grid.same_as(grid0):
            problems.append(InputError(f"background.mtl: {key}.grid", (grid.shape, str(grid.crs)),
                                       f"must equal the other bands' grid {grid0.shape} {grid0.crs}",
                                       "Use bands of one scene on one grid"))
    return grid0, from_mtl


def _check_dem(path, grid, problems: list) -> None:
    import rasterio
    from rasterio.warp import transform_bounds

    try:
        src = rasterio.open(path)
    except rasterio.errors.RasterioIOError as exc:
        problems.append(InputError("background.dem", path, "must be a readable raster (GeoTIFF)",
                                   str(exc).splitlines()[0]))
        return
    with src:
        if src.crs is None:
            problems.append(InputError("background.dem.crs", path, "the DEM must carry a CRS"))
            return
        if grid is None:
            return
        w, s, e, n = transform_bounds(src.crs, grid.crs, *src.bounds, densify_pts=21)
    t = grid.transform
    gw, gn = t.c, t.f
    ge, gs = t.c + grid.shape[1] * t.a, t.f + grid.shape[0] * t.e
    if e <= gw or w >= ge or n <= gs or s >= gn:
        problems.append(InputError("background.dem", path,
                                   f"must overlap the scene (scene {gw:.0f}..{ge:.0f} E, {gs:.0f}..{gn:.0f} N "
                                   f"in {grid.crs}; the DEM covers {w:.0f}..{e:.0f} E, {s:.0f}..{n:.0f} N)",
                                   "Give a DEM tile of the port"))


def check_background_inputs(mtl, roi=None, dem=None, met=None, band_files=None, *,
                            met_variable=None, met_units: str = "auto",
                            met_margin_cells: int = 4) -> tuple[list, list]:
    """Open every background input and collect all problems.

    Parameters
    ----------
    mtl : path-like
        Landsat MTL.
    roi, dem, met : path-like, optional
    band_files : str or dict, optional
        As :func:`.landsat.read_mtl`.
    met_variable, met_units, met_margin_cells
        As :func:`.met.read_met_grid` and :func:`.met.met_for_scene`.

    Returns
    -------
    problems : list[InputError]
        Every problem found (fields prefixed ``background.<key>``); empty when all is well.
    notes : list[str]
        What the readers decided (MTL georeferencing, band files found by suffix, ...).
    """
    problems: list[InputError] = []
    notes: list[str] = []
    meta = _collect(problems, "mtl", read_mtl, mtl, band_files)
    grid = None
    if meta is not None:
        notes += list(meta.notes)
        grid, from_mtl = _check_bands(meta, problems)
        if from_mtl:
            notes.append(f"band TIFFs carry no CRS: georeferencing from the MTL ({meta.georef.crs})")
    if roi is not None and grid is not None:
        labels = _collect(problems, "roi", read_roi, roi, grid)
        if labels is not None:
            absent = [CLASS_NAMES[c] for c in CLASS_CODES if not (labels == c).any()]
            if absent:
                problems.append(InputError("background.roi", os.fspath(roi),
                                           f"must give training pixels of every class inside the scene; "
                                           f"none for {', '.join(absent)}", "Draw ROIs of those classes"))
    if dem is not None:
        _check_dem(os.fspath(dem), grid, problems)
    if met is not None:
        grid_met = _collect(problems, "met", read_met_grid, met, met_variable, None, met_units)
        if grid_met is not None and meta is not None and grid is not None:
            # the overpass's local day and the scene plus margin, as the chain will take them
            overpass = np.datetime64(meta.acquired_utc.replace(tzinfo=None), "s")
            _collect(problems, "met", met_for_scene, grid_met, grid, overpass,
                     margin_cells=met_margin_cells)
    return problems, notes
