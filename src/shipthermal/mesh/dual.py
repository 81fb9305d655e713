"""Vertex-centred finite volumes on tetrahedra (control-volume finite elements, CVFEM).

The cells of this graph are the **vertices** of a tetrahedral mesh; each owns its
*median-dual* control volume: from every tet touching the vertex, the part closer to it
than the planes through the tet centroid, face centroids and edge midpoints (a quarter of
the tet's volume). Two vertices joined by a mesh edge exchange heat across the dual facets
of that edge, with the conductance taken from the P1 (linear finite-element) stiffness::

    G_ij = −K_ij = −Σ_tets k_t V_t ∇φ_i·∇φ_j              [W K-1]

which is exactly the flux of a piecewise-linear temperature through the median-dual facets
(the median dual cuts every tet face into three equal areas, so the CVFEM and Galerkin
stiffness coincide for linear elements: Baliga & Patankar 1980; Voller 2009, *Basic
Control Volume Finite Element Methods for Fluids and Solids*, ch. 3). Hence

* the flux of a **linear** field is exact on any tet mesh (no non-orthogonal correction);
* the operator is **symmetric** positive semi-definite: an implicit step is one SPD solve
  (one back-substitution with a reused factorisation, or one PCG solve) instead of the
  deferred-correction iterations of the cell-centred graph (:mod:`.tets`);
* ``G_ij`` is **negative** on edges whose opposite dihedral angles sum past 180°
  (obtuse tets: ``K_ij = k/6 Σ l_kl cot θ_kl`` over the opposite edges). ``K`` stays
  SPSD — it is the P1 stiffness — so the solver and the energy bookkeeping are unaffected,
  but it is not an M-matrix: a discrete maximum principle is not guaranteed (small
  over/undershoots next to steep fronts on poor meshes).

Boundary: every boundary triangle is split into three pieces (the median-dual cut, area
``A/3`` each, the triangle's normal), each a boundary face owned by its vertex. The surface
temperature of a piece is the vertex temperature; the graph expresses this with a
cell-to-face conductance ``g = β k A_piece / ℓ_v`` (``ℓ_v = V_v^{1/3}``) with a large
``β`` (:data:`SURFACE_CONDUCTANCE_FACTOR`), so that ``T_s − T_v = q ℓ_v / (β k)``: β⁻¹ of the
temperature drop across one element. For flux, convection and radiation boundaries the
surface balance stays well conditioned (its Jacobian is ``A γκ/(γ + κ) → A κ`` and
``T_s = (γ T_v + …)/(γ + h + …)`` is computed to round-off whatever γ). A
:class:`~shipthermal.conditions.FixedTemperature` becomes a penalty ``g (T_fix − T_v)``; its
residual round-off is ``g ε T`` per face, so the energy bookkeeping of Dirichlet faces is
accurate to about ``β ε`` (≈ 2e-8 relative for β = 1e8). Prescribe fixed temperatures at the
owning vertex (``graph.cell_centroid[graph.bface_cell]``), not at the piece centroid.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..errors import check_positive, require
from ..materials import Material
from .graph import CellGraph
from .tets import PatchRule, _tet_materials

__all__ = ["build_dual_tet_graph", "SURFACE_CONDUCTANCE_FACTOR", "VTK_VERTEX"]

VTK_VERTEX = 1

#: β of the module docstring: the boundary piece's surface temperature differs from its
#: vertex temperature by 1e-8 of the temperature drop across one element (1e-9 K for 300 W
#: m-2 into 1 cm steel elements), while the round-off of a fixed-temperature penalty stays
#: ~1e-8 of the face's heat flow. Measured on the tests' meshes: 1e8 to 1e12 give the same
#: MMS errors to 4 digits.
SURFACE_CONDUCTANCE_FACTOR = 1e8

# Tet edges (local vertex pairs) and, for each, the two other vertices.
_EDGES = np.array([[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]])
_OTHERS = np.array([[2, 3], [1, 3], [1, 2], [0, 3], [0, 2], [0, 1]])
# Faces opposite each vertex, wound outward for a positively oriented tet.
_FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])


def build_dual_tet_graph(points, tets, material: str | Material | Sequence = "mild_steel",
                         cell_material: np.ndarray | None = None,
                         patches: str | PatchRule = "boundary", part_name: str = "solid",
                         surface_conductance_factor: float = SURFACE_CONDUCTANCE_FACTOR) -> CellGraph:
    """Vertex-centred (median-dual, CVFEM) cell graph of a tetrahedral mesh.

    Parameters
    ----------
    points : (N, 3) [m]
        Mesh vertices; they become the cells (``cell_centroid`` = vertex position).
    tets : (M, 4) vertex indices
    material : str or Material, or a sequence of them
        The material (or the table indexed by ``cell_material``).
    cell_material : (M,) int, optional
        Index into ``material`` per **tet**. A vertex between materials gets a blended
        material with the volume-weighted ρc of its control volume (exact heat capacity);
        conduction is assembled tet by tet with each tet's own k.
    patches : str or callable
        Name for all boundary faces, or ``rule(triangle_centroid (t,3), triangle_normal
        (t,3))`` returning one patch name per boundary **triangle**; the triangle's three
        vertex pieces share it.
    part_name : str
        Part name of all cells.
    surface_conductance_factor : float
        β of the module docstring [-].

    Returns
    -------
    CellGraph
        ``kind="dual-tetrahedral"``. Boundary face ``3 t + k`` is the piece of boundary
        triangle ``t`` at its ``k``-th vertex; ``bface_vertices`` holds the whole triangle
        (for output). ``metadata``: ``tets`` (M, 4), ``boundary_triangles`` (t, 3),
        ``n_negative_edges`` (edges with G < 0), ``min_dihedral_deg``/``max_dihedral_deg``.
        Vertices no tet uses are rejected.
    """
    points = np.asarray(points, dtype=float)
    tets = np.asarray(tets, dtype=np.int64)
    check_positive("surface_conductance_factor", surface_conductance_factor)
    mats, cell_material, tets, volume = _tet_materials(points, tets, material, cell_material)
    n = len(points)
    used = np.bincount(tets.ravel(), minlength=n) > 0
    require(bool(used.all()), "points", f"{int(np.sum(~used))} unused vertices",
            "every vertex must belong to a tetrahedron (they become the cells)",
            "Drop unused vertices (e.g. np.unique(tets, return_inverse=True))")

    k_tet = np.array([m.conductivity for m in mats])[cell_material]
    owner = tets.ravel()
    cv_volume, vertex_material, materials = _control_volumes(owner, volume, cell_material, mats, n)
    p = points[tets]                                  # (M, 4, 3)
    face_cells, conductance, face_area = _edge_conductances(p, tets, k_tet, volume, n)

    btri = _boundary_triangles(tets, n)
    b_cell, b_area, b_normal, b_centroid, centroid_t, normal_t = _boundary_pieces(points, btri)
    k_vertex = np.bincount(owner, np.repeat(k_tet * volume / 4.0, 4), n) / cv_volume
    length = np.cbrt(cv_volume)
    b_conductance = surface_conductance_factor * k_vertex[b_cell] * b_area / length[b_cell]
    patch_names, t_patch = _triangle_patches(patches, centroid_t, normal_t)

    dihedral = _dihedral_range(p)
    return CellGraph(
        cell_centroid=points.copy(), cell_volume=cv_volume, cell_material=vertex_material,
        materials=materials, cell_part=np.zeros(n, np.int32), part_names=(part_name,),
        face_cells=face_cells, face_area=face_area, face_conductance=conductance,
        bface_cell=b_cell, bface_area=b_area, bface_normal=b_normal, bface_centroid=b_centroid,
        bface_conductance=b_conductance, bface_patch=np.repeat(t_patch, 3),
        patch_names=patch_names, points=points,
        cell_connectivity=np.stack([np.ones(n, np.int64), np.arange(n)], axis=1).ravel(),
        cell_types=np.full(n, VTK_VERTEX, np.uint8), bface_vertices=np.repeat(btri, 3, axis=0),
        correction=None, kind="dual-tetrahedral",
        metadata={"tets": tets, "tet_material": cell_material, "boundary_triangles": btri,
                  "n_negative_edges": int(np.sum(conductance < 0)),
                  "min_dihedral_deg": dihedral[0], "max_dihedral_deg": dihedral[1],
                  "surface_conductance_factor": float(surface_conductance_factor)},
    )


def _control_volumes(owner, volume, cell_material, mats, n: int):
    """Control volumes (a quarter of each tet to each of its vertices) and their material:
    ``(cv_volume (n,), vertex_material (n,), materials)``."""
    quarter = np.repeat(volume / 4.0, 4)
    cv_volume = np.bincount(owner, quarter, n)
    frac = np.zeros((n, len(mats)))
    np.add.at(frac, (owner, np.repeat(cell_material, 4)), quarter)
    frac /= cv_volume[:, None]
    vertex_material, materials = _blend(frac, mats)
    return cv_volume, vertex_material, materials


def _edge_conductances(p, tets, k_tet, volume, n: int):
    """The P1 stiffness summed per mesh edge, and the area of the edge's median-dual
    facets: ``(face_cells (e, 2) lo → hi, conductance (e,), face_area (e,))``."""
    # ---- P1 stiffness per tet edge -------------------------------------------------------
    jac = (p[:, 1:] - p[:, :1]).transpose(0, 2, 1)   # columns p1-p0, p2-p0, p3-p0
    inv = np.linalg.inv(jac)                          # rows: ∇φ1, ∇φ2, ∇φ3
    grads = np.concatenate([-inv.sum(axis=1, keepdims=True), inv], axis=1)   # (M, 4, 3)
    ga, gb = grads[:, _EDGES[:, 0]], grads[:, _EDGES[:, 1]]                    # (M, 6, 3)
    k_ab = (k_tet * volume)[:, None] * np.einsum("mei,mei->me", ga, gb)       # K_ab (M, 6)

    # Median-dual facet of each tet edge: quadrilateral midpoint → face centroid → tet
    # centroid → other face centroid; area vector ½ (diagonal × diagonal), oriented a → b.
    pa, pb = p[:, _EDGES[:, 0]], p[:, _EDGES[:, 1]]
    pc, pd = p[:, _OTHERS[:, 0]], p[:, _OTHERS[:, 1]]
    mid = 0.5 * (pa + pb)
    cen = p.mean(axis=1)[:, None, :]
    facet = 0.5 * np.cross(cen - mid, (pa + pb + pd) / 3.0 - (pa + pb + pc) / 3.0)
    sign = np.sign(np.einsum("mei,mei->me", facet, pb - pa))
    facet *= sign[..., None]

    # ---- unique edges --------------------------------------------------------------------
    ea = tets[:, _EDGES[:, 0]].ravel()
    eb = tets[:, _EDGES[:, 1]].ravel()
    lo, hi = np.minimum(ea, eb), np.maximum(ea, eb)
    flip = np.where(ea > eb, -1.0, 1.0)               # facet vectors point lo → hi
    key = lo * n + hi
    uniq, inv_e = np.unique(key, return_inverse=True)
    face_cells = np.stack([uniq // n, uniq % n], axis=1)
    conductance = -np.bincount(inv_e, k_ab.ravel(), len(uniq))
    svec = np.stack([np.bincount(inv_e, (facet[..., c].ravel() * flip), len(uniq))
                     for c in range(3)], axis=1)
    face_area = np.linalg.norm(svec, axis=1)
    return face_cells, conductance, face_area


def _boundary_triangles(tets, n: int):
    """The tet faces that belong to one tet only, wound outward (t, 3)."""
    tri = tets[:, _FACES].reshape(-1, 3)
    tkey = np.sort(tri, axis=1)
    if n < 2_000_000:     # one int64 key per triangle (n³ < 2⁶³): sorts ~10× faster than rows
        tkey = (tkey[:, 0] * n + tkey[:, 1]) * n + tkey[:, 2]
        _, first, counts = np.unique(tkey, return_index=True, return_counts=True)
    else:
        _, first, counts = np.unique(tkey, axis=0, return_index=True, return_counts=True)
    return tri[first[counts == 1]]


def _boundary_pieces(points, btri):
    """The three vertex pieces of each boundary triangle (piece ``3t + k`` at vertex
    ``btri[t, k]``): owner, area, normal and centroid of each piece, and the centroid and
    normal of each triangle."""
    q0, q1, q2 = points[btri[:, 0]], points[btri[:, 1]], points[btri[:, 2]]
    svec_t = 0.5 * np.cross(q1 - q0, q2 - q0)
    area_t = np.linalg.norm(svec_t, axis=1)
    normal_t = svec_t / area_t[:, None]
    centroid_t = (q0 + q1 + q2) / 3.0
    b_cell = btri.ravel()                               # piece 3t + k at vertex btri[t, k]
    b_area = np.repeat(area_t / 3.0, 3)
    b_normal = np.repeat(normal_t, 3, axis=0)
    # Centroid of the quadrilateral piece (vertex, two edge midpoints, triangle centroid):
    # 11/18 of its vertex and 7/36 of each other vertex.
    qs = points[btri]                                  # (t, 3, 3)
    b_centroid = ((11.0 / 18.0) * qs + (7.0 / 36.0) * (qs.sum(axis=1, keepdims=True) - qs)).reshape(-1, 3)
    return b_cell, b_area, b_normal, b_centroid, centroid_t, normal_t


def _triangle_patches(patches, centroid_t, normal_t):
    """Patch names, and the patch of each boundary triangle, from a name or a rule."""
    nt = len(centroid_t)
    if isinstance(patches, str):
        patch_names = (patches,)
        t_patch = np.zeros(nt, dtype=np.int32)
    else:
        labels = np.asarray(patches(centroid_t, normal_t)).astype(str)
        require(labels.shape == (nt,), "patches", labels.shape,
                f"the rule must return one name per boundary triangle ({nt})")
        names, t_patch = np.unique(labels, return_inverse=True)
        patch_names = tuple(str(x) for x in names)
        t_patch = t_patch.astype(np.int32)
    return patch_names, t_patch


def _blend(frac: np.ndarray, mats: tuple[Material, ...]):
    """Material index per vertex from its control volume's material fractions (n, m).

    Vertices inside one material keep it; each distinct mixture becomes a blended
    :class:`Material` with the volume-weighted ρ, ρc and k (ρc is what the solver uses: the
    heat capacity of the control volume is then exact).
    """
    n, m = frac.shape
    if m == 1:
        return np.zeros(n, np.int32), mats
    pure = np.isclose(frac.max(axis=1), 1.0, rtol=0, atol=1e-14)
    index = np.argmax(frac, axis=1).astype(np.int32)
    materials = list(mats)
    mixed = np.flatnonzero(~pure)
    if len(mixed):
        rows, inv = np.unique(frac[mixed], axis=0, return_inverse=True)
        rho = np.array([x.density for x in mats])
        rc = np.array([x.volumetric_heat_capacity for x in mats])
        kk = np.array([x.conductivity for x in mats])
        for w in rows:
            density = float(w @ rho)
            label = " + ".join(f"{w[j]:.3f} {mats[j].name}" for j in np.flatnonzero(w > 0))
            materials.append(Material(f"blend({label})", density, float(w @ rc) / density,
                                      float(w @ kk), "control-volume blend of the tets' "
                                      "materials by volume (vertex-centred graph)"))
        index[mixed] = len(mats) + inv.ravel().astype(np.int32)
    return index, tuple(materials)


def _dihedral_range(p: np.ndarray) -> tuple[float, float]:
    """Smallest and largest dihedral angle over all tets [deg] (mesh quality: the dual
    conductances turn negative past ~90° opposite an edge)."""
    normals = []
    for f in _FACES:
        a, b, c = p[:, f[0]], p[:, f[1]], p[:, f[2]]
        nrm = np.cross(b - a, c - a)
        normals.append(nrm / np.linalg.norm(nrm, axis=1, keepdims=True))
    cosines = [np.einsum("ij,ij->i", normals[i], normals[j]) for i in range(4) for j in range(i + 1, 4)]
    ang = np.degrees(np.pi - np.arccos(np.clip(np.stack(cosines), -1.0, 1.0)))
    return float(ang.min()), float(ang.max())
