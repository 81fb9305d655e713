"""Landsat C2 L1 readers and radiometric conversions."""

import json
import os
import shutil

import numpy as np
import pytest
import rasterio
from scipy.integrate import quad

from imaging.background.landsat import (brightness_temperature_to_radiance, dn_to_radiance, dn_to_reflectance,
                                        radiance_to_brightness_temperature, read_landsat_scene, read_mtl)
from imaging.background.synthetic import LANDSAT8_B10, write_synthetic_port
from shipthermal.errors import InputError

C1 = 1.191e8      # paper eq. 2 [W um4 m-2 sr-1]
C2 = 1.4388e4     # [um K]
K1, K2 = LANDSAT8_B10["k1"], LANDSAT8_B10["k2"]


def planck(wavelength_um, temp):
    return C1 / wavelength_um ** 5 / np.expm1(C2 / (wavelength_um * temp))


def test_brightness_temperature_is_exact_planck_inversion():
    # With K1 = c1/lambda^5, K2 = c2/lambda the MTL formula is Planck's law solved for T:
    # the only error left is floating-point round-off (1e-9 K is ~1e5 ulp of 300 K: ample).
    lam = 10.9
    temps = np.linspace(200.0, 350.0, 31)
    bt = radiance_to_brightness_temperature(planck(lam, temps), C1 / lam ** 5, C2 / lam)
    np.testing.assert_allclose(bt, temps, atol=1e-9)
    np.testing.assert_allclose(radiance_to_brightness_temperature(
        brightness_temperature_to_radiance(temps, K1, K2), K1, K2), temps, atol=1e-9)


def test_band10_constants_match_band_averaged_planck():
    # The published K1/K2 are fitted to TIRS band 10's real response; against Planck averaged
    # over the nominal 10.60-11.19 um box they agree to ~0.2 K (K1 is 0.3 % below c1/lambda_eff^5,
    # which is dT ~ 0.003 T^2/K2 = 0.14..0.25 K over 250..330 K). 0.3 K bounds it.
    for temp in (250.0, 280.0, 300.0, 330.0):
        band = quad(lambda lam: planck(lam, temp), 10.60, 11.19)[0] / 0.59
        assert abs(radiance_to_brightness_temperature(band, K1, K2) - temp) < 0.3


def test_dn_conversions_by_hand():
    # LSDS-1574 eqs. 5-1..5-3 with the real band-10 constants: DN 30000 -> 10.126 W m-2 sr-1 um-1.
    assert dn_to_radiance(30000, 3.342e-4, 0.1) == pytest.approx(30000 * 3.342e-4 + 0.1, rel=1e-15)
    assert dn_to_reflectance(10000, 2e-5, -0.1, 30.0) == pytest.approx((0.2 - 0.1) / 0.5, rel=1e-12)
    assert np.isnan(radiance_to_brightness_temperature(-1.0, K1, K2))


@pytest.fixture(scope="module")
def port_dir(tmp_path_factory):
    d = tmp_path_factory.mktemp("port")
    write_synthetic_port(d, "winter", seed=7, size_px=80)
    return d


def _mtl(d, ext):
    return next(os.path.join(d, f) for f in os.listdir(d) if f.endswith(f"_MTL.{ext}"))


def test_mtl_text_and_json_agree(port_dir):
    a, b = read_mtl(_mtl(port_dir, "txt")), read_mtl(_mtl(port_dir, "json"))
    assert a.k1 == b.k1 == pytest.approx(774.8853) and a.k2 == b.k2 == pytest.approx(1321.0789)
    assert a.radiance_mult == b.radiance_mult and a.reflectance_add == b.reflectance_add
    assert a.acquired_utc == b.acquired_utc and a.acquired_utc.tzinfo is not None
    assert a.band_files == b.band_files


def test_scene_reads_on_one_grid(port_dir):
    scene = read_landsat_scene(_mtl(port_dir, "json"))
    assert scene.grid.shape == (80, 80) and scene.grid.resolution == 30.0
    assert scene.grid.crs.to_epsg() == 32651
    assert not scene.fill.any()


