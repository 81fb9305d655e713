"""The user-facing schema table (``docs/SCENARIO.md``), generated from the sections'
field specifications.
"""

from __future__ import annotations

import dataclasses
from dataclasses import fields
from typing import Any, Mapping

from .spec import _Spec
from .wiring import Scenario

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
              "part_choices": "string per part", "materials": "table per material",
              "part_files": "path per part", "surface_classes": "table per class",
              "instant_list": "list of instants",
              "year_list": "list of years", "file_list": "list of files"}


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
        if spec.kind in ("part_table", "part_choices"):
            key += ".<part>"
        elif spec.kind == "part_bands":
            key += ".<part>.<band>"
        elif spec.kind in ("part_files", "layups"):
            key += ".<part>"
        elif spec.kind == "materials":
            yield from _rows(spec.cls, f"{key}.<name>")
            continue
        elif spec.kind == "surface_classes":
            key += ".<class>.<property>"
        allowed = spec.allowed()
        if spec.kind in ("part_table", "part_bands"):
            allowed = spec.range_text()
        yield (key, _TYPE_TEXT[spec.kind], _default_text(f), spec.unit, allowed, spec.doc)
        if spec.kind == "layups":
            yield from _rows(spec.cls, f"{key}[i]")


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
