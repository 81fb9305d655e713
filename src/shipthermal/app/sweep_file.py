"""The sweep file: the Cartesian product of scenario changes, read and validated.

A sweep file (TOML)::

    name = "heading-wind"                 # optional; names the sweep folder
    base = "my_scenario.toml"             # a scenario file (relative to the sweep file),
                                          # or "summer" / "winter" (the built-in defaults)
    stages = ["thermal", "imaging"]       # or ["thermal"] (default: both)

    [set]                                 # changes applied to every case (dotted keys)
    "ship.edge_length" = 3.0

    [axes]                                # one list of values per dotted scenario key
    "time.season" = ["summer", "winter"]
    "ship.heading" = [0, 90, 180, 270]
    "weather.wind_speed_offset" = [-1.0, 0.0, 1.0]
    "imaging.bands" = [["3-5"], ["8-14"]]

    [[axes.site]]                         # a grouped axis: keys that change together
    "weather.source" = "a.csv"
    "weather.temp_sea" = 290.0
    [[axes.site]]
    "weather.source" = "builtin"

Keys may also be written as nested tables (``ship.heading = [...]`` without quotes). The
changes are applied to the *raw* base scenario before validation, so season-dependent
defaults follow (``time.season = "winter"`` on the built-in base also moves the date, the
map and image times and the compartment temperatures to the winter defaults). Every case
is validated before anything runs: a bad value is a user error listing all problems.
"""

from __future__ import annotations

import copy
import hashlib
import itertools
import json
import math
import os
import tomllib
from dataclasses import dataclass, field
from pathlib import Path


from ..errors import InputError
from .pipeline import check_imaging_bands
from .rundir.inputs import named_files
from .scenario import SEASONS, ScenarioError, load_scenario
from .scenario.reading import read_toml

__all__ = ["SweepSpec", "SweepCase", "load_sweep", "sweep_inputs", "STAGES"]

STAGES = ("thermal", "imaging")
_TOP_KEYS = ("name", "description", "base", "stages", "set", "axes")

@dataclass(frozen=True)
class SweepCase:
    """One case: its id, position in the product, changes and scenario (TOML text)."""

    id: str
    index: int
    changes: dict
    labels: dict
    toml: str
    stages: tuple

    def spec(self) -> dict:
        """What a worker needs (plain data: pickles and serialises everywhere)."""
        return {"id": self.id, "index": self.index, "changes": self.changes,
                "labels": self.labels, "toml": self.toml, "stages": list(self.stages)}


@dataclass(frozen=True)
class SweepSpec:
    """A loaded and validated sweep file."""

    name: str
    source: str
    text: str
    base: str
    stages: tuple
    fixed: dict
    axes: dict
    cases: tuple = field(repr=False)

    @property
    def axis_names(self) -> list:
        return list(self.axes)


def _flatten(node, prefix: str, out: dict, leaf_lists: bool) -> None:
    """Nested tables → dotted keys. With ``leaf_lists`` (axes), a list ends a key."""
    for k, v in node.items():
        key = f"{prefix}.{k}" if prefix else str(k)
        if isinstance(v, dict):
            _flatten(v, key, out, leaf_lists)
        else:
            out[key] = v


def _set_dotted(raw: dict, key: str, value, where: str) -> None:
    node = raw
    parts = key.split(".")
    for p in parts[:-1]:
        nxt = node.setdefault(p, {})
        if not isinstance(nxt, dict):
            raise InputError(where, key, f"cannot set below {p!r}: it is a value, not a table")
        node = nxt
    node[parts[-1]] = value


def _show(v) -> str:
    if isinstance(v, float):
        return f"{v:g}"
    if isinstance(v, (list, tuple)):
        return "+".join(_show(x) for x in v)
    return str(v)


def _digest(text: str) -> str:
    return hashlib.sha1(text.encode("utf-8")).hexdigest()[:12]


def _first_error(reader, path, field):
    """A reader's :class:`ScenarioError` of one problem as a plain one-line InputError."""
    try:
        return reader(path, field)
    except ScenarioError as exc:
        e = exc.errors[0]
        raise InputError(e.field, e.value, e.allowed, e.fix) from None


