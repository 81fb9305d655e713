"""Landsat-8/9 Collection-2 Level-1 readers: MTL metadata (text and JSON) and GeoTIFF bands.

Radiometric conversions follow the USGS *Landsat 8-9 Collection 2 Level 1 Data Format
Control Book* (LSDS-1822) and the *Landsat 8 Data Users Handbook* (LSDS-1574, §5):

- TOA spectral radiance   ``L = M_L * Q_cal + A_L``            [W m-2 sr-1 um-1]
- TOA reflectance          ``rho = (M_rho * Q_cal + A_rho) / sin(theta_SE)``   [-]
- brightness temperature   ``T_B = K2 / ln(K1 / L + 1)``        [K]

``K1``/``K2`` are the band-effective Planck constants published in the MTL file, so
``T_B`` is the Planck inversion of the band radiance.
"""

from __future__ import annotations

import json
import os
import re
from dataclasses import dataclass, field
from datetime import datetime, timezone
from typing import Mapping

import numpy as np
import rasterio
from rasterio.crs import CRS
from rasterio.transform import Affine

from shipthermal.errors import InputError, require

__all__ = [
    "SceneGrid",
    "north_up_transform",
    "MtlMetadata",
    "read_mtl",
    "parse_mtl_text",
    "read_band",
    "band_grid",
    "window_of_bounds",
    "LandsatScene",
    "read_landsat_scene",
    "dn_to_radiance",
    "dn_to_reflectance",
    "radiance_to_brightness_temperature",
    "brightness_temperature_to_radiance",
    "REFLECTIVE_BANDS",
    "THERMAL_BAND",
]

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


# ---------------------------------------------------------------------------------------------
# MTL metadata
# ---------------------------------------------------------------------------------------------

_REQUIRED_KEYS = (
    "DATE_ACQUIRED",
    "SCENE_CENTER_TIME",
    "SUN_ELEVATION",
    f"RADIANCE_MULT_BAND_{THERMAL_BAND}",
    f"RADIANCE_ADD_BAND_{THERMAL_BAND}",
    f"K1_CONSTANT_BAND_{THERMAL_BAND}",
    f"K2_CONSTANT_BAND_{THERMAL_BAND}",
    f"FILE_NAME_BAND_{THERMAL_BAND}",
) + tuple(f"REFLECTANCE_MULT_BAND_{b}" for b in REFLECTIVE_BANDS) \
  + tuple(f"REFLECTANCE_ADD_BAND_{b}" for b in REFLECTIVE_BANDS) \
  + tuple(f"FILE_NAME_BAND_{b}" for b in REFLECTIVE_BANDS)


@dataclass(frozen=True)
class MtlMetadata:
    """The MTL fields the background needs, parsed and typed.

    Attributes
    ----------
    path : str
        File the metadata came from.
    acquired_utc : datetime
        Scene centre time (timezone-aware, UTC).
    sun_elevation_deg : float
        Sun elevation at scene centre [deg].
    radiance_mult, radiance_add : dict[int, float]
        ``M_L`` [W m-2 sr-1 um-1 DN-1] and ``A_L`` [W m-2 sr-1 um-1] per band.
    reflectance_mult, reflectance_add : dict[int, float]
        ``M_rho`` [DN-1] and ``A_rho`` [-] per band.
    k1 : float
        ``K1_CONSTANT_BAND_10`` [W m-2 sr-1 um-1].
    k2 : float
        ``K2_CONSTANT_BAND_10`` [K].
    band_files : dict[int, str]
        Absolute paths of the band GeoTIFFs.
    raw : dict[str, str]
        Every key of the file (flattened over groups), as text.
    """

    path: str
    acquired_utc: datetime
    sun_elevation_deg: float
    radiance_mult: dict
    radiance_add: dict
    reflectance_mult: dict
    reflectance_add: dict
    k1: float
    k2: float
    band_files: dict
    raw: dict = field(repr=False)


def parse_mtl_text(text: str) -> dict[str, str]:
    """Flatten a Collection-2 ``*_MTL.txt`` (ODL ``GROUP = ... / KEY = VALUE``) into a dict.

    Keys are unique across groups in Collection-2 files, so groups are dropped.
    Quotes around string values are removed; values stay text.
    """
    out: dict[str, str] = {}
    for line in text.splitlines():
        line = line.strip()
        if not line or line == "END" or "=" not in line:
            continue
        key, _, value = line.partition("=")
        key, value = key.strip(), value.strip()
        if key in ("GROUP", "END_GROUP"):
            continue
        out[key] = value.strip('"')
    return out


