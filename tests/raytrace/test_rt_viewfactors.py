"""View factors by cosine-weighted ray casting against closed forms.

Every rectangle is split into triangles of equal area, each shooting the same number of rays,
so the area-weighted group estimate F_AB is a mean over all rays of group A and its binomial
standard error is sqrt(F(1-F)/N_rays). The samples are randomised quasi-Monte Carlo, whose
error is at most of that order, so "within 3 sigma" is a fair (conservative) bound that a
biased tracer (e.g. wrong cosine weighting, self-hits, leaks between triangles) still fails:
a uniform instead of cosine weighting moves F_12 of two unit squares at unit gap from 0.200
to 0.111, ~50 sigma at the ray counts below (checked by swapping the sampler).
"""

import numpy as np
import pytest

from shipthermal.errors import InputError
from shipthermal.raytrace import make_tracer, symmetrize, view_factors
from shipthermal.raytrace.analytic import (parallel_rectangles, perpendicular_rectangles,
                                           sky_view_beside_infinite_wall, strip_to_wall)
from shipthermal.raytrace.scenes import combine, rectangle

BACKENDS = ["embree", "numba"]


def group_factor(vf, group_a, group_b):
    """Area-weighted view factor from the faces in group_a to those in group_b, and its SE."""
    F = vf.F_faces[group_a][:, group_b]
    a = vf.areas[group_a]
    f = float((a * np.asarray(F.sum(axis=1)).ravel()).sum() / a.sum())
    se = np.sqrt(f * (1 - f) / (vf.rays_per_face * len(group_a)))
    return f, se


def test_closed_forms_match_tabulated_values():
    # Incropera Table 13.2 / Fig. 13.4-13.6 read-offs: unit squares at unit gap 0.1998;
    # perpendicular squares with a common edge 0.2000 (both quoted to 4 digits in Howell's
    # catalogue C-11 / C-14). Guards against a typo in the formulas the tests rely on.
    assert parallel_rectangles(1.0, 1.0, 1.0) == pytest.approx(0.1998, abs=1e-4)
    assert perpendicular_rectangles(1.0, 1.0, 1.0) == pytest.approx(0.2000, abs=1e-4)
    # reciprocity of the perpendicular formula: A_i F_ij = A_j F_ji
    f_ij = perpendicular_rectangles(2.0, 1.0, 3.0)
    f_ji = perpendicular_rectangles(2.0, 3.0, 1.0)
    assert 1.0 * f_ij == pytest.approx(3.0 * f_ji, rel=1e-12)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("x, y, gap", [(1.0, 1.0, 1.0), (2.0, 1.0, 0.5)])
def test_parallel_rectangles(backend, x, y, gap):
    bottom = rectangle([0, 0, 0], [x, 0, 0], [0, y, 0], 4, 4)  # normal +z
    top = rectangle([0, 0, gap], [0, y, 0], [x, 0, 0], 4, 4)  # normal -z
    V, F = combine(bottom, top)
    tracer = make_tracer(V, F, backend)
    vf = view_factors(tracer, V, F, rays_per_face=1000, seed=3, sea_level_z=None)
    n = len(bottom[1])
    f12, se12 = group_factor(vf, np.arange(n), np.arange(n, 2 * n))
    f21, se21 = group_factor(vf, np.arange(n, 2 * n), np.arange(n))
    exact = parallel_rectangles(x, y, gap)
    assert abs(f12 - exact) < 3 * se12, (f12, exact, se12)
    assert abs(f21 - exact) < 3 * se21, (f21, exact, se21)
    # nothing else in the scene: what does not reach the other plate escapes to the sky
    np.testing.assert_allclose(vf.row_sums, 1.0, atol=1e-12)
    assert vf.F_sea.max() == 0.0
    # a plate cannot see itself (coplanar triangles, rays offset off the plane)
    assert vf.F_faces[:n][:, :n].nnz == 0


@pytest.mark.parametrize("edge, w_i, w_j", [(1.0, 1.0, 1.0), (2.0, 1.0, 3.0)])
def test_perpendicular_rectangles_common_edge(edge, w_i, w_j):
    floor = rectangle([0, 0, 0], [edge, 0, 0], [0, w_i, 0], 4, 4)  # z = 0, normal +z
    wall = rectangle([0, 0, 0], [0, 0, w_j], [edge, 0, 0], 4, 4)  # y = 0, normal +y
    V, F = combine(floor, wall)
    tracer = make_tracer(V, F, "embree")
    vf = view_factors(tracer, V, F, rays_per_face=1000, seed=5, sea_level_z=None)
    n = len(floor[1])
    f, se = group_factor(vf, np.arange(n), np.arange(n, 2 * n))
    exact = perpendicular_rectangles(edge, w_i, w_j)
    assert abs(f - exact) < 3 * se, (f, exact, se)
    f_back, se_back = group_factor(vf, np.arange(n, 2 * n), np.arange(n))
    exact_back = perpendicular_rectangles(edge, w_j, w_i)
    assert abs(f_back - exact_back) < 3 * se_back, (f_back, exact_back, se_back)


