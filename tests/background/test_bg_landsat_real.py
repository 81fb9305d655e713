"""Landsat readers, QA masks, ROIs and the overpass stage on real files (committed crops):
the Mersey Collection-2 Level-2 scene (TIFFs without CRS) and a pre-collection L1T scene
whose file names differ from its MTL."""

import os
import re
import shutil
from pathlib import Path

import numpy as np
import pytest
import rasterio
from rasterio.warp import transform as warp_transform

from imaging.background.background import build_overpass, fill_masked_pixels
from imaging.background.classify import read_roi
from imaging.background.landsat import qa_flags, read_landsat_scene, read_mtl
from shipthermal.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
MERSEY_DIR = ROOT / "examples/real_port/data"
MERSEY = MERSEY_DIR / "LC08_L2SP_204023_20200927_20201006_02_T1_MTL.txt"
ROIS = MERSEY_DIR / "mersey_rois.geojson"
PRE = ROOT / "tests/data/landsat8_pre_collection"


def _num(text, key):
    return float(re.search(rf"^\s*{key}\s*=\s*([-+0-9.Ee]+)", text, re.M).group(1))


@pytest.fixture(scope="module")
def mersey():
    return read_landsat_scene(MERSEY)


@pytest.fixture(scope="module")
def pre():
    return read_landsat_scene(PRE / "l8_MTL.txt")


# --- Level-2, MTL with groups, georeferencing from the MTL ------------------------------------
def test_level2_mtl_names_the_product_files_not_the_level1_record():
    mtl = read_mtl(MERSEY)
    assert mtl.level == "L2" and mtl.collection == "2"
    for b in (2, 3, 4, 5, 6, 7):
        assert os.path.basename(mtl.band_files[b]).endswith(f"_SR_B{b}.TIF")
        assert "L1TP" not in mtl.band_files[b]
    assert mtl.band_files[10].endswith("_ST_B10.TIF")
    # surface reflectance scaling of the L2 group, not the L1 TOA rescaling (2.0E-05)
    assert mtl.reflectance_mult[2] == 2.75e-05 and mtl.reflectance_add[2] == -0.2
    assert mtl.st_mult == 0.00341802 and mtl.st_add == 149.0


def test_level2_grid_from_mtl_corners(mersey):
    # MTL corners are pixel centres: 487020 .. 499980 E is 433 columns of 30 m.
    g = mersey.grid
    assert mersey.georeferenced_from_mtl
    assert g.crs.to_epsg() == 32630 and g.shape == (267, 433)
    assert (g.transform.c, g.transform.f) == (487005.0, 5929995.0)
    assert any("georeferencing from the MTL" in n for n in mersey.notes)
    # the scene centre is on the Mersey estuary (53.5 N, 3.1 W)
    (lon,), (lat,) = warp_transform(g.crs, "EPSG:4326", [g.transform.c + 433 * 15], [g.transform.f - 267 * 15])
    assert 53.4 < lat < 53.6 and -3.2 < lon < -2.9


def test_st_b10_is_the_scaled_dn(mersey):
    text = MERSEY.read_text()
    with rasterio.open(str(MERSEY).replace("_MTL.txt", "_ST_B10.TIF")) as src:
        dn = src.read(1).astype(float)
    ref = _num(text, "TEMPERATURE_MULT_BAND_ST_B10") * dn + _num(text, "TEMPERATURE_ADD_BAND_ST_B10")
    np.testing.assert_allclose(mersey.surface_temperature(), ref, rtol=0, atol=1e-9)
    assert 284.0 < np.nanmin(ref) and np.nanmax(ref) < 296.0          # late-September estuary
    with pytest.raises(InputError, match="Level-1"):
        mersey.brightness_temperature()


def test_level2_missing_key_is_named(tmp_path):
    text = "\n".join(ln for ln in MERSEY.read_text().splitlines() if "TEMPERATURE_MULT_BAND_ST_B10" not in ln)
    (tmp_path / "X_MTL.txt").write_text(text)
    with pytest.raises(InputError, match=r"TEMPERATURE_MULT_BAND_ST_B10.*Level-2 MTL"):
        read_mtl(tmp_path / "X_MTL.txt")


