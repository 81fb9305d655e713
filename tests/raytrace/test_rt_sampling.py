"""Sample rays: the fused numba kernel against the plain numpy reference, and the moments
of the distributions they must follow."""

import numpy as np

from shipthermal.raytrace import _raygen
from shipthermal.raytrace.sampling import (cosine_hemisphere, face_frames, face_geometry,
                                           triangle_points, unit_samples)


def random_mesh(n, seed):
    rng = np.random.default_rng(seed)
    V = rng.normal(size=(3 * n, 3)) * [5.0, 2.0, 1.0]
    F = np.arange(3 * n).reshape(n, 3)
    return V, F


def test_kernel_matches_numpy_reference():
    V, F = random_mesh(50, 0)
    normals, _, _ = face_geometry(V, F)
    t1, t2 = face_frames(V, F, normals)
    base, shift = unit_samples(len(F), 33, 4, seed=5)
    idx = np.array([3, 7, 7, 49, 0])
    tri = V[F]
    o, d = _raygen.face_rays(tri[:, 0], tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], normals,
                             t1, t2, base, shift, idx, 0.01, True)
    s = (base[None] + shift[idx, None]) % 1.0
    ref_o = triangle_points(tri[idx], s[..., 0], s[..., 1]) + 0.01 * normals[idx, None]
    ref_d = cosine_hemisphere(normals[idx], t1[idx], t2[idx], s[..., 2], s[..., 3])
    np.testing.assert_allclose(o, ref_o.reshape(-1, 3), rtol=0, atol=1e-12)
    np.testing.assert_allclose(d, ref_d.reshape(-1, 3), rtol=0, atol=1e-12)
    # the serial kernel (for chunks traced on several threads) makes the same rays
    for a, b in zip((o, d), _raygen.face_rays_serial(
            tri[:, 0], tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], normals, t1, t2, base,
            shift, idx, 0.01, True)):
        np.testing.assert_array_equal(a, b)


def test_frames_are_orthonormal_and_right_handed():
    V, F = random_mesh(200, 1)
    normals, areas, _ = face_geometry(V, F)
    t1, t2 = face_frames(V, F, normals)
    for a, b in ((t1, t2), (t1, normals), (t2, normals)):
        np.testing.assert_allclose(np.sum(a * b, 1), 0.0, atol=1e-12)
    np.testing.assert_allclose(np.cross(t1, t2), normals, atol=1e-12)
    # area from the cross product equals Heron's formula
    tri = V[F]
    a, b, c = (np.linalg.norm(tri[:, i] - tri[:, j], axis=1) for i, j in ((0, 1), (1, 2), (2, 0)))
    s = (a + b + c) / 2
    np.testing.assert_allclose(areas, np.sqrt(s * (s - a) * (s - b) * (s - c)), rtol=1e-8)


def test_distribution_moments():
    # One triangle, many samples: for Malley's method the polar cosine has mean 2/3 and
    # variance 1/2 - 4/9 = 1/18; uniform points have the centroid as mean. Tolerances are
    # 4 standard errors of plain Monte Carlo (quasi-random samples do better).
    V = np.array([[0.0, 0, 0], [3, 0, 0], [0, 1, 0]])
    F = np.array([[0, 1, 2]])
    normals, _, centroid = face_geometry(V, F)
    t1, t2 = face_frames(V, F, normals)
    n = 20000
    base, shift = unit_samples(1, n, 4, seed=2)
    tri = V[F]
    o, d = _raygen.face_rays(tri[:, 0], tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], normals,
                             t1, t2, base, shift, np.array([0]), 0.0, True)
    np.testing.assert_allclose(np.linalg.norm(d, axis=1), 1.0, atol=1e-12)
    cos = d @ normals[0]
    assert cos.min() >= 0.0
    assert abs(cos.mean() - 2 / 3) < 4 * np.sqrt(1 / 18 / n)
    # points inside the triangle (barycentric coordinates in [0, 1])
    lam = np.linalg.solve(np.c_[tri[0, 1, :2] - tri[0, 0, :2], tri[0, 2, :2] - tri[0, 0, :2]],
                          (o[:, :2] - tri[0, 0, :2]).T)
    assert lam.min() >= -1e-12 and lam.sum(0).max() <= 1 + 1e-12
    spread = np.linalg.norm(tri[0] - centroid[0], axis=1).max()
    np.testing.assert_allclose(o.mean(0), centroid[0], atol=4 * spread / np.sqrt(n))


def test_fused_frames_match_numpy_reference():
    V, F = random_mesh(300, 4)
    F[7] = [F[7, 0], F[7, 0], F[7, 1]]  # a zero-area face
    normals, areas, _ = face_geometry(V, F)
    t1, t2 = face_frames(V, F, normals)
    v0, e1, e2, n, a, u1, u2 = _raygen.face_frames(V, F)
    np.testing.assert_allclose(v0, V[F[:, 0]], atol=0)
    np.testing.assert_allclose(e1, V[F[:, 1]] - V[F[:, 0]], atol=0)
    np.testing.assert_allclose(e2, V[F[:, 2]] - V[F[:, 0]], atol=0)
    for got, ref in ((n, normals), (a, areas), (u1, t1), (u2, t2)):
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12)
    assert a[7] == 0 and not n[7].any()
