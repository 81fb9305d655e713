"""Sample points on triangles and directions over a hemisphere (pure functions).

Points and directions come from a scrambled Halton sequence (scipy.stats.qmc) with one
random Cranley–Patterson shift per face (Cranley & Patterson 1976): every face gets a
well-stratified set, the estimate of each face is unbiased (randomised quasi-Monte Carlo),
and the whole result is reproducible from one ``seed``. The shift also decorrelates
neighbouring faces, which would otherwise share the same pattern.
"""

from __future__ import annotations

import numpy as np
from scipy.stats import qmc

__all__ = ["face_frames", "face_geometry", "unit_samples", "triangle_points",
           "cosine_hemisphere"]


def face_geometry(vertices, faces):
    """Unit normals (right-hand rule on the vertex order), areas [m²] and centroids [m]."""
    tri = np.asarray(vertices, dtype=np.float64)[np.asarray(faces)]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    twice_area = np.linalg.norm(cross, axis=1)
    normals = cross / np.where(twice_area > 0, twice_area, 1.0)[:, None]
    return normals, 0.5 * twice_area, tri.mean(axis=1)


def face_frames(vertices, faces, normals):
    """Orthonormal tangent vectors (t1, t2) with t1 × t2 = normal, per face."""
    tri = np.asarray(vertices, dtype=np.float64)[np.asarray(faces)]
    t1 = tri[:, 1] - tri[:, 0]
    t1 -= np.sum(t1 * normals, axis=1)[:, None] * normals
    norm = np.linalg.norm(t1, axis=1)
    # degenerate faces (zero area) get any frame; they receive no rays anyway
    bad = norm <= 0
    if bad.any():
        helper = np.where(np.abs(normals[bad, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
        t1[bad] = np.cross(normals[bad], helper)
        norm[bad] = np.linalg.norm(t1[bad], axis=1)
    t1 /= np.where(norm > 0, norm, 1.0)[:, None]
    t2 = np.cross(normals, t1)
    return t1, t2


def unit_samples(n_faces: int, n_per_face: int, dim: int, seed: int):
    """Base points in [0, 1)^dim and one shift per face: sample k of face i is
    ``(base[k] + shift[i]) % 1``.

    Returns
    -------
    base : (n_per_face, dim) float
    shift : (n_faces, dim) float
    """
    rng = np.random.default_rng(seed)
    base = qmc.Halton(d=dim, scramble=True, seed=rng).random(n_per_face)
    shift = rng.random((n_faces, dim))
    return base, shift


def triangle_points(tri, u, v):
    """Map unit-square samples to uniformly distributed points on triangles.

    Parameters
    ----------
    tri : (n, 3, 3) float
        Triangle corners [m].
    u, v : (n, k) float
        Samples in [0, 1).

    Returns
    -------
    (n, k, 3) float
        Points [m].

    Notes
    -----
    Square-root mapping (Turk 1990; Shirley & Chiu 1997, eq. 1): barycentric weights
    ``(1 - √u, √u (1 - v), √u v)`` carry a uniform density on the square to a uniform
    density on the triangle while keeping the square's stratification.
    """
    su = np.sqrt(u)
    w1 = su * (1.0 - v)
    w2 = su * v
    w0 = 1.0 - su
    return (w0[..., None] * tri[:, None, 0] + w1[..., None] * tri[:, None, 1]
            + w2[..., None] * tri[:, None, 2])


def cosine_hemisphere(normals, t1, t2, u, v):
    """Cosine-weighted unit directions about each normal (Malley's method).

    Parameters
    ----------
    normals, t1, t2 : (n, 3) float
        Orthonormal frame per face.
    u, v : (n, k) float
        Samples in [0, 1).

    Returns
    -------
    (n, k, 3) float
        Directions with density cos θ / π over the hemisphere of ``normals``.
    """
    r = np.sqrt(u)
    phi = 2.0 * np.pi * v
    x = r * np.cos(phi)
    y = r * np.sin(phi)
    z = np.sqrt(np.maximum(0.0, 1.0 - u))
    return (x[..., None] * t1[:, None] + y[..., None] * t2[:, None]
            + z[..., None] * normals[:, None])
