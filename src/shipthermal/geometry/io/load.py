"""Loading a user's surface file: formats, units, header checks, welding coincident vertices."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...errors import InputError, require
from ..meshfiles import ascii_stl_problem, sniff_mesh_file

__all__ = ["UNITS", "TRIMESH_EXTENSIONS", "PYVISTA_EXTENSIONS", "MESH_EXTENSIONS",
           "load_surface", "weld"]

UNITS = {"m": 1.0, "mm": 1e-3}
"""Accepted length units and their factor to metres."""

TRIMESH_EXTENSIONS = frozenset({".stl", ".obj", ".ply", ".off", ".glb", ".gltf"})
"""Surface formats read with trimesh."""
PYVISTA_EXTENSIONS = frozenset({".vtk", ".vtp", ".vtu"})
"""Surface formats read with pyvista; they may carry a per-cell ``part`` array."""
MESH_EXTENSIONS = tuple(sorted(TRIMESH_EXTENSIONS | PYVISTA_EXTENSIONS))
"""Every surface format :func:`load_surface` reads (sorted)."""


def load_surface(path, units: str, field: str = "ship.files.mesh"):
    """Read a triangulated surface (STL/OBJ/PLY/OFF via trimesh, VTK/VTP/VTU via pyvista).

    Triangles keep the file's order (polygons are triangulated in place), so face ranges
    in a part map refer to triangles as loaded. Coincident vertices (STL stores none
    shared) are merged. The file's header is checked first
    (:func:`.meshfiles.sniff_mesh_file`: size limits, declared triangle count, format);
    a file the parser cannot read is an :class:`InputError` naming ``field``.

    Returns
    -------
    vertices (N, 3) [m], faces (M, 3), cell_part (M,) or None, part_names or None
    """
    require(units in UNITS, "ship.files.units", units, "must be declared: 'm' or 'mm'",
            'Set ship.files.units = "m" or "mm" (the unit the file\'s coordinates are in)')
    path = Path(path)
    require(path.is_file(), field, str(path), "must be an existing file", "Check the path")
    ext = path.suffix.lower()
    if ext not in TRIMESH_EXTENSIONS | PYVISTA_EXTENSIONS:
        raise InputError(field, str(path), "unsupported file type",
                         f"Use one of {', '.join(MESH_EXTENSIONS)}")
    info = sniff_mesh_file(path, field)
    cell_part = part_names = None
    try:
        if ext in TRIMESH_EXTENSIONS:
            import trimesh      # deferred: start-up cost (trimesh takes ~1.5 s to import)

            mesh = trimesh.load(path, force="mesh", process=False)
            v = np.asarray(mesh.vertices, float)
            f = np.asarray(getattr(mesh, "faces", np.zeros((0, 3))), np.int64)
        else:
            import pyvista as pv    # deferred: start-up cost (~1 s to import)

            data = pv.read(path)
            if not isinstance(data, pv.PolyData):
                data = data.extract_surface(pass_cellid=False, algorithm="dataset_surface")
            tri = data.triangulate()
            require(tri.is_all_triangles, field, path.name, "must contain polygons")
            v = np.asarray(tri.points, float)
            f = np.asarray(tri.faces).reshape(-1, 4)[:, 1:].astype(np.int64)
            if "part" in tri.cell_data:
                cell_part = np.asarray(tri.cell_data["part"]).astype(np.int64)
            if "part_names" in tri.field_data:
                part_names = tuple(str(x) for x in tri.field_data["part_names"])
    except InputError:
        raise
    except MemoryError:
        raise InputError(field, path.name, f"is too large to read here ({info['bytes']:,} "
                         "bytes)", "Export the ship coarser") from None
    except Exception:                      # a parser's complaint: the file is damaged
        raise _unreadable(path, info, field) from None
    fmt = {"stl_binary": "STL", "stl_ascii": "STL"}.get(info["format"], ext[1:].upper())
    require(len(f) > 0, field, path.name, f"holds no triangles (read as {fmt})",
            "Export the ship surface as triangles (not points, lines or an empty scene)")
    bad = ~np.isfinite(v)
    if bad.any():
        raise InputError(field, path.name, f"has {int(bad.any(axis=1).sum())} vertices whose "
                         "coordinates are not finite numbers (NaN or inf)",
                         "Export the ship again; check the CAD model for broken geometry")
    v = v * UNITS[units]
    v, f = weld(v, f)
    return v, f, cell_part, part_names


def _unreadable(path: Path, info: dict, field: str) -> InputError:
    """The message for a file its parser refused (the file's contents are not quoted)."""
    fmt = info["format"]
    if fmt == "stl_ascii":
        where = ascii_stl_problem(path)
        if where:
            return InputError(field, path.name, f"is not a readable ASCII STL ({where})",
                              "Fix that line or export the ship again")
    if fmt == "ply":
        n = info["triangles"]
        return InputError(field, path.name, "is not a readable PLY file: its body does not "
                          f"hold what its header declares ({n:,} faces)" if n is not None else
                          "is not a readable PLY file", "The file is truncated or damaged: "
                          "export the ship again")
    name = {"stl_binary": "STL", "stl_ascii": "ASCII STL"}.get(fmt, fmt.upper())
    return InputError(field, path.name, f"cannot be read as {name} (damaged, "
                      "truncated or another format)", "Export the ship again, or give the "
                      "file the suffix of its format")


def weld(v: np.ndarray, f: np.ndarray, rel_tol: float = 1e-9):
    """Merge coincident vertices (no triangle is dropped: degenerate ones are reported later)."""
    # deferred: start-up cost (scipy.sparse.csgraph and scipy.spatial take ~1 s to import)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    scale = float(np.ptp(v, axis=0).max()) or 1.0
    pairs = cKDTree(v).query_pairs(rel_tol * scale, output_type="ndarray")
    n = len(v)
    g = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, lab = connected_components(g, directed=False)
    _, first = np.unique(lab, return_index=True)
    used = np.unique(lab[f])
    remap = np.full(lab.max() + 1, -1)
    remap[used] = np.arange(len(used))
    return v[first][used], remap[lab[f]]