def _flatten_json(node: Mapping, out: dict[str, str]) -> None:
    for key, value in node.items():
        if isinstance(value, Mapping):
            _flatten_json(value, out)
        else:
            out[str(key)] = str(value)


def read_mtl(path: str | os.PathLike) -> MtlMetadata:
    """Read a Landsat Collection-2 Level-1 MTL file in its text (``.txt``) or JSON form.

    Parameters
    ----------
    path : path-like
        ``*_MTL.txt`` or ``*_MTL.json``. The form is detected from the content.

    Returns
    -------
    MtlMetadata

    Raises
    ------
    InputError
        If the file is missing, unparsable, lacks a required key, or holds a non-numeric
        value where a number is needed.
    """
    path = os.fspath(path)
    require(os.path.isfile(path), "mtl_path", path, "must be an existing MTL file (*_MTL.txt or *_MTL.json)")
    with open(path, encoding="utf-8") as fh:
        text = fh.read()
    if text.lstrip().startswith("{"):
        try:
            doc = json.loads(text)
        except json.JSONDecodeError as exc:
            raise InputError("mtl_path", path, "must be valid JSON (Collection-2 MTL.json)",
                             f"JSON error: {exc}") from None
        raw: dict[str, str] = {}
        _flatten_json(doc, raw)
    else:
        raw = parse_mtl_text(text)
    missing = [k for k in _REQUIRED_KEYS if k not in raw]
    if missing:
        raise InputError(f"{os.path.basename(path)}[{missing[0]}]", "missing",
                         f"the MTL must contain the keys {', '.join(missing)}",
                         "Use the complete Collection-2 Level-1 MTL delivered with the scene")

    def num(key: str) -> float:
        try:
            return float(raw[key])
        except ValueError:
            raise InputError(f"{os.path.basename(path)}[{key}]", raw[key], "must be a number") from None

    date = raw["DATE_ACQUIRED"]
    clock = raw["SCENE_CENTER_TIME"].rstrip("Z")
    m = re.match(r"^(\d{2}):(\d{2}):(\d{2})(?:\.(\d+))?$", clock)
    try:
        day = datetime.strptime(date, "%Y-%m-%d")
        if m is None:
            raise ValueError(clock)
    except ValueError:
        raise InputError(f"{os.path.basename(path)}[DATE_ACQUIRED/SCENE_CENTER_TIME]",
                         f"{date} {raw['SCENE_CENTER_TIME']}",
                         "must be YYYY-MM-DD and HH:MM:SS[.fff]Z") from None
    frac = float("0." + m.group(4)) if m.group(4) else 0.0
    acquired = day.replace(hour=int(m.group(1)), minute=int(m.group(2)), second=int(m.group(3)),
                           microsecond=int(round(frac * 1e6)) % 1_000_000, tzinfo=timezone.utc)
    base = os.path.dirname(os.path.abspath(path))
    bands = (*REFLECTIVE_BANDS, THERMAL_BAND)
    band_files = {b: os.path.join(base, raw[f"FILE_NAME_BAND_{b}"]) for b in bands}
    return MtlMetadata(
        path=path,
        acquired_utc=acquired,
        sun_elevation_deg=num("SUN_ELEVATION"),
        radiance_mult={THERMAL_BAND: num(f"RADIANCE_MULT_BAND_{THERMAL_BAND}")},
        radiance_add={THERMAL_BAND: num(f"RADIANCE_ADD_BAND_{THERMAL_BAND}")},
        reflectance_mult={b: num(f"REFLECTANCE_MULT_BAND_{b}") for b in REFLECTIVE_BANDS},
        reflectance_add={b: num(f"REFLECTANCE_ADD_BAND_{b}") for b in REFLECTIVE_BANDS},
        k1=num(f"K1_CONSTANT_BAND_{THERMAL_BAND}"),
        k2=num(f"K2_CONSTANT_BAND_{THERMAL_BAND}"),
        band_files=band_files,
        raw=raw,
    )


# ---------------------------------------------------------------------------------------------
# Bands
# ---------------------------------------------------------------------------------------------

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


