"""Finite-volume meshes: the cell graph and its builders (shells, tetrahedra cell-centred
and vertex-centred)."""

from .dual import build_dual_tet_graph
from .graph import CellGraph, NonOrthogonalCorrection
from .shells import build_shell_graph
from .tets import (build_tet_graph, check_closed_surface, find_self_intersections,
                   tetrahedralize_surface)

__all__ = ["CellGraph", "NonOrthogonalCorrection", "build_shell_graph", "build_tet_graph",
           "build_dual_tet_graph", "check_closed_surface", "find_self_intersections",
           "tetrahedralize_surface"]
