"""Met grids as users download them: CF NetCDF in any common layout, GRIB (real ERA5 file),
units, the day window, clipping to the scene, SST / water vapour, bad files."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform

from imaging.background.kriging import krige_dual, krige_hourly, krige_points
from imaging.background.landsat import SceneGrid, north_up_transform
from imaging.background.met import clip_to_scene, met_for_scene, read_met_grid
from shipthermal.errors import InputError

DATA = Path(__file__).resolve().parents[1] / "data" / "met"
ERA5 = DATA / "era5_t2m_2019-03-01_02_uk.grib"


def _scene(lon, lat, epsg, size=300, res=30.0):
    (x,), (y,) = warp_transform("EPSG:4326", CRS.from_epsg(epsg), [lon], [lat])
    half = size * res / 2
    return SceneGrid(north_up_transform(x - half, y + half, res, res), CRS.from_epsg(epsg), (size, size))


MERSEY = _scene(-3.0, 53.42, 32630)           # Liverpool docks, UTM 30N, 9 km square


# ---------------------------------------------------------------------------------------------
# real ERA5 GRIB
# ---------------------------------------------------------------------------------------------
def test_real_era5_grib_values_match_eccodes_decoding():
    # Independent decoding of the same messages with ecCodes itself (no cfgrib, no xarray).
    eccodes = pytest.importorskip("eccodes")
    met = read_met_grid(ERA5, n_hours=None)
    assert met.variable == "t2m" and met.units_read == "K" and met.temperature.shape == (48, 33, 49)
    assert met.times_utc[0] == np.datetime64("2019-03-01T00:00") and met.times_utc[-1] == np.datetime64(
        "2019-03-02T23:00")
    with open(ERA5, "rb") as f:
        for k in range(48):
            h = eccodes.codes_grib_new_from_file(f)
            if k in (0, 13, 47):
                vals = eccodes.codes_get_values(h).reshape(33, 49)
                lat0 = eccodes.codes_get(h, "latitudeOfFirstGridPointInDegrees")
                lon0 = eccodes.codes_get(h, "longitudeOfFirstGridPointInDegrees")
                assert (met.y[0, 0], met.x[0, 0]) == (lat0, lon0)
                # GRIB packing is lossless to the float32 cfgrib returns: ~1e-5 K
                np.testing.assert_allclose(met.temperature[k], vals, atol=1e-4)
            eccodes.codes_release(h)


def test_real_era5_grib_clipped_to_a_port_scene_and_the_day_of_the_overpass():
    met = read_met_grid(ERA5, n_hours=None)
    overpass = np.datetime64("2019-03-02T11:10")
    sub = met_for_scene(met, MERSEY, overpass, margin_cells=2, utc_offset_hours=0.0)
    # the UTC day of the overpass, 00..23 h
    assert sub.times_utc[0] == np.datetime64("2019-03-02T00:00") and sub.times_utc.size == 24
    # the 9 km scene spans 1-2 cells of 0.25 deg; +2 cells each side: 5-6 cells per axis
    assert 5 <= sub.x.shape[0] <= 6 and 5 <= sub.x.shape[1] <= 6
    assert np.all(np.abs(sub.x + 3.0) <= 0.25 * 2.5 + 0.07) and np.all(np.abs(sub.y - 53.42) <= 0.25 * 2.5 + 0.07)
    np.testing.assert_array_equal(sub.temperature[0], met.temperature[24][np.isin(met.y[:, 0], sub.y[:, 0])][
        :, np.isin(met.x[0], sub.x[0])])
    notes = " | ".join(sub.notes)
    assert f"{sub.n_cells} of 1617 cells" in notes
    assert "no SST in the met file" in notes and "US Standard" in notes
    # kriged onto the scene: within the range of the data of that hour
    x, y = sub.points_in(MERSEY.crs)
    fields, fits = krige_hourly(x, y, sub.temperature.reshape(24, -1), MERSEY, coarsen=10)
    assert fields.shape == (24, 300, 300) and len(fits) == 24
    for k in (0, 12):
        assert sub.temperature[k].min() - 0.5 < fields[k].min() <= fields[k].max() < sub.temperature[k].max() + 0.5


def test_real_era5_kriging_agrees_with_pykrige_and_gstools():
    # The real 0.25 deg field around the Mersey (clipped + 4 cells: ~100 points), two hours:
    # our dual-form kriging vs pykrige's full per-point solution with its own fit, and vs
    # gstools' OK with the same fitted variogram (gstools len_scale = pykrige range for the
    # spherical model). Measured differences ~1e-10 K (pykrige) and ~1e-9 K (gstools) at the
    # coarse nodes; the float32 output grid allows 1e-4 K.
    gs = pytest.importorskip("gstools")
    met = read_met_grid(ERA5, n_hours=None)
    sub = met_for_scene(met, MERSEY, np.datetime64("2019-03-01T11:00"), margin_cells=4)
    x, y = sub.points_in(MERSEY.crs)
    vals = sub.temperature.reshape(24, -1)[[3, 13]]
    fast, fits = krige_hourly(x, y, vals, MERSEY, coarsen=1)
    rng = np.random.default_rng(0)
    r, c = rng.integers(0, 300, 500), rng.integers(0, 300, 500)
    xq = MERSEY.transform.c + (c + 0.5) * 30.0
    yq = MERSEY.transform.f - (r + 0.5) * 30.0
    for k, fit in enumerate(fits):
        ref, fit_ref = krige_points(x, y, vals[k], xq, yq, "spherical", statistics=False)
        assert fit_ref.parameters == fit.parameters
        np.testing.assert_allclose(fast[k][r, c], ref, atol=1e-4)
        p = fit.parameters
        cov = gs.Spherical(dim=2, var=p["psill"], len_scale=p["range"], nugget=p["nugget"])
        g, _ = gs.krige.Ordinary(cov, [x, y], vals[k], exact=True)([xq, yq])
        np.testing.assert_allclose(fast[k][r, c], g, atol=1e-4)
        assert np.ptp(ref) > 0.05                # a real gradient across the 9 km scene


def test_grib_with_sst_and_water_vapour_fields(tmp_path):
    # An ERA5-style download with 2t, sst (missing over land through the GRIB bitmap) and tcwv
    # (kg m-2, on another level type): the real 2t messages plus derived sst/tcwv messages.
    eccodes = pytest.importorskip("eccodes")
    lon = np.tile(np.arange(49) * 0.25 - 10.0, 33)
    with open(ERA5, "rb") as f, open(tmp_path / "mixed.grib", "wb") as out:
        for _ in range(24):
            h = eccodes.codes_grib_new_from_file(f)
            out.write(eccodes.codes_get_message(h))
            sst = eccodes.codes_clone(h)
            eccodes.codes_set(sst, "paramId", 34)
            eccodes.codes_set(sst, "bitmapPresent", 1)
            eccodes.codes_set(sst, "missingValue", 9999)
            eccodes.codes_set_values(sst, np.where(lon < -5.0, eccodes.codes_get_values(h) + 1.0, 9999.0))
            out.write(eccodes.codes_get_message(sst))
            wv = eccodes.codes_clone(h)
            eccodes.codes_set(wv, "paramId", 137)
            eccodes.codes_set(wv, "typeOfLevel", "heightAboveGround")
            eccodes.codes_set(wv, "level", 2)
            eccodes.codes_set_values(wv, np.full(lon.size, 12.0))
            out.write(eccodes.codes_get_message(wv))
            for m in (h, sst, wv):
                eccodes.codes_release(m)
    met = read_met_grid(tmp_path / "mixed.grib", n_hours=None)
    assert met.variable == "t2m" and met.sst_field is not None and met.tcwv_field is not None
    sub = met_for_scene(met, MERSEY, np.datetime64("2019-03-01T11:00"), margin_cells=9)
    sea = sub.x < -5.0
    assert sea.any() and (~sea).any()
    np.testing.assert_allclose(sub.sst, np.nanmean(np.where(sea, sub.temperature + 1.0, np.nan), axis=(1, 2)),
                               atol=1e-4)
    np.testing.assert_allclose(sub.tcwv, 1.2)          # 12 kg m-2


def test_grib_without_a_time_axis(tmp_path):
    with open(ERA5, "rb") as f:
        import eccodes

        h = eccodes.codes_grib_new_from_file(f)
        (tmp_path / "one.grib").write_bytes(eccodes.codes_get_message(h))
        eccodes.codes_release(h)
    with pytest.raises(InputError, match=r"met\[t2m\]\.time = 'no time axis \(one time step\)'.*24 hourly fields"):
        read_met_grid(tmp_path / "one.grib", n_hours=None)


def test_truncated_grib(tmp_path):
    data = ERA5.read_bytes()
    (tmp_path / "cut.grib").write_bytes(data[: len(data) // 2 + 777])
    with pytest.raises(InputError, match=r"truncated or damaged GRIB file \(message 25 unreadable\).*Download it again"):
        read_met_grid(tmp_path / "cut.grib", n_hours=None)


def test_grid_that_misses_the_scene():
    met = read_met_grid(ERA5, n_hours=None)
    dalian = _scene(121.65, 38.93, 32651)
    with pytest.raises(InputError, match=r"met\.extent.*misses the scene entirely"):
        met_for_scene(met, dalian, np.datetime64("2019-03-01T03:00"))


# ---------------------------------------------------------------------------------------------
# NetCDF layouts
# ---------------------------------------------------------------------------------------------
def _field(times, lat, lon):
    t = np.arange(len(times))[:, None, None]
    return 280.0 + 0.1 * t + 0.5 * np.asarray(lat)[None, :, None] - 0.2 * np.asarray(lon)[None, None, :] % 7


def test_era5_netcdf_layout_valid_time_latitude_0_360_and_gridded_sst_tcwv(tmp_path):
    # The layout of the CDS NetCDF download: valid_time, latitude descending, longitude 0..360,
    # sst NaN over land, tcwv in kg m-2.
    times = pd.date_range("2019-03-02", periods=30, freq="h")
    lat = np.arange(54.5, 52.4, -0.25)
    lon = np.arange(355.0, 359.1, 0.25)
    t2m = _field(times, lat, lon)
    sst = np.where(lon[None, None, :] < 357.0, 282.0 + 0.01 * np.arange(30)[:, None, None], np.nan) * np.ones_like(t2m)
    ds = xr.Dataset({"t2m": (("valid_time", "latitude", "longitude"), t2m, {"units": "K"}),
                     "sst": (("valid_time", "latitude", "longitude"), sst, {"units": "K"}),
                     "tcwv": (("valid_time", "latitude", "longitude"), np.full_like(t2m, 14.0),
                              {"units": "kg m**-2"})},
                    coords={"valid_time": times, "latitude": lat, "longitude": lon})
    ds.to_netcdf(tmp_path / "era5.nc", engine="h5netcdf")
    met = read_met_grid(tmp_path / "era5.nc", n_hours=None)
    assert met.variable == "t2m" and met.x.min() == -5.0 and met.x.max() == -1.0
    sub = met_for_scene(met, MERSEY, np.datetime64("2019-03-02T11:00"), margin_cells=3)
    sea = sub.x[0] < -3.0
    np.testing.assert_allclose(sub.sst, 282.0 + 0.01 * np.arange(24))    # mean of the sea cells
    assert sea.any() and np.allclose(sub.tcwv, 1.4)                      # 14 kg m-2 = 1.4 g cm-2
    notes = " | ".join(sub.notes)
    assert "SST from the gridded field" in notes and "water vapour from the gridded field" in notes


def test_projected_xy_grid_with_a_cf_grid_mapping(tmp_path):
    # A national grid in metres (UTM 30N, km coordinates) read through its grid_mapping.
    crs = CRS.from_epsg(32630)
    x0, y0 = MERSEY.transform.c, MERSEY.transform.f
    xk = (x0 + np.arange(-20e3, 30e3, 5e3)) / 1000.0
    yk = (y0 + np.arange(-30e3, 20e3, 5e3)) / 1000.0
    times = pd.date_range("2020-09-27", periods=24, freq="h")
    xx, yy = np.meshgrid(xk, yk)
    temp = 10.0 + 0.01 * (xx - xk.mean()) + 0.2 * np.arange(24)[:, None, None]
    ds = xr.Dataset({"tas": (("time", "y", "x"), temp, {"units": "degC", "grid_mapping": "crs"}),
                     "crs": ((), 0, {"crs_wkt": crs.to_wkt()})},
                    coords={"time": times, "x": ("x", xk, {"units": "km"}), "y": ("y", yk, {"units": "km"})})
    ds.to_netcdf(tmp_path / "ukv.nc", engine="h5netcdf")
    met = read_met_grid(tmp_path / "ukv.nc")
    assert not met.geographic and met.units_read == "degC"
    np.testing.assert_allclose(met.temperature, temp + 273.15)
    xs, ys = met.points_in(MERSEY.crs)
    np.testing.assert_allclose(xs, xx.ravel() * 1000.0, atol=1e-6)
    sub = clip_to_scene(met, MERSEY, margin_cells=1)
    # scene 9 km square starting at a grid node: 3 cells of 5 km inside (+1 each side)
    assert sub.x.shape == (4, 4) or sub.x.shape == (5, 5)
    # kriging a field linear in x reproduces it in the scene (OK is unbiased, data exact)
    fields, _ = krige_hourly(*sub.points_in(MERSEY.crs), sub.temperature.reshape(24, -1), MERSEY, coarsen=10)
    assert np.ptp(fields[0]) > 0.05


def test_projected_grid_without_crs_and_unknown_variable(tmp_path):
    times = pd.date_range("2020-09-27", periods=24, freq="h")
    ds = xr.Dataset({"tas": (("time", "y", "x"), np.full((24, 3, 3), 285.0), {"units": "K"})},
                    coords={"time": times, "x": [0.0, 1e3, 2e3], "y": [0.0, 1e3, 2e3]})
    ds.to_netcdf(tmp_path / "nocrs.nc", engine="h5netcdf")
    with pytest.raises(InputError, match=r"grid_mapping.*must name its CRS"):
        read_met_grid(tmp_path / "nocrs.nc")
    ds.rename({"tas": "rain"}).to_netcdf(tmp_path / "rain.nc", engine="h5netcdf")
    with pytest.raises(InputError, match=r"met\[temperature\] = 'missing'.*Variables present: \['rain'\].*met_variable"):
        read_met_grid(tmp_path / "rain.nc")


def test_gdal_converted_grib_is_recognised(tmp_path):
    # gdal_translate GRIB -> NetCDF: Band1..BandN on (lat, lon), no time axis, units '[C]'
    ds = xr.Dataset({f"Band{i}": (("lat", "lon"), np.full((3, 3), 280.0), {"units": "[C]"}) for i in range(1, 30)},
                    coords={"lat": [50.0, 50.25, 50.5], "lon": [0.0, 0.25, 0.5]})
    ds.to_netcdf(tmp_path / "gdal.nc", engine="h5netcdf")
    with pytest.raises(InputError, match=r"'\.\.\. 21 more'\].*GDAL conversion.*original GRIB"):
        read_met_grid(tmp_path / "gdal.nc")


def test_two_dimensional_lat_lon(tmp_path):
    # curvilinear grids (WRF-like): 2-D latitude/longitude arrays
    times = pd.date_range("2020-09-27", periods=24, freq="h")
    j, i = np.mgrid[0:8, 0:9]
    lat = 53.0 + 0.1 * j + 0.01 * i
    lon = -3.5 + 0.12 * i
    ds = xr.Dataset({"T2": (("Time", "south_north", "west_east"), 280 + np.zeros((24, 8, 9)) + lat[None],
                            {"units": "K"})},
                    coords={"Time": times, "XLAT": (("south_north", "west_east"), lat),
                            "XLONG": (("south_north", "west_east"), lon)})
    ds.to_netcdf(tmp_path / "wrf.nc", engine="h5netcdf")
    met = read_met_grid(tmp_path / "wrf.nc")
    np.testing.assert_allclose(met.y, lat)
    np.testing.assert_allclose(met.temperature[5], 280 + lat)


# ---------------------------------------------------------------------------------------------
# fast kriging vs pykrige's full solution
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("model, params", [
    ("spherical", None), ("exponential", None), ("linear", None), ("power", None),
    ("gaussian", {"psill": 1.0, "range": 20e3, "nugget": 0.05})])   # gaussian without nugget: singular
def test_dual_kriging_equals_pykrige_full_solution(model, params):
    # Same variogram, same OK system: the dual form differs from pykrige's per-point solve by
    # round-off only (measured 1e-11..1e-10 K on 300 points); data points are reproduced.
    rng = np.random.default_rng(3)
    x, y = rng.uniform(0, 60e3, 300), rng.uniform(0, 60e3, 300)
    z = 285 + 2 * np.sin(x / 1.5e4) + np.cos(y / 9e3) + 0.02 * x / 1e3 + 0.05 * rng.standard_normal(300)
    xq, yq = np.r_[rng.uniform(0, 60e3, 3000), x[:5]], np.r_[rng.uniform(0, 60e3, 3000), y[:5]]
    ref, fit = krige_points(x, y, z, xq, yq, model, params, statistics=False)
    ours = krige_dual(x, y, z[None], [fit], xq, yq)[0]
    np.testing.assert_allclose(ours, ref, atol=1e-8)
    np.testing.assert_allclose(ours[-5:], z[:5], atol=1e-8)
    assert np.ptp(ours) > 1.0


def test_krige_hourly_dual_equals_pykrige_method_with_missing_cells():
    rng = np.random.default_rng(5)
    x, y = rng.uniform(0, 40e3, 90), rng.uniform(0, 40e3, 90)
    vals = np.stack([290 + np.sin(x / 8e3) + h * 0.3 + 0.1 * np.cos(y / 5e3) for h in range(3)])
    vals[1, :20] = np.nan                     # sea cells of a land product in one hour
    grid = SceneGrid(north_up_transform(5e3, 35e3, 100.0, 100.0), CRS.from_epsg(32651), (200, 210))
    fast, f1 = krige_hourly(x, y, vals, grid, coarsen=4)
    ref, f2 = krige_hourly(x, y, vals, grid, coarsen=4, method="pykrige")
    assert [f.parameters for f in f1] == [f.parameters for f in f2]
    np.testing.assert_allclose(fast, ref, atol=1e-4)         # float32 output: ~3e-5 K at 290 K
    assert all(np.isnan(f.q1) for f in f1)                   # statistics off by default
    _, f3 = krige_hourly(x, y, vals[:1], grid, coarsen=20, statistics=True)
    assert np.isfinite(f3[0].q1) and np.isfinite(f3[0].q2)


def test_variogram_range_stuck_at_the_largest_lag_is_flagged():
    # A field that keeps rising across the window (a trend larger than the data) has no sill
    # within it: pykrige's fitted range ends on its upper bound, the largest lag.
    rng = np.random.default_rng(0)
    x, y = rng.uniform(0, 50e3, 200), rng.uniform(0, 50e3, 200)
    _, trend = krige_points(x, y, 280 + 1e-4 * x + 0.01 * rng.standard_normal(200), [0.0], [0.0],
                            statistics=False)
    assert "range=max lag" in trend.at_bound
    assert trend.parameters["range"] == pytest.approx(trend.max_lag, rel=1e-4)
    _, wavy = krige_points(x, y, 280 + np.sin(x / 3e3) * np.cos(y / 3e3), [0.0], [0.0], statistics=False)
    assert wavy.at_bound == () and wavy.parameters["range"] < 0.8 * wavy.max_lag


# ---------------------------------------------------------------------------------------------
# `shipthermal check` opens the met grid and the DEM
# ---------------------------------------------------------------------------------------------
def test_scenario_validate_opens_met_and_dem_and_lists_every_problem(tmp_path, capsys):
    from shipthermal.app.cli import main

    dem = Path(__file__).resolve().parents[1] / "data" / "dem" / "srtm_N49W124_crop.tif"
    for name in ("scene_MTL.txt", "roi.tif"):
        (tmp_path / name).write_text("only checked for existence here")
    (tmp_path / "cut.grib").write_bytes(ERA5.read_bytes()[:50_000])
    (tmp_path / "dem.tif").write_bytes(dem.read_bytes()[:20_000])

    def scenario(name, met, dem_path):
        p = tmp_path / name
        p.write_text(f'[background]\nsource = "files"\nmtl = "scene_MTL.txt"\nroi = "roi.tif"\n'
                     f'met = "{met}"\ndem = "{dem_path}"\n')
        return str(p)

    # the stand-in MTL is reported (it is opened too); the real met grid and DEM pass
    good = scenario("good.toml", ERA5, dem)
    assert main(["check", good]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "background.mtl" in err[0], err
    bad = scenario("bad.toml", tmp_path / "cut.grib", tmp_path / "dem.tif")
    assert main(["check", bad]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 3, err
    assert "background.mtl" in err[0]
    assert "background.met" in err[1] and "truncated or damaged GRIB" in err[1]
    assert "background.dem" in err[2] and "must be a readable GeoTIFF" in err[2]
