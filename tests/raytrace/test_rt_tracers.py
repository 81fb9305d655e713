"""The two tracers against each other and against a brute-force reference.

Agreement tolerance: Embree works in float32. After centring, coordinates are at most
scale/2, where float32 spacing is at most 2**-24·scale ≈ 6e-8·scale; its watertight triangle
test decides edge membership to a few such spacings. Rays whose hit point lies within
EDGE_TOL = 1e-5·scale of a triangle edge (≈ 170 float32 spacings, 1 mm on a 100 m ship) may
legitimately get the neighbouring triangle (or a miss at a silhouette edge); every other ray
must get the identical triangle index from both backends.
"""

import numpy as np
import pytest
import trimesh

from shipthermal.errors import InputError
from shipthermal.raytrace import RAY_OFFSET_FACTOR, EmbreeTracer, NumbaTracer, make_tracer
from shipthermal.raytrace.scenes import box, combine, rectangle

EDGE_TOL_FACTOR = 1e-5


def scene():
    # no coincident faces (a box resting on another would make exact ties between two
    # coplanar triangles, which either backend may resolve either way)
    sphere = trimesh.creation.icosphere(subdivisions=3)  # 1280 faces
    return combine(box([-4, -2, 0], [4, 2, 2], 6),
                   box([-1, -1, 2.3], [1.5, 1, 3.5], 4),
                   (sphere.vertices * 0.8 + [2.5, 0, 3], sphere.faces),
                   rectangle([-6, -4, -0.5], [12, 0, 0], [0, 8, 0], 10, 10))


def random_rays(n, seed, vertices):
    rng = np.random.default_rng(seed)
    lo, hi = vertices.min(0), vertices.max(0)
    pad = 0.2 * (hi - lo)
    origins = rng.uniform(lo - pad, hi + pad, size=(n, 3))
    directions = rng.normal(size=(n, 3))
    return origins, directions / np.linalg.norm(directions, axis=1)[:, None]


def hit_distance(vertices, faces, tri, origins, directions):
    """Ray-plane distance to the given triangles (float64 numpy)."""
    v = vertices[faces[tri]]
    n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    return np.sum((v[:, 0] - origins) * n, 1) / np.sum(directions * n, 1)


def distance_to_edges(vertices, faces, tri, points):
    """Distance from each point to the nearest edge (segment) of its triangle."""
    v = vertices[faces[tri]]
    best = np.full(len(points), np.inf)
    for a, b in ((0, 1), (1, 2), (2, 0)):
        ab = v[:, b] - v[:, a]
        s = np.clip(np.sum((points - v[:, a]) * ab, 1) / np.sum(ab * ab, 1), 0, 1)
        best = np.minimum(best, np.linalg.norm(v[:, a] + s[:, None] * ab - points, axis=1))
    return best


def test_offset_factor_is_float32_safe():
    # 1e-5·scale must stay far above float32 spacing at |x| <= scale/2 (<= 2**-24·scale)
    assert RAY_OFFSET_FACTOR / 2.0**-24 > 100


def test_bvh_matches_brute_force():
    V, F = scene()
    tracer = NumbaTracer(V, F)
    o, d = random_rays(20000, 1, V)
    bvh = tracer.intersects_first(o, d)
    ref = tracer.brute_force_first(o, d)
    assert (bvh >= 0).mean() > 0.2  # the rays do exercise the tree
    diff = np.flatnonzero(bvh != ref)
    # the same float64 triangle test in both: only exact ties (a ray through a shared edge
    # or vertex, both triangles at the same distance) may be resolved differently
    assert (bvh[diff] >= 0).all() and (ref[diff] >= 0).all()
    t_bvh = hit_distance(V, F, bvh[diff], o[diff], d[diff])
    t_ref = hit_distance(V, F, ref[diff], o[diff], d[diff])
    np.testing.assert_allclose(t_bvh, t_ref, rtol=0, atol=1e-12 * tracer.scale)


@pytest.mark.parametrize("max_distance", [np.inf, 3.0])
def test_embree_and_numba_agree(max_distance):
    V, F = scene()
    emb, nb = EmbreeTracer(V, F), NumbaTracer(V, F)
    o, d = random_rays(200000, 2, V)
    a = emb.intersects_first(o, d, max_distance)
    b = nb.intersects_first(o, d, max_distance)
    assert 0.1 < (a >= 0).mean() < 0.9  # both hits and misses are exercised
    diff = np.flatnonzero(a != b)
    assert len(diff) <= 1e-3 * len(o), len(diff)
    tol = EDGE_TOL_FACTOR * emb.scale
    for got in (a, b):
        hit = diff[got[diff] >= 0]
        t = hit_distance(V, F, got[hit], o[hit], d[hit])
        p = o[hit] + t[:, None] * d[hit]
        near_edge = distance_to_edges(V, F, got[hit], p) < tol
        # a finite max_distance adds ties at the distance cut-off: allow those too
        near_cut = np.abs(t - max_distance) < tol
        assert (near_edge | near_cut).all(), (hit[~(near_edge | near_cut)], got[hit])
    # occlusion queries agree with "first hit exists" on both backends
    for tr, first in ((emb, a), (nb, b)):
        np.testing.assert_array_equal(tr.any_hit(o, d, max_distance), first >= 0)


