"""The finite-volume cell graph: the one mesh representation the solver knows.

Whatever the cell shape (multilayer shell prisms, tetrahedra), the solver sees

* **cells** with a centroid, a volume and a material (so a heat capacity ρ·c·V);
* **interior faces** between two cells with an area and a two-point conductance
  ``G = k_f A cos θ / |d|`` [W K-1] (``d`` joins the two centroids, ``θ`` is the angle
  between ``d`` and the face normal);
* **boundary faces** of one cell with an area, an outward normal, a cell-to-face
  conductance and a named **patch** (``"deck:outer"``, ``"xmin"`` …) that boundary
  conditions refer to.

On meshes whose faces are not orthogonal to the centroid joins (tetrahedra) the two-point
flux alone is not consistent. Such graphs carry a :class:`NonOrthogonalCorrection`: a
least-squares cell gradient and the explicit part ``k_f ∇T_f · (S − (S·e) e)`` of the face
flux. The flux of a linear temperature field is then exact. How a time step treats it
(:data:`CORRECTION_TREATMENTS`):

``"extrapolated"`` (default)
    evaluated once per step from the field extrapolated to the new time (``2Tⁿ − Tⁿ⁻¹``
    after the first step, ``Tⁿ`` on it; surface temperatures consistent with it) and held
    fixed in the step, like OpenFOAM's ``nNonOrthogonalCorrectors 0`` but second order in
    time: the lag error is that of the extrapolation, O(Δt²). A linear problem is then
    linear in the step: one Newton solve and one convergence check.
``"iterated"``
    re-evaluated at every Newton pass and iterated to convergence inside the step
    (deferred correction, Anderson-accelerated; ~12 passes per step on pytetwild meshes).

Either way the interior correction fluxes are antisymmetric face by face, so they cancel
in the energy sum to round-off.

The graph is immutable; builders live in :mod:`.shells` and :mod:`.tets`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from ..errors import InputError
from ..materials import Material

__all__ = ["CellGraph", "NonOrthogonalCorrection", "CORRECTION_TREATMENTS", "VTK_TETRA",
           "VTK_WEDGE"]

VTK_TETRA = 10
VTK_WEDGE = 13
CORRECTION_TREATMENTS = ("extrapolated", "iterated")


@dataclass(frozen=True, eq=False)
class NonOrthogonalCorrection:
    """Data for the explicit non-orthogonal flux correction.

    Attributes
    ----------
    gradient : scipy.sparse.csr_matrix, shape (3 n, n + b)
        Least-squares gradient operator: ``g = gradient @ concat(T_cell, T_face)`` gives the
        x, y, z components stacked (``g.reshape(3, n)``) [K m-1].
    face_weight : ndarray, shape (m,)
        Interpolation weight of the owner cell's gradient at each interior face.
    face_kt : ndarray, shape (m, 3)
        ``k_f (S − (S·e) e)`` for each interior face [W m K-1], with ``S = A n``.
    bface_kt : ndarray, shape (b, 3)
        The same for boundary faces, with ``e`` from the cell centroid to the face centroid.
    treatment : str
        How a time step treats it, one of :data:`CORRECTION_TREATMENTS` (module docstring).
    """

    gradient: sp.csr_matrix
    face_weight: np.ndarray
    face_kt: np.ndarray
    bface_kt: np.ndarray
    treatment: str = "extrapolated"


@dataclass(frozen=True, eq=False)
class CellGraph:
    """Cells, interior faces and patched boundary faces (see module docstring).

    All geometric arrays are SI: m, m², m³; conductances in W K-1.
    """

    cell_centroid: np.ndarray       # (n, 3) [m]
    cell_volume: np.ndarray         # (n,) [m3]
    cell_material: np.ndarray       # (n,) index into materials
    materials: tuple[Material, ...]
    cell_part: np.ndarray           # (n,) index into part_names
    part_names: tuple[str, ...]
    face_cells: np.ndarray          # (m, 2) owner, neighbour
    face_area: np.ndarray           # (m,) [m2]
    face_conductance: np.ndarray    # (m,) [W/K]
    bface_cell: np.ndarray          # (b,)
    bface_area: np.ndarray          # (b,) [m2]
    bface_normal: np.ndarray        # (b, 3) outward unit normal
    bface_centroid: np.ndarray      # (b, 3) [m]
    bface_conductance: np.ndarray   # (b,) [W/K] cell centre to face
    bface_patch: np.ndarray         # (b,) index into patch_names
    patch_names: tuple[str, ...]
    points: np.ndarray              # (p, 3) vertices for output
    cell_connectivity: np.ndarray   # VTK-style flat [npts, i0, i1, ...] per cell
    cell_types: np.ndarray          # (n,) VTK cell types
    bface_vertices: np.ndarray      # (b, 3) triangles into points
    correction: NonOrthogonalCorrection | None = None
    kind: str = "graph"
    metadata: dict = field(default_factory=dict)

    # ---- sizes -----------------------------------------------------------------
    @property
    def n_cells(self) -> int:
        return int(self.cell_volume.shape[0])

    @property
    def n_faces(self) -> int:
        return int(self.face_area.shape[0])

    @property
    def n_bfaces(self) -> int:
        return int(self.bface_area.shape[0])

    # ---- derived properties ----------------------------------------------------
    @cached_property
    def cell_rho_c(self) -> np.ndarray:
        """Volumetric heat capacity ρ·c of each cell [J m-3 K-1]."""
        table = np.array([m.volumetric_heat_capacity for m in self.materials])
        return table[self.cell_material]

    @cached_property
    def cell_conductivity(self) -> np.ndarray:
        """Thermal conductivity of each cell [W m-1 K-1]."""
        table = np.array([m.conductivity for m in self.materials])
        return table[self.cell_material]

    @cached_property
    def heat_capacity(self) -> np.ndarray:
        """Heat capacity ρ·c·V of each cell [J K-1]."""
        return self.cell_rho_c * self.cell_volume

    @cached_property
    def conduction_matrix(self) -> sp.csr_matrix:
        """Two-point conduction operator K (symmetric positive semi-definite) [W K-1].

        ``-K @ T`` is the net two-point conductive heat flow into each cell.
        """
        n = self.n_cells
        i, j = self.face_cells[:, 0], self.face_cells[:, 1]
        g = self.face_conductance
        rows = np.concatenate([i, j, i, j])
        cols = np.concatenate([i, j, j, i])
        vals = np.concatenate([g, g, -g, -g])
        return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))

    @cached_property
    def cell_faces(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Each cell's interior faces as a CSR list ``(ptr, neighbour, conductance)``: cell
        ``c``'s neighbours are ``neighbour[ptr[c]:ptr[c + 1]]`` (in face order). The per-cell
        (gathered) form of the conduction flows, which threads can share."""
        i, j = self.face_cells[:, 0], self.face_cells[:, 1]
        ptr, order = _group_by(np.concatenate([i, j]), self.n_cells)
        nb = np.concatenate([j, i])[order].astype(np.int64)
        g = np.concatenate([self.face_conductance, self.face_conductance])[order]
        return ptr, nb, np.ascontiguousarray(g, dtype=np.float64)

    @cached_property
    def cell_bfaces(self) -> tuple[np.ndarray, np.ndarray]:
        """Each cell's boundary faces as a CSR list ``(ptr, bface)`` (in face order)."""
        return _group_by(self.bface_cell, self.n_cells)

    @cached_property
    def boundary_gradient(self) -> tuple[sp.csr_matrix, np.ndarray] | None:
        """Rows of the least-squares gradient for the cells that own boundary faces.

        Returns ``(G, local)``: ``G @ concat(T_cell, T_face)`` gives those cells' gradients
        stacked ``(3, m)`` and ``local[b]`` is the row of boundary face ``b``'s cell. Used
        by the solver's face-level fixed point, which only needs boundary cells.
        """
        if self.correction is None:
            return None
        n = self.n_cells
        cells, local = np.unique(self.bface_cell, return_inverse=True)
        rows = np.concatenate([cells, n + cells, 2 * n + cells])
        return self.correction.gradient[rows].tocsr(), local

    @cached_property
    def correction_operators(self) -> tuple[sp.csr_matrix, sp.csr_matrix] | None:
        """The non-orthogonal correction as two sparse operators on ``concat(T_cell,
        T_face)``: ``(F, Fb)`` with ``F @ x`` the correction flux through each interior face
        into its owner and ``Fb @ x`` the flow from each boundary face into its cell [W]
        (the least-squares gradient, its interpolation to the face and ``k_f t_f`` folded
        into one matrix each). None without a correction.
        """
        corr = self.correction
        if corr is None:
            return None
        n = self.n_cells
        grad = corr.gradient
        own, nei = self.face_cells[:, 0], self.face_cells[:, 1]
        w = corr.face_weight
        face = None
        bface = None
        for c in range(3):
            kt, bkt = corr.face_kt[:, c], corr.bface_kt[:, c]
            term = (sp.diags(kt * w) @ grad[c * n + own] + sp.diags(kt * (1.0 - w)) @ grad[c * n + nei])
            bterm = sp.diags(bkt) @ grad[c * n + self.bface_cell]
            face = term if face is None else face + term
            bface = bterm if bface is None else bface + bterm
        return face.tocsr(), bface.tocsr()

    def correction_flows(self, temp_cell: np.ndarray, temp_face: np.ndarray):
        """Non-orthogonal correction flows ``(into each cell from its interior faces, from each
        boundary face into its cell)`` [W] (:attr:`correction_operators`). The interior
        part adds each face's flux to its owner and subtracts it from its neighbour, so it
        sums to zero to round-off."""
        face, bface = self.correction_operators
        x = np.concatenate([temp_cell, temp_face])
        flux = face @ x
        own, nei = self.face_cells[:, 0], self.face_cells[:, 1]
        n = self.n_cells
        return np.bincount(own, flux, n) - np.bincount(nei, flux, n), bface @ x

    def patch_faces(self, name: str) -> np.ndarray:
        """Indices of the boundary faces of one patch."""
        if name not in self.patch_names:
            raise InputError("patch", name, f"unknown patch; known: {', '.join(self.patch_names)}")
        return np.flatnonzero(self.bface_patch == self.patch_names.index(name))

    @cached_property
    def patch_area(self) -> dict[str, float]:
        """Total area of each patch [m2]."""
        sums = np.bincount(self.bface_patch, weights=self.bface_area, minlength=len(self.patch_names))
        return {name: float(a) for name, a in zip(self.patch_names, sums)}

    def summary(self) -> str:
        """One-paragraph description (counts, volume, patches)."""
        lines = [f"{self.kind} cell graph: {self.n_cells} cells, {self.n_faces} interior faces, "
                 f"{self.n_bfaces} boundary faces, volume {self.cell_volume.sum():.6g} m3"]
        for name, area in self.patch_area.items():
            lines.append(f"  patch {name}: {area:.6g} m2")
        return "\n".join(lines)

    # ---- output geometry ------------------------------------------------------------
    def to_pyvista(self):
        """Cells as a :class:`pyvista.UnstructuredGrid` (no data).

        For a vertex-centred graph (``kind == "dual-tetrahedral"``) the cells are the mesh
        vertices: the grid is the tetrahedral mesh itself, whose *points* are the cells
        (cell values go to ``point_data``).
        """
        import pyvista as pv        # deferred: start-up cost (~1 s to import)

        if self.kind == "dual-tetrahedral":
            tets = self.metadata["tets"]
            conn = np.hstack([np.full((len(tets), 1), 4), tets]).ravel()
            return pv.UnstructuredGrid(conn, np.full(len(tets), VTK_TETRA, np.uint8), self.points)
        return pv.UnstructuredGrid(self.cell_connectivity, self.cell_types, self.points)

    def boundary_surface(self):
        """Boundary faces as a :class:`pyvista.PolyData` with a ``patch`` cell array."""
        import pyvista as pv        # deferred: start-up cost (~1 s to import)

        faces = np.hstack([np.full((self.n_bfaces, 1), 3), self.bface_vertices]).ravel()
        surf = pv.PolyData(self.points, faces)
        surf.cell_data["patch"] = self.bface_patch.astype(np.int32)
        return surf


