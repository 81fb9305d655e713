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

import dataclasses
import os
import tempfile
import time
from dataclasses import dataclass, field
from datetime import datetime

import numpy as np
import pandas as pd
import pvlib
from rasterio.warp import transform as warp_transform
from scipy.ndimage import binary_dilation, binary_erosion, uniform_filter
from tqdm import tqdm

from shipthermal.errors import InputError, require

from .classify import CLASS_NAMES, ClassificationResult
from .kriging import krige_hourly
from .landsat.grid import SceneGrid
from .landsat.scene import read_landsat_scene
from .lst import AtmosphereB10
from .met import met_for_scene, read_met_grid
from .outputs import write_outputs
from .overpass_products import OverpassProducts, build_overpass, fill_masked_pixels
from .settings import BackgroundSettings
from .terrain import TerrainFit, fit_terrain_regression, load_dem, slope_aspect, southness, terrain_term

__all__ = ["PortBackground", "OverpassProducts", "build_overpass", "fill_masked_pixels",
           "BackgroundSettings", "build_background_from_files", "build_port_background",
           "unmix_border_pixels", "fit_eq15"]

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


def _sun_sin_elevation(grid: SceneGrid, when_utc) -> np.ndarray:
    xc = grid.transform.c + grid.shape[1] * grid.transform.a / 2
    yc = grid.transform.f + grid.shape[0] * grid.transform.e / 2
    (lon,), (lat,) = warp_transform(grid.crs, "EPSG:4326", [xc], [yc])
    idx = pd.DatetimeIndex(when_utc).tz_localize("UTC")
    el = pvlib.solarposition.get_solarposition(idx, lat, lon)["elevation"].to_numpy()
    return np.sin(np.radians(el))


def _tqdm(desc: str):
    return lambda it: tqdm(it, desc=desc, unit="h")


