"""Multilayer shell cell graphs: a surface triangulation extruded through plate layups.

Ships are thin plates. Each surface triangle becomes a column of prism cells through its
part's :class:`~shipthermal.materials.Layup` (outer surface first, extruded inwards along
the triangle normal). Conduction is

* **through the thickness** between consecutive cells of a column,
  ``G = A / (Δz_i/(2k_i) + Δz_j/(2k_j))``;
* **laterally** across each triangle edge between cells of neighbouring columns whose
  depth ranges overlap, ``G = L·overlap / (d_P/k_P + d_Q/k_Q)`` with ``d`` the in-plane
  distances from the triangle centroids to the shared edge. Identical layups connect layer
  to layer; different layups (e.g. deck to hull) connect by depth overlap, which conserves
  energy.

Thin-shell approximation: cell volume = triangle area × layer thickness (plate thickness ≪
radius of curvature). Lateral two-point fluxes are exact on orthogonal triangulations and
first-order consistent on skewed ones; diurnal plate temperatures are dominated by the
through-thickness balance, which is exact in this construction.

Boundary patches: ``"{part}:outer"`` (the given surface, normal as given) and
``"{part}:inner"`` (the inner side, normal reversed).
"""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from ..errors import InputError, check_finite, require
from ..materials import Layup
from .graph import VTK_WEDGE, CellGraph

__all__ = ["build_shell_graph"]


def build_shell_graph(vertices, faces, face_part, part_names: Sequence[str],
                      layups: Mapping[str, Layup]) -> CellGraph:
    """Build a multilayer shell cell graph.

    Parameters
    ----------
    vertices : (N, 3) array [m]
        Surface vertices.
    faces : (M, 3) int array
        Triangles, wound so that the normal points out of the ship (layers go inwards).
    face_part : (M,) int array
        Part index of each triangle into ``part_names``.
    part_names : sequence of str
        Part names.
    layups : mapping part name -> Layup
        Plate layup of each part that has faces.

    Returns
    -------
    CellGraph
        With ``kind="shell"``; ``metadata`` holds ``cell_face`` (the surface triangle of each
        cell), ``cell_layer`` (layer index), ``cell_depth`` (depth of the cell centre below
        the outer surface [m]).
    """
    vertices, faces, face_part, part_names, used = _checked_inputs(
        vertices, faces, face_part, part_names, layups)
    p0, p1, p2 = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    s = 0.5 * np.cross(p1 - p0, p2 - p0)
    area = np.linalg.norm(s, axis=1)
    if np.any(area <= 0):
        bad = int(np.flatnonzero(area <= 0)[0])
        raise InputError(f"faces[{bad}]", faces[bad].tolist(), "has zero area",
                         "Remove degenerate triangles (geometry checks report them)")
    normal = s / area[:, None]
    centroid = (p0 + p1 + p2) / 3.0

    materials, tables = _layup_tables(used, part_names, layups)
    offset, cell_face, cell_layer, cell_part, cell_mat, cell_dz, cell_ztop, cell_k = \
        _cell_columns(face_part, len(part_names), tables)
    n = int(offset[-1])
    cell_area = area[cell_face]
    depth = cell_ztop + 0.5 * cell_dz
    cell_centroid = centroid[cell_face] - normal[cell_face] * depth[:, None]
    cell_volume = cell_area * cell_dz

    # ---- through-thickness faces -------------------------------------------------------------
    up = np.flatnonzero(cell_layer[1:] > 0) + 1    # cells with a cell above in the column
    lo = up - 1
    g_tt = cell_area[up] / (0.5 * cell_dz[lo] / cell_k[lo] + 0.5 * cell_dz[up] / cell_k[up])
    tt_area = cell_area[up]

    # ---- boundary faces: outer (first cell) and inner (last cell) --------------------------
    first = offset[:-1]
    last = offset[1:] - 1
    g_out = area / (0.5 * cell_dz[first] / cell_k[first])
    g_in = area / (0.5 * cell_dz[last] / cell_k[last])
    total_t = cell_ztop[last] + cell_dz[last]

    # ---- lateral faces across triangle edges -------------------------------------------------
    lat_own, lat_nei, lat_g, lat_area = _lateral_faces(vertices, faces, face_part, centroid,
                                                       offset, tables)

    face_cells = np.concatenate([np.stack([lo, up], 1), np.stack([lat_own, lat_nei], 1)])
    face_area = np.concatenate([tt_area, lat_area])
    face_g = np.concatenate([g_tt, lat_g])
    patch_names, part_outer, part_inner = _patches(used, part_names)
    pts, conn, outer_tri, inner_tri = _wedges(np.stack([p0, p1, p2], 1), normal, cell_face,
                                              cell_ztop, cell_dz, first, last)

    bface_cell = np.concatenate([first, last])
    return CellGraph(
        cell_centroid=cell_centroid, cell_volume=cell_volume, cell_material=cell_mat.astype(np.int32),
        materials=tuple(materials), cell_part=cell_part.astype(np.int32), part_names=part_names,
        face_cells=face_cells, face_area=face_area, face_conductance=face_g,
        bface_cell=bface_cell, bface_area=np.concatenate([area, area]),
        bface_normal=np.concatenate([normal, -normal]),
        bface_centroid=np.concatenate([centroid, centroid - normal * total_t[:, None]]),
        bface_conductance=np.concatenate([g_out, g_in]),
        bface_patch=np.concatenate([part_outer[face_part], part_inner[face_part]]).astype(np.int32),
        patch_names=tuple(patch_names), points=pts, cell_connectivity=conn,
        cell_types=np.full(n, VTK_WEDGE, np.uint8),
        bface_vertices=np.concatenate([outer_tri, inner_tri]), correction=None, kind="shell",
        metadata=dict(cell_face=cell_face, cell_layer=cell_layer, cell_depth=depth,
                      n_surface_faces=len(faces)),
    )


