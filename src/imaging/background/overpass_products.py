"""The overpass part of the background: a Landsat scene's LST, classes and masks, its masked
pixels filled from same-class neighbours."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import distance_transform_edt

from shipthermal.errors import require

from ..parameters import N_SPLITS
from .classify import ClassificationResult, classify_scene, read_roi, water_index_check
from .landsat.bands import MASK_BITS, QA_MASK_FLAGS
from .landsat.grid import NIR_BAND, RED_BAND, REFLECTIVE_BANDS, SceneGrid
from .landsat.scene import LST_ACCURACY_ST_B10_K, LandsatScene
from .lst import (AtmosphereB10, atmospheric_functions, emissivity_ndvi_threshold,
                  lst_single_channel, ndvi)


LST_ACCURACY_SINGLE_CHANNEL_K = 3.0
"""Stated accuracy of the single-channel band-10 LST [K]: 2–3 K too cold against an
independent atmosphere (:mod:`.lst` module docstring, measured in its tests)."""


@dataclass
class OverpassProducts:
    """Everything the Landsat overpass alone gives: LST, classes, masks, their checks.

    Attributes
    ----------
    scene : LandsatScene
    grid : SceneGrid
    class_map : ndarray uint8
        Classes after masked pixels were filled (0 = fill with no valid neighbour).
    lst : ndarray float32
        Surface temperature at the overpass [K]: ``ST_B10`` (Level-2) or single-channel.
    lst_source : {"ST_B10", "single_channel"}
    lst_accuracy_k : float
        Stated accuracy of that LST [K] (:data:`.landsat.LST_ACCURACY_ST_B10_K`,
        :data:`LST_ACCURACY_SINGLE_CHANNEL_K`).
    brightness_temperature : ndarray float32
        Band-10 brightness temperature [K] (NaN for Level-2: no TOA band 10).
    emissivity, ndvi : ndarray float32
    features : ndarray (rows, cols, 6)
        Reflectances of bands 2–7 [-], masked pixels filled.
    atmosphere : AtmosphereB10 or None
        Band-10 atmosphere of the single-channel retrieval (None for ST_B10).
    classification : ClassificationResult
    water_check : dict
        :func:`.classify.water_index_check` (without its per-pixel mask).
    water_disagreement : ndarray bool
        Pixels where MNDWI and the water class disagree.
    mask : ndarray uint8
        Bit mask of replaced pixels: 1 fill, 2 cloud, 4 cirrus, 8 cloud shadow.
    filled_pixels : int
    notes : list[str]
    """

    scene: LandsatScene
    grid: SceneGrid
    class_map: np.ndarray
    lst: np.ndarray
    lst_source: str
    lst_accuracy_k: float
    brightness_temperature: np.ndarray
    emissivity: np.ndarray
    ndvi: np.ndarray
    features: np.ndarray
    atmosphere: AtmosphereB10 | None
    classification: ClassificationResult
    water_check: dict
    water_disagreement: np.ndarray
    mask: np.ndarray
    filled_pixels: int
    notes: list

    def summary_extra(self) -> dict:
        c = self.classification
        return {"landsat_level": self.scene.level, "landsat_collection": self.scene.mtl.collection,
                "lst_source": self.lst_source, "lst_stated_accuracy_K": self.lst_accuracy_k,
                "georeferenced_from_mtl": self.scene.georeferenced_from_mtl,
                "masked_pixels": {**{f: int(np.count_nonzero(self.mask & (1 << k)))
                                     for k, f in enumerate(QA_MASK_FLAGS)}, "filled": self.filled_pixels},
                "accuracy_over_splits": c.spread(),
                "water_check": self.water_check, "notes": list(self.notes)}




def fill_masked_pixels(class_map, masked, layers):
    """Give masked pixels the class of the nearest valid pixel and, per layer, the value of
    the nearest valid pixel **of that class**.

    Parameters
    ----------
    class_map : ndarray uint8
        Classes of the valid pixels (masked pixels are ignored).
    masked : ndarray bool
    layers : dict[str, ndarray]
        (rows, cols) or (rows, cols, k) arrays to fill.

    Returns
    -------
    class_map, layers : filled copies (unchanged where no valid pixel exists at all).
    """
    valid = ~masked & (class_map > 0)
    out_cls = class_map.copy()
    out = {k: np.array(v, copy=True) for k, v in layers.items()}
    if not masked.any() or not valid.any():
        return out_cls, out
    _, (ri, ci) = distance_transform_edt(~valid, return_indices=True)
    out_cls[masked] = class_map[ri[masked], ci[masked]]
    for c in np.unique(out_cls[masked]):
        ok = valid & (class_map == c)
        if not ok.any():
            continue
        _, (rj, cj) = distance_transform_edt(~ok, return_indices=True)
        sel = masked & (out_cls == c)
        for k, v in out.items():
            v[sel] = layers[k][rj[sel], cj[sel]]
    return out_cls, out


def build_overpass(scene: LandsatScene, roi_path, *, water_vapour: float | None = None,
                   lst_method: str = "planck", emissivity_model: str = "tirs_b10",
                   test_fraction: float = 0.5, roi_split: str = "regions", seed: int = 0,
                   n_splits: int = N_SPLITS) -> OverpassProducts:
    """LST, classes and masks of a Landsat scene (the overpass part of the background).

    Masked pixels (QA fill, cloud, cirrus, cloud shadow; DN fill) are left out of training
    and classification, then take the class of the nearest valid pixel and the LST,
    reflectances and emissivity of the nearest valid pixel of that class.

    Parameters
    ----------
    scene : LandsatScene
    roi_path : path-like
        Training ROIs (:func:`.classify.read_roi`).
    water_vapour : float, optional
        Column water vapour [g cm-2] for the single-channel LST (Level-1 only; required then).
    lst_method, emissivity_model, test_fraction, roi_split, seed, n_splits
        As :class:`.settings.BackgroundSettings`.
    """
    grid = scene.grid
    notes = list(scene.notes)
    masked = scene.masked
    mask = np.zeros(grid.shape, np.uint8)
    mask[scene.fill] |= MASK_BITS["fill"]
    if scene.qa is not None:
        for f in QA_MASK_FLAGS:
            mask[scene.qa[f]] |= MASK_BITS[f]
    red = scene.reflectance(RED_BAND)
    nir = scene.reflectance(NIR_BAND)
    ndvi_map = ndvi(red, nir)
    emissivity = emissivity_ndvi_threshold(ndvi_map, red, emissivity_model)
    atmosphere = None
    if scene.level == "L2":
        lst = scene.surface_temperature()
        bt = np.full(grid.shape, np.nan)
        source, accuracy = "ST_B10", LST_ACCURACY_ST_B10_K
        notes.append(f"LST = Level-2 ST_B10 (stated accuracy ~{LST_ACCURACY_ST_B10_K:g} K)")
    else:
        require(water_vapour is not None, "water_vapour", None,
                "the single-channel LST of a Level-1 scene needs the column water vapour [g cm-2]",
                "Give it, or a met grid with tcwv, or use the Level-2 product (ST_B10)")
        atmosphere = atmospheric_functions(water_vapour)
        lst = lst_single_channel(scene.radiance(), emissivity, atmosphere, scene.mtl.k1, scene.mtl.k2, lst_method)
        bt = scene.brightness_temperature()
        source, accuracy = "single_channel", LST_ACCURACY_SINGLE_CHANNEL_K
        notes.append(f"LST = single-channel band 10, w = {water_vapour:.2f} g cm-2 (stated accuracy "
                     f"{LST_ACCURACY_SINGLE_CHANNEL_K:g} K, systematic)")
    features = np.stack([scene.reflectance(b) for b in REFLECTIVE_BANDS], axis=-1)
    features[masked] = np.nan
    roi = read_roi(roi_path, grid)
    n_masked_roi = int((roi > 0)[masked].sum())
    if n_masked_roi:
        notes.append(f"{n_masked_roi} ROI pixels are masked (cloud/shadow/fill) and not used for training")
    classification = classify_scene(features, roi, test_fraction=test_fraction, seed=seed, split=roi_split,
                                    n_splits=n_splits)
    sp = classification.spread()["overall_accuracy"]
    notes.append(f"classification over {n_splits} held-out ROI splits ({roi_split}): overall accuracy "
                 f"{sp['mean']:.3f} +- {sp['std']:.3f} (min {sp['min']:.3f}, max {sp['max']:.3f}); "
                 "final map from all ROIs")
    b = {k: scene.reflectance(k) for k in (3, 5, 6)}
    wc = water_index_check(b[3], b[5], b[6], classification.class_map)
    disagree = wc.pop("disagree")
    notes.append(wc["message"])
    layers = {"lst": lst, "features": features, "emissivity": emissivity, "ndvi": ndvi_map, "bt": bt}
    class_map, filled = fill_masked_pixels(classification.class_map, masked, layers)
    n_filled = int((masked & (class_map > 0)).sum())
    if masked.any():
        notes.append(f"{int(masked.sum())} masked pixels; {n_filled} filled from the nearest valid pixel of "
                     "the same class (mask in qa_mask.tif)")
    return OverpassProducts(scene=scene, grid=grid, class_map=class_map, lst=filled["lst"].astype(np.float32),
                            lst_source=source, lst_accuracy_k=accuracy,
                            brightness_temperature=filled["bt"].astype(np.float32),
                            emissivity=filled["emissivity"].astype(np.float32),
                            ndvi=filled["ndvi"].astype(np.float32), features=filled["features"],
                            atmosphere=atmosphere, classification=classification, water_check=wc,
                            water_disagreement=disagree, mask=mask, filled_pixels=n_filled, notes=notes)