def load_sweep(path) -> SweepSpec:
    """Read and validate a sweep file (every case's scenario is validated here).

    Raises
    ------
    InputError
        A malformed file, an unknown top-level key, an empty axis, a base that cannot be
        read; or a :class:`~shipthermal.app.scenario.ScenarioError` naming the case and every
        problem of its scenario.
    """
    path = Path(path)
    text, raw = _first_error(read_toml, path, "sweep")
    name, stages, base = _sweep_header(raw, path)
    base_raw, base_dir = _base_table(base, path)
    fixed: dict = {}
    if "set" in raw:
        if not isinstance(raw["set"], dict):
            raise InputError("sweep.set", raw["set"], "must be a table of dotted scenario keys")
        _flatten(raw["set"], "", fixed, False)
    axes = _sweep_axes(raw.get("axes"))
    _check_owners(axes, fixed)
    n = math.prod(len(v) for v in axes.values())
    if n > 10000:
        raise InputError("sweep.axes", f"{n} cases", "must give at most 10000 cases")
    cases, problems = _sweep_cases(axes, fixed, base_raw, base_dir, stages)
    if problems:
        raise ScenarioError(problems, f"sweep {path}")
    return SweepSpec(name, str(path), text, base, tuple(stages), fixed, axes, tuple(cases))


def _sweep_header(raw: dict, path: Path) -> tuple:
    """``(name, stages, base)`` of a sweep file, its top-level keys checked."""
    for k in raw:
        if k not in _TOP_KEYS:
            raise InputError(f"sweep.{k}", raw[k], f"unknown key; allowed: {', '.join(_TOP_KEYS)}")
    name = raw.get("name", path.stem)
    if (not isinstance(name, str) or not name or any(c in name for c in "/\\")
            or name.startswith(".")):
        raise InputError("sweep.name", name, "must be a non-empty name without slashes")
    stages = raw.get("stages", list(STAGES))
    if (not isinstance(stages, list) or not stages or any(s not in STAGES for s in stages)
            or "thermal" not in stages):
        raise InputError("sweep.stages", stages, "must be ['thermal'] or ['thermal', 'imaging']")
    base = raw.get("base", "summer")
    if not isinstance(base, str) or not base:
        raise InputError("sweep.base", base, "must be 'summer', 'winter' or a scenario file path")
    return name, stages, base


def _base_table(base: str, path: Path) -> tuple:
    """``(table, folder)`` of the sweep's base scenario: a built-in season, or a scenario
    file (relative to the sweep file) whose folder resolves its relative paths."""
    base_dir = path.parent.resolve()
    if base in SEASONS:
        base_raw = {"time": {"season": base}}
    else:
        bp = Path(os.path.expanduser(base))
        bp = bp if bp.is_absolute() else base_dir / bp
        if not bp.is_file():
            raise InputError("sweep.base", base, "must be 'summer', 'winter' or an existing "
                             "scenario file", f"Not found: {bp} (relative to the sweep file)")
        _, base_raw = _first_error(read_toml, bp, "sweep.base")
        base_dir = bp.parent.resolve()
    return base_raw, base_dir


def _sweep_axes(axes_raw) -> dict:
    """axis → its entries, each a dict of dotted keys and values (one key for a plain
    axis, several for a grouped one); no entry repeated."""
    if not isinstance(axes_raw, dict) or not axes_raw:
        raise InputError("sweep.axes", axes_raw, "must be a non-empty table: one list of "
                         "values per dotted scenario key", 'e.g. "ship.heading" = [0, 90]')
    axes: dict = {}
    flat: dict = {}
    _flatten(axes_raw, "", flat, True)
    for key, values in flat.items():
        if not isinstance(values, list) or not values:
            raise InputError(f"sweep.axes.{key}", values, "must be a non-empty list of values")
        if all(isinstance(v, dict) for v in values):
            groups = []
            for v in values:
                g: dict = {}
                _flatten(v, "", g, False)
                if not g:
                    raise InputError(f"sweep.axes.{key}", v, "each entry must change at least "
                                     "one key")
                groups.append(g)
            axes[key] = groups
        elif any(isinstance(v, dict) for v in values):
            raise InputError(f"sweep.axes.{key}", values, "must hold plain values or only "
                             "tables (a grouped axis), not both")
        else:
            axes[key] = [{key: v} for v in values]
        seen: dict = {}
        for i, g in enumerate(axes[key]):
            sig = json.dumps(g, sort_keys=True)
            if sig in seen:
                raise InputError(f"sweep.axes.{key}", values, f"must not repeat a value: "
                                 f"entries {seen[sig]} and {i} are the same case",
                                 "Remove the repeated value")
            seen[sig] = i
    return axes


