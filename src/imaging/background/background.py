"""The port background pipeline: Landsat LST + classes + kriged met baseline + terrain -> T(x, y, t).

Temporal extension (paper §2.4), per pixel and local hour ``t``::

    land  : T(t) = T0(t) + [b1 Dem + b2 Slope + b3 Southness] + w(t) * (b0[class] + r)
    water : T(t) = LST + SST(t) - SST(t_ov)

``T0`` is the Ordinary-Kriging baseline of the hourly met grid (eq. 12); the bracket is eq. 15
with betas fitted by least squares on ``LST - T0(t_ov)`` over land pixels; ``b0[class]`` are
per-class intercepts of that fit and ``r`` the Landsat residual, so at the overpass
``T(t_ov) = LST`` exactly (the Landsat detail is kept, organised by class). ``w(t)`` is
``1`` (``residual_scaling="constant"``, default: the class contrast of the overpass persists)
or the solar-elevation ratio ``max(sin h(t), 0)/sin h(t_ov)`` (``"solar"``: class contrast is
daytime heating only; at night eq. 15 alone remains). Water pixels never use land physics:
they keep their Landsat pattern and follow the diurnal SST cycle of the met file.

**Mixed pixels on the land–water border** (a 30 m pixel straddling a quay, pier or the
coastline): taken as pure land, a pixel whose overpass LST is mostly water would carry its
large negative residual into the night and come out colder than both land and sea (on the
synthetic port: a 12 K cold ring round every pier at midnight). Border pixels (land next to
water or water next to land, 3x3) are therefore unmixed (:func:`unmix_border_pixels`)::

    border: T(t) = f * [T0(t) + terr_L + w(t) * b0_L] + (1 - f) * [W_ov + SST(t) - SST(t_ov)] + e

with the water end-member ``W_ov`` the mean LST of pure water within 2 pixels (7 if none),
the land end-member from the pixel's own class and terrain (land pixels) or the mean of pure
land within 2 (7) pixels (water pixels), the land fraction ``f = (LST - W_ov)/(L_ov - W_ov)``
clipped to [0, 1] where the end-members differ by >= 1 K, else from linear spectral unmixing
of the reflectances (a winter overpass can leave land and sea within a kelvin), and ``e``
the remainder, so ``T(t_ov) = LST`` still holds. Pixels without a pure neighbour keep the
plain rules above (``border_unmixing=False`` switches it off).
"""

from __future__ import annotations

import os
import tempfile
import time
from dataclasses import dataclass, field
from datetime import datetime

import numpy as np
import pandas as pd
from scipy.ndimage import binary_erosion

from shipthermal.errors import InputError, check_range, require

from ..parameters import DEM_NODATA, N_SPLITS
from .classify import CLASS_NAMES, ClassificationResult, classify_scene, read_roi, water_index_check
from .kriging import krige_hourly
from .landsat.bands import MASK_BITS, QA_MASK_FLAGS
from .landsat.grid import NIR_BAND, RED_BAND, REFLECTIVE_BANDS, SceneGrid
from .landsat.scene import LST_ACCURACY_ST_B10_K, LandsatScene, read_landsat_scene
from .lst import (EMISSIVITY_PARAMETERS, AtmosphereB10, atmospheric_functions, emissivity_ndvi_threshold,
                  lst_single_channel, ndvi)
from .met import met_for_scene, read_met_grid
from .terrain import TerrainFit, fit_terrain_regression, load_dem, slope_aspect, southness, terrain_term

__all__ = ["PortBackground", "OverpassProducts", "build_overpass", "fill_masked_pixels",
           "build_background_from_files", "build_port_background", "unmix_border_pixels"]

LST_ACCURACY_SINGLE_CHANNEL_K = 3.0
"""Stated accuracy of the single-channel band-10 LST [K]: 2–3 K too cold against an
independent atmosphere (:mod:`.lst` module docstring, measured in its tests)."""