def _checked_inputs(vertices, faces, face_part, part_names, layups):
    """The inputs as arrays, checked; returns them and the part indices that have faces."""
    vertices = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    face_part = np.asarray(face_part, dtype=np.int64)
    part_names = tuple(str(p) for p in part_names)
    check_finite("vertices", vertices)
    require(vertices.ndim == 2 and vertices.shape[1] == 3, "vertices", vertices.shape, "must be (N, 3)")
    require(faces.ndim == 2 and faces.shape[1] == 3 and len(faces) > 0, "faces", faces.shape,
            "must be (M, 3) with M > 0")
    require(faces.min() >= 0 and faces.max() < len(vertices), "faces",
            (int(faces.min()), int(faces.max())), f"vertex indices must lie in [0, {len(vertices) - 1}]")
    require(face_part.shape == (len(faces),), "face_part", face_part.shape,
            f"must give one part index per face ({len(faces)})")
    require(face_part.min() >= 0 and face_part.max() < len(part_names), "face_part",
            (int(face_part.min()), int(face_part.max())),
            f"part indices must lie in [0, {len(part_names) - 1}]")
    used = np.unique(face_part)
    for p in used:
        name = part_names[p]
        if name not in layups:
            raise InputError(f"layups[{name!r}]", None, "missing: every part with faces needs a layup",
                             f"Give a Layup for part {name!r} (parts: {', '.join(part_names)})")
        require(isinstance(layups[name], Layup), f"layups[{name!r}]", layups[name], "must be a Layup")
    return vertices, faces, face_part, part_names, used


def _layup_tables(used, part_names, layups):
    """The materials (each once, in order of first use) and, per part index, the layup's
    sub-cells: material index ``mat``, thickness ``dz``, depth of the top ``ztop``,
    conductivity ``k``."""
    materials: list = []
    mat_index: dict[str, int] = {}
    tables = {}  # part index -> dict of arrays per sub-cell
    for p in used:
        lay = layups[part_names[p]]
        mats, dz, ztop = [], [], []
        z = 0.0
        for layer, mat in zip(lay.layers, lay.materials):
            if mat.name not in mat_index:
                mat_index[mat.name] = len(materials)
                materials.append(mat)
            h = layer.thickness / layer.cells
            for c in range(layer.cells):
                mats.append(mat_index[mat.name])
                dz.append(h)
                ztop.append(z)
                z += h
        tables[int(p)] = dict(mat=np.array(mats), dz=np.array(dz), ztop=np.array(ztop),
                              k=np.array([materials[m].conductivity for m in mats]))
    return materials, tables


def _cell_columns(face_part, n_parts: int, tables):
    """A column of cells under each triangle, numbered column by column: ``offset`` (the
    first cell of each column, and the total), and per cell its triangle, layer, part,
    material, thickness, depth of its top and conductivity."""
    ncol = np.zeros(n_parts, dtype=np.int64)
    for p, t in tables.items():
        ncol[p] = len(t["dz"])
    face_ncell = ncol[face_part]
    offset = np.concatenate([[0], np.cumsum(face_ncell)])
    n = int(offset[-1])

    cell_face = np.repeat(np.arange(len(face_part)), face_ncell)
    cell_layer = np.arange(n) - offset[cell_face]
    cell_part = face_part[cell_face]
    # Per-cell layup quantities, gathered part by part (few parts, vectorised inside).
    cell_mat = np.empty(n, np.int64)
    cell_dz = np.empty(n)
    cell_ztop = np.empty(n)
    cell_k = np.empty(n)
    for p, t in tables.items():
        sel = cell_part == p
        lay_idx = cell_layer[sel]
        cell_mat[sel] = t["mat"][lay_idx]
        cell_dz[sel] = t["dz"][lay_idx]
        cell_ztop[sel] = t["ztop"][lay_idx]
        cell_k[sel] = t["k"][lay_idx]
    return offset, cell_face, cell_layer, cell_part, cell_mat, cell_dz, cell_ztop, cell_k