def _check_owners(axes: dict, fixed: dict) -> None:
    """A key is an axis or fixed, once: refuse a key of two axes, or of an axis and [set]."""
    owner: dict = {}
    for axis, groups in axes.items():
        for k in dict.fromkeys(k for g in groups for k in g):
            if k in fixed:
                raise InputError(f"sweep.axes.{axis}", k, "is also fixed in [set]: a key is "
                                 "either fixed for every case or an axis, not both",
                                 f"Remove \"{k}\" from [set] or from [axes]")
            if k in owner:
                raise InputError(f"sweep.axes.{axis}", k, f"is also changed by the axis "
                                 f"{owner[k]!r}: each key may belong to one axis",
                                 "Merge the two axes into one grouped axis")
            owner[k] = axis


def _case_table(base_raw: dict, fixed: dict, axes: dict, combo) -> tuple:
    """``(table, changes, labels)`` of one combination of the axes' entries: the base
    scenario's table with [set] and the entries applied, and each axis's label."""
    case_raw = copy.deepcopy(base_raw)      # TOML dates and times stay as they are
    changes: dict = {}
    for k, v in fixed.items():
        _set_dotted(case_raw, k, v, "sweep.set")
    labels = {}
    for axis, group in zip(axes, combo):
        for k, v in group.items():
            _set_dotted(case_raw, k, v, f"sweep.axes.{axis}")
            changes[k] = v
        only = next(iter(group.values()))
        if len(group) == 1:     # the value itself (numbers stay numbers in the table)
            labels[axis] = only if isinstance(only, (int, float, str, bool)) else _show(only)
        else:
            labels[axis] = ", ".join(f"{k}={_show(v)}" for k, v in group.items())
    return case_raw, changes, labels


def _sweep_cases(axes: dict, fixed: dict, base_raw: dict, base_dir, stages) -> tuple:
    """``(cases, problems)``: a :class:`SweepCase` per combination of the axes whose
    scenario loads (and whose bands the imaging accepts), and the problems of the others."""
    cases, problems = [], []
    for index, combo in enumerate(itertools.product(*axes.values())):
        case_raw, changes, labels = _case_table(base_raw, fixed, axes, combo)
        try:
            sc = load_scenario(case_raw, base_dir=base_dir)
        except ScenarioError as exc:
            where = ", ".join(f"{a}={labels[a]}" for a in labels)
            problems.extend(InputError(f"case {index} ({where}): {e.field}", e.value, e.allowed,
                                       e.fix) for e in exc.errors)
            continue
        if "imaging" in stages:
            try:
                check_imaging_bands(sc)
            except InputError as e:
                where = ", ".join(f"{a}={labels[a]}" for a in labels)
                problems.append(InputError(f"case {index} ({where}): {e.field}", e.value,
                                           e.allowed, e.fix))
                continue
        toml = sc.to_toml().split("\n", 1)[1]   # without the 'written by' comment
        cid = f"{index:04d}-{_digest(toml + '|'.join(stages))}"
        cases.append(SweepCase(cid, index, changes, labels, toml, tuple(stages)))
    return cases, problems



def sweep_inputs(spec: SweepSpec) -> list:
    """The files a sweep reads: the sweep file, its base scenario and every file its cases'
    scenarios name (the sweep folder may hold none of them)."""
    out = []
    src = Path(spec.source)
    if src.is_file():
        out.append(str(src))
    if spec.base not in SEASONS:
        bp = Path(os.path.expanduser(spec.base))
        bp = bp if bp.is_absolute() else src.parent / bp
        if bp.is_file():
            out.append(str(bp))
    for case in spec.cases:
        named_files(tomllib.loads(case.toml), out)
    return sorted(set(out))
