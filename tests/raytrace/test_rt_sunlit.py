"""Direct-sun lit fractions and shadows against exact geometry."""

import numpy as np
import pytest

from shipthermal.errors import InputError
from shipthermal.raytrace import (ReceiverPlane, make_tracer, shadow_area_on_plane,
                                  sun_lit_fraction)
from shipthermal.raytrace.analytic import convex_shadow_area
from shipthermal.raytrace.scenes import box, combine, rectangle

BACKENDS = ["embree", "numba"]


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("lo, hi, sun", [
    ([0, 0, 1.0], [2, 1, 2.5], [0.3, -0.4, 0.8]),  # floating box, high sun
    ([-1, -1, 0.0], [1, 2, 3.0], [-0.8, 0.3, 0.5]),  # box resting on the plane, low sun
])
def test_box_shadow_area_on_plane(backend, lo, hi, sun):
    V, F = box(lo, hi, 2)
    tracer = make_tracer(V, F, backend)
    s = unit(sun)
    exact = convex_shadow_area(V, s, 0.0)
    # the shadow lies within the hull of the box's footprint and its projection
    t = V[:, 2] / s[2]
    proj = V[:, :2] - t[:, None] * s[:2]
    (x0, y0), (x1, y1) = proj.min(0) - 0.5, proj.max(0) + 0.5
    plane = ReceiverPlane(z=0.0, x_min=x0, x_max=x1, y_min=y0, y_max=y1, nx=300, ny=300)
    area, se = shadow_area_on_plane(tracer, s, plane, seed=4)
    # stratified sampling: only cells on the shadow's edge carry error; 4 sigma of that
    # estimate (which is not a strict bound, see its docstring) plus nothing else
    assert abs(area - exact) < 4 * se, (area, exact, se)
    assert se < 0.01 * exact  # the test is sharp: a 1 % error in the geometry would fail


def test_half_shadowed_face():
    # Ground square [-5, 5]² at z = 0 as two triangles; a blocker plate at z = 2 over
    # x in [-20, 2]; sun at 45° elevation towards +x. A ground point is shaded when
    # x + 2 / tan(45°) <= 2, i.e. x <= 0: the shadow edge is the line x = 0, which cuts the
    # lower-right triangle (y <= x) with lit share 37.5/50 = 0.75 and the upper-left one
    # (y >= x) with 12.5/50 = 0.25.
    ground = rectangle([-5, -5, 0], [10, 0, 0], [0, 10, 0], 1, 1)
    blocker = rectangle([-20, -20, 2], [22, 0, 0], [0, 40, 0], 1, 1)
    V, F = combine(ground, blocker)
    tracer = make_tracer(V, F)
    s = unit([1.0, 0.0, 1.0])
    k = 1024
    lit = sun_lit_fraction(tracer, V, F, s, samples_per_face=k, seed=2).face[:, 0]
    # which ground triangle is which: its centroid tells
    centroid = V[F[:2]].mean(axis=1)
    expected = np.where(centroid[:, 1] < centroid[:, 0], 0.75, 0.25)
    # binomial 3 sigma with k samples bounds the stratified estimate's error
    tol = 3 * np.sqrt(0.75 * 0.25 / k)
    np.testing.assert_allclose(lit[:2], expected, atol=tol)
    # area-weighted: half the square is lit
    assert abs(lit[:2].mean() - 0.5) < tol
    # the blocker's top faces the sun unobstructed; nothing is above it
    np.testing.assert_array_equal(lit[2:], 1.0)


def test_grid_faces_in_shadow_are_exactly_dark():
    # same scene with the ground split along the shadow edge: whole faces are lit or dark
    ground = rectangle([-5, -5, 0], [10, 0, 0], [0, 10, 0], 10, 4)
    blocker = rectangle([-20, -20, 2], [22, 0, 0], [0, 40, 0], 1, 1)
    V, F = combine(ground, blocker)
    s = unit([1.0, 0.0, 1.0])
    for backend in BACKENDS:
        lit = sun_lit_fraction(make_tracer(V, F, backend), V, F, s, samples_per_face=8,
                               seed=0).face[:80, 0]
        cx = V[F[:80]].mean(axis=1)[:, 0]
        np.testing.assert_array_equal(lit, np.where(cx < 0, 0.0, 1.0))


