"""Reading scenarios: TOML files, TOML text, dicts, and the built-in season defaults.
"""

from __future__ import annotations

import os
import tomllib
from importlib import resources
from pathlib import Path
from typing import Mapping

from ...errors import InputError
from .spec import ScenarioError
from .values import SEASONS
from .wiring import Scenario, _load


MAX_TOML_BYTES = 1 << 20
"""Largest scenario or sweep file read [bytes] (1 MiB: the commented example scenarios are
about 5 kB; a larger file is a wrong file or a generated one gone astray)."""

MAX_TOML_NESTING = 16
"""Deepest nesting of tables and arrays in a scenario or sweep file (the schema's deepest
key, ``ship.layups.<part>[i].thickness``, is 4 levels)."""

MAX_TOML_LIST = 10_000
"""Longest list in a scenario or sweep file (``time.map_times`` at one per minute is 1440;
a sweep axis gives at most 10 000 cases)."""


def _decode(data: bytes, name: str, field: str) -> str:
    """Text of a TOML file: UTF-8 (a byte-order mark is dropped) or UTF-16 with its mark
    (what some Windows editors save)."""
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        try:
            return data.decode("utf-16")
        except UnicodeDecodeError:
            pass
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ScenarioError([InputError(field, name, f"must be UTF-8 text (byte {exc.start} is "
                                        "not UTF-8)", "Save the file as UTF-8 text (and give "
                                        "the .toml file, not a binary one)")], name) from None


def _shape_problem(raw) -> str | None:
    """Nesting deeper than :data:`MAX_TOML_NESTING` or a list longer than
    :data:`MAX_TOML_LIST` (the first found, with its dotted key)."""
    stack = [(raw, "", 1)]
    while stack:
        node, key, depth = stack.pop()
        if depth > MAX_TOML_NESTING:
            return f"nests tables and arrays {MAX_TOML_NESTING}+ levels deep at {key or 'the top'}"
        items = node.items() if isinstance(node, dict) else enumerate(node)
        if isinstance(node, list) and len(node) > MAX_TOML_LIST:
            return (f"has a list of {len(node):,} values at {key} (at most "
                    f"{MAX_TOML_LIST:,})")
        for k, v in items:
            if isinstance(v, (dict, list)):
                sub = f"{key}[{k}]" if isinstance(node, list) else (f"{key}.{k}" if key else str(k))
                stack.append((v, sub, depth + 1))
    return None


def read_toml(path, field: str = "scenario") -> tuple[str, dict]:
    """Text and table of a scenario or sweep file, every reading problem as a
    :class:`ScenarioError` naming ``field`` and the file: missing, larger than
    :data:`MAX_TOML_BYTES`, not text, not TOML, too deeply nested or with too long lists."""
    path = Path(path)
    name = str(path)
    if not path.is_file():
        raise ScenarioError([InputError(field, name, "must be an existing TOML file",
                                        "Check the path")], name)
    size = os.path.getsize(path)
    if size > MAX_TOML_BYTES:
        raise ScenarioError([InputError(field, name, f"is {size:,} bytes, more than the "
                                        f"{MAX_TOML_BYTES:,} a scenario or sweep file may have",
                                        "Check that this is the right file")], name)
    text = _decode(path.read_bytes(), name, field)
    return text, _parse(text, name, field)


def _parse(text: str, name: str, field: str) -> dict:
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError([InputError(field, name, f"must be valid TOML ({exc})",
                                        "Check quotes, brackets and '=' on that line")],
                            name) from None
    except RecursionError:
        raise ScenarioError([InputError(field, name, "nests arrays or tables too deeply to "
                                        f"read (a scenario needs at most {MAX_TOML_NESTING} "
                                        "levels)", "Check the brackets")], name) from None
    problem = _shape_problem(raw)
    if problem:
        raise ScenarioError([InputError(field, name, problem, "Check the file")], name)
    return raw


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
    _, raw = read_toml(path)
    base = Path(base_dir) if base_dir is not None else path.parent
    return _load(raw, base.resolve(), str(path))


def loads_scenario(text: str, *, base_dir=None, source: str = "scenario (string)") -> Scenario:
    """Validate a scenario given as TOML text (relative paths: ``base_dir`` or the cwd)."""
    raw = _parse(text, source, "scenario")
    base = Path(base_dir) if base_dir is not None else Path.cwd()
    return _load(raw, base.resolve(), source)


def default_scenario(season: str = "summer") -> Scenario:
    """The built-in default of a season (Dalian design day, frigate, synthetic port)."""
    if season not in SEASONS:
        raise InputError("season", season, f"must be one of {', '.join(SEASONS)}")
    return load_scenario({"time": {"season": season}})


def example_path(season: str = "summer") -> Path:
    """Path of the commented example scenario shipped with the package."""
    if season not in SEASONS:
        raise InputError("season", season, f"must be one of {', '.join(SEASONS)}")
    return Path(str(resources.files("shipthermal") / "data" / "scenarios" / f"{season}.toml"))