def build_background_from_files(mtl_path, dem_path, met_path, roi_path,
                                settings: BackgroundSettings | None = None, *, out_dir=None,
                                **options) -> PortBackground:
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
    settings : BackgroundSettings, optional
        The chain's options (default: those of :class:`BackgroundSettings`).
    out_dir : path-like, optional
        Write GeoTIFFs, PNGs and CSVs there (:mod:`.outputs`); nothing is written unless the
        whole chain succeeded.
    **options
        Fields of :class:`BackgroundSettings` replacing those of ``settings`` (e.g.
        ``utc_offset_hours=1.0, seed=3``).

    Returns
    -------
    PortBackground
    """
    o = dataclasses.replace(settings or BackgroundSettings(), **options)
    timings: dict[str, float] = {}
    t0 = time.perf_counter()

    scene = read_landsat_scene(mtl_path, o.bounds, band_files=o.band_files, use_qa=o.use_qa)
    grid = scene.grid
    overpass = np.datetime64(scene.mtl.acquired_utc.replace(tzinfo=None), "s")
    met = met_for_scene(read_met_grid(met_path, o.met_variable, None, o.met_units), grid, overpass,
                        margin_cells=o.met_margin_cells, season=o.season, utc_offset_hours=o.utc_offset_hours)
    sst_ov = met.interp_time(met.sst, overpass)      # also checks the met day contains the overpass
    water_vapour = o.water_vapour
    if water_vapour is None and scene.level == "L1":
        water_vapour = met.interp_time(met.tcwv, overpass)
    dem_info = load_dem(dem_path, grid, fill_voids=o.dem_nodata == "fill")
    timings["read"] = time.perf_counter() - t0

    # --- LST, classification, masks (the overpass) ------------------------------------------
    t1 = time.perf_counter()
    ov = build_overpass(scene, roi_path, water_vapour=water_vapour, lst_method=o.lst_method,
                        emissivity_model=o.emissivity_model, test_fraction=o.test_fraction, roi_split=o.roi_split,
                        seed=o.seed, n_splits=o.n_splits)
    class_map = ov.class_map
    timings["overpass"] = time.perf_counter() - t1

    # --- DEM checks (before any heavy work or output) ---------------------------------------
    land = np.isin(class_map, LAND_CLASSES)
    water = class_map == WATER
    dem, slope, aspect, south, terrain_ok = _terrain_on_scene(dem_info.elevation, class_map, grid, o.dem_nodata)
    dem_masked = int((~terrain_ok & (class_map > 0)).sum())

    # --- kriging of the met grid (eq. 12) -------------------------------------------------------
    t1 = time.perf_counter()
    x_met, y_met = met.points_in(grid.crs)
    values = met.temperature.reshape(met.temperature.shape[0], -1)
    baseline_utc, fits = krige_hourly(x_met, y_met, values, grid, model=o.variogram_model,
                                      coarsen=o.krige_coarsen, progress=_tqdm("kriging") if o.progress else None,
                                      statistics=o.krige_statistics)
    timings["kriging"] = time.perf_counter() - t1

    # --- eq. 15 on the overpass ---------------------------------------------------------------
    t1 = time.perf_counter()
    t0_ov = _baseline_at_overpass(met, baseline_utc, overpass)
    delta = ov.lst - t0_ov
    terrain, terr = fit_eq15(delta, class_map, dem, slope, south, terrain_ok)
    residual = delta - terr          # = b0[class] + r: the Landsat detail, organised by class
    timings["regression"] = time.perf_counter() - t1

    # --- hourly background ---------------------------------------------------------------------
    t1 = time.perf_counter()
    weight = _residual_weight(o.residual_scaling, grid, met.times_utc, overpass)
    hours_utc = (met.times_utc - met.times_utc.astype("datetime64[D]")).astype("timedelta64[s]").astype(float) / 3600
    hours_local = (hours_utc + o.utc_offset_hours) % 24.0
    order = np.argsort(hours_local, kind="stable")
    b0_map = np.full(class_map.shape, np.nan)
    for c in LAND_CLASSES:
        b0_map[class_map == c] = terrain.intercepts.get(CLASS_NAMES[c], np.nan)
    mix = (unmix_border_pixels(class_map, ov.lst, t0_ov, terr, b0_map, ov.features) if o.border_unmixing
           else {"mask": np.zeros(class_map.shape, bool)})
    temperature = _hourly_layers(baseline_utc, order, terr, weight, residual, ov.lst, met.sst, sst_ov,
                                 land, water, mix)
    timings["temporal"] = time.perf_counter() - t1

    acquired = scene.mtl.acquired_utc
    hour_ov = (acquired.hour + acquired.minute / 60 + acquired.second / 3600 + o.utc_offset_hours) % 24.0
    result = PortBackground(
        grid=grid, season=o.season, class_map=class_map, lst=ov.lst.astype(np.float32),
        brightness_temperature=ov.brightness_temperature.astype(np.float32),
        emissivity=ov.emissivity.astype(np.float32),
        ndvi=ov.ndvi.astype(np.float32), elevation=dem.astype(np.float32),
        slope_deg=slope.astype(np.float32), aspect_deg=aspect.astype(np.float32), terrain=terrain,
        classification=ov.classification, variograms=[fits[k] for k in order],
        hours_local=hours_local[order], temperature=temperature.astype(np.float32),
        baseline=baseline_utc[order].astype(np.float32), sst=met.sst[order], overpass_utc=acquired,
        overpass_hour_local=float(hour_ov), atmosphere=ov.atmosphere, utc_offset_hours=float(o.utc_offset_hours),
        dem_masked_pixels=dem_masked, emissivity_model=o.emissivity_model,
        unmixed_pixels=int(mix["mask"].sum()), land_fraction=mix.get("f"), timings=timings, overpass=ov,
        input_notes=met.notes + dem_info.notes)
    if out_dir is not None:
        t1 = time.perf_counter()
        result.outputs = write_outputs(result, out_dir)
        timings["outputs"] = time.perf_counter() - t1
    timings["total"] = time.perf_counter() - t0
    return result


def _terrain_on_scene(dem, class_map, grid: SceneGrid, dem_nodata: str) -> tuple:
    """Elevation, slope, aspect [deg] and southness on the scene grid, and where the terrain
    is known: land voids raise (``dem_nodata='error'``), sea voids are at sea level, pixels
    next to a void have no slope."""
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
    return dem, slope, aspect, south, terrain_ok


def _baseline_at_overpass(met, baseline_utc, overpass) -> np.ndarray:
    """The kriged baseline ``T0`` at the overpass instant, linear between the met hours."""
    tsec = (met.times_utc - met.times_utc[0]).astype("timedelta64[s]").astype(float)
    xo = float((overpass - met.times_utc[0]).astype("timedelta64[s]").astype(float))
    require(tsec[0] <= xo <= tsec[-1], "met.time", f"{met.times_utc[0]} .. {met.times_utc[-1]}",
            f"must contain the Landsat overpass {overpass} UTC", "Use the met day of the overpass")
    k = min(int(np.searchsorted(tsec, xo, side="right") - 1), tsec.size - 2)
    a = (xo - tsec[k]) / (tsec[k + 1] - tsec[k])
    return (1 - a) * baseline_utc[k] + a * baseline_utc[k + 1]


def fit_eq15(delta, class_map, dem, slope, south, terrain_ok) -> tuple[TerrainFit, np.ndarray]:
    """The paper's eq. 15 on the overpass: ``LST - T0(t_ov) = b1 Dem + b2 Slope + b3 Southness
    + b0[class]`` fitted by least squares on the land classes' interiors.

    Parameters
    ----------
    delta : ndarray (rows, cols)
        ``LST - T0(t_ov)`` [K].
    class_map : ndarray (rows, cols)
        Class codes (:data:`.classify.CLASS_NAMES`).
    dem, slope, south : ndarray (rows, cols)
        Elevation [m], slope [deg] and southness [-] on the scene grid.
    terrain_ok : ndarray bool (rows, cols)
        Where the terrain is known (elsewhere the terrain term is 0).

    Returns
    -------
    (TerrainFit, ndarray)
        The fit (betas and the classes' intercepts) and its terrain term
        ``b1 Dem + b2 Slope + b3 Southness`` on every pixel [K].
    """
    # Fit on class interiors: border pixels mix land and water (or two land classes) in the
    # Landsat radiance and would pull the betas with temperatures that terrain does not explain.
    interior = np.zeros(class_map.shape, dtype=bool)
    for c in LAND_CLASSES:
        interior |= binary_erosion(class_map == c, iterations=1)
    fit_mask = interior & np.isfinite(delta) & terrain_ok
    terrain = fit_terrain_regression(np.where(fit_mask, delta, np.nan), dem, slope, south,
                                     groups=class_map, group_names=CLASS_NAMES)
    terr = np.where(terrain_ok, terrain_term(terrain, np.where(terrain_ok, dem, 0.0),
                                             np.where(terrain_ok, slope, 0.0), south), 0.0)
    return terrain, terr


def _residual_weight(residual_scaling: str, grid: SceneGrid, times_utc, overpass) -> np.ndarray:
    """The diurnal weight ``w(t)`` of the Landsat class residual at the met hours: 1, or the
    sun's elevation ratio to the overpass (``"solar"``)."""
    if residual_scaling == "solar":
        sin_el = _sun_sin_elevation(grid, np.r_[times_utc, overpass])
        return np.clip(sin_el[:-1], 0, None) / max(sin_el[-1], 0.05)
    return np.ones(times_utc.size)


def _hourly_layers(baseline_utc, order, terr, weight, residual, lst, sst, sst_ov, land, water,
                   mix: dict) -> np.ndarray:
    """The background at every met hour in local-hour ``order`` (module docstring): land on
    its baseline, terrain and weighted residual, water on its Landsat pattern and the SST's
    change, border pixels mixed from their two end-members."""
    m = mix["mask"]
    temperature = np.empty_like(baseline_utc)
    for out_k, k in enumerate(order):
        land_t = baseline_utc[k] + terr + weight[k] * residual
        water_t = lst + (sst[k] - sst_ov)
        layer = np.where(water, water_t, np.where(land, land_t, np.nan))
        if m.any():
            f = mix["f"][m]
            land_end = baseline_utc[k][m] + mix["terr_land"][m] + weight[k] * mix["b0_land"][m]
            water_end = mix["water_ov"][m] + (sst[k] - sst_ov)
            layer[m] = f * land_end + (1.0 - f) * water_end + mix["e"][m]
        temperature[out_k] = layer
    return temperature


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
    # deferred: the synthetic port's writers load shipthermal.environment (55 ms over the
    # background package, measured); only the built-in port needs them
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
