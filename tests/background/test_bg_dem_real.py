"""The real SRTM tile crop (geographic degrees, sea at 0 m, voids inside land) onto a UTM
scene grid: resampling vs an independent bilinear, slope/aspect vs an independent Horn 3x3,
voids masked or filled, bad DEM files."""

from pathlib import Path

import numpy as np
import pytest
import rasterio
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform
from scipy.ndimage import correlate, map_coordinates, maximum_filter, minimum_filter

from imaging.background.landsat import SceneGrid, north_up_transform
from imaging.background.terrain import load_dem, slope_aspect
from shipthermal.errors import InputError

SRTM = Path(__file__).resolve().parents[1] / "data" / "dem" / "srtm_N49W124_crop.tif"


def _scene(lon=-123.29, lat=49.585, size=300, res=30.0, epsg=32610):
    (x,), (y,) = warp_transform("EPSG:4326", CRS.from_epsg(epsg), [lon], [lat])
    half = size * res / 2
    return SceneGrid(north_up_transform(x - half, y + half, res, res), CRS.from_epsg(epsg), (size, size))


GRID = _scene()


def _source():
    with rasterio.open(SRTM) as src:
        z = src.read(1).astype(float)
        z[z == src.nodata] = np.nan
        return z, src.transform


def test_reprojection_matches_an_independent_bilinear_sample():
    # Pixel centres of the UTM grid -> lon/lat (PROJ, exact) -> fractional source pixel ->
    # bilinear by scipy. GDAL's warper places a destination pixel up to 0.02 source pixels off
    # the exact position here (it interpolates the transform along each scan line even with
    # tolerance=0: measured with a ramp source, zero at the line ends, 0.020 px mid-line), so
    # the two agree to that shift times the local relief of the 3x3 source neighbourhood
    # (bound 0.025 px); where the neighbourhood is flat (sea) they agree exactly.
    dem = load_dem(SRTM, GRID)
    z, t = _source()
    r, c = np.mgrid[0:300:7, 0:300:7]
    xs = GRID.transform.c + (c + 0.5) * GRID.transform.a
    ys = GRID.transform.f + (r + 0.5) * GRID.transform.e
    lon, lat = warp_transform(GRID.crs, "EPSG:4326", xs.ravel(), ys.ravel())
    col = (np.asarray(lon) - t.c) / t.a - 0.5
    row = (np.asarray(lat) - t.f) / t.e - 0.5
    zf = np.nan_to_num(z, nan=-1e9)
    ref = map_coordinates(zf, [row, col], order=1)
    relief = maximum_filter(zf, 4) - minimum_filter(zf, 4)   # 4x4 window spans any 2x2 stencil +- 1 px
    local = map_coordinates(relief, [np.floor(row) + 0.5, np.floor(col) + 0.5], order=0)
    ok = (ref > -1e3) & (local < 1e8)             # no void near the bilinear stencil
    got = dem.elevation[r, c].ravel()
    assert ok.sum() > 1500 and np.ptp(ref[ok]) > 500          # real relief: sea to >500 m
    err = np.abs(got[ok] - ref[ok])
    assert np.all(err <= 0.025 * local[ok] + 1e-6), float((err / (local[ok] + 1e-9)).max())
    flat = local[ok] == 0
    assert flat.sum() > 100 and err[flat].max() < 1e-9
    assert dem.crs == "EPSG:4326" and dem.voids_source > 0


