"""The products in the conventions their readers expect, on the tiny run of the CLI tests:

* NetCDF: CF (``cfchecks`` with no error and no warning), a datetime ``time`` that xarray
  decodes to the right UTC instants, the CRS in a grid mapping GDAL reads;
* GeoTIFF: band units and times in the band metadata;
* VTKHDF: a time axis, units, part ids and the outer-surface temperature of the images;
* CSV: a unit in every numeric column's header, every column in docs/DATA.md.
"""

import datetime
import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import rasterio

from shipthermal.units import split_header, strip_units

CF_TABLES = Path(__file__).resolve().parents[1] / "data" / "cf"
DATA_DOC = Path(__file__).resolve().parents[2] / "docs" / "DATA.md"


def _cfchecker_usable() -> bool:
    """cfchecker installed and its udunits2 library loadable (cfunits loads it on import)."""
    if importlib.util.find_spec("cfchecker") is None:
        return False
    res = subprocess.run([sys.executable, "-c", "import cfchecker.cfchecks"],
                         capture_output=True, timeout=120)
    return res.returncode == 0


HAS_CFCHECKER = _cfchecker_usable()


def _zone(run):
    import tomllib

    sc = tomllib.loads((run / "scenario.toml").read_text())
    return sc["time"]["date"], sc["location"]["time_zone"]


@pytest.mark.skipif(not HAS_CFCHECKER, reason="cfchecker not usable (the test extra installs "
                    "it; it needs the udunits2 library: apt-get install libudunits2-dev, which "
                    "./run installs where it can)")
def test_netcdf_passes_cfchecks_without_errors_or_warnings(imaged_run):
    files = sorted((imaged_run / "imaging").glob("images_*.nc"))
    assert files
    for nc in files:
        res = subprocess.run(
            [sys.executable, "-c", "from cfchecker.cfchecks import main; main()",
             "-s", str(CF_TABLES / "cf-standard-name-table-excerpt.xml"),
             "-a", str(CF_TABLES / "cf-area-type-table-excerpt.xml"),
             "-r", str(CF_TABLES / "cf-region-table-excerpt.xml"), str(nc)],
            capture_output=True, text=True, timeout=300)
        out = res.stdout + res.stderr
        assert "ERRORS detected: 0" in out and "WARNINGS given: 0" in out, out[-3000:]
        assert "Checking variable: radiance" in out          # it really checked the file


def test_netcdf_time_decodes_to_utc_and_keeps_the_local_hours(imaged_run):
    import xarray as xr

    date, tz = _zone(imaged_run)
    from zoneinfo import ZoneInfo

    d = datetime.date.fromisoformat(date)
    midnight_utc = datetime.datetime(d.year, d.month, d.day, tzinfo=ZoneInfo(tz)).astimezone(
        datetime.timezone.utc).replace(tzinfo=None)
    nc = imaging_file(imaged_run, "images_summer_8-14.nc")
    with xr.open_dataset(nc, engine="h5netcdf") as ds:
        assert ds.attrs["Conventions"].startswith("CF-")
        assert np.issubdtype(ds["time"].dtype, np.datetime64)
        local_h = ds["time_local_h"].values
        expect = (np.datetime64(midnight_utc, "ns")
                  + (local_h * 3600e9).round().astype("timedelta64[ns]"))
        np.testing.assert_array_equal(ds["time"].values, expect)
        assert "UTC+8" in ds.attrs["local_time_zone"] and tz in ds.attrs["local_time_zone"]
        assert ds["radiance"].attrs["grid_mapping"] == "spatial_ref"
        assert ds["x"].attrs["standard_name"] == "projection_x_coordinate"
        assert "crs_wkt" not in ds.attrs                    # not a global attribute any more
        metrics = strip_units(pd.read_csv(imaging_file(imaged_run, "metrics_summer_8-14.csv")))
        np.testing.assert_allclose(local_h * 3600.0, metrics["time_s"], atol=1e-6)


def imaging_file(run, name):
    return run / "imaging" / name