def least_squares_gradient(cell_centroid: np.ndarray, face_cells: np.ndarray,
                           bface_cell: np.ndarray, bface_centroid: np.ndarray) -> sp.csr_matrix:
    """Weighted least-squares gradient operator over face neighbours.

    For each cell P the gradient minimises Σ_j w_j (T_j − T_P − g·d_j)² over its face
    neighbours j (neighbouring cells and its own boundary faces, whose temperature is the
    face temperature), with ``w_j = 1/|d_j|²``. Exact for linear fields.

    Returns a CSR matrix of shape (3 n, n + b) acting on ``concat(T_cell, T_face)``.
    """
    n = cell_centroid.shape[0]
    b = bface_cell.shape[0]
    own, nei = face_cells[:, 0], face_cells[:, 1]
    # Each neighbour relation (cell p, neighbour column q, offset d) twice for interior faces.
    p = np.concatenate([own, nei, bface_cell])
    q = np.concatenate([nei, own, n + np.arange(b)])
    d = np.concatenate([cell_centroid[nei] - cell_centroid[own],
                        cell_centroid[own] - cell_centroid[nei],
                        bface_centroid - cell_centroid[bface_cell]])
    w = 1.0 / np.einsum("ij,ij->i", d, d)
    # Normal matrix per cell: Σ w d dᵀ
    outer = w[:, None, None] * d[:, :, None] * d[:, None, :]
    normal = np.zeros((n, 3, 3))
    np.add.at(normal, p, outer)
    inv = np.linalg.inv(normal)
    # g_P = inv_P Σ w d (T_q − T_P): coefficient of T_q is inv_P w d, of T_P minus their sum.
    coef = np.einsum("kij,kj->ki", inv[p], w[:, None] * d)  # (r, 3)
    rows_q = []
    cols_q = []
    vals_q = []
    for comp in range(3):
        rows_q.append(comp * n + p)
        cols_q.append(q)
        vals_q.append(coef[:, comp])
        rows_q.append(comp * n + p)
        cols_q.append(p)
        vals_q.append(-coef[:, comp])
    return sp.csr_matrix((np.concatenate(vals_q), (np.concatenate(rows_q), np.concatenate(cols_q))),
                         shape=(3 * n, n + b))


def _group_by(cell: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """CSR grouping of items by their cell: ``(ptr, order)``, cell ``c``'s items being
    ``order[ptr[c]:ptr[c + 1]]`` in their own order."""
    order = np.argsort(cell, kind="stable").astype(np.int64)
    ptr = np.zeros(n + 1, np.int64)
    np.cumsum(np.bincount(cell, minlength=n), out=ptr[1:])
    return ptr, order
