"""Reading scenarios: TOML files, TOML text, dicts, and the built-in season defaults.
"""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Mapping

from ...errors import InputError
from .spec import ScenarioError
from .values import SEASONS
from .wiring import Scenario, _load


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
