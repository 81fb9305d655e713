"""The raster grid of a scene: Landsat's bands of the background, north-up affines, the
grid every product lives on and windows of it."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from rasterio.crs import CRS
from rasterio.transform import Affine

from shipthermal.errors import InputError, require


REFLECTIVE_BANDS = (2, 3, 4, 5, 6, 7)
"""OLI bands used as classification features: blue, green, red, NIR, SWIR-1, SWIR-2."""
THERMAL_BAND = 10
"""TIRS band 10 (10.6–11.19 um), the band of the single-channel algorithm."""
RED_BAND = 4
NIR_BAND = 5


def north_up_transform(west: float, north: float, xres: float, yres: float | None = None) -> Affine:
    """Affine of a north-up grid from its upper-left corner [m or deg] and pixel size
    (same as ``rasterio.transform.from_origin``, without its pending-deprecation warning)."""
    return Affine(xres, 0.0, west, 0.0, -(xres if yres is None else yres), north)


@dataclass(frozen=True)
class SceneGrid:
    """The raster grid every product of the background lives on.

    Attributes
    ----------
    transform : Affine
        Pixel (col, row) -> map (x, y) of the pixel's upper-left corner [m].
    crs : rasterio.crs.CRS
        Projected CRS (UTM for Landsat L1).
    shape : tuple[int, int]
        (rows, cols).
    """

    transform: Affine
    crs: CRS
    shape: tuple[int, int]

    @property
    def resolution(self) -> float:
        """Pixel size [m] (square pixels)."""
        return float(abs(self.transform.a))

    def pixel_centres(self, step: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """Map coordinates (x of columns, y of rows) of pixel centres [m], every ``step``."""
        rows = np.arange(0, self.shape[0], step)
        cols = np.arange(0, self.shape[1], step)
        x = self.transform.c + (cols + 0.5) * self.transform.a
        y = self.transform.f + (rows + 0.5) * self.transform.e
        return x, y

    def same_as(self, other: "SceneGrid", tol: float = 1e-6) -> bool:
        return (self.shape == other.shape and self.crs == other.crs
                and self.transform.almost_equals(other.transform, precision=tol))


def window_of_bounds(grid: SceneGrid, bounds, field_name: str = "bounds"):
    """Pixel window ``(row0, row1, col0, col1)`` of a map box on a north-up grid.

    Parameters
    ----------
    grid : SceneGrid
    bounds : (west, south, east, north)
        Box in the grid's CRS [m]; widened outwards to whole pixels.

    Raises
    ------
    InputError
        An empty box or one that leaves the grid.
    """
    try:
        west, south, east, north = (float(b) for b in bounds)
    except (TypeError, ValueError):
        raise InputError(field_name, bounds, "must be (west, south, east, north) in the scene CRS [m]") from None
    t = grid.transform
    require(west < east and south < north, field_name, tuple(bounds), "must satisfy west < east and south < north")
    # A hair of tolerance so boxes drawn on pixel edges do not grow by a pixel from round-off.
    eps = 1e-6
    col0 = int(np.floor((west - t.c) / t.a + eps))
    col1 = int(np.ceil((east - t.c) / t.a - eps))
    row0 = int(np.floor((north - t.f) / t.e + eps))
    row1 = int(np.ceil((south - t.f) / t.e - eps))
    rows, cols = grid.shape
    extent = (t.c, t.f + rows * t.e, t.c + cols * t.a, t.f)
    require(0 <= col0 < col1 <= cols and 0 <= row0 < row1 <= rows, field_name, tuple(bounds),
            f"must lie inside the raster (west, south, east, north) = {tuple(round(x, 3) for x in extent)} "
            f"of {grid.crs}", "Crop to a box inside the scene, in the scene's projected CRS")
    return row0, row1, col0, col1