WATER = 1
LAND_CLASSES = (2, 3, 4)


@dataclass
class PortBackground:
    """Everything the imaging stage needs about the port background.

    Attributes
    ----------
    grid : SceneGrid
        Scene grid (transform, CRS, shape; 30 m).
    season : str or None
    class_map : ndarray uint8 (rows, cols)
        1 water, 2 vegetation, 3 land, 4 building, 0 fill (:data:`CLASS_NAMES`).
    lst : ndarray float32
        Landsat land surface temperature at the overpass [K].
    brightness_temperature : ndarray float32
        Band-10 at-sensor brightness temperature [K].
    emissivity, ndvi : ndarray float32
        Band-10 emissivity [-] and NDVI [-].
    elevation : ndarray float32
        DEM on the scene grid [m] (NaN = masked).
    slope_deg, aspect_deg : ndarray float32
        Slope [deg] and aspect (compass azimuth of downslope) [deg].
    terrain : TerrainFit
        Eq. 15 coefficients and R^2.
    classification : ClassificationResult
        JM table, confusion matrix, OA, kappa, class fractions.
    variograms : list[VariogramFit]
        Variogram fitted per met time step (ordered by local hour).
    hours_local : ndarray (24,)
        Local clock hours of the layers of ``temperature`` [h].
    temperature : ndarray float32 (24, rows, cols)
        Background temperature per hour [K].
    baseline : ndarray float32 (24, rows, cols)
        Kriged met baseline T0 [K].
    sst : ndarray (24,)
        SST per local hour [K].
    overpass_utc : datetime
    overpass_hour_local : float
        [h]
    atmosphere : AtmosphereB10 or None
        Band-10 atmosphere used by the LST retrieval (None when ST_B10 was the LST).
    emissivity_model : str
        NDVI-thresholds coefficient set used (:data:`.lst.EMISSIVITY_PARAMETERS`).
    input_notes : tuple[str, ...]
        How the met grid and DEM were read: clipping, unit inference, SST / water-vapour
        sources and fallbacks, DEM voids filled or masked.
    unmixed_pixels : int
        Land–water border pixels treated as two-end-member mixtures (module docstring).
    land_fraction : ndarray or None
        Land fraction ``f`` of the unmixed pixels [-] (NaN elsewhere).
    utc_offset_hours : float
    dem_masked_pixels : int
        Scene pixels without a DEM value (explicitly masked; 0 unless ``dem_nodata="mask"``).
    outputs : dict[str, str]
        Files written (empty without ``out_dir``).
    timings : dict[str, float]
        Wall time per stage [s].
    synthetic_truth : dict or None
        The generator's truth arrays when built by :func:`build_port_background`.
    """

    grid: SceneGrid
    season: str | None
    class_map: np.ndarray
    lst: np.ndarray
    brightness_temperature: np.ndarray
    emissivity: np.ndarray
    ndvi: np.ndarray
    elevation: np.ndarray
    slope_deg: np.ndarray
    aspect_deg: np.ndarray
    terrain: TerrainFit
    classification: ClassificationResult
    variograms: list
    hours_local: np.ndarray
    temperature: np.ndarray
    baseline: np.ndarray
    sst: np.ndarray
    overpass_utc: datetime
    overpass_hour_local: float
    atmosphere: AtmosphereB10 | None
    utc_offset_hours: float
    dem_masked_pixels: int
    emissivity_model: str = "tirs_b10"
    unmixed_pixels: int = 0
    land_fraction: np.ndarray | None = field(default=None, repr=False)
    outputs: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)
    synthetic_truth: dict | None = field(default=None, repr=False)
    overpass: "OverpassProducts | None" = field(default=None, repr=False)
    input_notes: tuple = ()

    def temperature_at(self, hour_local: float) -> np.ndarray:
        """Background temperature at a local clock time [K], float32 (rows, cols).

        Linear in time between the hourly layers, periodic over 24 h.
        """
        h = float(hour_local)
        require(np.isfinite(h), "hour_local", hour_local, "must be a finite hour")
        hrs = self.hours_local
        h = hrs[0] + (h - hrs[0]) % 24.0
        k = int(np.searchsorted(hrs, h, side="right") - 1)
        k1 = (k + 1) % hrs.size
        span = (hrs[k1] - hrs[k]) % 24.0 or 24.0
        t = (h - hrs[k]) / span
        return ((1.0 - t) * self.temperature[k] + t * self.temperature[k1]).astype(np.float32)

    def summary(self) -> dict:
        """JSON-able key figures."""
        c = self.classification
        return {
            "season": self.season,
            "shape": list(self.grid.shape),
            "crs": str(self.grid.crs),
            "overpass_utc": self.overpass_utc.isoformat(),
            "overpass_hour_local": self.overpass_hour_local,
            "water_vapour_g_cm2": getattr(self.atmosphere, "water_vapour", None),
            "emissivity_model": self.emissivity_model,
            "tau": getattr(self.atmosphere, "tau", None), "l_up": getattr(self.atmosphere, "l_up", None),
            "l_down": getattr(self.atmosphere, "l_down", None),
            "held_out_split": c.split,
            "overall_accuracy": c.overall_accuracy, "kappa_quadratic": c.kappa_quadratic,
            "kappa_unweighted": c.kappa_unweighted,
            "class_fractions": dict(zip(c.fractions["class"], c.fractions["fraction"].round(4))),
            "beta_elevation_K_per_m": self.terrain.beta_elevation,
            "beta_slope_K_per_deg": self.terrain.beta_slope,
            "beta_aspect_K": self.terrain.beta_aspect,
            "class_intercepts_K": self.terrain.intercepts,
            "r2": self.terrain.r2,
            "dem_masked_pixels": self.dem_masked_pixels,
            "input_notes": list(self.input_notes),
            "variogram_hours_at_bound": {f"{h:g}": list(f.at_bound) for h, f in
                                         zip(self.hours_local, self.variograms) if f.at_bound},
            "unmixed_border_pixels": self.unmixed_pixels,
            "lst_K": [float(np.nanmin(self.lst)), float(np.nanmax(self.lst))],
            "timings_s": {k: round(v, 3) for k, v in self.timings.items()},
            **(self.overpass.summary_extra() if self.overpass is not None else {}),
        }