def read_band(path: str | os.PathLike, field_name: str = "band",
              bounds=None) -> tuple[np.ndarray, SceneGrid, float | None]:
    """Read band 1 of a GeoTIFF, whole or cropped to a map box.

    Parameters
    ----------
    path : path-like
    field_name : str
        Name used in error messages.
    bounds : (west, south, east, north), optional
        Crop box in the raster's CRS [m] (widened to whole pixels); only that window is
        read from the file.

    Returns
    -------
    data : ndarray
        Raw values (DN for Landsat L1, dtype as stored).
    grid : SceneGrid
        Grid of ``data`` (the window's, when cropped).
    nodata : float or None
        The file's nodata value (Landsat L1 uses 0 for fill).
    """
    from rasterio.windows import Window

    path = os.fspath(path)
    require(os.path.isfile(path), field_name, path, "must be an existing GeoTIFF file")
    try:
        with rasterio.open(path) as src:
            grid = SceneGrid(src.transform, src.crs, (src.height, src.width))
            require(grid.crs is not None, f"{field_name}.crs", path, "the raster must carry a CRS")
            if bounds is None:
                data = src.read(1)
            else:
                r0, r1, c0, c1 = window_of_bounds(grid, bounds, "bounds")
                win = Window(c0, r0, c1 - c0, r1 - r0)
                data = src.read(1, window=win)
                t = src.transform       # shifted by whole pixels (window_transform warns on rasterio 1.4)
                shifted = Affine(t.a, t.b, t.c + c0 * t.a + r0 * t.b, t.d, t.e, t.f + c0 * t.d + r0 * t.e)
                grid = SceneGrid(shifted, src.crs, data.shape)
            nodata = src.nodata
    except rasterio.errors.RasterioIOError as exc:
        raise InputError(field_name, path, "must be a readable GeoTIFF", str(exc)) from None
    return data, grid, nodata


def band_grid(path: str | os.PathLike, field_name: str = "band") -> SceneGrid:
    """Grid of a GeoTIFF without reading its pixels."""
    path = os.fspath(path)
    require(os.path.isfile(path), field_name, path, "must be an existing GeoTIFF file")
    try:
        with rasterio.open(path) as src:
            grid = SceneGrid(src.transform, src.crs, (src.height, src.width))
    except rasterio.errors.RasterioIOError as exc:
        raise InputError(field_name, path, "must be a readable GeoTIFF", str(exc)) from None
    require(grid.crs is not None, f"{field_name}.crs", path, "the raster must carry a CRS")
    return grid


@dataclass(frozen=True)
class LandsatScene:
    """A Landsat L1 scene on one grid.

    Attributes
    ----------
    mtl : MtlMetadata
    grid : SceneGrid
    dn : dict[int, ndarray]
        Quantised calibrated values ``Q_cal`` [DN] per band (uint16).
    fill : ndarray of bool
        Pixels that are fill (DN == 0) in any band.
    """

    mtl: MtlMetadata
    grid: SceneGrid
    dn: dict
    fill: np.ndarray

    def reflectance(self, band: int) -> np.ndarray:
        """Sun-angle-corrected TOA reflectance of an OLI band [-] (NaN on fill)."""
        rho = dn_to_reflectance(self.dn[band], self.mtl.reflectance_mult[band],
                                self.mtl.reflectance_add[band], self.mtl.sun_elevation_deg)
        return np.where(self.fill, np.nan, rho).astype(np.float32)

    def radiance(self, band: int = THERMAL_BAND) -> np.ndarray:
        """TOA spectral radiance [W m-2 sr-1 um-1] (NaN on fill)."""
        rad = dn_to_radiance(self.dn[band], self.mtl.radiance_mult[band], self.mtl.radiance_add[band])
        return np.where(self.fill, np.nan, rad)

    def brightness_temperature(self) -> np.ndarray:
        """TIRS band-10 brightness temperature [K] (NaN on fill)."""
        return radiance_to_brightness_temperature(self.radiance(THERMAL_BAND), self.mtl.k1, self.mtl.k2)


