"""Real Landsat scenes through the readers: agreement with independent computations, the
classification's spread over held-out splits (one split, as a single run used to report,
against the mean over splits with the map trained on all ROIs), and timings.

    PYTHONPATH=src python benchmarks/bench_landsat_real.py [--realdata DIR]

Uses the committed crops (examples/real_port/data, tests/data) by default; ``--realdata``
points at a folder with the uncropped copies (``landsat8_l1t_pre_collection/``).
"""

from __future__ import annotations

import argparse
import re
import time
from pathlib import Path

import numpy as np
import rasterio

from imaging.background.background import build_overpass
from imaging.background.classify import _ml_model, predict_chunked, read_roi, split_training
from imaging.background.landsat import REFLECTIVE_BANDS, read_landsat_scene

ROOT = Path(__file__).resolve().parents[1]
MERSEY = ROOT / "examples/real_port/data/LC08_L2SP_204023_20200927_20201006_02_T1_MTL.txt"
ROIS = ROOT / "examples/real_port/data/mersey_rois.geojson"
PRE = ROOT / "tests/data/landsat8_pre_collection"


def _mtl_number(text: str, key: str) -> float:
    return float(re.search(rf"^\s*{key}\s*=\s*([-+0-9.Ee]+)", text, re.M).group(1))


def brightness_temperature_check(folder: Path) -> None:
    text = (folder / "l8_MTL.txt").read_text()
    t0 = time.perf_counter()
    scene = read_landsat_scene(folder / "l8_MTL.txt")
    bt = scene.brightness_temperature()
    dt = time.perf_counter() - t0
    with rasterio.open(folder / "l8_B10.tif") as src:
        dn = src.read(1).astype(np.float64)
    m, a = _mtl_number(text, "RADIANCE_MULT_BAND_10"), _mtl_number(text, "RADIANCE_ADD_BAND_10")
    k1, k2 = _mtl_number(text, "K1_CONSTANT_BAND_10"), _mtl_number(text, "K2_CONSTANT_BAND_10")
    ref = k2 / np.log(k1 / (m * dn + a) + 1.0)
    ok = dn > 0
    clear = ~scene.masked
    print(f"pre-collection L1T {scene.grid.shape}: read {dt:.3f} s; BT vs K2/ln(K1/L+1): max |diff| "
          f"{np.max(np.abs(bt[ok] - ref[ok])):.2e} K over {ok.sum()} px")
    for f in ("cloud", "cirrus", "shadow"):
        sel = scene.qa[f]
        print(f"  {f:6s} {sel.sum():7d} px, mean BT {np.nanmean(bt[sel]) if sel.any() else float('nan'):.1f} K "
              f"(clear {np.nanmean(bt[clear]):.1f} K)")


def st_b10_check() -> None:
    text = MERSEY.read_text()
    scene = read_landsat_scene(MERSEY)
    with rasterio.open(str(MERSEY).replace("_MTL.txt", "_ST_B10.TIF")) as src:
        dn = src.read(1).astype(np.float64)
    ref = (_mtl_number(text, "TEMPERATURE_MULT_BAND_ST_B10") * dn
           + _mtl_number(text, "TEMPERATURE_ADD_BAND_ST_B10"))
    st = scene.surface_temperature()
    print(f"Mersey L2 {scene.grid.shape}, {scene.grid.crs} from the MTL: ST_B10 vs mult*DN+add max |diff| "
          f"{np.nanmax(np.abs(st - ref)):.2e} K; ST {np.nanmin(st):.2f}..{np.nanmax(st):.2f} K")


def classification_spread(n_seeds: int = 10) -> None:
    scene = read_landsat_scene(MERSEY)
    features = np.stack([scene.reflectance(b) for b in REFLECTIVE_BANDS], axis=-1)
    valid = np.all(np.isfinite(features), axis=-1)
    roi = np.where(valid, read_roi(ROIS, scene.grid), 0)
    rho = {b: scene.reflectance(b) for b in (3, 4, 5, 6)}
    open_water = (rho[5] - rho[4]) / (rho[5] + rho[4]) < -0.1        # NDVI < -0.1
    # before: one region split, the map from that split's training half
    rows = []
    for seed in range(n_seeds):
        train, test = split_training(roi, 0.5, seed, "regions")
        model = _ml_model(features[train], roi[train])
        cmap = predict_chunked(model, features, valid)
        oa = float((cmap[test] == roi[test]).mean())
        rows.append((oa, (cmap == 4).mean(), (open_water & (cmap != 1)).sum() / open_water.sum()))
    r = np.array(rows)
    print(f"before (one split per run, map from the training half), seeds 0..{n_seeds - 1}:")
    print(f"  OA {r[:, 0].min():.3f}..{r[:, 0].max():.3f}; building share {100 * r[:, 1].min():.1f}..{100 * r[:, 1].max():.1f} %; "
          f"open water not labelled water {100 * r[:, 2].min():.1f}..{100 * r[:, 2].max():.1f} %")
    # after: mean +- std over 10 splits, map from all ROIs
    res = []
    t0 = time.perf_counter()
    for seed in range(0, n_seeds * 10, 10):
        ov = build_overpass(scene, ROIS, seed=seed)
        sp = ov.classification.spread()["overall_accuracy"]
        cm = ov.class_map
        res.append((sp["mean"], sp["std"], (cm == 4).mean(), (open_water & (cm != 1)).sum() / open_water.sum()))
    dt = (time.perf_counter() - t0) / n_seeds
    a = np.array(res)
    print(f"after (10 splits per run, map from all ROIs), {n_seeds} runs with different seeds ({dt:.2f} s per run):")
    print(f"  reported OA mean {a[:, 0].min():.3f}..{a[:, 0].max():.3f} (std within a run {a[:, 1].mean():.3f}); "
          f"building share {100 * a[:, 2].min():.1f}..{100 * a[:, 2].max():.1f} %; open water not labelled water "
          f"{100 * a[:, 3].min():.1f}..{100 * a[:, 3].max():.1f} %")
    print("  water check:", ov.water_check["message"])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--realdata", type=Path, help="folder with landsat8_l1t_pre_collection/ (uncropped)")
    args = ap.parse_args()
    brightness_temperature_check(PRE)
    if args.realdata:
        brightness_temperature_check(args.realdata / "landsat8_l1t_pre_collection")
    st_b10_check()
    classification_spread()


if __name__ == "__main__":
    main()
