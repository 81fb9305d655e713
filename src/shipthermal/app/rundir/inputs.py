"""A run's inputs: the files a scenario reads (an output folder may hold none of them) and
the keys in which a scenario differs from the copy in a run folder."""

from __future__ import annotations

import os
from pathlib import Path

from ...errors import InputError
from ..scenario import load_scenario


def _flatten(d: dict, prefix: str = "") -> dict:
    out = {}
    for k, v in d.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            out.update(_flatten(v, key + "."))
        else:
            out[key] = v
    return out


def scenario_changes(old, new) -> list:
    """Dotted keys whose values differ between two scenarios (e.g. ``solver.time_step``)."""
    a, b = _flatten(old.to_dict()), _flatten(new.to_dict())
    return sorted(k for k in a.keys() | b.keys() if a.get(k) != b.get(k))


def changes_from_copy(path, scenario) -> list:
    """Keys in which ``scenario`` differs from the single-case copy in ``path`` ([] when
    there is no scenario or no copy to compare with)."""
    copy = Path(path) / "scenario.toml"
    if scenario is None or not copy.is_file():
        return []
    try:
        return scenario_changes(load_scenario(copy), scenario)
    except InputError:
        return ["(the run's scenario.toml no longer loads)"]


def named_files(node, out: list | None = None) -> list:
    """The absolute paths of existing files or folders among the strings of a nested
    dict / list (a scenario's tables: its files are stored as absolute paths)."""
    out = [] if out is None else out
    if isinstance(node, dict):
        for v in node.values():
            named_files(v, out)
    elif isinstance(node, (list, tuple)):
        for v in node:
            named_files(v, out)
    elif isinstance(node, str) and os.path.isabs(node) and os.path.exists(node):
        out.append(node)
    return out


def scenario_inputs(scenario) -> list:
    """The files a scenario reads: its TOML file (when it was loaded from one) and every
    file it names (weather, ship mesh and part maps, background rasters; these are stored
    as absolute paths), plus the folder of a Landsat band-file template below the MTL's."""
    out = []
    src = getattr(scenario, "source", None)
    if src and os.path.isfile(src):
        out.append(str(src))
    data = scenario.to_dict() if hasattr(scenario, "to_dict") else scenario
    named_files(data, out)
    bg = data.get("background", {}) if isinstance(data, dict) else {}
    if isinstance(bg, dict) and bg.get("mtl") and bg.get("band_files"):
        sub = os.path.dirname(str(bg["band_files"]))
        if sub:
            out.append(os.path.join(os.path.dirname(str(bg["mtl"])), sub))
    return out


def check_inputs(out, inputs, field: str = "--out") -> None:
    """Refuse an output folder that is, or holds, one of ``inputs`` (symbolic links
    followed); an output folder inside an input's folder is fine."""
    o = Path(os.path.realpath(out))
    for i in inputs:
        if not i:
            continue
        r = Path(os.path.realpath(i))
        if r == o or o in r.parents:
            what = "is" if r == o else "holds"
            raise InputError(field, str(out), f"{what} an input of this command ({i})",
                             "Choose an output folder that holds none of the inputs, e.g. a "
                             "new folder under runs/")
