"""Tetrahedral cell graphs: pytetwild meshing of a closed surface and the FV graph of tets."""

from __future__ import annotations

import os
from typing import Callable, Sequence

import numpy as np

from ..errors import InputError, check_finite, check_positive, require
from ..materials import Material, get_material
from .graph import (CORRECTION_TREATMENTS, VTK_TETRA, CellGraph, NonOrthogonalCorrection,
                    least_squares_gradient)

__all__ = ["check_closed_surface", "find_self_intersections", "tetrahedralize_surface",
           "build_tet_graph", "tetwild", "orient_tets", "tet_faces"]


def check_closed_surface(vertices, faces, field: str = "surface") -> None:
    """Raise :class:`InputError` unless the triangulation is closed and not self-intersecting.

    pytetwild silently closes open surfaces by winding number (and returns nothing for a
    flat sheet), so this check runs before it.
    """
    import trimesh      # deferred: start-up cost (trimesh takes ~1.5 s to import)

    vertices = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces)
    check_finite(f"{field}.vertices", vertices)
    require(faces.ndim == 2 and faces.shape[1] == 3 and faces.size > 0, f"{field}.faces",
            faces.shape, "must be an (M, 3) array of triangle vertex indices with M > 0")
    mesh = trimesh.Trimesh(vertices, faces, process=True, validate=False)
    if not mesh.is_watertight:
        edges = mesh.edges_sorted
        _, counts = np.unique(edges, axis=0, return_counts=True)
        n_open = int(np.sum(counts == 1))
        raise InputError(field, f"{len(faces)} triangles", f"must be a closed (watertight) surface; "
                         f"found {n_open} boundary edges that belong to one triangle only",
                         "Close the gaps in the CAD export, or repair it with pytetwild remeshing "
                         "(shipthermal.geometry repair option)")
    pairs = find_self_intersections(mesh.vertices, mesh.faces, max_report=1)
    if len(pairs):
        i, j = pairs[0]
        raise InputError(field, f"triangles {i} and {j} intersect",
                         "must not intersect itself",
                         "Repair the surface (e.g. pytetwild robust remeshing) before meshing")


def find_self_intersections(vertices, faces, max_report: int = 10) -> np.ndarray:
    """Pairs of triangles that cross each other (sharing no vertex).

    Two non-coplanar triangles intersect iff an edge of one pierces the other, so each mesh
    edge is cast as a ray segment against the mesh (Embree through trimesh) and hits on
    triangles not sharing a vertex with the edge are reported. Coplanar overlaps are not
    detected.
    """
    import trimesh      # deferred: start-up cost (trimesh takes ~1.5 s to import)

    mesh = trimesh.Trimesh(vertices, faces, process=False, validate=False)
    edges = mesh.edges_unique
    origin = mesh.vertices[edges[:, 0]]
    vec = mesh.vertices[edges[:, 1]] - origin
    length = np.linalg.norm(vec, axis=1)
    keep = length > 0
    edges, origin, vec, length = edges[keep], origin[keep], vec[keep], length[keep]
    direction = vec / length[:, None]
    tri, ray, loc = mesh.ray.intersects_id(origin, direction, multiple_hits=True,
                                           return_locations=True)
    if len(tri) == 0:
        return np.zeros((0, 2), dtype=int)
    dist = np.einsum("ij,ij->i", loc - origin[ray], direction[ray])
    eps = 1e-6 * mesh.scale
    inside = (dist > eps) & (dist < length[ray] - eps)
    shares = np.any(mesh.faces[tri][:, :, None] == edges[ray][:, None, :], axis=(1, 2))
    bad = inside & ~shares
    if not bad.any():
        return np.zeros((0, 2), dtype=int)
    # Report (a face holding the edge, the pierced face); only a few, so a loop is fine.
    pierced = tri[bad][:max_report]
    edge_ids = ray[bad][:max_report]
    owner = np.array([np.flatnonzero(np.any(mesh.faces == edges[e, 0], axis=1)
                                     & np.any(mesh.faces == edges[e, 1], axis=1))[0] for e in edge_ids])
    return np.stack([owner, pierced], axis=1)