def unmix_border_pixels(class_map, lst, t0_ov, terr, b0_map, reflectance=None, radius: int = 2,
                        min_contrast: float = 1.0, slack: float = 0.25):
    """Two-end-member unmixing of land–water border pixels at the overpass.

    Parameters
    ----------
    class_map : ndarray uint8
        Class codes (1 water, 2–4 land).
    lst : ndarray
        Landsat LST [K].
    t0_ov : ndarray
        Kriged baseline at the overpass [K].
    terr : ndarray
        Eq. 15 terrain term ``b1 Dem + b2 Slope + b3 Southness`` [K].
    b0_map : ndarray
        Class intercept ``b0`` of each land pixel [K] (NaN elsewhere).
    reflectance : ndarray (rows, cols, bands), optional
        OLI reflectances [-] for the spectral fallback.
    radius : int
        Neighbourhood half-width for the pure end-members [pixel] (3x wider where that
        window holds no pure pixel).
    min_contrast : float
        Smallest land–water end-member difference unmixed thermally [K].
    slack : float
        Accepted overshoot of the thermal fraction beyond [0, 1] [-].

    Returns
    -------
    dict
        ``mask`` (unmixed pixels), ``thermal`` (of which unmixed by temperature), ``f`` land
        fraction [-], ``e`` remainder [K], ``terr_land`` [K] and ``b0_land`` [K] of the land
        end-member, ``water_ov`` [K].

    Notes
    -----
    The land fraction comes from the temperatures, ``f = (LST - W_ov)/(L_ov - W_ov)``, where
    the two end-members differ by at least ``min_contrast`` and ``f`` falls in
    ``[-slack, 1 + slack]`` (then clipped). Elsewhere (a winter overpass can leave land and
    sea within a kelvin, so a thermal ``f`` would be noise that decides how much of the pixel
    cools at night) it comes from linear spectral unmixing of the reflectances with the same
    neighbourhood end-members (least squares over the bands, clipped to [0, 1]). ``e = LST -
    [f L_ov + (1 - f) W_ov]`` keeps the overpass LST exact.
    """
    from scipy.ndimage import binary_dilation, uniform_filter

    water = class_map == WATER
    land = np.isin(class_map, LAND_CLASSES)
    ring = np.ones((3, 3), bool)
    border = (land & binary_dilation(water, ring)) | (water & binary_dilation(land, ring))
    size = 2 * radius + 1

    def nbr_mean(values, mask):
        # Normalised convolution: mean of ``values`` over ``mask`` pixels in the window; where
        # the window holds none (a narrow channel whose water is all border), a 3x wider one.
        ok = mask & np.isfinite(values)
        out = np.full(ok.shape, np.nan)
        for width in (size, 3 * size):
            num = uniform_filter(np.where(ok, values, 0.0), width, mode="constant")
            den = uniform_filter(ok.astype(float), width, mode="constant")
            with np.errstate(invalid="ignore", divide="ignore"):
                out = np.where(np.isnan(out) & (den > 0.5 / width ** 2), num / den, out)
        return out

    pure_water, pure_land = water & ~border, land & ~border
    water_ov = nbr_mean(lst, pure_water)
    terr_land = np.where(land, terr, nbr_mean(terr, pure_land))
    b0_land = np.where(land, b0_map, nbr_mean(b0_map, pure_land))
    land_ov = t0_ov + terr_land + b0_land
    contrast = land_ov - water_ov
    ends = border & np.isfinite(land_ov) & np.isfinite(water_ov) & np.isfinite(lst)
    with np.errstate(invalid="ignore", divide="ignore"):
        f_thermal = (lst - water_ov) / contrast
    thermal = ends & (np.abs(contrast) >= min_contrast) & (f_thermal >= -slack) & (f_thermal <= 1.0 + slack)
    f = np.where(thermal, np.clip(f_thermal, 0.0, 1.0), np.nan)
    if reflectance is not None:
        rho = np.asarray(reflectance, dtype=np.float64)
        rho_w = np.stack([nbr_mean(rho[..., b], pure_water) for b in range(rho.shape[-1])], axis=-1)
        rho_l = np.stack([nbr_mean(rho[..., b], pure_land) for b in range(rho.shape[-1])], axis=-1)
        d = rho_l - rho_w
        with np.errstate(invalid="ignore", divide="ignore"):
            f_spec = np.clip(np.sum((rho - rho_w) * d, axis=-1) / np.sum(d * d, axis=-1), 0.0, 1.0)
        spectral = ends & ~thermal & np.isfinite(f_spec)
        f = np.where(spectral, f_spec, f)
    mask = ends & np.isfinite(f)
    e = lst - (f * land_ov + (1.0 - f) * water_ov)
    return {"mask": mask, "thermal": thermal, "f": np.where(mask, f, np.nan), "e": np.where(mask, e, np.nan),
            "terr_land": terr_land, "b0_land": b0_land, "water_ov": water_ov}


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
    from scipy.ndimage import distance_transform_edt

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
        As :func:`build_background_from_files`.
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


