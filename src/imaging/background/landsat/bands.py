"""Band GeoTIFFs of a scene: reading a band (georeferenced from the MTL when the TIFF has no
CRS) and the quality band's flags per product generation."""

from __future__ import annotations

import os
import warnings

import numpy as np
import rasterio
from rasterio.transform import Affine
from rasterio.windows import Window

from shipthermal.errors import InputError, require

from .grid import SceneGrid, window_of_bounds
from .mtl import MtlGeoreference


QA_LAYOUTS = {
    # Collection-2 QA_PIXEL (LSDS-1619 / LSDS-1328 Table 6-1): single bits.
    "2": {"fill": ((0, 1, 1),), "cloud": ((1, 1, 1), (3, 1, 1)), "cirrus": ((2, 1, 1),),
          "shadow": ((4, 1, 1),)},
    # Collection-1 BQA (LSDS-1873 Table 6-1): cloud bit, two-bit confidences (3 = high).
    "1": {"fill": ((0, 1, 1),), "cloud": ((4, 1, 1),), "cirrus": ((11, 3, 3),),
          "shadow": ((7, 3, 3),)},
    # Pre-collection L8 BQA (Landsat 8 QA band, 2013-2016): two-bit confidences, no shadow.
    # Cloud at medium or high confidence: on a real scene (LC80200392015216LGN00) medium-
    # confidence pixels are 7 K colder in band 10 than low-confidence ones (282.6 vs 289.7 K).
    "pre": {"fill": ((0, 1, 1),), "cloud": ((14, 3, 2), (14, 3, 3)), "cirrus": ((12, 3, 3),), "shadow": ()},
}
"""Quality-band bit tests per product generation: flag -> ((first bit, mask, value), ...);
a pixel carries the flag when any ``(qa >> bit) & mask == value`` holds."""

QA_MASK_FLAGS = ("fill", "cloud", "cirrus", "shadow")
"""Flags whose pixels are masked (and filled from same-class neighbours)."""

MASK_BITS = {flag: 1 << k for k, flag in enumerate(QA_MASK_FLAGS)}
"""Bits of the written mask raster (``qa_mask.tif``): fill 1, cloud 2, cirrus 4, shadow 8."""

def _open_grid(src, path: str, field_name: str, georef: MtlGeoreference | None) -> tuple[SceneGrid, bool]:
    """Grid of an open dataset; the MTL's grid when the file carries no CRS. Returns
    ``(grid, from_mtl)``."""
    if src.crs is not None:
        return SceneGrid(src.transform, src.crs, (src.height, src.width)), False
    if georef is None:
        raise InputError(f"{field_name}.crs", path, "the raster must carry a CRS",
                         "Georeference it, or read it through its MTL (which gives UTM_ZONE and "
                         "CORNER_*_PROJECTION_*_PRODUCT)")
    if georef.shape != (src.height, src.width):
        raise InputError(f"{field_name}.shape", (src.height, src.width),
                         f"must equal the grid of the MTL corners {georef.shape} (the TIFF carries no "
                         "CRS, so the MTL's georeferencing is used)",
                         "Use the MTL that came with these files, or georeference the TIFFs")
    return SceneGrid(georef.transform, georef.crs, georef.shape), True


def _rio_open(path: str, field_name: str):
    require(os.path.isfile(path), field_name, path, "must be an existing GeoTIFF file",
            "Give the band's path (the MTL's FILE_NAME_* or the background band_files key)")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", rasterio.errors.NotGeoreferencedWarning)
            return rasterio.open(path)
    except rasterio.errors.RasterioIOError as exc:
        raise InputError(field_name, path, "must be a readable GeoTIFF", str(exc).splitlines()[0]) from None


def read_band(path: str | os.PathLike, field_name: str = "band", bounds=None,
              georef: MtlGeoreference | None = None) -> tuple[np.ndarray, SceneGrid, float | None]:
    """Read band 1 of a GeoTIFF, whole or cropped to a map box.

    Parameters
    ----------
    path : path-like
    field_name : str
        Name used in error messages.
    bounds : (west, south, east, north), optional
        Crop box in the raster's CRS [m] (widened to whole pixels); only that window is
        read from the file.
    georef : MtlGeoreference, optional
        The grid to use when the file carries no CRS (from the scene's MTL).

    Returns
    -------
    data : ndarray
        Raw values (DN for Landsat, dtype as stored).
    grid : SceneGrid
        Grid of ``data`` (the window's, when cropped).
    nodata : float or None
        The file's nodata value (Landsat uses 0 for fill).
    """
    path = os.fspath(path)
    src = _rio_open(path, field_name)
    try:
        with src:
            grid, _ = _open_grid(src, path, field_name, georef)
            if bounds is None:
                data = src.read(1)
            else:
                r0, r1, c0, c1 = window_of_bounds(grid, bounds, "bounds")
                win = Window(c0, r0, c1 - c0, r1 - r0)
                data = src.read(1, window=win)
                t = grid.transform      # shifted by whole pixels (window_transform warns on rasterio 1.4)
                shifted = Affine(t.a, t.b, t.c + c0 * t.a + r0 * t.b, t.d, t.e, t.f + c0 * t.d + r0 * t.e)
                grid = SceneGrid(shifted, grid.crs, data.shape)
            nodata = src.nodata
    except rasterio.errors.RasterioIOError as exc:
        raise InputError(field_name, path, "must be a readable GeoTIFF (truncated or corrupt?)",
                         str(exc).splitlines()[0]) from None
    return data, grid, nodata


def band_grid(path: str | os.PathLike, field_name: str = "band",
              georef: MtlGeoreference | None = None) -> SceneGrid:
    """Grid of a GeoTIFF without reading its pixels (the MTL's when the file has no CRS)."""
    path = os.fspath(path)
    with _rio_open(path, field_name) as src:
        return _open_grid(src, path, field_name, georef)[0]


def qa_flags(qa, collection: str = "2") -> dict[str, np.ndarray]:
    """Decode a Landsat quality band into boolean flags.

    Parameters
    ----------
    qa : ndarray of uint16
        ``QA_PIXEL`` (Collection 2) or ``BQA`` (Collection 1, pre-collection).
    collection : {"2", "1", "pre"}

    Returns
    -------
    dict
        ``fill``, ``cloud`` (incl. dilated cloud on Collection 2), ``cirrus`` and ``shadow``
        (high confidence where the layout has confidences) -> bool arrays.
    """
    q = np.asarray(qa).astype(np.uint32)
    out = {}
    for flag, tests in QA_LAYOUTS[collection].items():
        m = np.zeros(q.shape, dtype=bool)
        for bit, mask, value in tests:
            m |= ((q >> bit) & mask) == value
        out[flag] = m
    return out
