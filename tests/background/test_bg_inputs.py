"""Bad inputs of the background chain that the other files leave out: each gets a clear error
naming the field, or explicit masking."""


import numpy as np
import pandas as pd
import pytest
import rasterio
import xarray as xr

from imaging.background import build_background_from_files
from imaging.background.classify import read_roi
from imaging.background.kriging import krige_points
from imaging.background.landsat import SceneGrid, north_up_transform, read_mtl
from imaging.background.met import read_met_grid
from imaging.background.synthetic import write_synthetic_port
from imaging.background.terrain import read_dem
from shipthermal.errors import InputError


@pytest.fixture(scope="module")
def port(tmp_path_factory):
    return write_synthetic_port(tmp_path_factory.mktemp("in"), "summer", seed=5, size_px=90)


def _hourly(path, times, var="temperature", dims=("time", "lat", "lon")):
    lat, lon = np.arange(38.6, 39.3, 0.0625), np.arange(121.3, 122.0, 0.0625)
    shape = {"time": len(times), "lat": lat.size, "lon": lon.size}
    data = 290.0 + np.zeros([shape[d] for d in dims])
    xr.Dataset({var: (dims, data, {"units": "K"})},
               coords={"time": times, "lat": lat, "lon": lon}).to_netcdf(path, engine="h5netcdf")
    return path


def test_met_grid_duplicated_hour(tmp_path):
    times = pd.date_range("2023-07-27 16:00", periods=24, freq="h")
    times = times[:23].append(times[22:23])            # hour 22 twice, last hour missing
    with pytest.raises(InputError, match=r"met\.time.*24 consecutive hourly steps.*Missing hours: 2023-07-28T15:00"):
        read_met_grid(_hourly(tmp_path / "dup.nc", times))


def test_met_grid_missing_variable_and_wrong_dims(tmp_path):
    times = pd.date_range("2023-07-27 16:00", periods=24, freq="h")
    with pytest.raises(InputError, match=r"met\[temperature\] = 'missing'.*Variables present: \['tair'\]"):
        read_met_grid(_hourly(tmp_path / "tair.nc", times, var="tair"))
    with pytest.raises(InputError, match=r"met\[temperature\]\.dims.*must be \(time, y, x\)"):
        read_met_grid(_hourly(tmp_path / "dims.nc", times, dims=("time", "lat")))
    (tmp_path / "not.nc").write_text("no netcdf here")
    with pytest.raises(InputError, match="met_path.*readable NetCDF"):
        read_met_grid(tmp_path / "not.nc")


def test_mtl_invalid_json_and_missing_file(port, tmp_path):
    bad = tmp_path / "Z_MTL.json"
    bad.write_text(open(port.mtl_json).read()[:-10])
    with pytest.raises(InputError, match="mtl_path.*valid JSON"):
        read_mtl(bad)
    with pytest.raises(InputError, match="mtl_path.*existing MTL file"):
        read_mtl(tmp_path / "absent_MTL.txt")


def test_mtl_bad_date_is_named(port, tmp_path):
    text = open(port.mtl_txt).read()
    text = text.replace("SCENE_CENTER_TIME = ", "SCENE_CENTER_TIME = 25:")
    (tmp_path / "T_MTL.txt").write_text(text)
    with pytest.raises(InputError, match="SCENE_CENTER_TIME.*HH:MM:SS"):
        read_mtl(tmp_path / "T_MTL.txt")


def test_roi_raster_on_another_grid(port, tmp_path):
    with rasterio.open(port.roi) as src:
        profile, data, grid = src.profile, src.read(1), SceneGrid(src.transform, src.crs, (src.height, src.width))
    t = profile["transform"]
    profile.update(transform=north_up_transform(t.c + 30.0, t.f, 30.0))   # shifted one pixel east
    with rasterio.open(tmp_path / "roi_shifted.tif", "w", **profile) as dst:
        dst.write(data, 1)
    with pytest.raises(InputError, match="roi_path.*must be on the scene grid.*Rasterise"):
        read_roi(tmp_path / "roi_shifted.tif", grid)
    with pytest.raises(InputError, match="roi_path.*existing GeoTIFF or vector file"):
        read_roi(tmp_path / "absent.tif", grid)