def test_netcdf_and_geotiff_are_georeferenced_for_gdal(imaged_run):
    """GDAL (what QGIS uses) reads the NetCDF's CRS and pixel grid from its grid mapping: the
    same CRS as the background GeoTIFF, the crop's corner on that grid."""
    import xarray as xr

    nc = imaging_file(imaged_run, "images_summer_8-14.nc")
    with rasterio.open(imaging_file(imaged_run, "background/tiny/background_K.tif")) as bg:
        crs, t0 = bg.crs, bg.transform
    with xr.open_dataset(nc, engine="h5netcdf") as ds:
        r0, r1, c0, c1 = (int(v) for v in ds.attrs["crop_rows_cols"])
        n_time = ds.sizes["time"]
    with xr.open_dataset(nc, engine="h5netcdf", decode_coords="all") as ds:    # rioxarray's way
        assert rasterio.crs.CRS.from_wkt(ds["radiance"].coords["spatial_ref"].attrs["crs_wkt"]) == crs
    with rasterio.open(f"netcdf:{nc}:radiance") as src:
        assert src.crs == crs and src.crs.to_epsg() is not None
        assert src.count == n_time and src.units[0] == "W m-2 sr-1"
        assert src.transform.almost_equals(t0 @ rasterio.Affine.translation(c0, r0))
        assert (src.height, src.width) == (r1 - r0, c1 - c0)


def test_geotiff_bands_carry_units_and_times(imaged_run):
    date, tz = _zone(imaged_run)
    with rasterio.open(imaging_file(imaged_run, "typical_summer_8-14.tif")) as src:
        assert src.count >= 1 and set(src.units) == {"W m-2 sr-1"}
        assert "UTC+8" in src.tags()["local_time_zone"]
        for k in range(1, src.count + 1):
            t = src.tags(k)
            local = datetime.datetime.fromisoformat(t["time_local"])
            utc = datetime.datetime.fromisoformat(t["time_utc"].replace("Z", "+00:00"))
            assert local == utc and local.utcoffset() == datetime.timedelta(hours=8)
            assert local.date().isoformat() == date
            assert float(t["hours_after_local_midnight"]) == pytest.approx(
                local.hour + local.minute / 60.0)
            assert f"{local:%H:%M} UTC+8" in src.descriptions[k - 1]
    with rasterio.open(imaging_file(imaged_run, "background/tiny/background_K.tif")) as src:
        assert set(src.units) == {"K"} and "time_local" in src.tags(1)


def test_surface_vtkhdf_has_a_time_axis_part_ids_and_the_images_temperatures(imaged_run):
    import pyvista as pv

    from shipthermal.app.pipeline import load_history

    d = imaged_run / "thermal" / "tiny"
    hist = load_history(d / "history.npz")
    r = pv.get_reader(d / "surface.vtkhdf")
    assert r.reader.GetNumberOfSteps() == len(hist.times_s)
    for k in (0, len(hist.times_s) // 2):
        r.reader.SetStep(k)
        mesh = r.read()
        assert mesh.n_cells == hist.n_faces
        assert mesh.field_data["Time"][0] == pytest.approx(hist.times_s[k])
        np.testing.assert_allclose(mesh["temperature_K"], hist.face_temperature[k], atol=1e-3)
        np.testing.assert_array_equal(mesh["part_id"], hist.face_part)
        assert list(mesh.field_data["part_names"]) == list(hist.part_names)
    vol = pv.get_reader(d / "thermal.vtkhdf")
    assert vol.reader.GetNumberOfSteps() == len(hist.times_s)
    assert {"temperature_K", "part_id"} <= set(vol.read().array_names)


def _csv_files(run):
    return sorted(p for p in run.rglob("*.csv"))


def test_every_numeric_csv_column_has_a_unit(imaged_run):
    files = _csv_files(imaged_run)
    assert len(files) >= 8
    for f in files:
        df = pd.read_csv(f)
        for col in df.columns:
            name, unit = split_header(col)
            numeric = pd.api.types.is_numeric_dtype(df[col])
            local = name.endswith(("_local", "_times"))
            assert unit or not (numeric or local), f"{f.name}: column {col!r} has no unit"
            if local:
                assert re.fullmatch(r"UTC[+-]\d+(:\d\d)?", unit), (f.name, col)


def test_every_csv_column_is_in_the_data_dictionary(imaged_run):
    """docs/DATA.md names every column of every CSV of a run (the part columns of
    part_means.csv are the ship's parts and are described as such)."""
    doc = DATA_DOC.read_text(encoding="utf-8")
    for f in _csv_files(imaged_run):
        assert f"`{f.name}`" in doc or f"`{f.stem.split('_summer')[0]}" in doc, f.name
        if f.name == "part_means.csv":
            continue
        for col in pd.read_csv(f).columns:
            name = split_header(col)[0]
            if name.startswith("Unnamed"):
                continue
            assert f"`{name}`" in doc or name in doc, f"{f.name}: {name} not in docs/DATA.md"