def _sun_sin_elevation(grid: SceneGrid, when_utc) -> np.ndarray:
    import pvlib
    from rasterio.warp import transform as warp_transform

    xc = grid.transform.c + grid.shape[1] * grid.transform.a / 2
    yc = grid.transform.f + grid.shape[0] * grid.transform.e / 2
    (lon,), (lat,) = warp_transform(grid.crs, "EPSG:4326", [xc], [yc])
    idx = pd.DatetimeIndex(when_utc).tz_localize("UTC")
    el = pvlib.solarposition.get_solarposition(idx, lat, lon)["elevation"].to_numpy()
    return np.sin(np.radians(el))


def _tqdm(desc: str):
    from tqdm import tqdm

    return lambda it: tqdm(it, desc=desc, unit="h")


def build_background_from_files(mtl_path, dem_path, met_path, roi_path, *, season: str | None = None,
                                utc_offset_hours: float = 8.0, water_vapour: float | None = None,
                                variogram_model: str = "spherical", krige_coarsen: int = 5,
                                lst_method: str = "planck", emissivity_model: str = "tirs_b10",
                                dem_nodata: str = "error",
                                residual_scaling: str = "constant", border_unmixing: bool = True,
                                test_fraction: float = 0.5, roi_split: str = "regions", seed: int = 0,
                                bounds=None, out_dir=None, band_files=None, use_qa: bool = True,
                                n_splits: int = N_SPLITS, progress: bool = False,
                                met_variable: str | None = None, met_units: str = "auto",
                                met_margin_cells: int = 4, krige_statistics: bool = False) -> PortBackground:
    """Run the full background chain on real-format inputs.

    Parameters
    ----------
    mtl_path : path-like
        Landsat 8/9 ``*_MTL.txt`` or ``*_MTL.json``: Collection-2 Level-1 (bands 2–7, 10) or
        Level-2 (SR_B2–B7, ST_B10 used as LST), Collection-1 or pre-collection Level-1; the
        quality band next to it when present.
    dem_path : path-like
        DEM GeoTIFF (any CRS; resampled bilinearly onto the scene grid).
    met_path : path-like
        Hourly met grid, NetCDF or GRIB (:func:`.met.read_met_grid`); the 24 hours of the
        overpass day are used, clipped to the scene (:func:`.met.met_for_scene`, which also
        states the SST and water-vapour fallbacks).
    roi_path : path-like
        Training ROIs (label GeoTIFF on the scene grid, or GeoJSON polygons).
    season : str, optional
        Label only.
    utc_offset_hours : float
        Local standard time minus UTC [h].
    water_vapour : float, optional
        Column water vapour [g cm-2]; default: the met file's at the overpass (or its
        fallback, :func:`.met.met_for_scene`).
    variogram_model : str
        pykrige model fitted per hour.
    krige_coarsen : int
        Krige every n-th pixel then bilinear (1 = every pixel).
    lst_method : {"planck", "taylor"}
    emissivity_model : str
        NDVI-thresholds coefficient set (:data:`.lst.EMISSIVITY_PARAMETERS`): ``"tirs_b10"``
        (band-10 specific, default) or ``"tm6_sobrino2004"``.
    dem_nodata : {"error", "mask", "fill"}
        DEM voids over land: raise, mask explicitly (terrain term left out there; counted), or
        fill them from the surrounding elevations (:func:`.terrain.load_dem`; counted).
    residual_scaling : {"constant", "solar"}
        Diurnal weight ``w(t)`` of the Landsat class residual (module docstring).
    border_unmixing : bool
        Unmix land–water border pixels into a land and a water end-member (module
        docstring); False treats them as pure land or pure water by their class.
    test_fraction : float
        Share of ROI pixels held out for the confusion matrix.
    roi_split : {"regions", "pixels"}
        Hold out whole ROI regions (spatially independent, default) or random pixels
        (:func:`.classify.split_training`).
    seed : int
        Seed of the train/test split.
    bounds : (west, south, east, north), optional
        Crop the scene to this box in its projected CRS [m] (the port out of a full 185 km
        Landsat scene; widened to whole pixels). The DEM, met grid and ROIs are then used on
        the cropped grid.
    out_dir : path-like, optional
        Write GeoTIFFs, PNGs and CSVs there (:mod:`.outputs`); nothing is written unless the
        whole chain succeeded.
    band_files : str or dict, optional
        Band files named differently on disk than in the MTL (:func:`.landsat.read_mtl`).
    use_qa : bool
        Mask fill, cloud, cirrus and cloud shadow from the quality band (QA_PIXEL / BQA) and
        fill those pixels from same-class neighbours (:func:`build_overpass`).
    n_splits : int
        Held-out ROI splits for the accuracy (mean and spread); the map uses all ROIs.
    progress : bool
        Show a tqdm progress bar over the hourly kriging.
    met_variable : str, optional
        Temperature variable of the met file (default: detected).
    met_units : {"auto", "K", "degC", "degF"}
        Temperature unit of the met file (``auto``: its ``units`` attribute, checked).
    met_margin_cells : int
        Met cells kept around the scene for the kriging.
    krige_statistics : bool
        pykrige's leave-one-out statistics per hour (slow for large grids).

    Returns
    -------
    PortBackground
    """
    require(dem_nodata in DEM_NODATA, "dem_nodata", dem_nodata,
            "must be " + ", ".join(repr(d) for d in DEM_NODATA[:-1]) + f" or {DEM_NODATA[-1]!r}")
    require(residual_scaling in ("constant", "solar"), "residual_scaling", residual_scaling,
            "must be 'constant' or 'solar'")
    require(lst_method in ("planck", "taylor"), "lst_method", lst_method, "must be 'planck' or 'taylor'")
    require(emissivity_model in EMISSIVITY_PARAMETERS, "emissivity_model", emissivity_model,
            f"must be one of {sorted(EMISSIVITY_PARAMETERS)}")
    check_range("utc_offset_hours", utc_offset_hours, -12.0, 14.0, unit="h")
    timings: dict[str, float] = {}
    t0 = time.perf_counter()

    scene = read_landsat_scene(mtl_path, bounds, band_files=band_files, use_qa=use_qa)
    grid = scene.grid
    overpass = np.datetime64(scene.mtl.acquired_utc.replace(tzinfo=None), "s")
    met = met_for_scene(read_met_grid(met_path, met_variable, None, met_units), grid, overpass,
                        margin_cells=met_margin_cells, season=season, utc_offset_hours=utc_offset_hours)
    sst_ov = met.interp_time(met.sst, overpass)      # also checks the met day contains the overpass
    if water_vapour is None and scene.level == "L1":
        water_vapour = met.interp_time(met.tcwv, overpass)
    dem_info = load_dem(dem_path, grid, fill_voids=dem_nodata == "fill")
    dem = dem_info.elevation
    timings["read"] = time.perf_counter() - t0

    # --- LST, classification, masks (the overpass) ------------------------------------------
    t1 = time.perf_counter()
    ov = build_overpass(scene, roi_path, water_vapour=water_vapour, lst_method=lst_method,
                        emissivity_model=emissivity_model, test_fraction=test_fraction, roi_split=roi_split,
                        seed=seed, n_splits=n_splits)
    lst, bt, emissivity, ndvi_map, features = ov.lst, ov.brightness_temperature, ov.emissivity, ov.ndvi, ov.features
    atmosphere = ov.atmosphere
    classification = ov.classification
    class_map = ov.class_map
    timings["overpass"] = time.perf_counter() - t1

    # --- DEM checks (before any heavy work or output) ---------------------------------------
    land = np.isin(class_map, LAND_CLASSES)
    water = class_map == WATER
    dem_nan = ~np.isfinite(dem)
    bad_land = dem_nan & land
    if bad_land.any() and dem_nodata == "error":
        r, c = (int(i) for i in np.argwhere(bad_land)[0])
        raise InputError("dem", f"{int(bad_land.sum())} land pixels without elevation (first at row {r}, col {c})",
                         "the DEM must cover every land pixel with valid values",
                         "Fill them (dem_nodata='fill'), mask them (dem_nodata='mask'), or use a DEM "
                         "that covers the scene")
    # Sea pixels without a DEM value are at sea level by definition (many DEMs leave the sea void).
    dem = np.where(dem_nan & water, 0.0, dem)
    slope, aspect = slope_aspect(dem, grid.resolution)
    south = southness(aspect)
    # Pixels whose 3x3 neighbourhood touches a void have no slope either: masked with the voids.
    terrain_ok = np.isfinite(dem) & np.isfinite(slope)
    dem_masked = int((~terrain_ok & (class_map > 0)).sum())

    # --- kriging of the met grid (eq. 12) -------------------------------------------------------
    t1 = time.perf_counter()
    x_met, y_met = met.points_in(grid.crs)
    values = met.temperature.reshape(met.temperature.shape[0], -1)
    baseline_utc, fits = krige_hourly(x_met, y_met, values, grid, model=variogram_model,
                                      coarsen=krige_coarsen, progress=_tqdm("kriging") if progress else None,
                                      statistics=krige_statistics)
    timings["kriging"] = time.perf_counter() - t1

    # --- eq. 15 on the overpass ---------------------------------------------------------------
    t1 = time.perf_counter()
    tsec = (met.times_utc - met.times_utc[0]).astype("timedelta64[s]").astype(float)
    xo = float((overpass - met.times_utc[0]).astype("timedelta64[s]").astype(float))
    require(tsec[0] <= xo <= tsec[-1], "met.time", f"{met.times_utc[0]} .. {met.times_utc[-1]}",
            f"must contain the Landsat overpass {overpass} UTC", "Use the met day of the overpass")
    k = min(int(np.searchsorted(tsec, xo, side="right") - 1), tsec.size - 2)
    a = (xo - tsec[k]) / (tsec[k + 1] - tsec[k])
    t0_ov = (1 - a) * baseline_utc[k] + a * baseline_utc[k + 1]
    delta = lst - t0_ov
    # Fit on class interiors: border pixels mix land and water (or two land classes) in the
    # Landsat radiance and would pull the betas with temperatures that terrain does not explain.
    interior = np.zeros_like(land)
    for c in LAND_CLASSES:
        interior |= binary_erosion(class_map == c, iterations=1)
    fit_mask = interior & np.isfinite(delta) & terrain_ok
    terrain = fit_terrain_regression(np.where(fit_mask, delta, np.nan), dem, slope, south,
                                     groups=class_map, group_names=CLASS_NAMES)
    terr = np.where(terrain_ok, terrain_term(terrain, np.where(terrain_ok, dem, 0.0),
                                             np.where(terrain_ok, slope, 0.0), south), 0.0)
    residual = delta - terr          # = b0[class] + r: the Landsat detail, organised by class
    timings["regression"] = time.perf_counter() - t1

    # --- hourly background ---------------------------------------------------------------------
    t1 = time.perf_counter()
    if residual_scaling == "solar":
        sin_el = _sun_sin_elevation(grid, np.r_[met.times_utc, overpass])
        weight = np.clip(sin_el[:-1], 0, None) / max(sin_el[-1], 0.05)
    else:
        weight = np.ones(met.times_utc.size)
    hours_utc = (met.times_utc - met.times_utc.astype("datetime64[D]")).astype("timedelta64[s]").astype(float) / 3600
    hours_local = (hours_utc + utc_offset_hours) % 24.0
    order = np.argsort(hours_local, kind="stable")
    b0_map = np.full(class_map.shape, np.nan)
    for c in LAND_CLASSES:
        b0_map[class_map == c] = terrain.intercepts.get(CLASS_NAMES[c], np.nan)
    mix = (unmix_border_pixels(class_map, lst, t0_ov, terr, b0_map, features) if border_unmixing
           else {"mask": np.zeros(class_map.shape, bool)})
    m = mix["mask"]
    temperature = np.empty_like(baseline_utc)
    for out_k, k in enumerate(order):
        land_t = baseline_utc[k] + terr + weight[k] * residual
        water_t = lst + (met.sst[k] - sst_ov)
        layer = np.where(water, water_t, np.where(land, land_t, np.nan))
        if m.any():
            f = mix["f"][m]
            land_end = baseline_utc[k][m] + mix["terr_land"][m] + weight[k] * mix["b0_land"][m]
            water_end = mix["water_ov"][m] + (met.sst[k] - sst_ov)
            layer[m] = f * land_end + (1.0 - f) * water_end + mix["e"][m]
        temperature[out_k] = layer
    timings["temporal"] = time.perf_counter() - t1

    acquired = scene.mtl.acquired_utc
    hour_ov = (acquired.hour + acquired.minute / 60 + acquired.second / 3600 + utc_offset_hours) % 24.0
    result = PortBackground(
        grid=grid, season=season, class_map=class_map, lst=lst.astype(np.float32),
        brightness_temperature=bt.astype(np.float32), emissivity=emissivity.astype(np.float32),
        ndvi=ndvi_map.astype(np.float32), elevation=dem.astype(np.float32),
        slope_deg=slope.astype(np.float32), aspect_deg=aspect.astype(np.float32), terrain=terrain,
        classification=classification, variograms=[fits[k] for k in order],
        hours_local=hours_local[order], temperature=temperature.astype(np.float32),
        baseline=baseline_utc[order].astype(np.float32), sst=met.sst[order], overpass_utc=acquired,
        overpass_hour_local=float(hour_ov), atmosphere=atmosphere, utc_offset_hours=float(utc_offset_hours),
        dem_masked_pixels=dem_masked, emissivity_model=emissivity_model,
        unmixed_pixels=int(m.sum()), land_fraction=mix.get("f"), timings=timings, overpass=ov,
        input_notes=met.notes + dem_info.notes)
    if out_dir is not None:
        from .outputs import write_outputs

        t1 = time.perf_counter()
        result.outputs = write_outputs(result, out_dir)
        timings["outputs"] = time.perf_counter() - t1
    timings["total"] = time.perf_counter() - t0
    return result