def read_landsat_scene(mtl_path: str | os.PathLike, bounds=None) -> LandsatScene:
    """Read the MTL and the bands it names (2–7 and 10); check they share one grid.

    Parameters
    ----------
    mtl_path : path-like
        ``*_MTL.txt`` or ``*_MTL.json``.
    bounds : (west, south, east, north), optional
        Crop box in the scene's projected CRS [m] (e.g. the port out of a 185 km scene);
        widened to whole 30 m pixels, only that window is read from each band.

    Raises
    ------
    InputError
        Missing MTL keys or band files; bands whose shape, CRS or transform differ; a crop
        box outside the scene.
    """
    mtl = read_mtl(mtl_path)
    dn: dict[int, np.ndarray] = {}
    grid0: SceneGrid | None = None
    ref_band = None
    for band, path in mtl.band_files.items():
        # Compare the full grids (a crop could hide a shape mismatch), then read.
        grid = band_grid(path, f"FILE_NAME_BAND_{band}")
        if grid0 is None:
            grid0, ref_band = grid, band
        else:
            if grid.shape != grid0.shape:
                raise InputError(f"FILE_NAME_BAND_{band}.shape", grid.shape,
                                 f"must equal band {ref_band}'s shape {grid0.shape}",
                                 "All Level-1 bands of one scene share the 30 m grid; "
                                 "check that the files belong to the same scene")
            if grid.crs != grid0.crs:
                raise InputError(f"FILE_NAME_BAND_{band}.crs", str(grid.crs),
                                 f"must equal band {ref_band}'s CRS {grid0.crs}",
                                 "Reproject the band onto the scene grid first")
            if not grid.same_as(grid0):
                raise InputError(f"FILE_NAME_BAND_{band}.transform", tuple(grid.transform)[:6],
                                 f"must equal band {ref_band}'s transform {tuple(grid0.transform)[:6]}",
                                 "Resample the band onto the scene grid first")
    scene_grid = None
    for band, path in mtl.band_files.items():
        data, scene_grid, _ = read_band(path, f"FILE_NAME_BAND_{band}", bounds)
        dn[band] = data
    fill = np.zeros(scene_grid.shape, dtype=bool)
    for data in dn.values():
        fill |= data == 0
    return LandsatScene(mtl=mtl, grid=scene_grid, dn=dn, fill=fill)


# ---------------------------------------------------------------------------------------------
# Radiometric kernels
# ---------------------------------------------------------------------------------------------

def dn_to_radiance(dn, mult, add):
    """TOA spectral radiance from Level-1 DN.

    Parameters
    ----------
    dn : array_like
        Quantised calibrated pixel value ``Q_cal`` [DN].
    mult : float
        ``RADIANCE_MULT_BAND_x`` [W m-2 sr-1 um-1 DN-1].
    add : float
        ``RADIANCE_ADD_BAND_x`` [W m-2 sr-1 um-1].

    Returns
    -------
    ndarray
        Radiance [W m-2 sr-1 um-1], float64.

    Notes
    -----
    Landsat 8 Data Users Handbook (LSDS-1574) eq. 5-1.
    """
    return mult * np.asarray(dn, dtype=np.float64) + add


def dn_to_reflectance(dn, mult, add, sun_elevation_deg):
    """Sun-angle-corrected TOA reflectance from Level-1 DN.

    Parameters
    ----------
    dn : array_like
        ``Q_cal`` [DN].
    mult, add : float
        ``REFLECTANCE_MULT_BAND_x`` [DN-1] and ``REFLECTANCE_ADD_BAND_x`` [-].
    sun_elevation_deg : float
        Scene-centre sun elevation [deg].

    Returns
    -------
    ndarray
        Reflectance [-].

    Notes
    -----
    LSDS-1574 eqs. 5-2 and 5-3.
    """
    return (mult * np.asarray(dn, dtype=np.float64) + add) / np.sin(np.radians(sun_elevation_deg))


def radiance_to_brightness_temperature(radiance, k1, k2):
    """At-sensor brightness temperature: Planck inversion with the band constants.

    Parameters
    ----------
    radiance : array_like
        Band spectral radiance [W m-2 sr-1 um-1], > 0.
    k1 : float
        ``K1_CONSTANT_BAND_x`` [W m-2 sr-1 um-1].
    k2 : float
        ``K2_CONSTANT_BAND_x`` [K].

    Returns
    -------
    ndarray
        Brightness temperature [K] (NaN where radiance <= 0).

    Notes
    -----
    LSDS-1574 eq. 5-4, ``T = K2 / ln(K1/L + 1)``: the monochromatic Planck law solved for T
    with ``K1 = c1/lambda^5`` and ``K2 = c2/lambda`` fitted to the band's response.
    """
    rad = np.asarray(radiance, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = k2 / np.log(k1 / rad + 1.0)
    return np.where(rad > 0, out, np.nan)


def brightness_temperature_to_radiance(temp, k1, k2):
    """Band radiance of a blackbody at ``temp`` [K] with the band constants [W m-2 sr-1 um-1].

    The exact inverse of :func:`radiance_to_brightness_temperature`.
    """
    return k1 / np.expm1(k2 / np.asarray(temp, dtype=np.float64))
