"""Ships with some parts solid: tetrahedra for the solid parts, plate shells for the rest.

A part declared solid (a solid mast, a gun house filled with equipment, a verification
block) is meshed as tetrahedra; all other parts stay multilayer shells. The two meshes are
joined into one :class:`~shipthermal.mesh.CellGraph`:

* the solid parts' surface is closed where it meets the shell parts (the *rim*) by a fan
  cap per rim loop (falling back to fTetWild's winding-number closure if a fan would
  cross itself), then tetrahedralised (pytetwild);
* tet boundary faces are patched ``"{part}:outer"`` (nearest surface triangle's part) or
  ``"{part}:inner"`` on the cap (which faces the ship's inside);
* each rim edge couples every layer cell of the shell triangle on one side to the tet
  next to the edge on the other: ``G = L·Δz / (d_shell/k_shell + d_tet/k_tet)`` with ``L``
  the edge length, ``Δz`` the layer cell thickness and ``d`` the distances from the cell
  centres to the edge — the same two-point form as the shells' own lateral fluxes.

The non-orthogonal correction of the tetrahedra is carried over (it is zero on shell
and coupling faces, where the two-point flux is used as is).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..errors import InputError
from ..mesh import CellGraph
from ..mesh.graph import NonOrthogonalCorrection
from ..mesh.tets import tetwild as _tetwild

__all__ = ["merge_cell_graphs", "mixed_ship_graph"]


def _offset_connectivity(conn: np.ndarray, n_cells: int, offset: int) -> np.ndarray:
    """Shift the point ids of a flat VTK connectivity ``[npts, i0, i1, ..., npts, ...]``."""
    conn = np.asarray(conn).copy()
    if n_cells and conn.size % n_cells == 0:
        width = conn.size // n_cells
        block = conn.reshape(n_cells, width)
        if np.all(block[:, 0] == width - 1):
            block[:, 1:] += offset
            return block.ravel()
    i = 0
    while i < conn.size:                           # mixed cell sizes: walk the list
        k = int(conn[i])
        conn[i + 1:i + 1 + k] += offset
        i += k + 1
    return conn


def merge_cell_graphs(graphs, cell_parts, couplings, metadata=None):
    """Join cell graphs into one, with extra coupling faces between them.

    Parameters
    ----------
    graphs : sequence of CellGraph
    cell_parts : sequence of (n_g,) arrays of part names (str) per cell, one per graph
    couplings : (own (k,), nei (k,), area (k,) [m2], conductance (k,) [W/K])
        Extra interior faces, cell indices in the merged numbering.
    metadata : dict, optional

    Returns
    -------
    CellGraph
        ``kind='mixed'``; patches, materials and parts merged by name.
    """
    n_off = np.cumsum([0] + [g.n_cells for g in graphs])
    b_off = np.cumsum([0] + [g.n_bfaces for g in graphs])
    p_off = np.cumsum([0] + [len(g.points) for g in graphs])
    n_tot, b_tot = int(n_off[-1]), int(b_off[-1])

    materials, mat_names = [], []
    part_names, patch_names = [], []
    cell_mat, cell_part, bpatch = [], [], []
    for g, cp in zip(graphs, cell_parts):
        remap_m = []
        for m in g.materials:
            if m.name not in mat_names:
                mat_names.append(m.name)
                materials.append(m)
            remap_m.append(mat_names.index(m.name))
        cell_mat.append(np.asarray(remap_m)[g.cell_material])
        for name in np.unique(cp):
            if name not in part_names:
                part_names.append(str(name))
        cell_part.append(np.array([part_names.index(str(x)) for x in cp]) if len(cp) else np.zeros(0, int))
        remap_p = []
        for name in g.patch_names:
            if name not in patch_names:
                patch_names.append(name)
            remap_p.append(patch_names.index(name))
        bpatch.append(np.asarray(remap_p)[g.bface_patch])

    own, nei, c_area, c_g = (np.asarray(x) for x in couplings)
    face_cells = np.concatenate([g.face_cells + n_off[k] for k, g in enumerate(graphs)]
                                + [np.stack([own, nei], 1).astype(np.int64)])
    face_area = np.concatenate([g.face_area for g in graphs] + [c_area])
    face_g = np.concatenate([g.face_conductance for g in graphs] + [c_g])

    correction = None
    if any(g.correction is not None for g in graphs):
        rows, cols, vals, weights, kts, bkts = [], [], [], [], [], []
        for k, g in enumerate(graphs):
            n_g = g.n_cells
            if g.correction is None:
                weights.append(np.full(g.n_faces, 0.5))
                kts.append(np.zeros((g.n_faces, 3)))
                bkts.append(np.zeros((g.n_bfaces, 3)))
                continue
            c = g.correction.gradient.tocoo()
            comp, cell = np.divmod(c.row, n_g)
            rows.append(comp * n_tot + n_off[k] + cell)
            cols.append(np.where(c.col < n_g, n_off[k] + c.col, n_tot + b_off[k] + (c.col - n_g)))
            vals.append(c.data)
            weights.append(g.correction.face_weight)
            kts.append(g.correction.face_kt)
            bkts.append(g.correction.bface_kt)
        weights.append(np.full(len(own), 0.5))
        kts.append(np.zeros((len(own), 3)))
        grad = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                             shape=(3 * n_tot, n_tot + b_tot))
        correction = NonOrthogonalCorrection(grad, np.concatenate(weights), np.concatenate(kts),
                                             np.concatenate(bkts))

    return CellGraph(
        cell_centroid=np.concatenate([g.cell_centroid for g in graphs]),
        cell_volume=np.concatenate([g.cell_volume for g in graphs]),
        cell_material=np.concatenate(cell_mat).astype(np.int32), materials=tuple(materials),
        cell_part=np.concatenate(cell_part).astype(np.int32), part_names=tuple(part_names),
        face_cells=face_cells, face_area=face_area, face_conductance=face_g,
        bface_cell=np.concatenate([g.bface_cell + n_off[k] for k, g in enumerate(graphs)]),
        bface_area=np.concatenate([g.bface_area for g in graphs]),
        bface_normal=np.concatenate([g.bface_normal for g in graphs]),
        bface_centroid=np.concatenate([g.bface_centroid for g in graphs]),
        bface_conductance=np.concatenate([g.bface_conductance for g in graphs]),
        bface_patch=np.concatenate(bpatch).astype(np.int32), patch_names=tuple(patch_names),
        points=np.concatenate([g.points for g in graphs]),
        cell_connectivity=np.concatenate([_offset_connectivity(g.cell_connectivity, g.n_cells, p_off[k])
                                          for k, g in enumerate(graphs)]),
        cell_types=np.concatenate([g.cell_types for g in graphs]),
        bface_vertices=np.concatenate([g.bface_vertices + p_off[k] for k, g in enumerate(graphs)]),
        correction=correction, kind="mixed", metadata=dict(metadata or {}))


def _cap_rim(vertices, faces):
    """Fan caps closing the open rim loops of a surface patch.

    Returns ``(cap_vertices (k, 3), cap_faces (j, 3))`` indexing ``concat(vertices,
    cap_vertices)``; each cap is wound against its rim so the closed surface is oriented
    like the patch.
    """
    half = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    key = np.sort(half, axis=1)
    _, inv, cnt = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    rim = half[cnt[inv.ravel()] == 1]
    if len(rim) == 0:
        return np.zeros((0, 3)), np.zeros((0, 3), np.int64)
    nxt = {int(a): int(b) for a, b in rim}
    unused = set(nxt)
    centres, tris = [], []
    n = len(vertices)
    while unused:
        start = unused.pop()
        loop = [start]
        cur = nxt[start]
        while cur != start:
            if cur not in unused:
                raise InputError("solid part", "rim", "the open rim of the solid parts is not a set of "
                                 "simple loops", "Declare a part whose boundary is simple")
            unused.remove(cur)
            loop.append(cur)
            cur = nxt[cur]
        c = len(centres)
        centres.append(vertices[loop].mean(axis=0))
        for a in loop:
            tris.append((n + c, nxt[a], a))
    return np.asarray(centres), np.asarray(tris, np.int64)


def mixed_ship_graph(ship, solid_parts, fvmesh):
    """Cell graph of a ship with ``solid_parts`` as tetrahedra and the rest as shells.

    Returns ``(graph, info)``; ``info`` holds ``n_tets``, ``n_shell_cells``,
    ``n_rim_edges``, ``closure`` (``'fan'`` or ``'winding number'``).
    """
    # deferred: start-up cost (scipy.spatial takes ~1 s to import)
    from scipy.spatial import cKDTree

    names = ship.part_names
    solid_idx = [names.index(p) for p in solid_parts]
    is_solid = np.isin(ship.face_part, solid_idx)
    v, f = np.array(ship.vertices), np.array(ship.faces)

    # ---- shells -------------------------------------------------------------------------------
    shell_faces = np.flatnonzero(~is_solid)
    shell = fvmesh.build_shell_graph(v, f[shell_faces], ship.face_part[shell_faces], names,
                                     {n: ship.layups[n] for n in names if n not in solid_parts})

    # ---- solid: close the rim and tetrahedralise --------------------------------------------
    sf = f[is_solid]
    cv, cf, n_cap, pts, tets, closure = _solid_tets(v, sf, ship.edge_length, fvmesh)
    face_label = np.concatenate([ship.face_part[is_solid], np.full(n_cap, -1)])
    tree = cKDTree(cv[cf].mean(axis=1))
    real = np.flatnonzero(face_label >= 0)
    mats, tet_part, cell_mat = _tet_parts(ship, solid_parts, pts, tets, cv, cf, face_label, real,
                                          tree)
    tet = fvmesh.build_tet_graph(pts, tets, material=mats, cell_material=cell_mat,
                                 patches=_patch_rule(names, cv, cf, face_label, real, tree),
                                 part_name=solid_parts[0])

    couplings, n_rim = _rim_couplings(v, f, is_solid, shell, shell_faces, tet)
    shell_parts = np.asarray(names)[shell.cell_part]
    meta = dict(n_shell_cells=shell.n_cells, n_tets=tet.n_cells,
                cell_face=np.concatenate([shell.metadata["cell_face"], np.full(tet.n_cells, -1)]),
                shell_face_index=shell_faces, n_rim_edges=n_rim, closure=closure)
    graph = merge_cell_graphs([shell, tet], [shell_parts, tet_part], couplings, meta)
    return graph, dict(n_tets=tet.n_cells, n_shell_cells=shell.n_cells,
                       n_rim_edges=n_rim, closure=closure)


def _solid_tets(v, sf, edge_length: float, fvmesh):
    """The solid parts' surface ``sf`` closed by a cap over its rim and tetrahedralised:
    ``(closed vertices, closed faces, number of cap faces, points, tets, closure)``."""
    cap_v, cap_f = _cap_rim(v, sf)
    closed_v = np.vstack([v, cap_v])
    closed_f = np.vstack([sf, cap_f])
    used, inv = np.unique(closed_f, return_inverse=True)
    cv, cf = closed_v[used], inv.reshape(-1, 3)
    closure = "fan"
    try:
        pts, tets = fvmesh.tetrahedralize_surface(cv, cf, edge_length=edge_length, field="solid parts")
    except InputError:
        # A fan crossing itself (non-star-shaped rim): let fTetWild close it by winding number.
        closure = "winding number"
        pts, tets = _tetwild(cv.astype(np.float64), cf.astype(np.int32),
                             edge_length_abs=float(edge_length), vtk_ordering=True)
        pts, tets = np.asarray(pts, float), np.asarray(tets, np.int64)
    return cv, cf, len(cap_f), pts, tets, closure


def _tet_parts(ship, solid_parts, pts, tets, cv, cf, face_label, real, tree):
    """Each solid part's material (its layup's thickest layer) and each tet's part (that of
    the nearest surface triangle, a real one for tets nearest to a cap):
    ``(materials, tet part names, tet material indices)``."""
    # deferred: start-up cost (scipy.spatial takes ~1 s to import)
    from scipy.spatial import cKDTree

    names = ship.part_names
    mats, part_mat = [], {}
    for p in solid_parts:
        lay = ship.layups[p]
        k = int(np.argmax([layer.thickness for layer in lay.layers]))
        m = lay.materials[k]
        if m.name not in [x.name for x in mats]:
            mats.append(m)
        part_mat[p] = [x.name for x in mats].index(m.name)
    _, near = tree.query(pts[tets].mean(axis=1))
    tet_label = face_label[near]
    # A tet nearest to a cap takes the part of the nearest real solid face.
    if (tet_label < 0).any():
        rtree = cKDTree(cv[cf[real]].mean(axis=1))
        _, rn = rtree.query(pts[tets[tet_label < 0]].mean(axis=1))
        tet_label[tet_label < 0] = face_label[real[rn]]
    tet_part = np.array([names[k] for k in tet_label])
    cell_mat = np.array([part_mat[p] for p in tet_part])
    return mats, tet_part, cell_mat


def _patch_rule(names, cv, cf, face_label, real, tree):
    """Patch rule of the tets' boundary triangles: ``"{part}:outer"`` of the nearest
    surface triangle; on the cap ``"{part}:inner"`` of the nearest real solid triangle."""
    # deferred: start-up cost (scipy.spatial takes ~1 s to import)
    from scipy.spatial import cKDTree

    def rule(centroid, normal):
        _, i = tree.query(centroid)
        lab = face_label[i]
        # Cap faces face the ship's inside: the part of the nearest real face, ':inner'.
        out = np.empty(len(i), dtype=object)
        cap = lab < 0
        out[~cap] = [f"{names[k]}:outer" for k in lab[~cap]]
        if cap.any():
            rtree = cKDTree(cv[cf[real]].mean(axis=1))
            _, rn = rtree.query(centroid[cap])
            out[cap] = [f"{names[k]}:inner" for k in face_label[real[rn]]]
        return out.astype(str)

    return rule


def _rim_couplings(v, f, is_solid, shell, shell_faces, tet):
    """Coupling faces along the rim, where solid and shell triangles share an edge: every
    layer cell of the shell triangle to the tet next to the edge (module docstring).
    Returns ``((own, nei, area, conductance), number of rim edges)``."""
    # deferred: start-up cost (scipy.spatial takes ~1 s to import)
    from scipy.spatial import cKDTree

    half = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    face_of = np.tile(np.arange(len(f)), 3)
    key = np.sort(half, axis=1)
    _, inv2, cnt = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    inv2 = inv2.ravel()
    order = np.argsort(inv2, kind="stable")
    two = cnt[inv2[order]] == 2
    pairs = order[two].reshape(-1, 2)
    fa, fb = face_of[pairs[:, 0]], face_of[pairs[:, 1]]
    rim = is_solid[fa] != is_solid[fb]
    f_shell = np.where(is_solid[fa], fb, fa)[rim]
    e = key[pairs[rim, 0]]
    mid = 0.5 * (v[e[:, 0]] + v[e[:, 1]])
    length = np.linalg.norm(v[e[:, 1]] - v[e[:, 0]], axis=1)
    # Tet next to each rim edge: owner of the nearest tet boundary face.
    _, bi = cKDTree(tet.bface_centroid).query(mid)
    t_cell = tet.bface_cell[bi]
    d_t = np.linalg.norm(tet.cell_centroid[t_cell] - mid, axis=1)
    k_t = tet.cell_conductivity[t_cell]
    # Shell face -> its column of cells in the shell graph.
    shell_pos = np.full(len(f), -1)
    shell_pos[shell_faces] = np.arange(len(shell_faces))
    cell_face = shell.metadata["cell_face"]
    col_start = np.searchsorted(cell_face, np.arange(len(shell_faces) + 1))
    tri = v[f[f_shell]]
    cen = tri.mean(axis=1)
    edge_dir = (v[e[:, 1]] - v[e[:, 0]]) / length[:, None]
    rel = cen - v[e[:, 0]]
    d_h = np.linalg.norm(rel - np.einsum("ij,ij->i", rel, edge_dir)[:, None] * edge_dir, axis=1)
    own, nei, area, g = [], [], [], []
    for r in range(len(f_shell)):
        s = shell_pos[f_shell[r]]
        cells = np.arange(col_start[s], col_start[s + 1])
        tri_area = 0.5 * np.linalg.norm(np.cross(tri[r, 1] - tri[r, 0], tri[r, 2] - tri[r, 0]))
        dz = shell.cell_volume[cells] / tri_area          # layer cell thickness [m]
        k_s = shell.cell_conductivity[cells]
        a = length[r] * dz
        own.append(cells)
        nei.append(np.full(len(cells), shell.n_cells + t_cell[r]))
        area.append(a)
        g.append(a / (d_h[r] / k_s + d_t[r] / k_t[r]))
    couplings = (np.concatenate(own), np.concatenate(nei), np.concatenate(area), np.concatenate(g))
    return couplings, int(len(f_shell))
