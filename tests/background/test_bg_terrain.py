"""Slope/aspect (eqs. 13-14), DEM resampling and the eq. 15 regression."""

import numpy as np
import pytest
import rasterio
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

from imaging.background.landsat import SceneGrid, north_up_transform
from imaging.background.terrain import fit_terrain_regression, read_dem, slope_aspect, southness
from shipthermal.errors import InputError

H = 30.0


def _xy(n):
    r, c = np.mgrid[0:n, 0:n]
    return (c - n // 2) * H, -(r - n // 2) * H      # x east, y north (row 0 = north)


@pytest.mark.parametrize("gx,gy,aspect", [(0.1, 0.0, 270.0), (0.0, 0.1, 180.0), (-0.2, 0.2, 135.0),
                                          (0.05, -0.05, 315.0)])
def test_inclined_plane(gx, gy, aspect):
    # z = gx x + gy y: slope = atan(|grad|), downslope azimuth = atan2(-gx, -gy); Horn's stencil
    # is exact on planes, including the one-sided border (round-off only).
    x, y = _xy(21)
    s, a = slope_aspect(100 + gx * x + gy * y, H)
    np.testing.assert_allclose(s, np.degrees(np.arctan(np.hypot(gx, gy))), atol=1e-10)
    np.testing.assert_allclose(a, aspect, atol=1e-9)
    assert southness(np.array([0.0, 90.0, 180.0]))[[0, 2]].tolist() == [-1.0, 1.0]


def test_cone_against_geometry_and_convergence():
    # z = 500 - k r: slope atan(k) everywhere, aspect = azimuth from the apex. Horn's stencil
    # is second order, so its error falls like (h/r)^2 away from the apex: check the slope
    # error at r >= 5 px is < 0.2 deg and that the observed order between 5 and 10 px is ~2.
    k = 0.3
    x, y = _xy(101)
    r = np.hypot(x, y) / H
    s, a = slope_aspect(500 - k * np.hypot(x, y), H)
    true_s = np.degrees(np.arctan(k))
    true_a = np.degrees(np.arctan2(x, y)) % 360
    far = r >= 5
    assert np.abs(s[far] - true_s).max() < 0.2
    da = (a - true_a + 180) % 360 - 180
    assert np.abs(da[far]).max() < 0.25     # measured 0.21 deg at r = 5 px
    e5 = np.abs(s[(r >= 5) & (r < 6)] - true_s).max()
    e10 = np.abs(s[(r >= 10) & (r < 11)] - true_s).max()
    order = np.log(e5 / e10) / np.log(2.0)
    assert 1.7 < order < 2.3, f"observed order {order:.2f}"


def test_flat_and_nan():
    z = np.zeros((5, 5))
    z[2, 2] = np.nan
    s, a = slope_aspect(z, H)
    assert np.isnan(s[1:4, 1:4]).all() and np.isnan(a[2, 2]) and s[0, 0] == 0 and np.isnan(a[0, 0])   # flat: no aspect


def test_regression_recovers_known_beta():
    # y = b0[class] + b1 z + b2 slope + b3 south + noise(0.3 K): OLS recovers beta within
    # 4 standard errors; without noise it is exact to round-off.
    rng = np.random.default_rng(5)
    n = 20000
    z = rng.uniform(0, 300, n)
    sl = rng.uniform(0, 25, n) + 0.02 * z              # correlated regressors, as on real hills
    so = rng.uniform(-1, 1, n)
    cls = rng.integers(2, 5, n)
    beta = np.array([-0.0065, -0.08, 1.5])
    b0 = {2: -2.0, 3: 1.0, 4: 4.0}
    clean = np.vectorize(b0.get)(cls) + beta[0] * z + beta[1] * sl + beta[2] * so
    exact = fit_terrain_regression(clean, z, sl, so, groups=cls, group_names={2: "veg", 3: "land", 4: "bld"})
    np.testing.assert_allclose(exact.beta, beta, rtol=1e-9)
    assert exact.intercepts == pytest.approx({"veg": -2.0, "land": 1.0, "bld": 4.0}) and exact.r2 == pytest.approx(1.0)
    noisy = fit_terrain_regression(clean + 0.3 * rng.standard_normal(n), z, sl, so, groups=cls)
    assert np.all(np.abs(noisy.beta - beta) < 4 * noisy.stderr)
    assert noisy.rmse == pytest.approx(0.3, rel=0.03)
    single = fit_terrain_regression(beta[0] * z + 3.0, z, sl, so)
    assert single.intercepts["all"] == pytest.approx(3.0) and single.beta_elevation == pytest.approx(beta[0])


def test_regression_needs_pixels():
    with pytest.raises(InputError, match="terrain_regression.pixels"):
        fit_terrain_regression(np.full(10, np.nan), np.ones(10), np.ones(10), np.ones(10))


def _geo_dem(path, nodata_hole=False):
    # a plane in lon/lat degrees, 1 arc-second, float32
    sec = 1 / 3600
    lon0, lat0, n = 121.60, 38.96, 500
    lon = lon0 + (np.arange(n) + 0.5) * sec
    lat = lat0 - (np.arange(n) + 0.5) * sec
    z = (50 + 2000 * (lon[None, :] - lon0) + 3000 * (lat0 - lat[:, None])).astype(np.float32)
    if nodata_hole:
        z[200:220, 200:220] = -9999
    with rasterio.open(path, "w", driver="GTiff", height=n, width=n, count=1, dtype="float32",
                       crs="EPSG:4326", transform=north_up_transform(lon0, lat0, sec, sec), nodata=-9999) as dst:
        dst.write(z, 1)
    return lon0, lat0


def test_dem_is_reprojected_onto_the_scene_grid(tmp_path):
    lon0, lat0 = _geo_dem(tmp_path / "dem.tif")
    (x0,), (y0,) = warp_transform("EPSG:4326", "EPSG:32651", [lon0 + 0.02], [lat0 - 0.02])
    grid = SceneGrid(north_up_transform(x0, y0, 30, 30), CRS.from_epsg(32651), (50, 60))
    dem = read_dem(tmp_path / "dem.tif", grid)
    cols, rows = np.meshgrid(np.arange(60) + 0.5, np.arange(50) + 0.5)
    lon, lat = warp_transform("EPSG:32651", "EPSG:4326", (x0 + cols * 30).ravel(), (y0 - rows * 30).ravel())
    truth = 50 + 2000 * (np.array(lon) - lon0) + 3000 * (lat0 - np.array(lat))
    # GDAL widens the bilinear kernel when the target pixel (30 m) is larger than the source
    # pixel (24 m in longitude), which leaves ~0.05 m on a plane (measured); 0.1 m is still
    # far below the 2-4 m vertical accuracy of 30 m DEMs. A wrong CRS/transform would be off by
    # tens of metres.
    np.testing.assert_allclose(dem.ravel(), truth, atol=0.1)


def test_dem_nodata_is_masked_not_filled(tmp_path):
    lon0, lat0 = _geo_dem(tmp_path / "dem.tif", nodata_hole=True)
    (x0,), (y0,) = warp_transform("EPSG:4326", "EPSG:32651", [lon0 + 0.04], [lat0 - 0.04])
    grid = SceneGrid(north_up_transform(x0, y0, 30, 30), CRS.from_epsg(32651), (80, 80))
    dem = read_dem(tmp_path / "dem.tif", grid)
    assert np.isnan(dem).sum() > 100 and np.isfinite(dem).sum() > 5000


def test_eq15_fits_class_interiors_and_leaves_unknown_terrain_out():
    # Land of two classes (2 west, 3 east) by water (1, south); delta follows eq. 15 exactly
    # inside the classes, and 40 K more on every pixel of a class border: fitted on the
    # interiors, the betas and intercepts are the exact ones (round-off); the terrain term is
    # zero where the terrain is unknown.
    from imaging.background.background import fit_eq15

    rng = np.random.default_rng(3)
    n = 30
    cm = np.full((n, n), 2, np.uint8)
    cm[:, n // 2:] = 3
    cm[-6:, :] = 1
    dem = rng.uniform(0.0, 80.0, (n, n))
    slope = rng.uniform(0.0, 20.0, (n, n))
    south = rng.uniform(-1.0, 1.0, (n, n))
    b0 = {2: 1.5, 3: -0.7}
    delta = 0.006 * dem + 0.04 * slope + 0.9 * south + np.vectorize(lambda c: b0.get(c, 0.0))(cm)
    border = np.zeros((n, n), bool)
    border[:, n // 2 - 1:n // 2 + 1] = True
    border[-7:-5, :] = True
    delta = np.where(border, delta + 40.0, delta)
    ok = np.ones((n, n), bool)
    ok[2, 3] = False
    fit, terr = fit_eq15(delta, cm, dem, slope, south, ok)
    assert fit.beta_elevation == pytest.approx(0.006, abs=1e-10)
    assert fit.beta_slope == pytest.approx(0.04, abs=1e-10)
    assert fit.beta_aspect == pytest.approx(0.9, abs=1e-10)
    assert fit.intercepts["vegetation"] == pytest.approx(1.5, abs=1e-8)
    assert fit.intercepts["land"] == pytest.approx(-0.7, abs=1e-8)
    assert terr[2, 3] == 0.0
    np.testing.assert_allclose(terr[ok], (0.006 * dem + 0.04 * slope + 0.9 * south)[ok], atol=1e-8)
