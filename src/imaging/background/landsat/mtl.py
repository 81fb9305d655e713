"""Landsat MTL metadata: text (ODL) and JSON, groups kept; the fields the background needs
parsed and typed, the band files found, the grid the MTL describes."""

from __future__ import annotations

import json
import os
import re
from dataclasses import dataclass, field
from datetime import datetime, timezone
from typing import Mapping

from rasterio.crs import CRS
from rasterio.transform import Affine

from shipthermal.errors import InputError, require

from .grid import REFLECTIVE_BANDS, THERMAL_BAND, north_up_transform


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


def _read_groups(path: str) -> tuple[str, dict[str, dict[str, str]]]:
    """The MTL's outermost group name and its keys per group, from text or JSON."""
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
    return root, groups


def _level_and_collection(root: str, groups: dict) -> tuple[str, str]:
    """Processing level (``"L1"``/``"L2"``) and collection (``"2"``, ``"1"``, ``"pre"``)."""
    level_text = _find(groups, "PROCESSING_LEVEL") or _find(groups, "DATA_TYPE") or "L1"
    level = "L2" if level_text.upper().startswith("L2") else "L1"
    if root == "LANDSAT_METADATA_FILE":
        collection = "2"
    elif (_find(groups, "COLLECTION_NUMBER") or "").lstrip("0") == "1":
        collection = "1"
    else:
        collection = "pre"
    return level, collection


def _flatten(groups: dict, skip: tuple) -> dict[str, str]:
    """Every key over the groups, those of groups not in ``skip`` taking precedence."""
    raw: dict[str, str] = {}
    for gname, items in groups.items():
        if not any(gname.startswith(s) for s in skip):
            for k, v in items.items():
                raw.setdefault(k, v)
    for gname, items in groups.items():
        for k, v in items.items():
            raw.setdefault(k, v)          # K1/K2 of a Level-2 MTL live in LEVEL1_THERMAL_CONSTANTS
    return raw


def _check_required(get, level: str, name: str) -> None:
    """Every key the level needs is there, or the first missing one is named."""
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


def _acquired(get, name: str) -> datetime:
    """Scene centre time (UTC) from ``DATE_ACQUIRED`` and ``SCENE_CENTER_TIME``."""
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
    return day.replace(hour=int(m.group(1)), minute=int(m.group(2)), second=int(m.group(3)),
                       microsecond=int(round(frac * 1e6)) % 1_000_000, tzinfo=timezone.utc)


def _band_files(path: str, get, probe: MtlMetadata, band_files) -> tuple[dict, str | None, list]:
    """The band files (2–7 and 10), the quality band and the notes: the user's names, else
    the MTL's, else a file of the same band suffix in the MTL's folder."""
    level = probe.level
    st = f"BAND_ST_B{THERMAL_BAND}"
    base = os.path.dirname(os.path.abspath(path))
    thermal_key = f"FILE_NAME_{st}" if level == "L2" else f"FILE_NAME_BAND_{THERMAL_BAND}"
    named = {b: get(f"FILE_NAME_BAND_{b}") for b in REFLECTIVE_BANDS}
    named[THERMAL_BAND] = get(thermal_key)
    qa_name = get("FILE_NAME_QUALITY_L1_PIXEL") or get("FILE_NAME_BAND_QUALITY")
    if qa_name is not None:
        named["qa"] = qa_name
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
    return files, qa_file, notes


def _georeference(raw: dict) -> MtlGeoreference | None:
    """The UTM grid in the MTL, or None when it does not describe one."""
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
    return georef


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
    root, groups = _read_groups(path)
    level, collection = _level_and_collection(root, groups)
    # A Level-2 MTL also records the Level-1 product it was made from (its file names and
    # TOA rescaling); only the Level-2 groups describe the files the user has.
    skip = ("LEVEL1_",) if level == "L2" else ()
    raw = _flatten(groups, skip)

    def get(key):
        return _find(groups, key, skip) if level == "L2" else raw.get(key)

    st = f"BAND_ST_B{THERMAL_BAND}"
    _check_required(get, level, name)

    def num(key: str, optional: bool = False) -> float:
        value = get(key) if level == "L2" and not key.startswith("K") else raw.get(key)
        if value is None and optional:
            return float("nan")
        try:
            return float(value)
        except (TypeError, ValueError):
            raise InputError(f"{name}[{key}]", value, "must be a number") from None

    acquired = _acquired(get, name)
    probe = MtlMetadata(path, acquired, 0.0, {}, {}, {}, {}, 0.0, 0.0, {}, {}, level=level, collection=collection)
    files, qa_file, notes = _band_files(path, get, probe, band_files)
    georef = _georeference(raw)

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
