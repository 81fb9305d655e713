"""Structured surface grids: triangles of a vertex grid, and merging coincident vertices."""

from __future__ import annotations

import numpy as np

__all__ = ["grid_faces", "merge_vertices"]


def grid_faces(ni: int, nj: int, offset: int = 0, flip: bool = False) -> np.ndarray:
    """Triangles of a structured (ni+1) × (nj+1) vertex grid (row-major), alternating diagonals."""
    i, j = np.meshgrid(np.arange(ni), np.arange(nj), indexing="ij")
    a = (i * (nj + 1) + j).ravel() + offset
    b = a + (nj + 1)
    c = b + 1
    d = a + 1
    alt = ((i + j) % 2 == 1).ravel()
    t1 = np.where(alt[:, None], np.stack([a, b, d], 1), np.stack([a, b, c], 1))
    t2 = np.where(alt[:, None], np.stack([b, c, d], 1), np.stack([a, c, d], 1))
    tri = np.concatenate([t1, t2])
    return tri[:, ::-1] if flip else tri


def merge_vertices(v: np.ndarray, f: np.ndarray, tol: float):
    """Merge vertices closer than ``tol`` (clusters of a k-d tree) and drop collapsed triangles."""
    # deferred: start-up cost (scipy.sparse.csgraph and scipy.spatial take ~1 s to import)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    pairs = cKDTree(v).query_pairs(tol, output_type="ndarray")
    n = len(v)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, inv = connected_components(graph, directed=False)
    _, first = np.unique(inv, return_index=True)
    f = inv[f]
    ok = (f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 2] != f[:, 0])
    return v[first], f[ok], ok