def test_sky_view_of_strip_beside_wall():
    # A horizontal strip 1 m to 3 m from a 4 m high, 60 m long wall, sea plane far below.
    # An upward face sees no direction below its horizon, so F_sky = 1 - F_wall exactly and
    # F_sea = 0; F_wall from view-factor algebra on the common-edge closed form.
    length, near, far, height = 60.0, 1.0, 3.0, 4.0
    x0 = -length / 2
    strip = rectangle([x0, near, 0], [length, 0, 0], [0, far - near, 0], 30, 2)
    wall = rectangle([x0, 0, 0], [0, 0, height], [length, 0, 0], 30, 4)  # normal +y
    V, F = combine(strip, wall)
    tracer = make_tracer(V, F, "embree")
    vf = view_factors(tracer, V, F, rays_per_face=400, seed=7, sea_level_z=-10.0)
    n = len(strip[1])
    a = vf.areas[:n]
    f_sky = float((a * vf.F_sky[:n]).sum() / a.sum())
    se = np.sqrt(f_sky * (1 - f_sky) / (400 * n))
    exact = 1.0 - strip_to_wall(length, near, far, height)
    assert abs(f_sky - exact) < 3 * se, (f_sky, exact, se)
    assert vf.F_sea[:n].max() == 0.0
    # the mid-strip faces see the wall almost as if it were infinitely long: the 2-D form
    # (1 + cos beta)/2 averaged over the strip's width differs from the 3-D value by the
    # wall-end corrections, O(height / (length / 2)) ~ 1e-2 here.
    xs = np.linspace(near, far, 201)
    inf_wall = np.trapezoid(sky_view_beside_infinite_wall(xs, height), xs) / (far - near)
    assert abs(inf_wall - exact) < 2e-2


def test_open_horizontal_face_sees_only_sky():
    V, F = rectangle([0, 0, 1], [2, 0, 0], [0, 2, 0], 2, 2)
    tracer = make_tracer(V, F, "embree")
    vf = view_factors(tracer, V, F, rays_per_face=500, seed=1, sea_level_z=0.0)
    # every ray of an upward face goes up: exactly 1, no statistical slack needed
    np.testing.assert_array_equal(vf.F_sky, 1.0)
    np.testing.assert_array_equal(vf.F_sea, 0.0)
    assert vf.F_faces.nnz == 0


@pytest.mark.parametrize("backend", BACKENDS)
def test_vertical_face_half_sky_half_sea(backend):
    V, F = rectangle([0, 0, 1], [1, 0, 0], [0, 0, 1], 2, 2)  # normal -y, above the sea
    tracer = make_tracer(V, F, backend)
    k = 2000
    vf = view_factors(tracer, V, F, rays_per_face=k, seed=11, sea_level_z=0.0)
    n = len(F)
    f_sky = vf.F_sky.mean()
    se = np.sqrt(0.25 / (k * n))
    assert abs(f_sky - 0.5) < 3 * se, (f_sky, se)
    np.testing.assert_allclose(vf.F_sky + vf.F_sea, 1.0, atol=1e-12)
    # without a sea everything escaping counts as sky
    vf_open = view_factors(tracer, V, F, rays_per_face=k, seed=11, sea_level_z=None)
    np.testing.assert_array_equal(vf_open.F_sky, 1.0)


def test_submerged_face_sees_only_sea():
    V, F = rectangle([0, 0, -2], [1, 0, 0], [0, 0, 1], 1, 1)
    vf = view_factors(make_tracer(V, F), V, F, rays_per_face=64, seed=0, sea_level_z=0.0)
    np.testing.assert_array_equal(vf.F_sea, 1.0)


def test_sea_plane_cuts_rays_before_far_faces():
    # A plate under water level seen from a vertical face above: the sea plane comes first,
    # so the plate (below the sea) must receive nothing.
    wall = rectangle([0, 0, 1], [1, 0, 0], [0, 0, 1], 1, 1)  # normal -y
    deep = rectangle([-5, -10, -1], [10, 0, 0], [0, 10, 0], 1, 1)  # normal +z, under the sea
    V, F = combine(wall, deep)
    vf = view_factors(make_tracer(V, F), V, F, rays_per_face=500, seed=2, sea_level_z=0.0)
    assert vf.F_faces[:2].nnz == 0
    vf_dry = view_factors(make_tracer(V, F), V, F, rays_per_face=500, seed=2, sea_level_z=None)
    assert vf_dry.F_faces[:2].nnz > 0  # the same plate is seen when there is no sea


