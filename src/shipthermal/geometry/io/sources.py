"""The source of a user ship: one file per part, one scene with named parts, or one mesh
with a part map (an array, face ranges, a JSON file, a ``part`` cell array, or parts by
rules), loaded as one welded surface with a part label per triangle."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from ...errors import check_finite, require
from ..cad import SCENE_EXTENSIONS, load_named_parts
from ..meshfiles import sniff_mesh_file
from ..parts import main_part
from .load import UNITS, load_surface, weld
from .part_map import read_part_map

__all__ = ["ShipSource", "load_source"]


@dataclass(frozen=True, eq=False)
class ShipSource:
    """A user ship as loaded, before any check: the welded surface, a label per triangle
    into ``names``, the ship's name, and the layup and compartment-temperature overrides
    (as given, or those a part-map JSON written by :func:`.write.write_ship` carries)."""

    vertices: np.ndarray
    faces: np.ndarray
    labels: np.ndarray
    names: tuple
    name: str
    layups: Mapping | None
    compartment_temperature: Mapping | None


def load_source(source, units: str, part_map=None, part_names: Sequence[str] | None = None,
                name: str | None = None, layups: Mapping | None = None,
                compartment_temperature: Mapping | None = None) -> ShipSource:
    """Load the surface and its part labels (see :func:`.read.read_ship` for the arguments);
    every part name must name a main part or a sub-part."""
    auto = isinstance(part_map, str) and part_map == "auto"
    if isinstance(source, Mapping):
        vs, fs, labs, names = [], [], [], []
        off = 0
        for k, (pname, path) in enumerate(source.items()):
            v, f, _, _ = load_surface(path, units, f"ship.files.parts.{pname}")
            vs.append(v)
            fs.append(f + off)
            labs.append(np.full(len(f), k))
            names.append(str(pname))
            off += len(v)
        v, f = weld(np.concatenate(vs), np.concatenate(fs))
        labels = np.concatenate(labs)
        names = tuple(names)
        src_name = name or "user_ship"
    elif (part_map is None and Path(source).suffix.lower() in SCENE_EXTENSIONS
          and sniff_mesh_file(source) is not None
          and (named := load_named_parts(source, UNITS[units])) is not None):
        check_finite(f"ship.files.mesh ({Path(source).name}) vertices", named[0])
        v, f = weld(named[0], named[1])
        labels, names = named[2], named[3]
        src_name = name or Path(source).stem
    elif auto:
        v, f, _, _ = load_surface(source, units)
        labels, names = np.zeros(len(f), np.int64), ("hull",)
        src_name = name or Path(source).stem
    else:
        v, f, cell_part, file_names = load_surface(source, units)
        if part_map is None:
            require(cell_part is not None, "ship.files.part_map", None,
                    "is required: a JSON file of face ranges, \"auto\" (parts by rules), or "
                    "one file per part (ship.files.parts)",
                    'e.g. part_map = "ship_parts.json" holding {"hull": [[0, 5000]], '
                    '"deck": [[5000, 6200]], "superstructure": [[6200, 9000]]}')
            labels, names = read_part_map(cell_part, len(f), part_names or file_names)
        else:
            labels, names = read_part_map(part_map, len(f), part_names)
            # A part-map JSON written by write_ship also carries layups and temperatures.
            if isinstance(part_map, (str, os.PathLike)):
                meta = json.loads(Path(part_map).read_text())
                if layups is None and isinstance(meta.get("layups"), dict):
                    layups = {k: [tuple(x) for x in val] for k, val in meta["layups"].items()}
                if compartment_temperature is None and isinstance(
                        meta.get("compartment_temperature_K"), dict):
                    compartment_temperature = meta["compartment_temperature_K"]
        src_name = name or Path(source).stem
    for n in names:
        main_part(n)
    return ShipSource(v, f, labels, names, src_name, layups, compartment_temperature)
