"""User ship meshes: reading, part maps, checks and optional repair; writing ship files.

A user ship is either **one file per part** (``{"hull": "hull.stl", "deck": "deck.stl",
"superstructure": "sup.obj"}``) or **one mesh plus a part map**: a per-triangle array of
part indices or names, a JSON file / dict of face ranges ``{"deck": [[0, 1200]], ...}``, or a
``part`` cell array inside a VTK file. Units must be declared (``'m'`` or ``'mm'``).

The surface must be a closed, consistently wound triangulation with outward normals. Checks
(each raising :class:`~shipthermal.errors.InputError` with what to do):

* scale sanity — a 130 000 m or 1 cm ship is a units mistake, not a ship;
* axes — the longest dimension must be x (bow +x, y port, z up);
* degenerate (zero-area) and duplicate triangles — error, or with ``clean=True`` collinear
  needles at T-junctions are flipped into their neighbour (surface stays closed, area
  unchanged) and the rest dropped (counted in the report);
* watertightness — open edges (gaps, a missing face) and edges shared by more than two
  triangles; ``repair='tetwild'`` remeshes through pytetwild instead (area and volume
  change reported);
* self-intersections — e.g. overlapping solids exported without a union: error, or
  ``repair='tetwild'``;
* orientation — inconsistent winding or inward normals (signed volume < 0): error, or
  fixed with ``fix_normals=True`` (reported).

A part named ``hull`` is split exactly at the waterline into ``hull_wetted``/``hull_dry``.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from ..errors import InputError, check_finite, require
from .cad import SHIP_LENGTH_RANGE
from .layups import compartment_temperatures, default_layups, outer_media
from .meshfiles import ascii_stl_problem, sniff_mesh_file
from .outside import classify_pieces, part_sense, sliver_share
from .parts import (MAIN_PARTS, boundary_edges, face_areas, main_part, signed_volume,
                    split_at_waterline)
from .ship_geometry import ShipGeometry
from .surface_ops import fix_winding

__all__ = ["UNITS", "SHIP_LENGTH_RANGE", "TRIMESH_EXTENSIONS", "PYVISTA_EXTENSIONS",
           "MESH_EXTENSIONS", "load_surface", "read_part_map", "check_surface",
           "read_ship", "write_ship"]

UNITS = {"m": 1.0, "mm": 1e-3}
"""Accepted length units and their factor to metres."""

TRIMESH_EXTENSIONS = frozenset({".stl", ".obj", ".ply", ".off", ".glb", ".gltf"})
"""Surface formats read with trimesh."""
PYVISTA_EXTENSIONS = frozenset({".vtk", ".vtp", ".vtu"})
"""Surface formats read with pyvista; they may carry a per-cell ``part`` array."""
MESH_EXTENSIONS = tuple(sorted(TRIMESH_EXTENSIONS | PYVISTA_EXTENSIONS))
"""Every surface format :func:`load_surface` reads (sorted)."""


# ---------------------------------------------------------------------------------------
# Loading
# ---------------------------------------------------------------------------------------
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
            import trimesh

            mesh = trimesh.load(path, force="mesh", process=False)
            v = np.asarray(mesh.vertices, float)
            f = np.asarray(getattr(mesh, "faces", np.zeros((0, 3))), np.int64)
        else:
            import pyvista as pv

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
    v, f = _weld(v, f)
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


def _weld(v: np.ndarray, f: np.ndarray, rel_tol: float = 1e-9):
    """Merge coincident vertices (no triangle is dropped: degenerate ones are reported later)."""
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


def read_part_map(part_map, n_faces: int, part_names: Sequence[str] | None = None):
    """Per-triangle part labels from a part map.

    Parameters
    ----------
    part_map : array, dict or path
        * (M,) ints indexing ``part_names``, or (M,) part-name strings;
        * ``{part: [[start, stop], ...]}`` face ranges (stop exclusive), or a JSON file
          holding that mapping (optionally under a ``"parts"`` key).
    n_faces : int
        Number of triangles of the mesh.

    Returns
    -------
    labels (M,) int, names tuple
    """
    if isinstance(part_map, (str, os.PathLike)):
        path = Path(part_map)
        require(path.exists(), "part_map", str(path), "file not found")
        with open(path) as fh:
            part_map = json.load(fh)
        if isinstance(part_map, dict) and "parts" in part_map:
            part_map = part_map["parts"]
    if isinstance(part_map, Mapping):
        names = tuple(part_map)
        labels = np.full(n_faces, -1, np.int64)
        for k, name in enumerate(names):
            ranges = part_map[name]
            ranges = [ranges] if len(ranges) == 2 and np.isscalar(ranges[0]) else ranges
            for r in ranges:
                require(len(r) == 2 and 0 <= int(r[0]) <= int(r[1]) <= n_faces,
                        f"part_map[{name!r}]", r, f"must be [start, stop] with 0 <= start <= stop <= {n_faces}")
                seg = labels[int(r[0]):int(r[1])]
                clash = seg >= 0
                if clash.any():
                    i = int(r[0]) + int(np.argmax(clash))
                    raise InputError(f"part_map[{name!r}]", r, f"overlaps part {names[seg[clash][0]]!r} "
                                     f"at face {i}: every face must belong to exactly one part")
                labels[int(r[0]):int(r[1])] = k
        missing = np.flatnonzero(labels < 0)
        if len(missing):
            raise InputError("part_map", f"{len(missing)} faces without a part",
                             f"must cover every face exactly once (first uncovered: face {missing[0]})",
                             f"Add ranges so that faces 0..{n_faces - 1} are all assigned")
        return labels, names
    arr = np.asarray(part_map)
    require(arr.shape == (n_faces,), "part_map", arr.shape, f"must hold one entry per face ({n_faces})")
    if arr.dtype.kind in "US":
        names, labels = np.unique(arr, return_inverse=True)
        return labels.astype(np.int64), tuple(str(n) for n in names)
    require(part_names is not None, "part_names", None, "are required with an integer part map")
    labels = arr.astype(np.int64)
    require(labels.min() >= 0 and labels.max() < len(part_names), "part_map",
            (int(labels.min()), int(labels.max())), f"must index part_names (0..{len(part_names) - 1})")
    return labels, tuple(part_names)


# ---------------------------------------------------------------------------------------
# Checks
# ---------------------------------------------------------------------------------------
def _check_scale(v: np.ndarray, units: str) -> None:
    ext = np.ptp(v, axis=0)
    length = float(ext[0])
    lo, hi = SHIP_LENGTH_RANGE
    if int(np.argmax(ext)) != 0:
        raise InputError("vertices", f"extent x {ext[0]:.4g} m, y {ext[1]:.4g} m, z {ext[2]:.4g} m",
                         "the longest dimension must lie along x (x forward, y to port, z up)",
                         "Rotate the mesh so the bow points to +x and the masts to +z")
    if lo <= length <= hi:
        return
    if length > hi:
        hint = ("it looks like millimetres: declare units='mm'" if units == "m" and lo <= length / 1e3 <= hi
                else "check the unit of the file")
        raise InputError("units", units, f"gives a ship length of {length:.6g} m, outside the plausible "
                         f"{lo:g}–{hi:g} m", f"Is the unit right? {hint} (or check_scale=False for a "
                         "deliberate non-ship geometry)")
    if units == "mm" and lo <= length * 1e3 <= hi:
        hint = "it looks like metres: declare units='m'"
    elif lo <= length * 1e2 <= hi:
        hint = "centimetres or a scale model? rescale the file to metres or millimetres"
    else:
        hint = "check the unit of the file"
    raise InputError("units", units, f"gives a ship length of {length:.6g} m, outside the plausible "
                     f"{lo:g}–{hi:g} m", f"Is the unit right? {hint} (or check_scale=False for a "
                     "deliberate small model)")


def check_surface(vertices, faces, units: str = "m", *, check_scale: bool = True,
                  clean: bool = False, fix_normals: bool = False, require_closed: bool = True,
                  face_part: np.ndarray | None = None, allow_nonmanifold: bool = False,
                  check_intersections: bool = True):
    """Check (and on request clean / re-orient) a ship surface.

    Parameters
    ----------
    vertices : (N, 3) [m]
    faces : (M, 3)
    units : str
        Declared unit, only to word the scale message.
    check_scale : bool
        Reject lengths outside :data:`SHIP_LENGTH_RANGE`.
    clean : bool
        Remove zero-area and duplicate triangles instead of rejecting them.
    fix_normals : bool
        Make winding consistent and normals outward instead of rejecting them.
    require_closed : bool
        Reject open surfaces (needed for shells to know their inside, and for tets).
    face_part : (M,) array, optional
        Carried along when triangles are removed.
    allow_nonmanifold : bool
        Accept edges shared by more than two triangles (the boundary of a tetrahedral
        mesh can touch itself along an edge); they are counted in the report.
    check_intersections : bool
        Reject self-intersecting surfaces (edges piercing triangles, found with Embree
        ray casts; coplanar overlaps are not detected).

    Returns
    -------
    vertices, faces, face_part, report (dict: ``degenerate_faces`` found, of which
    ``needles_flipped`` (collinear needles at T-junctions, flipped away: closed surface,
    unchanged area) and ``removed_degenerate`` (dropped); ``removed_duplicate``,
    ``flipped_faces``, ``open_edges``, ``nonmanifold_edges``, ``signed_volume`` [m3],
    ``area`` [m2])
    """
    v = np.asarray(vertices, float)
    f = np.asarray(faces, np.int64)
    lab = np.zeros(len(f), np.int64) if face_part is None else np.asarray(face_part, np.int64)
    check_finite("vertices", v)
    require(f.ndim == 2 and f.shape[1] == 3 and len(f) > 0, "faces", f.shape, "must be (M, 3), M > 0")
    report = dict(removed_degenerate=0, removed_duplicate=0, flipped_faces=0)
    if check_scale:
        _check_scale(v, units)
    scale = float(np.ptp(v, axis=0).max())

    # Degenerate triangles: a repeated vertex or (numerically) no area.
    area = face_areas(v, f)
    degenerate = ((f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 2] == f[:, 0])
                  | (area <= 1e-14 * scale * scale))
    if degenerate.any():
        idx = np.flatnonzero(degenerate)
        if not clean:
            raise InputError("faces", f"{len(idx)} zero-area triangles (first: face {idx[0]}, "
                             f"vertices {f[idx[0]].tolist()})",
                             "every triangle must have a positive area",
                             "Remove them in the CAD export, or pass clean=True (needles at "
                             "T-junctions are flipped away, others dropped; reported)")
        f, lab, resolved = _flip_needles(v, f, lab, idx)
        keep = ~degenerate
        keep[idx[resolved]] = True                 # rows now holding a flipped triangle
        f, lab = f[keep], lab[keep]
        report["degenerate_faces"] = int(len(idx))
        report["needles_flipped"] = int(resolved.sum())
        report["removed_degenerate"] = int(len(idx) - resolved.sum())

    # Duplicate triangles (same three vertices, either orientation).
    key = np.sort(f, axis=1)
    _, first, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
    if (counts > 1).any():
        n_dup = int(len(f) - len(first))
        if not clean:
            dup_rows = np.flatnonzero(~np.isin(np.arange(len(f)), first))
            raise InputError("faces", f"{n_dup} duplicate triangles (first: face {dup_rows[0]})",
                             "every triangle must appear once",
                             "Remove the duplicates (often a part exported twice), or pass clean=True (reported)")
        keep = np.sort(first)
        f, lab = f[keep], lab[keep]
        report["removed_duplicate"] = n_dup

    open_e, nonman = boundary_edges(f)
    report["open_edges"] = int(len(open_e))
    report["nonmanifold_edges"] = int(len(nonman))
    if allow_nonmanifold:
        nonman = nonman[:0]
    if require_closed and (len(open_e) or len(nonman)):
        where = v[open_e[0]].mean(axis=0) if len(open_e) else v[nonman[0]].mean(axis=0)
        kind = (f"{len(open_e)} open edges (used by one triangle)" if len(open_e)
                else f"{len(nonman)} edges shared by more than two triangles")
        raise InputError("surface", kind + f", first near (x, y, z) = ({where[0]:.3f}, {where[1]:.3f}, "
                         f"{where[2]:.3f}) m",
                         "the ship surface (hull + deck + superstructure) must be closed (watertight)",
                         "Close the gap in CAD, or pass repair='tetwild' to remesh it robustly "
                         "(pytetwild closes gaps; the change in area and volume is reported)")

    if require_closed and check_intersections:
        try:
            from ..mesh import find_self_intersections
        except ImportError:                      # the FV mesh package is absent
            find_self_intersections = None
            report["self_intersections_found"] = "not checked (shipthermal.mesh unavailable)"
        pairs = (find_self_intersections(v, f, max_report=1) if find_self_intersections
                 else np.zeros((0, 2), int))
        if find_self_intersections:
            report["self_intersections_found"] = int(len(pairs) > 0)
        if len(pairs):
            i, j = (int(x) for x in pairs[0])
            where = v[f[i]].mean(axis=0)
            raise InputError("surface", f"triangles {i} and {j} cross near (x, y, z) = "
                             f"({where[0]:.3f}, {where[1]:.3f}, {where[2]:.3f}) m",
                             "the ship surface must not intersect itself (overlapping solids "
                             "exported without a boolean union, or a folded face)",
                             "Unite the solids in CAD, or pass repair='tetwild' (reported)")

    # Orientation: consistent winding (each interior edge once in each direction), outward.
    directed = f[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    _, dcount = np.unique(directed, axis=0, return_counts=True)
    consistent = bool((dcount == 1).all())
    if not consistent:
        if not fix_normals:
            raise InputError("faces", f"{int((dcount > 1).sum())} edges traversed twice in the same direction",
                             "triangle winding must be consistent (normals all outward)",
                             "Re-export with consistent normals, or pass fix_normals=True (reported)")
        f, flipped = fix_winding(f)
        report["flipped_faces"] = int(flipped.sum())
    vol = signed_volume(v, f)
    if require_closed and vol < 0:
        if not fix_normals:
            raise InputError("signed volume", f"{vol:.6g} m3",
                             "must be > 0: the normals point into the ship",
                             "Flip the normals in CAD, or pass fix_normals=True to reverse every "
                             "triangle (reported)")
        f = f[:, ::-1].copy()
        report["flipped_faces"] = int(len(f)) - report["flipped_faces"]
        vol = -vol
    report["signed_volume"] = float(vol)
    report["area"] = float(face_areas(v, f).sum())
    return v, f, lab, report


def _flip_needles(v: np.ndarray, f: np.ndarray, lab: np.ndarray, idx: np.ndarray):
    """Resolve zero-area "needles" (three distinct, collinear vertices) by an edge flip.

    A needle ``(a, b, m)`` with ``m`` strictly inside the segment ``ab`` is what CAD exports
    leave at a T-junction: the triangle ``N = (b, a, c)`` across the long edge does not know
    about ``m``. Flipping the long edge replaces the needle and ``N`` by ``(b, m, c)`` and
    ``(m, a, c)``: the surface stays closed and consistently wound, and since ``m`` lies on
    ``ab`` no area, volume or shape changes (the two new triangles tile ``N``). Both take the
    part of ``N``. Needles whose neighbour is missing, degenerate or already used, and
    triangles with a repeated vertex, are left to be dropped.

    Returns ``(faces, labels, resolved)``: ``resolved[k]`` is True where ``idx[k]`` now holds
    a flipped (non-degenerate) triangle.
    """
    f = f.copy()
    lab = lab.copy()
    resolved = np.zeros(len(idx), bool)
    bad = np.zeros(len(f), bool)
    bad[idx] = True
    owner = {}
    for t, tri in enumerate(f):
        for k in range(3):
            owner.setdefault((int(tri[k]), int(tri[(k + 1) % 3])), []).append(t)
    used = np.zeros(len(f), bool)
    for k, d in enumerate(idx):
        tri = [int(x) for x in f[d]]
        if len(set(tri)) < 3:
            continue
        p = v[tri]
        # The long edge is opposite the middle vertex; rotate it to (a, b, m).
        opp = np.linalg.norm(p[[1, 2, 0]] - p[[2, 0, 1]], axis=1)   # edge opposite vertex i
        r = int(np.argmax(opp))
        a, b, m = tri[(r + 1) % 3], tri[(r + 2) % 3], tri[r]
        ab = v[b] - v[a]
        t_m = float(np.dot(v[m] - v[a], ab) / np.dot(ab, ab))
        if not 1e-9 < t_m < 1.0 - 1e-9:
            continue
        nbrs = [t for t in owner.get((b, a), []) if t != d]
        if len(nbrs) != 1 or bad[nbrs[0]] or used[nbrs[0]] or used[d]:
            continue
        n = nbrs[0]
        c = next(int(x) for x in f[n] if x != a and x != b)
        f[n] = (b, m, c)
        f[d] = (m, a, c)
        lab[d] = lab[n]
        used[n] = used[d] = True
        resolved[k] = True
    return f, lab, resolved


# ---------------------------------------------------------------------------------------
# Reading a ship
# ---------------------------------------------------------------------------------------
def read_ship(source, units: str | None = None, part_map=None, part_names: Sequence[str] | None = None,
              *, draught: float | None = None, waterline_z: float | None = None,
              name: str | None = None, layups: Mapping | None = None,
              compartment_temperature: Mapping | None = None, clean: bool = False,
              fix_normals: bool = False, repair: str | None = None,
              repair_edge_length: float | None = None, check_scale: bool = True,
              recentre: bool = True, max_repair_change: float | None = None):
    """Read a user ship and return it checked, positioned and split into parts.

    Parameters
    ----------
    source : path or mapping part → path
        One mesh file (with ``part_map`` or a ``part`` cell array), or one file per part.
    units : {'m', 'mm'}
        Unit of the file coordinates (required).
    part_map : array, dict, path or 'auto', optional
        See :func:`read_part_map`. ``'auto'``: parts by rules (:func:`.cad.assign_parts`);
        the report's ``auto_parts`` then holds the face ranges to edit and reuse. Without
        a part map, OBJ groups / GLB named meshes name the parts.
    part_names : sequence of str, optional
        Names for an integer part map.
    draught : float, optional
        Keel depth below the waterline [m]: the waterline is ``min z + draught``.
    waterline_z : float, optional
        Height of the waterline in the file's frame [m, after unit conversion]. Without
        either, the file's z = 0 is taken as the waterline.
    name : str, optional
    layups, compartment_temperature : mapping, optional
        Overrides of the defaults (:mod:`.layups`).
    clean : bool
        Drop zero-area and duplicate triangles (reported) instead of failing.
    fix_normals : bool
        Fix inconsistent / inward normals (reported) instead of failing.
    repair : {None, 'union', 'tetwild'}
        Before the checks: ``'union'`` unites closed overlapping pieces exactly
        (manifold3d, seconds); ``'tetwild'`` remeshes through pytetwild (closes gaps,
        resolves self-intersections; minutes for large soups). Area and volume change
        are reported and limited by ``max_repair_change``.
    repair_edge_length : float, optional
        Target edge length of the repair [m] (default: pytetwild's, 5 % of the bounding
        box diagonal; finer is much slower, e.g. ~50 s at 1 m for a 100 m box).
    check_scale : bool
        Reject implausible ship sizes (units mistakes).
    recentre : bool
        Move the origin amidships on the centreline (x, y of the bounding-box centre).
    max_repair_change : float, optional
        Largest relative change of area or volume a repair may make (default
        :data:`.cad.MAX_REPAIR_CHANGE`).

    Returns
    -------
    ship : ShipGeometry
    report : dict
        What was checked and changed (``removed_degenerate``, ``removed_duplicate``,
        ``flipped_faces``, ``repair`` (area/volume before and after), ``translation`` [m]);
        ``repairs``: one line per change made, for the console.

    Raises
    ------
    InputError
        Every problem found, in one error naming the options (the scenario keys
        ``ship.files.*``) that fix each one.
    """
    from .cad import (FIXED_BY, MAX_REPAIR_CHANGE, SCENE_EXTENSIONS, assign_parts,
                      diagnose_surface, load_named_parts, part_ranges, problems_message,
                      repair_change_check, union_repair)

    require(units in UNITS, "ship.files.units", units, "must be declared: 'm' or 'mm'",
            'Set ship.files.units = "m" or "mm" (the unit the file\'s coordinates are in)')
    require(repair in (None, "union", "tetwild"), "ship.files.repair", repair,
            "must be 'none', 'union' or 'tetwild'")
    max_change = MAX_REPAIR_CHANGE if max_repair_change is None else float(max_repair_change)
    auto = isinstance(part_map, str) and part_map == "auto"
    report: dict = {"units": units}
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
        v, f = _weld(np.concatenate(vs), np.concatenate(fs))
        labels = np.concatenate(labs)
        names = tuple(names)
        src_name = name or "user_ship"
    elif (part_map is None and Path(source).suffix.lower() in SCENE_EXTENSIONS
          and sniff_mesh_file(source) is not None
          and (named := load_named_parts(source, UNITS[units])) is not None):
        check_finite(f"ship.files.mesh ({Path(source).name}) vertices", named[0])
        v, f = _weld(named[0], named[1])
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

    # Every problem at once, each with the keys that fix it; the ones the options handle
    # are repaired below.
    enabled = {"clean": clean, "fix_normals": fix_normals, "repair": repair is not None,
               "check_scale": not check_scale}
    problems = diagnose_surface(v, f, units, check_scale=check_scale)
    report["problems_found"] = [str(p) for p in problems]
    left = [p for p in problems if not enabled.get(FIXED_BY.get(p.kind, ""), False)]
    if left:
        raise problems_message(source if not isinstance(source, Mapping) else
                               ", ".join(str(x) for x in source.values()), left)
    lines = report["repairs"] = []
    report["warnings"] = []
    n_file_faces = len(f)
    if repair is not None and any(p.kind in ("open", "nonmanifold", "intersecting")
                                  for p in problems):
        if clean and repair == "tetwild":      # no zero-area / duplicate triangles
            # (and consistently wound: fTetWild's inside test uses the winding number)
            v, f, labels, pre = check_surface(v, f, units, check_scale=False, clean=True,
                                              fix_normals=True, face_part=labels,
                                              require_closed=False)
        v, f, labels, rep = _repair_once(v, f, labels, repair, repair_edge_length, lines)
        report["repair"] = rep
        lines.append(f"repair ({rep['method']}, {rep['seconds']:.1f} s): area "
                     f"{rep['area_before']:.6g} -> {rep['area_after']:.6g} m2 "
                     f"({100 * rep['area_change']:+.2f} %), volume {rep['volume_before']:.6g} -> "
                     f"{rep['volume_after']:.6g} m3 ({100 * rep['volume_change']:+.2f} %)")
        repair_change_check(rep, max_change)
    a_before = float(face_areas(v, f).sum())
    v, f, labels, chk = check_surface(v, f, units, check_scale=False, clean=clean,
                                      fix_normals=fix_normals, face_part=labels,
                                      allow_nonmanifold=repair is not None)
    report.update(chk)
    if chk["removed_degenerate"] or chk["removed_duplicate"] or chk.get("needles_flipped"):
        lines.append(f"clean: {chk['removed_duplicate']} duplicate and "
                     f"{chk['removed_degenerate']} zero-area triangles removed, "
                     f"{chk.get('needles_flipped', 0)} needles flipped; area {a_before:.6g} -> "
                     f"{chk['area']:.6g} m2 ({100 * (chk['area'] / a_before - 1):+.4f} %)")
    if chk["flipped_faces"]:
        lines.append(f"fix_normals: {chk['flipped_faces']} triangles re-oriented (area and "
                     f"volume unchanged, volume {chk['signed_volume']:.6g} m3)")

    # The outside, by ray casting: interior shells removed, inside-out pieces turned.
    v, f, labels, outside = _outside_checked(v, f, labels, fix_normals, source, lines)
    report["outside"] = outside

    # Position: waterline at z = 0, origin amidships on the centreline.
    height = float(np.ptp(v[:, 2]))
    if draught is not None:
        require(0 < draught < height, "ship.files.draught", draught,
                f"must lie between 0 and the height of the mesh ({height:.3f} m)",
                "It is the keel depth below the waterline")
        z_wl = float(v[:, 2].min() + draught)
    elif waterline_z is not None:
        z_wl = float(waterline_z)
    else:
        z_wl = 0.0
    if not v[:, 2].min() < z_wl < v[:, 2].max():
        key = "ship.files.waterline_z" if waterline_z is not None and draught is None else \
            "waterline (z = 0 of the file)" if draught is None else "ship.files.draught"
        raise InputError(key, z_wl, f"must cut the ship (z from {v[:, 2].min():.3f} to "
                         f"{v[:, 2].max():.3f} m)", "Set ship.files.draught (keel depth "
                         "below the waterline) or ship.files.waterline_z")
    shift = np.array([0.0, 0.0, -z_wl])
    if recentre:
        mid = 0.5 * (v.min(axis=0) + v.max(axis=0))
        shift[:2] = -mid[:2]
    v = v + shift
    report["translation"] = shift.tolist()
    if auto:
        labels, names, info = assign_parts(v, f)
        report["auto_parts"] = dict(
            parts=part_ranges(labels, names), units=units, rules=info,
            faces_as_in_file=bool(len(f) == n_file_faces and "repair" not in report),
            note="parts assigned by rules (hull below the waterline and on the sides, deck "
                 "= upward faces at deck level, superstructure above): check the picture; "
                 "edit the face ranges and give this file as ship.files.part_map")

    # Parts: split 'hull' at the waterline; other parts keep their faces.
    v, f, labels, _ = split_at_waterline(v, f, labels, 0.0, tol=1e-9 * float(np.ptp(v[:, 0])))
    zc = v[f, 2].mean(axis=1)
    final = [n for n in MAIN_PARTS if n in names or (n.startswith("hull_") and "hull" in names)]
    final += sorted(n for n in names if n not in final and n != "hull")
    new_lab = np.empty(len(f), np.int64)
    for k, n in enumerate(names):
        sel = labels == k
        if n == "hull":
            new_lab[sel & (zc < 0)] = final.index("hull_wetted")
            new_lab[sel & (zc >= 0)] = final.index("hull_dry")
        else:
            new_lab[sel] = final.index(n)
    counts = np.bincount(new_lab, minlength=len(final))
    keep = [n for k, n in enumerate(final) if counts[k] > 0]
    remap = np.array([keep.index(n) if n in keep else -1 for n in final])
    face_part = remap[new_lab]
    wet = [k for k, n in enumerate(keep) if main_part(n) == "hull_wetted"]
    report["wetted_faces_above_waterline"] = int(np.sum(np.isin(face_part, wet) & (zc > 1e-9)))

    length = float(np.ptp(v[:, 0]))
    deck_k = [k for k, n in enumerate(keep) if main_part(n) == "deck"]
    deck_z = v[f[np.isin(face_part, deck_k)]].reshape(-1, 3)
    mid = np.abs(deck_z[:, 0]) < 0.1 * length
    freeboard = float(np.median(deck_z[mid, 2])) if mid.any() else float("nan")
    refusals, warnings = part_sense(v, f, face_part, keep, freeboard)
    if refusals:
        fix = ("The parts were assigned by rules (part_map = \"auto\"): check the mesh "
               "(ship.files.draught, inside shells) or give ship.files.part_map"
               if auto else "Check ship.files.part_map (or the part names in the file) and "
               "ship.files.draught / waterline_z")
        raise InputError("ship.files.part_map" if not isinstance(source, Mapping)
                         else "ship.files.parts", "auto" if auto else "as given",
                         "; ".join(refusals), fix)
    for w in warnings:
        report["warnings"].append(f"{w} (check ship.files.part_map)")
    share, edge = sliver_share(v, f)
    report["sliver_share"] = share
    report["equilateral_edge_m"] = edge
    hull_k = [k for k, n in enumerate(keep) if main_part(n) in ("hull_wetted", "hull_dry")]
    hull_v = v[f[np.isin(face_part, hull_k)]].reshape(-1, 3) if hull_k else v
    ship = ShipGeometry(
        vertices=v, faces=f, face_part=face_part, part_names=tuple(keep),
        layups=default_layups(keep, layups), compartment_temperature=compartment_temperatures(
            keep, compartment_temperature), outer_medium=outer_media(keep),
        length=length, beam=float(np.ptp(hull_v[:, 1])), draught=float(-v[:, 2].min()),
        freeboard=freeboard, name=src_name, provenance=f"user mesh ({units})",
        edge_length=float(np.median(np.linalg.norm(v[f[:, 0]] - v[f[:, 1]], axis=1))))
    return ship, report


def _repair_once(v, f, labels, method: str, edge_length, lines: list):
    """A repair (:func:`.cad.union_repair` or :func:`.remesh.tetwild_surface`), computed
    once per input and settings and reused from the cache afterwards
    (:mod:`.repair_cache`: fTetWild is not deterministic, so every read of the same file
    must get the first repair's surface)."""
    from .cad import union_repair
    from .repair_cache import load_repaired, repair_key, save_repaired

    key = repair_key(v, f, labels, method, edge_length=edge_length)
    cached = load_repaired(key)
    if cached is not None:
        nv, nf, nl, rep, path = cached
        rep = dict(rep, cache=str(path), reused=True)
        lines.append(f"repair ({method}): the repaired surface of this file computed before, "
                     f"reused from the cache ({path.name})")
        return nv, nf, nl, rep
    if method == "union":
        nv, nf, nl, rep = union_repair(v, f, labels)
    else:
        from .remesh import tetwild_surface

        nv, nf, nl, rep = tetwild_surface(v, f, labels, edge_length=edge_length)
        rep["method"] = "tetwild"
    path, why = save_repaired(key, nv, nf, nl, rep)
    rep = dict(rep, cache=str(path) if path else None, reused=False)
    if path is None:
        lines.append(f"repair ({method}): the repaired surface could not be cached ({why}); "
                     "another read of this file may repair it differently")
    return nv, nf, nl, rep


def _outside_checked(v, f, labels, fix_normals: bool, source, lines: list):
    """Ray-cast outside test (:func:`.outside.classify_pieces`): interior shells are
    removed (reported), inside-out pieces are turned with ``fix_normals`` or refused,
    stray inward or enclosed triangles above 1 % of the area are refused."""
    from .cad import Problem, problems_message

    rep = classify_pieces(v, f)
    area = face_areas(v, f)
    total = float(area.sum())
    out = {"pieces": int(rep.piece.max()) + 1 if len(rep.piece) else 0,
           "interior_pieces": len(rep.interior_pieces),
           "inverted_pieces": len(rep.inverted_pieces),
           "stray_inward_faces": rep.stray_inward, "stray_enclosed_faces": rep.stray_enclosed}
    where = source if not isinstance(source, Mapping) else ", ".join(
        str(x) for x in source.values())
    inverted = rep.inverted_faces
    if inverted.any():
        if not fix_normals:
            c = v[f[np.flatnonzero(inverted)[0]]].mean(axis=0)
            raise problems_message(where, [Problem(
                "inverted_piece", f"{len(rep.inverted_pieces)} separate piece(s) "
                f"({int(inverted.sum())} triangles, {100 * area[inverted].sum() / total:.1f} % "
                f"of the area; first near ({c[0]:.3f}, {c[1]:.3f}, {c[2]:.3f}) m) are "
                "inside-out: their normals point into themselves (ray casting: only the back "
                "of their triangles sees the outside)", "ship.files.fix_normals = true")])
        f = f.copy()
        f[inverted] = f[inverted][:, ::-1]
        lines.append(f"fix_normals: {len(rep.inverted_pieces)} inside-out piece(s) turned "
                     f"({int(inverted.sum())} triangles; ray casting)")
        out["inverted_faces_turned"] = int(inverted.sum())
    interior = rep.interior_faces
    if interior.any():
        if interior.all():
            raise InputError("ship.files.mesh", str(where), "has no outer surface: no "
                             "triangle sees the outside (ray casting)", "Check the file")
        a_int = float(area[interior].sum())
        lines.append(f"interior shells removed: {len(rep.interior_pieces)} closed piece(s) "
                     f"inside the ship ({int(interior.sum())} triangles, {a_int:.6g} m2 = "
                     f"{100 * a_int / total:.1f} % of the area; no ray from either side of "
                     "them reaches the outside)")
        out["interior_faces_removed"] = int(interior.sum())
        out["interior_area_removed_m2"] = a_int
        keep = ~interior
        f, labels = f[keep], np.asarray(labels)[keep]
        used, inv = np.unique(f, return_inverse=True)
        v, f = v[used], inv.reshape(-1, 3)
    stray = ~rep.interior_faces & ~rep.inverted_faces & (rep.inward | rep.enclosed)
    a_stray = float(area[stray].sum()) / total if stray.any() else 0.0
    out["stray_area_share"] = a_stray
    if a_stray > 0.01:
        raise problems_message(where, [Problem(
            "inward", f"{int(stray.sum())} triangles ({100 * a_stray:.1f} % of the area) of the "
            "outer surface face into the ship or see the outside from neither side (ray "
            "casting)", 'ship.files.repair = "tetwild", or fix the normals in CAD')])
    return v, f, labels, out


# ---------------------------------------------------------------------------------------
# Writing
# ---------------------------------------------------------------------------------------
def write_ship(ship: ShipGeometry, directory, stem: str | None = None) -> dict[str, Path]:
    """Write a ship as files a user can open and read back with :func:`read_ship`.

    * ``<stem>.ply`` — the whole surface, triangles sorted by part;
    * ``<stem>_parts.json`` — the part map (face ranges), units, particulars, layups;
    * ``<stem>_parts/<part>.stl`` — one binary STL per part.

    Returns the written paths by kind.
    """
    import trimesh

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
    tmp = path.with_name(f".{path.name}.tmp{os.getpid()}")
    try:
        writer(str(tmp))
        os.replace(tmp, path)
    except OSError as exc:
        if tmp.exists():
            tmp.unlink()
        if exc.errno is None or exc.filename not in (None, str(tmp)):
            raise
        raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from exc
    return path