def test_tiff_without_crs_and_foreign_mtl(tmp_path):
    # The same TIFF without its MTL: the error says where georeferencing comes from.
    from imaging.background.landsat import read_band

    tif = str(MERSEY).replace("_MTL.txt", "_SR_B4.TIF")
    with pytest.raises(InputError, match=r"must carry a CRS.*MTL"):
        read_band(tif, "band")
    # An MTL whose corners describe another grid size: named, not silently misplaced.
    for f in MERSEY_DIR.glob("LC08*"):
        shutil.copy(f, tmp_path / f.name)
    mtl = tmp_path / MERSEY.name
    mtl.write_text(mtl.read_text().replace("CORNER_LR_PROJECTION_X_PRODUCT = 499980.0",
                                           "CORNER_LR_PROJECTION_X_PRODUCT = 500010.0"))
    with pytest.raises(InputError, match=r"shape.*\(267, 433\).*MTL corners \(267, 434\)"):
        read_landsat_scene(mtl)


def test_truncated_tiff_is_a_clear_error(tmp_path):
    for f in MERSEY_DIR.glob("LC08*"):
        shutil.copy(f, tmp_path / f.name)
    b5 = tmp_path / MERSEY.name.replace("_MTL.txt", "_SR_B5.TIF")
    data = b5.read_bytes()
    b5.write_bytes(data[: len(data) // 3])
    with pytest.raises(InputError, match=r"FILE_NAME_BAND_5.*readable GeoTIFF"):
        read_landsat_scene(tmp_path / MERSEY.name)


# --- pre-collection: file names, BQA, brightness temperature -----------------------------------
def test_pre_collection_files_found_by_suffix_and_bt_is_planck_inversion(pre):
    assert pre.mtl.collection == "pre" and pre.level == "L1"
    assert os.path.basename(pre.mtl.band_files[10]) == "l8_B10.tif"
    assert any("l8_B10.tif" in n for n in pre.notes)
    text = (PRE / "l8_MTL.txt").read_text()
    with rasterio.open(PRE / "l8_B10.tif") as src:
        dn = src.read(1).astype(float)
    rad = _num(text, "RADIANCE_MULT_BAND_10") * dn + _num(text, "RADIANCE_ADD_BAND_10")
    ref = _num(text, "K2_CONSTANT_BAND_10") / np.log(_num(text, "K1_CONSTANT_BAND_10") / rad + 1.0)
    np.testing.assert_allclose(pre.brightness_temperature(), ref, rtol=0, atol=1e-9)


def test_band_file_template_and_missing_override(tmp_path):
    a = read_landsat_scene(PRE / "l8_MTL.txt", band_files="l8_{band}.tif")
    assert not any("same band suffix" in n for n in a.notes)
    assert os.path.basename(a.mtl.qa_file) == "l8_BQA.tif"
    with pytest.raises(InputError, match=r"FILE_NAME_BAND_4.*existing GeoTIFF.*band_files"):
        read_landsat_scene(PRE / "l8_MTL.txt", band_files={"B4": "nothere_B4.tif"})


def test_bqa_bits_against_an_independent_decoding(pre):
    # Pre-collection L8 BQA: cloud confidence in bits 14-15 (masked from 2 = medium), cirrus
    # in 12-13 (3 = high).
    with rasterio.open(PRE / "l8_BQA.tif") as src:
        q = src.read(1).astype(np.int64)
    cloud = (q // 2 ** 14) % 4 >= 2
    cirrus = (q // 2 ** 12) % 4 == 3
    np.testing.assert_array_equal(pre.qa["cloud"], cloud)
    np.testing.assert_array_equal(pre.qa["cirrus"], cirrus)
    assert 0.05 < cloud.mean() < 0.3
    # clouds are what made "228 K land": flagged pixels are much colder than clear ones
    bt = pre.brightness_temperature()
    assert np.mean(bt[cloud]) < np.mean(bt[~pre.masked]) - 8.0
    # Collection-2 QA_PIXEL single bits: 0x5440 = clear, low confidences (no flag), 1<<3 cloud, 1<<4 shadow
    f = qa_flags(np.array([0x5440, 1 << 3, 1 << 4, 1], np.uint16), "2")
    assert f["cloud"].tolist() == [False, True, False, False]
    assert f["shadow"].tolist() == [False, False, True, False]
    assert f["fill"].tolist() == [False, False, False, True]


# --- filling masked pixels ----------------------------------------------------------------------
def test_fill_masked_pixels_against_brute_force():
    rng = np.random.default_rng(1)
    cls = np.ones((30, 40), np.uint8)
    cls[:, 20:] = 2
    cls[10:15, 5:12] = 3
    val = rng.normal(size=cls.shape)
    masked = np.zeros(cls.shape, bool)
    masked[8:18, 15:26] = True
    out_cls, out = fill_masked_pixels(cls, masked, {"v": val})
    vr, vc = np.nonzero(~masked)
    for r, c in zip(*np.nonzero(masked)):
        d = (vr - r) ** 2 + (vc - c) ** 2
        nearest_cls = cls[vr[d == d.min()], vc[d == d.min()]]
        assert out_cls[r, c] in nearest_cls                       # ties: any of the nearest
        same = cls[vr, vc] == out_cls[r, c]
        dd = np.where(same, d, np.inf)
        cand = val[vr[dd == dd.min()], vc[dd == dd.min()]]
        assert out["v"][r, c] in cand
    np.testing.assert_array_equal(out["v"][~masked], val[~masked])


# --- ROIs in any CRS / format -------------------------------------------------------------------
def test_rois_geojson_lonlat_gpkg_bng_and_shapefile_agree(mersey, tmp_path):
    import pyogrio
    import shapely
    from rasterio.warp import transform_geom

    lab = read_roi(ROIS, mersey.grid)
    counts = np.bincount(lab.ravel(), minlength=5)
    assert counts[1:].min() >= 400 and (counts[1:] > 0).all()
    meta, _, geoms, fields = pyogrio.raw.read(ROIS)
    wkb_bng = [shapely.to_wkb(shapely.geometry.shape(transform_geom(
        "EPSG:4326", "EPSG:27700", shapely.geometry.mapping(shapely.from_wkb(g))))) for g in geoms]
    pyogrio.raw.write(tmp_path / "rois.gpkg", np.array(wkb_bng, dtype=object), [fields[0]],
                      fields=["class"], geometry_type="Polygon", crs="EPSG:27700", driver="GPKG")
    pyogrio.raw.write(tmp_path / "rois.shp", geoms, [fields[0]], fields=["class"],
                      geometry_type="Polygon", crs="EPSG:4326", driver="ESRI Shapefile")
    for other in ("rois.gpkg", "rois.shp"):
        lab2 = read_roi(tmp_path / other, mersey.grid)
        # polygon edges are straight in each CRS, so boundary pixels may flip: < 1 % of ROI pixels
        assert (lab2 != lab).sum() < 0.01 * (lab > 0).sum()


def test_rois_outside_the_scene(mersey, tmp_path):
    text = ROIS.read_text()
    far = re.sub(r"\[\s*(-?\d+\.\d+),", lambda m: f"[{float(m.group(1)) + 20.0:.6f},", text)
    (tmp_path / "far.geojson").write_text(far)
    with pytest.raises(InputError, match=r"roi_path.*polygons lie outside the scene"):
        read_roi(tmp_path / "far.geojson", mersey.grid)


# --- the overpass stage on the real scenes -----------------------------------------------------
def test_mersey_overpass_classification_and_water_check(mersey):
    ov = build_overpass(mersey, ROIS, seed=0)
    c = ov.classification
    assert len(c.splits) == 10
    sp = c.spread()["overall_accuracy"]
    # measured: 0.802 +- 0.053 over splits 0..9 (16 ROIs, 4 per class)
    assert 0.7 < sp["mean"] < 0.9 and 0.01 < sp["std"] < 0.15
    # the map is from all ROIs: another seed changes the assessment, not the map
    ov2 = build_overpass(mersey, ROIS, seed=100)
    np.testing.assert_array_equal(ov.class_map, ov2.class_map)
    frac = dict(zip(c.fractions["class"], c.fractions["fraction"]))
    assert 0.6 < frac["water"] < 0.8                   # the crop is ~75 % estuary
    wc = ov.water_check
    assert wc["mndwi_extra_share"] < 0.01 and wc["mndwi_missed_share"] < 0.10
    assert ov.lst_source == "ST_B10" and np.isfinite(ov.lst).all()


def test_pre_collection_overpass_fills_clouds_and_writes_mask(pre, tmp_path):
    # ROIs as a label raster on the scene grid, sampled in clear areas of the crop (no open
    # water there: four NDVI quartiles stand in for the classes; this tests the masking)
    lab = np.zeros(pre.grid.shape, np.uint8)
    rho5, rho4 = pre.reflectance(5), pre.reflectance(4)
    ndvi = (rho5 - rho4) / (rho5 + rho4)
    clear = ~pre.masked
    q = np.quantile(ndvi[clear], [0.25, 0.5, 0.75])
    rng = np.random.default_rng(0)
    for code, sel in ((1, ndvi < q[0]), (2, ndvi > q[2]), (3, (ndvi > q[0]) & (ndvi < q[1])),
                      (4, (ndvi > q[1]) & (ndvi < q[2]))):
        idx = np.flatnonzero((sel & clear).ravel())
        lab.flat[rng.choice(idx, min(idx.size, 200), replace=False)] = code
    prof = dict(driver="GTiff", height=lab.shape[0], width=lab.shape[1], count=1, dtype="uint8",
                crs=pre.grid.crs, transform=pre.grid.transform)
    with rasterio.open(tmp_path / "roi.tif", "w", **prof) as dst:
        dst.write(lab, 1)
    ov = build_overpass(pre, tmp_path / "roi.tif", water_vapour=2.0, roi_split="pixels")
    cloudy = pre.qa["cloud"] | pre.qa["cirrus"]
    assert ((ov.mask[cloudy] & (2 | 4)) > 0).all() and not (ov.mask[~pre.masked]).any()
    assert ov.filled_pixels == int(pre.masked.sum())
    assert (ov.class_map > 0).all() and np.isfinite(ov.lst).all()
    # filled LST comes from clear pixels: no cloud-top temperatures remain
    lst_clear = ov.lst[~pre.masked]
    assert ov.lst[pre.masked].min() >= lst_clear.min() - 1e-6


# --- scenario validate opens the rasters and lists every problem --------------------------------
def test_scenario_validate_reports_every_raster_problem_at_once(tmp_path, capsys):
    from shipthermal.app.cli import main

    scene = tmp_path / "scene"
    shutil.copytree(MERSEY_DIR, scene)
    b6 = scene / MERSEY.name.replace("_MTL.txt", "_SR_B6.TIF")
    b6.write_bytes(b6.read_bytes()[:40_000])                       # truncated
    roi = scene / "mersey_rois.geojson"
    roi.write_text(re.sub(r'"class": "building"', '"class": "water"', roi.read_text()))  # a class missing
    dem = ROOT / "tests/data/dem_srtm/N49W124_crop.tif"            # British Columbia: no overlap
    met = tmp_path / "met.nc"
    met.write_text("not netcdf")
    sc = tmp_path / "s.toml"
    sc.write_text(f'[background]\nsource = "files"\nmtl = "{scene / MERSEY.name}"\nroi = "{roi}"\n'
                  f'dem = "{dem}"\nmet = "{met}"\n')
    assert main(["check", str(sc)]) == 2
    err = capsys.readouterr().err
    for frag in ("FILE_NAME_BAND_6", "truncated or corrupt", "background.roi", "none for building",
                 "background.dem", "must overlap the scene", "background.met", "georeferencing from the MTL"):
        assert frag in err, (frag, err)
    # the untouched example passes
    assert main(["check", str(ROOT / "examples/real_port/background.toml")]) == 0


def test_level2_mtl_json_form_reads_like_the_text(tmp_path):
    # Collection-2 also ships the MTL as JSON (groups as nested objects): same product.
    import json

    from imaging.background.landsat import parse_mtl_groups

    root, groups = parse_mtl_groups(MERSEY.read_text())
    for f in MERSEY_DIR.glob("LC08*.TIF"):
        shutil.copy(f, tmp_path / f.name)
    js = tmp_path / MERSEY.name.replace(".txt", ".json")
    js.write_text(json.dumps({root: {g: items for g, items in groups.items() if g != root}}))
    a, b = read_mtl(MERSEY), read_mtl(js)
    assert b.level == "L2" and b.collection == "2"
    assert [os.path.basename(b.band_files[k]) for k in sorted(b.band_files)] == \
        [os.path.basename(a.band_files[k]) for k in sorted(a.band_files)]
    assert (b.st_mult, b.st_add, b.reflectance_mult, b.acquired_utc) == (a.st_mult, a.st_add, a.reflectance_mult,
                                                                         a.acquired_utc)
    assert b.georef == a.georef
