"""Writing a ship as files a user can open and read back: a PLY, a part-map JSON, an STL per part."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ...atomic import atomic_path
from ..ship_geometry import ShipGeometry

__all__ = ["write_ship"]


def write_ship(ship: ShipGeometry, directory, stem: str | None = None) -> dict[str, Path]:
    """Write a ship as files a user can open and read back with :func:`read_ship`.

    * ``<stem>.ply`` — the whole surface, triangles sorted by part;
    * ``<stem>_parts.json`` — the part map (face ranges), units, particulars, layups;
    * ``<stem>_parts/<part>.stl`` — one binary STL per part.

    Returns the written paths by kind.
    """
    import trimesh      # deferred: start-up cost (trimesh takes ~1.5 s to import)

    directory = Path(directory)
    stem = stem or ship.name
    order = np.argsort(ship.face_part, kind="stable")
    f = ship.faces[order]
    lab = ship.face_part[order]
    ranges = {}
    for k, n in enumerate(ship.part_names):
        idx = np.flatnonzero(lab == k)
        if len(idx):
            ranges[n] = [[int(idx[0]), int(idx[-1]) + 1]]
    (directory / f"{stem}_parts").mkdir(parents=True, exist_ok=True)
    out = {}
    mesh = trimesh.Trimesh(ship.vertices, f, process=False, validate=False)
    out["ply"] = _atomic(directory / f"{stem}.ply", lambda p: mesh.export(p, file_type="ply"))
    meta = dict(units="m", parts=ranges, name=ship.name, length=ship.length, beam=ship.beam,
                draught=ship.draught, freeboard=ship.freeboard, edge_length=ship.edge_length,
                provenance=ship.provenance,
                coordinates="x forward (bow +x), y to port, z up, z = 0 at the waterline, origin amidships",
                layups={n: [[getattr(l.material, "name", l.material), l.thickness, l.cells]
                            for l in ship.layups[n].layers] for n in ship.part_names},
                compartment_temperature_K=dict(ship.compartment_temperature))
    out["json"] = _atomic(directory / f"{stem}_parts.json",
                          lambda p: Path(p).write_text(json.dumps(meta, indent=1)))
    for n in ship.part_names:
        sel = ship.faces[ship.face_part == ship.part_names.index(n)]
        used, inv = np.unique(sel, return_inverse=True)
        part = trimesh.Trimesh(ship.vertices[used], inv.reshape(-1, 3), process=False, validate=False)
        out[f"stl:{n}"] = _atomic(directory / f"{stem}_parts" / f"{n}.stl",
                                  lambda p, part=part: part.export(p, file_type="stl"))
    return out


def _atomic(path: Path, writer) -> Path:
    with atomic_path(path) as tmp:
        writer(str(tmp))
    return path
