"""Open the background's input files without running the chain: every problem at once.

Used by ``shipthermal check``: each file the ``[background]`` section
names (``source = "files"``) is opened and checked the way the chain will read it, so a
scenario that validates does not fail minutes later on an unreadable input. Each problem is
an :class:`InputError` (one line: the key, the value, what is allowed, the fix).

Checked here: the met grid (readable NetCDF/GRIB, a time axis, a temperature variable, units
consistent with the values, at least 24 consecutive hourly steps) and the DEM (readable
GeoTIFF, a CRS, the whole band decodable). Voids are judged by the chain, which knows which
pixels are land (``dem_nodata``).
"""

from __future__ import annotations

import numpy as np

from shipthermal.errors import InputError

from .met import read_met_grid

__all__ = ["check_background_files", "check_met_file", "check_dem_file"]


def check_met_file(path, variable=None, units: str = "auto", field: str = "background.met",
                   n_hours: int = 24) -> list:
    """Problems of a met grid file ([] when it reads); also a summary line on success."""
    try:
        met = read_met_grid(path, variable, None, units, field=field)
    except InputError as exc:
        return [exc]
    t = met.times_utc
    step = np.timedelta64(3600, "s")
    run = best = 1 if t.size else 0
    for a, b in zip(t[:-1], t[1:]):
        run = run + 1 if b - a == step else 1
        best = max(best, run)
    if best < n_hours:
        return [InputError(f"{field}.time", f"{t.size} steps from {t[0]} to {t[-1]}",
                           f"must hold {n_hours} consecutive hourly steps (longest run: {best})",
                           "Download every hour of the overpass day")]
    return []


def check_dem_file(path, field: str = "background.dem") -> list:
    """Problems of a DEM GeoTIFF ([] when it reads)."""
    import rasterio
    from rasterio.errors import RasterioError

    try:
        with rasterio.open(path) as src:
            if src.crs is None:
                return [InputError(f"{field}.crs", str(path), "the DEM must carry a CRS",
                                   "Assign one (e.g. gdal_edit.py -a_srs EPSG:4326)")]
            src.read(1)           # every block decodes (a truncated download fails here)
    except RasterioError as exc:
        return [InputError(field, str(path), "must be a readable GeoTIFF", f"GDAL: {exc}")]
    return []


def check_background_files(bgs) -> list:
    """All problems of the met grid and DEM a ``[background]`` section names."""
    problems = []
    if getattr(bgs, "source", "builtin") != "files":
        return problems
    if bgs.met:
        problems += check_met_file(bgs.met, bgs.met_variable, bgs.met_units)
    if bgs.dem:
        problems += check_dem_file(bgs.dem)
    return problems