def build_port_background(season: str = "summer", out_dir=None, seed: int = 2026, *, size_px: int = 334,
                          lat: float = 38.93, lon: float = 121.65, input_dir=None, **kwargs) -> PortBackground:
    """The embedded default: generate the synthetic port, write it in the real formats, read it
    back with the real loaders and run the whole background chain.

    Parameters
    ----------
    season : {"summer", "winter"}
    out_dir : path-like, optional
        Where to write the products (GeoTIFF, PNG, CSV). ``None`` writes nothing.
    seed : int
        Seed of the synthetic port (textures, ROIs) and of the train/test split.
    size_px : int
        Scene side in 30 m pixels (334 -> 10 km).
    lat, lon : float
        Scene centre [deg].
    input_dir : path-like, optional
        Keep the generated input files there (default: a temporary directory, removed).
    **kwargs
        Passed to :func:`build_background_from_files`.

    Returns
    -------
    PortBackground
        Its ``synthetic_truth`` attribute holds the generator's truth arrays.
    """
    from .synthetic import SEASONS, UTC_OFFSET_HOURS, write_synthetic_port

    require(season in SEASONS, "season", season, f"must be one of {sorted(SEASONS)}")
    t0 = time.perf_counter()

    def run(directory):
        port = write_synthetic_port(directory, season, seed=seed, size_px=size_px, lat=lat, lon=lon)
        t_gen = time.perf_counter() - t0
        bg = build_background_from_files(port.mtl_txt, port.dem, port.met, port.roi, season=season,
                                         utc_offset_hours=UTC_OFFSET_HOURS, seed=seed, out_dir=out_dir, **kwargs)
        bg.timings = {"synthetic": t_gen, **bg.timings}
        bg.synthetic_truth = port.truth
        return bg

    if input_dir is not None:
        return run(os.fspath(input_dir))
    with tempfile.TemporaryDirectory(prefix="shipthermal_port_") as tmp:
        return run(tmp)
