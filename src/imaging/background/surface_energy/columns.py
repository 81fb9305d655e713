"""Columns of land pixels: the finite-volume mesh of a layered column and the columns of N
pixels, each of one surface class."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from shipthermal.errors import InputError, check_range, require

from ..surface_classes import SURFACE_CLASSES, Layer, SurfaceClass, surface_class


# ---------------------------------------------------------------------------------------------
# Mesh
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ColumnMesh:
    """Finite-volume mesh of one column (cells from the surface down).

    Attributes
    ----------
    thickness : numpy.ndarray
        (m,) cell thickness [m].
    depth : numpy.ndarray
        (m,) depth of the cell centres [m].
    capacity : numpy.ndarray
        (m,) heat capacity per area ρ c Δz [J m-2 K-1].
    conductance : numpy.ndarray
        (m + 1,) face conductances [W m-2 K-1]: ``[0]`` surface face → first cell centre,
        ``[i]`` cell i−1 → cell i (series resistance Δz/2k of both half cells: the
        harmonic mean), ``[m]`` last cell → bottom (the half cell, plus the room film
        for ``'room'``).
    layer : numpy.ndarray
        (m,) index of each cell's layer.
    bottom : str
        ``'deep'`` or ``'room'``.
    """

    thickness: np.ndarray
    depth: np.ndarray
    capacity: np.ndarray
    conductance: np.ndarray
    layer: np.ndarray
    bottom: str

    @property
    def n_cells(self) -> int:
        return len(self.thickness)


def _layer_cells(thickness: float, first: float, growth: float, max_cell: float) -> list:
    """Cell sizes filling one layer: a geometric series from ``first`` (capped at
    ``max_cell``), scaled so it ends exactly on the layer's bottom face."""
    sizes = []
    s = first
    total = 0.0
    while total < thickness * (1.0 - 1e-12):
        sizes.append(s)
        total += s
        s = min(s * growth, max_cell)
    if len(sizes) > 1 and total - thickness > 0.5 * sizes[-1]:
        # the last cell overshoots by more than half of itself: drop it, stretch the rest
        total -= sizes.pop()
    return [x * thickness / total for x in sizes]


def column_mesh(layers: Sequence[Layer], bottom: str = "deep",
                room_film_coefficient: float | None = None, first_cell: float = 0.002,
                growth: float = 1.3, max_cell: float = 0.25) -> ColumnMesh:
    """Cells of a layered column, refined toward the surface.

    Parameters
    ----------
    layers : sequence of Layer
        From the surface down.
    bottom : {'deep', 'room'}
        Bottom boundary; ``'room'`` adds the film ``1 / room_film_coefficient`` to the last
        face's resistance.
    room_film_coefficient : float, optional
        [W m-2 K-1] (``bottom == 'room'``).
    first_cell : float
        Thickness of the top cell [m] (2 mm: a twentieth of the diurnal damping depth of
        asphalt, √(2α/ω) ≈ 0.1 m).
    growth : float
        Ratio of successive cell thicknesses [-] (≥ 1).
    max_cell : float
        Largest cell [m].

    Returns
    -------
    ColumnMesh

    Notes
    -----
    Cells grow geometrically through the layers; each layer's series is scaled so the
    interface is a cell face, and the next layer continues from the last size. A face
    between cells i and i+1 conducts ``1 / (Δz_i / 2k_i + Δz_{i+1} / 2k_{i+1})`` (the
    harmonic mean of k for equal cells): exact for the steady flux through the two half
    cells.
    """
    require(bottom in ("deep", "room"), "column.bottom", bottom, "must be 'deep' or 'room'")
    check_range("column.first_cell", first_cell, 1e-5, 1.0, "m")
    check_range("column.growth", growth, 1.0, 3.0)
    thick, k, rc, which = [], [], [], []
    s = first_cell
    for i, layer in enumerate(layers):
        cells = _layer_cells(layer.thickness, min(s, layer.thickness), growth, max_cell)
        thick += cells
        k += [layer.conductivity] * len(cells)
        rc += [layer.heat_capacity] * len(cells)
        which += [i] * len(cells)
        s = min(cells[-1] * growth, max_cell)
    dz = np.asarray(thick)
    k = np.asarray(k)
    half = 0.5 * dz / k
    cond = np.empty(len(dz) + 1)
    cond[0] = 1.0 / half[0]
    cond[1:-1] = 1.0 / (half[:-1] + half[1:])
    r_bottom = half[-1]
    if bottom == "room":
        require(room_film_coefficient is not None and room_film_coefficient > 0,
                "column.room_film_coefficient", room_film_coefficient,
                "must be > 0 W m-2 K-1 for bottom = 'room'")
        r_bottom += 1.0 / room_film_coefficient
    cond[-1] = 1.0 / r_bottom
    depth = np.cumsum(dz) - 0.5 * dz
    return ColumnMesh(dz, depth, np.asarray(rc) * dz, cond, np.asarray(which), bottom)