def _patches(used, part_names):
    """Boundary patches ``"{part}:outer"`` and ``"{part}:inner"`` of the parts with faces,
    and each part's outer and inner patch index (-1 for parts without faces)."""
    patch_names = []
    for p in used:
        patch_names += [f"{part_names[p]}:outer", f"{part_names[p]}:inner"]
    patch_of = {name: i for i, name in enumerate(patch_names)}
    part_outer = np.full(len(part_names), -1)
    part_inner = np.full(len(part_names), -1)
    for p in used:
        part_outer[p] = patch_of[f"{part_names[p]}:outer"]
        part_inner[p] = patch_of[f"{part_names[p]}:inner"]
    return patch_names, part_outer, part_inner


def _wedges(tri_pts, normal, cell_face, cell_ztop, cell_dz, first, last):
    """Output geometry: one VTK wedge per cell with its own six points; returns the points,
    the connectivity, and the point triples of the outer and inner boundary faces."""
    n = len(cell_face)
    top = tri_pts[cell_face] - normal[cell_face][:, None, :] * cell_ztop[:, None, None]
    bot = tri_pts[cell_face] - normal[cell_face][:, None, :] * (cell_ztop + cell_dz)[:, None, None]
    # VTK wedge: first triangle then the opposite one, both with the same orientation.
    pts = np.concatenate([bot, top], axis=1).reshape(-1, 3)
    conn = np.hstack([np.full((n, 1), 6), np.arange(6 * n).reshape(n, 6)]).ravel()
    outer_tri = 6 * first[:, None] + 3 + np.arange(3)[None, :]
    inner_tri = (6 * last[:, None] + np.arange(3)[None, :])[:, ::-1]
    return pts, conn, outer_tri, inner_tri


def _lateral_faces(vertices, faces, face_part, centroid, offset, tables):
    """Faces between cells of neighbouring columns (see module docstring)."""
    m = len(faces)
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    edge_face = np.tile(np.arange(m), 3)
    key = np.sort(edges, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key_s = key[order]
    new_group = np.ones(len(key_s), bool)
    new_group[1:] = np.any(key_s[1:] != key_s[:-1], axis=1)
    group = np.cumsum(new_group) - 1
    counts = np.bincount(group)
    # Pairs of faces sharing an edge: all pairs within each group (manifold edges give one
    # pair; a non-manifold edge shared by c faces gives c(c-1)/2 pairs, each carrying 1/(c-1)
    # of the edge so that every face keeps one edge length of contact).
    starts = np.flatnonzero(new_group)
    pa, pb, pscale = [], [], []
    for c in np.unique(counts):
        if c < 2:
            continue
        gsel = starts[counts[group[starts]] == c]
        for i in range(c):
            for j in range(i + 1, c):
                pa.append(order[gsel + i])
                pb.append(order[gsel + j])
                pscale.append(np.full(len(gsel), 1.0 / (c - 1)))
    if not pa:
        e = np.zeros(0, np.int64)
        return e, e, np.zeros(0), np.zeros(0)
    ea, eb = np.concatenate(pa), np.concatenate(pb)
    scale = np.concatenate(pscale)
    fa, fb = edge_face[ea], edge_face[eb]
    v0 = vertices[edges[ea, 0]]
    v1 = vertices[edges[ea, 1]]
    t = v1 - v0
    length = np.linalg.norm(t, axis=1)
    t = t / length[:, None]

    def dist_to_edge(c):
        r = c - v0
        return np.linalg.norm(r - np.einsum("ij,ij->i", r, t)[:, None] * t, axis=1)

    da = np.maximum(dist_to_edge(centroid[fa]), 1e-12)
    db = np.maximum(dist_to_edge(centroid[fb]), 1e-12)

    own, nei, g, ar = [], [], [], []
    parts_a, parts_b = face_part[fa], face_part[fb]
    for pa_ in np.unique(parts_a):
        for pb_ in np.unique(parts_b[parts_a == pa_]):
            sel = np.flatnonzero((parts_a == pa_) & (parts_b == pb_))
            ta, tb = tables[int(pa_)], tables[int(pb_)]
            za0, za1 = ta["ztop"], ta["ztop"] + ta["dz"]
            zb0, zb1 = tb["ztop"], tb["ztop"] + tb["dz"]
            overlap = np.minimum(za1[:, None], zb1[None, :]) - np.maximum(za0[:, None], zb0[None, :])
            ia, ib = np.nonzero(overlap > 1e-15)
            ov = overlap[ia, ib]
            # (edges in sel) × (overlapping layer pairs)
            ka, kb = ta["k"][ia], tb["k"][ib]
            ee = np.repeat(sel, len(ia))
            la = np.tile(ia, len(sel))
            lb = np.tile(ib, len(sel))
            ovv = np.tile(ov, len(sel))
            kaa, kbb = np.tile(ka, len(sel)), np.tile(kb, len(sel))
            a_face = length[ee] * scale[ee] * ovv
            own.append(offset[fa[ee]] + la)
            nei.append(offset[fb[ee]] + lb)
            g.append(a_face / (da[ee] / kaa + db[ee] / kbb))
            ar.append(a_face)
    return np.concatenate(own), np.concatenate(nei), np.concatenate(g), np.concatenate(ar)