def test_back_faces_are_dark_and_sea_rules():
    up = rectangle([0, 0, 1], [1, 0, 0], [0, 1, 0])  # normal +z
    down = rectangle([0, 0, 3], [0, 1, 0], [1, 0, 0])  # normal -z, above the first
    wet = rectangle([3, 0, -2], [1, 0, 0], [0, 1, 0])  # normal +z, under water
    V, F = combine(up, down, wet)
    tracer = make_tracer(V, F)
    suns = np.array([[0, 0, 1.0], [1.0, 0, -1.0], [0.2, 0.1, 0.0]])
    lit = sun_lit_fraction(tracer, V, F, suns, samples_per_face=16, seed=1).face
    # sun overhead: `up` is shaded by `down` (same footprint, 2 m above)
    np.testing.assert_array_equal(lit[:2, 0], 0.0)
    np.testing.assert_array_equal(lit[2:4, 0], 0.0)  # `down` faces away
    np.testing.assert_array_equal(lit[4:, 0], 1.0)
    # sun below (its rays from `down` pass beside `up`): only `down` faces it, and without
    # a sea nothing stops it
    np.testing.assert_array_equal(lit[:, 1], [0, 0, 1, 1, 0, 0])
    # grazing sun: n · s = 0 counts as facing away
    np.testing.assert_array_equal(lit[:, 2], 0.0)
    with_sea = sun_lit_fraction(tracer, V, F, suns, samples_per_face=16, seed=1,
                                sea_level_z=0.0).face
    np.testing.assert_array_equal(with_sea[4:, 0], 0.0)  # under water: dark
    np.testing.assert_array_equal(with_sea[:, 1], 0.0)  # sun below the horizon: all dark


def test_many_suns_equal_one_at_a_time_and_backends_agree():
    V, F = combine(box([0, 0, 0], [4, 2, 1], 3), box([1, 0.5, 1], [2, 1.5, 3], 2))
    rng = np.random.default_rng(0)
    suns = rng.normal(size=(5, 3))
    suns[:, 2] = np.abs(suns[:, 2]) + 0.2
    # two threads: the directions run side by side (one per thread), a single one alone
    tracer = make_tracer(V, F, "embree", n_threads=2)
    together = sun_lit_fraction(tracer, V, F, suns, samples_per_face=8, seed=3).face
    serial = sun_lit_fraction(tracer.single_threaded(), V, F, suns, samples_per_face=8,
                              seed=3).face
    np.testing.assert_array_equal(serial, together)
    for j in range(len(suns)):
        alone = sun_lit_fraction(tracer, V, F, suns[j], samples_per_face=8, seed=3).face
        np.testing.assert_array_equal(alone[:, 0], together[:, j])
    assert 0 < together.mean() < 1 and ((together > 0) & (together < 1)).any()
    nb = sun_lit_fraction(make_tracer(V, F, "numba"), V, F, suns, samples_per_face=8,
                          seed=3).face
    # same rays: any disagreement is a ray within the float32 offset of an edge; allow
    # 3 of the 8 x 5 x 180 sample rays
    assert np.abs(nb - together).sum() * 8 <= 3


def test_receiver_plane_matches_shadow_area():
    V, F = box([0, 0, 1], [1, 1, 2], 1)
    s = unit([0.2, 0.1, 1.0])
    plane = ReceiverPlane(z=0.0, x_min=-1, x_max=2, y_min=-1, y_max=2, nx=120, ny=120)
    tracer = make_tracer(V, F)
    res = sun_lit_fraction(tracer, V, F, [s, -s], samples_per_face=4, seed=6,
                           receiver_plane=plane, sea_level_z=0.0)
    area = (1 - res.plane[..., 0]).sum() * plane.cell_area
    exact = convex_shadow_area(V, s, 0.0)
    assert abs(area - exact) < 0.02 * exact  # ~4 sigma of the edge-cell estimate (~0.5 %)
    np.testing.assert_array_equal(res.plane[..., 1], 0.0)  # sun below the horizon


def test_bad_input():
    V, F = rectangle([0, 0, 0], [1, 0, 0], [0, 1, 0])
    tracer = make_tracer(V, F)
    with pytest.raises(InputError, match="sun_dirs"):
        sun_lit_fraction(tracer, V, F, [[0, 0, 0]])
    with pytest.raises(InputError, match="samples_per_face"):
        sun_lit_fraction(tracer, V, F, [0, 0, 1], samples_per_face=0)
    with pytest.raises(InputError, match="x_max"):
        ReceiverPlane(z=0, x_min=1, x_max=0, y_min=0, y_max=1)
    with pytest.raises(InputError, match="sun_dir"):
        shadow_area_on_plane(tracer, [0, 0, -1], ReceiverPlane(0, 0, 1, 0, 1))