@pytest.mark.parametrize("form", ["txt", "json"])
def test_missing_mtl_key_is_named(port_dir, tmp_path, form):
    src = _mtl(port_dir, form)
    text = open(src).read()
    if form == "txt":
        text = "\n".join(l for l in text.splitlines() if "K2_CONSTANT_BAND_10" not in l)
    else:
        doc = json.loads(text)
        del doc["LANDSAT_METADATA_FILE"]["LEVEL1_THERMAL_CONSTANTS"]["K2_CONSTANT_BAND_10"]
        text = json.dumps(doc)
    bad = tmp_path / f"X_MTL.{form}"
    bad.write_text(text)
    with pytest.raises(InputError, match="K2_CONSTANT_BAND_10"):
        read_mtl(bad)


def test_non_numeric_mtl_value(port_dir, tmp_path):
    text = open(_mtl(port_dir, "txt")).read().replace("RADIANCE_MULT_BAND_10 = 3.3420E-04", "RADIANCE_MULT_BAND_10 = abc")
    (tmp_path / "Y_MTL.txt").write_text(text)
    with pytest.raises(InputError, match="RADIANCE_MULT_BAND_10.*must be a number"):
        read_mtl(tmp_path / "Y_MTL.txt")


def _rewrite(path, data, profile):
    # Not in place: GDAL deletes a GeoTIFF's sidecar files (the Landsat *_MTL.txt among them)
    # when a dataset is re-created over an existing file.
    with rasterio.open(str(path) + ".tmp.tif", "w", **profile) as dst:
        dst.write(data, 1)
    os.replace(str(path) + ".tmp.tif", path)


def _copy_scene(port_dir, tmp_path):
    for f in os.listdir(port_dir):
        shutil.copy(os.path.join(port_dir, f), tmp_path / f)
    mtl = read_mtl(_mtl(tmp_path, "txt"))
    return mtl


def test_band_shape_mismatch_is_an_error(port_dir, tmp_path):
    mtl = _copy_scene(port_dir, tmp_path)
    path = mtl.band_files[10]
    with rasterio.open(path) as src:
        profile, data = src.profile, src.read(1)
    profile.update(height=79)
    _rewrite(path, data[:79], profile)
    with pytest.raises(InputError, match=r"FILE_NAME_BAND_10\.shape.*\(79, 80\)"):
        read_landsat_scene(mtl.path)


def test_band_crs_mismatch_is_an_error(port_dir, tmp_path):
    mtl = _copy_scene(port_dir, tmp_path)
    path = mtl.band_files[5]
    with rasterio.open(path) as src:
        profile, data = src.profile, src.read(1)
    profile.update(crs="EPSG:32650")
    _rewrite(path, data, profile)
    with pytest.raises(InputError, match=r"FILE_NAME_BAND_5\.crs.*Reproject"):
        read_landsat_scene(mtl.path)


def test_missing_band_file(port_dir, tmp_path):
    mtl = _copy_scene(port_dir, tmp_path)
    os.remove(mtl.band_files[4])
    with pytest.raises(InputError, match="FILE_NAME_BAND_4"):
        read_landsat_scene(mtl.path)


def test_crop_reads_a_pixel_window(port_dir):
    # Cropping the port out of a scene: only the window is read, DN identical to the slice of
    # the full read, the grid moves by whole pixels; a box is widened outwards to whole pixels.
    full = read_landsat_scene(_mtl(port_dir, "txt"))
    t = full.grid.transform
    x0, y0 = t.c, t.f
    bounds = (x0 + 10 * 30 + 5, y0 - 70 * 30 + 3, x0 + 50 * 30 - 2, y0 - 20 * 30)
    crop = read_landsat_scene(_mtl(port_dir, "json"), bounds)
    assert crop.grid.shape == (50, 40) and crop.grid.crs == full.grid.crs
    assert crop.grid.transform.c == x0 + 300 and crop.grid.transform.f == y0 - 600
    for b in full.dn:
        np.testing.assert_array_equal(crop.dn[b], full.dn[b][20:70, 10:50])
    np.testing.assert_array_equal(crop.brightness_temperature(), full.brightness_temperature()[20:70, 10:50])
    with pytest.raises(InputError, match=r"bounds.*must lie inside the raster"):
        read_landsat_scene(_mtl(port_dir, "txt"), (x0 - 100, y0 - 900, x0 + 900, y0))
    with pytest.raises(InputError, match=r"bounds.*west < east"):
        read_landsat_scene(_mtl(port_dir, "txt"), (x0 + 900, y0 - 900, x0 + 300, y0))