def tetrahedralize_surface(vertices, faces, edge_length: float | None = None,
                           edge_length_fac: float | None = None, optimize: bool = True,
                           field: str = "surface") -> tuple[np.ndarray, np.ndarray]:
    """Tetrahedralise a closed surface with pytetwild (fTetWild).

    Parameters
    ----------
    vertices, faces : array_like
        Closed, non-self-intersecting triangulation [m].
    edge_length : float, optional
        Target absolute tet edge length [m] (``edge_length_abs``).
    edge_length_fac : float, optional
        Target edge length as a fraction of the bounding-box diagonal (pytetwild default 0.05).
    optimize : bool
        Run fTetWild's quality optimisation.

    Returns
    -------
    points : ndarray (N, 3) float64 [m]
    tets : ndarray (M, 4) int64, positively oriented (VTK ordering)
    """

    check_closed_surface(vertices, faces, field)
    kwargs = {}
    if edge_length is not None:
        check_positive(f"{field}.edge_length", edge_length, "m")
        kwargs["edge_length_abs"] = float(edge_length)
    elif edge_length_fac is not None:
        check_positive(f"{field}.edge_length_fac", edge_length_fac)
        kwargs["edge_length_fac"] = float(edge_length_fac)
    points, tets = tetwild(np.asarray(vertices, dtype=np.float64), np.asarray(faces, dtype=np.int32),
                           optimize=optimize, vtk_ordering=True, **kwargs)
    points = np.asarray(points, dtype=np.float64)
    tets = np.asarray(tets, dtype=np.int64)
    if len(tets) == 0:
        raise InputError(field, "empty tet mesh", "pytetwild produced no tetrahedra",
                         "Check that the surface encloses a volume")
    return points, orient_tets(points, tets)


def tetwild(vertices, faces, **kwargs):
    """``pytetwild.tetrahedralize`` without its side effect: fTetWild leaves a debug file
    ``__tracked_surface.stl`` in the working directory, removed here unless it was there
    before (a user's run directory must not collect it)."""
    import pytetwild    # deferred: start-up cost (~1.3 s to import)

    debris = "__tracked_surface.stl"
    had_debris = os.path.exists(debris)
    try:
        return pytetwild.tetrahedralize(vertices, faces, **kwargs)
    finally:
        if not had_debris and os.path.exists(debris):
            os.remove(debris)


def orient_tets(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """The tetrahedra with vertices 1 and 2 swapped where needed so that every one has a
    positive volume (a copy)."""
    a, b, c, d = (points[tets[:, k]] for k in range(4))
    vol = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a)
    tets = tets.copy()
    neg = vol < 0
    tets[neg, 1], tets[neg, 2] = tets[neg, 2], tets[neg, 1].copy()
    return tets


def tet_faces(tets: np.ndarray):
    """The faces of a positively oriented tetrahedral mesh (:func:`orient_tets`), paired.

    Returns ``(owner (F,), neighbour (F,), interior (F, 3), boundary_cell (B,),
    boundary (B, 3))``: each interior triangle once, wound outward from its owner; each
    boundary triangle wound outward from its tet. Triangles are vertex-index triples.
    """
    local = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])   # opposite each vertex
    tri = tets[:, local].reshape(-1, 3)          # (4M, 3), outward for the owning tet
    owner = np.repeat(np.arange(len(tets)), 4)
    key = np.sort(tri, axis=1)
    order = np.lexsort(key.T[::-1])
    key_s = key[order]
    # Interior faces: consecutive equal keys.
    first = np.flatnonzero(np.all(key_s[1:] == key_s[:-1], axis=1))
    is_pair = np.zeros(len(key_s), bool)
    is_pair[first] = True
    is_pair[first + 1] = True
    bidx = order[~is_pair]
    return (owner[order[first]], owner[order[first + 1]], tri[order[first]], owner[bidx],
            tri[bidx])


