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


def kuhn_cube_tets(n: int):
    """The unit cube cut into n³ cells, each into the six tetrahedra of its Kuhn
    (Freudenthal) subdivision along the main diagonal: a conforming, deterministic tet mesh
    (every tetrahedron positively oriented). Returns (points (p, 3), tets (6 n³, 4))."""
    g = np.linspace(0.0, 1.0, n + 1)
    x, y, z = np.meshgrid(g, g, g, indexing="ij")
    pts = np.column_stack([x.ravel(), y.ravel(), z.ravel()])

    def vid(i, j, k):
        return (i * (n + 1) + j) * (n + 1) + k

    i, j, k = (a.ravel() for a in np.meshgrid(np.arange(n), np.arange(n), np.arange(n),
                                              indexing="ij"))
    corner = {(a, b, c): vid(i + a, j + b, k + c) for a in (0, 1) for b in (0, 1)
              for c in (0, 1)}
    tets = []
    for perm in ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)):
        path = [(0, 0, 0)]
        for axis in perm:                       # walk from (0,0,0) to (1,1,1) axis by axis
            step = list(path[-1])
            step[axis] = 1
            path.append(tuple(step))
        tets.append(np.column_stack([corner[c] for c in path]))
    tets = np.concatenate(tets)
    a, b, c, d = (pts[tets[:, m]] for m in range(4))
    flip = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) < 0.0
    tets[flip, 2], tets[flip, 3] = tets[flip, 3], tets[flip, 2].copy()
    return pts, tets