def test_dem_nan_without_nodata_tag_is_masked_then_an_error(port, tmp_path):
    # A float DEM whose voids are NaN (no nodata value in the file, as some exports do) must
    # come out NaN on the scene grid, never interpolated over.
    with rasterio.open(port.dem) as src:
        profile, z = src.profile, src.read(1)
    z[:80, :80] = np.nan                                 # north-west corner: hills, land
    profile.update(nodata=None)
    path = tmp_path / "dem_nan.tif"
    with rasterio.open(path, "w", **profile) as dst:
        dst.write(z, 1)
    with rasterio.open(port.roi) as src:
        grid = SceneGrid(src.transform, src.crs, (src.height, src.width))
    dem = read_dem(path, grid)
    # 80 arc-seconds ~ 1.9-2.5 km of the north-west: > 1000 scene pixels, all NaN
    assert np.isnan(dem).sum() > 1000 and np.isnan(dem[0, 0])
    assert np.isfinite(dem[-1, -1])
    with pytest.raises(InputError, match=r"dem = .*land pixels without elevation"):
        build_background_from_files(port.mtl_txt, path, port.met, port.roi)


def test_unknown_options_are_named(port):
    with pytest.raises(InputError, match="emissivity_model.*tirs_b10"):
        build_background_from_files(port.mtl_txt, port.dem, port.met, port.roi, emissivity_model="modis")
    with pytest.raises(InputError, match="dem_nodata"):
        build_background_from_files(port.mtl_txt, port.dem, port.met, port.roi, dem_nodata="interpolate")
    with pytest.raises(InputError, match="variogram_model.*spherical"):
        krige_points([0.0, 1.0, 2.0], [0.0, 1.0, 0.0], [1.0, 2.0, 3.0], [0.5], [0.5], "cubic")
    with pytest.raises(InputError, match="utc_offset_hours"):
        build_background_from_files(port.mtl_txt, port.dem, port.met, port.roi, utc_offset_hours=20)


def test_tm6_emissivity_option_runs_and_is_reported(port):
    # The TM band-6 coefficient set gives higher bare-soil emissivity (0.979 - 0.035 rho vs
    # 0.973 - 0.047 rho): the same radiances then give a colder LST over land, by
    # dT ~ (lambda T^2 / c2) d(eps) = 7.6e-4 K-1 * 300^2 K^2 * d(eps) ~ 68 K * d(eps),
    # i.e. 0.3-0.5 K for d(eps) = 0.005-0.008
    # (Planck at 11 um; measured mean 0.39 K, range 0.27-0.42 K on the soil pixels).
    a = build_background_from_files(port.mtl_txt, port.dem, port.met, port.roi)
    b = build_background_from_files(port.mtl_txt, port.dem, port.met, port.roi, emissivity_model="tm6_sobrino2004")
    assert a.summary()["emissivity_model"] == "tirs_b10" and b.emissivity_model == "tm6_sobrino2004"
    soil = (a.ndvi > 0) & (a.ndvi < 0.2)
    d = (b.lst - a.lst)[soil]
    assert soil.sum() > 100 and np.all(d < 0) and 0.2 < -d.mean() < 0.8
    water = a.class_map == 1
    np.testing.assert_array_equal(a.lst[water & (a.ndvi < 0)], b.lst[water & (a.ndvi < 0)])


def test_pipeline_on_a_cropped_scene(port):
    # The full-scene ROI GeoTIFF is windowed onto the cropped grid; per-pixel products (LST,
    # emissivity) are those of the full run on the same pixels, exactly.
    full = build_background_from_files(port.mtl_txt, port.dem, port.met, port.roi)
    t = full.grid.transform
    bounds = (t.c + 150, t.f - 80 * 30, t.c + 85 * 30, t.f - 300)      # cols 5..85, rows 10..80
    crop = build_background_from_files(port.mtl_txt, port.dem, port.met, port.roi, bounds=bounds)
    assert crop.grid.shape == (70, 80)
    np.testing.assert_array_equal(crop.lst, full.lst[10:80, 5:85])
    np.testing.assert_array_equal(crop.emissivity, full.emissivity[10:80, 5:85])
    # DEM reprojected onto the cropped grid: same pixel centres, but GDAL's warp (wider
    # bilinear kernel when downsampling the 1" DEM, chunked per destination) differs by up to
    # 0.033 m (measured) from the full-grid warp: 0.05 m, far below 30 m DEM accuracy (2-4 m).
    np.testing.assert_allclose(crop.elevation, full.elevation[10:80, 5:85], atol=0.05)
    assert crop.temperature.shape == (24, 70, 80) and np.isfinite(crop.temperature[:, crop.class_map > 0]).all()
