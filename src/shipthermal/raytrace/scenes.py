"""Small triangle scenes for tests, examples and benchmarks (plates, boxes, spheres)."""

from __future__ import annotations

import numpy as np

__all__ = ["rectangle", "box", "combine", "benchmark_scene"]


def rectangle(corner, u, v, nu: int = 1, nv: int = 1):
    """Planar rectangle ``corner + a u + b v`` (a, b in [0, 1]) split into ``2 nu nv``
    triangles of equal area; the normal is u × v.

    Returns
    -------
    vertices : ((nu+1)(nv+1), 3) float [m]
    faces : (2 nu nv, 3) int
    """
    corner = np.asarray(corner, dtype=np.float64)
    u = np.asarray(u, dtype=np.float64)
    v = np.asarray(v, dtype=np.float64)
    a, b = np.meshgrid(np.linspace(0, 1, nu + 1), np.linspace(0, 1, nv + 1), indexing="ij")
    vertices = corner + a.reshape(-1, 1) * u + b.reshape(-1, 1) * v
    idx = np.arange((nu + 1) * (nv + 1)).reshape(nu + 1, nv + 1)
    p00 = idx[:-1, :-1].ravel()
    p10 = idx[1:, :-1].ravel()
    p11 = idx[1:, 1:].ravel()
    p01 = idx[:-1, 1:].ravel()
    faces = np.concatenate([np.stack([p00, p10, p11], 1), np.stack([p00, p11, p01], 1)])
    return vertices, faces


def box(lo, hi, n: int = 1):
    """Axis-aligned box with outward normals, each side split into ``2 n²`` triangles."""
    lo = np.asarray(lo, dtype=np.float64)
    hi = np.asarray(hi, dtype=np.float64)
    d = hi - lo
    ex, ey, ez = np.diag(d)
    sides = [
        rectangle(lo, ey, ex, n, n),  # bottom, normal -z
        rectangle(lo + ez, ex, ey, n, n),  # top, +z
        rectangle(lo, ex, ez, n, n),  # y = lo, normal -y
        rectangle(lo + ey, ez, ex, n, n),  # y = hi, +y
        rectangle(lo, ez, ey, n, n),  # x = lo, -x
        rectangle(lo + ex, ey, ez, n, n),  # x = hi, +x
    ]
    return combine(*sides)


def combine(*meshes):
    """Concatenate (vertices, faces) pairs into one mesh (vertices are not merged)."""
    vs, fs, offset = [], [], 0
    for v, f in meshes:
        vs.append(np.asarray(v, dtype=np.float64))
        fs.append(np.asarray(f) + offset)
        offset += len(v)
    return np.vstack(vs), np.vstack(fs).astype(np.int64)


def benchmark_scene(target_faces: int = 100_000):
    """A ship-sized scene of about ``target_faces`` triangles: an 80 m × 12 m hull-like box
    with superstructure boxes and a radar-dome sphere (trimesh icosphere), on z ≥ 0.

    The boxes interpenetrate rather than touch, so no two triangles are coplanar and
    overlapping (coincident faces make first-hit ties that either tracer may break either
    way, which would blur the backend comparison).
    """
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=5)  # 20 480 faces
    sv = sphere.vertices * 2.5 + [10.0, 0.0, 17.5]
    n_box = max(1, int(np.sqrt(max(target_faces - len(sphere.faces), 12) / (12 * 3))))
    parts = [
        box([-40.0, -6.0, 0.0], [40.0, 6.0, 6.0], n_box),
        box([-5.0, -5.0, 5.5], [20.0, 5.0, 12.0], n_box),
        box([5.0, -2.0, 11.5], [15.0, 2.0, 15.0], n_box),
        (sv, sphere.faces),
    ]
    return combine(*parts)