def test_slope_aspect_match_an_independent_horn_3x3():
    # Independent: ESRI's published Horn formulas (rate_x, rate_y, aspect conversion), with
    # scipy.ndimage.correlate kernels, on the interior of the real resampled DEM.
    dem = load_dem(SRTM, GRID, fill_voids=True).elevation
    assert np.isfinite(dem).all()
    slope, aspect = slope_aspect(dem, 30.0)
    kx = np.array([[-1, 0, 1], [-2, 0, 2], [-1, 0, 1]]) / (8 * 30.0)
    ky = np.array([[-1, -2, -1], [0, 0, 0], [1, 2, 1]]) / (8 * 30.0)
    rate_x = correlate(dem, kx)                   # dz/dx towards east (columns)
    rate_y = correlate(dem, ky)                   # dz/d(row), i.e. towards south
    ref_slope = np.degrees(np.arctan(np.hypot(rate_x, rate_y)))
    a = np.degrees(np.arctan2(rate_y, -rate_x))
    ref_aspect = np.where(a < 0, 90.0 - a, np.where(a > 90.0, 450.0 - a, 90.0 - a)) % 360.0
    inner = (slice(1, -1), slice(1, -1))
    np.testing.assert_allclose(slope[inner], ref_slope[inner], atol=1e-9)
    steep = (ref_slope[inner] > 1.0)
    d = (aspect[inner][steep] - ref_aspect[inner][steep] + 180.0) % 360.0 - 180.0
    assert steep.sum() > 30000 and np.abs(d).max() < 1e-7
    assert 20.0 < np.percentile(slope, 90) < 60.0            # coastal mountains: steep


def test_voids_masked_or_filled_with_counts():
    kept = load_dem(SRTM, GRID)
    filled = load_dem(SRTM, GRID, fill_voids=True)
    holes = np.isnan(kept.elevation)
    assert holes.sum() > 100 and not np.isnan(filled.elevation).any()
    assert filled.filled_source == filled.voids_source == kept.voids_source
    assert "voids kept" in kept.notes[-1] and "voids filled" in filled.notes[-1]
    # a fill interpolates from the void's rim: within the range of the terrain around it
    z = filled.elevation
    assert np.nanmin(kept.elevation) <= z[holes].min() and z[holes].max() <= np.nanmax(kept.elevation)
    # away from the holes (beyond the bilinear reach of a void source pixel, ~3 scene pixels)
    # the fill changes nothing
    from scipy.ndimage import binary_dilation

    far = ~binary_dilation(holes, iterations=6)
    assert far.sum() > 50000
    np.testing.assert_allclose(z[far], kept.elevation[far], atol=1e-9)


def test_dem_without_overlap_and_truncated_file(tmp_path):
    with pytest.raises(InputError, match=r"dem_path\.extent.*does not overlap the scene"):
        load_dem(SRTM, _scene(lon=121.65, lat=38.93, epsg=32651))
    cut = tmp_path / "cut.tif"
    cut.write_bytes(SRTM.read_bytes()[:30000])
    with pytest.raises(InputError, match=r"dem_path = .*cut\.tif.*must be a readable GeoTIFF"):
        load_dem(cut, GRID)


def test_real_dem_through_the_background_chain(tmp_path):
    # The synthetic port's Landsat/met/ROI files written at the SRTM crop's location, with the
    # real DEM: voids over land are refused by default, masked or filled on request (counted).
    from imaging.background import build_background_from_files
    from imaging.background.synthetic import write_synthetic_port

    port = write_synthetic_port(tmp_path, "summer", seed=5, size_px=120, lat=49.585, lon=-123.29)
    args = (port.mtl_txt, SRTM, port.met, port.roi)
    kw = dict(season="summer", utc_offset_hours=-8.0)
    with pytest.raises(InputError, match=r"land pixels without elevation.*dem_nodata='fill'"):
        build_background_from_files(*args, **kw)
    masked = build_background_from_files(*args, dem_nodata="mask", **kw)
    filled = build_background_from_files(*args, dem_nodata="fill", **kw)
    assert masked.dem_masked_pixels > 50 and filled.dem_masked_pixels == 0
    assert any("voids filled" in n for n in filled.summary()["input_notes"])
    assert np.isfinite(filled.temperature[:, filled.class_map > 0]).all()
    assert np.nanmax(filled.elevation) > 500                  # the real relief arrived