# ---------------------------------------------------------------------------------------------
# Columns and forcing
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Columns:
    """N columns, each of one surface class.

    Attributes
    ----------
    classes : tuple of SurfaceClass
        The distinct classes.
    meshes : tuple of ColumnMesh
        One per class.
    class_index : numpy.ndarray
        (N,) index into ``classes`` of each column.
    bottom_temperature : numpy.ndarray
        (N,) deep-ground temperature (``'deep'``) or room temperature (``'room'``) [K].
    emissivity : numpy.ndarray
        (N,) long-wave emissivity [-].
    surface_resistance : numpy.ndarray
        (N,) r_s [s m-1], −1 where the class has no latent heat.
    """

    classes: tuple
    meshes: tuple
    class_index: np.ndarray
    bottom_temperature: np.ndarray
    emissivity: np.ndarray
    surface_resistance: np.ndarray

    @property
    def n_columns(self) -> int:
        return len(self.class_index)

    @property
    def n_cells_max(self) -> int:
        return max(m.n_cells for m in self.meshes)

    def padded(self) -> tuple:
        """Per-class arrays padded to the largest column: ``(n_cells (C,), capacity (C, M),
        conductance (C, M + 1))``."""
        m_max = self.n_cells_max
        n = np.array([m.n_cells for m in self.meshes], dtype=np.int64)
        cap = np.zeros((len(self.meshes), m_max))
        cond = np.zeros((len(self.meshes), m_max + 1))
        for c, mesh in enumerate(self.meshes):
            cap[c, :mesh.n_cells] = mesh.capacity
            cond[c, :mesh.n_cells + 1] = mesh.conductance
        return n, cap, cond


def build_columns(class_of_column: Sequence, bottom_temperature,
                  classes=SURFACE_CLASSES, first_cell: float = 0.002, growth: float = 1.3,
                  max_cell: float = 0.25) -> Columns:
    """Columns for pixels of given classes.

    Parameters
    ----------
    class_of_column : sequence of str, int or SurfaceClass
        (N,) class of each column: a name or a code of ``classes``, or a class.
    bottom_temperature : float or array_like
        (N,) deep-ground temperature of ``'deep'`` classes, room temperature of ``'room'``
        classes [K].
    classes : mapping
        Name → :class:`SurfaceClass` (e.g. after
        :func:`~.surface_classes.apply_overrides`).
    first_cell, growth, max_cell
        Mesh of every class (:func:`column_mesh`).

    Returns
    -------
    Columns
    """
    by_code = {c.code: c for c in classes.values()}
    distinct: dict = {}
    index = np.empty(len(class_of_column), dtype=np.int64)
    for j, item in enumerate(class_of_column):
        if isinstance(item, SurfaceClass):
            cls = item
        elif isinstance(item, (int, np.integer)):
            if int(item) not in by_code:
                raise InputError(f"columns.class[{j}]", int(item),
                                 f"must be a land class code: {sorted(by_code)}")
            cls = by_code[int(item)]
        else:
            cls = surface_class(str(item), classes)
        index[j] = distinct.setdefault(cls.name, (len(distinct), cls))[0]
    cls_tuple = tuple(c for _, c in sorted(distinct.values(), key=lambda x: x[0]))
    meshes = tuple(column_mesh(c.layers, c.bottom, c.room_film_coefficient, first_cell, growth,
                               max_cell) for c in cls_tuple)
    n = len(index)
    tb = np.broadcast_to(np.asarray(bottom_temperature, dtype=float), (n,)).copy()
    check_range("columns.bottom_temperature", tb, 150.0, 400.0, "K")
    emis = np.array([cls_tuple[i].emissivity for i in index])
    rs = np.array([cls_tuple[i].surface_resistance if cls_tuple[i].latent == "penman_monteith"
                   else -1.0 for i in index])
    return Columns(cls_tuple, meshes, index, tb, emis, rs)
