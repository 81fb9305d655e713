"""Landsat-8/9 readers: MTL metadata (text and JSON, groups kept) and GeoTIFF bands of
Collection-2 Level-1 and Level-2 (SR + ST_B10), Collection-1 and pre-collection Level-1
products; quality bands (QA_PIXEL / BQA); the MTL's georeferencing for TIFFs without a CRS.

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
    "MtlGeoreference",
    "read_mtl",
    "parse_mtl_text",
    "parse_mtl_groups",
    "qa_flags",
    "QA_LAYOUTS",
    "LST_ACCURACY_ST_B10_K",
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

LST_ACCURACY_ST_B10_K = 1.5
"""Stated accuracy of the Collection-2 Level-2 surface temperature [K]: validation of the
product's single-channel algorithm against in-situ and buoy temperatures reports RMSE of
roughly 1–2 K for clear-sky pixels (Malakar et al. 2018, IEEE TGRS 56(10)), larger near
clouds (the product's ``ST_CDIST`` / ``ST_QA`` layers)."""


@dataclass(frozen=True)
class MtlGeoreference:
    """The grid an MTL describes (UTM, north up): used when a band TIFF carries no CRS.

    Attributes
    ----------
    crs : CRS
        WGS 84 / UTM north zone of ``UTM_ZONE`` (Landsat puts southern scenes in the north
        zone with negative northings).
    ul_x, ul_y : float
        Centre of the upper-left pixel (``CORNER_UL_PROJECTION_X/Y_PRODUCT``) [m].
    lr_x, lr_y : float
        Centre of the lower-right pixel [m].
    cell : float
        ``GRID_CELL_SIZE_REFLECTIVE`` [m].
    """

    crs: CRS
    ul_x: float
    ul_y: float
    lr_x: float
    lr_y: float
    cell: float

    @property
    def shape(self) -> tuple[int, int]:
        return (int(round((self.ul_y - self.lr_y) / self.cell)) + 1,
                int(round((self.lr_x - self.ul_x) / self.cell)) + 1)

    @property
    def transform(self) -> Affine:
        # MTL corners are pixel centres; the affine origin is the upper-left pixel's corner.
        return north_up_transform(self.ul_x - self.cell / 2, self.ul_y + self.cell / 2, self.cell)


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
        ``M_L`` [W m-2 sr-1 um-1 DN-1] and ``A_L`` [W m-2 sr-1 um-1] of band 10 (Level-1).
    reflectance_mult, reflectance_add : dict[int, float]
        ``M_rho`` [DN-1] and ``A_rho`` [-] per band: TOA (Level-1) or surface (Level-2).
    k1 : float
        ``K1_CONSTANT_BAND_10`` [W m-2 sr-1 um-1] (NaN if absent in a Level-2 MTL).
    k2 : float
        ``K2_CONSTANT_BAND_10`` [K] (NaN if absent in a Level-2 MTL).
    band_files : dict[int, str]
        Absolute paths of the band GeoTIFFs (2–7 and 10; 10 is ``ST_B10`` on Level-2).
    raw : dict[str, str]
        Every key of the file, flattened over groups with the product's own groups taking
        precedence (the Level-1 processing record of a Level-2 MTL never overrides).
    level : {"L1", "L2"}
        Processing level (``PROCESSING_LEVEL`` / ``DATA_TYPE``).
    collection : {"2", "1", "pre"}
        Collection-2, Collection-1 or pre-collection (file layout and QA bits differ).
    st_mult, st_add : float or None
        ``TEMPERATURE_MULT/ADD_BAND_ST_B10`` [K DN-1], [K] (Level-2).
    qa_file : str or None
        Quality band (``QA_PIXEL`` or ``BQA``), if the MTL names one.
    georef : MtlGeoreference or None
        The grid in the MTL, for TIFFs without georeferencing.
    groups : dict[str, dict[str, str]]
        Keys per MTL group (innermost group name).
    notes : tuple[str, ...]
        What the reader decided on the user's behalf (band files found by name, ...).
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
    level: str = "L1"
    collection: str = "2"
    st_mult: float | None = None
    st_add: float | None = None
    qa_file: str | None = None
    georef: MtlGeoreference | None = None
    groups: dict = field(default_factory=dict, repr=False)
    notes: tuple = ()

    def band_token(self, band) -> str:
        """Name of a band in ``band_files`` templates: ``B4``/``B10``/``BQA``/``QA_PIXEL``
        (Level-1), ``SR_B4``/``ST_B10``/``QA_PIXEL`` (Level-2)."""
        if band == "qa":
            return "QA_PIXEL" if self.collection == "2" else "BQA"
        if self.level == "L2":
            return f"ST_B{band}" if band == THERMAL_BAND else f"SR_B{band}"
        return f"B{band}"


def parse_mtl_groups(text: str) -> tuple[str, dict[str, dict[str, str]]]:
    """Parse an ODL ``*_MTL.txt`` keeping its groups.

    Returns
    -------
    root : str
        Name of the outermost group (``LANDSAT_METADATA_FILE`` for Collection 2,
        ``L1_METADATA_FILE`` before).
    groups : dict
        ``{innermost group name: {key: value}}``; quotes around values removed.
    """
    groups: dict[str, dict[str, str]] = {}
    stack: list[str] = []
    root = ""
    for line in text.splitlines():
        line = line.strip()
        if not line or line == "END" or "=" not in line:
            continue
        key, _, value = line.partition("=")
        key, value = key.strip(), value.strip().strip('"')
        if key == "GROUP":
            stack.append(value)
            root = root or value
            groups.setdefault(value, {})
        elif key == "END_GROUP":
            if stack:
                stack.pop()
        else:
            groups.setdefault(stack[-1] if stack else "", {})[key] = value
    return root, groups


def parse_mtl_text(text: str) -> dict[str, str]:
    """Flatten an ``*_MTL.txt`` into one dict, the first occurrence of a key winning (the
    product's groups come before the processing records in every MTL layout)."""
    out: dict[str, str] = {}
    for items in parse_mtl_groups(text)[1].values():
        for k, v in items.items():
            out.setdefault(k, v)
    return out


def _json_groups(node: Mapping, name: str, out: dict) -> None:
    for key, value in node.items():
        if isinstance(value, Mapping):
            _json_groups(value, str(key), out)
        else:
            out.setdefault(name, {})[str(key)] = str(value)


def _find(groups: dict, key: str, skip=()):
    for gname, items in groups.items():
        if key in items and not any(gname.startswith(s) for s in skip):
            return items[key]
    return None


def _discover(directory: str, patterns) -> str | None:
    """The one file in ``directory`` whose name matches one of ``patterns`` (case-insensitive)."""
    try:
        names = sorted(os.listdir(directory))
    except OSError:
        return None
    for pat in patterns:
        hits = [n for n in names if re.search(pat, n, re.IGNORECASE)]
        if len(hits) == 1:
            return os.path.join(directory, hits[0])
    return None


def read_mtl(path: str | os.PathLike, band_files=None) -> MtlMetadata:
    """Read a Landsat 8/9 MTL: Collection-2 Level-1 or Level-2 (text or JSON), Collection-1
    or pre-collection Level-1 (text).

    Parameters
    ----------
    path : path-like
        ``*_MTL.txt`` or ``*_MTL.json``. The form is detected from the content.
    band_files : str or dict, optional
        Where the band files are when their names on disk differ from the MTL's: a template
        with ``{band}`` (e.g. ``"l8_{band}.tif"``, tokens :meth:`MtlMetadata.band_token`),
        relative to the MTL's folder; or a dict ``{token or band number: path}``. Without
        it, a band the MTL names but that is not on disk is looked for by its suffix
        (``*_B4.TIF``, ``*_SR_B4.TIF``, ``*_BQA.TIF``) in the MTL's folder (noted).

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
    name = os.path.basename(path)
    require(os.path.isfile(path), "mtl_path", path, "must be an existing MTL file (*_MTL.txt or *_MTL.json)")
    try:
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
    except UnicodeDecodeError:
        raise InputError("mtl_path", path, "must be a text or JSON Landsat MTL file",
                         "Give the *_MTL.txt delivered with the scene, not a band image") from None
    if text.lstrip().startswith("{"):
        try:
            doc = json.loads(text)
        except json.JSONDecodeError as exc:
            raise InputError("mtl_path", path, "must be valid JSON (Collection-2 MTL.json)",
                             f"JSON error: {exc}") from None
        groups: dict[str, dict[str, str]] = {}
        _json_groups(doc, "", groups)
        root = next(iter(doc), "") if isinstance(doc, Mapping) else ""
    else:
        root, groups = parse_mtl_groups(text)
    require(bool(groups), "mtl_path", path, "must be a Landsat MTL (GROUP = ... / KEY = VALUE lines)")

    level_text = _find(groups, "PROCESSING_LEVEL") or _find(groups, "DATA_TYPE") or "L1"
    level = "L2" if level_text.upper().startswith("L2") else "L1"
    if root == "LANDSAT_METADATA_FILE":
        collection = "2"
    elif (_find(groups, "COLLECTION_NUMBER") or "").lstrip("0") == "1":
        collection = "1"
    else:
        collection = "pre"
    # A Level-2 MTL also records the Level-1 product it was made from (its file names and
    # TOA rescaling); only the Level-2 groups describe the files the user has.
    skip = ("LEVEL1_",) if level == "L2" else ()
    raw: dict[str, str] = {}
    for gname, items in groups.items():
        if not any(gname.startswith(s) for s in skip):
            for k, v in items.items():
                raw.setdefault(k, v)
    for gname, items in groups.items():
        for k, v in items.items():
            raw.setdefault(k, v)          # K1/K2 of a Level-2 MTL live in LEVEL1_THERMAL_CONSTANTS

    def get(key):
        return _find(groups, key, skip) if level == "L2" else raw.get(key)

    st = f"BAND_ST_B{THERMAL_BAND}"
    required = ["DATE_ACQUIRED", "SCENE_CENTER_TIME", "SUN_ELEVATION"]
    required += [f"REFLECTANCE_{w}_BAND_{b}" for w in ("MULT", "ADD") for b in REFLECTIVE_BANDS]
    required += [f"FILE_NAME_BAND_{b}" for b in REFLECTIVE_BANDS]
    if level == "L2":
        required += [f"TEMPERATURE_MULT_{st}", f"TEMPERATURE_ADD_{st}", f"FILE_NAME_{st}"]
    else:
        required += [f"RADIANCE_MULT_BAND_{THERMAL_BAND}", f"RADIANCE_ADD_BAND_{THERMAL_BAND}",
                     f"K1_CONSTANT_BAND_{THERMAL_BAND}", f"K2_CONSTANT_BAND_{THERMAL_BAND}",
                     f"FILE_NAME_BAND_{THERMAL_BAND}"]
    missing = [k for k in required if get(k) is None]
    if missing:
        raise InputError(f"{name}[{missing[0]}]", "missing",
                         f"the {'Level-2' if level == 'L2' else 'Level-1'} MTL must contain the keys "
                         f"{', '.join(missing)}",
                         "Use the complete MTL delivered with the scene (not edited or truncated)")

    def num(key: str, optional: bool = False) -> float:
        value = get(key) if level == "L2" and not key.startswith("K") else raw.get(key)
        if value is None and optional:
            return float("nan")
        try:
            return float(value)
        except (TypeError, ValueError):
            raise InputError(f"{name}[{key}]", value, "must be a number") from None

    date = get("DATE_ACQUIRED")
    clock = get("SCENE_CENTER_TIME").rstrip("Z")
    m = re.match(r"^(\d{2}):(\d{2}):(\d{2})(?:\.(\d+))?$", clock)
    try:
        day = datetime.strptime(date, "%Y-%m-%d")
        if m is None:
            raise ValueError(clock)
    except ValueError:
        raise InputError(f"{name}[DATE_ACQUIRED/SCENE_CENTER_TIME]", f"{date} {get('SCENE_CENTER_TIME')}",
                         "must be YYYY-MM-DD and HH:MM:SS[.fff]Z") from None
    frac = float("0." + m.group(4)) if m.group(4) else 0.0
    acquired = day.replace(hour=int(m.group(1)), minute=int(m.group(2)), second=int(m.group(3)),
                           microsecond=int(round(frac * 1e6)) % 1_000_000, tzinfo=timezone.utc)

    # --- band files -------------------------------------------------------------------------
    base = os.path.dirname(os.path.abspath(path))
    thermal_key = f"FILE_NAME_{st}" if level == "L2" else f"FILE_NAME_BAND_{THERMAL_BAND}"
    named = {b: get(f"FILE_NAME_BAND_{b}") for b in REFLECTIVE_BANDS}
    named[THERMAL_BAND] = get(thermal_key)
    qa_name = get("FILE_NAME_QUALITY_L1_PIXEL") or get("FILE_NAME_BAND_QUALITY")
    if qa_name is not None:
        named["qa"] = qa_name
    probe = MtlMetadata(path, acquired, 0.0, {}, {}, {}, {}, 0.0, 0.0, {}, {}, level=level, collection=collection)
    notes: list[str] = []
    files: dict = {}
    overrides = band_files
    for band, mtl_name in [*named.items(), *([("qa", None)] if "qa" not in named else [])]:
        token = probe.band_token(band)
        given = None
        if isinstance(overrides, str):
            given = overrides.replace("{band}", token)
        elif isinstance(overrides, Mapping):
            given = overrides.get(token, overrides.get(band, overrides.get(str(band))))
        if given is not None:
            files[band] = given if os.path.isabs(given) else os.path.join(base, given)
            continue
        if mtl_name is None:
            continue
        target = os.path.join(base, mtl_name)
        if not os.path.isfile(target):
            pats = [rf"[_.]{token}\.tiff?$"] if band != "qa" else [r"[_.]QA_PIXEL\.tiff?$", r"[_.]BQA\.tiff?$"]
            found = _discover(base, pats)
            if found is not None:
                notes.append(f"{token}: '{mtl_name}' named in the MTL is not there; using "
                             f"'{os.path.basename(found)}' (same band suffix)")
                target = found
        files[band] = target
    qa_file = files.pop("qa", None)
    if qa_file is not None and not os.path.isfile(qa_file) and not (
            isinstance(overrides, Mapping) and ("qa" in overrides or probe.band_token("qa") in overrides)):
        notes.append(f"quality band '{os.path.basename(qa_file)}' not found: clouds, shadows and fill "
                     "are not masked from QA")
        qa_file = None

    # --- georeferencing in the MTL ----------------------------------------------------------
    georef = None
    try:
        proj = (raw.get("MAP_PROJECTION") or "").upper()
        zone = int(float(raw["UTM_ZONE"]))
        cell = float(raw.get("GRID_CELL_SIZE_REFLECTIVE") or 30.0)
        if proj == "UTM" and 1 <= abs(zone) <= 60:
            georef = MtlGeoreference(CRS.from_epsg(32600 + abs(zone)),
                                     float(raw["CORNER_UL_PROJECTION_X_PRODUCT"]),
                                     float(raw["CORNER_UL_PROJECTION_Y_PRODUCT"]),
                                     float(raw["CORNER_LR_PROJECTION_X_PRODUCT"]),
                                     float(raw["CORNER_LR_PROJECTION_Y_PRODUCT"]), cell)
    except (KeyError, ValueError):
        georef = None

    l2 = level == "L2"
    return MtlMetadata(
        path=path,
        acquired_utc=acquired,
        sun_elevation_deg=num("SUN_ELEVATION"),
        radiance_mult={} if l2 else {THERMAL_BAND: num(f"RADIANCE_MULT_BAND_{THERMAL_BAND}")},
        radiance_add={} if l2 else {THERMAL_BAND: num(f"RADIANCE_ADD_BAND_{THERMAL_BAND}")},
        reflectance_mult={b: num(f"REFLECTANCE_MULT_BAND_{b}") for b in REFLECTIVE_BANDS},
        reflectance_add={b: num(f"REFLECTANCE_ADD_BAND_{b}") for b in REFLECTIVE_BANDS},
        k1=num(f"K1_CONSTANT_BAND_{THERMAL_BAND}", optional=l2),
        k2=num(f"K2_CONSTANT_BAND_{THERMAL_BAND}", optional=l2),
        band_files=files,
        raw=raw,
        level=level,
        collection=collection,
        st_mult=num(f"TEMPERATURE_MULT_{st}") if l2 else None,
        st_add=num(f"TEMPERATURE_ADD_{st}") if l2 else None,
        qa_file=qa_file,
        georef=georef,
        groups=groups,
        notes=tuple(notes),
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
    import warnings

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
    from rasterio.windows import Window

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


@dataclass(frozen=True)
class LandsatScene:
    """A Landsat L1 or L2 scene on one grid.

    Attributes
    ----------
    mtl : MtlMetadata
    grid : SceneGrid
    dn : dict[int, ndarray]
        Stored values per band (uint16): ``Q_cal`` [DN] on Level-1, scaled SR / ST on Level-2.
    fill : ndarray of bool
        Pixels that are fill (DN == 0 in any band, or the QA fill bit).
    qa : dict[str, ndarray] or None
        Decoded quality flags (:func:`qa_flags`), None without a quality band.
    georeferenced_from_mtl : bool
        The band TIFFs carried no CRS; the grid is the MTL's.
    notes : tuple[str, ...]
        What the reader decided (MTL georeferencing, band files found by suffix, ...).
    """

    mtl: MtlMetadata
    grid: SceneGrid
    dn: dict
    fill: np.ndarray
    qa: dict | None = None
    georeferenced_from_mtl: bool = False
    notes: tuple = ()

    @property
    def level(self) -> str:
        return self.mtl.level

    @property
    def masked(self) -> np.ndarray:
        """Pixels to replace: fill, cloud, cirrus, cloud shadow (:data:`QA_MASK_FLAGS`)."""
        m = self.fill.copy()
        if self.qa is not None:
            for f in QA_MASK_FLAGS:
                m |= self.qa[f]
        return m

    def reflectance(self, band: int) -> np.ndarray:
        """Reflectance of an OLI band [-] (NaN on fill): sun-angle-corrected TOA on Level-1,
        surface reflectance on Level-2."""
        if self.mtl.level == "L2":
            rho = dn_to_radiance(self.dn[band], self.mtl.reflectance_mult[band], self.mtl.reflectance_add[band])
        else:
            rho = dn_to_reflectance(self.dn[band], self.mtl.reflectance_mult[band],
                                    self.mtl.reflectance_add[band], self.mtl.sun_elevation_deg)
        return np.where(self.fill, np.nan, rho).astype(np.float32)

    def radiance(self, band: int = THERMAL_BAND) -> np.ndarray:
        """TOA spectral radiance [W m-2 sr-1 um-1] (NaN on fill; Level-1 only)."""
        require(self.mtl.level == "L1", "landsat.level", self.mtl.level,
                "TOA radiance needs a Level-1 band 10 (a Level-2 scene gives ST_B10 instead)")
        rad = dn_to_radiance(self.dn[band], self.mtl.radiance_mult[band], self.mtl.radiance_add[band])
        return np.where(self.fill, np.nan, rad)

    def brightness_temperature(self) -> np.ndarray:
        """TIRS band-10 brightness temperature [K] (NaN on fill; Level-1 only)."""
        return radiance_to_brightness_temperature(self.radiance(THERMAL_BAND), self.mtl.k1, self.mtl.k2)

    def surface_temperature(self) -> np.ndarray:
        """Level-2 ``ST_B10`` surface temperature [K] (NaN on fill), ``mult * DN + add``."""
        require(self.mtl.level == "L2", "landsat.level", self.mtl.level,
                "ST_B10 exists in Level-2 products only")
        st = dn_to_radiance(self.dn[THERMAL_BAND], self.mtl.st_mult, self.mtl.st_add)
        return np.where(self.fill | (self.dn[THERMAL_BAND] == 0), np.nan, st)


def read_landsat_scene(mtl_path: str | os.PathLike, bounds=None, band_files=None,
                       use_qa: bool = True) -> LandsatScene:
    """Read the MTL and the bands it names (2–7 and 10, and the quality band); check they
    share one grid.

    Parameters
    ----------
    mtl_path : path-like
        ``*_MTL.txt`` or ``*_MTL.json`` (Level-1 or Level-2, :func:`read_mtl`).
    bounds : (west, south, east, north), optional
        Crop box in the scene's projected CRS [m] (e.g. the port out of a 185 km scene);
        widened to whole 30 m pixels, only that window is read from each band.
    band_files : str or dict, optional
        Band file names differing from the MTL's (:func:`read_mtl`).
    use_qa : bool
        Read the quality band when there is one.

    Raises
    ------
    InputError
        Missing MTL keys or band files; bands whose shape, CRS or transform differ; a crop
        box outside the scene; TIFFs without CRS whose size differs from the MTL's grid.
    """
    mtl = read_mtl(mtl_path, band_files)
    notes = list(mtl.notes)
    files = dict(mtl.band_files)
    if use_qa and mtl.qa_file is not None:
        files["qa"] = mtl.qa_file
    dn: dict = {}
    grid0: SceneGrid | None = None
    ref_band = None
    from_mtl = False
    for band, path in files.items():
        # Compare the full grids (a crop could hide a shape mismatch), then read.
        key = "QA" if band == "qa" else f"FILE_NAME_BAND_{band}"
        with _rio_open(path, key) as src:
            grid, by_mtl = _open_grid(src, path, key, mtl.georef)
        from_mtl |= by_mtl
        if grid0 is None:
            grid0, ref_band = grid, band
        else:
            if grid.shape != grid0.shape:
                raise InputError(f"{key}.shape", grid.shape,
                                 f"must equal band {ref_band}'s shape {grid0.shape}",
                                 "All bands of one scene share the 30 m grid; "
                                 "check that the files belong to the same scene")
            if grid.crs != grid0.crs:
                raise InputError(f"{key}.crs", str(grid.crs),
                                 f"must equal band {ref_band}'s CRS {grid0.crs}",
                                 "Reproject the band onto the scene grid first")
            if not grid.same_as(grid0):
                raise InputError(f"{key}.transform", tuple(grid.transform)[:6],
                                 f"must equal band {ref_band}'s transform {tuple(grid0.transform)[:6]}",
                                 "Resample the band onto the scene grid first")
    if from_mtl:
        notes.append(f"band TIFFs carry no CRS: georeferencing from the MTL ({mtl.georef.crs}, upper-left "
                     f"pixel centre {mtl.georef.ul_x:.1f} E, {mtl.georef.ul_y:.1f} N, {mtl.georef.cell:g} m)")
    scene_grid = None
    for band, path in files.items():
        key = "QA" if band == "qa" else f"FILE_NAME_BAND_{band}"
        data, scene_grid, _ = read_band(path, key, bounds, mtl.georef)
        dn[band] = data
    qa_raw = dn.pop("qa", None)
    fill = np.zeros(scene_grid.shape, dtype=bool)
    for data in dn.values():
        fill |= data == 0
    qa = None
    if qa_raw is not None:
        qa = qa_flags(qa_raw, mtl.collection)
        fill |= qa["fill"]
        counts = ", ".join(f"{f} {int(qa[f].sum())}" for f in QA_MASK_FLAGS if f != "fill")
        notes.append(f"quality band {os.path.basename(files['qa'])} ({'QA_PIXEL' if mtl.collection == '2' else 'BQA'}"
                     f", {'pre-collection' if mtl.collection == 'pre' else 'collection ' + mtl.collection} bits): "
                     f"{counts} pixels")
    return LandsatScene(mtl=mtl, grid=scene_grid, dn=dn, fill=fill, qa=qa,
                        georeferenced_from_mtl=from_mtl, notes=tuple(notes))


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