def _tet_materials(points: np.ndarray, tets, material, cell_material):
    """Validate a tet mesh and its materials (shared by the cell- and vertex-centred
    builders).

    Returns ``(materials, cell_material (M,), tets (M, 4) positively oriented, volume (M,)
    [m3])``.
    """
    tets = np.asarray(tets, dtype=np.int64)
    check_finite("points", points)
    require(points.ndim == 2 and points.shape[1] == 3, "points", points.shape, "must be (N, 3)")
    require(tets.ndim == 2 and tets.shape[1] == 4 and len(tets) > 0, "tets", tets.shape,
            "must be (M, 4) with M > 0")
    require(tets.min() >= 0 and tets.max() < len(points), "tets", (int(tets.min()), int(tets.max())),
            f"vertex indices must lie in [0, {len(points) - 1}]")
    tets = orient_tets(points, tets)

    mats = [material] if isinstance(material, (str, Material)) else list(material)
    mats = tuple(get_material(m, f"material[{i}]") for i, m in enumerate(mats))
    if cell_material is None:
        require(len(mats) == 1, "cell_material", None, "is required when several materials are given")
        cell_material = np.zeros(len(tets), dtype=np.int32)
    cell_material = np.asarray(cell_material, dtype=np.int32)
    require(cell_material.shape == (len(tets),), "cell_material", cell_material.shape,
            f"must have one entry per tet ({len(tets)})")
    require(bool(np.all((cell_material >= 0) & (cell_material < len(mats)))), "cell_material",
            (int(cell_material.min()), int(cell_material.max())),
            f"must index the materials 0..{len(mats) - 1}")

    a, b, c, d = (points[tets[:, k]] for k in range(4))
    volume = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6.0
    if np.any(volume <= 0):
        raise InputError("tets", f"{int(np.sum(volume <= 0))} degenerate tets",
                         "every tetrahedron must have positive volume")
    return mats, cell_material, tets, volume


PatchRule = Callable[[np.ndarray, np.ndarray], Sequence[str] | np.ndarray]


