"""Checks of a ship surface: scale and axes, degenerate and duplicate triangles, closure,
self-intersections, orientation; cleaning and re-orienting on request."""

from __future__ import annotations

import numpy as np

from ...errors import InputError, check_finite, require
from ..cad import SHIP_LENGTH_RANGE
from ..parts import boundary_edges, face_areas, signed_volume
from ..surface_ops import fix_winding

__all__ = ["check_surface"]


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
    f, lab = _drop_degenerate(v, f, lab, scale, clean, report)
    f, lab = _drop_duplicates(f, lab, clean, report)
    _check_closed(v, f, require_closed, allow_nonmanifold, report)
    if require_closed and check_intersections:
        _check_intersections(v, f, report)
    f = _orient(v, f, fix_normals, require_closed, report)
    report["area"] = float(face_areas(v, f).sum())
    return v, f, lab, report


def _drop_degenerate(v, f, lab, scale: float, clean: bool, report: dict):
    """Degenerate triangles: a repeated vertex or (numerically) no area; with ``clean``,
    needles are flipped away and the rest dropped (counted in ``report``)."""
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
    return f, lab


def _drop_duplicates(f, lab, clean: bool, report: dict):
    """Duplicate triangles (same three vertices, either orientation): an error, or dropped
    with ``clean`` (counted in ``report``)."""
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
    return f, lab


def _check_closed(v, f, require_closed: bool, allow_nonmanifold: bool, report: dict) -> None:
    """Open and non-manifold edges, counted in ``report``; refused when the surface must
    be closed (non-manifold edges only unless allowed)."""
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


def _check_intersections(v, f, report: dict) -> None:
    """Refuse a self-intersecting surface (Embree ray casts; ``report`` says whether it was
    checked)."""
    try:    # deferred: the FV mesh package loads scipy (0.15 s), kept out of loading a scenario
        from ...mesh import find_self_intersections
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


def _orient(v, f, fix_normals: bool, require_closed: bool, report: dict):
    """Consistent winding and outward normals: an error, or fixed with ``fix_normals``
    (``flipped_faces`` and ``signed_volume`` in ``report``)."""
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
    return f


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
