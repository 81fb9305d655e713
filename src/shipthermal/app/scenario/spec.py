"""The scenario's schema framework: a field specification (:class:`_Spec`) per key is the
one source of validation, defaults and the schema table; the converters check one raw
value each and record every problem in a shared :class:`_Context`.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import difflib
import math
import os
import re
import zoneinfo
from dataclasses import dataclass, field, fields
from pathlib import Path
from types import MappingProxyType
from typing import Any, Callable, Mapping, Optional

from ...errors import InputError
from ...geometry.parts import MAIN_PARTS, main_part
from ...materials import MATERIALS
from ...parameters import parse_band
from .values import MESH_EXTENSIONS, SENSOR_BANDS


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
        if n == 1:                     # one problem: one line (the file named once)
            ValueError.__init__(self, str(first) if str(first.value) == source
                                else f"{source}: {first}")
            return
        head = f"{source}: {n} problems (all listed; fix them and load again)"
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
    fix: str = ""                          # how to fix a value out of range

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
        ctx.err(path, raw, f"must lie in {rng}", spec.fix)
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
    if len(raw) > 1440:
        ctx.err(path, f"{len(raw)} times", allowed + ", at most 1440 (one per minute)")
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
    seen: set = set()
    dup = sorted({t for t in out if t in seen or seen.add(t)})
    if dup:
        ctx.err(path, raw, allowed, f"{dup} appear more than once")
        ok = False
    return tuple(out) if ok else _BAD


def _band_list(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    if not isinstance(raw, list) or not raw:
        ctx.err(path, raw, "must be a non-empty list of bands", 'e.g. ["3-5", "8-14"]')
        return _BAD
    out, ok = [], True
    for i, item in enumerate(raw):
        if isinstance(item, str) and (item in SENSOR_BANDS or item == "user"):
            out.append(item)
            continue
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
                    " ".join(t for t in (_suggest(item, spec.choices) if isinstance(
                        item, str) else "", spec.fix) if t))
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


def _per_part(raw: Any, path: str, ctx: _Context, what: str, example: str, convert,
              out: dict) -> dict | None:
    """A ``{part: value}`` table: every key must name a part, every value goes through
    ``convert(value, path_of_value, current)`` (``_BAD`` once it has reported an error; all
    values are checked either way) and lands in ``out``, over what ``out`` held for that
    part. Returns ``out``, or None after errors."""
    if not isinstance(raw, dict):
        ctx.err(path, raw, f"must be a table of part = {what}", example)
        return None
    ok = True
    for part, val in raw.items():
        sub = f"{path}.{part}"
        if not _part_key(part, sub, ctx):
            ok = False
            continue
        v = convert(val, sub, out.get(part))
        if v is _BAD:
            ok = False
        else:
            out[part] = v
    return out if ok else None


def _part_table(raw: Any, path: str, spec: _Spec, ctx: _Context, default: Mapping) -> Any:
    """``{part: number}`` merged over the defaults."""
    out = _per_part(raw, path, ctx, "value", "e.g. {hull = 0.7, deck = 0.85, superstructure = 0.7}",
                    lambda val, sub, _: _number(val, sub, spec, ctx), dict(default))
    return _BAD if out is None else MappingProxyType(out)


def _part_choices(raw: Any, path: str, spec: _Spec, ctx: _Context, default: Mapping) -> Any:
    """``{part: name}`` (each name one of the spec's choices) merged over the defaults."""
    example = "e.g. {" + ", ".join(f'{p} = "{c}"' for p, c in
                                   zip(("deck", "superstructure"), spec.choices)) + "}"
    out = _per_part(raw, path, ctx, "name", example,
                    lambda val, sub, _: _choice(val, sub, spec, ctx), dict(default))
    return _BAD if out is None else MappingProxyType(out)


def _part_bands(raw: Any, path: str, spec: _Spec, ctx: _Context, default: Mapping) -> Any:
    """``{part: {band: emissivity}}`` merged band by band over the defaults."""

    def bands(table, sub, current):
        if not isinstance(table, dict):
            ctx.err(sub, table, "must be a table of band = emissivity",
                    "e.g. {3-5 = 0.85, 8-14 = 0.90}")
            return _BAD
        merged, ok = dict(current or {}), True
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
        return merged if ok else _BAD

    example = " and ".join(f"{b} = {e:.2f}" for b, e in default.get("deck", {}).items())
    out = _per_part(raw, path, ctx, "{band = emissivity}",
                    f"e.g. [ship.band_emissivity.deck] with {example}", bands,
                    {k: dict(v) for k, v in default.items()})
    return _BAD if out is None else _freeze(out)


def _layups(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    """``{part: [{material, thickness, cells}, ...]}`` (outer layer first)."""
    example = 'e.g. deck = [{material = "deck_covering", thickness = 0.003, cells = 1}, ...]'

    def layup(layers, sub, _):
        if not isinstance(layers, list) or not layers:
            ctx.err(sub, layers, "must be a non-empty list of layers, outer layer first", example)
            return _BAD
        built = [_section(spec.cls, layer, f"{sub}[{i}]", ctx) for i, layer in enumerate(layers)]
        return _BAD if any(obj is _BAD for obj in built) else tuple(built)

    out = _per_part(raw, path, ctx, "list of layers", example, layup, {})
    return _BAD if out is None else MappingProxyType(out)


_MATERIAL_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]{0,63}$")


def _materials(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    """``{name: {conductivity, density, specific_heat, source}}``: the user's materials."""
    example = ("e.g. [materials.my_steel] with conductivity, density, specific_heat and "
               "source")
    if not isinstance(raw, dict):
        ctx.err(path, raw, "must be a table of materials by name", example)
        return _BAD
    out, ok = {}, True
    for name, table in raw.items():
        sub = f"{path}.{name}"
        if not _MATERIAL_NAME.match(str(name)):
            ctx.err(sub, name, "must be a name of letters, digits and _ (a letter first, at "
                    "most 64)", example)
            ok = False
            continue
        if name in MATERIALS:
            ctx.err(sub, name, "is a built-in material's name (shipthermal.materials."
                    f"MATERIALS: {', '.join(sorted(MATERIALS))})",
                    f"Give yours another name (e.g. {name}_own) and use that in ship.layups")
            ok = False
            continue
        obj = _section(spec.cls, table, sub, ctx)
        if obj is _BAD:
            ok = False
        else:
            out[name] = obj
    return MappingProxyType(out) if ok else _BAD


def _part_files(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    out = _per_part(raw, path, ctx, "file path",
                    'e.g. {hull = "hull.stl", deck = "deck.stl", superstructure = "sup.obj"}',
                    lambda val, sub, _: _file(val, sub, ctx, MESH_EXTENSIONS), {})
    return _BAD if out is None else MappingProxyType(out)


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
    "materials": _materials,
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


def _surface_classes(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    """``{class: {property: value}}``: the port background's surface classes changed or
    added, validated by the class table's own rules
    (:func:`imaging.background.surface_classes.apply_overrides`)."""
    if not isinstance(raw, Mapping) or not all(isinstance(v, Mapping) for v in raw.values()):
        ctx.err(path, raw, "must be tables of class properties",
                "e.g. [background.classes.land] albedo = 0.15")
        return _BAD
    # imported here: the background package costs ~2 s to import (scikit-learn, rasterio),
    # and only scenarios that change a class need it
    from imaging.background.surface_classes import SURFACE_CLASSES, apply_overrides

    new = [name for name in raw if name not in SURFACE_CLASSES and name != "water"]
    if new:
        ctx.err(f"{path}.{new[0]}", dict(raw[new[0]]), "is not a class of the port's class "
                f"maps ({', '.join(SURFACE_CLASSES)}; water is the sea skin model's)",
                _suggest(new[0], SURFACE_CLASSES) or "Change one of those classes' properties")
        return _BAD
    try:
        apply_overrides(raw, field=path)
    except InputError as exc:
        ctx.errors.append(exc)
        return _BAD
    return _freeze(raw)


_CONVERTERS["surface_classes"] = _surface_classes


def _instant_list(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    """Instants with their zone or offset (ISO 8601), e.g. ``2020-09-27T11:10:50Z``."""
    allowed = "must be a list of instants with their offset, e.g. ['2020-09-27T11:10:50Z']"
    if not isinstance(raw, list) or len(raw) > 10000:
        ctx.err(path, raw if not isinstance(raw, list) else f"{len(raw)} items", allowed)
        return _BAD
    out = []
    for i, item in enumerate(raw):
        text = item.isoformat() if isinstance(item, _dt.datetime) else item
        try:
            t = _dt.datetime.fromisoformat(str(text).replace("Z", "+00:00"))
        except (TypeError, ValueError):
            ctx.err(f"{path}[{i}]", item, allowed)
            return _BAD
        if t.tzinfo is None:
            ctx.err(f"{path}[{i}]", item, "must carry its offset or zone (Z for UTC)",
                    f"e.g. '{t.isoformat()}Z'")
            return _BAD
        out.append(t.isoformat())
    return tuple(out)


_CONVERTERS["instant_list"] = _instant_list


def _year_list(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    """Distinct years within the spec's range, e.g. ``[2011, 2012, 2013]``."""
    allowed = f"must be a list of distinct years in {spec.range_text()}"
    if not isinstance(raw, list) or len(raw) > 200:
        ctx.err(path, raw if not isinstance(raw, list) else f"{len(raw)} items", allowed)
        return _BAD
    for i, item in enumerate(raw):
        if isinstance(item, bool) or not isinstance(item, int) or not spec.in_range(item):
            ctx.err(f"{path}[{i}]", item, allowed)
            return _BAD
    if len(set(raw)) != len(raw):
        ctx.err(path, raw, allowed, "Give each year once")
        return _BAD
    return tuple(raw)


def _file_list(raw: Any, path: str, spec: _Spec, ctx: _Context) -> Any:
    """Existing files, each resolved like a single file key."""
    if not isinstance(raw, list) or len(raw) > 200:
        ctx.err(path, raw if not isinstance(raw, list) else f"{len(raw)} items",
                "must be a list of file paths")
        return _BAD
    out = [_file(item, f"{path}[{i}]", ctx) for i, item in enumerate(raw)]
    return _BAD if any(o is _BAD for o in out) else tuple(out)


_CONVERTERS["year_list"] = _year_list
_CONVERTERS["file_list"] = _file_list


def _convert(f: dataclasses.Field, raw: Any, path: str, ctx: _Context) -> Any:
    spec: _Spec = f.metadata["spec"]
    if spec.kind == "section":
        return _section(spec.cls, raw, path, ctx)
    if spec.kind in ("part_table", "part_bands", "part_choices"):
        default = _default(f, ctx, path)
        conv = {"part_table": _part_table, "part_bands": _part_bands,
                "part_choices": _part_choices}[spec.kind]
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


_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$")


def _name(raw, path, spec, ctx):
    if not isinstance(raw, str) or not _NAME.match(raw):
        ctx.err(path, raw, f"must be {spec.allowed_text}", "It names the run directory")
        return _BAD
    return raw


_CONVERTERS["name"] = _name