def build_tet_graph(points, tets, material: str | Material | Sequence = "mild_steel",
                    cell_material: np.ndarray | None = None,
                    patches: str | PatchRule = "boundary", part_name: str = "solid",
                    correct_nonorthogonality: bool = True,
                    correction_treatment: str = "extrapolated") -> CellGraph:
    """Finite-volume cell graph of a tetrahedral mesh (cell-centred).

    Parameters
    ----------
    points : (N, 3) [m]
    tets : (M, 4) vertex indices
    material : str or Material, or a sequence of them
        The material (or the table indexed by ``cell_material``).
    cell_material : (M,) int, optional
        Index into ``material`` per tet when several materials are given.
    patches : str or callable
        Name for all boundary faces, or ``rule(face_centroid (b,3), face_normal (b,3))``
        returning one patch name per boundary face.
    part_name : str
        Part name of all cells.
    correct_nonorthogonality : bool
        Attach the least-squares gradient and the explicit non-orthogonal correction
        (needed for consistency on tetrahedra; off only to measure its effect).
    correction_treatment : {'extrapolated', 'iterated'}
        How a time step treats the correction (:mod:`.graph`): once per step from the
        extrapolated field (default; one Newton solve per step on a linear problem), or
        iterated to convergence inside every step.
    """
    require(correction_treatment in CORRECTION_TREATMENTS, "correction_treatment",
            correction_treatment, f"must be one of {CORRECTION_TREATMENTS}")
    points = np.asarray(points, dtype=float)
    mats, cell_material, tets, volume = _tet_materials(points, tets, material, cell_material)
    a, b, c, d = (points[tets[:, k]] for k in range(4))
    centroid = (a + b + c + d) / 4.0

    f_own, f_nei, f_tri, b_cell, b_tri = tet_faces(tets)

    def face_geom(t):
        p0, p1, p2 = points[t[:, 0]], points[t[:, 1]], points[t[:, 2]]
        s = 0.5 * np.cross(p1 - p0, p2 - p0)  # area vector, outward from the owner
        area = np.linalg.norm(s, axis=1)
        return s, area, (p0 + p1 + p2) / 3.0

    s_f, area_f, cen_f = face_geom(f_tri)
    s_b, area_b, cen_b = face_geom(b_tri)
    normal_b = s_b / area_b[:, None]

    k_cell = np.array([m.conductivity for m in mats])[cell_material]
    # Interior: harmonic k over the distances from each centroid to the face plane.
    dvec = centroid[f_nei] - centroid[f_own]
    dlen = np.linalg.norm(dvec, axis=1)
    e = dvec / dlen[:, None]
    n_f = s_f / area_f[:, None]
    cos = np.einsum("ij,ij->i", n_f, e)
    dp = np.abs(np.einsum("ij,ij->i", cen_f - centroid[f_own], n_f))
    dn = np.abs(np.einsum("ij,ij->i", centroid[f_nei] - cen_f, n_f))
    k_f = (dp + dn) / (dp / k_cell[f_own] + dn / k_cell[f_nei])
    # Over-relaxed split S = E + t with E = |S|²/(S·e) e (Jasak 1996, §3.3.1.3): the implicit
    # part grows as the face turns away from the centroid join, which keeps the deferred
    # correction a contraction on skewed tets (the minimum-correction split diverged on
    # pytetwild cubes with cos θ down to 0.45). Guard for slivers; the correction restores
    # the flux.
    cos_c = np.maximum(cos, 0.05)
    g_f = k_f * area_f / (cos_c * dlen)

    bvec = cen_b - centroid[b_cell]
    blen = np.linalg.norm(bvec, axis=1)
    eb = bvec / blen[:, None]
    cos_b = np.maximum(np.einsum("ij,ij->i", normal_b, eb), 0.05)
    g_b = k_cell[b_cell] * area_b / (cos_b * blen)

    # Boundary patches.
    if isinstance(patches, str):
        patch_names = (patches,)
        b_patch = np.zeros(len(b_cell), dtype=np.int32)
    else:
        labels = np.asarray(patches(cen_b, normal_b)).astype(str)
        require(labels.shape == (len(b_cell),), "patches", labels.shape,
                f"the rule must return one name per boundary face ({len(b_cell)})")
        patch_names, b_patch = np.unique(labels, return_inverse=True)
        patch_names = tuple(str(p) for p in patch_names)
        b_patch = b_patch.astype(np.int32)

    correction = None
    if correct_nonorthogonality:
        grad = least_squares_gradient(centroid, np.stack([f_own, f_nei], 1), b_cell, cen_b)
        face_kt = k_f[:, None] * (s_f - (area_f / cos_c)[:, None] * e)
        bface_kt = k_cell[b_cell][:, None] * (s_b - (area_b / cos_b)[:, None] * eb)
        # Gradient at the face by linear interpolation along the centroid join.
        w = dn / (dp + dn)
        correction = NonOrthogonalCorrection(grad, w, face_kt, bface_kt, correction_treatment)

    conn = np.hstack([np.full((len(tets), 1), 4), tets]).ravel()
    return CellGraph(
        cell_centroid=centroid, cell_volume=volume, cell_material=cell_material,
        materials=mats, cell_part=np.zeros(len(tets), np.int32), part_names=(part_name,),
        face_cells=np.stack([f_own, f_nei], 1), face_area=area_f, face_conductance=g_f,
        bface_cell=b_cell, bface_area=area_b, bface_normal=normal_b, bface_centroid=cen_b,
        bface_conductance=g_b, bface_patch=b_patch, patch_names=patch_names,
        points=points, cell_connectivity=conn, cell_types=np.full(len(tets), VTK_TETRA, np.uint8),
        bface_vertices=b_tri, correction=correction, kind="tetrahedral",
        metadata={"min_cos": float(cos.min()), "mean_cos": float(cos.mean())},
    )