@pytest.mark.parametrize("backend", ["embree", "numba"])
def test_max_distance_and_offsets(backend):
    # A plate at z = 10; rays straight up from z = 0 hit it at distance 10.
    V, F = rectangle([-1, -1, 10], [2, 0, 0], [0, 2, 0], 3, 3)
    tracer = make_tracer(V, F, backend)
    o = np.array([[0.1, 0.2, 0.0], [0.3, -0.4, 0.0], [5.0, 5.0, 0.0]])
    d = np.array([[0, 0, 1.0], [0, 0, 2.0], [0, 0, 1.0]])  # un-normalised direction is fine
    np.testing.assert_array_equal(tracer.any_hit(o, d, 10.0 + 1e-3), [True, True, False])
    np.testing.assert_array_equal(tracer.any_hit(o, d, 10.0 - 1e-3), [False] * 3)
    assert (tracer.intersects_first(o, d)[:2] >= 0).all()
    # a ray leaving the plate from an offset point does not see the plate itself
    start = np.array([[0.0, 0.0, 10.0 + tracer.offset], [0.0, 0.0, 10.0 - tracer.offset]])
    np.testing.assert_array_equal(
        tracer.intersects_first(start, [[0.3, 0.1, 1.0], [0.3, 0.1, -1.0]]), [-1, -1])
    # ... but a ray pointing back at it from there does
    assert (tracer.intersects_first(start, [[0, 0, -1.0], [0, 0, 1.0]]) >= 0).all()


def test_offset_survives_a_far_translation():
    # the same plate 1000 km away from the origin: centring keeps float32 precise
    V, F = rectangle([-1, -1, 10], [2, 0, 0], [0, 2, 0], 3, 3)
    shift = np.array([1e6, -2e6, 0.0])
    tracer = EmbreeTracer(V + shift, F)
    start = np.array([[0.0, 0.0, 10.0 + tracer.offset]]) + shift
    assert tracer.intersects_first(start, [[0.2, 0.0, 1.0]])[0] == -1
    assert tracer.intersects_first(start, [[0.0, 0.0, -1.0]])[0] >= 0


def test_bad_rays_are_rejected():
    V, F = rectangle([0, 0, 0], [1, 0, 0], [0, 1, 0])
    tracer = make_tracer(V, F)
    with pytest.raises(InputError, match="directions"):
        tracer.intersects_first(np.zeros((2, 3)), np.zeros((2, 3)))
    with pytest.raises(InputError, match="directions"):
        tracer.any_hit(np.zeros((2, 3)), np.ones((3, 3)))
    with pytest.raises(InputError, match="max_distance"):
        tracer.any_hit(np.zeros((1, 3)), np.ones((1, 3)), -1.0)


@pytest.mark.parametrize("backend", ["embree", "numba"])
def test_tracers_pickle(backend):
    # tracers travel to dask workers: a pickled copy must answer the same
    import pickle

    V, F = scene()
    tracer = make_tracer(V, F, backend)
    copy = pickle.loads(pickle.dumps(tracer))
    o, d = random_rays(1000, 3, V)
    np.testing.assert_array_equal(copy.intersects_first(o, d), tracer.intersects_first(o, d))


def test_embree_threads_come_from_one_persistent_pool():
    # a large batch is split over threads of the process's pool: the one-thread answer,
    # and calls after the first start no new threads
    import threading

    V, F = scene()
    one, two = EmbreeTracer(V, F, n_threads=1), EmbreeTracer(V, F, n_threads=2)
    o, d = random_rays(100_000, 4, V)
    expected = one.intersects_first(o, d)
    np.testing.assert_array_equal(two.intersects_first(o, d), expected)
    started = threading.active_count()
    for _ in range(5):
        np.testing.assert_array_equal(two.intersects_first(o, d), expected)
        np.testing.assert_array_equal(two.any_hit(o, d), expected >= 0)
    assert threading.active_count() == started


def test_backends_agree_on_ship_sized_scene():
    # ~97k triangles, 1.5M view-factor rays leaving the surfaces (the hard case: origins a
    # float32-offset away from faces, many grazing rays into concave corners)
    from shipthermal.raytrace.scenes import benchmark_scene
    from shipthermal.raytrace.viewfactors import view_factor_rays

    V, F = benchmark_scene()
    emb, nb = EmbreeTracer(V, F), NumbaTracer(V, F)
    o, d = view_factor_rays(emb, V, F, np.arange(len(F)), 16, seed=0)
    o, d = o.reshape(-1, 3), d.reshape(-1, 3)
    a = emb.intersects_first(o, d)
    b = nb.intersects_first(o, d)
    diff = np.flatnonzero(a != b)
    assert len(diff) <= 1e-4 * len(o), len(diff)
    tol = EDGE_TOL_FACTOR * emb.scale
    for got in (a, b):
        hit = diff[got[diff] >= 0]
        t = hit_distance(V, F, got[hit], o[hit], d[hit])
        p = o[hit] + t[:, None] * d[hit]
        assert (distance_to_edges(V, F, got[hit], p) < tol).all()
    # the offset is enough: no ray re-enters the plane it left (its own triangle or a
    # coplanar neighbour of the same flat side), which would be a false self-shadow
    src = np.repeat(np.arange(len(F)), 16)
    tri = V[F]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.linalg.norm(n, axis=1)[:, None]
    for got in (a, b):
        h = got >= 0
        i, j = src[h], got[h]
        same_plane = (np.sum(n[i] * n[j], 1) > 1 - 1e-12) & (
            np.abs(np.sum((tri[j, 0] - tri[i, 0]) * n[i], 1)) < 1e-9 * emb.scale)
        assert not same_plane.any(), np.flatnonzero(same_plane)[:10]