def test_reciprocity_option():
    bottom = rectangle([0, 0, 0], [1, 0, 0], [0, 2, 0], 2, 3)
    wall = rectangle([0, 0, 0], [0, 0, 1.5], [1, 0, 0], 3, 2)
    V, F = combine(bottom, wall)
    tracer = make_tracer(V, F)
    vf = view_factors(tracer, V, F, rays_per_face=400, seed=4, sea_level_z=-1.0)
    G = vf.F_faces.multiply(vf.areas[:, None]).toarray()
    assert np.abs(G - G.T).max() > 1e-3  # raw estimates are not reciprocal ...
    sym = view_factors(tracer, V, F, rays_per_face=400, seed=4, sea_level_z=-1.0,
                       reciprocity=True)
    Gs = sym.F_faces.multiply(sym.areas[:, None]).toarray()
    np.testing.assert_allclose(Gs, Gs.T, atol=1e-14)  # ... symmetrised ones are
    np.testing.assert_allclose(sym.row_sums, 1.0, atol=1e-12)
    assert sym.symmetric and (sym.F_sky >= 0).all() and (sym.F_sea >= 0).all()
    # symmetrising must not move the group factor beyond its noise
    n = len(bottom[1])
    f_raw, se = group_factor(vf, np.arange(n), np.arange(n, 2 * n))
    f_sym, _ = group_factor(sym, np.arange(n), np.arange(n, 2 * n))
    exact = perpendicular_rectangles(1.0, 2.0, 1.5)
    assert abs(f_sym - exact) < 3 * se, (f_sym, f_raw, exact, se)
    assert symmetrize(sym).F_faces.nnz == sym.F_faces.nnz


def test_deterministic_and_seed_dependent():
    V, F = combine(rectangle([0, 0, 0], [1, 0, 0], [0, 1, 0], 2, 2),
                   rectangle([0, 0, 0], [0, 0, 1], [1, 0, 0], 2, 2))
    tracer = make_tracer(V, F)
    a = view_factors(tracer, V, F, rays_per_face=64, seed=9)
    b = view_factors(tracer, V, F, rays_per_face=64, seed=9, chunk_rays=100)
    c = view_factors(tracer, V, F, rays_per_face=64, seed=10)
    np.testing.assert_array_equal(a.F_sky, b.F_sky)  # chunking does not change the rays
    np.testing.assert_array_equal(a.F_faces.toarray(), b.F_faces.toarray())
    assert not np.array_equal(a.F_faces.toarray(), c.F_faces.toarray())
    # Embree on two threads, one chunk of faces per thread, against one thread; with a sea
    # through the wall (origins under it) and one without
    two = make_tracer(V, F, "embree", n_threads=2)
    for sea in (0.5, None):
        d = view_factors(two, V, F, rays_per_face=64, seed=9, chunk_rays=100, sea_level_z=sea)
        e = view_factors(two.single_threaded(), V, F, rays_per_face=64, seed=9,
                         chunk_rays=100, sea_level_z=sea)
        assert (d.F_sea == 1).any() if sea else d.F_faces.nnz > 0   # submerged / hits
        for x, y in ((d.F_sky, e.F_sky), (d.F_sea, e.F_sea),
                     (d.F_faces.toarray(), e.F_faces.toarray())):
            np.testing.assert_array_equal(x, y)


def test_backends_give_same_view_factors():
    # Same rays on both tracers: the counts may differ only for rays passing within the
    # float32 offset of a triangle edge; with 4 x 4 x 400 rays we allow a handful. (The sea
    # is put below the floor: a floor lying exactly on the sea plane would make every
    # floor hit tie with the sea, decided differently in float32 and float64.)
    V, F = combine(rectangle([0, 0, 0], [1, 0, 0], [0, 1, 0], 4, 4),
                   rectangle([0, 0, 0], [0, 0, 1], [1, 0, 0], 4, 4))
    e = view_factors(make_tracer(V, F, "embree"), V, F, rays_per_face=400, seed=1,
                     sea_level_z=-0.5)
    m = view_factors(make_tracer(V, F, "numba"), V, F, rays_per_face=400, seed=1,
                     sea_level_z=-0.5)
    diff_rays = np.abs((e.F_faces - m.F_faces).toarray()).sum() * 400
    assert diff_rays <= 5, diff_rays
    assert np.abs(e.F_sky - m.F_sky).max() * 400 <= 2


def test_bad_input_names_the_field():
    V, F = rectangle([0, 0, 0], [1, 0, 0], [0, 1, 0])
    with pytest.raises(InputError, match="rays_per_face"):
        view_factors(make_tracer(V, F), V, F, rays_per_face=0)
    with pytest.raises(InputError, match="backend"):
        make_tracer(V, F, backend="optix")
    with pytest.raises(InputError, match="faces"):
        make_tracer(V, F + 10)


def test_subset_of_faces_shoots_against_the_whole_mesh():
    floor = rectangle([0, 0, 0], [1, 0, 0], [0, 1, 0], 2, 2)
    wall = rectangle([0, 0, 0], [0, 0, 1], [1, 0, 0], 2, 2)
    V, F = combine(floor, wall)
    tracer = make_tracer(V, F)
    n = len(floor[1])
    full = view_factors(tracer, V, F, rays_per_face=200, seed=8)
    part = view_factors(tracer, V, F[:n], rays_per_face=200, seed=8)
    assert part.F_faces.shape == (n, len(F))
    # the floor's rows do not depend on which other faces shoot rays
    np.testing.assert_array_equal(part.F_faces.toarray(), full.F_faces[:n].toarray())
    np.testing.assert_array_equal(part.F_sky, full.F_sky[:n])
    with pytest.raises(InputError, match="F_faces"):
        symmetrize(part)
