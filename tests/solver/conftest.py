"""Fixtures of the solver tests (helpers live in solver_meshes.py)."""

import pytest
import trimesh

from shipthermal.mesh import tetrahedralize_surface


@pytest.fixture(scope="session")
def unit_cube_tets():
    """Three pytetwild refinements of the unit cube (about 3 k, 7 k and 40 k tets)."""
    box = trimesh.creation.box(extents=(1, 1, 1))
    box.apply_translation((0.5, 0.5, 0.5))
    return [tetrahedralize_surface(box.vertices, box.faces, edge_length=h) for h in (0.2, 0.1, 0.07)]
