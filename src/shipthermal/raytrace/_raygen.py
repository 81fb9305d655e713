"""Numba kernels generating the sample rays (fused versions of :mod:`.sampling`).

They compute exactly what the numpy functions in :mod:`shipthermal.raytrace.sampling`
compute (square-root triangle mapping, Malley's cosine-weighted directions, Cranley–Patterson
shifted quasi-random samples) in one parallel pass without temporaries; the numpy functions
are the reference the tests compare them with.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange


@njit(cache=True, nogil=True)
def _face_samples(a, i, v0, e1, e2, normals, t1, t2, base, shift, offset, with_dirs,
                  origins, dirs):
    """Samples of face ``i`` into rows ``a·k … a·k + k − 1`` (see :func:`face_rays`)."""
    k = base.shape[0]
    for j in range(k):
        r = a * k + j
        u = (base[j, 0] + shift[i, 0]) % 1.0
        v = (base[j, 1] + shift[i, 1]) % 1.0
        su = np.sqrt(u)
        w1 = su * (1.0 - v)
        w2 = su * v
        for c in range(3):
            origins[r, c] = v0[i, c] + w1 * e1[i, c] + w2 * e2[i, c] + offset * normals[i, c]
        if with_dirs:
            u = (base[j, 2] + shift[i, 2]) % 1.0
            v = (base[j, 3] + shift[i, 3]) % 1.0
            rr = np.sqrt(u)
            phi = 2.0 * np.pi * v
            x = rr * np.cos(phi)
            y = rr * np.sin(phi)
            z = np.sqrt(max(0.0, 1.0 - u))
            for c in range(3):
                dirs[r, c] = x * t1[i, c] + y * t2[i, c] + z * normals[i, c]


@njit(parallel=True, cache=True)
def face_rays(v0, e1, e2, normals, t1, t2, base, shift, face_idx, offset, with_dirs):
    """Origins (and cosine-weighted directions when ``with_dirs``) of ``len(base)`` samples
    on each face in ``face_idx``.

    Sample k of face i uses ``s = (base[k] + shift[i]) % 1``: s[0:2] place the point on the
    triangle, s[2:4] (if present) pick the direction. Origins are moved ``offset`` along the
    normal. Returns arrays of shape (len(face_idx) * len(base), 3); directions are (0, 3)
    without ``with_dirs``.
    """
    n = face_idx.shape[0]
    k = base.shape[0]
    origins = np.empty((n * k, 3))
    dirs = np.empty((n * k if with_dirs else 0, 3))
    for a in prange(n):
        _face_samples(a, face_idx[a], v0, e1, e2, normals, t1, t2, base, shift, offset,
                      with_dirs, origins, dirs)
    return origins, dirs


@njit(cache=True, nogil=True)
def face_rays_serial(v0, e1, e2, normals, t1, t2, base, shift, face_idx, offset, with_dirs):
    """:func:`face_rays` in the calling thread, without the GIL (for callers that run
    several chunks at once on their own threads)."""
    n = face_idx.shape[0]
    k = base.shape[0]
    origins = np.empty((n * k, 3))
    dirs = np.empty((n * k if with_dirs else 0, 3))
    for a in range(n):
        _face_samples(a, face_idx[a], v0, e1, e2, normals, t1, t2, base, shift, offset,
                      with_dirs, origins, dirs)
    return origins, dirs


@njit(parallel=True, cache=True)
def face_frames(vertices, faces):
    """Corner v0, edges e1 = v1 - v0, e2 = v2 - v0, unit normal n = e1 × e2 / |e1 × e2|,
    area, and tangents t1 (e1 made orthogonal to n, normalised), t2 = n × t1 of each face.

    Fused version of :func:`.sampling.face_geometry` + :func:`.sampling.face_frames`;
    zero-area faces get n = t1 = t2 = 0 as there.
    """
    m = faces.shape[0]
    v0 = np.empty((m, 3))
    e1 = np.empty((m, 3))
    e2 = np.empty((m, 3))
    n = np.zeros((m, 3))
    t1 = np.zeros((m, 3))
    t2 = np.zeros((m, 3))
    area = np.empty(m)
    for i in prange(m):
        a = faces[i, 0]
        b = faces[i, 1]
        c = faces[i, 2]
        for k in range(3):
            v0[i, k] = vertices[a, k]
            e1[i, k] = vertices[b, k] - vertices[a, k]
            e2[i, k] = vertices[c, k] - vertices[a, k]
        cx = e1[i, 1] * e2[i, 2] - e1[i, 2] * e2[i, 1]
        cy = e1[i, 2] * e2[i, 0] - e1[i, 0] * e2[i, 2]
        cz = e1[i, 0] * e2[i, 1] - e1[i, 1] * e2[i, 0]
        twice = np.sqrt(cx * cx + cy * cy + cz * cz)
        area[i] = 0.5 * twice
        if twice <= 0.0:
            continue
        nx = cx / twice
        ny = cy / twice
        nz = cz / twice
        n[i, 0] = nx
        n[i, 1] = ny
        n[i, 2] = nz
        dot = e1[i, 0] * nx + e1[i, 1] * ny + e1[i, 2] * nz
        ux = e1[i, 0] - dot * nx
        uy = e1[i, 1] - dot * ny
        uz = e1[i, 2] - dot * nz
        un = np.sqrt(ux * ux + uy * uy + uz * uz)
        ux /= un
        uy /= un
        uz /= un
        t1[i, 0] = ux
        t1[i, 1] = uy
        t1[i, 2] = uz
        t2[i, 0] = ny * uz - nz * uy
        t2[i, 1] = nz * ux - nx * uz
        t2[i, 2] = nx * uy - ny * ux
    return v0, e1, e2, n, area, t1, t2
