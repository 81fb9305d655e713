"""Small meshes shared by the solver tests (imported by name: pytest puts this folder on
sys.path)."""

import numpy as np
import trimesh

from shipthermal.materials import Layer, Layup
from shipthermal.mesh import build_shell_graph, build_tet_graph, tetrahedralize_surface

SQUARE_V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0.0]])
SQUARE_F = np.array([[0, 1, 2], [0, 2, 3]])


def plate_graph(thickness, cells, material="mild_steel", name="plate"):
    """A 1 m × 1 m plate (two triangles) extruded through one layer: a 1-D column problem
    (the shell graph has no edge patches, so the sides are adiabatic)."""
    lay = Layup((Layer(material, thickness, cells),))
    return build_shell_graph(SQUARE_V, SQUARE_F, np.zeros(2, int), [name], {name: lay})


def box_tets(extents, edge_length, material="mild_steel", builder=build_tet_graph):
    """pytetwild tets of a box [0, ex]×[0, ey]×[0, ez] with patches xmin…zmax (cell-centred
    graph, or ``builder=build_dual_tet_graph`` for the vertex-centred one)."""
    box = trimesh.creation.box(extents=extents)
    box.apply_translation(np.asarray(extents) / 2.0)
    pts, tets = tetrahedralize_surface(box.vertices, box.faces, edge_length=edge_length)

    def rule(centroid, normal):
        axis = np.argmax(np.abs(normal), axis=1)
        side = np.where(normal[np.arange(len(normal)), axis] > 0, "max", "min")
        return np.char.add(np.array(list("xyz"))[axis], side)

    return builder(pts, tets, material=material, patches=rule)
